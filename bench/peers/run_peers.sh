#!/usr/bin/env bash
# The side-by-side comparisons of docs/performance.md ("Against what users
# would pick instead"), with one command:
#   1. lagrangian bench on the double pendulum from (2, 2) rad: error at
#      t = 5 s (against the shipped mpmath reference) and the runs to t = 20 s,
#      per stepper and tolerance;
#   2. the same system derived by SymPy and integrated by SciPy's solve_ivp
#      (DOP853, RK45, Radau) at the same tolerances: time, error, the speed
#      ratio at equal error, and SymPy's derivation time; both sides' energy
#      error at t = 20 s as |E(20) - E(0)| / |E(0)| (lagrangian's from one
#      `lagrangian run` per stepper and tolerance);
#   3. lagrangian's "derivation": the compile time of a file that evaluates
#      the AD-derived q'' (bench/peers/derive_double_pendulum.cpp), and one
#      evaluation;
#   4. simulate() against raw Boost.Odeint with a hand-coded right-hand side
#      (bench/bench_simulate.cpp): same steps, overhead ratio.
# Usage: bench/peers/run_peers.sh [OUT_DIR] [REPEAT]   (default out/peers, 3)
# Slow (several minutes; SciPy's Radau dominates). Not part of the test
# suite, which only checks that the scripts start (--smoke).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
out=${1:-$root/out/peers}
repeat=${2:-3}
py=/usr/bin/python3   # Debian's python3-sympy and python3-scipy install here
mkdir -p "$out"
"$root/scripts/build" lagrangian_cli bench_simulate
bin="$root/build/bin/lagrangian"
scene="$root/bench/scenes/double_pendulum_chaotic.toml"

echo "== 1. lagrangian bench (t = 5 s and t = 20 s)"
"$bin" bench "$scene" --methods dopri5,fehlberg78,bulirsch_stoer --repeat "$repeat" --out "$out/t5" -q
"$bin" bench "$scene" --t-end 20 --methods dopri5,fehlberg78,bulirsch_stoer --repeat "$repeat" --out "$out/t20" -q

echo "== 2. SymPy + SciPy"
"$py" "$root/bench/peers/sympy_scipy.py" --ours-error "$out/t5/bench.json" --ours-energy "$out/t20/bench.json" \
  --lagrangian "$bin" --scene "$scene" --out "$out" --repeat "$repeat"

echo "== 3. lagrangian's derivation: compile time of the AD q'' and one evaluation"
eigen=$(pkg-config --cflags eigen3 2>/dev/null || echo -I/usr/include/eigen3)
start=$(date +%s.%N)
g++ -std=c++20 -O2 -I"$root/include" -I"$root/models" $eigen "$root/bench/peers/derive_double_pendulum.cpp" \
  -o "$out/derive_double_pendulum"
end=$(date +%s.%N)
echo "compile time (g++ -O2, one file): $(awk "BEGIN { printf \"%.2f\", $end - $start }") s" | tee "$out/derive.txt"
"$out/derive_double_pendulum" | tee -a "$out/derive.txt"

echo "== 4. simulate() vs raw Boost.Odeint, hand-coded right-hand side"
"$root/build/bench/bench_simulate" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_min_time=0.5 2>&1 | tee "$out/odeint.txt" | grep -E "median|^Run on" || true
# Ratios of the medians, by wall time and by CPU time (the CPU time is the
# steadier of the two on a machine shared with other programs).
awk '/_median/ { name = $1; sub(/_median$/, "", name); wall[name] = $2; cpu[name] = $4 }
     END {
       split("Dopri5 Fehlberg78 Rk4", s, " ")
       split("DoublePendulum Oscillator", y, " ")
       for (j = 1; j <= 2; ++j)
       for (i = 1; i <= 3; ++i) {
         raw = "BM_RawOdeint_" s[i] "_" y[j]; hand = "BM_Simulate_HandRHS_" s[i] "_" y[j]
         ad = "BM_Simulate_AD_" s[i] "_" y[j]
         if (wall[raw] > 0)
           printf "%-14s %-10s raw %.3f ms (cpu %.3f), simulate(hand q\x27\x27) %.3f ms (%.2fx; cpu %.2fx), simulate(AD) %.3f ms (%.2fx; cpu %.2fx)\n",
             y[j], s[i], wall[raw], cpu[raw], wall[hand], wall[hand] / wall[raw], cpu[hand] / cpu[raw], wall[ad], wall[ad] / wall[raw], cpu[ad] / cpu[raw]
       }
     }' "$out/odeint.txt" | tee "$out/odeint_ratios.txt"
echo "peers: results in $out (peers.txt, scipy.csv, peers_*.png, derive.txt, odeint_ratios.txt)"
