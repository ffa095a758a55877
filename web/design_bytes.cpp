#include "web/design_bytes.hpp"

#include <cstdint>
#include <cstring>

#include "core/input_error.hpp"

namespace soda::web {

namespace {

// Bump with any change of the layout (ModelDef gaining a field, say).
constexpr std::string_view kTag = "sodadef1";

class Writer {
 public:
  void i32(std::int32_t v) { raw(&v, sizeof v); }
  void f64(double v) { raw(&v, sizeof v); }
  void text(std::string_view s) {
    i32(static_cast<std::int32_t>(s.size()));
    out += s;
  }
  std::string out;

 private:
  void raw(const void* p, std::size_t n) { out.append(static_cast<const char*>(p), n); }
};

class Reader {
 public:
  explicit Reader(std::string_view bytes) : in_(bytes) {}
  std::int32_t i32() {
    std::int32_t v;
    raw(&v, sizeof v);
    return v;
  }
  double f64() {
    double v;
    raw(&v, sizeof v);
    return v;
  }
  std::string text() {
    const std::int32_t n = i32();
    if (n < 0 || static_cast<std::size_t>(n) > in_.size() - at_) short_bytes();
    std::string s(in_.substr(at_, static_cast<std::size_t>(n)));
    at_ += static_cast<std::size_t>(n);
    return s;
  }
  /// A count of items of at least `item_bytes` each that the rest can hold.
  std::size_t count(std::size_t item_bytes) {
    const std::int32_t n = i32();
    if (n < 0 || static_cast<std::size_t>(n) > (in_.size() - at_) / item_bytes) short_bytes();
    return static_cast<std::size_t>(n);
  }
  bool at_end() const { return at_ == in_.size(); }

 private:
  [[noreturn]] static void short_bytes() { throw InputError("design bytes: cut short or not written by this engine"); }
  void raw(void* p, std::size_t n) {
    if (n > in_.size() - at_) short_bytes();
    std::memcpy(p, in_.data() + at_, n);
    at_ += n;
  }
  std::string_view in_;
  std::size_t at_ = 0;
};

} // namespace

std::string design_to_bytes(const ModelDef& d, const std::vector<std::string>& warnings) {
  Writer w;
  w.out.reserve(64 + d.nodes.size() * 48 + d.links.size() * 36);
  w.out += kTag;
  w.text(d.comment);
  w.text(d.name);
  w.i32(d.width);
  w.i32(d.height);
  for (const double v : {d.environment.gravity, d.environment.friction, d.environment.springyness,
                         d.collisions.surface_friction, d.collisions.surface_reflection, d.wave.amplitude,
                         d.wave.phase, d.wave.speed}) {
    w.f64(v);
  }
  w.i32(static_cast<std::int32_t>(d.settings.gravity_direction));
  w.i32(static_cast<std::int32_t>(d.settings.wave_direction));
  w.i32(d.settings.autoreverse ? 1 : 0);
  w.i32(static_cast<std::int32_t>(d.nodes.size()));
  for (const NodeDef& n : d.nodes) {
    w.text(n.id);
    w.i32(n.fixed ? 1 : 0);
    for (const double v : {n.x, n.y, n.vx, n.vy}) w.f64(v);
  }
  w.i32(static_cast<std::int32_t>(d.links.size()));
  for (const LinkDef& l : d.links) {
    w.i32(static_cast<std::int32_t>(l.kind));
    w.i32(l.a);
    w.i32(l.b);
    for (const double v : {l.rest_length, l.amplitude, l.phase}) w.f64(v);
  }
  w.i32(static_cast<std::int32_t>(warnings.size()));
  for (const std::string& warning : warnings) w.text(warning);
  return std::move(w.out);
}

void design_from_bytes(std::string_view bytes, ModelDef& design, std::vector<std::string>& warnings) {
  if (bytes.substr(0, kTag.size()) != kTag) throw InputError("design bytes: not written by this engine");
  Reader r(bytes.substr(kTag.size()));
  ModelDef d;
  d.comment = r.text();
  d.name = r.text();
  d.width = r.i32();
  d.height = r.i32();
  for (double* v : {&d.environment.gravity, &d.environment.friction, &d.environment.springyness,
                    &d.collisions.surface_friction, &d.collisions.surface_reflection, &d.wave.amplitude,
                    &d.wave.phase, &d.wave.speed}) {
    *v = r.f64();
  }
  d.settings.gravity_direction = static_cast<GravityDirection>(r.i32());
  d.settings.wave_direction = static_cast<WaveDirection>(r.i32());
  d.settings.autoreverse = r.i32() != 0;
  d.nodes.resize(r.count(40));
  for (NodeDef& n : d.nodes) {
    n.id = r.text();
    n.fixed = r.i32() != 0;
    for (double* v : {&n.x, &n.y, &n.vx, &n.vy}) *v = r.f64();
  }
  d.links.resize(r.count(36));
  for (LinkDef& l : d.links) {
    const std::int32_t kind = r.i32();
    l.a = r.i32();
    l.b = r.i32();
    if (kind < 0 || kind > 2 || l.a < 0 || l.b < 0 || static_cast<std::size_t>(l.a) >= d.nodes.size() ||
        static_cast<std::size_t>(l.b) >= d.nodes.size()) {
      throw InputError("design bytes: a link of no kind or to no node");
    }
    l.kind = static_cast<LinkKind>(kind);
    for (double* v : {&l.rest_length, &l.amplitude, &l.phase}) *v = r.f64();
  }
  std::vector<std::string> w(r.count(4));
  for (std::string& warning : w) warning = r.text();
  if (!r.at_end()) throw InputError("design bytes: more than a design");
  design = std::move(d);
  warnings = std::move(w);
}

} // namespace soda::web
