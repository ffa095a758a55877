#include "test_support.hpp"

#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/input_error.hpp"
#include "core/step.hpp"
#include "formats/model_file.hpp"

namespace sodaevo::test {

namespace fs = std::filesystem;

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

std::string compare_states(const soda::Model& m, const soda::State& a, const soda::State& b) {
  if (a.frame != b.frame) return "frame counter";
  if (!same_bits(a.wave_phase, b.wave_phase)) return "wave phase";
  if (a.wave_mode != b.wave_mode) return "wave mode";
  if (a.last_side_wall != b.last_side_wall) return "last side wall";
  if (!(a.bar_memory == b.bar_memory)) return "bar memory (masses the bars remember, corners)";
  for (int p = 0; p < m.point_count; ++p) {
    if (!same_bits(a.x[p], b.x[p]) || !same_bits(a.y[p], b.y[p]) || !same_bits(a.vx[p], b.vx[p]) ||
        !same_bits(a.vy[p], b.vy[p])) {
      return "point " + std::to_string(p);
    }
  }
  return {};
}

std::string compare_in_pieces(const std::vector<const soda::Model*>& models, std::vector<soda::State>& states,
                              long long frames, const std::function<void(long long)>& step) {
  std::vector<soda::State> ref;
  for (const soda::State& s : states) ref.push_back(s);
  const long long pieces[] = {1, 1, 7, 100, 391};
  long long done = 0;
  std::size_t next = 0;
  while (done < frames) {
    const long long n = std::min(frames - done, next < std::size(pieces) ? pieces[next++] : frames);
    step(n);
    done += n;
    for (std::size_t k = 0; k < models.size(); ++k) {
      soda::run(*models[k], ref[k], n);
      const std::string diff = compare_states(*models[k], ref[k], states[k]);
      if (!diff.empty()) return "entry " + std::to_string(k) + " at frame " + std::to_string(done) + ": " + diff;
    }
  }
  return {};
}

fs::path data_dir() { return SODAEVO_TEST_DATA_DIR; }
fs::path golden_dir() { return data_dir() / "soda" / "golden"; }
fs::path models_dir() { return SODAEVO_MODELS_DIR; }
fs::path shared_models_dir() {
  fs::path p = fs::path(SODAEVO_SHARED_DIR) / "models" / "soda";
  return fs::is_directory(p) ? p : fs::path();
}

std::vector<std::string> read_lines(const fs::path& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (f == nullptr) throw std::runtime_error("cannot open " + path.string());
  std::vector<std::string> lines;
  std::string line;
  char chunk[4096];
  while (gzgets(f, chunk, sizeof chunk) != nullptr) {
    line += chunk;
    if (line.back() != '\n') continue; // a longer line: read on
    line.pop_back();
    lines.push_back(std::move(line));
    line.clear();
  }
  if (!line.empty()) lines.push_back(std::move(line));
  gzclose(f);
  return lines;
}

std::vector<GoldenRow> read_golden_trace(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path.string());
  std::vector<GoldenRow> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::istringstream fields(line);
    GoldenRow row;
    fields >> row.wave_phase >> row.wave_mode;
    double v;
    while (fields >> v) row.values.push_back(v);
    rows.push_back(std::move(row));
  }
  return rows;
}

std::vector<GoldenCentroid> read_golden_centroids(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path.string());
  std::vector<GoldenCentroid> rows;
  GoldenCentroid r;
  while (in >> r.frame >> r.mean_x >> r.mean_y >> r.wave_phase >> r.wave_mode) rows.push_back(r);
  return rows;
}

std::vector<double> state_values(const soda::Model& model, const soda::State& state) {
  std::vector<double> v;
  for (int i = 0; i < model.mass_count; ++i) {
    v.insert(v.end(), {state.x[i], state.y[i], state.vx[i], state.vy[i]});
  }
  return v;
}

Scene load_scene(const fs::path& path) {
  soda::LoadedModel loaded = soda::read_model_file(path);
  soda::Model model = soda::build_model(loaded.def);
  return {std::move(loaded.def), std::move(model)};
}

std::optional<Scene> load_scene_unless_race(const fs::path& path) {
  // The racer's contender-filter golden set: inputs only the racer takes (self
  // links, infinite lanes); test_contender_filter.cpp runs them as the racer does.
  if (path.parent_path().filename() == "components" && path.parent_path().parent_path().filename() == "terrain") {
    return std::nullopt;
  }
  try {
    return load_scene(path);
  } catch (const soda::InputError& e) {
    if (std::string(e.what()).find("race") != std::string::npos) return std::nullopt;
    throw;
  }
}

ShellResult run_shell(const std::string& command) {
  ShellResult r;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("cannot run: " + command);
  std::array<char, 4096> buf{};
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string sodaevo_command(const std::string& args) { return std::string(SODAEVO_BINARY) + " " + args; }

ShellResult run_sodaevo(const std::string& args) { return run_shell(sodaevo_command(args)); }

std::vector<fs::path> xml_files_under(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file() && e.path().extension() == ".xml") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

fs::path fresh_temp_dir(const std::string& name) {
  fs::path d = fs::temp_directory_path() / ("sodaevo_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::vector<soda::SimdLevel> supported_levels() {
  std::vector<soda::SimdLevel> levels;
  for (auto l : {soda::SimdLevel::Sse2, soda::SimdLevel::Avx2, soda::SimdLevel::Avx512}) {
    if (soda::simd_level_supported(l)) levels.push_back(l);
  }
  return levels;
}

RunConfig walker_run_config(const std::string& name, std::uint64_t seed, int population, int generations,
                            int frames, int settle_frames) {
  RunConfig c;
  c.name = name;
  c.seed = seed;
  c.population.size = population;
  c.population.seed_models = {std::filesystem::absolute(models_dir() / "dainty_walker.xml").string()};
  c.budget.generations = generations;
  c.fitness.frames = frames;
  c.fitness.settle_frames = settle_frames;
  // Two replicas for new creatures, survivors up to four: the tests exercise the
  // replica estimate and its resampling at a quarter of the default's cost.
  c.fitness.replicas = 2;
  c.fitness.replicas_max = 4;
  return c;
}

} // namespace sodaevo::test
