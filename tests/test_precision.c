/* test_precision.c: the N-body model's real type (spec 4.6). This program is built three times,
 * with double, long double and quad (test_precision, test_precision_long, test_precision_quad),
 * and each checks the ring tests of spec 11 with bounds scaled by the type's machine epsilon
 * against double's, so a build whose arithmetic silently fell back to double somewhere on the
 * integration path fails:
 *   T10: the 30-body gravity ring over one period with the adaptive Taylor integrator at the
 *        type's default tolerance and order=auto: error <= 1e-12 r, |dE| <= 1e-14 r, where
 *        r = eps(type) / eps(double) (2^-11 for long double, 2^-60 for quad);
 *   T06: the same ring with Galactica's scheme at dT = 1e-5 (truncation-limited: the same
 *        error, <= 1e-10, in every type; not run in quad, where it takes minutes);
 *   the state file written with the type's digits reads back to the same bits;
 *   script values (dt=, x=) reach the model at the type's full precision.
 * No timings: the slowdown of each type is measured by bench/bench_nbody.c. */
#include "mote/nbody.h"
#include "mote/script.h"
#include "test.h"

#include <float.h>
#include <stdio.h>
#include <string.h>

#include "../src/nbody/nb.h" /* nb_state_save, nb_state_load */

#if MOTE_NB_PRECISION == 4
#define REAL_EPS 1.925929944387235853055977942584927319e-34 /* 2^-112 */
#elif MOTE_NB_PRECISION == 2
#define REAL_EPS ((double)LDBL_EPSILON)
#else
#define REAL_EPS DBL_EPSILON
#endif

static void ring(mote_nb *nb, mote_nb_ring *r)
{
    mote_err err = {0};
    mote_nb_init(nb, MOTE_NB_GRAVITY);
    mote_nb_ring_defaults(r, MOTE_NB_GRAVITY);
    CHECK(mote_nb_ring_build(nb, r, &err) == MOTE_OK, "ring: %s", err.msg);
}

static void test_taylor(double scale)
{
    mote_nb nb;
    mote_nb_ring r;
    ring(&nb, &r);
    nb.integrator = MOTE_NB_TAYLOR;
    nb.adaptive = 1;
    nb.tol = MOTE_REAL_TOL;
    nb.taylor_order = mote_nb_taylor_auto_order(nb.tol);
    mote_err err = {0};
    CHECK(mote_nb_integrate(&nb, UINT64_MAX, r.period, &err) == MOTE_OK, "run: %s", err.msg);
    const double e = (double)mote_nb_ring_error(&nb, &r, NULL);
    mote_nb_monitor mon;
    mote_nb_measure(&nb, &mon);
    printf("  T10 one period, adaptive Taylor (order %d, tol %.0e): %llu steps, error %.3e "
           "(bound %.1e), dE %.3e (bound %.1e)\n",
           nb.taylor_order, (double)nb.tol, (unsigned long long)nb.steps, e, 1e-12 * scale,
           (double)mon.dE, 1e-14 * scale);
    CHECK(nb.T == r.period, "the end time is not hit exactly");
    CHECK(e <= 1e-12 * scale, "error %.3e > %.1e", e, 1e-12 * scale);
    CHECK(fabs((double)mon.dE) <= 1e-14 * scale, "dE %.3e > %.1e", (double)mon.dE, 1e-14 * scale);
    /* the state file round trip: every value back to the same bits */
    char dir[64], path[96];
    if (!test_tmpdir_make(dir, sizeof dir, "mote_precision")) {
        CHECK(0, "no temporary directory");
        mote_nb_free(&nb);
        return;
    }
    snprintf(path, sizeof path, "%s/ring.state", dir);
    CHECK(nb_state_save(&nb, path, &err) == MOTE_OK, "save: %s", err.msg);
    mote_nb back;
    mote_nb_init(&back, MOTE_NB_GRAVITY);
    CHECK(nb_state_load(&back, path, &err) == MOTE_OK, "load: %s", err.msg);
    int same = back.n == nb.n && back.T == nb.T && back.Tc == nb.Tc;
    for (uint32_t i = 0; same && i < 3 * nb.n; i++)
        same = back.x[i] == nb.x[i] && back.v[i] == nb.v[i] && back.xc[i] == nb.xc[i] &&
               back.vc[i] == nb.vc[i];
    for (uint32_t i = 0; same && i < nb.n; i++)
        same = back.m[i] == nb.m[i] && back.ra[i] == nb.ra[i];
    CHECK(same, "the state file does not read back to the same bits");
    test_remove_tree(dir);
    mote_nb_free(&back);
    mote_nb_free(&nb);
}

/* Script values reach the model at the type's full precision: a body's x=0.1 and dt=1e-6 are
 * the real type's nearest values, not double's widened (they differ in long double and quad). */
static void test_script_values(void)
{
    char dir[64], path[96], text[512];
    if (!test_tmpdir_make(dir, sizeof dir, "mote_precision_script")) {
        CHECK(0, "no temporary directory");
        return;
    }
    snprintf(path, sizeof path, "%s/s.state", dir);
    snprintf(text, sizeof text,
             "model nbody gravity\nbody mass=1\nbody mass=1e-3 x=0.1 vy=3.1\n"
             "integrator galactica dt=1e-6\nintegrate steps=3\nsave %s\n", path);
    const mote_model *models[] = {&mote_model_nbody};
    mote_script *sc = NULL;
    mote_err err = {0};
    int rc = mote_script_parse(&sc, "precision.mote", text, strlen(text), models, 1, &err);
    FILE *sink = tmpfile();
    if (!rc && sink)
        mote_script_context(sc)->out = sink;
    if (!rc)
        rc = mote_script_execute(sc, &err);
    CHECK(rc == MOTE_OK, "script: %s", err.msg);
    mote_script_free(sc);
    if (sink)
        fclose(sink);
    mote_nb nb;
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    CHECK(nb_state_load(&nb, path, &err) == MOTE_OK, "load: %s", err.msg);
    const mote_real dt = mote_real_parse("1e-6", NULL), x = mote_real_parse("0.1", NULL);
    CHECK(nb.n == 2 && nb.dt == dt, "dt= not read to full precision");
    /* three steps from a fresh start: T = (0.001 + 2) dt, summed in the type */
    CHECK(nb.n == 2 && fabs((double)((nb.T - (mote_real)2.001 * dt) / dt)) < 1e-10,
          "T after three steps");
    mote_nb_free(&nb);
    /* the body's x before any step: read again without integrating */
    snprintf(text, sizeof text, "model nbody gravity\nbody mass=1\nbody mass=1e-3 x=0.1\nsave %s\n",
             path);
    rc = mote_script_parse(&sc, "precision.mote", text, strlen(text), models, 1, &err);
    sink = tmpfile();
    if (!rc && sink)
        mote_script_context(sc)->out = sink;
    if (!rc)
        rc = mote_script_execute(sc, &err);
    CHECK(rc == MOTE_OK, "script: %s", err.msg);
    mote_script_free(sc);
    if (sink)
        fclose(sink);
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    CHECK(nb_state_load(&nb, path, &err) == MOTE_OK, "load: %s", err.msg);
    CHECK(nb.n == 2 && nb.x[3] == x, "x= not read to full precision");
    mote_nb_free(&nb);
    test_remove_tree(dir);
}

static void test_galactica(void)
{
    mote_nb nb;
    mote_nb_ring r;
    ring(&nb, &r);
    nb.dt = 1e-5;
    mote_err err = {0};
    const uint64_t steps = (uint64_t)(r.period / nb.dt) + 1;
    CHECK(mote_nb_galactica(&nb, steps, &err) == MOTE_OK, "run: %s", err.msg);
    /* compare at the time reached (the exact solution is known at any T) */
    const double e = (double)mote_nb_ring_error(&nb, &r, NULL);
    printf("  T06 one period, Galactica scheme, dT = 1e-5: error %.3e (bound 1e-10)\n", e);
    CHECK(e <= 1e-10, "error %.3e", e);
    mote_nb_free(&nb);
}

int main(void)
{
    const double scale = REAL_EPS / DBL_EPSILON;
    printf("precision %s: %zu-byte reals, %d digits in text, epsilon %.3e (%.3g of double's)\n",
           MOTE_REAL_NAME, sizeof(mote_real), MOTE_REAL_DIG, REAL_EPS, scale);
    CHECK(sizeof(mote_real) == (MOTE_NB_PRECISION == 1 ? 8 : 16), "sizeof(mote_real) = %zu",
          sizeof(mote_real));
    /* the type's epsilon, measured: 1 + eps/2 rounds to 1, 1 + eps does not */
    volatile mote_real one = 1, half = (mote_real)REAL_EPS / 2, full = (mote_real)REAL_EPS;
    CHECK(one + half == one && one + full != one, "the real type's epsilon is not %.3e",
          REAL_EPS);
    test_taylor(scale);
    test_script_values();
    if (MOTE_NB_PRECISION != 4)
        test_galactica();
    return test_summary();
}
