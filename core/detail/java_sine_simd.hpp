// Java's Math.sin in SIMD, the kernel itself (sine.hpp and exact_sines.hpp say
// what and why).
//
// In a header so that a kernel which keeps its state in vector registers can
// have the sines inlined into its own loop (lockstep_batch.cpp): a call spills
// every vector register. Include it only where the instruction set of O is enabled
// (#pragma GCC target), as exact_sines.cpp and lockstep_batch.cpp do.
#pragma once

#include <cstdint>

#include "core/detail/simd_ops.hpp"
#include "core/java_sine_table.hpp"

namespace soda::java_sine {

// Templates returning vectors outside a target region: always inlined into code
// compiled for their instruction set, so no call passes a vector (no ABI change).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
// GCC 12 takes the undefined pass-through operand of _mm512_cvttpd_epi32 and
// _mm512_insertf64x4 (in O::to_i32 and O::gather_rows4) for an uninitialised
// variable once they are inlined here: a false positive.
#pragma GCC diagnostic ignored "-Wuninitialized"

/// sine.cpp's main path, W lanes at a time and N vectors side by side: in[0, N*W)
/// to out, each step written for all N vectors before the next, so that the
/// processor sees N independent chains (the reduction, the table row and the sums
/// are one long chain per vector). The same operations on the same operands as
/// sine.cpp, lane by lane: the same bits. Lanes below the main path give x, as
/// sine does; rest[k] marks the lanes of vector k above it (|x| >= 90112,
/// infinities, NaN: the routine's other paths), whose result the caller takes from
/// soda::sine.
template <class O, int N>
[[gnu::always_inline]] inline void java_sin(const double* in, double* out, unsigned* rest) {
  using V = typename O::V;
  using M = typename O::M;
  using simd::kMaxWidth;
#define SODA_EACH _Pragma("GCC unroll 4") for (int k = 0; k < N; ++k)
  const V sign = O::set1(-0.0);
  V x[N], nd[N];
  M main_path[N], tiny[N];
  alignas(64) std::int32_t n[N][kMaxWidth];
  SODA_EACH {
    x[k] = O::loadu(in + k * O::W);
    const V ax = O::abs(x[k]);
    tiny[k] = O::lt(ax, O::set1(kMainPathLow));
    main_path[k] = O::m_andnot(O::lt(ax, O::set1(kMainPathEnd)), tiny[k]); // false for NaN
    // N = (int)(x*32/pi + copysign(0.5, x)), truncated (lanes off the main path: any row)
    const V half = O::bits_or(O::bits_and(x[k], sign), O::set1(0.5));
    O::to_i32(O::add(O::mul(x[k], O::set1(kThirtyTwoOverPi)), half), n[k]);
    nd[k] = O::from_i32(n[k]);
    for (int l = 0; l < O::W; ++l) n[k][l] &= 63;
  }
  V cols[N][4]; // cos - sigma, sin high, sin low, sigma
  SODA_EACH O::gather_rows4(&kTable.row[0].cos_minus_sigma, n[k], cols[k]);

  V r1[N], r[N], minus_c[N];
  SODA_EACH {
    const V m1 = O::mul(nd[k], O::set1(kPiOver32Part1));
    const V m2 = O::mul(nd[k], O::set1(kPiOver32Part2));
    const V m3 = O::mul(nd[k], O::set1(kPiOver32Part3));
    r1[k] = O::sub(x[k], m1);
    r[k] = O::sub(r1[k], m2);
    const V c2 = O::sub(O::sub(r1[k], r[k]), m2);
    minus_c[k] = O::sub(m3, c2);
  }
  V pols_sin[N], pols_cos[N], corr[N];
  SODA_EACH {
    const V rr = r[k];
    const V r2 = O::mul(rr, rr);
    const V r4 = O::mul(r2, r2);
    const V cos_b = O::add(cols[k][0], cols[k][3]);
    const V sin_weight = O::mul(O::mul(cos_b, rr), r2);
    const V cos_weight = O::mul(cols[k][1], r2);
    const V psc3_sin = O::add(O::mul(O::mul(O::set1(kSc4Sin), r1[k]), rr), O::set1(kSc3Sin));
    const V psc3_cos = O::add(O::mul(O::mul(O::set1(kSc4Cos), r1[k]), rr), O::set1(kSc3Cos));
    const V psc1_sin = O::add(O::mul(O::set1(kSc2Sin), r2), O::set1(kSc1Sin));
    const V psc1_cos = O::add(O::mul(O::set1(kSc2Cos), r2), O::set1(kSc1Cos));
    pols_sin[k] = O::mul(O::add(psc1_sin, O::mul(psc3_sin, r4)), sin_weight);
    pols_cos[k] = O::mul(O::add(psc1_cos, O::mul(psc3_cos, r4)), cos_weight);
    corr[k] = O::add(O::mul(minus_c[k], O::sub(O::mul(cols[k][1], rr), cos_b)), cols[k][2]);
  }
  SODA_EACH {
    const V rs = O::mul(cols[k][3], r[k]);
    const V med = O::mul(r[k], cols[k][0]);
    const V res_int = O::add(rs, cols[k][1]);
    const V res_hi = O::add(med, res_int);
    const V k2 = O::add(O::sub(cols[k][1], res_int), rs);
    const V k3 = O::add(O::sub(res_int, res_hi), med);
    const V res_lo = O::add(O::add(O::add(O::add(corr[k], k2), k3), pols_sin[k]), pols_cos[k]);
    const V result = O::add(res_hi, res_lo);
    O::storeu(out + k * O::W, O::select(tiny[k], x[k], result));
    rest[k] = ((1u << O::W) - 1u) & ~O::lanes(O::m_or(main_path[k], tiny[k]));
  }
#undef SODA_EACH
}

#pragma GCC diagnostic pop

} // namespace soda::java_sine
