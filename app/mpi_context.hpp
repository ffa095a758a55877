// The MPI session of this process, if it was started by an MPI launcher and the
// build has MPI. main() owns it (MPI_Init to MPI_Finalize); `evolve` uses it.
#pragma once

#if SODAEVO_HAS_MPI
namespace sodaevo {
class MpiSession;
}

namespace sodaevo::app {

void set_current_mpi_session(MpiSession* session);
/// nullptr when the process was not started by mpirun/srun.
MpiSession* current_mpi_session();

} // namespace sodaevo::app
#endif
