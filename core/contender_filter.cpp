#include "contender_filter.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace soda {

namespace {

/// Union-find root of `i`, halving paths as it goes.
int root_of(std::vector<int>& parent, int i) {
  while (parent[static_cast<std::size_t>(i)] != i) {
    parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    i = parent[static_cast<std::size_t>(i)];
  }
  return i;
}

bool is_mass(const ModelDef& c, int node) { return !c.nodes[static_cast<std::size_t>(node)].fixed; }

/// The link's ends are valid node indices (a ModelDef from a reader always has them).
bool ends_valid(const ModelDef& c, const LinkDef& l) {
  const auto n = static_cast<int>(c.nodes.size());
  return l.a >= 0 && l.a < n && l.b >= 0 && l.b < n;
}

/// The link's Lmax in the scale's sum (docs/physics.md, "The contender", step 5). A link from a mass to
/// itself counts by its kind like any other (golden c09: a self muscle by the
/// muscle formula).
double lmax_of(const ModelDef& c, const LinkDef& l) {
  if (l.kind == LinkKind::FixedBar) { // the distance between its masses as loaded
    const NodeDef& a = c.nodes[static_cast<std::size_t>(l.a)];
    const NodeDef& b = c.nodes[static_cast<std::size_t>(l.b)];
    const double dx = b.x - a.x, dy = b.y - a.y;
    return std::sqrt(dx * dx + dy * dy);
  }
  if (l.kind == LinkKind::Muscle) return l.rest_length * (1.0 + l.amplitude * c.wave.amplitude);
  return l.rest_length;
}

} // namespace

ContenderPieces contender_pieces(const ModelDef& c) {
  ContenderPieces out;
  std::vector<int> parent(c.nodes.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (const LinkDef& l : c.links) {
    if (!ends_valid(c, l) || !is_mass(c, l.a) || !is_mass(c, l.b)) continue;
    const int ra = root_of(parent, l.a), rb = root_of(parent, l.b);
    // The smaller index as root: a piece's root is then its earliest mass.
    if (ra != rb) parent[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
  }
  std::vector<int> size(c.nodes.size(), 0);
  for (std::size_t i = 0; i < c.nodes.size(); ++i) {
    if (c.nodes[i].fixed) continue;
    ++out.masses;
    if (size[static_cast<std::size_t>(root_of(parent, static_cast<int>(i)))]++ == 0) ++out.pieces;
  }
  // Roots are visited in file order, so the strict > keeps the earliest on a tie.
  int best = -1;
  for (std::size_t i = 0; i < c.nodes.size(); ++i) {
    if (size[i] > 0 && (best < 0 || size[i] > size[static_cast<std::size_t>(best)])) best = static_cast<int>(i);
  }
  for (std::size_t i = 0; i < c.nodes.size() && best >= 0; ++i) {
    if (!c.nodes[i].fixed && root_of(parent, static_cast<int>(i)) == best) out.kept.push_back(static_cast<int>(i));
  }
  return out;
}

FilteredContender filter_contender(const ModelDef& c, const std::string& name) {
  if (c.nodes.empty()) {
    throw ContenderRejected(name + ": no result: the racer cannot race a contender without nodes");
  }
  if (c.nodes.back().fixed) {
    throw ContenderRejected(name + ": no result: the last entry of <nodes> ('" + c.nodes.back().id +
                            "') is a fixed node, which makes the original racer's contender filter fail "
                            "(expected a mass last; fixed nodes elsewhere are dropped)");
  }
  FilteredContender out;
  out.pieces = contender_pieces(c);
  std::vector<int> index(c.nodes.size(), -1);
  for (int node : out.pieces.kept) {
    index[static_cast<std::size_t>(node)] = static_cast<int>(out.masses.size());
    out.masses.push_back(c.nodes[static_cast<std::size_t>(node)]);
  }
  double sum = 0.0;
  for (const LinkDef& l : c.links) {
    if (!ends_valid(c, l)) {
      throw InputError(name + ": link from node " + std::to_string(l.a) + " to node " + std::to_string(l.b) +
                       ": expected node indices in [0, " + std::to_string(c.nodes.size()) + ")");
    }
    if (index[static_cast<std::size_t>(l.a)] < 0 || index[static_cast<std::size_t>(l.b)] < 0) continue;
    if (l.kind == LinkKind::FixedBar && l.a == l.b) {
      throw ContenderRejected(name + ": no result: a fixed bar from mass '" + c.nodes[static_cast<std::size_t>(l.a)].id +
                              "' to itself (what the original racer does with one is not known to this port)");
    }
    const double lmax = lmax_of(c, l);
    sum += lmax * lmax;
    LinkDef kept = l;
    kept.a = index[static_cast<std::size_t>(l.a)];
    kept.b = index[static_cast<std::size_t>(l.b)];
    if (kept.kind == LinkKind::FixedBar) kept.rest_length = 0.0; // a bar has no rest length (one in the file is ignored)
    out.links.push_back(kept);
  }
  // sum = 0 divides to +inf, as in Java: the racer races a NaN contender then.
  out.scale = (static_cast<double>(c.height) / 2.0) / std::sqrt(sum);
  double min_x = out.masses[0].x, max_x = min_x, max_y = out.masses[0].y;
  for (const NodeDef& m : out.masses) {
    min_x = std::min(min_x, m.x);
    max_x = std::max(max_x, m.x);
    max_y = std::max(max_y, m.y);
  }
  const double cx = (min_x + max_x) / 2.0;
  const double cy = max_y;
  for (NodeDef& m : out.masses) {
    m.x = cx + (m.x - cx) * out.scale;
    m.y = cy + (m.y - cy) * out.scale;
    m.vx = m.vx * out.scale;
    m.vy = m.vy * out.scale;
  }
  for (LinkDef& l : out.links) l.rest_length = l.rest_length * out.scale;
  return out;
}

} // namespace soda
