/* loop.c: the run loop every long command goes through: its stops, observers and progress
 * (loop.h). */
#include "mote/loop.h"

#include <math.h>

double mote_loop_next(const mote_loop *l)
{
    double next = INFINITY;
    for (size_t k = 0; l && k < l->nobs; k++) {
        if (!l->obs[k].at)
            continue;
        double t = mote_schedule_next(l->obs[k].at);
        if (t < next)
            next = t;
    }
    return next;
}

double mote_loop_stop(const mote_loop *l, double t_end)
{
    double stop = t_end;
    for (size_t k = 0; l && k < l->nobs; k++) {
        const mote_schedule *at = l->obs[k].at;
        if (!at)
            continue;
        double t = mote_schedule_next(at);
        /* a time a hair before the end is taken at the end */
        if (t < stop && t <= t_end - 1e-9 * at->dt)
            stop = t;
    }
    return stop;
}

int mote_loop_due(const mote_loop *l, double t)
{
    for (size_t k = 0; l && k < l->nobs; k++) {
        const mote_schedule *at = l->obs[k].at;
        if (at && mote_schedule_next(at) <= t + 1e-9 * at->dt)
            return 1;
    }
    return 0;
}

int mote_loop_fire(mote_loop *l, void *subject, double t, mote_err *err)
{
    for (size_t k = 0; l && k < l->nobs; k++) {
        mote_observer *o = &l->obs[k];
        if (!o->at)
            continue;
        const double tol = 1e-9 * o->at->dt;
        if (!(mote_schedule_next(o->at) <= t + tol))
            continue;
        int rc = o->fire(o->ctx, subject, err);
        do /* past t: exact times t0 + k dt, never a running sum */
            o->at->k++;
        while (o->at->dt > 0 && mote_schedule_next(o->at) <= t + tol);
        if (rc)
            return rc;
    }
    return MOTE_OK;
}

/* A spread observer: the smallest j in 1 .. spread whose count from + floor(j over / spread) is
 * above from + d (spread + 1: none). */
static uint64_t spread_above(const mote_observer *o, uint64_t d)
{
    uint64_t lo = 1, hi = o->spread + 1;
    while (lo < hi) {
        const uint64_t mid = lo + (hi - lo) / 2;
        if (mote_schedule_count_at(mid, o->spread, o->over) > d)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

/* The smallest count above n at which o fires (UINT64_MAX: none). */
static uint64_t count_next(const mote_observer *o, uint64_t n)
{
    const uint64_t from = o->from;
    if (o->spread) {
        if (n < from)
            return from + mote_schedule_count_at(1, o->spread, o->over);
        const uint64_t j = spread_above(o, n - from);
        return j <= o->spread ? from + mote_schedule_count_at(j, o->spread, o->over) : UINT64_MAX;
    }
    const uint64_t e = o->every;
    if (n < from)
        return from;
    const uint64_t j = (n - from) / e + 1;
    if (j > (UINT64_MAX - from) / e) /* (no count above n that fits) */
        return UINT64_MAX;
    return from + j * e;
}

/* How many times o fires at count n: 0 or 1; a spread observer once for each of its samples
 * there (more samples than counts share a count). */
static uint64_t count_due(const mote_observer *o, uint64_t n)
{
    if (n < o->from)
        return 0;
    if (!o->spread)
        return (n - o->from) % o->every == 0;
    const uint64_t d = n - o->from;
    return spread_above(o, d) - (d ? spread_above(o, d - 1) : 1);
}

/* How many times o fires for the counts passed from a to b (a < b): a spread observer once for
 * each of its samples in (a, b]; any other once when one or more of its counts lie there (a
 * model that went past its stop, like a time observer whose times a step went past). */
static uint64_t count_passed(const mote_observer *o, uint64_t a, uint64_t b)
{
    if (b < o->from)
        return 0;
    if (!o->spread)
        return count_next(o, a) <= b;
    const uint64_t upto_b = spread_above(o, b - o->from) - 1;
    const uint64_t upto_a = a >= o->from ? spread_above(o, a - o->from) - 1 : 0;
    return upto_b - upto_a;
}

uint64_t mote_loop_count_stop(const mote_loop *l, uint64_t n, uint64_t n_end)
{
    uint64_t stop = n_end;
    for (size_t k = 0; l && k < l->nobs; k++) {
        if (l->obs[k].at || !(l->obs[k].every || l->obs[k].spread))
            continue;
        const uint64_t next = count_next(&l->obs[k], n);
        if (next < stop)
            stop = next;
    }
    return stop;
}

int mote_loop_fire_count(mote_loop *l, void *subject, uint64_t n, mote_err *err)
{
    for (size_t k = 0; l && k < l->nobs; k++) {
        mote_observer *o = &l->obs[k];
        if (o->at || !(o->every || o->spread))
            continue;
        for (uint64_t times = count_due(o, n); times > 0; times--) {
            int rc = o->fire(o->ctx, subject, err);
            if (rc)
                return rc;
        }
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

/* ---- the loop ------------------------------------------------------------------------------- */

static void *subject(const mote_runner *r) { return r->subject ? r->subject : r->sys; }

/* Fire the time observers at the clock t: each time passed at its own (catching up), or those
 * due at t once. */
static int fire_times(const mote_runner *r, mote_loop *l, double t, mote_err *err)
{
    if (!r->at)
        return mote_loop_fire(l, subject(r), t, err);
    int rc = MOTE_OK;
    double next;
    while (!rc && (next = mote_loop_next(l)) <= t)
        rc = mote_loop_fire(l, subject(r), r->at(r->sys, next), err);
    return rc;
}

int mote_run(const mote_runner *r, const mote_observer *obs, size_t nobs, mote_progress *progress,
             double t_end, uint64_t n_end, mote_err *err)
{
    mote_observer all[MOTE_RUN_OBSERVERS_MAX];
    size_t n = 0;
    const size_t next = r->ctx ? r->ctx->nobservers : 0;
    if (nobs + next > MOTE_RUN_OBSERVERS_MAX)
        return mote_fail(err, MOTE_EINVAL, "%s: more than %d outputs and observers at once",
                         r->what, MOTE_RUN_OBSERVERS_MAX);
    for (size_t k = 0; k < nobs; k++)
        all[n++] = obs[k];
    for (size_t k = 0; k < next; k++)
        all[n++] = r->ctx->observers[k];
    const double t0 = r->clock ? r->clock(r->sys) : 0;
    const uint64_t c0 = r->count ? r->count(r->sys) : 0;
    mote_loop l = {all, n, n_end, progress, t0, t_end, c0, 0};
    /* time observers due at the start fire there (a catching-up model's after its first step) */
    int rc = r->clock && !r->at ? mote_loop_fire(&l, subject(r), t0, err) : MOTE_OK;
    for (size_t k = 0; !rc && k < n; k++) /* spread samples that fall on the first count */
        if (!all[k].at && all[k].spread && all[k].from == c0)
            for (uint64_t times = count_due(&all[k], c0); !rc && times > 0; times--)
                rc = all[k].fire(all[k].ctx, subject(r), err);
    double t = t0;
    uint64_t c = c0;
    while (!rc && c < n_end && (r->ended ? !r->ended(r->sys) : t < t_end)) {
        const double ts = r->clock ? mote_loop_stop(&l, t_end) : t_end;
        const uint64_t cs = mote_loop_count_stop(&l, c, n_end);
        rc = r->advance(r->sys, &l, ts, cs, err);
        if (rc)
            break;
        const double t1 = r->clock ? r->clock(r->sys) : 0;
        const uint64_t c1 = r->count ? r->count(r->sys) : 0;
        if (t1 == t && c1 == c) /* nothing more can happen */
            break;
        for (size_t k = 0; !rc && c1 > c && k < n; k++)
            if (!all[k].at && (all[k].every || all[k].spread))
                for (uint64_t times = count_passed(&all[k], c, c1); !rc && times > 0; times--)
                    rc = all[k].fire(all[k].ctx, subject(r), err);
        if (!rc && r->clock)
            rc = fire_times(r, &l, t1, err);
        t = t1;
        c = c1;
        if (rc || l.done)
            break;
        const int stop = r->fraction ? progress && mote_progress_update(progress, r->fraction(r->sys))
                                     : mote_loop_progress(&l, t, c);
        if (stop)
            rc = mote_interrupted(err, r->what);
    }
    return rc;
}

/* ---- the output layer's schedules ---------------------------------------------------------- */

int mote_call_check_every_dt(const mote_call *c, int required, mote_err *err)
{
    const mote_arg *every = mote_call_opt(c, "every"), *dt = mote_call_opt(c, "dt");
    if (every && dt)
        return mote_call_fail(err, c, mote_call_opt_index(c, "dt"), MOTE_EINVAL,
                              "%s: give every=K or dt=T, not both", c->name);
    if (required && !every && !dt)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "%s: give every=K (a count) or dt=T (a time)", c->name);
    return MOTE_OK;
}

mote_observer mote_call_observer(const mote_call *c, mote_schedule *at, double t_now,
                                 uint64_t n_now, uint64_t scale, void *ctx,
                                 int (*fire)(void *ctx, void *subject, mote_err *err))
{
    const mote_arg *every = mote_call_opt(c, "every"), *dt = mote_call_opt(c, "dt");
    mote_observer o = {.ctx = ctx, .fire = fire};
    if (dt) {
        *at = (mote_schedule){t_now, dt->r, 1};
        o.at = at;
    } else if (every) {
        const uint64_t k = (uint64_t)every->i, s = scale ? scale : 1;
        o.every = k > UINT64_MAX / s ? UINT64_MAX : k * s;
        o.from = n_now;
    }
    return o;
}
