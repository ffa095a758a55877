// The kernels of kernels.hpp and register_frame.hpp compiled per instruction set,
// and the tables that pick them (kernel_table.hpp). One translation unit, so that
// the frame loops inline what they call.
#include "core/fused/kernel_table.hpp"

#include "core/fused/kernels.hpp"
#if SODA_SIMD_WIDE // AVX-512 only (core/detail/simd_ops.hpp)
#include "core/fused/register_frame.hpp"
#endif

namespace soda::fused {


template <class O>
struct KernelTable {
  static LinkFn link();
  static ChunkFn chunk(bool g, bool f, bool c, bool sides);
  static ChunkFn bar_chunk(bool g);
  static TargetFn targets();
  static ArgsFn args();
};

// The 16 specialisations of a frame kernel (gravity, floor, ceiling, side walls),
// in the order of specialisation_index: X(args..., G, F, C, S) for each.
#define SODA_EACH_SPECIALISATION(X, ...)                                                                     \
  X(__VA_ARGS__, false, false, false, false) X(__VA_ARGS__, false, false, false, true)                     \
  X(__VA_ARGS__, false, false, true, false) X(__VA_ARGS__, false, false, true, true)                       \
  X(__VA_ARGS__, false, true, false, false) X(__VA_ARGS__, false, true, false, true)                       \
  X(__VA_ARGS__, false, true, true, false) X(__VA_ARGS__, false, true, true, true)                         \
  X(__VA_ARGS__, true, false, false, false) X(__VA_ARGS__, true, false, false, true)                       \
  X(__VA_ARGS__, true, false, true, false) X(__VA_ARGS__, true, false, true, true)                         \
  X(__VA_ARGS__, true, true, false, false) X(__VA_ARGS__, true, true, false, true)                         \
  X(__VA_ARGS__, true, true, true, false) X(__VA_ARGS__, true, true, true, true)

constexpr int specialisation_index(bool g, bool f, bool c, bool sides) {
  return (g ? 8 : 0) + (f ? 4 : 0) + (c ? 2 : 0) + (sides ? 1 : 0);
}

#define SODA_MASS_KERNEL(O, G, F, C, S) template bool mass_kernel<O, G, F, C, S>(SceneData&);
#define SODA_RUN_CHUNK(O, G, F, C, S) template void run_chunk<O, G, F, C, S>(SceneData&, State* const*, long long);
#define SODA_RUN_CHUNK_ADDRESS(O, G, F, C, S) &run_chunk<O, G, F, C, S>,
#define SODA_KERNELS(O)                                                                                    \
  SODA_EACH_SPECIALISATION(SODA_MASS_KERNEL, O)                                                            \
  template void link_kernel<O, false>(SceneData&);                                                              \
  SODA_EACH_SPECIALISATION(SODA_RUN_CHUNK, O)                                                              \
  template void targets_kernel<O>(SceneData&, const double*);                                                   \
  template void args_kernel<O>(SceneData&, int);                                                                \
  template bool mass_kernel<O, false, true, true, true, true>(SceneData&);                                 \
  template bool mass_kernel<O, true, true, true, true, true>(SceneData&);                                  \
  template void run_chunk<O, false, true, true, true, true>(SceneData&, State* const*, long long);           \
  template void run_chunk<O, true, true, true, true, true>(SceneData&, State* const*, long long);            \
  template <>                                                                                              \
  ChunkFn KernelTable<O>::bar_chunk(bool g) {                                                              \
    return g ? &run_chunk<O, true, true, true, true, true> : &run_chunk<O, false, true, true, true, true>;  \
  }                                                                                                        \
  template <>                                                                                              \
  TargetFn KernelTable<O>::targets() {                                                                     \
    return &targets_kernel<O>;                                                                             \
  }                                                                                                        \
  template <>                                                                                              \
  ArgsFn KernelTable<O>::args() {                                                                          \
    return &args_kernel<O>;                                                                                \
  }                                                                                                        \
  template <>                                                                                              \
  LinkFn KernelTable<O>::link() {                                                                          \
    return &link_kernel<O, false>;                                                                         \
  }                                                                                                        \
  template <>                                                                                              \
  ChunkFn KernelTable<O>::chunk(bool g, bool f, bool c, bool sides) {                                      \
    constexpr ChunkFn table[16] = {SODA_EACH_SPECIALISATION(SODA_RUN_CHUNK_ADDRESS, O)};                   \
    return table[specialisation_index(g, f, c, sides)];                                                    \
  }

SODA_KERNELS(Sse2Ops)

// Instantiated under the target pragma so that they are compiled for that
// instruction set (they are only called when the CPU has it).
#pragma GCC push_options
#pragma GCC target("avx2")
SODA_KERNELS(Avx2Ops)
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx512f")
SODA_KERNELS(Avx512Ops)
#if SODA_SIMD_WIDE
template void link_kernel<Avx512Ops, true>(SceneData&);
#define SODA_REGISTER_CHUNK(_, G, F, C, S) template void register_chunk<G, F, C, S>(SceneData&, State* const*, long long);
#define SODA_REGISTER_CHUNK_ADDRESS(_, G, F, C, S) &register_chunk<G, F, C, S>,
SODA_EACH_SPECIALISATION(SODA_REGISTER_CHUNK, 0)

ChunkFn register_chunk_fn(bool g, const WallNeeds& w) {
  constexpr ChunkFn table[16] = {SODA_EACH_SPECIALISATION(SODA_REGISTER_CHUNK_ADDRESS, 0)};
  return table[specialisation_index(g, w.floor, w.ceiling, w.sides)];
}
#else
// WebAssembly: no AVX-512, so no frame in registers (SceneData::frame_in_registers).
ChunkFn register_chunk_fn(bool, const WallNeeds&) { return nullptr; }
#endif
#pragma GCC pop_options

#undef SODA_REGISTER_CHUNK_ADDRESS
#undef SODA_REGISTER_CHUNK
#undef SODA_RUN_CHUNK_ADDRESS
#undef SODA_RUN_CHUNK
#undef SODA_MASS_KERNEL
#undef SODA_EACH_SPECIALISATION
#undef SODA_KERNELS

LinkFn link_fn(SimdLevel level) {
  switch (level) {
    case SimdLevel::Avx512: return KernelTable<Avx512Ops>::link();
    case SimdLevel::Avx2: return KernelTable<Avx2Ops>::link();
    default: return KernelTable<Sse2Ops>::link();
  }
}

TargetFn targets_fn(SimdLevel level) {
  switch (level) {
    case SimdLevel::Avx512: return KernelTable<Avx512Ops>::targets();
    case SimdLevel::Avx2: return KernelTable<Avx2Ops>::targets();
    default: return KernelTable<Sse2Ops>::targets();
  }
}

ArgsFn args_fn(SimdLevel level) {
  switch (level) {
    case SimdLevel::Avx512: return KernelTable<Avx512Ops>::args();
    case SimdLevel::Avx2: return KernelTable<Avx2Ops>::args();
    default: return KernelTable<Sse2Ops>::args();
  }
}

ChunkFn chunk_fn(SimdLevel level, bool g, const WallNeeds& w) {
  switch (level) {
    case SimdLevel::Avx512: return KernelTable<Avx512Ops>::chunk(g, w.floor, w.ceiling, w.sides);
    case SimdLevel::Avx2: return KernelTable<Avx2Ops>::chunk(g, w.floor, w.ceiling, w.sides);
    default: return KernelTable<Sse2Ops>::chunk(g, w.floor, w.ceiling, w.sides);
  }
}

ChunkFn bar_chunk_fn(SimdLevel level, bool g) {
  switch (level) {
    case SimdLevel::Avx512: return KernelTable<Avx512Ops>::bar_chunk(g);
    case SimdLevel::Avx2: return KernelTable<Avx2Ops>::bar_chunk(g);
    default: return KernelTable<Sse2Ops>::bar_chunk(g);
  }
}

void SceneData::update_targets(State* const* st) {
  if (const double* sine = row_for_frame(st)) targets_fn(simd)(*this, sine);
}
} // namespace soda::fused
