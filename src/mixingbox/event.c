/* event.c: the exact event-driven integrator of the mixing-box model (spec 3), on the shared
 * event engine in field mode (include/mote/event.h): parabolic flights under gravity, exact
 * disk-disk collisions with normal restitution e = sqrt(1 - loss) (or the document's scaling
 * rule) and the TC model, box walls with kicks, and the partition as two solid blocks whose
 * faces (with kicks) and the slit's four corners are obstacles of the engine.
 *
 * Each run builds an engine from the model's arrays (box moved to the origin: engine x = x - X_L,
 * y = y - X_B), runs it from one stop to the next (sample times, the end, the collision limit)
 * with mote_ev_run_to, and copies positions, velocities and counters back at every stop. Slit
 * crossings are exact: the engine reports every event of a disk, and between two of them a
 * disk's x moves linearly (gravity acts along y), so its centre passes X1_C at most once; the
 * chamber is compared at each event. Decisions: `collision_rule seed` in this mode is an exact
 * elastic collision followed by scaling both velocities by sqrt(1 - loss) (the document's
 * formula with its absolute values is kept for the timestep mode); corner hits add no kick.
 * The engine finds the events; the rules applied at them are rules.c's (mote_mb_event_rules). */
#include "mote/event.h"
#include "mote/mixingbox.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


typedef struct {
    mote_mb *sys;
    mote_ev *ev;
    double x0, y0; /* box origin */
    mote_loop *loop;
    uint32_t events; /* since the last progress call */
    uint64_t run_events; /* since the run began */
    double t_begin, t_end; /* of the run */
    double projected;    /* > 0: the events the run would need at its rate so far (it stops) */
    int interrupted;     /* the user asked to stop (it stops) */
} mb_link;

/* A run whose rate says it needs more events than this cannot finish (at some 1e7 events a
 * second, 11 days): it stops with an error naming the cause, never runs without end. It is
 * judged after RUN_JUDGED events, so a run's start (settling, a dense corner) does not count. */
#define RUN_EVENTS_MAX 1e13
#define RUN_JUDGED 10000000ull

/* After every event of disk i: its chamber may have changed. Every 4096 events the progress
 * (and a live view, which only reads the engine) gets a look between samples. */
static void on_event(void *ctx, uint32_t i)
{
    mb_link *l = ctx;
    double r[3];
    mote_ev_position(l->ev, i, r);
    l->sys->x[i] = r[0] + l->x0;
    mote_mb_note_side(l->sys, i);
    if (++l->events >= 4096) {
        l->run_events += l->events;
        l->events = 0;
        if (mote_mb_progress(l->loop, l->sys)) { /* the user asked to stop */
            l->interrupted = 1;
            l->ev->halt = 1;
        }
        if (l->run_events >= RUN_JUDGED) {
            const double done = mote_mb_live_time(l->sys) - l->t_begin;
            const double need = done > 0 ? (double)l->run_events * (l->t_end - l->t_begin) / done
                                         : INFINITY;
            if (!(need <= RUN_EVENTS_MAX)) {
                l->projected = need;
                l->ev->halt = 1;
            }
        }
    }
}

/* Segments of the partition (engine frame), with their kicks; returns how many. The lower block
 * spans y in [0, X2_B], the upper [X2_T, H]; with no slit (b = 0) one block spans the height. */
static int partition_segments(const mote_mb_params *p, mote_ev_segment seg[6], double kick[6],
                              double corner[4][2], int *ncorner, int kinds[6])
{
    double xl = mote_mb_x1_l(p) - p->x_l, xr = mote_mb_x1_r(p) - p->x_l;
    double h = p->x_t - p->x_b;
    int n = 0;
    *ncorner = 0;
    if (!(p->b > 0)) {
        kick[n] = p->dv_s;
        seg[n] = (mote_ev_segment){{xl, 0}, {xl, h}, {-1, 0}};
        kinds[n++] = 0;
        kick[n] = p->dv_s;
        seg[n] = (mote_ev_segment){{xr, h}, {xr, 0}, {1, 0}};
        kinds[n++] = 0;
        return n;
    }
    double yb = mote_mb_x2_b(p) - p->x_b, yt = mote_mb_x2_t(p) - p->x_b;
    if (yb > 0) { /* lower block: left face, slit floor (a bottom for the disk), right face */
        kick[n] = p->dv_s;
        seg[n] = (mote_ev_segment){{xl, 0}, {xl, yb}, {-1, 0}};
        kinds[n++] = 0;
        kick[n] = p->dv_b;
        seg[n] = (mote_ev_segment){{xl, yb}, {xr, yb}, {0, 1}};
        kinds[n++] = 1;
        kick[n] = p->dv_s;
        seg[n] = (mote_ev_segment){{xr, yb}, {xr, 0}, {1, 0}};
        kinds[n++] = 0;
        corner[(*ncorner)][0] = xl;
        corner[(*ncorner)++][1] = yb;
        corner[(*ncorner)][0] = xr;
        corner[(*ncorner)++][1] = yb;
    }
    if (yt < h) { /* upper block: left face, slit ceiling (a top), right face */
        kick[n] = p->dv_s;
        seg[n] = (mote_ev_segment){{xl, h}, {xl, yt}, {-1, 0}};
        kinds[n++] = 0;
        kick[n] = p->dv_t;
        seg[n] = (mote_ev_segment){{xl, yt}, {xr, yt}, {0, -1}};
        kinds[n++] = 1;
        kick[n] = p->dv_s;
        seg[n] = (mote_ev_segment){{xr, yt}, {xr, h}, {1, 0}};
        kinds[n++] = 0;
        corner[(*ncorner)][0] = xl;
        corner[(*ncorner)++][1] = yt;
        corner[(*ncorner)][0] = xr;
        corner[(*ncorner)++][1] = yt;
    }
    return n;
}

/* Copy the engine's state at its clock back to the model's arrays (model time t). */
static void sync_back(mb_link *l, double t)
{
    mote_mb *sys = l->sys;
    for (uint32_t i = 0; i < sys->n; i++) {
        double r[3], v[3];
        mote_ev_position(l->ev, i, r);
        mote_ev_velocity(l->ev, i, v);
        sys->x[i] = r[0] + l->x0;
        sys->y[i] = r[1] + l->y0;
        sys->vx[i] = v[0];
        sys->vy[i] = v[1];
        mote_mb_note_side(sys, i);
    }
    sys->time = t;
}

/* Add the engine's and the rules' counters since the last call to the model's. */
static void sync_counters(mote_mb *sys, const mote_ev *ev, const mote_mb_rules *r,
                          const int kinds[6], uint64_t last[9])
{
    uint64_t now[9] = {ev->collisions, r->tc_elastic, ev->wall_collisions, 0, 0, r->corner_hits};
    for (int k = 0; k < ev->field->nseg; k++)
        now[kinds[k] ? 4 : 3] += r->face_hits[k];
    sys->collisions += now[0] - last[0];
    sys->collisions_tc += now[1] - last[1];
    sys->wall_hits += now[2] - last[2];
    sys->partition_hits += now[3] - last[3];
    sys->slit_hits += now[4] - last[4];
    sys->corner_hits += now[5] - last[5];
    memcpy(last, now, sizeof now);
}

/* The model's side of the core loop: its clock and collisions. */
static double mb_clock(const void *sys) { return ((const mote_mb *)sys)->time; }
static uint64_t mb_count(const void *sys) { return ((const mote_mb *)sys)->collisions; }

/* With nothing moving (no disks): the clock goes to each stop. */
static int advance_empty(void *vs, mote_loop *l, double t_stop, uint64_t n_stop, mote_err *err)
{
    ((mote_mb *)vs)->time = t_stop;
    return MOTE_OK;
}

/* The engine to the next stop (a sample time, the end, a collision count), the model's arrays
 * synchronised there. */
typedef struct {
    mb_link *link;
    mote_mb_rules *rules;
    const int *kinds;
    uint64_t last[9];
    double t_offset;
} mb_event_run;

static double event_clock(const void *vr) { return ((const mb_event_run *)vr)->link->sys->time; }
static uint64_t event_count(const void *vr)
{
    return ((const mb_event_run *)vr)->link->sys->collisions;
}

static int advance_event(void *vr, mote_loop *loop, double t_stop, uint64_t n_stop, mote_err *err)
{
    mb_event_run *x = vr;
    mb_link *l = x->link;
    mote_mb *sys = l->sys;
    mote_ev *ev = l->ev;
    l->loop = loop;
    int rc = mote_ev_run_to(ev, t_stop - x->t_offset, n_stop - sys->collisions, err);
    sync_counters(sys, ev, x->rules, x->kinds, x->last);
    if (!rc && l->interrupted)
        rc = mote_interrupted(err, "run");
    if (!rc && l->projected > 0)
        rc = mote_fail(err, MOTE_ERUNTIME,
                       "run: this run cannot finish: %llu events advanced the time by "
                       "%.3g s of %.3g s, so it would need %s%.2g events (the disks move "
                       "too fast for the box: lower v_init, gravity or the kicks, or the "
                       "run's time)", (unsigned long long)l->run_events,
                       mote_mb_live_time(sys) - l->t_begin, l->t_end - l->t_begin,
                       isinf(l->projected) ? "more than " : "about ",
                       isinf(l->projected) ? 1e300 : l->projected);
    if (!rc) {
        sync_back(l, sys->collisions >= n_stop ? x->t_offset + mote_ev_time(ev) : t_stop);
        for (uint32_t i = 0; i < sys->n; i++) /* (the TC rule's clock too: the whole state) */
            sys->t_last[i] = x->rules->t_last[i] + x->t_offset;
    }
    return rc;
}

int mb_run_event(mote_mb *sys, double t_end, const mote_loop *spec, mote_err *err)
{
    const mote_mb_params *p = &sys->p;
    mote_runner r = {.what = "run", .sys = sys, .ctx = spec->progress ? spec->progress->ctx : NULL,
                     .clock = mb_clock, .count = mb_count, .advance = advance_empty};
    if (sys->n == 0) {
        int rc = mote_run(&r, spec->obs, spec->nobs, spec->progress, t_end, spec->n_end, err);
        sys->generation++;
        return rc;
    }
    mote_ev ev;
    int rc = mote_ev_init(&ev, sys->n, 2, 0, err);
    if (rc)
        return rc;
    const double t_offset = sys->time;
    mb_link l = {sys, &ev, p->x_l, p->x_b, NULL, 0, 0, sys->time, t_end, 0, 0};
    ev.len[0] = p->x_r - p->x_l;
    ev.len[1] = p->x_t - p->x_b;
    ev.radius0 = p->r;
    ev.mass0 = p->mass;
    for (uint32_t i = 0; i < sys->n; i++) {
        ev.p[i].r[0] = sys->x[i] - l.x0;
        ev.p[i].r[1] = sys->y[i] - l.y0;
        ev.p[i].v[0] = sys->vx[i];
        ev.p[i].v[1] = sys->vy[i];
    }
    mote_ev_segment seg[6];
    double corner[4][2], kick[6];
    int kinds[6], ncorner = 0;
    int nseg = partition_segments(p, seg, kick, corner, &ncorner, kinds);
    uint64_t face_hits[6] = {0};
    mote_mb_rules rules = {
        .e = sqrt(1 - p->loss),
        .scale_rule = p->rule == MOTE_MB_SEEDRULE,
        .tc = mote_mb_tc(p),
        .g = {0, -p->g},
        .kick = {{p->dv_s, p->dv_s}, {p->dv_b, p->dv_t}},
        .face_kick = kick,
        .t_last = malloc((size_t)sys->n * sizeof(double)),
        .face_hits = face_hits,
    };
    if (!rules.t_last) {
        mote_ev_free(&ev);
        return mote_fail(err, MOTE_ENOMEM, "run: out of memory");
    }
    for (uint32_t i = 0; i < sys->n; i++) /* the rules keep the engine's clock */
        rules.t_last[i] = sys->t_last[i] - t_offset;
    mote_ev_field f = {
        .g = {0, -p->g},
        .seg = seg,
        .nseg = nseg,
        .corner = (const double(*)[2])corner,
        .ncorner = ncorner,
        .rules = mote_mb_event_rules(&rules),
    };
    rc = mote_ev_set_field(&ev, &f, err);
    if (!rc)
        rc = mote_ev_rebuild(&ev, err);
    ev.obs = (mote_ev_observer){&l, NULL, NULL, on_event};
    sys->live_ev = &ev; /* (a live view reads positions from the engine during the run) */
    sys->live_x0 = l.x0;
    sys->live_y0 = l.y0;
    sys->live_t0 = t_offset;
    mb_event_run x = {&l, &rules, kinds, {0}, t_offset};
    r.sys = &x;
    r.subject = sys;
    r.clock = event_clock;
    r.count = event_count;
    r.advance = advance_event;
    if (!rc)
        rc = mote_run(&r, spec->obs, spec->nobs, spec->progress, t_end, spec->n_end, err);
    if (rc) /* leave the arrays at the engine's last consistent state */
        sync_back(&l, t_offset + mote_ev_time(&ev));
    sys->live_ev = NULL;
    for (uint32_t i = 0; i < sys->n; i++)
        sys->t_last[i] = rules.t_last[i] + t_offset;
    free(rules.t_last);
    sys->generation++;
    mote_ev_free(&ev);
    return rc;
}
