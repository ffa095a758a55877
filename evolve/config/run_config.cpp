// RunConfig from and to JSON (see run_config.hpp and configs/README.md).
//
// One table lists every key by its JSON pointer, in document order, with its type
// and range; parsing, the unknown-key check and to_json are all driven by it, so a
// key cannot be known to one and forgotten by another. Validation never stops at
// the first problem: every error is collected and reported together.
#include "run_config.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <system_error>
#include <variant>

#include "core/input_error.hpp"
#include "core/number_text.hpp"
#include "evolve/config/input_limits.hpp"
#include "evolve/config/map_elites_config.hpp"
#include "evolve/config/race_fitness_config.hpp"
#include "evolve/config/seed_model_paths.hpp"
#include "evolve/config/strict_json.hpp"

namespace sodaevo {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// --- the key table --------------------------------------------------------------

enum class Kind {
  Integer,          ///< an integral JSON number within [lo, hi]
  Number,           ///< any JSON number within the range (ends open or closed)
  Name,             ///< /name
  Preset,           ///< /preset (not stored; resolved into /world/evolve)
  Comment,          ///< /comment, /$schema: a string, ignored
  SeedModels,       ///< /population/seed_models
  FitnessKindName,  ///< /fitness/kind
  Race,             ///< /fitness/race: an object read by race_fitness_config.cpp
  Direction,        ///< /fitness/direction
  Scaling,          ///< /fitness/scaling
  Mode,             ///< /fitness/mode
  Integrator,       ///< /fitness/integrator
  Divergence,       ///< /fitness/divergence
  Statistic,        ///< /fitness/statistic
  GravityDirection, ///< /world/gravity_direction
  WorldEvolve,      ///< /world/evolve
  Algorithm,        ///< /algorithm
  MapElites,        ///< /map_elites: an object read by map_elites_config.cpp
};

using Accessor = std::variant<std::monostate, int& (*)(RunConfig&), long long& (*)(RunConfig&),
                              std::uint64_t& (*)(RunConfig&), double& (*)(RunConfig&)>;

#define SODAEVO_FIELD(member) +[](RunConfig& c) -> decltype(auto) { return (c.member); }

constexpr double kTwoPow53 = 9007199254740992.0;

struct Field {
  const char* pointer;
  Kind kind;
  Accessor access{};
  double lo = 0.0;
  double hi = 0.0;
  bool lo_open = false;
  bool hi_open = false;
};

Field integer(const char* p, Accessor a, double lo, double hi) {
  return {p, Kind::Integer, a, lo, hi};
}
Field number(const char* p, Accessor a, double lo, double hi, bool lo_open = false) {
  return {p, Kind::Number, a, lo, hi, lo_open, false};
}
Field number(const char* p, Accessor a, soda::Range r) { return number(p, a, r.min, r.max); }
Field special(const char* p, Kind k) { return {p, k}; }

const std::vector<Field>& fields() {
  static const std::vector<Field> table = {
      special("/name", Kind::Name),
      integer("/seed", SODAEVO_FIELD(seed), 0, kTwoPow53),
      integer("/generations", SODAEVO_FIELD(budget.generations), 1, 1e6),
      special("/preset", Kind::Preset),
      special("/algorithm", Kind::Algorithm),

      integer("/population/size", SODAEVO_FIELD(population.size), 2, 100000),
      special("/population/seed_models", Kind::SeedModels),
      number("/population/random_fraction", SODAEVO_FIELD(population.random_fraction), 0, 1),
      integer("/population/random/masses_min", SODAEVO_FIELD(population.random.masses_min), 2, 10000),
      integer("/population/random/masses_max", SODAEVO_FIELD(population.random.masses_max), 2, 10000),
      number("/population/random/extra_links_per_mass",
             SODAEVO_FIELD(population.random.extra_links_per_mass), 0, 20),
      number("/population/random/muscle_fraction", SODAEVO_FIELD(population.random.muscle_fraction), 0, 1),
      number("/population/random/size", SODAEVO_FIELD(population.random.size), 0, 10000, true),

      integer("/selection/tournament_size", SODAEVO_FIELD(selection.tournament_size), 1, 100000),
      integer("/selection/elites", SODAEVO_FIELD(selection.elites), 0, 99999),

      number("/crossover/rate", SODAEVO_FIELD(crossover_rate), 0, 1),

      number("/mutation/muscle_phase/rate", SODAEVO_FIELD(mutation.muscle_phase_rate), 0, 1),
      number("/mutation/muscle_phase/sigma", SODAEVO_FIELD(mutation.muscle_phase_sigma), 0, 1, true),
      number("/mutation/muscle_amplitude/rate", SODAEVO_FIELD(mutation.muscle_amplitude_rate), 0, 1),
      number("/mutation/muscle_amplitude/sigma", SODAEVO_FIELD(mutation.muscle_amplitude_sigma), 0, 1, true),
      number("/mutation/rest_length/rate", SODAEVO_FIELD(mutation.rest_length_rate), 0, 1),
      number("/mutation/rest_length/sigma", SODAEVO_FIELD(mutation.rest_length_sigma), 0, 1, true),
      number("/mutation/wave/rate", SODAEVO_FIELD(mutation.wave_rate), 0, 1),
      number("/mutation/wave/speed_sigma", SODAEVO_FIELD(mutation.wave_speed_sigma), 0,
             soda::kWaveMaxUiSpeed, true),
      number("/mutation/wave/amplitude_sigma", SODAEVO_FIELD(mutation.wave_amplitude_sigma), 0, 1, true),
      number("/mutation/move_mass/rate", SODAEVO_FIELD(mutation.move_mass_rate), 0, 1),
      number("/mutation/move_mass/sigma", SODAEVO_FIELD(mutation.move_mass_sigma), 0, 1000, true),
      number("/mutation/add_link/rate", SODAEVO_FIELD(mutation.add_link_rate), 0, 1),
      number("/mutation/remove_link/rate", SODAEVO_FIELD(mutation.remove_link_rate), 0, 1),
      number("/mutation/toggle_muscle/rate", SODAEVO_FIELD(mutation.toggle_muscle_rate), 0, 1),
      number("/mutation/add_mass/rate", SODAEVO_FIELD(mutation.add_mass_rate), 0, 1),
      number("/mutation/remove_mass/rate", SODAEVO_FIELD(mutation.remove_mass_rate), 0, 1),
      number("/mutation/world/rate", SODAEVO_FIELD(mutation.world_rate), 0, 1),
      number("/mutation/world/sigma", SODAEVO_FIELD(mutation.world_sigma), 0, 1, true),

      integer("/limits/min_masses", SODAEVO_FIELD(limits.min_masses), 2, 10000),
      integer("/limits/max_masses", SODAEVO_FIELD(limits.max_masses), 2, 10000),
      integer("/limits/max_links", SODAEVO_FIELD(limits.max_links), 1, 100000),

      integer("/budget/evaluations", SODAEVO_FIELD(budget.max_evaluations), 0, kTwoPow53),
      number("/budget/wall_seconds", SODAEVO_FIELD(budget.max_wall_seconds), 0, 1e9),

      special("/fitness/kind", Kind::FitnessKindName),
      integer("/fitness/frames", SODAEVO_FIELD(fitness.frames), 1, 1e7),
      integer("/fitness/settle_frames", SODAEVO_FIELD(fitness.settle_frames), 0, 1e7),
      special("/fitness/direction", Kind::Direction),
      special("/fitness/scaling", Kind::Scaling),
      number("/fitness/drop_height", SODAEVO_FIELD(fitness.drop_height), 0, 1000),
      special("/fitness/mode", Kind::Mode),
      special("/fitness/integrator", Kind::Integrator),
      integer("/fitness/substeps", SODAEVO_FIELD(fitness.substeps), 1, soda::kMaxSubsteps),
      special("/fitness/divergence", Kind::Divergence),
      number("/fitness/honesty/max_change", SODAEVO_FIELD(fitness.honesty_max_change), 0, 1e6),
      integer("/fitness/honesty/substeps_factor", SODAEVO_FIELD(fitness.honesty_substeps_factor), 2, 64),
      integer("/fitness/replicas", SODAEVO_FIELD(fitness.replicas), 1, 256),
      integer("/fitness/replicas_max", SODAEVO_FIELD(fitness.replicas_max), 1, 1024),
      integer("/fitness/confirm", SODAEVO_FIELD(fitness.confirm), 0, 100000),
      special("/fitness/statistic", Kind::Statistic),
      number("/fitness/jitter", SODAEVO_FIELD(fitness.jitter), 0, 1),
      special("/fitness/race", Kind::Race),
      number("/fitness/stability_margin_min", SODAEVO_FIELD(fitness.stability_margin_min), 0, 1e6),

      number("/world/gravity", SODAEVO_FIELD(world.gravity), soda::kGravityRange),
      number("/world/friction", SODAEVO_FIELD(world.friction), soda::kFrictionRange),
      number("/world/springyness", SODAEVO_FIELD(world.springyness), soda::kSpringynessRange),
      number("/world/surface_friction", SODAEVO_FIELD(world.surface_friction), soda::kSurfaceFrictionRange),
      number("/world/surface_reflection", SODAEVO_FIELD(world.surface_reflection),
             soda::kSurfaceReflectionRange),
      special("/world/gravity_direction", Kind::GravityDirection),
      special("/world/evolve", Kind::WorldEvolve),

      integer("/save/generation_every", SODAEVO_FIELD(save.generation_every), 0, 1e6),
      integer("/save/checkpoint_every", SODAEVO_FIELD(save.checkpoint_every), 1, 1e6),

      special("/map_elites", Kind::MapElites),

      special("/comment", Kind::Comment),
      special("/$schema", Kind::Comment),
  };
  return table;
}

#undef SODAEVO_FIELD

/// The object structure implied by the table: for each object's pointer ("" is
/// the top level), its keys in document order.
struct KeyTree {
  std::map<std::string, std::vector<std::string>> children;
};

const KeyTree& key_tree() {
  static const KeyTree tree = [] {
    KeyTree t;
    for (const Field& f : fields()) {
      const std::string p = f.pointer;
      std::size_t start = 0;
      while (start < p.size()) {
        const std::size_t slash = p.find('/', start + 1);
        const std::string parent = p.substr(0, start);
        const std::string token =
            p.substr(start + 1, (slash == std::string::npos ? p.size() : slash) - start - 1);
        auto& kids = t.children[parent];
        if (std::find(kids.begin(), kids.end(), token) == kids.end()) kids.push_back(token);
        if (slash == std::string::npos) break;
        start = slash;
      }
    }
    return t;
  }();
  return tree;
}

// --- text helpers ---------------------------------------------------------------

/// A range bound as a person writes it: integers without exponent or ".0".
std::string bound_text(double v) {
  if (std::abs(v) <= kTwoPow53 && v == std::floor(v)) {
    return std::to_string(static_cast<long long>(v));
  }
  return soda::format_double_plain(v);
}

std::string range_text(const Field& f) {
  return std::string(f.lo_open ? "(" : "[") + bound_text(f.lo) + ", " + bound_text(f.hi) +
         (f.hi_open ? ")" : "]");
}

std::string quoted_list(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += (i + 1 == names.size()) ? " or " : ", ";
    out += '"' + names[i] + '"';
  }
  return out;
}

bool is_valid_name(const std::string& s) {
  if (s.empty() || s.size() > 64) return false;
  if (s.find_first_not_of('.') == std::string::npos) return false; // "." and ".." are no folder names
  return std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '.' || c == '-';
  });
}

using soda::EnumName;

// The names of the enums are their own tables (core/stepping.hpp,
// problems/fitness_settings.hpp, problems/world_settings.hpp,
// algorithms/map_elites_settings.hpp; /fitness/kind: problems/fitness_kind.hpp).

// --- the parser -----------------------------------------------------------------

class ConfigReader {
 public:
  ConfigReader(const std::string& source, const fs::path& base_dir)
      : source_(source), base_dir_(base_dir) {}

  RunConfig read(const std::string& text) {
    const json root = parse_strict_json(text, source_, [this](const std::string& pointer) {
      error(pointer, "duplicate key (a key may appear only once in an object)");
    });
    check_structure(root, "");
    if (!root.is_object()) throw_errors(); // nothing more to say about it
    for (const Field& f : fields()) {
      if (const json* v = find(root, f.pointer)) read_field(f, *v);
    }
    resolve_world_evolve();
    check_cross_fields();
    if (!errors_.empty()) throw_errors();
    return config_;
  }

 private:
  [[noreturn]] void throw_errors() const {
    // Every problem is listed, up to a screenful (a generated file can have thousands).
    constexpr std::size_t kMaxShown = 50;
    std::string all;
    for (std::size_t i = 0; i < errors_.size() && i < kMaxShown; ++i) {
      if (!all.empty()) all += '\n';
      all += errors_[i];
    }
    if (errors_.size() > kMaxShown) {
      all += "\n" + source_ + ": " + std::to_string(errors_.size() - kMaxShown) + " more errors not shown";
    }
    throw soda::InputError(all);
  }

  void error(const std::string& pointer, const std::string& message) {
    errors_.push_back(source_ + ": " + show_pointer(pointer) + ": " + message);
    bad_.insert(pointer);
  }
  void expected(const std::string& pointer, const std::string& what, const json& got) {
    error(pointer, "expected " + what + ", got " + show_json(got));
  }
  bool ok(const std::string& pointer) const { return bad_.count(pointer) == 0; }
  bool given(const std::string& pointer) const { return present_.count(pointer) != 0; }

  // Unknown keys and members that should be objects but are not.
  void check_structure(const json& v, const std::string& pointer) {
    const auto& tree = key_tree().children;
    const auto& known = tree.at(pointer);
    if (!v.is_object()) {
      expected(pointer, "an object with keys " + join(known), v);
      return;
    }
    for (const auto& [key, value] : v.items()) {
      const std::string child = pointer + "/" + escape_token(key);
      if (std::find(known.begin(), known.end(), key) == known.end()) {
        std::string message = "unknown key (expected one of: " + join(known) + ")";
        std::string best;
        std::size_t best_distance = 3;
        for (const std::string& k : known) {
          const std::size_t d = edit_distance(key, k);
          if (d < best_distance) {
            best_distance = d;
            best = k;
          }
        }
        if (!best.empty()) message += "; did you mean \"" + best + "\"?";
        error(child, message);
      } else if (tree.count(child) != 0) {
        check_structure(value, child);
      }
    }
  }

  static std::string join(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
  }

  // The value at a table pointer, if every object on the way is there.
  const json* find(const json& root, const std::string& pointer) {
    const json* at = &root;
    std::size_t start = 0;
    while (start < pointer.size()) {
      const std::size_t slash = pointer.find('/', start + 1);
      const std::string token =
          pointer.substr(start + 1, (slash == std::string::npos ? pointer.size() : slash) - start - 1);
      if (!at->is_object()) return nullptr;
      const auto it = at->find(token);
      if (it == at->end()) return nullptr;
      at = &*it;
      if (slash == std::string::npos) break;
      start = slash;
    }
    present_.insert(pointer);
    return at;
  }

  void read_field(const Field& f, const json& v) {
    const std::string p = f.pointer;
    switch (f.kind) {
      case Kind::Integer: {
        const std::string what = "an integer in " + range_text(f);
        long long n = 0;
        if (v.is_number_unsigned()) {
          const auto u = v.get<std::uint64_t>();
          if (u > static_cast<std::uint64_t>(f.hi)) return expected(p, what, v);
          n = static_cast<long long>(u);
        } else if (v.is_number_integer()) {
          n = v.get<std::int64_t>();
        } else if (v.is_number_float()) {
          const double d = v.get<double>();
          if (d != std::floor(d) || d < f.lo || d > f.hi) return expected(p, what, v);
          n = static_cast<long long>(d);
        } else {
          return expected(p, what, v);
        }
        if (static_cast<double>(n) < f.lo || static_cast<double>(n) > f.hi) return expected(p, what, v);
        std::visit(
            [&](auto access) {
              using A = decltype(access);
              if constexpr (std::is_same_v<A, int& (*)(RunConfig&)>) access(config_) = static_cast<int>(n);
              else if constexpr (std::is_same_v<A, long long& (*)(RunConfig&)>) access(config_) = n;
              else if constexpr (std::is_same_v<A, std::uint64_t& (*)(RunConfig&)>)
                access(config_) = static_cast<std::uint64_t>(n);
            },
            f.access);
        return;
      }
      case Kind::Number: {
        const std::string what = "a number in " + range_text(f);
        if (!v.is_number()) return expected(p, what, v);
        const double d = v.get<double>();
        const bool above_lo = f.lo_open ? d > f.lo : d >= f.lo;
        const bool below_hi = f.hi_open ? d < f.hi : d <= f.hi;
        if (!std::isfinite(d) || !above_lo || !below_hi) return expected(p, what, v);
        std::get<double& (*)(RunConfig&)>(f.access)(config_) = d;
        return;
      }
      case Kind::Name:
        if (!v.is_string() || !is_valid_name(v.get<std::string>())) {
          return expected(p, "a name of 1 to 64 characters from A-Z a-z 0-9 _ . - (not only dots)", v);
        }
        config_.name = v.get<std::string>();
        return;
      case Kind::Preset:
        if (v == "sodarace") preset_sodarace_ = true;
        else if (v != "none") expected(p, "one of " + quoted_list({"none", "sodarace"}), v);
        return;
      case Kind::Comment:
        if (!v.is_string()) expected(p, "a string (ignored)", v);
        return;
      case Kind::SeedModels:
        return read_seed_models(v);
      case Kind::FitnessKindName:
        if (const std::optional<FitnessKind> kind =
                v.is_string() ? parse_fitness_kind(v.get<std::string>()) : std::nullopt) {
          config_.fitness.kind = *kind;
        } else {
          expected(p, "one of " + quoted_list(fitness_kind_names()), v);
        }
        return;
      case Kind::Race: {
        std::vector<ConfigProblem> problems;
        read_race_fitness(v, base_dir_, config_.fitness.race, problems);
        for (const ConfigProblem& problem : problems) error(problem.pointer, problem.message);
        if (!problems.empty()) bad_.insert(p);
        return;
      }
      case Kind::Direction:
        return read_enum(p, v, kWalkDirectionNames, config_.fitness.direction);
      case Kind::Scaling:
        return read_enum(p, v, kFitnessScalingNames, config_.fitness.scaling);
      case Kind::Mode:
        return read_enum(p, v, soda::kPhysicsModeNames, config_.fitness.mode);
      case Kind::Integrator:
        return read_enum(p, v, soda::kIntegratorNames, config_.fitness.integrator);
      case Kind::Divergence:
        return read_enum(p, v, kDivergenceCheckNames, config_.fitness.divergence);
      case Kind::Statistic:
        return read_enum(p, v, kEstimateStatisticNames, config_.fitness.statistic);
      case Kind::GravityDirection:
        return read_enum(p, v, kGravityDirectionNames, config_.world.gravity_direction);
      case Kind::WorldEvolve:
        return read_world_evolve(v);
      case Kind::Algorithm:
        return read_enum(p, v, kAlgorithmNames, config_.algorithm);
      case Kind::MapElites: {
        std::vector<ConfigProblem> problems;
        read_map_elites(v, config_.map_elites, problems);
        for (const ConfigProblem& problem : problems) error(problem.pointer, problem.message);
        return;
      }
    }
  }

  template <class E, std::size_t N>
  void read_enum(const std::string& p, const json& v, const EnumName<E> (&names)[N], E& out) {
    if (v.is_string()) {
      if (const std::optional<E> value = soda::value_of(names, v.get<std::string>())) {
        out = *value;
        return;
      }
    }
    expected(p, "one of " + quoted_list(soda::names_of(names)), v);
  }

  void read_seed_models(const json& v) {
    std::vector<ConfigProblem> problems;
    std::optional<std::vector<std::string>> models = read_seed_model_paths(v, base_dir_, problems);
    for (const ConfigProblem& problem : problems) error(problem.pointer, problem.message);
    if (models) config_.population.seed_models = std::move(*models);
    else bad_.insert("/population/seed_models");
  }

  void read_world_evolve(const json& v) {
    const std::string p = "/world/evolve";
    const auto& allowed = world_parameter_names();
    if (!v.is_array()) return expected(p, "an array of world parameter names", v);
    std::set<std::string> chosen;
    bool all_ok = true;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const std::string pi = p + "/" + std::to_string(i);
      const json& item = v[i];
      if (!item.is_string() ||
          std::find(allowed.begin(), allowed.end(), item.get<std::string>()) == allowed.end()) {
        expected(pi, "one of " + quoted_list(allowed), item);
        all_ok = false;
      } else if (!chosen.insert(item.get<std::string>()).second) {
        expected(pi, "a world parameter not listed before", item);
        all_ok = false;
      }
    }
    if (!all_ok) {
      bad_.insert(p);
      return;
    }
    config_.world.evolve.clear();
    for (const std::string& name : allowed) {
      if (chosen.count(name) != 0) config_.world.evolve.push_back(name);
    }
  }

  void resolve_world_evolve() {
    if (preset_sodarace_ && !given("/world/evolve")) config_.world.evolve = world_parameter_names();
  }

  // An integer that must lie in [lo, hi] because of other keys; `why` names them.
  void check_between(const char* pointer, long long value, long long lo, long long hi, const std::string& why) {
    if (bad_.count(pointer) != 0 || (value >= lo && value <= hi)) return;
    expected(pointer,
             "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] (" + why + ")",
             json(value));
  }

  void check_cross_fields() {
    // Each rule runs only when the keys it relates are valid so far (ok() is
    // asked again after every rule), so one mistake gives one message.
    const RunConfig& c = config_;
    if (ok("/limits/min_masses") && ok("/limits/max_masses")) {
      check_between("/limits/min_masses", c.limits.min_masses, 2, c.limits.max_masses,
                    "at most /limits/max_masses");
    }
    if (ok("/population/random/masses_max") && ok("/limits/max_masses")) {
      check_between("/population/random/masses_max", c.population.random.masses_max, 2,
                    c.limits.max_masses, "at most /limits/max_masses");
    }
    if (ok("/population/random/masses_min") && ok("/population/random/masses_max") &&
        ok("/limits/min_masses")) {
      check_between("/population/random/masses_min", c.population.random.masses_min,
                    c.limits.min_masses, c.population.random.masses_max,
                    "from /limits/min_masses to /population/random/masses_max");
    }
    const bool population_size = ok("/population/size");
    if (ok("/population/random/masses_max") && ok("/limits/max_links")) {
      check_between("/limits/max_links", c.limits.max_links,
                    std::max(1, c.population.random.masses_max - 1), 100000,
                    "a random creature of /population/random/masses_max masses needs that many links "
                    "to be connected");
    }
    if (population_size) {
      check_between("/selection/tournament_size", c.selection.tournament_size, 1, c.population.size,
                    "at most /population/size");
      check_between("/selection/elites", c.selection.elites, 0, c.population.size - 1,
                    "less than /population/size");
    }
    if (ok("/algorithm") && given("/map_elites") && c.algorithm != AlgorithmKind::MapElites) {
      error("/map_elites", "expected only with /algorithm \"map-elites\", got it with the GA");
    }
    if (ok("/algorithm") && c.algorithm == AlgorithmKind::MapElites &&
        (c.fitness.mode != soda::PhysicsMode::Soda || c.fitness.divergence != DivergenceCheck::Finite ||
         c.fitness.honesty_max_change > 0.0)) {
      error("/algorithm", "expected \"ga\" with /fitness/mode \"continuous\", /fitness/divergence \"energy\" or "
                          "/fitness/honesty (MAP-Elites measures its descriptors in the soda mode only), "
                          "got \"map-elites\"");
    }
    if (ok("/fitness/kind") && ok("/fitness/race") && ok("/algorithm")) {
      const bool soda_mode = c.fitness.mode == soda::PhysicsMode::Soda &&
                             c.fitness.divergence == DivergenceCheck::Finite && !(c.fitness.honesty_max_change > 0.0);
      for (const ConfigProblem& problem : race_fitness_conflicts(c.fitness.kind, c.fitness.race, given("/fitness/race"),
                                                                 c.algorithm == AlgorithmKind::MapElites ? &c.map_elites : nullptr, soda_mode)) {
        error(problem.pointer, problem.message);
      }
    }
    if (ok("/fitness/replicas") && ok("/fitness/replicas_max")) {
      // Unset, the cap follows a large replica count up.
      if (!given("/fitness/replicas_max")) config_.fitness.replicas_max = std::max(32, c.fitness.replicas);
      check_between("/fitness/replicas_max", c.fitness.replicas_max, c.fitness.replicas, 1024,
                    "at least /fitness/replicas");
    }
    if (ok("/population/seed_models") && ok("/population/random_fraction") &&
        c.population.seed_models.empty() && c.population.random_fraction != 1.0) {
      expected("/population/random_fraction",
               "1 when /population/seed_models is empty (every creature is then random; "
               "list seed models or set random_fraction to 1)",
               json(c.population.random_fraction));
    }
  }

  std::string source_;
  fs::path base_dir_;
  RunConfig config_;
  bool preset_sodarace_ = false;
  std::vector<std::string> errors_;
  std::set<std::string> present_; ///< table pointers found in the document
  std::set<std::string> bad_;     ///< pointers with an error
};

} // namespace

RunConfig parse_run_config(const std::string& json_text, const std::string& source,
                           const std::filesystem::path& base_dir) {
  if (json_text.size() > kMaxConfigBytes) {
    throw soda::InputError(source + ": expected a config of at most " + std::to_string(kMaxConfigBytes >> 10) +
                           " KiB (a config is a few), got " + std::to_string(json_text.size() >> 10) + " KiB");
  }
  return ConfigReader(source, base_dir).read(json_text);
}

RunConfig read_run_config(const std::filesystem::path& path) {
  const std::string source = path.string();
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    throw soda::InputError(source + ": cannot read the config file: it is a folder");
  }
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec && size > kMaxConfigBytes) {
    throw soda::InputError(source + ": cannot read the config file: expected at most " +
                           std::to_string(kMaxConfigBytes >> 10) + " KiB (a config is a few), got " +
                           std::to_string(size >> 10) + " KiB");
  }
  std::ifstream in(path, std::ios::binary);
  if (const int err = errno; !in) {
    throw soda::InputError(source + ": cannot read the config file: " + (err != 0 ? std::strerror(err) : "cannot open it"));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw soda::InputError(source + ": cannot read the config file: read error");
  const fs::path absolute = fs::absolute(path, ec);
  return parse_run_config(text.str(), source, (ec ? path : absolute).lexically_normal().parent_path());
}

nlohmann::json to_json(const RunConfig& config) {
  RunConfig c = config; // the accessors hand out references into a RunConfig
  json j = json::object();
  for (const Field& f : fields()) {
    const json::json_pointer p(f.pointer);
    switch (f.kind) {
      case Kind::Integer:
      case Kind::Number:
        std::visit(
            [&](auto access) {
              if constexpr (!std::is_same_v<decltype(access), std::monostate>) j[p] = access(c);
            },
            f.access);
        break;
      case Kind::Name: j[p] = c.name; break;
      case Kind::SeedModels: j[p] = c.population.seed_models; break;
      // A walk run's config.json stays as it was before races existed.
      case Kind::FitnessKindName:
        if (c.fitness.kind != FitnessKind::Walk) j[p] = fitness_kind_name(c.fitness.kind);
        break;
      case Kind::Race:
        if (c.fitness.kind != FitnessKind::Walk) j[p] = to_json(c.fitness.race);
        break;
      case Kind::Direction: j[p] = direction_name(c.fitness.direction); break;
      case Kind::Scaling: j[p] = scaling_name(c.fitness.scaling); break;
      case Kind::Mode: j[p] = soda::mode_name(c.fitness.mode); break;
      case Kind::Integrator: j[p] = soda::integrator_name(c.fitness.integrator); break;
      case Kind::Divergence: j[p] = divergence_check_name(c.fitness.divergence); break;
      case Kind::Statistic: j[p] = statistic_name(c.fitness.statistic); break;
      case Kind::GravityDirection: j[p] = gravity_direction_name(c.world.gravity_direction); break;
      case Kind::WorldEvolve: j[p] = c.world.evolve; break;
      // A GA run's config.json stays as it was before MAP-Elites existed.
      case Kind::Algorithm:
        if (c.algorithm != AlgorithmKind::Genetic) j[p] = algorithm_name(c.algorithm);
        break;
      case Kind::MapElites:
        if (c.algorithm != AlgorithmKind::Genetic) j[p] = to_json(c.map_elites);
        break;
      case Kind::Preset:  // resolved into /world/evolve
      case Kind::Comment: // not part of the configuration
        break;
    }
  }
  return j;
}

} // namespace sodaevo
