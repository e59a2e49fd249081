// What the study commands hand librocking_mpi.so (mpi_plugin.cpp), the MPI
// side they open only under mpirun (plugins.hpp): plain C types, so that no
// object of either side's C++ library crosses (the program carries its own
// C++ runtime, the plugin uses the shared one). The program packs and
// unpacks its rows (mpi_jobs.cpp); the plugin moves bytes.
#pragma once
#include <cstddef>

extern "C" {

struct RockingMpiWorld {
  int rank;
  int size;
};

// Receives the bytes gathered on rank 0; they are valid only during the call.
using RockingMpiReceive = void (*)(void* context, const char* bytes, std::size_t size);

struct RockingMpiFunctions {
  // MPI_Init_thread and this process's place in MPI_COMM_WORLD.
  RockingMpiWorld (*start)();
  void (*finish)();
  // Every rank's `size` bytes, concatenated in rank order on rank 0, which
  // gets them through receive(context, ...) once; the other ranks' receive is
  // never called. Returns 0, or -1 when the bytes exceed what MPI can count.
  int (*gather)(const char* mine, std::size_t size, void* context, RockingMpiReceive receive);
};

}
