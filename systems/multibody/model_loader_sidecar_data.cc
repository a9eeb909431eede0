// The sidecar's data: actuators, springs, contacts, loop closures and the nominal pose, each checked against the
// bodies and joints the URDF gave (model_loader.h lists the loader's stages).

#include <cmath>
#include <limits>
#include <stdexcept>

#include "framework/text.h"
#include "systems/multibody/model_checks.h"
#include "systems/multibody/model_loader.h"

namespace rome {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A point given in a link's frame, in its body's frame.
Eigen::Vector3d ToBody(const MultibodyFrame& f, const Eigen::Vector3d& p) {
  return f.X_body_frame.isApprox(Eigen::Isometry3d::Identity(), 0.0) ? p : Eigen::Vector3d(f.X_body_frame * p);
}

}  // namespace

using namespace model_loading;

// The velocity index of `joint`, which must exist in the URDF and move.
int MultibodyModelLoader::MovableJoint(const LoadState& s, const std::string& joint, const std::string& context) {
  const MultibodyModel& model = s.model;
  const std::string& ufile = s.ufile;
  const SidecarReader& sc = s.sc;
  if (!model.joint_index_.count(joint)) {
    if (s.urdf->joints_.count(joint))
      sc.Fail(context, "joint '" + Excerpt(joint) + "' is fixed in " + ufile + " and cannot be used here");
    sc.Fail(context, "joint '" + Excerpt(joint) + "' does not exist in " + ufile);
  }
  return model.joint_index_.at(joint);
}

const MultibodyFrame& MultibodyModelLoader::ExistingFrame(const LoadState& s, const std::string& link,
                                                          const std::string& context) {
  const MultibodyModel& model = s.model;
  if (!model.frame_index_.count(link)) s.sc.Fail(context, "link '" + Excerpt(link) + "' does not exist in " + s.ufile);
  return model.frames_[model.frame_index_.at(link)];
}

int MultibodyModelLoader::ReadJointEntry(const LoadState& s, const json& entry, const char* array, size_t i,
                                         std::initializer_list<const char*> known, std::string* joint,
                                         std::string* ctx) {
  *ctx = std::string(array) + "[" + std::to_string(i) + "]";
  s.sc.CheckKeys(entry, known, *ctx);
  *joint = s.sc.String(entry, "joint", *ctx);
  *ctx += " (joint '" + Excerpt(*joint) + "')";
  return MovableJoint(s, *joint, *ctx);
}

void MultibodyModelLoader::ReadActuators(LoadState& s) {
  MultibodyModel& model = s.model;
  const SidecarReader& sc = s.sc;
  const json& sidecar = s.sidecar;
  const int nv = model.nv_;
  model.reflected_inertia_.setZero(nv);
  const json& acts = sc.Array(sidecar, "actuators", "actuators");
  for (size_t i = 0; i < acts.size(); ++i) {
    std::string ctx;
    ActuatorInfo a;
    a.v_index = ReadJointEntry(s, acts[i], "actuators", i,
                               {"joint", "gear_ratio", "reflected_inertia_kgm2", "torque_limit_Nm"}, &a.joint, &ctx);
    a.gear_ratio = sc.NumberOr(acts[i], "gear_ratio", 1.0, ctx);
    a.reflected_inertia_kgm2 = sc.NumberOr(acts[i], "reflected_inertia_kgm2", 0.0, ctx);
    if (acts[i].contains("torque_limit_Nm")) {
      a.torque_limit_Nm = sc.Number(acts[i], "torque_limit_Nm", ctx);
      if (!(a.torque_limit_Nm > 0.0)) sc.Fail(ctx, "torque_limit_Nm must be positive, got " + Num(a.torque_limit_Nm));
    } else {
      auto jit = s.urdf->joints_.find(a.joint);
      const double effort = jit != s.urdf->joints_.end() && jit->second->limits ? jit->second->limits->effort : kInf;
      if (!std::isfinite(effort) || !(effort > 0.0))
        sc.Fail(ctx, "no torque limit: no torque_limit_Nm here and the URDF <limit effort> is " +
                         (effort == kInf ? std::string("missing") : Num(effort)) +
                         " (give a positive torque_limit_Nm)");
      a.torque_limit_Nm = effort;
    }
    CheckMagnitude(sc, ctx, "torque limit (torque_limit_Nm or the URDF <limit effort>)", a.torque_limit_Nm,
                   kMinTorqueLimit_Nm, kMaxTorqueLimit_Nm, "N m");
    if (a.reflected_inertia_kgm2 != 0.0)
      CheckMagnitude(sc, ctx, "reflected_inertia_kgm2", a.reflected_inertia_kgm2, kMinPositiveParameter,
                     kMaxInertia_kgm2, "kg m^2");
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
}

void MultibodyModelLoader::ReadSprings(LoadState& state) {
  MultibodyModel& model = state.model;
  const SidecarReader& sc = state.sc;
  const json& sidecar = state.sidecar;
  const int nv = model.nv_;
  model.spring_stiffness_.setZero(nv);
  model.spring_damping_.setZero(nv);
  model.spring_rest_.setZero(nv);
  const json& springs = sc.Array(sidecar, "springs", "springs");
  for (size_t i = 0; i < springs.size(); ++i) {
    std::string ctx;
    SpringInfo s;
    s.v_index =
        ReadJointEntry(state, springs[i], "springs", i,
                       {"joint", "stiffness_Nm_per_rad", "damping_Nms_per_rad", "rest_angle_rad"}, &s.joint, &ctx);
    s.stiffness_Nm_per_rad = sc.Number(springs[i], "stiffness_Nm_per_rad", ctx);
    s.damping_Nms_per_rad = sc.NumberOr(springs[i], "damping_Nms_per_rad", 0.0, ctx);
    s.rest_angle_rad = sc.NumberOr(springs[i], "rest_angle_rad", 0.0, ctx);
    if (s.stiffness_Nm_per_rad < 0.0 || s.damping_Nms_per_rad < 0.0)
      sc.Fail(ctx, "stiffness and damping must be >= 0, got " + Num(s.stiffness_Nm_per_rad) + " and " +
                       Num(s.damping_Nms_per_rad));
    if (s.stiffness_Nm_per_rad != 0.0)
      CheckMagnitude(sc, ctx, "stiffness_Nm_per_rad", s.stiffness_Nm_per_rad, kMinPositiveParameter,
                     kMaxSpringStiffness_Nm_per_rad, "N m/rad");
    if (s.damping_Nms_per_rad != 0.0)
      CheckMagnitude(sc, ctx, "damping_Nms_per_rad", s.damping_Nms_per_rad, kMinPositiveParameter,
                     kMaxSpringDamping_Nms_per_rad, "N m s/rad");
    if (std::abs(s.rest_angle_rad) > kMaxJointAngle_rad)
      sc.Fail(ctx, "rest_angle_rad " + Num(s.rest_angle_rad) + " is beyond +-" + Num(kMaxJointAngle_rad) + " rad");
    for (const auto& other : model.springs_)
      if (other.v_index == s.v_index) sc.Fail(ctx, "joint '" + Excerpt(s.joint) + "' has a second spring");
    model.spring_stiffness_[s.v_index] = s.stiffness_Nm_per_rad;
    model.spring_damping_[s.v_index] = s.damping_Nms_per_rad;
    model.spring_rest_[s.v_index] = s.rest_angle_rad;
    model.springs_.push_back(s);
  }
}

void MultibodyModelLoader::ReadContacts(LoadState& s) {
  MultibodyModel& model = s.model;
  const SidecarReader& sc = s.sc;
  const json& sidecar = s.sidecar;
  const bool planar = model.floating_base_ == FloatingBaseType::kPlanar;
  const json& contacts = sc.Array(sidecar, "contacts", "contacts");
  if (contacts.size() > 64)
    sc.Fail("contacts", "at most 64 contacts are supported, got " + std::to_string(contacts.size()));
  for (size_t i = 0; i < contacts.size(); ++i) {
    ContactInfo c;
    c.name = sc.String(contacts[i], "name", "contacts[" + std::to_string(i) + "]");
    const std::string ctx = "contacts[" + std::to_string(i) + "] ('" + Excerpt(c.name) + "')";
    sc.CheckKeys(contacts[i], {"name", "link", "type", "points", "friction_coefficient"}, ctx);
    c.link = sc.String(contacts[i], "link", ctx);
    const MultibodyFrame& frame = ExistingFrame(s, c.link, ctx);
    c.body = frame.body;
    const std::string type = sc.String(contacts[i], "type", ctx);
    size_t min_points = 1, max_points = 1;
    if (type == "point") {
      c.type = ContactType::kPoint;
    } else if (type == "line") {
      c.type = ContactType::kLine;
      min_points = max_points = 2;
    } else if (type == "flat") {
      c.type = ContactType::kFlat;
      min_points = 3;
      max_points = 64;
    } else
      sc.Fail(ctx, "unknown contact type '" + Excerpt(type) + "' (expected point, line or flat)");
    const json& pts = sc.Get(contacts[i], "points", ctx);
    if (!pts.is_array() || pts.size() < min_points || pts.size() > max_points)
      sc.Fail(ctx, "a " + type + " contact needs " + std::to_string(min_points) + (max_points > min_points ? "+" : "") +
                       " points, got " + SidecarReader::Dump(pts));
    for (const auto& p : pts) c.points.push_back(sc.Vec3(p, ctx + " points"));
    c.friction_coefficient = sc.NumberOr(contacts[i], "friction_coefficient", 1.0, ctx);
    CheckMagnitude(sc, ctx, "friction_coefficient", c.friction_coefficient, kMinFrictionCoefficient,
                   kMaxFrictionCoefficient, "");
    if (const std::string problem = DegenerateContactProblem(c); !problem.empty()) sc.Fail(ctx, problem);
    for (auto& p : c.points) p = ToBody(frame, p);
    c.frame_origin.setZero();
    for (const auto& p : c.points) c.frame_origin += p;
    c.frame_origin /= static_cast<double>(c.points.size());
    if (planar)
      c.num_rows = c.type == ContactType::kPoint ? 2 : 3;
    else
      c.num_rows = c.type == ContactType::kPoint ? 3 : (c.type == ContactType::kLine ? 5 : 6);
    if (model.contact_index_.count(c.name)) sc.Fail(ctx, "duplicate contact name");
    model.contact_index_[c.name] = static_cast<int>(model.contacts_.size());
    model.max_constraint_rows_ += c.num_rows;
    model.contacts_.push_back(c);
  }
}

void MultibodyModelLoader::ReadLoopClosures(LoadState& s) {
  MultibodyModel& model = s.model;
  const SidecarReader& sc = s.sc;
  const json& sidecar = s.sidecar;
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
    const MultibodyFrame& fa = ExistingFrame(s, l.link_a, ctx + " link_a");
    const MultibodyFrame& fb = ExistingFrame(s, l.link_b, ctx + " link_b");
    l.body_a = fa.body;
    l.body_b = fb.body;
    l.point_a = ToBody(fa, sc.Vec3(sc.Get(loops[i], "point_a", ctx), ctx + " point_a"));
    l.point_b = ToBody(fb, sc.Vec3(sc.Get(loops[i], "point_b", ctx), ctx + " point_b"));
    l.distance_m = sc.Number(loops[i], "distance_m", ctx);
    if (!(l.distance_m > 0.0) || l.distance_m > kMaxLength_m)
      sc.Fail(ctx, "distance_m must be positive and at most " + Num(kMaxLength_m) + " m, got " + Num(l.distance_m));
    model.max_constraint_rows_ += 1;
    model.loop_closures_.push_back(l);
  }
}

// The nominal pose: the floating joint's <origin> (if any), then the sidecar's nominal_pose. Returns which joints the
// sidecar gives.
std::vector<bool> MultibodyModelLoader::ReadNominalPose(LoadState& s) {
  MultibodyModel& model = s.model;
  const SidecarReader& sc = s.sc;
  const json& sidecar = s.sidecar;
  const int nv = model.nv_;
  model.q_nominal_.setZero(nv);
  std::vector<bool> given(static_cast<size_t>(nv), false);  // joints the sidecar's nominal_pose.joints gives
  if (s.base_nominal.size() == model.num_base_dofs()) model.q_nominal_.head(s.base_nominal.size()) = s.base_nominal;
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
          sc.Fail("nominal_pose.base",
                  "entry " + std::to_string(k) + " is " + Num(x) + " (not finite or beyond " + Num(kMaxLength_m) + ")");
        model.q_nominal_[k] = x;
      }
    }
    if (pose.contains("joints")) {
      const json& joints = pose.at("joints");
      if (!joints.is_object()) sc.Fail("nominal_pose.joints", "expected an object {joint: angle}");
      for (auto it = joints.begin(); it != joints.end(); ++it) {
        const std::string ctx = "nominal_pose.joints['" + Excerpt(it.key()) + "']";
        const int k = MovableJoint(s, it.key(), ctx);
        if (!it.value().is_number()) sc.Fail(ctx, "expected a number, got " + SidecarReader::Dump(it.value()));
        const double x = it.value().get<double>();
        if (!std::isfinite(x) || std::abs(x) > kMaxLength_m)
          sc.Fail(ctx, "value " + Num(x) + " is not finite or beyond " + Num(kMaxLength_m));
        model.q_nominal_[k] = x;
        given[static_cast<size_t>(k)] = true;
      }
    }
  }
  return given;
}

}  // namespace rome
