#include "mpi_worker.hpp"

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "evolve/estimators/estimator.hpp"
#include "evolve/evaluators/evaluator.hpp"
#include "evolve/mpi/mpi_protocol.hpp"
#include "evolve/problems/problem.hpp"
#include "evolve/problems/wire_format.hpp"

namespace sodaevo {

namespace {

using namespace mpi_protocol;

struct TestFault {
  enum class Kind { None, Kill, Fail } kind = Kind::None;
  long long after = 0;
};

TestFault read_test_fault(int rank) {
  TestFault f;
  const char* v = std::getenv("SODAEVO_TEST_FAULT");
  if (!v) return f;
  const std::string s = v;
  const auto c1 = s.find(':'), c2 = s.find(':', c1 == std::string::npos ? 0 : c1 + 1);
  if (c1 == std::string::npos || c2 == std::string::npos) return f;
  const std::string kind = s.substr(0, c1);
  if (std::atoi(s.substr(c1 + 1, c2 - c1 - 1).c_str()) != rank) return f;
  f.after = std::atoll(s.substr(c2 + 1).c_str());
  f.kind = kind == "kill" ? TestFault::Kind::Kill : kind == "fail" ? TestFault::Kind::Fail : TestFault::Kind::None;
  return f;
}

class Worker {
 public:
  explicit Worker(MpiSession& session) : session_(session), fault_(read_test_fault(session.rank())) {}

  int run() {
    for (;;) {
      Message m = receive(session_.comm(), 0);
      switch (m.tag) {
        case Setup: set_up(m.bytes); break;
        case Work: work(m.bytes); break;
        case Stop: return 0;
        default: fail("unexpected message tag " + std::to_string(m.tag) + " from rank 0");
      }
    }
  }

 private:
  void fail(const std::string& what) {
    WireWriter w;
    w.text("MPI rank " + std::to_string(session_.rank()) + " on " + session_.host() + ": " + what);
    send(session_.comm(), 0, Failure, w.bytes());
  }

  void set_up(const std::vector<char>& bytes) {
    try {
      WireReader r(bytes);
      std::unique_ptr<Problem> problem = read_problem(r);
      std::unique_ptr<Estimator> estimator = read_estimator(r);
      const int requested = r.i32();
      r.expect_end();
      problem_ = std::move(problem);
      estimator_ = std::move(estimator);
      evaluator_.emplace(session_.resolve_threads(requested));
    } catch (const std::exception& e) {
      problem_.reset();
      estimator_.reset();
      evaluator_.reset();
      return fail(std::string("could not set up: ") + e.what());
    }
    WireWriter w;
    w.i32(evaluator_->threads());
    send(session_.comm(), 0, Ready, w.bytes());
  }

  void work(const std::vector<char>& bytes) {
    std::vector<std::uint64_t> indices;
    std::vector<soda::ModelDef> creatures;
    std::vector<Evaluation> evaluations;
    try {
      if (!evaluator_) throw std::runtime_error("work arrived before the setup");
      WireReader r(bytes);
      const std::uint32_t count = r.u32();
      for (std::uint32_t k = 0; k < count; ++k) {
        indices.push_back(r.u64());
        creatures.push_back(r.creature());
      }
      r.expect_end();
      inject_test_fault();
      std::vector<const soda::ModelDef*> pointers;
      for (const soda::ModelDef& c : creatures) pointers.push_back(&c);
      evaluations = evaluator_->evaluate(pointers, *problem_, *estimator_); // fused batches, by index
    } catch (const std::exception& e) {
      return fail(std::string("evaluation failed: ") + e.what());
    }
    WireWriter w;
    w.u32(static_cast<std::uint32_t>(indices.size()));
    for (std::size_t k = 0; k < indices.size(); ++k) {
      w.u64(indices[k]);
      w.evaluation(evaluations[k]);
    }
    send(session_.comm(), 0, Results, w.bytes());
  }

  void inject_test_fault() {
    if (fault_.kind == TestFault::Kind::None) return;
    if (chunks_started_++ < fault_.after) return;
    if (fault_.kind == TestFault::Kind::Kill) std::raise(SIGKILL);
    throw std::runtime_error("test fault injected by SODAEVO_TEST_FAULT");
  }

  MpiSession& session_;
  TestFault fault_;
  long long chunks_started_ = 0;
  std::unique_ptr<Problem> problem_;
  std::unique_ptr<Estimator> estimator_;
  std::optional<ThreadEvaluator> evaluator_;
};

} // namespace

int run_mpi_worker(MpiSession& session) {
  // mpirun forwards SIGUSR1 (the polite stop) to every rank; only rank 0 acts on it.
  std::signal(SIGUSR1, SIG_IGN);
  try {
    return Worker(session).run();
  } catch (const std::exception& e) {
    // Lost contact with rank 0 (it stopped or died): nothing to save here.
    session.mark_broken();
    std::cerr << "sodaevo (MPI rank " << session.rank() << " on " << session.host() << "): " << e.what() << '\n';
    return 1;
  }
}

} // namespace sodaevo
