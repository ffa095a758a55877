// Creatures as data: Model.from_arrays (nodes, links and world as numpy arrays
// and a dict, checked by the engine's own model validation, soda::build_model,
// so its messages name the node, link or field), and the vector view of one body
// plan for CMA-ES or a pyribs emitter: to_vector / from_vector over a creature's
// continuous parameters, with bounds and names. The layout (docs/python.md):
//   rest_length of every spring and muscle, in link order (bars have none),
//   amplitude of every muscle, phase of every muscle (cycles; wrapped into [0, 1)
//   by from_vector, as the file reader wraps it), then with world=True gravity,
//   friction, springyness, surface_friction, surface_reflection, wave_amplitude,
//   wave_speed.
// The topology (masses, who links whom, kinds) is the model's and stays.
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "core/constants.hpp"
#include "core/input_error.hpp"
#include "core/model.hpp"
#include "python/bindings.hpp"

namespace sodaevo::python {

namespace {

/// One entry of the vector: its name, bounds and where it lives in a ModelDef.
struct Slot {
  std::string name;
  double low;
  double high;
  bool wraps; ///< a phase: any finite value, wrapped into [0, 1)
  std::function<double&(soda::ModelDef&)> field;
};

std::vector<Slot> slots_of(const soda::ModelDef& def, bool world) {
  std::vector<Slot> slots;
  // Rest lengths: up to the container's diagonal, or twice the model's longest link
  // if that is longer (some evolved creatures have links longer than the window).
  double longest = std::hypot(static_cast<double>(def.width), static_cast<double>(def.height));
  for (const soda::LinkDef& l : def.links) longest = std::max(longest, 2 * l.rest_length);
  for (std::size_t i = 0; i < def.links.size(); ++i) {
    if (def.links[i].kind == soda::LinkKind::FixedBar) continue;
    slots.push_back({"rest_length[" + std::to_string(i) + "]", 0.0, longest, false,
                     [i](soda::ModelDef& d) -> double& { return d.links[i].rest_length; }});
  }
  for (std::size_t i = 0; i < def.links.size(); ++i) {
    if (def.links[i].kind != soda::LinkKind::Muscle) continue;
    slots.push_back({"amplitude[" + std::to_string(i) + "]", soda::kAmplitudeRange.min, soda::kAmplitudeRange.max, false,
                     [i](soda::ModelDef& d) -> double& { return d.links[i].amplitude; }});
  }
  for (std::size_t i = 0; i < def.links.size(); ++i) {
    if (def.links[i].kind != soda::LinkKind::Muscle) continue;
    slots.push_back({"phase[" + std::to_string(i) + "]", 0.0, 1.0, true,
                     [i](soda::ModelDef& d) -> double& { return d.links[i].phase; }});
  }
  if (!world) return slots;
  const auto add = [&](const char* name, soda::Range r, std::function<double&(soda::ModelDef&)> f) {
    slots.push_back({name, r.min, r.max, false, std::move(f)});
  };
  add("gravity", soda::kGravityRange, [](soda::ModelDef& d) -> double& { return d.environment.gravity; });
  add("friction", soda::kFrictionRange, [](soda::ModelDef& d) -> double& { return d.environment.friction; });
  add("springyness", soda::kSpringynessRange, [](soda::ModelDef& d) -> double& { return d.environment.springyness; });
  add("surface_friction", soda::kSurfaceFrictionRange,
      [](soda::ModelDef& d) -> double& { return d.collisions.surface_friction; });
  add("surface_reflection", soda::kSurfaceReflectionRange,
      [](soda::ModelDef& d) -> double& { return d.collisions.surface_reflection; });
  add("wave_amplitude", soda::kAmplitudeRange, [](soda::ModelDef& d) -> double& { return d.wave.amplitude; });
  // Any finite speed runs; a search is kept to a cycle per frame either way.
  add("wave_speed", soda::Range{-1.0, 1.0}, [](soda::ModelDef& d) -> double& { return d.wave.speed; });
  return slots;
}

py::array_t<double> to_vector(const py::object& model, bool world) {
  soda::ModelDef def = model_of(model);
  const std::vector<Slot> slots = slots_of(def, world);
  py::array_t<double> out(static_cast<py::ssize_t>(slots.size()));
  auto v = out.mutable_unchecked<1>();
  for (std::size_t k = 0; k < slots.size(); ++k) v(static_cast<py::ssize_t>(k)) = slots[k].field(def);
  return out;
}

soda::ModelDef from_vector(const py::object& model, const py::object& vector, bool world) {
  soda::ModelDef def = model_of(model);
  const std::vector<Slot> slots = slots_of(def, world);
  const py::array_t<double, py::array::c_style | py::array::forcecast> v(vector);
  if (v.ndim() != 1 || static_cast<std::size_t>(v.shape(0)) != slots.size()) {
    std::string shape;
    for (py::ssize_t d = 0; d < v.ndim(); ++d) shape += (d ? ", " : "") + std::to_string(v.shape(d));
    throw soda::InputError("vector: expected " + std::to_string(slots.size()) + " numbers (to_vector's length for " +
                           "this model, world=" + (world ? "True" : "False") + "), got shape (" + shape + ")");
  }
  const auto r = v.unchecked<1>();
  for (std::size_t k = 0; k < slots.size(); ++k) {
    const double x = r(static_cast<py::ssize_t>(k));
    const Slot& s = slots[k];
    const bool ok = std::isfinite(x) && (s.wraps || (x >= s.low && x <= s.high));
    if (!ok) {
      throw soda::InputError("vector[" + std::to_string(k) + "] (" + s.name + "): expected " +
                             (s.wraps ? std::string("a finite number (a phase, wrapped into [0, 1))")
                                      : "a number in [" + py::repr(py::float_(s.low)).cast<std::string>() + ", " +
                                            py::repr(py::float_(s.high)).cast<std::string>() + "]") +
                             ", got " + py::repr(py::float_(x)).cast<std::string>());
    }
    s.field(def) = s.wraps ? soda::wrap_phase(x) : x;
  }
  return def;
}

py::tuple vector_bounds(const py::object& model, bool world) {
  const std::vector<Slot> slots = slots_of(model_of(model), world);
  const auto n = static_cast<py::ssize_t>(slots.size());
  py::array_t<double> low(n), high(n);
  auto lo = low.mutable_unchecked<1>(), hi = high.mutable_unchecked<1>();
  for (py::ssize_t k = 0; k < n; ++k) {
    lo(k) = slots[static_cast<std::size_t>(k)].low;
    hi(k) = slots[static_cast<std::size_t>(k)].high;
  }
  return py::make_tuple(low, high);
}

std::vector<std::string> vector_names(const py::object& model, bool world) {
  std::vector<std::string> names;
  for (const Slot& s : slots_of(model_of(model), world)) names.push_back(s.name);
  return names;
}

/// A float64 column of `n` values: field `name` of a structured array, else
/// column `index` of a 2-D one.
py::array_t<double, py::array::c_style | py::array::forcecast> column(const py::object& table, const char* name,
                                                                       int index, py::ssize_t n) {
  const py::object dtype = table.attr("dtype");
  const py::object col = dtype.attr("names").is_none() ? table[py::make_tuple(py::slice(0, n, 1), index)]
                                                        : table[py::str(name)];
  return py::array_t<double, py::array::c_style | py::array::forcecast>(col);
}

int direction_of(const py::dict& world, const char* key, const std::vector<std::pair<const char*, int>>& names,
                 int fallback) {
  if (!world.contains(key)) return fallback;
  const std::string given = py::str(world[key]);
  std::string expected;
  for (const auto& [name, value] : names) {
    if (given == name) return value;
    expected += (expected.empty() ? "" : ", ") + std::string(name);
  }
  throw soda::InputError(std::string("world: /") + key + ": expected one of " + expected + ", got '" + given + "'");
}

soda::ModelDef from_arrays(const py::object& nodes_arg, const py::object& links_arg, const py::object& world_arg,
                           const py::object& fixed_arg, const py::object& ids_arg, const std::string& name,
                           const std::string& comment) {
  const py::object np = py::module_::import("numpy");
  const py::array_t<double, py::array::c_style | py::array::forcecast> nodes(np.attr("asarray")(nodes_arg));
  if (nodes.ndim() != 2 || nodes.shape(1) != 4) {
    throw soda::InputError("nodes: expected an (n, 4) array of x, y, vx, vy, got " + py::repr(nodes.attr("shape")).cast<std::string>());
  }
  const py::ssize_t n = nodes.shape(0);
  soda::ModelDef def;
  def.name = name;
  def.comment = comment;
  std::vector<bool> fixed(static_cast<std::size_t>(n), false);
  if (!fixed_arg.is_none()) {
    const py::array_t<bool, py::array::c_style | py::array::forcecast> f(np.attr("asarray")(fixed_arg, "bool"));
    if (f.ndim() != 1 || f.shape(0) != n) throw soda::InputError("fixed: expected " + std::to_string(n) + " booleans (one per node)");
    for (py::ssize_t i = 0; i < n; ++i) fixed[static_cast<std::size_t>(i)] = f.at(i);
  }
  std::vector<std::string> ids;
  if (!ids_arg.is_none()) {
    ids = ids_arg.cast<std::vector<std::string>>();
    if (static_cast<py::ssize_t>(ids.size()) != n) throw soda::InputError("node_ids: expected " + std::to_string(n) + " ids (one per node)");
  }
  const auto xy = nodes.unchecked<2>();
  int masses = 0, fixed_nodes = 0;
  for (py::ssize_t i = 0; i < n; ++i) {
    soda::NodeDef node;
    node.fixed = fixed[static_cast<std::size_t>(i)];
    node.id = !ids.empty() ? ids[static_cast<std::size_t>(i)]
              : node.fixed ? "n" + std::to_string(fixed_nodes++)
                           : "m" + std::to_string(masses++);
    node.x = xy(i, 0);
    node.y = xy(i, 1);
    node.vx = xy(i, 2);
    node.vy = xy(i, 3);
    def.nodes.push_back(std::move(node));
  }
  const py::object table = np.attr("asarray")(links_arg);
  const bool structured = !table.attr("dtype").attr("names").is_none();
  const py::tuple shape = table.attr("shape");
  if (!(structured ? shape.size() == 1 : (shape.size() == 2 && shape[1].cast<int>() == 6) || table.attr("size").cast<int>() == 0)) {
    throw soda::InputError("links: expected Model.links' structured array (kind, a, b, rest_length, amplitude, phase) "
                           "or a (k, 6) array of those columns, got shape " + py::repr(shape).cast<std::string>());
  }
  const py::ssize_t k = shape.size() > 0 ? shape[0].cast<py::ssize_t>() : 0;
  if (k > 0) {
    const auto kind = column(table, "kind", 0, k), a = column(table, "a", 1, k), b = column(table, "b", 2, k),
               rest = column(table, "rest_length", 3, k), amp = column(table, "amplitude", 4, k),
               phase = column(table, "phase", 5, k);
    for (py::ssize_t i = 0; i < k; ++i) {
      const std::string where = "links[" + std::to_string(i) + "]: ";
      const double kd = kind.at(i), ad = a.at(i), bd = b.at(i);
      if (!(kd == 0 || kd == 1 || kd == 2)) throw soda::InputError(where + "kind: expected 0 (spring), 1 (muscle) or 2 (bar)");
      for (const double e : {ad, bd}) {
        if (!(e >= 0 && e < static_cast<double>(n) && e == std::floor(e))) {
          throw soda::InputError(where + "a, b: expected node indices in [0, " + std::to_string(n - 1) + "], got " +
                                 py::repr(py::float_(e)).cast<std::string>());
        }
      }
      soda::LinkDef link;
      link.kind = static_cast<soda::LinkKind>(static_cast<int>(kd));
      link.a = static_cast<int>(ad);
      link.b = static_cast<int>(bd);
      link.rest_length = link.kind == soda::LinkKind::FixedBar ? 0.0 : rest.at(i);
      if (link.kind == soda::LinkKind::Muscle) {
        link.amplitude = amp.at(i);
        link.phase = phase.at(i);
      }
      def.links.push_back(link);
    }
  }
  if (!world_arg.is_none()) {
    const py::dict world = py::dict(world_arg);
    static const char* const known[] = {"width", "height", "gravity", "friction", "springyness", "surface_friction",
                                        "surface_reflection", "gravity_direction", "wave_amplitude", "wave_phase",
                                        "wave_speed", "wave_direction", "autoreverse"};
    for (const auto& [key, value] : world) {
      const std::string k2 = py::str(key);
      if (std::find(std::begin(known), std::end(known), k2) == std::end(known)) {
        throw soda::InputError("world: unknown key '" + k2 + "' (expected those of Model.world)");
      }
    }
    const auto number = [&](const char* key, double& into) {
      if (world.contains(key)) into = py::float_(world[key]).cast<double>();
    };
    if (world.contains("width")) def.width = py::int_(world["width"]).cast<int>();
    if (world.contains("height")) def.height = py::int_(world["height"]).cast<int>();
    number("gravity", def.environment.gravity);
    number("friction", def.environment.friction);
    number("springyness", def.environment.springyness);
    number("surface_friction", def.collisions.surface_friction);
    number("surface_reflection", def.collisions.surface_reflection);
    number("wave_amplitude", def.wave.amplitude);
    number("wave_phase", def.wave.phase);
    number("wave_speed", def.wave.speed);
    if (world.contains("autoreverse")) def.settings.autoreverse = world["autoreverse"].cast<bool>();
    def.settings.gravity_direction = static_cast<soda::GravityDirection>(
        direction_of(world, "gravity_direction", {{"down", 1}, {"up", -1}, {"off", 0}}, 1));
    def.settings.wave_direction = static_cast<soda::WaveDirection>(
        direction_of(world, "wave_direction", {{"forward", 1}, {"reverse", -1}, {"manual", 0}}, 1));
  }
  (void)soda::build_model(def); // the engine's checks: every node, link and world value, named
  return def;
}

} // namespace

void bind_genome(py::module_& m) {
  auto model = py::reinterpret_borrow<py::class_<soda::ModelDef>>(m.attr("Model"));
  model.def_static("from_arrays", &from_arrays, py::arg("nodes"), py::arg("links"), py::arg("world") = py::none(),
                   py::kw_only(), py::arg("fixed") = py::none(), py::arg("node_ids") = py::none(),
                   py::arg("name") = "", py::arg("comment") = "",
                   "A model from arrays: nodes (n, 4) x, y, vx, vy; links as Model.links gives them (or a\n"
                   "(k, 6) array of kind, a, b, rest_length, amplitude, phase); world a dict with keys of\n"
                   "Model.world (missing ones: the file format's defaults); fixed (n,) bools; node_ids.\n"
                   "Checked as a model file is: a bad value raises InputError naming it.");
  m.def("to_vector", &to_vector, py::arg("model"), py::kw_only(), py::arg("world") = true);
  m.def("from_vector", &from_vector, py::arg("model"), py::arg("vector"), py::kw_only(), py::arg("world") = true);
  m.def("vector_bounds", &vector_bounds, py::arg("model"), py::kw_only(), py::arg("world") = true);
  m.def("vector_names", &vector_names, py::arg("model"), py::kw_only(), py::arg("world") = true);
}

} // namespace sodaevo::python
