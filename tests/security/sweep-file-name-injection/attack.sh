# Names a Slurm script carries: `lcjit sweep slurm` writes the sweep file's name and the plan's
# folder into sweep.sbatch (a comment, #SBATCH --job-name and --output, dir=). A name with a line
# break would end the comment and put a command on a line of its own, which bash runs on the
# cluster: such a name (of the file or of --out) must be refused before anything is written. A name
# with spaces, quotes, $( ), # and % is a name: the script must carry it as it is, to sbatch (its
# #SBATCH lines read as Slurm reads them, sbatch_directives.py) and to bash (run here with a
# stand-in GNU parallel that records what it was given), and run nothing it holds.
source "$(dirname "$0")/lib.sh"
cp "$here/tree.l" .
printf 'model: tree.l\nseeds: 2\n' > template.yaml

# nothing_written: only the inputs are here (no plan folder, no script).
nothing_written() {
  [ "$(ls -A | grep -v -x -e tree.l -e template.yaml -e out.txt -e err.txt -e "$1" | wc -l)" = 0 ] ||
    fail "$2: something was written: $(ls -A)"
}

# A line break in the sweep file's name (a listing shows it as two harmless-looking names).
name=$'study\ntouch INJECTED\n.yaml'
cp template.yaml "$name"
"$lcjit" sweep slurm "$name" > out.txt 2> err.txt && fail "a sweep file with a line break in its name was accepted"
grep -qF "$PWD/study\\ntouch INJECTED\\n.yaml: error: " err.txt || fail "the error does not name the file"
nothing_written "$name" "a line break in the file's name"
rm "$name"

# A line break in --out.
cp template.yaml study.yaml
"$lcjit" sweep slurm study.yaml --out $'runs\ntouch INJECTED' > out.txt 2> err.txt &&
  fail "a plan folder with a line break in its name was accepted"
grep -qF "$PWD/runs\\ntouch INJECTED: error: " err.txt || fail "the error does not name the folder"
nothing_written study.yaml "a line break in --out"

# A backslash in --out: Slurm's --output would drop it and stop reading %A_%a there.
"$lcjit" sweep slurm study.yaml --out 'runs\x' > out.txt 2> err.txt && fail "a plan folder with a backslash was accepted"
grep -qF "$PWD/runs\\x: error: " err.txt || fail "the error does not name the folder"
nothing_written study.yaml "a backslash in --out"
rm study.yaml

# Names that are names: every character a shell or sbatch would read as its own.
name='s $(touch INJECTED) "q" '\''x'\'' #h %j `touch INJECTED` \.yaml'
dir='runs $(touch INJECTED) "q" '\''x'\'' #h %j;touch INJECTED'
cp template.yaml "$name"
"$lcjit" sweep slurm "$name" --out "$dir" > out.txt 2> err.txt || fail "sweep slurm failed on an ordinary name"
script=$dir/sweep.sbatch
[ -f "$script" ] || fail "no script was written"
bash -n "$script" || fail "the script is not valid bash"
# What sbatch reads: the job's name and Slurm's output file as given, the array's size (2 runs in
# one array task) and the rest whole. In --output, Slurm turns %% into % and %X into a value: the
# folder's % must be %%, leaving %A and %a alone.
python3 "$here/sbatch_directives.py" "$script" > directives.txt || fail "sbatch would not read the script"
python3 - "$PWD" "$name" "$dir" <<'PY' || fail "sbatch would read other directives: $(cat directives.txt)"
import re, sys
cwd, name, out = sys.argv[1:]
args = open("directives.txt").read().splitlines()
def expanded(pattern):  # Slurm's filename pattern: %% is %, %X a value (here <X>)
    return re.sub(r"%(.)", lambda m: "%" if m.group(1) == "%" else "<" + m.group(1) + ">", pattern)
output = [a for a in args if a.startswith("--output=")]
assert len(output) == 1 and expanded(output[0][len("--output="):]) == cwd + "/" + out + "/slurm/<A>_<a>.out", output
rest = [a for a in args if not a.startswith("--output=")]
assert rest == ["--job-name=lcjit-" + name[:-len(".yaml")], "--array=0-0", "--ntasks=1", "--cpus-per-task=1"], rest
PY
# What bash runs: a stand-in GNU parallel records its arguments and the ids it was given.
mkdir bin
cat > bin/parallel <<'SH'
#!/bin/bash
printf '%s\0' "$@" > "$STANDIN/parallel.args"
cat > "$STANDIN/parallel.ids"
SH
chmod +x bin/parallel
STANDIN=$PWD PATH=$PWD/bin:$PATH SLURM_ARRAY_TASK_ID=0 bash "$script" > out.txt 2> err.txt || fail "the script failed"
[ -z "$(find . -name 'INJECTED*')" ] || fail "the script ran a command from a name: $(find . -name 'INJECTED*')"
[ "$(cat parallel.ids)" = $'000001\n000002' ] || fail "parallel was given the ids $(cat parallel.ids)"
python3 - "$PWD/$dir" "$(readlink -f "$lcjit")" <<'PY' || fail "parallel was given other arguments: $(tr '\0' ' ' < parallel.args)"
import sys
dir, lcjit = sys.argv[1:]
args = open("parallel.args").read().split("\0")[:-1]
assert args[-5:] == [lcjit, "sweep", "task", dir, "{}"], args
assert args[args.index("--joblog") + 1] == dir + "/joblog.0", args
PY
pass "names with line breaks refused before anything was written; a name of shell and Slurm characters carried as it is"
