# -out names where the sandboxed run's output goes; the model must be able to write that file and
# nothing else of the output's folder: not with -out naming a folder (an existing one, a link to
# one, the home folder), not beside the output, not a link or a dotfile there.
source "$(dirname "$0")/lib.sh"
need_sandbox
mkdir model results home
cp "$here/plant.l" model/
ln -s results results-link
files_in() { (cd "$1" && find . -mindepth 1 | sort | tr '\n' ' '); }
before=$(files_in results)

# -out naming a folder, directly, through a link, and the home folder: refused before any run.
for out in results results-link home; do
  HOME=$PWD/home "$lcjit" --sandbox -b -out "$PWD/$out" model/plant.l > out.txt 2> err.txt; status=$?
  [ $status = 1 ] || fail "-out $out: exit status $status"
  grep -q -- "-out $PWD/$out: is a folder; name a file" err.txt || fail "-out $out: not refused as a folder"
  ! grep -q "written" out.txt || fail "-out $out: the model ran and wrote: $(grep written out.txt)"
done
[ "$(files_in results)" = "$before" ] || fail "the folder changed: $(files_in results)"
[ -z "$(files_in home)" ] || fail "the home folder changed: $(files_in home)"

# A file in that folder: written, and nothing else appears beside it.
"$lcjit" --sandbox -b -out "$PWD/results/o.str" model/plant.l > out.txt 2> err.txt || fail "the run failed"
grep -q "A" results/o.str || fail "no string in results/o.str"
grep -q "planted.txt: written" out.txt || fail "the model could not even write in its view of the folder (the test means nothing)"
[ "$(files_in results)" = "./o.str " ] || fail "beside the output: $(files_in results)"

# The output kinds that write two files (an .obj and its .mtl): both, and still nothing else.
"$lcjit" --sandbox -b -out "$PWD/results/o.obj" model/plant.l > out.txt 2> err.txt || fail "the .obj run failed"
[ "$(files_in results)" = "./o.mtl ./o.obj ./o.str " ] ||
  fail "after the .obj: $(files_in results)"
pass "-out a folder refused three ways; only the output's own files reached the folder"
