#pragma once
// SteppingStonesSupervisor: the step sequencer of Algorithm 1 (stepping-stones paper). It knows which stone the
// stance foot is on, measures the robot relative to the stance foot for the planner, and at every impact updates
// α_0 from the post-impact state and solves the pre-impact posture NLP, Eq. (21), for the next stone (lines 8-10).
//
// inputs:  state (2 nv)               plant [q; v]
//          mode (int, typed)          plant contact mode (AlternatingSingleSupport graph: 0 left stance, 1 right
//                                     stance, 2 flight)
//          u_des (1)                  planner's desired pre-impact vertical COM velocity [m/s] (for the step log)
//          L_des (1)                  planner's desired post-impact momentum [m²/s] (for the step log)
// outputs: com_state (4)              [p^x, p^z (m), ṗ^x, ṗ^z (m/s)] COM relative to the stance foot
//          angular_momentum (1)       L_y [m²/s], mass-normalised, about the stance pivot a: r_z ṗ^x − r_x ṗ^z +
//          k_G,y/m,
//                                     r = p_com − a; a = the point foot, or for a line/flat foot the origin of the foot
//                                     link (its inboard joint: planar Cassie's toe joint, the passive stance ankle
//                                     whose torque is 0; hopping spec C.12), not the sole midpoint
//          com_vertical_state (2)     [p^z (m), ṗ^z (m/s)] relative to the stance foot
//          step (2)                   [l_des, h_des] (m): next stone centre minus the stance foot
//          pre_impact_com_height (1)  p_comf^{z,d} (m) from the posture NLP, relative to the stance foot
//          step_parameters (typed)    StepOutputParameters of the current step (output_trajectories.h)
//          stance_foot (2)            world (x, z) of the stance foot (m): its contact frame origin (the point foot,
//                                     the sole midpoint of a line foot); footholds and stones are checked there
//          stone (1)                  index of the stone under the stance foot
// Every output is a pure function of the committed step (discrete state) and, for the COM outputs, the plant state.
// Initialize() (or SetSteppingStonesInitialState for the stepping-stones diagram) must set up the first step before
// the run: until then every output and the periodic update throw a one-line error that names the call to make.
// discrete state: the committed step (see the kIndex constants in the .cc).
// Event update "impact" (at every guard event of the diagram, right after the plant's reset): when the plant's
// stance foot differs from the committed one, an impact happened: the new stance foot, the stone it landed on, α_0
// and the pre-impact posture for the next stone (NLP, Eq. (21)) are committed and a StepRecord is appended
// (Algorithm 1, lines 8-10). Blocks added after the supervisor (MPC, outputs, controller) see the new step in their
// own event updates at the same instant. A touchdown from flight onto the committed stance foot is no new step.
// Periodic update every update_period_s: the step log's last u_des, L_des and ṗ^z, and the fall check.
// The run ends with ReachedTermination (success) after max_steps steps or when the robot stands on the last stone,
// and with Failed ("robot fell") when the COM is less than min_com_height_m above the stance foot.
// Posture NLP failure: the optimiser's own fallback (previous solution, else nominal pose) is used, the failure
// is counted and reported in the step log; the walk goes on.

#include <memory>
#include <string>
#include <vector>

#include "framework/system.h"
#include "systems/multibody/multibody_model.h"
#include "systems/planners/output_trajectories.h"
#include "systems/plants/terrain.h"
#include "systems/posture/pre_impact_posture_optimizer.h"

namespace rome {

struct SteppingStonesSupervisorParams {
  double update_period_s = 1e-3;  ///< [s] same rate as the controller (paper: 1 kHz)
  double impact_fraction = 0.6;   ///< ε [-]: desired pre-impact COM position ε l_des (paper: 0.6)
  int max_steps = 30;             ///< the run ends after this many steps
  /// [m] the run ends ("robot fell") when the COM is less than this above the stance foot (ours). The plant's own
  /// fall guard uses an absolute base height, which cannot tell a fall from walking down a flight of stairs.
  double min_com_height_m = 0.45;
  double nominal_step_duration_s = 0.4;  ///< [s] T_s written into the step parameters (time-based phase only)
  /// [m] COM height above the lower of the stance foot and the next stone that the pre-impact posture aims for (the
  /// request's com_height_m, weighted by posture.com_height_weight), and at which the robot starts. Ours: the paper
  /// gives none. Eq. (21) alone leaves the height to the posture term, which picks AMBER's nearly straight nominal legs
  /// (COM 0.90 m, 7 mm of leg extension left), so the COM cannot rise after an impact without the stance knee reaching
  /// its singular straight position. 0.80 m keeps the knees bent 0.6-0.9 rad over a 0.4 m step.
  double walking_com_height_m = 0.80;
  /// [m] largest distance from either foot to the pre-impact COM (ours): on a long step the request's height drops
  /// below walking_com_height_m (+ min(h, 0)) until the COM, ε l ahead of the stance foot and (1 − ε) l behind the
  /// landing foot, is within this distance of both, so the legs do not arrive nearly straight. 0.904 m ≥
  /// sqrt(0.80² + (0.6 · 0.7)²) = 0.9035 m: on level ground the cap binds only on steps longer than the paper's
  /// random courses' 0.7 m (flat 0.8 m: 0.766 m). At 0.80 m AMBER slips on flat 0.8 m steps from E* = 0.8 (1.1 m/s);
  /// capped it walks them at 1.26-1.83 m/s (docs/design-notes.md#stepping-stones-long-step-height). Infinity: no cap.
  double max_com_foot_distance_m = 0.904;
  PreImpactPostureParams posture = DefaultPostureParams();  ///< Eq. (21)
  static PreImpactPostureParams DefaultPostureParams() {
    PreImpactPostureParams p;
    // w_z [1/m²] (ours): as strong as w_x = 1 on the pre-impact COM position ε l; a weak w_z leaves a long step down
    // on a straight leg the swing foot cannot reach (docs/design-notes.md#stepping-stones-posture-height-weight).
    p.com_height_weight = 1.0;
    return p;
  }
};

/// The pre-impact COM height above the stance foot that the posture NLP aims for on a step (l, h) (the supervisor's
/// request): walking_com_height_m + min(h, 0) (stepping down, the landing leg must not arrive straight), lowered on
/// long steps until the COM is within max_com_foot_distance_m of both feet. Throws std::invalid_argument naming the
/// parameter when the cap leaves no height for the step.
double PreImpactComHeightRequest(const SteppingStonesSupervisorParams& params, double l, double h);

/// One completed step, for summaries.
struct StepRecord {
  double start_time_s = 0, duration_s = 0;
  double step_length_m = 0, step_height_m = 0;  ///< l, h planned for the step
  double pre_impact_com_vz_mps = 0;             ///< ṗ^z⁻ measured just before touchdown
  double u_des_mps = 0;                         ///< planner's u_des just before touchdown
  double post_impact_momentum = 0;              ///< L_y⁺ about the new stance foot [m²/s]
  double L_des = 0;                             ///< planner's L_des for the step [m²/s]
  double foothold_error_m = 0;                  ///< |touchdown x − stone centre|
  int stone = -1;                               ///< stone the swing foot landed on (nearest to the foot)
  int planned_stone = -1;                       ///< stone it was aimed at
  bool posture_ok = true;
};

class SteppingStonesSupervisor final : public LeafSystem {
 public:
  SteppingStonesSupervisor(std::string name, std::shared_ptr<const MultibodyModel> model, Terrain terrain,
                           SteppingStonesSupervisorParams params = {});

  const SteppingStonesSupervisorParams& params() const { return params_; }
  const std::vector<StepRecord>& steps(const LeafContext& context) const;
  int posture_failures(const LeafContext& context) const;
  // The committed step state of `context` (what the last update decided).
  int stance_mode(const LeafContext& context) const;  ///< 0 left stance, 1 right stance
  int stone(const LeafContext& context) const;        ///< stone under the stance foot
  int num_steps(const LeafContext& context) const;    ///< impacts so far
  Eigen::Vector2d stance_foot(const LeafContext& context) const;
  StepOutputParameters step_parameters(const LeafContext& context) const;
  double pre_impact_com_height(const LeafContext& context) const;
  /// Sets up the first step from the plant state in `context`'s inputs (call after fixing the initial state).
  void Initialize(LeafContext& context, const Eigen::VectorXd& plant_state, int plant_mode) const;

  struct Scratch;

 private:
  std::any AllocateScratch() const override;
  EventStatus Update(const LeafContext& context, Eigen::VectorXd* next) const;
  EventStatus ImpactUpdate(const LeafContext& context, Eigen::VectorXd* next) const;
  /// The committed step state; throws, naming the call to make, if Initialize() was not called on `context`.
  const Eigen::VectorXd& Committed(const LeafContext& context) const;
  static StepOutputParameters step_parameters(const Eigen::VectorXd& xd);
  /// Impact bookkeeping on the step state xd (new stance foot, stone, α_0, posture); fills `rec` if given.
  void ApplyImpact(const LeafContext& context, const Eigen::VectorXd& x, int mode, Eigen::VectorXd* xd,
                   StepRecord* rec) const;
  void PlanStep(const LeafContext& context, const Eigen::VectorXd& x, int mode, Eigen::VectorXd* xd, double time) const;
  void ComRelative(const LeafContext& context, const Eigen::VectorXd& xd, const Eigen::VectorXd& x,
                   Eigen::Vector4d* com, double* L) const;
  /// ComRelative at the context's committed step and plant state: [x, z, ẋ, ż], and L if `L` is given.
  Eigen::Vector4d ComState(const LeafContext& context, double* L = nullptr) const;

  std::shared_ptr<const MultibodyModel> model_;
  Terrain terrain_;
  SteppingStonesSupervisorParams params_;
  /// World position of the foothold of foot `side` (0 left, 1 right): its contact frame origin.
  Eigen::Vector3d FootPosition(MultibodyWorkspace& ws, const Eigen::Ref<const Eigen::VectorXd>& q, int side) const;

  int contact_[2];                 // left, right contact indices
  Eigen::Vector3d foot_point_[2];  // foothold (contact frame origin), foot link frame
  bool pivot_is_foot_[2] = {true, true};
  Eigen::Vector3d
      pivot_point_[2];  // pivot of L_y (point foot, or the ankle joint of a line/flat foot), foot link frame
  int torso_pitch_index_ = 2;
};

}  // namespace rome
