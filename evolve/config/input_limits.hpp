// Limits on the JSON files a run reads (the config and checkpoint.json).
//
// Configs and checkpoints come from users, other programs and runs that were
// killed mid-way, so each reader refuses, with a clear message, input that no real
// file comes near: too large, nested too deep, too many elements. The limits keep
// a hostile or corrupt file from exhausting memory or the stack.
#pragma once

#include <cstddef>

namespace sodaevo {

/// A config is a few kilobytes; anything above this is not a config.
inline constexpr std::size_t kMaxConfigBytes = std::size_t{1} << 20;

/// JSON nesting: a config is 3 levels deep, a checkpoint 1.
inline constexpr int kMaxJsonDepth = 32;

/// /population/seed_models entries (each is a file that is read).
inline constexpr std::size_t kMaxSeedModels = 10'000;

/// checkpoint.json holds one whole generation as XML: 100,000 creatures (the
/// largest population a config allows) of a few kilobytes each stay far below.
inline constexpr std::size_t kMaxCheckpointBytes = std::size_t{2} << 30;

/// Generations a run may have (/generations); a larger index is corrupt.
inline constexpr int kMaxGenerations = 1'000'000;

/// Largest population a config allows (/population/size); a checkpoint or saved
/// generation holding more creatures is corrupt.
inline constexpr int kMaxPopulation = 100'000;

} // namespace sodaevo
