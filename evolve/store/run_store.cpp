#include "run_store.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "core/input_error.hpp"
#include "core/number_text.hpp"
#include "core/race_def.hpp"
#include "core/sine_identity.hpp"
#include "evolve/config/input_limits.hpp"
#include "evolve/estimators/sample_summary.hpp"
#include "formats/atomic_file.hpp"
#include "formats/xml_escape.hpp"
#include "formats/generation_xml.hpp"
#include "formats/model_file.hpp"

namespace sodaevo {

namespace fs = std::filesystem;

namespace {

constexpr const char* kGenerationsHeader =
    "generation,evaluations,best,mean,median,worst,invalid,diverged,best_id,best_replicas,best_sd,best_interval95_lo,"
    "best_interval95_hi\n";
constexpr const char* kTimingHeader = "generation,evaluations,wall_seconds,evaluations_per_second\n";

EvaluationStatus parse_status(const std::string& s, const std::string& where) {
  if (s == "ok") return EvaluationStatus::Ok;
  if (s == "invalid") return EvaluationStatus::Invalid;
  if (s == "diverged") return EvaluationStatus::Diverged;
  throw soda::InputError(where + ": status: expected ok, invalid or diverged, got '" + s + "'");
}

double parse_number(const std::string& s, const std::string& where) {
  const std::optional<double> v = soda::parse_double(s);
  if (v && std::isfinite(*v)) return *v;
  throw soda::InputError(where + ": expected a finite number, got '" + s + "'");
}

// Only creatures that were scored have a fitness: files never hold an infinity
// (kWorstFitness stays in memory).
std::string fitness_attribute(const Evaluation& e) {
  return e.ok() ? " fitness=\"" + soda::format_double_plain(e.fitness) + "\"" : std::string();
}

/// The estimate behind a scored creature's fitness (replicas, their mean, sd and
/// median), so that a resumed run resamples and a replay re-estimates it on the
/// same replicas.
std::string estimate_attributes(const Evaluation& e) {
  if (!e.ok() || e.estimate.rollouts <= 0) return {};
  return " replicas=\"" + std::to_string(e.estimate.rollouts) + "\" mean=\"" +
         soda::format_double_plain(e.estimate.mean) + "\" sd=\"" + soda::format_double_plain(e.estimate.sd) +
         "\" median=\"" + soda::format_double_plain(e.estimate.median) + "\"";
}

/// The estimate attributes of a saved creature; none (older files): rollouts 0.
Estimate parse_estimate(const soda::SavedModelElement& m, const std::string& where) {
  Estimate est;
  const std::string* replicas = m.find("replicas");
  if (!replicas) return est;
  const std::optional<long long> n = soda::parse_integer(*replicas);
  if (!n || *n < 1 || *n > 1024) {
    throw soda::InputError(where + ": attribute 'replicas': expected an integer in [1, 1024], got '" + *replicas + "'");
  }
  est.rollouts = static_cast<int>(*n);
  est.mean = parse_number(m.value("mean"), where + ": mean");
  est.sd = parse_number(m.value("sd"), where + ": sd");
  est.median = parse_number(m.value("median"), where + ": median");
  return est;
}

/// `written`: the fitness attribute's value, nullptr if the element has none.
double parse_fitness(const std::string* written, const Evaluation& e, const std::string& where) {
  if (!e.ok()) {
    if (written) throw soda::InputError(where + ": fitness: expected none for a creature that was not scored, got '" +
                                        *written + "'");
    return kWorstFitness;
  }
  if (!written) throw soda::InputError(where + ": fitness: expected a number for a scored creature, got none");
  return parse_number(*written, where + ": fitness");
}

// A generation with no scored creature has no best, mean, median or worst: the
// cell is left empty rather than holding an infinity.
std::string statistic_cell(double v) { return std::isfinite(v) ? soda::format_double_plain(v) : std::string(); }


std::string join(const std::vector<std::string>& v, char sep) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? std::string(1, sep) : "") + v[i];
  return out;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream in(s);
  while (std::getline(in, cur, sep)) {
    if (!cur.empty()) out.push_back(cur);
  }
  return out;
}

/// The <model>...</model> element of a written model, without prolog.
std::string model_element(const soda::ModelDef& creature, const std::string& attributes) {
  const std::string text = soda::write_model_text(creature);
  const std::size_t start = text.find("<model>");
  std::string element = text.substr(start);
  element.replace(0, 7, "<model " + attributes + ">");
  return element;
}


std::vector<std::pair<int, std::string>> read_rows(const fs::path& path) {
  std::vector<std::pair<int, std::string>> rows;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line); // header
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    rows.emplace_back(std::atoi(line.c_str()), line + "\n");
  }
  return rows;
}

} // namespace

std::string generation_file_name(int generation) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "gen_%05d.xml", generation);
  return buf;
}

std::string generation_to_xml(const Generation& g) {
  // A race timeout set by /fitness/race/timeout_factor is part of the generation.
  std::string out = "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n<generation index=\"" +
                    std::to_string(g.index) + "\"" +
                    (g.race_timeout > 0 ? " race_timeout=\"" + std::to_string(g.race_timeout) + "\"" : "") +
                    (g.race_stage > 0 ? " race_stage=\"" + std::to_string(g.race_stage) + "\"" : "") + ">\n";
  for (const Individual& ind : g.individuals) {
    const Evaluation& e = ind.evaluation;
    std::string attrs = "id=\"" + soda::xml_attribute_escaped(ind.id) + "\" parents=\"" + soda::xml_attribute_escaped(join(ind.parents, ' ')) +
                        "\" status=\"" + status_name(e.status) + "\"" + fitness_attribute(e) + estimate_attributes(e) +
                        " distance=\"" +
                        soda::format_double_plain(e.distance) + "\" reason=\"" + soda::xml_attribute_escaped(e.reason) + "\"";
    out += model_element(ind.creature, attrs);
  }
  out += "</generation>\n";
  return out;
}

Generation generation_from_xml(const std::string& text, const std::string& source) {
  const soda::GenerationXml xml(text, source);
  Generation g;
  const std::string index_text = xml.index_text();
  const std::optional<long long> index = soda::parse_integer(index_text);
  if (!index || *index < 0 || *index >= kMaxGenerations) {
    throw soda::InputError(xml.where() + ": <generation> attribute 'index': expected an integer in [0, " +
                           std::to_string(kMaxGenerations - 1) + "], got '" + index_text + "'");
  }
  g.index = static_cast<int>(*index);
  if (const std::string timeout = xml.root_attribute("race_timeout"); !timeout.empty()) {
    const std::optional<long long> t = soda::parse_integer(timeout);
    if (!t || *t < 1 || *t > soda::kMaxRaceTimeout) {
      throw soda::InputError(xml.where() + ": <generation> attribute 'race_timeout': expected an integer in [1, " +
                             std::to_string(soda::kMaxRaceTimeout) + "], got '" + timeout + "'");
    }
    g.race_timeout = static_cast<int>(*t);
  }
  if (const std::string stage = xml.root_attribute("race_stage"); !stage.empty()) {
    constexpr long long kMaxStage = kMaxCurriculumStages - 1;
    const std::optional<long long> s = soda::parse_integer(stage);
    if (!s || *s < 1 || *s > kMaxStage) {
      throw soda::InputError(xml.where() + ": <generation> attribute 'race_stage': expected an integer in [1, " +
                             std::to_string(kMaxStage) + "], got '" + stage + "'");
    }
    g.race_stage = static_cast<int>(*s);
  }
  std::set<std::string> ids;
  xml.for_each_model([&](const soda::SavedModelElement& m) {
    Individual ind;
    ind.id = m.value("id");
    const std::string where = m.where + ": <model id=\"" + ind.id + "\">";
    if (static_cast<int>(g.individuals.size()) >= kMaxPopulation) {
      throw soda::InputError(where + ": expected at most " + std::to_string(kMaxPopulation) +
                             " creatures in a generation (the largest population), got more");
    }
    if (ind.id.empty()) throw soda::InputError(where + ": attribute 'id': expected a creature id, got ''");
    if (!ids.insert(ind.id).second) {
      throw soda::InputError(where + ": attribute 'id': expected an id not used before, got '" + ind.id + "'");
    }
    ind.parents = split(m.value("parents"), ' ');
    ind.evaluation.status = parse_status(m.value("status"), where);
    ind.evaluation.fitness = parse_fitness(m.find("fitness"), ind.evaluation, where);
    ind.evaluation.distance = parse_number(m.value("distance"), where + ": distance");
    ind.evaluation.reason = m.value("reason");
    if (ind.evaluation.ok()) ind.evaluation.estimate = parse_estimate(m, where);
    ind.evaluated = true;
    // Positions in messages from here on are within the model element.
    ind.creature = soda::read_model_text(m.xml, where).def;
    g.individuals.push_back(std::move(ind));
  });
  return g;
}

namespace {

/// The compiler that built this program, by name: __VERSION__ alone is "12.2.0" for
/// g++ and "Debian Clang 14.0.6" for clang (and so em++, the page's engine).
std::string compiler_name() {
#if defined(__EMSCRIPTEN__)
  return std::string("em++ (WebAssembly) ") + __VERSION__;
#elif defined(__clang__)
  return std::string("clang++ ") + __VERSION__;
#else
  return std::string("g++ ") + __VERSION__;
#endif
}

/// `sine`: the sine that made the run (evolve/store/run_sine.hpp); none: not known.
void write_manifest(const fs::path& dir, const RunConfig& config, const std::string& command_line,
                    const std::optional<std::string>& sine) {
  nlohmann::json manifest = {{"program", "sodaevo"},
                             {"version", "0.1.0"},
                             {"compiler", compiler_name()},
                             {"seed", config.seed},
                             {"started", now_iso8601()},
                             {"command", command_line}};
  if (sine) manifest["sine"] = *sine;
  soda::write_file_atomically(dir / "manifest.json", manifest.dump(2) + "\n");
}

/// Copies the seed models into the run folder (seeds/) and returns the config as
/// config.json gives them: relative to the folder, so that a run moved, cloned or
/// shared can still be read, replayed, reported and resumed (config.json's paths
/// resolve against its own folder). Files of one name from different folders get
/// a number.
RunConfig with_seeds_in_folder(const fs::path& dir, const RunConfig& config) {
  RunConfig saved = config;
  if (config.population.seed_models.empty()) return saved;
  std::error_code ec;
  fs::create_directories(dir / "seeds", ec);
  if (ec) throw soda::InputError(dir.string() + ": cannot create the run folder's seeds/: " + ec.message());
  std::set<std::string> taken;
  for (std::size_t i = 0; i < config.population.seed_models.size(); ++i) {
    const fs::path from(config.population.seed_models[i]);
    std::string name = from.filename().string();
    for (int n = 2; taken.count(name); ++n) {
      name = from.stem().string() + "-" + std::to_string(n) + from.extension().string();
    }
    taken.insert(name);
    soda::write_file_atomically(dir / "seeds" / name, soda::read_whole_file(from));
    saved.population.seed_models[i] = "seeds/" + name;
  }
  return saved;
}

} // namespace

RunStore RunStore::create(const fs::path& dir, const RunConfig& config, bool force, const std::string& command_line) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_empty(dir, ec)) {
    if (!force) {
      throw soda::InputError(dir.string() + ": the run folder exists already; use --resume to continue it or --force to replace it");
    }
    for (const char* name : {"config.json", "manifest.json", "generations.csv", "timing.csv", "checkpoint.json"}) {
      fs::remove(dir / name, ec);
    }
    fs::remove_all(dir / "best", ec);
    fs::remove_all(dir / "generations", ec);
    fs::remove_all(dir / "seeds", ec);
  }
  fs::create_directories(dir / "best", ec);
  if (ec) throw soda::InputError(dir.string() + ": cannot create the run folder: " + ec.message());
  fs::create_directories(dir / "generations", ec);
  if (ec) throw soda::InputError(dir.string() + ": cannot create the run folder: " + ec.message());

  soda::write_file_atomically(dir / "config.json", to_json(with_seeds_in_folder(dir, config)).dump(2) + "\n");
  // The run goes on with the config as a resume reads it: the seed models in seeds/.
  RunStore store(dir, read_run_config(dir / "config.json"));
  write_manifest(dir, config, command_line, std::string(soda::kEngineSine));
  store.write_logs();
  return store;
}

RunStore RunStore::open(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw soda::InputError(dir.string() + ": no such run folder");
  // A run killed while writing leaves the temporary file of write_file_atomically
  // ("NAME.tmp-PID") beside the complete old NAME: remove such leftovers.
  for (const fs::path& sub : {dir, dir / "best", dir / "generations"}) {
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(sub, ec)) {
      if (e.is_regular_file(ec) && e.path().filename().string().find(".tmp-") != std::string::npos) {
        fs::remove(e.path(), ec);
      }
    }
  }
  RunStore store(dir, read_run_config(dir / "config.json"));
  // A run killed between writing its config and its manifest has none: write one,
  // saying so, rather than leave the folder without it.
  // Its sine is the checkpoint's, if a checkpoint (not written before the
  // manifest, but a folder may be edited) says which: else none is claimed.
  if (std::error_code ec; !fs::exists(dir / "manifest.json", ec)) {
    std::optional<std::string> sine = std::string(soda::kEngineSine);
    if (fs::exists(dir / "checkpoint.json", ec)) {
      const std::optional<Checkpoint> c = store.read_checkpoint();
      sine = c && !c->sine.empty() ? std::optional<std::string>(c->sine) : std::nullopt;
    }
    write_manifest(dir, store.config_, "(unknown: the run was killed before its manifest was written; resumed)", sine);
  }
  store.generation_rows_ = read_rows(dir / "generations.csv");
  store.timing_rows_ = read_rows(dir / "timing.csv");
  return store;
}

void RunStore::write_logs() const {
  std::string gen = kGenerationsHeader, timing = kTimingHeader;
  for (const auto& [g, row] : generation_rows_) gen += row;
  for (const auto& [g, row] : timing_rows_) timing += row;
  soda::write_file_atomically(dir_ / "generations.csv", gen);
  soda::write_file_atomically(dir_ / "timing.csv", timing);
}

void RunStore::truncate_logs_after(int generation) {
  const auto erased = std::erase_if(generation_rows_, [&](const auto& r) { return r.first > generation; }) +
                      std::erase_if(timing_rows_, [&](const auto& r) { return r.first > generation; });
  if (erased > 0) write_logs(); // a resume after a pause (ask/tell) truncates nothing: no rewrite
}

namespace {

/// The best creature's replicas, their sd and the 95 % prediction interval of one
/// more run (mean +- t * sd * sqrt(1 + 1/n)); empty cells without a best.
std::string best_estimate_cells(const Generation& g, const GenerationStats& s) {
  if (s.best_index < 0) return ",,,";
  const Estimate& e = g.individuals[static_cast<std::size_t>(s.best_index)].evaluation.estimate;
  if (e.rollouts <= 0) return ",,,";
  const double half = prediction_half_width95(e.rollouts, e.sd);
  using soda::format_double_plain;
  return std::to_string(e.rollouts) + "," + format_double_plain(e.sd) + "," + format_double_plain(e.mean - half) +
         "," + format_double_plain(e.mean + half);
}

} // namespace

void RunStore::record_generation(const Generation& g, const GenerationStats& s, double wall_seconds,
                                 double generation_seconds, long long generation_evaluations, bool save_whole,
                                 const std::optional<soda::ModelDef>& best_file) {
  using soda::format_double_plain;
  const std::string best_id = s.best_index >= 0 ? g.individuals[static_cast<std::size_t>(s.best_index)].id : "";
  std::erase_if(generation_rows_, [&](const auto& r) { return r.first >= g.index; });
  std::erase_if(timing_rows_, [&](const auto& r) { return r.first >= g.index; });
  generation_rows_.emplace_back(
      g.index, std::to_string(g.index) + "," + std::to_string(s.evaluations) + "," + statistic_cell(s.best) + "," +
                   statistic_cell(s.mean) + "," + statistic_cell(s.median) + "," + statistic_cell(s.worst) + "," + std::to_string(s.invalid) + "," +
                   std::to_string(s.diverged) + "," + best_id + "," + best_estimate_cells(g, s) + "\n");
  const double rate = generation_seconds > 0 ? static_cast<double>(generation_evaluations) / generation_seconds : 0.0;
  timing_rows_.emplace_back(g.index, std::to_string(g.index) + "," + std::to_string(s.evaluations) + "," +
                                         format_double_plain(wall_seconds) + "," + format_double_plain(rate) + "\n");
  if (save_whole) save_generation(g);
  if (best_file) soda::write_model_file(dir_ / "best" / generation_file_name(g.index), *best_file);
  write_logs();
}

void RunStore::save_generation(const Generation& g) const {
  soda::write_file_atomically(dir_ / "generations" / generation_file_name(g.index), generation_to_xml(g));
}

void RunStore::write_checkpoint(const Checkpoint& c) {
  nlohmann::json j = {{"format", "sodaevo-checkpoint-1"},
                      {"generation", c.generation.index},
                      {"evaluations", c.evaluations},
                      {"wall_seconds", c.wall_seconds},
                      {"sine", std::string(soda::kEngineSine)}, // what scored the population
                      {"population_xml", generation_to_xml(c.generation)}};
  soda::write_file_atomically(dir_ / "checkpoint.json", j.dump() + "\n");
}

std::optional<Checkpoint> RunStore::read_checkpoint() const {
  const fs::path path = dir_ / "checkpoint.json";
  std::error_code ec;
  if (!fs::exists(path, ec)) return std::nullopt;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec && size > kMaxCheckpointBytes) {
    throw soda::InputError(path.string() + ": corrupt checkpoint: expected at most " +
                           std::to_string(kMaxCheckpointBytes >> 20) + " MiB, got " + std::to_string(size >> 20) +
                           " MiB");
  }
  return parse_checkpoint(soda::read_whole_file(path), path.string());
}

Checkpoint parse_checkpoint(const std::string& text, const std::string& source) {
  const std::string prefix = source + ": corrupt checkpoint";
  if (text.size() > kMaxCheckpointBytes) {
    throw soda::InputError(prefix + ": expected at most " + std::to_string(kMaxCheckpointBytes >> 20) +
                           " MiB, got " + std::to_string(text.size() >> 20) + " MiB");
  }
  // Depth and duplicate keys are checked while parsing (nlohmann would keep the
  // last of duplicate keys silently; a checkpoint never has any).
  std::set<std::string> keys;
  std::string problem;
  const nlohmann::json::parser_callback_t callback = [&](int depth, nlohmann::json::parse_event_t event,
                                                         nlohmann::json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    if ((event == Event::object_start || event == Event::array_start) && depth >= kMaxJsonDepth) {
      problem = "expected JSON nested at most " + std::to_string(kMaxJsonDepth) + " levels deep, got deeper";
      throw std::length_error(problem);
    }
    if (event == Event::key && depth == 1 && !keys.insert(parsed.get<std::string>()).second) {
      problem = "/" + parsed.get<std::string>() + ": duplicate key";
      throw std::length_error(problem);
    }
    return true;
  };
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text, callback);
  } catch (const nlohmann::json::parse_error& e) {
    const soda::TextLocation at = soda::locate_offset(text, static_cast<std::ptrdiff_t>(e.byte) - 1);
    throw soda::InputError(source + ":" + std::to_string(at.line) + ":" + std::to_string(at.column) +
                           ": corrupt checkpoint: invalid JSON (truncated or damaged file?): " + e.what());
  } catch (const nlohmann::json::exception& e) {
    throw soda::InputError(prefix + ": invalid JSON: " + e.what());
  } catch (const std::length_error&) {
    throw soda::InputError(prefix + ": " + problem);
  }
  const auto got = [](const nlohmann::json& v) {
    std::string s = v.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    if (s.size() > 80) s = s.substr(0, 80) + "...";
    return s;
  };
  if (!j.is_object()) throw soda::InputError(prefix + ": (top level): expected an object, got " + got(j));
  const auto member = [&](const char* key, const char* expected) -> const nlohmann::json& {
    const auto it = j.find(key);
    if (it == j.end()) {
      throw soda::InputError(prefix + ": /" + key + ": expected " + expected + ", got nothing (missing)");
    }
    return *it;
  };
  // An integral JSON number within [lo, hi]; doubles and out-of-range values are errors
  // (never converted: 1e30 into an int is undefined behaviour).
  const auto integer = [&](const char* key, long long lo, long long hi) {
    const std::string expected = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    const nlohmann::json& v = member(key, expected.c_str());
    long long value = 0;
    bool fits = false;
    if (v.is_number_unsigned()) {
      const auto u = v.get<std::uint64_t>();
      fits = u <= static_cast<std::uint64_t>(hi);
      value = fits ? static_cast<long long>(u) : 0;
    } else if (v.is_number_integer()) {
      value = v.get<long long>();
      fits = true;
    }
    if (!fits || value < lo || value > hi) {
      throw soda::InputError(prefix + ": /" + key + ": expected " + expected + ", got " + got(v));
    }
    return value;
  };
  const nlohmann::json& format = member("format", "\"sodaevo-checkpoint-1\"");
  if (format != "sodaevo-checkpoint-1") {
    throw soda::InputError(prefix + ": /format: expected \"sodaevo-checkpoint-1\", got " + got(format));
  }
  for (const auto& [key, value] : j.items()) {
    if (key != "format" && key != "generation" && key != "evaluations" && key != "wall_seconds" && key != "sine" &&
        key != "population_xml") {
      throw soda::InputError(prefix + ": /" + key +
                             ": unknown key (expected format, generation, evaluations, wall_seconds, sine, "
                             "population_xml)");
    }
  }
  Checkpoint c;
  const long long generation = integer("generation", 0, kMaxGenerations - 1);
  c.evaluations = integer("evaluations", 0, 9007199254740992LL);
  const nlohmann::json& wall = member("wall_seconds", "a number >= 0");
  if (!wall.is_number() || !(wall.get<double>() >= 0) || !std::isfinite(wall.get<double>())) {
    throw soda::InputError(prefix + ": /wall_seconds: expected a number >= 0, got " + got(wall));
  }
  c.wall_seconds = wall.get<double>();
  // The sine that scored the population; none: a checkpoint from before sines were
  // recorded (glibc's, evolve/store/run_sine.hpp).
  if (const auto sine = j.find("sine"); sine != j.end()) {
    if (!sine->is_string() || sine->get_ref<const std::string&>().empty()) {
      throw soda::InputError(prefix + ": /sine: expected a sine's name (e.g. \"" + std::string(soda::kEngineSine) +
                             "\"), got " + got(*sine));
    }
    c.sine = sine->get<std::string>();
  }
  const nlohmann::json& xml = member("population_xml", "a string holding a <generation>");
  if (!xml.is_string()) {
    throw soda::InputError(prefix + ": /population_xml: expected a string holding a <generation>, got " + got(xml));
  }
  try {
    c.generation = generation_from_xml(xml.get_ref<const std::string&>(), source + " /population_xml");
  } catch (const soda::InputError& e) {
    throw soda::InputError(prefix + ": " + e.what());
  }
  if (c.generation.index != generation) {
    throw soda::InputError(prefix + ": /generation: expected the index of the saved population (" +
                           std::to_string(c.generation.index) + "), got " + std::to_string(generation));
  }
  if (c.generation.individuals.empty()) {
    throw soda::InputError(prefix + ": /population_xml: expected at least one creature, got none");
  }
  return c;
}

std::string now_iso8601() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

} // namespace sodaevo
