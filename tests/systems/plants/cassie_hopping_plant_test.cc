// HybridContactPlant on 3D Cassie (22 DOF, shin/heel springs live, achilles rods as loop closures) with the hopping
// paper's Jump -> Flight -> Landing graph (ContactModeGraph::JumpFlightLanding). Physics checks, each against a law
// that does not come from the plant's code:
//   * flight: the centroidal angular momentum is constant (motor torques, springs and rod tensions are internal) and
//     the linear momentum changes by m g t only (Newton's second law with gravity the only external force);
//   * Jump -> Flight: a foot's normal force reaching 0 ends Jump with no impact (q and v continuous across the event);
//   * Flight -> Landing: the plastic impact leaves q unchanged, stops every sole point of both feet and does not add
//     kinetic energy;
//   * every rod keeps its length (0.5012 m) to 1e-6 m through a whole jump, flight, impact and landing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/plants/hybrid_contact_plant.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

constexpr double kGravity = 9.81;

std::shared_ptr<const MultibodyModel> LoadCassie() {
  return std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("robots/cassie/cassie.rome.json"), {.euler_floating_base = true}));
}

SimulatorConfig Tight() {
  SimulatorConfig c;
  c.relative_tolerance = 1e-10;
  c.absolute_tolerance = 1e-11;
  return c;
}

// Largest |rod length - 0.5012 m| over both achilles rods.
double RodLengthError(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& q) {
  double worst = 0.0;
  for (const LoopClosureInfo& loop : model.loop_closures()) {
    const Eigen::Vector3d pa = CalcPointPosition(model, ws, q, loop.body_a, loop.point_a);
    const Eigen::Vector3d pb = CalcPointPosition(model, ws, q, loop.body_b, loop.point_b);
    worst = std::max(worst, std::abs((pa - pb).norm() - loop.distance_m));
  }
  return worst;
}

// Random joint velocities (seeded), projected so that the active constraints (rods; feet if given) hold: J v = 0.
Eigen::VectorXd ConsistentVelocity(const MultibodyModel& model, const Eigen::VectorXd& q, ContactSet active,
                                   unsigned seed, double joint_speed, const Eigen::VectorXd& base_velocity) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv());
  for (int i = model.num_base_dofs(); i < model.nv(); ++i) v[i] = joint_speed * uniform(rng);
  v.head(model.num_base_dofs()) = base_velocity;
  MultibodyWorkspace ws(model);
  const int rows = CalcConstraintJacobian(model, ws, q, v, active);
  const Eigen::MatrixXd J = ws.J.topRows(rows);
  v -= J.completeOrthogonalDecomposition().solve(J * v);
  return v;
}

TEST(CassieHoppingPlant, GraphHasThePapersThreeDomains) {
  auto model = LoadCassie();
  HybridContactPlant plant("cassie", model, ContactModeGraph::JumpFlightLanding("left_foot", "right_foot"),
                           Terrain::Flat());
  EXPECT_EQ(plant.GetModeIndex("jump"), 0);
  EXPECT_EQ(plant.GetModeIndex("flight"), 1);
  EXPECT_EQ(plant.GetModeIndex("landing"), 2);
  const ContactSet both = ContactBit(model->ContactIndex("left_foot")) | ContactBit(model->ContactIndex("right_foot"));
  EXPECT_EQ(plant.active_contacts(0), both);
  EXPECT_EQ(plant.active_contacts(1), 0u);
  EXPECT_EQ(plant.active_contacts(2), both);
  EXPECT_EQ(model->nv(), 22);
  EXPECT_EQ(model->num_loop_closures(), 2);
}

// Flight with the springs deflecting, joints moving and constant motor torques: H_G (angular, about the COM) is
// conserved and the linear momentum follows p(t) = p(0) - m g t e_z.
TEST(CassieHoppingPlant, FlightConservesCentroidalAngularMomentumAndFallsByMgt) {
  auto model = LoadCassie();
  HybridContactPlant plant("cassie", model, ContactModeGraph::JumpFlightLanding("left_foot", "right_foot"),
                           Terrain::Flat());
  auto context = plant.CreateDefaultLeafContext();
  Eigen::VectorXd q = model->q_nominal();
  q[model->VelocityIndex("base_z")] += 1.5;  // high enough that the 0.3 s flight never touches down
  Eigen::Vector<double, 6> base_velocity;
  base_velocity << 0.3, -0.1, 1.0, 0.2, -0.4, 0.3;
  const Eigen::VectorXd v = ConsistentVelocity(*model, q, 0, 3, 1.0, base_velocity);
  plant.SetState(*context, q, v, "flight");
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd u(model->nu());
  for (int i = 0; i < model->nu(); ++i) u[i] = 5.0 * uniform(rng);
  context->FixInputPort(0, u);
  const LeafContext* ctx = context.get();
  MultibodyWorkspace ws(*model);
  const int nv = model->nv();
  const double m = model->total_mass();
  const Vector6d h0 = CalcCentroidalMomentum(*model, ws, q, v);
  Simulator sim(plant, std::move(context), Tight());
  double worst_angular = 0.0, worst_linear = 0.0, worst_rod = 0.0, max_spring = 0.0;
  long steps = 0;
  const int shin = model->VelocityIndex("left_shin_spring");
  sim.set_monitor([&](const Context&) {
    const Eigen::VectorXd x = ctx->continuous_state();
    const Vector6d h = CalcCentroidalMomentum(*model, ws, x.head(nv), x.tail(nv));
    worst_angular = std::max(worst_angular, (h.head<3>() - h0.head<3>()).norm());
    Eigen::Vector3d expected = h0.tail<3>();
    expected.z() -= m * kGravity * ctx->time();
    worst_linear = std::max(worst_linear, (h.tail<3>() - expected).norm());
    worst_rod = std::max(worst_rod, RodLengthError(*model, ws, x.head(nv)));
    max_spring = std::max(max_spring, std::abs(x[shin]));
    ++steps;
    return EventStatus::Succeeded();
  });
  const SimulatorStatus status = sim.AdvanceTo(0.3);
  ASSERT_TRUE(status.ok()) << status.ToString();
  EXPECT_EQ(ctx->mode(), 1);
  std::printf(
      "  flight 0.3 s, %ld steps: |dH_angular| %.2e N m s, linear momentum vs m g t %.2e N s, rod %.2e m, shin spring "
      "up to %.3f rad\n",
      steps, worst_angular, worst_linear, worst_rod, max_spring);
  EXPECT_GT(steps, 50);
  EXPECT_GT(max_spring, 5e-4);  // the springs did move: the check is not on a frozen leg
  EXPECT_GT(h0.head<3>().norm(), 0.1);
  EXPECT_LT(worst_angular, 1e-6);
  EXPECT_LT(worst_linear, 1e-6);
  EXPECT_LT(worst_rod, 1e-6);
}

// Falling onto the ground with moving legs: the touchdown of the first sole point (of either foot) is an impact on
// both feet at once. Compared a hair before and after the event (a second run stops 1 ns before it).
TEST(CassieHoppingPlant, TouchdownImpactStopsBothFeetKeepsQAndAddsNoEnergy) {
  auto model = LoadCassie();
  const ContactModeGraph graph = ContactModeGraph::JumpFlightLanding("left_foot", "right_foot");
  HybridContactPlant plant("cassie", model, graph, Terrain::Flat());
  const int nv = model->nv();
  Eigen::VectorXd q0 = model->q_nominal();
  q0[model->VelocityIndex("base_z")] += 0.10;  // touchdown after ~0.1 s, beyond the guards' 50 ms arming delay
  Eigen::Vector<double, 6> base_velocity;
  base_velocity << 0.2, 0.05, -0.5, 0.1, 0.1, -0.05;
  const Eigen::VectorXd v0 = ConsistentVelocity(*model, q0, 0, 5, 0.5, base_velocity);
  auto run = [&](double t_final, Eigen::VectorXd* x, std::vector<EventRecord>* events) {
    auto context = plant.CreateDefaultLeafContext();
    plant.SetState(*context, q0, v0, "flight");
    context->FixInputPort(0, Eigen::VectorXd::Zero(model->nu()));
    const LeafContext* ctx = context.get();
    Simulator sim(plant, std::move(context), Tight());
    const SimulatorStatus status = sim.AdvanceTo(t_final);
    *x = ctx->continuous_state();
    *events = sim.statistics().events;
    return status;
  };
  Eigen::VectorXd x_probe, x_minus, x_plus;
  std::vector<EventRecord> events;
  // (After the touchdown the limp robot sags until it slips or falls: only the first event matters here.)
  const SimulatorStatus probe = run(0.3, &x_probe, &events);
  ASSERT_GE(events.size(), 1u) << probe.ToString();
  const double t_event = events[0].time;
  EXPECT_EQ(events[0].mode_before, 1);
  EXPECT_EQ(events[0].mode_after, 2);
  EXPECT_EQ(events[0].guard.rfind("touchdown_", 0), 0u) << events[0].guard;
  // The event is where the lowest sole point reaches the ground.
  ASSERT_TRUE(run(t_event - 1e-9, &x_minus, &events).ok());
  EXPECT_TRUE(events.empty());
  ASSERT_TRUE(run(t_event + 1e-9, &x_plus, &events).ok());
  ASSERT_EQ(events.size(), 1u);
  MultibodyWorkspace ws(*model);
  double lowest = 1e9;
  for (int c = 0; c < model->num_contacts(); ++c)
    lowest = std::min(lowest, CalcContactHeight(*model, ws, x_minus.head(nv), c));
  EXPECT_NEAR(lowest, 0.0, 1e-7);
  // q continuous (2 ns of motion at a few m/s is < 1e-8).
  EXPECT_LT((x_plus.head(nv) - x_minus.head(nv)).norm(), 1e-7);
  // Every sole point of both feet at rest; the velocities jumped.
  double worst_sole_speed = 0.0, sole_speed_before = 0.0;
  for (int c = 0; c < model->num_contacts(); ++c)
    for (int p = 0; p < 2; ++p) {
      worst_sole_speed = std::max(worst_sole_speed,
                                  CalcContactPointVelocity(*model, ws, x_plus.head(nv), x_plus.tail(nv), c, p).norm());
      sole_speed_before = std::max(
          sole_speed_before, CalcContactPointVelocity(*model, ws, x_minus.head(nv), x_minus.tail(nv), c, p).norm());
    }
  const double ke_minus = CalcKineticEnergy(*model, ws, x_minus.head(nv), x_minus.tail(nv));
  const double ke_plus = CalcKineticEnergy(*model, ws, x_plus.head(nv), x_plus.tail(nv));
  std::printf("  impact at t = %.6f s: sole speed %.3f -> %.2e m/s, kinetic energy %.3f -> %.3f J\n", t_event,
              sole_speed_before, worst_sole_speed, ke_minus, ke_plus);
  EXPECT_GT(sole_speed_before, 0.3);
  EXPECT_LT(worst_sole_speed, 1e-6);
  EXPECT_LE(ke_plus, ke_minus);
  EXPECT_LT(RodLengthError(*model, ws, x_plus.head(nv)), 1e-6);
}

// Jump -> Flight without a controller: standing in Jump, the hips (+100 N m), knees (+195 N m, flexion) and toes
// (-5 N m) get a torque step that folds the legs and pulls the feet up, so their normal forces are negative at once
// and the plant lifts off into Flight right after the step (HybridContactPlant's post-event check) with the identity
// reset: the velocities across the event change only by the flow over the nanosecond step to it. (A full hop with
// the rods checked through every domain is in tests/diagrams/hopping: a limp robot cannot land cleanly.)
TEST(CassieHoppingPlant, LiftoffIsNotAnImpactAndRodsHold) {
  auto model = LoadCassie();
  const int nv = model->nv(), nu = model->nu();
  HybridContactPlantParams params;
  params.min_base_height_m = 0.5;
  DiagramBuilder b;
  auto* plant = b.AddSystem(std::make_unique<HybridContactPlant>(
      "cassie", model, ContactModeGraph::JumpFlightLanding("left_foot", "right_foot"), Terrain::Flat(), params));
  Eigen::VectorXd fold = Eigen::VectorXd::Zero(nu);
  for (int i = 0; i < nu; ++i) {
    const std::string& joint = model->actuators()[i].joint;
    if (joint == "left_hip_pitch" || joint == "right_hip_pitch") fold[i] = 100.0;
    if (joint == "left_knee" || joint == "right_knee") fold[i] = 195.0;
    if (joint == "left_toe" || joint == "right_toe") fold[i] = -5.0;
  }
  b.AddSystem(std::make_unique<TrajectorySource>("torque", nu, [fold](double t, Eigen::Ref<Eigen::VectorXd> out) {
    out = t < 0.1 ? fold : Eigen::VectorXd::Zero(fold.size());
  }));
  b.Connect("torque", "y", "cassie", "u");
  auto diagram = b.Build("hop");
  Simulator sim(*diagram, Tight());
  LeafContext& pc = diagram->GetMutableSubsystemContext(*plant, sim.get_mutable_context());
  plant->SetState(pc, model->q_nominal(), Eigen::VectorXd::Zero(nv), "jump");
  MultibodyWorkspace ws(*model);
  double worst_rod = 0.0;
  Eigen::VectorXd last_v = Eigen::VectorXd::Zero(nv);
  int last_mode = 0;
  double liftoff_velocity_jump = -1.0;
  std::vector<int> modes_seen = {0};
  sim.set_monitor([&](const Context& c) {
    const LeafContext& ctx = diagram->GetSubsystemContext(*plant, c);
    const Eigen::VectorXd x = ctx.continuous_state();
    worst_rod = std::max(worst_rod, RodLengthError(*model, ws, x.head(nv)));
    if (ctx.mode() != last_mode) {
      modes_seen.push_back(ctx.mode());
      if (last_mode == 0) liftoff_velocity_jump = (x.tail(nv) - last_v).norm();
    }
    last_mode = ctx.mode();
    last_v = x.tail(nv);
    return EventStatus::Succeeded();
  });
  const SimulatorStatus status = sim.AdvanceTo(0.045);  // before the touchdown guards arm (50 ms)
  const auto& events = sim.statistics().events;
  for (const EventRecord& e : events)
    std::printf("  event %s at %.4f s: %d -> %d\n", e.guard.c_str(), e.time, e.mode_before, e.mode_after);
  std::printf("  run: %s; worst rod length error %.2e m\n", status.ToString().c_str(), worst_rod);
  ASSERT_TRUE(status.ok()) << status.ToString();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].guard.rfind("liftoff_", 0), 0u) << events[0].guard;
  EXPECT_EQ(events[0].mode_before, 0);
  EXPECT_EQ(events[0].mode_after, 1);
  // No impact at lift-off: the velocity across it changes only by the flow over the (nanosecond) step to it.
  EXPECT_GE(liftoff_velocity_jump, 0.0);
  EXPECT_LT(liftoff_velocity_jump, 1e-3);
  EXPECT_LT(events[0].time, 1e-6);
  EXPECT_LT(worst_rod, 1e-6);
}

}  // namespace
}  // namespace rome
