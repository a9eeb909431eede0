#pragma once
// RunHopping: what a hopping run means (hopping paper, Sec. V and Fig. 6), as library code the example and the tests
// share. It runs a built HoppingDiagram in its Simulator and measures, after every integrator step and event (the
// simulator's monitor):
//   * the hops: a domain change Jump → Flight is a lift-off, Flight → Landing a touchdown (the reference's domain,
//     driven by the plant's guards); the first hop's jump start, lift-off and touchdown times, COM rise, foot clearance
//     (lowest contact frame above the ground in flight), pelvis pitch change in flight, the feet's x offset from the
//     COM at lift-off and touchdown, H_pitch at lift-off, and the lowest pelvis height after the touchdown;
//   * the normal GRF against the ROM's leg force on a fixed sample grid (the first step at or after each tick):
//     NRMSE (RMS error / peak ROM force) in Jump and in Landing (after landing_grf_skip_s), and the correlation of the
//     shin springs' torque −Σ k q_shin with the GRF from the first jump start on (Fig. 6);
//   * the plant's own contact forces against unilateral contact and the friction cone (ContactForceStatistics);
//   * rest: max |q̇| rest_check_delay_s after the last hop's touchdown.
// Success rule: the run ended without a failure (ok or ReachedTermination), it hopped (lift-off and touchdown, the COM
// rose at least min_com_rise_fraction H in flight), it settled (max |q̇| < rest_max_speed at the rest check and at the
// end) and no contact sample violated the cone.
// With duration_s = 0 the run ends (ReachedTermination) stop_after_last_touchdown_s after the last hop's touchdown,
// or at settle + hops · 1 s + (hops − 1) max_rest_time_s + stop_after_last_touchdown_s at the latest.
// Usage (the 15 lines of build → run → result): see hopping_diagram.h.
#include <functional>
#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

#include "diagrams/hopping/hopping_diagram.h"
#include "diagrams/hopping/hopping_plans.h"
#include "systems/plants/contact_force_statistics.h"

namespace rome {

/// What the run knows at a monitor call (for HoppingRunParams::observer).
struct HoppingRunState {
  int domain = HoppingDomain::kLanding;           ///< the reference's domain now
  int previous_domain = HoppingDomain::kLanding;  ///< at the previous monitor call
  int touchdowns = 0;                             ///< hops landed so far (this call's touchdown included)
  double liftoff_s = -1, touchdown_s = -1;        ///< the first hop's lift-off and touchdown times [s] (−1: not yet)
};

struct HoppingRunParams {
  double duration_s = 0.0;  ///< [s] simulated time; 0: until stop_after_last_touchdown_s after the last hop
  double stop_after_last_touchdown_s = 2.5;  ///< [s] (ours)
  double rest_check_delay_s = 2.0;           ///< [s] rest is judged this long after the last touchdown (hopping issue)
  double rest_max_speed = 0.05;              ///< [rad/s, m/s] settled: every |q̇| below this (hopping issue)
  /// [-] a hop counts when the COM rises at least this fraction of the planned apex rise H in flight (ours: a foot's
  /// normal force dipping to the lift-off threshold in the crouch is no hop).
  double min_com_rise_fraction = 0.5;
  /// [m] H; NaN: the planners' jump_params.apex_rise (RunHopping's `planners`; required without them).
  double apex_rise_m = std::numeric_limits<double>::quiet_NaN();
  double sample_period_s = 1e-3;     ///< [s] grid of the GRF samples
  double landing_grf_skip_s = 0.02;  ///< [s] the landing NRMSE starts this long after touchdown (the impact)
  bool record_plot_samples = false;  ///< fill the plot-only fields of HoppingSample (costs a mass matrix per sample)
  double progress_period_s = 0.5;    ///< [s] of simulated time between progress lines
  std::ostream* progress = nullptr;  ///< "  t = … s, domain …" lines; null: none
  /// Called at every monitor call after the run's own bookkeeping (e.g. an animation recorder, a test's checks).
  std::function<void(const Context&, const HoppingRunState&)> observer;
  /// Throws std::invalid_argument "HoppingRunParams: <field> = <value>: must be ..." for the first invalid field.
  void Validate() const;
};

/// One GRF sample (every sample_period_s). The plot-only fields are NaN (q empty) unless record_plot_samples.
struct HoppingSample {
  double t = 0, grf = 0, rom_grf = 0, shin_torque = 0, com_z = 0, pitch = 0, pitch_momentum = 0;
  double since_touchdown = -1;  ///< [s] since the current hop's touchdown, or −1
  int domain = 0;
  // Plot-only: mean leg length L(q_knee) [m], COM x [m], pelvis pitch [rad], desired (NaN in Flight); energies [J]
  // relative to the current hop's jump start (robot: ½ vᵀ M v, m g Δz_com, ½ k (q − q_rest)²; ROM: ½ m ẋ², m g Δx,
  // ½ n K(L) s²; NaN without a plan); q for stick figures.
  double leg_length = NAN, leg_length_d = NAN, com_x = NAN, com_x_d = NAN, pitch_d = NAN;
  double leg_length_plan = NAN;  ///< [m] the spring-mass ROM plan's leg length L(t) before feedback (NaN: no plan)
  double kinetic = NAN, potential = NAN, spring_energy = NAN, rom_kinetic = NAN, rom_potential = NAN, rom_spring = NAN;
  Eigen::VectorXd q;
};

struct HoppingRunResult {
  SimulatorStatus status;
  bool success = false, hopped = false, settled = false;
  std::string
      status_kind;     ///< "success" or "failure" by the success rule when the run ended normally; else the status kind
  int touchdowns = 0;  ///< hops landed
  double jump_start_s = -1, liftoff_s = -1, touchdown_s = -1;  ///< the first hop's
  double air_time_s = NAN, foot_clearance_m = 0, com_rise_m = NAN, takeoff_time_error_s = NAN;
  double jump_plans = 0, landing_plans = 0, planner_failures = 0;  ///< HoppingReference's plan_status
  double rest_speed = NAN;  ///< max |q̇| rest_check_delay_s after the last touchdown
  double grf_nrmse_jump = NAN, grf_nrmse_landing = NAN, spring_torque_grf_correlation = NAN;
  double max_pelvis_pitch_change_flight_rad = 0;
  double liftoff_foot_com_offset_x_m = NAN, touchdown_foot_com_offset_x_m = NAN,
         min_pelvis_height_after_touchdown_m = NAN;
  double liftoff_pitch_momentum_Nms = NAN;  ///< H_pitch about the COM at the first lift-off
  Eigen::VectorXd liftoff_state;            ///< [q; v] at the first lift-off, Euler coordinates (empty: none)
  double qp_failures = NAN;                 ///< the controller's qp_failures at the end (NaN: it has no such output)
  double qp_failures_at_first_touchdown = NAN;         ///< ... through the last monitor call before the first touchdown
  double qp_solve_us_median = 0, qp_solve_us_p99 = 0;  ///< from the logged solve_time_s (0: not logged)
  double simulated_s = 0, wall_s = 0, realtime_factor = 0;
  ContactForceStatistics contact;
  long contact_violations_before_first_touchdown = 0;
  SimulatorStatistics integrator;
  std::vector<PlannerRecord> planner_records;
  std::vector<HoppingSample> samples;
};

/// [s] the simulated time RunHopping asks for: params.duration_s, or with 0 the longest the hops can take (settle +
/// hops · 1 s + (hops − 1) max_rest_time_s + stop_after_last_touchdown_s; the run ends earlier at the rest).
double HoppingRunDuration(const HoppingDiagram& d, const HoppingRunParams& params);

/// Runs `sim` (built on d.diagram, initial state set: SetHoppingInitialState) to the end and returns what it measured.
/// `planners` (may be null: no ROM force, NaN GRF metrics) are the ones the diagram was built with. Sets the
/// simulator's monitor. Exceptions from the simulation propagate.
HoppingRunResult RunHopping(const HoppingDiagram& d, Simulator& sim, const HoppingRunParams& params = {},
                            const SpringMassHopPlanners* planners = nullptr);

/// The run's JSON summary (keys as the hopping example writes them, plus the diagram's and the planners' parameters);
/// `scenario_json` (a JSON object's text; empty: none) goes under "scenario".
std::string HoppingSummaryJson(const HoppingDiagram& d, const HoppingRunResult& r,
                               const SpringMassHopPlanners* planners, const std::string& scenario_json = "");

}  // namespace rome
