// `sodaevo bench stability`: the stability predictor's confusion matrix and ROC
// curve on bench stress's extreme creatures (bench/stability_bench.hpp). Writes
// stability.csv (one row per creature), stability.md and stability.svg (the ROC).
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include "app/commands.hpp"
#include "app/stepping_options.hpp"
#include "charts/svg_chart.hpp"
#include "bench/stability_bench.hpp"
#include "formats/atomic_file.hpp"
#include "core/number_text.hpp"
#include "evolve/evaluators/parallel_for.hpp"

namespace sodaevo::app {

namespace {

namespace fs = std::filesystem;

struct BenchStabilityOptions {
  long long creatures = 2000;
  long long frames = 200;
  long long sample_every = 10;
  std::uint64_t seed = 1;
  int threads = 0;
  SteppingOptions stepping;
  std::string out = "results/bench";
};

std::string margin_text(double m) { return std::isinf(m) ? "inf" : soda::format_double_plain(m); }

std::string confusion_table(const bench::Confusion& c) {
  std::ostringstream md;
  const long long predicted_unstable = c.true_positive + c.false_positive;
  const long long diverged = c.true_positive + c.false_negative;
  md << "| | diverged | stayed healthy |\n|---|---:|---:|\n";
  md << "| predicted unstable (margin < 1) | " << c.true_positive << " | " << c.false_positive << " |\n";
  md << "| predicted stable (margin >= 1) | " << c.false_negative << " | " << c.true_negative << " |\n\n";
  auto share = [](long long a, long long b) { return b > 0 ? soda::format_double_plain(std::round(1000.0 * a / b) / 10.0) + " %" : std::string("-"); };
  md << "Precision " << share(c.true_positive, predicted_unstable) << ", recall " << share(c.true_positive, diverged)
     << ".\n\n";
  return md.str();
}

void run_bench_stability(const BenchStabilityOptions& opt, const std::string& command) {
  bench::StabilityBenchOptions o;
  o.creatures = opt.creatures;
  o.frames = opt.frames;
  o.sample_every = opt.sample_every;
  o.seed = opt.seed;
  o.threads = resolve_thread_count(opt.threads);
  o.stepping = stepping_of(opt.stepping);
  const bench::StabilityBenchReport r = bench::run_stability_bench(o);

  std::ostringstream csv;
  csv << "creature,masses,margin_frame0,margin_min,diverged,diverged_frame,reason\n";
  long long diverged = 0, missed_energy = 0, false_alarms = 0, held_by_syrup = 0, held_by_walls = 0;
  std::string missed_example;
  for (const bench::StabilityCase& c : r.cases) {
    std::string reason = c.reason;
    for (char& ch : reason) {
      if (ch == ',' || ch == '\n') ch = ';';
    }
    csv << c.creature << ',' << c.masses << ',' << margin_text(c.margin_first) << ',' << margin_text(c.margin_min)
        << ',' << (c.diverged ? 1 : 0) << ',' << c.diverged_frame << ',' << reason << '\n';
    if (c.diverged) ++diverged;
    if (!c.diverged && c.margin_first < 1.0) {
      ++false_alarms;
      if (c.speed_limited) ++held_by_syrup;
      else if (c.touching) ++held_by_walls;
    }
    if (c.diverged && c.margin_min >= 1.0) {
      ++missed_energy;
      if (missed_example.empty()) {
        missed_example = "creature " + std::to_string(c.creature) + " (lowest margin " + margin_text(c.margin_min) +
                         ", frame " + std::to_string(c.diverged_frame) + "): " + c.reason;
      }
    }
  }
  std::ostringstream md;
  md << "# Stability predictor on extreme creatures\n\n";
  md << "Measured with `" << command << "` (" << o.threads << " threads, " << soda::format_double_plain(std::round(r.seconds * 10) / 10)
     << " s). " << r.cases.size() << " creatures of `bench stress` (same seeds), each run " << o.frames
     << " frames in " << soda::stepping_label(o.stepping)
     << ", every frame watched for a non-finite state or an energy runaway; " << diverged
     << " diverged. Margin = (stable_dt / dt)^2 of the linearised step (docs/stability.md); below 1 predicts "
        "divergence.\n\n";
  md << "## At frame 0\n\n" << confusion_table(r.first);
  md << "ROC area " << soda::format_double_plain(std::round(r.auc_first * 1000) / 1000) << ".\n\n";
  md << "## Smallest margin over the run (sampled every " << o.sample_every << " frames before divergence)\n\n"
     << confusion_table(r.lowest);
  md << "ROC area " << soda::format_double_plain(std::round(r.auc_lowest * 1000) / 1000) << ".\n\n";
  md << "Healthy creatures called unstable at frame 0: " << false_alarms << "; at the end of the run " << held_by_syrup
     << " of them have a mass at the speed limit (the syrup holds the unstable mode's growth, so energy stays within "
        "the monitor's budget) and "
     << held_by_walls << " more a mass on the container's edge (contact clamps it).\n\n";
  md << "Diverged with every sampled margin >= 1 (not a step instability the linear prediction sees: energy pumped "
        "in by a V-shaped potential, overflow from an absurd rest length, contact): "
     << missed_energy << ".";
  if (!missed_example.empty()) md << " Example: " << missed_example << ".";
  md << "\n";

  charts::LineChart chart;
  chart.title = "Stability predictor: ROC on " + std::to_string(r.cases.size()) + " extreme creatures (" +
                soda::stepping_label(o.stepping) + ")";
  chart.x_axis = {"false positive rate (healthy creatures called unstable)", false, 0.0, 1.0};
  chart.y_axis = {"true positive rate (diverged creatures called unstable)", false, 0.0, 1.0};
  auto series = [](const std::string& name, const std::vector<bench::RocPoint>& roc) {
    charts::LineSeries s;
    s.name = name;
    s.markers = false;
    for (const bench::RocPoint& p : roc) {
      s.x.push_back(p.false_positive_rate);
      s.y.push_back(p.true_positive_rate);
    }
    return s;
  };
  chart.series.push_back(series("margin at frame 0 (area " + soda::format_double_plain(std::round(r.auc_first * 1000) / 1000) + ")", r.roc_first));
  chart.series.push_back(series("smallest sampled margin (area " + soda::format_double_plain(std::round(r.auc_lowest * 1000) / 1000) + ")", r.roc_lowest));
  chart.series.push_back({"chance", {0.0, 1.0}, {0.0, 1.0}, false, true});

  fs::create_directories(opt.out);
  soda::write_file_atomically(fs::path(opt.out) / "stability.csv", csv.str());
  soda::write_file_atomically(fs::path(opt.out) / "stability.md", md.str());
  soda::write_file_atomically(fs::path(opt.out) / "stability.svg", charts::render_line_chart(chart));
  std::cout << md.str();
}

} // namespace

void add_bench_stability_command(CLI::App& bench) {
  auto opt = std::make_shared<BenchStabilityOptions>();
  CLI::App* cmd = bench.add_subcommand(
      "stability",
      "How well the predicted stability margin (simulate --stability) tells which of bench stress's\n"
      "extreme creatures diverge: confusion matrix at margin 1 and ROC curve, at frame 0 and for the\n"
      "smallest margin sampled along the run. Writes stability.csv, stability.md and stability.svg.");
  cmd->add_option("--creatures", opt->creatures, "Creatures to try")->default_val(2000)->check(CLI::Range(1LL, 10'000'000LL));
  cmd->add_option("--frames", opt->frames, "Frames per creature")->default_val(200)->check(CLI::Range(1LL, 1'000'000LL));
  cmd->add_option("--sample-every", opt->sample_every, "Frames between margin samples")
      ->default_val(10)
      ->check(CLI::Range(1LL, 1'000'000LL));
  cmd->add_option("--seed", opt->seed, "Seed of the creatures (as bench stress)")->default_val(1);
  cmd->add_option("--threads", opt->threads, "Threads (0 = all cores)")->default_val(0)->check(CLI::Range(0, 1024));
  add_stepping_options(cmd, opt->stepping);
  cmd->add_option("--out", opt->out, "Output directory")->default_val("results/bench");
  cmd->callback([opt] {
    std::string command = "sodaevo bench stability --creatures " + std::to_string(opt->creatures) + " --frames " +
                          std::to_string(opt->frames);
    if (opt->sample_every != 10) command += " --sample-every " + std::to_string(opt->sample_every);
    if (opt->seed != 1) command += " --seed " + std::to_string(opt->seed);
    const soda::Stepping st = stepping_of(opt->stepping);
    if (st.mode != soda::PhysicsMode::Soda) {
      command += " --mode continuous --integrator " + soda::integrator_name(st.integrator) + " --substeps " +
                 std::to_string(st.substeps);
    }
    run_bench_stability(*opt, command);
  });
}

} // namespace sodaevo::app
