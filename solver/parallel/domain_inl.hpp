// on_root (domain.hpp).
#pragma once
#include <string>

#include "common/error.hpp"

namespace talus::solver {

template <class Work>
void on_root(Work&& work) {
  if (!mpi::distributed()) {
    work();
    return;
  }
  std::string failure;
  if (mpi::rank() == 0) {
    try {
      work();
    } catch (const Error& error) {
      failure = error.what();
      if (failure.empty()) failure = "error on rank 0";
    }
  }
  mpi::broadcast(failure, 0);
  if (!failure.empty()) throw SharedError(failure);
}

}  // namespace talus::solver
