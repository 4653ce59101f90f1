#!/usr/bin/python3
"""From a Lagrangian typed as text to a first trajectory: lagrangian's text
model against SymPy + SciPy, in one run on one machine.

The system is the chaotic double pendulum of
bench/scenes/double_pendulum_chaotic.toml (m1 = m2 = 1 kg, l1 = l2 = 1 m,
g = 9.81 m/s^2, released at rest from theta1 = theta2 = 2 rad), stated on
both sides by the same strings for T and V. Each side goes from the text to
the state at t = 5 s (or 20 s, --t-end):
  * lagrangian: `lagrangian run` on a scene with those strings (a new
    process: reading, parsing, integrating, writing trajectory.csv and
    report.json; no plots, no page), fehlberg78 (eighth order, as DOP853) at
    rtol = atol = 1e-10 unless --method/--tol say otherwise;
  * SymPy + SciPy: parse_expr of the strings, LagrangesMethod,
    form_lagranges_equations, rhs (M q'' = f solved), lambdify with `math`,
    solve_ivp with DOP853 at rtol = atol = 1e-10 (inside one Python process
    with SymPy already imported, which favours this side).
The error measure is the same on both: max_i |theta_i(5) - theta_i,ref(5)|
against the 36-digit reference of bench/reference/double_pendulum.txt.
Each side runs --repeat times (median wall time).

--t-end 20 compares at t = 20 s (the reference's other time), where the
chaos has amplified every error; --scipy-tol sets SciPy's tolerance, to
compare the two at equal error.

Usage: /usr/bin/python3 bench/peers/text_to_trajectory.py build/bin/lagrangian [--repeat 5]
           [--method fehlberg78] [--tol 1e-10] [--t-end 5|20] [--scipy-tol 1e-10]
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import sympy as sp
from scipy.integrate import solve_ivp
from sympy.parsing.sympy_parser import parse_expr
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

KINETIC = "0.5*(m1 + m2)*l1**2*th1_dot**2 + 0.5*m2*l2**2*th2_dot**2 + m2*l1*l2*th1_dot*th2_dot*cos(th1 - th2)"
POTENTIAL = "-(m1 + m2)*g*l1*cos(th1) - m2*g*l2*cos(th2)"
PARAMETERS = {"m1": 1.0, "m2": 1.0, "l1": 1.0, "l2": 1.0, "g": 9.81}
Q0 = [2.0, 2.0]
TOL = 1e-10

SCENE = """name = "double pendulum from text"
[run]
method = "{method}"
t_end = {t_end}
rtol = {tol}
atol = {tol}
output_interval = {t_end}
[model]
coordinates = ["th1", "th2"]
units = ["rad", "rad"]
kinetic = "{kinetic}"
potential = "{potential}"
q = [{q0}, {q1}]
[model.parameters]
{parameters}
"""


def reference(root, t_end):
    """theta1, theta2 at t_end (5 or 20 s) from bench/reference/double_pendulum.txt."""
    values, at5 = {}, False
    with open(os.path.join(root, "bench", "reference", "double_pendulum.txt")) as f:
        for line in f:
            if line.startswith("#") or "=" not in line:
                continue
            key, value = (s.strip() for s in line.split("=", 1))
            if key == "t":
                at5 = float(value) == t_end
            elif at5:
                values[key] = float(value)
    return values["theta1"], values["theta2"]


def ours(program, directory, method, tol, t_end):
    """Wall time of `lagrangian run` from the text to t_end, and theta(t_end)."""
    scene = os.path.join(directory, "text.toml")
    with open(scene, "w") as f:
        f.write(SCENE.format(method=method, t_end=t_end, tol=tol, kinetic=KINETIC, potential=POTENTIAL, q0=Q0[0], q1=Q0[1],
                             parameters="\n".join(f"{k} = {v}" for k, v in PARAMETERS.items())))
    out = os.path.join(directory, "out")
    start = time.perf_counter()
    subprocess.run([program, "run", scene, "--out", out, "--no-plots", "--no-animation", "-q"], check=True)
    wall = time.perf_counter() - start
    with open(os.path.join(out, "trajectory.csv")) as f:
        last = f.read().strip().splitlines()[-1].split(",")
    return wall, (float(last[1]), float(last[2]))


def sympy_scipy(t_end, tol):
    """Wall time from the text to t_end (each phase), and theta(t_end)."""
    start = time.perf_counter()
    t = sp.Symbol("t")
    q = dynamicsymbols("q1 q2")
    qd = [sp.diff(x, t) for x in q]
    names = {"th1": q[0], "th2": q[1], "th1_dot": qd[0], "th2_dot": qd[1]}
    names.update({k: sp.Float(v) for k, v in PARAMETERS.items()})
    lagrangian = parse_expr(KINETIC, local_dict=names) - parse_expr(POTENTIAL, local_dict=names)
    lm = LagrangesMethod(lagrangian, q)
    lm.form_lagranges_equations()
    rhs = lm.rhs()
    derived = time.perf_counter()
    y = sp.symbols("y0:4")
    flat = rhs.subs({qd[0]: y[2], qd[1]: y[3]}).subs({q[0]: y[0], q[1]: y[1]})
    f = sp.lambdify(y, list(flat), "math")
    lambdified = time.perf_counter()
    sol = solve_ivp(lambda _t, s: f(*s), (0.0, t_end), Q0 + [0.0, 0.0], method="DOP853", rtol=tol, atol=tol)
    end = time.perf_counter()
    return end - start, (derived - start, lambdified - derived, end - lambdified), (sol.y[0, -1], sol.y[1, -1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("lagrangian", help="the lagrangian program")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--method", default="fehlberg78", help="lagrangian's stepper")
    ap.add_argument("--tol", type=float, default=TOL, help="lagrangian's rtol = atol")
    ap.add_argument("--t-end", type=float, default=5.0, choices=[5.0, 20.0], help="where to compare (s)")
    ap.add_argument("--scipy-tol", type=float, default=TOL, help="SciPy's rtol = atol")
    args = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ref = reference(root, args.t_end)
    ours_times, theirs_times, phases = [], [], []
    with tempfile.TemporaryDirectory() as d:
        for _ in range(args.repeat):  # alternating, so that both see the same machine
            wall, theta = ours(args.lagrangian, d, args.method, args.tol, args.t_end)
            ours_times.append(wall)
            ours_error = max(abs(theta[0] - ref[0]), abs(theta[1] - ref[1]))
            wall, phase, theta = sympy_scipy(args.t_end, args.scipy_tol)
            theirs_times.append(wall)
            phases.append(phase)
            theirs_error = max(abs(theta[0] - ref[0]), abs(theta[1] - ref[1]))
    a, b = statistics.median(ours_times), statistics.median(theirs_times)
    print(f"lagrangian run (text model, {args.method} {args.tol:g}): {a * 1e3:.1f} ms (median of {args.repeat}; "
          f"range {min(ours_times) * 1e3:.1f}-{max(ours_times) * 1e3:.1f}), error at t = {args.t_end:g} s "
          f"{ours_error:.2e} rad")
    derive, lam, solve = (statistics.median(p[i] for p in phases) for i in range(3))
    print(f"SymPy + SciPy (DOP853 {args.scipy_tol:g}): {b * 1e3:.1f} ms (median; range {min(theirs_times) * 1e3:.1f}-"
          f"{max(theirs_times) * 1e3:.1f}: derive {derive * 1e3:.0f}, lambdify {lam * 1e3:.0f}, "
          f"solve {solve * 1e3:.0f}), error at t = {args.t_end:g} s {theirs_error:.2e} rad")
    print(f"ratio (SymPy + SciPy / lagrangian), text to the state at t = {args.t_end:g} s: {b / a:.1f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())
