#include "wire_format.hpp"

#include <bit>
#include <cstring>

namespace sodaevo {

void WireWriter::u32(std::uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes_.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
}

void WireWriter::u64(std::uint64_t v) {
  for (int i = 0; i < 8; ++i) bytes_.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
}

void WireWriter::f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }

void WireWriter::text(const std::string& s) {
  u64(s.size());
  bytes_.insert(bytes_.end(), s.begin(), s.end());
}

void WireWriter::creature(const soda::ModelDef& d) {
  text(d.comment);
  text(d.name);
  i32(d.width);
  i32(d.height);
  f64(d.environment.gravity);
  f64(d.environment.friction);
  f64(d.environment.springyness);
  f64(d.collisions.surface_friction);
  f64(d.collisions.surface_reflection);
  f64(d.wave.amplitude);
  f64(d.wave.phase);
  f64(d.wave.speed);
  i32(static_cast<int>(d.settings.gravity_direction));
  i32(static_cast<int>(d.settings.wave_direction));
  u8(d.settings.autoreverse ? 1 : 0);
  u64(d.nodes.size());
  for (const soda::NodeDef& n : d.nodes) {
    text(n.id);
    u8(n.fixed ? 1 : 0);
    f64(n.x);
    f64(n.y);
    f64(n.vx);
    f64(n.vy);
  }
  u64(d.links.size());
  for (const soda::LinkDef& l : d.links) {
    u8(static_cast<std::uint8_t>(l.kind));
    i32(l.a);
    i32(l.b);
    f64(l.rest_length);
    f64(l.amplitude);
    f64(l.phase);
  }
}

void WireWriter::evaluation(const Evaluation& e) {
  u8(static_cast<std::uint8_t>(e.status));
  text(e.reason);
  f64(e.fitness);
  f64(e.distance);
  f64(e.px_per_frame);
  f64(e.honesty_change);
  i32(e.estimate.rollouts);
  f64(e.estimate.mean);
  f64(e.estimate.sd);
  f64(e.estimate.median);
  u32(static_cast<std::uint32_t>(e.descriptors.size()));
  for (double d : e.descriptors) f64(d);
}

const char* WireReader::need(std::size_t n) {
  if (n > size_ - pos_) {
    throw WireError("message truncated: needed " + std::to_string(n) + " more bytes at offset " +
                    std::to_string(pos_) + " of " + std::to_string(size_));
  }
  const char* p = data_ + pos_;
  pos_ += n;
  return p;
}

std::uint8_t WireReader::u8() { return static_cast<std::uint8_t>(*need(1)); }

std::uint32_t WireReader::u32() {
  const auto* p = reinterpret_cast<const unsigned char*>(need(4));
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(p[i]) << (8 * i);
  return v;
}

std::uint64_t WireReader::u64() {
  const auto* p = reinterpret_cast<const unsigned char*>(need(8));
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(p[i]) << (8 * i);
  return v;
}

double WireReader::f64() { return std::bit_cast<double>(u64()); }

std::string WireReader::text() {
  const std::uint64_t n = u64();
  if (n > size_ - pos_) throw WireError("message truncated: a string of " + std::to_string(n) + " bytes does not fit");
  const char* p = need(static_cast<std::size_t>(n));
  return std::string(p, static_cast<std::size_t>(n));
}

namespace {

template <typename Enum>
Enum checked_enum(int v, int lo, int hi, const char* what) {
  if (v < lo || v > hi) throw WireError(std::string("bad ") + what + " value " + std::to_string(v));
  return static_cast<Enum>(v);
}

bool checked_bool(std::uint8_t v) {
  if (v > 1) throw WireError("bad boolean value " + std::to_string(v));
  return v == 1;
}

// Each node or link takes at least this many bytes, so a count larger than the
// rest of the message divided by it is malformed (no giant allocation).
std::size_t checked_count(std::uint64_t n, std::size_t left, std::size_t min_bytes) {
  if (n > left / min_bytes) throw WireError("bad element count " + std::to_string(n));
  return static_cast<std::size_t>(n);
}

} // namespace

soda::ModelDef WireReader::creature() {
  soda::ModelDef d;
  d.comment = text();
  d.name = text();
  d.width = i32();
  d.height = i32();
  d.environment.gravity = f64();
  d.environment.friction = f64();
  d.environment.springyness = f64();
  d.collisions.surface_friction = f64();
  d.collisions.surface_reflection = f64();
  d.wave.amplitude = f64();
  d.wave.phase = f64();
  d.wave.speed = f64();
  d.settings.gravity_direction = checked_enum<soda::GravityDirection>(i32(), -1, 1, "gravity direction");
  d.settings.wave_direction = checked_enum<soda::WaveDirection>(i32(), -1, 1, "wave direction");
  d.settings.autoreverse = checked_bool(u8());
  d.nodes.resize(checked_count(u64(), size_ - pos_, 8 + 1 + 32));
  for (soda::NodeDef& n : d.nodes) {
    n.id = text();
    n.fixed = checked_bool(u8());
    n.x = f64();
    n.y = f64();
    n.vx = f64();
    n.vy = f64();
  }
  d.links.resize(checked_count(u64(), size_ - pos_, 1 + 8 + 24));
  for (soda::LinkDef& l : d.links) {
    l.kind = checked_enum<soda::LinkKind>(u8(), 0, 2, "link kind");
    l.a = i32();
    l.b = i32();
    l.rest_length = f64();
    l.amplitude = f64();
    l.phase = f64();
  }
  return d;
}

Evaluation WireReader::evaluation() {
  Evaluation e;
  e.status = checked_enum<EvaluationStatus>(u8(), 0, 2, "evaluation status");
  e.reason = text();
  e.fitness = f64();
  e.distance = f64();
  e.px_per_frame = f64();
  e.honesty_change = f64();
  e.estimate.rollouts = i32();
  e.estimate.mean = f64();
  e.estimate.sd = f64();
  e.estimate.median = f64();
  const std::uint32_t descriptors = u32();
  if (descriptors > kMaxWireDescriptors) {
    throw WireError("evaluation: " + std::to_string(descriptors) + " descriptors, expected at most " +
                    std::to_string(kMaxWireDescriptors));
  }
  for (std::uint32_t k = 0; k < descriptors; ++k) e.descriptors.push_back(f64());
  return e;
}

void WireReader::expect_end() const {
  if (pos_ != size_) throw WireError(std::to_string(size_ - pos_) + " unexpected bytes at the end of a message");
}

std::vector<char> encode_creature(const soda::ModelDef& def) {
  WireWriter w;
  w.creature(def);
  return w.take();
}

soda::ModelDef decode_creature(const std::vector<char>& bytes) {
  WireReader r(bytes);
  soda::ModelDef d = r.creature();
  r.expect_end();
  return d;
}

std::vector<char> encode_evaluation(const Evaluation& e) {
  WireWriter w;
  w.evaluation(e);
  return w.take();
}

Evaluation decode_evaluation(const std::vector<char>& bytes) {
  WireReader r(bytes);
  Evaluation e = r.evaluation();
  r.expect_end();
  return e;
}

std::vector<char> encode_evaluations(const std::vector<Evaluation>& evaluations) {
  WireWriter w;
  w.u32(static_cast<std::uint32_t>(evaluations.size()));
  for (const Evaluation& e : evaluations) w.evaluation(e);
  return w.take();
}

std::vector<Evaluation> decode_evaluations(const char* bytes, std::size_t size) {
  WireReader r(bytes, size);
  const std::uint32_t count = r.u32();
  std::vector<Evaluation> out;
  for (std::uint32_t k = 0; k < count; ++k) out.push_back(r.evaluation());
  r.expect_end();
  return out;
}

} // namespace sodaevo
