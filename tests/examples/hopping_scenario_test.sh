#!/usr/bin/env bash
# hopping --scenario-file: a run is reproduced from its summary alone. A first run with non-default flags writes its
# summary; its "scenario" object becomes a scenario file; a second run given only that file must write the same figures
# (every line of the summary but the wall-clock timings: realtime_factor, wall_s, qp_solve_us_*, the NLPs' time_s).
# Also: an unknown key is an error naming it, and a flag on the command line wins over the file.
# usage: hopping_scenario_test.sh HOPPING_BIN WORK_DIR
set -euo pipefail
bin="$1"; work="$2"
rm -rf "$work"; mkdir -p "$work"
flags=(--apex-rise 0.15 --jump-momentum-gain 9 --landing-blend 0.45 --duration 2.4)
"$bin" "${flags[@]}" --summary "$work/first.json" > "$work/first.log" 2>&1 || [ $? -eq 3 ] || { echo "FAIL: first run"; cat "$work/first.log"; exit 1; }
# The summary is JSON with 2-space indents: the scenario is the object opened by '  "scenario": {' and closed by '  }'.
sed -n '/^  "scenario": {$/,/^  }/p' "$work/first.json" | sed -e '1s/.*/{/' -e '$s/.*/}/' > "$work/scenario.json"
grep -q '"apex-rise": 0.15' "$work/scenario.json" || { echo "FAIL: the scenario lacks apex-rise 0.15"; cat "$work/scenario.json"; exit 1; }
grep -q '"leg-stiffness": "identified"' "$work/scenario.json" || { echo "FAIL: the scenario lacks the default leg-stiffness"; exit 1; }
"$bin" --scenario-file "$work/scenario.json" --summary "$work/second.json" > "$work/second.log" 2>&1 || [ $? -eq 3 ] ||
  { echo "FAIL: second run"; cat "$work/second.log"; exit 1; }
figures() { grep -v -E '"(realtime_factor|wall_s|qp_solve_us_median|qp_solve_us_p99|time_s)":' "$1"; }
diff <(figures "$work/first.json") <(figures "$work/second.json") || { echo "FAIL: the rerun from the scenario differs"; exit 1; }
echo "hopping: the rerun from the summary's scenario has the same figures ($(figures "$work/first.json" | wc -l) lines)"
# An unknown key is named.
printf '{"apex-rise": 0.2, "apex_rise": 0.2}\n' > "$work/bad.json"
if "$bin" --scenario-file "$work/bad.json" > "$work/bad.log" 2>&1; then echo "FAIL: an unknown key was accepted"; exit 1; fi
grep -q "unknown key 'apex_rise'" "$work/bad.log" || { echo "FAIL: the error does not name the key"; cat "$work/bad.log"; exit 1; }
# The command line wins: --apex-rise 0.9 in the file is out of range, 0.15 on the command line is not; --hops 0 on the
# command line is out of range whatever the file says.
printf '{"apex-rise": 0.9, "hops": 2}\n' > "$work/override.json"
"$bin" --scenario-file "$work/override.json" --apex-rise 0.15 --hops 0 > "$work/override.log" 2>&1 && { echo "FAIL: --hops 0 was accepted"; exit 1; }
grep -q "reference.hops = 0" "$work/override.log" || { echo "FAIL: expected the hops error (command line wins)"; cat "$work/override.log"; exit 1; }
echo "hopping: unknown keys are named; the command line wins over the scenario file"
