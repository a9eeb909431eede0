#pragma once
// DirectCollocation: multi-phase trapezoidal direct collocation for hybrid reduced-order models.
//
// Phase p (p = 0 … P−1) has n_x^p states, n_u^p inputs, N^p ≥ 2 nodes at times
// t_k = t_0^p + k h^p, h^p = T^p / (N^p − 1), and dynamics ẋ = f^p(x, u). T^p is a decision
// variable when min_duration < max_duration. Phases follow each other: t_0^{p+1} = t_0^p + T^p.
//
// Decision variables (per phase, in this order): x_0 … x_{N−1}, u_0 … u_{N−1}, [T].
// Constraints:
//   defects      x_{k+1} − x_k − (h/2)(f(x_k, u_k) + f(x_{k+1}, u_{k+1})) = 0   (trapezoid rule, default), or
//                x_{k+1} − x_k − (h/6)(f_k + 4 f(x_c, u_c) + f_{k+1}) = 0 with x_c = (x_k + x_{k+1})/2 +
//                (h/8)(f_k − f_{k+1}), u_c = (u_k + u_{k+1})/2   (compressed Hermite–Simpson, 4th order; the
//                midpoint input is the first-order hold, so the plan re-integrates with that hold)
//   transitions  x_0^{p+1} − Δ^p(x_{N−1}^p) = 0   (reset map Δ, default identity)
//   periodicity  x_0^0 − Δ^P(x_{N−1}^{P−1}) = 0   (optional, SetPeriodicTransition: a periodic gait)
//   path         g_lo ≤ g(x_k, u_k) ≤ g_hi at every node of a phase
//   node         c_lo ≤ c(x_k, u_k) ≤ c_hi at one node (boundary conditions, e.g. apex ż = 0)
//   bounds       state/input bounds at every node, per-node state bounds (initial/final states)
// Cost:
//   Σ_p [ Σ_k (h/2)(L(x_k, u_k) + L(x_{k+1}, u_{k+1})) + w_T T^p ] + Φ(x_{N−1}, u_{N−1}) of the
//   last phase.
//
// All user functions are written once on AutoDiff scalars (NodeScalar below); a template
// functor  template <class T> void operator()(const Eigen::Matrix<T,-1,1>& x,
//                                             const Eigen::Matrix<T,-1,1>& u,
//                                             Eigen::Matrix<T,-1,1>& y) const
// converts to StateInputFunction directly. The constraint Jacobian is exact and sparse: each
// user function contributes a dense block over the (x_k, u_k) of its node only. By default the
// Hessian of the Lagrangian is NOT formed: Ipopt's limited-memory quasi-Newton (L-BFGS)
// approximation is used. SetExactHessian(true) declares it instead (block diagonal over nodes plus
// the duration rows; node blocks are forward differences of the exact AutoDiff gradients, the
// duration rows exact), which cuts Ipopt's iterations several-fold on stiff hybrid ROMs.
//
// Evaluation callbacks allocate a few Eigen vectors per node (not per AutoDiff operation); this is an offline planner.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "solvers/collocation/piecewise_polynomial.h"
#include "solvers/nlp/autodiff.h"
#include "solvers/nlp/ipopt_solver.h"
#include "solvers/nlp/nlp_problem.h"

namespace rome {

// The scalar of every user function: forward-mode AutoDiff over one node's [x; u], with the derivatives held inside
// the scalar (no heap allocation per operation), so a phase has n_x + n_u ≤ kMaxNodeVariables (the constructor
// checks). Template code on the scalar type (the ROMs in systems/rom) instantiates with NodeScalar.
inline constexpr int kMaxNodeVariables = 24;
using NodeScalar = AutoDiffMax<kMaxNodeVariables>;
using NodeVector = Eigen::Matrix<NodeScalar, Eigen::Dynamic, 1>;

// y = F(x, u); F must resize y itself.
using StateInputFunction = std::function<void(const NodeVector& x, const NodeVector& u, NodeVector& y)>;
// y = F(x) (reset maps).
using StateFunction = std::function<void(const NodeVector& x, NodeVector& y)>;
// Scalar L(x, u) (running and terminal costs).
using ScalarStateInputFunction = std::function<NodeScalar(const NodeVector& x, const NodeVector& u)>;

enum class CollocationMethod { kTrapezoidal, kHermiteSimpson };

struct CollocationPhase {
  std::string name;                                            // used in every message about this phase
  int num_states = 0;                                          // n_x ≥ 1
  int num_inputs = 0;                                          // n_u ≥ 0
  int num_nodes = 21;                                          // N ≥ 2
  StateInputFunction dynamics;                                 // ẋ = f(x, u), required
  CollocationMethod method = CollocationMethod::kTrapezoidal;  // defect rule (cost: trapezoid quadrature always)
  double min_duration = 1.0;                                   // [s], > 0
  double max_duration = 1.0;                                   // [s], ≥ min_duration; equal ⇒ fixed duration
  Eigen::VectorXd state_lower;                                 // size n_x or empty (unbounded), applied at every node
  Eigen::VectorXd state_upper;
  Eigen::VectorXd input_lower;  // size n_u or empty
  Eigen::VectorXd input_upper;
  ScalarStateInputFunction running_cost;  // L(x, u), optional
  double duration_cost = 0.0;             // w_T [cost unit / s]
};

struct CollocationPhaseSolution {
  std::string name;
  double start_time = 0.0;               // [s]
  double duration = 0.0;                 // [s]
  Eigen::VectorXd times;                 // N node times [s]
  Eigen::MatrixXd states;                // n_x × N
  Eigen::MatrixXd inputs;                // n_u × N
  Eigen::MatrixXd state_derivatives;     // f(x_k, u_k), n_x × N
  PiecewisePolynomial state_trajectory;  // cubic Hermite through (x_k, f_k)
  PiecewisePolynomial input_trajectory;  // first-order hold (empty if n_u = 0)
};

struct CollocationResult {
  NlpResult nlp;
  std::vector<CollocationPhaseSolution> phases;
  double max_defect = 0.0;  // ‖defects‖_∞ at the returned point
  bool success() const { return nlp.success(); }
  // All phases joined in time (requires equal state/input sizes in every phase; throws
  // std::invalid_argument otherwise). Right-continuous at phase boundaries (post-reset values).
  PiecewisePolynomial ConcatenatedStateTrajectory() const;
  PiecewisePolynomial ConcatenatedInputTrajectory() const;
};

class DirectCollocation {
 public:
  // Validates the phases (sizes, durations, dynamics present); throws std::invalid_argument
  // naming the phase at fault.
  DirectCollocation(std::string name, std::vector<CollocationPhase> phases);
  ~DirectCollocation();

  int num_phases() const { return static_cast<int>(phases_.size()); }
  const CollocationPhase& phase(int p) const;

  // g_lo ≤ g(x_k, u_k) ≤ g_hi at every node of phase p; g returns `size` entries.
  void AddPathConstraint(int p, int size, StateInputFunction g, const Eigen::VectorXd& lower,
                         const Eigen::VectorXd& upper, std::string name = "path");
  // c_lo ≤ c(x_k, u_k) ≤ c_hi at node k of phase p (k = −1: last node).
  void AddNodeConstraint(int p, int node, int size, StateInputFunction c, const Eigen::VectorXd& lower,
                         const Eigen::VectorXd& upper, std::string name = "node");
  // State bounds at one node (boundary conditions), intersected with the phase bounds.
  void SetNodeStateBounds(int p, int node, const Eigen::VectorXd& lower, const Eigen::VectorXd& upper);
  // x_0^{p+1} = Δ(x_{N−1}^p) with Δ: R^{n_x^p} → R^{n_x^{p+1}}. Default: identity (needs equal n_x).
  void SetTransition(int p, StateFunction reset);
  // Closes the phase sequence into a cycle: x_0^0 = Δ(x_{N−1}^{P−1}) with Δ: R^{n_x^{P−1}} → R^{n_x^0}
  // (e.g. the reset of a periodic gait that re-expresses the state about the new stance foot).
  void SetPeriodicTransition(StateFunction reset);
  // Ipopt with the Lagrangian Hessian (true) or with L-BFGS (false, the default).
  void SetExactHessian(bool exact);
  // Φ(x, u) at the last node of the last phase.
  void SetTerminalCost(ScalarStateInputFunction cost);
  // Initial guess of phase p: states n_x × N, inputs n_u × N, duration [s].
  void SetInitialGuess(int p, const Eigen::MatrixXd& states, const Eigen::MatrixXd& inputs, double duration);

  // The NLP for the current definition (rebuilt on every call) and the matching initial guess
  // vector; exposed for derivative checks and custom solvers.
  std::unique_ptr<NlpProblem> BuildNlp() const;
  Eigen::VectorXd InitialGuessVector() const;

  // Builds the NLP, solves it with Ipopt (L-BFGS unless SetExactHessian(true)) and unpacks it.
  CollocationResult Solve(const IpoptSolverOptions& options = {}) const;

  // Unpacks a decision vector of BuildNlp() into per-phase trajectories.
  CollocationResult Unpack(const Eigen::VectorXd& z) const;

  struct NodeConstraint {
    int phase;
    int node;
    int size;
    StateInputFunction function;
    Eigen::VectorXd lower, upper;
    std::string name;
  };
  struct NodeBounds {
    int phase;
    int node;
    Eigen::VectorXd lower, upper;
  };
  struct Guess {
    Eigen::MatrixXd states, inputs;
    double duration = 0.0;
    bool set = false;
  };

 private:
  int NodeIndex(int p, int node, const char* who) const;

  std::string name_;
  std::vector<CollocationPhase> phases_;
  std::vector<NodeConstraint> path_constraints_;  // node = −2 means every node
  std::vector<NodeConstraint> node_constraints_;
  std::vector<NodeBounds> node_bounds_;
  std::vector<StateFunction> transitions_;  // size P − 1, empty function = identity
  StateFunction periodic_transition_;       // empty: not periodic
  bool exact_hessian_ = false;
  ScalarStateInputFunction terminal_cost_;
  std::vector<Guess> guesses_;
};

}  // namespace rome
