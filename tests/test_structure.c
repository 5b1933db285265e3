/* test_structure.c: `rdf` and `msd` against theory (issue 19.3), with fixed seeds (MOTE_TEST_SEED
 * for others) and tolerances from the measured statistical errors:
 *
 * - rdf, periodic box of 2048 spheres at eta = 0.30: the contact value g(sigma+) agrees within 3
 *   standard errors (about 0.15%) with Hongqin Liu's correction to Carnahan-Starling, as SklogWiki
 *   gives it ("Liu hard sphere equation of state": Z = (1 + eta + eta^2 - 8/13 eta^3 - eta^4 +
 *   eta^5/2)/(1 - eta)^3, "improved accuracy by almost two orders of magnitude"), g = (Z - 1) /
 *   (4 eta) = 2.4867; and
 *   with Carnahan-Starling's (1 - eta/2)/(1 - eta)^3 = 2.4781 within 3 standard errors plus
 *   CS's own error there (0.35%, its distance from Liu's). The measurement resolves CS's error:
 *   over 6 seeds g(sigma+) = 2.4861 +- 0.0016. The contact theorem's Z = 1 + 4 eta g(sigma+)
 *   agrees with the virial Z of `pressure` on the next stretch of the same run within 3 combined
 *   errors; g = 0 inside the core.
 * - rdf, 2D periodic box of 400 disks at eta = 0.50: Z = 1 + 2 eta g(sigma+) against the
 *   virial Z (3 combined errors); g(r) -> 1 at large r.
 * - rdf, slit: the lateral g(s) of the mid-slit layer tends to 1 at large s (its own
 *   normalisation) and the wall layer's first peak lies at s ~ sigma.
 * - msd, periodic box of 4000 spheres at eta = 0.05: D within 5% (plus 3 standard errors) of
 *   Enskog's D_E = 3/(8 n sigma^2) sqrt(kT/(pi m)) / g(sigma+) (the issue's target: Enskog's first
 *   approximation is exact only as eta -> 0, and the periodic box lowers D by about 1.2% here);
 *   the ratio is printed. Measured over 12 seeds: 1.044 +- 0.002 (docs/measurements.md).
 * - msd in a slit: the displacement parallel to the walls only (2 dimensions in 3D).
 * - compress_box: a fluid compressed from 0.45 to 0.52 stays a fluid with the metastable Z. */
#include "mote/hardspheres.h"
#include "test.h"

static int sanitized;
static char DIR_[256];

static void path_in(char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "%s/%s", DIR_, name);
}

static const double *get(const mote_result *r, const char *key, double *err)
{
    const double *v = mote_result_get(r, key, err);
    CHECK(v != NULL, "result %s missing", key);
    return v;
}

/* Mean of column `col` over the data rows of a file whose column 2 lies in [lo, hi]. */
static double column_mean(const char *path, int col, double lo, double hi)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return NAN;
    char line[1024];
    double sum = 0;
    int n = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#')
            continue;
        double v[8];
        int k = sscanf(line, "%lf %lf %lf %lf %lf %lf %lf", &v[0], &v[1], &v[2], &v[3], &v[4],
                       &v[5], &v[6]);
        if (k > col && v[2] >= lo && v[2] <= hi && isfinite(v[col])) {
            sum += v[col];
            n++;
        }
    }
    fclose(f);
    return n ? sum / n : NAN;
}

/* The s of the largest value of column `col` in [lo, hi]. */
static double column_peak(const char *path, int col, double lo, double hi)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return NAN;
    char line[1024];
    double best = -1, at = NAN;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#')
            continue;
        double v[8];
        int k = sscanf(line, "%lf %lf %lf %lf %lf %lf %lf", &v[0], &v[1], &v[2], &v[3], &v[4],
                       &v[5], &v[6]);
        if (k > col && v[2] >= lo && v[2] <= hi && v[col] > best) {
            best = v[col];
            at = v[2];
        }
    }
    fclose(f);
    return at;
}

static void test_rdf_bulk3d(void)
{
    mote_hs hs;
    mote_err err = {0};
    mote_hs_init(&hs, NULL);
    mote_hs_seed(&hs, test_seed(31));
    const double eta = 0.30;
    CHECK(mote_hs_bulk(&hs, 2048, eta, &err) == 0, "%s", err.msg);
    CHECK(mote_hs_step(&hs, 100, &err) == 0, "%s", err.msg); /* melt the seed lattice */
    char path[512];
    path_in(path, sizeof path, "gr.dat");
    mote_result r = {0}, p = {0};
    const uint64_t k = sanitized ? 500 : 1500;
    int rc = mote_hs_rdf(&hs, k, 5, path, "test", &r, &err);
    CHECK(rc == 0, "rdf: %s", err.msg);
    path_in(path, sizeof path, "p.dat");
    rc = mote_hs_pressure(&hs, k, path, "test", &p, &err);
    CHECK(rc == 0, "pressure: %s", err.msg);
    double ge, ze, zve;
    const double *g = get(&r, "g_contact", &ge), *z = get(&r, "Z_contact", &ze),
                 *zv = get(&p, "Z", &zve);
    if (g && z && zv) {
        const double g_cs = (1 - eta / 2) / pow(1 - eta, 3);
        const double e2 = eta * eta, e3 = e2 * eta;
        const double z_liu = (1 + eta + e2 - 8.0 / 13 * e3 - e2 * e2 + 0.5 * e2 * e3) /
                             pow(1 - eta, 3);
        const double g_liu = (z_liu - 1) / (4 * eta);
        printf("rdf 3D eta %.2f: g(sigma+) = %.4f +- %.4f (Liu %.4f, %+.2f sigma; CS %.4f); "
               "Z_contact = %.4f +- %.4f, Z_virial = %.4f +- %.4f\n",
               eta, *g, ge, g_liu, (*g - g_liu) / ge, g_cs, *z, ze, *zv, zve);
        CHECK(ge > 0 && ge < 0.005 * g_cs, "g error %g", ge);
        CHECK(fabs(*g - g_liu) < 3 * ge, "g(sigma+) %.4f vs Liu %.4f (err %.4f)", *g, g_liu, ge);
        CHECK(fabs(*g - g_cs) < 3 * ge + fabs(g_cs - g_liu), "g(sigma+) %.4f vs CS %.4f", *g,
              g_cs);
        CHECK(fabs(*z - *zv) < 3 * sqrt(ze * ze + zve * zve), "Z contact %.4f vs virial %.4f", *z,
              *zv);
    }
    path_in(path, sizeof path, "gr.dat");
    CHECK(column_mean(path, 3, 0, 1.9) == 0, "g inside the core: %g", column_mean(path, 3, 0, 1.9));
    mote_hs_free(&hs);
}

static void test_rdf_disks(void)
{
    mote_hs hs;
    mote_err err = {0};
    mote_hs_init(&hs, NULL);
    mote_hs_seed(&hs, test_seed(32));
    CHECK(mote_hs_bulk_disks(&hs, 400, 0.50, &err) == 0, "%s", err.msg);
    CHECK(mote_hs_step(&hs, 100, &err) == 0, "%s", err.msg);
    char path[512];
    path_in(path, sizeof path, "gr2.dat");
    mote_result r = {0}, p = {0};
    const uint64_t k = sanitized ? 500 : 1500;
    CHECK(mote_hs_rdf(&hs, k, 12, path, "test", &r, &err) == 0, "rdf: %s", err.msg);
    /* beyond 4.5 sigma the oscillations of g are below 1% at this density */
    double tail = column_mean(path, 3, 9.0, 12.0);
    CHECK(fabs(tail - 1) < 0.02, "2D g(r) over r in [9, 12] R: %.4f, expected 1", tail);
    path_in(path, sizeof path, "p2.dat");
    CHECK(mote_hs_pressure(&hs, k, path, "test", &p, &err) == 0, "pressure: %s", err.msg);
    double ze, zve;
    const double *z = get(&r, "Z_contact", &ze), *zv = get(&p, "Z", &zve);
    if (z && zv) {
        printf("rdf 2D eta 0.50: Z_contact = %.4f +- %.4f, Z_virial = %.4f +- %.4f\n", *z, ze, *zv,
               zve);
        CHECK(fabs(*z - *zv) < 3 * sqrt(ze * ze + zve * zve), "2D Z contact %.4f vs virial %.4f",
              *z, *zv);
    }
    mote_hs_free(&hs);
}

static void test_rdf_slit(void)
{
    mote_hs hs;
    mote_err err = {0};
    mote_hs_init(&hs, NULL);
    mote_hs_seed(&hs, test_seed(33));
    CHECK(mote_hs_new(&hs, 6, 0.40, &err) == 0, "%s", err.msg);
    CHECK(mote_hs_step(&hs, 50, &err) == 0, "%s", err.msg);
    char path[512];
    path_in(path, sizeof path, "grs.dat");
    mote_result r = {0};
    CHECK(mote_hs_rdf(&hs, sanitized ? 100 : 300, 7, path, "test", &r, &err) == 0, "%s", err.msg);
    CHECK(mote_result_get(&r, "g_contact", NULL) == NULL, "a slit has no bulk contact value");
    double mid = column_mean(path, 5, 5.5, 7.0), wall = column_mean(path, 3, 5.5, 7.0);
    printf("rdf slit: lateral g over s in [5.5, 7] R: mid layer %.4f, wall layer %.4f; wall "
           "peak at s = %.3f R\n",
           mid, wall, column_peak(path, 3, 1.0, 3.0));
    /* a layer's pairs fill its periodic area (the sum rule of a fixed area), so the correlation
     * hole at s < sigma (about 4 pi R^2 of area) raises g at large s by about hole / area:
     * about 3% for this layer of the 2784-sphere slit; 5% is the bound */
    CHECK(fabs(mid - 1) < 0.05, "mid layer g at large s %.4f", mid);
    CHECK(fabs(wall - 1) < 0.05, "wall layer g at large s %.4f", wall);
    double peak = column_peak(path, 3, 1.0, 3.0);
    CHECK(peak >= 1.9 && peak <= 2.2, "wall layer's first peak at s = %.3f R", peak);
    /* RMAX beyond half a periodic length is refused */
    CHECK(mote_hs_rdf(&hs, 1, 100, path, "test", &r, &err) != 0, "RMAX 100 accepted");
    CHECK_HAS(err.msg, "exceeds half the periodic length");
    mote_hs_free(&hs);
}

static void test_msd(void)
{
    mote_hs hs;
    mote_err err = {0};
    mote_hs_init(&hs, NULL);
    mote_hs_seed(&hs, test_seed(34));
    const double eta = 0.05, sigma = 2;
    /* (a third of the spheres under the sanitizers: the tolerance below is 3 standard errors
     * at any size; the bound on the error itself is for 4000, checked in the plain build) */
    const int64_t N = sanitized ? 1372 : 4000;
    CHECK(mote_hs_bulk(&hs, N, eta, &err) == 0, "%s", err.msg);
    CHECK(mote_hs_step(&hs, 20, &err) == 0, "%s", err.msg);
    char path[512];
    path_in(path, sizeof path, "msd.dat");
    mote_result r = {0};
    CHECK(mote_hs_msd(&hs, 400, path, "test", &r, &err) == 0, "msd: %s", err.msg);
    double de;
    const double *D = get(&r, "D", &de);
    if (D) {
        const double n = 6 * eta / (MOTE_PI * sigma * sigma * sigma);
        const double g = (1 - eta / 2) / pow(1 - eta, 3);
        const double d_e = 3 / (8 * n * sigma * sigma) * sqrt(1 / MOTE_PI) / g;
        printf("msd eta 0.05, N %lld: D = %.4f +- %.4f, Enskog D_E = %.4f, D/D_E = %.4f +- %.4f\n",
               (long long)N, *D, de, d_e, *D / d_e, de / d_e);
        CHECK(de > 0 && (sanitized || de < 0.01 * d_e), "D error %g", de);
        /* the model's tolerance (5%: Enskog's first approximation is exact only as eta -> 0)
         * plus 3 standard errors of the measurement */
        CHECK(fabs(*D / d_e - 1) < 0.05 + 3 * de / d_e, "D/D_E = %.4f +- %.4f", *D / d_e,
              de / d_e);
    }
    const double *dims = get(&r, "dimensions", NULL);
    CHECK(dims && *dims == 3, "dimensions");
    CHECK(mote_hs_msd(&hs, 3, path, "test", &r, &err) != 0, "K = 3 accepted");
    mote_hs_free(&hs);

    /* a slit: only y and z */
    mote_hs_init(&hs, NULL);
    mote_hs_seed(&hs, test_seed(35));
    CHECK(mote_hs_new(&hs, 3, 0.30, &err) == 0, "%s", err.msg);
    CHECK(mote_hs_msd(&hs, 40, path, "test", &r, &err) == 0, "msd slit: %s", err.msg);
    dims = get(&r, "dimensions", NULL);
    CHECK(dims && *dims == 2, "slit dimensions");
    mote_hs_free(&hs);
}

/* compress_box: a fluid at 0.45 compressed to 0.52 (above freezing) is a fluid there: exactly at
 * eta, every invariant holds, almost no crystal-like particle, and Z on the metastable-fluid
 * branch: Carnahan-Starling, Z = 14.918 at 0.52 (about 1% from simulations there; tolerance 1%
 * plus 3 standard errors). Expansion is one move; a slit is refused. */
static void test_compress_box(void)
{
    mote_hs hs;
    mote_err err = {0};
    mote_hs_init(&hs, NULL);
    mote_hs_seed(&hs, test_seed(36));
    CHECK(mote_hs_bulk(&hs, 500, 0.45, &err) == 0, "%s", err.msg);
    CHECK(mote_hs_step(&hs, 100, &err) == 0, "%s", err.msg);
    int rc = mote_hs_compress_box(&hs, 0.52, 0.05, 2, &err);
    CHECK(rc == 0, "compress_box: %s", err.msg);
    CHECK(fabs(mote_hs_phi(&hs) - 0.52) < 1e-13, "eta after compress_box %.17g", mote_hs_phi(&hs));
    CHECK(mote_ev_check(&hs.ev, &err) == 0, "invariants after compress_box: %s", err.msg);
    char path[512];
    path_in(path, sizeof path, "o.dat");
    mote_result o = {0}, p = {0};
    CHECK(mote_hs_order(&hs, 20, path, "test", &o, &err) == 0, "order: %s", err.msg);
    const double *x = get(&o, "xtal_fraction", NULL);
    path_in(path, sizeof path, "p.dat");
    CHECK(mote_hs_pressure(&hs, sanitized ? 200 : 600, path, "test", &p, &err) == 0, "%s",
          err.msg);
    double ze;
    const double *z = get(&p, "Z", &ze);
    const double e = 0.52, z_cs = (1 + e + e * e - e * e * e) / pow(1 - e, 3);
    if (x && z) {
        printf("compress_box 0.45 -> 0.52, N 500: crystal-like %.4f, Z = %.3f +- %.3f (CS %.3f)\n",
               *x, *z, ze, z_cs);
        CHECK(*x < 0.05, "crystal-like fraction %.4f after compress_box", *x);
        CHECK(fabs(*z - z_cs) < 0.01 * z_cs + 3 * ze, "Z %.3f vs CS %.3f", *z, z_cs);
    }
    CHECK(mote_hs_compress_box(&hs, 0.40, 0.05, 1, &err) == 0, "expansion: %s", err.msg);
    CHECK(fabs(mote_hs_phi(&hs) - 0.40) < 1e-13, "eta after expansion %.17g", mote_hs_phi(&hs));
    mote_hs_free(&hs);
    mote_hs_init(&hs, NULL);
    CHECK(mote_hs_new(&hs, 2, 0.3, &err) == 0, "%s", err.msg);
    CHECK(mote_hs_compress_box(&hs, 0.35, 0.05, 1, &err) != 0, "a slit compressed as a box");
    CHECK_HAS(err.msg, "compress_left_wall");
    mote_hs_free(&hs);
}

int main(void)
{
    sanitized = getenv("MOTE_SANITIZED") != NULL;
    if (!test_tmpdir_make(DIR_, sizeof DIR_, "mote_test_structure"))
        return 1;
    test_rdf_bulk3d();
    test_rdf_disks();
    test_rdf_slit();
    test_msd();
    test_compress_box();
    test_remove_tree(DIR_);
    return test_summary();
}
