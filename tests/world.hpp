// This process's rank in PETSC_COMM_WORLD and their number, for the MPI tests.
#pragma once

#include <petscsys.h>

inline int world_rank() {
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  return rank;
}

inline int world_size() {
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  return size;
}
