#include "mpi_jobs.hpp"
#include "mpi_plugin.hpp"
#include "plugins.hpp"
#include <cstdlib>
#include <cstring>
#include <string>
import rocking.errors;

namespace rocking::app {

namespace {
bool launched_by_mpirun() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(var) != nullptr) return true;
  return false;
}

// librocking_mpi.so (plugins.hpp), opened once; it stays loaded until the
// process ends (OpenMPI must not be unloaded after MPI_Finalize).
const RockingMpiFunctions& mpi_functions() {
  static const RockingMpiFunctions* functions = [] {
    auto* entry = reinterpret_cast<const RockingMpiFunctions* (*)()>(
        plugin_symbol("librocking_mpi.so", "rocking_mpi_interface", "started by mpirun, but MPI"));
    return entry();
  }();
  return *functions;
}

// Rows travel as (index, length) headers, each followed by its text.
std::string pack(const MpiRows& rows) {
  std::string packed;
  for (const auto& [index, text] : rows) {
    const long header[2] = {index, static_cast<long>(text.size())};
    packed.append(reinterpret_cast<const char*>(header), sizeof header);
    packed += text;
  }
  return packed;
}

void unpack(void* context, const char* bytes, std::size_t size) {
  auto& rows = *static_cast<MpiRows*>(context);
  for (std::size_t at = 0; at + 2 * sizeof(long) <= size;) {
    long header[2];
    std::memcpy(header, bytes + at, sizeof header);
    at += sizeof header;
    rows.emplace_back(header[0], std::string(bytes + at, static_cast<std::size_t>(header[1])));
    at += static_cast<std::size_t>(header[1]);
  }
}
}  // namespace

MpiSession::MpiSession() {
  if (!launched_by_mpirun()) return;
  const RockingMpiWorld w = mpi_functions().start();
  world_ = {.rank = w.rank, .size = w.size, .active = true};
}

MpiSession::~MpiSession() {
  if (world_.active) mpi_functions().finish();
}

MpiRows gather_rows(const MpiWorld& w, const MpiRows& mine) {
  if (!w.active || w.size == 1) return mine;
  const std::string packed = pack(mine);
  MpiRows all;
  if (mpi_functions().gather(packed.data(), packed.size(), &all, unpack) != 0)
    throw RunError("the study's rows exceed what one MPI message holds (2 GB): split the study");
  return all;
}

}  // namespace rocking::app
