#!/usr/bin/env python3
"""Random gait pairs of the walking issue's range, each changed in both directions by the walking program.

Draws --count pairs with Python's random.Random(--seed): gait A, then gait B, each coordinate uniform in the range
(L 0.2-0.45 m, T_SSP 0.35-0.5 s, T_DSP 0.08-0.15 s, W 0.2-0.3 m) and rounded to 0.01. Runs
`walking --scenario gait-change` for A -> B and B -> A (--steps of each gait, NLP --nlp-seed, the plan cache --cache),
--jobs at a time, and sorts each run as the issue's acceptance does:
  walked    exit 0: every step, COM RMS <= 1 cm per axis after the first step, >= 95 % in band (strictly),
            zero infeasible QP ticks, zero contact violations;
  refused   exit 1 before simulating, with the walking program's one-line reason;
  failed    anything else (exit 3, or exit 0 outside a threshold);
  error     exit 1 that is no refusal (the walking program refused its input, e.g. a flag after --).
docs/walking.md's table of the 20 random pairs in both directions is --seed 39 --count 20.

Writes DIR/pairs.csv (one row per run, named columns) and DIR/summary.json, each run's summary and output in DIR/runs.
Exit status: 0 when every run walked or was refused, 3 when any failed, 1 bad input (its own or a run's).

usage: examples/python/walking_random_pairs.py [--seed 39] [--count 20] [--steps 10] [--jobs 2] [--out DIR]
           [--walking build/bin/walking] [--cache walking_plans] [-- extra walking flags, e.g. --hold-drift off]
"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import random
import shutil
import subprocess
import sys

RANGE_MIN = (0.20, 0.35, 0.08, 0.20)  # L m, T_SSP s, T_DSP s, W m: the walking issue's range
RANGE_MAX = (0.45, 0.50, 0.15, 0.30)
COM_RMS_MAX_M = 0.01  # the acceptance
STRICT_BAND_MIN = 0.95
COLUMNS = ["pair", "direction", "gait_a", "gait_b", "exit", "outcome", "steps_completed", "steps_planned",
           "com_rms_x_m", "com_rms_y_m", "com_rms_z_m", "force_in_band_fraction_strict", "qp_infeasible_ticks",
           "contact_violations", "reason"]


def random_pairs(seed, count):
    """The pairs as (gait A, gait B) tuples of 4 numbers each, in the order random.Random(seed) draws them."""
    rng = random.Random(seed)
    draw = lambda: tuple(round(rng.uniform(lo, hi), 2) for lo, hi in zip(RANGE_MIN, RANGE_MAX))
    return [(draw(), draw()) for _ in range(count)]


def text(gait):
    return ",".join(f"{v:.2f}" for v in gait)


def find_walking(given):
    executable = lambda path: bool(path) and os.path.isfile(path) and os.access(path, os.X_OK)
    if given:
        if executable(given):
            return given
        raise ValueError(f"walking_random_pairs: --walking '{given}' is not an executable file")
    for candidate in (os.environ.get("ROME_WALKING_EXE", ""), "build/bin/walking", shutil.which("walking")):
        if executable(candidate):
            return candidate
    raise ValueError("walking_random_pairs: no walking program found ($ROME_WALKING_EXE, build/bin/walking, PATH): "
                     "build it, or name it with --walking")


def judge(code, summary, output, errors=""):
    """(outcome, reason) of one run from its exit code, its summary (None if not written), its standard output and
    its standard error. Outcomes: walked, refused, failed, and error (exit 1 that is no refusal: bad input)."""
    last = lambda text: text.strip().splitlines()[-1] if text.strip() else ""
    reason = last(errors) or last(output)
    lines = output.splitlines()
    if code == 1:
        planned = any(line.startswith("planning:") for line in lines)
        simulated = any(line.startswith("simulating ") for line in lines)
        return ("refused" if planned and not simulated else "error"), reason
    if code != 0 or summary is None:
        failed = [line for line in lines if line.startswith("FAILED")]
        return "failed", (failed[0] if failed else reason) or f"exit {code}"
    numbers = [*summary["com_rms_error_m"], summary["force_in_band_fraction_strict"], summary["qp_infeasible_ticks"],
               summary["contact_violations"]]
    if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in numbers):
        return "failed", "a summary figure is missing or not finite"
    rms = summary["com_rms_error_m"]
    problems = []
    if max(rms) > COM_RMS_MAX_M:
        problems.append(f"COM RMS {max(rms):.4f} m > {COM_RMS_MAX_M} m")
    if summary["force_in_band_fraction_strict"] < STRICT_BAND_MIN:
        problems.append(f"strict band {summary['force_in_band_fraction_strict']:.4f} < {STRICT_BAND_MIN}")
    if summary["qp_infeasible_ticks"] != 0:
        problems.append(f"{summary['qp_infeasible_ticks']} infeasible QP ticks")
    if summary["contact_violations"] != 0:
        problems.append(f"{summary['contact_violations']} contact violations")
    if not summary["success"]:
        problems.append("the run's success rule")
    return ("failed", "; ".join(problems)) if problems else ("walked", "")


def run_one(walking, out, pair, direction, gait_a, gait_b, args, extra):
    name = f"pair{pair:02d}_{direction}"
    summary_path = os.path.join(out, "runs", name + ".json")
    command = [walking, "--scenario", "gait-change", "--gait-a", text(gait_a), "--gait-b", text(gait_b), "--steps",
               str(args.steps), "--seed", str(args.nlp_seed), "--cache", args.cache, "--summary", summary_path] + extra
    row = {"pair": pair, "direction": direction, "gait_a": text(gait_a), "gait_b": text(gait_b)}
    try:
        if os.path.exists(summary_path):
            os.remove(summary_path)
        done = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        with open(os.path.join(out, "runs", name + ".out"), "w") as f:
            f.write(done.stdout + done.stderr)
        summary = None
        if os.path.exists(summary_path):
            with open(summary_path) as f:
                summary = json.load(f)
        outcome, reason = judge(done.returncode, summary, done.stdout, done.stderr)
    except (OSError, ValueError, KeyError, TypeError) as error:  # a run that could not be started or read
        row.update(exit="", outcome="failed", reason=f"{type(error).__name__}: {error}")
        return row
    row.update({"exit": done.returncode, "outcome": outcome, "reason": reason})
    if summary is not None:
        rms = summary.get("com_rms_error_m") or ["", "", ""]
        row.update(steps_completed=summary.get("steps_completed", ""), steps_planned=summary.get("steps_planned", ""),
                   com_rms_x_m=rms[0], com_rms_y_m=rms[1], com_rms_z_m=rms[2],
                   force_in_band_fraction_strict=summary.get("force_in_band_fraction_strict", ""),
                   qp_infeasible_ticks=summary.get("qp_infeasible_ticks", ""),
                   contact_violations=summary.get("contact_violations", ""))
    return row


def write_atomically(path, write):
    temporary = path + ".tmp"
    try:
        with open(temporary, "w", newline="") as f:
            write(f)
        os.replace(temporary, path)
    finally:
        if os.path.exists(temporary):
            os.remove(temporary)


class Parser(argparse.ArgumentParser):
    def error(self, message):  # bad input exits 1, as the walking program does
        self.print_usage(sys.stderr)
        print(f"walking_random_pairs: {message}", file=sys.stderr)
        sys.exit(1)


def main(argv=None):
    parser = Parser(description=__doc__.splitlines()[0], epilog="Flags after -- go to every walking run.")
    parser.add_argument("--seed", type=int, default=39, help="seed of the pairs' draw (random.Random)")
    parser.add_argument("--count", type=int, default=20, help="pairs [1, 1000]; each runs in both directions")
    parser.add_argument("--steps", type=int, default=10, help="steps of each gait [1, 100]")
    parser.add_argument("--nlp-seed", type=int, default=1, help="the walking program's --seed (NLP initial guesses)")
    parser.add_argument("--jobs", type=int, default=2, help="runs at a time [1, 64] (each is one process)")
    parser.add_argument("--out", default="walking_random_pairs", help="output folder (created)")
    parser.add_argument("--walking", default="", help="the walking program (default: $ROME_WALKING_EXE, "
                        "build/bin/walking, or walking on PATH)")
    parser.add_argument("--cache", default="walking_plans", help="the walking program's plan cache folder")
    argv = sys.argv[1:] if argv is None else argv
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    args = parser.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
    try:
        if not 1 <= args.count <= 1000 or not 1 <= args.steps <= 100 or not 1 <= args.jobs <= 64:
            raise ValueError(f"walking_random_pairs: --count {args.count} must be in [1, 1000], --steps {args.steps} "
                             f"in [1, 100], --jobs {args.jobs} in [1, 64]")
        if args.nlp_seed < 0:
            raise ValueError(f"walking_random_pairs: --nlp-seed {args.nlp_seed} must be >= 0")
        walking = find_walking(args.walking)
        os.makedirs(os.path.join(args.out, "runs"), exist_ok=True)
    except (ValueError, OSError) as error:
        print(error, file=sys.stderr)
        return 1
    pairs = random_pairs(args.seed, args.count)
    # All forward runs first: the two directions of a pair, run at once, would solve the same gaits' NLPs twice.
    work = [(i + 1, d, a, b) if d == "forward" else (i + 1, d, b, a)
            for d in ("forward", "reverse") for i, (a, b) in enumerate(pairs)]
    rows = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = [pool.submit(run_one, walking, args.out, p, d, a, b, args, extra) for p, d, a, b in work]
        for future in concurrent.futures.as_completed(futures):
            row = future.result()
            rows.append(row)
            print(f"[{len(rows)}/{len(work)}] pair {row['pair']} {row['direction']} ({row['gait_a']} -> "
                  f"{row['gait_b']}): {row['outcome']} {row['reason']}".rstrip(), flush=True)
    rows.sort(key=lambda r: (r["pair"], r["direction"]))
    write_atomically(os.path.join(args.out, "pairs.csv"),
                     lambda f: (lambda w: (w.writeheader(), w.writerows(rows)))(csv.DictWriter(f, COLUMNS)))
    counts = {k: sum(r["outcome"] == k for r in rows) for k in ("walked", "refused", "failed", "error")}
    walked = [r for r in rows if r["outcome"] == "walked"]
    summary = {"seed": args.seed, "count": args.count, "steps": args.steps, "nlp_seed": args.nlp_seed,
               "walking_flags": extra, "runs": len(rows), **counts,
               "largest_com_rms_m": [max((r[f"com_rms_{a}_m"] for r in walked), default=None) for a in "xyz"],
               "smallest_strict_band": min((r["force_in_band_fraction_strict"] for r in walked), default=None),
               "failed_runs": [{k: r[k] for k in ("pair", "direction", "gait_a", "gait_b", "exit", "reason")}
                               for r in rows if r["outcome"] in ("failed", "error")]}
    write_atomically(os.path.join(args.out, "summary.json"), lambda f: json.dump(summary, f, indent=1, allow_nan=False))
    print(f"{len(rows)} runs: {counts['walked']} walked, {counts['refused']} refused before simulating, "
          f"{counts['failed']} failed; {args.out}/pairs.csv, {args.out}/summary.json")
    if counts["error"]:
        bad = next(r for r in rows if r["outcome"] == "error")
        print(f"walking_random_pairs: {counts['error']} runs exited 1 without a refusal (bad input?), e.g. pair "
              f"{bad['pair']} {bad['direction']}: {bad['reason']}", file=sys.stderr)
        return 1
    return 3 if counts["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
