/* run.c: integrate, which advances the bodies through the core run loop (mote/loop.h) with the
 * outputs (outputs.c) as its observers, by steps (every=K, a count observer) or by time (dt=T:
 * the Taylor step's dense output gives the state at t0 + k dt exactly, spec 4.5). */
#include "mote/nbody.h"

#include <tgmath.h>
#include <stdlib.h>
#include <string.h>

#include "mote/loop.h"

#include "model.h"

int nb_check_integrate(void *vm, const mote_call *c, mote_err *err)
{
    int given = (mote_call_opt(c, "steps") != NULL) + (mote_call_opt(c, "to") != NULL) +
                (mote_call_opt(c, "for") != NULL);
    if (given != 1)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "integrate: give exactly one of steps=N, to=T and for=D (found %d)",
                              given);
    int rc = nb_check_time_unit(vm, c, err);
    return rc ? rc : nb_need_bodies(vm, c, err);
}

/* The step integrate has just taken, as its observers see it: the bodies after it, where it
 * began, whether a merge ended it (then the step's polynomial no longer matches the bodies), and
 * for a time observer the time t the loop fires it at. */
typedef struct {
    nb_model *m;
    mote_real Tb;
    int merged;
    double t;
    mote_real *xv; /* room for a dense-output view */
    mote_real t_end;
    int by_time;   /* a sampler by time: every step end is looked at */
} nb_step;

/* The bodies at output time ts, as an output by time sees them: from the Taylor step's dense
 * output (spec 4.5) in *view when ts falls inside the step just taken, else (the Galactica
 * scheme, spec 10.3, or after a merge) the step end. */
static const mote_nb *bodies_at(nb_model *m, const nb_step *st, mote_real ts, mote_nb *view)
{
    mote_nb *nb = &m->nb;
    if (st && nb_integrator_of(nb->integrator)->dense && ts < nb->T && ts > st->Tb &&
        !st->merged) {
        *view = *nb;
        view->x = st->xv;
        view->v = st->xv + 3 * (size_t)nb->n;
        mote_nb_taylor_dense(nb, ts - st->Tb, view->x, view->v);
        view->T = ts;
        return view;
    }
    return nb;
}

/* The exact time in the model's precision of the output at t0 + k dt the loop fires at st->t
 * (k from the loop's double time). */
static mote_real output_time(mote_real t0, mote_real dt, const nb_step *st)
{
    const mote_real k = (mote_real)llround((st->t - (double)t0) / (double)dt);
    return t0 + k * dt;
}

/* A monitor or trajectory sample. By steps: the bodies now. By time: the sample t0 + k dt the
 * loop fires at st->t (bodies_at). */
static int sampler_fire(nb_model *m, int traj, const nb_step *st, mote_err *err)
{
    const nb_sampler *s = traj ? &m->traj : &m->mon;
    if (!(s->dt > 0) || !st)
        return nb_sample(m, traj, &m->nb, err);
    mote_nb view;
    return nb_sample(m, traj, bodies_at(m, st, output_time(s->t0, s->dt, st), &view), err);
}
static int fire_monitor(void *ctx, void *subject, mote_err *err)
{
    return sampler_fire(ctx, 0, subject, err);
}
static int fire_trajectory(void *ctx, void *subject, mote_err *err)
{
    return sampler_fire(ctx, 1, subject, err);
}

static int fire_checkpoint(void *ctx, void *subject, mote_err *err)
{
    nb_model *m = ctx;
    return nb_state_save(&m->nb, m->ckpt.path, err);
}

/* The snapshot of `snapshot every=K`: PREFIX, the step count and .snap (mote_series_path); of
 * `snapshot dt=T`: PREFIX, its number in order and .snap, the bodies at its time. */
static int fire_snapshot(void *ctx, void *subject, mote_err *err)
{
    nb_model *m = ctx;
    const int by_time = m->snap.dt > 0;
    char *path = by_time ? mote_series_path(m->snap.prefix, m->snap.index, 6,
                                            m->snap.galactica ? ".dat" : ".snap")
                         : mote_series_path(m->snap.prefix, m->nb.steps, 10,
                                            m->snap.galactica ? ".dat" : ".snap");
    if (!path)
        return mote_fail(err, MOTE_ENOMEM, "snapshot: out of memory");
    mote_make_dir_of(path); /* (a prefix= makes its folder) */
    mote_nb view;
    const mote_nb *nb = by_time ? bodies_at(m, subject, (mote_real)m->snap.at.t0 +
                                            (mote_real)m->snap.at.k * (mote_real)m->snap.dt, &view)
                                : &m->nb;
    int rc;
    if (m->snap.galactica && nb != &m->nb) { /* (Galactica's writer reads the model's bodies) */
        const mote_nb held = m->nb;
        m->nb = *nb;
        rc = nb_write_galactica(m, path, 1, err);
        m->nb = held;
    } else {
        rc = m->snap.galactica ? nb_write_galactica(m, path, 1, err)
                               : nb_snapshot_write(nb, path, m->snap.origin, err);
    }
    m->snap.index += by_time && !rc;
    free(path);
    return rc;
}

/* A frame of `frames every=K` (the bodies now) or `frames dt=T` (at its time). */
static int fire_frame(void *ctx, void *subject, mote_err *err)
{
    nb_model *m = ctx;
    if (!(m->frames.dt > 0))
        return nb_frame_now(m, err);
    mote_nb view;
    const mote_real ts = (mote_real)m->frames.at.t0 +
                         (mote_real)m->frames.at.k * (mote_real)m->frames.dt;
    return nb_frame_of(m, bodies_at(m, subject, ts, &view), err);
}

/* The closest approach of the interval of approaches every=K that ends now. */
static int fire_approach(void *ctx, void *subject, mote_err *err)
{
    nb_model *m = ctx;
    return nb_approach_close(&m->appr.a, m->nb.T, err);
}

/* The observers of integrate, in the order they fire after a step: the approach interval's
 * close, the monitor, the trajectory, the checkpoint, the snapshot and the frame. A sampler by
 * time keeps its place in its sequence (at) from one integrate to the next. */
static size_t integrate_observers(nb_model *m, mote_observer obs[6])
{
    size_t n = 0;
    if (m->appr.every)
        obs[n++] = (mote_observer){.ctx = m, .fire = fire_approach, .every = m->appr.every};
    nb_sampler *smp[2] = {&m->mon, &m->traj};
    int (*fire[2])(void *, void *, mote_err *) = {fire_monitor, fire_trajectory};
    for (int k = 0; k < 2; k++)
        if (smp[k]->on)
            obs[n++] = (mote_observer){.at = smp[k]->dt > 0 ? &smp[k]->at : NULL, .ctx = m,
                                       .fire = fire[k],
                                       .every = smp[k]->dt > 0 ? 0 : smp[k]->every};
    if (m->ckpt.path)
        obs[n++] = (mote_observer){.ctx = m, .fire = fire_checkpoint, .every = m->ckpt.every};
    if (m->snap.every || m->snap.dt > 0)
        obs[n++] = (mote_observer){.at = m->snap.dt > 0 ? &m->snap.at : NULL, .ctx = m,
                                   .fire = fire_snapshot, .every = m->snap.every};
    if (m->frames.every || m->frames.dt > 0)
        obs[n++] = (mote_observer){.at = m->frames.dt > 0 ? &m->frames.at : NULL, .ctx = m,
                                   .fire = fire_frame, .every = m->frames.every};
    return n;
}

/* The model's side of the core loop: a chunk of steps to the next count observer; single steps
 * where every step end is looked at (time samplers, approaches); at most 1000, for progress.
 * Time samplers are caught up after each chunk, from the Taylor step's dense output. */
static double nb_clock(const void *vs) { return (double)((const nb_step *)vs)->m->nb.T; }
static uint64_t nb_count(const void *vs) { return ((const nb_step *)vs)->m->nb.steps; }
static int nb_ended(const void *vs)
{
    const nb_step *st = vs;
    return !(st->m->nb.T < st->t_end);
}
static double nb_at(void *vs, double t)
{
    nb_step *st = vs;
    st->t = t;
    return nb_integrator_of(st->m->nb.integrator)->dense && !st->merged ? t
                                                                        : (double)st->m->nb.T;
}

static int nb_advance(void *vs, mote_loop *l, double t_stop, uint64_t n_stop, mote_err *err)
{
    nb_step *st = vs;
    nb_model *m = st->m;
    uint64_t chunk = n_stop - m->nb.steps;
    if (m->appr.every)
        chunk = 1;
    else if (st->by_time && nb_integrator_of(m->nb.integrator)->synchronised) {
        /* the map's steps up to the one that reaches the next sample (each stop synchronises
         * it) */
        const double next = mote_loop_next(l);
        const double left = (next - (double)m->nb.T) / (double)m->nb.dt;
        const uint64_t to = left < 1 ? 1 : left < 1e15 ? (uint64_t)ceil(left) : chunk;
        chunk = to < chunk ? to : chunk;
    } else if (st->by_time)
        chunk = 1;
    if (chunk > 1000)
        chunk = 1000;
    const uint64_t before = m->nb.steps, merges = m->nb.merges;
    st->Tb = m->nb.T;
    int rc = m->appr.every ? nb_approach_before(&m->appr.a, &m->nb, err) : MOTE_OK;
    if (!rc)
        rc = mote_nb_integrate(&m->nb, chunk, st->t_end, err);
    if (rc || m->nb.steps == before) /* (none could be taken: the end is reached) */
        return rc;
    st->merged = m->nb.merges != merges;
    if (m->appr.every)
        nb_approach_after(&m->appr.a, &m->nb, st->Tb, st->merged);
    return MOTE_OK;
}

int nb_run_integrate(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    nb_settle_units(m);
    m->nb.threads = c->ctx->threads;
    const mote_arg *a = mote_call_opt(c, "steps");
    const uint64_t s0 = m->nb.steps;
    const uint64_t n_end = a && (uint64_t)a->i < UINT64_MAX - s0 ? s0 + (uint64_t)a->i
                                                                 : UINT64_MAX;
    mote_real t_end = INFINITY;
    double scale;
    int rc = nb_time_scale(m, c, &scale, err);
    if (rc)
        return rc;
    if ((a = mote_call_opt(c, "to")))
        t_end = mote_real_parse(a->text, NULL) * scale;
    else if ((a = mote_call_opt(c, "for")))
        t_end = m->nb.T + mote_real_parse(a->text, NULL) * scale;
    if (!(t_end > m->nb.T))
        return mote_fail(err, MOTE_EINVAL, "integrate: %s=%s ends at or before the current time "
                         "%.17g (%s)", mote_call_opt(c, "to") ? "to" : "for", a ? a->text : "",
                         (double)(m->nb.T / scale),
                         t_end == m->nb.T ? "there is nothing to do" : "integration runs forward");
    if (m->nb.adaptive && m->nb.hmax > 0 && m->nb.hmin > m->nb.hmax)
        return mote_fail(err, MOTE_EINVAL, "integrate: hmin (%g) is greater than hmax (%g)",
                         (double)m->nb.hmin, (double)m->nb.hmax);
    const uint64_t forced = m->nb.hmin_forced;
    nb_step st = {m, 0, 0, 0, NULL, t_end, 0};
    st.by_time = (m->mon.on && m->mon.dt > 0) || (m->traj.on && m->traj.dt > 0) ||
                 m->snap.dt > 0 || m->frames.dt > 0;
    if (st.by_time) {
        st.xv = malloc(6 * (size_t)(m->nb.n ? m->nb.n : 1) * sizeof *st.xv);
        if (!st.xv)
            return mote_fail(err, MOTE_ENOMEM, "integrate: out of memory");
    }
    mote_observer obs[6];
    mote_progress prog;
    mote_progress_begin(&prog, c->ctx, "integrate");
    const uint64_t warned = m->nb.approach_warnings;
    const mote_runner r = {.what = "integrate", .sys = &st, .ctx = c->ctx, .clock = nb_clock,
                           .count = nb_count, .advance = nb_advance, .ended = nb_ended,
                           .at = nb_at};
    rc = mote_run(&r, obs, integrate_observers(m, obs), &prog, (double)t_end, n_end, err);
    /* samplers by steps also sample at the end time */
    nb_sampler *ends[2] = {&m->mon, &m->traj};
    for (int k = 0; k < 2 && !rc; k++)
        if (ends[k]->on && !(ends[k]->dt > 0) && m->nb.T == t_end &&
            m->nb.steps % ends[k]->every != 0)
            rc = nb_sample(m, k, &m->nb, err);
    mote_progress_end(&prog);
    free(st.xv);
    if (!rc && m->ckpt.path)
        rc = nb_state_save(&m->nb, m->ckpt.path, err);
    if (m->nb.hmin_forced > forced && m->log)
        fprintf(m->log, "integrate: warning: %llu adaptive step%s held at hmin = %g, longer than "
                "tol= allows (the accuracy is not ensured; watch dE): lower hmin=\n",
                (unsigned long long)(m->nb.hmin_forced - forced),
                m->nb.hmin_forced - forced > 1 ? "s" : "", (double)m->nb.hmin);
    if (m->nb.approach_warnings > warned && m->log)
        fprintf(m->log,
                "integrate: warning: %llu merge%s overlapped by more than 10%% of the radii after "
                "a step at the shortest length (merge accuracy not ensured; largest overlap "
                "%.3g): lower hmin= or bt= of 'merge'\n",
                (unsigned long long)(m->nb.approach_warnings - warned),
                m->nb.approach_warnings - warned > 1 ? "s" : "", (double)m->nb.max_overlap);
    if (!rc && m->appr.every && m->nb.steps % m->appr.every != 0 && m->appr.a.best >= 0)
        rc = nb_approach_close(&m->appr.a, m->nb.T, err); /* the last, partial interval */
    if (m->appr.every) {
        mote_err werr = {0};
        int wrc = nb_approaches_write(m, rc ? &werr : err);
        rc = rc ? rc : wrc;
    }
    /* the samples so far, even after a failure */
    nb_sampler *smp[2] = {&m->mon, &m->traj};
    for (int k = 0; k < 2; k++)
        rc = nb_sampler_finish(m, smp[k], k, rc, err);
    return rc;
}

