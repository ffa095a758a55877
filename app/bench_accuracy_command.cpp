// `sodaevo bench accuracy` (work-precision, bench/accuracy_bench.hpp) and
// `sodaevo bench stress` (stability, bench/extreme_creatures.hpp): CSV, log-log
// SVG charts and a Markdown summary under results/bench/.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "app/commands.hpp"
#include "app/svg_chart.hpp"
#include "bench/accuracy_bench.hpp"
#include "bench/extreme_creatures.hpp"
#include "core/input_error.hpp"
#include "core/number_text.hpp"
#include "evolve/parallel_for.hpp"
#include "formats/atomic_file.hpp"

namespace sodaevo::app {

namespace {

namespace fs = std::filesystem;

std::string num(double v) { return soda::format_printf("%.6g", v); }
std::string pct(double share) { return soda::format_printf("%.3g %%", 100.0 * share); }

std::string slug(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? static_cast<char>(std::tolower(c)) : '_';
  return out;
}

std::string accuracy_csv(const bench::AccuracyReport& r) {
  std::ostringstream o;
  o << "section,scene,setting,mode,integrator,substeps,dt,seconds_per_frame,position_error,distance,"
       "reference_distance,distance_error,kendall_tau,kendall_tau_100_frames,kendall_tau_movers,diverged\n";
  for (const auto& row : r.rows) {
    const bool soda = row.stepping.mode == soda::PhysicsMode::Soda;
    o << row.section << ',' << row.scene << ',' << soda::stepping_label(row.stepping) << ','
      << soda::mode_name(row.stepping.mode) << ',' << (soda ? "euler" : soda::integrator_name(row.stepping.integrator))
      << ',' << row.stepping.substeps << ',' << num(1.0 / row.stepping.substeps) << ',' << num(row.seconds_per_frame)
      << ',' << num(row.position_error) << ',' << num(row.distance) << ',' << num(row.reference_distance) << ','
      << num(row.distance_error) << ',' << num(row.kendall_tau) << ',' << num(row.kendall_tau_short) << ','
      << num(row.kendall_tau_movers) << ',' << row.diverged << '\n';
  }
  return o.str();
}

/// Per setting, aggregated over the rows of one section (and scenes): mean time
/// per frame and the largest error.
struct Aggregate {
  soda::Stepping stepping;
  double seconds_per_frame = 0.0;
  double worst_distance_error = 0.0;
  double median_distance_error = 0.0;
  double worst_position_error = 0.0;
  double kendall_tau = 0.0;
  double kendall_tau_short = 0.0;
  double kendall_tau_movers = 0.0;
  bool pareto = false;
};

std::vector<Aggregate> aggregate(const bench::AccuracyReport& r, const std::string& section,
                                 const std::vector<std::string>& scenes) {
  std::vector<Aggregate> out;
  for (const soda::Stepping& st : bench::swept_settings(64)) {
    Aggregate a;
    a.stepping = st;
    std::vector<double> errors;
    int n = 0;
    for (const auto& row : r.rows) {
      if (row.section != section || !(row.stepping == st)) continue;
      if (!scenes.empty() && std::find(scenes.begin(), scenes.end(), row.scene) == scenes.end()) continue;
      a.seconds_per_frame += row.seconds_per_frame;
      a.worst_distance_error = std::max(a.worst_distance_error, row.distance_error);
      a.worst_position_error = std::max(a.worst_position_error, row.position_error);
      a.kendall_tau = row.kendall_tau;
      a.kendall_tau_short = row.kendall_tau_short;
      a.kendall_tau_movers = row.kendall_tau_movers;
      errors.push_back(row.distance_error);
      ++n;
    }
    if (n == 0) continue;
    a.seconds_per_frame /= n;
    std::sort(errors.begin(), errors.end());
    a.median_distance_error = errors[errors.size() / 2];
    out.push_back(a);
  }
  return out;
}

/// Marks the settings no other setting beats in both time and `error`.
template <class Error>
void mark_pareto(std::vector<Aggregate>& v, Error error) {
  for (Aggregate& a : v) {
    a.pareto = std::none_of(v.begin(), v.end(), [&](const Aggregate& b) {
      return b.seconds_per_frame <= a.seconds_per_frame && error(b) <= error(a) &&
             (b.seconds_per_frame < a.seconds_per_frame || error(b) < error(a));
    });
  }
}

std::string work_precision_svg(const std::string& title, const std::string& y_label,
                               const std::vector<Aggregate>& points, double (*error)(const Aggregate&)) {
  LineChart c;
  c.title = title;
  c.x_axis = {"run time per frame (s)", true};
  c.y_axis = {y_label, true};
  for (soda::Integrator in : {soda::Integrator::Euler, soda::Integrator::Verlet, soda::Integrator::Rk4}) {
    LineSeries s;
    s.name = soda::integrator_name(in) + " (dt = 1 ... 1/64)";
    for (const Aggregate& a : points) {
      if (a.stepping.mode != soda::PhysicsMode::Continuous || a.stepping.integrator != in) continue;
      s.x.push_back(a.seconds_per_frame);
      s.y.push_back(std::max(error(a), 1e-16));
    }
    c.series.push_back(s);
  }
  for (const Aggregate& a : points) {
    if (a.stepping.mode != soda::PhysicsMode::Soda) continue;
    c.series.push_back({"soda (original)", {a.seconds_per_frame}, {std::max(error(a), 1e-16)},
                        true, false});
  }
  return render_line_chart(c);
}

/// True if `row` and every finer step of the same integrator on the same scene
/// are within `tolerance` (so the setting is not within it by luck of a sign
/// change in a converging error). Soda counts as Euler at one step per frame, and
/// euler/1 (identical to soda) is left out in favour of soda.
bool stays_within(const bench::AccuracyRow& row, double tolerance, const bench::AccuracyReport& r) {
  const bool soda_row = row.stepping.mode == soda::PhysicsMode::Soda;
  if (!soda_row && row.stepping.integrator == soda::Integrator::Euler && row.stepping.substeps == 1) return false;
  if (row.distance_error > tolerance) return false;
  const soda::Integrator integrator = soda_row ? soda::Integrator::Euler : row.stepping.integrator;
  const int substeps = soda_row ? 1 : row.stepping.substeps;
  for (const auto& other : r.rows) {
    if (other.section != row.section || other.scene != row.scene) continue;
    if (other.stepping.mode != soda::PhysicsMode::Continuous || other.stepping.integrator != integrator) continue;
    if (other.stepping.substeps > substeps && other.distance_error > tolerance) return false;
  }
  return true;
}

bool stays_within(const bench::AccuracyReport& r, const bench::AccuracyRow& row, double tolerance) {
  return stays_within(row, tolerance, r);
}

std::string accuracy_markdown(const bench::AccuracyReport& r, const std::string& command, std::vector<Aggregate>& classic,
                              std::vector<Aggregate>& walkers) {
  std::ostringstream o;
  o << "Measured with `" << command << "`: run time is wall time per simulated frame on one thread (the\n"
    << "fastest of 3 runs for analytic scenes and classics; soda runs the plain reference step, a scalar loop\n"
    << "like the continuous stepper, so times compare methods); errors against the closed form (analytic\n"
    << "scenes) or RK4 at many sub-steps (classics, walkers).\n\n";
  o << "Classic walkers (reference distance above 50 px): ";
  for (std::size_t i = 0; i < r.walkers_among_classics.size(); ++i) o << (i ? ", " : "") << r.walkers_among_classics[i];
  o << ".\nReference uncertainty (RK4 at half the reference sub-steps vs the reference, relative distance):";
  for (const auto& [name, u] : r.reference_uncertainty) o << ' ' << name << ' ' << pct(u) << ';';
  o << "\n\n## Distance walked by the classic walkers\n\n";
  o << "| setting | s/frame | median distance error | worst distance error | worst position error at frame 100 (px) | Pareto |\n";
  o << "|---|---:|---:|---:|---:|:-:|\n";
  for (const Aggregate& a : classic) {
    o << "| " << soda::stepping_label(a.stepping) << " | " << num(a.seconds_per_frame) << " | "
      << pct(a.median_distance_error) << " | " << pct(a.worst_distance_error) << " | " << num(a.worst_position_error)
      << " | " << (a.pareto ? "yes" : "") << " |\n";
  }
  o << "\nPer walker, the original scheme (soda) against the reference, and the cheapest setting that is within\n"
    << "1 % and stays within 1 % at every finer step of its integrator:\n\n";
  o << "| walker | reference distance (px) | soda distance (px) | soda error | cheapest within 1 % | its s/frame | x soda's time |\n";
  o << "|---|---:|---:|---:|---|---:|---:|\n";
  for (const std::string& w : r.walkers_among_classics) {
    const bench::AccuracyRow* soda_row = nullptr;
    const bench::AccuracyRow* cheapest = nullptr;
    for (const auto& row : r.rows) {
      if (row.section != "classic" || row.scene != w) continue;
      if (row.stepping.mode == soda::PhysicsMode::Soda) soda_row = &row;
    }
    for (const auto& row : r.rows) {
      if (row.section != "classic" || row.scene != w || !stays_within(r, row, 0.01)) continue;
      if (!cheapest || row.seconds_per_frame < cheapest->seconds_per_frame) cheapest = &row;
    }
    if (!soda_row) continue;
    o << "| " << w << " | " << num(soda_row->reference_distance) << " | " << num(soda_row->distance) << " | "
      << pct(soda_row->distance_error) << " | " << (cheapest ? soda::stepping_label(cheapest->stepping) : "none") << " | "
      << (cheapest ? num(cheapest->seconds_per_frame) : "-") << " | "
      << (cheapest && soda_row->seconds_per_frame > 0 ? num(cheapest->seconds_per_frame / soda_row->seconds_per_frame)
                                                      : "-")
      << " |\n";
  }
  const Aggregate* all_within = nullptr;
  for (const Aggregate& a : classic) {
    bool stays = a.worst_distance_error <= 0.01;
    for (const Aggregate& finer : classic) {
      if (finer.stepping.mode == a.stepping.mode && finer.stepping.integrator == a.stepping.integrator &&
          finer.stepping.substeps > a.stepping.substeps && finer.worst_distance_error > 0.01) {
        stays = false;
      }
    }
    if (stays && (!all_within || a.seconds_per_frame < all_within->seconds_per_frame)) all_within = &a;
  }
  o << "\nCheapest setting within 1 % on every classic walker (and at every finer step of its integrator): "
    << (all_within ? soda::stepping_label(all_within->stepping) + " (" + num(all_within->seconds_per_frame) + " s/frame)"
                   : std::string("none in the sweep"))
    << ".\n\n## Ranking of random walkers\n\n";
  o << "Noise floor: the reference at half its sub-steps ranks the walkers with tau " << num(r.walkers_noise_floor_tau)
    << " after all scored frames, " << num(r.walkers_noise_floor_tau_short) << " after 100 frames, and "
    << num(r.walkers_noise_floor_tau_movers) << " among the " << r.walkers_movers
    << " movers (reference speed at least 0.1 px/frame); no setting can be expected to do better. Most random\n"
    << "creatures barely move, and contact makes every integrator first order, so their distances are jitter.\n\n";
  o << "| setting | s/frame | tau, movers | tau, all walkers | tau, 100 frames | median distance error (all frames) | diverged | Pareto (tau, movers) |\n";
  o << "|---|---:|---:|---:|---:|---:|---:|:-:|\n";
  for (const Aggregate& a : walkers) {
    int diverged = 0;
    for (const auto& row : r.rows) {
      if (row.section == "walkers" && row.stepping == a.stepping) diverged = row.diverged;
    }
    o << "| " << soda::stepping_label(a.stepping) << " | " << num(a.seconds_per_frame) << " | "
      << num(a.kendall_tau_movers) << " | " << num(a.kendall_tau) << " | " << num(a.kendall_tau_short) << " | "
      << pct(a.median_distance_error) << " | " << diverged << " | " << (a.pareto ? "yes" : "") << " |\n";
  }
  o << "\n## Analytic scenes (largest position error at frames 10, 20, 40, px)\n\n| setting |";
  std::vector<std::string> scenes;
  for (const auto& row : r.rows) {
    if (row.section == "analytic" && std::find(scenes.begin(), scenes.end(), row.scene) == scenes.end()) {
      scenes.push_back(row.scene);
    }
  }
  for (const auto& s : scenes) o << ' ' << s << " |";
  o << "\n|---|";
  for (std::size_t i = 0; i < scenes.size(); ++i) o << "---:|";
  o << '\n';
  for (const soda::Stepping& st : bench::swept_settings(64)) {
    std::string line = "| " + soda::stepping_label(st) + " |";
    bool any = false;
    for (const auto& s : scenes) {
      for (const auto& row : r.rows) {
        if (row.section == "analytic" && row.scene == s && row.stepping == st) {
          line += ' ' + num(row.position_error) + " |";
          any = true;
        }
      }
    }
    if (any) o << line << '\n';
  }
  return o.str();
}

struct BenchAccuracyOptions {
  bool quick = false;
  std::string out = "results/bench";
  std::string models = "models";
  int walkers = 200;
  long long frames = 2000;
  long long walker_frames = 1000;
};

void run_bench_accuracy(const BenchAccuracyOptions& opt, const std::string& command) {
  bench::AccuracyOptions ao;
  ao.quick = opt.quick;
  ao.walkers = opt.walkers;
  ao.classic_frames = opt.frames;
  ao.walker_frames = opt.walker_frames;
  for (const char* name : {"dainty_walker", "carefulslug", "monster_truck", "treader", "wodka_m1", "wheel", "turbine"}) {
    const fs::path p = fs::path(opt.models) / (std::string(name) + ".xml");
    if (!fs::exists(p)) {
      throw soda::InputError(p.string() + ": bundled creature not found (run from the project root or pass --models DIR)");
    }
    ao.classics.emplace_back(name, p.string());
  }
  ao.progress = [](const std::string& line) { std::cerr << "bench accuracy: " << line << std::endl; };
  const bench::AccuracyReport report = bench::run_accuracy_bench(ao);

  std::vector<Aggregate> classic = aggregate(report, "classic", report.walkers_among_classics);
  mark_pareto(classic, [](const Aggregate& a) { return a.worst_distance_error; });
  std::vector<Aggregate> walkers = aggregate(report, "walkers", {});
  mark_pareto(walkers, [](const Aggregate& a) { return 1.0 - a.kendall_tau_movers; });

  fs::create_directories(opt.out);
  const fs::path out(opt.out);
  soda::write_file_atomically(out / "accuracy.csv", accuracy_csv(report));
  soda::write_file_atomically(
      out / "accuracy_classics.svg",
      work_precision_svg("Classic walkers: distance-walked error vs run time", "worst relative distance error", classic,
                         [](const Aggregate& a) { return a.worst_distance_error; }));
  soda::write_file_atomically(out / "accuracy_walkers.svg",
                              work_precision_svg("Random walkers that move: ranking error vs run time",
                                                 "1 - Kendall tau against the reference", walkers,
                                                 [](const Aggregate& a) { return 1.0 - a.kendall_tau_movers; }));
  soda::write_file_atomically(out / "accuracy_walkers_all.svg",
                              work_precision_svg("All random walkers: ranking error vs run time",
                                                 "1 - Kendall tau against the reference", walkers,
                                                 [](const Aggregate& a) { return 1.0 - a.kendall_tau; }));
  std::vector<std::string> written = {"accuracy.csv", "accuracy_classics.svg", "accuracy_walkers.svg",
                                      "accuracy_walkers_all.svg"};
  std::vector<std::string> scenes;
  for (const auto& row : report.rows) {
    if (row.section == "analytic" && std::find(scenes.begin(), scenes.end(), row.scene) == scenes.end()) {
      scenes.push_back(row.scene);
    }
  }
  for (const std::string& scene : scenes) {
    const std::vector<Aggregate> pts = aggregate(report, "analytic", {scene});
    const std::string file = "accuracy_" + slug(scene) + ".svg";
    soda::write_file_atomically(out / file, work_precision_svg(scene + ": position error vs run time",
                                                               "largest position error (px)", pts,
                                                               [](const Aggregate& a) { return a.worst_position_error; }));
    written.push_back(file);
  }
  const std::string md = accuracy_markdown(report, command, classic, walkers);
  soda::write_file_atomically(out / "accuracy.md", md);
  written.push_back("accuracy.md");
  std::cout << md;
  std::cerr << "bench accuracy: wrote";
  for (const auto& f : written) std::cerr << ' ' << (out / f).string();
  std::cerr << '\n';
}

struct BenchStressOptions {
  long long creatures = 1'000'000;
  long long frames = 20;
  std::uint64_t seed = 1;
  int threads = 0;
  bool all_modes = false;
  std::string out = "results/bench";
};

void run_bench_stress(const BenchStressOptions& opt, const std::string& command) {
  bench::StressOptions so;
  so.seed = opt.seed;
  so.creatures = opt.creatures;
  so.frames = opt.frames;
  so.threads = resolve_thread_count(opt.threads);
  if (opt.all_modes) {
    so.steppings = {soda::Stepping{},
                    {soda::PhysicsMode::Continuous, soda::Integrator::Euler, 4},
                    {soda::PhysicsMode::Continuous, soda::Integrator::Verlet, 4},
                    {soda::PhysicsMode::Continuous, soda::Integrator::Rk4, 4}};
  }
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<bench::StressCounts> counts = bench::run_stress(so);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::ostringstream csv, md;
  csv << "stepping,creatures_tried,frames_per_creature,frames_stepped,diverged_non_finite,diverged_energy,escaped\n";
  md << "Measured with `" << command << "` (" << so.threads << " threads, " << num(seconds) << " s).\n\n";
  md << "| stepping | creatures tried | frames stepped | flagged: non-finite state | flagged: energy runaway | escaped |\n";
  md << "|---|---:|---:|---:|---:|---:|\n";
  bool escaped = false;
  std::ostringstream notes;
  for (const auto& c : counts) {
    csv << c.stepping << ',' << c.tried << ',' << opt.frames << ',' << c.frames_stepped << ',' << c.diverged_non_finite
        << ',' << c.diverged_energy << ',' << c.escaped << '\n';
    md << "| " << c.stepping << " | " << c.tried << " | " << c.frames_stepped << " | " << c.diverged_non_finite << " | "
       << c.diverged_energy << " | " << c.escaped << " |\n";
    if (c.escaped) {
      escaped = true;
      notes << "\nFirst escape (" << c.stepping << "): " << c.first_escape << "\n";
    }
    if (!c.example_diverged.empty()) notes << "\nExample flagged (" << c.stepping << "): " << c.example_diverged << "\n";
  }
  md << notes.str();
  fs::create_directories(opt.out);
  soda::write_file_atomically(fs::path(opt.out) / "stress.csv", csv.str());
  soda::write_file_atomically(fs::path(opt.out) / "stress.md", md.str());
  std::cout << md.str();
  if (escaped) throw soda::InputError("bench stress: a non-finite value escaped the divergence detector (see above)");
}

} // namespace

void add_bench_accuracy_commands(CLI::App& bench) {
  auto opt = std::make_shared<BenchAccuracyOptions>();
  CLI::App* acc = bench.add_subcommand(
      "accuracy",
      "Work-precision: run time against error for soda and the continuous mode's euler, verlet\n"
      "and rk4 at dt = 1 ... 1/64 frame, on analytic scenes (closed forms), the bundled classics\n"
      "(distance walked vs RK4 at 256 sub-steps) and random walkers (Kendall tau of the ranking).\n"
      "Writes accuracy.csv, accuracy_*.svg (log-log) and accuracy.md. Takes a few minutes.");
  acc->add_flag("--quick", opt->quick, "Small sweep (dt down to 1/8, 20 walkers, short runs): a smoke test");
  acc->add_option("--out", opt->out, "Output directory")->default_val("results/bench");
  acc->add_option("--models", opt->models, "Directory with the bundled creatures")->default_val("models");
  acc->add_option("--walkers", opt->walkers, "Random walkers ranked")->default_val(200)->check(CLI::Range(2, 100000));
  acc->add_option("--frames", opt->frames, "Scored frames of the classics (after 100 settle frames)")
      ->default_val(2000)
      ->check(CLI::Range(1LL, 10'000'000LL));
  acc->add_option("--walker-frames", opt->walker_frames, "Scored frames of each random walker")
      ->default_val(1000)
      ->check(CLI::Range(1LL, 10'000'000LL));
  acc->callback([opt] {
    std::string command = "sodaevo bench accuracy";
    if (opt->quick) command += " --quick";
    if (opt->walkers != 200) command += " --walkers " + std::to_string(opt->walkers);
    if (opt->frames != 2000) command += " --frames " + std::to_string(opt->frames);
    if (opt->walker_frames != 1000) command += " --walker-frames " + std::to_string(opt->walker_frames);
    run_bench_accuracy(*opt, command);
  });

  auto sopt = std::make_shared<BenchStressOptions>();
  CLI::App* stress = bench.add_subcommand(
      "stress",
      "Stability: random creatures with extreme but legal parameters (springyness 0.5, gravity 4,\n"
      "hubs, zero/negative/huge rest lengths, coincident masses, masses outside the container,\n"
      "links listed twice), every frame watched by the divergence detector. Reports creatures\n"
      "tried and flagged; fails if a non-finite value escapes. Writes stress.csv and stress.md.");
  stress->add_option("--creatures", sopt->creatures, "Creatures to try")
      ->default_val(1000000)
      ->check(CLI::Range(1LL, 1'000'000'000LL));
  stress->add_option("--frames", sopt->frames, "Frames per creature")->default_val(20)->check(CLI::Range(1LL, 1'000'000LL));
  stress->add_option("--seed", sopt->seed, "Seed of the creatures")->default_val(1);
  stress->add_option("--threads", sopt->threads, "Threads (0 = all cores)")->default_val(0)->check(CLI::Range(0, 1024));
  stress->add_flag("--all-modes", sopt->all_modes, "Also run continuous euler, verlet and rk4 at 4 sub-steps");
  stress->add_option("--out", sopt->out, "Output directory")->default_val("results/bench");
  stress->callback([sopt] {
    std::string command = "sodaevo bench stress --creatures " + std::to_string(sopt->creatures) + " --frames " +
                          std::to_string(sopt->frames);
    if (sopt->seed != 1) command += " --seed " + std::to_string(sopt->seed);
    if (sopt->all_modes) command += " --all-modes";
    run_bench_stress(*sopt, command);
  });
}

} // namespace sodaevo::app
