# Sourced by the run_*.sh test scripts: arguments LCJIT DIR NAME, a scratch folder removed on
# exit, and `extra`, the input files NAME.files lists (prefixed by $extra_prefix, default DIR/).
set -u
lcjit=$1 dir=$2 name=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
extra=()
if [ -f "$dir/$name.files" ]; then
  for f in $(cat "$dir/$name.files"); do extra+=("${extra_prefix-$dir/}$f"); done
fi
