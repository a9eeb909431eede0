#include "diagrams/walking/walking_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "diagrams/walking/pre_impact_sampler.h"
#include "systems/multibody/multibody_kinematics.h"

namespace rome {

namespace {

void Require(bool ok, const char* field, double value, const char* range) {
  if (ok) return;
  std::ostringstream os;
  os << "WalkingRunParams: " << field << " = " << value << " is outside " << range;
  throw std::invalid_argument(os.str());
}

double Percentile(std::vector<double> x, double p) {
  if (x.empty()) return 0.0;
  std::sort(x.begin(), x.end());
  return x[std::min(x.size() - 1, static_cast<size_t>(p * (x.size() - 1) + 0.5))];
}

// Convergence after each transition: the largest step-to-step change of the pre-impact states from its own touchdown
// to the next transition's, from the from_step-th periodic touchdown on (−1 with fewer).
std::vector<double> PreImpactChanges(const WalkingRunResult& r, int from_step) {
  std::vector<double> changes;
  for (size_t j = 0; j < r.transition_ends_s.size(); ++j) {
    const double begin = r.transition_ends_s[j] - 0.05,
                 end = j + 1 < r.transition_ends_s.size() ? r.transition_ends_s[j + 1] - 0.05 : 1e9;
    std::vector<WalkingRunResult::ComState>
        states;  // states[0]: the transition's own touchdown; states[k]: the k-th periodic one
    for (const auto& [time, state] : r.pre_impact_states)
      if (time > begin && time < end) states.push_back(state);
    double worst = -1.0;
    for (size_t k = static_cast<size_t>(from_step); k < states.size(); ++k)
      worst = std::max(worst, (states[k] - states[k - 1]).norm());
    changes.push_back(worst);
  }
  return changes;
}

}  // namespace

void WalkingRunParams::Validate() const {
  Require(std::isnan(end_time_s) || std::isfinite(end_time_s), "end_time_s", end_time_s,
          "the finite numbers (NaN: from the plan)");
  Require(trailing_steps >= 0 && trailing_steps <= 1000, "trailing_steps", trailing_steps, "[0, 1000]");
  Require(std::isfinite(start_time_s) && start_time_s >= 0, "start_time_s", start_time_s, "[0, inf) s");
  Require(foothold_tolerance_m > 0 && foothold_tolerance_m <= 0.5, "foothold_tolerance_m", foothold_tolerance_m,
          "(0, 0.5] m");
  Require(tick_period_s > 0 && tick_period_s <= 0.1, "tick_period_s", tick_period_s, "(0, 0.1] s");
  Require(band_settle_s >= 0 && band_settle_s <= 1, "band_settle_s", band_settle_s, "[0, 1] s");
  Require(band_slack_mg >= 0 && band_slack_mg <= 1, "band_slack_mg", band_slack_mg, "[0, 1]");
  Require(convergence_from_step >= 1 && convergence_from_step <= 1000, "convergence_from_step", convergence_from_step,
          "[1, 1000]");
  Require(at_rest_offset_m > 0 && at_rest_offset_m <= 0.1, "at_rest_offset_m", at_rest_offset_m, "(0, 0.1] m");
  Require(at_rest_speed_mps > 0 && at_rest_speed_mps <= 0.1, "at_rest_speed_mps", at_rest_speed_mps, "(0, 0.1] m/s");
}

StandingMeasure MeasureStanding(const MultibodyModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  MultibodyWorkspace ws(model);
  const Eigen::Vector3d com = CalcComPosition(model, ws, q), vcom = CalcComVelocity(model, ws, q, v);
  const int left = model.contacts()[model.ContactIndex("left_foot")].body;
  const int right = model.contacts()[model.ContactIndex("right_foot")].body;
  const Eigen::Vector3d pl = CalcLinkPose(model, ws, q, left).translation();
  const Eigen::Vector3d pr = CalcLinkPose(model, ws, q, right).translation();
  StandingMeasure r;
  r.com_to_feet_midpoint_m = (com.head<2>() - 0.5 * (pl + pr).head<2>()).norm();
  r.com_speed_mps = vcom.norm();
  r.feet_gap_x_m = std::abs(pl.x() - pr.x());
  return r;
}

double WalkingRunEndTime(const WalkingPlan& plan, const WalkingRunParams& params) {
  if (!std::isnan(params.end_time_s)) return params.end_time_s;
  const std::vector<WalkingPlanSegment>& segs = plan.segments();
  if (segs.size() < 2) throw std::invalid_argument("RunWalking: the plan has fewer than 2 segments");
  // The plan ends with a DSP after its last SSP: one step of its last gait is those two segments.
  const double step_s = segs[segs.size() - 2].duration + segs.back().duration;
  return plan.end_time() - params.trailing_steps * step_s;
}

std::string WalkingRunResult::status_kind() const {
  // The run always goes to the plan's end: reaching it is judged by the success rule, never left as a "limit".
  return interrupted ? "interrupted" : success ? "success" : "failure";
}

std::string WalkingRunResult::ToJson() const {
  nlohmann::json s;
  s["success"] = success;
  s["status_kind"] = status_kind();
  s["status"] = status.ToString();
  s["fell"] = fell;
  s["steps_completed"] = steps_completed;
  s["steps_planned"] = steps_planned;
  s["pre_impact_state_change_from_step5"] =
      pre_impact_state_change_from_step5;  // per transition; -1: too few touchdowns
  // Each touchdown's pre-impact COM state about the stance ankle, y mirrored in right stance: [t, x, y, z, ẋ, ẏ, ż].
  s["pre_impact_states"] = nlohmann::json::array();
  for (const auto& [time, state] : pre_impact_states) {
    nlohmann::json row = {time};
    for (int i = 0; i < 6; ++i) row.push_back(state[i]);
    s["pre_impact_states"].push_back(row);
  }
  s["touchdowns_off_target"] = touchdowns_off_target;
  s["largest_touchdown_error_m"] = largest_touchdown_error_m;
  s["com_rms_error_m"] = {com_rms_error_m.x(), com_rms_error_m.y(), com_rms_error_m.z()};
  s["com_max_error_m"] = {com_max_error_m.x(), com_max_error_m.y(), com_max_error_m.z()};
  s["pelvis_max_orientation_error_rad"] = pelvis_max_orientation_error_rad;
  s["force_in_band_fraction"] = force_in_band_fraction;
  s["force_in_band_fraction_strict"] = force_in_band_fraction_strict;
  s["liftoff_normal_force_max_N"] = liftoff_normal_force_max_N;
  s["contact_violations"] = contact.violations;
  s["first_contact_violation"] = contact.first_violation;
  s["joint_limit_violations"] = joint_limits.violations;
  s["first_joint_limit_violation"] = joint_limits.first_violation;
  s["joint_limit_min_margin_rad"] =
      std::isfinite(joint_limit_min_margin) ? nlohmann::json(joint_limit_min_margin) : nlohmann::json();  // null: none
  s["joint_limit_min_margin_at"] = joint_limit_min_margin_at;
  s["min_stance_normal_force_N"] = contact.samples > 0 ? contact.min_normal_force_N : 0.0;
  s["max_friction_ratio"] = contact.max_friction_ratio;
  s["qp_infeasible_ticks"] = qp_infeasible_ticks;
  s["qp_fallbacks"] = qp_fallbacks;
  s["clf_row_active_fraction"] = clf_row_active_fraction;
  s["clf_relaxation_max"] = clf_relaxation_max;
  s["qp_solve_us_median"] = qp_solve_us_median;
  s["qp_solve_us_p99"] = qp_solve_us_p99;
  s["realtime_factor"] = realtime_factor();
  s["simulated_s"] = simulated_s;
  // Walk-to-stand (judge_standing_end): the plant's end state against the at-rest rule; null otherwise.
  s["standing_end"] = nullptr;
  if (standing_end_judged)
    s["standing_end"] = {{"com_to_feet_midpoint_m", standing_end.com_to_feet_midpoint_m},
                         {"com_speed_mps", standing_end.com_speed_mps},
                         {"feet_gap_x_m", standing_end.feet_gap_x_m},
                         {"at_rest", at_rest}};
  return s.dump();
}

namespace {

// Every single support of the plan that ends by the end time should end in a step; the transitions' ends.
void CountPlannedSteps(const WalkingPlan& plan, WalkingRunResult& r) {
  for (const WalkingPlanSegment& seg : plan.segments()) {
    if (seg.domain == WalkingDomain::kDoubleSupport || seg.start_time + seg.duration > r.end_time_s + 1e-9) continue;
    ++r.steps_planned;
    if (seg.lateral_nodes.cols() > 0) r.transition_ends_s.push_back(seg.start_time + seg.duration);
  }
}

// The CLF-QP's counts at the end of the run (none without a CLF-QP) and the solve-time percentiles.
void ReadClfQpTotals(const Diagram& diagram, const ClfQpController* clf, const Context& root,
                     const std::vector<double>& solve_us, WalkingRunResult& r) {
  if (clf != nullptr) {
    const LeafContext& cc = diagram.GetSubsystemContext(*clf, root);
    r.qp_infeasible_ticks = clf->EvalOutput(cc, "qp_failures")[0];
    r.qp_fallbacks = clf->EvalOutput(cc, "fallbacks").sum();
    const Eigen::VectorXd& activity = clf->EvalOutput(cc, "clf_activity");  // [CLF row active, solved] updates
    r.clf_row_active_fraction = activity[1] > 0 ? activity[0] / activity[1] : 0.0;
  }
  r.qp_solve_us_median = Percentile(solve_us, 0.5);
  r.qp_solve_us_p99 = Percentile(solve_us, 0.99);
}

// The success rule (walking_run.h) on the counts in r, with the plant's end state (standing_end, at_rest).
void JudgeRun(const WalkingDiagram& walking, const MultibodyModel& model, const Context& root,
              const WalkingRunParams& params, WalkingRunResult& r) {
  const Eigen::VectorXd& x = WalkingPlantEulerState(walking, root);
  const int nv = model.nv();
  r.standing_end = MeasureStanding(model, x.head(nv), x.tail(nv));
  r.at_rest = r.standing_end.com_to_feet_midpoint_m <= params.at_rest_offset_m &&
              r.standing_end.com_speed_mps <= params.at_rest_speed_mps;
  r.standing_end_judged = params.judge_standing_end;
  r.success = !r.fell && r.steps_completed == r.steps_planned && r.touchdowns_off_target == 0 &&
              r.contact.violations == 0 && (r.at_rest || !params.judge_standing_end);
}

// Puts the plant at the run's start (WalkingStandingPose in double support, at rest or on the plan's orbit) and a
// sensor latency's history at that state (it has been reading it); returns the pose.
Eigen::VectorXd SetWalkingStart(const WalkingDiagram& walking, const WalkingRunParams& params, Context& root) {
  const MultibodyModel& model = walking.plant_euler_model ? *walking.plant_euler_model : walking.plant->model();
  const Eigen::VectorXd q = WalkingStandingPose(model, walking.plan, params.start_time_s);
  SetWalkingPlantState(walking, root, q,
                       params.start_at_rest ? Eigen::VectorXd::Zero(model.nv())
                                            : WalkingInitialVelocity(model, q, walking.plan, params.start_time_s),
                       "double_support");
  if (const DelayLine* delay = walking.perturbation_blocks.sensor_latency)
    delay->SetHistory(walking.diagram->GetMutableSubsystemContext(*delay, root),
                      walking.plant->EvalOutput(walking.diagram->GetSubsystemContext(*walking.plant, root), "state"));
  return q;
}

}  // namespace

WalkingRunResult RunWalking(const WalkingDiagram& walking, const WalkingRunParams& params,
                            const WalkingRunObserver& observer) {
  params.Validate();
  if (walking.diagram == nullptr || walking.plant == nullptr)
    throw std::invalid_argument("RunWalking: the WalkingDiagram is not built");
  const Diagram& diagram = *walking.diagram;
  const ContactPlant& plant = *walking.plant;
  const MultibodyModel& model = walking.plant_euler_model ? *walking.plant_euler_model : plant.model();  // Euler
  const WalkingPlan& plan = walking.plan;
  const ClfQpController* clf = walking.clf_qp;
  WalkingRunResult r;
  r.start_time_s = params.start_time_s;
  r.end_time_s = WalkingRunEndTime(plan, params);
  if (!(r.end_time_s > r.start_time_s))
    throw std::invalid_argument("RunWalking: the end time " + std::to_string(r.end_time_s) +
                                " s is not after the start " + std::to_string(r.start_time_s) + " s");

  CountPlannedSteps(plan, r);

  Simulator sim(diagram, params.simulator);
  sim.get_mutable_context().SetTime(params.start_time_s);
  const Eigen::VectorXd q_init = SetWalkingStart(walking, params, sim.get_mutable_context());
  r.joint_limits.Record(model, params.start_time_s, q_init);  // joint stops may end the run here, before a sample

  // The band is the controller's reference (the plan of the nominal model), so its slack is of the nominal m g, not
  // of the plant's, which a mass-scale perturbation changes.
  const double mg = (walking.model != nullptr ? *walking.model : model).total_mass() * 9.81;
  const double band =
      clf != nullptr ? clf->params().force_band_halfwidth : WalkingDiagramParams{}.controller.force_band_halfwidth;
  const double ticks_per_s = 1.0 / params.tick_period_s;
  const double after_first_step = plan.segments().size() > 2 ? plan.segments()[2].start_time : 0.0;
  const int left_foot = model.BodyIndex("left_foot"), right_foot = model.BodyIndex("right_foot");
  const int u_port = plant.GetInputPortIndex("u");
  const int pelvis[3] = {model.VelocityIndex("base_roll"), model.VelocityIndex("base_pitch"),
                         model.VelocityIndex("base_yaw")};
  MultibodyWorkspace ws(model);
  PreImpactSampler single_support_com;
  long tick = -1, band_ticks = 0, band_in = 0, band_in_strict = 0, n_err = 0;
  int last_mode = kWalkingDoubleSupport;
  double last_touchdown = -1.0;
  Eigen::Vector2d last_fz = Eigen::Vector2d::Zero();
  Eigen::Vector3d sum_sq = Eigen::Vector3d::Zero();
  std::vector<double> solve_us;
  solve_us.reserve(static_cast<size_t>(std::max(0.0, (r.end_time_s - r.start_time_s) * ticks_per_s)) + 2);
  WalkingRunSample sample;
  const int nv = model.nv();
  Eigen::VectorXd q_euler(nv), v_euler(nv);

  sim.set_monitor([&](const Context& c) {
    const double t = c.time();
    const LeafContext& ctx = diagram.GetSubsystemContext(plant, c);
    r.contact.Record(plant, ctx);
    ++r.samples;
    const int mode = plant.EvalTypedOutput<int>(ctx, "mode");
    const Eigen::VectorXd& f = plant.EvalOutput(ctx, "contact_forces");
    const Eigen::VectorXd& x = WalkingPlantEulerState(walking, c);
    q_euler = x.head(nv), v_euler = x.tail(nv);  // sized before the run: no allocation
    const Eigen::VectorXd &q = q_euler, &v = v_euler;
    r.contact_violation_port_samples += plant.EvalOutput(ctx, "contact_violation").cwiseAbs().sum() > 0 ? 1 : 0;
    r.joint_limits.Record(model, t, q);
    const bool in_double = mode == kWalkingDoubleSupport, was_double = last_mode == kWalkingDoubleSupport;
    if ((in_double && !was_double) || (!in_double && !was_double && mode != last_mode)) {  // a touchdown
      const bool right_landed = last_mode == kWalkingLeftStance;
      r.pre_impact_states.push_back({t, single_support_com.At(t)});
      const Eigen::Vector2d ankle =
          CalcLinkPose(model, ws, q, right_landed ? right_foot : left_foot).translation().head<2>();
      const WalkingReference ref = plan.Sample(t);
      const double error = (ankle - (right_landed ? ref.right_foothold : ref.left_foothold)).norm();
      r.largest_touchdown_error_m = std::max(r.largest_touchdown_error_m, error);
      if (error <= params.foothold_tolerance_m)
        ++r.steps_completed;
      else
        ++r.touchdowns_off_target;
      if (r.first_touchdown_time_s < 0) r.first_touchdown_time_s = t;
      last_touchdown = t;
    }
    if (!in_double && was_double) {  // a lift-off: the plant's force on the foot just before it left
      ++r.liftoffs;
      if (r.first_liftoff_time_s < 0) r.first_liftoff_time_s = t;
      r.liftoff_normal_force_max_N =
          std::max(r.liftoff_normal_force_max_N, mode == kWalkingLeftStance ? last_fz[1] : last_fz[0]);
    }
    last_mode = mode;
    last_fz << f[2], f[5];
    if (!in_double) {  // single support: the COM about the stance ankle, y mirrored in right stance (P2 alternates)
      const bool left_stance = mode == kWalkingLeftStance;
      const Eigen::Vector3d p = CalcComPosition(model, ws, q), pv = CalcComVelocity(model, ws, q, v);
      const Eigen::Vector3d foot = CalcLinkPose(model, ws, q, left_stance ? left_foot : right_foot).translation();
      const double mirror = left_stance ? 1.0 : -1.0;
      PreImpactSampler::State com_state;
      com_state << p.x() - foot.x(), mirror * (p.y() - foot.y()), p.z(), pv.x(), mirror * pv.y(), pv.z();
      single_support_com.Record(t, com_state);
    }
    const long k = static_cast<long>(std::floor(t * ticks_per_s + 1e-9));
    sample.t = t, sample.mode = mode, sample.tick = k != tick, sample.tick_index = k;
    sample.q = &q, sample.v = &v, sample.contact_forces = &f, sample.u = &plant.EvalInput(ctx, u_port);
    if (sample.tick) {  // once per control tick
      tick = k;
      ++r.ticks;
      sample.com = CalcComPosition(model, ws, q);
      sample.com_velocity = CalcComVelocity(model, ws, q, v);
      sample.reference = plan.Sample(t);
      const WalkingReference& ref = sample.reference;
      if (clf != nullptr) {
        const LeafContext& cc = diagram.GetSubsystemContext(*clf, c);
        solve_us.push_back(1e6 * clf->EvalOutput(cc, "solve_time_s")[0]);
        r.clf_relaxation_max = std::max(r.clf_relaxation_max, clf->EvalOutput(cc, "delta")[0]);
      }
      for (int a : pelvis)
        r.pelvis_max_orientation_error_rad = std::max(r.pelvis_max_orientation_error_rad, std::abs(q[a]));
      if (t > after_first_step) {
        const Eigen::Vector3d e = (sample.com - ref.com_position).cwiseAbs();
        sum_sq += e.cwiseProduct(e);
        r.com_max_error_m = r.com_max_error_m.cwiseMax(e);
        ++n_err;
      }
      if (last_touchdown < 0 || t > last_touchdown + params.band_settle_s) {
        for (int foot = 0; foot < 2; ++foot) {
          const double fz = f[3 * foot + 2], fref = ref.normal_force[foot];
          band_in += (fz >= (1 - band) * fref - params.band_slack_mg * mg &&
                      fz <= (1 + band) * fref + params.band_slack_mg * mg)
                         ? 1
                         : 0;
          band_in_strict += (fz >= (1 - band) * fref && fz <= (1 + band) * fref) ? 1 : 0;  // Eq. (25) with no slack
          ++band_ticks;
        }
      }
    }
    sample.steps = r.steps_completed;
    if (observer) observer(c, sample);
    return EventStatus::Succeeded();
  });

  const auto wall0 = std::chrono::steady_clock::now();
  r.status = sim.AdvanceTo(r.end_time_s);
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  r.simulated_s = sim.get_context().time();
  r.interrupted = r.status.kind() == SimulatorStatus::Kind::kInterrupted;
  r.fell = r.status.kind() != SimulatorStatus::Kind::kLimit && !r.interrupted;
  r.pre_impact_state_change_from_step5 = PreImpactChanges(r, params.convergence_from_step);
  JudgeRun(walking, model, sim.get_context(), params, r);
  r.joint_limit_min_margin = r.joint_limits.SmallestMargin(model, &r.joint_limit_min_margin_at);
  if (n_err > 0) r.com_rms_error_m = (sum_sq / static_cast<double>(n_err)).cwiseSqrt();
  r.force_in_band_fraction = band_ticks ? static_cast<double>(band_in) / band_ticks : 0.0;
  r.force_in_band_fraction_strict = band_ticks ? static_cast<double>(band_in_strict) / band_ticks : 0.0;
  r.band_samples = band_ticks;
  ReadClfQpTotals(diagram, clf, sim.get_context(), solve_us, r);
  return r;
}

}  // namespace rome
