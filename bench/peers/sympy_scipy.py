#!/usr/bin/python3
"""The double pendulum the way many users would do it instead: equations of
motion derived by SymPy (sympy.physics.mechanics.LagrangesMethod), integrated
by SciPy's solve_ivp (DOP853, RK45, Radau) at the tolerances lagrangian bench
used, from the same state: m1 = m2 = 1 kg, l1 = l2 = 1 m, g = 9.81 m/s^2,
theta1 = theta2 = 2 rad at rest.

Two measures, each the same on both sides:
  * error at t = 5 s: max_i |theta_i(5) - theta_i,ref(5)| (rad), the reference
    being the one lagrangian bench used, read from its bench.json (for this
    scene the shipped 36-digit solution, bench/reference/double_pendulum.txt);
  * relative energy error at t = 20 s: |E(20) - E(0)| / |E(0)|. SciPy's from
    its final state. lagrangian's from a `lagrangian run` of each (stepper,
    tolerance) of the t = 20 s bench: report.json's
    energy_drift_relative_to_initial when the build writes it, otherwise E
    of trajectory.csv's first and last rows evaluated by the same SymPy
    energy function as SciPy's. (bench.json's energy_drift is the largest
    drift over the run relative to the largest |T| + |V|: another measure,
    not used here.) The wall times are the bench's medians.

Usage (run by bench/peers/run_peers.sh, which makes the lagrangian side):
  /usr/bin/python3 bench/peers/sympy_scipy.py --ours-error OUT/t5/bench.json \
      --ours-energy OUT/t20/bench.json --lagrangian build/bin/lagrangian \
      --scene bench/scenes/double_pendulum_chaotic.toml --out OUT [--repeat 3] [--budget 60]
  /usr/bin/python3 bench/peers/sympy_scipy.py --smoke
Writes OUT/scipy.csv, OUT/peers.txt (ratios, derivation times), OUT/peers.gp
and OUT/peers_error.png, OUT/peers_energy.png (gnuplot, when installed).
Debian's python3-sympy and python3-scipy install for /usr/bin/python3.
"""

import argparse
import csv
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import sympy as sp
import scipy
from scipy.integrate import solve_ivp
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

M1 = M2 = 1.0
L1 = L2 = 1.0
G = 9.81
Y0 = [2.0, 2.0, 0.0, 0.0]  # theta1, theta2, theta1', theta2'
METHODS = ["DOP853", "RK45", "Radau"]


def derive():
    """Lagrangian -> Lagrange's equations -> explicit first-order system, timed.

    Returns (rhs, energy, times) with rhs(t, y) and energy(y) plain Python
    callables and times = {"derive": s, "solve": s, "lambdify": s}.
    """
    t0 = time.perf_counter()
    q1, q2 = dynamicsymbols("q1 q2")
    q1d, q2d = dynamicsymbols("q1 q2", 1)
    m1, m2, l1, l2, g = sp.symbols("m1 m2 l1 l2 g", positive=True)
    # Bob positions (x right, y up), pivot at the origin, angles from the downward vertical.
    x1, y1 = l1 * sp.sin(q1), -l1 * sp.cos(q1)
    x2, y2 = x1 + l2 * sp.sin(q2), y1 - l2 * sp.cos(q2)
    t = dynamicsymbols._t
    v1sq = sp.diff(x1, t) ** 2 + sp.diff(y1, t) ** 2
    v2sq = sp.diff(x2, t) ** 2 + sp.diff(y2, t) ** 2
    T = sp.Rational(1, 2) * m1 * v1sq + sp.Rational(1, 2) * m2 * v2sq
    V = m1 * g * y1 + m2 * g * y2
    lm = LagrangesMethod(T - V, [q1, q2])
    lm.form_lagranges_equations()
    t1 = time.perf_counter()
    rhs_expr = lm.rhs()  # [q1', q2', q1'', q2''] by solving M q'' = f
    t2 = time.perf_counter()
    a, b, ad, bd = sp.symbols("a b ad bd")
    subs = {q1d: ad, q2d: bd}
    subs_q = {q1: a, q2: b}
    params = {m1: M1, m2: M2, l1: L1, l2: L2, g: G}
    exprs = [sp.sympify(e).subs(subs).subs(subs_q).subs(params) for e in rhs_expr]
    f = sp.lambdify((a, b, ad, bd), exprs, modules="math")
    energy_expr = (T + V).subs(subs).subs(subs_q).subs(params)
    e_fn = sp.lambdify((a, b, ad, bd), energy_expr, modules="math")
    t3 = time.perf_counter()

    def rhs(_t, y):
        return f(y[0], y[1], y[2], y[3])

    def energy(y):
        return e_fn(y[0], y[1], y[2], y[3])

    def kinetic_potential(y):
        tv = (T.subs(subs).subs(subs_q).subs(params), V.subs(subs_q).subs(params))
        return [float(sp.sympify(e).subs({a: y[0], b: y[1], ad: y[2], bd: y[3]})) for e in tv]

    return rhs, energy, kinetic_potential, {"derive": t1 - t0, "solve": t2 - t1, "lambdify": t3 - t2}


def hand_qdd(y):
    """The double pendulum's q'' written out by hand (independent check of the derivation)."""
    th1, th2, w1, w2 = y
    d = th1 - th2
    m11, m12, m22 = (M1 + M2) * L1 * L1, M2 * L1 * L2 * math.cos(d), M2 * L2 * L2
    f1 = -M2 * L1 * L2 * w2 * w2 * math.sin(d) - (M1 + M2) * G * L1 * math.sin(th1)
    f2 = M2 * L1 * L2 * w1 * w1 * math.sin(d) - M2 * G * L2 * math.sin(th2)
    det = m11 * m22 - m12 * m12
    return [(f1 * m22 - m12 * f2) / det, (m11 * f2 - m12 * f1) / det]


def check_derivation(rhs):
    for y in ([2.0, 2.0, 0.0, 0.0], [0.3, -1.1, 0.7, 2.5], [3.0, 1.0, -4.0, 1.5]):
        got = rhs(0.0, y)[2:]
        want = hand_qdd(y)
        if max(abs(g_ - w) for g_, w in zip(got, want)) > 1e-12 * (1 + max(abs(w) for w in want)):
            raise SystemExit(f"peers: SymPy's q'' {got} differs from the hand derivation {want} at {y}")


def tolerances(loose, tight, per_decade=1):
    n = round(math.log10(loose / tight) * per_decade)
    return [float(f"{loose * (tight / loose) ** (k / n):.3g}") for k in range(n + 1)] if n > 0 else [loose]


def run(rhs, method, tol, t_end, repeat):
    times, sol = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        sol = solve_ivp(rhs, (0.0, t_end), Y0, method=method, rtol=tol, atol=tol)
        times.append(time.perf_counter() - t0)
        if not sol.success:
            return None
    return statistics.median(times), sol


def interp_time(points, err):
    """log-log interpolation of wall time at error `err` on a curve of (error, time), or None."""
    pts = sorted((e, t) for e, t in points if e > 0 and t > 0)
    for (e0, t0), (e1, t1) in zip(pts, pts[1:]):
        if e0 <= err <= e1 and e1 > e0:
            w = (math.log(err) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + w * (math.log(t1) - math.log(t0)))
    return None


def ours(path, key):
    with open(path) as f:
        data = json.load(f)
    curves = {}
    for p in data["points"]:
        if p["status"] != "ok" or p.get(key) is None:
            continue
        if key == "error" and not p.get("resolved", True):
            continue
        curves.setdefault(p["method"], []).append((p[key], p["wall_time_s"], p["rhs_evaluations"]))
    return data, curves


def ours_energy_at_end(data, lagrangian, scene, energy, out):
    """|E(t_end) - E(0)| / |E(0)| of a `lagrangian run` per adaptive (stepper,
    tolerance) of the bench in `data`: {method: [(error, bench wall time, rhs)]}
    and a note saying where the numbers came from."""
    curves, sources = {}, set()
    t_end = data["t_end"]
    work = tempfile.mkdtemp(prefix="energy_", dir=out)
    for p in data["points"]:
        if p["status"] != "ok" or not p["adaptive"]:
            continue
        d = os.path.join(work, f"{p['method']}_{p['rtol']:.3g}")
        cmd = [lagrangian, "run", scene, "--t-end", repr(t_end), "--method", p["method"], "--rtol", repr(p["rtol"]),
               "--atol", repr(p["atol"]), "--out", d, "--no-plots", "--no-animation", "--allow-drift", "-q"]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            raise SystemExit(f"peers: {' '.join(cmd)} failed: {r.stderr.strip()}")
        with open(os.path.join(d, "report.json")) as f:
            report = json.load(f)["report"]  # the run's report, inside the scene's
        drift = report.get("energy_drift_relative_to_initial")
        if drift is not None:
            sources.add("report.json energy_drift_relative_to_initial")
        else:
            with open(os.path.join(d, "trajectory.csv")) as f:
                rows = [row for row in csv.reader(line for line in f if not line.startswith("#"))]
            header, first, last = rows[0], rows[1], rows[-1]
            names = [h.split(" [")[0] for h in header]
            cols = [names.index(n) for n in ("theta1", "theta2", "theta1_dot", "theta2_dot")]
            if abs(float(last[0]) - t_end) > 1e-9 * t_end:
                raise SystemExit(f"peers: {d}/trajectory.csv ends at t = {last[0]}, not {t_end}")
            e0 = energy([float(first[c]) for c in cols])
            e1 = energy([float(last[c]) for c in cols])
            drift = abs(e1 - e0) / abs(e0)
            sources.add("trajectory.csv first and last rows, E by SymPy's energy function")
        curves.setdefault(p["method"], []).append((drift, p["wall_time_s"], p["rhs_evaluations"]))
    shutil.rmtree(work, ignore_errors=True)
    return curves, "; ".join(sorted(sources))


def gnuplot(out, scipy_rows, ours_err, ours_energy, machine):
    blocks, plots = [], {"error": [], "energy": []}
    series = []
    for name, curve in sorted(ours_err.items()):
        series.append(("error", f"lagrangian {name}", [(t, e) for e, t, _ in curve]))
    for name, curve in sorted(ours_energy.items()):
        series.append(("energy", f"lagrangian {name}", [(t, e) for e, t, _ in curve]))
    for m in METHODS:
        series.append(("error", f"SciPy {m}", [(r["time5"], r["error5"]) for r in scipy_rows if r["method"] == m and r["error5"]]))
        series.append(("energy", f"SciPy {m}", [(r["time20"], r["drift20"]) for r in scipy_rows if r["method"] == m and r["drift20"]]))
    lines = ["if (!exists('suffix')) suffix = ''", "set terminal pngcairo size 800,560 noenhanced font 'Sans,10'",
             "set logscale xy", "set grid", "set key outside right top", "set format x '%.0e'; set format y '%.0e'",
             "set xlabel 'wall time (s)'", "set bmargin 6",
             f"set label 1 '{machine[:110]}' at screen 0.01, 0.025 font ',8'"]
    for i, (which, title, pts) in enumerate(series):
        pts = [(t, e) for t, e in pts if t and e and t > 0 and e > 0]
        if not pts:
            continue
        blocks.append(f"$d{i} << EOD\n" + "\n".join(f"{t:.6e} {e:.6e}" for t, e in sorted(pts)) + "\nEOD")
        style = "linespoints pt 7 ps 0.7" if title.startswith("lagrangian") else "linespoints dt 2 pt 6 ps 0.8"
        plots[which].append(f"$d{i} using 1:2 with {style} title '{title}'")
    lines = blocks + lines
    lines += ["set output 'peers_error'.suffix.'.png'",
              "set title 'double pendulum, theta1 = theta2 = 2 rad: error at t = 5 s against wall time'",
              "set ylabel 'max |theta_i(5) - theta_i,ref(5)| (rad)'",
              "plot " + ", \\\n     ".join(plots["error"]), "set output",
              "set output 'peers_energy'.suffix.'.png'",
              "set title 'double pendulum, t in [0, 20] s: relative energy error at the end against wall time'",
              "set ylabel '|E(20) - E(0)| / |E(0)|'",
              "plot " + ", \\\n     ".join(plots["energy"]), "set output"]
    with open(os.path.join(out, "peers.gp"), "w") as f:
        f.write("\n".join(lines) + "\n")
    exe = shutil.which("gnuplot")
    if not exe:
        return "gnuplot not found; install it with: apt-get install gnuplot-nox (plots skipped)"
    r = subprocess.run([exe, "-e", "suffix = '.partial'", "peers.gp"], cwd=out, capture_output=True, text=True)
    if r.returncode != 0:
        return "gnuplot failed: " + r.stderr.strip()
    for name in ("peers_error", "peers_energy"):
        os.replace(os.path.join(out, name + ".partial.png"), os.path.join(out, name + ".png"))
    return "wrote peers_error.png and peers_energy.png"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ours-error", help="bench.json of `lagrangian bench` on [0, 5] s")
    ap.add_argument("--ours-energy", help="bench.json of `lagrangian bench` on [0, 20] s")
    ap.add_argument("--lagrangian", help="the lagrangian program (runs each stepper and tolerance of --ours-energy "
                                         "once more for its energy at the end)")
    ap.add_argument("--scene", help="the scene file both benches ran")
    ap.add_argument("--out", default="out/peers")
    ap.add_argument("--tolerances", default="1e-3:1e-13")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--budget", type=float, default=30.0,
                    help="stop tightening a method once one run takes longer than this (s)")
    ap.add_argument("--smoke", action="store_true", help="derive, check and integrate once; for the test suite")
    a = ap.parse_args()

    rhs, energy, kinetic_potential, dtimes = derive()
    check_derivation(rhs)
    if a.smoke:
        res = run(rhs, "DOP853", 1e-6, 0.5, 1)
        if res is None:
            raise SystemExit("peers smoke: solve_ivp failed")
        e0, e1 = energy(Y0), energy(res[1].y[:, -1])
        if not abs(e1 - e0) < 1e-4 * abs(e0):
            raise SystemExit(f"peers smoke: energy not conserved ({e0} -> {e1})")
        print(f"peers smoke: ok (sympy {sp.__version__}, scipy {scipy.__version__}; derived in "
              f"{dtimes['derive'] + dtimes['solve'] + dtimes['lambdify']:.2f} s)")
        return

    if not (a.ours_error and a.ours_energy and a.lagrangian and a.scene):
        ap.error("--ours-error, --ours-energy, --lagrangian and --scene are required (or --smoke)")
    try:
        loose, tight = (float(x) for x in a.tolerances.split(":"))
    except ValueError:
        ap.error(f"--tolerances: expected LOOSE:TIGHT, got '{a.tolerances}'")
    if not (loose > tight > 0):
        ap.error(f"--tolerances: need LOOSE > TIGHT > 0, got '{a.tolerances}'")
    os.makedirs(a.out, exist_ok=True)
    data5, ours_err = ours(a.ours_error, "error")
    with open(a.ours_energy) as f:
        data20 = json.load(f)
    ours_energy, energy_source = ours_energy_at_end(data20, a.lagrangian, a.scene, energy, a.out)
    qref5 = data5["reference_q"]
    if len(qref5) != 2:
        raise SystemExit("peers: the bench.json for t = 5 s has no reference state (was it a reference run?)")
    E0 = energy(Y0)

    rows = []
    for m in METHODS:
        for tol in tolerances(loose, tight):
            row = {"method": m, "tol": tol, "time5": None, "error5": None, "nfev5": None,
                   "time20": None, "drift20": None, "nfev20": None}
            r5 = run(rhs, m, tol, 5.0, a.repeat)
            if r5:
                row["time5"], row["nfev5"] = r5[0], r5[1].nfev
                row["error5"] = max(abs(r5[1].y[i, -1] - qref5[i]) for i in range(2))
            r20 = run(rhs, m, tol, 20.0, a.repeat)
            if r20:
                row["time20"], row["nfev20"] = r20[0], r20[1].nfev
                row["drift20"] = abs(energy(r20[1].y[:, -1]) - E0) / abs(E0)
            rows.append(row)
            print(f"  SciPy {m} tol {tol:.0e}: error(5) {row['error5']}, {row['time5']} s; "
                  f"drift(20) {row['drift20']}, {row['time20']} s", file=sys.stderr)
            if (r20 and r20[0] > a.budget) or not r20:
                break

    with open(os.path.join(a.out, "scipy.csv"), "w") as f:
        f.write("method,rtol,time5_s,error5,nfev5,time20_s,drift20,nfev20\n")
        for r in rows:
            f.write(",".join("" if r[k] is None else (f"{r[k]:.6e}" if isinstance(r[k], float) else str(r[k]))
                             for k in ("method", "tol", "time5", "error5", "nfev5", "time20", "drift20", "nfev20")) + "\n")

    # Speed ratio at equal error: SciPy's time over the time lagrangian's
    # fastest stepper needs for the same error (log-log interpolation).
    def best(curves, err):
        ts = [interp_time([(e, t) for e, t, _ in c], err) for c in curves.values()]
        ts = [t for t in ts if t]
        return min(ts) if ts else None

    out = [f"SymPy {sp.__version__}, SciPy {scipy.__version__}, NumPy {np.__version__}, Python {sys.version.split()[0]}",
           f"SymPy derivation: LagrangesMethod + form_lagranges_equations {dtimes['derive']:.3f} s, "
           f"solving for q'' (rhs) {dtimes['solve']:.3f} s, lambdify {dtimes['lambdify']:.3f} s",
           "error at t = 5 s against: " + data5.get("reference", "?"),
           "energy error at t = 20 s, both sides |E(20) - E(0)| / |E(0)|; lagrangian's from " + energy_source,
           "", "speed ratio at equal error (SciPy time / lagrangian's fastest stepper's time at the same error):"]
    ratios = {"error5": [], "drift20": []}
    for r in rows:
        for key, tkey, curves in (("error5", "time5", ours_err), ("drift20", "time20", ours_energy)):
            if r[key] and r[tkey]:
                t_ours = best(curves, r[key])
                if t_ours:
                    ratios[key].append((r["method"], r["tol"], r[key], r[tkey] / t_ours))
    for key, label in (("error5", "error at t = 5 s"), ("drift20", "relative energy error |E(20) - E(0)| / |E(0)|")):
        out.append(f"  {label}:")
        for m, tol, e, ratio in ratios[key]:
            out.append(f"    {m:7s} rtol {tol:.0e}: error {e:.2e}, ratio {ratio:,.0f}x")
        for m in METHODS:
            rs = [ratio for mm, _, _, ratio in ratios[key] if mm == m]
            if rs:
                out.append(f"    {m}: median ratio {statistics.median(rs):,.0f}x (min {min(rs):,.0f}x, max {max(rs):,.0f}x)")
    out.append("")
    out.append("lagrangian machine: " + data5.get("machine", "?"))
    out.append(gnuplot(a.out, rows, ours_err, ours_energy, data5.get("machine", "")))
    text = "\n".join(out) + "\n"
    with open(os.path.join(a.out, "peers.txt"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
