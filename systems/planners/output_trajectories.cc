#include "systems/planners/output_trajectories.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace rome {
namespace {

std::string Num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

// de Casteljau evaluation of the Bernstein polynomial with coefficients c[0..n] (degree n) at τ.
double DeCasteljau(const double* c, int n, double tau) {
  double w[BezierCurve::kMaxControlPoints] = {};
  for (int k = 0; k <= n; ++k) w[k] = c[k];
  for (int r = 1; r <= n; ++r)
    for (int k = 0; k <= n - r; ++k) w[k] = (1 - tau) * w[k] + tau * w[k + 1];
  return w[0];
}

}  // namespace

ScalarDerivatives ToTimeDerivatives(const ScalarDerivatives& y, const Phase& phase) {
  return {y.value, y.first * phase.tau_dot, y.second * phase.tau_dot * phase.tau_dot + y.first * phase.tau_ddot};
}

Phase PhaseVariable::Saturate(Phase phase) const {
  if (!params_.saturate) return phase;
  if (phase.tau < 0) return {0.0, 0.0, 0.0};
  if (phase.tau > 1) return {1.0, 0.0, 0.0};
  return phase;
}

Phase PhaseVariable::StateBased(double p_com_x, double pdot_com_x, double pddot_com_x, double p_com_x0,
                                double p_com_xf) const {
  const double span = p_com_xf - p_com_x0;
  if (!(span != 0 && std::isfinite(span)))
    throw std::invalid_argument("PhaseVariable (Eq. (20)): the final COM position ε l_des (" + Num(p_com_xf) +
                                " m) must differ from the start position p_com0^x (" + Num(p_com_x0) + " m)");
  // Eq. (20).
  return Saturate({(p_com_x - p_com_x0) / span, pdot_com_x / span, pddot_com_x / span});
}

Phase PhaseVariable::TimeBased(double t, double step_start_time, double step_duration) const {
  if (!(step_duration > 0 && std::isfinite(step_duration)))
    throw std::invalid_argument("PhaseVariable (time-based, Sec. VI-D): step duration T_s must be positive, got " +
                                Num(step_duration) + " s");
  return Saturate({(t - step_start_time) / step_duration, 1.0 / step_duration, 0.0});
}

TorsoPitchCubic::TorsoPitchCubic(double phi_0, double phi_f) {
  // Eq. (22): c = [1 0 0 0; 0 1 0 0; 1 1 1 1; 0 1 2 3]⁻¹ [φ_0; 0; φ_f; 0], in closed form.
  const double d = phi_f - phi_0;
  c_ << phi_0, 0.0, 3.0 * d, -2.0 * d;
}

ScalarDerivatives TorsoPitchCubic::Evaluate(double tau) const {
  return {c_[0] + tau * (c_[1] + tau * (c_[2] + tau * c_[3])), c_[1] + tau * (2 * c_[2] + 3 * tau * c_[3]),
          2 * c_[2] + 6 * tau * c_[3]};
}

BezierCurve::BezierCurve(const Eigen::Ref<const Eigen::VectorXd>& control_points) {
  const int n = static_cast<int>(control_points.size());
  if (n < 2 || n > kMaxControlPoints)
    throw std::invalid_argument("BezierCurve: needs 2.." + std::to_string(kMaxControlPoints) + " control points, got " +
                                std::to_string(n));
  for (int k = 0; k < n; ++k) gamma_[k] = control_points[k];
  num_points_ = n;
}

ScalarDerivatives BezierCurve::Evaluate(double tau) const {
  const int M = degree();
  ScalarDerivatives out;
  out.value = DeCasteljau(gamma_, M, tau);
  double d1[kMaxControlPoints] = {}, d2[kMaxControlPoints] = {};
  for (int k = 0; k < M; ++k) d1[k] = gamma_[k + 1] - gamma_[k];
  out.first = M >= 1 ? M * DeCasteljau(d1, M - 1, tau) : 0.0;
  for (int k = 0; k + 1 < M; ++k) d2[k] = d1[k + 1] - d1[k];
  out.second = M >= 2 ? M * (M - 1) * DeCasteljau(d2, M - 2, tau) : 0.0;
  return out;
}

SwingFootBezier::SwingFootBezier(SwingFootBezierParams params, double p_sw0_x, double p_sw0_z, double step_length,
                                 double step_height)
    : params_(params), p_sw0_x_(p_sw0_x), step_length_(step_length), step_height_(step_height) {
  if (!(params_.strike_depth < 0))
    throw std::invalid_argument(
        "SwingFootBezier: parameter strike_depth (z_sw^neg) must be negative so that the foot strikes, got " +
        Num(params_.strike_depth) + " m");
  if (!(params_.horizontal_arrival_phase > 0 && params_.horizontal_arrival_phase <= 1))
    throw std::invalid_argument("SwingFootBezier: parameter horizontal_arrival_phase must be in (0, 1], got " +
                                Num(params_.horizontal_arrival_phase));
  if (params_.apex_shape == SwingApexShape::kClearStanceStone &&
      !(params_.stance_stone_half_length >= 0 && std::isfinite(params_.stance_stone_half_length) &&
        std::isfinite(params_.stance_stone_clearance)))
    throw std::invalid_argument("SwingFootBezier: parameters stance_stone_half_length (" +
                                Num(params_.stance_stone_half_length) + " m) and stance_stone_clearance (" +
                                Num(params_.stance_stone_clearance) + " m) must be finite, the length >= 0");
  if (!std::isfinite(p_sw0_x) || !std::isfinite(p_sw0_z) || !std::isfinite(step_length) || !std::isfinite(step_height))
    throw std::invalid_argument("SwingFootBezier: start position and step must be finite");
  switch (params_.apex_reference) {
    case SwingApexReference::kStanceFoot: apex_ = params_.clearance; break;
    case SwingApexReference::kHigherFoothold: apex_ = std::max(p_sw0_z, step_height) + params_.clearance; break;
    case SwingApexReference::kHighestStone: apex_ = std::max({p_sw0_z, 0.0, step_height}) + params_.clearance; break;
  }
  // Table under Eq. (24): b_h: [0, 0, 0, 1, 1, 1]; b_v: [p_sw0^z, z_max 1_3, h_des, h_des + z_neg].
  using Vector6d = Eigen::Matrix<double, 6, 1>;
  b_h_ = BezierCurve((Vector6d() << 0, 0, 0, 1, 1, 1).finished());
  b_v_ = BezierCurve(
      (Vector6d() << p_sw0_z, apex_, apex_, apex_, step_height, step_height + params_.strike_depth).finished());
  if (params_.lift_off_at_rest) b_v_.set_control_point(1, p_sw0_z);
  if (params_.apex_shape != SwingApexShape::kControlPoints) {
    if (!(apex_ > std::max(p_sw0_z, step_height)))
      throw std::invalid_argument("SwingFootBezier: exact apex height " + Num(apex_) +
                                  " m must lie above both the start height " + Num(p_sw0_z) +
                                  " m and the foothold height " + Num(step_height) + " m");
    SetExactPeak();
  }
  tau_touchdown_ = TouchdownParameter();
  if (params_.apex_shape == SwingApexShape::kClearStanceStone) {
    // The vertical curve runs on s τ (kAtPhaseEnd, s = τ_td, which depends on c) or on τ: a few fixed-point passes.
    const double c_exact = b_v_.control_point(params_.lift_off_at_rest ? 2 : 1);
    for (int iteration = 0; iteration < 20; ++iteration) {
      const double scale = params_.touchdown_timing == SwingTouchdownTiming::kAtPhaseEnd ? tau_touchdown_ : 1.0;
      double c = c_exact;
      // The stance stone's two edges (top at 0) and, optionally, the next stone's rear edge (top at the step height).
      const struct {
        double x, top;
        bool checked;
      } edges[] = {{-params_.stance_stone_half_length, 0.0, true},
                   {params_.stance_stone_half_length, 0.0, true},
                   {step_length_ - params_.stance_stone_half_length, step_height_, params_.clear_next_stone_rear_edge}};
      for (const auto& [edge, top, checked] : edges) {
        if (!checked) continue;
        const double tau = CrossingPhase(edge);
        if (!std::isfinite(tau)) continue;
        const double sigma = scale * tau;
        // b_v(σ) = B_0 γ_0 + (B_1 + B_2 + B_3) c + B_4 γ_4 + B_5 γ_5 = top + stance_stone_clearance.
        const double B0 = std::pow(1 - sigma, 5), B4 = 5 * std::pow(sigma, 4) * (1 - sigma), B5 = std::pow(sigma, 5);
        // lift_off_at_rest: γ_1 = γ_0 is fixed, so B_1 moves to the fixed part.
        const double B1 = params_.lift_off_at_rest ? 5 * sigma * std::pow(1 - sigma, 4) : 0.0;
        const double middle = 1 - B0 - B1 - B4 - B5;
        if (middle > 1e-6)
          c = std::max(c, (top + params_.stance_stone_clearance - (B0 + B1) * b_v_.control_point(0) -
                           B4 * b_v_.control_point(4) - B5 * b_v_.control_point(5)) /
                              middle);
      }
      for (int k = params_.lift_off_at_rest ? 2 : 1; k <= 3; ++k) b_v_.set_control_point(k, c);
      const double previous = tau_touchdown_;
      tau_touchdown_ = TouchdownParameter();
      if (std::abs(tau_touchdown_ - previous) < 1e-12) break;
    }
  }
  if (!(tau_touchdown_ > 0) && params_.touchdown_timing == SwingTouchdownTiming::kAtPhaseEnd)
    throw std::invalid_argument(
        "SwingFootBezier: touchdown_timing kAtPhaseEnd needs the swing curve to rise above the foothold height " +
        Num(step_height) + " m; its peak is " + Num(MaxHeight()) + " m");
}

void SwingFootBezier::SetExactPeak() {
  // F(c) = max_τ b_v(τ; c) is convex and increasing in c (γ_1..3 = c); dF/dc = B_1 + B_2 + B_3 at the argmax
  // (B_2 + B_3 with lift_off_at_rest).
  double c = apex_;
  const int first = params_.lift_off_at_rest ? 2 : 1;  // γ_1 = γ_0 is fixed with lift_off_at_rest
  for (int iteration = 0; iteration < 100; ++iteration) {
    for (int k = first; k <= 3; ++k) b_v_.set_control_point(k, c);
    double tau_max = 0;
    const double F = MaxHeight(&tau_max);
    const double m = 1 - std::pow(1 - tau_max, 5) - 5 * tau_max * tau_max * tau_max * tau_max * (1 - tau_max) -
                     std::pow(tau_max, 5) - (first == 2 ? 5 * tau_max * std::pow(1 - tau_max, 4) : 0.0);
    if (std::abs(F - apex_) <= 1e-14 * (1 + std::abs(apex_)) || !(m > 0)) break;
    c -= (F - apex_) / m;
  }
}

double SwingFootBezier::TouchdownParameter() const {
  // τ_td: where b_v comes down through h_des (b_v(1) = h_des + z_neg < h_des). Bisection between the apex and 1.
  double tau_apex = 0;
  const double peak = MaxHeight(&tau_apex);
  if (!(peak > step_height_)) return 0.0;
  double lo = tau_apex, hi = 1.0;
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (b_v_.Evaluate(mid).value > step_height_ ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double SwingFootBezier::CrossingPhase(double x) const {
  if (!(p_sw0_x_ < x && x < step_length_)) return std::numeric_limits<double>::quiet_NaN();
  // Eq. (23): p_sw^x = x where b_h = (x − p_sw0^x) / (l − p_sw0^x); b_h is increasing, so bisection.
  const double target = (x - p_sw0_x_) / (step_length_ - p_sw0_x_);
  double lo = 0.0, hi = 1.0;
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (b_h_.Evaluate(mid).value < target ? lo : hi) = mid;
  }
  return params_.horizontal_arrival_phase * 0.5 * (lo + hi);
}

double SwingFootBezier::touchdown_phase() const {
  return params_.touchdown_timing == SwingTouchdownTiming::kAtPhaseEnd ? 1.0 : tau_touchdown_;
}

ScalarDerivatives SwingFootBezier::X(double tau) const {
  // Eq. (23). Beyond τ = 1 (only reached with kAtPhaseEnd) the foot stays at l_des.
  const double a = params_.horizontal_arrival_phase;
  if (tau >= a) return {step_length_, 0.0, 0.0};
  const ScalarDerivatives b = b_h_.Evaluate(tau / a);
  const double span = step_length_ - p_sw0_x_;
  return {(1 - b.value) * p_sw0_x_ + b.value * step_length_, b.first * span / a, b.second * span / (a * a)};
}

ScalarDerivatives SwingFootBezier::Z(double tau) const {
  if (params_.touchdown_timing == SwingTouchdownTiming::kPaperPhase) return b_v_.Evaluate(tau);  // Eq. (24)
  // Eq. (24) re-timed: b_v(τ_td τ); past τ = 1 a straight continuation with the touchdown slope.
  const double s = tau_touchdown_;
  if (tau > 1.0) {
    const ScalarDerivatives end = b_v_.Evaluate(s);
    return {end.value + s * end.first * (tau - 1.0), s * end.first, 0.0};
  }
  const ScalarDerivatives b = b_v_.Evaluate(s * tau);
  return {b.value, s * b.first, s * s * b.second};
}

double SwingFootBezier::MaxHeight(double* tau_at_max) const {
  constexpr int kSamples = 200;
  int best = 0;
  double best_value = -INFINITY;
  for (int k = 0; k <= kSamples; ++k) {
    const double v = b_v_.Evaluate(static_cast<double>(k) / kSamples).value;
    if (v > best_value) best_value = v, best = k;
  }
  double tau = static_cast<double>(best) / kSamples;
  if (best > 0 && best < kSamples) {
    // Newton on dz/dτ = 0 from the best sample.
    for (int iteration = 0; iteration < 30; ++iteration) {
      const ScalarDerivatives z = b_v_.Evaluate(tau);
      if (!(z.second < 0)) break;
      const double step = z.first / z.second;
      tau = std::clamp(tau - step, 0.0, 1.0);
      if (std::abs(step) < 1e-15) break;
    }
  }
  const double value = b_v_.Evaluate(tau).value;
  if (value < best_value) tau = static_cast<double>(best) / kSamples;
  if (tau_at_max != nullptr) *tau_at_max = tau;
  return std::max(value, best_value);
}

SteppingStonesOutputTrajectories::SteppingStonesOutputTrajectories(PhaseVariableParams phase_params,
                                                                   SwingFootBezierParams swing_params,
                                                                   const StepOutputParameters& step)
    : phase_(phase_params),
      raw_phase_({.type = phase_params.type, .saturate = false}),
      step_(step),
      torso_(step.phi_0, step.phi_f),
      swing_(swing_params, step.p_sw0_x, step.p_sw0_z, step.step_length, step.step_height) {}

Phase SteppingStonesOutputTrajectories::CalcPhase(double t, double p_com_x, double pdot_com_x,
                                                  double pddot_com_x) const {
  if (phase_.params().type == PhaseType::kTimeBased)
    return phase_.TimeBased(t, step_.step_start_time, step_.step_duration);
  return phase_.StateBased(p_com_x, pdot_com_x, pddot_com_x, step_.p_com_x0, step_.impact_fraction * step_.step_length);
}

DesiredOutputs SteppingStonesOutputTrajectories::Evaluate(double t, double p_com_x, double pdot_com_x,
                                                          double pddot_com_x,
                                                          const Eigen::Vector3d& com_height_desired) const {
  DesiredOutputs out;
  out.phase = CalcPhase(t, p_com_x, pdot_com_x, pddot_com_x);
  const double tau = out.phase.tau;
  // kAtPhaseEnd: past τ = 1 the swing foot keeps descending along the unsaturated phase.
  Phase swing_z_phase = out.phase;
  if (swing_.params().touchdown_timing == SwingTouchdownTiming::kAtPhaseEnd) {
    const Phase raw = phase_.params().type == PhaseType::kTimeBased
                          ? raw_phase_.TimeBased(t, step_.step_start_time, step_.step_duration)
                          : raw_phase_.StateBased(p_com_x, pdot_com_x, pddot_com_x, step_.p_com_x0,
                                                  step_.impact_fraction * step_.step_length);
    if (raw.tau > 1.0) swing_z_phase = raw;
  }
  const ScalarDerivatives parts[4] = {ToTimeDerivatives(torso_.Evaluate(tau), out.phase),
                                      {com_height_desired[0], com_height_desired[1], com_height_desired[2]},
                                      ToTimeDerivatives(swing_.X(tau), out.phase),
                                      ToTimeDerivatives(swing_.Z(swing_z_phase.tau), swing_z_phase)};
  for (int i = 0; i < 4; ++i) {
    out.y[i] = parts[i].value;
    out.ydot[i] = parts[i].first;
    out.yddot[i] = parts[i].second;
  }
  return out;
}

}  // namespace rome
