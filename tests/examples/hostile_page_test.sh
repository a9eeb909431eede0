#!/usr/bin/env bash
# Shared robot packages with script in their names (issue: security at the trust boundaries). For each diagram's
# program, a copy of its robot has one link renamed to close the page's <script> element, inject an <img> whose handler
# sets the title, and open a script of its own. The run's animation page, opened in headless Chromium, must run its own
# scripts (the Content-Security-Policy's hashes match: the test report appears), create no injected element, keep its
# title, and carry the name as escaped data. A control copy of one page with an inline script appended checks that
# the policy blocks scripts it does not name.
# usage: hostile_page_test.sh BIN_DIR WORK_DIR
set -euo pipefail
bin="$(cd "$1" && pwd)"; work="$2"
rm -rf "$work"; mkdir -p "$work"; work="$(cd "$work" && pwd)"
command -v chromium > /dev/null || { echo "FAIL: chromium is not installed (./rome setup installs it)"; exit 1; }
fail=0
url() { echo "file://$1"; }
dump() { timeout 120 chromium --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader --window-size=800,500 --dump-dom "$1" 2>> "$work/chromium.log"; }

plant() {  # plant ROBOT_DIR URDF LINK: renames LINK in the copy's URDF (XML entities keep the file valid)
  local h="$3"'\&lt;/script\&gt;\&lt;img src=x onerror=\&quot;document.title=\&#39;PWNED\&#39;\&quot;\&gt;\&lt;script\&gt;document.title=\&#39;PWNED2\&#39;\&lt;/script\&gt;'
  sed -i "s|<link name=\"$3\"|<link name=\"$h\"|; s| link=\"$3\"| link=\"$h\"|g" "$1/$2"
  grep -q 'PWNED2' "$1/$2" || { echo "FAIL: the hostile name was not planted in $2"; exit 1; }
}

check_page() {  # check_page NAME PAGE TITLE LINK
  local name="$1" page="$2" title="$3" link="$4"
  [ "$(grep -o '<script>' "$page" | wc -l)" = 3 ] || { echo "FAIL: $name: the page has other than its 3 scripts"; fail=1; }
  grep -q '<img' "$page" && { echo "FAIL: $name: an <img> element is in the page's text"; fail=1; }
  grep -q "$link"'\\u003C/script\\u003E\\u003Cimg' "$page" || { echo "FAIL: $name: the name is not in the data, escaped"; fail=1; }
  grep -q 'http-equiv="Content-Security-Policy"' "$page" || { echo "FAIL: $name: no Content-Security-Policy"; fail=1; }
  local dom report
  dom=$(dump "$(url "$page")#test=0.2,0.8")
  report=$(sed -n 's/.*<pre id="test-result">\([^<]*\)<.*/\1/p' <<< "$dom")
  [ -n "$report" ] || { echo "FAIL: $name: the page's own scripts did not run to the end (CSP hashes?)"; fail=1; }
  case "$report" in *'"errors":[]'*) ;; *) echo "FAIL: $name: JavaScript errors: $report"; fail=1 ;; esac
  case "$dom" in *'<img'*) echo "FAIL: $name: an <img> element was created"; fail=1 ;; esac
  case "$dom" in *PWNED*'</title>'*) echo "FAIL: $name: an injected script ran (title changed)"; fail=1 ;; esac
  grep -q "<title>$title" <<< "$dom" || { echo "FAIL: $name: the page's title is not its own"; fail=1; }
  echo "$name: page ran its own scripts only, name shown as data; report: $report"
}

# stepping_stones: AMBER's torso.
cp -r robots/amber "$work/amber"; plant "$work/amber" amber.urdf torso
"$bin/stepping_stones" --robot "$work/amber/amber.rome.json" --steps 2 --terrain flat --log "" --summary "" \
  --animation "$work/stepping_stones.html" > "$work/stepping_stones.out" 2>&1 || { echo "FAIL: stepping_stones with the hostile robot"; cat "$work/stepping_stones.out"; exit 1; }
check_page stepping_stones "$work/stepping_stones.html" "ROME stepping stones" torso
# walking: the exoskeleton's left thigh.
cp -r robots/exoskeleton "$work/exoskeleton"; plant "$work/exoskeleton" exoskeleton.urdf left_thigh
"$bin/walking" --robot "$work/exoskeleton/exoskeleton.rome.json" --scenario periodic --steps 2 --cache "$work/plans" --log "" --summary "" \
  --animation "$work/walking.html" > "$work/walking.out" 2>&1 || { echo "FAIL: walking with the hostile robot"; cat "$work/walking.out"; exit 1; }
check_page walking "$work/walking.html" "ROME walking" left_thigh
# hopping (its robot is fixed: the hostile Cassie is found through ROME_DATA_DIR): the left shin.
mkdir -p "$work/data/robots"; cp -r robots/cassie "$work/data/robots/cassie"; plant "$work/data/robots/cassie" cassie.urdf left_shin
ROME_DATA_DIR="$work/data" "$bin/hopping" --log "" --summary "" --animation "$work/hopping.html" > "$work/hopping.out" 2>&1 ||
  { echo "FAIL: hopping with the hostile robot"; cat "$work/hopping.out"; exit 1; }
check_page hopping "$work/hopping.html" "ROME hopping" left_shin

# Control: an inline script the policy does not name is blocked.
sed 's|</body></html>|<script>document.title="INJECTED";</script></body></html>|' "$work/stepping_stones.html" > "$work/control.html"
case "$(dump "$(url "$work/control.html")#test=0.2")" in *INJECTED*'</title>'*) echo "FAIL: an unlisted inline script ran"; fail=1 ;; esac
[ "$fail" = 0 ] && echo "hostile pages: all checks passed"
exit "$fail"
