#include "diagrams/stepping_stones/stepping_stones_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "systems/multibody/multibody_kinematics.h"

namespace rome {

SteppingStonesTrackingStatistics::SteppingStonesTrackingStatistics(const MultibodyModel& model)
    : model_(model), ws_(model), left_(model.ContactIndex("left_foot")), right_(model.ContactIndex("right_foot")) {}

void SteppingStonesTrackingStatistics::Record(const Eigen::VectorXd& x, int mode, const Eigen::VectorXd& desired) {
  const int nv = model_.nv();
  const Eigen::VectorXd q = x.head(nv);
  const double pitch = q[model_.num_base_dofs() - 1];
  const double com_z = CalcComPosition(model_, ws_, q).z();
  sum_[0] += std::pow(pitch - desired[0], 2);
  sum_[1] += std::pow(com_z - desired[1], 2);
  ++n_;
  using Mode = ContactModeGraph::SingleSupportMode;
  if (mode == Mode::kLeftStance || mode == Mode::kRightStance) {  // the swing foot's rows: right foot in left stance
                                                                  // (4, 5), left foot in right stance (2, 3)
    const int contact = mode == Mode::kLeftStance ? right_ : left_, row = mode == Mode::kLeftStance ? 4 : 2;
    const ContactInfo& info = model_.contacts()[contact];
    const Eigen::Vector3d p = CalcPointPosition(model_, ws_, q, info.body, info.frame_origin);
    sum_[2] += std::pow(p.x() - desired[row], 2) + std::pow(p.z() - desired[row + 1], 2);
    ++n_swing_;
  }
}

double SteppingStonesTrackingStatistics::Rms(int k) const {
  return std::sqrt(sum_[k] / std::max<long>(k == 2 ? n_swing_ : n_, 1));
}

double SteppingStonesResult::ControllerUpdateTime(double p) const {
  std::vector<double> v = controller_update_times_s;
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5))];
}

namespace {

// What the monitor measures after every integrator step and event; shared with the monitor, which the simulator keeps.
struct RunMeasurements {
  explicit RunMeasurements(const MultibodyModel& model) : tracking(model), last_u(Eigen::VectorXd::Zero(model.nu())) {}
  ContactForceStatistics contact;
  SteppingStonesTrackingStatistics tracking;
  std::vector<double> solve_times;
  double u2_integral = 0, last_time = 0, last_solve_time = -1;
  Eigen::VectorXd last_u;
};

}  // namespace

SteppingStonesResult RunSteppingStones(const SteppingStonesDiagram& d, Simulator& sim,
                                       const SteppingStonesRunOptions& options) {
  if (!(options.chunk_s > 0))
    throw std::invalid_argument("RunSteppingStones: options.chunk_s must be positive, got " +
                                std::to_string(options.chunk_s) + " s");
  const LeafContext& sup_ctx = d.diagram->GetSubsystemContext(*d.supervisor, sim.get_context());
  const double max_time =
      std::isnan(options.max_time_s) ? 3.0 * d.supervisor->params().max_steps + 2.0 : options.max_time_s;
  if (!(max_time > 0 && max_time <= kMaxRunTime_s))
    throw std::invalid_argument("RunSteppingStones: options.max_time_s must be NaN or in (0, " +
                                std::to_string(kMaxRunTime_s) + "] s, got " + std::to_string(options.max_time_s));
  auto m = std::make_shared<RunMeasurements>(*d.model);
  m->solve_times.reserve(static_cast<size_t>(std::min(max_time, 3600.0) * 1000.0) +
                         1000);  // 1 kHz updates; grows beyond an hour
  // The run's monitor is removed when the function leaves (also by an exception): the caller's monitors stay.
  struct RemoveMonitor {
    Simulator& sim;
    ~RemoveMonitor() { sim.remove_monitor("stepping_stones_run"); }
  } remove_monitor{sim};
  const bool has_solve_time = d.controller->HasOutputPort("solve_time_s");
  sim.add_monitor(
      [&d, m, has_solve_time](const Context& c) {
        const LeafContext& plant_context = d.diagram->GetSubsystemContext(*d.plant, c);
        m->contact.Record(*d.plant, plant_context);
        m->u2_integral += m->last_u.squaredNorm() * (c.time() - m->last_time);  // u is held between updates
        m->last_time = c.time();
        m->last_u = d.EvalControllerOutput(c, "u");
        m->tracking.Record(
            d.plant->EvalOutput(plant_context, "state"), d.plant->EvalTypedOutput<int>(plant_context, "mode"),
            d.output_adapter->EvalOutput(d.diagram->GetSubsystemContext(*d.output_adapter, c), "desired"));
        if (has_solve_time) {
          const double st = d.EvalControllerOutput(c, "solve_time_s")[0];
          if (st != m->last_solve_time && st > 0) m->solve_times.push_back(st);
          m->last_solve_time = st;
        }
        return EventStatus::Succeeded();
      },
      "stepping_stones_run");

  SteppingStonesResult r;
  const auto start = std::chrono::steady_clock::now();
  for (double t = options.chunk_s; t <= max_time + 1e-9; t += options.chunk_s) {
    try {
      r.status = sim.AdvanceTo(t);
    } catch (const std::exception& e) {
      // A block rejected its inputs mid-run (e.g. a step the planner cannot reach): a failed run, not a crash.
      r.status.reason = SimulatorStatus::Reason::kFailed;
      r.status.time = sim.get_context().time();
      r.status.message = e.what();
    }
    if (options.progress) options.progress(sim, d.supervisor->steps(sup_ctx));
    if (!r.status.ok()) break;
  }
  r.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const Context& c = sim.get_context();
  r.steps = d.supervisor->steps(sup_ctx);
  r.sim_time_s = c.time();
  r.contact = m->contact;
  r.tracking_torso_pitch_rms_rad = m->tracking.torso_pitch_rms_rad();
  r.tracking_com_height_rms_m = m->tracking.com_height_rms_m();
  r.tracking_swing_foot_rms_m = m->tracking.swing_foot_rms_m();
  r.u_squared_integral_N2m2s = m->u2_integral;
  r.controller_update_times_s = m->solve_times;
  r.success = r.status.kind() == SimulatorStatus::Kind::kSuccess && r.contact.violations == 0;
  r.fell = r.status.kind() == SimulatorStatus::Kind::kFailure && r.status.message.find("fell") != std::string::npos;
  r.x_end_m = d.plant->EvalOutput(d.diagram->GetSubsystemContext(*d.plant, c), "com")[0];
  const LogData& log = d.logger->log(d.diagram->GetSubsystemContext(*d.logger, c));
  r.x_start_m = log.samples.empty() ? r.x_end_m : log.samples.front()[d.logger->ColumnIndex("plant.com.x")];
  for (const StepRecord& s : r.steps) r.max_foothold_error_m = std::max(r.max_foothold_error_m, s.foothold_error_m);
  r.qp_failures = static_cast<int>(d.EvalControllerOutput(c, "qp_failures")[0]) +
                  static_cast<int>(d.mpc->EvalOutput(d.diagram->GetSubsystemContext(*d.mpc, c), "qp_failures")[0]);
  r.nlp_failures = d.supervisor->posture_failures(sup_ctx);
  r.has_clf_activity = d.controller->HasOutputPort("clf_activity");
  if (r.has_clf_activity) {  // [active, solved updates]: how often the CLF inequality binds at the solution
    const Eigen::VectorXd a = d.EvalControllerOutput(c, "clf_activity");
    r.clf_active_updates = a[0];
    r.clf_solved_updates = a[1];
  }
  const System& controller = *d.controller;
  const std::string type = DemangledTypeName(typeid(controller));
  r.controller_kind = type.substr(type.rfind(':') + 1);
  r.integrator = sim.statistics();
  return r;
}

}  // namespace rome
