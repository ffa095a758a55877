#include "mpi_session.hpp"

#include <algorithm>
#include <thread>

#include "evolve/mpi/mpi_protocol.hpp"

namespace sodaevo {

void check_mpi(int rc, const char* what) {
  if (rc == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  if (MPI_Error_string(rc, text, &length) != MPI_SUCCESS) length = 0;
  throw MpiError(std::string("MPI call failed: ") + what + ": " + std::string(text, static_cast<std::size_t>(length)));
}

MpiSession::MpiSession() {
  int provided = 0;
  check_mpi(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  check_mpi(MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler");
  if (provided < MPI_THREAD_FUNNELED) {
    broken_ = true;
    throw MpiError("the MPI library does not allow threads in an MPI process (MPI_THREAD_FUNNELED)");
  }
  check_mpi(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
  check_mpi(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
  MPI_Comm node = MPI_COMM_NULL;
  check_mpi(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node),
            "MPI_Comm_split_type");
  check_mpi(MPI_Comm_size(node, &local_size_), "MPI_Comm_size");
  MPI_Comm_free(&node);
  char name[MPI_MAX_PROCESSOR_NAME];
  int length = 0;
  if (MPI_Get_processor_name(name, &length) == MPI_SUCCESS) host_.assign(name, static_cast<std::size_t>(length));
}

MpiSession::~MpiSession() {
  if (broken_) {
    MPI_Abort(MPI_COMM_WORLD, 1);
    return;
  }
  try {
    stop_workers();
  } catch (const MpiError&) {
    MPI_Abort(MPI_COMM_WORLD, 1);
    return;
  }
  MPI_Finalize();
}

int MpiSession::resolve_threads(int requested) const {
  if (requested > 0) return requested;
  const unsigned cores = std::thread::hardware_concurrency();
  return std::max(1, static_cast<int>(cores > 0 ? cores : 1) / std::max(1, local_size_));
}

void MpiSession::stop_workers() {
  if (rank_ != 0 || workers_stopped_) return;
  workers_stopped_ = true;
  for (int r = 1; r < size_; ++r) mpi_protocol::send(MPI_COMM_WORLD, r, mpi_protocol::Stop, {});
}

} // namespace sodaevo
