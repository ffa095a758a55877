// sodaevo designer: writes the designer page (app/designer_page.hpp).
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.hpp"
#include "app/designer_page.hpp"
#include "formats/atomic_file.hpp"
#include "core/input_error.hpp"
#include "formats/model_file.hpp"

namespace sodaevo::app {

namespace {

struct DesignerOptions {
  std::string out = "designer.html";
  std::string model;
};

void run_designer(const DesignerOptions& opt) {
  if (!designer_available()) throw soda::InputError(designer_unavailable_reason());
  std::string xml;
  std::string name;
  if (!opt.model.empty()) {
    soda::read_model_file(opt.model); // refused here with the usual message, not later in the page
    xml = soda::read_whole_file(opt.model);
    name = std::filesystem::path(opt.model).filename().string();
  }
  soda::write_file_atomically(opt.out, designer_page(xml, name));
  std::cout << "wrote " << opt.out << ": open it in a browser (it needs no network)"
            << (name.empty() ? "" : "; it starts with " + name) << "\n";
}

} // namespace

void add_designer_command(CLI::App& app) {
  auto opt = std::make_shared<DesignerOptions>();
  CLI::App* cmd = app.add_subcommand(
      "designer",
      "Write the creature designer: one self-contained page (no network, opens from a file) running\n"
      "the exact engine in WebAssembly. Construct, simulate and delete modes; the wave bar (drag a\n"
      "muscle to set its phase and amplitude); sliders for the world; open and save SodaConstructor\n"
      "XML; share a creature by URL; distance, px/frame and the replica spread; \"Evolve from this\"\n"
      "downloads a run config seeded with the design. Evolve mode runs `sodaevo evolve` in the page\n"
      "(Web Workers, one per core): the same run as the command line for the same config, with a\n"
      "live chart, the champion, the best few, a MAP-Elites heat map and the run folder to download.");
  cmd->add_option("model", opt->model, "Model to start with (SodaConstructor XML, v1 or v2); default: an empty design")
      ->check(non_empty_path());
  cmd->add_option("-o,--out", opt->out, "Output page")->default_val("designer.html");
  cmd->callback([opt] { run_designer(*opt); });
}

} // namespace sodaevo::app
