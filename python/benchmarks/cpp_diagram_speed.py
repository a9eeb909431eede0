#!/usr/bin/env python3
"""A diagram of C++ blocks built and run from Python against the same diagram built and run from C++.

The diagram (python/benchmarks/cpp_diagram_speed.cc builds the same one in C++): a stepping LIP walking a periodic orbit
(an event per step), a spring-mass model settling on its leg, a 1 kHz zero-order hold of the spring-mass state and a
100 Hz logger. Each side times Simulator.advance_to (wall clock and process CPU time) over the same simulated time and
keeps the smallest of `repeats` runs (the machine is shared; the minimum is the run least disturbed). Runs alternate between the two sides. The final
states must agree to every printed digit.

usage: PYTHONPATH=build/python /usr/bin/python3 python/benchmarks/cpp_diagram_speed.py build/python/cpp_diagram_speed \
           [seconds=50] [repeats=7] [rounds=3]
"""
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


def python_run(seconds, repeats):
    best, best_cpu, final = float("inf"), float("inf"), None
    for _ in range(repeats):
        diagram, lip, spring_mass = build()
        simulator = rome.Simulator(diagram)
        start, cpu_start = time.perf_counter(), time.process_time()
        status = simulator.advance_to(seconds)
        best_cpu = min(best_cpu, time.process_time() - cpu_start)
        best = min(best, time.perf_counter() - start)
        assert status.ok(), status
        final = (diagram.eval_subsystem_output(lip, "state", simulator.context),
                 diagram.eval_subsystem_output(spring_mass, "state", simulator.context))
    return best, best_cpu, final


def cpp_run(exe, seconds, repeats):
    out = subprocess.run([exe, str(seconds), str(repeats)], check=True, capture_output=True, text=True).stdout
    lines = dict(line.split(" ", 1) for line in out.strip().splitlines())
    return float(lines["wall_s"]), float(lines["cpu_s"]), lines


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 1
    exe = sys.argv[1]
    seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 50.0
    repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 7
    rounds = int(sys.argv[4]) if len(sys.argv) > 4 else 3
    best = {"cpp": float("inf"), "py": float("inf"), "cpp_cpu": float("inf"), "py_cpu": float("inf")}
    for _ in range(rounds):
        wall_cpp, cpu_cpp, lines = cpp_run(exe, seconds, repeats)
        wall_py, cpu_py, (lip, spring_mass) = python_run(seconds, repeats)
        for key, value in (("cpp", wall_cpp), ("py", wall_py), ("cpp_cpu", cpu_cpp), ("py_cpu", cpu_py)):
            best[key] = min(best[key], value)
        same_lip = lines["stepping_lip"] == " ".join(f"{v:.12g}" for v in lip)
        same_sm = lines["spring_mass"] == " ".join(f"{v:.12g}" for v in spring_mass)
        print(f"round: C++ {wall_cpp * 1e3:.1f} ms (CPU {cpu_cpp * 1e3:.1f} ms), Python {wall_py * 1e3:.1f} ms "
              f"(CPU {cpu_py * 1e3:.1f} ms), same final state: {same_lip and same_sm}")
        if not (same_lip and same_sm):
            print(f"  C++ {lines}\n  Python {lip} {spring_mass}")
            return 3
    print(f"{seconds:g} s simulated, min of {rounds} x {repeats} runs: wall C++ {best['cpp'] * 1e3:.1f} ms, Python "
          f"{best['py'] * 1e3:.1f} ms ({100 * (best['py'] / best['cpp'] - 1):+.1f} %); process CPU C++ "
          f"{best['cpp_cpu'] * 1e3:.1f} ms, Python {best['py_cpu'] * 1e3:.1f} ms "
          f"({100 * (best['py_cpu'] / best['cpp_cpu'] - 1):+.1f} %)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
