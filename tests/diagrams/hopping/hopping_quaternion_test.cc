// The default hop (one hop, the hopping example's defaults) with the plant on the quaternion free-flyer base
// (HoppingDiagramParams::plant_base, issue 43): the controller runs on the quaternion twin and reads the plant's state
// (its state port has nq + nv entries); the reference and the run read the Euler state through the
// QuaternionToEulerState block. Checks, from the plant's own outputs:
//   * the run succeeds (hops, lands, rests) with no plant contact violation after any integrator step (normal forces
//     >= 0, inside the friction cone: ContactForceStatistics), and the largest |F_t|/F_n stays below mu;
//   * the quaternion's norm stays within 1e-8 of 1: the plant's norm term holds the drift at the integrator's error
//     (docs/design-notes.md#quaternion-norm: 1e-10 at rtol 1e-10), and this diagram integrates at atol 1e-7;
//   * in flight (no contact, gravity only) the COM's vertical energy 1/2 m vz^2 + m g z is constant (Newton: m a_com =
//     m g) and the centroidal angular momentum is constant (internal torques only): the plant's com output and the
//     quaternion model's A_G, against their values at lift-off;
//   * the kinetic energy 1/2 v^T M v from the quaternion model's own mass matrix equals the Euler model's from the
//     mapped state, at every sample;
//   * against the same hop on the Euler plant: the COM rise and the air time agree within 0.1 mm and 0.1 ms (the
//     tolerance: the two plants integrate different coordinates at rtol 1e-5, atol 1e-7, so their trajectories differ
//     at the integrator's error, and the closed loop (2 kHz QP, event-timed domains) carries it to the apex; measured:
//     1e-6 m and 0 s, docs/design-notes.md, "Diagrams on the quaternion plant").
// Label slow.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "diagrams/hopping/hopping_diagram.h"
#include "diagrams/hopping/hopping_plans.h"
#include "diagrams/hopping/hopping_run.h"
#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_workspace.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

std::shared_ptr<const MultibodyModel> LoadCassieEuler() {
  LoadOptions euler;
  euler.euler_floating_base = true;
  return std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromSidecar(rome::test::SourcePath("robots/cassie/cassie.rome.json"), euler));
}

struct FlightChecks {
  double worst_norm = 0, worst_flight_energy = 0, worst_flight_momentum = 0, worst_kinetic = 0;
  int flight_samples = 0;
};

HoppingRunResult RunDefaultHop(PlantBase base, FlightChecks* checks, int latency_samples = 0) {
  auto model = LoadCassieEuler();
  SpringMassHopPlanners planners(*model, LegStiffnessVariant::kIdentified, SpringMassJumpParams{},
                                 SpringMassLandingParams{});
  HoppingDiagramParams params;
  params.plant_base = base;
  params.perturbations.latency_samples = latency_samples;
  params.perturbations.sample_period_s = params.controller.update_period_s;
  HoppingDiagram d = BuildHoppingDiagram(model, planners.leg_length, planners.jump, planners.landing, params);
  const int state_size = d.controller->input_port(d.controller->GetInputPortIndex("state")).size;
  EXPECT_EQ(state_size, base == PlantBase::kQuaternion ? 2 * model->nv() + 1 : 2 * model->nv());
  Simulator sim(*d.diagram, HoppingSimulatorConfig());
  SetHoppingInitialState(d, sim.get_mutable_context(), model->q_nominal());
  HoppingRunParams run;
  if (checks && base == PlantBase::kQuaternion) {
    const MultibodyModel* quat = d.plant_model.get();
    const int nv = model->nv();
    auto ws_q = std::make_shared<MultibodyWorkspace>(*quat);
    auto ws_e = std::make_shared<MultibodyWorkspace>(*model);
    const double m = model->total_mass(), g = 9.81;
    auto liftoff = std::make_shared<Eigen::Matrix<double, 7, 1>>();  // [E_z; k_G]
    run.observer = [=, &d](const Context& c, const HoppingRunState& state) {
      const LeafContext& pc = d.diagram->GetSubsystemContext(*d.plant, c);
      const Eigen::VectorXd& x = d.plant->EvalOutput(pc, "state");
      const Eigen::VectorXd q = x.head(nv + 1), v = x.tail(nv);
      checks->worst_norm = std::max(checks->worst_norm, std::abs(q.segment<4>(3).norm() - 1.0));
      const Eigen::VectorXd& xe = HoppingEulerState(d, c);
      const Eigen::VectorXd ve = xe.tail(nv);
      const double T_q = 0.5 * v.dot(CalcMassMatrix(*quat, *ws_q, q) * v);
      const double T_e = 0.5 * ve.dot(CalcMassMatrix(*model, *ws_e, xe.head(nv)) * ve);
      checks->worst_kinetic = std::max(checks->worst_kinetic, std::abs(T_q - T_e) / std::max(1.0, T_q));
      if (state.domain != HoppingDomain::kFlight) return;
      const Eigen::VectorXd& com = d.plant->EvalOutput(pc, "com");
      Eigen::Matrix<double, 7, 1> now;
      now[0] = 0.5 * m * com[5] * com[5] + m * g * com[2];
      now.tail<6>() = CalcCentroidalMomentum(*quat, *ws_q, q, v);
      if (state.previous_domain != HoppingDomain::kFlight) *liftoff = now;
      checks->worst_flight_energy = std::max(checks->worst_flight_energy, std::abs(now[0] - (*liftoff)[0]));
      checks->worst_flight_momentum =
          std::max(checks->worst_flight_momentum, (now.segment<3>(1) - liftoff->segment<3>(1)).norm());
      ++checks->flight_samples;
    };
  }
  return RunHopping(d, sim, run, &planners);
}

TEST(HoppingQuaternion, DefaultHopOnTheQuaternionPlantIsPhysicalAndMatchesTheEulerPlant) {
  FlightChecks checks;
  const HoppingRunResult q = RunDefaultHop(PlantBase::kQuaternion, &checks);
  const HoppingRunResult e = RunDefaultHop(PlantBase::kEuler, nullptr);
  std::printf(
      "quaternion plant: %s, COM rise %.6f m, air time %.6f s, max |F_t|/F_n %.4f, violations %ld; norm %.3g, "
      "flight (%d samples) |dE_z| %.3g J, |dk_G| %.3g N m s, kinetic energy rel. %.3g\n"
      "Euler plant:      %s, COM rise %.6f m, air time %.6f s, max |F_t|/F_n %.4f\n",
      q.status.ToString().c_str(), q.com_rise_m, q.air_time_s, q.contact.max_friction_ratio, q.contact.violations,
      checks.worst_norm, checks.flight_samples, checks.worst_flight_energy, checks.worst_flight_momentum,
      checks.worst_kinetic, e.status.ToString().c_str(), e.com_rise_m, e.air_time_s, e.contact.max_friction_ratio);
  ASSERT_TRUE(q.success) << q.status.ToString();
  ASSERT_TRUE(e.success) << e.status.ToString();
  EXPECT_EQ(q.contact.violations, 0);
  EXPECT_LT(q.contact.max_friction_ratio, 0.8);  // Cassie's feet: mu = 0.8 (robots/cassie/cassie.rome.json)
  EXPECT_LT(checks.worst_norm, 1e-8);
  ASSERT_GT(checks.flight_samples, 50);
  // Flight: m g z + 1/2 m vz^2 ~ 330 N x 1 m; the integrator's rtol 1e-5 on z and vz bounds its drift near 1e-2 J.
  EXPECT_LT(checks.worst_flight_energy, 1e-4);    // J; measured 1.2e-6 J
  EXPECT_LT(checks.worst_flight_momentum, 1e-5);  // N m s; measured 7.3e-8
  EXPECT_LT(checks.worst_kinetic, 1e-10);
  EXPECT_NEAR(q.com_rise_m, e.com_rise_m, 1e-4);
  EXPECT_NEAR(q.air_time_s, e.air_time_s, 1e-4);
}

// The sensor path on the quaternion base carries the plant's quaternion state (nq + nv): a latency of two controller
// periods, its history set from the initial state, gives the same hop as on the Euler base.
TEST(HoppingQuaternion, SensorLatencyOnTheQuaternionBaseMatchesTheEulerBase) {
  const HoppingRunResult q = RunDefaultHop(PlantBase::kQuaternion, nullptr, 2);
  const HoppingRunResult e = RunDefaultHop(PlantBase::kEuler, nullptr, 2);
  std::printf("latency 2 periods: quaternion %s, COM rise %.6f m; Euler %s, COM rise %.6f m\n",
              q.status.ToString().c_str(), q.com_rise_m, e.status.ToString().c_str(), e.com_rise_m);
  ASSERT_TRUE(e.success) << e.status.ToString();
  ASSERT_TRUE(q.success) << q.status.ToString();
  EXPECT_EQ(q.contact.violations, 0);
  EXPECT_NEAR(q.com_rise_m, e.com_rise_m, 1e-4);
  EXPECT_NEAR(q.air_time_s, e.air_time_s, 1e-4);
}

TEST(HoppingQuaternion, RefusesTheBulletPlantAndAPush) {
  auto model = LoadCassieEuler();
  SpringMassHopPlanners planners(*model, LegStiffnessVariant::kIdentified, SpringMassJumpParams{},
                                 SpringMassLandingParams{});
  HoppingDiagramParams params;
  params.plant_base = PlantBase::kQuaternion;
  EXPECT_THROW(
      BuildHoppingDiagram(model, planners.leg_length, planners.jump, planners.landing, params, PlantKind::kBullet),
      std::invalid_argument);
  params.perturbations.push = ExternalPushParams{};
  params.perturbations.push->body = "pelvis";
  params.perturbations.push->force_N = Eigen::Vector3d(10, 0, 0);
  EXPECT_THROW(BuildHoppingDiagram(model, planners.leg_length, planners.jump, planners.landing, params),
               std::invalid_argument);
}

}  // namespace
}  // namespace rome
