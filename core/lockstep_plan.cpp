// LockstepBatch's construction (lockstep_batch.hpp): which models a batch takes,
// their groups and sine columns, the rows' layout, the states' load and store.
// The frame kernels are in lockstep_batch.cpp.
#include "detail/lockstep_data.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>

#include "constants.hpp"
#include "detail/bits.hpp"
#include "physics_rules.hpp"
#include "scene_analysis.hpp"
#include "simd_level.hpp"

namespace soda {

namespace {
using lockstep_detail::kSideBySide;
using lockstep_detail::kW;
} // namespace

SimdLevel LockstepBatch::level_for(SimdLevel level) {
  if (level != SimdLevel::Auto) return level;
  const SimdLevel best = best_simd_level(); // as forced (simd_level.hpp), if it is
  if (best == SimdLevel::Avx512 && usable(SimdLevel::Avx512)) return SimdLevel::Avx512;
  return best == SimdLevel::Sse2 ? SimdLevel::Sse2 : SimdLevel::Avx2;
}

bool LockstepBatch::usable(SimdLevel level) {
  switch (level) {
    // AVX512DQ for the 8-bit mask instructions and the 64-bit multiply (every AVX-512 CPU but the Xeon Phi has it).
    case SimdLevel::Avx512: return simd_level_supported(SimdLevel::Avx512) && __builtin_cpu_supports("avx512dq");
    case SimdLevel::Avx2: return simd_level_supported(SimdLevel::Avx2);
    case SimdLevel::Auto: return level_for(level) != SimdLevel::Sse2 && usable(level_for(level));
    case SimdLevel::Sse2: return false;
  }
  return false;
}

bool LockstepBatch::can_take(const Model& model) {
  for (int b = 0; b < model.bar_count(); ++b) {
    if (model.is_mass(model.bar_a[b]) || model.is_mass(model.bar_b[b])) return false; // BarKind::MovingEnds
  }
  return true;
}

namespace {
// The same fixed bars: ends, geometry and box rule, bit for bit (the rest of
// FixedBars, chains and the index by x, follows from these: make_fixed_bars).
bool same_bars(const Model& a, const Model& b) {
  const FixedBars& p = a.fixed_bars;
  const FixedBars& q = b.fixed_bars;
  if (a.bar_a != b.bar_a || a.bar_b != b.bar_b || p.engine != q.engine || p.size() != q.size()) return false;
  for (int k = 0; k < p.size(); ++k) {
    const FixedBar& u = p.bars[static_cast<std::size_t>(k)];
    const FixedBar& v = q.bars[static_cast<std::size_t>(k)];
    if (u.a != v.a || u.b != v.b || bits_of(u.x1) != bits_of(v.x1) || bits_of(u.y1) != bits_of(v.y1) ||
        bits_of(u.x2) != bits_of(v.x2) || bits_of(u.y2) != bits_of(v.y2)) {
      return false;
    }
  }
  return true;
}
} // namespace

bool LockstepBatch::same_shape(const Model& a, const Model& b) {
  return can_take(a) && can_take(b) && a.mass_count == b.mass_count && a.point_count == b.point_count &&
         a.link_a == b.link_a && a.link_b == b.link_b && same_bars(a, b);
}

LockstepBatch::LockstepBatch(std::unique_ptr<Data> d, int) : d_(std::move(d)) {}

LockstepBatch::LockstepBatch(const std::vector<const Model*>& models, SimdLevel level)
    : LockstepBatch(of_shapes({models}, level)) {}

LockstepBatch LockstepBatch::of_shapes(const std::vector<std::vector<const Model*>>& shapes, SimdLevel level) {
  if (shapes.empty()) throw std::invalid_argument("LockstepBatch: no models");
  for (const std::vector<const Model*>& models : shapes) {
    if (models.empty()) throw std::invalid_argument("LockstepBatch: no models");
    for (const Model* m : models) {
      assert(constants_current(*m));
      if (!same_shape(*models[0], *m)) throw std::invalid_argument("LockstepBatch: models of different shapes (or bars), or with a fixed bar moved by a mass");
    }
  }
  if (!usable(level)) {
    throw std::runtime_error(std::string("LockstepBatch: this CPU does not run lockstep kernels at level ") + simd_level_name(level) +
                             " (they need AVX2, or AVX-512 F and DQ)");
  }
  auto data = std::make_unique<Data>();
  Data& d = *data;
  d.level = level_for(level);
  d.kernels = d.level == SimdLevel::Avx512 ? lockstep_kernels_avx512() : lockstep_kernels_avx2();
  for (const std::vector<const Model*>& models : shapes) {
    const int n = static_cast<int>(models.size());
    for (int first = 0; first < n; first += kW) {
      const std::vector<const Model*> lanes(models.begin() + first, models.begin() + std::min(n, first + kW));
      d.add_group(lanes, d.count + first, static_cast<int>(lanes.size()));
    }
    d.count += n;
  }
  d.lay_out();
  const int groups = static_cast<int>(d.groups.size());
  return LockstepBatch(std::move(data), groups);
}

// Group of `lanes` models (one shape), states [first, first + lanes): its shape
// and sine columns. A link whose power is 0 in every lane has target
// rest * (1 + 0 * sine) = rest exactly, as a spring: only the others need sines.
// Wave links whose muscle phases agree in every lane share a column of sines.
void LockstepBatch::Data::add_group(const std::vector<const Model*>& models, int first, int lanes) {
  Group G;
  G.first = first;
  G.lanes = lanes;
  const Model& shape = *models[0];
  G.points = shape.point_count;
  G.masses = shape.mass_count;
  G.links = shape.link_count();
  G.link_a = shape.link_a;
  G.link_b = shape.link_b;
  for (int j = 0; j < G.links; ++j) {
    G.link_ends.push_back(static_cast<std::uint32_t>(G.link_a[static_cast<std::size_t>(j)]) * kPointBytes);
    G.link_ends.push_back(static_cast<std::uint32_t>(G.link_b[static_cast<std::size_t>(j)]) * kPointBytes);
  }
  G.bars = shape.bar_count() > 0;
  group_bars.push_back(G.bars ? shape.fixed_bars : FixedBars{});
  std::vector<int> column_link;
  for (int j = 0; j < G.links; ++j) {
    bool moves = false;
    for (const Model* m : models) moves = moves || is_wave_muscle(*m, j);
    if (!moves) continue;
    int column = 0;
    for (; column < static_cast<int>(column_link.size()); ++column) {
      bool same = true;
      for (const Model* m : models) same = same && bits_of(m->link_phase[j]) == bits_of(m->link_phase[column_link[column]]);
      if (same) break;
    }
    if (column == static_cast<int>(column_link.size())) column_link.push_back(j);
    G.wave_links.push_back(j);
    G.column_of.push_back(column);
  }
  G.columns = static_cast<int>(column_link.size());
  G.uniform = true;
  for (const Model* m : models) {
    for (int q = 0; q < G.columns; ++q) G.uniform = G.uniform && bits_of(m->link_phase[column_link[q]]) == bits_of(shape.link_phase[column_link[q]]);
  }
  state_points.insert(state_points.end(), static_cast<std::size_t>(lanes), G.points);
  groups.push_back(std::move(G));
  for (int l = 0; l < kW; ++l) lane_models.push_back(models[static_cast<std::size_t>(std::min(l, lanes - 1))]);
  group_column_links.push_back(std::move(column_link));
}

// The rows of every group, filled from each lane's model; the order in which the
// groups step (side by side where consecutive groups have the same links).
void LockstepBatch::Data::lay_out() {
  std::size_t block_rows = 0, row_count = 0, pool_columns = 0, move_rows = 0;
  int most_masses = 0;
  for (Group& G : groups) {
    if (G.bars) {
      G.move_at = move_rows;
      G.due_at = move_rows / 4;
      move_rows += 4 * static_cast<std::size_t>(G.masses);
      most_masses = std::max(most_masses, G.masses);
    }
    G.block = block_rows;
    G.sine_at = row_count;
    G.pool_at = pool_columns;
    block_rows += 4 * static_cast<std::size_t>(G.points) + 3 * static_cast<std::size_t>(G.links) + G.columns + kWorldRows;
    row_count += static_cast<std::size_t>(G.columns);
    pool_columns += static_cast<std::size_t>(G.uniform ? G.columns : 0);
  }
  pool_rows = static_cast<int>((pool_columns + kW - 1) / kW);
  const int group_total = static_cast<int>(groups.size());
  rows.assign(block_rows * kW, 0.0);
  moves.assign(move_rows * kW, 0.0);
  bar_due.assign(move_rows / 4, 0);
  bar_held.assign(static_cast<std::size_t>(most_masses), 0);
  arguments.assign(row_count * kW, 0.0);
  sines.assign(arguments.size(), 0.0);
  pool_phase.assign(static_cast<std::size_t>(pool_rows) * kW, 0.0);
  pool_wave.assign(pool_phase.size(), 0.0);
  pool_arguments.assign(pool_phase.size(), 0.0);
  pool_sines.assign(pool_phase.size(), 0.0);
  redo.assign(static_cast<std::size_t>(group_total), 0);
  predicted.assign(static_cast<std::size_t>(group_total) * kW, 0.0);
  packed.assign(static_cast<std::size_t>(group_total), 0);
  walls_far.assign(static_cast<std::size_t>(group_total), 0);
  sine_fn = exact_sin_fn(level);
  inline_sines = vector_sines_usable(level);
  autoreverse.assign(static_cast<std::size_t>(group_total) * kW, 0);
  for (int g = 0; g < group_total; ++g) {
    const Group& G = groups[static_cast<std::size_t>(g)];
    const std::vector<int>& column_link = group_column_links[static_cast<std::size_t>(g)];
    for (int l = 0; l < kW; ++l) {
      const Model& m = *lane_models[static_cast<std::size_t>(g) * kW + l];
      for (int j = 0; j < G.links; ++j) {
        link_row(g, 0, j)[l] = m.link_rest[j];
        link_row(g, 1, j)[l] = m.link_power[j];
        link_row(g, 2, j)[l] = m.link_rest[j]; // springs' target, for good
      }
      for (int q = 0; q < G.columns; ++q) column_row(g, q)[l] = m.link_phase[column_link[q]];
      world_row(g, kSpringyness)[l] = m.springyness;
      world_row(g, kGravityStep)[l] = m.gravity_step;
      world_row(g, kKeep)[l] = m.air_keep;
      world_row(g, kWidth)[l] = m.width;
      world_row(g, kHeight)[l] = m.height;
      world_row(g, kFs)[l] = m.surface_friction;
      world_row(g, kRs)[l] = m.surface_reflection;
      world_row(g, kSpeed)[l] = m.wave_speed;
      // A free mass moves at most kMaxMovePerFrame (x max(1, |keep|)) px a frame
      // (scene_analysis.hpp); out to kWallAnalysisMaxCoordinate. NaN limits
      // (a world without walls is +inf wide) keep every wall tested.
      const double reach = kMaxMovePerFrame * std::max(1.0, std::fabs(m.air_keep));
      world_row(g, kLeft)[l] = reach;
      world_row(g, kRight)[l] = std::min(m.width - reach, kWallAnalysisMaxCoordinate);
      world_row(g, kTop)[l] = std::min(m.height - reach, kWallAnalysisMaxCoordinate);
      autoreverse[static_cast<std::size_t>(g) * kW + l] = m.autoreverse ? 1 : 0;
    }
    if (G.uniform) {
      for (int q = 0; q < G.columns; ++q) pool(pool_phase, g)[q] = column_row(g, q)[0];
    }
  }
  sine_work.reserve(row_count + static_cast<std::size_t>(pool_rows));
  lane_models.clear();
  group_column_links.clear();
  for (int g = 0; g < group_total; g += kSideBySide) {
    const int n = std::min(kSideBySide, group_total - g);
    schedule.emplace_back(g, n);
    int links = 0;
    bool bars = false;
    for (int k = g; k < g + n; ++k) {
      links = std::max(links, groups[static_cast<std::size_t>(k)].links);
      bars = bars || groups[static_cast<std::size_t>(k)].bars;
    }
    schedule_bars.push_back(bars ? 1 : 0);
    total_links += links;
  }
}

LockstepBatch::~LockstepBatch() = default;
LockstepBatch::LockstepBatch(LockstepBatch&&) noexcept = default;
LockstepBatch& LockstepBatch::operator=(LockstepBatch&&) noexcept = default;

int LockstepBatch::size() const { return d_->count; }
int LockstepBatch::group_count() const { return static_cast<int>(d_->groups.size()); }
int LockstepBatch::sine_columns(int g) const { return d_->groups.at(static_cast<std::size_t>(g)).columns; }
bool LockstepBatch::shares_sines(int g) const { return d_->groups.at(static_cast<std::size_t>(g)).uniform; }
long long LockstepBatch::bar_rules_run() const { return d_->bar_rules_run; }
SimdLevel LockstepBatch::level() const { return d_->level; }

void LockstepBatch::Data::load(State* const* st) {
  for (int g = 0; g < static_cast<int>(groups.size()); ++g) {
    const Group& G = groups[static_cast<std::size_t>(g)];
    const int points = G.points;
    double* const phase = world_row(g, kPhase);
    double* const mode = world_row(g, kMode);
    for (int l = 0; l < kW; ++l) {
      const State& s = *st[G.first + std::min(l, G.lanes - 1)];
      const double* const from[4] = {s.x.data(), s.y.data(), s.vx.data(), s.vy.data()};
      for (int k = 0; k < 4; ++k) {
        for (int p = 0; p < points; ++p) point_row(g, k, p)[l] = from[k][static_cast<std::size_t>(p)];
      }
      phase[l] = s.wave_phase;
      mode[l] = static_cast<double>(static_cast<int>(s.wave_mode));
    }
  }
}

void LockstepBatch::Data::store_lane(int g, int l, State& s) {
  const Group& G = groups[static_cast<std::size_t>(g)];
  for (int p = 0; p < G.masses; ++p) {
    s.x[p] = point_row(g, 0, p)[l];
    s.y[p] = point_row(g, 1, p)[l];
    s.vx[p] = point_row(g, 2, p)[l];
    s.vy[p] = point_row(g, 3, p)[l];
  }
  s.wave_phase = world_row(g, kPhase)[l];
  s.wave_mode = static_cast<WaveDirection>(static_cast<int>(world_row(g, kMode)[l]));
}

} // namespace soda
