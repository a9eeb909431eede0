#pragma once
// MultibodyModelLoader: what MultibodyModel::Load, LoadFromSidecar and LoadFromText run. Internal to rome_multibody
// (needs urdfdom and nlohmann_json); users call MultibodyModel's loaders (multibody_model.h).
//
// Load runs the stages below in order on one LoadState; each reads one thing:
//   sidecar file: the file (next to the URDF, given, or in memory), its top-level keys, "urdf", "floating_base"
//                 (model_loader_sidecar.cc, parsed first: it decides the floating base; "spatial", "quaternion" and
//                 "spatial_euler" load a spatial Euler base, which the last stage, UseQuaternionBase, converts to the
//                 free-flyer unless "spatial_euler" or LoadOptions::euler_floating_base asks for Euler);
//   URDF:         the XML, names, tree shape, a floating or planar joint out of a massless world root, the links'
//                 <inertial> and the joint tree walked into bodies (model_loader_urdf.cc);
//   merging:      links welded over fixed joints into one rigid body each, inertia validity judged per body (and
//                 repaired if asked), principal frames, degrees of freedom (model_loader_merge.cc);
//   sidecar data: actuators, springs, contacts, loop closures, nominal pose (model_loader_sidecar_data.cc);
//   validation:   the checks of model_checks.h between and after these stages.
// Each throws std::runtime_error with one line naming the file, the element and the problem.

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <urdf_model/model.h>
#include <urdf_world/types.h>

#include "systems/multibody/multibody_model.h"

namespace rome {

namespace model_loading {

using json = nlohmann::json;

/// "%.6g", or NaN, inf, -inf.
std::string Num(double x);
std::string Num3(const Eigen::Vector3d& v);
/// The folder of `path` ("." for a bare name).
std::string FolderOf(const std::string& path);
/// A file a robot package names: `entry`, relative to `folder` (the folder of the file that names it), resolved inside
/// that folder tree; with options.allow_files_outside_package, anywhere (an absolute entry as given).
std::string PackageFile(const std::string& folder, const std::string& entry, const std::string& what,
                        const LoadOptions& options);
/// Text given in memory instead of a file: the same size cap as ReadRegularFile.
const std::string& CheckTextSize(const std::string& text, const char* what, const std::string& name,
                                 std::uintmax_t max_bytes);
/// Whether two paths name one file (both resolved on the disk; a path that cannot be resolved names no file).
bool SameFile(const std::string& a, const std::string& b);

/// Reads sidecar entries; every failure throws "sidecar <file>: <context>: <problem>".
struct SidecarReader {
  std::string file;

  [[noreturn]] void Fail(const std::string& context, const std::string& problem) const;
  static std::string Dump(const json& v);
  const json& Get(const json& obj, const std::string& key, const std::string& context) const;
  /// Rejects keys that are not in `known`, suggesting the nearest known key.
  void CheckKeys(const json& obj, std::initializer_list<const char*> known, const std::string& context) const;
  double Number(const json& obj, const std::string& key, const std::string& context) const;
  double NumberOr(const json& obj, const std::string& key, double fallback, const std::string& context) const;
  std::string String(const json& obj, const std::string& key, const std::string& context) const;
  /// A point or offset in metres: finite and within +-kMaxLength_m.
  Eigen::Vector3d Vec3(const json& v, const std::string& context) const;
  /// The array at `key` (an empty one if absent).
  const json& Array(const json& obj, const std::string& key, const std::string& context) const;
};

/// A magnitude a robot file gives: within [lo, hi], else "<name> <value> <unit> is outside [lo, hi] <unit>".
void CheckMagnitude(const SidecarReader& sc, const std::string& context, const std::string& name, double value,
                    double lo, double hi, const std::string& unit);

/// A link's mass properties in its link frame (inertia about the COM, link axes). A non-physical <inertia> is not
/// rejected here: it is judged with the body it ends up in (MultibodyModelLoader::CheckBodyInertias), so `problem`
/// records it.
struct LinkMass {
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  std::string problem;  // empty, or why the <inertia> is not physical (with its principal moments)
};

/// One contribution to a body: a link's mass properties expressed in the body frame.
struct BodyPart {
  double mass;
  Eigen::Vector3d com;
  Eigen::Matrix3d inertia;
  std::string link;     // URDF link it comes from
  std::string problem;  // LinkMass::problem
};

}  // namespace model_loading

class MultibodyModelLoader {
 public:
  // urdf_text / sidecar_text, when given, are the files' contents (urdf_path and sidecar_path then only name them,
  // and no sidecar is looked for next to the URDF).
  static MultibodyModel Load(const std::string& urdf_path, std::string sidecar_path, bool sidecar_required,
                             const LoadOptions& options, const std::string* urdf_text = nullptr,
                             const std::string* sidecar_text = nullptr);
  /// ScaleMassAndFriction (model_scaling.h): a friend of MultibodyModel, so that scaling needs no public setter.
  static MultibodyModel Scale(const MultibodyModel& model, double mass_scale, double friction_scale);

 private:
  // What one Load builds, stage by stage.
  struct LoadState {
    LoadState(MultibodyModel& model_in, const LoadOptions& options_in, std::string ufile_in)
        : model(model_in), options(options_in), ufile(std::move(ufile_in)) {}
    MultibodyModel& model;
    const LoadOptions& options;
    std::string ufile;  // "URDF <file>", for messages
    model_loading::json sidecar = model_loading::json::object();
    model_loading::SidecarReader sc;
    urdf::ModelInterfaceSharedPtr urdf;
    urdf::LinkConstSharedPtr root;  // the robot's root link (the world link's child for a floating joint out of it)
    Eigen::VectorXd base_nominal;   // default nominal_pose.base from that floating joint's <origin>
    std::shared_ptr<std::vector<MultibodyBody>> bodies = std::make_shared<std::vector<MultibodyBody>>();
    std::vector<std::vector<model_loading::BodyPart>> parts;  // per body
    std::vector<std::pair<double, double>> limits;            // per body: the joint's position limits
    bool sidecar_euler = false;  // the sidecar's "floating_base": "spatial_euler" (UseQuaternionBase)
  };
  static void Warn(LoadState& s, const std::string& warning) { s.model.warnings_.push_back(warning); }

  // Sidecar file (model_loader_sidecar.cc).
  static void ReadSidecarFile(LoadState& s, const std::string& urdf_path, std::string sidecar_path,
                              bool sidecar_required, const std::string* urdf_text, const std::string* sidecar_text);
  static void ReadFloatingBaseEntry(LoadState& s);

  // URDF (model_loader_urdf.cc).
  static void ReadUrdf(LoadState& s, const std::string& urdf_path, const std::string* urdf_text);
  static void ReadFloatingJointFromWorld(LoadState& s);
  static void AddBaseBodies(LoadState& s);
  static model_loading::LinkMass ReadLinkMass(LoadState& s, const urdf::Link& link);
  static void WalkJointTree(LoadState& s);

  // Merging (model_loader_merge.cc).
  static void AddFrame(LoadState& s, const std::string& link, int body, const Eigen::Isometry3d& X_body_link);
  static void AddPart(LoadState& s, int body, const urdf::Link& link, const model_loading::LinkMass& lm,
                      const Eigen::Isometry3d* X_body_link);
  static void CheckBodyInertias(LoadState& s);
  static void CombineBodyParts(LoadState& s);
  static void IndexDegreesOfFreedom(LoadState& s);

  // Sidecar data (model_loader_sidecar_data.cc).
  static int MovableJoint(const LoadState& s, const std::string& joint, const std::string& context);
  /// Entry i of the sidecar array `array` that names a joint: checks its keys against `known`, reads its "joint" into
  /// *joint, sets *ctx to "ARRAY[i] (joint 'JOINT')" for the errors that follow and returns the joint's velocity index.
  static int ReadJointEntry(const LoadState& s, const model_loading::json& entry, const char* array, size_t i,
                            std::initializer_list<const char*> known, std::string* joint, std::string* ctx);
  static const MultibodyFrame& ExistingFrame(const LoadState& s, const std::string& link, const std::string& context);
  static void ReadActuators(LoadState& s);
  static void ReadSprings(LoadState& s);
  static void ReadContacts(LoadState& s);
  static void ReadLoopClosures(LoadState& s);
  static std::vector<bool> ReadNominalPose(LoadState& s);

  // Last stage (multibody_model.cc): a spatial Euler base, loaded and checked, turned into the quaternion free-flyer
  // (the default) unless the sidecar's "spatial_euler" or LoadOptions::euler_floating_base asks for Euler.
  static void UseQuaternionBase(LoadState& s);
};

}  // namespace rome
