"""LeafSystem subclassed in Python: a pendulum's energy and period against the closed form (the period from a guard
that fires at each upward zero crossing), a periodic discrete update's count, and a Python plant in a diagram with the
C++ LqrController against the closed-loop matrix exponential computed in numpy."""
import math

import numpy as np
import pytest

import rome

G, L, M = 9.81, 0.9, 1.4


class Pendulum(rome.LeafSystem):
    """theta'' = -(g/l) sin(theta); a guard counts the upward zero crossings of theta in the discrete state."""

    def __init__(self, theta0):
        super().__init__("pendulum")
        self.declare_continuous_state([theta0, 0.0])
        self.declare_discrete_state([0.0])
        self.declare_output_port("state", ["theta", "omega"], lambda c: c.continuous_state, feedthrough=False)
        self.declare_guard("upward_zero", lambda c: c.continuous_state[0], rome.CrossingDirection.rising, self.count)

    def do_calc_time_derivatives(self, context):
        theta, omega = context.continuous_state
        return [omega, -G / L * math.sin(theta)]

    @staticmethod
    def count(context, component, state):
        state.discrete = state.discrete + 1.0


def energy(theta, omega):
    return 0.5 * M * L ** 2 * omega ** 2 - M * G * L * np.cos(theta)


def closed_form_period(theta0):
    """T = 4 sqrt(l/g) K(sin(theta0/2)), K by the arithmetic-geometric mean."""
    a, b = 1.0, math.sqrt(1.0 - math.sin(theta0 / 2) ** 2)
    while abs(a - b) > 1e-15:
        a, b = 0.5 * (a + b), math.sqrt(a * b)
    return 4.0 * math.sqrt(L / G) * math.pi / (2.0 * a)


def test_pendulum_conserves_energy_and_swings_with_the_closed_form_period():
    theta0 = 2.0  # a large swing: far from the small-angle period
    builder = rome.DiagramBuilder()
    pendulum = builder.add_system(Pendulum(theta0))
    logger = rome.add_vector_logger(builder, "logger", [("pendulum", "state")], 0.01)
    diagram = builder.build()
    sim = rome.Simulator(diagram, rome.SimulatorConfig(relative_tolerance=1e-11, absolute_tolerance=1e-12))
    status = sim.advance_to(8.0)
    assert status.kind == "limit"
    data = logger.data(diagram.get_subsystem_context(logger, sim.context))
    e = energy(data["pendulum.state.theta"], data["pendulum.state.omega"])
    e0 = energy(theta0, 0.0)
    assert np.max(np.abs(e - e0)) < 1e-7 * abs(e0)
    crossings = [event.time for event in sim.statistics.events if event.guard == "upward_zero"]
    period = closed_form_period(theta0)
    assert len(crossings) == int((8.0 - 0.75 * period) // period) + 1  # first upward crossing at 3/4 of a period
    assert crossings[0] == pytest.approx(0.75 * period, rel=1e-8)
    np.testing.assert_allclose(np.diff(crossings), period, rtol=1e-8)
    assert diagram.get_subsystem_context(pendulum, sim.context).discrete_state[0] == len(crossings)


class Counter(rome.LeafSystem):
    def __init__(self, period):
        super().__init__("counter")
        self.declare_discrete_state([0.0])
        self.declare_periodic_discrete_update(period, 0.0, lambda c: c.discrete_state + 1.0)


def test_periodic_update_runs_at_every_sample_time():
    builder = rome.DiagramBuilder()
    counter = builder.add_system(Counter(0.01))
    diagram = builder.build()
    sim = rome.Simulator(diagram)
    sim.advance_to(0.995)  # samples at 0, 0.01, ..., 0.99
    assert diagram.get_subsystem_context(counter, sim.context).discrete_state[0] == 100


class DoubleIntegrator(rome.LeafSystem):
    """x'' = u / m: state [x, v], input u, output the state (no feedthrough)."""

    mass = 2.0

    def __init__(self, x0):
        super().__init__("plant")
        self.declare_continuous_state(x0)
        self.declare_input_port("u", 1)
        self.declare_output_port("x", 2, lambda c: c.continuous_state, feedthrough=False)

    def do_calc_time_derivatives(self, context):
        return [context.continuous_state[1], self.eval_input(context, "u")[0] / self.mass]


def expm(A):
    values, vectors = np.linalg.eig(A)
    return (vectors @ np.diag(np.exp(values)) @ np.linalg.inv(vectors)).real


def test_python_plant_with_the_cpp_lqr_follows_the_closed_loop_exponential():
    A = np.array([[0.0, 1.0], [0.0, 0.0]])
    B = np.array([[0.0], [1.0 / DoubleIntegrator.mass]])
    x0 = np.array([1.0, -0.5])
    builder = rome.DiagramBuilder()
    builder.add_system(DoubleIntegrator(x0))
    controller = builder.add_system(rome.LqrController("lqr", A, B, np.diag([10.0, 1.0]), np.eye(1), np.zeros(2), np.zeros(1)))
    builder.connect("plant", "x", "lqr", "x")
    builder.connect("lqr", "u", "plant", "u")
    diagram = builder.build()
    sim = rome.Simulator(diagram, rome.SimulatorConfig(relative_tolerance=1e-11, absolute_tolerance=1e-13))
    sim.advance_to(3.0)
    K = controller.K
    expected = expm((A - B @ K) * 3.0) @ x0
    np.testing.assert_allclose(diagram.get_continuous_state(sim.context), expected, rtol=1e-7, atol=1e-9)
    assert np.max(np.linalg.eigvals(A - B @ K).real) < 0


def test_a_python_leaf_is_freed_with_its_diagram():
    import gc
    import weakref

    class Source(rome.LeafSystem):
        def __init__(self):
            super().__init__("source")
            self.declare_continuous_state(1)
            self.declare_output_port("y", 1, self.output, feedthrough=False)  # a bound method of the leaf itself

        def output(self, context):
            return context.continuous_state

        def do_calc_time_derivatives(self, context):
            return [1.0]

    builder = rome.DiagramBuilder()
    leaf = builder.add_system(Source())
    builder.add_system(rome.ZeroOrderHold("zoh", 0.01, 1))
    builder.connect("source", "y", "zoh", "u")
    diagram = builder.build()
    sim = rome.Simulator(diagram)
    sim.advance_to(0.1)
    assert diagram.get_subsystem_context(leaf, sim.context).continuous_state[0] == pytest.approx(0.1)
    leaf_ref, diagram_ref = weakref.ref(leaf), weakref.ref(diagram)
    del builder, leaf, diagram, sim
    gc.collect()
    assert leaf_ref() is None and diagram_ref() is None
