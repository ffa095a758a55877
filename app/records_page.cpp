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
  view.caption = role + ": " + e.name + " (" + std::filesystem::path(e.file).filename().string() + "), " +
                 race_result_text(e.outcome) + (e.outcome.finished ? " frames" : "");
  view.width = 560;
  view.height = 260;
  return player_element(motion, view);
}

} // namespace

std::string records_page(const RecordBook& book, int max_samples) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>The Sodarace record book</title>\n"
    << "<style>body { font-family: Helvetica, Arial, sans-serif; margin: 20px; color: #222; }\n"
    << ".pair { display: flex; flex-wrap: wrap; gap: 16px; }\n.pair .soda-player { max-width: 560px; }\n"
    << "h2 { margin-top: 28px; }</style>\n"
    << player_head() << "</head>\n<body>\n<pre id=\"page-errors\" hidden></pre>\n"
    << "<h1>The Sodarace record book</h1>\n<p>Each race file's record race (left) beside the best public "
    << "contender's (right), raced exactly as the original racer races them (2004 bar rule). "
    << "The table with replicas and how each record was found: README.md.</p>\n";
  for (std::size_t i = 0; i < book.files.size(); ++i) {
    const FileRecord& f = book.files[i];
    const std::string name = std::filesystem::path(f.race_file).filename().string();
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
