#pragma once
// WalkingPlan: the composition of the walking paper's sagittal aSLIP and lateral H-LIP orbits into a 3D COM reference,
// footholds and per-foot vertical force references (Sec. III-B "Orbit Composition", spec §4):
//   COM_des(t) = (stance x + x_aSLIP(t), y_HLIP(t), z_aSLIP(t)), with velocities and accelerations from the same ROMs;
//   footholds: x from the aSLIP step length, y = ±W/2 about the walking line (H-LIP P2 with foot separation W);
//   force reference per foot: the aSLIP's vertical GRF G_z of the leg on that foot.
// Interpolation (spec [R]): the aSLIP state is the collocation's cubic Hermite through the nodal states and
// derivatives; its accelerations and forces are linear between nodes (first-order hold of the nodal values, which are
// the ROM dynamics at the nodes). The H-LIP pieces are closed form (SSP ÿ = λ² (y − y_stance), DSP ÿ = 0).
// A plan is a list of segments (one domain each) on a global clock starting at 0.
// Home: systems/planners, beside the planners whose orbits it composes; any biped with an aSLIP + H-LIP plan uses it,
// and centroidal_momentum_compensation.h (a general block) builds on it.
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "solvers/collocation/piecewise_polynomial.h"
#include "systems/planners/aslip_periodic_gait_planner.h"
#include "systems/planners/aslip_transition_planner.h"
#include "systems/planners/footed_hlip_transition_planner.h"
#include "systems/rom/hybrid_linear_inverted_pendulum.h"

namespace rome {

enum class WalkingDomain { kDoubleSupport = 0, kLeftStance = 1, kRightStance = 2 };

/// The references at one instant.
struct WalkingReference {
  Eigen::Vector3d com_position = Eigen::Vector3d::Zero();      ///< [m] world
  Eigen::Vector3d com_velocity = Eigen::Vector3d::Zero();      ///< [m/s]
  Eigen::Vector3d com_acceleration = Eigen::Vector3d::Zero();  ///< [m/s²]
  Eigen::Vector2d left_foothold = Eigen::Vector2d::Zero();     ///< [m] (x, y) of the left ankle at the segment's end
  Eigen::Vector2d right_foothold = Eigen::Vector2d::Zero();    ///< [m] (x, y) of the right ankle at the segment's end
  Eigen::Vector2d normal_force = Eigen::Vector2d::Zero();      ///< [N] F^z_aSLIP of the left and right foot
  WalkingDomain domain = WalkingDomain::kDoubleSupport;
};

struct WalkingPlanSegment {
  double start_time = 0.0;  ///< [s] global
  double duration = 0.0;    ///< [s]
  WalkingDomain domain = WalkingDomain::kDoubleSupport;
  double sagittal_x_offset = 0.0;             ///< [m] world x of the aSLIP plan's origin (its stance foot)
  PiecewisePolynomial sagittal;               ///< [x, z, ẋ, ż] of the aSLIP on [0, duration]
  PiecewisePolynomial sagittal_acceleration;  ///< [ẍ, z̈] (first-order hold)
  PiecewisePolynomial normal_forces;          ///< [F_L, F_R] (first-order hold)
  Eigen::Vector2d lateral_start = Eigen::Vector2d::Zero();  ///< [y (m), ẏ (m/s)] world, at the segment start
  double lateral_pivot_y = 0.0;                             ///< [m] stance foot y (SSP)
  double lambda = 0.0;                                      ///< [1/s] H-LIP λ
  /// Footed H-LIP (transitions): lateral node times (relative to the segment start), node states [y; ẏ] (world) and
  /// the torque driving each interval (u_stance in SSP, u_L + u_R in DSP), held constant; m z0 of the model. Empty:
  /// the point-foot H-LIP from lateral_start.
  Eigen::VectorXd lateral_node_times;
  Eigen::MatrixXd lateral_nodes;
  Eigen::VectorXd lateral_torques;
  /// Per lateral interval: ÿ = a_k (y − c_k) + u_k/(m z0), a_k [1/s²] and c_k [m, world] from the footed H-LIP plan.
  Eigen::VectorXd lateral_stiffness, lateral_pivots;
  double mass_height = 0.0;  ///< [kg m] m z0
  /// [kg m] per lateral interval: m z_k of the footed H-LIP plan (FootedHlipTransitionPlan::interval_height); empty:
  /// mass_height on every interval.
  Eigen::VectorXd lateral_mass_heights;
  Eigen::Vector2d left_foothold = Eigen::Vector2d::Zero(), right_foothold = Eigen::Vector2d::Zero();
};

class WalkingPlan {
 public:
  const std::vector<WalkingPlanSegment>& segments() const { return segments_; }
  double end_time() const { return segments_.empty() ? 0.0 : segments_.back().start_time + segments_.back().duration; }
  /// The references at global time t (clamped to [0, end_time()]). Throws std::logic_error on an empty plan.
  WalkingReference Sample(double t) const;
  /// [s] A time this close below a segment's start belongs to that segment (ours). Control ticks fall at k Δt and
  /// segment starts are sums of durations, so a tick meant to sit on a boundary lands ~1e-15 s on either side of it.
  /// Without it a swing could start one tick late (docs/design-notes.md#walking-segment-boundary).
  static constexpr double kSegmentBoundaryTolerance_s = 1e-10;
  /// Index of the segment that holds global time t: the last one whose start is at most t + kSegmentBoundaryTolerance_s
  /// (0 before the first). Throws std::logic_error on an empty plan.
  size_t SegmentIndexAt(double t) const;

  /// Appends `steps` steps of a periodic gait (each SSP then DSP), the first SSP standing on `first_stance`
  /// (kLeftStance or kRightStance) at world x = stance_x, feet at y = walking_line_y ± W/2. The lateral motion is the
  /// H-LIP P2 orbit with z0 = the gait's mean height, T_SSP and T_DSP from the gait, and foot separation W (spec §2.2).
  /// Throws std::invalid_argument naming the argument for steps < 1, W <= 0, a failed gait, or a non-stance domain.
  /// With begin_with_double_support, the first step contributes only its DSP (e.g. after a transition that ended
  /// at this gait's pre-impact state). With end_with_single_support the last step stops at its touchdown (its DSP is
  /// left out, e.g. for a gait-change transition that starts at this gait's post-impact state).
  void AppendPeriodicSteps(const AslipPeriodicGaitPlanner& planner, const AslipPeriodicGait& gait, int steps,
                           WalkingDomain first_stance, double stance_x, double step_width,
                           bool begin_with_double_support = false, bool end_with_single_support = false,
                           double walking_line_y = 0.0);

  /// Appends a transition (spec §3.2-3.3): the footed-aSLIP NLP's DSP and SSP (world x = x_offset + plan x, legs as
  /// labelled there) and the footed H-LIP QP's lateral plan on the same node grid (its node_times start at 0 at the
  /// DSP start; its single_support flags mark the SSP). Throws std::invalid_argument if either is not solved or the
  /// grids differ. landing_x: world x where the lifting foot lands at the end of the SSP; landing_y: its world y (NaN,
  /// the default: where it lifted, lateral_data's foot y; a change of step width lands elsewhere).
  /// A correction added to the COM reference's x and y on the global clock (e.g. CompensateCentroidalMomentum):
  /// `position` [δx, δy] (m; its time derivative is the velocity correction) and `acceleration` [δẍ, δÿ] (m/s²).
  /// Outside the polynomials' span the correction is 0. Throws std::invalid_argument if either does not have 2 rows.
  void SetComCorrection(PiecewisePolynomial position, PiecewisePolynomial acceleration);
  bool has_com_correction() const { return !correction_position_.empty(); }
  /// The correction [δx, δy] at global time t (0 without one).
  Eigen::Vector2d ComCorrection(double t) const;

  /// Appends a segment built elsewhere (e.g. the walk-to-stand stop, walking_stop_plan.h). Throws
  /// std::invalid_argument naming the field unless it starts at end_time() (within kSegmentBoundaryTolerance_s), lasts
  /// > 0 s and has 4-row sagittal, 2-row sagittal_acceleration and 2-row normal_forces polynomials.
  void AppendSegment(WalkingPlanSegment segment);
  /// Removes the last segment (none: nothing happens), e.g. a gait's last double support that a stop replaces.
  void RemoveLastSegment() {
    if (!segments_.empty()) segments_.pop_back();
  }

  void AppendTransition(const AslipTransitionPlanner& planner, const AslipTransition& transition,
                        const AslipTransitionData& data, double x_offset, const FootedHlipTransitionData& lateral_data,
                        const FootedHlipTransitionPlan& lateral, double mass, double landing_x,
                        double landing_y = std::numeric_limits<double>::quiet_NaN());

 private:
  std::vector<WalkingPlanSegment> segments_;
  PiecewisePolynomial correction_position_, correction_acceleration_;
};

/// The footed H-LIP transition QP's data on the nodes of a solved standing transition (DSP then SSP; the DSP's last
/// node is the SSP's first): node times, each foot's normal force from the transition's ground reactions (clipped at
/// 0), the single-support flags, left stance, feet at ±step_width_m / 2, z0 = the transition's mean height, the node
/// heights (used by the normal-force-pivot model) and a zero initial lateral state. The caller sets the final state and
/// any other option.
FootedHlipTransitionData LateralDataOnTransitionNodes(const AslipTransition& transition,
                                                      const ActuatedSpringLoadedInvertedPendulumParams& aslip,
                                                      const AslipTransitionData& data, int nodes_per_domain,
                                                      double step_width_m);

}  // namespace rome
