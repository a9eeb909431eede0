#!/usr/bin/env python3
"""The walking paper's gait change from Python: the exoskeleton stands, walks gait A, changes to gait B through the
footed-aSLIP transition and walks B (the walking program's gait-change scenario), then the COM tracking and the
normal forces are plotted with matplotlib.

The run is rome.run_walking(scenario="gait-change", record=True): the C++ planners, diagram and RunWalking, with the
per-tick COM, its plan, and the plant's and the plan's normal forces returned as numpy arrays.
Exit status: 0 walked (the run's success rule), 3 failed, 1 bad input.

usage: PYTHONPATH=build/python /usr/bin/python3 examples/python/walking_gait_change.py \
           [--gait-a 0.30,0.40,0.10,0.25] [--gait-b 0.35,0.40,0.10,0.25] [--steps 10] [--seed 1] [--plot change.png]
"""
import argparse
import sys

import numpy as np

import rome


def gait(text, name):
    """step length (m), single-support and double-support durations (s), step width (m)."""
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 4:
        raise ValueError(f"walking_gait_change: --{name} '{text}' must be four numbers: length,ssp,dsp,width")
    return rome.WalkingGait(step_length_m=values[0], ssp_duration_s=values[1], dsp_duration_s=values[2],
                            step_width_m=values[3])


def run(gait_a, gait_b, steps, seed):
    """The gait-change run with its per-tick series (rome.run_walking's dict)."""
    return rome.run_walking(gait=gait_a, gait_b=gait_b, steps=steps, scenario="gait-change", seed=seed, record=True)


def com_tracking(series):
    """RMS and largest |COM - planned COM| per axis (m) over the run's ticks."""
    error = series["com"] - series["com_reference"]
    return np.sqrt(np.mean(error**2, axis=0)), np.abs(error).max(axis=0)


def plot(series, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = series["time"]
    figure, axes = plt.subplots(4, 1, figsize=(8, 9), sharex=True)
    for i, axis in enumerate("xyz"):
        axes[i].plot(t, series["com"][:, i], label=f"COM {axis}")
        axes[i].plot(t, series["com_reference"][:, i], "--", label="plan")
        axes[i].set_ylabel(f"{axis} [m]")
        axes[i].legend(loc="upper left")
    for j, foot in enumerate(["left", "right"]):
        axes[3].plot(t, series["normal_force"][:, j], label=f"{foot} foot")
        axes[3].plot(t, series["normal_force_reference"][:, j], "--", label=f"{foot} plan")
    axes[3].set_ylabel("normal force [N]")
    axes[3].set_xlabel("time [s]")
    axes[3].legend(loc="upper left", ncol=2)
    axes[0].set_title(title)
    figure.tight_layout()
    figure.savefig(path, dpi=100)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--gait-a", default="0.30,0.40,0.10,0.25", help="gait A: length,ssp,dsp,width (m, s, s, m)")
    parser.add_argument("--gait-b", default="0.35,0.40,0.10,0.25", help="gait B: length,ssp,dsp,width (m, s, s, m)")
    parser.add_argument("--steps", type=int, default=10, help="steps of each gait [1, 100]")
    parser.add_argument("--seed", type=int, default=1, help="seed of the NLPs' initial guesses")
    parser.add_argument("--plot", default="", help="PNG file of the COM tracking and the normal forces")
    args = parser.parse_args(argv)
    try:
        gait_a, gait_b = gait(args.gait_a, "gait-a"), gait(args.gait_b, "gait-b")
        gait_a.validate("walking_gait_change: --gait-a")
        gait_b.validate("walking_gait_change: --gait-b")
        if not 1 <= args.steps <= 100 or args.seed < 0:
            raise ValueError(f"walking_gait_change: --steps {args.steps} must be in [1, 100], --seed {args.seed} >= 0")
    except ValueError as error:
        print(error, file=sys.stderr)
        return 1
    try:
        result = run(gait_a, gait_b, args.steps, args.seed)
    except RuntimeError as error:  # a plan that failed (an NLP, a QP): a failed run
        print(f"walking_gait_change: {error}", file=sys.stderr)
        return 3
    series = result["series"]
    rms, largest = com_tracking(series)
    print(f"{result['status_kind']}: {result['steps_completed']} of {result['steps_planned']} steps, "
          f"{result['simulated_s']:.2f} s simulated in {result['wall_s']:.1f} s")
    print("COM error vs plan, rms (x, y, z): " + ", ".join(f"{1e3 * e:.1f} mm" for e in rms) +
          "; largest: " + ", ".join(f"{1e3 * e:.1f} mm" for e in largest))
    if args.plot:
        plot(series, args.plot, f"gait change {args.gait_a} -> {args.gait_b}, {args.steps} steps each")
        print(f"plot: {args.plot}")
    return 0 if result["success"] else 3


if __name__ == "__main__":
    sys.exit(main())
