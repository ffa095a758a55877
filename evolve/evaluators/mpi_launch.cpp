#include "mpi_launch.hpp"

#include <cstdlib>
#include <string>

#if SODAEVO_HAS_MPI
#include <mpi.h>
#endif

namespace sodaevo {

bool mpi_support_built() { return SODAEVO_HAS_MPI != 0; }

std::string mpi_support_summary() {
#if SODAEVO_HAS_MPI
#if defined(OMPI_MAJOR_VERSION)
  return "MPI: yes (Open MPI " + std::to_string(OMPI_MAJOR_VERSION) + "." + std::to_string(OMPI_MINOR_VERSION) + "." +
         std::to_string(OMPI_RELEASE_VERSION) + ", MPI " + std::to_string(MPI_VERSION) + "." +
         std::to_string(MPI_SUBVERSION) + ")";
#else
  return "MPI: yes (MPI " + std::to_string(MPI_VERSION) + "." + std::to_string(MPI_SUBVERSION) + ")";
#endif
#else
  return "MPI: no (built without SODAEVO_MPI; install libopenmpi-dev and rebuild for mpirun)";
#endif
}

int launcher_rank_count() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE", "SLURM_STEP_NUM_TASKS"}) {
    if (const char* v = std::getenv(name)) {
      char* end = nullptr;
      const long n = std::strtol(v, &end, 10);
      if (end != v && *end == '\0' && n > 0 && n < (1L << 30)) return static_cast<int>(n);
    }
  }
  return 0;
}

} // namespace sodaevo
