// Helpers shared by the accuracy and stability benchmarks: run a scene in-process (scene file ->
// build_model -> solve) in a scratch folder and time it, read the numbers back from results.h5,
// find Pareto-optimal points, and run the plotting script.
#pragma once
#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/model/model.hpp"
#include "postproc/validation.hpp"
#include "solver/solver.hpp"

namespace talus::bench {

// The scene files of the source tree this benchmark was built from.
std::string scene_path(const std::string& name);  // "spring_mass" -> .../geometries/spring_mass.toml

// A fresh folder under the system's temporary directory, removed with its contents on destruction.
class Scratch {
 public:
  explicit Scratch(const std::string& tag);
  ~Scratch();
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// The same particles_per_cell for every body of a scene, as --set overrides.
std::vector<std::string> particles_per_cell_overrides(const std::string& scene_file, int particles_per_cell);

struct TimedRun {
  solver::SolveSummary summary;
  std::size_t elements = 0;
  double mesh_seconds = 0;  // load_scene + build_model
  double wall_seconds = 0;  // mesh_seconds + solve (incl. writing results.h5)
};

// load_scene(scene_file, overrides) -> preproc::build_model -> solver::solve into out_dir.
// Throws what they throw (talus::Error).
TimedRun run_scene(const std::string& scene_file, const std::vector<std::string>& overrides,
                   const std::string& out_dir, int threads);

// Solves an already built model into out_dir, timing it (elements and mesh_seconds left 0).
TimedRun run_model(const Model& model, const std::string& out_dir, int threads);

// Mass-weighted centre of each frame of the named body's particles, read from results.h5
// (as talus post computes it). `initial` receives the centre at the model's initial positions.
struct BodyTrack {
  std::vector<double> time;
  std::vector<Eigen::Vector2d> centre;
  Eigen::Vector2d initial{0, 0};
};
BodyTrack track_body(const std::string& results_file, const std::string& body);

// talus post's checks against the analytical solutions (postproc/validation.hpp) of the named
// body of a results file: the spring-mass settlement against A (1 - cos(omega t)), and the
// box's slide along an incline of angle_deg against 0.5 g (sin a - mu cos a) t^2.
postproc::SpringMassCheck spring_mass_check(const std::string& results_file, const std::string& body,
                                            double amplitude, double omega);
postproc::BoxInclineCheck box_incline_check(const std::string& results_file, const std::string& body,
                                            double angle_deg, const Eigen::Vector2d& gravity, double friction,
                                            double gravity_ramp);

// A number stored under "key": in a JSON text, searched after `after` (a key that opens an
// enclosing object, or empty). Empty when absent or null.
std::optional<double> json_number(const std::string& json, const std::string& key, const std::string& after = "");

// For each point (cost, error): true when no other point is at least as good in both and
// better in one.
std::vector<bool> pareto_front(const std::vector<double>& cost, const std::vector<double>& error);

// /usr/bin/python3 bench/plot_benchmarks.py ARGS; returns its exit status.
int run_plot_script(const std::vector<std::string>& args);

// "%.*f" and "%.*g" of a number.
std::string fixed(double value, int digits);
std::string general(double value, int digits = 3);

// CPU model, core count, kernel and the current load average, for the reports.
std::string machine_line();

// Seconds since an arbitrary start (steady clock).
double now_seconds();

}  // namespace talus::bench
