// Model mismatch and terrain errors: scaling masses scales the plant's total mass and its mass matrix (rotor inertias
// aside) by the factor, computed from the model's dynamics; stone-height errors are reproducible, keep the first
// stone and have the requested spread.
#include "systems/perturbations/perturbation_params.h"

#include <gtest/gtest.h>

#include <cmath>

#include "systems/multibody/model_scaling.h"
#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_workspace.h"
#include "tests/common/error_of.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

MultibodyModel Load(const std::string& robot) {
  return MultibodyModel::LoadFromSidecar(rome::test::SourcePath("robots/" + robot + "/" + robot + ".rome.json"),
                                         {.euler_floating_base = true});
}

TEST(ScaleMassAndFriction, ScalesTheMassMatrixAndTotalMassByTheFactor) {
  for (const char* robot : {"amber", "cassie_planar"}) {
    const MultibodyModel nominal = Load(robot);
    const double s = 1.1;
    const MultibodyModel scaled = ScaleMassAndFriction(nominal, s, 0.5);
    MultibodyWorkspace ws_n(nominal), ws_s(scaled);
    const Eigen::VectorXd& q = nominal.q_nominal();
    const Eigen::MatrixXd Mn = CalcMassMatrix(nominal, ws_n, q), Ms = CalcMassMatrix(scaled, ws_s, q);
    // The planar base's x coordinate moves every body: M(0, 0) is the total mass the dynamics sees.
    EXPECT_NEAR(Ms(0, 0), s * Mn(0, 0), 1e-9 * Mn(0, 0)) << robot;
    EXPECT_NEAR(scaled.total_mass(), s * nominal.total_mass(), 1e-12 * nominal.total_mass()) << robot;
    // The whole mass matrix scales, except the rotor inertias on its diagonal (motor property, unchanged).
    const Eigen::MatrixXd rotor = nominal.reflected_inertia().asDiagonal();
    EXPECT_LT((Ms - rotor - s * (Mn - rotor)).norm(), 1e-9 * Mn.norm()) << robot;
    for (int c = 0; c < nominal.num_contacts(); ++c)
      EXPECT_DOUBLE_EQ(scaled.contacts()[c].friction_coefficient, 0.5 * nominal.contacts()[c].friction_coefficient);
    // The nominal model is untouched (the bodies are copied, not shared).
    EXPECT_EQ(CalcMassMatrix(nominal, ws_n, q), Mn);
  }
}

TEST(ScaleMassAndFriction, BadScaleNamesTheRobotAndTheValue) {
  const MultibodyModel m = Load("amber");
  const std::string e = test::ErrorOf([&] { ScaleMassAndFriction(m, 0.0); });
  EXPECT_NE(e.find("mass_scale = 0"), std::string::npos) << e;
  EXPECT_NE(e.find("amber"), std::string::npos) << e;
  EXPECT_NE(test::ErrorOf([&] { ScaleMassAndFriction(m, 1.0, std::nan("")); }).find("friction_scale = nan"),
            std::string::npos);
}

TEST(WithStoneHeightErrors, KeepsTheFirstStoneIsReproducibleAndHasTheRequestedSpread) {
  std::vector<SteppingStone> stones;
  for (int i = 0; i < 4001; ++i) stones.push_back({0.5 * i, 0.01 * i, 0.1});
  const Terrain map = Terrain::Stones(stones);
  const double sigma = 0.02;
  const Terrain a = WithStoneHeightErrors(map, sigma, 5), b = WithStoneHeightErrors(map, sigma, 5);
  EXPECT_EQ(a.stones()[0].top_height_m, 0.0);
  double m2 = 0;
  for (size_t i = 1; i < stones.size(); ++i) {
    EXPECT_EQ(a.stones()[i].top_height_m, b.stones()[i].top_height_m);
    EXPECT_EQ(a.stones()[i].x_center_m, stones[i].x_center_m);
    const double e = a.stones()[i].top_height_m - stones[i].top_height_m;
    m2 += e * e;
  }
  // 4000 draws: the standard error of the sd is 1.1 % of sigma.
  EXPECT_NEAR(std::sqrt(m2 / 4000) / sigma, 1.0, 0.06);
  EXPECT_EQ(WithStoneHeightErrors(map, 0.0, 5).stones()[7].top_height_m, stones[7].top_height_m);
}

TEST(PerturbationParams, ValidateNamesTheField) {
  PerturbationParams p;
  p.latency_samples = -1;
  EXPECT_NE(test::ErrorOf([&] { p.Validate(); }).find("latency_samples = -1"), std::string::npos);
  p = {};
  p.mass_scale = 0.0;
  EXPECT_NE(test::ErrorOf([&] { p.Validate(); }).find("mass_scale = 0"), std::string::npos);
}

}  // namespace
}  // namespace rome
