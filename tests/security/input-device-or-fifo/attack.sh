# Inputs that are not regular files: each kind of file lcjit reads (the model, a header it
# includes, the view file and the files its lines name, colours, contours, functions, the
# environment file, a string loaded with LoadString, lpfg.mak, a C++ source, a sweep file) is made
# a link to /dev/zero or /dev/urandom (read without end: all of the machine's memory), a FIFO (its
# open() waits for ever for a writer) or a socket, as a model folder from tar or cp -a can carry
# them. Each run must end with the file named and why it was not read: an error where a missing
# file is one (exit 1), a warning where lcjit goes on without it (exit 0). lcjit runs under a
# 3 GB address-space limit, so that a reader that does not refuse cannot take the machine, and a
# bound of 120 s that only a hang (or a broken machine) reaches.
source "$(dirname "$0")/lib.sh"
export LCJIT_CACHE_DIR=$PWD/cache
top=$PWD
tried=0

# make_input KIND PATH: PATH made what KIND says.
make_input() {
  case $1 in
    zero) ln -s /dev/zero "$2" ;;
    urandom) ln -s /dev/urandom "$2" ;;
    fifo) mkfifo "$2" ;;
    socket) python3 -c 'import socket, sys; socket.socket(socket.AF_UNIX).bind(sys.argv[1])' "$2" ;;
  esac
}
# reason KIND: what lcjit must say of it.
reason() {
  case $1 in
    zero | urandom) echo "not a regular file (a character device)" ;;
    fifo) echo "not a regular file (a FIFO)" ;;
    socket) echo "not a regular file (a socket)" ;;
  esac
}

# attempt WHAT KIND STATUS SAYS LCJIT-ARGUMENTS…: runs lcjit in the current folder; it must end by
# itself with exit STATUS and a line holding SAYS (the file and how the reader reports it) and
# `reason KIND`.
attempt() {
  local what=$1 kind=$2 expected=$3 says=$4 why
  shift 4
  why=$(reason "$kind")
  prlimit --as=3000000000 timeout -s KILL 120 "$lcjit" "$@" < /dev/null > out.txt 2> err.txt
  local status=$?
  [ $status = 137 ] && fail "$what ($kind): lcjit did not end within 120 s, or took its 3 GB and was killed"
  [ $status -gt 128 ] && fail "$what ($kind): lcjit ended by signal $((status - 128))"
  [ $status = "$expected" ] || fail "$what ($kind): exit status $status, expected $expected"
  grep -hF -- "$why" err.txt out.txt | grep -qF -- "$says" || fail "$what ($kind): no line '$says…$why'"
  tried=$((tried + 1))
}

# in_folder NAME MODEL: a fresh folder for one attempt, holding MODEL (from the attack's folder).
in_folder() {
  { cd "$top" && mkdir "$1" && cd "$1" && cp "$here/$2" .; } || fail "cannot make the folder $1"
}

kinds="zero fifo"
command -v python3 > /dev/null && kinds="$kinds socket"

for k in $kinds; do
  # The model itself: an error, as a missing one.
  in_folder "model-$k" plant.l && rm plant.l && make_input $k plant.l
  attempt "the model" $k 1 "plant.l: error: cannot open file" -b -out o.obj -w 50 50 plant.l
  # A header it includes: an error at the #include.
  in_folder "include-$k" includes.l && make_input $k header.h
  attempt "an included header" $k 1 "includes.l:3:10: error: cannot open file './header.h'" -b -out o.obj -w 50 50 includes.l
  # The view file: lcjit goes on with the default view.
  in_folder "view-$k" plant.l && make_input $k plant.v
  attempt "the view file" $k 0 "plant.v: warning: cannot open file" -b -out o.obj -w 50 50 plant.l plant.v
done
in_folder include-urandom urandom.l
attempt "an include of /dev/urandom" urandom 1 "urandom.l:3:10: error: cannot open file '/dev/urandom'" -b -out o.obj -w 50 50 urandom.l

# The files a view file's lines name: each left out with a warning, as a missing one.
while read -r kind file line; do
  in_folder "view-line-$kind-$file" plant.l && echo "$line" > plant.v && make_input "$kind" "$file"
  attempt "'$line' in the view file" "$kind" 0 "$file: warning: cannot open file" -b -out o.obj -w 50 50 plant.l plant.v
done << 'EOF'
zero leaf.s surface: leaf.s 1 4 4
fifo leaf.s surface: leaf.s 1 4 4
urandom leaf.s surface: leaf.s 1 4 4
zero bleaf.s bsurface: bleaf.s 1 4 4
fifo bleaf.s bsurface: bleaf.s 1 4 4
zero pot.obj mesh: pot.obj
fifo pot.obj mesh: pot.obj
zero bark.png texture: bark.png
fifo bark.png texture: bark.png
zero ground.patch terrain: ground.patch 4 1 0.3 on 0 2 2
fifo ground.patch terrain: ground.patch 4 1 0.3 on 0 2 2
EOF

# Colours and contours: left out with a message, as a missing file is.
while read -r kind file says; do
  in_folder "input-$kind-$file" plant.l && make_input "$kind" "$file"
  attempt "$file" "$kind" 0 "$file: $says" -b -out o.obj -w 50 50 plant.l "$file"
done << 'EOF'
zero plant.mat cannot read
fifo plant.map cannot read
zero plant.con warning: cannot open file
fifo plant.cset warning: cannot open file
EOF

# Functions, the environment file and a C++ source: errors, as a missing file is.
while read -r kind file; do
  in_folder "input-$kind-$file" plant.l && make_input "$kind" "$file"
  attempt "$file" "$kind" 1 "$file: error: cannot open file" -b -out o.obj -w 50 50 plant.l "$file"
done << 'EOF'
zero plant.func
fifo plant.fset
zero plant.tset
fifo plant.vset
zero plant.e
fifo unit.cpp
EOF

# LoadString: the model's own message (it prints lcjit's error and goes on), as for a missing file.
for k in zero fifo; do
  in_folder "load-string-$k" loads.l && make_input $k saved.strb
  attempt "LoadString's file" $k 0 "saved.strb: error: cannot open file" -b -out o.obj -w 50 50 loads.l
done

# lpfg.mak (make would wait on it for ever): an error.
in_folder lpfg-mak plant.l && make_input fifo lpfg.mak
attempt "lpfg.mak" fifo 1 "lpfg.mak: error: cannot read it" -b -out o.obj -w 50 50 plant.l

# A sweep file: an error.
in_folder sweep-file plant.l && make_input fifo sweep.yaml
attempt "the sweep file" fifo 1 "sweep.yaml: error: cannot read it" sweep plan sweep.yaml --out planned

# Under --sandbox the same readers run in the sandboxed child: a FIFO in the model's folder named by
# the view file. One given on the command line is refused before the run: the parent shows the
# sandbox only regular files (a FIFO or a socket bound into it would be a way to talk out).
if command -v bwrap > /dev/null && bwrap --unshare-all --ro-bind / / true 2> /dev/null; then
  in_folder sandbox-view-line plant.l && echo "surface: leaf.s 1 4 4" > plant.v && make_input fifo leaf.s
  attempt "--sandbox: a surface file" fifo 0 "leaf.s: warning: cannot open file" --sandbox -b -out o.obj -w 50 50 plant.l plant.v
  in_folder sandbox-contours plant.l && make_input fifo plant.con
  attempt "--sandbox: a contour file" fifo 1 "plant.con: error:" --sandbox -b -out o.obj -w 50 50 plant.l plant.con
else
  echo "note: bubblewrap cannot make a sandbox here; the --sandbox runs were not tried"
fi

pass "$tried inputs that are not regular files were each refused, naming the file and why"
