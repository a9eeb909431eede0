// Python binding of the direct collocation (solvers/collocation/direct_collocation.h) on a system's dynamics
// (systems/trajectory_optimization/collocation_dynamics.h): one phase, a quadratic running cost, bounds and boundary
// states, solved with Ipopt. The system may be a C++ block or a Python LeafSystem (its derivatives are then called
// from the solver, with the interpreter lock held).
#include <cmath>
#include <memory>
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "python/bindings.h"
#include "systems/trajectory_optimization/collocation_dynamics.h"

namespace py = pybind11;

namespace rome::python {
namespace {

/// x^T W x on AutoDiff scalars (W dense, size of x).
NodeScalar Quadratic(const Eigen::MatrixXd& W, const NodeVector& x) {
  NodeScalar sum(0.0);
  for (int i = 0; i < W.rows(); ++i)
    for (int j = 0; j < W.cols(); ++j)
      if (W(i, j) != 0.0) sum += W(i, j) * x(i) * x(j);
  return sum;
}

void CheckSquare(const Eigen::MatrixXd& W, int n, const char* what) {
  if (W.size() != 0 && (W.rows() != n || W.cols() != n))
    throw py::value_error(std::string("solve_collocation: ") + what + " is " + std::to_string(W.rows()) + " x " +
                          std::to_string(W.cols()) + ", expected " + std::to_string(n) + " x " + std::to_string(n));
}

void CheckSize(const Eigen::VectorXd& v, int n, const char* what) {
  if (v.size() != 0 && v.size() != n)
    throw py::value_error(std::string("solve_collocation: ") + what + " has " + std::to_string(v.size()) +
                          " entries, expected " + std::to_string(n));
}

struct CollocationProblem {
  std::string input_port;
  int num_nodes = CollocationPhase{}.num_nodes;
  double min_duration = 1.0, max_duration = 1.0;
  std::string method = "trapezoidal";
  Eigen::VectorXd initial_state, final_state;
  Eigen::VectorXd state_lower, state_upper, input_lower, input_upper;
  Eigen::MatrixXd Q, R;
  double duration_cost = 0.0;
  double tolerance = IpoptSolverOptions{}.tolerance;  // Ipopt `tol`
};

py::dict SolveCollocation(const LeafSystem& system, const CollocationProblem& p) {
  std::unique_ptr<Context> context = system.CreateDefaultContext();
  const auto* leaf_context = dynamic_cast<const LeafContext*>(context.get());
  if (leaf_context == nullptr) throw py::value_error("solve_collocation: system '" + system.name() + "' is not a leaf");
  CollocationPhase phase;
  phase.name = system.name();
  phase.num_states = leaf_context->continuous_state().size();
  phase.num_inputs = p.input_port.empty() ? 0 : system.input_port(system.GetInputPortIndex(p.input_port)).size;
  phase.num_nodes = p.num_nodes;
  phase.dynamics = CollocationDynamicsFromSystem(system, *leaf_context, p.input_port);
  if (p.method == "hermite-simpson")
    phase.method = CollocationMethod::kHermiteSimpson;
  else if (p.method != "trapezoidal")
    throw py::value_error("solve_collocation: method must be 'trapezoidal' or 'hermite-simpson', got '" + p.method +
                          "'");
  phase.min_duration = p.min_duration;
  phase.max_duration = p.max_duration;
  const int nx = phase.num_states, nu = phase.num_inputs;
  CheckSize(p.state_lower, nx, "state_lower");
  CheckSize(p.state_upper, nx, "state_upper");
  CheckSize(p.input_lower, nu, "input_lower");
  CheckSize(p.input_upper, nu, "input_upper");
  CheckSize(p.initial_state, nx, "initial_state");
  CheckSize(p.final_state, nx, "final_state");
  CheckSquare(p.Q, nx, "Q");
  CheckSquare(p.R, nu, "R");
  phase.state_lower = p.state_lower;
  phase.state_upper = p.state_upper;
  phase.input_lower = p.input_lower;
  phase.input_upper = p.input_upper;
  const Eigen::MatrixXd Q = p.Q, R = p.R;
  if (Q.size() != 0 || R.size() != 0)
    phase.running_cost = [Q, R](const NodeVector& x, const NodeVector& u) {
      NodeScalar cost(0.0);
      if (Q.size() != 0) cost += Quadratic(Q, x);
      if (R.size() != 0) cost += Quadratic(R, u);
      return cost;
    };
  phase.duration_cost = p.duration_cost;
  DirectCollocation collocation("collocation of '" + system.name() + "'", {phase});
  if (p.initial_state.size() != 0) collocation.SetNodeStateBounds(0, 0, p.initial_state, p.initial_state);
  if (p.final_state.size() != 0) collocation.SetNodeStateBounds(0, -1, p.final_state, p.final_state);
  if (p.initial_state.size() != 0 && p.final_state.size() != 0) {  // straight-line guess between the boundaries
    Eigen::MatrixXd states(nx, p.num_nodes);
    for (int k = 0; k < p.num_nodes; ++k) {
      const double s = static_cast<double>(k) / (p.num_nodes - 1);
      states.col(k) = (1.0 - s) * p.initial_state + s * p.final_state;
    }
    collocation.SetInitialGuess(0, states, Eigen::MatrixXd::Zero(nu, p.num_nodes),
                                0.5 * (p.min_duration + p.max_duration));
  }
  IpoptSolverOptions options;
  options.tolerance = p.tolerance;
  const CollocationResult result = collocation.Solve(options);
  const CollocationPhaseSolution& s = result.phases.at(0);
  py::dict d;
  d["success"] = result.success();
  d["status"] = std::string(ToString(result.nlp.status));
  d["message"] = result.nlp.message;
  d["iterations"] = result.nlp.iterations;
  d["cost"] = result.nlp.cost;
  d["max_defect"] = result.max_defect;
  d["duration"] = s.duration;
  d["times"] = s.times;
  d["states"] = s.states;
  d["inputs"] = s.inputs;
  d["state_derivatives"] = s.state_derivatives;
  return d;
}

}  // namespace

void BindCollocation(py::module_& m) {
  m.def(
      "solve_collocation",
      [](const LeafSystem& system, const std::string& input_port, int num_nodes, py::object duration,
         const std::string& method, const Eigen::VectorXd& initial_state, const Eigen::VectorXd& final_state,
         const Eigen::VectorXd& state_lower, const Eigen::VectorXd& state_upper, const Eigen::VectorXd& input_lower,
         const Eigen::VectorXd& input_upper, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R, double duration_cost,
         double tolerance) {
        CollocationProblem p;
        p.input_port = input_port;
        p.num_nodes = num_nodes;
        try {
          if (py::isinstance<py::tuple>(duration) || py::isinstance<py::list>(duration)) {
            const auto range = duration.cast<std::pair<double, double>>();
            p.min_duration = range.first;
            p.max_duration = range.second;
          } else {
            p.min_duration = p.max_duration = duration.cast<double>();
          }
        } catch (const py::cast_error&) {
          throw py::value_error("solve_collocation: duration must be a number of seconds or a (min, max) pair, got " +
                                std::string(py::str(py::repr(duration))));
        }
        p.method = method;
        p.initial_state = initial_state;
        p.final_state = final_state;
        p.state_lower = state_lower;
        p.state_upper = state_upper;
        p.input_lower = input_lower;
        p.input_upper = input_upper;
        p.Q = Q;
        p.R = R;
        p.duration_cost = duration_cost;
        p.tolerance = tolerance;
        return SolveCollocation(system, p);
      },
      py::arg("system"), py::arg("input_port") = "", py::arg("num_nodes") = CollocationPhase{}.num_nodes,
      py::arg("duration") = py::float_(1.0), py::arg("method") = "trapezoidal",
      py::arg("initial_state") = Eigen::VectorXd(), py::arg("final_state") = Eigen::VectorXd(),
      py::arg("state_lower") = Eigen::VectorXd(), py::arg("state_upper") = Eigen::VectorXd(),
      py::arg("input_lower") = Eigen::VectorXd(), py::arg("input_upper") = Eigen::VectorXd(),
      py::arg("Q") = Eigen::MatrixXd(), py::arg("R") = Eigen::MatrixXd(), py::arg("duration_cost") = 0.0,
      py::arg("tolerance") = IpoptSolverOptions{}.tolerance,
      "Direct collocation (one phase) of a leaf system's dynamics xdot = f(x, u), u on `input_port`:\n"
      "  min  integral of x^T Q x + u^T R u dt + duration_cost T\n"
      "  s.t. x(0) = initial_state, x(T) = final_state (each optional), bounds at every node,\n"
      "T = duration (a number) or free in (min, max). method: 'trapezoidal' or 'hermite-simpson'. Returns a dict: "
      "success, status, cost, max_defect, duration, times (N), states (nx x N), inputs (nu x N).");
}

}  // namespace rome::python
