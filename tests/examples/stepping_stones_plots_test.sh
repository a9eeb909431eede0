#!/usr/bin/env bash
# --plots works for every robot, not only AMBER: the example walks a few steps with planar Cassie (line feet, other
# link names) and AMBER, exits 0, and writes each plot as a non-empty PNG file (its 8-byte signature checked).
# usage: stepping_stones_plots_test.sh STEPPING_STONES_BINARY WORK_DIR   (run from the repository root)
set -euo pipefail
bin="$1"; work="$2"
rm -rf "$work"; mkdir -p "$work"
fail=0
png_signature="89504e470d0a1a0a"
for robot in robots/cassie_planar/cassie_planar.rome.json robots/amber/amber.rome.json; do
  name="$(basename "$robot" .rome.json)"
  out="$work/$name"
  mkdir -p "$out"
  code=0
  "$bin" --robot "$robot" --steps 3 --terrain flat --log "$out/log.csv" --summary "$out/summary.json" --plots "$out/plots" \
    > "$out/run.log" 2>&1 || code=$?
  if [ "$code" -ne 0 ]; then echo "FAIL: $name: exit code $code"; cat "$out/run.log"; fail=1; continue; fi
  for plot in com_height phase_portrait gait_tiles outputs pre_impact_vz; do
    f="$out/plots/$plot.png"
    if [ ! -s "$f" ]; then echo "FAIL: $name: $f is missing or empty"; fail=1; continue; fi
    sig="$(head -c 8 "$f" | od -An -tx1 | tr -d ' \n')"
    [ "$sig" = "$png_signature" ] || { echo "FAIL: $name: $f is not a PNG file (starts with $sig)"; fail=1; }
  done
  if grep -q "warning" "$out/run.log"; then echo "FAIL: $name: the run printed a warning"; grep warning "$out/run.log"; fail=1; fi
  [ "$fail" -ne 0 ] || echo "$name: exit 0, 5 PNG plots"
done
exit "$fail"
