// The walking plans from standing, between gaits and along a sequence (walking_diagram.h: BuildStandToWalkPlan,
// BuildGaitChangePlan, BuildGaitSequencePlan, BuildPeriodicWalkingPlan) and the sole geometry they use.
#include "diagrams/walking/walking_diagram.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <map>
#include <optional>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "framework/simulator_presets.h"
#include "systems/controllers/task_space_qp_controller.h"
#include "systems/multibody/multibody_kinematics.h"

namespace rome {

SoleGeometry SoleOf(const MultibodyModel& model, const std::string& contact) {
  const ContactInfo& c = model.contacts()[model.ContactIndex(contact)];
  if (c.type != ContactType::kFlat || c.points.empty())
    throw std::invalid_argument("SoleOf: robot '" + model.name() + "': contact '" + contact + "' is not a flat foot");
  SoleGeometry s;
  s.heel_m = s.toe_m = s.left_m = s.right_m = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& p : c.points) {
    s.toe_m = std::max(s.toe_m, p.x());
    s.heel_m = std::max(s.heel_m, -p.x());
    s.left_m = std::max(s.left_m, p.y());
    s.right_m = std::max(s.right_m, -p.y());
  }
  if (!(s.heel_m > 0 && s.toe_m > 0 && s.left_m > 0 && s.right_m > 0))
    throw std::invalid_argument("SoleOf: robot '" + model.name() + "': contact '" + contact +
                                "': the ankle is not over the sole");
  return s;
}

namespace {

using Clock = std::chrono::steady_clock;
double SecondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
// The calling thread's CPU time (POSIX CLOCK_THREAD_CPUTIME_ID; the machine may be shared, so wall time overstates).
double ThreadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

AslipPeriodicGaitParams GaitParams(const WalkingGait& g, const StandToWalkParams& sp) {
  AslipPeriodicGaitParams gp;
  gp.step_length = g.step_length_m;
  gp.ssp_duration = g.ssp_duration_s;
  gp.dsp_duration = g.dsp_duration_s;
  gp.height_min = sp.height_min_m;
  gp.height_max = sp.height_max_m;
  return gp;
}

struct SolvedGait {
  AslipPeriodicGaitPlanner planner;
  AslipPeriodicGait gait;
  double solve_s = 0;
};

SolvedGait SolveGait(const WalkingGait& g, std::uint32_t seed, const PlanCache* cache, const StandToWalkParams& sp,
                     const std::string& who, const std::string& which) {
  if (!(sp.periodic_max_force_fraction == 0 ||
        (sp.periodic_max_force_fraction > 1 && std::isfinite(sp.periodic_max_force_fraction))))
    throw std::invalid_argument(who + ": periodic_max_force_fraction must be 0 (no bound) or > 1, got " +
                                std::to_string(sp.periodic_max_force_fraction));
  SolvedGait r{AslipPeriodicGaitPlanner(GaitParams(g, sp)), {}, 0.0};
  const auto t0 = Clock::now();
  r.gait = r.planner.Solve(seed, cache);
  r.solve_s = SecondsSince(t0);
  if (!r.gait.success())
    throw std::runtime_error(who + ": the periodic aSLIP NLP of " + which +
                             " failed: " + r.gait.collocation.nlp.message);
  if (sp.periodic_max_force_fraction > 0) {  // re-plan a gait that asks more than the bound (see the parameter)
    const AslipPeriodicGaitParams& gp = r.planner.params();
    double peak = 0;
    for (int ph = 0; ph < 2; ++ph) {
      const Eigen::MatrixXd G = r.gait.GroundReactions(gp.aslip, gp.step_length, ph);
      peak = std::max({peak, G.row(1).maxCoeff(), G.row(3).maxCoeff()});
    }
    if (peak > sp.periodic_max_force_fraction * gp.aslip.mass * gp.aslip.gravity) {
      AslipPeriodicGaitParams bounded = gp;
      bounded.max_vertical_force_fraction = sp.periodic_max_force_fraction;
      SolvedGait b{AslipPeriodicGaitPlanner(bounded), {}, 0.0};
      b.gait = b.planner.Solve(seed, cache);
      b.solve_s = r.solve_s + SecondsSince(t0);
      if (!b.gait.success())
        throw std::runtime_error(
            who + ": the periodic aSLIP NLP of " + which + " asks " +
            std::to_string(peak / (gp.aslip.mass * gp.aslip.gravity)) +
            " m g per leg, and with periodic_max_force_fraction = " + std::to_string(sp.periodic_max_force_fraction) +
            " it failed: " + b.gait.collocation.nlp.message);
      return b;
    }
  }
  return r;
}

// The footed-aSLIP transition NLP onto `target` (Eq. (9)-(10) on the robot's sole, less the ROM margins).
AslipTransitionParams TransitionParams(const AslipPeriodicGaitParams& target_params, const WalkingGait& target,
                                       const StandToWalkParams& sp) {
  AslipTransitionParams tp;
  tp.bounds = target_params;
  tp.bounds.aslip.heel_length = sp.sole.heel_m - sp.sagittal_cop_margin_m;
  tp.bounds.aslip.toe_length = sp.sole.toe_m - sp.sagittal_cop_margin_m;
  tp.min_ssp_duration = std::max({tp.min_ssp_duration, target.ssp_duration_s, sp.transition_min_ssp_duration_s});
  tp.max_ssp_duration = std::max(tp.max_ssp_duration, tp.min_ssp_duration);
  if (sp.point_foot_transition_ssp) tp.max_ssp_ankle_torque = 0.0;
  tp.min_dsp_stance_force_fraction = sp.min_dsp_stance_force_fraction;
  tp.lateral = sp.lateral_in_transition_nlp;
  tp.foot_width_left_of_ankle = sp.sole.left_m - sp.lateral_cop_margin_m;
  tp.foot_width_right_of_ankle = sp.sole.right_m - sp.lateral_cop_margin_m;
  return tp;
}

// Solves the transition NLP for `data` (legs and pivots in the frame whose origin is world x = x_offset), then the
// footed H-LIP QP on its nodes (Eq. (11)-(15)), and appends both to `plan`; the lifting foot lands at world landing_x.
// landing_y: the lifting foot's world y at touchdown (NaN: where it lifted).
void AppendSolvedTransition(WalkingPlan& plan, const AslipTransitionPlanner& planner, const AslipTransitionData& data,
                            double x_offset, double step_width, double landing_x, const StandToWalkParams& sp,
                            const PlanCache* cache, const std::string& who, WalkingNlpReport* report,
                            WalkingTransitionNodes* nodes, double landing_y = std::numeric_limits<double>::quiet_NaN(),
                            double reload_floor_N = 0.0) {
  const auto t0 = Clock::now();
  const double cpu0 = ThreadCpuSeconds();
  const AslipTransition transition = planner.Solve(data, cache);
  const WalkingNlpReport solved{SecondsSince(t0), transition.collocation.nlp.iterations,
                                transition.max_constraint_violation, ThreadCpuSeconds() - cpu0};
  if (report != nullptr) *report = solved;
  if (sp.on_transition_nlp) sp.on_transition_nlp(solved);
  if (!transition.success())
    throw std::runtime_error(who + ": the transition footed-aSLIP NLP failed: " + transition.collocation.nlp.message);
  const ActuatedSpringLoadedInvertedPendulumParams& aslip = planner.params().bounds.aslip;
  if (const double t = transition.LiftingLegReloadTime(aslip, data, reload_floor_N);
      reload_floor_N > 0 && !std::isnan(t))
    throw std::runtime_error(who + ": the transition's plan unloads the lifting foot and loads it again " +
                             std::to_string(t) + " s into its double support");
  FootedHlipTransitionData lat =
      LateralDataOnTransitionNodes(transition, aslip, data, planner.params().bounds.nodes_per_domain, step_width);
  lat.stance_left = data.lifting_leg == 1;
  lat.left_foot_y = data.left_foot_y;
  lat.right_foot_y = data.right_foot_y;
  lat.initial_state = data.initial_lateral_state;
  lat.final_state = data.final_lateral_state;
  FootedHlipTransitionParams lp;
  lp.mass = aslip.mass;
  lp.foot_width_left_of_ankle = sp.sole.left_m - sp.lateral_cop_margin_m;  // Eq. (14) on the robot's sole
  lp.foot_width_right_of_ankle = sp.sole.right_m - sp.lateral_cop_margin_m;
  lp.normal_force_pivots = sp.lateral_normal_force_pivots;
  const FootedHlipTransitionPlan lateral = FootedHlipTransitionPlanner(lp).Solve(lat);
  if (!lateral.success()) throw std::runtime_error(who + ": the footed H-LIP transition QP failed: " + lateral.message);
  if (nodes != nullptr) {
    const int n = static_cast<int>(lat.node_times.size()), N = planner.params().bounds.nodes_per_domain;
    WalkingTransitionNodes& r = *nodes;
    r = WalkingTransitionNodes{};
    r.t = lat.node_times.array() + plan.end_time();
    r.x.resize(n), r.z.resize(n), r.y = lateral.states.row(0).transpose(), r.ydot = lateral.states.row(1).transpose();
    r.normal_force.resize(2, n), r.pitch_torque.resize(2, n), r.roll_torque.resize(2, n);
    r.roll_torque.row(0) = lateral.left_torque.transpose(), r.roll_torque.row(1) = lateral.right_torque.transpose();
    for (int ph = 0; ph < 2; ++ph) {
      const CollocationPhaseSolution& s = transition.collocation.phases[ph];
      const Eigen::MatrixXd G = transition.GroundReactions(aslip, data, ph);
      for (int k = ph; k < N; ++k) {
        const int j = ph * (N - 1) + k;
        r.x(j) = x_offset + s.states(0, k), r.z(j) = s.states(1, k);
        r.normal_force(0, j) = G(1, k), r.normal_force(1, j) = G(3, k);
        r.pitch_torque(0, j) = s.inputs(2, k), r.pitch_torque(1, j) = s.inputs(3, k);
      }
    }
    for (int j = 0; j < n; ++j) r.single_support.push_back(j >= N);
    r.heel_m = aslip.heel_length, r.toe_m = aslip.toe_length;
    r.left_m = lp.foot_width_left_of_ankle, r.right_m = lp.foot_width_right_of_ankle;
  }
  plan.AppendTransition(planner, transition, data, x_offset, lat, lateral, aslip.mass, landing_x, landing_y);
}

// Swaps the two legs' rest lengths and rates of an aSLIP state [x, z, ẋ, ż, L_0, L_1, L̇_0, L̇_1].
Eigen::Matrix<double, 8, 1> SwapLegs(Eigen::Matrix<double, 8, 1> s) {
  std::swap(s[4], s[5]);
  std::swap(s[6], s[7]);
  return s;
}

bool SameTiming(const WalkingGait& a, const WalkingGait& b) {
  return std::abs(a.step_length_m - b.step_length_m) <= 1e-9 && std::abs(a.ssp_duration_s - b.ssp_duration_s) <= 1e-9 &&
         std::abs(a.dsp_duration_s - b.dsp_duration_s) <= 1e-9;
}

// `sp` with the standing transition's sagittal CoP margin in place of sagittal_cop_margin_m (when it is set).
StandToWalkParams WithStandingMargin(const StandToWalkParams& sp) {
  StandToWalkParams p = sp;
  if (sp.standing_sagittal_cop_margin_m >= 0) p.sagittal_cop_margin_m = sp.standing_sagittal_cop_margin_m;
  return p;
}

// Stand → the solved gait `a` (timing of `g`; the right foot lifts first) and `steps` periodic steps of it; with
// end_in_single_support the last step stops at its touchdown (its DSP left to a following transition).
WalkingPlan StandingInto(const SolvedGait& a, const WalkingGait& g, int steps, const PlanCache* cache,
                         WalkingPlanReport* report, const StandToWalkParams& sp, const std::string& who,
                         bool end_in_single_support, const char* into = "gait") {
  const AslipPeriodicGaitParams& gp = a.planner.params();
  const StandToWalkParams standing = WithStandingMargin(sp);
  AslipTransitionParams tp = TransitionParams(gp, g, standing);
  tp.bounds.height_max = std::max(tp.bounds.height_max, sp.standing_height_m);
  const AslipTransitionPlanner transition_planner(tp);
  AslipTransitionData data;
  data.left_foot_x = 0.0;
  data.right_foot_x = -sp.stance_stagger_m;
  data.initial_state =
      AslipTransitionPlanner::StandingState(gp.aslip, sp.standing_height_m, data.left_foot_x, data.right_foot_x);
  data.final_state = a.gait.collocation.phases[0].states.col(gp.nodes_per_domain - 1);
  const HybridLinearInvertedPendulum hlip(
      {.z0 = a.gait.mean_height, .ssp_duration = g.ssp_duration_s, .dsp_duration = g.dsp_duration_s});
  const Eigen::Vector2d pre = hlip.P2PreImpactState(g.step_width_m);  // end of a left stance, about the left foot
  data.left_foot_y = g.step_width_m / 2;
  data.right_foot_y = -g.step_width_m / 2;
  data.initial_lateral_state = Eigen::Vector2d(0.0, 0.0);
  data.final_lateral_state = Eigen::Vector2d(data.left_foot_y + pre(0), pre(1));
  data.lifting_leg = 1;
  WalkingPlan plan;
  WalkingNlpReport transition_report;
  AppendSolvedTransition(plan, transition_planner, data, 0.0, g.step_width_m, gp.step_length, standing, cache,
                         who + " (standing -> " + into + ")", &transition_report,
                         report != nullptr ? &report->transition_nodes : nullptr);
  // The transition lands the right foot one step ahead: the first periodic step contributes its DSP only, so `steps`
  // single supports of the gait follow.
  plan.AppendPeriodicSteps(a.planner, a.gait, steps + 1, WalkingDomain::kLeftStance, 0.0, g.step_width_m,
                           /*begin_with_double_support=*/true, end_in_single_support);
  if (report != nullptr) report->transition = transition_report;
  return plan;
}

// `plan` ends at a touchdown of the solved gait `ga` (timing `a`): the transition footed-aSLIP NLP from its post-impact
// state to `gb`'s pre-impact state (the foot behind lifts) with its footed H-LIP QP, then `steps_b` steps of b.
// Returns the transition's end (the end of its single support).
double AppendGaitChange(WalkingPlan& plan, const SolvedGait& ga, const WalkingGait& a, const SolvedGait& gb,
                        const WalkingGait& b, int steps_b, bool end_in_single_support, const PlanCache* cache,
                        const StandToWalkParams& sp, const std::string& who, WalkingNlpReport* transition_report,
                        WalkingTransitionNodes* nodes) {
  const AslipPeriodicGaitParams& pa = ga.planner.params();
  const AslipPeriodicGaitParams& pb = gb.planner.params();
  // The plan ends at a touchdown of gait A: the foot that just landed is the transition's stance foot, the one behind
  // lifts. The transition's frame has its origin at the landed foot.
  const WalkingPlanSegment& last = plan.segments().back();
  const bool old_stance_left = last.domain == WalkingDomain::kLeftStance;
  const Eigen::Vector2d landed = old_stance_left ? last.right_foothold : last.left_foothold;
  const Eigen::Vector2d behind = old_stance_left ? last.left_foothold : last.right_foothold;
  const double x_offset = landed.x();
  AslipTransitionData data;
  (old_stance_left ? data.left_foot_x : data.right_foot_x) = behind.x() - x_offset;
  (old_stance_left ? data.right_foot_x : data.left_foot_x) = 0.0;
  data.left_foot_y = old_stance_left ? behind.y() : landed.y();
  data.right_foot_y = old_stance_left ? landed.y() : behind.y();
  data.lifting_leg = old_stance_left ? 0 : 1;
  // Gait A's post-impact state (start of its DSP; plan leg 0 = the old stance) in the new frame, world legs.
  Eigen::Matrix<double, 8, 1> start = ga.gait.collocation.phases[1].states.col(0);
  start[0] -= pa.step_length;
  data.initial_state = old_stance_left ? start : SwapLegs(start);
  // Gait B's pre-impact state (end of its SSP; plan leg 0 = the stance, here the landed foot), world legs.
  const Eigen::Matrix<double, 8, 1> end = gb.gait.collocation.phases[0].states.col(pb.nodes_per_domain - 1);
  data.final_state = old_stance_left ? SwapLegs(end) : end;
  const WalkingReference at_touchdown = plan.Sample(plan.end_time());
  data.initial_lateral_state = Eigen::Vector2d(at_touchdown.com_position.y(), at_touchdown.com_velocity.y());
  const HybridLinearInvertedPendulum hlip(
      {.z0 = gb.gait.mean_height, .ssp_duration = b.ssp_duration_s, .dsp_duration = b.dsp_duration_s});
  const Eigen::Vector2d pre = hlip.P2PreImpactState(b.step_width_m);  // end of a left stance, about the left foot
  data.final_lateral_state =
      old_stance_left ? Eigen::Vector2d(landed.y() - pre(0), -pre(1)) : Eigen::Vector2d(landed.y() + pre(0), pre(1));
  // Initial guess: gait A's DSP and gait B's SSP in the new frame, world legs.
  data.dsp_state_guess = ga.gait.collocation.phases[1].states.topRows(8);
  data.dsp_state_guess.row(0).array() -= pa.step_length;
  data.ssp_state_guess = gb.gait.collocation.phases[0].states.topRows(8);
  for (Eigen::Index k = 0; k < data.dsp_state_guess.cols(); ++k)
    if (!old_stance_left) data.dsp_state_guess.col(k) = SwapLegs(data.dsp_state_guess.col(k));
  for (Eigen::Index k = 0; k < data.ssp_state_guess.cols(); ++k)
    if (old_stance_left) data.ssp_state_guess.col(k) = SwapLegs(data.ssp_state_guess.col(k));
  data.dsp_duration_guess = a.dsp_duration_s;
  data.ssp_duration_guess = b.ssp_duration_s;
  // The A → B transition's SSP may use the stance ankle (Eq. (10)): measured, with a point-foot SSP (as the standing
  // transition's) Ipopt ends at a point of local infeasibility (violation 9e-3) for gaits A and B.
  StandToWalkParams spb = sp;
  spb.point_foot_transition_ssp = false;
  AslipTransitionParams tp = TransitionParams(pb, b, spb);
  // The DSP starts at A's touchdown, where the landed (stance) leg carries nothing (s = 0): no load floor on it.
  tp.min_dsp_stance_force_fraction = 0.0;
  tp.max_vertical_force_fraction = sp.gait_change_max_force_fraction;
  // The transition's DSP may be as short as the gaits' own (the spec's [R] 0.1 s lower bound is above T_DSP = 0.08 s):
  // measured, (0.20 m, 0.35 s, 0.08 s, 0.20 m) -> 0.25 m steps is locally infeasible with 0.1 s and walks with 0.08 s.
  tp.min_dsp_duration = std::min({tp.min_dsp_duration, a.dsp_duration_s, b.dsp_duration_s});
  const AslipTransitionPlanner transition_planner(tp);
  if (transition_planner.params()
          .lateral) {  // lateral rows [y, ẏ]: straight from the initial to the final lateral state
    const Eigen::Vector2d y0 = data.initial_lateral_state, y1 = data.final_lateral_state, mid = 0.5 * (y0 + y1);
    for (Eigen::MatrixXd* g : {&data.dsp_state_guess, &data.ssp_state_guess}) {
      const Eigen::Vector2d from = g == &data.dsp_state_guess ? y0 : mid, to = g == &data.dsp_state_guess ? mid : y1;
      g->conservativeResize(10, Eigen::NoChange);
      for (Eigen::Index k = 0; k < g->cols(); ++k)
        g->col(k).tail<2>() = from + (to - from) * (double(k) / double(g->cols() - 1));
    }
  }
  // The lateral footed H-LIP transition to B's step width: the landed foot stays, the lifting foot lands W_B to its
  // side (the final lateral state above is B's P2 pre-impact state about the landed foot), and B walks about the
  // walking line between them (it moves by (W_A - W_B) / 2 when W changes).
  const double landing_y = old_stance_left ? landed.y() + b.step_width_m : landed.y() - b.step_width_m;
  AppendSolvedTransition(plan, transition_planner, data, x_offset, b.step_width_m, x_offset + pb.step_length, sp, cache,
                         who, transition_report, nodes, landing_y,
                         sp.reload_floor_fraction * pb.aslip.mass * pb.aslip.gravity);
  const double transition_end = plan.end_time();
  // As after the standing transition: B's first step is the transition's single support (on the foot A landed last,
  // at x_offset), so it contributes its DSP only.
  plan.AppendPeriodicSteps(gb.planner, gb.gait, steps_b + 1,
                           old_stance_left ? WalkingDomain::kRightStance : WalkingDomain::kLeftStance, x_offset,
                           b.step_width_m, /*begin_with_double_support=*/true, end_in_single_support,
                           0.5 * (landed.y() + landing_y));
  return transition_end;
}

// AppendGaitChange, then sp.change_check on the transition. A transition the check refuses is planned again with the
// tighter bound sp.gait_change_retry_max_force_fraction (when set and tighter); if that has no plan or is refused too,
// std::runtime_error names every refusal (the caller then chains through the gait graph). Refusals are appended to
// *refused, and the first refused plan to *refused_plan (if given). `plan` is unchanged unless the change succeeds.
// A plan that every way tried was refused by the torque check (StandToWalkParams::change_check): the first refused
// transition's whole plan, thrown so that a caller with another way (a lead-in) tries it first; the public builders
// return it, and the check before simulating refuses it naming the joint (exit 1), not the planner (exit 3).
struct RefusedPlan : std::runtime_error {
  RefusedPlan(WalkingPlan refused, const std::string& why) : std::runtime_error(why), plan(std::move(refused)) {}
  WalkingPlan plan;
};

void AppendCheckedGaitChange(WalkingPlan& plan, const SolvedGait& ga, const WalkingGait& a, const SolvedGait& gb,
                             const WalkingGait& b, int steps_b, bool end_in_single_support, const PlanCache* cache,
                             const StandToWalkParams& sp, const std::string& who, WalkingNlpReport* transition_report,
                             WalkingTransitionNodes* nodes, std::vector<WalkingChangeRefusal>* refused,
                             WalkingPlan* refused_plan = nullptr) {
  const double first = sp.gait_change_max_force_fraction, retry = sp.gait_change_retry_max_force_fraction;
  std::vector<double> bounds{first};
  if (sp.change_check && retry > 0 && (first == 0 || retry < first)) bounds.push_back(retry);
  std::string refusals;
  for (const double bound : bounds) {
    StandToWalkParams bounded = sp;
    bounded.gait_change_max_force_fraction = bound;
    WalkingPlan next = plan;
    const double from = plan.end_time();
    double to = from;
    try {
      to = AppendGaitChange(next, ga, a, gb, b, steps_b, end_in_single_support, cache, bounded, who, transition_report,
                            nodes);
    } catch (const std::runtime_error& e) {
      if (refusals.empty()) throw;
      throw std::runtime_error(refusals + "; with the force bound " + std::to_string(bound) + " m g: " + e.what());
    }
    if (!sp.change_check) {
      plan = std::move(next);
      return;
    }
    try {
      sp.change_check(next, from, to);
      plan = std::move(next);
      return;
    } catch (const std::runtime_error& e) {
      if (refused != nullptr) refused->push_back({a, b, bound, e.what()});
      if (refused_plan != nullptr && refusals.empty()) *refused_plan = std::move(next);
      refusals += (refusals.empty() ? who + ": the transition is beyond the robot with the force bound "
                                    : "; with the force bound ") +
                  std::to_string(bound) + " m g: " + e.what();
    }
  }
  throw std::runtime_error(refusals);
}

// Stand → gait `g` (the right foot lifts first) and `steps` periodic steps of g; with end_in_single_support the last
// step stops at its touchdown (its DSP left to a following transition). With StandToWalkParams::start_gait_steps, the
// standing transition goes into the start gait, which walks those steps and changes into g.
WalkingPlan ChainGaitChange(WalkingPlan plan, const SolvedGait& ga, const WalkingGait& a, const SolvedGait& gb,
                            const WalkingGait& b, int steps_b, bool end_in_single_support, std::uint32_t seed,
                            const PlanCache* cache, const StandToWalkParams& sp, const std::string& who,
                            const std::string& direct_error, WalkingNlpReport* last_transition,
                            WalkingTransitionNodes* nodes, WalkingPlanReport* report, std::vector<WalkingGait>* walked,
                            const StandToWalkParams* first_link = nullptr, WalkingPlan* refused_out = nullptr);

// With `chain`, a start gait → g change with no direct plan goes through the gait graph (report->start_chain).
WalkingPlan StandToWalk(const WalkingGait& g, int steps, std::uint32_t seed, const PlanCache* cache,
                        WalkingPlanReport* report, const StandToWalkParams& sp, const std::string& who,
                        bool end_in_single_support, SolvedGait* gait_out, bool chain = false) {
  sp.Validate(who);
  if (steps < 1) throw std::invalid_argument(who + ": steps must be >= 1, got " + std::to_string(steps));
  SolvedGait a = SolveGait(g, seed, cache, sp, who, "the gait");
  const WalkingGait start{sp.start_gait_step_length_m, sp.start_gait_ssp_duration_s, sp.start_gait_dsp_duration_s,
                          g.step_width_m};
  WalkingPlan plan;
  if (sp.start_gait_steps > 0 && !SameTiming(g, start)) {
    const SolvedGait s = SolveGait(start, seed, cache, sp, who, "the start gait");
    plan = StandingInto(s, start, sp.start_gait_steps, cache, report, sp, who, /*end_in_single_support=*/true,
                        "start gait");
    WalkingNlpReport change;
    const StandToWalkParams from_start = WithStandingMargin(sp);  // the start gait's change keeps the standing margin
    WalkingTransitionNodes* nodes = report != nullptr ? &report->start_change_nodes : nullptr;
    if (report != nullptr) report->start_chain = {start, g};
    WalkingPlan refused;  // the direct change the check refused (empty: none)
    try {
      AppendCheckedGaitChange(plan, s, start, a, g, steps, end_in_single_support, cache, from_start,
                              who + " (start gait -> gait)", &change, nodes,
                              report != nullptr ? &report->refused_changes : nullptr, &refused);
    } catch (const std::runtime_error& direct) {
      try {
        if (!chain) throw;
        std::vector<WalkingGait> walked{start};
        // Only the chain's first link leaves the start gait: it keeps the standing margin, the later links are
        // changes between walking gaits (docs/design-notes.md#walking-start-chain).
        plan = ChainGaitChange(std::move(plan), s, start, a, g, steps, end_in_single_support, seed, cache, sp, who,
                               direct.what(), &change, nodes, report, &walked, &from_start,
                               refused.segments().empty() ? &refused : nullptr);
        if (report != nullptr) report->start_chain = walked;
      } catch (const std::runtime_error& e) {
        if (refused.segments().empty()) throw;
        throw RefusedPlan(std::move(refused), e.what());  // beyond the robot every way tried here
      }
    }
    if (report != nullptr) {
      report->start_gait_used = true;
      report->start_gait = start;
      report->periodic_start = {s.solve_s, s.gait.collocation.nlp.iterations, s.gait.max_constraint_violation};
      report->transition_start = change;
    }
  } else {
    plan = StandingInto(a, g, steps, cache, report, sp, who, end_in_single_support);
    if (report != nullptr) report->start_gait_used = false, report->periodic_start = {}, report->transition_start = {};
  }
  if (report != nullptr)
    report->periodic = {a.solve_s, a.gait.collocation.nlp.iterations, a.gait.max_constraint_violation};
  if (gait_out != nullptr) *gait_out = std::move(a);
  return plan;
}

GaitVector AsVector(const WalkingGait& g) {
  return {g.step_length_m, g.ssp_duration_s, g.dsp_duration_s, g.step_width_m};
}
std::string GaitText(const WalkingGait& g) {
  char b[96];
  std::snprintf(b, sizeof b, "(%g m, %g s, %g s, %g m)", g.step_length_m, g.ssp_duration_s, g.dsp_duration_s,
                g.step_width_m);
  return b;
}

// `plan` ends at a touchdown of the solved gait `ga`, whose direct change into `gb` has no plan (`direct_error`): the
// lazy gait-graph search (GaitGraph) appends changes through intermediate gaits, chain_steps steps each, then the
// change into b and steps_b steps of it. A transition or an intermediate gait that has no plan removes that edge.
// Appends the gaits after a to *walked and adds the search's time and counts to the report. first_link (if given):
// the parameters of the links that leave a (the start gait's change keeps the standing margin); sp: the others'.
// refused_out (if given and empty): the whole plan through the first chain whose link into b planned but was refused
// by the torque check (StandToWalkParams::change_check), for the caller to keep when no chain is found, so that the
// check before simulating refuses it naming the joint (exit 1) instead of the planner failing.
WalkingPlan ChainGaitChange(WalkingPlan plan, const SolvedGait& ga, const WalkingGait& a, const SolvedGait& gb,
                            const WalkingGait& b, int steps_b, bool end_in_single_support, std::uint32_t seed,
                            const PlanCache* cache, const StandToWalkParams& sp, const std::string& who,
                            const std::string& direct_error, WalkingNlpReport* last_transition,
                            WalkingTransitionNodes* nodes, WalkingPlanReport* report, std::vector<WalkingGait>* walked,
                            const StandToWalkParams* first_link, WalkingPlan* refused_out) {
  const auto t0 = Clock::now();
  // A gait outside the graph's range (a start gait may be slower) has no chain: the direct change's failure stands.
  for (const WalkingGait* g : {&a, &b})
    for (int i = 0; i < 4; ++i)
      if (AsVector(*g)[i] < sp.gait_graph.min[i] - 1e-12 || AsVector(*g)[i] > sp.gait_graph.max[i] + 1e-12)
        throw std::runtime_error(direct_error + "; no chain through the gait graph: gait " + GaitText(*g) +
                                 " is outside its range");
  GaitGraph graph(sp.gait_graph, AsVector(a), AsVector(b));
  graph.MarkInfeasible(graph.start(), graph.goal());
  const GaitVector goal = graph.node(graph.goal());
  std::vector<WalkingPlan> plans{std::move(plan)};  // plans[k]: after the chain's first k transitions
  std::vector<std::shared_ptr<const SolvedGait>> solved{std::make_shared<const SolvedGait>(ga)};
  std::vector<WalkingGait> gaits{a};
  std::map<GaitVector, std::shared_ptr<const SolvedGait>> periodic;  // intermediate gaits solved so far (null: no plan)
  const GaitChain chain = graph.ShortestFeasibleChain([&](int depth, const GaitVector&, const GaitVector& to) {
    plans.resize(depth + 1), solved.resize(depth + 1), gaits.resize(depth + 1);
    const bool last = to == goal;
    const WalkingGait g = last ? b : WalkingGait{to[0], to[1], to[2], to[3]};
    try {
      if (!last && !periodic.count(to)) {
        periodic[to] = nullptr;  // stays null when the gait has no periodic plan (SolveGait throws)
        periodic[to] =
            std::make_shared<const SolvedGait>(SolveGait(g, seed, cache, sp, who, "the chain gait " + GaitText(g)));
      }
      const std::shared_ptr<const SolvedGait> s = last ? std::make_shared<const SolvedGait>(gb) : periodic[to];
      if (s == nullptr) return false;
      WalkingPlan next = plans[depth];
      AppendCheckedGaitChange(
          next, *solved[depth], gaits[depth], *s, g, last ? steps_b : sp.chain_steps,
          last ? end_in_single_support : true, cache, depth == 0 && first_link != nullptr ? *first_link : sp,
          who + " (chain " + GaitText(gaits[depth]) + " -> " + GaitText(g) + ")", last_transition,
          last ? nodes : nullptr, report != nullptr ? &report->refused_changes : nullptr,
          last && refused_out != nullptr && refused_out->segments().empty() ? refused_out : nullptr);
      plans.push_back(std::move(next)), solved.push_back(s), gaits.push_back(g);
      return true;
    } catch (const std::runtime_error&) { return false; }
  });
  if (report != nullptr) {
    report->chain_planning_s += SecondsSince(t0);
    report->chain_transitions_tried += chain.transitions_tried;
    report->chain_transitions_failed += chain.transitions_failed;
  }
  if (!chain.found) throw std::runtime_error(direct_error + "; through the gait graph: " + chain.message);
  if (walked != nullptr) walked->insert(walked->end(), gaits.begin() + 1, gaits.end());
  return std::move(plans.back());
}

// Standing → gaits[0] (as StandToWalk, `steps` steps), then each change into the next gait (directly, or with `chain`
// through the gait graph when the direct transition has no plan), `steps` steps of each and steps_last of the last.
// The report's *_b entries are the last gait's and its change's.
WalkingPlan SequencePlan(const std::vector<WalkingGait>& gaits, int steps, std::uint32_t seed, const PlanCache* cache,
                         WalkingPlanReport* report, const StandToWalkParams& sp, int steps_last, bool chain,
                         const std::string& who) {
  if (steps_last < 0) steps_last = steps;
  SolvedGait prev{AslipPeriodicGaitPlanner(GaitParams(gaits.front(), sp)), {}, 0.0};
  if (report != nullptr)
    report->chain_planning_s = 0, report->chain_transitions_tried = report->chain_transitions_failed = 0,
    report->refused_changes.clear(), report->refused_plan_kept.clear();
  WalkingPlan plan =
      StandToWalk(gaits.front(), steps, seed, cache, report, sp, who, /*end_in_single_support=*/true, &prev, chain);
  if (report != nullptr) report->chain = {gaits.front()};
  for (size_t i = 1; i < gaits.size(); ++i) {
    const bool last = i + 1 == gaits.size();
    const WalkingGait &a = gaits[i - 1], &b = gaits[i];
    SolvedGait gb = SolveGait(b, seed, cache, sp, who, gaits.size() == 2 ? "gait B" : "gait " + std::to_string(i + 1));
    const std::string change = gaits.size() == 2
                                   ? " (gait A -> gait B)"
                                   : " (gait " + std::to_string(i) + " -> gait " + std::to_string(i + 1) + ")";
    const int steps_b = last ? steps_last : steps;
    WalkingNlpReport transition_report;
    WalkingTransitionNodes* nodes = last && report != nullptr ? &report->transition_b_nodes : nullptr;
    WalkingPlan refused;  // the direct change the check refused (empty: none)
    try {
      AppendCheckedGaitChange(plan, prev, a, gb, b, steps_b, /*end_in_single_support=*/!last, cache, sp, who + change,
                              &transition_report, nodes, report != nullptr ? &report->refused_changes : nullptr,
                              &refused);
      if (report != nullptr) report->chain.push_back(b);
    } catch (const std::runtime_error& direct) {
      try {
        if (!chain) throw;
        plan = ChainGaitChange(std::move(plan), prev, a, gb, b, steps_b, !last, seed, cache, sp, who, direct.what(),
                               &transition_report, nodes, report, report != nullptr ? &report->chain : nullptr, nullptr,
                               refused.segments().empty() ? &refused : nullptr);
      } catch (const std::runtime_error& e) {
        if (refused.segments().empty()) throw;
        if (report != nullptr) report->chain.push_back(b);
        throw RefusedPlan(std::move(refused), e.what());  // beyond the robot every way tried
      }
    }
    if (report != nullptr && last) {
      report->periodic_b = {gb.solve_s, gb.gait.collocation.nlp.iterations, gb.gait.max_constraint_violation};
      report->transition_b = transition_report;
    }
    prev = std::move(gb);
  }
  return plan;
}

// BuildGaitChangePlan without the gait range check (the lead-in gait may lie outside it); with `chain`, a change with
// no direct plan goes through the gait graph (ChainGaitChange).
WalkingPlan GaitChangePlan(const WalkingGait& a, const WalkingGait& b, int steps, std::uint32_t seed,
                           const PlanCache* cache, WalkingPlanReport* report, const StandToWalkParams& sp, int steps_b,
                           bool chain = false) {
  return SequencePlan({a, b}, steps, seed, cache, report, sp, steps_b, chain, "BuildGaitChangePlan");
}

// Standing → g without the lead-in: the start gait's change into g directly or (StandToWalkParams::chain_gait_changes)
// through the gait graph, as BuildGaitChangePlan's changes; report->chain is {g}, its figures this start's.
WalkingPlan StandToWalkChained(const WalkingGait& g, int steps, std::uint32_t seed, const PlanCache* cache,
                               WalkingPlanReport* report, const StandToWalkParams& sp) {
  if (report != nullptr)
    report->chain_planning_s = 0, report->chain_transitions_tried = report->chain_transitions_failed = 0,
    report->refused_changes.clear();
  WalkingPlan plan =
      StandToWalk(g, steps, seed, cache, report, sp, "BuildStandToWalkPlan", false, nullptr, sp.chain_gait_changes);
  if (report != nullptr) report->chain = {g};
  return plan;
}

}  // namespace

WalkingPlan BuildStandToWalkPlan(const WalkingGait& g, int steps, std::uint32_t seed, const PlanCache* cache,
                                 WalkingPlanReport* report, const StandToWalkParams& sp) {
  g.Validate("BuildStandToWalkPlan: gait");
  sp.Validate("BuildStandToWalkPlan");
  if (steps < 1) throw std::invalid_argument("BuildStandToWalkPlan: steps must be >= 1, got " + std::to_string(steps));
  WalkingGait lead = g;
  lead.step_length_m = sp.lead_in_step_length_m;
  lead.ssp_duration_s = sp.lead_in_ssp_duration_s;
  lead.dsp_duration_s = sp.lead_in_dsp_duration_s;
  const bool is_lead = SameTiming(g, lead);
  const bool faster = g.ssp_duration_s < lead.ssp_duration_s - 1e-9 || g.dsp_duration_s < lead.dsp_duration_s - 1e-9;
  std::optional<RefusedPlan> refused;  // the first plan the torque check refused: returned once no other way plans
  if (report != nullptr) report->refused_plan_kept.clear();
  const auto keep = [&](const std::runtime_error& e) {
    if (const auto* r = dynamic_cast<const RefusedPlan*>(&e); r != nullptr && !refused) refused.emplace(*r);
  };
  const auto refused_plan = [&] {
    if (report != nullptr) report->refused_plan_kept = refused->what();
    return std::move(refused->plan);
  };
  const auto with_lead_in = [&](const std::string& reason) {
    WalkingPlanReport r;
    WalkingPlan plan = GaitChangePlan(lead, g, sp.lead_in_steps, seed, cache, &r, sp, steps, sp.chain_gait_changes);
    r.lead_in = true;
    r.lead_in_gait = lead;
    r.lead_in_reason = reason;
    if (report != nullptr) *report = r;
    return plan;
  };
  const auto with_unit = [](double x, const char* unit) {
    char b[40];
    std::snprintf(b, sizeof b, "%g %s", x, unit);
    return std::string(b);
  };
  const auto seconds = [&](double s) { return with_unit(s, "s"); };
  if (faster && sp.lead_in_steps > 0) {
    const std::string reason = "the gait (T_SSP " + seconds(g.ssp_duration_s) + ", T_DSP " + seconds(g.dsp_duration_s) +
                               ") is faster than the lead-in (T_SSP " + seconds(lead.ssp_duration_s) + ", T_DSP " +
                               seconds(lead.dsp_duration_s) + "): " +
                               (sp.start_gait_steps > 0 ? "the change from the start gait would ask more of the legs"
                                                        : "its first swing from the step stance would lag");
    try {
      return with_lead_in(reason);
    } catch (const std::runtime_error& e) {  // "gait A" / "gait B" in e are the lead-in and the gait
      keep(e);
      const std::string through = "BuildStandToWalkPlan: " + reason + "; through a lead-in of " +
                                  std::to_string(sp.lead_in_steps) + " steps of (" +
                                  with_unit(lead.step_length_m, "m") + ", " + seconds(lead.ssp_duration_s) + ", " +
                                  seconds(lead.dsp_duration_s) + "): " + e.what();
      if (sp.start_gait_steps == 0) {
        if (refused) return refused_plan();
        throw std::runtime_error(through);
      }
      // From the start gait (a short, slow first swing) the direct change may still plan.
      try {
        WalkingPlan plan = StandToWalkChained(g, steps, seed, cache, report, sp);
        if (sp.plan_check) sp.plan_check(plan);
        if (report != nullptr)
          report->lead_in = false,
          report->lead_in_reason = "tried and had no plan, so planned directly from the start gait: " + through;
        return plan;
      } catch (const std::runtime_error& direct) {
        keep(direct);
        if (refused) return refused_plan();
        throw std::runtime_error(through + "; directly from the start gait: " + direct.what());
      }
    }
  }
  try {
    WalkingPlan plan = StandToWalkChained(g, steps, seed, cache, report, sp);
    if (sp.plan_check) sp.plan_check(plan);
    return plan;
  } catch (const std::runtime_error& direct) {
    keep(direct);
    if (sp.lead_in_steps == 0 || is_lead) {
      if (refused) return refused_plan();
      throw;
    }
    try {
      return with_lead_in(direct.what());
    } catch (const std::runtime_error& e) {
      keep(e);
      if (refused) return refused_plan();
      throw std::runtime_error(std::string(direct.what()) + "; with a lead-in of " + std::to_string(sp.lead_in_steps) +
                               " steps of (" + with_unit(lead.step_length_m, "m") + ", " +
                               seconds(lead.ssp_duration_s) + ", " + seconds(lead.dsp_duration_s) + "): " + e.what());
    }
  }
}

WalkingPlan BuildGaitChangePlan(const WalkingGait& a, const WalkingGait& b, int steps, std::uint32_t seed,
                                const PlanCache* cache, WalkingPlanReport* report, const StandToWalkParams& sp,
                                int steps_b) {
  a.Validate("BuildGaitChangePlan: gait A");
  b.Validate("BuildGaitChangePlan: gait B");
  sp.Validate("BuildGaitChangePlan");
  try {
    return GaitChangePlan(a, b, steps, seed, cache, report, sp, steps_b, sp.chain_gait_changes);
  } catch (RefusedPlan& r) {
    if (report != nullptr) report->refused_plan_kept = r.what();
    return std::move(r.plan);
  }
}

WalkingPlan BuildGaitSequencePlan(const std::vector<WalkingGait>& gaits, int steps, std::uint32_t seed,
                                  const PlanCache* cache, WalkingPlanReport* report, const StandToWalkParams& sp,
                                  int steps_last) {
  const std::string who = "BuildGaitSequencePlan";
  if (gaits.size() < 2 || gaits.size() > 20)
    throw std::invalid_argument(who + ": the sequence has " + std::to_string(gaits.size()) +
                                " gaits, expected 2 to 20");
  for (size_t i = 0; i < gaits.size(); ++i) gaits[i].Validate(who + ": gait " + std::to_string(i + 1));
  sp.Validate(who);
  if (steps < 1) throw std::invalid_argument(who + ": steps must be >= 1, got " + std::to_string(steps));
  try {
    return SequencePlan(gaits, steps, seed, cache, report, sp, steps_last, sp.chain_gait_changes, who);
  } catch (RefusedPlan& r) {
    if (report != nullptr) report->refused_plan_kept = r.what();
    return std::move(r.plan);
  }
}

WalkingPlan BuildPeriodicWalkingPlan(const WalkingGait& g, int steps, std::uint32_t seed, const PlanCache* cache,
                                     const StandToWalkParams& sp) {
  g.Validate("BuildPeriodicWalkingPlan: gait");
  sp.Validate("BuildPeriodicWalkingPlan");
  if (steps < 1)
    throw std::invalid_argument("BuildPeriodicWalkingPlan: steps must be >= 1, got " + std::to_string(steps));
  const SolvedGait a = SolveGait(g, seed, cache, sp, "BuildPeriodicWalkingPlan", "the gait");
  WalkingPlan plan;
  plan.AppendPeriodicSteps(a.planner, a.gait, steps + 1, WalkingDomain::kLeftStance, 0.0, g.step_width_m,
                           /*begin_with_double_support=*/true);
  return plan;
}
}  // namespace rome
