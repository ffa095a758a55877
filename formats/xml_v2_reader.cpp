// Reader of the SodaConstructor 2 object graph (docs/file-formats.md, v2),
// mapped onto the v1 model.
//
// An object is `<object id=".." type="..">` holding `<field name="..">` children,
// each with one value element: <double>, <int>, <boolean>, <string>, <ref refid=".."/>,
// <object> or <list>. The v2 application's value ranges are unknown and wider than
// v1's, so values outside a v1 range are clamped into it with a warning (a converted
// file must load in the original v1 engine); non-finite or malformed values are errors.

#include <algorithm>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "core/model_def.hpp"
#include "core/number_text.hpp"
#include "formats/xml_util.hpp"

namespace soda::xml {

namespace {

/// The part of a Java class name after the last '.'.
std::string_view simple_type(std::string_view type) {
  const std::size_t dot = type.rfind('.');
  return dot == std::string_view::npos ? type : type.substr(dot + 1);
}

/// The fields of one <object>, by name. Duplicate or nameless fields are errors,
/// fields not in `known` are ignored with a warning.
class Fields {
 public:
  Fields(ReadContext& ctx, pugi::xml_node object, std::initializer_list<const char*> known,
         std::initializer_list<const char*> ignored = {})
      : ctx_(ctx), object_(object) {
    for (pugi::xml_node child : object.children()) {
      if (child.type() != pugi::node_element) continue;
      if (std::string_view(child.name()) != "field") {
        ctx.warn(child, nullptr, "unknown element ignored (expected <field>)");
        continue;
      }
      pugi::xml_attribute name_attr = child.attribute("name");
      if (!name_attr) ctx.fail(child, "name", "expected a field name, got nothing");
      const std::string name = name_attr.value();
      const bool is_known = std::any_of(known.begin(), known.end(), [&](const char* k) { return name == k; });
      const bool is_ignored =
          std::any_of(ignored.begin(), ignored.end(), [&](const char* k) { return name == k; });
      if (!is_known) {
        if (!is_ignored) ctx.warn(child, nullptr, "unknown field ignored");
        continue;
      }
      const auto [it, inserted] = fields_.emplace(name, child);
      if (!inserted) {
        ctx.fail(
            child, nullptr,
            "expected each field once, got a second one (the first is at " + ctx.where(it->second) + ")");
      }
    }
  }

  /// The field element, or an empty node if the object does not have it.
  [[nodiscard]] pugi::xml_node find(const char* name) const {
    const auto it = fields_.find(name);
    return it == fields_.end() ? pugi::xml_node() : it->second;
  }

  [[nodiscard]] pugi::xml_node require(const char* name, std::string_view what) const {
    pugi::xml_node field = find(name);
    if (!field) {
      ctx_.fail(object_, nullptr,
                "expected a field '" + std::string(name) + "' (" + std::string(what) + "), got none");
    }
    return field;
  }

 private:
  ReadContext& ctx_;
  pugi::xml_node object_;
  std::unordered_map<std::string, pugi::xml_node> fields_;
};

/// The typed values of v2 fields.
class Values {
 public:
  explicit Values(ReadContext& ctx) : ctx_(ctx) {}

  /// The one value element of a field, which must be a `tag`.
  [[nodiscard]] pugi::xml_node value(pugi::xml_node field, const char* tag) const {
    pugi::xml_node found;
    int count = 0;
    for (pugi::xml_node child : field.children()) {
      if (child.type() != pugi::node_element) continue;
      if (++count == 1) found = child;
    }
    if (count != 1) {
      ctx_.fail(field, nullptr,
                "expected one <" + std::string(tag) + "> value, got " + std::to_string(count) + " elements");
    }
    if (std::string_view(found.name()) != tag) {
      ctx_.fail(field, nullptr, "expected a <" + std::string(tag) + "> value, got <" + found.name() + ">");
    }
    return found;
  }

  [[nodiscard]] double number(pugi::xml_node field) const {
    const char* text = value(field, "double").text().get();
    std::optional<double> v = parse_double(text);
    if (!v) ctx_.fail(field, nullptr, "expected a finite number in <double>, got " + quote(text));
    return *v;
  }

  [[nodiscard]] long long integer(pugi::xml_node field) const {
    const char* text = value(field, "int").text().get();
    std::optional<long long> v = parse_integer(text);
    if (!v) ctx_.fail(field, nullptr, "expected an integer in <int>, got " + quote(text));
    return *v;
  }

  [[nodiscard]] bool boolean(pugi::xml_node field) const {
    const std::string_view text = value(field, "boolean").text().get();
    if (text == "true") return true;
    if (text == "false") return false;
    ctx_.fail(field, nullptr, "expected true or false in <boolean>, got " + quote(text));
  }

  [[nodiscard]] std::string string(pugi::xml_node field) const {
    return element_text(ctx_, value(field, "string"));
  }

  /// What the v1 parser does with a value outside its range.
  enum class V1 { Rejects, Clamps, ClampsAbove };

  /// A number the v1 engine accepts only inside `range`: clamped into it, with a
  /// warning, when the v2 file holds a value outside.
  [[nodiscard]] double clamped(pugi::xml_node field, Range range, V1 v1 = V1::Rejects) const {
    const double v = number(field);
    const double c = std::min(std::max(v, range.min), range.max);
    if (c != v) {
      const bool v1_clamps = v1 == V1::Clamps || (v1 == V1::ClampsAbove && v > range.max);
      ctx_.warn(field, nullptr,
                format_double_plain(v) + " is outside the v1 range " + range_text(range) + "; clamped to " +
                    format_double_plain(c) +
                    (v1_clamps ? std::string(" (as the original v1 engine does)")
                               : " (the original v1 engine would reject " + format_double_plain(v) + ")"));
    }
    return c;
  }

  /// A Java object value of the given simple type (e.g. "Wave").
  [[nodiscard]] pugi::xml_node object(pugi::xml_node field, std::string_view type) const {
    pugi::xml_node obj = value(field, "object");
    if (simple_type(obj.attribute("type").value()) != type) {
      ctx_.fail(obj, "type",
                "expected an object of type ..." + std::string(type) + ", got " +
                    quote(obj.attribute("type").value()));
    }
    return obj;
  }

 private:
  ReadContext& ctx_;
};

void read_wave(ReadContext& ctx, const Values& values, pugi::xml_node wave_field, ModelDef& def) {
  const pugi::xml_node obj = values.object(wave_field, "Wave");
  const Fields f(ctx, obj, {"amplitude", "direction", "phase", "speed"});
  WaveDef& wave = def.wave;
  if (pugi::xml_node field = f.find("amplitude"))
    wave.amplitude = values.clamped(field, kAmplitudeRange, Values::V1::ClampsAbove);
  if (pugi::xml_node field = f.find("phase")) wave.phase = wrap_phase(values.number(field));
  if (pugi::xml_node field = f.find("speed")) wave.speed = values.number(field);
  if (pugi::xml_node field = f.find("direction")) {
    const std::string dir = values.string(field);
    if (dir == "forward") {
      def.settings.wave_direction = WaveDirection::Forward;
    } else if (dir == "reverse") {
      def.settings.wave_direction = WaveDirection::Reverse;
    } else if (dir == "manual") {
      def.settings.wave_direction = WaveDirection::Manual;
    } else {
      ctx.fail(field, nullptr, "expected forward, reverse or manual, got " + quote(dir));
    }
  }
}

void read_nodes(ReadContext& ctx, const Values& values, pugi::xml_node nodes_field, ModelDef& def,
                std::unordered_map<std::string, int>& index_of) {
  const pugi::xml_node list = values.value(nodes_field, "list");
  for (pugi::xml_node obj : list.children()) {
    if (obj.type() != pugi::node_element) continue;
    if (std::string_view(obj.name()) != "object") {
      ctx.fail(obj, nullptr,
               "expected an <object> of type Mass or Node in the nodes list, got <" +
                   std::string(obj.name()) + ">");
    }
    const std::string_view type = simple_type(obj.attribute("type").value());
    const bool fixed = type == "Node";
    if (!fixed && type != "Mass") {
      ctx.fail(obj, "type",
               "expected an object of type ...model.Mass or ...model.Node in the nodes list, got " +
                   quote(obj.attribute("type").value()));
    }
    if (static_cast<long>(def.nodes.size()) >= kMaxNodes) {
      ctx.fail(obj, nullptr,
               "expected at most " + std::to_string(kMaxNodes) +
                   " nodes and masses, got more (a limit of this program)");
    }
    NodeDef node;
    node.fixed = fixed;
    node.id = obj.attribute("id").value();
    if (node.id.empty()) ctx.fail(obj, "id", "expected a non-empty object id, got ''");
    const Fields f = fixed ? Fields(ctx, obj, {"x", "y"}) : Fields(ctx, obj, {"vx", "vy", "x", "y"});
    node.x = values.number(f.require("x", "a <double>"));
    node.y = values.number(f.require("y", "a <double>"));
    if (!fixed) {
      node.vx = values.number(f.require("vx", "a <double>"));
      node.vy = values.number(f.require("vy", "a <double>"));
    }
    const auto [it, inserted] = index_of.emplace(node.id, static_cast<int>(def.nodes.size()));
    if (!inserted) ctx.fail(obj, "id", "expected an object id not used before, got " + quote(node.id));
    def.nodes.push_back(std::move(node));
  }
}

void read_springs(ReadContext& ctx, const Values& values, pugi::xml_node springs_field, ModelDef& def,
                  const std::unordered_map<std::string, int>& index_of) {
  const pugi::xml_node list = values.value(springs_field, "list");
  for (pugi::xml_node obj : list.children()) {
    if (obj.type() != pugi::node_element) continue;
    if (std::string_view(obj.name()) != "object") {
      ctx.fail(obj, nullptr,
               "expected an <object> of type Spring or Muscle in the springs list, got <" +
                   std::string(obj.name()) + ">");
    }
    const std::string_view type = simple_type(obj.attribute("type").value());
    LinkDef link;
    if (type == "Spring") {
      link.kind = LinkKind::Spring;
    } else if (type == "Muscle") {
      link.kind = LinkKind::Muscle;
    } else {
      ctx.fail(obj, "type",
               "expected an object of type ...model.Spring or ...model.Muscle in the springs list, got " +
                   quote(obj.attribute("type").value()));
    }
    if (static_cast<long>(def.links.size()) >= kMaxLinks) {
      ctx.fail(
          obj, nullptr,
          "expected at most " + std::to_string(kMaxLinks) + " links, got more (a limit of this program)");
    }
    const Fields f = link.kind == LinkKind::Spring
                         ? Fields(ctx, obj, {"a", "b", "restLength"})
                         : Fields(ctx, obj, {"a", "amplitude", "b", "phase", "restLength"});
    const auto endpoint = [&](const char* name) {
      const pugi::xml_node field = f.require(name, "a <ref> to a Mass or Node");
      const pugi::xml_node ref = values.value(field, "ref");
      const pugi::xml_attribute refid = ref.attribute("refid");
      if (!refid) ctx.fail(ref, "refid", "expected the id of a Mass or Node, got nothing");
      const auto it = index_of.find(refid.value());
      if (it == index_of.end()) {
        ctx.fail(ref, "refid",
                 "expected the id of a Mass or Node in the nodes list, got " + quote(refid.value()) +
                     " (no such object)");
      }
      return it->second;
    };
    link.a = endpoint("a");
    link.b = endpoint("b");
    if (link.a == link.b) {
      ctx.fail(obj, nullptr,
               "expected two different nodes, got a = b = " +
                   quote(def.nodes[static_cast<std::size_t>(link.a)].id));
    }
    link.rest_length = values.number(f.require("restLength", "a <double>"));
    if (link.kind == LinkKind::Muscle) {
      link.amplitude =
          values.clamped(f.require("amplitude", "a <double>"), kAmplitudeRange, Values::V1::Clamps);
      link.phase = wrap_phase(values.number(f.require("phase", "a <double>")));
    }
    def.links.push_back(link);
  }
}

} // namespace

void read_v2_model(ReadContext& ctx, pugi::xml_node root, ModelDef& def) {
  const Values values(ctx);
  pugi::xml_node model = root;
  const std::string_view root_type = simple_type(root.attribute("type").value());
  if (root_type == "ConstructorApplication") {
    const Fields app(ctx, root, {"model"});
    model = values.object(app.require("model", "the Model"), "Model");
  } else if (root_type != "Model") {
    ctx.fail(root, "type",
             "expected com.sodaplay.soda.constructor2.ConstructorApplication or ...model.Model, got " +
                 quote(root.attribute("type").value()));
  }

  const Fields f(ctx, model,
                 {"autoReverse", "comment", "friction", "gravity", "gravityDirection", "height", "name",
                  "nodes", "springs", "springyness", "surfaceFriction", "surfaceReflection", "wave", "width"},
                 {"metadata"});
  if (pugi::xml_node field = f.find("comment")) def.comment = values.string(field);
  if (pugi::xml_node field = f.find("name")) def.name = values.string(field);
  for (auto [name, side] : {std::pair{"width", &def.width}, std::pair{"height", &def.height}}) {
    if (pugi::xml_node field = f.find(name)) {
      const long long v = values.integer(field);
      if (v < 1 || v > kMaxContainerSide) {
        ctx.fail(field, nullptr,
                 "expected an integer in [1, " + std::to_string(kMaxContainerSide) + "], got " +
                     quote(std::to_string(v)));
      }
      *side = static_cast<int>(v);
    }
  }
  EnvironmentDef& env = def.environment;
  if (pugi::xml_node field = f.find("gravity")) env.gravity = values.clamped(field, kGravityRange);
  if (pugi::xml_node field = f.find("friction")) env.friction = values.clamped(field, kFrictionRange);
  if (pugi::xml_node field = f.find("springyness"))
    env.springyness = values.clamped(field, kSpringynessRange);
  CollisionsDef& col = def.collisions;
  if (pugi::xml_node field = f.find("surfaceFriction")) {
    col.surface_friction = values.clamped(field, kSurfaceFrictionRange);
  }
  if (pugi::xml_node field = f.find("surfaceReflection")) {
    col.surface_reflection = values.clamped(field, kSurfaceReflectionRange);
  }
  if (pugi::xml_node field = f.find("gravityDirection")) {
    const long long d = values.integer(field);
    if (d != 1 && d != -1 && d != 0) {
      ctx.fail(field, nullptr, "expected 1 (down), -1 (up) or 0 (off), got " + quote(std::to_string(d)));
    }
    def.settings.gravity_direction = static_cast<GravityDirection>(d);
  }
  if (pugi::xml_node field = f.find("autoReverse")) def.settings.autoreverse = values.boolean(field);
  if (pugi::xml_node field = f.find("wave")) read_wave(ctx, values, field, def);

  std::unordered_map<std::string, int> index_of;
  const pugi::xml_node nodes = f.find("nodes");
  if (nodes) read_nodes(ctx, values, nodes, def, index_of);
  if (def.nodes.empty()) {
    ctx.fail(nodes ? nodes : model, nullptr, "empty model: expected at least one Mass or Node, got none");
  }
  if (pugi::xml_node field = f.find("springs")) read_springs(ctx, values, field, def, index_of);
}

} // namespace soda::xml
