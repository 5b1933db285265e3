/* bench_nbody.c: the N-body model's benchmarks (specs/nbody-galactica.md section 12):
 *
 *   b1 [P [TOL]]   the 30-body exact ring (spec 9.1) over one period with the adaptive Taylor
 *                  integrator of order P (default 20) and tolerance TOL (default 1e-16): CPU
 *                  time of the integration only (median of 5 runs), steps, the error against
 *                  the exact solution and |dE| at the end;
 *   b2 FILE [P [TOL [TH]]]  the outer Solar System of the data file FILE (data/outer_solar_system.dat,
 *                  Hairer, Lubich & Wanner) over 10^4 sidereal years (T = 100 in units of the
 *                  sidereal century) with the adaptive Taylor integrator, stopping exactly at 1000
 *                  equally spaced samples: CPU time of the integration only (median of 5), steps,
 *                  max |dE| over the samples, |dE| and |dL/L| at the end; TH turns the system
 *                  about z by TH radians first (the same problem with other rounding errors);
 *   wh FILE [YEARS [DT [K [SAMPLES [IC [CURVE]]]]]]  the same outer Solar System over YEARS
 *                  sidereal years (default 10^6) with the Wisdom-Holman map, step DT years
 *                  (default 0.5), corrector K (default 17), synchronised at SAMPLES equally
 *                  spaced times (default 1000) where |dE| is measured: CPU time (median of 5),
 *                  ns per step, max |dE| and |dE| at the end; IC: the initial bodies as for
 *                  cluster (for WHFast); CURVE: "T_years dE" per sample of the last run;
 *   galactica      the same period with Galactica's scheme, dT = 1e-6 (10 000 steps);
 *   pairs N [T]    ordered-pair evaluations per second of the Galactica scheme's passes for N
 *                  random bodies on T threads (default 1);
 *   cluster [N [T [P [TOL [SEED [IC [FINAL]]]]]]]  a Plummer sphere of N bodies (default 100;
 *                  seed SEED, default 1) to time T (default 10) with the adaptive Taylor
 *                  integrator (order P, tolerance TOL): CPU time of the integration only (median
 *                  of 5), steps, |dE/E| at the end; IC: its initial bodies into that file (mass,
 *                  x, y, z, vx, vy, vz per line, %.17g) for IAS15 to start from the same state;
 *                  FINAL: the bodies at T, the same way (to evaluate both codes' energy errors
 *                  with one evaluator);
 *   kepler [E [PERIODS [P [TOL [IC [FINAL [THETA]]]]]]]  the two-body orbit of eccentricity E
 *                  (default 0.9; M = 1, m = 1e-3, a = 1, from pericentre at the angle THETA from
 *                  the x axis, default 0, barycentric) over PERIODS periods (default 100), as
 *                  cluster (P 0, the default: the order auto gives for TOL); turned copies are
 *                  the same orbit with other rounding errors;
 *   pythagorean [T [P [TOL [IC [FINAL]]]]]  Burrau's three bodies (masses 3, 4, 5 at rest at (1,
 *                  3), (-2, -1), (1, -1), barycentric) to T (default 10), as cluster;
 *   plummer [NMAX [DMAX [PNG [T]]]]  seconds per Galactica-scheme step against N for a Plummer
 *                  sphere (spec 6.2), N = 10^3, 3*10^3, ... NMAX (default 10^6), direct sums up
 *                  to DMAX (default 3*10^4) and the Barnes-Hut tree at theta 0.5 for all, on T
 *                  threads (default 1); also seconds / (N log2 N) for the tree, and the plot
 *                  (log-log) into PNG (default plummer.png).
 *
 * One `key=value` line per run. Compare with the reference (REBOUND's IAS15) as bench/README.md
 * describes: same machine, same compiler and flags, one thread, median of 5. */
#include "mote/nbody.h"
#include "mote/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef MOTE_MPI
#include <mpi.h>
#endif

MOTE_PROGRAM_THREADS

/* the build's real type (make PRECISION=), as a word */
#define PREC (MOTE_NB_PRECISION == 4 ? "quad" : MOTE_NB_PRECISION == 2 ? "long" : "double")

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The integrator (order P, adaptive at tolerance tol) ready to run: for Taylor its scratch
 * sized by an integration of no step; the energy's reference taken now. */
static int ready(mote_nb *nb, int integrator, int P, double tol, mote_err *e)
{
    nb->integrator = integrator;
    nb->taylor_order = P;
    nb->adaptive = 1;
    nb->tol = tol;
    if (integrator == MOTE_NB_TAYLOR && mote_nb_integrate(nb, 0, INFINITY, e)) {
        fprintf(stderr, "bench_nbody: %s\n", e->msg);
        return 1;
    }
    mote_nb_set_reference(nb);
    return 0;
}

static int ring_period(int integrator, int P, double tol)
{
    double t[5], err = 0, dE = 0;
    unsigned long long steps = 0;
    for (int run = 0; run < 5; run++) {
        mote_nb nb;
        mote_nb_ring r;
        mote_nb_init(&nb, MOTE_NB_GRAVITY);
        mote_nb_ring_defaults(&r, MOTE_NB_GRAVITY);
        mote_err e = {0};
        if (mote_nb_ring_build(&nb, &r, &e)) {
            fprintf(stderr, "bench_nbody: %s\n", e.msg);
            return 1;
        }
        nb.dt = 1e-6;
        if (ready(&nb, integrator, P, tol, &e))
            return 1;
        double c0 = cpu_seconds();
        int rc = integrator == MOTE_NB_TAYLOR ? mote_nb_integrate(&nb, UINT64_MAX, r.period, &e)
                                              : mote_nb_integrate(&nb, 10000, INFINITY, &e);
        t[run] = cpu_seconds() - c0;
        if (rc) {
            fprintf(stderr, "bench_nbody: %s\n", e.msg);
            return 1;
        }
        err = mote_nb_ring_error(&nb, &r, NULL);
        mote_nb_monitor mon;
        mote_nb_measure(&nb, &mon);
        dE = mon.dE;
        steps = (unsigned long long)nb.steps;
        mote_nb_free(&nb);
    }
    qsort(t, 5, sizeof t[0], cmp_double);
    if (integrator == MOTE_NB_TAYLOR)
        printf("workload=b1 precision=%s integrator=taylor order=%d tol=%g steps=%llu cpu_seconds_median=%.6f "
               "cpu_seconds_min=%.6f error=%.3e abs_dE=%.3e\n",
               PREC, P, tol, steps, t[2], t[0], err, fabs(dE));
    else
        printf("workload=b1 precision=%s integrator=galactica dt=1e-6 steps=%llu "
               "cpu_seconds_median=%.6f "
               "cpu_seconds_min=%.6f error=%.3e abs_dE=%.3e\n",
               PREC, steps, t[2], t[0], err, fabs(dE));
    return 0;
}

/* The bodies of nb into path, one line each: mass x y z vx vy vz (%.17g). */
static int write_ic(const mote_nb *nb, const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "bench_nbody: cannot write %s\n", path);
        return 1;
    }
    for (uint32_t i = 0; i < nb->n; i++)
        fprintf(f, "%.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", (double)nb->m[i],
                (double)nb->x[3 * i], (double)nb->x[3 * i + 1], (double)nb->x[3 * i + 2],
                (double)nb->v[3 * i], (double)nb->v[3 * i + 1], (double)nb->v[3 * i + 2]);
    if (fclose(f)) {
        fprintf(stderr, "bench_nbody: cannot write %s\n", path);
        return 1;
    }
    return 0;
}

/* The Solar-System data file at path into nb (its own builder: total mass 1, the sidereal
 * century, barycentric); 1 with the message on stderr when it cannot be read. */
static int load_solar(const char *path, mote_nb *nb)
{
    mote_nb_solar s = {NULL, 0};
    mote_err e = {0};
    mote_nb_init(nb, MOTE_NB_GRAVITY);
    int rc = mote_nb_solar_read(path, &s, &e) || mote_nb_solar_build(nb, &s, NULL, 0, &e);
    mote_nb_solar_free(&s);
    if (rc)
        fprintf(stderr, "bench_nbody: %s\n", e.msg);
    return rc;
}

/* The bodies of the small-N workloads (par: the workload's numbers): a Plummer sphere (n,
 * seed); the two-body Kepler orbit of eccentricity e from its pericentre (M = 1, m = 10^-3,
 * a = 1); Burrau's Pythagorean three-body problem (masses 3, 4, 5 at rest at (1, 3), (-2, -1),
 * (1, -1)); the last two moved to the barycentre. G = 1. */
typedef int (*bodies_fn)(mote_nb *nb, const double *par, mote_err *e);

static int bodies_cluster(mote_nb *nb, const double *par, mote_err *e)
{
    return mote_nb_plummer(nb, (uint32_t)par[0], (uint64_t)par[1], e);
}

static int bodies_kepler(mote_nb *nb, const double *par, mote_err *e)
{
    /* par[1]: the pericentre's direction, an angle from the x axis (the same orbit with
     * other rounding errors: a realisation of the round-off walk) */
    const double M = 1, m = 1e-3, q = 1 - par[0], v = sqrt((M + m) * (1 + par[0]) / q);
    const double c = cos(par[1]), s = sin(par[1]);
    const mote_real x0[3] = {0, 0, 0}, x1[3] = {q * c, q * s, 0}, v1[3] = {-v * s, v * c, 0};
    int rc = mote_nb_add(nb, M, 0, x0, x0, 0, e) || mote_nb_add(nb, m, 0, x1, v1, 0, e);
    if (!rc)
        mote_nb_barycentric(nb, NULL, NULL);
    return rc;
}

static int bodies_pythagorean(mote_nb *nb, const double *par, mote_err *e)
{
    (void)par;
    static const double mass[3] = {3, 4, 5}, pos[3][2] = {{1, 3}, {-2, -1}, {1, -1}};
    const mote_real v0[3] = {0, 0, 0};
    for (int i = 0; i < 3; i++) {
        const mote_real x[3] = {pos[i][0], pos[i][1], 0};
        if (mote_nb_add(nb, mass[i], 0, x, v0, 0, e))
            return 1;
    }
    mote_nb_barycentric(nb, NULL, NULL);
    return 0;
}

/* The bodies of `make` to time T with the adaptive Taylor integrator of order P (0: the order
 * auto gives for tol) and tolerance tol: CPU time of the integration only (median of 5),
 * steps, |dE/E| at the end; with ic, the initial bodies (mass x y z vx vy vz, one line each,
 * %.17g) into that file, for another code to start from the same state. `what` names the
 * workload and its numbers on the output line. */
static int small_n(const char *what, bodies_fn make, const double *par, double T, int P,
                   double tol, const char *ic, const char *fin)
{
    double t[5], dE = 0;
    unsigned long long steps = 0;
    if (P <= 0)
        P = mote_nb_taylor_auto_order(tol);
    for (int run = 0; run < 5; run++) {
        mote_nb nb;
        mote_nb_init(&nb, MOTE_NB_GRAVITY);
        mote_err e = {0};
        if (make(&nb, par, &e)) {
            fprintf(stderr, "bench_nbody: %s\n", e.msg);
            return 1;
        }
        if (ic && run == 0 && write_ic(&nb, ic))
            return 1;
        nb.dt = 1e-6;
        if (ready(&nb, MOTE_NB_TAYLOR, P, tol, &e))
            return 1;
        const double c0 = cpu_seconds();
        const int rc = mote_nb_integrate(&nb, UINT64_MAX, T, &e);
        t[run] = cpu_seconds() - c0;
        if (rc) {
            fprintf(stderr, "bench_nbody: %s\n", e.msg);
            return 1;
        }
        mote_nb_monitor mon;
        mote_nb_measure(&nb, &mon);
        dE = mon.dE;
        steps = (unsigned long long)nb.steps;
        if (fin && run == 4 && write_ic(&nb, fin))
            return 1;
        mote_nb_free(&nb);
    }
    qsort(t, 5, sizeof t[0], cmp_double);
    printf("%s precision=%s T=%g order=%d tol=%g steps=%llu cpu_seconds_median=%.6f "
           "cpu_seconds_min=%.6f abs_dE=%.3e\n",
           what, PREC, T, P, tol, steps, t[2], t[0], fabs(dE));
    return 0;
}

/* Turn every position and velocity about the z axis by the angle th (radians): the same
 * physics with another sequence of rounding errors (a realisation of the round-off walk). */
static void rotate_z(mote_nb *nb, double th)
{
    const mote_real c = cos(th), s = sin(th);
    mote_real *arr[2] = {nb->x, nb->v};
    for (int b = 0; b < 2; b++)
        for (uint32_t i = 0; i < nb->n; i++) {
            mote_real *p = arr[b] + 3 * (size_t)i, x = p[0], y = p[1];
            p[0] = c * x - s * y;
            p[1] = s * x + c * y;
        }
}

static int solar(const char *path, int P, double tol, double th)
{
    double t[5], worst = 0, dE = 0, dL = 0;
    unsigned long long steps = 0;
    const int samples = 1000;
    const double t_end = 100;
    for (int run = 0; run < 5; run++) {
        mote_nb nb;
        mote_err e = {0};
        if (load_solar(path, &nb))
            return 1;
        if (th != 0)
            rotate_z(&nb, th);
        if (ready(&nb, MOTE_NB_TAYLOR, P, tol, &e))
            return 1;
        mote_nb_monitor mon;
        mote_nb_measure(&nb, &mon);
        mote_real L0[3] = {mon.L[0] + mon.S[0], mon.L[1] + mon.S[1], mon.L[2] + mon.S[2]};
        double cpu = 0;
        worst = 0;
        for (int k = 1; k <= samples; k++) {
            double c0 = cpu_seconds();
            int rc = mote_nb_integrate(&nb, UINT64_MAX, t_end * k / samples, &e);
            cpu += cpu_seconds() - c0;
            if (rc) {
                fprintf(stderr, "bench_nbody: %s\n", e.msg);
                return 1;
            }
            mote_nb_measure(&nb, &mon);
            worst = fmax(worst, fabs((double)mon.dE));
        }
        t[run] = cpu;
        dE = fabs((double)mon.dE);
        double d2 = 0, l2 = 0;
        for (int a = 0; a < 3; a++) {
            double d = (double)(mon.L[a] + mon.S[a] - L0[a]);
            d2 += d * d;
            l2 += (double)(L0[a] * L0[a]);
        }
        dL = sqrt(d2 / l2);
        steps = (unsigned long long)nb.steps;
        mote_nb_free(&nb);
    }
    qsort(t, 5, sizeof t[0], cmp_double);
    printf("workload=b2 precision=%s integrator=taylor order=%d tol=%g rotation=%g steps=%llu "
           "cpu_seconds_median=%.6f cpu_seconds_min=%.6f max_abs_dE=%.3e abs_dE_end=%.3e "
           "abs_dL_end=%.3e\n",
           PREC, P, tol, th, steps, t[2], t[0], worst, dE, dL);
    return 0;
}

static int wh(const char *path, double years, double dt, int K, int samples, const char *ic,
              const char *curve)
{
    double t[5], worst = 0, dE = 0;
    unsigned long long steps = 0;
    FILE *cf = NULL;
    for (int run = 0; run < 5; run++) {
        mote_nb nb;
        mote_err e = {0};
        if (load_solar(path, &nb))
            return 1;
        if (ic && run == 0 && write_ic(&nb, ic))
            return 1;
        if (curve && run == 4 && !(cf = fopen(curve, "w"))) {
            fprintf(stderr, "bench_nbody: cannot write %s\n", curve);
            return 1;
        }
        nb.integrator = MOTE_NB_WH;
        nb.wh_corrector = K;
        nb.dt = dt / 100; /* the time unit is the sidereal century */
        mote_nb_set_reference(&nb);
        mote_nb_monitor mon;
        double cpu = 0;
        worst = 0;
        for (int k = 1; k <= samples; k++) {
            double c0 = cpu_seconds();
            int rc = mote_nb_integrate(&nb, UINT64_MAX, years / 100 * k / samples, &e);
            cpu += cpu_seconds() - c0;
            if (rc) {
                fprintf(stderr, "bench_nbody: %s\n", e.msg);
                return 1;
            }
            mote_nb_measure(&nb, &mon);
            worst = fmax(worst, fabs((double)mon.dE));
            if (cf)
                fprintf(cf, "%.9g %.6e\n", (double)nb.T * 100, (double)mon.dE);
        }
        if (cf && fclose(cf)) {
            fprintf(stderr, "bench_nbody: cannot write %s\n", curve);
            return 1;
        }
        cf = NULL;
        t[run] = cpu;
        dE = fabs((double)mon.dE);
        steps = (unsigned long long)nb.steps;
        mote_nb_free(&nb);
    }
    qsort(t, 5, sizeof t[0], cmp_double);
    printf("workload=wh precision=%s years=%g dt_years=%g corrector=%d samples=%d steps=%llu "
           "cpu_seconds_median=%.6f cpu_seconds_min=%.6f ns_per_step=%.1f max_abs_dE=%.3e "
           "abs_dE_end=%.3e\n",
           PREC, years, dt, K, samples, steps, t[2], t[0], 1e9 * t[2] / (double)steps, worst,
           dE);
    return 0;
}

static int pairs(uint32_t n, int threads)
{
    mote_nb nb;
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    mote_rng g;
    mote_rng_seed(&g, 1);
    mote_err e = {0};
    for (uint32_t i = 0; i < n; i++) {
        mote_real x[3], v[3] = {0, 0, 0};
        for (int a = 0; a < 3; a++)
            x[a] = mote_rng_uniform(&g) - 0.5;
        mote_nb_add(&nb, (mote_real)1 / n, 0, x, v, 0, &e);
    }
    nb.dt = 1e-6;
    nb.threads = threads;
    mote_nb_galactica(&nb, 1, &e);
    const int steps = 3;
    double w0 = mote_wall_seconds();
    int rc = mote_nb_galactica(&nb, steps, &e);
    double w = mote_wall_seconds() - w0;
    if (rc) {
        fprintf(stderr, "bench_nbody: %s\n", e.msg);
        return 1;
    }
    double evals = 2.0 * steps * (double)n * (n - 1);
    printf("workload=pairs precision=%s N=%u threads=%d steps=%d wall_seconds=%.3f "
           "pair_evaluations_per_second=%.3e per_thread=%.3e bytes_per_body=%.0f\n",
           PREC, n, threads, steps, w, evals / w, evals / w / threads,
           (double)mote_peak_rss_bytes() / n);
    mote_nb_free(&nb);
    return 0;
}

/* One Galactica-scheme step of a Plummer sphere of n bodies (the second of two: the first is a
 * restart step of 0.001 dT, which costs the same), in wall seconds. */
static double plummer_step(uint32_t n, int tree, int threads, double *rss)
{
    mote_nb nb;
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    mote_err e = {0};
    if (mote_nb_plummer(&nb, n, 6, &e)) {
        fprintf(stderr, "bench_nbody: %s\n", e.msg);
        return -1;
    }
    nb.dt = 1e-4;
    nb.threads = threads;
    nb.tree_on = tree;
    nb.theta = 0.5;
    nb.ref_set = 1; /* (the energy reference is O(N^2): not wanted here) */
    if (mote_nb_galactica(&nb, 1, &e))
        return -1;
    double w0 = mote_wall_seconds();
    int rc = mote_nb_galactica(&nb, 1, &e);
    double w = mote_wall_seconds() - w0;
    *rss = (double)mote_peak_rss_bytes();
    mote_nb_free(&nb);
    return rc ? -1 : w;
}

static int plummer(uint32_t nmax, uint32_t dmax, const char *png, int threads)
{
    double N[16], td[16], tt[16], lnd[16], lnt[16], lN[16];
    int k = 0, kd = 0;
    for (double n = 1000; n <= nmax * 1.0001 && k < 16; n *= (k % 2 ? 10.0 / 3 : 3), k++) {
        const uint32_t m = (uint32_t)(n + 0.5);
        double rss;
        N[k] = m;
        td[k] = m <= dmax ? plummer_step(m, 0, threads, &rss) : NAN;
        tt[k] = plummer_step(m, 1, threads, &rss);
        if (tt[k] < 0 || (m <= dmax && td[k] < 0))
            return 1;
        lN[k] = log10(N[k]);
        lnd[k] = m <= dmax ? log10(td[k]) : NAN;
        lnt[k] = log10(tt[k]);
        kd += m <= dmax;
        printf("workload=plummer N=%u threads=%d direct_seconds_per_step=%.4g "
               "tree_seconds_per_step=%.4g tree_over_NlogN_ns=%.4g peak_rss_mb=%.0f\n", m,
               threads, td[k], tt[k], 1e9 * tt[k] / (N[k] * log2(N[k])), rss / 1e6);
        fflush(stdout);
    }
    /* the crossover: the first N at which the tree is faster */
    for (int i = 0; i < k; i++)
        if (isfinite(td[i]) && tt[i] < td[i]) {
            printf("crossover: the tree is faster from N = %.0f on (measured)\n", N[i]);
            break;
        }
    const mote_series s[2] = {{lN, lnd, (size_t)k, "direct sums", 2},
                              {lN, lnt, (size_t)k, "Barnes-Hut tree, theta 0.5", 2}};
    mote_plot_opts o = {0};
    o.title = "N-body: one Galactica-scheme step of a Plummer sphere";
    o.xlabel = "log10 N";
    o.ylabel = "log10 (wall seconds per step)";
    mote_err e = {0};
    if (mote_plot_png(png, &o, s, 2, &e)) {
        fprintf(stderr, "bench_nbody: %s\n", e.msg);
        return 1;
    }
    printf("plot: %s\n", png);
    return 0;
}

static int run(int argc, char **argv);

/* The MPI build (make MPI=1): `mpirun -np K bench_nbody pairs N` shares the passes among K ranks
 * (spec 6.3); rank 0 prints. */
int main(int argc, char **argv)
{
#ifdef MOTE_MPI
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    if (rank != 0 && !freopen("/dev/null", "w", stdout))
        MPI_Abort(MPI_COMM_WORLD, 1);
    if (rank == 0 && size > 1)
        printf("ranks=%d\n", size);
    int rc = run(argc, argv);
    MPI_Finalize();
    return rc;
#else
    return run(argc, argv);
#endif
}

static int run(int argc, char **argv)
{
    if (argc < 2 || strcmp(argv[1], "b1") == 0) {
        int P = argc > 2 ? atoi(argv[2]) : 20;
        double tol = argc > 3 ? atof(argv[3]) : 1e-16;
        return ring_period(MOTE_NB_TAYLOR, P, tol);
    }
    if (strcmp(argv[1], "b2") == 0 && argc > 2)
        return solar(argv[2], argc > 3 ? atoi(argv[3]) : 20, argc > 4 ? atof(argv[4]) : 1e-16,
                     argc > 5 ? atof(argv[5]) : 0);
    if (strcmp(argv[1], "wh") == 0 && argc > 2)
        return wh(argv[2], argc > 3 ? atof(argv[3]) : 1e6, argc > 4 ? atof(argv[4]) : 0.5,
                  argc > 5 ? atoi(argv[5]) : 17, argc > 6 ? atoi(argv[6]) : 1000,
                  argc > 7 ? argv[7] : NULL, argc > 8 ? argv[8] : NULL);
    if (strcmp(argv[1], "galactica") == 0)
        return ring_period(MOTE_NB_GALACTICA, 6, 0);
    if (strcmp(argv[1], "pairs") == 0 && argc > 2)
        return pairs((uint32_t)atoi(argv[2]), argc > 3 ? atoi(argv[3]) : 1);
    if (strcmp(argv[1], "cluster") == 0) {
        const double par[2] = {argc > 2 ? atof(argv[2]) : 100, argc > 6 ? atof(argv[6]) : 1};
        char what[96];
        snprintf(what, sizeof what, "workload=cluster N=%.0f seed=%.0f", par[0], par[1]);
        return small_n(what, bodies_cluster, par, argc > 3 ? atof(argv[3]) : 10,
                       argc > 4 ? atoi(argv[4]) : 20, argc > 5 ? atof(argv[5]) : 1e-16,
                       argc > 7 ? argv[7] : NULL, argc > 8 ? argv[8] : NULL);
    }
    if (strcmp(argv[1], "kepler") == 0) { /* e, periods (2 pi / sqrt(M + m) each) */
        const double par[2] = {argc > 2 ? atof(argv[2]) : 0.9, argc > 8 ? atof(argv[8]) : 0};
        const double periods = argc > 3 ? atof(argv[3]) : 100;
        char what[96];
        snprintf(what, sizeof what, "workload=kepler e=%g periods=%g", par[0], periods);
        return small_n(what, bodies_kepler, par, periods * 2 * MOTE_PI / sqrt(1.001),
                       argc > 4 ? atoi(argv[4]) : 0, argc > 5 ? atof(argv[5]) : 1e-16,
                       argc > 6 ? argv[6] : NULL, argc > 7 ? argv[7] : NULL);
    }
    if (strcmp(argv[1], "pythagorean") == 0)
        return small_n("workload=pythagorean", bodies_pythagorean, NULL,
                       argc > 2 ? atof(argv[2]) : 10, argc > 3 ? atoi(argv[3]) : 0,
                       argc > 4 ? atof(argv[4]) : 1e-16, argc > 5 ? argv[5] : NULL,
                       argc > 6 ? argv[6] : NULL);
    if (strcmp(argv[1], "plummer") == 0)
        return plummer(argc > 2 ? (uint32_t)atof(argv[2]) : 1000000,
                       argc > 3 ? (uint32_t)atof(argv[3]) : 30000,
                       argc > 4 ? argv[4] : "plummer.png", argc > 5 ? atoi(argv[5]) : 1);
    fprintf(stderr, "usage: bench_nbody [b1 [P [TOL]] | b2 FILE [P [TOL [TH]]] | galactica | "
                    "pairs N [THREADS] | plummer [NMAX [DMAX [PNG [THREADS]]]] | "
                    "cluster [N [T [P [TOL [SEED [IC]]]]]]] | kepler [E [PERIODS [P [TOL [IC]]]]] | "
                    "pythagorean [T [P [TOL [IC]]]] | "
                    "wh FILE [YEARS [DT [K [SAMPLES [IC [CURVE]]]]]]]\n");
    return 2;
}
