// What this build and this process know about MPI, without needing MPI itself.
//
// A binary built without MPI can still be started by `mpirun -np 4`; every copy
// would then run the whole evolution into the same folder. launcher_rank_count()
// reads the environment MPI launchers set (Open MPI, MPICH/Hydra, Slurm's srun), so
// the CLI can refuse that with a clear message instead.
#pragma once

#include <string>

namespace sodaevo {

/// True when this binary was built with MPI support (CMake option SODAEVO_MPI).
bool mpi_support_built();

/// "MPI: yes (Open MPI 4.1.4)" or "MPI: no (built without SODAEVO_MPI)".
std::string mpi_support_summary();

/// The number of ranks the launcher started, read from the environment
/// (OMPI_COMM_WORLD_SIZE, PMI_SIZE, PMIX_SIZE, SLURM_STEP_NUM_TASKS), or 0 when
/// this process was not started by an MPI launcher.
int launcher_rank_count();

} // namespace sodaevo
