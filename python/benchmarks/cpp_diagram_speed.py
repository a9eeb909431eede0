#!/usr/bin/env python3
"""A diagram of C++ blocks built and run from Python against the same diagram built and run from C++.

The diagram (python/benchmarks/cpp_diagram_speed.cc builds the same one in C++): a stepping LIP walking a periodic orbit
(an event per step), a spring-mass model settling on its leg, a 1 kHz zero-order hold of the spring-mass state and a
100 Hz logger. Each side times Simulator.advance_to (wall clock and the process's user CPU time, getrusage) over the
same simulated time, `repeats` runs a round, rounds alternating between the two sides, and the script prints the medians
(and minima) over all runs. On a shared machine the user CPU time is the steadier figure. The final states must agree
to every printed digit (exit 3 otherwise).

usage: PYTHONPATH=build/python /usr/bin/python3 python/benchmarks/cpp_diagram_speed.py build/python/cpp_diagram_speed \
           [seconds=50] [repeats=7] [rounds=3]
"""
import os
import resource
import statistics
import subprocess
import sys
import time

import rome


def build():
    builder = rome.DiagramBuilder()
    params = rome.SteppingLinearInvertedPendulumParams(impact_fraction=0.5)
    lip = builder.add_system(rome.SteppingLinearInvertedPendulum("stepping_lip", params))
    builder.add_system(rome.ConstantVectorSource("step", [0.4, 0.0]))
    builder.add_system(rome.ConstantVectorSource("impact_velocity", [0.0]))
    spring_mass = builder.add_system(rome.SpringMassSystem("spring_mass"))
    builder.add_system(rome.ConstantVectorSource("leg_acceleration", [0.0]))
    builder.add_system(rome.ZeroOrderHold("zoh", 1e-3, 4))
    builder.connect("step", "y", "stepping_lip", "step")
    builder.connect("impact_velocity", "y", "stepping_lip", "impact_vertical_velocity")
    builder.connect("leg_acceleration", "y", "spring_mass", "leg_length_acceleration")
    builder.connect("spring_mass", "state", "zoh", "u")
    rome.add_vector_logger(builder, "logger", [("stepping_lip", "state"), ("zoh", "y")], 0.01)
    return builder.build("benchmark"), lip, spring_mass


def user_cpu_s():
    """User CPU time of this process so far [s] (getrusage, as the C++ half reads it)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_utime


def python_run(seconds, repeats):
    walls, users, final = [], [], None
    for _ in range(repeats):
        diagram, lip, spring_mass = build()
        simulator = rome.Simulator(diagram)
        start, user_start = time.perf_counter(), user_cpu_s()
        status = simulator.advance_to(seconds)
        users.append(user_cpu_s() - user_start)
        walls.append(time.perf_counter() - start)
        assert status.ok(), status
        final = (diagram.eval_subsystem_output(lip, "state", simulator.context),
                 diagram.eval_subsystem_output(spring_mass, "state", simulator.context))
    return walls, users, final


def cpp_run(exe, seconds, repeats):
    out = subprocess.run([exe, str(seconds), str(repeats)], check=True, capture_output=True, text=True).stdout
    lines = dict(line.split(" ", 1) for line in out.strip().splitlines())
    walls = [float(x) for x in lines["wall_runs_s"].split()]
    users = [float(x) for x in lines["user_runs_s"].split()]
    return walls, users, lines


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 1
    exe = sys.argv[1]
    seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 50.0
    repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 7
    rounds = int(sys.argv[4]) if len(sys.argv) > 4 else 3
    runs = {"cpp_wall": [], "cpp_user": [], "py_wall": [], "py_user": []}
    for _ in range(rounds):
        wall_cpp, user_cpp, lines = cpp_run(exe, seconds, repeats)
        wall_py, user_py, (lip, spring_mass) = python_run(seconds, repeats)
        runs["cpp_wall"] += wall_cpp
        runs["cpp_user"] += user_cpp
        runs["py_wall"] += wall_py
        runs["py_user"] += user_py
        same_lip = lines["stepping_lip"] == " ".join(f"{v:.12g}" for v in lip)
        same_sm = lines["spring_mass"] == " ".join(f"{v:.12g}" for v in spring_mass)
        print(f"round: median user CPU C++ {statistics.median(user_cpp) * 1e3:.1f} ms, Python "
              f"{statistics.median(user_py) * 1e3:.1f} ms; median wall C++ {statistics.median(wall_cpp) * 1e3:.1f} ms, "
              f"Python {statistics.median(wall_py) * 1e3:.1f} ms; same final state: {same_lip and same_sm}")
        if not (same_lip and same_sm):
            print(f"  C++ {lines}\n  Python {lip} {spring_mass}")
            return 3
    med = {k: statistics.median(v) for k, v in runs.items()}
    low = {k: min(v) for k, v in runs.items()}
    print(f"{seconds:g} s simulated, {rounds} x {repeats} runs a side (rounds alternating), load average "
          f"{os.getloadavg()[0]:.1f}:")
    for what in ("user", "wall"):
        print(f"  {what:4s} median C++ {med['cpp_' + what] * 1e3:.1f} ms, Python {med['py_' + what] * 1e3:.1f} ms "
              f"({100 * (med['py_' + what] / med['cpp_' + what] - 1):+.1f} %); min C++ "
              f"{low['cpp_' + what] * 1e3:.1f} ms, Python {low['py_' + what] * 1e3:.1f} ms "
              f"({100 * (low['py_' + what] / low['cpp_' + what] - 1):+.1f} %)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
