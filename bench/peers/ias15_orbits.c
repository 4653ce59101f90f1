/* Two bodies on an eccentric orbit with REBOUND's IAS15, for the same-run
 * comparison with gauss_radau15 (bench/peers/run_ias15.sh; docs/performance.md,
 * "Gauss–Radau against IAS15"). Not part of the build or the tests: REBOUND
 * is not a Debian package; run_ias15.sh builds this file against a REBOUND
 * source tree given on its command line.
 *
 * The case is the one `bench_orbits --case` integrates: masses m1 = 1 and
 * m2 = RATIO, G = a = 1, the relative orbit of eccentricity E started at true
 * anomaly F0 (rad), both bodies in the centre-of-mass frame (z = 0), for
 * ORBITS periods 2π/√(G(m1 + m2)), IAS15 at its default settings (adaptive
 * mode PRS23) with epsilon EPS (default 1e-9, REBOUND's default), first step
 * 1e-6 of a period (as bench_orbits), integrated exactly to t_end.
 *
 * Prints one line:
 *   ias15 two_body E RATIO F0 |dE/E0| WALL_S CPU_S STEPS
 * |dE/E0| = |E(t_end) − E(0)| / |E(0)| with E = ½m1v1² + ½m2v2² − Gm1m2/|r2 − r1|
 * evaluated in long double from the double state, the same formula and
 * precision bench_orbits uses for its Cartesian form; WALL_S and CPU_S are
 * the wall and process CPU time of reb_simulation_integrate() alone
 * (CLOCK_MONOTONIC, CLOCK_PROCESS_CPUTIME_ID).
 *
 * Usage: ias15_orbits E RATIO F0 ORBITS [EPS=1e-9]
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "rebound.h"

static long double energy(const struct reb_simulation* r, double G) {
    const struct reb_particle* p = r->particles;
    const long double dx = (long double)p[1].x - p[0].x, dy = (long double)p[1].y - p[0].y,
                      dz = (long double)p[1].z - p[0].z;
    long double t = 0;
    for (int i = 0; i < 2; ++i)
        t += 0.5L * p[i].m *
             ((long double)p[i].vx * p[i].vx + (long double)p[i].vy * p[i].vy + (long double)p[i].vz * p[i].vz);
    return t - (long double)G * p[0].m * p[1].m / sqrtl(dx * dx + dy * dy + dz * dz);
}

int main(int argc, char** argv) {
    if (argc < 5) {
        fprintf(stderr, "usage: %s E RATIO F0 ORBITS [EPS=1e-9]\n", argv[0]);
        return 2;
    }
    const double e = atof(argv[1]), ratio = atof(argv[2]), f0 = atof(argv[3]), orbits = atof(argv[4]);
    const double eps = argc > 5 ? atof(argv[5]) : 1e-9;
    const double G = 1, a = 1, m1 = 1, m2 = ratio, M = m1 + m2, gm = G * M;
    const double period = 2 * acos(-1.0) * sqrt(a * a * a / gm);
    /* The relative orbit at true anomaly f0: r = p/(1 + e cos f), v = √(GM/p) (−sin f, e + cos f). */
    const double p = a * (1 - e * e), r = p / (1 + e * cos(f0)), h = sqrt(gm / p);
    const double x = r * cos(f0), y = r * sin(f0), vx = -h * sin(f0), vy = h * (e + cos(f0));

    struct reb_simulation* sim = reb_simulation_create();
    sim->G = G;
    reb_simulation_set_integrator(sim, "ias15");
    struct reb_integrator_ias15_state* ias15 = (struct reb_integrator_ias15_state*)sim->integrator.state;
    ias15->epsilon = eps;
    sim->dt = 1e-6 * period;
    struct reb_particle b1 = {0}, b2 = {0};
    b1.m = m1;
    b1.x = -m2 / M * x;
    b1.y = -m2 / M * y;
    b1.vx = -m2 / M * vx;
    b1.vy = -m2 / M * vy;
    b2.m = m2;
    b2.x = m1 / M * x;
    b2.y = m1 / M * y;
    b2.vx = m1 / M * vx;
    b2.vy = m1 / M * vy;
    reb_simulation_add(sim, b1);
    reb_simulation_add(sim, b2);

    const long double e0 = energy(sim, G);
    struct timespec start, stop, cpu_start, cpu_stop;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &cpu_start);
    clock_gettime(CLOCK_MONOTONIC, &start);
    const enum REB_STATUS status = reb_simulation_integrate(sim, orbits * period);
    clock_gettime(CLOCK_MONOTONIC, &stop);
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &cpu_stop);
    const double wall = (double)(stop.tv_sec - start.tv_sec) + 1e-9 * (double)(stop.tv_nsec - start.tv_nsec);
    const double cpu =
        (double)(cpu_stop.tv_sec - cpu_start.tv_sec) + 1e-9 * (double)(cpu_stop.tv_nsec - cpu_start.tv_nsec);
    if (status != REB_STATUS_SUCCESS || fabs(sim->t - orbits * period) > 1e-12 * orbits * period) {
        fprintf(stderr, "ias15_orbits: the run stopped at t = %.17g of %.17g (status %d)\n", sim->t,
                orbits * period, (int)status);
        return 1;
    }
    const long double e1 = energy(sim, G);
    printf("ias15 two_body %s %s %s %.6e %.6e %.6e %llu\n", argv[1], argv[2], argv[3], (double)fabsl((e1 - e0) / e0),
           wall, cpu, (unsigned long long)sim->steps_done);
    reb_simulation_free(sim);
    return 0;
}
