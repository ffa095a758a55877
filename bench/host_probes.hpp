// What the host gives a second thread, measured beside the population runs of
// `sodaevo bench speed` (population_speed.cpp): work items that share nothing
// (one bound by its own latency, one by the square-root/divide unit, as the step
// is), holding a thread to one core, and the steal time the hypervisor took.
#pragma once

#include <sched.h>

#include <cstddef>
#include <vector>

#include "core/simd_level.hpp"

namespace sodaevo::bench {

/// A work item that shares nothing with the others: products and sums on 16
/// independent chains (no memory traffic), about a millisecond. Each chain waits on
/// its own latency, so its thread speed-up shows whether a second thread runs at
/// all (a host may time-slice both virtual cores on one hardware thread), not
/// whether the two share one physical core's units: divider_item below shows that.
double arithmetic_item(std::size_t i);

/// A work item bound by the square-root/divide unit, as the step's link pass is:
/// four square roots and four divisions per pass on independent vectors of the
/// engine's SIMD level, about half a millisecond. Its thread speed-up is 2x only
/// on two physical cores. Where the host runs the two virtual cores as the two
/// hardware threads of one physical core, they share that unit and it drops to 1x,
/// while the arithmetic items above (chains waiting on their own latency) still
/// show 2x; this project's machine has shown both in the same rounds
/// (bench/README.md, "Ninth session").
double divider_item(std::size_t i, soda::SimdLevel level);

/// The first `wanted` cores this process may run on; empty where there are fewer or
/// the set cannot be read (the 1-thread runs then go unpinned). The all-thread run
/// may use other cores where more are allowed than `wanted`.
std::vector<int> cores_to_pin(int wanted);

/// Holds the calling thread to one core while it lives and puts the thread's
/// previous core set back. `held()` says whether the hold took (it may not, where
/// the process may not choose its cores); a thread started meanwhile would inherit
/// the hold, so the population's 1-thread runs start none.
class CoreHold {
 public:
  explicit CoreHold(int core);
  ~CoreHold() noexcept(false);
  CoreHold(const CoreHold&) = delete;
  CoreHold& operator=(const CoreHold&) = delete;
  bool held() const { return held_; }

 private:
  cpu_set_t saved_{};
  bool held_ = false;
};

/// Steal time the kernel has accounted to this machine's virtual CPUs since boot,
/// summed over them, in ms (the "steal" column of /proc/stat's cpu line: time the
/// hypervisor ran something else while a virtual CPU had work), or -1 where it
/// cannot be read. Counted in clock ticks (10 ms here).
double steal_ms();

} // namespace sodaevo::bench
