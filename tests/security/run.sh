#!/usr/bin/env bash
# ctest's entry to the security suite (README.md): runs NAME/attack.sh in a fresh working folder,
# as the suite's user (AS=self) or as an unprivileged one (AS=unprivileged: a uid of its own). Exit: the attack's.
# Usage: run.sh LCJIT NAME AS
set -u
lcjit=$(realpath "$1") name=$2 as=$3
suite=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/lcjit-security.XXXXXX")
trap 'rm -rf "$work"' EXIT
# The attack and lib.sh are copied in: the attacker's user may not read the checkout.
mkdir "$work/attack" "$work/run"
cp -r "$suite/$name/." "$work/attack/"
cp "$suite/lib.sh" "$work/attack/lib.sh"
if [ "$as" = unprivileged ] && [ "$(id -u)" = 0 ]; then
  # A user of its own for each attack (one with no other processes, no name needed): limits the
  # kernel counts per user (RLIMIT_NPROC) are then the attack's alone, whatever runs beside it.
  uid=$((60000 + $(printf %s "$name" | cksum | cut -d' ' -f1) % 5000))
  user() { setpriv --reuid=$uid --regid=$uid --clear-groups "$@"; }
  chmod 755 "$work"
  # lcjit reads its runtime headers and precompiled headers beside itself or in the build: where
  # that user cannot read them, an install into the working folder is what it runs.
  build=$(dirname "$lcjit")
  if ! user test -x "$lcjit" || ! user test -r "$suite/../../runtime/include/lpfgall.h" || ! user test -r "$build/prebuilt"; then
    cmake --install "$build" --prefix "$work/install" >/dev/null || { echo "FAIL: cannot install lcjit for uid $uid"; exit 1; }
    chmod -R a+rX "$work/install"
    lcjit=$work/install/bin/lcjit
  fi
  chown -R $uid:$uid "$work/attack" "$work/run"
  mkdir "$work/home" && chown $uid:$uid "$work/home"
  cd "$work/run" && user env HOME="$work/home" LCJIT_SECURITY_AS=unprivileged bash "$work/attack/attack.sh" "$lcjit"
  exit $?
fi
cd "$work/run" && LCJIT_SECURITY_AS=$as bash "$work/attack/attack.sh" "$lcjit"
