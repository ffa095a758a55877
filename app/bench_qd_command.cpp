// `sodaevo bench qd`: MAP-Elites against the GA at equal evaluations
// (bench/qd_bench.hpp). Writes qd.csv, qd.md and qd.svg, and keeps the runs'
// folders under qd-runs/.
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.hpp"
#include "bench/qd_bench.hpp"
#include "formats/atomic_file.hpp"

namespace sodaevo::app {

namespace {

struct BenchQdOptions {
  std::string config = "configs/map_elites.json";
  int seeds = 5;
  int iterations = 0; ///< 0: the config's
  int check_replicas = 8;
  int threads = 0;
  std::string out = "results/bench";
};

void run_bench_qd(const BenchQdOptions& opt, const std::string& command) {
  namespace fs = std::filesystem;
  bench::QdOptions qo;
  qo.config = read_run_config(opt.config);
  qo.config_name = opt.config;
  qo.seeds.clear();
  for (int s = 1; s <= opt.seeds; ++s) qo.seeds.push_back(static_cast<std::uint64_t>(s));
  qo.iterations = opt.iterations;
  qo.check_replicas = opt.check_replicas;
  qo.threads = opt.threads;
  qo.work_dir = fs::path(opt.out) / "qd-runs";
  qo.progress = [](const std::string& s) { std::cerr << "bench qd: " << s << std::endl; };
  const std::vector<bench::QdRow> rows = bench::run_qd_bench(qo);
  fs::create_directories(opt.out);
  soda::write_file_atomically(fs::path(opt.out) / "qd.csv", bench::qd_csv(rows));
  soda::write_file_atomically(fs::path(opt.out) / "qd.svg", bench::qd_svg(rows));
  const std::string md = bench::qd_markdown(rows, qo, command);
  soda::write_file_atomically(fs::path(opt.out) / "qd.md", md);
  std::cout << md;
}

} // namespace

void add_bench_qd_command(CLI::App& bench) {
  auto opt = std::make_shared<BenchQdOptions>();
  CLI::App* cmd = bench.add_subcommand(
      "qd",
      "MAP-Elites against the GA at equal evaluations over several seeds: QD-score, coverage and\n"
      "best fitness (as estimated and checked on fresh replicas), the GA's last population counted\n"
      "as an archive of the same grid. Writes qd.csv, qd.md and qd.svg (and the runs under qd-runs/).");
  cmd->add_option("--config", opt->config, "A MAP-Elites config")
      ->default_val("configs/map_elites.json")
      ->check(non_empty_path())
      ->check(CLI::ExistingFile);
  cmd->add_option("--seeds", opt->seeds, "Seeds 1..N")->default_val(5)->check(CLI::Range(1, 1000));
  cmd->add_option("--iterations", opt->iterations, "MAP-Elites iterations (0 = the config's)")
      ->default_val(0)
      ->check(CLI::Range(0, 1000000));
  cmd->add_option("--check-replicas", opt->check_replicas, "Fresh replicas of the checks")
      ->default_val(8)
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--threads", opt->threads, "Threads (0 = all cores)")->default_val(0)->check(CLI::Range(0, 1024));
  cmd->add_option("--out", opt->out, "Output directory")->default_val("results/bench");
  cmd->callback([opt] {
    std::string command = "sodaevo bench qd --config " + opt->config + " --seeds " + std::to_string(opt->seeds);
    if (opt->iterations > 0) command += " --iterations " + std::to_string(opt->iterations);
    run_bench_qd(*opt, command);
  });
}

} // namespace sodaevo::app
