#!/usr/bin/env bash
# walking's feasibility check before simulating (issue 39 §4), as a user sees it:
#  * (0.45 m, 0.35 s, 0.08 s, 0.20 m) asks the knee for more than its URDF effort (300 N m): exit 1 before any
#    simulation step, one line on stderr naming the gait, the knee, its need above 300 N m and the limit, no CSV log;
#  * gait A's plan passes the check (--check-only: exit 0, nothing simulated);
#  * the default gait change's direct transition is refused (the knee) and the plan kept passes the check (exit 0).
# usage: walking_feasibility_test.sh WALKING_BIN WORK_DIR
set -uo pipefail
walking="$1"; work="$2"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 2
fail=0
robot="$OLDPWD/robots/exoskeleton/exoskeleton.rome.json"

"$walking" --robot "$robot" --scenario periodic --gait-a 0.45,0.35,0.08,0.20 --steps 3 --cache plans --log refused.csv \
  > refused.out 2> refused.err
rc=$?
[ "$rc" = 1 ] || { echo "FAIL: the knee-limited gait exited $rc, expected 1"; fail=1; }
[ "$(wc -l < refused.err)" = 1 ] || { echo "FAIL: stderr is not one line:"; cat refused.err; fail=1; }
line="$(head -n 1 refused.err)"
re='gait 0\.45,0\.35,0\.08,0\.20: the (left|right) knee needs ([0-9]+) N m \(limit 300 N m\) at ([0-9.]+) s of single support'
if [[ "$line" =~ $re ]]; then
  need="${BASH_REMATCH[2]}"; at="${BASH_REMATCH[3]}"
  [ "$need" -gt 300 ] || { echo "FAIL: the refused knee needs $need N m, not above its 300 N m"; fail=1; }
  awk -v t="$at" 'BEGIN { exit !(t >= 0 && t <= 0.35) }' || { echo "FAIL: $at s is not inside the 0.35 s single support"; fail=1; }
else
  echo "FAIL: the refusal does not name the gait, the knee, its need and its limit: $line"; fail=1
fi
grep -q '^simulating' refused.out && { echo "FAIL: the refused gait was simulated"; fail=1; }
[ -e refused.csv ] && { echo "FAIL: the refused gait wrote a CSV log"; fail=1; }

"$walking" --robot "$robot" --scenario periodic --steps 3 --cache plans --check-only on --log passed.csv > passed.out 2> passed.err
rc=$?
[ "$rc" = 0 ] || { echo "FAIL: gait A's check exited $rc, expected 0:"; cat passed.err; fail=1; }
grep -q 'feasibility check (torque).*within what it enforces' passed.out || { echo "FAIL: gait A's check did not pass:"; cat passed.out; fail=1; }
grep -q '^simulating' passed.out && { echo "FAIL: --check-only simulated"; fail=1; }

# The default gait change: its direct transition asks more of the knee than it has; the planner refuses that
# transition, plans another way, and the plan it keeps passes the check (exit 0).
"$walking" --robot "$robot" --scenario gait-change --cache plans --check-only on > change.out 2> change.err
rc=$?
[ "$rc" = 0 ] || { echo "FAIL: the default gait change's check exited $rc, expected 0:"; cat change.err; fail=1; }
grep -q '^refused before simulating (force bound 1.6 m g): .* knee needs [0-9]* N m (limit 300 N m)' change.out ||
  { echo "FAIL: the direct transition's refusal is not reported:"; cat change.out; fail=1; }
grep -q 'feasibility check (torque).*within what it enforces' change.out ||
  { echo "FAIL: the kept gait-change plan did not pass the check:"; cat change.out; fail=1; }

[ "$fail" = 0 ] && echo "walking feasibility: refused '$line'; gait A passes; the default gait change is planned within the torque limits"
exit "$fail"
