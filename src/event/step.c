/* step.c: the event loop of the engine: predicting a particle's next event, renewing its
 * neighbour list, and running from event to event. It is written once, as inline functions whose
 * last arguments are the dimension D (2 or 3) and FIELD (0, or 1 for field mode), and built
 * three times by thin wrappers with constant arguments (predict_2d, predict_3d, predict_2f,
 * refresh_batch_2d, refresh_batch_3d, run_2d, run_3d, run_2f), so the compiler keeps D and FIELD
 * as constants in every inner loop and drops what a build does not need. Where the hot loop
 * calls another such function it calls the build of its own kind (predict_v, refresh_batch_v). */
#include "internal.h"

#define REFRESH_BATCH 128 /* candidates gathered before they are tested */

/* Loops over the axes, unrolled: at -O2 gcc keeps them as loops, and their control then costs
 * as much as the arithmetic in the pair test (callgrind). D is the function's constant. */
#define FOR_AXES(a) _Pragma("GCC unroll 3") for (int a = 0; a < D; a++)
/* two doubles in one SSE2 register (every x86-64 has SSE2; elsewhere gcc splits it) */
typedef double v2d __attribute__((vector_size(16)));
typedef long long v2i __attribute__((vector_size(16))); /* lane masks of v2d comparisons */

/* Move particle p along its flight line (field mode: parabola) to time t. */
static inline __attribute__((always_inline)) void advance(const mote_ev *ev, mote_particle *p,
                                                           double t, const int D, const int FIELD)
{
    double dt = t - p->t;
    if (FIELD) {
        const double *g = ev->field->g;
        FOR_AXES(a) {
            p->r[a] += (p->v[a] + 0.5 * g[a] * dt) * dt;
            p->v[a] += g[a] * dt;
        }
    } else {
        FOR_AXES(a)
            p->r[a] += p->v[a] * dt;
    }
    p->t = t;
}

/* Time from p's local time until p is nbr_reach away from its list reference: the larger root
 * of |d + v t|^2 = reach^2, written so that it keeps its precision for either sign of d.v. The
 * stored position may predate the reference (a list expiry does not move the particle), so it
 * may lie outside the reach, on the line through it; a negative result (rounding) means now. */
static inline __attribute__((always_inline)) double list_expiry(const mote_ev *ev,
                                                                 const mote_particle *p,
                                                                 const double r_ref[3],
                                                                 const int D, const int FIELD)
{
    if (FIELD) {
        /* a bound from the clock on (the stored position may predate the reference): with d
         * and v the offset from the reference and the velocity now, |d + v t + g t^2/2| <=
         * |d| + |v| t + |g| t^2/2, which reaches nbr_reach first */
        const double *g = ev->field->g, tau0 = ev->clock - p->t;
        double d2 = 0, v2 = 0, g2 = 0;
        FOR_AXES(k) {
            double vk = p->v[k] + g[k] * tau0;
            double d = p->r[k] + (p->v[k] + 0.5 * g[k] * tau0) * tau0 - r_ref[k];
            d2 += d * d;
            v2 += vk * vk;
            g2 += g[k] * g[k];
        }
        double rest = ev->nbr_reach - sqrt(d2), v = sqrt(v2), hg = 0.5 * sqrt(g2);
        if (!(rest > 0))
            return tau0;
        if (hg == 0)
            return v > 0 ? tau0 + rest / v : INFINITY;
        return tau0 + 2 * rest / (v + sqrt(v * v + 4 * hg * rest)); /* hg t^2 + v t = rest */
    }
    double b = 0, a = 0, d2 = 0;
    FOR_AXES(k) {
        double d = p->r[k] - r_ref[k];
        b += d * p->v[k];
        a += p->v[k] * p->v[k];
        d2 += d * d;
    }
    if (a == 0)
        return INFINITY;
    double c = d2 - ev->nbr_reach * ev->nbr_reach;
    double disc = b * b - a * c;
    if (disc < 0)
        disc = 0;
    /* select the operands, not the code path: the sign of b is a coin toss for the predictor */
    const double q = sqrt(disc);
    const double num = b > 0 ? -c : q - b, den = b > 0 ? b + q : a;
    return num / den;
}

/* The earliest collision of i with a listed neighbour, if earlier than *best (absolute time);
 * updates *best, *partner and *pcount. POLY: per-particle radii; MINIMG: minimum images on the
 * axes named by i's MOTE_EV_WRAP_X bits (only needed near a periodic face, see ref_flags).
 * The constant flags let the compiler drop what a case does not need.
 *
 * Each pair is solved from the later of the two local times, t0, not from the clock: both fly
 * straight from t0 on, and after a collision (the common case) t0 is the clock anyway. A list
 * expiry thus re-predicts exactly what was predicted before it, without extra rounding. */
/* What scan_pairs keeps for particle i while it looks at its neighbours: its position and
 * velocity at its local time ti (x and y also in one SSE2 register), and the minimum image's
 * half lengths and lengths without branches (an axis without its wrap bit gets an infinite
 * half length, so its shift is always zero: the shift is +len, -len or +0, and subtracting +0
 * changes no value). */
typedef struct {
    double ri[3], vi[3], half[3], len[3], now, ti;
    unsigned wrap;
    v2d rixy, vixy, hxy, lxy, hz, lz, nhxy, nlxy, nhz, nlz;
} pair_frame;

/* The pair i, j (pj) from the later of the two local times t0: the relative velocity dv, b = dr
 * . dv and |dr|^2 with the minimum image chosen at the clock. */
static inline __attribute__((always_inline)) void
pair_relative(const mote_ev *ev, const pair_frame *f, const mote_particle *pj, const int minimg,
              double dv[3], double *pb_out, double *dr2_out, double *t0_out, const int D,
              const int FIELD)
{
    const double *ri = f->ri, *vi = f->vi, ti = f->ti, tj = pj->t;
    double b = 0, dr2 = 0, t0;
    if (!FIELD && D == 3) {
        /* straight flights with x and y in one SSE2 register: the same operations in the same
         * order as the scalar code of the 2D and field builds below */
        v2d rj, vj, pb, pr;
        memcpy(&rj, pj->r, sizeof rj);
        memcpy(&vj, pj->v, sizeof vj);
        double dz, vz = vi[2] - pj->v[2];
        v2d dvxy = f->vixy - vj, drxy;
        if (tj <= ti) {
            const double dtj = ti - tj;
            t0 = ti;
            drxy = f->rixy - (rj + vj * dtj);
            dz = ri[2] - (pj->r[2] + pj->v[2] * dtj);
        } else {
            const double dti = tj - ti;
            t0 = tj;
            drxy = (f->rixy + f->vixy * dti) - rj;
            dz = (ri[2] + vi[2] * dti) - pj->r[2];
        }
        if (minimg) { /* as in the scalar code below, with lane masks (z in a lane of its own) */
            const double tn = f->now - t0;
            const v2d dn = drxy + dvxy * tn;
            const v2i up = dn > f->hxy, down = dn < f->nhxy;
            drxy -= (v2d)(((v2i)f->lxy & up) | ((v2i)f->nlxy & down));
            const double dzn = dz + vz * tn;
            const v2d dz2 = {dzn, dzn};
            const v2i zup = dz2 > f->hz, zdown = dz2 < f->nhz;
            dz -= ((v2d)(((v2i)f->lz & zup) | ((v2i)f->nlz & zdown)))[0];
        }
        pb = drxy * dvxy;
        pr = drxy * drxy;
        b = (pb[0] + pb[1]) + dz * vz;
        dr2 = (pr[0] + pr[1]) + dz * dz;
        dv[0] = dvxy[0];
        dv[1] = dvxy[1];
        dv[2] = vz;
    } else {
        double dr[3];
        if (FIELD) {
            /* both in the same field: bring the earlier one to the later local time along its
             * parabola; from there the relative motion is straight */
            const double *g = ev->field->g;
            if (tj <= ti) {
                const double dtj = ti - tj;
                t0 = ti;
                FOR_AXES(a) {
                    dr[a] = ri[a] - (pj->r[a] + (pj->v[a] + 0.5 * g[a] * dtj) * dtj);
                    dv[a] = vi[a] - (pj->v[a] + g[a] * dtj);
                }
            } else {
                const double dti = tj - ti;
                t0 = tj;
                FOR_AXES(a) {
                    dr[a] = (ri[a] + (vi[a] + 0.5 * g[a] * dti) * dti) - pj->r[a];
                    dv[a] = (vi[a] + g[a] * dti) - pj->v[a];
                }
            }
        } else {
            if (tj <= ti) {
                const double dtj = ti - tj;
                t0 = ti;
                FOR_AXES(a)
                    dr[a] = ri[a] - (pj->r[a] + pj->v[a] * dtj);
            } else {
                const double dti = tj - ti;
                t0 = tj;
                FOR_AXES(a)
                    dr[a] = (ri[a] + vi[a] * dti) - pj->r[a];
            }
            FOR_AXES(a)
                dv[a] = vi[a] - pj->v[a];
        }
        if (minimg) {
            /* the image is chosen at the clock, where both lists are valid and so the pair's
             * minimum image is the one it can touch through; t0 may be long before */
            const double tn = f->now - t0;
            FOR_AXES(a) {
                if (!(f->wrap >> a & 1u))
                    continue;
                double dn = dr[a] + dv[a] * tn;
                if (dn > f->half[a])
                    dr[a] -= f->len[a];
                else if (dn < -f->half[a])
                    dr[a] += f->len[a];
            }
        }
        FOR_AXES(a) {
            b += dr[a] * dv[a];
            dr2 += dr[a] * dr[a];
        }
    }
    *pb_out = b;
    *dr2_out = dr2;
    *t0_out = t0;
}

static inline __attribute__((always_inline)) int
scan_pairs(const mote_ev *ev, uint32_t i, const int poly, const int minimg, double *best,
           uint32_t *partner, uint32_t *pcount, const int D, const int FIELD)
{
    const mote_particle *P = ev->p;
    const mote_particle *pi = &P[i];
    const uint32_t *L = ev->nbr + (size_t)i * ev->nbr_cap;
    const uint32_t nn = pi->nnbr;
    pair_frame f;
    f.now = ev->clock;
    f.ti = pi->t;
    f.wrap = pi->flags / MOTE_EV_WRAP_X; /* bit a: minimum image along a */
    const double now = f.now;
    FOR_AXES(a) {
        f.ri[a] = pi->r[a];
        f.vi[a] = pi->v[a];
        f.len[a] = ev->len[a];
        f.half[a] = 0.5 * ev->len[a];
    }
    for (int a = D; a < 3; a++)
        f.ri[a] = f.vi[a] = f.len[a] = f.half[a] = 0;
    const double *vi = f.vi;
    const double Ri = poly ? ev->radius[i] : ev->radius0;
    const double sig_mono = 2 * ev->radius0, sig2_mono = sig_mono * sig_mono;
    /* the 3D build of hard particles pairs x and y in SSE2 registers (pair_relative) */
    f.rixy = (v2d){f.ri[0], f.ri[1]};
    f.vixy = (v2d){f.vi[0], f.vi[1]};
    f.hxy = (v2d){INFINITY, INFINITY};
    f.lxy = (v2d){0, 0};
    f.hz = (v2d){INFINITY, INFINITY};
    f.lz = (v2d){0, 0};
    if (minimg) { /* chosen by index, not by branch: which axes wrap is a coin toss too */
        const unsigned wrap = f.wrap;
        const double hx[2] = {INFINITY, f.half[0]}, hy[2] = {INFINITY, f.half[1]},
                     hzz[2] = {INFINITY, f.half[2]}, lx[2] = {0, f.len[0]}, ly[2] = {0, f.len[1]},
                     lzz[2] = {0, f.len[2]};
        f.hxy = (v2d){hx[wrap & 1u], hy[wrap >> 1 & 1u]};
        f.lxy = (v2d){lx[wrap & 1u], ly[wrap >> 1 & 1u]};
        f.hz = (v2d){hzz[wrap >> 2 & 1u], hzz[wrap >> 2 & 1u]};
        f.lz = (v2d){lzz[wrap >> 2 & 1u], lzz[wrap >> 2 & 1u]};
    }
    f.nlxy = -f.lxy;
    f.nhxy = -f.hxy;
    f.nlz = -f.lz;
    f.nhz = -f.hz;
    int found = 0;
    /* in large systems each neighbour's record is a cache miss: ask for the next ones early,
     * PREFETCH_AHEAD entries ahead, in one loop without a bounds test (past the end of the
     * list, the array is padded and holds stale entries: see prefetch_record) */
    _Pragma("GCC unroll 4") for (uint32_t k = 0; k < PREFETCH_AHEAD; k++)
        prefetch_record(P, L[k]);
    for (uint32_t k = 0; k < nn; k++) {
        prefetch_record(P, L[k + PREFETCH_AHEAD]);
        const uint32_t j = L[k];
        const mote_particle *pj = &P[j];
        double dv[3], b, dr2, t0;
        pair_relative(ev, &f, pj, minimg, dv, &b, &dr2, &t0, D, FIELD);
        double sig2 = sig2_mono;
        if (poly) {
            double sig = Ri + ev->radius[j];
            sig2 = sig * sig;
        }
        const double c = dr2 - sig2;
        /* One test, mostly failing, instead of two unpredictable ones: the pair must approach
         * (b < 0), and since c + 2 b t + |dv|^2 t^2 = 0 at contact, contact is no earlier than
         * c / (-2b), which must not be later than the best so far. Touching pairs (c <= 0) pass
         * whenever they approach. */
        if (!((b < 0) & (c <= -2 * b * (*best - t0))))
            continue;
        double dt = 0; /* touching, or overlapping by rounding, and approaching */
        if (c > 0) {
            double dv2 = 0;
            FOR_AXES(a)
                dv2 += dv[a] * dv[a];
            double disc = b * b - dv2 * c;
            if (disc <= 0)
                continue;
            dt = c / (-b + sqrt(disc));
        } else {
            /* A pair in contact that approaches by less than the rounding of its speeds was left
             * so by a collision whose change of velocity fell below an ulp (an inelastic one at
             * 10^4 m/s): colliding it again changes nothing and would repeat for ever at this
             * instant. It is not approaching. (|b| <= 1e-12 |dr| |v|; rounding leaves 1e-16.) */
            double s2 = 0;
            FOR_AXES(a)
                s2 += vi[a] * vi[a] + pj->v[a] * pj->v[a];
            if (b * b <= 1e-24 * dr2 * s2)
                continue;
        }
        double t = t0 + dt;
        if (t < now)
            t = now; /* never before the clock (rounding of a pair already touching) */
        if (t < *best) {
            *best = t;
            *partner = j;
            *pcount = pj->count;
            found = 1;
        }
    }
    return found;
}

/* ---- field mode: walls, faces and corners under a uniform field (field.inc: the same unit,
 * its own file) ------------------------------------------------------------------------------ */
#include "field.inc"

/* Predict the earliest event of particle i from the current clock and store it in p[i].
 * Candidates: its list expiry, the walls it can reach before that (reference within half a
 * shell of a contact plane), and its listed neighbours. Times are solved from the particle's
 * local time (see scan_pairs) and never earlier than the clock. */
static inline __attribute__((always_inline)) void predict(mote_ev *ev, uint32_t i, const int D,
                                                           const int FIELD)
{
    mote_particle *pi = &ev->p[i];
    mote_ev_cold *ci = &ev->pc[i];
    const double now = ev->clock, ti = pi->t;
    double best = ti + list_expiry(ev, pi, ci->r_ref, D, FIELD);
    if (best < now)
        best = now;
    uint32_t kind = MOTE_EV_NBR, partner = 0, pcount = 0;

    if (FIELD) {
        predict_field(ev, i, &best, &kind, &partner);
    } else if (pi->flags & MOTE_EV_NEAR_WALL) {
        const double Ri = mote_ev_radius(ev, i), reach = 0.5 * ev->shell;
        FOR_AXES(a) {
            if (ev->periodic[a])
                continue;
            double v = pi->v[a], dt;
            uint32_t code;
            if (v < 0 && ci->r_ref[a] - Ri <= reach) {
                dt = (Ri - pi->r[a]) / v;
                code = (uint32_t)(2 * a);
            } else if (v > 0 && ev->len[a] - Ri - ci->r_ref[a] <= reach) {
                dt = (ev->len[a] - Ri - pi->r[a]) / v;
                code = (uint32_t)(2 * a + 1);
            } else {
                continue;
            }
            double t = ti + dt;
            if (t < now)
                t = now;
            if (t < best) {
                best = t;
                kind = MOTE_EV_WALL;
                partner = code;
            }
        }
    }

    int pair;
    if (ev->radius)
        pair = (pi->flags & MOTE_EV_EDGE) ? scan_pairs(ev, i, 1, 1, &best, &partner, &pcount, D, FIELD)
                             : scan_pairs(ev, i, 1, 0, &best, &partner, &pcount, D, FIELD);
    else
        pair = (pi->flags & MOTE_EV_EDGE) ? scan_pairs(ev, i, 0, 1, &best, &partner, &pcount, D, FIELD)
                             : scan_pairs(ev, i, 0, 0, &best, &partner, &pcount, D, FIELD);
    if (pair)
        kind = MOTE_EV_PAIR;
    ci->t_ev = best;
    pi->kind = (uint8_t)kind;
    ci->partner = partner;
    ci->partner_count = pcount;
}

/* The three builds of predict, and the choice among them where the build is a constant. */
static void predict_2d(mote_ev *ev, uint32_t i) { predict(ev, i, 2, 0); }
static void predict_3d(mote_ev *ev, uint32_t i) { predict(ev, i, 3, 0); }
static void predict_2f(mote_ev *ev, uint32_t i) { predict(ev, i, 2, 1); }

static inline __attribute__((always_inline)) void predict_v(mote_ev *ev, uint32_t i, const int D,
                                                             const int FIELD)
{
    if (FIELD)
        predict_2f(ev, i);
    else if (D == 3)
        predict_3d(ev, i);
    else
        predict_2d(ev, i);
}

/* The candidates cand[0..n) for i's new list (reference x): those within sigma_ij + shell
 * (minimum image along the axes whose bit is set in `edge`) join the new list being built in
 * ev->nbr_new (*nnew entries). A marked one was a neighbour before and stays in i's list: its
 * mark is cleared and its own list is left alone; i joins the lists of the others. POLY and
 * WRAP (edge != 0) are constants in each copy (see refresh_batch), so the common case, equal
 * radii far from periodic faces, tests a candidate without either branch. */
static inline __attribute__((always_inline)) int
refresh_test(mote_ev *ev, uint32_t i, const double x[3], unsigned edge, uint32_t *cand, uint32_t n,
             uint32_t *nnew, const int poly, const int wrap, const int D)
{
    mote_particle *P = ev->p;
    mote_ev_cold *C = ev->pc;
    double half[3] = {0, 0, 0}, len[3] = {0, 0, 0};
    FOR_AXES(a) {
        len[a] = ev->len[a];
        half[a] = 0.5 * len[a];
    }
    const double cut_mono = 2 * ev->radius0 + ev->shell, cut2_mono = cut_mono * cut_mono;
    const v2d xxy = {x[0], x[1]}; /* (3D) */
    uint32_t in = 0;
    for (uint32_t k = 0; k < n; k++) {
        const uint32_t j = cand[k];
        double d2 = 0;
        if (D == 3 && !wrap) {
            /* x and y in one SSE2 register: the same operations in the same order as the loop
             * below, so the same result */
            v2d dxy;
            memcpy(&dxy, C[j].r_ref, sizeof dxy);
            dxy = xxy - dxy;
            dxy = dxy * dxy;
            const double dz = x[2] - C[j].r_ref[2];
            d2 = (dxy[0] + dxy[1]) + dz * dz;
        } else {
            FOR_AXES(a) {
                double d = x[a] - C[j].r_ref[a];
                if (wrap && (edge >> a & 1u)) {
                    if (d > half[a])
                        d -= len[a];
                    else if (d < -half[a])
                        d += len[a];
                }
                d2 += d * d;
            }
        }
        double cut2 = cut2_mono;
        if (poly) {
            double c = ev->radius[i] + ev->radius[j] + ev->shell;
            cut2 = c * c;
        }
        /* compacted in place (k >= in) without a branch: about one candidate in five is in,
         * at random (i itself never is: see refresh) */
        cand[in] = j;
        in += (uint32_t)(d2 < cut2);
    }
    for (uint32_t k = 0; k < in; k++)
        __builtin_prefetch(&P[cand[k]].nnbr, 1);
    for (uint32_t k = 0; k < in; k++) {
        const uint32_t j = cand[k];
        if (*nnew >= ev->nbr_cap && ev_nbr_grow(ev))
            return MOTE_ENOMEM;
        if (P[j].flags & MOTE_EV_MARK)
            P[j].flags &= (uint8_t)~MOTE_EV_MARK;
        else if (nbr_push(ev, j, i))
            return MOTE_ENOMEM;
        ev->nbr_new[(*nnew)++] = j; /* (on failure the lists stay symmetric) */
    }
    return MOTE_OK;
}

static inline __attribute__((always_inline)) int
refresh_batch(mote_ev *ev, uint32_t i, const double x[3], unsigned edge, uint32_t *cand, uint32_t n,
              uint32_t *nnew, const int D)
{
    _Pragma("GCC unroll 4") for (uint32_t k = 0; k < n; k++)
        __builtin_prefetch(&ev->pc[cand[k]].r_ref);
    if (ev->radius)
        return edge ? refresh_test(ev, i, x, edge, cand, n, nnew, 1, 1, D)
                    : refresh_test(ev, i, x, edge, cand, n, nnew, 1, 0, D);
    return edge ? refresh_test(ev, i, x, edge, cand, n, nnew, 0, 1, D)
                : refresh_test(ev, i, x, edge, cand, n, nnew, 0, 0, D);
}

/* The builds of refresh_batch (field mode shares the 2D one: a batch's test knows no field). */
static int refresh_batch_2d(mote_ev *ev, uint32_t i, const double x[3], unsigned edge,
                            uint32_t *cand, uint32_t n, uint32_t *nnew)
{
    return refresh_batch(ev, i, x, edge, cand, n, nnew, 2);
}
static int refresh_batch_3d(mote_ev *ev, uint32_t i, const double x[3], unsigned edge,
                            uint32_t *cand, uint32_t n, uint32_t *nnew)
{
    return refresh_batch(ev, i, x, edge, cand, n, nnew, 3);
}

static inline __attribute__((always_inline)) int
refresh_batch_v(mote_ev *ev, uint32_t i, const double x[3], unsigned edge, uint32_t *cand,
                uint32_t n, uint32_t *nnew, const int D, const int FIELD)
{
    (void)FIELD;
    return D == 3 ? refresh_batch_3d(ev, i, x, edge, cand, n, nnew)
                  : refresh_batch_2d(ev, i, x, edge, cand, n, nnew);
}

/* List expiry of i: take its position at the clock as the new reference (wrapped into the box
 * on periodic axes), move cells, and collect every particle whose reference lies within
 * sigma_ij + shell into i's new list. Most of them were neighbours before: the old neighbours
 * are marked first, and only the lists of those that join (i is added) or leave (i is removed)
 * change. The stored position and local time stay as they are (a wrap shifts the stored
 * position by the period): an expiry changes no trajectory, so it should not add rounding to
 * one either. */
static inline __attribute__((always_inline)) int refresh(mote_ev *ev, uint32_t i, const int D,
                                                          const int FIELD)
{
    mote_particle *P = ev->p;
    mote_particle *p = &P[i];
    mote_ev_cold *cp = &ev->pc[i];
    const double dt = ev->clock - p->t;
    double x[3] = {0, 0, 0};
    FOR_AXES(a) {
        if (FIELD)
            x[a] = p->r[a] + (p->v[a] + 0.5 * ev->field->g[a] * dt) * dt;
        else
            x[a] = p->r[a] + p->v[a] * dt;
        if (ev->periodic[a]) {
            while (x[a] < 0) {
                x[a] += ev->len[a];
                p->r[a] += ev->len[a];
            }
            while (x[a] >= ev->len[a]) {
                x[a] -= ev->len[a];
                p->r[a] -= ev->len[a];
            }
        }
        cp->r_ref[a] = x[a];
    }
    /* mark the old neighbours (their records are fetched all at once first) */
    const uint32_t nold = p->nnbr;
    {
        const uint32_t *Li = nbr_list(ev, i);
        for (uint32_t k = 0; k < nold; k++)
            __builtin_prefetch(&P[Li[k]].nnbr, 1);
        for (uint32_t k = 0; k < nold; k++)
            P[Li[k]].flags |= MOTE_EV_MARK;
    }
    p->flags = ref_flags(ev, i, x);
    const unsigned edge = p->flags / MOTE_EV_WRAP_X; /* bit a: minimum image along a */

    /* cell coordinates, the cell, and the range of neighbouring cells per axis */
    int kc[3] = {0, 0, 0}, lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, nc[3] = {1, 1, 1};
    FOR_AXES(a) {
        nc[a] = ev->ncell[a];
        double f = (x[a] - ev->cell_lo[a]) / ev->cell_w[a];
        int k = f > 0 ? (int)f : 0;
        kc[a] = k < nc[a] ? k : nc[a] - 1;
        if (nc[a] < 3) { /* -1 and +1 would name one cell twice: take each once */
            lo[a] = -kc[a];
            hi[a] = nc[a] - 1 - kc[a];
        } else {
            lo[a] = ev->periodic[a] || kc[a] > 0 ? -1 : 0;
            hi[a] = ev->periodic[a] || kc[a] < nc[a] - 1 ? 1 : 0;
        }
    }
    int32_t cell = (kc[2] * nc[1] + kc[1]) * nc[0] + kc[0];
    if (cell != cp->cell && cell_move(ev, i, cell))
        return MOTE_ENOMEM;

    /* squared gap from x to the neighbouring cells' slabs along each axis (index offset + 1):
     * a cell whose nearest point is beyond the largest cutoff holds no neighbour and is skipped
     * (mostly corners) */
    double gap2[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    FOR_AXES(a) {
        if (nc[a] >= 3) {
            double flo = ev->cell_lo[a] + kc[a] * ev->cell_w[a];
            double dlo = x[a] - flo, dhi = flo + ev->cell_w[a] - x[a];
            gap2[a][0] = dlo > 0 ? dlo * dlo : 0;
            gap2[a][2] = dhi > 0 ? dhi * dhi : 0;
        }
    }
    const double reach_max = ev->sigma_max + ev->shell, reach2_max = reach_max * reach_max;
    /* the neighbouring cells' coordinates per axis, wrapped on periodic axes (index offset + 1) */
    int32_t wc[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    FOR_AXES(a) {
        for (int o = lo[a]; o <= hi[a]; o++) {
            int k = kc[a] + o;
            wc[a][o + 1] = k < 0 ? k + nc[a] : k >= nc[a] ? k - nc[a] : k;
        }
    }
    int32_t cells[27];
    int ncells = 0;
    for (int oz = lo[2]; oz <= hi[2]; oz++) {
        const double gz = D == 3 ? gap2[2][oz + 1] : 0;
        const int32_t plane = D == 3 ? wc[2][oz + 1] * nc[1] : 0;
        for (int oy = lo[1]; oy <= hi[1]; oy++) {
            const double gyz = gz + gap2[1][oy + 1];
            if (gyz >= reach2_max)
                continue;
            const int32_t row = (plane + wc[1][oy + 1]) * nc[0];
            for (int ox = lo[0]; ox <= hi[0]; ox++) {
                if (gyz + gap2[0][ox + 1] >= reach2_max)
                    continue;
                cells[ncells++] = row + wc[0][ox + 1];
                __builtin_prefetch(cell_members(ev, row + wc[0][ox + 1]));
            }
        }
    }
    /* the candidates, in batches: gather them (asking for their references), then test them
     * (asking for the records and lists of those that are in), then add the pairs */
    uint32_t cand[REFRESH_BATCH];
    uint32_t ncand = 0, nnew = 0;
    /* i is a candidate too (its own cell): meanwhile an infinite reference keeps it out of its
     * own list, without a test per candidate */
    cp->r_ref[0] = INFINITY;
    int rc = MOTE_OK;
    /* a cell of up to GATHER_WORDS members (nearly all) is copied as a fixed block, without a
     * loop whose length changes from cell to cell; the words past its count (the next block,
     * or the padding after the last) are ignored */
    for (int q = 0; q < ncells && !rc; q++) {
        const uint32_t *B = cell_members(ev, cells[q]);
        const uint32_t m = B[0];
        if (m <= GATHER_WORDS) {
            if (ncand + GATHER_WORDS > REFRESH_BATCH) {
                rc = refresh_batch_v(ev, i, x, edge, cand, ncand, &nnew, D, FIELD);
                ncand = 0;
            }
            memcpy(cand + ncand, B + 1, GATHER_WORDS * sizeof *cand);
            ncand += m;
            continue;
        }
        /* a crowded cell, one member at a time; the batch may already be full (a block can
         * fill it exactly), so it is tested before each member is added, not after */
        for (uint32_t s = 1; s <= m && !rc; s++) {
            if (ncand == REFRESH_BATCH) {
                rc = refresh_batch_v(ev, i, x, edge, cand, ncand, &nnew, D, FIELD);
                ncand = 0;
                if (rc)
                    break;
            }
            cand[ncand++] = B[s];
        }
    }
    if (!rc && ncand)
        rc = refresh_batch_v(ev, i, x, edge, cand, ncand, &nnew, D, FIELD);
    cp->r_ref[0] = x[0];
    nbr_renewed(ev, i, nold, nnew);
    return rc;
}

/* A pair collision in field mode: the model's rule sets the velocities (elastic without one).
 * dr = r_i - r_j at contact, b = dr . (v_i - v_j) < 0. The observer gets the impulse on i. */
static void field_pair(mote_ev *ev, uint32_t i, uint32_t j, const double dr[3], double b,
                       double dr2, double te, int has_obs_pair)
{
    const mote_ev_rules *R = &ev->field->rules;
    mote_particle *pi = &ev->p[i], *pj = &ev->p[j];
    const double mi = mote_ev_mass(ev, i), vi0[2] = {pi->v[0], pi->v[1]};
    if (R->pair) {
        R->pair(R->ctx, ev->pc[i].label, ev->pc[j].label, dr, pi->v, pj->v, ev->time_total + te);
    } else {
        double mj = mote_ev_mass(ev, j), k = -2.0 * mi * mj / (mi + mj) * b / dr2;
        for (int a = 0; a < 2; a++) {
            pi->v[a] += k * dr[a] / mi;
            pj->v[a] -= k * dr[a] / mj;
        }
    }
    if (has_obs_pair) {
        double J[3] = {mi * (pi->v[0] - vi0[0]), mi * (pi->v[1] - vi0[1]), 0};
        ev->obs.on_pair(ev->obs.ctx, i, j, dr, J, te);
    }
}

/* The events of the loop (run), each its own function, inlined into every build of it. */
#define EV_INLINE static inline __attribute__((always_inline))

/* A pair collision of i with its partner at te, or, when the partner changed course since the
 * prediction, the prediction renewed (a stale event). */
EV_INLINE void pair_event(mote_ev *ev, mote_particle *P, mote_ev_cold *C, uint32_t i, double te,
                          const int D, const int FIELD, const int has_obs_pair,
                          const int has_obs_event, uint64_t *since_pair)
{
    mote_particle *pi = &P[i];
    mote_ev_cold *ci = &C[i];
    uint32_t j = ci->partner;
    mote_particle *pj = &P[j];
    advance(ev, pi, te, D, FIELD);
    if (pj->count != ci->partner_count) { /* j changed course: stale */
        ev->stale_events++;
        predict_v(ev, i, D, FIELD);
        cal_insert(ev, i);
        return;
    }
    advance(ev, pj, te, D, FIELD);
    double dr[3] = {0, 0, 0}, dv[3] = {0, 0, 0}, b = 0, dr2 = 0;
    FOR_AXES(a) {
        double d = pi->r[a] - pj->r[a];
        if (ev->periodic[a]) {
            double half = 0.5 * ev->len[a];
            if (d > half)
                d -= ev->len[a];
            else if (d < -half)
                d += ev->len[a];
        }
        dr[a] = d;
        dv[a] = pi->v[a] - pj->v[a];
        b += d * dv[a];
        dr2 += d * d;
    }
    if (FIELD) {
        field_pair(ev, i, j, dr, b, dr2, te, has_obs_pair);
    } else if (ev->mass) {
        double mi = ev->mass[i], mj = ev->mass[j];
        double f = -2.0 * mi * mj / (mi + mj) * b / dr2; /* J = f r */
        double J[3] = {0, 0, 0};
        FOR_AXES(a) {
            J[a] = f * dr[a];
            pi->v[a] += J[a] / mi;
            pj->v[a] -= J[a] / mj;
        }
        if (has_obs_pair)
            ev->obs.on_pair(ev->obs.ctx, i, j, dr, J, te);
    } else {
        double f = b / dr2;
        FOR_AXES(a) {
            pi->v[a] -= f * dr[a];
            pj->v[a] += f * dr[a];
        }
        if (has_obs_pair) {
            double J[3] = {0, 0, 0};
            FOR_AXES(a)
                J[a] = -ev->mass0 * f * dr[a];
            ev->obs.on_pair(ev->obs.ctx, i, j, dr, J, te);
        }
    }
    pi->count++;
    pj->count++;
    ev->collisions++;
    *since_pair = 0;
    cal_remove(ev, j);
    { /* ask for j's neighbours now: they arrive while i's are scanned */
        const uint32_t *Lj = nbr_list(ev, j);
        for (uint32_t k = 0; k < pj->nnbr; k++)
            __builtin_prefetch(&P[Lj[k]]);
    }
    predict_v(ev, i, D, FIELD);
    cal_insert(ev, i);
    predict_v(ev, j, D, FIELD);
    cal_insert(ev, j);
    if (has_obs_event) {
        ev->obs.on_event(ev->obs.ctx, i);
        ev->obs.on_event(ev->obs.ctx, j);
    }
}

/* A wall collision of i at te: the wall's rule (a reflection without a field). */
EV_INLINE void wall_event(mote_ev *ev, mote_particle *P, mote_ev_cold *C, uint32_t i, double te,
                          const int D, const int FIELD, const int has_obs_wall,
                          const int has_obs_event)
{
    mote_particle *pi = &P[i];
    mote_ev_cold *ci = &C[i];
    int a = (int)(ci->partner >> 1), side = (int)(ci->partner & 1);
    advance(ev, pi, te, D, FIELD);
    double m = mote_ev_mass(ev, i);
    double mom = 2.0 * m * fabs(pi->v[a]);
    if (!FIELD) {
        pi->v[a] = -pi->v[a];
    } else if (ev->field->rules.wall) {
        ev->field->rules.wall(ev->field->rules.ctx, ci->label, a, side, pi->v,
                              ev->time_total + te);
    } else if (side ? pi->v[a] > 0 : pi->v[a] < 0) {
        /* reflect only a particle moving into the wall (rounding can put one that
         * just left it here) */
        pi->v[a] = -pi->v[a];
    }
    pi->count++;
    ev->wall_collisions++;
    if (has_obs_wall)
        ev->obs.on_wall(ev->obs.ctx, i, a, side, mom, te);
    predict_v(ev, i, D, FIELD);
    cal_insert(ev, i);
    if (has_obs_event)
        ev->obs.on_event(ev->obs.ctx, i);
}

/* i meets an obstacle's face or corner at te (field mode only). */
EV_INLINE int obstacle_event(mote_ev *ev, mote_particle *P, mote_ev_cold *C, uint32_t i,
                             double te, mote_err *err, const int D, const int FIELD,
                             const int has_obs_event)
{
    mote_particle *pi = &P[i];
    mote_ev_cold *ci = &C[i];
    if (!FIELD) { /* never scheduled without a field */
        cal_insert(ev, i);
        return mote_fail(err, MOTE_ERUNTIME, "internal: particle %u has an obstacle event",
                         i);
    }
    advance(ev, pi, te, D, FIELD);
    double n[2];
    if (pi->kind == MOTE_EV_SEG) {
        const mote_ev_segment *sk = &ev->field->seg[ci->partner];
        n[0] = sk->n[0];
        n[1] = sk->n[1];
    } else {
        const double *cc = ev->field->corner[ci->partner];
        double dx = pi->r[0] - cc[0], dy = pi->r[1] - cc[1], d = sqrt(dx * dx + dy * dy);
        n[0] = dx / d;
        n[1] = dy / d;
    }
    double vn = pi->v[0] * n[0] + pi->v[1] * n[1];
    if (vn < 0) { /* moving in (rounding can put one that just left it here) */
        const mote_ev_rules *R = &ev->field->rules;
        int changed = 1;
        if (R->face) {
            changed = R->face(R->ctx, ci->label, pi->kind, ci->partner, n, pi->v,
                              ev->time_total + te);
        } else {
            pi->v[0] -= 2 * vn * n[0];
            pi->v[1] -= 2 * vn * n[1];
        }
        if (changed)
            pi->count++;
    }
    predict_v(ev, i, D, FIELD);
    cal_insert(ev, i);
    if (has_obs_event)
        ev->obs.on_event(ev->obs.ctx, i);
    return MOTE_OK;
}

/* i's neighbour list renewed (it moved half the shell from its reference). */
EV_INLINE int nbr_event(mote_ev *ev, uint32_t i, mote_err *err, const int D, const int FIELD,
                        const int has_obs_event)
{
    ev->renewals++;
    if (refresh(ev, i, D, FIELD)) {
        cal_insert(ev, i); /* keep the calendar whole for the caller */
        return mote_fail(err, MOTE_ENOMEM, "out of memory growing the neighbour lists");
    }
    predict_v(ev, i, D, FIELD);
    cal_insert(ev, i);
    if (has_obs_event)
        ev->obs.on_event(ev->obs.ctx, i);
    return MOTE_OK;
}

static inline __attribute__((always_inline)) int run(mote_ev *ev, uint64_t ncoll, double t_stop,
                                                      mote_err *err, const int D, const int FIELD)
{
    mote_particle *P = ev->p;
    mote_ev_cold *C = ev->pc;
    const uint64_t target = ev->collisions + ncoll;
    const uint64_t watchdog = 1000ull * ev->n + 1000000ull;
    uint64_t since_pair = 0;
    const int has_obs_pair = ev->obs.on_pair != NULL;
    const int has_obs_wall = ev->obs.on_wall != NULL;
    const int has_obs_event = FIELD && ev->obs.on_event != NULL; /* (field mode only) */

    while (ev->collisions < target) {
        if (FIELD && ev->halt) { /* an observer asked to stop (the run cannot finish, say) */
            ev->halt = 0;
            return MOTE_OK;
        }
        if ((ev->heap_n == 0 && ev_cal_refill(ev)) || !(ev->heap_t[0] < INFINITY)) {
            if (t_stop < INFINITY) { /* nothing happens before t_stop: just go there */
                if (t_stop - ev->time_total > ev->clock)
                    ev->clock = t_stop - ev->time_total;
                return MOTE_OK;
            }
            return mote_fail(err, MOTE_ERUNTIME,
                             "no further events can happen (all particles at rest?)");
        }
        uint32_t i = ev->heap[0];
        mote_particle *pi = &P[i];
        mote_ev_cold *ci = &C[i];
        double te = ci->t_ev;
        /* stop at t_stop (a time since creation) before any later event, unless a rebuild
         * comes first */
        const double stop_clock = t_stop - ev->time_total;
        if (te > stop_clock && stop_clock <= ev->t_rebuild) {
            if (stop_clock > ev->clock)
                ev->clock = stop_clock;
            return MOTE_OK;
        }
        if (te > ev->t_rebuild) {
            /* Right after a rebuild (clock 0) a rebuild at the clock would make the same state
             * again, forever (a dilute gas whose next event lies beyond the horizon): move
             * everyone to the horizon first, which no event precedes. Otherwise the rebuild
             * happens at the last event, as it always has. */
            if (ev->clock == 0)
                ev->clock = ev->t_rebuild;
            ev->rebuilds++;
            int rc = mote_ev_rebuild(ev, err);
            if (rc)
                return rc;
            /* events follow: the stored coordinates stop being the present ones (a save
             * after this run must synchronise again, not write them as they are) */
            ev->canonical = 0;
            P = ev->p;
            continue;
        }
        if (++since_pair > watchdog && t_stop == INFINITY) /* a timed run ends anyway */
            return mote_fail(err, MOTE_ERUNTIME,
                             "watchdog: %llu events without a pair collision",
                             (unsigned long long)watchdog);
        heap_remove_at(ev, 0);
        cal_walk(ev);
        if (ev->heap_n) { /* most often the next event: its record arrives meanwhile */
            __builtin_prefetch(&P[ev->heap[0]]);
            __builtin_prefetch(&C[ev->heap[0]].t_ev);
        }
        ev->clock = te;
        ev->events++;
        switch (pi->kind) {
        case MOTE_EV_PAIR:
            pair_event(ev, P, C, i, te, D, FIELD, has_obs_pair, has_obs_event, &since_pair);
            break;
        case MOTE_EV_WALL:
            wall_event(ev, P, C, i, te, D, FIELD, has_obs_wall, has_obs_event);
            break;
        case MOTE_EV_SEG:
        case MOTE_EV_CORNER: {
            int rc = obstacle_event(ev, P, C, i, te, err, D, FIELD, has_obs_event);
            if (rc)
                return rc;
            break;
        }
        case MOTE_EV_NBR: {
            int rc = nbr_event(ev, i, err, D, FIELD, has_obs_event);
            if (rc)
                return rc;
            break;
        }
        default:
            cal_insert(ev, i);
            return mote_fail(err, MOTE_ERUNTIME, "internal: particle %u has no event", i);
        }
    }
    return MOTE_OK;
}

/* The three builds of the event loop. */
static int run_2d(mote_ev *ev, uint64_t ncoll, double t_stop, mote_err *err)
{
    return run(ev, ncoll, t_stop, err, 2, 0);
}
static int run_3d(mote_ev *ev, uint64_t ncoll, double t_stop, mote_err *err)
{
    return run(ev, ncoll, t_stop, err, 3, 0);
}
static int run_2f(mote_ev *ev, uint64_t ncoll, double t_stop, mote_err *err)
{
    return run(ev, ncoll, t_stop, err, 2, 1);
}

void ev_predict(mote_ev *ev, uint32_t i)
{
    if (ev->field)
        predict_2f(ev, i);
    else if (ev->dim == 2)
        predict_2d(ev, i);
    else
        predict_3d(ev, i);
}


int mote_ev_run(mote_ev *ev, uint64_t ncoll, mote_err *err)
{
    if (!ev->ready)
        return not_ready(err, "run");
    if (ncoll == 0)
        return MOTE_OK;
    ev->canonical = 0;
    if (ev->field)
        return run_2f(ev, ncoll, INFINITY, err);
    return ev->dim == 2 ? run_2d(ev, ncoll, INFINITY, err) : run_3d(ev, ncoll, INFINITY, err);
}

int mote_ev_run_to(mote_ev *ev, double t_stop, uint64_t ncoll, mote_err *err)
{
    if (!ev->ready)
        return not_ready(err, "run");
    if (ncoll == 0 || !(t_stop > mote_ev_time(ev)))
        return MOTE_OK;
    if (ncoll > UINT64_MAX - ev->collisions)
        ncoll = UINT64_MAX - ev->collisions;
    ev->canonical = 0;
    if (ev->field)
        return run_2f(ev, ncoll, t_stop, err);
    return ev->dim == 2 ? run_2d(ev, ncoll, t_stop, err) : run_3d(ev, ncoll, t_stop, err);
}
