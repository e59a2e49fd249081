// The MPI side of the study commands, built as its own shared object
// (librocking_mpi.so beside the program) so that OpenMPI and the libraries it
// pulls in are loaded only when the program was started by mpirun: a run
// outside mpirun never maps them (mpi_jobs.cpp opens this object on demand).
// It exposes one C symbol, rocking_mpi_interface, the table of functions of
// mpi_plugin.hpp.
#include "mpi_plugin.hpp"
#include <mpi.h>
#include <climits>
#include <vector>

namespace {

RockingMpiWorld start() {
  RockingMpiWorld w{0, 1};
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &w.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &w.size);
  return w;
}

void finish() { MPI_Finalize(); }

// The lengths first (MPI_Gather), then the bytes at their offsets (MPI_Gatherv).
int gather(const char* mine, std::size_t size, void* context, RockingMpiReceive receive) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  int length = size > static_cast<std::size_t>(INT_MAX) ? -1 : static_cast<int>(size);
  std::vector<int> lengths(static_cast<std::size_t>(ranks)), offsets(static_cast<std::size_t>(ranks));
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  // Every rank learns whether some rank's bytes (or their sum) overflow an int, and all stop alike.
  long long total = 0;
  int too_long = 0;
  if (rank == 0)
    for (int r = 0; r < ranks; ++r) {
      const int n = lengths[static_cast<std::size_t>(r)];
      if (n < 0 || total + n > INT_MAX) too_long = 1;
      offsets[static_cast<std::size_t>(r)] = static_cast<int>(total);
      total += n < 0 ? 0 : n;
    }
  MPI_Bcast(&too_long, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (too_long != 0) return -1;
  std::vector<char> all(rank == 0 ? static_cast<std::size_t>(total) : 0);
  MPI_Gatherv(mine, length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
  if (rank == 0) receive(context, all.data(), all.size());
  return 0;
}

const RockingMpiFunctions functions{start, finish, gather};

}  // namespace

extern "C" __attribute__((visibility("default"))) const RockingMpiFunctions* rocking_mpi_interface() {
  return &functions;
}
