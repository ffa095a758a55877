// The messages between rank 0 (the master) and the workers, and the helpers that
// send and receive them as byte buffers.
//
//   master -> worker  Setup    problem, estimator (wire_format), requested threads (i32)
//   worker -> master  Ready    threads the worker will use (i32)
//   master -> worker  Work     count (u32), then per creature: index (u64), creature
//   worker -> master  Results  count (u32), then per creature: index (u64), evaluation
//   worker -> master  Failure  text: what went wrong, naming rank and host
//   master -> worker  Stop     empty: leave the worker loop
//
// A worker only ever answers; it has at most one chunk at a time, so every
// blocking send meets a posted receive and nothing can deadlock. Waiting polls
// with a short sleep rather than MPI's busy wait, so a waiting rank leaves its
// core to the evaluation threads.
#pragma once

#include <mpi.h>

#include <optional>
#include <vector>

namespace sodaevo::mpi_protocol {

enum Tag : int { Setup = 1, Ready = 2, Work = 3, Results = 4, Failure = 5, Stop = 6 };

struct Message {
  int source = -1;
  int tag = 0;
  std::vector<char> bytes;
};

void send(MPI_Comm comm, int destination, Tag tag, const std::vector<char>& bytes);

/// A message from `source` (or MPI_ANY_SOURCE) if one has arrived.
std::optional<Message> try_receive(MPI_Comm comm, int source);

/// Waits for a message from `source` (or MPI_ANY_SOURCE), sleeping between polls.
Message receive(MPI_Comm comm, int source);

/// Sleeps a little longer each time it is called, up to a cap; reset() after work.
class Backoff {
 public:
  void wait();
  void reset() { micros_ = 0; }

 private:
  int micros_ = 0;
};

} // namespace sodaevo::mpi_protocol
