#!/usr/bin/python3
"""High-precision reference for the chaotic double pendulum of
bench/scenes/double_pendulum_chaotic.toml: m1 = m2 = 1 kg, l1 = l2 = 1 m,
g = 9.81 m/s^2, released at rest from theta1 = theta2 = 2 rad.

The equations of motion (Lagrange's, solved for the accelerations), with
D = theta1 - theta2 and d = 2 m1 + m2 - m2 cos 2D:
  theta1'' = (-g (2 m1 + m2) sin theta1 - m2 g sin(theta1 - 2 theta2)
              - 2 sin D m2 (w2^2 l2 + w1^2 l1 cos D)) / (l1 d)
  theta2'' = 2 sin D (w1^2 l1 (m1 + m2) + g (m1 + m2) cos theta1
              + w2^2 l2 m2 cos D) / (l2 d)
integrated with Gragg's modified midpoint rule and Richardson extrapolation
in h^2 (the Gragg-Bulirsch-Stoer method, step sequence n = 2, 4, 6, ...),
each macro step extrapolated until two successive diagonal entries agree to
10^-(digits + 5), in mpmath's arbitrary precision (Debian's python3-mpmath).

Usage: double_pendulum.py DIGITS MACRO_STEP T_END [T_END ...] [--offset D]
Prints the state at each T_END to 40 significant digits. Two runs at
different precision and macro step agree to the digits stated in
bench/reference/double_pendulum.txt, which records them. --offset D starts
from theta1 = 2 + D instead: how far a change of the size of one rounding
(D = 2^-52 ~ 2.2e-16, half an ulp of 2) carries by T_END, the floor of any
integration in double precision.
"""
import sys
from mpmath import mp, mpf, sin, cos, nstr


def main():
    args = sys.argv[1:]
    offset = "0"
    if "--offset" in args:
        k = args.index("--offset")
        offset = args[k + 1]
        del args[k:k + 2]
    digits = int(args[0])
    H = mpf(args[1])
    ends = [mpf(a) for a in args[2:]]
    mp.dps = digits
    m1 = m2 = l1 = l2 = mpf(1)
    g = mpf("9.81")
    tol = mpf(10) ** (-(digits - 15))

    def f(y):
        t1, t2, w1, w2 = y
        D = t1 - t2
        d = 2 * m1 + m2 - m2 * cos(2 * D)
        a1 = (-g * (2 * m1 + m2) * sin(t1) - m2 * g * sin(t1 - 2 * t2)
              - 2 * sin(D) * m2 * (w2 * w2 * l2 + w1 * w1 * l1 * cos(D))) / (l1 * d)
        a2 = (2 * sin(D) * (w1 * w1 * l1 * (m1 + m2) + g * (m1 + m2) * cos(t1)
                            + w2 * w2 * l2 * m2 * cos(D))) / (l2 * d)
        return [w1, w2, a1, a2]

    def axpy(a, x, y):
        return [a * xi + yi for xi, yi in zip(x, y)]

    def midpoint(y, h, n):
        z0 = y
        z1 = axpy(h, f(z0), z0)
        for _ in range(n - 1):
            z0, z1 = z1, axpy(2 * h, f(z1), z0)
        # Gragg's smoothing step
        return [(a + b + h * c) / 2 for a, b, c in zip(z1, z0, f(z1))]

    def macro_step(y, H):
        rows = []
        for k in range(1, 31):
            n = 2 * k
            row = [midpoint(y, H / n, n)]
            for j in range(1, k):
                ratio = (mpf(n) / (2 * (k - j))) ** 2 - 1
                prev = rows[-1][j - 1]
                row.append([a + (a - b) / ratio for a, b in zip(row[j - 1], prev)])
            rows.append(row)
            if k > 2 and max(abs(a - b) for a, b in zip(row[-1], rows[-2][-1])) < tol:
                return row[-1]
        return None  # not converged: the caller halves the macro step

    y = [mpf(2) + mpf(offset), mpf(2), mpf(0), mpf(0)]
    t = mpf(0)
    for end in ends:
        while t < end:
            h = min(H, end - t)
            z = macro_step(y, h)
            while z is None:  # a stretch of fast motion: shorter macro steps
                h /= 2
                z = macro_step(y, h)
            y = z
            t += h
        print("t = %s: theta1 = %s, theta2 = %s, theta1_dot = %s, theta2_dot = %s"
              % (nstr(t, 10), *(nstr(v, 40) for v in y)))
        sys.stdout.flush()


if __name__ == "__main__":
    main()
