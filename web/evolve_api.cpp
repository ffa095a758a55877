// The evolution in WebAssembly (web/build_wasm.sh builds soda_evolve_wasm.js from
// this file, evolve/, formats/ and core/ with 128-bit SIMD): a C interface for the
// page (web/evolve_driver.js) in two roles.
//
//  - The driver (one instance, the page's thread) runs the library's own loop,
//    run_evolution or run_map_elites, on a run folder in the instance's memory
//    file system. Its Evaluator cannot wait for the Web Workers (a page has no
//    blocking wait without SharedArrayBuffer, which a page opened from a file does
//    not get), so it asks instead: an AskTellEvaluator
//    (evolve/evaluators/ask_tell_evaluator.hpp) throws the request out of the loop, the
//    workers evaluate it, and the loop is run again from the checkpoint.
//  - A worker (one instance per Web Worker) evaluates a chunk of a request: the
//    wire format of evolve/wire_format.hpp, as the MPI workers get theirs.
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <emscripten/emscripten.h>
#include <nlohmann/json.hpp>

#include "evolve/problems/fitness_kind.hpp"
#include "core/input_error.hpp"
#include "evolve/runs/archive_check.hpp"
#include "evolve/evaluators/ask_tell_evaluator.hpp"
#include "evolve/store/archive_store.hpp"
#include "evolve/evaluators/evaluator.hpp"
#include "evolve/runs/evolution_run.hpp"
#include "evolve/runs/map_elites_run.hpp"
#include "evolve/runs/race_schedule.hpp"
#include "evolve/runs/replica_check.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/store/run_reader.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/store/run_store.hpp"
#include "evolve/problems/wire_format.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"
#include "core/fast_step.hpp"
#include "core/model.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace sodaevo;

namespace {

std::string g_out; ///< the last answer's bytes (text or wire), read by JavaScript

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

/// The creature as text the designer opens (its export form: what is stepped).
std::string creature_xml(const Problem& problem, const Individual& ind) {
  return soda::write_model_text(problem.export_form(ind.creature, ind.id, ind.evaluation));
}

json individual_json(const Problem& problem, const Individual& ind) {
  json j = {{"id", ind.id},
            {"status", ind.evaluation.ok() ? "ok" : ind.evaluation.status == EvaluationStatus::Diverged ? "diverged" : "invalid"},
            {"reason", ind.evaluation.reason},
            {"fitness", number(ind.evaluation.fitness)},
            {"replicas", ind.evaluation.estimate.rollouts},
            {"sd", ind.evaluation.estimate.sd}};
  try {
    j["xml"] = creature_xml(problem, ind);
  } catch (const std::exception& e) {
    j["xml"] = nullptr;
    j["xml_error"] = e.what();
  }
  return j;
}

struct Run {
  std::optional<RunStore> store;
  AskTellEvaluator evaluator;
  std::atomic<bool> stop{false};
  json last_progress;
  bool finished = false;
  std::string stopped_because;
  std::string best_id;
  double best_fitness = kWorstFitness;
};

std::unique_ptr<Run> g_run;

constexpr int kStripSize = 8; ///< the generation's best few, shown as a strip

/// What the page shows after a generation of the GA: its statistics and best few.
json generation_json(const RunStore& store, const Progress& p) {
  json j = {{"algorithm", "ga"},
            {"generation", p.generation},
            {"generations", p.generations},
            {"evaluations", p.stats.evaluations},
            {"best", number(p.stats.best)},
            {"mean", number(p.stats.mean)},
            {"median", number(p.stats.median)},
            {"worst", number(p.stats.worst)},
            {"invalid", p.stats.invalid},
            {"diverged", p.stats.diverged}};
  const std::optional<Checkpoint> c = store.read_checkpoint(); // this generation: the stop checkpointed it
  if (!c || c->generation.index != p.generation) return j;
  const Generation& g = c->generation;
  const std::unique_ptr<Problem> problem = problem_of(store.config(), 0);
  json strip = json::array();
  for (std::size_t i : ranked_best_first(g)) {
    if (strip.size() >= kStripSize) break;
    strip.push_back(individual_json(*problem, g.individuals[i]));
  }
  j["strip"] = std::move(strip);
  // The best's spread: its replicas' sd (the interval the chart draws).
  if (p.stats.best_index >= 0) {
    const Estimate& e = g.individuals[static_cast<std::size_t>(p.stats.best_index)].evaluation.estimate;
    j["best_sd"] = e.sd;
    j["best_replicas"] = e.rollouts;
  }
  return j;
}

json map_elites_json(const RunStore& store, const MapElitesProgress& p) {
  json j = {{"algorithm", "map-elites"},
            {"iteration", p.iteration},
            {"iterations", p.iterations},
            {"evaluations", p.evaluations},
            {"rollouts", p.rollouts},
            {"filled", p.metrics.filled},
            {"cells", p.metrics.cells},
            {"qd_score", p.metrics.qd_score},
            {"best", number(p.metrics.best)}};
  // The archive as the run saved it (archive.json), for the heat map.
  std::error_code ec;
  const fs::path index = store.dir() / "archive.json";
  if (fs::exists(index, ec)) j["archive"] = json::parse(soda::read_whole_file(index), nullptr, false);
  return j;
}

void set_out(const std::string& s) { g_out = s; }

int fail(const std::exception& e) {
  set_out(e.what());
  return -1;
}

} // namespace

extern "C" {

EMSCRIPTEN_KEEPALIVE const char* sev_out() { return g_out.c_str(); }
EMSCRIPTEN_KEEPALIVE int sev_out_size() { return static_cast<int>(g_out.size()); }

/// Writes a file of the instance's memory file system (the bundled models, the
/// config, the current design), creating its folders.
EMSCRIPTEN_KEEPALIVE int sev_write_file(const char* path, const char* bytes, int size) {
  try {
    const fs::path p(path);
    fs::create_directories(p.parent_path());
    soda::write_file_atomically(p, std::string_view(bytes, static_cast<std::size_t>(size)));
    return 0;
  } catch (const std::exception& e) {
    return fail(e);
  }
}

/// Reads a file of the memory file system into sev_out.
EMSCRIPTEN_KEEPALIVE int sev_read_file(const char* path) {
  try {
    set_out(soda::read_whole_file(path));
    return 0;
  } catch (const std::exception& e) {
    return fail(e);
  }
}

/// Reads the config at `config_path` (with the command line's checks and
/// messages) and creates the run folder `run_dir`. 0, or -1 with the message.
EMSCRIPTEN_KEEPALIVE int sev_start(const char* config_path, const char* run_dir) {
  try {
    g_run.reset();
    auto run = std::make_unique<Run>();
    // Read as the command line reads a config named in its own folder, so that its
    // messages name it alike ("config.json: /population/size: ...").
    const fs::path given(config_path);
    if (given.has_parent_path()) fs::current_path(given.parent_path());
    const std::string config_name = given.filename().string();
    const RunConfig config = read_run_config(config_name);
    try {
      load_seed_creatures(config);
    } catch (const soda::InputError& e) {
      throw soda::InputError(config_name + ": " + e.what());
    }
    run->store.emplace(RunStore::create(run_dir, config, true, "sodaevo evolve " + config_name + " (in the browser)"));
    json j = {{"name", config.name},
              {"algorithm", algorithm_name(config.algorithm)},
              {"race", config.fitness.kind == FitnessKind::Race},
              {"unit", fitness_kind_info(config.fitness.kind).unit},
              {"lower_is_better", fitness_kind_info(config.fitness.kind).lower_is_better},
              {"generations", config.budget.generations},
              {"frames", config.fitness.frames},
              {"config", to_json(config)}};
    if (config.algorithm == AlgorithmKind::MapElites) {
      j["iterations"] = config.map_elites.iterations;
    }
    set_out(j.dump());
    g_run = std::move(run);
    return 0;
  } catch (const std::exception& e) {
    return fail(e);
  }
}

/// Runs the loop as far as it goes: 1 it asks for an evaluation (sev_request_*),
/// 2 a generation (iteration) was finished and saved (progress JSON in sev_out),
/// 3 the run ended (JSON), -1 an error (the message).
EMSCRIPTEN_KEEPALIVE int sev_advance() {
  if (!g_run) return fail(std::logic_error("no run started"));
  Run& run = *g_run;
  if (run.finished) return 3;
  run.stop = false;
  const RunConfig& config = run.store->config();
  try {
    std::string stopped;
    if (config.algorithm == AlgorithmKind::MapElites) {
      MapElitesOptions options;
      options.stop_requested = &run.stop;
      options.on_iteration = [&](const MapElitesProgress& p) {
        run.stop = true;
        run.last_progress = map_elites_json(*run.store, p);
      };
      const MapElitesOutcome o = run_map_elites(run.store->dir(), config, config.map_elites, run.evaluator, options);
      stopped = stop_reason_name(o.stopped_because);
      run.best_fitness = o.metrics.best;
      if (stopped != "interrupted") run.last_progress = map_elites_json(*run.store, {o.last_iteration, config.map_elites.iterations, o.evaluations, o.rollouts, o.metrics, {}, 0.0});
    } else {
      EvolutionOptions options;
      options.stop_requested = &run.stop;
      options.on_generation = [&](const Progress& p) {
        run.stop = true;
        run.last_progress = generation_json(*run.store, p);
      };
      const EvolutionOutcome o = run_evolution(*run.store, run.evaluator, options);
      stopped = stop_reason_name(o.stopped_because);
      run.best_id = o.best_id;
      run.best_fitness = o.best_fitness;
    }
    run.evaluator.forget(); // a generation is done: its answers are in the run folder
    if (stopped == "interrupted") {
      set_out(run.last_progress.dump());
      return 2;
    }
    run.finished = true;
    run.stopped_because = stopped;
    json j = run.last_progress;
    j["stopped_because"] = stopped;
    set_out(j.dump());
    return 3;
  } catch (const NeedEvaluation&) {
    set_out(std::to_string(run.evaluator.pending_count()));
    return 1;
  } catch (const std::exception& e) {
    return fail(e);
  }
}

/// The pending request's creatures [first, last) in the wire format, in sev_out.
EMSCRIPTEN_KEEPALIVE int sev_request_chunk(int first, int last) {
  if (!g_run) return fail(std::logic_error("no run started"));
  const std::vector<char> bytes = g_run->evaluator.chunk(static_cast<std::size_t>(first), static_cast<std::size_t>(last));
  g_out.assign(bytes.begin(), bytes.end());
  return 0;
}

/// A worker's results for the creatures from `first` on (what sev_evaluate wrote).
/// 1 once the whole request is answered, 0 before, -1 malformed.
EMSCRIPTEN_KEEPALIVE int sev_tell(int first, const char* bytes, int size) {
  if (!g_run) return fail(std::logic_error("no run started"));
  try {
    return g_run->evaluator.tell(static_cast<std::size_t>(first), bytes, static_cast<std::size_t>(size)) ? 1 : 0;
  } catch (const std::exception& e) {
    return fail(e);
  }
}

/// A worker: evaluates a chunk (problem, estimator, count, creatures) on this
/// thread, in fused batches as a thread of `sodaevo evolve` does; sev_out holds
/// the count and the evaluations in order.
EMSCRIPTEN_KEEPALIVE int sev_evaluate(const char* bytes, int size) {
  try {
    WireReader r(bytes, static_cast<std::size_t>(size));
    const std::unique_ptr<Problem> problem = read_problem(r);
    const std::unique_ptr<Estimator> estimator = read_estimator(r);
    const std::uint32_t count = r.u32();
    std::vector<soda::ModelDef> creatures;
    for (std::uint32_t k = 0; k < count; ++k) creatures.push_back(r.creature());
    r.expect_end();
    std::vector<const soda::ModelDef*> pointers;
    for (const soda::ModelDef& c : creatures) pointers.push_back(&c);
    ThreadEvaluator evaluator(1);
    const std::vector<Evaluation> results = evaluator.evaluate(pointers, *problem, *estimator);
    const std::vector<char> wire = encode_evaluations(results);
    g_out.assign(wire.begin(), wire.end());
    return 0;
  } catch (const std::exception& e) {
    return fail(e);
  }
}

/// After the run: what `sodaevo evolve` writes at its end (RUN/champions.json, its
/// best on fresh replicas) and what `sodaevo export RUN --best N` writes for the
/// champions (rank01_<id>.xml ... and champions.json) into `out_dir`. JSON in
/// sev_out: the champion's id, fitness, file name and each exported file's path.
EMSCRIPTEN_KEEPALIVE int sev_export(const char* out_dir, int best_count) {
  if (!g_run || !g_run->finished) return fail(std::logic_error("no finished run"));
  try {
    const fs::path run = g_run->store->dir();
    const RunConfig config = read_run_config(run / "config.json");
    json j = {{"stopped_because", g_run->stopped_because}, {"files", json::array()}};
    if (config.algorithm == AlgorithmKind::MapElites) {
      // As app/evolve_map_elites.cpp ends a run (RUN/archive_checked.json) and
      // app/export_command.cpp's export --archive writes DIR: every elite as
      // cell<N>_<id>.xml, archive.json and champions.json.
      const GridArchive archive = read_run_archive(run, config);
      if (archive.elites().empty()) {
        set_out(j.dump());
        return 0;
      }
      if (config.map_elites.check_replicas > 0) write_checked_archive(run, 1);
      const std::unique_ptr<Problem> problem = problem_of(config, 0);
      const CheckedArchive checked =
          check_archive(archive, *problem, replica_plan(config), 16, 1, config.map_elites.qd_offset);
      const std::string unit = sodaevo::fitness_kind_info(config.fitness.kind).unit;
      fs::create_directories(out_dir);
      json champions = json::array();
      for (std::size_t i = 0; i < checked.cells.size(); ++i) {
        const std::size_t cell = checked.cells[i];
        const ArchiveEntry& e = *archive.elite(cell);
        const std::string name = "cell" + std::to_string(cell) + "_" + e.id + ".xml";
        soda::ModelDef prepared = soda::read_model_file(run / elite_file(e.id)).def;
        prepared.comment += "; " + check_comment(checked.checks[i], unit);
        soda::write_model_file(fs::path(out_dir) / name, prepared);
        json c = champion_json(checked.checks[i], name, config);
        c["cell"] = cell;
        champions.push_back(std::move(c));
      }
      soda::write_file_atomically(fs::path(out_dir) / "archive.json", soda::read_whole_file(run / "archive.json"));
      soda::write_file_atomically(fs::path(out_dir) / "champions.json", champions.dump(2) + "\n");
      j["files"].push_back((fs::path(out_dir) / "champions.json").string());
      set_out(j.dump());
      return 0;
    }
    if (std::isfinite(g_run->best_fitness)) write_run_champions(run, 10, 16, 1); // as evolve_command.cpp
    // As app/export_command.cpp's run_export.
    const std::unique_ptr<Problem> problem = final_problem(run, config);
    fs::create_directories(out_dir);
    const std::vector<Individual> best = best_individuals(run, best_count);
    const std::vector<ReplicaCheck> checks = check_all_on_fresh_replicas(*problem, best, replica_plan(config), 16, 1);
    const std::string unit = sodaevo::fitness_kind_info(config.fitness.kind).unit;
    json champions = json::array();
    for (std::size_t i = 0; i < best.size(); ++i) {
      const Individual& ind = best[i];
      const ExportedChampion exported =
          export_ranked_champion(*problem, ind, checks[i], config, unit, out_dir, static_cast<int>(i + 1));
      const fs::path& file = exported.file;
      champions.push_back(exported.entry);
      j["files"].push_back(file.string());
      if (i == 0) {
        std::uint64_t bits;
        std::memcpy(&bits, &ind.evaluation.fitness, sizeof bits);
        char hex[17];
        std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(bits));
        j["champion"] = {{"id", ind.id}, {"fitness", number(ind.evaluation.fitness)}, {"fitness_bits", hex},
                         {"file", file.string()}};
      }
    }
    const fs::path champions_file = fs::path(out_dir) / "champions.json";
    soda::write_file_atomically(champions_file, champions.dump(2) + "\n");
    j["files"].push_back(champions_file.string());
    set_out(j.dump());
    return 0;
  } catch (const std::exception& e) {
    return fail(e);
  }
}

/// The speed of the fast stepper here (web/README.md, "Speed"): `frames` frames of
/// the model `xml` from its start, on this thread. JSON in sev_out: frames,
/// seconds, frames_per_second and centroid_dx (as `sodaevo simulate --json`
/// gives it: the same number is the same run).
EMSCRIPTEN_KEEPALIVE int sev_fast_run(const char* xml, int size, double frames) {
  try {
    const soda::LoadedModel loaded = soda::read_model_text(std::string_view(xml, static_cast<std::size_t>(size)), "model.xml");
    const soda::Model model = soda::build_model(loaded.def);
    soda::State state = soda::make_state(model);
    const double start = soda::mass_centroid(model, state).x;
    const long long n = static_cast<long long>(frames);
    soda::FastStepper stepper(model, n);
    const double t0 = emscripten_get_now();
    stepper.run(state, n);
    const double seconds = (emscripten_get_now() - t0) / 1000.0;
    const json j = {{"frames", n}, {"seconds", seconds}, {"frames_per_second", seconds > 0 ? frames / seconds : 0.0},
                    {"centroid_dx", soda::mass_centroid(model, state).x - start}};
    set_out(j.dump());
    return 0;
  } catch (const std::exception& e) {
    return fail(e);
  }
}

/// Every file under `dir` (for the run folder's download), one path a line.
EMSCRIPTEN_KEEPALIVE int sev_list_files(const char* dir) {
  try {
    std::string out;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
      if (entry.is_regular_file()) out += entry.path().string() + "\n";
    }
    set_out(out);
    return 0;
  } catch (const std::exception& e) {
    return fail(e);
  }
}

} // extern "C"
