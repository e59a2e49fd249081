// The MPI side of the study commands, built as its own shared object
// (librocking_mpi.so beside the program) so that OpenMPI and the libraries it
// pulls in are loaded only when the program was started by mpirun: a run
// outside mpirun never maps them (mpi_jobs.cpp opens this object on demand).
// It exposes one C symbol, rocking_mpi_interface, the table of functions
// declared in mpi_jobs.hpp.
#include "mpi_jobs.hpp"
#include <mpi.h>
#include <cstring>
#include <string>

namespace {

using rocking::app::MpiWorld;

MpiWorld start() {
  MpiWorld w;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &w.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &w.size);
  w.active = true;
  return w;
}

void finish() { MPI_Finalize(); }

// Every rank packs its rows as (index, length, bytes) into one buffer; rank 0
// gathers the buffers and unpacks them.
std::vector<std::pair<long, std::string>> gather(const MpiWorld& w,
                                                 const std::vector<std::pair<long, std::string>>& mine) {
  std::string packed;
  for (const auto& [index, text] : mine) {
    const long header[2] = {index, static_cast<long>(text.size())};
    packed.append(reinterpret_cast<const char*>(header), sizeof header);
    packed += text;
  }
  int length = static_cast<int>(packed.size());
  std::vector<int> lengths(static_cast<std::size_t>(w.size)), offsets(static_cast<std::size_t>(w.size));
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::string all;
  if (w.rank == 0) {
    int total = 0;
    for (int r = 0; r < w.size; ++r) {
      offsets[static_cast<std::size_t>(r)] = total;
      total += lengths[static_cast<std::size_t>(r)];
    }
    all.resize(static_cast<std::size_t>(total));
  }
  MPI_Gatherv(packed.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0,
              MPI_COMM_WORLD);
  std::vector<std::pair<long, std::string>> out;
  for (std::size_t at = 0; w.rank == 0 && at < all.size();) {
    long header[2];
    std::memcpy(header, all.data() + at, sizeof header);
    at += sizeof header;
    out.emplace_back(header[0], all.substr(at, static_cast<std::size_t>(header[1])));
    at += static_cast<std::size_t>(header[1]);
  }
  return out;
}

const rocking::app::MpiFunctions functions{start, finish, gather};

}  // namespace

extern "C" __attribute__((visibility("default"))) const rocking::app::MpiFunctions* rocking_mpi_interface() {
  return &functions;
}
