// Python bindings of the solvers: the dense QP (solvers/qp), the CARE (solvers/riccati) and the LQR
// (systems/controllers/linear_quadratic_regulator.h), numpy in and out.
#include <limits>
#include <optional>
#include <string>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "solvers/qp/dense_qp_solver.h"
#include "solvers/riccati/continuous_algebraic_riccati_equation.h"
#include "systems/controllers/linear_quadratic_regulator.h"
#include "python/bindings.h"

namespace py = pybind11;

namespace rome::python {
namespace {

using OptMatrix = std::optional<Eigen::MatrixXd>;
using OptVector = std::optional<Eigen::VectorXd>;

/// The rows of an optional matrix argument (0 when absent); its columns must be n.
int RowsOf(const OptMatrix& M, Eigen::Index n, const char* what) {
  if (!M) return 0;
  if (M->cols() != n)
    throw py::value_error(std::string("solve_qp: ") + what + " has " + std::to_string(M->cols()) +
                          " columns, expected n = " + std::to_string(n));
  return static_cast<int>(M->rows());
}

/// Copies an optional vector argument into `target` (left at its default when absent), checking its size.
void CopyVector(const OptVector& v, Eigen::VectorXd& target, const char* what) {
  if (!v) return;
  if (v->size() != target.size())
    throw py::value_error(std::string("solve_qp: ") + what + " has " + std::to_string(v->size()) +
                          " elements, expected " + std::to_string(target.size()));
  target = *v;
}

py::dict SolveQp(const Eigen::MatrixXd& H, const Eigen::VectorXd& g, const OptMatrix& A_eq, const OptVector& b_eq,
                 const OptMatrix& A, const OptVector& l, const OptVector& u, const OptVector& lb, const OptVector& ub,
                 int max_iterations) {
  const Eigen::Index n = H.rows();
  if (H.cols() != n)
    throw py::value_error("solve_qp: H is " + std::to_string(H.rows()) + "x" + std::to_string(H.cols()) +
                          ", expected square");
  if (g.size() != n)
    throw py::value_error("solve_qp: g has " + std::to_string(g.size()) +
                          " elements, expected n = " + std::to_string(n));
  if (A_eq.has_value() != b_eq.has_value()) throw py::value_error("solve_qp: give A_eq and b_eq together");
  if (A && !l && !u) throw py::value_error("solve_qp: A needs l, u or both");
  QpSettings settings;
  settings.max_iterations = max_iterations;
  DenseQpSolver qp(static_cast<int>(n), RowsOf(A_eq, n, "A_eq"), RowsOf(A, n, "A"), settings);
  qp.H = H;
  qp.g = g;
  if (A_eq) qp.A_eq = *A_eq;
  if (A) qp.A = *A;
  CopyVector(b_eq, qp.b_eq, "b_eq");
  CopyVector(l, qp.l, "l");
  CopyVector(u, qp.u, "u");
  CopyVector(lb, qp.lb, "lb");
  CopyVector(ub, qp.ub, "ub");
  const QpStatus status = qp.Solve();
  if (status == QpStatus::kInvalidInput) throw py::value_error("solve_qp: " + qp.status_message());
  py::dict r;
  r["status"] = std::string(to_string(status));
  r["message"] = qp.status_message();
  r["x"] = qp.x();
  r["y_eq"] = qp.y_eq();
  r["y_ineq"] = qp.y_ineq();
  r["y_bounds"] = qp.y_bounds();
  r["objective"] = qp.objective();
  r["iterations"] = qp.iterations();
  r["infeasible_constraints"] = qp.infeasible_constraints();
  return r;
}

}  // namespace

void BindSolvers(py::module_& m) {
  m.def("solve_qp", &SolveQp, py::arg("H"), py::arg("g"), py::arg("A_eq") = py::none(), py::arg("b_eq") = py::none(),
        py::arg("A") = py::none(), py::arg("l") = py::none(), py::arg("u") = py::none(), py::arg("lb") = py::none(),
        py::arg("ub") = py::none(), py::arg("max_iterations") = QpSettings{}.max_iterations,
        "min 1/2 x'Hx + g'x s.t. A_eq x = b_eq, l <= A x <= u, lb <= x <= ub (solvers/qp/dense_qp_solver.h). Returns a "
        "dict: "
        "status ('optimal', 'infeasible', ...), message, x, y_eq, y_ineq, y_bounds (H x + g + A_eq'y_eq + A'y_ineq + "
        "y_bounds = 0), "
        "objective, iterations. Bad data raises ValueError.");
  m.def(
      "solve_care",
      [](const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R) {
        const ContinuousAlgebraicRiccatiSolution s = SolveContinuousAlgebraicRiccatiEquationWithDetails(A, B, Q, R);
        py::dict r;
        r["P"] = s.P;
        r["K"] = s.K;
        r["relative_residual"] = s.relative_residual;
        return r;
      },
      py::arg("A"), py::arg("B"), py::arg("Q"), py::arg("R"),
      "Stabilizing solution of A'P + PA - PBR^-1B'P + Q = 0: a dict with P, K = R^-1 B'P and relative_residual.");
  m.def(
      "lqr",
      [](const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R,
         const OptMatrix& N) {
        const LinearQuadraticRegulatorResult r = LinearQuadraticRegulator(A, B, Q, R, N.value_or(Eigen::MatrixXd()));
        return py::make_tuple(r.K, r.S);
      },
      py::arg("A"), py::arg("B"), py::arg("Q"), py::arg("R"), py::arg("N") = py::none(),
      "(K, S) of the infinite-horizon LQR, u = -K x.");
  m.def(
      "lqr_of_system",
      [](const System& system, Context& context, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R,
         const std::string& input_port) {
        const LinearQuadraticRegulatorResult r = LinearQuadraticRegulator(system, context, Q, R, input_port);
        return py::make_tuple(r.K, r.S);
      },
      py::arg("system"), py::arg("context"), py::arg("Q"), py::arg("R"), py::arg("input_port"),
      "(K, S) of the LQR of `system` linearized about the point held by `context` (u0 fixed on `input_port`).");
}

}  // namespace rome::python
