// The hopping diagram end to end on a hand-made leg-length plan (independent of the spring-mass ROM's NLPs): after
// settling 1.5 s under the Landing outputs, Cassie crouches 6 cm and extends 14 cm along quintics, lifts off without
// an impact, flies with its motors held and touches down on both feet. Checks:
//   * the domains follow Jump → Flight → Landing, driven by the plant's guards, and nothing fails before touchdown;
//   * the plant's contact forces are physical at every integrator step in Jump (contact_violation = 0), no QP fails
//     (in Landing too, until the run ends);
//   * the air time agrees with the ballistic flight of the COM from its lift-off velocity (t = 2 v_z / g, 5 %);
//   * the rods hold to 1e-6 m throughout;
//   * the Jump pitch reference from the centroidal pitch momentum (HoppingReferenceParams::jump_momentum_gain) lowers
//     |H_pitch| at lift-off against holding the pelvis level, and in flight the pelvis pitch rate follows from the
//     conserved momentum, θ̇ ≈ H_pitch / I_yy with I_yy the whole-body inertia about the COM (motors held);
//   * why Jump tracks the pelvis pitch and not H_pitch (Eq. (41)): the closed loop (plant's constrained dynamics with
//     the CLF-QP's torque), linearised by central differences at the first Jump sample, has its largest eigenvalue
//     below 1 1/s with the pitch output and above 100 1/s with H_pitch (measured +0.11 and +444 1/s with the
//     diagram's ρ_u = 1e-4 and relaxation weight 1e4; +0.05 and +414 1/s with 1e5; +2305 1/s with the block default
//     ρ_u = 1e-6 on the ROM plan).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "diagrams/hopping/hopping_diagram.h"
#include "diagrams/hopping/hopping_plans.h"
#include "diagrams/hopping/hopping_run.h"
#include "framework/primitives.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/robot_files.h"
#include "systems/plants/contact_force_statistics.h"
#include "tests/diagrams/hopping/spec_leg_length.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

std::shared_ptr<const MultibodyModel> LoadCassie() {
  return std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("robots/cassie/cassie.rome.json"), {.euler_floating_base = true}));
}

// Quintic rest-to-rest from a to b over [t0, t0 + T], sampled into plan nodes.
void AppendQuintic(double t0, double T, double a, double b, int n, LegLengthPlan* plan) {
  const int start = static_cast<int>(plan->t.size());
  plan->t.conservativeResize(start + n);
  plan->L.conservativeResize(start + n);
  plan->Ldot.conservativeResize(start + n);
  for (int k = 0; k < n; ++k) {
    const double s = (k + (start > 0 ? 1.0 : 0.0)) / (n - (start > 0 ? 0.0 : 1.0));
    plan->t[start + k] = t0 + s * T;
    plan->L[start + k] = a + (b - a) * (10 * std::pow(s, 3) - 15 * std::pow(s, 4) + 6 * std::pow(s, 5));
    plan->Ldot[start + k] = (b - a) * (30 * s * s - 60 * std::pow(s, 3) + 30 * std::pow(s, 4)) / T;
  }
}

struct HopRun {
  SimulatorStatus status;
  double liftoff_time = -1, touchdown_time = -1, max_pitch_change = 0, H_liftoff = 0, I_yy = 0, flight_rate = 0,
         H_flight_drift = 0, worst_rod = 0, qp_failures = 0, qp_failures_before_touchdown = -1;
  Eigen::Vector3d vcom_liftoff = Eigen::Vector3d::Zero();
  long violations = 0, contact_samples = 0;
};

// Settle 1.5 s, crouch 6 cm and extend 14 cm (hand-made quintics), fly, touch down; `gain` is the Jump pitch
// reference's momentum gain (0: the pelvis is held level). The hops, lift-off and touchdown come from RunHopping; this
// test adds, through its observer, the rods' length error and H_pitch and the pelvis pitch rate in the first flight.
HopRun RunHandMadeHop(double gain, double duration) {
  auto model = LoadCassie();
  const double crouch_depth = 0.06, extension = 0.14, crouch_T = 0.4, push_T = 0.22;
  auto jump_planner = [&](const RomState& start, LegLengthPlan* plan, std::string*) {
    *plan = {};
    AppendQuintic(0.0, crouch_T, start.L, start.L - crouch_depth, 21, plan);
    AppendQuintic(crouch_T, push_T, start.L - crouch_depth, start.L - crouch_depth + extension, 20, plan);
    return true;
  };
  HoppingDiagramParams params;
  params.reference.jump_momentum_gain = gain;
  // The hand-made plan carries no ROM force, so the GRF feedback of the Jump is off (the reference rejects the plan
  // otherwise).
  params.reference.jump_force_feedback = 0.0;
  params.reference.jump_force_integral_per_s = 0.0;
  if (std::getenv("HOP_MOMENTUM"))
    params.outputs.jump_tracks_momentum = true;  // the paper's Eq. (41) (see hopping_diagram.h)
  // No landing planner: the reference's documented fallback (a quintic back to the standing leg length).
  HoppingDiagram d = BuildHoppingDiagram(model, test::SpecLegLength, jump_planner, nullptr, params);
  Simulator sim(*d.diagram, HoppingSimulatorConfig());
  SetHoppingInitialState(d, sim.get_mutable_context(), model->q_nominal());
  const int nv = model->nv();
  MultibodyWorkspace ws(*model);
  HopRun r;
  double flight_rate_sum = 0;
  int flight_samples = 0;
  Eigen::MatrixXd A_G(6, nv);
  HoppingRunParams run;
  run.duration_s = duration;
  run.apex_rise_m = extension;  // the hop rule's H (not asserted here)
  run.observer = [&](const Context& c, const HoppingRunState& s) {
    const LeafContext& pc = d.diagram->GetSubsystemContext(*d.plant, c);
    const Eigen::VectorXd x = pc.continuous_state();
    for (const LoopClosureInfo& loop : model->loop_closures())
      r.worst_rod =
          std::max(r.worst_rod, std::abs((CalcPointPosition(*model, ws, x.head(nv), loop.body_a, loop.point_a) -
                                          CalcPointPosition(*model, ws, x.head(nv), loop.body_b, loop.point_b))
                                             .norm() -
                                         loop.distance_m));
    // The first flight only: with the fallback landing (no landing planner) the robot may bounce off again after its
    // touchdown (it does with the diagram's relaxation weight 1e4; the landing is not this test's subject).
    if (s.touchdown_s >= 0 || s.domain != HoppingDomain::kFlight) return;
    CalcCentroidalMomentumMatrix(*model, ws, x.head(nv), A_G);
    if (s.previous_domain != HoppingDomain::kFlight) r.H_liftoff = A_G.row(1).dot(x.tail(nv));
    r.H_flight_drift = std::max(r.H_flight_drift, std::abs(A_G.row(1).dot(x.tail(nv)) - r.H_liftoff));
    // Only while the motors are held (every motor within 0.02 rad and 0.2 rad/s of its held target): the body then
    // turns as one rigid body.
    const Eigen::VectorXd& y_d = d.reference->EvalOutput(d.diagram->GetSubsystemContext(*d.reference, c), "desired");
    double motor_error = 0.0, motor_rate = 0.0;
    for (int i = 0; i < model->nu(); ++i) {
      const int k = model->actuators()[i].v_index;
      motor_error = std::max(motor_error, std::abs(x[k] - y_d[d.layout.motors + i]));
      motor_rate = std::max(motor_rate, std::abs(x[nv + k]));
    }
    if (motor_error < 0.02 && motor_rate < 0.2)
      flight_rate_sum += x[nv + model->VelocityIndex("base_pitch")], ++flight_samples;
  };
  const HoppingRunResult result = RunHopping(d, sim, run);
  for (const EventRecord& e : result.integrator.events)
    std::printf("  event %s/%s at %.4f s: %d -> %d\n", e.system.c_str(), e.guard.c_str(), e.time, e.mode_before,
                e.mode_after);
  r.status = result.status;
  r.liftoff_time = result.liftoff_s;
  r.touchdown_time = result.touchdown_s;
  r.max_pitch_change = result.max_pelvis_pitch_change_flight_rad;
  if (result.liftoff_state.size() > 0) {
    const Eigen::VectorXd& x = result.liftoff_state;
    CalcCentroidalMomentumMatrix(*model, ws, x.head(nv), A_G);
    r.I_yy = A_G(1, model->VelocityIndex("base_pitch"));  // the whole body turning rigidly about world y
    r.vcom_liftoff = CalcComVelocity(*model, ws, x.head(nv), x.tail(nv));
  }
  r.violations = result.contact_violations_before_first_touchdown;
  r.contact_samples = result.contact.samples;
  r.qp_failures = result.qp_failures;
  r.qp_failures_before_touchdown = result.qp_failures_at_first_touchdown;
  r.flight_rate = flight_samples > 0 ? flight_rate_sum / flight_samples : NAN;
  return r;
}

TEST(HoppingDiagram, HandMadeExtensionLiftsOffFliesAndTouchesDown) {
  const HopRun r = RunHandMadeHop(HoppingReferenceParams{}.jump_momentum_gain, 3.5);
  // Ballistic air time of the COM from its lift-off state back to its lift-off height... the feet land when the COM
  // is back near that height (the legs are held): t = 2 vz / g.
  const double ballistic = 2.0 * r.vcom_liftoff.z() / 9.81;
  std::printf(
      "  %s; lift-off %.4f s (COM vz %.3f m/s), touchdown %.4f s, air %.4f s vs ballistic %.4f s; pitch change %.2f "
      "deg; rod %.2e m;\n"
      "  violations %ld / %ld; qp_failures %.0f; H_pitch at lift-off %.3f N m s, I_yy %.3f kg m^2, flight pitch rate "
      "%.3f rad/s "
      "vs H/I %.3f; qp failures before touchdown %.0f; H_pitch drift in flight %.2e N m s\n",
      r.status.ToString().c_str(), r.liftoff_time, r.vcom_liftoff.z(), r.touchdown_time,
      r.touchdown_time - r.liftoff_time, ballistic, r.max_pitch_change * 180 / M_PI, r.worst_rod, r.violations,
      r.contact_samples, r.qp_failures, r.H_liftoff, r.I_yy, r.flight_rate, r.H_liftoff / r.I_yy,
      r.qp_failures_before_touchdown, r.H_flight_drift);
  ASSERT_GT(r.liftoff_time, 0.0) << r.status.ToString();
  ASSERT_GT(r.touchdown_time, r.liftoff_time) << r.status.ToString();
  EXPECT_GE(r.status.time, r.touchdown_time);  // nothing failed before the touchdown
  EXPECT_GT(r.vcom_liftoff.z(), 0.3);
  EXPECT_NEAR(r.touchdown_time - r.liftoff_time, ballistic, 0.05 * ballistic + 0.01);
  EXPECT_EQ(r.violations, 0);  // the plant's forces through the Jump, including the take-off (ContactForceStatistics)
  EXPECT_EQ(r.qp_failures_before_touchdown, 0.0);
  // After the touchdown (the landing, not met yet: see below) the QP failures are reported, not asserted: measured 0 in
  // the Release build (ρ_u = 1e-4 keeps the Hessian well conditioned after the impact) and 10 in the -O1 sanitizer
  // build.
  EXPECT_LT(r.worst_rod, 1e-6);
  // Conserved H_pitch: while the motors are held (the samples above) the body turns nearly rigidly, θ̇ ≈ H / I_yy (I_yy
  // at lift-off; the springs' small motion and the change of I_yy in flight account for the 25 %).
  // The controller's torques are internal: H_pitch about the COM stays that of the lift-off through the flight.
  EXPECT_LT(r.H_flight_drift, 1e-3 * std::max(1.0, std::abs(r.H_liftoff)));
  // The motors do not always settle within the flight (the CLF-QP's cost_pd_feedback tracks them at 10 rad/s from their
  // lift-off speeds); when they do, the rigid-body rate is checked.
  if (std::isfinite(r.flight_rate)) {
    EXPECT_NEAR(r.flight_rate, r.H_liftoff / r.I_yy, 0.25 * std::abs(r.H_liftoff / r.I_yy) + 0.05);
  }
  // Not yet met (reported, not asserted): the landing itself (the robot rebounds and a foot slips within ~0.1 s of the
  // impact); see the README.
}

TEST(HoppingDiagram, MomentumPitchReferenceLowersLiftoffMomentum) {
  // Until just after lift-off, with the pelvis held level (gain 0) and with the momentum pitch reference.
  const HopRun held = RunHandMadeHop(0.0, 2.3);
  const HopRun steered = RunHandMadeHop(HoppingReferenceParams{}.jump_momentum_gain, 2.3);
  std::printf("  H_pitch at lift-off: pelvis held %.3f N m s, momentum reference %.3f N m s\n", held.H_liftoff,
              steered.H_liftoff);
  ASSERT_GT(held.liftoff_time, 0.0) << held.status.ToString();
  ASSERT_GT(steered.liftoff_time, 0.0) << steered.status.ToString();
  EXPECT_EQ(steered.violations, 0);
  EXPECT_LT(std::abs(steered.H_liftoff), 0.8 * std::abs(held.H_liftoff));
}

// Largest real part of the eigenvalues of d/dx [v; q̈(x, u*(x))] at the state and desired outputs of the first Jump
// sample, u* from a ClfQpController with `outputs` (continuous time: the QP re-solved at every state).
double LargestClosedLoopEigenvalue(bool jump_tracks_momentum) {
  auto model = LoadCassie();
  auto jump_planner = [&](const RomState& start, LegLengthPlan* plan, std::string*) {
    *plan = {};
    AppendQuintic(0.0, 0.4, start.L, start.L - 0.06, 21, plan);
    return true;
  };
  HoppingDiagramParams params;
  params.outputs.jump_tracks_momentum = jump_tracks_momentum;
  params.reference.jump_force_feedback = 0.0;  // the hand-made plan carries no ROM force
  params.reference.jump_force_integral_per_s = 0.0;
  HoppingDiagram d = BuildHoppingDiagram(model, test::SpecLegLength, jump_planner, nullptr, params);
  Simulator sim(*d.diagram, HoppingSimulatorConfig());
  SetHoppingInitialState(d, sim.get_mutable_context(), model->q_nominal());
  Eigen::VectorXd x0, desired;
  HoppingRunParams run;
  run.duration_s = params.reference.settle_time_s + 1e-3;
  run.apex_rise_m = 0.06;  // the hop rule's H (no hop in this window)
  run.observer = [&](const Context& c, const HoppingRunState& s) {
    if (x0.size() == 0 && s.domain == HoppingDomain::kJump) {
      x0 = d.diagram->GetSubsystemContext(*d.plant, c).continuous_state();
      desired = d.reference->EvalOutput(d.diagram->GetSubsystemContext(*d.reference, c), "desired");
    }
  };
  RunHopping(d, sim, run);
  if (x0.size() == 0) return NAN;
  ClfQpParams cp = params.controller;
  cp.contact_stabilization = params.plant.dynamics;
  ClfQpController controller("clf", model, ActiveContactsPerMode(*d.plant),
                             MakeHoppingOutputs(*model, test::SpecLegLength, params.outputs), cp);
  auto context = controller.CreateDefaultLeafContext();
  context->FixInputPort(0, x0);
  context->FixAbstractInputPort(1, std::any(HoppingDomain::kJump));
  context->FixInputPort(2, desired);
  const ContactSet active = ActiveContactsPerMode(*d.plant)[HoppingDomain::kJump];
  const int nv = model->nv(), n = 2 * nv;
  MultibodyWorkspace ws(*model);
  auto flow = [&](const Eigen::VectorXd& x) {
    const_cast<Eigen::VectorXd&>(controller.EvalInput(*context, 0)) = x;
    context->InvalidateCache();
    EXPECT_EQ(controller.SolveQp(*context), QpStatus::kOptimal);
    const Eigen::VectorXd u = controller.last_qp(*context).x().head(model->nu());
    Eigen::VectorXd qdd(nv), F(model->max_constraint_rows()), out(n);
    CalcConstrainedForwardDynamics(*model, ws, x.head(nv), x.tail(nv), u, active, params.plant.dynamics, qdd, F);
    out << x.tail(nv), qdd;
    return out;
  };
  Eigen::MatrixXd A(n, n);
  const double h = 1e-6;
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd xp = x0, xm = x0;
    xp[i] += h, xm[i] -= h;
    A.col(i) = (flow(xp) - flow(xm)) / (2 * h);
  }
  return Eigen::EigenSolver<Eigen::MatrixXd>(A).eigenvalues().real().maxCoeff();
}

TEST(HoppingDiagram, JumpClosedLoopIsStableWithPitchAndNotWithMomentumOutput) {
  const double with_pitch = LargestClosedLoopEigenvalue(false), with_momentum = LargestClosedLoopEigenvalue(true);
  std::printf(
      "  largest closed-loop eigenvalue at the start of Jump: pelvis pitch output %.3f 1/s, H_pitch output %.1f 1/s\n",
      with_pitch, with_momentum);
  EXPECT_LT(with_pitch, 1.0);
  EXPECT_GT(with_momentum, 100.0);
}

// The hopping diagram on the Bullet plant (PlantKind::kBullet, the one builder argument), through the settle phase
// (Landing outputs, both feet down) up to 50 ms before the first Jump. Checks, from the plant: Bullet's contact forces
// are unilateral and inside the friction cone at every simulator step (ContactForceStatistics); the plant stays in
// "jump" (both feet) and does not fail; Cassie stays upright (pelvis pitch and roll within 0.05 rad, pelvis above
// 0.8 m); and the plant's ground forces carry the robot: their impulse over the window equals the COM's momentum change
// plus m g T (impulse-momentum, from the plant's own state through our kinematics), within 1e-5 of m g T (measured:
// 2.6e-5 N s of 401 N s over 1.25 s).
TEST(HoppingDiagram, SettlesOnTheBulletPlantWithPhysicalContactForces) {
  auto model = LoadCassie();
  auto no_jump = [](const RomState&, LegLengthPlan*, std::string* message) {
    *message = "not reached in this test";
    return false;
  };
  HoppingDiagramParams params;
  HoppingDiagram d = BuildHoppingDiagram(model, test::SpecLegLength, no_jump, nullptr, params, PlantKind::kBullet);
  ASSERT_NE(dynamic_cast<const BulletWorldPlant*>(d.plant), nullptr);
  Simulator sim(*d.diagram, HoppingSimulatorConfig());
  SetHoppingInitialState(d, sim.get_mutable_context(), model->q_nominal());
  const double h = params.bullet_plant.step_s, m = model->total_mass(), g = 9.81, t0 = 0.2;
  const double t_end = params.reference.settle_time_s - 0.05;
  long other_mode = 0;
  double worst_tilt = 0, lowest_pelvis = 1e9, impulse = 0, vz0 = NAN, vz1 = NAN, last_step = -1;
  HoppingRunParams run;
  run.duration_s = t_end;
  run.apex_rise_m = 0.1;  // the hop rule's H (no hop in this window)
  run.observer = [&](const Context& c, const HoppingRunState&) {
    const LeafContext& pc = d.diagram->GetSubsystemContext(*d.plant, c);
    other_mode += d.plant->EvalTypedOutput<int>(pc, "mode") != 0;
    const Eigen::VectorXd& q = d.plant->EvalOutput(pc, "q");
    worst_tilt = std::max(
        {worst_tilt, std::abs(q[model->VelocityIndex("base_pitch")]), std::abs(q[model->VelocityIndex("base_roll")])});
    lowest_pelvis = std::min(lowest_pelvis, q[2]);
    // One sample per plant step: after its update at t_k + offset the plant holds the state at t_(k+1) and the mean
    // ground force over [t_k, t_(k+1)].
    const double step_end = std::ceil(c.time() / h - 1e-6) * h;
    if (step_end > last_step + 0.5 * h) {
      last_step = step_end;
      const Eigen::VectorXd& f = d.plant->EvalOutput(pc, "contact_forces");
      const double vz = d.plant->EvalOutput(pc, "com")[5];
      if (step_end > t0 + 0.5 * h && step_end <= t_end + 1e-9) impulse += (f[2] + f[5]) * h;
      if (std::abs(step_end - t0) < 0.5 * h) vz0 = vz;
      if (std::abs(step_end - t_end) < 0.5 * h) vz1 = vz;
    }
  };
  const HoppingRunResult result =
      RunHopping(d, sim, run);  // its ContactForceStatistics: the plant's forces at every step
  const SimulatorStatus& status = result.status;
  const ContactForceStatistics& contact = result.contact;
  const double T = t_end - t0, momentum_error = impulse - m * g * T - m * (vz1 - vz0);
  std::printf(
      "  %s; %ld contact samples, %ld violations (%s), min F_n %.1f N, max |F_t|/F_n %.3f; tilt %.4f rad, pelvis >= "
      "%.3f m; "
      "impulse %.3f N s vs m g T + m dv %.3f N s (difference %.2e N s)\n",
      status.ToString().c_str(), contact.samples, contact.violations, contact.first_violation.c_str(),
      contact.min_normal_force_N, contact.max_friction_ratio, worst_tilt, lowest_pelvis, impulse,
      m * g * T + m * (vz1 - vz0), momentum_error);
  EXPECT_EQ(status.kind(), SimulatorStatus::Kind::kLimit) << status.ToString();
  EXPECT_GT(contact.samples, 1000);
  EXPECT_EQ(contact.violations, 0) << contact.first_violation;
  EXPECT_EQ(other_mode, 0);
  EXPECT_LT(worst_tilt, 0.05);
  EXPECT_GT(lowest_pelvis, 0.8);
  ASSERT_TRUE(std::isfinite(vz0) && std::isfinite(vz1));
  EXPECT_LT(std::abs(momentum_error), 1e-5 * m * g * T);
}

// The build → run → result snippet of hopping_diagram.h's header, exactly: the default hop (spring-mass ROM plans)
// succeeds, lands once, and the run's COM rise in flight is the ballistic one from the COM's vertical speed at
// lift-off, v_z² / (2 g) (closed form; the flight has only gravity acting on the COM).
TEST(HoppingRun, HeaderSnippetHopsAndTheComRiseIsBallistic) {
  auto model = std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromSidecar(FindRobotFile("robots/cassie/cassie.rome.json"), {.euler_floating_base = true}));
  SpringMassHopPlanners rom(*model, LegStiffnessVariant::kIdentified, SpringMassJumpParams{},
                            SpringMassLandingParams{});
  HoppingDiagramParams params;
  params.reference.hops = 1;
  HoppingDiagram d = BuildHoppingDiagram(model, rom.leg_length, rom.jump, rom.landing, params);
  Simulator sim(*d.diagram, HoppingSimulatorConfig());
  SetHoppingInitialState(d, sim.get_mutable_context(), model->q_nominal());
  const HoppingRunResult result = RunHopping(d, sim, HoppingRunParams{}, &rom);
  // (end of the snippet)
  ASSERT_EQ(result.liftoff_state.size(), 2 * model->nv()) << result.status.ToString();
  MultibodyWorkspace ws(*model);
  const Eigen::VectorXd& x = result.liftoff_state;
  const double vz = CalcComVelocity(*model, ws, x.head(model->nv()), x.tail(model->nv())).z();
  const double ballistic_rise = vz * vz / (2.0 * rom.rom.gravity);
  std::printf(
      "  %s; %s, hops landed %d, air %.4f s, COM rise %.4f m vs v_z^2/(2g) %.4f m, NRMSE jump %.3f landing %.3f, "
      "violations %ld\n",
      result.status.ToString().c_str(), result.status_kind.c_str(), result.touchdowns, result.air_time_s,
      result.com_rise_m, ballistic_rise, result.grf_nrmse_jump, result.grf_nrmse_landing, result.contact.violations);
  EXPECT_TRUE(result.success) << result.status.ToString();
  EXPECT_EQ(result.status_kind, "success");
  EXPECT_EQ(result.touchdowns, 1);
  EXPECT_NEAR(result.com_rise_m, ballistic_rise, 1e-3);
  EXPECT_EQ(result.contact.violations, 0) << result.contact.first_violation;
  // The rule's parts, from the result's own measurements: rest and the hop's rise against H/2.
  EXPECT_LT(result.rest_speed, HoppingRunParams{}.rest_max_speed);
  EXPECT_GE(result.com_rise_m, 0.5 * rom.jump_params.apex_rise);
}

// Out-of-range parameters from C++ fail at once (before any planner runs or the simulation starts), with a message
// that names the field and the value.
// A run whose initial state was never set is refused at once, naming the call to make (not simulated from q = 0).
TEST(HoppingRun, AForgottenInitialStateNamesTheCallToMake) {
  auto model = LoadCassie();
  int planner_calls = 0;
  auto planner = [&](const RomState&, LegLengthPlan*, std::string*) { return ++planner_calls > 0; };
  HoppingDiagram d = BuildHoppingDiagram(model, test::SpecLegLength, planner, nullptr, HoppingDiagramParams{});
  Simulator sim(*d.diagram, HoppingSimulatorConfig());
  HoppingRunParams run;
  run.apex_rise_m = 0.2;
  try {
    RunHopping(d, sim, run, nullptr);
    FAIL() << "a run without its initial state was simulated";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("call SetHoppingInitialState(diagram, context, q)"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(planner_calls, 0);
  EXPECT_EQ(sim.get_context().time(), 0.0);
}

TEST(HoppingDiagram, OutOfRangeParametersFailAtOnceNamingTheFieldAndTheValue) {
  auto model = LoadCassie();
  int planner_calls = 0;
  auto jump_planner = [&](const RomState&, LegLengthPlan*, std::string*) { return ++planner_calls > 0; };
  auto expect_error = [](const std::function<void()>& f, const std::string& field, const std::string& value) {
    try {
      f();
      ADD_FAILURE() << "no error for " << field << " = " << value;
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(field), std::string::npos) << what;
      EXPECT_NE(what.find(value), std::string::npos) << what;
    }
  };
  HoppingDiagramParams params;
  // Cassie on its default base, the quaternion free-flyer, is refused naming the file and the option.
  expect_error(
      [&] {
        BuildHoppingDiagram(std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
                                rome::test::SourcePath("robots/cassie/cassie.rome.json"))),
                            test::SpecLegLength, jump_planner, nullptr, params);
      },
      "BuildHoppingDiagram: robot 'cassie' has a quaternion floating base",
      "cassie.rome.json' with LoadOptions::euler_floating_base");
  params.reference.jump_momentum_gain = 250.0;
  const auto t0 = std::chrono::steady_clock::now();
  expect_error([&] { BuildHoppingDiagram(model, test::SpecLegLength, jump_planner, nullptr, params); },
               "reference.jump_momentum_gain", "250");
  params = {};
  params.reference.hops = 0;
  expect_error([&] { BuildHoppingDiagram(model, test::SpecLegLength, jump_planner, nullptr, params); },
               "reference.hops", "0");
  params = {};
  params.bullet_plant.substeps = 500;
  expect_error(
      [&] { BuildHoppingDiagram(model, test::SpecLegLength, jump_planner, nullptr, params, PlantKind::kBullet); },
      "bullet_plant.substeps", "500");
  SpringMassJumpParams jump;
  jump.apex_rise = 0.6;
  expect_error([&] { SpringMassHopPlanners(*model, LegStiffnessVariant::kIdentified, jump); }, "apex_rise", "0.6");
  SpringMassLandingParams landing;
  landing.min_force_fraction = 1.5;
  expect_error([&] { SpringMassHopPlanners(*model, LegStiffnessVariant::kIdentified, {}, landing); },
               "min_force_fraction", "1.5");
  HoppingRunParams run;
  run.duration_s = -2.0;
  expect_error([&] { run.Validate(); }, "duration_s", "-2");
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(planner_calls, 0);
  EXPECT_LT(elapsed, 5.0);  // no NLP, no simulation (each check builds at most the ROM's K(L) identification)
}

// The controller's desired rows per domain are the hopping paper's output counts (Sec. IV-D): Jump 6 (Eq. (41)-(42):
// 16 DOF without tarsi and springs − 10 foot constraints), Flight 10 (the motors, Eq. (43)), Landing 6 (Eq. (44)); the
// rows tile y_d of the reference's desired output [y_d; ẏ_d; ÿ_d] without gaps.
TEST(HoppingDiagram, TaskListGivesTheDesiredRowsOfEachDomain) {
  auto model = LoadCassie();
  auto no_jump = [](const RomState&, LegLengthPlan*, std::string*) { return false; };
  const HoppingDiagram d = BuildHoppingDiagram(model, test::SpecLegLength, no_jump, nullptr);
  int rows[3] = {0, 0, 0}, next_row = 0;
  for (const HoppingTask& t : d.tasks) {
    EXPECT_EQ(t.row, next_row) << t.name;
    next_row += t.size;
    for (int domain : t.domains) rows[domain] += t.size;
  }
  auto context = d.diagram->CreateDefaultContext();
  // [y_d; ẏ_d; ÿ_d]
  EXPECT_EQ(3 * next_row,
            d.reference->EvalOutput(d.diagram->GetSubsystemContext(*d.reference, *context), "desired").size());
  EXPECT_EQ(rows[HoppingDomain::kJump], 6);
  EXPECT_EQ(rows[HoppingDomain::kFlight], model->nu());
  EXPECT_EQ(rows[HoppingDomain::kLanding], 6);
  const std::vector<HoppingTask> listed = HoppingTasks(*model, d.params.outputs);  // without building a diagram
  ASSERT_EQ(listed.size(), d.tasks.size());
  for (size_t i = 0; i < listed.size(); ++i)
    EXPECT_TRUE(listed[i].name == d.tasks[i].name && listed[i].row == d.tasks[i].row &&
                listed[i].size == d.tasks[i].size);
}

// The controller seam takes a sub-diagram: the default controller → Saturation (framework/primitives.h), built with
// DiagramBuilder, with torque limits below the model's. The default hop still succeeds, and the torque the plant
// receives (the diagram's exported u, logged) stays within the limits at every logged sample.
TEST(HoppingDiagram, SaturatedSubDiagramControllerHops) {
  // 95 % of the model's torque limits (the default controller's): the saturation binds in the push-off (measured: 49
  // logged torques at the limit, air time 0.369 s against 0.402 s unsaturated; at 90 % the COM rise is 0.136 m, at 85 %
  // 0.109 m, below the hop rule's H/2 = 0.110 m).
  constexpr double kSaturationFraction = 0.95;
  auto model = LoadCassie();
  Eigen::VectorXd limit(model->nu());
  for (int i = 0; i < model->nu(); ++i) limit[i] = kSaturationFraction * model->actuators()[i].torque_limit_Nm;
  auto saturated = [&](const HoppingControllerSpec& spec) -> std::unique_ptr<System> {
    DiagramBuilder b;
    HoppingControllerSpec inner = spec;
    inner.name = "clf";
    b.AddSystem(MakeDefaultHoppingController(inner), "clf");
    b.AddSystem(std::make_unique<Saturation>("saturation", -limit, limit));
    b.Connect("clf", "u", "saturation", "u");
    for (const char* port : {"state", "mode", "desired"}) b.ExportInput("clf", port);
    b.ExportOutput("saturation", "y", "u");
    b.ExportOutput("clf", "qp_failures");
    b.ExportOutput("clf", "solve_time_s");
    return b.Build(spec.name);
  };
  SpringMassHopPlanners rom(*model, LegStiffnessVariant::kIdentified);
  HoppingDiagram d =
      BuildHoppingDiagram(model, rom.leg_length, rom.jump, rom.landing, {}, PlantKind::kHybrid, saturated);
  Simulator sim(*d.diagram, HoppingSimulatorConfig());
  SetHoppingInitialState(d, sim.get_mutable_context(), model->q_nominal());
  const HoppingRunResult result = RunHopping(d, sim, {}, &rom);
  const LogData& log = d.logger->log(d.diagram->GetSubsystemContext(*d.logger, sim.get_context()));
  const std::vector<std::string> columns = d.logger->ColumnNames();  // "time" first, then the sample's entries
  int u0 = -1;
  for (size_t i = 1; i < columns.size() && u0 < 0; ++i)
    if (columns[i].rfind("controller.u", 0) == 0 && (columns[i][12] == '[' || columns[i][12] == '.'))
      u0 = static_cast<int>(i) - 1;
  ASSERT_GE(u0, 0);
  double worst_excess = -1e9;
  long at_limit = 0;
  for (const Eigen::VectorXd& row : log.samples)
    for (int i = 0; i < model->nu(); ++i) {
      const double u = row[u0 + i];
      worst_excess = std::max(worst_excess, std::abs(u) - limit[i]);
      at_limit += std::abs(u) >= limit[i] - 1e-9;
    }
  std::printf(
      "  %s; %s, air %.4f s, COM rise %.4f m, %zu logged samples, %ld torques at the limit, largest |u| - limit %.3g N "
      "m\n",
      result.status.ToString().c_str(), result.status_kind.c_str(), result.air_time_s, result.com_rise_m,
      log.samples.size(), at_limit, worst_excess);
  ASSERT_GT(log.samples.size(), 1000u);
  EXPECT_LE(worst_excess, 0.0);
  EXPECT_GT(at_limit, 0) << "the limits never bound: the test would not show the seam";
  EXPECT_TRUE(result.success) << result.status.ToString();
}

}  // namespace
}  // namespace rome
