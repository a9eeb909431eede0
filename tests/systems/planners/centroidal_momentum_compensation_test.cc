// CompensateCentroidalMomentum (ours): the COM correction δ of (C1) that lets the horizontal ground force, not the
// CoP, carry the legs' centroidal angular momentum. Checks:
//  * SolveDrivenInvertedPendulum against the closed form of δ̈ = ω² δ − A sin(Ω t) with δ(0) = 0 and the bounded end
//    δ(T) + δ̇(T)/ω = 0: δ = A sin(Ω t)/(Ω² + ω²) + c₁ e^{ω t} + c₂ e^{−ω t}, c₁, c₂ from the two end conditions; the
//    discrete end condition is first order in h, so the error falls at least by 2 when h halves.
//  * On gait A of the exoskeleton (a periodic plan), an independent route to the CoP: inverse dynamics of the replayed
//    motion (M q̈ + h = B u + Jᵀ W, q̈ by second differences of the poses, W the stance sole's wrench) gives the CoP the
//    robot needs; with the correction it stays within 2.5 cm of the point-mass ROM's own CoP in single support, without
//    it it leaves the sole (more than 10 cm off). The correction itself stays below 3 cm.
#include "systems/planners/centroidal_momentum_compensation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/planners/aslip_periodic_gait_planner.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

TEST(CentroidalMomentumCompensation, DrivenInvertedPendulumMatchesItsClosedForm) {
  const double omega2 = 10.9, Omega = 2 * M_PI / 0.5, A = 1.7, T = 2.0;  // four periods: sin(Ω T) = 0
  double previous_error = 0.0;
  for (const int N : {1000, 2000}) {
    const double h = T / N;
    const double w0 = std::sqrt(omega2), P = A / (Omega * Omega + omega2);
    // δ(0) = 0: c₂ = −c₁. End: δ(T) + δ̇(T)/ω = P (sin ΩT + Ω cos ΩT / ω) + 2 c₁ e^{ωT} = 0.
    const double c1 = -P * (std::sin(Omega * T) + Omega * std::cos(Omega * T) / w0) / (2.0 * std::exp(w0 * T));
    Eigen::VectorXd w = Eigen::VectorXd::Constant(N + 1, omega2), a(N + 1), exact(N + 1);
    for (int k = 0; k <= N; ++k) {
      const double t = k * h;
      a[k] = A * std::sin(Omega * t);
      exact[k] = P * std::sin(Omega * t) + c1 * (std::exp(w0 * t) - std::exp(-w0 * t));
    }
    const double error = (SolveDrivenInvertedPendulum(w, a, h) - exact).cwiseAbs().maxCoeff();
    std::printf("  N = %d: max error %.3e m (amplitude %.3e m, end value %.3e m)\n", N, error, P, exact[N]);
    EXPECT_LT(error, 2e-2 * P);
    if (N == 2000) {
      EXPECT_GT(previous_error / error, 1.9);  // converges (first order at the end, second inside)
    }
    previous_error = error;
  }
  EXPECT_THROW(SolveDrivenInvertedPendulum(Eigen::VectorXd::Ones(3), Eigen::VectorXd::Ones(4), 0.01), std::invalid_argument);
}

// The largest |robot CoP − ROM CoP| (x, y) in single support: the robot's by inverse dynamics of `plan`'s kinematic
// replay, the point mass's of `rom` (its CoP p − z p̈_xy / (z̈ + g): the stance ankle for the aSLIP in x; in y the H-LIP's
// constant-height flow puts it off the ankle by up to ~3 cm, the approximation the paper leaves to the ankle roll).
double LargestCopOffsetByInverseDynamics(const MultibodyModel& model, const WalkingPlan& plan, const WalkingPlan& rom,
                                         const SwingFootTrajectoryParams& swing) {
  const WalkingOutputReference feet("feet", plan, swing);
  MultibodyWorkspace ws(model);
  const int nv = model.nv(), nu = model.nu();
  const double h = 2e-3;
  const int N = static_cast<int>(plan.end_time() / h);
  std::vector<Eigen::VectorXd> q(N + 1);
  Eigen::VectorXd guess = model.q_nominal();
  for (int k = 0; k <= N; ++k) {
    const WalkingReference r = plan.Sample(k * h);
    Eigen::Vector3d p[2], v, a;
    for (int f = 0; f < 2; ++f) {
      feet.SwingFoot(f, k * h, p[f], v, a);
      p[f].z() = std::max(p[f].z(), swing.ankle_height_m);
    }
    q[k] = guess = SolveWalkingPose(model, r.com_position, p[0], p[1], guess);
  }
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(nv, nu), A(nv, nv), J(6, nv);
  for (int j = 0; j < nu; ++j) B(model.actuators()[j].v_index, j) = 1.0;
  Eigen::VectorXd tau(nv);
  double worst = 0.0;
  for (int k = 1; k < N; ++k) {
    const WalkingReference r = plan.Sample(k * h);
    if (r.domain == WalkingDomain::kDoubleSupport) continue;
    // Skip the samples whose second difference straddles a domain switch.
    if (plan.Sample((k - 1) * h).domain != r.domain || plan.Sample((k + 1) * h).domain != r.domain) continue;
    const Eigen::VectorXd v = (q[k + 1] - q[k - 1]) / (2 * h), qdd = (q[k + 1] - 2 * q[k] + q[k - 1]) / (h * h);
    CalcInverseDynamics(model, ws, q[k], v, qdd, tau);
    const int foot = model.BodyIndex(r.domain == WalkingDomain::kLeftStance ? "left_foot" : "right_foot");
    CalcFrameJacobian(model, ws, q[k], foot, Eigen::Vector3d(0, 0, -swing.ankle_height_m), J);  // the sole point below the ankle
    A << B, J.transpose();
    const Eigen::VectorXd x = A.fullPivLu().solve(tau);
    const Eigen::Vector3d M = x.segment<3>(nu), F = x.segment<3>(nu + 3);
    EXPECT_GT(F.z(), 0.0);
    const Eigen::Vector2d robot_cop = CalcLinkPose(model, ws, q[k], foot).translation().head<2>() + Eigen::Vector2d(-M.y() / F.z(), M.x() / F.z());
    const WalkingReference p = rom.Sample(k * h);
    const Eigen::Vector2d rom_cop = p.com_position.head<2>() - p.com_position.z() * p.com_acceleration.head<2>() / (p.com_acceleration.z() + 9.81);
    worst = std::max(worst, (robot_cop - rom_cop).cwiseAbs().maxCoeff());
  }
  return worst;
}

TEST(CentroidalMomentumCompensation, KeepsTheRobotsCopOnTheRomPivotByInverseDynamics) {
  auto model = test::LoadRobot("exoskeleton");
  AslipPeriodicGaitParams gp;  // gait A: l = 0.3 m, T_SSP = 0.4 s, T_DSP = 0.1 s
  gp.height_min = 0.84;
  gp.height_max = 0.90;
  const AslipPeriodicGaitPlanner planner(gp);
  const PlanCache cache((std::filesystem::temp_directory_path() / "rome_compensation_test_plans").string());
  const AslipPeriodicGait gait = planner.Solve(1, &cache);
  ASSERT_TRUE(gait.success());
  WalkingPlan plan;
  plan.AppendPeriodicSteps(planner, gait, 3, WalkingDomain::kLeftStance, 0.0, 0.25, /*begin_with_double_support=*/true);
  SwingFootTrajectoryParams swing;
  swing.ankle_height_m = 0.08;  // the exoskeleton's sole is 0.08 m below the ankle
  const double before = LargestCopOffsetByInverseDynamics(*model, plan, plan, swing);
  WalkingPlan corrected = plan;
  const CentroidalMomentumCompensationReport report = CompensateCentroidalMomentum(*model, corrected, swing);
  const double after = LargestCopOffsetByInverseDynamics(*model, corrected, plan, swing);
  std::printf("  CoP off the pivot by inverse dynamics: %.4f m uncorrected, %.4f m corrected; report %.4f -> %.4f m; |delta| <= %.4f m\n", before,
              after, report.max_cop_shift_uncorrected_m, report.max_cop_shift_corrected_m, report.max_correction_m);
  EXPECT_GT(before, 0.10);
  EXPECT_LT(after, 0.025);  // measured 0.0216 m (the centroidal estimate of the report says 0.0066 m; the gap is not explained yet)
  EXPECT_LT(report.max_correction_m, 0.03);
  EXPECT_TRUE(corrected.has_com_correction());
  EXPECT_LT((corrected.Sample(0.0).com_position - plan.Sample(0.0).com_position).norm(), 1e-12);  // δ(0) = 0
  EXPECT_THROW(CompensateCentroidalMomentum(*model, corrected, swing, {.sample_period_s = 0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace rome
