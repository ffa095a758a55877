// Reader of the v1 `<model>` format (docs/file-formats.md, v1).
//
// Unlike the original parser, this one does not depend on element order: every
// child of <model> is found first, then the header, the nodes and the links are
// read in that order. Defaults, clamps and wraps are the original's; everything
// the original would crash on or silently misread is an error here.

#include <cstring>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include "core/model_def.hpp"
#include "core/number_text.hpp"
#include "formats/xml_util.hpp"

namespace soda::xml {

namespace {

/// The attributes of one element: duplicates are errors, unknown names warnings.
class Attributes {
 public:
  Attributes(ReadContext& ctx, pugi::xml_node element, std::initializer_list<const char*> known)
      : ctx_(ctx), element_(element) {
    std::unordered_set<std::string_view> seen;
    for (pugi::xml_attribute attr : element.attributes()) {
      const std::string_view name = attr.name();
      if (!seen.insert(name).second) ctx.fail(element, attr.name(), "attribute given twice");
      bool is_known = false;
      for (const char* k : known) is_known = is_known || name == k;
      if (!is_known) ctx.warn(element, attr.name(), "unknown attribute ignored");
    }
  }

  /// The attribute's text, or nullptr if it is absent.
  [[nodiscard]] const char* find(const char* name) const {
    pugi::xml_attribute attr = element_.attribute(name);
    return attr ? attr.value() : nullptr;
  }

  [[nodiscard]] const char* require(const char* name, std::string_view expected) const {
    const char* value = find(name);
    if (value == nullptr) {
      ctx_.fail(element_, name,
                "expected " + std::string(expected) + ", got nothing (the attribute is required)");
    }
    return value;
  }

  [[nodiscard]] double number(const char* name, const char* text) const {
    std::optional<double> v = parse_double(text);
    if (!v) ctx_.fail(element_, name, "expected a finite number, got " + quote(text));
    return *v;
  }

  [[nodiscard]] double required_number(const char* name) const {
    return number(name, require(name, "a finite number"));
  }

  /// An optional number that must lie in `range` (the original rejects the file
  /// otherwise); `fallback` if absent.
  [[nodiscard]] double ranged(const char* name, Range range, double fallback) const {
    const char* text = find(name);
    if (text == nullptr) return fallback;
    std::optional<double> v = parse_double(text);
    if (!v || !range.contains(*v)) {
      ctx_.fail(element_, name, "expected a number in " + range_text(range) + ", got " + quote(text));
    }
    return *v;
  }

  [[nodiscard]] int container_side(const char* name, int fallback) const {
    const char* text = find(name);
    if (text == nullptr) return fallback;
    std::optional<long long> v = parse_integer(text);
    if (!v || *v < 1 || *v > kMaxContainerSide) {
      ctx_.fail(element_, name,
                "expected an integer in [1, " + std::to_string(kMaxContainerSide) + "], got " + quote(text));
    }
    return static_cast<int>(*v);
  }

  /// One of `names` (mapped to `values`), or `fallback` if absent.
  template <typename T, std::size_t N>
  [[nodiscard]] T choice(const char* name, const char* const (&names)[N], const T (&values)[N],
                         T fallback) const {
    const char* text = find(name);
    if (text == nullptr) return fallback;
    std::string allowed;
    for (std::size_t i = 0; i < N; ++i) {
      if (std::strcmp(text, names[i]) == 0) return values[i];
      allowed += (i == 0 ? "" : (i + 1 == N ? " or " : ", "));
      allowed += names[i];
    }
    ctx_.fail(element_, name, "expected " + allowed + ", got " + quote(text));
  }

 private:
  ReadContext& ctx_;
  pugi::xml_node element_;
};

/// The children of <model> this reader knows, found before anything is read.
struct ModelElements {
  pugi::xml_node comment, name, container, environment, collisions, wave, settings, nodes, links;
};

ModelElements find_elements(ReadContext& ctx, pugi::xml_node model) {
  ModelElements e;
  struct Slot {
    const char* tag;
    pugi::xml_node* node;
  };
  const Slot slots[] = {{"comment", &e.comment},
                        {"name", &e.name},
                        {"container", &e.container},
                        {"environment", &e.environment},
                        {"collisions", &e.collisions},
                        {"wave", &e.wave},
                        {"settings", &e.settings},
                        {"nodes", &e.nodes},
                        {"links", &e.links}};
  for (pugi::xml_node child : model.children()) {
    if (child.type() != pugi::node_element) continue;
    const std::string_view tag = child.name();
    bool known = false;
    for (const Slot& slot : slots) {
      if (tag != slot.tag) continue;
      known = true;
      if (*slot.node) {
        ctx.fail(child, nullptr,
                 "expected at most one <" + std::string(tag) +
                     "> in <model>, got a second one (the first is at " + ctx.where(*slot.node) + ")");
      }
      *slot.node = child;
    }
    if (!known && tag != "polys") ctx.warn(child, nullptr, "unknown element ignored");
  }
  return e;
}

void read_header(ReadContext& ctx, const ModelElements& e, ModelDef& def) {
  if (e.comment) {
    Attributes(ctx, e.comment, {});
    def.comment = element_text(ctx, e.comment);
  }
  if (e.name) {
    Attributes(ctx, e.name, {});
    def.name = element_text(ctx, e.name);
  }
  if (e.container) {
    Attributes a(ctx, e.container, {"width", "height"});
    def.width = a.container_side("width", def.width);
    def.height = a.container_side("height", def.height);
  }
  if (e.environment) {
    Attributes a(ctx, e.environment, {"gravity", "friction", "springyness"});
    EnvironmentDef& env = def.environment;
    env.gravity = a.ranged("gravity", kGravityRange, env.gravity);
    env.friction = a.ranged("friction", kFrictionRange, env.friction);
    env.springyness = a.ranged("springyness", kSpringynessRange, env.springyness);
  }
  if (e.collisions) {
    Attributes a(ctx, e.collisions, {"surface_friction", "surface_reflection"});
    CollisionsDef& col = def.collisions;
    col.surface_friction = a.ranged("surface_friction", kSurfaceFrictionRange, col.surface_friction);
    col.surface_reflection = a.ranged("surface_reflection", kSurfaceReflectionRange, col.surface_reflection);
  }
  if (e.wave) {
    Attributes a(ctx, e.wave, {"amplitude", "phase", "speed"});
    WaveDef& wave = def.wave;
    if (const char* text = a.find("amplitude")) {
      const double amplitude = a.number("amplitude", text);
      if (amplitude < kAmplitudeRange.min) {
        ctx.fail(e.wave, "amplitude",
                 "expected a number >= 0 (values above 1 are clamped to 1), got " + quote(text));
      }
      wave.amplitude = amplitude;
      if (amplitude > kAmplitudeRange.max) {
        wave.amplitude = kAmplitudeRange.max;
        ctx.warn(e.wave, "amplitude", quote(text) + " is above 1; clamped to 1 (as the original does)");
      }
    }
    if (const char* text = a.find("phase")) wave.phase = wrap_phase(a.number("phase", text));
    if (const char* text = a.find("speed")) wave.speed = a.number("speed", text);
  }
  if (e.settings) {
    Attributes a(ctx, e.settings, {"gravitydirection", "wavedirection", "autoreverse"});
    SettingsDef& s = def.settings;
    static const char* const gravity_names[] = {"down", "up", "off"};
    static const GravityDirection gravity_values[] = {GravityDirection::Down, GravityDirection::Up,
                                                      GravityDirection::Off};
    s.gravity_direction = a.choice("gravitydirection", gravity_names, gravity_values, s.gravity_direction);
    static const char* const wave_names[] = {"forward", "reverse", "manual"};
    static const WaveDirection wave_values[] = {WaveDirection::Forward, WaveDirection::Reverse,
                                                WaveDirection::Manual};
    s.wave_direction = a.choice("wavedirection", wave_names, wave_values, s.wave_direction);
    static const char* const onoff_names[] = {"on", "off"};
    static const bool onoff_values[] = {true, false};
    s.autoreverse = a.choice("autoreverse", onoff_names, onoff_values, s.autoreverse);
  }
}

void read_nodes(ReadContext& ctx, pugi::xml_node nodes, ModelDef& def,
                std::unordered_map<std::string, int>& index_of) {
  Attributes(ctx, nodes, {});
  for (pugi::xml_node child : nodes.children()) {
    if (child.type() != pugi::node_element) continue;
    const std::string_view tag = child.name();
    const bool fixed = tag == "node";
    if (!fixed && tag != "mass") {
      ctx.warn(child, nullptr, "unknown element ignored (expected <node> or <mass>)");
      continue;
    }
    if (static_cast<long>(def.nodes.size()) >= kMaxNodes) {
      ctx.fail(child, nullptr,
               "expected at most " + std::to_string(kMaxNodes) +
                   " nodes and masses, got more (a limit of this program)");
    }
    Attributes a = fixed ? Attributes(ctx, child, {"id", "x", "y"})
                         : Attributes(ctx, child, {"id", "x", "y", "vx", "vy"});
    NodeDef node;
    node.fixed = fixed;
    node.id = a.require("id", "an id");
    if (node.id.empty()) ctx.fail(child, "id", "expected a non-empty id, got ''");
    node.x = a.required_number("x");
    node.y = a.required_number("y");
    if (!fixed) {
      node.vx = a.required_number("vx");
      node.vy = a.required_number("vy");
    }
    const auto [it, inserted] = index_of.emplace(node.id, static_cast<int>(def.nodes.size()));
    if (!inserted) {
      ctx.fail(child, "id",
               "expected an id not used before, got " + quote(node.id) + " (already the id of the " +
                   (def.nodes[static_cast<std::size_t>(it->second)].fixed ? "node" : "mass") + " at index " +
                   std::to_string(it->second) + ")");
    }
    def.nodes.push_back(std::move(node));
  }
}

void read_links(ReadContext& ctx, pugi::xml_node links, ModelDef& def,
                const std::unordered_map<std::string, int>& index_of) {
  Attributes(ctx, links, {});
  for (pugi::xml_node child : links.children()) {
    if (child.type() != pugi::node_element) continue;
    const std::string_view tag = child.name();
    LinkDef link;
    if (tag == "spring") {
      link.kind = LinkKind::Spring;
    } else if (tag == "muscle") {
      link.kind = LinkKind::Muscle;
    } else if (tag == "fixedbar") {
      link.kind = LinkKind::FixedBar;
    } else {
      ctx.warn(child, nullptr, "unknown element ignored (expected <spring>, <muscle> or <fixedbar>)");
      continue;
    }
    if (static_cast<long>(def.links.size()) >= kMaxLinks) {
      ctx.fail(
          child, nullptr,
          "expected at most " + std::to_string(kMaxLinks) + " links, got more (a limit of this program)");
    }
    Attributes a = link.kind == LinkKind::Spring ? Attributes(ctx, child, {"a", "b", "restlength"})
                   : link.kind == LinkKind::Muscle
                       ? Attributes(ctx, child, {"a", "b", "restlength", "amplitude", "phase"})
                       : Attributes(ctx, child, {"a", "b"});
    const auto endpoint = [&](const char* attr) {
      const char* id = a.require(attr, "the id of a <node> or <mass>");
      const auto it = index_of.find(id);
      if (it == index_of.end()) {
        ctx.fail(child, attr,
                 "expected the id of a <node> or <mass> in <nodes>, got " + quote(id) + " (no such id)");
      }
      return it->second;
    };
    link.a = endpoint("a");
    link.b = endpoint("b");
    // The original reads a link from a node to itself: the engine skips it (length
    // 0), the Sodarace racer keeps it and counts its rest length in the scale.
    if (link.a == link.b) {
      ctx.warn(child, "b",
               "a link from " + quote(a.find("b")) + " to itself: kept (no force; the Sodarace racer counts its "
               "rest length in its scale), but simulate refuses it");
    }
    if (link.kind != LinkKind::FixedBar) link.rest_length = a.required_number("restlength");
    if (link.kind == LinkKind::Muscle) {
      const char* text = a.require("amplitude", "a finite number");
      const double amplitude = a.number("amplitude", text);
      link.amplitude = std::min(std::max(amplitude, kAmplitudeRange.min), kAmplitudeRange.max);
      if (link.amplitude != amplitude) {
        ctx.warn(child, "amplitude",
                 quote(text) + " is outside " + range_text(kAmplitudeRange) + "; clamped to " +
                     format_double_plain(link.amplitude) + " (as the original does)");
      }
      // The original wraps the phase silently; real files rely on it (phase="1.000").
      link.phase = wrap_phase(a.required_number("phase"));
    }
    def.links.push_back(link);
  }
}

} // namespace

void read_v1_model(ReadContext& ctx, pugi::xml_node model, ModelDef& def) {
  Attributes(ctx, model, {});
  const ModelElements e = find_elements(ctx, model);
  read_header(ctx, e, def);
  std::unordered_map<std::string, int> index_of;
  if (e.nodes) read_nodes(ctx, e.nodes, def, index_of);
  if (def.nodes.empty()) {
    ctx.fail(e.nodes ? e.nodes : model, nullptr,
             "empty model: expected at least one <node> or <mass> inside <nodes>, got none");
  }
  if (e.links) read_links(ctx, e.links, def, index_of);
}

} // namespace soda::xml
