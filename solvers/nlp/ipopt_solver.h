#pragma once
// IpoptSolver: solves an NlpProblem with Ipopt (interior point, MUMPS linear solver).
//
// Ipopt 3.11 + MUMPS is not thread-safe: every solve in the process is serialized through
// IpoptMutex(). Ipopt's console output is off unless IpoptSolverOptions::print_level > 0.
// If the problem has no exact Lagrangian Hessian (NlpProblem::has_lagrangian_hessian() false) or
// options.use_limited_memory_hessian is set, Ipopt's limited-memory (L-BFGS) quasi-Newton Hessian
// approximation is used.
//
// Exceptions thrown by the problem's Eval* callbacks abort the solve and are rethrown by Solve().
#include <mutex>
#include <string>

#include <Eigen/Dense>

#include "solvers/nlp/nlp_problem.h"

namespace rome {

// The one process-wide lock around Ipopt.
std::mutex& IpoptMutex();

struct IpoptSolverOptions {
  double tolerance = 1e-8;                       // Ipopt `tol`, scaled KKT error [-]
  double constraint_violation_tolerance = 1e-8;  // Ipopt `constr_viol_tol`, absolute [unit of g]
  double acceptable_tolerance = 1e-6;            // Ipopt `acceptable_tol` [-]
  int max_iterations = 3000;                     // Ipopt `max_iter` [-]
  double max_cpu_time = 1e6;                     // Ipopt `max_cpu_time` [s]
  std::string linear_solver = "mumps";           // Ipopt `linear_solver`
  int print_level = 0;                           // 0 = silent … 5 = Ipopt default, 12 = max
  bool use_limited_memory_hessian = false;       // force L-BFGS even if an exact Hessian exists
  int limited_memory_history = 6;                // Ipopt `limited_memory_max_history` [-]
  // Ipopt `bound_relax_factor` [-] (Ipopt's default): bounds are relaxed by this relative amount while solving and
  // x is moved back inside them at the end, so g(x) can differ from the last iterate's; 0 solves on exact bounds.
  double bound_relax_factor = 1e-8;
  std::string mu_strategy = "monotone";  // Ipopt `mu_strategy`: "monotone" or "adaptive"
  double mu_init = 0.1;                  // Ipopt `mu_init`, initial barrier parameter of a cold start [-]
  // Ipopt `bound_mult_init_method`: "constant" (every bound multiplier starts at 1) or "mu-based" (mu_init / slack).
  std::string bound_mult_init_method = "constant";
  // Ipopt `mumps_pivot_order`: MUMPS's fill-reducing ordering (ICNTL(7)): 0 AMD, 2 AMF, 4 PORD, 6 QAMD (AMD that
  // detects quasi-dense rows, e.g. a free duration coupling every node), 7 MUMPS's automatic choice (Ipopt's default).
  int mumps_pivot_order = 7;
  // Warm start: when Solve() receives multipliers, use them (Ipopt `warm_start_init_point`).
  double warm_start_bound_push = 1e-9;       // Ipopt `warm_start_bound_push` [-]
  double warm_start_mult_bound_push = 1e-9;  // Ipopt `warm_start_mult_bound_push` [-]
  double warm_start_mu_init = 1e-6;          // Ipopt `mu_init` used for warm starts [-]
};

enum class NlpStatus {
  kSolved,                   // converged to tolerance
  kSolvedToAcceptableLevel,  // converged to acceptable_tolerance only
  kInfeasible,               // Ipopt converged to a point of local infeasibility
  kMaxIterations,
  kMaxCpuTime,
  kDivergingIterates,
  kRestorationFailed,
  kSearchDirectionTooSmall,
  kInvalidProblem,  // bad problem definition, too few degrees of freedom, NaN, …
  kError,           // any other Ipopt failure
};

const char* ToString(NlpStatus status);

// Multipliers for warm starts and results (Ipopt sign convention: ∇f + Jᵀλ − z_L + z_U = 0).
struct NlpMultipliers {
  Eigen::VectorXd constraints;   // λ, size num_constraints
  Eigen::VectorXd lower_bounds;  // z_L ≥ 0, size num_variables
  Eigen::VectorXd upper_bounds;  // z_U ≥ 0, size num_variables
};

struct NlpResult {
  NlpStatus status = NlpStatus::kError;
  std::string message;  // names the problem and the outcome, e.g. "NLP 'hs071': solved (…)"
  int iterations = 0;
  double wall_time = 0.0;  // [s], whole Solve() including the wait for the Ipopt mutex
  double cost = 0.0;
  Eigen::VectorXd x;
  Eigen::VectorXd constraints;  // g(x)
  NlpMultipliers multipliers;
  bool success() const { return status == NlpStatus::kSolved || status == NlpStatus::kSolvedToAcceptableLevel; }
};

class IpoptSolver {
 public:
  explicit IpoptSolver(IpoptSolverOptions options = {});
  const IpoptSolverOptions& options() const { return options_; }
  IpoptSolverOptions& mutable_options() { return options_; }

  // Solves from the initial guess x0 (size num_variables). With `warm_start` the multipliers
  // are used as the initial dual point (e.g. NlpResult::multipliers of a previous solve).
  // Throws std::invalid_argument on size mismatches or an invalid problem definition.
  NlpResult Solve(NlpProblem& problem, const Eigen::VectorXd& x0, const NlpMultipliers* warm_start = nullptr) const;

 private:
  IpoptSolverOptions options_;
};

}  // namespace rome
