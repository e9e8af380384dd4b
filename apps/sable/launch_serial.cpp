// A build without MPI: every run is one process (`mpirun -np N` would start N independent
// runs, each writing the same outputs: refused when the environment shows a launcher).
#include <cstdio>
#include <cstdlib>

#include "launch.hpp"

Launch::Launch(int& /*argc*/, char**& /*argv*/) {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const char* v = std::getenv(var);
    if (v && std::atoi(v) > 1) {
      std::fprintf(stderr,
                   "error: started by an MPI launcher (%s = %s) but this sable was built "
                   "without MPI: install libopenmpi-dev and build again (scripts/setup.sh)\n",
                   var, v);
      std::exit(2);
    }
  }
}

Launch::~Launch() = default;

std::string Launch::prefix() const {
  return {};
}

void Launch::abort(int code) const {
  std::exit(code);
}
