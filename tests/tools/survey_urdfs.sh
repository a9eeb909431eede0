#!/usr/bin/env bash
# Runs model_info on every URDF under a folder and prints one table row per file: loaded, refused
# (with model_info's one-line message), crash (killed by a signal) or hang (timeout), with nq and nv
# (position and velocity coordinates), the floating base (model_info's floating_base: quaternion,
# the default for a URDF "floating" joint, spatial_euler, planar or fixed), bodies (after merging
# fixed joints), frames (URDF links), warnings and the load time. Ends with a summary and the
# refusals grouped by class. It reads local files only and fetches nothing.
#
# Usage: survey_urdfs.sh [--bin MODEL_INFO] [--timeout SECONDS] [--repeat N] [--repair-inertia] [--euler-base] FOLDER
#   --bin        model_info to run (default: build/bin/model_info next to this source tree)
#   --timeout    seconds before a run counts as a hang (default 20)
#   --repeat     runs per loaded file; the load time is their median (default 1)
#   --repair-inertia  pass --repair-inertia to model_info
#   --euler-base      pass --euler-base to model_info (a spatial base as ZYX Euler, nq = nv)
# Each file is loaded without a sidecar unless FILE.rome.json sits next to it (model_info's default).
# Exit: 0 when nothing crashed or hung, 3 otherwise, 1 for bad arguments.
set -u
here="$(cd "$(dirname "$0")/../.." && pwd)"
bin="$here/build/bin/model_info"; limit=20; repeat=1; extra=(); dir=""
die() { echo "survey_urdfs.sh: error: $*" >&2; exit 1; }
while [ $# -gt 0 ]; do
  case "$1" in
    --bin) [ $# -ge 2 ] || die "--bin needs a file"; bin="$2"; shift 2 ;;
    --timeout) [ $# -ge 2 ] || die "--timeout needs seconds"; limit="$2"; shift 2 ;;
    --repeat) [ $# -ge 2 ] || die "--repeat needs a count"; repeat="$2"; shift 2 ;;
    --repair-inertia) extra+=(--repair-inertia); shift ;;
    --euler-base) extra+=(--euler-base); shift ;;
    -h|--help) sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) die "unknown option '$1' (see --help)" ;;
    *) [ -z "$dir" ] || die "unexpected argument '$1' (one folder only)"; dir="$1"; shift ;;
  esac
done
[ -n "$dir" ] || die "no folder given (see --help)"
[ -d "$dir" ] || die "folder '$dir' does not exist"
[ -x "$bin" ] || die "model_info '$bin' is not an executable (build first, or pass --bin)"
case "$limit" in ''|*[!0-9]*) die "--timeout must be a whole number of seconds, got '$limit'" ;; esac
case "$repeat" in ''|*[!0-9]*|0) die "--repeat must be a positive whole number, got '$repeat'" ;; esac

tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
mapfile -t files < <(find "$dir" -type f -name '*.urdf' | LC_ALL=C sort)
[ "${#files[@]}" -gt 0 ] || die "no *.urdf files under '$dir'"

# Fields of model_info's JSON summary (pretty-printed, two-space indent; no JSON tool needed).
field() { sed -n "s/^  \"$1\": \\([^,]*\\),\\{0,1\\}\$/\\1/p" "$2" | head -n 1 | tr -d '"'; }
count_in() {  # count_in KEY FILE: entries of the top-level array KEY
  awk -v key="\"$1\": [" '
    index($0, "  " key) == 1 { if ($0 ~ /\]/) { print 0; exit } inside = 1; n = 0; next }
    inside && /^  \]/ { print n; exit }
    inside && /^    [^ }\]]/ { n++ }' "$2"
}
median() { LC_ALL=C sort -g | awk '{ v[NR] = $1 } END { if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

loaded=0; refused=0; crashed=0; hung=0
printf '%-8s %4s %4s %-13s %6s %6s %8s %10s  %s\n' result nq nv base bodies frames warnings load_ms file
: > "$tmp/refusals"
for f in "${files[@]}"; do
  abs="$(cd "$(dirname "$f")" && pwd)/$(basename "$f")"
  times=()
  for ((i = 0; i < repeat; i++)); do
    (cd "$tmp" && timeout "$limit" "$bin" "$abs" "${extra[@]}" > "$tmp/out.json" 2> "$tmp/err.txt")
    rc=$?
    [ "$rc" -eq 0 ] || break
    times+=("$(field load_time_ms "$tmp/out.json")")
  done
  if [ "$rc" -eq 0 ]; then
    loaded=$((loaded + 1))
    ms="$(printf '%s\n' "${times[@]}" | median)"
    printf '%-8s %4s %4s %-13s %6s %6s %8s %10.3f  %s\n' loaded "$(field nq "$tmp/out.json")" \
      "$(field nv "$tmp/out.json")" "$(field floating_base "$tmp/out.json")" \
      "$(count_in bodies "$tmp/out.json")" "$(count_in frames "$tmp/out.json")" \
      "$(count_in warnings "$tmp/out.json")" "$ms" "$f"
  elif [ "$rc" -eq 124 ]; then
    hung=$((hung + 1)); printf '%-8s %4s %4s %-13s %6s %6s %8s %10s  %s (no answer within %s s)\n' hang - - - - - - - "$f" "$limit"
  elif [ "$rc" -eq 1 ]; then
    refused=$((refused + 1))
    lines=$(wc -l < "$tmp/err.txt")
    msg="$(head -n 1 "$tmp/err.txt")"
    [ "$lines" -eq 1 ] || msg="$msg [NOT ONE LINE: $lines lines on stderr]"
    printf '%-8s %4s %4s %-13s %6s %6s %8s %10s  %s\n' refused - - - - - - - "$f"
    printf '         %s\n' "$msg"
    printf '%s\n' "$msg" >> "$tmp/refusals"
  else
    crashed=$((crashed + 1)); printf '%-8s %4s %4s %-13s %6s %6s %8s %10s  %s (exit code %s)\n' crash - - - - - - - "$f" "$rc"
  fi
done

echo
echo "files ${#files[@]}: loaded $loaded, refused $refused, crash $crashed, hang $hung"
if [ "$refused" -gt 0 ]; then
  echo "refusals by class:"
  awk '{
    c = "other"
    if (/violates the triangle inequality/) c = "non-physical inertia (triangle inequality)"
    else if (/not positive semi-definite/) c = "non-physical inertia (not positive semi-definite)"
    else if (/moves no mass/) c = "moving joint moves no mass (M singular)"
    else if (/unsupported joint type/) c = "unsupported joint type"
    else if (/(floating|planar) joint .* is not supported|(floating|planar) joint .*: (its parent|root link|<axis>|<origin>)/) c = "floating/planar joint not from a massless root"
    else if (/malformed or invalid URDF/) c = "malformed URDF"
    n[c]++ }
    END { for (c in n) printf "  %3d  %s\n", n[c], c }' "$tmp/refusals" | LC_ALL=C sort -k1,1nr
fi
[ "$crashed" -eq 0 ] && [ "$hung" -eq 0 ] || exit 3
