#include "diagrams/walking/walking_stop_plan.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "systems/multibody/multibody_kinematics.h"

namespace rome {

namespace {

// Quintic q(τ) on [0, T] with q, q̇, q̈ given at both ends; returns the coefficients c_0..c_5 in τ.
Eigen::Matrix<double, 6, 1> Quintic(double T, const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  Eigen::Matrix<double, 6, 1> c;
  c(0) = from(0), c(1) = from(1), c(2) = 0.5 * from(2);
  const double T2 = T * T, T3 = T2 * T;
  // Remaining c_3..c_5 from the end conditions (the standard minimum-jerk boundary solution).
  const double h = to(0) - from(0) - from(1) * T - 0.5 * from(2) * T2;
  const double hd = to(1) - from(1) - from(2) * T;
  const double hdd = to(2) - from(2);
  c(3) = (20 * h - 8 * hd * T + hdd * T2) / (2 * T3);
  c(4) = (-30 * h + 14 * hd * T - 2 * hdd * T2) / (2 * T3 * T);
  c(5) = (12 * h - 6 * hd * T + hdd * T2) / (2 * T3 * T2);
  return c;
}
// [q, q̇, q̈] of the quintic at τ.
Eigen::Vector3d Eval(const Eigen::Matrix<double, 6, 1>& c, double tau) {
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  for (int k = 5; k >= 0; --k) r(0) = r(0) * tau + c(k);
  for (int k = 5; k >= 1; --k) r(1) = r(1) * tau + k * c(k);
  for (int k = 5; k >= 2; --k) r(2) = r(2) * tau + k * (k - 1) * c(k);
  return r;
}
// One phase of the stop on its nodes: times from the phase start, sagittal [x, z, ẋ, ż, ẍ, z̈] (x world) and the
// normal forces [F_L, F_R].
struct StopPhase {
  WalkingDomain domain = WalkingDomain::kDoubleSupport;
  Eigen::VectorXd t;
  Eigen::MatrixXd sagittal, forces;
};

// The phase's COM quintics in x, z and a lateral design y; the load split puts the lateral centre of pressure of the
// point mass, y − z ÿ / (g + z̈), between the feet where the design needs it (front share (p_y − y_other) / (y_front −
// y_other), clipped to [0, 1]; the footed H-LIP QP then plans y on these forces with the soles' roll torques). Moving
// the COM sideways needs the centre of pressure on its far side first: a split that followed the COM would push it
// back. other_floor_fraction: the other foot carries at least this share of the load at every node but the last
// (the settle's rear foot, unloaded only where it lifts).
StopPhase MakePhase(WalkingDomain domain, double T, int n, const Eigen::Matrix<double, 6, 1>& cx,
                    const Eigen::Matrix<double, 6, 1>& cz, const Eigen::Matrix<double, 6, 1>& cy, double mass, double g,
                    int front, double y_front, double y_other, double other_floor_fraction = 0.0) {
  StopPhase p;
  p.domain = domain;
  p.t = Eigen::VectorXd::LinSpaced(n, 0.0, T);
  p.sagittal.resize(6, n), p.forces.resize(2, n);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d x = Eval(cx, p.t(k)), z = Eval(cz, p.t(k)), y = Eval(cy, p.t(k));
    p.sagittal.col(k) << x(0), z(0), x(1), z(1), x(2), z(2);
    const double total = mass * (g + z(2)), cop_y = y(0) - z(0) * y(2) / (g + z(2));
    const double top = k < n - 1 ? 1.0 - other_floor_fraction : 1.0;
    const double share =
        domain == WalkingDomain::kDoubleSupport ? std::clamp((cop_y - y_other) / (y_front - y_other), 0.0, top) : 1.0;
    p.forces(front, k) = share * total;
    p.forces(1 - front, k) = (1.0 - share) * total;
  }
  return p;
}

// The sagittal centre of pressure of phase p's nodes must lie on the feet that carry the load: between the heel of the
// rear-weighted and the toe of the front-weighted ankle (each foot's CoP on its own sole, force-weighted).
void CheckSagittalCop(const StopPhase& p, double x_front, double x_rear, int front, const StandToWalkParams& sp,
                      double g, const std::string& who) {
  const double heel = sp.sole.heel_m - sp.standing_sagittal_cop_margin_m;
  const double toe = sp.sole.toe_m - sp.standing_sagittal_cop_margin_m;
  for (Eigen::Index k = 0; k < p.t.size(); ++k) {
    const double total = p.forces(0, k) + p.forces(1, k), share = p.forces(front, k) / total;
    const double cop = p.sagittal(0, k) - p.sagittal(1, k) * p.sagittal(4, k) / (g + p.sagittal(5, k));
    const double ankles = share * x_front + (1 - share) * x_rear;
    if (cop < ankles - heel - 1e-9 || cop > ankles + toe + 1e-9) {
      std::ostringstream m;
      m << who << ": the stop's centre of pressure leaves the feet: " << cop - ankles << " m from the loaded ankles at "
        << p.t(k) << " s of the settle (sole [-" << heel << ", " << toe << "] m; the COM lands "
        << p.sagittal(0, 0) - x_rear << " m ahead of the rear ankle at " << p.sagittal(2, 0)
        << " m/s); change settle_duration_s";
      throw std::runtime_error(m.str());
    }
  }
}

// Appends phase p as a plan segment; its lateral motion is nodes [first, first + n) of the QP plan.
void AppendPhase(WalkingPlan& plan, const StopPhase& p, double x_offset, const FootedHlipTransitionData& lat,
                 const FootedHlipTransitionPlan& lateral, int first, double mass, double g, const Eigen::Vector2d& left,
                 const Eigen::Vector2d& right) {
  const Eigen::Index n = p.t.size();
  WalkingPlanSegment s;
  s.start_time = plan.end_time();
  s.duration = p.t(n - 1);
  s.domain = p.domain;
  s.sagittal_x_offset = x_offset;
  Eigen::MatrixXd values = p.sagittal.topRows(4), derivatives = p.sagittal.middleRows(2, 4);
  values.row(0).array() -= x_offset;
  s.sagittal = PiecewisePolynomial::CubicHermite(p.t, values, derivatives);
  s.sagittal_acceleration = PiecewisePolynomial::FirstOrderHold(p.t, p.sagittal.bottomRows(2));
  s.normal_forces = PiecewisePolynomial::FirstOrderHold(p.t, p.forces);
  s.lateral_node_times = lat.node_times.segment(first, n).array() - lat.node_times(first);
  s.lateral_nodes = lateral.states.middleCols(first, n);
  s.lateral_torques.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index j = first + k;
    s.lateral_torques(k) = p.domain == WalkingDomain::kDoubleSupport ? lateral.left_torque(j) + lateral.right_torque(j)
                           : p.domain == WalkingDomain::kLeftStance  ? lateral.left_torque(j)
                                                                     : lateral.right_torque(j);
  }
  s.lateral_stiffness = lateral.interval_stiffness.segment(first, n - 1);
  s.lateral_pivots = lateral.interval_pivot.segment(first, n - 1);
  s.mass_height = mass * lat.z0;
  s.lateral_mass_heights = mass * lateral.interval_height.segment(first, n - 1);
  s.lateral_start = s.lateral_nodes.col(0);
  s.lateral_pivot_y = p.domain == WalkingDomain::kLeftStance ? left.y() : right.y();
  s.lambda = std::sqrt(g / lat.z0);
  s.left_foothold = left;
  s.right_foothold = right;
  plan.AppendSegment(std::move(s));
}

}  // namespace

void WalkToStandParams::Validate(const std::string& who) const {
  std::ostringstream m;
  const auto in = [](double v, double lo, double hi) { return v >= lo && v <= hi; };
  if (!(stop_gait_steps >= 1 && stop_gait_steps <= 20))
    m << "stop_gait_steps = " << stop_gait_steps << " is outside [1, 20]";
  else if (!in(settle_duration_s, 0.3, 5.0))
    m << "settle_duration_s = " << settle_duration_s << " s is outside [0.3, 5] s";
  else if (!in(step_duration_s, 0.3, 2.0))
    m << "step_duration_s = " << step_duration_s << " s is outside [0.3, 2] s";
  else if (!in(shift_duration_s, 0.3, 5.0))
    m << "shift_duration_s = " << shift_duration_s << " s is outside [0.3, 5] s";
  else if (!in(hold_duration_s, 0.1, 60.0))
    m << "hold_duration_s = " << hold_duration_s << " s is outside [0.1, 60] s";
  else if (!(settle_rear_force_fraction >= 0.0 && settle_rear_force_fraction < 0.5))
    m << "settle_rear_force_fraction = " << settle_rear_force_fraction << " is outside [0, 0.5)";
  else if (!(nodes_per_phase >= 5 && nodes_per_phase <= 200))
    m << "nodes_per_phase = " << nodes_per_phase << " is outside [5, 200]";
  if (!m.str().empty()) throw std::invalid_argument(who + ": " + m.str());
}

WalkingPlan BuildWalkToStandPlan(const WalkingGait& gait, int steps, std::uint32_t seed, const PlanCache* cache,
                                 WalkingPlanReport* report, const StandToWalkParams& sp,
                                 const WalkToStandParams& stop) {
  const std::string who = "BuildWalkToStandPlan";
  gait.Validate(who + ": gait");
  sp.Validate(who);
  stop.Validate(who);
  if (steps < 1) throw std::invalid_argument(who + ": steps must be >= 1, got " + std::to_string(steps));
  const WalkingGait slow{sp.start_gait_step_length_m, sp.start_gait_ssp_duration_s, sp.start_gait_dsp_duration_s,
                         gait.step_width_m};
  slow.Validate(who + ": the stop gait (the start gait's L, T_SSP, T_DSP: StandToWalkParams::start_gait_*)");
  const bool same = std::abs(slow.step_length_m - gait.step_length_m) < 1e-9 &&
                    std::abs(slow.ssp_duration_s - gait.ssp_duration_s) < 1e-9 &&
                    std::abs(slow.dsp_duration_s - gait.dsp_duration_s) < 1e-9;
  WalkingPlan plan = same ? BuildStandToWalkPlan(gait, steps + stop.stop_gait_steps, seed, cache, report, sp)
                          : BuildGaitChangePlan(gait, slow, steps, seed, cache, report, sp, stop.stop_gait_steps);
  // The stop replaces the stop gait's last double support: the plan then ends at a touchdown.
  if (plan.segments().empty() || plan.segments().back().domain != WalkingDomain::kDoubleSupport)
    throw std::logic_error(who + ": the walking plan does not end in a double support");
  plan.RemoveLastSegment();
  const WalkingPlanSegment& last = plan.segments().back();
  const int front = last.domain == WalkingDomain::kLeftStance ? 1 : 0;  // the foot that just landed (0 left)
  const Eigen::Vector2d front_foot = front == 0 ? last.left_foothold : last.right_foothold;
  const Eigen::Vector2d rear_foot = front == 0 ? last.right_foothold : last.left_foothold;
  const WalkingReference td = plan.Sample(plan.end_time());
  const ActuatedSpringLoadedInvertedPendulumParams rom;  // the ROM plans' mass and gravity
  const double m = rom.mass, g = rom.gravity, h = sp.standing_height_m;
  // Settle and step at the gaits' height range: a standing height above it is reached in the shift, feet side by side.
  const double step_h = std::min(h, sp.height_max_m);
  const int n = stop.nodes_per_phase;
  const Eigen::Vector3d rest_x(front_foot.x(), 0.0, 0.0), rest_z(step_h, 0.0, 0.0), stand_z(h, 0.0, 0.0);
  const Eigen::Matrix<double, 6, 1> hold_x = Quintic(1.0, rest_x, rest_x), hold_z = Quintic(1.0, rest_z, rest_z);
  // The rear foot lands beside the front one, at the same step width (its y does not change).
  const Eigen::Vector2d landed(front_foot.x(), rear_foot.y());
  const Eigen::Vector2d mid = 0.5 * (front_foot + landed);
  const double yf = front_foot.y(), yo = rear_foot.y();
  const Eigen::Vector3d rest_y(yf, 0.0, 0.0), mid_y(mid.y(), 0.0, 0.0);
  const double Ts = stop.settle_duration_s, Tf = stop.shift_duration_s;
  const StopPhase settle =
      MakePhase(WalkingDomain::kDoubleSupport, Ts, n,
                Quintic(Ts, Eigen::Vector3d(td.com_position.x(), td.com_velocity.x(), td.com_acceleration.x()), rest_x),
                Quintic(Ts, Eigen::Vector3d(td.com_position.z(), td.com_velocity.z(), td.com_acceleration.z()), rest_z),
                Quintic(Ts, Eigen::Vector3d(td.com_position.y(), td.com_velocity.y(), td.com_acceleration.y()), rest_y),
                m, g, front, yf, yo, stop.settle_rear_force_fraction);
  CheckSagittalCop(settle, front_foot.x(), rear_foot.x(), front, sp, g, who);
  const WalkingDomain stance = front == 0 ? WalkingDomain::kLeftStance : WalkingDomain::kRightStance;
  const StopPhase step =
      MakePhase(stance, stop.step_duration_s, n, hold_x, hold_z, Quintic(1.0, rest_y, rest_y), m, g, front, yf, yo);
  const StopPhase shift = MakePhase(WalkingDomain::kDoubleSupport, Tf, n, hold_x, Quintic(Tf, rest_z, stand_z),
                                    Quintic(Tf, rest_y, mid_y), m, g, front, yf, yo);
  const StopPhase hold = MakePhase(WalkingDomain::kDoubleSupport, stop.hold_duration_s, 2, hold_x,
                                   Quintic(1.0, stand_z, stand_z), Quintic(1.0, mid_y, mid_y), m, g, front, yf, yo);
  // One footed H-LIP QP over settle, step and shift (shared nodes once).
  FootedHlipTransitionData lat;
  const StopPhase* phases[3] = {&settle, &step, &shift};
  const int N = 3 * n - 2;
  lat.node_times.resize(N), lat.left_normal_force.resize(N), lat.right_normal_force.resize(N);
  lat.node_heights.resize(N);
  double t0 = 0;
  for (int ph = 0; ph < 3; ++ph) {
    for (int k = ph == 0 ? 0 : 1; k < n; ++k) {
      const int j = ph * (n - 1) + k;
      lat.node_times(j) = t0 + phases[ph]->t(k);
      lat.left_normal_force(j) = std::max(0.0, phases[ph]->forces(0, k));
      lat.right_normal_force(j) = std::max(0.0, phases[ph]->forces(1, k));
      lat.node_heights(j) = phases[ph]->sagittal(1, k);
    }
    t0 += phases[ph]->t(n - 1);
  }
  lat.single_support.assign(N - 1, false);  // the step's intervals are single supports
  for (int k = n - 1; k < 2 * (n - 1); ++k) lat.single_support[k] = true;
  lat.stance_left = front == 0;
  lat.left_foot_y = front == 0 ? front_foot.y() : rear_foot.y();
  lat.right_foot_y = front == 0 ? rear_foot.y() : front_foot.y();
  lat.z0 = lat.node_heights.mean();
  lat.initial_state = Eigen::Vector2d(td.com_position.y(), td.com_velocity.y());
  lat.final_state = Eigen::Vector2d(mid.y(), 0.0);
  FootedHlipTransitionParams lp;
  lp.mass = m;
  lp.gravity = g;
  lp.foot_width_left_of_ankle = sp.sole.left_m - sp.lateral_cop_margin_m;
  lp.foot_width_right_of_ankle = sp.sole.right_m - sp.lateral_cop_margin_m;
  lp.normal_force_pivots = true;  // the stop's split moves the weight from foot to foot: the pivots carry it
  const FootedHlipTransitionPlan lateral = FootedHlipTransitionPlanner(lp).Solve(lat);
  if (!lateral.success()) throw std::runtime_error(who + ": the stop's footed H-LIP QP failed: " + lateral.message);
  // Footholds at each segment's end: the settle keeps both feet, the step lands the rear foot beside the front one.
  const Eigen::Vector2d left_before = front == 0 ? front_foot : rear_foot;
  const Eigen::Vector2d right_before = front == 0 ? rear_foot : front_foot;
  const Eigen::Vector2d left_after = front == 0 ? front_foot : landed;
  const Eigen::Vector2d right_after = front == 0 ? landed : front_foot;
  AppendPhase(plan, settle, front_foot.x(), lat, lateral, 0, m, g, left_before, right_before);
  AppendPhase(plan, step, front_foot.x(), lat, lateral, n - 1, m, g, left_after, right_after);
  AppendPhase(plan, shift, front_foot.x(), lat, lateral, 2 * (n - 1), m, g, left_after, right_after);
  // The hold: a double support with the COM still at the midpoint (the point-foot H-LIP DSP row, ÿ = 0, at rest).
  WalkingPlanSegment s;
  s.start_time = plan.end_time();
  s.duration = stop.hold_duration_s;
  s.domain = WalkingDomain::kDoubleSupport;
  s.sagittal_x_offset = front_foot.x();
  Eigen::MatrixXd values = hold.sagittal.topRows(4), derivatives = hold.sagittal.middleRows(2, 4);
  values.row(0).array() -= front_foot.x();
  s.sagittal = PiecewisePolynomial::CubicHermite(hold.t, values, derivatives);
  s.sagittal_acceleration = PiecewisePolynomial::FirstOrderHold(hold.t, hold.sagittal.bottomRows(2));
  s.normal_forces = PiecewisePolynomial::FirstOrderHold(hold.t, hold.forces);
  s.lateral_start = lat.final_state;
  s.lambda = std::sqrt(g / lat.z0);
  s.lateral_pivot_y = mid.y();
  s.left_foothold = left_after;
  s.right_foothold = right_after;
  plan.AppendSegment(std::move(s));
  return plan;
}

}  // namespace rome
