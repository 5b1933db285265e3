/* timestep.c: the time-stepped reference integrator of the mixing-box model (spec 2), the
 * document's algorithm kept so users can reproduce the original behaviour and compare it with
 * the exact event-driven mode. Each step: dt = R / (8 V) from the fastest speed; move every disk
 * (a parabola under gravity); collide every pair closer than 2R that approaches, pushing the upper
 * disk out to contact; apply the wall, partition and slit rules with their kicks; note slit
 * crossings; count overlapping pairs. Its known defects (late or missed collisions, overlaps,
 * energy drift under gravity, unhandled slit corners) are kept, not fixed. A cell grid makes a
 * step O(N). */
#include "mb.h"


#include <math.h>
#include <stdlib.h>
#include <string.h>

double mb_ts_dt(const mote_mb *sys)
{
    double v2max = 0.0;
    for (uint32_t i = 0; i < sys->n; i++) {
        double v2 = sys->vx[i] * sys->vx[i] + sys->vy[i] * sys->vy[i];
        if (!(v2 <= v2max)) {
            if (!isfinite(v2))
                return NAN;
            v2max = v2;
        }
    }
    double v = sqrt(v2max);
    if (v == 0.0)
        v = sys->p.v_init;
    if (v == 0.0)
        v = 0.1;
    return sys->p.r / (8.0 * v);
}

int mb_ts_pair(mote_mb *sys, uint32_t i, uint32_t j, double t)
{
    const double R = sys->p.r;
    double dx = sys->x[j] - sys->x[i], dy = sys->y[j] - sys->y[i];
    double d2 = dx * dx + dy * dy;
    if (!(d2 < 4.0 * R * R) || !(d2 > 0))
        return 0;
    /* The exact approach test; the document's per-axis test is a cruder stand-in for it. */
    if (!(dx * (sys->vx[j] - sys->vx[i]) + dy * (sys->vy[j] - sys->vy[i]) < 0))
        return 0;
    mote_mb_collide(sys, i, j, t);
    /* Push the upper disk out along the line of centres to contact (none when level). */
    double d = sqrt(d2), shift = 2.0 * R - d;
    uint32_t up, lo;
    if (sys->y[i] > sys->y[j]) {
        up = i;
        lo = j;
    } else if (sys->y[j] > sys->y[i]) {
        up = j;
        lo = i;
    } else {
        return 1;
    }
    double ex = (sys->x[up] - sys->x[lo]) / d, ey = (sys->y[up] - sys->y[lo]) / d;
    sys->x[up] += shift * ex;
    sys->y[up] += shift * ey;
    return 1;
}

void mb_ts_walls(mote_mb *sys, uint32_t i)
{
    const mote_mb_params *p = &sys->p;
    const double R = p->r;
    double x = sys->x[i], y = sys->y[i], vx = sys->vx[i], vy = sys->vy[i];
    /* box walls, in the document's order */
    if (y > p->x_t - R && vy > 0) {
        y = p->x_t - R;
        vy = -(vy + p->dv_t);
        sys->wall_hits++;
    }
    if (y < p->x_b + R && vy < 0) {
        y = p->x_b + R;
        vy = -(vy - p->dv_b);
        sys->wall_hits++;
    }
    if (x < p->x_l + R && vx < 0) {
        x = p->x_l + R;
        vx = -(vx - p->dv_s);
        sys->wall_hits++;
    }
    if (x > p->x_r - R && vx > 0) {
        x = p->x_r - R;
        vx = -(vx + p->dv_s);
        sys->wall_hits++;
    }
    /* the partition band */
    const double x1l = mote_mb_x1_l(p), x1r = mote_mb_x1_r(p);
    const double x2b = mote_mb_x2_b(p), x2t = mote_mb_x2_t(p);
    if (x1l - R < x && x < x1r + R) {
        if (x1l < x && x < x1r) {
            /* centre inside the slit channel: its top and bottom edges */
            if (y > x2t - R && vy > 0) {
                y = x2t - R;
                vy = -(vy + p->dv_t);
                sys->slit_hits++;
            }
            if (y < x2b + R && vy < 0) { /* the document's "y > X2_B + R" is a sign typo */
                y = x2b + R;
                vy = -(vy - p->dv_b);
                sys->slit_hits++;
            }
        } else if (y > x2t || y < x2b) {
            /* beside the partition, not at slit height: its face on the disk's side */
            if (x < p->x1_c && vx > 0) {
                x = x1l - R;
                vx = -(vx + p->dv_s);
                sys->partition_hits++;
            } else if (x > p->x1_c && vx < 0) {
                x = x1r + R;
                vx = -(vx - p->dv_s);
                sys->partition_hits++;
            }
        }
    }
    sys->x[i] = x;
    sys->y[i] = y;
    sys->vx[i] = vx;
    sys->vy[i] = vy;
}

/* Pairs (i < j) packed as (uint64_t)i << 32 | j. */
typedef struct {
    uint64_t *p;
    size_t n, cap;
} mb_pairs;

static int push_pair(void *ctx, uint32_t i, uint32_t j, const double d[3], double r2)
{
    mb_pairs *out = ctx;
    if (out->n == out->cap) {
        size_t cap = out->cap ? 2 * out->cap : 256;
        uint64_t *p = realloc(out->p, cap * sizeof *p);
        if (!p)
            return 1;
        out->p = p;
        out->cap = cap;
    }
    out->p[out->n++] = (uint64_t)i << 32 | j;
    return 0;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* Working memory of the steps of one run. */
typedef struct {
    mb_pairs pairs;   /* pairs closer than 2R after the move, sorted */
    uint8_t *moved;   /* per disk: moved after the pairs were gathered (push, wall) */
    uint32_t *list;   /* the moved disks */
    size_t nlist;
    double *mx, *my;  /* their positions, for the moved-moved pairs */
    mote_grid sub;    /* grid over the moved disks */
} ts_work;

static int work_init(ts_work *w, uint32_t n)
{
    memset(w, 0, sizeof *w);
    size_t m = n ? n : 1;
    w->moved = calloc(m, 1);
    w->list = malloc(m * sizeof *w->list);
    w->mx = malloc(m * sizeof *w->mx);
    w->my = malloc(m * sizeof *w->my);
    return w->moved && w->list && w->mx && w->my ? 0 : -1;
}

static void work_free(ts_work *w)
{
    free(w->pairs.p);
    free(w->moved);
    free(w->list);
    free(w->mx);
    free(w->my);
    mote_grid_free(&w->sub);
}

static void mark_moved(ts_work *w, uint32_t i)
{
    if (!w->moved[i]) {
        w->moved[i] = 1;
        w->list[w->nlist++] = i;
    }
}

/* The disk-disk part of a step: the pairs closer than 2R after the move, taken in the order of
 * the document's double loop (i ascending, then j ascending), each tested again with the
 * positions and velocities of its turn (an earlier pair of the same step may have changed them).
 * Pairs that only come closer than 2R through a push of the same pass wait for the next step. */
static int pair_pass(mote_mb *sys, ts_work *w, double t, mote_err *err)
{
    mb_grid_build(sys->grid, sys->n, sys->x, sys->y);
    w->pairs.n = 0;
    if (mote_grid_pairs(sys->grid, 2 * sys->p.r, push_pair, &w->pairs) == UINT64_MAX)
        return mote_fail(err, MOTE_ENOMEM, "run: out of memory");
    if (w->pairs.n > 1)
        qsort(w->pairs.p, w->pairs.n, sizeof *w->pairs.p, cmp_u64);
    for (size_t k = 0; k < w->pairs.n; k++) {
        uint32_t i = (uint32_t)(w->pairs.p[k] >> 32), j = (uint32_t)w->pairs.p[k];
        double xi = sys->x[i], yi = sys->y[i], xj = sys->x[j], yj = sys->y[j];
        mb_ts_pair(sys, i, j, t);
        if (sys->x[i] != xi || sys->y[i] != yi)
            mark_moved(w, i);
        if (sys->x[j] != xj || sys->y[j] != yj)
            mark_moved(w, j);
    }
    return MOTE_OK;
}

/* Pairs closer than 2R (1 - tol) at the end of the step, without a new grid: a pair of disks
 * that did not move since the pairs were gathered is overlapping only if it was gathered; a
 * moved disk is checked against the unmoved ones in the cells around it, and the moved disks
 * against each other on a small grid of their own. Equal to mote_mb_count_overlaps. */
static uint64_t step_overlaps(mote_mb *sys, ts_work *w)
{
    const double s = 2 * sys->p.r * (1 - MOTE_MB_OVERLAP_TOL), s2 = s * s;
    const double *x = sys->x, *y = sys->y;
    uint64_t count = 0;
    for (size_t k = 0; k < w->pairs.n; k++) {
        uint32_t i = (uint32_t)(w->pairs.p[k] >> 32), j = (uint32_t)w->pairs.p[k];
        if (w->moved[i] || w->moved[j])
            continue;
        double dx = x[j] - x[i], dy = y[j] - y[i];
        count += dx * dx + dy * dy < s2;
    }
    if (w->nlist == 0)
        return count;
    const mote_grid *g = sys->grid;
    for (size_t k = 0; k < w->nlist; k++) {
        uint32_t i = w->list[k];
        const double xi[3] = {x[i], y[i], 0};
        size_t cells[27];
        double shift[27][3];
        int nn = mote_grid_neighbours(g, mote_grid_cell_of(g, xi), cells, shift);
        for (int q = 0; q < nn; q++)
            for (uint32_t b = g->start[cells[q]]; b < g->start[cells[q] + 1]; b++) {
                if (w->moved[g->order[b]])
                    continue;
                double dx = g->pos[3 * (size_t)b] - x[i], dy = g->pos[3 * (size_t)b + 1] - y[i];
                count += dx * dx + dy * dy < s2;
            }
        w->mx[k] = x[i];
        w->my[k] = y[i];
    }
    if (w->nlist > 1) {
        const mote_mb_params *p = &sys->p;
        if (mb_grid_setup(&w->sub, p, (uint32_t)w->nlist))
            return UINT64_MAX;
        mb_grid_build(&w->sub, (uint32_t)w->nlist, w->mx, w->my);
        uint64_t c = mote_grid_pairs(&w->sub, s, NULL, NULL);
        if (c == UINT64_MAX)
            return c;
        count += c;
    }
    return count;
}

static int step(mote_mb *sys, ts_work *w, double dt, double t_new, mote_err *err)
{
    const double g = sys->p.g, dy_g = 0.5 * g * dt * dt, dv_g = g * dt;
    for (uint32_t i = 0; i < sys->n; i++) {
        sys->x[i] += sys->vx[i] * dt;
        sys->y[i] += sys->vy[i] * dt - dy_g;
        sys->vy[i] -= dv_g;
    }
    int rc = pair_pass(sys, w, t_new, err);
    if (rc)
        return rc;
    for (uint32_t i = 0; i < sys->n; i++) {
        double xi = sys->x[i], yi = sys->y[i];
        mb_ts_walls(sys, i);
        if (sys->x[i] != xi || sys->y[i] != yi)
            mark_moved(w, i);
        mote_mb_note_side(sys, i);
    }
    uint64_t ov = step_overlaps(sys, w);
    for (size_t k = 0; k < w->nlist; k++)
        w->moved[w->list[k]] = 0;
    w->nlist = 0;
    if (ov == UINT64_MAX)
        return mote_fail(err, MOTE_ENOMEM, "run: out of memory");
    mote_mb_note_overlaps(sys, ov);
    if (ov)
        sys->overlap_steps++;
    sys->steps++;
    return MOTE_OK;
}

int mb_ts_step(mote_mb *sys, double dt, double t_new, mote_err *err)
{
    ts_work w;
    memset(&w, 0, sizeof w);
    int rc = mb_ensure_grid(sys) || work_init(&w, sys->n)
                 ? mote_fail(err, MOTE_ENOMEM, "run: out of memory")
                 : step(sys, &w, dt, t_new, err);
    if (!rc)
        sys->time = t_new;
    work_free(&w);
    return rc;
}

/* The model's side of the core loop: steps of dt from the fastest speed, the last one cut at
 * the stop; the advance returns as soon as a sample is due (within its tolerance) or the
 * collision count is reached. */
typedef struct {
    mote_mb *sys;
    ts_work *w;
} ts_run;

static double ts_clock(const void *vr) { return ((const ts_run *)vr)->sys->time; }
static uint64_t ts_count(const void *vr) { return ((const ts_run *)vr)->sys->collisions; }

static int ts_advance(void *vr, mote_loop *loop, double t_stop, uint64_t n_stop, mote_err *err)
{
    ts_run *x = vr;
    mote_mb *sys = x->sys;
    while (sys->time < t_stop && sys->collisions < n_stop) {
        double dt = mb_ts_dt(sys);
        if (!isfinite(dt))
            return mote_fail(err, MOTE_ERUNTIME,
                             "run: a speed is no longer finite at t = %.9g s (do the kicks "
                             "feed energy without bound?)",
                             sys->time);
        double t_new = sys->time + dt;
        if (t_new >= t_stop) {
            dt = t_stop - sys->time;
            t_new = t_stop;
        }
        int rc = step(sys, x->w, dt, t_new, err);
        if (rc)
            return rc;
        sys->time = t_new;
        if (mote_loop_due(loop, sys->time))
            break;
        if ((sys->steps & 255) == 0 && mote_mb_progress(loop, sys))
            return mote_interrupted(err, "run");
    }
    return MOTE_OK;
}

int mb_run_timestep(mote_mb *sys, double t_end, const mote_loop *spec, mote_err *err)
{
    ts_work w;
    memset(&w, 0, sizeof w);
    int rc = MOTE_OK;
    if (mb_ensure_grid(sys) || work_init(&w, sys->n)) {
        work_free(&w);
        return mote_fail(err, MOTE_ENOMEM, "run: out of memory");
    }
    ts_run x = {sys, &w};
    const mote_runner r = {.what = "run", .sys = &x, .subject = sys,
                           .ctx = spec->progress ? spec->progress->ctx : NULL,
                           .clock = ts_clock, .count = ts_count, .advance = ts_advance};
    rc = mote_run(&r, spec->obs, spec->nobs, spec->progress, t_end, spec->n_end, err);
    work_free(&w);
    sys->generation++;
    return rc;
}
