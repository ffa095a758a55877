#include "evolve/store/run_sine.hpp"

#include <chrono>
#include <ctime>

#include <nlohmann/json.hpp>

#include "core/input_error.hpp"
#include "core/sine_identity.hpp"
#include "evolve/store/run_store.hpp"
#include "evolve/config/strict_json.hpp"
#include "formats/atomic_file.hpp"

namespace sodaevo {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json read_json_object(const fs::path& path) {
  json j;
  try {
    j = json::parse(soda::read_whole_file(path));
  } catch (const json::exception& e) {
    throw soda::InputError(path.string() + ": not valid JSON: " + e.what());
  }
  if (!j.is_object()) throw soda::InputError(path.string() + ": expected a JSON object, got " + show_json(j));
  return j;
}

/// `key` of `j` as a sine name; nullopt if absent.
std::optional<std::string> sine_member(const json& j, const char* key, const std::string& where) {
  const auto it = j.find(key);
  if (it == j.end()) return std::nullopt;
  if (!it->is_string() || it->get_ref<const std::string&>().empty()) {
    throw soda::InputError(where + ": /" + key + ": expected a sine's name (e.g. \"" + std::string(soda::kEngineSine) +
                           "\"), got " + show_json(*it));
  }
  return it->get<std::string>();
}


} // namespace

std::string RunSine::of_generation(int g) const {
  if (changes.empty()) return sine;
  std::string s = changes.front().from;
  for (const SineChange& c : changes) {
    if (c.generation <= g) s = c.to;
  }
  return s;
}

bool RunSine::all_engine() const {
  return sine == soda::kEngineSine && (changes.empty() || changes.front().from == soda::kEngineSine);
}

std::string RunSine::summary() const {
  if (changes.empty()) {
    return sine_description(sine) + (recorded ? "" : "; not recorded: runs before " + std::string(soda::kGlibcSineUntil) +
                                                         " record no sine");
  }
  // One part per range of generations, "a-b" or "from a" for the last.
  std::string out;
  const auto part = [&](const std::string& s, int first, int end) { // end: one past, -1 for open
    if (end >= 0 && end <= first) return; // a change at the generation of the one before
    out += (out.empty() ? "" : ", then ") + sine_description(s) +
           (end < 0 ? " from generation " + std::to_string(first)
                    : " for generations " + std::to_string(first) + "-" + std::to_string(end - 1));
  };
  part(changes.front().from, 0, changes.front().generation);
  for (std::size_t i = 0; i < changes.size(); ++i) {
    part(changes[i].to, changes[i].generation, i + 1 == changes.size() ? -1 : changes[i + 1].generation);
  }
  return out + " (evolve --resume-other-sine)";
}

RunSine read_run_sine(const fs::path& run_dir) {
  RunSine r;
  r.sine = soda::kGlibcSine;
  const fs::path path = run_dir / "manifest.json";
  std::error_code ec;
  if (!fs::exists(path, ec)) return r;
  const json j = read_json_object(path);
  const std::string where = path.string();
  if (std::optional<std::string> s = sine_member(j, "sine", where)) {
    r.recorded = true;
    r.sine = *s;
  }
  const auto changes = j.find("sine_changes");
  if (changes == j.end()) return r;
  if (!changes->is_array()) {
    throw soda::InputError(where + ": /sine_changes: expected an array of {generation, from, to}, got " +
                           show_json(*changes));
  }
  int previous = 0;
  for (std::size_t i = 0; i < changes->size(); ++i) {
    const json& c = (*changes)[i];
    const std::string at = where + ": /sine_changes/" + std::to_string(i);
    if (!c.is_object() || !c.contains("generation") || !c["generation"].is_number_integer() ||
        c["generation"].get<long long>() < previous || c["generation"].get<long long>() > 100000000) {
      throw soda::InputError(at + ": expected {generation, from, to} with generations in increasing order, got " +
                             show_json(c));
    }
    SineChange change;
    change.generation = c["generation"].get<int>();
    const std::optional<std::string> from = sine_member(c, "from", at);
    const std::optional<std::string> to = sine_member(c, "to", at);
    if (!from || !to) throw soda::InputError(at + ": expected both \"from\" and \"to\", got " + show_json(c));
    change.from = *from;
    change.to = *to;
    previous = change.generation;
    r.changes.push_back(std::move(change));
  }
  if (!r.changes.empty() && r.changes.back().to != r.sine) {
    throw soda::InputError(where + ": /sine: expected the last change's \"to\" (\"" + r.changes.back().to + "\"), got " +
                           (r.recorded ? "\"" + r.sine + "\"" : std::string("nothing")));
  }
  return r;
}

std::string sine_description(std::string_view sine) {
  if (sine == soda::kEngineSine) return "Java's Math.sin (" + std::string(sine) + ")";
  if (sine == soda::kGlibcSine) {
    return "glibc's sin (" + std::string(sine) + ", the engine before " + std::string(soda::kGlibcSineUntil) + ")";
  }
  return "a sine this sodaevo does not know ('" + std::string(sine) + "')";
}

std::string other_sine_note(const std::string& subject_made, std::string_view made_with, bool recorded) {
  if (made_with == soda::kEngineSine) return {};
  const bool known = made_with == soda::kGlibcSine;
  // Not recorded: glibc's, by the rule of run_sine.hpp.
  const std::string made = recorded ? sine_description(made_with)
                                    : "glibc's sin (" + std::string(soda::kGlibcSine) +
                                          ": its manifest.json names no sine, as runs made before " +
                                          std::string(soda::kGlibcSineUntil) + " do not)";
  return subject_made + " with " + made + "; this engine computes " + sine_description(soda::kEngineSine) +
         ", so trajectories part after the first muscle sine that differs in its last bit: re-simulated fitnesses " +
         (known ? "will differ" : "will differ unless the two sines agree in every bit") + " from the logged ones";
}

std::string run_sine_note(const RunSine& run) {
  if (run.all_engine()) return {};
  if (run.changes.empty() || run.sine != soda::kEngineSine) return other_sine_note("this run was made", run.sine, run.recorded);
  const int from = run.changes.back().generation; // every generation from here on is the engine's
  const std::string which = from == 1 ? "generation 0 of this run was made" : "generations 0-" + std::to_string(from - 1) + " of this run were made";
  return other_sine_note(which, run.changes.front().from, true) +
         " (generation " + std::to_string(from) + " on was made with this engine's sine: evolve --resume-other-sine)";
}

std::optional<ResumePoint> resume_point(const fs::path& run_dir, bool map_elites) {
  const fs::path path = run_dir / (map_elites ? "archive_checkpoint.json" : "checkpoint.json");
  std::error_code ec;
  if (!fs::exists(path, ec)) return std::nullopt;
  // Only the two keys this needs; the resume itself reads the checkpoint strictly.
  const json j = read_json_object(path);
  const char* index_key = map_elites ? "iteration" : "generation";
  const auto index = j.find(index_key);
  if (index == j.end() || !index->is_number_integer() || index->get<long long>() < 0 ||
      index->get<long long>() > 100000000) {
    throw soda::InputError(path.string() + ": corrupt checkpoint: /" + index_key + ": expected an integer >= 0, got " +
                           (index == j.end() ? std::string("nothing") : show_json(*index)));
  }
  ResumePoint p;
  p.generation = index->get<int>();
  const std::optional<std::string> own = sine_member(j, "sine", path.string());
  p.sine = own ? *own : std::string(soda::kGlibcSine);
  p.recorded = own.has_value();
  p.file = path.string();
  if (p.sine != soda::kEngineSine) return p;
  // The checkpoint is this engine's: the manifest must agree about its generation.
  const RunSine run = read_run_sine(run_dir);
  const std::string manifest = run.of_generation(p.generation);
  if (manifest != soda::kEngineSine) {
    p.sine = manifest;
    p.recorded = run.recorded;
    p.file = (run_dir / "manifest.json").string();
  }
  return p;
}

void record_sine_change(const fs::path& run_dir, int generation, const std::string& from) {
  const fs::path path = run_dir / "manifest.json";
  json j = read_json_object(path);
  json& changes = j["sine_changes"];
  if (!changes.is_array()) changes = json::array();
  const bool repeated = !changes.empty() && changes.back().value("generation", -1) == generation &&
                        changes.back().value("to", std::string()) == soda::kEngineSine;
  if (!repeated) {
    changes.push_back({{"generation", generation},
                       {"from", from},
                       {"to", std::string(soda::kEngineSine)},
                       {"resumed", now_iso8601()}});
  }
  j["sine"] = std::string(soda::kEngineSine);
  soda::write_file_atomically(path, j.dump(2) + "\n");
}

} // namespace sodaevo
