// The engine's C interface for WebAssembly (web/build_wasm.sh compiles it with
// core/ and the XML reader and writer; web/soda_engine.js wraps it for pages and
// Node).
//
// A Session holds one design (the ModelDef being edited, as the XML reader gives
// it and the writer takes it) and one simulation of it (Model and State, built on
// reset). Every stepping call runs soda::run, the reference step: the portable
// scalar path, which gives the native engine's bits (the engine's own sine, no
// libm). Functions return 1 for success, 0 for failure with the reason in
// soda_message(); bad input never changes the design. Strings go out through the
// session's buffer: soda_output() and soda_output_length() (bytes, since a saved
// model is ISO-8859-1). A big design's nodes and links leave as arrays of doubles
// (soda_design_numbers), not as text: formatting 40,000 numbers is 0.1-0.5 s in
// WebAssembly, on the page's thread.
#include <cmath>
#include <exception>
#include <string>
#include <string_view>
#include <vector>

#include <emscripten/emscripten.h>

#include "core/input_error.hpp"
#include "core/model.hpp"
#include "formats/model_file.hpp"
#include "web/design_bytes.hpp"
#include "core/number_text.hpp"
#include "core/step.hpp"
#if __has_include("core/sine_jitter.hpp")
#include "core/sine_jitter.hpp"
#define SODA_HAS_JITTER 1
#else
#define SODA_HAS_JITTER 0
#endif

namespace {

struct Session {
  soda::ModelDef design;
  std::vector<std::string> warnings; ///< of the last load
  bool simulating = false;           ///< model and state are built from the design
  soda::Model model;
  soda::State state;
  soda::Point2 start;                ///< mass centroid at reset
  std::vector<double> positions;     ///< x, y per design node, refreshed on request
  std::vector<double> numbers;       ///< the design's nodes and links (soda_design_numbers)
  std::string message;
  std::string output;
};

int fail(Session* s, const std::string& message) {
  s->message = message;
  return 0;
}

/// Runs `body`, turning any exception into a failure with its message.
template <class Body>
int guarded(Session* s, Body body) {
  try {
    body();
    s->message.clear();
    return 1;
  } catch (const std::exception& e) {
    return fail(s, e.what());
  }
}

void append_json_string(std::string& out, std::string_view text) {
  out += '"';
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20) {
      static const char* hex = "0123456789abcdef";
      out += "\\u00";
      out += hex[u >> 4];
      out += hex[u & 15];
    } else {
      out += c;
    }
  }
  out += '"';
}

std::string number(double v) { return std::isfinite(v) ? soda::format_double_plain(v) : "null"; }

/// The design's world and name as JSON; its nodes and links: soda_design_numbers.
std::string design_json(const soda::ModelDef& d) {
  std::string j = "{\"name\":";
  append_json_string(j, d.name);
  j += ",\"comment\":";
  append_json_string(j, d.comment);
  j += ",\"width\":" + std::to_string(d.width) + ",\"height\":" + std::to_string(d.height);
  j += ",\"gravity\":" + number(d.environment.gravity) + ",\"friction\":" + number(d.environment.friction) +
       ",\"springyness\":" + number(d.environment.springyness);
  j += ",\"surfaceFriction\":" + number(d.collisions.surface_friction) +
       ",\"surfaceReflection\":" + number(d.collisions.surface_reflection);
  j += ",\"waveAmplitude\":" + number(d.wave.amplitude) + ",\"wavePhase\":" + number(d.wave.phase) +
       ",\"waveSpeed\":" + number(d.wave.speed);
  j += ",\"gravityDirection\":" + std::to_string(static_cast<int>(d.settings.gravity_direction)) +
       ",\"waveDirection\":" + std::to_string(static_cast<int>(d.settings.wave_direction)) +
       ",\"autoreverse\":" + (d.settings.autoreverse ? "true" : "false");
  return j + "}";
}

bool valid_node(const Session* s, int i) { return i >= 0 && static_cast<std::size_t>(i) < s->design.nodes.size(); }
bool valid_link(const Session* s, int i) { return i >= 0 && static_cast<std::size_t>(i) < s->design.links.size(); }

double distance(const soda::NodeDef& a, const soda::NodeDef& b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  return std::sqrt(dx * dx + dy * dy);
}

std::string hex_bits(double v) {
  std::uint64_t bits;
  static_assert(sizeof bits == sizeof v);
  __builtin_memcpy(&bits, &v, sizeof v);
  static const char* hex = "0123456789abcdef";
  std::string out(16, '0');
  for (int k = 15; k >= 0; --k, bits >>= 4) out[static_cast<std::size_t>(k)] = hex[bits & 15];
  return out;
}

/// Builds a model and its initial state from the design, as a run would.
void build(const soda::ModelDef& design, soda::Model& model, soda::State& state) {
  model = soda::build_model(design);
  state = soda::make_state(model);
}

} // namespace

extern "C" {

EMSCRIPTEN_KEEPALIVE Session* soda_new() { return new Session(); }
EMSCRIPTEN_KEEPALIVE void soda_delete(Session* s) { delete s; }
EMSCRIPTEN_KEEPALIVE const char* soda_message(Session* s) { return s->message.c_str(); }
EMSCRIPTEN_KEEPALIVE const char* soda_output(Session* s) { return s->output.data(); }
EMSCRIPTEN_KEEPALIVE int soda_output_length(Session* s) { return static_cast<int>(s->output.size()); }
EMSCRIPTEN_KEEPALIVE int soda_has_jitter() { return SODA_HAS_JITTER; }
EMSCRIPTEN_KEEPALIVE int soda_node_count(Session* s) { return static_cast<int>(s->design.nodes.size()); }

// --- files ------------------------------------------------------------------------

/// Reads model XML (v1 or v2, the bytes of the file) as `name`; on success it
/// becomes the design (warnings in soda_output, one per line) and the simulation
/// stops. On failure the design is kept.
EMSCRIPTEN_KEEPALIVE int soda_load_xml(Session* s, const char* bytes, int length, const char* name) {
  return guarded(s, [&] {
    soda::LoadedModel loaded = soda::read_model_text(std::string_view(bytes, static_cast<std::size_t>(length)), name);
    soda::Model model;
    soda::State state;
    build(loaded.def, model, state); // a file the engine refuses is refused here
    s->design = std::move(loaded.def);
    s->warnings = std::move(loaded.warnings);
    s->simulating = false;
    s->output.clear();
    for (const std::string& w : s->warnings) s->output += w + "\n";
  });
}

/// The design as canonical v1 XML (what `sodaevo convert` writes) in soda_output.
EMSCRIPTEN_KEEPALIVE int soda_save_xml(Session* s) {
  return guarded(s, [&] { s->output = soda::write_model_text(s->design); });
}

/// The design's world and name as JSON (see design_json) in soda_output.
EMSCRIPTEN_KEEPALIVE int soda_design_json(Session* s) {
  return guarded(s, [&] { s->output = design_json(s->design); });
}

EMSCRIPTEN_KEEPALIVE int soda_link_count(Session* s) { return static_cast<int>(s->design.links.size()); }

/// The design's nodes, then its links, as doubles: x, y, fixed (0 or 1) per node;
/// kind, a, b, rest length, amplitude, phase per link.
EMSCRIPTEN_KEEPALIVE const double* soda_design_numbers(Session* s) {
  const soda::ModelDef& d = s->design;
  s->numbers.resize(3 * d.nodes.size() + 6 * d.links.size());
  double* out = s->numbers.data();
  for (const soda::NodeDef& n : d.nodes) {
    *out++ = n.x;
    *out++ = n.y;
    *out++ = n.fixed ? 1.0 : 0.0;
  }
  for (const soda::LinkDef& l : d.links) {
    *out++ = static_cast<double>(l.kind);
    *out++ = l.a;
    *out++ = l.b;
    *out++ = l.rest_length;
    *out++ = l.amplitude;
    *out++ = l.phase;
  }
  return s->numbers.data();
}

/// The design and the last load's warnings as bytes (web/design_bytes.hpp) in
/// soda_output, for another engine's soda_import_design.
EMSCRIPTEN_KEEPALIVE int soda_export_design(Session* s) {
  return guarded(s, [&] { s->output = soda::web::design_to_bytes(s->design, s->warnings); });
}

/// Takes the design of soda_export_design's bytes, as soda_load_xml takes a file
/// (warnings in soda_output, the simulation stops). Not built again to check it:
/// the engine that exported it read it from a file it could build.
EMSCRIPTEN_KEEPALIVE int soda_import_design(Session* s, const char* bytes, int length) {
  return guarded(s, [&] {
    soda::web::design_from_bytes(std::string_view(bytes, static_cast<std::size_t>(length)), s->design, s->warnings);
    s->simulating = false;
    s->output.clear();
    for (const std::string& w : s->warnings) s->output += w + "\n";
  });
}

// --- editing ----------------------------------------------------------------------

/// Adds a mass (fixed = 0) or a fixed node; returns its index.
EMSCRIPTEN_KEEPALIVE int soda_add_node(Session* s, double x, double y, int fixed) {
  soda::NodeDef n;
  n.fixed = fixed != 0;
  n.x = x;
  n.y = y;
  n.id = (n.fixed ? "n" : "m") + std::to_string(s->design.nodes.size());
  s->design.nodes.push_back(n);
  return static_cast<int>(s->design.nodes.size()) - 1;
}

/// Moves node i; the springs and muscles at it take their new lengths as rest
/// lengths (a design is drawn at rest, as SodaConstructor's construct mode does).
EMSCRIPTEN_KEEPALIVE int soda_move_node(Session* s, int i, double x, double y) {
  if (!valid_node(s, i)) return fail(s, "no node " + std::to_string(i));
  s->design.nodes[static_cast<std::size_t>(i)].x = x;
  s->design.nodes[static_cast<std::size_t>(i)].y = y;
  for (soda::LinkDef& l : s->design.links) {
    if ((l.a == i || l.b == i) && l.kind != soda::LinkKind::FixedBar) {
      l.rest_length = distance(s->design.nodes[static_cast<std::size_t>(l.a)], s->design.nodes[static_cast<std::size_t>(l.b)]);
    }
  }
  return 1;
}

EMSCRIPTEN_KEEPALIVE int soda_set_fixed(Session* s, int i, int fixed) {
  if (!valid_node(s, i)) return fail(s, "no node " + std::to_string(i));
  soda::NodeDef& n = s->design.nodes[static_cast<std::size_t>(i)];
  n.fixed = fixed != 0;
  n.vx = n.vy = 0.0;
  return 1;
}

/// Removes node i and every link at it; later nodes move down one index.
EMSCRIPTEN_KEEPALIVE int soda_remove_node(Session* s, int i) {
  if (!valid_node(s, i)) return fail(s, "no node " + std::to_string(i));
  std::vector<soda::LinkDef> kept;
  for (soda::LinkDef l : s->design.links) {
    if (l.a == i || l.b == i) continue;
    if (l.a > i) --l.a;
    if (l.b > i) --l.b;
    kept.push_back(l);
  }
  s->design.links = std::move(kept);
  s->design.nodes.erase(s->design.nodes.begin() + i);
  return 1;
}

/// Adds a link of `kind` (0 spring, 1 muscle, 2 fixed bar) from node a to node b at
/// rest at its current length; returns its index, or -1 (message) for a bad pair.
EMSCRIPTEN_KEEPALIVE int soda_add_link(Session* s, int a, int b, int kind) {
  if (!valid_node(s, a) || !valid_node(s, b) || a == b || kind < 0 || kind > 2) {
    fail(s, "cannot link node " + std::to_string(a) + " to node " + std::to_string(b) + " as kind " +
                std::to_string(kind));
    return -1;
  }
  soda::LinkDef l;
  l.kind = static_cast<soda::LinkKind>(kind);
  l.a = a;
  l.b = b;
  if (l.kind != soda::LinkKind::FixedBar) {
    l.rest_length = distance(s->design.nodes[static_cast<std::size_t>(a)], s->design.nodes[static_cast<std::size_t>(b)]);
  }
  if (l.kind == soda::LinkKind::Muscle) l.amplitude = 0.5;
  s->design.links.push_back(l);
  return static_cast<int>(s->design.links.size()) - 1;
}

EMSCRIPTEN_KEEPALIVE int soda_remove_link(Session* s, int i) {
  if (!valid_link(s, i)) return fail(s, "no link " + std::to_string(i));
  s->design.links.erase(s->design.links.begin() + i);
  return 1;
}

/// Makes link i a spring (0) or a muscle (1) of `amplitude` in [0, 1] and `phase`
/// (cycles, wrapped into [0, 1) as the reader wraps it).
EMSCRIPTEN_KEEPALIVE int soda_set_link(Session* s, int i, int kind, double amplitude, double phase) {
  if (!valid_link(s, i)) return fail(s, "no link " + std::to_string(i));
  soda::LinkDef& l = s->design.links[static_cast<std::size_t>(i)];
  if (l.kind == soda::LinkKind::FixedBar || (kind != 0 && kind != 1)) {
    return fail(s, "link " + std::to_string(i) + ": only springs and muscles change kind");
  }
  if (!(amplitude >= 0.0 && amplitude <= 1.0) || !std::isfinite(phase)) {
    return fail(s, "link " + std::to_string(i) + ": expected an amplitude in [0, 1] and a finite phase");
  }
  l.kind = static_cast<soda::LinkKind>(kind);
  l.amplitude = kind == 1 ? amplitude : 0.0;
  l.phase = kind == 1 ? soda::wrap_phase(phase) : 0.0;
  return 1;
}

/// Sets one world value by name (the names of design_json). Ranges are checked
/// when the design is built (soda_reset), with the reader's messages.
EMSCRIPTEN_KEEPALIVE int soda_set_world(Session* s, const char* key, double value) {
  soda::ModelDef& d = s->design;
  const std::string_view k = key;
  if (!std::isfinite(value)) return fail(s, std::string(k) + ": expected a finite number");
  if (k == "gravity") d.environment.gravity = value;
  else if (k == "friction") d.environment.friction = value;
  else if (k == "springyness") d.environment.springyness = value;
  else if (k == "surfaceFriction") d.collisions.surface_friction = value;
  else if (k == "surfaceReflection") d.collisions.surface_reflection = value;
  else if (k == "waveAmplitude") d.wave.amplitude = value;
  else if (k == "wavePhase") d.wave.phase = soda::wrap_phase(value);
  else if (k == "waveSpeed") d.wave.speed = value;
  else if (k == "width" || k == "height") {
    if (!(value >= 1 && value <= static_cast<double>(soda::kMaxContainerSide)))
      return fail(s, std::string(k) + ": expected a side in [1, " + std::to_string(soda::kMaxContainerSide) + "]");
    (k == "width" ? d.width : d.height) = static_cast<int>(value);
  } else if (k == "gravityDirection" || k == "waveDirection") {
    if (value != -1 && value != 0 && value != 1) return fail(s, std::string(k) + ": expected -1, 0 or 1");
    if (k == "gravityDirection") d.settings.gravity_direction = static_cast<soda::GravityDirection>(static_cast<int>(value));
    else d.settings.wave_direction = static_cast<soda::WaveDirection>(static_cast<int>(value));
  } else if (k == "autoreverse") {
    d.settings.autoreverse = value != 0;
  } else {
    return fail(s, "unknown world value '" + std::string(k) + "'");
  }
  return 1;
}

EMSCRIPTEN_KEEPALIVE int soda_set_name(Session* s, const char* name) {
  s->design.name = name;
  return 1;
}

/// Empties the design (the default world, no nodes).
EMSCRIPTEN_KEEPALIVE void soda_clear(Session* s) {
  s->design = soda::ModelDef{};
  s->simulating = false;
}

// --- simulating ---------------------------------------------------------------

/// Builds the simulation from the design (frame 0). Fails, with the message the
/// command line gives, for a design the engine refuses.
EMSCRIPTEN_KEEPALIVE int soda_reset(Session* s) {
  return guarded(s, [&] {
    s->simulating = false;
    build(s->design, s->model, s->state);
    s->start = soda::mass_centroid(s->model, s->state);
    s->simulating = true;
  });
}

EMSCRIPTEN_KEEPALIVE int soda_step(Session* s, double frames) {
  if (!s->simulating) return fail(s, "not simulating: call soda_reset first");
  return guarded(s, [&] { soda::run(s->model, s->state, static_cast<long long>(frames)); });
}

EMSCRIPTEN_KEEPALIVE double soda_frame(Session* s) { return s->simulating ? static_cast<double>(s->state.frame) : 0.0; }
EMSCRIPTEN_KEEPALIVE double soda_wave_phase(Session* s) { return s->simulating ? s->state.wave_phase : s->design.wave.phase; }
EMSCRIPTEN_KEEPALIVE int soda_wave_mode(Session* s) {
  return static_cast<int>(s->simulating ? s->state.wave_mode : s->design.settings.wave_direction);
}

/// x, y of every design node (by its index in the design) in the simulation,
/// or as designed when not simulating; 2 doubles per node.
EMSCRIPTEN_KEEPALIVE const double* soda_positions(Session* s) {
  const std::size_t n = s->design.nodes.size();
  s->positions.assign(2 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    s->positions[2 * i] = s->design.nodes[i].x;
    s->positions[2 * i + 1] = s->design.nodes[i].y;
  }
  if (s->simulating) {
    for (int p = 0; p < s->model.point_count; ++p) {
      const auto node = static_cast<std::size_t>(s->model.node_of_point[static_cast<std::size_t>(p)]);
      s->positions[2 * node] = s->state.x[static_cast<std::size_t>(p)];
      s->positions[2 * node + 1] = s->state.y[static_cast<std::size_t>(p)];
    }
  }
  return s->positions.data();
}

/// Distance the mass centroid moved along x since the reset (px).
EMSCRIPTEN_KEEPALIVE double soda_distance(Session* s) {
  if (!s->simulating) return 0.0;
  return soda::mass_centroid(s->model, s->state).x - s->start.x;
}

/// The simulation's state as text, for comparing with the native engine bit for
/// bit: "frame F wave PHASE MODE" and one line per point in the engine's order
/// (masses, then fixed nodes) with the bits of x, y, vx, vy in hex.
EMSCRIPTEN_KEEPALIVE int soda_state_bits(Session* s) {
  if (!s->simulating) return fail(s, "not simulating: call soda_reset first");
  const soda::State& st = s->state;
  s->output = "frame " + std::to_string(st.frame) + " wave " + hex_bits(st.wave_phase) + " " +
              std::to_string(static_cast<int>(st.wave_mode)) + "\n";
  for (std::size_t p = 0; p < st.x.size(); ++p) {
    s->output += hex_bits(st.x[p]) + " " + hex_bits(st.y[p]) + " " + hex_bits(st.vx[p]) + " " + hex_bits(st.vy[p]) + "\n";
  }
  return 1;
}

/// The replica statistics of the design (see web/README.md): `replicas` runs of
/// `frames` frames from the designed state, replica r with sine jitter seed r + 1
/// (a replica's other libm) of `probability`, each scored by the distance its mass
/// centroid moved along x per frame. soda_output: JSON {"exact": px/frame without
/// jitter, "values": [per replica]}; the page takes mean and spread.
EMSCRIPTEN_KEEPALIVE int soda_replicas(Session* s, int replicas, double frames, double probability) {
  return guarded(s, [&] {
    if (replicas < 0 || replicas > 1000 || !(frames >= 1 && frames <= 1e7) || !(probability >= 0 && probability <= 1)) {
      throw soda::InputError("replicas: expected 0-1000 replicas, 1-10000000 frames and a probability in [0, 1]");
    }
    soda::Model model;
    soda::State initial;
    build(s->design, model, initial);
    const auto frames_ll = static_cast<long long>(frames);
    const auto speed = [&](soda::State state) {
      const double x0 = soda::mass_centroid(model, state).x;
      soda::run(model, state, frames_ll);
      return (soda::mass_centroid(model, state).x - x0) / frames;
    };
    std::string j = "{\"exact\":" + number(speed(initial)) + ",\"values\":[";
    for (int r = 0; r < replicas; ++r) {
      soda::State state = initial;
#if SODA_HAS_JITTER
      state.jitter.seed = static_cast<std::uint64_t>(r) + 1;
      state.jitter.probability = probability;
#endif
      j += (r ? "," : "") + number(speed(state));
    }
    s->output = j + "]}";
  });
}

} // extern "C"
