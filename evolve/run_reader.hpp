// Reading a finished (or interrupted) run back: its saved generations, for
// replay and export.
#pragma once

#include <filesystem>
#include <vector>

#include "evolve/population.hpp"

namespace sodaevo {

/// Generation numbers saved whole in the run folder, ascending.
std::vector<int> saved_generations(const std::filesystem::path& run_dir);

/// Reads generations/gen_NNNNN.xml. Throws InputError (naming the file and the
/// generations that are available) if it was not saved.
Generation read_saved_generation(const std::filesystem::path& run_dir, int generation);

/// The `count` best distinct creatures over every saved generation and the
/// checkpoint (elites copied between generations count once), best first.
std::vector<Individual> best_individuals(const std::filesystem::path& run_dir, int count);

} // namespace sodaevo
