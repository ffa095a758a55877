// Eight double lanes as two AVX2 vectors: the lockstep lanes' vector where the CPU
// has AVX2 and no AVX-512 (lockstep_batch.hpp).
//
// Why: a lockstep group holds 8 creatures (a GA creature's 8 replicas fill one),
// and its rows are 8 doubles. On AVX2 each operation of the AVX-512 kernel becomes
// two, one per half: the same operations per lane, so the same bits, and the
// group layout, sine pool and planning stay those of AVX-512. The two halves are
// independent chains, which a small creature's frame (bound by the latency of
// its square roots and divisions) needs anyway.
//
// The interface is simd_ops.hpp's (the kernels are templates over it), plus the
// 64-bit integer lanes that the sine jitter's hash takes (mix64.hpp). Include only
// where AVX2 is enabled (#pragma GCC target), as simd_ops.hpp's users do.
#pragma once

#include <immintrin.h>

#include <cstdint>

#include "simd_ops.hpp"

#if SODA_SIMD_WIDE
namespace soda::simd {

#pragma GCC push_options
#pragma GCC target("avx2")
struct Avx2PairOps {
  static constexpr int W = 8;
  static constexpr bool kMaskedArithmetic = false; // add_where is an add and a blend
  using H = Avx2Ops; // one half
  struct V {
    __m256d lo, hi;
  };
  using M = V; // all-ones lanes where true, as Avx2Ops's masks
  struct I {
    __m256i lo, hi;
  };
  static V load(const double* p) { return {H::load(p), H::load(p + 4)}; }
  static void store(double* p, V v) { H::store(p, v.lo); H::store(p + 4, v.hi); }
  static V loadu(const double* p) { return {H::loadu(p), H::loadu(p + 4)}; }
  static void storeu(double* p, V v) { H::storeu(p, v.lo); H::storeu(p + 4, v.hi); }
  static V set1(double v) { return {H::set1(v), H::set1(v)}; }
  static V add(V a, V b) { return {H::add(a.lo, b.lo), H::add(a.hi, b.hi)}; }
  static V sub(V a, V b) { return {H::sub(a.lo, b.lo), H::sub(a.hi, b.hi)}; }
  static V mul(V a, V b) { return {H::mul(a.lo, b.lo), H::mul(a.hi, b.hi)}; }
  static V div(V a, V b) { return {H::div(a.lo, b.lo), H::div(a.hi, b.hi)}; }
  static V sqrt(V a) { return {H::sqrt(a.lo), H::sqrt(a.hi)}; }
  static V max(V a, V b) { return {H::max(a.lo, b.lo), H::max(a.hi, b.hi)}; }
  static V min(V a, V b) { return {H::min(a.lo, b.lo), H::min(a.hi, b.hi)}; }
  static M lt(V a, V b) { return {H::lt(a.lo, b.lo), H::lt(a.hi, b.hi)}; }
  static M gt(V a, V b) { return {H::gt(a.lo, b.lo), H::gt(a.hi, b.hi)}; }
  static M eq(V a, V b) { return {H::eq(a.lo, b.lo), H::eq(a.hi, b.hi)}; }
  static M ne(V a, V b) { return {H::ne(a.lo, b.lo), H::ne(a.hi, b.hi)}; }
  static M le(V a, V b) { return {H::le(a.lo, b.lo), H::le(a.hi, b.hi)}; }
  static M ge(V a, V b) { return {H::ge(a.lo, b.lo), H::ge(a.hi, b.hi)}; }
  static M m_or(M a, M b) { return {H::m_or(a.lo, b.lo), H::m_or(a.hi, b.hi)}; }
  static M m_and(M a, M b) { return {H::m_and(a.lo, b.lo), H::m_and(a.hi, b.hi)}; }
  static M m_andnot(M a, M b) { return {H::m_andnot(a.lo, b.lo), H::m_andnot(a.hi, b.hi)}; }
  static M m_none() { return {H::m_none(), H::m_none()}; }
  static M m_all() {
    const __m256d ones = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    return {ones, ones};
  }
  static unsigned lanes(M m) { return H::lanes(m.lo) | (H::lanes(m.hi) << 4); }
  static bool any(M m) { return !_mm256_testz_pd(_mm256_or_pd(m.lo, m.hi), _mm256_or_pd(m.lo, m.hi)); }
  static V select(M m, V if_true, V if_false) {
    return {H::select(m.lo, if_true.lo, if_false.lo), H::select(m.hi, if_true.hi, if_false.hi)};
  }
  static V abs(V a) { return {H::abs(a.lo), H::abs(a.hi)}; }
  static V bits_and(V a, V b) { return {H::bits_and(a.lo, b.lo), H::bits_and(a.hi, b.hi)}; }
  static V bits_or(V a, V b) { return {H::bits_or(a.lo, b.lo), H::bits_or(a.hi, b.hi)}; }
  static V trunc(V a) {
    return {_mm256_round_pd(a.lo, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC),
            _mm256_round_pd(a.hi, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC)};
  }
  /// a + b in lanes m, a elsewhere (and a - b). A blend, not a + (b & m): -0 + +0 would be +0.
  static V add_where(M m, V a, V b) { return select(m, add(a, b), a); }
  static V sub_where(M m, V a, V b) { return select(m, sub(a, b), a); }
  static void to_i32(V v, std::int32_t* out) { H::to_i32(v.lo, out); H::to_i32(v.hi, out + 4); }
  static V from_i32(const std::int32_t* in) { return {H::from_i32(in), H::from_i32(in + 4)}; }
  static void gather_rows4(const double* rows, const std::int32_t* idx, V (&v)[4]) {
    __m256d lo[4], hi[4];
    H::gather_rows4(rows, idx, lo);
    H::gather_rows4(rows, idx + 4, hi);
    for (int c = 0; c < 4; ++c) v[c] = {lo[c], hi[c]};
  }
  /// base[idx[l]] in lane l.
  static V gather64(const double* base, const std::int64_t* idx) {
    return {_mm256_i64gather_pd(base, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(idx)), 8),
            _mm256_i64gather_pd(base, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(idx + 4)), 8)};
  }
  /// Lane 0's value.
  static double first(V a) { return _mm256_cvtsd_f64(a.lo); }
  /// Whether every lane of a has the bits of lane 0.
  static bool lanes_alike(V a) {
    const __m256i b = _mm256_castpd_si256(_mm256_permute4x64_pd(a.lo, 0));
    const __m256i same = _mm256_and_si256(_mm256_cmpeq_epi64(_mm256_castpd_si256(a.lo), b),
                                          _mm256_cmpeq_epi64(_mm256_castpd_si256(a.hi), b));
    return _mm256_movemask_pd(_mm256_castsi256_pd(same)) == 0xf;
  }
  /// Whether a and b differ in the bits of some lane.
  static bool bits_differ(V a, V b) {
    const __m256i same = _mm256_and_si256(_mm256_cmpeq_epi64(_mm256_castpd_si256(a.lo), _mm256_castpd_si256(b.lo)),
                                          _mm256_cmpeq_epi64(_mm256_castpd_si256(a.hi), _mm256_castpd_si256(b.hi)));
    return _mm256_movemask_pd(_mm256_castsi256_pd(same)) != 0xf;
  }

  // 64-bit integer lanes (the jitter's hash).
  static I iload(const std::uint64_t* p) {
    return {_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)), _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p + 4))};
  }
  static I ibits(V a) { return {_mm256_castpd_si256(a.lo), _mm256_castpd_si256(a.hi)}; }
  static I iset1(std::uint64_t v) { return {_mm256_set1_epi64x(static_cast<long long>(v)), _mm256_set1_epi64x(static_cast<long long>(v))}; }
  static I ixor(I a, I b) { return {_mm256_xor_si256(a.lo, b.lo), _mm256_xor_si256(a.hi, b.hi)}; }
  template <int S>
  static I ishr(I a) { return {_mm256_srli_epi64(a.lo, S), _mm256_srli_epi64(a.hi, S)}; }
  /// a * b modulo 2^64 per lane, from 32-bit products (AVX2 has no 64-bit multiply).
  static __m256i mul64(__m256i a, __m256i b) {
    const __m256i low = _mm256_mul_epu32(a, b);
    const __m256i cross = _mm256_add_epi64(_mm256_mul_epu32(_mm256_srli_epi64(a, 32), b), _mm256_mul_epu32(a, _mm256_srli_epi64(b, 32)));
    return _mm256_add_epi64(low, _mm256_slli_epi64(cross, 32));
  }
  static I imul(I a, I b) { return {mul64(a.lo, b.lo), mul64(a.hi, b.hi)}; }
  /// Lanes where a < b, both below 2^63 (a signed compare is then the unsigned one).
  static unsigned ilt_small(I a, I b) {
    return H::lanes(_mm256_castsi256_pd(_mm256_cmpgt_epi64(b.lo, a.lo))) |
           (H::lanes(_mm256_castsi256_pd(_mm256_cmpgt_epi64(b.hi, a.hi))) << 4);
  }
};
#pragma GCC pop_options

} // namespace soda::simd
#endif
