#!/usr/bin/env bash
# `lagrangian sweep` as a user meets it: one-line errors naming the option and
# the value (exit 2), a failed run as a row (exit 1), and the same table —
# byte for byte — from 1 thread, 2 threads and, when lagrangian-mpi is
# given, 2 MPI ranks.
# Usage: sweep_cli.sh LAGRANGIAN SOURCE_DIR WORK_DIR [LAGRANGIAN_MPI MPIEXEC]
set -uo pipefail
bin=$1
src=$2
work=$3
mpi_bin=${4:-}
mpiexec=${5:-}
rm -rf "$work"
mkdir -p "$work"
fails=0
scene=$src/examples/sweeps/ke_loss.toml
flip=$src/examples/sweeps/flip_map.toml

# shellcheck source=expect.sh
source "$(dirname "$0")/expect.sh"

expect 0 "--vary.*--monte-carlo" -- "$bin" sweep --help

# Bad input: exit 2, the option and the value named.
expect 2 "--vary: expected KEY=.*'model.parameters.e' \(no '='\)" -- "$bin" sweep "$scene" --vary model.parameters.e
expect 2 "--vary model.parameters.e: COUNT must be an integer >= 1, got '0'" -- "$bin" sweep "$scene" --vary model.parameters.e=0:1:0
expect 2 "--vary model.parameters.e: STOP must be a finite number, got 'one'" -- "$bin" sweep "$scene" --vary model.parameters.e=0:one:3
expect 2 "--threads: must be >= 1, got 0" -- "$bin" sweep "$scene" --vary model.parameters.e=0:1:3 --threads 0
expect 2 "--monte-carlo: every --vary must be a distribution.*model.parameters.e" -- "$bin" sweep "$scene" --vary model.parameters.e=0:1:3 --monte-carlo 10
expect 2 "--vary model.parameters.e: a distribution needs --monte-carlo" -- "$bin" sweep "$scene" --vary model.parameters.e=uniform:0:1
expect 2 "--monte-carlo: must be >= 1, got 0" -- "$bin" sweep "$scene" --vary model.parameters.e=uniform:0:1 --monte-carlo 0
expect 2 "--monte-carlo: must be >= 1, got -5" -- "$bin" sweep "$scene" --vary model.parameters.e=uniform:0:1 --monte-carlo -5
expect 2 "--seed: must be a non-negative integer, got -1" -- "$bin" sweep "$scene" --vary model.parameters.e=uniform:0:1 --monte-carlo 3 --seed -1
expect 2 "ke_loss.toml:[0-9]+: run.rtoll: unknown key 'rtoll'; did you mean 'rtol'" -- "$bin" sweep "$scene" --vary run.rtoll=1e-8:1e-6:2 --out "$work/x"
expect 2 "model.parameters.ee: unknown parameter 'ee'.*did you mean 'e'" -- "$bin" sweep "$scene" --vary model.parameters.ee=0:1:2 --out "$work/x"
expect 2 "--vary model.q\[5\]: index 5 is out of range" -- "$bin" sweep "$scene" --vary 'model.q[5]=0:1:2' --out "$work/x"
expect 2 "--set model.qd\[0\]: .*unknown name 'alpah'; did you mean 'alpha'" -- "$bin" sweep "$scene" --vary alpha=0:1:2 --set 'model.qd[0]=alpah' --out "$work/x"
expect 2 "--first-time flip: .*unknown name 'theta3'; did you mean 'theta1'" -- "$bin" sweep "$flip" --vary 'model.q[0]=0:1:2' --first-time 'flip=abs(theta3)-pi' --out "$work/x"
expect 2 "--output: unknown column group 'energie'; did you mean 'energy'" -- "$bin" sweep "$scene" --vary model.parameters.e=0:1:2 --output final,energie
# The chaos columns need a tangent flow: a text model of more than 6
# coordinates has none; a particle scene with contacts crosses its impacts.
cat > "$work/seven.toml" <<'TOML'
name = "seven oscillators"
[model]
coordinates = ["a", "b", "c", "d", "e", "f", "h"]
kinetic = "0.5*(a_dot^2 + b_dot^2 + c_dot^2 + d_dot^2 + e_dot^2 + f_dot^2 + h_dot^2)"
potential = "0.5*(a^2 + b^2 + c^2 + d^2 + e^2 + f^2 + h^2)"
q = [1, 0, 0, 0, 0, 0, 0]
TOML
expect 2 "--output chaos: the model stated as text: the tangent flow is derived for models with at most 6 coordinates; this one has 7" -- "$bin" sweep "$work/seven.toml" --vary 'model.q[0]=1:2:2' --output chaos --out "$work/x"
expect 0 "2 runs" -- "$bin" sweep "$src/examples/scenes/bouncing_ball.toml" --vary 'bodies[0].mass=1:2:2' --set run.t_end=3 --output chaos --out "$work/ball_chaos" --no-plots
# A varied variable that no --set expression reads changes nothing: the sweep says so before it runs.
expect 0 "warning: --vary alpha: no --set expression uses the variable 'alpha'" -- "$bin" sweep "$scene" --vary alpha=0:1:2 --out "$work/unused" --no-plots
expect 0 "" -- "$bin" sweep "$scene" --vary alpha=0:1:2 --set 'model.parameters.e=0.5+0.1*alpha' --out "$work/used" --no-plots
if grep -q "no --set expression uses" <<<"$("$bin" sweep "$scene" --vary alpha=0:1:2 --set 'model.parameters.e=0.5+0.1*alpha' --out "$work/used" --no-plots 2>&1)"; then
  echo "FAIL: a used variable was warned about"; fails=$((fails + 1))
fi
[ ! -e "$work/x/sweep.csv" ] || { echo "FAIL: bad input left sweep.csv"; fails=$((fails + 1)); }

# An integer key the scene does not write (run.max_steps): integral values go in as integers.
expect 0 "3 runs \(0 failed\)" -- "$bin" sweep "$scene" --vary run.max_steps=1000:3000:3 --out "$work/int" --no-plots
# A failed run is a row with its message; the others run; exit 1.
expect 1 "1 of 3 runs failed" -- "$bin" sweep "$scene" --vary model.parameters.e=0.5:1.5:3 --out "$work/failed" --no-plots
grep -q '^2,1.5,"*failed: .*model.parameters.e' "$work/failed/sweep.csv" || { echo "FAIL: no failed row"; cat "$work/failed/sweep.csv"; fails=$((fails + 1)); }
grep -q '^1,1,ok,' "$work/failed/sweep.csv" || { echo "FAIL: the run after... missing"; fails=$((fails + 1)); }
[ ! -e "$work/failed/sweep.csv.partial" ] || { echo "FAIL: a partial file was left"; fails=$((fails + 1)); }

# The same table from 1 thread, 2 threads and 2 MPI ranks (the default columns: no wall time).
args=(sweep "$flip" --vary 'model.q[0]=-3:3:7' --vary 'model.q[1]=-3:3:6' --first-time 'flip=max(abs(theta1),abs(theta2))-pi' -q)
expect 0 "" -- "$bin" "${args[@]}" --threads 1 --out "$work/t1"
expect 0 "" -- "$bin" "${args[@]}" --threads 2 --out "$work/t2"
[ "$(wc -l < "$work/t1/sweep.csv")" -eq 43 ] || { echo "FAIL: expected 42 rows and a header"; fails=$((fails + 1)); }
cmp "$work/t1/sweep.csv" "$work/t2/sweep.csv" || { echo "FAIL: 1 and 2 threads differ"; fails=$((fails + 1)); }
[ -s "$work/t1/sweep_t_flip.png" ] || ! command -v gnuplot >/dev/null || { echo "FAIL: no heat map"; fails=$((fails + 1)); }
# The largest Lyapunov exponent and MEGNO: the same from 1 and 2 threads (and 2 ranks below).
chaos=(sweep "$flip" --vary 'model.q[0]=0.5:2.5:3' --vary 'model.q[1]=2:2:1' --output final,chaos -q --no-plots)
expect 0 "" -- "$bin" "${chaos[@]}" --threads 1 --out "$work/c1"
expect 0 "" -- "$bin" "${chaos[@]}" --threads 2 --out "$work/c2"
head -1 "$work/c1/sweep.csv" | grep -q ',lyapunov_max \[1/s\],megno$' || { echo "FAIL: no chaos columns"; head -1 "$work/c1/sweep.csv"; fails=$((fails + 1)); }
cmp "$work/c1/sweep.csv" "$work/c2/sweep.csv" || { echo "FAIL: chaos columns differ with the thread count"; fails=$((fails + 1)); }
# A particle scene's bodies have a tangent flow too: the binary star's mass
# ratio varied, every orbit regular (MEGNO of a Kepler orbit, below 3).
expect 0 "" -- "$bin" sweep "$src/examples/scenes/binary_star.toml" --vary 'bodies[1].mass=1:2:2' --set run.t_end=20 \
  --output chaos -q --no-plots --out "$work/c_particles"
/usr/bin/python3 - "$work/c_particles/sweep.csv" <<'PY' || fails=$((fails + 1))
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
ok = len(rows) == 2 and all(0 < float(r['megno']) < 3 and abs(float(r['lyapunov_max [1/s]'])) < 0.5 for r in rows)
print("ok: particle chaos columns" if ok else "FAIL: particle chaos columns " + str(rows))
sys.exit(0 if ok else 1)
PY
# The same map from the double pendulum stated as text, with the same run settings: the same exponents and MEGNO.
expect 0 "" -- "$bin" sweep "$src/examples/scenes/text/double_pendulum.toml" --vary 'model.q[0]=0.5:2.5:3' --vary 'model.q[1]=2:2:1' \
  --set 'run.t_end=10' --set 'run.rtol=1e-8' --set 'run.atol=1e-10' --output final,chaos -q --no-plots --out "$work/c_text"
/usr/bin/python3 - "$work/c1/sweep.csv" "$work/c_text/sweep.csv" <<'PY' || fails=$((fails + 1))
import csv, sys
a, b = (list(csv.DictReader(open(f))) for f in sys.argv[1:])
bad = [(x[k], y[k]) for x, y in zip(a, b) for k in ("lyapunov_max [1/s]", "megno") if abs(float(x[k]) - float(y[k])) > 1e-6 * (1 + abs(float(x[k])))]
print("FAIL: the text model's chaos map differs:", bad) if bad or len(a) != 3 or len(b) != 3 else print("ok: the text model's chaos map is the built-in model's")
sys.exit(1 if bad or len(a) != 3 or len(b) != 3 else 0)
PY
# Monte Carlo: the same draws whatever the thread count.
mc=(sweep "$scene" --vary model.parameters.e=uniform:0:1 --vary model.parameters.m2=normal:2:0.1 --monte-carlo 40 --seed 7 -q --no-plots)
expect 0 "" -- "$bin" "${mc[@]}" --threads 1 --out "$work/mc1"
expect 0 "" -- "$bin" "${mc[@]}" --threads 2 --out "$work/mc2"
cmp "$work/mc1/sweep.csv" "$work/mc2/sweep.csv" || { echo "FAIL: Monte Carlo differs with the thread count"; fails=$((fails + 1)); }
# Ctrl-C (SIGINT) during a long sweep: the runs under way finish, no new one
# starts, the working files go, nothing that looks like a table is left;
# exit 130 and one line saying so. An earlier table in the directory is
# removed too (it is not this sweep's).
mkdir -p "$work/intr" && echo "old" > "$work/intr/sweep.csv"
"$bin" sweep "$scene" --vary model.parameters.e=0:1:200000 --threads 1 --no-plots --out "$work/intr" \
  > "$work/intr.out" 2>&1 &
pid=$!
sleep 2
kill -INT "$pid"
wait "$pid"
rc=$?
if [ "$rc" -ne 130 ] || ! grep -qE "sweep interrupted after [0-9]+ of 200000 runs; no table written" "$work/intr.out"; then
  echo "FAIL: interrupted sweep exited $rc"; head -5 "$work/intr.out"; fails=$((fails + 1))
else
  echo "ok: interrupted sweep -> 130: $(tail -1 "$work/intr.out")"
fi
[ ! -e "$work/intr/sweep.csv" ] || { echo "FAIL: an interrupted sweep left sweep.csv"; fails=$((fails + 1)); }
ls -A "$work/intr" | grep -q "work-rank" && { echo "FAIL: an interrupted sweep left its work directory"; fails=$((fails + 1)); }

if [ -n "$mpi_bin" ]; then
  # As root, Open MPI needs these; on two cores two ranks may need --oversubscribe.
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
  expect 0 "" -- "$mpiexec" -np 2 "$mpi_bin" "${args[@]}" --threads 1 --out "$work/r2"
  cmp "$work/t1/sweep.csv" "$work/r2/sweep.csv" || { echo "FAIL: 2 ranks differ from 1 thread"; fails=$((fails + 1)); }
  expect 0 "" -- "$mpiexec" -np 2 "$mpi_bin" "${mc[@]}" --threads 2 --out "$work/mcr2"
  expect 0 "" -- "$mpiexec" -np 2 "$mpi_bin" "${chaos[@]}" --threads 1 --out "$work/cr2"
  cmp "$work/c1/sweep.csv" "$work/cr2/sweep.csv" || { echo "FAIL: chaos columns on 2 ranks differ"; fails=$((fails + 1)); }
  cmp "$work/mc1/sweep.csv" "$work/mcr2/sweep.csv" || { echo "FAIL: Monte Carlo on 2 ranks differs"; fails=$((fails + 1)); }
  expect 2 "--threads: must be >= 1, got 0" -- "$mpiexec" -np 2 "$mpi_bin" sweep "$scene" --vary model.parameters.e=0:1:3 --threads 0
  expect 2 "unknown subcommand 'run'; the subcommands are: sweep; lagrangian-mpi runs sweeps only" -- "$mpi_bin" run "$scene"
  # Rank 0 cannot write its output directory while rank 1 can run: no rank waits forever.
  touch "$work/blocker"
  expect 2 "--out: cannot create the directory" -- timeout 120 "$mpiexec" -np 2 "$mpi_bin" sweep "$scene" --vary model.parameters.e=0:1:3 --out "$work/blocker/x"
  ls "$work"/r2/.work-rank* >/dev/null 2>&1 && { echo "FAIL: a rank left its work directory"; fails=$((fails + 1)); }
else
  echo "skipped: the MPI comparison (lagrangian-mpi not built)"
fi

if [ "$fails" -eq 0 ]; then echo "all sweep CLI checks passed"; else echo "$fails sweep CLI checks failed"; exit 1; fi
