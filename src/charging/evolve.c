/* evolve.c: the charging of the charged body in time (spec 6.6), C dU/dt = I_net(U). The net
 * current is tabulated by Monte Carlo runs (common random numbers) on an adaptive grid: from U0
 * in steps of 0.1 min(kT/|Z|), doubled until the net current changes sign, then every interval
 * whose end currents differ by more than 5% of the largest species current there is bisected;
 * between the points it is interpolated by monotone piecewise-cubic Hermite curves
 * (Fritsch-Carlson). The equation has one unknown and I_net(U) keeps its sign between U0 and the
 * floating potential, so its solution is the time t(U) = C * integral dU / I_net(U), which is
 * integrated (Simpson's rule on a fine grid of the interpolant) and inverted; no stiff time
 * stepping is needed. Close to U_f, where t(U) grows without bound, the linearised law
 * U_f - U ~ exp(-t / tau), tau = C / |dI/dU|, continues it. */
#include "mote/charging.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ch.h"

void ch_table_free(ch_table *t)
{
    free(t->U);
    free(t->I);
    free(t->d);
    free(t->tt);
    free(t->tu);
    free(t->col);
    memset(t, 0, sizeof *t);
}

static int table_put(ch_table *t, double U, double I, double Imax, const double *col)
{
    double *nc = realloc(t->col, (size_t)(t->n + 1) * (size_t)t->ncol * sizeof *nc);
    if (!nc)
        return -1;
    t->col = nc;
    double *nu = realloc(t->U, (size_t)(t->n + 1) * sizeof *nu);
    if (!nu)
        return -1;
    t->U = nu;
    double *ni = realloc(t->I, (size_t)(t->n + 1) * sizeof *ni);
    if (!ni)
        return -1;
    t->I = ni;
    double *nm = realloc(t->d, (size_t)(t->n + 1) * sizeof *nm);
    if (!nm)
        return -1;
    t->d = nm; /* (holds the largest species current until the slopes replace it) */
    int k = t->n++;
    const size_t w = (size_t)t->ncol;
    while (k > 0 && ((t->U[k - 1] > U) != t->down)) { /* keep U ordered along the path */
        t->U[k] = t->U[k - 1];
        t->I[k] = t->I[k - 1];
        t->d[k] = t->d[k - 1];
        memcpy(t->col + (size_t)k * w, t->col + (size_t)(k - 1) * w, w * sizeof *t->col);
        k--;
    }
    t->U[k] = U;
    t->I[k] = I;
    t->d[k] = Imax;
    memcpy(t->col + (size_t)k * w, col, w * sizeof *t->col);
    return 0;
}

double ch_table_col(const ch_table *t, double U, int j)
{
    int k = 0;
    while (k + 2 < t->n && (t->down ? U < t->U[k + 1] : U > t->U[k + 1]))
        k++;
    const double s = fmax(0, fmin(1, (U - t->U[k]) / (t->U[k + 1] - t->U[k])));
    const size_t w = (size_t)t->ncol;
    return (1 - s) * t->col[(size_t)k * w + (size_t)j] + s * t->col[(size_t)(k + 1) * w + (size_t)j];
}

/* One Monte Carlo evaluation: the net current, the largest species current and the columns
 * (each species, secondaries, photoelectrons, the net current's error) at U. */
static int eval(const mote_ch_plasma *p, const mote_ch_body *b, const mote_ch_tracer *tr,
                const mote_ch_run_opts *o, double U, double *I, double *Imax, double *col,
                mote_err *err)
{
    mote_ch_run_opts q = *o;
    q.potential = U;
    mote_ch_result r;
    int rc = mote_ch_run(p, b, tr, &q, &r, err);
    if (rc)
        return rc;
    double sig;
    *I = mote_ch_net(&r, &sig);
    *Imax = 0;
    double see = 0;
    for (int s = 0; s < r.nsp; s++) {
        *Imax = fmax(*Imax, fabs(r.current[s]));
        col[s] = r.current[s];
        for (int k = 0; k < MOTE_CH_MAX_COMPONENTS; k++)
            see += r.see[s][k];
    }
    col[r.nsp] = see;
    col[r.nsp + 1] = r.photo;
    col[r.nsp + 2] = sig;
    mote_ch_result_free(&r);
    return MOTE_OK;
}

int ch_table_build(const mote_ch_plasma *p, const mote_ch_body *b, const mote_ch_tracer *tr,
                   const mote_ch_run_opts *o, double U0, ch_table *t, mote_err *err)
{
    memset(t, 0, sizeof *t);
    t->ncol = p->nsp + 3;
    double col[MOTE_CH_MAX_SPECIES + 3];
    double kTmin = INFINITY;
    for (int s = 0; s < p->nsp; s++)
        for (int k = 0; k < p->sp[s].ncomp; k++)
            kTmin = fmin(kTmin, p->sp[s].kT[k] / abs(p->sp[s].Z));
    double I0, M0;
    int rc = eval(p, b, tr, o, U0, &I0, &M0, col, err);
    if (rc)
        return rc;
    if (I0 == 0)
        return mote_fail(err, MOTE_EINVAL, "evolve: the net current at U0 is zero: the body "
                         "floats already");
    t->down = I0 < 0; /* the potential falls while the net current is negative */
    if (table_put(t, U0, I0, M0, col))
        return mote_fail(err, MOTE_ENOMEM, "evolve: out of memory");
    double step = 0.1 * kTmin, U = U0;
    for (int it = 0; it < 60; it++) { /* march until the sign changes */
        U += t->down ? -step : step;
        double I, M;
        if ((rc = eval(p, b, tr, o, U, &I, &M, col, err)) != 0)
            return rc;
        if (table_put(t, U, I, M, col))
            return mote_fail(err, MOTE_ENOMEM, "evolve: out of memory");
        if ((I < 0) != (I0 < 0))
            break;
        step *= 2;
        if (it == 59)
            return mote_fail(err, MOTE_EINVAL, "evolve: the net current keeps its sign to %g V",
                             U);
    }
    /* bisect the intervals whose end currents differ by more than 5% of the largest current */
    for (int pass = 0; pass < 12; pass++) {
        int added = 0;
        for (int k = 0; k + 1 < t->n && t->n < 400; k++) {
            const double lim = 0.05 * fmax(t->d[k], t->d[k + 1]);
            if (fabs(t->I[k + 1] - t->I[k]) <= lim)
                continue;
            const double Um = 0.5 * (t->U[k] + t->U[k + 1]);
            double I, M;
            if ((rc = eval(p, b, tr, o, Um, &I, &M, col, err)) != 0)
                return rc;
            if (table_put(t, Um, I, M, col))
                return mote_fail(err, MOTE_ENOMEM, "evolve: out of memory");
            added++;
            k++; /* (the new point is between k and k + 1) */
        }
        if (!added)
            break;
    }
    /* Fritsch-Carlson slopes of I(U) */
    const int n = t->n;
    double *delta = malloc((size_t)n * sizeof *delta);
    if (!delta)
        return mote_fail(err, MOTE_ENOMEM, "evolve: out of memory");
    for (int k = 0; k + 1 < n; k++)
        delta[k] = (t->I[k + 1] - t->I[k]) / (t->U[k + 1] - t->U[k]);
    for (int k = 0; k < n; k++) {
        if (k == 0)
            t->d[k] = delta[0];
        else if (k == n - 1)
            t->d[k] = delta[n - 2];
        else if (delta[k - 1] * delta[k] <= 0)
            t->d[k] = 0;
        else
            t->d[k] = 0.5 * (delta[k - 1] + delta[k]);
    }
    for (int k = 0; k + 1 < n; k++) {
        if (delta[k] == 0) {
            t->d[k] = t->d[k + 1] = 0;
            continue;
        }
        const double a = t->d[k] / delta[k], bb = t->d[k + 1] / delta[k];
        const double h = a * a + bb * bb;
        if (h > 9) {
            const double tau = 3 / sqrt(h);
            t->d[k] = tau * a * delta[k];
            t->d[k + 1] = tau * bb * delta[k];
        }
    }
    free(delta);
    /* the root between the last two points */
    for (int k = 0; k + 1 < n; k++)
        if ((t->I[k] < 0) != (t->I[k + 1] < 0)) {
            double lo = t->U[k], hi = t->U[k + 1];
            for (int it = 0; it < 200; it++) {
                const double mid = 0.5 * (lo + hi);
                if ((ch_table_eval(t, mid) < 0) == (t->I[k] < 0))
                    lo = mid;
                else
                    hi = mid;
            }
            t->Uf = 0.5 * (lo + hi);
            break;
        }
    return MOTE_OK;
}

double ch_table_eval(const ch_table *t, double U)
{
    int k = 0;
    /* the interval: U[k] ... U[k + 1] along the path (U falls when t->down) */
    while (k + 2 < t->n && (t->down ? U < t->U[k + 1] : U > t->U[k + 1]))
        k++;
    const double h = t->U[k + 1] - t->U[k], s = (U - t->U[k]) / h;
    const double h00 = (1 + 2 * s) * (1 - s) * (1 - s), h10 = s * (1 - s) * (1 - s);
    const double h01 = s * s * (3 - 2 * s), h11 = s * s * (s - 1);
    return h00 * t->I[k] + h10 * h * t->d[k] + h01 * t->I[k + 1] + h11 * h * t->d[k + 1];
}

int ch_table_times(ch_table *t, double C, mote_err *err)
{
    /* t(U) on a fine grid from U0 to U_f (1 - 1e-7), Simpson on each cell */
    const int m = 20000;
    t->tt = malloc((size_t)(m + 1) * sizeof *t->tt);
    t->tu = malloc((size_t)(m + 1) * sizeof *t->tu);
    if (!t->tt || !t->tu)
        return mote_fail(err, MOTE_ENOMEM, "evolve: out of memory");
    const double U0 = t->U[0], span = (t->Uf - U0) * (1 - 1e-7);
    t->tu[0] = U0;
    t->tt[0] = 0;
    t->nt = m + 1;
    for (int k = 1; k <= m; k++) {
        /* denser near U_f, where 1/I grows: u = U0 + span (1 - (1 - k/m)^3) */
        const double f0 = 1 - (double)(k - 1) / m, f1 = 1 - (double)k / m;
        const double a = U0 + span * (1 - f0 * f0 * f0), b = U0 + span * (1 - f1 * f1 * f1);
        const double fa = 1 / ch_table_eval(t, a), fb = 1 / ch_table_eval(t, b),
                     fm = 1 / ch_table_eval(t, 0.5 * (a + b));
        t->tu[k] = b;
        t->tt[k] = t->tt[k - 1] + C * (b - a) / 6 * (fa + 4 * fm + fb);
    }
    /* the time constant at U_f: C / |dI/dU| */
    const double e = 1e-4 * fabs(t->Uf) + 1e-3;
    t->tau = C / fabs((ch_table_eval(t, t->Uf + e) - ch_table_eval(t, t->Uf - e)) / (2 * e));
    return MOTE_OK;
}

double ch_table_u_at(const ch_table *t, double time)
{
    if (time <= 0)
        return t->tu[0];
    const int last = t->nt - 1;
    if (time >= t->tt[last]) /* beyond the grid: the linearised approach to U_f */
        return t->Uf - (t->Uf - t->tu[last]) * exp(-(time - t->tt[last]) / t->tau);
    int lo = 0, hi = last;
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        if (t->tt[mid] <= time)
            lo = mid;
        else
            hi = mid;
    }
    const double f = (time - t->tt[lo]) / (t->tt[hi] - t->tt[lo]);
    return t->tu[lo] + f * (t->tu[hi] - t->tu[lo]);
}

double ch_table_t_at(const ch_table *t, double U)
{
    int lo = 0, hi = t->nt - 1;
    if ((t->down ? U <= t->tu[hi] : U >= t->tu[hi]))
        return t->tt[hi];
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        if (t->down ? t->tu[mid] >= U : t->tu[mid] <= U)
            lo = mid;
        else
            hi = mid;
    }
    const double f = (U - t->tu[lo]) / (t->tu[hi] - t->tu[lo]);
    return t->tt[lo] + f * (t->tt[hi] - t->tt[lo]);
}
