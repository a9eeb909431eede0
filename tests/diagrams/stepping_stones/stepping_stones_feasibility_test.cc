// CheckSteppingStonesFeasible / CalcLegReach: the limits come from the robot (leg lengths of robots.md, the sole's
// contact points, the weight) and from the supervisor's heights, and a course is refused just beyond each limit and
// accepted just inside it. Also: the initial pose on a stone far from the origin is the pose at the origin, moved.
#include "diagrams/stepping_stones/stepping_stones_feasibility.h"

#include <gtest/gtest.h>

#include "diagrams/walking/walking_robot_check.h"

namespace rome {
namespace {

MultibodyModel Load(const std::string& robot) {
  return MultibodyModel::LoadFromSidecar("robots/" + robot + "/" + robot + ".rome.json", {.euler_floating_base = true});
}

// The message of the std::invalid_argument that `f` throws ("" if none).
template <typename F>
std::string Refusal(F f) {
  try {
    f();
  } catch (const std::invalid_argument& e) { return e.what(); }
  return "";
}

Terrain TwoSteps(double dx, double dz, double length = 0.1) {
  return Terrain::Stones({{0.0, 0.0, length}, {dx, dz, length}, {2 * dx, 2 * dz, length}});
}

TEST(SteppingStonesFeasibility, AmberLegReachIsThighPlusShin) {
  const MultibodyModel amber = Load("amber");
  // robots.md (AMBER-3M): thigh 0.4064 m, shin 0.4667 m; the foot is the shin's end, both hips at the torso origin.
  for (const char* foot : {"left_foot", "right_foot"}) {
    const LegReach leg = CalcLegReach(amber, amber.ContactIndex(foot));
    EXPECT_NEAR(leg.reach_m, 0.4064 + 0.4667, 1e-9) << foot;
    EXPECT_NEAR(leg.hip_in_base.norm(), 0.0, 1e-12) << foot;
  }
}

TEST(SteppingStonesFeasibility, StepBeyondBothLegsIsRefused) {
  const MultibodyModel amber = Load("amber");
  SteppingStonesDiagramParams params;
  params.supervisor.max_steps = 2;
  const double reach = 2 * (0.4064 + 0.4667);
  EXPECT_EQ(Refusal([&] { CheckSteppingStonesFeasible(amber, TwoSteps(0.999 * reach, 0.0), params); }), "");
  const std::string m = Refusal([&] { CheckSteppingStonesFeasible(amber, TwoSteps(1.001 * reach, 0.0), params); });
  EXPECT_NE(m.find("stone 1"), std::string::npos) << m;
  EXPECT_NE(m.find("reach at most 1.7462 m"), std::string::npos) << m;
  // The margin is a parameter: half the reach refuses a step of 0.6 reach.
  EXPECT_NE(Refusal([&] {
              CheckSteppingStonesFeasible(amber, TwoSteps(0.6 * reach, 0.0), params, {.leg_reach_fraction = 0.5});
            }),
            "");
  // Only the steps to be walked are checked: stone 3, beyond max_steps = 2, may be far.
  const Terrain far_last = Terrain::Stones({{0.0, 0.0, 0.1}, {0.4, 0.0, 0.1}, {0.8, 0.0, 0.1}, {50.0, 0.0, 0.1}});
  EXPECT_EQ(Refusal([&] { CheckSteppingStonesFeasible(amber, far_last, params); }), "");
}

TEST(SteppingStonesFeasibility, OneStoneHasNoStepToTake) {
  SteppingStonesDiagramParams params;
  const std::string m = Refusal([&] {
    CheckSteppingStonesFeasible(Load("amber"), Terrain::Stones({{0.0, 0.0, 1.0}}), params);
  });
  EXPECT_NE(m.find("has 1 stone"), std::string::npos) << m;
}

TEST(SteppingStonesFeasibility, RiseAndDropBeyondTheSupervisorsHeightsAreRefused) {
  const MultibodyModel amber = Load("amber");
  SteppingStonesDiagramParams params;
  params.supervisor.max_steps = 2;
  const double limit = params.supervisor.walking_com_height_m - params.supervisor.min_com_height_m;  // 0.8 - 0.45 m
  for (const double sign : {1.0, -1.0}) {
    EXPECT_EQ(Refusal([&] { CheckSteppingStonesFeasible(amber, TwoSteps(0.4, sign * (limit - 0.001)), params); }), "")
        << sign;
    const std::string m =
        Refusal([&] { CheckSteppingStonesFeasible(amber, TwoSteps(0.4, sign * (limit + 0.001)), params); });
    EXPECT_NE(m.find(sign > 0 ? "above stone 0" : "below stone 0"), std::string::npos) << m;
    EXPECT_NE(m.find("below 0.35 m"), std::string::npos) << m;
  }
  params.supervisor.walking_com_height_m = params.supervisor.min_com_height_m;  // would fall at once
  EXPECT_NE(Refusal([&] { CheckSteppingStonesFeasible(amber, TwoSteps(0.4, 0.0), params); }).find("min_com_height_m"),
            std::string::npos);
}

TEST(SteppingStonesFeasibility, StoneShorterThanTheSoleIsRefused) {
  const MultibodyModel cassie = Load("cassie_planar");
  SteppingStonesDiagramParams params =
      SteppingStonesDiagramParams::ForRobot("robots/cassie_planar/cassie_planar.rome.json");
  params.supervisor.max_steps = 2;
  // robots.md: toe and heel 0.07 m either side of the sole midpoint; the nominal pose holds the sole level.
  const double sole = 0.14;
  EXPECT_EQ(Refusal([&] { CheckSteppingStonesFeasible(cassie, TwoSteps(0.4, 0.0, sole + 1e-3), params); }), "");
  const std::string m = Refusal([&] { CheckSteppingStonesFeasible(cassie, TwoSteps(0.4, 0.0, sole - 1e-3), params); });
  EXPECT_NE(m.find("shorter than the sole"), std::string::npos) << m;
  EXPECT_NE(Refusal([&] {
              CheckSteppingStonesFeasible(cassie, TwoSteps(0.4, 0.0, sole + 1e-3), params, {.sole_margin_m = 0.01});
            }),
            "");
  // Point feet have no sole: any stone length passes.
  SteppingStonesDiagramParams amber_params;
  amber_params.supervisor.max_steps = 2;
  EXPECT_EQ(Refusal([&] { CheckSteppingStonesFeasible(Load("amber"), TwoSteps(0.4, 0.0, 1e-3), amber_params); }), "");
}

TEST(SteppingStonesFeasibility, MinimumNormalForceMustBeBelowTheWeight) {
  const MultibodyModel amber = Load("amber");
  double mass = 0.0;  // summed over the bodies here, not the model's total
  for (const MultibodyBody& b : amber.bodies()) mass += b.mass;
  SteppingStonesDiagramParams params;
  params.supervisor.max_steps = 2;
  params.controller.min_normal_force_N = params.clf_controller.contact.min_normal_force_N = 0.99 * mass * 9.81;
  EXPECT_EQ(Refusal([&] { CheckSteppingStonesFeasible(amber, TwoSteps(0.4, 0.0), params); }), "");
  params.controller.min_normal_force_N = 1.01 * mass * 9.81;
  EXPECT_NE(Refusal([&] { CheckSteppingStonesFeasible(amber, TwoSteps(0.4, 0.0), params); }).find("below the weight"),
            std::string::npos);
}

TEST(SteppingStonesFeasibility, RobotsTheDiagramsCannotUse) {
  EXPECT_NE(Refusal([] { CheckSteppingStonesRobot(Load("exoskeleton")); }).find("planar robots only"),
            std::string::npos);
  EXPECT_EQ(Refusal([] { CheckSteppingStonesRobot(Load("amber")); }), "");
  EXPECT_NE(Refusal([] { CheckWalkingRobot(Load("amber")); }).find("spatial"), std::string::npos);
  EXPECT_NE(Refusal([] { CheckWalkingRobot(Load("cassie")); }).find("flat feet"), std::string::npos);
  EXPECT_EQ(Refusal([] { CheckWalkingRobot(Load("exoskeleton")); }), "");
  // The exoskeleton on its default base, the quaternion free-flyer: one line naming the file and the option.
  const std::string quaternion =
      Refusal([] { CheckWalkingRobot(MultibodyModel::LoadFromSidecar("robots/exoskeleton/exoskeleton.rome.json")); });
  EXPECT_NE(quaternion.find("walking diagram: robot 'exoskeleton' has a quaternion floating base (nq = 19, nv = 18)"),
            std::string::npos)
      << quaternion;
  EXPECT_NE(quaternion.find("exoskeleton.rome.json' with LoadOptions::euler_floating_base"), std::string::npos)
      << quaternion;
  EXPECT_EQ(quaternion.find('\n'), std::string::npos) << quaternion;
}

TEST(SteppingStonesInitialState, FarFromTheOriginIsThePoseAtTheOriginMoved) {
  const MultibodyModel amber = Load("amber");
  SteppingStonesDiagramParams params;
  const Eigen::VectorXd near = SteppingStonesInitialState(amber, TwoSteps(0.4, 0.0), params);
  const Terrain high = Terrain::Stones({{3.0, 1e5, 0.1}, {3.4, 1e5, 0.1}, {3.8, 1e5, 0.1}});
  Eigen::VectorXd far = SteppingStonesInitialState(amber, high, params);
  far[0] -= 3.0;
  far[1] -= 1e5;
  EXPECT_LT((far - near).cwiseAbs().maxCoeff(), 1e-9);
}

}  // namespace
}  // namespace rome
