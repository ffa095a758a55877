// sodaevo.race: Sodarace races as `sodaevo race --json` runs them, through the
// same library calls (evolve/runs/race_entries.hpp); contenders are files (models or
// race files) or sodaevo.Model objects. Returns the parsed JSON of the command.
// Ctrl-C stops a race (python/interruptible.hpp).
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "core/input_error.hpp"
#include "evolve/runs/race_entries.hpp"
#include "formats/race_file.hpp"
#include "python/arguments.hpp"
#include "python/bindings.hpp"
#include "python/interruptible.hpp"

namespace sodaevo::python {

namespace {

py::object race(const py::object& race_file, const py::sequence& contenders, const py::object& replicas_arg,
                const py::object& jitter_arg, const py::object& timeout_arg, const py::object& threads_arg) {
  const py::object fspath = py::module_::import("os").attr("fspath");
  const std::string race_path = fspath(race_file).cast<std::string>();
  const int replicas = static_cast<int>(integer_in(replicas_arg, "replicas", 0, 4096));
  if (replicas == 1) throw soda::InputError("replicas: expected 0 or an integer in [2, 4096], got 1");
  const double jitter = number_in(jitter_arg, "jitter", 0.0, 1.0);
  const int threads = static_cast<int>(integer_in(threads_arg, "threads", 0, kMaxThreads));
  const soda::RaceDef race_def = soda::read_race_file(race_path);
  int timeout = race_def.timeout;
  if (!timeout_arg.is_none()) timeout = static_cast<int>(integer_in(timeout_arg, "timeout", 1, soda::kMaxRaceTimeout));
  // Files are read as the command reads them; models are entries as they are,
  // named "<model k>" (or by their name).
  std::vector<std::string> warnings;
  std::vector<RaceEntry> entries;
  std::vector<std::string> files;
  for (std::size_t k = 0; k < contenders.size(); ++k) {
    const py::object c = contenders[k];
    if (py::isinstance<soda::ModelDef>(c)) {
      if (!files.empty()) {
        for (RaceEntry& e : load_race_entries(race_path, race_def, files, warnings)) entries.push_back(std::move(e));
        files.clear();
      }
      entries.push_back(race_entry("<model " + std::to_string(k + 1) + ">", model_of(c)));
    } else {
      files.push_back(fspath(c).cast<std::string>());
    }
  }
  if (!files.empty() || contenders.size() == 0) {
    for (RaceEntry& e : load_race_entries(race_path, race_def, files, warnings)) entries.push_back(std::move(e));
  }
  warn_all(warnings);
  warnings.clear();
  RaceLanes lanes;
  try {
    lanes = build_race_lanes(race_def, entries, false, warnings);
  } catch (...) {
    warn_all(warnings);
    throw;
  }
  warn_all(warnings);
  run_interruptibly([&] {
    race_entries_together(lanes, timeout, entries);
    for (std::size_t k = 0; k < entries.size() && replicas > 0; ++k) {
      if (!entries[k].no_result.empty()) continue;
      race_entry_replicas(entries[k], lanes.lanes[k], lanes.models[k], timeout, replicas, jitter, threads);
    }
    return true;
  });
  assign_places(entries);
  const std::string text = race_results_json(race_path, timeout, entries, replicas, jitter).dump();
  return py::module_::import("json").attr("loads")(text);
}

} // namespace

void bind_race(py::module_& m) {
  m.def("race", &race, py::arg("race_file"), py::arg("contenders") = py::list(), py::kw_only(),
        py::arg("replicas") = 0, py::arg("jitter") = 0.002, py::arg("timeout") = py::none(), py::arg("threads") = 0);
}

} // namespace sodaevo::python
