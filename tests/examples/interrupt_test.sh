#!/usr/bin/env bash
# An interrupted run (issue: hostile input, lost outputs): SIGTERM or SIGINT stops the simulation at its next step,
# the program writes its log up to there and a summary whose status_kind is "interrupted", and exits 128 + signal.
# A run killed outright (SIGKILL) leaves the earlier outputs exactly as they were: outputs are written atomically.
# usage: interrupt_test.sh BIN_DIR WORK_DIR
set -euo pipefail
bin="$(cd "$1" && pwd)"; work="$2"
rm -rf "$work"; mkdir -p "$work"
cd "$work"
fail=0

run_and_signal() {  # run_and_signal SIGNAL SECONDS PROGRAM ARGS...: signals SECONDS after the simulation started; prints the exit code
  local sig="$1" after="$2"; shift 2
  # A shell without job control starts background jobs with SIGINT ignored (and the programs keep an ignored signal
  # ignored); env --default-signal gives the program the default disposition, as a foreground Ctrl-C would find it.
  env --default-signal=INT "$@" > run.out 2>&1 &
  local pid=$!
  for _ in $(seq 600); do  # the simulation has started when the program says so (up to 300 s: the sanitizer build is slow)
    grep -q 'simulating\|  t = ' run.out 2> /dev/null && break
    kill -0 "$pid" 2> /dev/null || break
    sleep 0.5
  done
  sleep "$after"
  kill -s "$sig" "$pid" 2> /dev/null || true
  local rc=0
  wait "$pid" || rc=$?
  echo "$rc"
}

complete_csv() {  # complete_csv FILE: every row has the header's column count, and the file ends with a newline
  awk -F, 'NR == 1 { n = NF } NF != n { bad = 1 } END { exit (bad || NR < 2) }' "$1" && [ "$(tail -c 1 "$1" | od -An -c | tr -d ' ')" = '\n' ]
}

for case in "TERM 143 stepping_stones --steps 4000 --terrain flat" "INT 130 hopping --duration 600"; do
  read -r sig code program args <<< "$case"
  printf 'old log\n' > log.csv; printf 'old summary\n' > summary.json
  # shellcheck disable=SC2086
  rc=$(run_and_signal "$sig" 2 "$bin/$program" $args --log log.csv --summary summary.json)
  if [ "$rc" != "$code" ]; then echo "FAIL: $program after SIG$sig exited $rc, expected $code"; cat run.out; fail=1; continue; fi
  grep -q '"status_kind": "interrupted"' summary.json || { echo "FAIL: $program's summary does not say interrupted"; fail=1; }
  complete_csv log.csv || { echo "FAIL: $program's log after SIG$sig is not a complete CSV"; fail=1; }
  echo "$program: SIG$sig -> exit $rc, $(($(wc -l < log.csv) - 1)) log rows, summary interrupted"
done

printf 'old log\n' > log.csv; printf 'old summary\n' > summary.json
rc=$(run_and_signal KILL 2 "$bin/stepping_stones" --steps 4000 --terrain flat --log log.csv --summary summary.json)
[ "$rc" = 137 ] || { echo "FAIL: SIGKILL gave exit $rc"; fail=1; }
[ "$(cat log.csv)" = "old log" ] && [ "$(cat summary.json)" = "old summary" ] || { echo "FAIL: a killed run changed the earlier outputs"; fail=1; }
left=$(find . -name '.*.??????' | wc -l)
echo "stepping_stones: SIGKILL -> exit $rc, earlier outputs intact, $left temporary files left"
[ "$fail" = 0 ] && echo "interrupt: all checks passed"
exit "$fail"
