#!/usr/bin/env bash
# Runs the example sweeps (README.md): sweep.csv and plots in OUT_DIR/<name>/.
# Usage: run_sweeps.sh [LAGRANGIAN] [OUT_DIR]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${1:-$here/../../build/bin/lagrangian}
out=${2:-out/sweeps}
launch=(--set 'model.qd[0]=20*cos(alpha*pi/180)' --set 'model.qd[1]=20*sin(alpha*pi/180)')
"$bin" sweep "$here/range_flat.toml" --vary alpha=5:85:33 "${launch[@]}" --plot q_x --out "$out/range_flat"
"$bin" sweep "$here/range_incline.toml" --vary alpha=21:89:35 "${launch[@]}" --plot q_x --out "$out/range_incline"
"$bin" sweep "$here/ke_loss.toml" --vary model.parameters.e=0:1:21 --vary model.parameters.m2=0.25:4:16 \
  --plot impact_energy_loss --out "$out/ke_loss"
"$bin" sweep "$here/flip_map.toml" --vary 'model.q[0]=-3.1:3.1:81' --vary 'model.q[1]=-3.1:3.1:81' \
  --first-time 'flip=max(abs(theta1),abs(theta2))-pi' --plot t_flip --out "$out/flip_map"
"$bin" sweep "$here/chaos_map.toml" --vary 'model.q[0]=-3.1:3.1:81' --vary 'model.q[1]=-3.1:3.1:81' \
  --output chaos --plot lyapunov_max,megno --out "$out/chaos_map"
