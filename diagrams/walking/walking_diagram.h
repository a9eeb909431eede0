#pragma once
// The walking diagram (walking paper, Fig. 1 and Sec. IV-V) on the 12-joint exoskeleton, as the paper's block figure:
//
//   ROM plan (WalkingPlan: periodic aSLIP + H-LIP, transitions; built offline by the caller)
//     → walking_reference (WalkingTrajectorySource: COM [p; ṗ; p̈], footholds, per-foot F^z_aSLIP)
//     → outputs (WalkingOutputReference: Eq. (16) in DSP, Eq. (17) in SSP, swing foot to the planned foothold)
//     → controller (ClfQpController: RES-CLF Eq. (18)-(19), F eliminated Eq. (20)-(22), flat-foot wrench rows
//       Eq. (23), force band Eq. (25) on normal_force_reference, torque limits, 1 kHz, re-solved at every event)
//     → plant (HybridContactPlant, DSP ↔ SSP: ContactModeGraph::WithDoubleSupport; DSP → SSP when the trailing foot's
//       normal force reaches 0, no impact; SSP → DSP when the swing sole reaches the ground, plastic impact; flat
//       feet with 6 constraints each)
//
// Choices beyond the paper (each a named parameter): the trailing foot is released at 1 % of m g (spec §7.5 [R],
// HybridContactPlantParams::planned_liftoff_force_N; at F_n → 0 the held force's |F_t|/F_n is ill-conditioned and
// the run would end as a slip at ~0.1 N); the QP keeps the CoP 10 mm inside the sole (cop_margin_m) and uses half the
// spec's μ = 0.6 (friction_margin 0.5): the plant's forces drift over the 1 ms held sample.
// Status: the robot stands, shifts its weight along the transition plan with its plant normal forces in the Eq. (25)
// band and lifts the trailing foot on schedule; it does not yet complete the first step (see the walking test).
//
// Plant modes (WithDoubleSupport): 0 left_foot_stance, 1 double_support, 2 right_foot_stance.
// Controller outputs (order of WalkingOutputReference): COM x, y, z; pelvis roll, pitch, yaw (the base's ZYX angles);
// left ankle position and foot orientation (active in right stance); right ankle position and orientation (active in
// left stance).
#include <cstdint>
#include <memory>

#include "framework/diagram.h"
#include "systems/controllers/clf_qp_controller.h"
#include "systems/planners/plan_cache.h"
#include "systems/planners/walking_output_reference.h"
#include "systems/planners/walking_plan.h"
#include "systems/planners/walking_trajectory_source.h"
#include "systems/plants/hybrid_contact_plant.h"

namespace rome {

struct WalkingDiagramParams {
  HybridContactPlantParams plant;
  ClfQpParams controller = DefaultWalkingControllerParams();
  SwingFootTrajectoryParams swing;  ///< ankle_height_m is set from the model's sole by the builder
  double swing_foot_weight = 5.0;   ///< [-] cost weight of the swing-foot outputs (ours: land on the foothold)

  /// Spec §5 [R]: ε = 0.1, p = 1e5, 1 kHz, force band c = 0.1 (Eq. (25)), μ = 0.6 pyramid, yaw moment |τ_z| ≤ 0.02 f_z,
  /// unilateral F_z ≥ 0 (the band must be able to reach 0 at lift-off), re-solved at every guard event.
  static ClfQpParams DefaultWalkingControllerParams();
};

struct WalkingDiagram {
  std::unique_ptr<Diagram> diagram;
  HybridContactPlant* plant = nullptr;
  WalkingTrajectorySource* reference = nullptr;
  WalkingOutputReference* outputs = nullptr;
  ClfQpController* controller = nullptr;
};

/// Builds the diagram above. The model must have flat contacts "left_foot" and "right_foot" on links of those names.
WalkingDiagram BuildWalkingDiagram(std::shared_ptr<const MultibodyModel> model, const WalkingPlan& plan,
                                   const WalkingDiagramParams& params = {});

/// One gait of the issue's --gait flags: step length l, T_SSP, T_DSP, step width W.
struct WalkingGait {
  double step_length_m = 0.30, ssp_duration_s = 0.40, dsp_duration_s = 0.10, step_width_m = 0.25;  ///< gait A (spec §3.1)
};

/// The ROM plan of the stand-to-walk scenario (spec §0): the periodic aSLIP gait (Eq. (4)-(5), seed `seed`), the
/// standing → gait transition (footed aSLIP Eq. (9)-(10), the right foot lifts; footed H-LIP QP Eq. (11)-(15) onto the
/// H-LIP P2 orbit), then `steps` periodic steps, composed into a WalkingPlan. Standing height standing_height_m. NLPs
/// use `cache` if given. zmp_margin_m (ours) shrinks the footed aSLIP's ZMP bounds L_h, L_t of Eq. (10) so that the
/// whole-body controller keeps room on the sole. Default 0: with gait A, 0.015 m already makes the transition NLP
/// infeasible (the standing -> gait A transition uses the whole heel). Throws std::runtime_error naming the problem that failed.
struct WalkingPlanReport {
  double periodic_solve_s = 0, transition_solve_s = 0;
  int periodic_iterations = 0, transition_iterations = 0;
  double periodic_violation = 0, transition_violation = 0;
};
WalkingPlan BuildStandToWalkPlan(const WalkingGait& gait, int steps, std::uint32_t seed, const PlanCache* cache,
                                 WalkingPlanReport* report = nullptr, double standing_height_m = 0.9, double zmp_margin_m = 0.0);

/// A standing configuration for the plan's start: pelvis level with zero yaw, both feet flat on the ground with the
/// ankles at the plan's footholds at t = 0, and the COM at the plan's COM (Newton on the 15 remaining coordinates,
/// from the model's nominal pose). Throws std::runtime_error if it does not converge to 1e-10.
Eigen::VectorXd WalkingStandingPose(const MultibodyModel& model, const WalkingPlan& plan);

}  // namespace rome
