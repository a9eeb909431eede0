// BulletWorldPlant: energy of a free pendulum, a box at rest on the plane, a ball falling off a stone's edge into the
// gap and hitting the stone's side, agreement with HybridContactPlant in flight and in stance, and bad input.
#include "systems/plants/bullet_world_plant.h"

#include <gtest/gtest.h>

#include <cmath>

#include "framework/simulator.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_workspace.h"
#include "systems/plants/hybrid_contact_plant.h"

namespace rome {
namespace {

std::string Source(const std::string& path) { return std::string(ROME_SOURCE_DIR) + "/" + path; }

std::shared_ptr<const MultibodyModel> LoadSidecar(const std::string& path) {
  return std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(Source(path)));
}

ContactModeGraph NoContacts() {
  ContactModeGraph g;
  g.modes = {{"free", {}}};
  return g;
}

// Runs a plant alone (input fixed) from (q, v) in `mode` to t_final; returns the simulator (its context holds the state).
struct PlantRun {
  std::unique_ptr<Simulator> sim;
  const LeafContext* context = nullptr;
};
PlantRun Start(const ContactPlant& plant, const Eigen::VectorXd& q, const Eigen::VectorXd& v, const std::string& mode, const Eigen::VectorXd& u,
          SimulatorConfig config = {}) {
  auto context = plant.CreateDefaultLeafContext();
  plant.SetState(*context, q, v, mode);
  context->FixInputPort(0, u);
  PlantRun r;
  r.context = context.get();
  r.sim = std::make_unique<Simulator>(plant, std::move(context), config);
  return r;
}

// Bullet steps a multibody by semi-implicit Euler with explicit velocity-product terms: for a double pendulum (its
// mass matrix depends on q) that is not symplectic, and the energy drifts, at first order in the step. Double pendulum
// (tests/systems/multibody/data), released from 1.0 rad and 0.5 rad, energy from our own kinematics (not Bullet's):
// over 10 s at 1 kHz |E(t) - E(0)| stays below 2.5 % of the potential-energy swing m g Δz ~ 22.6 J (bound ours;
// measured 1.3 %, growing steadily), and 10 substeps (0.1 ms) cut it at least fivefold (first order).
TEST(BulletWorldPlant, FreePendulumEnergyDriftIsBoundedOver10sAt1kHz) {
  auto model = std::make_shared<const MultibodyModel>(MultibodyModel::Load(Source("tests/systems/multibody/data/double_pendulum.urdf")));
  MultibodyWorkspace ws(*model);
  auto energy = [&](const Eigen::VectorXd& x) {
    return CalcKineticEnergy(*model, ws, x.head(2), x.tail(2)) + CalcPotentialEnergy(*model, ws, x.head(2));
  };
  double drift[2];
  for (int i = 0; i < 2; ++i) {
    BulletWorldPlantParams params;
    params.enable_joint_limits = false;
    params.substeps = i == 0 ? 1 : 10;
    BulletWorldPlant plant("pendulum", model, NoContacts(), Terrain::Flat(-100.0), params);
    Eigen::VectorXd q(2);
    q << 1.0, 0.5;
    PlantRun run = Start(plant, q, Eigen::VectorXd::Zero(2), "free", Eigen::VectorXd::Zero(model->nu()));
    const double e0 = energy(run.context->discrete_state().head(4));
    drift[i] = 0;
    double max_speed = 0;
    for (int k = 1; k <= 10000; ++k) {
      ASSERT_TRUE(run.sim->AdvanceTo(k * 1e-3).ok());
      drift[i] = std::max(drift[i], std::abs(energy(run.context->discrete_state().head(4)) - e0));
      max_speed = std::max(max_speed, run.context->discrete_state().tail(2).norm());
    }
    EXPECT_GT(max_speed, 1.0) << "it swung";
  }
  const double pe_swing = 2.3 * 9.81 * 1.0;  // total mass x g x ~1 m of height change
  RecordProperty("energy_drift_1ms_J", std::to_string(drift[0]));
  RecordProperty("energy_drift_0.1ms_J", std::to_string(drift[1]));
  EXPECT_LT(drift[0], 0.025 * pe_swing);
  EXPECT_LT(drift[1], 0.2 * drift[0]);
}

// A box dropped flat from 0.2 m comes to rest with its bottom on the plane: base height = half its height 0.05 m
// (geometry), every corner penetrating < 1 mm, and the ground carrying its weight m g (statics).
TEST(BulletWorldPlant, DroppedBoxRestsOnThePlaneAtItsHalfHeight) {
  auto model = LoadSidecar("tests/systems/plants/data/planar_box.rome.json");
  ContactModeGraph graph;
  graph.modes = {{"flight", {}}, {"resting", {"bottom"}}};
  graph.transitions = {{"flight", "resting", ContactModeGraph::Kind::kTouchdown, "bottom"}, {"resting", "flight", ContactModeGraph::Kind::kLiftoff, "bottom"}};
  graph.initial_mode = "flight";
  BulletWorldPlantParams params;
  params.min_base_height_m = -1.0;
  BulletWorldPlant plant("box", model, graph, Terrain::Flat(), params);
  Eigen::VectorXd q(3);
  q << 0.0, 0.25, 0.0;
  PlantRun run = Start(plant, q, Eigen::VectorXd::Zero(3), "flight", Eigen::VectorXd::Zero(0));
  const auto status = run.sim->AdvanceTo(1.5);
  ASSERT_TRUE(status.ok()) << status.ToString();
  EXPECT_EQ(run.context->mode(), plant.GetModeIndex("resting"));
  ASSERT_GE(run.sim->statistics().events.size(), 1u);
  EXPECT_EQ(run.sim->statistics().events[0].guard, "touchdown_bottom");
  // Free fall of 0.2 m: touchdown at sqrt(2 h / g) = 0.2019 s, within one 1 ms step.
  EXPECT_NEAR(run.sim->statistics().events[0].time, std::sqrt(2 * 0.2 / 9.81), 2e-3);
  const Eigen::VectorXd x = run.context->discrete_state();
  EXPECT_NEAR(x[1], 0.05, 1e-3);
  EXPECT_NEAR(x[2], 0.0, 1e-3);
  MultibodyWorkspace ws(*model);
  for (const Eigen::Vector3d& p : model->contacts()[0].points) {
    const double z = CalcPointPosition(*model, ws, x.head(3), model->contacts()[0].body, p).z();
    EXPECT_GT(z, -1e-3) << "penetration";
    EXPECT_LT(z, 1e-3);
  }
  const Eigen::VectorXd f = plant.EvalOutput(*run.context, "contact_forces");
  EXPECT_NEAR(f[2], 3.0 * 9.81, 1e-3 * 3.0 * 9.81);
  EXPECT_NEAR(f[0], 0.0, 1e-6);
  EXPECT_LT(x.segment(3, 3).norm(), 1e-6);
}

// A ball sliding at 1 m/s with its bottom on a stone's top, 1 cm before the right edge, slides off the edge and falls
// into the gap (no stone top under it, so nothing holds it at the stone's height). Sent back left at 1 m/s while in
// the gap, its left side hits the stone's right side face, which pushes it along +x (a horizontal normal), and it never
// passes into the stone.
TEST(BulletWorldPlant, BallOnAStoneEdgeFallsIntoTheGapAndHitsTheSide) {
  auto model = LoadSidecar("tests/systems/plants/data/planar_ball.rome.json");
  ContactModeGraph graph;
  graph.modes = {{"free", {}}};
  const Terrain stones = Terrain::Stones({{0.0, 0.0, 0.2}, {1.0, 0.0, 0.2}});  // stone 0 spans -0.1 .. 0.1 m
  BulletWorldPlantParams params;
  params.min_base_height_m = -10.0;
  BulletWorldPlant plant("ball", model, graph, stones, params);
  Eigen::VectorXd q(3), v(3);
  q << 0.09, 0.05, 0.0;
  v << 1.0, 0.0, 0.0;
  PlantRun run = Start(plant, q, v, "free", Eigen::VectorXd::Zero(0));
  const int surface = model->ContactIndex("surface");
  double min_x_after_push = 1e9, max_side_fx = 0;
  // 0.42 s: still above the floor plane (1 m below the stone tops), so every +x force comes from the side face.
  for (int k = 1; k <= 420; ++k) {
    ASSERT_TRUE(run.sim->AdvanceTo(k * 1e-3).ok());
    if (k == 200) {
      const Eigen::VectorXd& x = run.context->discrete_state();
      ASSERT_GT(x[0] - 0.05, 0.1) << "the ball is not past the edge";
      ASSERT_LT(x[1] + 0.05, -0.05) << "the ball did not fall into the gap";
      Eigen::VectorXd& xd = const_cast<LeafContext*>(run.context)->get_mutable_discrete_state();
      xd[3] = -1.0;
      xd[5] = 0.0;
      run.sim->Initialize();
    }
    if (k > 200) {
      min_x_after_push = std::min(min_x_after_push, run.context->discrete_state()[0]);
      max_side_fx = std::max(max_side_fx, plant.EvalOutput(*run.context, "contact_forces")[3 * surface + 0]);
    }
  }
  const Eigen::VectorXd x = run.context->discrete_state();
  EXPECT_LT(x[1], -0.5) << "fell deep into the gap";
  // The side face is at x = 0.1: the ball's left side (x - 0.05) stays outside it (1 mm between its points, 1 mm slack).
  EXPECT_GT(min_x_after_push - 0.05, 0.1 - 2e-3);
  EXPECT_LT(min_x_after_push - 0.05, 0.1 + 2e-3) << "it reached the side face";
  EXPECT_GT(max_side_fx, 1.0) << "the side face pushed the ball along +x";
  EXPECT_GT(x[3], -1e-3) << "it no longer moves into the face";
}

// AMBER in flight, far above the ground, under the same constant torques on both plants for 0.2 s: Bullet's
// semi-implicit Euler converges at first order to the hybrid plant's CVODE solution (rtol 1e-10). At 1 ms the joint
// angles agree to 5 mrad; with 10 substeps (0.1 ms) the error shrinks about tenfold (first order). The reflected
// rotor inertia (a geared rotor link in Bullet, added to M's diagonal in ours) is part of what is compared.
TEST(BulletWorldPlant, AgreesWithHybridPlantInFlightToIntegrationAccuracy) {
  auto model = LoadSidecar("robots/amber/amber.rome.json");
  const auto graph = ContactModeGraph::AlternatingSingleSupport("left_foot", "right_foot");
  Eigen::VectorXd q = model->q_nominal();
  q[1] += 5.0;
  Eigen::VectorXd v = Eigen::VectorXd::Zero(model->nv());
  v[0] = 0.5, v[2] = 0.3, v[3] = -1.0, v[5] = 2.0;
  Eigen::VectorXd u(model->nu());
  u << 8.0, -5.0, -6.0, 4.0;
  HybridContactPlant hybrid("hybrid", model, graph, Terrain::Flat());
  SimulatorConfig tight;
  tight.relative_tolerance = 1e-10;
  tight.absolute_tolerance = 1e-10;
  PlantRun h = Start(hybrid, q, v, "flight", u, tight);
  ASSERT_TRUE(h.sim->AdvanceTo(0.2).ok());
  const Eigen::VectorXd x_ref = h.context->continuous_state();
  double err[2];
  for (int i = 0; i < 2; ++i) {
    BulletWorldPlantParams params;
    params.substeps = i == 0 ? 1 : 10;
    params.enable_joint_limits = false;  // the hybrid plant has none
    BulletWorldPlant bullet("bullet", model, graph, Terrain::Flat(), params);
    PlantRun b = Start(bullet, q, v, "flight", u);
    // The state held after the update at 0.199 s + offset is the state at 0.2 s.
    ASSERT_TRUE(b.sim->AdvanceTo(0.1995).ok());
    err[i] = (b.context->discrete_state().head(model->nv()) - x_ref.head(model->nv())).cwiseAbs().maxCoeff();
    EXPECT_LT(bullet.GearVelocityError(*b.context), 1e-6) << "the armature gears slipped";
  }
  RecordProperty("flight_error_1ms", std::to_string(err[0]));
  RecordProperty("flight_error_0.1ms", std::to_string(err[1]));
  EXPECT_LT(err[0], 5e-3);
  EXPECT_LT(err[1], 0.2 * err[0]);
}

// AMBER standing on its left foot (right foot 5 cm up, in the air), passive except for constant torques that hold the
// hip and knee only roughly: on both plants it tips and the swing foot falls. Until the first impact (the hybrid
// plant's first guard event) the stance foot stays put on both (no slip: the friction cone holds) and q agrees within
// 2 cm / 0.02 rad (bound ours: Bullet's contact holds the foot by a velocity-level constraint with ERP position
// correction, ours by an exact acceleration-level weld, plus Bullet's first-order step).
TEST(BulletWorldPlant, AgreesWithHybridPlantInStanceUntilTheFirstImpact) {
  auto model = LoadSidecar("robots/amber/amber.rome.json");
  const auto graph = ContactModeGraph::AlternatingSingleSupport("left_foot", "right_foot");
  MultibodyWorkspace ws(*model);
  Eigen::VectorXd q = model->q_nominal();
  q[model->VelocityIndex("right_knee")] = 0.9;  // lifts the right foot
  q[model->VelocityIndex("right_hip")] = -0.5;
  // Keep the left (stance) foot on the ground: shift the base so that its point is at z = 0, x = 0.
  const Eigen::Vector3d p = CalcContactPointPosition(*model, ws, q, model->ContactIndex("left_foot"), 0);
  q[0] -= p.x(), q[1] -= p.z();
  ASSERT_GT(CalcContactPointPosition(*model, ws, q, model->ContactIndex("right_foot"), 0).z(), 0.03);
  Eigen::VectorXd u(model->nu());
  u << 2.0, 10.0, 1.0, 3.0;
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(model->nv());
  HybridContactPlant hybrid("hybrid", model, graph, Terrain::Flat());
  SimulatorConfig tight;
  tight.relative_tolerance = 1e-10;
  tight.absolute_tolerance = 1e-10;
  PlantRun h = Start(hybrid, q, v, "left_foot_stance", u, tight);
  BulletWorldPlant bullet("bullet", model, graph, Terrain::Flat());
  PlantRun b = Start(bullet, q, v, "left_foot_stance", u);
  double worst = 0, t_impact = 1.0;
  for (int k = 1; k <= 1000; ++k) {
    const double t = k * 1e-3;
    const auto status = h.sim->AdvanceTo(t);
    if (!status.ok() || !h.sim->statistics().events.empty()) {
      t_impact = t;
      break;
    }
    ASSERT_TRUE(b.sim->AdvanceTo(t - 0.5e-3).ok());  // Bullet's state at t
    const Eigen::VectorXd dq = b.context->discrete_state().head(model->nv()) - h.context->continuous_state().head(model->nv());
    worst = std::max(worst, dq.cwiseAbs().maxCoeff());
    const Eigen::Vector3d foot = CalcContactPointPosition(*model, ws, b.context->discrete_state().head(model->nv()), 0, 0);
    ASSERT_LT(std::abs(foot.x()), 1e-3) << "Bullet's stance foot slipped at t = " << t;
    ASSERT_LT(std::abs(foot.z()), 1e-3) << "Bullet's stance foot left the ground at t = " << t;
  }
  RecordProperty("stance_error", std::to_string(worst));
  RecordProperty("first_impact_s", std::to_string(t_impact));
  EXPECT_GT(t_impact, 0.1) << "the comparison covered too little time";
  EXPECT_LT(worst, 0.02);
}

TEST(BulletWorldPlant, BadInputGetsOneLineErrors) {
  auto model = LoadSidecar("tests/systems/plants/data/planar_ball.rome.json");
  auto expect_error = [](const std::function<void()>& f, const std::string& part) {
    try {
      f();
      ADD_FAILURE() << "no error; expected one containing '" << part << "'";
    } catch (const std::exception& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(part), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << "not one line: " << what;
    }
  };
  BulletWorldPlantParams zero_step;
  zero_step.step_s = 0.0;
  expect_error([&] { BulletWorldPlant("ball", model, NoContacts(), Terrain::Flat(), zero_step); }, "step_s must be positive, got 0");
  BulletWorldPlantParams negative_step;
  negative_step.step_s = -1e-3;
  expect_error([&] { BulletWorldPlant("ball", model, NoContacts(), Terrain::Flat(), negative_step); }, "step_s must be positive, got -0.001");
  BulletWorldPlantParams no_substeps;
  no_substeps.substeps = 0;
  expect_error([&] { BulletWorldPlant("ball", model, NoContacts(), Terrain::Flat(), no_substeps); }, "substeps must be at least 1");
  // A stone of zero size: the terrain rejects it, naming the stone.
  expect_error([&] { Terrain::Stones({{0.0, 0.0, 0.2}, {1.0, 0.0, 0.0}}); }, "stone");
  // A sidecar contact with no points has no collision geometry: the sidecar loader rejects it, naming the contact.
  expect_error([&] { LoadSidecar("tests/systems/plants/data/no_points.rome.json"); }, "needs 1 points, got []");
}

}  // namespace
}  // namespace rome
