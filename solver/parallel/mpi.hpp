// The MPI runtime of a distributed solve (docs/scaling.md). One binary serves both ways: built
// with MPI (TALUS_WITH_MPI, when OpenMPI and METIS are installed) it starts MPI only when it was
// launched by mpirun or mpiexec; started any other way, or built without MPI, it is one rank and
// every call below is the identity. The solver's decomposition (domain.hpp) is written on these
// few calls only, so that no other file names MPI.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace talus::solver::mpi {

// Built with MPI.
bool built_with_mpi();
// This process was started by mpirun/mpiexec (its environment has the launcher's rank variables).
bool launched_by_mpirun();
// Starts MPI when launched by mpirun and built with MPI; otherwise nothing. Call once, first in
// main (before any thread is started).
void init(int* argc, char*** argv);
// Ends MPI if init started it (at exit; safe to call more than once).
void finalize();
// This process's rank and the number of ranks: 0 and 1 without MPI.
int rank();
int size();
inline bool distributed() { return size() > 1; }
// Stops every rank at once (MPI_Abort) with `code`; exit(code) with one rank.
[[noreturn]] void abort_all(int code);

// Built with the parallel HDF5 (TALUS_PARALLEL_HDF5): every rank can write its rows of a frame
// into the one results.h5 (results_parallel.hpp).
bool parallel_hdf5();
// Sets the HDF5 file access list `fapl` to open a file on every rank of the run at once
// (MPI-IO on all ranks) and the transfer list `dxpl` to collective writes. Both are HDF5
// identifiers (hid_t). Returns false, setting nothing, without the parallel HDF5.
bool set_parallel_io(std::int64_t fapl, std::int64_t dxpl);

// ---- Collectives (every rank calls them, in the same order) ----------------------------------

// values[k] <- the sum over the ranks of values[k], added in rank order: the same bits on every
// rank, for a given rank count.
void sum_in_rank_order(double* values, std::size_t count);
double sum_in_rank_order(double value);
long sum(long value);
double max(double value);
long max(long value);
long min(long value);
// True on every rank when `flag` is true on any.
bool any(bool flag);
// The first rank (lowest) with `flag` true, -1 when none.
int first_rank_with(bool flag);
// Rank `root`'s bytes on every rank.
void broadcast(std::string& bytes, int root);
void broadcast(std::vector<double>& values, int root);
// Every rank's bytes on rank 0, in rank order (empty on the others).
std::vector<std::string> gather(const std::string& bytes);
// Sends send[r] to rank r (send.size() == size()) and returns what each rank sent here.
std::vector<std::string> all_to_all(const std::vector<std::string>& send);

// Point to point with a list of neighbours: send[k] goes to ranks[k], and receive[k] (sized by
// the caller, as the neighbour sends it) comes from ranks[k].
void exchange(const std::vector<int>& ranks, const std::vector<std::vector<double>>& send,
              std::vector<std::vector<double>>& receive);

}  // namespace talus::solver::mpi
