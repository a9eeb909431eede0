// ForEachSingleSupportInverseDynamics / CalcWalkingPlanTorques (ours) on gait A's periodic aSLIP plan for the
// exoskeleton. Independent checks of each single-support sample's torques u and stance wrench W:
//  * forward dynamics: the plant's constrained forward dynamics (contact_dynamics.h, stance foot active, no Baumgarte
//    terms) driven by u reproduces the replay's q̈ (central second differences), to the differences' own
//    inconsistency with the contact (J q̈ + J̇ v is O(h²), not 0);
//  * Newton: W's force equals m (p̈_com + g ẑ) with p̈_com the second difference of the replay's COM (a route that
//    never forms M, h or J), to O(h²);
//  * Newton-Euler about the COM: with ḣ_G = A_G q̈ + Ȧ_G v (the centroidal momentum matrix, not M, h or J) the
//    sole's force is ḣ_lin + m g ẑ and its moment about the sole point ḣ_ang + (c − p) × F, so the friction ratio,
//    CoP and torsion peaks of the report follow from the replay alone (equal to rounding: both routes are exact
//    consequences of the same equations of motion);
//  * the report's peaks are the samples' largest |u_j|. (Without the momentum correction gait A's plan asks the knee
//    for more than its 300 N m; the diagram's corrected plan fits, walking_diagram_test.)
#include "systems/planners/walking_plan_inverse_dynamics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/planners/centroidal_momentum_compensation.h"
#include "tests/systems/controllers/amber_test_setup.h"
#include "tests/systems/planners/exoskeleton_gait_a_plan.h"

namespace rome {
namespace {

WalkingPlan GaitAPlan() { return test::ExoskeletonGaitAPlan("rome_plan_inverse_dynamics_test_plans"); }
SwingFootTrajectoryParams ExoSwing() { return test::ExoskeletonSwing(); }

TEST(WalkingPlanInverseDynamics, ForwardDynamicsAndNewtonReproduceTheReplay) {
  auto model = test::LoadRobot("exoskeleton");
  const WalkingPlan plan = GaitAPlan();
  const double h = 2e-3, mg = model->total_mass() * 9.81;
  MultibodyWorkspace ws(*model);
  ConstrainedDynamicsParameters no_baumgarte;
  no_baumgarte.baumgarte_alpha_per_s = 0.0;
  no_baumgarte.baumgarte_beta_per_s = 0.0;
  Eigen::VectorXd qdd(model->nv()), F(model->max_constraint_rows());
  double worst_qdd = 0.0, worst_qdd_scale = 0.0, worst_newton = 0.0;
  int samples = 0;
  ForEachSingleSupportInverseDynamics(
      *model, plan, ExoSwing(), {.sample_period_s = h}, [&](const WalkingPlanInverseDynamicsSample& s) {
        const int contact =
            model->ContactIndex(s.stance_body == model->BodyIndex("left_foot") ? "left_foot" : "right_foot");
        CalcConstrainedForwardDynamics(*model, ws, s.q, s.v, s.u, ContactBit(contact), no_baumgarte, qdd, F);
        worst_qdd = std::max(worst_qdd, (qdd - s.qdd).cwiseAbs().maxCoeff());
        worst_qdd_scale = std::max(worst_qdd_scale, s.qdd.cwiseAbs().maxCoeff());
        // Newton on the COM, by second differences of the replay's COM (q at t ± h from the replay's differences).
        const Eigen::VectorXd q_prev = s.q - h * s.v + 0.5 * h * h * s.qdd,
                              q_next = s.q + h * s.v + 0.5 * h * h * s.qdd;
        const Eigen::Vector3d com_acc = (CalcComPosition(*model, ws, q_next) - 2.0 * CalcComPosition(*model, ws, s.q) +
                                         CalcComPosition(*model, ws, q_prev)) /
                                        (h * h);
        const Eigen::Vector3d newton = model->total_mass() * (com_acc + Eigen::Vector3d(0, 0, 9.81));
        worst_newton = std::max(worst_newton, (s.wrench.tail<3>() - newton).cwiseAbs().maxCoeff());
        ++samples;
      });
  std::printf(
      "  %d single-support samples: forward dynamics q̈ within %.3e of the replay's (largest |q̈| %.1f), Newton within "
      "%.3e N (m g %.0f N)\n",
      samples, worst_qdd, worst_qdd_scale, worst_newton, mg);
  // Every grid point inside a single support but its first and last (whose differences reach across the switch).
  int expected = 0;
  for (const WalkingPlanSegment& seg : plan.segments())
    if (seg.domain != WalkingDomain::kDoubleSupport)
      expected += static_cast<int>(std::floor(seg.duration / h + 1e-9)) - 2;
  EXPECT_GE(samples, expected);
  EXPECT_LE(samples, expected + 2 * static_cast<int>(plan.segments().size()));
  EXPECT_LT(worst_qdd, 2e-5 * worst_qdd_scale);
  EXPECT_LT(worst_newton, 1e-4 * mg);
}

TEST(WalkingPlanInverseDynamics, TorqueReportHoldsTheSamplesPeaks) {
  auto model = test::LoadRobot("exoskeleton");
  const WalkingPlan plan = GaitAPlan();
  Eigen::VectorXd peak = Eigen::VectorXd::Zero(model->nu());
  ForEachSingleSupportInverseDynamics(*model, plan, ExoSwing(), {}, [&](const WalkingPlanInverseDynamicsSample& s) {
    peak = peak.cwiseMax(s.u.cwiseAbs());
  });
  const WalkingPlanTorqueReport r = CalcWalkingPlanTorques(*model, plan, ExoSwing());
  EXPECT_EQ(r.peak_torque_Nm, peak);
  ASSERT_GE(r.worst_actuator, 0);
  const ActuatorInfo& worst = model->actuators()[r.worst_actuator];
  std::printf("  worst: %s %.1f N m of %.1f at t = %.3f s; peak stance F_z %.0f N\n", worst.joint.c_str(),
              r.peak_torque_Nm[r.worst_actuator], worst.torque_limit_Nm, r.peak_time_s[r.worst_actuator],
              r.peak_normal_force_N);
  EXPECT_NEAR(r.worst_limit_fraction, r.peak_torque_Nm[r.worst_actuator] / worst.torque_limit_Nm, 1e-15);
  for (int j = 0; j < model->nu(); ++j)
    EXPECT_LE(r.peak_torque_Nm[j] / model->actuators()[j].torque_limit_Nm, r.worst_limit_fraction);
  EXPECT_GT(r.peak_normal_force_N, model->total_mass() * 9.81);  // the aSLIP's mid-stance force exceeds m g
}

TEST(WalkingPlanInverseDynamics, FrictionCopAndTorsionPeaksFollowNewtonEuler) {
  auto model = test::LoadRobot("exoskeleton");
  const WalkingPlan plan = GaitAPlan();
  const SwingFootTrajectoryParams swing = ExoSwing();
  const double m = model->total_mass();
  MultibodyWorkspace ws(*model);
  Eigen::MatrixXd A_G(6, model->nv());
  double friction = 0, friction_time = 0, torsion = 0;
  Eigen::Vector2d cop = Eigen::Vector2d::Zero();
  ForEachSingleSupportInverseDynamics(*model, plan, swing, {}, [&](const WalkingPlanInverseDynamicsSample& s) {
    CalcCentroidalMomentumMatrix(*model, ws, s.q, A_G);
    const Vector6d hdot = A_G * s.qdd + CalcCentroidalMomentumBias(*model, ws, s.q, s.v);
    const Eigen::Vector3d F = hdot.tail<3>() + Eigen::Vector3d(0, 0, m * 9.81);
    const Eigen::Vector3d p =
        CalcPointPosition(*model, ws, s.q, s.stance_body, Eigen::Vector3d(0, 0, -swing.ankle_height_m));
    const Eigen::Vector3d M = hdot.head<3>() + (CalcComPosition(*model, ws, s.q) - p).cross(F);
    ASSERT_GT(F.z(), 0.0) << "t = " << s.time_s;
    const double ratio = F.head<2>().norm() / F.z();
    if (ratio > friction) friction = ratio, friction_time = s.time_s;
    cop = cop.cwiseMax(Eigen::Vector2d(std::abs(M.y() / F.z()), std::abs(M.x() / F.z())));
    torsion = std::max(torsion, std::abs(M.z() / F.z()));
  });
  const WalkingPlanTorqueReport r = CalcWalkingPlanTorques(*model, plan, swing);
  std::printf(
      "  report: |F_t|/F_n %.4f at %.3f s, CoP %.4f / %.4f m, |M_z|/F_n %.4f m; Newton-Euler: %.4f at %.3f s, %.4f / "
      "%.4f m, %.4f m\n",
      r.peak_friction_ratio, r.peak_friction_ratio_time_s, r.peak_cop_offset_m.x(), r.peak_cop_offset_m.y(),
      r.peak_yaw_moment_ratio_m, friction, friction_time, cop.x(), cop.y(), torsion);
  EXPECT_NEAR(r.peak_friction_ratio, friction, 1e-6);
  EXPECT_NEAR(r.peak_friction_ratio_time_s, friction_time, 1e-12);
  EXPECT_NEAR(r.peak_cop_offset_m.x(), cop.x(), 1e-6);
  EXPECT_NEAR(r.peak_cop_offset_m.y(), cop.y(), 1e-6);
  EXPECT_NEAR(r.peak_yaw_moment_ratio_m, torsion, 1e-6);
  // Gait A walks on μ = 0.8 (walking_diagram_test); its ROM plan, even without the momentum correction, needs less.
  EXPECT_LT(r.peak_friction_ratio, 0.8);
  EXPECT_GT(r.peak_friction_ratio, 0.0);
}

TEST(WalkingPlanInverseDynamics, BadInputIsNamed) {
  auto model = test::LoadRobot("exoskeleton");
  const WalkingPlan plan = GaitAPlan();
  try {
    CalcWalkingPlanTorques(*model, plan, ExoSwing(), {.sample_period_s = 0.0});
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "ForEachSingleSupportInverseDynamics: sample_period_s must be in (0, 0.02] s, got 0.000000");
  }
  EXPECT_THROW(CalcWalkingPlanTorques(*model, WalkingPlan{}, ExoSwing()), std::invalid_argument);
  EXPECT_THROW(CalcWalkingPlanTorques(*model, plan, ExoSwing(), {.end_time_s = std::nan("")}), std::invalid_argument);
  // end_time_s cuts the samples: none after it, and the first single support's alone before its end.
  const WalkingPlanSegment& first_ssp = plan.segments()[1];
  ASSERT_NE(first_ssp.domain, WalkingDomain::kDoubleSupport);
  int after = 0, kept = 0;
  ForEachSingleSupportInverseDynamics(*model, plan, ExoSwing(),
                                      {.end_time_s = first_ssp.start_time + first_ssp.duration},
                                      [&](const WalkingPlanInverseDynamicsSample& s) {
                                        ++kept;
                                        after += s.time_s > first_ssp.start_time + first_ssp.duration ? 1 : 0;
                                      });
  EXPECT_EQ(after, 0);
  EXPECT_EQ(kept, static_cast<int>(std::floor(first_ssp.duration / 2e-3 + 1e-9)) - 2);  // as in the first test
}

}  // namespace
}  // namespace rome
