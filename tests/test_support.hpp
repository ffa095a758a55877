// Shared helpers for the tests: where the data is, reading golden traces, and
// running the built binary in fresh folders.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/fast_step.hpp"
#include "core/model.hpp"
#include "evolve/config/run_config.hpp"

namespace sodaevo::test {

std::filesystem::path data_dir();    ///< tests/data
std::filesystem::path golden_dir();  ///< tests/data/soda/golden (copied from ../shared)
std::filesystem::path models_dir();  ///< models/ (the bundled creatures)
/// ../shared/models/soda if present (the developers' workspace), else empty.
std::filesystem::path shared_models_dir();

/// The lines of a text file, gzip-compressed or not (zlib reads both); throws if it
/// cannot be opened.
std::vector<std::string> read_lines(const std::filesystem::path& path);

/// One row of a golden trace of the original engine: wave phase, wave mode, then
/// x, y, vx, vy per mass (golden/README.md).
struct GoldenRow {
  double wave_phase = 0.0;
  int wave_mode = 0;
  std::vector<double> values; ///< x0 y0 vx0 vy0 x1 ...
};
std::vector<GoldenRow> read_golden_trace(const std::filesystem::path& path);

/// One row of a golden centroid file: frame meanX meanY wavePhase waveMode.
struct GoldenCentroid {
  long long frame = 0;
  double mean_x = 0.0, mean_y = 0.0, wave_phase = 0.0;
  int wave_mode = 0;
};
std::vector<GoldenCentroid> read_golden_centroids(const std::filesystem::path& path);

/// Whether a and b are the same double to the bit (tells -0 from 0, compares NaNs).
bool same_bits(double a, double b);

/// The state's values in golden-row order (x, y, vx, vy per free mass).
std::vector<double> state_values(const soda::Model& model, const soda::State& state);

/// Empty string if the two states of `model` are equal in every bit, else where
/// they first differ.
std::string compare_states(const soda::Model& model, const soda::State& a, const soda::State& b);

/// Steps `states` (a state of each of `models`) with `step(frames)` and each
/// model's reference (soda::run) side by side, in pieces of 1, 1, 7, 100 and 391
/// frames and then the rest, up to `frames`; returns where they first differ
/// ("entry k at frame f: ..."), or an empty string.
std::string compare_in_pieces(const std::vector<const soda::Model*>& models, std::vector<soda::State>& states,
                              long long frames, const std::function<void(long long)>& step);

/// Loads a model file and builds it (fails the test on any error).
struct Scene {
  soda::ModelDef def;
  soda::Model model;
};
Scene load_scene(const std::filesystem::path& path);
/// load_scene, or nullopt for a Sodarace race file (it holds no model) and for the
/// racer-only contender-filter golden set (terrain/components: see
/// test_contender_filter.cpp); other errors still throw.
std::optional<Scene> load_scene_unless_race(const std::filesystem::path& path);

/// Runs a shell command; its exit code and stdout+stderr together.
struct ShellResult {
  int exit_code = -1;
  std::string output;
};
ShellResult run_shell(const std::string& command);

/// The shell command that runs the built sodaevo binary with `args`.
std::string sodaevo_command(const std::string& args);
/// run_shell(sodaevo_command(args)).
ShellResult run_sodaevo(const std::string& args);

/// Every .xml file under `dir` (recursively), sorted.
std::vector<std::filesystem::path> xml_files_under(const std::filesystem::path& dir);

/// A fresh, empty folder under the system's temp folder, unique to this process.
std::filesystem::path fresh_temp_dir(const std::string& name);

/// The SIMD levels of the fast stepper this CPU can run (core/fast_step.hpp).
std::vector<soda::SimdLevel> supported_levels();

/// A small evolution run for tests: the Dainty Walker as seed model, every other
/// key at its default.
RunConfig walker_run_config(const std::string& name, std::uint64_t seed, int population, int generations,
                            int frames, int settle_frames);

} // namespace sodaevo::test
