// CheckWalkingPlanFeasibility and SoleWrenchProblem (walking_robot_check.h, ours; walking issue 39 §4). Independent
// checks:
//  * the rigid sole's wrench cone: wrenches built from four corner forces, each inside its friction pyramid, are
//    accepted; the largest torsion four corners can make (every corner at its pyramid's edge, tangent to the sole's
//    centre) is on the cone's boundary, 2 % more is refused; a CoP past the toe and a friction ratio past the pyramid
//    are refused;
//  * the knee torque the check reports for (0.45 m, 0.35 s, 0.08 s, 0.20 m) (over its 300 N m limit) is the torque
//    with which the plant's constrained forward dynamics (contact_dynamics.h, stance foot active) reproduces the
//    plan's acceleration: u found by least squares from the forward dynamics' response to unit torques, never from
//    the inverse dynamics;
//  * the 2 ms grid: the knee's peak on a 1 ms grid is within 1 %;
//  * gait A's plan fits the torque limits (its peak knee torque, 269 N m, is under 300 N m).
#include "diagrams/walking/walking_robot_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "diagrams/walking/walking_diagram.h"
#include "systems/multibody/contact_dynamics.h"
#include "systems/planners/walking_plan_inverse_dynamics.h"
#include "tests/common/source_path.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

using Wrench = Eigen::Matrix<double, 6, 1>;

// The wrench about the sole's centre (foot frame) of corner forces f_i at the rectangle's corners.
Wrench CornerWrench(const SoleRectangle& sole, const Eigen::Matrix<double, 3, 4>& f) {
  const double X = sole.half_length_m, Y = sole.half_width_m;
  const Eigen::Vector3d corners[4] = {{X, Y, 0}, {X, -Y, 0}, {-X, -Y, 0}, {-X, Y, 0}};
  Wrench w = Wrench::Zero();
  for (int i = 0; i < 4; ++i) w.head<3>() += corners[i].cross(f.col(i)), w.tail<3>() += f.col(i);
  return w;
}

TEST(WalkingFeasibility, RigidSoleConeIsWhatFourCornersCanHold) {
  auto model = test::LoadRobot("exoskeleton");
  const SoleRectangle sole = SoleRectangleOf(*model, "left_foot");
  EXPECT_NEAR(2 * sole.half_length_m, 0.25, 1e-12);  // the sidecar's 0.25 x 0.10 m sole
  EXPECT_NEAR(2 * sole.half_width_m, 0.10, 1e-12);
  const WalkingFeasibilityParams params;  // inscribed pyramid: μ' = μ/√2
  const double mup = sole.friction_coefficient / std::sqrt(2.0);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> unit(0.0, 1.0), sym(-1.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    Eigen::Matrix<double, 3, 4> f;
    for (int i = 0; i < 4; ++i) {
      const double fz = 10.0 + 300.0 * unit(rng);
      f.col(i) << 0.999 * mup * fz * sym(rng), 0.999 * mup * fz * sym(rng), fz;
    }
    EXPECT_EQ(SoleWrenchProblem(sole, CornerWrench(sole, f), params), "") << "trial " << trial;
  }
  // The largest torsion: every corner pushes F/4 and pulls sideways at its pyramid's edge, turning about the centre.
  const double F = 700.0, X = sole.half_length_m, Y = sole.half_width_m;
  Eigen::Matrix<double, 3, 4> f;
  const double s[4][2] = {{-1, 1}, {1, 1}, {1, -1}, {-1, -1}};  // (sign f_x, sign f_y) making +τ_z at each corner
  for (int i = 0; i < 4; ++i) f.col(i) << s[i][0] * mup * F / 4, s[i][1] * mup * F / 4, F / 4;
  Wrench w = CornerWrench(sole, f);
  EXPECT_NEAR(w[2], mup * (X + Y) * F, 1e-9);  // four corners' torsion: μ'(X + Y) F
  w[2] *= 0.999;
  EXPECT_EQ(SoleWrenchProblem(sole, w, params), "");
  w[2] *= 1.02 / 0.999;
  EXPECT_NE(SoleWrenchProblem(sole, w, params).find("yaw moment"), std::string::npos);
  // A CoP 1 mm past the toe; a friction ratio 1 % past the pyramid.
  Wrench toe = Wrench::Zero();
  toe << 0, -(X + 1e-3) * F, 0, 0, 0, F;
  EXPECT_NE(SoleWrenchProblem(sole, toe, params).find("CoP"), std::string::npos);
  Wrench slide = Wrench::Zero();
  slide << 0, 0, 0, 1.01 * mup * F, 0, F;
  EXPECT_NE(SoleWrenchProblem(sole, slide, params).find("friction"), std::string::npos);
  Wrench pull = Wrench::Zero();
  pull[5] = -1.0;
  EXPECT_NE(SoleWrenchProblem(sole, pull, params).find("pull"), std::string::npos);
}

// The torque u with which the constrained forward dynamics (stance foot active, no Baumgarte terms) gives q̈ closest
// to `qdd`: q̈(u) is affine in u, so u solves a least-squares problem built from nu + 1 forward-dynamics calls.
Eigen::VectorXd TorqueFromForwardDynamics(const MultibodyModel& model, const WalkingPlanInverseDynamicsSample& s,
                                          int contact) {
  MultibodyWorkspace ws(model);
  ConstrainedDynamicsParameters no_baumgarte;
  no_baumgarte.baumgarte_alpha_per_s = 0.0;
  no_baumgarte.baumgarte_beta_per_s = 0.0;
  Eigen::VectorXd qdd0(model.nv()), qdd(model.nv()), F(model.max_constraint_rows()),
      u = Eigen::VectorXd::Zero(model.nu());
  CalcConstrainedForwardDynamics(model, ws, s.q, s.v, u, ContactBit(contact), no_baumgarte, qdd0, F);
  Eigen::MatrixXd G(model.nv(), model.nu());
  for (int j = 0; j < model.nu(); ++j) {
    u.setZero();
    u[j] = 1.0;
    CalcConstrainedForwardDynamics(model, ws, s.q, s.v, u, ContactBit(contact), no_baumgarte, qdd, F);
    G.col(j) = qdd - qdd0;
  }
  return G.colPivHouseholderQr().solve(s.qdd - qdd0);
}

TEST(WalkingFeasibility, RefusesTheKneeOverItsLimitWithTheTorqueTheForwardDynamicsNeeds) {
  auto model = test::LoadRobot("exoskeleton");
  const PlanCache cache(rome::test::TestPlanCacheDir("rome_walking_feasibility_test_plans"));
  StandToWalkParams stand;
  stand.sole = SoleOf(*model, "left_foot");
  const WalkingDiagramParams params;
  const WalkingGait quick{.step_length_m = 0.45, .ssp_duration_s = 0.35, .dsp_duration_s = 0.08, .step_width_m = 0.20};
  const WalkingDiagram d = BuildWalkingDiagram(model, BuildPeriodicWalkingPlan(quick, 4, 1, &cache, stand), params);
  const WalkingFeasibilityReport r = CheckWalkingPlanFeasibility(*model, d.plan, params);
  std::printf("  (0.45, 0.35, 0.08, 0.20): %s\n  %d samples (%d single support), %.2f s\n", r.problem.c_str(),
              r.samples, r.single_support_samples, r.solve_s);
  // The message: the gait, the joint, its need over its URDF limit, and where in the single support.
  // (sscanf, not std::regex: GCC 12's <regex> warns falsely, -Wmaybe-uninitialized, in the -O1 sanitizer build.)
  const std::string prefix = "gait 0.45,0.35,0.08,0.20: the ";
  ASSERT_EQ(r.problem.rfind(prefix, 0), 0u) << r.problem;
  char side[6] = {};
  int need_Nm = 0, limit_Nm = 0, consumed = 0;
  double at_s = -1.0;
  ASSERT_EQ(std::sscanf(r.problem.c_str() + prefix.size(),
                        "%5[a-z] knee needs %d N m (limit %d N m) at %lf s of single support%n", side, &need_Nm,
                        &limit_Nm, &at_s, &consumed),
            4)
      << r.problem;
  ASSERT_GT(consumed, 0) << r.problem;
  ASSERT_TRUE(std::string(side) == "left" || std::string(side) == "right") << r.problem;
  int knee = -1;
  for (int j = 0; j < model->nu(); ++j)
    if (model->actuators()[j].joint == std::string(side) + "_knee") knee = j;
  ASSERT_GE(knee, 0);
  EXPECT_EQ(limit_Nm, 300);  // exoskeleton.urdf's knee effort
  EXPECT_NEAR(need_Nm, r.peak_torque_Nm[knee], 0.5);
  EXPECT_GT(r.peak_torque_Nm[knee], 300.0);
  EXPECT_GE(at_s, 0.0);
  EXPECT_LE(at_s, quick.ssp_duration_s);
  // The 2 ms grid is dense enough: at 1 ms the knee's peak moves by less than 1 %.
  WalkingFeasibilityParams fine;
  fine.sample_period_s = 1e-3;
  const WalkingFeasibilityReport r1 = CheckWalkingPlanFeasibility(*model, d.plan, params, 1e9, fine);
  std::printf("  knee peak: %.2f N m on the 2 ms grid, %.2f N m on 1 ms\n", r.peak_torque_Nm[knee],
              r1.peak_torque_Nm[knee]);
  EXPECT_NEAR(r1.peak_torque_Nm[knee], r.peak_torque_Nm[knee], 0.01 * r.peak_torque_Nm[knee]);
  // The same torque from the forward dynamics at the peak's sample.
  SwingFootTrajectoryParams swing = params.swing;
  swing.ankle_height_m = 0.08;
  bool found = false;
  ForEachSingleSupportInverseDynamics(*model, d.plan, swing, {}, [&](const WalkingPlanInverseDynamicsSample& s) {
    if (std::abs(s.time_s - r.peak_time_s[knee]) > 1e-9) return;
    found = true;
    const int contact =
        model->ContactIndex(s.stance_body == model->BodyIndex("left_foot") ? "left_foot" : "right_foot");
    const Eigen::VectorXd u = TorqueFromForwardDynamics(*model, s, contact);
    std::printf("  knee at %.3f s: check %.2f N m, forward dynamics %.2f N m\n", s.time_s, r.peak_torque_Nm[knee],
                std::abs(u[knee]));
    EXPECT_NEAR(std::abs(u[knee]), r.peak_torque_Nm[knee], 0.01 * r.peak_torque_Nm[knee]);
  });
  EXPECT_TRUE(found);
}

TEST(WalkingFeasibility, GaitAFitsTheTorqueLimits) {
  auto model = test::LoadRobot("exoskeleton");
  const PlanCache cache(rome::test::TestPlanCacheDir("rome_walking_feasibility_test_plans"));
  StandToWalkParams stand;
  stand.sole = SoleOf(*model, "left_foot");
  const WalkingDiagramParams params;
  const WalkingDiagram d =
      BuildWalkingDiagram(model, BuildPeriodicWalkingPlan(WalkingGait{}, 4, 1, &cache, stand), params);
  WalkingFeasibilityParams torque_only;  // as the walking example's default (the header says why)
  torque_only.enforce_sole_wrench = torque_only.enforce_joint_limits = false;
  const WalkingFeasibilityReport r = CheckWalkingPlanFeasibility(*model, d.plan, params, 1e9, torque_only);
  EXPECT_EQ(r.problem, "");
  EXPECT_EQ(r.torque_problem, "");
  EXPECT_GT(r.single_support_samples, 4 * 0.38 / 2e-3);
}

}  // namespace
}  // namespace rome
