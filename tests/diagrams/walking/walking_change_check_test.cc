// StandToWalkParams::change_check with WalkingChangeFeasibilityCheck (walking issue 39 §1, §4): a gait change whose
// direct transition asks more torque than the robot has is planned again (a tighter force bound, then the gait graph),
// and the plan it takes fits the torque limits. The walking example's default change, gait A (0.30 m, 0.40 s, 0.10 s,
// 0.25 m) → B (0.40 m, same timing), NLP seed 1, 10 steps of A and 12 of B (as the example plans them).
// Independent check: the joint torques are computed here by the mass-matrix form of the equations of motion,
// M(q) q̈ + C(q, q̇) q̇ + g(q) − τ_spring = B u + J_sᵀ w (CalcMassMatrix, CalcBiasForces: the composite-rigid-body
// algorithm, where the check uses recursive Newton-Euler inverse dynamics), with the stance sole's wrench w, on the
// plan's kinematic replay with the COM correction the diagram tracks (BuildWalkingDiagram's plan):
//  * without the change check, the direct plan's transition single support needs more than an actuator's limit;
//  * with it, the refusal is reported, and every single support up to the run's end fits every actuator's limit.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include <Eigen/LU>

#include "diagrams/walking/walking_diagram.h"
#include "diagrams/walking/walking_robot_check.h"
#include "diagrams/walking/walking_run.h"
#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "tests/common/source_path.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

struct TorquePeak {
  double limit_fraction = 0;  ///< largest |u_j| / limit_j
  std::string joint;
  double time_s = 0;
};

// The largest |u_j| / limit_j over the single supports of `plan` in [from_s, to_s] (transition SSPs only when
// transitions_only), on a 2 ms replay, by M q̈ + h = B u + J_sᵀ w.
TorquePeak PeakTorque(const MultibodyModel& model, const WalkingPlan& plan, double from_s, double to_s,
                      bool transitions_only) {
  const double h = 2e-3;
  SwingFootTrajectoryParams swing = WalkingDiagramParams{}.swing;  // as the diagram: the robot's ankle height
  swing.ankle_height_m = -model.contacts()[model.ContactIndex("left_foot")].points.front().z();
  const Eigen::MatrixXd q = ReplayWalkingPlan(model, plan, swing, h);
  const int nv = model.nv(), nu = model.nu();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(nv, nu + 6), J(6, nv);
  for (int j = 0; j < nu; ++j) A(model.actuators()[j].v_index, j) = 1.0;
  MultibodyWorkspace ws(model);
  TorquePeak peak;
  for (Eigen::Index k = 1; k + 1 < q.cols(); ++k) {
    const double t = static_cast<double>(k) * h;
    if (t < from_s || t > to_s) continue;
    const size_t seg = plan.SegmentIndexAt(t);
    const WalkingPlanSegment& s = plan.segments()[seg];
    if (s.domain == WalkingDomain::kDoubleSupport) continue;
    if (transitions_only && s.lateral_nodes.cols() == 0) continue;
    if (plan.SegmentIndexAt(t - h) != seg || plan.SegmentIndexAt(t + h) != seg) continue;  // no difference across
    const Eigen::VectorXd v = (q.col(k + 1) - q.col(k - 1)) / (2 * h);
    const Eigen::VectorXd qdd = (q.col(k + 1) - 2 * q.col(k) + q.col(k - 1)) / (h * h);
    const Eigen::VectorXd tau = CalcMassMatrix(model, ws, q.col(k)) * qdd + CalcBiasForces(model, ws, q.col(k), v) -
                                CalcSpringTorques(model, ws, q.col(k), v);
    const int foot = model.BodyIndex(s.domain == WalkingDomain::kLeftStance ? "left_foot" : "right_foot");
    CalcFrameJacobian(model, ws, q.col(k), foot, Eigen::Vector3d(0, 0, -swing.ankle_height_m), J);
    A.rightCols(6) = J.transpose();
    const Eigen::VectorXd x = A.fullPivLu().solve(tau);
    EXPECT_LT((A * x - tau).norm(), 1e-6 * (1.0 + tau.norm())) << "t = " << t;
    for (int j = 0; j < nu; ++j) {
      const double f = std::abs(x[j]) / model.actuators()[j].torque_limit_Nm;
      if (f > peak.limit_fraction) peak = {f, model.actuators()[j].joint, t};
    }
  }
  return peak;
}

TEST(WalkingChangeCheck, AChangeBeyondTheTorqueLimitsIsPlannedAgainWithinThem) {
  std::shared_ptr<const MultibodyModel> model = test::LoadRobot("exoskeleton");
  const PlanCache cache(test::TestPlanCacheDir("rome_walking_diagram_test_plans"));
  const WalkingGait a{0.30, 0.40, 0.10, 0.25}, b{0.40, 0.40, 0.10, 0.25};
  const WalkingDiagramParams params;
  StandToWalkParams stand;
  stand.sole = SoleOf(*model, "left_foot");
  stand.plan_check = WalkingPoseCheck(model, params);
  const WalkingRunParams run;

  // Without the check: the direct transition's single support asks more than a joint has.
  WalkingPlanReport direct_report;
  const WalkingPlan direct = BuildGaitChangePlan(a, b, 10, 1, &cache, &direct_report, stand, 12);
  ASSERT_EQ(direct_report.chain.size(), 2u);  // A, B: the direct transition
  const WalkingDiagram d0 = BuildWalkingDiagram(model, direct, params);
  const TorquePeak over = PeakTorque(*model, d0.plan, 0.0, WalkingRunEndTime(d0.plan, run), true);
  std::printf("  direct: the %s needs %.3f of its limit at t = %.3f s\n", over.joint.c_str(), over.limit_fraction,
              over.time_s);
  EXPECT_GT(over.limit_fraction, 1.0);

  // With the check: the refusal is reported and the plan taken fits every limit.
  stand.change_check = WalkingChangeFeasibilityCheck(model, params);
  WalkingPlanReport report;
  const WalkingPlan checked = BuildGaitChangePlan(a, b, 10, 1, &cache, &report, stand, 12);
  ASSERT_FALSE(report.refused_changes.empty());
  EXPECT_NEAR(report.refused_changes.front().from.step_length_m, a.step_length_m, 1e-12);
  EXPECT_NEAR(report.refused_changes.front().to.step_length_m, b.step_length_m, 1e-12);
  EXPECT_NE(report.refused_changes.front().problem.find("N m"), std::string::npos);
  std::printf("  refused: %s; %zu gaits walked from A on\n", report.refused_changes.front().problem.c_str(),
              report.chain.size());
  EXPECT_NEAR(report.chain.front().step_length_m, a.step_length_m, 1e-12);
  EXPECT_NEAR(report.chain.back().step_length_m, b.step_length_m, 1e-12);
  const WalkingDiagram d = BuildWalkingDiagram(model, checked, params);
  const TorquePeak peak = PeakTorque(*model, d.plan, 0.0, WalkingRunEndTime(d.plan, run), false);
  std::printf("  checked: the %s needs %.3f of its limit at t = %.3f s\n", peak.joint.c_str(), peak.limit_fraction,
              peak.time_s);
  EXPECT_LE(peak.limit_fraction, 1.0);
}

}  // namespace
}  // namespace rome
