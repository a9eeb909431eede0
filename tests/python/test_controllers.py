"""C++ controllers closing the loop around Python plants in Python-built diagrams.

LQR: the cost integral of (x'Qx + u'Ru) dt accumulated along the simulated closed loop (a state of the Python plant)
equals x0' S x0, the Riccati solution's value (exactly for the cart-pole's linearization, whose A and B are written
here from the equations of motion; to first order in the tilt for the nonlinear cart-pole). Joint PD: a pendulum held by
u = kp (q_des - q) - kd qdot settles where kp (q_des - q) = m g l sin q, solved here by bisection.
"""
import math

import numpy as np
import pytest

import rome

M_C, M_P, L_POLE, G = 1.0, 0.3, 0.5, 9.81
Q, R = np.diag([10.0, 10.0, 1.0, 1.0]), np.eye(1)
UPRIGHT = np.array([0.0, math.pi, 0.0, 0.0])


def cart_pole_derivative(x, f):
    _, theta, xdot, thetadot = x
    s, c = math.sin(theta), math.cos(theta)
    d = M_C + M_P * s * s
    xddot = (f + M_P * s * (L_POLE * thetadot**2 + G * c)) / d
    thetaddot = (-f * c - M_P * L_POLE * thetadot**2 * c * s - (M_C + M_P) * G * s) / (L_POLE * d)
    return np.array([xdot, thetadot, xddot, thetaddot])


# The linearization about upright (theta = pi, cos = -1): x'' = (f + m_p g dtheta) / m_c,
# theta'' = (f + (m_c + m_p) g dtheta) / (l m_c) with dtheta = theta - pi.
A_UP = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [0, M_P * G / M_C, 0, 0], [0, (M_C + M_P) * G / (L_POLE * M_C), 0, 0]])
B_UP = np.array([[0.0], [0.0], [1 / M_C], [1 / (L_POLE * M_C)]])


class CartPoleWithCost(rome.LeafSystem):
    """State [x, theta, xdot, thetadot, J] with J' = dx' Q dx + f' R f; `linear` uses the upright linearization."""

    def __init__(self, x0, linear):
        super().__init__("cart_pole")
        self.linear = linear
        self.declare_continuous_state(list(x0) + [0.0])
        self.declare_input_port("f", 1)
        self.declare_output_port("state", 4, lambda c: c.continuous_state[:4], feedthrough=False)

    def do_calc_time_derivatives(self, context):
        x = context.continuous_state[:4]
        f = self.eval_input(context, "f")[0]
        dx = x - UPRIGHT
        xdot = A_UP @ dx + B_UP[:, 0] * f if self.linear else cart_pole_derivative(x, f)
        return list(xdot) + [dx @ Q @ dx + R[0, 0] * f * f]


def closed_loop_cost(x0, linear, t_end=15.0):
    builder = rome.DiagramBuilder()
    builder.add_system(CartPoleWithCost(x0, linear))
    lqr = builder.add_system(rome.LqrController("lqr", A_UP, B_UP, Q, R, UPRIGHT, [0.0]))
    builder.connect("cart_pole", "state", "lqr", "x")
    builder.connect("lqr", "u", "cart_pole", "f")
    diagram = builder.build()
    sim = rome.Simulator(diagram, rome.SimulatorConfig(relative_tolerance=1e-10, absolute_tolerance=1e-12))
    assert sim.advance_to(t_end).ok()
    state = diagram.get_continuous_state(sim.context)
    return state[4], state[:4], np.asarray(lqr.S)


def test_linearize_matches_the_cart_poles_upright_jacobian():
    plant = CartPoleWithCost(UPRIGHT, linear=False)
    context = plant.create_default_context()
    plant.fix_input_port(context, "f", [0.0])
    lin = rome.linearize(plant, context, "f", "state")
    assert np.allclose(lin.A[:4, :4], A_UP, atol=1e-6)
    assert np.allclose(lin.B[:4], B_UP, atol=1e-6)


def test_lqr_cost_along_the_closed_loop_is_x0_s_x0():
    dx0 = np.array([0.1, 0.2, 0.0, -0.1])
    cost, final, S = closed_loop_cost(UPRIGHT + dx0, linear=True)
    assert np.abs(final - UPRIGHT).max() < 1e-6
    assert cost == pytest.approx(dx0 @ S @ dx0, rel=1e-6)


def test_lqr_on_the_nonlinear_cart_pole_costs_x0_s_x0_to_first_order():
    dx0 = np.array([0.0, 0.02, 0.0, 0.0])
    cost, final, S = closed_loop_cost(UPRIGHT + dx0, linear=False)
    assert np.abs(final - UPRIGHT).max() < 1e-6
    assert cost == pytest.approx(dx0 @ S @ dx0, rel=0.02)


class JointPendulum(rome.LeafSystem):
    """One revolute joint, point mass m at length l, q = 0 hanging down: m l^2 q'' = u - m g l sin q."""

    def __init__(self, m=2.0, l=0.6):
        super().__init__("pendulum")
        self.m, self.l = m, l
        self.declare_continuous_state([0.0, 0.0])
        self.declare_input_port("u", 1)
        self.declare_output_port("state", 2, lambda c: c.continuous_state, feedthrough=False)

    def do_calc_time_derivatives(self, context):
        q, qdot = context.continuous_state
        u = self.eval_input(context, "u")[0]
        return [qdot, (u - self.m * G * self.l * math.sin(q)) / (self.m * self.l**2)]


def test_joint_pd_settles_where_the_spring_balances_gravity():
    kp, kd, q_des = 40.0, 6.0, 1.0
    builder = rome.DiagramBuilder()
    builder.add_system(JointPendulum())
    gains = rome.JointPdGains(kp=[kp], kd=[kd], q_des=[q_des], u_ff=[0.0])
    assert repr(gains).startswith("JointPdGains(kp=")
    builder.add_system(rome.JointPdController("pd", np.eye(1), gains))
    builder.connect("pendulum", "state", "pd", "state")
    builder.connect("pd", "u", "pendulum", "u")
    diagram = builder.build()
    sim = rome.Simulator(diagram, rome.SimulatorConfig(relative_tolerance=1e-10))
    assert sim.advance_to(20.0).ok()
    q = diagram.get_continuous_state(sim.context)[0]
    lo, hi = 0.0, q_des  # kp (q_des - q) - m g l sin q is decreasing in q on [0, q_des]
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if kp * (q_des - mid) - 2.0 * G * 0.6 * math.sin(mid) > 0 else (lo, mid)
    assert q == pytest.approx(lo, abs=1e-7)


def test_controller_params_have_keyword_constructors():
    p = rome.TaskSpaceQpParams(min_normal_force_N=5.0, failure_policy=rome.QpFailurePolicy.hold_previous)
    assert p.min_normal_force_N == 5.0 and "min_normal_force_N=5.0" in repr(p)
    c = rome.ClfQpParams(epsilon=0.05)
    assert c.epsilon == 0.05 and repr(c).startswith("ClfQpParams(update_period_s=0.001")
    with pytest.raises(ValueError, match="gain .kd. has size 2, expected nu = 1"):
        rome.JointPdController("pd", np.eye(1), rome.JointPdGains(kp=[1.0], kd=[1.0, 2.0], q_des=[0.0], u_ff=[0.0]))
