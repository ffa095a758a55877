// Choosing a fused scene's kernels: each kernel of kernels.hpp compiled for SSE2,
// AVX2 and AVX-512 (under target pragmas, for CPUs chosen at run time), and the
// functions that pick the one for a level and a wall/gravity specialisation.
#pragma once

#include "core/fused/scene_data.hpp"

namespace soda::fused {

using LinkFn = void (*)(SceneData&);
using TargetFn = void (*)(SceneData&, const double*);
using ArgsFn = void (*)(SceneData&, int);
using ChunkFn = void (*)(SceneData&, State* const*, long long);

/// The link pass of `level` (points from memory).
LinkFn link_fn(SimdLevel level);
/// The muscle targets from a row of sines.
TargetFn targets_fn(SimdLevel level);
/// The sine arguments of the first rows (fill_rows).
ArgsFn args_fn(SimdLevel level);
/// Frames with the kernels of `level`, gravity `g` and the walls `w` tested.
ChunkFn chunk_fn(SimdLevel level, bool g, const WallNeeds& w);
/// Frames of a scene where some creature has fixed bars: every wall tested, the bar rules after
/// the mass pass (run_chunk with Bars).
ChunkFn bar_chunk_fn(SimdLevel level, bool g);
/// Frames in registers (AVX-512; SceneData::frame_in_registers).
ChunkFn register_chunk_fn(bool g, const WallNeeds& w);

} // namespace soda::fused
