// What the core's MPI tests share (run by ctest under mpirun; main() in
// TestPartition.cxx).
#pragma once

#include <mpi.h>

#include <utility>

/// This process's rank and the number of processes (MPI_COMM_WORLD).
inline std::pair<int, int> RankAndSize()
{
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return { rank, size };
}
