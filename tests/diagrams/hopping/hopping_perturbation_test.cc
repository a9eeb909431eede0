// Perturbations on the hopping diagram, checked against Newton's second law for the whole robot in flight, where the
// ground exerts no force: the linear momentum changes by exactly the push's impulse J = F T_push less m g Δt. The plant
// is built with its link masses scaled by s (ScaleMassAndFriction), so the COM velocity changes by J / (s m) − g Δt:
// the push measures the plant's mass. Uniform scaling leaves the COM where it is, so the COM velocity is computed on
// the unscaled model (the controller's).
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "diagrams/hopping/hopping_diagram.h"
#include "diagrams/hopping/hopping_plans.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/robot_files.h"

namespace rome {
namespace {

constexpr double kMassScale = 1.1;
constexpr double kGravity = 9.81;  // [m/s^2] the plant's gravity (MultibodyModel default)

struct Hop {
  std::shared_ptr<const MultibodyModel> model;
  std::unique_ptr<SpringMassHopPlanners> rom;
  HoppingDiagram d;
  std::unique_ptr<Simulator> sim;
};

std::unique_ptr<Hop> MakeHop(const PerturbationParams& perturbations) {
  auto h = std::make_unique<Hop>();
  h->model = std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromSidecar(FindRobotFile("robots/cassie/cassie.rome.json"), {.euler_floating_base = true}));
  h->rom = std::make_unique<SpringMassHopPlanners>(*h->model, LegStiffnessVariant::kIdentified, SpringMassJumpParams{},
                                                   SpringMassLandingParams{});
  HoppingDiagramParams params;
  params.reference.hops = 1;
  params.perturbations = perturbations;
  h->d = BuildHoppingDiagram(h->model, h->rom->leg_length, h->rom->jump, h->rom->landing, params);
  h->sim = std::make_unique<Simulator>(*h->d.diagram, HoppingSimulatorConfig());
  SetHoppingInitialState(h->d, h->sim->get_mutable_context(), h->model->q_nominal());
  return h;
}

int Mode(const Hop& h) {
  return h.d.plant->EvalTypedOutput<int>(h.d.diagram->GetSubsystemContext(*h.d.plant, h.sim->get_context()), "mode");
}

// COM velocity of the plant's state, on the controller's (unscaled) model.
Eigen::Vector3d ComVelocity(const Hop& h) {
  const Eigen::VectorXd x =
      h.d.plant->EvalOutput(h.d.diagram->GetSubsystemContext(*h.d.plant, h.sim->get_context()), "state");
  MultibodyWorkspace ws(*h.model);
  const int nv = h.model->nv();
  return CalcComVelocity(*h.model, ws, x.head(nv), x.tail(nv));
}

// Advances to t in 1 ms steps; false if the run ends or the plant's mode is not `mode` at any of them.
bool AdvanceIn(Hop& h, double t, int mode) {
  while (h.sim->get_context().time() < t - 1e-12) {
    const double next = std::min(t, h.sim->get_context().time() + 1e-3);
    if (!h.sim->AdvanceTo(next).ok()) return false;
    if (Mode(h) != mode) return false;
  }
  return true;
}

TEST(HoppingPerturbations, PushInFlightChangesTheMomentumOfTheScaledPlantByTheImpulseLessGravity) {
  PerturbationParams scaled;
  scaled.mass_scale = kMassScale;
  // The lift-off time of the scaled robot, unpushed (a push that starts later cannot change it).
  auto nominal = MakeHop(scaled);
  const int flight = nominal->d.plant->graph().ModeIndex("flight", "test");
  double liftoff = -1;
  while (nominal->sim->get_context().time() < 3.0) {
    ASSERT_TRUE(nominal->sim->AdvanceTo(nominal->sim->get_context().time() + 1e-3).ok());
    if (Mode(*nominal) == flight) {
      liftoff = nominal->sim->get_context().time();
      break;
    }
  }
  ASSERT_GT(liftoff, 0.5) << "the robot did not lift off within 3 s";
  EXPECT_NEAR(nominal->d.plant->model().total_mass(), kMassScale * nominal->model->total_mass(), 1e-9);

  // Unpushed flight: the COM falls freely, Δv = −g Δt (contact-free, whatever the mass).
  const double t_a = liftoff + 0.02, t_b = liftoff + 0.22;
  ASSERT_TRUE(AdvanceIn(*nominal, t_a, flight));
  const Eigen::Vector3d v_a0 = ComVelocity(*nominal);
  ASSERT_TRUE(AdvanceIn(*nominal, t_b, flight)) << "touched down before t_b";
  const Eigen::Vector3d free_fall = ComVelocity(*nominal) - v_a0;
  EXPECT_NEAR(free_fall.x(), 0.0, 1e-5);
  EXPECT_NEAR(free_fall.y(), 0.0, 1e-5);
  EXPECT_NEAR(free_fall.z(), -kGravity * (t_b - t_a), 1e-5);

  // Pushed in flight on the pelvis, off its origin (the push also turns the robot; the linear momentum does not care).
  PerturbationParams pushed = scaled;
  ExternalPushParams push;
  push.body = "pelvis";
  push.point_in_body_m = Eigen::Vector3d(0.05, -0.03, 0.1);
  push.start_time_s = liftoff + 0.05;
  push.duration_s = 0.1;
  push.force_N = Eigen::Vector3d(40.0, -25.0, 60.0);
  pushed.push = push;
  auto hop = MakeHop(pushed);
  // The same 1 ms steps as the unpushed run up to its lift-off.
  while (hop->sim->get_context().time() < liftoff - 1e-12)
    ASSERT_TRUE(hop->sim->AdvanceTo(hop->sim->get_context().time() + 1e-3).ok());
  ASSERT_EQ(Mode(*hop), flight) << "the pushed run lifted off at another time";
  ASSERT_TRUE(AdvanceIn(*hop, t_a, flight));
  const Eigen::Vector3d v_a = ComVelocity(*hop);
  EXPECT_NEAR((v_a - v_a0).norm(), 0.0, 1e-9) << "the runs differ before the push";
  ASSERT_TRUE(AdvanceIn(*hop, t_b, flight)) << "touched down before t_b";
  const double m = kMassScale * hop->model->total_mass();
  const Eigen::Vector3d dp = m * (ComVelocity(*hop) - v_a);
  const Eigen::Vector3d expected =
      push.force_N * push.duration_s - m * kGravity * (t_b - t_a) * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR((dp - expected).norm(), 0.0, 1e-3) << "dp = " << dp.transpose() << ", expected " << expected.transpose();
  // The same push on the unscaled mass would give a velocity change larger by s: the check above tells them apart.
  EXPECT_GT(((kMassScale - 1.0) / kMassScale) * (push.force_N * push.duration_s).norm(), 100 * 1e-3);
}

}  // namespace
}  // namespace rome
