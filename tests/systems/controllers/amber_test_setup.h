#pragma once
// Shared AMBER setups for the task-space QP tests and the controllers benchmark: the model, a single-support
// posture found by Newton iterations (stance foot, COM above it, torso upright, swing foot in the air), and
// the paper's output set of Eq. (19) (torso pitch, COM height, swing-foot x and z).
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "systems/controllers/task_space_tasks.h"
#include "systems/multibody/contact_dynamics.h"

namespace rome::test {

inline std::shared_ptr<const MultibodyModel> LoadRobot(const std::string& robot) {
  return std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromSidecar(std::string(ROME_SOURCE_DIR) + "/robots/" + robot + "/" + robot + ".rome.json"));
}

/// AMBER standing on its left foot at (0, 0) with the COM straight above it, the torso upright and the right
/// foot at (swing_x, swing_z). Minimum-norm Newton steps from the nominal pose.
inline Eigen::VectorXd AmberSingleSupportPose(const MultibodyModel& model, double swing_x = 0.12, double swing_z = 0.08) {
  MultibodyWorkspace ws(model);
  const int lf = model.ContactIndex("left_foot"), rf = model.ContactIndex("right_foot");
  const ContactInfo& L = model.contacts()[lf];
  const ContactInfo& R = model.contacts()[rf];
  Eigen::VectorXd q = model.q_nominal();
  Eigen::MatrixXd J3(3, model.nv()), C(6, model.nv());
  Eigen::VectorXd c(6);
  for (int it = 0; it < 50; ++it) {
    const Eigen::Vector3d pl = CalcPointPosition(model, ws, q, L.body, L.frame_origin);
    const Eigen::Vector3d pr = CalcPointPosition(model, ws, q, R.body, R.frame_origin);
    const Eigen::Vector3d com = CalcComPosition(model, ws, q);
    c << pl.x(), pl.z(), com.x() - pl.x(), q[2], pr.x() - swing_x, pr.z() - swing_z;
    if (c.norm() < 1e-13) return q;
    CalcPointJacobian(model, ws, q, L.body, L.frame_origin, J3);
    C.row(0) = J3.row(0);
    C.row(1) = J3.row(2);
    C.row(2) = -J3.row(0);
    CalcComJacobian(model, ws, q, J3);
    C.row(2) += J3.row(0);
    C.row(3) = Eigen::RowVectorXd::Unit(model.nv(), 2);
    CalcPointJacobian(model, ws, q, R.body, R.frame_origin, J3);
    C.row(4) = J3.row(0);
    C.row(5) = J3.row(2);
    q -= C.completeOrthogonalDecomposition().solve(c);
  }
  throw std::runtime_error("AmberSingleSupportPose: Newton did not converge, residual " + std::to_string(c.norm()));
}

/// AMBER in double support with the feet `stance_width` apart (left behind, right ahead), the COM midway
/// between them and the torso upright. Minimum-norm Newton steps from the nominal pose (legs are symmetric).
inline Eigen::VectorXd AmberDoubleSupportPose(const MultibodyModel& model, double stance_width = 0.3) {
  MultibodyWorkspace ws(model);
  const ContactInfo& L = model.contacts()[model.ContactIndex("left_foot")];
  const ContactInfo& R = model.contacts()[model.ContactIndex("right_foot")];
  Eigen::VectorXd q = model.q_nominal();
  Eigen::MatrixXd J3(3, model.nv()), C(6, model.nv());
  Eigen::VectorXd c(6);
  for (int it = 0; it < 50; ++it) {
    const Eigen::Vector3d pl = CalcPointPosition(model, ws, q, L.body, L.frame_origin);
    const Eigen::Vector3d pr = CalcPointPosition(model, ws, q, R.body, R.frame_origin);
    const Eigen::Vector3d com = CalcComPosition(model, ws, q);
    c << pl.x() + stance_width / 2, pl.z(), pr.x() - stance_width / 2, pr.z(), com.x(), q[2];
    if (c.norm() < 1e-13) return q;
    CalcPointJacobian(model, ws, q, L.body, L.frame_origin, J3);
    C.row(0) = J3.row(0);
    C.row(1) = J3.row(2);
    CalcPointJacobian(model, ws, q, R.body, R.frame_origin, J3);
    C.row(2) = J3.row(0);
    C.row(3) = J3.row(2);
    CalcComJacobian(model, ws, q, J3);
    C.row(4) = J3.row(0);
    C.row(5) = Eigen::RowVectorXd::Unit(model.nv(), 2);
    q -= C.completeOrthogonalDecomposition().solve(c);
  }
  throw std::runtime_error("AmberDoubleSupportPose: Newton did not converge, residual " + std::to_string(c.norm()));
}

/// The paper's outputs (Eq. (19)): torso pitch, COM height, swing-foot (right foot) x and z; ny = 4.
inline std::vector<std::shared_ptr<const TaskSpaceTask>> AmberWalkingTasks(const MultibodyModel& model, TaskGains gains = {}) {
  return {std::make_shared<BodyPitchTask>("torso_pitch", model, "torso", gains), std::make_shared<ComPositionTask>("com_z", std::vector<Axis>{Axis::kZ}, gains),
          PointPositionTask::ForContact("swing_foot", model, "right_foot", {Axis::kX, Axis::kZ}, gains)};
}

/// Stacked current values of the tasks at q (v only enters J̇q̇).
inline Eigen::VectorXd TaskValues(const MultibodyModel& model, const std::vector<std::shared_ptr<const TaskSpaceTask>>& tasks, const Eigen::VectorXd& q,
                                  const Eigen::VectorXd& v, Eigen::MatrixXd* J_out = nullptr, Eigen::VectorXd* Jdq_out = nullptr) {
  MultibodyWorkspace ws(model);
  int ny = 0;
  for (const auto& t : tasks) ny += t->size();
  Eigen::VectorXd y(ny), Jdq(ny);
  Eigen::MatrixXd J(ny, model.nv());
  int off = 0;
  for (const auto& t : tasks) {
    t->Calc(model, ws, q, v, y.segment(off, t->size()), J.middleRows(off, t->size()), Jdq.segment(off, t->size()));
    off += t->size();
  }
  if (J_out) *J_out = J;
  if (Jdq_out) *Jdq_out = Jdq;
  return y;
}

}  // namespace rome::test
