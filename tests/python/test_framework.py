"""Framework from Python: DiagramBuilder by name, Simulator config and statuses, logger columns, state get/set.

Expected values come from the LIP's closed-form solution (x = a cosh(lt) + b sinh(lt)) and the zero-order hold's
definition, never from the code under test.
"""
import math

import numpy as np
import pytest

import rome

Z0, G = 0.8, 9.81
LAMBDA = math.sqrt(G / Z0)


def lip_closed_form(t, x0, L0):
    """State [x, L] of x' = L / z0, L' = g x (Eq. (12) of the stepping-stones paper)."""
    b = L0 / (Z0 * LAMBDA)
    x = x0 * np.cosh(LAMBDA * t) + b * np.sinh(LAMBDA * t)
    L = Z0 * LAMBDA * (x0 * np.sinh(LAMBDA * t) + b * np.cosh(LAMBDA * t))
    return x, L


def lip_diagram(x0=-0.15, L0=0.5, log_period=0.01):
    builder = rome.DiagramBuilder()
    lip = builder.add_system(rome.LinearInvertedPendulumSystem("lip", initial_x=x0, initial_L=L0, z0=Z0, gravity=G))
    logger = rome.add_vector_logger(builder, "logger", [("lip", "state")], log_period)
    return builder.build("lip_diagram"), lip, logger


def tight_config():
    return rome.SimulatorConfig(relative_tolerance=1e-10, absolute_tolerance=1e-12)


def test_logged_columns_follow_the_closed_form():
    diagram, lip, logger = lip_diagram()
    sim = rome.Simulator(diagram, tight_config())
    status = sim.advance_to(0.5)
    assert status.kind == "limit" and status.ok() and status.reason == rome.SimulatorStatus.Reason.reached_boundary_time
    assert status.time == pytest.approx(0.5)
    data = logger.data(diagram.get_subsystem_context(logger, sim.context))
    names = logger.column_names()
    assert names[0] == "time" and list(data.keys()) == names and len(names) == 3
    assert all(name.startswith("lip.state") for name in names[1:])
    t = data["time"]
    np.testing.assert_allclose(t, np.arange(len(t)) * 0.01, atol=1e-12)  # sampled every 10 ms from t = 0
    assert len(t) == 50  # samples at 0, 0.01, ..., 0.49; the one due at t_final is left for the next advance
    x, L = lip_closed_form(t, -0.15, 0.5)
    np.testing.assert_allclose(data[names[1]], x, rtol=0, atol=1e-8)
    np.testing.assert_allclose(data[names[2]], L, rtol=0, atol=1e-8)


def test_state_set_from_numpy_is_simulated_from():
    diagram, lip, _ = lip_diagram()
    sim = rome.Simulator(diagram, tight_config())
    diagram.set_continuous_state(sim.context, np.array([0.05, -0.1]))
    np.testing.assert_array_equal(diagram.get_continuous_state(sim.context), [0.05, -0.1])
    sim.advance_to(0.3)
    np.testing.assert_allclose(diagram.get_continuous_state(sim.context), lip_closed_form(0.3, 0.05, -0.1), atol=1e-8)
    # The leaf's own context is a view into the diagram's: setting it there changes the run.
    leaf_context = diagram.get_subsystem_context(lip, sim.context)
    leaf_context.continuous_state = [0.0, 0.0]
    sim.initialize()
    sim.advance_to(0.6)
    np.testing.assert_array_equal(leaf_context.continuous_state, [0.0, 0.0])  # the LIP's equilibrium
    assert leaf_context.time == pytest.approx(0.6)


def test_monitor_ends_the_run_with_its_status():
    diagram, lip, _ = lip_diagram()
    sim = rome.Simulator(diagram, rome.SimulatorConfig(relative_tolerance=1e-10, absolute_tolerance=1e-12, max_step_s=1e-3))

    def crossed(context):
        if diagram.get_continuous_state(context)[0] > 0:
            return rome.EventStatus.reached_termination("COM over the foot")
        return None

    sim.add_monitor(crossed, "crossing")
    status = sim.advance_to(2.0)
    # x(t*) = 0: tanh(l t*) = -x0 / b, b = L0 / (z0 l).
    t_star = math.atanh(0.15 / (0.5 / (Z0 * LAMBDA))) / LAMBDA
    assert status.kind == "success" and not status.ok()
    assert status.system == "crossing" and "COM over the foot" in status.message
    assert t_star <= status.time <= t_star + 1e-3 + 1e-12


def test_discrete_state_of_a_zero_order_hold():
    builder = rome.DiagramBuilder()
    builder.add_system(rome.ConstantVectorSource("source", [2.0, -1.0]))
    zoh = builder.add_system(rome.ZeroOrderHold("zoh", 0.1, 2))
    builder.connect("source", "y", "zoh", "u")
    builder.export_output("zoh", "y", "held")
    diagram = builder.build()
    sim = rome.Simulator(diagram)
    context = diagram.get_subsystem_context(zoh, sim.context)
    context.discrete_state = np.array([5.0, 6.0])
    np.testing.assert_array_equal(diagram.eval_output(sim.context, "held"), [5.0, 6.0])  # y = the held value
    np.testing.assert_array_equal(diagram.get_discrete_state(sim.context), [5.0, 6.0])
    sim.advance_to(0.15)  # samples at t = 0 and 0.1
    np.testing.assert_array_equal(context.discrete_state, [2.0, -1.0])
    assert sim.statistics.discrete_samples == 2


def test_config_keywords_and_repr():
    config = rome.SimulatorConfig(relative_tolerance=1e-6, scheme=rome.IntegrationScheme.explicit_runge_kutta)
    assert config.relative_tolerance == 1e-6 and config.scheme == rome.IntegrationScheme.explicit_runge_kutta
    assert "relative_tolerance=1e-06" in repr(config)
    with pytest.raises(TypeError, match="no field 'tolerance'"):
        rome.SimulatorConfig(tolerance=1e-6)
