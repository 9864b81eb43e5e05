#!/usr/bin/env bash
# VerifyString (manual §10.4): lcjit -b checks the final string's module names as lpfg does.
# Usage: run_verify.sh LCJIT DIR
set -u
lcjit=$1 dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$dir"/pass.l "$dir"/fail.l "$work"/
cd "$work" || exit 1
out=$("$lcjit" -b pass.l) || { echo "FAIL: a passing VerifyString made lcjit fail"; exit 1; }
[ "$out" = "Verify: Success" ] || { echo "FAIL: expected 'Verify: Success', got: $out"; exit 1; }
[ ! -e Verify_pass.l_expected.txt ] || { echo "FAIL: a success wrote the lists"; exit 1; }
out=$("$lcjit" -b fail.l); status=$?
[ $status -eq 1 ] || { echo "FAIL: a failed VerifyString exited with $status, not 1"; exit 1; }
[ "$out" = "Verify: Fail" ] || { echo "FAIL: expected 'Verify: Fail', got: $out"; exit 1; }
diff <(printf 'A\nB\n') Verify_fail.l_expected.txt || { echo "FAIL: Verify_fail.l_expected.txt"; exit 1; }
diff <(printf 'A\nB\nB\n') Verify_fail.l_actual.txt || { echo "FAIL: Verify_fail.l_actual.txt"; exit 1; }
echo "ok: VerifyString"
