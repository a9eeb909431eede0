#!/usr/bin/env python3
"""The headline number of each figure, measured from the runs rome_figures.sh made (OUT_DIR/runs/*.json, the sweeps'
sweep.csv, the Fig. 5 pre_impact_vz.csv), printed as a Markdown table beside the paper's statement.

usage: figures_numbers.py OUT_DIR   (rome_figures.sh writes its output to OUT_DIR/numbers.md)
Exit codes: 0 written, 1 a run's summary is missing or unreadable (named on stderr).
"""
import csv
import json
import os
import sys


def load(runs, name):
    with open(os.path.join(runs, name)) as f:
        return json.load(f)


def fmt(x, digits=3):
    return f"{x:.{digits}f}"


def stepping_stones(runs):
    rows = []
    for robot, label in (("amber", "AMBER"), ("cassie_planar", "planar Cassie")):
        for kind, lh in (("flat", "l = 0.7 m"), ("stairs-up", "(0.5, 0.2) m"), ("stairs-down", "(0.4, -0.1) m")):
            s = load(runs, f"ss_{kind}_{robot}.json")
            steps = s["steps"]
            # Convergence to a periodic gait: the change of the pre-impact vertical COM velocity over the last step.
            dvz = abs(steps[-1]["pre_impact_com_vz_mps"] - steps[-2]["pre_impact_com_vz_mps"]) if len(steps) > 1 else float("nan")
            rows.append((f"4, {label}, {kind} {lh}",
                         f"{s['steps_completed']} steps, {s['status_kind']}; mean speed {fmt(s['mean_forward_speed_mps'], 2)} m/s; "
                         f"pre-impact ż changes {fmt(dvz, 4)} m/s over the last step",
                         "converges to a periodic gait; 0.4-1.6 m/s over l 0.1-0.8 m, h -0.2 to +0.25 m on both robots"))
        with open(os.path.join(runs, f"ss_stairs-down_{robot}", "pre_impact_vz.csv")) as f:
            last = list(csv.DictReader(f))[-1]
        vz, u = float(last["com_vz_mps"]), float(last["u_des_mps"])
        rows.append((f"5, {label}, stairs down",
                     f"last pre-impact ż {fmt(vz)} m/s against u_des {fmt(u)} m/s ({fmt(100 * abs(vz - u) / abs(u), 1)} % off)",
                     "ż⁻ converges to u_des within each step"))
    for fig, csv_name, param, label, paper in (
            ("6a", "ss_fig6a/sweep.csv", "step-length", "l [m]", "speed rises with l at the same E* = 0.3"),
            ("6b", "ss_fig6b/sweep.csv", "energy", "E* [m²/s²]", "speed scales with E* at l = 0.4 m")):
        with open(os.path.join(runs, csv_name)) as f:
            pts = [(float(r[param]), float(r["mean_forward_speed_mps"]) if r["exit_code"] == "0" else None)
                   for r in csv.DictReader(f)]
        ok = [(x, v) for x, v in pts if v is not None]
        failed = [x for x, v in pts if v is None]
        text = ", ".join(f"{x:g}: {v:.2f}" for x, v in ok) + " m/s"
        if failed:
            text += "; failed at " + ", ".join(f"{x:g}" for x in failed)
        rows.append((f"{fig}, AMBER, flat, speed over {label}", text, paper))
    for robot, label in (("amber", "AMBER"), ("cassie_planar", "planar Cassie")):
        s = load(runs, f"ss_random_{robot}.json")
        rows.append((f"7, {label}, random stones (seed 1)",
                     f"{s['steps_completed']} steps, {s['status_kind']}; mean speed {fmt(s['mean_forward_speed_mps'], 2)} m/s; "
                     f"largest foothold error {fmt(100 * s['max_foothold_error_m'], 2)} cm",
                     "both robots cross the same random stones (0.2-0.7 m, ±0.25 m), E* = 0.5"))
    return rows


def walking(runs):
    s = load(runs, "walking.json")
    e, r = s["com_max_error_m"], s["com_rms_error_m"]
    return [
        ("5a, COM position", f"largest error (x, y, z) {', '.join(fmt(1e3 * v, 1) for v in e)} mm; RMS "
         f"{', '.join(fmt(1e3 * v, 1) for v in r)} mm; {s['steps_completed']} steps, {s['status_kind']}",
         "the COM follows the desired trajectory well (no number)"),
        ("5d, normal forces", f"{fmt(100 * s['force_in_band_fraction'], 1)} % of the stance ticks inside the band",
         "normal forces within the relaxation (c = 0.1)"),
    ]


def hopping(runs):
    s = load(runs, "hopping.json")
    return [
        ("6a,b, outputs", f"COM rise {fmt(s['com_rise_m'])} m (plan's apex rise {fmt(s['apex_rise_m'])} m), air time "
         f"{fmt(s['air_time_s'])} s, foot clearance {fmt(s['foot_clearance_m'])} m; {s['status_kind']}",
         "fast convergence of the outputs (no number); hardware clearance ~7 in (0.18 m)"),
        ("6d, spring torque", f"correlation with the normal GRF {fmt(s['spring_torque_grf_correlation'])}",
         "the spring torques show the same profile as the GRF"),
        ("6f, GRF", f"NRMSE against the ROM: jump {fmt(s['grf_nrmse_jump'])}, landing {fmt(s['grf_nrmse_landing'])}",
         "the robot's GRF aligns closely with the spring-mass model's"),
    ]


def main():
    if len(sys.argv) != 2:
        print("usage: figures_numbers.py OUT_DIR", file=sys.stderr)
        return 1
    runs = os.path.join(sys.argv[1], "runs")
    try:
        tables = (("Stepping stones", stepping_stones(runs)), ("Walking", walking(runs)), ("Hopping", hopping(runs)))
    except (OSError, KeyError, ValueError, IndexError) as e:
        print(f"figures_numbers.py: cannot read the runs in {runs}: {e!r}", file=sys.stderr)
        return 1
    for paper, rows in tables:
        print(f"\n### {paper}\n\n| Fig. | measured here | paper |\n|---|---|---|")
        for row in rows:
            print("| " + " | ".join(row) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
