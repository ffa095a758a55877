// sodaevo.Model: a SodaConstructor model (soda::ModelDef) read from a file or XML
// text, written back as canonical v1 XML, its nodes and links readable as numpy
// arrays (read-only copies) and its world as a read-only mapping. Immutable from
// Python, so a batch may read it on other threads while the GIL is released; new
// creatures come from the GA's operators (python/evolve.cpp) and from arrays and
// vectors (python/genome.cpp).
#include <cstdint>
#include <filesystem>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "evolve/problems/wire_format.hpp"
#include "formats/model_file.hpp"
#include "python/bindings.hpp"

namespace sodaevo::python {

namespace {

/// One row of Model.links (a numpy structured array).
struct LinkRow {
  std::int8_t kind; ///< 0 spring, 1 muscle, 2 fixed bar
  std::int32_t a;
  std::int32_t b;
  double rest_length;
  double amplitude;
  double phase;
};

std::string wave_direction_name(soda::WaveDirection d) {
  switch (d) {
    case soda::WaveDirection::Forward: return "forward";
    case soda::WaveDirection::Reverse: return "reverse";
    case soda::WaveDirection::Manual: return "manual";
  }
  return "forward";
}

/// Nodes as an (n, 4) array of x, y, vx, vy; only the free masses if `masses_only`.
py::array_t<double> node_array(const soda::ModelDef& def, bool masses_only) {
  std::size_t n = 0;
  for (const soda::NodeDef& node : def.nodes) n += masses_only && node.fixed ? 0 : 1;
  py::array_t<double> out({n, std::size_t{4}});
  auto v = out.mutable_unchecked<2>();
  std::size_t i = 0;
  for (const soda::NodeDef& node : def.nodes) {
    if (masses_only && node.fixed) continue;
    v(i, 0) = node.x;
    v(i, 1) = node.y;
    v(i, 2) = node.vx;
    v(i, 3) = node.vy;
    ++i;
  }
  return out;
}

py::array_t<LinkRow> link_array(const soda::ModelDef& def) {
  py::array_t<LinkRow> out(static_cast<py::ssize_t>(def.links.size()));
  auto v = out.mutable_unchecked<1>();
  for (std::size_t i = 0; i < def.links.size(); ++i) {
    const soda::LinkDef& l = def.links[i];
    v(i) = LinkRow{static_cast<std::int8_t>(l.kind), l.a, l.b, l.rest_length, l.amplitude, l.phase};
  }
  return out;
}

py::dict world_dict(const soda::ModelDef& def) {
  py::dict w;
  w["width"] = def.width;
  w["height"] = def.height;
  w["gravity"] = def.environment.gravity;
  w["friction"] = def.environment.friction;
  w["springyness"] = def.environment.springyness;
  w["surface_friction"] = def.collisions.surface_friction;
  w["surface_reflection"] = def.collisions.surface_reflection;
  w["gravity_direction"] = gravity_direction_name(def.settings.gravity_direction);
  w["wave_amplitude"] = def.wave.amplitude;
  w["wave_phase"] = def.wave.phase;
  w["wave_speed"] = def.wave.speed;
  w["wave_direction"] = wave_direction_name(def.settings.wave_direction);
  w["autoreverse"] = def.settings.autoreverse;
  return w;
}

/// The model's numbers are its own: an array handed out is a copy marked
/// read-only, so an edit raises instead of being silently lost.
template <class T>
py::array_t<T> read_only(py::array_t<T> a) {
  a.attr("flags").attr("writeable") = false;
  return a;
}

soda::ModelDef loaded(soda::LoadedModel m) {
  warn_all(m.warnings);
  return std::move(m.def);
}

} // namespace

const soda::ModelDef& model_of(const py::handle& model) {
  if (!py::isinstance<soda::ModelDef>(model)) {
    throw py::type_error("expected a sodaevo.Model, got " + py::str(py::type::of(model).attr("__name__")).cast<std::string>() +
                         " (read one with sodaevo.Model.load(path))");
  }
  return model.cast<const soda::ModelDef&>();
}

void bind_model(py::module_& m) {
  PYBIND11_NUMPY_DTYPE(LinkRow, kind, a, b, rest_length, amplitude, phase);
  py::class_<soda::ModelDef>(m, "Model",
                             "A SodaConstructor model: masses and fixed nodes, springs, muscles and fixed bars,\n"
                             "its world and wave. Read with Model.load(path) or Model.from_xml(text); immutable.")
      .def_static(
          "load", [](const std::filesystem::path& path) { return loaded(soda::read_model_file(path)); }, py::arg("path"),
          "Reads a model file (SodaConstructor v1 or v2 XML). Bad input raises sodaevo.InputError\n"
          "(file, line, column); what the reader clamped or ignored is issued as a UserWarning.")
      .def_static(
          "from_xml",
          [](const std::string& text, const std::string& source) {
            return loaded(soda::read_model_text(text, source));
          },
          py::arg("text"), py::arg("source") = "<string>",
          "Parses model XML text; `source` names it in error messages.")
      .def("to_xml", [](const soda::ModelDef& def) { return soda::write_model_text(def); },
           "The model as canonical SodaConstructor v1 XML (what `simulate --out` and the run store write).")
      .def("save", [](const soda::ModelDef& def, const std::filesystem::path& path) { soda::write_model_file(path, def); },
           py::arg("path"), "Writes to_xml() to `path` atomically.")
      .def_property_readonly("name", [](const soda::ModelDef& d) { return d.name; })
      .def_property_readonly("comment", [](const soda::ModelDef& d) { return d.comment; })
      .def_property_readonly("nodes", [](const soda::ModelDef& d) { return read_only(node_array(d, false)); },
                             "Every node in file order as an (n, 4) float64 array: x, y, vx, vy (px, px/frame).")
      .def_property_readonly(
          "fixed",
          [](const soda::ModelDef& d) {
            py::array_t<bool> out(static_cast<py::ssize_t>(d.nodes.size()));
            auto v = out.mutable_unchecked<1>();
            for (std::size_t i = 0; i < d.nodes.size(); ++i) v(i) = d.nodes[i].fixed;
            return read_only(out);
          },
          "Whether each node (in `nodes` order) is a fixed node.")
      .def_property_readonly("masses", [](const soda::ModelDef& d) { return read_only(node_array(d, true)); },
                             "The free masses in file order (the columns of a trace): (m, 4) x, y, vx, vy.")
      .def_property_readonly("node_ids", [](const soda::ModelDef& d) {
        py::list ids;
        for (const soda::NodeDef& n : d.nodes) ids.append(n.id);
        return py::tuple(ids);
      })
      .def_property_readonly("links", [](const soda::ModelDef& d) { return read_only(link_array(d)); },
                             "Links in file order, a structured array: kind (0 spring, 1 muscle, 2 fixed bar),\n"
                             "a, b (indices into nodes), rest_length (px), amplitude, phase (cycles).")
      .def_property_readonly(
          "world",
          [](const soda::ModelDef& d) { return py::module_::import("types").attr("MappingProxyType")(world_dict(d)); },
          "Container, environment, collisions, wave and settings as a read-only mapping.")
      .def_property_readonly("mass_count", [](const soda::ModelDef& d) {
        int n = 0;
        for (const soda::NodeDef& node : d.nodes) n += node.fixed ? 0 : 1;
        return n;
      })
      .def_property_readonly("link_count", [](const soda::ModelDef& d) { return d.links.size(); })
      .def("__eq__", [](const soda::ModelDef& a, const soda::ModelDef& b) { return a == b; }, py::is_operator())
      .def("__copy__", [](const soda::ModelDef& d) { return d; })
      .def("__deepcopy__", [](const soda::ModelDef& d, const py::object&) { return d; }, py::arg("memo"))
      .def(py::pickle( // the wire format: every double exactly, link order kept
          [](const soda::ModelDef& d) {
            const std::vector<char> bytes = encode_creature(d);
            return py::bytes(bytes.data(), bytes.size());
          },
          [](const py::bytes& state) {
            const std::string text = state;
            return decode_creature(std::vector<char>(text.begin(), text.end()));
          }))
      .def("__repr__", [](const soda::ModelDef& d) {
        int masses = 0;
        for (const soda::NodeDef& node : d.nodes) masses += node.fixed ? 0 : 1;
        return "<sodaevo.Model '" + d.name + "': " + std::to_string(masses) + " masses, " +
               std::to_string(d.links.size()) + " links>";
      });
  m.attr("Model").attr("__hash__") = py::none();
}

} // namespace sodaevo::python
