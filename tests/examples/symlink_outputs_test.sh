#!/usr/bin/env bash
# Outputs cannot be redirected (issue: security at the trust boundaries). Each program runs once to learn every file
# it writes; then a symlink to a victim file outside the output folder is planted at each of those names, and the
# program runs again. Every victim must keep its content, every output must be a regular file, and no file may be
# left in the output folder but the program's own outputs (no temporary file).
# usage: symlink_outputs_test.sh BIN_DIR WORK_DIR
set -euo pipefail
bin="$(cd "$1" && pwd)"; work="$2"
rm -rf "$work"; mkdir -p "$work"
work="$(cd "$work" && pwd)"
fail=0

check() {  # check NAME COMMAND...: COMMAND writes into $out (its current folder)
  local name="$1"; shift
  local out="$work/$name/out" victims="$work/$name/victims"
  mkdir -p "$out" "$victims"
  (cd "$out" && "$@" > "$work/$name/first.log" 2>&1) || { echo "FAIL: $name: the first run failed"; cat "$work/$name/first.log"; fail=1; return; }
  local files; files=$(cd "$out" && find . -type f | sort)
  [ -n "$files" ] || { echo "FAIL: $name wrote nothing"; fail=1; return; }
  local i=0
  while IFS= read -r f; do
    i=$((i + 1))
    printf 'victim %d\n' "$i" > "$victims/v$i"
    rm "$out/$f"; ln -s "$victims/v$i" "$out/$f"
  done <<< "$files"
  (cd "$out" && "$@" > "$work/$name/second.log" 2>&1) || { echo "FAIL: $name: the run with planted links failed"; cat "$work/$name/second.log"; fail=1; return; }
  i=0
  while IFS= read -r f; do
    i=$((i + 1))
    [ "$(cat "$victims/v$i")" = "victim $i" ] || { echo "FAIL: $name wrote through the link at $f"; fail=1; }
    [ -f "$out/$f" ] && [ ! -L "$out/$f" ] || { echo "FAIL: $name: $f is not a regular file after the run"; fail=1; }
  done <<< "$files"
  local after; after=$(cd "$out" && find . -type f -o -type l | sort)
  [ "$after" = "$files" ] || { echo "FAIL: $name left other files: $(comm -13 <(echo "$files") <(echo "$after") | tr '\n' ' ')"; fail=1; }
  echo "$name: $(echo "$files" | wc -l) outputs, none written through a planted link"
}

check bouncing_ball "$bin/bouncing_ball" --log ball.csv --summary ball.json --plots plots --animation ball.html
check stepping_stones "$bin/stepping_stones" --steps 3 --terrain flat --log ss.csv --summary ss.json --plots plots --animation ss.html
check hopping "$bin/hopping" --log hop.csv --summary hop.json --plots plots --animation hop.html
# walking's plan cache is kept outside the output folder (its entries are checked by plan_cache_test).
check walking "$bin/walking" --scenario periodic --steps 2 --cache "$work/walking_plans" --log walk.csv --summary walk.json --plots plots \
  --animation walk.html
[ "$fail" = 0 ] && echo "symlink outputs: all checks passed"
exit "$fail"
