// CalcPeriodicPlanTorqueNeed against independent computations at the planned samples (AMBER, flat 0.8 m steps and
// stairs down (0.6, -0.1) m):
//  * torques and stance force against the plant's inverse dynamics by the recursive Newton-Euler algorithm
//    (CalcInverseDynamics, RNEA; the function itself solves with the CRBA mass matrix and the bias forces): at every
//    sample RNEA(q, v, q̈) − J_stᵀ F must be B τ, zero on the floating base's three rows;
//  * the stance force against Newton's law for the whole body, F = m (p̈_com + g e_z): vertically with p̈_com by
//    central finite differences of the planned COM velocity of neighbouring samples; horizontally, where the COM's
//    acceleration is the dynamics' and not prescribed, with p̈_com = J_com q̈ + J̇_com v (Newton's law is not among
//    the equations the function solves);
//  * the velocities against central finite differences of the planned postures;
//  * the postures: stance foot at the origin, the torso pitch constant (periodic: φ_0 = φ_f);
//  * the plan's start: the COM at the post-impact position behind the stance foot, the speed l / T̂_s.
#include "diagrams/stepping_stones/stepping_stones_torque_need.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "systems/multibody/multibody_dynamics.h"

namespace rome {
namespace {

MultibodyModel Amber() {
  return MultibodyModel::LoadFromSidecar("robots/amber/amber.rome.json", {.euler_floating_base = true});
}

SteppingStonesDiagramParams Params(double energy, double eps) {
  SteppingStonesDiagramParams p;
  p.target_orbital_energy = energy;
  p.impact_fraction = eps;
  return p;
}

double Mass(const MultibodyModel& m) {
  double mass = 0;
  for (const auto& b : m.bodies()) mass += b.mass;
  return mass;
}

struct Case {
  double l, h, energy, eps;
};

class PlanTorqueNeedTest : public ::testing::TestWithParam<Case> {};

TEST_P(PlanTorqueNeedTest, AgreesWithRneaNewtonAndFiniteDifferences) {
  const Case c = GetParam();
  const MultibodyModel amber = Amber();
  MultibodyWorkspace ws(amber);
  const int nv = amber.nv();
  PlanTorqueNeedParams np;
  np.samples = 400;
  std::vector<PlanInverseDynamicsSample> s;
  const PlanTorqueNeed need = CalcPeriodicPlanTorqueNeed(amber, c.l, c.h, 0.1, Params(c.energy, c.eps), np, &s);
  ASSERT_EQ(static_cast<int>(s.size()), np.samples);
  EXPECT_NEAR(need.mean_speed_mps, c.l / need.step_duration_s, 1e-12);
  const double m = Mass(amber), g = 9.81, dt = s[1].time_s - s[0].time_s;
  const ContactInfo& stance = amber.contacts()[amber.ContactIndex("right_foot")];
  Eigen::MatrixXd J(3, nv);
  Eigen::VectorXd rnea(nv);
  double max_tau_residual = 0, max_base_residual = 0, max_force_error = 0, max_v_error = 0, max_tau = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    const PlanInverseDynamicsSample& x = s[i];
    const Eigen::Vector3d foot = CalcPointPosition(amber, ws, x.q, stance.body, stance.frame_origin);
    EXPECT_LT(std::hypot(foot.x(), foot.z()), 1e-9) << "t = " << x.time_s;
    EXPECT_NEAR(x.q[2], s[0].q[2], 1e-9);
    CalcInverseDynamics(amber, ws, x.q, x.v, x.vdot, rnea);
    CalcPointJacobian(amber, ws, x.q, stance.body, stance.frame_origin, J);
    Eigen::VectorXd generalized = rnea - J.row(0).transpose() * x.force.x() - J.row(2).transpose() * x.force.y();
    max_base_residual = std::max(max_base_residual, generalized.head(3).cwiseAbs().maxCoeff());
    for (int k = 0; k < amber.nu(); ++k) {
      const int vi = amber.actuators()[k].v_index;
      max_tau_residual = std::max(max_tau_residual, std::abs(generalized[vi] - x.tau[k]));
      max_tau = std::max(max_tau, std::abs(x.tau[k]));
    }
    if (i == 0 || i + 1 == s.size()) continue;
    // Central differences over neighbouring samples: O(dt²) errors with dt = T̂_s / 400.
    const Eigen::Vector3d a_com =
        (CalcComVelocity(amber, ws, s[i + 1].q, s[i + 1].v) - CalcComVelocity(amber, ws, s[i - 1].q, s[i - 1].v)) /
        (2 * dt);
    max_force_error = std::max(max_force_error, std::abs(m * (a_com.z() + g) - x.force.y()));
    // Horizontally the COM's acceleration is the dynamics' (not the LIP's, which the velocities follow): from q̈.
    Eigen::MatrixXd J_com(3, nv);
    CalcComJacobian(amber, ws, x.q, J_com);
    const double ax = (J_com * x.vdot + CalcComJdotQdot(amber, ws, x.q, x.v)).x();
    max_force_error = std::max(max_force_error, std::abs(m * ax - x.force.x()));
    const Eigen::VectorXd v_fd = (s[i + 1].q - s[i - 1].q) / (2 * dt);
    max_v_error = std::max(max_v_error, (v_fd - x.v).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(max_base_residual, 1e-8);
  EXPECT_LT(max_tau_residual, 1e-8 * std::max(1.0, max_tau));
  // F is about m g = 211 N; the finite-difference error of the spikes (swing knee near straight) stays below 1 %.
  EXPECT_LT(max_force_error, 2.0) << "Newton's law";
  EXPECT_LT(max_v_error, 2e-2) << "velocities against finite differences of the postures";
  // The largest torque reported is the largest over the samples.
  EXPECT_NEAR(need.torque_Nm, max_tau, 1e-9 * max_tau);
  // Weight carried: the mean vertical force over the step is m g plus m times the mean vertical acceleration, which
  // is (ż(T) − ż(0)) / T.
  double fz_mean = 0;
  for (const auto& x : s) fz_mean += x.force.y() / s.size();
  const double vz0 = CalcComVelocity(amber, ws, s.front().q, s.front().v).z();
  const double vz1 = CalcComVelocity(amber, ws, s.back().q, s.back().v).z();
  EXPECT_NEAR(fz_mean, m * g + m * (vz1 - vz0) / (s.back().time_s - s.front().time_s), 0.02 * m * g);
}

INSTANTIATE_TEST_SUITE_P(Amber, PlanTorqueNeedTest,
                         ::testing::Values(Case{0.8, 0.0, 1.5, 0.55}, Case{0.6, -0.1, 1.0, 0.6}));

TEST(PlanTorqueNeed, BadInputIsRefused) {
  const MultibodyModel amber = Amber();
  EXPECT_THROW(CalcPeriodicPlanTorqueNeed(amber, 0.0, 0.0, 0.1, Params(0.5, 0.6)), std::invalid_argument);
  EXPECT_THROW(CalcPeriodicPlanTorqueNeed(amber, 0.4, 0.0, 0.1, Params(0.5, 0.6), {.samples = 0}),
               std::invalid_argument);
  const MultibodyModel cassie =
      MultibodyModel::LoadFromSidecar("robots/cassie_planar/cassie_planar.rome.json", {.euler_floating_base = true});
  EXPECT_THROW(CalcPeriodicPlanTorqueNeed(cassie, 0.4, 0.0, 0.1, Params(0.5, 0.6)), std::invalid_argument);
}

}  // namespace
}  // namespace rome
