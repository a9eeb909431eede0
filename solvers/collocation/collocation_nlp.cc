// CollocationNlp: the NlpProblem of a DirectCollocation problem (collocation_nlp.h): defects, transitions, path and
// node constraints, cost, their sparse Jacobian and the Lagrangian Hessian.

#include "solvers/collocation/collocation_nlp.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace rome::collocation_internal {
namespace {

// Writes dense blocks of the constraint Jacobian either as a pattern or as values, so the two
// can never disagree.
class JacobianWriter {
 public:
  explicit JacobianWriter(SparsityPattern* pattern) : pattern_(pattern) {}
  explicit JacobianWriter(Eigen::VectorXd* values) : values_(values) {}
  void Block(int row0, int col0, const Eigen::MatrixXd& M) {
    for (Eigen::Index j = 0; j < M.cols(); ++j) {
      for (Eigen::Index i = 0; i < M.rows(); ++i) Put(row0 + static_cast<int>(i), col0 + static_cast<int>(j), M(i, j));
    }
  }
  int count() const { return next_; }

 private:
  void Put(int row, int col, double value) {
    if (pattern_ != nullptr) {
      pattern_->Add(row, col);
    } else {
      (*values_)(next_) = value;
    }
    ++next_;
  }
  SparsityPattern* pattern_ = nullptr;
  Eigen::VectorXd* values_ = nullptr;
  int next_ = 0;
};

void EvalScalar(const ScalarStateInputFunction& F, const Eigen::VectorXd& x, const Eigen::VectorXd& u, double* value,
                Eigen::VectorXd* gradient) {
  const int nd = static_cast<int>(x.size() + u.size());
  const NodeScalar y =
      F(InitializeAutoDiff<NodeScalar>(x, nd, 0), InitializeAutoDiff<NodeScalar>(u, nd, static_cast<int>(x.size())));
  *value = y.value();
  *gradient = y.derivatives().size() == nd ? Eigen::VectorXd(y.derivatives()) : Eigen::VectorXd::Zero(nd);
}

}  // namespace

// Evaluates y = F(x, u) and ∂y/∂[x; u] with AutoDiff, checking the output size.
void EvalWithJacobian(const StateInputFunction& F, int expected_size, const Eigen::VectorXd& x,
                      const Eigen::VectorXd& u, const std::string& what, Eigen::VectorXd* value,
                      Eigen::MatrixXd* jacobian) {
  const int nd = static_cast<int>(x.size() + u.size());
  const NodeVector xa = InitializeAutoDiff<NodeScalar>(x, nd, 0);
  const NodeVector ua = InitializeAutoDiff<NodeScalar>(u, nd, static_cast<int>(x.size()));
  NodeVector y;
  F(xa, ua, y);
  if (y.size() != expected_size) {
    std::ostringstream msg;
    msg << what << " returned " << y.size() << " values, expected " << expected_size;
    throw std::runtime_error(msg.str());
  }
  *value = ExtractValue(y);
  *jacobian = ExtractJacobian(y, nd);
}

namespace {

class CollocationNlp final : public NlpProblem {
 public:
  CollocationNlp(const std::string& name, const std::vector<CollocationPhase>& phases,
                 const std::vector<PhaseLayout>& layout, int num_variables, int num_constraints,
                 const std::vector<DirectCollocation::NodeConstraint>& constraints,
                 const std::vector<StateFunction>& transitions, const StateFunction& periodic_transition,
                 const ScalarStateInputFunction& terminal_cost, const Eigen::VectorXd& z_probe, bool exact_hessian)
      : NlpProblem(name, num_variables, num_constraints),
        phases_(phases),
        layout_(layout),
        constraints_(constraints),
        transitions_(transitions),
        periodic_transition_(periodic_transition),
        terminal_cost_(terminal_cost) {
    SparsityPattern pattern;
    JacobianWriter writer(&pattern);
    Eigen::VectorXd g(num_constraints);
    EvaluateConstraints(z_probe, g, writer);
    SetConstraintJacobianSparsity(std::move(pattern));
    jacobian_values_.resize(writer.count());
    g_values_.resize(num_constraints);
    gradient_.resize(num_variables);
    if (exact_hessian) DeclareHessian();
  }

  // Hessian of the Lagrangian σ f + λᵀ g. Every nonlinear term of the NLP depends on the (x_k, u_k) of one node
  // (and the phase duration), so the Hessian is block diagonal over nodes plus the duration rows:
  //   node block  Σ of λ-weighted second derivatives of the dynamics (weight −(h/2)(λ_{k−1} + λ_k) of the two
  //               adjacent defects), path/node constraints, resets, running cost (σ h c_k) and terminal cost;
  //               each is the forward difference of the exact AutoDiff gradient of λᵀF (step √ε max(1, |z_j|)),
  //               symmetrised;
  //   (T, node)   exact: −(1/(2(N−1))) ∂f_kᵀ(λ_{k−1} + λ_k) + σ c_k/(N−1) ∇L_k (h = T/(N−1) enters linearly).
  void EvalLagrangianHessian(const Eigen::Ref<const Eigen::VectorXd>& z, double sigma,
                             const Eigen::Ref<const Eigen::VectorXd>& lambda,
                             Eigen::Ref<Eigen::VectorXd> values) override {
    const Eigen::VectorXd zz = z;
    int next = 0;
    for (size_t p = 0; p < phases_.size(); ++p) {
      const CollocationPhase& phase = phases_[p];
      const PhaseLayout& L = layout_[p];
      const int n = L.nx + L.nu;
      const double T = Duration(L, zz);
      const double h = T / (L.N - 1);
      for (int k = 0; k < L.N; ++k) {
        const Eigen::VectorXd xk = zz.segment(L.x(k), L.nx), uk = zz.segment(L.u(k), L.nu);
        Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
        Eigen::VectorXd hT = Eigen::VectorXd::Zero(n);
        // Dynamics through the adjacent defects.
        Eigen::VectorXd mu = Eigen::VectorXd::Zero(L.nx);
        if (k > 0) mu += lambda.segment(L.defect_row + (k - 1) * L.nx, L.nx);
        if (k + 1 < L.N) mu += lambda.segment(L.defect_row + k * L.nx, L.nx);
        if (mu.cwiseAbs().maxCoeff() > 0) {
          AddWeightedHessian(phase.dynamics, L.nx, xk, uk, -0.5 * h * mu, &H);
          if (L.T_index >= 0) {
            Eigen::VectorXd f;
            Eigen::MatrixXd J;
            EvalWithJacobian(phase.dynamics, L.nx, xk, uk, "dynamics", &f, &J);
            hT -= J.transpose() * mu / (2.0 * (L.N - 1));
          }
        }
        // Running cost with trapezoid weights.
        if (phase.running_cost && sigma != 0.0) {
          const double c = (k == 0 || k == L.N - 1) ? 0.5 : 1.0;
          AddScalarHessian(phase.running_cost, xk, uk, sigma * c * h, &H);
          if (L.T_index >= 0) {
            double value;
            Eigen::VectorXd grad;
            EvalScalar(phase.running_cost, xk, uk, &value, &grad);
            hT += sigma * c / (L.N - 1) * grad;
          }
        }
        // Path and node constraints at this node.
        for (size_t ci = 0; ci < constraints_.size(); ++ci) {
          const auto& c = constraints_[ci];
          if (static_cast<size_t>(c.phase) != p) continue;
          int row = -1;
          if (c.node == kEveryNode) {
            row = constraint_rows_[ci] + k * c.size;
          } else if (c.node == k) {
            row = constraint_rows_[ci];
          }
          if (row < 0) continue;
          AddWeightedHessian(c.function, c.size, xk, uk, lambda.segment(row, c.size), &H);
        }
        if (k == L.N - 1) {
          // Resets out of this phase act on its last state: rows x_0^{next} − Δ(x) carry −Δ.
          if (p + 1 < phases_.size() && transitions_[p]) {
            AddResetHessian(transitions_[p], xk, -lambda.segment(transition_rows_[p], layout_[p + 1].nx), &H);
          }
          if (p + 1 == phases_.size() && periodic_transition_) {
            AddResetHessian(periodic_transition_, xk, -lambda.segment(periodic_row_, layout_.front().nx), &H);
          }
          if (p + 1 == phases_.size() && terminal_cost_ && sigma != 0.0) {
            AddScalarHessian(terminal_cost_, xk, uk, sigma, &H);
          }
        }
        // Write the lower triangle in the pattern's order (see DeclareHessian).
        const std::vector<int> idx = NodeVariables(L, k);
        for (int a = 0; a < n; ++a) {
          for (int b = 0; b <= a; ++b) values(next++) = 0.5 * (H(a, b) + H(b, a));
        }
        if (L.T_index >= 0) {
          for (int a = 0; a < n; ++a) values(next++) = hT(a);
        }
      }
    }
  }

  double EvalCost(const Eigen::Ref<const Eigen::VectorXd>& z) override {
    UpdateCost(z);
    return cost_;
  }
  void EvalCostGradient(const Eigen::Ref<const Eigen::VectorXd>& z, Eigen::Ref<Eigen::VectorXd> gradient) override {
    UpdateCost(z);
    gradient = gradient_;
  }
  void EvalConstraints(const Eigen::Ref<const Eigen::VectorXd>& z, Eigen::Ref<Eigen::VectorXd> g) override {
    UpdateConstraints(z);
    g = g_values_;
  }
  void EvalConstraintJacobian(const Eigen::Ref<const Eigen::VectorXd>& z, Eigen::Ref<Eigen::VectorXd> values) override {
    UpdateConstraints(z);
    values = jacobian_values_;
  }

 private:
  double Duration(const PhaseLayout& L, const Eigen::VectorXd& z) const {
    return L.T_index >= 0 ? z(L.T_index) : L.fixed_T;
  }

  void UpdateCost(const Eigen::Ref<const Eigen::VectorXd>& z) {
    if (cost_z_.size() == z.size() && cost_z_ == z) return;
    cost_ = 0.0;
    gradient_.setZero();
    double value = 0.0;
    Eigen::VectorXd grad;
    for (size_t p = 0; p < phases_.size(); ++p) {
      const CollocationPhase& phase = phases_[p];
      const PhaseLayout& L = layout_[p];
      const double T = Duration(L, z);
      const double h = T / (L.N - 1);
      if (phase.running_cost) {
        for (int k = 0; k < L.N; ++k) {
          const double c = (k == 0 || k == L.N - 1) ? 0.5 : 1.0;  // trapezoid weights
          EvalScalar(phase.running_cost, z.segment(L.x(k), L.nx), z.segment(L.u(k), L.nu), &value, &grad);
          cost_ += c * h * value;
          gradient_.segment(L.x(k), L.nx) += c * h * grad.head(L.nx);
          gradient_.segment(L.u(k), L.nu) += c * h * grad.tail(L.nu);
          if (L.T_index >= 0) gradient_(L.T_index) += c / (L.N - 1) * value;
        }
      }
      if (L.T_index >= 0) {
        cost_ += phase.duration_cost * T;
        gradient_(L.T_index) += phase.duration_cost;
      }
    }
    if (terminal_cost_) {
      const PhaseLayout& L = layout_.back();
      EvalScalar(terminal_cost_, z.segment(L.x(L.N - 1), L.nx), z.segment(L.u(L.N - 1), L.nu), &value, &grad);
      cost_ += value;
      gradient_.segment(L.x(L.N - 1), L.nx) += grad.head(L.nx);
      gradient_.segment(L.u(L.N - 1), L.nu) += grad.tail(L.nu);
    }
    cost_z_ = z;
  }

  static std::vector<int> NodeVariables(const PhaseLayout& L, int k) {
    std::vector<int> idx;
    for (int i = 0; i < L.nx; ++i) idx.push_back(L.x(k) + i);
    for (int i = 0; i < L.nu; ++i) idx.push_back(L.u(k) + i);
    return idx;
  }

  void DeclareHessian() {
    // Rows of the transition, periodic and path/node constraints, in EvaluateConstraints' order.
    int row = 0;
    for (const auto& L : layout_) row += (L.N - 1) * L.nx;
    transition_rows_.assign(phases_.size(), -1);
    for (size_t p = 0; p + 1 < phases_.size(); ++p) {
      transition_rows_[p] = row;
      row += layout_[p + 1].nx;
    }
    if (periodic_transition_) {
      periodic_row_ = row;
      row += layout_.front().nx;
    }
    for (const auto& c : constraints_) {
      constraint_rows_.push_back(row);
      row += c.node == kEveryNode ? layout_[c.phase].N * c.size : c.size;
    }
    SparsityPattern pattern;
    for (const auto& L : layout_) {
      for (int k = 0; k < L.N; ++k) {
        const std::vector<int> idx = NodeVariables(L, k);
        const int n = static_cast<int>(idx.size());
        for (int a = 0; a < n; ++a) {
          for (int b = 0; b <= a; ++b) pattern.Add(std::max(idx[a], idx[b]), std::min(idx[a], idx[b]));
        }
        if (L.T_index >= 0) {
          for (int a = 0; a < n; ++a) pattern.Add(L.T_index, idx[a]);  // T comes after the phase's nodes
        }
      }
    }
    SetLagrangianHessianSparsity(std::move(pattern));
  }

  static double FdStep(double v) { return 1.5e-8 * std::max(1.0, std::abs(v)); }

  // H += ∇²(wᵀF)(x, u) by forward differences of the exact gradient Jᵀw.
  static void AddWeightedHessian(const StateInputFunction& F, int size, const Eigen::VectorXd& x,
                                 const Eigen::VectorXd& u, const Eigen::VectorXd& w, Eigen::MatrixXd* H) {
    if (w.cwiseAbs().maxCoeff() == 0.0) return;
    const int nx = static_cast<int>(x.size()), n = nx + static_cast<int>(u.size());
    Eigen::VectorXd f;
    Eigen::MatrixXd J;
    EvalWithJacobian(F, size, x, u, "Hessian", &f, &J);
    const Eigen::VectorXd g0 = J.transpose() * w;
    for (int j = 0; j < n; ++j) {
      Eigen::VectorXd xp = x, up = u;
      double& v = j < nx ? xp(j) : up(j - nx);
      const double step = FdStep(v);
      v += step;
      EvalWithJacobian(F, size, xp, up, "Hessian", &f, &J);
      H->col(j) += (J.transpose() * w - g0) / step;
    }
  }
  static void AddScalarHessian(const ScalarStateInputFunction& F, const Eigen::VectorXd& x, const Eigen::VectorXd& u,
                               double weight, Eigen::MatrixXd* H) {
    const int nx = static_cast<int>(x.size()), n = nx + static_cast<int>(u.size());
    double value;
    Eigen::VectorXd g0, g;
    EvalScalar(F, x, u, &value, &g0);
    for (int j = 0; j < n; ++j) {
      Eigen::VectorXd xp = x, up = u;
      double& v = j < nx ? xp(j) : up(j - nx);
      const double step = FdStep(v);
      v += step;
      EvalScalar(F, xp, up, &value, &g);
      H->col(j) += weight * (g - g0) / step;
    }
  }
  static void AddResetHessian(const StateFunction& F, const Eigen::VectorXd& x, const Eigen::VectorXd& w,
                              Eigen::MatrixXd* H) {
    if (w.cwiseAbs().maxCoeff() == 0.0) return;
    const int nx = static_cast<int>(x.size());
    auto gradient = [&](const Eigen::VectorXd& xx) {
      NodeVector y;
      F(InitializeAutoDiff<NodeScalar>(xx), y);
      return Eigen::VectorXd(ExtractJacobian(y, nx).transpose() * w);
    };
    const Eigen::VectorXd g0 = gradient(x);
    for (int j = 0; j < nx; ++j) {
      Eigen::VectorXd xp = x;
      const double step = FdStep(xp(j));
      xp(j) += step;
      H->col(j).head(nx) += (gradient(xp) - g0) / step;
    }
  }

  void UpdateConstraints(const Eigen::Ref<const Eigen::VectorXd>& z) {
    if (constraint_z_.size() == z.size() && constraint_z_ == z) return;
    JacobianWriter writer(&jacobian_values_);
    EvaluateConstraints(z, g_values_, writer);
    constraint_z_ = z;
  }

  void EvaluateConstraints(const Eigen::VectorXd& z, Eigen::VectorXd& g, JacobianWriter& writer) {
    // Defects, x_{k+1} − x_k − (h/2)(f_k + f_{k+1}) = 0 (trapezoid) or the Hermite–Simpson form.
    Eigen::VectorXd f_k, f_next, f_c, value;
    Eigen::MatrixXd J_k, J_next, J_c, J;
    int row = 0;
    for (size_t p = 0; p < phases_.size(); ++p) {
      const CollocationPhase& phase = phases_[p];
      const PhaseLayout& L = layout_[p];
      const double T = Duration(L, z);
      const double h = T / (L.N - 1);
      const std::string what = "dynamics of phase '" + phase.name + "'";
      const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(L.nx, L.nx);
      EvalWithJacobian(phase.dynamics, L.nx, z.segment(L.x(0), L.nx), z.segment(L.u(0), L.nu), what, &f_k, &J_k);
      for (int k = 0; k + 1 < L.N; ++k) {
        EvalWithJacobian(phase.dynamics, L.nx, z.segment(L.x(k + 1), L.nx), z.segment(L.u(k + 1), L.nu), what, &f_next,
                         &J_next);
        if (phase.method == CollocationMethod::kHermiteSimpson) {
          // x_c = (x_k + x_{k+1})/2 + (h/8)(f_k − f_{k+1}), u_c = (u_k + u_{k+1})/2,
          // defect x_{k+1} − x_k − (h/6)(f_k + 4 f(x_c, u_c) + f_{k+1}).
          const Eigen::VectorXd x_c =
              0.5 * (z.segment(L.x(k), L.nx) + z.segment(L.x(k + 1), L.nx)) + (h / 8.0) * (f_k - f_next);
          const Eigen::VectorXd u_c = 0.5 * (z.segment(L.u(k), L.nu) + z.segment(L.u(k + 1), L.nu));
          EvalWithJacobian(phase.dynamics, L.nx, x_c, u_c, what, &f_c, &J_c);
          const Eigen::MatrixXd Jcx = J_c.leftCols(L.nx);
          g.segment(row, L.nx) =
              z.segment(L.x(k + 1), L.nx) - z.segment(L.x(k), L.nx) - (h / 6.0) * (f_k + 4.0 * f_c + f_next);
          writer.Block(row, L.x(k),
                       -I - (h / 6.0) * (J_k.leftCols(L.nx) + 4.0 * Jcx * (0.5 * I + (h / 8.0) * J_k.leftCols(L.nx))));
          if (L.nu > 0) {
            writer.Block(row, L.u(k),
                         -(h / 6.0) * (J_k.rightCols(L.nu) +
                                       4.0 * (Jcx * ((h / 8.0) * J_k.rightCols(L.nu)) + 0.5 * J_c.rightCols(L.nu))));
          }
          writer.Block(
              row, L.x(k + 1),
              I - (h / 6.0) * (J_next.leftCols(L.nx) + 4.0 * Jcx * (0.5 * I - (h / 8.0) * J_next.leftCols(L.nx))));
          if (L.nu > 0) {
            writer.Block(row, L.u(k + 1),
                         -(h / 6.0) * (J_next.rightCols(L.nu) + 4.0 * (Jcx * (-(h / 8.0) * J_next.rightCols(L.nu)) +
                                                                       0.5 * J_c.rightCols(L.nu))));
          }
          if (L.T_index >= 0) {
            const double dh = 1.0 / (L.N - 1);  // ∂h/∂T
            writer.Block(
                row, L.T_index,
                -(dh / 6.0) * (f_k + 4.0 * f_c + f_next) - (h / 6.0) * 4.0 * Jcx * ((dh / 8.0) * (f_k - f_next)));
          }
        } else {
          g.segment(row, L.nx) = z.segment(L.x(k + 1), L.nx) - z.segment(L.x(k), L.nx) - 0.5 * h * (f_k + f_next);
          writer.Block(row, L.x(k), -I - 0.5 * h * J_k.leftCols(L.nx));
          if (L.nu > 0) writer.Block(row, L.u(k), -0.5 * h * J_k.rightCols(L.nu));
          writer.Block(row, L.x(k + 1), I - 0.5 * h * J_next.leftCols(L.nx));
          if (L.nu > 0) writer.Block(row, L.u(k + 1), -0.5 * h * J_next.rightCols(L.nu));
          if (L.T_index >= 0) writer.Block(row, L.T_index, -(f_k + f_next) / (2.0 * (L.N - 1)));
        }
        row += L.nx;
        f_k.swap(f_next);
        J_k.swap(J_next);
      }
    }
    // Transitions x_0^{p+1} − Δ(x_{N−1}^p) = 0.
    for (size_t p = 0; p + 1 < phases_.size(); ++p) {
      const PhaseLayout& A = layout_[p];
      const PhaseLayout& B = layout_[p + 1];
      const Eigen::VectorXd x_end = z.segment(A.x(A.N - 1), A.nx);
      if (transitions_[p]) {
        NodeVector y;
        transitions_[p](InitializeAutoDiff<NodeScalar>(x_end), y);
        if (y.size() != B.nx) {
          std::ostringstream msg;
          msg << "transition from phase '" << phases_[p].name << "' to '" << phases_[p + 1].name << "' returned "
              << y.size() << " values, expected " << B.nx;
          throw std::runtime_error(msg.str());
        }
        value = ExtractValue(y);
        J = ExtractJacobian(y, A.nx);
      } else {
        value = x_end;
        J = Eigen::MatrixXd::Identity(A.nx, A.nx);
      }
      g.segment(row, B.nx) = z.segment(B.x(0), B.nx) - value;
      writer.Block(row, B.x(0), Eigen::MatrixXd::Identity(B.nx, B.nx));
      writer.Block(row, A.x(A.N - 1), -J);
      row += B.nx;
    }
    // Periodicity x_0^0 − Δ(x_{N−1}^{P−1}) = 0.
    if (periodic_transition_) {
      const PhaseLayout& A = layout_.back();
      const PhaseLayout& B = layout_.front();
      NodeVector y;
      periodic_transition_(InitializeAutoDiff<NodeScalar>(z.segment(A.x(A.N - 1), A.nx)), y);
      if (y.size() != B.nx) {
        std::ostringstream msg;
        msg << "periodic transition from phase '" << phases_.back().name << "' to '" << phases_.front().name
            << "' returned " << y.size() << " values, expected " << B.nx;
        throw std::runtime_error(msg.str());
      }
      g.segment(row, B.nx) = z.segment(B.x(0), B.nx) - ExtractValue(y);
      writer.Block(row, B.x(0), Eigen::MatrixXd::Identity(B.nx, B.nx));
      writer.Block(row, A.x(A.N - 1), -ExtractJacobian(y, A.nx));
      row += B.nx;
    }
    // Path and node constraints.
    for (const auto& c : constraints_) {
      const PhaseLayout& L = layout_[c.phase];
      const int first = c.node == kEveryNode ? 0 : c.node;
      const int last = c.node == kEveryNode ? L.N - 1 : c.node;
      const std::string what = "constraint '" + c.name + "' of phase '" + phases_[c.phase].name + "'";
      for (int k = first; k <= last; ++k) {
        EvalWithJacobian(c.function, c.size, z.segment(L.x(k), L.nx), z.segment(L.u(k), L.nu), what, &value, &J);
        g.segment(row, c.size) = value;
        writer.Block(row, L.x(k), J.leftCols(L.nx));
        if (L.nu > 0) writer.Block(row, L.u(k), J.rightCols(L.nu));
        row += c.size;
      }
    }
  }

  std::vector<CollocationPhase> phases_;
  std::vector<PhaseLayout> layout_;
  std::vector<DirectCollocation::NodeConstraint> constraints_;
  std::vector<StateFunction> transitions_;
  StateFunction periodic_transition_;
  ScalarStateInputFunction terminal_cost_;
  std::vector<int> transition_rows_, constraint_rows_;
  int periodic_row_ = -1;
  Eigen::VectorXd cost_z_, constraint_z_;
  double cost_ = 0.0;
  Eigen::VectorXd gradient_, g_values_, jacobian_values_;
};

}  // namespace

std::vector<PhaseLayout> MakeLayout(const std::vector<CollocationPhase>& phases, int* num_variables) {
  std::vector<PhaseLayout> layout;
  int offset = 0, row = 0;
  for (const auto& phase : phases) {
    PhaseLayout L;
    L.nx = phase.num_states;
    L.nu = phase.num_inputs;
    L.N = phase.num_nodes;
    L.x_offset = offset;
    L.u_offset = offset + L.N * L.nx;
    offset = L.u_offset + L.N * L.nu;
    if (phase.max_duration > phase.min_duration) {
      L.T_index = offset++;
    } else {
      L.fixed_T = phase.min_duration;
    }
    L.defect_row = row;
    row += (L.N - 1) * L.nx;
    layout.push_back(L);
  }
  *num_variables = offset;
  return layout;
}

std::unique_ptr<NlpProblem> MakeCollocationNlp(
    const std::string& name, const std::vector<CollocationPhase>& phases, const std::vector<PhaseLayout>& layout,
    int num_variables, int num_constraints, const std::vector<DirectCollocation::NodeConstraint>& constraints,
    const std::vector<StateFunction>& transitions, const StateFunction& periodic_transition,
    const ScalarStateInputFunction& terminal_cost, const Eigen::VectorXd& z_probe, bool exact_hessian) {
  return std::make_unique<CollocationNlp>(name, phases, layout, num_variables, num_constraints, constraints,
                                          transitions, periodic_transition, terminal_cost, z_probe, exact_hessian);
}

}  // namespace rome::collocation_internal
