// /population/seed_models of a run config: model file paths relative to the
// config's folder, a pattern in the file name ("../models/*.xml") expanding to
// every matching file sorted by name, so the resolved config (and the run) does
// not depend on the order a folder lists its files in.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "evolve/config/strict_json.hpp"

namespace sodaevo {

/// The absolute paths `value` names, or nullopt with every problem appended
/// (pointers "/population/seed_models/...").
std::optional<std::vector<std::string>> read_seed_model_paths(const nlohmann::json& value,
                                                              const std::filesystem::path& base_dir,
                                                              std::vector<ConfigProblem>& problems);

} // namespace sodaevo
