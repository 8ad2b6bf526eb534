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

  // The first error gmsh logged, and how many more it logged (gmsh sometimes logs an error and
  // carries on, or logs the same one for every curve); empty when none.
  static std::string logged_errors() {
    std::vector<std::string> log;
    gmsh::logger::get(log);
    std::string first;
    int more = 0;
    for (const auto& line : log)
      if (line.rfind("Error", 0) == 0) {
        if (first.empty()) first = line;
        else ++more;
      }
    if (more > 0) first += " (and " + std::to_string(more) + " more errors)";
    return first;
  }

  // gmsh::model::mesh::generate, with gmsh's errors logged rather than thrown: gmsh meshes the
  // curves and surfaces in OpenMP regions, out of which an exception cannot pass (std::terminate,
  // SIGABRT). The caller reads the errors with logged_errors().
  static void generate(int dimension) {
    double abort_on_error = 2;
    gmsh::option::getNumber("General.AbortOnError", abort_on_error);
    gmsh::option::setNumber("General.AbortOnError", 1);  // log, and stop meshing
    try {
      gmsh::model::mesh::generate(dimension);
    } catch (...) {
      gmsh::option::setNumber("General.AbortOnError", abort_on_error);
      throw;
    }
    gmsh::option::setNumber("General.AbortOnError", abort_on_error);
  }

 private:
  int openmp_threads_;
};

}  // namespace talus::preproc
