#include "fixed_bars.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace soda {

std::string bar_engine_name(BarEngine engine) {
  return engine == BarEngine::Racer2004 ? "2004" : "2003";
}

bool parse_bar_engine(const std::string& text, BarEngine& engine) {
  if (text == "2003") {
    engine = BarEngine::SodaConstructor2003;
  } else if (text == "2004") {
    engine = BarEngine::Racer2004;
  } else {
    return false;
  }
  return true;
}


int relative_ccw(double x1, double y1, double x2, double y2, double px, double py) {
  x2 -= x1;
  y2 -= y1;
  px -= x1;
  py -= y1;
  double ccw = px * y2 - py * x2;
  if (ccw == 0.0) {
    // On the line: before a counts as left, beyond b as right, on the segment as 0.
    ccw = px * x2 + py * y2;
    if (ccw > 0.0) {
      px -= x2;
      py -= y2;
      ccw = px * x2 + py * y2;
      if (ccw < 0.0) ccw = 0.0;
    }
  }
  return ccw < 0.0 ? -1 : (ccw > 0.0 ? 1 : 0);
}

namespace {

constexpr double kTweak = 1e-4;            // FixedBar.TWEAK of the original
constexpr double kRacerBoxWidening = 0.01; // the racer's box on an inverted axis (physics.md, last bits)

/// java.awt.geom.Line2D.linesIntersect semantics (touching counts).
bool lines_intersect(double x1, double y1, double x2, double y2, double x3, double y3, double x4, double y4) {
  return relative_ccw(x1, y1, x2, y2, x3, y3) * relative_ccw(x1, y1, x2, y2, x4, y4) <= 0 &&
         relative_ccw(x3, y3, x4, y4, x1, y1) * relative_ccw(x3, y3, x4, y4, x2, y2) <= 0;
}

int side_of(const FixedBar& bar, double px, double py) {
  return relative_ccw(bar.x1, bar.y1, bar.x2, bar.y2, px, py);
}

/// s0 for a mass the bar remembers on side `side` (SideRule); counts far starts.
int remembered_side(const FixedBar& bar, SideRule rule, int side, double ox, double oy, BarMemory& memory) {
  const double num = bar.w * (oy - bar.y1) - bar.h * (ox - bar.x1); // the distance to the line times L
  if (std::fabs(num) <= kSideTolerance * bar.length) return side;
  const int own = side_of(bar, ox, oy);
  if (own != side) ++memory.counters.far_starts;
  return rule == SideRule::Stored ? side : own;
}

struct Point {
  double x, y;
};

/// How far along the move o -> n it crosses the bar's line, as a share of the move:
/// |num / den| of crossing_point, 1 for a move parallel to the bar (crossing_point is
/// then n). The bar hit first is the one of least share (docs/physics.md, "Inferred
/// rules": at a shared end point both crossing points round to the node, so their
/// distances from o tie, while the shares still tell which line the move meets first).
double crossing_share(const FixedBar& bar, const MassMove& m) {
  const double num = bar.w * (m.y0 - bar.y1) - bar.h * (m.x0 - bar.x1);
  const double den = bar.h * (m.x - m.x0) - bar.w * (m.y - m.y0);
  return den == 0.0 ? 1.0 : std::fabs(num / den);
}

/// Where the line of the move o -> n crosses the bar's line; n for a move parallel to it.
Point crossing_point(const FixedBar& bar, double ox, double oy, double nx, double ny) {
  const double mx = nx - ox;
  const double my = ny - oy;
  const double num = bar.w * (oy - bar.y1) - bar.h * (ox - bar.x1);
  const double den = bar.h * mx - bar.w * my;
  if (den == 0.0) return {nx, ny};
  return {ox + num * mx / den, oy + num * my / den};
}

/// The point of the bar's line at parameter s from its start.
Point point_at(const FixedBar& bar, double s) { return {bar.x1 + s * bar.ux, bar.y1 + s * bar.uy}; }

/// Parameter along the bar of the projection of (px, py).
double parameter_of(const FixedBar& bar, double px, double py) {
  return (px - bar.x1) * bar.ux + (py - bar.y1) * bar.uy;
}

/// Where the mass ends for a bar's answer p: the engine keeps the move as a
/// displacement, so p is re-added to the start, o + (p - o), two roundings per
/// axis (docs/physics.md, "The last bits"; not p itself in the last bits when p and o lie in
/// different binades, e.g. near the floor).
Point readded(const MassMove& m, Point p) { return {m.x0 + (p.x - m.x0), m.y0 + (p.y - m.y0)}; }

/// The crossing point plus the surface friction's share of the rest of the move along the bar.
Point slide(const FixedBar& bar, Point p, double nx, double ny, double sf) {
  const double d = (nx - p.x) * bar.ux + (ny - p.y) * bar.uy;
  return {p.x + sf * d * bar.ux, p.y + sf * d * bar.uy};
}

/// The velocity after a hit: tangential part times Fs, normal part times Rs. The
/// normal is (uy, -ux): the same bits as (-uy, ux) but for the sign of a zero, which
/// the originals' traces show (a mass sliding left on a level bar keeps vy = -0;
/// lastbit scenes lowfar_2003_17, lowfar_2004_21).
void bar_velocity(const FixedBar& bar, double vx, double vy, const Surface& surface, MassEnd& end) {
  const double vt = vx * bar.ux + vy * bar.uy;
  const double vn = vx * bar.uy + vy * -bar.ux;
  end.vx = surface.friction * vt * bar.ux + surface.reflection * vn * bar.uy;
  end.vy = surface.friction * vt * bar.uy + surface.reflection * vn * -bar.ux;
}

/// One axis of the racer's (2004) box test: the bar's range [start, start + size]
/// as is. An inverted axis (size < 0) takes the move's range as X = min - 0.01,
/// W = |move| + 0.01, in this rounding order (docs/physics.md, "The last bits").
bool racer_axis_touches(double start, double size, double from, double to) {
  if (size >= 0.0) return std::max(from, to) >= start && std::min(from, to) <= start + size;
  const double lo = std::min(from, to) - kRacerBoxWidening;
  const double extent = std::fabs(to - from) + kRacerBoxWidening;
  return lo + extent >= start && lo <= start + size;
}

bool box_touches(const FixedBar& bar, BarEngine engine, const MassMove& m) {
  if (engine == BarEngine::Racer2004) {
    return racer_axis_touches(bar.x1, bar.w, m.x0, m.x) && racer_axis_touches(bar.y1, bar.h, m.y0, m.y);
  }
  return std::max(m.x0, m.x) >= bar.box_x0 && std::min(m.x0, m.x) <= bar.box_x1 &&
         std::max(m.y0, m.y) >= bar.box_y0 && std::min(m.y0, m.y) <= bar.box_y1;
}

bool in_box_with_margin(const FixedBar& bar, Point p, double margin) {
  return p.x >= bar.box_x0 - margin && p.x <= bar.box_x1 + margin && p.y >= bar.box_y0 - margin &&
         p.y <= bar.box_y1 + margin;
}

bool outside_container(Point p, const Surface& s) {
  return p.x < 0.0 || p.x > s.width || p.y < 0.0 || p.y > s.height;
}

/// A run of bar indices in link order.
struct BarList {
  const int* first = nullptr;
  const int* last = nullptr;
  [[nodiscard]] const int* begin() const { return first; }
  [[nodiscard]] const int* end() const { return last; }
};

/// Bars whose x range the move's x range touches, in link order: one cell's list
/// as it is (a move is shorter than a cell, so nearly always), else the cells'
/// lists merged (into a list of this thread, valid until the next call).
BarList candidate_bars(const FixedBars& bars, double lo, double hi) {
  const int c0 = bars.cell_of(lo), c1 = bars.cell_of(hi);
  const int* cells = bars.cell_bars.data();
  if (c0 == c1) return {cells + bars.cell_start[c0], cells + bars.cell_start[c0 + 1]};
  thread_local std::vector<int> merged; // valid until the next call on this thread
  merged.clear();
  for (int c = c0; c <= c1; ++c) merged.insert(merged.end(), cells + bars.cell_start[c], cells + bars.cell_start[c + 1]);
  std::sort(merged.begin(), merged.end());
  merged.erase(std::unique(merged.begin(), merged.end()), merged.end());
  return {merged.data(), merged.data() + merged.size()};
}

/// A mass in a corner: only the two corner bars count (docs/physics.md, "Fixed bars").
/// Returns true when the corner decided the position (the mass stays or leaves
/// along a bar), false when the mass moves freely (the corner ends).
bool corner_move(const FixedBars& bars, BarMemory& memory, int mass, const MassMove& m, const Surface& surface,
                 MassEnd& end) {
  BarCorner& corner = memory.corners[static_cast<std::size_t>(mass)];
  const FixedBar& c = bars.bars[static_cast<std::size_t>(corner.bar)];
  const int other = corner.end == 0 ? c.prev : c.next;
  const auto wrong_side = [&](int b) {
    if (b < 0) return false;
    const BarContact* remembered = memory.find(b, mass);
    const int side = remembered ? remembered->side : 0;
    return side_of(bars.bars[static_cast<std::size_t>(b)], m.x, m.y) != side;
  };
  if (!wrong_side(corner.bar) && !wrong_side(other)) {
    corner.bar = -1;
    return false;
  }
  // Leave along the bar that starts at the node first, then the one that ends there.
  const int node = corner.end == 0 ? c.a : c.b;
  int first = other, second = corner.bar;
  const bool c_starts = c.a == node;
  const bool other_starts = other >= 0 && bars.bars[static_cast<std::size_t>(other)].a == node;
  if (c_starts && !other_starts) std::swap(first, second);
  end.vx = m.vx;
  end.vy = m.vy;
  for (int b : {first, second}) {
    if (b < 0) continue;
    const FixedBar& e = bars.bars[static_cast<std::size_t>(b)];
    const Point r = slide(e, crossing_point(e, m.x0, m.y0, m.x, m.y), m.x, m.y, surface.friction);
    const double s = parameter_of(e, r.x, r.y);
    if (s > 0.0 && s < e.length) {
      const Point at = readded(m, r);
      end.x = at.x;
      end.y = at.y;
      corner.bar = -1;
      return true;
    }
  }
  end.x = m.x0;
  end.y = m.y0;
  return true;
}

/// After a slide along `bar` that passes one of its ends: the joint with the
/// neighbour there (docs/physics.md, "Fixed bars": a joint). `r` is the slide's end; returns the position.
Point joint(const FixedBars& bars, BarMemory& memory, int mass, int bar_index, int side, Point r,
            const MassMove& m) {
  const FixedBar& bar = bars.bars[static_cast<std::size_t>(bar_index)];
  const double s = parameter_of(bar, r.x, r.y);
  int next = -1;
  bool reversed = false;
  int node = -1;
  if (s > bar.length && bar.next >= 0) {
    next = bar.next;
    reversed = bar.next_reversed;
    node = bar.b;
  } else if (s < 0.0 && bar.prev >= 0) {
    next = bar.prev;
    reversed = bar.prev_reversed;
    node = bar.a;
  }
  if (next < 0) return r;
  const FixedBar& c = bars.bars[static_cast<std::size_t>(next)];
  const int side_on_c = reversed ? -side : side;
  memory.remember(next, mass, side_on_c);
  const double on_c = parameter_of(c, m.x, m.y);
  if (bar.w * c.h - bar.h * c.w == 0.0) return point_at(c, on_c); // colinear: walk on along c
  if (side_of(c, r.x, r.y) == side_on_c) return r;                 // convex: fly on
  // Concave: caught in the corner, unless the end point is already beyond the node on c.
  const std::int8_t end = c.a == node ? 0 : 1;
  if (end == 0 ? on_c >= c.length : on_c <= 0.0) {
    // Past c's far end: at that end, in the corner there (InferredBarRules::far_end_corner).
    ++memory.counters.far_end_corners;
    if (bars.inferred.far_end_corner) {
      memory.corners[static_cast<std::size_t>(mass)] = {next, static_cast<std::int8_t>(1 - end)};
      return point_at(c, end == 0 ? c.length : 0.0);
    }
  }
  if (end == 0 ? on_c > 0.0 : on_c < c.length) return point_at(c, on_c);
  memory.corners[static_cast<std::size_t>(mass)] = {next, end};
  return point_at(c, end == 0 ? 0.0 : c.length);
}

} // namespace

const BarContact* BarMemory::find(int bar, int mass) const {
  for (const BarContact& c : contacts) {
    if (c.bar == bar && c.mass == mass) return &c;
  }
  return nullptr;
}

void BarMemory::remember(int bar, int mass, int side) {
  for (BarContact& c : contacts) {
    if (c.bar == bar && c.mass == mass) {
      c.side = static_cast<std::int8_t>(side);
      return;
    }
  }
  contacts.push_back({bar, mass, static_cast<std::int8_t>(side)});
}

void BarMemory::forget(int bar, int mass) {
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    if (contacts[k].bar == bar && contacts[k].mass == mass) {
      contacts[k] = contacts.back();
      contacts.pop_back();
      return;
    }
  }
}

FixedBars make_fixed_bars(const std::vector<int>& bar_a, const std::vector<int>& bar_b, const double* px,
                          const double* py, BarEngine engine) {
  FixedBars out;
  out.engine = engine;
  const int n = static_cast<int>(bar_a.size());
  out.bars.resize(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    FixedBar& b = out.bars[static_cast<std::size_t>(k)];
    b.a = bar_a[static_cast<std::size_t>(k)];
    b.b = bar_b[static_cast<std::size_t>(k)];
    b.x1 = px[b.a];
    b.y1 = py[b.a];
    b.x2 = px[b.b];
    b.y2 = py[b.b];
    b.w = b.x2 - b.x1;
    b.h = b.y2 - b.y1;
    b.length = std::sqrt(b.w * b.w + b.h * b.h);
    b.ux = b.w / b.length;
    b.uy = b.h / b.length;
    // The 2003 box: the range of (x1, x1 + w), not of the nodes (x1 + w can differ
    // from x2 in the last bit; docs/physics.md, "The last bits").
    b.box_x0 = std::min(b.x1, b.x1 + b.w);
    b.box_x1 = std::max(b.x1, b.x1 + b.w);
    b.box_y0 = std::min(b.y1, b.y1 + b.h);
    b.box_y1 = std::max(b.y1, b.y1 + b.h);
  }
  // Chains: bars sharing a node (the same point); the last in link order wins.
  for (int k = 0; k < n; ++k) {
    FixedBar& b = out.bars[static_cast<std::size_t>(k)];
    for (int j = 0; j < n; ++j) {
      if (j == k) continue;
      const FixedBar& c = out.bars[static_cast<std::size_t>(j)];
      if (c.a == b.b) b.next = j, b.next_reversed = false;
      if (c.b == b.b) b.next = j, b.next_reversed = true;
      if (c.b == b.a) b.prev = j, b.prev_reversed = false;
      if (c.a == b.a) b.prev = j, b.prev_reversed = true;
    }
  }
  if (n == 0) return out;
  // The reach of a bar for the index and the tiles: its box under either rule,
  // i.e. the normalised box, widened on an inverted axis (the racer's test reaches
  // up to 0.01 beyond it, give or take its roundings: 0.02 covers them).
  const auto margin = [](double size) { return size < 0.0 ? 2 * kRacerBoxWidening : 0.0; };
  const auto reach_lo = [&](const FixedBar& b) { return b.box_x0 - margin(b.w); };
  const auto reach_hi = [&](const FixedBar& b) { return b.box_x1 + margin(b.w); };
  const auto reach_y_lo = [&](const FixedBar& b) { return b.box_y0 - margin(b.h); };
  const auto reach_y_hi = [&](const FixedBar& b) { return b.box_y1 + margin(b.h); };
  double lo = reach_lo(out.bars[0]), hi = reach_hi(out.bars[0]);
  for (const FixedBar& b : out.bars) {
    lo = std::min(lo, reach_lo(b));
    hi = std::max(hi, reach_hi(b));
  }
  out.cell_x0 = lo;
  // A power of two: the lookup multiplies by its inverse, which is the division exactly.
  out.cell_width = FixedBars::kMinCellWidth;
  while (out.cell_width < (hi - lo) / FixedBars::kMaxCells) out.cell_width *= 2.0;
  out.cell_scale = 1.0 / out.cell_width;
  out.cell_count = static_cast<int>(std::floor((hi - lo) * out.cell_scale)) + 1;
  std::vector<std::vector<int>> cells(static_cast<std::size_t>(out.cell_count));
  for (int k = 0; k < n; ++k) {
    const FixedBar& b = out.bars[static_cast<std::size_t>(k)];
    const int c0 = static_cast<int>(std::floor((reach_lo(b) - lo) * out.cell_scale));
    const int c1 = std::min(out.cell_count - 1, static_cast<int>(std::floor((reach_hi(b) - lo) * out.cell_scale)));
    for (int c = c0; c <= c1; ++c) cells[static_cast<std::size_t>(c)].push_back(k);
  }
  out.cell_start.push_back(0);
  for (const auto& cell : cells) {
    out.cell_bars.insert(out.cell_bars.end(), cell.begin(), cell.end());
    out.cell_start.push_back(static_cast<int>(out.cell_bars.size()));
  }
  // Tiles: a bar whose x range meets cell c's range as doubles is listed in a cell
  // within one of c (the cells are wide, the rounding of cell_of tiny).
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (int c = 0; c < out.cell_count; ++c) {
    // The first and last tiles reach out to infinity (cell_of clamps to them).
    const double x_lo = c == 0 ? -kInf : lo + c * out.cell_width;
    const double x_hi = c == out.cell_count - 1 ? kInf : lo + (c + 1) * out.cell_width;
    double tile[FixedBars::kTileStride] = {x_lo, x_hi, kInf, -kInf, kInf, -kInf, 0.0, 0.0};
    for (int n = std::max(0, c - 1); n <= std::min(out.cell_count - 1, c + 1); ++n) {
      for (int k : cells[static_cast<std::size_t>(n)]) {
        const FixedBar& b = out.bars[static_cast<std::size_t>(k)];
        const double bx0 = reach_lo(b), bx1 = reach_hi(b);
        if (bx1 < x_lo || bx0 > x_hi) continue;
        tile[2] = std::min(tile[2], bx0);
        tile[3] = std::max(tile[3], bx1);
        tile[4] = std::min(tile[4], reach_y_lo(b));
        tile[5] = std::max(tile[5], reach_y_hi(b));
      }
    }
    out.cell_tile.insert(out.cell_tile.end(), tile, tile + FixedBars::kTileStride);
  }
  return out;
}

bool collide_with_fixed_bars(const FixedBars& bars, BarMemory& memory, int mass, const MassMove& m,
                             const Surface& surface, MassEnd& end) {
  if (memory.corners.size() <= static_cast<std::size_t>(mass)) {
    memory.corners.resize(static_cast<std::size_t>(mass) + 1);
  }
  if (memory.corners[static_cast<std::size_t>(mass)].bar >= 0) {
    if (corner_move(bars, memory, mass, m, surface, end)) return true;
    return false;
  }
  const BarList candidates = candidate_bars(bars, std::min(m.x0, m.x), std::max(m.x0, m.x));
  // Bars that remember the mass but are out of reach: their box test fails.
  bool remembered_any = false; // whether any bar remembers this mass (else nothing to find or forget)
  for (std::size_t k = memory.contacts.size(); k-- > 0;) {
    const BarContact c = memory.contacts[k];
    if (c.mass != mass) continue;
    if (!std::binary_search(candidates.begin(), candidates.end(), c.bar)) {
      memory.contacts[k] = memory.contacts.back();
      memory.contacts.pop_back();
    } else {
      remembered_any = true;
    }
  }
  int best = -1;
  int best_side = 0;
  Point best_point{0.0, 0.0};
  double best_share = 0.0;
  // The memory changes exactly as with find / remember / forget each time: a
  // remembered side is never changed here (s0 is it), an absent pair is added.
  for (int k : candidates) {
    const FixedBar& bar = bars.bars[static_cast<std::size_t>(k)];
    const BarContact* remembered = remembered_any ? memory.find(k, mass) : nullptr;
    if (!box_touches(bar, bars.engine, m)) {
      if (remembered) memory.forget(k, mass);
      continue;
    }
    const int s0 =
        remembered ? remembered_side(bar, bars.inferred.side_rule, remembered->side, m.x0, m.y0, memory) : side_of(bar, m.x0, m.y0);
    const int s1 = side_of(bar, m.x, m.y);
    if (s0 == s1 && s0 != 0) {
      if (remembered) memory.forget(k, mass);
      continue;
    }
    Point p{0.0, 0.0};
    if (remembered) {
      p = crossing_point(bar, m.x0, m.y0, m.x, m.y);
      // A move exactly parallel to the bar (p is its end) hits iff it starts exactly
      // on the bar's line, wherever it ends (docs/physics.md, "The last bits").
      const bool parallel = bar.h * (m.x - m.x0) - bar.w * (m.y - m.y0) == 0.0;
      if (parallel ? bar.w * (m.y0 - bar.y1) - bar.h * (m.x0 - bar.x1) != 0.0 : !in_box_with_margin(bar, p, bars.inferred.hit_margin)) {
        if (!parallel && in_box_with_margin(bar, p, kTweakMargin)) ++memory.counters.near_end_misses;
        memory.forget(k, mass);
        continue;
      }
    } else {
      if (!lines_intersect(m.x0, m.y0, m.x, m.y, bar.x1, bar.y1, bar.x2, bar.y2)) continue;
      p = crossing_point(bar, m.x0, m.y0, m.x, m.y);
      memory.contacts.push_back({k, mass, static_cast<std::int8_t>(s0)});
      remembered_any = true;
    }
    // The crossing first along the move wins, by its share of the move (not by the
    // distance of the rounded crossing point, which ties at a shared end point); at
    // equal shares the first bar in link order. Shares are taken only when two compete.
    if (best < 0) {
      best = k;
      best_side = s0;
      best_point = p;
      best_share = -1.0; // not taken yet
      continue;
    }
    if (best_share < 0.0) best_share = crossing_share(bars.bars[static_cast<std::size_t>(best)], m);
    const double share = crossing_share(bar, m);
    if (share < best_share) {
      best = k;
      best_side = s0;
      best_point = p;
      best_share = share;
    }
  }
  if (best < 0) return false;
  const FixedBar& bar = bars.bars[static_cast<std::size_t>(best)];
  bar_velocity(bar, m.vx, m.vy, surface, end);
  const bool clamped = m.free_x != m.x || m.free_y != m.y;
  Point at{0.0, 0.0};
  if (clamped) {
    // The container clamped the end: the unclamped end projected on the bar, its
    // parameter clamped to [0, L] (the ends too are a + s u, not the nodes).
    at = point_at(bar, std::clamp(parameter_of(bar, m.free_x, m.free_y), 0.0, bar.length));
    if (outside_container(at, surface)) at = best_point;
  } else {
    at = joint(bars, memory, mass, best, best_side, slide(bar, best_point, m.x, m.y, surface.friction), m);
  }
  at = readded(m, at);
  end.x = at.x;
  end.y = at.y;
  return true;
}

void tweak_for_writing(const FixedBars& bars, const BarMemory& memory, int mass, double& x, double& y) {
  for (const BarContact& c : memory.contacts) {
    if (c.mass != mass || c.side == 0) continue;
    const FixedBar& bar = bars.bars[static_cast<std::size_t>(c.bar)];
    const double sign = c.side < 0 ? 1.0 : -1.0;
    x += sign * kTweak * -bar.uy;
    y += sign * kTweak * bar.ux;
  }
}

} // namespace soda
