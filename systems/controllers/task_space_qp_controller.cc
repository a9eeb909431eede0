#include "systems/controllers/task_space_qp_controller.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "systems/controllers/controller_setup.h"
#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_workspace.h"
#include "systems/plants/hybrid_contact_plant.h"

namespace rome {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// Where one active contact's force rows sit in x = [q̈; u; F] and which inequality rows it owns.
struct ContactBlock {
  int contact = -1;
  int x_offset = 0;     // first F entry of this contact in x
  int num_rows = 0;     // F rows of this contact
  int normal = 0;       // x index of F_z
  int ineq_offset = 0;  // first inequality row
  int num_ineq = 0;
  bool cop = false;  // planar line/flat foot: CoP rows
  double mu = 1.0;
};

int InequalityRows(const MultibodyModel& model, const ContactInfo& c, const std::string& system) {
  if (model.is_planar()) return c.type == ContactType::kPoint ? 2 : 4;
  if (c.type == ContactType::kPoint) return 4;
  throw std::invalid_argument("system '" + system + "': contact '" + c.name + "' of robot '" + model.name() +
                              "' is a " + ToString(c.type) +
                              " contact on a 3D model; the task-space QP supports point contacts in 3D and every "
                              "contact type in planar models");
}
}  // namespace

struct TaskSpaceQpController::Scratch {
  struct ModeQp {
    ModeQp(int n, int n_eq, int n_ineq, const QpSettings& settings) : qp(n, n_eq, n_ineq, settings) {}
    ContactSet active = 0;
    int rows = 0;  // constraint force rows (contacts + loop closures)
    std::vector<ContactBlock> contacts;
    std::vector<int> zero_u;
    DenseQpSolver qp;
    // params.predict_hold_drift: the last used answer's F and time, and the predicted drift d (rows).
    Eigen::VectorXd F_prev, drift;
    double t_prev = 0.0;
    bool prev_valid = false;
  };
  explicit Scratch(const MultibodyModel& model) : ws(model) {}
  MultibodyWorkspace ws;
  std::vector<ModeQp> modes;
  Eigen::VectorXd y, ydot, Jdot_qdot, ydd_star, w_rows, residual;
  Eigen::MatrixXd Jy, WJy;
  Eigen::VectorXd saved_l, saved_u;  // GRF row bounds while the relaxed QP runs
  Eigen::VectorXd qdd_hold, F_hold;  // forward dynamics at the held u (params.predict_hold_drift)
  int last_mode = 0;
};

TaskSpaceQpController::TaskSpaceQpController(std::string name, std::shared_ptr<const MultibodyModel> model,
                                             std::vector<ContactSet> mode_contacts,
                                             std::vector<std::shared_ptr<const TaskSpaceTask>> tasks,
                                             TaskSpaceQpParams params)
    : QpControllerSystem(std::move(name)),
      model_(std::move(model)),
      mode_contacts_(std::move(mode_contacts)),
      tasks_(std::move(tasks)),
      params_(std::move(params)) {
  if (!model_) ThrowError("null MultibodyModel");
  const int nv = model_->nv(), nu = model_->nu(), nc = model_->num_contacts();
  if (mode_contacts_.empty()) ThrowError("no contact modes given (mode_contacts is empty)");
  if (!(params_.update_period_s > 0.0) || !std::isfinite(params_.update_period_s))
    ThrowError("params.update_period_s = " + std::to_string(params_.update_period_s) + " must be positive");
  auto check_nonneg = [&](double value, const char* what) {
    if (!(value >= 0.0) || !std::isfinite(value))
      ThrowError(std::string("params.") + what + " = " + std::to_string(value) + " must be finite and >= 0");
  };
  check_nonneg(params_.qdd_regularization, "qdd_regularization");
  check_nonneg(params_.u_regularization, "u_regularization");
  check_nonneg(params_.force_regularization, "force_regularization");
  check_nonneg(params_.min_normal_force_N, "min_normal_force_N");
  check_nonneg(params_.friction_cone_offset_N, "friction_cone_offset_N");
  if (!(params_.friction_margin > 0.0 && params_.friction_margin <= 1.0))
    ThrowError("params.friction_margin = " + std::to_string(params_.friction_margin) + " must be in (0, 1]");
  check_nonneg(params_.contact_stabilization.baumgarte_alpha_per_s, "contact_stabilization.baumgarte_alpha_per_s");
  check_nonneg(params_.contact_stabilization.baumgarte_beta_per_s, "contact_stabilization.baumgarte_beta_per_s");
  if (params_.qdd_regularization + params_.u_regularization + params_.force_regularization == 0.0 && tasks_.empty())
    ThrowError("no tasks and no regularisation: the QP cost is zero");

  for (size_t i = 0; i < tasks_.size(); ++i) {
    if (!tasks_[i]) ThrowError("task " + std::to_string(i) + " is null");
    task_offsets_.push_back(ny_);
    ny_ += tasks_[i]->size();
    for (int m : tasks_[i]->active_modes())
      if (m >= static_cast<int>(mode_contacts_.size()))
        ThrowError("task '" + tasks_[i]->name() + "' is active in mode " + std::to_string(m) + ", but only " +
                   std::to_string(mode_contacts_.size()) + " modes were given");
  }

  u_max_ = ResolveTorqueLimits(*model_, params_.torque_limits, this->name());
  zero_torque_ = ZeroTorqueActuatorsPerMode(*model_, mode_contacts_, params_.zero_torque_in_contact, this->name());
  // Validate the contact sets and contact types now (errors at construction, not mid-run).
  for (size_t m = 0; m < mode_contacts_.size(); ++m) {
    try {
      CountConstraintRows(*model_, mode_contacts_[m]);
    } catch (const std::exception& e) { ThrowError("contact set of mode " + std::to_string(m) + ": " + e.what()); }
    for (int c = 0; c < nc; ++c)
      if (mode_contacts_[m] & ContactBit(c)) InequalityRows(*model_, model_->contacts()[c], this->name());
  }

  state_port_ = DeclareInputPort("state", model_->nq() + nv);
  mode_port_ = DeclareTypedInputPort<int>("mode");
  desired_port_ = DeclareInputPort("desired", 3 * ny_);

  Eigen::VectorXd xd0 = Eigen::VectorXd::Zero(slot(kNumSlots));
  xd0[slot(kStatus)] = -1;  // no QP solved yet
  DeclareDiscreteState(xd0);
  DeclareOutputPort(
      "u", nu,
      [this, nu](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state().segment(u_offset(), nu); },
      Feedthrough::None());
  DeclareOutputPort(
      "qdd", nv,
      [this, nv](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state().segment(qdd_offset(), nv); },
      Feedthrough::None());
  DeclareOutputPort(
      "contact_forces", 3 * nc,
      [this, nc](const LeafContext& c, Eigen::VectorXd* y) {
        *y = c.discrete_state().segment(forces_offset(), 3 * nc);
      },
      Feedthrough::None());
  DeclareTypedOutputPort<TaskSpaceQpDiagnostics>(
      "diagnostics", [this](const LeafContext& c, TaskSpaceQpDiagnostics* d) { *d = diagnostics(c); },
      Feedthrough::None());
  DeclareQpPortsAndUpdates(slot(kFailures), slot(kStatus), slot(kSolveTime), params_.update_period_s,
                           params_.resolve_at_events, params_.resolve_at,
                           [this](const LeafContext& c, Eigen::VectorXd* next) { return Update(c, next); });
}

std::any TaskSpaceQpController::AllocateScratch() const {
  const MultibodyModel& model = *model_;
  const int nv = model.nv(), nu = model.nu();
  Scratch s(model);
  s.y.setZero(ny_);
  s.ydot.setZero(ny_);
  s.Jdot_qdot.setZero(ny_);
  s.ydd_star.setZero(ny_);
  s.residual.setZero(ny_);
  s.w_rows.setZero(ny_);
  s.Jy.setZero(ny_, nv);
  s.WJy.setZero(ny_, nv);
  int max_ineq = 0, max_rows = 0;
  s.modes.reserve(mode_contacts_.size());
  for (size_t m = 0; m < mode_contacts_.size(); ++m) {
    const ContactSet active = mode_contacts_[m];
    const int rows = CountConstraintRows(model, active);
    max_rows = std::max(max_rows, rows);
    std::vector<ContactBlock> blocks;
    int f_row = 0, ineq = 0;
    for (int c = 0; c < model.num_contacts(); ++c) {
      if (!(active & ContactBit(c))) continue;
      const ContactInfo& info = model.contacts()[c];
      ContactBlock b;
      b.contact = c;
      b.x_offset = nv + nu + f_row;
      b.num_rows = info.num_rows;
      b.normal = model.is_planar() ? b.x_offset + info.num_rows - 1 : b.x_offset + 2;
      b.ineq_offset = ineq;
      b.num_ineq = InequalityRows(model, info, name());
      b.cop = model.is_planar() && info.type != ContactType::kPoint;
      b.mu = params_.friction_margin *
             (params_.friction_coefficient >= 0.0 ? params_.friction_coefficient : info.friction_coefficient);
      blocks.push_back(b);
      f_row += info.num_rows;
      ineq += b.num_ineq;
    }
    const int nx = nv + nu + rows;
    max_ineq = std::max(max_ineq, ineq);
    Scratch::ModeQp mq(nx, nv + rows, ineq, params_.qp);
    mq.active = active;
    mq.rows = rows;
    mq.contacts = blocks;
    mq.zero_u = zero_torque_[m];
    mq.F_prev.setZero(rows);
    mq.drift.setZero(rows);
    DenseQpSolver& qp = mq.qp;
    // Constant data: −B in the dynamics rows, friction rows, bounds.
    qp.A_eq.block(0, nv, nv, nu) = -model.B();
    for (int j = 0; j < nu; ++j) {
      qp.lb[nv + j] = -u_max_[j];
      qp.ub[nv + j] = u_max_[j];
    }
    for (int j : mq.zero_u) qp.lb[nv + j] = qp.ub[nv + j] = 0.0;
    for (const ContactBlock& b : blocks) {
      const int r = b.ineq_offset;
      if (model.is_planar()) {
        const int fx = b.normal - 1;
        // F_x − μ F_z ≤ −μ F_0 and F_x + μ F_z ≥ μ F_0 (F_0: the apex offset; bounds in SetContactRowBounds).
        qp.A(r, fx) = 1.0, qp.A(r, b.normal) = -b.mu;
        qp.A(r + 1, fx) = 1.0, qp.A(r + 1, b.normal) = b.mu;
        // x_min F_z ≤ −τ_y ≤ x_max F_z; the F_z coefficients depend on the foot pose (set in SolveQp).
        if (b.cop) qp.A(r + 2, b.x_offset) = -1.0, qp.A(r + 3, b.x_offset) = -1.0;
      } else {
        // ±F_x − μ F_z ≤ −μ F_0, ±F_y − μ F_z ≤ −μ F_0.
        for (int k = 0; k < 4; ++k) {
          qp.A(r + k, b.x_offset + k / 2) = (k % 2 == 0) ? 1.0 : -1.0;
          qp.A(r + k, b.normal) = -b.mu;
        }
      }
    }
    s.modes.push_back(std::move(mq));
    SetContactRowBounds(s, static_cast<int>(m));
  }
  s.qdd_hold.setZero(nv);
  s.F_hold.setZero(std::max(1, max_rows));
  s.saved_l.setZero(max_ineq);
  s.saved_u.setZero(max_ineq);
  return s;
}

int TaskSpaceQpController::ModeFromInput(const LeafContext& context) const {
  return CheckedModeIndex(EvalTypedInput<int>(context, mode_port_), static_cast<int>(mode_contacts_.size()), name());
}

QpStatus TaskSpaceQpController::SolveQp(const LeafContext& context) const {
  const MultibodyModel& model = *model_;
  const int nv = model.nv(), nu = model.nu();
  const int mode = ModeFromInput(context);
  Scratch& s = context.scratch<Scratch>();
  Scratch::ModeQp& mq = s.modes[mode];
  DenseQpSolver& qp = mq.qp;
  MultibodyWorkspace& ws = s.ws;

  const Eigen::VectorXd& x = EvalInput(context, state_port_);
  const Eigen::VectorXd& desired = EvalInput(context, desired_port_);
  const auto q = x.head(model.nq());
  const auto v = x.tail(nv);
  CalcHoldDrift(context, mode, q, v);  // before the rows below: it overwrites ws' Jacobians
  s.last_mode = mode;

  // Tasks: y, J_y, J̇_y q̇ and the PD output dynamics ÿ* (Eq. (29), (30)).
  for (size_t i = 0; i < tasks_.size(); ++i) {
    const TaskSpaceTask& task = *tasks_[i];
    const int off = task_offsets_[i], n = task.size();
    task.Calc(model, ws, q, v, s.y.segment(off, n), s.Jy.middleRows(off, n), s.Jdot_qdot.segment(off, n));
    const TaskGains& g = task.gains();
    s.w_rows.segment(off, n).setConstant(task.IsActiveIn(mode) ? g.weight : 0.0);
    s.ydot.segment(off, n).noalias() = s.Jy.middleRows(off, n) * v;
    s.ydd_star.segment(off, n) = desired.segment(2 * ny_ + off, n) +
                                 g.kp * (desired.segment(off, n) - s.y.segment(off, n)) +
                                 g.kd * (desired.segment(ny_ + off, n) - s.ydot.segment(off, n));
  }
  // Cost: 1/2 xᵀHx + gᵀx with H_q̈q̈ = J_yᵀ W J_y, g_q̈ = J_yᵀ W (J̇_y q̇ − ÿ*), plus the regularisation.
  qp.H.setZero();
  qp.g.setZero();
  if (ny_ > 0) {
    s.WJy.noalias() = s.w_rows.asDiagonal() * s.Jy;
    // lazyProduct: coefficient-based, so Eigen sets up no heap GEMM blocking space for these small sizes.
    qp.H.topLeftCorner(nv, nv).noalias() = s.Jy.transpose().lazyProduct(s.WJy);
    s.ydd_star = s.Jdot_qdot - s.ydd_star;  // reuse: J̇_y q̇ − ÿ*
    qp.g.head(nv).noalias() = s.WJy.transpose() * s.ydd_star;
  }
  // Regularisation relative to the largest task curvature, so that H stays well conditioned (DenseQpSolver
  // treats pivots below 1e-8 max H_jj as singular) whatever the task weights are.
  const double scale = ny_ > 0 && qp.H.diagonal().head(nv).maxCoeff() > 0.0 ? qp.H.diagonal().head(nv).maxCoeff() : 1.0;
  qp.H.diagonal().head(nv).array() += scale * params_.qdd_regularization;
  qp.H.diagonal().segment(nv, nu).array() += scale * params_.u_regularization;
  qp.H.diagonal().tail(mq.rows).array() += scale * params_.force_regularization;

  // Dynamics rows: M q̈ − B u − J_cᵀ F = τ_spring − h.
  qp.A_eq.topLeftCorner(nv, nv) = CalcMassMatrix(model, ws, q);
  qp.b_eq.head(nv) = CalcSpringTorques(model, ws, q, v) - CalcBiasForces(model, ws, q, v);
  // Contact rows: J_c q̈ = −J̇_c q̇ − 2α J_c q̇ − β² φ.
  const int rows = CalcConstraintJacobian(model, ws, q, v, mq.active);
  if (rows > 0) {
    const auto Jc = ws.J.topRows(rows);
    qp.A_eq.block(0, nv + nu, nv, rows) = -Jc.transpose();
    qp.A_eq.bottomLeftCorner(rows, nv) = Jc;
    qp.b_eq.tail(rows) =
        -ws.Jdot_qdot.head(rows) - ws.phi.head(rows) * (params_.contact_stabilization.baumgarte_beta_per_s *
                                                        params_.contact_stabilization.baumgarte_beta_per_s);
    qp.b_eq.tail(rows).noalias() -= (2.0 * params_.contact_stabilization.baumgarte_alpha_per_s) * (Jc * v);
  }
  // CoP rows of planar line/flat feet: x_min, x_max of the contact points relative to the frame origin.
  for (const ContactBlock& b : mq.contacts) {
    if (!b.cop) continue;
    const ContactInfo& info = model.contacts()[b.contact];
    const double origin_x = CalcPointPosition(model, ws, q, info.body, info.frame_origin).x();
    double x_min = kInf, x_max = -kInf;
    for (int p = 0; p < static_cast<int>(info.points.size()); ++p) {
      const double dx = CalcContactPointPosition(model, ws, q, b.contact, p).x() - origin_x;
      x_min = std::min(x_min, dx);
      x_max = std::max(x_max, dx);
    }
    qp.A(b.ineq_offset + 2, b.normal) = -x_min;
    qp.A(b.ineq_offset + 3, b.normal) = -x_max;
  }
  SetContactRowBounds(s, mode);
  return qp.Solve();
}

void TaskSpaceQpController::CalcHoldDrift(const LeafContext& context, int mode, const VectorRef& q,
                                          const VectorRef& v) const {
  Scratch& s = context.scratch<Scratch>();
  Scratch::ModeQp& mq = s.modes[mode];
  mq.drift.setZero();
  if (!params_.predict_hold_drift || !mq.prev_valid || s.last_mode != mode || mq.rows == 0) return;
  const double dt = context.time() - mq.t_prev;
  if (!(dt > 0.25 * params_.update_period_s && dt < 1.5 * params_.update_period_s)) return;
  // F(x_k, u_{k−1}): the plant's force now under the torque it has held since the last answer.
  const auto u_held = context.discrete_state().segment(u_offset(), model_->nu());
  CalcConstrainedForwardDynamics(*model_, s.ws, q, v, u_held, mq.active, params_.contact_stabilization, s.qdd_hold,
                                 s.F_hold);
  mq.drift = (s.F_hold.head(mq.rows) - mq.F_prev) * (params_.update_period_s / dt);
}

void TaskSpaceQpController::SetContactRowBounds(Scratch& s, int mode) const {
  const int nv = model_->nv(), nu = model_->nu();
  Scratch::ModeQp& mq = s.modes[mode];
  DenseQpSolver& qp = mq.qp;
  // A row a F ≥ l (or ≤ u) also holds on F + d when l is raised by max(0, −a d) (u lowered by max(0, a d)).
  for (const ContactBlock& b : mq.contacts) {
    const int r = b.ineq_offset, f0 = b.x_offset - nv - nu, fz = b.normal - nv - nu;
    const double apex = b.mu * params_.friction_cone_offset_N, dz = mq.drift[fz];
    qp.lb[b.normal] = params_.min_normal_force_N + std::max(0.0, -dz);
    if (model_->is_planar()) {
      const double dx = mq.drift[fz - 1];
      qp.l[r] = -kInf, qp.u[r] = -apex - std::max(0.0, dx - b.mu * dz);
      qp.l[r + 1] = apex + std::max(0.0, -(dx + b.mu * dz)), qp.u[r + 1] = kInf;
      if (b.cop) {
        // −τ_y − x_min F_z ≥ 0 and −τ_y − x_max F_z ≤ 0 (A holds −x_min, −x_max once SolveQp has set them).
        const double d_min = -mq.drift[f0] + qp.A(r + 2, b.normal) * dz;
        const double d_max = -mq.drift[f0] + qp.A(r + 3, b.normal) * dz;
        qp.l[r + 2] = std::max(0.0, -d_min), qp.u[r + 2] = kInf;
        qp.l[r + 3] = -kInf, qp.u[r + 3] = std::min(0.0, -d_max);
      }
    } else {
      for (int k = 0; k < 4; ++k) {
        const double dtan = ((k % 2 == 0) ? 1.0 : -1.0) * mq.drift[f0 + k / 2];
        qp.l[r + k] = -kInf, qp.u[r + k] = -apex - std::max(0.0, dtan - b.mu * dz);
      }
    }
  }
}

QpStatus TaskSpaceQpController::SolveRelaxedQp(const LeafContext& context) const {
  Scratch& s = context.scratch<Scratch>();
  Scratch::ModeQp& mq = s.modes[s.last_mode];
  DenseQpSolver& qp = mq.qp;
  // Drop the GRF rows (their bounds become infinite) and the normal-force bounds; no allocation.
  for (const ContactBlock& b : mq.contacts) {
    qp.lb[b.normal] = -kInf;
    for (int r = b.ineq_offset; r < b.ineq_offset + b.num_ineq; ++r) {
      s.saved_l[r] = qp.l[r], s.saved_u[r] = qp.u[r];
      qp.l[r] = -kInf, qp.u[r] = kInf;
    }
  }
  const QpStatus status = qp.Solve();
  for (const ContactBlock& b : mq.contacts) {
    qp.lb[b.normal] = params_.min_normal_force_N;
    for (int r = b.ineq_offset; r < b.ineq_offset + b.num_ineq; ++r) qp.l[r] = s.saved_l[r], qp.u[r] = s.saved_u[r];
  }
  return status;
}

TaskSpaceQpDiagnostics TaskSpaceQpController::diagnostics(const LeafContext& context) const {
  const Eigen::VectorXd& xd = context.discrete_state();
  auto count = [&](DiagnosticsSlot k) { return static_cast<int>(xd[slot(k)]); };  // whole numbers, stored as doubles
  TaskSpaceQpDiagnostics d;
  d.qp_failures = count(kFailures);
  if (xd[slot(kStatus)] >= 0.0) d.qp_status = static_cast<QpStatus>(count(kStatus));
  d.solved = count(kSolved);
  d.relaxed = count(kRelaxed);
  d.held = count(kHeld);
  d.task_cost = xd[slot(kTaskCost)];
  d.solve_time_s = xd[slot(kSolveTime)];
  return d;
}

double TaskSpaceQpController::TaskCost(Scratch& s, const Eigen::Ref<const Eigen::VectorXd>& qdd) const {
  if (ny_ == 0) return 0.0;
  // After SolveQp, s.ydd_star holds J̇_y q̇ − ÿ* (see the cost).
  s.residual.noalias() = s.Jy.lazyProduct(qdd);
  s.residual += s.ydd_star;
  return 0.5 * s.residual.cwiseAbs2().dot(s.w_rows);
}

EventStatus TaskSpaceQpController::Update(const LeafContext& context, Eigen::VectorXd* next) const {
  const int nv = model_->nv(), nu = model_->nu(), nc = model_->num_contacts();
  QpStatus status;
  try {
    status = SolveQp(context);
  } catch (const std::exception& e) { return EventStatus::Failed(e.what()); }
  Scratch& s = context.scratch<Scratch>();
  const Scratch::ModeQp& mq = s.modes[s.last_mode];
  (*next)[slot(kStatus)] = static_cast<double>(status);
  bool use_solution = status == QpStatus::kOptimal;
  if (use_solution) (*next)[slot(kSolved)] += 1.0;
  if (!use_solution && status != QpStatus::kInvalidInput &&
      params_.failure_policy == QpFailurePolicy::kRelaxContactForces) {
    (*next)[slot(kFailures)] += 1.0;
    const QpStatus relaxed = SolveRelaxedQp(context);
    if (relaxed == QpStatus::kOptimal) {
      use_solution = true;
      (*next)[slot(kRelaxed)] += 1.0;
    } else {
      (*next)[slot(kStatus)] = static_cast<double>(relaxed);
      (*next)[slot(kHeld)] += 1.0;
      return EventStatus::Succeeded();  // hold the previous u
    }
  }
  Scratch::ModeQp& used = s.modes[s.last_mode];
  used.prev_valid = use_solution;
  if (use_solution) {
    const Eigen::VectorXd& x = mq.qp.x();
    used.F_prev = x.tail(mq.rows);
    used.t_prev = context.time();
    next->segment(u_offset(), nu) = x.segment(nv, nu);
    next->segment(qdd_offset(), nv) = x.head(nv);
    auto forces = next->segment(forces_offset(), 3 * nc);
    forces.setZero();
    (*next)[slot(kTaskCost)] = TaskCost(s, x.head(nv));
    const auto q = EvalInput(context, state_port_).head(model_->nq());
    for (const ContactBlock& b : mq.contacts)
      forces.segment<3>(3 * b.contact) =
          ExtractContactWrench(*model_, s.ws, q, mq.active, x.tail(mq.rows), b.contact).force;
  } else {
    (*next)[slot(kFailures)] += 1.0;
    (*next)[slot(kHeld)] += 1.0;
    if (params_.failure_policy == QpFailurePolicy::kZeroTorque) next->segment(u_offset(), nu).setZero();
    // kHoldPrevious: next starts as a copy of the current discrete state.
  }
  return EventStatus::Succeeded();
}

const DenseQpSolver& TaskSpaceQpController::last_qp(const LeafContext& context) const {
  const Scratch& s = context.scratch<Scratch>();
  return s.modes[s.last_mode].qp;
}

int TaskSpaceQpController::last_mode(const LeafContext& context) const { return context.scratch<Scratch>().last_mode; }

int TaskSpaceQpController::last_num_force_rows(const LeafContext& context) const {
  const Scratch& s = context.scratch<Scratch>();
  return s.modes[s.last_mode].rows;
}

}  // namespace rome
