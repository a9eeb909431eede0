#pragma once
// BouncingBall: a point mass falling under gravity onto flat ground, with a restitution impact.
//
// outputs: state (2) = [height (m), vertical velocity (m/s)]
// flow:    ḣ = v, v̇ = −g
// guard:   "ground_contact", h crosses 0 falling
// reset:   v⁺ = −e v⁻  (Newton restitution; e in [0, 1])
// Closed form from rest at h0: t1 = sqrt(2 h0 / g), t_{k+1} = t_k + 2 e^k sqrt(2 g h0) / g.
// With e < 1 the impact times accumulate (Zeno) at t1 (1 + e) / (1 − e) — the simulator's EventPolicy
// stops such a run with a clear status.

#include <vector>

#include "framework/system.h"

namespace rome {

struct BouncingBallParams {
  double restitution = 0.8;       ///< [-] coefficient of restitution e.
  double gravity = 9.81;          ///< [m/s²] used throughout ROME.
  double initial_height = 1.0;    ///< [m]
  double initial_velocity = 0.0;  ///< [m/s]
  /// [m/s] below this impact speed the ball comes to rest (v⁺ = 0, and it stays on the ground); 0 = no cutoff.
  double rest_velocity_cutoff = 0.0;
};

class BouncingBall final : public LeafSystem {
 public:
  explicit BouncingBall(std::string name = "ball", BouncingBallParams params = {});
  const BouncingBallParams& params() const { return params_; }
  /// Analytic impact times from the initial state (first `count`).
  std::vector<double> AnalyticImpactTimes(int count) const;

 private:
  void DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const override;
  BouncingBallParams params_;
};

}  // namespace rome
