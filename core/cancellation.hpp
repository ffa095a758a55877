// Stopping a long run from outside: Ctrl-C in Python (python/interruptible.hpp).
//
// A caller that wants to stop its own work installs a Cancellation on its thread
// (CancellationScope); parallel_for_index hands it on to the threads it starts,
// and the engine's frame loops call check_cancellation() between chunks of at most
// kCancellationFrames frames, which throws Cancelled once the cancellation was
// requested. Nothing is installed by the command line, and a thread without one
// pays a thread-local read per chunk. Chunking never changes a result: the
// steppers give the bits of one long run however the frames are split.
#pragma once

#include <atomic>
#include <exception>

namespace soda {

/// Frames the engine steps at most between two checks.
inline constexpr long long kCancellationFrames = 1024;

/// Thrown by check_cancellation once the thread's cancellation was requested.
struct Cancelled : std::exception {
  [[nodiscard]] const char* what() const noexcept override { return "cancelled"; }
};

class Cancellation {
 public:
  void request() { requested_.store(true, std::memory_order_relaxed); }
  [[nodiscard]] bool requested() const { return requested_.load(std::memory_order_relaxed); }

 private:
  std::atomic<bool> requested_{false};
};

/// The cancellation installed on this thread, or nullptr.
const Cancellation* current_cancellation();

/// Installs `c` on this thread while the scope lives (the previous one after).
class CancellationScope {
 public:
  explicit CancellationScope(const Cancellation* c);
  ~CancellationScope();
  CancellationScope(const CancellationScope&) = delete;
  CancellationScope& operator=(const CancellationScope&) = delete;

 private:
  const Cancellation* previous_;
};

/// Throws Cancelled if this thread's cancellation was requested.
void check_cancellation();

} // namespace soda
