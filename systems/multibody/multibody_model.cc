#include "systems/multibody/multibody_model.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "framework/files.h"
#include "framework/text.h"
#include "systems/multibody/model_checks.h"
#include "systems/multibody/model_loader.h"
#include "systems/multibody/robot_file_text.h"
#include "systems/multibody/robot_files.h"

namespace rome {

const char* ToString(FloatingBaseType type) {
  switch (type) {
    case FloatingBaseType::kFixed: return "fixed";
    case FloatingBaseType::kPlanar: return "planar";
    case FloatingBaseType::kSpatial: return "spatial";
  }
  return "unknown";
}

const char* ToString(ContactType type) {
  switch (type) {
    case ContactType::kPoint: return "point";
    case ContactType::kLine: return "line";
    case ContactType::kFlat: return "flat";
  }
  return "unknown";
}

int MultibodyModel::num_base_dofs() const {
  switch (floating_base_) {
    case FloatingBaseType::kFixed: return 0;
    case FloatingBaseType::kPlanar: return 3;
    case FloatingBaseType::kSpatial: return 6;
  }
  return 0;
}

int MultibodyModel::BodyIndex(const std::string& link_name) const {
  auto it = body_index_.find(link_name);
  if (it == body_index_.end()) throw std::invalid_argument("robot '" + name_ + "': no link named '" + link_name + "'");
  return it->second;
}

int MultibodyModel::FrameIndex(const std::string& link_name) const {
  auto it = frame_index_.find(link_name);
  if (it == frame_index_.end())
    throw std::invalid_argument("robot '" + name_ + "': no link or frame named '" + link_name + "'");
  return it->second;
}

int MultibodyModel::VelocityIndex(const std::string& joint_name) const {
  auto it = joint_index_.find(joint_name);
  if (it == joint_index_.end())
    throw std::invalid_argument("robot '" + name_ + "': no movable joint named '" + joint_name + "'");
  return it->second;
}

int MultibodyModel::ContactIndex(const std::string& contact_name) const {
  auto it = contact_index_.find(contact_name);
  if (it == contact_index_.end())
    throw std::invalid_argument("robot '" + name_ + "': no contact named '" + contact_name + "'");
  return it->second;
}

namespace model_loading {

std::string Num(double x) {
  if (std::isnan(x)) return "NaN";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", x);
  return buf;
}

std::string Num3(const Eigen::Vector3d& v) { return Num(v[0]) + " " + Num(v[1]) + " " + Num(v[2]); }

// A file a robot package names: `entry`, relative to `folder` (the folder of the file that names it), resolved inside
// that folder tree; with options.allow_files_outside_package, anywhere (an absolute entry as given).
std::string PackageFile(const std::string& folder, const std::string& entry, const std::string& what,
                        const LoadOptions& options) {
  if (entry.find('\0') != std::string::npos)
    throw std::runtime_error(what + " " + Excerpt(entry, 200) + ": contains a NUL byte");
  if (options.allow_files_outside_package) {
    if (entry.empty()) throw std::runtime_error(what + " '': the path is empty");
    return std::filesystem::path(entry).is_absolute() ? entry : (std::filesystem::path(folder) / entry).string();
  }
  try {
    return ResolveInsideFolder(folder, entry, what);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) +
                             " (allow_files_outside_package lifts this for a package you trust)");
  }
}

std::string FolderOf(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

// Text given in memory instead of a file: the same size cap as ReadRegularFile.
const std::string& CheckTextSize(const std::string& text, const char* what, const std::string& name,
                                 std::uintmax_t max_bytes) {
  if (text.size() > max_bytes)
    throw std::runtime_error(std::string(what) + " " + Excerpt(name, 200) + ": text is " + std::to_string(text.size()) +
                             " bytes; the limit is " + std::to_string(max_bytes) + " bytes");
  return text;
}

// Whether two paths name one file (both resolved on the disk; a path that cannot be resolved names no file).
bool SameFile(const std::string& a, const std::string& b) {
  std::error_code ec_a, ec_b;
  const std::filesystem::path ca = std::filesystem::weakly_canonical(a, ec_a),
                              cb = std::filesystem::weakly_canonical(b, ec_b);
  return !ec_a && !ec_b && ca == cb;
}

}  // namespace model_loading

using namespace model_loading;

MultibodyModel MultibodyModelLoader::Load(const std::string& urdf_path, std::string sidecar_path, bool sidecar_required,
                                          const LoadOptions& options, const std::string* urdf_text,
                                          const std::string* sidecar_text) {
  MultibodyModel model;
  model.urdf_path_ = urdf_path;
  LoadState s{model, options, "URDF " + Excerpt(urdf_path, 200)};
  ReadSidecarFile(s, urdf_path, std::move(sidecar_path), sidecar_required, urdf_text,
                  sidecar_text);  // it decides the floating base
  ReadFloatingBaseEntry(s);
  ReadUrdf(s, urdf_path, urdf_text);
  ReadFloatingJointFromWorld(s);
  AddBaseBodies(s);
  WalkJointTree(s);
  CheckBodyInertias(s);
  CombineBodyParts(s);
  IndexDegreesOfFreedom(s);
  ReadActuators(s);
  // A moving joint must move some mass (else M is singular).
  bool any_inertial = false;
  for (const auto& [name, link] : s.urdf->links_) any_inertial = any_inertial || link->inertial != nullptr;
  CheckEveryJointMovesMass(
      model, s.ufile, any_inertial ? "" : " (no link in this URDF has an <inertial>: it describes kinematics only)");
  ReadSprings(s);
  ReadContacts(s);
  ReadLoopClosures(s);
  const std::vector<bool> given = ReadNominalPose(s);
  CheckNominalPose(model, model.sidecar_path_.empty() ? s.ufile : "sidecar " + Excerpt(model.sidecar_path_, 200), given,
                   &model.warnings_);
  return model;
}

MultibodyModel MultibodyModel::Load(const std::string& urdf_path, const std::string& sidecar_path,
                                    const LoadOptions& options) {
  return MultibodyModelLoader::Load(FindRobotFile(urdf_path),
                                    sidecar_path.empty() ? sidecar_path : FindRobotFile(sidecar_path), false, options);
}

MultibodyModel MultibodyModel::LoadFromSidecar(const std::string& given_sidecar_path, const LoadOptions& options) {
  const std::string sidecar_path = FindRobotFile(given_sidecar_path);
  const std::string text = ReadRegularFile(sidecar_path, "sidecar", kMaxUrdfBytes);
  const json j = ParseSidecarJson(text, sidecar_path);
  SidecarReader sc{sidecar_path};
  const std::string what = "sidecar " + Excerpt(sidecar_path, 200) + ": \"urdf\"";
  const std::string entry = sc.String(j, "urdf", "top level");
  if (entry.empty()) sc.Fail("urdf", "the entry is empty; name the URDF file, relative to the sidecar");
  const std::string urdf_path = PackageFile(FolderOf(sidecar_path), entry, what, options);
  if (SameFile(urdf_path, sidecar_path))
    sc.Fail("urdf", "'" + Excerpt(entry) + "' names the sidecar itself; name the URDF file");
  // Both files are read once, here: what the loader checks is what was read.
  const std::string xml = ReadRegularFile(urdf_path, what, kMaxUrdfBytes);
  return MultibodyModelLoader::Load(urdf_path, sidecar_path, true, options, &xml, &text);
}

MultibodyModel MultibodyModel::LoadFromText(const std::string& urdf_xml, const std::string& sidecar_json,
                                            const std::string& urdf_name, const std::string& sidecar_name,
                                            const LoadOptions& options) {
  return MultibodyModelLoader::Load(urdf_name, sidecar_json.empty() ? "" : sidecar_name, false, options, &urdf_xml,
                                    sidecar_json.empty() ? nullptr : &sidecar_json);
}

}  // namespace rome
