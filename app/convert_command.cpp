#include <iostream>
#include <memory>
#include <string>

#include "app/commands.hpp"
#include "core/model.hpp"
#include "formats/model_file.hpp"

namespace sodaevo::app {

namespace {

struct ConvertOptions {
  std::string input;
  std::string output;
};

void run_convert(const ConvertOptions& opt) {
  soda::LoadedModel loaded = soda::read_model_file(opt.input);
  for (const std::string& w : loaded.warnings) std::cerr << "sodaevo: warning: " << w << '\n';
  (void)soda::build_model(loaded.def); // refuse to write a model the engine would reject
  soda::write_model_file(opt.output, loaded.def);
  std::cerr << "wrote " << opt.output << " (canonical SodaConstructor v1 XML)\n";
}

} // namespace

void add_convert_command(CLI::App& app) {
  auto opt = std::make_shared<ConvertOptions>();
  CLI::App* cmd = app.add_subcommand(
      "convert",
      "Convert a SodaConstructor model (v1 <model> or v2 object graph) to canonical v1 XML,\n"
      "the form the original SodaConstructor writes (fixed nodes first, links grouped as\n"
      "springs, muscles, fixed bars; numbers shortest round-trip).");
  cmd->add_option("input", opt->input, "Model to read (.xml, v1 or v2)")->required()->check(non_empty_path())->check(CLI::ExistingFile);
  cmd->add_option("output", opt->output, "Where to write the v1 XML")->required();
  cmd->callback([opt] { run_convert(*opt); });
}

} // namespace sodaevo::app
