#include "app/run_report.hpp"
#include "app/claims_chart.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/classic_models.hpp"
#include "app/designer_page.hpp"
#include "app/motion.hpp"
#include "app/player_html.hpp"
#include "evolve/runs/run_roles.hpp"
#include "evolve/problems/fitness_kind.hpp"
#include "charts/fixed_text.hpp"
#include "charts/svg_chart.hpp"
#include "core/input_error.hpp"
#include "core/number_text.hpp"
#include "evolve/problems/race_problem.hpp"
#include "evolve/runs/race_schedule.hpp"
#include "evolve/estimators/replica_estimator.hpp"
#include "evolve/config/run_config.hpp"
#include "evolve/store/run_sine.hpp"
#include "evolve/store/run_store.hpp"
#include "evolve/algorithms/variation.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"

namespace sodaevo::app {

using charts::fixed;
using charts::LineChart;
using charts::LineSeries;
using charts::render_line_chart;

namespace fs = std::filesystem;

namespace {

/// One row of generations.csv.
struct GenerationRow {
  int generation = 0;
  long long evaluations = 0;
  double best = 0, mean = 0, median = 0, worst = 0;
  int invalid = 0, diverged = 0;
  std::string best_id;
};

/// A statistic of generations.csv; empty (no creature was scored) reads as NaN,
/// which the table shows as a dash and the chart leaves out.
double csv_number(const std::string& text, const std::string& where) {
  if (text.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::optional<double> v = soda::parse_double(text);
  if (!v) throw soda::InputError(where + ": expected a number, got '" + text + "'");
  return *v;
}

long long csv_integer(const std::string& text, const std::string& where) {
  const std::optional<long long> v = soda::parse_integer(text);
  if (!v || *v < 0) throw soda::InputError(where + ": expected a count, got '" + text + "'");
  return *v;
}

std::vector<GenerationRow> read_generations_csv(const fs::path& path) {
  if (!fs::exists(path)) throw soda::InputError(path.string() + ": missing: not a sodaevo run folder?");
  std::istringstream in(soda::read_whole_file(path));
  std::string line;
  std::vector<GenerationRow> rows;
  long line_number = 0;
  static const char* kColumns[] = {"generation", "evaluations", "best", "mean", "median", "worst", "invalid", "diverged", "best_id"};
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    const std::string where = path.string() + ":" + std::to_string(line_number);
    if (line_number == 1) {
      if (cells.size() < 9 || cells[0] != "generation") throw soda::InputError(where + ": expected the header 'generation,evaluations,best,...'");
      continue;
    }
    // 9 columns, 13 since runs log the best creature's replicas (ignored here).
    if (cells.size() != 9 && cells.size() != 13) {
      throw soda::InputError(where + ": expected 9 or 13 columns, got " + std::to_string(cells.size()));
    }
    GenerationRow r;
    auto at = [&](int i) { return where + " (" + kColumns[i] + ")"; };
    r.generation = static_cast<int>(csv_integer(cells[0], at(0)));
    r.evaluations = csv_integer(cells[1], at(1));
    r.best = csv_number(cells[2], at(2));
    r.mean = csv_number(cells[3], at(3));
    r.median = csv_number(cells[4], at(4));
    r.worst = csv_number(cells[5], at(5));
    r.invalid = static_cast<int>(csv_integer(cells[6], at(6)));
    r.diverged = static_cast<int>(csv_integer(cells[7], at(7)));
    r.best_id = cells[8];
    rows.push_back(r);
  }
  return rows;
}

/// A table or caption number; none (NaN: no creature scored) shows as a dash.
std::string table_number(double v, int digits) { return std::isfinite(v) ? fixed(v, digits) : "&#8211;"; }


/// "TerrainFlat, TerrainHilly" for the run's race files; a curriculum's stages
/// joined by "then".
std::string terrain_names(const RaceFitnessConfig& race) {
  std::string out;
  for (const std::string& t : race.terrains) out += (out.empty() ? "" : ", ") + fs::path(t).stem().string();
  for (const CurriculumStage& s : race.curriculum) {
    out += (out.empty() ? "" : " then ") + fs::path(s.terrain).stem().string();
  }
  return out;
}

/// A creature to animate: a prepared model, scored as in the run.
struct Shown {
  std::string caption;
  soda::ModelDef prepared;
};

void config_table(std::ostringstream& o, const RunConfig& c, const nlohmann::json& manifest, const RunSine& sine) {
  auto row = [&](const std::string& k, const std::string& v) {
    o << "<tr><th>" << html_escape(k) << "</th><td>" << html_escape(v) << "</td></tr>\n";
  };
  using soda::format_double_plain;
  o << "<table class=\"config\">\n";
  row("name", c.name);
  row("seed", std::to_string(c.seed));
  if (manifest.contains("started") && manifest["started"].is_string()) row("started", manifest["started"].get<std::string>());
  if (manifest.contains("command") && manifest["command"].is_string()) row("command", manifest["command"].get<std::string>());
  row("muscle sine", sine.summary());
  row("generations", std::to_string(c.budget.generations));
  row("population", std::to_string(c.population.size) + " (random fraction " + format_double_plain(c.population.random_fraction) + ")");
  std::string seeds;
  for (const std::string& s : c.population.seed_models) seeds += (seeds.empty() ? "" : ", ") + fs::path(s).filename().string();
  row("seed models", seeds.empty() ? "none" : seeds);
  row("selection", "tournament of " + std::to_string(c.selection.tournament_size) + ", " + std::to_string(c.selection.elites) + " elites");
  row("crossover rate", format_double_plain(c.crossover_rate));
  if (c.fitness.kind == FitnessKind::Race) {
    const RaceFitnessConfig& r = c.fitness.race;
    row("fitness", "race: frames to the finish on " + terrain_names(r) +
                       (r.terrains.size() > 1 ? " (the " + race_combine_name(r.combine) + ")" : std::string()) +
                       ", fewer is better (fitness = minus frames); timeout " +
                       (r.timeout > 0 ? std::to_string(r.timeout) + " frames" : std::string("of each race file")) +
                       "; raced as the original racer races a contender (2004 bar rule)");
  } else {
    row("fitness", "centroid x moved " + direction_name(c.fitness.direction) + " in " + std::to_string(c.fitness.frames) +
                       " frames after " + std::to_string(c.fitness.settle_frames) + " settle frames; scaling " +
                       scaling_name(c.fitness.scaling) + "; dropped from " + format_double_plain(c.fitness.drop_height) + " px");
  }
  row("world", "gravity " + format_double_plain(c.world.gravity) + " " + gravity_direction_name(c.world.gravity_direction) +
                   ", friction " + format_double_plain(c.world.friction) + ", springyness " + format_double_plain(c.world.springyness) +
                   ", surface friction " + format_double_plain(c.world.surface_friction) + ", reflection " +
                   format_double_plain(c.world.surface_reflection));
  std::string evolves;
  for (const std::string& s : c.world.evolve) evolves += (evolves.empty() ? "" : ", ") + s;
  row("creatures choose", evolves.empty() ? "nothing (fixed world)" : evolves);
  row("limits", std::to_string(c.limits.min_masses) + "-" + std::to_string(c.limits.max_masses) + " masses, up to " +
                    std::to_string(c.limits.max_links) + " links");
  o << "</table>\n";
}

/// "3, 5-9" for {9, 3, 5, 6, 7, 8}.
std::string generation_ranges(std::vector<int> g) {
  std::sort(g.begin(), g.end());
  std::string out;
  for (std::size_t i = 0; i < g.size();) {
    std::size_t j = i;
    while (j + 1 < g.size() && g[j + 1] == g[j] + 1) ++j;
    // Counted from 1, as the CLI and the page count (the ids and files from 0).
    out += (out.empty() ? "" : ", ") + std::to_string(g[i] + 1) + (j > i ? "&#8211;" + std::to_string(g[j] + 1) : "");
    i = j + 1;
  }
  return out;
}

/// The players of a walk run: each the fitness trial in the run's physics mode.
void walk_players(std::ostringstream& o, const RunConfig& config, const std::vector<Shown>& shown,
                  const std::string& classic_note, const ReportOptions& options) {
  const soda::Stepping stepping = config.fitness.stepping();
  const long long trial_frames = config.fitness.settle_frames + config.fitness.frames;
  o << "<p class=\"note\">Each animation is the fitness trial, simulated again by the engine ("
    << html_escape(stepping == soda::Stepping{} ? std::string("soda mode, as the original")
                                        : "the run's physics mode: " + soda::stepping_label(stepping))
    << "): " << config.fitness.settle_frames << " settle frames, then " << config.fitness.frames
    << " scored frames (the dashed mark under the floor shows where scoring starts). Masses blue, springs grey, muscles red (dark and "
       "thick when contracted); marks on the floor are px from the start. Add <code>#frame=N</code> to the address to "
       "stop every player at frame N.</p>\n"
    << classic_note;
  const int every = sample_interval(trial_frames, options.max_samples);
  int index = 0;
  for (const Shown& s : shown) {
    try {
      const Motion motion = record_motion(s.prepared, trial_frames, every, stepping);
      o << player_element(motion, {"player" + std::to_string(index++), s.caption, config.fitness.settle_frames, 640, 280});
    } catch (const soda::InputError& e) {
      o << "<p class=\"note\">" << html_escape(s.caption) << ": " << html_escape(e.what()) << "</p>\n";
    }
  }
}

/// The players of a race run: each creature's race on the run's first terrain,
/// with the terrain, the start and the finish.
void race_players(std::ostringstream& o, const Problem& problem, const std::vector<Shown>& shown,
                  const std::string& classic_note, const ReportOptions& options) {
  const auto* race = dynamic_cast<const RaceProblem*>(&problem);
  if (race == nullptr) return;
  const RaceTerrain& terrain = race->terrains().front();
  o << "<p class=\"note\">Each animation is the creature's race on " << html_escape(fs::path(terrain.file).stem().string())
    << ", raced again as the original racer races it (2004 bar rule) to the finish or the timeout ("
    << race->timeout_of(0) << " frames). Fixed bars are the terrain; the lines are the start and the finish. Masses "
       "blue, springs grey, muscles red. Add <code>#frame=N</code> to the address to stop every player at frame N.</p>\n"
    << classic_note;
  int index = 0;
  for (const Shown& s : shown) {
    try {
      const Motion motion = record_race_motion(terrain.race, race->timeout_of(0), s.prepared, s.caption, options.max_samples);
      o << player_element(motion, {"player" + std::to_string(index++), s.caption, -1, 640, 280});
    } catch (const std::exception& e) {
      o << "<p class=\"note\">" << html_escape(s.caption) << ": " << html_escape(e.what()) << "</p>\n";
    }
  }
}

constexpr const char* kRunPageStyle = R"css(
body { font-family: Helvetica, Arial, sans-serif; margin: 20px auto; max-width: 1560px; color: #222; padding: 0 16px; }
h1 { margin-bottom: 4px; } h2 { margin-top: 28px; border-bottom: 1px solid #ddd; padding-bottom: 4px; }
table { border-collapse: collapse; font-size: 14px; }
th, td { padding: 3px 10px; border-bottom: 1px solid #eee; text-align: left; vertical-align: top; }
table.best td.n { text-align: right; font-variant-numeric: tabular-nums; }
table.config th { color: #555; font-weight: normal; white-space: nowrap; }
.charts svg { max-width: 100%; height: auto; margin-right: 12px; }
.note { color: #555; font-size: 14px; }
tr.classic td { color: #7a4b00; }
.sine-note { background: #fff4d6; border: 1px solid #e0b040; padding: 8px 12px; font-size: 14px; }
)css";

} // namespace

fs::path default_report_path(const fs::path& run_dir) { return run_dir / "report.html"; }

std::string report_sine_note(const fs::path& run_dir) {
  if (std::error_code ec; !fs::is_directory(run_dir, ec)) return {}; // the report's own error says what is wrong
  const std::string note = run_sine_note(read_run_sine(run_dir));
  if (note.empty()) return {};
  return note + ". What the report simulates again (animations, distances, speeds, races run again, the Dainty "
                "Walker) is this engine's; the logged fitnesses are the run's own";
}

std::string run_report_html(const fs::path& run_dir, const ReportOptions& options) {
  if (!fs::is_directory(run_dir)) throw soda::InputError(run_dir.string() + ": no such run folder");
  const RunConfig config = read_run_config(run_dir / "config.json");
  const ReplicaEstimator estimator(replica_plan(config)); // the run's estimator (its problem is `scored`)
  // What the table and the players race: a curriculum's last saved stage.
  const std::unique_ptr<Problem> scored = final_problem(run_dir, config);
  nlohmann::json manifest = nlohmann::json::object();
  if (fs::exists(run_dir / "manifest.json")) {
    try {
      manifest = nlohmann::json::parse(soda::read_whole_file(run_dir / "manifest.json"));
    } catch (const nlohmann::json::exception& e) {
      throw soda::InputError((run_dir / "manifest.json").string() + ": not valid JSON: " + e.what());
    }
  }
  const std::vector<GenerationRow> rows = read_generations_csv(run_dir / "generations.csv");
  const FitnessKindInfo& score = fitness_kind_info(config.fitness.kind);
  const bool race = config.fitness.kind == FitnessKind::Race; // a race is shown racing, with its terrains
  const RunSine sine = read_run_sine(run_dir);
  const std::string sine_note = report_sine_note(run_dir);

  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>sodaevo run " << html_escape(config.name)
    << "</title>\n<style>" << kRunPageStyle << "</style>\n" << player_head() << "</head>\n<body>\n"
    << "<pre id=\"page-errors\" hidden></pre>\n"
    << "<h1>Run <code>" << html_escape(config.name) << "</code></h1>\n<p class=\"note\">" << html_escape(run_dir.string()) << " &#183; ";
  if (rows.empty()) {
    o << "no generation finished yet";
  } else {
    o << rows.size() << " of " << config.budget.generations << " generations, " << rows.back().evaluations
      << " evaluations";
  }
  o << " &#183; report written by sodaevo 0.1.0</p>\n";
  if (!sine_note.empty()) o << "<p class=\"sine-note\">Made with another sine: " << html_escape(sine_note) << ".</p>\n";

  o << "<h2>Config</h2>\n";
  config_table(o, config, manifest, sine);

  // Fitness over generations.
  o << "<h2>Fitness over generations</h2>\n";
  int invalid_total = 0, diverged_total = 0;
  for (const GenerationRow& r : rows) invalid_total += r.invalid, diverged_total += r.diverged;
  if (!rows.empty()) {
    LineChart fitness;
    fitness.title = race ? "Race result: frames to the finish on " + terrain_names(config.fitness.race) +
                                     " (fewer is better)"
                               : "Fitness: centroid distance " + direction_name(config.fitness.direction) + " in " +
                                     std::to_string(config.fitness.frames) + " frames";
    fitness.x_axis.label = "generation";
    fitness.x_axis.integer = true;
    fitness.y_axis = {race ? "frames (fewer is better)" : "fitness (px)"};
    auto named = [](const char* name) {
      LineSeries s;
      s.name = name;
      return s;
    };
    LineSeries best = named("best"), mean = named("mean"), median = named("median");
    LineSeries invalid = named("invalid"), diverged = named("diverged");
    const bool markers = rows.size() <= 60;
    best.markers = mean.markers = median.markers = invalid.markers = diverged.markers = markers;
    median.dashed = true;
    for (const GenerationRow& r : rows) {
      const double g = r.generation + 1; // counted from 1, as the CLI and the page count
      best.x.push_back(g), best.y.push_back(score.shown(r.best));
      mean.x.push_back(g), mean.y.push_back(score.shown(r.mean));
      median.x.push_back(g), median.y.push_back(score.shown(r.median));
      invalid.x.push_back(g), invalid.y.push_back(r.invalid);
      diverged.x.push_back(g), diverged.y.push_back(r.diverged);
    }
    fitness.series = {best, mean, median};
    LineChart failures;
    failures.title = "Creatures that could not be scored, per generation";
    failures.x_axis.label = "generation";
    failures.x_axis.integer = true;
    failures.y_axis.label = "creatures";
    failures.y_axis.integer = true;
    failures.y_axis.min = 0.0;
    failures.series = {invalid, diverged};
    failures.width = 560;
    auto inline_svg = [](std::string svg) { // drop the XML declaration inside HTML
      if (svg.rfind("<?xml", 0) == 0) svg.erase(0, svg.find('\n') + 1);
      return svg;
    };
    o << "<div class=\"charts\">\n" << inline_svg(render_line_chart(fitness)) << inline_svg(render_line_chart(failures)) << "</div>\n";
  }
  o << "<p class=\"note\">Invalid creatures (could not be built or prepared): " << invalid_total
    << "; diverged (non-finite state): " << diverged_total << "; over all generations.</p>\n";

  // Best creatures: the best of each generation, best first, each creature once
  // (elites are copied into later generations under new ids); read from best/.
  auto best_file = [&](int generation) { return run_dir / "best" / generation_file_name(generation); };
  auto body = [](soda::ModelDef def) { // the creature without its name and score comment
    def.name.clear();
    def.comment.clear();
    return def;
  };
  struct Ranked {
    GenerationRow row;       ///< where it was first the best
    soda::ModelDef prepared; ///< best/ file as read
    std::string problem;     ///< why best/ could not be read
    std::vector<int> generations; ///< every generation it was the best of
  };
  std::vector<Ranked> ranked;
  {
    std::vector<GenerationRow> by_fitness = rows;
    std::stable_sort(by_fitness.begin(), by_fitness.end(), [](const GenerationRow& a, const GenerationRow& b) { return a.best > b.best; });
    for (const GenerationRow& r : by_fitness) {
      if (r.best_id.empty() || !std::isfinite(r.best)) continue;
      // Once the table is full, only copies of listed creatures (same fitness) matter.
      const bool full = static_cast<int>(ranked.size()) >= options.table_rows;
      if (full && r.best < ranked.back().row.best) break;
      Ranked k{r, {}, {}, {r.generation}};
      try {
        k.prepared = soda::read_model_file(best_file(r.generation)).def;
      } catch (const soda::InputError& e) {
        k.problem = e.what();
      }
      const auto same = std::find_if(ranked.begin(), ranked.end(), [&](const Ranked& q) {
        return q.row.best_id == r.best_id || (k.problem.empty() && q.problem.empty() && body(q.prepared) == body(k.prepared));
      });
      if (same != ranked.end()) same->generations.push_back(r.generation);
      else if (!full) ranked.push_back(std::move(k));
    }
  }
  std::vector<Shown> shown;

  // The classic, prepared and scored exactly like every creature of the run.
  std::optional<Shown> classic;
  std::optional<Evaluation> classic_evaluation;
  std::string classic_problem;
  try {
    const soda::ModelDef dainty = soda::read_model_text(dainty_walker_xml(), "built-in models/dainty_walker.xml").def;
    const soda::ModelDef creature = creature_from_seed(dainty, config);
    classic_evaluation = estimator.estimate(*scored, {&creature}).front();
    if (classic_evaluation->status == EvaluationStatus::Invalid) {
      classic_problem = classic_evaluation->reason;
    } else {
      soda::ModelDef prepared = scored->prepare(creature);
      prepared.name = "Dainty Walker (classic, same fitness settings)";
      classic = Shown{prepared.name, prepared};
    }
  } catch (const soda::InputError& e) {
    classic_problem = e.what();
  }

  o << "<h2>Best creatures</h2>\n"
    << "<p class=\"note\">Each generation's best, ranked by the fitness it scored in its own generation. The champion "
       "(what <code>sodaevo evolve</code> prints and the designer's Evolve mode exports) is the best of the last "
       "generation: an earlier creature can rank above it on a luckier score. Generations are counted from 1 here; "
       "ids (g9-1) and file names (gen_00009.xml) count from 0.</p>\n";
  if (ranked.empty()) {
    o << "<p class=\"note\">No creature has been scored yet.</p>\n";
  } else {
    // One click opens a creature in the designer (RUN/designer.html, written with the report).
    const auto designer_link = [](const std::string& xml) {
      if (!designer_available() || xml.empty()) return std::string();
      return " &middot; <a href=\"designer.html#" + designer_model_fragment(xml) + "\">open in the designer</a>";
    };
    const auto file_text = [](const fs::path& p) {
      try {
        return soda::read_whole_file(p);
      } catch (const std::exception&) {
        return std::string();
      }
    };
    o << "<table class=\"best\">\n<tr><th>#</th><th>creature</th><th>best of generations</th>"
      << (race ? "<th>race result (frames, fewer is better)</th><th>raced again (frames)</th>"
                     : "<th>fitness (px)</th><th>distance (px)</th><th>speed (px/frame)</th>")
      << "<th>file</th></tr>\n";
    int rank = 0;
    for (const Ranked& k : ranked) {
      const GenerationRow& r = k.row;
      ++rank;
      std::string distance = html_escape(k.problem), speed;
      if (k.problem.empty()) {
        const Evaluation e = scored->rollouts({&k.prepared}).front();
        if (e.ok()) distance = table_number(e.distance, 1), speed = table_number(e.px_per_frame, 3);
        else distance = html_escape(e.reason);
      }
      o << "<tr><td class=\"n\">" << rank << "</td><td>" << html_escape(r.best_id) << "</td><td class=\"n\">" << generation_ranges(k.generations)
        << "</td><td class=\"n\">" << table_number(score.shown(r.best), 1) << "</td><td class=\"n\">" << distance << "</td>"
        << (race ? "" : "<td class=\"n\">" + speed + "</td>") << "<td><a href=\"best/" << generation_file_name(r.generation) << "\">best/"
        << generation_file_name(r.generation) << "</a>" << designer_link(file_text(best_file(r.generation))) << "</td></tr>\n";
    }
    if (classic_evaluation && classic_evaluation->ok()) {
      o << "<tr class=\"classic\"><td></td><td>Dainty Walker (classic)</td><td></td><td class=\"n\">"
        << table_number(score.shown(classic_evaluation->fitness), 1) << "</td><td class=\"n\">"
        << table_number(classic_evaluation->distance, 1) << "</td>"
        << (race ? "" : "<td class=\"n\">" + table_number(classic_evaluation->px_per_frame, 3) + "</td>") << "<td>built in"
        << designer_link(std::string(dainty_walker_xml())) << "</td></tr>\n";
    }
    o << "</table>\n";
  }

  o << claims_section_html(run_dir);

  // Animations: the champion, the best of a few generations along the run (each
  // creature once), the classic. The champion is the best of the last generation, as `sodaevo evolve` prints it
  // and Evolve mode exports it; the table's first row, the highest fitness any
  // generation scored, is shown as the top score when it is another creature.
  const auto fitness_text = [&](double v) {
    return (race ? std::string() : std::string("fitness ")) + table_number(score.shown(v), 1) + " " + score.unit;
  };
  const std::string of_planned = " of " + std::to_string(config.budget.generations);
  if (!ranked.empty() && !rows.back().best_id.empty()) {
    const GenerationRow& last_row = rows.back();
    try {
      shown.push_back({"Champion " + last_row.best_id + " (best of the last generation, " + std::to_string(last_row.generation + 1) +
                           of_planned + ": " + fitness_text(last_row.best) + ")",
                       soda::read_model_file(best_file(last_row.generation)).def});
    } catch (const soda::InputError& e) {
      o << "<p class=\"note\">" << html_escape(e.what()) << "</p>\n";
    }
  }
  if (!ranked.empty() && ranked.front().problem.empty()) {
    const GenerationRow& top = ranked.front().row;
    const bool seen = std::any_of(shown.begin(), shown.end(), [&](const Shown& s) { return body(s.prepared) == body(ranked.front().prepared); });
    if (!seen) {
      shown.push_back({"Top score " + top.best_id + " (best of generation " + std::to_string(top.generation + 1) + of_planned + ": " +
                           fitness_text(top.best) + ", the highest any generation scored)",
                       ranked.front().prepared});
    }
    const int last = rows.back().generation, first = rows.front().generation;
    const int k = std::max(1, options.chosen_generations);
    for (int i = 0; i < k; ++i) {
      const int g = k == 1 ? first : first + static_cast<int>(std::lround(static_cast<double>(i) * (last - first) / (k - 1)));
      const auto row = std::find_if(rows.begin(), rows.end(), [&](const GenerationRow& r) { return r.generation == g; });
      if (row == rows.end() || row->best_id.empty()) continue;
      try {
        const soda::ModelDef def = soda::read_model_file(best_file(g)).def;
        const bool seen = std::any_of(shown.begin(), shown.end(), [&](const Shown& s) { return body(s.prepared) == body(def); });
        if (seen) continue;
        shown.push_back({"Generation " + std::to_string(g + 1) + of_planned + ": " + row->best_id + " (its best, " + fitness_text(row->best) + ")",
                          def});
      } catch (const soda::InputError& e) {
        o << "<p class=\"note\">" << html_escape(e.what()) << "</p>\n";
      }
    }
  }
  if (classic) shown.push_back(*classic);
  if (!classic_problem.empty()) classic_problem = "<p class=\"note\">Dainty Walker not shown: " + html_escape(classic_problem) + "</p>\n";
  o << "<h2>Watch them</h2>\n";
  if (race) race_players(o, *scored, shown, classic_problem, options);
  else walk_players(o, config, shown, classic_problem, options);
  o << player_script() << "</body>\n</html>\n";
  return o.str();
}

void write_run_report(const fs::path& run_dir, const fs::path& out, const ReportOptions& options) {
  soda::write_file_atomically(out, run_report_html(run_dir, options));
  // The page the report's "open in the designer" links open, beside it.
  if (designer_available()) {
    const fs::path page = out.parent_path() / "designer.html";
    const std::string text = designer_page();
    if (!fs::exists(page) || soda::read_whole_file(page) != text) soda::write_file_atomically(page, text);
  }
}

} // namespace sodaevo::app
