#pragma once
// What a stepping-stones run means, shared by the example program and the tests: the run from the initial state to the
// supervisor's verdict or a time limit, the figures measured on the way, and the success rule.
//
// Build → run → result from C++:
//   SteppingStonesDiagramParams params;
//   params.supervisor.max_steps = 10;
//   SteppingStonesDiagram d = BuildSteppingStonesDiagram(PeriodicSteppingStones(0.4, 0.0, 12), params);
//   Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
//   SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
//   const SteppingStonesResult r = RunSteppingStones(d, sim);
//   if (r.success) std::cout << r.steps.size() << " steps at " << r.mean_forward_speed_mps() << " m/s\n";
//
// Success rule: the supervisor ended the run with ReachedTermination (max_steps walked, or the last stone reached: the
// diagram's planned end), and the plant's own contact forces stayed unilateral and inside the friction cone at every
// integrator step and event (ContactForceStatistics). A run that reaches the time limit is not a success (kind
// "limit"); a fall, a missed stone, a slip or a block that rejects its inputs is a failure.

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "diagrams/stepping_stones/stepping_stones_diagram.h"
#include "framework/simulator.h"
#include "systems/plants/contact_force_statistics.h"

namespace rome {

/// RMS tracking errors of the stepping-stones outputs (Eq. (19)) against the output adapter's world-frame desired
/// values (the `desired` layout of SteppingStonesControllerSpec): torso pitch [rad], COM height [m], and the swing
/// foot's position (x, z) [m] (the foot that swings in the plant's mode), measured on the plant state.
class SteppingStonesTrackingStatistics {
 public:
  explicit SteppingStonesTrackingStatistics(const MultibodyModel& model);
  /// One sample: plant state x = [q; v], plant mode, the output adapter's `desired` port.
  void Record(const Eigen::VectorXd& x, int mode, const Eigen::VectorXd& desired);
  double torso_pitch_rms_rad() const { return Rms(0); }
  double com_height_rms_m() const { return Rms(1); }
  double swing_foot_rms_m() const { return Rms(2); }

 private:
  double Rms(int k) const;
  const MultibodyModel& model_;
  MultibodyWorkspace ws_;
  int left_, right_;
  double sum_[3] = {0, 0, 0};
  long n_ = 0, n_swing_ = 0;
};

/// [s] Longest simulated time a run may ask for (ours: 30 000 steps at 3 s each plus margin; bounded work).
inline constexpr double kMaxRunTime_s = 1e5;

struct SteppingStonesRunOptions {
  /// [s] Simulated time limit; NaN: 3 s per step of params.supervisor.max_steps, plus 2 s (ours: a step lasts 0.3-0.6
  /// s).
  double max_time_s = std::numeric_limits<double>::quiet_NaN();
  /// [s] The run advances in chunks of this length; `progress` is called after each.
  double chunk_s = 0.5;
  /// Called after each chunk with the simulator and the steps so far (e.g. to print progress); may be empty.
  std::function<void(const Simulator&, const std::vector<StepRecord>&)> progress;
};

struct SteppingStonesResult {
  SimulatorStatus status;          ///< how the run ended; a block that threw mid-run gives kFailed with its message
  bool success = false;            ///< the success rule (top of this file)
  bool fell = false;               ///< a failure whose message says the robot fell
  std::vector<StepRecord> steps;   ///< the supervisor's step records
  ContactForceStatistics contact;  ///< the plant's contact forces after every integrator step and event
  /// RMS tracking errors (SteppingStonesTrackingStatistics), sampled after every integrator step and event.
  double tracking_torso_pitch_rms_rad = 0, tracking_com_height_rms_m = 0, tracking_swing_foot_rms_m = 0;
  double u_squared_integral_N2m2s = 0;  ///< [N² m² s] ∫ |u|² dt of the held torque
  std::vector<double>
      controller_update_times_s;  ///< [s] each new value of the controller's solve_time_s port, if it has one
  double sim_time_s = 0, wall_time_s = 0;
  double x_start_m = 0, x_end_m = 0;  ///< [m] COM x at the first logged sample and at the end
  double max_foothold_error_m = 0;    ///< [m] largest StepRecord::foothold_error_m
  int qp_failures = 0;                ///< the controller's and the vertical-COM MPC's qp_failures
  int nlp_failures = 0;               ///< posture NLP failures (SteppingStonesSupervisor::posture_failures)
  bool has_clf_activity = false;      ///< the controller has a clf_activity port (CLF-QP)
  double clf_active_updates = 0, clf_solved_updates = 0;
  std::string
      controller_kind;  ///< the controller block's C++ class without its namespace, e.g. "TaskSpaceQpController"
  SimulatorStatistics integrator;

  double mean_forward_speed_mps() const { return sim_time_s > 0 ? (x_end_m - x_start_m) / sim_time_s : 0.0; }
  double u_squared_integral_per_step() const {
    return steps.empty() ? 0.0 : u_squared_integral_N2m2s / static_cast<double>(steps.size());
  }
  /// [s] The p-quantile (p in [0, 1], nearest rank) of controller_update_times_s; 0 if there are none.
  double ControllerUpdateTime(double p) const;
};

/// Runs `sim` (on d.diagram, its state set by SetSteppingStonesInitialState) to the supervisor's verdict or the time
/// limit, measuring the figures of SteppingStonesResult with a monitor it adds to `sim` (other monitors may be added
/// before; the monitor refers to `d`, which must outlive any later use of `sim`). Returns the result with the success
/// rule applied.
SteppingStonesResult RunSteppingStones(const SteppingStonesDiagram& d, Simulator& sim,
                                       const SteppingStonesRunOptions& options = {});

}  // namespace rome
