# A picture or window size below 1 x 1: `-w 0 0` used to write a picture of 1 x 1, `-w -5 200`
# one of 1 x 200, and succeed. Each is an error before the run (exit 1, naming the option, no
# picture), as are the REPL's -w and --wr (a fraction of the screen); a view file's `window:` of
# no size is a warning naming its line.
source "$(dirname "$0")/lib.sh"
cp "$here"/koch.{l,v,map} .
export LCJIT_CACHE_DIR=$PWD/cache
# refused WHAT EXPECTED ARGS…: lcjit ARGS exits 1 with one line of error containing EXPECTED, and
# writes no o.png.
refused() {
  local what=$1 expected=$2
  shift 2
  rm -f o.png
  timeout 300 "$lcjit" "$@" < /dev/null > out.txt 2> err.txt; local status=$?
  [ $status = 1 ] || fail "$what: exit status $status, not 1"
  [ ! -e o.png ] || fail "$what: a picture was written"
  [ "$(wc -l < err.txt)" = 1 ] && grep -qF -- "$expected" err.txt || fail "$what: not the one line '$expected'"
}
for size in "0 0" "-5 200" "200 0.5"; do
  refused "-w $size" "-w $size: the size must be at least 1 x 1" -b -out o.png -w $size koch.v koch.map koch.l
done
refused "repl -w 0 0" "repl -w 0 0: the size must be at least 1 x 1" repl -w 0 0 koch.l
refused "--wr 0 0" "--wr 0 0: the size is a fraction of the screen's, above 0" -b -out o.png --wr 0 0 koch.v koch.map koch.l
# The view file: its third line gives a window no width; the width is column 18.
printf 'projection: parallel\nline style: pixel\nwindow: main 0 0 0 1\n' > zero.v
timeout 300 "$lcjit" -b -out o.str zero.v koch.map koch.l > out.txt 2> err.txt || fail "the view file's window made the run fail"
grep -q "zero\.v:3:18: .*window: the width and height must be above 0" err.txt || fail "no warning naming zero.v:3:18"
pass "-w 0 0, -w -5 200, -w 200 0.5, repl -w 0 0 and --wr 0 0 refused before the run; a window: of no width warned of"
