# A sandboxed run that lcjit stops (a newer save under --watch) or that lcjit's own end takes
# with it must leave no process behind — also when it is stopped while bubblewrap is still
# setting the sandbox up (an orphan there sleeps for ever, holding lcjit's output open). A
# stand-in bubblewrap (./bwrap) is stopped at the two moments that matter; then real bubblewrap
# is stopped by a storm of saves.
source "$(dirname "$0")/lib.sh"
need_sandbox
mkdir m fakebin marks
cp "$here/bwrap" fakebin/
printf 'derivation length: 1;\naxiom: A;\n' > m/m.l
tag=3600.$$$RANDOM  # the stand-in's processes: `sleep $tag`
left() { pgrep -f "^sleep $tag\$" | tr '\n' ' '; }
for mode in setup let-go; do
  rm -f marks/*
  printf 'FAKE_MODE=%s\nFAKE_TAG=%s\nFAKE_MARKS=%s\n' $mode $tag "$PWD/marks" > fakebin/config
  PATH=$PWD/fakebin:$PATH "$lcjit" --sandbox --watch -out o.str m/m.l > out.txt 2> err.txt &
  run=$!
  keep $run
  wait_for 120 sh -c 'ls marks | grep -q started' || fail "$mode: the first run never started"
  echo '// saved' >> m/m.l  # a newer save: the run in progress is stopped, the next one starts
  wait_for 120 sh -c '[ "$(ls marks | grep -c started)" -ge 2 ]' || fail "$mode: no run after the save"
  kill -TERM $run  # lcjit's end, with a run in progress
  wait $run
  wait_for 60 sh -c "! pgrep -f '^sleep $tag\$' >/dev/null" || fail "$mode: left behind: $(left)"
done

# Real bubblewrap, saved over 300 times as fast as the file system takes it.
printf 'derivation length: 1;\nmodule A;\nStart: { }\naxiom: A;\n' > m/m.l
"$lcjit" --sandbox --watch -out o.str m/m.l > out.txt 2> err.txt &
run=$!
keep $run
wait_for 120 test -e o.str || fail "the first real run wrote nothing"
for i in $(seq 1 300); do
  printf 'derivation length: 1;\nmodule A;\nStart: { }\naxiom: A; // %d\n' $i > m/m.new && mv m/m.new m/m.l
done
kill -TERM $run
wait $run
# bubblewrap and the sandboxed lcjit name the model's folder on their command lines (the parent
# lcjit was given m/m.l, relative).
# ("[m].l": the pattern must not match the command line of the shell that runs pgrep.)
model=$(cd m && pwd -P)
wait_for 60 sh -c "! pgrep -f -- '$model/[m].l' >/dev/null" ||
  fail "processes of the sandbox left: $(pgrep -af -- "$model/[m].l" | cut -c1-200)"
pass "nothing left: stopped in setup, once let go, by lcjit's end, and after 300 saves"
