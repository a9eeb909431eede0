#pragma once
// LinearInvertedPendulum: the passive (point-foot, no ankle torque) LIP in momentum form, Sec. III of the
// stepping-stones paper (Xiong & Ames, "Dynamic and versatile walking on stepping stones via momentum
// regulation"). Pure math: no framework dependency.
//
// Conventions (planar sagittal x-z, used by every ROME stepping-stones block):
//   x forward, z up, g = 9.81 m/s². The state is relative to the stance foot (pivot):
//   x [m]      forward COM position p_com^x relative to the stance foot,
//   L [m²/s]   y-component of the MASS-NORMALISED angular momentum about the stance foot, Eq. (7):
//              L = p^z ṗ^x − p^x ṗ^z + L_com. With this sign convention forward walking (ṗ^x > 0) has L > 0 and
//              gravity increases L when the COM is ahead of the foot: L̇ = g x.
//   z0 [m]     height of the COM above the line through the footholds (the "virtual slope", Fig. 1). On a
//              slope of angle α = atan(h/l) the COM height relative to the stance foot is z = tan(α) x + z0
//              and L = z ẋ − x ż = z0 ẋ, so the dynamics do not depend on α.
//
// Equations:
//   Eq. (12)  ẋ = L / z0,  L̇ = g x                               (λ = sqrt(g / z0), Eq. (11))
//   Eq. (13)  [x(t); L(t)] = A(t, z0) [x(0); L(0)],
//             A = [cosh(λt), sinh(λt)/(λ z0); λ z0 sinh(λt), cosh(λt)]
//   Eq. (14)-(15) time-to-impact T_I(x_des, z0, x(0), L(0)): the first t >= 0 with x(t) = x_des.
//             Writing x(t) = a e^{λt} + b e^{−λt}, a = (x0 + L0/(λz0))/2, b = (x0 − L0/(λz0))/2, y = e^{λt}
//             solves a y² − x_des y + b = 0; Eq. (14) is the root y = (x_des + sqrt(x_des² − x0² +
//             L0²/(λz0)²)) / (x0 + L0/(λz0)), which is the only admissible root in forward walking (x0 < 0 <
//             x_des, E > 0). We take the smallest root y >= 1 of both, so the answer is also right when the
//             COM starts ahead of the foot, moves backwards, or is on the stable manifold (a = 0).
//   Eq. (16)  orbital energy E = ẋ² − λ² x² [m²/s²], conserved by the flow.
//   Slope (Sec. III and Eq. (27)): ẑ0 = p^z − (h/l) p^x, the COM height above the line of slope h/l through
//             the stance foot; COM height on that line: z(x) = (h/l) x + z0.

#include <optional>
#include <string>

#include <Eigen/Core>

namespace rome {

struct LinearInvertedPendulumParams {
  double z0 = 0.8;        ///< [m] COM height above the virtual slope (AMBER-like default; the paper gives none).
  double gravity = 9.81;  ///< [m/s²] used throughout ROME.
};

/// Result of the time-to-impact function Eq. (14)-(15).
struct TimeToImpact {
  enum class Status {
    kReached,             ///< time_s >= 0 is the first time at which x(t) = x_des.
    kInsufficientEnergy,  ///< E < 0 and the orbit turns around before x_des (x_des² + E/λ² < 0, no real root)
                          ///< or x_des lies across the foot from the COM, which never crosses it.
    kNotReachedForward,   ///< x_des is on the COM's orbit but only at t < 0 (already passed, or moving away).
  };
  Status status = Status::kReached;
  double time_s = 0.0;  ///< [s] valid only if status == kReached.
  bool ok() const { return status == Status::kReached; }
  /// The time as an optional: empty when there is no solution t >= 0.
  std::optional<double> time() const { return ok() ? std::optional<double>(time_s) : std::nullopt; }
};

std::string ToString(TimeToImpact::Status status);

class LinearInvertedPendulum {
 public:
  /// Throws std::invalid_argument naming the parameter if z0 <= 0 or gravity <= 0 (or not finite).
  explicit LinearInvertedPendulum(LinearInvertedPendulumParams params = {});

  const LinearInvertedPendulumParams& params() const { return params_; }
  double z0() const { return params_.z0; }
  double gravity() const { return params_.gravity; }
  /// λ = sqrt(g / z0) [1/s], Eq. (11).
  double lambda() const { return lambda_; }

  /// Eq. (12): time derivative of the state [x, L].
  Eigen::Vector2d Derivative(const Eigen::Vector2d& state) const;
  /// Eq. (13): A(t, z0).
  Eigen::Matrix2d TransitionMatrix(double t) const;
  /// Eq. (13): state after flowing for time t (t may be negative).
  Eigen::Vector2d Flow(const Eigen::Vector2d& state, double t) const;
  /// Eq. (14)-(15): first time t >= 0 at which x(t) = x_des, from `state` = [x(0), L(0)].
  TimeToImpact TimeToReach(double x_des, const Eigen::Vector2d& state) const;
  /// Eq. (16): E = ẋ² − λ² x² with ẋ = L / z0 [m²/s²].
  double OrbitalEnergy(const Eigen::Vector2d& state) const;
  /// Forward velocity ẋ = L / z0 [m/s].
  double ForwardVelocity(double L) const { return L / params_.z0; }
  /// Angular momentum L > 0 on the orbit of energy E at position x (forward branch), or nullopt if
  /// E + λ² x² < 0 (that orbit never passes through x). Inverse of Eq. (16).
  std::optional<double> MomentumOnOrbit(double orbital_energy, double x) const;

  /// Slope-adjusted z0 of Eq. (27): height of the COM (p_com_x, p_com_z, relative to the stance foot) above
  /// the line of slope h/l through the stance foot. Throws std::invalid_argument if l == 0.
  static double SlopeAdjustedHeight(double p_com_x, double p_com_z, double step_length, double step_height);
  /// COM height relative to the stance foot on the virtual slope: z(x) = (h/l) x + z0.
  static double ComHeightOnSlope(double x, double z0, double step_length, double step_height);

 private:
  LinearInvertedPendulumParams params_;
  double lambda_;
};

}  // namespace rome
