// The scene's [random.NAME] tables (common/scene_random.cpp): a good table read back, and each
// bad key refused with one talus::Error naming the file and the key.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "common/error.hpp"
#include "common/scene.hpp"
#include "support/bad_input_table.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

std::string message_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no talus::Error";
  return "";
}

// The scene's [random.NAME] tables (common/scene_random.cpp), read by load_scene from the bad-input
// table's small valid scene with two fields added.
const char* const kRandomTables = R"(
[random.cohesion]
material = "rock"
parameter = "cohesion"
distribution = "lognormal"
mean = 10e3
cov = 0.3
correlation_length = [20.0, 2.0]
correlation = "markov"

[random.friction]
material = "rock"
parameter = "friction_angle"
distribution = "normal"
mean = 30.0
cov = 0.1
correlation_length = [20.0, 2.0]
cross_correlation = { with = "cohesion", rho = -0.5 }
)";

std::string random_scene(const testing::ScratchDir& dir, const std::string& tables,
                         const std::string& extra_material = "") {
  testing::write_file(dir.path() / "block.geo", testing::kGeo);
  return testing::write_file(dir.path() / "block.toml", testing::kScene + extra_material + tables);
}

TEST(RandomScene, TablesAreReadBack) {
  const testing::ScratchDir dir("random-scene");
  const Scene scene = load_scene(random_scene(dir, kRandomTables), {"random.friction.cov=0.15"});
  ASSERT_EQ(scene.random.size(), 2u);
  const RandomField& c = scene.random[0];
  EXPECT_EQ(c.name, "cohesion");
  EXPECT_EQ(c.material, "rock");
  EXPECT_EQ(c.parameter, "cohesion");
  EXPECT_EQ(c.distribution, RandomDistribution::Lognormal);
  EXPECT_EQ(c.mean, 10e3);
  EXPECT_EQ(c.cov, 0.3);
  EXPECT_EQ(c.correlation_length, Eigen::Vector2d(20, 2));
  EXPECT_EQ(c.correlation, Correlation::Markov);
  EXPECT_EQ(c.cross_with, "");
  const RandomField& f = scene.random[1];
  EXPECT_EQ(f.parameter, "friction_angle");
  EXPECT_EQ(f.distribution, RandomDistribution::Normal);
  EXPECT_EQ(f.cov, 0.15);  // from --set
  EXPECT_EQ(f.cross_with, "cohesion");
  EXPECT_EQ(f.cross_rho, -0.5);
  // The defaults, and inf for a fully correlated axis.
  std::string tables = testing::replaced(kRandomTables, "correlation = \"markov\"\n", "");
  for (int k = 0; k < 2; ++k) tables = testing::replaced(tables, "[20.0, 2.0]", "[inf, inf]");
  const Scene fully = load_scene(random_scene(dir, tables));
  EXPECT_EQ(fully.random[0].correlation, Correlation::Markov);
  EXPECT_TRUE(std::isinf(fully.random[0].correlation_length.x()));
  EXPECT_TRUE(load_scene(random_scene(dir, "")).random.empty());
}

struct BadTable {
  std::string what, from, to;  // the change to kRandomTables
  std::string item;            // the dotted key the one message must name
};

TEST(RandomScene, EachBadKeyIsOneErrorNamingIt) {
  const std::string steel = "\n[materials.steel]\nmodel = \"linear_elastic\"\ndensity = 7800.0\n"
                            "youngs_modulus = 2e11\npoisson_ratio = 0.3\n";
  const std::string strength = "\n[random.strength]\nmaterial = \"rock\"\nparameter = \"cohesion\"\n"
                               "distribution = \"normal\"\nmean = 5e3\ncov = 0.2\ncorrelation_length = [5.0, 1.0]\n";
  const std::string pair = "cross_correlation = { with = \"cohesion\", rho = -0.5 }";
  const std::vector<BadTable> rows = {
      {"unknown key", "correlation = \"markov\"\n", "correlation = \"markov\"\ncolour = 1\n", "random.cohesion.colour"},
      {"not a table", "\n[random.cohesion]", "\n[random]\nbad = 5\n[random.cohesion]", "random.bad"},
      {"name not a word", "[random.cohesion]", "[random.\"co hesion\"]", "random.co hesion"},
      {"bad distribution", "\"lognormal\"", "\"weibull\"", "random.cohesion.distribution"},
      {"cov 0", "cov = 0.3", "cov = 0.0", "random.cohesion.cov"},
      {"cov < 0", "cov = 0.3", "cov = -0.3", "random.cohesion.cov"},
      {"cov inf", "cov = 0.3", "cov = inf", "random.cohesion.cov"},
      {"NaN mean", "mean = 10e3", "mean = nan", "random.cohesion.mean"},
      {"no mean", "mean = 10e3\n", "", "random.cohesion.mean"},
      {"mean out of range", "mean = 30.0", "mean = 95.0", "random.friction.mean"},
      {"mean beyond another parameter", "parameter = \"cohesion\"\ndistribution = \"lognormal\"\nmean = 10e3",
       "parameter = \"dilation_angle\"\ndistribution = \"lognormal\"\nmean = 35.0", "random.cohesion.mean"},
      {"uniform out of range", "\"lognormal\"\nmean = 10e3\ncov = 0.3", "\"uniform\"\nmean = 10e3\ncov = 0.7",
       "random.cohesion.cov"},
      {"unknown material", "material = \"rock\"\nparameter = \"cohesion\"",
       "material = \"clay\"\nparameter = \"cohesion\"", "random.cohesion.material"},
      {"parameter not allowed", "parameter = \"cohesion\"", "parameter = \"density\"", "random.cohesion.parameter"},
      {"parameter of another model", "correlation = \"markov\"\n",
       "correlation = \"markov\"\n" + steel + "\n[random.x]\nmaterial = \"steel\"\nparameter = \"cohesion\"\n",
       "random.x.parameter"},
      {"residual without softening", "parameter = \"cohesion\"", "parameter = \"residual_cohesion\"",
       "random.cohesion.parameter"},
      {"same material and parameter", "correlation = \"markov\"\n", "correlation = \"markov\"\n" + strength,
       "random.strength.parameter"},
      {"lengths not two", "[20.0, 2.0]\ncorrelation", "[20.0]\ncorrelation", "random.cohesion.correlation_length"},
      {"length 0", "[20.0, 2.0]\ncorrelation", "[20.0, 0.0]\ncorrelation", "random.cohesion.correlation_length"},
      {"length NaN", "[20.0, 2.0]\ncorrelation", "[nan, 2.0]\ncorrelation", "random.cohesion.correlation_length"},
      {"no lengths", "correlation_length = [20.0, 2.0]\ncorrelation", "correlation",
       "random.cohesion.correlation_length"},
      {"bad correlation", "\"markov\"", "\"spherical\"", "random.cohesion.correlation"},
      {"cross_correlation not a table", pair, "cross_correlation = 0.5", "random.friction.cross_correlation"},
      {"missing partner", "with = \"cohesion\"", "with = \"strength\"", "random.friction.cross_correlation.with"},
      {"self", "with = \"cohesion\"", "with = \"friction\"", "random.friction.cross_correlation.with"},
      {"rho 1", "rho = -0.5", "rho = 1.0", "random.friction.cross_correlation.rho"},
      {"|rho| > 1", "rho = -0.5", "rho = -1.5", "random.friction.cross_correlation.rho"},
      {"no rho", ", rho = -0.5", "", "random.friction.cross_correlation.rho"},
      {"unknown key in the pair", "rho = -0.5", "rho = -0.5, lag = 1.0", "random.friction.cross_correlation.lag"},
      {"pair given twice", "correlation = \"markov\"\n",
       "correlation = \"markov\"\ncross_correlation = { with = \"friction\", rho = -0.5 }\n",
       "random.cohesion.cross_correlation.with"},
      {"pair of two correlations", "[20.0, 2.0]\ncross", "[10.0, 2.0]\ncross", "random.friction.cross_correlation.with"},
  };
  for (const BadTable& row : rows) {
    const testing::ScratchDir dir("random-scene");
    const std::string path = random_scene(dir, testing::replaced(kRandomTables, row.from, row.to));
    const std::string message = message_of([&] { load_scene(path); });
    EXPECT_EQ(message.rfind(path + ": " + row.item + ": ", 0), 0u) << row.what << ": " << message;
  }
}

}  // namespace
}  // namespace talus
