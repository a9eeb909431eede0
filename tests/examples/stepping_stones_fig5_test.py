#!/usr/bin/env python3
"""The stepping-stones paper's Fig. 5 from a short run: AMBER walks 10 steps down stairs (0.4 m, -0.1 m), logged every
1 ms, and `--plots` writes outputs.png, pre_impact_vz.png and pre_impact_vz.csv. Checks, each with its source:

1. both PNGs are PNG files (8-byte signature) of the size the plot code asks (IHDR width x height): a check that the
   plotter drew them, not of what they show;
2. the CSV has a row for every logged touchdown (at least steps - 1: the run ends at the last touchdown);
3. every pre-impact COM vertical velocity is negative: on stairs down the COM falls at touchdown;
4. the logged velocity against the test's own backward difference of the logged COM height (--log) over the last
   1 ms: they differ by at most |z_ddot| dt / 2 with |z_ddot| <= 2 g, i.e. 0.0098 m/s (a derivative of the plant's
   positions, not its velocity);
5. the log's pre-impact velocity against the supervisor's step record in the JSON summary (another path through the
   diagram, sampled at the same 1 kHz controller tick): within g * 1 ms = 0.0098 m/s;
6. from step 4 on the gait is periodic (the paper's Fig. 4): consecutive pre-impact velocities within 0.01 m/s;

The pre-impact ż does not reach u_des (a steady 9.6 % offset, docs/stepping-stones.md, a known gap against the
paper): no bound is asserted on it, since the only bound available would come from this code's own output.

usage: stepping_stones_fig5_test.py STEPPING_STONES_BINARY WORK_DIR   (run from the repository root)
"""
import csv
import json
import os
import shutil
import struct
import subprocess
import sys

G = 9.81
STEPS = 10


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    if len(head) < 24 or head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        return None
    return struct.unpack(">II", head[16:24])


def main():
    binary, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    plots = os.path.join(work, "plots")
    summary = os.path.join(work, "summary.json")
    log = os.path.join(work, "log.csv")
    run = subprocess.run([binary, "--terrain", "stairs-down", "--step-length", "0.4", "--step-height", "-0.1", "--steps", str(STEPS),
                          "--log-period", "0.001", "--plots", plots, "--summary", summary, "--log", log],
                         capture_output=True, text=True)
    failures = []
    if run.returncode != 0:
        print(run.stdout, run.stderr)
        print(f"FAIL: stepping_stones exited {run.returncode}")
        return 1
    if "warning" in run.stdout + run.stderr:
        failures.append("the run printed a warning: " + (run.stdout + run.stderr).strip()[-300:])
    # 1. The PNGs: 3 stacked panels of 900 x 330 px, and the per-step plot 1100 x 500 px.
    for name, size in (("outputs.png", (900, 990)), ("pre_impact_vz.png", (1100, 500))):
        got = png_size(os.path.join(plots, name))
        if got != size:
            failures.append(f"{name}: expected a {size[0]} x {size[1]} PNG, got {got}")
    rows = list(csv.DictReader(open(os.path.join(plots, "pre_impact_vz.csv"))))
    records = json.load(open(summary))["steps"]
    # The plant's COM height and time from the log, for the test's own backward difference.
    log_t, log_z = [], []
    for r in csv.DictReader(open(log)):
        log_t.append(float(r["time"]))
        log_z.append(float(r["plant.com.z"]))
    # 2. A row per logged touchdown.
    if len(rows) < STEPS - 1:
        failures.append(f"pre_impact_vz.csv: {len(rows)} rows, expected at least {STEPS - 1}")
    for i, r in enumerate(rows):
        step, vz = int(r["step"]), float(r["com_vz_mps"])
        # 3. Falling at touchdown.
        if not vz < 0:
            failures.append(f"step {step}: pre-impact z_dot {vz} m/s is not negative on stairs down")
        # 4. Against the test's own backward difference of the logged COM height at the same sample.
        k = min(range(len(log_t)), key=lambda j: abs(log_t[j] - float(r["time_s"])))
        if k == 0 or abs(log_t[k] - float(r["time_s"])) > 1e-9:
            failures.append(f"step {step}: no log sample at t = {r['time_s']} s")
            continue
        fd = (log_z[k] - log_z[k - 1]) / (log_t[k] - log_t[k - 1])
        if abs(vz - fd) > 0.5 * 2 * G * (log_t[k] - log_t[k - 1]):
            failures.append(f"step {step}: z_dot {vz} against the height's backward difference {fd} m/s")
        # 5. Against the supervisor's step record (every touchdown has one).
        if step - 1 >= len(records):
            failures.append(f"step {step}: the summary has no step record for it ({len(records)} records)")
        elif abs(vz - records[step - 1]["pre_impact_com_vz_mps"]) > G * 1e-3:
            failures.append(f"step {step}: log {vz} against the step record {records[step - 1]['pre_impact_com_vz_mps']} m/s")
        # 6. Periodic from step 4.
        if step >= 4 and abs(vz - float(rows[i - 1]["com_vz_mps"])) > 0.01:
            failures.append(f"step {step}: z_dot {vz} m/s against {rows[i - 1]['com_vz_mps']} one step before: not periodic")
    for f in failures:
        print("FAIL: " + f)
    if not failures:
        last = rows[-1]
        print(f"Fig. 5: {len(rows)} touchdowns; last pre-impact z_dot {float(last['com_vz_mps']):.4f} m/s, u_des {float(last['u_des_mps']):.4f} m/s")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
