#include "evolve/config/race_fitness_config.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <optional>
#include <system_error>

#include "core/number_text.hpp"
#include "core/race_def.hpp"
#include "evolve/problems/race_problem.hpp"
#include "evolve/config/strict_json.hpp"
#include "formats/race_file.hpp"

namespace sodaevo {

namespace fs = std::filesystem;
using nlohmann::json;


fs::path find_race_terrain(const std::string& entry, const fs::path& base_dir) {
  std::error_code ec;
  const fs::path given(entry);
  const fs::path relative = (given.is_absolute() ? given : base_dir / given).lexically_normal();
  if (fs::is_regular_file(relative, ec)) return fs::absolute(relative, ec).lexically_normal();
  if (given.has_parent_path()) return {};
  const std::string file = given.extension() == ".xml" ? entry : entry + ".xml";
  for (const fs::path& dir : {base_dir / ".." / "models" / "terrains", fs::current_path(ec) / "models" / "terrains"}) {
    const fs::path p = (dir / file).lexically_normal();
    if (fs::is_regular_file(p, ec)) return fs::absolute(p, ec).lexically_normal();
  }
  return {};
}

namespace {

class RaceFitnessReader {
 public:
  RaceFitnessReader(const fs::path& base_dir, RaceFitnessConfig& config, std::vector<ConfigProblem>& problems)
      : base_dir_(base_dir), config_(config), problems_(problems) {}

  void read(const json& v) {
    static const std::vector<std::string> keys = {"terrains",       "combine",    "score", "timeout",
                                                  "timeout_factor", "curriculum"};
    if (!v.is_object()) {
      return expected("", "an object with keys terrains, combine, score, timeout, timeout_factor, curriculum", v);
    }
    for (const auto& [key, value] : v.items()) {
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
        problem("/" + key,
                "unknown key (expected one of: terrains, combine, score, timeout, timeout_factor, curriculum)");
      }
    }
    if (const auto it = v.find("score"); it != v.end()) {
      const std::optional<RaceScore> score =
          it->is_string() ? soda::value_of(kRaceScoreNames, it->get<std::string>()) : std::nullopt;
      if (score) config_.score = *score;
      else expected("/score", "one of \"racer\" or \"progress\"", *it);
    }
    if (v.contains("curriculum") && v.contains("terrains")) {
      problem("/terrains", "expected no terrains with /fitness/race/curriculum (its stages name them), got both");
    }
    read_curriculum(v);
    if (const auto it = v.find("timeout_factor"); it != v.end()) {
      constexpr double kMaxFactor = 100.0;
      const bool valid = it->is_number() && (it->get<double>() == 0.0 ||
                                             (it->get<double>() >= 1.0 && it->get<double>() <= kMaxFactor));
      if (!valid) expected("/timeout_factor", "0 (off) or a number in [1, 100]", *it);
      else config_.timeout_factor = it->get<double>();
    }
    if (const auto it = v.find("combine"); it != v.end()) {
      const std::optional<RaceCombine> combine =
          it->is_string() ? soda::value_of(kRaceCombineNames, it->get<std::string>()) : std::nullopt;
      if (combine) config_.combine = *combine;
      else expected("/combine", "one of \"mean\" or \"worst\"", *it);
    }
    if (const auto it = v.find("timeout"); it != v.end()) {
      const bool integral = it->is_number() && it->get<double>() == std::floor(it->get<double>());
      if (!integral || it->get<double>() < 0 || it->get<double>() > soda::kMaxRaceTimeout) {
        expected("/timeout", "an integer in [0, " + std::to_string(soda::kMaxRaceTimeout) + "] (0: the race file's)",
                 *it);
      } else {
        config_.timeout = static_cast<int>(it->get<double>());
      }
    }
    read_terrains(v);
  }

 private:
  void problem(const std::string& pointer, const std::string& message) {
    problems_.push_back({"/fitness/race" + pointer, message});
  }
  void expected(const std::string& pointer, const std::string& what, const json& got) {
    problem(pointer, "expected " + what + ", got " + show_json(got));
  }

  /// The race file a terrain entry names, or empty after reporting why not.
  std::string terrain_file(const json& item, const std::string& at) {
    if (!item.is_string() || item.get<std::string>().empty()) {
      expected(at, "a race file or a bundled terrain name (e.g. \"TerrainFlat\")", item);
      return {};
    }
    const fs::path found = find_race_terrain(item.get<std::string>(), base_dir_);
    if (found.empty()) {
      expected(at, "an existing race file (looked in " + base_dir_.string() + ") or a bundled terrain of models/terrains/",
               item);
      return {};
    }
    try {
      (void)soda::read_race_file(found);
    } catch (const std::exception& ex) {
      problem(at, std::string("expected a race file, got one that does not read: ") + ex.what());
      return {};
    }
    return found.string();
  }

  void read_curriculum(const json& v) {
    const auto it = v.find("curriculum");
    if (it == v.end()) return;
    if (!it->is_array() || it->empty() || it->size() > static_cast<std::size_t>(kMaxCurriculumStages)) {
      return expected("/curriculum", "an array of 1 to 64 stages {\"terrain\": ..., \"threshold\": frames}", *it);
    }
    std::vector<CurriculumStage> stages;
    for (std::size_t i = 0; i < it->size(); ++i) {
      const json& item = (*it)[i];
      const std::string at = "/curriculum/" + std::to_string(i);
      const bool last = i + 1 == it->size();
      if (!item.is_object()) {
        expected(at, "an object {\"terrain\": ..., \"threshold\": frames}", item);
        continue;
      }
      for (const auto& [key, value] : item.items()) {
        if (key != "terrain" && key != "threshold") problem(at + "/" + key, "unknown key (expected terrain or threshold)");
      }
      CurriculumStage stage;
      if (!item.contains("terrain")) problem(at + "/terrain", "expected a race file or a bundled terrain name, got nothing");
      else stage.terrain = terrain_file(item["terrain"], at + "/terrain");
      if (const auto t = item.find("threshold"); t != item.end()) {
        if (!t->is_number() || !(t->get<double>() > 0.0) || t->get<double>() > soda::kMaxRaceTimeout) {
          expected(at + "/threshold", "frames in (0, " + std::to_string(soda::kMaxRaceTimeout) + "]", *t);
        } else {
          stage.threshold = t->get<double>();
        }
      } else if (!last) {
        problem(at + "/threshold", "expected the frames under which the best racer moves on to stage " +
                                       std::to_string(i + 1) + ", got nothing");
      }
      stages.push_back(stage);
    }
    const bool complete = stages.size() == it->size() &&
                          std::none_of(stages.begin(), stages.end(), [](const CurriculumStage& s) { return s.terrain.empty(); });
    if (complete) config_.curriculum = std::move(stages);
  }

  void read_terrains(const json& v) {
    const auto it = v.find("terrains");
    if (it == v.end()) return; // checked with /fitness/kind (a race needs terrains)
    constexpr std::size_t kMaxTerrains = 64;
    if (!it->is_array() || it->empty() || it->size() > kMaxTerrains) {
      return expected("/terrains", "an array of 1 to 64 race files or bundled terrain names", *it);
    }
    std::vector<std::string> paths;
    for (std::size_t i = 0; i < it->size(); ++i) {
      std::string file = terrain_file((*it)[i], "/terrains/" + std::to_string(i));
      if (!file.empty()) paths.push_back(std::move(file));
    }
    if (paths.size() == it->size()) config_.terrains = std::move(paths);
  }

  fs::path base_dir_;
  RaceFitnessConfig& config_;
  std::vector<ConfigProblem>& problems_;
};

} // namespace

void read_race_fitness(const json& value, const fs::path& base_dir, RaceFitnessConfig& config,
                       std::vector<ConfigProblem>& problems) {
  RaceFitnessReader(base_dir, config, problems).read(value);
}

std::vector<ConfigProblem> race_fitness_conflicts(FitnessKind kind, const RaceFitnessConfig& race, bool race_given,
                                                  const MapElitesConfig* map_elites, bool soda_mode) {
  std::vector<ConfigProblem> out;
  if (kind != FitnessKind::Race) {
    if (race_given) out.push_back({"/fitness/race", "expected only with /fitness/kind \"race\", got it with \"walk\""});
    return out;
  }
  if (map_elites != nullptr && race.timeout_factor > 0.0) {
    out.push_back({"/fitness/race/timeout_factor", "expected 0 with /algorithm \"map-elites\" (an archive has no "
                                                   "generations), got " + soda::format_double_plain(race.timeout_factor)});
  }
  if (map_elites != nullptr && !race.curriculum.empty()) {
    out.push_back({"/fitness/race/curriculum", "expected no curriculum with /algorithm \"map-elites\" (an archive "
                                               "has no generations), got " + std::to_string(race.curriculum.size()) +
                                               " stages"});
  }
  if (race.terrains.empty() && race.curriculum.empty()) {
    out.push_back({"/fitness/race/terrains",
                   "expected at least one race file or bundled terrain with /fitness/kind \"race\", got none"});
  }
  for (std::size_t i = 0; map_elites != nullptr && i < map_elites->axes.size(); ++i) {
    const Descriptor d = map_elites->axes[i].descriptor;
    if (race_describes(d)) continue;
    out.push_back({"/map_elites/descriptors/" + std::to_string(i),
                   "expected one of \"mass_count\", \"muscle_share\", \"width\", \"height\" with /fitness/kind \"race\" "
                   "(a lane's ground is its terrain, not the floor), got \"" + descriptor_name(d) + "\""});
  }
  if (!soda_mode) {
    out.push_back({"/fitness/kind", "expected \"walk\" with /fitness/mode \"continuous\", /fitness/divergence \"energy\" "
                                    "or /fitness/honesty (a race runs the racer's own step), got \"race\""});
  }
  return out;
}

json to_json(const RaceFitnessConfig& c) {
  json j = {{"terrains", c.terrains},
          {"combine", race_combine_name(c.combine)},
          {"score", race_score_name(c.score)},
          {"timeout", c.timeout},
          {"timeout_factor", c.timeout_factor}};
  if (!c.curriculum.empty()) { // instead of terrains
    j.erase("terrains");
    json stages = json::array();
    for (const CurriculumStage& s : c.curriculum) {
      json stage = {{"terrain", s.terrain}};
      if (s.threshold > 0.0) stage["threshold"] = s.threshold;
      stages.push_back(std::move(stage));
    }
    j["curriculum"] = std::move(stages);
  }
  return j;
}

} // namespace sodaevo
