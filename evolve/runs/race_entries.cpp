#include "evolve/runs/race_entries.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/contender_filter.hpp"
#include "core/fixed_bars.hpp"
#include "core/input_error.hpp"
#include "core/lockstep_batch.hpp"
#include "evolve/evaluators/parallel_for.hpp"
#include "evolve/estimators/replica_estimator.hpp"
#include "formats/model_file.hpp"
#include "formats/race_file.hpp"

namespace sodaevo {

namespace {

/// The contenders of race file `file` (`race`), named "FILE#k".
void add_race_contenders(const std::string& file, const soda::RaceDef& race, std::vector<RaceEntry>& out) {
  for (std::size_t k = 0; k < race.contenders.size(); ++k) {
    RaceEntry e;
    e.file = file + "#" + std::to_string(k + 1);
    e.model = race.contenders[k].model;
    e.name = !e.model.name.empty() ? e.model.name : "contender " + std::to_string(k + 1) + " (line " +
                                                         std::to_string(race.contenders[k].line) + ")";
    out.push_back(std::move(e));
  }
}

} // namespace

std::vector<RaceEntry> load_race_entries(const std::string& race_path, const soda::RaceDef& race,
                                         const std::vector<std::string>& contenders,
                                         std::vector<std::string>& warnings) {
  std::vector<RaceEntry> out;
  if (contenders.empty()) {
    add_race_contenders(race_path, race, out);
    if (out.empty()) {
      throw soda::InputError(race_path + ": the race file has no contenders; name contender model files after it");
    }
    return out;
  }
  for (const std::string& path : contenders) {
    if (soda::looks_like_race(soda::read_race_file_text(path))) {
      const std::size_t before = out.size();
      add_race_contenders(path, soda::read_race_file(path), out);
      if (out.size() == before) throw soda::InputError(path + ": a race file without contenders (expected a contender)");
      continue;
    }
    soda::LoadedModel loaded = soda::read_model_file(path);
    for (const std::string& w : loaded.warnings) warnings.push_back("warning: " + w);
    out.push_back(race_entry(path, std::move(loaded.def)));
  }
  return out;
}

RaceEntry race_entry(const std::string& file, soda::ModelDef model) {
  RaceEntry e;
  e.file = file;
  e.model = std::move(model);
  e.name = e.model.name.empty() ? std::filesystem::path(file).filename().string() : e.model.name;
  return e;
}

RaceLanes build_race_lanes(const soda::RaceDef& race, std::vector<RaceEntry>& entries, bool rejected_throws,
                           std::vector<std::string>& warnings) {
  RaceLanes out;
  out.lanes.resize(entries.size());
  out.models.resize(entries.size());
  for (std::size_t k = 0; k < entries.size(); ++k) {
    RaceEntry& e = entries[k];
    try {
      out.lanes[k] = soda::build_lane(race.terrain, race.constraints, e.model, e.file);
    } catch (const soda::ContenderRejected& ex) {
      if (rejected_throws) throw;
      e.no_result = ex.what();
      e.outcome.result = std::nan("");
      if (entries.size() > 1) warnings.push_back(e.no_result);
      continue;
    }
    out.models[k] = soda::build_lane_model(out.lanes[k]);
    if (out.lanes[k].contender_pieces > 1) {
      warnings.push_back("warning: " + e.file + ": not one connected piece: the original racer races only its largest piece: " +
                         std::to_string(out.models[k].mass_count) + " of " +
                         std::to_string(out.lanes[k].contender_masses) + " masses");
    }
  }
  if (std::all_of(entries.begin(), entries.end(), [](const RaceEntry& e) { return !e.no_result.empty(); })) {
    throw soda::InputError(entries.size() == 1 ? entries[0].no_result
                                               : "race: no contender can be raced (the reasons are above)");
  }
  return out;
}

void race_entries_together(const RaceLanes& lanes, int timeout, std::vector<RaceEntry>& entries) {
  std::vector<std::size_t> raced;
  for (std::size_t k = 0; k < entries.size(); ++k) {
    if (entries[k].no_result.empty()) raced.push_back(k);
  }
  std::vector<soda::State> states;
  for (std::size_t k : raced) states.push_back(soda::make_state(lanes.models[k]));
  std::vector<soda::LaneRace> races;
  for (std::size_t i = 0; i < raced.size(); ++i) {
    races.push_back({&lanes.lanes[raced[i]], &lanes.models[raced[i]], timeout, &states[i]});
  }
  const std::vector<soda::RaceOutcome> outcomes = soda::run_races_together(races);
  for (std::size_t i = 0; i < raced.size(); ++i) entries[raced[i]].outcome = outcomes[i];
}

std::vector<soda::RaceOutcome> race_replica_outcomes(const soda::RaceLane& lane, const soda::Model& model, int timeout,
                                                     const soda::ModelDef& contender, int replicas, double jitter,
                                                     int threads) {
  const std::uint64_t key = creature_key(contender);
  std::vector<soda::RaceOutcome> results(static_cast<std::size_t>(replicas));
  // Replicas by lockstep groups (run_races_fast: one group of 8 lanes at a time,
  // the same results as one by one), the groups spread over the threads.
  constexpr std::size_t kGroup = soda::LockstepBatch::kLanes;
  parallel_for_index((results.size() + kGroup - 1) / kGroup, threads, [&](std::size_t g) {
    const std::size_t first = g * kGroup, end = std::min(results.size(), first + kGroup);
    std::vector<soda::State> states;
    for (std::size_t r = first; r < end; ++r) {
      states.push_back(soda::make_state(model));
      states.back().jitter = {replica_seed(1, ReplicaPurpose::Check, key, static_cast<int>(r)), jitter};
    }
    std::vector<soda::State*> pointers;
    for (soda::State& s : states) pointers.push_back(&s);
    const std::vector<soda::RaceOutcome> outcomes = soda::run_races_fast(lane, model, timeout, pointers);
    for (std::size_t r = first; r < end; ++r) results[r] = outcomes[r - first];
  });
  return results;
}

SampleSummary summarize_race_results(const std::vector<soda::RaceOutcome>& outcomes) {
  std::vector<double> results;
  for (const soda::RaceOutcome& o : outcomes) results.push_back(o.result);
  // A race result is a frame count, never below 0: the interval, mean -+ t sd, is
  // clipped there, where a contender that sometimes finishes and sometimes times
  // out stretches it below 0. (No upper clip: a timeout scores timeout + its
  // share of the course left, which exceeds 1 for a contender behind its start.)
  SampleSummary s = summarize_sample(results);
  s.interval95_low = std::max(s.interval95_low, 0.0);
  return s;
}

void race_entry_replicas(RaceEntry& e, const soda::RaceLane& lane, const soda::Model& model, int timeout, int replicas,
                         double jitter, int threads) {
  const std::vector<soda::RaceOutcome> outcomes =
      race_replica_outcomes(lane, model, timeout, e.model, replicas, jitter, threads);
  e.replicas = summarize_race_results(outcomes);
  e.replicas_finished = finished_share(outcomes);
}

double finished_share(const std::vector<soda::RaceOutcome>& outcomes) {
  if (outcomes.empty()) return 0.0;
  const auto finished = std::count_if(outcomes.begin(), outcomes.end(), [](const soda::RaceOutcome& o) { return o.finished; });
  return static_cast<double>(finished) / static_cast<double>(outcomes.size());
}

std::string race_result_text(const soda::RaceOutcome& o) {
  char text[64];
  if (std::isnan(o.result)) return "no result";
  if (o.finished) {
    std::snprintf(text, sizeof text, "%.0f", o.result);
  } else {
    std::snprintf(text, sizeof text, "%.4f (timeout)", o.result);
  }
  return text;
}

void assign_places(std::vector<RaceEntry>& entries) {
  for (RaceEntry& e : entries) {
    e.place = 0;
    if (!e.no_result.empty()) continue;
    e.place = 1;
    for (const RaceEntry& other : entries) {
      e.place += other.no_result.empty() && other.outcome.result < e.outcome.result ? 1 : 0;
    }
  }
}

nlohmann::json race_results_json(const std::string& race_path, int timeout, const std::vector<RaceEntry>& entries,
                                 int replicas, double jitter) {
  nlohmann::json j = {
      {"race", race_path}, {"timeout", timeout}, {"bar_engine", soda::bar_engine_name(soda::BarEngine::Racer2004)}};
  nlohmann::json list = nlohmann::json::array();
  for (const RaceEntry& e : entries) {
    nlohmann::json item = {{"file", e.file},
                           {"name", e.name},
                           {"frames", e.outcome.result},
                           {"finished", e.outcome.finished},
                           {"place", e.place}};
    if (!e.no_result.empty()) { // the racer gives none (contender_filter.hpp)
      item["frames"] = nullptr;
      item["place"] = nullptr;
      item["no_result"] = e.no_result;
    }
    if (replicas > 0 && e.no_result.empty()) {
      const SampleSummary& s = e.replicas;
      item["replicas"] = {{"n", s.n},   {"jitter", jitter}, {"mean", s.mean}, {"median", s.median},
                          {"sd", s.sd}, {"min", s.min},     {"max", s.max},
                          {"interval95", {s.interval95_low, s.interval95_high}},
                          {"finished", e.replicas_finished}};
    }
    list.push_back(std::move(item));
  }
  j["contenders"] = list;
  return j;
}

} // namespace sodaevo
