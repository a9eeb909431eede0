// CompensateCentroidalMomentum (ours): the COM correction δ of (C1) that lets the horizontal ground force, not the
// CoP, carry the legs' centroidal angular momentum. Checks:
//  * SolveDrivenInvertedPendulum against the closed form of δ̈ = ω² δ − A sin(Ω t) with δ(0) = 0 and the bounded end
//    δ(T) + δ̇(T)/ω = 0: δ = A sin(Ω t)/(Ω² + ω²) + c₁ e^{ω t} + c₂ e^{−ω t}, c₁, c₂ from the two end conditions; the
//    discrete end condition is first order in h, so the error falls at least by 2 when h halves.
//  * On gait A of the exoskeleton (a periodic plan), an independent route to the CoP: inverse dynamics of the replayed
//    motion (ForEachSingleSupportInverseDynamics: M q̈ + h = B u + Jᵀ W, q̈ by second differences of the poses, W the
//    stance sole's wrench; walking_plan_inverse_dynamics_test checks it against forward dynamics) gives the CoP the
//    robot needs; with the correction it stays within 2.5 cm of the point-mass ROM's own CoP in single support, without
//    it it leaves the sole (more than 10 cm off). The correction itself stays below 3 cm.
//  * SolveWalkingPose with a toe-down foot pitch: by forward kinematics the pitched foot's rotation is the pure pitch
//    R_y(θ) (R(0,2) = sin θ, R(0,0) = cos θ, no roll or yaw), its ankle and the COM on their targets, the other foot
//    flat; and the pitched foot's ankle joint bends toward plantarflexion (the purpose of the swing pitch).
#include "systems/planners/centroidal_momentum_compensation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/planners/walking_plan_inverse_dynamics.h"
#include "tests/systems/controllers/amber_test_setup.h"
#include "tests/systems/planners/exoskeleton_gait_a_plan.h"

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
  EXPECT_THROW(SolveDrivenInvertedPendulum(Eigen::VectorXd::Ones(3), Eigen::VectorXd::Ones(4), 0.01),
               std::invalid_argument);
}

// The largest |robot CoP − ROM CoP| in single support: the robot's by inverse dynamics of `plan`'s kinematic replay,
// the point mass's of `rom`, p − z p̈_xy / (z̈ + g) (the stance ankle for the aSLIP in x; in y the H-LIP's
// constant-height flow puts it off the ankle by up to ~3 cm, the approximation the paper leaves to the ankle roll).
// `plan_acceleration`: max over x and y with p̈ the plan's own com_acceleration (what the controller feeds forward:
// a first-order hold of the collocation's node accelerations); `x_from_positions` / `y_from_positions`: with p̈ the
// second difference of the plan's COM positions (a cubic Hermite of the nodes), the acceleration the replay has.
struct CopOffsets {
  double plan_acceleration = 0, x_from_positions = 0, y_from_positions = 0;
  double z_acceleration_mismatch = 0;  ///< [m/s²] largest |plan z̈ − second difference of the plan's z|
};
CopOffsets LargestCopOffsetByInverseDynamics(const MultibodyModel& model, const WalkingPlan& plan,
                                             const WalkingPlan& rom, const SwingFootTrajectoryParams& swing) {
  MultibodyWorkspace ws(model);
  CopOffsets worst;
  const double h = 2e-3;
  ForEachSingleSupportInverseDynamics(
      model, plan, swing, {.sample_period_s = h}, [&](const WalkingPlanInverseDynamicsSample& s) {
        const Eigen::Vector3d M = s.wrench.head<3>(), F = s.wrench.tail<3>();
        EXPECT_GT(F.z(), 0.0);
        const Eigen::Vector2d robot_cop = CalcLinkPose(model, ws, s.q, s.stance_body).translation().head<2>() +
                                          Eigen::Vector2d(-M.y() / F.z(), M.x() / F.z());
        const WalkingReference p = rom.Sample(s.time_s);
        auto cop = [&](const Eigen::Vector3d& acc) {
          return Eigen::Vector2d(p.com_position.head<2>() - p.com_position.z() * acc.head<2>() / (acc.z() + 9.81));
        };
        const Eigen::Vector3d from_positions =
            (rom.Sample(s.time_s + h).com_position - 2.0 * p.com_position + rom.Sample(s.time_s - h).com_position) /
            (h * h);
        worst.plan_acceleration =
            std::max(worst.plan_acceleration, (robot_cop - cop(p.com_acceleration)).cwiseAbs().maxCoeff());
        worst.z_acceleration_mismatch =
            std::max(worst.z_acceleration_mismatch, std::abs(p.com_acceleration.z() - from_positions.z()));
        const Eigen::Vector2d off = (robot_cop - cop(from_positions)).cwiseAbs();
        worst.x_from_positions = std::max(worst.x_from_positions, off.x());
        worst.y_from_positions = std::max(worst.y_from_positions, off.y());
      });
  return worst;
}

TEST(CentroidalMomentumCompensation, WalkingPoseTakesAFootPitchAboutTheWorldYAxis) {
  auto model = test::LoadRobot("exoskeleton");
  const Eigen::Vector3d com(0.05, 0.0, 0.86), left(0.0, 0.125, 0.08), right(0.2, -0.125, 0.14);
  const Eigen::VectorXd flat = SolveWalkingPose(*model, com, left, right, model->q_nominal());
  const double pitch = 0.3;
  const Eigen::VectorXd q = SolveWalkingPose(*model, com, left, right, flat, 0.0, pitch);
  MultibodyWorkspace ws(*model);
  const Eigen::Isometry3d X = CalcLinkPose(*model, ws, q, model->BodyIndex("right_foot"));
  EXPECT_NEAR(X.linear()(0, 0), std::cos(pitch), 1e-9);
  EXPECT_NEAR(X.linear()(0, 2), std::sin(pitch), 1e-9);  // toe (x) down: R_y(θ) x = (cos θ, 0, −sin θ)
  EXPECT_NEAR(X.linear()(2, 0), -std::sin(pitch), 1e-9);
  EXPECT_NEAR(X.linear()(1, 1), 1.0, 1e-9);
  EXPECT_LT((X.translation() - right).norm(), 1e-9);
  EXPECT_LT((CalcComPosition(*model, ws, q) - com).norm(), 1e-9);
  const Eigen::Isometry3d L = CalcLinkPose(*model, ws, q, model->BodyIndex("left_foot"));
  EXPECT_LT((L.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  const int ankle = model->VelocityIndex("right_ankle_pitch");
  EXPECT_GT(q[ankle] - flat[ankle], 0.2);  // most of the pitch is taken by the ankle (the COM moves the rest)
}

TEST(CentroidalMomentumCompensation, KeepsTheRobotsCopOnTheRomPivotByInverseDynamics) {
  auto model = test::LoadRobot("exoskeleton");
  const WalkingPlan plan = test::ExoskeletonGaitAPlan("rome_compensation_test_plans");  // gait A, three steps
  const SwingFootTrajectoryParams swing = test::ExoskeletonSwing();
  const CopOffsets before = LargestCopOffsetByInverseDynamics(*model, plan, plan, swing);
  WalkingPlan corrected = plan;
  const CentroidalMomentumCompensationReport report = CompensateCentroidalMomentum(*model, corrected, swing);
  const CopOffsets after = LargestCopOffsetByInverseDynamics(*model, corrected, plan, swing);
  std::printf(
      "  CoP off the pivot by inverse dynamics: %.4f m uncorrected, %.4f m corrected; report %.4f -> %.4f m; |delta| "
      "<= %.4f m\n",
      before.plan_acceleration, after.plan_acceleration, report.max_cop_shift_uncorrected_m,
      report.max_cop_shift_corrected_m, report.max_correction_m);
  std::printf(
      "  corrected, with the plan positions' own second differences: x %.4f m, y %.5f m (plan z acceleration off its "
      "positions' by up to %.2f m/s^2)\n",
      after.x_from_positions, after.y_from_positions, after.z_acceleration_mismatch);
  EXPECT_GT(before.plan_acceleration, 0.10);
  EXPECT_LT(after.plan_acceleration, 0.025);  // measured 0.0216 m, in y: see below
  // The report's estimate (0.0070 m) and the inverse dynamics' 2.1 cm differ by the plan's interpolation, not the
  // physics: the plan's z acceleration (first-order hold of the trapezoidal collocation's nodes, 20 ms apart) differs
  // from its position spline's second derivative by up to 0.66 m/s², which moves the ROM's y CoP by up to 2.2 cm. With
  // the positions' own second differences y agrees to 1.7 mm; x stays near the report's 0.6 cm but for the first
  // sample of each single support (2.0 cm) and ~1 cm at the nodes, where the C1 spline's second derivative jumps.
  EXPECT_LT(after.y_from_positions, 0.003);
  EXPECT_GT(after.z_acceleration_mismatch, 0.3);  // the interpolants' disagreement is what the analytic route sees
  EXPECT_LT(after.x_from_positions, 0.025);
  EXPECT_LT(report.max_correction_m, 0.03);
  EXPECT_TRUE(corrected.has_com_correction());
  EXPECT_LT((corrected.Sample(0.0).com_position - plan.Sample(0.0).com_position).norm(), 1e-12);  // δ(0) = 0
  EXPECT_THROW(CompensateCentroidalMomentum(*model, corrected, swing, {.sample_period_s = 0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace rome
