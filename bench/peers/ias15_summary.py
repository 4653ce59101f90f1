#!/usr/bin/python3
"""The table of bench/peers/run_ias15.sh from its raw lines.

Raw lines (after '#' comments): ROUND SIDE FORMULATION E RATIO F0 ERR WALL CPU STEPS [EVALUATIONS],
SIDE gauss_radau15 (formulations two_body, reduced_mass, kepler_polar) or
ias15 (two_body). ERR is |E(t_end) - E(0)| / |E(0)|, the same measure on both
sides. Per case (E, RATIO, F0) and side the time kept is the minimum over the
rounds; the table gives the medians over the cases and the ratio
IAS15 / gauss_radau15 of those medians (> 1: gauss_radau15 faster), each
gauss_radau15 formulation against IAS15's Cartesian run of the same cases,
and beside it the same ratio from each round alone. The errors are
deterministic (the same in every round); the table gives their medians and
in how many cases gauss_radau15's is the smaller.
"""
import statistics
import sys
from collections import defaultdict


def main(path):
    comments, runs = [], defaultdict(list)  # (side, form, e, case) -> [(round, err, wall, cpu)]
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                comments.append(line.rstrip())
                continue
            w = line.split()
            if len(w) < 10:
                continue
            rnd, side, form, e, ratio, f0 = w[:6]
            runs[(side, form, e, (ratio, f0))].append((int(rnd), float(w[6]), float(w[7]), float(w[8])))
    for c in comments:
        print(c)
    rounds = sorted({r for v in runs.values() for r, *_ in v})
    es = sorted({k[2] for k in runs}, key=float)
    print()
    print("| e | gauss_radau15 formulation | cases | median abs(dE/E0): gauss_radau15 / IAS15 | "
          "gauss_radau15 smaller in | median wall (s): gauss_radau15 / IAS15 | wall ratio IAS15/radau "
          "(single rounds) | median CPU (s): gauss_radau15 / IAS15 | CPU ratio (single rounds) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for e in es:
        ias = {k[3]: v for k, v in runs.items() if k[0] == "ias15" and k[2] == e}
        for form in ("two_body", "reduced_mass", "kepler_polar"):
            lag = {k[3]: v for k, v in runs.items() if k[0] == "gauss_radau15" and k[1] == form and k[2] == e}
            cases = sorted(set(lag) & set(ias))
            if not cases:
                continue
            err_l = [lag[c][0][1] for c in cases]
            err_i = [ias[c][0][1] for c in cases]
            smaller = sum(a < b for a, b in zip(err_l, err_i))

            def med(side, col, rnd=None):
                return statistics.median(
                    min(x[col] for x in side[c] if rnd is None or x[0] == rnd) for c in cases)

            def per_round(col):
                rs = []
                for r in rounds:
                    if all(any(x[0] == r for x in lag[c]) and any(x[0] == r for x in ias[c]) for c in cases):
                        rs.append(med(ias, col, r) / med(lag, col, r))
                return ", ".join(f"{x:.2f}" for x in rs)

            wl, wi, cl, ci = med(lag, 2), med(ias, 2), med(lag, 3), med(ias, 3)
            print(f"| {e} | {form} | {len(cases)} | {statistics.median(err_l):.1e} / {statistics.median(err_i):.1e} "
                  f"| {smaller} of {len(cases)} | {wl:.3f} / {wi:.3f} | **{wi / wl:.2f}** ({per_round(2)}) "
                  f"| {cl:.3f} / {ci:.3f} | **{ci / cl:.2f}** ({per_round(3)}) |")
    print()
    print(f"time: per case the minimum over {len(rounds)} interleaved rounds, then the median over the cases; "
          "ratio = IAS15 / gauss_radau15 (> 1: gauss_radau15 faster); in brackets the ratio from each round alone.")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: ias15_summary.py RAW")
    main(sys.argv[1])
