// Shared objects the program opens only when a command needs them, so that
// its start-up loads none of their libraries: librocking_mpi.so (OpenMPI,
// under mpirun) and librocking_serve.so (cpp-httplib and OpenSSL, for
// `rocking serve`). Each sits beside the program and exposes one C symbol.
#pragma once
#include <string>

namespace rocking::app {

// The address of `symbol` in `object` (a file name beside the program),
// opened once and kept open until the process ends. Throws RunError saying
// what could not be loaded, for `why` ("started by mpirun, but MPI").
void* plugin_symbol(const std::string& object, const char* symbol, const std::string& why);

}  // namespace rocking::app
