#!/usr/bin/env python3
"""Cost per call of a LeafSystem written in Python, against the same block in C++.

The LIP flow (x' = L / z0, L' = g x) is simulated for the same time with the same settings twice: as the C++
LinearInvertedPendulumSystem and as a Python subclass of rome.LeafSystem; a second pair adds an output port read by a
C++ Gain at a 1 kHz zero-order hold. The overhead per call is the extra wall time divided by the number of calls into
Python (derivative evaluations, output evaluations).

usage: PYTHONPATH=build/python /usr/bin/python3 python/benchmarks/leaf_system_overhead.py
"""
import time

import rome

Z0, G = 0.8, 9.81
END_S = 20.0
REPEATS = 5


class PythonLip(rome.LeafSystem):
    def __init__(self):
        super().__init__("lip")
        self.declare_continuous_state([-0.15, 0.5])
        self.declare_output_port("state", 2, self.state, feedthrough=False)
        self.output_calls = 0

    def do_calc_time_derivatives(self, context):
        x, L = context.continuous_state
        return [L / Z0, G * x]

    def state(self, context):
        self.output_calls += 1
        return context.continuous_state


def diagram(python, sampled):
    builder = rome.DiagramBuilder()
    lip = builder.add_system(PythonLip() if python else rome.LinearInvertedPendulumSystem("lip", z0=Z0, gravity=G))
    if sampled:  # a 1 kHz zero-order hold reads the LIP's output port
        builder.add_system(rome.ZeroOrderHold("zoh", 1e-3, 2))
        builder.connect("lip", "state", "zoh", "u")
    return builder.build(), lip


def best_run(python, sampled, end_s):
    best = None
    for _ in range(REPEATS):
        d, lip = diagram(python, sampled)
        config = rome.SimulatorConfig(scheme=rome.IntegrationScheme.explicit_runge_kutta,
                                      explicit_rk_method=rome.ExplicitRungeKuttaMethod.bogacki_shampine_32,
                                      relative_tolerance=1e-8, absolute_tolerance=1e-10)
        sim = rome.Simulator(d, config)
        sim.initialize()
        start = time.perf_counter()
        sim.advance_to(end_s)
        wall = time.perf_counter() - start
        outputs = lip.output_calls if python else 0
        if best is None or wall < best[0]:
            best = (wall, sim.statistics.rhs_evals, outputs)
    return best


def main():
    print(f"LIP over {END_S} s (explicit RK 3(2), rtol 1e-8), best of {REPEATS}")
    for sampled, end_s in ((False, END_S), (True, 2.0)):
        cpp = best_run(False, sampled, end_s)
        py = best_run(True, sampled, end_s)
        calls = py[1] + py[2]
        label = "derivatives + 1 kHz output reads" if sampled else "derivatives only"
        print(f"{label}: simulated {end_s} s")
        print(f"  C++ leaf:    {cpp[0] * 1e3:9.2f} ms, {cpp[1]} derivative evaluations")
        print(f"  Python leaf: {py[0] * 1e3:9.2f} ms, {py[1]} derivative evaluations, {py[2]} output evaluations")
        print(f"  overhead per Python call: {(py[0] - cpp[0]) / calls * 1e6:.2f} us")


if __name__ == "__main__":
    main()
