#pragma once
// Structural and physical checks of a robot description, run by MultibodyModel's loader (multibody_model.h lists
// them). Each throws std::runtime_error with one line that names the file (`where`), the joint, link or contact, the
// value and what is expected.

#include <string>
#include <vector>

#include <Eigen/Core>

namespace urdf {
class ModelInterface;
}

namespace rome {

class MultibodyModel;
struct ContactInfo;

/// Every link is the child of at most one joint (a closed chain is written as a loop closure in the sidecar), and no
/// joint has a <mimic> (ROME does not model coupled joints). `where` names the URDF ("URDF <file>").
void CheckUrdfIsTree(const urdf::ModelInterface& urdf, const std::string& where);
/// One warning per joint whose <dynamics> damping or friction is nonzero, or whose <limit velocity> is negative: ROME
/// does not model them (they are ignored).
void WarnUnmodelledUrdfElements(const urdf::ModelInterface& urdf, std::vector<std::string>* warnings);
/// `axis` scaled to unit length without overflow (1e300 entries stay representable); throws naming `where` if it is
/// zero or not finite.
Eigen::Vector3d UnitAxis(const Eigen::Vector3d& axis, const std::string& where);
/// A planar robot moves in the world x-z plane: at q = 0 each revolute joint turns about ±y and each prismatic joint
/// slides in the x-z plane (within kPlanarAxisTolerance).
void CheckPlanarJoints(const MultibodyModel& model, const std::string& where);
/// The nominal pose: a joint given in the sidecar (`given[k]`) lies within its position limits (one left at 0 outside
/// them gets a warning), each revolute angle within ±kMaxJointAngle_rad, and every loop closure holds there within
/// kMaxLoopClosureResidual_m. `where` names the sidecar ("sidecar <file>").
void CheckNominalPose(const MultibodyModel& model, const std::string& where, const std::vector<bool>& given,
                      std::vector<std::string>* warnings);

/// Why a rotational inertia (about the COM) of a body of `mass` kg is not physical, or "" if it is: positive
/// semi-definite and I1 + I2 >= I3 for its principal moments, each within a tolerance on the body's own scale:
/// kInertiaRelativeTolerance times its largest principal moment, or mass * kInertiaLengthTolerance_m^2 (a radius of
/// gyration of 1 um) if larger, so that an inertia of pure rounding noise (every entry ~1e-20, as exporters write a
/// point mass) counts as zero. Needs finite entries.
std::string PhysicalInertiaProblem(const Eigen::Matrix3d& inertia, double mass);
/// Why a contact's points are degenerate ("" if they are not): a line needs two distinct points, a flat contact points
/// that span an area (not all on one line), each to 1 um. Needs finite points.
std::string DegenerateContactProblem(const ContactInfo& contact);
/// Rejects a moving joint whose diagonal entry of M at q = 0 (without armature) is zero: the mass it moves
/// (prismatic), or the moment of inertia of everything it moves about its axis (revolute), relative to the robot's
/// scale. A sidecar armature (reflected inertia) on the joint makes the row nonsingular and is accepted. `where` names
/// the URDF; `hint` is appended to the message.
void CheckEveryJointMovesMass(const MultibodyModel& model, const std::string& where, const std::string& hint);

}  // namespace rome
