#include "bench/accuracy_report.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include "charts/svg_chart.hpp"
#include "core/number_text.hpp"
#include "formats/atomic_file.hpp"

namespace sodaevo::bench {

namespace {

std::string num(double v) { return soda::format_printf("%.6g", v); }
std::string pct(double share) { return soda::format_printf("%.3g %%", 100.0 * share); }
std::string signed_pct(double share) { return soda::format_printf("%+.3g %%", 100.0 * share); }
/// A relative error with its 95 % interval: "+2.1 % [+0.4, +3.8]".
std::string pct_interval(double point, double low, double high) {
  return signed_pct(point) + soda::format_printf(" [%+.3g", 100.0 * low) + soda::format_printf(", %+.3g]", 100.0 * high);
}

std::string slug(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? static_cast<char>(std::tolower(c)) : '_';
  return out;
}

std::string accuracy_csv(const AccuracyReport& r) {
  std::ostringstream o;
  o << "section,scene,setting,mode,integrator,substeps,dt,seconds_per_frame,position_error,distance,distance_se,"
       "reference_distance,reference_se,distance_error,error_low,error_high,exact_distance,exact_error,kendall_tau,"
       "kendall_tau_movers,kendall_tau_exact_movers,diverged,replicas\n";
  for (const auto& row : r.rows) {
    const bool soda = row.stepping.mode == soda::PhysicsMode::Soda;
    o << row.section << ',' << row.scene << ',' << soda::stepping_label(row.stepping) << ','
      << soda::mode_name(row.stepping.mode) << ',' << (soda ? "euler" : soda::integrator_name(row.stepping.integrator))
      << ',' << row.stepping.substeps << ',' << num(1.0 / row.stepping.substeps) << ',' << num(row.seconds_per_frame)
      << ',' << num(row.position_error) << ',' << num(row.distance) << ',' << num(row.distance_se) << ','
      << num(row.reference_distance) << ',' << num(row.reference_se) << ',' << num(row.distance_error) << ','
      << num(row.error_low) << ',' << num(row.error_high) << ',' << num(row.exact_distance) << ','
      << num(row.exact_error) << ',' << num(row.kendall_tau) << ',' << num(row.kendall_tau_movers) << ','
      << num(row.kendall_tau_exact_movers) << ',' << row.diverged << ',' << (row.section == "analytic" ? 1 : r.replicas)
      << '\n';
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
  double median_exact_error = 0.0;
  double worst_position_error = 0.0;
  double kendall_tau = 0.0;
  double kendall_tau_movers = 0.0;
  double kendall_tau_exact_movers = 0.0;
  int diverged = 0;
  bool pareto = false;
};

std::vector<Aggregate> aggregate(const AccuracyReport& r, const std::string& section,
                                 const std::vector<std::string>& scenes) {
  std::vector<Aggregate> out;
  for (const soda::Stepping& st : swept_settings(soda::kMaxSubsteps)) {
    Aggregate a;
    a.stepping = st;
    std::vector<double> errors, exact_errors;
    int n = 0;
    for (const auto& row : r.rows) {
      if (row.section != section || !(row.stepping == st)) continue;
      if (!scenes.empty() && std::find(scenes.begin(), scenes.end(), row.scene) == scenes.end()) continue;
      a.seconds_per_frame += row.seconds_per_frame;
      a.worst_distance_error = std::max(a.worst_distance_error, row.distance_error);
      a.worst_position_error = std::max(a.worst_position_error, row.position_error);
      a.kendall_tau = row.kendall_tau;
      a.kendall_tau_movers = row.kendall_tau_movers;
      a.kendall_tau_exact_movers = row.kendall_tau_exact_movers;
      a.diverged += row.diverged;
      errors.push_back(row.distance_error);
      exact_errors.push_back(row.exact_error);
      ++n;
    }
    if (n == 0) continue;
    a.seconds_per_frame /= n;
    std::sort(errors.begin(), errors.end());
    std::sort(exact_errors.begin(), exact_errors.end());
    a.median_distance_error = errors[errors.size() / 2];
    a.median_exact_error = exact_errors[exact_errors.size() / 2];
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
    int finest = 0;
    for (const Aggregate& a : points) {
      if (a.stepping.mode != soda::PhysicsMode::Continuous || a.stepping.integrator != in) continue;
      s.x.push_back(a.seconds_per_frame);
      s.y.push_back(std::max(error(a), 1e-16));
      finest = std::max(finest, a.stepping.substeps);
    }
    s.name = soda::integrator_name(in) + " (dt = 1 ... 1/" + std::to_string(finest) + ")";
    if (!s.x.empty()) c.series.push_back(s);
  }
  for (const Aggregate& a : points) {
    if (a.stepping.mode != soda::PhysicsMode::Soda) continue;
    c.series.push_back({"soda (original)", {a.seconds_per_frame}, {std::max(error(a), 1e-16)}, true, false});
  }
  return charts::render_line_chart(c);
}

/// True if `row`'s expected-distance error and that of every finer step of the
/// same integrator on the same creature are within `tolerance` (so the setting is
/// not within it by luck of a sign change in a converging error). Soda counts as
/// Euler at one step per frame, and euler/1 (identical to soda) is left out.
bool stays_within(const AccuracyReport& r, const AccuracyRow& row, double tolerance) {
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

/// The creatures' table: reference, what one update per frame costs, the cheapest
/// setting within 1 %.
void creature_table(std::ostringstream& o, const AccuracyReport& r, const std::string& section,
                    const std::vector<std::string>& walking) {
  o << "| creature | reference expected distance (px, +- 95 %) | its sd | reference at half step | soda expected "
       "distance (px) | soda error [95 %] | soda error, one rollout | cheapest within 1 % | its error [95 %] | x soda's time |\n";
  o << "|---|---:|---:|---:|---:|---:|---:|---|---:|---:|\n";
  for (const CreatureReference& ref : r.references) {
    if (ref.section != section || std::find(walking.begin(), walking.end(), ref.name) == walking.end()) continue;
    const AccuracyRow* soda_row = nullptr;
    const AccuracyRow* cheapest = nullptr;
    for (const auto& row : r.rows) {
      if (row.section != section || row.scene != ref.name) continue;
      if (row.stepping.mode == soda::PhysicsMode::Soda) soda_row = &row;
      if (stays_within(r, row, 0.01) && (!cheapest || row.seconds_per_frame < cheapest->seconds_per_frame)) {
        cheapest = &row;
      }
    }
    if (!soda_row) continue;
    o << "| " << ref.name << " | " << num(ref.distance) << " +- " << num(ref.half_width) << " | "
      << num(ref.sd) << " | " << pct_interval(ref.half_step_change, ref.half_step_low, ref.half_step_high) << " | "
      << num(soda_row->distance) << " | "
      << pct_interval((soda_row->distance - ref.distance) / std::max(std::fabs(ref.distance), 1.0),
                      soda_row->error_low, soda_row->error_high)
      << " | " << pct(soda_row->exact_error) << " | "
      << (cheapest ? soda::stepping_label(cheapest->stepping) : "none in the sweep") << " | "
      << (cheapest ? pct_interval((cheapest->distance - ref.distance) / std::max(std::fabs(ref.distance), 1.0),
                                  cheapest->error_low, cheapest->error_high)
                   : "-")
      << " | "
      << (cheapest && soda_row->seconds_per_frame > 0 ? num(cheapest->seconds_per_frame / soda_row->seconds_per_frame)
                                                      : "-")
      << " |\n";
  }
}

void setting_table(std::ostringstream& o, const std::vector<Aggregate>& rows) {
  o << "| setting | s/frame | median expected-distance error | worst expected-distance error | median error, one "
       "rollout | worst position error at frame 100 (px) | diverged replicas | Pareto |\n";
  o << "|---|---:|---:|---:|---:|---:|---:|:-:|\n";
  for (const Aggregate& a : rows) {
    o << "| " << soda::stepping_label(a.stepping) << " | " << num(a.seconds_per_frame) << " | "
      << pct(a.median_distance_error) << " | " << pct(a.worst_distance_error) << " | " << pct(a.median_exact_error)
      << " | " << num(a.worst_position_error) << " | " << a.diverged << " | " << (a.pareto ? "yes" : "") << " |\n";
  }
}

/// The cheapest setting within `tolerance` on every creature of `rows` (and at
/// every finer step of its integrator).
const Aggregate* cheapest_within_on_all(const std::vector<Aggregate>& rows, double tolerance) {
  const Aggregate* best = nullptr;
  for (const Aggregate& a : rows) {
    bool stays = a.worst_distance_error <= tolerance;
    for (const Aggregate& finer : rows) {
      if (finer.stepping.mode == a.stepping.mode && finer.stepping.integrator == a.stepping.integrator &&
          finer.stepping.substeps > a.stepping.substeps && finer.worst_distance_error > tolerance) {
        stays = false;
      }
    }
    if (stays && (!best || a.seconds_per_frame < best->seconds_per_frame)) best = &a;
  }
  return best;
}

std::string accuracy_markdown(const AccuracyReport& r, const std::string& command,
                              const std::vector<Aggregate>& classic, const std::vector<Aggregate>& champions,
                              const std::vector<Aggregate>& walkers) {
  std::ostringstream o;
  o << "Measured with `" << command << "`: run time is wall time per simulated frame on one thread (analytic\n"
    << "scenes: the fastest of 3 runs; creatures: the fastest replica; soda runs the plain reference step, a scalar\n"
    << "loop like the continuous stepper, so times compare methods). Errors against the closed form (analytic scenes)\n"
    << "or the reference, " << soda::stepping_label(r.reference) << ". A walker is chaotic, so creatures are measured\n"
    << "by their expected distance: the mean over " << r.replicas << " sine-jitter replicas (replica 0 exact, replica r\n"
    << "with seed r moving 0.2 % of muscle sines by one ulp), a setting's error is its expected distance minus the\n"
    << "reference's, relative, with a 95 % interval (Welch). \"One rollout\" is the old single-draw measure: replica 0\n"
    << "against the reference's replica 0.\n\n";
  o << "## What one update per frame costs: the classics\n\n";
  o << "Classics that walk (reference distance above 50 px; their own world, " << r.creature_frames
    << " frames after " << r.settle_frames << " settle frames).\n"
    << "\"Within 1 %\": the expected-distance error is at most 1 % at this and every finer step of its integrator; the\n"
    << "interval says whether " << r.replicas << " replicas resolve it.\n\n";
  creature_table(o, r, "classic", r.walkers_among_classics);
  if (!r.walkers_among_champions.empty()) {
    o << "\n## What one update per frame costs: the GA's own champions\n\n";
    o << "Champions of a GA run in soda mode (models/champions/README.md), measured as the classics.\n\n";
    creature_table(o, r, "champion", r.walkers_among_champions);
  }
  o << "\n## Every setting on the classics that walk\n\n";
  setting_table(o, classic);
  const Aggregate* all_within = cheapest_within_on_all(classic, 0.01);
  o << "\nCheapest setting within 1 % on every classic that walks (and at every finer step of its integrator): "
    << (all_within ? soda::stepping_label(all_within->stepping) + " (" + num(all_within->seconds_per_frame) + " s/frame)"
                   : std::string("none in the sweep"))
    << ".\n";
  if (!champions.empty()) {
    o << "\n## Every setting on the champions that walk\n\n";
    setting_table(o, champions);
    const Aggregate* champion_within = cheapest_within_on_all(champions, 0.01);
    o << "\nCheapest setting within 1 % on every champion that walks: "
      << (champion_within ? soda::stepping_label(champion_within->stepping) + " (" +
                                num(champion_within->seconds_per_frame) + " s/frame)"
                          : std::string("none in the sweep"))
      << ".\n";
  }
  o << "\n## Ranking of random walkers by expected distance\n\n";
  o << "Noise floor: the reference at half its sub-steps ranks the " << r.walkers_movers << " movers of "
    << r.walkers << " walkers (reference speed at least 0.1 px/frame) by expected distance with tau "
    << num(r.walkers_noise_floor_tau_movers) << " (" << num(r.walkers_noise_floor_tau) << " over all walkers); by one\n"
    << "rollout each, as before, with tau " << num(r.walkers_noise_floor_tau_exact_movers)
    << ". Two independent estimates of the same expected distances from " << r.replicas << " replicas would\n"
    << "agree with tau " << num(r.walkers_predicted_tau_movers) << " (from the reference's standard errors; median standard\n"
    << "error " << pct(r.walkers_median_relative_se) << " of the distance), from " << 4 * r.replicas << " replicas "
    << num(r.walkers_predicted_tau_movers_4r) << ", from " << 16 * r.replicas << " "
    << num(r.walkers_predicted_tau_movers_16r) << ".\n\n";
  o << "| setting | s/frame | tau, movers | tau, all walkers | tau, movers, one rollout | median expected-distance error "
       "(movers) | median error, one rollout | walkers with a diverged replica | Pareto (tau, movers) |\n";
  o << "|---|---:|---:|---:|---:|---:|---:|---:|:-:|\n";
  for (const Aggregate& a : walkers) {
    o << "| " << soda::stepping_label(a.stepping) << " | " << num(a.seconds_per_frame) << " | "
      << num(a.kendall_tau_movers) << " | " << num(a.kendall_tau) << " | " << num(a.kendall_tau_exact_movers) << " | "
      << pct(a.median_distance_error) << " | " << pct(a.median_exact_error) << " | " << a.diverged << " | "
      << (a.pareto ? "yes" : "") << " |\n";
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
  for (const soda::Stepping& st : swept_settings(soda::kMaxSubsteps)) {
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
  auto worst = [](const Aggregate& a) { return a.worst_distance_error; };
  std::vector<Aggregate> classic = aggregate(report, "classic", report.walkers_among_classics);
  mark_pareto(classic, worst);
  std::vector<Aggregate> champions;
  if (!report.walkers_among_champions.empty()) {
    champions = aggregate(report, "champion", report.walkers_among_champions);
    mark_pareto(champions, worst);
  }
  std::vector<Aggregate> walkers = aggregate(report, "walkers", {});
  mark_pareto(walkers, [](const Aggregate& a) { return 1.0 - a.kendall_tau_movers; });

  std::filesystem::create_directories(out);
  AccuracyFiles files;
  auto write = [&](const std::string& name, const std::string& text) {
    soda::write_file_atomically(out / name, text);
    files.written.push_back(name);
  };
  write("accuracy.csv", accuracy_csv(report));
  write("accuracy_classics.svg",
        work_precision_svg("Classics that walk: expected-distance error vs run time",
                           "worst relative error of the expected distance", classic,
                           [](const Aggregate& a) { return a.worst_distance_error; }));
  if (!champions.empty()) {
    write("accuracy_champions.svg",
          work_precision_svg("GA champions: expected-distance error vs run time",
                             "worst relative error of the expected distance", champions,
                             [](const Aggregate& a) { return a.worst_distance_error; }));
  }
  write("accuracy_walkers.svg", work_precision_svg("Random walkers that move: ranking by expected distance",
                                                   "1 - Kendall tau against the reference", walkers,
                                                   [](const Aggregate& a) { return 1.0 - a.kendall_tau_movers; }));
  write("accuracy_walkers_all.svg", work_precision_svg("All random walkers: ranking by expected distance",
                                                       "1 - Kendall tau against the reference", walkers,
                                                       [](const Aggregate& a) { return 1.0 - a.kendall_tau; }));
  std::vector<std::string> scenes;
  for (const auto& row : report.rows) {
    if (row.section == "analytic" && std::find(scenes.begin(), scenes.end(), row.scene) == scenes.end()) {
      scenes.push_back(row.scene);
    }
  }
  for (const std::string& scene : scenes) {
    const std::vector<Aggregate> pts = aggregate(report, "analytic", {scene});
    write("accuracy_" + slug(scene) + ".svg",
          work_precision_svg(scene + ": position error vs run time", "largest position error (px)", pts,
                             [](const Aggregate& a) { return a.worst_position_error; }));
  }
  files.markdown = accuracy_markdown(report, command, classic, champions, walkers);
  write("accuracy.md", files.markdown);
  return files;
}

} // namespace sodaevo::bench
