// What `sodaevo` with no arguments prints: a short "start here" with the three
// commands a newcomer wants first, instead of every option (`sodaevo --help`).
#pragma once

#include <string>

namespace sodaevo::app {

/// The text, with `program` (argv[0], as the user typed it) in each command.
std::string start_here_text(const std::string& program);

} // namespace sodaevo::app
