// LockstepBatch's frame kernels for AVX2: the 8 lanes of a group as two 256-bit
// vectors (avx2_pair_ops.hpp), where the CPU has no AVX-512.
//
// The headers first, outside the target region: only the kernels themselves (and
// what they inline) are compiled for the instruction set, never a library
// function the linker could pick for every caller.
#include "detail/avx2_pair_ops.hpp"
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>

#include "detail/java_sine_simd.hpp"
#include "detail/lockstep_data.hpp"
#include "detail/simd_rules.hpp"
#include "physics_rules.hpp"

#pragma GCC push_options
#pragma GCC target("avx2")
#include "detail/lockstep_kernels.hpp"

namespace soda {

LockstepEntry lockstep_kernels_avx2() { return LockstepKernels<simd::Avx2PairOps>::entry(); }

} // namespace soda
#pragma GCC pop_options
