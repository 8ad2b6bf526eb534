// The stability benchmark's stress cases: stiffness contrast, very soft material, high-velocity
// impact, grid crossing and a long run (1e5 steps).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "common/h5.hpp"
#include "postproc/output.hpp"
#include "stability.hpp"

namespace talus::bench::stability {

std::string stress_cases(const Options& options, std::vector<StressRow>& rows) {
  const Eigen::Vector2d downhill(std::cos(M_PI / 6), -std::sin(M_PI / 6));
  auto record = [&](StressRow row) {
    std::fprintf(stderr, " %s (%.1f s): %s\n", row.outcome.kind.c_str(), row.outcome.wall_seconds, row.figure.c_str());
    rows.push_back(row);
  };
  auto start = [](const char* name) {
    std::fprintf(stderr, "stress: %s ...", name);
    std::fflush(stderr);
  };

  {  // 1. Stiffness contrast 1e4 between bonded bodies: the spring-mass block 1e4 x stiffer than the spring.
    start("stiffness contrast");
    Model model = build_scene("spring_mass", {"materials.block.youngs_modulus=5e9"});
    bench::Scratch scratch("stability-stress");
    StressRow row{"stiffness contrast 1e4",
                  "spring-mass scene with the block's E raised to 5e9 Pa (1e4 x the spring's 5e5 Pa), bonded: the "
                  "error against y(t) = 1e-3 (1 - cos 100t) over two periods",
                  "", run_and_scan(model, scratch.path().string(), options.threads)};
    if (row.outcome.kind == "completed")
      row.figure = "max |y - y_exact| / A = " + fixed(100 * spring_error(scratch.file("results.h5")), 2) + "% in " +
                   std::to_string(row.outcome.steps) + " steps";
    record(row);
  }
  {  // 2. Very soft material under gravity: the box at E = 1e4 Pa sliding on the incline.
    start("soft material");
    Model model = build_scene("box_incline", {});
    const int box = body_index(model, "box");
    own_material(model, box, [](Material& m) { m.youngs_modulus = 1e4; });
    bench::Scratch scratch("stability-stress");
    StressRow row{"very soft material",
                  "box scene with the box at E = 1e4 Pa (static strain rho g H / E = 0.2): sliding error at 1 s "
                  "against 0.5 g (sin 30 - 0.3 cos 30) t^2, and the box's lowest-to-highest height change",
                  "", run_and_scan(model, scratch.path().string(), options.threads)};
    if (row.outcome.kind == "completed")
      row.figure = "relative error at 1 s " + fixed(100 * box_error(scratch.file("results.h5"), 0.3), 2) + "% in " +
                   std::to_string(row.outcome.steps) + " steps";
    record(row);
  }
  {  // 3. High-velocity impact: the box thrown at 20 m/s down the slope into the wall.
    start("impact");
    Model model = build_scene("box_incline", {"run.end_time=0.3", "run.output_interval=0.01"});
    const double speed = 20;
    set_body_velocity(model, body_index(model, "box"), speed * downhill);
    bench::Scratch scratch("stability-stress");
    StressRow row{"high-velocity impact",
                  "box scene, box launched at 20 m/s down the slope (about 0.25 x its P-wave speed) into the wall "
                  "at the lower end: total energy afterwards against before (contact and impact may only dissipate)",
                  "", run_and_scan(model, scratch.path().string(), options.threads)};
    if (row.outcome.scan.exists) {
      const EnergyRecord e = read_energy(scratch.file("results.h5"));
      const double initial = e.total_particle.front();
      const double largest_gain = *std::max_element(e.total_particle.begin(), e.total_particle.end()) - initial;
      const auto kinetic = h5::read_doubles(h5::File::open_read(scratch.file("results.h5")),
                                            "history/particle_kinetic_energy");
      row.figure = "initial kinetic energy " + general(kinetic.front()) + " J/m; largest rise of the total energy " +
                   general(largest_gain) + " J/m (" + fixed(100 * largest_gain / kinetic.front(), 2) +
                   "% of it); total energy at the end " +
                   fixed(100 * (e.total_particle.back() - initial) / kinetic.front(), 1) + "% of it";
    }
    record(row);
  }
  {  // 4. Grid crossing: the box sliding frictionless across 36 elements under its own weight.
    start("grid crossing");
    const double duration = 0.6, acceleration = 10 * 0.5;  // g sin 30
    Model model = build_scene("box_incline", {"contact.friction=0.0", "run.end_time=" + std::to_string(duration),
                                        "run.output_interval=0.02"});
    bench::Scratch scratch("stability-stress");
    StressRow row{"grid crossing",
                  "box scene without friction: the box slides 0.5 (g sin 30) t^2 = 0.9 m in 0.6 s, across 36 element "
                  "widths of 0.025 m, carrying its self-weight stress from element to element (linear elements: "
                  "a particle's stress jumps as it crosses). Figures: the slide against the exact one, and the "
                  "ripple of the strain energy over the last half (its std over its mean)",
                  "", run_and_scan(model, scratch.path().string(), options.threads)};
    if (row.outcome.kind == "completed") {
      const bench::BodyTrack track = bench::track_body(scratch.file("results.h5"), "box");
      const double travelled = (track.centre.back() - track.initial).dot(downhill);
      const double expected = 0.5 * acceleration * track.time.back() * track.time.back();
      const EnergyRecord e = read_energy(scratch.file("results.h5"));
      double sum = 0, sum2 = 0;
      int count = 0;
      for (std::size_t k = 0; k < e.time.size(); ++k)
        if (e.time[k] >= 0.5 * duration) sum += e.strain[k], sum2 += e.strain[k] * e.strain[k], ++count;
      const double mean = sum / count, deviation = std::sqrt(std::max(0.0, sum2 / count - mean * mean));
      row.figure = "slid " + fixed(travelled, 4) + " m against " + fixed(expected, 4) + " m (" +
                   fixed(100 * (travelled - expected) / expected, 2) + "%); strain-energy ripple " +
                   fixed(100 * deviation / mean, 1) + "% of its mean";
    }
    record(row);
  }
  {  // 5. A long run: 1e5 steps of the spring-mass scene, total energy drift.
    start("1e5 steps");
    const long steps = options.quick ? 20000 : 100000;
    Model model = build_scene("spring_mass", {"run.end_time=100.0", "run.output_interval=0.05"});
    model.run.max_steps = steps;
    bench::Scratch scratch("stability-stress");
    StressRow row{"long run",
                  "spring-mass scene for " + std::to_string(steps) +
                      " steps: drift of the total energy (kinetic + potential + strain) from its start, over the "
                      "largest strain energy (the energy the oscillation exchanges)",
                  "", run_and_scan(model, scratch.path().string(), options.threads)};
    if (row.outcome.kind == "completed") {
      const EnergyRecord e = read_energy(scratch.file("results.h5"));
      const double swing = *std::max_element(e.strain.begin(), e.strain.end());
      std::vector<double> drift_grid, drift_particle;
      double worst_grid = 0, worst_particle = 0;
      for (std::size_t k = 0; k < e.time.size(); ++k) {
        drift_grid.push_back((e.total_grid[k] - e.total_grid.front()) / swing);
        drift_particle.push_back((e.total_particle[k] - e.total_particle.front()) / swing);
        worst_grid = std::max(worst_grid, std::abs(drift_grid.back()));
        worst_particle = std::max(worst_particle, std::abs(drift_particle.back()));
      }
      postproc::write_csv((std::filesystem::path(options.out) / "stability_energy.csv").string(),
                          {"time_s", "total_particle_J", "total_grid_J", "drift_particle", "drift_grid"},
                          {e.time, e.total_particle, e.total_grid, drift_particle, drift_grid});
      row.figure = std::to_string(row.outcome.steps) + " steps to t = " + fixed(e.time.back(), 3) +
                   " s; with the particle kinetic energy the total ends " + fixed(100 * drift_particle.back(), 2) +
                   "% (largest " + fixed(100 * worst_particle, 2) + "%) of the swing from its start; with the grid " +
                   "kinetic energy " + fixed(100 * drift_grid.back(), 2) + "% (largest " + fixed(100 * worst_grid, 2) + "%)";
    }
    record(row);
  }

  std::vector<std::vector<std::string>> table;
  std::ostringstream md;
  md << "## Stress cases\n\n| case | what it measures | outcome | figure |\n|---|---|---|---|\n";
  for (const StressRow& r : rows) {
    table.push_back({r.name, r.outcome.kind, std::to_string(r.outcome.steps), fixed(r.outcome.wall_seconds, 2),
                     std::to_string(r.outcome.scan.nonfinite), r.outcome.consistent() ? "1" : "0", r.figure,
                     r.outcome.message, r.measures});
    md << "| " << r.name << " | " << r.measures << " | " << r.outcome.kind
       << (r.outcome.message.empty() ? "" : ": " + short_message(r.outcome.message))
       << (r.outcome.consistent() ? "" : " (**inconsistent results file**)") << " | " << r.figure << " |\n";
  }
  write_table((std::filesystem::path(options.out) / "stability_stress.csv").string(),
              {"case", "outcome", "steps", "wall_seconds", "nonfinite_values", "consistent", "figure", "message",
               "measures"},
              table);
  return md.str() + "\n";
}

}  // namespace talus::bench::stability
