#include "mpi_jobs.hpp"
#include "plugins.hpp"
#include <cstdlib>
#include <string>
import rocking;

namespace rocking::app {

namespace {
bool launched_by_mpirun() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(var) != nullptr) return true;
  return false;
}

// librocking_mpi.so (plugins.hpp), opened once; it stays loaded until the
// process ends (OpenMPI must not be unloaded after MPI_Finalize).
const MpiFunctions& mpi_functions() {
  static const MpiFunctions* functions = [] {
    auto* entry = reinterpret_cast<const MpiFunctions* (*)()>(
        plugin_symbol("librocking_mpi.so", "rocking_mpi_interface", "started by mpirun, but MPI"));
    return entry();
  }();
  return *functions;
}
}  // namespace

MpiSession::MpiSession() {
  if (launched_by_mpirun()) world_ = mpi_functions().start();
}

MpiSession::~MpiSession() {
  if (world_.active) mpi_functions().finish();
}

MpiRows gather_rows(const MpiWorld& w, const MpiRows& mine) {
  if (!w.active || w.size == 1) return mine;
  return mpi_functions().gather(w, mine);
}

}  // namespace rocking::app
