// parallel_for_index: run work(i) for every i in [0, count) on up to `threads`
// threads.
//
// Work items are handed out dynamically (an atomic counter), because creatures
// differ in cost; each item writes its result into its own slot, so the thread
// count and the scheduling never change a result (determinism by index, as in
// pagmo's island/evaluator split). The first exception thrown by an item is
// re-thrown on the calling thread after all threads have stopped.
#pragma once

#include <cstddef>
#include <functional>

namespace sodaevo {

/// Number of threads to use when the user asked for `requested` (0 = all cores).
int resolve_thread_count(int requested);

void parallel_for_index(std::size_t count, int threads, const std::function<void(std::size_t)>& work);

} // namespace sodaevo
