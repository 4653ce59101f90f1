#!/usr/bin/env bash
# Runs per second of `lagrangian sweep` against the thread count (1, 2) and
# the MPI rank count (1, 2 ranks of 1 thread each), on the double-pendulum
# grid of examples/sweeps/flip_map.toml (41 x 41 = 1681 runs of 10 s each;
# no trajectory files). Each configuration runs REPEAT times (default 3); the
# median is printed, with the CPU time (user + system) of each process and the
# machine's load average. Runs per second count the sweep from loading the
# scene to the last result gathered (not MPI start-up, not writing the table).
# Usage: bench/sweep_scaling.sh [BUILD_DIR] [REPEAT]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
repeat=${2:-3}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
args=(sweep "$root/examples/sweeps/flip_map.toml" --vary 'model.q[0]=-3.1:3.1:41' --vary 'model.q[1]=-3.1:3.1:41'
      --no-plots)

rate() {  # the runs/s that the sweep prints
  sed -n 's/.*: \([0-9.]*\) runs\/s$/\1/p'
}
median() { sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }

measure() {  # measure LABEL command...
  local label=$1
  shift
  local rates=() cpu=()
  for ((k = 0; k < repeat; ++k)); do
    rates+=("$(/usr/bin/time -f '%U %S' -o "$out/time" "$@" --out "$out/s" | rate)")
    cpu+=("$(awk '{printf "%.2f", $1 + $2}' "$out/time")")
  done
  printf '%-26s %8s runs/s  (each: %s; CPU s of the whole process: %s)\n' "$label" \
    "$(printf '%s\n' "${rates[@]}" | median)" "${rates[*]}" "${cpu[*]}"
}

echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), load average $(cut -d' ' -f1-3 /proc/loadavg), $(date -u +%Y-%m-%dT%H:%MZ)"
measure "1 thread" "$build/bin/lagrangian" "${args[@]}" --threads 1
measure "2 threads" "$build/bin/lagrangian" "${args[@]}" --threads 2
if [ -x "$build/bin/lagrangian-mpi" ]; then
  measure "1 rank x 1 thread (MPI)" mpiexec -np 1 "$build/bin/lagrangian-mpi" "${args[@]}" --threads 1
  measure "2 ranks x 1 thread (MPI)" mpiexec -np 2 "$build/bin/lagrangian-mpi" "${args[@]}" --threads 1
fi
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
