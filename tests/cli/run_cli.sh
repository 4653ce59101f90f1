#!/usr/bin/env bash
# The `lagrangian` command as a user meets it: exit codes (0 ok, 1 run
# failed, 2 bad input), the files a run writes, and the one-line errors.
# Usage: run_cli.sh LAGRANGIAN_BINARY SOURCE_DIR WORK_DIR
set -uo pipefail
bin=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")  # absolute: some checks run from another directory
src=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
fails=0

# shellcheck source=expect.sh
source "$(dirname "$0")/expect.sh"

# Help on every command.
expect 0 "run.*inspect.*list|Subcommands" -- "$bin" --help
expect 0 "--t-end" -- "$bin" run --help
expect 0 "scene" -- "$bin" inspect --help
expect 0 "" -- "$bin" list --help

# list: built-in models and example scenes.
expect 0 "double_pendulum" -- "$bin" list
expect 0 "bouncing_ball.toml" -- "$bin" list
# The README says how many built-in models there are: as many as list shows.
models=$("$bin" list | sed -n '/^Built-in models/,/^$/p' | grep -c '^  [a-z]')
grep -q "^$models built-in generalized-coordinate models" "$src/README.md" || { echo "FAIL: README's model count is not list's $models"; fails=$((fails + 1)); }
# list MODEL: the coordinates with units and the parameters with defaults.
expect 0 "^  theta2 +rad$" -- "$bin" list double_pendulum
expect 0 "^  g +9.81 +m/s\^2 +acceleration of gravity$" -- "$bin" list double_pendulum
expect 2 "list: unknown model 'double_pendlum'; did you mean 'double_pendulum'" -- "$bin" list double_pendlum

# A model stated by T and V in the scene runs with no compiler: the summary,
# the CSV header with the coordinates' units, and errors with file, line,
# key and column.
expect 0 "momentum of cyclic phi: 1.41614683655" -- "$bin" run "$src/examples/scenes/text/spherical_pendulum.toml" --out "$work/text" --no-plots --no-animation
head -1 "$work/text/trajectory.csv" | grep -q '^t \[s\],theta \[rad\],phi \[rad\],theta_dot \[rad/s\],phi_dot \[rad/s\]' ||
  { echo "FAIL: text model trajectory header"; fails=$((fails + 1)); }
sed 's/theta_dot^2 +/thta_dot^2 +/' "$src/examples/scenes/text/spherical_pendulum.toml" > "$work/text_bad.toml"
expect 2 "text_bad.toml:13: model.kinetic: column 12: unknown name 'thta_dot'" -- "$bin" run "$work/text_bad.toml" --out "$work/text_bad"
[ ! -e "$work/text_bad" ] || { echo "FAIL: a scene with a bad expression left $work/text_bad"; fails=$((fails + 1)); }
expect 0 "p_phi = 1.41614683655 kg\*m\^2/s \(conserved\)" -- "$bin" inspect "$src/examples/scenes/text/spherical_pendulum.toml"
expect 0 "2 runs \(0 failed\)" -- "$bin" sweep "$src/examples/scenes/text/spherical_pendulum.toml" --vary model.parameters.l=0.5:1.0:2 --set run.t_end=1 --out "$work/text_sweep" --no-plots
grep -q '^1,1,1,ok,1,' "$work/text_sweep/sweep.csv" || { echo "FAIL: text model sweep row"; fails=$((fails + 1)); }
expect 0 "^fehlberg78 +1e-08 " -- "$bin" bench "$src/examples/scenes/text/spherical_pendulum.toml" --methods fehlberg78 --tolerances 1e-6:1e-8 --out "$work/text_bench" --no-plots
# Constraints and contacts stated as text: the string's tension as a column
# with its unit, the degrees of freedom, a contact's impacts and rest, and a
# contact without its restitution named with file and line.
expect 0 "constraints \(1, projection\)" -- "$bin" run "$src/examples/scenes/text/atwood_machine.toml" --out "$work/text_atwood" --no-plots --no-animation
head -1 "$work/text_atwood/trajectory.csv" | grep -q ',lambda_string \[N\],' ||
  { echo "FAIL: text Atwood machine has no lambda_string [N] column"; fails=$((fails + 1)); }
expect 0 "degrees of freedom +1 +=" -- "$bin" inspect "$src/examples/scenes/text/atwood_machine.toml"
expect 0 "event: rest incline at t = 2\.3541" -- "$bin" run "$src/examples/scenes/text/projectile_on_incline.toml" --out "$work/text_incline" --no-plots --no-animation
grep -q '^1\.17706476899[0-9]*,impact,incline,' "$work/text_incline/events.csv" ||
  { echo "FAIL: text incline's first impact"; fails=$((fails + 1)); }
grep -v '^restitution' "$src/examples/scenes/text/projectile_on_incline.toml" > "$work/text_no_e.toml"
expect 2 "text_no_e.toml:[0-9]+: model.contacts\[0\].restitution: " -- "$bin" run "$work/text_no_e.toml" --out "$work/text_no_e"
# A text model that cannot start: an expression undefined at t0 (named with
# the operation and the value), a coordinate without inertia (named).
cat > "$work/text_start.toml" <<'TOML'
[model]
coordinates = ["x", "y"]
kinetic = "0.5*m*x_dot^2 + 0.5*m*y_dot^2"
potential = "k*log(x - a)"
q = [1.0, 0.0]
[model.parameters]
m = 1.0
k = 1.0
a = 2.0
TOML
expect 2 "text_start.toml:4: model.potential: at t0 = 0 s, log of a number <= 0: log\(x - a\) with x - a = -1" -- "$bin" run "$work/text_start.toml" --out "$work/text_start"
[ ! -e "$work/text_start" ] || { echo "FAIL: a text model that cannot start left $work/text_start"; fails=$((fails + 1)); }
sed -e 's/ + 0.5\*m\*y_dot^2//' -e 's/k\*log(x - a)/k*x/' "$work/text_start.toml" > "$work/text_mass.toml"
expect 2 "text_mass.toml:3: model.kinetic: coordinate 'y' carries no inertia at t0" -- "$bin" run "$work/text_mass.toml" --out "$work/text_mass"
# The harmonic oscillator as text: equilibrium x = 0 with omega = 2 rad/s
# (k/m = 4), and its boundary-value problem; with D, solve-bvp refuses.
cat > "$work/text_oscillator.toml" <<'TOML'
[model]
coordinates = ["x"]
units = ["m"]
kinetic = "0.5*m*x_dot^2"
potential = "0.5*k*x^2"
q = [0.3]
[model.parameters]
m = 2.0
k = 8.0
TOML
expect 0 "^  1 +4 +2 +0.31830989" -- "$bin" inspect "$work/text_oscillator.toml" --equilibria --modes
expect 0 "action" -- "$bin" solve-bvp "$work/text_oscillator.toml" --from 0.1 --to 0.2 --time 1 --out "$work/text_bvp" --no-plots
sed 's/^potential = .*/&\ndissipation = "0.5*x_dot^2"/' "$work/text_oscillator.toml" > "$work/text_damped.toml"
expect 2 "solve-bvp: model 'text' declares a dissipation function" -- "$bin" solve-bvp "$work/text_damped.toml" --from 0.1 --to 0.2 --time 1 --out "$work/text_bvp2"

# A run writes its files and prints a summary with the cost and the accuracy.
expect 0 "RHS evaluations.*wall" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --out "$work/ball" --no-plots
for f in trajectory.csv events.csv report.json; do
  [ -s "$work/ball/$f" ] || { echo "FAIL: $work/ball/$f missing"; fails=$((fails + 1)); }
done
grep -q '"engine": "ode"' "$work/ball/report.json" || { echo "FAIL: report.json lacks the engine"; fails=$((fails + 1)); }
head -1 "$work/ball/trajectory.csv" | grep -q '^t \[s\],ball.x \[m\],ball.y \[m\],ball.z \[m\],ball.x_dot \[m/s\]' ||
  { echo "FAIL: trajectory header"; fails=$((fails + 1)); }
# Columns found by name and unit, as pandas would (df["ball.z [m]"]): the
# drop height, and the first impact at sqrt(2h/g) with impulse m(1 + e)sqrt(2gh).
/usr/bin/python3 - "$work/ball" <<'PY' || { echo "FAIL: the CSV files read by column name and unit"; fails=$((fails + 1)); }
import csv, math, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(d + "/trajectory.csv")))
assert float(rows[0]["ball.z [m]"]) == 1.033 and float(rows[0]["t [s]"]) == 0, rows[0]
assert all(float(r["energy [J]"]) > 0 for r in rows)
first = next(csv.DictReader(open(d + "/events.csv")))
h, g, m, e = 1.0, 9.81, 0.057, 0.8
assert first["kind"] == "impact" and first["bodies"] == "ball-floor", first
assert abs(float(first["t [s]"]) - math.sqrt(2 * h / g)) < 1e-9, first
assert abs(float(first["impulse [N*s]"]) - m * (1 + e) * math.sqrt(2 * g * h)) < 1e-9, first
assert abs(float(first["approach_speed [m/s]"]) - math.sqrt(2 * g * h)) < 1e-9, first
PY
# The animation page: written by default, listed, one self-contained file; --no-animation removes the old one.
grep -q 'id="lagrangian-data"' "$work/ball/animation.html" || { echo "FAIL: animation.html missing"; fails=$((fails + 1)); }
grep -q '^animation.html$' "$work/ball/.lagrangian-outputs" || { echo "FAIL: animation.html not in the manifest"; fails=$((fails + 1)); }
expect 0 "wrote: .*report.json$" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --out "$work/ball" --no-plots --no-animation
[ ! -e "$work/ball/animation.html" ] || { echo "FAIL: --no-animation left the old animation.html"; fails=$((fails + 1)); }
# A video for slides (ffmpeg): written and listed; an unknown format is bad input; ffmpeg failing is a failed run.
expect 0 "wrote: .*ball.mp4$" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --out "$work/ball" --no-plots --animate-to "$work/ball.mp4" --animate-seconds 2
[ -s "$work/ball.mp4" ] || { echo "FAIL: --animate-to wrote no video"; fails=$((fails + 1)); }
expect 2 "--animate-to: '.*ball.avi': unknown format '.avi' \\(use .mp4, .webm or .gif\\)" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --out "$work/ball" --animate-to "$work/ball.avi"
expect 1 "video: ffmpeg failed writing" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --out "$work/ball" --no-plots --animate-to "$work/no/such/dir/ball.gif"
[ ! -e "$work/no/such/dir/ball.gif.partial" ] || { echo "FAIL: a failed video left a partial file"; fails=$((fails + 1)); }
# Overrides from the command line.
expect 0 "t = 0 .. 0.5 s" -- "$bin" run "$src/examples/scenes/link_pendulum.toml" --out "$work/pend" --t-end 0.5 --method rk4 --no-plots
expect 0 "closed form" -- "$bin" run "$src/examples/scenes/kepler.toml" --out "$work/kepler" --rtol 1e-8 --atol 1e-10 --no-plots
# The structure-preserving steppers by name; refused with the reason where they do not apply.
expect 0 "Newton iterations" -- "$bin" run "$src/examples/scenes/double_pendulum.toml" --out "$work/dpv" --t-end 2 --method variational --no-plots
expect 2 "needs a separable model.*mass matrix" -- "$bin" run "$src/examples/scenes/double_pendulum.toml" --out "$work/dps" --method velocity_verlet --no-plots
# --set: any numeric key, as if the file said so. The ball rests at
# t = sqrt(2h/g)(1 + e)/(1 - e) = 1.35457 s for e = 0.5 (h = 1 m).
expect 0 "event: rest ball-floor at t = 1\.3545[67]" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --out "$work/set" --no-plots --no-animation --set 'contacts.planes[0].restitution=0.5'
expect 0 "l2 += +2 +m .*from the scene" -- "$bin" inspect "$src/examples/scenes/double_pendulum.toml" --set model.parameters.l2=2
expect 2 "--set: 'foo' is not KEY=VALUE" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --set foo
expect 2 "--set run.rtol: 'abc' is not a finite number" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --set run.rtol=abc
expect 2 "command line: --set sets bodies\[0\]\.mas: unknown key 'mas'; did you mean 'mass'" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --set 'bodies[0].mas=1'
expect 2 "command line: --set sets bodies\[0\]\.mass: must be > 0, got -1" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --set 'bodies[0].mass=-1'
# "-": the scene from standard input, named <stdin> in errors.
expect 0 "event: rest ball-floor at t = 4\.0637" -- sh -c "'$bin' run - --out '$work/stdin' --no-plots --no-animation < '$src/examples/scenes/bouncing_ball.toml'"
expect 2 "<stdin>:1: name: expected a string, got integer 3" -- sh -c "echo 'name = 3' | '$bin' run - --out '$work/stdin_bad'"
# Quiet in a pipe: no progress bar characters on stderr.
"$bin" run "$src/examples/scenes/bouncing_ball.toml" --out "$work/quiet" --no-plots 2>"$work/stderr.txt" >/dev/null
[ ! -s "$work/stderr.txt" ] || { echo "FAIL: stderr not empty in a pipe"; cat "$work/stderr.txt"; fails=$((fails + 1)); }

# Shell completion: tests/cli/completion_cli.sh.

# inspect --json: the same facts as one JSON object (read here by Python's json module).
json_check() {  # SCENE PYTHON-ASSERTIONS (d: the parsed object)
  "$bin" inspect "$src/examples/scenes/$1" --json > "$work/inspect.json" \
    || { echo "FAIL: inspect $1 --json exited $?"; fails=$((fails + 1)); return; }
  /usr/bin/python3 -c "import json, sys; d = json.load(open(sys.argv[1])); $2" "$work/inspect.json" \
    && echo "ok: inspect $1 --json" || { echo "FAIL: inspect $1 --json: $2"; fails=$((fails + 1)); }
}
json_check double_pendulum_links.toml "c = d['constraints']; assert (c['coordinates'], c['rank'], c['degrees_of_freedom']) == (6, 2, 4), c; assert [b['name'] for b in d['bodies']] == ['upper', 'lower']"
json_check cartesian_double_pendulum.toml "c = d['constraints']; assert c['degrees_of_freedom'] == 2 and d['declared']['holonomic'] == ['rod1', 'rod2'], c; assert d['coordinates'][0]['unit'] == 'm'"
# The projectile's x is cyclic: p_x = m v cos 45 degrees = 20/sqrt(2) kg m/s; apex and landing are watched.
json_check projectile.toml "import math; c = d['cyclic']; assert c[0]['coordinate'] == 'x' and abs(c[0]['p'] - 20 / math.sqrt(2)) < 1e-12, c; assert [e['name'] for e in d['declared']['watched_events']] == ['apex', 'landing']"
# Every example scene's inspection is one valid JSON object, with its coordinates or bodies.
for f in "$src"/examples/scenes/*.toml; do
  json_check "$(basename "$f")" "assert d.get('coordinates') or d.get('bodies'), list(d)"
done
expect 2 "--json: describes the state at t0" -- "$bin" inspect "$src/examples/scenes/double_pendulum.toml" --json --modes

# inspect: DOF and conserved quantities.
expect 0 "DOF +4 = 6 coordinates" -- "$bin" inspect "$src/examples/scenes/double_pendulum_links.toml"
expect 0 "rank" -- "$bin" inspect "$src/examples/scenes/cartesian_double_pendulum.toml"

# Bad input: exit 2 with a one-line error naming the file, the line and the key.
cat > "$work/typo.toml" <<'TOML'
[[bodies]]
name = "ball"
mas = 1.0
TOML
expect 2 "typo.toml:3: bodies\[0\]\.mas: .*did you mean 'mass'" -- "$bin" run "$work/typo.toml" --out "$work/typo"
[ ! -e "$work/typo/report.json" ] || { echo "FAIL: a bad scene left report.json"; fails=$((fails + 1)); }
# A model parameter the model itself rejects, at its line in the file.
cat > "$work/badparam.toml" <<'TOML'
[model]
name = "simple_pendulum"
[model.parameters]
l = -1.0
TOML
expect 2 "badparam.toml:4: model.parameters.l: .*-1" -- "$bin" run "$work/badparam.toml" --out "$work/badparam"
expect 2 "cannot|No such|not found|unreadable" -- "$bin" run "$work/does_not_exist.toml"
expect 2 "--rtol" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --rtol -1 --out "$work/x"
expect 2 "--t-end" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --t-end -3 --out "$work/x"
expect 2 "did you mean 'dopri5'" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --method dopri --out "$work/x"
expect 2 "" -- "$bin" run
expect 2 "unknown subcommand 'frobnicate'; the subcommands are: run, inspect, list, solve-bvp, lyapunov, floquet, sensitivity, bench, sweep" -- "$bin" frobnicate
expect 2 "unknown subcommand 'simulate'; the subcommands are: .*" -- "$bin" simulate "$src/examples/scenes/bouncing_ball.toml"
expect 2 "unknown subcommand 'rnu'.*did you mean 'run'" -- "$bin" rnu "$src/examples/scenes/bouncing_ball.toml"
touch "$work/blocker"
# Values from the command line: the flag is named, not the scene file's line,
# and numbers are printed as given.
expect 2 "^lagrangian: command line: --out sets output.directory: cannot create" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --out "$work/blocker/sub"
expect 2 "^lagrangian: command line: --rtol sets run.rtol: must be < 1, got 2\$" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --rtol 2 --out "$work/x"
expect 2 "command line: --atol: must be a positive finite number, got -9.9999999999999998e-13" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --atol -1e-12 --out "$work/x"
expect 2 "command line: --t-end: must be finite and > t0 = 0 s, got -3" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --t-end -3 --out "$work/x"
expect 2 "command line: --rtol sets run.rtol: must be at least 1e-15 .*got 1e-30" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --rtol 1e-30 --out "$work/x"
cat > "$work/tiny_rtol.toml" <<'TOML'
[run]
t_end = 1.0
rtol = 1e-16
[model]
name = "harmonic_oscillator"
q = [0.1]
qd = [0.2]
TOML
expect 2 "tiny_rtol.toml:3: run.rtol: must be at least 1e-15" -- "$bin" run "$work/tiny_rtol.toml" --out "$work/x"

# The sanity monitor: an eccentric orbit (e = 0.9) with rk4 steps too long
# for its periapsis drifts 1.6 % in energy, more than any tolerance excuses:
# exit 3 with a warning, unless --allow-drift; dopri5 stays far below.
cat > "$work/kep_drift.toml" <<'TOML'
[run]
method = "rk4"
dt = 0.03
t_end = 6.0
output_interval = 0.05
[model]
name = "kepler"
q = [0.1, 0.0]
qd = [0.0, 4.358898943540674]
TOML
expect 3 "warning: energy drift .* exceeds 0.01" -- "$bin" run "$work/kep_drift.toml" --out "$work/kd" --no-plots
grep -q '"drift_exceeded": true' "$work/kd/report.json" || { echo "FAIL: report.json lacks drift_exceeded"; fails=$((fails + 1)); }
expect 0 "warning: energy drift" -- "$bin" run "$work/kep_drift.toml" --out "$work/kd" --no-plots --allow-drift
expect 0 "" -- "$bin" run "$work/kep_drift.toml" --out "$work/kd" --no-plots --method dopri5
grep -q '"drift_exceeded": false' "$work/kd/report.json" || { echo "FAIL: dopri5 flagged"; fails=$((fails + 1)); }

# Every monitor has the same verdict: a pendulum on a link, unstabilised
# under rk4 steps of 0.05 s, lets its rod stretch by 2 % of its length:
# exit 3 naming the constraint residual; dopri5 at its tolerance holds it.
cat > "$work/link_drift.toml" <<'TOML'
[run]
method = "rk4"
dt = 0.05
t_end = 20.0
output_interval = 0.1
stabilization = "none"
[[bodies]]
name = "bob"
mass = 1.0
position = [0.932039085967226, 0.0, -0.362357754476674]
[gravity]
[[links]]
name = "rod"
a = "bob"
anchor = [0.0, 0.0, 0.0]
length = 1.0
TOML
expect 3 "warning: constraint residual max \\|g\\| .* exceeds 0.01" -- "$bin" run "$work/link_drift.toml" --out "$work/ld" --no-plots --no-animation
grep -q '{"name": "constraint residual", "figure": [0-9.e+-]*, "exceeded": true}' "$work/ld/report.json" ||
  { echo "FAIL: report.json lacks the constraint residual's verdict"; fails=$((fails + 1)); }
expect 0 "" -- "$bin" run "$work/link_drift.toml" --out "$work/ld" --no-plots --no-animation --method dopri5

# Unbound orbits run and are checked against their closed form (universal
# variables): a hyperbolic flyby of the reduced problem, a parabolic pair.
cat > "$work/flyby.toml" <<'TOML'
[run]
t_end = 40.0
rtol = 1e-11
atol = 1e-13
[model]
name = "kepler"
q = [-20.0, 1.0]
qd = [1.2, 0.0]
TOML
expect 0 "error against the closed form: max [0-9.]+e-(09|1[0-9])" -- "$bin" run "$work/flyby.toml" --out "$work/flyby" --no-plots
cat > "$work/parabola.toml" <<'TOML'
[run]
t_end = 20.0
rtol = 1e-11
atol = 1e-13
[model]
name = "two_body"
q = [0.0, 0.0, 1.0, 0.0]
qd = [0.0, 0.0, 0.0, 2.0]
TOML
expect 0 "error against the closed form: max [0-9.]+e-(09|1[0-9])" -- "$bin" run "$work/parabola.toml" --out "$work/parabola" --no-plots

# A run that fails part-way: exit 1, no output that looks complete.
cat > "$work/short.toml" <<'TOML'
[run]
t_end = 10.0
max_steps = 3
[[bodies]]
name = "m"
mass = 1.0
position = [1.0, 0.0, 0.0]
[[springs]]
a = "m"
anchor = [0.0, 0.0, 0.0]
stiffness = 1.0
TOML
expect 0 "" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --out "$work/short" --no-plots -q
expect 1 "max_steps" -- "$bin" run "$work/short.toml" --out "$work/short"
for f in trajectory.csv events.csv report.json trajectory.csv.partial animation.html animation.html.partial; do
  [ ! -e "$work/short/$f" ] || { echo "FAIL: failed run left $f"; fails=$((fails + 1)); }
done

# bench: work-precision table, JSON and diagrams; one-line errors naming the option.
expect 0 "" -- "$bin" bench "$src/examples/scenes/kepler.toml" --t-end 6.283185307179586 \
  --methods dopri5,rk4 --tolerances 1e-4:1e-6 --dt 0.1:0.01 --repeat 2 --out "$work/bench" -q
[ -s "$work/bench/work_precision.csv" ] || { echo "FAIL: bench wrote no work_precision.csv"; fails=$((fails + 1)); }
[ -s "$work/bench/bench.json" ] || { echo "FAIL: bench wrote no bench.json"; fails=$((fails + 1)); }
grep -q '^method,adaptive,rtol,atol,dt,status,error,wall_time_s' "$work/bench/work_precision.csv" ||
  { echo "FAIL: work_precision.csv header"; fails=$((fails + 1)); }
rows=$(grep -c '^dopri5,1,\|^rk4,0,' "$work/bench/work_precision.csv")
[ "$rows" -eq 5 ] || { echo "FAIL: work_precision.csv has $rows rows, expected 5"; fails=$((fails + 1)); }
grep -q '^# machine\|machine: ' "$work/bench/work_precision.csv" || { echo "FAIL: the table does not note the machine"; fails=$((fails + 1)); }
if command -v gnuplot >/dev/null 2>&1; then
  for f in work_precision_time.png work_precision_rhs.png work_precision_time.svg bench.gp; do
    [ -s "$work/bench/$f" ] || { echo "FAIL: bench did not draw $f"; fails=$((fails + 1)); }
  done
fi
expect 0 "error: .*reference run" -- "$bin" bench "$src/examples/scenes/double_pendulum.toml" --t-end 1 \
  --methods dopri5 --tolerances 1e-4:1e-5 --repeat 1 --out "$work/bench_ref" --no-plots
# gauss_radau15 drops tolerances below 1e-11 (it runs them at 1e-11) and says so on stderr and in bench.json.
expect 0 "warning: gauss_radau15: tolerances 1e-12, 1e-13 dropped" -- "$bin" bench "$src/examples/scenes/kepler.toml" \
  --t-end 6.283185307179586 --methods gauss_radau15 --tolerances 1e-10:1e-13 --repeat 1 --out "$work/bench_radau" --no-plots -q
grep -q '"warnings": \[".*1e-12, 1e-13' "$work/bench_radau/bench.json" ||
  { echo "FAIL: bench.json does not name the dropped tolerances"; fails=$((fails + 1)); }
expect 2 "--methods: unknown stepper 'dopri'; did you mean 'dopri5'" -- "$bin" bench "$src/examples/scenes/kepler.toml" --methods dopri --out "$work/x"
expect 2 "--tolerances: 'abc' is not a number, got '1e-3:abc'" -- "$bin" bench "$src/examples/scenes/kepler.toml" --tolerances 1e-3:abc --out "$work/x"
expect 2 "--tolerances: .*loosest first.*1e-13:1e-3" -- "$bin" bench "$src/examples/scenes/kepler.toml" --tolerances 1e-13:1e-3 --out "$work/x"
expect 2 "--tolerances: .*positive" -- "$bin" bench "$src/examples/scenes/kepler.toml" --tolerances 0:-1 --out "$work/x"
expect 2 "--repeat: must be in \[1, 1000\], got 0" -- "$bin" bench "$src/examples/scenes/kepler.toml" --repeat 0 --out "$work/x"
expect 2 "--dt: .*loosest first|--dt: .*larger" -- "$bin" bench "$src/examples/scenes/kepler.toml" --dt 1e-4:1e-2 --out "$work/x"
[ "$(ls -A "$work/x" 2>/dev/null | wc -l)" -eq 0 ] || { echo "FAIL: bad bench input wrote files"; fails=$((fails + 1)); }
# A bench whose runs all fail: exit 1, no table left (not even an earlier one).
cp -r "$work/bench" "$work/bench_fail"
expect 1 "bench failed" -- "$bin" bench "$work/short.toml" --methods dopri5 --tolerances 1e-4:1e-5 --repeat 1 --out "$work/bench_fail" -q
for f in work_precision.csv bench.json work_precision.csv.partial work_precision_time.png; do
  [ ! -e "$work/bench_fail/$f" ] || { echo "FAIL: failed bench left $f"; fails=$((fails + 1)); }
done

# inspect --equilibria --modes: the double pendulum's four equilibria and its two
# normal modes, w^2 = (g/l)(2 -+ sqrt 2), w = 2.3971994 and 5.7873513 rad/s (m = l = 1).
expect 0 "#4 .*maximum" -- "$bin" inspect "$src/examples/scenes/double_pendulum.toml" --equilibria
expect 0 "this list may be incomplete \(--starts N searches from more\)" -- "$bin" inspect "$src/examples/scenes/cartesian_double_pendulum.toml" --equilibria
expect 0 "2\.39719939.*5\.78735129|2\.39719939[^$]*" -- "$bin" inspect "$src/examples/scenes/double_pendulum.toml" --modes
out=$("$bin" inspect "$src/examples/scenes/double_pendulum.toml" --equilibria --modes 2>&1)
for w in 2.39719939 5.78735129; do
  grep -q "$w" <<<"$out" || { echo "FAIL: double pendulum mode $w rad/s missing"; fails=$((fails + 1)); }
done
[ "$(grep -c '(stable)' <<<"$out")" -eq 1 ] || { echo "FAIL: expected one stable equilibrium"; fails=$((fails + 1)); }
# The bead on a hoop spun beyond sqrt(g/R): two stable equilibria at +-acos(g/(w^2 R)) = +-0.99441 rad.
expect 0 "0\.99440.*minimum \(stable\)" -- "$bin" inspect "$src/examples/scenes/bead_on_rotating_hoop.toml" --equilibria
expect 0 "not an equilibrium" -- "$bin" inspect "$src/examples/scenes/double_pendulum.toml" --modes --at-initial-state
expect 0 "degenerate|minimum" -- "$bin" inspect "$src/examples/scenes/cartesian_double_pendulum.toml" --equilibria --modes
expect 2 "--equilibria: .*particle scene" -- "$bin" inspect "$src/examples/scenes/bouncing_ball.toml" --equilibria
expect 2 "unilateral" -- "$bin" inspect "$src/examples/scenes/newtons_cradle_model.toml" --equilibria
expect 2 "--starts: must be at least 1, got 0" -- "$bin" inspect "$src/examples/scenes/double_pendulum.toml" --equilibria --starts 0
expect 2 "--at-initial-state: only with --modes" -- "$bin" inspect "$src/examples/scenes/double_pendulum.toml" --at-initial-state

# solve-bvp: the harmonic oscillator (w = 2 rad/s, half period pi/2 s).
ho="$src/examples/scenes/harmonic_oscillator.toml"
expect 0 "local minimum of the action" -- "$bin" solve-bvp "$ho" --from 0.1 --to 0.2 --time 1 --out "$work/bvp" --no-plots
[ -s "$work/bvp/bvp_path.csv" ] || { echo "FAIL: bvp_path.csv missing"; fails=$((fails + 1)); }
head -1 "$work/bvp/bvp_path.csv" | grep -q '^t \[s\],x \[m\],x_dot \[m/s\],energy \[J\]$' || { echo "FAIL: bvp_path.csv header"; fails=$((fails + 1)); }
[ "$(wc -l < "$work/bvp/bvp_path.csv")" -eq 202 ] || { echo "FAIL: bvp_path.csv should have 201 rows"; fails=$((fails + 1)); }
expect 0 "saddle point of the action.*1 negative eigenvalue" -- "$bin" solve-bvp "$ho" --from 0.1 --to 0.2 --time 0:2 --steps 100 --out "$work/bvp2" --no-plots
if command -v gnuplot >/dev/null 2>&1; then
  expect 0 "wrote:.*coordinates" -- "$bin" solve-bvp "$ho" --from 0.1 --to 0.2 --time 1 --out "$work/bvp_plot"
  [ -s "$work/bvp_plot/coordinates.png" ] || { echo "FAIL: solve-bvp drew no plot"; fails=$((fails + 1)); }
fi
# Exactly half a period: singular, exit 1, nothing left that looks complete.
expect 1 "singular" -- "$bin" solve-bvp "$ho" --from 0.1 --to 0.2 --time 1.5707963267948966 --out "$work/bvp_sing"
[ ! -e "$work/bvp_sing/bvp_path.csv" ] || { echo "FAIL: a singular problem left bvp_path.csv"; fails=$((fails + 1)); }
expect 2 "--from: 2 values given; model 'harmonic_oscillator' has 1 coordinate" -- "$bin" solve-bvp "$ho" --from 0.1,0.2 --to 0.2 --time 1 --out "$work/x"
expect 2 "--from: 'abc' is not a number" -- "$bin" solve-bvp "$ho" --from abc --to 0.2 --time 1 --out "$work/x"
expect 2 "--to: 'nan' is not finite" -- "$bin" solve-bvp "$ho" --from 0.1 --to nan --time 1 --out "$work/x"
expect 2 "--time: must be a positive duration" -- "$bin" solve-bvp "$ho" --from 0.1 --to 0.2 --time -1 --out "$work/x"
expect 2 "--time: need t0:t1 with t1 > t0" -- "$bin" solve-bvp "$ho" --from 0.1 --to 0.2 --time 2:1 --out "$work/x"
expect 2 "--steps: must be in 2 .. 100000, got 1" -- "$bin" solve-bvp "$ho" --from 0.1 --to 0.2 --time 1 --steps 1 --out "$work/x"
expect 2 "solve-bvp: .*particle scene" -- "$bin" solve-bvp "$src/examples/scenes/bouncing_ball.toml" --from 0 --to 1 --time 1 --out "$work/x"

# lyapunov: the oscillator (w = 2 rad/s) has zero exponents and MEGNO -> 0;
# the double pendulum from 2 rad, 2 rad (set on the command line) is chaotic,
# from the scene's 1 rad, 0.5 rad it is not; Hamiltonian spectra sum to 0.
analysis_json() {  # analysis_json SUBCOMMAND NAME PYTHON-CONDITION -- its arguments...
  local sub=$1 name=$2 cond=$3
  shift 4
  if "$bin" "$sub" "$@" --json > "$work/$name.json" 2> "$work/$name.err" &&
    /usr/bin/python3 -c "import json, sys; d = json.load(open(sys.argv[1])); sys.exit(0 if ($cond) else 1)" \
      "$work/$name.json"; then
    echo "ok: $sub $name: $cond"
  else
    echo "FAIL: $sub $name: $cond"; cat "$work/$name.json" "$work/$name.err" | head -20; fails=$((fails + 1))
  fi
}
analysis_json lyapunov ho "len(d['spectrum']) == 2 and all(abs(l) < 1e-2 for l in d['spectrum']) and abs(d['sum']) < 1e-8 and abs(d['megno']) < 0.05" -- "$ho" --t-end 300
dp="$src/examples/scenes/double_pendulum.toml"
analysis_json lyapunov dp_chaos "len(d['spectrum']) == 4 and d['spectrum'][0] > 0.5 and abs(d['sum']) < 1e-8 and d['megno'] > 5 and d['t_end'] == 25" -- "$dp" --set 'model.q[0]=2' --set 'model.q[1]=2' --t-end 25
analysis_json lyapunov dp_largest "len(d['spectrum']) == 1 and d['spectrum'][0] > 0.5 and d['method'] == 'fehlberg78'" -- "$dp" --set 'model.q[0]=2' --set 'model.q[1]=2' --t-end 25 --exponents 1 --method fehlberg78
analysis_json lyapunov dp_calm "d['spectrum'][0] < 0.1 and d['megno'] < 3" -- "$dp" --t-end 100
expect 0 "MEGNO <Y> = " -- "$bin" lyapunov "$ho" --t-end 10
# The bouncing ball's floor (e = 0.8) over 3 s: 6 impacts, each taking
# 2 ln e from the sum of the exponents (det S = e^2): sum = 12 ln 0.8 / 3 1/s.
analysis_json lyapunov ball "d['model'] == 'particles' and len(d['spectrum']) == 6 and abs(d['sum'] - (-0.8925742052568388)) < 1e-6" -- "$src/examples/scenes/bouncing_ball.toml" --t-end 3
# Over its whole 5 s it comes to rest at 4.06 s and rolls on along x: the
# four exponents of the free flight along x and y are 0 (their canonical
# start vectors keep length 1), the rest removes z's two (null: -inf, and
# the sum), JSON null.
analysis_json lyapunov ball_rest "d['rests'] == 1 and d['releases'] == 0 and d['impacts'] == 62 and all(abs(l) < 1e-12 for l in d['spectrum'][:4]) and d['spectrum'][4:] == [None, None] and d['sum'] is None" -- "$src/examples/scenes/bouncing_ball.toml"
expect 0 "lambda_6 = -inf" -- "$bin" lyapunov "$src/examples/scenes/bouncing_ball.toml"
# Newton's cradle starts with its spheres touching at rest: no derivative
# of the flow there (a neighbouring start pushes them apart or together).
expect 1 "lyapunov failed at t = 0 s: tangent flow: contact 'b4-b5' touches slower than contact_touch_speed" -- "$bin" lyapunov "$src/examples/scenes/newtons_cradle.toml"
# A gas on the event-driven engine (scene/hard_spheres_tangent.hpp): its 1000
# spheres' whole spectrum (6000 exponents) is more than the run carries; its
# three largest are positive, tens of thousands of impacts crossed.
gas="$src/examples/scenes/gas_in_container.toml"
expect 2 "lyapunov: all 6000 exponents asked of a gas of 1000 spheres; its tangent run carries at most 600 vectors .*--exponents K" -- "$bin" lyapunov "$gas"
analysis_json lyapunov gas "d['model'] == 'gas' and len(d['spectrum']) == 3 and d['spectrum'][2] > 1000 and d['impacts'] > 10000 and d['evaluations'] == 0" -- "$gas" --exponents 3
expect 0 "events of the event-driven engine" -- "$bin" lyapunov "$gas" --exponents 1
# A particle scene's bodies under their forces: the binary star's circular
# orbits, 12 exponents of a Hamiltonian flow (sum 0, MEGNO near 2: Kepler shear).
binary="$src/examples/scenes/binary_star.toml"
analysis_json lyapunov binary "d['model'] == 'particles' and len(d['spectrum']) == 12 and abs(d['sum']) < 1e-9 and abs(d['megno'] - 2) < 0.2" -- "$binary"
# Bodies held by links: the double pendulum on two links (3-D, 2 rows) has
# 8 exponents on its manifold, summing to 0, the largest positive (chaotic).
analysis_json lyapunov links "d['model'] == 'particles' and len(d['spectrum']) == 8 and abs(d['sum']) < 1e-8 and d['spectrum'][0] > 0.5" -- "$src/examples/scenes/double_pendulum_links.toml"
# A model with a holonomic constraint: the Atwood machine (3 kg, 1 kg) moves
# on a 2-dimensional manifold, tangent vectors (a, -a, b, -b) in (y1, y2,
# y1', y2') with a(t) = a0 + b0 t. Its reduced canonical coordinates
# (U^T dq, U^T dp), U = (1, -1)/sqrt 2, are A = sqrt 2 a and
# B = (m1 + m2) b / sqrt 2, in which the flow over T = 2 s is the shear
# [[1, s], [0, 1]], s = 2 T / (m1 + m2) = 1: the two exponents sum to 0 and
# the first is at most ln(sigma_max) / T, sigma_max = (1 + sqrt 5) / 2.
# (The lighter mass passes the pulley at 0.64 s: the exponents are those of
# the equations of motion, which go on; a plain run stops there.)
atwood="$src/examples/scenes/atwood_machine.toml"
analysis_json lyapunov atwood "len(d['spectrum']) == 2 and abs(d['sum']) < 1e-9 and 0 < d['spectrum'][0] <= __import__('math').log((1 + 5 ** 0.5) / 2) / 2 + 1e-9" -- "$atwood"
# A model with contacts: the ball (e = 0.5, from 1 m) bounces at 0.45 s and
# 0.90 s within 1 s, each bounce multiplying phase volume by det S = e^2:
# the six exponents sum to 4 ln 0.5 = -2.7725887 1/s. Over the scene's 3 s
# it comes to rest (at 1.35 s), held shut as the plain run holds it, and
# slides on along x: the rest removes z's two directions (null, and the
# sum), the four of the slide along x and y are 0.
ball="$src/examples/scenes/ball_and_plane.toml"
analysis_json lyapunov ball "len(d['spectrum']) == 6 and d['impacts'] == 2 and abs(d['sum'] + 2.772588722239781) < 1e-6" -- "$ball" --t-end 1
analysis_json lyapunov ball_rest_model "d['rests'] == 1 and d['releases'] == 0 and d['impacts'] > 10 and all(abs(l) < 1e-9 for l in d['spectrum'][:4]) and d['spectrum'][4:] == [None, None] and d['sum'] is None" -- "$ball"
# A model stated as text with a contact (the projectile on a 30-degree
# incline, e = 0.5): bounces at 1.18 s and 1.77 s within 2 s, the four
# exponents summing to 2 ln 0.5 per bounce over 2 s.
analysis_json lyapunov text_incline "d['impacts'] == 2 and abs(d['sum'] - 2 * d['impacts'] * __import__('math').log(0.5) / d['t_end']) < 1e-6" -- "$src/examples/scenes/text/projectile_on_incline.toml" --t-end 2
# Over its whole 3 s its bounces accumulate, the Zeno rule rests it on the
# incline at 2.35 s and it slides down: the rest removes two of the four
# directions (null), the other two are the slide's.
analysis_json lyapunov text_incline_rest "d['rests'] == 1 and d['spectrum'][2:] == [None, None] and all(l is not None for l in d['spectrum'][:2])" -- "$src/examples/scenes/text/projectile_on_incline.toml"
# A disc (1 kg, r = 0.1 m) stated as text, at rest on the floor by 2.87 s
# (e = 0.8), slides into a wall leaning back, gap 1.9 - x + 0.3 (y - 0.1):
# the wall's law alone, e = 0.8, lifts it off the floor (released, as a
# plain run releases it) and it comes to rest again. Along x the flow over
# 5.5 s is [[c, c t], [0, c]], c = 1 - 1.8/1.09: the two finite exponents
# sum to 2 ln|c| / 5.5; y's two are removed (null). Leaning the other way
# the wall's impulse presses the disc into the floor (impacts in sequence
# at one instant): exit 1, naming both contacts.
cat > "$work/disc_and_wall.toml" <<'TOML'
name = "disc against a leaning wall (text)"
[run]
t_end = 5.5
rtol = 1e-11
atol = 1e-13
[model]
coordinates = ["x", "y"]
units = ["m", "m"]
kinetic = "0.5*m*(x_dot^2 + y_dot^2)"
potential = "m*g*y"
q = [0.5, 0.6]
qd = [0.3, 0.0]
[[model.contacts]]
name = "floor"
gap = "y - 0.1"
restitution = 0.8
unit = "m"
[[model.contacts]]
name = "wall"
gap = "1.9 - x + lean*(y - 0.1)"
restitution = 0.8
unit = "m"
[model.parameters]
m = 1.0
g = 9.81
lean = 0.3
TOML
analysis_json lyapunov text_lifted "d['rests'] == 2 and d['releases'] == 1 and d['spectrum'][2:] == [None, None] and abs(d['spectrum'][0] + d['spectrum'][1] - 2 * __import__('math').log(1.8 / 1.09 - 1) / 5.5) < 1e-8" -- "$work/disc_and_wall.toml"
expect 1 "tangent flow: the impulse of contact 'wall' sets resting contact 'floor' moving" -- "$bin" lyapunov "$work/disc_and_wall.toml" --set model.parameters.lean=-0.3
# The elastic bounce from its apex 1 m up is periodic, T = 2 sqrt(2/9.81) s:
# a closed orbit, every multiplier 1 (a double one per plane: to ~1e-6;
# without the saltation matrix's correction one would be -1).
analysis_json floquet ball_elastic "d['impacts'] == 1 and d['closure'] < 1e-8 and len(d['multipliers']) == 6 and all(abs(complex(*m) - 1) < 1e-3 for m in d['multipliers'])" -- "$ball" --set model.parameters.e=1 --set 'model.qd[0]=0' --period 0.9030472819714618 --rtol 1e-12
# A model stated as text: the double pendulum's spectrum is the built-in
# model's (over 10 s rounding grows by e^(1.5 * 10): the two runs agree to
# about 1e-9); constraints are refused as for a built-in model.
tdp="$src/examples/scenes/text/double_pendulum.toml"
analysis_json lyapunov dp_ten "len(d['spectrum']) == 4" -- "$dp" --set 'model.q[0]=2' --set 'model.q[1]=2' --t-end 10
analysis_json lyapunov text_dp "len(d['spectrum']) == 4 and d['spectrum'][0] > 0.5 and abs(d['sum']) < 1e-8 and all(abs(a - b) < 1e-6 for a, b in zip(d['spectrum'], json.load(open('$work/dp_ten.json'))['spectrum'])) and abs(d['megno'] - json.load(open('$work/dp_ten.json'))['megno']) < 1e-6" -- "$tdp" --t-end 10 --rtol 1e-10 --atol 1e-12 --method dopri5
analysis_json lyapunov sph "len(d['spectrum']) == 4" -- "$src/examples/scenes/spherical_pendulum.toml" --t-end 5
analysis_json lyapunov text_sph "len(d['spectrum']) == 4 and all(abs(a - b) < 1e-6 for a, b in zip(d['spectrum'], json.load(open('$work/sph.json'))['spectrum'])) and abs(d['sum']) < 1e-8" -- "$src/examples/scenes/text/spherical_pendulum.toml" --t-end 5 --rtol 1e-10 --atol 1e-12 --method dopri5
# The Atwood machine stated as text (y1 + y2 = c, from rest) on its manifold:
# the built-in model's exponents over the same 2 s, at the same tolerances.
analysis_json lyapunov text_atwood "len(d['spectrum']) == 2 and abs(d['sum']) < 1e-9 and all(abs(a - b) < 1e-9 for a, b in zip(d['spectrum'], json.load(open('$work/atwood.json'))['spectrum']))" -- "$src/examples/scenes/text/atwood_machine.toml" --t-end 2 --method dopri5
# A rod and a wall (e = 0.5) stated as text: each impact multiplies phase
# volume by e^2 (docs/analysis.md), so the two exponents sum to
# 2 ln e * impacts / t_end.
cat > "$work/text_held.toml" <<'TOML'
[model]
coordinates = ["x", "y"]
kinetic = "0.5*(x_dot^2 + y_dot^2)"
potential = "9.81*y"
holonomic = ["x^2 + y^2 - 1"]
q = [0.0, -1.0]
qd = [2.0, 0.0]
[[model.contacts]]
name = "wall"
gap = "0.5 - x"
restitution = 0.5
TOML
analysis_json lyapunov text_rod_wall "len(d['spectrum']) == 2 and d['impacts'] >= 2 and abs(d['sum'] - 2 * __import__('math').log(0.5) * d['impacts'] / d['t_end']) < 1e-6" -- "$work/text_held.toml" --t-end 4
# The same rod as bodies: a bob on a link against a contact plane, its
# four exponents (a spherical pendulum's manifold) summing to 2 ln e per impact.
cat > "$work/bob_wall.toml" <<'TOML'
name = "bob against a wall"
[[bodies]]
name = "bob"
mass = 1.0
radius = 0.05
position = [0.0, 0.0, -1.0]
velocity = [2.0, 0.0, 0.0]
[gravity]
[[links]]
a = "bob"
anchor = [0.0, 0.0, 0.0]
[[contacts.planes]]
point = [0.55, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
restitution = 0.5
TOML
analysis_json lyapunov bob_wall "d['model'] == 'particles' and len(d['spectrum']) == 4 and d['impacts'] == json.load(open('$work/text_rod_wall.json'))['impacts'] and abs(d['sum'] - 2 * __import__('math').log(0.5) * d['impacts'] / d['t_end']) < 1e-6" -- "$work/bob_wall.toml" --t-end 4
expect 2 "exponents = 9 is outside \\[0, 4\\]" -- "$bin" lyapunov "$dp" --exponents 9
expect 2 "--exponents: must be at least 1" -- "$bin" lyapunov "$dp" --exponents -1
expect 2 "--interval: must be a finite time" -- "$bin" lyapunov "$dp" --interval -2
expect 2 "method 'velocity_verlet'" -- "$bin" lyapunov "$ho" --method velocity_verlet
expect 2 "--method: unknown stepper 'dopri'; did you mean 'dopri5'" -- "$bin" lyapunov "$ho" --method dopri

# floquet: Kapitza's pendulum upright (a = 0.05 m, l = 1 m) is stable at
# Omega = 200 rad/s (a^2 Omega^2 = 100 > 2 g l = 19.62) and not at 60 (9).
kap="$src/examples/scenes/driven_pendulum.toml"
analysis_json floquet kapitza_fast "d['stable'] and len(d['multipliers']) == 2 and all(abs(abs(complex(*m)) - 1) < 1e-6 for m in d['multipliers']) and d['closure'] < 1e-12" -- "$kap" --set 'model.q[0]=3.141592653589793' --period 0.031415926535897934
analysis_json floquet kapitza_slow "not d['stable'] and d['largest_modulus'] > 1.2" -- "$kap" --set 'model.q[0]=3.141592653589793' --set model.parameters.Omega=60 --period 0.10471975511965977
# Kapitza's pendulum stated as text (T and V depend on t): the same verdicts.
tkap="$src/examples/scenes/text/driven_pendulum.toml"
# A text model has the parameters its file declares: a new name is a typo, not a setting.
expect 2 "--set model.parameters.Omga: the model stated as text has no parameter 'Omga'.*Omega" -- "$bin" floquet "$tkap" --set model.parameters.Omga=60 --period 0.1
expect 2 "--vary model.parameters.Omga: the model stated as text has no parameter 'Omga'" -- "$bin" sweep "$tkap" --vary model.parameters.Omga=50:60:2 --out "$work/omga"
analysis_json floquet text_kapitza_fast "d['stable'] and len(d['multipliers']) == 2 and all(abs(abs(complex(*m)) - 1) < 1e-6 for m in d['multipliers']) and d['closure'] < 1e-12" -- "$tkap" --set 'model.q[0]=3.141592653589793' --period 0.031415926535897934
analysis_json floquet text_kapitza_slow "not d['stable'] and d['largest_modulus'] > 1.2" -- "$tkap" --set 'model.q[0]=3.141592653589793' --set model.parameters.Omega=60 --period 0.10471975511965977
expect 0 "^stable: largest \\|mu\\| = 1 <= 1 \\+ 1e-06" -- "$bin" floquet "$kap" --set 'model.q[0]=3.141592653589793' --period 0.031415926535897934 --rtol 1e-11
expect 2 "floquet: --period T \\(s\\) is required" -- "$bin" floquet "$kap"
expect 2 "--period: must be a finite time > 0 s, got -1" -- "$bin" floquet "$kap" --period -1
expect 2 "--tolerance: must be finite and >= 0" -- "$bin" floquet "$kap" --period 1 --tolerance -1
expect 2 "floquet: particle scene 'gas in a container': the Floquet multipliers of a gas are not derived \\(its motion has no period\\)" -- "$bin" floquet "$src/examples/scenes/gas_in_container.toml" --period 1
# One period of the binary star's circular orbits (2 pi sqrt(d^3 / G(m1 + m2)), d = 2):
# every multiplier 1.
analysis_json floquet binary_floquet "len(d['multipliers']) == 12 and all(abs(complex(*m) - 1) < 1e-5 for m in d['multipliers']) and d['stable']" -- "$binary" --period 8.885765876316732
# On a constraint manifold: the Atwood machine's uniform acceleration is a
# shear on its 2-dimensional manifold, both multipliers 1 (a Jordan block:
# trace 2 and det 1 of the 2 x 2 monodromy); it has no periodic orbit for --find-orbit to find.
analysis_json floquet atwood_floquet "len(d['multipliers']) == 2 and all(abs(complex(*m) - 1) < 1e-4 for m in d['multipliers'])" -- "$atwood" --period 1
expect 1 "floquet: no periodic orbit found" -- "$bin" floquet "$atwood" --period 1 --find-orbit
# sensitivity: the harmonic oscillator (m = 1 kg, k = 4 N/m: w = 2 rad/s) at t = 1 s has the state
# transition matrix [[cos w t, sin w t / w], [-w sin w t, cos w t]]; the projectile's column of g is
# (0, -t^2/2, 0, -t); the double pendulum stated as text and the built-in one from the same start give
# the same column of m1 (two derivations of one model).
analysis_json sensitivity ho_phi "(lambda m, c, s: d['model'] == 'harmonic_oscillator' and len(sum(d['state_transition'], [])) == 4 and all(abs(a - b) < 1e-8 for a, b in zip(sum(d['state_transition'], []), [c, s / 2, -2 * s, c])))(__import__('math'), __import__('math').cos(2.0), __import__('math').sin(2.0))" -- "$ho" --t-end 1
analysis_json sensitivity projectile_g "len(d['parameters']['g']) == 4 and 'state_transition' not in d and all(abs(a - b) < 1e-9 for a, b in zip(d['parameters']['g'], [0, -0.5, 0, -1]))" -- "$src/examples/scenes/projectile.toml" --t-end 1 --parameter g --parameters-only
# The ball dropped 1 m onto the floor (e = 0.5) bounces at t1 = sqrt(2/g) with speed v1 = g t1; at
# t = 0.8 s its column of e is (0, 0, v1 (t - t1), 0, 0, v1): the parameter's column crosses the impact.
analysis_json sensitivity ball_e "(lambda t1: all(abs(a - b) < 1e-7 for a, b in zip(d['parameters']['e'], [0, 0, 9.81 * t1 * (0.8 - t1), 0, 0, 9.81 * t1])) and len(d['parameters']['e']) == 6 and d['impacts'] == 1)((2 / 9.81) ** 0.5)" -- "$src/examples/scenes/ball_and_plane.toml" --t-end 0.8 --parameter e --parameters-only
# The same scene to its end (3 s): the bounces accumulate and the ball rests on the floor from
# 1.35 s, sliding on at 0.3 m/s. At rest z = R + offset and z_dot = 0 whatever e and g, so the
# columns through the rest are (0, 0, 1, 0, 0, 0) for the offset and 0 for e and g.
analysis_json sensitivity ball_rest_columns "d['impacts'] > 10 and all(abs(a - b) < 1e-7 for a, b in zip(d['parameters']['offset'], [0, 0, 1, 0, 0, 0])) and all(abs(a) < 1e-7 for a in d['parameters']['e'] + d['parameters']['g']) and len(d['parameters']['g']) == 6" -- "$src/examples/scenes/ball_and_plane.toml" --parameter offset --parameter e --parameter g --parameters-only
# A circular orbit of kepler_polar (r = a = 1 m, k/m = 1: w = 1 rad/s) over half a turn: along k
# dr = -(a/k)(1 - cos wt) = -2, dphi = (2/k)(wt - sin wt) = 2 pi, dr_dot = 0, dphi_dot = (2w/k)(1 - cos wt) = 4.
analysis_json sensitivity polar_k "len(d['parameters']['k']) == 4 and all(abs(a - b) < 1e-7 for a, b in zip(d['parameters']['k'], [-2, 2 * __import__('math').pi, 0, 4]))" -- "$src/examples/scenes/kepler_polar.toml" --set 'model.q[0]=1' --set 'model.qd[1]=1' --t-end 3.141592653589793 --parameter k --parameters-only
if "$bin" sensitivity "$src/examples/scenes/text/double_pendulum.toml" --t-end 1 --parameter m1 --parameters-only --json > "$work/dp_text_m1.json" &&
  "$bin" sensitivity "$src/examples/scenes/double_pendulum.toml" --set 'model.q[0]=2' --set 'model.q[1]=2' --t-end 1 \
    --parameter m1 --parameters-only --json > "$work/dp_m1.json" &&
  /usr/bin/python3 -c "import json, sys; a, b = (json.load(open(f))['parameters']['m1'] for f in sys.argv[1:]); sys.exit(0 if len(a) == 4 and max(abs(x - y) for x, y in zip(a, b)) < 1e-8 * max(map(abs, b)) and 'state_transition' not in json.load(open(sys.argv[1])) else 1)" \
    "$work/dp_text_m1.json" "$work/dp_m1.json"; then
  echo "ok: sensitivity: the text double pendulum's column of m1 is the built-in model's"
else
  echo "FAIL: sensitivity: the text and built-in double pendulums' columns of m1"; cat "$work/dp_text_m1.json" "$work/dp_m1.json"; fails=$((fails + 1))
fi
# Bodies on a link: the state transition of the 6 Cartesian coordinates is Phi P0 on the link's manifold,
# so a start moved along the link (r0 = (sin 1.2, 0, -cos 1.2), the anchor at the origin) maps to 0.
analysis_json sensitivity link_phi "d['model'] == 'particles' and len(d['state_transition']) == 6 and all(len(r) == 6 for r in d['state_transition']) and max(abs(r[0] * 0.932039085967226 - r[2] * 0.362357754476674) for r in d['state_transition']) < 1e-9 and max(max(map(abs, r)) for r in d['state_transition']) > 0.1" -- "$src/examples/scenes/link_pendulum.toml" --t-end 1
expect 2 "'m' is not a parameter of the model \\(bodies\\[0\\].mass, gravity.g\\[0\\], gravity.g\\[1\\], gravity.g\\[2\\], links\\[0\\].length\\)" -- "$bin" sensitivity "$src/examples/scenes/link_pendulum.toml" --parameter m
# A particle scene's parameters by their scene keys: the bouncing ball (dropped from h = 1 m above
# its contact, e = 0.8) at 0.6 s, after its first impact at t1 = sqrt(2h/g) at v1 = g t1: the column
# of the floor's e is v1 (t - t1) in z and v1 in its velocity; that of g_z in z is t (t - (1 + e) t1) / 2.
analysis_json sensitivity ball_scene_e "(lambda t1: d['model'] == 'particles' and d['impacts'] == 1 and all(abs(a - b) < 1e-7 for a, b in zip(d['parameters']['contacts.planes[0].restitution'], [0, 0, 9.81 * t1 * (0.6 - t1), 0, 0, 9.81 * t1])) and abs(d['parameters']['gravity.g[2]'][2] - 0.5 * 0.6 * (0.6 - 1.8 * t1)) < 1e-7)((2 / 9.81) ** 0.5)" -- "$src/examples/scenes/bouncing_ball.toml" --t-end 0.6 --parameter 'contacts.planes[0].restitution' --parameter 'gravity.g[2]' --parameters-only
# pendulum_chain_3 sets one m and one l for its three links: the scene's m has the sum of the links'
# columns (m1, m2, m3), zero from rest (only g/l sets the motion there: q(t) = Theta(t sqrt(g/l))), and
# along g the angles move by t qdot / (2 g), here at t = 1 s; a link's own name is not the scene's.
analysis_json sensitivity chain_m_g "len(d['parameters']['m']) == 6 and max(map(abs, d['parameters']['m'])) < 1e-8 and max(map(abs, d['parameters']['g'])) > 0.1 and all(abs(a - 1.0 * b / (2 * 9.81)) < 1e-7 for a, b in zip(d['parameters']['g'][:3], d['state'][3:]))" -- "$src/examples/scenes/pendulum_chain_3.toml" --t-end 1 --parameter m --parameter g --parameters-only
expect 2 "'m1' is not a parameter of the model \\(m, l, g\\)" -- "$bin" sensitivity "$src/examples/scenes/pendulum_chain_3.toml" --parameter m1
# The same circular orbit in Cartesian coordinates (kepler: k sits in its potential) at t = pi, phi = pi:
# x = r cos phi, y = r sin phi and their rates differentiated: (2, -2 pi, 2 pi, -2).
analysis_json sensitivity kepler_k "len(d['parameters']['k']) == 4 and all(abs(a - b) < 1e-7 for a, b in zip(d['parameters']['k'], [2, -2 * __import__('math').pi, 2 * __import__('math').pi, -2]))" -- "$src/examples/scenes/kepler.toml" --set model.parameters.mu=1 --set model.parameters.k=1 --set 'model.q[0]=1' --set 'model.q[1]=0' --set 'model.qd[0]=0' --set 'model.qd[1]=1' --t-end 3.141592653589793 --parameter k --parameters-only
expect 2 "'gee' is not a parameter of the model \\(m, g, beta\\)" -- "$bin" sensitivity "$src/examples/scenes/projectile.toml" --parameter gee
expect 2 "--parameters-only needs at least one --parameter NAME" -- "$bin" sensitivity "$src/examples/scenes/projectile.toml" --parameters-only
# floquet --find-orbit: from the pendulum's state at 0.5 rad and a guess of 2.2 s (8 % long) Newton finds an
# orbit of the family near it, whose period is 4 K(k) / w0 at its own energy, k^2 = (qd/2w0)^2 + sin^2(q/2),
# w0 = sqrt(g/l) (K by the arithmetic-geometric mean); its multipliers are 1.
sp="$src/examples/scenes/simple_pendulum.toml"
period_of_orbit="(lambda w0: (lambda k: abs(d['period'] - 4 * (__import__('math').pi / (2 * __import__('functools').reduce(lambda p, _: ((p[0] + p[1]) / 2, (p[0] * p[1]) ** 0.5), range(40), (1.0, (1 - k * k) ** 0.5))[0])) / w0) < 1e-9 * d['period'])(((d['qd'][0] / (2 * w0)) ** 2 + __import__('math').sin(d['q'][0] / 2) ** 2) ** 0.5))(9.81 ** 0.5)"
analysis_json floquet pendulum_orbit "$period_of_orbit and d['iterations'] >= 2 and d['stable'] and abs(d['q'][0] - 0.5) < 1e-3 and abs(d['period'] - 2.0378679151581687) < 1e-4 and d['closure'] < 1e-7" -- "$sp" --find-orbit --period 2.2 --rtol 1e-12
# Kapitza's pendulum from 3.1 rad: the drive's period fixed, Newton finds the upright rest (pi).
analysis_json floquet kapitza_orbit "abs(d['q'][0] - 3.141592653589793) < 1e-8 and abs(d['qd'][0]) < 1e-6 and d['stable'] and d['period'] == 0.031415926535897934" -- "$kap" --set 'model.q[0]=3.1' --period 0.031415926535897934 --find-orbit --fixed-period --rtol 1e-12
expect 0 "^periodic orbit of simple_pendulum found in [0-9]+ Newton iterations: T = 2.0378" -- "$bin" floquet "$sp" --find-orbit --period 2.2 --rtol 1e-12
# Spinning at 100 rad/s the pendulum rotates: no orbit in (q, qd); Newton's period runs off towards 0.
expect 1 "floquet failed: floquet: no periodic orbit found: the period's Newton iterate went to .* outside \\[T/2, 2T\\]" -- "$bin" floquet "$sp" --find-orbit --period 2.2 --set 'model.qd[0]=100'
expect 2 "floquet: --fixed-period and --any-energy go with --find-orbit" -- "$bin" floquet "$sp" --period 2 --fixed-period
expect 2 "declares constraints" -- "$bin" solve-bvp "$src/examples/scenes/cartesian_double_pendulum.toml" --from 0,-1,0,-2 --to 0.1,-1,0.1,-2 --time 1 --out "$work/x"
expect 2 "dissipation" -- "$bin" solve-bvp "$src/examples/scenes/projectile_linear_drag.toml" --from 0,0 --to 10,0 --time 1 --out "$work/x"
[ ! -e "$work/x/bvp_path.csv" ] || { echo "FAIL: bad solve-bvp input wrote bvp_path.csv"; fails=$((fails + 1)); }

# The energy figure users quote is relative to the initial energy: report.json's
# energy_drift_relative_to_initial is |h(t_end) - h0| / |h0| of trajectory.csv's first and last
# rows, computed here in exact rational arithmetic (within a factor 2: h is evaluated in double).
expect 0 "drift \|E - E0\|/\|E0\| max" -- "$bin" run "$src/examples/scenes/kepler.toml" --set model.qd[1]=1.9 --rtol 1e-8 --atol 1e-10 --out "$work/kepler_drift" --no-plots --no-animation
/usr/bin/python3 - "$work/kepler_drift" <<'PY' || { echo "FAIL: report.json's relative energy drift against the CSV"; fails=$((fails + 1)); }
import csv, json, sys
from fractions import Fraction
d = sys.argv[1]
rows = list(csv.DictReader(open(d + "/trajectory.csv")))
e0, e1 = Fraction(rows[0]["energy [J]"]), Fraction(rows[-1]["energy [J]"])
exact = abs(e1 - e0) / abs(e0)
report = json.load(open(d + "/report.json"))["report"]
got = report["energy_drift_relative_to_initial"]
assert exact > 0, exact
assert float(exact) / 2 <= got <= 2 * float(exact), (got, float(exact))
# and not the figure relative to the energy scale, which reads smaller for this orbit (e ~ 0.44)
assert report["energy_drift_final"] < got / 1.5, (report["energy_drift_final"], got)
PY

# Built-in models state their domain: the Atwood machine stops where the light mass reaches the pulley
# (t = sqrt(2 d / a) = 0.63855 s, a = g (m1 - m2)/(m1 + m2) = 4.905 m/s^2, d = 1 m), naming the edge; a start
# beyond an edge is bad input naming the key.
expect 0 "stopped by event mass2_at_pulley at t = 0.63855" -- "$bin" run "$src/examples/scenes/atwood_machine.toml" --out "$work/atwood" --no-plots --no-animation
grep -q '"stopped_by": "mass2_at_pulley"' "$work/atwood/report.json" || { echo "FAIL: atwood report.json stopped_by"; fails=$((fails + 1)); }
head -1 "$work/atwood/trajectory.csv" | grep -q ',lambda_string \[N\],Qc_y1 \[N\],Qc_y2 \[N\]$' || { echo "FAIL: atwood multiplier column unit"; head -1 "$work/atwood/trajectory.csv"; fails=$((fails + 1)); }
expect 2 "model.q.*beyond the edge 'mass1_at_pulley'" -- "$bin" run "$src/examples/scenes/atwood_machine.toml" --set 'model.q[0]=1.5' --set 'model.q[1]=-1.5' --out "$work/x" --no-plots
expect 0 "stopped by event bead_at_wire_end at t = 1.4966" -- "$bin" run "$src/examples/scenes/bead_on_rotating_wire.toml" --out "$work/wire" --no-plots --no-animation
expect 0 "" -- "$bin" run "$src/examples/scenes/oblique_impact.toml" --out "$work/oblique" --no-plots --no-animation
head -1 "$work/oblique/trajectory.csv" | grep -q ',lambda_s1-s2 \[N\],' || { echo "FAIL: oblique impact multiplier column unit"; head -1 "$work/oblique/trajectory.csv"; fails=$((fails + 1)); }
# A singular start is bad input naming the keys: r = 0 of the Kepler problem, two bodies at one place.
expect 2 "model.q.*singularity of the model: the potential energy V = -inf" -- "$bin" run "$src/examples/scenes/kepler.toml" --set 'model.q[0]=0' --out "$work/x" --no-plots
sed 's/^position = \[1.5, 0.0, 0.0\]/position = [-0.5, 0.0, 0.0]/' "$src/examples/scenes/binary_star.toml" > "$work/together.toml"
expect 2 "bodies\[1\].position.*'primary' \(bodies\[0\].position\) and 'secondary' are both at" -- "$bin" run "$work/together.toml" --out "$work/x" --no-plots
# One notation for units: inspect of a particle scene and of a model, and the summary.
out=$("$bin" inspect "$src/examples/scenes/bouncing_ball.toml" 2>&1)
grep -q 'kg\*m/s' <<<"$out" && ! grep -q 'kg·m' <<<"$out" || { echo "FAIL: inspect's momentum unit"; fails=$((fails + 1)); }
# The bouncing ball's rest: only the digits the Zeno cut-off leaves known, and the cut-off said.
expect 0 "rest ball-floor at t = 4\.0637[0-9]{0,3} s \(the Zeno rule ended the bounces there; those it cut off would take about" -- "$bin" run "$src/examples/scenes/bouncing_ball.toml" --out "$work/ball_rest" --no-plots --no-animation
# wrote: names every file the same way: relative to the working directory when inside it.
out=$(cd "$work" && "$bin" run "$src/examples/scenes/bouncing_ball.toml" --out ball_rel --no-plots --animate-to "$work/ball_rel.gif" --animate-seconds 1 2>&1)
wrote=$(grep '^wrote:' <<<"$out")
if [ -z "$wrote" ] || grep -qE ' /' <<<"$wrote" || ! grep -q ' ball_rel.gif' <<<"$wrote"; then
  echo "FAIL: wrote: mixes absolute and relative paths: $wrote"; fails=$((fails + 1))
fi

if [ "$fails" -ne 0 ]; then
  echo "$fails CLI check(s) failed"
  exit 1
fi
echo "all CLI checks passed"
