#!/usr/bin/env bash
# Binary strings (.strb, lpfg's layout): OutputString in End:, -out FILE.strb, LoadString in
# StartEach: in a second run, and LoadString of bad files. Models are in tests/strb/.
# Usage: run_strb.sh LCJIT STRB_DIR
set -u
lcjit=$1 dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
fail=0
check() { if ! eval "$2"; then echo "FAIL: $1"; fail=1; else echo "ok: $1"; fi; }
bytes() { od -An -tx1 -j "$2" -N "$3" "$1" | tr -d ' \n'; }

# Run 1: End: calls OutputString("written.strb"); -out final.strb writes the same string.
if ! "$lcjit" -b -out final.strb "$dir/write.l"; then echo "FAIL: write.l did not run"; exit 1; fi
check "OutputString wrote written.strb" '[ -f written.strb ]'
check "-out wrote final.strb" '[ -f final.strb ]'
# A(float) 12 + 3 x B 4 + C(double) 24 + D(int,char) 12.
check "size of final.strb is 60 bytes (got $(stat -c %s final.strb 2>/dev/null))" '[ "$(stat -c %s final.strb)" = 60 ]'
check "size of written.strb is 60 bytes" '[ "$(stat -c %s written.strb)" = 60 ]'
check "OutputString in End: and -out give the same bytes" 'cmp -s final.strb written.strb'
# Record starts hold the module ids (little-endian u16): A=103, B=104, C=105, D=106.
check "A id at byte 0" '[ "$(bytes final.strb 0 2)" = 6700 ]'
check "A(4): float 4.0 at byte 4" '[ "$(bytes final.strb 4 4)" = 00008040 ]'
check "A id again at the record end (byte 8)" '[ "$(bytes final.strb 8 2)" = 6700 ]'
check "B records at bytes 12, 16, 20" '[ "$(bytes final.strb 12 2)$(bytes final.strb 16 2)$(bytes final.strb 20 2)" = 680068006800 ]'
check "C id at byte 24" '[ "$(bytes final.strb 24 2)" = 6900 ]'
check "C(0.1): double at byte 32" '[ "$(bytes final.strb 32 8)" = 9a9999999999b93f ]'
check "D id at byte 48, int 7 at 52, char x at 56" '[ "$(bytes final.strb 48 2)$(bytes final.strb 52 4)$(bytes final.strb 56 1)" = 6a000700000078 ]'
# The text form of the same run, for reference.
"$lcjit" -b -out final.str "$dir/write.l" >/dev/null
check "text output of write.l" '[ "$(cat final.str)" = "$(printf "A(4)\nB\nB\nB\nC(0.10000000000000001)\nD(7,120)")" ]'

# Run 2: StartEach: of step 2 loads written.strb; step 2 rewrites the loaded string.
if ! "$lcjit" -b -out reload.str "$dir/reload.l"; then echo "FAIL: reload.l did not run"; exit 1; fi
check "reloaded and rewritten string" 'diff -u "$dir/reload.expected" reload.str'
# Binary output of the reloaded model: A(4.5) B B B C D(8,121): again 60 bytes.
"$lcjit" -b -out reload.strb "$dir/reload.l" >/dev/null
check "size of reload.strb is 60 bytes" '[ "$(stat -c %s reload.strb)" = 60 ]'
check "A(4.5) in reload.strb" '[ "$(bytes reload.strb 4 4)" = 00009040 ]'

# Bad files: missing, truncated (10 of A's 12 bytes), an id no module has.
head -c 10 written.strb >truncated.strb
printf '\160\000\160\000' >foreign.strb
"$lcjit" -b -out errors.str "$dir/load_errors.l" >errors.log 2>&1
rc=$?
cat errors.log
check "lcjit exits 0 after LoadString errors" '[ $rc = 0 ]'
check "missing file reported" 'grep -qF "nothere.strb: error: cannot open file" errors.log'
check "truncated file reported" "grep -qF \"truncated.strb: error: corrupt module 'A' at byte 0\" errors.log"
check "foreign file reported" 'grep -qF "foreign.strb: error: unknown module id 112 at byte 0" errors.log'
check "the string is unchanged" 'diff -u "$dir/load_errors.expected" errors.str'

# A string with a Label (a pointer to text in the writing run's memory) is not loaded by another.
"$lcjit" -b -out label.strb "$dir/label_write.l" >/dev/null 2>&1
"$lcjit" -b -out label.str "$dir/label_load.l" >label.log 2>&1
cat label.log
check "label.strb written (A 12 bytes, Label 24)" '[ "$(stat -c %s label.strb)" = 36 ]'
check "a pointer parameter is refused" "grep -qF \"label.strb: error: module 'Label' at byte 12 has a pointer parameter (const char*)\" label.log"
check "the string is unchanged after the refused load" '[ "$(cat label.str)" = "A(2)" ]'
exit $fail
