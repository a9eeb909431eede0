#!/bin/sh
# Usage: check_model_info_output.sh MODEL_INFO "MUST1|MUST2|..." "MUST_NOT" ARGS...
# Passes when model_info exits 0 and its stdout contains every MUST fragment (separated by |)
# and not MUST_NOT (empty: no check).
bin="$1"; must="$2"; must_not="$3"; shift 3
out=$("$bin" "$@")
rc=$?
echo "$out"
[ "$rc" -eq 0 ] || { echo "FAIL: exit code $rc"; exit 1; }
IFS='|'
for m in $must; do
  case "$out" in *"$m"*) ;; *) echo "FAIL: missing '$m'"; exit 1;; esac
done
if [ -n "$must_not" ]; then
  case "$out" in *"$must_not"*) echo "FAIL: unexpected '$must_not'"; exit 1;; esac
fi
echo PASS
