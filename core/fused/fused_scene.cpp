#include "core/fused/fused_scene.hpp"
#include "core/cancellation.hpp"

#include <algorithm>
#include <cassert>
#include <stdexcept>
#include <utility>

#include "core/fused/kernel_table.hpp"
#include "core/fused/scene_data.hpp"
#include "core/fused/sine_rows.hpp"

namespace soda {

using fused::SceneData;
using fused::chunk_fn;
using fused::register_chunk_fn;

void fused::SceneData::load_state(State* const* st) {
  for (std::size_t c = 0; c < creatures.size(); ++c) {
    const Creature& cr = creatures[c];
    const State& s = *st[c];
    for (int p = 0; p < cr.model->point_count; ++p) {
      const int w = cr.work_of_point[p];
      px(w) = s.x[p];
      py(w) = s.y[p];
      pvx(w) = s.vx[p];
      pvy(w) = s.vy[p];
    }
  }
  for (int w = masses; w < padded_masses; ++w) px(w) = py(w) = pvx(w) = pvy(w) = 0.0;
}

void fused::SceneData::store_state(State* const* st) {
  for (std::size_t c = 0; c < creatures.size(); ++c) {
    const Creature& cr = creatures[c];
    State& s = *st[c];
    for (int p = 0; p < cr.model->mass_count; ++p) {
      const int w = cr.work_of_point[p];
      s.x[p] = px(w);
      s.y[p] = py(w);
      s.vx[p] = pvx(w);
      s.vy[p] = pvy(w);
    }
  }
}
void fused::SceneData::record(const KernelChoice& k) {
  last = k;
  if (std::find(used.begin(), used.end(), k) == used.end()) used.push_back(k);
}

FusedScene::FusedScene(const std::vector<const Model*>& models, long long frame_budget, FastStepOptions options)
    : d_(std::make_unique<SceneData>()) {
  if (models.empty()) throw std::invalid_argument("FusedScene: no models");
  if (models.size() > 1 && options.force_ordered) {
    throw std::invalid_argument("FusedScene: the ordered kernel takes one model");
  }
#ifndef NDEBUG
  for (const Model* m : models) assert(constants_current(*m));
#endif
  d_->build(models, frame_budget, options);
}
FusedScene::~FusedScene() = default;
FusedScene::FusedScene(FusedScene&&) noexcept = default;
FusedScene& FusedScene::operator=(FusedScene&&) noexcept = default;

int FusedScene::size() const { return static_cast<int>(d_->creatures.size()); }
const Model& FusedScene::model(int c) const { return *d_->creatures[c].model; }
const SceneNeeds& FusedScene::needs(int c) const { return d_->creatures[c].needs; }
bool FusedScene::used(const KernelChoice& k) const {
  return std::find(d_->used.begin(), d_->used.end(), k) != d_->used.end();
}
const KernelChoice& FusedScene::last_kernel() const { return d_->last; }
long long FusedScene::sines_evaluated() const { return d_->sines_evaluated; }
long long FusedScene::bar_rules_run() const { return d_->bar_rules_run; }
bool FusedScene::points_in_registers() const { return d_->points_in_registers; }
bool FusedScene::frame_in_registers() const { return d_->frame_in_registers; }

namespace {

/// Checks the states of a run and takes their sine jitter: jitter is part of the
/// rows of sines (fill_rows), so a state whose jitter is not the one its creature's
/// rows and targets were made with makes them again.
void take_states(SceneData& s, State* const* states, const char* who) {
  const bool alone = s.creatures.size() == 1;
  require_batch_states(
      states, static_cast<int>(s.creatures.size()), [&](int c) { return s.creatures[c].model->point_count; }, who);
  bool jitter_changed = false;
  for (std::size_t c = 0; c < s.creatures.size(); ++c) {
    const SineJitter& jitter = states[c]->jitter;
    require_valid_jitter_of(jitter, who, alone ? -1 : static_cast<int>(c));
    if (!(jitter == s.creatures[c].jitter)) {
      s.creatures[c].jitter = jitter;
      jitter_changed = true;
    }
  }
  if (jitter_changed) {
    s.numbering_valid = false;
    s.targets_valid = false;
    s.row_count = 0;
    s.row_next = 0;
    s.rows_synced = false;
  }
}

/// Loads the states into the scene and gives the kernel the scene needs (walls
/// left to the caller).
KernelChoice begin_frames(SceneData& s, State* const* states) {
  s.load_state(states);
  s.leave_rows(); // the states may be others, or changed since
  KernelChoice k;
  k.simd = s.simd;
  k.wave = s.any_wave;
  k.gravity = s.any_gravity;
  k.bars = s.bars;
  k.ordered = s.options.force_ordered;
  // Fixed bars: every wall tested (a bar's response is not bounded by the speed),
  // the bar rules after the mass pass (bar_pass) from the states' memories.
  if (s.bars != BarKind::None) {
    k.walls = WallNeeds{};
    if (!k.ordered) s.watch_bars(states);
  }
  return k;
}

/// The free masses' least and greatest x, in mass order (as a race takes them).
template <typename XOf>
std::pair<double, double> x_extent(int masses, const XOf& x_of) {
  double lo = x_of(0), hi = lo;
  for (int p = 1; p < masses; ++p) {
    const double x = x_of(p);
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  return {lo, hi};
}

} // namespace

long long FusedScene::run_until(State& state, long long frames, const std::function<bool(double, double)>& stop) {
  if (d_->creatures.size() != 1) throw std::invalid_argument("FusedScene::run_until: a scene of one model only");
  State* const st[1] = {&state};
  std::vector<long long> done;
  std::vector<bool> stopped;
  return run_until(st, frames, [&](int, double lo, double hi) { return stop(lo, hi); }, done, stopped);
}

long long FusedScene::run_until(State* const* states, long long frames, const StopFn& stop, std::vector<long long>& done,
                                std::vector<bool>& stopped, int min_running) {
  SceneData& s = *d_;
  const std::size_t n = s.creatures.size();
  take_states(s, states, "FusedScene::run_until");
  done.assign(n, 0);
  stopped.assign(n, false);
  if (frames <= 0) return 0;
  KernelChoice k = begin_frames(s, states);
  k.walls = WallNeeds{}; // every wall tested: a frame at a time
  s.record(k);
  const fused::ChunkFn one_frame = k.ordered                      ? nullptr
                                   : s.bars != BarKind::None     ? fused::bar_chunk_fn(s.simd, k.gravity)
                                   : s.frame_in_registers        ? register_chunk_fn(k.gravity, k.walls)
                                                                 : chunk_fn(s.simd, k.gravity, k.walls);
  // A creature that stops is parked: its state as after its last frame is kept
  // aside (the scene goes on stepping its masses, whose results are then dropped).
  std::vector<State> parked;
  int running = static_cast<int>(n);
  long long f = 0;
  // Every state as after the frames it ran: the running ones after f, the stopped
  // ones as parked (also when `stop` throws: the states are then left there).
  const auto finish = [&] {
    s.store_state(states);
    for (std::size_t c = 0; c < n; ++c) {
      if (stopped[c]) {
        *states[c] = std::move(parked[c]);
      } else {
        states[c]->frame += f;
        done[c] = f;
      }
    }
  };
  try {
    while (f < frames && running > 0 && running >= min_running) {
      if (f % kCancellationFrames == kCancellationFrames - 1) check_cancellation();
      if (k.ordered) {
        s.ordered_frame(*states[0]);
      } else {
        one_frame(s, states, 1);
      }
      ++f;
      for (std::size_t c = 0; c < n; ++c) {
        if (stopped[c]) continue;
        const SceneData::Creature& cr = s.creatures[c];
        const int masses = cr.model->mass_count;
        const std::vector<int>& work = cr.work_of_point;
        const auto [lo, hi] = x_extent(std::max(masses, 1), [&](int p) {
          return masses > 0 ? s.px(work[static_cast<std::size_t>(p)]) : 0.0;
        });
        if (!stop(static_cast<int>(c), lo, hi)) continue;
        if (parked.empty()) parked.resize(n);
        parked[c] = *states[c];
        for (int p = 0; p < masses; ++p) {
          const int w = work[static_cast<std::size_t>(p)];
          parked[c].x[p] = s.px(w);
          parked[c].y[p] = s.py(w);
          parked[c].vx[p] = s.pvx(w);
          parked[c].vy[p] = s.pvy(w);
        }
        parked[c].frame += f;
        done[c] = f;
        stopped[c] = true;
        s.park(static_cast<int>(c));
        --running;
      }
    }
  } catch (...) {
    finish();
    throw;
  }
  finish();
  return f;
}

void FusedScene::run(State* const* states, long long frames) {
  SceneData& s = *d_;
  const bool alone = s.creatures.size() == 1;
  const char* who = alone ? "FastStepper::run" : "FusedScene::run";
  take_states(s, states, who);
  if (frames <= 0) return;
  KernelChoice k = begin_frames(s, states);
  // Walls: without bars, the walls no mass of any creature can reach within a
  // chunk of frames are not tested in that chunk. A chunk ends when a skipped wall
  // might come into reach; while every wall is tested the reach is re-checked
  // every kRecheck frames.
  constexpr long long kMinSkip = 32;  // a wall test costs less than re-checking the reach often
  constexpr long long kRecheck = 256;
  const bool adaptive = s.options.adaptive_walls && s.bars == BarKind::None && !k.ordered;
  long long done = 0;
  while (done < frames) {
    if (done > 0) check_cancellation();
    long long chunk = std::min(frames - done, kCancellationFrames);
    if (adaptive) {
      WallSafeFrames safe{kSafeFramesCap, kSafeFramesCap, kSafeFramesCap};
      for (const SceneData::Creature& cr : s.creatures) {
        const double* p = s.positions.data() + 2 * static_cast<std::size_t>(cr.mass_base);
        const WallSafeFrames c = wall_safe_frames(*cr.model, p, p + 1, 2);
        safe.floor = std::min(safe.floor, c.floor);
        safe.ceiling = std::min(safe.ceiling, c.ceiling);
        safe.sides = std::min(safe.sides, c.sides);
      }
      k.walls = WallNeeds{safe.floor < kMinSkip, safe.ceiling < kMinSkip, safe.sides < kMinSkip};
      long long valid = kSafeFramesCap;
      if (!k.walls.floor) valid = std::min(valid, safe.floor);
      if (!k.walls.ceiling) valid = std::min(valid, safe.ceiling);
      if (!k.walls.sides) valid = std::min(valid, safe.sides);
      if (valid == kSafeFramesCap) valid = kRecheck; // every wall tested
      chunk = std::min(chunk, valid);
    } else {
      k.walls = WallNeeds{};
    }
    s.record(k);
    if (k.ordered) {
      for (long long f = 0; f < chunk; ++f) s.ordered_frame(*states[0]);
    } else if (s.bars != BarKind::None) {
      fused::bar_chunk_fn(s.simd, k.gravity)(s, states, chunk);
    } else {
      (s.frame_in_registers ? register_chunk_fn(k.gravity, k.walls) : chunk_fn(s.simd, k.gravity, k.walls))(
          s, states, chunk);
    }
    done += chunk;
  }
  s.store_state(states);
  for (std::size_t c = 0; c < s.creatures.size(); ++c) states[c]->frame += frames;
}

} // namespace soda
