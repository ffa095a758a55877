// Instruction sets of the SIMD kernels, chosen at run time: all give identical
// results (simd_ops.hpp), so the choice is one of speed only.
#pragma once

namespace soda {

enum class SimdLevel { Auto, Sse2, Avx2, Avx512 };

/// The level Auto means: the best this CPU runs, or the one forced below it (so
/// that one machine measures and tests each level) by force_simd_level or, before
/// that, by the environment variable SODAEVO_SIMD (sse2, avx2, avx512).
SimdLevel best_simd_level();
/// Auto means at most `level` from now on (Auto: the CPU's best again). A level the
/// CPU lacks means its best.
void force_simd_level(SimdLevel level);
/// The level named `name` (auto, sse2, avx2, avx512); false for another name.
bool parse_simd_level(const char* name, SimdLevel& level);
const char* simd_level_name(SimdLevel level);
/// Whether this CPU runs `level` (no level needs fused multiply-add: the engine uses none).
bool simd_level_supported(SimdLevel level);

} // namespace soda
