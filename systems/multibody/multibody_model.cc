#include "systems/multibody/multibody_model.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>
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

// Captures urdfdom's console_bridge messages so that parse errors can be reported in the
// exception instead of being printed to stderr. console_bridge's handler is process global.
class CaptureHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) {
      if (!errors.empty()) errors += "; ";
      errors += text;
    }
  }
  std::string errors;
};

std::mutex& ConsoleMutex() {
  static std::mutex m;
  return m;
}

std::string ReadFile(const std::string& path, const char* what) {
  if (!std::filesystem::exists(path))
    throw std::runtime_error(std::string(what) + " " + path + ": file does not exist");
  std::ifstream in(path);
  if (!in) throw std::runtime_error(std::string(what) + " " + path + ": cannot be opened");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Eigen::Vector3d ToEigen(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }

Eigen::Isometry3d ToEigen(const urdf::Pose& p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  Eigen::Quaterniond quat(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  X.linear() = quat.normalized().toRotationMatrix();
  X.translation() = ToEigen(p.position);
  return X;
}

// Small helpers that throw "sidecar <file>: <context>: <problem>".
struct SidecarReader {
  std::string file;

  [[noreturn]] void Fail(const std::string& context, const std::string& problem) const {
    throw std::runtime_error("sidecar " + file + ": " + context + ": " + problem);
  }
  const json& Get(const json& obj, const std::string& key, const std::string& context) const {
    if (!obj.is_object()) Fail(context, "expected a JSON object");
    auto it = obj.find(key);
    if (it == obj.end()) Fail(context, "missing required entry '" + key + "'");
    return *it;
  }
  double Number(const json& obj, const std::string& key, const std::string& context) const {
    const json& v = Get(obj, key, context);
    if (!v.is_number()) Fail(context, "'" + key + "' must be a number, got " + v.dump());
    const double x = v.get<double>();
    if (!std::isfinite(x)) Fail(context, "'" + key + "' is not finite");
    return x;
  }
  double NumberOr(const json& obj, const std::string& key, double fallback,
                  const std::string& context) const {
    if (!obj.contains(key)) return fallback;
    return Number(obj, key, context);
  }
  std::string String(const json& obj, const std::string& key, const std::string& context) const {
    const json& v = Get(obj, key, context);
    if (!v.is_string()) Fail(context, "'" + key + "' must be a string, got " + v.dump());
    return v.get<std::string>();
  }
  Eigen::Vector3d Vec3(const json& v, const std::string& context) const {
    if (!v.is_array() || v.size() != 3) Fail(context, "expected [x, y, z], got " + v.dump());
    Eigen::Vector3d out;
    for (int i = 0; i < 3; ++i) {
      if (!v[i].is_number()) Fail(context, "expected numbers in [x, y, z], got " + v.dump());
      out[i] = v[i].get<double>();
    }
    return out;
  }
  const json& Array(const json& obj, const std::string& key, const std::string& context) const {
    static const json kEmpty = json::array();
    if (!obj.contains(key)) return kEmpty;
    const json& v = obj.at(key);
    if (!v.is_array()) Fail(context, "'" + key + "' must be an array");
    return v;
  }
};

}  // namespace

class MultibodyModelLoader {
 public:
  static MultibodyModel Load(const std::string& urdf_path, std::string sidecar_path,
                             bool sidecar_required) {
    MultibodyModel model;
    model.urdf_path_ = urdf_path;

    // ---------------- sidecar (parsed first: it decides the floating base) ----------------
    json sidecar = json::object();
    if (sidecar_path.empty()) {
      std::filesystem::path p(urdf_path);
      std::string stem = p.stem().string();
      sidecar_path = (p.parent_path() / (stem + ".rome.json")).string();
      if (!std::filesystem::exists(sidecar_path)) sidecar_path.clear();
    } else {
      sidecar_required = true;
    }
    SidecarReader sc{sidecar_path};
    if (!sidecar_path.empty() || sidecar_required) {
      const std::string text = ReadFile(sidecar_path, "sidecar");
      try {
        sidecar = json::parse(text, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/true);
      } catch (const json::exception& e) {
        throw std::runtime_error("sidecar " + sidecar_path + ": malformed JSON: " + e.what());
      }
      if (!sidecar.is_object()) sc.Fail("top level", "expected a JSON object");
    }
    model.sidecar_path_ = sidecar_path;

    model.floating_base_ = FloatingBaseType::kFixed;
    if (sidecar.contains("floating_base")) {
      const std::string fb = sc.String(sidecar, "floating_base", "floating_base");
      if (fb == "fixed") model.floating_base_ = FloatingBaseType::kFixed;
      else if (fb == "planar") model.floating_base_ = FloatingBaseType::kPlanar;
      else if (fb == "spatial") model.floating_base_ = FloatingBaseType::kSpatial;
      else sc.Fail("floating_base", "unknown type '" + fb + "' (expected fixed, planar or spatial)");
    }

    // ---------------- URDF ----------------
    const std::string xml = ReadFile(urdf_path, "URDF");
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
      if (!urdf_model)
        throw std::runtime_error("URDF " + urdf_path + ": malformed or invalid URDF: " +
                                 (handler.errors.empty() ? "urdfdom could not parse it" : handler.errors));
    }
    model.name_ = urdf_model->getName();
    if (sidecar.contains("robot")) model.name_ = sc.String(sidecar, "robot", "robot");

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
    std::function<void(const std::string&, MultibodyJointType, Eigen::Vector3d)> root_joint;
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

    auto fill_inertia = [&](MultibodyBody& b, const urdf::Link& link, bool fixed_joint) {
      const std::string where = "URDF " + urdf_path + ": link '" + link.name + "'";
      if (!link.inertial) throw std::runtime_error(where + ": missing <inertial> (mass and inertia are required)");
      const urdf::Inertial& in = *link.inertial;
      b.mass = in.mass;
      Eigen::Isometry3d X = ToEigen(in.origin);
      b.com = X.translation();
      Eigen::Matrix3d I_in;
      I_in << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
      b.inertia = X.linear() * I_in * X.linear().transpose();
      if (!std::isfinite(b.mass) || !b.inertia.allFinite())
        throw std::runtime_error(where + ": <inertial> has non-finite values");
      const bool pure_frame = fixed_joint && b.mass == 0.0 && b.inertia.isZero(0.0);
      if (!pure_frame && !(b.mass > 0.0))
        throw std::runtime_error(where + ": <mass> must be positive, got " + std::to_string(b.mass));
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(b.inertia);
      if (!pure_frame && !(eig.eigenvalues().minCoeff() > 0.0)) {
        std::ostringstream os;
        os << where << ": <inertia> is not positive definite (eigenvalues "
           << eig.eigenvalues().transpose() << " kg m^2)";
        throw std::runtime_error(os.str());
      }
      if (pure_frame) {
        b.principal_moments.setZero();
        b.R_link_principal.setIdentity();
      } else {
        b.principal_moments = eig.eigenvalues();
        b.R_link_principal = eig.eigenvectors();
        if (b.R_link_principal.determinant() < 0) b.R_link_principal.col(2) *= -1.0;
      }
    };

    // Depth-first walk of the URDF tree, parents before children.
    urdf::LinkConstSharedPtr root = urdf_model->getRoot();
    if (!root) throw std::runtime_error("URDF " + urdf_path + ": no root link");
    {
      MultibodyBody b;
      b.name = root->name;
      b.joint_name = root_joint_name;
      b.parent = static_cast<int>(bodies->size()) - 1;
      b.joint_type = root_type;
      b.axis = root_axis;
      fill_inertia(b, *root, model.floating_base_ == FloatingBaseType::kFixed);
      bodies->push_back(b);
    }
    std::vector<std::pair<double, double>> limits;  // per body
    limits.assign(bodies->size(), {-std::numeric_limits<double>::infinity(),
                                   std::numeric_limits<double>::infinity()});
    std::function<void(const urdf::Link&, int)> walk = [&](const urdf::Link& link, int parent_body) {
      for (const auto& joint : link.child_joints) {
        const std::string where = "URDF " + urdf_path + ": joint '" + joint->name + "'";
        auto child_it = urdf_model->links_.find(joint->child_link_name);
        if (child_it == urdf_model->links_.end())
          throw std::runtime_error(where + ": child link '" + joint->child_link_name + "' does not exist");
        const urdf::Link& child = *child_it->second;
        MultibodyBody b;
        b.name = child.name;
        b.joint_name = joint->name;
        b.parent = parent_body;
        b.X_parent_joint = ToEigen(joint->parent_to_joint_origin_transform);
        std::pair<double, double> lim{-std::numeric_limits<double>::infinity(),
                                      std::numeric_limits<double>::infinity()};
        switch (joint->type) {
          case urdf::Joint::REVOLUTE:
          case urdf::Joint::CONTINUOUS: b.joint_type = MultibodyJointType::kRevolute; break;
          case urdf::Joint::PRISMATIC: b.joint_type = MultibodyJointType::kPrismatic; break;
          case urdf::Joint::FIXED: b.joint_type = MultibodyJointType::kFixed; break;
          default:
            throw std::runtime_error(where + ": unsupported joint type (only revolute, continuous, "
                                     "prismatic and fixed are supported)");
        }
        if (b.joint_type != MultibodyJointType::kFixed) {
          Eigen::Vector3d axis = ToEigen(joint->axis);
          if (!(axis.norm() > 1e-9)) throw std::runtime_error(where + ": <axis> is zero");
          b.axis = axis.normalized();
          if (joint->type != urdf::Joint::CONTINUOUS && joint->limits &&
              joint->limits->lower < joint->limits->upper)
            lim = {joint->limits->lower, joint->limits->upper};
        }
        fill_inertia(b, child, b.joint_type == MultibodyJointType::kFixed);
        const int index = static_cast<int>(bodies->size());
        bodies->push_back(b);
        limits.push_back(lim);
        walk(child, index);
      }
    };
    walk(*root, static_cast<int>(bodies->size()) - 1);

    // Degrees of freedom in body order (matches Bullet's dof order).
    int nv = 0;
    for (int i = 0; i < static_cast<int>(bodies->size()); ++i) {
      MultibodyBody& b = (*bodies)[i];
      model.body_index_[b.name] = i;
      if (b.joint_type != MultibodyJointType::kFixed) {
        b.v_index = nv++;
        model.joint_index_[b.joint_name] = b.v_index;
        model.joint_names_.push_back(b.joint_name);
        model.body_of_v_.push_back(i);
      }
      model.total_mass_ += b.mass;
    }
    model.nv_ = nv;
    model.q_lower_.setConstant(nv, -std::numeric_limits<double>::infinity());
    model.q_upper_.setConstant(nv, std::numeric_limits<double>::infinity());
    for (int i = 0; i < static_cast<int>(bodies->size()); ++i) {
      const int k = (*bodies)[i].v_index;
      if (k >= 0) { model.q_lower_[k] = limits[i].first; model.q_upper_[k] = limits[i].second; }
    }
    model.bodies_ = bodies;

    auto movable_joint = [&](const std::string& joint, const std::string& context) {
      if (!model.joint_index_.count(joint)) {
        if (urdf_model->joints_.count(joint))
          sc.Fail(context, "joint '" + joint + "' is fixed in URDF " + urdf_path + " and cannot be used here");
        sc.Fail(context, "joint '" + joint + "' does not exist in URDF " + urdf_path);
      }
      return model.joint_index_.at(joint);
    };
    auto existing_link = [&](const std::string& link, const std::string& context) {
      if (!model.body_index_.count(link))
        sc.Fail(context, "link '" + link + "' does not exist in URDF " + urdf_path);
      return model.body_index_.at(link);
    };

    // ---------------- actuators ----------------
    model.reflected_inertia_.setZero(nv);
    const json& acts = sc.Array(sidecar, "actuators", "actuators");
    for (size_t i = 0; i < acts.size(); ++i) {
      const std::string ctx = "actuators[" + std::to_string(i) + "]";
      ActuatorInfo a;
      a.joint = sc.String(acts[i], "joint", ctx);
      a.v_index = movable_joint(a.joint, ctx + " (joint '" + a.joint + "')");
      a.gear_ratio = sc.NumberOr(acts[i], "gear_ratio", 1.0, ctx);
      a.reflected_inertia_kgm2 = sc.NumberOr(acts[i], "reflected_inertia_kgm2", 0.0, ctx);
      double urdf_effort = std::numeric_limits<double>::infinity();
      auto jit = urdf_model->joints_.find(a.joint);
      if (jit != urdf_model->joints_.end() && jit->second->limits && jit->second->limits->effort > 0)
        urdf_effort = jit->second->limits->effort;
      a.torque_limit_Nm = sc.NumberOr(acts[i], "torque_limit_Nm", urdf_effort, ctx);
      if (!(a.torque_limit_Nm > 0.0)) sc.Fail(ctx, "torque_limit_Nm must be positive");
      if (a.reflected_inertia_kgm2 < 0.0) sc.Fail(ctx, "reflected_inertia_kgm2 must be >= 0");
      if (!(a.gear_ratio > 0.0)) sc.Fail(ctx, "gear_ratio must be positive");
      for (const auto& other : model.actuators_)
        if (other.v_index == a.v_index) sc.Fail(ctx, "joint '" + a.joint + "' is actuated twice");
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

    // ---------------- springs ----------------
    model.spring_stiffness_.setZero(nv);
    model.spring_damping_.setZero(nv);
    model.spring_rest_.setZero(nv);
    const json& springs = sc.Array(sidecar, "springs", "springs");
    for (size_t i = 0; i < springs.size(); ++i) {
      const std::string ctx = "springs[" + std::to_string(i) + "]";
      SpringInfo s;
      s.joint = sc.String(springs[i], "joint", ctx);
      s.v_index = movable_joint(s.joint, ctx + " (joint '" + s.joint + "')");
      s.stiffness_Nm_per_rad = sc.Number(springs[i], "stiffness_Nm_per_rad", ctx);
      s.damping_Nms_per_rad = sc.NumberOr(springs[i], "damping_Nms_per_rad", 0.0, ctx);
      s.rest_angle_rad = sc.NumberOr(springs[i], "rest_angle_rad", 0.0, ctx);
      if (s.stiffness_Nm_per_rad < 0.0 || s.damping_Nms_per_rad < 0.0)
        sc.Fail(ctx, "stiffness and damping must be >= 0");
      model.spring_stiffness_[s.v_index] = s.stiffness_Nm_per_rad;
      model.spring_damping_[s.v_index] = s.damping_Nms_per_rad;
      model.spring_rest_[s.v_index] = s.rest_angle_rad;
      model.springs_.push_back(s);
    }

    // ---------------- contacts ----------------
    const bool planar = model.floating_base_ == FloatingBaseType::kPlanar;
    const json& contacts = sc.Array(sidecar, "contacts", "contacts");
    for (size_t i = 0; i < contacts.size(); ++i) {
      ContactInfo c;
      c.name = sc.String(contacts[i], "name", "contacts[" + std::to_string(i) + "]");
      const std::string ctx = "contacts[" + std::to_string(i) + "] ('" + c.name + "')";
      c.link = sc.String(contacts[i], "link", ctx);
      c.body = existing_link(c.link, ctx);
      const std::string type = sc.String(contacts[i], "type", ctx);
      size_t min_points = 1, max_points = 1;
      if (type == "point") { c.type = ContactType::kPoint; }
      else if (type == "line") { c.type = ContactType::kLine; min_points = max_points = 2; }
      else if (type == "flat") { c.type = ContactType::kFlat; min_points = 3; max_points = 64; }
      else sc.Fail(ctx, "unknown contact type '" + type + "' (expected point, line or flat)");
      const json& pts = sc.Get(contacts[i], "points", ctx);
      if (!pts.is_array() || pts.size() < min_points || pts.size() > max_points)
        sc.Fail(ctx, "a " + type + " contact needs " + std::to_string(min_points) +
                         (max_points > min_points ? "+" : "") + " points, got " + pts.dump());
      for (const auto& p : pts) c.points.push_back(sc.Vec3(p, ctx + " points"));
      c.friction_coefficient = sc.NumberOr(contacts[i], "friction_coefficient", 1.0, ctx);
      if (!(c.friction_coefficient > 0.0)) sc.Fail(ctx, "friction_coefficient must be positive");
      if (c.type == ContactType::kLine && (c.points[0] - c.points[1]).norm() < 1e-6)
        sc.Fail(ctx, "line contact points coincide");
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
    if (model.contacts_.size() > 64) sc.Fail("contacts", "at most 64 contacts are supported");

    // ---------------- loop closures ----------------
    const json& loops = sc.Array(sidecar, "loop_closures", "loop_closures");
    for (size_t i = 0; i < loops.size(); ++i) {
      LoopClosureInfo l;
      l.name = sc.String(loops[i], "name", "loop_closures[" + std::to_string(i) + "]");
      const std::string ctx = "loop_closures[" + std::to_string(i) + "] ('" + l.name + "')";
      l.link_a = sc.String(loops[i], "link_a", ctx);
      l.link_b = sc.String(loops[i], "link_b", ctx);
      l.body_a = existing_link(l.link_a, ctx + " link_a");
      l.body_b = existing_link(l.link_b, ctx + " link_b");
      l.point_a = sc.Vec3(sc.Get(loops[i], "point_a", ctx), ctx + " point_a");
      l.point_b = sc.Vec3(sc.Get(loops[i], "point_b", ctx), ctx + " point_b");
      l.distance_m = sc.Number(loops[i], "distance_m", ctx);
      if (!(l.distance_m > 0.0)) sc.Fail(ctx, "distance_m must be positive");
      model.max_constraint_rows_ += 1;
      model.loop_closures_.push_back(l);
    }

    // ---------------- nominal pose ----------------
    model.q_nominal_.setZero(nv);
    if (sidecar.contains("nominal_pose")) {
      const json& pose = sidecar.at("nominal_pose");
      if (!pose.is_object()) sc.Fail("nominal_pose", "expected a JSON object");
      const json& base = sc.Array(pose, "base", "nominal_pose");
      const int nb = model.num_base_dofs();
      if (pose.contains("base")) {
        if (static_cast<int>(base.size()) != nb)
          sc.Fail("nominal_pose.base", "expected " + std::to_string(nb) + " numbers for a " +
                                           ToString(model.floating_base_) + " base, got " + base.dump());
        for (int k = 0; k < nb; ++k) {
          if (!base[k].is_number()) sc.Fail("nominal_pose.base", "expected numbers, got " + base.dump());
          model.q_nominal_[k] = base[k].get<double>();
        }
      }
      if (pose.contains("joints")) {
        const json& joints = pose.at("joints");
        if (!joints.is_object()) sc.Fail("nominal_pose.joints", "expected an object {joint: angle}");
        for (auto it = joints.begin(); it != joints.end(); ++it) {
          const std::string ctx = "nominal_pose.joints['" + it.key() + "']";
          const int k = movable_joint(it.key(), ctx);
          if (!it.value().is_number()) sc.Fail(ctx, "expected a number");
          model.q_nominal_[k] = it.value().get<double>();
        }
      }
    }
    return model;
  }
};

MultibodyModel MultibodyModel::Load(const std::string& urdf_path, const std::string& sidecar_path) {
  return MultibodyModelLoader::Load(urdf_path, sidecar_path, false);
}

MultibodyModel MultibodyModel::LoadFromSidecar(const std::string& sidecar_path) {
  const std::string text = ReadFile(sidecar_path, "sidecar");
  json j;
  try {
    j = json::parse(text, nullptr, true, true);
  } catch (const json::exception& e) {
    throw std::runtime_error("sidecar " + sidecar_path + ": malformed JSON: " + e.what());
  }
  SidecarReader sc{sidecar_path};
  const std::string urdf = sc.String(j, "urdf", "top level");
  const std::string urdf_path =
      (std::filesystem::path(sidecar_path).parent_path() / urdf).string();
  return MultibodyModelLoader::Load(urdf_path, sidecar_path, true);
}

}  // namespace rome
