#include "systems/planners/walking_plan.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace rome {

size_t WalkingPlan::SegmentIndexAt(double t) const {
  if (segments_.empty()) throw std::logic_error("WalkingPlan::SegmentIndexAt: the plan is empty");
  // Last segment that has started (segments are contiguous and ordered).
  const double shifted = t + kSegmentBoundaryTolerance_s;
  auto it = std::upper_bound(segments_.begin(), segments_.end(), shifted,
                             [](double time, const WalkingPlanSegment& s) { return time < s.start_time; });
  return it == segments_.begin() ? 0 : static_cast<size_t>(it - segments_.begin()) - 1;
}

WalkingReference WalkingPlan::Sample(double t) const {
  if (segments_.empty()) throw std::logic_error("WalkingPlan::Sample: the plan is empty");
  t = std::clamp(t, 0.0, end_time());
  const WalkingPlanSegment& s = segments_[SegmentIndexAt(t)];
  const double tau = std::clamp(t - s.start_time, 0.0, s.duration);
  WalkingReference r;
  // Fixed-size outputs: Sample runs every control tick and allocates nothing.
  Eigen::Vector4d sag;
  Eigen::Vector2d acc;
  s.sagittal.ValueInto(tau, sag);
  s.sagittal_acceleration.ValueInto(tau, acc);
  r.com_position << s.sagittal_x_offset + sag(0), 0.0, sag(1);
  r.com_velocity << sag(2), 0.0, sag(3);
  r.com_acceleration << acc(0), 0.0, acc(1);
  // Lateral, closed form.
  if (s.lateral_nodes.cols() > 0) {
    // Footed H-LIP with the torque held on [t_k, t_{k+1}).
    const Eigen::Index n = s.lateral_node_times.size();
    Eigen::Index k = std::upper_bound(s.lateral_node_times.data(), s.lateral_node_times.data() + n,
                                      tau + kSegmentBoundaryTolerance_s) -
                     s.lateral_node_times.data() - 1;
    k = std::clamp<Eigen::Index>(k, 0, n - 2);
    const double mz =
        s.lateral_mass_heights.size() == s.lateral_stiffness.size() ? s.lateral_mass_heights(k) : s.mass_height;
    const double dt = tau - s.lateral_node_times(k), a_u = s.lateral_torques(k) / mz;
    const double y0 = s.lateral_nodes(0, k), v0 = s.lateral_nodes(1, k);
    const double a = s.lateral_stiffness(k);
    if (a <= 0.0) {  // ÿ = a_u
      r.com_position(1) = y0 + v0 * dt + 0.5 * a_u * dt * dt;
      r.com_velocity(1) = v0 + a_u * dt;
      r.com_acceleration(1) = a_u;
    } else {
      // ÿ = a (y − c_k) + a_u = a (y − c), c = c_k − a_u/a.
      const double l = std::sqrt(a), c = s.lateral_pivots(k) - a_u / a;
      const double ch = std::cosh(l * dt), sh = std::sinh(l * dt);
      const double y = (y0 - c) * ch + v0 / l * sh;
      r.com_position(1) = c + y;
      r.com_velocity(1) = (y0 - c) * l * sh + v0 * ch;
      r.com_acceleration(1) = a * y;
    }
  } else if (s.domain == WalkingDomain::kDoubleSupport) {
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
  if (has_com_correction() && t >= correction_position_.start_time() && t <= correction_position_.end_time()) {
    Eigen::Vector2d c;
    correction_position_.ValueInto(t, c);
    r.com_position.head<2>() += c;
    correction_position_.DerivativeInto(t, 1, c);
    r.com_velocity.head<2>() += c;
    correction_acceleration_.ValueInto(t, c);
    r.com_acceleration.head<2>() += c;
  }
  s.normal_forces.ValueInto(tau, r.normal_force);
  r.left_foothold = s.left_foothold;
  r.right_foothold = s.right_foothold;
  r.domain = s.domain;
  return r;
}

void WalkingPlan::SetComCorrection(PiecewisePolynomial position, PiecewisePolynomial acceleration) {
  if (position.rows() != 2 || acceleration.rows() != 2)
    throw std::invalid_argument(
        "WalkingPlan::SetComCorrection: position and acceleration must have 2 rows (x, y), got " +
        std::to_string(position.rows()) + " and " + std::to_string(acceleration.rows()));
  correction_position_ = std::move(position);
  correction_acceleration_ = std::move(acceleration);
}

Eigen::Vector2d WalkingPlan::ComCorrection(double t) const {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  if (has_com_correction() && t >= correction_position_.start_time() && t <= correction_position_.end_time())
    correction_position_.ValueInto(t, c);
  return c;
}

void WalkingPlan::AppendPeriodicSteps(const AslipPeriodicGaitPlanner& planner, const AslipPeriodicGait& gait, int steps,
                                      WalkingDomain first_stance, double stance_x, double step_width,
                                      bool begin_with_double_support, bool end_with_single_support,
                                      double walking_line_y) {
  std::ostringstream msg;
  if (steps < 1) msg << "steps must be >= 1, got " << steps;
  if (!(step_width > 0) || !std::isfinite(step_width)) msg << "step_width must be > 0 m, got " << step_width;
  if (!std::isfinite(walking_line_y)) msg << "walking_line_y must be finite, got " << walking_line_y;
  if (first_stance == WalkingDomain::kDoubleSupport) msg << "first_stance must be kLeftStance or kRightStance";
  if (!gait.success()) msg << "the gait is not solved (" << gait.collocation.nlp.message << ")";
  if (!msg.str().empty()) throw std::invalid_argument("WalkingPlan::AppendPeriodicSteps: " + msg.str());
  const AslipPeriodicGaitParams& q = planner.params();
  const HybridLinearInvertedPendulum hlip({.z0 = gait.mean_height,
                                           .ssp_duration = q.ssp_duration,
                                           .dsp_duration = q.dsp_duration,
                                           .gravity = q.aslip.gravity});
  const Eigen::Vector2d pre_left = hlip.P2PreImpactState(step_width);  // end of a left stance, about the left foot
  double t0 = end_time();
  bool left = first_stance == WalkingDomain::kLeftStance;
  double x0 = stance_x;
  const double half = 0.5 * step_width;
  for (int step = 0; step < steps; ++step) {
    const double stance_y = walking_line_y + (left ? half : -half);
    // Pre-impact lateral state about this stance foot: (p, v) for a left stance, −(p, v) for a right stance; by the
    // symmetry of the P2 orbit the SSP starts at (p, −v) (left) or (−p, v) (right).
    const Eigen::Vector2d pre = left ? pre_left : Eigen::Vector2d(-pre_left);
    const Eigen::Vector2d start(pre(0), -pre(1));
    const int stance_leg = left ? 0 : 1;  // world leg standing in this SSP (plan leg 0)
    const int last_phase = (step == steps - 1 && end_with_single_support) ? 0 : 1;
    for (int ph = (step == 0 && begin_with_double_support) ? 1 : 0; ph <= last_phase; ++ph) {
      const CollocationPhaseSolution& s = gait.collocation.phases[ph];
      WalkingPlanSegment seg;
      seg.start_time = t0;
      seg.duration = s.duration;
      seg.domain =
          ph == 1 ? WalkingDomain::kDoubleSupport : (left ? WalkingDomain::kLeftStance : WalkingDomain::kRightStance);
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
      const Eigen::Vector2d stance_foot(x0, stance_y), other_foot(x0 + q.step_length, 2.0 * walking_line_y - stance_y);
      seg.left_foothold = left ? stance_foot : other_foot;
      seg.right_foothold = left ? other_foot : stance_foot;
      t0 += s.duration;
      segments_.push_back(std::move(seg));
    }
    x0 += q.step_length;
    left = !left;
  }
}

void WalkingPlan::AppendSegment(WalkingPlanSegment segment) {
  std::ostringstream msg;
  if (!(std::abs(segment.start_time - end_time()) <= kSegmentBoundaryTolerance_s))
    msg << "start_time = " << segment.start_time << " s, expected the plan's end " << end_time() << " s";
  else if (!(segment.duration > 0) || !std::isfinite(segment.duration))
    msg << "duration = " << segment.duration << " s, expected > 0";
  else if (segment.sagittal.rows() != 4 || segment.sagittal_acceleration.rows() != 2 ||
           segment.normal_forces.rows() != 2)
    msg << "sagittal, sagittal_acceleration, normal_forces have " << segment.sagittal.rows() << ", "
        << segment.sagittal_acceleration.rows() << ", " << segment.normal_forces.rows() << " rows, expected 4, 2, 2";
  if (!msg.str().empty()) throw std::invalid_argument("WalkingPlan::AppendSegment: " + msg.str());
  segment.start_time = end_time();
  segments_.push_back(std::move(segment));
}

void WalkingPlan::AppendTransition(const AslipTransitionPlanner& planner, const AslipTransition& transition,
                                   const AslipTransitionData& data, double x_offset,
                                   const FootedHlipTransitionData& lateral_data,
                                   const FootedHlipTransitionPlan& lateral, double mass, double landing_x,
                                   double landing_y) {
  std::ostringstream msg;
  if (!transition.success())
    msg << "the footed-aSLIP transition is not solved (" << transition.collocation.nlp.message << ")";
  if (!lateral.success()) msg << "the footed H-LIP transition is not solved (" << lateral.message << ")";
  if (!(mass > 0)) msg << "mass must be > 0 kg, got " << mass;
  if (std::isinf(landing_y)) msg << "landing_y must be finite or NaN (where the foot lifted), got " << landing_y;
  const int Nd =
      static_cast<int>(transition.collocation.phases.empty() ? 0 : transition.collocation.phases[0].times.size());
  const int Ns =
      static_cast<int>(transition.collocation.phases.size() < 2 ? 0 : transition.collocation.phases[1].times.size());
  if (msg.str().empty() && lateral_data.node_times.size() != Nd + Ns - 1) {
    msg << "the lateral plan has " << lateral_data.node_times.size() << " nodes, the sagittal grid " << Nd + Ns - 1;
  }
  if (msg.str().empty() && lateral.interval_stiffness.size() != lateral_data.node_times.size() - 1) {
    msg << "the lateral plan has " << lateral.interval_stiffness.size() << " interval models for "
        << lateral_data.node_times.size() << " nodes";
  }
  if (!msg.str().empty()) throw std::invalid_argument("WalkingPlan::AppendTransition: " + msg.str());
  const ActuatedSpringLoadedInvertedPendulumParams& p = planner.params().bounds.aslip;
  const double z0 = lateral_data.z0, lambda = std::sqrt(p.gravity / z0);
  double t0 = end_time();
  const int stance = 1 - data.lifting_leg;
  for (int ph = 0; ph < 2; ++ph) {
    const CollocationPhaseSolution& s = transition.collocation.phases[ph];
    WalkingPlanSegment seg;
    seg.start_time = t0;
    seg.duration = s.duration;
    seg.domain = ph == 0 ? WalkingDomain::kDoubleSupport
                         : (stance == 0 ? WalkingDomain::kLeftStance : WalkingDomain::kRightStance);
    seg.sagittal_x_offset = x_offset;
    const Eigen::VectorXd tau = s.times.array() - s.start_time;
    seg.sagittal = PiecewisePolynomial::CubicHermite(tau, s.states.topRows(4), s.state_derivatives.topRows(4));
    seg.sagittal_acceleration = PiecewisePolynomial::FirstOrderHold(tau, s.state_derivatives.middleRows(2, 2));
    const Eigen::MatrixXd G = transition.GroundReactions(p, data, ph);
    Eigen::MatrixXd F(2, G.cols());
    F.row(0) = G.row(1);
    F.row(1) = G.row(3);
    seg.normal_forces = PiecewisePolynomial::FirstOrderHold(tau, F);
    seg.lambda = lambda;
    seg.lateral_pivot_y = stance == 0 ? lateral_data.left_foot_y : lateral_data.right_foot_y;
    seg.mass_height = mass * z0;
    const int first = ph == 0 ? 0 : Nd - 1;
    const int count = ph == 0 ? Nd : Ns;
    seg.lateral_node_times = lateral_data.node_times.segment(first, count).array() - lateral_data.node_times(first);
    seg.lateral_nodes = lateral.states.middleCols(first, count);
    seg.lateral_torques.resize(count);
    for (int k = 0; k < count; ++k) {
      const int j = first + k;
      seg.lateral_torques(k) = ph == 0 ? lateral.left_torque(j) + lateral.right_torque(j)
                                       : (stance == 0 ? lateral.left_torque(j) : lateral.right_torque(j));
    }
    seg.lateral_stiffness = lateral.interval_stiffness.segment(first, count - 1);
    seg.lateral_pivots = lateral.interval_pivot.segment(first, count - 1);
    if (lateral.interval_height.size() == lateral.interval_stiffness.size())
      seg.lateral_mass_heights = mass * lateral.interval_height.segment(first, count - 1);
    seg.lateral_start = seg.lateral_nodes.col(0);
    // Footholds at the end of the segment: in the SSP the lifting foot lands at the final state's step.
    Eigen::Vector2d left(x_offset + data.left_foot_x, lateral_data.left_foot_y);
    Eigen::Vector2d right(x_offset + data.right_foot_x, lateral_data.right_foot_y);
    if (ph == 1) (data.lifting_leg == 0 ? left : right)(0) = landing_x;
    if (ph == 1 && !std::isnan(landing_y)) (data.lifting_leg == 0 ? left : right)(1) = landing_y;
    seg.left_foothold = left;
    seg.right_foothold = right;
    t0 += s.duration;
    segments_.push_back(std::move(seg));
  }
}

FootedHlipTransitionData LateralDataOnTransitionNodes(const AslipTransition& transition,
                                                      const ActuatedSpringLoadedInvertedPendulumParams& aslip,
                                                      const AslipTransitionData& data, int nodes_per_domain,
                                                      double step_width_m) {
  const int N = nodes_per_domain;
  FootedHlipTransitionData lat;
  lat.node_times.resize(2 * N - 1);
  lat.left_normal_force.resize(2 * N - 1);
  lat.right_normal_force.resize(2 * N - 1);
  for (int ph = 0; ph < 2; ++ph) {
    const Eigen::MatrixXd G = transition.GroundReactions(aslip, data, ph);
    const CollocationPhaseSolution& s = transition.collocation.phases[ph];
    for (int k = ph; k < N; ++k) {
      const int j = ph * (N - 1) + k;
      lat.node_times(j) = s.times(k);
      lat.left_normal_force(j) = std::max(0.0, G(1, k));
      lat.right_normal_force(j) = std::max(0.0, G(3, k));
    }
  }
  for (int k = 0; k + 1 < 2 * N - 1; ++k) lat.single_support.push_back(k >= N - 1);
  lat.stance_left = true;
  lat.left_foot_y = step_width_m / 2;
  lat.right_foot_y = -step_width_m / 2;
  lat.z0 = transition.mean_height;
  lat.node_heights.resize(2 * N - 1);
  for (int ph = 0; ph < 2; ++ph)
    for (int k = ph; k < N; ++k) lat.node_heights(ph * (N - 1) + k) = transition.collocation.phases[ph].states(1, k);
  lat.initial_state = Eigen::Vector2d(0.0, 0.0);
  return lat;
}

}  // namespace rome
