#!/usr/bin/env bash
# Runs every entry of the bad-input catalogue and reports every mismatch (not only the first).
# Usage: run_catalogue.sh BIN_DIR CATALOGUE.tsv INPUTS_DIR [LIMIT_S]
#
# Catalogue lines (tab-separated; '#' starts a comment line):
#   program  expected_exit  required_words  arguments
# program: stepping_stones | bouncing_ball | model_info (in BIN_DIR). required_words: '|'-separated strings that
# must all appear in the error (stderr) for exit 1, or in stdout + stderr otherwise ('-' for none). arguments:
# space-separated; @IN@ is INPUTS_DIR, @TMP@ a scratch folder holding the generated inputs (see below), @EMPTY@ an
# empty argument; backslash escapes (\xFF, \t) are expanded, so any byte can be passed.
# Every entry also must: end within its time limit (LIMIT_S, default 60 s; the sanitizer build passes 300 s, where
# the programs run 15-25 times slower: no hang), not die from a signal (no crash), and, for
# exit 1, print exactly one line on stderr, of at most 2000 bytes, with no control bytes (truncated, escaped).
# The programs run in a scratch folder (empty but for a planted robots/amber/amber.rome.json), so default outputs
# never land in the source tree.
set -u
bin="$(cd "$1" && pwd)"; catalogue="$2"; inputs="$(cd "$3" && pwd)"; limit="${4:-60}"
case "$limit" in ''|*[!0-9]*) echo "run_catalogue.sh: LIMIT_S must be a whole number of seconds, got '$limit'"; exit 2 ;; esac
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/run"

# ---- Generated inputs (too big, or too many, to keep in git) ----
chain() {  # chain N FILE: N links in a chain of revolute joints
  {
    echo '<?xml version="1.0"?>'; echo '<robot name="chain">'
    awk -v n="$1" 'BEGIN {
      for (i = 0; i <= n; i++)
        printf "<link name=\"l%d\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial></link>\n", i
      for (i = 1; i <= n; i++)
        printf "<joint name=\"j%d\" type=\"revolute\"><parent link=\"l%d\"/><child link=\"l%d\"/><origin xyz=\"0 0 -0.1\"/><axis xyz=\"0 1 0\"/><limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"5\"/></joint>\n", i, i - 1, i
    }'
    echo '</robot>'
  } > "$2"
}
chain 10000 "$tmp/chain_10000.urdf"
chain 4000 "$tmp/chain_4000.urdf"
awk 'BEGIN { printf "<robot name=\"deep\">"; for (i = 0; i < 200000; i++) printf "<a>"; for (i = 0; i < 200000; i++) printf "</a>"; print "</robot>" }' > "$tmp/nested_200000.urdf"
{ printf '<robot name="big"><!-- '; head -c $((17 * 1024 * 1024)) /dev/zero | tr '\0' 'x'; printf ' --></robot>\n'; } > "$tmp/big_17MiB.urdf"
{ head -c $((10 * 1024 * 1024)) /dev/zero | tr '\0' '7'; printf ',0\n'; } > "$tmp/terrain_10MB_line.csv"
awk 'BEGIN { for (i = 0; i < 1000000; i++) printf "%d,0,0.1\n", i }' > "$tmp/terrain_1M_stones.csv"
# A sidecar nested 100000 deep under a key whose error would print its value (the depth is capped while parsing).
awk 'BEGIN { printf "{\"robot\": "; for (i = 0; i < 100000; i++) printf "["; for (i = 0; i < 100000; i++) printf "]"; print "}" }' > "$tmp/deep_100000.rome.json"
# A sidecar with 200000 contacts (a strict JSON check that was quadratic in an array's length took 158 s).
cp "$inputs/pendulum.urdf" "$tmp/pendulum.urdf"
awk 'BEGIN { printf "{\"robot\": \"pendulum\", \"urdf\": \"pendulum.urdf\", \"floating_base\": \"fixed\", \"contacts\": ["
  for (i = 0; i < 200000; i++) printf "%s{\"name\": \"c%d\", \"link\": \"arm\", \"type\": \"point\", \"points\": [[0, 0, -1]]}", (i ? ", " : ""), i
  print "]}" }' > "$tmp/contacts_200000.rome.json"
printf '{"energy": 0.5}\n' > "$tmp/scenario.json"  # an input that an output must not overwrite
mkdir -p "$tmp/a_folder"
printf 'not a folder\n' > "$tmp/a_file"
# Robot packages that reach out: a FIFO as the URDF, a link to a URDF outside the package; a FIFO as a terrain.
mkdir -p "$tmp/fifo_package" "$tmp/link_package"
mkfifo "$tmp/fifo_package/fifo.urdf" "$tmp/terrain_fifo.csv"
printf '{"robot": "pendulum", "urdf": "fifo.urdf"}\n' > "$tmp/fifo_package/fifo.rome.json"
ln -s "$inputs/pendulum.urdf" "$tmp/link_package/link.urdf"
printf '{"robot": "pendulum", "urdf": "link.urdf"}\n' > "$tmp/link_package/link.rome.json"
# A robot planted in the programs' working folder: a relative robot path must not read it (only ./robots/... does).
mkdir -p "$tmp/run/robots/amber"
printf 'planted\n' > "$tmp/run/robots/amber/amber.rome.json"

entries=0; mismatches=0
report() {  # report LINE_NO PROGRAM ARGS PROBLEM
  mismatches=$((mismatches + 1))
  printf 'MISMATCH (catalogue line %d) %s %s\n    %s\n' "$1" "$2" "$3" "$4"
}
line_no=0
while IFS=$'\t' read -r program expected words args || [ -n "$program" ]; do
  line_no=$((line_no + 1))
  [ -z "$program" ] && continue
  case "$program" in \#*) continue ;; esac
  entries=$((entries + 1))
  argv=()
  for token in $args; do
    token="${token//@IN@/$inputs}"; token="${token//@TMP@/$tmp}"
    [ "$token" = @EMPTY@ ] && token=""
    argv+=("$(printf '%b' "$token")")
  done
  # Open MPI never frees what MPI_Init allocates: under the sanitizers rome_sweep runs without leak checking (the
  # sanitizer suite leaves out the mpi-labelled tests for the same reason).
  asan="${ASAN_OPTIONS:-}"
  [ "$program" = rome_sweep ] && asan="${asan:+$asan:}detect_leaks=0"
  (cd "$tmp/run" && ASAN_OPTIONS="$asan" exec timeout -k 5 "$limit" "$bin/$program" "${argv[@]}" > "$tmp/stdout" 2> "$tmp/stderr")
  rc=$?
  shown="$program ${args:0:200}"
  if [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; then report "$line_no" "$program" "$args" "HANG: no exit within $limit s"; continue; fi
  if [ "$rc" -gt 128 ]; then report "$line_no" "$program" "$args" "CRASH: killed by signal $((rc - 128)); stderr: $(head -c 300 "$tmp/stderr")"; continue; fi
  if [ "$rc" -ne "$expected" ]; then
    report "$line_no" "$program" "$args" "exit $rc, expected $expected; stderr: $(head -c 300 "$tmp/stderr" | tr '\n' ' ')"
    continue
  fi
  if [ "$expected" -eq 1 ]; then
    text="$(cat "$tmp/stderr")"
    lines=$(grep -c '' "$tmp/stderr")
    [ "$lines" -eq 1 ] || { report "$line_no" "$program" "$args" "error has $lines lines, expected 1: $(head -c 300 "$tmp/stderr" | tr '\n' '~')"; continue; }
    bytes=$(wc -c < "$tmp/stderr")
    [ "$bytes" -le 2001 ] || { report "$line_no" "$program" "$args" "error is $bytes bytes (not truncated)"; continue; }
    if LC_ALL=C tr -d '\n' < "$tmp/stderr" | LC_ALL=C grep -q '[[:cntrl:]]'; then
      report "$line_no" "$program" "$args" "error prints control bytes raw"; continue
    fi
  else
    text="$(cat "$tmp/stdout" "$tmp/stderr")"
  fi
  if [ "$words" != - ]; then
    IFS='|' read -r -a required <<< "$words"
    for w in "${required[@]}"; do
      case "$text" in
        *"$w"*) ;;
        *) report "$line_no" "$program" "$args" "missing '$w' in: $(printf '%s' "$text" | head -c 400 | tr '\n' '~')" ;;
      esac
    done
  fi
done < "$catalogue"

echo "bad-input catalogue: $entries entries, $mismatches mismatches"
[ "$entries" -ge 60 ] || { echo "the catalogue must hold at least 60 entries"; exit 1; }
[ "$mismatches" -eq 0 ]
