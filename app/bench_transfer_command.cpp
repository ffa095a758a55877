// `sodaevo bench transfer`: do exported champions walk as claimed?
// (bench/transfer_bench.hpp). Writes transfer.csv, transfer.md and transfer.svg.
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.hpp"
#include "bench/transfer_bench.hpp"
#include "formats/atomic_file.hpp"

namespace sodaevo::app {

namespace {

struct BenchTransferOptions {
  std::vector<std::string> configs{"configs/quick.json", "configs/default.json"};
  int seeds = 5;
  int top = 10;
  int replicas = 8;
  int check_replicas = 16;
  int holdout_replicas = 64;
  int threads = 0;
  std::string out = "results/bench";
};

void run_bench_transfer(const BenchTransferOptions& opt, const std::string& command) {
  namespace fs = std::filesystem;
  bench::TransferOptions to;
  for (const std::string& path : opt.configs) {
    to.configs.push_back({fs::path(path).stem().string(), read_run_config(path)});
  }
  to.seeds.clear();
  for (int s = 1; s <= opt.seeds; ++s) to.seeds.push_back(static_cast<std::uint64_t>(s));
  to.replica_counts = {1, opt.replicas};
  to.top = opt.top;
  to.check_replicas = opt.check_replicas;
  to.holdout_replicas = opt.holdout_replicas;
  to.threads = opt.threads;
  to.work_dir = fs::path(opt.out) / "transfer-runs";
  to.progress = [](const std::string& s) { std::cerr << "bench transfer: " << s << std::endl; };
  const bench::TransferResult result = bench::run_transfer_bench(to);
  fs::create_directories(opt.out);
  soda::write_file_atomically(fs::path(opt.out) / "transfer.csv", bench::transfer_csv(result));
  const std::string md = bench::transfer_markdown(result, to, command);
  soda::write_file_atomically(fs::path(opt.out) / "transfer.md", md);
  soda::write_file_atomically(fs::path(opt.out) / "transfer.svg", bench::transfer_svg(result));
  std::cout << md;
}

} // namespace

void add_bench_transfer_command(CLI::App& bench) {
  auto opt = std::make_shared<BenchTransferOptions>();
  CLI::App* cmd = bench.add_subcommand(
      "transfer",
      "Do exported champions walk as claimed? For each config and seed, a run with one rollout per\n"
      "creature and one with K replicas at an equal budget of simulated frames; each run's top\n"
      "creatures are checked on fresh replicas (the winner's curse: claim minus check) and the\n"
      "check's 95 % interval is judged on a larger held-out ensemble. Writes transfer.csv,\n"
      "transfer.md and transfer.svg.");
  cmd->add_option("--configs", opt->configs, "Run configs (comma-separated)")->delimiter(',')->check(CLI::ExistingFile);
  cmd->add_option("--seeds", opt->seeds, "Seeds 1..N per config")->default_val(5)->check(CLI::Range(1, 1000));
  cmd->add_option("--top", opt->top, "Champions checked per run")->default_val(10)->check(CLI::Range(1, 1000));
  cmd->add_option("--replicas", opt->replicas, "K of the replica runs (against K = 1)")->default_val(8)->check(CLI::Range(2, 256));
  cmd->add_option("--check-replicas", opt->check_replicas, "Fresh replicas per champion")->default_val(16)->check(CLI::Range(2, 4096));
  cmd->add_option("--holdout", opt->holdout_replicas, "Held-out runs per champion")->default_val(64)->check(CLI::Range(1, 100000));
  cmd->add_option("--threads", opt->threads, "Threads (0 = all cores)")->default_val(0)->check(CLI::Range(0, 1024));
  cmd->add_option("--out", opt->out, "Output directory")->default_val("results/bench");
  cmd->callback([opt] {
    run_bench_transfer(*opt, "sodaevo bench transfer --seeds " + std::to_string(opt->seeds) + " --top " +
                                 std::to_string(opt->top) + " --replicas " + std::to_string(opt->replicas));
  });
}

} // namespace sodaevo::app
