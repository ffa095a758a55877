#include "app/start_here.hpp"

#include "app/designer_page.hpp"

namespace sodaevo::app {

std::string start_here_text(const std::string& program) {
  const std::string p = program.empty() ? std::string("sodaevo") : program;
  // Without the WebAssembly engine `designer` refuses; say at once how to get it.
  const std::string designer_note = designer_available()
                                        ? ""
                                        : "      (This build has no WebAssembly engine yet: `./build.sh designer` builds it\n"
                                          "      and writes the page.)\n";
  return "sodaevo evolves SodaConstructor walkers on an exact re-implementation of the\n"
         "SodaConstructor mass-spring engine. Start here (in the project folder):\n"
         "\n"
         "  " + p + " evolve configs/default.json\n"
         "      Evolve walkers from the Dainty Walker and random creatures (about a minute\n"
         "      on 2 cores). The run folder, results/default-<time>/, gets report.html:\n"
         "      open it in a browser to watch the champions walk.\n"
         "\n"
         "  " + p + " designer models/dainty_walker.xml -o designer.html\n"
         "      A page to watch, build and tune a creature: open designer.html in a browser.\n"
         "      Any creature file works, e.g. a run's best/gen_00199.xml.\n" +
         designer_note +
         "\n"
         "  " + p + " simulate models/dainty_walker.xml --frames 10000\n"
         "      Run a bundled creature (models/) and print how far it walked.\n"
         "\n"
         "Every command: " + p + " --help    One command's options: " + p + " COMMAND --help\n";
}

} // namespace sodaevo::app
