#!/usr/bin/env bash
# rome_sweep under Open MPI: the same CSV bitwise with 1 and 2 ranks; a restart resumes (reruns only what is missing,
# killed or damaged; refuses other parameters); a grid draws the speed plot; a sweep whose runs fail still completes
# (exit 0); an --out folder named with backquotes, $(...), quotes and a newline runs nothing; symlinks planted at the
# names it writes are replaced, never followed; bad input gets one line naming it and exit 1.
# usage: sweep_test.sh BIN_DIR WORK_DIR
set -uo pipefail
bin="$(cd "$1" && pwd)"; work="$2"
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
# Resume: a damaged record, a damaged summary and a run killed by a signal run again; the intact run does not.
printf 'garbage\n' > "$work/two/runs/run_000000.exit"
printf '{"status": "walked", "status_kind": ' > "$work/two/runs/run_000001.json"
{ printf -- '-9\n'; sed -n 2p "$work/two/runs/run_000002.exit"; } > "$work/two/runs/run_000002.exit.new"
mv "$work/two/runs/run_000002.exit.new" "$work/two/runs/run_000002.exit"
mpirun -np 2 "$bin/rome_sweep" "${sweep[@]}" --out "$work/two" > "$work/resume2.out" 2>&1
check "resume reran the damaged and the killed runs (3)" 'grep -q "rome_sweep: 3 runs in" "$work/resume2.out"'
check "CSV identical after rerunning them" 'cmp -s "$work/one/sweep.csv" "$work/two/sweep.csv"'
# Resume with other parameters: refused, and the folder keeps its results.
out=$("$bin/rome_sweep" stepping-stones --seeds 1:4 --set steps=5 --out "$work/two" 2>&1); code=$?
check "resume with other parameters exits 1 (got $code)" '[ $code = 1 ]'
check "resume with other parameters names them" 'printf "%s" "$out" | grep -q "made with other parameters"'
check "CSV kept after a refused resume" 'cmp -s "$work/one/sweep.csv" "$work/two/sweep.csv"'
# An --out folder whose name holds a backquote, $(...), quotes and a newline: nothing runs, the sweep works.
mkdir -p "$work/cwd"
hostile="$work/out \`touch pwned1\` \$(touch pwned2) 'q\" \"
nl"
(cd "$work/cwd" && mpirun -np 1 "$bin/rome_sweep" stepping-stones --seeds 1:2 --set steps=4 --out "$hostile") > "$work/hostile.out" 2>&1
check "hostile --out exits 0" '[ $? = 0 ]'
check "hostile --out has its 2 rows" '[ "$(wc -l < "$hostile/sweep.csv")" = 3 ]'
check "hostile --out ran no command (no pwned file)" '[ -z "$(find "$work" "$PWD" -maxdepth 2 -name "pwned*" 2>/dev/null)" ]'
check "hostile --out plot written" '[ -s "$hostile/sweep_success.png" ] || ! command -v gnuplot > /dev/null'
# Symlinks planted at every name the sweep writes, pointing at files outside it: replaced, never followed.
mkdir -p "$work/planted/runs" "$work/victims"
for name in runs/run_000000.log runs/run_000000.json runs/run_000000.exit runs/run_000001.log runs/.write_probe sweep.csv sweep.json \
            sweep_success.png; do
  victim="$work/victims/$(basename "$name")"
  printf 'precious\n' > "$victim"
  ln -s "$victim" "$work/planted/$name"
done
mpirun -np 1 "$bin/rome_sweep" stepping-stones --seeds 1:2 --set steps=4 --out "$work/planted" > "$work/planted.out" 2>&1
check "planted symlinks: the sweep exits 0" '[ $? = 0 ]'
for victim in "$work"/victims/*; do
  check "planted symlink: $(basename "$victim") unchanged" '[ "$(cat "$victim")" = precious ]'
done
check "planted symlinks: the log is a regular file" '[ -f "$work/planted/runs/run_000000.log" ] && [ ! -L "$work/planted/runs/run_000000.log" ]'
check "planted symlinks: sweep.csv is a regular file" '[ ! -L "$work/planted/sweep.csv" ] && [ "$(wc -l < "$work/planted/sweep.csv")" = 3 ]'
# A sweep whose runs all fail completes: exit 0, its success rate and the failures' reason in sweep.json.
mpirun -np 1 "$bin/rome_sweep" stepping-stones --seeds 1:2 --set terrain="$work/no_such_terrain.csv" --out "$work/failing" > "$work/failing.out" 2>&1
check "a sweep of failing runs exits 0" '[ $? = 0 ]'
check "its success rate is 0" 'grep -q "\"success_rate\": 0.0" "$work/failing/sweep.json"'
check "its failures have their reason" 'grep -q "no summary (exit code 1)\": 2" "$work/failing/sweep.json"'
# A 2 x 2 grid (Fig. 6 shape) draws the speed plot.
mpirun -np 2 "$bin/rome_sweep" stepping-stones --grid energy=0.3:0.5:2 --grid step-length=0.3:0.5:2 --set terrain=flat --set steps=4 \
  --out "$work/grid" > "$work/grid.out" 2>&1
check "grid exits 0" '[ $? = 0 ]'
check "grid plot written" '[ -s "$work/grid/sweep_speed.png" ] || ! command -v gnuplot > /dev/null'
# A tuple grid: each row's scenario holds its tuple as the flag's text (the summary writes most as a JSON list).
mpirun -np 2 "$bin/rome_sweep" stepping-stones --grid sensor-noise=0,0:1e-4,1e-3:3 --set steps=2 --out "$work/tuple" \
  > "$work/tuple.out" 2>&1
check "tuple grid exits 0" '[ $? = 0 ]'
check "tuple grid rows hold their scenario tuple" 'python3 -c "
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
sys.exit(not (len(rows) == 3 and all(r[\"scenario.sensor-noise\"] == r[\"sensor-noise\"] != \"\" for r in rows)))
" "$work/tuple/sweep.csv"'
# Hopping (Cassie, 3D) over a grid of apex rises: every run hops and settles, and each row records its apex rise.
mpirun -np 2 "$bin/rome_sweep" hopping --grid apex-rise=0.15:0.20:2 --out "$work/hop" > "$work/hop.out" 2>&1
check "hopping sweep exits 0" '[ $? = 0 ]'
check "hopping sweep has 2 rows" '[ "$(wc -l < "$work/hop/sweep.csv")" = 3 ]'
check "hopping sweep success rate 1" 'grep -q "\"success_rate\": 1.0" "$work/hop/sweep.json"'
check "hopping rows hold the swept apex rise" 'grep -q "0.15" "$work/hop/sweep.csv" && grep -q "0.2" "$work/hop/sweep.csv"'
bad_walk_out=$("$bin/rome_sweep" walking --seeds 1:2 --set nonexistent=1 --out "$work/x" 2>&1)
check "walking is a known example (its flags are read)" 'printf "%s" "$bad_walk_out" | grep -q "example .walking. has no parameter .nonexistent."'
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
bad "--steps takes whole numbers, and this grid gives 1.5" stepping-stones --grid steps=1:2:3 --out "$work/x"
bad "--set seed=7: --seed is swept by --seeds 1:3" stepping-stones --seeds 1:3 --set seed=7 --out "$work/x"
bad "--energy is already swept by --grid energy=0.3:0.5:2" stepping-stones --grid energy=0.3:0.5:2 --grid energy=0.1:0.2:2 --out "$work/x"
bad "= 1e+20 runs; a sweep has at most 1000000" stepping-stones --grid energy=0:1:100000 --grid epsilon=0:1:100000 \
  --grid step-length=0:1:100000 --grid max-gap=0:1:100000 --out "$work/x"
bad "2000001 seeds; a sweep has at most 1000000 runs" stepping-stones --seeds 0:2000000 --out "$work/x"
mkdir -p "$work/runs_link"; ln -s "$work/victims" "$work/runs_link/runs"
bad "has a 'runs' that is not a folder" stepping-stones --seeds 1:2 --out "$work/runs_link"
[ "$fail" = 0 ] && echo "rome_sweep: all checks passed"
exit "$fail"
