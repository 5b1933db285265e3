/* rules.c: the collision rules of the mixing box, for both integrators: the document's rule
 * (spec 2.3, `collision_rule seed`, as the time-stepped mode writes it) and normal restitution
 * (`collision_rule restitution`), with the TC model of Luding & McNamara (a collision within t_c
 * of either disk's previous one is elastic); and the event integrator's rules as the event
 * engine calls them (disk pairs, box walls, partition faces and corners). The engine only finds
 * the events; everything that happens at one is here. */
#include "mote/mixingbox.h"

#include <math.h>

int mote_mb_rule_seed(double x1, double y1, double x2, double y2, double v1[2], double v2[2],
                      double f)
{
    double dx = fabs(x2 - x1), dy = fabs(y2 - y1);
    double d = sqrt(dx * dx + dy * dy);
    if (!(d > 0))
        return 0;
    double s = dy / d, c = dx / d;
    double dvx = v1[0] - v2[0], dvy = v1[1] - v2[1];
    double v2x = v2[0], v2y = v2[1];
    v1[0] = (dvx * s * s - dvy * s * c + v2x) * f;
    v1[1] = (dvy * c * c - dvx * s * c + v2y) * f;
    v2[0] = (dvx * c * c + dvy * s * c + v2x) * f;
    v2[1] = (dvy * s * s + dvx * s * c + v2y) * f;
    return 1;
}

int mote_mb_rule_restitution(double x1, double y1, double x2, double y2, double v1[2],
                             double v2[2], double e)
{
    double dx = x2 - x1, dy = y2 - y1;
    double d = sqrt(dx * dx + dy * dy);
    if (!(d > 0))
        return 0;
    double nx = dx / d, ny = dy / d;
    double u = (v1[0] - v2[0]) * nx + (v1[1] - v2[1]) * ny;
    double j = 0.5 * (1.0 + e) * u;
    v1[0] -= j * nx;
    v1[1] -= j * ny;
    v2[0] += j * nx;
    v2[1] += j * ny;
    return 1;
}

void mote_mb_collide(mote_mb *sys, uint32_t i, uint32_t j, double t)
{
    double f = sqrt(1.0 - sys->p.loss);
    if (f != 1.0) {
        double tc = mote_mb_tc(&sys->p);
        if (t - sys->t_last[i] < tc || t - sys->t_last[j] < tc) {
            f = 1.0;
            sys->collisions_tc++;
        }
    }
    double v1[2] = {sys->vx[i], sys->vy[i]}, v2[2] = {sys->vx[j], sys->vy[j]};
    if (sys->p.rule == MOTE_MB_SEEDRULE)
        mote_mb_rule_seed(sys->x[i], sys->y[i], sys->x[j], sys->y[j], v1, v2, f);
    else
        mote_mb_rule_restitution(sys->x[i], sys->y[i], sys->x[j], sys->y[j], v1, v2, f);
    sys->vx[i] = v1[0];
    sys->vy[i] = v1[1];
    sys->vx[j] = v2[0];
    sys->vy[j] = v2[1];
    sys->t_last[i] = sys->t_last[j] = t;
    sys->collisions++;
}

/* ---- the event integrator's rules ------------------------------------------------------------ */

static void ev_pair(void *ctx, uint32_t i, uint32_t j, const double dr[2], double vi[2],
                    double vj[2], double t)
{
    mote_mb_rules *r = ctx;
    double e = r->e;
    if (e < 1 && (t - r->t_last[i] < r->tc || t - r->t_last[j] < r->tc)) {
        e = 1;
        r->tc_elastic++;
    }
    r->t_last[i] = r->t_last[j] = t;
    /* disk i at dr, disk j at the origin */
    mote_mb_rule_restitution(dr[0], dr[1], 0, 0, vi, vj, r->scale_rule ? 1.0 : e);
    if (r->scale_rule)
        for (int a = 0; a < 2; a++) {
            vi[a] *= e;
            vj[a] *= e;
        }
}

/* A disk leaving a surface the field pulls towards (pull = the field's component into it) with
 * normal speed `out` leaves at no less than pull tc. */
static double tc_floor(double out, double pull, double tc)
{
    return pull > 0 && out < pull * tc ? pull * tc : out;
}

static void ev_wall(void *ctx, uint32_t i, int a, int side, double v[2], double t)
{
    mote_mb_rules *r = ctx;
    if (side ? v[a] > 0 : v[a] < 0) /* (rounding can bring one that just left it here) */
        v[a] = -v[a];
    double out = (side ? -v[a] : v[a]) + r->kick[a][side];
    out = tc_floor(out, side ? r->g[a] : -r->g[a], r->tc);
    v[a] = side ? -out : out;
}

static int ev_face(void *ctx, uint32_t i, int kind, uint32_t which, const double n[2],
                   double v[2], double t)
{
    mote_mb_rules *r = ctx;
    double vn = v[0] * n[0] + v[1] * n[1];
    double out = -vn; /* the normal speed after a reflection */
    if (kind == MOTE_EV_SEG) {
        out = tc_floor(out + r->face_kick[which], -(r->g[0] * n[0] + r->g[1] * n[1]), r->tc);
        r->face_hits[which]++;
    } else {
        r->corner_hits++;
    }
    v[0] += (out - vn) * n[0];
    v[1] += (out - vn) * n[1];
    return 1;
}

mote_ev_rules mote_mb_event_rules(mote_mb_rules *r)
{
    return (mote_ev_rules){r, ev_pair, ev_wall, ev_face};
}
