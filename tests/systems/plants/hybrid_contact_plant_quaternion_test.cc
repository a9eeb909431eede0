// HybridContactPlant on the quaternion free-flyer base (issue 43). References: conservation of energy and of spatial
// momentum in free flight (the COM's parabola, a constant angular momentum about the COM); the Euler-base plant from
// the same physical state (mapped through the closed-form Euler-rate-to-body-rate map written here); the free-fall time
// sqrt(2h/g); the impulse-momentum balance of the impact, with the impulse recovered from M (v+ - v-) = J^T lambda;
// a body spinning about a principal axis through +-90 deg of pitch against R(t) = Ry(w t).
#include <cmath>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include <Eigen/QR>

#include "framework/simulator.h"
#include "systems/multibody/free_flyer.h"
#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/plants/hybrid_contact_plant.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

constexpr double kG = 9.81;

std::shared_ptr<const MultibodyModel> LoadRobot(const std::string& robot, bool quaternion) {
  LoadOptions options;
  options.quaternion_floating_base = quaternion;
  options.euler_floating_base = !quaternion;
  return std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromSidecar(rome::test::SourcePath("robots/" + robot + "/" + robot + ".rome.json"), options));
}
std::shared_ptr<const MultibodyModel> LoadExo(bool quaternion) { return LoadRobot("exoskeleton", quaternion); }

SimulatorConfig Tight() {
  SimulatorConfig c;
  c.relative_tolerance = 1e-10;
  c.absolute_tolerance = 1e-10;
  return c;
}

ContactModeGraph FlightOnly() {
  ContactModeGraph g;
  g.modes = {{"flight", {}}};
  g.initial_mode = "flight";
  return g;
}

// A spatial Euler-base state [x y z yaw pitch roll joints; their rates] as the quaternion base's (q, v):
// R = Rz(yaw) Ry(pitch) Rx(roll); v_B = R^T dp/dt; w_B from the ZYX rates (closed form, written here).
void EulerToQuaternionState(const Eigen::VectorXd& q_e, const Eigen::VectorXd& v_e, Eigen::VectorXd* q,
                            Eigen::VectorXd* v) {
  const int n = static_cast<int>(q_e.size()) - 6;
  const double yaw = q_e[3], pitch = q_e[4], roll = q_e[5];
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  const Eigen::Quaterniond quat(R);
  q->resize(n + 7);
  *q << q_e.head<3>(), quat.w(), quat.x(), quat.y(), quat.z(), q_e.tail(n);
  const double dyaw = v_e[3], dpitch = v_e[4], droll = v_e[5];
  const Eigen::Vector3d w_B(droll - std::sin(pitch) * dyaw,
                            std::cos(roll) * dpitch + std::sin(roll) * std::cos(pitch) * dyaw,
                            -std::sin(roll) * dpitch + std::cos(roll) * std::cos(pitch) * dyaw);
  v->resize(n + 6);
  *v << R.transpose() * v_e.head<3>(), w_B, v_e.tail(n);
}

// A robot thrown with a twist (base and joints moving) at 10 m: no contact, no torque.
void ThrownState(const MultibodyModel& euler, Eigen::VectorXd* q_e, Eigen::VectorXd* v_e) {
  *q_e = euler.q_nominal();
  (*q_e)[2] += 10.0;
  (*q_e)[3] = 0.3, (*q_e)[4] = 0.4, (*q_e)[5] = -0.2;
  *v_e = Eigen::VectorXd::Zero(euler.nv());
  v_e->head<6>() << 0.5, -0.3, 2.0, 0.8, -1.5, 1.1;  // m/s and ZYX rates, rad/s
  for (int i = 6; i < euler.nv(); ++i) (*v_e)[i] = 0.6 * std::sin(1.7 * i);
}

TEST(HybridContactPlantQuaternion, FreeFlightConservesEnergyAndSpatialMomentumAndKeepsTheQuaternionUnit) {
  auto euler = LoadExo(false);
  auto model = LoadExo(true);
  ASSERT_EQ(model->nq(), model->nv() + 1);
  Eigen::VectorXd q_e, v_e, q0, v0;
  ThrownState(*euler, &q_e, &v_e);
  EulerToQuaternionState(q_e, v_e, &q0, &v0);
  HybridContactPlant plant("exo", model, FlightOnly(), Terrain::Flat());
  auto context = plant.CreateDefaultLeafContext();
  plant.SetState(*context, q0, v0, "flight");
  context->FixInputPort(0, Eigen::VectorXd::Zero(model->nu()));
  const LeafContext* ctx = context.get();
  MultibodyWorkspace ws(*model);
  const int nq = model->nq(), nv = model->nv();
  const double m = model->total_mass();
  const double E0 = CalcKineticEnergy(*model, ws, q0, v0) + CalcPotentialEnergy(*model, ws, q0);
  const Vector6d h0 = CalcCentroidalMomentum(*model, ws, q0, v0);
  Simulator sim(plant, std::move(context), Tight());
  double worst_E = 0, worst_k = 0, worst_l = 0, worst_norm = 0;
  sim.set_monitor([&](const Context&) {
    const Eigen::VectorXd q = ctx->continuous_state().head(nq), v = ctx->continuous_state().tail(nv);
    const double E = CalcKineticEnergy(*model, ws, q, v) + CalcPotentialEnergy(*model, ws, q);
    const Vector6d h = CalcCentroidalMomentum(*model, ws, q, v);
    worst_E = std::max(worst_E, std::abs(E - E0));
    worst_k = std::max(worst_k, (h.head<3>() - h0.head<3>()).norm());
    // Linear momentum: m v_com(t) = m v_com(0) + m g t.
    const Eigen::Vector3d l_expected = h0.tail<3>() + m * ctx->time() * Eigen::Vector3d(0, 0, -kG);
    worst_l = std::max(worst_l, (h.tail<3>() - l_expected).norm());
    worst_norm = std::max(worst_norm, std::abs(q.segment<4>(3).norm() - 1.0));
    return EventStatus::Succeeded();
  });
  const SimulatorStatus status = sim.AdvanceTo(1.0);
  ASSERT_TRUE(status.ok()) << status.ToString();
  std::printf("exo free flight 1 s: |dE| %.3g J (E0 %.4g J), |dk| %.3g, |dl| %.3g kg m/s, quaternion norm %.3g\n",
              worst_E, E0, worst_k, worst_l, worst_norm);
  EXPECT_LT(worst_E, 1e-6 * std::abs(E0));
  EXPECT_LT(worst_k, 1e-6 * std::max(1.0, h0.head<3>().norm()));
  EXPECT_LT(worst_l, 1e-6 * m * kG);
  EXPECT_LT(worst_norm, 1e-10);  // the documented bound (docs/design-notes.md#quaternion-norm)
}

// Cassie adds its achilles loop closures (Baumgarte-stabilised in both plants) and its damped leaf springs.
class QuaternionVsEuler : public ::testing::TestWithParam<std::string> {};

TEST_P(QuaternionVsEuler, FreeFlightMatchesTheEulerBasePlantThroughTheFootKinematics) {
  auto euler = LoadRobot(GetParam(), false);
  auto model = LoadRobot(GetParam(), true);
  Eigen::VectorXd q_e, v_e, q0, v0;
  ThrownState(*euler, &q_e, &v_e);
  EulerToQuaternionState(q_e, v_e, &q0, &v0);
  HybridContactPlant plant_e("euler", euler, FlightOnly(), Terrain::Flat());
  HybridContactPlant plant_q("quaternion", model, FlightOnly(), Terrain::Flat());
  auto ctx_e = plant_e.CreateDefaultLeafContext();
  auto ctx_q = plant_q.CreateDefaultLeafContext();
  plant_e.SetState(*ctx_e, q_e, v_e, "flight");
  plant_q.SetState(*ctx_q, q0, v0, "flight");
  ctx_e->FixInputPort(0, Eigen::VectorXd::Zero(euler->nu()));
  ctx_q->FixInputPort(0, Eigen::VectorXd::Zero(model->nu()));
  const LeafContext *ce = ctx_e.get(), *cq = ctx_q.get();
  Simulator sim_e(plant_e, std::move(ctx_e), Tight());
  Simulator sim_q(plant_q, std::move(ctx_q), Tight());
  MultibodyWorkspace ws_e(*euler), ws_q(*model);
  double worst = 0;
  for (int k = 1; k <= 10; ++k) {
    const double t = 0.1 * k;
    ASSERT_TRUE(sim_e.AdvanceTo(t).ok());
    ASSERT_TRUE(sim_q.AdvanceTo(t).ok());
    const Eigen::VectorXd qe = ce->continuous_state().head(euler->nq());
    const Eigen::VectorXd qq = cq->continuous_state().head(model->nq());
    ASSERT_LT(std::abs(qe[4]), 1.4) << "the Euler run must stay away from +-90 deg pitch";
    for (int c = 0; c < model->num_contacts(); ++c)
      for (int p = 0; p < static_cast<int>(model->contacts()[c].points.size()); ++p)
        worst = std::max(
            worst, (CalcContactPointPosition(*euler, ws_e, qe, c, p) - CalcContactPointPosition(*model, ws_q, qq, c, p))
                       .norm());
  }
  std::printf("%s free flight, quaternion vs Euler plant: worst contact-point distance %.3g m over 1 s\n",
              GetParam().c_str(), worst);
  EXPECT_LT(worst, 1e-6);
}
INSTANTIATE_TEST_SUITE_P(Robots, QuaternionVsEuler, ::testing::Values("exoskeleton", "cassie"));

TEST(HybridContactPlantQuaternion, TouchdownTimeIsFreeFallAndTheImpactChangesMomentumByTheContactImpulse) {
  auto model = LoadExo(true);
  HybridContactPlant plant("exo", model, ContactModeGraph::Hopping("left_foot", "right_foot"), Terrain::Flat());
  auto context = plant.CreateDefaultLeafContext();
  const double drop = 0.25;
  Eigen::VectorXd q = model->q_nominal();
  q[2] += drop;
  // Level base, tilted about no axis: every sole corner falls as the body does.
  plant.SetState(*context, q, Eigen::VectorXd::Zero(model->nv()), "flight");
  context->FixInputPort(0, Eigen::VectorXd::Zero(model->nu()));
  const LeafContext* ctx = context.get();
  MultibodyWorkspace ws(*model);
  double z0 = std::numeric_limits<double>::infinity();  // lowest sole corner at the nominal pose
  for (int c = 0; c < 2; ++c)
    for (int p = 0; p < 4; ++p) z0 = std::min(z0, CalcContactPointPosition(*model, ws, model->q_nominal(), c, p).z());
  ASSERT_NEAR(z0, 0.0, 1e-3);
  const double t_expected = std::sqrt(2 * (drop + z0) / kG);
  SimulatorConfig config = Tight();
  config.max_guard_events = 1;  // stop right after the touchdown's reset: the post-impact state at the event time
  Simulator sim(plant, std::move(context), config);
  ASSERT_TRUE(sim.AdvanceTo(t_expected - 1e-4).ok());
  ASSERT_EQ(ctx->mode(), plant.GetModeIndex("flight"));
  const SimulatorStatus status = sim.AdvanceTo(t_expected + 1e-3);
  ASSERT_EQ(status.reason, SimulatorStatus::Reason::kReachedEventLimit) << status.ToString();
  ASSERT_GE(sim.statistics().events.size(), 1u);
  const EventRecord& ev = sim.statistics().events[0];
  EXPECT_NEAR(ev.time, t_expected, 1e-8);
  EXPECT_EQ(ev.mode_after, plant.GetModeIndex("stance"));

  // Just before the impact, free fall in closed form: the level base falls at -g t, nothing else moves.
  const int nq = model->nq(), nv = model->nv();
  Eigen::VectorXd v_minus = Eigen::VectorXd::Zero(nv);
  v_minus[2] = -kG * ev.time;  // base axes = world axes (level base)
  const Eigen::VectorXd v_plus = ctx->continuous_state().tail(nv);
  const Eigen::VectorXd q_plus = ctx->continuous_state().head(nq);  // the reset leaves q
  EXPECT_NEAR(q_plus[2], q[2] - 0.5 * kG * ev.time * ev.time, 1e-8);
  // Impulse: M (v+ - v-) = J^T lambda with J the sole corners' point Jacobians (world rows); lambda least squares.
  Eigen::MatrixXd J(24, nv), Jp(3, nv);
  for (int c = 0; c < 2; ++c)
    for (int p = 0; p < 4; ++p) {
      CalcPointJacobian(*model, ws, q_plus, model->contacts()[c].body, model->contacts()[c].points[p], Jp);
      J.middleRows<3>(12 * c + 3 * p) = Jp;
    }
  const Eigen::VectorXd Mdv = CalcMassMatrix(*model, ws, q_plus) * (v_plus - v_minus);
  const Eigen::VectorXd lambda = J.transpose().completeOrthogonalDecomposition().solve(Mdv);
  EXPECT_LT((J.transpose() * lambda - Mdv).norm(), 1e-7 * Mdv.norm()) << "M dv is not a contact impulse";
  EXPECT_LT((J * v_plus).norm(), 1e-9) << "the soles are not at rest after the plastic impact";
  // Spatial momentum across the impact: dl = sum lambda_i, dk_G = sum (p_i - c) x lambda_i.
  Eigen::Vector3d sum_f = Eigen::Vector3d::Zero(), sum_tau = Eigen::Vector3d::Zero();
  const Eigen::Vector3d com = CalcComPosition(*model, ws, q_plus);
  for (int c = 0; c < 2; ++c)
    for (int p = 0; p < 4; ++p) {
      const Eigen::Vector3d f = lambda.segment<3>(12 * c + 3 * p);
      sum_f += f;
      sum_tau += (CalcContactPointPosition(*model, ws, q_plus, c, p) - com).cross(f);
    }
  const Vector6d dh =
      CalcCentroidalMomentum(*model, ws, q_plus, v_plus) - CalcCentroidalMomentum(*model, ws, q_plus, v_minus);
  const double scale = model->total_mass() * kG * ev.time;  // |momentum before|
  std::printf(
      "exo touchdown: event time - sqrt(2h/g) = %.3g s; |dl - sum lambda| %.3g, |dk - sum r x lambda| %.3g "
      "(|l-| = %.4g kg m/s)\n",
      ev.time - t_expected, (dh.tail<3>() - sum_f).norm(), (dh.head<3>() - sum_tau).norm(), scale);
  EXPECT_GT(sum_f.z(), 0.0);
  EXPECT_LT((dh.tail<3>() - sum_f).norm(), 1e-7 * scale);
  EXPECT_LT((dh.head<3>() - sum_tau).norm(), 1e-7 * scale);
}

// One rigid body, inertia diagonal in its frame, COM at its origin (test values).
std::shared_ptr<const MultibodyModel> LoadSpinningBody() {
  const std::string urdf = R"(<robot name="brick"><link name="brick"><inertial><origin xyz="0 0 0"/><mass value="2"/>
      <inertia ixx="0.05" iyy="0.08" izz="0.11" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>)";
  return std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromText(
      urdf, R"({"floating_base": "quaternion", "contacts": []})", "brick.urdf", "brick.rome.json"));
}

TEST(HybridContactPlantQuaternion, BodyTumblingThroughNinetyDegreesPitchFollowsTheClosedForm) {
  auto model = LoadSpinningBody();
  HybridContactPlantParams params;
  params.min_base_height_m = -1e9;  // no ground: free fall for the whole run
  HybridContactPlant plant("brick", model, FlightOnly(), Terrain::Flat(), params);
  auto context = plant.CreateDefaultLeafContext();
  Eigen::VectorXd q(7), v(6);
  q << 0, 0, 10, 1, 0, 0, 0;
  const double w = 2 * M_PI;                       // rad/s about the body's y axis (a principal axis): pitch
  const Eigen::Vector3d v0_world(0.3, -0.2, 4.0);  // m/s
  v << v0_world, 0, w, 0;                          // base = world axes at t = 0
  plant.SetState(*context, q, v, "flight");
  context->FixInputPort(0, Eigen::VectorXd::Zero(model->nu()));
  const LeafContext* ctx = context.get();
  Simulator sim(plant, std::move(context), Tight());
  double worst_R = 0, worst_p = 0;
  for (int k = 1; k <= 40; ++k) {  // every 25 ms for 1 s: pitch passes +90 deg at 0.25 s and -90 deg at 0.75 s
    const double t = 0.025 * k;
    ASSERT_TRUE(sim.AdvanceTo(t).ok());
    const Eigen::VectorXd x = ctx->continuous_state();
    const Eigen::Matrix3d R = Eigen::Quaterniond(x[3], x[4], x[5], x[6]).normalized().toRotationMatrix();
    const Eigen::Matrix3d R_expected = Eigen::AngleAxisd(w * t, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::Vector3d p_expected =
        Eigen::Vector3d(0, 0, 10) + v0_world * t + 0.5 * t * t * Eigen::Vector3d(0, 0, -kG);
    worst_R = std::max(worst_R, (R - R_expected).cwiseAbs().maxCoeff());
    worst_p = std::max(worst_p, (x.head<3>() - p_expected).norm());
  }
  std::printf("brick tumbling through +-90 deg pitch: |R - Ry(wt)| %.3g, |p - parabola| %.3g m\n", worst_R, worst_p);
  EXPECT_LT(worst_R, 1e-8);
  EXPECT_LT(worst_p, 1e-8 * 10.0);  // the integrator's relative tolerance on |p| ~ 10 m
}

// The tennis-racket effect in the plant: a spin about the intermediate principal axis (y) with a small perturbation
// flips the axis over; energy and angular momentum about the COM stay constant, and the quaternion's norm stays within
// the documented bound for 10 s without any projection (no reset happens in free flight).
void RunTennisRacket(double norm_gain_per_s) {
  SCOPED_TRACE("quaternion_norm_gain_per_s = " + std::to_string(norm_gain_per_s));
  auto model = LoadSpinningBody();
  HybridContactPlantParams params;
  params.min_base_height_m = -1e9;
  params.quaternion_norm_gain_per_s = norm_gain_per_s;
  HybridContactPlant plant("brick", model, FlightOnly(), Terrain::Flat(), params);
  auto context = plant.CreateDefaultLeafContext();
  Eigen::VectorXd q(7), v(6);
  q << 0, 0, 0, 1, 0, 0, 0;
  v << 0, 0, 0, 0.01, 6.0, 0.01;
  plant.SetState(*context, q, v, "flight");
  context->FixInputPort(0, Eigen::VectorXd::Zero(model->nu()));
  const LeafContext* ctx = context.get();
  MultibodyWorkspace ws(*model);
  const double T0 = CalcKineticEnergy(*model, ws, q, v);
  const Eigen::Vector3d k0 = CalcCentroidalMomentum(*model, ws, q, v).head<3>();
  Simulator sim(plant, std::move(context), Tight());
  double worst_T = 0, worst_k = 0, worst_norm = 0, min_yy = 1;
  sim.set_monitor([&](const Context&) {
    const Eigen::VectorXd x = ctx->continuous_state();
    // Kinetic energy of the rotation alone: the COM's own motion is the parabola, its energy exchanges with gravity.
    Eigen::VectorXd w_only = x.tail(6);
    w_only.head<3>().setZero();
    Eigen::VectorXd q_now = x.head(7);
    worst_T = std::max(worst_T, std::abs(CalcKineticEnergy(*model, ws, q_now, w_only) - T0));
    worst_k = std::max(worst_k, (CalcCentroidalMomentum(*model, ws, q_now, x.tail(6)).head<3>() - k0).norm());
    worst_norm = std::max(worst_norm, std::abs(x.segment<4>(3).norm() - 1.0));
    const Eigen::Matrix3d R = Eigen::Quaterniond(x[3], x[4], x[5], x[6]).normalized().toRotationMatrix();
    min_yy = std::min(min_yy, R(1, 1));
    return EventStatus::Succeeded();
  });
  ASSERT_TRUE(sim.AdvanceTo(10.0).ok());
  std::printf(
      "brick tennis racket 10 s, norm gain %g /s: |dT| %.3g J (T0 %.4g J), |dk| %.3g, quaternion norm %.3g, "
      "min R_yy %.3f\n",
      norm_gain_per_s, worst_T, T0, worst_k, worst_norm, min_yy);
  EXPECT_LT(min_yy, -0.9) << "the intermediate axis did not flip";
  EXPECT_LT(worst_T, 1e-7 * T0);
  EXPECT_LT(worst_k, 1e-7 * k0.norm());
  // The bound documented in docs/design-notes.md#quaternion-norm: without the gain the error accumulates.
  EXPECT_LT(worst_norm, norm_gain_per_s > 0 ? 1e-10 : 1e-8);
}

TEST(HybridContactPlantQuaternion, TennisRacketFlipConservesEnergyAndAngularMomentumFor10Seconds) {
  RunTennisRacket(HybridContactPlantParams{}.quaternion_norm_gain_per_s);
  RunTennisRacket(0.0);
}

TEST(HybridContactPlantQuaternion, SetStateRefusesANonUnitQuaternionNamingIt) {
  auto model = LoadSpinningBody();
  HybridContactPlant plant("brick", model, FlightOnly(), Terrain::Flat());
  auto context = plant.CreateDefaultLeafContext();
  Eigen::VectorXd q(7);
  q << 0, 0, 1, 0.9, 0, 0, 0;
  try {
    plant.SetState(*context, q, Eigen::VectorXd::Zero(6), "flight");
    ADD_FAILURE() << "SetState accepted a quaternion of norm 0.9";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("brick"), std::string::npos) << what;
    EXPECT_NE(what.find("norm 0.9"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace rome
