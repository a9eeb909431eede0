// BulletWorldPlant: energy of a free pendulum, a box at rest on the plane, a ball falling off a stone's edge into the
// gap and hitting the stone's side, agreement with HybridContactPlant in flight and in stance, Cassie's achilles rods
// (loop closures) holding their length while it stands, the exoskeleton standing in double support (forces sum to
// m g, centres of pressure inside the soles, no drift), and bad input.
#include "systems/plants/bullet_world_plant.h"
#include "systems/plants/contact_force_statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "framework/diagram.h"
#include "framework/simulator.h"
#include "systems/controllers/joint_pd_controller.h"
#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_workspace.h"
#include "systems/plants/hybrid_contact_plant.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

std::string Source(const std::string& path) { return rome::test::SourcePath(path); }

std::shared_ptr<const MultibodyModel> LoadSidecar(const std::string& path) {
  return std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromSidecar(Source(path), {.euler_floating_base = true}));
}

ContactModeGraph NoContacts() {
  ContactModeGraph g;
  g.modes = {{"free", {}}};
  return g;
}

// Runs a plant alone (input fixed) from (q, v) in `mode` to t_final; returns the simulator (its context holds the
// state).
struct PlantRun {
  std::unique_ptr<Simulator> sim;
  const LeafContext* context = nullptr;
};
PlantRun Start(const ContactPlant& plant, const Eigen::VectorXd& q, const Eigen::VectorXd& v, const std::string& mode,
               const Eigen::VectorXd& u, SimulatorConfig config = {}) {
  auto context = plant.CreateDefaultLeafContext();
  plant.SetState(*context, q, v, mode);
  context->FixInputPort(0, u);
  PlantRun r;
  r.context = context.get();
  r.sim = std::make_unique<Simulator>(plant, std::move(context), config);
  return r;
}

// The planar box's modes: "flight" and "resting" on its bottom (one flat contact), starting in `initial_mode`.
ContactModeGraph BoxGraph(const std::string& initial_mode) {
  ContactModeGraph graph;
  graph.modes = {{"flight", {}}, {"resting", {"bottom"}}};
  graph.transitions = {{"flight", "resting", ContactModeGraph::Kind::kTouchdown, "bottom"},
                       {"resting", "flight", ContactModeGraph::Kind::kLiftoff, "bottom"}};
  graph.initial_mode = initial_mode;
  return graph;
}

// Bullet steps a multibody by semi-implicit Euler with explicit velocity-product terms: for a double pendulum (its
// mass matrix depends on q) that is not symplectic, and the energy drifts, at first order in the step. Double pendulum
// (tests/systems/multibody/data), released from 1.0 rad and 0.5 rad, energy from our own kinematics (not Bullet's):
// over 10 s at 1 kHz |E(t) - E(0)| stays below 2.5 % of the potential-energy swing m g Δz ~ 22.6 J (bound ours;
// measured 1.3 %, growing steadily), and 10 substeps (0.1 ms) cut it at least fivefold (first order).
TEST(BulletWorldPlant, FreePendulumEnergyDriftIsBoundedOver10sAt1kHz) {
  auto model = std::make_shared<const MultibodyModel>(MultibodyModel::Load(
      Source("tests/systems/multibody/data/double_pendulum.urdf"), "", {.euler_floating_base = true}));
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
  const ContactModeGraph graph = BoxGraph("flight");
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

// Planned lift-offs (planned_liftoff_force_N): a 3 kg box resting on the plane carries m g = 29.4 N (statics). With the
// threshold at 0.5 m g its planned lift-off never fires over 0.3 s; at 2 m g the plant releases it after its first step
// (F_n = m g <= 2 m g: liftoff_bottom within 2 ms), it rests on and touches again in the next step, and that
// touchdown is announced only min_time_in_mode_s = 50 ms after the release (touchdown_bottom 50-51 ms later). In
// neither case does the mode change move the box (Bullet's physics does not see the mode): it stays at 0.05 m.
// planned_liftoff_min_contact_s = 50 ms: the box resting at the start stands, it is not landing, so its first release
// does not wait (it waited 50 ms when the start counted as its touchdown); having touched again after that release,
// it is released again only 50 ms after (liftoff_bottom at least 50 ms after the first).
TEST(BulletWorldPlant, PlannedLiftoffReleasesAContactBelowItsForceThreshold) {
  auto model = LoadSidecar("tests/systems/plants/data/planar_box.rome.json");
  const ContactModeGraph graph = BoxGraph("resting");
  const double mg = 3.0 * 9.81;
  for (const double threshold : {0.5 * mg, 2.0 * mg}) {
    SCOPED_TRACE(threshold);
    BulletWorldPlantParams params;
    params.min_base_height_m = -1.0;
    params.planned_liftoff_force_N = threshold;
    params.min_time_in_mode_s = 0.05;
    params.planned_liftoff_min_contact_s = 0.05;
    BulletWorldPlant plant("box", model, graph, Terrain::Flat(), params);
    Eigen::VectorXd q(3);
    q << 0.0, 0.05, 0.0;
    PlantRun run = Start(plant, q, Eigen::VectorXd::Zero(3), "resting", Eigen::VectorXd::Zero(0));
    ASSERT_TRUE(run.sim->AdvanceTo(0.3).ok());
    const auto& events = run.sim->statistics().events;
    EXPECT_NEAR(run.context->discrete_state()[1], 0.05, 1e-3);
    if (threshold < mg) {
      EXPECT_TRUE(events.empty()) << events.front().guard << " at " << events.front().time;
      EXPECT_EQ(run.context->mode(), plant.GetModeIndex("resting"));
      EXPECT_NEAR(plant.EvalOutput(*run.context, "contact_forces")[2], mg, 1e-3 * mg);
    } else {
      ASSERT_GE(events.size(), 2u);
      EXPECT_EQ(events[0].guard, "liftoff_bottom");
      EXPECT_LT(events[0].time, 2e-3);
      EXPECT_EQ(events[1].guard, "touchdown_bottom");
      EXPECT_GE(events[1].time - events[0].time, params.min_time_in_mode_s - 1e-9);
      EXPECT_LT(events[1].time - events[0].time, params.min_time_in_mode_s + 1e-3);
      ASSERT_GE(events.size(), 3u);
      EXPECT_EQ(events[2].guard, "liftoff_bottom");
      EXPECT_GE(events[2].time - events[0].time, params.planned_liftoff_min_contact_s - 1e-9);
      EXPECT_LT(events[2].time - events[0].time, params.planned_liftoff_min_contact_s + 4e-3);
    }
  }
}

// Slip by sliding (slip_speed_mps, slip_distance_m): a 3 kg box resting on the plane (μ = 0.6) and sent along x at
// v0 slides under Coulomb friction, x(t) = v0 t − ½ μ g t², and stops after v0² / (2 μ g). At v0 = 0.5 m/s it slides
// 21 mm: the plant reports the slip once it has slid slip_distance_m = 1 cm, at t = (v0 − √(v0² − 2 μ g d)) / (μ g) =
// 23.2 ms (closed form), through SlipDistance, contact_violation (+2) and ContactForceStatistics, although the force
// stays in the friction cone. At v0 = 0.3 m/s it stops after 7.6 mm: no slip, and the distance resets once it holds.
TEST(BulletWorldPlant, ReportsASlideLongerThanTheSlipDistanceAtItsClosedFormTime) {
  auto model = LoadSidecar("tests/systems/plants/data/planar_box.rome.json");
  const ContactModeGraph graph = BoxGraph("resting");
  const double mu = 0.6, g = 9.81;
  for (const double v0 : {0.5, 0.3}) {
    SCOPED_TRACE(v0);
    BulletWorldPlantParams params;
    params.min_base_height_m = -1.0;
    BulletWorldPlant plant("box", model, graph, Terrain::Flat(), params);
    Eigen::VectorXd q(3), v = Eigen::VectorXd::Zero(3);
    q << 0.0, 0.05, 0.0;
    v[0] = v0;
    PlantRun run = Start(plant, q, v, "resting", Eigen::VectorXd::Zero(0));
    ContactForceStatistics stats;
    double first_slip = -1.0, max_ratio = 0.0;
    run.sim->set_monitor([&](const Context&) {
      stats.Record(plant, *run.context);
      if (first_slip < 0 && plant.SlipDistance(*run.context, 0) > 0) {
        first_slip = run.context->time();
        EXPECT_EQ(plant.EvalOutput(*run.context, "contact_violation")[0], 2.0);
      }
      const Eigen::VectorXd f = plant.EvalOutput(*run.context, "contact_forces");
      if (f[2] > 1.0) max_ratio = std::max(max_ratio, std::abs(f[0]) / f[2]);
      return EventStatus::Succeeded();
    });
    ASSERT_TRUE(run.sim->AdvanceTo(0.2).ok());
    const double stop = v0 * v0 / (2 * mu * g);
    std::printf("  v0 = %.1f m/s: stopped at x = %.4f m (Coulomb %.4f m), first slip at %.4f s\n", v0,
                run.context->discrete_state()[0], stop, first_slip);
    EXPECT_NEAR(run.context->discrete_state()[0], stop, 0.05 * stop);  // where Coulomb friction stops it
    EXPECT_LE(max_ratio, mu * (1 + 1e-6));                             // the force never leaves the cone
    if (stop > params.slip_distance_m) {
      const double t_slip = (v0 - std::sqrt(v0 * v0 - 2 * mu * g * params.slip_distance_m)) / (mu * g);
      EXPECT_NEAR(first_slip, t_slip, 2e-3) << "closed form " << t_slip << " s";
      EXPECT_GT(stats.violations, 0);
      EXPECT_NE(stats.first_violation.find("slid"), std::string::npos) << stats.first_violation;
      EXPECT_EQ(plant.SlipDistance(*run.context, 0), 0.0);  // it has stopped: holding again resets the slide
    } else {
      EXPECT_LT(first_slip, 0.0) << "slip reported at " << first_slip << " s";
      EXPECT_EQ(stats.violations, 0) << stats.first_violation;
    }
  }
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
  // The side face is at x = 0.1: the ball's left side (x - 0.05) stays outside it (1 mm between its points, 1 mm
  // slack).
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
    // All solver_iterations (100), no early stop: this checks the gears themselves (|q̇_joint − q̇_rotor| ~ 1e-13
    // rad/s); the default stopping threshold (1e-10 (m/s)²) leaves them at ~6e-6 rad/s (measured).
    params.solver_residual_threshold = 0.0;
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
    const Eigen::VectorXd dq =
        b.context->discrete_state().head(model->nv()) - h.context->continuous_state().head(model->nv());
    worst = std::max(worst, dq.cwiseAbs().maxCoeff());
    const Eigen::Vector3d foot =
        CalcContactPointPosition(*model, ws, b.context->discrete_state().head(model->nv()), 0, 0);
    ASSERT_LT(std::abs(foot.x()), 1e-3) << "Bullet's stance foot slipped at t = " << t;
    ASSERT_LT(std::abs(foot.z()), 1e-3) << "Bullet's stance foot left the ground at t = " << t;
  }
  RecordProperty("stance_error", std::to_string(worst));
  RecordProperty("first_impact_s", std::to_string(t_impact));
  EXPECT_GT(t_impact, 0.1) << "the comparison covered too little time";
  EXPECT_LT(worst, 0.02);
}

ContactModeGraph DoubleSupportOnly() {
  ContactModeGraph graph;
  graph.modes = {{"double_support", {"left_foot", "right_foot"}}};
  graph.initial_mode = "double_support";
  return graph;
}

// A plant in closed loop with a joint PD (feedforward u_ff) around the nominal pose, standing in double support.
struct PdStance {
  std::unique_ptr<Diagram> diagram;
  std::unique_ptr<Simulator> sim;
  const BulletWorldPlant* plant = nullptr;
  const LeafContext* context = nullptr;
};
PdStance StandUnderPd(std::shared_ptr<const MultibodyModel> model, const Eigen::VectorXd& kp, const Eigen::VectorXd& kd,
                      const Eigen::VectorXd& u_ff) {
  PdStance s;
  DiagramBuilder builder;
  s.plant = builder.AddSystem(std::make_unique<BulletWorldPlant>("robot", model, DoubleSupportOnly(), Terrain::Flat()));
  builder.AddSystem(std::make_unique<JointPdController>(
      "pd", model->B(), JointPdGains{kp, kd, model->B().transpose() * model->q_nominal(), u_ff}));
  builder.Connect("robot", "state", "pd", "state");
  builder.Connect("pd", "u", "robot", "u");
  s.diagram = builder.Build("standing");
  s.sim = std::make_unique<Simulator>(*s.diagram);
  LeafContext& plant_context = s.diagram->GetMutableSubsystemContext(*s.plant, s.sim->get_mutable_context());
  s.plant->SetState(plant_context, model->q_nominal(), Eigen::VectorXd::Zero(model->nv()), "double_support");
  s.context = &plant_context;
  return s;
}

// Largest |rod length − L| over the model's loop closures at q, from our own kinematics (not Bullet's) [m].
double RodLengthError(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& q) {
  double worst = 0;
  for (const LoopClosureInfo& l : model.loop_closures())
    worst = std::max(worst, std::abs((CalcPointPosition(model, ws, q, l.body_a, l.point_a) -
                                      CalcPointPosition(model, ws, q, l.body_b, l.point_b))
                                         .norm() -
                                     l.distance_m));
  return worst;
}

// Cassie (3D, 22 DOF, springs live) standing under the joint PD of HybridContactPlant's rod test (kp 1000 N m/rad,
// 1500 on the toes) around its nominal pose, on the Bullet plant: the achilles rods are BulletRodConstraints (one
// row along each rod). The derivative gain is 0.01 kp, not the hybrid test's 0.03 kp: the PD is sampled at the 1 ms
// step here, and kd h / I must stay below 2 for the lightest actuated link (the toe, I ≈ 0.0123 kg m² reflected):
// 45 N m s/rad made the feet chatter and slip (measured), 15 does not. For the first second (Cassie settles 4 cm into
// its springs) the rod lengths, measured with our kinematics, stay within 1e-6 m of 0.5012 m (bound ours; measured
// 2.6e-7 m, during the first 0.1 s of settling, ~1e-8 m after: the row is held at velocity level with ERP position
// correction each step), the toes do not slip (1 mm; measured 0.25 mm) and the friction cones hold. Finding (not
// asserted): after ~1 s Cassie tips forward over its toes on Bullet (heel up 2.5 cm at 1 s, fallen at ~1.7 s), with or
// without gravity compensation and with stiffer gains, although the same PD stands on the hybrid plant; the knees and
// springs sag (knee −0.054 rad, tarsus +0.13 rad at 0.5 s) and the pelvis pitches forward, and Bullet's contact is
// unilateral.
TEST(BulletWorldPlant, CassieStandingUnderPdKeepsAchillesRodLength) {
  auto model = LoadSidecar("robots/cassie/cassie.rome.json");
  ASSERT_EQ(model->num_loop_closures(), 2);
  MultibodyWorkspace ws(*model);
  ASSERT_LT(RodLengthError(*model, ws, model->q_nominal()), 1e-9);
  const int nu = model->nu(), nv = model->nv();
  ASSERT_EQ(model->actuators()[4].joint, "left_toe");
  Eigen::VectorXd kp(nu);
  kp << 1000, 1000, 1000, 1000, 1500, 1000, 1000, 1000, 1000, 1500;
  PdStance s = StandUnderPd(model, kp, 0.01 * kp, Eigen::VectorXd::Zero(nu));
  double worst = 0, worst_slip = 0, worst_lift = 0;
  int violations = 0;
  std::vector<Eigen::Vector3d> start;
  for (int c = 0; c < 2; ++c)
    for (int k = 0; k < 2; ++k) start.push_back(CalcContactPointPosition(*model, ws, model->q_nominal(), c, k));
  s.sim->set_monitor([&](const Context&) {
    const Eigen::VectorXd q = s.context->discrete_state().head(nv);
    worst = std::max(worst, RodLengthError(*model, ws, q));
    for (int c = 0; c < 2; ++c)
      for (int k = 0; k < 2; ++k) {
        const Eigen::Vector3d p = CalcContactPointPosition(*model, ws, q, c, k);
        if (k == 0)
          worst_slip =
              std::max(worst_slip, (p - start[2 * c + k]).head<2>().norm());  // toe (the heel moves as it lifts)
        worst_lift = std::max(worst_lift, p.z());
      }
    violations += static_cast<int>(s.plant->EvalOutput(*s.context, "contact_violation").sum() > 0);
    return EventStatus::Succeeded();
  });
  const SimulatorStatus status = s.sim->AdvanceTo(1.0);
  ASSERT_TRUE(status.ok()) << status.ToString();
  RecordProperty("rod_length_error_m", std::to_string(worst));
  std::printf(
      "Cassie on Bullet, 1 s standing: largest rod length error %.3g m, foot slip %.3g m, lift %.3g m, pelvis height "
      "%.4f m (nominal %.4f m)\n",
      worst, worst_slip, worst_lift, s.context->discrete_state()[2], model->q_nominal()[2]);
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(worst_slip, 1e-3);
  EXPECT_EQ(violations, 0);
  EXPECT_NEAR(s.context->discrete_state()[2], model->q_nominal()[2], 0.05);
}

// The exoskeleton (flat feet, 4 sole corners each) stands 5 s in double support on the Bullet plant under a joint PD
// around its nominal pose plus static gravity compensation. After 0.2 s of settling, every step: the feet's normal
// forces sum to m g (Newton: the robot is at rest; within 1e-6 m g, measured 1e-10), each foot's centre of pressure
// (from Bullet's manifold points) is inside its sole (CheckContactForce), no contact leaves the friction cone; over the
// 5 s the pelvis moves less than 0.01 and turns less than 0.01 (bounds ours).
TEST(BulletWorldPlant, ExoskeletonStandsFiveSecondsInDoubleSupport) {
  auto model = LoadSidecar("robots/exoskeleton/exoskeleton.rome.json");
  const int nu = model->nu(), nv = model->nv();
  const ContactSet both = ContactBit(0) | ContactBit(1);
  PdStance s = StandUnderPd(model, Eigen::VectorXd::Constant(nu, 500.0), Eigen::VectorXd::Constant(nu, 50.0),
                            CalcStanceGravityCompensation(*model, both, model->q_nominal()));
  MultibodyWorkspace ws(*model);
  const double mg = model->total_mass() * 9.81;
  double worst_force = 0, worst_cop_margin = 1e9, worst_drift = 0, worst_turn = 0;
  int cop_outside = 0, violations = 0, samples = 0;
  double last_checked = -1;
  s.sim->set_monitor([&](const Context& c) {
    const double t = c.time();
    const Eigen::VectorXd q = s.context->discrete_state().head(nv);
    worst_drift = std::max(worst_drift, (q.head<3>() - model->q_nominal().head<3>()).norm());
    worst_turn = std::max(worst_turn, (q.segment<3>(3) - model->q_nominal().segment<3>(3)).cwiseAbs().maxCoeff());
    if (t < 0.2 || t - last_checked < 0.9e-3) return EventStatus::Succeeded();
    last_checked = t;
    ++samples;
    const Eigen::VectorXd f = s.plant->EvalOutput(*s.context, "contact_forces");
    worst_force = std::max(worst_force, std::abs(f[2] + f[5] - mg) / mg);
    violations += static_cast<int>(s.plant->EvalOutput(*s.context, "contact_violation").sum() > 0);
    for (int foot = 0; foot < 2; ++foot) {
      const ContactForceCheck check =
          CheckContactForce(*model, ws, q, foot, s.plant->LastStepContactWrench(*s.context, foot));
      cop_outside += static_cast<int>(!check.cop_ok);
      // Distance of the CoP to the nearest sole edge (the soles stay level and aligned with x; corners from our
      // kinematics).
      Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector2d p = CalcContactPointPosition(*model, ws, q, foot, k).head<2>();
        lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
      }
      worst_cop_margin = std::min(worst_cop_margin, std::min((check.cop - lo).minCoeff(), (hi - check.cop).minCoeff()));
    }
    return EventStatus::Succeeded();
  });
  const SimulatorStatus status = s.sim->AdvanceTo(5.0);
  ASSERT_TRUE(status.ok()) << status.ToString();
  std::printf(
      "exoskeleton on Bullet, 5 s: %d steps checked; |sum F_z - m g| / m g <= %.3g; CoP at least %.4f m inside the "
      "soles; "
      "pelvis drift %.3g m, %.3g rad; friction-cone violations %d\n",
      samples, worst_force, worst_cop_margin, worst_drift, worst_turn, violations);
  RecordProperty("force_error", std::to_string(worst_force));
  RecordProperty("drift_m", std::to_string(worst_drift));
  EXPECT_GT(samples, 4500);
  EXPECT_LT(worst_force, 1e-6);
  EXPECT_EQ(cop_outside, 0);
  EXPECT_GT(worst_cop_margin, 0.0);
  EXPECT_EQ(violations, 0);
  EXPECT_LT(worst_drift, 1e-3);
  EXPECT_LT(worst_turn, 1e-3);
}

// The solver's stopping threshold (solver_residual_threshold, ConvergingMultiBodySolver): one step of AMBER standing
// on both feet (the plants benchmark's state). Stopped at the default 1e-10 (m/s)², the solver uses fewer than its 100
// iterations (measured 63), and the step's ground forces agree with a solve run to 1000 iterations (the converged
// answer) within 0.5 % of the robot's weight (measured 0.45 N of 211.5 N; 0.14 N at 100 iterations); with the threshold
// at 0 it runs all 100. A negative threshold is refused.
TEST(BulletWorldPlant, SolverStopsAtItsConvergenceThreshold) {
  auto model = LoadSidecar("robots/amber/amber.rome.json");
  auto step = [&](int iterations, double threshold, int* used) {
    BulletWorldPlantParams params;
    params.solver_iterations = iterations;
    params.solver_residual_threshold = threshold;
    BulletWorldPlant plant("amber", model, ContactModeGraph::Hopping("left_foot", "right_foot"), Terrain::Flat(),
                           params);
    auto context = plant.CreateDefaultLeafContext();
    plant.SetState(*context, model->q_nominal(), Eigen::VectorXd::Zero(model->nv()), "stance");
    context->FixInputPort(0, Eigen::VectorXd::Constant(model->nu(), 5.0));
    const auto& update = plant.periodic_events().at(0).update;
    Eigen::VectorXd next = context->discrete_state();
    for (int i = 0; i < 11; ++i) {
      next = context->discrete_state();
      EXPECT_TRUE(update(*context, &next).ok());
    }
    *used = plant.SolverIterationsUsed(*context);
    return Eigen::VectorXd(next.segment(plant.forces_offset(), 6));
  };
  int used_default = 0, used_full = 0, used_reference = 0;
  const Eigen::VectorXd f_default = step(100, BulletWorldPlantParams{}.solver_residual_threshold, &used_default);
  const Eigen::VectorXd f_full = step(100, 0.0, &used_full);
  const Eigen::VectorXd f_reference = step(1000, 0.0, &used_reference);
  const double weight = model->total_mass() * 9.81;
  std::printf(
      "iterations used: %d (default threshold), %d (none); force error against 1000 iterations: %.3g N, %.3g N (weight "
      "%.1f N)\n",
      used_default, used_full, (f_default - f_reference).cwiseAbs().maxCoeff(),
      (f_full - f_reference).cwiseAbs().maxCoeff(), weight);
  EXPECT_LT(used_default, 100);
  EXPECT_EQ(used_full, 100);
  EXPECT_LT((f_default - f_reference).cwiseAbs().maxCoeff(), 0.005 * weight);
  BulletWorldPlantParams negative;
  negative.solver_residual_threshold = -1.0;
  EXPECT_THROW(
      BulletWorldPlant("amber", model, ContactModeGraph::Hopping("left_foot", "right_foot"), Terrain::Flat(), negative),
      std::exception);
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
  expect_error([&] { BulletWorldPlant("ball", model, NoContacts(), Terrain::Flat(), zero_step); },
               "step_s must be positive, got 0");
  BulletWorldPlantParams negative_step;
  negative_step.step_s = -1e-3;
  expect_error([&] { BulletWorldPlant("ball", model, NoContacts(), Terrain::Flat(), negative_step); },
               "step_s must be positive, got -0.001");
  BulletWorldPlantParams no_substeps;
  no_substeps.substeps = 0;
  expect_error([&] { BulletWorldPlant("ball", model, NoContacts(), Terrain::Flat(), no_substeps); },
               "substeps must be at least 1");
  BulletWorldPlantParams negative_min_time;
  negative_min_time.min_time_in_mode_s = -0.01;
  expect_error([&] { BulletWorldPlant("ball", model, NoContacts(), Terrain::Flat(), negative_min_time); },
               "min_time_in_mode_s must be >= 0, got -0.01");
  BulletWorldPlantParams no_slip_distance;
  no_slip_distance.slip_distance_m = 0.0;
  expect_error([&] { BulletWorldPlant("ball", model, NoContacts(), Terrain::Flat(), no_slip_distance); },
               "slip_distance_m must be positive (infinity: off), got 0");
  BulletWorldPlantParams nan_slip_speed;
  nan_slip_speed.slip_speed_mps = std::nan("");
  expect_error([&] { BulletWorldPlant("ball", model, NoContacts(), Terrain::Flat(), nan_slip_speed); },
               "slip_speed_mps must be finite and >= 0");
  // A stone of zero size: the terrain rejects it, naming the stone.
  expect_error([&] { Terrain::Stones({{0.0, 0.0, 0.2}, {1.0, 0.0, 0.0}}); }, "stone");
  // A sidecar contact with no points has no collision geometry: the sidecar loader rejects it, naming the contact.
  expect_error([&] { LoadSidecar("tests/systems/plants/data/no_points.rome.json"); }, "needs 1 points, got []");
}

}  // namespace
}  // namespace rome
