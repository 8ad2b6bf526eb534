// The parallel layer. Threads (threads.hpp): the thread contract (every region runs exactly the
// simulation's thread count; sums in an order fixed by it), the automatic thread count, pinning
// and owner-first chunks. MPI (mpi.hpp): the few collectives the solver uses, the identity on
// one rank; only mpi.cpp names MPI. Domains (domain.hpp): one model split among ranks by METIS,
// particles migrating with every registered field, and the halo exchanges of the step's nodal
// sums (halo.cpp).
#pragma once
#include "solver/parallel/domain.hpp"
#include "solver/parallel/mpi.hpp"
#include "solver/parallel/threads.hpp"
