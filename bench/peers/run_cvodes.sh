#!/usr/bin/env bash
# Forward sensitivities of the double pendulum by SUNDIALS CVODES against
# lagrangian's sensitivities(), over a ladder of tolerances
# (bench/peers/cvodes_sensitivity.cpp; docs/performance.md). Installs
# Debian's libsundials-dev when it is missing, builds the library, then
# compiles and runs the comparison.
# Usage: bench/peers/run_cvodes.sh [REPEATS]   (default 5; the fastest run counts)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
repeats=${1:-5}
if [ ! -f /usr/include/cvodes/cvodes.h ]; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y libsundials-dev
fi
"$root/scripts/build" lagrangian
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
g++ -std=c++20 -O3 -DNDEBUG -I"$root/include" -I"$root/models" -isystem /usr/include/eigen3 \
  "$root/bench/peers/cvodes_sensitivity.cpp" "$root/build/liblagrangian.a" \
  -lsundials_cvodes -lsundials_nvecserial -lsundials_sunmatrixdense -lsundials_sunlinsoldense -lnlopt \
  -o "$out/cvodes_sensitivity"
"$out/cvodes_sensitivity" "$repeats"
