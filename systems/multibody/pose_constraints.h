#pragma once
// Inverse kinematics for poses given as scalar equality constraints (stance poses, initial states).
//
// A pose request is a list of scalar constraints g_i(q) = target_i, each one world coordinate of a point on a
// link (e.g. a contact frame origin), one world coordinate of the whole-body COM, or one generalized coordinate
// (e.g. the base pitch), or the length error of one of the model's loop closures. SolvePose() finds q by Newton
// iterations with minimum-norm steps from a start q0:
//
//   c_k = g(q_k) - target,   C_k = dg/dv (q_k)  (rows of CalcPointJacobian / CalcComJacobian / unit rows),
//   q_{k+1} = Integrate(q_k, -C_k^+ c_k, 1)      (C^+ from a complete orthogonal decomposition),
//
// where Integrate is MultibodyModel::Integrate: q + dv, except on the quaternion base, whose quaternion moves by its
// exponential and stays a unit quaternion (nq = nv + 1; C has nv columns, the base twist first).
// until |c_k|_2 < tolerance. With fewer constraints than nv the step is the smallest change of q that zeroes the
// linearised residual, so the solution stays close to q0 (the free directions keep their start values to first
// order); redundant but consistent constraints are harmless. Positions are world coordinates in m, generalized
// coordinates in the units of q (rad for revolute joints and base angles).
//
// Example (planar AMBER on its left foot at (0, 0), COM above it, torso upright, right foot at (0.12, 0.08)):
//   const std::vector<PoseConstraint> pose = {
//       PoseConstraint::ContactPoint(model, "left_foot", 0, 0.0), PoseConstraint::ContactPoint(model, "left_foot", 2,
//       0.0), PoseConstraint::Com(0, 0.0), PoseConstraint::Coordinate(2, 0.0), PoseConstraint::ContactPoint(model,
//       "right_foot", 0, 0.12), PoseConstraint::ContactPoint(model, "right_foot", 2, 0.08)};
//   const Eigen::VectorXd q = SolvePose(model, ws, model.q_nominal(), pose);
#include <string>
#include <vector>

#include <Eigen/Core>

#include "systems/multibody/multibody_model.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome {

/// One scalar equality constraint g(q) = target on a configuration q.
struct PoseConstraint {
  enum class Kind {
    kPoint,        ///< world coordinate `axis` of the point `p_link` of link `body`
    kCom,          ///< world coordinate `axis` of the whole-body centre of mass
    kCoordinate,   ///< generalized coordinate q[coordinate]
    kLoopClosure,  ///< |p_a − p_b| − distance_m of loop closure `loop_closure` (target 0 keeps the rod length)
  };
  Kind kind = Kind::kCoordinate;
  int axis = 0;   ///< kPoint, kCom: world axis, 0 = x, 1 = y, 2 = z
  int body = -1;  ///< kPoint: body index (MultibodyModel::BodyIndex)
  Eigen::Vector3d p_link =
      Eigen::Vector3d::Zero();  ///< kPoint: point in the body frame, m (Point() converts from the link frame)
  int coordinate = -1;          ///< kCoordinate: index into q
  int loop_closure = -1;        ///< kLoopClosure: index into MultibodyModel::loop_closures()
  double target = 0.0;          ///< m for kPoint/kCom, units of q for kCoordinate
  std::string name;             ///< for error messages; "" = generated from the fields

  /// Coordinate `axis` of the contact frame origin of `contact` (ContactInfo::frame_origin: the point, the line
  /// midpoint or the sole centroid). Throws std::invalid_argument if the model has no such contact.
  static PoseConstraint ContactPoint(const MultibodyModel& model, const std::string& contact, int axis, double target);
  /// Coordinate `axis` of the point `p_link` of link `link`. Throws std::invalid_argument for an unknown link.
  static PoseConstraint Point(const MultibodyModel& model, const std::string& link, const Eigen::Vector3d& p_link,
                              int axis, double target);
  /// Coordinate `axis` of the whole-body COM.
  static PoseConstraint Com(int axis, double target);
  /// q[index] = target (e.g. index num_base_dofs() - 1 is the base pitch of a planar model). On the quaternion base,
  /// q[0..2] is the base position and q[7..] the joints; the quaternion's entries q[3..6] cannot be constrained one by
  /// one (ValidatePoseConstraints refuses them): constrain points on the base instead.
  static PoseConstraint Coordinate(int index, double target);
  /// Loop closure `index` holds its length (|p_a − p_b| = distance_m; e.g. planar Cassie's achilles rods).
  static PoseConstraint LoopClosure(int index);
  /// One LoopClosure() per loop closure of `model` (none for a tree).
  static std::vector<PoseConstraint> LoopClosures(const MultibodyModel& model);
};

struct PoseSolverOptions {
  int max_iterations = 100;  ///< Newton steps before giving up
  double tolerance = 1e-12;  ///< on the Euclidean norm of the residual g(q) - target
  /// Keep every coordinate inside its URDF position limits (ours; off by default, the plain Newton above): each step
  /// is the minimum-norm step with the coordinates that sit on a limit and would move beyond it held there, then
  /// clamped to the limits; the free directions of a redundant request carry the rest.
  bool respect_joint_limits = false;
};

/// Human-readable description of `c` ("x of contact left_foot", "COM z", "q[2] (base_pitch)").
std::string DescribePoseConstraint(const MultibodyModel& model, const PoseConstraint& c);

/// Checks a request without evaluating it. Throws std::invalid_argument naming the first bad constraint: axis not
/// in {0, 1, 2}; a y (axis 1) point or COM constraint on a planar model (motion is in the x-z plane, so y cannot be
/// changed); body or coordinate index out of range; an entry of a base quaternion; non-finite target; an empty list.
void ValidatePoseConstraints(const MultibodyModel& model, const std::vector<PoseConstraint>& constraints);

/// Residual c = g(q) - target (size m) and Jacobian C = dg/dv (m x nv; dg/dq on every base but the quaternion's) of the
/// constraints at q (m = constraints.size()). Does not validate (call ValidatePoseConstraints once). No heap
/// allocation.
void CalcPoseConstraints(const MultibodyModel& model, MultibodyWorkspace& ws,
                         const Eigen::Ref<const Eigen::VectorXd>& q, const std::vector<PoseConstraint>& constraints,
                         Eigen::Ref<Eigen::VectorXd> residual, Eigen::Ref<Eigen::MatrixXd> jacobian);

/// Solves g(q) = target by Newton iterations with minimum-norm steps from q0 (see the file comment) and returns q
/// with |g(q) - target| < options.tolerance (and, with options.respect_joint_limits, every coordinate within its
/// limits). Throws std::invalid_argument for a bad request (q0 of the wrong size or not finite, bad options, or any
/// ValidatePoseConstraints error), and std::runtime_error if the iteration does not converge within
/// options.max_iterations (e.g. a foot out of reach); that message names the robot, the residual norm and the
/// constraint with the largest residual.
Eigen::VectorXd SolvePose(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& q0,
                          const std::vector<PoseConstraint>& constraints, const PoseSolverOptions& options = {});

}  // namespace rome
