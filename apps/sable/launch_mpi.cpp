// A build with MPI: a process started by an MPI launcher (mpirun, mpiexec, srun with PMI)
// joins the job; one started alone does not call MPI_Init at all, so the serial commands
// (and the test suite's hundreds of them) pay nothing and need no launcher.
#include <fmt/format.h>
#include <mpi.h>

#include <cstdlib>

#include "launch.hpp"
#include "sable/mpi/mpi_domain.hpp"

namespace {

// The variables the launchers of Open MPI, MPICH (Hydra) and PMIx-based ones set.
bool started_by_launcher() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(var)) return true;
  return false;
}

class MpiDomains final : public sable::DomainMaker {
 public:
  std::unique_ptr<sable::Domain<2>> make2() const override {
    return std::make_unique<sable::MpiDomain<2>>(MPI_COMM_WORLD);
  }
  std::unique_ptr<sable::Domain<3>> make3() const override {
    return std::make_unique<sable::MpiDomain<3>>(MPI_COMM_WORLD);
  }
};

}  // namespace

Launch::Launch(int& argc, char**& argv) {
  if (!started_by_launcher()) return;
  // OpenMP threads inside a process never call MPI: the main thread does all of it.
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  if (size_ > 1) domains_ = std::make_unique<MpiDomains>();
}

Launch::~Launch() {
  int joined = 0;
  MPI_Initialized(&joined);
  if (joined) MPI_Finalize();
}

std::string Launch::prefix() const {
  return rank_ > 0 ? fmt::format("process {}: ", rank_) : std::string();
}

void Launch::abort(int code) const {
  if (size_ > 1) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}
