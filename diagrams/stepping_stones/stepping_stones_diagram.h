#pragma once
// The stepping-stones diagram (stepping-stones paper, Algorithm 1) on a planar point-foot biped:
//
//   plant (HybridContactPlant, stepping-stone terrain, SSP→SSP through impact; or BulletWorldPlant: PlantKind)
//     → supervisor (step sequence, α_0, pre-impact posture NLP Eq. (21))
//     → planner (momentum regulation, Eq. (17)-(18), (25)-(27))
//     → vertical_com_mpc (Eq. (28), 1 kHz, warm-started QP)
//     → outputs (Eq. (19)-(24))
//     → output_adapter (SteppingStonesOutputAdapter: stance-foot frame → world, task layout of the controller)
//     → controller (any System with the controller ports below, a leaf or a diagram; default: task-space QP,
//       Eq. (29)-(31), 1 kHz)
//     → plant
//   plus a logger.
// Every block is a framework system. The controller is a parameter of the builder (SteppingStonesControllerFactory):
//   BuildSteppingStonesDiagram(terrain, params, MyControllerFactory)
// Controller ports (the seam), connected by name:
//   inputs  state (2 nv, plant [q; v]), mode (int, plant contact mode),
//           desired (3 × SteppingStonesControllerSpec::num_task_rows, see SteppingStonesControllerSpec);
//   outputs u (nu, N m, held between updates), qp_failures (1), qp_status (1, 0 = solved).
// A diagram (e.g. controller → Saturation, SaturatedControllerFactory) exports these names with DiagramBuilder::
// ExportInput/ExportOutput; read its outputs with SteppingStonesDiagram::EvalControllerOutput.
// The controller should re-solve at guard events (an event update) so that the new contact mode's torque acts from
// the touchdown instant on. The plant and the controller get the same contact stabilisation parameters.
// Event order at a touchdown: the plant's impact reset, then the event updates of the supervisor (new stance foot,
// posture NLP), the MPC (re-solved about the new stance foot) and the controller (new contact set), in that order.
//
// Choices beyond the paper (each a named parameter below, with the reason next to it):
//  * initial state: both feet at rest on the first stone (J_c v = 0; a base velocity alone would slide the stance
//    foot), COM at initial_com_x_m on the E* orbit at supervisor.walking_com_height_m;
//  * walking height: the posture NLP aims the pre-impact COM at walking_com_height_m (AMBER's nominal pose has
//    nearly straight legs; a COM rising after impact then drives the stance knee into its singular straight
//    position and the task-space QP infeasible);
//  * swing foot touches down at τ = 1 (COM at ε l_des), where the impact map and the planner assume the impact;
//  * the vertical-COM plan is held in the last 50 ms before the impact (the re-solved plan becomes deadbeat);
//  * the supervisor's outputs switch to the new stance foot and step at the impact itself, not one control period
//    later (see stepping_stones_supervisor.h);
//  * falls: the supervisor watches the COM height above the stance foot; the plant's absolute base-height guard is
//    shifted to the lowest stone; a stance foot that would pull on the ground lifts off (flight mode), one that leaves
//    the friction cone ends the run as a slip (HybridContactPlant);
//  * task weights: the swing foot 5, torso pitch and COM height 1 (when the torque limits bind, the foot keeps to its
//    path and lands on the planned stone);
//  * integration: ARKODE's explicit Bogacki-Shampine 3(2) with a 1 ms first step, i.e. one error-controlled step per
//    controller sample (see SteppingStonesSimulatorConfig); touchdowns are still located by root finding.
// Solver failures in the loop: the task-space QP re-solves without its GRF rows and counts the failure
// (TaskSpaceQpController; the controller's GRF rows use a friction margin and a minimum normal force, see
// DefaultControllerParams()); the MPC relaxes its terminal equality (VerticalComMpc); the posture NLP retries from the
// nominal pose, then falls back to the previous solution (PreImpactPostureOptimizer). The example counts QP and NLP
// failures in its summary (qp_failures, nlp_failures).

#include <functional>
#include <limits>
#include <memory>
#include <string>

#include "diagrams/stepping_stones/stepping_stones_supervisor.h"
#include "framework/diagram.h"
#include "framework/simulator.h"
#include "framework/vector_logger.h"
#include "systems/controllers/clf_qp_controller.h"
#include "systems/controllers/task_space_qp_controller.h"
#include "systems/planners/momentum_regulation_planner_system.h"
#include "diagrams/stepping_stones/stepping_stones_output_adapter.h"
#include "diagrams/stepping_stones/stepping_stones_outputs_system.h"
#include "systems/perturbations/perturbation_params.h"
#include "systems/planners/vertical_com_mpc_system.h"
#include "systems/plants/bullet_world_plant.h"
#include "systems/plants/hybrid_contact_plant.h"
#include "systems/plants/plant_kind.h"

namespace rome {

/// One task (output, Eq. (19)) of the controller's `desired` input: where its rows sit in each third of `desired`.
struct SteppingStonesTaskRows {
  std::string task;                    ///< the task's name, as in SteppingStonesTasks()
  int first_row = 0;                   ///< its first row within one third of `desired`
  std::vector<std::string> row_names;  ///< names of its rows (SteppingStonesOutputAdapter::task_row_names())
  std::vector<int> active_modes;       ///< plant modes in which it is tracked (empty: every mode)
};

/// What the diagram hands a controller factory.
///
/// Layout of the controller's `desired` input (SteppingStonesOutputAdapter): 3 × num_task_rows elements, [y_d; ẏ_d;
/// ÿ_d], each third in the rows of `tasks`, world frame (m, rad; rates per s, per s²); the rows of a task that is not
/// active in the current mode are zero.
///   Point feet (AMBER), num_task_rows = 6, `desired` has 18 elements:
///     torso_pitch       row 0     torso_pitch (rad)                every mode
///     com_height        row 1     com_z (m)                        every mode
///     left_swing_foot   rows 2-3  left_foot_x, left_foot_z (m)     right stance
///     right_swing_foot  rows 4-5  right_foot_x, right_foot_z (m)   left stance
///   Line/flat feet (planar Cassie), num_task_rows = 8, `desired` has 24 elements: the six rows above, then
///     left_swing_foot_pitch   row 6  left_foot_pitch (rad)   right stance
///     right_swing_foot_pitch  row 7  right_foot_pitch (rad)  left stance
/// The element names of the port are the row names, prefixed "d_" in the second third and "dd_" in the third.
struct SteppingStonesControllerSpec {
  std::string name = "controller";  ///< the block's name in the diagram
  std::shared_ptr<const MultibodyModel> model;
  std::vector<ContactSet> mode_contacts;  ///< active contacts of each plant mode (0 left, 1 right stance, 2 flight)
  ConstrainedDynamicsParameters contact_stabilization;  ///< the plant's (HybridContactPlantParams::dynamics)
  int left_stance_mode = 0, right_stance_mode = 1;
  int num_task_rows = 0;                      ///< rows of one third of `desired` (6 point feet, 8 line/flat feet)
  std::vector<SteppingStonesTaskRows> tasks;  ///< the tasks of `desired`, in row order (see above)
};
/// Builds the controller block: any System (a leaf system or a Diagram) with the controller ports (see the top of this
/// file), connected by port name.
using SteppingStonesControllerFactory = std::function<std::unique_ptr<System>(const SteppingStonesControllerSpec&)>;

struct SteppingStonesDiagramParams {
  std::string robot_sidecar = "robots/amber/amber.rome.json";  ///< planar point-foot robot
  /// E* [m²/s²]. Paper: 0.5 (random stones), 0.3 (Fig. 6). Ours for AMBER (this default): 0.4. At 0.5, after a short
  /// step up by about 0.25 m onto a stone followed by a short step, AMBER's rear foot must rise about 0.3 m within
  /// about 0.12 s to clear its stance stone; its swing joints (reflected rotor inertia 0.43 kg m² each) saturate and
  /// the foot stubs the stone's rear edge (docs/design-notes.md#stepping-stones-amber-energy). ForRobot sets planar
  /// Cassie's 0.5.
  double target_orbital_energy = 0.4;
  double impact_fraction = 0.6;  ///< ε [-] (paper: 0.6)
  double log_period_s = 5e-3;    ///< [s]
  /// [m] COM position relative to the stance foot at the start (ours; the paper gives no initial state). The
  /// robot starts on the E* orbit there: ṗx = sqrt(E* + λ² x²), λ² = g / walking height (Eq. (16)). Starting
  /// behind the foot gives the first swing (from standing, both feet on the first stone) time to lift; from
  /// x = 0 the first step of a short random step lasts only about 0.2 s.
  double initial_com_x_m = -0.1;
  HybridContactPlantParams
      plant;  ///< min_base_height_m is taken above the lowest stone (see BuildSteppingStonesDiagram)
  /// The Bullet plant's (PlantKind::kBullet); min_base_height_m likewise. Its contact points are 1 mm spheres
  /// on the stones' boxes, its step 1 ms, its update just after the controller's sample (bullet_world_plant.h).
  BulletWorldPlantParams bullet_plant;
  SteppingStonesSupervisorParams supervisor;
  /// Ours for AMBER (this default): u_des >= −1.5 m/s (min_pre_impact_vertical_velocity_mps; the paper: unbounded;
  /// why: MomentumRegulationPlannerParams, docs/design-notes.md#stepping-stones-amber-energy). ForRobot sets planar
  /// Cassie's −1 m/s. Its target_orbital_energy and
  /// impact_fraction are replaced by this struct's (BuildSteppingStonesDiagram).
  MomentumRegulationPlannerParams planner = DefaultPlannerParams();
  /// Eq. (28). Ours: the plan is held (not re-solved) in the last 50 ms before the predicted impact.
  VerticalComMpcSystemParams mpc = DefaultMpcParams();
  /// Eq. (19)-(24). Ours: the swing foot is re-timed to touch down when the COM reaches ε l_des
  /// (SwingTouchdownTiming::kAtPhaseEnd), where Eq. (17), (25)-(27) put the impact, and its clearance is
  /// measured from the highest of the start, stance and next stones (SwingApexReference::kHighestStone),
  /// reached exactly and held over the stance stone (SwingApexShape::kClearStanceStone; the paper's control points
  /// peak about 20 % lower, near τ = 0.5 whatever the step).
  SteppingStonesOutputsSystemParams outputs = DefaultOutputsParams();
  TaskSpaceQpParams controller = DefaultControllerParams();
  /// The CLF-QP alternative (ClfQpControllerFactory): the same outputs (Eq. (19)), GRF rows and torque limits.
  ClfQpParams clf_controller = DefaultClfParams();
  TaskGains torso_gains{1.0, 100.0, 20.0};
  TaskGains com_height_gains{1.0, 100.0, 20.0};
  /// [-] The CLF-QP's cost weight on the COM-height output (ClfQpControllerFactory only; NaN: com_height_gains'
  /// weight, as the task-space QP). Ours; ForRobot sets it for line feet (planar Cassie), see the .cc.
  double clf_com_height_weight = std::numeric_limits<double>::quiet_NaN();
  /// Weight 5 (ours): when the torque limits bind (short steep steps), the QP gives the swing foot priority over the
  /// COM height and torso pitch, so that it clears the stones and lands on the planned one.
  TaskGains swing_foot_gains{5.0, 400.0, 40.0};
  /// Line/flat feet only (planar Cassie): the fifth output, the swing foot's pitch, held at its flat pitch so that
  /// the sole lands parallel to the stone (hopping spec C.12). Not used for point feet.
  TaskGains swing_foot_pitch_gains{1.0, 400.0, 40.0};
  /// Line/flat feet: the actuator of the foot link's inboard joint (planar Cassie's toe) gets zero torque while that
  /// foot stands (zero_torque_in_contact of either controller), so the stance ankle is passive as for a point foot
  /// (stepping-stones paper, Sec. IV-A). No effect on point feet.
  bool passive_stance_ankle = true;
  /// What the simulated world does differently from the controller's model (systems/perturbations/): a push on a body
  /// (hybrid plant only), link masses/inertias and friction scaled in the plant only, stone heights off the map the
  /// supervisor plans on, sensor noise and latency on the state the controller sees (the supervisor reads the plant's
  /// state), torque noise between controller and plant. Default: none.
  PerturbationParams perturbations;

  /// The defaults above (tuned on AMBER, point feet) adapted to the robot of `sidecar` (sets robot_sidecar). Point
  /// feet: the defaults unchanged. Line/flat feet (planar Cassie), see the .cc for each value and its reason:
  /// walking height = the nominal standing pose's COM height above its soles (hopping spec C.12: z0), gains from the
  /// RoMoCo-like Cassie anchors (Kp 150-600 1/s², Kd 2-40 1/s).
  static SteppingStonesDiagramParams ForRobot(const std::string& sidecar);
  /// Throws std::invalid_argument naming the field, the value and the allowed range (ranges ours: bounded work and a
  /// meaningful gait): E* in (0, 10] m²/s², ε in (0, 1), log period [1e-4, 10] s, initial COM x [-0.5, 0.5] m,
  /// max_steps [1, 10000], swing clearance (0, 1] m, MPC hold [0, 10] s, CLF COM weight (0, 1000] (or NaN), CLF period
  /// [1e-5, 1] s, friction margin (0, 1], min normal force [0, 1e4] N, task weights [0, 1e6], kp [0, 1e6], kd [0, 1e5].
  /// BuildSteppingStonesDiagram calls it first.
  void Validate() const;

  static TaskSpaceQpParams DefaultControllerParams() {
    TaskSpaceQpParams p;
    // Ours: the QP's friction pyramid at 0.95 μ and F_z ≥ 2 N: over the 1 ms zero-order hold the plant's forces drift
    // from the QP's (docs/design-notes.md#stepping-stones-friction-margin).
    p.friction_margin = 0.95;
    p.min_normal_force_N = 2.0;
    // Ours: the pyramid's apex raised to 1.5 N, as the CLF-QP's: a stance foot that unloads near the end of its stance
    // (a few newtons) otherwise sits at 0.95 μ, which the held sample's drift carries past μ (unloading slips,
    // docs/design-notes.md#stepping-stones-random-course-failures).
    p.friction_cone_offset_N = 1.5;
    // Ours: the GRF rows also hold at the end of the held sample, as the CLF-QP's (planar Cassie's stance force moves
    // by 4 N per 1 ms sample at 30 N of load; docs/design-notes.md#stepping-stones-cassie-slips).
    p.predict_hold_drift = true;
    return p;
  }
  static ClfQpParams DefaultClfParams() {
    ClfQpParams p;
    // The same GRF rows as the task-space QP's (see DefaultControllerParams), with the pyramid's apex raised to 1.5 N
    // (ours): the CLF-QP's torques change faster within a held sample (docs/design-notes.md#stepping-stones-clf-qp).
    p.contact.friction_margin = 0.95;
    p.contact.min_normal_force_N = 2.0;
    p.contact.friction_cone_offset_N = 1.5;
    // The cost tracks each output's PD target (cost_pd_feedback, ours) so that the task weights rank the outputs as in
    // the task-space QP; ε = 0.1 (spec [R] 0.02-0.1); the wrench rows also hold at the end of the held sample
    // (predict_hold_drift, ours). Chosen on random seeds 1000-1099 (docs/design-notes.md#stepping-stones-clf-qp).
    p.cost_pd_feedback = true;
    p.epsilon = 0.1;
    p.predict_hold_drift = true;
    return p;
  }
  static MomentumRegulationPlannerParams DefaultPlannerParams() {
    MomentumRegulationPlannerParams p;
    p.min_pre_impact_vertical_velocity_mps = -1.5;
    return p;
  }
  /// Ours: the relaxed plan (pre-impact state out of reach) keeps the terminal velocity before the height
  /// (terminal_position_weight 1e3 against terminal_velocity_weight 1e6), as planar Cassie's: with equal weights
  /// the height error (scaled by 1/dt²) wins, the plan gives up u_des, and an impact that arrives rising leaves the
  /// next stance asking for free fall, which unloads the stance foot until it slips
  /// (docs/design-notes.md#stepping-stones-cassie-whip, #stepping-stones-amber-energy).
  static VerticalComMpcSystemParams DefaultMpcParams() {
    VerticalComMpcSystemParams p;
    p.hold_plan_below_horizon_s = 0.05;
    p.mpc.terminal_position_weight = 1e3;
    return p;
  }
  static SteppingStonesOutputsSystemParams DefaultOutputsParams() {
    SteppingStonesOutputsSystemParams p;
    p.swing_foot.touchdown_timing = SwingTouchdownTiming::kAtPhaseEnd;
    p.swing_foot.apex_reference = SwingApexReference::kHighestStone;  // clears the start, stance and next stones
    // The curve really reaches the clearance, and is at least that high over the stance stone (kExactPeak, raised
    // where the foot passes over the stance stone late in the swing).
    p.swing_foot.apex_shape = SwingApexShape::kClearStanceStone;
    // NaN: BuildSteppingStonesDiagram uses half the longest stone of the terrain.
    p.swing_foot.stance_stone_half_length = std::numeric_limits<double>::quiet_NaN();
    return p;
  }
};

struct SteppingStonesDiagram {
  std::unique_ptr<Diagram> diagram;
  const ContactPlant* plant = nullptr;
  const SteppingStonesSupervisor* supervisor = nullptr;
  const MomentumRegulationPlannerSystem* planner = nullptr;
  const VerticalComMpcSystem* mpc = nullptr;
  const SteppingStonesOutputsSystem* outputs = nullptr;
  const SteppingStonesOutputAdapter* output_adapter = nullptr;
  const System* controller = nullptr;  ///< whatever the factory built, a leaf or a diagram (read it through its ports)
  const VectorLogger* logger = nullptr;
  PerturbationBlocks perturbation_blocks;       ///< the perturbation blocks that are on (params.perturbations)
  std::shared_ptr<const MultibodyModel> model;  ///< the controller's and supervisor's model (the plant's may differ)
  /// Output `port` of the controller (e.g. "qp_failures") in the diagram's `context`, whether the controller is a leaf
  /// or a diagram.
  const Eigen::VectorXd& EvalControllerOutput(const Context& context, const std::string& port) const {
    return diagram->EvalSubsystemOutput(*controller, port, context);
  }
};

/// Stones `step_length_m` apart along x, each `step_height_m` above the previous (0: flat ground; stairs), the
/// first centred at x = 0, z = 0.
Terrain PeriodicSteppingStones(double step_length_m, double step_height_m, int num_stones, double stone_length_m = 0.1);

/// Random stones as in the paper's Sec. VI-C: distances uniform in [min_gap_m, max_gap_m], each stone's height
/// changed from the previous one's by a uniform draw in [−max_rise_m, max_rise_m] (std::mt19937 with `seed`).
struct RandomSteppingStonesParams {
  int num_stones = 32;
  double min_gap_m = 0.2;    ///< [m] paper: 0.2
  double max_gap_m = 0.7;    ///< [m] paper: 0.7
  double max_rise_m = 0.25;  ///< [m] paper: ±0.25
  double stone_length_m = 0.1;
  unsigned seed = 1;
};
Terrain RandomSteppingStones(const RandomSteppingStonesParams& params);

/// Simulator settings of the example and the closed-loop tests: ARKODE's explicit Bogacki-Shampine 3(2)
/// (IntegrationScheme::kExplicitRungeKutta, ExplicitRungeKuttaMethod::kBogackiShampine32), rtol 1e-6, atol 1e-8,
/// first step 1 ms. The closed loop restarts the integrator at every 1 kHz controller sample (the zero-order-held
/// torque jumps); a one-step method loses nothing by a restart, and the plant is not stiff (contact stabilisation
/// α = β = 10 1/s), so one error-controlled step per sample suffices: 4 derivative evaluations per sample, against 8
/// with Dormand-Prince 5(4), about 13 with CVODE Adams and fixed-point iteration, and several times that with BDF and
/// a finite-difference Jacobian rebuilt after every restart (30-step demo, same machine and hour: 39-43x, 32-35x,
/// 20x and 10x real time). The two explicit pairs give the same footholds to 1e-8 m. Touchdowns are located by root
/// finding on the dense output.
SimulatorConfig SteppingStonesSimulatorConfig();

/// [m] Length of the longest line/flat sole of `model` along x in the nominal pose (toe to heel); 0 for point feet.
double SoleLength(const MultibodyModel& model);

/// [m] Stone length (top, along x) the robot's feet need: 0.1 m (AMBER's stones) for point feet; for line/flat feet
/// the longest sole plus 2 × 2 cm (a touchdown may be 2 cm off the centre and the whole sole must still stand on the
/// stone, since the plant welds the foot and the controller's centre-of-pressure rows span the whole sole).
double SteppingStoneLengthFor(const MultibodyModel& model);

/// True if either foot of `model` is a line or flat contact: the diagram then adds the swing-foot pitch output.
bool HasFootPitchOutput(const MultibodyModel& model);

/// The outputs of Eq. (19) that the default controllers track, in the row order of `desired` (spec.tasks): torso pitch,
/// COM height, each foot's x and z while it swings, and for line/flat feet each foot's pitch while it swings, with the
/// task gains of `params`. For a controller of your own built on TaskSpaceTask.
std::vector<std::shared_ptr<const TaskSpaceTask>> SteppingStonesTasks(const SteppingStonesDiagramParams& params,
                                                                      const SteppingStonesControllerSpec& spec);

/// Wraps the block of `controller` in a diagram (controller → Saturation) that clamps its torques u to [lower, upper]
/// (N m, nu each; the Saturation block's contract, framework/primitives.h) and exports the same controller ports.
/// The inner block is named "controller" inside the diagram, the Saturation "saturation". Throws, naming the sizes, if
/// lower or upper does not have nu elements, and as Saturation does for crossed or NaN bounds.
SteppingStonesControllerFactory SaturatedControllerFactory(SteppingStonesControllerFactory controller,
                                                           Eigen::VectorXd lower, Eigen::VectorXd upper);

/// The paper's controller: TaskSpaceQpController (Eq. (29)-(31)) with params.controller and the task gains of
/// `params` (torso pitch, COM height, swing foot), the plant's contact stabilisation.
SteppingStonesControllerFactory TaskSpaceQpControllerFactory(const SteppingStonesDiagramParams& params);

/// The CLF-QP controller (ClfQpController) tracking the same outputs as the task-space QP: torso pitch, COM height and
/// the swing foot's x and z (Eq. (19)), as relative-degree-2 outputs with the task weights of `params`, with
/// params.clf_controller and the plant's contact stabilisation.
SteppingStonesControllerFactory ClfQpControllerFactory(const SteppingStonesDiagramParams& params);

/// Builds the diagram for `terrain` (the robot starts standing on its first stone). `controller`: the controller
/// block's factory; empty = TaskSpaceQpControllerFactory(params). `plant`: which plant (params.plant or
/// params.bullet_plant). Throws, naming the port, if the block lacks a controller port or a port has the wrong type or
/// size.
SteppingStonesDiagram BuildSteppingStonesDiagram(const Terrain& terrain, const SteppingStonesDiagramParams& params,
                                                 const SteppingStonesControllerFactory& controller = nullptr,
                                                 PlantKind plant = PlantKind::kHybrid);

/// The initial plant state [q; v]: both feet on the centre of the first stone (left stance, right foot beside it),
/// COM straight above them at params.supervisor.walking_com_height_m, torso upright; both feet at rest, torso not
/// rotating, COM moving forward at the speed of the E* orbit at mid-stance (ṗ^x = sqrt(E*), Eq. (16)) and not
/// vertically (the stance foot must not slide: J_c v = 0). Throws std::runtime_error naming the robot if no such
/// pose exists.
Eigen::VectorXd SteppingStonesInitialState(const MultibodyModel& model, const Terrain& terrain,
                                           const SteppingStonesDiagramParams& params);

/// Sets SteppingStonesInitialState() in the plant (left stance) and initialises the supervisor. `context` is the
/// diagram's.
void SetSteppingStonesInitialState(const SteppingStonesDiagram& d, const SteppingStonesDiagramParams& params,
                                   Context& context);

}  // namespace rome
