/* monitor.c: `monitor every=K|dt=T file=FILE`, the run's quantities over time (issue 53): a row
 * now, then one every K collisions per particle or every T of time during every later command
 * that runs the dynamics: the time, the collisions, the kinetic temperature, and the pressure of
 * the interval since the previous row (on each wall of a slit from the momentum the walls
 * received; in a periodic box from the collisional virial, as `pressure` computes them, spec
 * 8.4). The rows follow the core's policy (mote_rows): FILE.partial as they are taken (`tail
 * -f`), FILE whole at the end of every command that ran the dynamics (and at the command when
 * there is no FILE yet), so an earlier complete FILE is replaced only by a complete one. The
 * collisions and wall hits are counted by
 * engine hooks that pass every event on to hooks installed before them (a measurement's). */
#include "mote/datafile.h"
#include "mote/hardspheres.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "measure.h"

struct hs_monitor {
    char *origin;
    mote_rows out;     /* FILE's rows (the core's file policy) */
    uint64_t k;        /* collisions per particle between rows (0: by time) */
    uint64_t next_at;  /* by collisions: the count of the next row */
    mote_schedule at;  /* by time: the next row at at.t0 + at.k at.dt */
    double t_last;     /* the time of the last row */
    double W, mom[2];  /* since the last row: sum r_ij . J_ij, the walls' momentum */
    mote_ev_observer chained; /* during a run: the hooks installed before ours */
};

static const char COLUMNS[] = "t collisions wall_collisions kT P_virial P_left P_right";

static uint64_t interval(const mote_hs *hs)
{
    const uint64_t c = hs->monitor->k * hs->ev.n / 2;
    return c ? c : 1;
}

/* A row of the interval since the last: written to f. */
static void row(FILE *f, const mote_hs *hs)
{
    const struct hs_monitor *m = hs->monitor;
    const mote_ev *ev = &hs->ev;
    const int d = ev->dim;
    const double t = mote_ev_time(ev), tau = t - m->t_last, kt = mote_ev_kt(ev);
    const double area = mote_hs_cross_section(hs), V = ev->len[0] * area;
    double pv = NAN, pl = NAN, pr = NAN;
    if (tau > 0 && hs->geometry == MOTE_HS_PERIODIC)
        pv = (d * (double)ev->n * kt + m->W / tau) / (d * V);
    if (tau > 0 && hs->geometry == MOTE_HS_SLIT) {
        pl = m->mom[0] / (area * tau);
        pr = m->mom[1] / (area * tau);
    }
    fprintf(f, "%.17g %llu %llu %.17g %.17g %.17g %.17g\n", t,
            (unsigned long long)ev->collisions, (unsigned long long)ev->wall_collisions, kt, pv,
            pl, pr);
}

static void interval_start(mote_hs *hs)
{
    struct hs_monitor *m = hs->monitor;
    m->t_last = mote_ev_time(&hs->ev);
    m->W = m->mom[0] = m->mom[1] = 0;
}

static void header(FILE *f, const void *vhs, int growing)
{
    const mote_hs *hs = vhs;
    const struct hs_monitor *m = hs->monitor;
    const mote_ev *ev = &hs->ev;
    mote_datafile_preamble(f, "hard-spheres-monitor", m->origin, hs->seed);
    fprintf(f, "# N = %u\n# d = %d\n# geometry = %s\n", ev->n, ev->dim,
            hs->geometry == MOTE_HS_SLIT ? "slit" : "periodic");
    if (m->k)
        fprintf(f, "# every = %llu collisions per particle\n", (unsigned long long)m->k);
    else
        fprintf(f, "# dt = %.17g\n", m->at.dt);
    fprintf(f, "# A row now and then on the schedule: t; pair and wall collisions so far; kT, the "
               "kinetic temperature now; the pressure of the interval since the previous row: "
               "P_virial (periodic box: (N d kT + sum r_ij . J_ij / tau) / (d V)), P_left and "
               "P_right (slit: the momentum each wall received / (A tau)); nan where the "
               "geometry has none or the interval is empty\n");
    fprintf(f, "# units: length R; time sqrt(m R^2 / kT); pressure kT / R^%d\n", ev->dim);
    fprintf(f, "# columns: %s\n", COLUMNS);
}

int mote_hs_monitor_start(mote_hs *hs, uint64_t k, double dt, const char *path,
                          const char *origin, mote_err *err)
{
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "monitor: no system");
    if ((k > 0) == (dt > 0) || !(dt >= 0))
        return mote_fail(err, MOTE_EINVAL, "monitor: give every=K or dt=T (> 0), one of them");
    struct hs_monitor *m = calloc(1, sizeof *m);
    if (m)
        m->origin = strdup(origin ? origin : "(library call)");
    if (!m || !m->origin) {
        if (m)
            free(m->origin);
        free(m);
        return mote_fail(err, MOTE_ENOMEM, "monitor: out of memory");
    }
    mote_hs_monitor_stop(hs);
    hs->monitor = m;
    m->k = k;
    m->at = (mote_schedule){mote_ev_time(&hs->ev), dt, 1};
    m->next_at = k ? hs->ev.collisions + interval(hs) : 0;
    interval_start(hs);
    /* the first row now: FILE.partial, and FILE when there is none yet */
    int rc = mote_rows_open(&m->out, path, header, hs, err);
    if (!rc) {
        m->out.as = hs->monitor_as;
        row(m->out.text, hs);
        rc = mote_rows_start(&m->out, err);
    }
    if (rc)
        mote_hs_monitor_stop(hs);
    return rc;
}

void mote_hs_monitor_stop(mote_hs *hs)
{
    if (!hs->monitor)
        return;
    mote_rows_free(&hs->monitor->out);
    free(hs->monitor->origin);
    free(hs->monitor);
    hs->monitor = NULL;
}

int hs_monitor_end(mote_hs *hs, int rc, mote_err *err)
{
    if (!hs->monitor)
        return rc;
    return mote_rows_end(&hs->monitor->out, rc, err);
}

uint64_t mote_hs_monitor_rows(const mote_hs *hs) { return hs->monitor ? hs->monitor->out.rows : 0; }

/* A row: formatted once, followed in FILE.partial. */
static int fire(void *ctx, void *subject, mote_err *err)
{
    mote_hs *hs = ctx;
    struct hs_monitor *m = hs->monitor;
    row(m->out.text, hs);
    int rc = mote_rows_follow(&m->out, err);
    if (rc)
        return rc;
    interval_start(hs);
    if (m->k)
        m->next_at = hs->ev.collisions + interval(hs);
    return MOTE_OK;
}

size_t hs_monitor_observer(mote_hs *hs, mote_observer *o)
{
    struct hs_monitor *m = hs->monitor;
    if (!m)
        return 0;
    if (!m->k) { /* by time (a state loaded from another time: on from it) */
        const double now = mote_ev_time(&hs->ev);
        if (!(mote_schedule_next(&m->at) > now) || mote_schedule_next(&m->at) > now + m->at.dt) {
            m->at = (mote_schedule){now, m->at.dt, 1};
            interval_start(hs);
        }
        *o = (mote_observer){.at = &m->at, .ctx = hs, .fire = fire};
        return 1;
    }
    if (m->next_at <= hs->ev.collisions) { /* a state loaded from another point of time */
        m->next_at = hs->ev.collisions + interval(hs);
        interval_start(hs);
    }
    *o = (mote_observer){.ctx = hs, .fire = fire, .every = interval(hs), .from = m->next_at};
    return 1;
}

/* The engine's hooks during a run: the interval's virial and wall momentum, every event passed
 * on to the hooks installed before. */
static void on_pair(void *ctx, uint32_t i, uint32_t j, const double rij[3], const double J[3],
                    double t)
{
    struct hs_monitor *m = ctx;
    m->W += rij[0] * J[0] + rij[1] * J[1] + rij[2] * J[2];
    if (m->chained.on_pair)
        m->chained.on_pair(m->chained.ctx, i, j, rij, J, t);
}

static void on_wall(void *ctx, uint32_t i, int axis, int side, double momentum, double t)
{
    struct hs_monitor *m = ctx;
    if (axis == 0)
        m->mom[side] += momentum;
    if (m->chained.on_wall)
        m->chained.on_wall(m->chained.ctx, i, axis, side, momentum, t);
}

static void on_event(void *ctx, uint32_t i)
{
    struct hs_monitor *m = ctx;
    if (m->chained.on_event)
        m->chained.on_event(m->chained.ctx, i);
}

void hs_monitor_hooks(mote_hs *hs, int on)
{
    struct hs_monitor *m = hs->monitor;
    if (!m)
        return;
    if (on) {
        m->chained = hs->ev.obs;
        hs->ev.obs = (mote_ev_observer){m, on_pair, on_wall, m->chained.on_event ? on_event : NULL};
    } else {
        hs->ev.obs = m->chained;
    }
}
