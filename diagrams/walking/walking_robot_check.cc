#include "diagrams/walking/walking_robot_check.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "diagrams/walking/walking_diagram.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/planners/walking_plan_inverse_dynamics.h"

namespace rome {

void CheckWalkingRobot(const MultibodyModel& model) {
  const std::string robot = "walking diagram: robot '" + model.name() + "'";
  if (model.floating_base() != FloatingBaseType::kSpatial)
    throw std::invalid_argument(
        robot + " has a " + std::string(ToString(model.floating_base())) +
        " floating base; the walking diagram needs a spatial one (a 3D biped such as robots/exoskeleton)");
  model.RequireNqEqualsNv("walking diagram");  // its plans, pose solver and controllers take the Euler base
  for (const char* foot : {"left_foot", "right_foot"}) {
    const auto& contacts = model.contacts();
    const auto it =
        std::find_if(contacts.begin(), contacts.end(), [&](const ContactInfo& c) { return c.name == foot; });
    if (it == contacts.end())
      throw std::invalid_argument(robot + " has no contact named '" + foot +
                                  "'; the walking diagram needs 'left_foot' and 'right_foot'");
    if (it->type != ContactType::kFlat)
      throw std::invalid_argument(robot + ": contact '" + foot + "' is a " +
                                  (it->type == ContactType::kPoint ? "point" : "line") +
                                  " contact; the walking diagram needs flat feet (a sole of corner points)");
  }
  if (model.nu() == 0) throw std::invalid_argument(robot + " has no actuators");
}

namespace {

std::string Fixed(double x, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, x);
  return buffer;
}

// A gait value with 3 decimals, a trailing zero dropped ("0.45", "0.375").
std::string GaitValue(double x) {
  std::string s = Fixed(x, 3);
  if (s.back() == '0') s.pop_back();
  return s;
}

void Require(bool ok, const char* field, double value, const std::string& range) {
  if (!ok)
    throw std::invalid_argument(std::string("WalkingFeasibilityParams: ") + field + " = " + Fixed(value, 6) +
                                " is outside " + range);
}

// "left knee" for joint "left_knee".
std::string JointWords(std::string joint) {
  std::replace(joint.begin(), joint.end(), '_', ' ');
  return joint;
}

bool PeriodicSingleSupport(const WalkingPlanSegment& s) {
  return s.domain != WalkingDomain::kDoubleSupport && s.lateral_node_times.size() == 0;
}

std::string GaitOfSingleSupport(const std::vector<WalkingPlanSegment>& segments, size_t i) {
  const WalkingPlanSegment& s = segments[i];
  const bool left = s.domain == WalkingDomain::kLeftStance;
  const Eigen::Vector2d stance = left ? s.left_foothold : s.right_foothold;
  const Eigen::Vector2d landing = left ? s.right_foothold : s.left_foothold;
  double dsp = 0.0;
  if (i + 1 < segments.size() && segments[i + 1].domain == WalkingDomain::kDoubleSupport)
    dsp = segments[i + 1].duration;
  else if (i > 0 && segments[i - 1].domain == WalkingDomain::kDoubleSupport)
    dsp = segments[i - 1].duration;
  return "gait " + GaitValue(landing.x() - stance.x()) + "," + GaitValue(s.duration) + "," + GaitValue(dsp) + "," +
         GaitValue(std::abs(landing.y() - stance.y()));
}

std::string TransitionName(const std::vector<WalkingPlanSegment>& segments, size_t i) {
  for (size_t j = i + 1; j < segments.size(); ++j)
    if (PeriodicSingleSupport(segments[j])) return "the transition into " + GaitOfSingleSupport(segments, j);
  return "the transition";
}

// One problem found at a sample: how far past its bound (to pick the worst) and its words.
struct Finding {
  double excess = 0.0;
  std::string what;
  double time_s = 0.0;
};

std::string Describe(const WalkingPlan& plan, const Finding& f) {
  const WalkingPlanSegment& s = plan.segments()[plan.SegmentIndexAt(f.time_s)];
  const bool single = s.domain != WalkingDomain::kDoubleSupport;
  return WalkingPlanPhaseName(plan, f.time_s) + ": " + f.what + " at " + Fixed(f.time_s - s.start_time, 2) + " s of " +
         (single ? "single" : "double") + " support (t = " + Fixed(f.time_s, 2) + " s)";
}

}  // namespace

void WalkingFeasibilityParams::Validate() const {
  Require(sample_period_s >= 1e-4 && sample_period_s <= 0.01, "sample_period_s", sample_period_s, "[1e-4, 0.01] s");
  Require(torque_margin >= 0 && torque_margin <= 0.5, "torque_margin", torque_margin, "[0, 0.5]");
  Require(friction_coefficient < 0 || (friction_coefficient > 0 && friction_coefficient <= 3), "friction_coefficient",
          friction_coefficient, "(0, 3] (or < 0: the contacts' own)");
  Require(cop_margin_m >= 0 && cop_margin_m <= 0.02, "cop_margin_m", cop_margin_m, "[0, 0.02] m");
  Require(min_normal_force_N >= 0 && min_normal_force_N <= 1e4, "min_normal_force_N", min_normal_force_N, "[0, 1e4] N");
  Require(joint_limit_margin_rad >= 0 && joint_limit_margin_rad <= 0.1, "joint_limit_margin_rad",
          joint_limit_margin_rad, "[0, 0.1] rad");
  Require(start_time_s >= 0 && std::isfinite(start_time_s), "start_time_s", start_time_s, ">= 0 s, finite");
}

SoleRectangle SoleRectangleOf(const MultibodyModel& model, const std::string& contact) {
  const ContactInfo& c = model.contacts()[model.ContactIndex(contact)];
  if (c.type != ContactType::kFlat || c.points.size() < 3)
    throw std::invalid_argument("SoleRectangleOf: contact '" + contact + "' of robot '" + model.name() +
                                "' is not a flat sole of corner points");
  Eigen::Vector3d lo = c.points.front(), hi = c.points.front(), sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : c.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p), sum += p;
  SoleRectangle r;
  r.center =
      Eigen::Vector3d(0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()), sum.z() / static_cast<double>(c.points.size()));
  r.half_length_m = 0.5 * (hi.x() - lo.x());
  r.half_width_m = 0.5 * (hi.y() - lo.y());
  r.friction_coefficient = c.friction_coefficient;
  return r;
}

std::string SoleWrenchProblem(const SoleRectangle& sole, const Eigen::Matrix<double, 6, 1>& wrench,
                              const WalkingFeasibilityParams& params, double* excess) {
  double unused = 0.0;
  double& over = excess ? *excess : unused;
  over = 0.0;
  const double tx = wrench[0], ty = wrench[1], tz = wrench[2], fx = wrench[3], fy = wrench[4], fz = wrench[5];
  if (!(fz > 0) || fz < params.min_normal_force_N) {
    over = 1.0;
    return "needs the sole to pull (F_z = " + Fixed(fz, 0) + " N)";
  }
  const double mu = params.friction_coefficient >= 0 ? params.friction_coefficient : sole.friction_coefficient;
  const double mup = params.inscribe_pyramid ? mu / std::sqrt(2.0) : mu;  // each corner's pyramid half-width
  const double fmax = std::max(std::abs(fx), std::abs(fy));
  if (fmax > mup * fz) {
    over = fmax / (mup * fz) - 1.0;
    return "needs a friction ratio max(|F_x|, |F_y|)/F_z of " + Fixed(fmax / fz, 2) +
           " (the corners' friction pyramid holds " + Fixed(mup, 2) + ", mu " + Fixed(mu, 2) + ")";
  }
  const double X = sole.half_length_m - params.cop_margin_m, Y = sole.half_width_m - params.cop_margin_m;
  const double cop_x = -ty / fz, cop_y = tx / fz;  // from the sole's centre
  if (std::abs(cop_x) > X || std::abs(cop_y) > Y) {
    over = std::max(std::abs(cop_x) / X, std::abs(cop_y) / Y) - 1.0;
    return "needs its CoP at (" + Fixed(cop_x, 3) + ", " + Fixed(cop_y, 3) +
           ") m from the sole's centre (the sole: |x| <= " + Fixed(X, 3) + ", |y| <= " + Fixed(Y, 3) + " m)";
  }
  const double tmax = mup * (X + Y) * fz - std::abs(Y * fx + mup * tx) - std::abs(X * fy + mup * ty);
  const double tmin = -mup * (X + Y) * fz + std::abs(Y * fx - mup * tx) + std::abs(X * fy - mup * ty);
  if (tz > tmax || tz < tmin) {
    const double bound = tz > tmax ? tmax : -tmin;
    over = (std::abs(tz) - bound) / (mup * (X + Y) * fz);
    return "needs a yaw moment of " + Fixed(std::abs(tz) / fz, 3) +
           " m F_z about the sole's centre (its four corners hold " + Fixed(std::max(bound, 0.0) / fz, 3) +
           " m F_z there by friction, mu " + Fixed(mu, 2) + ")";
  }
  return "";
}

std::string WalkingPlanPhaseName(const WalkingPlan& plan, double t) {
  const std::vector<WalkingPlanSegment>& segments = plan.segments();
  const size_t k = plan.SegmentIndexAt(t);
  if (segments[k].domain != WalkingDomain::kDoubleSupport)
    return PeriodicSingleSupport(segments[k]) ? GaitOfSingleSupport(segments, k) : TransitionName(segments, k);
  if (k == 0) return "standing";
  return PeriodicSingleSupport(segments[k - 1]) ? GaitOfSingleSupport(segments, k - 1)
                                                : TransitionName(segments, k - 1);
}

WalkingFeasibilityReport CheckWalkingPlanFeasibility(const MultibodyModel& model, const WalkingPlan& plan,
                                                     const WalkingDiagramParams& diagram, double end_time_s,
                                                     const WalkingFeasibilityParams& params) {
  params.Validate();
  const auto t0 = std::chrono::steady_clock::now();
  SwingFootTrajectoryParams swing = diagram.swing;  // as the diagram tracks it: ankle height from the robot's sole
  swing.ankle_height_m = -model.contacts()[model.ContactIndex("left_foot")].points.front().z();
  const SoleRectangle soles[2] = {SoleRectangleOf(model, "left_foot"), SoleRectangleOf(model, "right_foot")};
  const int left_body = model.BodyIndex("left_foot");
  WalkingFeasibilityReport r;
  r.peak_torque_Nm = Eigen::VectorXd::Zero(model.nu());
  r.peak_time_s = Eigen::VectorXd::Zero(model.nu());
  Finding torque, sole, joint;
  MultibodyWorkspace ws(model);
  const Eigen::VectorXd &lower = model.position_lower_limits(), &upper = model.position_upper_limits();
  const double m = params.joint_limit_margin_rad;
  auto visit = [&](const WalkingPlanInverseDynamicsSample& s) {
    if (s.time_s < params.start_time_s) return;
    ++r.samples;
    for (int i = 6; i < model.nv(); ++i) {
      const double below = lower[i] + m - s.q[i], above = s.q[i] - (upper[i] - m);
      if (std::max(below, above) > joint.excess) {
        const bool low = below > above;
        joint = {std::max(below, above),
                 "the " + JointWords(model.JointName(i)) + " reaches " + Fixed(s.q[i], 3) + " rad (limit " +
                     Fixed(low ? lower[i] : upper[i], 3) + " rad" + (m > 0 ? ", margin " + Fixed(m, 3) + " rad" : "") +
                     ")",
                 s.time_s};
      }
    }
    if (s.double_support) return;
    ++r.single_support_samples;
    for (int j = 0; j < model.nu(); ++j) {
      const double need = std::abs(s.u[j]), limit = model.actuators()[j].torque_limit_Nm;
      if (need > r.peak_torque_Nm[j]) r.peak_torque_Nm[j] = need, r.peak_time_s[j] = s.time_s;
      const double over = need / ((1.0 - params.torque_margin) * limit) - 1.0;
      if (over > torque.excess)
        torque = {over,
                  "the " + JointWords(model.actuators()[j].joint) + " needs " + Fixed(need, 0) + " N m (limit " +
                      Fixed(limit, 0) + " N m" +
                      (params.torque_margin > 0 ? ", margin " + Fixed(params.torque_margin, 2) : "") + ")",
                  s.time_s};
    }
    const int side = s.stance_body == left_body ? 0 : 1;
    const Eigen::Isometry3d pose = CalcLinkPose(model, ws, s.q, s.stance_body);
    const Eigen::Vector3d ankle_sole = pose * Eigen::Vector3d(0, 0, -swing.ankle_height_m);
    const Eigen::Vector3d centre = pose * soles[side].center;
    const Eigen::Vector3d force = s.wrench.tail<3>();
    const Eigen::Vector3d moment = s.wrench.head<3>() + (ankle_sole - centre).cross(force);
    Eigen::Matrix<double, 6, 1> local;
    local << pose.linear().transpose() * moment, pose.linear().transpose() * force;
    if (local[5] > 0) r.peak_yaw_ratio_m = std::max(r.peak_yaw_ratio_m, std::abs(local[2]) / local[5]);
    double over = 0.0;
    const std::string problem = SoleWrenchProblem(soles[side], local, params, &over);
    if (!problem.empty() && over > sole.excess)
      sole = {over, std::string("the ") + (side == 0 ? "left" : "right") + " sole " + problem, s.time_s};
  };
  ForEachSingleSupportInverseDynamics(
      model, plan, swing,
      {.sample_period_s = params.sample_period_s, .end_time_s = end_time_s, .visit_double_support = true}, visit);
  if (!torque.what.empty()) r.torque_problem = Describe(plan, torque);
  if (!sole.what.empty()) r.sole_problem = Describe(plan, sole);
  if (!joint.what.empty()) r.joint_limit_problem = Describe(plan, joint);
  const std::string* enforced[3] = {&r.torque_problem, params.enforce_sole_wrench ? &r.sole_problem : nullptr,
                                    params.enforce_joint_limits ? &r.joint_limit_problem : nullptr};
  for (const std::string* p : enforced)
    if (p != nullptr && !p->empty()) r.problem += (r.problem.empty() ? "" : "; also ") + *p;
  r.solve_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

std::function<void(const WalkingPlan&, double, double)> WalkingChangeFeasibilityCheck(
    std::shared_ptr<const MultibodyModel> model, const WalkingDiagramParams& diagram, WalkingFeasibilityParams params) {
  if (model == nullptr) throw std::invalid_argument("WalkingChangeFeasibilityCheck: the model is null");
  params.Validate();
  return [model, diagram, params](const WalkingPlan& plan, double from_s, double to_s) {
    WalkingFeasibilityParams window = params;
    window.start_time_s = std::max(0.0, from_s);
    const WalkingDiagram d = BuildWalkingDiagram(model, plan, diagram);
    const WalkingFeasibilityReport r = CheckWalkingPlanFeasibility(*model, d.plan, diagram, to_s, window);
    if (!r.problem.empty()) throw std::runtime_error(r.problem);
  };
}

}  // namespace rome
