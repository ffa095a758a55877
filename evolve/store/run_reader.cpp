#include "run_reader.hpp"

#include <algorithm>
#include <cstdlib>

#include "core/input_error.hpp"
#include "evolve/store/run_store.hpp"
#include "formats/atomic_file.hpp"

namespace sodaevo {

namespace fs = std::filesystem;

std::vector<int> saved_generations(const fs::path& run_dir) {
  std::vector<int> out;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(run_dir / "generations", ec)) {
    const std::string name = e.path().filename().string();
    if (name.size() == 13 && name.rfind("gen_", 0) == 0 && name.substr(9) == ".xml") {
      out.push_back(std::atoi(name.substr(4, 5).c_str()));
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

Generation read_saved_generation(const fs::path& run_dir, int generation) {
  const fs::path path = run_dir / "generations" / generation_file_name(generation);
  if (!fs::exists(path)) {
    std::string available;
    for (int g : saved_generations(run_dir)) available += (available.empty() ? "" : ", ") + std::to_string(g);
    throw soda::InputError(path.string() + ": generation " + std::to_string(generation) +
                           " was not saved; saved generations: " + (available.empty() ? "none" : available));
  }
  return generation_from_xml(soda::read_whole_file(path), path.string());
}

std::vector<Individual> best_individuals(const fs::path& run_dir, int count) {
  const std::vector<int> saved = saved_generations(run_dir);
  if (saved.empty()) throw soda::InputError(run_dir.string() + ": no saved generation (generations/gen_NNNNN.xml)");
  std::vector<Individual> all;
  for (Individual& ind : read_saved_generation(run_dir, saved.back()).individuals) {
    if (ind.evaluation.ok()) all.push_back(std::move(ind));
  }
  if (all.empty()) {
    throw soda::InputError(run_dir.string() + ": generation " + std::to_string(saved.back()) +
                           " (the last saved) has no valid creature");
  }
  std::stable_sort(all.begin(), all.end(), [](const Individual& a, const Individual& b) {
    return a.evaluation.fitness > b.evaluation.fitness;
  });
  std::vector<Individual> best;
  for (Individual& ind : all) {
    if (static_cast<int>(best.size()) >= count) break;
    const bool seen = std::any_of(best.begin(), best.end(), [&](const Individual& b) { return b.creature == ind.creature; });
    if (!seen) best.push_back(std::move(ind));
  }
  return best;
}

} // namespace sodaevo
