// Splitting a study's job list across MPI processes (OpenMPI): each rank runs
// the jobs i with i % size == rank on its threads, and rank 0 gathers the rows
// and writes them in job order, so the output equals that of one process.
// MPI is initialised only when the program was started by mpirun (its
// environment says so); otherwise everything runs in this process, and
// OpenMPI is never loaded: its calls live in librocking_mpi.so beside the
// program (mpi_plugin.hpp), opened on demand.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace rocking::app {

struct MpiWorld {
  int rank = 0, size = 1;
  bool active = false;
};

using MpiRows = std::vector<std::pair<long, std::string>>;

// Starts MPI when launched by mpirun/mpiexec; finalises on destruction.
// Throws RunError naming the object when MPI is asked for and cannot be loaded.
class MpiSession {
 public:
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  const MpiWorld& world() const { return world_; }

 private:
  MpiWorld world_;
};

// Rank 0 receives every rank's (job index, text) pairs, the others get nothing.
// Throws RunError when the rows exceed what one MPI message counts (2 GB).
MpiRows gather_rows(const MpiWorld& w, const MpiRows& mine);

}  // namespace rocking::app
