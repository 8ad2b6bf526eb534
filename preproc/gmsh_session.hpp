// gmsh is one global library state: a GmshSession initializes it on entry and finalizes it on
// every way out. gmsh also sets OpenMP's thread count for the whole process (to its
// General.NumThreads, 1 by default, when it starts and again when it meshes); the session puts
// back the count it found, or a solve that follows meshing in the same process (`talus run`,
// `talus fos`) would run on one core.
#pragma once
#include <gmsh.h>
#include <omp.h>

#include <string>
#include <vector>

namespace talus::preproc {

class GmshSession {
 public:
  GmshSession() : openmp_threads_(omp_get_max_threads()) {
    // No gmshrc or gmsh-options: the same .geo meshes the same on every machine.
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::logger::start();
  }
  ~GmshSession() {
    gmsh::logger::stop();
    gmsh::finalize();
    omp_set_num_threads(openmp_threads_);
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

  // The errors gmsh logged, one per line (gmsh sometimes logs an error and carries on).
  static std::string logged_errors() {
    std::vector<std::string> log;
    gmsh::logger::get(log);
    std::string errors;
    for (const auto& line : log)
      if (line.rfind("Error", 0) == 0) errors += (errors.empty() ? "" : "\n") + line;
    return errors;
  }

 private:
  int openmp_threads_;
};

}  // namespace talus::preproc
