#include "mpi_jobs.hpp"
#include <dlfcn.h>
#include <fmt/format.h>
#include <cstdlib>
#include <filesystem>
#include <string>
import rocking;

namespace rocking::app {

namespace {
bool launched_by_mpirun() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(var) != nullptr) return true;
  return false;
}

// librocking_mpi.so from the program's own folder, opened once; it stays
// loaded until the process ends (OpenMPI must not be unloaded after
// MPI_Finalize).
const MpiFunctions& mpi_functions() {
  static const MpiFunctions* functions = [] {
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    const std::string object = (self.parent_path() / "librocking_mpi.so").string();
    void* handle = dlopen(object.c_str(), RTLD_NOW | RTLD_GLOBAL);
    if (handle == nullptr)
      throw RunError(fmt::format("started by mpirun, but MPI cannot be loaded: {}", dlerror()));
    auto* entry = reinterpret_cast<const MpiFunctions* (*)()>(dlsym(handle, "rocking_mpi_interface"));
    if (entry == nullptr) throw RunError(fmt::format("{}: no rocking_mpi_interface: {}", object, dlerror()));
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
