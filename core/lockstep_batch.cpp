#include "lockstep_batch.hpp"

// The SIMD templates (simd_rules.hpp) are instantiated with the default target
// and always inlined into the AVX-512 kernels below: no call ever crosses the
// vector ABI that this warning is about.
#pragma GCC diagnostic ignored "-Wpsabi"

#include <immintrin.h>

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <stdexcept>

#include "detail/aligned_vector.hpp"
#include "detail/bits.hpp"
#include "constants.hpp"
#include "exact_sines.hpp"
#include "detail/glibc_sine.hpp"
#include "physics_rules.hpp"
#include "simd_level.hpp"
#include "detail/simd_ops.hpp"
#include "detail/simd_rules.hpp"

namespace soda {

namespace {
using O = simd::Avx512Ops;
constexpr int kW = LockstepBatch::kLanes;
static_assert(O::W == kW);
} // namespace

// Lane l of group g is creature 8g + l (padding lanes repeat the last creature;
// their results are never read). Every per-lane value is a row of 8 doubles.
struct LockstepBatch::Data {
  int count = 0, groups = 0;
  int points = 0, masses = 0, links = 0;
  std::vector<int> link_a, link_b;     ///< point indices, file order (one shape)
  std::vector<int> wave_links;         ///< links with a moving target in some lane
  std::vector<int> column_of;          ///< [wave_links] its sine column
  int columns = 0;
  SinFn sine_fn = nullptr;
  const glibc_sine::GlibcTable* sine_table = nullptr; ///< for the sines inlined into the link pass

  // Rows per group: points: x, y, vx, vy [4][points]; links: rest, power, target
  // [3][links]; columns: muscle phase [columns]; world: kWorldRows.
  enum World { kSpringyness, kGravityStep, kKeep, kWidth, kHeight, kFs, kRs, kSpeed, kMode, kPhase, kWorldRows };
  // One allocation: the distances between the rows, hence which loads and stores
  // share their low 12 address bits (a false dependency), are then the same in
  // every run; with four allocations the speed changed from process to process
  // (bench/README.md, "Design figures").
  AVec<double> rows;
  double *point_rows = nullptr, *link_rows = nullptr, *column_rows = nullptr, *world_rows = nullptr;
  // Sines of the next frame: computed during this frame's links (where the
  // square-root/divide unit is the bottleneck and the other units idle), for the
  // phase each wave will have if no lane's direction turns; a group whose phase
  // came out otherwise gets them again after its frame (sines_now).
  AVec<double> arguments, sines; ///< [groups * columns] rows
  AVec<double> predicted;        ///< [groups] rows: the phase the sines are for
  bool inline_sines = false;     ///< the CPU has the vector sine (exact_sines.hpp)
  std::vector<std::uint8_t> autoreverse; ///< [groups * 8]
  std::vector<State*> lane_state;        ///< [groups * 8] the state each lane loads from
  /// [groups * 8] each lane's sine jitter as PreparedJitter holds it (threshold 0:
  /// exact), in rows that jitter_sines loads 8 lanes at a time.
  std::vector<std::uint64_t> lane_seed_mix, lane_threshold;
  std::vector<std::uint8_t> group_jittered; ///< [groups] some lane of the group has jitter

  double* point_row(int g, int k, int p) { return point_rows + ((static_cast<std::size_t>(g) * 4 + k) * points + p) * kW; }
  double* link_row(int g, int k, int j) { return link_rows + ((static_cast<std::size_t>(g) * 3 + k) * links + j) * kW; }
  double* column_row(int g, int q) { return column_rows + (static_cast<std::size_t>(g) * columns + q) * kW; }
  double* world_row(int g, int k) { return world_rows + (static_cast<std::size_t>(g) * kWorldRows + k) * kW; }

  void load(State* const* st);
  void store(State* const* st);
  double* arguments_row(int g, int q) { return arguments.data() + (static_cast<std::size_t>(g) * columns + q) * kW; }
  double* sines_row(int g, int q) { return sines.data() + (static_cast<std::size_t>(g) * columns + q) * kW; }
  void arguments_for(int g, O::V phase);
  void sines_now(int g);
  void targets_from_sines(int g);
  void jitter_sines(int g);
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

LockstepBatch::LockstepBatch(const std::vector<const Model*>& models) : d_(std::make_unique<Data>()) {
  if (models.empty()) throw std::invalid_argument("LockstepBatch: no models");
  for (const Model* m : models) {
    assert(constants_current(*m));
    if (!same_shape(*models[0], *m)) throw std::invalid_argument("LockstepBatch: models of different shapes, or with fixed bars");
  }
  if (!usable()) throw std::runtime_error("LockstepBatch: this CPU has no AVX-512 (F and DQ)");
  Data& d = *d_;
  const Model& shape = *models[0];
  d.count = static_cast<int>(models.size());
  d.groups = (d.count + kW - 1) / kW;
  d.points = shape.point_count;
  d.masses = shape.mass_count;
  d.links = shape.link_count();
  d.link_a = shape.link_a;
  d.link_b = shape.link_b;
  const int lanes = d.groups * kW;
  auto model_of = [&](int lane) -> const Model& { return *models[std::min(lane, d.count - 1)]; };

  // A link whose power is 0 in every lane has target rest * (1 + 0 * sine) = rest
  // exactly, as a spring: only the others need sines. Wave links whose muscle
  // phases agree in every lane share a column of sines.
  std::vector<int> column_link;
  for (int j = 0; j < d.links; ++j) {
    bool moves = false;
    for (int l = 0; l < lanes; ++l) moves = moves || is_wave_muscle(model_of(l), j);
    if (!moves) continue;
    int column = 0;
    for (; column < static_cast<int>(column_link.size()); ++column) {
      bool same = true;
      for (int l = 0; l < lanes && same; ++l) {
        same = bits_of(model_of(l).link_phase[j]) == bits_of(model_of(l).link_phase[column_link[column]]);
      }
      if (same) break;
    }
    if (column == static_cast<int>(column_link.size())) column_link.push_back(j);
    d.wave_links.push_back(j);
    d.column_of.push_back(column);
  }
  d.columns = static_cast<int>(column_link.size());
  d.sine_fn = exact_sin_fn(SimdLevel::Avx512);

  const std::size_t point_size = static_cast<std::size_t>(d.groups) * 4 * d.points * kW;
  const std::size_t link_size = static_cast<std::size_t>(d.groups) * 3 * d.links * kW;
  const std::size_t column_size = static_cast<std::size_t>(d.groups) * d.columns * kW;
  const std::size_t world_size = static_cast<std::size_t>(d.groups) * Data::kWorldRows * kW;
  d.rows.assign(point_size + link_size + column_size + world_size, 0.0);
  d.point_rows = d.rows.data();
  d.link_rows = d.point_rows + point_size;
  d.column_rows = d.link_rows + link_size;
  d.world_rows = d.column_rows + column_size;
  d.arguments.assign(static_cast<std::size_t>(d.groups) * d.columns * kW, 0.0);
  d.sines.assign(d.arguments.size(), 0.0);
  d.predicted.assign(static_cast<std::size_t>(d.groups) * kW, 0.0);
  d.inline_sines = vector_sines_usable(SimdLevel::Avx512);
  d.sine_table = &glibc_sine::glibc_table();
  d.autoreverse.assign(lanes, 0);
  for (int lane = 0; lane < lanes; ++lane) {
    const Model& m = model_of(lane);
    const int g = lane / kW, l = lane % kW;
    for (int j = 0; j < d.links; ++j) {
      d.link_row(g, 0, j)[l] = m.link_rest[j];
      d.link_row(g, 1, j)[l] = m.link_power[j];
      d.link_row(g, 2, j)[l] = m.link_rest[j]; // springs' target, for good
    }
    for (int q = 0; q < d.columns; ++q) d.column_row(g, q)[l] = m.link_phase[column_link[q]];
    d.world_row(g, Data::kSpringyness)[l] = m.springyness;
    d.world_row(g, Data::kGravityStep)[l] = m.gravity_step;
    d.world_row(g, Data::kKeep)[l] = m.air_keep;
    d.world_row(g, Data::kWidth)[l] = m.width;
    d.world_row(g, Data::kHeight)[l] = m.height;
    d.world_row(g, Data::kFs)[l] = m.surface_friction;
    d.world_row(g, Data::kRs)[l] = m.surface_reflection;
    d.world_row(g, Data::kSpeed)[l] = m.wave_speed;
    d.autoreverse[lane] = m.autoreverse ? 1 : 0;
  }
}

LockstepBatch::~LockstepBatch() = default;
LockstepBatch::LockstepBatch(LockstepBatch&&) noexcept = default;
LockstepBatch& LockstepBatch::operator=(LockstepBatch&&) noexcept = default;

int LockstepBatch::size() const { return d_->count; }
int LockstepBatch::sine_columns() const { return d_->columns; }

void LockstepBatch::Data::load(State* const* st) {
  for (int lane = 0; lane < groups * kW; ++lane) {
    const State& s = *st[std::min(lane, count - 1)];
    const int g = lane / kW, l = lane % kW;
    for (int p = 0; p < points; ++p) {
      point_row(g, 0, p)[l] = s.x[p];
      point_row(g, 1, p)[l] = s.y[p];
      point_row(g, 2, p)[l] = s.vx[p];
      point_row(g, 3, p)[l] = s.vy[p];
    }
    world_row(g, kPhase)[l] = s.wave_phase;
    world_row(g, kMode)[l] = static_cast<double>(static_cast<int>(s.wave_mode));
  }
}

void LockstepBatch::Data::store(State* const* st) {
  for (int c = 0; c < count; ++c) {
    State& s = *st[c];
    const int g = c / kW, l = c % kW;
    for (int p = 0; p < masses; ++p) {
      s.x[p] = point_row(g, 0, p)[l];
      s.y[p] = point_row(g, 1, p)[l];
      s.vx[p] = point_row(g, 2, p)[l];
      s.vy[p] = point_row(g, 3, p)[l];
    }
    s.wave_phase = world_row(g, kPhase)[l];
    s.wave_mode = static_cast<WaveDirection>(static_cast<int>(world_row(g, kMode)[l]));
  }
}

// The AVX-512 kernels.
#pragma GCC push_options
#pragma GCC target("avx512f,avx512dq")

// Group g's sine arguments for wave phase `phase`, noted in `predicted`.
[[gnu::always_inline]] inline void LockstepBatch::Data::arguments_for(int g, O::V phase) {
  O::store(predicted.data() + static_cast<std::size_t>(g) * kW, phase);
  for (int q = 0; q < columns; ++q) O::store(arguments_row(g, q), simd_rules::sine_argument<O>(O::load(column_row(g, q)), phase));
}

// Group g's sines for the phase it has now.
void LockstepBatch::Data::sines_now(int g) {
  arguments_for(g, O::load(world_row(g, kPhase)));
  sine_fn(arguments_row(g, 0), sines_row(g, 0), columns * kW);
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
  for (int q = 0; q < columns; ++q) {
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

// Group g's wave links' targets from its sines: rest * (1 + power * sine).
[[gnu::always_inline]] inline void LockstepBatch::Data::targets_from_sines(int g) {
  for (std::size_t w = 0; w < wave_links.size(); ++w) {
    const int j = wave_links[w];
    O::store(link_row(g, 2, j), simd_rules::muscle_target<O>(O::load(link_row(g, 0, j)), O::load(link_row(g, 1, j)),
                                                             O::load(sines_row(g, column_of[w]))));
  }
}

// One frame's physics and wave advance of groups [g0, g0 + N), side by side: N
// independent chains for the processor to overlap.
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
  // This frame's targets from the sines computed for it, then the arguments of
  // the next frame's at the phase the waves will have if no direction turns.
  const int sine_rows = inline_sines ? N * columns : 0;
  if (columns > 0) {
    for (int n = 0; n < N; ++n) {
      const int g = g0 + n;
      if (group_jittered[g] != 0) [[unlikely]] jitter_sines(g);
      targets_from_sines(g);
      arguments_for(g, simd_rules::advance_wave_phase<O>(O::load(world_row(g, kPhase)), O::load(world_row(g, kSpeed)),
                                                         O::load(world_row(g, kMode))));
    }
  }
  const glibc_sine::GlibcTable& table = *sine_table;
  double* const args = arguments_row(g0, 0); // the N groups' rows are consecutive
  double* const out = sines_row(g0, 0);
  unsigned far_lanes = 0; // lanes glibc's sin takes elsewhere (|x| >= 105414336, NaN): none from phases in [0, 1)
  int sines_done = 0, sine_credit = 0; // sines due after link j: (j + 1) * sine_rows / links, by steps
  // Links in file order (step.cpp apply_links): each impulse goes into both
  // ends' velocities at once; a zero-length link adds nothing (masked).
  const int* la = link_a.data();
  const int* lb = link_b.data();
  for (int j = 0; j < links; ++j) {
    const int a = la[j], b = lb[j];
    // The next frame's sines, spread over the links.
    for (sine_credit += sine_rows; sine_credit >= links; sine_credit -= links, ++sines_done) {
      unsigned far = 0;
      glibc_sine::glibc_sin<O, 1>(table, args + sines_done * kW, out + sines_done * kW, &far);
      far_lanes |= far;
    }
#pragma GCC unroll 4
    for (int n = 0; n < N; ++n) {
      const V dx = O::sub(x[n][b], x[n][a]);
      const V dy = O::sub(y[n][b], y[n][a]);
      const V length = simd_rules::length<O>(dx, dy);
      const M acts = O::ne(length, zero);
      const V c = simd_rules::impulse_factor<O>(springyness[n], length, O::load(target[n] + static_cast<std::size_t>(j) * kW));
      const V px = O::mul(c, dx), py = O::mul(c, dy);
      if (a < masses) {
        vx[n][a] = O::add_where(acts, vx[n][a], px);
        vy[n][a] = O::add_where(acts, vy[n][a], py);
      }
      if (b < masses) {
        vx[n][b] = O::sub_where(acts, vx[n][b], px);
        vy[n][b] = O::sub_where(acts, vy[n][b], py);
      }
    }
  }
  // Masses in order (step.cpp move_masses); autoreverse lane by lane in mass order.
  simd_rules::MassParams<O> params[N];
  for (int n = 0; n < N; ++n) {
    const int g = g0 + n;
    params[n] = {O::load(world_row(g, kGravityStep)), O::load(world_row(g, kKeep)), O::load(world_row(g, kWidth)),
                 O::load(world_row(g, kHeight)),      O::load(world_row(g, kFs)),   O::load(world_row(g, kRs))};
  }
  for (int i = 0; i < masses; ++i) {
#pragma GCC unroll 4
    for (int n = 0; n < N; ++n) {
      const simd_rules::SideHits<O> hits =
          simd_rules::move_mass<O, true, true, true, true>(params[n], x[n][i], y[n][i], vx[n][i], vy[n][i]);
      if (O::any(hits.hit)) [[unlikely]] {
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
  // The wave advance after the physics (docs/physics.md, "The wave"). Where a direction turned
  // (or the sines were not computed above), the next frame's sines again.
  for (int n = 0; n < N; ++n) {
    const int g = g0 + n;
    const V phase = simd_rules::advance_wave_phase<O>(O::load(world_row(g, kPhase)), O::load(world_row(g, kSpeed)),
                                                      O::load(world_row(g, kMode)));
    O::store(world_row(g, kPhase), phase);
    if (columns == 0) continue;
    const double* expected = predicted.data() + static_cast<std::size_t>(g) * kW;
    if (sine_rows == 0 || far_lanes != 0 ||
        _mm512_cmpneq_epi64_mask(_mm512_castpd_si512(phase), _mm512_load_si512(expected)) != 0) {
      sines_now(g);
    }
  }
}

void LockstepBatch::run(State* const* states, long long frames) {
  Data& d = *d_;
  require_batch_states(states, d.count, [&](int) { return d.points; }, "LockstepBatch::run");
  for (int c = 0; c < d.count; ++c) require_valid_jitter_of(states[c]->jitter, "LockstepBatch::run", c);
  if (frames <= 0) return;
  d.load(states);
  // Padding lanes autoreverse into a scratch copy of the last state, not into it.
  std::vector<State> padding;
  padding.reserve(static_cast<std::size_t>(d.groups) * kW - d.count);
  d.lane_state.resize(static_cast<std::size_t>(d.groups) * kW);
  d.lane_seed_mix.assign(static_cast<std::size_t>(d.groups) * kW, 0); // padding lanes: exact, unread
  d.lane_threshold.assign(d.lane_seed_mix.size(), 0);
  d.group_jittered.assign(static_cast<std::size_t>(d.groups), 0);
  for (int lane = 0; lane < d.groups * kW; ++lane) {
    if (lane < d.count) {
      d.lane_state[lane] = states[lane];
      const PreparedJitter jitter(states[lane]->jitter);
      d.lane_seed_mix[lane] = jitter.seed_mix;
      d.lane_threshold[lane] = jitter.threshold;
      if (jitter.threshold != 0) d.group_jittered[lane / kW] = 1;
    } else {
      padding.push_back(*states[d.count - 1]);
      d.lane_state[lane] = &padding.back();
    }
  }
  if (d.columns > 0) {
    for (int g = 0; g < d.groups; ++g) d.sines_now(g);
  }
  for (long long f = 0; f < frames; ++f) {
    int g = 0;
    for (; g + 1 < d.groups; g += 2) d.step_groups<2>(g);
    if (g < d.groups) d.step_groups<1>(g);
  }
  d.store(states);
  for (int c = 0; c < d.count; ++c) states[c]->frame += frames;
}

#pragma GCC pop_options

} // namespace soda
