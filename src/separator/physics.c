/* physics.c: the separator's single-particle physics (specs/separator.md 2.5, 2.7, 4): the
 * Schiller-Naumann drag factor, the still-gas terminal velocity and cut size, and the size
 * distributions with their number-basis sampling tables. */
#include "mote/separator.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


double mote_sep_drag_f(double Re)
{
    /* Re^0.687 as exp(0.687 ln Re): f within 2e-15 relative of pow()'s, in half its time (the
     * drift's largest cost); Re = 0 gives exp(-inf) = 0 */
    return Re <= 1000 ? 1 + 0.15 * exp(0.687 * log(Re)) : 0.44 * Re / 24;
}

double mote_sep_terminal_velocity(double d, double rho_p, double rho_g, double mu_g, double g,
                                  double *Re_t)
{
    if (Re_t)
        *Re_t = 0;
    if (!(rho_p > rho_g) || !(d > 0) || !(g > 0))
        return 0;
    if (!(mu_g > 0) || !(rho_g > 0)) /* vacuum: no terminal velocity */
        return INFINITY;
    /* C_d Re^2 = 24 Re f(Re) rises monotonically with Re */
    const double Ar = rho_g * (rho_p - rho_g) * g * d * d * d / (mu_g * mu_g);
    double lo = 0, hi = 1;
    while (24 * hi * mote_sep_drag_f(hi) < 4.0 / 3 * Ar)
        hi *= 2;
    for (int it = 0; it < 200; it++) {
        const double mid = 0.5 * (lo + hi);
        if (24 * mid * mote_sep_drag_f(mid) < 4.0 / 3 * Ar)
            lo = mid;
        else
            hi = mid;
    }
    const double Re = 0.5 * (lo + hi);
    if (Re_t)
        *Re_t = Re;
    return Re * mu_g / (rho_g * d);
}

double mote_sep_cut_size(double v, double rho_p, double rho_g, double mu_g, double g)
{
    double lo = 1e-9, hi = 1;
    for (int it = 0; it < 200; it++) {
        const double mid = sqrt(lo * hi);
        if (mote_sep_terminal_velocity(mid, rho_p, rho_g, mu_g, g, NULL) < v)
            lo = mid;
        else
            hi = mid;
    }
    return sqrt(lo * hi);
}

/* ---- size distributions --------------------------------------------------------------------- */

/* The cumulative undersize F(d) of the distribution's own basis, untruncated. */
static double cdf_own(const mote_sep_dist *s, double d)
{
    switch (s->type) {
    case MOTE_SEP_LOGNORMAL:
        return 0.5 * erfc(-log(d / s->a) / (log(s->b) * sqrt(2.0)));
    case MOTE_SEP_ROSIN_RAMMLER:
        return -expm1(-pow(d / s->a, s->b));
    case MOTE_SEP_TABLE: {
        if (d <= s->td[0])
            return s->tF[0];
        int k = 0;
        while (k + 2 < s->tn && s->td[k + 1] < d)
            k++;
        if (d >= s->td[k + 1])
            return s->tF[k + 1];
        const double f = (log(d) - log(s->td[k])) / (log(s->td[k + 1]) - log(s->td[k]));
        return s->tF[k] + f * (s->tF[k + 1] - s->tF[k]);
    }
    default: /* loguniform */
        return (log(d) - log(s->lo)) / (log(s->hi) - log(s->lo));
    }
}

/* The sampling table only (a table distribution keeps its rows). */
static void free_sampling(mote_sep_dist *s)
{
    free(s->lnd);
    free(s->cdf);
    s->lnd = s->cdf = NULL;
    s->n = 0;
}

void mote_sep_dist_free(mote_sep_dist *s)
{
    free_sampling(s);
    free(s->td);
    free(s->tF);
    s->td = s->tF = NULL;
    s->tn = 0;
}

int mote_sep_dist_table(mote_sep_dist *s, int n, const double *d, const double *F, mote_err *err)
{
    if (n < 2)
        return mote_fail(err, MOTE_EINVAL, "size table: at least 2 rows, found %d", n);
    for (int k = 0; k < n; k++) {
        if (!(d[k] > 0) || !isfinite(d[k]) || (k && !(d[k] > d[k - 1])))
            return mote_fail(err, MOTE_EINVAL, "row %d: the diameters must be > 0 and increase "
                             "(found %g)", k + 1, d[k]);
        if (!(F[k] >= 0 && F[k] <= 1) || (k && F[k] < F[k - 1]))
            return mote_fail(err, MOTE_EINVAL, "row %d: the cumulative undersize must lie in "
                             "[0, 1] and not decrease (found %g)", k + 1, F[k]);
    }
    double *a = malloc((size_t)n * sizeof *a), *b = malloc((size_t)n * sizeof *b);
    if (!a || !b) {
        free(a);
        free(b);
        return mote_fail(err, MOTE_ENOMEM, "size table: out of memory");
    }
    memcpy(a, d, (size_t)n * sizeof *a);
    memcpy(b, F, (size_t)n * sizeof *b);
    free(s->td);
    free(s->tF);
    s->td = a;
    s->tF = b;
    s->tn = n;
    if (!(s->lo >= d[0] && s->lo < d[n - 1]))
        s->lo = d[0];
    if (!(s->hi <= d[n - 1] && s->hi > s->lo))
        s->hi = d[n - 1];
    return MOTE_OK;
}

int mote_sep_dist_build(mote_sep_dist *s, mote_err *err)
{
    free_sampling(s);
    if (s->type == MOTE_SEP_TABLE && s->tn < 2)
        return mote_fail(err, MOTE_EINVAL, "size table: no rows");
    if (s->type == MOTE_SEP_MONO) {
        if (!(s->a > 0) || !isfinite(s->a))
            return mote_fail(err, MOTE_EINVAL, "size mono: the diameter must be > 0 m");
        return MOTE_OK;
    }
    if (!(s->lo > 0) || !(s->hi > s->lo) || !isfinite(s->hi))
        return mote_fail(err, MOTE_EINVAL, "size: need 0 < d_min < d_max (found %g and %g m)",
                         s->lo, s->hi);
    if (s->type == MOTE_SEP_LOGNORMAL && (!(s->a > 0) || !(s->b >= 1)))
        return mote_fail(err, MOTE_EINVAL, "size lognormal: need d50 > 0 and sigma_g >= 1");
    if (s->type == MOTE_SEP_ROSIN_RAMMLER && (!(s->a > 0) || !(s->b > 0)))
        return mote_fail(err, MOTE_EINVAL, "size rosin_rammler: need d' > 0 and n > 0");
    const int n = 4096;
    s->lnd = malloc((size_t)n * sizeof *s->lnd);
    s->cdf = malloc((size_t)n * sizeof *s->cdf);
    if (!s->lnd || !s->cdf) {
        free_sampling(s);
        return mote_fail(err, MOTE_ENOMEM, "size: out of memory");
    }
    s->n = n;
    /* the number-basis density: q0 = q3 / d^3 for a mass basis; integrate the own-basis
     * increments between nodes (exact for the own CDF), weighted by 1/d^3 at the midpoint in
     * ln d */
    const double a = log(s->lo), b = log(s->hi), h = (b - a) / (n - 1);
    s->lnd[0] = a;
    s->cdf[0] = 0;
    double Fprev = cdf_own(s, s->lo);
    for (int k = 1; k < n; k++) {
        s->lnd[k] = a + k * h;
        const double F = cdf_own(s, exp(s->lnd[k]));
        double dF = F - Fprev;
        if (!s->number_basis)
            dF *= exp(-3 * (s->lnd[k] - 0.5 * h));
        s->cdf[k] = s->cdf[k - 1] + fmax(dF, 0);
        Fprev = F;
    }
    const double tot = s->cdf[n - 1];
    if (!(tot > 0))
        return mote_fail(err, MOTE_EINVAL, "size: the distribution has no mass between %g and "
                         "%g m", s->lo, s->hi);
    for (int k = 0; k < n; k++)
        s->cdf[k] /= tot;
    return MOTE_OK;
}

double mote_sep_dist_sample(const mote_sep_dist *s, double u)
{
    if (s->type == MOTE_SEP_MONO || s->n == 0)
        return s->a;
    int lo = 0, hi = s->n - 1;
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        if (s->cdf[mid] <= u)
            lo = mid;
        else
            hi = mid;
    }
    const double c0 = s->cdf[lo], c1 = s->cdf[hi];
    const double f = c1 > c0 ? (u - c0) / (c1 - c0) : 0;
    return exp(s->lnd[lo] + f * (s->lnd[hi] - s->lnd[lo]));
}

double mote_sep_dist_min(const mote_sep_dist *s)
{
    return s->type == MOTE_SEP_MONO ? s->a : s->lo;
}

double mote_sep_dist_max(const mote_sep_dist *s)
{
    return s->type == MOTE_SEP_MONO ? s->a : s->hi;
}
