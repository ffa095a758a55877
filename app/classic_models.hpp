// Classic creatures built into the binary (their XML is compiled in from models/
// by CMake), so a run report can show one next to the evolved creatures wherever
// the binary runs, without looking for the models/ folder.
#pragma once

#include <string_view>

namespace sodaevo::app {

/// models/dainty_walker.xml as it was when the binary was built.
std::string_view dainty_walker_xml();

} // namespace sodaevo::app
