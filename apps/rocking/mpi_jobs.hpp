// Splitting a study's job list across MPI processes (OpenMPI): each rank runs
// the jobs i with i % size == rank on its threads, and rank 0 gathers the rows
// and writes them in job order, so the output equals that of one process.
// MPI is initialised only when the program was started by mpirun (its
// environment says so); otherwise everything runs in this process.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace rocking::app {

struct MpiWorld {
  int rank = 0, size = 1;
  bool active = false;
};

// Starts MPI when launched by mpirun/mpiexec; finalises on destruction.
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
std::vector<std::pair<long, std::string>> gather_rows(const MpiWorld& w,
                                                      const std::vector<std::pair<long, std::string>>& mine);

}  // namespace rocking::app
