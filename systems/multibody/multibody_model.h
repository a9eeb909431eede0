#pragma once
// MultibodyModel: the immutable description of a legged robot (Pinocchio's "Model").
//
// Loaded from a URDF (urdfdom) plus the ROME JSON sidecar (see robots/README or the
// sidecar schema): floating base type, actuators, springs, contacts, loop closures and
// the nominal pose. Everything that changes while a simulation runs lives in
// MultibodyWorkspace (multibody_workspace.h); every computation takes
// (const MultibodyModel&, MultibodyWorkspace&, ...).
//
// Generalized coordinates (nq == nv and v = dq/dt, except on the quaternion base). A spatial floating base (the
// sidecar's "floating_base": "spatial" or "quaternion", or a URDF "floating" joint out of a massless world link) is
// the quaternion free-flyer BY DEFAULT; the ZYX-Euler base is asked for explicitly with the sidecar's
// "floating_base": "spatial_euler" or LoadOptions::euler_floating_base (LoadOptions override the sidecar). base_kind()
// names the result:
//   "fixed"        : q = [joints]
//   "planar"       : q = [x, z, pitch, joints]          (motion in the world x-z plane, pitch about +y)
//   "quaternion"   : q = [x, y, z, qw, qx, qy, qz, joints] (nq = nv + 1),
//                    v = [v_B, w_B, joint rates]: the base twist in base coordinates; the
//                    convention, Integrate and Difference are in free_flyer.h. No singularity.
//                    Joint coordinate k of v is entry k + 1 of q (PositionIndex).
//                    HybridContactPlant and the pose solver (SolvePose) run it; BulletWorldPlant and the walking and
//                    hopping diagrams' own models refuse it (RequireNqEqualsNv, one line naming the file and the
//                    option; the diagrams' plants may run the quaternion twin, PlantBase). Bullet is not
//                    used (forward dynamics and M^-1 go through the CRBA and the tree factor).
//   "spatial_euler": q = [x, y, z, yaw, pitch, roll, joints] (opt-in; floating_base() is kSpatial for both)
//                    R_world_base = Rz(yaw) Ry(pitch) Rx(roll) (ZYX Euler).
//                    SINGULAR at pitch = +-90 deg (yaw and roll axes align); walking
//                    postures stay far from it. The controllers, the diagrams and Bullet need it.
// The sidecar's nominal_pose "base" is written [x, y, z, yaw, pitch, roll] for either spatial base.
// The floating base is modelled as a chain of massless virtual joints (prismatic x, [y], z,
// revolute [yaw about z], pitch about y, [roll about x]) ending in the URDF root link, so the
// whole robot is a fixed-base kinematic tree and dq/dt is the velocity. The quaternion base keeps the
// same chain of six massless bodies (prismatic along the base's x, y, z, then revolute about them,
// joints "base_vx", "base_vy", "base_vz", "base_wx", "base_wy", "base_wz") with every one posed
// at the base itself, so that their motion subspace columns are the base-frame twist's basis; the kernels treat them
// as one 6-DOF joint (free_flyer_kernels.h).
// Joint coordinates follow a depth-first walk of the URDF tree (children in urdfdom's order);
// use VelocityIndex("joint_name") rather than hard-coded indices.
//
// URDF semantics (as Drake and Pinocchio read URDF):
//  * Links joined by a fixed joint are merged into ONE rigid body (the body of the fixed joint's
//    parent): masses, COMs and inertias are combined exactly (parallel-axis theorem). Every URDF
//    link stays addressable by name as a frame: Frame("link") gives the body it belongs to and
//    the fixed pose X_body_frame. BodyIndex("merged_link") returns the body it was merged into;
//    sidecar contacts and loop closures on a merged link are converted to that body's frame.
//  * A massless root link (typically "world") whose single joint is of type "floating" (or
//    "planar", with <axis> 0 1 0) is how URDF writes a floating base: the joint's child becomes the
//    root and the joint the spatial (planar) floating base above, as the sidecar's floating_base
//    makes one for a URDF without the world link; the joint's <origin> is the default nominal
//    base pose. A floating or planar joint anywhere else is rejected, naming it.
//  * A link without <inertial>, or with mass 0, is a massless frame (a nonzero inertia on a
//    zero mass is ignored, with a warning).
//  * Every <inertial> is checked: finite (a NaN is named), mass >= 0, inertia positive
//    semi-definite and satisfying the triangle inequality (I1 + I2 >= I3 for the principal
//    moments), each with a tolerance of kInertiaRelativeTolerance times the largest principal
//    moment or, if larger, the body's mass times kInertiaLengthTolerance_m^2. Physical validity is required of each
//    rigid body the dynamics sees: a link whose own <inertia> violates it (typically a dummy value such as every entry
//    1e-6 on a sensor, foot or base frame) is accepted, with a warning naming it, when the body it is merged into over
//    fixed joints has a physical combined inertia; otherwise the file is rejected naming the link.
//    LoadOptions::repair_inertia projects a rejected inertia onto the nearest physical one
//    (Frobenius norm, same principal axes) instead, with a warning.
//  * A moving joint that moves no mass (its row of M would be zero, M singular) is rejected,
//    naming the joint, unless the sidecar gives it a reflected inertia (armature).
//  * <limit> with lower > upper is rejected; lower == upper (urdfdom reads a <limit> without
//    lower/upper as 0, 0) means "no position limit", with a warning.
//  * Input caps (one-line errors): URDF file <= kMaxUrdfBytes and XML nesting depth
//    <= kMaxXmlDepth (checked before the XML parser runs), at most kMaxDofs degrees of freedom,
//    lengths (joint origins, COMs, contact and loop-closure points) within +-kMaxLength_m,
//    masses 0 or in [kMinNonzeroMass_kg, kMaxMass_kg], and the magnitude caps below (inertia, torque limit, gear ratio,
//    spring, friction), each named with its cap. Names must be valid UTF-8. A sidecar is nested at most kMaxJsonDepth
//    deep and names no key twice in one object (robot_file_text.h).
//  * Structure (systems/multibody/model_checks.h): the URDF is a tree (no link with two parent joints), holds one
//    <robot>, no xacro and no <mimic> (not modelled: refused, never dropped); a joint axis is nonzero and finite; a
//    planar robot's joints turn about y and slide in the x-z plane; a line contact's points are distinct and a flat
//    contact's span an area; the nominal pose lies within the joint limits and every loop closure holds there
//    (within kMaxLoopClosureResidual_m); the sidecar's "urdf" entry, when present, names the URDF being loaded.
//  * Files: only regular files are read (a device, FIFO, socket or directory is refused at once), the size cap is
//    checked while reading; a sidecar names files only inside its own folder tree (LoadOptions).
// Warnings (merged links, massless frames, repaired inertias, ...) are in warnings().
//
// Equations of motion (all quantities in SI units):
//   (M_rigid(q) + diag(I_reflected)) qdd + h(q, v) = B u + tau_spring(q, v) + J(q)^T F
//   h           = C(q, v) v + g(q): Coriolis, centrifugal and gravity (gravity 9.81 m/s^2 along -z)
//   tau_spring  = -K (q - q_rest) - D v on the sidecar's spring joints (a restoring torque,
//                 on the right-hand side; NOT part of h)
//   B           = nv x nu selection matrix (u are joint-side torques, N m or N)
//   I_reflected = gear_ratio^2 rotor inertia from the sidecar, added to M's diagonal on the
//                 actuated joints (rotor gyroscopic coupling neglected, as in MuJoCo's armature).
#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rome {

enum class FloatingBaseType { kFixed, kPlanar, kSpatial };
enum class MultibodyJointType { kFixed, kRevolute, kPrismatic };
enum class ContactType { kPoint, kLine, kFlat };

const char* ToString(FloatingBaseType type);
const char* ToString(ContactType type);

// One rigid body of the kinematic tree (one Bullet link). Bodies are in topological order
// (parent index < own index). Virtual floating-base bodies are massless.
struct MultibodyBody {
  std::string name;        // URDF link name (of the first link, if links were merged into it);
                           // virtual bodies are "floating_base_x" etc.
  std::string joint_name;  // inboard joint; virtual joints are "base_x", "base_z", "base_pitch"...
  int parent = -1;         // parent body index, -1 = world
  MultibodyJointType joint_type = MultibodyJointType::kFixed;
  int v_index = -1;                                                  // dof index in q and v, -1 if fixed
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();                   // joint axis in this link frame (unit)
  Eigen::Isometry3d X_parent_joint = Eigen::Isometry3d::Identity();  // this link frame in the
                                                                     // parent link frame at q = 0
  double mass = 0.0;                                                 // kg
  Eigen::Vector3d com = Eigen::Vector3d::Zero();                     // COM in the link frame, m
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();                 // about the COM, link axes, kg m^2
  // Bullet needs a diagonal inertia: inertia = R_link_principal diag(principal_moments) R^T.
  // The Bullet link frame is the principal frame at the COM; the link frame is recovered as
  // X_world_link = X_world_principal * X_link_principal^-1.
  Eigen::Vector3d principal_moments = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R_link_principal = Eigen::Matrix3d::Identity();
  bool is_virtual = false;
  std::vector<std::string> merged_links;  // URDF links welded into this body by fixed joints
};

// A named frame rigidly attached to a body: one per URDF link (a link that is a body has
// X_body_frame = identity; a merged link has the fixed pose of its frame in the body).
struct MultibodyFrame {
  std::string name;  // URDF link name
  int body = -1;
  Eigen::Isometry3d X_body_frame = Eigen::Isometry3d::Identity();
};

struct LoadOptions {
  // Projects a non-physical <inertia> onto the nearest physical inertia (and warns) instead of
  // rejecting the file.
  bool repair_inertia = false;
  // A robot package reads only regular files inside its own folder tree: the sidecar's "urdf" entry, and the sidecar
  // found beside a URDF, must resolve (symlinks followed) inside the folder of the file that names them; an absolute
  // path, a "../" that climbs out, or a link that points out is refused with one line. Set this only for a package
  // you trust (its files then may lie anywhere; devices, FIFOs and directories are still refused).
  bool allow_files_outside_package = false;
  // The two floating-base options override the sidecar's "floating_base" spelling; setting both is refused.
  // Loads a spatial floating base as the ZYX-Euler chain (nq == nv, v = dq/dt), as the sidecar's
  // "floating_base": "spatial_euler" does, instead of the default quaternion free-flyer: for BulletWorldPlant, the pose
  // solver, the controllers and the diagrams. No effect on a fixed or planar robot.
  bool euler_floating_base = false;
  // Loads a spatial floating base as the quaternion free-flyer even if the sidecar says "spatial_euler" (the default
  // otherwise). A fixed or planar robot with this option is refused, naming the file.
  bool quaternion_floating_base = false;
};

inline constexpr double kInertiaRelativeTolerance = 1e-6;
// Absolute floor of the inertia tolerance, as a radius of gyration (ours): principal moments within
// mass * (1 um)^2 of the limits count as rounding (exporters write a point mass as entries ~1e-20).
inline constexpr double kInertiaLengthTolerance_m = 1e-6;
inline constexpr std::size_t kMaxUrdfBytes = 16u << 20;  // 16 MiB
inline constexpr int kMaxXmlDepth = 64;
inline constexpr int kMaxDofs = 1000;
inline constexpr double kMaxLength_m = 1e3;
inline constexpr double kMaxMass_kg = 1e6;
/// Smallest nonzero link mass (ours: a microgram; below it a link is a massless frame written with rounding, or a
/// typo such as 1e-300, which would make the mass matrix singular to working precision).
inline constexpr double kMinNonzeroMass_kg = 1e-9;
// Magnitude caps of a robot description (ours: each a few orders beyond any legged robot's value, so that a typo or an
// overflow such as 1e308 or 1e-300 is refused, with the cap in the message, instead of ending as a physics failure).
inline constexpr double kMaxInertia_kgm2 = 1e6;  ///< |entries| of <inertia>, reflected_inertia_kgm2
inline constexpr double kMinTorqueLimit_Nm = 1e-3, kMaxTorqueLimit_Nm = 1e5;
inline constexpr double kMinGearRatio = 1e-2, kMaxGearRatio = 1e4;
inline constexpr double kMaxSpringStiffness_Nm_per_rad = 1e7, kMaxSpringDamping_Nms_per_rad = 1e5;
inline constexpr double kMinFrictionCoefficient = 1e-3, kMaxFrictionCoefficient = 10.0;
inline constexpr double kMinPositiveParameter = 1e-9;            ///< smallest nonzero stiffness, damping or armature
inline constexpr double kMaxJointAngle_rad = 6.283185307179586;  ///< |nominal or rest angle| of a revolute joint
inline constexpr double kMaxLoopClosureResidual_m = 1e-3;        ///< | |p_a - p_b| - distance_m | at the nominal pose
/// Out-of-plane part of a planar robot's joint axis (ours: rpy written with 1.5708 for π/2 leaves 3.7e-6).
inline constexpr double kPlanarAxisTolerance = 1e-4;

struct ActuatorInfo {
  std::string joint;
  int v_index = -1;
  double gear_ratio = 1.0;
  double reflected_inertia_kgm2 = 0.0;
  // Joint-side limit (N m, or N for prismatic): the sidecar's torque_limit_Nm, else the URDF
  // <limit effort>; one of them is required and must be positive and finite.
  double torque_limit_Nm = 0.0;
};

struct SpringInfo {
  std::string joint;
  int v_index = -1;
  double stiffness_Nm_per_rad = 0.0;
  double damping_Nms_per_rad = 0.0;
  double rest_angle_rad = 0.0;
};

struct ContactInfo {
  std::string name;
  std::string link;
  int body = -1;
  ContactType type = ContactType::kPoint;
  // In the BODY frame, m (the link frame, unless the link was merged into a body through a fixed
  // joint; the sidecar gives them in the link frame).
  std::vector<Eigen::Vector3d> points;
  double friction_coefficient = 1.0;
  // Constraint rows this contact contributes when active (see contact_dynamics.h):
  // planar model: point 2 (x, z), line/flat 3 (x, z, pitch of the contact frame)
  // otherwise   : point 3, line 5 (toe xyz + heel across the line), flat 6 (frame)
  int num_rows = 0;
  // Contact frame origin in the body frame: the point, the midpoint of the line or the
  // centroid of the corners.
  Eigen::Vector3d frame_origin = Eigen::Vector3d::Zero();
};

struct LoopClosureInfo {
  std::string name;
  std::string link_a, link_b;
  int body_a = -1, body_b = -1;
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  // body_a frame, m (sidecar: link_a frame)
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  // body_b frame, m (sidecar: link_b frame)
  double distance_m = 0.0;                            // |p_a - p_b| = distance_m
};

class MultibodyModel {
 public:
  // Loads URDF + sidecar. sidecar_path "" means: same directory and stem as the URDF with
  // extension ".rome.json"; if that file does not exist the model is fixed-base with no
  // actuators/contacts. Both paths are found by FindRobotFile (robot_files.h); only regular files are read, each
  // under kMaxUrdfBytes. Throws std::runtime_error naming the file, element and problem.
  static MultibodyModel Load(const std::string& urdf_path, const std::string& sidecar_path = "",
                             const LoadOptions& options = {});
  // Loads from a sidecar alone (its "urdf" entry is resolved relative to the sidecar's folder and must stay inside
  // it; see LoadOptions::allow_files_outside_package). The sidecar path is found by FindRobotFile (robot_files.h).
  static MultibodyModel LoadFromSidecar(const std::string& sidecar_path, const LoadOptions& options = {});
  // Loads from text in memory: a URDF's XML and a sidecar's JSON (sidecar_json "" means no
  // sidecar: fixed base, no actuators or contacts; the sidecar's "urdf" entry is not followed).
  // urdf_name and sidecar_name stand for the files in error messages. The same checks and caps
  // as Load (the size cap applies to the text); throws std::runtime_error.
  static MultibodyModel LoadFromText(const std::string& urdf_xml, const std::string& sidecar_json,
                                     const std::string& urdf_name = "<URDF text>",
                                     const std::string& sidecar_name = "<sidecar text>",
                                     const LoadOptions& options = {});

  const std::string& name() const { return name_; }
  const std::string& urdf_path() const { return urdf_path_; }
  const std::string& sidecar_path() const { return sidecar_path_; }
  FloatingBaseType floating_base() const { return floating_base_; }
  int num_base_dofs() const;  // velocity dofs of the base: 0, 3 or 6
  bool is_planar() const { return floating_base_ == FloatingBaseType::kPlanar; }
  // A spatial base in free-flyer coordinates (free_flyer.h); floating_base() is then kSpatial.
  bool has_quaternion_base() const { return quaternion_base_; }
  // "fixed", "planar", "quaternion" or "spatial_euler" (the sidecar's spellings that ask for each).
  const char* base_kind() const;

  int nq() const { return nq_; }
  int nv() const { return nv_; }

  // q_out = q (+) v dt: the free-flyer base by the SE(3) exponential (free_flyer.h), every other coordinate
  // q + v dt. Difference is its inverse: Integrate(q0, Difference(q0, q1), 1) = q1 (the shortest base rotation).
  // Throw std::invalid_argument naming the robot on a size mismatch or a zero or non-finite base quaternion.
  void Integrate(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v, double dt,
                 Eigen::Ref<Eigen::VectorXd> q_out) const;
  void Difference(const Eigen::Ref<const Eigen::VectorXd>& q0, const Eigen::Ref<const Eigen::VectorXd>& q1,
                  Eigen::Ref<Eigen::VectorXd> v) const;
  // qdot = G(q) v (nq): v itself, except the quaternion base (MapFreeFlyerVelocityToQDot).
  void MapVelocityToQDot(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v,
                         Eigen::Ref<Eigen::VectorXd> qdot) const;
  // Index in q of joint coordinate v_index (v_index + 1 after a quaternion base; -1 for its twist entries).
  int PositionIndexOfVelocity(int v_index) const {
    return !quaternion_base_ ? v_index : (v_index < 6 ? -1 : v_index + 1);
  }
  // Throws std::invalid_argument("<user>: robot '<name>' has a quaternion floating base (nq = .., nv = ..) ...; load
  // '<file>' with LoadOptions::euler_floating_base ...") for a user (a plant, a diagram) that takes q as the integral
  // of v.
  void RequireNqEqualsNv(const std::string& user) const;
  int nu() const { return static_cast<int>(actuators_.size()); }
  int num_bodies() const { return static_cast<int>(bodies_->size()); }
  const std::vector<MultibodyBody>& bodies() const { return *bodies_; }
  const std::shared_ptr<const std::vector<MultibodyBody>>& shared_bodies() const { return bodies_; }
  const MultibodyBody& body(int i) const { return (*bodies_)[i]; }

  // Lookups (throw std::invalid_argument naming the robot and the missing name).
  // BodyIndex accepts every URDF link name; for a link merged through a fixed joint it returns
  // the body it was merged into (use Frame() for points given in that link's frame).
  int BodyIndex(const std::string& link_name) const;
  int FrameIndex(const std::string& link_name) const;
  const MultibodyFrame& Frame(const std::string& link_name) const { return frames_[FrameIndex(link_name)]; }
  const std::vector<MultibodyFrame>& frames() const { return frames_; }
  bool HasFrame(const std::string& link_name) const { return frame_index_.count(link_name) > 0; }
  // One line per merged link, massless frame, repaired inertia, unlimited joint, ...
  const std::vector<std::string>& warnings() const { return warnings_; }
  int VelocityIndex(const std::string& joint_name) const;  // == position index unless has_quaternion_base()
  int ContactIndex(const std::string& contact_name) const;
  bool HasBody(const std::string& link_name) const { return body_index_.count(link_name) > 0; }
  bool HasJoint(const std::string& joint_name) const { return joint_index_.count(joint_name) > 0; }
  const std::string& JointName(int v_index) const { return joint_names_[v_index]; }
  const std::vector<std::string>& joint_names() const { return joint_names_; }
  int BodyOfVelocity(int v_index) const { return body_of_v_[v_index]; }

  const Eigen::Vector3d& gravity() const { return gravity_; }  // (0, 0, -9.81) m/s^2
  double total_mass() const { return total_mass_; }

  const std::vector<ActuatorInfo>& actuators() const { return actuators_; }
  const Eigen::MatrixXd& B() const { return B_; }                                  // nv x nu
  const Eigen::VectorXd& torque_limits() const { return torque_limits_; }          // nu
  const Eigen::VectorXd& reflected_inertia() const { return reflected_inertia_; }  // nv
  const std::vector<SpringInfo>& springs() const { return springs_; }
  const Eigen::VectorXd& spring_stiffness() const { return spring_stiffness_; }  // nv
  const Eigen::VectorXd& spring_damping() const { return spring_damping_; }      // nv
  const Eigen::VectorXd& spring_rest() const { return spring_rest_; }            // nv, at q[PositionIndexOfVelocity(k)]
  const std::vector<ContactInfo>& contacts() const { return contacts_; }
  const std::vector<LoopClosureInfo>& loop_closures() const { return loop_closures_; }
  int num_contacts() const { return static_cast<int>(contacts_.size()); }
  int num_loop_closures() const { return static_cast<int>(loop_closures_.size()); }
  int max_constraint_rows() const { return max_constraint_rows_; }           // all contacts + loops
  const Eigen::VectorXd& position_lower_limits() const { return q_lower_; }  // nq; -inf if none
  const Eigen::VectorXd& position_upper_limits() const { return q_upper_; }
  const Eigen::VectorXd& q_nominal() const { return q_nominal_; }  // nq

 private:
  MultibodyModel() = default;
  friend class MultibodyModelLoader;

  std::string name_, urdf_path_, sidecar_path_;
  FloatingBaseType floating_base_ = FloatingBaseType::kFixed;
  bool quaternion_base_ = false;
  int nq_ = 0, nv_ = 0;
  std::shared_ptr<const std::vector<MultibodyBody>> bodies_;
  std::map<std::string, int> body_index_, joint_index_, contact_index_, frame_index_;
  std::vector<MultibodyFrame> frames_;
  std::vector<std::string> warnings_;
  std::vector<std::string> joint_names_;
  std::vector<int> body_of_v_;
  Eigen::Vector3d gravity_{0.0, 0.0, -9.81};
  double total_mass_ = 0.0;
  std::vector<ActuatorInfo> actuators_;
  Eigen::MatrixXd B_;
  Eigen::VectorXd torque_limits_, reflected_inertia_;
  std::vector<SpringInfo> springs_;
  Eigen::VectorXd spring_stiffness_, spring_damping_, spring_rest_;
  std::vector<ContactInfo> contacts_;
  std::vector<LoopClosureInfo> loop_closures_;
  int max_constraint_rows_ = 0;
  Eigen::VectorXd q_lower_, q_upper_, q_nominal_;
};

}  // namespace rome
