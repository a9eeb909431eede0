#!/bin/sh
# Usage: check_model_info_error.sh MODEL_INFO EXPECTED_SUBSTRING ARGS...
# Passes when model_info exits non-zero, prints exactly one line on stderr, nothing on stdout,
# and that line contains EXPECTED_SUBSTRING.
bin="$1"; expected="$2"; shift 2
err=$("$bin" "$@" 2>&1 >/dev/null)
rc=$?
out=$("$bin" "$@" 2>/dev/null)
echo "exit code: $rc"
echo "stderr: $err"
[ "$rc" -ne 0 ] || { echo "FAIL: exit code 0"; exit 1; }
[ -z "$out" ] || { echo "FAIL: unexpected stdout"; exit 1; }
[ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || { echo "FAIL: error is not one line"; exit 1; }
case "$err" in *"$expected"*) ;; *) echo "FAIL: missing '$expected'"; exit 1;; esac
echo PASS
