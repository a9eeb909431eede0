"""Planners from Python, checked against physics written here in numpy.

Momentum regulation: the LIP's cosh/sinh solution reaches eps l at the predicted time with the predicted momentum, and
the impact map Eq. (17) with the planned u_des puts the COM on the orbit of energy E*. Vertical-COM MPC: the
minimum-norm input of the exact zero-order-hold double integrator (numpy's least squares). Spring-mass jump: the plan
re-integrated with numpy's RK4 on x'' = F/m - g lifts off (F = 0) with the speed sqrt(2 g H) of the apex rise H. Footed
H-LIP transition: the planned lateral states follow y'' = lambda^2 (y - y_stance) + u / (m z0) (SSP) and
y'' = u / (m z0) (DSP) between the nodes, integrated in closed form.
"""
import math

import numpy as np
import pytest

import rome

G = 9.81


def test_momentum_regulation_predicts_the_lip_and_lands_on_the_target_orbit():
    E_star, eps, l, z0 = 0.5, 0.6, 0.4, 0.8
    planner = rome.MomentumRegulationPlanner(rome.MomentumRegulationPlannerParams(target_orbital_energy=E_star))
    x, L = -0.1, 0.6
    plan = planner.plan(rome.MomentumRegulationInput(p_com_x=x, p_com_z=z0, pdot_com_x=L / z0, L_y=L, step_length=l,
                                                     step_height=0.0, pre_impact_com_height=z0))
    assert plan["ok"], plan
    lam = math.sqrt(G / z0)
    T = plan["time_to_impact"]
    b = L / (z0 * lam)
    assert x * math.cosh(lam * T) + b * math.sinh(lam * T) == pytest.approx(eps * l, rel=1e-9)
    L_T = z0 * lam * (x * math.sinh(lam * T) + b * math.cosh(lam * T))
    assert plan["L_pre_impact"] == pytest.approx(L_T, rel=1e-9)
    # Eq. (17) on flat ground: L+ = L- + l u_des, at x+ = (eps - 1) l; its orbital energy is E*.
    L_plus = plan["L_pre_impact"] + l * plan["u_des"]
    x_plus = (eps - 1) * l
    assert (L_plus / z0) ** 2 - lam**2 * x_plus**2 == pytest.approx(E_star, rel=1e-9)
    after = rome.MomentumRegulationPlanner.impact_map(eps * l, plan["L_pre_impact"], L_T / z0, plan["u_des"], l, 0.0)
    assert list(after) == pytest.approx([x_plus, L_plus], rel=1e-12)


def test_vertical_com_mpc_is_the_minimum_norm_input():
    N, T, p0, v0, pf, vf = 20, 0.4, 0.80, 0.05, 0.78, -0.2
    mpc = rome.VerticalComMpc(rome.VerticalComMpcParams(horizon_steps=N))
    r = mpc.solve(p0, v0, pf, vf, T)
    assert r["status"] == "optimal" and not r["terminal_relaxed"]
    dt = T / N
    # z_N = A^N z_0 + sum_k A^(N-1-k) B u_k with A = [1 dt; 0 1], B = [dt^2/2; dt].
    rows = np.array([[dt**2 / 2 + (N - 1 - k) * dt**2 for k in range(N)], [dt] * N])
    rhs = np.array([pf - p0 - v0 * T, vf - v0])
    u = np.linalg.lstsq(rows, rhs, rcond=None)[0]
    assert np.all(u > -G)  # the contact bound is inactive, so the QP's optimum is the least-norm solution
    assert np.allclose(r["inputs"], u, atol=1e-8)
    assert r["positions"][-1] == pytest.approx(pf, abs=1e-9)
    assert r["velocities"][-1] == pytest.approx(vf, abs=1e-9)


def leg_polynomial(c, L):
    return c.c0 + c.c1 * L + c.c2 * L**2 + c.c4 * L**4


def test_spring_mass_jump_lifts_off_with_the_apex_rise_speed():
    rom = rome.SpringMassParams()
    H = 0.15
    planner = rome.SpringMassJumpPlanner(rom, rome.SpringMassJumpParams(apex_rise=H))
    z_start = rome.SpringMassModel(rom).static_state(0.85)
    plan = planner.solve(z_start)
    assert plan["success"], plan["message"]
    t, z, v = plan["times"], plan["states"], plan["inputs"]

    def f(zz, acc):
        x, xdot, L, Ldot = zz
        F = rom.n_legs * (leg_polynomial(rom.leg.stiffness, L) * (L - x) +
                          leg_polynomial(rom.leg.damping, L) * (Ldot - xdot))
        return np.array([xdot, F / rom.mass - G, Ldot, acc])

    state = np.array(z_start, dtype=float)
    substeps = 50
    for k in range(len(t) - 1):  # RK4 with the plan's first-order hold of L''
        h = (t[k + 1] - t[k]) / substeps
        for j in range(substeps):
            s0, s1 = j / substeps, (j + 0.5) / substeps
            a0, a1, a2 = (v[k] + s * (v[k + 1] - v[k]) for s in (s0, s1, (j + 1) / substeps))
            k1 = f(state, a0)
            k2 = f(state + h / 2 * k1, a1)
            k3 = f(state + h / 2 * k2, a1)
            k4 = f(state + h * k3, a2)
            state = state + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    assert state == pytest.approx(z[:, -1], abs=5e-3)
    assert state[1] == pytest.approx(math.sqrt(2 * G * H), rel=1e-2)  # x + xdot^2 / (2 g) = x + H
    x, xdot, L, Ldot = state
    lift_off_force = rom.n_legs * (leg_polynomial(rom.leg.stiffness, L) * (L - x) +
                                   leg_polynomial(rom.leg.damping, L) * (Ldot - xdot))
    assert abs(lift_off_force) < 0.02 * rom.mass * G


def lateral_step(y, ydot, dt, a, pivot=None):
    """One zero-order-hold interval of the lateral dynamics: SSP y'' = lam^2 (y - pivot) + a, DSP y'' = a."""
    if pivot is None:
        return y + ydot * dt + a * dt**2 / 2, ydot + a * dt
    lam = math.sqrt(G / 0.9)
    c = pivot - a / lam**2
    return (c + (y - c) * math.cosh(lam * dt) + ydot / lam * math.sinh(lam * dt),
            (y - c) * lam * math.sinh(lam * dt) + ydot * math.cosh(lam * dt))


def test_footed_hlip_transition_states_follow_the_lateral_dynamics():
    params = rome.FootedHlipTransitionParams()
    m, z0, left_y = params.mass, 0.9, 0.1
    times = np.linspace(0.0, 0.5, 11)  # DSP 0.1 s (2 intervals), then SSP on the left foot 0.4 s (8 intervals)
    ssp = [False] * 2 + [True] * 8
    weight = m * G
    left = np.concatenate([np.full(3, weight / 2), np.full(8, weight)])
    right = np.concatenate([np.full(3, weight / 2), np.zeros(8)])
    # A feasible motion: ankle torques inside the ZMP bounds (|u| <= W F), integrated here; its end is the target.
    feasible_left = np.array([5.0, 5.0] + [10.0] * 8 + [0.0])
    feasible_right = np.array([5.0, 5.0] + [0.0] * 9)
    y, ydot = 0.02, 0.0
    for k in range(10):
        a = (feasible_left[k] + feasible_right[k]) / (m * z0)
        y, ydot = lateral_step(y, ydot, times[k + 1] - times[k], a, left_y if ssp[k] else None)
    data = rome.FootedHlipTransitionData(node_times=times, single_support=ssp, stance_left=True,
                                         left_normal_force=left, right_normal_force=right, left_foot_y=left_y,
                                         right_foot_y=-0.1, z0=z0, initial_state=[0.02, 0.0], final_state=[y, ydot])
    plan = rome.FootedHlipTransitionPlanner(params).solve(data)
    assert plan["success"], plan["message"]
    Y = plan["states"]
    u_total = plan["left_torque"] + plan["right_torque"]
    assert list(Y[:, -1]) == pytest.approx([y, ydot], abs=1e-9)
    for k in range(10):
        a = u_total[k] / (m * z0)
        expected = lateral_step(*Y[:, k], times[k + 1] - times[k], a, left_y if ssp[k] else None)
        assert list(expected) == pytest.approx(list(Y[:, k + 1]), abs=1e-9)
    # Eq. (14): the COP stays on the soles; Eq. (15): no more effort than the feasible motion's.
    assert np.all(np.abs(plan["left_torque"]) <= params.foot_width_left_of_ankle * left + 1e-9)
    assert np.all(np.abs(plan["right_torque"]) <= params.foot_width_right_of_ankle * right + 1e-9)
    assert plan["cost"] <= np.sum(feasible_left**2 + feasible_right**2) + 1e-9
