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
//     → controller (ClfQpController: augmented input [u; F_h], Eq. (45)-(51), RES-CLF Eq. (29)-(37), line-foot wrench
//                   rows and torque limits, 2 kHz and re-solved at every event; outputs per domain from
//                   MakeHoppingOutputs)
//     → plant
//   plus a logger.
// The ROM pieces enter as functions: the virtual leg length L(q_knee) (Eq. (13)) and the two planners, so the
// builder does not depend on how the plans are computed.
// Event order at a lift-off or touchdown: the plant's reset, then the reference's event update (new domain, motor
// snapshot or landing plan), then the controller's re-solve for the new domain.
#include <memory>
#include <string>

#include "diagrams/hopping/hopping_outputs.h"
#include "framework/diagram.h"
#include "framework/simulator.h"
#include "framework/vector_logger.h"
#include "systems/controllers/clf_qp_controller.h"
#include "systems/controllers/task_space_qp_controller.h"
#include "systems/planners/hopping_reference.h"
#include "systems/plants/plant_kind.h"

namespace rome {

struct HoppingDiagramParams {
  HybridContactPlantParams plant = DefaultPlantParams();  ///< PlantKind::kHybrid; its dynamics are the controller's on either plant
  BulletWorldPlantParams bullet_plant = DefaultBulletPlantParams();  ///< PlantKind::kBullet
  ClfQpParams controller = DefaultControllerParams();  ///< contact_stabilization is overwritten with plant.dynamics
  HoppingOutputParams outputs = DefaultOutputParams();
  HoppingReferenceParams reference = DefaultReferenceParams();
  double log_period_s = 1e-3;  ///< [s]
  /// [-] ρ_u is multiplied by this in the Landing domain (ours, measured; 1: off), which also covers the settle before
  /// the first hop and the rests between hops. It sets the controller's u_regularization_weights and
  /// u_regularization_modes (BuildHoppingDiagram throws if those are set too). With the Jump's GRF feedback the robot lands
  /// from higher and, 0.1-0.2 s after touchdown with ~100 N on each foot, the landing QP's torques jumped between
  /// solutions tick to tick (hip pitches +177 / −195 N m, the legs scissoring) while V stayed ~0.1: the 4 torque
  /// directions the 6 landing outputs leave free are set by ρ_u alone. Each jump put the feet's forces on the friction
  /// pyramid's edge and a foot slipped (apex rises 0.23 and 0.28 m). With 10 all six tuning apex rises land.
  double landing_u_regularization_scale = 10.0;
  static HybridContactPlantParams DefaultPlantParams();
  /// The Bullet plant steps at the controller's 2 kHz (0.5 ms, ours: a 1 ms step would apply only every other torque)
  /// in 5 substeps (ours, see the source), with the hybrid plant's fall height (0.5 m), lift-off force (8 N) and
  /// minimum time between a lift-off and the next touchdown (20 ms).
  static BulletWorldPlantParams DefaultBulletPlantParams();
  /// The block's defaults, with flight_hip_pitch_follow = −1, jump_momentum_gain = 10, landing_deflection_feedback =
  /// 0.7, jump_force_feedback = 6, jump_force_integral_per_s = 40 and landing_blend_s = 0.5 (ours; see the source).
  static HoppingReferenceParams DefaultReferenceParams();
  /// Augmented input, 2 kHz (hopping paper), ε = 0.1, F_z ≥ 0 (the paper's GRF rows), μ = 0.8 inscribed pyramid,
  /// ρ_u = 1e-4 (spec [R]; see the source for why not the block's 1e-6), relaxation weight p = 1e4 (ours; see the
  /// source for why not the block's 1e5).
  static ClfQpParams DefaultControllerParams();
  /// Jump tracks the pelvis pitch, not H_pitch (ours, a deviation from Eq. (41)). Measured cause: with H_pitch as the
  /// relative-degree-1 output the closed loop (plant + CLF-QP, linearised by central differences at the first Jump
  /// sample) has a real eigenvalue at +2305 1/s whose mode is the pelvis pitch, both hip pitches and the shin and heel
  /// springs (H_pitch stays ~0 while the pelvis and the legs turn against each other through the springs). The 6 Jump
  /// outputs leave 4 of the 10 torque directions to the QP's least-torque term, and that choice drives the mode: the
  /// eigenvalue is +206 1/s with u_regularization 1e-3 and +6.9 1/s with 1e-1 (the pelvis pitch then drifts freely);
  /// adding the pelvis pitch as a seventh output next to H_pitch leaves +83 1/s (tarsus, heel spring, toe). A_pitch and
  /// Ȧ_pitch q̇ are right (finite differences and Newton-Euler with contact forces, tests/systems/multibody); the
  /// output's row and sign are right (the momentum weight 1e-4 ... 1e2 changes nothing). With the pelvis pitch output
  /// the largest eigenvalue is +0.036 1/s. (With this diagram's ρ_u = 1e-4, at the start of the hand-made Jump of
  /// tests/diagrams/hopping: +444 1/s with H_pitch, +0.11 1/s with the pitch (relaxation weight 1e4; +414 and +0.05 1/s
  /// with 1e5); that test checks both.) The momentum is steered instead through the pitch reference
  /// (HoppingReferenceParams::jump_momentum_gain). HOP_MOMENTUM=1 in tests/diagrams/hopping reproduces the slip.
  static HoppingOutputParams DefaultOutputParams();
};

struct HoppingDiagram {
  std::unique_ptr<Diagram> diagram;
  const ContactPlant* plant = nullptr;
  HoppingReference* reference = nullptr;
  ClfQpController* controller = nullptr;
  VectorLogger* logger = nullptr;
};

HoppingDiagram BuildHoppingDiagram(std::shared_ptr<const MultibodyModel> model, const HoppingReference::LegLengthFunction& leg_length,
                                   HoppingReference::JumpPlanner jump_planner, HoppingReference::LandingPlanner landing_planner,
                                   const HoppingDiagramParams& params = {}, PlantKind plant = PlantKind::kHybrid);

/// Puts the robot at q (at rest, plant mode "jump": both feet down) and the reference into its settle phase.
void SetHoppingInitialState(const HoppingDiagram& d, Context& context, const Eigen::VectorXd& q);

/// Integrator settings measured for the hopping loop (see hopping_diagram.cc).
SimulatorConfig HoppingSimulatorConfig();

}  // namespace rome
