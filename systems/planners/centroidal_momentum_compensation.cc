#include "systems/planners/centroidal_momentum_compensation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "systems/multibody/multibody_kinematics.h"

namespace rome {
namespace {

// The 15 coordinates Newton moves: every velocity index but the base angles.
std::vector<int> FreeCoordinates(const MultibodyModel& model) {
  const int yaw = model.VelocityIndex("base_yaw"), pitch = model.VelocityIndex("base_pitch"),
            roll = model.VelocityIndex("base_roll");
  std::vector<int> free;
  for (int i = 0; i < model.nv(); ++i)
    if (i != yaw && i != pitch && i != roll) free.push_back(i);
  return free;
}

}  // namespace

// Tridiagonal system in δ_1 … δ_N (Thomas algorithm): rows k = 1 … N−1 are δ_{k−1} − (2 + h² ω_k²) δ_k + δ_{k+1} =
// −h² a_k (δ_0 = 0); row N is the end condition δ_N + (δ_N − δ_{N−1}) / (h ω_N) = 0 times h ω_N. Diagonally dominant.
Eigen::VectorXd SolveDrivenInvertedPendulum(const Eigen::VectorXd& omega2, const Eigen::VectorXd& a, double h) {
  const Eigen::Index n = a.size();
  if (omega2.size() != n || !(h > 0))
    throw std::invalid_argument("SolveDrivenInvertedPendulum: omega2 has " + std::to_string(omega2.size()) +
                                " samples, a " + std::to_string(n) + ", h = " + std::to_string(h) +
                                " s (sizes must match, h > 0)");
  Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
  if (n < 3) return d;
  const Eigen::Index m = n - 1;  // unknowns δ_1 … δ_N
  Eigen::VectorXd c(m), r(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const Eigen::Index k = i + 1;
    const bool last = k == n - 1;
    const double sub = i == 0 ? 0.0 : (last ? -1.0 : 1.0), super = last ? 0.0 : 1.0;
    const double diag = last ? 1.0 + h * std::sqrt(std::max(omega2[k], 0.0)) : -(2.0 + h * h * omega2[k]);
    const double rhs = last ? 0.0 : -h * h * a[k];
    const double denom = diag - (i > 0 ? sub * c[i - 1] : 0.0);
    c[i] = super / denom;
    r[i] = (rhs - (i > 0 ? sub * r[i - 1] : 0.0)) / denom;
  }
  d[m] = r[m - 1];
  for (Eigen::Index i = m - 2; i >= 0; --i) d[i + 1] = r[i] - c[i] * d[i + 2];
  return d;
}

Eigen::VectorXd SolveWalkingPose(const MultibodyModel& model, const Eigen::Vector3d& com,
                                 const Eigen::Vector3d& left_ankle, const Eigen::Vector3d& right_ankle,
                                 const Eigen::VectorXd& q_guess, double left_pitch, double right_pitch) {
  const int nv = model.nv();
  const std::vector<int> free = FreeCoordinates(model);
  const int n = static_cast<int>(free.size());
  if (n != 15)
    throw std::invalid_argument("SolveWalkingPose: robot '" + model.name() +
                                "' must have 18 velocities (a spatial base and 12 joints), got " + std::to_string(nv));
  const int feet[2] = {model.BodyIndex("left_foot"), model.BodyIndex("right_foot")};
  const Eigen::Vector3d target[2] = {left_ankle, right_ankle};
  const Eigen::Matrix3d R_target_T[2] = {
      Eigen::AngleAxisd(left_pitch, Eigen::Vector3d::UnitY()).toRotationMatrix().transpose(),
      Eigen::AngleAxisd(right_pitch, Eigen::Vector3d::UnitY()).toRotationMatrix().transpose()};
  MultibodyWorkspace ws(model);
  Eigen::VectorXd q = q_guess, res(n), dq(n);
  Eigen::MatrixXd J(n, nv), Jc(3, nv), Jf(6, nv), Jr(n, n);
  for (int it = 0; it < 50; ++it) {
    res.head<3>() = CalcComPosition(model, ws, q) - com;
    CalcComJacobian(model, ws, q, Jc);
    J.topRows(3) = Jc;
    for (int f = 0; f < 2; ++f) {
      const Eigen::Isometry3d X = CalcLinkPose(model, ws, q, feet[f]);
      // Orientation error log(R_targetᵀ R), whose rate near 0 is R_targetᵀ ω (ω world).
      const Eigen::AngleAxisd aa(R_target_T[f] * X.linear());
      res.segment<3>(3 + 6 * f) = X.translation() - target[f];
      res.segment<3>(6 + 6 * f) = aa.angle() * aa.axis();
      CalcFrameJacobian(model, ws, q, feet[f], Eigen::Vector3d::Zero(), Jf);
      J.middleRows(3 + 6 * f, 3) = Jf.bottomRows(3);
      J.middleRows(6 + 6 * f, 3) = R_target_T[f] * Jf.topRows(3);
    }
    if (res.norm() < 1e-10) return q;
    for (int k = 0; k < n; ++k) Jr.col(k) = J.col(free[k]);
    dq = Jr.fullPivLu().solve(-res);
    for (int k = 0; k < n; ++k) q[free[k]] += dq[k];
  }
  throw std::runtime_error("SolveWalkingPose: robot '" + model.name() + "': no pose with the COM at (" +
                           std::to_string(com.x()) + ", " + std::to_string(com.y()) + ", " + std::to_string(com.z()) +
                           ") m and the feet on their targets (residual " + std::to_string(res.norm()) + ")");
}

Eigen::MatrixXd ReplayWalkingPlan(const MultibodyModel& model, const WalkingPlan& plan,
                                  const SwingFootTrajectoryParams& swing, double h, const Eigen::MatrixXd& com_shift) {
  if (!(h > 0 && h <= 0.02))
    throw std::invalid_argument("ReplayWalkingPlan: the sample period must be in (0, 0.02] s, got " +
                                std::to_string(h));
  if (plan.segments().empty()) throw std::invalid_argument("ReplayWalkingPlan: the plan is empty");
  const Eigen::Index N = static_cast<Eigen::Index>(std::floor(plan.end_time() / h + 1e-9));
  if (com_shift.size() != 0 && (com_shift.rows() != 2 || com_shift.cols() != N + 1))
    throw std::invalid_argument("ReplayWalkingPlan: com_shift must be 2 x " + std::to_string(N + 1) + ", got " +
                                std::to_string(com_shift.rows()) + " x " + std::to_string(com_shift.cols()));
  const WalkingOutputReference feet("replay_swing", plan, swing);
  Eigen::MatrixXd q(model.nv(), N + 1);
  const Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(N + 1, 0.0, static_cast<double>(N) * h);
  Eigen::VectorXd guess = model.q_nominal();
  for (Eigen::Index k = 0; k <= N; ++k) {
    const double t = times[k];
    WalkingReference r = plan.Sample(t);
    if (com_shift.size() != 0) r.com_position.head<2>() += com_shift.col(k);
    Eigen::Vector3d p[2], v, a;
    double pitch[2], rate, acceleration;
    for (int f = 0; f < 2; ++f) {
      feet.SwingFoot(f, t, p[f], v, a);
      feet.SwingFootPitch(f, t, &pitch[f], &rate, &acceleration);
      p[f].z() =
          std::max(p[f].z(), swing.ankle_height_m);  // on its foothold after T_SSP (SwingFoot's late-touchdown descent)
    }
    q.col(k) = SolveWalkingPose(model, r.com_position, p[0], p[1], guess, pitch[0], pitch[1]);
    guess = q.col(k);
  }
  return q;
}

CentroidalMomentumCompensationReport CompensateCentroidalMomentum(const MultibodyModel& model, WalkingPlan& plan,
                                                                  const SwingFootTrajectoryParams& swing,
                                                                  const CentroidalMomentumCompensationParams& params) {
  const double h = params.sample_period_s;
  if (!(h > 0 && h <= 0.02))
    throw std::invalid_argument("CompensateCentroidalMomentum: sample_period_s must be in (0, 0.02] s, got " +
                                std::to_string(h));
  if (params.iterations < 1 || params.iterations > 10)
    throw std::invalid_argument("CompensateCentroidalMomentum: iterations must be in [1, 10], got " +
                                std::to_string(params.iterations));
  if (plan.segments().empty()) throw std::invalid_argument("CompensateCentroidalMomentum: the plan is empty");
  const double m = model.total_mass(), g = 9.81;
  const Eigen::Index N = static_cast<Eigen::Index>(std::floor(plan.end_time() / h + 1e-9));
  if (N < 4) throw std::invalid_argument("CompensateCentroidalMomentum: the plan is shorter than 4 samples");
  Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(N + 1, 0.0, N * h);
  MultibodyWorkspace ws(model);
  Eigen::VectorXd omega2(N + 1), z(N + 1), Fz(N + 1);
  std::vector<int> ssp(N + 1);
  Eigen::MatrixXd delta = Eigen::MatrixXd::Zero(2, N + 1);
  CentroidalMomentumCompensationReport report;
  Eigen::MatrixXd q(model.nv(), N + 1), H(3, N + 1), Hdot(3, N + 1);
  for (Eigen::Index k = 0; k <= N; ++k) {
    const WalkingReference r = plan.Sample(times[k]);
    z[k] = r.com_position.z();
    Fz[k] = m * (r.com_acceleration.z() + g);
    omega2[k] = std::max(Fz[k], 1e-3 * m * g) / (m * z[k]);
    ssp[k] = r.domain == WalkingDomain::kDoubleSupport ? 0 : 1;
  }
  for (int round = 0; round <= params.iterations; ++round) {
    q = ReplayWalkingPlan(model, plan, swing, h, delta);  // against the current correction
    for (Eigen::Index k = 0; k <= N; ++k) {
      const Eigen::Index a = std::max<Eigen::Index>(k - 1, 0), b = std::min<Eigen::Index>(k + 1, N);
      const Eigen::VectorXd v = (q.col(b) - q.col(a)) / ((b - a) * h);
      H.col(k) = CalcCentroidalMomentum(model, ws, q.col(k), v).head<3>();
    }
    for (Eigen::Index k = 0; k <= N; ++k) {
      const Eigen::Index a = std::max<Eigen::Index>(k - 1, 0), b = std::min<Eigen::Index>(k + 1, N);
      Hdot.col(k) = (H.col(b) - H.col(a)) / ((b - a) * h);
    }
    // CoP shift the robot needs off the ROM's pivot with this δ: (m z (ω² δ − δ̈) − Ḣ × ẑ) / F_z.
    double shift = 0.0, rate = 0.0;
    for (Eigen::Index k = 1; k < N; ++k) {
      const Eigen::Vector2d dd = (delta.col(k + 1) - 2.0 * delta.col(k) + delta.col(k - 1)) / (h * h);
      const Eigen::Vector2d resid = m * z[k] * (omega2[k] * delta.col(k) - dd);
      const double sx = (resid.x() - Hdot(1, k)) / Fz[k], sy = (resid.y() + Hdot(0, k)) / Fz[k];
      if (ssp[k]) shift = std::max({shift, std::abs(sx), std::abs(sy)});
      rate = std::max({rate, std::abs(Hdot(0, k)), std::abs(Hdot(1, k))});
    }
    if (round == 0) report.max_cop_shift_uncorrected_m = shift;
    report.max_cop_shift_corrected_m = shift;
    report.max_angular_momentum_rate_Nm = rate;
    if (round == params.iterations) break;
    // (C1): δ̈_x = ω² δ_x − Ḣ_y/(m z), δ̈_y = ω² δ_y + Ḣ_x/(m z).
    Eigen::VectorXd ax(N + 1), ay(N + 1);
    for (Eigen::Index k = 0; k <= N; ++k) {
      ax[k] = Hdot(1, k) / (m * z[k]);
      ay[k] = -Hdot(0, k) / (m * z[k]);
    }
    delta.row(0) = SolveDrivenInvertedPendulum(omega2, ax, h).transpose();
    delta.row(1) = SolveDrivenInvertedPendulum(omega2, ay, h).transpose();
  }
  report.max_correction_m = delta.cwiseAbs().maxCoeff();
  Eigen::MatrixXd vel(2, N + 1), acc(2, N + 1);
  for (Eigen::Index k = 0; k <= N; ++k) {
    const Eigen::Index a = std::max<Eigen::Index>(k - 1, 0), b = std::min<Eigen::Index>(k + 1, N);
    vel.col(k) = (delta.col(b) - delta.col(a)) / ((b - a) * h);
    acc.col(k) = k > 0 && k < N ? Eigen::Vector2d((delta.col(k + 1) - 2.0 * delta.col(k) + delta.col(k - 1)) / (h * h))
                                : Eigen::Vector2d::Zero();
  }
  plan.SetComCorrection(PiecewisePolynomial::CubicHermite(times, delta, vel),
                        PiecewisePolynomial::FirstOrderHold(times, acc));
  return report;
}

}  // namespace rome
