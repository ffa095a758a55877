#include "mpi_evaluator.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <thread>

#include "evolve/mpi/mpi_protocol.hpp"
#include "evolve/problems/wire_format.hpp"

namespace sodaevo {

using namespace mpi_protocol;

MpiEvaluator::MpiEvaluator(MpiSession& session, int threads)
    : session_(session),
      requested_threads_(threads),
      local_threads_(session.resolve_threads(threads)),
      worker_threads_(static_cast<std::size_t>(session.size()), 0) {}

int MpiEvaluator::total_threads() const {
  return std::accumulate(worker_threads_.begin() + 1, worker_threads_.end(), local_threads_);
}

namespace {

std::string failure_text(const Message& m) {
  try {
    WireReader r(m.bytes);
    return r.text();
  } catch (const WireError&) {
    return "MPI rank " + std::to_string(m.source) + " failed (unreadable failure message)";
  }
}

} // namespace

void MpiEvaluator::set_up_workers(const Problem& problem, const Estimator& estimator) {
  WireWriter w;
  problem.write(w);
  estimator.write(w);
  w.i32(requested_threads_);
  if (w.bytes() == setup_sent_ || session_.size() == 1) return;
  for (int r = 1; r < session_.size(); ++r) send(session_.comm(), r, Setup, w.bytes());
  std::string failure;
  for (int answered = 1; answered < session_.size(); ++answered) {
    const Message m = receive(session_.comm(), MPI_ANY_SOURCE);
    if (m.tag == Ready) {
      WireReader r(m.bytes);
      worker_threads_[static_cast<std::size_t>(m.source)] = std::max(1, r.i32());
    } else if (failure.empty()) {
      failure = m.tag == Failure ? failure_text(m) : "unexpected answer from MPI rank " + std::to_string(m.source);
    }
  }
  if (!failure.empty()) throw std::runtime_error(failure);
  setup_sent_ = w.take();
}

std::vector<Evaluation> MpiEvaluator::evaluate(const std::vector<const soda::ModelDef*>& creatures,
                                               const Problem& problem, const Estimator& estimator) {
  try {
    set_up_workers(problem, estimator);
  } catch (const MpiError&) {
    session_.mark_broken();
    throw;
  }

  const std::size_t n = creatures.size();
  std::vector<Evaluation> results(n);
  std::vector<char> done(n, 0); // not vector<bool>: written by several threads
  const std::size_t all_threads = static_cast<std::size_t>(std::max(1, total_threads()));

  // One queue for everyone: positions in `creatures` are claimed with fetch_add, by
  // rank 0's threads one at a time, for a worker a chunk at a time.
  std::atomic<std::size_t> cursor{0};
  std::atomic<bool> abandon{false};
  std::mutex error_mutex;
  std::exception_ptr local_error;
  std::atomic<int> local_running{local_threads_};
  std::atomic<long long> local_done{0};

  auto local_work = [&] {
    try {
      while (!abandon.load()) {
        const std::size_t k = cursor.fetch_add(1);
        if (k >= n) break;
        results[k] = estimator.estimate(problem, {creatures[k]}).front();
        done[k] = 1;
        local_done.fetch_add(1);
      }
    } catch (...) {
      std::lock_guard lock(error_mutex);
      if (!local_error) local_error = std::current_exception();
      abandon = true;
    }
    local_running.fetch_sub(1);
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(local_threads_));
  std::string failure;
  std::exception_ptr mpi_error;
  try {
    std::vector<std::vector<std::uint64_t>> assigned(static_cast<std::size_t>(session_.size()));
    int outstanding = 0;
    auto send_chunk = [&](int rank) {
      if (abandon.load()) return;
      const std::size_t threads = static_cast<std::size_t>(worker_threads_[static_cast<std::size_t>(rank)]);
      const std::size_t claimed = cursor.load();
      const std::size_t remaining = claimed < n ? n - claimed : 0;
      // Guided: half of this rank's fair share of what is left, at least a
      // creature per thread.
      const std::size_t chunk = std::max(threads, (remaining * threads + 2 * all_threads - 1) / (2 * all_threads));
      const std::size_t begin = cursor.fetch_add(chunk);
      if (begin >= n) return;
      const std::size_t end = std::min(n, begin + chunk);
      WireWriter w;
      w.u32(static_cast<std::uint32_t>(end - begin));
      std::vector<std::uint64_t>& mine = assigned[static_cast<std::size_t>(rank)];
      mine.clear();
      for (std::size_t k = begin; k < end; ++k) {
        mine.push_back(k);
        w.u64(k);
        w.creature(*creatures[k]);
      }
      send(session_.comm(), rank, Work, w.bytes());
      ++outstanding;
      ++traffic_.work_messages;
      traffic_.bytes_sent += static_cast<long long>(w.bytes().size());
    };
    // Workers get their first chunk before rank 0's threads start, so every worker
    // has work in every generation that has enough creatures.
    for (int r = 1; r < session_.size(); ++r) send_chunk(r);
    for (int t = 0; t < local_threads_; ++t) pool.emplace_back(local_work);

    Backoff backoff;
    while (outstanding > 0 || local_running.load() > 0) {
      std::optional<Message> m = try_receive(session_.comm(), MPI_ANY_SOURCE);
      if (!m) {
        backoff.wait();
        continue;
      }
      backoff.reset();
      --outstanding;
      std::vector<std::uint64_t>& mine = assigned[static_cast<std::size_t>(m->source)];
      if (m->tag == Results) {
        traffic_.bytes_received += static_cast<long long>(m->bytes.size());
        try {
          WireReader r(m->bytes);
          const std::uint32_t count = r.u32();
          if (count != mine.size()) throw WireError("wrong number of results");
          std::vector<Evaluation> farmed;
          for (std::uint32_t k = 0; k < count; ++k) {
            if (r.u64() != mine[k]) throw WireError("results out of order");
            farmed.push_back(r.evaluation());
          }
          r.expect_end();
          for (std::uint32_t k = 0; k < count; ++k) {
            results[mine[k]] = std::move(farmed[k]);
            done[mine[k]] = 1;
          }
          traffic_.creatures_farmed += count;
        } catch (const WireError& e) {
          if (failure.empty()) failure = "MPI rank " + std::to_string(m->source) + " sent malformed results: " + e.what();
          abandon = true;
        }
      } else {
        if (failure.empty()) {
          failure = m->tag == Failure ? failure_text(*m)
                                      : "unexpected message (tag " + std::to_string(m->tag) + ") from MPI rank " +
                                            std::to_string(m->source);
        }
        abandon = true;
      }
      mine.clear();
      send_chunk(m->source);
    }
  } catch (const MpiError&) {
    mpi_error = std::current_exception();
    abandon = true;
  }
  for (std::thread& t : pool) t.join();
  traffic_.creatures_local += local_done.load();

  if (mpi_error) {
    session_.mark_broken();
    std::rethrow_exception(mpi_error);
  }
  if (local_error) std::rethrow_exception(local_error);
  if (!failure.empty()) throw std::runtime_error(failure);
  if (std::find(done.begin(), done.end(), 0) != done.end()) {
    throw std::logic_error("MPI evaluator left a creature unevaluated");
  }
  return results;
}

} // namespace sodaevo
