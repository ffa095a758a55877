// sodaevo.race: Sodarace races as `sodaevo race --json` runs them, through the
// same library calls (evolve/race_entries.hpp); contenders are files (models or
// race files) or sodaevo.Model objects. Returns the parsed JSON of the command.
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "core/input_error.hpp"
#include "evolve/race_entries.hpp"
#include "formats/race_file.hpp"
#include "python/bindings.hpp"

namespace sodaevo::python {

namespace {

py::object race(const py::object& race_file, const py::sequence& contenders, int replicas, double jitter,
                const py::object& timeout_arg, int threads) {
  const py::object fspath = py::module_::import("os").attr("fspath");
  const std::string race_path = fspath(race_file).cast<std::string>();
  if (replicas != 0 && (replicas < 2 || replicas > 4096)) {
    throw soda::InputError("replicas: expected 0 or an integer in [2, 4096], got " + std::to_string(replicas));
  }
  if (!(jitter >= 0.0 && jitter <= 1.0)) throw soda::InputError("jitter: expected a number in [0, 1]");
  const soda::RaceDef race_def = soda::read_race_file(race_path);
  int timeout = race_def.timeout;
  if (!timeout_arg.is_none()) {
    timeout = timeout_arg.cast<int>();
    if (timeout < 1 || timeout > soda::kMaxRaceTimeout) {
      throw soda::InputError("timeout: expected an integer in [1, " + std::to_string(soda::kMaxRaceTimeout) +
                             "], got " + std::to_string(timeout));
    }
  }
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
  {
    py::gil_scoped_release free_python;
    race_entries_together(lanes, timeout, entries);
    for (std::size_t k = 0; k < entries.size() && replicas > 0; ++k) {
      if (!entries[k].no_result.empty()) continue;
      race_entry_replicas(entries[k], lanes.lanes[k], lanes.models[k], timeout, replicas, jitter, threads);
    }
  }
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
