// glibc's sin in SIMD, the kernel itself (sine.hpp and exact_sines.hpp say what and why).
//
// In a header so that a kernel which keeps its state in vector registers can
// have the sines inlined into its own loop (lockstep_batch.cpp, step_groups): a call
// spills every vector register. Include it only where the instruction set of O is
// enabled (#pragma GCC target), as exact_sines.cpp and lockstep_batch.cpp do.
#pragma once

#include <cstdint>

#include "core/detail/simd_ops.hpp"
#include "core/sine_table.hpp"

namespace soda::glibc_sine {

// Templates returning vectors outside a target region: always inlined into code
// compiled for their instruction set, so no call passes a vector (no ABI change).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

// glibc's sin, W lanes at a time: the branches of sine_table.hpp, which every lane
// takes and keeps its own; the operations, and which of them are fused (the FMA
// build's choice, read from its machine code), are glibc's, as in sine.cpp.

/// N vectors of sines at once: in[0, N*W) to out, each step written for all N
/// vectors before the next, so that the processor sees N independent chains side
/// by side (one vector's chain, from the reduction through the table to the
/// polynomials, is longer than the reorder window can cover with one vector's
/// instructions). rest[k] marks the lanes of vector k outside sine's range
/// (|x| >= 105414336, infinities, NaN), whose result the caller takes from
/// soda::sine.
// GCC 12 takes the undefined pass-through operand of _mm512_cvttpd_epi32 and
// _mm512_insertf64x4 (in O::to_i32 and O::gather_rows4) for an uninitialised
// variable once they are inlined here: a false positive.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
template <class O, int N>
[[gnu::always_inline]] inline void glibc_sin(const GlibcTable& t, const double* in, double* out, unsigned* rest) {
  using V = typename O::V;
  using M = typename O::M;
  using simd::kMaxWidth;
#define SODA_EACH _Pragma("GCC unroll 4") for (int k = 0; k < N; ++k)
  const V sign = O::set1(-0.0);
  const V zero = O::set1(0.0);
  V x[N], ax[N];
  M sin_branch[N], cos_branch[N], reduced[N], reducible[N];
  SODA_EACH {
    x[k] = O::loadu(in + k * O::W);
    ax[k] = O::abs(x[k]);
    sin_branch[k] = O::lt(ax[k], O::set1(kSinBound));
    const M below_cos_end = O::lt(ax[k], O::set1(kCosBound));
    reducible[k] = O::lt(ax[k], O::set1(kReduceBound)); // false for NaN
    cos_branch[k] = O::m_andnot(below_cos_end, sin_branch[k]);
    reduced[k] = O::m_andnot(reducible[k], below_cos_end);
  }

  // reduce_sincos: n = round(x * 2/pi), x - n*pi/2 in four parts as b + db.
  const V toint = O::set1(kToInt);
  V tn[N], xn[N], y[N];
  SODA_EACH tn[k] = O::fma(x[k], O::set1(kHalfPiInverse), toint);
  SODA_EACH xn[k] = O::sub(tn[k], toint);
  SODA_EACH y[k] = O::fnma(xn[k], O::set1(kHalfPi1), x[k]);
  SODA_EACH y[k] = O::fnma(xn[k], O::set1(kHalfPi2), y[k]);
  const V pp3 = O::set1(kHalfPi3), pp4 = O::set1(kHalfPi4);
  V t2[N], db[N], b[N];
  SODA_EACH t2[k] = O::fnma(xn[k], pp3, y[k]);
  SODA_EACH db[k] = O::fnma(pp3, xn[k], O::sub(y[k], t2[k]));
  SODA_EACH b[k] = O::fnma(xn[k], pp4, t2[k]);
  SODA_EACH db[k] = O::add(db[k], O::fnma(xn[k], pp4, O::sub(t2[k], b[k])));

  // Each lane's (a, da) and whether it takes do_cos.
  M use_cos[N], negate[N];
  V a[N], da[N], abs_a[N];
  SODA_EACH {
    const M odd = O::m_and(reduced[k], O::has_bit(tn[k], 1));
    negate[k] = O::m_and(reduced[k], O::has_bit(tn[k], 2));
    use_cos[k] = O::m_or(cos_branch[k], odd);
    a[k] = O::select(sin_branch[k], x[k],
                     O::select(cos_branch[k], O::sub(O::set1(kHalfPiHigh), ax[k]), O::select(reduced[k], b[k], zero)));
    da[k] = O::select(cos_branch[k], O::set1(kHalfPiLow), O::select(reduced[k], db[k], zero));
    abs_a[k] = O::abs(a[k]);
  }

  // do_sin and do_cos: the table row nearest |a|, and a short polynomial in the
  // distance xr to it. do_sin negates da when a <= 0, do_cos when a < 0.
  const V big = O::set1(kBig);
  V table_point[N];
  alignas(64) std::int32_t row[N][kMaxWidth];
  SODA_EACH {
    table_point[k] = O::sub(O::add(abs_a[k], big), big); // i/128, exact
    O::to_i32(O::mul(table_point[k], O::set1(128.0)), row[k]);
  }
  V cols[N][4];
  SODA_EACH O::gather_rows4(&t.row[0][0], row[k], cols[k]);

  // do_sin for |a| < 0.126: a + ((P(a^2)*a - da/2)*a^2 + da).
  V aa[N], p[N], taylor_result[N];
  SODA_EACH aa[k] = O::mul(a[k], a[k]);
  SODA_EACH p[k] = O::fma(aa[k], O::set1(kS5), O::set1(kS4));
  SODA_EACH p[k] = O::fma(aa[k], p[k], O::set1(kS3));
  SODA_EACH p[k] = O::fma(aa[k], p[k], O::set1(kS2));
  SODA_EACH p[k] = O::fma(aa[k], p[k], O::set1(kS1));
  SODA_EACH taylor_result[k] = O::add(a[k], O::fma(aa[k], O::fms(p[k], a[k], O::mul(da[k], O::set1(0.5))), da[k]));

  V xr[N], xx[N], p1[N], xr_xx[N], c_cos[N];
  SODA_EACH {
    const M flip = O::m_or(O::m_and(use_cos[k], O::lt(a[k], zero)), O::m_andnot(O::le(a[k], zero), use_cos[k]));
    const V dx = O::select(flip, O::bits_xor(da[k], sign), da[k]);
    const V xr0 = O::sub(abs_a[k], table_point[k]);
    xr[k] = O::select(use_cos[k], O::add(xr0, dx), xr0);
    da[k] = dx;
  }
  SODA_EACH xx[k] = O::mul(xr[k], xr[k]);
  SODA_EACH {
    p1[k] = O::fma(xx[k], O::set1(kSn5), O::set1(kSn3));
    xr_xx[k] = O::mul(xr[k], xx[k]);
    const V p2 = O::fma(xx[k], O::fma(xx[k], O::set1(kCs6), O::set1(kCs4)), O::set1(kCs2));
    c_cos[k] = O::mul(xx[k], p2);
  }
  V sin_result[N], cos_result[N];
  SODA_EACH {
    const V sn = cols[k][0], ssn = cols[k][1], cs = cols[k][2], ccs = cols[k][3];
    const V dx = da[k];
    // do_sin: s = xr + (dx + xr^3 p1), c = xr*dx + xx*p2, cor = (ssn + s*ccs - sn*c) + cs*s.
    const V s_sin = O::add(xr[k], O::fma(xr_xx[k], p1[k], dx));
    const V c_sin = O::fma(xr[k], dx, c_cos[k]);
    const V cor_sin = O::fma(s_sin, cs, O::fnma(c_sin, sn, O::fma(s_sin, ccs, ssn)));
    sin_result[k] = O::bits_or(O::abs(O::add(sn, cor_sin)), O::bits_and(a[k], sign));
  }
  SODA_EACH {
    const V sn = cols[k][0], ssn = cols[k][1], cs = cols[k][2], ccs = cols[k][3];
    // do_cos: s = xr + xr^3 p1, c = xx*p2, cor = (ccs - s*ssn - cs*c) - sn*s.
    const V s_cos = O::fma(xr_xx[k], p1[k], xr[k]);
    const V cor_cos = O::fnma(s_cos, sn, O::fnma(c_cos[k], cs, O::fnma(s_cos, ssn, ccs)));
    cos_result[k] = O::add(cs, cor_cos);
  }
  SODA_EACH {
    const M taylor = O::m_andnot(O::lt(abs_a[k], O::set1(kTaylorBound)), use_cos[k]);
    V r = O::select(taylor, taylor_result[k], O::select(use_cos[k], cos_result[k], sin_result[k]));
    r = O::select(cos_branch[k], O::bits_or(O::abs(r), O::bits_and(x[k], sign)), r);
    r = O::select(negate[k], O::bits_xor(r, sign), r);
    r = O::select(O::lt(ax[k], O::set1(kTinyBound)), x[k], r);
    O::storeu(out + k * O::W, r);
    rest[k] = ((1u << O::W) - 1u) & ~O::lanes(reducible[k]);
  }
#undef SODA_EACH
}
#pragma GCC diagnostic pop


#pragma GCC diagnostic pop

} // namespace soda::glibc_sine
