#!/usr/bin/env bash
# The stepping-stones paper's speed range on flat 0.8 m steps (issue 44 §3), as a user sees it:
#  * AMBER at E* = 1.0 (epsilon 0.6): the plan asks the stance foot for |F_t|/F_n above mu = 0.8 at the impact
#    (CalcPeriodicPlanFrictionNeed): exit 1 before any simulation step, one line on stderr naming the robot, the gait,
#    the need, the time in the step and mu, and no log or summary written;
#  * planar Cassie at E* = 1.5 walks 30 steps at >= 1.5 m/s with every plant contact force unilateral and inside the
#    friction cone (the example's count of violations over all samples is 0).
# usage: stepping_stones_speed_test.sh STEPPING_STONES_BIN WORK_DIR
set -uo pipefail
bin="$1"; work="$2"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 2
fail=0

"$bin" --terrain flat --step-length 0.8 --energy 1.0 --steps 30 --log refused.csv --summary refused.json \
  > refused.out 2> refused.err
rc=$?
[ "$rc" = 1 ] || { echo "FAIL: AMBER at E* 1.0 exited $rc, expected 1"; fail=1; }
[ "$(wc -l < refused.err)" = 1 ] || { echo "FAIL: stderr is not one line:"; cat refused.err; fail=1; }
line="$(head -n 1 refused.err)"
re="robot 'amber' at E\* 1 m\^2/s\^2, epsilon 0\.6 on 0\.8 m steps \(rise 0 m\): the plan needs \|F_t\|/F_n ([0-9.]+) at ([0-9.]+) s of the ([0-9.]+) s step .*the feet have mu 0\.8"
if [[ "$line" =~ $re ]]; then
  need="${BASH_REMATCH[1]}"; at="${BASH_REMATCH[2]}"; step="${BASH_REMATCH[3]}"
  awk -v n="$need" 'BEGIN { exit !(n > 0.8) }' || { echo "FAIL: the refused plan needs $need, not above mu 0.8"; fail=1; }
  awk -v t="$at" -v T="$step" 'BEGIN { exit !(t >= 0 && t <= T) }' || { echo "FAIL: $at s is not inside the $step s step"; fail=1; }
else
  echo "FAIL: the refusal does not name the robot, the gait, the need and mu: $line"; fail=1
fi
grep -q 'steps' refused.out && { echo "FAIL: the refused gait was simulated:"; cat refused.out; fail=1; }
[ -e refused.csv ] && { echo "FAIL: the refused gait wrote a CSV log"; fail=1; }
[ -e refused.json ] && { echo "FAIL: the refused gait wrote a summary"; fail=1; }

"$bin" --robot robots/cassie_planar/cassie_planar.rome.json --terrain flat --step-length 0.8 --energy 1.5 --steps 30 \
  --log cassie.csv --summary cassie.json > cassie.out 2> cassie.err
rc=$?
[ "$rc" = 0 ] || { echo "FAIL: planar Cassie at E* 1.5 exited $rc:"; tail -n 3 cassie.out; cat cassie.err; fail=1; }
grep -q '^30 of 30 steps' cassie.out || { echo "FAIL: planar Cassie did not walk 30 steps"; fail=1; }
speed="$(sed -n 's/^mean forward speed \([0-9.]*\) m\/s.*/\1/p' cassie.out)"
awk -v v="${speed:-0}" 'BEGIN { exit !(v >= 1.5) }' || { echo "FAIL: planar Cassie walked at '$speed' m/s, below 1.5"; fail=1; }
grep -q 'violations 0 of [1-9][0-9]* samples' cassie.out ||
  { echo "FAIL: a plant contact force left the friction cone or pulled:"; grep 'plant contact forces' cassie.out; fail=1; }

[ "$fail" = 0 ] && echo "stepping-stones speed: refused '$line'; planar Cassie $speed m/s"
exit "$fail"
