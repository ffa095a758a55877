#include "evolve/config/seed_model_paths.hpp"

#include <fnmatch.h>

#include <algorithm>
#include <system_error>

#include "evolve/config/input_limits.hpp"
#include "evolve/config/strict_json.hpp"

namespace sodaevo {

namespace fs = std::filesystem;
using nlohmann::json;

std::optional<std::vector<std::string>> read_seed_model_paths(const json& v, const fs::path& base_dir,
                                                              std::vector<ConfigProblem>& problems) {
  const std::string p = "/population/seed_models";
  const auto expected = [&](const std::string& pointer, const std::string& what, const json& got) {
    problems.push_back({pointer, "expected " + what + ", got " + show_json(got)});
  };
  if (!v.is_array()) {
    expected(p, "an array of model file paths", v);
    return std::nullopt;
  }
  if (v.size() > kMaxSeedModels) {
    problems.push_back({p, "expected at most " + std::to_string(kMaxSeedModels) + " model file paths, got " +
                               std::to_string(v.size())});
    return std::nullopt;
  }
  std::vector<std::string> models;
  bool all_ok = true;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::string pi = p + "/" + std::to_string(i);
    const json& item = v[i];
    if (!item.is_string() || item.get<std::string>().empty()) {
      expected(pi, "a model file path", item);
      all_ok = false;
      continue;
    }
    const fs::path given = fs::path(item.get<std::string>());
    std::error_code ec;
    fs::path resolved = fs::absolute(given.is_absolute() ? given : base_dir / given, ec);
    if (ec) resolved = base_dir / given;
    resolved = resolved.lexically_normal();
    const std::string pattern = resolved.filename().string();
    if (pattern.find_first_of("*?[") != std::string::npos) {
      std::vector<std::string> matches;
      for (const fs::directory_entry& e : fs::directory_iterator(resolved.parent_path(), ec)) {
        if (e.is_regular_file(ec) && ::fnmatch(pattern.c_str(), e.path().filename().c_str(), 0) == 0) {
          matches.push_back(e.path().string());
        }
      }
      std::sort(matches.begin(), matches.end());
      if (matches.empty()) {
        expected(pi, "a pattern matching at least one model file (looked in " + resolved.parent_path().string() + ")",
                 item);
        all_ok = false;
      }
      models.insert(models.end(), matches.begin(), matches.end());
      continue;
    }
    if (!fs::is_regular_file(resolved, ec)) {
      std::string what = "an existing model file";
      if (resolved.string() != item.get<std::string>()) what += " (looked for " + resolved.string() + ")";
      expected(pi, what, item);
      all_ok = false;
      continue;
    }
    models.push_back(resolved.string());
  }
  if (!all_ok) return std::nullopt;
  return models;
}

} // namespace sodaevo
