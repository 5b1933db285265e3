/* test_bem.c: the body's own field by boundary elements (src/charging/bem.c, issue 55), against
 * exact values:
 *
 * - the integral of 1/r over a flat triangle (Wilton et al. 1984) at points above, beside and
 *   in its plane against a fine subdivision (1-point rule on 4^7 pieces), and at the centroid
 *   of an equilateral triangle against the closed form sqrt(3) s ln(2 + sqrt(3));
 * - the sphere (icospheres of 80, 320, 1280 panels): C -> 4 pi eps0 a with the error falling
 *   as h^2 (a factor 3.5 or more per level; measured -4.9 %, -1.3 %, -0.33 %), under 0.5 % at
 *   1280 panels; the solved potential a/r outside and U inside to 0.5 %;
 * - the unit cube: C -> 0.6606785 4 pi eps0 (Hwang and Mascagni 2004), the error falling with
 *   every refinement, within 1 % at 6 x 12^2 x 2 panels (measured -1.6 %, -0.67 %, -0.27 % at
 *   108, 432, 1728: edges and corners make the charge singular, and the error falls as about
 *   h^1.3, not h^2);
 * - two equal spheres at one potential, 4a apart and touching: the classical series
 *   C = 8 pi eps0 a sinh(b) sum (-1)^(n+1) / sinh(n b), cosh b = d / 2a (touching: 2 ln 2
 *   4 pi eps0 a), within 0.5 % at 2 x 1280 panels (measured 0.27 % and 0.26 %); as two
 *   conductors 4a apart, the capacitance matrix: c11 = c22 within 0.5 %, c12 = c21 within 1 %
 *   of the series, reciprocal (c12 = c21) within 1e-3, its sum the one conductor's;
 * - a thin disk of radius a (an open sheet, both sides in one density; rings graded towards
 *   the rim): 8 eps0 a within 0.5 % at 1296 panels (measured 0.27 %);
 * - the paths' cache of the field (fcache.c): a sphere with a boom as two conductors at 1 and
 *   0.5 V; where the cache answers (most of its cube), its potential and field against the
 *   tree's of the same charge at 4 000 random points: within twice the tolerance 1e-3
 *   (measured 2.7e-4 V per volt and 1.0e-3 of |E| + 1/half);
 * - bad input: too many panels refused before any memory is taken; the exact sphere refused;
 *   two conductors in the same place (a singular system) refused, saying so; conductor labels
 *   out of range or a conductor without panels refused. */
#include "mote/charging.h"
#include "../src/charging/ch.h" /* the field's cache (fcache.c) */

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "test.h"

static const double K4 = 4 * MOTE_CH_PI * MOTE_CH_EPS0;

/* the 1-point rule on the triangle cut into 4^level pieces */
static double integral_by_pieces(double t[3][3], const double p[3], int level)
{
    if (level == 0) {
        double c[3], e1[3], e2[3];
        for (int k = 0; k < 3; k++) {
            c[k] = (t[0][k] + t[1][k] + t[2][k]) / 3 - p[k];
            e1[k] = t[1][k] - t[0][k];
            e2[k] = t[2][k] - t[0][k];
        }
        const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0]};
        return 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) /
               sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    }
    double m[3][3], s = 0;
    for (int k = 0; k < 3; k++) {
        m[0][k] = 0.5 * (t[0][k] + t[1][k]);
        m[1][k] = 0.5 * (t[1][k] + t[2][k]);
        m[2][k] = 0.5 * (t[2][k] + t[0][k]);
    }
    double a[4][3][3];
    memcpy(a[0][0], t[0], sizeof t[0]);
    memcpy(a[0][1], m[0], sizeof m[0]);
    memcpy(a[0][2], m[2], sizeof m[0]);
    memcpy(a[1][0], m[0], sizeof m[0]);
    memcpy(a[1][1], t[1], sizeof t[0]);
    memcpy(a[1][2], m[1], sizeof m[0]);
    memcpy(a[2][0], m[2], sizeof m[0]);
    memcpy(a[2][1], m[1], sizeof m[0]);
    memcpy(a[2][2], t[2], sizeof t[0]);
    memcpy(a[3][0], m[0], sizeof m[0]);
    memcpy(a[3][1], m[1], sizeof m[0]);
    memcpy(a[3][2], m[2], sizeof m[0]);
    for (int q = 0; q < 4; q++)
        s += integral_by_pieces(a[q], p, level - 1);
    return s;
}

static void test_triangle_integral(void)
{
    printf("the integral of 1/r over a triangle\n");
    double t[3][3] = {{0, 0, 0}, {1, 0, 0}, {0.3, 0.8, 0}};
    const double pts[][3] = {{0.4, 0.3, 0.5},  {0.4, 0.3, -0.2}, {2, 1, 0.1},
                             {-0.5, 0.2, 0.0}, {1.5, 1.5, 0.0},  {0.5, -0.3, 0.05}};
    for (size_t k = 0; k < sizeof pts / sizeof pts[0]; k++) {
        const double exact = mote_ch_triangle_integral(t, pts[k]);
        const double fine = integral_by_pieces(t, pts[k], 7);
        /* the 1-point rule's error on pieces of 1/128 the size: about 1e-5 relative here */
        CHECK(fabs(exact / fine - 1) < 3e-5, "point %zu: %.12g against %.12g by pieces", k, exact,
              fine);
    }
    const double s = 2.0, h = sqrt(3) / 2 * s;
    double eq[3][3] = {{0, 0, 1}, {s, 0, 1}, {s / 2, h, 1}};
    const double c[3] = {s / 2, h / 3, 1};
    const double closed = sqrt(3) * s * log(2 + sqrt(3));
    CHECK(fabs(mote_ch_triangle_integral(eq, c) / closed - 1) < 1e-13,
          "equilateral at its centroid: %.15g against %.15g", mote_ch_triangle_integral(eq, c),
          closed);
    /* the vertices' order (the normal's side) does not matter */
    double rev[3][3];
    memcpy(rev[0], eq[0], sizeof eq[0]);
    memcpy(rev[1], eq[2], sizeof eq[0]);
    memcpy(rev[2], eq[1], sizeof eq[0]);
    CHECK(fabs(mote_ch_triangle_integral(rev, c) / closed - 1) < 1e-13, "reversed: %.15g",
          mote_ch_triangle_integral(rev, c));
}

/* the gradient of the triangle's integral against central differences of the integral, and the
 * value it returns against mote_ch_triangle_integral */
static void test_triangle_gradient(void)
{
    printf("the gradient of the triangle's integral\n");
    double t[3][3] = {{0, 0, 0}, {1, 0, 0}, {0.3, 0.8, 0}};
    const double pts[][3] = {{0.4, 0.3, 0.5},  {0.4, 0.3, -0.2}, {2, 1, 0.1},  {-0.5, 0.2, 0.0},
                             {1.5, 1.5, 0.0},  {0.5, -0.3, 0.05}, {0.4, 0.3, 1e-3}, {3, -2, 4}};
    for (size_t k = 0; k < sizeof pts / sizeof pts[0]; k++) {
        double g[3], p[3];
        const double v = mote_ch_triangle_gradient(t, pts[k], g);
        CHECK(fabs(v - mote_ch_triangle_integral(t, pts[k])) <= 1e-14 * fabs(v),
              "point %zu: value %.15g", k, v);
        for (int a = 0; a < 3; a++) {
            /* central differences, step 1e-5 of the distance: error about 1e-10 relative */
            const double h = 1e-5 * fmax(1e-2, fabs(pts[k][2]));
            memcpy(p, pts[k], sizeof p);
            p[a] += h;
            const double up = mote_ch_triangle_integral(t, p);
            p[a] -= 2 * h;
            const double dn = mote_ch_triangle_integral(t, p);
            const double fd = (up - dn) / (2 * h);
            CHECK(fabs(g[a] - fd) <= 1e-6 * (fabs(g[0]) + fabs(g[1]) + fabs(g[2])),
                  "point %zu, d/dx%d: %.12g against %.12g by differences", k, a, g[a], fd);
        }
    }
}

/* the direct sum of every panel's exact potential and field (per volt, times 4 pi eps0) */
static void direct_field(const mote_ch_body *b, const double *sigma, const double x[3],
                         double *phi, double E[3])
{
    *phi = 0;
    E[0] = E[1] = E[2] = 0;
    for (uint32_t j = 0; j < b->ntri; j++) {
        double g[3];
        *phi += sigma[j] * mote_ch_triangle_gradient(b->v[j], x, g);
        for (int a = 0; a < 3; a++)
            E[a] -= sigma[j] * g[a];
    }
    *phi /= K4;
    for (int a = 0; a < 3; a++)
        E[a] /= K4;
}

/* The treecode against the direct sum: a sphere with a boom beside it (two conductors at one
 * potential, 1280 + 1040 panels), at 400 points from 0.02 to 8 radii off the surfaces */
static void test_tree(void)
{
    printf("the field's treecode against the direct sum\n");
    mote_err err = {0};
    mote_ch_body b = {0};
    const double size[3] = {4, 0.2, 0.2}, centre[3] = {3.3, 0, 0};
    CHECK(mote_ch_body_icosphere(&b, 1, 3, &err) == MOTE_OK &&
              mote_ch_body_box(&b, size, centre, 5, &err) == MOTE_OK, "%s", err.msg);
    mote_ch_bem f;
    CHECK(mote_ch_bem_solve(&b, 2, NULL, NULL, &f, &err) == MOTE_OK, "%s", err.msg);
    const double theta[3] = {0.3, 0.4, 0.5};
    double eph[3] = {0}, eEk[3] = {0};
    for (int k = 0; k < 3 && f.sigma; k++) {
        mote_ch_ftree *T = mote_ch_ftree_build(&b, f.sigma, theta[k], &err);
        CHECK(T != NULL, "%s", err.msg);
        if (!T)
            break;
        double ephi = 0, eE = 0;
        uint64_t s = 12345;
        for (int i = 0; i < 400; i++) {
            double u[3], x[3];
            for (int a = 0; a < 3; a++) {
                s = s * 6364136223846793005ull + 1442695040888963407ull;
                u[a] = (double)(s >> 11) / 9007199254740992.0;
            }
            /* about the sphere (i even) or the boom (odd), 0.02 to 8 off its surface */
            const double d = 0.02 * pow(400, u[0]), z = 2 * u[1] - 1, ph = 2 * MOTE_CH_PI * u[2];
            const double dir[3] = {sqrt(1 - z * z) * cos(ph), sqrt(1 - z * z) * sin(ph), z};
            if (i % 2 == 0) {
                for (int a = 0; a < 3; a++)
                    x[a] = (1 + d) * dir[a];
            } else { /* off the boom's side at (u[1]-spread) along it */
                x[0] = 1.3 + 4 * u[1];
                x[1] = (0.1 + d) * cos(ph);
                x[2] = (0.1 + d) * sin(ph);
            }
            if (x[0] > 1.3 - 0.02 && x[0] < 5.3 + 0.02 && fabs(x[1]) < 0.12 && fabs(x[2]) < 0.12)
                continue;
            double p1, E1[3], p2, E2[3];
            mote_ch_ftree_eval(T, x, &p1, E1);
            direct_field(&b, f.sigma, x, &p2, E2);
            const double dE = sqrt((E1[0] - E2[0]) * (E1[0] - E2[0]) +
                                   (E1[1] - E2[1]) * (E1[1] - E2[1]) +
                                   (E1[2] - E2[2]) * (E1[2] - E2[2]));
            ephi = fmax(ephi, fabs(p1 / p2 - 1));
            eE = fmax(eE, dE / sqrt(E2[0] * E2[0] + E2[1] * E2[1] + E2[2] * E2[2]));
        }
        printf("  theta %.1f: largest relative error phi %.2e, E %.2e (%zu bytes)\n", theta[k],
               ephi, eE, mote_ch_ftree_bytes(T));
        eph[k] = ephi;
        eEk[k] = eE;
        if (k == 1) { /* the default: what the help promises */
            CHECK(ephi < 1e-3 && eE < 1e-2, "theta 0.4: phi %.3g, E %.3g", ephi, eE);
            /* beyond the monopole radius the monopole's field is within 1e-3 (plus the tree's
             * own error there, 1e-4: its expansions at several times their radius) */
            const double c0[3] = {0, 0, 0};
            const double rf = mote_ch_ftree_monopole_radius(T, c0, 1e-3);
            double worst = 0;
            for (int i = 0; i < 64; i++) {
                const double z = -1 + (2 * i + 1) / 64.0, ph = 2.399963 * i;
                const double x[3] = {rf * sqrt(1 - z * z) * cos(ph), rf * sqrt(1 - z * z) *
                                     sin(ph), rf * z};
                double p2, E2[3];
                direct_field(&b, f.sigma, x, &p2, E2);
                const double em = f.capacitance / K4 / (rf * rf * rf);
                double d2 = 0, e2 = 0;
                for (int a = 0; a < 3; a++) {
                    d2 += (em * x[a] - E2[a]) * (em * x[a] - E2[a]);
                    e2 += E2[a] * E2[a];
                }
                worst = fmax(worst, sqrt(d2 / e2));
            }
            printf("  the monopole from %.4g m (%.3g R_bound): its field within %.2e\n", rf,
                   rf / 5.3, worst);
            CHECK(worst < 1.1e-3 && rf < 1e4, "monopole at %g: %.3g", rf, worst);
        }
        mote_ch_ftree_free(T);
    }
    CHECK(eph[0] < eph[2] && eEk[0] < eEk[2], "the error does not fall with theta: %.3g %.3g, "
          "%.3g %.3g", eph[0], eph[2], eEk[0], eEk[2]);
    CHECK(mote_ch_ftree_build(&b, f.sigma, 1.0, &err) == NULL &&
              strstr(err.msg, "theta must be in (0, 1), found 1") != NULL,
          "theta 1 taken: %s", err.msg);
    mote_ch_bem_free(&f);
    mote_ch_body_free(&b);
}

static double solve_c(mote_ch_body *b)
{
    mote_err err = {0};
    mote_ch_bem f;
    int rc = mote_ch_bem_solve(b, 2, NULL, NULL, &f, &err);
    CHECK(rc == MOTE_OK, "solve: %s", err.msg);
    const double C = rc ? NAN : f.capacitance;
    mote_ch_bem_free(&f);
    return C;
}

static void test_fcache(void)
{
    printf("the paths' cache of the field (fcache.c)\n");
    mote_err err = {0};
    mote_ch_body b = {0};
    const double size[3] = {3, 0.2, 0.2}, centre[3] = {2.5, 0, 0};
    CHECK(mote_ch_body_icosphere(&b, 1, 3, &err) == MOTE_OK, "%s", err.msg);
    const uint32_t nsph = b.ntri;
    CHECK(mote_ch_body_box(&b, size, centre, 4, &err) == MOTE_OK, "%s", err.msg);
    int *cond = malloc(b.ntri * sizeof *cond);
    for (uint32_t i = 0; cond && i < b.ntri; i++)
        cond[i] = i >= nsph; /* the sphere 0, the boom 1 */
    mote_ch_bem f;
    if (!cond || mote_ch_bem_solve_conductors(&b, cond, 2, 2, NULL, NULL, &f, &err)) {
        CHECK(0, "solve: %s", err.msg);
        free(cond);
        mote_ch_body_free(&b);
        return;
    }
    mote_ch_geometry g;
    mote_ch_body_geometry(&b, &g);
    const double half = 1.1 * g.r_bound, coef[2] = {1, 0.5}, tol = 1e-3;
    ch_fcache *c = ch_fcache_build(&b, &f, 0.4, g.centre, half, g.r_bound / 16, tol, 1e9, 2, &err);
    double *sig = malloc(b.ntri * sizeof *sig);
    for (uint32_t j = 0; sig && j < b.ntri; j++)
        sig[j] = coef[0] * f.basis[j] + coef[1] * f.basis[f.n + j];
    mote_ch_ftree *T = sig ? mote_ch_ftree_build(&b, sig, 0.4, &err) : NULL;
    CHECK(c && T, "cache or tree: %s", err.msg);
    if (c && T) {
        long nk, nt;
        size_t bytes;
        ch_fcache_stats(c, &nk, &nt, &bytes);
        uint64_t s = 777;
        int n = 4000, answered = 0;
        double ephi = 0, eE = 0;
        for (int i = 0; i < n; i++) {
            double x[3];
            for (int a = 0; a < 3; a++) {
                s = s * 6364136223846793005ull + 1442695040888963407ull;
                x[a] = g.centre[a] + half * (2 * ((double)(s >> 11) / 9007199254740992.0) - 1);
            }
            double p1, E1[3], p2, E2[3];
            if (ch_fcache_eval(c, coef, x, &p1, E1))
                continue;
            answered++;
            mote_ch_ftree_eval(T, x, &p2, E2);
            const double Em = sqrt(E2[0] * E2[0] + E2[1] * E2[1] + E2[2] * E2[2]);
            const double dE = sqrt((E1[0] - E2[0]) * (E1[0] - E2[0]) +
                                   (E1[1] - E2[1]) * (E1[1] - E2[1]) +
                                   (E1[2] - E2[2]) * (E1[2] - E2[2]));
            ephi = fmax(ephi, fabs(p1 - p2));
            eE = fmax(eE, dE / (Em + 1 / half));
        }
        printf("  %ld cells interpolated, %ld left to the tree, %.3g MB; answered %d of %d "
               "points; largest differences: potential %.3g V, field %.3g of |E| + 1/half\n",
               nk, nt, bytes / 1e6, answered, n, ephi, eE);
        /* the tolerance holds at the cells' centres and face centres; between them the
         * interpolation could stray a little further (measured 2.7e-4 V and 1.0e-3: within it) */
        CHECK(answered > n / 2 && nk > 0 && nt > 0, "the cache answered %d of %d points", answered,
              n);
        CHECK(ephi <= 2 * tol && eE <= 2 * tol,
              "the cache against the tree: potential %.3g, field %.3g (tolerance %g)", ephi, eE,
              tol);
        /* outside its cube (or not finite) the tree answers */
        const double far[3] = {g.centre[0] + 2 * half, 0, 0}, bad[3] = {NAN, 0, 0};
        double p, E[3];
        CHECK(ch_fcache_eval(c, coef, far, &p, E) == 1 && ch_fcache_eval(c, coef, bad, &p, E) == 1,
              "the cache answered outside its cube");
    }
    /* a cache over its memory bound is refused, saying so */
    mote_err e2 = {0};
    ch_fcache *small = ch_fcache_build(&b, &f, 0.4, g.centre, half, g.r_bound / 16, tol, 1e5, 2,
                                       &e2);
    CHECK(!small && e2.code == MOTE_ENOMEM && strstr(e2.msg, "more than 0 MB") &&
              strstr(e2.msg, "use cache=off"),
          "a cache over its bound: %s", small ? "built" : e2.msg);
    ch_fcache_free(small);
    ch_fcache_free(c);
    mote_ch_ftree_free(T);
    free(sig);
    free(cond);
    mote_ch_bem_free(&f);
    mote_ch_body_free(&b);
}

static void test_sphere(void)
{
    printf("the sphere: C = 4 pi eps0 a, the potential a / r\n");
    double errs[4];
    for (int level = 1; level <= 3; level++) {
        mote_ch_body b = {0};
        mote_err err = {0};
        CHECK(mote_ch_body_icosphere(&b, 2.0, level, &err) == MOTE_OK, "%s", err.msg);
        mote_ch_bem f;
        CHECK(mote_ch_bem_solve(&b, 2, NULL, NULL, &f, &err) == MOTE_OK, "%s", err.msg);
        errs[level] = f.capacitance / (K4 * 2.0) - 1;
        printf("  %5u panels: C / (4 pi eps0 a) - 1 = %+.3e\n", b.ntri, errs[level]);
        if (level == 3) {
            CHECK(fabs(errs[3]) < 5e-3, "1280 panels: error %g", errs[3]);
            const double out[3] = {0, 0, 4.0}, far[3] = {3, 4, 12}, in[3] = {0.3, -0.2, 0.1};
            CHECK(fabs(mote_ch_bem_potential(&b, &f, out) / 0.5 - 1) < 5e-3, "phi(2a) = %g",
                  mote_ch_bem_potential(&b, &f, out));
            CHECK(fabs(mote_ch_bem_potential(&b, &f, far) / (2.0 / 13) - 1) < 5e-3,
                  "phi(6.5a) = %g", mote_ch_bem_potential(&b, &f, far));
            CHECK(fabs(mote_ch_bem_potential(&b, &f, in) - 1) < 5e-3, "phi inside = %g",
                  mote_ch_bem_potential(&b, &f, in));
        }
        mote_ch_bem_free(&f);
        mote_ch_body_free(&b);
    }
    CHECK(fabs(errs[1] / errs[2]) > 3.5 && fabs(errs[2] / errs[3]) > 3.5,
          "the error does not fall as h^2: %g %g %g", errs[1], errs[2], errs[3]);
}

static void test_cube(void)
{
    printf("the unit cube: C = 0.6606785 4 pi eps0 (Hwang and Mascagni 2004)\n");
    double prev = INFINITY;
    const int subdiv[] = {3, 6, 12};
    for (int k = 0; k < 3; k++) {
        mote_ch_body b = {0};
        mote_err err = {0};
        const double size[3] = {1, 1, 1}, centre[3] = {0, 0, 0};
        CHECK(mote_ch_body_box(&b, size, centre, subdiv[k], &err) == MOTE_OK, "%s", err.msg);
        const double e = solve_c(&b) / K4 / 0.6606785 - 1;
        printf("  %5u panels: C / C_exact - 1 = %+.3e\n", b.ntri, e);
        CHECK(fabs(e) < fabs(prev), "the error grew: %g after %g", e, prev);
        prev = e;
        mote_ch_body_free(&b);
    }
    CHECK(fabs(prev) < 0.01, "1728 panels: error %g", prev);
}

/* two spheres of radius a, centres d apart on x, as one conductor (C) and as two (their
 * capacitance matrix into cm, when not NULL) */
static double two_spheres(double a, double d, int level, double cm[4])
{
    mote_ch_body b = {0};
    mote_err err = {0};
    CHECK(mote_ch_body_icosphere(&b, a, level, &err) == MOTE_OK, "%s", err.msg);
    const uint32_t half = b.ntri;
    CHECK(mote_ch_body_icosphere(&b, a, level, &err) == MOTE_OK, "%s", err.msg);
    for (uint32_t i = 0; i < b.ntri; i++)
        for (int j = 0; j < 3; j++)
            b.v[i][j][0] += i < half ? -d / 2 : d / 2;
    double C = NAN;
    if (!cm) {
        C = solve_c(&b);
    } else {
        int *cond = malloc(b.ntri * sizeof *cond);
        for (uint32_t i = 0; cond && i < b.ntri; i++)
            cond[i] = i >= half;
        mote_ch_bem f;
        CHECK(cond && mote_ch_bem_solve_conductors(&b, cond, 2, 2, NULL, NULL, &f, &err) == MOTE_OK,
              "%s", err.msg);
        if (cond && f.nc == 2) {
            memcpy(cm, f.cmat, 4 * sizeof *cm);
            C = f.capacitance;
            double q = 0; /* the all-at-1-V density is the columns' sum */
            for (uint32_t j = 0; j < b.ntri; j++)
                q += f.sigma[j] * b.area[j];
            CHECK(fabs(q / C - 1) < 1e-12, "the columns' sum: %.17g against %.17g", q, C);
            mote_ch_bem_free(&f);
        }
        free(cond);
    }
    mote_ch_body_free(&b);
    return C;
}

/* the classical series for two equal spheres, cosh b = d / 2a, per 4 pi eps0 a (Smythe,
 * Static and Dynamic Electricity, 5.08): at one potential C = 2 sinh(b) sum (-1)^(n+1) /
 * sinh(n b); the matrix c11 = sinh(b) sum 1 / sinh((2n - 1) b), c12 = -sinh(b) sum 1 /
 * sinh(2n b) */
static double series(double d_over_2a)
{
    const double beta = acosh(d_over_2a);
    double s = 0;
    for (int n = 1; n < 2000; n++)
        s += (n % 2 ? 1 : -1) / sinh(n * beta) * sinh(beta);
    return 2 * s;
}

static void series_matrix(double d_over_2a, double *c11, double *c12)
{
    const double beta = acosh(d_over_2a);
    *c11 = *c12 = 0;
    for (int n = 1; n < 2000; n++) {
        *c11 += sinh(beta) / sinh((2 * n - 1) * beta);
        *c12 -= sinh(beta) / sinh(2 * n * beta);
    }
}

static void test_two_spheres(void)
{
    printf("two equal spheres: the classical series\n");
    double cm[4], c11, c12;
    series_matrix(2, &c11, &c12);
    if (getenv("MOTE_SANITIZED")) { /* (2 x 1280 panels take a minute there: the same code
                                     * as the sphere's, checked for its numbers in the plain
                                     * pass) */
        CHECK(fabs(two_spheres(1, 4, 1, NULL) / K4 / series(2) - 1) < 0.05, "d = 4a, 2 x 80 panels");
        two_spheres(1, 4, 2, cm); /* (the matrix: 2 x 320 panels, errors about h^2) */
        CHECK(fabs(cm[0] / K4 / c11 - 1) < 0.02 && fabs(cm[1] / K4 / c12 - 1) < 0.04,
              "d = 4a, 2 x 320 panels: c11 %g c12 %g", cm[0] / K4, cm[1] / K4);
        return;
    }
    const double apart = two_spheres(1, 4, 3, NULL) / K4, exact = series(2);
    printf("  d = 4a: %.6f against %.6f\n", apart, exact);
    CHECK(fabs(apart / exact - 1) < 0.005, "d = 4a: %g against %g", apart, exact);
    const double touching = two_spheres(1, 2, 3, NULL) / K4;
    printf("  touching: %.6f against 2 ln 2 = %.6f\n", touching, 2 * log(2));
    CHECK(fabs(touching / (2 * log(2)) - 1) < 0.005, "touching: %g", touching);
    /* the capacitance matrix: each sphere its own conductor, both right-hand sides on one LU;
     * c12 is the small difference of the induced charges, so its error is that of the
     * potential (h^2) over c12 / c11 */
    const double both = two_spheres(1, 4, 3, cm) / K4;
    for (int q = 0; q < 4; q++)
        cm[q] /= K4;
    printf("  d = 4a as two conductors: c11 %.6f c22 %.6f (series %.6f), c12 %.6f c21 %.6f "
           "(series %.6f)\n", cm[0], cm[3], c11, cm[1], cm[2], c12);
    CHECK(fabs(cm[0] / c11 - 1) < 0.005 && fabs(cm[3] / c11 - 1) < 0.005, "c11 %g c22 %g "
          "against %g", cm[0], cm[3], c11);
    CHECK(fabs(cm[1] / c12 - 1) < 0.01 && fabs(cm[2] / c12 - 1) < 0.01, "c12 %g c21 %g "
          "against %g", cm[1], cm[2], c12);
    CHECK(fabs(cm[1] / cm[2] - 1) < 1e-3, "reciprocity: c12 %g c21 %g", cm[1], cm[2]);
    CHECK(fabs(both / apart - 1) < 1e-12, "the matrix's sum %.17g against one conductor's %.17g",
          both, apart);
}

static void test_disk(const char *dir)
{
    printf("a thin disk: C = 8 eps0 a\n");
    char path[512];
    snprintf(path, sizeof path, "%s/disk.obj", dir);
    FILE *f = fopen(path, "w");
    CHECK(f != NULL, "cannot write %s", path);
    if (!f)
        return;
    /* rings graded towards the rim (where the charge grows as 1 / sqrt(a - r)) */
    const int nr = 14, nt = 48;
    fprintf(f, "v 0 0 0\n");
    for (int i = 1; i <= nr; i++) {
        const double r = sin(0.5 * MOTE_CH_PI * i / nr);
        for (int j = 0; j < nt; j++)
            fprintf(f, "v %.17g %.17g 0\n", r * cos(2 * MOTE_CH_PI * j / nt),
                    r * sin(2 * MOTE_CH_PI * j / nt));
    }
    for (int j = 0; j < nt; j++)
        fprintf(f, "f 1 %d %d\n", 2 + j, 2 + (j + 1) % nt);
    for (int i = 1; i < nr; i++)
        for (int j = 0; j < nt; j++) {
            const int a = 2 + (i - 1) * nt + j, b = 2 + (i - 1) * nt + (j + 1) % nt;
            fprintf(f, "f %d %d %d\nf %d %d %d\n", a, a + nt, b + nt, a, b + nt, b);
        }
    fclose(f);
    mote_ch_body b = {0};
    mote_err err = {0};
    mote_ch_load_opts o = {.format = "auto", .scale = 1, .rot_axis = -1};
    mote_ch_load_report rep;
    CHECK(mote_ch_body_load(&b, path, &o, &rep, &err) == MOTE_OK, "%s", err.msg);
    const double C = solve_c(&b), exact = 8 * MOTE_CH_EPS0;
    printf("  %u panels: C / (8 eps0 a) - 1 = %+.3e\n", b.ntri, C / exact - 1);
    CHECK(fabs(C / exact - 1) < 0.005, "disk: %g against %g", C, exact);
    mote_ch_body_free(&b);
}

static void test_refusals(void)
{
    printf("refusals\n");
    mote_err err = {0};
    mote_ch_bem f;
    mote_ch_body b = {0};
    CHECK(mote_ch_body_sphere(&b, 1, &err) == MOTE_OK, "%s", err.msg);
    CHECK(mote_ch_bem_solve(&b, 1, NULL, NULL, &f, &err) == MOTE_EINVAL, "the exact sphere was solved");
    CHECK_HAS(err.msg, "the exact sphere's field is exact already");
    mote_ch_body_free(&b);
    memset(&b, 0, sizeof b);
    CHECK(mote_ch_body_icosphere(&b, 1, 7, &err) == MOTE_OK, "%s", err.msg); /* 327 680 */
    CHECK(mote_ch_bem_solve(&b, 1, NULL, NULL, &f, &err) == MOTE_ENOMEM, "327 680 panels were taken");
    CHECK_HAS(err.msg, "327680 panels are more than the field's solve takes (at most 16384");
    mote_ch_body_free(&b);
    /* two conductors in the same place: their panels' rows are the same, the system singular */
    memset(&b, 0, sizeof b);
    CHECK(mote_ch_body_icosphere(&b, 1, 1, &err) == MOTE_OK &&
              mote_ch_body_icosphere(&b, 1, 1, &err) == MOTE_OK, "%s", err.msg);
    CHECK(mote_ch_bem_solve(&b, 1, NULL, NULL, &f, &err) == MOTE_EINVAL, "coincident conductors solved");
    CHECK_HAS(err.msg, "the field's system of 160 panels is singular");
    CHECK_HAS(err.msg, "two panels in the same place (coincident conductors)?");
    mote_ch_body_free(&b);
    /* the conductors' labels: each panel on one of them, each of them with a panel */
    memset(&b, 0, sizeof b);
    CHECK(mote_ch_body_icosphere(&b, 1, 0, &err) == MOTE_OK, "%s", err.msg);
    int cond[20] = {0};
    cond[7] = 2;
    CHECK(mote_ch_bem_solve_conductors(&b, cond, 2, 1, NULL, NULL, &f, &err) == MOTE_EINVAL,
          "a label out of range taken");
    CHECK_HAS(err.msg, "panel 8 is on conductor 2 (of 0 to 1)");
    cond[7] = 0;
    CHECK(mote_ch_bem_solve_conductors(&b, cond, 2, 1, NULL, NULL, &f, &err) == MOTE_EINVAL,
          "a conductor without panels taken");
    CHECK_HAS(err.msg, "conductor 1 has no panels");
    CHECK(mote_ch_bem_solve_conductors(&b, NULL, 2, 1, NULL, NULL, &f, &err) == MOTE_EINVAL,
          "two conductors without labels taken");
    mote_ch_body_free(&b);
}

int main(void)
{
    char dir[256];
    if (!test_tmpdir_make(dir, sizeof dir, "mote_test_bem"))
        return 1;
    test_triangle_integral();
    test_triangle_gradient();
    test_tree();
    test_fcache();
    test_sphere();
    test_cube();
    test_two_spheres();
    test_disk(dir);
    test_refusals();
    test_remove_tree(dir);
    return test_summary();
}
