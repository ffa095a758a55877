// HotSpot's large-argument reduction for Math.sin (java_sine_large.hpp says what
// and why). Variable names follow the routine's registers, so that each line can be
// checked against one instruction; "32-bit" marks where the routine works on the low
// half of a register (and clears the high half), as x86-64 does.
#include "java_sine_large.hpp"

#include <bit>
#include <cstdint>

#include "java_sine_table.hpp"

namespace soda::java_sine {
namespace {

// 2/pi in binary, 32 bits a word (after two zero words): a mathematical constant,
// as the routine stores it.
constexpr std::uint32_t kTwoOverPi[41] = {
    0x00000000, 0x00000000, 0xa2f9836e, 0x4e441529, 0xfc2757d1, 0xf534ddc0, 0xdb629599, 0x3c439041, 0xfe5163ab,
    0xdebbc561, 0xb7246e3a, 0x424dd2e0, 0x06492eea, 0x09d1921c, 0xfe1deb1c, 0xb129a73e, 0xe88235f5, 0x2ebb4484,
    0xe99c7026, 0xb45f7e41, 0x3991d639, 0x835339f4, 0x9c845f8b, 0xbdf9283b, 0x1ff897ff, 0xde05980f, 0xef2f118b,
    0x5a0a6d1f, 0x6d367ecf, 0x27cb09b7, 0x4f463f66, 0x9e5fea2d, 0x7527bac7, 0xebe5f17b, 0x3d0739f7, 0x8a5292ea,
    0x6bfb5fb1, 0x1f8d5d08, 0x56033046, 0xfc7b6bab, 0xf0cfbc21};
constexpr double kPiOver4High = from_bits(0x3fe921fb40000000);
constexpr double kPiOver4Low = from_bits(0x3e64442d18469899);

using u32 = std::uint32_t;
using u64 = std::uint64_t;

u64 low32(u64 v) { return static_cast<u32>(v); }
u64 shl32(u64 v, u32 count) { return static_cast<u32>(static_cast<u32>(v) << (count & 31)); }
u64 shr32(u64 v, u32 count) { return static_cast<u32>(v) >> (count & 31); }
u64 shl64(u64 v, u32 count) { return v << (count & 63); }
u64 shr64(u64 v, u32 count) { return v >> (count & 63); }

/// hi:mid:lo = top:0:0 - hi:mid:lo (the routine's sub, sbb, sbb).
void negate_from(u64 top, u64& hi, u64& mid, u64& lo) {
  const u64 new_lo = 0 - lo;
  const u64 borrow1 = lo != 0 ? 1 : 0;
  const u64 new_mid = 0 - mid - borrow1;
  const u64 borrow2 = (mid != 0 || borrow1 != 0) ? 1 : 0;
  const u64 new_hi = top - hi - borrow2;
  lo = new_lo, mid = new_mid, hi = new_hi;
}

} // namespace

LargeReduction reduce_large(double x) {
  const u64 bits = std::bit_cast<u64>(x);
  const u32 top16 = static_cast<u32>(bits >> 48);
  // The three 32-bit words of 2/pi that meet the significand: from the exponent.
  const u32 offset = ((((top16 & 0x7ff0u) - 16224u) >> 7) & 65532u); // in bytes
  const u32* t = kTwoOverPi + offset / 4;
  // Significand = rax * 2^32 + rdx (rax: the top 21 bits with the leading 1).
  u64 rdx = low32(bits);
  u64 rax = ((static_cast<u32>(bits >> 21) | 0x80000000u) >> 11);
  // The products of the significand's two parts with six words of 2/pi, summed
  // into r9:r10:r8 (and r11) with the routine's carries.
  u64 r10 = t[5], r8 = t[6];
  u64 r9 = low32(r10);
  r10 = r10 * rdx;
  r9 = r9 * rax;
  r8 = r8 * rax;
  u64 rsi = t[4], rdi = t[3];
  u64 r11 = low32(r10);
  r10 >>= 32;
  r9 += r10;
  r11 += r8;
  r8 = low32(r11);
  r11 >>= 32;
  r9 += r11;
  r10 = low32(rsi);
  rsi = rsi * rdx;
  r10 = r10 * rax;
  r11 = low32(rdi);
  rdi = rdi * rdx;
  u64 rbx = low32(rsi);
  rsi >>= 32;
  r9 += rbx;
  rbx = low32(r9);
  r9 >>= 32;
  r10 += rsi;
  r10 += r9;
  rbx <<= 32;
  r8 |= rbx;
  r11 = r11 * rax;
  r9 = t[2];
  rsi = t[1];
  rbx = low32(rdi);
  rdi >>= 32;
  r10 += rbx;
  rbx = low32(r10);
  r10 >>= 32;
  r11 += rdi;
  r11 += r10;
  rdi = r9;
  r9 = r9 * rdx;
  rdi = rdi * rax;
  r10 = low32(r9);
  r9 >>= 32;
  r11 += r10;
  r10 = low32(r11);
  r11 >>= 32;
  rdi += r9;
  rdi += r11;
  r9 = rsi;
  rsi = rsi * rdx;
  r9 = r9 * rax;
  r10 <<= 32;
  r10 |= rbx;
  rax = t[0];
  r11 = low32(rsi);
  rsi >>= 32;
  rdi += r11;
  r11 = low32(rdi);
  rdi >>= 32;
  r9 += rsi;
  r9 += rdi;
  rdx = rdx * rax;
  // The binary point: 8 * offset + 19 - (unbiased exponent).
  const u32 sign = 32768u & top16;
  u32 ecx = offset * 8u + 19u - (((top16 >> 4) & 2047u) - 1023u);
  r9 += rdx;
  u32 edx = ecx + 32u;
  u32 flip = 0; // the routine's ebx: 32768 when the fraction was negated
  if (static_cast<std::int32_t>(ecx) >= 1) {
    ecx = 29u - ecx;
    r9 = shl32(r9, ecx);
    rdi = low32(r9);
    r9 = low32(r9) & 0x1fffffffu;
    if ((r9 & 0x10000000u) != 0) { // past half a quadrant: negate toward the next
      r9 = shr32(r9, ecx);
      u64 top = shr32(0x20000000u, ecx);
      r9 = (r9 << 32) | r11;
      top <<= 32;
      rdi = low32(static_cast<u32>(rdi) + 0x20000000u);
      negate_from(top, r9, r10, r8);
      flip = 32768;
    } else {
      r9 = shr32(r9, ecx);
      r9 = (r9 << 32) | r11;
    }
  } else {
    ecx = 0u - ecx;
    r9 = (r9 << 32) | r11;
    r9 = shl64(r9, ecx);
    rdi = r9;
    if ((r9 & 0x80000000u) != 0) {
      r9 = shr32(r9, ecx);
      const u64 top = shr64(0x100000000ull, ecx);
      negate_from(top, r9, r10, r8);
      flip = 32768;
      rdi >>= 3;
      rdi = low32(static_cast<u32>(rdi) + 0x20000000u);
    } else {
      r9 = shr32(r9, ecx);
      rdi >>= 3;
    }
  }

  LargeReduction out;
  // Normalise the fraction r9:r10:r8 so that r9's top bit is bit 29.
  bool zero = false;
  if (r9 == 0) {
    edx += 64u;
    r9 = r10, r10 = r8, r8 = 0;
    if (r9 == 0) {
      edx += 64u;
      r9 = r10, r10 = r8;
      if (r9 == 0) zero = true; // no double lands on a multiple of pi/4: not reached
    }
  }
  if (zero) {
    out.rows = static_cast<u32>(rax) << 3;
    return out;
  }
  const u32 top_bit = 63u - static_cast<u32>(std::countl_zero(r9));
  const std::int32_t up = 29 - static_cast<std::int32_t>(top_bit);
  if (up > 0) {
    const u32 c = static_cast<u32>(up);
    r9 = shl64(r9, c);
    rax = r10;
    r10 = shl64(r10, c);
    edx += c;
    const u32 back = 64u - c;
    rax = shr64(rax, back);
    r8 = shr64(r8, back);
    r9 |= rax;
    r10 |= r8;
  } else if (up < 0) {
    const u32 c = static_cast<u32>(-up);
    r10 = shr64(r10, c);
    rax = r9;
    r9 = shr64(r9, c);
    edx -= c;
    rax = shl64(rax, 64u - c);
    r10 |= rax;
  }
  // The fraction as two doubles scaled by powers of two built from edx, times pi/4.
  double d0 = static_cast<double>(static_cast<std::int64_t>(r9));
  r10 >>= 1;
  double d3 = static_cast<double>(static_cast<std::int64_t>(r10));
  edx <<= 4;
  edx = 16368u - edx;
  edx |= sign;
  edx ^= flip;
  const double scale_high = std::bit_cast<double>(static_cast<u64>(edx & 0xffffu) << 48);
  edx -= 1008u;
  const double scale_low = std::bit_cast<double>(static_cast<u64>(edx & 0xffffu) << 48);
  d0 = d0 * scale_high;
  const u32 sign_mask = static_cast<u32>(static_cast<std::int32_t>(sign << 16) >> 31);
  d3 = d3 * scale_low;
  double d1 = d0;
  d0 = d0 * kPiOver4High;
  u32 quadrant = static_cast<u32>(rdi) >> 29;
  d1 = d1 + d3;
  d3 = d3 * kPiOver4High;
  quadrant = (quadrant + sign_mask) ^ sign_mask;
  double d6 = kPiOver4Low * d1;
  d6 = d6 + d3;
  const double d2 = d0;
  d0 = d0 + d6;
  d6 = d6 + (d2 - d0);
  out.high = d0;
  out.low = d6;
  out.rows = quadrant << 3;
  return out;
}

} // namespace soda::java_sine
