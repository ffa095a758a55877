// LockstepBatch's frame kernels for AVX-512 (F and DQ: the 8-bit masks and the
// jitter hash's 64-bit multiply), one lane per creature in one 512-bit vector.
//
// The headers first, outside the target region: only the kernels themselves (and
// what they inline) are compiled for the instruction set, never a library
// function the linker could pick for every caller.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>

#include "detail/java_sine_simd.hpp"
#include "detail/lockstep_data.hpp"
#include "detail/simd_rules.hpp"
#include "physics_rules.hpp"

#pragma GCC push_options
#pragma GCC target("avx512f,avx512dq")
#include "detail/lockstep_kernels.hpp"

namespace soda {

LockstepEntry lockstep_kernels_avx512() { return LockstepKernels<simd::Avx512Ops>::entry(); }

} // namespace soda
#pragma GCC pop_options
