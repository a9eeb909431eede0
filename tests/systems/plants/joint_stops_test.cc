// HybridContactPlant's joint stops and JointLimitStatistics on a compound pendulum made in the test: the time the
// pendulum, released at rest, reaches its upper limit against the closed form (complete and incomplete elliptic
// integrals of the first kind), the failure message, a start beyond a limit, and the monitor's margins.
#include <cmath>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "framework/simulator.h"
#include "systems/plants/hybrid_contact_plant.h"
#include "systems/plants/joint_limit_statistics.h"

namespace rome {
namespace {

// A rod hinged about y at the world origin: mass m at distance l below the hinge, inertia Iyy about its centre of
// mass; URDF limits [lower, upper] rad. q > 0 swings the mass toward -x; q = 0 hangs straight down.
constexpr double kMass = 2.0, kLength = 0.6, kIyy = 0.03, kLower = -2.0, kUpper = 0.5;

std::shared_ptr<const MultibodyModel> Pendulum() {
  const std::string urdf = R"(<?xml version="1.0"?>
<robot name="stop_pendulum">
  <link name="world_anchor"/>
  <joint name="hinge" type="revolute">
    <parent link="world_anchor"/><child link="rod"/>
    <origin xyz="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2.0" upper="0.5" effort="10" velocity="100"/>
  </joint>
  <link name="rod">
    <inertial><origin xyz="0 0 -0.6"/><mass value="2.0"/>
      <inertia ixx="0.03" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.001"/></inertial>
  </link>
</robot>)";
  return std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromText(urdf, "", "stop_pendulum.urdf"));
}

ContactModeGraph FreeSwing() {
  ContactModeGraph g;
  g.modes = {{"swing", {}}};
  g.initial_mode = "swing";
  return g;
}

// Released at rest from -theta0, a pendulum with equivalent length L = (m l² + Iyy) / (m l) reaches theta (|theta| <
// theta0) after sqrt(L / g) (K(k) + F(phi, k)), k = sin(theta0 / 2), sin(phi) = sin(theta / 2) / k.
double ClosedFormTime(double theta0, double theta) {
  const double L = (kMass * kLength * kLength + kIyy) / (kMass * kLength);
  const double k = std::sin(theta0 / 2);
  const double phi = std::asin(std::sin(theta / 2) / k);
  return std::sqrt(L / 9.81) * (std::comp_ellint_1(k) + std::ellint_1(k, phi));
}

SimulatorConfig Tight() {
  SimulatorConfig c;
  c.relative_tolerance = 1e-11;
  c.absolute_tolerance = 1e-11;
  return c;
}

struct Outcome {
  SimulatorStatus status;
  JointLimitStatistics limits;
  double final_q = 0;  // the context's q where the run ended
};

Outcome Release(double q0, bool stops, double t_final) {
  const auto model = Pendulum();
  HybridContactPlantParams params;
  params.joint_stops = stops;
  HybridContactPlant plant("pendulum", model, FreeSwing(), Terrain::Flat(), params);
  auto context = plant.CreateDefaultLeafContext();
  plant.SetState(*context, Eigen::VectorXd::Constant(1, q0), Eigen::VectorXd::Zero(1), "swing");
  context->FixInputPort(0, Eigen::VectorXd::Zero(model->nu()));
  Outcome run;
  const LeafContext* ctx = context.get();
  Simulator sim(plant, std::move(context), Tight());
  sim.add_monitor([&](const Context&) {
    run.limits.Record(*model, ctx->time(), ctx->continuous_state().head(1));
    return EventStatus::Succeeded();
  });
  run.status = sim.AdvanceTo(t_final);
  run.final_q = ctx->continuous_state()[0];
  return run;
}

TEST(JointStops, ReachingTheUpperLimitEndsTheRunAtTheClosedFormTime) {
  const double theta0 = 1.0;  // released at -1 rad: it would swing up to +1 rad, past the 0.5 rad stop
  const Outcome run = Release(-theta0, true, 3.0);
  ASSERT_EQ(run.status.reason, SimulatorStatus::Reason::kFailed) << run.status.ToString();
  EXPECT_NEAR(run.status.time, ClosedFormTime(theta0, kUpper), 1e-8);
  for (const std::string part : {"joint 'hinge' reached its upper limit 0.5", "joint stop"})
    EXPECT_NE(run.status.message.find(part), std::string::npos) << run.status.message;
  EXPECT_EQ(run.status.system, "pendulum");
  // The run ends on the limit; every integrator step before the stop's event stayed inside it (the monitor does not
  // run after the failed event).
  EXPECT_NEAR(run.final_q, kUpper, 1e-8);
  EXPECT_EQ(run.limits.violations, 0) << run.limits.first_violation;
  EXPECT_GT(run.limits.min_upper_margin[0], 0.0);
  EXPECT_NEAR(run.limits.min_lower_margin[0], -theta0 - kLower, 1e-12);
}

TEST(JointStops, WithoutStopsThePendulumSwingsPastTheLimitAndTheMonitorSeesIt) {
  const double theta0 = 1.0;
  // Half a period: the turning point +theta0 (energy), 0.5 rad beyond the upper limit.
  const Outcome run = Release(-theta0, false, 2 * ClosedFormTime(theta0, 0.0));
  EXPECT_TRUE(run.status.ok()) << run.status.ToString();
  EXPECT_GT(run.limits.violations, 0);
  EXPECT_NE(run.limits.first_violation.find("joint 'hinge'"), std::string::npos) << run.limits.first_violation;
  EXPECT_NE(run.limits.first_violation.find("upper limit 0.5"), std::string::npos) << run.limits.first_violation;
  EXPECT_NEAR(run.limits.min_upper_margin[0], kUpper - theta0, 1e-6);
  const auto model = Pendulum();
  std::string where;
  EXPECT_NEAR(run.limits.SmallestMargin(*model, &where), kUpper - theta0, 1e-6);
  EXPECT_EQ(where, "hinge upper");
}

TEST(JointStops, AStartBeyondALimitEndsTheRunAtOnceNamingTheJoint) {
  const Outcome run = Release(kUpper + 0.1, true, 1.0);
  ASSERT_EQ(run.status.reason, SimulatorStatus::Reason::kFailed) << run.status.ToString();
  EXPECT_NEAR(run.status.time, 0.0, 1e-12);
  for (const std::string part : {"joint 'hinge' is beyond its upper limit 0.5", "q = 0.6", "outside the limits"})
    EXPECT_NE(run.status.message.find(part), std::string::npos) << run.status.message;
}

TEST(JointStops, ABadToleranceIsNamed) {
  HybridContactPlantParams params;
  params.joint_stops = true;
  params.joint_stop_tolerance = -1.0;
  try {
    HybridContactPlant plant("pendulum", Pendulum(), FreeSwing(), Terrain::Flat(), params);
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("joint_stop_tolerance = -1"), std::string::npos) << e.what();
  }
}

TEST(JointLimitStatistics, AWronglySizedStateIsNamed) {
  JointLimitStatistics s;
  EXPECT_THROW(s.Record(*Pendulum(), 0.0, Eigen::VectorXd::Zero(2)), std::invalid_argument);
}

}  // namespace
}  // namespace rome
