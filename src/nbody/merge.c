/* merge.c: collisions with merging (spec 5). After every accepted step, bodies that touch (closer
 * than the sum of their radii) merge, by the conservative rules of spec 5: the heavier survives
 * (equal masses: the lower index) with the sum of the masses and charges at the pair's centre of
 * mass with its velocity (momentum kept); the orbital moment of the pair about its centre of mass
 * goes into spin (L + S kept exactly); the volume is kept (Ra^3 = Ra_i^3 + Ra_k^3); the radial
 * part of the relative kinetic energy becomes heat (Galactica's eq. 11), the tangential part is
 * recorded as spin energy. The lighter body stays in the arrays, frozen, with mass, charge and
 * radius 0 and inactive, so body numbers never change. Overlapping pairs are taken in increasing
 * r / (Ra_i + Ra_k), then by index; a body merges at most once per sweep, and sweeps repeat until
 * nothing overlaps (a grown body may touch a third). The energy change of every merge, from the
 * states around it, is recorded, so E_corr = E_tot - sum dE_merge is conserved; the next step
 * restarts (no valid previous derivatives). */
#include "mote/nbody.h"

#include <tgmath.h>
#include <stdlib.h>
#include <string.h>

#include "nb.h"

typedef struct {
    mote_real ratio;
    uint32_t i, k;
} touch;

static int touch_cmp(const void *a, const void *b)
{
    const touch *x = a, *y = b;
    if (x->ratio != y->ratio)
        return x->ratio < y->ratio ? -1 : 1;
    if (x->i != y->i)
        return x->i < y->i ? -1 : 1;
    return (x->k > y->k) - (x->k < y->k);
}

/* Merge the lighter of i, k into the heavier. */
static void merge_pair(mote_nb *nb, uint32_t i, uint32_t k)
{
    uint32_t s = i, l = k; /* survivor, lost */
    if (nb->m[k] > nb->m[i] || (nb->m[k] == nb->m[i] && k < i)) {
        s = k;
        l = i;
    }
    const mote_real ms = nb->m[s], ml = nb->m[l], M = ms + ml, mu = ms * ml / M;
    mote_real *xs = nb->x + 3 * (size_t)s, *vs = nb->v + 3 * (size_t)s;
    const mote_real *xl = nb->x + 3 * (size_t)l, *vl = nb->v + 3 * (size_t)l;
    mote_real r[3], u[3];
    for (int a = 0; a < 3; a++) {
        r[a] = xl[a] - xs[a];
        u[a] = vl[a] - vs[a];
    }
    mote_real rr = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    mote_real uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    mote_real vr = rr > 0 ? (r[0] * u[0] + r[1] * u[1] + r[2] * u[2]) / rr : 0;
    /* spin: the pair's orbital moment about its centre of mass */
    nb->sp[3 * s + 0] += nb->sp[3 * l + 0] + mu * (r[1] * u[2] - r[2] * u[1]);
    nb->sp[3 * s + 1] += nb->sp[3 * l + 1] + mu * (r[2] * u[0] - r[0] * u[2]);
    nb->sp[3 * s + 2] += nb->sp[3 * l + 2] + mu * (r[0] * u[1] - r[1] * u[0]);
    mote_real heat = ms * ml * vr * vr / (2 * M); /* eq. 11 */
    nb->et[s] += nb->et[l] + heat;
    nb->e_heat += heat;
    nb->e_spin += 0.5 * mu * (uu - vr * vr);
    for (int a = 0; a < 3; a++) {
        xs[a] = (ms * xs[a] + ml * xl[a]) / M;
        vs[a] = (ms * vs[a] + ml * vl[a]) / M;
        nb->xc[3 * s + a] = nb->vc[3 * s + a] = 0;
    }
    nb->ra[s] = cbrt(nb->ra[s] * nb->ra[s] * nb->ra[s] + nb->ra[l] * nb->ra[l] * nb->ra[l]);
    nb->m[s] = M;
    nb->q[s] += nb->q[l];
    nb->m[l] = nb->q[l] = nb->ra[l] = 0;
    nb->active[l] = 0;
    nb->merges++;
}

int mote_nb_merge(mote_nb *nb, mote_err *err)
{
    uint64_t merged = 0;
    for (;;) {
        size_t nt = 0, cap = 0;
        touch *t = NULL;
        for (uint32_t i = 0; i < nb->n; i++) {
            if (!nb->active[i] || !(nb->ra[i] > 0))
                continue;
            const mote_real *xi = nb->x + 3 * (size_t)i;
            for (uint32_t k = i + 1; k < nb->n; k++) {
                if (!nb->active[k] || !(nb->ra[k] > 0))
                    continue;
                const mote_real *xk = nb->x + 3 * (size_t)k;
                mote_real d0 = xi[0] - xk[0], d1 = xi[1] - xk[1], d2 = xi[2] - xk[2];
                mote_real sum = nb->ra[i] + nb->ra[k], d2sum = d0 * d0 + d1 * d1 + d2 * d2;
                if (!(d2sum < sum * sum)) /* the common case, without a square root */
                    continue;
                mote_real d = sqrt(d2sum);
                if (!(d < sum))
                    continue;
                if (nt == cap) {
                    cap = cap ? 2 * cap : 16;
                    touch *p = realloc(t, cap * sizeof *p);
                    if (!p) {
                        free(t);
                        return mote_fail(err, MOTE_ENOMEM, "merge: out of memory");
                    }
                    t = p;
                }
                t[nt++] = (touch){d / sum, i, k};
            }
        }
        if (nt == 0) {
            free(t);
            break;
        }
        qsort(t, nt, sizeof *t, touch_cmp);
        mote_nb_monitor before, after;
        int was_ref = nb->ref_set;
        nb->ref_set = 0; /* measure without the drift */
        mote_nb_measure(nb, &before);
        uint8_t *used = calloc(nb->n, 1);
        if (!used) {
            free(t);
            nb->ref_set = was_ref;
            return mote_fail(err, MOTE_ENOMEM, "merge: out of memory");
        }
        for (size_t q = 0; q < nt; q++) {
            if (used[t[q].i] || used[t[q].k])
                continue;
            mote_real ovl = 1 - t[q].ratio;
            if (ovl > nb->max_overlap)
                nb->max_overlap = ovl;
            if (ovl > 0.1 && nb->happ > 0 && nb->happ <= nb->bt_hmin * nb->dt)
                nb->approach_warnings++; /* spec 4.7: merge accuracy not ensured */
            used[t[q].i] = used[t[q].k] = 1;
            merge_pair(nb, t[q].i, t[q].k);
            merged++;
        }
        free(used);
        free(t);
        mote_nb_measure(nb, &after);
        nb->ref_set = was_ref;
        nb->de_merge += after.etot - before.etot;
    }
    if (merged) { /* the next step restarts */
        nb->dtp = 0;
        nb->restart = 1;
        nb->hprev = 0;
    }
    return MOTE_OK;
}
