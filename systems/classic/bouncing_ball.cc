#include "systems/classic/bouncing_ball.h"

#include <cmath>

namespace rome {

BouncingBall::BouncingBall(std::string name, BouncingBallParams params) : LeafSystem(std::move(name)), params_(params) {
  if (!(params_.restitution >= 0 && params_.restitution <= 1))
    ThrowError("restitution must be in [0, 1], got " + std::to_string(params_.restitution));
  if (!(params_.gravity > 0)) ThrowError("gravity must be positive, got " + std::to_string(params_.gravity));
  if (!(params_.initial_height >= 0))
    ThrowError("initial_height must be >= 0 m, got " + std::to_string(params_.initial_height));
  // A ball released at rest on the ground starts resting (its guard starts at 0 and would never cross).
  DeclareModes({"flight", "resting"}, params_.initial_height == 0 && params_.initial_velocity <= 0 ? 1 : 0);
  DeclareContinuousState(Eigen::Vector2d(params_.initial_height, params_.initial_velocity));
  DeclareOutputPort(
      "state", 2, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state(); }, Feedthrough::None());
  DeclareGuard(
      "ground_contact", /*mode=*/0, [](const LeafContext& c) { return c.continuous_state()[0]; },
      CrossingDirection::kFalling,
      [this](const LeafContext&, int, State* next) {
        const double v_after = -params_.restitution * next->continuous[1];
        if (!(std::abs(v_after) > params_.rest_velocity_cutoff)) {  // includes e = 0: no rebound, the ball stays
          next->continuous << 0.0, 0.0;
          next->mode = 1;
        } else {
          next->continuous[1] = v_after;
        }
        return EventStatus::Succeeded();
      });
}

void BouncingBall::DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const {
  if (context.mode() == 1) {
    xdot->setZero();
    return;
  }
  (*xdot)[0] = context.continuous_state()[1];
  (*xdot)[1] = -params_.gravity;
}

std::vector<double> BouncingBall::AnalyticImpactTimes(int count) const {
  std::vector<double> t;
  const double g = params_.gravity, h0 = params_.initial_height, v0 = params_.initial_velocity;
  if (h0 == 0 && v0 <= 0) return t;  // starts resting: no impact
  // First impact: h0 + v0 t − g t²/2 = 0.
  double time = (v0 + std::sqrt(v0 * v0 + 2 * g * h0)) / g;
  double speed = std::sqrt(v0 * v0 + 2 * g * h0);  // impact speed
  for (int k = 0; k < count; ++k) {
    t.push_back(time);
    speed *= params_.restitution;
    if (!(speed > params_.rest_velocity_cutoff)) break;
    time += 2 * speed / g;
  }
  return t;
}

}  // namespace rome
