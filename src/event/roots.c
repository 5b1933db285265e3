/* roots.c: the earliest zero crossing of a polynomial of degree <= 4 on an interval. Used to
 * predict hits under a uniform field, where a centre's distance to a wall is quadratic in time
 * and its squared distance to a corner quartic. The real roots of the derivative split [0, tmax]
 * into intervals on which the polynomial is monotone; the first interval whose end is <= 0
 * holds the crossing, which bisection then brackets to adjacent doubles. The derivative's roots
 * are found the same way, recursively, down to a linear polynomial. */
#include "roots.h"

#include <math.h>

static double horner(const double *c, int deg, double t)
{
    double p = c[deg];
    for (int k = deg - 1; k >= 0; k--)
        p = p * t + c[k];
    return p;
}

/* A root of the polynomial in [u, w], where p(u) and p(w) have opposite signs (or one is 0):
 * bisection until the bracket cannot shrink. Returns the end nearer the sign of p(u) when
 * want_before, else the midpoint's final value. */
static double bisect(const double *c, int deg, double u, double w, int want_before)
{
    double pu = horner(c, deg, u);
    for (int it = 0; it < 2000; it++) {
        double m = 0.5 * (u + w);
        if (!(m > u && m < w))
            break;
        double pm = horner(c, deg, m);
        if ((pm > 0) == (pu > 0)) {
            u = m;
            pu = pm;
        } else {
            w = m;
        }
    }
    return want_before ? u : w;
}

/* All real roots in (a, b) of the polynomial (deg >= 1), ascending; returns their number. */
static int roots_in(const double *c, int deg, double a, double b, double *out)
{
    while (deg > 0 && c[deg] == 0)
        deg--;
    if (deg == 0)
        return 0;
    if (deg == 1) {
        double t = -c[0] / c[1];
        if (t > a && t < b) {
            out[0] = t;
            return 1;
        }
        return 0;
    }
    double d[4], crit[4];
    for (int k = 1; k <= deg; k++)
        d[k - 1] = k * c[k];
    int nc = roots_in(d, deg - 1, a, b, crit);
    int n = 0;
    double u = a;
    for (int k = 0; k <= nc; k++) {
        double w = k < nc ? crit[k] : b;
        double pu = horner(c, deg, u), pw = horner(c, deg, w);
        if (pw == 0 && w < b)
            out[n++] = w;
        else if ((pu < 0 && pw > 0) || (pu > 0 && pw < 0))
            out[n++] = bisect(c, deg, u, w, 0);
        u = w;
    }
    return n;
}

double mote_first_root(const double *c, int deg, double tmax)
{
    while (deg > 0 && c[deg] == 0)
        deg--;
    if (!(c[0] > 0))
        return 0;
    return mote_first_entry(c, deg, tmax); /* from above zero: its first entry */
}

double mote_first_entry(const double *c, int deg, double tmax)
{
    while (deg > 0 && c[deg] == 0)
        deg--;
    if (deg == 0 || !(tmax > 0))
        return INFINITY;
    double crit[4];
    int nc = 0;
    if (deg >= 2) {
        double d[4];
        for (int k = 1; k <= deg; k++)
            d[k - 1] = k * c[k];
        nc = roots_in(d, deg - 1, 0, tmax, crit);
    }
    /* on each monotone piece: once above zero, the first piece that ends at or below it holds
     * the entry; below zero, a piece that ends above it rose there (and stays up to its end) */
    double u = 0;
    int above = c[0] > 0;
    for (int k = 0; k <= nc; k++) {
        double w = k < nc ? crit[k] : tmax, pw = horner(c, deg, w);
        if (above && !(pw > 0))
            return bisect(c, deg, u, w, 1);
        if (pw > 0)
            above = 1;
        u = w;
    }
    return INFINITY;
}
