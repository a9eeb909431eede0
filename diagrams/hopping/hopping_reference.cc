#include "diagrams/hopping/hopping_reference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome {

namespace {
constexpr int kJump = 0, kFlight = 1, kLanding = 2;
// Discrete state.
constexpr int kDomain = 0, kDomainStart = 1, kCentreX = 2, kCentreY = 3, kYaw0 = 4,
              kMotorTargets = 5;  // 10 motor targets
constexpr int kLandComX = 15, kLandComXdot = 16, kLandPitch = 17, kLandPitchRate = 18, kHopsDone = 19, kJumpPlans = 20,
              kLandingPlans = 21, kPlanFailures = 22, kHoldL = 23, kJumpPitch = 24, kJumpPitchRate = 25,
              kJumpHipPerPitch = 26, kFlightPitch0 = 28, kFlightHipPerPitch = 29, kForceIntegral = 31,
              kFixed = 32;  // *HipPerPitch: 2 legs

// Quintic from (p0, v0, a0 = 0) to (p1, 0, 0) over T; value, rate, acceleration at s (held after T).
Eigen::Vector3d Blend(double s, double T, double p0, double v0, double p1) {
  if (s >= T) return {p1, 0.0, 0.0};
  s = std::max(s, 0.0);
  const double tau = s / T, D = p1 - p0 - v0 * T, E = -v0 * T;
  const double c3 = 10 * D - 4 * E, c4 = 7 * E - 15 * D, c5 = 6 * D - 3 * E;
  const double t2 = tau * tau, t3 = t2 * tau, t4 = t3 * tau, t5 = t4 * tau;
  return {p0 + v0 * T * tau + c3 * t3 + c4 * t4 + c5 * t5, v0 + (3 * c3 * t2 + 4 * c4 * t3 + 5 * c5 * t4) / T,
          (6 * c3 * tau + 12 * c4 * t2 + 20 * c5 * t3) / (T * T)};
}
}  // namespace

struct HoppingReference::Scratch {
  explicit Scratch(const MultibodyModel& model) : ws(model), A_G(6, model.nv()) {}
  MultibodyWorkspace ws;
  Eigen::MatrixXd A_G;
};

std::any HoppingReference::AllocateScratch() const { return Scratch(*model_); }

double HoppingReference::HipPerPitch(const Eigen::VectorXd& q, int leg) const {
  // (dθ_sole/dθ_base) / (dθ_sole/dq_hip): the hip turn that keeps the sole's world pitch when the pelvis pitches.
  const double h = 1e-6, base = SolePitch(q, contact_[leg]);
  Eigen::VectorXd dq = q;
  dq[model_->VelocityIndex("base_pitch")] += h;
  const double per_base = (SolePitch(dq, contact_[leg]) - base) / h;
  dq = q;
  dq[hip_pitch_[leg]] += h;
  const double per_hip = (SolePitch(dq, contact_[leg]) - base) / h;
  return std::abs(per_hip) > 1e-9 ? per_base / per_hip : 0.0;
}

HoppingReference::HoppingReference(std::string name, std::shared_ptr<const MultibodyModel> model,
                                   LegLengthFunction leg_length, JumpPlanner jump_planner,
                                   LandingPlanner landing_planner, HoppingOutputLayout layout,
                                   HoppingReferenceParams params)
    : LeafSystem(std::move(name)),
      model_(std::move(model)),
      leg_length_(std::move(leg_length)),
      jump_planner_(std::move(jump_planner)),
      landing_planner_(std::move(landing_planner)),
      layout_(layout),
      params_(std::move(params)) {
  if (!model_) ThrowError("null MultibodyModel");
  if (!leg_length_) ThrowError("no leg-length function given");
  if (!jump_planner_) ThrowError("no jump planner given");
  if (model_->nu() != 10)
    ThrowError("robot '" + model_->name() + "' has " + std::to_string(model_->nu()) +
               " actuators; the hopping outputs need Cassie's 10");
  if (params_.hops < 1) ThrowError("params.hops = " + std::to_string(params_.hops) + " must be at least 1");
  if (params_.max_plan_nodes < 2)
    ThrowError("params.max_plan_nodes = " + std::to_string(params_.max_plan_nodes) + " must be at least 2");
  for (double value : {params_.update_period_s, params_.landing_blend_s, params_.landing_fallback_s})
    if (!(value > 0.0) || !std::isfinite(value))
      ThrowError("update_period_s, landing_blend_s and landing_fallback_s must be positive, got " +
                 std::to_string(value));
  if (params_.landing_blend_s < params_.update_period_s)
    ThrowError("params.landing_blend_s = " + std::to_string(params_.landing_blend_s) +
               " s must be at least update_period_s = " + std::to_string(params_.update_period_s) + " s");
  if (!(params_.settle_time_s >= 0.0) || !(params_.rest_time_s >= 0.0))
    ThrowError("settle_time_s and rest_time_s must be >= 0");
  if (!(params_.jump_force_feedback >= 0.0) || !std::isfinite(params_.jump_force_feedback) ||
      !(params_.jump_force_integral_per_s >= 0.0) || !std::isfinite(params_.jump_force_integral_per_s) ||
      !(params_.jump_force_correction_max_m > 0.0) || !std::isfinite(params_.jump_force_correction_max_m))
    ThrowError("jump_force_feedback = " + std::to_string(params_.jump_force_feedback) +
               " and jump_force_integral_per_s = " + std::to_string(params_.jump_force_integral_per_s) +
               " must be finite and >= 0, jump_force_correction_max_m = " +
               std::to_string(params_.jump_force_correction_max_m) + " finite and > 0");
  if (!(params_.rest_max_speed >= 0.0) || !(params_.max_rest_time_s >= params_.rest_time_s) ||
      !std::isfinite(params_.max_rest_time_s))
    ThrowError("rest_max_speed = " + std::to_string(params_.rest_max_speed) +
               " must be >= 0 and max_rest_time_s = " + std::to_string(params_.max_rest_time_s) +
               " finite and >= rest_time_s = " + std::to_string(params_.rest_time_s));
  if (!(params_.landing_deflection_feedback >= 0.0) || !std::isfinite(params_.landing_deflection_feedback))
    ThrowError("params.landing_deflection_feedback = " + std::to_string(params_.landing_deflection_feedback) +
               " must be finite and >= 0");
  const std::string* knees[2] = {&params_.left_knee, &params_.right_knee};
  const std::string* shins[2] = {&params_.left_shin, &params_.right_shin};
  const std::string* tarsi[2] = {&params_.left_tarsus, &params_.right_tarsus};
  const std::string* toes[2] = {&params_.left_toe, &params_.right_toe};
  const std::string* hips[2] = {&params_.left_hip_pitch_link,
                                &params_.right_hip_pitch_link};  // link and joint share the name
  const std::string* feet[2] = {&params_.left_toe_link, &params_.right_toe_link};
  try {
    for (int leg = 0; leg < 2; ++leg) {
      knee_[leg] = model_->VelocityIndex(*knees[leg]);
      shin_[leg] = model_->VelocityIndex(*shins[leg]);
      tarsus_[leg] = model_->VelocityIndex(*tarsi[leg]);
      toe_[leg] = model_->VelocityIndex(*toes[leg]);
      hip_pitch_[leg] = model_->VelocityIndex(*hips[leg]);
      hip_actuator_[leg] = -1;
      for (int i = 0; i < model_->nu(); ++i)
        if (model_->actuators()[i].v_index == hip_pitch_[leg]) hip_actuator_[leg] = i;
      if (hip_actuator_[leg] < 0) throw std::invalid_argument("joint '" + *hips[leg] + "' has no actuator");
      hip_link_[leg] = model_->BodyIndex(*hips[leg]);
      toe_link_[leg] = model_->BodyIndex(*feet[leg]);
      contact_[leg] = model_->ContactIndex(leg == 0 ? params_.left_contact : params_.right_contact);
    }
  } catch (const std::exception& e) { ThrowError(std::string("robot '") + model_->name() + "': " + e.what()); }
  // The rigid-spring rule knee + tarsus = c at the nominal pose (springs undeflected there).
  const Eigen::VectorXd& qn = model_->q_nominal();
  rigid_knee_plus_tarsus_ = qn[knee_[0]] + qn[tarsus_[0]];
  const int n = params_.max_plan_nodes;
  jump_plan_offset_ = kFixed;
  landing_plan_offset_ = kFixed + 1 + 7 * n;  // per plan: node count, then t, L, L̇, x, ẋ, F, n K (N each)
  size_ = landing_plan_offset_ + 1 + 7 * n;
  Eigen::VectorXd xd0 = Eigen::VectorXd::Zero(size_);
  xd0[kDomain] = kLanding;
  DeclareDiscreteState(xd0);
  const int nv = model_->nv();
  state_port_ = DeclareInputPort("state", 2 * nv);
  mode_port_ = DeclareTypedInputPort<int>("mode");
  forces_port_ = DeclareInputPort("contact_forces", 3 * model_->num_contacts());
  // The flight hip targets read the state when params.flight_hip_pitch_follow ≠ 0.
  std::vector<int> reads;
  if (params_.flight_hip_pitch_follow != 0.0 || params_.landing_deflection_feedback != 0.0)
    reads.push_back(state_port_);
  if (params_.jump_force_feedback != 0.0 || params_.jump_force_integral_per_s != 0.0) reads.push_back(forces_port_);
  DeclareOutputPort(
      "desired", 3 * layout_.size, [this](const LeafContext& c, Eigen::VectorXd* y) { CalcDesired(c, y); },
      reads.empty() ? Feedthrough::None() : Feedthrough::From(reads));
  DeclareTypedOutputPort<int>(
      "domain", [](const LeafContext& c, int* y) { *y = static_cast<int>(c.discrete_state()[kDomain]); },
      Feedthrough::None());
  DeclareOutputPort(
      "plan_status", {"jump_plans", "landing_plans", "planner_failures"},
      [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state().segment<3>(kJumpPlans); },
      Feedthrough::None());
  DeclarePeriodicDiscreteUpdate(params_.update_period_s, 0.0, [this](const LeafContext& c, Eigen::VectorXd* next) {
    return PeriodicUpdate(c, next);
  });
  DeclareEventUpdate(
      "domain_switch", EventTrigger::AnyGuard(),
      [this](const LeafContext& c, const EventRecord& e, State* next) { return GuardUpdate(c, e, next); });
}

RomState HoppingReference::MeasureRomState(const Eigen::VectorXd& q, const Eigen::VectorXd& v) const {
  MultibodyWorkspace ws(*model_);
  return MeasureRomState(ws, q, v);
}

RomState HoppingReference::MeasureRomState(MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v) const {
  RomState r;
  for (int leg = 0; leg < 2; ++leg) {
    const Eigen::Vector3d hip = CalcLinkPose(*model_, ws, q, hip_link_[leg]).translation();
    const Eigen::Vector3d toe = CalcLinkPose(*model_, ws, q, toe_link_[leg]).translation();
    double L = 0, dL = 0;
    leg_length_(q[knee_[leg]], &L, &dL);
    r.x += 0.5 * (hip - toe).norm();
    r.L += 0.5 * L;
    r.Ldot += 0.5 * dL * v[knee_[leg]];
  }
  r.xdot = CalcComVelocity(*model_, ws, q, v).z();
  return r;
}

void HoppingReference::SnapshotSupport(const Eigen::VectorXd& q, Eigen::VectorXd* xd) const {
  MultibodyWorkspace ws(*model_);
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (int c = 0; c < model_->num_contacts(); ++c)
    for (int p = 0; p < static_cast<int>(model_->contacts()[c].points.size()); ++p)
      centre += CalcContactPointPosition(*model_, ws, q, c, p).head<2>();
  int points = 0;
  for (const ContactInfo& c : model_->contacts()) points += static_cast<int>(c.points.size());
  centre /= points;
  (*xd)[kCentreX] = centre.x();
  (*xd)[kCentreY] = centre.y();
}

double HoppingReference::SolePitch(const Eigen::VectorXd& q, int contact) const {
  MultibodyWorkspace ws(*model_);
  const Eigen::Vector3d d =
      CalcContactPointPosition(*model_, ws, q, contact, 1) - CalcContactPointPosition(*model_, ws, q, contact, 0);
  return std::atan2(d.z(), d.head<2>().norm());
}

void HoppingReference::Initialize(LeafContext& context, const Eigen::VectorXd& q) const {
  Eigen::VectorXd& xd = context.get_mutable_state().discrete;
  xd.setZero();
  xd[kDomain] = kLanding;
  xd[kDomainStart] = context.time();
  SnapshotSupport(q, &xd);
  xd[kYaw0] = q[model_->VelocityIndex("base_yaw")];
  double L = 0, dL = 0, sum = 0;
  for (int leg = 0; leg < 2; ++leg) {
    leg_length_(q[knee_[leg]], &L, &dL);
    sum += 0.5 * L;
  }
  xd[kHoldL] = sum;
}

void HoppingReference::WritePlan(int offset, const LegLengthPlan& plan, Eigen::VectorXd* xd) const {
  const int n = static_cast<int>(plan.t.size()), N = params_.max_plan_nodes;
  if (n < 2 || n > N || plan.L.size() != n || plan.Ldot.size() != n)
    throw std::invalid_argument("system '" + name() + "': a leg-length plan needs 2.." + std::to_string(N) +
                                " nodes with t, L, Ldot of equal size; got " + std::to_string(n) + ", " +
                                std::to_string(plan.L.size()) + ", " + std::to_string(plan.Ldot.size()));
  (*xd)[offset] = n;
  xd->segment(offset + 1, n) = plan.t;
  xd->segment(offset + 1 + N, n) = plan.L;
  xd->segment(offset + 1 + 2 * N, n) = plan.Ldot;
  if ((plan.x.size() != 0 || plan.xdot.size() != 0) && (plan.x.size() != n || plan.xdot.size() != n))
    throw std::invalid_argument("system '" + name() + "': a leg-length plan's x and xdot must be empty or have its " +
                                std::to_string(n) + " nodes; got " + std::to_string(plan.x.size()) + " and " +
                                std::to_string(plan.xdot.size()));
  const bool has_x = plan.x.size() == n;
  if (has_x)
    xd->segment(offset + 1 + 3 * N, n) = plan.x, xd->segment(offset + 1 + 4 * N, n) = plan.xdot;
  else
    xd->segment(offset + 1 + 3 * N, 2 * N).setConstant(std::numeric_limits<double>::quiet_NaN());
  if ((plan.force.size() != 0 || plan.stiffness.size() != 0) && (plan.force.size() != n || plan.stiffness.size() != n))
    throw std::invalid_argument("system '" + name() +
                                "': a leg-length plan's force and stiffness must be empty or have its " +
                                std::to_string(n) + " nodes; got " + std::to_string(plan.force.size()) + " and " +
                                std::to_string(plan.stiffness.size()));
  if (plan.force.size() == n) {
    for (int k = 0; k < n; ++k)
      if (!(std::isfinite(plan.force[k]) && plan.stiffness[k] > 0.0))
        throw std::invalid_argument("system '" + name() +
                                    "': a leg-length plan's force must be finite and its stiffness > 0; node " +
                                    std::to_string(k) + " has " + std::to_string(plan.force[k]) + " N, " +
                                    std::to_string(plan.stiffness[k]) + " N/m");
    xd->segment(offset + 1 + 5 * N, n) = plan.force, xd->segment(offset + 1 + 6 * N, n) = plan.stiffness;
  } else {
    xd->segment(offset + 1 + 5 * N, 2 * N).setConstant(std::numeric_limits<double>::quiet_NaN());
  }
}

Eigen::Vector3d HoppingReference::Evaluate(const Eigen::Ref<const Eigen::VectorXd>& t,
                                           const Eigen::Ref<const Eigen::VectorXd>& L,
                                           const Eigen::Ref<const Eigen::VectorXd>& Ldot, int n, double s) {
  if (n < 2) return {n == 1 ? L[0] : 0.0, 0.0, 0.0};
  if (s >= t[n - 1]) return {L[n - 1], 0.0, 0.0};  // hold the last node (spec [R])
  s = std::max(s, t[0]);
  int k = static_cast<int>(std::upper_bound(t.data(), t.data() + n, s) - t.data()) - 1;
  k = std::clamp(k, 0, n - 2);
  const double h = t[k + 1] - t[k], tau = (s - t[k]) / h;
  const double p0 = L[k], p1 = L[k + 1], m0 = h * Ldot[k], m1 = h * Ldot[k + 1];
  const double t2 = tau * tau, t3 = t2 * tau;
  const double value = (2 * t3 - 3 * t2 + 1) * p0 + (t3 - 2 * t2 + tau) * m0 + (-2 * t3 + 3 * t2) * p1 + (t3 - t2) * m1;
  const double rate =
      ((6 * t2 - 6 * tau) * p0 + (3 * t2 - 4 * tau + 1) * m0 + (-6 * t2 + 6 * tau) * p1 + (3 * t2 - 2 * tau) * m1) / h;
  const double accel = ((12 * tau - 6) * p0 + (6 * tau - 4) * m0 + (-12 * tau + 6) * p1 + (6 * tau - 2) * m1) / (h * h);
  return {value, rate, accel};
}

LegLengthPlan HoppingReference::jump_plan(const LeafContext& context) const {
  const Eigen::VectorXd& xd = context.discrete_state();
  const int n = static_cast<int>(xd[jump_plan_offset_]), N = params_.max_plan_nodes;
  return {xd.segment(jump_plan_offset_ + 1, n),         xd.segment(jump_plan_offset_ + 1 + N, n),
          xd.segment(jump_plan_offset_ + 1 + 2 * N, n), xd.segment(jump_plan_offset_ + 1 + 3 * N, n),
          xd.segment(jump_plan_offset_ + 1 + 4 * N, n), xd.segment(jump_plan_offset_ + 1 + 5 * N, n),
          xd.segment(jump_plan_offset_ + 1 + 6 * N, n)};
}

LegLengthPlan HoppingReference::landing_plan(const LeafContext& context) const {
  const Eigen::VectorXd& xd = context.discrete_state();
  const int n = static_cast<int>(xd[landing_plan_offset_]), N = params_.max_plan_nodes;
  return {xd.segment(landing_plan_offset_ + 1, n),         xd.segment(landing_plan_offset_ + 1 + N, n),
          xd.segment(landing_plan_offset_ + 1 + 2 * N, n), xd.segment(landing_plan_offset_ + 1 + 3 * N, n),
          xd.segment(landing_plan_offset_ + 1 + 4 * N, n), xd.segment(landing_plan_offset_ + 1 + 5 * N, n),
          xd.segment(landing_plan_offset_ + 1 + 6 * N, n)};
}

// Initialize holds the standing leg length (> 0); the declared default state holds 0.
bool HoppingReference::initialized(const LeafContext& context) const { return context.discrete_state()[kHoldL] > 0.0; }

double HoppingReference::domain_start_time(const LeafContext& context) const {
  return context.discrete_state()[kDomainStart];
}

void HoppingReference::CalcDesired(const LeafContext& context, Eigen::VectorXd* y) const {
  const Eigen::VectorXd& xd = context.discrete_state();
  const int N = params_.max_plan_nodes, kNy = layout_.size;
  const int kComX = layout_.com_x, kComY = layout_.com_y, kYaw = layout_.yaw, kPitch = layout_.pitch,
            kMotors = layout_.motors;
  y->setZero();
  auto set = [&](int index, const Eigen::Vector3d& value) {
    for (int k = 0; k < 3; ++k) (*y)[k * kNy + index] = value[k];
  };
  const int domain = static_cast<int>(xd[kDomain]);
  const double s = context.time() - xd[kDomainStart];
  (*y)[kComX] = xd[kCentreX];
  (*y)[kComY] = xd[kCentreY];
  (*y)[kYaw] = xd[kYaw0];
  // Eq. (42): H_pitch^d = 0 (layout_.momentum, if present, stays 0).
  if (domain == kFlight) {
    y->segment(kMotors, 10) = xd.segment(kMotorTargets, 10);
    if (params_.flight_hip_pitch_follow != 0.0) {
      // The hips turn with the pelvis pitch so the legs keep their lift-off world pitch (see the params).
      const Eigen::VectorXd& x = EvalInput(context, state_port_);
      const int pitch = model_->VelocityIndex("base_pitch"), nv = model_->nv();
      for (int leg = 0; leg < 2; ++leg) {
        // HipPerPitch is (dθ_sole/dθ) / (dθ_sole/dq_hip): the hip turn that keeps the sole's world pitch is −r dθ.
        const double k = -params_.flight_hip_pitch_follow * xd[kFlightHipPerPitch + leg];
        (*y)[kMotors + hip_actuator_[leg]] += k * (x[pitch] - xd[kFlightPitch0]);
        (*y)[kNy + kMotors + hip_actuator_[leg]] = k * x[nv + pitch];
      }
    }
    return;
  }
  Eigen::Vector3d L(xd[kHoldL], 0.0, 0.0);
  if (domain == kJump) {
    set(kPitch, {xd[kJumpPitch], xd[kJumpPitchRate], 0.0});
    const int o = jump_plan_offset_;
    L = Evaluate(xd.segment(o + 1, N), xd.segment(o + 1 + N, N), xd.segment(o + 1 + 2 * N, N), static_cast<int>(xd[o]),
                 s);
    if (params_.jump_force_feedback != 0.0 || params_.jump_force_integral_per_s != 0.0) {
      // GRF feedback (see the params), from the force measured now; the integral comes from the periodic update.
      double fade = 0.0;
      const double e = JumpForceError(context, s, &fade);
      const double limit = params_.jump_force_correction_max_m;
      L[0] += fade * std::clamp(params_.jump_force_feedback * e + xd[kForceIntegral], -limit, limit);
    }
  } else if (xd[kHopsDone] > 0) {  // landing after a hop (before the first hop: settle at the held length)
    const int o = landing_plan_offset_;
    L = Evaluate(xd.segment(o + 1, N), xd.segment(o + 1 + N, N), xd.segment(o + 1 + 2 * N, N), static_cast<int>(xd[o]),
                 s);
    if (params_.landing_deflection_feedback != 0.0 && std::isfinite(xd[o + 1 + 3 * N])) {
      const Eigen::Vector3d x_plan = Evaluate(xd.segment(o + 1, N), xd.segment(o + 1 + 3 * N, N),
                                              xd.segment(o + 1 + 4 * N, N), static_cast<int>(xd[o]), s);
      const Eigen::VectorXd& x = EvalInput(context, state_port_);
      const int nv = model_->nv();
      const RomState r = MeasureRomState(context.scratch<Scratch>().ws, x.head(nv), x.tail(nv));
      L[0] += params_.landing_deflection_feedback * (r.x - x_plan[0]);
      L[1] += params_.landing_deflection_feedback * (r.xdot - x_plan[1]);
    }
    set(kComX, Blend(s, params_.landing_blend_s, xd[kLandComX], xd[kLandComXdot], xd[kCentreX]));
    set(kPitch, Blend(s, params_.landing_blend_s, xd[kLandPitch], xd[kLandPitchRate], 0.0));
  }
  set(layout_.leg_left, L);
  set(layout_.leg_right, L);
}

double HoppingReference::JumpForceError(const LeafContext& context, double s, double* fade) const {
  // (F_plan − F) / (n K): the plan's F and n K linear between nodes, F the plant's total normal force; fade =
  // clamp(F_plan / F_plan(0), 0, 1).
  const Eigen::VectorXd& xd = context.discrete_state();
  const int o = jump_plan_offset_, N = params_.max_plan_nodes, n = static_cast<int>(xd[o]);
  *fade = 0.0;
  if (n < 2 || !std::isfinite(xd[o + 1 + 5 * N]) || s > xd[o + n]) return 0.0;
  const auto t = xd.segment(o + 1, n);
  int k = static_cast<int>(std::upper_bound(t.data(), t.data() + n, s) - t.data()) - 1;
  k = std::clamp(k, 0, n - 2);
  const double w = std::clamp((s - t[k]) / (t[k + 1] - t[k]), 0.0, 1.0);
  const double F_plan = (1 - w) * xd[o + 1 + 5 * N + k] + w * xd[o + 1 + 5 * N + k + 1];
  const double K = (1 - w) * xd[o + 1 + 6 * N + k] + w * xd[o + 1 + 6 * N + k + 1];
  const Eigen::VectorXd& f = EvalInput(context, forces_port_);
  const double F0 = xd[o + 1 + 5 * N];
  *fade = F0 > 0.0 ? std::clamp(F_plan / F0, 0.0, 1.0) : 1.0;
  return (F_plan - (f[3 * contact_[0] + 2] + f[3 * contact_[1] + 2])) / K;
}

EventStatus HoppingReference::PeriodicUpdate(const LeafContext& context, Eigen::VectorXd* next) const {
  const Eigen::VectorXd& xd = context.discrete_state();
  if (static_cast<int>(xd[kDomain]) == kJump &&
      (params_.jump_force_feedback != 0.0 || params_.jump_force_integral_per_s != 0.0)) {
    // The integral of the GRF feedback: I += T k_I e, clamped to ±jump_force_correction_max_m.
    double fade = 0.0;
    const double e = JumpForceError(context, context.time() - xd[kDomainStart], &fade);
    const double limit = params_.jump_force_correction_max_m;
    (*next)[kForceIntegral] =
        std::clamp(xd[kForceIntegral] + params_.update_period_s * params_.jump_force_integral_per_s * e, -limit, limit);
  }
  if (static_cast<int>(xd[kDomain]) == kJump && params_.jump_momentum_gain > 0.0) {
    // Jump pitch reference from the centroidal pitch momentum (ours, in place of the H_pitch output of Eq. (41)): the
    // pelvis is asked to turn at the rate that cancels H_pitch, θ̇_d = θ̇ − k H_pitch / I_p, with I_p = ∂H_pitch/∂θ̇ along
    // "pelvis pitches, hips turn back, legs keep their world angle"; θ_d integrates θ̇_d. The pelvis pitch stays an
    // RD2 output (its position anchored), which keeps the closed loop stable where H_pitch as an RD1 output is not.
    Scratch& s = context.scratch<Scratch>();
    const Eigen::VectorXd& x = EvalInput(context, state_port_);
    const int nv = model_->nv(), pitch = model_->VelocityIndex("base_pitch");
    CalcCentroidalMomentumMatrix(*model_, s.ws, x.head(nv), s.A_G);
    const double H = s.A_G.row(1).dot(x.tail(nv));
    double I_p = s.A_G(1, pitch);
    for (int leg = 0; leg < 2; ++leg) I_p -= xd[kJumpHipPerPitch + leg] * s.A_G(1, hip_pitch_[leg]);
    const double rate = std::abs(I_p) > 1e-6 ? x[nv + pitch] - params_.jump_momentum_gain * H / I_p : 0.0;
    (*next)[kJumpPitchRate] = rate;
    (*next)[kJumpPitch] = xd[kJumpPitch] + params_.update_period_s * rate;
    return EventStatus::Succeeded();
  }
  if (static_cast<int>(xd[kDomain]) != kLanding || xd[kHopsDone] >= params_.hops) return EventStatus::Succeeded();
  const double wait = xd[kHopsDone] == 0 ? params_.settle_time_s : params_.rest_time_s;
  const double waited = context.time() - xd[kDomainStart];
  if (waited < wait - 1e-12) return EventStatus::Succeeded();
  const Eigen::VectorXd& x = EvalInput(context, state_port_);
  const int nv = model_->nv();
  // The next hop waits until the robot is at rest (max |q̇| < rest_max_speed), at most max_rest_time_s.
  if (xd[kHopsDone] > 0 && params_.rest_max_speed > 0.0 && waited < params_.max_rest_time_s - 1e-12 &&
      x.tail(nv).cwiseAbs().maxCoeff() >= params_.rest_max_speed)
    return EventStatus::Succeeded();
  const Eigen::VectorXd q = x.head(nv), v = x.tail(nv);
  LegLengthPlan plan;
  std::string message;
  const RomState start = MeasureRomState(q, v);
  if (!jump_planner_(start, &plan, &message)) {
    (*next)[kPlanFailures] += 1.0;
    return EventStatus::Failed("jump plan failed at t = " + std::to_string(context.time()) + " s: " + message);
  }
  if ((params_.jump_force_feedback != 0.0 || params_.jump_force_integral_per_s != 0.0) && plan.force.size() == 0) {
    (*next)[kPlanFailures] += 1.0;
    return EventStatus::Failed(
        "system '" + name() + "': the jump plan at t = " + std::to_string(context.time()) +
        " s has no force and stiffness, which jump_force_feedback / jump_force_integral_per_s need (set both to 0)");
  }
  try {
    WritePlan(jump_plan_offset_, plan, next);
  } catch (const std::exception& e) { return EventStatus::Failed(e.what()); }
  (*next)[kJumpPlans] += 1.0;
  (*next)[kJumpPitch] = q[model_->VelocityIndex("base_pitch")];
  (*next)[kJumpPitchRate] = 0.0;
  (*next)[kForceIntegral] = 0.0;
  for (int leg = 0; leg < 2; ++leg) (*next)[kJumpHipPerPitch + leg] = HipPerPitch(q, leg);
  (*next)[kDomain] = kJump;
  (*next)[kDomainStart] = context.time();
  SnapshotSupport(q, next);
  return EventStatus::Succeeded();
}

EventStatus HoppingReference::GuardUpdate(const LeafContext& context, const EventRecord&, State* state) const {
  Eigen::VectorXd* next = &state->discrete;
  const int plant_mode = EvalTypedInput<int>(context, mode_port_);
  const int domain = static_cast<int>(context.discrete_state()[kDomain]);
  const int nv = model_->nv();
  const Eigen::VectorXd& x = EvalInput(context, state_port_);
  const Eigen::VectorXd q = x.head(nv), v = x.tail(nv);
  if (plant_mode == kFlight && domain != kFlight) {
    // Lift-off (Eq. (19)): hold the motors (Eq. (43)); toes corrected for the springs' unloading (see the header).
    for (int i = 0; i < model_->nu(); ++i) (*next)[kMotorTargets + i] = q[model_->actuators()[i].v_index];
    for (int leg = 0; leg < 2; ++leg) {
      Eigen::VectorXd predicted = q;
      predicted[shin_[leg]] = 0.0;
      predicted[tarsus_[leg]] = rigid_knee_plus_tarsus_ - q[knee_[leg]];
      const int contact = contact_[leg];
      const double target = SolePitch(q, contact);  // level now (the foot was on the ground)
      for (int it = 0; it < 3; ++it) {
        const double h = 1e-6, pitch = SolePitch(predicted, contact);
        Eigen::VectorXd bumped = predicted;
        bumped[toe_[leg]] += h;
        const double slope = (SolePitch(bumped, contact) - pitch) / h;
        if (std::abs(slope) < 1e-9) break;
        predicted[toe_[leg]] -= (pitch - target) / slope;
      }
      for (int i = 0; i < model_->nu(); ++i)
        if (model_->actuators()[i].v_index == toe_[leg]) (*next)[kMotorTargets + i] = predicted[toe_[leg]];
    }
    (*next)[kFlightPitch0] = q[model_->VelocityIndex("base_pitch")];
    for (int leg = 0; leg < 2; ++leg) (*next)[kFlightHipPerPitch + leg] = HipPerPitch(q, leg);
    (*next)[kDomain] = kFlight;
    (*next)[kDomainStart] = context.time();
    if (landing_planner_ && domain == kJump) {
      // The landing NLP from the touchdown predicted at a planned lift-off (not a bounce in Landing): only a warm start
      // for the touchdown solve, so a failure is counted (planner_failures) and nothing falls back.
      LegLengthPlan predicted;
      std::string message;
      if (landing_planner_(MeasureRomState(q, v), LandingSolve::kPredictedAtLiftoff, &predicted, &message))
        (*next)[kLandingPlans] += 1.0;
      else
        (*next)[kPlanFailures] += 1.0;
    }
  } else if (plant_mode != kFlight && domain == kFlight) {
    // Touchdown (Eq. (21)): landing from the post-impact state.
    MultibodyWorkspace ws(*model_);
    (*next)[kDomain] = kLanding;
    (*next)[kDomainStart] = context.time();
    (*next)[kHopsDone] += 1.0;
    SnapshotSupport(q, next);
    (*next)[kLandComX] = CalcComPosition(*model_, ws, q).x();
    (*next)[kLandComXdot] = CalcComVelocity(*model_, ws, q, v).x();
    (*next)[kLandPitch] = q[model_->VelocityIndex("base_pitch")];
    (*next)[kLandPitchRate] = v[model_->VelocityIndex("base_pitch")];
    const RomState post = MeasureRomState(q, v);
    LegLengthPlan plan;
    std::string message;
    bool ok = landing_planner_ && landing_planner_(post, LandingSolve::kAtTouchdown, &plan, &message);
    if (ok) {
      (*next)[kLandingPlans] += 1.0;
    } else {
      // Fallback (counted): quintic from the post-impact leg length and rate to the standing length.
      (*next)[kPlanFailures] += landing_planner_ ? 1.0 : 0.0;
      const int n = 21;
      plan.t.resize(n), plan.L.resize(n), plan.Ldot.resize(n);
      for (int k = 0; k < n; ++k) {
        const double s = params_.landing_fallback_s * k / (n - 1);
        const Eigen::Vector3d b =
            Blend(s, params_.landing_fallback_s, post.L, post.Ldot, context.discrete_state()[kHoldL]);
        plan.t[k] = s, plan.L[k] = b[0], plan.Ldot[k] = b[1];
      }
    }
    try {
      WritePlan(landing_plan_offset_, plan, next);
    } catch (const std::exception& e) { return EventStatus::Failed(e.what()); }
  }
  return EventStatus::Succeeded();
}

}  // namespace rome
