// Writer of canonical v1 XML (docs/file-formats.md): the original writer's layout and element
// order, ids and link order of canonical_form(), numbers shortest round-trip, and
// text escaped for an ISO-8859-1 document (the original did not escape).

#include <cmath>

#include "core/number_text.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"
#include "formats/xml_escape.hpp"
#include "formats/xml_util.hpp"

namespace soda {

namespace {

[[noreturn]] void refuse(const std::string& what) { throw InputError("cannot write the model: " + what); }

void check_finite(double v, const std::string& what) {
  if (!std::isfinite(v)) refuse(what + " is " + format_double_plain(v) + ", expected a finite number");
}

void check_range(double v, Range range, const std::string& what) {
  check_finite(v, what);
  if (!range.contains(v)) {
    refuse(what + " is " + format_double_plain(v) + ", expected a number in " + xml::range_text(range) +
           " (the reader would reject the file)");
  }
}

void check_phase(double v, const std::string& what) {
  check_finite(v, what);
  if (!(v >= 0.0 && v < 1.0)) {
    refuse(what + " is " + format_double_plain(v) + ", expected a phase in [0, 1) (use wrap_phase)");
  }
}

/// Everything a file must satisfy for the reader to read it back unchanged.
void check_writable(const ModelDef& def) {
  if (def.width < 1 || def.width > kMaxContainerSide || def.height < 1 || def.height > kMaxContainerSide) {
    refuse("container " + std::to_string(def.width) + "x" + std::to_string(def.height) +
           ", expected sides in [1, " + std::to_string(kMaxContainerSide) + "]");
  }
  check_range(def.environment.gravity, kGravityRange, "gravity");
  check_range(def.environment.friction, kFrictionRange, "friction");
  check_range(def.environment.springyness, kSpringynessRange, "springyness");
  check_range(def.collisions.surface_friction, kSurfaceFrictionRange, "surface_friction");
  check_range(def.collisions.surface_reflection, kSurfaceReflectionRange, "surface_reflection");
  check_range(def.wave.amplitude, kAmplitudeRange, "wave amplitude");
  check_phase(def.wave.phase, "wave phase");
  check_finite(def.wave.speed, "wave speed");
  const int gd = static_cast<int>(def.settings.gravity_direction);
  const int wd = static_cast<int>(def.settings.wave_direction);
  if (gd < -1 || gd > 1) refuse("gravity direction " + std::to_string(gd) + ", expected -1, 0 or 1");
  if (wd < -1 || wd > 1) refuse("wave direction " + std::to_string(wd) + ", expected -1, 0 or 1");

  if (def.nodes.empty()) refuse("it has no nodes (the reader rejects an empty model)");
  if (static_cast<long>(def.nodes.size()) > kMaxNodes)
    refuse("more than " + std::to_string(kMaxNodes) + " nodes");
  if (static_cast<long>(def.links.size()) > kMaxLinks)
    refuse("more than " + std::to_string(kMaxLinks) + " links");
  for (std::size_t i = 0; i < def.nodes.size(); ++i) {
    const NodeDef& n = def.nodes[i];
    const std::string what = "node " + std::to_string(i) + " ('" + n.id + "') ";
    check_finite(n.x, what + "x");
    check_finite(n.y, what + "y");
    check_finite(n.vx, what + "vx");
    check_finite(n.vy, what + "vy");
  }
  const int node_count = static_cast<int>(def.nodes.size());
  for (std::size_t i = 0; i < def.links.size(); ++i) {
    const LinkDef& l = def.links[i];
    const std::string what = "link " + std::to_string(i) + " ";
    if (l.a < 0 || l.a >= node_count || l.b < 0 || l.b >= node_count) {
      refuse(what + "joins nodes " + std::to_string(l.a) + " and " + std::to_string(l.b) +
             ", expected indices in [0, " + std::to_string(node_count - 1) + "]");
    }
    // A link from a node to itself is written (the reader keeps it, as the original).
    if (l.kind != LinkKind::Spring && l.kind != LinkKind::Muscle && l.kind != LinkKind::FixedBar) {
      refuse(what + "has an unknown kind " + std::to_string(static_cast<int>(l.kind)));
    }
    check_finite(l.rest_length, what + "rest length");
    if (l.kind == LinkKind::Muscle) {
      check_range(l.amplitude, kAmplitudeRange, what + "amplitude");
      check_phase(l.phase, what + "phase");
    }
  }
}

std::string attr(const char* name, double v) {
  return std::string(" ") + name + "=\"" + format_double(v) + "\"";
}

std::string id_attr(const char* name, const std::string& id) {
  std::string out = std::string(" ") + name + "=\"";
  append_xml_escaped(out, id, true);
  return out + "\"";
}

const char* gravity_name(GravityDirection d) {
  switch (d) {
    case GravityDirection::Up: return "up";
    case GravityDirection::Off: return "off";
    case GravityDirection::Down: break;
  }
  return "down";
}

const char* wave_name(WaveDirection d) {
  switch (d) {
    case WaveDirection::Reverse: return "reverse";
    case WaveDirection::Manual: return "manual";
    case WaveDirection::Forward: break;
  }
  return "forward";
}

} // namespace

std::string write_model_text(const ModelDef& input) {
  check_writable(input);
  const ModelDef def = canonical_form(input);
  std::string out;
  out.reserve(256 + def.nodes.size() * 80 + def.links.size() * 80);
  out += "<?xml version=\"1.0\" encoding=\"ISO-8859-1\" standalone=\"no\"?>\n";
  out += "<!DOCTYPE sodaconstructor>\n";
  out += "<model>\n";
  out += "\t<comment>";
  append_xml_escaped(out, def.comment, false);
  out += "</comment>\n";
  if (!def.name.empty()) {
    out += "\t<name>";
    append_xml_escaped(out, def.name, false);
    out += "</name>\n";
  }
  out += "\t<container width=\"" + std::to_string(def.width) + "\" height=\"" + std::to_string(def.height) +
         "\"/>\n";
  out += "\t<environment" + attr("gravity", def.environment.gravity) +
         attr("friction", def.environment.friction) + attr("springyness", def.environment.springyness) +
         "/>\n";
  out += "\t<collisions" + attr("surface_friction", def.collisions.surface_friction) +
         attr("surface_reflection", def.collisions.surface_reflection) + "/>\n";
  out += "\t<wave" + attr("amplitude", def.wave.amplitude) + attr("phase", def.wave.phase) +
         attr("speed", def.wave.speed) + "/>\n";
  out += std::string("\t<settings gravitydirection=\"") + gravity_name(def.settings.gravity_direction) +
         "\" wavedirection=\"" + wave_name(def.settings.wave_direction) + "\" autoreverse=\"" +
         (def.settings.autoreverse ? "on" : "off") + "\"/>\n";
  out += "\n\t<nodes>\n";
  for (const NodeDef& n : def.nodes) {
    if (n.fixed) {
      out += "\t\t<node" + id_attr("id", n.id) + attr("x", n.x) + attr("y", n.y) + "/>\n";
    } else {
      out += "\t\t<mass" + id_attr("id", n.id) + attr("x", n.x) + attr("y", n.y) + attr("vx", n.vx) +
             attr("vy", n.vy) + "/>\n";
    }
  }
  out += "\t</nodes>\n";
  out += "\n\t<links>\n";
  for (const LinkDef& l : def.links) {
    const std::string ends = id_attr("a", def.nodes[static_cast<std::size_t>(l.a)].id) +
                             id_attr("b", def.nodes[static_cast<std::size_t>(l.b)].id);
    switch (l.kind) {
      case LinkKind::Spring: out += "\t\t<spring" + ends + attr("restlength", l.rest_length) + "/>\n"; break;
      case LinkKind::Muscle:
        out += "\t\t<muscle" + ends + attr("restlength", l.rest_length) + attr("amplitude", l.amplitude) +
               attr("phase", l.phase) + "/>\n";
        break;
      case LinkKind::FixedBar: out += "\t\t<fixedbar" + ends + "/>\n"; break;
    }
  }
  out += "\t</links>\n";
  out += "</model>\n";
  return out;
}

void write_model_file(const std::filesystem::path& path, const ModelDef& def) {
  write_file_atomically(path, write_model_text(def)); // <path>.tmp-<pid>, then rename
}

} // namespace soda
