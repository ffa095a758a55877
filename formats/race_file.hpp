// Reading Sodarace race files (`<!DOCTYPE sodarace>`, docs/physics.md, "The race file") into a
// RaceDef
// (core/race_def.hpp).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/race_def.hpp"

namespace soda {

/// Reads race XML held in memory; `source_name` names it in messages. Throws
/// InputError naming file, line, column, element and attribute, expected and got, for:
/// another root, an unknown racer class or filter, no terrain (or no fixed node in
/// it), a terrain wider than the lane's container can be, a timeout that is not an
/// integer in [1, kMaxRaceTimeout], a constraint other than CONTENDER or RACER.
RaceDef read_race_text(std::string_view text, const std::string& source_name);
RaceDef read_race_file(const std::filesystem::path& path);
/// A race file's text, as read_race_file reads it (size limit, messages naming the path).
std::string read_race_file_text(const std::filesystem::path& path);

/// Whether the XML text's root element is <race> (cheap look at the text).
bool looks_like_race(std::string_view text);

} // namespace soda
