#!/usr/bin/env bash
# Makes every work-precision figure of docs/accuracy.md with `lagrangian bench`
# and copies the diagrams to docs/img/accuracy/. Each bench also leaves its
# work_precision.csv and bench.json under OUT_DIR (default out/accuracy).
# Usage: bench/accuracy_figures.sh [OUT_DIR] [REPEAT]   (default 3 repeats; a few minutes)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$root/out/accuracy}
repeat=${2:-3}
"$root/scripts/build" lagrangian_cli
bin="$root/build/bin/lagrangian"
img="$root/docs/img/accuracy"
mkdir -p "$out" "$img"

run() {  # run NAME SCENE [OPTIONS...]
  local name=$1 scene=$2
  shift 2
  echo "== $name: lagrangian bench $scene $*"
  "$bin" bench "$root/$scene" --repeat "$repeat" --out "$out/$name" "$@" | tee "$out/$name.txt"
  for f in work_precision_time work_precision_rhs work_precision_energy; do
    [ -f "$out/$name/$f.png" ] && cp "$out/$name/$f.png" "$img/${name}_${f#work_precision_}.png"
  done
  return 0
}

run projectile        examples/scenes/projectile.toml
run harmonic_oscillator examples/scenes/harmonic_oscillator.toml
run pendulum_large    bench/scenes/pendulum_large_amplitude.toml
run kepler_e05        bench/scenes/kepler_e05_100_orbits.toml --dt 0.01:0.0001
run kepler_e09        bench/scenes/kepler_e09_100_orbits.toml --dt 0.01:0.0001
run double_pendulum_5 bench/scenes/double_pendulum_chaotic.toml
run double_pendulum_20 bench/scenes/double_pendulum_chaotic.toml --t-end 20
run bouncing_ball     examples/scenes/bouncing_ball.toml
for s in none baumgarte projection; do
  run "link_pendulum_$s" examples/scenes/link_pendulum.toml --stabilization "$s"
done
echo "figures in $img"
