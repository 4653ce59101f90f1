#!/usr/bin/env bash
# gauss_radau15 against REBOUND's IAS15 on the same two-body orbits, measured
# in one run on one machine with one error measure (docs/performance.md,
# "Gauss–Radau against IAS15"). A manual benchmark: REBOUND is not a Debian
# package and is not part of the build, the tests or CI.
#
# Usage: bench/peers/run_ias15.sh REBOUND_SRC [OUT_DIR=/tmp/lagrangian_ias15]
#   REBOUND_SRC  a REBOUND source tree (git clone https://github.com/hannorein/rebound);
#                its src/ is copied to OUT_DIR and built there (make librebound.so)
# Environment:
#   BUILD=<repo>/build  lagrangian's Release build with LAGRANGIAN_BUILD_BENCH=ON
#                       (the script builds its target bench_orbits)
#   BENCH_ORBITS=       a bench_orbits program to use instead (no build)
#   ROUNDS=3            interleaved rounds over all cases
#   ORBITS=1000         orbits per case
#   CASES=24            cases per eccentricity: case k starts at true anomaly
#                       2πk/CASES with m2/m1 = 1e-3, 1e-2, 1e-1, 1 for k mod 4
#   EPS=1e-9            IAS15's epsilon and gauss_radau15's rtol
#
# Each case runs bench_orbits --case (gauss_radau15 in Cartesian coordinates
# of both bodies, the reduced-mass relative coordinate and polar coordinates)
# and ias15_orbits (IAS15, both bodies, Cartesian: its only formulation) one
# after the other, in alternating order, so that load from other programs
# falls on both alike. Both report |E(t_end) − E(0)| / |E(0)| with the
# energy of the final double state evaluated in long double, and the wall
# and process CPU time of the integration alone. The summary
# (ias15_summary.py) takes per case the minimum time over the rounds, then
# the median over the cases, and the ratio IAS15 / gauss_radau15 of those
# medians, with the ratios of the single rounds beside it.
set -euo pipefail

if [[ $# -lt 1 || ! -f "$1/src/integrator_ias15.c" ]]; then
  echo "usage: $0 REBOUND_SRC [OUT_DIR]   (REBOUND_SRC/src/integrator_ias15.c must exist)" >&2
  exit 2
fi
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
rebound=$(cd "$1" && pwd)
out=${2:-/tmp/lagrangian_ias15}
build=${BUILD:-$repo/build}
rounds=${ROUNDS:-3}
orbits=${ORBITS:-1000}
cases=${CASES:-24}
eps=${EPS:-1e-9}
mkdir -p "$out"

echo "== building REBOUND ($rebound) in $out/rebound-src" >&2
rm -rf "$out/rebound-src"
cp -r "$rebound/src" "$out/rebound-src"
rebound_commit=$(git -C "$rebound" rev-parse HEAD 2>/dev/null || echo unknown)
rebound_version=$(cat "$rebound/version.txt" 2>/dev/null || echo unknown)
make -C "$out/rebound-src" librebound.so SERVER=0 GITHASH="$rebound_commit" >"$out/rebound_make.log" 2>&1
rebound_flags=$(grep -m1 -- ' -c ' "$out/rebound_make.log" | sed 's/ -o .*//')
ias15_flags="-O3 -std=c99 -D_GNU_SOURCE"
cc $ias15_flags -I"$out/rebound-src" "$here/ias15_orbits.c" -L"$out/rebound-src" -lrebound -lm \
  -Wl,-rpath,"$out/rebound-src" -o "$out/ias15_orbits"

if [[ -n "${BENCH_ORBITS:-}" ]]; then
  bench_orbits=$BENCH_ORBITS
else
  echo "== building bench_orbits in $build" >&2
  cmake --build "$build" --target bench_orbits >"$out/bench_orbits_build.log" 2>&1
  bench_orbits=$(find "$build" -name bench_orbits -type f -perm -u+x | head -1)
fi
[[ -x "$bench_orbits" ]] || { echo "bench_orbits not found under $build" >&2; exit 1; }

raw="$out/raw.txt"
{
  echo "# run_ias15.sh $*: ROUNDS=$rounds ORBITS=$orbits CASES=$cases EPS=$eps"
  echo "# REBOUND $rebound_version, commit $rebound_commit; built: $rebound_flags; driver: cc $ias15_flags"
  echo "# lagrangian $(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown): $bench_orbits" \
       "($(grep -m1 '^CMAKE_BUILD_TYPE' "$build/CMakeCache.txt" 2>/dev/null || echo 'build type unknown');" \
       "$(grep -m1 '^CMAKE_CXX_FLAGS_RELEASE' "$build/CMakeCache.txt" 2>/dev/null || true))"
  echo "# machine: $(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //'), $(nproc) hardware threads;" \
       "load average at start $(cut -d' ' -f1-3 /proc/loadavg); $(date -u '+%Y-%m-%d %H:%M UTC')"
} >"$raw"

twopi=6.283185307179586
for ((round = 1; round <= rounds; ++round)); do
  for e in 0.5 0.9 0.99; do
    for ((k = 0; k < cases; ++k)); do
      ratio=$(awk -v k="$k" 'BEGIN { split("1e-3 1e-2 1e-1 1", r, " "); print r[k % 4 + 1] }')
      f0=$(awk -v k="$k" -v n="$cases" -v tp="$twopi" 'BEGIN { printf "%.17g", tp * k / n }')
      lag() { "$bench_orbits" --case "$e" "$ratio" "$f0" "$orbits" "$eps" | sed "s/^/$round /"; }
      ias() { "$out/ias15_orbits" "$e" "$ratio" "$f0" "$orbits" "$eps" | sed "s/^/$round /"; }
      if (((k + round) % 2)); then lag; ias; else ias; lag; fi >>"$raw"
    done
    echo "round $round of $rounds, e = $e done (load $(cut -d' ' -f1 /proc/loadavg))" >&2
  done
done
echo "# load average at the end $(cut -d' ' -f1-3 /proc/loadavg); $(date -u '+%Y-%m-%d %H:%M UTC')" >>"$raw"

/usr/bin/python3 "$here/ias15_summary.py" "$raw" | tee "$out/summary.md"
