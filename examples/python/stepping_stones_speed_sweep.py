#!/usr/bin/env python3
"""Fig. 6 of the stepping-stones paper from Python: AMBER's mean forward speed over the target orbital energy E*, one
line per step length, on flat stepping stones (task-space QP, epsilon = 0.6, 15 steps).

Each point is one rome.run_stepping_stones run, the run `stepping_stones --terrain flat --energy E --step-length L
--steps 15` makes in C++ (tests/python/test_stepping_stones.py checks that the two give the same figures); the mean
speed printed is the C++ summary's mean_forward_speed_mps, with every digit.
Exit status: 0 every run walked, 3 a run failed, 1 bad input.

usage: PYTHONPATH=build/python /usr/bin/python3 examples/python/stepping_stones_speed_sweep.py \
           [--energies 0.1,0.3,0.5,0.7] [--step-lengths 0.4] [--steps 15] [--plot sweep.png]
"""
import argparse
import sys

import rome


def numbers(text, name):
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise SystemExit(f"stepping_stones_speed_sweep: --{name} must be numbers separated by commas, got '{text}'")
    return values


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--energies", default="0.1,0.3,0.5,0.7", help="E* values [m^2/s^2]")
    parser.add_argument("--step-lengths", default="0.4", help="distances between stones [m]")
    parser.add_argument("--steps", type=int, default=15, help="steps per run")
    parser.add_argument("--plot", default="", help="PNG file of the speed over E* (matplotlib)")
    args = parser.parse_args()
    try:
        energies, lengths = numbers(args.energies, "energies"), numbers(args.step_lengths, "step-lengths")
    except SystemExit as error:
        print(error, file=sys.stderr)
        return 1
    results, failed = {}, False
    print("step_length_m  E*  steps  mean_forward_speed_mps  status")
    for length in lengths:
        for energy in energies:
            params = rome.SteppingStonesDiagramParams.for_robot("robots/amber/amber.rome.json")
            params.target_orbital_energy = energy
            params.supervisor.max_steps = args.steps
            try:
                params.validate()
                terrain = rome.periodic_stepping_stones(length, 0.0, args.steps + 2, 0.1)
            except ValueError as error:
                print(f"stepping_stones_speed_sweep: {error}", file=sys.stderr)
                return 1
            r = rome.run_stepping_stones(terrain, params)
            failed = failed or not r["success"]
            results[(length, energy)] = r["mean_forward_speed_mps"] if r["success"] else float("nan")
            print(f"{length}  {energy}  {r['steps_completed']}  {r['mean_forward_speed_mps']!r}  {r['status_kind']}")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        figure, axes = plt.subplots(figsize=(6, 4))
        for length in lengths:
            axes.plot(energies, [results[(length, e)] for e in energies], "o-", label=f"l = {length} m")
        axes.set_xlabel("E* [m$^2$/s$^2$]")
        axes.set_ylabel("mean forward speed [m/s]")
        axes.set_title(f"AMBER on flat stepping stones, {args.steps} steps")
        axes.legend()
        axes.grid(True)
        figure.tight_layout()
        figure.savefig(args.plot, dpi=100)
        print(f"plot: {args.plot}")
    return 3 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
