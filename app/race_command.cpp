// `sodaevo race RACE.xml [CONTENDER.xml ...]`: Sodarace races as the original racer
// runs them (core/race_lane.hpp): each contender in its own lane on the race's
// terrain, its result in frames (a timeout as timeout + fraction) and its place.
// A contender argument may be another race file: its contenders race this terrain.
// A contender the racer rejects (a fixed node last in <nodes>) gets "no result".
// With --replicas K each contender also races K replicas with sine jitter
// (core/sine_jitter.hpp: another machine's sine), which gives the distribution of
// its result: the original racer's run is one more draw from it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "app/motion.hpp"
#include "app/player_html.hpp"
#include "core/fixed_bars.hpp"
#include "core/input_error.hpp"
#include "formats/model_file.hpp"
#include "formats/race_file.hpp"
#include "core/lockstep_batch.hpp"
#include "core/race_lane.hpp"
#include "formats/trace_csv.hpp"
#include "evolve/parallel_for.hpp"
#include "evolve/replica_estimator.hpp"
#include "evolve/sample_summary.hpp"

namespace sodaevo::app {

namespace {

struct RaceOptions {
  std::string race;
  std::vector<std::string> contenders;
  bool json = false;
  std::string trace;
  std::string render;
  int timeout = -1;
  int replicas = 0;
  double jitter = 0.002;
  int threads = 0;
};

struct Entry {
  std::string file; ///< the contender's file, or the race file's contender "RACE#k"
  std::string name;
  soda::ModelDef model;
  soda::RaceOutcome outcome;
  std::string no_result; ///< why the racer gives this contender no result (contender_filter.hpp); empty: raced
  int place = 0;
  SampleSummary replicas; ///< --replicas: the results of the jittered replicas
};

std::string result_text(const soda::RaceOutcome& o) {
  char text[64];
  if (std::isnan(o.result)) return "no result";
  if (o.finished) {
    std::snprintf(text, sizeof text, "%.0f", o.result);
  } else {
    std::snprintf(text, sizeof text, "%.4f (timeout)", o.result);
  }
  return text;
}

/// The contenders of race file `file` (`race`), named "FILE#k".
void add_race_contenders(const std::string& file, const soda::RaceDef& race, std::vector<Entry>& out) {
  for (std::size_t k = 0; k < race.contenders.size(); ++k) {
    Entry e;
    e.file = file + "#" + std::to_string(k + 1);
    e.model = race.contenders[k].model;
    e.name = !e.model.name.empty() ? e.model.name : "contender " + std::to_string(k + 1) + " (line " +
                                                         std::to_string(race.contenders[k].line) + ")";
    out.push_back(std::move(e));
  }
}

std::vector<Entry> load_entries(const RaceOptions& opt, const soda::RaceDef& race) {
  std::vector<Entry> out;
  if (opt.contenders.empty()) {
    add_race_contenders(opt.race, race, out);
    if (out.empty()) {
      throw soda::InputError(opt.race + ": the race file has no contenders; name contender model files after it");
    }
    return out;
  }
  for (const std::string& path : opt.contenders) {
    if (soda::looks_like_race(soda::read_race_file_text(path))) {
      const std::size_t before = out.size();
      add_race_contenders(path, soda::read_race_file(path), out);
      if (out.size() == before) throw soda::InputError(path + ": a race file without contenders (expected a contender)");
      continue;
    }
    soda::LoadedModel loaded = soda::read_model_file(path);
    for (const std::string& w : loaded.warnings) std::cerr << "sodaevo: warning: " << w << '\n';
    Entry e;
    e.file = path;
    e.model = std::move(loaded.def);
    e.name = e.model.name.empty() ? std::filesystem::path(path).filename().string() : e.model.name;
    out.push_back(std::move(e));
  }
  return out;
}

/// The results of `opt.replicas` replicas of the lane with sine jitter (seeds of
/// the check on fresh replicas, from the contender's genome: the same on every run).
SampleSummary race_replicas(const soda::RaceLane& lane, const soda::Model& model, int timeout,
                            const soda::ModelDef& contender, const RaceOptions& opt) {
  const std::uint64_t key = creature_key(contender);
  std::vector<double> results(static_cast<std::size_t>(opt.replicas));
  // Replicas by lockstep groups (run_races_fast: one group of 8 lanes at a time,
  // the same results as one by one), the groups spread over the threads.
  constexpr std::size_t kGroup = soda::LockstepBatch::kLanes;
  parallel_for_index((results.size() + kGroup - 1) / kGroup, opt.threads, [&](std::size_t g) {
    const std::size_t first = g * kGroup, end = std::min(results.size(), first + kGroup);
    std::vector<soda::State> states;
    for (std::size_t r = first; r < end; ++r) {
      states.push_back(soda::make_state(model));
      states.back().jitter = {replica_seed(1, ReplicaPurpose::Check, key, static_cast<int>(r)), opt.jitter};
    }
    std::vector<soda::State*> pointers;
    for (soda::State& s : states) pointers.push_back(&s);
    const std::vector<soda::RaceOutcome> outcomes = soda::run_races_fast(lane, model, timeout, pointers);
    for (std::size_t r = first; r < end; ++r) results[r] = outcomes[r - first].result;
  });
  // A race result is a frame count, never below 0: the interval, mean -+ t sd, is
  // clipped there, where a contender that sometimes finishes and sometimes times
  // out stretches it below 0. (No upper clip: a timeout scores timeout + its
  // share of the course left, which exceeds 1 for a contender behind its start.)
  SampleSummary s = summarize_sample(results);
  s.interval95_low = std::max(s.interval95_low, 0.0);
  return s;
}

std::string distribution_text(const SampleSummary& s) {
  char text[96];
  std::snprintf(text, sizeof text, "%.1f [%.1f, %.1f]", s.median, s.interval95_low, s.interval95_high);
  return text;
}

/// Places: 1 for the lowest result; equal results share a place; no result, no place (0).
void assign_places(std::vector<Entry>& entries) {
  for (Entry& e : entries) {
    e.place = 0;
    if (!e.no_result.empty()) continue;
    e.place = 1;
    for (const Entry& other : entries) e.place += other.no_result.empty() && other.outcome.result < e.outcome.result ? 1 : 0;
  }
}

void run_race_command(const RaceOptions& opt) {
  const soda::RaceDef race = soda::read_race_file(opt.race);
  const int timeout = opt.timeout >= 0 ? opt.timeout : race.timeout;
  std::vector<Entry> entries = load_entries(opt, race);
  if ((!opt.trace.empty() || !opt.render.empty()) && entries.size() != 1) {
    throw soda::InputError("race: --trace and --render draw one lane: expected one contender, got " +
                           std::to_string(entries.size()) + " (name one contender file)");
  }
  // Lanes of the contenders the racer races (by entry; an empty lane for one it
  // rejects: no result, as the original racer gives none).
  std::vector<soda::RaceLane> lanes(entries.size());
  std::vector<soda::Model> models(entries.size());
  for (std::size_t k = 0; k < entries.size(); ++k) {
    Entry& e = entries[k];
    try {
      lanes[k] = soda::build_lane(race.terrain, race.constraints, e.model, e.file);
    } catch (const soda::ContenderRejected& ex) {
      if (!opt.trace.empty() || !opt.render.empty()) throw; // nothing to draw
      e.no_result = ex.what();
      e.outcome.result = std::nan("");
      if (entries.size() > 1) std::cerr << "sodaevo: " << e.no_result << '\n';
      continue;
    }
    models[k] = soda::build_lane_model(lanes[k]);
    if (lanes[k].contender_pieces > 1) {
      std::cerr << "sodaevo: warning: " << e.file << ": not one connected piece: the original racer races only its "
                << "largest piece: " << models[k].mass_count << " of " << lanes[k].contender_masses << " masses\n";
    }
  }
  if (std::all_of(entries.begin(), entries.end(), [](const Entry& e) { return !e.no_result.empty(); })) {
    throw soda::InputError(entries.size() == 1 ? entries[0].no_result
                                               : "race: no contender can be raced (the reasons are above)");
  }
  if (opt.trace.empty()) { // the contenders raced together (fused scenes: the same results as one by one)
    std::vector<std::size_t> raced;
    for (std::size_t k = 0; k < entries.size(); ++k) {
      if (entries[k].no_result.empty()) raced.push_back(k);
    }
    std::vector<soda::State> states;
    for (std::size_t k : raced) states.push_back(soda::make_state(models[k]));
    std::vector<soda::LaneRace> races;
    for (std::size_t i = 0; i < raced.size(); ++i) races.push_back({&lanes[raced[i]], &models[raced[i]], timeout, &states[i]});
    const std::vector<soda::RaceOutcome> outcomes = soda::run_races_together(races);
    for (std::size_t i = 0; i < raced.size(); ++i) entries[raced[i]].outcome = outcomes[i];
  }
  for (std::size_t k = 0; k < entries.size(); ++k) {
    Entry& e = entries[k];
    if (!e.no_result.empty()) continue;
    const soda::RaceLane& lane = lanes[k];
    const soda::Model& model = models[k];
    if (!opt.trace.empty()) {
      std::ofstream trace_file(opt.trace, std::ios::binary | std::ios::trunc);
      if (!trace_file) throw soda::InputError(opt.trace + ": cannot open the trace file for writing");
      soda::TraceCsv trace(trace_file, model);
      trace.write_row(soda::make_state(model));
      e.outcome = soda::run_race(lane, model, timeout, [&](const soda::State& s) { trace.write_row(s); });
      trace_file.flush();
      if (!trace_file) throw soda::InputError(opt.trace + ": writing the trace failed (disk full?)");
    }
    if (opt.replicas > 0) e.replicas = race_replicas(lane, model, timeout, e.model, opt);
    if (!opt.render.empty()) {
      const Motion motion = record_race_motion(lane, model, timeout, e.name);
      std::ofstream out(opt.render, std::ios::binary | std::ios::trunc);
      out << render_player_page(motion, "Race: " + e.name,
                                race.source + ": " + result_text(e.outcome) + " frames (fixed bars: " +
                                    soda::bar_engine_name(soda::BarEngine::Racer2004) + " racer rule)");
      if (!out) throw soda::InputError(opt.render + ": cannot write the page");
    }
  }
  assign_places(entries);
  const std::string engine = soda::bar_engine_name(soda::BarEngine::Racer2004);
  if (opt.json) {
    nlohmann::json j = {{"race", opt.race}, {"timeout", timeout}, {"bar_engine", engine}};
    nlohmann::json list = nlohmann::json::array();
    for (const Entry& e : entries) {
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
      if (opt.replicas > 0 && e.no_result.empty()) {
        const SampleSummary& s = e.replicas;
        item["replicas"] = {{"n", s.n},     {"jitter", opt.jitter}, {"mean", s.mean}, {"median", s.median},
                            {"sd", s.sd},   {"min", s.min},         {"max", s.max},
                            {"interval95", {s.interval95_low, s.interval95_high}}};
      }
      list.push_back(std::move(item));
    }
    j["contenders"] = list;
    std::cout << j.dump() << '\n';
    return;
  }
  std::printf("race        %s\ntimeout     %d frames\nfixed bars  %s rule (the racer's: bars running downhill or right "
              "to left are not hit)\n\n",
              opt.race.c_str(), timeout, engine.c_str());
  const bool replicas = opt.replicas > 0;
  if (replicas) {
    std::printf("%-6s %-22s %-30s %s\n", "place", "frames", "replicas: median [95 % interval]", "contender");
  } else {
    std::printf("%-6s %-22s %s\n", "place", "frames", "contender");
  }
  std::vector<const Entry*> order;
  for (const Entry& e : entries) order.push_back(&e);
  const auto rank = [](const Entry* e) { return e->place > 0 ? e->place : std::numeric_limits<int>::max(); };
  std::stable_sort(order.begin(), order.end(), [&](const Entry* a, const Entry* b) { return rank(a) < rank(b); });
  for (const Entry* e : order) {
    if (!e->no_result.empty()) {
      std::printf("%-6s %-22s %s (%s)\n", "-", "no result", e->name.c_str(), e->file.c_str());
      continue;
    }
    if (replicas) {
      std::printf("%-6d %-22s %-30s %s (%s)\n", e->place, result_text(e->outcome).c_str(),
                  distribution_text(e->replicas).c_str(), e->name.c_str(), e->file.c_str());
    } else {
      std::printf("%-6d %-22s %s (%s)\n", e->place, result_text(e->outcome).c_str(), e->name.c_str(), e->file.c_str());
    }
  }
}

} // namespace

void add_race_command(CLI::App& app) {
  auto opt = std::make_shared<RaceOptions>();
  CLI::App* cmd = app.add_subcommand(
      "race",
      "Race contenders on a Sodarace race file's terrain exactly as the original racer (2004) does:\n"
      "each one's largest connected piece (fixed nodes dropped) scaled to half its container's\n"
      "height, placed left of the start, run until it passes the finish or the timeout. Prints\n"
      "each result in frames (a timeout as timeout + fraction of the way left to go) and its\n"
      "place; fewer frames is better. A fixed node last in <nodes>: no result, as the racer.");
  cmd->add_option("race", opt->race, "Race file (<!DOCTYPE sodarace>, e.g. models/terrains/TerrainFlat.xml)")
      ->required()
      ->check(non_empty_path())
      ->check(CLI::ExistingFile);
  cmd->add_option("contenders", opt->contenders,
                  "Contender model files (.xml, v1 or v2), or race files (their contenders); none: the race\n"
                  "file's own contenders")
      ->check(non_empty_path())
      ->check(CLI::ExistingFile);
  cmd->add_flag("--json", opt->json,
                "Print {\"race\", \"timeout\", \"bar_engine\", \"contenders\": [{\"file\", \"name\", \"frames\",\n"
                "\"finished\", \"place\"}]}; with --replicas each entry also has \"replicas\"; a contender\n"
                "the racer gives no result (a fixed node last in <nodes>) has \"frames\" and \"place\" null\n"
                "and \"no_result\": the reason");
  cmd->add_option("--trace", opt->trace,
                  "Write the lane's CSV trace (one contender): frame,wave_phase,wave_mode,x0,y0,vx0,vy0,...");
  cmd->add_option("--render", opt->render,
                  "Write an HTML player of the race (one contender): terrain, start and finish lines, frames");
  cmd->add_option("--timeout", opt->timeout, "Timeout in frames instead of the race file's")
      ->check(CLI::Range(1, soda::kMaxRaceTimeout));
  cmd->add_option("--replicas", opt->replicas,
                  "Also race K replicas with sine jitter (another machine's sine) per contender: the\n"
                  "distribution of the result (median, 95 % prediction interval; --json: n, mean, median,\n"
                  "sd, min, max, interval95)")
      ->check(CLI::Range(2, 4096));
  cmd->add_option("--jitter", opt->jitter, "Share of sines a replica moves by 1 ulp")
      ->default_val(0.002)
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--threads", opt->threads, "Threads for the replicas (0: all cores)")->check(CLI::Range(0, 4096));
  cmd->callback([opt] { run_race_command(*opt); });
}

} // namespace sodaevo::app
