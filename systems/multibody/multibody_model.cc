#include "systems/multibody/multibody_model.h"
#include "systems/multibody/model_checks.h"
#include "systems/multibody/robot_file_text.h"
#include "systems/multibody/robot_files.h"
#include "framework/files.h"
#include "framework/text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <mutex>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <console_bridge/console.h>
#include <nlohmann/json.hpp>
#include <urdf_parser/urdf_parser.h>

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
  if (it == body_index_.end())
    throw std::invalid_argument("robot '" + name_ + "': no link named '" + link_name + "'");
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

namespace {

using json = nlohmann::json;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Captures urdfdom's console_bridge messages so that parse errors can be reported in the
// exception instead of being printed to stderr. console_bridge's handler is process global.
class CaptureHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR && errors.size() < 4096) {
      if (!errors.empty()) errors += "; ";
      errors += text.substr(0, 1024);
    }
  }
  std::string errors;
};

std::mutex& ConsoleMutex() {
  static std::mutex m;
  return m;
}

std::string Num(double x) {
  if (std::isnan(x)) return "NaN";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", x);
  return buf;
}

std::string Num3(const Eigen::Vector3d& v) { return Num(v[0]) + " " + Num(v[1]) + " " + Num(v[2]); }

// Levenshtein distance, case-insensitive.
size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(b[j - 1]));
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (same ? 0 : 1)});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

// A file a robot package names: `entry`, relative to `folder` (the folder of the file that names it), resolved inside
// that folder tree; with options.allow_files_outside_package, anywhere (an absolute entry as given).
std::string PackageFile(const std::string& folder, const std::string& entry, const std::string& what, const LoadOptions& options) {
  if (entry.find('\0') != std::string::npos) throw std::runtime_error(what + " " + Excerpt(entry, 200) + ": contains a NUL byte");
  if (options.allow_files_outside_package) {
    if (entry.empty()) throw std::runtime_error(what + " '': the path is empty");
    return std::filesystem::path(entry).is_absolute() ? entry : (std::filesystem::path(folder) / entry).string();
  }
  try {
    return ResolveInsideFolder(folder, entry, what);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) + " (allow_files_outside_package lifts this for a package you trust)");
  }
}

std::string FolderOf(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

// Text given in memory instead of a file: the same size cap as ReadRegularFile.
const std::string& CheckTextSize(const std::string& text, const char* what, const std::string& name, std::uintmax_t max_bytes) {
  if (text.size() > max_bytes)
    throw std::runtime_error(std::string(what) + " " + Excerpt(name, 200) + ": text is " + std::to_string(text.size()) +
                             " bytes; the limit is " + std::to_string(max_bytes) + " bytes");
  return text;
}

Eigen::Vector3d ToEigen(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }

Eigen::Isometry3d ToEigen(const urdf::Pose& p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  Eigen::Quaterniond quat(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  X.linear() = quat.normalized().toRotationMatrix();
  X.translation() = ToEigen(p.position);
  return X;
}

// Euclidean projection of principal moments onto the physical cone
// {l : l_i + l_j >= l_k for every permutation} (which implies l >= 0): the nearest physical
// inertia in the Frobenius norm keeps the principal axes. Enumerates the faces of the cone
// (active sets of the 3 constraints); the closest feasible face projection is the projection.
Eigen::Vector3d ProjectPhysicalMoments(const Eigen::Vector3d& l) {
  Eigen::Matrix3d A;  // rows a_k: a_k . x >= 0
  A << 1, 1, -1, 1, -1, 1, -1, 1, 1;
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  double best_dist = (l - best).squaredNorm();
  for (int mask = 0; mask < 8; ++mask) {
    std::vector<int> rows;
    for (int k = 0; k < 3; ++k)
      if (mask & (1 << k)) rows.push_back(k);
    Eigen::Vector3d x = l;
    if (!rows.empty()) {
      Eigen::MatrixXd Aa(rows.size(), 3);
      for (size_t r = 0; r < rows.size(); ++r) Aa.row(r) = A.row(rows[r]);
      // x = l - Aa^T (Aa Aa^T)^-1 Aa l
      const Eigen::MatrixXd G = Aa * Aa.transpose();
      x = l - Aa.transpose() * G.ldlt().solve(Aa * l);
    }
    if ((A * x).minCoeff() < -1e-14 * (1.0 + l.cwiseAbs().maxCoeff())) continue;
    const double d = (l - x).squaredNorm();
    if (d < best_dist) { best_dist = d; best = x; }
  }
  return best.cwiseMax(0.0);
}

// Small helpers that throw "sidecar <file>: <context>: <problem>".
struct SidecarReader {
  std::string file;

  [[noreturn]] void Fail(const std::string& context, const std::string& problem) const {
    throw std::runtime_error("sidecar " + Excerpt(file, 200) + ": " + context + ": " + problem);
  }
  static std::string Dump(const json& v) {
    return Excerpt(v.dump(-1, ' ', false, json::error_handler_t::replace), 60);
  }
  const json& Get(const json& obj, const std::string& key, const std::string& context) const {
    if (!obj.is_object()) Fail(context, "expected a JSON object, got " + Dump(obj));
    auto it = obj.find(key);
    if (it == obj.end()) Fail(context, "missing required entry '" + key + "'");
    return *it;
  }
  // Rejects keys that are not in `known`, suggesting the nearest known key.
  void CheckKeys(const json& obj, std::initializer_list<const char*> known, const std::string& context) const {
    if (!obj.is_object()) Fail(context, "expected a JSON object, got " + Dump(obj));
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      bool ok = false;
      for (const char* k : known) ok |= it.key() == k;
      if (ok) continue;
      std::string nearest, all;
      size_t best = std::numeric_limits<size_t>::max();
      for (const char* k : known) {
        const size_t d = it.key().size() > 64 ? it.key().size() : EditDistance(it.key(), k);
        if (d < best) { best = d; nearest = k; }
        all += std::string(all.empty() ? "" : ", ") + k;
      }
      std::string hint = best <= std::max<size_t>(2, nearest.size() / 3) ? " (did you mean '" + nearest + "'?)"
                                                                           : " (known keys: " + all + ")";
      Fail(context, "unknown key '" + Excerpt(it.key(), 60) + "'" + hint);
    }
  }
  double Number(const json& obj, const std::string& key, const std::string& context) const {
    const json& v = Get(obj, key, context);
    if (!v.is_number()) Fail(context, "'" + key + "' must be a number, got " + Dump(v));
    const double x = v.get<double>();
    if (!std::isfinite(x)) Fail(context, "'" + key + "' is not finite (" + Dump(v) + ")");
    return x;
  }
  double NumberOr(const json& obj, const std::string& key, double fallback,
                  const std::string& context) const {
    if (!obj.contains(key)) return fallback;
    return Number(obj, key, context);
  }
  std::string String(const json& obj, const std::string& key, const std::string& context) const {
    const json& v = Get(obj, key, context);
    if (!v.is_string()) Fail(context, "'" + key + "' must be a string, got " + Dump(v));
    return v.get<std::string>();
  }
  // A point or offset in metres: finite and within +-kMaxLength_m.
  Eigen::Vector3d Vec3(const json& v, const std::string& context) const {
    if (!v.is_array() || v.size() != 3) Fail(context, "expected [x, y, z], got " + Dump(v));
    Eigen::Vector3d out;
    for (int i = 0; i < 3; ++i) {
      if (!v[i].is_number()) Fail(context, "expected numbers in [x, y, z], got " + Dump(v));
      out[i] = v[i].get<double>();
    }
    if (!out.allFinite() || out.cwiseAbs().maxCoeff() > kMaxLength_m)
      Fail(context, "coordinates " + Num3(out) + " m are not finite or exceed " + Num(kMaxLength_m) + " m");
    return out;
  }
  const json& Array(const json& obj, const std::string& key, const std::string& context) const {
    static const json kEmpty = json::array();
    if (!obj.contains(key)) return kEmpty;
    const json& v = obj.at(key);
    if (!v.is_array()) Fail(context, "'" + key + "' must be an array, got " + Dump(v));
    return v;
  }
};

// A magnitude a robot file gives: within [lo, hi], else "<name> <value> <unit> is outside [lo, hi] <unit>".
void CheckMagnitude(const SidecarReader& sc, const std::string& context, const std::string& name, double value, double lo, double hi,
                    const std::string& unit) {
  if (value >= lo && value <= hi) return;
  const std::string u = unit.empty() ? "" : " " + unit;
  sc.Fail(context, name + " " + Num(value) + u + " is outside [" + Num(lo) + ", " + Num(hi) + "]" + u);
}

// Why a contact's points are degenerate ("" if they are not): a line needs two distinct points, a flat contact points
// that span an area (not all on one line), each to 1 um.
std::string DegenerateContactProblem(const ContactInfo& c) {
  constexpr double kResolution_m = 1e-6;
  if (c.type == ContactType::kLine && (c.points[0] - c.points[1]).norm() < kResolution_m) return "line contact points coincide";
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

// Whether two paths name one file (both resolved on the disk; a path that cannot be resolved names no file).
bool SameFile(const std::string& a, const std::string& b) {
  std::error_code ec_a, ec_b;
  const std::filesystem::path ca = std::filesystem::weakly_canonical(a, ec_a), cb = std::filesystem::weakly_canonical(b, ec_b);
  return !ec_a && !ec_b && ca == cb;
}

// The sidecar's "urdf" entry when a URDF is loaded with a sidecar: a non-empty path that is not the sidecar itself.
// One that names another URDF than the one loaded is reported as a warning (a sidecar may be shared by variants).
void CheckSidecarNamesUrdf(const SidecarReader& sc, const std::string& entry, const std::string& urdf_path, const LoadOptions& options,
                           std::vector<std::string>* warnings) {
  if (entry.empty()) sc.Fail("urdf", "the entry is empty; name the URDF file, relative to the sidecar");
  std::string named;
  try {
    named = PackageFile(FolderOf(sc.file), entry, "sidecar " + Excerpt(sc.file, 200) + ": \"urdf\"", options);
  } catch (const std::exception& e) {  // not read here (the URDF was given): what is wrong with it is a warning
    warnings->push_back(e.what());
    return;
  }
  if (SameFile(named, sc.file)) sc.Fail("urdf", "'" + Excerpt(entry) + "' names the sidecar itself; name the URDF file");
  if (!SameFile(named, urdf_path))
    warnings->push_back("sidecar \"urdf\" names '" + Excerpt(entry) + "', but the URDF loaded is '" + Excerpt(urdf_path, 200) +
                        "' (given explicitly)");
}

// Mass properties of one URDF link in its own frame (inertia about the COM, link axes).
// A link's mass properties in its link frame. A non-physical <inertia> is not rejected here: it
// is judged with the body it ends up in (see CheckPhysical below), so `problem` records it.
struct LinkMass {
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  std::string problem;  // empty, or why the <inertia> is not physical (with its principal moments)
};

// One contribution to a body: a link's mass properties expressed in the body frame.
struct BodyPart {
  double mass;
  Eigen::Vector3d com;
  Eigen::Matrix3d inertia;
  std::string link;     // URDF link it comes from
  std::string problem;  // LinkMass::problem
};

// Why a rotational inertia (about the COM) of a body of `mass` kg is not physical, or "" if it is:
// positive semi-definite and I1 + I2 >= I3 for its principal moments, each within a tolerance on
// the body's own scale: kInertiaRelativeTolerance times its largest principal moment, or
// mass * kInertiaLengthTolerance_m^2 (a radius of gyration of 1 um) if larger, so that an inertia
// of pure rounding noise (every entry ~1e-20, as exporters write a point mass) counts as zero.
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

// Mass, COM and rotational inertia about the COM of parts expressed in one frame (exact;
// parallel-axis theorem).
BodyPart CombineParts(const std::vector<BodyPart>& parts) {
  BodyPart total{0.0, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Zero(), "", ""};
  if (parts.size() == 1) {
    total.mass = parts[0].mass;
    total.com = parts[0].com;
    total.inertia = parts[0].inertia;
    return total;
  }
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  for (const BodyPart& part : parts) {
    total.mass += part.mass;
    first_moment += part.mass * part.com;
  }
  if (total.mass == 0.0) return total;
  total.com = first_moment / total.mass;
  for (const BodyPart& part : parts) {
    const Eigen::Vector3d d = part.com - total.com;
    total.inertia += part.inertia + part.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  total.inertia = 0.5 * (total.inertia + total.inertia.transpose()).eval();
  return total;
}

}  // namespace

class MultibodyModelLoader {
 public:
  // urdf_text / sidecar_text, when given, are the files' contents (urdf_path and sidecar_path then only name them,
  // and no sidecar is looked for next to the URDF).
  static MultibodyModel Load(const std::string& urdf_path, std::string sidecar_path, bool sidecar_required,
                             const LoadOptions& options, const std::string* urdf_text = nullptr,
                             const std::string* sidecar_text = nullptr) {
    MultibodyModel model;
    model.urdf_path_ = urdf_path;
    const std::string ufile = "URDF " + Excerpt(urdf_path, 200);
    auto warn = [&](const std::string& w) { model.warnings_.push_back(w); };

    // ---------------- sidecar (parsed first: it decides the floating base) ----------------
    json sidecar = json::object();
    if (urdf_text) {
      sidecar_required = sidecar_text != nullptr;
      if (!sidecar_text) sidecar_path.clear();
    } else if (sidecar_path.empty()) {
      const std::string beside = std::filesystem::path(urdf_path).stem().string() + ".rome.json";
      std::error_code ec;
      if (std::filesystem::exists(std::filesystem::path(FolderOf(urdf_path)) / beside, ec))
        sidecar_path = PackageFile(FolderOf(urdf_path), beside, ufile + ": its sidecar", options);
    } else {
      sidecar_required = true;
    }
    SidecarReader sc{sidecar_path};
    if (!sidecar_path.empty() || sidecar_required) {
      const std::string text = sidecar_text ? CheckTextSize(*sidecar_text, "sidecar", sidecar_path, kMaxUrdfBytes)
                                            : ReadRegularFile(sidecar_path, "sidecar", kMaxUrdfBytes);
      sidecar = ParseSidecarJson(text, sidecar_path);
      if (!sidecar.is_object()) sc.Fail("top level", "expected a JSON object");
      sc.CheckKeys(sidecar, {"robot", "urdf", "floating_base", "actuators", "springs", "contacts", "loop_closures",
                             "nominal_pose"},
                   "top level");
    }
    model.sidecar_path_ = sidecar_path;
    if (!urdf_text && sidecar.contains("urdf")) CheckSidecarNamesUrdf(sc, sc.String(sidecar, "urdf", "urdf"), urdf_path, options, &model.warnings_);

    model.floating_base_ = FloatingBaseType::kFixed;
    if (sidecar.contains("floating_base")) {
      const std::string fb = sc.String(sidecar, "floating_base", "floating_base");
      if (fb == "fixed") model.floating_base_ = FloatingBaseType::kFixed;
      else if (fb == "planar") model.floating_base_ = FloatingBaseType::kPlanar;
      else if (fb == "spatial") model.floating_base_ = FloatingBaseType::kSpatial;
      else sc.Fail("floating_base", "unknown type '" + Excerpt(fb) + "' (expected fixed, planar or spatial)");
    }

    // ---------------- URDF ----------------
    const std::string xml = urdf_text ? CheckTextSize(*urdf_text, "URDF", urdf_path, kMaxUrdfBytes)
                                      : ReadRegularFile(urdf_path, "URDF", kMaxUrdfBytes);
    CheckXmlText(xml, urdf_path);
    urdf::ModelInterfaceSharedPtr urdf_model;
    {
      std::lock_guard<std::mutex> lock(ConsoleMutex());
      CaptureHandler handler;
      console_bridge::OutputHandler* previous = console_bridge::getOutputHandler();
      console_bridge::useOutputHandler(&handler);
      try {
        urdf_model = urdf::parseURDF(xml);
      } catch (const std::exception& e) {
        handler.errors += e.what();
        urdf_model.reset();
      }
      console_bridge::useOutputHandler(previous);
      // urdfdom logs some errors (e.g. an unparsable number) and still returns a model with
      // zeros in their place: any logged error rejects the file.
      if (!urdf_model || !handler.errors.empty())
        throw std::runtime_error(ufile + ": malformed or invalid URDF: " +
                                 (handler.errors.empty() ? "urdfdom could not parse it" : Excerpt(handler.errors, 300)) +
                                 NonFiniteNumberHint(xml));
    }
    auto check_name = [&](const char* what, const std::string& name) {
      if (!IsValidUtf8(name))
        throw std::runtime_error(ufile + ": " + what + " name '" + Excerpt(name) + "' is not valid UTF-8");
    };
    check_name("robot", urdf_model->getName());
    for (const auto& [name, link] : urdf_model->links_) check_name("link", name);
    for (const auto& [name, joint] : urdf_model->joints_) check_name("joint", name);
    CheckUrdfIsTree(*urdf_model, ufile);
    WarnUnmodelledUrdfElements(*urdf_model, &model.warnings_);
    model.name_ = urdf_model->getName();
    if (sidecar.contains("robot")) model.name_ = sc.String(sidecar, "robot", "robot");

    // ---------------- a floating or planar joint out of a massless root (the world) ----------------
    // The URDF way of writing a floating base (as Pinocchio and Drake read it): a massless root link,
    // typically "world", joined to the robot by a 6-DOF floating joint (or a 3-DOF planar joint).
    // The joint's child is then the robot's root, and the joint becomes ROME's spatial (planar)
    // floating base, exactly as the sidecar's "floating_base" makes one for a URDF without the world
    // link; the joint's <origin> is the default nominal base pose. The world link is not a frame of
    // the robot (it does not move with it). A floating or planar joint anywhere else is rejected
    // (in the walk below), naming it.
    urdf::LinkConstSharedPtr root = urdf_model->getRoot();
    if (!root) throw std::runtime_error(ufile + ": no root link");
    Eigen::VectorXd base_nominal;  // default nominal_pose.base from the joint's <origin>
    for (const auto& joint : root->child_joints) {
      if (joint->type != urdf::Joint::FLOATING && joint->type != urdf::Joint::PLANAR) continue;
      const bool floating = joint->type == urdf::Joint::FLOATING;
      const FloatingBaseType type = floating ? FloatingBaseType::kSpatial : FloatingBaseType::kPlanar;
      const std::string jname = Excerpt(joint->name), rname = Excerpt(root->name);
      const std::string where = ufile + ": " + (floating ? "floating" : "planar") + " joint '" + jname + "'";
      const std::string supported = std::string("; a ") + (floating ? "floating" : "planar") +
                                    " joint is supported only as the single joint of a massless root link (the world), "
                                    "where it becomes the robot's " + ToString(type) + " floating base";
      if (root->inertial && root->inertial->mass != 0.0)
        throw std::runtime_error(where + ": its parent, root link '" + rname + "', has mass " + Num(root->inertial->mass) +
                                 " kg" + supported);
      if (root->child_joints.size() != 1)
        throw std::runtime_error(where + ": root link '" + rname + "' has " + std::to_string(root->child_joints.size()) +
                                 " joints" + supported);
      if (sidecar.contains("floating_base") && model.floating_base_ != type)
        sc.Fail("floating_base", std::string("'") + ToString(model.floating_base_) + "' contradicts " + ufile + ", whose " +
                                     (floating ? "floating" : "planar") + " joint '" + jname + "' makes a " +
                                     ToString(type) + " floating base (remove the entry, or make it '" + ToString(type) + "')");
      const Eigen::Isometry3d X = ToEigen(joint->parent_to_joint_origin_transform);
      if (!X.matrix().allFinite() || X.translation().cwiseAbs().maxCoeff() > kMaxLength_m)
        throw std::runtime_error(where + ": <origin> " + Num3(X.translation()) + " m is not finite or exceeds " +
                                 Num(kMaxLength_m) + " m");
      const Eigen::Matrix3d& R = X.linear();
      if (floating) {
        // q_base = [x, y, z, yaw, pitch, roll], R = Rz(yaw) Ry(pitch) Rx(roll).
        base_nominal.resize(6);
        base_nominal << X.translation(), std::atan2(R(1, 0), R(0, 0)), std::asin(std::clamp(-R(2, 0), -1.0, 1.0)),
            std::atan2(R(2, 1), R(2, 2));
      } else {
        // ROME's planar base moves in the world x-z plane and pitches about +y: the URDF planar joint
        // must have that plane (normal +y) and an <origin> within it.
        const Eigen::Vector3d axis = ToEigen(joint->axis);
        const double scale = axis.cwiseAbs().maxCoeff();
        if (!axis.allFinite() || !(scale > 0.0) || ((axis / scale).normalized() - Eigen::Vector3d::UnitY()).norm() > 1e-9)
          throw std::runtime_error(where + ": <axis> " + Num3(axis) + " is not supported; ROME's planar base moves in the "
                                   "world x-z plane, so the planar joint's axis (the plane's normal) must be 0 1 0");
        if (std::abs(X.translation().y()) > 0.0 || std::abs(R(1, 1) - 1.0) > 1e-12)
          throw std::runtime_error(where + ": <origin> (xyz " + Num3(X.translation()) + ") leaves the world x-z plane or "
                                   "turns about an axis other than y; ROME's planar base needs y = 0 and rpy = (0, pitch, 0)");
        base_nominal.resize(3);
        base_nominal << X.translation().x(), X.translation().z(), std::atan2(R(0, 2), R(0, 0));
      }
      model.floating_base_ = type;
      warn("link '" + rname + "': massless root of " + (floating ? "floating" : "planar") + " joint '" + jname +
           "': the fixed world, not a frame of the robot; the joint is the robot's " + ToString(type) +
           " floating base (its <origin> is the default nominal base pose)");
      urdf::LinkConstSharedPtr child = urdf_model->getLink(joint->child_link_name);
      if (!child) throw std::runtime_error(where + ": child link '" + Excerpt(joint->child_link_name) + "' does not exist");
      root = child;
      break;  // the root's only joint
    }

    auto bodies = std::make_shared<std::vector<MultibodyBody>>();
    auto add_virtual = [&](const std::string& joint, MultibodyJointType type, Eigen::Vector3d axis) {
      MultibodyBody b;
      b.name = "floating_" + joint;
      b.joint_name = joint;
      b.parent = static_cast<int>(bodies->size()) - 1;
      b.joint_type = type;
      b.axis = axis;
      b.is_virtual = true;
      bodies->push_back(b);
    };
    const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ey = Eigen::Vector3d::UnitY(),
                          ez = Eigen::Vector3d::UnitZ();
    // The last virtual joint's child is the URDF root link itself.
    MultibodyJointType root_type = MultibodyJointType::kFixed;
    Eigen::Vector3d root_axis = ez;
    std::string root_joint_name = "world_fixed";
    switch (model.floating_base_) {
      case FloatingBaseType::kFixed: break;
      case FloatingBaseType::kPlanar:
        add_virtual("base_x", MultibodyJointType::kPrismatic, ex);
        add_virtual("base_z", MultibodyJointType::kPrismatic, ez);
        root_type = MultibodyJointType::kRevolute; root_axis = ey; root_joint_name = "base_pitch";
        break;
      case FloatingBaseType::kSpatial:
        add_virtual("base_x", MultibodyJointType::kPrismatic, ex);
        add_virtual("base_y", MultibodyJointType::kPrismatic, ey);
        add_virtual("base_z", MultibodyJointType::kPrismatic, ez);
        add_virtual("base_yaw", MultibodyJointType::kRevolute, ez);
        add_virtual("base_pitch", MultibodyJointType::kRevolute, ey);
        root_type = MultibodyJointType::kRevolute; root_axis = ex; root_joint_name = "base_roll";
        break;
    }

    // Mass properties of one link, checked (and repaired if asked). Massless: mass 0.
    auto link_mass = [&](const urdf::Link& link) -> LinkMass {
      const std::string where = ufile + ": link '" + Excerpt(link.name) + "'";
      LinkMass lm;
      if (!link.inertial) {
        warn("link '" + Excerpt(link.name) + "': no <inertial>: massless frame");
        return lm;
      }
      const urdf::Inertial& in = *link.inertial;
      const std::pair<const char*, double> values[] = {
          {"<mass value>", in.mass}, {"<inertia ixx>", in.ixx}, {"<inertia ixy>", in.ixy},
          {"<inertia ixz>", in.ixz}, {"<inertia iyy>", in.iyy}, {"<inertia iyz>", in.iyz},
          {"<inertia izz>", in.izz}, {"<origin xyz> x", in.origin.position.x},
          {"<origin xyz> y", in.origin.position.y}, {"<origin xyz> z", in.origin.position.z},
          {"<origin rpy>", in.origin.rotation.w + in.origin.rotation.x + in.origin.rotation.y + in.origin.rotation.z}};
      for (const auto& [what, x] : values)
        if (!std::isfinite(x)) throw std::runtime_error(where + ": <inertial> " + what + " is " + Num(x));
      if (in.mass < 0.0) throw std::runtime_error(where + ": <mass> must be >= 0, got " + Num(in.mass) + " kg");
      if (in.mass > kMaxMass_kg)
        throw std::runtime_error(where + ": <mass> " + Num(in.mass) + " kg exceeds " + Num(kMaxMass_kg) + " kg");
      for (const auto& [what, x] : values)
        if (std::string(what).rfind("<inertia", 0) == 0 && std::abs(x) > kMaxInertia_kgm2)
          throw std::runtime_error(where + ": " + what + " " + Num(x) + " kg m^2 exceeds " + Num(kMaxInertia_kgm2) + " kg m^2");
      const Eigen::Isometry3d X = ToEigen(in.origin);
      if (X.translation().cwiseAbs().maxCoeff() > kMaxLength_m)
        throw std::runtime_error(where + ": <inertial> <origin xyz> " + Num3(X.translation()) + " m exceeds " +
                                 Num(kMaxLength_m) + " m");
      Eigen::Matrix3d I_in;
      I_in << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      if (in.mass == 0.0) {
        warn("link '" + Excerpt(link.name) + "': mass 0: massless frame" +
             (I_in.isZero(0.0) ? "" : " (its nonzero <inertia> is ignored)"));
        return lm;
      }
      lm.mass = in.mass;
      lm.com = X.translation();
      lm.inertia = X.linear() * I_in * X.linear().transpose();
      lm.problem = PhysicalInertiaProblem(I_in, in.mass);
      return lm;
    };

    // Depth-first walk of the URDF tree, parents before children (iterative: a long chain must
    // not overflow the stack). Links on fixed joints are merged into their parent's body.
    std::vector<std::vector<BodyPart>> parts;  // per body
    std::vector<std::pair<double, double>> limits;  // per body
    auto add_frame = [&](const std::string& link, int body, const Eigen::Isometry3d& X_body_link) {
      model.frame_index_[link] = static_cast<int>(model.frames_.size());
      model.frames_.push_back({link, body, X_body_link});
      model.body_index_[link] = body;
    };
    auto add_part = [&](int body, const urdf::Link& link, const LinkMass& lm, const Eigen::Isometry3d* X_body_link) {
      if (lm.mass == 0.0) return;
      if (!X_body_link) {
        parts[body].push_back({lm.mass, lm.com, lm.inertia, link.name, lm.problem});
      } else {
        // Zero first: GCC 12 at -O1 warns (maybe-uninitialized) on a Matrix3d built straight from linear().
        Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
        R = X_body_link->linear();
        const Eigen::Matrix3d inertia = R * lm.inertia * R.transpose();
        parts[body].push_back({lm.mass, *X_body_link * lm.com, inertia, link.name, lm.problem});
      }
    };
    parts.resize(bodies->size());
    limits.assign(bodies->size(), {-kInf, kInf});
    {
      MultibodyBody b;
      b.name = root->name;
      b.joint_name = root_joint_name;
      b.parent = static_cast<int>(bodies->size()) - 1;
      b.joint_type = root_type;
      b.axis = root_axis;
      bodies->push_back(b);
      parts.emplace_back();
      limits.push_back({-kInf, kInf});
      add_frame(root->name, static_cast<int>(bodies->size()) - 1, Eigen::Isometry3d::Identity());
      add_part(static_cast<int>(bodies->size()) - 1, *root, link_mass(*root), nullptr);
    }
    struct Item {
      const urdf::Link* link;
      int body;
      bool merged;                  // link is not the body's own frame
      Eigen::Isometry3d X_body_link;
      size_t next_child;
    };
    std::vector<Item> stack;
    stack.push_back({root.get(), static_cast<int>(bodies->size()) - 1, false, Eigen::Isometry3d::Identity(), 0});
    int nv_count = static_cast<int>(bodies->size()) - (root_type == MultibodyJointType::kFixed ? 1 : 0);
    while (!stack.empty()) {
      if (stack.back().next_child >= stack.back().link->child_joints.size()) {
        stack.pop_back();
        continue;
      }
      const Item parent = stack.back();
      const auto& joint = parent.link->child_joints[stack.back().next_child++];
      const std::string jname = Excerpt(joint->name);
      const std::string where = ufile + ": joint '" + jname + "'";
      auto child_it = urdf_model->links_.find(joint->child_link_name);
      if (child_it == urdf_model->links_.end())
        throw std::runtime_error(where + ": child link '" + Excerpt(joint->child_link_name) + "' does not exist");
      const urdf::Link& child = *child_it->second;
      const Eigen::Isometry3d X_link_joint = ToEigen(joint->parent_to_joint_origin_transform);
      if (!X_link_joint.matrix().allFinite() || X_link_joint.translation().cwiseAbs().maxCoeff() > kMaxLength_m)
        throw std::runtime_error(where + ": <origin> " + Num3(X_link_joint.translation()) +
                                 " m is not finite or exceeds " + Num(kMaxLength_m) + " m");
      const Eigen::Isometry3d X_body_joint = parent.merged ? parent.X_body_link * X_link_joint : X_link_joint;
      MultibodyJointType type;
      switch (joint->type) {
        case urdf::Joint::REVOLUTE:
        case urdf::Joint::CONTINUOUS: type = MultibodyJointType::kRevolute; break;
        case urdf::Joint::PRISMATIC: type = MultibodyJointType::kPrismatic; break;
        case urdf::Joint::FIXED: type = MultibodyJointType::kFixed; break;
        case urdf::Joint::FLOATING:
        case urdf::Joint::PLANAR:
          throw std::runtime_error(ufile + ": " + (joint->type == urdf::Joint::FLOATING ? "floating" : "planar") +
                                   " joint '" + jname + "' between links '" + Excerpt(parent.link->name) + "' and '" +
                                   Excerpt(child.name) + "' is not supported; a floating or planar joint is supported "
                                   "only as the single joint of a massless root link (the world), where it becomes the "
                                   "floating base");
        default:
          throw std::runtime_error(where + ": unsupported joint type (only revolute, continuous, "
                                   "prismatic and fixed are supported)");
      }
      if (type == MultibodyJointType::kFixed) {
        // Weld the child link into the parent's body.
        const int body = parent.body;
        (*bodies)[body].merged_links.push_back(child.name);
        add_frame(child.name, body, X_body_joint);
        add_part(body, child, link_mass(child), &X_body_joint);
        warn("link '" + Excerpt(child.name) + "': merged into body '" + Excerpt((*bodies)[body].name) +
             "' (fixed joint '" + jname + "')");
        stack.push_back({&child, body, true, X_body_joint, 0});
        continue;
      }
      if (++nv_count > kMaxDofs)
        throw std::runtime_error(ufile + ": more than " + std::to_string(kMaxDofs) +
                                 " degrees of freedom (at joint '" + jname + "'); ROME's dense mass matrix supports at most " +
                                 std::to_string(kMaxDofs));
      MultibodyBody b;
      b.name = child.name;
      b.joint_name = joint->name;
      b.parent = parent.body;
      b.joint_type = type;
      b.X_parent_joint = X_body_joint;
      b.axis = UnitAxis(ToEigen(joint->axis), where);
      std::pair<double, double> lim{-kInf, kInf};
      if (joint->type != urdf::Joint::CONTINUOUS && joint->limits) {
        const double lo = joint->limits->lower, hi = joint->limits->upper;
        if (std::isnan(lo) || std::isnan(hi) || lo > hi)
          throw std::runtime_error(where + ": <limit> lower " + Num(lo) + " must not exceed upper " + Num(hi));
        if (lo < hi) lim = {lo, hi};
        else warn("joint '" + jname + "': <limit> lower == upper (" + Num(lo) + "): treated as no position limit");
      }
      const int index = static_cast<int>(bodies->size());
      bodies->push_back(b);
      parts.emplace_back();
      limits.push_back(lim);
      add_frame(child.name, index, Eigen::Isometry3d::Identity());
      add_part(index, child, link_mass(child), nullptr);
      stack.push_back({&child, index, false, Eigen::Isometry3d::Identity(), 0});
    }

    // Physical validity is a property of the rigid body the dynamics sees. A link whose own
    // <inertia> is not physical (a dummy value on a sensor, foot or base frame) is accepted, with
    // a warning, when it is welded into a body whose combined inertia is physical; otherwise it is
    // rejected naming the link (or repaired with LoadOptions::repair_inertia).
    for (size_t i = 0; i < bodies->size(); ++i) {
      std::vector<BodyPart>& p = parts[i];
      bool any_problem = false;
      for (const BodyPart& part : p) any_problem = any_problem || !part.problem.empty();
      if (!any_problem) continue;
      const std::string body_name = Excerpt((*bodies)[i].name);
      const bool welded = p.size() > 1;
      const BodyPart combined = CombineParts(p);
      const bool body_physical = welded && PhysicalInertiaProblem(combined.inertia, combined.mass).empty();
      for (BodyPart& part : p) {
        if (part.problem.empty()) continue;
        const std::string link = Excerpt(part.link);
        if (body_physical) {
          warn("link '" + link + "': <inertia> " + part.problem + ": accepted, because rigid body '" + body_name +
               "' (its links merged over fixed joints) has a physical combined inertia");
          continue;
        }
        if (!options.repair_inertia)
          throw std::runtime_error(ufile + ": link '" + link + "': <inertia> " + part.problem +
                                   (welded ? ", and so does rigid body '" + body_name + "' (its links merged over fixed joints)" : "") +
                                   "; fix it, or repair it with model_info --repair-inertia / LoadOptions::repair_inertia");
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(part.inertia);
        const Eigen::Vector3d fixed = ProjectPhysicalMoments(eig.eigenvalues());
        part.inertia = eig.eigenvectors() * fixed.asDiagonal() * eig.eigenvectors().transpose();
        warn("link '" + link + "': <inertia> " + part.problem + ": repaired to the nearest physical inertia " +
             "(principal moments " + Num3(fixed) + " kg m^2)");
      }
    }

    // Combine the parts of each body (exact; parallel-axis theorem about the combined COM) and
    // find its principal frame.
    for (size_t i = 0; i < bodies->size(); ++i) {
      MultibodyBody& b = (*bodies)[i];
      const std::vector<BodyPart>& p = parts[i];
      if (!p.empty()) {
        const BodyPart total = CombineParts(p);
        b.mass = total.mass;
        b.com = total.com;
        b.inertia = total.inertia;
      }
      if (b.inertia.isZero(0.0)) {
        b.principal_moments.setZero();
        b.R_link_principal.setIdentity();
      } else {
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(b.inertia);
        b.principal_moments = eig.eigenvalues();
        b.R_link_principal = eig.eigenvectors();
        if (b.R_link_principal.determinant() < 0) b.R_link_principal.col(2) *= -1.0;
        if (b.principal_moments.minCoeff() < 0.0) {  // rounding within the tolerance
          b.principal_moments = b.principal_moments.cwiseMax(0.0);
          b.inertia = b.R_link_principal * b.principal_moments.asDiagonal() * b.R_link_principal.transpose();
        }
      }
    }

    // Degrees of freedom in body order (matches Bullet's dof order).
    int nv = 0;
    for (int i = 0; i < static_cast<int>(bodies->size()); ++i) {
      MultibodyBody& b = (*bodies)[i];
      if (b.is_virtual) model.body_index_[b.name] = i;
      if (b.joint_type != MultibodyJointType::kFixed) {
        b.v_index = nv++;
        model.joint_index_[b.joint_name] = b.v_index;
        model.joint_names_.push_back(b.joint_name);
        model.body_of_v_.push_back(i);
      }
      model.total_mass_ += b.mass;
    }
    model.nv_ = nv;
    model.q_lower_.setConstant(nv, -kInf);
    model.q_upper_.setConstant(nv, kInf);
    for (int i = 0; i < static_cast<int>(bodies->size()); ++i) {
      const int k = (*bodies)[i].v_index;
      if (k >= 0) { model.q_lower_[k] = limits[i].first; model.q_upper_[k] = limits[i].second; }
    }
    model.bodies_ = bodies;
    if (model.floating_base_ == FloatingBaseType::kPlanar) CheckPlanarJoints(model, ufile);

    auto movable_joint = [&](const std::string& joint, const std::string& context) {
      if (!model.joint_index_.count(joint)) {
        if (urdf_model->joints_.count(joint))
          sc.Fail(context, "joint '" + Excerpt(joint) + "' is fixed in " + ufile + " and cannot be used here");
        sc.Fail(context, "joint '" + Excerpt(joint) + "' does not exist in " + ufile);
      }
      return model.joint_index_.at(joint);
    };
    auto existing_frame = [&](const std::string& link, const std::string& context) -> const MultibodyFrame& {
      if (!model.frame_index_.count(link))
        sc.Fail(context, "link '" + Excerpt(link) + "' does not exist in " + ufile);
      return model.frames_[model.frame_index_.at(link)];
    };
    auto to_body = [](const MultibodyFrame& f, const Eigen::Vector3d& p) -> Eigen::Vector3d {
      return f.X_body_frame.isApprox(Eigen::Isometry3d::Identity(), 0.0) ? p : Eigen::Vector3d(f.X_body_frame * p);
    };

    // ---------------- actuators ----------------
    model.reflected_inertia_.setZero(nv);
    const json& acts = sc.Array(sidecar, "actuators", "actuators");
    for (size_t i = 0; i < acts.size(); ++i) {
      std::string ctx = "actuators[" + std::to_string(i) + "]";
      sc.CheckKeys(acts[i], {"joint", "gear_ratio", "reflected_inertia_kgm2", "torque_limit_Nm"}, ctx);
      ActuatorInfo a;
      a.joint = sc.String(acts[i], "joint", ctx);
      ctx += " (joint '" + Excerpt(a.joint) + "')";
      a.v_index = movable_joint(a.joint, ctx);
      a.gear_ratio = sc.NumberOr(acts[i], "gear_ratio", 1.0, ctx);
      a.reflected_inertia_kgm2 = sc.NumberOr(acts[i], "reflected_inertia_kgm2", 0.0, ctx);
      if (acts[i].contains("torque_limit_Nm")) {
        a.torque_limit_Nm = sc.Number(acts[i], "torque_limit_Nm", ctx);
        if (!(a.torque_limit_Nm > 0.0)) sc.Fail(ctx, "torque_limit_Nm must be positive, got " + Num(a.torque_limit_Nm));
      } else {
        auto jit = urdf_model->joints_.find(a.joint);
        const double effort = jit != urdf_model->joints_.end() && jit->second->limits ? jit->second->limits->effort : kInf;
        if (!std::isfinite(effort) || !(effort > 0.0))
          sc.Fail(ctx, "no torque limit: no torque_limit_Nm here and the URDF <limit effort> is " +
                           (effort == kInf ? std::string("missing") : Num(effort)) +
                           " (give a positive torque_limit_Nm)");
        a.torque_limit_Nm = effort;
      }
      CheckMagnitude(sc, ctx, "torque limit (torque_limit_Nm or the URDF <limit effort>)", a.torque_limit_Nm, kMinTorqueLimit_Nm, kMaxTorqueLimit_Nm, "N m");
      if (a.reflected_inertia_kgm2 != 0.0)
        CheckMagnitude(sc, ctx, "reflected_inertia_kgm2", a.reflected_inertia_kgm2, kMinPositiveParameter, kMaxInertia_kgm2, "kg m^2");
      CheckMagnitude(sc, ctx, "gear_ratio", a.gear_ratio, kMinGearRatio, kMaxGearRatio, "");
      for (const auto& other : model.actuators_)
        if (other.v_index == a.v_index) sc.Fail(ctx, "joint '" + Excerpt(a.joint) + "' is actuated twice");
      model.reflected_inertia_[a.v_index] += a.reflected_inertia_kgm2;
      model.actuators_.push_back(a);
    }
    const int nu = static_cast<int>(model.actuators_.size());
    model.B_.setZero(nv, nu);
    model.torque_limits_.resize(nu);
    for (int i = 0; i < nu; ++i) {
      model.B_(model.actuators_[i].v_index, i) = 1.0;
      model.torque_limits_[i] = model.actuators_[i].torque_limit_Nm;
    }

    // ---------------- a moving joint must move some mass (else M is singular) ----------------
    bool any_inertial = false;
    for (const auto& [name, link] : urdf_model->links_) any_inertial = any_inertial || link->inertial != nullptr;
    CheckEveryJointMovesMass(model, ufile, any_inertial ? "" : " (no link in this URDF has an <inertial>: it describes kinematics only)");

    // ---------------- springs ----------------
    model.spring_stiffness_.setZero(nv);
    model.spring_damping_.setZero(nv);
    model.spring_rest_.setZero(nv);
    const json& springs = sc.Array(sidecar, "springs", "springs");
    for (size_t i = 0; i < springs.size(); ++i) {
      std::string ctx = "springs[" + std::to_string(i) + "]";
      sc.CheckKeys(springs[i], {"joint", "stiffness_Nm_per_rad", "damping_Nms_per_rad", "rest_angle_rad"}, ctx);
      SpringInfo s;
      s.joint = sc.String(springs[i], "joint", ctx);
      ctx += " (joint '" + Excerpt(s.joint) + "')";
      s.v_index = movable_joint(s.joint, ctx);
      s.stiffness_Nm_per_rad = sc.Number(springs[i], "stiffness_Nm_per_rad", ctx);
      s.damping_Nms_per_rad = sc.NumberOr(springs[i], "damping_Nms_per_rad", 0.0, ctx);
      s.rest_angle_rad = sc.NumberOr(springs[i], "rest_angle_rad", 0.0, ctx);
      if (s.stiffness_Nm_per_rad < 0.0 || s.damping_Nms_per_rad < 0.0)
        sc.Fail(ctx, "stiffness and damping must be >= 0, got " + Num(s.stiffness_Nm_per_rad) + " and " +
                         Num(s.damping_Nms_per_rad));
      if (s.stiffness_Nm_per_rad != 0.0)
        CheckMagnitude(sc, ctx, "stiffness_Nm_per_rad", s.stiffness_Nm_per_rad, kMinPositiveParameter, kMaxSpringStiffness_Nm_per_rad, "N m/rad");
      if (s.damping_Nms_per_rad != 0.0)
        CheckMagnitude(sc, ctx, "damping_Nms_per_rad", s.damping_Nms_per_rad, kMinPositiveParameter, kMaxSpringDamping_Nms_per_rad, "N m s/rad");
      if (std::abs(s.rest_angle_rad) > kMaxJointAngle_rad)
        sc.Fail(ctx, "rest_angle_rad " + Num(s.rest_angle_rad) + " is beyond +-" + Num(kMaxJointAngle_rad) + " rad");
      for (const auto& other : model.springs_)
        if (other.v_index == s.v_index) sc.Fail(ctx, "joint '" + Excerpt(s.joint) + "' has a second spring");
      model.spring_stiffness_[s.v_index] = s.stiffness_Nm_per_rad;
      model.spring_damping_[s.v_index] = s.damping_Nms_per_rad;
      model.spring_rest_[s.v_index] = s.rest_angle_rad;
      model.springs_.push_back(s);
    }

    // ---------------- contacts ----------------
    const bool planar = model.floating_base_ == FloatingBaseType::kPlanar;
    const json& contacts = sc.Array(sidecar, "contacts", "contacts");
    if (contacts.size() > 64) sc.Fail("contacts", "at most 64 contacts are supported, got " + std::to_string(contacts.size()));
    for (size_t i = 0; i < contacts.size(); ++i) {
      ContactInfo c;
      c.name = sc.String(contacts[i], "name", "contacts[" + std::to_string(i) + "]");
      const std::string ctx = "contacts[" + std::to_string(i) + "] ('" + Excerpt(c.name) + "')";
      sc.CheckKeys(contacts[i], {"name", "link", "type", "points", "friction_coefficient"}, ctx);
      c.link = sc.String(contacts[i], "link", ctx);
      const MultibodyFrame& frame = existing_frame(c.link, ctx);
      c.body = frame.body;
      const std::string type = sc.String(contacts[i], "type", ctx);
      size_t min_points = 1, max_points = 1;
      if (type == "point") { c.type = ContactType::kPoint; }
      else if (type == "line") { c.type = ContactType::kLine; min_points = max_points = 2; }
      else if (type == "flat") { c.type = ContactType::kFlat; min_points = 3; max_points = 64; }
      else sc.Fail(ctx, "unknown contact type '" + Excerpt(type) + "' (expected point, line or flat)");
      const json& pts = sc.Get(contacts[i], "points", ctx);
      if (!pts.is_array() || pts.size() < min_points || pts.size() > max_points)
        sc.Fail(ctx, "a " + type + " contact needs " + std::to_string(min_points) +
                         (max_points > min_points ? "+" : "") + " points, got " + SidecarReader::Dump(pts));
      for (const auto& p : pts) c.points.push_back(sc.Vec3(p, ctx + " points"));
      c.friction_coefficient = sc.NumberOr(contacts[i], "friction_coefficient", 1.0, ctx);
      CheckMagnitude(sc, ctx, "friction_coefficient", c.friction_coefficient, kMinFrictionCoefficient, kMaxFrictionCoefficient, "");
      if (const std::string problem = DegenerateContactProblem(c); !problem.empty()) sc.Fail(ctx, problem);
      for (auto& p : c.points) p = to_body(frame, p);
      c.frame_origin.setZero();
      for (const auto& p : c.points) c.frame_origin += p;
      c.frame_origin /= static_cast<double>(c.points.size());
      if (planar) c.num_rows = c.type == ContactType::kPoint ? 2 : 3;
      else c.num_rows = c.type == ContactType::kPoint ? 3 : (c.type == ContactType::kLine ? 5 : 6);
      if (model.contact_index_.count(c.name)) sc.Fail(ctx, "duplicate contact name");
      model.contact_index_[c.name] = static_cast<int>(model.contacts_.size());
      model.max_constraint_rows_ += c.num_rows;
      model.contacts_.push_back(c);
    }

    // ---------------- loop closures ----------------
    const json& loops = sc.Array(sidecar, "loop_closures", "loop_closures");
    for (size_t i = 0; i < loops.size(); ++i) {
      LoopClosureInfo l;
      l.name = sc.String(loops[i], "name", "loop_closures[" + std::to_string(i) + "]");
      const std::string ctx = "loop_closures[" + std::to_string(i) + "] ('" + Excerpt(l.name) + "')";
      sc.CheckKeys(loops[i], {"name", "link_a", "point_a", "link_b", "point_b", "distance_m"}, ctx);
      for (const auto& other : model.loop_closures_)
        if (other.name == l.name) sc.Fail(ctx, "duplicate loop closure name");
      l.link_a = sc.String(loops[i], "link_a", ctx);
      l.link_b = sc.String(loops[i], "link_b", ctx);
      const MultibodyFrame& fa = existing_frame(l.link_a, ctx + " link_a");
      const MultibodyFrame& fb = existing_frame(l.link_b, ctx + " link_b");
      l.body_a = fa.body;
      l.body_b = fb.body;
      l.point_a = to_body(fa, sc.Vec3(sc.Get(loops[i], "point_a", ctx), ctx + " point_a"));
      l.point_b = to_body(fb, sc.Vec3(sc.Get(loops[i], "point_b", ctx), ctx + " point_b"));
      l.distance_m = sc.Number(loops[i], "distance_m", ctx);
      if (!(l.distance_m > 0.0) || l.distance_m > kMaxLength_m)
        sc.Fail(ctx, "distance_m must be positive and at most " + Num(kMaxLength_m) + " m, got " + Num(l.distance_m));
      model.max_constraint_rows_ += 1;
      model.loop_closures_.push_back(l);
    }

    // ---------------- nominal pose ----------------
    model.q_nominal_.setZero(nv);
    std::vector<bool> given(static_cast<size_t>(nv), false);  // joints the sidecar's nominal_pose.joints gives
    if (base_nominal.size() == model.num_base_dofs()) model.q_nominal_.head(base_nominal.size()) = base_nominal;
    if (sidecar.contains("nominal_pose")) {
      const json& pose = sidecar.at("nominal_pose");
      sc.CheckKeys(pose, {"base", "joints"}, "nominal_pose");
      const json& base = sc.Array(pose, "base", "nominal_pose");
      const int nb = model.num_base_dofs();
      if (pose.contains("base")) {
        if (static_cast<int>(base.size()) != nb)
          sc.Fail("nominal_pose.base", "expected " + std::to_string(nb) + " numbers for a " +
                                           ToString(model.floating_base_) + " base, got " + SidecarReader::Dump(base));
        for (int k = 0; k < nb; ++k) {
          if (!base[k].is_number()) sc.Fail("nominal_pose.base", "expected numbers, got " + SidecarReader::Dump(base));
          const double x = base[k].get<double>();
          if (!std::isfinite(x) || std::abs(x) > kMaxLength_m)
            sc.Fail("nominal_pose.base", "entry " + std::to_string(k) + " is " + Num(x) + " (not finite or beyond " +
                                             Num(kMaxLength_m) + ")");
          model.q_nominal_[k] = x;
        }
      }
      if (pose.contains("joints")) {
        const json& joints = pose.at("joints");
        if (!joints.is_object()) sc.Fail("nominal_pose.joints", "expected an object {joint: angle}");
        for (auto it = joints.begin(); it != joints.end(); ++it) {
          const std::string ctx = "nominal_pose.joints['" + Excerpt(it.key()) + "']";
          const int k = movable_joint(it.key(), ctx);
          if (!it.value().is_number()) sc.Fail(ctx, "expected a number, got " + SidecarReader::Dump(it.value()));
          const double x = it.value().get<double>();
          if (!std::isfinite(x) || std::abs(x) > kMaxLength_m)
            sc.Fail(ctx, "value " + Num(x) + " is not finite or beyond " + Num(kMaxLength_m));
          model.q_nominal_[k] = x;
          given[static_cast<size_t>(k)] = true;
        }
      }
    }
    CheckNominalPose(model, sidecar_path.empty() ? ufile : "sidecar " + Excerpt(sidecar_path, 200), given, &model.warnings_);
    return model;
  }

 private:
  // Rejects a moving joint whose diagonal entry of M at q = 0 (without armature) is zero: the
  // mass it moves (prismatic), or the moment of inertia of everything it moves about its axis
  // (revolute), relative to the robot's scale. A sidecar armature (reflected inertia) on the
  // joint makes the row nonsingular and is accepted.
  static void CheckEveryJointMovesMass(const MultibodyModel& model, const std::string& ufile, const std::string& hint) {
    const std::vector<MultibodyBody>& bodies = *model.bodies_;
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
      if (bodies[i].parent < 0) { total_m += m[i]; total_J += J[i]; }
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
      if (b.joint_type == MultibodyJointType::kFixed || model.reflected_inertia_[b.v_index] > 0.0) continue;
      const bool prismatic = b.joint_type == MultibodyJointType::kPrismatic;
      if (value[i] > (prismatic ? tol_prismatic : tol_revolute)) continue;
      const std::string carried = b.is_virtual ? "the whole robot" : "link '" + Excerpt(b.name) + "' and its descendants";
      const std::string verb = b.is_virtual ? " is" : " are";
      throw std::runtime_error(
          ufile + ": joint '" + Excerpt(b.joint_name) + "' moves " +
          (m[i] == 0.0 ? "no mass (" + carried + verb + " massless)"
                       : "no inertia about its axis (" + carried + (b.is_virtual ? " has" : " have") +
                             " all the mass on the axis)") +
          ", so the mass matrix is singular" + hint + "; give them an <inertial>, or the joint a reflected_inertia_kgm2 in the sidecar");
    }
  }
};

MultibodyModel MultibodyModel::Load(const std::string& urdf_path, const std::string& sidecar_path,
                                    const LoadOptions& options) {
  return MultibodyModelLoader::Load(FindRobotFile(urdf_path), sidecar_path.empty() ? sidecar_path : FindRobotFile(sidecar_path), false, options);
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
  if (SameFile(urdf_path, sidecar_path)) sc.Fail("urdf", "'" + Excerpt(entry) + "' names the sidecar itself; name the URDF file");
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
