#include "systems/controllers/task_space_tasks.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rome {

namespace {
// The index in q of `joint`'s coordinate; a twist entry of a quaternion base has none.
int JointPositionIndex(const std::string& task, const MultibodyModel& model, const std::string& joint) {
  const int i = model.VelocityIndex(joint), p = model.PositionIndexOfVelocity(i);
  if (p < 0)
    throw std::invalid_argument("task '" + task + "': joint '" + joint + "' of robot '" + model.name() +
                                "' is a twist entry of its quaternion free-flyer base and has no coordinate (track the "
                                "base with BodyEulerAngleTask, BodyOrientationTask or a position task)");
  return p;
}

void CheckAxes(const std::string& task, const std::vector<Axis>& axes) {
  if (axes.empty()) throw std::invalid_argument("task '" + task + "': no axes given");
  for (size_t i = 0; i < axes.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (axes[i] == axes[j])
        throw std::invalid_argument("task '" + task + "': axis " + std::to_string(static_cast<int>(axes[i])) +
                                    " is listed twice");
}
}  // namespace

TaskSpaceTask::TaskSpaceTask(std::string name, int size, TaskGains gains, std::vector<int> active_modes)
    : name_(std::move(name)), size_(size), gains_(gains), active_modes_(std::move(active_modes)) {
  if (size_ <= 0)
    throw std::invalid_argument("task '" + name_ + "': size " + std::to_string(size_) + " must be positive");
  if (!(gains_.weight >= 0.0) || !std::isfinite(gains_.weight))
    throw std::invalid_argument("task '" + name_ + "': weight " + std::to_string(gains_.weight) +
                                " must be finite and >= 0");
  if (!std::isfinite(gains_.kp) || !std::isfinite(gains_.kd))
    throw std::invalid_argument("task '" + name_ + "': gains kp = " + std::to_string(gains_.kp) +
                                ", kd = " + std::to_string(gains_.kd) + " must be finite");
  for (int m : active_modes_)
    if (m < 0)
      throw std::invalid_argument("task '" + name_ + "': active mode index " + std::to_string(m) + " is negative");
}

bool TaskSpaceTask::IsActiveIn(int mode) const {
  return active_modes_.empty() || std::find(active_modes_.begin(), active_modes_.end(), mode) != active_modes_.end();
}

void TaskSpaceTask::Calc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
                         Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
                         Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const {
  if (q.size() != model.nq() || v.size() != model.nv())
    throw std::invalid_argument("task '" + name_ + "': Calc got q of size " + std::to_string(q.size()) +
                                " and v of size " + std::to_string(v.size()) + "; robot '" + model.name() +
                                "' has nq = " + std::to_string(model.nq()) + ", nv = " + std::to_string(model.nv()));
  if (y.size() != size_ || J.rows() != size_ || J.cols() != model.nv() || Jdot_qdot.size() != size_)
    throw std::invalid_argument("task '" + name_ + "': Calc outputs have sizes y " + std::to_string(y.size()) + ", J " +
                                std::to_string(J.rows()) + "x" + std::to_string(J.cols()) + ", Jdot_qdot " +
                                std::to_string(Jdot_qdot.size()) + "; expected " + std::to_string(size_) +
                                " and nv = " + std::to_string(model.nv()));
  DoCalc(model, ws, q, v, y, J, Jdot_qdot);
}

// ---------------------------------------------------------------------------------------------------------

ComPositionTask::ComPositionTask(std::string name, std::vector<Axis> axes, TaskGains gains,
                                 std::vector<int> active_modes)
    : TaskSpaceTask(std::move(name), static_cast<int>(axes.size()), gains, std::move(active_modes)),
      axes_(std::move(axes)) {
  CheckAxes(this->name(), axes_);
}

void ComPositionTask::DoCalc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                             const VectorRef& v, Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
                             Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const {
  const Eigen::Vector3d p = CalcComPosition(model, ws, q);
  const Eigen::Vector3d a = CalcComJdotQdot(model, ws, q, v);
  auto J3 = ws.J_point.topRows(3);
  CalcComJacobian(model, ws, q, J3);
  for (int i = 0; i < size(); ++i) {
    const int k = static_cast<int>(axes_[i]);
    y[i] = p[k];
    J.row(i) = J3.row(k);
    Jdot_qdot[i] = a[k];
  }
}

// ---------------------------------------------------------------------------------------------------------

BodyPitchTask::BodyPitchTask(std::string name, const MultibodyModel& model, const std::string& body, TaskGains gains,
                             std::vector<int> active_modes)
    : TaskSpaceTask(std::move(name), 1, gains, std::move(active_modes)) {
  if (!model.is_planar())
    throw std::invalid_argument("task '" + this->name() + "': BodyPitchTask needs a planar model; robot '" +
                                model.name() + "' has a " + ToString(model.floating_base()) + " floating base");
  body_ = model.BodyIndex(body);
  if (model.HasFrame(body)) {
    const Eigen::Matrix3d& R = model.Frame(body).X_body_frame.linear();
    if (std::abs(R(1, 1) - 1.0) > 1e-12)
      throw std::invalid_argument("task '" + this->name() + "': link '" + body + "' is welded to body '" +
                                  model.body(body_).name + "' with a rotation that is not about y");
    pitch_offset_ = std::atan2(R(0, 2), R(0, 0));
  }
}

void BodyPitchTask::DoCalc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
                           Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
                           Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const {
  ws.SetPositions(model, q);
  // R_y(θ) = [[c, 0, s], [0, 1, 0], [−s, 0, c]].
  const Eigen::Matrix3d& R = ws.R_world_link(body_);
  y[0] = std::atan2(R(0, 2), R(0, 0)) + pitch_offset_;
  auto J6 = ws.J_point.topRows(6);
  CalcFrameJacobian(model, ws, q, body_, Eigen::Vector3d::Zero(), J6);
  J.row(0) = J6.row(1);  // ω_y
  Jdot_qdot[0] = CalcFrameJdotQdot(model, ws, q, v, body_, Eigen::Vector3d::Zero())[1];
}

// ---------------------------------------------------------------------------------------------------------

PointPositionTask::PointPositionTask(std::string name, const MultibodyModel& model, const std::string& body,
                                     const Eigen::Vector3d& p_link, std::vector<Axis> axes, TaskGains gains,
                                     std::vector<int> active_modes)
    : TaskSpaceTask(std::move(name), static_cast<int>(axes.size()), gains, std::move(active_modes)),
      body_(model.BodyIndex(body)),
      p_link_(model.HasFrame(body) ? Eigen::Vector3d(model.Frame(body).X_body_frame * p_link) : p_link),
      axes_(std::move(axes)) {
  CheckAxes(this->name(), axes_);
}

std::shared_ptr<PointPositionTask> PointPositionTask::ForContact(std::string name, const MultibodyModel& model,
                                                                 const std::string& contact, std::vector<Axis> axes,
                                                                 TaskGains gains, std::vector<int> active_modes) {
  const ContactInfo& c = model.contacts()[model.ContactIndex(contact)];
  // frame_origin is in the body frame (c.link may have been merged into that body).
  return std::make_shared<PointPositionTask>(std::move(name), model, model.body(c.body).name, c.frame_origin,
                                             std::move(axes), gains, std::move(active_modes));
}

void PointPositionTask::DoCalc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                               const VectorRef& v, Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
                               Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const {
  const Eigen::Vector3d p = CalcPointPosition(model, ws, q, body_, p_link_);
  const Eigen::Vector3d a = CalcPointJdotQdot(model, ws, q, v, body_, p_link_);
  auto J3 = ws.J_point.topRows(3);
  CalcPointJacobian(model, ws, q, body_, p_link_, J3);
  for (int i = 0; i < size(); ++i) {
    const int k = static_cast<int>(axes_[i]);
    y[i] = p[k];
    J.row(i) = J3.row(k);
    Jdot_qdot[i] = a[k];
  }
}

// ---------------------------------------------------------------------------------------------------------

JointPositionTask::JointPositionTask(std::string name, const MultibodyModel& model, const std::string& joint,
                                     TaskGains gains, std::vector<int> active_modes)
    : TaskSpaceTask(std::move(name), 1, gains, std::move(active_modes)),
      index_(model.VelocityIndex(joint)),
      q_index_(JointPositionIndex(this->name(), model, joint)) {}

void JointPositionTask::DoCalc(const MultibodyModel&, MultibodyWorkspace&, const VectorRef& q, const VectorRef&,
                               Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
                               Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const {
  y[0] = q[q_index_];
  J.setZero();
  J(0, index_) = 1.0;
  Jdot_qdot[0] = 0.0;
}

JointFunctionTask::JointFunctionTask(std::string name, const MultibodyModel& model, const std::string& joint,
                                     Function function, TaskGains gains, std::vector<int> active_modes,
                                     double second_derivative_step)
    : TaskSpaceTask(std::move(name), 1, gains, std::move(active_modes)),
      index_(model.VelocityIndex(joint)),
      q_index_(JointPositionIndex(this->name(), model, joint)),
      function_(std::move(function)),
      step_(second_derivative_step) {
  if (!function_) throw std::invalid_argument("task '" + this->name() + "': no function given");
  if (!(step_ > 0.0) || !std::isfinite(step_))
    throw std::invalid_argument("task '" + this->name() + "': second_derivative_step = " + std::to_string(step_) +
                                " must be positive");
}

void JointFunctionTask::DoCalc(const MultibodyModel&, MultibodyWorkspace&, const VectorRef& q, const VectorRef& v,
                               Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
                               Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const {
  const double qi = q[q_index_];
  double value = 0.0, slope = 0.0, unused = 0.0, slope_plus = 0.0, slope_minus = 0.0;
  function_(qi, &value, &slope);
  function_(qi + step_, &unused, &slope_plus);
  function_(qi - step_, &unused, &slope_minus);
  y[0] = value;
  J.setZero();
  J(0, index_) = slope;
  Jdot_qdot[0] = (slope_plus - slope_minus) / (2.0 * step_) * v[index_] * v[index_];
}

// ---------------------------------------------------------------------------------------------------------

BodyOrientationTask::BodyOrientationTask(std::string name, const MultibodyModel& model, const std::string& body,
                                         TaskGains gains, std::vector<int> active_modes)
    : TaskSpaceTask(std::move(name), 3, gains, std::move(active_modes)), body_(model.BodyIndex(body)) {
  if (model.is_planar())
    throw std::invalid_argument("task '" + this->name() + "': BodyOrientationTask needs a 3D model; robot '" +
                                model.name() + "' is planar");
  if (model.HasFrame(body)) R_body_link_ = model.Frame(body).X_body_frame.linear();
}

void BodyOrientationTask::DoCalc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                 const VectorRef& v, Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
                                 Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const {
  ws.SetPositions(model, q);
  const Eigen::Matrix3d R = ws.R_world_link(body_) * R_body_link_;
  const Eigen::AngleAxisd aa(R);
  y = aa.angle() * aa.axis();
  auto J6 = ws.J_point.topRows(6);
  CalcFrameJacobian(model, ws, q, body_, Eigen::Vector3d::Zero(), J6);
  J = J6.topRows(3);  // ω (world): the same for every frame on the body
  Jdot_qdot = CalcFrameJdotQdot(model, ws, q, v, body_, Eigen::Vector3d::Zero()).head<3>();
}

// ---------------------------------------------------------------------------------------------------------

BodyEulerAngleTask::BodyEulerAngleTask(std::string name, const MultibodyModel& model, const std::string& body,
                                       EulerAngle angle, TaskGains gains, std::vector<int> active_modes,
                                       double singularity_margin_rad)
    : TaskSpaceTask(std::move(name), 1, gains, std::move(active_modes)),
      body_(model.BodyIndex(body)),
      angle_(angle),
      margin_(singularity_margin_rad) {
  if (model.is_planar())
    throw std::invalid_argument("task '" + this->name() + "': BodyEulerAngleTask needs a 3D model; robot '" +
                                model.name() + "' is planar");
  if (!(margin_ > 0.0 && margin_ < M_PI / 2))
    throw std::invalid_argument("task '" + this->name() + "': singularity_margin_rad = " + std::to_string(margin_) +
                                " must be in (0, pi/2)");
  if (model.HasFrame(body)) R_body_link_ = model.Frame(body).X_body_frame.linear();
}

void BodyEulerAngleTask::DoCalc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                const VectorRef& v, Eigen::Ref<Eigen::VectorXd> y, Eigen::Ref<Eigen::MatrixXd> J,
                                Eigen::Ref<Eigen::VectorXd> Jdot_qdot) const {
  ws.SetPositions(model, q);
  const Eigen::Matrix3d R = ws.R_world_link(body_) * R_body_link_;
  const double yaw = std::atan2(R(1, 0), R(0, 0)), pitch = std::atan2(-R(2, 0), std::hypot(R(0, 0), R(1, 0))),
               roll = std::atan2(R(2, 1), R(2, 2));
  if (std::abs(pitch) > M_PI / 2 - margin_)
    throw std::runtime_error("task '" + name() + "': body '" + model.body(body_).name + "' pitch " +
                             std::to_string(pitch) + " rad is within singularity_margin_rad = " +
                             std::to_string(margin_) + " of +-pi/2 (ZYX angles are singular there)");
  const double cy = std::cos(yaw), sy = std::sin(yaw), cp = std::cos(pitch), sp = std::sin(pitch);
  Eigen::Matrix3d E;  // ω = E (roll, pitch, yaw)'
  E.col(0) << cy * cp, sy * cp, -sp;
  E.col(1) << -sy, cy, 0.0;
  E.col(2) << 0.0, 0.0, 1.0;
  const Eigen::Matrix3d E_inv = E.inverse();
  auto J6 = ws.J_point.topRows(6);
  CalcFrameJacobian(model, ws, q, body_, Eigen::Vector3d::Zero(), J6);
  const auto J_w = J6.topRows(3);  // ω (world): the same for every frame on the body
  Eigen::Vector3d omega;
  omega.noalias() = J_w * v;  // into a fixed-size vector: no temporary on the heap
  const Eigen::Vector3d eta_dot = E_inv * omega;
  const double droll = eta_dot[0], dpitch = eta_dot[1], dyaw = eta_dot[2];
  Eigen::Vector3d E_dot_eta_dot;
  E_dot_eta_dot << droll * (-sy * cp * dyaw - cy * sp * dpitch) - dpitch * cy * dyaw,
      droll * (cy * cp * dyaw - sy * sp * dpitch) - dpitch * sy * dyaw, -droll * cp * dpitch;
  const Eigen::Vector3d bias = CalcFrameJdotQdot(model, ws, q, v, body_, Eigen::Vector3d::Zero()).head<3>();
  const int k = static_cast<int>(angle_);
  y[0] = k == 0 ? roll : (k == 1 ? pitch : yaw);
  J.row(0).noalias() = E_inv.row(k) * J_w;
  Jdot_qdot[0] = E_inv.row(k).dot(bias - E_dot_eta_dot);
}

std::shared_ptr<TaskSpaceTask> MakeBaseAngleTask(std::string name, const MultibodyModel& model, EulerAngle angle,
                                                 TaskGains gains, std::vector<int> active_modes) {
  if (model.has_quaternion_base())
    return std::make_shared<BodyEulerAngleTask>(std::move(name), model, model.body(0).name, angle, gains,
                                                std::move(active_modes));
  if (model.floating_base() != FloatingBaseType::kSpatial)
    throw std::invalid_argument("task '" + name + "': robot '" + model.name() + "' has a " + model.base_kind() +
                                " base; a base angle task needs a spatial floating base");
  static const char* const kCoordinates[3] = {"base_roll", "base_pitch", "base_yaw"};
  return std::make_shared<JointPositionTask>(std::move(name), model, kCoordinates[static_cast<int>(angle)], gains,
                                             std::move(active_modes));
}

}  // namespace rome
