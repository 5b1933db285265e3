/* test_nbody.c: the N-body model against the numbers of specs/nbody-galactica.md section 11:
 * the ring generators' check values (T01, T02), the neutral ring's net force F(N) (T03), the
 * first-step rule and exact time bookkeeping (T04), the gravity ring over one period against
 * the exact solution with its invariants (T05), a coarser step (T06), the Coulomb ring (T07),
 * the accuracy gained per added derivative (T08), the Coulomb sign (T23) and the scales (T24). */
#include "mote/nbody.h"
#include "test.h"

#include <cairo.h>
#include <sys/resource.h>
#include <time.h>

#include "../src/nbody/nb.h" /* nb_plot_file */

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define REL(a, b) (fabs((a) - (b)) / fabs(b))
#define CHECK_REL(a, b, tol)                                                                    \
    CHECK(REL(a, b) <= (tol), "%s = %.17g, expected %.17g (relative %.2e > %.0e)", #a,        \
          (double)(a), (double)(b), REL(a, b), (double)(tol))

/* Half a unit of the last digit of a number as printed ("0.010823751785177", "4.6e-5"). */
static double half_unit(const char *printed)
{
    const char *e = strpbrk(printed, "eE"), *dot = strchr(printed, '.');
    int exp10 = e ? atoi(e + 1) : 0;
    int decimals = 0;
    if (dot)
        for (const char *q = dot + 1; *q >= '0' && *q <= '9'; q++)
            decimals++;
    return 0.5 * pow(10.0, exp10 - decimals);
}

/* A value against a check value of the seed document: within the spec's relative tolerance, or
 * where the document prints fewer digits than that tolerance needs, within half a unit of its
 * last printed digit (the printed number carries no more). */
#define CHECK_PRINTED(a, printed, tol)                                                          \
    do {                                                                                        \
        double p_ = strtod(printed, NULL), a_ = (a);                                            \
        double t_ = fmax((tol) * fabs(p_), half_unit(printed));                                 \
        CHECK(fabs(a_ - p_) <= t_, "%s = %.17g, printed %s (allowed %.2e)", #a, a_, printed, t_); \
    } while (0)

static void test_ring_values(void)
{
    printf("T01: gravity ring generator (spec 9.1)\n");
    mote_nb nb;
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    mote_nb_ring r;
    mote_nb_ring_defaults(&r, MOTE_NB_GRAVITY);
    mote_err err = {0};
    CHECK(mote_nb_ring_build(&nb, &r, &err) == MOTE_OK, "build: %s", err.msg);
    CHECK_REL(r.alpha1, -0.829462508294625, 1e-15);
    CHECK_REL(r.fN, 16.12083740509405, 1e-14);
    CHECK_REL(r.mu1, -1.32824690980362e20, 1e-14);
    CHECK_REL(r.d, 784.3895396357486, 1e-12);
    CHECK_REL(nb.u.Am_first, 1.097960770309581e13, 2e-15);
    CHECK_REL(nb.u.Am, 1.097960770309582e13, 2e-15);
    CHECK_REL(nb.u.kv, 2.874251102012488e-4, 2e-15);
    CHECK(nb.u.Am - 1 / (nb.u.kt * nb.u.kv) == 0, "(Am - 1/(kt kv)) / Am = %g",
          (nb.u.Am - 1 / (nb.u.kt * nb.u.kv)) / nb.u.Am);
    mote_ksum ms = {0, 0}; /* the exact sum of the stored masses */
    for (uint32_t i = 0; i < nb.n; i++)
        mote_ksum_add(&ms, nb.m[i]);
    double msum = mote_ksum_value(&ms);
    CHECK(fabs(msum - 1) <= 4.5e-16, "sum m_o - 1 = %g", msum - 1);
    CHECK(fabs(r.xc[0]) <= 1e-20 && fabs(r.xc[1]) <= 1e-20 && fabs(r.xc[2]) <= 1e-20 &&
              fabs(r.vc[0]) <= 1e-17 && fabs(r.vc[1]) <= 1e-17 && fabs(r.vc[2]) <= 1e-17,
          "residual centre of mass %g %g %g, %g %g %g", r.xc[0], r.xc[1], r.xc[2], r.vc[0],
          r.vc[1], r.vc[2]);
    mote_nb_monitor mon;
    mote_nb_measure(&nb, &mon);
    double M0 = sqrt(mon.L[0] * mon.L[0] + mon.L[1] * mon.L[1] + mon.L[2] * mon.L[2]);
    CHECK(fabs((M0 - r.M00) / M0) <= 1e-14, "(M0 - M00)/M0 = %g", (M0 - r.M00) / M0);
    CHECK(fabs(mon.L[1] - -6.087427365523565e-5) <= 5e-5 && fabs(mon.L[2] - 1.404436095090305e-4) <= 5e-5,
          "My %.17g Mz %.17g", mon.L[1], mon.L[2]);
    CHECK_REL(r.M00, 1.530663479694117e-4, 1e-14);
    CHECK_PRINTED(r.rp_o, "0.010823751785177", 1e-14);
    CHECK_PRINTED(r.a_o, "0.013625065187786", 1e-14);
    CHECK_REL(r.vp_o, 10.55075187031951, 1e-14);
    CHECK_REL(r.mo0, 0.99865964917308, 1e-13);
    CHECK_REL(r.mo1, 4.6218994031734e-5, 1e-13);
    CHECK_REL(r.mu, 0.99940473806089, 1e-13);
    CHECK_REL(r.ra0 / nb.u.Am, 4.1554092e-5, 1e-7);
    CHECK_REL(r.ra1 / nb.u.Am, 1.4919289e-6, 1e-7);
    CHECK_REL(mon.ekin, 0.0746028313090509, 1e-13);
    CHECK_REL(mon.etot, -0.0491576718579219, 1e-13);
    CHECK_REL(r.period, 0.009995788296740863, 1e-14);
    printf("  Am %.16e m, kv %.16e s/m, period %.17g, E_tot %.16g\n", nb.u.Am, nb.u.kv, r.period,
           mon.etot);
    /* T24: the scales invert (eq. 7) */
    double xm = nb.x[3] * nb.u.Am, vm = nb.v[4] / nb.u.kv;
    CHECK_REL(xm / nb.u.Am, nb.x[3], 1e-15);
    CHECK_REL(vm * nb.u.kv, nb.v[4], 1e-15);
    mote_nb_free(&nb);
}

static void test_coulomb_values(void)
{
    printf("T02: Coulomb ring generator (spec 9.2)\n");
    mote_nb nb;
    mote_nb_init(&nb, MOTE_NB_COULOMB);
    mote_nb_ring r;
    mote_nb_ring_defaults(&r, MOTE_NB_COULOMB);
    mote_err err = {0};
    CHECK(mote_nb_ring_build(&nb, &r, &err) == MOTE_OK, "build: %s", err.msg);
    CHECK_REL(r.a, 3.30729375e-11, 1e-14);
    CHECK_REL(r.rn, 3.77976314968462e-15, 1e-14);
    CHECK_REL(r.alpha1, -0.869565217391304, 1e-15);
    CHECK_REL(r.fN, 2.804865846209121, 1e-14);
    CHECK_REL(r.mu1, -1.315657523093202e3, 1e-14);
    CHECK_REL(r.d, 7171.996969841117, 1e-12);
    CHECK_REL(nb.u.Am_first, 2.049767130503777e-11, 2e-15);
    CHECK_REL(nb.u.Am, 2.049767130503774e-11, 2e-15);
    CHECK_REL(nb.u.kv, 4.878602964787661e-5, 2e-15);
    CHECK_REL(2 * r.a_o, 3.226994618834738, 1e-14);
    CHECK_REL(r.rp_o, 1.371472713004765, 1e-14);
    CHECK_REL(r.vp_o, 357.9068202230957, 1e-14);
    CHECK_REL(r.mo0, 0.99972794452253, 1e-13);
    mote_nb_monitor mon;
    mote_nb_measure(&nb, &mon);
    CHECK(fabs(mon.L[1] - -0.053108187925464) <= 1e-14 * 0.2 && fabs(mon.L[2] - 0.122526400051667) <= 1e-14 * 0.2 &&
              fabs(mon.L[0]) <= 1e-16,
          "Mx %.3g My %.17g Mz %.17g", mon.L[0], mon.L[1], mon.L[2]);
    double M0 = sqrt(mon.L[0] * mon.L[0] + mon.L[1] * mon.L[1] + mon.L[2] * mon.L[2]);
    CHECK(fabs((M0 - r.M00) / M0) <= 1e-14, "(M0 - M00)/M0 = %g", (M0 - r.M00) / M0);
    CHECK_REL(mon.ekin, 17.4247849635, 1e-11);
    CHECK_REL(mon.etot, -12.8791888861, 1e-11);
    CHECK_REL(r.period, 0.032947130559790413, 1e-14);
    CHECK(fabs(r.xc[0]) <= 1e-18 && fabs(r.xc[1]) <= 1e-18 && fabs(r.xc[2]) <= 1e-18 &&
              fabs(r.vc[0]) <= 5e-17 && fabs(r.vc[1]) <= 5e-17 && fabs(r.vc[2]) <= 5e-17,
          "residual centre of mass %g %g %g, %g %g %g", r.xc[0], r.xc[1], r.xc[2], r.vc[0],
          r.vc[1], r.vc[2]);
    printf("  Am %.16e m, kv %.16e s/m, period %.17g, E_tot %.12g\n", nb.u.Am, nb.u.kv, r.period,
           mon.etot);
    mote_nb_free(&nb);
}

static void test_fN(void)
{
    printf("T03: the neutral ring's net central force F(N) = N - f_N(N)\n");
    int best = 0;
    double fmax = -INFINITY, f[601];
    int positive_below = 1;
    for (int N = 2; N <= 600; N++) {
        f[N] = N - mote_nb_ring_fN(N);
        if (f[N] > fmax) {
            fmax = f[N];
            best = N;
        }
        if (N < 473)
            positive_below &= f[N] > 0;
    }
    CHECK_INT(best, 174);
    CHECK(fabs(f[174] - 27.6515) < 5e-5 && fabs(f[173] - 27.65125) < 5e-6 &&
              fabs(f[175] - 27.65077) < 5e-6,
          "F(173..175) = %.6f %.6f %.6f", f[173], f[174], f[175]);
    CHECK(fabs(f[472] - 0.04312) < 5e-6 && f[472] > 0, "F(472) = %.6f", f[472]);
    CHECK(fabs(f[473] - -0.11611) < 5e-6 && f[473] < 0, "F(473) = %.6f", f[473]);
    CHECK(positive_below, "F(N) > 0 for all N < 473");
    printf("  maximum F(174) = %.5f; F(472) = %.5f; F(473) = %.5f\n", f[174], f[472], f[473]);
}

/* A ring run: `steps` steps of dt with the Galactica scheme of order K. */
static double ring_run(mote_nb_interaction kind, double dt, uint64_t steps, int K, mote_nb *nb,
                       mote_nb_ring *r, double *plane)
{
    mote_nb_init(nb, kind);
    mote_nb_ring_defaults(r, kind);
    mote_err err = {0};
    CHECK(mote_nb_ring_build(nb, r, &err) == MOTE_OK, "build: %s", err.msg);
    nb->dt = dt;
    nb->order = K;
    CHECK(mote_nb_galactica(nb, steps, &err) == MOTE_OK, "galactica: %s", err.msg);
    return mote_nb_ring_error(nb, r, plane);
}

static void test_gravity_ring(void)
{
    printf("T04, T05: gravity ring, dT = 1e-6, 10 000 steps from a fresh start\n");
    mote_nb nb;
    mote_nb_ring r;
    double plane;
    double err = ring_run(MOTE_NB_GRAVITY, 1e-6, 10000, 6, &nb, &r, &plane);
    CHECK(nb.T == 0.009999000999999999, "T = %.17g, expected 0.009999000999999999 exactly", nb.T);
    mote_nb_monitor mon;
    mote_nb_measure(&nb, &mon);
    double pabs = 0, sum_mv = 0;
    for (uint32_t i = 0; i < nb.n; i++)
        sum_mv += nb.m[i] * sqrt(nb.v[3 * i] * nb.v[3 * i] + nb.v[3 * i + 1] * nb.v[3 * i + 1] +
                                 nb.v[3 * i + 2] * nb.v[3 * i + 2]);
    pabs = sqrt(mon.P[0] * mon.P[0] + mon.P[1] * mon.P[1] + mon.P[2] * mon.P[2]);
    double cm = sqrt(mon.R[0] * mon.R[0] + mon.R[1] * mon.R[1] + mon.R[2] * mon.R[2]);
    printf("  T = %.17g (%.4f periods): error %.3e, out of plane %.3e of a, dE %.3e, dMz %.3e, "
           "|P| %.2e of sum m|v|, CM %.2e of a\n",
           nb.T, nb.T / r.period, err, plane / r.a_o, mon.dE, mon.dMz, pabs / sum_mv, cm / r.a_o);
    CHECK(err <= 1e-12, "error %.3g after one period", err);
    CHECK(plane <= 1e-12 * r.a_o, "out of plane %.3g", plane / r.a_o);
    CHECK(fabs(mon.dE) <= 1e-13, "dE %.3g", mon.dE);
    CHECK(fabs(mon.dMz) <= 1e-14, "dMz %.3g", mon.dMz);
    CHECK(pabs <= 1e-15 * sum_mv && cm <= 1e-15 * r.a_o, "momentum %.3g, CM %.3g", pabs / sum_mv,
          cm / r.a_o);
    mote_nb_free(&nb);

    printf("T06: dT = 1e-5, 1000 steps\n");
    err = ring_run(MOTE_NB_GRAVITY, 1e-5, 1000, 6, &nb, &r, NULL);
    printf("  error %.3e\n", err);
    CHECK(err <= 1e-10, "error %.3g", err);
    mote_nb_free(&nb);
}

static void test_orders(void)
{
    printf("T08: accuracy per added derivative (truncated scheme, one period)\n");
    double e[7] = {0};
    mote_nb nb;
    mote_nb_ring r;
    for (int K = 2; K <= 6; K++) {
        e[K] = ring_run(MOTE_NB_GRAVITY, 1e-6, 10000, K, &nb, &r, NULL);
        mote_nb_free(&nb);
    }
    printf("  dT 1e-6: errors K=2..6: %.2e %.2e %.2e %.2e %.2e\n", e[2], e[3], e[4], e[5], e[6]);
    for (int K = 2; K <= 4; K++) {
        double g = log10(e[K] / e[K + 1]);
        CHECK(g >= 2.5 && g <= 4.5, "err(%d)/err(%d) = 10^%.2f, expected 10^2.5 ... 10^4.5", K,
              K + 1, g);
    }
    double e5 = ring_run(MOTE_NB_GRAVITY, 1e-5, 1000, 5, &nb, &r, NULL);
    mote_nb_free(&nb);
    double e6 = ring_run(MOTE_NB_GRAVITY, 1e-5, 1000, 6, &nb, &r, NULL);
    mote_nb_free(&nb);
    double g = log10(e5 / e6);
    printf("  dT 1e-5: err(5) %.2e, err(6) %.2e: 10^%.2f\n", e5, e6, g);
    CHECK(g >= 2 && g <= 3.5, "err(5)/err(6) = 10^%.2f, expected 10^2 ... 10^3.5", g);
}

static void test_coulomb_ring(void)
{
    printf("T04, T07: Coulomb ring\n");
    mote_nb nb;
    mote_nb_ring r;
    double err = ring_run(MOTE_NB_COULOMB, 1e-6, 30000, 6, &nb, &r, NULL);
    mote_nb_monitor mon;
    mote_nb_measure(&nb, &mon);
    printf("  dT 1e-6, 30 000 steps: T = %.17g (%.3f periods), error %.3e, dE %.3e\n", nb.T,
           nb.T / r.period, err, mon.dE);
    CHECK(err <= 1e-11, "error %.3g", err);
    CHECK(fabs(mon.dE) <= 1e-13, "dE %.3g", mon.dE);
    mote_nb_free(&nb);
    if (!getenv("MOTE_SANITIZED")) {
        ring_run(MOTE_NB_COULOMB, 1e-7, 300000, 6, &nb, &r, NULL);
        CHECK(nb.T == 0.029999900099999997, "T = %.17g, expected 0.029999900099999997", nb.T);
        mote_nb_free(&nb);
    }
}

static void test_coulomb_sign(void)
{
    printf("T23: like charges repel, opposite charges attract\n");
    for (int like = 0; like < 2; like++) {
        mote_nb nb;
        mote_nb_init(&nb, MOTE_NB_COULOMB);
        mote_err err = {0};
        double x0[3] = {-0.5, 0, 0}, x1[3] = {0.5, 0, 0}, v[3] = {0, 0, 0};
        mote_nb_add(&nb, 0.5, 1, x0, v, 0, &err);
        mote_nb_add(&nb, 0.5, like ? 1 : -1, x1, v, 0, &err);
        nb.dt = 1e-3;
        CHECK(mote_nb_galactica(&nb, 10, &err) == MOTE_OK, "run: %s", err.msg);
        double gap = nb.x[3] - nb.x[0];
        CHECK(like ? gap > 1 : gap < 1, "%s charges: separation 1 -> %.17g",
              like ? "like" : "opposite", gap);
        mote_nb_free(&nb);
    }
    /* bad input */
    mote_nb nb;
    mote_nb_init(&nb, MOTE_NB_COULOMB);
    mote_err err = {0};
    double x[3] = {0, 0, 0}, y[3] = {1, 0, 0}, v[3] = {0, 0, 0}, bad[3] = {NAN, 0, 0};
    CHECK(mote_nb_add(&nb, 1, 0, bad, v, 0, &err) != 0, "NaN position accepted");
    CHECK(mote_nb_add(&nb, 0, 0, x, v, 0, &err) != 0, "zero mass accepted");
    CHECK(mote_nb_add(&nb, -1, 0, x, v, 0, &err) != 0, "negative mass accepted");
    mote_nb_add(&nb, 1, 0, x, v, 0, &err);
    mote_nb_add(&nb, 1, 0, y, v, 0, &err);
    CHECK(mote_nb_galactica(&nb, 1, &err) != 0 && strstr(err.msg, "charge"),
          "an uncharged Coulomb run: %s", err.msg);
    mote_nb_free(&nb);
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    CHECK(mote_nb_galactica(&nb, 1, &err) != 0, "a run without bodies");
    mote_nb_add(&nb, 1, 0, x, v, 0, &err);
    mote_nb_add(&nb, 1, 0, x, v, 0, &err);
    CHECK(mote_nb_galactica(&nb, 1, &err) != 0 && strstr(err.msg, "same point"),
          "two bodies at one point: %s", err.msg);
    mote_nb_free(&nb);
}

/* T09: the Taylor recurrences against the explicit derivatives, store = recompute, and the
 * error falling with the order at a fixed step. */
static void test_taylor(void)
{
    printf("T09: Taylor recurrences (spec 4.4)\n");
    for (int kind = 0; kind < 2; kind++) {
        double worst = 0;
        for (int trial = 0; trial < 5; trial++) {
            mote_nb nb;
            mote_nb_init(&nb, kind ? MOTE_NB_COULOMB : MOTE_NB_GRAVITY);
            mote_rng g;
            mote_rng_seed(&g, (uint64_t)(100 + 10 * kind + trial));
            mote_err err = {0};
            for (int b = 0; b < 4; b++) {
                double x[3], v[3];
                for (int a = 0; a < 3; a++) {
                    x[a] = 2 * mote_rng_uniform(&g) - 1;
                    v[a] = mote_rng_uniform(&g) - 0.5;
                }
                mote_nb_add(&nb, 0.1 + mote_rng_uniform(&g), kind ? (b % 2 ? 1 : -1) : 0, x, v, 0,
                            &err);
            }
            CHECK(mote_nb_derivatives(&nb, &err) == MOTE_OK, "derivatives: %s", err.msg);
            double X[8 * 12];
            mote_nb_taylor_coefficients(&nb, 7, 0, X);
            const double *ref[4] = {nb.acc, nb.jerk, nb.d4, nb.d5};
            const double fact[4] = {2, 6, 24, 120};
            for (int o = 0; o < 4; o++)
                for (int q = 0; q < 12; q++) {
                    double want = ref[o][q] / fact[o], got = X[(o + 2) * 12 + q];
                    double scale = 0;
                    for (int r = 0; r < 12; r++)
                        scale = fmax(scale, fabs(ref[o][r] / fact[o]));
                    worst = fmax(worst, fabs(got - want) / scale);
                }
            mote_nb_free(&nb);
        }
        printf("  %s: x^[2..5] from the recurrences against the explicit formulas: %.2e\n",
               kind ? "Coulomb" : "gravity", worst);
        CHECK(worst <= 1e-13, "%s: recurrences differ by %.3g", kind ? "Coulomb" : "gravity",
              worst);
    }
    /* store and recompute: the same bits */
    double *ref = NULL;
    for (int mem = 1; mem <= 2; mem++) {
        mote_nb nb;
        mote_nb_ring r;
        mote_nb_init(&nb, MOTE_NB_GRAVITY);
        mote_nb_ring_defaults(&r, MOTE_NB_GRAVITY);
        mote_err err = {0};
        mote_nb_ring_build(&nb, &r, &err);
        nb.taylor_order = 12;
        nb.taylor_memory = mem;
        nb.dt = 1e-4;
        CHECK(mote_nb_taylor(&nb, 20, &err) == MOTE_OK, "taylor: %s", err.msg);
        CHECK(mote_nb_taylor_memory_store(&nb, 12) == (mem == 1), "memory mode %d", mem);
        if (!ref) {
            ref = malloc(6 * (size_t)nb.n * sizeof *ref);
            memcpy(ref, nb.x, 3 * (size_t)nb.n * sizeof *ref);
            memcpy(ref + 3 * (size_t)nb.n, nb.v, 3 * (size_t)nb.n * sizeof *ref);
        } else {
            CHECK(memcmp(ref, nb.x, 3 * (size_t)nb.n * sizeof *ref) == 0 &&
                      memcmp(ref + 3 * (size_t)nb.n, nb.v, 3 * (size_t)nb.n * sizeof *ref) == 0,
                  "store and recompute differ");
        }
        mote_nb_free(&nb);
    }
    free(ref);
    /* fixed step 1e-4 (100 steps per period) on the ring: the error against the order */
    double e[11] = {0};
    for (int p = 4; p <= 10; p += 2) {
        mote_nb nb;
        mote_nb_ring r;
        mote_nb_init(&nb, MOTE_NB_GRAVITY);
        mote_nb_ring_defaults(&r, MOTE_NB_GRAVITY);
        mote_err err = {0};
        mote_nb_ring_build(&nb, &r, &err);
        nb.taylor_order = p;
        nb.dt = 1e-4;
        mote_nb_taylor(&nb, 100, &err);
        e[p] = mote_nb_ring_error(&nb, &r, NULL);
        mote_nb_free(&nb);
    }
    printf("  ring, h = 1e-4, 100 steps: error p=4 %.2e, 6 %.2e, 8 %.2e, 10 %.2e\n", e[4], e[6],
           e[8], e[10]);
    for (int p = 4; p <= 8; p += 2)
        CHECK(e[p + 2] <= 1e-12 || e[p] / e[p + 2] >= pow(10, 2.5),
              "p %d -> %d: error %.3g -> %.3g (less than 10^2.5 better, above 1e-12)", p, p + 2,
              e[p], e[p + 2]);
    CHECK(mote_nb_taylor_auto_order(1e-16) == 20 && mote_nb_taylor_auto_order(1e-19) == 23 &&
              mote_nb_taylor_auto_order(1e-34) == 41,
          "order=auto: %d %d %d", mote_nb_taylor_auto_order(1e-16),
          mote_nb_taylor_auto_order(1e-19), mote_nb_taylor_auto_order(1e-34));
}

/* T10: the adaptive Taylor integrator on the ring, one and ten periods, ending exactly. */
static void test_adaptive(void)
{
    printf("T10: adaptive Taylor, p = 20, tol = 1e-16\n");
    for (int periods = 1; periods <= 10; periods += 9) {
        mote_nb nb;
        mote_nb_ring r;
        mote_nb_init(&nb, MOTE_NB_GRAVITY);
        mote_nb_ring_defaults(&r, MOTE_NB_GRAVITY);
        mote_err err = {0};
        mote_nb_ring_build(&nb, &r, &err);
        nb.integrator = MOTE_NB_TAYLOR;
        nb.taylor_order = 20;
        nb.adaptive = 1;
        nb.tol = 1e-16;
        double t_end = periods * r.period;
        CHECK(mote_nb_integrate(&nb, UINT64_MAX, t_end, &err) == MOTE_OK, "run: %s", err.msg);
        double e = mote_nb_ring_error(&nb, &r, NULL);
        mote_nb_monitor mon;
        mote_nb_measure(&nb, &mon);
        printf("  %d period%s: %llu steps, error %.3e, dE %.3e, T exact: %s\n", periods,
               periods > 1 ? "s" : "", (unsigned long long)nb.steps, e, mon.dE,
               nb.T == t_end ? "yes" : "no");
        CHECK(nb.T == t_end, "T = %.17g, expected %.17g", nb.T, t_end);
        CHECK(e <= (periods == 1 ? 1e-12 : 1e-11), "%d periods: error %.3g", periods, e);
        CHECK(fabs(mon.dE) <= 1e-14, "%d periods: dE %.3g", periods, mon.dE);
        if (periods == 1)
            CHECK(nb.steps <= 50, "one period took %llu steps (at most 50)",
                  (unsigned long long)nb.steps);
        mote_nb_free(&nb);
    }
}

/* n equal masses (total 1) at random in the unit cube about the origin, velocities within
 * +-0.05 (gravity; the seed's stream). */
static void random_cluster(mote_nb *nb, uint32_t n, uint64_t seed)
{
    mote_nb_init(nb, MOTE_NB_GRAVITY);
    mote_rng g;
    mote_rng_seed(&g, seed);
    mote_err err = {0};
    int rc = MOTE_OK;
    for (uint32_t i = 0; i < n && !rc; i++) {
        double x[3], v[3];
        for (int a = 0; a < 3; a++) {
            x[a] = mote_rng_uniform(&g) - 0.5;
            v[a] = 0.1 * (mote_rng_uniform(&g) - 0.5);
        }
        rc = mote_nb_add(nb, 1.0 / n, 0, x, v, 0, &err);
    }
    CHECK(rc == MOTE_OK && nb->n == n, "random cluster: %s", err.msg);
}

/* T17: 1, 2 and 4 threads give the same bits (a cluster large enough to be split). */
static void test_threads(void)
{
    printf("T17: 1, 2 and 4 threads bit-identical (Galactica scheme, then Taylor)\n");
    const uint32_t n = 300;
    double *ref = NULL;
    for (int t = 1; t <= 4; t *= 2) {
        mote_nb nb;
        mote_err err = {0};
        random_cluster(&nb, n, 5);
        nb.dt = 1e-5;
        nb.threads = t;
        nb.threads_min_n = 64; /* (below the default: these systems are split among threads) */
        CHECK(mote_nb_galactica(&nb, getenv("MOTE_SANITIZED") ? 10 : 50, &err) == MOTE_OK, "run: %s",
              err.msg);
        /* then the Taylor integrator, whose pairs are shared among the threads */
        nb.taylor_order = 8;
        nb.dt = 1e-4;
        CHECK(mote_nb_taylor(&nb, 3, &err) == MOTE_OK, "taylor: %s", err.msg);
        if (!ref) {
            ref = malloc(6 * (size_t)n * sizeof *ref);
            memcpy(ref, nb.x, 3 * (size_t)n * sizeof *ref);
            memcpy(ref + 3 * (size_t)n, nb.v, 3 * (size_t)n * sizeof *ref);
        } else {
            CHECK(memcmp(ref, nb.x, 3 * (size_t)n * sizeof *ref) == 0 &&
                      memcmp(ref + 3 * (size_t)n, nb.v, 3 * (size_t)n * sizeof *ref) == 0,
                  "%d threads differ from one", t);
        }
        mote_nb_free(&nb);
    }
    free(ref);
}

/* The Taylor integrator's pair kernel on 1, 2, 4 and 8 pairs at once (as far as the processor
 * runs them: SSE2, AVX2, AVX-512F) gives the same bits; some bodies inactive, so that the
 * kernels hand the rest of a row to narrower ones. */
static void test_lanes(void)
{
    printf("the Taylor pair kernel on 1, 2, 4 and 8 lanes bit-identical\n");
    const uint32_t n = 61;
    double *ref = NULL;
    for (int w = 1; w <= 8; w *= 2) {
        mote_nb nb;
        mote_err err = {0};
        random_cluster(&nb, n, 11);
        for (uint32_t i = 5; i < n; i += 13)
            nb.active[i] = 0;
        nb.simd = w;
        nb.soft = 0.05; /* the softening's term in the kernel too */
        nb.taylor_order = 20;
        nb.taylor_memory = 1; /* store: the mode with the pair kernels */
        nb.dt = 1e-3;
        /* every coefficient of every order (a last bit of a high order would not show in a
         * step), then the state after three steps */
        const size_t nc = 21 * 3 * (size_t)n, nx = 3 * (size_t)n;
        double *X = calloc(nc + 2 * nx, sizeof *X); /* (inactive bodies: zeros) */
        CHECK(mote_nb_prepare(&nb, &err) == MOTE_OK &&
                  mote_nb_taylor_coefficients(&nb, 20, 1, X) == MOTE_OK, "coefficients");
        CHECK(mote_nb_taylor(&nb, 3, &err) == MOTE_OK, "taylor: %s", err.msg);
        memcpy(X + nc, nb.x, nx * sizeof *X);
        memcpy(X + nc + nx, nb.v, nx * sizeof *X);
        if (!ref)
            ref = X;
        else {
            CHECK(memcmp(ref, X, nc * sizeof *X) == 0, "%d lanes: coefficients differ from one",
                  w);
            CHECK(memcmp(ref + nc, X + nc, 2 * nx * sizeof *X) == 0,
                  "%d lanes: the state differs from one", w);
            free(X);
        }
        mote_nb_free(&nb);
    }
    free(ref);
}

/* ---- T13: merging (spec 5) ---- */

typedef struct {
    double m, q, vol, P[3], L[3], pnorm, lnorm;
} conserved;

static conserved conserved_of(const mote_nb *nb)
{
    conserved c = {0};
    mote_nb_monitor mon;
    mote_nb_measure(nb, &mon);
    for (uint32_t i = 0; i < nb->n; i++) {
        c.m += nb->m[i];
        c.q += nb->q[i];
        c.vol += nb->ra[i] * nb->ra[i] * nb->ra[i];
        const double *x = nb->x + 3 * (size_t)i, *v = nb->v + 3 * (size_t)i;
        double l[3] = {x[1] * v[2] - x[2] * v[1], x[2] * v[0] - x[0] * v[2], x[0] * v[1] - x[1] * v[0]};
        c.pnorm += nb->m[i] * sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        c.lnorm += nb->m[i] * sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
        const double *sp = nb->sp + 3 * (size_t)i;
        c.lnorm += sqrt(sp[0] * sp[0] + sp[1] * sp[1] + sp[2] * sp[2]);
    }
    for (int a = 0; a < 3; a++) {
        c.P[a] = mon.P[a];
        c.L[a] = mon.L[a] + mon.S[a];
    }
    return c;
}

/* Mass, charge, momentum and L + S to 1e-15 relative; the volume to rounding (a cube root and a
 * cube per merge: a few ulps). */
static void check_conserved(const char *what, const conserved *a, const conserved *b)
{
    CHECK(fabs(b->m - a->m) <= 1e-15 * a->m, "%s: mass %.17g -> %.17g", what, a->m, b->m);
    CHECK(fabs(b->q - a->q) <= 1e-15 * (fabs(a->q) + a->m), "%s: charge %.17g -> %.17g", what, a->q,
          b->q);
    CHECK(fabs(b->vol - a->vol) <= 2e-15 * a->vol, "%s: volume %.17g -> %.17g", what, a->vol, b->vol);
    for (int k = 0; k < 3; k++) {
        CHECK(fabs(b->P[k] - a->P[k]) <= 1e-15 * a->pnorm, "%s: P[%d] %.17g -> %.17g", what, k,
              a->P[k], b->P[k]);
        CHECK(fabs(b->L[k] - a->L[k]) <= 1e-15 * a->lnorm, "%s: (L+S)[%d] %.17g -> %.17g", what, k,
              a->L[k], b->L[k]);
    }
}

/* Eq. 11 for bodies i, k as they are now. */
static double eq11(const mote_nb *nb, uint32_t i, uint32_t k)
{
    double r[3], u[3];
    for (int a = 0; a < 3; a++) {
        r[a] = nb->x[3 * k + a] - nb->x[3 * i + a];
        u[a] = nb->v[3 * k + a] - nb->v[3 * i + a];
    }
    double rr = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    double vr = (r[0] * u[0] + r[1] * u[1] + r[2] * u[2]) / rr;
    return nb->m[i] * nb->m[k] * vr * vr / (2 * (nb->m[i] + nb->m[k]));
}

static void test_merging(void)
{
    printf("T13: merging (spec 5)\n");
    mote_err err = {0};
    /* head-on and grazing: A (m 2, q 1, Ra 0.2) meets B (m 1, q -0.5, Ra 0.1) */
    for (int graze = 0; graze < 2; graze++) {
        mote_nb nb;
        mote_nb_init(&nb, MOTE_NB_GRAVITY);
        double xa[3] = {0.3, -0.1, 0.2}, va[3] = {0.1, 0.02, 0};
        double xb[3] = {0.55, graze ? 0.05 : -0.1, 0.2}, vb[3] = {-0.3, graze ? 0.05 : 0.02, 0};
        mote_nb_add(&nb, 2, 1, xa, va, 0.2, &err);
        mote_nb_add(&nb, 1, -0.5, xb, vb, 0.1, &err);
        conserved c0 = conserved_of(&nb);
        double heat = eq11(&nb, 0, 1);
        CHECK(mote_nb_merge(&nb, &err) == MOTE_OK, "merge: %s", err.msg);
        const char *what = graze ? "grazing" : "head-on";
        conserved c1 = conserved_of(&nb);
        check_conserved(what, &c0, &c1);
        CHECK(nb.merges == 1 && nb.active[0] && !nb.active[1] && nb.m[0] == 3 && nb.m[1] == 0 &&
                  nb.q[0] == 0.5 && nb.ra[1] == 0,
              "%s: merges %llu, survivor m %g q %g, lost m %g", what, (unsigned long long)nb.merges,
              nb.m[0], nb.q[0], nb.m[1]);
        CHECK(nb.et[0] == heat && nb.e_heat == heat, "%s: E_t %.17g, eq. 11 gives %.17g", what,
              nb.et[0], heat);
        double s2 = nb.sp[0] * nb.sp[0] + nb.sp[1] * nb.sp[1] + nb.sp[2] * nb.sp[2];
        CHECK(graze ? s2 > 0 && nb.e_spin > 0 : s2 == 0 && nb.e_spin == 0,
              "%s: spin %.3g, E_spin %.3g", what, sqrt(s2), nb.e_spin);
        /* the merged body moves on with the pair's centre of mass velocity */
        CHECK(fabs(nb.v[0] - (2 * va[0] + vb[0]) / 3) <= 1e-16, "%s: vx %.17g", what, nb.v[0]);
        mote_nb_free(&nb);
    }
    /* a chain: A touches B, B touches C; the closer pair (A, B) merges first, B is then taken
     * for this sweep, and the grown body reaches C in a second sweep */
    {
        mote_nb nb;
        mote_nb_init(&nb, MOTE_NB_GRAVITY);
        double v[3] = {0, 0, 0}, x0[3] = {0.06, 0, 0}, x1[3] = {0.19, 0, 0}, x2[3] = {0.36, 0, 0};
        mote_nb_add(&nb, 1, 0, x0, v, 0.1, &err);
        mote_nb_add(&nb, 1.5, 0, x1, v, 0.1, &err);
        mote_nb_add(&nb, 1, 0, x2, v, 0.1, &err);
        conserved c0 = conserved_of(&nb);
        CHECK(mote_nb_merge(&nb, &err) == MOTE_OK, "merge: %s", err.msg);
        conserved c1 = conserved_of(&nb);
        check_conserved("chain", &c0, &c1);
        CHECK(nb.merges == 2 && !nb.active[0] && nb.active[1] && !nb.active[2] && nb.m[1] == 3.5,
              "chain: merges %llu, active %d %d %d, m %g", (unsigned long long)nb.merges,
              nb.active[0], nb.active[1], nb.active[2], nb.m[1]);
        mote_nb_free(&nb);
    }
    /* in flight: two bodies fall together under gravity (adaptive Taylor). E_corr is continuous
     * through the merge: its jump over the merging step is no larger than the integration error
     * of a step (about 1e-14 here), well within the spec's 1e-13. The pair's internal energy
     * E_rel = mu u^2 / 2 - m1 m2 / r, conserved along the orbit, is what the merge takes out:
     * dE_merge = -E_rel, to the integration error. */
    {
        mote_nb nb;
        mote_nb_init(&nb, MOTE_NB_GRAVITY);
        double x0[3] = {-0.5, 0, 0}, x1[3] = {0.5, 0, 0}, v0[3] = {0, -0.04, 0}, v1[3] = {0, 0.06, 0};
        mote_nb_add(&nb, 0.6, 0, x0, v0, 0.05, &err);
        mote_nb_add(&nb, 0.4, 0, x1, v1, 0.04, &err);
        const double erel = 0.5 * 0.24 * 0.1 * 0.1 - 0.24;
        nb.integrator = MOTE_NB_TAYLOR;
        nb.adaptive = 1;
        nb.tol = 1e-16;
        double prev = 0, jump = 0;
        uint64_t s = 0;
        for (; s < 1000 && nb.merges == 0; s++) {
            CHECK(mote_nb_integrate(&nb, 1, INFINITY, &err) == MOTE_OK, "run: %s", err.msg);
            mote_nb_monitor mon;
            mote_nb_measure(&nb, &mon);
            jump = fabs(mon.dE - prev);
            prev = mon.dE;
        }
        CHECK(nb.merges == 1, "no merge after %llu steps", (unsigned long long)s);
        CHECK(mote_nb_integrate(&nb, 5, INFINITY, &err) == MOTE_OK, "after: %s", err.msg);
        mote_nb_monitor mon;
        mote_nb_measure(&nb, &mon);
        printf("  two bodies fall together: merged at step %llu, dE jump there %.3e, after %.3e, "
               "dE_merge %.17g (-E_rel %.17g)\n", (unsigned long long)s, jump, mon.dE, nb.de_merge,
               -erel);
        CHECK(jump <= 1e-13, "E_corr jumped by %.3g over the merging step", jump);
        CHECK(mon.dE == prev, "E_corr changed after the merge: %.3g -> %.3g", prev, mon.dE);
        CHECK(fabs(nb.de_merge + erel) <= 1e-12 * fabs(erel), "dE_merge %.17g, expected %.17g",
              nb.de_merge, -erel);
        mote_nb_free(&nb);
    }
    /* a cluster with many merges: 1 and 4 threads give the same bits */
    double *ref = NULL;
    uint64_t ref_merges = 0;
    for (int t = 1; t <= 4; t *= 4) {
        mote_nb nb;
        mote_nb_init(&nb, MOTE_NB_GRAVITY);
        mote_rng g;
        mote_rng_seed(&g, 13);
        const uint32_t n = 200;
        for (uint32_t i = 0; i < n; i++) {
            double x[3], v[3] = {0, 0, 0};
            for (int a = 0; a < 3; a++)
                x[a] = mote_rng_uniform(&g) - 0.5;
            mote_nb_add(&nb, 1.0 / n, 0, x, v, 0.02, &err);
        }
        conserved c0 = conserved_of(&nb);
        nb.dt = 1e-3;
        nb.threads = t;
        nb.threads_min_n = 64; /* (below the default: these systems are split among threads) */
        CHECK(mote_nb_galactica(&nb, getenv("MOTE_SANITIZED") ? 20 : 100, &err) == MOTE_OK,
              "cluster: %s", err.msg);
        conserved c1 = conserved_of(&nb);
        CHECK(fabs(c1.m - c0.m) <= 1e-15 * c0.m && fabs(c1.vol - c0.vol) <= 1e-14 * c0.vol,
              "cluster: mass %.17g -> %.17g, volume %.17g -> %.17g", c0.m, c1.m, c0.vol, c1.vol);
        if (!ref) {
            printf("  cluster of %u: %llu merges\n", n, (unsigned long long)nb.merges);
            CHECK(nb.merges >= 5, "cluster: only %llu merges", (unsigned long long)nb.merges);
            ref_merges = nb.merges;
            ref = malloc(6 * (size_t)n * sizeof *ref);
            memcpy(ref, nb.x, 3 * (size_t)n * sizeof *ref);
            memcpy(ref + 3 * (size_t)n, nb.v, 3 * (size_t)n * sizeof *ref);
        } else {
            CHECK(nb.merges == ref_merges && memcmp(ref, nb.x, 3 * (size_t)n * sizeof *ref) == 0 &&
                      memcmp(ref + 3 * (size_t)n, nb.v, 3 * (size_t)n * sizeof *ref) == 0,
                  "cluster: %d threads differ from one", t);
        }
        mote_nb_free(&nb);
    }
    free(ref);
}

/* Spec 9.3: the Solar-System builder on the shipped outer-Solar-System file (Hairer, Lubich &
 * Wanner): units, the barycentre, the relative positions in AU recovered, and ten centuries of
 * motion with the adaptive Taylor integrator. */
static void test_solar(void)
{
    printf("Solar System builder (spec 9.3), data/outer_solar_system.dat\n");
    mote_nb_solar s;
    mote_err err = {0};
    if (mote_nb_solar_read("data/outer_solar_system.dat", &s, &err)) {
        CHECK(0, "read: %s", err.msg);
        return;
    }
    CHECK(s.n == 6 && strcmp(s.b[1].name, "Jupiter") == 0, "%d bodies", s.n);
    /* Pluto's mass is written 1/1.3e8 */
    CHECK(fabs(s.b[5].gm / s.b[0].gm - 1 / 1.3e8 / 1.00000597682) <= 1e-15 / 1.3e8,
          "Pluto / Sun mass %.17g", s.b[5].gm / s.b[0].gm);
    mote_nb nb;
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    CHECK(mote_nb_solar_build(&nb, &s, NULL, 0, &err) == MOTE_OK, "build: %s", err.msg);
    double mt = 0, P[3] = {0, 0, 0}, R[3] = {0, 0, 0};
    for (uint32_t i = 0; i < nb.n; i++) {
        mt += nb.m[i];
        for (int a = 0; a < 3; a++) {
            P[a] += nb.m[i] * nb.v[3 * i + a];
            R[a] += nb.m[i] * nb.x[3 * i + a];
        }
    }
    CHECK(fabs(mt - 1) <= 4e-16, "total mass %.17g", mt);
    CHECK(fabs(P[0]) + fabs(P[1]) + fabs(P[2]) <= 1e-17 && fabs(R[0]) + fabs(R[1]) + fabs(R[2]) <= 1e-15,
          "not barycentric: P %.3g, R %.3g", fabs(P[0]) + fabs(P[1]) + fabs(P[2]),
          fabs(R[0]) + fabs(R[1]) + fabs(R[2]));
    CHECK(nb.u.Am == 1.0 / (nb.u.kt * nb.u.kv), "Am not refined");
    /* Jupiter relative to the Sun, back in AU and AU/day, as in the file */
    const double xj[3] = {-3.5023653, -3.8169847, -1.5507963}, vj[3] = {0.00565429, -0.00412490, -0.00190589};
    double worst = 0;
    for (int a = 0; a < 3; a++) {
        double x = (nb.x[3 + a] - nb.x[a]) * nb.u.Am / MOTE_NB_AU;
        double v = (nb.v[3 + a] - nb.v[a]) / nb.u.kv / MOTE_NB_AU * 86400;
        worst = fmax(worst, fmax(fabs(x - xj[a]) / 5.5, fabs(v - vj[a]) / 0.0076));
    }
    CHECK(worst <= 1e-14, "Jupiter's heliocentric state back-converted: relative error %.3g", worst);
    /* bodies= and a missing name */
    mote_nb sub;
    mote_nb_init(&sub, MOTE_NB_GRAVITY);
    CHECK(mote_nb_solar_build(&sub, &s, "Sun,Jupiter", 0, &err) == MOTE_OK && sub.n == 2,
          "bodies=Sun,Jupiter: %u bodies (%s)", sub.n, err.msg);
    mote_nb_free(&sub);
    mote_nb_init(&sub, MOTE_NB_GRAVITY);
    CHECK(mote_nb_solar_build(&sub, &s, "Sun,Vulcan", 0, &err) != MOTE_OK && strstr(err.msg, "Vulcan"),
          "an unknown body accepted");
    mote_nb_free(&sub);
    mote_nb_solar_free(&s);
    /* ten centuries: Jupiter stays between its perihelion and aphelion (4.95 and 5.46 AU),
     * energy and angular momentum are kept */
    nb.integrator = MOTE_NB_TAYLOR;
    nb.adaptive = 1;
    nb.taylor_order = 22;
    nb.tol = 1e-18;
    double rmin = 1e9, rmax = 0;
    for (int k = 1; k <= 100; k++) {
        CHECK(mote_nb_integrate(&nb, UINT64_MAX, 0.1 * k, &err) == MOTE_OK, "run: %s", err.msg);
        double r2 = 0;
        for (int a = 0; a < 3; a++)
            r2 += (nb.x[3 + a] - nb.x[a]) * (nb.x[3 + a] - nb.x[a]);
        double r = sqrt(r2) * nb.u.Am / MOTE_NB_AU;
        rmin = fmin(rmin, r);
        rmax = fmax(rmax, r);
    }
    mote_nb_monitor mon;
    mote_nb_measure(&nb, &mon);
    printf("  1000 years: %llu steps, Jupiter at %.4f .. %.4f AU, dE %.3e, dMz %.3e\n",
           (unsigned long long)nb.steps, rmin, rmax, mon.dE, mon.dMz);
    CHECK(rmin > 4.9 && rmin < 5.0 && rmax > 5.4 && rmax < 5.5, "Jupiter between %.4f and %.4f AU",
          rmin, rmax);
    CHECK(fabs(mon.dE) <= 1e-14 && fabs(mon.dMz) <= 1e-14, "dE %.3g, dMz %.3g", mon.dE, mon.dMz);
    mote_nb_free(&nb);
}


/* T12 (spec 11): the Solar-System builder on the shipped J2000 state (JPL Horizons, DE441): the
 * total mass is the unit, the centre of mass rests at the origin, the Earth, the Moon and Jupiter
 * are where they should be, and the invariable plane is tilted by the obliquity from the equator
 * of the ICRF axes. The bounds are the spec's. */
static void test_t12_file(const char *path, uint32_t nbodies)
{
    printf("T12 Solar-System builder, %s\n", path);
    FILE *f = fopen(path, "r");
    char line[256];
    int source = 0;
    while (f && fgets(line, sizeof line, f) && line[0] == '#')
        source |= strncmp(line, "# source: ", 10) == 0 && strlen(line) > 40;
    if (f)
        fclose(f);
    CHECK(source, "no '# source:' line");
    mote_nb_solar s;
    mote_err err = {0};
    if (mote_nb_solar_read(path, &s, &err)) {
        CHECK(0, "read: %s", err.msg);
        return;
    }
    mote_nb nb;
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    CHECK(mote_nb_solar_build(&nb, &s, NULL, 0, &err) == MOTE_OK, "build: %s", err.msg);
    int sun = -1, earth = -1, moon = -1, jupiter = -1;
    for (int i = 0; i < s.n; i++) {
        sun = strcmp(s.b[i].name, "Sun") ? sun : i;
        earth = strcmp(s.b[i].name, "Earth") ? earth : i;
        moon = strcmp(s.b[i].name, "Moon") ? moon : i;
        jupiter = strcmp(s.b[i].name, "Jupiter") ? jupiter : i;
    }
    CHECK(nb.n == nbodies && sun == 0 && earth == 3 && moon == 4 && jupiter == 6,
          "%u bodies, order Sun %d Earth %d Moon %d Jupiter %d", nb.n, sun, earth, moon, jupiter);
    mote_nb_solar_free(&s);
    if (nb.n != nbodies) {
        mote_nb_free(&nb);
        return;
    }
    double mt = 0, R[3] = {0, 0, 0}, L[3] = {0, 0, 0};
    for (uint32_t i = 0; i < nb.n; i++) {
        const double *x = &nb.x[3 * i], *v = &nb.v[3 * i];
        mt += nb.m[i];
        for (int a = 0; a < 3; a++)
            R[a] += nb.m[i] * x[a];
        L[0] += nb.m[i] * (x[1] * v[2] - x[2] * v[1]);
        L[1] += nb.m[i] * (x[2] * v[0] - x[0] * v[2]);
        L[2] += nb.m[i] * (x[0] * v[1] - x[1] * v[0]);
    }
    CHECK(fabs(mt - 1) <= 4.5e-16, "sum of masses %.17g", mt);
    const double rcm = sqrt(R[0] * R[0] + R[1] * R[1] + R[2] * R[2]);
    CHECK(rcm <= 1e-17, "centre of mass at %.3g", rcm);
    double d[3][3];
    const int pair[3][2] = {{earth, sun}, {moon, earth}, {jupiter, sun}};
    for (int k = 0; k < 3; k++)
        for (int a = 0; a < 3; a++)
            d[k][a] = (nb.x[3 * pair[k][0] + a] - nb.x[3 * pair[k][1] + a]) * nb.u.Am;
    const double es = sqrt(d[0][0] * d[0][0] + d[0][1] * d[0][1] + d[0][2] * d[0][2]) / MOTE_NB_AU;
    const double em = sqrt(d[1][0] * d[1][0] + d[1][1] * d[1][1] + d[1][2] * d[1][2]) / 1e3;
    const double js = sqrt(d[2][0] * d[2][0] + d[2][1] * d[2][1] + d[2][2] * d[2][2]) / MOTE_NB_AU;
    CHECK(es >= 0.983 && es <= 1.017, "Earth-Sun %.6f AU", es);
    CHECK(em >= 356000 && em <= 407000, "Earth-Moon %.1f km", em);
    CHECK(js >= 4.95 && js <= 5.46, "Jupiter-Sun %.6f AU", js);
    const double tilt = acos(L[2] / sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2])) * 45 / atan(1.0);
    CHECK(tilt >= 22.8 && tilt <= 23.2, "invariable plane tilted %.4f deg from the equator", tilt);
    printf("  sum m - 1 = %.2g, |R_cm| = %.2g, Earth-Sun %.5f AU, Earth-Moon %.0f km, "
           "Jupiter-Sun %.4f AU, tilt %.4f deg\n", mt - 1, rcm, es, em, js, tilt);
    mote_nb_free(&nb);
}

/* The DE405 file gives the Earth-Moon barycentre and the geocentric Moon (spec 9.3): the reader
 * splits them with EMRAT, so the Earth and the Moon have the EMB's mass and barycentre and the
 * Moon's geocentric offset, and their mass ratio is EMRAT. */
static void test_emb_split(void)
{
    mote_nb_solar s;
    mote_err err = {0};
    if (mote_nb_solar_read("data/solar_system_de405.dat", &s, &err)) {
        CHECK(0, "read: %s", err.msg);
        return;
    }
    const double au = MOTE_NB_AU, day = 86400, gmu = au * au * au / (day * day);
    const double emb[6] = {0.12051741729540039, -0.9258384789394528, -0.401540220801811,
                           0.016811268303992644, 0.0017483093133816164, 0.0007582028689905378};
    const double moon[3] = {-0.0008081773279114842, -0.0019946300016203994, -0.0010872626608381018};
    const mote_nb_sbody *e = &s.b[3], *m = &s.b[4];
    CHECK(s.n == 11 && !strcmp(e->name, "Earth") && !strcmp(m->name, "Moon"), "bodies 4, 5: %s %s",
          s.n > 4 ? e->name : "?", s.n > 4 ? m->name : "?");
    double worst = 0;
    for (int a = 0; a < 3; a++) {
        double xb = (e->gm * e->x[a] + m->gm * m->x[a]) / (e->gm + m->gm) / au;
        double vb = (e->gm * e->v[a] + m->gm * m->v[a]) / (e->gm + m->gm) / au * day;
        worst = fmax(worst, fabs(xb - emb[a]) / fabs(emb[a]));
        worst = fmax(worst, fabs(vb - emb[3 + a]) / fabs(emb[3 + a]));
        worst = fmax(worst, fabs((m->x[a] - e->x[a]) / au - moon[a]) / fabs(moon[a]));
    }
    const double ratio = e->gm / m->gm, gmb = (e->gm + m->gm) / gmu;
    CHECK(worst < 1e-12, "EMB and the geocentric Moon back from the split: %.3g", worst);
    CHECK(fabs(ratio / 81.30056 - 1) < 1e-13 && fabs(gmb / 8.997011346712499e-10 - 1) < 1e-14,
          "Earth/Moon %.15g, GM(EMB) %.17g AU^3/day^2", ratio, gmb);
    printf("  DE405 EMB split: Earth/Moon mass ratio %.10g, EMB and Moon back to %.2g\n", ratio,
           worst);
    mote_nb_solar_free(&s);
}

static void test_t12(void)
{
    test_t12_file("data/solar_system_j2000.dat", 10);
    test_t12_file("data/solar_system_de405.dat", 11);
    test_emb_split();
}

/* Spec 4.7: the close-approach control of the Galactica scheme. Two bodies (radii 0.01) meet
 * head-on at a closing speed of about 20 while dt = 1e-2: a step moves them 0.2, ten times the
 * sum of their radii. Without the control (bt = 1) they merge deeply overlapped or pass
 * through; with bt = 0.5 the merge happens within 10% of contact and the step returns to dt
 * afterwards. (The rule extrapolates to second order: a slow fall from rest, whose acceleration
 * grows as 1/r^2 in the last step, can still overshoot; docs/nbody.md says so.) */
static void test_approach(void)
{
    printf("close approaches (spec 4.7): a head-on meeting at speed 20, dt = 1e-2\n");
    double ovl[2] = {0, 0};
    for (int control = 0; control < 2; control++) {
        mote_nb nb;
        mote_nb_init(&nb, MOTE_NB_GRAVITY);
        mote_err err = {0};
        double x0[3] = {-0.5, 0, 0}, x1[3] = {0.5, 0, 0}, v0[3] = {10, 0, 0}, v1[3] = {-10, 0, 0};
        mote_nb_add(&nb, 0.5, 0, x0, v0, 0.01, &err);
        mote_nb_add(&nb, 0.5, 0, x1, v1, 0.01, &err);
        nb.dt = 1e-2;
        nb.bt = control ? 0.5 : 1;
        uint64_t s = 0;
        for (; s < 10000 && nb.merges == 0 && nb.T < 3; s++)
            CHECK(mote_nb_galactica(&nb, 1, &err) == MOTE_OK, "run: %s", err.msg);
        double hmerge = nb.hlast;
        CHECK(mote_nb_galactica(&nb, 40, &err) == MOTE_OK, "after: %s", err.msg);
        ovl[control] = nb.max_overlap;
        printf("  bt = %.1f: merges %llu after %llu steps (last step %.3g), overlap %.3f of the "
               "radii, step 40 steps later %.3g\n", nb.bt, (unsigned long long)nb.merges,
               (unsigned long long)s, hmerge, nb.max_overlap, nb.hlast);
        if (control) {
            CHECK(nb.merges == 1 && nb.max_overlap <= 0.1, "with the control: merges %llu, overlap %.3g",
                  (unsigned long long)nb.merges, nb.max_overlap);
            CHECK(hmerge < 1e-3 && nb.hlast == nb.dt && nb.happ == 0,
                  "the step: %.3g at the merge, %.3g later (happ %.3g)", hmerge, nb.hlast, nb.happ);
            CHECK(nb.approach_warnings == 0, "%llu warnings", (unsigned long long)nb.approach_warnings);
        }
        mote_nb_free(&nb);
    }
    CHECK(ovl[0] > 0.1 || ovl[0] == 0, "without the control the merge was accurate anyway (%.3g)",
          ovl[0]);
}

/* T26: the orbit picture. A body on a circle of radius 1 about the origin (a trajectory file
 * written exactly), plotted: a valid PNG (signature, IHDR first with the size plot.c asks for,
 * IEND last), and the coloured pixels that are not the legend or the centre lie on one circle
 * (equal scales on both axes), with a coloured pixel within 3 px of it in at least 355 of 360
 * directions. */
static int coloured(const unsigned char *p) /* cairo ARGB32: B G R A in memory (little endian) */
{
    int mx = p[0] > p[1] ? (p[0] > p[2] ? p[0] : p[2]) : (p[1] > p[2] ? p[1] : p[2]);
    int mn = p[0] < p[1] ? (p[0] < p[2] ? p[0] : p[2]) : (p[1] < p[2] ? p[1] : p[2]);
    return mx - mn > 60;
}
/* The orbit picture: a circle of coloured pixels. drift = 1: body 1 moves along x while body 2
 * circles it, drawn with relative_to=1, which must give the same circle. */
static void test_png_case(int drift)
{
    char dir[256], data[320], png[320];
    if (!test_tmpdir_make(dir, sizeof dir, "mote_nbpng"))
        return;
    snprintf(data, sizeof data, "%s/t.dat", dir);
    snprintf(png, sizeof png, "%s/o.png", dir);
    FILE *f = fopen(data, "w");
    CHECK(f != NULL, "cannot write %s", data);
    if (!f)
        return;
    fprintf(f, "# mote nbody-trajectory 1\n# Lx0 = 0\n# Ly0 = 0\n# Lz0 = 1\n"
               "# columns: T E_kin E_tot x1 y1 z1 x2 y2 z2\n");
    for (int k = 0; k <= 2000; k++) {
        double a = 2 * MOTE_PI * k / 2000.0, x1 = drift ? 0.8 * a : 0;
        fprintf(f, "%.17g 0 0 %.17g 0 0 %.17g %.17g 0\n", a, x1, x1 + cos(a), sin(a));
    }
    fclose(f);
    mote_err err = {0};
    mote_opt opt = {.key = "relative_to", .value = {.text = "1"}};
    mote_call call = {.file = "t.mote", .line = 1, .col = 1, .name = "plot", .nopts = 1,
                      .opts = &opt};
    CHECK(nb_plot_file(data, png, drift ? &call : NULL, &err) == MOTE_OK, "plot: %s", err.msg);
    /* the file: signature, IHDR first, IEND last */
    unsigned char b[33] = {0}, tail[12] = {0};
    f = fopen(png, "rb");
    CHECK(f != NULL, "no %s", png);
    if (!f)
        return;
    size_t got = fread(b, 1, sizeof b, f);
    fseek(f, -12, SEEK_END);
    size_t got2 = fread(tail, 1, sizeof tail, f);
    fclose(f);
    CHECK(got == sizeof b && memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0 && memcmp(b + 12, "IHDR", 4) == 0,
          "not a PNG with IHDR first");
    CHECK(got2 == sizeof tail && memcmp(tail + 4, "IEND", 4) == 0, "no IEND chunk at the end");
    long w = (long)b[16] << 24 | b[17] << 16 | b[18] << 8 | b[19];
    cairo_surface_t *s = cairo_image_surface_create_from_png(png);
    CHECK(cairo_surface_status(s) == CAIRO_STATUS_SUCCESS, "cairo cannot read %s", png);
    if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(s);
        return;
    }
    int W = cairo_image_surface_get_width(s), H = cairo_image_surface_get_height(s);
    int stride = cairo_image_surface_get_stride(s);
    const unsigned char *px = cairo_image_surface_get_data(s);
    /* plot.c asks for a 1024 px longer side (the default size) around a square frame */
    CHECK((W > H ? W : H) == 1024 && (W < H ? W : H) > 920 && w == W, "size %d x %d (IHDR width %ld)",
          W, H, w);
    /* robust circle: the centroid of the coloured pixels, then again over those near the median
     * radius only (dropping the legend's swatches and the centre body) */
    double cx = 0, cy = 0, r = 0;
    for (int pass = 0; pass < 3; pass++) {
        double sx = 0, sy = 0, sr = 0;
        long n = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                if (!coloured(px + (size_t)y * stride + 4 * (size_t)x))
                    continue;
                double d = hypot(x - cx, y - cy);
                if (pass > 0 && fabs(d - r) > 0.1 * r)
                    continue;
                sx += x;
                sy += y;
                sr += d;
                n++;
            }
        CHECK(n > 1000, "pass %d: only %ld coloured pixels", pass, n);
        if (n <= 1000)
            break;
        if (pass == 0) {
            cx = sx / n;
            cy = sy / n;
            r = 0.4 * W; /* a first guess of the radius: the frame is about 0.8 W wide */
        } else {
            cx = sx / n;
            cy = sy / n;
            r = sr / n;
        }
    }
    int hit = 0;
    for (int k = 0; k < 360; k++) {
        double a = 2 * MOTE_PI * k / 360.0;
        int found = 0;
        for (double d = r - 3; d <= r + 3 && !found; d += 0.5) {
            int x = (int)lround(cx + d * cos(a)), y = (int)lround(cy + d * sin(a));
            found = x >= 0 && y >= 0 && x < W && y < H &&
                    coloured(px + (size_t)y * stride + 4 * (size_t)x);
        }
        hit += found;
    }
    CHECK(hit >= 355, "the orbit: coloured pixels in %d of 360 directions on the circle of radius "
                      "%.1f px about (%.1f, %.1f)", hit, r, cx, cy);
    CHECK(r > 0.3 * W && r < 0.5 * W, "the orbit's radius %.1f px in a %d px picture", r, W);
    cairo_surface_destroy(s);
    test_remove_tree(dir);
}
static void test_png(void)
{
    test_png_case(0);
    test_png_case(1);
}

/* T11: long runs. The ring over 10 periods with the Galactica scheme, and the outer Solar System
 * (Hairer, Lubich & Wanner's data) over 10^4 Julian years with the adaptive Taylor integrator. */
static void test_longrun(void)
{
    /* under the sanitizers (MOTE_SANITIZED) 2 periods and 10^3 years: the same code, the long
     * runs' error bounds are the plain build's */
    const int san = getenv("MOTE_SANITIZED") != NULL;
    printf("T11: gravity ring, Galactica scheme, %d periods (%d steps)\n", san ? 2 : 10,
           san ? 20000 : 100000);
    mote_nb nb;
    mote_nb_ring r;
    double plane;
    double e = ring_run(MOTE_NB_GRAVITY, 1e-6, san ? 20000 : 100000, 6, &nb, &r, &plane);
    mote_nb_monitor mon;
    mote_nb_measure(&nb, &mon);
    printf("  T = %.6g periods: error %.3e, dE %.3e, dMz %.3e\n", nb.T / r.period, e, mon.dE,
           mon.dMz);
    CHECK(e <= 1e-11, "error %.3g after %d periods", e, san ? 2 : 10);
    CHECK(fabs(mon.dE) <= 1e-13, "dE %.3g", mon.dE);
    CHECK(fabs(mon.dMz) <= 1e-14, "dMz %.3g", mon.dMz);
    mote_nb_free(&nb);

    printf("T11: outer Solar System, adaptive Taylor (order 20, tol 1e-16), 10^%d years\n",
           san ? 3 : 4);
    mote_nb_solar s;
    mote_err err = {0};
    if (mote_nb_solar_read("data/outer_solar_system.dat", &s, &err)) {
        CHECK(0, "read: %s", err.msg);
        return;
    }
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    CHECK(mote_nb_solar_build(&nb, &s, NULL, 0, &err) == MOTE_OK, "build: %s", err.msg);
    mote_nb_solar_free(&s);
    nb.integrator = MOTE_NB_TAYLOR;
    nb.taylor_order = 20;
    nb.adaptive = 1;
    nb.tol = 1e-16;
    mote_nb_set_reference(&nb);
    const double t_end = (san ? 1e3 : 1e4) * 365.25 * 86400 * nb.u.kt;
    double worst = 0;
    for (int k = 1; k <= 100; k++) { /* |dE| sampled 100 times on the way */
        CHECK(mote_nb_integrate(&nb, UINT64_MAX, t_end * k / 100, &err) == MOTE_OK, "%s", err.msg);
        mote_nb_measure(&nb, &mon);
        worst = fmax(worst, fabs(mon.dE));
    }
    printf("  %llu steps to T = %.17g: max |dE| %.3e, end dE %.3e, dL %.3e\n",
           (unsigned long long)nb.steps, nb.T, worst, mon.dE, mon.dL);
    CHECK(nb.T == t_end, "T %.17g, expected %.17g", nb.T, t_end);
    CHECK(worst <= 1e-12, "max |dE| %.3g", worst);
    CHECK(fabs(mon.dL) <= 1e-12, "dL %.3g", mon.dL);
    mote_nb_free(&nb);
}

/* T19 (slow: MOTE_SLOW): N = 30 000, a Plummer sphere of equal masses (G = 1, total mass 1,
 * Plummer radius 1; Aarseth, Henon & Wielen 1974), zero radii, dT = 1e-6: 3 Galactica-scheme
 * steps and 1 Taylor step of order 10 in recompute mode; memory below 200 MB, energy and angular
 * momentum kept to 1e-10; prints the pair rate. */
static void test_scale(void)
{
    if (!getenv("MOTE_SLOW")) {
        printf("T19 (N = 30 000): in make slow\n");
        return;
    }
    const uint32_t N = 30000;
    printf("T19: N = %u Plummer sphere\n", N);
    mote_nb nb;
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    mote_err err = {0};
    CHECK(mote_nb_plummer(&nb, N, 19, &err) == MOTE_OK, "%s", err.msg);
    nb.dt = 1e-6;
    nb.threads = 2;
    mote_nb_set_reference(&nb);
    mote_nb_monitor m0, m1;
    mote_nb_measure(&nb, &m0);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    CHECK(mote_nb_galactica(&nb, 3, &err) == MOTE_OK, "%s", err.msg);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double sg = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    nb.taylor_order = 10;
    nb.taylor_memory = 2;
    nb.adaptive = 0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    CHECK(mote_nb_taylor(&nb, 1, &err) == MOTE_OK, "%s", err.msg);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double st = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    mote_nb_measure(&nb, &m1);
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    double pairs = (double)N * (N - 1);
    printf("  3 Galactica steps %.2f s (%.3g ordered pairs/s per pass, 2 passes a step), 1 Taylor "
           "step (p = 10, recompute) %.2f s; peak memory %.1f MB; dE %.3e, dL %.3e\n",
           sg, 3 * 2 * pairs / sg, st, ru.ru_maxrss / 1024.0, m1.dE, m1.dL);
    CHECK(ru.ru_maxrss < 200 * 1024, "peak memory %.1f MB", ru.ru_maxrss / 1024.0);
    CHECK(fabs(m1.dE) <= 1e-10 && fabs(m1.dL) <= 1e-10, "dE %.3g, dL %.3g", m1.dE, m1.dL);
    mote_nb_free(&nb);
}

/* T18 (spec 6.2): Barnes-Hut tree forces against direct summation on a Plummer sphere: the
 * relative acceleration error's median <= 2e-3 and 99th percentile <= 1.5e-2 at theta 0.5, median
 * <= 5e-4 at theta 0.3, and theta 0 (every cell opened) the direct sums to 1e-13; the Taylor
 * coefficients through the tree at theta 0 the direct ones; 1 and 2 threads the same bits.
 * N = 30 000 as the spec says in `make slow`, 4000 otherwise (the same bounds). */
static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static void tree_errors(mote_nb *nb, const double *ref, double *med, double *p99, double *mx)
{
    const uint32_t N = nb->n;
    double *e = malloc(N * sizeof *e);
    *mx = 0;
    for (uint32_t i = 0; i < N; i++) {
        double d2 = 0, r2 = 0;
        for (int a = 0; a < 3; a++) {
            const double d = (double)nb->acc[3 * i + a] - ref[3 * i + a];
            d2 += d * d;
            r2 += ref[3 * i + a] * ref[3 * i + a];
        }
        e[i] = sqrt(d2 / r2);
        *mx = fmax(*mx, e[i]);
    }
    qsort(e, N, sizeof *e, cmp_double);
    *med = e[N / 2];
    *p99 = e[(size_t)(0.99 * N)];
    free(e);
}

/* The direct accelerations and fifth derivatives of nb (every pair), as doubles. */
static void direct_reference(mote_nb *nb, double **ref, double **ref5)
{
    mote_err err = {0};
    const size_t n3 = 3 * (size_t)nb->n;
    nb->tree_on = 0;
    CHECK(mote_nb_derivatives(nb, &err) == MOTE_OK, "%s", err.msg);
    *ref = malloc(n3 * sizeof **ref);
    *ref5 = malloc(n3 * sizeof **ref5);
    for (size_t k = 0; k < n3; k++) {
        (*ref)[k] = (double)nb->acc[k];
        (*ref5)[k] = (double)nb->d5[k];
    }
}

/* The tree at theta against the direct reference: acceleration errors (median, 99th percentile,
 * largest) and the fifth derivative's largest error relative to its largest value. */
static void tree_against(mote_nb *nb, double theta, const double *ref, const double *ref5,
                         double *med, double *p99, double *mx, double *d5rel)
{
    mote_err err = {0};
    nb->tree_on = 1;
    nb->theta = theta;
    CHECK(mote_nb_derivatives(nb, &err) == MOTE_OK, "%s", err.msg);
    tree_errors(nb, ref, med, p99, mx);
    double d5 = 0, s5 = 0; /* the fifth derivative (pass 2 through the tree) */
    for (size_t k = 0; k < 3 * (size_t)nb->n; k++) {
        d5 = fmax(d5, fabs((double)nb->d5[k] - ref5[k]));
        s5 = fmax(s5, fabs(ref5[k]));
    }
    *d5rel = d5 / s5;
    printf("  theta %.1f: relative acceleration error median %.3g, 99th percentile %.3g, "
           "largest %.3g; fifth derivative %.3g of its largest\n", theta, *med, *p99, *mx, *d5rel);
}

static void test_tree(void)
{
    /* the approximation's statistics on N = 4000 bodies; its exactness at theta 0 (every node
     * opened: the cost of every pair, many times over) on 1000 of their own (MOTE_SLOW: both
     * on 30 000) */
    /* (under the sanitizers, MOTE_SANITIZED, 1500 and 400: the code paths are the same; the
     * error statistics are checked at 4000 in the plain build) */
    const int san = getenv("MOTE_SANITIZED") != NULL;
    const uint32_t N = getenv("MOTE_SLOW") ? 30000 : san ? 1500 : 4000;
    const uint32_t N0 = getenv("MOTE_SLOW") ? N : san ? 400 : 1000;
    printf("T18: tree forces on a Plummer sphere, N = %u (theta 0: N = %u)\n", N, N0);
    mote_nb nb;
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    mote_err err = {0};
    CHECK(mote_nb_plummer(&nb, N, 18, &err) == MOTE_OK, "%s", err.msg);
    nb.threads = 2;
    double *ref, *ref5, med, p99, mx, d5rel;
    direct_reference(&nb, &ref, &ref5);
    tree_against(&nb, 0.5, ref, ref5, &med, &p99, &mx, &d5rel);
    /* (the bounds are for N = 4000: a smaller sphere has larger relative errors) */
    CHECK(san || (med <= 2e-3 && p99 <= 1.5e-2), "theta 0.5: median %.3g, 99%% %.3g", med, p99);
    tree_against(&nb, 0.3, ref, ref5, &med, &p99, &mx, &d5rel);
    CHECK(san || med <= 5e-4, "theta 0.3: median %.3g", med);
    /* threads: the same bits */
    nb.theta = 0.5;
    nb.threads = 1;
    CHECK(mote_nb_derivatives(&nb, &err) == MOTE_OK, "%s", err.msg);
    mote_real *one = malloc(6 * N * sizeof *one);
    memcpy(one, nb.acc, 3 * N * sizeof *one);
    memcpy(one + 3 * (size_t)N, nb.d5, 3 * N * sizeof *one);
    nb.threads = 2;
    CHECK(mote_nb_derivatives(&nb, &err) == MOTE_OK, "%s", err.msg);
    CHECK(memcmp(one, nb.acc, 3 * N * sizeof *one) == 0 &&
              memcmp(one + 3 * (size_t)N, nb.d5, 3 * N * sizeof *one) == 0,
          "tree forces differ between 1 and 2 threads");
    free(one);
    if (N0 != N) { /* the exact cases on their own, smaller sphere */
        mote_nb_free(&nb);
        free(ref);
        free(ref5);
        mote_nb_init(&nb, MOTE_NB_GRAVITY);
        CHECK(mote_nb_plummer(&nb, N0, 18, &err) == MOTE_OK, "%s", err.msg);
        nb.threads = 2;
        direct_reference(&nb, &ref, &ref5);
    }
    tree_against(&nb, 0, ref, ref5, &med, &p99, &mx, &d5rel);
    CHECK(mx <= 1e-13 && d5rel <= 1e-12, "theta 0: %.3g, fifth derivative %.3g", mx, d5rel);
    /* Taylor coefficients through the tree at theta 0 are the direct ones (order 8) */
    const int p = 8;
    const size_t blk = 3 * (size_t)N0;
    mote_real *Xd = malloc((p + 1) * blk * sizeof *Xd), *Xt = malloc((p + 1) * blk * sizeof *Xt);
    nb.tree_on = 0;
    nb.taylor_order = p;
    CHECK(mote_nb_taylor_coefficients(&nb, p, 0, Xd) == MOTE_OK, "direct coefficients");
    nb.tree_on = 1;
    nb.theta = 0;
    CHECK(mote_nb_taylor_coefficients(&nb, p, 0, Xt) == MOTE_OK, "tree coefficients");
    double worst = 0;
    for (int o = 2; o <= p; o++) {
        double d = 0, sc = 0;
        for (size_t k = 0; k < blk; k++) {
            d = fmax(d, fabs((double)(Xt[o * blk + k] - Xd[o * blk + k])));
            sc = fmax(sc, fabs((double)Xd[o * blk + k]));
        }
        worst = fmax(worst, d / sc);
    }
    printf("  Taylor coefficients 2 ... %d through the tree at theta 0: %.3g of their largest\n",
           p, worst);
    CHECK(worst <= 1e-12, "tree Taylor coefficients off by %.3g", worst);
    /* and at theta 0.5 the acceleration coefficient is the tree's acceleration */
    nb.theta = 0.5;
    CHECK(mote_nb_taylor_coefficients(&nb, p, 0, Xt) == MOTE_OK, "tree coefficients");
    CHECK(mote_nb_derivatives(&nb, &err) == MOTE_OK, "%s", err.msg);
    double da = 0, amax = 0;
    for (size_t k = 0; k < blk; k++) {
        da = fmax(da, fabs((double)(2 * Xt[2 * blk + k] - nb.acc[k])));
        amax = fmax(amax, fabs(ref[k]));
    }
    CHECK(da <= 1e-13 * amax, "2 x^[2] through the tree differs from the tree's acceleration by "
          "%.3g of the largest", da / amax);

    /* softened (issue 37): at theta 0 the tree gives the direct softened derivatives and Taylor
     * coefficients, which differ from the unsoftened ones */
    nb.soft = 0.05;
    nb.tree_on = 0;
    CHECK(mote_nb_derivatives(&nb, &err) == MOTE_OK, "%s", err.msg);
    mote_real *sd = malloc(6 * blk * sizeof *sd);
    memcpy(sd, nb.acc, blk * sizeof *sd);
    memcpy(sd + blk, nb.d5, blk * sizeof *sd);
    CHECK(mote_nb_taylor_coefficients(&nb, p, 0, Xd) == MOTE_OK, "direct coefficients");
    nb.tree_on = 1;
    nb.theta = 0;
    CHECK(mote_nb_derivatives(&nb, &err) == MOTE_OK, "%s", err.msg);
    CHECK(mote_nb_taylor_coefficients(&nb, p, 0, Xt) == MOTE_OK, "tree coefficients");
    double ds = 0, d5s = 0, dsoft = 0, s5m = 0, dco = 0, sco = 0;
    for (size_t k = 0; k < blk; k++) {
        ds = fmax(ds, fabs((double)(nb.acc[k] - sd[k])));
        d5s = fmax(d5s, fabs((double)(nb.d5[k] - sd[blk + k])));
        s5m = fmax(s5m, fabs((double)sd[blk + k]));
        dsoft = fmax(dsoft, fabs((double)sd[k] - ref[k]));
        for (int o = 2; o <= p; o++) {
            dco = fmax(dco, fabs((double)(Xt[o * blk + k] - Xd[o * blk + k])));
            sco = fmax(sco, fabs((double)Xd[o * blk + k]));
        }
    }
    printf("  softened (eps 0.05), theta 0 against direct: acceleration %.3g, fifth derivative "
           "%.3g, Taylor coefficients %.3g of their largest; the softening moved the "
           "acceleration by %.3g\n", ds / amax, d5s / s5m, dco / sco, dsoft / amax);
    CHECK(ds <= 1e-13 * amax && d5s <= 1e-12 * s5m && dco <= 1e-12 * sco,
          "softened tree at theta 0: %.3g %.3g %.3g", ds / amax, d5s / s5m, dco / sco);
    CHECK(dsoft > 1e-3 * amax, "the softening did not change the forces (%.3g)", dsoft / amax);
    nb.soft = 0;
    free(sd);
    free(Xd);
    free(Xt);
    /* mixed charges are refused */
    mote_nb c;
    mote_nb_init(&c, MOTE_NB_COULOMB);
    mote_real x0[3] = {0, 0, 0}, x1[3] = {1, 0, 0}, v0[3] = {0, 0, 0};
    CHECK(mote_nb_add(&c, 0.5, 1, x0, v0, 0, &err) == MOTE_OK && mote_nb_add(&c, 0.5, -1, x1, v0,
                                                                             0, &err) == MOTE_OK,
          "%s", err.msg);
    c.tree_on = 1;
    c.theta = 0.5;
    CHECK(mote_nb_integrate(&c, 1, INFINITY, &err) == MOTE_EINVAL &&
              strstr(err.msg, "both signs"),
          "mixed charges with the tree: %s", err.msg);
    mote_nb_free(&c);
    free(ref);
    free(ref5);
    mote_nb_free(&nb);
}

/* The drift plot's time axis is in the user's units once the run has physical scales (issue 34:
 * after `units solar` and `integrate to=100 unit=year` it read 0 ... 628 "dimensionless"): the
 * unit that reads best over the span, exactly T / (kt * seconds per unit). */
static void test_time_axis(void)
{
    printf("plots: the time axis in physical units\n");
    char dir[256], data[320];
    if (!test_tmpdir_make(dir, sizeof dir, "mote_nbaxis"))
        return;
    snprintf(data, sizeof data, "%s/m.dat", dir);
    const double kt = 2 * MOTE_PI / 31557600.0; /* solar units: T = 2 pi per year */
    struct {
        int scales;
        double span_s;
        const char *unit;
        double per_unit_s;
    } cases[5] = {{0, 100, "dimensionless", 0},       {1, 1000, "s", 1},
                  {1, 10 * 86400.0, "day", 86400.0}, {1, 100 * 31557600.0, "year", 31557600.0},
                  {1, 1e4 * 31557600.0, "year", 31557600.0}};
    for (int k = 0; k < 5; k++) {
        FILE *f = fopen(data, "w");
        CHECK(f != NULL, "cannot write %s", data);
        if (!f)
            return;
        fprintf(f, "# mote nbody-monitor 1\n");
        if (cases[k].scales)
            fprintf(f, "# kt = %.17g\n", kt);
        fprintf(f, "# columns: T dE dMz\n0 0 0\n%.17g 0 0\n", cases[k].span_s * kt);
        fclose(f);
        mote_table t;
        mote_err err = {0};
        CHECK(mote_table_read(&t, data, &err) == MOTE_OK, "read: %s", err.msg);
        double scale;
        const char *u = nb_plot_time_unit(&t, 0, cases[k].span_s * kt, &scale);
        double want = cases[k].scales ? 1 / (kt * cases[k].per_unit_s) : 1;
        CHECK(strcmp(u, cases[k].unit) == 0 && fabs(scale - want) <= 1e-15 * want,
              "span %g s: unit %s, scale %.17g; expected %s, %.17g", cases[k].span_s, u, scale,
              cases[k].unit, want);
        mote_table_free(&t);
    }
    test_remove_tree(dir);
}

/* The outer Solar System of data/outer_solar_system.dat into nb (G = 1, the sidereal century). */
static int outer_solar(mote_nb *nb)
{
    mote_nb_solar s;
    mote_err err = {0};
    mote_nb_init(nb, MOTE_NB_GRAVITY);
    if (mote_nb_solar_read("data/outer_solar_system.dat", &s, &err) ||
        mote_nb_solar_build(nb, &s, NULL, 0, &err)) {
        CHECK(0, "outer Solar System: %s", err.msg);
        return -1;
    }
    mote_nb_solar_free(&s);
    return 0;
}

/* The largest |dE| of nb run with the map (step h, corrector k) to T in `samples` pieces, and
 * its positions at T into x (3n, may be NULL). */
static double wh_run(double h, int k, double T, int samples, mote_real *x)
{
    mote_nb nb;
    if (outer_solar(&nb))
        return NAN;
    nb.integrator = MOTE_NB_WH;
    nb.dt = h;
    nb.wh_corrector = k;
    mote_nb_set_reference(&nb);
    double worst = 0;
    mote_err err = {0};
    for (int j = 1; j <= samples; j++) {
        if (mote_nb_integrate(&nb, UINT64_MAX, T * j / samples, &err)) {
            CHECK(0, "wh: %s", err.msg);
            break;
        }
        mote_nb_monitor mon;
        mote_nb_measure(&nb, &mon);
        worst = fmax(worst, fabs((double)mon.dE));
    }
    if (x)
        memcpy(x, nb.x, 3 * (size_t)nb.n * sizeof *x);
    mote_nb_free(&nb);
    return worst;
}

/* The Wisdom-Holman map (issue 37): its Kepler drift exact on two bodies (an orbit of e = 0.9
 * closes after a period in 7 steps to rounding, 10^-12 of its size, any step being exact, with
 * the corrector's long drifts too), its second order (the energy error of the uncorrected map
 * and the corrected map's distance from an accurate Taylor solution fall 4 times when the step
 * halves: 3.5 ... 4.5 allows for the terms of higher order), the correctors' gain (the error of
 * first order in the masses gone: over 100 times smaller), and a trajectory independent of where
 * runs stop. */
static void test_wh(void)
{
    printf("Wisdom-Holman map: Kepler drift, order, correctors\n");
    /* two bodies: the interaction is empty, each step is the exact Kepler flow */
    const double e = 0.9, a = 1, m0 = 1, m1 = 1e-3, mu = m0 + m1;
    const double ra = a * (1 + e), va = sqrt(mu / a * (1 - e) / (1 + e));
    const double P = 8 * atan(1.0) * sqrt(a * a * a / mu);
    mote_nb nb;
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    const mote_real x0[3] = {0, 0, 0}, v0[3] = {0, 0, 0};
    const mote_real x1[3] = {ra, 0, 0}, v1[3] = {0, va, 0};
    mote_err err = {0};
    CHECK(mote_nb_add(&nb, m0, 0, x0, v0, 0, &err) == 0 && mote_nb_add(&nb, m1, 0, x1, v1, 0,
                                                                          &err) == 0,
          "add: %s", err.msg);
    mote_nb_barycentric(&nb, NULL, NULL);
    mote_real start[6];
    memcpy(start, nb.x, sizeof start);
    nb.integrator = MOTE_NB_WH;
    nb.dt = P / 7;
    nb.wh_corrector = 17;
    CHECK(mote_nb_integrate(&nb, 7, INFINITY, &err) == 0, "two bodies: %s", err.msg);
    double d = 0;
    for (int c = 0; c < 6; c++)
        d = fmax(d, fabs((double)(nb.x[c] - start[c])));
    printf("  two bodies, e = 0.9, one period in 7 steps: max |x - x0| = %.2e\n", d);
    CHECK(d <= 1e-12 * ra, "the two-body orbit did not close: %.3e", d);
    mote_nb_free(&nb);
    /* an unbound flyby (e > 1: the hyperbolic Stumpff functions) through its pericentre in 10
     * steps, against the adaptive Taylor solution: the same to rounding (10^-12 of the scale) */
    mote_nb fly[2];
    for (int j = 0; j < 2; j++) {
        mote_nb_init(&fly[j], MOTE_NB_GRAVITY);
        const mote_real xf[3] = {-10, 1, 0}, vf[3] = {1, 0, 0.1};
        CHECK(mote_nb_add(&fly[j], 1, 0, x0, v0, 0, &err) == 0 &&
                  mote_nb_add(&fly[j], 1e-3, 0, xf, vf, 0, &err) == 0, "add: %s", err.msg);
        mote_nb_barycentric(&fly[j], NULL, NULL);
        fly[j].integrator = j ? MOTE_NB_TAYLOR : MOTE_NB_WH;
        fly[j].dt = 2;
        fly[j].wh_corrector = 17;
        fly[j].adaptive = j;
        fly[j].tol = 1e-16;
        CHECK(mote_nb_integrate(&fly[j], UINT64_MAX, 20, &err) == 0, "flyby: %s", err.msg);
    }
    d = 0;
    for (int c = 0; c < 6; c++)
        d = fmax(d, fabs((double)(fly[0].x[c] - fly[1].x[c])));
    printf("  hyperbolic flyby in 10 steps against Taylor: max |x - x_taylor| = %.2e\n", d);
    CHECK(d <= 1e-11, "the flyby differs from the Taylor solution by %.3e", d);
    mote_nb_free(&fly[0]);
    mote_nb_free(&fly[1]);

    /* second order in the step: 10^3 years, steps of 0.5 and 0.25 years (T in sidereal
     * centuries) */
    const double T = 10, dE1 = wh_run(0.005, 0, T, 100, NULL);
    const double dE2 = wh_run(0.0025, 0, T, 100, NULL);
    printf("  outer Solar System, 10^3 yr, no corrector: max |dE| %.3e (0.5 yr), %.3e (0.25 yr): "
           "ratio %.3f\n", dE1, dE2, dE1 / dE2);
    CHECK(dE1 / dE2 > 3.5 && dE1 / dE2 < 4.5, "energy error ratio %.3f, expected 4", dE1 / dE2);
    /* the corrector of order 17: the error of first order in the masses gone */
    const double dE17 = wh_run(0.005, 17, T, 100, NULL);
    printf("  corrector 17, 0.5 yr: max |dE| %.3e (%.0f times smaller)\n", dE17, dE1 / dE17);
    CHECK(dE17 < dE1 / 100, "corrector 17: %.3e against %.3e without", dE17, dE1);
    /* against the adaptive Taylor solution (order 20, tol 1e-16), positions after 10^3 years */
    mote_nb ref;
    mote_real xr[18], xa[18], xb[18];
    if (outer_solar(&ref) == 0) {
        ref.integrator = MOTE_NB_TAYLOR;
        ref.adaptive = 1;
        ref.tol = 1e-16;
        ref.taylor_order = 20;
        CHECK(mote_nb_integrate(&ref, UINT64_MAX, T, &err) == 0, "taylor: %s", err.msg);
        memcpy(xr, ref.x, sizeof xr);
        mote_nb_free(&ref);
    }
    wh_run(0.005, 17, T, 1, xa);
    wh_run(0.0025, 17, T, 1, xb);
    double ea = 0, eb = 0;
    for (int c = 3; c < 18; c++) {
        ea = fmax(ea, fabs((double)(xa[c] - xr[c])));
        eb = fmax(eb, fabs((double)(xb[c] - xr[c])));
    }
    printf("  corrector 17 against Taylor: max |x - x_taylor| %.3e (0.5 yr), %.3e (0.25 yr): "
           "ratio %.3f\n", ea, eb, ea / eb);
    CHECK(ea / eb > 3.5 && ea / eb < 4.5, "position error ratio %.3f, expected 4", ea / eb);
    /* stopping every 7 steps (at times T k / 10, which the sums of dt reach to rounding), or
     * once: the same bits */
    mote_real xs[18], xo[18];
    wh_run(0.005, 17, 0.35, 10, xs);
    wh_run(0.005, 17, 0.35, 1, xo);
    CHECK(memcmp(xs, xo, sizeof xs) == 0, "stops changed the trajectory");
}

/* The Clausius virial V = sum over pairs m_i m_k r^2 / (r^2 + eps^2)^(3/2) (-sum r.F) and the
 * kinetic energy K of nb: the virial theorem of a bound system is <2K> = <V>. */
static void virial(const mote_nb *nb, double *K, double *V)
{
    const double e2 = (double)(nb->soft * nb->soft);
    *K = *V = 0;
    for (uint32_t i = 0; i < nb->n; i++) {
        const mote_real *v = nb->v + 3 * (size_t)i, *x = nb->x + 3 * (size_t)i;
        *K += 0.5 * (double)(nb->m[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
        for (uint32_t k = i + 1; k < nb->n; k++) {
            const mote_real *y = nb->x + 3 * (size_t)k;
            const double d0 = (double)(x[0] - y[0]), d1 = (double)(x[1] - y[1]),
                         d2 = (double)(x[2] - y[2]), r2 = d0 * d0 + d1 * d1 + d2 * d2;
            *V += (double)(nb->m[i] * nb->m[k]) * r2 / ((r2 + e2) * sqrt(r2 + e2));
        }
    }
}

/* Plummer softening (issue 37): the potential energy -m_i m_k / sqrt(r^2 + eps^2); a circular
 * binary of separation d whose angular velocity is sqrt(M / (d^2 + eps^2)^(3/2)) closes after
 * its period with both integrators (without softening it would not: its period is 1.18 times
 * longer at eps = d / 2); a softened Plummer sphere keeps its energy over several crossing
 * times and satisfies the virial theorem of the softened force. */
static void test_softening(void)
{
    printf("softening: potential, a softened circular binary, a softened Plummer sphere\n");
    const double d = 1, eps = 0.5, M = 1;
    const double om = sqrt(M / pow(d * d + eps * eps, 1.5)), P = 8 * atan(1.0) / om;
    for (int integ = 0; integ < 2; integ++) {
        mote_nb nb;
        mote_nb_init(&nb, MOTE_NB_GRAVITY);
        mote_err err = {0};
        const mote_real xa[3] = {d / 2, 0, 0}, va[3] = {0, om * d / 2, 0};
        const mote_real xb[3] = {-d / 2, 0, 0}, vb[3] = {0, -om * d / 2, 0};
        CHECK(mote_nb_add(&nb, M / 2, 0, xa, va, 0, &err) == 0 &&
                  mote_nb_add(&nb, M / 2, 0, xb, vb, 0, &err) == 0, "add: %s", err.msg);
        nb.soft = eps;
        mote_nb_monitor mon;
        mote_nb_measure(&nb, &mon);
        const double U = -(M / 2) * (M / 2) / sqrt(d * d + eps * eps);
        if (integ == 0)
            CHECK(REL((double)mon.u, U) <= 1e-15, "softened U = %.17g, expected %.17g",
                  (double)mon.u, U);
        nb.integrator = integ ? MOTE_NB_TAYLOR : MOTE_NB_GALACTICA;
        nb.adaptive = integ;
        nb.tol = 1e-16;
        nb.dt = P / 2000;
        CHECK(mote_nb_integrate(&nb, UINT64_MAX, P, &err) == 0, "binary: %s", err.msg);
        double dx = 0;
        for (int c = 0; c < 6; c++)
            dx = fmax(dx, fabs((double)(nb.x[c] - (c < 3 ? xa[c] : xb[c - 3]))));
        mote_nb_measure(&nb, &mon);
        printf("  circular binary, eps = d/2, one period (%s): |x - x0| = %.2e, dE = %.1e\n",
               integ ? "adaptive Taylor" : "Galactica, 2000 steps", dx, (double)mon.dE);
        CHECK(dx <= 1e-10, "the softened binary did not close: %.3e", dx);
        CHECK(fabs((double)mon.dE) <= 1e-13, "binary dE = %.3e", (double)mon.dE);
        mote_nb_free(&nb);
    }
    /* a Plummer sphere of 128 bodies (Plummer radius 1, G = M = 1: crossing time about 6),
     * eps = 0.1, four crossing times with the default adaptive Taylor integrator. 2K/V of one
     * sample spreads by 0.02-0.07 (seeds 3, 7, 11, 19); the mean over four crossing times (at
     * least 4 independent samples) has a standard error of at most 0.035: 0.1 is 3 of them.
     * The sanitized build leaves it out (its force code is the binary's, above; 20 s there). */
    if (getenv("MOTE_SANITIZED")) {
        printf("  (the softened Plummer sphere runs in the plain build only)\n");
        return;
    }
    mote_nb nb;
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    mote_err err = {0};
    CHECK(mote_nb_plummer(&nb, 128, 7, &err) == 0, "plummer: %s", err.msg);
    nb.soft = 0.1;
    nb.integrator = MOTE_NB_TAYLOR;
    nb.adaptive = 1;
    nb.tol = 1e-16;
    mote_nb_set_reference(&nb);
    double s2K = 0, sV = 0, worst = 0, sq = 0, sq2 = 0;
    const int samples = 48;
    for (int j = 1; j <= samples; j++) {
        if (mote_nb_integrate(&nb, UINT64_MAX, 24.0 * j / samples, &err)) {
            CHECK(0, "softened Plummer: %s", err.msg);
            break;
        }
        mote_nb_monitor mon;
        mote_nb_measure(&nb, &mon);
        worst = fmax(worst, fabs((double)mon.dE));
        double K, V;
        virial(&nb, &K, &V);
        s2K += 2 * K;
        sV += V;
        sq += 2 * K / V;
        sq2 += (2 * K / V) * (2 * K / V);
    }
    const double qsd = sqrt(fmax(0, sq2 / samples - (sq / samples) * (sq / samples)));
    printf("  Plummer sphere N = 128, eps = 0.1, T = 24: max |dE| %.2e, <2K>/<V> = %.4f (the "
           "samples' spread %.3f; %llu steps)\n", worst, s2K / sV, qsd,
           (unsigned long long)nb.steps);
    CHECK(worst <= 1e-13, "softened Plummer: max |dE| %.3e", worst);
    CHECK(fabs(s2K / sV - 1) <= 0.1, "softened Plummer: <2K>/<V> = %.4f", s2K / sV);
    mote_nb_free(&nb);
}

int main(void)
{
    double w0 = mote_wall_seconds();
    test_tree();
    test_time_axis();
    test_ring_values();
    test_coulomb_values();
    test_fN();
    test_gravity_ring();
    test_coulomb_ring();
    test_orders();
    test_coulomb_sign();
    test_threads();
    test_lanes();
    test_taylor();
    test_adaptive();
    test_merging();
    test_solar();
    test_wh();
    test_softening();
    test_t12();
    test_approach();
    test_png();
    test_longrun();
    test_scale();
    printf("test_nbody: %.1f s\n", mote_wall_seconds() - w0);
    return test_summary();
}
