#include "systems/rom/linear_inverted_pendulum.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace rome {
namespace {

// A root of Eq. (14) at t in (−kRoundingTime, 0) is the starting point itself seen through rounding.
constexpr double kRoundingTime = 1e-12;  // [s]

std::string Num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

}  // namespace

std::string ToString(TimeToImpact::Status status) {
  switch (status) {
    case TimeToImpact::Status::kReached: return "reached";
    case TimeToImpact::Status::kInsufficientEnergy: return "insufficient orbital energy to reach the target";
    case TimeToImpact::Status::kNotReachedForward: return "target is reached only backwards in time";
  }
  return "unknown";
}

LinearInvertedPendulum::LinearInvertedPendulum(LinearInvertedPendulumParams params) : params_(params) {
  if (!(std::isfinite(params_.z0) && params_.z0 > 0)) {
    throw std::invalid_argument("LinearInvertedPendulum: parameter z0 must be a positive height in m, got " +
                                Num(params_.z0));
  }
  if (!(std::isfinite(params_.gravity) && params_.gravity > 0)) {
    throw std::invalid_argument("LinearInvertedPendulum: parameter gravity must be positive in m/s², got " +
                                Num(params_.gravity));
  }
  lambda_ = std::sqrt(params_.gravity / params_.z0);
}

Eigen::Vector2d LinearInvertedPendulum::Derivative(const Eigen::Vector2d& state) const {
  // Eq. (12).
  return Eigen::Vector2d(state[1] / params_.z0, params_.gravity * state[0]);
}

Eigen::Matrix2d LinearInvertedPendulum::TransitionMatrix(double t) const {
  // Eq. (13).
  const double c = std::cosh(lambda_ * t), s = std::sinh(lambda_ * t), lz = lambda_ * params_.z0;
  Eigen::Matrix2d A;
  A << c, s / lz, lz * s, c;
  return A;
}

Eigen::Vector2d LinearInvertedPendulum::Flow(const Eigen::Vector2d& state, double t) const {
  return TransitionMatrix(t) * state;
}

double LinearInvertedPendulum::OrbitalEnergy(const Eigen::Vector2d& state) const {
  // Eq. (16).
  const double xdot = state[1] / params_.z0;
  return xdot * xdot - lambda_ * lambda_ * state[0] * state[0];
}

std::optional<double> LinearInvertedPendulum::MomentumOnOrbit(double orbital_energy, double x) const {
  const double xdot_squared = orbital_energy + lambda_ * lambda_ * x * x;
  if (xdot_squared < 0) return std::nullopt;
  return params_.z0 * std::sqrt(xdot_squared);
}

TimeToImpact LinearInvertedPendulum::TimeToReach(double x_des, const Eigen::Vector2d& state) const {
  const double x0 = state[0];
  if (x0 == x_des) return {TimeToImpact::Status::kReached, 0.0};
  // x(t) = a e^{λt} + b e^{−λt}; with y = e^{λt}: a y² − x_des y + b = 0 (Eq. (14) is one of its roots).
  const double c = state[1] / (lambda_ * params_.z0);
  const double a = 0.5 * (x0 + c), b = 0.5 * (x0 - c);
  const double discriminant = x_des * x_des - x0 * x0 + c * c;  // = x_des² − 4ab = x_des² + E/λ²
  if (discriminant < 0) return {TimeToImpact::Status::kInsufficientEnergy, 0.0};

  double roots[2];
  int num_roots = 0;
  const double scale = std::abs(x0) + std::abs(c);
  const bool on_stable_manifold = std::abs(a) <= std::numeric_limits<double>::epsilon() * scale;
  if (on_stable_manifold) {
    // On the stable manifold: x(t) = b e^{−λt}, so y = b / x_des.
    if (x_des != 0) roots[num_roots++] = b / x_des;
  } else {
    // Numerically stable quadratic roots: q = −(B + sgn(B) sqrt(D)) / 2 with B = −x_des.
    const double B = -x_des;
    const double q = -0.5 * (B + std::copysign(std::sqrt(discriminant), B));
    roots[num_roots++] = q / a;
    if (q != 0) roots[num_roots++] = b / q;
  }
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < num_roots; ++i) {
    if (!(roots[i] > 0)) continue;
    double t = std::log(roots[i]) / lambda_;
    if (t < 0 && t > -kRoundingTime) t = 0;
    if (t >= 0 && t < best) best = t;
  }
  if (!std::isfinite(best)) {
    // E <= 0 (ab >= 0): the COM never crosses the foot; a target on the other side (or at the foot) is out of
    // reach for lack of energy. Otherwise the target was passed (or the COM moves away from it).
    const bool one_sided = on_stable_manifold || a * b >= 0;
    if (one_sided && x_des * x0 <= 0) return {TimeToImpact::Status::kInsufficientEnergy, 0.0};
    return {TimeToImpact::Status::kNotReachedForward, 0.0};
  }
  return {TimeToImpact::Status::kReached, best};
}

double LinearInvertedPendulum::SlopeAdjustedHeight(double p_com_x, double p_com_z, double step_length,
                                                   double step_height) {
  if (!(step_length != 0 && std::isfinite(step_length))) {
    throw std::invalid_argument(
        "LinearInvertedPendulum::SlopeAdjustedHeight: step_length l must be nonzero and finite, got " +
        Num(step_length));
  }
  // Eq. (27): ẑ0 = p^z − (h/l) p^x.
  return p_com_z - step_height / step_length * p_com_x;
}

double LinearInvertedPendulum::ComHeightOnSlope(double x, double z0, double step_length, double step_height) {
  if (!(step_length != 0 && std::isfinite(step_length))) {
    throw std::invalid_argument(
        "LinearInvertedPendulum::ComHeightOnSlope: step_length l must be nonzero and finite, got " + Num(step_length));
  }
  return step_height / step_length * x + z0;
}

}  // namespace rome
