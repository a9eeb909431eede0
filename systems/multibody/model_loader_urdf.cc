// The URDF: the XML parsed by urdfdom (its errors captured), names, tree shape, a floating or planar joint out of a
// massless world root, each link's <inertial> and the joint tree walked into bodies (model_loader.h lists the
// loader's stages).

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include "framework/files.h"
#include "framework/text.h"
#include "systems/multibody/model_checks.h"
#include "systems/multibody/model_loader.h"
#include "systems/multibody/robot_file_text.h"

namespace rome {

namespace model_loading {

namespace {

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

Eigen::Vector3d ToEigen(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }

Eigen::Isometry3d ToEigen(const urdf::Pose& p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  Eigen::Quaterniond quat(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  X.linear() = quat.normalized().toRotationMatrix();
  X.translation() = ToEigen(p.position);
  return X;
}

}  // namespace

}  // namespace model_loading

using namespace model_loading;

void MultibodyModelLoader::ReadUrdf(LoadState& s, const std::string& urdf_path, const std::string* urdf_text) {
  MultibodyModel& model = s.model;
  const std::string& ufile = s.ufile;
  const SidecarReader& sc = s.sc;
  const json& sidecar = s.sidecar;
  urdf::ModelInterfaceSharedPtr& urdf_model = s.urdf;
  const std::string xml = urdf_text ? CheckTextSize(*urdf_text, "URDF", urdf_path, kMaxUrdfBytes)
                                    : ReadRegularFile(urdf_path, "URDF", kMaxUrdfBytes);
  CheckXmlText(xml, urdf_path);
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
}

// A floating or planar joint out of a massless root (the world).
// The URDF way of writing a floating base (as Pinocchio and Drake read it): a massless root link,
// typically "world", joined to the robot by a 6-DOF floating joint (or a 3-DOF planar joint).
// The joint's child is then the robot's root, and the joint becomes ROME's spatial (planar)
// floating base, exactly as the sidecar's "floating_base" makes one for a URDF without the world
// link; the joint's <origin> is the default nominal base pose. The world link is not a frame of
// the robot (it does not move with it). A floating or planar joint anywhere else is rejected
// (in the walk below), naming it.
void MultibodyModelLoader::ReadFloatingJointFromWorld(LoadState& s) {
  MultibodyModel& model = s.model;
  const std::string& ufile = s.ufile;
  const SidecarReader& sc = s.sc;
  const json& sidecar = s.sidecar;
  auto warn = [&](const std::string& w) { Warn(s, w); };
  urdf::LinkConstSharedPtr& root = s.root;
  root = s.urdf->getRoot();
  if (!root) throw std::runtime_error(ufile + ": no root link");
  Eigen::VectorXd& base_nominal = s.base_nominal;
  for (const auto& joint : root->child_joints) {
    if (joint->type != urdf::Joint::FLOATING && joint->type != urdf::Joint::PLANAR) continue;
    const bool floating = joint->type == urdf::Joint::FLOATING;
    const FloatingBaseType type = floating ? FloatingBaseType::kSpatial : FloatingBaseType::kPlanar;
    const std::string jname = Excerpt(joint->name), rname = Excerpt(root->name);
    const std::string where = ufile + ": " + (floating ? "floating" : "planar") + " joint '" + jname + "'";
    const std::string supported = std::string("; a ") + (floating ? "floating" : "planar") +
                                  " joint is supported only as the single joint of a massless root link (the world), "
                                  "where it becomes the robot's " +
                                  ToString(type) + " floating base";
    if (root->inertial && root->inertial->mass != 0.0)
      throw std::runtime_error(where + ": its parent, root link '" + rname + "', has mass " +
                               Num(root->inertial->mass) + " kg" + supported);
    if (root->child_joints.size() != 1)
      throw std::runtime_error(where + ": root link '" + rname + "' has " + std::to_string(root->child_joints.size()) +
                               " joints" + supported);
    if (sidecar.contains("floating_base") && model.floating_base_ != type)
      sc.Fail("floating_base", std::string("'") + ToString(model.floating_base_) + "' contradicts " + ufile +
                                   ", whose " + (floating ? "floating" : "planar") + " joint '" + jname + "' makes a " +
                                   ToString(type) + " floating base (remove the entry, or make it '" + ToString(type) +
                                   "')");
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
        throw std::runtime_error(where + ": <axis> " + Num3(axis) +
                                 " is not supported; ROME's planar base moves in the "
                                 "world x-z plane, so the planar joint's axis (the plane's normal) must be 0 1 0");
      if (std::abs(X.translation().y()) > 0.0 || std::abs(R(1, 1) - 1.0) > 1e-12)
        throw std::runtime_error(
            where + ": <origin> (xyz " + Num3(X.translation()) +
            ") leaves the world x-z plane or "
            "turns about an axis other than y; ROME's planar base needs y = 0 and rpy = (0, pitch, 0)");
      base_nominal.resize(3);
      base_nominal << X.translation().x(), X.translation().z(), std::atan2(R(0, 2), R(0, 0));
    }
    model.floating_base_ = type;
    warn("link '" + rname + "': massless root of " + (floating ? "floating" : "planar") + " joint '" + jname +
         "': the fixed world, not a frame of the robot; the joint is the robot's " + ToString(type) +
         " floating base (its <origin> is the default nominal base pose)");
    urdf::LinkConstSharedPtr child = s.urdf->getLink(joint->child_link_name);
    if (!child)
      throw std::runtime_error(where + ": child link '" + Excerpt(joint->child_link_name) + "' does not exist");
    root = child;
    break;  // the root's only joint
  }
}

// The virtual bodies of the floating base (the last virtual joint's child is the URDF root link itself), then the root
// link's body, frame and mass.
void MultibodyModelLoader::AddBaseBodies(LoadState& s) {
  const MultibodyModel& model = s.model;
  const urdf::LinkConstSharedPtr& root = s.root;
  std::shared_ptr<std::vector<MultibodyBody>>& bodies = s.bodies;
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
  const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ey = Eigen::Vector3d::UnitY(), ez = Eigen::Vector3d::UnitZ();
  // The last virtual joint's child is the URDF root link itself.
  MultibodyJointType root_type = MultibodyJointType::kFixed;
  Eigen::Vector3d root_axis = ez;
  std::string root_joint_name = "world_fixed";
  switch (model.floating_base_) {
    case FloatingBaseType::kFixed: break;
    case FloatingBaseType::kPlanar:
      add_virtual("base_x", MultibodyJointType::kPrismatic, ex);
      add_virtual("base_z", MultibodyJointType::kPrismatic, ez);
      root_type = MultibodyJointType::kRevolute;
      root_axis = ey;
      root_joint_name = "base_pitch";
      break;
    case FloatingBaseType::kSpatial:
      add_virtual("base_x", MultibodyJointType::kPrismatic, ex);
      add_virtual("base_y", MultibodyJointType::kPrismatic, ey);
      add_virtual("base_z", MultibodyJointType::kPrismatic, ez);
      add_virtual("base_yaw", MultibodyJointType::kRevolute, ez);
      add_virtual("base_pitch", MultibodyJointType::kRevolute, ey);
      root_type = MultibodyJointType::kRevolute;
      root_axis = ex;
      root_joint_name = "base_roll";
      break;
  }
  s.parts.resize(bodies->size());
  s.limits.assign(bodies->size(), {-kInf, kInf});
  {
    MultibodyBody b;
    b.name = root->name;
    b.joint_name = root_joint_name;
    b.parent = static_cast<int>(bodies->size()) - 1;
    b.joint_type = root_type;
    b.axis = root_axis;
    bodies->push_back(b);
    s.parts.emplace_back();
    s.limits.push_back({-kInf, kInf});
    AddFrame(s, root->name, static_cast<int>(bodies->size()) - 1, Eigen::Isometry3d::Identity());
    AddPart(s, static_cast<int>(bodies->size()) - 1, *root, ReadLinkMass(s, *root), nullptr);
  }
}

// Mass properties of one link, checked. Massless: mass 0.
model_loading::LinkMass MultibodyModelLoader::ReadLinkMass(LoadState& s, const urdf::Link& link) {
  const std::string& ufile = s.ufile;
  auto warn = [&](const std::string& w) { Warn(s, w); };
  const std::string where = ufile + ": link '" + Excerpt(link.name) + "'";
  LinkMass lm;
  if (!link.inertial) {
    warn("link '" + Excerpt(link.name) + "': no <inertial>: massless frame");
    return lm;
  }
  const urdf::Inertial& in = *link.inertial;
  const std::pair<const char*, double> values[] = {
      {"<mass value>", in.mass},
      {"<inertia ixx>", in.ixx},
      {"<inertia ixy>", in.ixy},
      {"<inertia ixz>", in.ixz},
      {"<inertia iyy>", in.iyy},
      {"<inertia iyz>", in.iyz},
      {"<inertia izz>", in.izz},
      {"<origin xyz> x", in.origin.position.x},
      {"<origin xyz> y", in.origin.position.y},
      {"<origin xyz> z", in.origin.position.z},
      {"<origin rpy>", in.origin.rotation.w + in.origin.rotation.x + in.origin.rotation.y + in.origin.rotation.z}};
  for (const auto& [what, x] : values)
    if (!std::isfinite(x)) throw std::runtime_error(where + ": <inertial> " + what + " is " + Num(x));
  if (in.mass < 0.0) throw std::runtime_error(where + ": <mass> must be >= 0, got " + Num(in.mass) + " kg");
  if (in.mass > kMaxMass_kg)
    throw std::runtime_error(where + ": <mass> " + Num(in.mass) + " kg exceeds " + Num(kMaxMass_kg) + " kg");
  if (in.mass > 0.0 && in.mass < kMinNonzeroMass_kg)
    throw std::runtime_error(where + ": <mass> " + Num(in.mass) + " kg is below " + Num(kMinNonzeroMass_kg) +
                             " kg; give 0 for a massless frame");
  for (const auto& [what, x] : values)
    if (std::string(what).rfind("<inertia", 0) == 0 && std::abs(x) > kMaxInertia_kgm2)
      throw std::runtime_error(where + ": " + what + " " + Num(x) + " kg m^2 exceeds " + Num(kMaxInertia_kgm2) +
                               " kg m^2");
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
}

// Depth-first walk of the URDF tree, parents before children (iterative: a long chain must not overflow the stack).
// Links on fixed joints are merged into their parent's body.
void MultibodyModelLoader::WalkJointTree(LoadState& s) {
  const std::string& ufile = s.ufile;
  const urdf::ModelInterface& urdf_model = *s.urdf;
  std::shared_ptr<std::vector<MultibodyBody>>& bodies = s.bodies;
  auto warn = [&](const std::string& w) { Warn(s, w); };
  struct Item {
    const urdf::Link* link;
    int body;
    bool merged;  // link is not the body's own frame
    Eigen::Isometry3d X_body_link;
    size_t next_child;
  };
  std::vector<Item> stack;
  stack.push_back({s.root.get(), static_cast<int>(bodies->size()) - 1, false, Eigen::Isometry3d::Identity(), 0});
  int nv_count = static_cast<int>(bodies->size()) - (bodies->back().joint_type == MultibodyJointType::kFixed ? 1 : 0);
  while (!stack.empty()) {
    if (stack.back().next_child >= stack.back().link->child_joints.size()) {
      stack.pop_back();
      continue;
    }
    const Item parent = stack.back();
    const auto& joint = parent.link->child_joints[stack.back().next_child++];
    const std::string jname = Excerpt(joint->name);
    const std::string where = ufile + ": joint '" + jname + "'";
    auto child_it = urdf_model.links_.find(joint->child_link_name);
    if (child_it == urdf_model.links_.end())
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
                                 Excerpt(child.name) +
                                 "' is not supported; a floating or planar joint is supported "
                                 "only as the single joint of a massless root link (the world), where it becomes the "
                                 "floating base");
      default:
        throw std::runtime_error(where +
                                 ": unsupported joint type (only revolute, continuous, "
                                 "prismatic and fixed are supported)");
    }
    if (type == MultibodyJointType::kFixed) {
      // Weld the child link into the parent's body.
      const int body = parent.body;
      (*bodies)[body].merged_links.push_back(child.name);
      AddFrame(s, child.name, body, X_body_joint);
      AddPart(s, body, child, ReadLinkMass(s, child), &X_body_joint);
      warn("link '" + Excerpt(child.name) + "': merged into body '" + Excerpt((*bodies)[body].name) +
           "' (fixed joint '" + jname + "')");
      stack.push_back({&child, body, true, X_body_joint, 0});
      continue;
    }
    if (++nv_count > kMaxDofs)
      throw std::runtime_error(ufile + ": more than " + std::to_string(kMaxDofs) + " degrees of freedom (at joint '" +
                               jname + "'); ROME's dense mass matrix supports at most " + std::to_string(kMaxDofs));
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
      if (lo < hi)
        lim = {lo, hi};
      else
        warn("joint '" + jname + "': <limit> lower == upper (" + Num(lo) + "): treated as no position limit");
    }
    const int index = static_cast<int>(bodies->size());
    bodies->push_back(b);
    s.parts.emplace_back();
    s.limits.push_back(lim);
    AddFrame(s, child.name, index, Eigen::Isometry3d::Identity());
    AddPart(s, index, child, ReadLinkMass(s, child), nullptr);
    stack.push_back({&child, index, false, Eigen::Isometry3d::Identity(), 0});
  }
}

}  // namespace rome
