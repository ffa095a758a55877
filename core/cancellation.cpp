#include "cancellation.hpp"

namespace soda {

namespace {
thread_local const Cancellation* installed = nullptr;
}

const Cancellation* current_cancellation() { return installed; }

CancellationScope::CancellationScope(const Cancellation* c) : previous_(installed) { installed = c; }

CancellationScope::~CancellationScope() { installed = previous_; }

void check_cancellation() {
  if (installed != nullptr && installed->requested()) throw Cancelled{};
}

} // namespace soda
