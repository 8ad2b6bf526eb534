// The material registry (common/materials/materials.hpp): names to models and back, the one
// parameter visitor that the scene reader, model.h5 and the per-particle properties share, the
// strength that strength reduction and Bishop's method take through the unit, and model.h5's
// materials as the landed build wrote them.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <set>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/materials/materials.hpp"
#include "common/model/model.hpp"
#include "solver/io/checkpoint.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

using testing::ScratchDir;

Material softening_sand() {
  Material m = testing::mohr_coulomb(1800, 1e7, 0.3, 32, 2e3);
  m.name = "sand";
  MohrCoulomb::Parameters& own = parameters_of<MohrCoulomb>(m);
  own.dilation_angle = 4, own.tensile_strength = 500;
  own.softening_start = 0.02, own.softening_end = 0.2;
  own.residual_cohesion = 100, own.residual_friction_angle = 25, own.residual_dilation_angle = 1;
  own.softening_reference_size = 0.5;
  return m;
}

std::vector<std::pair<std::string, double>> values_of(const Material& m) {
  std::vector<std::pair<std::string, double>> out;
  for_each_parameter(m, [&](const Parameter& p, double value) { out.emplace_back(p.name, value); });
  return out;
}

TEST(Registry, EveryModelIsFoundByItsNameAndNoOther) {
  const std::string names = model_names();
  EXPECT_EQ(names, "linear_elastic, mohr_coulomb or mu_i");
  std::size_t found = 0;
  for (const char* name : {"linear_elastic", "mohr_coulomb", "mu_i"}) {
    Material m;
    ASSERT_TRUE(set_model(m, name));
    EXPECT_EQ(model_name(m), name);
    ++found;
  }
  EXPECT_EQ(found, MaterialModels::kCount);
  Material m;
  EXPECT_FALSE(set_model(m, "plasticine"));
  EXPECT_EQ(model_name(m), "linear_elastic");  // the default, untouched
}

// docs/scenes.md's [materials.NAME] table lists exactly the keys the models' visitors list.
TEST(Registry, TheScenesDocumentListsEveryKeyOfEveryModel) {
  const std::string doc = testing::read_text(testing::source_path("docs/scenes.md"));
  const std::size_t start = doc.find("### `[materials.NAME]`");
  ASSERT_NE(start, std::string::npos);
  const std::string table = doc.substr(start, doc.find("\n### ", start + 1) - start);
  std::set<std::string> documented;
  const std::regex row("\\n\\| `([a-z_]+)` \\|");
  for (auto it = std::sregex_iterator(table.begin(), table.end(), row); it != std::sregex_iterator(); ++it)
    documented.insert((*it)[1]);
  std::set<std::string> visited{"model"};
  for (const char* name : {"linear_elastic", "mohr_coulomb", "mu_i"}) {
    Material m;
    set_model(m, name);
    for (const auto& [key, value] : values_of(m)) visited.insert(key);
  }
  EXPECT_EQ(documented, visited);
}

TEST(Registry, ASlotWritesTheParameterItNames) {
  Material m = softening_sand();
  double value = 1000;
  for (const auto& [key, old] : values_of(m)) {
    const std::optional<ParameterSlot> slot = parameter_slot(m, key);
    ASSERT_TRUE(slot) << key;
    set_parameter(m, *slot, ++value);
    for (const auto& [other, now] : values_of(m)) EXPECT_EQ(now == value, other == key) << key << " wrote " << other;
  }
  EXPECT_FALSE(parameter_slot(m, "stiffness"));
  EXPECT_FALSE(parameter_slot(testing::elastic(2000, 1e7, 0.3), "cohesion"));  // not a key of that model
}

TEST(Registry, ARangeMayDependOnTheParametersBeforeIt) {
  Material m = softening_sand();
  EXPECT_EQ(find_parameter(m, "dilation_angle")->range.max, 32);
  EXPECT_EQ(find_parameter(m, "residual_dilation_angle")->range.max, 25);
  EXPECT_EQ(find_parameter(m, "softening_end")->range.min, 0.02);
  EXPECT_STREQ(find_parameter(m, "cohesion")->unit, "Pa");
  EXPECT_FALSE(find_parameter(testing::elastic(2000, 1e7, 0.3), "friction_angle"));
  // The rules across parameters come after the ranges.
  parameters_of<MohrCoulomb>(m).residual_cohesion = 0;
  parameters_of<MohrCoulomb>(m).residual_friction_angle = 0;
  parameters_of<MohrCoulomb>(m).residual_dilation_angle = 0;
  EXPECT_EQ(material_problem(m)->key, "residual_cohesion");
  parameters_of<MohrCoulomb>(m).softening_end = 0;  // off: the residual strength does not matter
  EXPECT_FALSE(material_problem(m));
}

TEST(Registry, StrengthIsReachedThroughTheUnit) {
  const Material sand = softening_sand(), rock = testing::elastic(2400, 3e10, 0.2);
  EXPECT_TRUE(has_strength(sand));
  EXPECT_FALSE(has_strength(rock));
  const Material reduced_sand = reduced(sand, 2);
  const MohrCoulomb::Parameters& r = parameters_of<MohrCoulomb>(reduced_sand);
  EXPECT_EQ(r.cohesion, 1e3);
  EXPECT_EQ(r.residual_cohesion, 50);
  EXPECT_EQ(r.tensile_strength, 250);
  EXPECT_NEAR(std::tan(r.friction_angle * M_PI / 180), std::tan(32 * M_PI / 180) / 2, 1e-14);
  EXPECT_NEAR(std::tan(r.residual_friction_angle * M_PI / 180), std::tan(25 * M_PI / 180) / 2, 1e-14);
  EXPECT_EQ(values_of(reduced(rock, 2)), values_of(rock));
  EXPECT_EQ(limit_equilibrium_strength(sand)->cohesion, 2e3);
  EXPECT_EQ(limit_equilibrium_strength(sand)->friction_angle, 32);
  EXPECT_FALSE(limit_equilibrium_strength(rock));
  EXPECT_EQ(history_width(sand), 1);
  EXPECT_EQ(history_width(rock), 0);
}

// A model with one material of each model.
Model two_material_model() {
  Model model = testing::rectangle_mesh(0, 0, 4, 4, 0.25);
  testing::add_box_body(model, "soil", softening_sand(), 0, 1, 0, 0.5);
  testing::add_box_body(model, "rock", testing::elastic(2400, 3e10, 0.2), 0, 1, 0.5, 1);
  testing::fix_base_roll_sides(model);
  testing::set_run(model, 0.1);
  model.post.body = "soil";
  return model;
}

TEST(ModelFile, MaterialsRoundTripWithTheirModelsKeysOnly) {
  const ScratchDir dir("materials-file");
  const Model model = two_material_model();
  write_model(dir.file("model.h5"), model);
  const Model read = read_model(dir.file("model.h5"));
  ASSERT_EQ(read.materials.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(model_name(read.materials[i]), model_name(model.materials[i]));
    EXPECT_EQ(values_of(read.materials[i]), values_of(model.materials[i]));
  }
  const h5::File file = h5::File::open_read(dir.file("model.h5"));
  EXPECT_EQ(h5::list_attributes(file, "materials/rock_material").size(), 6u);  // model and the five shared
  EXPECT_EQ(h5::list_attributes(file, "materials/soil_material").size(), 16u);
}

// The landed build wrote all fifteen parameters for every material: a linear elastic material's
// Mohr-Coulomb keys at their defaults. Such a file reads, the keys of another model ignored; and
// a file from before the water and softening keys reads them at their defaults.
TEST(ModelFile, AFileOfTheLandedBuildStillReads) {
  const ScratchDir dir("materials-landed");
  Model model = two_material_model();
  parameters_of<MohrCoulomb>(model.materials[0]) = MohrCoulomb::Parameters{.friction_angle = 30, .cohesion = 1e3};
  write_model(dir.file("model.h5"), model);
  {
    h5::File file = h5::File::open_write(dir.file("model.h5"));
    for (const char* key : {"friction_angle", "cohesion", "dilation_angle", "residual_cohesion",
                            "residual_friction_angle", "residual_dilation_angle", "softening_start", "softening_end",
                            "softening_reference_size"})
      h5::set_attribute(file, "materials/rock_material", key, 0.0);
    h5::set_attribute(file, "materials/rock_material", "tensile_strength", -1.0);
    for (const char* key : {"residual_cohesion", "softening_end", "saturated_density", "porosity"})
      H5Adelete_by_name(file.id(), "materials/soil_material", key, H5P_DEFAULT);
  }
  const Model read = read_model(dir.file("model.h5"));
  EXPECT_TRUE(is<LinearElastic>(read.materials[1]));
  EXPECT_EQ(values_of(read.materials[1]), values_of(model.materials[1]));
  EXPECT_EQ(values_of(read.materials[0]), values_of(model.materials[0]));  // the defaults it was written with
}

// Checkpoints of version 2 hashed the materials otherwise: they are refused by their version.
TEST(ModelFile, ACheckpointOfTheEarlierFormatIsRefusedByItsVersion) {
  const ScratchDir dir("materials-checkpoint");
  const Model model = two_material_model();
  solver::Simulation sim = solver::make_simulation(model, 1);
  solver::write_checkpoint(dir.path().string(), model, sim, solver::LoopState{0.5, 0.5}, solver::ResultsPosition{1, 0});
  {
    h5::File file = h5::File::open_write(dir.file("checkpoint.h5"));
    h5::set_attribute(file, "/", "format_version", int64_t{2});
  }
  solver::LoopState loop;
  solver::ResultsPosition position;
  try {
    solver::read_checkpoint(dir.path().string(), model, sim, loop, position);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("format_version: file has version 2, this talus reads version 3"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace talus
