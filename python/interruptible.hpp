// Long calls that Ctrl-C stops (simulate, evaluate, race, the optimiser's
// evaluations): the work runs on a thread of its own, without the GIL, under a
// soda::Cancellation (core/cancellation.hpp) that reaches every thread it starts;
// the calling thread waits, and every kSignalCheck takes the GIL for a moment and
// runs Python's signal handlers (PyErr_CheckSignals: signals are handled on the
// main thread only). When a handler raises (KeyboardInterrupt), the work is
// cancelled, stops within a chunk of frames, its partial results are dropped and
// the handler's exception is raised: nothing is returned half made.
#pragma once

#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <type_traits>
#include <utility>

#include <pybind11/pybind11.h>

#include "core/cancellation.hpp"

namespace sodaevo::python {

inline constexpr std::chrono::milliseconds kSignalCheck{50};

/// work() (which must not touch Python objects) run as above; its result.
template <class Work>
std::invoke_result_t<Work&> run_interruptibly(Work&& work) {
  using Result = std::invoke_result_t<Work&>;
  soda::Cancellation cancellation;
  std::optional<Result> result;
  std::exception_ptr error;
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  bool interrupted = false;
  {
    pybind11::gil_scoped_release free_python;
    std::thread worker([&] {
      const soda::CancellationScope scope(&cancellation);
      try {
        result.emplace(work());
      } catch (...) {
        error = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(mutex);
      done = true;
      finished.notify_one();
    });
    std::unique_lock<std::mutex> lock(mutex);
    while (!finished.wait_for(lock, kSignalCheck, [&] { return done; })) {
      if (interrupted) continue;
      lock.unlock();
      {
        const pybind11::gil_scoped_acquire python;
        interrupted = PyErr_CheckSignals() != 0; // the handler's exception stays set
      }
      if (interrupted) cancellation.request();
      lock.lock();
    }
    lock.unlock();
    worker.join();
  }
  if (interrupted) throw pybind11::error_already_set();
  if (error) std::rethrow_exception(error);
  return std::move(*result);
}

} // namespace sodaevo::python
