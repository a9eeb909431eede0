#include "systems/multibody/model_checks.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include <urdf_model/model.h>

#include "framework/text.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_model.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome {

namespace {

std::string Num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", x);
  return buf;
}

std::string Num3(const Eigen::Vector3d& v) { return Num(v[0]) + " " + Num(v[1]) + " " + Num(v[2]); }

}  // namespace

void CheckUrdfIsTree(const urdf::ModelInterface& urdf, const std::string& where) {
  std::map<std::string, std::string> parent_joint;  // child link -> the joint that names it
  for (const auto& [name, joint] : urdf.joints_) {
    if (joint->mimic)
      throw std::runtime_error(where + ": joint '" + Excerpt(name) + "' has <mimic joint='" + Excerpt(joint->mimic->joint_name) +
                               "'>; ROME does not model coupled joints: remove the <mimic> (the joint becomes independent) "
                               "or write the coupling as a loop closure in the sidecar");
    const auto [it, inserted] = parent_joint.emplace(joint->child_link_name, name);
    if (!inserted)
      throw std::runtime_error(where + ": link '" + Excerpt(joint->child_link_name) + "' is the child of two joints ('" + Excerpt(it->second) +
                               "' and '" + Excerpt(name) + "'); a URDF must be a tree: write a closed chain as a loop closure in the sidecar");
  }
}

void WarnUnmodelledUrdfElements(const urdf::ModelInterface& urdf, std::vector<std::string>* warnings) {
  for (const auto& [name, joint] : urdf.joints_) {
    if (joint->dynamics && (joint->dynamics->damping != 0.0 || joint->dynamics->friction != 0.0))
      warnings->push_back("joint '" + Excerpt(name) + "': <dynamics damping=" + Num(joint->dynamics->damping) + " friction=" +
                          Num(joint->dynamics->friction) + "> is not modelled by ROME (ignored; a sidecar spring's damping is)");
    // ROME has no velocity limits; one that could not be meant (negative) is said, not dropped without a word.
    if (joint->limits && !(joint->limits->velocity >= 0.0))
      warnings->push_back("joint '" + Excerpt(name) + "': <limit velocity=" + Num(joint->limits->velocity) +
                          "> is negative; ROME does not model velocity limits (ignored)");
  }
}

Eigen::Vector3d UnitAxis(const Eigen::Vector3d& axis, const std::string& where) {
  if (!axis.allFinite()) throw std::runtime_error(where + ": <axis> " + Num3(axis) + " is not finite");
  const double scale = axis.cwiseAbs().maxCoeff();
  if (!(scale > 0.0)) throw std::runtime_error(where + ": <axis> is zero");
  return (axis / scale).normalized();  // divided first: the squared norm of 1e300 entries would overflow
}

void CheckPlanarJoints(const MultibodyModel& model, const std::string& where) {
  const std::vector<MultibodyBody>& bodies = model.bodies();
  std::vector<Eigen::Matrix3d> R_world(bodies.size());
  for (size_t i = 0; i < bodies.size(); ++i) {
    const MultibodyBody& b = bodies[i];
    R_world[i] = (b.parent >= 0 ? R_world[b.parent] : Eigen::Matrix3d::Identity()) * b.X_parent_joint.linear();
    if (b.is_virtual || b.joint_type == MultibodyJointType::kFixed) continue;
    const Eigen::Vector3d a = R_world[i] * b.axis;
    const bool revolute = b.joint_type == MultibodyJointType::kRevolute;
    const double off_plane = revolute ? std::hypot(a.x(), a.z()) : std::abs(a.y());
    if (off_plane > kPlanarAxisTolerance)
      throw std::runtime_error(where + ": joint '" + Excerpt(b.joint_name) + "' " + (revolute ? "turns about" : "slides along") +
                               " world axis " + Num3(a) + " at q = 0; the robot is planar (x-z plane), so a revolute joint must turn "
                               "about y (0 ±1 0) and a prismatic joint slide in the x-z plane (check its <axis> and the rpy of the "
                               "<origin>s above it)");
  }
}

void CheckNominalPose(const MultibodyModel& model, const std::string& where, const std::vector<bool>& given,
                      std::vector<std::string>* warnings) {
  const Eigen::VectorXd& q = model.q_nominal();
  const int nb = model.num_base_dofs();
  for (int k = nb; k < model.nv(); ++k) {
    const double lo = model.position_lower_limits()[k], hi = model.position_upper_limits()[k];
    const std::string joint = "nominal_pose: joint '" + Excerpt(model.JointName(k)) + "' at " + Num(q[k]);
    const std::string limits = " is outside its limits [" + Num(lo) + ", " + Num(hi) + "]";
    if ((q[k] < lo || q[k] > hi) && given[static_cast<size_t>(k)]) throw std::runtime_error(where + ": " + joint + limits);
    if (q[k] < lo || q[k] > hi)
      warnings->push_back(joint + limits + " (not given in the sidecar's nominal_pose.joints, so 0; give it there)");
    if (model.body(model.BodyOfVelocity(k)).joint_type == MultibodyJointType::kRevolute && std::abs(q[k]) > kMaxJointAngle_rad)
      throw std::runtime_error(where + ": " + joint + " rad is beyond +-" + Num(kMaxJointAngle_rad) + " rad (one turn)");
  }
  if (model.loop_closures().empty()) return;
  MultibodyWorkspace ws(model);
  for (const LoopClosureInfo& l : model.loop_closures()) {
    const double d = (CalcPointPosition(model, ws, q, l.body_a, l.point_a) - CalcPointPosition(model, ws, q, l.body_b, l.point_b)).norm();
    if (!(std::abs(d - l.distance_m) <= kMaxLoopClosureResidual_m))
      throw std::runtime_error(where + ": loop closure '" + Excerpt(l.name) + "' does not hold at the nominal pose: |p_a - p_b| = " + Num(d) +
                               " m, distance_m = " + Num(l.distance_m) + " m (tolerance " + Num(kMaxLoopClosureResidual_m) +
                               " m); fix the nominal pose or the attachment points");
  }
}

}  // namespace rome
