#include "bench/golden_races.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>

#include "formats/model_file.hpp"
#include "formats/race_file.hpp"
#include "core/batch_step.hpp"
#include "core/fast_step.hpp"
#include "core/race_lane.hpp"

namespace sodaevo::bench {

namespace fs = std::filesystem;

namespace {

fs::path local_path(const fs::path& data, const std::string& p) {
  const std::string terrain = "shared/models/soda/golden/terrain/";
  const std::string soda = "shared/models/soda/";
  if (p.rfind(terrain, 0) == 0) return data / "terrain" / p.substr(terrain.size());
  if (p.rfind(soda, 0) == 0) return data / "soda" / p.substr(soda.size());
  return p;
}


long long situation_count(const soda::BarMemory& m, int k) {
  const soda::BarCounters& c = m.counters;
  return k == 0 ? c.far_starts : k == 1 ? c.near_end_misses : c.far_end_corners;
}

bool diagnosed(const std::string& contender_path) {
  const std::string name = fs::path(contender_path).stem().string();
  for (const RaceDiagnosis& d : race_diagnoses()) {
    if (name == d.contender) return true;
  }
  return false;
}

} // namespace

const char* bar_situation_name(BarSituation s) {
  switch (s) {
    case BarSituation::FarStart: return "far start";
    case BarSituation::NearEndMiss: return "near-end miss";
    case BarSituation::FarEndCorner: return "far-end corner";
  }
  return "?";
}

const std::vector<RaceDiagnosis>& race_diagnoses() {
  static const std::vector<RaceDiagnosis> table = {
      {"walker_313", BarSituation::FarStart, "SideRule::Near",
       "frame 6763, mass 3: bar 1 remembers it on side 0 (handed over at the joint from bar 0); its move starts "
       "2.68 px above the bar's line and ends on that side. The original lets it go; the remembered side 0 "
       "caught it at the line's crossing point."},
      {"walker_382", BarSituation::FarEndCorner, "InferredBarRules::far_end_corner",
       "frame 3307, mass 4 slides up bar 1 (side 0) past its end into the steeper bar 2, a concave joint; its "
       "end point projects 0.88 px beyond bar 2's far end. The original puts it at that node (50074, 20), in the "
       "corner of bars 2 and 3; it was put on bar 2's line beyond the node."},
      {"walker_514", BarSituation::NearEndMiss, "InferredBarRules::hit_margin (1e-5, was 1e-4)",
       "frame 6457, mass 1 (on bar 1, to the floor): bar 0 remembers it (side -1) and its move crosses bar 0's "
       "line 9.35e-5 px beyond the bar's end: a hit under a 1e-4 margin, none in the original, so bar 0 forgets "
       "it and catches it anew with side 0. At frame 6463 its move off bar 0 is caught (side 0) in the "
       "original, was released (side -1)."},
  };
  return table;
}

std::vector<GoldenRace> race_golden(const fs::path& data, const std::string& race_filter,
                                    const std::string& contender_filter) {
  std::ifstream in(data / "terrain" / "races.tsv");
  if (!in) throw std::runtime_error((data / "terrain" / "races.tsv").string() + ": cannot open");
  std::string line;
  std::getline(in, line); // header
  std::map<std::string, soda::RaceDef> races;
  std::vector<GoldenRace> out;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    GoldenRace g;
    if (!(row >> g.race >> g.contender >> g.golden)) continue;
    if (!race_filter.empty() && g.race.find(race_filter) == std::string::npos) continue;
    if (!contender_filter.empty() && g.contender.find(contender_filter) == std::string::npos) continue;
    auto it = races.find(g.race);
    if (it == races.end()) it = races.emplace(g.race, soda::read_race_file(local_path(data, g.race))).first;
    const soda::RaceDef& race = it->second;
    const soda::ModelDef contender = soda::read_model_file(local_path(data, g.contender)).def;
    const soda::RaceLane lane = soda::build_lane(race.terrain, race.constraints, contender, g.contender);
    const soda::Model model = soda::build_lane_model(lane);
    soda::State state = soda::make_state(model);
    const soda::RaceOutcome o = soda::run_race_fast(lane, model, race.timeout, state);
    g.ours = o.result;
    g.ours_finished = o.finished;
    for (int k = 0; k < kBarSituations; ++k) g.situations[k] = situation_count(state.bar_memory, k);
    if (!g.same() || diagnosed(g.contender)) {
      // The reference race again, watched frame by frame.
      long long update = 0;
      (void)soda::run_race(lane, model, race.timeout, [&](const soda::State& s) {
        ++update;
        for (int k = 0; k < kBarSituations; ++k) {
          if (g.first_update[k] < 0 && situation_count(s.bar_memory, k) > 0) g.first_update[k] = update;
        }
      });
    }
    out.push_back(g);
  }
  return out;
}

std::string golden_races_report(const std::vector<GoldenRace>& races) {
  std::map<std::string, std::pair<int, int>> per_race; // same, total
  int same = 0;
  int meeting[kBarSituations] = {0, 0, 0}; // races that meet each situation
  for (const GoldenRace& g : races) {
    auto& c = per_race[fs::path(g.race).filename().string()];
    c.second += 1;
    c.first += g.same() ? 1 : 0;
    same += g.same() ? 1 : 0;
    for (int k = 0; k < kBarSituations; ++k) meeting[k] += g.situations[k] > 0 ? 1 : 0;
  }
  std::ostringstream o;
  char text[512];
  std::snprintf(text, sizeof text, "Same result as the original racer: **%d of %zu** races.\n\n", same, races.size());
  o << text;
  o << "| race file | same | of |\n|---|---|---|\n";
  for (const auto& [name, c] : per_race) o << "| " << name << " | " << c.first << " | " << c.second << " |\n";
  const auto frame = [](long long u) { return u < 0 ? std::string("-") : std::to_string(u); };
  o << "\n## Situations of the inferred bar rules (measured on our runs)\n\n"
       "Three bar rules were inferred from these races alone (core/fixed_bars.hpp); each situation they decide, "
       "and how many of the races above meet it at least once:\n\n| situation | races meeting it |\n|---|---|\n";
  for (int k = 0; k < kBarSituations; ++k) {
    std::snprintf(text, sizeof text, "| %s | %d of %zu |\n", bar_situation_name(static_cast<BarSituation>(k)),
                  meeting[k], races.size());
    o << text;
  }
  o << "\nDiagnosis (by hand, not measured here): the races each rule was inferred from, and what happens there; "
       "beside it, measured: the race files where our run of that contender meets the situation, the first update "
       "at which it does, and how many of those races give the original's result.\n\n"
       "| contender | situation | rule | race files (first update, ours) | same | diagnosis |\n"
       "|---|---|---|---|---|---|\n";
  for (const RaceDiagnosis& d : race_diagnoses()) {
    std::string where;
    int met = 0, met_same = 0;
    for (const GoldenRace& g : races) {
      const long long u = g.first_update[static_cast<int>(d.situation)];
      if (fs::path(g.contender).stem().string() != d.contender || u < 0) continue;
      where += (met > 0 ? ", " : "") + fs::path(g.race).stem().string() + " (" + frame(u) + ")";
      met += 1;
      met_same += g.same() ? 1 : 0;
    }
    if (met == 0) where = "-";
    std::snprintf(text, sizeof text, "| %s | %s | %s | ", d.contender, bar_situation_name(d.situation), d.rule);
    o << text << where << " | " << met_same << " of " << met << " | " << d.what << " |\n";
  }
  const int differ = static_cast<int>(races.size()) - same;
  std::snprintf(text, sizeof text, "\n## Differences\n\n%d differ.", differ);
  o << text;
  if (differ == 0) return o.str() + "\n";
  o << " Per race, the first update at which our run meets each situation (measured), and the diagnosis if "
       "the contender has one (else none: a new case).\n\n"
       "| race | contender | original | ours | far start | near-end miss | far-end corner | diagnosis |\n"
       "|---|---|---|---|---|---|---|---|\n";
  for (const GoldenRace& g : races) {
    if (g.same()) continue;
    std::string diagnosis = "none";
    for (const RaceDiagnosis& d : race_diagnoses()) {
      if (fs::path(g.contender).stem().string() == d.contender) diagnosis = bar_situation_name(d.situation);
    }
    std::snprintf(text, sizeof text, "| %s | %s | %.4f | %.4f | %s | %s | %s | %s |\n",
                  fs::path(g.race).filename().c_str(), fs::path(g.contender).filename().c_str(), g.golden, g.ours,
                  frame(g.first_update[0]).c_str(), frame(g.first_update[1]).c_str(), frame(g.first_update[2]).c_str(),
                  diagnosis.c_str());
    o << text;
  }
  return o.str();
}

} // namespace sodaevo::bench

namespace sodaevo::bench {

namespace {

/// A lane model without its bars: the creature on the container's floor.
soda::ModelDef without_fixed_bars(soda::ModelDef def) {
  std::erase_if(def.links, [](const soda::LinkDef& l) { return l.kind == soda::LinkKind::FixedBar; });
  return def;
}

/// The contender files of a folder, sorted.
std::vector<fs::path> contender_files(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".xml") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

double best_fps(const soda::Model& model, long long frames, int repeats, soda::FastStepOptions options = {},
                long long* bar_rules = nullptr) {
  double best = 0.0;
  soda::FastStepper stepper(model, frames, options);
  for (int r = 0; r < repeats; ++r) {
    soda::State state = soda::make_state(model);
    const auto t0 = std::chrono::steady_clock::now();
    stepper.run(state, frames);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (s > 0.0) best = std::max(best, static_cast<double>(frames) / s);
  }
  if (bar_rules != nullptr) *bar_rules = stepper.bar_rules_run();
  return best;
}

} // namespace

LaneSpeed measure_lane_speed(const fs::path& race_file, const fs::path& contender, long long frames, int repeats) {
  const soda::RaceDef race = soda::read_race_file(race_file);
  const soda::RaceLane lane =
      soda::build_lane(race.terrain, race.constraints, soda::read_model_file(contender).def, contender.string());
  const soda::Model with_bars = soda::build_lane_model(lane);
  const soda::Model without_bars = soda::build_model(without_fixed_bars(lane.def));
  LaneSpeed out;
  out.masses = with_bars.mass_count;
  soda::FastStepOptions ordered;
  ordered.force_ordered = true;
  // Alternated, so that all see the same machine load.
  for (int r = 0; r < repeats; ++r) {
    long long rules = 0;
    out.lane_fps = std::max(out.lane_fps, best_fps(with_bars, frames, 1, {}, &rules));
    out.rules_per_frame = static_cast<double>(rules) / static_cast<double>(frames);
    out.floor_fps = std::max(out.floor_fps, best_fps(without_bars, frames, 1));
    out.ordered_fps = std::max(out.ordered_fps, best_fps(with_bars, frames, 1, ordered));
  }
  return out;
}

namespace {

double seconds_of(const std::function<void()>& work) {
  const auto t0 = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Lane-frames per second of `models` stepped `frames` frames, fused or one by one.
double lanes_fps(const std::vector<soda::Model>& models, long long frames, bool fused) {
  std::vector<const soda::Model*> pointers;
  std::vector<soda::State> states;
  for (const soda::Model& m : models) {
    pointers.push_back(&m);
    states.push_back(soda::make_state(m));
  }
  const double s = seconds_of([&] {
    if (fused) {
      std::vector<soda::State*> sp;
      for (soda::State& st : states) sp.push_back(&st);
      soda::BatchStepper batch(pointers, frames);
      batch.run(sp, frames);
    } else {
      for (std::size_t k = 0; k < models.size(); ++k) {
        soda::FastStepper stepper(models[k], frames);
        stepper.run(states[k], frames);
      }
    }
  });
  return s > 0.0 ? static_cast<double>(models.size()) * static_cast<double>(frames) / s : 0.0;
}

} // namespace

FusedLaneSpeed measure_fused_lanes(const fs::path& race_file, const fs::path& contenders_dir, long long frames,
                                   int repeats) {
  const soda::RaceDef race = soda::read_race_file(race_file);
  std::vector<soda::RaceLane> lanes;
  for (const fs::path& file : contender_files(contenders_dir)) {
    lanes.push_back(soda::build_lane(race.terrain, race.constraints, soda::read_model_file(file).def, file.string()));
  }
  std::vector<soda::Model> with_bars, without_bars;
  for (const soda::RaceLane& lane : lanes) {
    with_bars.push_back(soda::build_lane_model(lane));
    without_bars.push_back(soda::build_model(without_fixed_bars(lane.def)));
  }
  FusedLaneSpeed out;
  out.lanes = static_cast<int>(lanes.size());
  const auto best_time = [](double& best, double s) { best = best == 0.0 ? s : std::min(best, s); };
  for (int r = 0; r < repeats; ++r) { // alternated, so that all see the same machine load
    out.alone_fps = std::max(out.alone_fps, lanes_fps(with_bars, frames, false));
    out.fused_fps = std::max(out.fused_fps, lanes_fps(with_bars, frames, true));
    out.floor_alone_fps = std::max(out.floor_alone_fps, lanes_fps(without_bars, frames, false));
    out.floor_fused_fps = std::max(out.floor_fused_fps, lanes_fps(without_bars, frames, true));
    std::vector<soda::State> alone, together;
    for (const soda::Model& m : with_bars) {
      alone.push_back(soda::make_state(m));
      together.push_back(alone.back());
    }
    long long updates = 0;
    best_time(out.races_alone_s, seconds_of([&] {
                for (std::size_t k = 0; k < lanes.size(); ++k) {
                  updates += soda::run_race_fast(lanes[k], with_bars[k], race.timeout, alone[k]).updates;
                }
              }));
    std::vector<soda::LaneRace> races;
    for (std::size_t k = 0; k < lanes.size(); ++k) races.push_back({&lanes[k], &with_bars[k], race.timeout, &together[k]});
    best_time(out.races_fused_s, seconds_of([&] { soda::run_races_together(races); }));
    out.race_frames = updates;
  }
  return out;
}

} // namespace sodaevo::bench
