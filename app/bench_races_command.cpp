// `sodaevo bench races`: the 880 golden race results of the original racer, raced
// again (bench/golden_races.hpp); writes results/bench/races.md.
#include <chrono>
#include <iostream>
#include <memory>

#include "app/commands.hpp"
#include "bench/golden_races.hpp"
#include "core/atomic_file.hpp"

namespace sodaevo::app {

namespace {

struct BenchRacesOptions {
  std::string data = "tests/data";
  std::string out = "results/bench";
  std::string race_filter;
};

void run_bench_races(const BenchRacesOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<bench::GoldenRace> races = bench::race_golden(opt.data, opt.race_filter);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::string report = "# Golden races (sodaevo bench races)\n\nThe results of the original racer (" + opt.data +
                       "/terrain/races.tsv) raced again with `sodaevo race`'s lane, in " +
                       std::to_string(static_cast<int>(seconds)) + " s.\n\n" + bench::golden_races_report(races);
  std::cout << report;
  if (opt.race_filter.empty()) {
    std::filesystem::create_directories(opt.out);
    soda::write_file_atomically(std::filesystem::path(opt.out) / "races.md", report);
    std::cerr << "bench races: wrote " << (std::filesystem::path(opt.out) / "races.md").string() << "\n";
  }
}

} // namespace

void add_bench_races_command(CLI::App& bench) {
  auto opt = std::make_shared<BenchRacesOptions>();
  CLI::App* cmd = bench.add_subcommand(
      "races", "The original racer's 880 golden race results (20 race files x 44 contenders), raced again:\n"
               "how many agree to the last bit, and each difference with its diagnosis. Writes races.md.");
  cmd->add_option("--data", opt->data, "Folder holding soda/ and terrain/ (the golden data)")->default_val(opt->data);
  cmd->add_option("--out", opt->out, "Output directory")->default_val(opt->out);
  cmd->add_option("--race", opt->race_filter, "Only race files whose path contains this (prints, writes nothing)");
  cmd->callback([opt] { run_bench_races(*opt); });
}

} // namespace sodaevo::app
