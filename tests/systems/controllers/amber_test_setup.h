#pragma once
// Shared setups for the controller tests and the controllers benchmark: LoadRobot, a generic Euler-base state, and for
// AMBER a single-support posture found by SolvePose (stance foot, COM above it, torso upright, swing foot in the air)
// and the paper's output set of Eq. (19) (torso pitch, COM height, swing-foot x and z).
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "systems/controllers/task_space_tasks.h"
#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/pose_constraints.h"
#include "tests/common/source_path.h"

namespace rome::test {

inline std::shared_ptr<const MultibodyModel> LoadRobot(const std::string& robot) {
  return std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("robots/" + robot + "/" + robot + ".rome.json"), {.euler_floating_base = true}));
}

/// A generic state of a robot on the ZYX-Euler base: its nominal pose turned (yaw 0.4 rad) and tilted (`pitch`,
/// `roll` [rad]), with every coordinate moving (rate 0.3 sin(1.7 i + 0.5) of coordinate i), so that no contact holds.
inline Eigen::VectorXd GenericEulerState(const MultibodyModel& euler, double pitch, double roll) {
  const int nv = euler.nv();
  Eigen::VectorXd x(2 * nv);
  x.head(nv) = euler.q_nominal();
  x[euler.VelocityIndex("base_yaw")] = 0.4;
  x[euler.VelocityIndex("base_pitch")] = pitch;
  x[euler.VelocityIndex("base_roll")] = roll;
  for (int i = 0; i < nv; ++i) x[nv + i] = 0.3 * std::sin(1.7 * i + 0.5);
  return x;
}

/// AMBER standing on its left foot at (0, 0) with the COM straight above it, the torso upright and the right
/// foot at (swing_x, swing_z): SolvePose (minimum-norm Newton steps) from the nominal pose. Joint limits are not
/// imposed: at the default swing point the stance knee is at -0.333 rad (straightened past 0).
inline Eigen::VectorXd AmberSingleSupportPose(const MultibodyModel& model, double swing_x = 0.12,
                                              double swing_z = 0.08) {
  MultibodyWorkspace ws(model);
  return SolvePose(model, ws, model.q_nominal(),
                   {PoseConstraint::ContactPoint(model, "left_foot", 0, 0.0),
                    PoseConstraint::ContactPoint(model, "left_foot", 2, 0.0), PoseConstraint::Com(0, 0.0),
                    PoseConstraint::Coordinate(2, 0.0),  // q[2] = torso pitch
                    PoseConstraint::ContactPoint(model, "right_foot", 0, swing_x),
                    PoseConstraint::ContactPoint(model, "right_foot", 2, swing_z)},
                   {.max_iterations = 50, .tolerance = 1e-13});
}

/// AMBER in double support with the feet `stance_width` apart (left behind, right ahead), the COM midway
/// between them and the torso upright: SolvePose from the nominal pose (legs are symmetric).
inline Eigen::VectorXd AmberDoubleSupportPose(const MultibodyModel& model, double stance_width = 0.3) {
  MultibodyWorkspace ws(model);
  return SolvePose(model, ws, model.q_nominal(),
                   {PoseConstraint::ContactPoint(model, "left_foot", 0, -stance_width / 2),
                    PoseConstraint::ContactPoint(model, "left_foot", 2, 0.0),
                    PoseConstraint::ContactPoint(model, "right_foot", 0, stance_width / 2),
                    PoseConstraint::ContactPoint(model, "right_foot", 2, 0.0), PoseConstraint::Com(0, 0.0),
                    PoseConstraint::Coordinate(2, 0.0)},
                   {.max_iterations = 50, .tolerance = 1e-13});
}

/// The paper's outputs (Eq. (19)): torso pitch, COM height, swing-foot (right foot) x and z; ny = 4.
inline std::vector<std::shared_ptr<const TaskSpaceTask>> AmberWalkingTasks(const MultibodyModel& model,
                                                                           TaskGains gains = {}) {
  return {std::make_shared<BodyPitchTask>("torso_pitch", model, "torso", gains),
          std::make_shared<ComPositionTask>("com_z", std::vector<Axis>{Axis::kZ}, gains),
          PointPositionTask::ForContact("swing_foot", model, "right_foot", {Axis::kX, Axis::kZ}, gains)};
}

/// Stacked current values of the tasks at q (v only enters J̇q̇).
inline Eigen::VectorXd TaskValues(const MultibodyModel& model,
                                  const std::vector<std::shared_ptr<const TaskSpaceTask>>& tasks,
                                  const Eigen::VectorXd& q, const Eigen::VectorXd& v, Eigen::MatrixXd* J_out = nullptr,
                                  Eigen::VectorXd* Jdq_out = nullptr) {
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
