/* approach.c: closest approaches of one body to the others (spec 7.9, 10.4). After every step the
 * distance to each active body is sampled at the step end; with refine the true minimum inside
 * the step is found from the step's own polynomial: the Taylor integrator's coefficients (its
 * dense output), or for the Galactica scheme the Taylor polynomial of the step (velocity,
 * acceleration, jerk, fourth and fifth derivatives at its start and the sixth from the difference
 * of fifth derivatives), from the start state saved before the step. The minimum is where the
 * relative radial velocity r . v changes sign from negative to positive; it is found by bisection
 * on r . v to the last bit of the step fraction. Every interval's closest approach is kept: time,
 * body, distance and relative speed. */
#include <stdlib.h>
#include <string.h>
#include <tgmath.h>

#include "nb.h"

int nb_approach_init(nb_approach *a, uint32_t body, int refine, mote_err *err)
{
    memset(a, 0, sizeof *a);
    a->body = body;
    a->refine = refine;
    a->best = -1;
    (void)err;
    return MOTE_OK;
}

void nb_approach_free(nb_approach *a)
{
    free(a->x0);
    free(a->rows);
    memset(a, 0, sizeof *a);
}

int nb_approach_before(nb_approach *a, const mote_nb *nb, mote_err *err)
{
    if (!a->refine || nb->integrator != MOTE_NB_GALACTICA)
        return MOTE_OK;
    const size_t blk = 3 * (size_t)nb->n;
    if (a->cap < blk) {
        mote_real *p = realloc(a->x0, 3 * blk * sizeof *p);
        if (!p)
            return mote_fail(err, MOTE_ENOMEM, "approaches: out of memory");
        a->x0 = p;
        a->cap = blk;
    }
    memcpy(a->x0, nb->x, blk * sizeof *nb->x);
    memcpy(a->x0 + blk, nb->v, blk * sizeof *nb->v);
    memcpy(a->x0 + 2 * blk, nb->d5p, blk * sizeof *nb->d5p);
    a->dtp0 = nb->dtp;
    a->restart0 = nb->restart;
    return MOTE_OK;
}

/* Position and velocity of body i at s into the step, from the step's polynomial. */
static void dense(const nb_approach *a, const mote_nb *nb, uint32_t i, mote_real s, mote_real x[3],
                  mote_real v[3])
{
    const size_t blk = 3 * (size_t)nb->n;
    if (nb->integrator == MOTE_NB_TAYLOR) {
        const int p = nb->taylor_order;
        const mote_real *X = nb->tx;
        for (int c = 0; c < 3; c++) {
            const size_t o = 3 * (size_t)i + (size_t)c;
            mote_real dx = 0, dv = 0;
            for (int n = p; n >= 1; n--)
                dx = dx * s + X[(size_t)n * blk + o];
            for (int n = p; n >= 2; n--)
                dv = dv * s + n * X[(size_t)n * blk + o];
            x[c] = X[o] + dx * s;
            v[c] = X[blk + o] + dv * s;
        }
        return;
    }
    const int K = nb->order, have6 = K >= 6 && a->dtp0 > 0 && !a->restart0;
    for (int c = 0; c < 3; c++) {
        const size_t o = 3 * (size_t)i + (size_t)c;
        mote_real d[7] = {0, a->x0[blk + o], nb->acc[o], nb->jerk[o], 0, 0, 0};
        if (K >= 4) {
            d[4] = nb->d4[o];
            d[5] = nb->d5[o];
        }
        if (have6)
            d[6] = (nb->d5[o] - a->x0[2 * blk + o]) / a->dtp0;
        mote_real dx = 0, dv = 0;
        for (int k = K; k >= 1; k--) {
            dx = dx * s / (k + 1) + d[k];
            if (k >= 2)
                dv = dv * s / k + d[k];
        }
        x[c] = a->x0[o] + dx * s;
        v[c] = d[1] + dv * s;
    }
}

/* r = x_k - x_b, w = v_k - v_b; returns r . w */
static mote_real rel(const mote_real xb[3], const mote_real vb[3], const mote_real xk[3],
                     const mote_real vk[3], mote_real *dist, mote_real *speed)
{
    mote_real r2 = 0, w2 = 0, rw = 0;
    for (int c = 0; c < 3; c++) {
        const mote_real r = xk[c] - xb[c], w = vk[c] - vb[c];
        r2 += r * r;
        w2 += w * w;
        rw += r * w;
    }
    *dist = sqrt(r2);
    *speed = sqrt(w2);
    return rw;
}

static void keep(nb_approach *a, mote_real t, uint32_t k, mote_real d, mote_real w)
{
    if (a->best < 0 || d < a->best) {
        a->best = d;
        a->t = t;
        a->with = k;
        a->speed = w;
    }
}

void nb_approach_after(nb_approach *a, const mote_nb *nb, mote_real Tb, int merged)
{
    const uint32_t b = a->body;
    if (b >= nb->n || !nb->active[b])
        return;
    const mote_real h = nb->T - Tb;
    const int refine = a->refine && !merged && h > 0 &&
                       (nb->integrator == MOTE_NB_TAYLOR || a->x0 != NULL);
    mote_real xb0[3], vb0[3];
    if (refine)
        dense(a, nb, b, 0, xb0, vb0);
    for (uint32_t k = 0; k < nb->n; k++) {
        if (k == b || !nb->active[k])
            continue;
        mote_real d, w;
        const mote_real g1 = rel(nb->x + 3 * b, nb->v + 3 * b, nb->x + 3 * k, nb->v + 3 * k, &d, &w);
        keep(a, nb->T, k, d, w);
        if (!refine || !(g1 > 0))
            continue;
        mote_real xk[3], vk[3], xb[3], vb[3];
        dense(a, nb, k, 0, xk, vk);
        if (!(rel(xb0, vb0, xk, vk, &d, &w) < 0))
            continue; /* receding at both ends: the minimum is not inside */
        mote_real lo = 0, hi = h;
        for (int it = 0; it < 200 && lo < hi; it++) {
            const mote_real mid = lo + (hi - lo) / 2;
            if (!(mid > lo && mid < hi))
                break;
            dense(a, nb, b, mid, xb, vb);
            dense(a, nb, k, mid, xk, vk);
            if (rel(xb, vb, xk, vk, &d, &w) < 0)
                lo = mid;
            else
                hi = mid;
        }
        dense(a, nb, b, lo, xb, vb);
        dense(a, nb, k, lo, xk, vk);
        rel(xb, vb, xk, vk, &d, &w);
        keep(a, Tb + lo, k, d, w);
    }
}

int nb_approach_push(nb_approach *a, const double row[4], mote_err *err)
{
    if (a->nrows == a->rowcap) {
        size_t cap = a->rowcap ? 2 * a->rowcap : 64;
        double *p = realloc(a->rows, 4 * cap * sizeof *p);
        if (!p)
            return mote_fail(err, MOTE_ENOMEM, "approaches: out of memory");
        a->rows = p;
        a->rowcap = cap;
    }
    memcpy(a->rows + 4 * a->nrows++, row, 4 * sizeof *row);
    return MOTE_OK;
}

int nb_approach_close(nb_approach *a, mote_real T, mote_err *err)
{
    const double none[4] = {(double)T, 0, 0, 0},
                 row[4] = {(double)a->t, a->with + 1.0, (double)a->best, (double)a->speed};
    const int rc = nb_approach_push(a, a->best < 0 ? none : row, err);
    a->best = -1;
    return rc;
}
