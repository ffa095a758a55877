// Instruction sets of the SIMD kernels, chosen at run time: all give identical
// results (simd_ops.hpp), so the choice is one of speed only.
#pragma once

namespace soda {

enum class SimdLevel { Auto, Sse2, Avx2, Avx512 };

/// The best level this CPU runs.
SimdLevel best_simd_level();
const char* simd_level_name(SimdLevel level);
/// Whether this CPU runs `level` (no level needs fused multiply-add: the engine uses none).
bool simd_level_supported(SimdLevel level);

} // namespace soda
