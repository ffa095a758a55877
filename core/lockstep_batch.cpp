#include "lockstep_batch.hpp"

// The SIMD templates (simd_rules.hpp) are instantiated with the default target
// and always inlined into the AVX-512 kernels below: no call ever crosses the
// vector ABI that this warning is about.
#pragma GCC diagnostic ignored "-Wpsabi"

#include <immintrin.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "detail/aligned_vector.hpp"
#include "detail/bits.hpp"
#include "constants.hpp"
#include "exact_sines.hpp"
#include "detail/glibc_sine.hpp"
#include "physics_rules.hpp"
#include "scene_analysis.hpp"
#include "simd_level.hpp"
#include "detail/simd_ops.hpp"
#include "detail/simd_rules.hpp"

namespace soda {

namespace {
using O = simd::Avx512Ops;
constexpr int kW = LockstepBatch::kLanes;
/// Groups stepped side by side in one pass over their links and masses (two,
/// three and four measured alike on the GA's creatures; one alone ~25 % slower).
constexpr int kSideBySide = 2;
static_assert(O::W == kW);
} // namespace

// Lane l of group g is state groups[g].first + l (padding lanes past a group's
// own repeat its last state; their results are never read). Every per-lane value
// is a row of 8 doubles.
struct LockstepBatch::Data {
  struct Group {
    int first = 0, lanes = 0;            ///< its states: [first, first + lanes)
    int points = 0, masses = 0, links = 0;
    std::vector<int> link_a, link_b;     ///< point indices, file order (the group's shape)
    std::vector<int> wave_links;         ///< links with a moving target in some lane
    std::vector<int> column_of;          ///< [wave_links] its sine column
    int columns = 0;
    bool uniform = false;                ///< every lane has the same phase in each column
    bool jittered = false;               ///< some lane's state carries sine jitter (run)
    /// Where its rows start: a block of points x, y, vx, vy [4][points], links
    /// rest, power, target [3][links], column phases [columns] and the world
    /// [kWorldRows]; sine arguments and sines [columns]; shared ones: columns
    /// [pool_at, pool_at + columns) of the pool.
    std::size_t block = 0, sine_at = 0, pool_at = 0;
  };
  int count = 0;
  std::vector<Group> groups;
  std::vector<int> state_points; ///< [count] points of state c's model
  std::vector<std::pair<int, int>> schedule; ///< (first group, groups stepped side by side: same links)
  SinFn sine_fn = nullptr;
  const glibc_sine::GlibcTable* sine_table = nullptr; ///< for the sines inlined into the link pass

  // kLeft, kRight, kTop: the walls are out of reach this frame where every mass
  // is right of kLeft, left of kRight and below kTop (walls_far).
  enum World { kSpringyness, kGravityStep, kKeep, kWidth, kHeight, kFs, kRs, kSpeed, kMode, kPhase, kLeft, kRight, kTop, kWorldRows };
  // One allocation: the distances between the rows, hence which loads and stores
  // share their low 12 address bits (a false dependency), are then the same in
  // every run; with four allocations the speed changed from process to process
  // (bench/README.md, "Design figures").
  AVec<double> rows;
  // Sines of the next frame: computed during this frame's links (where the
  // square-root/divide unit is the bottleneck and the other units idle), for the
  // phase each wave will have if no lane's direction turns; a group whose phase
  // came out otherwise gets them again after the frame (sines_now). A group whose
  // lanes share them (packed) has one per column in the pool, the columns of all
  // such groups one after the other, 8 to a row, each with its muscle phase and
  // its group's wave phase (pool_wave): a row's arguments are then those of each
  // column's group, whatever groups the row holds.
  AVec<double> arguments, sines;                                      ///< rows at sine_at
  AVec<double> pool_phase, pool_wave, pool_arguments, pool_sines;     ///< columns at pool_at
  int pool_rows = 0;
  std::vector<std::uint8_t> redo;   ///< [groups] the wave turned: sines again after the frame
  int total_links = 0;              ///< the link passes of a frame, over all steps
  int sine_rows = 0, sines_done = 0, sine_credit = 0; ///< a frame's sines, spread over its link passes
  unsigned far_lanes = 0; ///< lanes glibc's sin takes elsewhere (|x| >= 105414336, NaN): none from phases in [0, 1)
  AVec<double> predicted;        ///< [groups] rows: the phase the sines are for
  std::vector<std::uint8_t> packed; ///< [groups] the group's sines are the packed ones
  /// [groups] no mass of any lane can reach the ceiling or a side wall this frame
  /// (the floor is tested always: walkers touch it every frame).
  std::vector<std::uint8_t> walls_far;
  bool inline_sines = false;     ///< the CPU has the vector sine (exact_sines.hpp)
  std::vector<std::uint8_t> autoreverse; ///< [groups * 8]
  std::vector<State*> lane_state;        ///< [groups * 8] the state each lane loads from
  /// [groups * 8] each lane's sine jitter as PreparedJitter holds it (threshold 0:
  /// exact), in rows that jitter_sines loads 8 lanes at a time.
  std::vector<std::uint64_t> lane_seed_mix, lane_threshold;
  std::vector<std::pair<const double*, double*>> sine_work; ///< (arguments, sines) rows of a step
  // Until lay_out: each group's lane models [groups * 8] and the link of each of its columns.
  std::vector<const Model*> lane_models;
  std::vector<std::vector<int>> group_column_links;

  double* block_row(int g, std::size_t row) { return rows.data() + (groups[static_cast<std::size_t>(g)].block + row) * kW; }
  double* point_row(int g, int k, int p) {
    return block_row(g, static_cast<std::size_t>(k) * groups[static_cast<std::size_t>(g)].points + p);
  }
  double* link_row(int g, int k, int j) {
    const Group& G = groups[static_cast<std::size_t>(g)];
    return block_row(g, 4 * static_cast<std::size_t>(G.points) + static_cast<std::size_t>(k) * G.links + j);
  }
  double* column_row(int g, int q) {
    const Group& G = groups[static_cast<std::size_t>(g)];
    return block_row(g, 4 * static_cast<std::size_t>(G.points) + 3 * static_cast<std::size_t>(G.links) + q);
  }
  double* world_row(int g, int k) { return column_row(g, groups[static_cast<std::size_t>(g)].columns + k); }
  double* arguments_row(int g, int q) { return arguments.data() + (groups[static_cast<std::size_t>(g)].sine_at + q) * kW; }
  double* sines_row(int g, int q) { return sines.data() + (groups[static_cast<std::size_t>(g)].sine_at + q) * kW; }
  double* pool(AVec<double>& v, int g) { return v.data() + groups[static_cast<std::size_t>(g)].pool_at; }

  void add_group(const std::vector<const Model*>& models, int first, int lanes);
  void lay_out();
  void load(State* const* st);
  void store(State* const* st);
  void arguments_for(int g, O::V phase, bool pool_rows_now);
  void pool_arguments_rows(std::size_t first_row, std::size_t end_row);
  void step_frame();
  void sines_now(int g);
  void unpack_sines(int g);
  void targets_from_sines(int g);
  bool packed_jitter_hits(int g);
  void targets_from_packed(int g);
  void jitter_sines(int g);
  void queue_sines(int g);
  template <int N>
  void step_groups(int g0);
};

bool LockstepBatch::usable() {
  // AVX512DQ for the 8-bit mask instructions (every AVX-512 CPU but the Xeon Phi has it).
  return simd_level_supported(SimdLevel::Avx512) && __builtin_cpu_supports("avx512dq");
}

bool LockstepBatch::can_take(const Model& model) { return model.bar_count() == 0; }

bool LockstepBatch::same_shape(const Model& a, const Model& b) {
  return can_take(a) && can_take(b) && a.mass_count == b.mass_count && a.point_count == b.point_count &&
         a.link_a == b.link_a && a.link_b == b.link_b;
}

LockstepBatch::LockstepBatch(std::unique_ptr<Data> d, int) : d_(std::move(d)) {}

LockstepBatch::LockstepBatch(const std::vector<const Model*>& models) : LockstepBatch(of_shapes({models})) {}

LockstepBatch LockstepBatch::of_shapes(const std::vector<std::vector<const Model*>>& shapes) {
  if (shapes.empty()) throw std::invalid_argument("LockstepBatch: no models");
  for (const std::vector<const Model*>& models : shapes) {
    if (models.empty()) throw std::invalid_argument("LockstepBatch: no models");
    for (const Model* m : models) {
      assert(constants_current(*m));
      if (!same_shape(*models[0], *m)) throw std::invalid_argument("LockstepBatch: models of different shapes, or with fixed bars");
    }
  }
  if (!usable()) throw std::runtime_error("LockstepBatch: this CPU has no AVX-512 (F and DQ)");
  auto data = std::make_unique<Data>();
  Data& d = *data;
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
  std::size_t block_rows = 0, row_count = 0, pool_columns = 0;
  for (Group& G : groups) {
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
  sine_fn = exact_sin_fn(SimdLevel::Avx512);
  inline_sines = vector_sines_usable(SimdLevel::Avx512);
  sine_table = &glibc_sine::glibc_table();
  autoreverse.assign(static_cast<std::size_t>(group_total) * kW, 0);
  std::size_t most_work = 0;
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
    most_work = std::max(most_work, static_cast<std::size_t>(G.columns));
  }
  sine_work.reserve(row_count + static_cast<std::size_t>(pool_rows));
  (void)most_work;
  lane_models.clear();
  group_column_links.clear();
  for (int g = 0; g < group_total; g += kSideBySide) {
    const int n = std::min(kSideBySide, group_total - g);
    schedule.emplace_back(g, n);
    int links = 0;
    for (int k = g; k < g + n; ++k) links = std::max(links, groups[static_cast<std::size_t>(k)].links);
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

void LockstepBatch::Data::load(State* const* st) {
  for (int g = 0; g < static_cast<int>(groups.size()); ++g) {
    const Group& G = groups[static_cast<std::size_t>(g)];
    const std::size_t points = static_cast<std::size_t>(G.points);
    double* const row = point_row(g, 0, 0); // x, y, vx, vy: rows of `points` each
    double* const phase = world_row(g, kPhase);
    double* const mode = world_row(g, kMode);
    for (int l = 0; l < kW; ++l) {
      const State& s = *st[G.first + std::min(l, G.lanes - 1)];
      const double* const from[4] = {s.x.data(), s.y.data(), s.vx.data(), s.vy.data()};
      for (std::size_t k = 0; k < 4; ++k) {
        for (std::size_t p = 0; p < points; ++p) row[(k * points + p) * kW + static_cast<std::size_t>(l)] = from[k][p];
      }
      phase[l] = s.wave_phase;
      mode[l] = static_cast<double>(static_cast<int>(s.wave_mode));
    }
  }
}

void LockstepBatch::Data::store(State* const* st) {
  for (int g = 0; g < static_cast<int>(groups.size()); ++g) {
    const Group& G = groups[static_cast<std::size_t>(g)];
    for (int l = 0; l < G.lanes; ++l) {
      State& s = *st[G.first + l];
      for (int p = 0; p < G.masses; ++p) {
        s.x[p] = point_row(g, 0, p)[l];
        s.y[p] = point_row(g, 1, p)[l];
        s.vx[p] = point_row(g, 2, p)[l];
        s.vy[p] = point_row(g, 3, p)[l];
      }
      s.wave_phase = world_row(g, kPhase)[l];
      s.wave_mode = static_cast<WaveDirection>(static_cast<int>(world_row(g, kMode)[l]));
    }
  }
}

// The AVX-512 kernels.
#pragma GCC push_options
#pragma GCC target("avx512f,avx512dq")

// The pool's arguments in rows [first_row, end_row): each column's muscle phase
// against its group's wave phase, the operations of sine_argument lane by lane.
// Recomputing a row leaves the other groups' columns as they were (the same
// operands), so one group's sines may be formed again alone (sines_now).
[[gnu::always_inline]] inline void LockstepBatch::Data::pool_arguments_rows(std::size_t first_row, std::size_t end_row) {
  for (std::size_t r = first_row; r < end_row; ++r) {
    O::store(pool_arguments.data() + r * kW,
             simd_rules::sine_argument<O>(O::load(pool_phase.data() + r * kW), O::load(pool_wave.data() + r * kW)));
  }
}

// Group g's sine arguments for wave phase `phase`, noted in `predicted`: in the
// pool (one per column) where the lanes share their column phases and their
// wave phase, its rows' arguments formed now if `pool_rows_now` (else by the caller).
[[gnu::always_inline]] inline void LockstepBatch::Data::arguments_for(int g, O::V phase, bool pool_rows_now) {
  O::store(predicted.data() + static_cast<std::size_t>(g) * kW, phase);
  const Group& G = groups[static_cast<std::size_t>(g)];
  const O::V first = _mm512_broadcastsd_pd(_mm512_castpd512_pd128(phase));
  const bool share = G.uniform && _mm512_cmpneq_epi64_mask(_mm512_castpd_si512(phase), _mm512_castpd_si512(first)) == 0;
  packed[static_cast<std::size_t>(g)] = share ? 1 : 0;
  if (share) {
    double* wave = pool(pool_wave, g);
    const double w = _mm512_cvtsd_f64(phase);
    for (int q = 0; q < G.columns; ++q) wave[q] = w;
    if (pool_rows_now) pool_arguments_rows(G.pool_at / kW, (G.pool_at + static_cast<std::size_t>(G.columns) + kW - 1) / kW);
    return;
  }
  for (int q = 0; q < G.columns; ++q) O::store(arguments_row(g, q), simd_rules::sine_argument<O>(O::load(column_row(g, q)), phase));
}

// Group g's sines for the phase it has now (in the pool: its rows' sines, the
// other columns' the same again).
void LockstepBatch::Data::sines_now(int g) {
  const Group& G = groups[static_cast<std::size_t>(g)];
  arguments_for(g, O::load(world_row(g, kPhase)), true);
  if (packed[static_cast<std::size_t>(g)] != 0) {
    const std::size_t first = G.pool_at / kW, end = (G.pool_at + static_cast<std::size_t>(G.columns) + kW - 1) / kW;
    sine_fn(pool_arguments.data() + first * kW, pool_sines.data() + first * kW, static_cast<int>((end - first) * kW));
  } else {
    sine_fn(arguments_row(g, 0), sines_row(g, 0), G.columns * kW);
  }
}

// Packed sines (and, for the jitter, their arguments) into group g's rows, one
// column's value in each of its lanes.
[[gnu::always_inline]] inline void LockstepBatch::Data::unpack_sines(int g) {
  const Group& G = groups[static_cast<std::size_t>(g)];
  const double* argument = pool(pool_arguments, g);
  const double* sine = pool(pool_sines, g);
  for (int q = 0; q < G.columns; ++q) {
    O::store(sines_row(g, q), O::set1(sine[q]));
    O::store(arguments_row(g, q), O::set1(argument[q]));
  }
}

// Group g's (arguments, sines) rows to compute during the link passes (not
// packed: the pool's rows are queued whole).
[[gnu::always_inline]] inline void LockstepBatch::Data::queue_sines(int g) {
  const Group& G = groups[static_cast<std::size_t>(g)];
  if (packed[static_cast<std::size_t>(g)] != 0) return;
  for (int q = 0; q < G.columns; ++q) sine_work.emplace_back(arguments_row(g, q), sines_row(g, q));
}

// Group g's sines moved by each lane's jitter, as rules::muscle_sine moves them:
// the arguments row still holds the arguments these sines were computed from
// (inline for the predicted phase, or again by sines_now). The hash of
// PreparedJitter::steps for the 8 lanes at once (64-bit multiplies: AVX-512DQ);
// the few lanes it hits (a share p of them) move one by one.
void LockstepBatch::Data::jitter_sines(int g) {
  const std::size_t first = static_cast<std::size_t>(g) * kW;
  const __m512i seed_mix = _mm512_loadu_si512(lane_seed_mix.data() + first);
  const __m512i threshold = _mm512_loadu_si512(lane_threshold.data() + first);
  const __m512i m1 = _mm512_set1_epi64(static_cast<long long>(0xbf58476d1ce4e5b9ULL));
  const __m512i m2 = _mm512_set1_epi64(static_cast<long long>(0x94d049bb133111ebULL));
  for (int q = 0; q < groups[static_cast<std::size_t>(g)].columns; ++q) {
    const double* argument = arguments_row(g, q);
    __m512i z = _mm512_xor_si512(_mm512_castpd_si512(_mm512_loadu_pd(argument)), seed_mix);
    z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 30)), m1);
    z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 27)), m2);
    z = _mm512_xor_si512(z, _mm512_srli_epi64(z, 31));
    unsigned hits = _mm512_cmplt_epu64_mask(_mm512_srli_epi64(z, 11), threshold);
    if (hits == 0) [[likely]] continue;
    double* sine = sines_row(g, q);
    for (; hits != 0; hits &= hits - 1) {
      const int l = __builtin_ctz(hits);
      PreparedJitter jitter;
      jitter.seed_mix = lane_seed_mix[first + static_cast<std::size_t>(l)];
      jitter.threshold = lane_threshold[first + static_cast<std::size_t>(l)];
      sine[l] = jitter.apply(sine[l], argument[l]);
    }
  }
}

// Whether the jitter of some lane of packed group g moves one of its sines this
// frame (the hash of jitter_sines, each column's argument in every lane).
[[gnu::always_inline]] inline bool LockstepBatch::Data::packed_jitter_hits(int g) {
  const std::size_t first = static_cast<std::size_t>(g) * kW;
  const __m512i seed_mix = _mm512_loadu_si512(lane_seed_mix.data() + first);
  const __m512i threshold = _mm512_loadu_si512(lane_threshold.data() + first);
  const __m512i m1 = _mm512_set1_epi64(static_cast<long long>(0xbf58476d1ce4e5b9ULL));
  const __m512i m2 = _mm512_set1_epi64(static_cast<long long>(0x94d049bb133111ebULL));
  const double* argument = pool(pool_arguments, g);
  unsigned hits = 0;
  for (int q = 0; q < groups[static_cast<std::size_t>(g)].columns; ++q) {
    __m512i z = _mm512_xor_si512(_mm512_castpd_si512(_mm512_set1_pd(argument[q])), seed_mix);
    z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 30)), m1);
    z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 27)), m2);
    z = _mm512_xor_si512(z, _mm512_srli_epi64(z, 31));
    hits |= _mm512_cmplt_epu64_mask(_mm512_srli_epi64(z, 11), threshold);
  }
  return hits != 0;
}

// Packed group g's wave links' targets: each column's one sine in every lane.
[[gnu::always_inline]] inline void LockstepBatch::Data::targets_from_packed(int g) {
  const Group& G = groups[static_cast<std::size_t>(g)];
  const double* sine = pool(pool_sines, g);
  for (std::size_t w = 0; w < G.wave_links.size(); ++w) {
    const int j = G.wave_links[w];
    O::store(link_row(g, 2, j), simd_rules::muscle_target<O>(O::load(link_row(g, 0, j)), O::load(link_row(g, 1, j)),
                                                             O::set1(sine[G.column_of[w]])));
  }
}

// Group g's wave links' targets from its sines: rest * (1 + power * sine).
[[gnu::always_inline]] inline void LockstepBatch::Data::targets_from_sines(int g) {
  const Group& G = groups[static_cast<std::size_t>(g)];
  for (std::size_t w = 0; w < G.wave_links.size(); ++w) {
    const int j = G.wave_links[w];
    O::store(link_row(g, 2, j), simd_rules::muscle_target<O>(O::load(link_row(g, 0, j)), O::load(link_row(g, 1, j)),
                                                             O::load(sines_row(g, G.column_of[w]))));
  }
}

// One frame's physics and wave advance of groups [g0, g0 + N) (the same links),
// side by side: N independent chains for the processor to overlap.
template <int N>
[[gnu::always_inline]] inline void LockstepBatch::Data::step_groups(int g0) {
  using V = O::V;
  using M = O::M;
  V *x[N], *y[N], *vx[N], *vy[N];
  const double* target[N];
  V springyness[N];
  for (int n = 0; n < N; ++n) {
    x[n] = reinterpret_cast<V*>(point_row(g0 + n, 0, 0));
    y[n] = reinterpret_cast<V*>(point_row(g0 + n, 1, 0));
    vx[n] = reinterpret_cast<V*>(point_row(g0 + n, 2, 0));
    vy[n] = reinterpret_cast<V*>(point_row(g0 + n, 3, 0));
    target[n] = link_row(g0 + n, 2, 0);
    springyness[n] = O::load(world_row(g0 + n, kSpringyness));
  }
  const V zero = O::set1(0.0);
  // The groups' links and masses side by side, each group's in its own order.
  const int* la[N];
  const int* lb[N];
  int group_links[N], group_masses[N];
  int links = 0, masses = 0;
  for (int n = 0; n < N; ++n) {
    const Group& G = groups[static_cast<std::size_t>(g0 + n)];
    la[n] = G.link_a.data();
    lb[n] = G.link_b.data();
    group_links[n] = G.links;
    group_masses[n] = G.masses;
    links = std::max(links, G.links);
    masses = std::max(masses, G.masses);
  }
  const glibc_sine::GlibcTable& table = *sine_table;
  // Links in file order (step.cpp apply_links): each impulse goes into both
  // ends' velocities at once; a zero-length link adds nothing (masked).
  for (int j = 0; j < links; ++j) {
    // The next frame's sines, spread over the link passes: sine_rows / total_links of them a link.
    for (sine_credit += sine_rows; sine_credit >= total_links; sine_credit -= total_links, ++sines_done) {
      unsigned far = 0;
      const auto& [in, out] = sine_work[static_cast<std::size_t>(sines_done)];
      glibc_sine::glibc_sin<O, 1>(table, in, out, &far);
      far_lanes |= far;
    }
#pragma GCC unroll 4
    for (int n = 0; n < N; ++n) {
      if (j >= group_links[n]) continue;
      const int a = la[n][j], b = lb[n][j];
      const V dx = O::sub(x[n][b], x[n][a]);
      const V dy = O::sub(y[n][b], y[n][a]);
      const V length = simd_rules::length<O>(dx, dy);
      const M acts = O::ne(length, zero);
      const V c = simd_rules::impulse_factor<O>(springyness[n], length, O::load(target[n] + static_cast<std::size_t>(j) * kW));
      const V px = O::mul(c, dx), py = O::mul(c, dy);
      if (a < group_masses[n]) {
        vx[n][a] = O::add_where(acts, vx[n][a], px);
        vy[n][a] = O::add_where(acts, vy[n][a], py);
      }
      if (b < group_masses[n]) {
        vx[n][b] = O::sub_where(acts, vx[n][b], px);
        vy[n][b] = O::sub_where(acts, vy[n][b], py);
      }
    }
  }
  // Masses in order (step.cpp move_masses); autoreverse lane by lane in mass order.
  simd_rules::MassParams<O> params[N];
  bool hit_wall[N] = {};
  for (int n = 0; n < N; ++n) {
    const int g = g0 + n;
    params[n] = {O::load(world_row(g, kGravityStep)), O::load(world_row(g, kKeep)), O::load(world_row(g, kWidth)),
                 O::load(world_row(g, kHeight)),      O::load(world_row(g, kFs)),   O::load(world_row(g, kRs))};
  }
  // Where this frame's walls were out of reach, the ceiling and side tests
  // would change nothing (the same bits without them); whether they are next
  // frame, from the new positions.
  bool far[N];
  M inside[N];
  V left[N], right[N], top[N];
  for (int n = 0; n < N; ++n) {
    const int g = g0 + n;
    far[n] = walls_far[static_cast<std::size_t>(g)] != 0;
    inside[n] = static_cast<M>(0xff);
    left[n] = O::load(world_row(g, kLeft));
    right[n] = O::load(world_row(g, kRight));
    top[n] = O::load(world_row(g, kTop));
  }
  for (int i = 0; i < masses; ++i) {
#pragma GCC unroll 4
    for (int n = 0; n < N; ++n) {
      if (i >= group_masses[n]) continue;
      if (far[n]) {
        simd_rules::move_mass<O, true, true, false, false>(params[n], x[n][i], y[n][i], vx[n][i], vy[n][i]);
      }
      const simd_rules::SideHits<O> hits =
          far[n] ? simd_rules::SideHits<O>{O::m_none(), O::m_none()}
                 : simd_rules::move_mass<O, true, true, true, true>(params[n], x[n][i], y[n][i], vx[n][i], vy[n][i]);
      inside[n] = O::m_and(inside[n], O::m_and(O::gt(x[n][i], left[n]), O::m_and(O::lt(x[n][i], right[n]), O::lt(y[n][i], top[n]))));
      if (O::any(hits.hit)) [[unlikely]] {
        hit_wall[n] = true;
        const int g = g0 + n;
        double* mode = world_row(g, kMode);
        for (int l = 0; l < kW; ++l) {
          if (!((hits.hit >> l) & 1)) continue;
          State& s = *lane_state[static_cast<std::size_t>(g) * kW + l];
          WaveDirection m = static_cast<WaveDirection>(static_cast<int>(mode[l]));
          rules::autoreverse_on_wall_hit((hits.left >> l) & 1 ? SideWall::Left : SideWall::Right,
                                         autoreverse[static_cast<std::size_t>(g) * kW + l] != 0, m, s.last_side_wall);
          mode[l] = static_cast<double>(static_cast<int>(m));
        }
      }
    }
  }
  for (int n = 0; n < N; ++n) walls_far[static_cast<std::size_t>(g0 + n)] = inside[n] == static_cast<M>(0xff) ? 1 : 0;
  // The wave advance after the physics (docs/physics.md, "The wave"): the
  // predicted phase where no lane hit a side wall (the same operations on the
  // same operands). Where a direction turned, the next frame's sines again once
  // the frame is done (step_frame).
  for (int n = 0; n < N; ++n) {
    const int g = g0 + n;
    const double* expected = predicted.data() + static_cast<std::size_t>(g) * kW;
    if (groups[static_cast<std::size_t>(g)].columns > 0 && !hit_wall[n]) {
      O::store(world_row(g, kPhase), O::load(expected));
      continue;
    }
    const V phase = simd_rules::advance_wave_phase<O>(O::load(world_row(g, kPhase)), O::load(world_row(g, kSpeed)),
                                                      O::load(world_row(g, kMode)));
    O::store(world_row(g, kPhase), phase);
    if (groups[static_cast<std::size_t>(g)].columns == 0) continue;
    redo[static_cast<std::size_t>(g)] = _mm512_cmpneq_epi64_mask(_mm512_castpd_si512(phase), _mm512_load_si512(expected)) != 0;
  }
}

// One frame of every group: this frame's targets from the sines computed for it
// and the arguments of the next frame's at the phase each wave will have if no
// direction turns; the link and mass passes, two groups at a time, with those
// sines spread over them; the sines again of a group whose wave turned (or all,
// where they were not computed in the passes).
void LockstepBatch::Data::step_frame() {
  sine_work.clear();
  for (int g = 0; g < static_cast<int>(groups.size()); ++g) {
    const Group& G = groups[static_cast<std::size_t>(g)];
    if (G.columns == 0) continue;
    if (packed[static_cast<std::size_t>(g)] != 0 && !(G.jittered && packed_jitter_hits(g))) {
      targets_from_packed(g); // the lanes' sines as computed: each column's in every lane
    } else {
      if (packed[static_cast<std::size_t>(g)] != 0) unpack_sines(g);
      if (G.jittered) [[unlikely]] jitter_sines(g);
      targets_from_sines(g);
    }
    arguments_for(g, simd_rules::advance_wave_phase<O>(O::load(world_row(g, kPhase)), O::load(world_row(g, kSpeed)),
                                                       O::load(world_row(g, kMode))),
                  false);
    if (inline_sines) queue_sines(g);
  }
  pool_arguments_rows(0, static_cast<std::size_t>(pool_rows));
  if (inline_sines) {
    for (int r = 0; r < pool_rows; ++r) {
      sine_work.emplace_back(pool_arguments.data() + static_cast<std::size_t>(r) * kW, pool_sines.data() + static_cast<std::size_t>(r) * kW);
    }
  }
  sine_rows = static_cast<int>(sine_work.size());
  sines_done = 0;
  sine_credit = 0;
  far_lanes = 0;
  for (const auto& [g, n] : schedule) {
    static_assert(kSideBySide == 2);
    if (n == 2) {
      step_groups<2>(g);
    } else {
      step_groups<1>(g);
    }
  }
  assert(sines_done == sine_rows);
  const bool all_again = !inline_sines || far_lanes != 0;
  for (int g = 0; g < static_cast<int>(groups.size()); ++g) {
    if (groups[static_cast<std::size_t>(g)].columns > 0 && (all_again || redo[static_cast<std::size_t>(g)] != 0)) sines_now(g);
    redo[static_cast<std::size_t>(g)] = 0;
  }
}

void LockstepBatch::run(State* const* states, long long frames) {
  Data& d = *d_;
  require_batch_states(states, d.count, [&](int c) { return d.state_points[static_cast<std::size_t>(c)]; }, "LockstepBatch::run");
  for (int c = 0; c < d.count; ++c) require_valid_jitter_of(states[c]->jitter, "LockstepBatch::run", c);
  step(states, frames);
}

void LockstepBatch::step(State* const* states, long long frames) {
  Data& d = *d_;
  if (frames <= 0) return;
  d.load(states);
  std::fill(d.walls_far.begin(), d.walls_far.end(), 0); // tested in the first frame, known after it
  const std::size_t lanes = d.groups.size() * kW;
  // Padding lanes autoreverse into a scratch copy of their group's last state, not into it.
  std::vector<State> padding;
  padding.reserve(lanes - static_cast<std::size_t>(d.count));
  d.lane_state.resize(lanes);
  d.lane_seed_mix.assign(lanes, 0); // padding lanes: exact, unread
  d.lane_threshold.assign(lanes, 0);
  for (std::size_t g = 0; g < d.groups.size(); ++g) {
    Data::Group& G = d.groups[g];
    G.jittered = false;
    for (int l = 0; l < kW; ++l) {
      const std::size_t lane = g * kW + static_cast<std::size_t>(l);
      if (l < G.lanes) {
        State* s = states[G.first + l];
        d.lane_state[lane] = s;
        const PreparedJitter jitter(s->jitter);
        d.lane_seed_mix[lane] = jitter.seed_mix;
        d.lane_threshold[lane] = jitter.threshold;
        if (jitter.threshold != 0) G.jittered = true;
      } else {
        padding.push_back(*states[G.first + G.lanes - 1]);
        d.lane_state[lane] = &padding.back();
      }
    }
  }
  for (int g = 0; g < static_cast<int>(d.groups.size()); ++g) {
    if (d.groups[static_cast<std::size_t>(g)].columns > 0) d.sines_now(g);
  }
  for (long long f = 0; f < frames; ++f) d.step_frame();
  d.store(states);
  for (int c = 0; c < d.count; ++c) states[c]->frame += frames;
}

#pragma GCC pop_options

} // namespace soda
