#include "systems/planners/momentum_regulation_planner.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace rome {
namespace {

std::string Num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

void Require(bool condition, const char* what, double value) {
  if (!condition)
    throw std::invalid_argument(std::string("MomentumRegulationPlanner: ") + what + ", got " + Num(value));
}

}  // namespace

MomentumRegulationPlanner::MomentumRegulationPlanner(MomentumRegulationPlannerParams params) : params_(params) {
  Require(std::isfinite(params_.target_orbital_energy), "parameter target_orbital_energy (E*, m²/s²) must be finite",
          params_.target_orbital_energy);
  Require(params_.impact_fraction > 0 && params_.impact_fraction <= 1,
          "parameter impact_fraction (ε) must be in (0, 1]", params_.impact_fraction);
  Require(params_.gravity > 0 && std::isfinite(params_.gravity), "parameter gravity (m/s²) must be positive",
          params_.gravity);
  Require(params_.min_time_to_impact_s > 0, "parameter min_time_to_impact_s must be positive",
          params_.min_time_to_impact_s);
  Require(params_.max_time_to_impact_s >= params_.min_time_to_impact_s && std::isfinite(params_.max_time_to_impact_s),
          "parameter max_time_to_impact_s must be finite and >= min_time_to_impact_s", params_.max_time_to_impact_s);
  Require(
      !std::isnan(params_.min_pre_impact_vertical_velocity_mps) && params_.min_pre_impact_vertical_velocity_mps <= 0,
      "parameter min_pre_impact_vertical_velocity_mps (m/s) must be <= 0 or -infinity",
      params_.min_pre_impact_vertical_velocity_mps);
}

double MomentumRegulationPlanner::DesiredPostImpactMomentum(double step_length, double step_height,
                                                            double pre_impact_com_height) const {
  Require(step_length > 0 && std::isfinite(step_length), "step length l_des (m) must be positive", step_length);
  const double l = step_length, h = step_height;
  const double p_x_plus = (params_.impact_fraction - 1.0) * l;
  // Slope-adjusted post-impact height (the paper's p_com^{z+}).
  const double z0_plus = pre_impact_com_height - h - h / l * p_x_plus;
  Require(z0_plus > 0 && std::isfinite(z0_plus),
          "post-impact COM height above the virtual slope z0+ (m) must be positive", z0_plus);
  const double lambda_squared = params_.gravity / z0_plus;
  const double xdot_squared = params_.target_orbital_energy + lambda_squared * p_x_plus * p_x_plus;
  Require(xdot_squared >= 0,
          "target orbital energy E* is below −λ² (p^{x+})²: no forward orbit through the post-impact position; E* + "
          "λ²(p^{x+})² =",
          xdot_squared);
  return z0_plus * std::sqrt(xdot_squared);
}

double MomentumRegulationPlanner::PredictPreImpactMomentum(double p_com_x, double L_y, double z0_hat,
                                                           double pre_impact_position, double gravity, bool* clamped) {
  // Eq. (25).
  const double radicand =
      z0_hat * gravity * (pre_impact_position * pre_impact_position - p_com_x * p_com_x) + L_y * L_y;
  if (clamped != nullptr) *clamped = radicand < 0;
  return radicand < 0 ? 0.0 : std::sqrt(radicand);
}

double MomentumRegulationPlanner::DesiredPreImpactVerticalVelocity(double step_length, double step_height, double L_des,
                                                                   double L_pre_impact, double pdot_com_x_pre_impact) {
  // Eq. (18) / (26).
  return (L_des - L_pre_impact + step_height * pdot_com_x_pre_impact) / step_length;
}

Eigen::Vector2d MomentumRegulationPlanner::ImpactMap(double p_com_x_pre, double L_pre, double pdot_com_x_pre,
                                                     double pdot_com_z_pre, double step_length, double step_height) {
  // Eq. (17).
  return Eigen::Vector2d(p_com_x_pre - step_length,
                         L_pre + step_length * pdot_com_z_pre - step_height * pdot_com_x_pre);
}

MomentumRegulationPlan MomentumRegulationPlanner::Plan(const MomentumRegulationInput& in) const {
  Require(std::isfinite(in.p_com_x), "COM position p_com_x (m) must be finite", in.p_com_x);
  Require(std::isfinite(in.p_com_z), "COM height p_com_z (m) must be finite", in.p_com_z);
  Require(std::isfinite(in.pdot_com_x), "COM velocity pdot_com_x (m/s) must be finite", in.pdot_com_x);
  Require(std::isfinite(in.L_y), "angular momentum L_y (m²/s) must be finite", in.L_y);
  Require(std::isfinite(in.step_height), "step height h_des (m) must be finite", in.step_height);
  Require(std::isfinite(in.pre_impact_com_height), "pre-impact COM height (m) must be finite",
          in.pre_impact_com_height);
  Require(in.step_length > 0 && std::isfinite(in.step_length), "step length l_des (m) must be positive",
          in.step_length);
  const double l = in.step_length, h = in.step_height;

  MomentumRegulationPlan plan;
  plan.pre_impact_position = params_.impact_fraction * l;
  plan.slope_adjusted_height = LinearInvertedPendulum::SlopeAdjustedHeight(in.p_com_x, in.p_com_z, l, h);
  Require(plan.slope_adjusted_height > 0,
          "COM height above the virtual slope ẑ0 = p^z − (h/l) p^x (m) must be positive", plan.slope_adjusted_height);

  const double p_z_minus = params_.pre_impact_height_source == PreImpactHeightSource::kDesiredPreImpactHeight
                               ? in.pre_impact_com_height
                               : in.p_com_z;
  plan.L_des = DesiredPostImpactMomentum(l, h, p_z_minus);
  plan.post_impact_height = p_z_minus - h - h / l * (params_.impact_fraction - 1.0) * l;

  bool clamped = false;
  plan.L_pre_impact = PredictPreImpactMomentum(in.p_com_x, in.L_y, plan.slope_adjusted_height, plan.pre_impact_position,
                                               params_.gravity, &clamped);
  if (clamped) plan.status |= MomentumRegulationPlan::kPreImpactMomentumClamped;
  plan.u_des = DesiredPreImpactVerticalVelocity(l, h, plan.L_des, plan.L_pre_impact, in.pdot_com_x);
  if (plan.u_des < params_.min_pre_impact_vertical_velocity_mps) {
    plan.u_des = params_.min_pre_impact_vertical_velocity_mps;
    plan.status |= MomentumRegulationPlan::kPreImpactVelocityClamped;
  }

  // Eq. (27).
  const LinearInvertedPendulum lip({.z0 = plan.slope_adjusted_height, .gravity = params_.gravity});
  const TimeToImpact t_i = lip.TimeToReach(plan.pre_impact_position, Eigen::Vector2d(in.p_com_x, in.L_y));
  double T = 0;
  switch (t_i.status) {
    case TimeToImpact::Status::kReached:
      plan.time_to_impact_raw = t_i.time_s;
      T = t_i.time_s;
      if (T < params_.min_time_to_impact_s || T > params_.max_time_to_impact_s)
        plan.status |= MomentumRegulationPlan::kTimeToImpactClamped;
      break;
    case TimeToImpact::Status::kInsufficientEnergy:
      plan.status |= MomentumRegulationPlan::kTimeToImpactInsufficientEnergy;
      T = params_.max_time_to_impact_s;
      break;
    case TimeToImpact::Status::kNotReachedForward:
      plan.status |= MomentumRegulationPlan::kTimeToImpactPassed;
      T = params_.min_time_to_impact_s;
      break;
  }
  plan.time_to_impact = std::clamp(T, params_.min_time_to_impact_s, params_.max_time_to_impact_s);
  return plan;
}

}  // namespace rome
