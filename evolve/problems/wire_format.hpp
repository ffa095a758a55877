// Wire format: creatures, evaluations, problems and estimators as compact bytes,
// for sending between processes (the MPI evaluator). A Problem or Estimator
// writes and reads its own fields with WireWriter / WireReader (problem.hpp,
// estimator.hpp), its kind's name first.
//
// Every field of a soda::ModelDef and of an Evaluation is written as is: doubles
// as their 8 bytes (so they round-trip bit for bit, NaN payloads and -0 included),
// integers little-endian, strings with their length. No MPI here, so the format
// is tested in every build. Decoding checks every length and throws WireError on
// a short or malformed message instead of reading past it.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/model_def.hpp"
#include "evolve/problems/evaluation.hpp"

namespace sodaevo {

class WireError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Most descriptors an evaluation may carry (a damaged count is refused before
/// any allocation).
inline constexpr std::uint32_t kMaxWireDescriptors = 64;

/// Appends values to a byte buffer.
class WireWriter {
 public:
  void u8(std::uint8_t v) { bytes_.push_back(v); }
  void u32(std::uint32_t v);
  void u64(std::uint64_t v);
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void f64(double v);
  void text(const std::string& s);
  void creature(const soda::ModelDef& def);
  void evaluation(const Evaluation& e);

  [[nodiscard]] const std::vector<char>& bytes() const { return bytes_; }
  [[nodiscard]] std::vector<char> take() { return std::move(bytes_); }

 private:
  std::vector<char> bytes_;
};

/// Reads values back in the order they were written.
class WireReader {
 public:
  WireReader(const char* data, std::size_t size) : data_(data), size_(size) {}
  explicit WireReader(const std::vector<char>& bytes) : WireReader(bytes.data(), bytes.size()) {}

  std::uint8_t u8();
  std::uint32_t u32();
  std::uint64_t u64();
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  double f64();
  std::string text();
  soda::ModelDef creature();
  Evaluation evaluation();

  /// Throws WireError unless every byte was read.
  void expect_end() const;

 private:
  const char* need(std::size_t n);
  const char* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

/// Convenience: one creature / one evaluation as bytes and back.
std::vector<char> encode_creature(const soda::ModelDef& def);
soda::ModelDef decode_creature(const std::vector<char>& bytes);
std::vector<char> encode_evaluation(const Evaluation& e);
Evaluation decode_evaluation(const std::vector<char>& bytes);
/// A batch's evaluations as an evaluator hands them back (the page's workers,
/// Python's evaluate): their count, then each in order.
std::vector<char> encode_evaluations(const std::vector<Evaluation>& evaluations);
/// Throws WireError if malformed or not wholly read.
std::vector<Evaluation> decode_evaluations(const char* bytes, std::size_t size);

} // namespace sodaevo
