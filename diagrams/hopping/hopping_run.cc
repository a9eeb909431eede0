#include "diagrams/hopping/hopping_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"

namespace rome {

namespace {

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(p * (v.size() - 1) + 0.5))];
}

// RMS of a − b over the peak |b|.
double Nrmse(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.empty()) return NAN;
  double se = 0, peak = 0;
  for (size_t i = 0; i < a.size(); ++i) se += (a[i] - b[i]) * (a[i] - b[i]), peak = std::max(peak, std::abs(b[i]));
  return std::sqrt(se / a.size()) / std::max(peak, 1e-9);
}

// Pearson's correlation coefficient.
double Correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  if (n < 2) return NAN;
  double ma = 0, mb = 0;
  for (size_t i = 0; i < a.size(); ++i) ma += a[i] / n, mb += b[i] / n;
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i)
    sab += (a[i] - ma) * (b[i] - mb), saa += (a[i] - ma) * (a[i] - ma), sbb += (b[i] - mb) * (b[i] - mb);
  return sab / std::sqrt(saa * sbb);
}

void Require(bool ok, const char* field, double value, const char* rule) {
  if (ok) return;
  std::ostringstream msg;
  msg << "HoppingRunParams: " << field << " = " << value << ": must be " << rule;
  throw std::invalid_argument(msg.str());
}

// The run's metrics once it ended: GRF agreement with the ROM, rest, QP timing, the success rule.
void FinishHoppingMetrics(const HoppingDiagram& d, const Simulator& sim, const HoppingRunParams& params,
                          const std::vector<PlannerRecord>* records, double apex_rise, double com_liftoff,
                          double com_max, bool has_qp_failures, HoppingRunResult* result) {
  HoppingRunResult& r = *result;
  std::vector<double> jr, jm, lr, lm, st, sg;
  for (const HoppingSample& s : r.samples) {
    if (s.domain == HoppingDomain::kJump && std::isfinite(s.rom_grf)) jr.push_back(s.grf), jm.push_back(s.rom_grf);
    if (s.domain == HoppingDomain::kLanding && s.since_touchdown > params.landing_grf_skip_s &&
        std::isfinite(s.rom_grf))
      lr.push_back(s.grf), lm.push_back(s.rom_grf);
    if (s.domain != HoppingDomain::kFlight && r.jump_start_s > 0 && s.t >= r.jump_start_s)
      st.push_back(s.shin_torque), sg.push_back(s.grf);
  }
  r.grf_nrmse_jump = Nrmse(jr, jm);
  r.grf_nrmse_landing = Nrmse(lr, lm);
  r.spring_torque_grf_correlation = Correlation(st, sg);
  const Context& context = sim.get_context();
  const LeafContext& pc = d.diagram->GetSubsystemContext(*d.plant, context);
  const Eigen::VectorXd v_end = HoppingEulerState(d, context).tail(d.model->nv());
  r.settled = std::isfinite(r.rest_speed) && r.rest_speed < params.rest_max_speed &&
              v_end.cwiseAbs().maxCoeff() < params.rest_max_speed;
  if (d.controller->HasOutputPort("solve_time_s")) {
    const LogData& log = d.logger->log(d.diagram->GetSubsystemContext(*d.logger, context));
    std::vector<double> solve_us;
    const int solve_col = d.logger->ColumnIndex("controller.solve_time_s[0]");
    for (const Eigen::VectorXd& row : log.samples) solve_us.push_back(1e6 * row[solve_col]);
    r.qp_solve_us_median = Percentile(solve_us, 0.5);
    r.qp_solve_us_p99 = Percentile(solve_us, 0.99);
  }
  if (records) r.planner_records = *records;
  if (r.liftoff_s > 0 && !r.planner_records.empty())
    r.takeoff_time_error_s = (r.liftoff_s - r.jump_start_s) - r.planner_records.front().plan.duration;
  r.hopped = r.liftoff_s > 0 && r.touchdown_s > 0 && com_max - com_liftoff >= params.min_com_rise_fraction * apex_rise;
  const bool ran = r.status.ok() || r.status.reason == SimulatorStatus::Reason::kReachedTermination;
  r.success = ran && r.hopped && r.settled && r.contact.violations == 0;
  r.status_kind =
      ran ? (r.success ? "success" : "failure") : r.status.kind_name();  // judged by the success rule, never a "limit"
  r.air_time_s = r.liftoff_s > 0 && r.touchdown_s > 0 ? r.touchdown_s - r.liftoff_s : NAN;
  r.com_rise_m = r.liftoff_s > 0 ? com_max - com_liftoff : NAN;
  const Eigen::VectorXd& plan_status =
      d.reference->EvalOutput(d.diagram->GetSubsystemContext(*d.reference, context), "plan_status");
  r.jump_plans = plan_status[0], r.landing_plans = plan_status[1], r.planner_failures = plan_status[2];
  if (has_qp_failures) r.qp_failures = d.diagram->EvalOutput(context, "qp_failures")[0];
  r.simulated_s = pc.time();
  r.realtime_factor = pc.time() / r.wall_s;
  r.integrator = sim.statistics();
}

}  // namespace

void HoppingRunParams::Validate() const {
  Require(duration_s >= 0.0 && duration_s <= 3600.0, "duration_s", duration_s,
          "in [0, 3600] s (0: until the robot rests)");
  Require(stop_after_last_touchdown_s >= rest_check_delay_s && stop_after_last_touchdown_s <= 60.0,
          "stop_after_last_touchdown_s", stop_after_last_touchdown_s, "in [rest_check_delay_s, 60] s");
  Require(rest_check_delay_s >= 0.0 && rest_check_delay_s <= 60.0, "rest_check_delay_s", rest_check_delay_s,
          "in [0, 60] s");
  Require(rest_max_speed > 0.0 && std::isfinite(rest_max_speed), "rest_max_speed", rest_max_speed,
          "positive and finite");
  Require(min_com_rise_fraction >= 0.0 && min_com_rise_fraction <= 1.0, "min_com_rise_fraction", min_com_rise_fraction,
          "in [0, 1]");
  Require(std::isnan(apex_rise_m) || (apex_rise_m > 0.0 && std::isfinite(apex_rise_m)), "apex_rise_m", apex_rise_m,
          "positive and finite, or NaN");
  Require(sample_period_s > 0.0 && sample_period_s <= 1.0, "sample_period_s", sample_period_s, "in (0, 1] s");
  Require(landing_grf_skip_s >= 0.0 && landing_grf_skip_s <= 1.0, "landing_grf_skip_s", landing_grf_skip_s,
          "in [0, 1] s");
  Require(progress_period_s > 0.0, "progress_period_s", progress_period_s, "positive");
}

double HoppingRunDuration(const HoppingDiagram& d, const HoppingRunParams& params) {
  const HoppingReferenceParams& ref = d.params.reference;
  return params.duration_s > 0 ? params.duration_s
                               : ref.settle_time_s + ref.hops * 1.0 + (ref.hops - 1) * ref.max_rest_time_s +
                                     params.stop_after_last_touchdown_s;
}

namespace {

// The mean x of the contact points less the COM's x [m] (the foot's offset ahead of the COM).
double FootComOffsetX(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& q) {
  double x_sum = 0;
  int points = 0;
  for (int k = 0; k < model.num_contacts(); ++k)
    for (size_t i = 0; i < model.contacts()[k].points.size(); ++i, ++points)
      x_sum += CalcContactPointPosition(model, ws, q, k, static_cast<int>(i)).x();
  return x_sum / points - CalcComPosition(model, ws, q).x();
}

// The robot's kinetic, potential (COM height rise com_rise_m above the hop's jump start) and spring energies [J].
void RecordEnergies(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& x, double com_rise_m,
                    const SpringMassHopPlanners* planners, HoppingSample* s) {
  const int nv = model.nv();
  const Eigen::VectorXd q = x.head(nv), v = x.tail(nv);
  const double gravity = planners ? planners->rom.gravity : 9.81;
  s->kinetic = 0.5 * v.dot(CalcMassMatrix(model, ws, q) * v);
  s->potential = model.total_mass() * gravity * com_rise_m;
  s->spring_energy = 0.5 * (model.spring_stiffness().array() * (q - model.spring_rest()).array().square()).sum();
}

// The spring-mass ROM's energies [J] on its plan at plan_time_s (potential above rom_x_ref).
void RecordRomEnergies(const SpringMassParams& rom, const SpringMassPlan& plan, double plan_time_s, double rom_x_ref,
                       HoppingSample* s) {
  const Eigen::Vector4d z = plan.State(plan_time_s);
  s->rom_kinetic = 0.5 * rom.mass * z[1] * z[1];
  s->rom_potential = rom.mass * rom.gravity * (z[0] - rom_x_ref);
  s->rom_spring = 0.5 * rom.n_legs * rom.leg.stiffness.Evaluate(z[2]) * (z[2] - z[0]) * (z[2] - z[0]);
}

}  // namespace

HoppingRunResult RunHopping(const HoppingDiagram& d, Simulator& sim, const HoppingRunParams& params,
                            const SpringMassHopPlanners* planners) {
  params.Validate();
  if (!d.reference->initialized(d.diagram->GetSubsystemContext(*d.reference, sim.get_context())))
    throw std::invalid_argument(
        "RunHopping: the initial state is not set: call SetHoppingInitialState(diagram, context, q) before running");
  const double apex_rise =
      std::isnan(params.apex_rise_m) && planners ? planners->jump_params.apex_rise : params.apex_rise_m;
  if (std::isnan(apex_rise))
    throw std::invalid_argument("RunHopping: HoppingRunParams::apex_rise_m = nan needs the planners (got none)");
  const MultibodyModel& model = *d.model;
  const int nv = model.nv(), hops = d.params.reference.hops;
  MultibodyWorkspace ws(model);
  const int pitch_index = model.VelocityIndex("base_pitch"), base_z = model.VelocityIndex("base_z");
  const int shin[2] = {model.VelocityIndex("left_shin_spring"), model.VelocityIndex("right_shin_spring")};
  const int knee[2] = {model.VelocityIndex("left_knee"), model.VelocityIndex("right_knee")};
  const std::vector<PlannerRecord>* records = planners ? planners->records.get() : nullptr;
  const HoppingOutputLayout& layout = d.layout;

  HoppingRunResult r;
  HoppingRunState state;
  double com_z_ref = NAN, rom_x_ref = NAN;  // at the current hop's jump start
  double next_sample_t = 0.0;
  // *_now: the current hop's (the ROM force of its plans); the result's: the first hop's.
  double jump_start_now = -1, touchdown_now = -1, com_liftoff = 0, com_max = 0, pitch_liftoff = 0;
  const bool stop_after_last = params.duration_s <= 0;
  const bool has_qp_failures = d.diagram->HasOutputPort("qp_failures");
  double last_progress = 0;
  // The run's monitor refers to this function's locals: it is removed when the function leaves, also by an exception.
  struct RemoveMonitor {
    Simulator& sim;
    ~RemoveMonitor() { sim.remove_monitor("hopping_run"); }
  } remove_monitor{sim};
  sim.add_monitor(
      [&](const Context& c) {
        const LeafContext& pc = d.diagram->GetSubsystemContext(*d.plant, c);
        const LeafContext& rc = d.diagram->GetSubsystemContext(*d.reference, c);
        r.contact.Record(*d.plant, pc);
        const Eigen::VectorXd& x = HoppingEulerState(d, c);  // the controller's (Euler) coordinates
        const Eigen::VectorXd q = x.head(nv);
        const int domain = d.reference->EvalTypedOutput<int>(rc, "domain");
        const int last_domain = state.domain;
        const double t = pc.time();
        const Eigen::VectorXd& f = d.plant->EvalOutput(pc, "contact_forces");
        // The COM height only where it is used (a domain change, Flight, a sample): a new q costs the forward
        // kinematics.
        const bool sample_due = t >= next_sample_t;
        const double com_z = domain != last_domain || domain == HoppingDomain::kFlight || sample_due
                                 ? CalcComPosition(model, ws, q).z()
                                 : NAN;
        if (domain == HoppingDomain::kJump && last_domain != HoppingDomain::kJump) {
          jump_start_now = t;
          if (r.jump_start_s < 0) r.jump_start_s = t;
          com_z_ref = com_z;
          if (records && !records->empty()) rom_x_ref = records->back().plan.states(0, 0);
        }
        if (domain == HoppingDomain::kLanding && last_domain == HoppingDomain::kFlight)
          touchdown_now = t, ++r.touchdowns;
        if (domain == HoppingDomain::kFlight && last_domain != HoppingDomain::kFlight && r.liftoff_s < 0) {
          r.liftoff_s = t, com_liftoff = com_max = com_z, pitch_liftoff = q[pitch_index];
          r.liftoff_foot_com_offset_x_m = FootComOffsetX(model, ws, q);
          r.liftoff_pitch_momentum_Nms = CalcCentroidalMomentum(model, ws, q, x.tail(nv))[1];
          r.liftoff_state = x;
        }
        if (domain == HoppingDomain::kLanding && last_domain == HoppingDomain::kFlight && r.touchdown_s < 0) {
          r.touchdown_s = t;
          r.touchdown_foot_com_offset_x_m = FootComOffsetX(model, ws, q);
        }
        if (r.touchdown_s < 0) {
          r.contact_violations_before_first_touchdown = r.contact.violations;
          if (has_qp_failures) r.qp_failures_at_first_touchdown = d.diagram->EvalOutput(c, "qp_failures")[0];
        }
        if (r.touchdown_s > 0)
          r.min_pelvis_height_after_touchdown_m = std::isfinite(r.min_pelvis_height_after_touchdown_m)
                                                      ? std::min(r.min_pelvis_height_after_touchdown_m, q[base_z])
                                                      : q[base_z];
        if (domain == HoppingDomain::kFlight && r.touchdown_s < 0) {
          double lowest = 1e9;
          for (int k = 0; k < model.num_contacts(); ++k) lowest = std::min(lowest, CalcContactHeight(model, ws, q, k));
          r.foot_clearance_m = std::max(r.foot_clearance_m, lowest);
          com_max = std::max(com_max, com_z);
          r.max_pelvis_pitch_change_flight_rad =
              std::max(r.max_pelvis_pitch_change_flight_rad, std::abs(q[pitch_index] - pitch_liftoff));
        }
        // ROM force of the active plan (Jump: the jump plan from its start; Landing after a hop: the landing plan).
        double rom_grf = NAN;
        if (records && domain == HoppingDomain::kJump && !records->empty() && records->back().plan.success())
          rom_grf = records->back().plan.LegForce(planners->rom, t - jump_start_now);
        if (records && domain == HoppingDomain::kLanding && touchdown_now > 0 && !records->empty() &&
            records->back().kind == PlannerRecord::Kind::kLanding &&
            records->back().plan.success())  // a failed solve: the quintic fallback
          rom_grf = records->back().plan.LegForce(planners->rom, t - touchdown_now);
        if (sample_due) {
          HoppingSample s;
          s.t = t, s.grf = f[2] + f[5], s.rom_grf = rom_grf, s.com_z = com_z, s.pitch = q[pitch_index];
          s.shin_torque =
              -model.spring_stiffness()[shin[0]] * x[shin[0]] - model.spring_stiffness()[shin[1]] * x[shin[1]];
          s.pitch_momentum = CalcCentroidalMomentum(model, ws, q, x.tail(nv))[1];
          s.since_touchdown = touchdown_now > 0 ? t - touchdown_now : -1.0;
          s.domain = domain;
          if (params.record_plot_samples) {
            double L_leg[2], dL;
            for (int leg = 0; leg < 2; ++leg) d.leg_length(q[knee[leg]], &L_leg[leg], &dL);
            s.leg_length = 0.5 * (L_leg[0] + L_leg[1]);
            s.com_x = CalcComPosition(model, ws, q).x();
            if (domain != HoppingDomain::kFlight) {
              const Eigen::VectorXd& yd = d.reference->EvalOutput(rc, "desired");
              s.leg_length_d = 0.5 * (yd[layout.leg_left] + yd[layout.leg_right]), s.com_x_d = yd[layout.com_x],
              s.pitch_d = yd[layout.pitch];
            }
            RecordEnergies(model, ws, x, com_z - com_z_ref, planners, &s);
            if (std::isfinite(rom_grf)) {
              const double plan_t = domain == HoppingDomain::kJump ? t - jump_start_now : t - touchdown_now;
              RecordRomEnergies(planners->rom, records->back().plan, plan_t, rom_x_ref, &s);
              s.leg_length_plan = records->back().plan.State(plan_t)[2];
            }
            s.q = q;
          }
          r.samples.push_back(std::move(s));
          next_sample_t = std::floor(t / params.sample_period_s + 1.0) * params.sample_period_s;
        }
        state.previous_domain = last_domain, state.domain = domain, state.touchdowns = r.touchdowns;
        state.liftoff_s = r.liftoff_s, state.touchdown_s = r.touchdown_s;
        if (params.observer) params.observer(c, state);
        if (r.touchdowns >= hops && t >= touchdown_now + params.rest_check_delay_s && std::isnan(r.rest_speed))
          r.rest_speed = x.tail(nv).cwiseAbs().maxCoeff();
        if (stop_after_last && r.touchdowns >= hops && t >= touchdown_now + params.stop_after_last_touchdown_s) {
          std::ostringstream why;
          why << "all " << hops << " hop(s) landed; " << params.stop_after_last_touchdown_s
              << " s after the last touchdown";
          return EventStatus::ReachedTermination(why.str());
        }
        if (params.progress && t - last_progress >= params.progress_period_s) {
          last_progress = t;
          *params.progress << "  t = " << t << " s, domain " << domain << "\n";
        }
        return EventStatus::Succeeded();
      },
      "hopping_run");

  const double duration = HoppingRunDuration(d, params);
  const auto wall0 = std::chrono::steady_clock::now();
  r.status = sim.AdvanceTo(duration);
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  sim.remove_monitor("hopping_run");  // before the metrics: the monitor refers to this function's locals

  FinishHoppingMetrics(d, sim, params, records, apex_rise, com_liftoff, com_max, has_qp_failures, &r);
  return r;
}

std::string HoppingSummaryJson(const HoppingDiagram& d, const HoppingRunResult& r,
                               const SpringMassHopPlanners* planners, const std::string& scenario_json) {
  nlohmann::json s;
  s["success"] = r.success;
  s["status_kind"] = r.status_kind;
  s["status"] = r.status.ToString();
  s["air_time_s"] = r.air_time_s;
  s["foot_clearance_m"] = r.foot_clearance_m;
  s["com_rise_m"] = r.com_rise_m;
  s["takeoff_time_error_s"] = r.takeoff_time_error_s;
  s["jump_plans"] = r.jump_plans;
  s["landing_plans"] = r.landing_plans;  // at each planned lift-off (predicted touchdown) and at each touchdown
  s["planner_failures"] = r.planner_failures;
  s["rest_speed_2s_after_last_touchdown"] = r.rest_speed;  // max |q̇| [rad/s, m/s]
  s["grf_nrmse_jump"] = r.grf_nrmse_jump;
  s["grf_nrmse_landing"] = r.grf_nrmse_landing;
  s["spring_torque_grf_correlation"] = r.spring_torque_grf_correlation;
  s["settled"] = r.settled;
  s["hopped"] = r.hopped;
  s["hops_landed"] = r.touchdowns;
  s["max_pelvis_pitch_change_flight_rad"] = r.max_pelvis_pitch_change_flight_rad;
  s["liftoff_foot_com_offset_x_m"] = r.liftoff_foot_com_offset_x_m;
  s["liftoff_pitch_momentum_Nms"] = r.liftoff_pitch_momentum_Nms;
  s["touchdown_foot_com_offset_x_m"] = r.touchdown_foot_com_offset_x_m;
  s["min_pelvis_height_after_touchdown_m"] = r.min_pelvis_height_after_touchdown_m;
  s["qp_infeasible_ticks"] = r.qp_failures;
  s["qp_solve_us_median"] = r.qp_solve_us_median;
  s["qp_solve_us_p99"] = r.qp_solve_us_p99;
  s["realtime_factor"] = r.realtime_factor;
  const HoppingReferenceParams& ref = d.params.reference;
  s["jump_momentum_gain"] = ref.jump_momentum_gain;
  s["flight_hip_follow"] = ref.flight_hip_pitch_follow;
  s["landing_blend_s"] = ref.landing_blend_s;
  s["landing_deflection_feedback"] = ref.landing_deflection_feedback;
  s["jump_force_feedback"] = ref.jump_force_feedback;
  s["jump_force_integral_per_s"] = ref.jump_force_integral_per_s;
  s["landing_torque_regularization"] = d.params.landing_u_regularization_scale;
  s["plant"] = ToString(d.plant_kind);
  s["plant_base"] = ToString(d.params.plant_base);
  s["bullet_substeps"] = d.params.bullet_plant.substeps;
  if (planners) {
    s["leg_stiffness"] = planners->variant == LegStiffnessVariant::kPublished ? "published" : "identified";
    s["landing_min_force_fraction"] = planners->landing_params.min_force_fraction;
    s["apex_rise_m"] = planners->jump_params.apex_rise;
  }
  s["contact_violations"] = r.contact.violations;
  s["first_contact_violation"] = r.contact.first_violation;
  s["max_friction_ratio"] = r.contact.max_friction_ratio;
  s["simulated_s"] = r.simulated_s;
  nlohmann::json nlp = nlohmann::json::array();
  for (const PlannerRecord& p : r.planner_records)
    nlp.push_back({{"problem", p.kind == PlannerRecord::Kind::kJump      ? "jump"
                               : p.kind == PlannerRecord::Kind::kLanding ? "landing"
                                                                         : "landing_predicted_at_liftoff"},
                   {"time_s", p.plan.solve_time_s},
                   {"iterations", p.plan.iterations},
                   {"violation", p.plan.max_violation},
                   {"duration_s", p.plan.duration},
                   {"status", p.plan.message}});
  s["nlp"] = nlp;
  const SimulatorStatistics& stats = r.integrator;
  s["integrator"] = {{"steps", stats.steps},
                     {"rhs_evaluations", stats.rhs_evals},
                     {"jacobian_evaluations", stats.jacobian_evals},
                     {"jacobian_rhs_evaluations", stats.jacobian_rhs_evals},
                     {"nonlinear_iterations", stats.nonlinear_iterations},
                     {"error_test_failures", stats.error_test_failures},
                     {"convergence_failures", stats.convergence_failures},
                     {"restarts", stats.restarts},
                     {"root_evaluations", stats.root_evals},
                     {"guard_events", stats.guard_events},
                     {"discrete_samples", stats.discrete_samples},
                     {"wall_s", r.wall_s}};
  if (!scenario_json.empty()) s["scenario"] = nlohmann::json::parse(scenario_json);
  return s.dump(2) + "\n";
}

}  // namespace rome
