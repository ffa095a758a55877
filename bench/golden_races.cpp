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

} // namespace

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
    if (!g.same()) {
      // The diagnosis: the reference race again, watched frame by frame.
      long long update = 0;
      (void)soda::run_race(lane, model, race.timeout, [&](const soda::State& s) {
        ++update;
        if (g.first_floor_and_bar < 0 && s.bar_memory.floor_and_bar_hits > 0) g.first_floor_and_bar = update;
      });
    }
    out.push_back(g);
  }
  return out;
}

std::string golden_races_report(const std::vector<GoldenRace>& races) {
  std::map<std::string, std::pair<int, int>> per_race; // same, total
  int same = 0, with_residue = 0;
  for (const GoldenRace& g : races) {
    auto& c = per_race[fs::path(g.race).filename().string()];
    c.second += 1;
    c.first += g.same() ? 1 : 0;
    same += g.same() ? 1 : 0;
    with_residue += (!g.same() && g.first_floor_and_bar >= 0) ? 1 : 0;
  }
  std::ostringstream o;
  char text[256];
  std::snprintf(text, sizeof text, "Same result as the original racer: **%d of %zu** races.\n\n", same, races.size());
  o << text;
  o << "| race file | same | of |\n|---|---|---|\n";
  for (const auto& [name, c] : per_race) o << "| " << name << " | " << c.first << " | " << c.second << " |\n";
  const int differ = static_cast<int>(races.size()) - same;
  std::snprintf(text, sizeof text,
                "\n%d differ; %d of them after a floor-or-wall and bar collision in one update (once spec 9's "
                "residue, now reproduced), %d without one (a muscle sine: glibc's here, Java's in the original; or "
                "a rule).\n\n",
                differ, with_residue, differ - with_residue);
  o << text;
  o << "| race | contender | original | ours | first floor+bar update |\n|---|---|---|---|---|\n";
  for (const GoldenRace& g : races) {
    if (g.same()) continue;
    std::snprintf(text, sizeof text, "| %s | %s | %.4f | %.4f | %lld |\n", fs::path(g.race).filename().c_str(),
                  fs::path(g.contender).filename().c_str(), g.golden, g.ours, g.first_floor_and_bar);
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
