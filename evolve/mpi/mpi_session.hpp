// MpiSession: this process's membership in an MPI job, from MPI_Init to
// MPI_Finalize (one per process, RAII).
//
// Errors return instead of aborting (MPI_ERRORS_RETURN), so a failed call becomes
// an MpiError the run can stop on cleanly. Only the main thread calls MPI
// (MPI_THREAD_FUNNELED); evaluation threads never do. Rank 0 runs the genetic
// algorithm and owns the run folder; the other ranks are workers (mpi_worker.hpp).
#pragma once

#include <mpi.h>

#include <stdexcept>
#include <string>

namespace sodaevo {

class MpiError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws MpiError naming `what` and MPI's own description unless rc == MPI_SUCCESS.
void check_mpi(int rc, const char* what);

class MpiSession {
 public:
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  [[nodiscard]] int rank() const { return rank_; }
  [[nodiscard]] int size() const { return size_; }
  [[nodiscard]] const std::string& host() const { return host_; }
  [[nodiscard]] MPI_Comm comm() const { return MPI_COMM_WORLD; }

  /// Threads a rank uses when the user asked for `requested` (0 = this node's
  /// cores shared evenly between the ranks on it).
  [[nodiscard]] int resolve_threads(int requested) const;

  /// Rank 0: tells every worker to leave (done once; the destructor does it too).
  void stop_workers();
  /// After an MPI error the job cannot be left politely: the destructor then
  /// calls MPI_Abort (the run folder is already consistent by then).
  void mark_broken() { broken_ = true; }

 private:
  int rank_ = 0;
  int size_ = 1;
  int local_size_ = 1;
  std::string host_;
  bool workers_stopped_ = false;
  bool broken_ = false;
};

} // namespace sodaevo
