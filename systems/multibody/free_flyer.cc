#include "systems/multibody/free_flyer.h"

#include <cmath>

namespace rome {

namespace {

// Below this rotation angle (rad) the coefficients of V and V^-1 use their Taylor series (ours: the next term is
// below 1e-16 there, and the closed forms lose no more than ~1e-11 relative above it).
constexpr double kSeriesAngle_rad = 1e-2;
// Below this |vector part| of a quaternion, Log uses 2 / w (the error is of order |vec|^2 relative).
constexpr double kSmallQuaternionVector = 1e-8;

Eigen::Quaterniond QuaternionOf(const Vector7d& q) { return Eigen::Quaterniond(q[3], q[4], q[5], q[6]); }

void StoreQuaternion(const Eigen::Quaterniond& R, Vector7d* q) {
  (*q)[3] = R.w();
  (*q)[4] = R.x();
  (*q)[5] = R.y();
  (*q)[6] = R.z();
}

}  // namespace

bool FreeFlyerRotation(const Vector7d& q_base, Eigen::Quaterniond* R) {
  const Eigen::Quaterniond quat = QuaternionOf(q_base);
  const double n = quat.norm();
  if (!std::isfinite(n) || !(n > 0.0)) return false;
  *R = Eigen::Quaterniond(quat.coeffs() / n);
  return true;
}

Eigen::Quaterniond QuaternionExp(const Eigen::Vector3d& w) {
  const double t = w.norm();
  // sin(t / 2) / t, by its series near 0.
  const double s = t < kSeriesAngle_rad ? 0.5 - t * t / 48.0 : std::sin(0.5 * t) / t;
  Eigen::Quaterniond q;
  q.w() = std::cos(0.5 * t);
  q.vec() = s * w;
  return q;
}

Eigen::Vector3d QuaternionLog(const Eigen::Quaterniond& q_in) {
  // q and -q are one rotation: take w >= 0 for the shortest angle.
  const Eigen::Quaterniond q = q_in.w() < 0.0 ? Eigen::Quaterniond(-q_in.coeffs()) : q_in;
  const double s = q.vec().norm();
  const double scale = s < kSmallQuaternionVector ? 2.0 / q.w() : 2.0 * std::atan2(s, q.w()) / s;
  return scale * q.vec();
}

Eigen::Vector3d Se3LeftJacobianTimes(const Eigen::Vector3d& w, const Eigen::Vector3d& u) {
  const double t2 = w.squaredNorm(), t = std::sqrt(t2);
  double a, b;
  if (t < kSeriesAngle_rad) {
    a = 0.5 - t2 / 24.0 + t2 * t2 / 720.0;
    b = 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0;
  } else {
    const double sh = std::sin(0.5 * t);
    a = 2.0 * sh * sh / t2;  // (1 - cos t) / t^2 without cancellation
    b = (t - std::sin(t)) / (t2 * t);
  }
  const Eigen::Vector3d wu = w.cross(u);
  return u + a * wu + b * w.cross(wu);
}

Eigen::Vector3d Se3LeftJacobianInverseTimes(const Eigen::Vector3d& w, const Eigen::Vector3d& u) {
  const double t2 = w.squaredNorm(), t = std::sqrt(t2);
  double c;  // (1 - (t / 2) cot(t / 2)) / t^2
  if (t < kSeriesAngle_rad) {
    c = 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0;
  } else {
    c = (1.0 - 0.5 * t * std::cos(0.5 * t) / std::sin(0.5 * t)) / t2;
  }
  const Eigen::Vector3d wu = w.cross(u);
  return u - 0.5 * wu + c * w.cross(wu);
}

Vector7d FreeFlyerIntegrate(const Vector7d& q_base, const FreeFlyerTwist& xi) {
  Eigen::Quaterniond R = Eigen::Quaterniond::Identity();
  FreeFlyerRotation(q_base, &R);
  const Eigen::Vector3d v = xi.head<3>(), w = xi.tail<3>();
  Vector7d out;
  out.head<3>() = q_base.head<3>() + R * Se3LeftJacobianTimes(w, v);
  StoreQuaternion((R * QuaternionExp(w)).normalized(), &out);
  return out;
}

FreeFlyerTwist FreeFlyerDifference(const Vector7d& q0, const Vector7d& q1) {
  Eigen::Quaterniond R0 = Eigen::Quaterniond::Identity(), R1 = Eigen::Quaterniond::Identity();
  FreeFlyerRotation(q0, &R0);
  FreeFlyerRotation(q1, &R1);
  FreeFlyerTwist xi;
  const Eigen::Vector3d w = QuaternionLog(R0.conjugate() * R1);
  xi.tail<3>() = w;
  xi.head<3>() = Se3LeftJacobianInverseTimes(w, R0.conjugate() * (q1.head<3>() - q0.head<3>()));
  return xi;
}

Vector7d MapFreeFlyerVelocityToQDot(const Vector7d& q_base, const FreeFlyerTwist& v_base) {
  const Eigen::Quaterniond quat = QuaternionOf(q_base);
  Eigen::Quaterniond w_pure;
  w_pure.w() = 0.0;
  w_pure.vec() = v_base.tail<3>();
  const Eigen::Quaterniond dquat = quat * w_pure;
  Vector7d out;
  out.head<3>() = quat.normalized().toRotationMatrix() * v_base.head<3>();
  out[3] = 0.5 * dquat.w();
  out.segment<3>(4) = 0.5 * dquat.vec();
  return out;
}

Vector7d FreeFlyerFromEuler(const Eigen::Matrix<double, 6, 1>& q_euler) {
  const Eigen::Quaterniond R = Eigen::AngleAxisd(q_euler[3], Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(q_euler[4], Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(q_euler[5], Eigen::Vector3d::UnitX());
  Vector7d out;
  out.head<3>() = q_euler.head<3>();
  StoreQuaternion(R.w() < 0.0 ? Eigen::Quaterniond(-R.coeffs()) : R, &out);
  return out;
}

}  // namespace rome
