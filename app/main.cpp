// sodaevo: evolutionary creature designer on an exact SodaConstructor engine.
#include <cstdio>
#include <exception>
#include <iostream>
#include <memory>

#include <CLI/CLI.hpp>

#include "app/commands.hpp"
#include "core/input_error.hpp"
#include "evolve/evaluators/mpi_launch.hpp"
#include "app/mpi_context.hpp"
#include "app/start_here.hpp"
#if SODAEVO_HAS_MPI
#include "evolve/mpi/mpi_session.hpp"
#include "evolve/mpi/mpi_worker.hpp"
#endif

int main(int argc, char** argv) {
#if SODAEVO_HAS_MPI
  // Started by mpirun/srun: join the MPI job. Ranks other than 0 are workers: they
  // ignore the command line and evaluate what rank 0 sends them until it is done.
  std::unique_ptr<sodaevo::MpiSession> mpi;
  if (sodaevo::launcher_rank_count() > 0) {
    try {
      mpi = std::make_unique<sodaevo::MpiSession>();
    } catch (const std::exception& e) {
      std::cerr << "sodaevo: error: " << e.what() << '\n';
      return 1;
    }
    if (mpi->rank() != 0) return sodaevo::run_mpi_worker(*mpi);
    sodaevo::app::set_current_mpi_session(mpi.get());
  }
#endif
  // No arguments: a newcomer's "start here", not every option (that is --help).
  if (argc <= 1) {
    std::cout << sodaevo::app::start_here_text(argc == 1 ? argv[0] : "sodaevo");
    return 0;
  }
  CLI::App app{
      "sodaevo: evolve SodaConstructor walkers on an exact re-implementation of the\n"
      "SodaConstructor mass-spring engine, and simulate or convert SodaConstructor models.\n"
      "Models are SodaConstructor XML: v1 (<model>) or v2 (SodaConstructor 2 object graph)."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "sodaevo 0.1.0\n" + sodaevo::mpi_support_summary());
  app.footer(sodaevo::mpi_support_summary() +
             ".\nUnder mpirun/srun, `evolve` runs the algorithm on rank 0 and evaluates creatures on\n"
             "every rank (docs/cluster.md).");
  sodaevo::app::add_simulate_command(app);
  sodaevo::app::add_convert_command(app);
  sodaevo::app::add_evolve_command(app);
  sodaevo::app::add_export_command(app);
  sodaevo::app::add_replay_command(app);
  sodaevo::app::add_bench_command(app);
  sodaevo::app::add_render_command(app);
  sodaevo::app::add_report_command(app);
  sodaevo::app::add_designer_command(app);
  sodaevo::app::add_race_command(app);
  sodaevo::app::add_records_command(app);
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
