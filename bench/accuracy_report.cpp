#include "bench/accuracy_report.hpp"

#include <algorithm>
#include <cctype>
#include <sstream>

#include "charts/svg_chart.hpp"
#include "core/number_text.hpp"
#include "formats/atomic_file.hpp"

namespace sodaevo::bench {

namespace {

std::string num(double v) { return soda::format_printf("%.6g", v); }
std::string pct(double share) { return soda::format_printf("%.3g %%", 100.0 * share); }

std::string slug(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? static_cast<char>(std::tolower(c)) : '_';
  return out;
}

std::string accuracy_csv(const AccuracyReport& r) {
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

std::vector<Aggregate> aggregate(const AccuracyReport& r, const std::string& section,
                                 const std::vector<std::string>& scenes) {
  std::vector<Aggregate> out;
  for (const soda::Stepping& st : swept_settings(64)) {
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
  charts::LineChart c;
  c.title = title;
  c.x_axis = {"run time per frame (s)", true};
  c.y_axis = {y_label, true};
  for (soda::Integrator in : soda::kIntegrators) {
    charts::LineSeries s;
    s.name = soda::integrator_name(in) + " (dt = 1 ... 1/" + std::to_string(std::min(64, swept_max_substeps(in))) + ")";
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
  return charts::render_line_chart(c);
}

/// True if `row` and every finer step of the same integrator on the same scene
/// are within `tolerance` (so the setting is not within it by luck of a sign
/// change in a converging error). Soda counts as Euler at one step per frame, and
/// euler/1 (identical to soda) is left out in favour of soda.
bool stays_within(const AccuracyRow& row, double tolerance, const AccuracyReport& r) {
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

bool stays_within(const AccuracyReport& r, const AccuracyRow& row, double tolerance) {
  return stays_within(row, tolerance, r);
}

std::string accuracy_markdown(const AccuracyReport& r, const std::string& command, std::vector<Aggregate>& classic,
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
    const AccuracyRow* soda_row = nullptr;
    const AccuracyRow* cheapest = nullptr;
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
  for (const soda::Stepping& st : swept_settings(64)) {
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

} // namespace

AccuracyFiles write_accuracy_files(const std::filesystem::path& out, const AccuracyReport& report,
                                   const std::string& command) {
  std::vector<Aggregate> classic = aggregate(report, "classic", report.walkers_among_classics);
  mark_pareto(classic, [](const Aggregate& a) { return a.worst_distance_error; });
  std::vector<Aggregate> walkers = aggregate(report, "walkers", {});
  mark_pareto(walkers, [](const Aggregate& a) { return 1.0 - a.kendall_tau_movers; });

  std::filesystem::create_directories(out);
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
  AccuracyFiles files;
  files.written = {"accuracy.csv", "accuracy_classics.svg", "accuracy_walkers.svg", "accuracy_walkers_all.svg"};
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
    files.written.push_back(file);
  }
  files.markdown = accuracy_markdown(report, command, classic, walkers);
  soda::write_file_atomically(out / "accuracy.md", files.markdown);
  files.written.push_back("accuracy.md");
  return files;
}

} // namespace sodaevo::bench
