# A numbered -out (frame%02d.png: the axiom and every step) outside the model's folder: every frame
# must reach that folder — or the run fail — never a success with the frames lost.
source "$(dirname "$0")/lib.sh"
need_sandbox
mkdir model frames
cp "$here/grow.l" model/
# Without the sandbox: the frames the model makes (the expected names come from this run).
mkdir plain
"$lcjit" -b -w 64 64 -out "$PWD/plain/f%02d.str" model/grow.l > out.txt 2> err.txt || fail "the plain run failed"
expected=$(cd plain && ls | tr '\n' ' ')
[ "$expected" = "f00.str f01.str f02.str f03.str " ] || fail "the plain run wrote: $expected"
"$lcjit" --sandbox -b -w 64 64 -out "$PWD/frames/f%02d.str" model/grow.l > out.txt 2> err.txt; status=$?
[ $status = 0 ] || fail "exit status $status"
[ "$(cd frames && ls -A | tr '\n' ' ')" = "$expected" ] || fail "frames/ holds: $(cd frames && ls -A | tr '\n' ' ')"
for f in f00.str f03.str; do cmp -s "plain/$f" "frames/$f" || fail "$f differs from the plain run's"; done
pass "the four frames reached the folder, as without the sandbox"
