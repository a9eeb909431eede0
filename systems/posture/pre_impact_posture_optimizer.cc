#include "systems/posture/pre_impact_posture_optimizer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"

namespace rome {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kBase = 2;  // planar base translation [x, z] is not a variable

double Pitch(const Eigen::Matrix3d& R) { return std::atan2(R(0, 2), R(0, 0)); }

std::string RequestText(const PreImpactPostureRequest& r) {
  std::ostringstream os;
  os << "pre-impact posture for the step (l = " << r.step_length_m << " m, h = " << r.step_height_m << " m) of '"
     << r.swing_contact << "' from stance '" << r.stance_contact << "'";
  return os.str();
}

int CountFlatContacts(const MultibodyModel& model, const PreImpactPostureRequest& r) {
  int n = 0;
  for (const std::string& c : {r.swing_contact, r.stance_contact})
    if (model.contacts()[model.ContactIndex(c)].type != ContactType::kPoint) ++n;
  return n;
}

void ValidateRequest(const MultibodyModel& model, const PreImpactPostureRequest& r) {
  if (!model.is_planar())
    throw std::invalid_argument("PreImpactPostureOptimizer: robot '" + model.name() + "' has a " +
                                ToString(model.floating_base()) +
                                " floating base; Eq. (21) is implemented for planar models");
  for (const std::string* c : {&r.stance_contact, &r.swing_contact})
    if (!model.num_contacts() || [&] {
          for (const auto& info : model.contacts())
            if (info.name == *c) return false;
          return true;
        }())
      throw std::invalid_argument("PreImpactPostureOptimizer: robot '" + model.name() + "' has no contact named '" +
                                  *c + "'");
  if (r.stance_contact == r.swing_contact)
    throw std::invalid_argument("PreImpactPostureOptimizer: stance and swing contact are both '" + r.stance_contact +
                                "'");
  if (!std::isfinite(r.step_length_m) || !std::isfinite(r.step_height_m) || !r.stance_foot_position.allFinite())
    throw std::invalid_argument("PreImpactPostureOptimizer: " + RequestText(r) +
                                " has a non-finite step or stance position");
}
}  // namespace

// ---------------------------------------------------------------------------------------------------------
// The NLP

PreImpactPostureProblem::PreImpactPostureProblem(const MultibodyModel& model, const PreImpactPostureParams& params,
                                                 const PreImpactPostureRequest& request)
    : NlpProblem("pre_impact_posture", model.nv() - kBase,
                 3 + model.num_loop_closures() + CountFlatContacts(model, request)),
      model_(model),
      params_(params),
      request_(request),
      ws_(model) {
  ValidateRequest(model, request);
  stance_ = model.ContactIndex(request.stance_contact);
  swing_ = model.ContactIndex(request.swing_contact);
  com_x_target_ = std::isnan(request.com_x_m) ? params.com_x_fraction * request.step_length_m : request.com_x_m;
  const int nv = model.nv(), n = num_variables(), m = num_constraints();
  q_nominal_ = model.q_nominal();
  for (int c : {swing_, stance_})
    if (model.contacts()[c].type != ContactType::kPoint) {
      ws_.SetPositions(model, q_nominal_);
      flat_contacts_.push_back(c);
      flat_pitch_.push_back(Pitch(ws_.R_world_link(model.contacts()[c].body)));
    }
  q_ = q_nominal_;
  g_.setZero(m);
  G_.setZero(m, n);
  cost_gradient_.setZero(n);
  J3_.setZero(3, nv);
  J6_.setZero(6, nv);

  // Bounds: joint limits on the joints; the base pitch is free.
  Eigen::VectorXd lower = model.position_lower_limits().tail(n), upper = model.position_upper_limits().tail(n);
  lower[0] = -kInf;
  upper[0] = kInf;
  SetVariableBounds(lower, upper);
  Eigen::VectorXd gl = Eigen::VectorXd::Zero(m), gu = Eigen::VectorXd::Zero(m);
  gl[0] = gu[0] = request.step_length_m;
  gl[1] = gu[1] = request.step_height_m;
  // The minimum COM height is measured from the lower of the two feet (stepping down, the COM may be less than
  // p_com^{z,min} above the stance foot: the landing leg is below it).
  gl[2] = params.min_com_height_m + std::min(request.step_height_m, 0.0);
  gu[2] = kInf;
  SetConstraintBounds(gl, gu);
  SparsityPattern pattern;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < n; ++j) pattern.Add(i, j);
  SetConstraintJacobianSparsity(std::move(pattern));
  SparsityPattern hessian;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) hessian.Add(i, j);
  SetLagrangianHessianSparsity(std::move(hessian));
}

Eigen::VectorXd PreImpactPostureProblem::FromConfiguration(const Eigen::VectorXd& q) const {
  return q.tail(num_variables());
}

Eigen::VectorXd PreImpactPostureProblem::ToConfiguration(const Eigen::Ref<const Eigen::VectorXd>& x) {
  Eigen::VectorXd q(model_.nv());
  q << 0.0, 0.0, x;
  const ContactInfo& st = model_.contacts()[stance_];
  const Eigen::Vector3d p = CalcPointPosition(model_, ws_, q, st.body, st.frame_origin);
  // The base translation is along world x and z, so shifting it moves the stance foot by the same amount.
  q[0] = request_.stance_foot_position.x() - p.x();
  q[1] = request_.stance_foot_position.y() - p.z();
  return q;
}

void PreImpactPostureProblem::Evaluate(const Eigen::Ref<const Eigen::VectorXd>& x) {
  if (cached_ && x == cached_x_) return;
  const int nv = model_.nv(), n = num_variables();
  q_ << 0.0, 0.0, x;
  const ContactInfo& st = model_.contacts()[stance_];
  const ContactInfo& sw = model_.contacts()[swing_];
  const Eigen::Vector3d p_st = CalcPointPosition(model_, ws_, q_, st.body, st.frame_origin);
  const Eigen::Vector3d p_sw = CalcPointPosition(model_, ws_, q_, sw.body, sw.frame_origin);
  const Eigen::Vector3d com = CalcComPosition(model_, ws_, q_);
  Eigen::MatrixXd J_st(3, nv), J_sw(3, nv), J_com(3, nv);
  CalcPointJacobian(model_, ws_, q_, st.body, st.frame_origin, J_st);
  CalcPointJacobian(model_, ws_, q_, sw.body, sw.frame_origin, J_sw);
  CalcComJacobian(model_, ws_, q_, J_com);
  const auto vars = [&](const Eigen::MatrixXd& J, int row) { return J.row(row).tail(n); };

  // Constraints: stone (2), COM height (1), loop closures, flat feet.
  g_[0] = p_sw.x() - p_st.x();
  g_[1] = p_sw.z() - p_st.z();
  g_[2] = com.z() - p_st.z();
  G_.row(0) = vars(J_sw, 0) - vars(J_st, 0);
  G_.row(1) = vars(J_sw, 2) - vars(J_st, 2);
  G_.row(2) = vars(J_com, 2) - vars(J_st, 2);
  int row = 3;
  if (model_.num_loop_closures() > 0) {
    const int rows = CalcConstraintJacobian(model_, ws_, q_, Eigen::VectorXd::Zero(nv), ContactSet{0});
    g_.segment(row, rows) = ws_.phi.head(rows);
    G_.middleRows(row, rows) = ws_.J.topRows(rows).rightCols(n);
    row += rows;
  }
  for (size_t k = 0; k < flat_contacts_.size(); ++k) {
    const int body = model_.contacts()[flat_contacts_[k]].body;
    ws_.SetPositions(model_, q_);
    g_[row] = Pitch(ws_.R_world_link(body)) - flat_pitch_[k];
    CalcFrameJacobian(model_, ws_, q_, body, Eigen::Vector3d::Zero(), J6_);
    G_.row(row) = J6_.row(1).tail(n);  // ω_y
    ++row;
  }

  // Cost of Eq. (21) plus the optional COM-height and posture terms.
  const double e_x = com.x() - p_st.x() - com_x_target_;
  const double phi = q_[2];
  cost_ = params_.com_x_weight * e_x * e_x + params_.torso_pitch_weight * phi * phi;
  cost_gradient_ = 2.0 * params_.com_x_weight * e_x * (vars(J_com, 0) - vars(J_st, 0)).transpose();
  cost_gradient_[0] += 2.0 * params_.torso_pitch_weight * phi;
  if (params_.com_height_weight > 0.0 && !std::isnan(request_.com_height_m)) {
    const double e_z = com.z() - p_st.z() - request_.com_height_m;
    cost_ += params_.com_height_weight * e_z * e_z;
    cost_gradient_ += 2.0 * params_.com_height_weight * e_z * (vars(J_com, 2) - vars(J_st, 2)).transpose();
  }
  const auto dq = x.tail(n - 1) - q_nominal_.tail(n - 1);
  cost_ += params_.posture_weight * dq.squaredNorm();
  cost_gradient_.tail(n - 1) += 2.0 * params_.posture_weight * dq;
  cached_x_ = x;
  cached_ = true;
}

double PreImpactPostureProblem::EvalCost(const Eigen::Ref<const Eigen::VectorXd>& x) {
  Evaluate(x);
  return cost_;
}

void PreImpactPostureProblem::EvalCostGradient(const Eigen::Ref<const Eigen::VectorXd>& x,
                                               Eigen::Ref<Eigen::VectorXd> gradient) {
  Evaluate(x);
  gradient = cost_gradient_;
}

void PreImpactPostureProblem::EvalConstraints(const Eigen::Ref<const Eigen::VectorXd>& x,
                                              Eigen::Ref<Eigen::VectorXd> g) {
  Evaluate(x);
  g = g_;
}

void PreImpactPostureProblem::EvalConstraintJacobian(const Eigen::Ref<const Eigen::VectorXd>& x,
                                                     Eigen::Ref<Eigen::VectorXd> values) {
  Evaluate(x);
  int k = 0;
  for (int i = 0; i < G_.rows(); ++i)
    for (int j = 0; j < G_.cols(); ++j) values[k++] = G_(i, j);
}

void PreImpactPostureProblem::EvalLagrangianHessian(const Eigen::Ref<const Eigen::VectorXd>& x, double cost_factor,
                                                    const Eigen::Ref<const Eigen::VectorXd>& lambda,
                                                    Eigen::Ref<Eigen::VectorXd> values) {
  // Central differences of the analytic gradient ∇L = σ∇f + Gᵀλ (n = nv − 2 = 5 for AMBER: 10 gradient
  // evaluations of about a microsecond each). Cuts Ipopt's iterations by about half against L-BFGS.
  const int n = num_variables();
  const double step = params_.hessian_difference_step;
  Eigen::MatrixXd H(n, n);
  Eigen::VectorXd xp = x, grad_plus(n);
  for (int j = 0; j < n; ++j) {
    xp[j] = x[j] + step;
    Evaluate(xp);
    grad_plus = cost_factor * cost_gradient_ + G_.transpose() * lambda;
    xp[j] = x[j] - step;
    Evaluate(xp);
    H.col(j) = (grad_plus - cost_factor * cost_gradient_ - G_.transpose() * lambda) / (2.0 * step);
    xp[j] = x[j];
  }
  int k = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) values[k++] = 0.5 * (H(i, j) + H(j, i));
}

// ---------------------------------------------------------------------------------------------------------
// The optimizer

PreImpactPostureOptimizer::PreImpactPostureOptimizer(std::shared_ptr<const MultibodyModel> model,
                                                     PreImpactPostureParams params)
    : model_(std::move(model)), params_(std::move(params)), solver_(params_.ipopt) {
  if (!model_) throw std::invalid_argument("PreImpactPostureOptimizer: null MultibodyModel");
  if (!model_->is_planar())
    throw std::invalid_argument("PreImpactPostureOptimizer: robot '" + model_->name() + "' has a " +
                                ToString(model_->floating_base()) +
                                " floating base; Eq. (21) is implemented for planar models");
  auto check = [](double value, const char* what) {
    if (!(value >= 0.0) || !std::isfinite(value))
      throw std::invalid_argument(std::string("PreImpactPostureParams::") + what + " = " + std::to_string(value) +
                                  " must be finite and >= 0");
  };
  check(params_.com_x_weight, "com_x_weight");
  check(params_.torso_pitch_weight, "torso_pitch_weight");
  check(params_.com_height_weight, "com_height_weight");
  check(params_.posture_weight, "posture_weight");
  if (!std::isfinite(params_.min_com_height_m) || !std::isfinite(params_.com_x_fraction))
    throw std::invalid_argument("PreImpactPostureParams: min_com_height_m and com_x_fraction must be finite");
  previous_.resize(model_->num_contacts());
  previous_multipliers_.resize(model_->num_contacts());
}

void PreImpactPostureOptimizer::Reset() {
  for (auto& p : previous_) p.resize(0);
  for (auto& m : previous_multipliers_) m = NlpMultipliers{};
}

PreImpactPosture PreImpactPostureOptimizer::Describe(PreImpactPostureProblem& problem,
                                                     const PreImpactPostureRequest& request,
                                                     const Eigen::VectorXd& x) const {
  PreImpactPosture out;
  out.q = problem.ToConfiguration(x);
  Eigen::VectorXd g(problem.num_constraints());
  problem.EvalConstraints(x, g);
  out.cost = problem.EvalCost(x);
  out.torso_pitch_rad = out.q[2];
  out.swing_foot = g.head<2>();
  out.com_height_m = g[2];
  MultibodyWorkspace ws(*model_);
  out.com_x_m = CalcComPosition(*model_, ws, out.q).x() - request.stance_foot_position.x();
  return out;
}

PreImpactPosture PreImpactPostureOptimizer::Solve(const PreImpactPostureRequest& request) {
  ValidateRequest(*model_, request);
  PreImpactPostureProblem problem(*model_, params_, request);
  const int stance = model_->ContactIndex(request.stance_contact);
  const Eigen::VectorXd x0 =
      previous_[stance].size() > 0 ? previous_[stance] : problem.FromConfiguration(model_->q_nominal());
  const bool warm =
      previous_[stance].size() > 0 && previous_multipliers_[stance].constraints.size() == problem.num_constraints();
  NlpResult result = solver_.Solve(problem, x0, warm ? &previous_multipliers_[stance] : nullptr);
  if (!result.success() && previous_[stance].size() > 0) {
    // A warm start from a very different step can lead Ipopt to a point of local infeasibility: retry once from
    // the nominal pose before declaring the step infeasible.
    NlpResult cold = solver_.Solve(problem, problem.FromConfiguration(model_->q_nominal()));
    cold.wall_time += result.wall_time;
    cold.iterations += result.iterations;
    result = std::move(cold);
  }

  // Ipopt's verdict, double-checked against the constraints (a "solved" point must satisfy them).
  bool success = result.success();
  double violation = 0.0;
  if (success) {
    Eigen::VectorXd g(problem.num_constraints());
    problem.EvalConstraints(result.x, g);
    violation = (problem.constraint_lower_bounds() - g)
                    .cwiseMax(g - problem.constraint_upper_bounds())
                    .cwiseMax(0.0)
                    .maxCoeff();
    if (violation > 1e-6) success = false;
  }

  PreImpactPosture out;
  std::ostringstream msg;
  msg << RequestText(request) << ": ";
  if (success) {
    previous_[stance] = result.x;
    previous_multipliers_[stance] = result.multipliers;
    out = Describe(problem, request, result.x);
    msg << "solved (" << ToString(result.status) << ", " << result.iterations << " iterations, "
        << result.wall_time * 1e3 << " ms)";
  } else {
    const bool have_previous = previous_[stance].size() > 0;
    out =
        Describe(problem, request, have_previous ? previous_[stance] : problem.FromConfiguration(model_->q_nominal()));
    out.fallback =
        have_previous ? PreImpactPosture::Fallback::kPreviousSolution : PreImpactPosture::Fallback::kNominalPose;
    msg << "FAILED: "
        << (result.status == NlpStatus::kInfeasible
                ? "infeasible (stone out of reach or COM height/joint limits unattainable)"
                : ToString(result.status));
    if (violation > 1e-6) msg << ", constraint violation " << violation;
    msg << "; Ipopt: " << result.message << "; falling back to "
        << (have_previous ? "the previous solution for this stance" : "the nominal pose");
  }
  out.success = success;
  out.status = result.status;
  out.iterations = result.iterations;
  out.solve_time_s = result.wall_time;
  out.message = msg.str();
  return out;
}

}  // namespace rome
