// The readers of the scene's settings tables: [scene], [mesh], [run] and [post].
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "common/model/checks.hpp"
#include "common/scene/reader.hpp"

namespace talus::scene_reader {
namespace {

// scene.name is the output folder's name (out/NAME/): one plain path component.
std::string folder_name_problem(const std::string& name) {
  const std::string expected = "expected a folder name of 1 to 128 characters, without '/', '\\' or control "
                               "characters, and not '.' or '..' (it names the output folder out/NAME/)";
  if (name.empty() || name.size() > 128 || name == "." || name == "..") return expected;
  for (unsigned char c : name)
    if (c < 0x20 || c == 0x7f || c == '/' || c == '\\') return expected;
  return "";
}

}  // namespace

void read_scene_table(TableReader& top, Scene& scene) {
  namespace fs = std::filesystem;
  const std::string& path = top.file();
  TableReader scene_table = top.child(top.table("scene"), "scene");
  scene.name = scene_table.text("name", fs::path(path).stem().string());
  const std::string geometry = scene_table.text("geometry", fs::path(path).stem().string() + ".geo");
  scene_table.finish();
  scene.geometry = (fs::path(path).parent_path() / geometry).lexically_normal().string();
  // A device or a pipe would be read without end (by the stamps' hash, then by gmsh).
  std::error_code error;
  if (fs::exists(scene.geometry, error) && !fs::is_regular_file(scene.geometry, error))
    scene_table.fail("geometry", "'" + echoed(geometry) + "' is not a regular file (a device, pipe or folder)");
  if (const std::string problem = folder_name_problem(scene.name); !problem.empty())
    scene_table.fail("name", problem + ", got '" + echoed(scene.name) + "'");
}

void read_mesh(TableReader& top, Scene& scene) {
  TableReader mesh = top.child(top.table("mesh"), "mesh");
  if (mesh.has("size")) scene.mesh.size = mesh.number("size", std::nullopt, 0, kInf, false);
  scene.mesh.domain = mesh.text("domain", scene.mesh.domain);
  // B-splines take their nodes from the grid pattern's lattice: it is their default pattern.
  const toml::table* run = top.table("run");
  const bool bspline = run && (*run)["shape_functions"].value<std::string>() == std::optional<std::string>("bspline");
  const std::string pattern = mesh.text("pattern", bspline ? "grid" : "delaunay");
  if (pattern == "delaunay") scene.mesh.pattern = MeshPattern::Delaunay;
  else if (pattern == "crossed") scene.mesh.pattern = MeshPattern::Crossed;
  else if (pattern == "grid") scene.mesh.pattern = MeshPattern::Grid;
  else mesh.fail("pattern", "unknown pattern '" + echoed(pattern) + "' (expected delaunay, crossed or grid)");
  if (scene.mesh.pattern == MeshPattern::Grid && !scene.mesh.size)
    mesh.fail("size", "missing: the grid pattern needs it (the edge of its cells, m)");
  if (const toml::table* parameters = mesh.table("parameters")) {
    TableReader values = mesh.child(parameters, "mesh.parameters");
    for (const auto& [key, node] : *parameters) {
      const std::string name(key.str());
      check_name(name, "mesh.parameters." + name, values.file());
      scene.mesh.parameters[name] = values.number(name, std::nullopt, -kInf, kInf);
    }
    values.finish();
  }
  mesh.finish();
}

void read_run(TableReader& top, Scene& scene) {
  TableReader run = top.child(top.table("run"), "run");
  RunSettings& rs = scene.run;
  rs.end_time = run.number("end_time", std::nullopt, 0, kInf, false);
  rs.cfl = run.number("cfl", rs.cfl, 0, 1, false, true);
  rs.output_interval = run.number("output_interval", rs.output_interval, 0, kInf, false);
  rs.gravity = run.vector2("gravity", rs.gravity);
  if (!(std::hypot(rs.gravity.x(), rs.gravity.y()) <= kMaxGravity)) {
    std::ostringstream message;
    message << "a magnitude of " << std::hypot(rs.gravity.x(), rs.gravity.y()) << " m/s^2, expected at most "
            << kMaxGravity << " (100 g)";
    run.fail("gravity", message.str());
  }
  rs.gravity_ramp = run.number("gravity_ramp", rs.gravity_ramp, 0, kInf);
  rs.damping = run.number("damping", rs.damping, 0, 1, true, false);
  rs.evs = run.boolean("evs", rs.evs);
  const std::string transfer = run.text("transfer", transfer_name(rs.transfer));
  if (!transfer_from_name(transfer))
    run.fail("transfer", "unknown transfer '" + echoed(transfer) + "' (expected flip, pic_blend, xpic or apic)");
  rs.transfer = *transfer_from_name(transfer);
  if (rs.transfer != Transfer::PicBlend && run.has("pic_fraction"))
    run.fail("pic_fraction", "applies to transfer = \"pic_blend\" only (the transfer is \"" + transfer + "\")");
  if (rs.transfer == Transfer::PicBlend) rs.pic_fraction = run.number("pic_fraction", 0.05, 0, 1);
  if (rs.transfer != Transfer::Xpic && run.has("xpic_order"))
    run.fail("xpic_order", "applies to transfer = \"xpic\" only (the transfer is \"" + transfer + "\")");
  if (rs.transfer == Transfer::Xpic) rs.xpic_order = static_cast<int>(run.integer("xpic_order", rs.xpic_order, 1, 100));
  const std::string shape_functions = run.text("shape_functions", "linear");
  if (const auto family = shape_functions_from_name(shape_functions)) rs.shape_functions = *family;
  else run.fail("shape_functions", "unknown shape functions '" + echoed(shape_functions) + "' (expected linear, bspline or cpdi)");
  const bool bspline = rs.shape_functions == ShapeFunctions::QuadraticBspline;
  if (rs.transfer == Transfer::Apic && !bspline && rs.shape_functions != ShapeFunctions::Cpdi)
    run.fail("transfer", "\"apic\" needs run.shape_functions = \"bspline\" or \"cpdi\": on plain linear triangles it "
                         "throws particles out of every shipped scene (docs/transfer.md, \"APIC\")");
  if (bspline && scene.mesh.pattern != MeshPattern::Grid)
    run.fail("shape_functions", std::string("\"bspline\" takes its nodes from the grid pattern's lattice, and mesh.pattern is \"") +
                                    (scene.mesh.pattern == MeshPattern::Crossed ? "crossed" : "delaunay") +
                                    "\": set mesh.pattern = \"grid\" (the default with bspline when the scene names no pattern)");
  if (bspline && rs.evs) run.fail("evs", "enhanced volumetric strain is for linear triangles; B-splines do not use it");
  const std::string integration = run.text("integration", "material_points");
  if (bspline && integration == "mixed")
    run.fail("integration", "\"mixed\" is for linear triangles; B-splines integrate at the particles");
  if (rs.shape_functions == ShapeFunctions::Cpdi && integration == "mixed")
    run.fail("integration", "\"mixed\" is for linear triangles; CPDI integrates over the particles' domains");
  if (integration != "material_points" && integration != "mixed")
    run.fail("integration", "unknown integration '" + echoed(integration) + "' (expected material_points or mixed)");
  if (integration != "mixed" && run.has("full_cell_fill"))
    run.fail("full_cell_fill", "applies to integration = \"mixed\" only (the integration is \"" + integration + "\")");
  if (integration == "mixed") rs.full_cell_fill = run.number("full_cell_fill", 0.5, 0, 1, false, true);
  rs.history_interval = static_cast<int>(run.integer("history_interval", rs.history_interval, 1, 1000000));
  rs.rest_ratio = run.number("rest_ratio", rs.rest_ratio, 0, 1, true, false);
  rs.rest_window = run.number("rest_window", rs.rest_window, 0, kInf, false);
  rs.max_steps = run.integer("max_steps", rs.max_steps, 0, std::numeric_limits<long>::max());
  run.finish();
  if (const std::string problem = output_interval_problem(rs); !problem.empty()) run.fail("output_interval", problem);
}

void read_post(TableReader& top, Scene& scene) {
  TableReader post = top.child(top.table("post"), "post");
  PostSettings& ps = scene.post;
  ps.metrics = post.strings("metrics");
  static const std::vector<std::string> kMetrics{"runout",      "failure_surface", "bishop", "spring_mass",
                                                 "box_incline", "newmark_block"};
  for (const auto& m : ps.metrics)
    if (std::find(kMetrics.begin(), kMetrics.end(), m) == kMetrics.end()) {
      const std::string suggestion = nearest(m, kMetrics);
      post.fail("metrics", "unknown metric '" + echoed(m) + "'" +
                               (suggestion.empty() ? " (expected runout, failure_surface, bishop, spring_mass, box_incline or newmark_block)"
                                                   : " (did you mean '" + suggestion + "'?)"));
    }
  const bool body_given = post.has("body");
  ps.body = post.text("body", scene.bodies.front().name);
  if (scene.body_index(ps.body) < 0) post.fail("body", "no body named '" + ps.body + "' in [bodies]");
  if (post.has("bodies")) {
    ps.bodies = post.strings("bodies");
    if (ps.bodies.empty()) post.fail("bodies", "expected at least one body name");
    for (std::size_t i = 0; i < ps.bodies.size(); ++i) {
      const std::string& name = ps.bodies[i];
      if (scene.body_index(name) < 0) {
        std::vector<std::string> names;
        for (const auto& b : scene.bodies) names.push_back(b.name);
        const std::string suggestion = nearest(name, names);
        post.fail("bodies", "no body named '" + echoed(name) + "' in [bodies]" +
                                (suggestion.empty() ? "" : " (did you mean '" + suggestion + "'?)"));
      }
      if (std::find(ps.bodies.begin(), ps.bodies.begin() + i, name) != ps.bodies.begin() + i)
        post.fail("bodies", "body '" + echoed(name) + "' is listed twice");
    }
  } else if (!body_given) {
    // Every soil body: not fixed, of a material with a strength (Mohr-Coulomb).
    for (const auto& b : scene.bodies) {
      const int m = scene.material_index(b.material);
      if (!b.fixed && m >= 0 && has_strength(scene.materials[m])) ps.bodies.push_back(b.name);
    }
  }
  ps.sliding_threshold = post.number("sliding_threshold", ps.sliding_threshold, 0, 1, false, true);
  ps.spring_amplitude = post.number("spring_amplitude", ps.spring_amplitude, 0, kInf, false);
  ps.spring_omega = post.number("spring_omega", ps.spring_omega, 0, kInf, false);
  ps.incline_angle = post.number("incline_angle", ps.incline_angle, 0, 90, false, false);
  ps.animate = post.boolean("animate", ps.animate);
  post.finish();
}

}  // namespace talus::scene_reader

namespace talus {

std::string output_interval_problem(const RunSettings& run) {
  const double frames = run.end_time / run.output_interval;
  if (!(frames > kMaxFrames)) return "";
  std::ostringstream text;
  text << "got " << run.output_interval << " s: " << frames << " frames over run.end_time = " << run.end_time
       << " s, at most " << kMaxFrames << " (raise run.output_interval)";
  return text.str();
}

}  // namespace talus
