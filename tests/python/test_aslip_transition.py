"""The transitional aSLIP planner from Python (walking paper Eq. (9)-(10)), standing -> a periodic gait, against the
footed aSLIP's physics in numpy.

The ground reactions are recomputed here from the published stiffness and damping polynomials and the ankle torques
(walking paper, Appendix 1 and 3: G_i = F_i e_i + (u_i / r_i) n_i, F_i = K(L_i)(L_i - r_i) + D(L_i)(Ldot_i - rdot_i)),
then checked against the point mass's velocity change (Newton, integrated with the collocation's trapezoid), the
ZMP bound of Eq. (10), the lift-off condition and the boundary states the transition must join.
"""
import numpy as np
import pytest

import rome


def ground_reaction(aslip, x, leg, foot_x, u):
    """[G_x, G_z] [N] of leg `leg` standing at (foot_x, 0) with ankle torque u [N m]."""
    dx, dz = x[0] - foot_x, x[1]
    r = np.hypot(dx, dz)
    e = np.array([dx, dz]) / r
    n = np.array([-e[1], e[0]])
    r_dot = e @ x[2:4]
    L, L_dot = x[4 + leg], x[6 + leg]
    K = aslip.spring_scale * (aslip.k4 * L**4 + aslip.k2 * L**2 + aslip.k1 * L + aslip.k0)
    D = aslip.spring_scale * (aslip.d4 * L**4 + aslip.d2 * L**2 + aslip.d1 * L + aslip.d0)
    return (K * (L - r) + D * (L_dot - r_dot)) * e + (u / r) * n


@pytest.fixture(scope="module")
def stand_to_gait():
    gait_params = rome.AslipPeriodicGaitParams(step_length=0.30, ssp_duration=0.40, dsp_duration=0.10)
    gait = rome.AslipPeriodicGaitPlanner(gait_params).solve(seed=1)
    assert gait["success"], gait["message"]
    params = rome.AslipTransitionParams(bounds=gait_params)
    standing = rome.AslipTransitionPlanner.standing_state(gait_params.aslip, gait["mean_height"])
    # The gait's SSP ends pre-impact with leg 0 (left) standing at x = 0: the transition's SSP stands on the left.
    data = rome.AslipTransitionData(initial_state=standing, final_state=gait["phases"][0]["states"][:, -1],
                                    left_foot_x=0.0, right_foot_x=0.0, lifting_leg=1)
    transition = rome.AslipTransitionPlanner(params).solve(data)
    assert transition["success"], transition["message"]
    return params, data, transition


def test_standing_state_carries_half_the_weight_on_each_leg():
    aslip = rome.ActuatedSpringLoadedInvertedPendulumParams()
    x = rome.AslipTransitionPlanner.standing_state(aslip, 0.88)
    for leg in (0, 1):
        np.testing.assert_allclose(ground_reaction(aslip, x, leg, 0.0, 0.0), [0.0, aslip.mass * aslip.gravity / 2],
                                   atol=1e-6 * aslip.mass * aslip.gravity)


def test_transition_joins_its_boundary_states_and_lifts_the_right_leg(stand_to_gait):
    params, data, transition = stand_to_gait
    dsp, ssp = transition["phases"]
    assert (dsp["name"], ssp["name"]) == ("dsp", "ssp")
    np.testing.assert_allclose(dsp["states"][:, 0], data.initial_state, atol=1e-6)
    np.testing.assert_allclose(ssp["states"][:, -1], data.final_state, atol=1e-6)
    np.testing.assert_allclose(dsp["states"][:, -1], ssp["states"][:, 0], atol=1e-9)  # continuous at lift-off
    assert params.min_dsp_duration - 1e-9 <= dsp["duration"] <= params.max_dsp_duration + 1e-9
    assert params.min_ssp_duration - 1e-9 <= ssp["duration"] <= params.max_ssp_duration + 1e-9
    m_g = params.bounds.aslip.mass * params.bounds.aslip.gravity
    assert abs(dsp["ground_reactions"][3, -1]) <= 1e-6 * m_g  # the lifting leg's G_z = 0 at the DSP's last node
    assert not ssp["ground_reactions"][2:].any()  # and nothing in the air


def test_transition_obeys_the_footed_aslip_physics(stand_to_gait):
    params, data, transition = stand_to_gait
    aslip = params.bounds.aslip
    m, g = aslip.mass, aslip.gravity
    tol = 1e-6 * m * g  # [N] the NLP's rows hold to its constraint tolerance
    for phase, legs in zip(transition["phases"], [(0, 1), (0,)]):
        X, U, t = phase["states"], phase["inputs"], phase["times"]
        G = np.zeros((4, X.shape[1]))
        for k in range(X.shape[1]):
            for leg in legs:
                G[2 * leg:2 * leg + 2, k] = ground_reaction(aslip, X[:, k], leg, 0.0, U[2 + leg, k])
        np.testing.assert_allclose(phase["ground_reactions"], G, atol=tol)
        for leg in legs:
            Gz, u = G[2 * leg + 1], U[2 + leg]
            assert (Gz >= -tol).all()
            assert (np.abs(G[2 * leg]) <= params.bounds.friction_coefficient * Gz + tol).all()
            # Eq. (10): the centre of pressure u / G_z stays on the sole, from the heel to the toe.
            assert (u >= -aslip.heel_length * Gz - 1e-6).all() and (u <= aslip.toe_length * Gz + 1e-6).all()
            assert (np.abs(u) <= params.max_ankle_torque + 1e-6).all()
        # m (v_end - v_0) = integral of (sum G - m g e_z) dt, with the collocation's trapezoid.
        assert m * (X[2, -1] - X[2, 0]) == pytest.approx(np.trapz(G[0] + G[2], t), abs=1e-5 * m * g * t[-1])
        assert m * (X[3, -1] - X[3, 0]) == pytest.approx(np.trapz(G[1] + G[3] - m * g, t), abs=1e-5 * m * g * t[-1])
    assert transition["phases"][1]["inputs"][2, -1] == pytest.approx(0.0, abs=1e-6)  # zero_final_ankle_torque


def test_transition_planner_refuses_a_bad_bound():
    with pytest.raises(ValueError, match="max_dsp_duration"):
        rome.AslipTransitionPlanner(rome.AslipTransitionParams(min_dsp_duration=0.5, max_dsp_duration=0.2))
