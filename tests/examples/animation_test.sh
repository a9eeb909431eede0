#!/usr/bin/env bash
# The stepping_stones animation page in headless Chromium (Debian's chromium, installed by ./rome setup): the page
# renders two times of a 4-step walk (test hook #test=t1,t2), and reports the robot's pixel centroid at each, whether
# every stone on screen is drawn where the terrain puts it, and any JavaScript error.
# usage: animation_test.sh STEPPING_STONES_BINARY WORK_DIR
set -euo pipefail
bin="$1"; work="$2"
mkdir -p "$work"
page="$work/animation_test.html"
"$bin" --steps 4 --terrain random --seed 3 --log "" --summary "" --animation "$page" > "$work/animation_test.out"
command -v chromium > /dev/null || { echo "FAIL: chromium is not installed (./rome setup installs it)"; exit 1; }
dom=$(timeout 120 chromium --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader --window-size=800,500 \
      --dump-dom "file://$(cd "$(dirname "$page")" && pwd)/$(basename "$page")#test=0.3,1.6" 2> "$work/chromium.log")
report=$(printf '%s' "$dom" | sed -n 's/.*<pre id="test-result">\([^<]*\)<.*/\1/p')
echo "report: $report"
[ -n "$report" ] || { echo "FAIL: the page wrote no test report (JavaScript did not run to the end)"; exit 1; }
fail=0
case "$report" in *'"errors":[]'*) ;; *) echo "FAIL: JavaScript errors"; fail=1 ;; esac
checked=$(printf '%s' "$report" | sed -n 's/.*"stones_checked":\([0-9]*\).*/\1/p')
ok=$(printf '%s' "$report" | sed -n 's/.*"stones_ok":\([0-9]*\).*/\1/p')
[ "${checked:-0}" -ge 3 ] || { echo "FAIL: fewer than 3 stones on screen ($checked)"; fail=1; }
[ "$ok" = "$checked" ] || { echo "FAIL: $ok of $checked stones drawn where the terrain puts them"; fail=1; }
# The robot moved between the two times: its red pixels' centroid or count changed.
read -r x1 y1 n1 x2 y2 n2 < <(printf '%s' "$report" | sed -n 's/.*"centroids":\[\[\([^]]*\)\],\[\([^]]*\)\]\].*/\1,\2/p' | tr ',' ' ') || true
[ -n "${n2:-}" ] || { echo "FAIL: the robot is not on screen at both times"; exit 1; }
moved=$(awk -v a="$x1" -v b="$y1" -v c="$n1" -v d="$x2" -v e="$y2" -v f="$n2" \
  'BEGIN { dx = a - d; dy = b - e; dn = (c - f) / c; if (dn < 0) dn = -dn; print (sqrt(dx*dx + dy*dy) > 3 || dn > 0.05) ? 1 : 0 }')
[ "$moved" = 1 ] || { echo "FAIL: the robot's pixels did not move between the two times"; fail=1; }
[ "$fail" = 0 ] && echo "animation page: all checks passed"
exit "$fail"
