#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "core/input_error.hpp"
#include "core/number_text.hpp"
#include "evolve/run_config.hpp"
#include "evolve/run_reader.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"
#include "evolve/run_roles.hpp"

namespace sodaevo::app {

namespace {

struct ExportOptions {
  std::string run;
  int best = 5;
  std::string out;
  bool archive = false;
};

/// Every elite of a MAP-Elites run's archive, as the run wrote it to RUN/elites/
/// (prepared as evaluated), named by cell, with the archive's index beside them.
void export_archive(const std::filesystem::path& run, const std::filesystem::path& out) {
  const std::filesystem::path index = run / "archive.json";
  if (!std::filesystem::exists(index)) {
    throw soda::InputError(index.string() + ": missing: --archive needs a MAP-Elites run folder");
  }
  nlohmann::json archive;
  try {
    archive = nlohmann::json::parse(soda::read_whole_file(index));
    std::printf("cell    id            fitness (px)   file\n");
    for (const nlohmann::json& cell : archive.at("cells")) {
      const std::string id = cell.at("id").get<std::string>();
      const std::filesystem::path file = out / ("cell" + std::to_string(cell.at("cell").get<long long>()) + "_" + id + ".xml");
      soda::write_model_file(file, soda::read_model_file(run / cell.at("file").get<std::string>()).def);
      std::printf("%6lld  %-12s  %12.3f   %s\n", cell.at("cell").get<long long>(), id.c_str(),
                  cell.at("fitness").at("mean").get<double>(), file.string().c_str());
    }
  } catch (const nlohmann::json::exception& e) {
    throw soda::InputError(index.string() + ": not a readable archive: " + e.what());
  }
  soda::write_file_atomically(out / "archive.json", archive.dump(1) + "\n");
}

void run_export(const ExportOptions& opt) {
  const std::filesystem::path run(opt.run);
  const RunConfig config = read_run_config(run / "config.json");
  const std::unique_ptr<Problem> problem = roles_of(config).problem;
  std::error_code ec;
  std::filesystem::create_directories(opt.out, ec);
  if (ec) throw soda::InputError(opt.out + ": cannot create the folder: " + ec.message());
  if (opt.archive) return export_archive(run, opt.out);
  const std::vector<Individual> best = best_individuals(run, opt.best);
  std::printf("rank  id            fitness (px)   px/frame   file\n");
  int rank = 0;
  for (const Individual& ind : best) {
    ++rank;
    const soda::ModelDef prepared = problem->export_form(ind.creature, ind.id, ind.evaluation);
    char name[64];
    std::snprintf(name, sizeof name, "rank%02d_%s.xml", rank, ind.id.c_str());
    const std::filesystem::path file = std::filesystem::path(opt.out) / name;
    soda::write_model_file(file, prepared);
    std::printf("%4d  %-12s  %12.3f   %8.4f   %s\n", rank, ind.id.c_str(), ind.evaluation.fitness,
                ind.evaluation.distance / static_cast<double>(config.fitness.frames), file.string().c_str());
  }
}

} // namespace

void add_export_command(CLI::App& app) {
  auto opt = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export",
      "Write the best creatures of a run as SodaConstructor v1 XML, prepared exactly as they\n"
      "were evaluated (world, Sodarace scaling, wide container, wave forward, autoreverse off),\n"
      "so SodaConstructor and `sodaevo simulate` run them the same way.");
  cmd->add_option("run", opt->run, "Run folder")->required()->check(non_empty_path())->check(CLI::ExistingDirectory);
  cmd->add_option("--best", opt->best, "How many distinct creatures")->default_val(5)->check(CLI::Range(1, 100000));
  cmd->add_option("--out", opt->out, "Output folder")->required();
  cmd->add_flag("--archive", opt->archive,
                "A MAP-Elites run: every elite of its archive (DIR/cell<N>_<id>.xml) and DIR/archive.json");
  cmd->callback([opt] { run_export(*opt); });
}

} // namespace sodaevo::app
