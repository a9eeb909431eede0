// LegLengthTable (the tabulated Eq. (13) the hopping controller evaluates every tick) against the hopping spec's
// independently derived L(q_knee) table (shared/specs/hopping.md A1.3: L to 1 mm, dL/dq_knee to 1e-3 m/rad), and
// ToLegLengthPlan against the plan it converts; the landing planner's start state when the measured leg length is
// outside the NLP's bounds (the spring deflection s = L − x, hence the ROM's ground force, is the measured one), and a
// landing planner that cannot be built fails with a message instead of throwing.
#include <gtest/gtest.h>

#include <cmath>

#include "diagrams/hopping/hopping_plans.h"
#include "systems/rom/cassie_leg_stiffness.h"

namespace rome {
namespace {

TEST(LegLengthTable, MatchesTheSpecTable) {
  const MultibodyModel model = MultibodyModel::LoadFromSidecar(std::string(ROME_SOURCE_DIR) + "/robots/cassie/cassie.rome.json");
  const LegLengthTable table(model);
  const double q_deg[] = {-45, -54.4, -60, -70, -80, -90, -100, -110, -120};
  const double L_m[] = {0.9577, 0.9235, 0.9003, 0.8535, 0.8002, 0.7407, 0.6757, 0.6055, 0.5308};
  const double dL[] = {0.188, 0.227, 0.249, 0.287, 0.323, 0.357, 0.388, 0.416, 0.440};
  const double lo = model.position_lower_limits()[model.VelocityIndex("left_knee")], hi = model.position_upper_limits()[model.VelocityIndex("left_knee")];
  int checked = 0;
  for (int i = 0; i < 9; ++i) {
    const double q = q_deg[i] * M_PI / 180;
    if (q < lo || q > hi) continue;  // outside our model's knee range
    double L = 0, slope = 0;
    table(q, &L, &slope);
    EXPECT_NEAR(L, L_m[i], 1e-3) << "q_knee = " << q_deg[i] << " deg";
    EXPECT_NEAR(slope, dL[i], 2e-3) << "q_knee = " << q_deg[i] << " deg";
    ++checked;
  }
  EXPECT_GE(checked, 5);
}

TEST(LegLengthTable, ToLegLengthPlanTakesTheLegRows) {
  SpringMassPlan plan;
  plan.times = Eigen::Vector3d(0.0, 0.1, 0.2);
  plan.states.setZero(4, 3);
  plan.states.row(0) << 0.76, 0.8, 0.87;
  plan.states.row(1) << -1.0, 0.2, 0.1;
  plan.states.row(2) << 0.8, 0.85, 0.9;
  plan.states.row(3) << 0.0, 0.5, 0.0;
  plan.leg_force = Eigen::Vector3d(500.0, 300.0, 0.0);
  SpringMassParams rom;
  rom.n_legs = 2;
  const LegLengthPlan p = ToLegLengthPlan(rom, plan);
  EXPECT_EQ(p.force, plan.leg_force);  // jump_force_feedback's F_plan and n K(L)
  for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(p.stiffness[k], 2.0 * rom.leg.stiffness.Evaluate(plan.states(2, k)));
  EXPECT_EQ(p.t, plan.times);
  EXPECT_EQ(p.L, Eigen::Vector3d(0.8, 0.85, 0.9));
  EXPECT_EQ(p.Ldot, Eigen::Vector3d(0.0, 0.5, 0.0));
  EXPECT_EQ(p.x, Eigen::Vector3d(0.76, 0.8, 0.87));  // the mass height and its rate (landing_deflection_feedback)
  EXPECT_EQ(p.xdot, Eigen::Vector3d(-1.0, 0.2, 0.1));
  // The reference's Hermite passes through the nodes with the node rates.
  const Eigen::Vector3d mid = HoppingReference::Evaluate(p.t, p.L, p.Ldot, 3, 0.1);
  EXPECT_NEAR(mid[0], 0.85, 1e-12);
  EXPECT_NEAR(mid[1], 0.5, 1e-12);
  EXPECT_EQ(HoppingReference::Evaluate(p.t, p.L, p.Ldot, 3, 0.5), Eigen::Vector3d(0.9, 0.0, 0.0));  // held after T
}

TEST(SpringMassLandingPlanner, ClampedLegLengthKeepsTheMeasuredSpringDeflection) {
  const MultibodyModel model = MultibodyModel::LoadFromSidecar(std::string(ROME_SOURCE_DIR) + "/robots/cassie/cassie.rome.json");
  const SpringMassParams rom = CassieSpringMassParams(model, LegStiffnessVariant::kIdentified);
  const SpringMassLandingParams params;
  auto records = std::make_shared<std::vector<PlannerRecord>>();
  auto rest = std::make_shared<double>(0.85);
  auto planner = MakeSpringMassLandingPlanner(rom, params, records, rest);
  // Post-impact: knees extended 4 cm beyond the NLP's max leg length, springs nearly unloaded (s = 5 mm), falling.
  const RomState post{0.955, -1.5, params.max_leg_length + 0.04, 0.0};
  LegLengthPlan plan;
  std::string message;
  ASSERT_TRUE(planner(post, &plan, &message)) << message;
  const SpringMassPlan& p = records->back().plan;
  EXPECT_NEAR(p.states(2, 0), params.max_leg_length, 1e-9);
  EXPECT_NEAR(p.states(2, 0) - p.states(0, 0), post.L - post.x, 1e-9);  // s as measured
  EXPECT_NEAR(p.states(1, 0), post.xdot, 1e-9);
  // Hence the plan's first ground force is the measured spring force n (K s + D ṡ) (positive), not the large negative
  // one of s = −3.5 cm that clamping L alone gave.
  const double L0 = params.max_leg_length, s0 = post.L - post.x, sdot0 = post.Ldot - post.xdot;
  const double expected = rom.n_legs * (rom.leg.stiffness.Evaluate(L0) * s0 + rom.leg.damping.Evaluate(L0) * sdot0);
  EXPECT_GT(expected, 0.0);
  EXPECT_NEAR(p.LegForce(rom, 0.0), expected, 1e-6 * std::abs(expected));

  auto no_rest = MakeSpringMassLandingPlanner(rom, params, records, std::make_shared<double>(0.0));
  EXPECT_FALSE(no_rest(post, &plan, &message));
  EXPECT_NE(message.find("rest_height"), std::string::npos) << message;
}

}  // namespace
}  // namespace rome
