/* test_roots.c: mote_first_root, the earliest zero crossing of a polynomial of degree <= 4
 * (event prediction under gravity): known roots of quadratics and quartics, tangent and missing
 * crossings, the "not later than the crossing" guarantee, and random polynomials against a dense
 * scan. */
#include <stdlib.h>

#include "../src/event/roots.h"
#include "mote/core.h"
#include "test.h"

static double horner(const double *c, int deg, double t)
{
    double p = c[deg];
    for (int k = deg - 1; k >= 0; k--)
        p = p * t + c[k];
    return p;
}

int main(void)
{
    /* (t - 1)(t - 3) = t^2 - 4t + 3: first crossing at 1 */
    double q[] = {3, -4, 1};
    double t = mote_first_root(q, 2, 10);
    CHECK(fabs(t - 1) < 1e-15 && horner(q, 2, t) > 0, "quadratic: t = %.17g", t);
    CHECK(mote_first_root(q, 2, 0.5) == INFINITY, "quadratic before its root: not infinite");
    /* a parabola that never reaches zero: t^2 - 2t + 2 */
    double nz[] = {2, -2, 1};
    CHECK(mote_first_root(nz, 2, 100) == INFINITY, "no root: not infinite");
    /* already non-positive */
    double neg[] = {-1, 1};
    CHECK(mote_first_root(neg, 1, 5) == 0, "p(0) < 0 must give 0");
    /* linear */
    double lin[] = {2, -4};
    t = mote_first_root(lin, 1, 5);
    CHECK(fabs(t - 0.5) < 1e-15, "linear: %.17g", t);
    /* quartic (t-1)(t-2)(t-3)(t-4) = t^4 - 10t^3 + 35t^2 - 50t + 24: positive before 1 */
    double qu[] = {24, -50, 35, -10, 1};
    t = mote_first_root(qu, 4, 10);
    CHECK(fabs(t - 1) < 1e-14 && horner(qu, 4, t) > 0, "quartic: t = %.17g", t);
    /* a quartic that dips below zero only between 2.9 and 3.1 (a corner grazed late) */
    /* p = ((t-3)^2 - 0.01)^2 * 0 + (t-3)^2 - 0.01, written as a quadratic in the quartic slot */
    double g[] = {9 - 0.01, -6, 1, 0, 0};
    t = mote_first_root(g, 4, 10);
    CHECK(fabs(t - 2.9) < 1e-14, "graze: %.17g", t);
    /* tangent touch: (t-2)^2 reaches 0 exactly at 2 */
    double tg[] = {4, -4, 1};
    t = mote_first_root(tg, 2, 10);
    CHECK(fabs(t - 2) < 1e-7, "tangent: %.17g", t);
    /* random polynomials against a dense scan */
    mote_rng g2;
    mote_rng_seed(&g2, test_seed(5));
    int bad = 0;
    for (int trial = 0; trial < 2000; trial++) {
        double c[5];
        int deg = 2 + trial % 3;
        for (int k = 0; k <= deg; k++)
            c[k] = 2 * mote_rng_uniform(&g2) - 1;
        c[0] = fabs(c[0]) + 1e-3;
        double r = mote_first_root(c, deg, 3);
        /* scan for the first sign change */
        double scan = INFINITY;
        for (int s = 1; s <= 30000; s++) {
            double x = 3.0 * s / 30000;
            if (!(horner(c, deg, x) > 0)) {
                scan = x;
                break;
            }
        }
        if (scan == INFINITY) {
            if (r != INFINITY && horner(c, deg, r) > 1e-9)
                bad++;
        } else if (!(r <= scan && r > scan - 3.0 / 30000 - 1e-12 && horner(c, deg, r) >= 0)) {
            bad++;
        }
    }
    CHECK(bad == 0, "%d of 2000 random polynomials disagree with a dense scan", bad);
    return test_summary();
}
