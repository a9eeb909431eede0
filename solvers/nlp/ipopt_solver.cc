#include "solvers/nlp/ipopt_solver.h"

#include <chrono>
#include <cmath>
#include <exception>
#include <sstream>
#include <stdexcept>

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>

namespace rome {

std::mutex& IpoptMutex() {
  static std::mutex mutex;
  return mutex;
}

const char* ToString(NlpStatus status) {
  switch (status) {
    case NlpStatus::kSolved: return "solved";
    case NlpStatus::kSolvedToAcceptableLevel: return "solved to acceptable level";
    case NlpStatus::kInfeasible: return "infeasible";
    case NlpStatus::kMaxIterations: return "maximum iterations reached";
    case NlpStatus::kMaxCpuTime: return "maximum CPU time reached";
    case NlpStatus::kDivergingIterates: return "diverging iterates";
    case NlpStatus::kRestorationFailed: return "restoration phase failed";
    case NlpStatus::kSearchDirectionTooSmall: return "search direction too small";
    case NlpStatus::kInvalidProblem: return "invalid problem";
    case NlpStatus::kError: return "error";
  }
  return "unknown";
}

namespace {

using Ipopt::Index;
using Ipopt::Number;

// Ipopt's view of an NlpProblem. Exceptions from the problem are captured and rethrown after
// the solve (Ipopt is C++ but must not unwind through MUMPS/Fortran frames).
class TnlpAdapter final : public Ipopt::TNLP {
 public:
  TnlpAdapter(NlpProblem& problem, const Eigen::VectorXd& x0, const NlpMultipliers* warm, NlpResult* result)
      : problem_(problem), x0_(x0), warm_(warm), result_(result) {}

  std::exception_ptr exception() const { return exception_; }
  int iterations() const { return iterations_; }

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& index_style) override {
    n = problem_.num_variables();
    m = problem_.num_constraints();
    nnz_jac_g = problem_.constraint_jacobian_sparsity().nnz();
    nnz_h_lag = problem_.has_lagrangian_hessian() ? problem_.lagrangian_hessian_sparsity().nnz() : 0;
    index_style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l, Number* g_u) override {
    // Ipopt treats |bound| ≥ 1e19 as infinite.
    auto clip = [](double v) { return std::isinf(v) ? (v > 0 ? 2e19 : -2e19) : v; };
    for (Index i = 0; i < n; ++i) {
      x_l[i] = clip(problem_.variable_lower_bounds()(i));
      x_u[i] = clip(problem_.variable_upper_bounds()(i));
    }
    for (Index i = 0; i < m; ++i) {
      g_l[i] = clip(problem_.constraint_lower_bounds()(i));
      g_u[i] = clip(problem_.constraint_upper_bounds()(i));
    }
    return true;
  }

  bool get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number* z_L, Number* z_U, Index m,
                          bool init_lambda, Number* lambda) override {
    if (init_x) Eigen::Map<Eigen::VectorXd>(x, n) = x0_;
    if (init_z) {
      if (warm_ == nullptr) return false;
      Eigen::Map<Eigen::VectorXd>(z_L, n) = warm_->lower_bounds;
      Eigen::Map<Eigen::VectorXd>(z_U, n) = warm_->upper_bounds;
    }
    if (init_lambda) {
      if (warm_ == nullptr) return false;
      Eigen::Map<Eigen::VectorXd>(lambda, m) = warm_->constraints;
    }
    return true;
  }

  bool eval_f(Index n, const Number* x, bool, Number& obj_value) override {
    return Guard([&] { obj_value = problem_.EvalCost(Eigen::Map<const Eigen::VectorXd>(x, n)); });
  }

  bool eval_grad_f(Index n, const Number* x, bool, Number* grad_f) override {
    return Guard([&] {
      Eigen::Map<Eigen::VectorXd> g(grad_f, n);
      problem_.EvalCostGradient(Eigen::Map<const Eigen::VectorXd>(x, n), g);
    });
  }

  bool eval_g(Index n, const Number* x, bool, Index m, Number* g) override {
    return Guard([&] {
      Eigen::Map<Eigen::VectorXd> gm(g, m);
      problem_.EvalConstraints(Eigen::Map<const Eigen::VectorXd>(x, n), gm);
    });
  }

  bool eval_jac_g(Index n, const Number* x, bool, Index, Index nele_jac, Index* iRow, Index* jCol,
                  Number* values) override {
    if (values == nullptr) {
      const auto& J = problem_.constraint_jacobian_sparsity();
      for (Index k = 0; k < nele_jac; ++k) {
        iRow[k] = J.rows[k];
        jCol[k] = J.cols[k];
      }
      return true;
    }
    return Guard([&] {
      Eigen::Map<Eigen::VectorXd> v(values, nele_jac);
      problem_.EvalConstraintJacobian(Eigen::Map<const Eigen::VectorXd>(x, n), v);
    });
  }

  bool eval_h(Index n, const Number* x, bool, Number obj_factor, Index m, const Number* lambda, bool, Index nele_hess,
              Index* iRow, Index* jCol, Number* values) override {
    if (!problem_.has_lagrangian_hessian()) return false;
    if (values == nullptr) {
      const auto& H = problem_.lagrangian_hessian_sparsity();
      for (Index k = 0; k < nele_hess; ++k) {
        // Ipopt wants the lower triangle: row ≥ col (our convention too).
        iRow[k] = H.rows[k];
        jCol[k] = H.cols[k];
      }
      return true;
    }
    return Guard([&] {
      Eigen::Map<Eigen::VectorXd> v(values, nele_hess);
      problem_.EvalLagrangianHessian(Eigen::Map<const Eigen::VectorXd>(x, n), obj_factor,
                                     Eigen::Map<const Eigen::VectorXd>(lambda, m), v);
    });
  }

  bool intermediate_callback(Ipopt::AlgorithmMode, Index iter, Number, Number, Number, Number, Number, Number, Number,
                             Number, Index, const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    iterations_ = iter;
    return exception_ == nullptr;
  }

  void finalize_solution(Ipopt::SolverReturn, Index n, const Number* x, const Number* z_L, const Number* z_U, Index m,
                         const Number* g, const Number* lambda, Number obj_value, const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override {
    result_->x = Eigen::Map<const Eigen::VectorXd>(x, n);
    result_->multipliers.lower_bounds = Eigen::Map<const Eigen::VectorXd>(z_L, n);
    result_->multipliers.upper_bounds = Eigen::Map<const Eigen::VectorXd>(z_U, n);
    result_->constraints = Eigen::Map<const Eigen::VectorXd>(g, m);
    result_->multipliers.constraints = Eigen::Map<const Eigen::VectorXd>(lambda, m);
    result_->cost = obj_value;
  }

 private:
  template <class F>
  bool Guard(F&& f) {
    if (exception_ != nullptr) return false;
    try {
      f();
      return true;
    } catch (...) {
      exception_ = std::current_exception();
      return false;
    }
  }

  NlpProblem& problem_;
  const Eigen::VectorXd& x0_;
  const NlpMultipliers* warm_;
  NlpResult* result_;
  std::exception_ptr exception_;
  int iterations_ = 0;
};

NlpStatus Translate(Ipopt::ApplicationReturnStatus status) {
  switch (status) {
    case Ipopt::Solve_Succeeded: return NlpStatus::kSolved;
    case Ipopt::Solved_To_Acceptable_Level: return NlpStatus::kSolvedToAcceptableLevel;
    case Ipopt::Infeasible_Problem_Detected: return NlpStatus::kInfeasible;
    case Ipopt::Maximum_Iterations_Exceeded: return NlpStatus::kMaxIterations;
    case Ipopt::Maximum_CpuTime_Exceeded: return NlpStatus::kMaxCpuTime;
    case Ipopt::Diverging_Iterates: return NlpStatus::kDivergingIterates;
    case Ipopt::Restoration_Failed: return NlpStatus::kRestorationFailed;
    case Ipopt::Search_Direction_Becomes_Too_Small: return NlpStatus::kSearchDirectionTooSmall;
    case Ipopt::Not_Enough_Degrees_Of_Freedom:
    case Ipopt::Invalid_Problem_Definition:
    case Ipopt::Invalid_Number_Detected:
    case Ipopt::Invalid_Option: return NlpStatus::kInvalidProblem;
    default: return NlpStatus::kError;
  }
}

std::string Describe(NlpStatus status, Ipopt::ApplicationReturnStatus raw) {
  switch (status) {
    case NlpStatus::kSolved: return "solved to tolerance";
    case NlpStatus::kSolvedToAcceptableLevel: return "solved to the acceptable tolerance only";
    case NlpStatus::kInfeasible:
      return "infeasible: Ipopt converged to a point of local infeasibility (the constraints "
             "cannot be satisfied near the returned x)";
    case NlpStatus::kMaxIterations: return "stopped at the iteration limit";
    case NlpStatus::kMaxCpuTime: return "stopped at the CPU time limit";
    case NlpStatus::kDivergingIterates: return "iterates diverge (problem unbounded?)";
    case NlpStatus::kRestorationFailed: return "restoration phase failed (possibly infeasible or badly scaled)";
    case NlpStatus::kSearchDirectionTooSmall: return "search direction became too small";
    case NlpStatus::kInvalidProblem: break;
    case NlpStatus::kError: break;
  }
  std::ostringstream msg;
  msg << ToString(status) << " (Ipopt return code " << static_cast<int>(raw) << ")";
  return msg.str();
}

}  // namespace

IpoptSolver::IpoptSolver(IpoptSolverOptions options) : options_(std::move(options)) {}

NlpResult IpoptSolver::Solve(NlpProblem& problem, const Eigen::VectorXd& x0, const NlpMultipliers* warm_start) const {
  const auto start = std::chrono::steady_clock::now();
  const int n = problem.num_variables();
  const int m = problem.num_constraints();
  std::ostringstream err;
  if (x0.size() != n) {
    err << "NLP '" << problem.name() << "': initial guess has size " << x0.size() << ", expected " << n;
    throw std::invalid_argument(err.str());
  }
  if (warm_start != nullptr && (warm_start->constraints.size() != m || warm_start->lower_bounds.size() != n ||
                                warm_start->upper_bounds.size() != n)) {
    err << "NLP '" << problem.name() << "': warm-start multipliers have sizes " << warm_start->constraints.size() << "/"
        << warm_start->lower_bounds.size() << "/" << warm_start->upper_bounds.size() << ", expected " << m << "/" << n
        << "/" << n;
    throw std::invalid_argument(err.str());
  }
  problem.Validate();

  NlpResult result;
  Ipopt::SmartPtr<TnlpAdapter> adapter = new TnlpAdapter(problem, x0, warm_start, &result);
  Ipopt::ApplicationReturnStatus raw = Ipopt::Internal_Error;
  {
    std::lock_guard<std::mutex> lock(IpoptMutex());
    Ipopt::SmartPtr<Ipopt::IpoptApplication> app = new Ipopt::IpoptApplication();
    auto opts = app->Options();
    // Ipopt's setters return false for a value it rejects (e.g. mu_strategy "fast", tol ≤ 0): say which.
    auto reject = [&](const char* option, const std::string& value) {
      throw std::invalid_argument("NLP '" + problem.name() + "': IpoptSolverOptions: Ipopt rejects " + option + " = " +
                                  value);
    };
    auto set_str = [&](const char* option, const std::string& value) {
      if (!opts->SetStringValue(option, value)) reject(option, "'" + value + "'");
    };
    auto set_num = [&](const char* option, double value) {
      if (opts->SetNumericValue(option, value)) return;
      std::ostringstream text;
      text << value;  // %g-like: 1e-09, not to_string's 0.000000
      reject(option, text.str());
    };
    auto set_int = [&](const char* option, int value) {
      if (!opts->SetIntegerValue(option, value)) reject(option, std::to_string(value));
    };
    set_int("print_level", options_.print_level);
    set_str("sb", "yes");  // no banner
    set_num("tol", options_.tolerance);
    set_num("constr_viol_tol", options_.constraint_violation_tolerance);
    set_num("acceptable_tol", options_.acceptable_tolerance);
    set_int("max_iter", options_.max_iterations);
    set_num("max_cpu_time", options_.max_cpu_time);
    set_str("linear_solver", options_.linear_solver);
    set_num("bound_relax_factor", options_.bound_relax_factor);
    set_str("mu_strategy", options_.mu_strategy);
    set_num("mu_init", options_.mu_init);
    set_str("bound_mult_init_method", options_.bound_mult_init_method);
    if (options_.linear_solver == "mumps") set_int("mumps_pivot_order", options_.mumps_pivot_order);
    if (options_.use_limited_memory_hessian || !problem.has_lagrangian_hessian()) {
      set_str("hessian_approximation", "limited-memory");
      set_int("limited_memory_max_history", options_.limited_memory_history);
    }
    if (warm_start != nullptr) {
      set_str("warm_start_init_point", "yes");
      set_num("warm_start_bound_push", options_.warm_start_bound_push);
      set_num("warm_start_mult_bound_push", options_.warm_start_mult_bound_push);
      set_num("mu_init", options_.warm_start_mu_init);
    }
    // Initialize("") : do not read an ipopt.opt file from the working directory.
    raw = app->Initialize("");
    if (raw == Ipopt::Solve_Succeeded) {
      raw = app->OptimizeTNLP(adapter);
      if (IsValid(app->Statistics())) result.iterations = app->Statistics()->IterationCount();
    }
  }
  if (adapter->exception() != nullptr) std::rethrow_exception(adapter->exception());
  if (result.iterations == 0) result.iterations = adapter->iterations();
  result.status = Translate(raw);
  std::ostringstream msg;
  msg << "NLP '" << problem.name() << "': " << Describe(result.status, raw) << " after " << result.iterations
      << " iterations";
  if (result.x.size() == n) {
    // Report the worst constraint/bound violation; useful for infeasible outcomes.
    double violation = 0.0;
    for (int i = 0; i < m && result.constraints.size() == m; ++i) {
      violation = std::max({violation, problem.constraint_lower_bounds()(i) - result.constraints(i),
                            result.constraints(i) - problem.constraint_upper_bounds()(i)});
    }
    msg << ", cost " << result.cost << ", max constraint violation " << violation;
  } else {
    result.x = x0;
  }
  result.message = msg.str();
  result.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace rome
