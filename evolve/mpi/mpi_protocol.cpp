#include "mpi_protocol.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <string>
#include <thread>

#include "evolve/mpi/mpi_session.hpp"

namespace sodaevo::mpi_protocol {

void send(MPI_Comm comm, int destination, Tag tag, const std::vector<char>& bytes) {
  if (bytes.size() > static_cast<std::size_t>(INT_MAX)) {
    throw MpiError("a message of " + std::to_string(bytes.size()) + " bytes is too large for one MPI send");
  }
  check_mpi(MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, destination, tag, comm), "MPI_Send");
}

std::optional<Message> try_receive(MPI_Comm comm, int source) {
  int flag = 0;
  MPI_Status status;
  check_mpi(MPI_Iprobe(source, MPI_ANY_TAG, comm, &flag, &status), "MPI_Iprobe");
  if (!flag) return std::nullopt;
  int count = 0;
  check_mpi(MPI_Get_count(&status, MPI_BYTE, &count), "MPI_Get_count");
  Message m;
  m.source = status.MPI_SOURCE;
  m.tag = status.MPI_TAG;
  m.bytes.resize(static_cast<std::size_t>(count));
  check_mpi(MPI_Recv(m.bytes.data(), count, MPI_BYTE, m.source, m.tag, comm, MPI_STATUS_IGNORE), "MPI_Recv");
  return m;
}

Message receive(MPI_Comm comm, int source) {
  Backoff backoff;
  for (;;) {
    if (std::optional<Message> m = try_receive(comm, source)) return std::move(*m);
    backoff.wait();
  }
}

void Backoff::wait() {
  // 10 us, 20 us, ... up to 200 us: a returned chunk waits at most 0.2 ms for
  // its next one, and an idle rank polls 5000 times a second (about 1% of a core).
  micros_ = micros_ == 0 ? 10 : std::min(micros_ * 2, 200);
  std::this_thread::sleep_for(std::chrono::microseconds(micros_));
}

} // namespace sodaevo::mpi_protocol
