#pragma once
// The walking diagram (walking paper, Fig. 1 and Sec. IV-V) on the 12-joint exoskeleton, as the paper's block figure:
//
//   ROM plan (WalkingPlan: periodic aSLIP + H-LIP, transitions; built offline by the caller)
//     → walking_reference (WalkingTrajectorySource: COM [p; ṗ; p̈], footholds, per-foot F^z_aSLIP)
//     → outputs (WalkingOutputReference: Eq. (16) in DSP, Eq. (17) in SSP, swing foot to the planned foothold)
//     → controller (ClfQpController: RES-CLF Eq. (18)-(19), F eliminated Eq. (20)-(22), flat-foot wrench rows
//       Eq. (23), force band Eq. (25) on normal_force_reference, torque limits, 1 kHz, re-solved at every event)
//     ← contact_projection (ContactVelocityProjection, with sensor latency: the delayed state with its velocity
//       projected onto the plant's current contacts) ← plant state
//     → plant (PlantKind, one builder argument: HybridContactPlant, DSP ↔ SSP: ContactModeGraph::WithDoubleSupport;
//       DSP → SSP when the trailing foot's normal force reaches 0, no impact; SSP → DSP when the swing sole reaches the
//       ground, plastic impact; flat feet with 6 constraints each. Or BulletWorldPlant on the same graph: each sole's
//       four corners are spheres on Bullet's ground plane, modes from which feet touch, impacts inside Bullet's step)
//
// Choices beyond the paper (each a named parameter): the trailing foot is released at 1 % of m g (spec §7.5 [R],
// HybridContactPlantParams::planned_liftoff_force_N; at F_n → 0 the held force's |F_t|/F_n is ill-conditioned and
// the run would end as a slip at ~0.1 N); the QP keeps the CoP 10 mm inside the sole (cop_margin_m) and uses half the
// spec's μ = 0.6 (friction_margin 0.5): the plant's forces drift over the 1 ms held sample. For the same hold, the
// force band bounds the force predicted at the hold's end against the plan's F^z one update ahead
// (force_band_lead_periods, ClfQpParams::force_band_at_hold_end), 0.5 N inside its edges (force_band_margin_N), and
// each stance wrench's rows also hold at the hold's end (ClfQpParams::predict_hold_drift, from 3 ms into a mode on).
// The COM reference is the composed ROM plan shifted for the legs' centroidal angular momentum
// (compensate_centroidal_momentum), which the point-mass ROMs do not model. What the diagram achieves, measured, is in
// docs/walking.md (figures) and docs/design-notes.md#walking-status.
//
// Plant modes (WithDoubleSupport): WalkingPlantMode below (BuildWalkingDiagram checks them against the plant's names).
//
// The controller is a parameter of the builder (WalkingControllerFactory; default MakeWalkingClfQpController, the
// CLF-QP above). The factory may return any System, a leaf or a Diagram (e.g. controller → Saturation). Its ports:
//   inputs  state (nq + nv, plant [q; v] on spec.model's base), mode (int, plant mode), desired (54, below),
//           normal_force_reference (2, N: the aSLIP's vertical force on the left, right foot; connected only if the
//           controller has this input);
//   outputs u (nu, N m: the plant's torque input; actuator order of the model).
// desired = [y_d; ẏ_d; ÿ_d], 18 rows each (WalkingOutputReference), one task after another in this order (rows of each
// third; WalkingControllerSpec::layout gives them, WalkingControllerTasks builds the default controller's tasks):
//   com (0-2: x, y, z, m), pelvis_roll (3), pelvis_pitch (4), pelvis_yaw (5: the base's ZYX angles, rad),
//   left_ankle (6-8: m) and left_foot_orientation (9-11: rotation vector, rad), active in right stance,
//   right_ankle (12-14) and right_foot_orientation (15-17), active in left stance. The pelvis angles are
//   MakeBaseAngleTask's: the base coordinates on the Euler base, the pelvis's ZYX angles on the quaternion base.
// It should re-solve at guard events so that the new contact mode's torque acts from the event instant on.
//
// The example below is walking_diagram_test's snippet, line for line (the test checks it), so it keeps its layout.
// clang-format off
// A run from C++ (build → run → result; RunWalking and WalkingRunResult in walking_run.h judge it as the example does):
//   auto model = std::make_shared<const rome::MultibodyModel>(rome::MultibodyModel::LoadFromSidecar("robots/exoskeleton/exoskeleton.rome.json", {.euler_floating_base = true}));
//   rome::StandToWalkParams stand;
//   stand.sole = rome::SoleOf(*model, "left_foot");
//   const rome::WalkingPlan plan = rome::BuildStandToWalkPlan(rome::WalkingGait{}, 8, 1, nullptr, nullptr, stand);
//   rome::WalkingDiagram walking = rome::BuildWalkingDiagram(model, plan);
//   const rome::WalkingRunResult result = rome::RunWalking(walking);
//   std::printf("%s: %d of %d steps, COM RMS error %.4f m\n", result.success ? "walked" : "failed", result.steps_completed,
//               result.steps_planned, result.com_rms_error_m.maxCoeff());
// clang-format on
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "framework/diagram.h"
#include "framework/simulator.h"
#include "systems/controllers/clf_qp_controller.h"
#include "systems/planners/centroidal_momentum_compensation.h"
#include "systems/planners/gait_graph.h"
#include "systems/planners/plan_cache.h"
#include "systems/planners/walking_output_reference.h"
#include "systems/planners/walking_plan.h"
#include "systems/planners/walking_plan_inverse_dynamics.h"
#include "systems/planners/walking_trajectory_source.h"
#include "systems/perturbations/perturbation_params.h"
#include "systems/plants/plant_kind.h"
#include "systems/plants/quaternion_to_euler_state.h"

namespace rome {

/// The plant's modes on ContactModeGraph::WithDoubleSupport("left_foot", "right_foot"), as its int 'mode' output
/// carries them (unscoped so that they compare with that int).
enum WalkingPlantMode : int { kWalkingLeftStance = 0, kWalkingDoubleSupport = 1, kWalkingRightStance = 2 };

struct WalkingDiagramParams {
  /// PlantKind::kHybrid
  HybridContactPlantParams plant = DefaultWalkingPlantParams();
  /// PlantKind::kBullet (defaults: 1 ms step, the controller's 1 kHz; rigid contact, μ from the sidecar). Its
  /// planned_liftoff_force_N, min_time_in_mode_s and planned_liftoff_min_contact_s, when left at their "off" defaults,
  /// are taken from `plant` (the trailing foot is released at 1 % of m g on either plant; a foot is released by that
  /// force only after min_time_in_mode_s of contact).
  BulletWorldPlantParams bullet_plant;
  /// The CLF-QP. Its contact_stabilization is its own, not the plant's: the default predicts the stance feet as held
  /// (α = 0; docs/design-notes.md#walking-controller-contact-model).
  ClfQpParams controller = DefaultWalkingControllerParams();
  SwingFootTrajectoryParams swing;  ///< ankle_height_m is set from the model's sole by the builder
  /// Shift the COM reference so that the legs' centroidal angular momentum is carried by the horizontal ground force,
  /// not by the CoP (CompensateCentroidalMomentum, ours; the paper's point-mass ROMs have none).
  bool compensate_centroidal_momentum = true;
  CentroidalMomentumCompensationParams compensation;
  /// With sensor latency (perturbations.latency_samples > 0) the controller reads the delayed state through a
  /// ContactVelocityProjection onto the plant's current contact mode (ours): the first solves after a touchdown
  /// otherwise see the pre-impact velocities, and the new stance foot bounces. Not added without latency: on a
  /// noisy, undelayed state it moved the first lift-off of gait A to the torsion limit on one seed of six
  /// (docs/design-notes.md#walking-latency-projection).
  bool project_velocity_on_contacts = true;
  double swing_foot_weight = 5.0;  ///< [-] cost weight of the swing ankle's position (ours: land on the foothold)
  /// [-] cost weight of the swing foot's orientation (ours). The light foot's rows set the QP cost's largest curvature
  /// and so the scale of ClfQpParams::u_regularization (docs/design-notes.md#walking-swing-foot-orientation-weight).
  double swing_foot_orientation_weight = 0.1;
  /// [controller update periods] the force band's reference F^z_aSLIP (Eq. (25)) is the plan's at t + this many
  /// controller.update_period_s (ours; 0: the paper's F_ref(t)). The torque solved at t is held until t + T, so the
  /// plant's force at the end of the hold, where the next update and RunWalking sample it, is the one the band at
  /// t + T should hold; 0.5 centres the band on the hold instead. In [0, 2].
  double force_band_lead_periods = 1.0;
  /// What the simulated world does differently from the controller's model (systems/perturbations/): a push on a body
  /// (either plant), link masses/inertias and friction scaled in the plant only, sensor noise and latency on the
  /// state the controller sees, torque noise. The plan and the controller keep the nominal model. Default: none.
  PerturbationParams perturbations;
  /// The plant's base (issue 43; ours, default Euler for now). kQuaternion: the hybrid plant runs on the quaternion
  /// twin of the builder's model (LoadQuaternionTwin: the same URDF and sidecar; a spatial Euler base only), the
  /// controller runs on that twin and reads the plant's state (its pelvis angles by BodyEulerAngleTask), and a
  /// QuaternionToEulerState block ("euler_state") maps the plant's state to the Euler state the run's monitors and logs
  /// read; the plan keeps the builder's model. Needs PlantKind::kHybrid and no perturbations.push.
  PlantBase plant_base = PlantBase::kEuler;
  EulerStateParams euler_state;  ///< the map's refusal near pitch +-90 deg (plant_base = kQuaternion)

  /// Spec §5 [R]: ε = 0.1, p = 1e5, 1 kHz, force band c = 0.1 (Eq. (25)), μ = 0.6 pyramid, yaw moment |τ_z| ≤ 0.02 f_z,
  /// unilateral F_z ≥ 0 (the band must be able to reach 0 at lift-off), re-solved at every guard event. Ours,
  /// differing: yaw |τ_z| ≤ 0.1 m f_z, the torque penalty 3e-8, and the cost's target is the outputs' PD law
  /// (cost_pd_feedback), not the spec's minimum-norm μ = 0 (docs/design-notes.md#walking-controller-defaults).
  static ClfQpParams DefaultWalkingControllerParams();
  /// The hybrid plant's defaults with sole_torsion on (the four-corner soles slip torsionally as a rigid sole's do).
  static HybridContactPlantParams DefaultWalkingPlantParams();

  /// Throws std::invalid_argument "WalkingDiagramParams: FIELD = VALUE is outside RANGE" for the first field out of
  /// its range (the ranges the CLI enforces; BuildWalkingDiagram calls it first).
  void Validate() const;
};

/// One task's rows in each third of the controller's `desired` input (see the top of this file).
struct WalkingTaskRows {
  std::string name;
  int row = 0;   ///< first row in each third
  int size = 0;  ///< rows
};

/// What the diagram hands a controller factory.
struct WalkingControllerSpec {
  std::string name = "controller";  ///< the block's name in the diagram
  /// The plant's base: the builder's model, or its quaternion twin (plant_base = kQuaternion; state = [q (nv + 1); v]).
  std::shared_ptr<const MultibodyModel> model;
  std::vector<ContactSet> mode_contacts;  ///< active contacts of each plant mode (0 left, 1 double, 2 right stance)
  std::vector<ClfOutput> tasks;           ///< WalkingControllerTasks: the default controller's outputs, in layout order
  std::vector<WalkingTaskRows> layout;    ///< each task's rows of `desired` (18 rows per third)
  /// params.controller with the plant's contact stabilisation (HybridContactPlantParams::dynamics) and the force band's
  /// loading floor resolved (2 x the plant's planned lift-off force when negative).
  ClfQpParams params;
};
/// Builds the controller block: any System (leaf or diagram) with the controller ports of the top of this file.
using WalkingControllerFactory = std::function<std::unique_ptr<System>(const WalkingControllerSpec&)>;
/// The default controller: ClfQpController(spec.name, spec.model, spec.mode_contacts, spec.tasks, spec.params).
std::unique_ptr<System> MakeWalkingClfQpController(const WalkingControllerSpec& spec);
/// The CLF-QP's tasks on `model` (the order of the top of this file): COM, pelvis roll/pitch/yaw (Eq. (16)), each
/// swing ankle's position and orientation in the other foot's stance (Eq. (17)), weighted by params' foot weights.
std::vector<ClfOutput> WalkingControllerTasks(const MultibodyModel& model, const WalkingDiagramParams& params = {});
/// Each task's rows of `desired` (offsets accumulate the tasks' sizes).
std::vector<WalkingTaskRows> WalkingDesiredLayout(const std::vector<ClfOutput>& tasks);

struct WalkingDiagram {
  std::unique_ptr<Diagram> diagram;
  std::shared_ptr<const MultibodyModel> model;
  const ContactPlant* plant = nullptr;
  WalkingTrajectorySource* reference = nullptr;
  WalkingOutputReference* outputs = nullptr;
  const System* controller = nullptr;  ///< the factory's block (a leaf or a sub-diagram)
  /// The ClfQpController among the diagram's leaves (the default controller, or one inside a factory's sub-diagram;
  /// null when there is none): RunWalking reads its diagnostics (δ, solve time, QP failures).
  const ClfQpController* clf_qp = nullptr;
  CentroidalMomentumCompensationReport compensation;  ///< zeros when params.compensate_centroidal_momentum is off
  WalkingPlan plan;                                   ///< the plan the diagram runs (with the compensation, if on)
  PerturbationBlocks perturbation_blocks;             ///< the perturbation blocks that are on (params.perturbations)
  /// The plant's physics in Euler coordinates (the plant's model on the Euler base; on the quaternion base the Euler
  /// model with the plant's mass and friction scaling): what RunWalking measures the plant's state with.
  std::shared_ptr<const MultibodyModel> plant_euler_model;
  /// The map from the plant's quaternion state to the Euler state (null on the Euler base).
  const QuaternionToEulerState* euler_state = nullptr;
};

/// The plant's state [q; v] in Euler coordinates: the plant's own, or the euler_state block's map of it.
const Eigen::VectorXd& WalkingPlantEulerState(const WalkingDiagram& d, const Context& context);
/// Sets the plant's state from an Euler state [q; v] (mapped by EulerStateToQuaternion on the quaternion base).
void SetWalkingPlantState(const WalkingDiagram& d, Context& context, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                          const std::string& mode);

/// Builds the diagram above on the plant `plant` (params.plant or params.bullet_plant) with the controller `controller`
/// makes (empty: MakeWalkingClfQpController). The model must have flat contacts "left_foot" and "right_foot" on links
/// of those names. Calls params.Validate() first.
WalkingDiagram BuildWalkingDiagram(std::shared_ptr<const MultibodyModel> model, const WalkingPlan& plan,
                                   const WalkingDiagramParams& params = {}, PlantKind plant = PlantKind::kHybrid,
                                   const WalkingControllerFactory& controller = {});

/// The simulator settings of the walking runs (example, tests, benchmark): ExplicitRestartingSimulatorConfig at rtol
/// 1e-5, atol 1e-7, as hopping (ours; docs/design-notes.md#walking-simulator-config).
SimulatorConfig WalkingSimulatorConfig();

/// One gait of the issue's --gait flags: step length l, T_SSP, T_DSP, step width W.
struct WalkingGait {
  double step_length_m = 0.30, ssp_duration_s = 0.40, dsp_duration_s = 0.10,
         step_width_m = 0.25;  ///< gait A (spec §3.1)
  /// The range the ROM planners are built and tested for (the walking issue's gait range).
  static constexpr double kMin[4] = {0.2, 0.35, 0.08, 0.2}, kMax[4] = {0.45, 0.5, 0.15, 0.3};
  /// Throws std::invalid_argument "WHO: FIELD = VALUE UNIT is outside [MIN, MAX] UNIT" for the first field out of the
  /// range above. The plan builders call it first.
  void Validate(const std::string& who = "WalkingGait") const;
};

/// The sole of a flat foot about its ankle (the foot frame's origin), from the robot's contact corners [m].
struct SoleGeometry {
  double heel_m = 0.07, toe_m = 0.18;    ///< L_h, L_t of Eq. (10): ankle to heel and to toe along the foot's x
  double left_m = 0.05, right_m = 0.05;  ///< W1, W2 of Eq. (14): ankle to the sole's left and right edges
};
/// The sole of flat contact `contact` of `model` (its corner points in the foot frame). Throws std::invalid_argument
/// naming the robot and contact if the contact is not flat or the ankle is not over the sole.
SoleGeometry SoleOf(const MultibodyModel& model, const std::string& contact);

struct WalkingNlpReport;
/// Choices of the stand-to-walk plan beyond the gait.
struct StandToWalkParams {
  /// [m] the aSLIP height range of the periodic and transition NLPs (ours; spec §1.1/§3.1 [R]: range 0.85-0.95 m):
  /// lower keeps the stance knee under its torque limit, higher straightens the trailing knee
  /// (docs/design-notes.md#walking-standing-height).
  double height_min_m = 0.84, height_max_m = 0.90;
  /// [m] COM (ROM mass) height standing, in [height_min_m, 1] (ours; spec [R] about 0.9 m). Above height_max_m the
  /// standing transition's NLP may start above the range and lowers the COM into it, and the walk-to-stand stop raises
  /// it in its last double support, feet side by side: 0.91 m keeps the standing ankles 0.035 rad inside the URDF's
  /// dorsiflexion limit, which 0.86 m passes by 0.127 rad (docs/design-notes.md#walking-standing-above-the-range).
  double standing_height_m = 0.91;
  /// [m] the lifting (right) foot starts this far behind the stance (left) foot (spec [R]: 0, feet side by side, the
  /// default). Side by side, the standing transition's single step must reach the next gait's pre-impact state over one
  /// sole: a LIP from rest with its CoP on the heel (L_h behind the ankle) reaches at most ω (x_f + L_h) at x_f, so
  /// gait A's state is out of reach and the plan goes through the start gait (start_gait_steps;
  /// docs/design-notes.md#walking-start-gait). StepStance() is the earlier start from a 0.4 m step
  /// stance, whose double support pushes off the rear heel straight into the gait.
  double stance_stagger_m = 0.0;
  /// [m] the footed ROMs' ZMP bounds are the sole's, this much inside (ours): sagittal (Eq. (10) L_h, L_t) and
  /// lateral (Eq. (14) W1, W2). The whole-body controller keeps its own CoP margin (ClfQpParams
  /// contact.cop_margin_m, 10 mm) and needs room for the legs' angular momentum, which the point-mass ROM does not see
  /// (docs/design-notes.md#walking-sagittal-cop-margin).
  double sagittal_cop_margin_m = 0.05;
  double lateral_cop_margin_m = 0.02;
  SoleGeometry sole;  ///< the robot's sole (set it with SoleOf(model, "left_foot"))
  /// With it (StepStance(); off by default) the standing transition's SSP is point-foot (u = 0, CoP at the ankle, as in
  /// the periodic gait); it always lasts at least the T_SSP of the gait it goes into (ours; the spec's [R] lets T_SSP
  /// go down to 0.3 s with ankle torque). Off: the robot's swing leg needs the stance CoP ahead of the ROM's, and side
  /// by side the transition into the start gait needs the ankle
  /// (docs/design-notes.md#walking-point-foot-transition-ssp).
  bool point_foot_transition_ssp = false;
  /// [-] the transition's stance leg carries at least this fraction of m g through the DSP (ours; without it the plan
  /// unloads the front foot mid-DSP and the plant's lift-off guard fires there).
  double min_dsp_stance_force_fraction = 0.1;
  /// [s] lower bound of the transition's SSP duration (ours; 0: the gait's T_SSP). The first swing carries the foot
  /// from stance_stagger_m behind to a step ahead; a longer SSP lowers its peak acceleration (minimum jerk: 5.77 d/T²)
  /// and so the swing leg's reaction on the stance foot.
  double transition_min_ssp_duration_s = 0.0;
  /// The lateral transition QP moves the mass on the feet's normal forces (FootedHlipTransitionParams::
  /// normal_force_pivots, ours) rather than the paper's ÿ = u/(m z0) in DSP, whose lateral CoP the uneven push-off
  /// cannot realise (docs/design-notes.md#walking-lateral-normal-force-pivots).
  bool lateral_normal_force_pivots = true;
  /// The footed-aSLIP transition NLP carries the lateral motion too (AslipTransitionParams::lateral, ours), so that its
  /// vertical force split is one the lateral motion can realise; the footed H-LIP QP then plans y on those forces
  /// (without it, that QP with normal_force_pivots is infeasible for the 0.3 and 0.4 m step stances).
  bool lateral_in_transition_nlp = true;
  /// [-] the gait-change (A → B) transition keeps each leg's vertical GRF ≤ this fraction of m g
  /// (AslipTransitionParams::max_vertical_force_fraction, ours; 0: no bound): unbounded, the stance knee saturates
  /// (docs/design-notes.md#walking-gait-change-force-bound).
  double gait_change_max_force_fraction = 1.6;
  /// [-] a gait-change transition that change_check refuses is planned again with this tighter bound before the
  /// change goes through the gait graph (ours; 0: no retry; docs/design-notes.md#walking-change-check).
  double gait_change_retry_max_force_fraction = 1.5;
  /// [-] a periodic gait whose aSLIP plan asks more than this fraction of m g on one leg is planned again with that
  /// bound (AslipPeriodicGaitParams::max_vertical_force_fraction, ours; 0: never): above it the stance knee saturates
  /// (docs/design-notes.md#walking-periodic-force-bound).
  double periodic_max_force_fraction = 1.5;
  /// Lead-in (ours): BuildStandToWalkPlan starts with lead_in_steps steps of the lead-in gait (lead_in_step_length_m,
  /// lead_in_ssp_duration_s, lead_in_dsp_duration_s, the requested W; the spec's gait A timing) and changes gait as
  /// BuildGaitChangePlan does when the requested gait is faster (its T_SSP or T_DSP is shorter than the lead-in's), or
  /// when the standing transition into it has no plan (0 steps: no lead-in, the error is thrown;
  /// docs/design-notes.md#walking-lead-in).
  int lead_in_steps = 6;
  double lead_in_step_length_m = 0.30;
  double lead_in_ssp_duration_s = 0.40;  ///< [s]
  double lead_in_dsp_duration_s = 0.10;  ///< [s]
  /// Start gait (ours; 0 steps: none, as StepStance()): the standing transition goes into this short, slow gait (at
  /// the requested W), which walks start_gait_steps steps and then changes (as BuildGaitChangePlan does) into the gait,
  /// or into the lead-in first when the gait is faster than the lead-in (if that has no plan, directly). It makes the
  /// spec's [R] standing start with the feet side by side plannable: gait A's pre-impact state is beyond what one step
  /// from rest reaches over one sole (docs/design-notes.md#walking-start-gait). 6 steps, as the lead-in, so that the
  /// convergence check from step 5 after each transition applies to the start gait too.
  int start_gait_steps = 6;
  double start_gait_step_length_m = 0.20;   ///< [m]
  double start_gait_ssp_duration_s = 0.50;  ///< [s]
  double start_gait_dsp_duration_s = 0.15;  ///< [s]
  /// [m] the footed-aSLIP CoP margin (Eq. (10)) of the standing transition and of the start gait's change into the next
  /// gait; negative: sagittal_cop_margin_m (ours). The
  /// 5 cm default margin is for the step stance's push-off from the rear heel (the legs' angular momentum as the knees
  /// extend); side by side the legs barely move in the double support.
  double standing_sagittal_cop_margin_m = 0.02;
  /// Called with the direct standing plan before BuildStandToWalkPlan returns it; a std::runtime_error from it sends
  /// the plan through the lead-in, as a failed NLP does (empty: no check). The plan builder does not know the robot:
  /// WalkingPoseCheck(model, params) replays the plan's poses as BuildWalkingDiagram's compensation will
  /// (docs/design-notes.md#walking-plan-check).
  std::function<void(const WalkingPlan&)> plan_check;
  /// Called after every transition NLP the plan builders solve or load (standing, changes, chain links; failures
  /// too) with its wall time, iterations and largest constraint violation (empty: none), e.g. to time them.
  std::function<void(const WalkingNlpReport&)> on_transition_nlp;
  /// Called after every gait-change transition (A → B, a chain link, the start gait's change) is appended, with the
  /// plan and the transition's start and end (its double and single support); a std::runtime_error from it refuses
  /// the transition as beyond the robot (its what(): the reason): the change is planned again with
  /// gait_change_retry_max_force_fraction, then (chain_gait_changes) through the gait graph, as when its NLP has no
  /// plan; when neither plans (nor, from standing, a lead-in), the builder returns the plan up to the first refused
  /// change (the direct one, else the first chain's link into the gait), for the check before simulating to refuse
  /// (empty: no check). The plan builder does not know the robot: WalkingChangeFeasibilityCheck
  /// (walking_robot_check.h) checks the torques as the walking example's feasibility check does.
  std::function<void(const WalkingPlan&, double from_s, double to_s)> change_check;
  /// A → B with no direct transition plan (BuildGaitChangePlan; and every start from standing: the start gait's or the
  /// lead-in's change into the gait, BuildStandToWalkPlan included): chain through intermediate gaits of the gait
  /// graph (GaitGraph, ours; false: the direct failure is thrown). Each intermediate gait walks chain_steps steps.
  bool chain_gait_changes = true;
  int chain_steps = 4;
  /// [-] A gait-change transition whose plan unloads the lifting foot below this fraction of m g and loads it again
  /// within the double support (AslipTransition::LiftingLegReloadTime) has no plan (ours; 0: off; 2 %: twice the
  /// plant's 1 % release force; docs/design-notes.md#walking-reload-floor).
  double reload_floor_fraction = 0.02;
  GaitGraphParams gait_graph;

  /// Ranges of the lead-in and start gaits (L, T_SSP, T_DSP; ours: they may lie outside the walking issue's range).
  static constexpr double kSideGaitMin[3] = {0.1, 0.35, 0.08}, kSideGaitMax[3] = {0.45, 0.6, 0.3};
  /// Throws std::invalid_argument "WHO: FIELD = VALUE is outside RANGE" for the first field out of its range (the
  /// CLI's ranges; the plan builders call it first).
  void Validate(const std::string& who = "StandToWalkParams") const;

  /// The earlier standing start from a step stance (ours): the right foot `stagger_m` behind the left, no start gait,
  /// the standing transition straight into the gait with a point-foot SSP and the 5 cm CoP margin of the push-off
  /// from the rear heel, standing at 0.86 m (the legs 0.4 m apart do not reach 0.91 m). With gait A, 0.35 and 0.40 m
  /// walk (docs/design-notes.md#walking-step-stance).
  static StandToWalkParams StepStance(double stagger_m = 0.40) {
    StandToWalkParams p;
    p.standing_height_m = 0.86;
    p.stance_stagger_m = stagger_m;
    p.start_gait_steps = 0;
    p.point_foot_transition_ssp = true;
    p.standing_sagittal_cop_margin_m = -1.0;
    return p;
  }
};

/// A StandToWalkParams::plan_check for `model`: the angular-momentum compensation of BuildWalkingDiagram (with
/// `params`' swing and compensation settings) on a copy of the plan; it throws std::runtime_error when a replay pose
/// does not exist. Nothing when params.compensate_centroidal_momentum is off.
std::function<void(const WalkingPlan&)> WalkingPoseCheck(std::shared_ptr<const MultibodyModel> model,
                                                         const WalkingDiagramParams& params);

/// The inverse dynamics of `plan`'s single supports on `model` (CalcWalkingPlanTorques, with `params`' swing settings):
/// the joint torques the plan's kinematic replay needs, against the robot's torque limits. Pass the diagram's plan
/// (WalkingDiagram::plan, with its COM correction) to check what the controller will track. Throws as
/// CalcWalkingPlanTorques. `end_time_s`: the run's end, when the plan goes on past it.
WalkingPlanTorqueReport CheckWalkingPlanTorques(const MultibodyModel& model, const WalkingPlan& plan,
                                                const WalkingDiagramParams& params = {},
                                                double end_time_s = std::numeric_limits<double>::infinity());

/// The ROM plan of the stand-to-walk scenario (spec §0): the periodic aSLIP gait (Eq. (4)-(5), seed `seed`), the
/// standing → gait transition (footed aSLIP Eq. (9)-(10), the right foot lifts; footed H-LIP QP Eq. (11)-(15) onto the
/// H-LIP P2 orbit), then `steps` periodic steps, composed into a WalkingPlan. NLPs use `cache` if given. If the gait
/// is faster than the lead-in gait of StandToWalkParams, or its standing transition has no plan (directly or, with
/// chain_gait_changes, through the gait graph: report->start_chain), the plan starts with that lead-in (reported in
/// `report`).
/// Throws std::runtime_error naming the problem that failed, std::invalid_argument for a bad parameter.
/// One ROM problem's solve: wall time, Ipopt iterations, largest constraint violation (0 when not solved here).
struct WalkingNlpReport {
  double solve_s = 0;
  int iterations = 0;
  double violation = 0;
  double cpu_s = 0;  ///< [s] the solving thread's CPU time (transition NLPs; 0 otherwise)
};
/// A solved transition on its node grid (DSP nodes, then the SSP's; the shared node once), for plots (Fig. 3 S2, L2):
/// the footed aSLIP's sagittal plan and ankle pitch torques with their Eq. (10) ZMP bounds, and the footed H-LIP's
/// lateral plan and ankle roll torques with their Eq. (14) bounds. Empty when the transition was not solved.
struct WalkingTransitionNodes {
  Eigen::VectorXd t;                 ///< [s] plan (global) time
  std::vector<bool> single_support;  ///< per node: in the SSP (the DSP's last node is false)
  Eigen::VectorXd x, z;              ///< [m] world COM x and height
  Eigen::MatrixXd normal_force;      ///< [N] 2 × N: vertical GRF of the left, right foot (G_z)
  Eigen::MatrixXd pitch_torque;      ///< [N m] 2 × N: ankle pitch torque u_y of the left, right foot (Eq. (9)-(10))
  double heel_m = 0, toe_m = 0;      ///< Eq. (10): −L_h G_z ≤ u_y ≤ L_t G_z
  Eigen::VectorXd y, ydot;           ///< [m], [m/s] world lateral COM (footed H-LIP QP)
  Eigen::MatrixXd roll_torque;       ///< [N m] 2 × N: ankle roll torque u_x of the left, right foot (Eq. (15))
  double left_m = 0, right_m = 0;    ///< Eq. (14): −W1 F ≤ u_x ≤ W2 F
};
/// A gait-change transition planned and then refused by StandToWalkParams::change_check.
struct WalkingChangeRefusal {
  WalkingGait from, to;
  double max_force_fraction = 0;  ///< [-] the transition NLP's vertical force bound (m g per leg; 0: none)
  std::string problem;            ///< the check's reason
};
struct WalkingPlanReport {
  WalkingNlpReport periodic, transition;      ///< gait A's periodic aSLIP, the standing transition
  WalkingNlpReport periodic_b, transition_b;  ///< gait-change only: gait B's periodic aSLIP, the A → B transition
  WalkingTransitionNodes transition_nodes, transition_b_nodes;  ///< the two transitions' plans on their nodes
  /// BuildStandToWalkPlan only: the plan starts with a lead-in (StandToWalkParams::lead_in_steps) of `lead_in_gait`
  /// (with lead_in false and lead_in_reason set, a lead-in was tried, had no plan, and the plan goes directly from the
  /// start gait);
  /// the *_b entries are then the requested gait and the lead-in → gait transition. lead_in_reason: why (the gait is
  /// faster than the lead-in, or the direct standing transition's error).
  bool lead_in = false;
  WalkingGait lead_in_gait;
  std::string lead_in_reason;
  /// StandToWalkParams::start_gait_steps > 0: the standing transition goes into `start_gait` (then `transition` is
  /// standing → start gait), whose periodic aSLIP and change into the (lead-in or requested) gait are these.
  bool start_gait_used = false;
  WalkingGait start_gait;
  WalkingNlpReport periodic_start, transition_start;
  WalkingTransitionNodes start_change_nodes;
  /// BuildGaitChangePlan / BuildGaitSequencePlan: the gaits walked from gait A on, in order, with any chain's
  /// intermediate gaits (A, B alone: the direct transition; BuildStandToWalkPlan: the gait alone, or the lead-in, any
  /// chain and the gait), and the chain searches' wall time and transitions tried / failed (0 when every direct
  /// transition planned).
  std::vector<WalkingGait> chain;
  /// With the start gait and chaining on (BuildStandToWalkPlan, BuildGaitChangePlan, BuildGaitSequencePlan): the gaits
  /// from the start gait to gait A (2 entries: the direct change; more: its chain through the gait graph, counted in
  /// the figures below).
  std::vector<WalkingGait> start_chain;
  double chain_planning_s = 0;
  int chain_transitions_tried = 0, chain_transitions_failed = 0;
  /// Every transition StandToWalkParams::change_check refused, in the order planned (empty: none).
  std::vector<WalkingChangeRefusal> refused_changes;
  /// Non-empty when the builder returned a plan change_check refused (every way tried was refused; see
  /// StandToWalkParams::change_check): the refusal's reason. The walking example refuses such a plan (exit 1) also
  /// when its check before simulating, on the whole plan, finds it within the limits.
  std::string refused_plan_kept;
};
WalkingPlan BuildStandToWalkPlan(const WalkingGait& gait, int steps, std::uint32_t seed, const PlanCache* cache,
                                 WalkingPlanReport* report = nullptr, const StandToWalkParams& params = {});

/// The gait-change scenario (spec §4 (ii)): standing → gait A as BuildStandToWalkPlan with `steps` steps of A, the
/// transition footed-aSLIP NLP from A's post-impact state (its last touchdown) to B's pre-impact state (the foot
/// behind lifts, as in A) with its footed H-LIP QP, then `steps` steps of B. A change of step width W is the lateral
/// footed H-LIP transition: the QP ends on B's P2 pre-impact state about the landed foot, the lifting foot lands W_B
/// beside it and B walks about the walking line between them. Throws std::invalid_argument for a bad parameter,
/// std::runtime_error naming the problem that failed.
/// steps_b: gait B's steps (default: `steps`).
WalkingPlan BuildGaitChangePlan(const WalkingGait& gait_a, const WalkingGait& gait_b, int steps, std::uint32_t seed,
                                const PlanCache* cache, WalkingPlanReport* report = nullptr,
                                const StandToWalkParams& params = {}, int steps_b = -1);

/// A sequence of gaits (2 to 20, each in the WalkingGait range): standing → gaits[0] as BuildGaitChangePlan's gait A,
/// then each change into the next gait as its A → B (directly, or through the gait graph), `steps` steps of each gait
/// and steps_last (default `steps`) of the last. report->chain lists every gait walked after the standing start (the
/// chains' intermediate gaits included); its *_b entries are the last change's. Throws as BuildGaitChangePlan.
WalkingPlan BuildGaitSequencePlan(const std::vector<WalkingGait>& gaits, int steps, std::uint32_t seed,
                                  const PlanCache* cache, WalkingPlanReport* report = nullptr,
                                  const StandToWalkParams& params = {}, int steps_last = -1);

/// `steps` + 1 periodic steps of `gait` alone (no transition), starting with the double support after a right-foot
/// touchdown (left foot behind at x = 0): a run started on the orbit (WalkingStandingPose and WalkingInitialVelocity at
/// a time inside that double support) tests the controller on the periodic gait alone. Throws as BuildStandToWalkPlan.
WalkingPlan BuildPeriodicWalkingPlan(const WalkingGait& gait, int steps, std::uint32_t seed, const PlanCache* cache,
                                     const StandToWalkParams& params = {});
/// Joint and base velocities with both feet still, the pelvis not rotating and the COM at the plan's velocity at t
/// (least squares on the 15 coordinates other than the base angles).
Eigen::VectorXd WalkingInitialVelocity(const MultibodyModel& model, const Eigen::VectorXd& q, const WalkingPlan& plan,
                                       double t = 0.0);

/// A standing configuration for the plan at time t (default its start): pelvis level with zero yaw, both feet flat on
/// the ground with the ankles at the plan's footholds at t, and the COM at the plan's COM (Newton on the 15 remaining
/// coordinates, from the model's nominal pose). Throws std::runtime_error if it does not converge to 1e-10.
Eigen::VectorXd WalkingStandingPose(const MultibodyModel& model, const WalkingPlan& plan, double t = 0.0);

}  // namespace rome
