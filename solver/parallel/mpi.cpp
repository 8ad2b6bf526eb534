#include "solver/parallel/mpi.hpp"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#ifdef TALUS_WITH_MPI
// The C API only: OpenMPI would pull in its deprecated C++ bindings otherwise.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif
#ifdef TALUS_PARALLEL_HDF5
#include <hdf5.h>

#include <type_traits>
static_assert(std::is_same_v<hid_t, std::int64_t>, "mpi.hpp passes HDF5 identifiers as int64_t");
#endif

namespace talus::solver::mpi {

bool built_with_mpi() {
#ifdef TALUS_WITH_MPI
  return true;
#else
  return false;
#endif
}

bool launched_by_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
    if (std::getenv(name)) return true;
  return false;
}

bool parallel_hdf5() {
#ifdef TALUS_PARALLEL_HDF5
  return true;
#else
  return false;
#endif
}

bool set_parallel_io(std::int64_t fapl, std::int64_t dxpl) {
#ifdef TALUS_PARALLEL_HDF5
  return H5Pset_fapl_mpio(fapl, MPI_COMM_WORLD, MPI_INFO_NULL) >= 0 && H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE) >= 0;
#else
  return false;
#endif
}

#ifdef TALUS_WITH_MPI

namespace {

bool started = false;
int my_rank = 0, ranks = 1;

// Counts and displacements in MPI's int, refusing what does not fit.
int as_count(std::size_t n) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::length_error("MPI message of " + std::to_string(n) + " bytes: more than 2 GB in one call");
  return static_cast<int>(n);
}

}  // namespace

void init(int* argc, char*** argv) {
  if (started || !launched_by_mpirun()) return;
  int provided = 0;
  // Only the master thread calls MPI (outside the OpenMP regions).
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  started = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &my_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  std::atexit(finalize);
}

void finalize() {
  if (!started) return;
  int done = 0;
  MPI_Finalized(&done);
  if (!done) MPI_Finalize();
}

int rank() { return my_rank; }
int size() { return ranks; }

void abort_all(int code) {
  if (started && ranks > 1) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

void sum_in_rank_order(double* values, std::size_t count) {
  if (ranks == 1 || count == 0) return;
  std::vector<double> all(count * static_cast<std::size_t>(ranks));
  MPI_Allgather(values, as_count(count), MPI_DOUBLE, all.data(), as_count(count), MPI_DOUBLE, MPI_COMM_WORLD);
  for (std::size_t k = 0; k < count; ++k) {
    double sum = 0;
    for (int r = 0; r < ranks; ++r) sum += all[static_cast<std::size_t>(r) * count + k];
    values[k] = sum;
  }
}

double sum_in_rank_order(double value) {
  sum_in_rank_order(&value, 1);
  return value;
}

long sum(long value) {
  if (ranks == 1) return value;
  long total = 0;
  MPI_Allreduce(&value, &total, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  return total;
}

double max(double value) {
  if (ranks == 1) return value;
  double out = 0;
  MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return out;
}

long max(long value) {
  if (ranks == 1) return value;
  long out = 0;
  MPI_Allreduce(&value, &out, 1, MPI_LONG, MPI_MAX, MPI_COMM_WORLD);
  return out;
}

long min(long value) {
  if (ranks == 1) return value;
  long out = 0;
  MPI_Allreduce(&value, &out, 1, MPI_LONG, MPI_MIN, MPI_COMM_WORLD);
  return out;
}

bool any(bool flag) { return max(static_cast<long>(flag)) > 0; }

int first_rank_with(bool flag) {
  const long first = min(flag ? static_cast<long>(my_rank) : std::numeric_limits<long>::max());
  return first == std::numeric_limits<long>::max() ? -1 : static_cast<int>(first);
}

void broadcast(std::string& bytes, int root) {
  if (ranks == 1) return;
  long n = static_cast<long>(bytes.size());
  MPI_Bcast(&n, 1, MPI_LONG, root, MPI_COMM_WORLD);
  bytes.resize(static_cast<std::size_t>(n));
  MPI_Bcast(bytes.data(), as_count(bytes.size()), MPI_CHAR, root, MPI_COMM_WORLD);
}

void broadcast(std::vector<double>& values, int root) {
  if (ranks == 1) return;
  long n = static_cast<long>(values.size());
  MPI_Bcast(&n, 1, MPI_LONG, root, MPI_COMM_WORLD);
  values.resize(static_cast<std::size_t>(n));
  MPI_Bcast(values.data(), as_count(values.size()), MPI_DOUBLE, root, MPI_COMM_WORLD);
}

std::vector<std::string> gather(const std::string& bytes) {
  if (ranks == 1) return {bytes};
  const int mine = as_count(bytes.size());
  std::vector<int> counts(static_cast<std::size_t>(ranks), 0), offsets(static_cast<std::size_t>(ranks), 0);
  MPI_Gather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::string all;
  if (my_rank == 0) {
    std::size_t total = 0;
    for (int r = 0; r < ranks; ++r) {
      offsets[r] = as_count(total);
      total += static_cast<std::size_t>(counts[r]);
    }
    all.resize(total);
    as_count(total);
  }
  MPI_Gatherv(bytes.data(), mine, MPI_CHAR, all.data(), counts.data(), offsets.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
  std::vector<std::string> out;
  if (my_rank == 0)
    for (int r = 0; r < ranks; ++r) out.emplace_back(all, static_cast<std::size_t>(offsets[r]), counts[r]);
  return out;
}

std::vector<std::string> all_to_all(const std::vector<std::string>& send) {
  if (ranks == 1) return {send.at(0)};
  const std::size_t n = static_cast<std::size_t>(ranks);
  std::vector<int> send_counts(n), receive_counts(n), send_offsets(n), receive_offsets(n);
  std::string out_bytes;
  std::size_t total = 0;
  for (std::size_t r = 0; r < n; ++r) {
    send_counts[r] = as_count(send[r].size());
    send_offsets[r] = as_count(total);
    total += send[r].size();
  }
  out_bytes.reserve(total);
  for (const auto& part : send) out_bytes += part;
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  total = 0;
  for (std::size_t r = 0; r < n; ++r) {
    receive_offsets[r] = as_count(total);
    total += static_cast<std::size_t>(receive_counts[r]);
  }
  std::string in_bytes(total, '\0');
  MPI_Alltoallv(out_bytes.data(), send_counts.data(), send_offsets.data(), MPI_CHAR, in_bytes.data(),
                receive_counts.data(), receive_offsets.data(), MPI_CHAR, MPI_COMM_WORLD);
  std::vector<std::string> received;
  for (std::size_t r = 0; r < n; ++r)
    received.emplace_back(in_bytes, static_cast<std::size_t>(receive_offsets[r]), receive_counts[r]);
  return received;
}

void exchange(const std::vector<int>& neighbours, const std::vector<std::vector<double>>& send,
              std::vector<std::vector<double>>& receive) {
  if (neighbours.empty()) return;
  std::vector<MPI_Request> requests(2 * neighbours.size());
  for (std::size_t k = 0; k < neighbours.size(); ++k)
    MPI_Irecv(receive[k].data(), as_count(receive[k].size()), MPI_DOUBLE, neighbours[k], 7, MPI_COMM_WORLD,
              &requests[k]);
  for (std::size_t k = 0; k < neighbours.size(); ++k)
    MPI_Isend(send[k].data(), as_count(send[k].size()), MPI_DOUBLE, neighbours[k], 7, MPI_COMM_WORLD,
              &requests[neighbours.size() + k]);
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
}

#else  // one rank: every collective is the identity

void init(int*, char***) {}
void finalize() {}
int rank() { return 0; }
int size() { return 1; }
void abort_all(int code) { std::exit(code); }
void sum_in_rank_order(double*, std::size_t) {}
double sum_in_rank_order(double value) { return value; }
long sum(long value) { return value; }
double max(double value) { return value; }
long max(long value) { return value; }
long min(long value) { return value; }
bool any(bool flag) { return flag; }
int first_rank_with(bool flag) { return flag ? 0 : -1; }
void broadcast(std::string&, int) {}
void broadcast(std::vector<double>&, int) {}
std::vector<std::string> gather(const std::string& bytes) { return {bytes}; }
std::vector<std::string> all_to_all(const std::vector<std::string>& send) { return {send.at(0)}; }
void exchange(const std::vector<int>&, const std::vector<std::vector<double>>&, std::vector<std::vector<double>>&) {}

#endif

}  // namespace talus::solver::mpi
