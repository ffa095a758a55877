#include "map_elites_config.hpp"

#include <algorithm>
#include <cmath>

#include "core/number_text.hpp"

namespace sodaevo {

namespace {

using nlohmann::json;

std::string show(const json& v) {
  std::string s = v.dump(-1, ' ', false, json::error_handler_t::replace);
  constexpr std::size_t kMax = 120;
  if (s.size() > kMax) s = s.substr(0, kMax) + "...";
  return s;
}

std::string join(const std::vector<std::string>& names, const char* separator) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : separator) + n;
  return out;
}

const std::vector<std::string>& keys() {
  static const std::vector<std::string> k = {"descriptors", "bins",          "ranges",       "iterations",
                                             "batch_size",  "crossover_rate", "snapshot_every", "sample_every",
                                             "qd_offset",   "check_replicas", "parent_tournament",
                                             "elite_share", "elite_pool",  "elite_recent"};
  return k;
}

class Reader {
 public:
  Reader(MapElitesConfig& config, std::vector<ConfigProblem>& problems) : config_(config), problems_(problems) {}

  void read(const json& v) {
    if (!v.is_object()) {
      expected("", "an object with keys " + join(keys(), ", "), v);
      return;
    }
    for (const auto& [key, value] : v.items()) {
      if (std::find(keys().begin(), keys().end(), key) == keys().end()) {
        problem("/" + key, "unknown key (expected one of: " + join(keys(), ", ") + ")");
      }
    }
    integer(v, "iterations", 1, 1e6, config_.iterations);
    integer(v, "batch_size", 1, 100000, config_.batch_size);
    number(v, "crossover_rate", 0, 1, config_.crossover_rate);
    integer(v, "snapshot_every", 0, 1e6, config_.snapshot_every);
    integer(v, "sample_every", 1, 1e6, config_.sample_every);
    number(v, "qd_offset", -1e9, 1e9, config_.qd_offset);
    integer(v, "check_replicas", 0, 4096, config_.check_replicas);
    integer(v, "parent_tournament", 1, 64, config_.parent_tournament);
    number(v, "elite_share", 0, 1, config_.elite_share);
    integer(v, "elite_pool", 1, 100000, config_.elite_pool);
    integer(v, "elite_recent", 0, 1e6, config_.elite_recent);
    read_axes(v);
  }

 private:
  void problem(const std::string& pointer, const std::string& message) {
    problems_.push_back({"/map_elites" + pointer, message});
  }
  void expected(const std::string& pointer, const std::string& what, const json& got) {
    problem(pointer, "expected " + what + ", got " + show(got));
  }

  static bool is_integer_in(const json& v, double lo, double hi) {
    if (!v.is_number()) return false;
    const double d = v.get<double>();
    return d == std::floor(d) && d >= lo && d <= hi;
  }
  static std::string bound(double v) {
    return v == std::floor(v) && std::fabs(v) < 1e15 ? std::to_string(static_cast<long long>(v))
                                                     : soda::format_double_plain(v);
  }

  void integer(const json& v, const char* key, double lo, double hi, int& out) {
    const auto it = v.find(key);
    if (it == v.end()) return;
    if (!is_integer_in(*it, lo, hi)) {
      expected(std::string("/") + key, "an integer in [" + bound(lo) + ", " + bound(hi) + "]", *it);
      return;
    }
    out = static_cast<int>(it->get<double>());
  }
  void number(const json& v, const char* key, double lo, double hi, double& out) {
    const auto it = v.find(key);
    if (it == v.end()) return;
    if (!it->is_number() || !(it->get<double>() >= lo && it->get<double>() <= hi)) {
      expected(std::string("/") + key, "a number in [" + bound(lo) + ", " + bound(hi) + "]", *it);
      return;
    }
    out = it->get<double>();
  }

  void read_axes(const json& v) {
    const auto d = v.find("descriptors");
    const auto b = v.find("bins");
    const auto r = v.find("ranges");
    if (d == v.end() && b == v.end() && r == v.end()) return; // the default grid
    // The three arrays describe one grid: given together, one entry per axis.
    for (const char* key : {"descriptors", "bins", "ranges"}) {
      if (v.find(key) == v.end()) {
        problem(std::string("/") + key,
                "expected an array (descriptors, bins and ranges are given together), got nothing");
      }
    }
    if (d == v.end() || b == v.end() || r == v.end()) return;
    std::vector<GridAxis> axes;
    const std::string names = "one of " + join(descriptor_names(), ", ");
    if (!d->is_array() || d->size() < 2 || d->size() > 3) {
      expected("/descriptors", "an array of 2 or 3 descriptor names (" + names + ")", *d);
      return;
    }
    bool ok = true;
    for (std::size_t i = 0; i < d->size(); ++i) {
      const json& name = (*d)[i];
      const std::string at = "/descriptors/" + std::to_string(i);
      const std::optional<Descriptor> descriptor =
          name.is_string() ? descriptor_from_name(name.get<std::string>()) : std::nullopt;
      if (!descriptor) {
        expected(at, names, name);
        ok = false;
        continue;
      }
      for (const GridAxis& earlier : axes) {
        if (earlier.descriptor == *descriptor) {
          expected(at, "a descriptor not named before", name);
          ok = false;
        }
      }
      axes.push_back({*descriptor, 1, 0.0, 1.0});
    }
    const std::string count = std::to_string(d->size());
    if (!b->is_array() || b->size() != d->size()) {
      expected("/bins", "an array of " + count + " integers (one per descriptor)", *b);
      ok = false;
    }
    if (!r->is_array() || r->size() != d->size()) {
      expected("/ranges", "an array of " + count + " [lo, hi] pairs (one per descriptor)", *r);
      ok = false;
    }
    if (!ok) return;
    double cells = 1;
    for (std::size_t i = 0; i < axes.size(); ++i) {
      const json& bins = (*b)[i];
      if (!is_integer_in(bins, 1, kMaxArchiveCells)) {
        expected("/bins/" + std::to_string(i), "an integer in [1, " + bound(kMaxArchiveCells) + "]", bins);
        ok = false;
      } else {
        axes[i].bins = static_cast<int>(bins.get<double>());
        cells *= axes[i].bins;
      }
      const json& range = (*r)[i];
      const std::string at = "/ranges/" + std::to_string(i);
      if (!range.is_array() || range.size() != 2 || !range[0].is_number() || !range[1].is_number() ||
          !std::isfinite(range[0].get<double>()) || !std::isfinite(range[1].get<double>())) {
        expected(at, "a pair of numbers [lo, hi]", range);
        ok = false;
      } else if (!(range[0].get<double>() < range[1].get<double>())) {
        expected(at, "lo < hi (a range that is neither empty nor inverted)", range);
        ok = false;
      } else {
        axes[i].lo = range[0].get<double>();
        axes[i].hi = range[1].get<double>();
      }
    }
    if (ok && cells > kMaxArchiveCells) {
      problem("/bins", "expected at most " + bound(kMaxArchiveCells) + " cells (the bins multiplied), got " +
                           bound(cells) + " from " + show(*b));
      ok = false;
    }
    if (ok) config_.axes = std::move(axes);
  }

  MapElitesConfig& config_;
  std::vector<ConfigProblem>& problems_;
};

} // namespace

void read_map_elites(const json& value, MapElitesConfig& config, std::vector<ConfigProblem>& problems) {
  Reader(config, problems).read(value);
}

json to_json(const MapElitesConfig& c) {
  json descriptors = json::array(), bins = json::array(), ranges = json::array();
  for (const GridAxis& a : c.axes) {
    descriptors.push_back(descriptor_name(a.descriptor));
    bins.push_back(a.bins);
    ranges.push_back({a.lo, a.hi});
  }
  json j = {{"descriptors", descriptors},     {"bins", bins},
          {"ranges", ranges},               {"iterations", c.iterations},
          {"batch_size", c.batch_size},     {"crossover_rate", c.crossover_rate},
          {"snapshot_every", c.snapshot_every}, {"sample_every", c.sample_every},
          {"qd_offset", c.qd_offset},       {"check_replicas", c.check_replicas},
          {"parent_tournament", c.parent_tournament}, {"elite_share", c.elite_share},
          {"elite_pool", c.elite_pool}};
  if (c.elite_recent > 0) j["elite_recent"] = c.elite_recent; // absent when off: older run folders keep their bytes
  return j;
}

} // namespace sodaevo
