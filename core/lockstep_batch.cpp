// LockstepBatch's frame loop (lockstep_batch.hpp): the states in and out, the
// race's stops and the fixed-bar rules; the frame kernels are in
// lockstep_kernels.hpp (one file per instruction set), the construction in
// lockstep_plan.cpp.
#include "lockstep_batch.hpp"
#include "core/cancellation.hpp"

#include <algorithm>
#include <cstdint>
#include <stdexcept>

#include "detail/lockstep_data.hpp"
#include "physics_rules.hpp"

namespace soda {

using lockstep_detail::kW;

// The fixed-bar rules of group g's lanes after the mass pass (which left each
// mass as the reference leaves it before its bar rules, and kept its move), as
// FastStepper's bar_pass (fused/ordered.cpp) does them: per lane in file order
// against the lane's own BarMemory, for a mass that moved and that a bar
// remembers, a corner holds or whose move may touch a bar's box (every moving
// mass until each has its corner entry); a bar's response replaces the mass's
// position and velocity in the lane. The rules of one mass read and change only
// its own move and memory, so the lanes and masses left out change nothing.
void LockstepBatch::Data::bar_pass(int g) {
  const Group& G = groups[static_cast<std::size_t>(g)];
  const FixedBars& fixed = group_bars[static_cast<std::size_t>(g)];
  const std::uint8_t* due = bar_due.data() + G.due_at;
  for (int l = 0; l < G.lanes; ++l) { // padding lanes: never read
    State& s = *lane_state[static_cast<std::size_t>(g) * kW + static_cast<std::size_t>(l)];
    BarMemory& memory = s.bar_memory;
    const bool all = memory.corners.size() < static_cast<std::size_t>(G.masses);
    for (const BarContact& c : memory.contacts) { // bar_held is all 0 between lanes
      if (c.mass >= 0 && c.mass < G.masses) bar_held[static_cast<std::size_t>(c.mass)] = 1;
    }
    const Surface surface{world_row(g, kFs)[l], world_row(g, kRs)[l], world_row(g, kWidth)[l], world_row(g, kHeight)[l]};
    for (int p = 0; p < G.masses; ++p) {
      if (!all && ((due[p] >> l) & 1) == 0 && bar_held[static_cast<std::size_t>(p)] == 0 &&
          memory.corners[static_cast<std::size_t>(p)].bar < 0) {
        continue; // its rules would change nothing (may_meet_bars)
      }
      const double vx = move_row(g, 2, p)[l], vy = move_row(g, 3, p)[l];
      if (rules::is_at_rest(vx, vy)) continue; // not moved: no bar rules
      const double x0 = move_row(g, 0, p)[l], y0 = move_row(g, 1, p)[l];
      double& x = point_row(g, 0, p)[l];
      double& y = point_row(g, 1, p)[l];
      ++bar_rules_run;
      rules::apply_fixed_bars(fixed, memory, p, rules::mass_move(x0, y0, x0 + vx, y0 + vy, vx, vy), surface, x, y,
                              point_row(g, 2, p)[l], point_row(g, 3, p)[l]);
    }
    for (const BarContact& c : memory.contacts) {
      if (c.mass >= 0 && c.mass < G.masses) bar_held[static_cast<std::size_t>(c.mass)] = 0;
    }
  }
}

void LockstepBatch::run(State* const* states, long long frames) {
  Data& d = *d_;
  require_batch_states(states, d.count, [&](int c) { return d.state_points[static_cast<std::size_t>(c)]; }, "LockstepBatch::run");
  for (int c = 0; c < d.count; ++c) require_valid_jitter_of(states[c]->jitter, "LockstepBatch::run", c);
  step(states, frames);
}

void LockstepBatch::step(State* const* states, long long frames) { step_until(states, frames, nullptr, nullptr); }

long long LockstepBatch::run_until(State* const* states, long long frames, const StopFn& stop, std::vector<long long>& done) {
  Data& d = *d_;
  require_batch_states(states, d.count, [&](int c) { return d.state_points[static_cast<std::size_t>(c)]; }, "LockstepBatch::run_until");
  for (int c = 0; c < d.count; ++c) require_valid_jitter_of(states[c]->jitter, "LockstepBatch::run_until", c);
  done.assign(static_cast<std::size_t>(d.count), 0);
  return step_until(states, frames, &stop, done.data());
}

long long LockstepBatch::step_until(State* const* states, long long frames, const StopFn* stop, long long* done) {
  Data& d = *d_;
  if (frames <= 0) return 0;
  d.load(states);
  std::fill(d.walls_far.begin(), d.walls_far.end(), 0); // tested in the first frame, known after it
  const std::size_t lanes = d.groups.size() * kW;
  // Padding lanes autoreverse into a scratch copy of their group's last state, not
  // into it; so do stopped lanes (and their bar memory), which step on unread.
  std::vector<State> scratch;
  scratch.reserve(lanes);
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
        scratch.push_back(*states[G.first + G.lanes - 1]);
        d.lane_state[lane] = &scratch.back();
      }
    }
  }
  for (int g = 0; g < static_cast<int>(d.groups.size()); ++g) {
    if (d.groups[static_cast<std::size_t>(g)].columns > 0) d.kernels.sines_now(d, g);
  }
  std::vector<std::uint8_t> running(static_cast<std::size_t>(d.count), 1);
  int left = d.count;
  long long ran = 0;
  while (ran < frames && left > 0) {
    if (ran % kCancellationFrames == kCancellationFrames - 1) check_cancellation();
    d.kernels.step_frame(d);
    ++ran;
    if (stop == nullptr) continue;
    // Each running lane's free masses' least and greatest x, in mass order as
    // FastStepper::run_until takes them (std::min, std::max one after the other).
    for (int g = 0; g < static_cast<int>(d.groups.size()); ++g) {
      const Data::Group& G = d.groups[static_cast<std::size_t>(g)];
      for (int l = 0; l < G.lanes; ++l) {
        const int c = G.first + l;
        if (running[static_cast<std::size_t>(c)] == 0) continue;
        double lo = G.masses > 0 ? d.point_row(g, 0, 0)[l] : 0.0, hi = lo;
        for (int p = 1; p < G.masses; ++p) {
          const double x = d.point_row(g, 0, p)[l];
          lo = std::min(lo, x);
          hi = std::max(hi, x);
        }
        if (!(*stop)(c, lo, hi)) continue;
        State& s = *states[c];
        d.store_lane(g, l, s);
        s.frame += ran;
        done[c] = ran;
        running[static_cast<std::size_t>(c)] = 0;
        --left;
        scratch.push_back(s);
        d.lane_state[static_cast<std::size_t>(g) * kW + static_cast<std::size_t>(l)] = &scratch.back();
      }
    }
  }
  for (int g = 0; g < static_cast<int>(d.groups.size()); ++g) {
    const Data::Group& G = d.groups[static_cast<std::size_t>(g)];
    for (int l = 0; l < G.lanes; ++l) {
      const int c = G.first + l;
      if (running[static_cast<std::size_t>(c)] == 0) continue;
      d.store_lane(g, l, *states[c]);
      states[c]->frame += ran;
      if (done != nullptr) done[c] = ran;
    }
  }
  return ran;
}

} // namespace soda
