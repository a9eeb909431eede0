#pragma once
// Tasks (outputs to track) for the task-space QP controller (task_space_qp_controller.h).
//
// A task is a relative-degree-two output y(q) of the robot (stepping-stones paper, Eq. (19)): it reports
//   y (size),  J_y = ∂y/∂q (size × nv),  J̇_y q̇ (size),
// so that ÿ = J_y q̈ + J̇_y q̇ (Eq. (29)). The controller asks for the PD output dynamics
//   ÿ* = ÿ_d + Kp (y_d − y) + Kd (ẏ_d − J_y q̇)
// and penalises weight · ||ÿ − ÿ*||² (Eq. (30)). Each task carries its own gains and weight (TaskGains) and
// the contact modes it is active in (a swing-foot task only in the single-support mode of the other foot).
//
// Concrete tasks (all world frame, SI units):
//   ComPositionTask     p_com along the chosen axes [m]
//   BodyPitchTask       pitch of a body about world +y [rad] (planar models; the torso angle φ_torso)
//   PointPositionTask   position of a point fixed on a body along the chosen axes [m] (e.g. the swing foot);
//                       ForContact() places it at a contact's frame origin
//   JointPositionTask   one generalized coordinate q_i [rad or m]
//   JointFunctionTask   a scalar function f(q_i) of one coordinate, e.g. Cassie's virtual leg length L(q_knee)
//                       (hopping paper Eq. (13)) [the function's unit]
//   BodyOrientationTask orientation of a body in 3D as the rotation vector log(R_world_body) [rad] (target 0 = the
//                       body aligned with the world: a flat foot with zero yaw, walking paper Eq. (17)); ẏ is taken
//                       as the world angular velocity ω, exact at y = 0 (the error of d/dt log R is O(|y| |ω|))
//   BodyEulerAngleTask  one ZYX Euler angle (roll, pitch or yaw) of a body on any 3D base [rad]; on a ZYX-Euler base
//                       the root link's angles are its coordinates base_roll, base_pitch, base_yaw
// Tasks are immutable after construction (names are resolved against the model then) and may be shared
// between controllers; all scratch lives in the MultibodyWorkspace handed to Calc (no heap allocation).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "systems/multibody/multibody_kinematics.h"

namespace rome {

/// PD gains and cost weight of one task (the same for every row of the task).
struct TaskGains {
  double weight = 1.0;  ///< [-] weight of ||ÿ − ÿ*||² in the QP cost (Eq. (30) uses 1 for every output).
  double kp = 100.0;  ///< [1/s²] Kp of ÿ* (the paper gives no values; 100 with kd 20 is critically damped, 10 rad/s).
  double kd = 20.0;   ///< [1/s] Kd of ÿ*.
};

enum class Axis { kX = 0, kY = 1, kZ = 2 };

class TaskSpaceTask {
 public:
  /// `active_modes`: indices of the plant's contact modes in which the task is tracked (empty = all modes).
  TaskSpaceTask(std::string name, int size, TaskGains gains, std::vector<int> active_modes = {});
  virtual ~TaskSpaceTask() = default;
  TaskSpaceTask(const TaskSpaceTask&) = delete;
  TaskSpaceTask& operator=(const TaskSpaceTask&) = delete;

  const std::string& name() const { return name_; }
  int size() const { return size_; }
  const TaskGains& gains() const { return gains_; }
  const std::vector<int>& active_modes() const { return active_modes_; }
  bool IsActiveIn(int mode) const;

  /// y (size), J (size × nv) and J̇q̇ (size) at (q, v). The outputs are preallocated by the caller; the
  /// workspace's J_point scratch may be overwritten. Throws std::invalid_argument on wrong sizes.
  void Calc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
            Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J, Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const;

 protected:
  virtual void DoCalc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
                      Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
                      Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const = 0;

 private:
  std::string name_;
  int size_;
  TaskGains gains_;
  std::vector<int> active_modes_;
};

/// Centre of mass position along `axes` (e.g. {Axis::kZ} for the paper's p_com^z).
class ComPositionTask final : public TaskSpaceTask {
 public:
  ComPositionTask(std::string name, std::vector<Axis> axes, TaskGains gains = {}, std::vector<int> active_modes = {});

 private:
  void DoCalc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
              Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
              Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const override;
  std::vector<Axis> axes_;
};

/// Pitch angle θ of a body about world +y, θ ∈ (−π, π] (R_world_body = R_y(θ) in a planar model). For the
/// root link of a planar floating base this is q[2]. Planar models only (the error names the model).
class BodyPitchTask final : public TaskSpaceTask {
 public:
  /// `body` may be any URDF link; a link merged into a body through a fixed joint adds its fixed pitch
  /// offset (its fixed rotation must be about y, else std::invalid_argument).
  BodyPitchTask(std::string name, const MultibodyModel& model, const std::string& body, TaskGains gains = {},
                std::vector<int> active_modes = {});

 private:
  void DoCalc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
              Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
              Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const override;
  int body_;
  double pitch_offset_ = 0.0;  // pitch of the link frame in the body frame (merged links)
};

/// World position of the point `p_link` (body frame) along `axes`.
class PointPositionTask final : public TaskSpaceTask {
 public:
  /// p_link is in the frame of link `body` (any URDF link, also one merged through a fixed joint).
  PointPositionTask(std::string name, const MultibodyModel& model, const std::string& body,
                    const Eigen::Vector3d& p_link, std::vector<Axis> axes, TaskGains gains = {},
                    std::vector<int> active_modes = {});
  /// The frame origin of contact `contact` (e.g. the swing foot "right_foot").
  static std::shared_ptr<PointPositionTask> ForContact(std::string name, const MultibodyModel& model,
                                                       const std::string& contact, std::vector<Axis> axes,
                                                       TaskGains gains = {}, std::vector<int> active_modes = {});

 private:
  void DoCalc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
              Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
              Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const override;
  int body_;
  Eigen::Vector3d p_link_;  // in the body frame (a link merged through a fixed joint is converted)
  std::vector<Axis> axes_;
};

/// One generalized coordinate q[i] of the joint `joint` (or a coordinate of a ZYX-Euler base such as "base_pitch"). On
/// a quaternion free-flyer base the joint's position is q[i + 1] (J's column stays i); the base's twist entries
/// ("base_vx" ... "base_wz") have no coordinate and are refused (std::invalid_argument naming the task and the joint:
/// track the base with BodyEulerAngleTask, BodyOrientationTask, ComPositionTask or PointPositionTask).
class JointPositionTask final : public TaskSpaceTask {
 public:
  JointPositionTask(std::string name, const MultibodyModel& model, const std::string& joint, TaskGains gains = {},
                    std::vector<int> active_modes = {});

 private:
  void DoCalc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
              Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
              Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const override;
  int index_;    // in v
  int q_index_;  // in q
};

/// y = f(q_i), a scalar function of the generalized coordinate of `joint` (hopping paper Eq. (13): the virtual leg
/// length L(q_knee) of Cassie, whose rod closure at zero spring deflection makes it a function of the knee alone).
/// J = f'(q_i) e_iᵀ; J̇ q̇ = f''(q_i) q̇_i², with f'' a central difference of f' (step second_derivative_step).
/// The function must be smooth (C¹, piecewise C²) near the operating range and must not allocate. Any base (the
/// joint's position index as JointPositionTask's).
class JointFunctionTask final : public TaskSpaceTask {
 public:
  /// Writes f(q) and f'(q).
  using Function = std::function<void(double q, double* value, double* derivative)>;
  JointFunctionTask(std::string name, const MultibodyModel& model, const std::string& joint, Function function,
                    TaskGains gains = {}, std::vector<int> active_modes = {}, double second_derivative_step = 1e-5);

 private:
  void DoCalc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
              Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
              Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const override;
  int index_;    // in v
  int q_index_;  // in q
  Function function_;
  double step_;
};

/// Orientation of a body as the rotation vector log(R_world_body) [rad], with J = the world angular-velocity Jacobian
/// (3D models; see the header for the small-angle reading of ẏ).
class BodyOrientationTask final : public TaskSpaceTask {
 public:
  BodyOrientationTask(std::string name, const MultibodyModel& model, const std::string& body, TaskGains gains = {},
                      std::vector<int> active_modes = {});

 private:
  void DoCalc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
              Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
              Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const override;
  int body_;
  Eigen::Matrix3d R_body_link_ = Eigen::Matrix3d::Identity();  // a link merged through a fixed joint
};

/// One ZYX Euler angle of a body, R_world_body = Rz(yaw) Ry(pitch) Rx(roll) [rad], from the body's rotation: on any 3D
/// base (the quaternion free-flyer included). On a ZYX-Euler floating base the root link's angles are the coordinates
/// base_yaw, base_pitch, base_roll, and the task equals a JointPositionTask on them (value, J, J̇q̇) to rounding.
/// Principal values: pitch in [−π/2, π/2], yaw and roll in (−π, π] (a body turning through ±π jumps by 2π).
/// With η = (roll, pitch, yaw) and the world angular velocity ω = E(η) η̇, E = [Rz Ry e_x, Rz e_y, e_z]:
///   J = E⁻¹ J_ω (row of the angle),  J̇q̇ = E⁻¹ (J̇_ω q̇ − Ė η̇).
/// E is singular at pitch = ±π/2: Calc throws std::runtime_error naming the task, the body and the pitch within
/// singularity_margin_rad of it.
enum class EulerAngle { kRoll = 0, kPitch = 1, kYaw = 2 };
class BodyEulerAngleTask final : public TaskSpaceTask {
 public:
  /// Throws std::invalid_argument for a planar model, an unknown body, or a margin outside (0, π/2).
  BodyEulerAngleTask(std::string name, const MultibodyModel& model, const std::string& body, EulerAngle angle,
                     TaskGains gains = {}, std::vector<int> active_modes = {}, double singularity_margin_rad = 1e-2);

 private:
  void DoCalc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
              Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
              Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const override;
  int body_;
  EulerAngle angle_;
  double margin_;
  Eigen::Matrix3d R_body_link_ = Eigen::Matrix3d::Identity();  // a link merged through a fixed joint
};

/// The floating base's ZYX angle `angle` on either spatial base: a JointPositionTask on the coordinate base_roll,
/// base_pitch or base_yaw of a ZYX-Euler base, a BodyEulerAngleTask of the root link on the quaternion free-flyer (the
/// same value, and the same ÿ for the same motion). Throws std::invalid_argument for another base.
std::shared_ptr<TaskSpaceTask> MakeBaseAngleTask(std::string name, const MultibodyModel& model, EulerAngle angle,
                                                 TaskGains gains = {}, std::vector<int> active_modes = {});

}  // namespace rome
