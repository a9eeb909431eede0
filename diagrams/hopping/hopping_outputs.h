#pragma once
// The hopping paper's CLF-QP outputs for Cassie, per domain (Sec. IV-D, Eq. (41)-(44)), as data for ClfQpController.
// Domains are the controller's modes, in ContactModeGraph::JumpFlightLanding order: 0 jump, 1 flight, 2 landing.
//
// Outputs, in this order (the layout of the controller's 'desired' input; MakeHoppingOutputLayout gives the offsets):
//   centroidal_pitch_momentum  RD1  jump             H_pitch = A_pitch(q) q̇ [N m s] (Eq. (38)-(42), y1^J)
//   leg_length_left            RD2  jump, landing    L_L = L(q_knee_left) [m] (Eq. (13), virtual leg length)
//   leg_length_right           RD2  jump, landing    L_R [m]
//   com_xy                     RD2  jump, landing    COM x, y [m] (world; the reference holds the support centre)
//   pelvis_yaw                 RD2  jump, landing    base yaw [rad]
//   pelvis_pitch               RD2  landing          base pitch [rad] (Eq. (44): replaces H_pitch)
//   motors                     RD2  flight           the 10 motor positions [rad] (Eq. (43))
// Jump: 1 + 5 outputs (Eq. (41)-(42), 6 = 16 DOF without tarsi and springs − 10 foot constraints); flight: 10;
// landing: 6. The virtual leg length L(q_knee) is a function argument (the spring-mass ROM owns it, Eq. (13)).
#include <memory>
#include <string>
#include <vector>

#include "systems/controllers/clf_qp_controller.h"
#include "diagrams/hopping/hopping_reference.h"

namespace rome {

struct HoppingDomain {
  static constexpr int kJump = 0, kFlight = 1, kLanding = 2;
};

/// Cost weights of the outputs (ours: the paper weighs every output by 1 in A ubar + L_f).
struct HoppingOutputParams {
  double momentum_weight = 1.0;    ///< [-] H_pitch (its unit, N m s per s, differs from the RD2 rows' m/s²)
  double leg_length_weight = 1.0;  ///< [-]
  double com_weight = 1.0;         ///< [-]
  double pelvis_weight = 1.0;      ///< [-] yaw and pitch
  double motor_weight = 1.0;       ///< [-] flight motor positions
  /// Kp [1/s²], Kd [1/s] of the flight motors' PD target ÿ* (with ClfQpParams::cost_pd_feedback; ours, the
  /// TaskGains default 100, 20: 10 rad/s, critically damped).
  double motor_kp = 100.0, motor_kd = 20.0;
  /// true: Jump tracks H_pitch (Eq. (41)); false: Jump tracks the pelvis pitch as Landing does and the momentum output
  /// is left out (ours, a deviation: docs/design-notes.md#hopping-jump-output).
  bool jump_tracks_momentum = true;
};

/// The outputs above for `model` (Cassie: joints left_/right_ knee etc.; the 10 actuated joints in actuator order),
/// and their offsets in the stacked output vector y (HoppingOutputLayout; momentum = -1 when Jump tracks the pitch).
/// `leg_length(q_knee, &L, &dL/dq_knee)` is Eq. (13).
std::vector<ClfOutput> MakeHoppingOutputs(const MultibodyModel& model, const JointFunctionTask::Function& leg_length,
                                          const HoppingOutputParams& params = {});
HoppingOutputLayout MakeHoppingOutputLayout(const HoppingOutputParams& params = {});

}  // namespace rome
