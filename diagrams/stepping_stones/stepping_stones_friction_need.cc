#include "diagrams/stepping_stones/stepping_stones_friction_need.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace rome {

PlanFrictionNeed CalcPeriodicPlanFrictionNeed(double step_length_m, double step_height_m,
                                              double pre_impact_com_height_m,
                                              const MomentumRegulationPlannerParams& planner_params,
                                              const VerticalComMpcParams& mpc_params, int samples) {
  if (!(step_length_m > 0.0) || !std::isfinite(step_length_m) || !std::isfinite(step_height_m))
    throw std::invalid_argument("CalcPeriodicPlanFrictionNeed: the step (" + std::to_string(step_length_m) + ", " +
                                std::to_string(step_height_m) + ") m needs a finite length > 0");
  if (samples < 1)
    throw std::invalid_argument("CalcPeriodicPlanFrictionNeed: samples must be >= 1, got " + std::to_string(samples));
  const MomentumRegulationPlanner planner(planner_params);
  const double l = step_length_m, h = step_height_m, g = planner_params.gravity;
  // The post-impact state of the E* orbit, relative to the new stance foot.
  MomentumRegulationInput in;
  in.step_length = l;
  in.step_height = h;
  in.pre_impact_com_height = pre_impact_com_height_m;
  in.p_com_x = (planner_params.impact_fraction - 1.0) * l;
  in.p_com_z = pre_impact_com_height_m - h;
  in.L_y = planner.DesiredPostImpactMomentum(l, h, pre_impact_com_height_m);
  const double z0_hat = LinearInvertedPendulum::SlopeAdjustedHeight(in.p_com_x, in.p_com_z, l, h);
  in.pdot_com_x = in.L_y / z0_hat;
  const MomentumRegulationPlan plan = planner.Plan(in);
  const double T = plan.time_to_impact, lambda = std::sqrt(g / z0_hat);
  if (!std::isfinite(T) || !std::isfinite(plan.u_des) || !(z0_hat > 0.0))
    throw std::invalid_argument("CalcPeriodicPlanFrictionNeed: no finite plan for the step (" + std::to_string(l) +
                                ", " + std::to_string(h) + ") m");
  // Eq. (28) once from the post-impact state: with the plant on the plan, the receding-horizon re-solves continue it.
  VerticalComMpc mpc(mpc_params);
  const double zdot0 = (h / l) * in.pdot_com_x;
  if (mpc.Solve(in.p_com_z, zdot0, pre_impact_com_height_m, plan.u_des, T) != QpStatus::kOptimal)
    throw std::invalid_argument("CalcPeriodicPlanFrictionNeed: the vertical-COM QP failed for the step (" +
                                std::to_string(l) + ", " + std::to_string(h) + ") m");
  PlanFrictionNeed need;
  need.step_duration_s = T;
  need.u_des_mps = plan.u_des;
  need.mean_speed_mps = l / T;
  need.min_normal_force_fraction = std::numeric_limits<double>::infinity();
  for (int i = 0; i < samples; ++i) {
    const double t = T * (i + 0.5) / samples;
    const double x = in.p_com_x * std::cosh(lambda * t) + in.pdot_com_x / lambda * std::sinh(lambda * t);
    const double xddot = lambda * lambda * x;
    const double zddot = VerticalComMpc::EvaluatePlan(in.p_com_z, zdot0, mpc.inputs(), mpc.dt(), t)[2];
    const double fn = g + zddot;  // F_n / m
    const double ratio = fn > 0.0 ? std::abs(xddot) / fn : std::numeric_limits<double>::infinity();
    need.min_normal_force_fraction = std::min(need.min_normal_force_fraction, fn / g);
    if (ratio > need.max_ratio || i == 0) {
      need.max_ratio = ratio;
      need.time_of_max_s = t;
    }
  }
  return need;
}

}  // namespace rome
