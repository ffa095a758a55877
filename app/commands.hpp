// The sodaevo subcommands. Each registers its options on the CLI11 app and runs
// when selected; main.cpp only wires them together and turns errors into messages.
#pragma once

#include <CLI/CLI.hpp>

namespace sodaevo::app {

/// Refuses an empty path argument, saying so: CLI11's existence checks would print
/// "File does not exist: " naming nothing. Checked before them.
inline CLI::Validator non_empty_path() {
  return CLI::Validator([](std::string& path) { return path.empty() ? "expected a path, got an empty one" : ""; },
                        "");
}

void add_simulate_command(CLI::App& app);
void add_convert_command(CLI::App& app);
void add_evolve_command(CLI::App& app);
void add_export_command(CLI::App& app);
void add_replay_command(CLI::App& app);
void add_bench_command(CLI::App& app);
/// `bench evolve`, registered by add_bench_command on its `bench` subcommand.
void add_bench_evolve_command(CLI::App& bench);
/// `bench transfer` (app/bench_transfer_command.cpp), registered the same way.
void add_bench_transfer_command(CLI::App& bench);
/// `bench qd` (MAP-Elites against the GA), registered on the `bench` subcommand.
void add_bench_qd_command(CLI::App& bench);
/// `bench stability` (app/bench_stability_command.cpp), registered the same way.
void add_bench_stability_command(CLI::App& bench);
void add_render_command(CLI::App& app);
void add_report_command(CLI::App& app);
void add_designer_command(CLI::App& app);
void add_race_command(CLI::App& app);
/// `records`: the Sodarace record book (app/records_command.cpp).
void add_records_command(CLI::App& app);
/// `bench accuracy` and `bench stress`, registered on the `bench` subcommand.
void add_bench_accuracy_commands(CLI::App& bench);
/// `bench races`, registered on the `bench` subcommand.
void add_bench_races_command(CLI::App& bench);

} // namespace sodaevo::app
