// How `sable` was started: alone, or as one of the processes of `mpirun -np N sable ...`.
// The build picks the implementation (CMakeLists.txt): launch_mpi.cpp when MPI is found,
// launch_serial.cpp otherwise; nothing else in Sable calls MPI_Init.
#pragma once

#include <memory>
#include <string>

#include "sable/world/domain.hpp"

class Launch {
 public:
  // Joins the MPI job when an MPI launcher started this process (its environment says so);
  // otherwise, and in a build without MPI, a run of one process.
  Launch(int& argc, char**& argv);
  ~Launch();
  Launch(const Launch&) = delete;
  Launch& operator=(const Launch&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  // The decomposition every process of a run of several builds; null for one process.
  const sable::DomainMaker* domains() const { return domains_.get(); }
  // What starts this process's lines on the error output ("process 2: "; "" for process 0).
  std::string prefix() const;
  // Ends every process of the job with this exit status (one process's error would otherwise
  // leave the others waiting for it); a plain exit for a run of one process.
  [[noreturn]] void abort(int code) const;

 private:
  int rank_ = 0, size_ = 1;
  std::unique_ptr<sable::DomainMaker> domains_;
};
