#!/usr/bin/env bash
# A shared robot package with script in its names (issue: security at the trust boundaries): AMBER's torso link is
# renamed to close the page's <script> element and inject an <img> whose handler sets the title. The walk's animation
# page, opened in headless Chromium, must run its own scripts (the Content-Security-Policy's hashes match: the test
# report appears), show no injected element, keep its title, and carry the name as data. A control copy of the page
# with an inline script appended checks that the policy blocks scripts it does not name.
# usage: hostile_page_test.sh STEPPING_STONES_BINARY WORK_DIR
set -euo pipefail
bin="$1"; work="$2"
rm -rf "$work"; mkdir -p "$work"
command -v chromium > /dev/null || { echo "FAIL: chromium is not installed (./rome setup installs it)"; exit 1; }
pkg="$work/amber_hostile"
cp -r robots/amber "$pkg"
hostile='torso\&lt;/script\&gt;\&lt;img src=x onerror=\&quot;document.title=\&#39;PWNED\&#39;\&quot;\&gt;\&lt;script\&gt;document.title=\&#39;PWNED2\&#39;\&lt;/script\&gt;'
sed -i "s|name=\"torso\"|name=\"$hostile\"|; s|link=\"torso\"|link=\"$hostile\"|g" "$pkg/amber.urdf"
grep -q 'PWNED2' "$pkg/amber.urdf" || { echo "FAIL: the hostile name was not planted"; exit 1; }
page="$work/page.html"
"$bin" --robot "$(cd "$pkg" && pwd)/amber.rome.json" --steps 2 --terrain flat --log "" --summary "" --animation "$page" > "$work/run.out" 2>&1 ||
  { echo "FAIL: the walk with the hostile robot did not run"; cat "$work/run.out"; exit 1; }
fail=0
# The raw page: the name is data inside the script (escaped), never markup.
[ "$(grep -o '<script>' "$page" | wc -l)" = 3 ] || { echo "FAIL: the page has other than its 3 scripts"; fail=1; }
grep -q '<img' "$page" && { echo "FAIL: an <img> element is in the page's text"; fail=1; }
grep -q 'torso\\u003C/script\\u003E\\u003Cimg' "$page" || { echo "FAIL: the name is not in the data, escaped"; fail=1; }
grep -q 'http-equiv="Content-Security-Policy"' "$page" || { echo "FAIL: no Content-Security-Policy"; fail=1; }
url() { echo "file://$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"; }
dump() { timeout 120 chromium --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader --window-size=800,500 --dump-dom "$1" 2>> "$work/chromium.log"; }
dom=$(dump "$(url "$page")#test=0.2,0.8")
report=$(printf '%s' "$dom" | sed -n 's/.*<pre id="test-result">\([^<]*\)<.*/\1/p')
echo "report: $report"
[ -n "$report" ] || { echo "FAIL: the page's own scripts did not run to the end (CSP hashes?)"; fail=1; }
case "$report" in *'"errors":[]'*) ;; *) echo "FAIL: JavaScript errors"; fail=1 ;; esac
case "$dom" in *'<img'*) echo "FAIL: an <img> element was created"; fail=1 ;; esac
case "$dom" in *PWNED*'</title>'*) echo "FAIL: the injected handler ran (title changed)"; fail=1 ;; esac
grep -q '<title>ROME stepping stones' <<< "$dom" || { echo "FAIL: the page's title is not its own"; fail=1; }
# Control: an inline script the policy does not name is blocked.
control="$work/control.html"
sed 's|</body></html>|<script>document.title="INJECTED";</script></body></html>|' "$page" > "$control"
case "$(dump "$(url "$control")#test=0.2")" in *INJECTED*'</title>'*) echo "FAIL: an unlisted inline script ran"; fail=1 ;; esac
[ "$fail" = 0 ] && echo "hostile page: all checks passed"
exit "$fail"
