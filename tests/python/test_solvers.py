"""Solvers from Python, checked in numpy: the QP's KKT conditions, the Riccati residual and closed-loop stability,
the LQR of the double integrator in closed form, Linearize against numpy finite differences and the LIP's exact A."""
import math

import numpy as np
import pytest

import rome


def random_qp(seed, n=6, n_eq=2, n_ineq=3):
    rng = np.random.default_rng(seed)
    M = rng.standard_normal((n, n))
    H = M @ M.T + 0.1 * np.eye(n)
    g = 5.0 * rng.standard_normal(n)  # pushes the unconstrained minimum out of the feasible set
    x_feasible = rng.standard_normal(n)
    A_eq = rng.standard_normal((n_eq, n))
    A = rng.standard_normal((n_ineq, n))
    slack = rng.uniform(0.05, 0.3, n_ineq)
    return dict(H=H, g=g, A_eq=A_eq, b_eq=A_eq @ x_feasible, A=A, l=A @ x_feasible - slack, u=A @ x_feasible + slack,
                lb=x_feasible - 0.5, ub=x_feasible + 0.5)


@pytest.mark.parametrize("seed", range(1, 11))
def test_qp_answer_satisfies_kkt(seed):
    p = random_qp(seed)
    r = rome.solve_qp(**p)
    assert r["status"] == "optimal", r["message"]
    x, y_eq, y_ineq, y_b = r["x"], r["y_eq"], r["y_ineq"], r["y_bounds"]
    tol = 1e-8
    # Stationarity (OSQP's sign convention).
    residual = p["H"] @ x + p["g"] + p["A_eq"].T @ y_eq + p["A"].T @ y_ineq + y_b
    assert np.max(np.abs(residual)) < tol * max(1.0, np.max(np.abs(p["g"])))
    # Primal feasibility.
    assert np.max(np.abs(p["A_eq"] @ x - p["b_eq"])) < tol
    Ax = p["A"] @ x
    assert np.all(Ax >= p["l"] - tol) and np.all(Ax <= p["u"] + tol)
    assert np.all(x >= p["lb"] - tol) and np.all(x <= p["ub"] + tol)
    # Complementarity and dual signs: y > 0 only at the upper side, y < 0 only at the lower side.
    for y, value, lower, upper in ((y_ineq, Ax, p["l"], p["u"]), (y_b, x, p["lb"], p["ub"])):
        assert np.all((y <= tol) | (np.abs(value - upper) < 1e-7))
        assert np.all((y >= -tol) | (np.abs(value - lower) < 1e-7))
    assert r["objective"] == pytest.approx(0.5 * x @ p["H"] @ x + p["g"] @ x, rel=1e-10, abs=1e-10)


def test_qp_infeasible_is_a_status_not_an_exception():
    r = rome.solve_qp(np.eye(2), np.zeros(2), A=np.array([[1.0, 0.0], [1.0, 0.0]]), l=np.array([1.0, -np.inf]), u=np.array([np.inf, 0.0]))
    assert r["status"] == "infeasible"


@pytest.mark.parametrize("seed", range(1, 6))
def test_care_residual_and_closed_loop_stable(seed):
    rng = np.random.default_rng(seed)
    n, m = 5, 2
    A = rng.standard_normal((n, n))
    B = rng.standard_normal((n, m))
    Q = np.eye(n)
    R = np.diag(rng.uniform(0.5, 2.0, m))
    sol = rome.solve_care(A, B, Q, R)
    P = sol["P"]
    residual = A.T @ P + P @ A - P @ B @ np.linalg.solve(R, B.T @ P) + Q
    scale = np.linalg.norm(A.T @ P) + np.linalg.norm(P @ A) + np.linalg.norm(P @ B @ np.linalg.solve(R, B.T @ P)) + np.linalg.norm(Q)
    assert np.linalg.norm(residual) / scale < 1e-12
    np.testing.assert_allclose(P, P.T, atol=1e-10 * np.linalg.norm(P))
    assert np.min(np.linalg.eigvalsh(0.5 * (P + P.T))) > 0
    K = np.linalg.solve(R, B.T @ P)
    np.testing.assert_allclose(sol["K"], K, rtol=1e-10, atol=1e-12)
    assert np.max(np.linalg.eigvals(A - B @ K).real) < 0


def test_lqr_of_the_double_integrator_in_closed_form():
    # x'' = u, Q = I, R = 1: K = [1, sqrt(3)], S = [[sqrt(3), 1], [1, sqrt(3)]].
    K, S = rome.lqr(np.array([[0.0, 1.0], [0.0, 0.0]]), np.array([[0.0], [1.0]]), np.eye(2), np.eye(1))
    np.testing.assert_allclose(K, [[1.0, math.sqrt(3.0)]], rtol=1e-10)
    np.testing.assert_allclose(S, [[math.sqrt(3.0), 1.0], [1.0, math.sqrt(3.0)]], rtol=1e-10)


class DrivenPendulum(rome.LeafSystem):
    """theta'' = -g/l sin(theta) - c theta' + u / (m l^2); y = [sin(theta), theta * omega]."""

    g, l, m, c = 9.81, 0.7, 1.3, 0.2

    def __init__(self):
        super().__init__("pendulum")
        self.declare_continuous_state([0.0, 0.0])
        self.declare_input_port("u", 1)
        self.declare_output_port("y", 2, self.output, feedthrough=False)

    @classmethod
    def f(cls, x, u):
        return np.array([x[1], -cls.g / cls.l * math.sin(x[0]) - cls.c * x[1] + u[0] / (cls.m * cls.l ** 2)])

    @staticmethod
    def h(x):
        return np.array([math.sin(x[0]), x[0] * x[1]])

    def do_calc_time_derivatives(self, context):
        return self.f(context.continuous_state, self.eval_input(context, "u"))

    def output(self, context):
        return self.h(context.continuous_state)


def numpy_jacobian(F, z, h=1e-6):
    columns = []
    for j in range(len(z)):
        e = np.zeros(len(z))
        e[j] = h
        columns.append((F(z + e) - F(z - e)) / (2 * h))
    return np.column_stack(columns)


def test_linearize_matches_numpy_finite_differences():
    system = DrivenPendulum()
    context = system.create_default_context()
    x0, u0 = np.array([0.8, -0.4]), np.array([0.3])
    context.continuous_state = x0
    system.fix_input_port(context, "u", u0)
    lin = rome.linearize(system, context, "u", "y")
    A = numpy_jacobian(lambda x: DrivenPendulum.f(x, u0), x0)
    B = numpy_jacobian(lambda u: DrivenPendulum.f(x0, u), u0)
    C = numpy_jacobian(DrivenPendulum.h, x0)
    D = numpy_jacobian(lambda u: DrivenPendulum.h(x0), u0)
    for rome_value, numpy_value in ((lin.A, A), (lin.B, B), (lin.C, C), (lin.D, D)):
        np.testing.assert_allclose(rome_value, numpy_value, rtol=1e-7, atol=1e-8)
    np.testing.assert_allclose(lin.xdot0, DrivenPendulum.f(x0, u0), rtol=1e-15)
    np.testing.assert_array_equal(context.continuous_state, x0)  # restored exactly


def test_linearize_the_lip_exactly():
    lip = rome.LinearInvertedPendulumSystem("lip", z0=0.8, gravity=9.81)
    lin = rome.linearize(lip, lip.create_default_context())
    np.testing.assert_allclose(lin.A, [[0.0, 1.0 / 0.8], [9.81, 0.0]], rtol=1e-9, atol=1e-12)
    assert lin.B.shape == (2, 0)
