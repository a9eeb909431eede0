// ExternalPush on the hybrid plant and on the Bullet plant: a push of impulse J on a robot in flight changes its linear
// momentum by exactly J (plus the impulse of gravity, m g T), against the closed form; no push leaves gravity alone.
#include "systems/perturbations/external_push.h"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_workspace.h"
#include "systems/plants/bullet_world_plant.h"
#include "systems/plants/hybrid_contact_plant.h"
#include "tests/common/error_of.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

std::shared_ptr<const MultibodyModel> Amber() {
  return std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("robots/amber/amber.rome.json"), {.euler_floating_base = true}));
}

// Adds the push and a zero-torque source next to `plant` (named "plant") and connects them.
void AddPushAndZeroTorque(DiagramBuilder& b, const std::shared_ptr<const MultibodyModel>& model,
                          const ExternalPushParams& push) {
  b.AddSystem(std::make_unique<ExternalPush>("push", model, push));
  b.AddSystem(std::make_unique<ConstantVectorSource>("zero_torque", Eigen::VectorXd::Zero(model->nu())));
  b.Connect("plant", "state", "push", "state");
  b.Connect("push", "tau_external", "plant", "tau_external");
  b.Connect("zero_torque", "y", "plant", "u");
}

// The nominal pose 10 m up, tumbling so that the pushed point moves.
std::pair<Eigen::VectorXd, Eigen::VectorXd> TumblingInFlight(const MultibodyModel& model) {
  Eigen::VectorXd q = model.q_nominal(), v = Eigen::VectorXd::Zero(model.nv());
  q[1] += 10.0;
  v[0] = 0.3, v[1] = 0.5, v[2] = -0.4, v[4] = 1.0;
  return {q, v};
}

// AMBER in flight 10 m up, passive (u = 0), with a push on its left shin 5 cm below the link origin. Returns the
// change of the linear momentum m (v_com(T) - v_com(0)) over [0, T].
Eigen::Vector3d MomentumChange(const std::shared_ptr<const MultibodyModel>& model, const ExternalPushParams& push,
                               double T) {
  HybridContactPlantParams pp;
  pp.external_force_input = true;
  DiagramBuilder b;
  const auto* plant = b.AddSystem(std::make_unique<HybridContactPlant>(
      "plant", model, ContactModeGraph::Hopping("left_foot", "right_foot"), Terrain::Flat(), pp));
  AddPushAndZeroTorque(b, model, push);
  auto diagram = b.Build("push_in_flight");
  SimulatorConfig config;
  config.relative_tolerance = 1e-11;
  config.absolute_tolerance = 1e-11;
  Simulator sim(*diagram, config);
  const auto [q, v] = TumblingInFlight(*model);
  plant->SetState(diagram->GetMutableSubsystemContext(*plant, sim.get_mutable_context()), q, v, "flight");
  MultibodyWorkspace ws(*model);
  const Eigen::Vector3d v0 = CalcComVelocity(*model, ws, q, v);
  sim.Initialize();
  const SimulatorStatus status = sim.AdvanceTo(T);
  EXPECT_EQ(status.reason, SimulatorStatus::Reason::kReachedBoundaryTime) << status.ToString();
  const Eigen::VectorXd& x = diagram->GetSubsystemContext(*plant, sim.get_context()).continuous_state();
  const Eigen::Vector3d v1 = CalcComVelocity(*model, ws, x.head(model->nv()), x.tail(model->nv()));
  return model->total_mass() * (v1 - v0);
}

// 60 N forward and 25 N up for 50 ms on the left shin, 5 cm below its origin, from t = 0.1 s.
ExternalPushParams ShinPush() {
  ExternalPushParams push;
  push.body = "left_shin";
  push.point_in_body_m = Eigen::Vector3d(0.0, 0.0, -0.05);
  push.start_time_s = 0.1;
  push.duration_s = 0.05;
  push.force_N = Eigen::Vector3d(60.0, 0.0, 25.0);
  return push;
}

TEST(ExternalPush, ImpulseChangesTheLinearMomentumOfAFlyingRobotByExactlyJ) {
  auto model = Amber();
  ExternalPushParams push = ShinPush();
  const double T = 0.3, m = model->total_mass();
  // Closed form: Δp = m g T + F duration (the push ends before T). Planar model: y stays 0.
  const Eigen::Vector3d expected = m * model->gravity() * T + push.force_N * push.duration_s;
  const Eigen::Vector3d dp = MomentumChange(model, push, T);
  EXPECT_NEAR(dp.x(), expected.x(), 1e-6) << "J = " << push.impulse_Ns().transpose();
  EXPECT_NEAR(dp.z(), expected.z(), 1e-6);
  // Stopped halfway through the push: half the impulse.
  const Eigen::Vector3d half = MomentumChange(model, push, 0.125);
  EXPECT_NEAR(half.x(), 0.5 * push.force_N.x() * push.duration_s, 1e-6);
  EXPECT_NEAR(half.z(), m * model->gravity().z() * 0.125 + 0.5 * push.force_N.z() * push.duration_s, 1e-6);
  // No push (zero force): gravity alone.
  push.force_N.setZero();
  const Eigen::Vector3d none = MomentumChange(model, push, T);
  EXPECT_NEAR(none.x(), 0.0, 1e-6);
  EXPECT_NEAR(none.z(), m * model->gravity().z() * T, 1e-6);
}

// The same flight on BulletWorldPlant (1 ms steps, semi-implicit Euler; the push's force enters as joint torques
// J_pᵀ F through its tau_external input). The plant's step at t_k reads the push as it was before the push's own
// update at t_k, so the impulse arrives one step late but whole. Returns m (v_com(T) - v_com(0)).
Eigen::Vector3d BulletMomentumChange(const std::shared_ptr<const MultibodyModel>& model, const ExternalPushParams& push,
                                     double T) {
  BulletWorldPlantParams pp;
  pp.external_force_input = true;
  DiagramBuilder b;
  const auto* plant = b.AddSystem(std::make_unique<BulletWorldPlant>(
      "plant", model, ContactModeGraph::Hopping("left_foot", "right_foot"), Terrain::Flat(), pp));
  AddPushAndZeroTorque(b, model, push);
  auto diagram = b.Build("bullet_push_in_flight");
  Simulator sim(*diagram, SimulatorConfig{});
  const auto [q, v] = TumblingInFlight(*model);
  plant->SetState(diagram->GetMutableSubsystemContext(*plant, sim.get_mutable_context()), q, v, "flight");
  MultibodyWorkspace ws(*model);
  const Eigen::Vector3d v0 = CalcComVelocity(*model, ws, q, v);
  const SimulatorStatus status = sim.AdvanceTo(T);
  EXPECT_EQ(status.reason, SimulatorStatus::Reason::kReachedBoundaryTime) << status.ToString();
  const LeafContext& pc = diagram->GetSubsystemContext(*plant, sim.get_context());
  const Eigen::Vector3d v1 = CalcComVelocity(*model, ws, plant->EvalOutput(pc, "q"), plant->EvalOutput(pc, "v"));
  return model->total_mass() * (v1 - v0);
}

TEST(ExternalPush, OnTheBulletPlantTheImpulseChangesTheLinearMomentumByJ) {
  auto model = Amber();
  ExternalPushParams push = ShinPush();
  const double m = model->total_mass();
  const Eigen::Vector3d J = push.force_N * push.duration_s;
  // Compared with the same flight unpushed, so that gravity's impulse (m g per step, whatever the plant's step
  // convention) cancels. Bullet's semi-implicit Euler does not conserve m v_com exactly: v_com = J_com(q) v and q moves
  // within a step, which leaves 1.5e-5 N s in x over the unpushed flight and 5e-4 of J with the push (1 ms steps,
  // measured); the tolerance is 1e-3 of |J|. A missing push or one step of it too many or too few (2 % of J) fails.
  const Eigen::Vector3d with = BulletMomentumChange(model, push, 0.3);
  push.force_N.setZero();
  const Eigen::Vector3d without = BulletMomentumChange(model, push, 0.3);
  const double tol = 1e-3 * J.norm();
  EXPECT_NEAR(with.x() - without.x(), J.x(), tol) << "with " << with.transpose() << ", without " << without.transpose();
  EXPECT_NEAR(with.z() - without.z(), J.z(), tol);
  // Gravity alone: m g over the flight (0.3 s, 300 steps, give or take one).
  EXPECT_NEAR(without.z(), m * model->gravity().z() * 0.3, std::abs(m * model->gravity().z()) * 1e-3 + tol);
  EXPECT_NEAR(without.x(), 0.0, tol);
}

TEST(ExternalPush, BadInputNamesTheSystemAndTheValue) {
  auto model = Amber();
  ExternalPushParams push;
  push.body = "no_such_link";
  EXPECT_NE(test::ErrorOf([&] { ExternalPush("push", model, push); }).find("no_such_link"), std::string::npos)
      << test::ErrorOf([&] { ExternalPush("push", model, push); });
  push.body = "torso";
  push.duration_s = 0.0;
  EXPECT_NE(test::ErrorOf([&] { ExternalPush("push", model, push); }).find("duration_s = 0"), std::string::npos)
      << test::ErrorOf([&] { ExternalPush("push", model, push); });
  push.duration_s = 0.1;
  push.force_N = Eigen::Vector3d(std::nan(""), 0, 0);
  EXPECT_NE(test::ErrorOf([&] { ExternalPush("push", model, push); }).find("force_N"), std::string::npos)
      << test::ErrorOf([&] { ExternalPush("push", model, push); });
}

}  // namespace
}  // namespace rome
