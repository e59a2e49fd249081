#include "mpi_jobs.hpp"
#include <mpi.h>
#include <cstdlib>
#include <cstring>
#include <string>

namespace rocking::app {

namespace {
bool launched_by_mpirun() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(var) != nullptr) return true;
  return false;
}
}  // namespace

MpiSession::MpiSession() {
  if (!launched_by_mpirun()) return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &world_.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &world_.size);
  world_.active = true;
}

MpiSession::~MpiSession() {
  if (world_.active) MPI_Finalize();
}

std::vector<std::pair<long, std::string>> gather_rows(const MpiWorld& w,
                                                      const std::vector<std::pair<long, std::string>>& mine) {
  if (!w.active || w.size == 1) return mine;
  // Pack: index, length, bytes ... as one char buffer per rank.
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

}  // namespace rocking::app
