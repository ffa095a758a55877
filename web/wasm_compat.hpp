// Included first into every file of the WebAssembly build (web/build_wasm.sh):
// what the C++ library of Debian's Emscripten 3.1.6 (libc++ 14) lacks of C++20.
#pragma once

#include <bit>
#include <version>

#if !defined(__cpp_lib_bit_cast)
namespace std {
/// std::bit_cast (C++20) by the compiler's builtin, which clang 14 has.
template <class To, class From>
constexpr To bit_cast(const From& from) noexcept {
  return __builtin_bit_cast(To, from);
}
} // namespace std
#endif
