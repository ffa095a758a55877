#include "app/archive_report.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <utility>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "charts/fixed_text.hpp"
#include "app/motion.hpp"
#include "app/player_html.hpp"
#include "app/run_report.hpp"
#include "charts/svg_chart.hpp"
#include "formats/atomic_file.hpp"
#include "core/input_error.hpp"
#include "formats/model_file.hpp"
#include "core/number_text.hpp"
#include "evolve/problems/fitness_kind.hpp"
#include "evolve/problems/race_problem.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/runs/run_roles.hpp"

namespace sodaevo::app {

using charts::fixed;
using charts::format_tick;
using charts::LineChart;
using charts::LineSeries;
using charts::render_line_chart;

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kPageStyle = R"css(
body { font-family: sans-serif; margin: 1.5em; color: #222; }
.note { color: #666; font-size: 0.9em; }
.sine-note { background: #fff4d6; border: 1px solid #e0b040; padding: 8px 12px; font-size: 0.9em; }
.charts, .maps { display: flex; flex-wrap: wrap; gap: 12px; align-items: flex-start; }
.map { font-size: 12px; }
.map rect.cell { cursor: pointer; stroke: #fff; stroke-width: 0.5; }
.map rect.cell.chosen { stroke: #000; stroke-width: 2; }
.maps.single svg { width: 30em; height: auto; } /* one map shown: larger */
.legend { display: inline-block; width: 200px; height: 10px; vertical-align: middle;
          background: linear-gradient(to right, #440154, #3b528b, #21918c, #5ec962, #fde725); }
table.metrics td { padding: 2px 10px 2px 0; }
)css";

/// Viridis at five stops, linearly between them: t in [0, 1].
std::string colour(double t) {
  static const int stops[5][3] = {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * 4.0;
  const int i = std::min(3, static_cast<int>(t));
  const double f = t - i;
  char buf[8];
  int rgb[3];
  for (int c = 0; c < 3; ++c) rgb[c] = static_cast<int>(std::lround(stops[i][c] + f * (stops[i + 1][c] - stops[i][c])));
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
  return buf;
}

std::string esc(const std::string& s) { return html_escape(s); }

std::string inline_svg(std::string svg) {
  if (svg.rfind("<?xml", 0) == 0) svg.erase(0, svg.find('\n') + 1);
  return svg;
}

std::string number(double v) { return std::isfinite(v) ? fixed(v, 2) : std::string("-"); }

/// The qd.csv columns the charts show.
struct QdRows {
  std::vector<double> iteration, evaluations, coverage, qd_score;
};

QdRows read_qd_csv(const fs::path& path) {
  QdRows rows;
  std::istringstream in(soda::read_whole_file(path));
  std::string line;
  std::getline(in, line); // header
  int number_of_line = 1;
  while (std::getline(in, line)) {
    ++number_of_line;
    std::vector<double> v;
    std::stringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) {
      const std::optional<double> d = soda::parse_double(field);
      if (!d) throw soda::InputError(path.string() + ":" + std::to_string(number_of_line) + ": expected numbers, got '" + line + "'");
      v.push_back(*d);
    }
    if (v.size() < 5) throw soda::InputError(path.string() + ":" + std::to_string(number_of_line) + ": expected 10 columns");
    rows.iteration.push_back(v[0]);
    rows.evaluations.push_back(v[1]);
    rows.coverage.push_back(v[3]);
    rows.qd_score.push_back(v[4]);
  }
  return rows;
}

void charts(std::ostringstream& o, const QdRows& rows) {
  LineChart qd;
  qd.title = "QD-score over evaluations";
  qd.x_axis.label = "evaluations";
  qd.y_axis.label = "QD-score";
  qd.width = 560;
  qd.height = 340;
  LineSeries s{"QD-score", rows.evaluations, rows.qd_score, rows.iteration.size() <= 60, false};
  qd.series = {s};
  LineChart coverage = qd;
  coverage.title = "Coverage over evaluations";
  coverage.y_axis.label = "cells filled (%)";
  coverage.y_axis.min = 0.0;
  coverage.series = {{"coverage", rows.evaluations, rows.coverage, rows.iteration.size() <= 60, false}};
  o << "<div class=\"charts\">\n" << inline_svg(render_line_chart(qd)) << inline_svg(render_line_chart(coverage))
    << "</div>\n";
}

struct Axis {
  std::string name;
  int bins = 1;
  double lo = 0.0, hi = 1.0;
};

std::string bin_text(const Axis& a, int bin) {
  const double w = (a.hi - a.lo) / a.bins;
  return a.name + " " + format_tick(a.lo + bin * w) + "-" + format_tick(a.lo + (bin + 1) * w);
}

} // namespace

bool has_archive(const fs::path& run_dir) {
  std::error_code ec;
  return fs::exists(run_dir / "archive.json", ec);
}

fs::path default_archive_report_path(const fs::path& run_dir) { return run_dir / "archive.html"; }

std::string archive_report_html(const fs::path& run_dir, const ArchiveReportOptions& options) {
  const fs::path archive_path = run_dir / "archive.json";
  if (!has_archive(run_dir)) throw soda::InputError(archive_path.string() + ": missing: not a MAP-Elites run folder?");
  const RunConfig config = read_run_config(run_dir / "config.json");
  json archive;
  std::vector<Axis> axes;
  try {
    archive = json::parse(soda::read_whole_file(archive_path));
    for (const json& a : archive.at("axes")) {
      axes.push_back({a.at("descriptor").get<std::string>(), a.at("bins").get<int>(), a.at("range").at(0).get<double>(),
                      a.at("range").at(1).get<double>()});
    }
    if (axes.size() < 2 || axes.size() > 3) throw soda::InputError("expected 2 or 3 axes");
  } catch (const std::exception& e) {
    throw soda::InputError(archive_path.string() + ": not a readable archive: " + e.what());
  }
  // The corrected archive, when the run wrote it (evolve/runs/archive_check.hpp).
  json checked;
  std::map<long long, double> checked_fitness; // by cell
  const fs::path checked_path = run_dir / "archive_checked.json";
  if (fs::exists(checked_path)) {
    try {
      checked = json::parse(soda::read_whole_file(checked_path));
      for (const json& c : checked.at("cells")) {
        if (c.contains("checked_fitness")) checked_fitness[c.at("cell").get<long long>()] = c.at("checked_fitness").get<double>();
      }
    } catch (const std::exception& e) {
      throw soda::InputError(checked_path.string() + ": not a readable checked archive: " + e.what());
    }
  }
  const json& metrics = archive.at("metrics");
  const json& cells = archive.at("cells");
  const FitnessKindInfo& score = fitness_kind_info(config.fitness.kind);
  const bool race = config.fitness.kind == FitnessKind::Race; // its elites are shown racing
  const auto shown = [&score](double fitness) { return number(score.shown(fitness)); };
  const std::string unit = std::string(" ") + score.unit;
  const std::string score_name = score.score_name;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const json& c : cells) {
    lo = std::min(lo, c.at("fitness").at("mean").get<double>());
    hi = std::max(hi, c.at("fitness").at("mean").get<double>());
  }

  std::string sine_note = report_sine_note(run_dir);
  if (!sine_note.empty()) sine_note = "<p class=\"sine-note\">Made with another sine: " + esc(sine_note) + ".</p>\n";
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>sodaevo archive "
    << esc(config.name) << "</title>\n<style>" << kPageStyle << "</style>\n" << player_head() << "</head>\n<body>\n"
    << "<pre id=\"page-errors\" hidden></pre>\n"
    << "<h1>MAP-Elites archive <code>" << esc(config.name) << "</code></h1>\n<p class=\"note\">"
    << esc(run_dir.string()) << " &#183; iteration " << archive.at("iteration").get<int>() << "</p>\n"
    << sine_note
    << "<table class=\"metrics\"><tr><td>cells filled</td><td>" << metrics.at("filled").get<long long>() << " of "
    << metrics.at("cells").get<long long>() << " (" << fixed(100.0 * metrics.at("coverage").get<double>(), 1)
    << " %)</td></tr><tr><td>QD-score</td><td>" << number(metrics.at("qd_score").get<double>())
    << " (sum over elites of fitness - " << number(archive.at("qd_offset").get<double>())
    << ", terms below 0 as 0)</td></tr><tr><td>normalised QD-score</td><td>"
    << number(metrics.at("normalized_qd_score").get<double>()) << " (QD-score / cells)</td></tr><tr><td>best</td><td>"
    << shown(metrics.at("best").get<double>()) << unit << "</td></tr><tr><td>mean elite"
    << " " << score_name << "</td><td>" << shown(metrics.at("mean_fitness").get<double>()) << unit
    << "</td></tr></table>\n"
    << (race ? "<p class=\"note\">A race: fitness is minus the frames to the finish (fewer is better).</p>\n" : "");
  if (!checked.is_null()) {
    const json& m = checked.at("metrics").at("checked");
    o << "<p>Checked on " << checked.at("check_replicas").get<int>() << " fresh replicas (seeds never used in "
      << "selection; archive_checked.json): QD-score " << number(m.at("qd_score").get<double>()) << ", best "
      << shown(m.at("best").get<double>()) << unit << ", mean elite " << shown(m.at("mean_fitness").get<double>())
      << unit << "; the elites' estimates are better than their checks by "
      << number(checked.at("mean_winners_curse").get<double>()) << unit << " on average (the winner's curse).</p>\n";
  }
  if (fs::exists(run_dir / "qd.csv")) charts(o, read_qd_csv(run_dir / "qd.csv"));

  // The heat maps: axis 0 across, axis 1 up, one map per bin of axis 2 and one of
  // the best over axis 2; a selector shows them all or one.
  const Axis& ax = axes[0];
  const Axis& ay = axes[1];
  const int panels = axes.size() == 3 ? axes[2].bins : 1;
  constexpr int kSide = 14;
  o << "<h2>The archive</h2>\n<p class=\"note\">" << esc(ax.name) << " across, " << esc(ay.name) << " up"
    << (panels > 1 ? ", one map per bin of " + esc(axes[2].name) : std::string()) << "; colour: "
    << score_name << " " << shown(lo) << " <span class=\"legend\"></span> " << shown(hi) << unit
    << ". Click a cell to play its elite below.</p>\n";
  if (panels > 1) {
    o << "<p><label>" << esc(axes[2].name) << ": <select id=\"third\"><option value=\"all\">every bin (small "
      << "multiples)</option><option value=\"best\">the best over every " << esc(axes[2].name) << "</option>";
    for (int p = 0; p < panels; ++p) o << "<option value=\"" << p << "\">" << esc(bin_text(axes[2], p)) << "</option>";
    o << "</select></label></p>\n";
  }
  o << "<div class=\"maps\">\n";
  std::vector<std::ostringstream> maps(static_cast<std::size_t>(panels));
  std::map<std::pair<int, int>, std::pair<double, std::string>> best; // (x, y) -> the best over axis 2
  for (const json& c : cells) {
    const std::vector<int> bins = c.at("bins").get<std::vector<int>>();
    const double f = c.at("fitness").at("mean").get<double>();
    const std::string id = c.at("id").get<std::string>();
    std::ostringstream caption;
    caption << "cell " << c.at("cell").get<long long>() << ": " << id << ", " << score_name << " "
            << shown(f) << unit << " (n "
            << c.at("fitness").at("n").get<long long>() << ", sd " << number(c.at("fitness").at("sd").get<double>())
            << ")";
    if (const auto k = checked_fitness.find(c.at("cell").get<long long>()); k != checked_fitness.end()) {
      caption << ", checked " << shown(k->second) << unit;
    }
    const std::vector<double> d = c.at("descriptors").get<std::vector<double>>();
    for (std::size_t a = 0; a < axes.size() && a < d.size(); ++a) caption << ", " << axes[a].name << " " << number(d[a]);
    std::ostringstream rect;
    rect << "\" width=\"" << kSide << "\" height=\"" << kSide << "\" fill=\""
         << colour(hi > lo ? (f - lo) / (hi - lo) : 1.0) << "\" data-cell=\"" << c.at("cell").get<long long>()
         << "\" data-id=\"" << esc(id) << "\" data-caption=\"" << esc(caption.str()) << "\"><title>"
         << esc(caption.str()) << "</title></rect>\n";
    const std::string at = "<rect class=\"cell\" x=\"" + std::to_string(bins.at(0) * kSide) + "\" y=\"" +
                           std::to_string((ay.bins - 1 - bins.at(1)) * kSide);
    maps[static_cast<std::size_t>(panels > 1 ? bins.at(2) : 0)] << at << rect.str();
    auto& b = best[{bins.at(0), bins.at(1)}];
    if (b.second.empty() || f > b.first) b = {f, at + rect.str()};
  }
  auto panel = [&](const std::string& key, const std::string& title, const std::string& body) {
    o << "<div class=\"map\" data-panel=\"" << key << "\"" << (key == "best" ? " hidden" : "") << "><div>"
      << esc(title) << "</div><svg width=\"" << ax.bins * kSide << "\" height=\"" << ay.bins * kSide
      << "\" viewBox=\"0 0 " << ax.bins * kSide << " " << ay.bins * kSide << "\" style=\"background:#eee\">" << body
      << "</svg></div>\n";
  };
  for (int p = 0; p < panels; ++p) {
    panel(std::to_string(p), panels > 1 ? bin_text(axes[2], p) : std::string(), maps[static_cast<std::size_t>(p)].str());
  }
  if (panels > 1) {
    std::string body;
    for (const auto& [xy, b] : best) body += b.second;
    panel("best", "the best over every " + axes[2].name, body);
  }
  o << "</div>\n<h2>Elite</h2>\n<div id=\"player-slot\"><p class=\"note\">Click a cell.</p></div>\n";

  // Every elite's motion, and a player template the click fills in.
  // A race's elite races on the first terrain (to its finish or the timeout).
  const long long frames = config.fitness.settle_frames + config.fitness.frames;
  const int every = sample_interval(frames, options.max_samples);
  const std::unique_ptr<Problem> problem = race ? problem_of(config, 0) : nullptr;
  const auto* racing = dynamic_cast<const RaceProblem*>(problem.get());
  json motions = json::object();
  Motion example;
  for (const json& c : cells) {
    const fs::path file = run_dir / c.at("file").get<std::string>();
    const soda::ModelDef elite = soda::read_model_file(file).def;
    const Motion m = racing != nullptr ? record_race_motion(racing->terrains().front().race, racing->timeout_of(0),
                                                            elite, c.at("id").get<std::string>(), options.max_samples)
                                       : record_motion(elite, frames, every, config.fitness.stepping());
    motions[c.at("id").get<std::string>()] = json::parse(motion_json(m, race ? -1 : config.fitness.settle_frames));
    if (example.samples() == 0) example = m;
  }
  o << "<script type=\"application/json\" id=\"elite-motions\">" << script_safe(motions.dump()) << "</script>\n"
    << "<template id=\"player-template\">" << player_element(example, {"elite", "", race ? -1 : config.fitness.settle_frames, 720, 300})
    << "</template>\n"
    << player_script() << R"js(<script>
(function () {
  var code = document.currentScript.previousElementSibling.text;
  var motions = JSON.parse(document.getElementById('elite-motions').textContent);
  var chosen = null;
  function play(rect) {
    if (chosen) chosen.classList.remove('chosen');
    chosen = rect;
    rect.classList.add('chosen');
    var player = document.getElementById('player-template').content.cloneNode(true);
    player.querySelector('.caption').textContent = rect.getAttribute('data-caption');
    player.querySelector('script').textContent = JSON.stringify(motions[rect.getAttribute('data-id')]);
    var slot = document.getElementById('player-slot');
    slot.textContent = '';
    slot.appendChild(player);
    slot.setAttribute('data-id', rect.getAttribute('data-id'));
    var run = document.createElement('script');
    run.text = code; // starts the players of the page: the one just placed
    slot.appendChild(run);
  }
  var rects = document.querySelectorAll('rect.cell');
  for (var i = 0; i < rects.length; ++i) rects[i].addEventListener('click', function (e) { play(e.currentTarget); });
  var third = document.getElementById('third');
  function show(which) {
    var panels = document.querySelectorAll('.map[data-panel]');
    document.querySelector('.maps').classList.toggle('single', which !== 'all');
    for (var i = 0; i < panels.length; ++i) {
      var key = panels[i].getAttribute('data-panel');
      panels[i].hidden = which === 'all' ? key === 'best' : key !== which;
    }
  }
  var params = new URLSearchParams(location.hash.slice(1));
  if (third) {
    third.addEventListener('change', function () { show(third.value); });
    var wanted = params.get('third');
    if (wanted !== null && third.querySelector('option[value="' + wanted + '"]')) third.value = wanted;
    show(third.value);
  }
  var cell = params.get('cell');
  var target = null;
  if (cell !== null) {
    var same = document.querySelectorAll('rect.cell[data-cell="' + cell + '"]');
    for (var k = 0; k < same.length && !target; ++k) if (!same[k].closest('.map').hidden) target = same[k];
  }
  if (target) target.dispatchEvent(new MouseEvent('click', {bubbles: true}));
})();
</script>
</body>
</html>
)js";
  return o.str();
}

void write_archive_report(const fs::path& run_dir, const fs::path& out, const ArchiveReportOptions& options) {
  soda::write_file_atomically(out, archive_report_html(run_dir, options));
}

} // namespace sodaevo::app
