/* rules.c: the collision rules every mixing-box integrator shares: the document's rule (spec 2.3,
 * `collision_rule seed`) and normal restitution (`collision_rule restitution`), both with the TC
 * model of Luding & McNamara (a collision within t_c of either disk's previous one is elastic),
 * so the time-stepped and the event-driven integrators collide disks identically. */
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
