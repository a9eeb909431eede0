#pragma once
// QuaternionToEulerState: the state of a plant on the quaternion free-flyer base, as the state of the same robot on
// the ZYX-Euler base, for the controllers, planners, references and loggers that are written for the Euler state
// (nq = nv, x = [q; dq/dt]). Issue 43: the plant runs on the quaternion model, the rest of a diagram on the Euler one.
//
// inputs:  quaternion_state (nv + 1 + nv)  [q; v] of the quaternion model (multibody_model.h, free_flyer.h):
//            q = [p (m); qw, qx, qy, qz; joints (rad or m)], v = [v_B (m/s); w_B (rad/s); joint rates]
//            with v_B = R^T dp/dt and w_B the angular velocity, both in BASE axes
// outputs: state (2 nv)                    [q; v] of the Euler model:
//            q = [x, y, z (m); yaw, pitch, roll (rad); joints], v = dq/dt = [dp/dt (world, m/s); d(yaw, pitch,
//            roll)/dt (rad/s); joint rates]; element names as the Euler plant's state (StateElementNames)
// Conventions: R_world_base = Rz(yaw) Ry(pitch) Rx(roll) (the Euler model's chain x, y, z, yaw, pitch, roll; the
//   quaternion is R's, w first). The map returns pitch in [-pi/2, pi/2] and yaw, roll in (-pi, pi]: the Euler model's
//   yaw is a free real, so a robot that turns through +-pi appears with a jump of 2 pi in yaw (the block keeps no
//   state to unwrap it). Body rates to ZYX rates (singular at pitch = +-pi/2):
//     dyaw = (sin(roll) w_y + cos(roll) w_z) / cos(pitch),  dpitch = cos(roll) w_y - sin(roll) w_z,
//     droll = w_x + sin(pitch) dyaw.
//   The output refuses (throws, naming the pitch) a pitch within EulerStateParams::singularity_margin_rad of +-90 deg.
// The inverse map (EulerStateToQuaternion, for initial states and resets) is defined everywhere and returns the
// quaternion with w >= 0.
// The joint coordinates and rates pass through unchanged: the quaternion model keeps the Euler model's joints and
// their order after the base (MultibodyModelLoader::UseQuaternionBase).
#include <memory>
#include <string>

#include <Eigen/Core>

#include "framework/system.h"
#include "systems/multibody/multibody_model.h"

namespace rome {

/// Which base the plant of a diagram runs on (the walking and hopping diagrams run their controller on it too); the
/// planners, references and loggers keep the Euler model either way.
enum class PlantBase { kEuler, kQuaternion };
/// "euler" or "quaternion".
const char* ToString(PlantBase base);
/// Parses "euler" or "quaternion"; otherwise throws std::invalid_argument("<what> <text>: unknown base (euler or
/// quaternion)").
PlantBase ParsePlantBase(const std::string& text, const std::string& what);

struct EulerStateParams {
  /// [rad] The map to Euler coordinates refuses |pitch| > pi/2 - this. Ours: within it the ZYX rates amplify the body
  /// rates by up to 1/sin(margin) = 100 and the yaw/roll split of R loses two digits; a legged robot's pelvis that
  /// pitches to 89.4 deg has fallen.
  double singularity_margin_rad = 1e-2;
  /// Throws std::invalid_argument naming the field and value unless 0 < margin < pi/2.
  void Validate() const;
};

/// The Euler state x_e = [x, y, z, yaw, pitch, roll, joints; their time derivatives] (2 nv) of the quaternion state
/// x_q = [p, quat, joints; v_B, w_B, joint rates] (2 nv + 1), nv = (x_q.size() - 1) / 2. The quaternion need not be
/// unit (it is normalised; a zero or non-finite one throws). Throws std::invalid_argument("QuaternionStateToEuler:
/// pitch = ... rad is within singularity_margin_rad = ... of +-pi/2 ...") near the singularity.
void QuaternionStateToEuler(const Eigen::Ref<const Eigen::VectorXd>& x_q, const EulerStateParams& params,
                            Eigen::Ref<Eigen::VectorXd> x_e);
/// The inverse: the quaternion state (2 nv + 1) of an Euler state (2 nv), quaternion with w >= 0.
void EulerStateToQuaternion(const Eigen::Ref<const Eigen::VectorXd>& x_e, Eigen::Ref<Eigen::VectorXd> x_q);
/// Only the configurations: q_q (nv + 1) of q_e (nv).
Eigen::VectorXd EulerConfigurationToQuaternion(const Eigen::VectorXd& q_e);

/// The quaternion-base twin of an Euler-base model: the same URDF and sidecar (MultibodyModel::Load with
/// LoadOptions::quaternion_floating_base). Throws std::invalid_argument naming the robot if `euler` is not a spatial
/// Euler base or was not loaded from files; CheckEulerQuaternionTwins on the result.
std::shared_ptr<const MultibodyModel> LoadQuaternionTwin(const MultibodyModel& euler);
/// Throws std::invalid_argument("<user>: ...") unless `euler` has a spatial Euler base, `quaternion` the quaternion
/// base, both the same nv and the same joint names after the base.
void CheckEulerQuaternionTwins(const MultibodyModel& euler, const MultibodyModel& quaternion, const std::string& user);

class QuaternionToEulerState final : public LeafSystem {
 public:
  /// Throws as CheckEulerQuaternionTwins and EulerStateParams::Validate, naming the system.
  QuaternionToEulerState(std::string name, std::shared_ptr<const MultibodyModel> euler,
                         std::shared_ptr<const MultibodyModel> quaternion, EulerStateParams params = {});
  const EulerStateParams& params() const { return params_; }

 private:
  EulerStateParams params_;
};

}  // namespace rome
