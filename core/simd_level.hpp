// Instruction sets of the SIMD kernels, chosen at run time: all give identical
// results (simd_ops.hpp), so the choice is one of speed only.
#pragma once

namespace soda {

enum class SimdLevel { Auto, Sse2, Avx2, Avx512 };

/// The best level this CPU runs.
SimdLevel best_simd_level();
const char* simd_level_name(SimdLevel level);
/// AVX2 counts only with FMA (the sine needs it; Intel and AMD CPUs with AVX2 have both).
bool simd_level_supported(SimdLevel level);

} // namespace soda
