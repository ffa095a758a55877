#include "bench/speed_bench.hpp"

#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "bench/speed_engines.hpp"
#include "bench/speed_sections.hpp"
#include "bench/synthetic.hpp"
#include "core/lockstep_batch.hpp"
#include "core/model.hpp"
#include "core/simd_level.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/store/run_reader.hpp"
#include "evolve/problems/walk_problem.hpp"
#include "formats/model_file.hpp"

namespace sodaevo::bench {
namespace {

/// The first "model name" of /proc/cpuinfo ("" where there is none).
std::string cpu_model_name() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("model name", 0) != 0) continue;
    const std::size_t colon = line.find(':');
    return colon == std::string::npos ? std::string() : line.substr(line.find_first_not_of(' ', colon + 1));
  }
  return {};
}

} // namespace

void time_creature_section(const SpeedSectionInput& in, SpeedReport& report) {
  for (const auto& [name, model] : in.creatures) {
    in.say("creature " + name + " (" + std::to_string(model.mass_count) + " masses, " +
        std::to_string(model.link_count()) + " links)");
    const EngineChoice every{.reference = true, .batch = true, .no_wave = true};
    for (SpeedRow& r : time_engines("creature", name, size_of(model), make_engines(model, every), in.runs, in.target)) {
      report.rows.push_back(r);
    }
  }

}

void time_size_section(const SpeedSectionInput& in, SpeedReport& report) {
  const std::vector<int> sizes = in.options.quick ? std::vector<int>{10, 100, 1000, 10000, 100000}
                                               : std::vector<int>{10, 30, 100, 300, 1000, 3000, 10000, 30000, 100000};
  for (int links : sizes) {
    const soda::Model model = soda::build_model(synthetic_creature(links));
    in.say("synthetic " + std::to_string(links) + " links");
    for (SpeedRow& r : time_engines("size", "synthetic", size_of(model), make_engines(model, {}), in.runs, in.target)) {
      if (r.engine == "fast" && r.link_updates_per_second > report.best_link_updates_per_second) {
        report.best_link_updates_per_second = r.link_updates_per_second;
        report.best_links = r.links;
      }
      report.rows.push_back(r);
    }
  }

}

/// Every creature of the saved generations, prepared as the GA evaluates them.
void time_ga_section(const SpeedSectionInput& in, SpeedReport& report) {
  if (in.options.ga_run.empty()) return;
  const std::filesystem::path run(in.options.ga_run);
  const RunConfig config = read_run_config(run / "config.json");
  const WalkProblem problem = walk_problem_of(config);
  std::vector<int> generations = saved_generations(run);
  if (generations.empty()) throw std::runtime_error(in.options.ga_run + ": the run has no saved generation");
  if (in.options.quick && generations.size() > 2) generations = {generations.front(), generations.back()};
  auto models = std::make_shared<std::vector<soda::Model>>();
  double links = 0.0;
  for (int g : generations) {
    for (const Individual& individual : read_saved_generation(run, g).individuals) {
      // As the GA's estimator: a creature the problem refuses is not stepped.
      soda::ModelDef prepared;
      try {
        prepared = problem.prepare(individual.creature);
      } catch (const std::exception&) {
        ++report.ga_refused;
        continue;
      }
      models->push_back(soda::build_model(prepared));
      links += models->back().link_count();
    }
  }
  if (models->empty()) throw std::runtime_error(in.options.ga_run + ": no creature of the saved generations can be stepped");
  report.ga_run = in.options.ga_run;
  report.ga_generations = static_cast<int>(generations.size());
  report.ga_creatures = static_cast<int>(models->size());
  report.ga_mean_links = links / static_cast<double>(models->size());
  in.say("the GA's creatures: " + std::to_string(report.ga_creatures) + " from " +
      std::to_string(report.ga_generations) + " saved generations of " + in.options.ga_run);
  for (SpeedRow& r : time_engines("ga", "ga_run", {0, report.ga_mean_links},
                                  make_ga_engines(models), in.runs, in.target)) {
    report.rows.push_back(r);
  }
}

SpeedReport run_speed_bench(const SpeedOptions& options) {
  SpeedReport report;
  soda::SimdLevel forced = soda::SimdLevel::Auto;
  if (!soda::parse_simd_level(options.simd.c_str(), forced)) {
    throw std::invalid_argument("bench speed: --simd " + options.simd + ": expected auto, sse2, avx2 or avx512");
  }
  soda::force_simd_level(forced);
  report.simd = soda::simd_level_name(soda::best_simd_level());
  report.lockstep = soda::LockstepBatch::usable() ? soda::simd_level_name(soda::LockstepBatch::level_for(soda::SimdLevel::Auto)) : "none";
  report.cpu = cpu_model_name();
  report.cpu_time = options.cpu_time;
  time_engines_by_cpu(options.cpu_time);
  std::vector<std::pair<std::string, soda::Model>> creatures;
  for (const auto& [name, path] : options.creatures) {
    creatures.emplace_back(name, soda::build_model(soda::read_model_file(path).def));
  }
  const SpeedSectionInput in{.options = options,
                             .runs = options.quick ? 3 : 11,
                             .target = options.quick ? 0.02 : 0.12,
                             .creatures = creatures,
                             .say = [&](const std::string& s) {
                               if (options.progress) options.progress(s);
                             }};
  // The GA's section runs before the population's, the longest.
  struct Section {
    bool SpeedOptions::*wanted;
    void (*time)(const SpeedSectionInput&, SpeedReport&);
  };
  for (const Section& section : {Section{&SpeedOptions::creature_section, time_creature_section},
                                 Section{&SpeedOptions::size_section, time_size_section},
                                 Section{&SpeedOptions::ga_section, time_ga_section},
                                 Section{&SpeedOptions::population_section, time_population_section}}) {
    if (options.*section.wanted) section.time(in, report);
  }
  return report;
}

} // namespace sodaevo::bench
