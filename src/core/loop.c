/* loop.c: the shared run loop's schedule, firing and progress (loop.h). */
#include "mote/loop.h"

#include <math.h>

double mote_loop_next(const mote_loop *l)
{
    double next = INFINITY;
    for (size_t k = 0; l && k < l->nobs; k++) {
        if (l->obs[k].every)
            continue;
        double t = mote_schedule_next(&l->obs[k].at);
        if (t < next)
            next = t;
    }
    return next;
}

double mote_loop_stop(const mote_loop *l, double t_end)
{
    double stop = t_end;
    for (size_t k = 0; l && k < l->nobs; k++) {
        const mote_observer *o = &l->obs[k];
        if (o->every)
            continue;
        double t = mote_schedule_next(&o->at);
        /* a time a hair before the end is taken at the end */
        if (t < stop && t <= t_end - 1e-9 * o->at.dt)
            stop = t;
    }
    return stop;
}

int mote_loop_due(const mote_loop *l, double t)
{
    for (size_t k = 0; l && k < l->nobs; k++) {
        const mote_observer *o = &l->obs[k];
        if (!o->every && mote_schedule_next(&o->at) <= t + 1e-9 * o->at.dt)
            return 1;
    }
    return 0;
}

int mote_loop_fire(mote_loop *l, void *subject, double t, mote_err *err)
{
    for (size_t k = 0; l && k < l->nobs; k++) {
        mote_observer *o = &l->obs[k];
        const double tol = 1e-9 * o->at.dt;
        if (o->every || !(mote_schedule_next(&o->at) <= t + tol))
            continue;
        int rc = o->fire(o->ctx, subject, err);
        do /* past t: exact times t0 + k dt, never a running sum */
            o->at.k++;
        while (o->at.dt > 0 && mote_schedule_next(&o->at) <= t + tol);
        if (rc)
            return rc;
    }
    return MOTE_OK;
}

uint64_t mote_loop_count_stop(const mote_loop *l, uint64_t n, uint64_t n_end)
{
    uint64_t stop = n_end;
    for (size_t k = 0; l && k < l->nobs; k++) {
        const uint64_t e = l->obs[k].every, from = l->obs[k].from;
        if (!e)
            continue;
        uint64_t next = from;
        if (n >= from) {
            const uint64_t j = (n - from) / e + 1;
            if (j > (UINT64_MAX - from) / e) /* (no count above n that fits) */
                continue;
            next = from + j * e;
        }
        if (next < stop)
            stop = next;
    }
    return stop;
}

int mote_loop_fire_count(mote_loop *l, void *subject, uint64_t n, mote_err *err)
{
    for (size_t k = 0; l && k < l->nobs; k++) {
        mote_observer *o = &l->obs[k];
        if (!o->every || n < o->from || (n - o->from) % o->every != 0)
            continue;
        o->at.k++;
        int rc = o->fire(o->ctx, subject, err);
        if (rc)
            return rc;
    }
    return MOTE_OK;
}

int mote_loop_progress(mote_loop *l, double t, uint64_t n)
{
    if (!l || !l->progress)
        return 0;
    double f = 0.0;
    if (isfinite(l->t_end) && l->t_end > l->t_begin)
        f = (t - l->t_begin) / (l->t_end - l->t_begin);
    if (l->n_end != UINT64_MAX && l->n_end > l->n_begin) {
        double fc = (double)(n - l->n_begin) / (double)(l->n_end - l->n_begin);
        if (fc > f)
            f = fc;
    }
    return mote_progress_update(l->progress, f);
}
