#include "app/records_page.hpp"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "app/motion.hpp"
#include "app/player_html.hpp"
#include "formats/race_file.hpp"

namespace sodaevo::app {

namespace {

/// One player of a race, or a line saying why there is none.
std::string player_of(const soda::RaceDef& race, int timeout, const RaceEntry& e, const std::string& id,
                      const std::string& role, int max_samples) {
  if (!e.no_result.empty()) return "<p>" + html_escape(role + ": no result (" + e.no_result + ")") + "</p>\n";
  const Motion motion = record_race_motion(race, timeout, e.model, e.name, max_samples);
  PlayerView view;
  view.id = id;
  view.caption = role + ": " + e.name + " (" + file_name_of(e.file) + "), " +
                 race_result_text(e.outcome) + (e.outcome.finished ? " frames" : "");
  view.width = 560;
  view.height = 260;
  return player_element(motion, view);
}

std::string percent(double share) {
  char text[16];
  std::snprintf(text, sizeof text, "%.0f %%", 100.0 * share);
  return text;
}

/// The README's table in short, each file linking to its races below: what a
/// reader looks for first.
std::string summary_table(const RecordBook& book) {
  std::ostringstream o;
  o << "<table class=\"summary\">\n<tr><th>race file</th><th>record</th><th>frames</th><th>replicas finishing</th>"
    << "<th>best public contender</th><th>its frames</th><th>ratio</th></tr>\n";
  for (const FileRecord& f : book.files) {
    const std::string name = file_name_of(f.race_file);
    o << "<tr><td><a href=\"#" << html_escape(name) << "\">" << html_escape(name) << "</a></td>";
    const RaceEntry* record = f.record >= 0 ? &f.candidates[static_cast<std::size_t>(f.record)] : nullptr;
    const RaceEntry* pub = f.best_public >= 0 ? &f.publics[static_cast<std::size_t>(f.best_public)] : nullptr;
    if (record != nullptr) {
      o << "<td>" << html_escape(file_name_of(record->file)) << "</td><td class=\"n\"><b>"
        << race_result_text(record->outcome) << "</b></td><td class=\"n\">" << percent(f.record_replicas.finished_share)
        << (f.qualified ? "" : " (not qualified)") << "</td>";
    } else {
      o << "<td colspan=\"3\">none of ours finishes</td>";
    }
    if (pub != nullptr) {
      o << "<td>" << html_escape(file_name_of(pub->file)) << "</td><td class=\"n\">"
        << race_result_text(pub->outcome) << "</td><td class=\"n\">";
      if (record != nullptr && pub->outcome.finished) {
        char ratio[32];
        std::snprintf(ratio, sizeof ratio, "%.3f", record->outcome.result / pub->outcome.result);
        o << ratio;
      } else {
        o << "-";
      }
      o << "</td>";
    } else {
      o << "<td colspan=\"3\">no public contender raced</td>";
    }
    o << "</tr>\n";
  }
  o << "</table>\n";
  if (book.generalist.candidate >= 0 && !book.files.empty()) {
    const auto k = static_cast<std::size_t>(book.generalist.candidate);
    o << "<p><b>The generalist</b>, "
      << html_escape(file_name_of(book.files.front().candidates[k].file)) << ", finishes "
      << book.generalist.files_finished << " of " << book.files.size() << " files: ";
    for (std::size_t i = 0; i < book.files.size(); ++i) {
      const RaceEntry& e = book.files[i].candidates[k];
      o << (i > 0 ? ", " : "") << html_escape(file_name_of(book.files[i].race_file)) << " "
        << (e.no_result.empty() ? race_result_text(e.outcome) : "no result");
    }
    o << " frames.</p>\n";
  }
  return o.str();
}

} // namespace

std::string file_name_of(const std::string& path) { return std::filesystem::path(path).filename().string(); }

std::string records_page(const RecordBook& book, int max_samples) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>The Sodarace record book</title>\n"
    << "<style>body { font-family: Helvetica, Arial, sans-serif; margin: 20px; color: #222; }\n"
    << ".pair { display: flex; flex-wrap: wrap; gap: 16px; }\n.pair .soda-player { max-width: 560px; }\n"
    << "h2 { margin-top: 28px; }\ntable.summary { border-collapse: collapse; font-size: 14px; }\n"
    << "table.summary th, table.summary td { border-bottom: 1px solid #ddd; padding: 3px 10px; text-align: left; }\n"
    << "table.summary td.n { text-align: right; font-variant-numeric: tabular-nums; }</style>\n"
    << player_head() << "</head>\n<body>\n<pre id=\"page-errors\" hidden></pre>\n"
    << "<h1>The Sodarace record book</h1>\n<p>Each race file's record race (left) beside the best public "
    << "contender's (right), raced exactly as the original racer races them (2004 bar rule). "
    << "Frames are the exact result; replicas finishing: the share of 16 jittered replicas (another machine's "
    << "sine) that finish. Intervals and how each record was found: <a href=\"README.md\">README.md</a>.</p>\n"
    << summary_table(book);
  for (std::size_t i = 0; i < book.files.size(); ++i) {
    const FileRecord& f = book.files[i];
    const std::string name = file_name_of(f.race_file);
    const soda::RaceDef race = soda::read_race_file(f.race_file);
    o << "<h2 id=\"" << html_escape(name) << "\">" << html_escape(name) << "</h2>\n<div class=\"pair\">\n";
    if (f.record >= 0) {
      o << player_of(race, f.timeout, f.candidates[static_cast<std::size_t>(f.record)], "record" + std::to_string(i),
                     "record", max_samples);
    } else {
      o << "<p>No racer of ours finishes this file yet.</p>\n";
    }
    if (f.best_public >= 0) {
      o << player_of(race, f.timeout, f.publics[static_cast<std::size_t>(f.best_public)], "public" + std::to_string(i),
                     "best public", max_samples);
    }
    o << "</div>\n";
  }
  o << player_script() << "</body>\n</html>\n";
  return o.str();
}

} // namespace sodaevo::app
