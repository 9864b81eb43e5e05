#!/usr/bin/env bash
# A model folder's lpfg.mak (app/session/LpfgMak.h): lcjit builds the helper unit it names, with its
# -DFACTOR=3, and leaves the folder as it was (its lsys.ii too). The expected string is the one
# the reference lpfg (vlab 9bf820dc) derives in this folder: sqrt(16)*3 = 12, and FACTOR unseen
# by the model's #ifdef (lpfg preprocesses the model without lpfg.mak's flags).
# Usage: run_lpfg_mak.sh LCJIT DIR
set -u
lcjit=$1 dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp -r "$dir" "$work/model"
echo "lpfg's translated model" > "$work/model/lsys.ii"
before=$(cd "$work/model" && find . -type f | sort && cat lsys.ii)
(cd "$work/model" && "$lcjit" -b -out "$work/out.str" lpfg_mak.l) || { echo "FAIL: lcjit failed"; exit 1; }
diff -u "$dir/lpfg_mak.expected" "$work/out.str" || { echo "FAIL: the string differs"; exit 1; }
after=$(cd "$work/model" && find . -type f | sort && cat lsys.ii)
[ "$before" = "$after" ] || { echo "FAIL: the model folder changed"; diff <(echo "$before") <(echo "$after"); exit 1; }
echo "ok: lpfg.mak"
