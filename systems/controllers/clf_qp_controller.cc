#include "systems/controllers/clf_qp_controller.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>

#include <Eigen/Cholesky>

#include "solvers/riccati/rapidly_exponentially_stabilizing_clf.h"
#include "systems/controllers/controller_setup.h"
#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

// The first scalar parameter out of its range, as "params.<name> = <value> must ...", or "" if all are in range.
std::string ScalarParamError(const ClfQpParams& p) {
  auto text = [](const char* what, double value, const char* rule) {
    return std::string("params.") + what + " = " + std::to_string(value) + " must " + rule;
  };
  for (const auto& [value, what] : {std::pair{p.update_period_s, "update_period_s"}, std::pair{p.epsilon, "epsilon"},
                                    std::pair{p.relaxation_weight, "relaxation_weight"}})
    if (!(value > 0.0) || !std::isfinite(value)) return text(what, value, "be positive and finite");
  if (!(p.u_regularization >= 0.0)) return text("u_regularization", p.u_regularization, "be >= 0");
  for (const auto& [value, what, rule] :
       {std::tuple{p.force_band_loading_floor_N, "force_band_loading_floor_N", "be >= 0 N and finite"},
        std::tuple{p.force_band_loading_fall_tolerance_N, "force_band_loading_fall_tolerance_N",
                   "be >= 0 N and finite"},
        std::tuple{p.force_band_margin_N, "force_band_margin_N", "be >= 0 N and finite"},
        std::tuple{p.hold_drift_settle_s, "hold_drift_settle_s", "be >= 0 s and finite"},
        std::tuple{p.contact_stabilization.baumgarte_alpha_per_s, "contact_stabilization.baumgarte_alpha_per_s",
                   "be >= 0 1/s and finite"},
        std::tuple{p.contact_stabilization.baumgarte_beta_per_s, "contact_stabilization.baumgarte_beta_per_s",
                   "be >= 0 1/s and finite"}})
    if (!(value >= 0.0) || !std::isfinite(value)) return text(what, value, rule);
  if (!(p.force_band_halfwidth >= 0.0 && p.force_band_halfwidth < 1.0))
    return text("force_band_halfwidth", p.force_band_halfwidth, "be in [0, 1)");
  if ((p.predict_hold_drift || p.force_band_at_hold_end) && p.formulation != ClfQpFormulation::kEliminateContactForces)
    return "params.predict_hold_drift and params.force_band_at_hold_end need formulation kEliminateContactForces";
  if (!(p.contact.friction_margin > 0.0 && p.contact.friction_margin <= 1.0))
    return text("contact.friction_margin", p.contact.friction_margin, "be in (0, 1]");
  return "";
}
}  // namespace

struct ClfQpController::Scratch {
  struct ModeQp {
    ModeQp(int n, int n_eq, int n_ineq, const QpSettings& settings) : qp(n, n_eq, n_ineq, settings) {}
    ContactSet active = 0;
    int rows = 0;  // constraint force rows: active contacts, then loop closures
    std::vector<ContactWrenchConstraints> wrench;
    std::vector<int> force_offset, ineq_offset;
    int band_offset = -1;
    int drift_offset = -1;   // first hold-drift row (params.predict_hold_drift), the wrench rows again
    int brake_offset = -1;   // first joint-limit brake row (params.joint_limit_brake)
    Eigen::VectorXd F_prev;  // planned constraint forces of the last solve in this mode, and its time
    double t_prev = -kInf;
    bool prev_valid = false;
    std::vector<int> rd1, rd2, soft;  // active outputs: CLF (relative degree 1, 2), cost-only
    int o1 = 0, o2 = 0, os = 0, nout = 0, nx = 0, delta = 0;
    std::vector<int> zero_u;
    DenseQpSolver qp;
    Eigen::LLT<Eigen::MatrixXd> llt;
    Eigen::MatrixXd MinvJT, Lambda, Av, JMinvB, Q, Aout, WAout, Gc;
    Eigen::VectorXd bv, stab, Lf, w, eta, Peta, LGV, clf_row, lc, uc, F, drift, pd_shift;
    Eigen::VectorXd drift_rows;  // the hold drift of the wrench rows' copies (0 for hold_drift_settle_s into a mode)
  };
  explicit Scratch(const MultibodyModel& model) : ws(model) {}
  MultibodyWorkspace ws;
  std::vector<ModeQp> modes;
  Eigen::MatrixXd MinvB, Jy, JyMinvB;
  Eigen::VectorXd rhs_free, minv_rhs, qdd0, y, Jdv, Mb;
  int last_mode = 0;
  double mode_since = -std::numeric_limits<double>::infinity();  // when last_mode began (its first solve) [s]
  bool solved_once = false;
  // force_band_loading_floor_N: each contact's band reference at the last two update instants, whether it was in
  // the mode then and whether it was loading (see BandOf).
  Eigen::VectorXd band_ref_prev, band_ref_cur;
  ContactSet band_active_prev = 0, band_active_cur = 0, band_loading_prev = 0, band_loading_cur = 0;
  double band_time = -std::numeric_limits<double>::infinity();
};

ClfQpController::ClfQpController(std::string name, std::shared_ptr<const MultibodyModel> model,
                                 std::vector<ContactSet> mode_contacts, std::vector<ClfOutput> outputs,
                                 ClfQpParams params)
    : QpControllerSystem(std::move(name)),
      model_(std::move(model)),
      mode_contacts_(std::move(mode_contacts)),
      outputs_(std::move(outputs)),
      params_(std::move(params)) {
  if (!model_) ThrowError("null MultibodyModel");
  const int nv = model_->nv(), nu = model_->nu(), nc = model_->num_contacts();
  if (mode_contacts_.empty()) ThrowError("no contact modes given (mode_contacts is empty)");
  if (const std::string e = ScalarParamError(params_); !e.empty()) ThrowError(e);
  for (size_t i = 0; i < outputs_.size(); ++i) {
    const ClfOutput& o = outputs_[i];
    if (!o.rd1 == !o.rd2)
      ThrowError("output " + std::to_string(i) +
                 " must be exactly one of a relative-degree-1 and a relative-degree-2 output");
    offsets_.push_back(ny_);
    ny_ += o.size();
    const std::vector<int>& modes = o.rd2 ? o.rd2->active_modes() : o.rd1->active_modes();
    for (int m : modes)
      if (m < 0 || m >= static_cast<int>(mode_contacts_.size()))
        ThrowError("output '" + o.name() + "' is active in mode " + std::to_string(m) + ", but only " +
                   std::to_string(mode_contacts_.size()) + " modes were given");
  }
  if (params_.u_regularization_weights.size() != 0) {
    if (params_.u_regularization_weights.size() != nu)
      ThrowError("params.u_regularization_weights has " + std::to_string(params_.u_regularization_weights.size()) +
                 " entries, expected " + std::to_string(nu) + " (one per actuator)");
    for (int j = 0; j < nu; ++j)
      if (!(params_.u_regularization_weights[j] > 0.0) || !std::isfinite(params_.u_regularization_weights[j]))
        ThrowError("params.u_regularization_weights[" + std::to_string(j) +
                   "] = " + std::to_string(params_.u_regularization_weights[j]) + " must be positive and finite");
  }
  for (int m : params_.u_regularization_modes)
    if (m < 0 || m >= static_cast<int>(mode_contacts_.size()))
      ThrowError("params.u_regularization_modes names mode " + std::to_string(m) + ", but only " +
                 std::to_string(mode_contacts_.size()) + " modes were given");
  cost_only_.assign(outputs_.size(), false);
  for (const std::string& name : params_.cost_only_outputs) {
    const auto it =
        std::find_if(outputs_.begin(), outputs_.end(), [&](const ClfOutput& o) { return o.name() == name; });
    if (it == outputs_.end())
      ThrowError("params.cost_only_outputs names '" + name + "', which is not an output of this controller");
    if (!it->rd2)
      ThrowError("params.cost_only_outputs names '" + name +
                 "', a relative-degree-1 output; only relative-degree-2 outputs (with PD gains) may be cost-only");
    cost_only_[it - outputs_.begin()] = true;
  }
  if (!(params_.clf_active_tolerance >= 0.0) || !std::isfinite(params_.clf_active_tolerance))
    ThrowError("params.clf_active_tolerance = " + std::to_string(params_.clf_active_tolerance) +
               " must be finite and >= 0");
  u_max_ = ResolveTorqueLimits(*model_, params_.torque_limits, this->name());
  brake_ = JointLimitBrake(*model_, params_.joint_limit_brake, "system '" + this->name() + "'");
  zero_torque_ = ZeroTorqueActuatorsPerMode(*model_, mode_contacts_, params_.zero_torque_in_contact, this->name());
  // RES-CLF of every mode (Eq. (26)-(30)), Q = I.
  for (size_t m = 0; m < mode_contacts_.size(); ++m) {
    try {
      CountConstraintRows(*model_, mode_contacts_[m]);
      for (int c = 0; c < nc; ++c)
        if (mode_contacts_[m] & ContactBit(c)) {
          const ContactWrenchConstraints cw(*model_, c, params_.contact, this->name());
          if (params_.force_band && !cw.has_normal_entry())
            throw std::invalid_argument(
                "params.force_band needs a single F_z entry per contact, which the 3D line contact '" +
                model_->contacts()[c].name + "' does not have");
        }
    } catch (const std::invalid_argument& e) {
      ThrowError("contact set of mode " + std::to_string(m) + ": " + e.what());
    }
    int o1 = 0, o2 = 0;
    for (size_t i = 0; i < outputs_.size(); ++i)
      if (outputs_[i].IsActiveIn(static_cast<int>(m)) && !cost_only_[i])
        (outputs_[i].rd1 ? o1 : o2) += outputs_[i].size();
    ModeClf clf;
    if (o1 + o2 > 0) {
      MakeOutputDynamics(o1, o2, &clf.F, &clf.G);
      RapidlyExponentiallyStabilizingClfParameters p;
      p.num_relative_degree_one_outputs = o1;
      p.num_relative_degree_two_outputs = o2;
      p.epsilon = params_.epsilon;
      const int n_eta = o1 + 2 * o2;
      const RapidlyExponentiallyStabilizingClf res =
          ComputeRapidlyExponentiallyStabilizingClf(clf.F, clf.G, Eigen::MatrixXd::Identity(n_eta, n_eta), p);
      clf.P_epsilon = res.P_epsilon;
      clf.convergence_rate = params_.gamma > 0.0 ? params_.gamma / params_.epsilon : res.convergence_rate;
    }
    clf_.push_back(std::move(clf));
  }

  state_port_ = DeclareInputPort("state", model_->nq() + nv);
  mode_port_ = DeclareTypedInputPort<int>("mode");
  desired_port_ = DeclareInputPort("desired", 3 * ny_);
  if (params_.force_band) force_ref_port_ = DeclareInputPort("normal_force_reference", nc);
  Eigen::VectorXd xd0 = Eigen::VectorXd::Zero(slot(kNumSlots));
  xd0[slot(kStatus)] = -1;  // no QP solved yet
  DeclareDiscreteState(xd0);
  DeclareOutputPort(
      "u", nu,
      [this, nu](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state().segment(u_offset(), nu); },
      Feedthrough::None());
  DeclareOutputPort(
      "contact_forces", 3 * nc,
      [this, nc](const LeafContext& c, Eigen::VectorXd* y) {
        *y = c.discrete_state().segment(forces_offset(), 3 * nc);
      },
      Feedthrough::None());
  DeclareOutputPort(
      "V", 1, [this](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = c.discrete_state()[slot(kV)]; },
      Feedthrough::None());
  DeclareOutputPort(
      "delta", 1, [this](const LeafContext& c, Eigen::VectorXd* y) { (*y)[0] = c.discrete_state()[slot(kDelta)]; },
      Feedthrough::None());
  DeclareOutputPort(
      "fallbacks", {"drift_dropped", "band_dropped", "cop_dropped", "held"},
      [this](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state().segment<4>(slot(kDriftDropped)); },
      Feedthrough::None());
  DeclareOutputPort(
      "clf_activity", {"clf_active", "solved"},
      [this](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state().segment<2>(slot(kClfActive)); },
      Feedthrough::None());
  DeclareQpPortsAndUpdates(slot(kFailures), slot(kStatus), slot(kSolveTime), params_.update_period_s,
                           params_.resolve_at_events, params_.resolve_at,
                           [this](const LeafContext& c, Eigen::VectorXd* next) { return Update(c, next); });
  DeclareTypedOutputPort<ClfQpDiagnostics>(
      "diagnostics", [this](const LeafContext& c, ClfQpDiagnostics* d) { *d = diagnostics(c); }, Feedthrough::None());
}

std::any ClfQpController::AllocateScratch() const {
  const MultibodyModel& model = *model_;
  const int nv = model.nv(), nu = model.nu();
  const bool augmented = params_.formulation == ClfQpFormulation::kAugmentedInput;
  Scratch s(model);
  s.MinvB.setZero(nv, nu);
  s.Jy.setZero(std::max(ny_, 1), nv);
  s.JyMinvB.setZero(std::max(ny_, 1), nu);
  s.rhs_free.setZero(nv);
  s.minv_rhs.setZero(nv);
  s.qdd0.setZero(nv);
  s.band_ref_prev.setZero(model.num_contacts());
  s.band_ref_cur.setZero(model.num_contacts());
  s.y.setZero(std::max(ny_, 1));
  s.Jdv.setZero(std::max(ny_, 1));
  s.Mb.setZero(nv);
  s.modes.reserve(mode_contacts_.size());
  for (size_t m = 0; m < mode_contacts_.size(); ++m) {
    const ContactSet active = mode_contacts_[m];
    const int rows = CountConstraintRows(model, active);
    std::vector<ContactWrenchConstraints> wrench;
    std::vector<int> force_offset, ineq_offset;
    int f = 0, ineq = 1;  // row 0: the CLF row
    int max_wrench_rows = 0, max_force_rows = 0;
    for (int c = 0; c < model.num_contacts(); ++c) {
      if (!(active & ContactBit(c))) continue;
      wrench.emplace_back(model, c, params_.contact, name());
      force_offset.push_back(f);
      ineq_offset.push_back(ineq);
      f += wrench.back().num_force_rows();
      ineq += wrench.back().num_rows();
      max_wrench_rows = std::max(max_wrench_rows, wrench.back().num_rows());
      max_force_rows = std::max(max_force_rows, wrench.back().num_force_rows());
    }
    const int band_offset = params_.force_band ? ineq : -1;
    if (params_.force_band) ineq += static_cast<int>(wrench.size());
    int drift_offset = -1;
    if (params_.predict_hold_drift && !wrench.empty()) {
      drift_offset = ineq;
      for (const ContactWrenchConstraints& cw : wrench) ineq += cw.num_rows();
    }
    const int brake_offset = brake_.num_rows() > 0 ? ineq : -1;
    ineq += brake_.num_rows();
    const int nx = nu + (augmented ? rows : 0) + 1;
    Scratch::ModeQp mq(nx, augmented ? rows : 0, ineq, params_.qp);
    mq.active = active;
    mq.rows = rows;
    mq.wrench = std::move(wrench);
    mq.force_offset = std::move(force_offset);
    mq.ineq_offset = std::move(ineq_offset);
    mq.band_offset = band_offset;
    mq.drift_offset = drift_offset;
    mq.brake_offset = brake_offset;
    mq.F_prev.setZero(std::max(rows, 1));
    mq.drift.setZero(std::max(rows, 1));
    mq.drift_rows.setZero(std::max(rows, 1));
    mq.nx = nx;
    mq.delta = nx - 1;
    mq.zero_u = zero_torque_[m];
    for (size_t i = 0; i < outputs_.size(); ++i)
      if (outputs_[i].IsActiveIn(static_cast<int>(m))) {
        if (cost_only_[i]) {
          mq.soft.push_back(static_cast<int>(i));
          mq.os += outputs_[i].size();
        } else if (outputs_[i].rd1) {
          mq.rd1.push_back(static_cast<int>(i));
          mq.o1 += outputs_[i].size();
        } else {
          mq.rd2.push_back(static_cast<int>(i));
          mq.o2 += outputs_[i].size();
        }
      }
    mq.nout = mq.o1 + mq.o2 + mq.os;
    // Sized (and its status set) here, so the per-update compute() on the same size allocates nothing. (LLT(size)
    // leaves its status uninitialised, which a move would read.)
    mq.llt.compute(Eigen::MatrixXd::Identity(rows, rows));
    mq.MinvJT.setZero(nv, rows);
    mq.Lambda.setZero(rows, rows);
    mq.Av.setZero(rows, nu);
    mq.JMinvB.setZero(rows, nu);
    mq.Q.setZero(nv, nu);
    mq.bv.setZero(rows);
    mq.stab.setZero(rows);
    mq.F.setZero(std::max(rows, 1));
    mq.Aout.setZero(mq.nout, nx);
    mq.WAout.setZero(mq.nout, nx);
    mq.Lf.setZero(mq.nout);
    mq.pd_shift.setZero(mq.nout);  // nonzero only on relative-degree-2 CLF rows with params.cost_pd_feedback
    mq.w.setZero(mq.nout);
    mq.eta.setZero(mq.o1 + 2 * mq.o2);
    mq.Peta.setZero(mq.o1 + 2 * mq.o2);
    mq.LGV.setZero(mq.nout);
    mq.clf_row.setZero(nx);
    mq.Gc.setZero(std::max(max_wrench_rows, 1), std::max(max_force_rows, 1));
    mq.lc.setZero(std::max(max_wrench_rows, 1));
    mq.uc.setZero(std::max(max_wrench_rows, 1));
    // Constant data: torque bounds, δ ≥ 0 (F free).
    DenseQpSolver& qp = mq.qp;
    for (int j = 0; j < nu; ++j) qp.lb[j] = -u_max_[j], qp.ub[j] = u_max_[j];
    for (int j : mq.zero_u) qp.lb[j] = qp.ub[j] = 0.0;
    qp.lb[mq.delta] = 0.0;
    qp.l[0] = -kInf;
    s.modes.push_back(std::move(mq));
  }
  return s;
}

int ClfQpController::ModeFromInput(const LeafContext& context) const {
  return CheckedModeIndex(EvalTypedInput<int>(context, mode_port_), static_cast<int>(mode_contacts_.size()), name());
}

QpStatus ClfQpController::SolveQp(const LeafContext& context) const {
  const int mode = ModeFromInput(context);
  Scratch& s = context.scratch<Scratch>();
  const bool same_mode = s.last_mode == mode;
  s.last_mode = mode;
  if (!same_mode || !s.solved_once) s.mode_since = context.time();
  s.solved_once = true;
  const Eigen::VectorXd& x = EvalInput(context, state_port_);
  const Eigen::VectorXd& desired = EvalInput(context, desired_port_);
  if (!x.allFinite()) throw std::runtime_error("system '" + name() + "': input port 'state' is not finite");
  const auto q = x.head(model_->nq());
  const auto v = x.tail(model_->nv());
  const int rows = CalcConstrainedDynamics(context, q, v, same_mode, s, mode);
  if (rows < 0) return QpStatus::kInvalidInput;
  const double reg_scale = CalcOutputRows(q, v, desired, rows, s, mode);
  if (!FillCost(q, reg_scale, rows, s, mode)) return QpStatus::kInvalidInput;
  FillClfRow(s, mode);
  FillWrenchRows(context, q, s, mode);
  Scratch::ModeQp& mq = s.modes[mode];
  if (mq.brake_offset >= 0) {  // q̈ = q̈0 + Q_u u (+ M⁻¹ Jᵀ F when augmented)
    const bool augmented = params_.formulation == ClfQpFormulation::kAugmentedInput;
    brake_.Fill(q, v, s.qdd0, augmented ? s.MinvB : mq.Q, mq.MinvJT.leftCols(augmented ? rows : 0), mq.brake_offset,
                mq.qp);
  }
  const QpStatus status = s.modes[mode].qp.Solve();
  if (status == QpStatus::kOptimal) StorePlannedForces(rows, s, mode);
  return status;
}

int ClfQpController::CalcConstrainedDynamics(const LeafContext& context, const VectorRef& q, const VectorRef& v,
                                             bool same_mode, Scratch& s, int mode) const {
  const MultibodyModel& model = *model_;
  const int nv = model.nv(), nu = model.nu();
  const bool augmented = params_.formulation == ClfQpFormulation::kAugmentedInput;
  Scratch::ModeQp& mq = s.modes[mode];
  DenseQpSolver& qp = mq.qp;
  MultibodyWorkspace& ws = s.ws;
  const double alpha = params_.contact_stabilization.baumgarte_alpha_per_s,
               beta = params_.contact_stabilization.baumgarte_beta_per_s;
  // Free dynamics: M q̈ = τ_s − h + B u + Jᵀ F.
  s.rhs_free = CalcSpringTorques(model, ws, q, v) - CalcBiasForces(model, ws, q, v);
  s.minv_rhs = s.rhs_free;
  SolveMassMatrix(model, ws, q, Eigen::Map<Eigen::MatrixXd>(s.minv_rhs.data(), nv, 1));
  s.MinvB = model.B();
  SolveMassMatrix(model, ws, q, s.MinvB);
  const int rows = CalcConstraintJacobian(model, ws, q, v, mq.active);
  s.qdd0 = s.minv_rhs;
  if (rows == 0) {
    mq.Q = s.MinvB;
    return rows;
  }
  const auto J = ws.J.topRows(rows);
  mq.MinvJT = J.transpose();
  SolveMassMatrix(model, ws, q, mq.MinvJT);
  mq.Lambda.noalias() = J.lazyProduct(mq.MinvJT);
  mq.JMinvB.noalias() = J.lazyProduct(s.MinvB);
  // J q̈ + J̇ q̇ + 2α J q̇ + β² φ = 0  ⇔  Λ F + J M⁻¹ B u = −(J M⁻¹ (τ_s − h) + J̇ q̇ + 2α J q̇ + β² φ).
  mq.stab = ws.Jdot_qdot.head(rows) + (beta * beta) * ws.phi.head(rows);
  mq.stab.noalias() += (2.0 * alpha) * (J * v);
  mq.stab.noalias() += J * s.minv_rhs;
  if (augmented) {
    qp.A_eq.leftCols(nu) = mq.JMinvB;
    qp.A_eq.middleCols(nu, rows) = mq.Lambda;
    qp.b_eq = -mq.stab;
    return rows;
  }
  mq.llt.compute(mq.Lambda);
  if (mq.llt.info() != Eigen::Success) return -1;
  mq.Av = -mq.JMinvB;
  mq.llt.solveInPlace(mq.Av);  // A_v = −Λ⁻¹ J M⁻¹ B (Eq. (21))
  mq.bv = -mq.stab;
  mq.llt.solveInPlace(mq.bv);  // b_v (Eq. (22))
  mq.Q = s.MinvB;
  mq.Q.noalias() += mq.MinvJT.lazyProduct(mq.Av);
  s.qdd0.noalias() += mq.MinvJT * mq.bv;
  // Hold drift: F(x_k, u_{k-1}) − F(x_{k-1}, u_{k-1}), per update period (0 without a previous solve in this mode).
  mq.drift.head(rows).setZero();
  const double dt = context.time() - mq.t_prev;
  if ((params_.predict_hold_drift || params_.force_band_at_hold_end) && mq.prev_valid && same_mode &&
      dt > 0.25 * params_.update_period_s && dt < 1.5 * params_.update_period_s) {
    mq.drift.head(rows) = mq.bv - mq.F_prev.head(rows);
    mq.drift.head(rows).noalias() += mq.Av * context.discrete_state().segment(u_offset(), nu);
    mq.drift.head(rows) *= params_.update_period_s / dt;
  }
  if (context.time() - s.mode_since >= params_.hold_drift_settle_s - 1e-9)  // 1 ns: a mode begun on the update grid
    mq.drift_rows.head(rows) = mq.drift.head(rows);
  else
    mq.drift_rows.head(rows).setZero();
  return rows;
}

double ClfQpController::CalcOutputRows(const VectorRef& q, const VectorRef& v, const Eigen::VectorXd& desired, int rows,
                                       Scratch& s, int mode) const {
  const MultibodyModel& model = *model_;
  const int nu = model.nu();
  const bool augmented = params_.formulation == ClfQpFormulation::kAugmentedInput;
  Scratch::ModeQp& mq = s.modes[mode];
  MultibodyWorkspace& ws = s.ws;
  // q̈ = q̈0 + Qu u (+ M⁻¹ Jᵀ F when augmented).
  const Eigen::MatrixXd& Qu = augmented ? s.MinvB : mq.Q;
  // μ rows [RD1; RD2; cost-only] = Aout x + L_f; η = [y1; y2; ẏ2] errors.
  int r = 0;
  int e = 0;
  double reg_scale = 0.0;
  auto add_rows = [&](int off, int n, double weight, const Eigen::Ref<const Eigen::VectorXd>& target) {
    const auto Jrows = s.Jy.middleRows(off, n);
    mq.Aout.block(r, 0, n, nu).noalias() = Jrows.lazyProduct(Qu);
    if (augmented && rows > 0) mq.Aout.block(r, nu, n, rows).noalias() = Jrows.lazyProduct(mq.MinvJT);
    mq.Lf.segment(r, n).noalias() = Jrows * s.qdd0;
    mq.Lf.segment(r, n) += s.Jdv.segment(off, n) - target;
    mq.w.segment(r, n).setConstant(weight);
    // Curvature scale of the regularisation from J_y M⁻¹ B (the same in both formulations; augmented, it is the u block
    // just formed).
    if (augmented) {
      reg_scale = std::max(reg_scale, weight * mq.Aout.block(r, 0, n, nu).colwise().squaredNorm().maxCoeff());
    } else {
      s.JyMinvB.topRows(n).noalias() = Jrows.lazyProduct(s.MinvB);
      reg_scale = std::max(reg_scale, weight * s.JyMinvB.topRows(n).colwise().squaredNorm().maxCoeff());
    }
    r += n;
  };
  for (int i : mq.rd1) {
    const ClfOutput& o = outputs_[i];
    const int off = offsets_[i], n = o.size();
    o.rd1->Calc(model, ws, q, v, s.y.segment(off, n), s.Jy.middleRows(off, n), s.Jdv.segment(off, n));
    mq.eta.segment(e, n) = s.y.segment(off, n) - desired.segment(off, n);
    e += n;
    add_rows(off, n, o.weight(), desired.segment(ny_ + off, n));
  }
  for (int i : mq.rd2) {
    const ClfOutput& o = outputs_[i];
    const int off = offsets_[i], n = o.size();
    o.rd2->Calc(model, ws, q, v, s.y.segment(off, n), s.Jy.middleRows(off, n), s.Jdv.segment(off, n));
    mq.eta.segment(e, n) = s.y.segment(off, n) - desired.segment(off, n);
    mq.eta.segment(e + mq.o2, n).noalias() = s.Jy.middleRows(off, n) * v;
    mq.eta.segment(e + mq.o2, n) -= desired.segment(ny_ + off, n);
    // The CLF row needs μ = ÿ − ÿ_d; with params.cost_pd_feedback the cost's target is ÿ* = ÿ_d + pd_shift instead.
    if (params_.cost_pd_feedback) {
      const TaskGains& gains = o.rd2->gains();
      mq.pd_shift.segment(r, n) = -gains.kp * mq.eta.segment(e, n) - gains.kd * mq.eta.segment(e + mq.o2, n);
    }
    add_rows(off, n, o.weight(), desired.segment(2 * ny_ + off, n));
    e += n;
  }
  // Cost-only outputs: target ÿ* = ÿ_d − Kp (y − y_d) − Kd (ẏ − ẏ_d) (s.y, s.Jdv rows as scratch for ÿ*).
  for (int i : mq.soft) {
    const ClfOutput& o = outputs_[i];
    const int off = offsets_[i], n = o.size();
    const TaskGains& gains = o.rd2->gains();
    o.rd2->Calc(model, ws, q, v, s.y.segment(off, n), s.Jy.middleRows(off, n), s.Jdv.segment(off, n));
    // ÿ* into s.y's rows (y is not needed after this).
    s.y.segment(off, n) =
        desired.segment(2 * ny_ + off, n) - gains.kp * (s.y.segment(off, n) - desired.segment(off, n));
    s.y.segment(off, n).noalias() -= gains.kd * (s.Jy.middleRows(off, n) * v);
    s.y.segment(off, n) += gains.kd * desired.segment(ny_ + off, n);
    add_rows(off, n, o.weight(), s.y.segment(off, n));
  }
  return reg_scale;
}

bool ClfQpController::FillCost(const VectorRef& q, double reg_scale, int rows, Scratch& s, int mode) const {
  const MultibodyModel& model = *model_;
  const int nu = model.nu();
  const bool augmented = params_.formulation == ClfQpFormulation::kAugmentedInput;
  Scratch::ModeQp& mq = s.modes[mode];
  DenseQpSolver& qp = mq.qp;
  // ½||W^½(Aout x + L_f)||² + ½ ρ s ||u||² + ½ p δ².
  qp.H.setZero();
  qp.g.setZero();
  if (mq.nout > 0) {
    mq.WAout.noalias() = mq.w.asDiagonal() * mq.Aout;
    qp.H.noalias() = mq.Aout.transpose().lazyProduct(mq.WAout);
    qp.g.noalias() = mq.WAout.transpose() * mq.Lf;
    if (params_.cost_pd_feedback) qp.g.noalias() -= mq.WAout.transpose() * mq.pd_shift;
  }
  const double scale = reg_scale > 0.0 ? reg_scale : 1.0;
  const bool per_actuator = params_.u_regularization_modes.empty() ||
                            std::find(params_.u_regularization_modes.begin(), params_.u_regularization_modes.end(),
                                      mode) != params_.u_regularization_modes.end();
  if (!per_actuator) {
    qp.H.diagonal().head(nu).array() += params_.u_regularization * scale;
  } else {
    const bool inertia = params_.u_regularization_kind == TorqueRegularization::kInverseJointInertia;
    const Eigen::MatrixXd* M = inertia ? &CalcMassMatrix(model, s.ws, q) : nullptr;
    for (int j = 0; j < nu; ++j) {
      double s_j = scale;
      if (inertia) {
        s.Mb.noalias() = *M * model.B().col(j);
        const double m_j = model.B().col(j).dot(s.Mb);  // b_jᵀ M b_j [kg m²]
        if (!(m_j > 0.0)) return false;
        s_j = 1.0 / (m_j * m_j);
      }
      if (params_.u_regularization_weights.size() != 0) s_j *= params_.u_regularization_weights[j];
      qp.H(j, j) += params_.u_regularization * s_j;
    }
  }
  // δ enters as δ' = √p δ, so that ½ p δ² = ½ δ'² keeps H well scaled (DenseQpSolver's pivot test is relative).
  qp.H(mq.delta, mq.delta) = 1.0;
  if (augmented && rows > 0) {
    // ½ ρ ||A_eq x − b_eq||²: zero on the feasible set, so the optimum is unchanged, but it gives H curvature along F
    // (the output cost sees F only through the outputs), so H is positive definite and needs no proximal iterations.
    const double rho = scale / std::max(mq.Lambda.diagonal().maxCoeff() * mq.Lambda.diagonal().maxCoeff(), 1e-300);
    // Symmetric rank update of the lower triangle, then mirrored (H was symmetric before).
    auto Hn = qp.H.topLeftCorner(nu + rows, nu + rows);
    Hn.selfadjointView<Eigen::Lower>().rankUpdate(qp.A_eq.leftCols(nu + rows).transpose(), rho);
    Hn.triangularView<Eigen::StrictlyUpper>() = Hn.transpose();
    qp.g.head(nu + rows).noalias() -= rho * (qp.A_eq.leftCols(nu + rows).transpose() * qp.b_eq);
  }
  return true;
}

void ClfQpController::FillClfRow(Scratch& s, int mode) const {
  Scratch::ModeQp& mq = s.modes[mode];
  DenseQpSolver& qp = mq.qp;
  // Eq. (36)-(37): L_G V Aout x − δ ≤ −(γ/ε) V − L_F V − L_G V L_f, normalised.
  if (mq.o1 + mq.o2 == 0) {
    qp.A.row(0).setZero();
    qp.u[0] = kInf;
    return;
  }
  const ModeClf& clf = clf_[mode];
  mq.Peta.noalias() = clf.P_epsilon * mq.eta;
  const double V = mq.eta.dot(mq.Peta);
  // L_F V = 2 ηᵀ P_ε F η; F η moves ẏ2 into the y2 slots.
  const double LFV = 2.0 * mq.Peta.segment(mq.o1, mq.o2).dot(mq.eta.tail(mq.o2));
  // L_G V = 2 ηᵀ P_ε G: G picks the y1 and ẏ2 slots.
  mq.LGV.head(mq.o1) = 2.0 * mq.Peta.head(mq.o1);
  mq.LGV.segment(mq.o1, mq.o2) = 2.0 * mq.Peta.tail(mq.o2);
  mq.LGV.tail(mq.os).setZero();  // cost-only rows are not in V
  mq.clf_row.noalias() = mq.Aout.transpose() * mq.LGV;
  mq.clf_row[mq.delta] = -1.0 / std::sqrt(params_.relaxation_weight);
  const double rhs = -clf.convergence_rate * V - LFV - mq.LGV.dot(mq.Lf);
  const double norm = 1.0 + mq.clf_row.head(mq.delta).norm();
  qp.A.row(0) = mq.clf_row.transpose() / norm;
  qp.u[0] = rhs / norm;
}

void ClfQpController::FillWrenchRows(const LeafContext& context, const VectorRef& q, Scratch& s, int mode) const {
  const MultibodyModel& model = *model_;
  const int nu = model.nu();
  const bool augmented = params_.formulation == ClfQpFormulation::kAugmentedInput;
  Scratch::ModeQp& mq = s.modes[mode];
  DenseQpSolver& qp = mq.qp;
  // The contact-wrench rows of each active contact, and the force band.
  const Eigen::VectorXd* force_ref = params_.force_band ? &EvalInput(context, force_ref_port_) : nullptr;
  double active_ref = 0.0, inactive_ref = 0.0;  // force_band_carry_inactive: the load of the contacts not in the mode
  if (force_ref != nullptr && params_.force_band_carry_inactive && !mq.wrench.empty()) {
    for (int c = 0; c < force_ref->size(); ++c) inactive_ref += std::max((*force_ref)[c], 0.0);
    for (const ContactWrenchConstraints& cw : mq.wrench) active_ref += std::max((*force_ref)[cw.contact()], 0.0);
    inactive_ref -= active_ref;
  }
  if (force_ref != nullptr && context.time() != s.band_time) {  // a new update instant (fallback re-solves share one)
    s.band_ref_prev = s.band_ref_cur;
    s.band_active_prev = s.band_active_cur;
    s.band_loading_prev = s.band_loading_cur;
    s.band_active_cur = mq.active;
    s.band_time = context.time();
  }
  for (size_t k = 0; k < mq.wrench.size(); ++k) {
    const ContactWrenchConstraints& cw = mq.wrench[k];
    const int nr = cw.num_rows(), nf = cw.num_force_rows(), fo = mq.force_offset[k], io = mq.ineq_offset[k];
    const Band band =
        force_ref != nullptr ? BandOf(*force_ref, static_cast<int>(k), active_ref, inactive_ref, s, mode) : Band{};
    auto G = mq.Gc.topLeftCorner(nr, nf);
    cw.Fill(model, s.ws, q, G, mq.lc.head(nr), mq.uc.head(nr));
    auto A = qp.A.middleRows(io, nr);
    A.setZero();
    if (augmented) {
      A.middleCols(nu + fo, nf) = G;
      qp.l.segment(io, nr) = mq.lc.head(nr);
      qp.u.segment(io, nr) = mq.uc.head(nr);
    } else {
      A.leftCols(nu).noalias() = G.lazyProduct(mq.Av.middleRows(fo, nf));
      for (int i = 0; i < nr; ++i) {
        const double shift = G.row(i).dot(mq.bv.segment(fo, nf));
        qp.l[io + i] = mq.lc[i] - shift;
        qp.u[io + i] = mq.uc[i] - shift;
      }
      if (mq.drift_offset >= 0) {
        // The same rows on F(u) + d (see params.predict_hold_drift), but for a contact the band releases.
        const int dro = mq.drift_offset + (io - mq.ineq_offset[0]);
        qp.A.middleRows(dro, nr) = A;
        const bool released = force_ref != nullptr &&  // 0 but for the plan's solver noise
                              band.upper <= params_.force_band_loading_fall_tolerance_N;
        for (int i = 0; i < nr; ++i) {
          const double shift = G.row(i).dot(mq.drift_rows.segment(fo, nf));
          qp.l[dro + i] = released ? -kInf : qp.l[io + i] - shift;
          qp.u[dro + i] = released ? kInf : qp.u[io + i] - shift;
        }
      }
    }
    if (force_ref != nullptr) FillForceBandRow(band, static_cast<int>(k), s, mode);
  }
}

ClfQpController::Band ClfQpController::BandOf(const Eigen::VectorXd& force_ref, int k, double active_ref,
                                              double inactive_ref, const Scratch& s, int mode) const {
  const Scratch::ModeQp& mq = s.modes[mode];
  const int ci = mq.wrench[k].contact();
  double f_ref = std::max(force_ref[ci], 0.0);
  if (inactive_ref > 0.0)
    f_ref += inactive_ref * (active_ref > 0.0 ? f_ref / active_ref : 1.0 / static_cast<double>(mq.wrench.size()));
  // Walking paper Eq. (25): (1 − c) F_ref ≤ F_z ≤ (1 + c) F_ref, with the margin and the loading floor (params).
  const double c = params_.force_band_halfwidth;
  double lower = (1.0 - c) * f_ref, upper = (1.0 + c) * f_ref;
  const double margin = std::min(params_.force_band_margin_N, 0.25 * (upper - lower));
  lower += margin, upper -= margin;
  // Loading: new in the mode, or its reference did not fall, unless it fell to 0 before (a foot the plan released
  // but the plant has not: held at the floor, it would never be released).
  const double tol = params_.force_band_loading_fall_tolerance_N;
  const bool loading = !(s.band_active_prev & ContactBit(ci)) ||
                       (f_ref >= s.band_ref_prev[ci] - tol && ((s.band_loading_prev & ContactBit(ci)) || f_ref > tol));
  if (loading && params_.force_band_loading_floor_N > 0.0) {
    lower = std::max(lower, params_.force_band_loading_floor_N);
    upper = std::max(upper, lower);
  }
  return {f_ref, lower, upper, loading};
}

void ClfQpController::FillForceBandRow(const Band& band, int k, Scratch& s, int mode) const {
  const int nu = model_->nu();
  Scratch::ModeQp& mq = s.modes[mode];
  DenseQpSolver& qp = mq.qp;
  const ContactWrenchConstraints& cw = mq.wrench[k];
  const int br = mq.band_offset + k;
  const int fz = mq.force_offset[k] + cw.normal_index();
  qp.A.row(br).setZero();
  double shift = 0.0;
  if (params_.formulation == ClfQpFormulation::kAugmentedInput) {
    qp.A(br, nu + fz) = 1.0;
  } else {
    qp.A.row(br).head(nu) = mq.Av.row(fz);
    // F_z(u) (+ d_z: the hold's end); a drift above the upper edge would ask F_z(u) < 0 against the unilateral row.
    shift = mq.bv[fz] + (params_.force_band_at_hold_end ? std::min(mq.drift[fz], band.upper) : 0.0);
  }
  s.band_ref_cur[cw.contact()] = band.reference;
  s.band_loading_cur =
      band.loading ? s.band_loading_cur | ContactBit(cw.contact()) : s.band_loading_cur & ~ContactBit(cw.contact());
  qp.l[br] = band.lower - shift;
  qp.u[br] = band.upper - shift;
}

void ClfQpController::StorePlannedForces(int rows, Scratch& s, int mode) const {
  Scratch::ModeQp& mq = s.modes[mode];
  if (rows <= 0) return;
  const int nu = model_->nu();
  if (params_.formulation == ClfQpFormulation::kAugmentedInput) {
    mq.F.head(rows) = mq.qp.x().segment(nu, rows);
  } else {
    mq.F.head(rows) = mq.bv;
    mq.F.head(rows).noalias() += mq.Av * mq.qp.x().head(nu);
  }
}

void ClfQpController::SetRowsEnabled(const LeafContext& context, bool drift, bool band, bool cop) const {
  Scratch& s = context.scratch<Scratch>();
  Scratch::ModeQp& mq = s.modes[s.last_mode];
  DenseQpSolver& qp = mq.qp;
  if (!band && mq.band_offset >= 0)
    for (size_t k = 0; k < mq.wrench.size(); ++k) qp.l[mq.band_offset + k] = -kInf, qp.u[mq.band_offset + k] = kInf;
  if (!drift && mq.drift_offset >= 0)
    for (int i = mq.drift_offset;
         i < mq.drift_offset + mq.ineq_offset.back() + mq.wrench.back().num_rows() - mq.ineq_offset[0]; ++i)
      qp.l[i] = -kInf, qp.u[i] = kInf;
  if (!band && mq.brake_offset >= 0) brake_.Disable(mq.brake_offset, qp);
  if (!cop)
    for (size_t k = 0; k < mq.wrench.size(); ++k)
      for (int i = 0; i < mq.wrench[k].num_rows(); ++i)
        if (mq.wrench[k].kind(i) == ContactWrenchConstraints::RowKind::kCenterOfPressure)
          qp.l[mq.ineq_offset[k] + i] = -kInf, qp.u[mq.ineq_offset[k] + i] = kInf;
}

EventStatus ClfQpController::Update(const LeafContext& context, Eigen::VectorXd* next) const {
  const int nu = model_->nu(), nc = model_->num_contacts();
  QpStatus status;
  try {
    status = SolveQp(context);
  } catch (const std::exception& e) { return EventStatus::Failed(e.what()); }
  Scratch& s = context.scratch<Scratch>();
  Scratch::ModeQp& mq = s.modes[s.last_mode];
  if (status != QpStatus::kOptimal && status != QpStatus::kInvalidInput) {
    (*next)[slot(kFailures)] += 1.0;
    // Fallback 0: drop the hold-drift rows; 1: also the force band and the brake rows; 2: also the CoP rows (each
    // counted); else hold the previous u.
    if (mq.drift_offset >= 0) {
      SetRowsEnabled(context, false, true, true);
      status = mq.qp.Solve();
      (*next)[slot(kDriftDropped)] += 1.0;
    }
    if (status != QpStatus::kOptimal && (mq.band_offset >= 0 || mq.brake_offset >= 0)) {
      SetRowsEnabled(context, false, false, true);
      status = mq.qp.Solve();
      (*next)[slot(kBandDropped)] += 1.0;
    }
    if (status != QpStatus::kOptimal) {
      SetRowsEnabled(context, false, false, false);
      status = mq.qp.Solve();
      (*next)[slot(kCopDropped)] += 1.0;
    }
    if (status == QpStatus::kOptimal) StorePlannedForces(mq.rows, s, s.last_mode);
  }
  (*next)[slot(kStatus)] = static_cast<double>(status);
  if (status != QpStatus::kOptimal) {
    mq.prev_valid = false;
    (*next)[slot(kHeld)] += 1.0;
    if (status == QpStatus::kInvalidInput) (*next)[slot(kFailures)] += 1.0;
    return EventStatus::Succeeded();  // hold the previous u
  }
  const Eigen::VectorXd& x = mq.qp.x();
  // CLF activity: δ > 0, or the CLF row (row 0, normalised) within clf_active_tolerance of its bound.
  (*next)[slot(kSolved)] += 1.0;
  // (At η = 0 the row is 0 ≤ δ, met with equality by every u: not counted.)
  const bool clf_row = mq.o1 + mq.o2 > 0 && mq.eta.squaredNorm() > 0.0;
  if (clf_row && (x[mq.delta] > 0.0 || mq.qp.u[0] - mq.qp.A.row(0).dot(x) <= params_.clf_active_tolerance))
    (*next)[slot(kClfActive)] += 1.0;
  next->segment(u_offset(), nu) = x.head(nu);
  mq.F_prev = mq.F;  // the applied u's planned forces, for the next update's hold drift
  mq.t_prev = context.time();
  mq.prev_valid = true;
  (*next)[slot(kDelta)] = x[mq.delta] / std::sqrt(params_.relaxation_weight);
  (*next)[slot(kV)] = mq.eta.size() > 0 ? mq.eta.dot(mq.Peta) : 0.0;
  auto forces = next->segment(forces_offset(), 3 * nc);
  forces.setZero();
  const auto q = EvalInput(context, state_port_).head(model_->nq());
  for (const ContactWrenchConstraints& cw : mq.wrench)
    forces.segment<3>(3 * cw.contact()) =
        ExtractContactWrench(*model_, s.ws, q, mq.active, mq.F.head(std::max(mq.rows, 1)), cw.contact()).force;
  return EventStatus::Succeeded();
}

ClfQpDiagnostics ClfQpController::diagnostics(const LeafContext& context) const {
  const Eigen::VectorXd& xd = context.discrete_state();
  auto count = [&](DiagnosticsSlot k) { return static_cast<int>(xd[slot(k)]); };  // whole numbers, stored as doubles
  ClfQpDiagnostics d;
  d.V = xd[slot(kV)];
  d.delta = xd[slot(kDelta)];
  d.qp_failures = count(kFailures);
  if (xd[slot(kStatus)] >= 0.0) d.qp_status = static_cast<QpStatus>(count(kStatus));
  d.drift_dropped = count(kDriftDropped);
  d.band_dropped = count(kBandDropped);
  d.cop_dropped = count(kCopDropped);
  d.held = count(kHeld);
  d.clf_active = count(kClfActive);
  d.solved = count(kSolved);
  d.solve_time_s = xd[slot(kSolveTime)];
  return d;
}

const DenseQpSolver& ClfQpController::last_qp(const LeafContext& context) const {
  const Scratch& s = context.scratch<Scratch>();
  return s.modes[s.last_mode].qp;
}
int ClfQpController::last_mode(const LeafContext& context) const { return context.scratch<Scratch>().last_mode; }
const Eigen::VectorXd& ClfQpController::last_eta(const LeafContext& context) const {
  const Scratch& s = context.scratch<Scratch>();
  return s.modes[s.last_mode].eta;
}
Eigen::Ref<const Eigen::MatrixXd> ClfQpController::last_output_matrix(const LeafContext& context) const {
  const Scratch& s = context.scratch<Scratch>();
  return s.modes[s.last_mode].Aout;
}
Eigen::Ref<const Eigen::VectorXd> ClfQpController::last_output_drift(const LeafContext& context) const {
  const Scratch& s = context.scratch<Scratch>();
  return s.modes[s.last_mode].Lf;
}
Eigen::Ref<const Eigen::VectorXd> ClfQpController::last_constraint_forces(const LeafContext& context) const {
  const Scratch& s = context.scratch<Scratch>();
  const auto& mq = s.modes[s.last_mode];
  return mq.F.head(mq.rows);
}

}  // namespace rome
