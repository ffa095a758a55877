#include "archive_store.hpp"

#include <cmath>
#include <cstdio>

#include "formats/atomic_file.hpp"
#include "core/input_error.hpp"
#include "core/sine_identity.hpp"
#include "formats/model_file.hpp"
#include "core/number_text.hpp"
#include "evolve/store/run_store.hpp"

namespace sodaevo {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kQdHeader =
    "iteration,evaluations,filled,coverage_percent,qd_score,normalized_qd_score,best,mean_fitness,entered,replaced,"
    "rollouts,resampled,evicted\n";
constexpr const char* kCheckpointFormat = "sodaevo-map-elites-checkpoint-2";

json estimate_to_json(const RunningEstimate& e) { return {{"n", e.n}, {"mean", e.mean}, {"m2", e.m2}}; }

RunningEstimate estimate_from_json(const json& j) {
  RunningEstimate e;
  e.n = j.at("n").get<long long>();
  e.mean = j.at("mean").get<double>();
  e.m2 = j.at("m2").get<double>();
  if (e.n < 1 || !std::isfinite(e.mean) || !(e.m2 >= 0.0)) throw std::invalid_argument("bad estimate");
  return e;
}

/// The Evaluation an elite is exported with: its mean fitness, its exact run's distance.
Evaluation elite_evaluation(const ArchiveEntry& e, const RunConfig& config) {
  Evaluation ev;
  ev.status = EvaluationStatus::Ok;
  ev.fitness = e.fitness.mean;
  ev.distance = e.distance;
  ev.px_per_frame = e.distance / static_cast<double>(config.fitness.frames);
  return ev;
}

} // namespace

json metrics_to_json(const QdMetrics& m) {
  return {{"cells", m.cells},
          {"filled", m.filled},
          {"coverage", m.coverage},
          {"qd_score", m.qd_score},
          {"normalized_qd_score", m.normalized_qd_score},
          {"best", m.best},
          {"mean_fitness", m.mean}};
}

std::string elite_file(const std::string& id) { return "elites/" + id + ".xml"; }

json archive_to_json(const GridArchive& archive, const MapElitesConfig& me, int iteration) {
  json axes = json::array();
  for (const GridAxis& a : archive.axes()) {
    axes.push_back({{"descriptor", descriptor_name(a.descriptor)}, {"bins", a.bins}, {"range", {a.lo, a.hi}}});
  }
  const QdMetrics m = archive.metrics(me.qd_offset);
  json cells = json::array();
  for (const auto& [cell, e] : archive.elites()) {
    json descriptors = json::array();
    for (double d : e.descriptors) descriptors.push_back(d);
    cells.push_back({{"cell", cell},
                     {"bins", archive.coordinates(cell)},
                     {"id", e.id},
                     {"fitness", {{"n", e.fitness.n}, {"mean", e.fitness.mean}, {"sd", e.fitness.sd()}}},
                     {"distance", e.distance},
                     {"descriptors", descriptors},
                     {"iteration", e.iteration},
                     {"file", elite_file(e.id)}});
  }
  return {{"format", "sodaevo-archive-1"},
          {"iteration", iteration},
          {"axes", axes},
          {"qd_offset", me.qd_offset},
          {"metrics", metrics_to_json(m)},
          {"cells", cells}};
}

void ArchiveStore::record_iteration(int iteration, const ArchiveCheckpoint& totals, const QdMetrics& m,
                                    const InsertionCounts& counts) {
  const std::string row = std::to_string(iteration) + "," + std::to_string(totals.evaluations) + "," +
                          std::to_string(m.filled) + "," + soda::format_double_plain(100.0 * m.coverage) + "," +
                          soda::format_double_plain(m.qd_score) + "," +
                          soda::format_double_plain(m.normalized_qd_score) + "," +
                          soda::format_double_plain(m.best) + "," + soda::format_double_plain(m.mean) + "," +
                          std::to_string(counts.entered) + "," + std::to_string(counts.replaced) + "," +
                          std::to_string(totals.rollouts) + "," + std::to_string(counts.resampled) + "," +
                          std::to_string(counts.evicted) + "\n";
  rows_.emplace_back(iteration, row);
  std::string text = kQdHeader;
  for (const auto& [i, r] : rows_) text += r;
  soda::write_file_atomically(dir_ / "qd.csv", text);
}

void ArchiveStore::truncate_after(int iteration) {
  rows_.clear();
  std::error_code ec;
  if (!fs::exists(dir_ / "qd.csv", ec)) return;
  const std::string text = soda::read_whole_file(dir_ / "qd.csv");
  std::size_t start = text.find('\n');
  std::string kept = kQdHeader;
  while (start != std::string::npos && start + 1 < text.size()) {
    const std::size_t end = text.find('\n', start + 1);
    const std::string row = text.substr(start + 1, end == std::string::npos ? std::string::npos : end - start);
    const int i = std::atoi(row.c_str());
    if (i <= iteration && !row.empty()) {
      rows_.emplace_back(i, row.back() == '\n' ? row : row + "\n");
      kept += rows_.back().second;
    }
    start = end;
  }
  if (kept != text) soda::write_file_atomically(dir_ / "qd.csv", kept); // a resume after a pause truncates nothing
}

void ArchiveStore::write_snapshot(const GridArchive& archive, const MapElitesConfig& me, int iteration) const {
  char name[40];
  std::snprintf(name, sizeof name, "archive_%05d.json", iteration);
  fs::create_directories(dir_ / "snapshots");
  soda::write_file_atomically(dir_ / "snapshots" / name, archive_to_json(archive, me, iteration).dump(1) + "\n");
}

void ArchiveStore::write_archive(const GridArchive& archive, const Problem& exporter, const RunConfig& config,
                                 const MapElitesConfig& me, int iteration) const {
  const fs::path elites = dir_ / "elites";
  fs::remove_all(elites);
  fs::create_directories(elites);
  for (const auto& [cell, e] : archive.elites()) {
    const soda::ModelDef prepared = exporter.export_form(e.creature, e.id, elite_evaluation(e, config));
    soda::write_model_file(dir_ / elite_file(e.id), prepared);
  }
  json j = archive_to_json(archive, me, iteration);
  j["sine"] = std::string(soda::kEngineSine); // what scored the elites (evolve/store/run_sine.hpp)
  soda::write_file_atomically(dir_ / "archive.json", j.dump(1) + "\n");
}

void ArchiveStore::write_checkpoint(const GridArchive& archive, const ArchiveCheckpoint& c) const {
  Generation elites; // the genomes, in cell order, in the run store's exact XML
  json cells = json::array();
  for (const auto& [cell, e] : archive.elites()) {
    Individual ind;
    ind.id = e.id;
    ind.parents = e.parents;
    ind.creature = e.creature;
    elites.individuals.push_back(std::move(ind));
    cells.push_back({{"cell", cell},
                     {"iteration", e.iteration},
                     {"distance", e.distance},
                     {"fitness", estimate_to_json(e.fitness)},
                     {"descriptors", e.descriptors}});
  }
  const json j = {{"format", kCheckpointFormat},     {"iteration", c.iteration},
                  {"evaluations", c.evaluations},    {"rollouts", c.rollouts},
                  {"wall_seconds", c.wall_seconds},      {"sine", std::string(soda::kEngineSine)},
                  {"cells", cells},                  {"elites_xml", generation_to_xml(elites)}};
  soda::write_file_atomically(dir_ / "archive_checkpoint.json", j.dump() + "\n");
}

std::optional<ArchiveCheckpoint> ArchiveStore::read_checkpoint(GridArchive& archive) const {
  const fs::path path = dir_ / "archive_checkpoint.json";
  std::error_code ec;
  if (!fs::exists(path, ec)) return std::nullopt;
  const std::string where = path.string() + ": corrupt checkpoint: ";
  try {
    const json j = json::parse(soda::read_whole_file(path));
    if (j.at("format") != kCheckpointFormat) throw soda::InputError(where + "/format: expected \"" +
                                                                    std::string(kCheckpointFormat) + "\"");
    ArchiveCheckpoint c;
    c.iteration = j.at("iteration").get<int>();
    c.evaluations = j.at("evaluations").get<long long>();
    c.rollouts = j.at("rollouts").get<long long>();
    c.wall_seconds = j.at("wall_seconds").get<double>();
    const Generation elites = generation_from_xml(j.at("elites_xml").get<std::string>(), path.string());
    const json& cells = j.at("cells");
    if (!cells.is_array() || cells.size() != elites.individuals.size()) {
      throw soda::InputError(where + "/cells: expected one entry per creature of /elites_xml");
    }
    for (std::size_t k = 0; k < cells.size(); ++k) {
      const json& cj = cells[k];
      ArchiveEntry e;
      e.id = elites.individuals[k].id;
      e.parents = elites.individuals[k].parents;
      e.creature = elites.individuals[k].creature;
      e.iteration = cj.at("iteration").get<long long>();
      e.distance = cj.at("distance").get<double>();
      e.fitness = estimate_from_json(cj.at("fitness"));
      for (const json& d : cj.at("descriptors")) e.descriptors.push_back(d.get<double>());
      const auto cell = cj.at("cell").get<std::size_t>();
      if (cell >= archive.cell_count() || e.descriptors.size() != archive.axes().size()) {
        throw soda::InputError(where + "/cells/" + std::to_string(k) + ": expected a cell of the run's grid");
      }
      archive.place(cell, std::move(e));
    }
    return c;
  } catch (const soda::InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw soda::InputError(where + e.what());
  }
}

} // namespace sodaevo
