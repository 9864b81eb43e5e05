# -I through a link in the model's folder that points out of it (inc -> ../common): whoever wrote
# the folder chose where it points (it could be ~/.ssh), so a sandboxed run does not follow it and
# says so, naming the link and the folder to name instead; named as it is, the folder is shown
# read-only and the header found. (Before, the run failed with "'shared.h' file not found".)
source "$(dirname "$0")/lib.sh"
need_sandbox
mkdir model common
cp "$here/m.l" model/
echo '#define SHARED_VALUE 42' > common/shared.h
ln -s ../common model/inc
"$lcjit" -b -I model/inc -out o.str model/m.l 2> err.txt || fail "the plain run failed"
grep -q "A(42)" o.str || fail "the plain run's string: $(cat o.str)"
rm o.str
"$lcjit" --sandbox -b -I model/inc -out o.str model/m.l > out.txt 2> err.txt; status=$?
[ $status = 1 ] || fail "-I a link out of the folder: exit status $status"
common=$(cd common && pwd -P)
grep -qF "model/inc: error: a link to '$common', outside the model's folder; a sandboxed run does not follow it (name the folder itself: -I $common)" err.txt ||
  fail "the link was not named"
"$lcjit" --sandbox -b -I "$common" -out o.str model/m.l > out.txt 2> err.txt || fail "-I the folder itself failed"
grep -q "A(42)" o.str || fail "the sandboxed run's string: $(cat o.str)"
# A relative -I, from another working folder than the model's: the child works in the model's.
rm o.str
(cd model && "$lcjit" --sandbox -b -I ../common -out ../o.str m.l > ../out.txt 2> ../err.txt) || fail "-I ../common failed"
grep -q "A(42)" o.str || fail "the relative -I's string: $(cat o.str)"
pass "the link named, the folder itself found"
