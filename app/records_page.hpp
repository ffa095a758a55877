// The record book's page (results/records/index.html): for every race file the
// record race played beside the best public contender's, in the race player
// (app/player_html.hpp), both started together so the gap shows.
#pragma once

#include <string>

#include "evolve/runs/record_book.hpp"

namespace sodaevo::app {

/// A path's file name ("race05.xml"): how the book names race files and racers.
std::string file_name_of(const std::string& path);

/// The whole page; each race sampled to at most `max_samples` frames.
std::string records_page(const RecordBook& book, int max_samples = 400);

} // namespace sodaevo::app
