"""The periodic aSLIP gait planner from Python (walking paper Eq. (4)-(5)) against the aSLIP's physics in numpy.

The ground reactions are recomputed here from the published stiffness and damping polynomials (walking paper,
Appendix 3: K(L) = c (k4 L^4 + k2 L^2 + k1 L + k0), D(L) likewise, force along the leg from the foot to the mass), the
mass's velocity change over each domain against the impulse of those forces and gravity, the gait's periodicity with
the legs swapped one step ahead, and every stance force inside the friction cone.
"""
import numpy as np
import pytest

import rome


def leg_force(aslip, x, leg, foot_x):
    """[G_x, G_z] [N] of leg `leg` (state [x, z, xdot, zdot, L_0, L_1, Ldot_0, Ldot_1]) standing at (foot_x, 0)."""
    dx, dz = x[0] - foot_x, x[1]
    r = np.hypot(dx, dz)
    ex, ez = dx / r, dz / r
    r_dot = ex * x[2] + ez * x[3]
    L, L_dot = x[4 + leg], x[6 + leg]
    K = aslip.spring_scale * (aslip.k4 * L**4 + aslip.k2 * L**2 + aslip.k1 * L + aslip.k0)
    D = aslip.spring_scale * (aslip.d4 * L**4 + aslip.d2 * L**2 + aslip.d1 * L + aslip.d0)
    force = K * (L - r) + D * (L_dot - r_dot)
    return np.array([force * ex, force * ez])


@pytest.mark.parametrize("step_length, ssp, dsp", [(0.30, 0.40, 0.10), (0.40, 0.35, 0.12)])
def test_periodic_gait_obeys_the_aslip_physics(step_length, ssp, dsp):
    params = rome.AslipPeriodicGaitParams(step_length=step_length, ssp_duration=ssp, dsp_duration=dsp)
    gait = rome.AslipPeriodicGaitPlanner(params).solve(seed=1)
    assert gait["success"], gait["message"]
    aslip, m, g = params.aslip, params.aslip.mass, params.aslip.gravity
    ssp_phase, dsp_phase = gait["phases"]
    assert ssp_phase["duration"] == pytest.approx(ssp) and dsp_phase["duration"] == pytest.approx(dsp)
    stances = {"ssp": [(0, 0.0)], "dsp": [(0, 0.0), (1, step_length)]}  # leg, foot x: leg 1 lands at x = l
    for phase in gait["phases"]:
        X, t = phase["states"], phase["times"]
        G = np.zeros((4, X.shape[1]))
        for k in range(X.shape[1]):
            for leg, foot in stances[phase["name"]]:
                G[2 * leg:2 * leg + 2, k] = leg_force(aslip, X[:, k], leg, foot)
        np.testing.assert_allclose(phase["ground_reactions"], G, atol=1e-6 * m * g)
        tol = 1e-6 * m * g  # [N] the NLP's rows hold to its constraint tolerance, not exactly
        for leg, _ in stances[phase["name"]]:
            assert (G[2 * leg + 1] >= -tol).all()  # unilateral
            assert (np.abs(G[2 * leg]) <= params.friction_coefficient * G[2 * leg + 1] + tol).all()
        # Newton on the point mass, integrated over the domain (trapezoid, the collocation's own quadrature):
        # m (v_end - v_0) = integral of (sum G - m g e_z) dt.
        impulse_x = np.trapz(G[0] + G[2], t)
        impulse_z = np.trapz(G[1] + G[3] - m * g, t)
        assert m * (X[2, -1] - X[2, 0]) == pytest.approx(impulse_x, abs=1e-6 * m * g * t[-1])
        assert m * (X[3, -1] - X[3, 0]) == pytest.approx(impulse_z, abs=1e-5 * m * g * t[-1])
    # Periodic: the last DSP state, one step back and with the legs swapped, is the first SSP state.
    end = dsp_phase["states"][:, -1].copy()
    end[0] -= step_length
    end[[4, 5, 6, 7]] = end[[5, 4, 7, 6]]
    np.testing.assert_allclose(end, ssp_phase["states"][:, 0], atol=1e-6)
    speed = step_length / (ssp + dsp)
    mean_xdot = np.trapz(np.concatenate([ssp_phase["states"][2], dsp_phase["states"][2]]),
                         np.concatenate([ssp_phase["times"], dsp_phase["times"]])) / (ssp + dsp)
    assert mean_xdot == pytest.approx(speed, rel=1e-4)


def test_periodic_gait_planner_refuses_a_negative_step_length():
    with pytest.raises(ValueError, match=r"step_length.*-0\.3"):
        rome.AslipPeriodicGaitPlanner(rome.AslipPeriodicGaitParams(step_length=-0.3))
