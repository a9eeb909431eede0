#include "systems/plants/hybrid_contact_plant.h"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome {

namespace {
std::string Num(double x) {
  std::ostringstream os;
  os << std::setprecision(12) << x;
  return os.str();
}
}  // namespace

// ---------------------------------------------------------------------------------------------------------
// Plant

struct HybridContactPlant::Scratch {
  explicit Scratch(const MultibodyModel& model)
      : ws(model),
        u(Eigen::VectorXd::Zero(model.nu())),
        qdd(Eigen::VectorXd::Zero(model.nv())),
        F(Eigen::VectorXd::Zero(std::max(model.max_constraint_rows(), 1))),
        impulse(Eigen::VectorXd::Zero(std::max(model.max_constraint_rows(), 1))),
        v_plus(Eigen::VectorXd::Zero(model.nv())),
        forces(Eigen::Matrix3Xd::Zero(3, model.num_contacts())),
        torques(Eigen::Matrix3Xd::Zero(3, model.num_contacts())),
        x_key(Eigen::VectorXd::Zero(model.nq() + model.nv())),
        u_key(Eigen::VectorXd::Zero(model.nu())),
        tau_key(Eigen::VectorXd::Zero(model.nv())),
        event_forces(Eigen::Matrix3Xd::Zero(3, model.num_contacts())) {}
  MultibodyWorkspace ws;
  Eigen::VectorXd u, qdd, F, impulse, v_plus;
  Eigen::Matrix3Xd forces;   ///< ground force on each contact [N], world axes (zero when inactive)
  Eigen::Matrix3Xd torques;  ///< its torque about the contact frame origin [N m], world axes
  ContactSet active = 0;
  std::uint64_t version = 0;
  // The inputs of the last computation: a root-function evaluation at the state and input of the step's last stage
  // (or of the next step's first stage) reuses it although the context's version changed.
  Eigen::VectorXd x_key, u_key, tau_key;  // tau_key: tau_external (zero without that input)
  int mode_key = -1;
  std::uint64_t dynamics_id = 0;  // bumps when qdd and F are recomputed
  std::uint64_t forces_version = 0;
  // Set by the event publish (see the header), valid while the mode is pending_mode: contacts beyond a bound right
  // after the event at pending_time (they lift off / slip at pending_time + immediate_event_delay_s), contacts within
  // event_tolerance_N beyond it (their witness is offset by event_tolerance_N), and the forces at the event.
  double pending_time = 0;
  int pending_mode = -1;
  ContactSet pending_liftoff = 0, pending_slip = 0, grace_liftoff = 0, grace_slip = 0;
  Eigen::Matrix3Xd event_forces;
};

void HybridContactPlant::EnterMode(double t, int from, int to, State* next) const {
  next->discrete[0] = t;
  for (int c = 0; c < model_->num_contacts(); ++c)
    if ((mode_contacts_[from] & ContactBit(c)) && !(mode_contacts_[to] & ContactBit(c))) next->discrete[1 + c] = t;
  next->mode = to;
}

HybridContactPlant::HybridContactPlant(std::string name, std::shared_ptr<const MultibodyModel> model,
                                       ContactModeGraph graph, Terrain terrain, HybridContactPlantParams params)
    : ContactPlant(std::move(name), std::move(model), std::move(graph), std::move(terrain)), params_(params) {
  const int nq = model_->nq(), nv = model_->nv(), nu = model_->nu(), nc = model_->num_contacts();
  if (!(params_.planned_liftoff_force_N >= 0.0) || !std::isfinite(params_.planned_liftoff_force_N))
    ThrowError("params.planned_liftoff_force_N = " + std::to_string(params_.planned_liftoff_force_N) +
               " N must be >= 0 and finite");

  if (!(params_.quaternion_norm_gain_per_s >= 0.0) || !std::isfinite(params_.quaternion_norm_gain_per_s))
    ThrowError("params.quaternion_norm_gain_per_s = " + std::to_string(params_.quaternion_norm_gain_per_s) +
               " 1/s must be >= 0 and finite");
  if (!(params_.max_quaternion_norm_error > 0.0) || !std::isfinite(params_.max_quaternion_norm_error))
    ThrowError("params.max_quaternion_norm_error = " + std::to_string(params_.max_quaternion_norm_error) +
               " must be > 0 and finite");
  Eigen::VectorXd x0(nq + nv);
  x0 << model_->q_nominal(), Eigen::VectorXd::Zero(nv);
  DeclareContinuousState(x0);
  // [time the current mode began; per contact: time it last left the ground] (see the header). Zeros: every
  // touchdown guard arms min_time_in_mode_s after t = 0.
  DeclareDiscreteState(Eigen::VectorXd::Zero(1 + nc));
  DeclareInputPort("u", nu);
  if (params_.external_force_input) DeclareInputPort("tau_external", model_->joint_names());

  FindFourCornerSoles();
  DeclarePlantOutputs();
  DeclareLiftoffAndSlipGuards();
  DeclarePostEventCheck();
  DeclareTouchdownAndFallGuards();
  if (params_.joint_stops) DeclareJointStops();
}

void HybridContactPlant::DeclarePlantOutputs() {
  const int nq = model_->nq(), nv = model_->nv(), nc = model_->num_contacts();
  DeclareOutputPort(
      "q", nq, [nq](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state().head(nq); },
      Feedthrough::None());
  DeclareOutputPort(
      "v", nv, [nv](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state().tail(nv); },
      Feedthrough::None());
  const std::vector<std::string> state_names = StateElementNames(*model_);
  std::vector<std::string> force_names;
  for (const ContactInfo& contact : model_->contacts())
    for (const char* axis : {"fx", "fy", "fz"}) force_names.push_back(contact.name + "_" + axis);
  DeclareOutputPort(
      "state", state_names, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state(); },
      Feedthrough::None());
  DeclareTypedOutputPort<int>(
      "mode", [](const LeafContext& c, int* y) { *y = c.mode(); }, Feedthrough::None());
  DeclareOutputPort("contact_forces", force_names, [this, nc](const LeafContext& c, Eigen::VectorXd* y) {
    const Eigen::Matrix3Xd& f = EvalContactForces(c);
    for (int i = 0; i < nc; ++i) y->segment<3>(3 * i) = f.col(i);
  });
  DeclareOutputPort("contact_violation", nc, [this, nc, nq](const LeafContext& c, Eigen::VectorXd* y) {
    const Scratch& s = EvalDynamics(c);
    y->setZero();
    auto& ws = const_cast<Scratch&>(s).ws;
    const auto q = c.continuous_state().head(nq);
    for (int i = 0; i < nc; ++i)
      if (s.active & ContactBit(i)) {
        const ContactWrench w = ExtractContactWrench(*model_, ws, q, s.active, s.F, i);
        const ContactForceCheck check = CheckContactForce(*model_, ws, q, i, w);
        (*y)[i] = (check.unilateral_ok ? 0 : 1) + (check.friction_ok ? 0 : 2);
      }
  });
  DeclareOutputPort(
      "com", {"x", "y", "z", "vx", "vy", "vz"},
      [this, nq, nv](const LeafContext& c, Eigen::VectorXd* y) {
        auto& ws = c.scratch<Scratch>().ws;
        const auto q = c.continuous_state().head(nq);
        const auto v = c.continuous_state().tail(nv);
        y->head<3>() = CalcComPosition(*model_, ws, q);
        y->tail<3>() = CalcComVelocity(*model_, ws, q, v);
      },
      Feedthrough::None());
}

void HybridContactPlant::DeclareLiftoffAndSlipGuards() {
  const int nc = model_->num_contacts();
  const int num_modes = static_cast<int>(graph_.modes.size());
  // Unilateral contact: in every mode, every active contact lifts off when its normal force crosses 0 falling.
  // Target: the graph's lift-off transition, else the mode with exactly the remaining contacts, else failure.
  // Declared before the slip guards of the same mode: when a contact unloads with no tangential force
  // (|F_t| = F_n = 0 at the same instant) the lift-off wins and the mode's slip guard is then inactive.
  liftoff_threshold_.assign(num_modes, std::vector<double>(nc, 0.0));
  for (int m = 0; m < num_modes; ++m) {
    for (int c = 0; c < nc; ++c) {
      if (!(mode_contacts_[m] & ContactBit(c))) continue;
      if (!params_.unilateral_contact && !IsGraphLiftoff(m, c)) continue;  // welded: only the graph's lift-offs
      const int to = LiftoffMode(m, c);
      const std::string contact_name = model_->contacts()[c].name;
      // A planned lift-off (the graph's own transition) may fire at a small positive load (params: walking spec §7.5).
      const double threshold = IsGraphLiftoff(m, c) ? params_.planned_liftoff_force_N : 0.0;
      liftoff_threshold_[m][c] = threshold;
      DeclareGuard(
          "liftoff_" + contact_name, m,
          [this, c, threshold](const LeafContext& ctx) {
            const Scratch& s = ctx.scratch<Scratch>();
            const bool valid = s.pending_mode == ctx.mode();
            if (valid && (s.pending_liftoff & ContactBit(c))) return PendingWitness(ctx);
            const double fn = EvalContactForces(ctx)(2, c) - threshold;
            return valid && (s.grace_liftoff & ContactBit(c)) ? fn + params_.event_tolerance_N : fn;
          },
          CrossingDirection::kFalling,
          [this, m, c, to, contact_name](const LeafContext& ctx, int, State* next) {
            if (to < 0) {
              const Scratch& s = ctx.scratch<Scratch>();
              const bool pending = s.pending_mode == ctx.mode() && (s.pending_liftoff & ContactBit(c));
              std::ostringstream os;
              os << "'" << contact_name << "' lifted off at t = " << (pending ? s.pending_time : ctx.time())
                 << " s (normal force ";
              if (pending)
                os << s.event_forces(2, c) << " N right after an event";
              else
                os << "0 N";
              os << " in mode '" << graph_.modes[m].name
                 << "'), but the contact-mode graph has no mode to lift off into";
              return EventStatus::Failed(os.str());
            }
            EnterMode(ctx.time(), m, to, next);
            return EventStatus::Succeeded();
          });
    }
    if (mode_contacts_[m] == 0 || !params_.unilateral_contact) continue;
    // Friction: one component per contact, SlipMargin (inactive contacts: +1, never crossing).
    DeclareGuard(
        "slip", m, nc,
        [this, nc](const LeafContext& ctx, Eigen::Ref<Eigen::VectorXd> w) {
          const ContactSet active = mode_contacts_[ctx.mode()];
          const Scratch& s = ctx.scratch<Scratch>();
          const bool valid = s.pending_mode == ctx.mode();
          const ContactSet pending = valid ? s.pending_slip : 0, grace = valid ? s.grace_slip : 0;
          // A contact whose lift-off is pending (its normal force jumped below the release threshold at the event) is
          // released an instant later: its unloaded cone is not judged meanwhile.
          const ContactSet releasing = valid ? s.pending_liftoff : 0;
          for (int c = 0; c < nc; ++c)
            w[c] = !(active & ContactBit(c)) || (releasing & ContactBit(c)) ? 1.0
                   : (pending & ContactBit(c))                              ? PendingWitness(ctx)
                   : (grace & ContactBit(c)) ? SlipMargin(ctx, c) + params_.event_tolerance_N
                                             : SlipMargin(ctx, c);
        },
        CrossingDirection::kFalling,
        [this](const LeafContext& ctx, int c, State*) {
          const Scratch& s = ctx.scratch<Scratch>();
          const bool pending = s.pending_mode == ctx.mode() && (s.pending_slip & ContactBit(c));
          const Eigen::Matrix3Xd& f = pending ? s.event_forces : EvalContactForces(ctx);
          const double ft = f.col(c).head<2>().norm(), fn = f(2, c);
          std::ostringstream os;
          if (sole_[c].x() >= 0.0 && fn > 0.0 &&
              TorsionMargin(ctx, c) / (sole_[c].x() + sole_[c].y()) < FrictionMargin(EvalContactForces(ctx), c))
            return EventStatus::Failed(TorsionMessage(ctx, c, pending ? s.pending_time : ctx.time()));
          os << "'" << model_->contacts()[c].name << "' slipped at t = " << (pending ? s.pending_time : ctx.time())
             << " s: ";
          // F_n < 0 (within event_tolerance_N, else the contact lifts off): the contact pulls on the ground, and the
          // ratio |F_t|/F_n would read as a negative friction coefficient.
          const char* after_event = pending ? "; already outside the cone right after an event" : "";
          if (fn < 0)
            os << "pulling contact (F_n = " << fn << " N < 0) with a tangential force |F_t| = " << ft
               << " N left (mu = " << model_->contacts()[c].friction_coefficient << after_event << ")";
          else
            os << "|F_t|/F_n = " << ft / fn << (pending ? " exceeded" : " reached")
               << " the friction coefficient mu = " << model_->contacts()[c].friction_coefficient << " (|F_t| = " << ft
               << " N, F_n = " << fn << " N" << after_event << ")";
          // A contact that unloads with a tangential force left (even round-off) meets the cone's apex just before its
          // normal force reaches 0: say so, since the ratio of two near-zero forces alone reads like a violent slip.
          if (std::abs(fn) <= params_.event_tolerance_N)
            os << "; the contact was unloading (F_n within event_tolerance_N = " << params_.event_tolerance_N
               << " N of 0): it lost its load with a tangential force left";
          return EventStatus::Failed(os.str());
        });
  }
}

void HybridContactPlant::DeclarePostEventCheck() {
  const int nc = model_->num_contacts();
  // Violations that no guard can see: right after an event (initialisation, a reset, another system's discrete
  // update such as a zero-order-held input) the witnesses restart from the new values, so a normal force or a
  // friction margin that jumped below 0 would never cross. Such contacts lift off / slip just after the event.
  if (params_.unilateral_contact)
    DeclareEventPublish([this, nc](const LeafContext& ctx) {
      Scratch& s = ctx.scratch<Scratch>();
      const Eigen::Matrix3Xd& f = EvalContactForces(ctx);
      s.pending_time = ctx.time();
      s.pending_mode = ctx.mode();
      s.event_forces = f;
      s.pending_liftoff = s.pending_slip = s.grace_liftoff = s.grace_slip = 0;
      const double tol = params_.event_tolerance_N;
      for (int c = 0; c < nc; ++c) {
        if (!(s.active & ContactBit(c))) continue;
        const double fn = f(2, c) - liftoff_threshold_[ctx.mode()][c], margin = SlipMargin(ctx, c);
        if (fn < -tol)
          s.pending_liftoff |= ContactBit(c);
        else if (margin < -tol)
          s.pending_slip |= ContactBit(c);
        if (fn < 0 && fn >= -tol) s.grace_liftoff |= ContactBit(c);
        if (margin < 0 && margin >= -tol) s.grace_slip |= ContactBit(c);
      }
      return EventStatus::Succeeded();
    });
}

void HybridContactPlant::DeclareTouchdownAndFallGuards() {
  const int nq = model_->nq(), nv = model_->nv();
  // Touchdowns from the graph.
  for (const ResolvedTransition& td : transitions_) {
    if (td.kind != ContactModeGraph::Kind::kTouchdown) continue;
    const int from = td.from, to = td.to, contact = td.contact;
    const std::string contact_name = model_->contacts()[contact].name;
    DeclareGuard(
        "touchdown_" + contact_name, from,
        [this, contact](const LeafContext& c) { return TouchdownWitness(c, contact); }, CrossingDirection::kFalling,
        [this, contact, contact_name, from, to, nq, nv](const LeafContext& c, int, State* next) {
          auto& s = c.scratch<Scratch>();
          const auto q = c.continuous_state().head(nq);
          if (!terrain_.is_flat()) {
            const Eigen::Vector3d p = CalcContactPointPosition(*model_, s.ws, q, contact, 0);
            if (terrain_.StoneAt(p.x(), params_.stone_tolerance_m) < 0) {
              std::ostringstream os;
              const int near = terrain_.NearestStone(p.x());
              os << "robot fell: '" << contact_name << "' touched down at x = " << p.x()
                 << " m, not on any stone (nearest stone " << near << " spans "
                 << terrain_.stones()[near].x_center_m - terrain_.stones()[near].length_m / 2 << " .. "
                 << terrain_.stones()[near].x_center_m + terrain_.stones()[near].length_m / 2 << " m)";
              return EventStatus::Failed(os.str());
            }
          }
          CalcImpactMap(*model_, s.ws, q, c.continuous_state().tail(nv), mode_contacts_[to], params_.dynamics, s.v_plus,
                        s.impulse);
          next->continuous.tail(nv) = s.v_plus;
          NormalizeBaseQuaternion(next->continuous);
          EnterMode(c.time(), from, to, next);
          return EventStatus::Succeeded();
        });
  }
  if (base_height_index() >= 0) {
    DeclareGuard(
        "fall", kAllModes,
        [this](const LeafContext& c) { return c.continuous_state()[base_height_index()] - params_.min_base_height_m; },
        CrossingDirection::kFalling,
        [this](const LeafContext& c, int, State*) {
          std::ostringstream os;
          os << "robot fell: base height " << c.continuous_state()[base_height_index()]
             << " m is below min_base_height_m = " << params_.min_base_height_m << " m";
          return EventStatus::Failed(os.str());
        });
  }
}

void HybridContactPlant::DeclareJointStops() {
  if (!(params_.joint_stop_tolerance >= 0.0) || !std::isfinite(params_.joint_stop_tolerance))
    ThrowError("params.joint_stop_tolerance = " + std::to_string(params_.joint_stop_tolerance) +
               " must be >= 0 and finite");
  // Components 2k and 2k + 1: the lower and upper stop of the k-th limited coordinate (finite URDF limits only; an
  // index into q: a joint's velocity index plus one after a quaternion base, whose own seven entries have no limits).
  std::vector<int> limited;
  const Eigen::VectorXd &lo = model_->position_lower_limits(), &hi = model_->position_upper_limits();
  for (int i = 0; i < model_->nq(); ++i)
    if (std::isfinite(lo[i]) || std::isfinite(hi[i])) limited.push_back(i);
  if (limited.empty()) return;
  const auto margin = [lo, hi](double q, int i, bool lower) {
    if (lower) return std::isfinite(lo[i]) ? q - lo[i] : 1.0;
    return std::isfinite(hi[i]) ? hi[i] - q : 1.0;
  };
  const auto message = [this, lo, hi](int i, bool lower, double q, double t, bool beyond) {
    std::ostringstream os;
    os << "joint '" << model_->JointName(model_->has_quaternion_base() ? i - 1 : i) << "' "
       << (beyond ? "is beyond" : "reached") << " its " << (lower ? "lower" : "upper") << " limit "
       << (lower ? lo[i] : hi[i]) << " at t = " << t << " s (q = " << q << "; joint stop";
    if (beyond) os << ", right after an event: a start pose or reset outside the limits";
    os << ")";
    return os.str();
  };
  const int n = static_cast<int>(limited.size());
  DeclareGuard(
      "joint_stop", kAllModes, 2 * n,
      [limited, margin, n](const LeafContext& ctx, Eigen::Ref<Eigen::VectorXd> w) {
        const auto q = ctx.continuous_state();
        for (int k = 0; k < n; ++k) {
          w[2 * k] = margin(q[limited[k]], limited[k], true);
          w[2 * k + 1] = margin(q[limited[k]], limited[k], false);
        }
      },
      CrossingDirection::kFalling,
      [limited, message](const LeafContext& ctx, int component, State*) {
        const int i = limited[component / 2];
        return EventStatus::Failed(message(i, component % 2 == 0, ctx.continuous_state()[i], ctx.time(), false));
      });
  // A joint already beyond a stop right after an event has a witness that cannot cross: end the run there.
  DeclareEventPublish([this, limited, margin, message](const LeafContext& ctx) {
    const auto q = ctx.continuous_state();
    for (const int i : limited)
      for (const bool lower : {true, false})
        if (margin(q[i], i, lower) < -params_.joint_stop_tolerance)
          return EventStatus::Failed(message(i, lower, q[i], ctx.time(), true));
    return EventStatus::Succeeded();
  });
}

std::any HybridContactPlant::AllocateScratch() const { return Scratch(*model_); }

void HybridContactPlant::SetState(LeafContext& context, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                  const std::string& mode) const {
  const int nq = model_->nq(), nv = model_->nv();
  if (q.size() != nq || v.size() != nv)
    ThrowError("SetState: q has size " + std::to_string(q.size()) + " and v size " + std::to_string(v.size()) +
               "; robot '" + model_->name() + "' has nq = " + std::to_string(nq) + ", nv = " + std::to_string(nv));
  if (model_->has_quaternion_base()) {
    const double norm = q.segment<4>(3).norm();
    if (!(std::abs(norm - 1.0) <= params_.max_quaternion_norm_error))
      ThrowError("SetState: q's base quaternion (w x y z) = " + Num(q[3]) + " " + Num(q[4]) + " " + Num(q[5]) + " " +
                 Num(q[6]) + " has norm " + Num(norm) +
                 "; expected 1 within max_quaternion_norm_error = " + Num(params_.max_quaternion_norm_error));
  }
  State& s = context.get_mutable_state();
  s.continuous << q, v;
  NormalizeBaseQuaternion(s.continuous);
  s.mode = graph_.ModeIndex(mode, name());
  s.discrete.setConstant(context.time());  // the mode clock starts now; inactive contacts count as just lifted off
}

const HybridContactPlant::Scratch& HybridContactPlant::EvalDynamics(const LeafContext& context) const {
  Scratch& s = context.scratch<Scratch>();
  if (s.version == context.version()) return s;
  const int nq = model_->nq(), nv = model_->nv();
  const auto q = context.continuous_state().head(nq);
  const auto v = context.continuous_state().tail(nv);
  const Eigen::VectorXd& u = EvalInput(context, 0);
  const bool external = params_.external_force_input;
  if (s.mode_key == context.mode() && s.x_key == context.continuous_state() && s.u_key == u &&
      (!external || s.tau_key == EvalInput(context, 1))) {
    s.version = context.version();
    return s;
  }
  s.mode_key = context.mode();
  s.x_key = context.continuous_state();
  s.u_key = u;
  if (external) s.tau_key = EvalInput(context, 1);
  ++s.dynamics_id;
  if (params_.saturate_torques)
    s.u = u.cwiseMax(-model_->torque_limits()).cwiseMin(model_->torque_limits());
  else
    s.u = u;
  s.active = mode_contacts_[context.mode()];
  if (external)
    CalcConstrainedForwardDynamics(*model_, s.ws, q, v, s.u, s.tau_key, s.active, params_.dynamics, s.qdd, s.F);
  else
    CalcConstrainedForwardDynamics(*model_, s.ws, q, v, s.u, s.active, params_.dynamics, s.qdd, s.F);
  s.version = context.version();
  return s;
}

const Eigen::Matrix3Xd& HybridContactPlant::EvalContactForces(const LeafContext& context) const {
  Scratch& s = const_cast<Scratch&>(EvalDynamics(context));
  if (s.forces_version == s.dynamics_id) return s.forces;
  const auto q = context.continuous_state().head(model_->nq());
  for (int i = 0; i < model_->num_contacts(); ++i) {
    s.forces.col(i).setZero(), s.torques.col(i).setZero();
    if (!(s.active & ContactBit(i))) continue;
    const ContactWrench w = ExtractContactWrench(*model_, s.ws, q, s.active, s.F, i);
    s.forces.col(i) = w.force, s.torques.col(i) = w.torque;
  }
  s.forces_version = s.dynamics_id;
  return s.forces;
}

void HybridContactPlant::NormalizeBaseQuaternion(Eigen::VectorXd& x) const {
  if (model_->has_quaternion_base()) x.segment<4>(3).normalize();
}

double HybridContactPlant::FrictionMargin(const Eigen::Matrix3Xd& forces, int contact) const {
  return model_->contacts()[contact].friction_coefficient * forces(2, contact) - forces.col(contact).head<2>().norm();
}

void HybridContactPlant::FindFourCornerSoles() {
  const int nc = model_->num_contacts();
  sole_.assign(nc, Eigen::Vector3d(-1.0, -1.0, 0.0));
  sole_centre_.assign(nc, Eigen::Vector3d::Zero());
  if (!params_.sole_torsion || model_->is_planar()) return;
  for (int c = 0; c < nc; ++c) {
    const ContactInfo& info = model_->contacts()[c];
    if (info.type != ContactType::kFlat || info.points.size() != 4) continue;
    Eigen::Vector3d lo = info.points[0], hi = info.points[0];
    for (const Eigen::Vector3d& p : info.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    // The four points must be the corners of their bounding rectangle (in the body's x-y plane, at one height).
    bool rectangle = hi.z() - lo.z() < 1e-9;
    for (const Eigen::Vector3d& p : info.points)
      rectangle = rectangle && std::min(p.x() - lo.x(), hi.x() - p.x()) < 1e-9 &&
                  std::min(p.y() - lo.y(), hi.y() - p.y()) < 1e-9;
    if (!rectangle)
      ThrowError("params.sole_torsion: flat contact '" + info.name +
                 "' is not four corners of a rectangle in its body's x-y plane (set sole_torsion = false)");
    sole_[c] = Eigen::Vector3d(0.5 * (hi.x() - lo.x()), 0.5 * (hi.y() - lo.y()), 0.0);
    sole_centre_[c] = 0.5 * (lo + hi);
  }
}

double HybridContactPlant::TorsionMargin(const LeafContext& context, int contact) const {
  const Eigen::Matrix3Xd& f = EvalContactForces(context);
  const Scratch& s = context.scratch<Scratch>();
  auto& ws = const_cast<Scratch&>(s).ws;
  const auto q = context.continuous_state().head(model_->nq());
  const ContactInfo& info = model_->contacts()[contact];
  const Eigen::Matrix3d R = CalcLinkPose(*model_, ws, q, info.body).linear();
  // Torque about the sole's centre, then foot axes.
  const Eigen::Vector3d arm = R * (sole_centre_[contact] - info.frame_origin);
  const Eigen::Vector3d force = R.transpose() * f.col(contact);
  const Eigen::Vector3d tau = R.transpose() * (s.torques.col(contact) - arm.cross(f.col(contact)));
  const double mu = model_->contacts()[contact].friction_coefficient / std::sqrt(2.0);
  const double X = sole_[contact].x(), Y = sole_[contact].y(), hold = mu * (X + Y) * force.z();
  const double upper = hold - tau.z() - std::abs(Y * force.x() + mu * tau.x()) - std::abs(X * force.y() + mu * tau.y());
  const double lower = hold + tau.z() - std::abs(Y * force.x() - mu * tau.x()) - std::abs(X * force.y() - mu * tau.y());
  return std::min(upper, lower);
}

double HybridContactPlant::SlipMargin(const LeafContext& context, int contact) const {
  const double linear = FrictionMargin(EvalContactForces(context), contact);
  if (sole_[contact].x() < 0.0) return linear;
  return std::min(linear, TorsionMargin(context, contact) / (sole_[contact].x() + sole_[contact].y()));
}

std::string HybridContactPlant::TorsionMessage(const LeafContext& context, int contact, double t) const {
  const Eigen::Matrix3Xd& f = EvalContactForces(context);
  const double X = sole_[contact].x(), Y = sole_[contact].y();
  const double mu = model_->contacts()[contact].friction_coefficient;
  const double margin = TorsionMargin(context, contact);
  std::ostringstream os;
  os << "'" << model_->contacts()[contact].name << "' slipped torsionally at t = " << t
     << " s: its wrench left the four-corner sole's wrench cone (sole " << 2 * X << " x " << 2 * Y
     << " m, corner pyramids mu/sqrt(2), mu = " << mu << "; F_n = " << f(2, contact)
     << " N, |F_t| = " << f.col(contact).head<2>().norm() << " N, torsion margin " << margin
     << " N m: the yaw moment exceeds what four corners hold at this CoP and tangential force)";
  return os.str();
}

double HybridContactPlant::PendingWitness(const LeafContext& context) const {
  const Scratch& s = context.scratch<Scratch>();
  return s.pending_time + params_.immediate_event_delay_s - context.time();
}

void HybridContactPlant::DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const {
  const int nq = model_->nq(), nv = model_->nv();
  const Scratch& s = EvalDynamics(context);
  // dq/dt = G(q) v: v itself, except the quaternion base, whose quaternion rate is linear in the stored quaternion
  // (its exact flow keeps the norm; the integrator's drift is renormalised at every reset, see the header).
  const auto x = context.continuous_state();
  model_->MapVelocityToQDot(x.head(nq), x.tail(nv), xdot->head(nq));
  if (model_->has_quaternion_base()) {
    // Norm stabilisation (zero on the unit sphere, so the exact flow is unchanged): |quat|^2 - 1 decays at
    // 2 quaternion_norm_gain_per_s instead of integrating the integrator's error.
    const auto quat = x.segment<4>(3);
    xdot->segment<4>(3) -= params_.quaternion_norm_gain_per_s * (quat.squaredNorm() - 1.0) * quat;
  }
  xdot->tail(nv) = s.qdd;
}

double HybridContactPlant::TouchdownWitness(const LeafContext& context, int contact) const {
  // Only a contact that left the ground less than min_time_in_mode_s ago is held unarmed (it starts at height ~0).
  if (context.time() - context.discrete_state()[1 + contact] < params_.min_time_in_mode_s) return 1.0;
  auto& ws = context.scratch<Scratch>().ws;
  const auto q = context.continuous_state().head(model_->nq());
  double lowest = std::numeric_limits<double>::infinity();
  const int np = static_cast<int>(model_->contacts()[contact].points.size());
  for (int p = 0; p < np; ++p) {
    const Eigen::Vector3d pos = CalcContactPointPosition(*model_, ws, q, contact, p);
    lowest = std::min(lowest, pos.z() - terrain_.SurfaceHeight(pos.x()));
  }
  return lowest;
}

}  // namespace rome
