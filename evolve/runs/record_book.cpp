#include "evolve/runs/record_book.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/input_error.hpp"
#include "formats/race_file.hpp"

namespace sodaevo {

namespace {

ReplicaRecord replicas_of(const soda::RaceLane& lane, const soda::Model& model, int timeout,
                          const soda::ModelDef& contender, const RecordBookInputs& in) {
  ReplicaRecord r;
  r.outcomes = race_replica_outcomes(lane, model, timeout, contender, in.replicas, in.jitter, in.threads);
  r.summary = summarize_race_results(r.outcomes);
  r.finished_share = finished_share(r.outcomes);
  return r;
}

/// Less is better: a finish before any timeout, then the result.
bool ahead(const RaceEntry& a, const RaceEntry& b) {
  if (!a.no_result.empty() || !b.no_result.empty()) return a.no_result.empty() && !b.no_result.empty();
  if (a.outcome.finished != b.outcome.finished) return a.outcome.finished;
  return a.outcome.result < b.outcome.result;
}

/// The candidates and publics of one file raced together; their lanes kept for replicas.
struct RacedFile {
  FileRecord record;
  RaceLanes lanes; ///< candidates first, then publics
};

RacedFile race_file(const std::string& path, const RecordBookInputs& in, std::vector<std::string>& warnings) {
  const soda::RaceDef race = soda::read_race_file(path);
  RacedFile out;
  out.record.race_file = path;
  out.record.timeout = race.timeout;
  std::vector<RaceEntry> entries = load_race_entries(path, race, in.candidates, warnings);
  const std::size_t ours = entries.size();
  if (!in.publics.empty()) {
    std::vector<RaceEntry> publics = load_race_entries(path, race, in.publics, warnings);
    entries.insert(entries.end(), std::make_move_iterator(publics.begin()), std::make_move_iterator(publics.end()));
  }
  std::vector<std::string> lane_warnings; // contenders in pieces: said once by `race`, not per file here
  out.lanes = build_race_lanes(race, entries, false, lane_warnings);
  race_entries_together(out.lanes, race.timeout, entries);
  out.record.candidates.assign(entries.begin(), entries.begin() + static_cast<std::ptrdiff_t>(ours));
  out.record.publics.assign(entries.begin() + static_cast<std::ptrdiff_t>(ours), entries.end());
  for (std::size_t k = 0; k < out.record.publics.size(); ++k) {
    const RaceEntry& e = out.record.publics[k];
    if (!e.no_result.empty()) continue;
    if (out.record.best_public < 0 || ahead(e, out.record.publics[static_cast<std::size_t>(out.record.best_public)])) {
      out.record.best_public = static_cast<int>(k);
    }
  }
  return out;
}

/// The record of a raced file: finishers fastest first, the first that qualifies.
void choose_record(RacedFile& f, const RecordBookInputs& in) {
  FileRecord& r = f.record;
  std::vector<std::size_t> order;
  for (std::size_t k = 0; k < r.candidates.size(); ++k) {
    if (r.candidates[k].no_result.empty() && r.candidates[k].outcome.finished) order.push_back(k);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return ahead(r.candidates[a], r.candidates[b]); });
  constexpr std::size_t kMostTried = 8; // replicas cost 16 races each: the fastest few
  for (std::size_t i = 0; i < order.size() && i < kMostTried; ++i) {
    const std::size_t k = order[i];
    ReplicaRecord rep = replicas_of(f.lanes.lanes[k], f.lanes.models[k], r.timeout, r.candidates[k].model, in);
    const bool qualifies = rep.finished_share >= in.qualify;
    if (i == 0 || qualifies) {
      r.record = static_cast<int>(k);
      r.record_replicas = std::move(rep);
      r.qualified = qualifies;
    }
    if (qualifies) break;
  }
}

} // namespace

RecordBook compile_record_book(const RecordBookInputs& in, std::vector<std::string>& warnings,
                               const std::function<void(int, int, const std::string&)>& progress) {
  if (in.race_files.empty()) throw soda::InputError("records: expected at least one race file, got none");
  if (in.candidates.empty()) throw soda::InputError("records: expected at least one racer of ours, got none");
  if (in.replicas < 2) throw soda::InputError("records: expected at least 2 replicas, got " + std::to_string(in.replicas));
  RecordBook book;
  std::vector<RacedFile> raced;
  const int total = static_cast<int>(in.race_files.size()) * 2;
  int done = 0;
  for (const std::string& path : in.race_files) {
    if (progress) progress(done, total, path);
    raced.push_back(race_file(path, in, warnings));
    choose_record(raced.back(), in);
    ++done;
  }
  // The generalist: most files finished, then the fewest frames over them.
  std::vector<int> finished(in.candidates.size(), 0);
  std::vector<double> frames(in.candidates.size(), 0.0);
  for (const RacedFile& f : raced) {
    for (std::size_t k = 0; k < f.record.candidates.size(); ++k) {
      const RaceEntry& e = f.record.candidates[k];
      if (!e.no_result.empty() || !e.outcome.finished) continue;
      ++finished[k];
      frames[k] += e.outcome.result;
    }
  }
  for (std::size_t k = 0; k < in.candidates.size(); ++k) {
    const int best = book.generalist.candidate;
    if (best < 0 || finished[k] > finished[static_cast<std::size_t>(best)] ||
        (finished[k] == finished[static_cast<std::size_t>(best)] && frames[k] < frames[static_cast<std::size_t>(best)])) {
      book.generalist.candidate = static_cast<int>(k);
    }
  }
  const std::size_t g = static_cast<std::size_t>(book.generalist.candidate);
  book.generalist.files_finished = finished[g];
  for (RacedFile& f : raced) {
    if (progress) progress(done, total, f.record.race_file + " (the generalist's replicas)");
    const RaceEntry& e = f.record.candidates[g];
    if (e.no_result.empty()) {
      book.generalist.replicas.push_back(replicas_of(f.lanes.lanes[g], f.lanes.models[g], f.record.timeout, e.model, in));
    } else {
      book.generalist.replicas.emplace_back();
    }
    ++done;
    book.files.push_back(std::move(f.record));
  }
  if (progress) progress(done, total, "");
  return book;
}

} // namespace sodaevo
