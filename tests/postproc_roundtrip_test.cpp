// run_post end to end on small results.h5 files written here with the HDF5 wrapper: a slope
// whose slide is a rigid rotation about a known circle's centre, the same slope mirrored, and
// a spring-and-mass record. Checks metrics.json (parsed back minimally), the CSVs and the PNGs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "postproc/output.hpp"
#include "postproc/postproc.hpp"
#include "postproc/results.hpp"
#include "support/test_support.hpp"
#include "postproc/runout.hpp"

namespace talus::postproc {
namespace {

constexpr double kSpacing = 0.5;
const Polyline kOutline = {{0, 0}, {60, 0}, {60, 5}, {30, 5}, {20, 15}, {0, 15}};
const Eigen::Vector2d kCentre(26, 21);
const double kRadius = std::sqrt(16.0 + 256.0);

Model slope_metadata(const Polyline& outline) {
  Model model;
  model.scene_name = "synthetic_slope";
  BodyInfo body;
  body.name = "slope";
  body.loops = {outline};
  model.bodies = {body};
  Material sand = testing::mohr_coulomb(1800, 1e7, 0.3, 30, 1e3);
  sand.name = "sand";
  model.materials = {sand};
  model.post.metrics = {"runout", "failure_surface", "bishop"};
  model.post.body = "slope";
  return model;
}

// Frames at t = 0, 0.5, 1, 1.5 s: the particles inside the circle rotate about its centre by
// 0, 10, 20, 20 degrees counter-clockwise, which carries the toe downhill (a rotational slide
// that comes to rest).
Results rotational_slide(bool mirrored) {
  const double side = mirrored ? -1 : 1;
  Polyline outline;
  for (const auto& p : kOutline) outline.emplace_back(side * p.x(), p.y());
  Results r;
  r.metadata = slope_metadata(outline);
  const SlopeProfile profile = slope_profile(kOutline);
  for (double x = kSpacing / 2; x < 60; x += kSpacing)
    for (double y = kSpacing / 2; y < 15; y += kSpacing)
      if (y < surface_height(profile.surface, x)) r.initial_position.emplace_back(x, y);
  const std::size_t n = r.initial_position.size();
  r.body.assign(n, 0);
  r.volume.assign(n, kSpacing * kSpacing);
  r.mass.assign(n, 1800 * kSpacing * kSpacing);
  const std::vector<double> angles = {0, 10, 20, 20};
  for (std::size_t f = 0; f < angles.size(); ++f) {
    const double a = angles[f] * M_PI / 180;
    const Eigen::Matrix2d rotation = (Eigen::Matrix2d() << std::cos(a), -std::sin(a), std::sin(a), std::cos(a)).finished();
    std::vector<Eigen::Vector2d> x(n), v(n, Eigen::Vector2d::Zero());
    std::vector<double> eps(n);
    for (std::size_t p = 0; p < n; ++p) {
      const Eigen::Vector2d& x0 = r.initial_position[p];
      const double d = (x0 - kCentre).norm() - kRadius;
      x[p] = d < 0 ? Eigen::Vector2d(kCentre + rotation * (x0 - kCentre)) : x0;
      if (d < 0 && f == 1) v[p] = 0.4 * Eigen::Vector2d(kCentre.y() - x0.y(), x0.x() - kCentre.x());
      eps[p] = 0.1 * angles[f] * std::exp(-d * d / 0.18);
    }
    r.frame_time.push_back(0.5 * f);
    r.position.push_back(x);
    r.velocity.push_back(v);
    r.plastic_strain.push_back(eps);
  }
  for (int k = 0; k <= 30; ++k) {
    const double t = 0.05 * k;
    r.history_time.push_back(t);
    r.kinetic_energy.push_back(t < 0.5 ? 1e5 * t : 5e4 * std::exp(-(t - 0.5) / 0.1));
    r.potential_energy.push_back(1e7 - 2e5 * std::min(t, 1.0));
    r.strain_energy.push_back(1e4);
  }
  if (mirrored) {
    for (auto& p : r.initial_position) p.x() = -p.x();
    for (auto& frame : r.position)
      for (auto& p : frame) p.x() = -p.x();
    for (auto& frame : r.velocity)
      for (auto& v : frame) v.x() = -v.x();
  }
  return r;
}

using testing::read_text;

// The number after "key": (searching from `after`, the position of an enclosing key).
double number(const std::string& json, const std::string& key, const std::string& after = "") {
  const std::size_t start = after.empty() ? 0 : json.find("\"" + after + "\"");
  const std::size_t at = json.find("\"" + key + "\": ", start);
  EXPECT_NE(at, std::string::npos) << key;
  if (at == std::string::npos) return NAN;
  const char* value = json.c_str() + at + key.size() + 4;
  char* end = nullptr;
  const double parsed = std::strtod(value, &end);
  EXPECT_NE(end, value) << key << " is not a number";
  return end == value ? NAN : parsed;
}

std::string script() { return testing::source_path("postproc/figures.py"); }

TEST(RunPost, SlopeMetricsJsonCsvAndFigures) {
  testing::ScratchDir dir("postproc-roundtrip");
  const Results written = rotational_slide(false);
  write_results(dir.file("results.h5"), written);

  std::ostringstream log;
  const int status = run_post(dir.file("results.h5"), dir.path().string(), log, {script()});
  EXPECT_EQ(status, 0) << log.str();
  const std::string json = read_text(dir.file("metrics.json"));
  for (const char* key : {"runout_distance_m", "crest_retreat_m", "travel_angle_deg", "failed_area_m2", "slip_circle",
                          "bishop_fos", "bishop_circle", "failure_surface", "time_to_rest_s", "shear_band"})
    EXPECT_NE(json.find("\"" + std::string(key) + "\""), std::string::npos) << key;

  // The values are those of the library functions on the same particles.
  const SlopeProfile profile = slope_profile(kOutline);
  const RunoutMetrics expected = runout_metrics(profile, written.initial_position, written.position.back(),
                                                0.05 * profile.height, column_rule_for(written.volume));
  ASSERT_TRUE(expected.deposit_found);
  EXPECT_GT(expected.runout_distance, 0);
  EXPECT_NEAR(number(json, "runout_distance_m"), expected.runout_distance, 1e-8);
  EXPECT_NEAR(number(json, "crest_retreat_m"), expected.crest_retreat, 1e-8);
  EXPECT_NEAR(number(json, "travel_angle_deg"), *expected.travel_angle_deg, 1e-7);

  double moved_area = 0;
  for (const auto& p : written.initial_position)
    if ((p - kCentre).norm() < kRadius) moved_area += kSpacing * kSpacing;
  EXPECT_NEAR(number(json, "failed_area_m2"), moved_area, 1e-8);
  // The rotation's circle is the slip circle (to within the particle spacing).
  EXPECT_NEAR(number(json, "xc_m", "slip_circle"), kCentre.x(), 0.75);
  EXPECT_NEAR(number(json, "yc_m", "slip_circle"), kCentre.y(), 0.75);
  EXPECT_NEAR(number(json, "r_m", "slip_circle"), kRadius, 0.75);
  EXPECT_GT(number(json, "bishop_fos"), 0.5);
  EXPECT_LT(number(json, "bishop_fos"), 5);
  // Kinetic energy falls below 1% of its 5e4 J peak at t = 0.5 + 0.1 ln 100 = 0.96 s: the
  // first record after that is at 1.0 s.
  EXPECT_NEAR(number(json, "time_to_rest_s"), 1.0, 1e-9);
  EXPECT_NEAR(number(json, "onset_time_s"), 0.5, 1e-12);

  const std::string front = read_text(dir.file("front.csv"));
  EXPECT_EQ(front.substr(0, front.find('\n')), "time_s,front_x_m,front_velocity_m_s");
  EXPECT_EQ(std::count(front.begin(), front.end(), '\n'), 5);
  const std::string energy = read_text(dir.file("energy.csv"));
  EXPECT_EQ(energy.substr(0, energy.find('\n')), "time_s,kinetic_J,potential_J,strain_J");
  EXPECT_EQ(std::count(energy.begin(), energy.end(), '\n'), 32);
  for (const char* png : {"deformed.png", "front.png", "energy.png"})
    EXPECT_GT(std::filesystem::file_size(dir.file(png)), 10000u) << png;
  EXPECT_FALSE(std::filesystem::exists(dir.file("metrics.json.tmp")));

  // The movie: 4 frames at 5 a second (the fewest), the last held for a second (5 more); the
  // GIF beside it. ffmpeg is one of the packages ./talus installs.
  const auto probe = testing::run_shell("ffprobe -v error -count_frames -select_streams v:0 -show_entries "
                                        "stream=nb_read_frames,codec_name,r_frame_rate -of csv=p=0 " +
                                        dir.file("runout.mp4"));
  EXPECT_EQ(probe.status, 0) << probe.output;
  EXPECT_EQ(probe.output, "h264,5/1,9\n");
  EXPECT_EQ(read_text(dir.file("runout.gif")).substr(0, 6), "GIF89a");
  for (const char* left : {"runout.mp4.tmp", "runout.gif.tmp"}) EXPECT_FALSE(std::filesystem::exists(dir.file(left)));
  const char* keep = std::getenv("TALUS_KEEP_POSTPROC_TEST");  // to look at the figures
  if (keep) std::filesystem::copy(dir.path(), keep, std::filesystem::copy_options::recursive |
                                                        std::filesystem::copy_options::overwrite_existing);
}

TEST(RunPost, MirroredSlopeGivesMirroredMetrics) {
  testing::ScratchDir dir("postproc-mirror");
  write_results(dir.file("right.h5"), rotational_slide(false));
  write_results(dir.file("left.h5"), rotational_slide(true));
  std::ostringstream log;
  PostOptions no_figures;
  no_figures.figures = false;
  run_post(dir.file("right.h5"), dir.file("right"), log, no_figures);
  run_post(dir.file("left.h5"), dir.file("left"), log, no_figures);
  const std::string right = read_text(dir.file("right/metrics.json"));
  const std::string left = read_text(dir.file("left/metrics.json"));
  for (const char* key : {"runout_distance_m", "crest_retreat_m", "travel_angle_deg", "failed_area_m2", "bishop_fos"})
    EXPECT_NEAR(number(left, key), number(right, key), 1e-9) << key;
  EXPECT_NEAR(number(left, "xc_m", "slip_circle"), -number(right, "xc_m", "slip_circle"), 1e-6);
  EXPECT_NEAR(number(left, "xc_m", "bishop_circle"), -number(right, "xc_m", "bishop_circle"), 1e-6);
}

// The same slide as two bodies of one soil (docs/layered.md): a foundation layer below y = 5 and
// the slope above it, both listed in post.bodies. The ground, the runout, the sliding mass and
// Bishop's factor are those of the one body; mirrored too. A load on the crest goes on
// Bishop's slices and lowers F.
Results two_layer_slide(bool mirrored) {
  Results r = rotational_slide(mirrored);
  const double side = mirrored ? -1 : 1;
  BodyInfo slope = r.metadata.bodies[0], foundation = r.metadata.bodies[0];
  slope.loops = {{}};
  for (const auto& p : Polyline{{0, 5}, {30, 5}, {20, 15}, {0, 15}}) slope.loops[0].emplace_back(side * p.x(), p.y());
  foundation.name = "foundation";
  foundation.loops = {{}};
  for (const auto& p : Polyline{{0, 0}, {60, 0}, {60, 5}, {30, 5}, {0, 5}})
    foundation.loops[0].emplace_back(side * p.x(), p.y());
  r.metadata.bodies = {slope, foundation};
  r.metadata.post.bodies = {"slope", "foundation"};
  for (std::size_t p = 0; p < r.body.size(); ++p) r.body[p] = r.initial_position[p].y() < 5 ? 1 : 0;
  return r;
}

TEST(RunPost, TwoLayersOfOneSoilGiveTheOneBodysMetrics) {
  testing::ScratchDir dir("postproc-layers");
  PostOptions no_figures;
  no_figures.figures = false;
  std::ostringstream log;
  write_results(dir.file("one.h5"), rotational_slide(false));
  run_post(dir.file("one.h5"), dir.file("one"), log, no_figures);
  const std::string one = read_text(dir.file("one/metrics.json"));
  for (bool mirrored : {false, true}) {
    const std::string name = mirrored ? "left" : "right";
    write_results(dir.file(name + ".h5"), two_layer_slide(mirrored));
    run_post(dir.file(name + ".h5"), dir.file(name), log, no_figures);
    const std::string two = read_text(dir.file(name + "/metrics.json"));
    EXPECT_NE(two.find("\"bodies\": [\"slope\", \"foundation\"]"), std::string::npos) << two;
    EXPECT_NE(two.find("\"bishop_layers\""), std::string::npos);
    for (const char* key : {"slope_height_m", "runout_distance_m", "crest_retreat_m", "travel_angle_deg",
                            "failed_area_m2", "r_m"})
      EXPECT_NEAR(number(two, key), number(one, key), 1e-9) << key << (mirrored ? " (mirrored)" : "");
    EXPECT_NEAR(number(two, "bishop_fos"), number(one, "bishop_fos"), 1e-6 * number(one, "bishop_fos"));
  }
  EXPECT_NE(log.str().find("bodies slope and foundation"), std::string::npos) << log.str();

  // 20 kPa on the crest between x = 10 and 20 m, carried by the top row of particles there.
  Results loaded = two_layer_slide(false);
  loaded.load_force.assign(loaded.particles(), Eigen::Vector2d::Zero());
  double total = 0;
  for (std::size_t p = 0; p < loaded.particles(); ++p) {
    const auto& x = loaded.initial_position[p];
    if (x.x() > 10 && x.x() < 20 && x.y() > 15 - kSpacing) loaded.load_force[p] = {0, -20e3 * kSpacing}, total += 20e3 * kSpacing;
  }
  write_results(dir.file("loaded.h5"), loaded);
  run_post(dir.file("loaded.h5"), dir.file("loaded"), log, no_figures);
  const std::string json = read_text(dir.file("loaded/metrics.json"));
  EXPECT_NEAR(number(json, "bishop_surcharge_N_m"), total, 1e-6);
  EXPECT_NEAR(total, 20e3 * 10, 1e-6);
  EXPECT_LT(number(json, "bishop_fos"), number(one, "bishop_fos") - 0.01);
}

TEST(RunPost, SpringMassAgainstItsAnalyticalSolution) {
  testing::ScratchDir dir("postproc-spring");
  Results r;
  r.metadata = slope_metadata({{0, 0}, {0.1, 0}, {0.1, 0.05}, {0, 0.05}});
  r.metadata.bodies[0].name = "mass";
  r.metadata.materials[0].model = LinearElastic::Parameters{};
  r.metadata.post.metrics = {"spring_mass"};
  r.metadata.post.body = "mass";
  r.metadata.post.animate = false;
  r.initial_position = {{0.025, 1.0}, {0.075, 1.0}};
  r.body = {0, 0};
  r.mass = {2.5, 2.5};
  r.volume = {0.0025, 0.0025};
  for (int k = 0; k <= 130; ++k) {
    const double t = 1e-3 * k;
    // 2% of the amplitude off, as a solver's error would be.
    const double y = 1.0 - 1e-3 * (1 - std::cos(100 * t)) * 1.02;
    r.frame_time.push_back(t);
    r.position.push_back({{0.025, y}, {0.075, y}});
    r.velocity.push_back({{0, 0}, {0, 0}});
  }
  r.history_time = {0, 0.13};
  r.kinetic_energy = {0, 0};
  r.potential_energy = {0, 0};
  r.strain_energy = {0, 0};
  write_results(dir.file("results.h5"), r);
  std::ostringstream log;
  EXPECT_EQ(run_post(dir.file("results.h5"), dir.path().string(), log, {script()}), 0) << log.str();
  const std::string json = read_text(dir.file("metrics.json"));
  EXPECT_NEAR(number(json, "max_error_over_amplitude", "spring_mass"), 0.04, 1e-3);  // 2% of 2A at the trough
  EXPECT_GT(std::filesystem::file_size(dir.file("spring_mass.png")), 10000u);
  EXPECT_FALSE(std::filesystem::exists(dir.file("runout.mp4")));  // post.animate = false
  EXPECT_FALSE(std::filesystem::exists(dir.file("runout.gif")));
  const char* keep = std::getenv("TALUS_KEEP_POSTPROC_TEST");
  if (keep) std::filesystem::copy_file(dir.file("spring_mass.png"), std::string(keep) + "/spring_mass.png",
                                       std::filesystem::copy_options::overwrite_existing);
}

TEST(RunPost, BoxInclineUsesThePairFriction) {
  testing::ScratchDir dir("postproc-box");
  Results r;
  r.metadata = slope_metadata({{0, 0}, {0.15, 0}, {0.15, 0.1}, {0, 0.1}});
  r.metadata.bodies[0].name = "box";
  BodyInfo surface = r.metadata.bodies[0];
  surface.name = "surface";
  r.metadata.bodies.push_back(surface);
  r.metadata.contact.friction = 0.1;
  r.metadata.contact.pairs = {{"surface", "box", 0.3}};
  r.metadata.run.gravity = {0, -10};
  r.metadata.post.metrics = {"box_incline"};
  r.metadata.post.body = "box";
  r.initial_position = {{0.5, 0.5}, {0.6, 0.5}, {0.5, -1.0}};
  r.body = {0, 0, 1};
  r.mass = {1, 1, 5};
  r.volume = {0.01, 0.01, 0.01};
  const Eigen::Vector2d downhill(-std::cos(M_PI / 6), -std::sin(M_PI / 6));  // down to the left
  for (int k = 0; k <= 20; ++k) {
    const double t = 0.05 * k, s = 1.201 * t * t;  // validation.md: x = 1.201 t^2 for mu = 0.3
    r.frame_time.push_back(t);
    r.position.push_back({r.initial_position[0] + s * downhill, r.initial_position[1] + s * downhill,
                          r.initial_position[2]});
    r.velocity.push_back({{0, 0}, {0, 0}, {0, 0}});
  }
  r.history_time = {0};
  r.kinetic_energy = r.potential_energy = r.strain_energy = {0};
  write_results(dir.file("results.h5"), r);
  std::ostringstream log;
  EXPECT_EQ(run_post(dir.file("results.h5"), dir.path().string(), log, {script()}), 0) << log.str();
  const std::string json = read_text(dir.file("metrics.json"));
  EXPECT_NEAR(number(json, "friction", "box_incline"), 0.3, 1e-12);
  EXPECT_NEAR(number(json, "relative_error", "box_incline"), 0, 1e-3);
  EXPECT_GT(std::filesystem::file_size(dir.file("box_incline.png")), 10000u);
  const char* keep = std::getenv("TALUS_KEEP_POSTPROC_TEST");
  if (keep) std::filesystem::copy_file(dir.file("box_incline.png"), std::string(keep) + "/box_incline.png",
                                       std::filesystem::copy_options::overwrite_existing);
}

TEST(JsonWriter, EscapesAndNulls) {
  JsonWriter json;
  json.begin_object().key("a \"b\"").value("line\nnext").key("nan").value(NAN).key("none").value(std::optional<double>())
      .key("list").value(Polyline{{1, 2}, {3, 4}}).end_object();
  EXPECT_EQ(json.text(), "{\n  \"a \\\"b\\\"\": \"line\\nnext\",\n  \"nan\": null,\n  \"none\": null,\n"
                         "  \"list\": [[1, 2], [3, 4]]\n}\n");
}

}  // namespace
}  // namespace talus::postproc
