/* compress.c: slow compression or expansion of the slit by moving one wall or both (spec 7.6).
 * Each move is limited by dLmax and, when compressing, by the gap of the moving wall divided by a
 * safety factor, so no sphere ever overlaps a wall; K collisions per particle follow every move.
 * The final move lands exactly on L* = 2 R + sum v_i / (eta A^2).
 *
 * Decision (performance; departs from spec 6.7's "rebuild after every compress move"): a move
 * does not rebuild the whole calendar. Gaps are measured on positions projected to the clock and
 * the engine moves the walls in place (mote_ev_move_walls), re-predicting only the particles next
 * to a wall, which are the only ones whose predictions a wall can change. Compression is gap
 * limited (moves of about 1e-3 R at N ~ 7000), so it takes ~10^4 moves; a full O(N) rebuild per
 * move used to cost more than the collisions themselves. The result is exact and deterministic;
 * it is not bit-identical to a run that rebuilds after every move. */
#include "mote/hardspheres.h"

#include <math.h>

#include "measure.h"

/* Smallest distances of a sphere surface to the left and right walls, at the clock. */
static void wall_gaps(const mote_ev *ev, double *gl, double *gr)
{
    double l = INFINITY, r = INFINITY;
    for (uint32_t i = 0; i < ev->n; i++) {
        const mote_particle *p = &ev->p[i];
        double R = mote_ev_radius(ev, i), x = p->r[0] + p->v[0] * (ev->clock - p->t);
        if (x - R < l)
            l = x - R;
        if (ev->len[0] - R - x < r)
            r = ev->len[0] - R - x;
    }
    *gl = l;
    *gr = r;
}

int mote_hs_compress(mote_hs *hs, int which, double eta, double dlmax, uint64_t k, mote_err *err)
{
    static const char *const names[3] = {"compress_left_wall", "compress_right_wall",
                                   "compress_two_walls"};
    const char *name = names[which];
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "%s: no system (use new or load first)", name);
    if (hs->geometry != MOTE_HS_SLIT)
        return mote_fail(err, MOTE_EINVAL, "%s: the system is periodic; there is no wall to move",
                         name);
    mote_ev *ev = &hs->ev;
    const double eta_cp = ev->dim == 3 ? 0.74048048969306104 : 0.90689968211710892;
    if (!(eta > 0) || !(eta < eta_cp))
        return mote_fail(err, MOTE_EINVAL, "%s: eta must be in (0, %.5f), got %.17g", name,
                         eta_cp, eta);
    if (!(dlmax > 0))
        return mote_fail(err, MOTE_EINVAL, "%s: dLmax must be > 0, got %g", name, dlmax);

    const double target = mote_hs_target_length(hs, eta);
    const double safety = 1.1;
    const uint64_t per_move = k * ev->n / 2;
    if (ev->len[0] == target) {
        if (hs->log)
            fprintf(hs->log, "%s: already at target eta=%.15g; nothing to do\n", name, eta);
        return MOTE_OK;
    }
    uint64_t moves = 0, zero_moves = 0, c0 = ev->collisions;
    double L_start = ev->len[0];
    mote_progress prog;
    mote_progress_begin(&prog, hs->ctx, name);
    int final = 0, rc = MOTE_OK;
    while (!final) {
        double gl, gr, delta;
        wall_gaps(ev, &gl, &gr);
        double L = ev->len[0];
        if (L > target) {
            double D = L - target;
            double cap = which == MOTE_HS_LEFT    ? gl / safety
                         : which == MOTE_HS_RIGHT ? gr / safety
                                                  : 2 * fmin(gl, gr) / safety;
            delta = fmin(cap, dlmax);
            final = delta >= D;
            if (final)
                delta = D;
            else if (delta < 1e-13 * L)
                delta = 0;
        } else {
            double D = target - L;
            delta = -fmin(D, dlmax);
            final = D <= dlmax;
        }
        double shift = which == MOTE_HS_LEFT ? delta : which == MOTE_HS_BOTH ? 0.5 * delta : 0;
        if ((rc = mote_ev_move_walls(ev, 0, shift, final ? target : L - delta, err)))
            break;
        moves++;
        zero_moves = delta == 0 ? zero_moves + 1 : 0;
        if (zero_moves >= 10000) {
            rc = mote_fail(err, MOTE_ERUNTIME,
                           "%s: stalled: 10000 moves in a row could not move the wall (a sphere "
                           "stays in contact); eta=%.12g, target %.12g",
                           name, mote_hs_eta(hs), eta);
            break;
        }
        if ((rc = hs_run(hs, per_move, err)))
            break;
        if (moves % 1000 == 0 && hs->log && !(hs->ctx && hs->ctx->terminal))
        {
            fprintf(hs->log, "%s: %llu moves, eta=%.12g\n", name, (unsigned long long)moves,
                    mote_hs_eta(hs));
            fflush(hs->log); /* progress must show up promptly in a log file */
        }
        double span = fabs(L_start - target);
        if (mote_progress_update(&prog, span > 0 ? 1 - fabs(ev->len[0] - target) / span : 1)) {
            rc = mote_interrupted(err, name);
            break;
        }
    }
    mote_progress_end(&prog);
    if ((rc = hs_monitor_end(hs, rc, err)))
        return rc;
    if (hs->log)
        fprintf(hs->log, "%s: done: moves=%llu collisions=%llu eta=%.15g (target %.15g)\n", name,
                (unsigned long long)moves, (unsigned long long)(ev->collisions - c0),
                mote_hs_eta(hs), eta);
    return MOTE_OK;
}

/* ---- a periodic box: affine compression (issue 20.3) ----------------------------------------- */

/* Decision: the box and every centre are scaled by one factor s per move, measured on the
 * canonical state (a rebuild), so that the closest pair, at distance ratio r_min = |r_ij| /
 * sigma_ij, stays apart: s >= 1 - (1 - 1/r_min) / 1.1 (the walls' safety factor), and the box
 * length changes by at most dLmax. K collisions per particle follow each move; the last move lands
 * on the target: every length is the starting length times (phi / eta)^(1/d), so phi = eta up to
 * rounding. Expansion is one move (it cannot overlap). */
int mote_hs_compress_box(mote_hs *hs, double eta, double dlmax, uint64_t k, mote_err *err)
{
    const char *name = "compress_box";
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "%s: no system (use bulk, bulk_disks or load first)",
                         name);
    if (hs->geometry != MOTE_HS_PERIODIC)
        return mote_fail(err, MOTE_EINVAL,
                         "%s: the system has walls; compress a slit with compress_left_wall, "
                         "compress_right_wall or compress_two_walls",
                         name);
    mote_ev *ev = &hs->ev;
    const int d = ev->dim;
    const double eta_cp = d == 3 ? 0.74048048969306104 : 0.90689968211710892;
    if (!(eta > 0) || !(eta < eta_cp))
        return mote_fail(err, MOTE_EINVAL, "%s: eta must be in (0, %.5f), got %.17g", name,
                         eta_cp, eta);
    if (!(dlmax > 0))
        return mote_fail(err, MOTE_EINVAL, "%s: dLmax must be > 0, got %g", name, dlmax);
    const uint64_t per_move = k * ev->n / 2;
    const double phi0 = mote_hs_phi(hs), len0[3] = {ev->len[0], ev->len[1], ev->len[2]};
    const double c_end = pow(phi0 / eta, 1.0 / d); /* final lengths: len0 * c_end */
    double c = 1;                                  /* lengths now: len0 * c */
    uint64_t moves = 0, stalled = 0, c0 = ev->collisions;
    mote_progress prog;
    mote_progress_begin(&prog, hs->ctx, name);
    int rc = MOTE_OK, final = c_end == 1;
    while (!final) {
        if ((rc = mote_hs_settle(hs, err)))
            break;
        double ratio = mote_ev_min_gap_ratio(ev, NULL, NULL);
        double s;
        if (c_end > c) { /* expansion: at once */
            s = c_end / c;
            final = 1;
        } else {
            double s_gap = ratio > 1 ? 1 - (1 - 1 / ratio) / 1.1 : 1;
            double s_step = 1 - dlmax / (len0[0] * c);
            s = fmax(s_gap, s_step);
            if (s <= c_end / c) {
                s = c_end / c;
                final = 1;
            }
        }
        stalled = s == 1 ? stalled + 1 : 0;
        if (stalled >= 10000) {
            rc = mote_fail(err, MOTE_ERUNTIME,
                           "%s: stalled: 10000 moves in a row could not shrink the box (a pair "
                           "stays in contact); eta=%.12g, target %.12g",
                           name, mote_hs_phi(hs), eta);
            break;
        }
        c = final ? c_end : c * s;
        for (uint32_t i = 0; i < ev->n; i++)
            for (int a = 0; a < d; a++)
                ev->p[i].r[a] *= s;
        for (int a = 0; a < d; a++)
            ev->len[a] = len0[a] * c;
        if ((rc = mote_ev_rebuild(ev, err)))
            break;
        moves++;
        double t0 = mote_ev_time(ev);
        if ((rc = hs_run(hs, per_move, err)))
            break;
        /* a run stops right after a collision, whose pair is then at contact and would stop the
         * next move: go on for a quarter of a mean free time, to an instant no collision marks */
        double tau = (mote_ev_time(ev) - t0) / (double)k;
        if (!final && tau > 0 && (rc = mote_ev_run_to(ev, mote_ev_time(ev) + 0.25 * tau,
                                                      UINT64_MAX, err)))
            break;
        double span = fabs(c_end - 1);
        if (mote_progress_update(&prog, span > 0 ? fabs(c - 1) / span : 1)) {
            rc = mote_interrupted(err, "compress");
            break;
        }
    }
    mote_progress_end(&prog);
    if ((rc = hs_monitor_end(hs, rc, err)))
        return rc;
    if (hs->log)
        fprintf(hs->log, "%s: done: moves=%llu collisions=%llu eta=%.15g (target %.15g)\n", name,
                (unsigned long long)moves, (unsigned long long)(ev->collisions - c0),
                mote_hs_phi(hs), eta);
    return MOTE_OK;
}
