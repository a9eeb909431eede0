"""Direct collocation from Python, against closed forms.

The double integrator's minimum-effort transfer from rest at 0 to rest at 1 in T = 1 has u(t) = 6 - 12 t,
p(t) = 3 t^2 - 2 t^3 and cost integral u^2 dt = 12; the LIP (a C++ block, no input) from a fixed initial state follows
x(t) = x0 cosh(lambda t) + xdot0 / lambda sinh(lambda t).
"""
import math

import numpy as np
import pytest

import rome


class DoubleIntegrator(rome.LeafSystem):
    """p'' = u, state [p, v]."""

    def __init__(self):
        super().__init__("double_integrator")
        self.declare_continuous_state([0.0, 0.0])
        self.declare_input_port("u", 1)

    def do_calc_time_derivatives(self, context):
        return [context.continuous_state[1], self.eval_input(context, "u")[0]]


@pytest.mark.parametrize("method", ["hermite-simpson", "trapezoidal"])
def test_minimum_effort_double_integrator_converges_to_the_closed_form(method):
    """The discrete optimum (trapezoid quadrature of u^2) approaches the continuous one at second order in h."""
    errors = []
    for nodes in (41, 81):
        result = rome.solve_collocation(DoubleIntegrator(), input_port="u", num_nodes=nodes, duration=1.0,
                                        method=method, initial_state=[0.0, 0.0], final_state=[1.0, 0.0], R=[[1.0]])
        assert result["success"], result["message"]
        assert result["max_defect"] < 1e-9
        t = result["times"]
        errors.append((abs(result["cost"] - 12.0), np.abs(result["states"][0] - (3 * t**2 - 2 * t**3)).max(),
                       np.abs(result["states"][1] - (6 * t - 6 * t**2)).max(),
                       np.abs(result["inputs"][0] - (6 - 12 * t)).max()))
    (cost_41, p_41, v_41, _), (cost_81, p_81, v_81, u_81) = errors
    assert cost_81 < 1e-3 * 12.0 and p_81 < 1e-4 and v_81 < 1e-3 and u_81 < 0.1
    for coarse, fine in ((cost_41, cost_81), (p_41, p_81), (v_41, v_81)):
        assert coarse / fine > 3.5  # halving h divides the error by about 4


def test_free_time_with_an_input_bound_is_bang_bang():
    """Minimum time from rest at 0 to rest at 1 with |u| <= 1: T = 2 (accelerate for 1 s, brake for 1 s)."""
    result = rome.solve_collocation(DoubleIntegrator(), input_port="u", num_nodes=41, duration=(0.5, 5.0),
                                    method="hermite-simpson", initial_state=[0.0, 0.0], final_state=[1.0, 0.0],
                                    input_lower=[-1.0], input_upper=[1.0], duration_cost=1.0,
                                    R=[[1e-6]])
    assert result["success"], result["message"]
    assert result["duration"] == pytest.approx(2.0, rel=2e-3)


def test_a_cpp_block_without_input_follows_its_closed_form():
    z0, x0, L0 = 0.8, -0.15, 0.5
    lip = rome.LinearInvertedPendulumSystem("lip", initial_x=x0, initial_L=L0, z0=z0)
    result = rome.solve_collocation(lip, num_nodes=31, duration=0.5, method="hermite-simpson",
                                    initial_state=[x0, L0])
    assert result["success"], result["message"]
    lam = math.sqrt(9.81 / z0)
    t = result["times"]
    x = x0 * np.cosh(lam * t) + L0 / (z0 * lam) * np.sinh(lam * t)
    assert np.allclose(result["states"][0], x, atol=1e-6)


def test_bad_input_names_the_argument():
    with pytest.raises(ValueError, match="final_state has 3 entries, expected 2"):
        rome.solve_collocation(DoubleIntegrator(), input_port="u", final_state=[1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"duration must be a number of seconds or a \(min, max\) pair, got \(1, 2, 3\)"):
        rome.solve_collocation(DoubleIntegrator(), input_port="u", duration=(1, 2, 3))
    with pytest.raises(ValueError, match="method must be"):
        rome.solve_collocation(DoubleIntegrator(), input_port="u", method="euler")
