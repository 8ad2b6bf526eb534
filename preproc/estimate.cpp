#include "preproc/estimate.hpp"

#include <gmsh.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <new>
#include <sstream>
#include <utility>

#include "common/error.hpp"
#include "preproc/geo_guard.hpp"
#include "preproc/gmsh_geometry.hpp"
#include "preproc/gmsh_session.hpp"

namespace talus::preproc {
namespace {

constexpr double kBytesPerParticle = 500, kBytesPerNode = 200, kBytesPerTriangle = 150;
constexpr int kSamplesPerCurve = 64;

// Points along a curve, from its start to its end.
std::vector<Eigen::Vector2d> sample_curve(int tag) {
  std::vector<double> low, high;
  gmsh::model::getParametrizationBounds(1, tag, low, high);
  std::vector<double> parameters(kSamplesPerCurve + 1), xyz;
  for (int k = 0; k <= kSamplesPerCurve; ++k) parameters[k] = low[0] + (high[0] - low[0]) * k / kSamplesPerCurve;
  gmsh::model::getValue(1, tag, parameters, xyz);
  std::vector<Eigen::Vector2d> points;
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3) points.emplace_back(xyz[i], xyz[i + 1]);
  return points;
}

// The area of a surface from its oriented boundary curves (holes count negative): the
// shoelace sum over the sampled edges of every curve, each in the direction the surface uses.
double surface_area(int tag) {
  gmsh::vectorpair boundary;
  gmsh::model::getBoundary({{2, tag}}, boundary, false, true, false);
  double twice = 0;
  for (const auto& [dim, signed_tag] : boundary) {
    std::vector<Eigen::Vector2d> points = sample_curve(std::abs(signed_tag));
    if (signed_tag < 0) std::reverse(points.begin(), points.end());
    for (std::size_t i = 0; i + 1 < points.size(); ++i)
      twice += points[i].x() * points[i + 1].y() - points[i + 1].x() * points[i].y();
  }
  return std::abs(0.5 * twice);
}

double curve_length(int tag) {
  const auto points = sample_curve(tag);
  double length = 0;
  for (std::size_t i = 0; i + 1 < points.size(); ++i) length += (points[i + 1] - points[i]).norm();
  return length;
}

// The entities of the named physical group of dimension dim (empty when there is none).
std::vector<int> group_entities(const std::string& name, int dim) {
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, dim);
  for (const auto& [d, tag] : groups) {
    std::string group_name;
    gmsh::model::getPhysicalName(d, tag, group_name);
    if (group_name != name) continue;
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(d, tag, entities);
    return entities;
  }
  return {};
}

double body_area(const std::string& group) {
  double area = 0;
  for (int surface : group_entities(group, 2)) area += surface_area(surface);
  if (area > 0) return area;
  // A closed physical curve: its bounding box.
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (int curve : group_entities(group, 1))
    for (const auto& p : sample_curve(curve)) {
      x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x());
      y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
    }
  return x1 > x0 && y1 > y0 ? (x1 - x0) * (y1 - y0) : 0;
}

// The mean edge length of gmsh's 1D mesh of the domain's boundary, with the .geo's own sizes.
double boundary_element_size(const std::vector<int>& domain) {
  GmshSession::generate(1);
  if (!GmshSession::logged_errors().empty()) return 0;  // the meshing reports it
  double length = 0, segments = 0;
  for (int surface : domain) {
    gmsh::vectorpair boundary;
    gmsh::model::getBoundary({{2, surface}}, boundary, false, false, false);
    for (const auto& [dim, tag] : boundary) {
      std::vector<std::size_t> nodes;
      std::vector<double> xyz, parametric;
      gmsh::model::mesh::getNodes(nodes, xyz, parametric, 1, std::abs(tag), true, false);
      if (nodes.size() < 2) continue;
      length += curve_length(std::abs(tag));
      segments += static_cast<double>(nodes.size() - 1);
    }
  }
  return segments > 0 ? length / segments : 0;
}

std::string number(double x, int digits = 3);

// A "Key: N kB" line of a /proc file, in bytes; NaN when missing.
double proc_kilobytes(const std::string& path, const std::string& key) {
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    std::string word;
    double kilobytes = 0;
    if (fields >> word && word == key && fields >> kilobytes) return kilobytes * 1024;
  }
  return NAN;
}

// A whole file's one number ("max", a missing file or anything else: NaN).
double file_number(const std::string& path) {
  std::ifstream in(path);
  double value = NAN;
  if (!(in >> value)) return NAN;
  return value;
}

}  // namespace

double cgroup_memory_left(const std::string& root) {
  // The memory cgroup of this process: "0::/path" (v2) or "N:...memory...:/path" (v1).
  std::ifstream cgroups(root + "/proc/self/cgroup");
  std::string v2_path, v1_path;
  for (std::string line; std::getline(cgroups, line);) {
    const auto first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1), path = line.substr(second + 1);
    if (line.substr(0, first) == "0" && controllers.empty()) v2_path = path;
    std::stringstream list(controllers);
    for (std::string c; std::getline(list, c, ',');)
      if (c == "memory") v1_path = path;
  }
  // Where each hierarchy is mounted, and which of its folders the mount shows as its root.
  std::ifstream mounts(root + "/proc/self/mountinfo");
  double left = INFINITY;
  for (std::string line; std::getline(mounts, line);) {
    std::istringstream fields(line);
    std::string id, parent, device, mount_root, mount_point, options, field;
    fields >> id >> parent >> device >> mount_root >> mount_point >> options;
    while (fields >> field && field != "-") {
    }
    std::string type, source, super_options;
    fields >> type >> source >> super_options;
    const bool v2 = type == "cgroup2" && !v2_path.empty();
    const bool v1 = type == "cgroup" && !v1_path.empty() && ("," + super_options + ",").find(",memory,") != std::string::npos;
    if (!v1 && !v2) continue;
    std::string path = v2 ? v2_path : v1_path;
    if (mount_root != "/" && path.rfind(mount_root, 0) == 0) path = path.substr(mount_root.size());
    // The limits of the cgroup and of every cgroup above it in this mount.
    for (std::filesystem::path folder = std::filesystem::path(root + mount_point) / std::filesystem::path(path).relative_path();;
         folder = folder.parent_path()) {
      const double limit = file_number((folder / (v2 ? "memory.max" : "memory.limit_in_bytes")).string());
      const double used = file_number((folder / (v2 ? "memory.current" : "memory.usage_in_bytes")).string());
      if (limit < 1e18 && std::isfinite(used)) left = std::min(left, std::max(0.0, limit - used));
      if (folder.string().size() <= (root + mount_point).size() || folder == folder.parent_path()) break;
    }
  }
  return left;
}

MemoryLeft memory_left() {
  MemoryLeft best{proc_kilobytes("/proc/meminfo", "MemAvailable:"), "MemAvailable"};
  if (std::isnan(best.bytes)) best = {INFINITY, ""};  // unknown: no refusal on memory
  auto consider = [&](double bytes, const std::string& what) {
    if (bytes < best.bytes) best = {std::max(0.0, bytes), what};
  };
  struct rlimit limit {};
  if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    const double mapped = proc_kilobytes("/proc/self/status", "VmSize:");
    consider(static_cast<double>(limit.rlim_cur) - (std::isnan(mapped) ? 0 : mapped),
             "the address-space limit (ulimit -v) of " + number(static_cast<double>(limit.rlim_cur) / 1e9) +
                 " GB, less the " + number(mapped / 1e9) + " GB this process maps already");
  }
  if (getrlimit(RLIMIT_DATA, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    const double data = proc_kilobytes("/proc/self/status", "VmData:");
    consider(static_cast<double>(limit.rlim_cur) - (std::isnan(data) ? 0 : data),
             "the data-size limit (ulimit -d) of " + number(static_cast<double>(limit.rlim_cur) / 1e9) + " GB, less the " +
                 number(data / 1e9) + " GB this process uses already");
  }
  consider(cgroup_memory_left(), "what the memory limit of this process's cgroup leaves");
  return best;
}

namespace {

std::string number(double x, int digits) {
  std::ostringstream s;
  s.precision(digits);
  s << x;
  return s.str();
}

// The explicit solver's time step is about cfl x (an element's height) / (the P-wave speed of
// the stiffest material): a run of more than kMaxSteps steps would not finish. run.max_steps
// bounds the run, so a scene that sets it is not refused; a wave speed that is not finite is,
// at the parameter that makes it so.
void check_steps(const Scene& scene, double h) {
  constexpr double kMaxSteps = 1e8;
  for (const auto& body : scene.bodies) {
    const int index = scene.material_index(body.material);
    if (index < 0) continue;  // the meshing names it
    const Material& m = scene.materials[index];
    const double nu = m.poisson_ratio;
    const double modulus = m.youngs_modulus * (1 - nu) / ((1 + nu) * (1 - 2 * nu));  // P-wave modulus M
    const double wave_speed = std::sqrt(modulus / m.density);
    if (!std::isfinite(wave_speed)) {
      // Each value is in its range, yet their combination overflows: name the one that does.
      const bool stiff = !std::isfinite(m.youngs_modulus * (1 - nu) / (1 + nu));
      const std::string key = std::isfinite(modulus) ? "density" : stiff ? "youngs_modulus" : "poisson_ratio";
      const double got = key == "density" ? m.density : stiff ? m.youngs_modulus : nu;
      throw Error(located(scene.path, "materials." + m.name + "." + key,
                          "got " + number(got, 6) + ": the P-wave speed sqrt(M / density), M = E (1 - nu) / ((1 + nu) "
                          "(1 - 2 nu)), is not a finite number (" +
                              (key == "density" ? "M = " + number(modulus) + " Pa over a density this small"
                                                : std::string("M overflows")) +
                              ")"));
    }
    if (scene.run.max_steps > 0) continue;
    // A body thrown faster than its material's waves travel sets the step by its speed.
    const double speed = body.fixed ? 0 : std::hypot(body.initial_velocity.x(), body.initial_velocity.y());
    const double step = scene.run.cfl * 0.5 * h / (wave_speed + speed);
    const double steps = scene.run.end_time / step;
    if (steps > kMaxSteps && speed > wave_speed)
      throw Error(located(scene.path, "bodies." + body.name + ".initial_velocity",
                          "a speed of " + number(speed) + " m/s at an element size of " + number(h) +
                              " m gives a time step of about " + number(step) + " s: about " + number(steps) +
                              " steps over run.end_time = " + number(scene.run.end_time) + " s, more than " +
                              number(kMaxSteps) + " (lower the speed, shorten run.end_time, or set run.max_steps "
                              "to run anyway)"));
    if (steps > kMaxSteps)
      throw Error(located(scene.path, "materials." + m.name + ".youngs_modulus",
                          "a wave speed of " + number(wave_speed) + " m/s at an element size of " + number(h) +
                              " m gives a time step of about " + number(step) + " s: about " + number(steps) +
                              " steps over run.end_time = " + number(scene.run.end_time) + " s, more than " +
                              number(kMaxSteps) +
                              " (lower youngs_modulus, shorten run.end_time, raise mesh.size, or set run.max_steps "
                              "to run anyway)"));
  }
}

}  // namespace

SizeEstimate estimate_size(const Scene& scene) {
  SizeEstimate estimate;
  std::ifstream probe(scene.geometry);
  if (!probe) return estimate;  // the meshing reports the missing file
  check_geo_program(scene.geometry);  // before gmsh parses (and runs) the .geo
  try {
    GmshSession reader;
    open_geometry(scene.geometry, scene.mesh.parameters);
    const std::vector<int> domain = group_entities(scene.mesh.domain, 2);
    if (domain.empty()) return estimate;
    for (int surface : domain) estimate.domain_area += surface_area(surface);
    for (const auto& body : scene.bodies) estimate.body_areas.push_back(body_area(body.group));
    estimate.element_size = scene.mesh.size ? *scene.mesh.size : boundary_element_size(domain);
  } catch (const std::bad_alloc&) {
    throw;  // out of memory already (talus exits with status 3)
  } catch (...) {  // gmsh 4.8 throws strings; whatever it is, the meshing reports it
    return estimate;
  }
  const double h = estimate.element_size;
  if (!(h > 0) || !(estimate.domain_area > 0) || !std::isfinite(h)) return estimate;
  estimate.known = true;
  // Delaunay: equilateral triangles of edge h; crossed: a quadrilateral of edge h in four.
  const bool crossed = scene.mesh.pattern != MeshPattern::Delaunay;  // crossed, or the grid's crossed lattice
  estimate.element_area = crossed ? h * h / 4 : std::sqrt(3.0) / 4 * h * h;
  estimate.triangles = estimate.domain_area / estimate.element_area;
  estimate.nodes = estimate.triangles / 2;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    estimate.particles += scene.bodies[b].particles_per_cell *
                          std::min(estimate.body_areas[b], estimate.domain_area) / estimate.element_area;
  estimate.bytes = kBytesPerParticle * estimate.particles + kBytesPerNode * estimate.nodes +
                   kBytesPerTriangle * estimate.triangles;
  // What model.h5 holds of each (positions, velocities, masses, volumes, stresses and indices;
  // coordinates; corners and neighbours), measured on the slope at two sizes within 0.1 %.
  estimate.model_bytes = 88 * estimate.particles + 16 * estimate.nodes + 24 * estimate.triangles;
  return estimate;
}

void check_size(const Scene& scene) {
  const SizeEstimate e = estimate_size(scene);
  if (!e.known) return;
  const std::string size_item = scene.mesh.size ? "mesh.size" : "the element sizes of " + scene.geometry;
  const std::string sizes = "an element size of " + number(e.element_size) + " m over the domain's " +
                            number(e.domain_area) + " m^2 gives about " + number(e.triangles) + " triangles and " +
                            number(e.particles) + " particles, ";
  const MemoryLeft memory = memory_left();
  if (e.bytes > memory.bytes)
    throw Error(located(scene.path, size_item,
                        sizes + "about " + number(e.bytes / 1e9) +
                            " GB to solve (500 B per particle, 200 B per node, 150 B per triangle), more than the " +
                            number(memory.bytes / 1e9) + " GB left by " + memory.what + ": raise mesh.size"));
  // model.h5 against the file size limit (ulimit -f), which would stop its write at the end.
  struct rlimit file_limit {};
  if (getrlimit(RLIMIT_FSIZE, &file_limit) == 0 && file_limit.rlim_cur != RLIM_INFINITY &&
      e.model_bytes > static_cast<double>(file_limit.rlim_cur))
    throw Error(located(scene.path, size_item,
                        sizes + "a model.h5 of about " + number(e.model_bytes / 1e6) +
                            " MB (88 B per particle, 16 B per node, 24 B per triangle), more than the file size "
                            "limit of " + number(static_cast<double>(file_limit.rlim_cur) / 1e6) +
                            " MB (ulimit -f): raise mesh.size or the limit"));
  // The time step follows the smallest altitude: h/2 in a crossed square, that of an equilateral
  // triangle of edge h/sqrt(3).
  check_steps(scene, scene.mesh.pattern != MeshPattern::Delaunay ? e.element_size / std::sqrt(3.0) : e.element_size);
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b];
    const double area = e.body_areas[b];
    if (area <= 0) continue;  // the meshing names the missing group
    if (body.particles_per_cell * area < e.element_area)
      throw Error(located(scene.path, "bodies." + body.name,
                          "the mesh is too coarse for the body: its area, " + number(area) +
                              " m^2, is less than one element's (" + number(e.element_area) + " m^2 for h = " +
                              number(e.element_size) + " m) over particles_per_cell = " +
                              std::to_string(body.particles_per_cell) +
                              ", so it would get no particle (lower mesh.size or raise particles_per_cell)"));
  }
}

}  // namespace talus::preproc
