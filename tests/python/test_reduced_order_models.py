"""Reduced-order models from Python: the stepping LIP, the H-LIP and the spring-mass hopping model.

Expected values come from closed forms written here in numpy: the LIP's cosh/sinh solution and its orbital energy
E = xdot^2 - lambda^2 x^2, the impact map Eq. (17) of the stepping-stones paper, the H-LIP's step-to-step map composed
from its DSP (constant velocity) and SSP (cosh/sinh) flows, and the spring-mass energy 1/2 m xdot^2 + m g x +
1/2 n K(L) s^2.
"""
import math

import numpy as np
import pytest

import rome

G = 9.81


def simulate(system, inputs, t_end, ports, period=0.002, rtol=1e-10):
    builder = rome.DiagramBuilder()
    builder.add_system(system)
    for port, value in inputs.items():
        builder.fix_input(system.name, port, value)
    logger = rome.add_vector_logger(builder, "logger", [(system.name, p) for p in ports], period)
    diagram = builder.build()
    sim = rome.Simulator(diagram, rome.SimulatorConfig(relative_tolerance=rtol, absolute_tolerance=1e-12))
    status = sim.advance_to(t_end)
    assert status.ok(), status.message
    return logger.data(diagram.get_subsystem_context(logger, sim.context)), sim


def test_lip_flow_energy_and_time_to_reach_follow_the_closed_form():
    lip = rome.LinearInvertedPendulum(rome.LinearInvertedPendulumParams(z0=0.8))
    lam = math.sqrt(G / 0.8)
    assert lip.lambda_ == pytest.approx(lam)
    x0, L0, t = -0.15, 0.5, 0.37
    b = L0 / (0.8 * lam)
    x_t = x0 * math.cosh(lam * t) + b * math.sinh(lam * t)
    L_t = 0.8 * lam * (x0 * math.sinh(lam * t) + b * math.cosh(lam * t))
    assert lip.flow([x0, L0], t) == pytest.approx([x_t, L_t], rel=1e-12)
    assert lip.orbital_energy([x0, L0]) == pytest.approx((L0 / 0.8) ** 2 - lam**2 * x0**2, rel=1e-12)
    # The time at which x reaches x_t is t.
    assert lip.time_to_reach(x_t, [x0, L0]) == pytest.approx(t, rel=1e-9)
    # Not enough energy to reach x = 1 m: None.
    assert lip.time_to_reach(1.0, [-0.3, 0.1]) is None


def test_stepping_lip_conserves_orbital_energy_between_impacts_and_applies_eq17():
    z0, l, h, u = 0.8, 0.4, 0.05, -0.1
    params = rome.SteppingLinearInvertedPendulumParams(lip=rome.LinearInvertedPendulumParams(z0=z0), initial_x=-0.15,
                                                       initial_L=0.5, impact_fraction=0.6)
    system = rome.SteppingLinearInvertedPendulum("stepping_lip", params)
    log, sim = simulate(system, {"step": [l, h], "impact_vertical_velocity": [u]}, 2.0, ["state", "orbital_energy"], period=0.001)
    lam2 = G / z0
    x, L = log["stepping_lip.state[0]"], log["stepping_lip.state[1]"]
    energy = (L / z0) ** 2 - lam2 * x**2
    assert np.allclose(log["stepping_lip.orbital_energy[0]"], energy, rtol=1e-9, atol=1e-12)
    events = [e for e in sim.statistics.events if "touchdown" in e.guard]
    assert len(events) >= 2, [e.time for e in events]
    t_impact = [e.time for e in events]
    # Between impacts E is constant (the LIP's first integral), to the integrator's tolerance.
    segments = np.digitize(log["time"], t_impact)
    for k in range(len(t_impact)):
        inside = segments == k
        inside &= np.all(np.abs(log["time"][:, None] - np.array(t_impact)[None, :]) > 1e-3, axis=1)
        if inside.sum() > 2:
            assert np.ptp(energy[inside]) < 1e-7
    # Eq. (17) at the first impact: x+ = x- - l, L+ = L- + l u - h L-/z0, with x- = eps l.
    x_minus = 0.6 * l
    L_minus = z0 * math.sqrt(energy[0] + lam2 * x_minus**2)
    flow = rome.LinearInvertedPendulum(rome.LinearInvertedPendulumParams(z0=z0))
    after = flow.flow([x_minus - l, L_minus + l * u - h * L_minus / z0], 0.0)
    i = np.searchsorted(log["time"], t_impact[0]) + 1
    expected = flow.flow(after, log["time"][i] - t_impact[0])
    assert [x[i], L[i]] == pytest.approx(list(expected), rel=1e-6, abs=1e-8)


def test_hlip_step_to_step_map_is_the_composed_dsp_and_ssp_flow():
    p = rome.HybridLinearInvertedPendulumParams(z0=0.9, ssp_duration=0.4, dsp_duration=0.1)
    hlip = rome.HybridLinearInvertedPendulum(p)
    lam = math.sqrt(G / 0.9)
    c, s = math.cosh(lam * 0.4), math.sinh(lam * 0.4)
    ssp = np.array([[c, s / lam], [lam * s, c]])
    dsp = np.array([[1.0, 0.1], [0.0, 1.0]])
    # Pre-impact state [p, v] about the stance foot: DSP at constant velocity, the new foot u ahead, then the SSP.
    A = ssp @ dsp
    B = ssp @ np.array([-1.0, 0.0])
    assert np.allclose(hlip.step_to_step_A(), A, rtol=1e-12)
    assert np.allclose(hlip.step_to_step_B(), B, rtol=1e-12)
    assert hlip.sigma2 == pytest.approx(lam * math.tanh(lam * 0.4 / 2))
    # The P1 orbit of step 0.3 m is a fixed point of the map.
    x = np.asarray(hlip.p1_pre_impact_state(0.3))
    assert np.allclose(A @ x + B * 0.3, x, atol=1e-12)
    # Deadbeat: two steps from any state reach the P1 orbit of the step the gain targets.
    K = np.asarray(hlip.deadbeat_gain()).reshape(2)
    closed = A + np.outer(B, K)
    assert np.allclose(np.linalg.matrix_power(closed, 2), 0, atol=1e-9)


def test_spring_mass_block_conserves_energy_without_damping():
    stiffness = rome.published_leg_stiffness().stiffness
    model = rome.SpringMassParams(mass=33.3, n_legs=2, leg=rome.LegStiffness(stiffness=stiffness))
    L = 0.8
    z0 = np.array([0.74, 0.0, L, 0.0])  # compressed below the static deflection: the mass bounces
    system = rome.SpringMassSystem("spring_mass", rome.SpringMassSystemParams(model=model, initial_state=z0))
    log, _ = simulate(system, {"leg_length_acceleration": [0.0]}, 0.6, ["state", "energy"], rtol=1e-11)
    x, xdot = log["spring_mass.state[0]"], log["spring_mass.state[1]"]
    K = stiffness.c0 + stiffness.c1 * L + stiffness.c2 * L**2 + stiffness.c4 * L**4
    s = np.maximum(L - x, 0.0)
    energy = 0.5 * 33.3 * xdot**2 + 33.3 * G * x + 0.5 * 2 * K * s**2
    assert np.ptp(energy) < 1e-6 * energy[0]
    assert np.ptp(x) > 0.02  # it bounces: the energy moves between the spring, the height and the speed
    total = log["spring_mass.energy[0]"] + log["spring_mass.energy[1]"] + log["spring_mass.energy[2]"]
    assert np.allclose(total, energy, rtol=1e-9)
    rom = rome.SpringMassModel(model)
    assert rom.energy(z0)["total"] == pytest.approx(energy[0], rel=1e-12)
    # Static state: n K(L) s = m g.
    zs = rom.static_state(L)
    assert 2 * K * (L - zs[0]) == pytest.approx(33.3 * G, rel=1e-9)


def test_params_have_keyword_constructors_and_a_readable_repr():
    p = rome.HybridLinearInvertedPendulumParams(z0=1.0)
    assert repr(p).startswith("HybridLinearInvertedPendulumParams(z0=1.0, ssp_duration=")
    with pytest.raises(TypeError, match="no field 'height'"):
        rome.LinearInvertedPendulumParams(height=1.0)


def test_aslip_without_damping_conserves_energy_and_its_grf_is_the_leg_force():
    """Both legs on the ground at fixed rest lengths, no damping: the mass bounces on two linear springs of stiffness
    c K(L); 1/2 m |pdot|^2 + m g z + sum 1/2 c K(L) s^2 is constant, and the ground reaction of each leg is
    F e with F = c K(L) s along the leg (walking paper, Appendix 3)."""
    aslip = rome.ActuatedSpringLoadedInvertedPendulumParams(d4=0.0, d2=0.0, d1=0.0, d0=0.0)
    L0, feet = 0.97, (-0.05, 0.05)
    state = [0.01, 0.935, 0.0, 0.0, L0, L0, 0.0, 0.0]
    params = rome.ActuatedSpringLoadedInvertedPendulumSystemParams(aslip=aslip, initial_state=state,
                                                                   initial_left_foot_x=feet[0],
                                                                   initial_right_foot_x=feet[1])
    system = rome.ActuatedSpringLoadedInvertedPendulumSystem("aslip", params)
    log, sim = simulate(system, {"leg_length_acceleration": [0.0, 0.0], "next_foothold": [0.3]}, 1.0,
                        ["state", "grf"])
    assert not [e for e in sim.statistics.events if e.system == "aslip"]  # stays in double support
    c, m = aslip.spring_scale, aslip.mass
    K = c * (aslip.k4 * L0**4 + aslip.k2 * L0**2 + aslip.k1 * L0 + aslip.k0)
    x, z = log["aslip.state.x"], log["aslip.state.z"]
    xdot, zdot = log["aslip.state.xdot"], log["aslip.state.zdot"]
    energy = 0.5 * m * (xdot**2 + zdot**2) + m * G * z
    for side, foot in zip(("left", "right"), feet):
        r = np.hypot(x - foot, z)
        s = L0 - r
        energy += 0.5 * K * s**2
        F = K * s
        assert np.allclose(log[f"aslip.grf.{side}_x"], F * (x - foot) / r, atol=1e-6)
        assert np.allclose(log[f"aslip.grf.{side}_z"], F * z / r, atol=1e-6)
    assert np.ptp(z) > 0.005  # it moves
    assert np.ptp(energy) < 1e-7 * energy[0]
