#pragma once
// RunWalking: simulates a built WalkingDiagram and judges the run: what counts as a step, the walking issue's metrics
// and the success rule. The example (examples/walking) and walking_diagram_test use this one code.
//
// Start: at params.start_time_s in double support, in WalkingStandingPose (both feet flat on the plan's footholds,
// the COM on the plan's), at rest or (start_at_rest false: on the plan's orbit) at WalkingInitialVelocity.
// End: params.end_time_s (NaN: the plan's end less trailing_steps of its last step, SSP + DSP, so that the momentum
// correction's end of the plan is not judged), or earlier when the plant fails (a fall, a slip) or on SIGINT/SIGTERM.
//
// Measured from the PLANT after every integrator step and event (the simulator's monitor):
//   touchdown: the plant's mode enters double support, or goes straight from one stance into the other (modes of
//     ContactModeGraph::WithDoubleSupport: 0 left stance, 1 double support, 2 right stance). It is a step when the
//     landed ankle's (x, y) lies within foothold_tolerance_m of that foot's planned foothold at that instant;
//   pre-impact COM state [x, y, z, ẋ, ẏ, ż] about the stance ankle (y mirrored in right stance), sampled in single
//     support and extrapolated to each touchdown (PreImpactSampler); after each transition (a single support with
//     footed H-LIP nodes) its step-to-step change (2-norm) from the 5th periodic touchdown on (walking issue);
//   lift-off force: the plant's normal force on the foot just before it leaves (the largest over the run);
//   contact: ContactForceStatistics of the plant's own forces; the plant's contact_violation port;
//   joint limits: JointLimitStatistics of the plant's q against the URDF's position limits (and of the start pose).
// Once per control tick (tick_period_s, the controller's 1 kHz):
//   COM position error against the plan's COM after the first step (from the plan's third segment), RMS and max per
//   axis; pelvis roll, pitch, yaw (largest |angle|); the Eq. (25) band on the plant's normal forces: each foot's F_z
//   within
//   [(1 − c) F_ref − s m g, (1 + c) F_ref + s m g] (c: the controller's force_band_halfwidth, s: band_slack_mg, m:
//   the controller's (nominal) model's mass, not the plant's, which a mass-scale perturbation changes; F_ref: the
//   plan's aSLIP force at t), scored outside band_settle_s after each touchdown, and strictly (s = 0: Eq. (25) as
//   written); the CLF-QP's δ and solve time.
// Success: the simulator reached the end time (no failure, no interrupt), every single support of the plan that ends
// before the end time ended in a step on its foothold, none landed off target, no contact violation, and (with
// judge_standing_end, walk-to-stand) the plant ends standing at rest. (Joint limits
// are reported, not judged: the walking plans bend the ankles beyond the URDF's, docs/design-notes.md#joint-limits.)
//
// The monitor allocates only at touchdowns (the pre-impact list); the per-tick solve-time list is reserved up front.
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "diagrams/walking/walking_diagram.h"
#include "framework/simulator.h"
#include "systems/plants/contact_force_statistics.h"
#include "systems/plants/joint_limit_statistics.h"

namespace rome {

/// The standing state of a run's end, measured on the robot from the plant's [q; v]: the horizontal distance from the
/// COM to the midpoint between the ankles (the "left_foot" and "right_foot" contacts' links) and the COM speed.
struct StandingMeasure {
  double com_to_feet_midpoint_m = 0;  ///< [m] horizontal
  double com_speed_mps = 0;           ///< [m/s] 3D
  double feet_gap_x_m = 0;            ///< [m] |x_left − x_right| of the ankles (side by side: ~0)
};
StandingMeasure MeasureStanding(const MultibodyModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v);

struct WalkingRunParams {
  /// [s] end of the run; NaN: the plan's end less trailing_steps steps of its last gait.
  double end_time_s = std::numeric_limits<double>::quiet_NaN();
  int trailing_steps = 2;     ///< [-] planned steps past the run's end (ours: the plan's end is not judged)
  double start_time_s = 0.0;  ///< [s] start, inside the plan's first double support
  bool start_at_rest = true;  ///< false: the plan's COM velocity (WalkingInitialVelocity; the periodic scenario)
  double foothold_tolerance_m = 0.05;  ///< [m] a touchdown is a step only this close to its planned foothold (ours)
  double tick_period_s = 1e-3;         ///< [s] the per-tick metrics' sampling (the controller's 1 kHz)
  double band_settle_s = 0.02;         ///< [s] the force band is not scored this long after each touchdown (ours)
  double band_slack_mg = 0.02;         ///< [-] the band's slack, a fraction of m g (ours)
  int convergence_from_step = 5;  ///< the pre-impact change is judged from this periodic touchdown after a transition
  /// Walk-to-stand: the run succeeds only if it ends standing at rest, the plant's COM within at_rest_offset_m of the
  /// midpoint between the ankles (horizontal) and at most at_rest_speed_mps fast (issue 39's acceptance;
  /// MeasureStanding). Off: the end is measured and reported, not judged.
  bool judge_standing_end = false;
  double at_rest_offset_m = 0.01;   ///< [m] in (0, 0.1]
  double at_rest_speed_mps = 0.01;  ///< [m/s] in (0, 0.1]
  SimulatorConfig simulator = WalkingSimulatorConfig();

  /// Throws std::invalid_argument "WalkingRunParams: FIELD = VALUE is outside RANGE" for the first bad field.
  void Validate() const;
};

/// One monitor sample, for an observer (a log, plots, an animation, extra checks). References are valid during the
/// call.
struct WalkingRunSample {
  double t = 0;
  int mode = kWalkingDoubleSupport;  ///< the plant's mode (WalkingPlantMode)
  bool tick = false;     ///< the first sample of a control tick; the fields below marked (tick) are set then
  long tick_index = -1;  ///< floor(t / tick_period_s)
  const Eigen::VectorXd* q = nullptr;
  const Eigen::VectorXd* v = nullptr;
  const Eigen::VectorXd* contact_forces = nullptr;         ///< the plant's [F_left; F_right] (world, N)
  const Eigen::VectorXd* u = nullptr;                      ///< the torque the plant receives (its input 'u', N m)
  Eigen::Vector3d com = Eigen::Vector3d::Zero();           ///< (tick) [m]
  Eigen::Vector3d com_velocity = Eigen::Vector3d::Zero();  ///< (tick) [m/s]
  WalkingReference reference;                              ///< (tick) the plan at t
  int steps = 0;                                           ///< steps so far
};
using WalkingRunObserver = std::function<void(const Context& diagram_context, const WalkingRunSample& sample)>;

struct WalkingRunResult {
  using ComState = Eigen::Matrix<double, 6, 1>;
  SimulatorStatus status;
  bool success = false;  ///< no fall, exactly the planned steps (an extra touchdown is a bounce), none off target, no
                         ///< contact violation
  bool fell = false;     ///< the run ended before its end time for a reason other than an interrupt
  bool interrupted = false;
  double start_time_s = 0, end_time_s = 0;  ///< [s] the run's start and planned end
  double simulated_s = 0;                   ///< [s] the context's time at the end
  double wall_s = 0;                        ///< [s] wall time of the simulation
  int steps_completed = 0;                  ///< touchdowns on their footholds
  int steps_planned = 0;                    ///< single supports of the plan ending before end_time_s
  int touchdowns_off_target = 0;
  double largest_touchdown_error_m = 0;
  int liftoffs = 0;
  double first_liftoff_time_s = -1, first_touchdown_time_s = -1;
  double liftoff_normal_force_max_N = 0;
  std::vector<std::pair<double, ComState>> pre_impact_states;  ///< (touchdown time, COM state just before)
  std::vector<double> transition_ends_s;                       ///< end of each transition's single support
  /// Per transition: the largest step-to-step change from the convergence_from_step-th periodic touchdown on; −1 with
  /// fewer touchdowns after it.
  std::vector<double> pre_impact_state_change_from_step5;
  Eigen::Vector3d com_rms_error_m = Eigen::Vector3d::Zero(), com_max_error_m = Eigen::Vector3d::Zero();
  double pelvis_max_orientation_error_rad = 0;
  double force_in_band_fraction = 0;         ///< ticks × feet in the band with the band_slack_mg tolerance
  double force_in_band_fraction_strict = 0;  ///< the same ticks in the band with no tolerance (Eq. (25) as written)
  long band_samples = 0;
  ContactForceStatistics contact;
  long contact_violation_port_samples = 0;  ///< samples where the plant's contact_violation port was not zero
  JointLimitStatistics joint_limits;        ///< the plant's q against the URDF's position limits, every sample
  /// [rad] the smallest margin to a joint limit over the run (negative: beyond it), and "<joint> lower|upper"
  double joint_limit_min_margin = std::numeric_limits<double>::infinity();
  std::string joint_limit_min_margin_at;
  long samples = 0, ticks = 0;
  /// The plant's state at the run's end (MeasureStanding), and whether it is at rest by the params' bounds (judged
  /// for success only with judge_standing_end).
  StandingMeasure standing_end;
  bool at_rest = false;
  bool standing_end_judged = false;
  /// The ClfQpController's diagnostics (WalkingDiagram::clf_qp; zeros when the controller has none).
  double qp_infeasible_ticks = 0, qp_fallbacks = 0, clf_row_active_fraction = 0, clf_relaxation_max = 0;
  double qp_solve_us_median = 0, qp_solve_us_p99 = 0;
  double realtime_factor() const { return wall_s > 0 ? simulated_s / wall_s : 0.0; }
  /// "interrupted", "success" or "failure" (the summary's status_kind; the same words as SimulatorStatus::kind_name).
  std::string status_kind() const;
  /// The run's metrics as JSON object text: the walking example's summary fields (success, status_kind,
  /// steps_completed, steps_planned, the pre-impact states and their change, COM and pelvis errors, band, contact and
  /// QP figures).
  std::string ToJson() const;
};

/// Simulates `walking` as described above. `observer`, if given, is called after the run's own bookkeeping at every
/// monitor sample. Throws std::invalid_argument for bad params (Validate) or an end time before the start.
WalkingRunResult RunWalking(const WalkingDiagram& walking, const WalkingRunParams& params = {},
                            const WalkingRunObserver& observer = {});

/// The planned end of a run of `plan` with `params` (params.end_time_s, or the plan's end less trailing_steps steps).
double WalkingRunEndTime(const WalkingPlan& plan, const WalkingRunParams& params);

}  // namespace rome
