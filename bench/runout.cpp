// Runout benchmark (docs/column.md, docs/transfer.md): each velocity transfer on the column
// collapse against Lube et al. (2005), on the aluminium rods' collapse against Nguyen et al.
// (2015), on the slope at several element sizes, on a freely vibrating elastic cantilever
// (energy lost per period), and, on request, on every shipped scene as it is. Every run is
// in-process.
//
//   talus_bench_runout                                 column, rods, slope, vibration; default transfers
//   talus_bench_runout --only column --aspect 0.5,1,3,6 --transfers xpic2
//   talus_bench_runout --only rods --transfers flip,apic --set run.shape_functions=bspline
//   talus_bench_runout --only slope --sizes 0.5,0.25,0.125
//   talus_bench_runout --only scenes --transfers apic --set run.shape_functions=cpdi
//
// Writes runout_column.csv, runout_slope.csv, runout_vibration.csv, runout_scenes.csv, runout.md
// and bench_runout_column.png (bench/plot_benchmarks.py) to --out (default out/bench).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>

#include "bench_support.hpp"
#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/scene/scene.hpp"
#include "postproc/output.hpp"
#include "postproc/postproc.hpp"
#include "solver/step/step.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

using bench::fixed;
using bench::general;

// A transfer as a name and its --set overrides: flip, pic_blend (0.05), xpicM, apic.
struct TransferChoice {
  std::string name;
  std::vector<std::string> overrides;
  Transfer transfer = Transfer::Flip;
  int order = 1;
};

// The overrides of one --transfers name (common/scene, transfer_overrides) and the transfer and
// XPIC order they set, for the vibration, which builds its model here.
TransferChoice transfer_choice(const std::string& name) {
  TransferChoice t{name, {}, Transfer::Flip, 1};
  try {
    t.overrides = transfer_overrides(name);
  } catch (const Error& error) {
    throw Error(std::string("--transfers: ") + error.what());
  }
  for (const std::string& o : t.overrides) {
    const std::string value = o.substr(o.find('=') + 1);
    if (o.rfind("run.transfer=", 0) == 0) t.transfer = *transfer_from_name(value);
    if (o.rfind("run.xpic_order=", 0) == 0) t.order = std::stoi(value);
  }
  return t;
}

struct Options {
  std::vector<std::string> parts = {"column", "rods", "slope", "vibration"};
  // apic needs B-splines (--set run.shape_functions=bspline --set mesh.pattern=grid) or CPDI
  // (--set run.shape_functions=cpdi).
  std::vector<std::string> transfers = {"flip", "pic_blend", "xpic2", "xpic5"};
  std::vector<double> aspect = {0.5, 3};
  std::vector<double> rods_aspect = {1, 2, 4};
  std::vector<double> sizes = {0.5, 0.25};
  std::vector<std::string> overrides;  // --set, for every column and slope run
  std::string out = "out/bench";
  int threads = 1;
  bool plots = true;
};

// A run's scene overrides: the transfer's, then the --set ones (which win).
std::vector<std::string> scene_overrides(const TransferChoice& t, const Options& options) {
  std::vector<std::string> overrides = t.overrides;
  overrides.insert(overrides.end(), options.overrides.begin(), options.overrides.end());
  return overrides;
}

// The column's length for aspect ratio a: the same column area, 0.02 m^2, at every a (0.2 m at
// a = 0.5, 0.058 m at a = 6), so that every run has about 7,500 particles (4 per 5 mm triangle).
double column_length(double a) { return std::sqrt(0.02 / a); }

std::vector<Eigen::Vector2d> last_frame(const std::string& results) {
  const h5::File file = h5::File::open_read(results);
  h5::Dims dims;
  const std::vector<double> flat = h5::read_doubles(file, "frames/position", &dims);
  const std::size_t n = dims[1], last = dims[0] - 1;
  std::vector<Eigen::Vector2d> x(n);
  for (std::size_t p = 0; p < n; ++p) x[p] = {flat[(last * n + p) * 2], flat[(last * n + p) * 2 + 1]};
  return x;
}

// talus post on a finished run in `scratch` (figures off): the text of its metrics.json.
std::string post_metrics(const bench::Scratch& scratch) {
  postproc::PostOptions post;
  post.figures = false;
  std::ostringstream log;
  postproc::run_post(scratch.file("results.h5"), scratch.path().string(), log, post);
  std::ifstream in(scratch.file("metrics.json"));
  std::stringstream json;
  json << in.rdbuf();
  return json.str();
}

// talus post's runout_distance_m (m) of a finished run in `scratch`, or nothing.
std::optional<double> post_runout(const bench::Scratch& scratch) {
  return bench::json_number(post_metrics(scratch), "runout_distance_m");
}

// Nguyen, Bui et al. (2015), "Failure mechanism of true 2D granular flows" (arXiv:1512.05180),
// collapses of aluminium rods: (d - d0)/d0 = 3.25 a^0.96 for 0.65 < a < 1.5, 3.80 a^0.73 above;
// no value below 0.65.
std::optional<double> rods_runout(double a) {
  if (a <= 0.65) return std::nullopt;
  return a < 1.5 ? 3.25 * std::pow(a, 0.96) : 3.80 * std::pow(a, 0.73);
}
// Their final height, h0/h = 1.42 a^(2/3) (h0 the column's height, h the deposit's); a column that
// does not lose height (h0/h = 1) has no value.
std::optional<double> rods_height(double a) {
  const double ratio = 1.42 * std::pow(a, 2.0 / 3.0);
  if (ratio <= 1) return std::nullopt;
  return ratio;
}
// Lube et al. (2005): the top of the deposit stays at H0 below a = 1.15 (h0/h = 1).
std::optional<double> lube_height(double a) {
  if (a < 1.15) return 1.0;
  return std::nullopt;
}

// A column-collapse scene and the laws it is compared with.
struct ColumnCase {
  std::string part;   // the --only name and the CSV's suffix
  std::string scene;  // geometries/<scene>.toml
  std::string title;
  std::string law_name;
  std::function<std::optional<double>(double)> runout_law, height_law;
};

std::string percent(double value, double reference) { return fixed(100 * (value / reference - 1), 1) + "%"; }

void run_column(const Options& options, const ColumnCase& c, const std::vector<double>& aspects,
                std::ostringstream& md) {
  std::vector<std::vector<std::string>> rows;
  md << "## " << c.title << " (geometries/" << c.scene << ".toml";
  for (const auto& o : options.overrides) md << ", " << o;
  md << ")\n\n"
     << "| transfer | a | L0 (m) | particles | steps | wall (s) | (L_inf - L0)/L0 | " << c.law_name
     << " | error | H0 / H_inf | " << c.law_name << " | error | detached | talus post | error | outcome |\n"
     << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  for (const auto& name : options.transfers) {
    const TransferChoice t = transfer_choice(name);
    for (double a : aspects) {
      const double L0 = column_length(a), H0 = a * L0;
      std::vector<std::string> overrides = scene_overrides(t, options);
      overrides.push_back("mesh.parameters.a=" + general(a, 6));
      overrides.push_back("mesh.parameters.L0=" + general(L0, 6));
      std::fprintf(stderr, "%s %s a = %g ...", c.part.c_str(), name.c_str(), a);
      bench::Scratch scratch(c.part);
      std::string outcome = "at rest", ratio = "", error = "", height = "", height_error = "", detached = "",
                  post = "", post_error = "";
      const auto law = c.runout_law(a);
      const auto height_law = c.height_law(a);
      bench::TimedRun run;
      try {
        run = bench::run_scene(bench::scene_path(c.scene), overrides, scratch.path().string(), options.threads);
        if (!run.summary.stopped_at_rest) outcome = "not at rest by end_time";
        const auto deposit = testing::column_deposit(last_frame(scratch.file("results.h5")), 0.005);
        const double r = (deposit.tip - L0) / L0;
        ratio = fixed(r, 3);
        if (law) error = percent(r, *law);
        height = fixed(H0 / deposit.height, 3);
        if (height_law) height_error = percent(H0 / deposit.height, *height_law);
        detached = std::to_string(deposit.detached);
        try {  // from the released face's foot, x = L0; a failed post leaves the run's own outcome
          if (const auto runout = post_runout(scratch)) {
            post = fixed(*runout / L0, 3);
            if (law) post_error = percent(*runout / L0, *law);
          }
        } catch (const Error& e) {
          post = std::string("failed: ") + e.what();
        }
      } catch (const Error& e) {
        outcome = e.what();
      }
      std::fprintf(stderr, " %s %s\n", ratio.c_str(), outcome.c_str());
      rows.push_back({name, general(a, 4), general(L0, 4), std::to_string(run.summary.particles),
                      std::to_string(run.summary.steps), fixed(run.wall_seconds, 1), ratio,
                      law ? fixed(*law, 3) : "", error, height, height_law ? fixed(*height_law, 3) : "",
                      height_error, detached, post, post_error, outcome});
      md << "| " << rows.back()[0];
      for (std::size_t k = 1; k < rows.back().size(); ++k) md << " | " << rows.back()[k];
      md << " |\n";
    }
  }
  std::ofstream csv((std::filesystem::path(options.out) / ("runout_" + c.part + ".csv")).string());
  csv << "transfer,aspect_ratio,L0_m,particles,steps,wall_s,runout_ratio,law,error,height_ratio,height_law,"
         "height_error,detached,post_runout_ratio,post_error,outcome\n";
  for (const auto& row : rows) {
    for (std::size_t k = 0; k < row.size(); ++k) csv << (k ? "," : "") << (k + 1 == row.size() ? "\"" + row[k] + "\"" : row[k]);
    csv << "\n";
  }
  md << "\nL_inf: the deposit's tip, bins 5 mm wide from the wall out to the first empty one (particles "
        "beyond are 'detached'). H_inf: the deposit's highest particle; H0 / H_inf is the final height's "
        "ratio (1 where the top stays at H0). talus post: runout_distance_m / L0 of metrics.json, whose tip "
        "leaves out a front thinner than its rule (docs/postproc.md).\n\n";
}

const ColumnCase kSandColumn{"column", "column_collapse", "Column collapse", "Lube",
                             [](double a) { return testing::lube_runout(a); }, lube_height};
const ColumnCase kRodsColumn{"rods", "rods_collapse", "Aluminium rods (measured parameters)", "Nguyen",
                            rods_runout, rods_height};

void run_slope(const Options& options, std::ostringstream& md) {
  md << "## Slope runout (geometries/slope.toml) against element size\n\n"
     << "| transfer | mesh size (m) | particles | steps | wall (s) | runout (m) |\n|---|---:|---:|---:|---:|---:|\n";
  std::ofstream csv((std::filesystem::path(options.out) / "runout_slope.csv").string());
  csv << "transfer,mesh_size_m,particles,steps,wall_s,runout_m\n";
  for (const auto& name : options.transfers) {
    const TransferChoice t = transfer_choice(name);
    for (double size : options.sizes) {
      std::vector<std::string> overrides = scene_overrides(t, options);
      overrides.push_back("mesh.size=" + general(size, 6));
      std::fprintf(stderr, "slope %s %g m ...", name.c_str(), size);
      bench::Scratch scratch("slope");
      std::string runout = "failed";
      bench::TimedRun run;
      try {
        run = bench::run_scene(bench::scene_path("slope"), overrides, scratch.path().string(), options.threads);
        if (const auto r = post_runout(scratch)) runout = fixed(*r, 2);
      } catch (const Error& e) {
        runout = std::string("failed: ") + e.what();
      }
      std::fprintf(stderr, " %s\n", runout.c_str());
      md << "| " << name << " | " << general(size, 4) << " | " << run.summary.particles << " | " << run.summary.steps
         << " | " << fixed(run.wall_seconds, 1) << " | " << runout << " |\n";
      csv << name << "," << size << "," << run.summary.particles << "," << run.summary.steps << ","
          << run.wall_seconds << ",\"" << runout << "\"\n";
    }
  }
  md << "\n";
}

// Every value of `key` in a JSON text (a number after "key":), the largest; nothing if none.
std::optional<double> largest_json_number(const std::string& json, const std::string& key) {
  std::optional<double> largest;
  const std::string quoted = "\"" + key + "\":";
  for (std::size_t at = json.find(quoted); at != std::string::npos; at = json.find(quoted, at + 1)) {
    char* end = nullptr;
    const char* begin = json.c_str() + at + quoted.size();
    const double value = std::strtod(begin, &end);
    if (end != begin) largest = largest ? std::max(*largest, std::abs(value)) : std::abs(value);
  }
  return largest;
}

// Every shipped scene (geometries/*.toml) as it is, with each transfer and the --set overrides:
// whether it runs to its end (or to rest) with every particle inside the mesh, its runout and,
// for the scenes with an exact answer, talus post's largest relative error against it.
void run_scenes(const Options& options, std::ostringstream& md) {
  std::vector<std::string> scenes;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(TALUS_SOURCE_DIR) / "geometries"))
    if (entry.path().extension() == ".toml") scenes.push_back(entry.path().stem().string());
  std::sort(scenes.begin(), scenes.end());
  md << "## Every shipped scene";
  for (const auto& o : options.overrides) md << (&o == &options.overrides.front() ? " (" : ", ") << o;
  md << (options.overrides.empty() ? "" : ")") << "\n\n"
     << "| scene | transfer | particles | steps | simulated (s) | wall (s) | outcome | runout (m) | error against the exact "
        "answer |\n|---|---|---:|---:|---:|---:|---|---:|---:|\n";
  std::ofstream csv((std::filesystem::path(options.out) / "runout_scenes.csv").string());
  csv << "scene,transfer,particles,steps,simulated_s,wall_s,outcome,runout_m,exact_error\n";
  for (const auto& name : options.transfers) {
    const TransferChoice t = transfer_choice(name);
    for (const auto& scene : scenes) {
      std::vector<std::string> overrides = scene_overrides(t, options);
      std::fprintf(stderr, "scene %s %s ...", scene.c_str(), name.c_str());
      bench::Scratch scratch("scene");
      std::string outcome, runout, error;
      bench::TimedRun run;
      try {
        run = bench::run_scene(bench::scene_path(scene), overrides, scratch.path().string(), options.threads);
        outcome = run.summary.stopped_at_rest ? "at rest" : "to end_time";
        const std::string json = post_metrics(scratch);
        if (const auto r = bench::json_number(json, "runout_distance_m")) runout = fixed(*r, 2);
        // The validation scenes' errors: box_incline's and newmark_block's relative_error,
        // spring_mass's max_error_over_amplitude.
        std::optional<double> e = largest_json_number(json, "relative_error");
        if (!e) e = largest_json_number(json, "max_error_over_amplitude");
        if (e) error = fixed(100 * *e, 2) + "%";
      } catch (const Error& failure) {
        outcome = std::string("failed: ") + failure.what();
      }
      std::fprintf(stderr, " %s\n", outcome.c_str());
      md << "| " << scene << " | " << name << " | " << run.summary.particles << " | " << run.summary.steps << " | "
         << fixed(run.summary.simulated_time, 2) << " | " << fixed(run.wall_seconds, 1) << " | " << outcome << " | "
         << runout << " | " << error << " |\n";
      csv << scene << "," << name << "," << run.summary.particles << "," << run.summary.steps << ","
          << run.summary.simulated_time << "," << run.wall_seconds << ",\"" << outcome << "\"," << runout << ","
          << error << "\n";
    }
  }
  md << "\nA particle that leaves the mesh, or a state that blows up, fails the run. Runout: talus post's "
        "runout_distance_m (scenes that post a runout). Error: the largest relative error of talus post's "
        "comparison with the exact answer (box_incline, newmark_block, spring_mass).\n\n";
}

// The family a --set run.shape_functions=NAME asks for (linear without one), for the vibration,
// which builds its model here.
ShapeFunctions vibration_family(const Options& options) {
  ShapeFunctions family = ShapeFunctions::Linear;
  const std::string key = "run.shape_functions=";
  for (const std::string& o : options.overrides)
    if (o.rfind(key, 0) == 0) {
      const auto named = shape_functions_from_name(o.substr(key.size()));
      if (!named) throw Error("--set " + o + ": expected linear, bspline or cpdi");
      family = *named;
    }
  return family;
}

// A cantilever 1 m long and 0.1 m deep (E = 1 MPa, nu = 0.3, rho = 1000 kg/m^3, 0.025 m cells,
// 4 particles per cell), clamped at x = 0, no gravity, set swinging with v_y = 0.05 (x / L)^2 m/s.
// Energy = particle kinetic + strain energy, over 4 first-mode periods. With --set
// run.shape_functions=bspline on the lattice's crossed squares (the grid pattern), with cpdi on
// the same triangles as linear, seeded as the preprocessor seeds them (domains that tile).
void run_vibration(const Options& options, std::ostringstream& md) {
  const double L = 1, h = 0.1, cell = 0.025, E = 1e6, nu = 0.3, rho = 1000;
  const ShapeFunctions family = vibration_family(options);
  const double E_plane = E / (1 - nu * nu);
  const double period = 2 * M_PI / (1.8751 * 1.8751 * std::sqrt(E_plane * h * h * h / 12 / (rho * h * std::pow(L, 4))));
  md << "## Elastic vibration: a clamped cantilever swinging freely\n\n"
     << "L = 1 m, depth 0.1 m, E = 1 MPa, nu = 0.3, rho = 1000 kg/m^3, 0.025 m cells, 4 particles per cell, "
        "v_y = 0.05 (x/L)^2 m/s at t = 0, no gravity; first bending period (Euler-Bernoulli) "
     << fixed(period, 3) << " s; 4 periods; shape functions " << shape_functions_name(family) << ".\n\n"
     << "| transfer | steps | energy left after 4 periods | loss per period |\n|---|---:|---:|---:|\n";
  std::ofstream csv((std::filesystem::path(options.out) / "runout_vibration.csv").string());
  csv << "transfer,steps,energy_left,loss_per_period\n";
  for (const auto& name : options.transfers) {
    const TransferChoice t = transfer_choice(name);
    if (t.transfer == Transfer::Apic && family == ShapeFunctions::Linear) {  // as the scene reader refuses it
      md << "| " << name << " | | refused: APIC needs run.shape_functions = bspline or cpdi | |\n";
      csv << name << ",0,,\n";
      continue;
    }
    const int nx = static_cast<int>(L / cell) + 2, ny = static_cast<int>(h / cell) + 4;
    Model model = family == ShapeFunctions::QuadraticBspline ? testing::crossed_rectangle_mesh(0, -2 * cell, nx, ny, cell)
                                                             : testing::rectangle_mesh(0, -2 * cell, nx, ny, cell);
    testing::add_box_body(model, "beam", testing::elastic(rho, E, nu), 0, L, 0, h, false,
                          family == ShapeFunctions::Cpdi ? testing::Seeding::SubTriangles : testing::Seeding::FourPoints);
    model.run.shape_functions = family;
    for (int32_t i : model.node_sets["left"]) model.fixed_nodes.push_back(i);
    for (std::size_t p = 0; p < model.particle_count(); ++p)
      model.velocity[p] = {0, 0.05 * std::pow(model.position[p].x() / L, 2)};
    testing::set_run(model, 4 * period);
    model.run.transfer = t.transfer;
    model.run.xpic_order = t.order;
    model.run.pic_fraction = t.transfer == Transfer::PicBlend ? 0.05 : 0;
    solver::Simulation sim = solver::make_simulation(model, options.threads);
    auto total = [&] {
      const auto e = solver::energies(sim);
      return e.kinetic + e.strain;
    };
    const double start = total();
    const double dt = solver::stable_time_step(sim, 0.5);
    bool ok = true;
    while (ok && sim.time < 4 * period) ok = solver::step(sim, dt);
    const double left = ok ? total() / start : NAN;
    const double per_period = 1 - std::pow(left, 0.25);
    std::fprintf(stderr, "vibration %s: %.4f left\n", name.c_str(), left);
    if (ok)
      md << "| " << name << " | " << sim.steps << " | " << fixed(100 * left, 2) << "% | " << fixed(100 * per_period, 2)
         << "% |\n";
    else
      md << "| " << name << " | " << sim.steps << " | blew up at step " << sim.steps << " | |\n";
    csv << name << "," << sim.steps << "," << left << "," << per_period << "\n";
  }
  md << "\n";
}

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');) out.push_back(item);
  return out;
}

std::vector<double> numbers(const std::string& text) {
  std::vector<double> out;
  for (const auto& item : split(text)) out.push_back(std::stod(item));
  return out;
}

int usage(const char* self, int status) {
  std::fprintf(status ? stderr : stdout,
               "usage: %s [--only column,rods,slope,vibration,scenes] [--transfers LIST] [--aspect LIST] [--sizes LIST]\n"
               "          [--set KEY=VALUE]... [--out DIR] [--threads N] [--no-plots]\n"
               "  --transfers  comma-separated flip, pic_blend, xpicM (M = order), apic (apic with\n"
               "               --set run.shape_functions=bspline --set mesh.pattern=grid, or\n"
               "               --set run.shape_functions=cpdi)\n"
               "  --aspect     column aspect ratios (default 0.5,3 for column, 1,2,4 for rods)\n"
               "  --sizes      slope element sizes in m (default 0.5,0.25)\n"
               "  --set        a scene override for every column, slope and scene run\n"
               "  scenes       (only with --only) every geometries/*.toml as it is: whether it finishes,\n"
               "               its runout and its error against an exact answer where it has one\n",
               self);
  return status;
}

}  // namespace
}  // namespace talus

int main(int argc, char** argv) {
  using namespace talus;
  Options options;
  std::string command = "talus bench runout";
  for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      const bool has_value = i + 1 < argc;
      if (arg == "--only" && has_value) options.parts = split(argv[++i]);
      else if (arg == "--transfers" && has_value) options.transfers = split(argv[++i]);
      else if (arg == "--aspect" && has_value) options.aspect = options.rods_aspect = numbers(argv[++i]);
      else if (arg == "--sizes" && has_value) options.sizes = numbers(argv[++i]);
      else if (arg == "--set" && has_value) options.overrides.push_back(argv[++i]);
      else if (arg == "--out" && has_value) options.out = argv[++i];
      else if (arg == "--threads" && has_value) options.threads = std::max(1, std::atoi(argv[++i]));
      else if (arg == "--no-plots") options.plots = false;
      else return usage(argv[0], arg == "--help" || arg == "-h" ? 0 : 1);
    }
    std::ostringstream md;
    const std::vector<std::pair<std::string, std::function<void()>>> known = {
        {"column", [&] { run_column(options, kSandColumn, options.aspect, md); }},
        {"rods", [&] { run_column(options, kRodsColumn, options.rods_aspect, md); }},
        {"slope", [&] { run_slope(options, md); }},
        {"vibration", [&] { run_vibration(options, md); }},
        {"scenes", [&] { run_scenes(options, md); }}};
    auto part_named = [&](const std::string& name) {
      for (const auto& [part, run] : known)
        if (part == name) return run;
      throw Error("--only: unknown part '" + name + "' (expected column, rods, slope, vibration or scenes)");
    };
    // Bad names are refused before anything runs.
    for (const auto& name : options.transfers) transfer_choice(name);
    std::vector<std::function<void()>> parts;
    for (const auto& name : options.parts) parts.push_back(part_named(name));
    std::filesystem::create_directories(options.out);
    md << "# Runout benchmark\n\n";
    const double start = bench::now_seconds();
    for (const auto& run : parts) run();
    md << "Made by `" << command << "` (" << options.threads << (options.threads == 1 ? " thread" : " threads") << " per run) on " << bench::machine_line()
       << " in " << fixed(bench::now_seconds() - start, 0) << " s.\n";
    const std::string md_path = (std::filesystem::path(options.out) / "runout.md").string();
    postproc::write_file_atomically(md_path, md.str());
    std::printf("%s", md.str().c_str());
    if (options.plots && bench::run_plot_script({"runout", options.out}) != 0) {
      std::fprintf(stderr, "talus_bench_runout: the plots failed\n");
      return 1;
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "talus_bench_runout: %s\n", error.what());
    return 1;
  }
  return 0;
}
