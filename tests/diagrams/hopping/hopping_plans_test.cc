// LegLengthTable (the tabulated Eq. (13) the hopping controller evaluates every tick) against the hopping spec's
// independently derived L(q_knee) table (shared/specs/hopping.md A1.3: L to 1 mm, dL/dq_knee to 1e-3 m/rad), and
// ToLegLengthPlan against the plan it converts; the landing planner's start state when the measured leg length is
// outside the NLP's bounds (the spring deflection s = L − x, hence the ROM's ground force, is the measured one), and a
// landing planner that cannot be built fails with a message instead of throwing.
#include <gtest/gtest.h>

#include <cstdio>

#include <cmath>

#include "diagrams/hopping/hopping_plans.h"
#include "systems/rom/cassie_leg_stiffness.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

TEST(LegLengthTable, MatchesTheSpecTable) {
  const MultibodyModel model = MultibodyModel::LoadFromSidecar(rome::test::SourcePath("robots/cassie/cassie.rome.json"),
                                                               {.euler_floating_base = true});
  const LegLengthTable table(model);
  const double q_deg[] = {-45, -54.4, -60, -70, -80, -90, -100, -110, -120};
  const double L_m[] = {0.9577, 0.9235, 0.9003, 0.8535, 0.8002, 0.7407, 0.6757, 0.6055, 0.5308};
  const double dL[] = {0.188, 0.227, 0.249, 0.287, 0.323, 0.357, 0.388, 0.416, 0.440};
  const double lo = model.position_lower_limits()[model.VelocityIndex("left_knee")],
               hi = model.position_upper_limits()[model.VelocityIndex("left_knee")];
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
  const MultibodyModel model = MultibodyModel::LoadFromSidecar(rome::test::SourcePath("robots/cassie/cassie.rome.json"),
                                                               {.euler_floating_base = true});
  const SpringMassParams rom = CassieSpringMassParams(model, LegStiffnessVariant::kIdentified);
  const SpringMassLandingParams params;
  auto records = std::make_shared<std::vector<PlannerRecord>>();
  auto rest = std::make_shared<double>(0.85);
  auto planner = MakeSpringMassLandingPlanner(rom, params, records, rest);
  // Post-impact: knees extended 4 cm beyond the NLP's max leg length, springs nearly unloaded (s = 5 mm), falling.
  const RomState post{0.955, -1.5, params.max_leg_length + 0.04, 0.0};
  LegLengthPlan plan;
  std::string message;
  ASSERT_TRUE(planner(post, HoppingReference::LandingSolve::kAtTouchdown, &plan, &message)) << message;
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
  EXPECT_FALSE(no_rest(post, HoppingReference::LandingSolve::kAtTouchdown, &plan, &message));
  EXPECT_NE(message.find("rest_height"), std::string::npos) << message;
}

// The landing NLP solved at lift-off starts from the touchdown of the ROM's ballistic flight with the leg held
// (closed form: x = L, ẋ = −sqrt(ẋ_lo² + 2 g (x_lo − L))), and the touchdown solve that follows is recorded after it.
TEST(SpringMassLandingPlanner, LiftoffSolveStartsFromTheBallisticTouchdown) {
  const MultibodyModel model = MultibodyModel::LoadFromSidecar(rome::test::SourcePath("robots/cassie/cassie.rome.json"),
                                                               {.euler_floating_base = true});
  const SpringMassParams rom = CassieSpringMassParams(model, LegStiffnessVariant::kIdentified);
  const SpringMassLandingParams params;
  auto records = std::make_shared<std::vector<PlannerRecord>>();
  auto planner = MakeSpringMassLandingPlanner(rom, params, records, std::make_shared<double>(0.83));
  const RomState liftoff{0.915, 1.9, 0.92, 0.3};  // mass 5 mm below the leg length (springs still loaded), rising
  LegLengthPlan plan;
  std::string message;
  ASSERT_TRUE(planner(liftoff, HoppingReference::LandingSolve::kPredictedAtLiftoff, &plan, &message)) << message;
  ASSERT_EQ(records->size(), 1u);
  EXPECT_EQ(records->back().kind, PlannerRecord::Kind::kLandingPredicted);
  const Eigen::Vector4d z0 = records->back().plan.InitialState();
  EXPECT_NEAR(z0[0], 0.92, 1e-9);
  EXPECT_NEAR(z0[1], -std::sqrt(1.9 * 1.9 + 2 * rom.gravity * (0.915 - 0.92)), 1e-9);
  EXPECT_NEAR(z0[2], 0.92, 1e-9);
  EXPECT_NEAR(z0[3], 0.0, 1e-12);
  // The touchdown, 1 cm/s faster than predicted, is solved warm and recorded as the landing plan.
  const RomState post{0.92, z0[1] - 0.01, 0.92, 0.0};
  ASSERT_TRUE(planner(post, HoppingReference::LandingSolve::kAtTouchdown, &plan, &message)) << message;
  ASSERT_EQ(records->size(), 2u);
  EXPECT_EQ(records->back().kind, PlannerRecord::Kind::kLanding);
  EXPECT_NEAR(records->back().plan.InitialState()[1], post.xdot, 1e-9);
  // Warm from the lift-off solve, the touchdown solve takes fewer Ipopt iterations than a cold solve of the same state.
  auto cold_records = std::make_shared<std::vector<PlannerRecord>>();
  auto cold = MakeSpringMassLandingPlanner(rom, params, cold_records, std::make_shared<double>(0.83));
  ASSERT_TRUE(cold(post, HoppingReference::LandingSolve::kAtTouchdown, &plan, &message)) << message;
  std::printf("  iterations: predicted at lift-off %d (cold), at touchdown %d (warm), the same touchdown cold %d\n",
              records->front().plan.iterations, records->back().plan.iterations, cold_records->back().plan.iterations);
  EXPECT_LT(records->back().plan.iterations, cold_records->back().plan.iterations);
  // A lift-off that does not leave the ground upwards cannot be predicted: false with PredictFlight's message.
  EXPECT_FALSE(
      planner(RomState{0.9, -0.1, 0.92, 0.0}, HoppingReference::LandingSolve::kPredictedAtLiftoff, &plan, &message));
  EXPECT_NE(message.find("PredictFlight"), std::string::npos) << message;
}

}  // namespace
}  // namespace rome
