#include "systems/multibody/model_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

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
      throw std::runtime_error(
          where + ": joint '" + Excerpt(name) + "' has <mimic joint='" + Excerpt(joint->mimic->joint_name) +
          "'>; ROME does not model coupled joints: remove the <mimic> (the joint becomes independent) "
          "or write the coupling as a loop closure in the sidecar");
    const auto [it, inserted] = parent_joint.emplace(joint->child_link_name, name);
    if (!inserted)
      throw std::runtime_error(where + ": link '" + Excerpt(joint->child_link_name) +
                               "' is the child of two joints ('" + Excerpt(it->second) + "' and '" + Excerpt(name) +
                               "'); a URDF must be a tree: write a closed chain as a loop closure in the sidecar");
  }
}

void WarnUnmodelledUrdfElements(const urdf::ModelInterface& urdf, std::vector<std::string>* warnings) {
  for (const auto& [name, joint] : urdf.joints_) {
    if (joint->dynamics && (joint->dynamics->damping != 0.0 || joint->dynamics->friction != 0.0))
      warnings->push_back("joint '" + Excerpt(name) + "': <dynamics damping=" + Num(joint->dynamics->damping) +
                          " friction=" + Num(joint->dynamics->friction) +
                          "> is not modelled by ROME (ignored; a sidecar spring's damping is)");
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
      throw std::runtime_error(
          where + ": joint '" + Excerpt(b.joint_name) + "' " + (revolute ? "turns about" : "slides along") +
          " world axis " + Num3(a) +
          " at q = 0; the robot is planar (x-z plane), so a revolute joint must turn "
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
    if ((q[k] < lo || q[k] > hi) && given[static_cast<size_t>(k)])
      throw std::runtime_error(where + ": " + joint + limits);
    if (q[k] < lo || q[k] > hi)
      warnings->push_back(joint + limits + " (not given in the sidecar's nominal_pose.joints, so 0; give it there)");
    if (model.body(model.BodyOfVelocity(k)).joint_type == MultibodyJointType::kRevolute &&
        std::abs(q[k]) > kMaxJointAngle_rad)
      throw std::runtime_error(where + ": " + joint + " rad is beyond +-" + Num(kMaxJointAngle_rad) +
                               " rad (one turn)");
  }
  if (model.loop_closures().empty()) return;
  MultibodyWorkspace ws(model);
  for (const LoopClosureInfo& l : model.loop_closures()) {
    const double d =
        (CalcPointPosition(model, ws, q, l.body_a, l.point_a) - CalcPointPosition(model, ws, q, l.body_b, l.point_b))
            .norm();
    if (!(std::abs(d - l.distance_m) <= kMaxLoopClosureResidual_m))
      throw std::runtime_error(where + ": loop closure '" + Excerpt(l.name) +
                               "' does not hold at the nominal pose: |p_a - p_b| = " + Num(d) +
                               " m, distance_m = " + Num(l.distance_m) + " m (tolerance " +
                               Num(kMaxLoopClosureResidual_m) + " m); fix the nominal pose or the attachment points");
  }
}

std::string PhysicalInertiaProblem(const Eigen::Matrix3d& inertia, double mass) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d l = eig.eigenvalues();  // ascending
  const double tol = std::max(kInertiaRelativeTolerance * l.cwiseAbs().maxCoeff(),
                              mass * kInertiaLengthTolerance_m * kInertiaLengthTolerance_m);
  const bool not_psd = l[0] < -tol;
  const bool not_triangle = l[0] + l[1] < l[2] - tol;
  if (!not_psd && !not_triangle) return "";
  return std::string(not_psd ? "is not positive semi-definite" : "violates the triangle inequality I1 + I2 >= I3") +
         " (principal moments " + Num3(l) + " kg m^2)";
}

std::string DegenerateContactProblem(const ContactInfo& c) {
  constexpr double kResolution_m = 1e-6;
  if (c.type == ContactType::kLine && (c.points[0] - c.points[1]).norm() < kResolution_m)
    return "line contact points coincide";
  if (c.type != ContactType::kFlat) return "";
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : c.points) mean += p;
  mean /= static_cast<double>(c.points.size());
  Eigen::Matrix3Xd centred(3, static_cast<Eigen::Index>(c.points.size()));
  for (size_t i = 0; i < c.points.size(); ++i) centred.col(static_cast<Eigen::Index>(i)) = c.points[i] - mean;
  const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::Matrix3Xd>(centred).singularValues();  // descending
  if (sv[1] < kResolution_m)
    return "flat contact points lie on one line (they span no area: second singular value " + Num(sv[1]) +
           " m); use a line contact, or give points that span the sole";
  return "";
}

void CheckEveryJointMovesMass(const MultibodyModel& model, const std::string& ufile, const std::string& hint) {
  const std::vector<MultibodyBody>& bodies = model.bodies();
  const int nb = static_cast<int>(bodies.size());
  std::vector<Eigen::Isometry3d> X_w(nb);
  for (int i = 0; i < nb; ++i)
    X_w[i] = bodies[i].parent >= 0 ? X_w[bodies[i].parent] * bodies[i].X_parent_joint : bodies[i].X_parent_joint;
  // Subtree mass, first moment and second moment about the world origin (world axes).
  std::vector<double> m(nb, 0.0);
  std::vector<Eigen::Vector3d> h(nb, Eigen::Vector3d::Zero());
  std::vector<Eigen::Matrix3d> J(nb, Eigen::Matrix3d::Zero());
  for (int i = 0; i < nb; ++i) {
    const MultibodyBody& b = bodies[i];
    const Eigen::Vector3d c = X_w[i] * b.com;
    const Eigen::Matrix3d& R = X_w[i].linear();
    m[i] = b.mass;
    h[i] = b.mass * c;
    J[i] = R * b.inertia * R.transpose() + b.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  }
  for (int i = nb - 1; i >= 0; --i) {
    const int p = bodies[i].parent;
    if (p < 0) continue;
    m[p] += m[i];
    h[p] += h[i];
    J[p] += J[i];
  }
  std::vector<double> value(nb, 0.0);
  double max_prismatic = 0.0, max_revolute = 0.0, total_m = 0.0;
  Eigen::Matrix3d total_J = Eigen::Matrix3d::Zero();
  for (int i = 0; i < nb; ++i) {
    if (bodies[i].parent < 0) {
      total_m += m[i];
      total_J += J[i];
    }
    if (bodies[i].joint_type == MultibodyJointType::kFixed) continue;
    if (bodies[i].joint_type == MultibodyJointType::kPrismatic) {
      value[i] = m[i];
      max_prismatic = std::max(max_prismatic, value[i]);
    } else {
      const Eigen::Vector3d a = X_w[i].linear() * bodies[i].axis;
      const Eigen::Vector3d o = X_w[i].translation();
      Eigen::Matrix3d I_o = J[i];
      if (m[i] > 0.0) {
        const Eigen::Vector3d c = h[i] / m[i];
        const Eigen::Vector3d d = c - o;
        I_o = J[i] - m[i] * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose()) +
              m[i] * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
      }
      value[i] = a.dot(I_o * a);
      max_revolute = std::max(max_revolute, value[i]);
    }
  }
  const double tol_prismatic = 1e-12 * std::max(max_prismatic, total_m);
  const double tol_revolute = 1e-12 * std::max(max_revolute, total_J.trace());
  for (int i = 0; i < nb; ++i) {
    const MultibodyBody& b = bodies[i];
    if (b.joint_type == MultibodyJointType::kFixed || model.reflected_inertia()[b.v_index] > 0.0) continue;
    const bool prismatic = b.joint_type == MultibodyJointType::kPrismatic;
    if (value[i] > (prismatic ? tol_prismatic : tol_revolute)) continue;
    const std::string carried = b.is_virtual ? "the whole robot" : "link '" + Excerpt(b.name) + "' and its descendants";
    const std::string verb = b.is_virtual ? " is" : " are";
    throw std::runtime_error(ufile + ": joint '" + Excerpt(b.joint_name) + "' moves " +
                             (m[i] == 0.0 ? "no mass (" + carried + verb + " massless)"
                                          : "no inertia about its axis (" + carried +
                                                (b.is_virtual ? " has" : " have") + " all the mass on the axis)") +
                             ", so the mass matrix is singular" + hint +
                             "; give them an <inertial>, or the joint a reflected_inertia_kgm2 in the sidecar");
  }
}

}  // namespace rome
