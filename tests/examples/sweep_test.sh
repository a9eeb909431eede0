#!/usr/bin/env bash
# rome_sweep under Open MPI: the same CSV bitwise with 1 and 2 ranks; a restart resumes (reruns only what is missing);
# a grid draws the speed plot; bad input gets one line naming it and exit 1.
# usage: sweep_test.sh BIN_DIR WORK_DIR
set -uo pipefail
bin="$1"; work="$2"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
rm -rf "$work"; mkdir -p "$work"
fail=0
check() { if ! eval "$2"; then echo "FAIL: $1"; fail=1; fi; }
sweep=(stepping-stones --seeds 1:4 --set steps=4)
mpirun -np 1 "$bin/rome_sweep" "${sweep[@]}" --out "$work/one" > "$work/one.out" 2>&1; check "1 rank exits 0" '[ $? = 0 ]'
mpirun -np 2 "$bin/rome_sweep" "${sweep[@]}" --out "$work/two" > "$work/two.out" 2>&1; check "2 ranks exit 0" '[ $? = 0 ]'
check "CSV identical with 1 and 2 ranks" 'cmp -s "$work/one/sweep.csv" "$work/two/sweep.csv"'
check "4 rows" '[ "$(wc -l < "$work/one/sweep.csv")" = 5 ]'
check "success rate 1" 'grep -q "\"success_rate\": 1.0" "$work/one/sweep.json"'
# Resume: remove one finished run; the restart runs only that one and gives the same CSV.
rm "$work/two/runs/run_000002.exit"
mpirun -np 2 "$bin/rome_sweep" "${sweep[@]}" --out "$work/two" > "$work/resume.out" 2>&1
check "resume reran exactly one run" 'grep -q "rome_sweep: 1 runs in" "$work/resume.out"'
check "CSV identical after resuming" 'cmp -s "$work/one/sweep.csv" "$work/two/sweep.csv"'
# A 2 x 2 grid (Fig. 6 shape) draws the speed plot.
mpirun -np 2 "$bin/rome_sweep" stepping-stones --grid energy=0.3:0.5:2 --grid step-length=0.3:0.5:2 --set terrain=flat --set steps=4 \
  --out "$work/grid" > "$work/grid.out" 2>&1
check "grid exits 0" '[ $? = 0 ]'
check "grid plot written" '[ -s "$work/grid/sweep_speed.png" ] || ! command -v gnuplot > /dev/null'
# Bad input: one line, naming it, exit 1.
bad() {  # expected-text args...
  local want="$1"; shift
  out=$("$bin/rome_sweep" "$@" 2>&1); code=$?
  check "'$*' exits 1 (got $code)" '[ $code = 1 ]'
  check "'$*' names it: $want" 'printf "%s" "$out" | grep -q -- "$want"'
}
bad "unknown example 'walker'" walker --seeds 1:2 --out "$work/x"
bad "has no parameter 'energyy'" stepping-stones --grid energyy=0:1:2 --out "$work/x"
bad "malformed range '0.1:0.7'" stepping-stones --grid energy=0.1:0.7 --out "$work/x"
bad "malformed range '5:1'" stepping-stones --seeds 5:1 --out "$work/x"
bad "cannot write to the output folder '/proc/rome_sweep'" stepping-stones --seeds 1:2 --out /proc/rome_sweep
[ "$fail" = 0 ] && echo "rome_sweep: all checks passed"
exit "$fail"
