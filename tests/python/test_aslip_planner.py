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


def dijkstra(graph, params, allowed):
    """Cheapest start -> goal cost over the documented edges (every |dg_i| <= reach_i, cost 1 + w sum |dg_i|/reach_i)
    that `allowed(from, to)` keeps, computed here from the nodes alone."""
    nodes = [np.array(graph.node(i)) for i in range(graph.num_nodes)]
    reach = np.array(params.reach)
    cost = [np.inf] * len(nodes)
    cost[graph.start] = 0.0
    done = set()
    while len(done) < len(nodes):
        i = min((k for k in range(len(nodes)) if k not in done), key=lambda k: cost[k])
        if cost[i] == np.inf:
            break
        done.add(i)
        for j in range(len(nodes)):
            d = np.abs(nodes[j] - nodes[i])
            if j != i and (d <= reach + 1e-12).all() and allowed(nodes[i], nodes[j]):
                cost[j] = min(cost[j], cost[i] + 1 + params.step_cost_weight * (d / reach).sum())
    return cost[graph.goal]


def chain_cost(gaits, params):
    reach = np.array(params.reach)
    return sum(1 + params.step_cost_weight * (np.abs(np.subtract(b, a)) / reach).sum() for a, b in zip(gaits, gaits[1:]))


def test_gait_graph_chains_are_the_cheapest_over_the_feasible_edges():
    params = rome.GaitGraphParams(max_failed_transitions=1000)  # every failure below is a cheap Python call
    start, goal = (0.20, 0.40, 0.10, 0.20), (0.45, 0.35, 0.14, 0.30)
    graph = rome.GaitGraph(params, start, goal)
    path = graph.shortest_path()
    assert path[0] == graph.start and path[-1] == graph.goal
    gaits = [graph.node(i) for i in path]
    assert chain_cost(gaits, params) == pytest.approx(dijkstra(graph, params, lambda a, b: True))

    # A planner that can change the step length by at most 5 cm a transition (a larger change from the same gait
    # fails too, as the lazy search assumes): the chain found is the cheapest one over those edges.
    def short_steps(a, b):
        return abs(b[0] - a[0]) <= 0.05 + 1e-9

    tried = []
    chain = rome.GaitGraph(params, start, goal).shortest_feasible_chain(
        lambda depth, a, b: tried.append((a, b)) or short_steps(a, b))
    assert chain["found"], chain["message"]
    assert chain["transitions_tried"] == len(tried) and chain["transitions_failed"] > 0
    assert tuple(chain["gaits"][0]) == pytest.approx(start) and tuple(chain["gaits"][-1]) == pytest.approx(goal)
    assert all(short_steps(a, b) for a, b in zip(chain["gaits"], chain["gaits"][1:]))
    assert chain_cost(chain["gaits"], params) == pytest.approx(dijkstra(graph, params, short_steps))


def test_gait_graph_refuses_a_gait_outside_its_range():
    with pytest.raises(ValueError, match="0.9"):
        rome.GaitGraph(rome.GaitGraphParams(), (0.9, 0.40, 0.10, 0.20), (0.30, 0.40, 0.10, 0.20))
