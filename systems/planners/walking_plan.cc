#include "systems/planners/walking_plan.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rome {

WalkingReference WalkingPlan::Sample(double t) const {
  if (segments_.empty()) throw std::logic_error("WalkingPlan::Sample: the plan is empty");
  t = std::clamp(t, 0.0, end_time());
  // Last segment that has started (segments are contiguous and ordered).
  auto it = std::upper_bound(segments_.begin(), segments_.end(), t,
                             [](double time, const WalkingPlanSegment& s) { return time < s.start_time; });
  const WalkingPlanSegment& s = *(it == segments_.begin() ? it : it - 1);
  const double tau = std::clamp(t - s.start_time, 0.0, s.duration);
  WalkingReference r;
  const Eigen::VectorXd sag = s.sagittal.Value(tau);
  const Eigen::VectorXd acc = s.sagittal_acceleration.Value(tau);
  r.com_position << s.sagittal_x_offset + sag(0), 0.0, sag(1);
  r.com_velocity << sag(2), 0.0, sag(3);
  r.com_acceleration << acc(0), 0.0, acc(1);
  // Lateral, closed form.
  if (s.domain == WalkingDomain::kDoubleSupport) {
    r.com_position(1) = s.lateral_start(0) + s.lateral_start(1) * tau;
    r.com_velocity(1) = s.lateral_start(1);
    r.com_acceleration(1) = 0.0;
  } else {
    const double y0 = s.lateral_start(0) - s.lateral_pivot_y, v0 = s.lateral_start(1);
    const double ch = std::cosh(s.lambda * tau), sh = std::sinh(s.lambda * tau);
    const double y = y0 * ch + v0 / s.lambda * sh;
    r.com_position(1) = s.lateral_pivot_y + y;
    r.com_velocity(1) = y0 * s.lambda * sh + v0 * ch;
    r.com_acceleration(1) = s.lambda * s.lambda * y;
  }
  r.normal_force = s.normal_forces.Value(tau);
  r.left_foothold = s.left_foothold;
  r.right_foothold = s.right_foothold;
  r.domain = s.domain;
  return r;
}

void WalkingPlan::AppendPeriodicSteps(const AslipPeriodicGaitPlanner& planner, const AslipPeriodicGait& gait, int steps,
                                      WalkingDomain first_stance, double stance_x, double step_width) {
  std::ostringstream msg;
  if (steps < 1) msg << "steps must be >= 1, got " << steps;
  if (!(step_width > 0) || !std::isfinite(step_width)) msg << "step_width must be > 0 m, got " << step_width;
  if (first_stance == WalkingDomain::kDoubleSupport) msg << "first_stance must be kLeftStance or kRightStance";
  if (!gait.success()) msg << "the gait is not solved (" << gait.collocation.nlp.message << ")";
  if (!msg.str().empty()) throw std::invalid_argument("WalkingPlan::AppendPeriodicSteps: " + msg.str());
  const AslipPeriodicGaitParams& q = planner.params();
  const HybridLinearInvertedPendulum hlip(
      {.z0 = gait.mean_height, .ssp_duration = q.ssp_duration, .dsp_duration = q.dsp_duration, .gravity = q.aslip.gravity});
  const Eigen::Vector2d pre_left = hlip.P2PreImpactState(step_width);  // end of a left stance, about the left foot
  double t0 = end_time();
  bool left = first_stance == WalkingDomain::kLeftStance;
  double x0 = stance_x;
  const double half = 0.5 * step_width;
  for (int step = 0; step < steps; ++step) {
    const double stance_y = left ? half : -half;
    // Pre-impact lateral state about this stance foot: (p, v) for a left stance, −(p, v) for a right stance; by the
    // symmetry of the P2 orbit the SSP starts at (p, −v) (left) or (−p, v) (right).
    const Eigen::Vector2d pre = left ? pre_left : Eigen::Vector2d(-pre_left);
    const Eigen::Vector2d start(pre(0), -pre(1));
    const int stance_leg = left ? 0 : 1;  // world leg standing in this SSP (plan leg 0)
    for (int ph = 0; ph < 2; ++ph) {
      const CollocationPhaseSolution& s = gait.collocation.phases[ph];
      WalkingPlanSegment seg;
      seg.start_time = t0;
      seg.duration = s.duration;
      seg.domain = ph == 1 ? WalkingDomain::kDoubleSupport : (left ? WalkingDomain::kLeftStance : WalkingDomain::kRightStance);
      seg.sagittal_x_offset = x0;
      seg.sagittal = PiecewisePolynomial::CubicHermite(s.times.array() - s.start_time, s.states.topRows(4),
                                                       s.state_derivatives.topRows(4));
      seg.sagittal_acceleration =
          PiecewisePolynomial::FirstOrderHold(s.times.array() - s.start_time, s.state_derivatives.middleRows(2, 2));
      const Eigen::MatrixXd G = gait.GroundReactions(q.aslip, q.step_length, ph);
      Eigen::MatrixXd F(2, G.cols());
      F.row(stance_leg) = G.row(1);
      F.row(1 - stance_leg) = G.row(3);
      seg.normal_forces = PiecewisePolynomial::FirstOrderHold(s.times.array() - s.start_time, F);
      seg.lambda = hlip.lambda();
      seg.lateral_pivot_y = stance_y;
      if (ph == 0) {
        seg.lateral_start = Eigen::Vector2d(stance_y + start(0), start(1));
      } else {
        seg.lateral_start = Eigen::Vector2d(stance_y + pre(0), pre(1));
      }
      // Footholds at the end of this segment: the stance foot at x0, the other at x0 + l (landing point in SSP).
      const Eigen::Vector2d stance_foot(x0, stance_y), other_foot(x0 + q.step_length, -stance_y);
      seg.left_foothold = left ? stance_foot : other_foot;
      seg.right_foothold = left ? other_foot : stance_foot;
      t0 += s.duration;
      segments_.push_back(std::move(seg));
    }
    x0 += q.step_length;
    left = !left;
  }
}

}  // namespace rome
