// Reading a finished (or interrupted) run back: its saved generations, for
// replay and export.
#pragma once

#include <filesystem>
#include <vector>

#include "evolve/algorithms/population.hpp"

namespace sodaevo {

/// Generation numbers saved whole in the run folder, ascending.
std::vector<int> saved_generations(const std::filesystem::path& run_dir);

/// Reads generations/gen_NNNNN.xml. Throws InputError (naming the file and the
/// generations that are available) if it was not saved.
Generation read_saved_generation(const std::filesystem::path& run_dir, int generation);

/// The `count` best distinct creatures of the last saved generation (the one the
/// run ended with), best first. Why not every saved generation: an earlier
/// generation's record of a creature is its claim before the run resampled it, and
/// the creatures that fell out since are mostly those whose first replicas were
/// lucky; the last generation keeps the elites (the best the run still believes
/// in) and its best are confirmed on more replicas (/fitness/confirm).
std::vector<Individual> best_individuals(const std::filesystem::path& run_dir, int count);

} // namespace sodaevo
