// SIMD operations for the kernels: one struct per instruction set (SSE2, AVX2 with
// FMA, AVX-512F), each a set of static one-liners over a vector type V and a mask
// type M, so that a kernel is written once as a template and compiled per level
// (under a target pragma, for CPUs chosen at run time).
//
// Internal to the core's .cpp files (core/fused/, exact_sines.cpp, lockstep_batch.cpp).
#pragma once

#include <immintrin.h>

#include <cstdint>

// GCC 12's AVX-512 headers trip -Wmaybe-uninitialized inside their own intrinsics
// (the "undefined" source operand idiom); nothing here is uninitialised.
#if !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace soda::simd {
// ---------------------------------------------------------------------------
// SIMD operations. Each is one IEEE operation per lane (add, sub, mul, div, sqrt
// are correctly rounded in every instruction set, so all levels give the same
// bits); comparisons are the ordered ones, false for NaN, as C++'s < and >. No
// fused multiply-add in the physics (the build has -ffp-contract=off and the
// kernels only use separate mul and add intrinsics), none in the sine either
// (java_sine_simd.hpp): there are no fused operations here on purpose.
// ---------------------------------------------------------------------------

struct Sse2Ops {
  static constexpr int W = 2;
  static constexpr bool kPointRegisters = false; // see Avx512Ops
  using V = __m128d;
  using M = __m128d;
  static V load(const double* p) { return _mm_load_pd(p); }
  static void store(double* p, V v) { _mm_store_pd(p, v); }
  static V set1(double v) { return _mm_set1_pd(v); }
  static V add(V a, V b) { return _mm_add_pd(a, b); }
  static V sub(V a, V b) { return _mm_sub_pd(a, b); }
  static V mul(V a, V b) { return _mm_mul_pd(a, b); }
  static V div(V a, V b) { return _mm_div_pd(a, b); }
  static V sqrt(V a) { return _mm_sqrt_pd(a); }
  // x86 max/min: a where a > b (a < b), else b (ties of +-0 and NaN give b).
  static V max(V a, V b) { return _mm_max_pd(a, b); }
  static V min(V a, V b) { return _mm_min_pd(a, b); }
  static M lt(V a, V b) { return _mm_cmplt_pd(a, b); }
  static M gt(V a, V b) { return _mm_cmpgt_pd(a, b); }
  static M eq(V a, V b) { return _mm_cmpeq_pd(a, b); }
  static M m_or(M a, M b) { return _mm_or_pd(a, b); }
  static M m_and(M a, M b) { return _mm_and_pd(a, b); }
  static M m_andnot(M a, M b) { return _mm_andnot_pd(b, a); } // a & !b
  static M m_none() { return _mm_setzero_pd(); }
  static bool any(M m) { return _mm_movemask_pd(m) != 0; }
  static V select(M m, V if_true, V if_false) {
    return _mm_or_pd(_mm_and_pd(m, if_true), _mm_andnot_pd(m, if_false));
  }
  static V neg(V a) { return _mm_xor_pd(a, _mm_set1_pd(-0.0)); }
  static V abs(V a) { return _mm_andnot_pd(_mm_set1_pd(-0.0), a); }
  static V bits_and(V a, V b) { return _mm_and_pd(a, b); }
  static V bits_xor(V a, V b) { return _mm_xor_pd(a, b); }
  static V bits_or(V a, V b) { return _mm_or_pd(a, b); }
  static M le(V a, V b) { return _mm_cmple_pd(a, b); }
  static M ge(V a, V b) { return _mm_cmpge_pd(a, b); }
  static M ne(V a, V b) { return _mm_cmpneq_pd(a, b); }
  static unsigned lanes(M m) { return static_cast<unsigned>(_mm_movemask_pd(m)); }
  static V loadu(const double* p) { return _mm_loadu_pd(p); }
  static void storeu(double* p, V v) { _mm_storeu_pd(p, v); }
  // Truncation of values in [0, 2^31) to int32, and back.
  static void to_i32(V v, std::int32_t* out) { _mm_storel_epi64(reinterpret_cast<__m128i*>(out), _mm_cvttpd_epi32(v)); }
  static V from_i32(const std::int32_t* in) {
    return _mm_cvtepi32_pd(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(in)));
  }
  static V gather(const double* base, const std::int32_t* idx) { return _mm_set_pd(base[idx[1]], base[idx[0]]); }
  /// Rows idx[l] of a table of 4-double rows, transposed: column c of lane l's row in lane l of v[c].
  static void gather_rows4(const double* rows, const std::int32_t* idx, V (&v)[4]) {
    const double* r0 = rows + 4 * idx[0];
    const double* r1 = rows + 4 * idx[1];
    for (int c = 0; c < 4; c += 2) {
      const V a = _mm_load_pd(r0 + c), b = _mm_load_pd(r1 + c);
      v[c] = _mm_unpacklo_pd(a, b);
      v[c + 1] = _mm_unpackhi_pd(a, b);
    }
  }
  // W (x, y) pairs -> x and y vectors, lanes in the order sigma (see kLaneLink).
  // off: offsets in doubles (2 * pair index), unsigned so that no sign extension is needed.
  static void load_pairs_at(const double* pairs, const std::uint32_t* off, V& x, V& y) {
    const V p0 = _mm_load_pd(pairs + off[0]), p1 = _mm_load_pd(pairs + off[1]);
    x = _mm_unpacklo_pd(p0, p1);
    y = _mm_unpackhi_pd(p0, p1);
  }
  static void load_pairs(const double* pairs, V& x, V& y) {
    const V p0 = _mm_load_pd(pairs), p1 = _mm_load_pd(pairs + 2);
    x = _mm_unpacklo_pd(p0, p1);
    y = _mm_unpackhi_pd(p0, p1);
  }
  // The inverse: lanes in sigma order -> W pairs in natural order.
  static void store_pairs(double* pairs, V x, V y) {
    _mm_store_pd(pairs, _mm_unpacklo_pd(x, y));
    _mm_store_pd(pairs + 2, _mm_unpackhi_pd(x, y));
  }
  // W pairs held in registers -> x and y vectors, lanes as load_pairs puts them.
  static void pairs_to_xy(const __m128d* p, V& x, V& y) {
    x = _mm_unpacklo_pd(p[0], p[1]);
    y = _mm_unpackhi_pd(p[0], p[1]);
  }
};

// AVX2 and AVX-512 exist on x86 only. In WebAssembly (web/build_wasm.sh: 128-bit
// SIMD, which takes the SSE2 intrinsics) the wide levels are stand-ins of SSE2 so
// that the kernels compile unchanged; simd_level_supported never offers them there.
#if defined(__x86_64__) || defined(__i386__)
#define SODA_SIMD_WIDE 1
#else
#define SODA_SIMD_WIDE 0
#endif

#if SODA_SIMD_WIDE
#pragma GCC push_options
#pragma GCC target("avx2")
struct Avx2Ops {
  static constexpr int W = 4;
  static constexpr bool kPointRegisters = false;
  using V = __m256d;
  using M = __m256d;
  static V load(const double* p) { return _mm256_load_pd(p); }
  static void store(double* p, V v) { _mm256_store_pd(p, v); }
  static V set1(double v) { return _mm256_set1_pd(v); }
  static V add(V a, V b) { return _mm256_add_pd(a, b); }
  static V sub(V a, V b) { return _mm256_sub_pd(a, b); }
  static V mul(V a, V b) { return _mm256_mul_pd(a, b); }
  static V div(V a, V b) { return _mm256_div_pd(a, b); }
  static V sqrt(V a) { return _mm256_sqrt_pd(a); }
  // x86 max/min: a where a > b (a < b), else b (ties of +-0 and NaN give b).
  static V max(V a, V b) { return _mm256_max_pd(a, b); }
  static V min(V a, V b) { return _mm256_min_pd(a, b); }
  static M lt(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_LT_OQ); }
  static M gt(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_GT_OQ); }
  static M eq(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_EQ_OQ); }
  static M m_or(M a, M b) { return _mm256_or_pd(a, b); }
  static M m_and(M a, M b) { return _mm256_and_pd(a, b); }
  static M m_andnot(M a, M b) { return _mm256_andnot_pd(b, a); }
  static M m_none() { return _mm256_setzero_pd(); }
  static bool any(M m) { return _mm256_movemask_pd(m) != 0; }
  static V select(M m, V if_true, V if_false) { return _mm256_blendv_pd(if_false, if_true, m); }
  static V neg(V a) { return _mm256_xor_pd(a, _mm256_set1_pd(-0.0)); }
  static V abs(V a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }
  static V bits_and(V a, V b) { return _mm256_and_pd(a, b); }
  static V bits_xor(V a, V b) { return _mm256_xor_pd(a, b); }
  static V bits_or(V a, V b) { return _mm256_or_pd(a, b); }
  static M le(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_LE_OQ); }
  static M ge(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_GE_OQ); }
  static M ne(V a, V b) { return _mm256_cmp_pd(a, b, _CMP_NEQ_UQ); }
  static unsigned lanes(M m) { return static_cast<unsigned>(_mm256_movemask_pd(m)); }
  static V loadu(const double* p) { return _mm256_loadu_pd(p); }
  static void storeu(double* p, V v) { _mm256_storeu_pd(p, v); }
  static void to_i32(V v, std::int32_t* out) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm256_cvttpd_epi32(v));
  }
  static V from_i32(const std::int32_t* in) {
    return _mm256_cvtepi32_pd(_mm_loadu_si128(reinterpret_cast<const __m128i*>(in)));
  }
  static V gather(const double* base, const std::int32_t* idx) {
    return _mm256_set_pd(base[idx[3]], base[idx[2]], base[idx[1]], base[idx[0]]);
  }
  static void gather_rows4(const double* rows, const std::int32_t* idx, V (&v)[4]) {
    const V r0 = _mm256_load_pd(rows + 4 * idx[0]), r1 = _mm256_load_pd(rows + 4 * idx[1]);
    const V r2 = _mm256_load_pd(rows + 4 * idx[2]), r3 = _mm256_load_pd(rows + 4 * idx[3]);
    const V lo01 = _mm256_unpacklo_pd(r0, r1), hi01 = _mm256_unpackhi_pd(r0, r1); // c0 c0 c2 c2 / c1 c1 c3 c3
    const V lo23 = _mm256_unpacklo_pd(r2, r3), hi23 = _mm256_unpackhi_pd(r2, r3);
    v[0] = _mm256_permute2f128_pd(lo01, lo23, 0x20);
    v[1] = _mm256_permute2f128_pd(hi01, hi23, 0x20);
    v[2] = _mm256_permute2f128_pd(lo01, lo23, 0x31);
    v[3] = _mm256_permute2f128_pd(hi01, hi23, 0x31);
  }
  static V pair2(const double* pairs, std::uint32_t i, std::uint32_t j) {
    return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_load_pd(pairs + i)), _mm_load_pd(pairs + j), 1);
  }
  static void load_pairs_at(const double* pairs, const std::uint32_t* off, V& x, V& y) {
    const V p0 = pair2(pairs, off[0], off[1]), p1 = pair2(pairs, off[2], off[3]);
    x = _mm256_unpacklo_pd(p0, p1);
    y = _mm256_unpackhi_pd(p0, p1);
  }
  static void load_pairs(const double* pairs, V& x, V& y) {
    const V p0 = _mm256_load_pd(pairs), p1 = _mm256_load_pd(pairs + 4);
    x = _mm256_unpacklo_pd(p0, p1);
    y = _mm256_unpackhi_pd(p0, p1);
  }
  static void store_pairs(double* pairs, V x, V y) {
    _mm256_store_pd(pairs, _mm256_unpacklo_pd(x, y));
    _mm256_store_pd(pairs + 4, _mm256_unpackhi_pd(x, y));
  }
  static void pairs_to_xy(const __m128d* p, V& x, V& y) {
    const V p0 = _mm256_set_m128d(p[1], p[0]), p1 = _mm256_set_m128d(p[3], p[2]);
    x = _mm256_unpacklo_pd(p0, p1);
    y = _mm256_unpackhi_pd(p0, p1);
  }
};
#pragma GCC pop_options

#pragma GCC push_options
#pragma GCC target("avx512f")
struct Avx512Ops {
  static constexpr int W = 8;
  using V = __m512d;
  using M = __mmask8;
  // Scenes of at most kRegisterPoints points keep x and y of every point in two
  // registers each during the link pass; an end's coordinate is then one
  // two-register permute instead of a pair load with its offset load and inserts.
  static constexpr bool kPointRegisters = true;
  static constexpr int kRegisterPoints = 16;
  static void load_points(const double* pairs, V (&x)[2], V (&y)[2]) {
    const __m512i even = _mm512_setr_epi64(0, 2, 4, 6, 8, 10, 12, 14);
    const __m512i odd = _mm512_setr_epi64(1, 3, 5, 7, 9, 11, 13, 15);
    for (int r = 0; r < 2; ++r) {
      const V p0 = _mm512_load_pd(pairs + 16 * r), p1 = _mm512_load_pd(pairs + 16 * r + 8);
      x[r] = _mm512_permutex2var_pd(p0, even, p1);
      y[r] = _mm512_permutex2var_pd(p0, odd, p1);
    }
  }
  static V point(const V (&c)[2], const std::int64_t* idx) {
    return _mm512_permutex2var_pd(c[0], _mm512_load_si512(idx), c[1]);
  }
  // Up to 8 * kPickRegisters values in registers: lane l takes value idx[l] (of
  // c[idx / 8]) by one two-register permute per pair of registers in use and a
  // masked move, a third of the instructions of a gather by loads and inserts.
  static constexpr int kPickRegisters = 12;
  static V pick(const V (&c)[kPickRegisters], int pairs, const std::int64_t* idx) {
    const __m512i i = _mm512_load_si512(idx);
    const __m512i pair = _mm512_srli_epi64(i, 4); // the permute reads bits 0-3
    V v = _mm512_permutex2var_pd(c[0], i, c[1]);
#pragma GCC unroll 6
    for (int j = 1; j < kPickRegisters / 2; ++j) {
      if (j >= pairs) break;
      const __mmask8 mine = _mm512_cmpeq_epi64_mask(pair, _mm512_set1_epi64(j));
      v = _mm512_mask_mov_pd(v, mine, _mm512_permutex2var_pd(c[2 * j], i, c[2 * j + 1]));
    }
    return v;
  }
  static V load(const double* p) { return _mm512_load_pd(p); }
  static void store(double* p, V v) { _mm512_store_pd(p, v); }
  static V set1(double v) { return _mm512_set1_pd(v); }
  static V add(V a, V b) { return _mm512_add_pd(a, b); }
  static V sub(V a, V b) { return _mm512_sub_pd(a, b); }
  static V mul(V a, V b) { return _mm512_mul_pd(a, b); }
  static V div(V a, V b) { return _mm512_div_pd(a, b); }
  static V sqrt(V a) { return _mm512_sqrt_pd(a); }
  // x86 max/min: a where a > b (a < b), else b (ties of +-0 and NaN give b).
  static V max(V a, V b) { return _mm512_max_pd(a, b); }
  static V min(V a, V b) { return _mm512_min_pd(a, b); }
  static M lt(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_LT_OQ); }
  static M gt(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_GT_OQ); }
  static M eq(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_EQ_OQ); }
  static M m_or(M a, M b) { return static_cast<M>(a | b); }
  static M m_and(M a, M b) { return static_cast<M>(a & b); }
  static M m_andnot(M a, M b) { return static_cast<M>(a & ~b); }
  static M m_none() { return 0; }
  static bool any(M m) { return m != 0; }
  static V select(M m, V if_true, V if_false) { return _mm512_mask_blend_pd(m, if_false, if_true); }
  static V neg(V a) {
    return _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(a), _mm512_set1_epi64(INT64_MIN)));
  }
  static V abs(V a) {
    return _mm512_castsi512_pd(_mm512_and_si512(_mm512_castpd_si512(a), _mm512_set1_epi64(INT64_MAX)));
  }
  static V bits_and(V a, V b) {
    return _mm512_castsi512_pd(_mm512_and_si512(_mm512_castpd_si512(a), _mm512_castpd_si512(b)));
  }
  static V bits_xor(V a, V b) {
    return _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(a), _mm512_castpd_si512(b)));
  }
  static V bits_or(V a, V b) {
    return _mm512_castsi512_pd(_mm512_or_si512(_mm512_castpd_si512(a), _mm512_castpd_si512(b)));
  }
  static M le(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_LE_OQ); }
  static M ge(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_GE_OQ); }
  static M ne(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_NEQ_UQ); }
  static V trunc(V a) { return _mm512_roundscale_pd(a, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC); }
  /// a + b in lanes m, a elsewhere (and a - b): one masked instruction.
  static V add_where(M m, V a, V b) { return _mm512_mask_add_pd(a, m, a, b); }
  static V sub_where(M m, V a, V b) { return _mm512_mask_sub_pd(a, m, a, b); }
  static unsigned lanes(M m) { return m; }
  static constexpr bool kMaskedArithmetic = true; // add_where is one masked instruction
  static M m_all() { return 0xff; }
  /// base[idx[l]] in lane l.
  static V gather64(const double* base, const std::int64_t* idx) {
    return _mm512_i64gather_pd(_mm512_loadu_si512(idx), base, 8);
  }
  /// Lane 0's value.
  static double first(V a) { return _mm512_cvtsd_f64(a); }
  /// Whether every lane of a has the bits of lane 0.
  static bool lanes_alike(V a) {
    const __m512i b = _mm512_castpd_si512(_mm512_broadcastsd_pd(_mm512_castpd512_pd128(a)));
    return _mm512_cmpneq_epi64_mask(_mm512_castpd_si512(a), b) == 0;
  }
  /// Whether a and b differ in the bits of some lane.
  static bool bits_differ(V a, V b) { return _mm512_cmpneq_epi64_mask(_mm512_castpd_si512(a), _mm512_castpd_si512(b)) != 0; }
  // 64-bit integer lanes (the jitter's hash; the multiply is AVX-512DQ's).
  using I = __m512i;
  static I iload(const std::uint64_t* p) { return _mm512_loadu_si512(p); }
  static I ibits(V a) { return _mm512_castpd_si512(a); }
  static I iset1(std::uint64_t v) { return _mm512_set1_epi64(static_cast<long long>(v)); }
  static I ixor(I a, I b) { return _mm512_xor_si512(a, b); }
  template <int S>
  static I ishr(I a) { return _mm512_srli_epi64(a, S); }
  [[gnu::target("avx512f,avx512dq")]] static I imul(I a, I b) { return _mm512_mullo_epi64(a, b); }
  /// Lanes where a < b, both below 2^63.
  static unsigned ilt_small(I a, I b) { return _mm512_cmplt_epu64_mask(a, b); }
  static V loadu(const double* p) { return _mm512_loadu_pd(p); }
  static void storeu(double* p, V v) { _mm512_storeu_pd(p, v); }
  static void to_i32(V v, std::int32_t* out) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm512_cvttpd_epi32(v));
  }
  static V from_i32(const std::int32_t* in) {
    return _mm512_cvtepi32_pd(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(in)));
  }
  static V gather(const double* base, const std::int32_t* idx) {
    return _mm512_set_pd(base[idx[7]], base[idx[6]], base[idx[5]], base[idx[4]], base[idx[3]], base[idx[2]],
                         base[idx[1]], base[idx[0]]);
  }
  // One 256-bit load per row and a transpose: a quarter of the loads of four gathers.
  static void gather_rows4(const double* rows, const std::int32_t* idx, V (&v)[4]) {
    auto two = [&](int l) { // rows of lanes l and l + 1 in one register
      return _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_load_pd(rows + 4 * idx[l])),
                                _mm256_load_pd(rows + 4 * idx[l + 1]), 1);
    };
    const V z01 = two(0), z23 = two(2), z45 = two(4), z67 = two(6);
    // lo: c0 of rows (0,2) | c2 of (0,2) | c0 of (1,3) | c2 of (1,3); hi: c1, c3 likewise.
    const V lo0 = _mm512_unpacklo_pd(z01, z23), hi0 = _mm512_unpackhi_pd(z01, z23);
    const V lo4 = _mm512_unpacklo_pd(z45, z67), hi4 = _mm512_unpackhi_pd(z45, z67);
    // Lane l takes element k[l] of (first, second): rows 0 1 2 3 from the first, 4 5 6 7 from the second.
    const __m512i even = _mm512_setr_epi64(0, 4, 1, 5, 8, 12, 9, 13);
    const __m512i odd = _mm512_setr_epi64(2, 6, 3, 7, 10, 14, 11, 15);
    v[0] = _mm512_permutex2var_pd(lo0, even, lo4);
    v[1] = _mm512_permutex2var_pd(hi0, even, hi4);
    v[2] = _mm512_permutex2var_pd(lo0, odd, lo4);
    v[3] = _mm512_permutex2var_pd(hi0, odd, hi4);
  }
  // Pair loads and inserts: faster than vgatherdpd (bench/README.md, "Design figures").
  static V pair4(const double* pairs, const std::uint32_t* off) {
    const __m256d lo = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_load_pd(pairs + off[0])),
                                            _mm_load_pd(pairs + off[1]), 1);
    const __m256d hi = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_load_pd(pairs + off[2])),
                                            _mm_load_pd(pairs + off[3]), 1);
    return _mm512_insertf64x4(_mm512_zextpd256_pd512(lo), hi, 1);
  }
  static void load_pairs_at(const double* pairs, const std::uint32_t* off, V& x, V& y) {
    const V p0 = pair4(pairs, off), p1 = pair4(pairs, off + 4);
    x = _mm512_unpacklo_pd(p0, p1);
    y = _mm512_unpackhi_pd(p0, p1);
  }
  static void load_pairs(const double* pairs, V& x, V& y) {
    const V p0 = _mm512_load_pd(pairs), p1 = _mm512_load_pd(pairs + 8);
    x = _mm512_unpacklo_pd(p0, p1);
    y = _mm512_unpackhi_pd(p0, p1);
  }
  static void store_pairs(double* pairs, V x, V y) {
    _mm512_store_pd(pairs, _mm512_unpacklo_pd(x, y));
    _mm512_store_pd(pairs + 8, _mm512_unpackhi_pd(x, y));
  }
  static void pairs_to_xy(const __m128d* p, V& x, V& y) {
    const V p0 = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_set_m128d(p[1], p[0])),
                                    _mm256_set_m128d(p[3], p[2]), 1);
    const V p1 = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_set_m128d(p[5], p[4])),
                                    _mm256_set_m128d(p[7], p[6]), 1);
    x = _mm512_unpacklo_pd(p0, p1);
    y = _mm512_unpackhi_pd(p0, p1);
  }
};
#pragma GCC pop_options
#else
struct Avx2Ops : Sse2Ops {};
struct Avx512Ops : Sse2Ops {
  static constexpr int kRegisterPoints = 16;
};
#endif

// Widest SIMD width; every array is padded to a multiple of it.
constexpr int kMaxWidth = 8;

} // namespace soda::simd
