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

}  // namespace rome
