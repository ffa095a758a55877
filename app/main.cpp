// sodaevo: evolutionary creature designer on an exact SodaConstructor engine.
#include <cstdio>
#include <exception>
#include <iostream>

#include <CLI/CLI.hpp>

#include "app/commands.hpp"
#include "core/input_error.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "sodaevo: evolve SodaConstructor walkers on an exact re-implementation of the\n"
      "SodaConstructor mass-spring engine, and simulate or convert SodaConstructor models.\n"
      "Models are SodaConstructor XML: v1 (<model>) or v2 (SodaConstructor 2 object graph)."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "sodaevo 0.1.0");
  sodaevo::app::add_simulate_command(app);
  sodaevo::app::add_convert_command(app);
  sodaevo::app::add_evolve_command(app);
  sodaevo::app::add_export_command(app);
  sodaevo::app::add_replay_command(app);
  sodaevo::app::add_bench_command(app);
  sodaevo::app::add_render_command(app);
  sodaevo::app::add_report_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const soda::InputError& e) {
    std::cerr << "sodaevo: error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "sodaevo: error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
