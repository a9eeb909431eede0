#!/usr/bin/env bash
# --scenario-file for stepping_stones and bouncing_ball (walking and hopping have their own tests): a run with
# non-default options writes its effective "scenario" into its summary; that object, given back as --scenario-file with
# no other option, must give the same figures (every summary line but the wall-clock timings).
# usage: scenario_file_test.sh BIN_DIR WORK_DIR
set -euo pipefail
bin="$1"; work="$2"
rm -rf "$work"; mkdir -p "$work"
timings='"(wall_time_s|realtime_factor|controller_update_us)":'
rerun() {  # rerun NAME PROGRAM FLAGS...
  local name="$1" program="$2"; shift 2
  "$bin/$program" "$@" --summary "$work/$name.1.json" --log "$work/$name.1.csv" > "$work/$name.1.out" 2>&1 ||
    { echo "FAIL: $name: first run"; cat "$work/$name.1.out"; exit 1; }
  # The summary is JSON with 2-space indents: the scenario is the object opened by '  "scenario": {' and closed by '  }'.
  sed -n '/^  "scenario": {$/,/^  }/p' "$work/$name.1.json" | sed -e '1s/.*/{/' -e '$s/.*/}/' > "$work/$name.scenario.json"
  "$bin/$program" --scenario-file "$work/$name.scenario.json" --summary "$work/$name.2.json" --log "$work/$name.2.csv" > "$work/$name.2.out" 2>&1 ||
    { echo "FAIL: $name: rerun from the scenario"; cat "$work/$name.2.out"; exit 1; }
  figures() { sed '/"controller_update_us": {/,/}/d' "$1" | grep -v -E "$timings"; }  # timings, and the update count they sample
  diff <(figures "$work/$name.1.json") <(figures "$work/$name.2.json") ||
    { echo "FAIL: $name: the rerun from the summary's scenario differs"; exit 1; }
  echo "$name: the rerun from the summary's scenario has the same figures ($(wc -l < "$work/$name.1.json") lines)"
}
rerun ball bouncing_ball --restitution 0.7 --height 1.3 --duration 2
rerun stones stepping_stones --steps 4 --seed 3 --energy 0.4 --torso-gains 1,150,20
grep -q '"torso-gains": \[' "$work/stones.scenario.json" || { echo "FAIL: a list of numbers is not an array in the scenario"; exit 1; }
# Outputs are not scenario parameters: a scenario file that names one is refused, naming the key.
printf '{"seed": 2, "log": "x.csv"}\n' > "$work/output_key.json"
if "$bin/stepping_stones" --scenario-file "$work/output_key.json" > "$work/output_key.out" 2>&1; then echo "FAIL: an output key was accepted"; exit 1; fi
grep -q "unknown key 'log' (an output or the file itself" "$work/output_key.out" || { echo "FAIL: not named"; cat "$work/output_key.out"; exit 1; }
echo "scenario files: all checks passed"
