#include "systems/multibody/multibody_model.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "framework/files.h"
#include "framework/text.h"
#include "systems/multibody/free_flyer.h"
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

const char* MultibodyModel::base_kind() const {
  if (quaternion_base_) return "quaternion";
  return floating_base_ == FloatingBaseType::kSpatial ? "spatial_euler" : ToString(floating_base_);
}

namespace {

void CheckVectorSize(const MultibodyModel& model, Eigen::Index got, int expected, const char* what) {
  if (got != expected)
    throw std::invalid_argument("robot '" + model.name() + "': " + what + " has size " + std::to_string(got) +
                                ", expected " + std::to_string(expected));
}

Vector7d BaseOf(const MultibodyModel& model, const Eigen::Ref<const Eigen::VectorXd>& q, const char* what) {
  const Vector7d base = q.head<7>();
  Eigen::Quaterniond R;
  if (!FreeFlyerRotation(base, &R))
    throw std::invalid_argument("robot '" + model.name() + "': " + what + " has the base quaternion (" +
                                model_loading::Num(base[3]) + ", " + model_loading::Num(base[4]) + ", " +
                                model_loading::Num(base[5]) + ", " + model_loading::Num(base[6]) +
                                "); expected a finite, nonzero (unit) quaternion");
  return base;
}

}  // namespace

void MultibodyModel::Integrate(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v,
                               double dt, Eigen::Ref<Eigen::VectorXd> q_out) const {
  CheckVectorSize(*this, q.size(), nq_, "q");
  CheckVectorSize(*this, v.size(), nv_, "v");
  CheckVectorSize(*this, q_out.size(), nq_, "Integrate's output");
  if (!quaternion_base_) {
    q_out = q + dt * v;
    return;
  }
  const FreeFlyerTwist xi = dt * v.head<6>();
  q_out.head<7>() = FreeFlyerIntegrate(BaseOf(*this, q, "q"), xi);
  q_out.tail(nv_ - 6) = q.tail(nv_ - 6) + dt * v.tail(nv_ - 6);
}

void MultibodyModel::Difference(const Eigen::Ref<const Eigen::VectorXd>& q0,
                                const Eigen::Ref<const Eigen::VectorXd>& q1, Eigen::Ref<Eigen::VectorXd> v) const {
  CheckVectorSize(*this, q0.size(), nq_, "q0");
  CheckVectorSize(*this, q1.size(), nq_, "q1");
  CheckVectorSize(*this, v.size(), nv_, "Difference's output");
  if (!quaternion_base_) {
    v = q1 - q0;
    return;
  }
  v.head<6>() = FreeFlyerDifference(BaseOf(*this, q0, "q0"), BaseOf(*this, q1, "q1"));
  v.tail(nv_ - 6) = q1.tail(nv_ - 6) - q0.tail(nv_ - 6);
}

void MultibodyModel::MapVelocityToQDot(const Eigen::Ref<const Eigen::VectorXd>& q,
                                       const Eigen::Ref<const Eigen::VectorXd>& v,
                                       Eigen::Ref<Eigen::VectorXd> qdot) const {
  CheckVectorSize(*this, q.size(), nq_, "q");
  CheckVectorSize(*this, v.size(), nv_, "v");
  CheckVectorSize(*this, qdot.size(), nq_, "MapVelocityToQDot's output");
  if (!quaternion_base_) {
    qdot = v;
    return;
  }
  const FreeFlyerTwist v_base = v.head<6>();
  qdot.head<7>() = MapFreeFlyerVelocityToQDot(q.head<7>(), v_base);
  qdot.tail(nv_ - 6) = v.tail(nv_ - 6);
}

void MultibodyModel::RequireNqEqualsNv(const std::string& user) const {
  if (nq_ == nv_) return;
  const std::string& file = sidecar_path_.empty() ? urdf_path_ : sidecar_path_;
  throw std::invalid_argument(user + ": robot '" + name_ + "' has a " + base_kind() +
                              " floating base (nq = " + std::to_string(nq_) + ", nv = " + std::to_string(nv_) +
                              "), which it does not support yet; load '" + (file.empty() ? name_ : file) +
                              "' with LoadOptions::euler_floating_base (or the sidecar's \"floating_base\": "
                              "\"spatial_euler\")");
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
  UseQuaternionBase(s);
  return model;
}

void MultibodyModelLoader::UseQuaternionBase(LoadState& s) {
  MultibodyModel& model = s.model;
  const LoadOptions& o = s.options;
  if (o.quaternion_floating_base && o.euler_floating_base)
    throw std::runtime_error(s.ufile +
                             ": LoadOptions::quaternion_floating_base and LoadOptions::euler_floating_base are both "
                             "set (choose one)");
  if (model.floating_base_ != FloatingBaseType::kSpatial) {
    if (o.quaternion_floating_base)
      throw std::runtime_error(
          s.ufile + ": LoadOptions::quaternion_floating_base asks for a quaternion free-flyer, but " +
          "the robot's floating base is " + ToString(model.floating_base_) + " (only a spatial base has one)");
    return;
  }
  // A spatial base is the free-flyer unless asked for as Euler; LoadOptions override the sidecar.
  if (o.euler_floating_base || (s.sidecar_euler && !o.quaternion_floating_base)) return;
  // The six virtual joints become the base twist's coordinates: prismatic along, then revolute about, the base's own
  // x, y, z (the workspace poses all six bodies at the base, free_flyer.h).
  auto bodies = std::make_shared<std::vector<MultibodyBody>>(*model.bodies_);
  static const char* const kNames[6] = {"base_vx", "base_vy", "base_vz", "base_wx", "base_wy", "base_wz"};
  for (int k = 0; k < 6; ++k) {
    MultibodyBody& b = (*bodies)[model.body_of_v_[k]];
    model.joint_index_.erase(b.joint_name);
    b.joint_name = kNames[k];
    model.joint_index_[b.joint_name] = k;
    model.joint_names_[k] = b.joint_name;
    if (b.is_virtual) {
      model.body_index_.erase(b.name);
      b.name = std::string("floating_") + kNames[k];
      model.body_index_[b.name] = model.body_of_v_[k];
    }
    b.joint_type = k < 3 ? MultibodyJointType::kPrismatic : MultibodyJointType::kRevolute;
    b.axis = Eigen::Vector3d::Unit(k % 3);
  }
  model.bodies_ = bodies;
  const int nv = model.nv_, nj = nv - 6;
  model.nq_ = nv + 1;
  auto widen = [&](Eigen::VectorXd& x, const Vector7d& base) {
    Eigen::VectorXd out(model.nq_);
    out << base, x.tail(nj);
    x = out;
  };
  const Eigen::Matrix<double, 6, 1> euler = model.q_nominal_.head<6>();
  widen(model.q_nominal_, FreeFlyerFromEuler(euler));
  widen(model.q_lower_, Vector7d::Constant(-std::numeric_limits<double>::infinity()));
  widen(model.q_upper_, Vector7d::Constant(std::numeric_limits<double>::infinity()));
  model.quaternion_base_ = true;
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
