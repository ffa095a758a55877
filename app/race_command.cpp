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


#include "app/commands.hpp"
#include "app/motion.hpp"
#include "app/player_html.hpp"
#include "core/fixed_bars.hpp"
#include "core/input_error.hpp"
#include "formats/race_file.hpp"
#include "core/race_lane.hpp"
#include "formats/trace_csv.hpp"
#include "evolve/runs/race_entries.hpp"
#include "evolve/estimators/sample_summary.hpp"

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

using Entry = RaceEntry;

std::string distribution_text(const SampleSummary& s) {
  char text[96];
  std::snprintf(text, sizeof text, "%.1f [%.1f, %.1f]", s.median, s.interval95_low, s.interval95_high);
  return text;
}

void run_race_command(const RaceOptions& opt) {
  const soda::RaceDef race = soda::read_race_file(opt.race);
  const int timeout = opt.timeout >= 0 ? opt.timeout : race.timeout;
  std::vector<std::string> warnings;
  auto print_warnings = [&] {
    for (const std::string& w : warnings) std::cerr << "sodaevo: " << w << '\n';
    warnings.clear();
  };
  std::vector<Entry> entries;
  try {
    entries = load_race_entries(opt.race, race, opt.contenders, warnings);
  } catch (...) {
    print_warnings();
    throw;
  }
  print_warnings();
  if ((!opt.trace.empty() || !opt.render.empty()) && entries.size() != 1) {
    throw soda::InputError("race: --trace and --render draw one lane: expected one contender, got " +
                           std::to_string(entries.size()) + " (name one contender file)");
  }
  // Lanes of the contenders the racer races (by entry; an empty lane for one it
  // rejects: no result, as the original racer gives none; nothing to draw).
  RaceLanes field;
  try {
    field = build_race_lanes(race, entries, !opt.trace.empty() || !opt.render.empty(), warnings);
  } catch (...) {
    print_warnings();
    throw;
  }
  print_warnings();
  const std::vector<soda::RaceLane>& lanes = field.lanes;
  const std::vector<soda::Model>& models = field.models;
  // The contenders raced together (fused scenes: the same results as one by one).
  if (opt.trace.empty()) race_entries_together(field, timeout, entries);
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
    if (opt.replicas > 0) race_entry_replicas(e, lane, model, timeout, opt.replicas, opt.jitter, opt.threads);
    if (!opt.render.empty()) {
      const Motion motion = record_race_motion(lane, model, timeout, e.name);
      std::ofstream out(opt.render, std::ios::binary | std::ios::trunc);
      out << render_player_page(motion, "Race: " + e.name,
                                race.source + ": " + race_result_text(e.outcome) + " frames (fixed bars: " +
                                    soda::bar_engine_name(soda::BarEngine::Racer2004) + " racer rule)");
      if (!out) throw soda::InputError(opt.render + ": cannot write the page");
    }
  }
  assign_places(entries);
  const std::string engine = soda::bar_engine_name(soda::BarEngine::Racer2004);
  if (opt.json) {
    std::cout << race_results_json(opt.race, timeout, entries, opt.replicas, opt.jitter).dump() << '\n';
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
      std::printf("%-6d %-22s %-30s %s (%s)\n", e->place, race_result_text(e->outcome).c_str(),
                  distribution_text(e->replicas).c_str(), e->name.c_str(), e->file.c_str());
    } else {
      std::printf("%-6d %-22s %s (%s)\n", e->place, race_result_text(e->outcome).c_str(), e->name.c_str(), e->file.c_str());
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
                  "sd, min, max, interval95, finished: the share that finish)")
      ->check(CLI::Range(2, 4096));
  cmd->add_option("--jitter", opt->jitter, "Share of sines a replica moves by 1 ulp")
      ->default_val(0.002)
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--threads", opt->threads, "Threads for the replicas (0: all cores)")->check(CLI::Range(0, 4096));
  cmd->callback([opt] { run_race_command(*opt); });
}

} // namespace sodaevo::app
