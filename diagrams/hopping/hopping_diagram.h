#pragma once
// The hopping diagram (hopping paper, Fig. 5 and Sec. IV): Cassie hops on the spring-mass ROM's plans.
//
//   plant (PlantKind, one builder argument. HybridContactPlant: 3D Cassie, springs live, achilles rods as loop
//          closures, Jump → Flight → Landing, Eq. (18)-(21). Or BulletWorldPlant on the same graph: springs as joint
//          torques per substep, rods as Bullet rod constraints, each foot's toe and heel spheres on Bullet's ground
//          plane, modes from which feet touch)
//     → reference (HoppingReference: the domain and the desired outputs, Eq. (41)-(44), from the ROM's jump plan
//                  (Eq. (14)-(15), solved from the measured standing state) and landing plan (Eq. (16), solved at
//                  lift-off from the predicted touchdown and again, warm, from the post-impact state); it reads the
//                  plant's state, mode and contact forces (the Jump's GRF feedback, ours))
//     → controller (any System from a HoppingControllerFactory, a leaf or a diagram; default
//     MakeDefaultHoppingController:
//                   ClfQpController, augmented input [u; F_h], Eq. (45)-(51), RES-CLF Eq. (29)-(37), line-foot wrench
//                   rows and torque limits, 2 kHz and re-solved at every event; outputs per domain from
//                   MakeHoppingOutputs)
//     → plant
//   plus a logger.
// Controller ports (the seam):
//   inputs  state (nq + nv)   plant [q; v] on HoppingControllerSpec::model's base
//           mode (int, typed) the reference's domain: 0 jump, 1 flight, 2 landing (HoppingDomain)
//           desired (3 ny)    the reference's [y_d; ẏ_d; ÿ_d], ny = 16 (17 with HoppingOutputParams::
//                             jump_tracks_momentum, Eq. (41)); rows of y_d in HoppingControllerSpec::tasks order (the
//                             same offsets in ẏ_d and ÿ_d, + ny and + 2 ny): with jump_tracks_momentum
//                             centroidal_pitch_momentum (1, row 0, jump, [N m s]) first; then leg_length_left,
//                             leg_length_right (1 each, jump and landing, [m]), com_xy (2, jump and landing, [m]),
//                             pelvis_yaw, pelvis_pitch (1 each, [rad]; the pitch in landing, and in jump by default),
//                             motor_<joint> (1 each, the 10 actuated joints in actuator order, flight, [rad]). The
//                             default starts with leg_length_left at row 0 (MakeHoppingOutputLayout gives the offsets).
//   outputs u (nu, N m)       the plant's motor torques, held between updates (required)
//           qp_failures (1)   failed solves so far (optional: the run reports it when present)
//           V, delta, contact_forces, qp_status, solve_time_s (optional: logged when present)
// A controller should re-solve at guard events (an event update), so that the new domain's torque acts from the event
// on. Swapping it is one argument:
//   BuildHoppingDiagram(model, leg_length, jump, landing, params, PlantKind::kHybrid, MyControllerFactory)
// A diagram built with DiagramBuilder is a controller too when it exports these ports, e.g. the default controller →
// Saturation (framework/primitives.h) exporting the saturation's y as u (tests/diagrams/hopping,
// SaturatedSubDiagram...).
//
// Build → run → result from C++ (diagrams/hopping/hopping_run.h; tests/diagrams/hopping/hopping_diagram_test.cc
// compiles exactly this):
//   auto model = std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
//       FindRobotFile("robots/cassie/cassie.rome.json"), {.euler_floating_base = true}));
//   SpringMassHopPlanners rom(*model, LegStiffnessVariant::kIdentified, SpringMassJumpParams{},
//   SpringMassLandingParams{}); HoppingDiagramParams params; params.reference.hops = 1; HoppingDiagram d =
//   BuildHoppingDiagram(model, rom.leg_length, rom.jump, rom.landing, params); Simulator sim(*d.diagram,
//   HoppingSimulatorConfig()); SetHoppingInitialState(d, sim.get_mutable_context(), model->q_nominal()); const
//   HoppingRunResult result = RunHopping(d, sim, HoppingRunParams{}, &rom);
//   // result.success, result.hopped, result.air_time_s, result.grf_nrmse_jump, result.contact.violations, ...
// (headers: diagrams/hopping/hopping_run.h, systems/multibody/robot_files.h)
//
// The ROM pieces enter as functions: the virtual leg length L(q_knee) (Eq. (13)) and the two planners, so the
// builder does not depend on how the plans are computed.
// Event order at a lift-off or touchdown: the plant's reset, then the reference's event update (new domain, motor
// snapshot or landing plan), then the controller's re-solve for the new domain.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "diagrams/hopping/hopping_outputs.h"
#include "framework/diagram.h"
#include "framework/simulator.h"
#include "framework/vector_logger.h"
#include "systems/controllers/clf_qp_controller.h"
#include "systems/controllers/task_space_qp_controller.h"
#include "diagrams/hopping/hopping_reference.h"
#include "systems/perturbations/perturbation_params.h"
#include "systems/plants/plant_kind.h"
#include "systems/plants/quaternion_to_euler_state.h"

namespace rome {

struct HoppingDiagramParams {
  HybridContactPlantParams plant =
      DefaultPlantParams();  ///< PlantKind::kHybrid; its dynamics are the controller's on either plant
  BulletWorldPlantParams bullet_plant = DefaultBulletPlantParams();  ///< PlantKind::kBullet
  ClfQpParams controller = DefaultControllerParams();  ///< contact_stabilization is overwritten with plant.dynamics
  HoppingOutputParams outputs = DefaultOutputParams();
  HoppingReferenceParams reference = DefaultReferenceParams();
  double log_period_s = 1e-3;  ///< [s]
  /// [-] ρ_u is multiplied by this in the Landing domain (ours, measured; 1: off), which also covers the settle before
  /// the first hop and the rests between hops. It sets the controller's u_regularization_weights and
  /// u_regularization_modes (BuildHoppingDiagram throws if those are set too). With the Jump's GRF feedback the robot
  /// lands from higher and, 0.1-0.2 s after touchdown with ~100 N on each foot, the landing QP's torques jumped between
  /// solutions tick to tick (hip pitches +177 / −195 N m, the legs scissoring) while V stayed ~0.1: the 4 torque
  /// directions the 6 landing outputs leave free are set by ρ_u alone. Each jump put the feet's forces on the friction
  /// pyramid's edge and a foot slipped (apex rises 0.23 and 0.28 m). With 10 all six tuning apex rises land.
  double landing_u_regularization_scale = 10.0;
  /// What the simulated world does differently from the controller's model (systems/perturbations/): a push on a body
  /// (either plant), link masses/inertias and friction scaled in the plant only, sensor noise and latency on the
  /// state the controller sees (the reference and its planners read the plant's true state), torque noise. Default:
  /// none.
  PerturbationParams perturbations;
  /// The plant's base (issue 43; ours, default Euler for now). kQuaternion: the hybrid plant runs on the quaternion
  /// twin of the builder's model (LoadQuaternionTwin: the same URDF and sidecar), the controller runs on that twin and
  /// reads the plant's state (its pelvis angles by BodyEulerAngleTask), and a QuaternionToEulerState block
  /// ("euler_state") maps the plant's state to the Euler state that the reference and the logger read. Needs
  /// PlantKind::kHybrid and no perturbations.push (its generalized force is the Euler model's).
  PlantBase plant_base = PlantBase::kEuler;
  EulerStateParams euler_state;  ///< the map's refusal near pitch +-90 deg (plant_base = kQuaternion)
  static HybridContactPlantParams DefaultPlantParams();
  /// The Bullet plant steps at the controller's 2 kHz (0.5 ms, ours: a 1 ms step would apply only every other torque)
  /// in 5 substeps (ours; docs/design-notes.md#hopping-bullet-substeps), with the hybrid plant's fall height (0.5 m),
  /// lift-off force (8 N) and minimum time between a lift-off and the next touchdown (20 ms).
  static BulletWorldPlantParams DefaultBulletPlantParams();
  /// The block's defaults, with flight_hip_pitch_follow = −1, jump_momentum_gain = 10, landing_deflection_feedback =
  /// 0.7, jump_force_feedback = 6, jump_force_integral_per_s = 40 and landing_blend_s = 0.5 (ours;
  /// docs/design-notes.md#hopping-first-landing, #hopping-air-time, #hopping-landing-blend).
  static HoppingReferenceParams DefaultReferenceParams();
  /// Augmented input, 2 kHz (hopping paper), ε = 0.1, F_z ≥ 0 (the paper's GRF rows), μ = 0.8 inscribed pyramid,
  /// ρ_u = 1e-4 (spec [R]; docs/design-notes.md#hopping-torque-penalty), relaxation weight p = 1e4 (ours;
  /// docs/design-notes.md#hopping-relaxation-weight).
  static ClfQpParams DefaultControllerParams();
  /// Jump tracks the pelvis pitch, not H_pitch (ours, a deviation from Eq. (41)): with H_pitch the closed loop has an
  /// unstable real eigenvalue (docs/design-notes.md#hopping-jump-output); the momentum is steered through the pitch
  /// reference (HoppingReferenceParams::jump_momentum_gain). Flight motors at 30 rad/s, critically damped (ours).
  static HoppingOutputParams DefaultOutputParams();
  /// Throws std::invalid_argument "HoppingDiagramParams: <field> = <value>: must be in <range>" for the first field out
  /// of its range (the hopping example's flags use the same ranges). BuildHoppingDiagram calls it first.
  void Validate() const;
};

/// One task of the controller's desired input: its name (ClfOutput name), first row and number of rows in `desired`,
/// and the domains it is tracked in (HoppingDomain).
struct HoppingTask {
  std::string name;
  int row = 0, size = 0;
  std::vector<int> domains;
};

/// What the diagram hands a controller factory.
struct HoppingControllerSpec {
  std::string name = "controller";  ///< the block's name in the diagram
  /// The plant's base: the builder's model, or its quaternion twin (plant_base = kQuaternion; state = [q (nv + 1); v]).
  std::shared_ptr<const MultibodyModel> model;
  std::vector<ContactSet> mode_contacts;  ///< active contacts of each domain (0 jump, 1 flight, 2 landing)
  std::vector<ClfOutput> outputs;         ///< the outputs of the desired input, in row order (MakeHoppingOutputs)
  std::vector<HoppingTask> tasks;         ///< the same as a list of rows (HoppingTasks)
  HoppingOutputLayout layout;             ///< offsets of the desired rows (MakeHoppingOutputLayout)
  /// The diagram's ClfQpParams with contact_stabilization = the plant's dynamics and the landing torque penalty
  /// (HoppingDiagramParams::landing_u_regularization_scale) applied.
  ClfQpParams controller;
};

/// Builds the controller block: any System (a leaf or a diagram) with the controller ports (see the top of this file).
using HoppingControllerFactory = std::function<std::unique_ptr<System>(const HoppingControllerSpec&)>;

/// The default controller: ClfQpController(spec.name, spec.model, spec.mode_contacts, spec.outputs, spec.controller).
std::unique_ptr<System> MakeDefaultHoppingController(const HoppingControllerSpec& spec);

/// The rows of the controller's desired input for these output params (name, first row, size, domains).
std::vector<HoppingTask> HoppingTasks(const MultibodyModel& model, const HoppingOutputParams& params = {});

struct HoppingDiagram {
  std::unique_ptr<Diagram> diagram;
  const ContactPlant* plant = nullptr;
  HoppingReference* reference = nullptr;
  const System* controller = nullptr;  ///< whatever the factory built (read it through the diagram's exported ports)
  VectorLogger* logger = nullptr;
  /// The reference's (Euler base); the controller's is the plant's base (HoppingControllerSpec::model).
  std::shared_ptr<const MultibodyModel> model;
  std::shared_ptr<const MultibodyModel>
      plant_model;  ///< the plant's (the quaternion twin with plant_base = kQuaternion)
  /// The map from the plant's quaternion state to the Euler state (null on the Euler base).
  const QuaternionToEulerState* euler_state = nullptr;
  HoppingReference::LegLengthFunction leg_length;  ///< L(q_knee), Eq. (13)
  HoppingDiagramParams params;                     ///< as built (validated)
  std::vector<HoppingTask> tasks;                  ///< the controller's desired rows
  HoppingOutputLayout layout;
  PlantKind plant_kind = PlantKind::kHybrid;
  PerturbationBlocks perturbation_blocks;  ///< the perturbation blocks that are on (params.perturbations)
};

/// The diagram also exports the controller's u (as "u") and, when the controller has it, qp_failures (as
/// "qp_failures"), so a run reads them whatever the controller is. Validates `params` first.
HoppingDiagram BuildHoppingDiagram(std::shared_ptr<const MultibodyModel> model,
                                   const HoppingReference::LegLengthFunction& leg_length,
                                   HoppingReference::JumpPlanner jump_planner,
                                   HoppingReference::LandingPlanner landing_planner,
                                   const HoppingDiagramParams& params = {}, PlantKind plant = PlantKind::kHybrid,
                                   const HoppingControllerFactory& controller = MakeDefaultHoppingController);

/// The robot's state [q; v] in the controller's (Euler) coordinates: the plant's state, or the euler_state block's map
/// of it on the quaternion base.
const Eigen::VectorXd& HoppingEulerState(const HoppingDiagram& d, const Context& context);

/// Puts the robot at q (the controller's Euler coordinates; at rest, plant mode "jump": both feet down), the reference
/// into its settle phase and a sensor latency's history at that state.
void SetHoppingInitialState(const HoppingDiagram& d, Context& context, const Eigen::VectorXd& q);

/// Integrator of the hopping loop: explicit Bogacki-Shampine 3(2), rtol 1e-5, atol 1e-7 (ours;
/// docs/design-notes.md#hopping-integrator).
SimulatorConfig HoppingSimulatorConfig();

}  // namespace rome
