// Bad input through the talus binary, one row per mistake: scene files, .geo files, HDF5 models
// and results, and command lines. Every row must stop with exit status 1, a message holding
// the row's key words (the file, the item, what was expected), and leave no model.h5,
// results.h5, metrics.json, checkpoint.h5 or *.tmp in the output folder.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>

#include "common/h5.hpp"
#include "common/model/model.hpp"
#include "support/bad_input_table.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;
using testing::kGeo;
using testing::kScene;
using testing::replaced;
using testing::Row;
using testing::scene_change;
using testing::scene_row;
using testing::ScratchDir;
using testing::write_file;

// A small valid model: an elastic block on a fixed base, a few steps long.
Model small_model() {
  Model model = testing::rectangle_mesh(0, 0, 8, 8, 0.125);
  testing::add_box_body(model, "block", testing::elastic(2000, 1e7, 0.25), 0.25, 0.75, 0, 0.5);
  model.fixed_nodes = model.node_sets["bottom"];
  testing::set_run(model, 0.002, Eigen::Vector2d(0, -9.81));
  model.scene_name = "small";
  return model;
}

// Changes one thing in an HDF5 file written by Talus.
void edit_h5(const std::string& path, const std::function<void(const h5::File&)>& change) {
  h5::File file = h5::File::open_write(path);
  change(file);
  file.close();
}

void set_double(const std::string& path, const std::string& dataset, std::size_t index, double value) {
  edit_h5(path, [&](const h5::File& file) {
    h5::Dims dims;
    auto values = h5::read_doubles(file, dataset, &dims);
    values.at(index) = value;
    h5::write(file, dataset, values, dims);
  });
}

void set_int(const std::string& path, const std::string& dataset, std::size_t index, int32_t value) {
  edit_h5(path, [&](const h5::File& file) {
    h5::Dims dims;
    auto values = h5::read_ints(file, dataset, &dims);
    values.at(index) = value;
    h5::write(file, dataset, values, dims);
  });
}

void truncate_file(const std::string& path, double fraction) {
  const auto size = fs::file_size(path);
  fs::resize_file(path, static_cast<std::uintmax_t>(size * fraction));
}

std::string model_row(const fs::path& dir, const std::function<void(const std::string&)>& change,
                      const std::string& command = "solve") {
  const std::string path = (dir / "model.h5").string();
  write_model(path, small_model());
  change(path);
  return command + " " + path;
}

// The small model with a pressure on its top edge, carried by particle 0.
std::string loaded_model_row(const fs::path& dir, const std::function<void(const std::string&)>& change) {
  const std::string path = (dir / "model.h5").string();
  Model model = small_model();
  SurfaceLoad load;
  load.name = "push";
  load.group = "top";
  load.pressure = 1000.0;
  model.loads = {load};
  model.load.assign(model.particle_count(), -1);
  model.load_length.assign(model.particle_count(), 0);
  model.load_normal.assign(model.particle_count(), Eigen::Vector2d::Zero());
  model.load[0] = 0;
  model.load_length[0] = 0.5;
  model.load_normal[0] = {0, 0.5};
  write_model(path, model);
  change(path);
  return "solve " + path;
}

// results.h5 of a valid run, to hand to `talus post` after a change.
std::string results_row(const fs::path& dir, const std::function<void(const std::string&)>& change) {
  const std::string model = (dir / "model.h5").string();
  write_model(model, small_model());
  const auto solved = testing::run_talus("solve " + model + " --quiet --out " + (dir / "run").string());
  EXPECT_EQ(solved.status, 0) << solved.output;
  const std::string results = (dir / "run" / "results.h5").string();
  change(results);
  return "post " + results;
}

// The base scene with more bodies (TOML tables before [contact]) and [[contact.pairs]] after
// its friction. The scene is refused while it is read, before any body is meshed.
std::string pairs_row(const fs::path& dir, const std::string& bodies, const std::string& pairs) {
  return scene_row(dir, replaced(kScene, "[contact]\nfriction = 0.3\n",
                                 bodies + "\n[contact]\nfriction = 0.3\n\n" + pairs));
}
const char* const kOther = "[bodies.other]\nmaterial = \"rock\"\ngroup = \"speck\"\n";

// The small model with one contact pair (datasets as model.cpp writes them).
std::string paired_model_row(const fs::path& dir, const std::vector<std::string>& names, int32_t bonded) {
  return model_row(dir, [=](auto p) {
    edit_h5(p, [&](auto& f) {
      h5::write(f, "settings/contact/pair_bodies", names);
      h5::write(f, "settings/contact/pair_friction", std::vector<double>{0.0}, {1});
      h5::write(f, "settings/contact/pair_bonded", std::vector<int32_t>{bonded}, {1});
    });
  });
}

std::vector<Row> rows() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return {
      // Scene files.
      {"unknown key in a table", [](auto d) { return scene_change(d, "cfl = 0.5", "cfl = 0.5\ncfll = 0.4"); },
       {"block.toml", "run.cfll", "unknown key", "did you mean 'run.cfl'"}},
      {"unknown table", [](auto d) { return scene_change(d, "[contact]", "[contacts]"); },
       {"block.toml", "contacts", "unknown key", "did you mean 'contact'"}},
      {"unknown key by --set", [](auto d) { return scene_row(d, kScene, "--set run.end_tme=2"); },
       {"block.toml", "run.end_tme", "did you mean 'run.end_time'"}},
      {"mesh parameter that is not a number",
       [](auto d) { return scene_change(d, "size = 0.25", "size = 0.25\nparameters = { a = \"tall\" }"); },
       {"mesh.parameters.a", "expected a number"}},
      {"NaN CFL", [](auto d) { return scene_change(d, "cfl = 0.5", "cfl = nan"); },
       {"block.toml", "run.cfl", "finite", "(0, 1]"}},
      {"zero CFL", [](auto d) { return scene_change(d, "cfl = 0.5", "cfl = 0.0"); }, {"run.cfl", "got 0", "(0, 1]"}},
      {"CFL above one", [](auto d) { return scene_change(d, "cfl = 0.5", "cfl = 1.5"); },
       {"run.cfl", "got 1.5", "(0, 1]"}},
      {"negative friction", [](auto d) { return scene_change(d, "friction = 0.3", "friction = -0.1"); },
       {"contact.friction", "got -0.1", "[0, inf]"}},
      {"friction boundary without its coefficient",
       [](auto d) { return scene_change(d, "type = \"fixed\"", "type = \"friction\""); },
       {"block.toml", "boundaries.base.friction", "missing"}},
      {"negative boundary friction",
       [](auto d) { return scene_change(d, "type = \"fixed\"", "type = \"friction\"\nfriction = -0.2"); },
       {"boundaries.base.friction", "-0.2"}},
      {"NaN boundary friction",
       [](auto d) { return scene_change(d, "type = \"fixed\"", "type = \"friction\"\nfriction = nan"); },
       {"boundaries.base.friction", "finite"}},
      {"friction on a fixed boundary",
       [](auto d) { return scene_change(d, "type = \"fixed\"", "type = \"fixed\"\nfriction = 0.3"); },
       {"boundaries.base.friction", "belongs to type = \"friction\" only"}},
      {"converge with one level",
       [](auto d) { return replaced(scene_row(d, kScene, "--levels 1"), "mesh ", "converge "); },
       {"--levels", "[2, 6]", "got 1"}},
      {"converge with seven levels",
       [](auto d) { return replaced(scene_row(d, kScene, "--levels=7"), "mesh ", "converge "); },
       {"--levels", "[2, 6]", "got 7"}},
      {"converge ratio of one", [](auto d) { return replaced(scene_row(d, kScene, "--ratio 1"), "mesh ", "converge "); },
       {"--ratio", "expected a number > 1", "got 1"}},
      {"converge ratio that is not a number",
       [](auto d) { return replaced(scene_row(d, kScene, "--ratio two"), "mesh ", "converge "); },
       {"--ratio", "expected a number > 1", "'two'"}},
      {"converge level too large for memory",
       [](auto d) {
         return replaced(scene_row(d, kScene, "--levels 6 --ratio 20 --set 'post.metrics=[\"runout\"]'"), "mesh ",
                         "converge ");
       },
       {"converge: level", "mesh.size = ", "cannot run", "MemAvailable"}},
      {"levels outside converge", [](auto d) { return scene_row(d, kScene, "--levels 3"); },
       {"--levels, --ratio and --transfers belong to converge"}},
      {"transfers outside converge", [](auto d) { return scene_row(d, kScene, "--transfers flip,apic"); },
       {"--levels, --ratio and --transfers belong to converge"}},
      {"Poisson ratio of one half", [](auto d) { return scene_change(d, "poisson_ratio = 0.25", "poisson_ratio = 0.5"); },
       {"materials.rock.poisson_ratio", "got 0.5", "[0, 0.5)"}},
      {"negative Poisson ratio",
       [](auto d) { return scene_change(d, "poisson_ratio = 0.25", "poisson_ratio = -0.1"); },
       {"materials.rock.poisson_ratio", "got -0.1"}},
      {"friction angle beyond 90", [](auto d) { return scene_change(d, "friction_angle = 30.0", "friction_angle = 95.0"); },
       {"materials.rock.friction_angle", "got 95", "[0, 90)"}},
      {"dilation above friction", [](auto d) { return scene_change(d, "dilation_angle = 0.0", "dilation_angle = 40.0"); },
       {"materials.rock.dilation_angle", "got 40", "[0, 30]"}},
      {"water table missing",
       [](auto d) { return scene_change(d, "friction = 0.3", "friction = 0.3\n[water]\nunit_weight = 9810.0"); },
       {"water.table", "missing", "[x, y]"}},
      {"water table of one point",
       [](auto d) { return scene_change(d, "friction = 0.3", "friction = 0.3\n[water]\ntable = [[0.0, 0.5]]"); },
       {"water.table", "at least two"}},
      {"water table going back",
       [](auto d) {
         return scene_change(d, "friction = 0.3",
                             "friction = 0.3\n[water]\ntable = [[0.0, 0.5], [1.5, 0.5], [1.0, 0.6]]");
       },
       {"water.table", "point 3", "x must increase"}},
      {"NaN in the water table",
       [](auto d) {
         return scene_change(d, "friction = 0.3", "friction = 0.3\n[water]\ntable = [[0.0, nan], [2.0, 0.5]]");
       },
       {"water.table", "point 1", "not finite"}},
      {"water table outside the domain",
       [](auto d) {
         return scene_change(d, "friction = 0.3", "friction = 0.3\n[water]\ntable = [[10.0, 0.5], [12.0, 0.5]]");
       },
       {"water.table", "outside the domain"}},
      {"water table above the ground",
       [](auto d) {
         return scene_change(d, "friction = 0.3", "friction = 0.3\n[water]\ntable = [[0.0, 30.0], [2.0, 30.0]]");
       },
       {"water.table", "above the ground", "follow the ground surface"}},
      {"water table rising above the ground",
       [](auto d) {
         return scene_change(d, "friction = 0.3",
                             "friction = 0.3\n[water]\ntable = [[0.0, -5.0], [2.0, -5.0]]\nrise = [[0.0, 0.0], [1.0, 40.0]]");
       },
       {"water.table", "at its highest rise", "above the ground"}},
      {"unknown water mode",
       [](auto d) {
         return scene_change(d, "friction = 0.3",
                             "friction = 0.3\n[water]\ntable = [[0.0, 0.5], [2.0, 0.5]]\nmode = \"wet\"");
       },
       {"water.mode", "drained or undrained"}},
      {"water rise going back in time",
       [](auto d) {
         return scene_change(d, "friction = 0.3",
                             "friction = 0.3\n[water]\ntable = [[0.0, 0.5], [2.0, 0.5]]\nrise = [[1.0, 0.1], [0.5, 0.2]]");
       },
       {"water.rise", "point 2", "time must increase"}},
      {"porosity of one", [](auto d) { return scene_change(d, "dilation_angle = 0.0", "dilation_angle = 0.0\nporosity = 1.0"); },
       {"materials.rock.porosity", "got 1", "[0, 1)"}},
      {"residual strength without softening_end",
       [](auto d) {
         return scene_change(d, "dilation_angle = 0.0", "dilation_angle = 0.0\nresidual_friction_angle = 20.0");
       },
       {"materials.rock.residual_friction_angle", "softening_end"}},
      {"softening ending before it starts",
       [](auto d) {
         return scene_change(d, "dilation_angle = 0.0",
                             "dilation_angle = 0.0\nsoftening_start = 0.05\nsoftening_end = 0.01");
       },
       {"materials.rock.softening_end", "got 0.01"}},
      {"zero end time", [](auto d) { return scene_change(d, "end_time = 0.01", "end_time = 0.0"); },
       {"run.end_time", "got 0", "(0, inf]"}},
      {"negative end time", [](auto d) { return scene_change(d, "end_time = 0.01", "end_time = -1.0"); },
       {"run.end_time", "got -1"}},
      {"infinite output interval",
       [](auto d) { return scene_change(d, "output_interval = 0.005", "output_interval = inf"); },
       {"run.output_interval", "finite"}},
      {"negative mesh size", [](auto d) { return scene_change(d, "size = 0.25", "size = -0.25"); },
       {"mesh.size", "got -0.25"}},
      {"unknown mesh pattern", [](auto d) { return scene_change(d, "size = 0.25", "size = 0.25\npattern = \"cross\""); },
       {"mesh.pattern", "unknown pattern 'cross'", "expected delaunay, crossed or grid"}},
      {"unknown shape functions",
       [](auto d) { return scene_change(d, "end_time = 0.01", "end_time = 0.01\nshape_functions = \"cubic\""); },
       {"run.shape_functions", "unknown shape functions 'cubic'", "linear, bspline or cpdi"}},
      {"CPDI with mixed integration",
       [](auto d) {
         return scene_change(d, "end_time = 0.01", "end_time = 0.01\nshape_functions = \"cpdi\"\nintegration = \"mixed\"");
       },
       {"run.integration", "\"mixed\" is for linear triangles", "CPDI"}},
      {"B-splines on Delaunay triangles",
       [](auto d) {
         return scene_change(d, "end_time = 0.01", "end_time = 0.01\nshape_functions = \"bspline\"") +
                " --set mesh.pattern=delaunay";
       },
       {"run.shape_functions", "mesh.pattern is \"delaunay\"", "grid"}},
      {"damping of one", [](auto d) { return scene_change(d, "damping = 0.0", "damping = 1.0"); },
       {"run.damping", "[0, 1)"}},
      {"NaN in gravity", [](auto d) { return scene_change(d, "gravity = [0.0, -9.81]", "gravity = [0.0, nan]"); },
       {"run.gravity", "finite"}},
      {"density of the wrong type", [](auto d) { return scene_change(d, "density = 2000.0", "density = \"heavy\""); },
       {"materials.rock.density", "expected a number"}},
      {"boolean of the wrong type", [](auto d) { return scene_change(d, "evs = false", "evs = 1"); },
       {"run.evs", "expected true or false"}},
      {"animate of the wrong type", [](auto d) { return scene_row(d, kScene, "--set post.animate=1"); },
       {"block.toml", "post.animate", "expected true or false"}},
      {"unknown body in post.bodies", [](auto d) { return scene_row(d, kScene, "--set 'post.bodies=[\"blok\"]'"); },
       {"block.toml", "post.bodies", "no body named 'blok'", "did you mean 'block'?"}},
      {"body listed twice in post.bodies",
       [](auto d) { return scene_row(d, kScene, "--set 'post.bodies=[\"block\", \"block\"]'"); },
       {"block.toml", "post.bodies", "listed twice"}},
      {"empty post.bodies", [](auto d) { return scene_row(d, kScene, "--set 'post.bodies=[]'"); },
       {"block.toml", "post.bodies", "at least one body"}},
      {"fractional particles per cell",
       [](auto d) { return scene_change(d, "particles_per_cell = 4", "particles_per_cell = 4.5"); },
       {"bodies.block.particles_per_cell", "expected an integer"}},
      {"unsupported particles per cell",
       [](auto d) { return scene_change(d, "particles_per_cell = 4", "particles_per_cell = 5"); },
       {"bodies.block.particles_per_cell", "expected 1, 3, 4, 6 or 10"}},
      {"unknown material model", [](auto d) { return scene_change(d, "\"mohr_coulomb\"", "\"plasticine\""); },
       {"materials.rock.model", "plasticine", "linear_elastic, mohr_coulomb or mu_i"}},
      {"body named like a reserved dataset", [](auto d) { return scene_change(d, "[bodies.block]", "[bodies.names]\ngroup = \"block\""); },
       {"bodies.names", "not 'names'"}},
      {"load on a curve off every body's outline",
       [](auto d) { return scene_change(d, "[contact]", "[loads.push]\ngroup = \"speck\"\npressure = 1000.0\n\n[contact]"); },
       {"block.toml", "loads.push", "speck", "not on any body's outline"}},
      {"load with both pressure and traction",
       [](auto d) {
         return scene_change(d, "[contact]", "[loads.push]\ngroup = \"base\"\npressure = 1.0\ntraction = [1.0, 0.0]\n\n[contact]");
       },
       {"block.toml", "loads.push.traction", "either pressure", "not both"}},
      {"load with neither pressure nor traction",
       [](auto d) { return scene_change(d, "[contact]", "[loads.push]\ngroup = \"base\"\n\n[contact]"); },
       {"block.toml", "loads.push.pressure", "missing"}},
      {"NaN load pressure",
       [](auto d) { return scene_change(d, "[contact]", "[loads.push]\ngroup = \"base\"\npressure = nan\n\n[contact]"); },
       {"block.toml", "loads.push.pressure", "got nan", "finite"}},
      {"NaN in a load traction",
       [](auto d) { return scene_change(d, "[contact]", "[loads.push]\ngroup = \"base\"\ntraction = [nan, 0.0]\n\n[contact]"); },
       {"block.toml", "loads.push.traction", "finite"}},
      {"load on a surface",
       [](auto d) { return scene_change(d, "[contact]", "[loads.push]\ngroup = \"block\"\npressure = 1.0\n\n[contact]"); },
       {"block.geo", "block", "loads.push", "a load needs a physical curve"}},
      {"bad TOML syntax", [](auto d) { return scene_change(d, "[run]", "[run"); },
       {"block.toml", "not valid TOML", "line 7"}},
      {"--set with an empty key part", [](auto d) { return scene_row(d, kScene, "--set run.=2"); },
       {"--set run.=2", "expected KEY=VALUE"}},
      {"missing scene file", [](auto d) { return "mesh " + (d / "nowhere.toml").string(); },
       {"nowhere.toml", "no such scene file"}},
      // .geo files.
      {"missing .geo", [](auto d) { return scene_change(d, "block.geo", "nowhere.geo"); },
       {"nowhere.geo", "no such geometry file"}},
      {"unparsable .geo",
       [](auto d) {
         write_file(d / "bad.geo", "Point(1) = {0, 0, 0};\nLine(1) = {1, 2\n");
         return scene_change(d, "block.geo", "bad.geo");
       },
       {"bad.geo", "syntax error"}},
      {"physical group missing from the .geo",
       [](auto d) { return scene_change(d, "material = \"rock\"", "material = \"rock\"\ngroup = \"granite\""); },
       {"block.geo", "granite", "bodies.block", "not a physical group", "speck"}},
      {"physical curve name with a '/'",
       [](auto d) {
         write_file(d / "slash.geo", replaced(kGeo, "Physical Curve(\"base\")", "Physical Curve(\"ba/se\")"));
         return "mesh " + write_file(d / "block.toml", replaced(kScene, "block.geo", "slash.geo"));
       },
       {"slash.geo", "Physical Curve(\"ba/se\")", "without '/'"}},
      {"domain missing from the .geo", [](auto d) { return scene_change(d, "size = 0.25", "size = 0.25\ndomain = \"ground\""); },
       {"block.geo", "ground", "mesh.domain"}},
      {"mesh too fine for the memory", [](auto d) { return scene_row(d, kScene, "--set mesh.size=1e-5"); },
       {"block.toml", "mesh.size", "triangles", "particles", "GB", "MemAvailable"}},
      {"body smaller than an element",
       [](auto d) { return scene_change(d, "material = \"rock\"", "material = \"rock\"\ngroup = \"speck\""); },
       {"block.toml", "bodies.block", "too coarse", "element"}},
      // HDF5 models through `talus solve`.
      {"truncated model", [](auto d) { return model_row(d, [](auto p) { truncate_file(p, 0.5); }); },
       {"model.h5", "truncated"}},
      {"empty model file", [](auto d) { return model_row(d, [](auto p) { truncate_file(p, 0); }); },
       {"model.h5", "not an HDF5 file"}},
      {"text file named .h5",
       [](auto d) { return model_row(d, [](auto p) { write_file(p, "[scene]\nname = \"not hdf5\"\n"); }); },
       {"model.h5", "not an HDF5 file"}},
      {"wrong format tag",
       [](auto d) {
         return model_row(d, [](auto p) {
           edit_h5(p, [](auto& f) { h5::set_attribute(f, "/", "format", std::string("talus-results")); });
         });
       },
       {"model.h5", "not a Talus talus-model file"}},
      {"load index out of range in a model",
       [](auto d) { return loaded_model_row(d, [](auto p) { set_int(p, "particles/load", 3, 7); }); },
       {"model.h5", "particles/load", "load index out of range for particle 3"}},
      {"negative load length in a model",
       [](auto d) { return loaded_model_row(d, [](auto p) { set_double(p, "particles/load_length", 0, -1.0); }); },
       {"model.h5", "particles/load_length", "particle 0"}},
      {"model load with a NaN pressure",
       [](auto d) {
         return loaded_model_row(d, [](auto p) {
           edit_h5(p, [](auto& f) { h5::set_attribute(f, "loads/push", "pressure", std::nan("")); });
         });
       },
       {"model.h5", "loads/push", "pressure: expected a finite number"}},
      {"older format version",
       [](auto d) {
         return model_row(d, [](auto p) {
           edit_h5(p, [](auto& f) { h5::set_attribute(f, "/", "format_version", int64_t{0}); });
         });
       },
       {"model.h5", "format_version", "file has version 0", "reads version 1"}},
      {"missing dataset",
       [](auto d) {
         return model_row(d, [](auto p) { edit_h5(p, [](auto& f) { H5Ldelete(f.id(), "particles/mass", H5P_DEFAULT); }); });
       },
       {"model.h5", "particles/mass", "missing dataset"}},
      {"NaN particle position",
       [nan](auto d) { return model_row(d, [nan](auto p) { set_double(p, "particles/position", 7, nan); }); },
       {"model.h5", "particles/position", "non-finite"}},
      {"NaN particle stress",
       [nan](auto d) { return model_row(d, [nan](auto p) { set_double(p, "particles/stress", 3, nan); }); },
       {"model.h5", "particles/stress", "non-finite"}},
      {"negative particle mass",
       [](auto d) { return model_row(d, [](auto p) { set_double(p, "particles/mass", 2, -1.0); }); },
       {"model.h5", "particles/mass", "particle 2", "non-positive"}},
      {"element index out of range",
       [](auto d) { return model_row(d, [](auto p) { set_int(p, "particles/element", 0, 100000); }); },
       {"model.h5", "particles/element", "out of range"}},
      {"triangle node index out of range",
       [](auto d) { return model_row(d, [](auto p) { set_int(p, "mesh/triangles", 4, -3); }); },
       {"model.h5", "mesh/triangles", "out of range in row 1"}},
      {"dataset of the wrong shape",
       [](auto d) {
         return model_row(d, [](auto p) {
           edit_h5(p, [](auto& f) { h5::write(f, "particles/velocity", std::vector<double>(9, 0.0), {3, 3}); });
         });
       },
       {"model.h5", "particles/velocity", "expected shape"}},
      {"per-particle dataset with rows but no values (found by fuzzing)",
       [](auto d) {
         return model_row(d, [](auto p) {
           edit_h5(p, [](auto& f) {
             h5::write(f, "particles/volume", std::vector<double>{}, {h5::shape(f, "particles/volume")[0], 0});
           });
         });
       },
       {"model.h5", "particles/volume", "expected shape"}},
      {"run settings out of range in the model",
       [](auto d) {
         return model_row(d, [](auto p) { edit_h5(p, [](auto& f) { h5::set_attribute(f, "settings/run", "cfl", 2.0); }); });
       },
       {"model.h5", "settings/run", "out of range"}},
      {"material out of range in the model (the scene's check)",
       [](auto d) {
         return model_row(d, [](auto p) {
           edit_h5(p, [](auto& f) {
             const std::string material = "materials/" + h5::read_strings(f, "materials/names").at(0);
             h5::set_attribute(f, material, "poisson_ratio", 0.5);
           });
         });
       },
       {"model.h5", "@poisson_ratio", "got 0.5", "[0, 0.5)"}},
      {"results file handed to solve", [](auto d) { return results_row(d, [](auto) {}).replace(0, 4, "solve"); },
       {"results.h5", "not a Talus talus-model file"}},
      {"restart without a checkpoint", [](auto d) { return model_row(d, [](auto) {}) + " --restart"; },
       {"checkpoint.h5", "no checkpoint to restart from"}},
      {"unknown solve option", [](auto d) { return model_row(d, [](auto) {}) + " --checkpoint-intervl=1"; },
       {"unknown option '--checkpoint-intervl=1'"}},
      {"negative checkpoint interval", [](auto d) { return model_row(d, [](auto) {}) + " --checkpoint-interval -1"; },
       {"--checkpoint-interval", "'-1'"}},
      // Results through `talus post`.
      {"results of another format version",
       [](auto d) {
         return results_row(d, [](auto p) {
           edit_h5(p, [](auto& f) { h5::set_attribute(f, "/", "format_version", int64_t{2}); });
         });
       },
       {"results.h5", "file has version 2", "reads version 1"}},
      {"bonded pair not a boolean",
       [](auto d) { return pairs_row(d, kOther, "[[contact.pairs]]\nbodies = [\"block\", \"other\"]\nbonded = 1\n"); },
       {"block.toml", "contact.pairs[0].bonded", "expected true or false"}},
      {"bonded pair with friction",
       [](auto d) {
         return pairs_row(d, kOther, "[[contact.pairs]]\nbodies = [\"block\", \"other\"]\nbonded = true\nfriction = 0.2\n");
       },
       {"block.toml", "contact.pairs[0].friction", "a bonded pair takes no friction"}},
      {"contact pair naming an unknown body",
       [](auto d) { return pairs_row(d, kOther, "[[contact.pairs]]\nbodies = [\"block\", \"ghost\"]\nbonded = true\n"); },
       {"block.toml", "contact.pairs[0].bodies", "no body named 'ghost'"}},
      {"contact pair listed twice",
       [](auto d) {
         return pairs_row(d, kOther,
                          "[[contact.pairs]]\nbodies = [\"block\", \"other\"]\nbonded = true\n\n"
                          "[[contact.pairs]]\nbodies = [\"other\", \"block\"]\nfriction = 0.1\n");
       },
       {"block.toml", "contact.pairs[1].bodies", "listed twice", "contact.pairs[0]"}},
      {"bonded bodies meeting a third with two coefficients",
       [](auto d) {
         return pairs_row(d, std::string(kOther) + "\n[bodies.third]\nmaterial = \"rock\"\ngroup = \"speck\"\n",
                          "[[contact.pairs]]\nbodies = [\"block\", \"other\"]\nbonded = true\n\n"
                          "[[contact.pairs]]\nbodies = [\"other\", \"third\"]\nfriction = 0.5\n");
       },
       {"block.toml", "contact.pairs", "one friction coefficient", "'block'-'third' has 0.3", "'other'-'third' has 0.5"}},
      {"bonded fixed and moving bodies",
       [](auto d) {
         return pairs_row(d, std::string(kOther) + "fixed = true\n",
                          "[[contact.pairs]]\nbodies = [\"block\", \"other\"]\nbonded = true\n");
       },
       {"block.toml", "contact.pairs", "mix fixed and moving bodies"}},
      {"model with a bonded pair naming an unknown body",
       [](auto d) { return paired_model_row(d, {"block", "ghost"}, 1); },
       {"model.h5", "settings/contact", "no body named 'ghost'"}},
      {"model with a pair_bonded flag of 2",
       [](auto d) { return paired_model_row(d, {"block", "block"}, 2); },
       {"model.h5", "settings/contact/pair_bonded", "expected 0 or 1"}},
      {"model with pair_bonded of another length",
       [](auto d) {
         return model_row(d, [](auto p) {
           edit_h5(p, [](auto& f) { h5::write(f, "settings/contact/pair_bonded", std::vector<int32_t>{0}, {1}); });
         });
       },
       {"model.h5", "settings/contact", "pair_bonded and pair_friction disagree"}},
      {"model handed to post", [](auto d) { return model_row(d, [](auto) {}, "post"); },
       {"model.h5", "not a Talus talus-results file"}},
  };
}

TEST(BadInput, TheBaseInputsAreValid) {
  ScratchDir dir("bad-input-base");
  auto meshed = testing::run_talus(scene_row(dir.path(), kScene) + " --out " + dir.file("out"));
  EXPECT_EQ(meshed.status, 0) << meshed.output;
  EXPECT_TRUE(fs::exists(dir.file("out/model.h5")));
  auto solved = testing::run_talus(model_row(dir.path(), [](auto) {}) + " --quiet --out " + dir.file("solved"));
  EXPECT_EQ(solved.status, 0) << solved.output;
  EXPECT_TRUE(fs::exists(dir.file("solved/results.h5")));
}

TEST(BadInput, EveryRowStopsWithOneClearMessageAndLeavesNothing) {
  const auto table = rows();
  EXPECT_GE(table.size(), 30u);
  testing::expect_rows_fail_cleanly(table);
}

}  // namespace
}  // namespace talus
