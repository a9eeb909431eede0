#!/usr/bin/env bash
# The stepping-stones paper's speed range on its periodic terrains (issue 44 §3), as a user sees it: 30 steps at
# >= 1.5 m/s with every sample of the plant's contact forces unilateral and inside the friction cone (the example
# counts the samples that are not: "violations 0 of N samples"; a slip ends the run with exit 3):
#  * AMBER on stairs down, 0.8 m apart and 0.2 m lower (the paper's longest step and deepest drop), E* = 0.5;
#  * AMBER on flat ground, 0.65 m steps, E* = 2.5 (1.66 m/s measured);
#  * planar Cassie on flat 0.8 m steps, E* = 1.5;
#  * AMBER on flat 0.8 m steps, E* = 2.0, with both controllers (1.59 m/s measured; the pre-impact COM capped at
#    0.904 m from both feet, supervisor.max_com_foot_distance_m). These two runs log every 1 ms control sample, and the
#    log is checked on its own: each foot's force unilateral (F_z >= 0) and inside the friction cone |F_x| <= mu F_z
#    (mu = 0.8, robots/amber), each torque within AMBER's 100 N m, and the speed from the plant's COM,
#    (x_end - x_start) / (t_end - t_start) >= 1.5 m/s. Without the cap (--max-com-foot-distance 100, the walking height
#    0.80 m) the same gait slips (exit 3): the cap is what lets it walk.
# And --plan-check (the plan's inverse dynamics, printed before the run): a bad value or a non-periodic course is bad
# input (exit 1, one line naming the option and the value).
# usage: stepping_stones_speed_test.sh STEPPING_STONES_BIN WORK_DIR
set -uo pipefail
bin="$1"; work="$2"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 2
fail=0
summary=""

walk() {  # walk NAME ARGS...: 30 steps at >= 1.5 m/s, no contact violation
  local name="$1"; shift
  "$bin" "$@" --steps 30 --log "$name.csv" --summary "$name.json" > "$name.out" 2> "$name.err"
  local rc=$?
  [ "$rc" = 0 ] || { echo "FAIL: $name exited $rc:"; tail -n 3 "$name.out"; cat "$name.err"; fail=1; }
  grep -q '^30 of 30 steps' "$name.out" || { echo "FAIL: $name did not walk 30 steps"; fail=1; }
  local speed
  speed="$(sed -n 's/^mean forward speed \([0-9.]*\) m\/s.*/\1/p' "$name.out")"
  awk -v v="${speed:-0}" 'BEGIN { exit !(v >= 1.5) }' || { echo "FAIL: $name walked at '$speed' m/s, below 1.5"; fail=1; }
  grep -q 'violations 0 of [1-9][0-9]* samples' "$name.out" ||
    { echo "FAIL: $name: a plant contact force pulled or left the friction cone:"; grep 'plant contact forces' "$name.out"; fail=1; }
  summary="$summary $name $speed m/s;"
}

walk amber_stairs_down --terrain stairs-down --step-length 0.8 --step-height -0.2 --energy 0.5
walk amber_flat --terrain flat --step-length 0.65 --energy 2.5 --plan-check report
grep -q '^plan check: the plan needs [0-9.]* N m at the \(stance\|swing\) [a-z_]* (limit 100 N m)' amber_flat.out ||
  { echo "FAIL: amber_flat printed no plan check line:"; grep 'plan check' amber_flat.out; fail=1; }

refused() {  # refused NAME PATTERN ARGS...: exit 1 with one error line matching PATTERN
  local name="$1" pattern="$2"; shift 2
  "$bin" "$@" --steps 2 > "$name.out" 2> "$name.err"
  local rc=$?
  [ "$rc" = 1 ] || { echo "FAIL: $name exited $rc, expected 1"; fail=1; }
  [ "$(wc -l < "$name.err")" = 1 ] && grep -q "$pattern" "$name.err" ||
    { echo "FAIL: $name: expected one line matching '$pattern':"; cat "$name.err"; fail=1; }
}
refused plan_check_value "plan-check must be 'off' or 'report', got 'on'" --terrain flat --plan-check on
refused plan_check_random "plan-check report needs --terrain flat, stairs-up or stairs-down.*got 'random'" \
  --terrain random --plan-check report

walk cassie_flat --robot robots/cassie_planar/cassie_planar.rome.json --terrain flat --step-length 0.8 --energy 1.5

check_log() {  # check_log NAME: every logged sample of NAME.csv inside the cone, torques within 100 N m, COM speed
  local report
  report="$(awk -F, '
    NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
    {
      for (f = 0; f < 2; ++f) {
        side = f ? "right_foot" : "left_foot"
        fx = $c["plant.contact_forces." side "_fx"]; fz = $c["plant.contact_forces." side "_fz"]
        if (fz < -1e-9) { bad = bad sprintf(" t=%s %s pulls (F_z %g N);", $1, side, fz) }
        if ((fx < 0 ? -fx : fx) > 0.8 * fz + 1e-9) { bad = bad sprintf(" t=%s %s out of the cone (F_x %g, F_z %g N);", $1, side, fx, fz) }
      }
      for (j = 0; j < 4; ++j) { u = $c["controller.u[" j "]"]; if ((u < 0 ? -u : u) > 100 + 1e-6) bad = bad sprintf(" t=%s u[%d] = %g N m;", $1, j, u) }
      if (n == 0) { t0 = $1; x0 = $c["plant.com.x"] }
      t1 = $1; x1 = $c["plant.com.x"]; ++n
    }
    END { if (n < 1000 || t1 <= t0) { print "FAIL too few samples " n; exit }
          v = (x1 - x0) / (t1 - t0)
          if (bad != "") print "FAIL" substr(bad, 1, 400); else if (v < 1.5) print "FAIL COM speed " v " m/s"; else print "ok " n " samples, COM speed " v " m/s" }' "$1.csv")"
  case "$report" in ok*) summary="$summary $1 log: ${report#ok };" ;; *) echo "FAIL: $1: ${report:-no log $1.csv}"; fail=1 ;; esac
}
for controller in tsc-qp clf-qp; do
  walk "amber_flat08_$controller" --terrain flat --step-length 0.8 --energy 2.0 --controller "$controller" --log-period 0.001
  check_log "amber_flat08_$controller"
done
"$bin" --terrain flat --step-length 0.8 --energy 2.0 --max-com-foot-distance 100 --steps 30 --log uncapped.csv \
  --summary uncapped.json > uncapped.out 2> uncapped.err
rc=$?
[ "$rc" = 3 ] && grep -q 'slipped' uncapped.out ||
  { echo "FAIL: flat 0.8 m at E* = 2.0 without the cap exited $rc (expected 3, a slip):"; tail -n 2 uncapped.out; fail=1; }

[ "$fail" = 0 ] && echo "stepping-stones speed:$summary"
exit "$fail"
