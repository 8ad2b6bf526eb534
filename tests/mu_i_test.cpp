// The mu(I) material (common/materials/mu_i.hpp): in steady simple shear under a constant normal
// stress the sample mobilises tau / p = mu(I) at the inertial number of its shear rate, from
// mu_s in slow flow to mu_2 in fast flow (Jop, Forterre and Pouliquen 2006); with mu_2 = mu_s it
// is the rate-independent Mohr-Coulomb material of sin(phi) = mu_s, c = 0, psi = 0; and the scene
// reader, strength reduction and Bishop's method reach it through the registry.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "common/h5.hpp"
#include "common/materials/materials.hpp"
#include "support/preproc_checks.hpp"
#include "support/simple_shear.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

constexpr double kPi = std::numbers::pi;

// Jop et al.'s (2006) glass beads: mu_s = tan 20.9 deg, mu_2 = tan 32.76 deg, I0 = 0.279,
// d = 0.5 mm, rho_s = 2450 kg/m^3 (their Nature paper's values), a stiffness of a loose sand.
Material glass_beads() {
  Material m;
  m.name = "beads";
  set_model(m, "mu_i");
  m.density = 1500;
  m.youngs_modulus = 20e6;
  m.poisson_ratio = 0.3;
  MuI::Parameters& own = parameters_of<MuI>(m);
  own.mu_static = std::tan(20.9 * kPi / 180);
  own.mu_limit = std::tan(32.76 * kPi / 180);
  own.inertial_number_scale = 0.279;
  own.grain_diameter = 0.5e-3;
  own.grain_density = 2450;
  return m;
}

double jop_mu(double inertial_number) {
  const double mu_s = std::tan(20.9 * kPi / 180), mu_2 = std::tan(32.76 * kPi / 180);
  return mu_s + (mu_2 - mu_s) / (0.279 / inertial_number + 1);
}

// tau / p after shearing at the rate of inertial number I under the normal stress p, to a total
// shear of 200 yield strains (steady).
double steady_ratio(const Material& m, double inertial_number, double p_normal) {
  const PreparedMaterial prepared = prepare(m, {});
  const MuI::Parameters& own = parameters_of<MuI>(m);
  const double rho_s = own.grain_density > 0 ? own.grain_density : m.density;
  const double rate = inertial_number * std::sqrt(p_normal / rho_s) / own.grain_diameter;
  const double d_gamma = p_normal / m.youngs_modulus / 20, dt = d_gamma / rate;
  double eps_p = 0;
  const Eigen::Vector4d sigma = testing::sheared_under_normal_stress(
      [&](Eigen::Vector4d& stress, const Eigen::Vector4d& d_eps) {
        update_stress(prepared, stress, d_eps, dt, eps_p, nullptr);
      },
      Eigen::Vector4d(-0.5 * p_normal, -p_normal, -0.5 * p_normal, 0), p_normal, d_gamma, 4000);
  EXPECT_NEAR(sigma[1], -p_normal, 1e-9 * p_normal);
  EXPECT_GT(eps_p, 0.05);  // it flowed
  return sigma[3] / p_normal;
}

TEST(MuI, SteadySimpleShearMobilisesMuOfTheInertialNumber) {
  const Material beads = glass_beads();
  for (const double p_normal : {2e3, 50e3}) {
    for (const double inertial_number : {1e-4, 0.03, 0.279, 1.0, 30.0}) {
      SCOPED_TRACE("p " + std::to_string(p_normal) + " Pa, I " + std::to_string(inertial_number));
      EXPECT_NEAR(steady_ratio(beads, inertial_number, p_normal), jop_mu(inertial_number), 1e-4);
    }
  }
  // What it tells apart: the ends of the law, 0.382 and 0.643, and halfway at I = I0.
  EXPECT_NEAR(jop_mu(1e-4), std::tan(20.9 * kPi / 180), 1e-4);
  EXPECT_NEAR(jop_mu(0.279), 0.5 * (std::tan(20.9 * kPi / 180) + std::tan(32.76 * kPi / 180)), 1e-12);
}

// The inertial number takes the grains' density, or the material's when grain_density is 0.
TEST(MuI, WithoutAGrainDensityTheInertialNumberTakesTheMaterialsDensity) {
  Material beads = glass_beads();
  const double p_normal = 10e3, inertial_number = 0.1;
  parameters_of<MuI>(beads).grain_density = 0;
  beads.density = 2450;
  EXPECT_NEAR(steady_ratio(beads, inertial_number, p_normal), jop_mu(inertial_number), 1e-4);
}

// With mu_limit = mu_static the rate drops out: every step equals Mohr-Coulomb's with
// sin(phi) = mu_s, c = 0, psi = 0, on random strain paths through yield and back.
TEST(MuI, WithoutARateDependenceIsMohrCoulombOfSinPhiEqualToMuStatic) {
  Material beads = glass_beads();
  MuI::Parameters& own = parameters_of<MuI>(beads);
  own.mu_limit = own.mu_static;
  Material sand;
  sand.name = "sand";
  set_model(sand, "mohr_coulomb");
  static_cast<SharedParameters&>(sand) = beads;
  parameters_of<MohrCoulomb>(sand).friction_angle = std::asin(own.mu_static) * 180 / kPi;
  const PreparedMaterial a = prepare(beads, {}), b = prepare(sand, {});
  std::mt19937 random(7);
  std::uniform_real_distribution<double> strain(-4e-5, 4e-5);
  Eigen::Vector4d sigma_a(-8e3, -10e3, -6e3, 0), sigma_b = sigma_a;
  double eps_a = 0, eps_b = 0;
  for (int step = 0; step < 3000; ++step) {
    const Eigen::Vector4d d_eps(strain(random), strain(random) - 1e-6, 0, strain(random));
    update_stress(a, sigma_a, d_eps, 1e-4, eps_a, nullptr);
    update_stress(b, sigma_b, d_eps, 1e-4, eps_b, nullptr);
    ASSERT_LE((sigma_a - sigma_b).norm(), 1e-9 * sigma_b.norm()) << "step " << step;
  }
  EXPECT_GT(eps_b, 1e-3);  // the path did yield
  EXPECT_NEAR(eps_a, eps_b, 1e-12);
}

// A particle at rest costs nothing extra and feels no rate: below the static surface a fast
// increment is elastic, and with no compression (a grain at a free surface) mu is mu_2.
TEST(MuI, ElasticBelowTheStaticSurfaceAndMuLimitWithoutPressure) {
  const Material beads = glass_beads();
  const PreparedMaterial prepared = prepare(beads, {});
  const MuI::Prepared& s = std::get<MuI::Prepared>(prepared);
  Eigen::Vector4d sigma(-10e3, -10e3, -10e3, 0), elastic = sigma;
  const Eigen::Vector4d d_eps(0, -1e-5, 0, 2e-5);
  double eps_p = 0;
  update_stress(prepared, sigma, d_eps, 1e-9, eps_p, nullptr);  // a shear rate of 4e4 /s
  elastic_update(beads.shear_modulus(), beads.bulk_modulus(), elastic, d_eps);
  EXPECT_EQ(eps_p, 0);
  EXPECT_LT((sigma - elastic).norm(), 1e-12 * elastic.norm());
  EXPECT_DOUBLE_EQ(s.friction(1e3, 0.0), std::tan(32.76 * kPi / 180));
  EXPECT_DOUBLE_EQ(s.friction(0.0, 1e3), std::tan(20.9 * kPi / 180));
  EXPECT_DOUBLE_EQ(MuI::shear_rate(Eigen::Vector4d(0, 0, 0, 0.5e-3), 1e-3), 1.0);  // simple shear, gamma_dot 1
  EXPECT_DOUBLE_EQ(MuI::pressure(Eigen::Vector4d(-3e3, -1e3, -2e3, 0)), 2e3);
}

TEST(MuI, RegistryChecksReducesAndGivesBishopItsAngle) {
  Material beads = glass_beads();
  EXPECT_FALSE(material_problem(beads));
  EXPECT_TRUE(has_strength(beads));
  EXPECT_EQ(history_width(beads), 0);
  // Reduced as the Mohr-Coulomb material of sin(phi) = mu is: tan(phi) / F.
  const auto tan_phi = [](double mu) { return mu / std::sqrt(1 - mu * mu); };
  const Material half = reduced(beads, 2);
  EXPECT_NEAR(tan_phi(parameters_of<MuI>(half).mu_static), tan_phi(parameters_of<MuI>(beads).mu_static) / 2, 1e-14);
  EXPECT_NEAR(tan_phi(parameters_of<MuI>(half).mu_limit), tan_phi(parameters_of<MuI>(beads).mu_limit) / 2, 1e-14);
  // Raised (F < 1, as talus fos brackets) the coefficients stay below 1 and in order.
  for (const double factor : {0.5, 0.1, 0.01}) {
    const Material raised = reduced(beads, factor);
    EXPECT_FALSE(material_problem(raised)) << "F " << factor;
    EXPECT_LT(parameters_of<MuI>(raised).mu_limit, 1.0);
    EXPECT_GT(parameters_of<MuI>(raised).mu_static, parameters_of<MuI>(beads).mu_static);
  }
  EXPECT_NEAR(limit_equilibrium_strength(beads)->friction_angle, 20.9, 1e-12);
  EXPECT_EQ(limit_equilibrium_strength(beads)->cohesion, 0);
  parameters_of<MuI>(beads).mu_limit = 0.3;  // below mu_static
  ASSERT_TRUE(material_problem(beads));
  EXPECT_EQ(material_problem(beads)->key, "mu_limit");
  parameters_of<MuI>(beads).mu_limit = 1.0;  // asin would have no angle beyond it
  EXPECT_EQ(material_problem(beads)->key, "mu_limit");
  parameters_of<MuI>(beads).mu_limit = 0.6;
  parameters_of<MuI>(beads).grain_diameter = 0;
  EXPECT_EQ(material_problem(beads)->key, "grain_diameter");
}

// geometries/column_collapse.toml (a = 0.5, here on 1 cm triangles) with its material block
// replaced by `material`; the deposit's tip (L_inf - L0) / L0 and the final positions.
struct Collapse {
  double runout = 0;
  std::vector<double> positions;
};
Collapse collapse(const testing::ScratchDir& dir, const std::string& name, const std::string& material) {
  std::string scene = testing::read_text(testing::source_path("geometries/column_collapse.toml"));
  const std::size_t begin = scene.find("[materials.sand]"), end = scene.find("[bodies.column]");
  EXPECT_NE(begin, std::string::npos);
  EXPECT_NE(end, std::string::npos);
  scene.replace(begin, end - begin, "[materials.sand]\n" + material + "\n");
  scene.replace(scene.find("k0 = 0.357"), 10, "k0 = 0.618");  // 1 - mu_s
  const std::string geometry = "geometry = \"column_collapse.geo\"";
  scene.replace(scene.find(geometry), geometry.size(),
                "geometry = \"" + testing::source_path("geometries/column_collapse.geo") + "\"");
  const std::string path = testing::write_file(dir, name + ".toml", scene);
  const auto run = testing::run_talus("run " + path + " --set mesh.size=0.01 --out " + dir.file(name) + " -q --threads 1");
  EXPECT_EQ(run.status, 0) << run.output;  // exit 0: no particle left the domain
  Collapse out;
  if (run.status != 0) return out;
  const h5::File results = h5::File::open_read(dir.file(name) + "/results.h5");
  EXPECT_EQ(h5::get_int(results, "/", "complete"), 1);
  h5::Dims dims;
  const std::vector<double> flat = h5::read_doubles(results, "frames/position", &dims);
  const std::size_t n = dims[1], last = dims[0] - 1;
  out.positions.assign(flat.begin() + static_cast<long>(last * n * 2), flat.end());
  std::vector<Eigen::Vector2d> x(n);
  for (std::size_t p = 0; p < n; ++p) x[p] = {out.positions[2 * p], out.positions[2 * p + 1]};
  out.runout = (testing::column_deposit(x, 0.005).tip - 0.2) / 0.2;
  return out;
}

// Through the whole pipeline (scene, model.h5, solver): Jop et al.'s glass beads collapse to a
// deposit shorter than the same beads' static friction alone gives, since the fast flow of the
// collapse mobilises more than mu_s; and with mu_limit = mu_static the frames are the
// Mohr-Coulomb material's of sin(phi) = mu_s, bit for bit. Measured on 5 mm triangles
// (docs/column.md, "The mu(I) material"): the tip 1.167 against 1.360, 14 % shorter.
TEST(MuI, GlassBeadsCollapseShorterThanTheirStaticFrictionAloneGives) {
  const testing::ScratchDir dir("mu-i-column");
  const std::string elastic = "density = 1500.0\nyoungs_modulus = 1.0e6\npoisson_ratio = 0.3\n";
  const std::string beads = "model = \"mu_i\"\n" + elastic +
                            "mu_static = 0.38186\ninertial_number_scale = 0.279\ngrain_diameter = 0.5e-3\n"
                            "grain_density = 2450.0\n";
  const Collapse rate = collapse(dir, "rate", beads + "mu_limit = 0.64349\n");
  const Collapse still = collapse(dir, "still", beads + "mu_limit = 0.38186\n");
  char phi[64];  // asin(mu_s) to the last bit
  std::snprintf(phi, sizeof phi, "%.17g", std::asin(0.38186) * 180 / kPi);
  const Collapse coulomb =
      collapse(dir, "coulomb", "model = \"mohr_coulomb\"\n" + elastic + "friction_angle = " + phi + "\ncohesion = 0.0\n");
  ASSERT_EQ(still.positions.size(), coulomb.positions.size());
  double difference = 0;
  for (std::size_t k = 0; k < still.positions.size(); ++k)
    difference = std::max(difference, std::abs(still.positions[k] - coulomb.positions[k]));
  EXPECT_LT(difference, 1e-9) << "mu_limit = mu_static against Mohr-Coulomb";
  EXPECT_GT(still.runout, 0.9);  // the beads' low friction runs far past the sand's 0.6
  EXPECT_LT(rate.runout, 0.95 * still.runout) << rate.runout << " against " << still.runout;
  EXPECT_GT(rate.runout, 0.7 * still.runout) << rate.runout << " against " << still.runout;
}

}  // namespace
}  // namespace talus
