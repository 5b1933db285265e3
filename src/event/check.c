/* check.c: the invariant checker (spec 6.10) and the queries over near pairs it shares with the
 * models (the smallest gap, the list of overlaps). */
#include "internal.h"

#include <stdarg.h>
#include <stdio.h>


/* ---- invariant checker --------------------------------------------------------------------------- */

/* Visit every unordered pair (i < j by index, minimum image) whose reference positions lie in
 * neighbouring cells and whose distance at the clock is below 2 sigma_ij. Every pair closer than
 * sigma_ij + shell at the clock is visited, because no position is more than shell/2 from its
 * reference and cells are at least sigma_max + shell wide. An engine that is not ready may lack
 * its cells: then every pair is tried (slow, but only after a failed rebuild). */
typedef void (*pair_fn)(void *ctx, uint32_t i, uint32_t j, double dist, double sigma);

static void near_pair_visit(const mote_ev *ev, uint32_t i, const double ri[3], uint32_t j,
                            pair_fn fn, void *ctx)
{
    double r2 = 0, dx[3] = {0, 0, 0}, rj[3];
    project(ev, &ev->p[j], ev->clock - ev->p[j].t, rj, NULL);
    for (int a = 0; a < ev->dim; a++)
        dx[a] = ri[a] - rj[a];
    min_image(ev, dx);
    for (int a = 0; a < ev->dim; a++)
        r2 += dx[a] * dx[a];
    double sig = mote_ev_radius(ev, i) + mote_ev_radius(ev, j);
    if (r2 < 4 * sig * sig)
        fn(ctx, i, j, sqrt(r2), sig);
}

static void for_near_pairs(const mote_ev *ev, pair_fn fn, void *ctx)
{
    const mote_particle *P = ev->p;
    const mote_ev_cold *C = ev->pc;
    int32_t cells[27];
    for (uint32_t i = 0; i < ev->n; i++) {
        double ri[3];
        project(ev, &P[i], ev->clock - P[i].t, ri, NULL);
        if (!ev->ready) {
            for (uint32_t j = i + 1; j < ev->n; j++)
                near_pair_visit(ev, i, ri, j, fn, ctx);
            continue;
        }
        int nc = ev_cell_neighbours(ev, C[i].cell, cells);
        for (int q = 0; q < nc; q++) {
            const uint32_t *B = cell_members(ev, cells[q]);
            for (uint32_t s = 1; s <= B[0]; s++)
                if (B[s] > i)
                    near_pair_visit(ev, i, ri, B[s], fn, ctx);
        }
    }
}

typedef struct {
    double min_ratio;
    size_t overlaps;
    uint32_t worst_i, worst_j;
} gap_acc;

static void gap_visit(void *ctx, uint32_t i, uint32_t j, double dist, double sigma)
{
    gap_acc *g = ctx;
    double ratio = dist / sigma;
    if (ratio < g->min_ratio) {
        g->min_ratio = ratio;
        g->worst_i = i;
        g->worst_j = j;
    }
    if (ratio < 1 - 1e-10)
        g->overlaps++;
}

double mote_ev_min_gap_ratio(const mote_ev *ev, uint32_t *wi, uint32_t *wj)
{
    gap_acc g = {INFINITY, 0, 0, 0};
    for_near_pairs(ev, gap_visit, &g);
    if (wi)
        *wi = g.worst_i;
    if (wj)
        *wj = g.worst_j;
    return g.min_ratio;
}

typedef struct {
    double tol;
    uint32_t (*pairs)[2];
    size_t max, count;
} overlap_acc;

static void overlap_visit(void *ctx, uint32_t i, uint32_t j, double dist, double sigma)
{
    overlap_acc *o = ctx;
    if (dist < sigma * (1 - o->tol)) {
        if (o->count < o->max) {
            o->pairs[o->count][0] = i;
            o->pairs[o->count][1] = j;
        }
        o->count++;
    }
}

static int pair_cmp(const void *a, const void *b)
{
    const uint32_t *x = a, *y = b;
    if (x[0] != y[0])
        return x[0] < y[0] ? -1 : 1;
    return x[1] < y[1] ? -1 : (x[1] > y[1]);
}

size_t mote_ev_overlaps(const mote_ev *ev, double tol, uint32_t (*pairs)[2], size_t max)
{
    overlap_acc o = {tol, pairs, max, 0};
    for_near_pairs(ev, overlap_visit, &o);
    if (pairs)
        qsort(pairs, o.count < max ? o.count : max, sizeof *pairs, pair_cmp);
    return o.count;
}

/* Append a formatted failure to the message buffer, keeping it bounded. */
static void add_failure(mote_err *err, int *nfail, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

static void add_failure(mote_err *err, int *nfail, const char *fmt, ...)
{
    (*nfail)++;
    if (!err || *nfail > 20)
        return;
    size_t used = strlen(err->msg);
    if (used + 2 >= sizeof err->msg)
        return;
    if (used > 0) {
        err->msg[used++] = ';';
        err->msg[used++] = ' ';
        err->msg[used] = '\0';
    }
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->msg + used, sizeof err->msg - used, fmt, ap);
    va_end(ap);
}

/* Each particle: inside the walls, its reference in its cell and within half the shell, no
 * event before the clock, its cell and number consistent, its flags those of its reference. */
static void check_particles(const mote_ev *ev, mote_err *err, int *pnfail)
{
    int nfail = *pnfail;
    const int d = ev->dim;
    const mote_particle *P = ev->p;
    const mote_ev_cold *C = ev->pc;
    const double tol = 1e-10 * ev->sigma_max;
    const size_t ncells = (size_t)ev->ncell[0] * ev->ncell[1] * ev->ncell[2];
    for (uint32_t i = 0; i < ev->n; i++) {
        double r[3], moved2 = 0;
        project(ev, &P[i], ev->clock - P[i].t, r, NULL);
        double Ri = mote_ev_radius(ev, i);
        int32_t c = C[i].cell;
        int cc[3] = {c % ev->ncell[0], (c / ev->ncell[0]) % ev->ncell[1],
                     c / (ev->ncell[0] * ev->ncell[1])};
        for (int a = 0; a < d; a++) {
            if (!ev->periodic[a] &&
                (r[a] < Ri * (1 - 1e-10) || r[a] > ev->len[a] - Ri * (1 - 1e-10)))
                add_failure(err, &nfail, "particle %u at %c = %.17g is outside the walls [%g, %g]",
                            C[i].label, "xyz"[a], r[a], Ri, ev->len[a] - Ri);
            double lo = ev->cell_lo[a] + cc[a] * ev->cell_w[a];
            double hi = cc[a] + 1 == ev->ncell[a] ? ev->cell_lo[a] + ev->len_grid[a]
                                                  : lo + ev->cell_w[a];
            double x = C[i].r_ref[a];
            if (x < lo - tol || x > hi + tol)
                add_failure(err, &nfail,
                            "particle %u: reference %c = %.17g is outside its cell [%g, %g]",
                            C[i].label, "xyz"[a], x, lo, hi);
            /* the direct difference, not the minimum image: a position must be stored
             * consistently with its reference, which the edge band relies on (ref_flags) */
            moved2 += (r[a] - x) * (r[a] - x);
        }
        if (sqrt(moved2) > 0.5 * ev->shell + tol)
            add_failure(err, &nfail,
                        "particle %u is %.17g from its list reference, beyond half the shell %g",
                        C[i].label, sqrt(moved2), 0.5 * ev->shell);
        if (C[i].t_ev < ev->clock)
            add_failure(err, &nfail, "particle %u has an event at %.17g before the clock %.17g",
                        C[i].label, C[i].t_ev, ev->clock);
        if (c < 0 || (size_t)c >= ncells)
            add_failure(err, &nfail, "particle %u names cell %d of %zu", C[i].label, c,
                        ncells);
        /* numbers: a permutation whose index finds each record; no renewal mark left over */
        if (C[i].label >= ev->n || C[C[i].label].label_slot != i)
            add_failure(err, &nfail, "record %u carries particle number %u, which does not lead "
                        "back to it", i, C[i].label);
        if (P[i].flags & MOTE_EV_MARK)
            add_failure(err, &nfail, "particle %u still carries a list-renewal mark",
                        C[i].label);
        else if (P[i].flags != ref_flags(ev, i, C[i].r_ref))
            add_failure(err, &nfail,
                        "particle %u has flags %#x; its list reference needs %#x",
                        C[i].label, P[i].flags, ref_flags(ev, i, C[i].r_ref));
    }
    *pnfail = nfail;
}

/* Cell blocks: each holds exactly the particles that say they are in it, once. */
static void check_cells(const mote_ev *ev, mote_err *err, int *pnfail)
{
    int nfail = *pnfail;
    const mote_ev_cold *C = ev->pc;
    const size_t ncells = (size_t)ev->ncell[0] * ev->ncell[1] * ev->ncell[2];
    uint8_t *listed = calloc(ev->n, 1); /* times each particle appears in a cell block */
    if (listed) {
        for (size_t c = 0; c < ncells; c++) {
            const uint32_t *B = cell_members(ev, (int32_t)c);
            if (B[0] >= ev->cell_stride) {
                add_failure(err, &nfail, "cell %zu holds %u particles in a block of %u", c, B[0],
                            ev->cell_stride);
                continue;
            }
            for (uint32_t s = 1; s <= B[0]; s++) {
                uint32_t j = B[s];
                if (j >= ev->n)
                    add_failure(err, &nfail, "cell %zu lists record %u of %u", c, j, ev->n);
                else if (C[j].cell != (int32_t)c)
                    add_failure(err, &nfail, "cell %zu lists particle %u, which is not in it", c,
                                C[j].label);
                else if (listed[j] < 255)
                    listed[j]++;
            }
        }
        for (uint32_t i = 0; i < ev->n; i++)
            if (listed[i] != 1)
                add_failure(err, &nfail, "particle %u is listed %u times in the cells",
                            C[i].label, listed[i]);
        free(listed);
    }
    *pnfail = nfail;
}

/* Neighbour lists: symmetric, no repeats, no stale entry, none missing (spec 6.6). */
static void check_neighbours(const mote_ev *ev, mote_err *err, int *pnfail)
{
    int nfail = *pnfail;
    const mote_particle *P = ev->p;
    const mote_ev_cold *C = ev->pc;
    {
        const double cm = 2 * ev->radius0 + ev->shell;
        int32_t cells[27];
        for (uint32_t i = 0; i < ev->n; i++) {
            const uint32_t *L = nbr_list(ev, i);
            uint32_t n = P[i].nnbr;
            for (uint32_t k = 0; k < n; k++) {
                uint32_t j = L[k], back = 0;
                if (j >= ev->n || j == i) {
                    add_failure(err, &nfail, "neighbour list of particle %u holds record %u",
                                C[i].label, j);
                    continue;
                }
                for (uint32_t q = 0; q < n; q++)
                    if (q != k && L[q] == j)
                        add_failure(err, &nfail, "neighbour list of %u holds %u twice",
                                    C[i].label, C[j].label);
                for (uint32_t q = 0; q < P[j].nnbr; q++)
                    back += nbr_list(ev, j)[q] == i;
                if (back != 1)
                    add_failure(err, &nfail, "%u lists %u but %u lists %u %u times", C[i].label,
                                C[j].label, C[j].label, C[i].label, back);
                if (!nbr_within(ev, i, j, cm * cm))
                    add_failure(err, &nfail, "%u lists %u, whose reference is beyond the shell",
                                C[i].label, C[j].label);
            }
            int nc = ev_cell_neighbours(ev, C[i].cell, cells);
            for (int q = 0; q < nc; q++) {
                const uint32_t *B = cell_members(ev, cells[q]);
                for (uint32_t s = 1; s <= B[0]; s++) {
                    const uint32_t j = B[s];
                    if (j == i || !nbr_within(ev, i, j, cm * cm))
                        continue;
                    uint32_t found = 0;
                    for (uint32_t k = 0; k < n; k++)
                        found |= L[k] == j;
                    if (!found)
                        add_failure(err, &nfail, "neighbour list of %u misses %u",
                                    C[i].label, C[j].label);
                }
            }
        }
    }
    *pnfail = nfail;
}

/* The calendar: heap positions and order, bucket lists, every particle exactly once. */
static void check_calendar(const mote_ev *ev, mote_err *err, int *pnfail)
{
    int nfail = *pnfail;
    const mote_ev_cold *C = ev->pc;
    {
        size_t seen = 0;
        for (uint32_t k = 0; k < ev->heap_n; k++) {
            uint32_t i = ev->heap[k];
            if (i >= ev->n || C[i].cal_slot != -1 || C[i].cal_next != k)
                add_failure(err, &nfail, "calendar heap slot %u is inconsistent", k);
            if (i < ev->n && ev->heap_t[k] != C[i].t_ev)
                add_failure(err, &nfail, "calendar heap slot %u holds a stale time", k);
            if (k > 0 && ev_before(C, i, ev->heap[(k - 1) / 2]))
                add_failure(err, &nfail, "calendar order broken at slot %u", k);
            if (i < ev->n && cal_index(ev, C[i].t_ev) > ev->bucket_cur)
                add_failure(err, &nfail, "particle %u is in the calendar heap but due later",
                            C[i].label);
        }
        seen += ev->heap_n;
        for (uint32_t s = 0; ev->bucket && s <= ev->nbuckets; s++) {
            uint32_t prev = MOTE_EV_NIL;
            for (uint32_t i = ev->bucket[s]; i != MOTE_EV_NIL && seen <= ev->n;
                 i = C[i].cal_next, seen++) {
                if (i >= ev->n || C[i].cal_slot != (int32_t)s || C[i].cal_prev != prev) {
                    add_failure(err, &nfail, "calendar bucket %u is inconsistent", s);
                    break;
                }
                int64_t b = cal_index(ev, C[i].t_ev);
                if (b <= ev->bucket_cur ||
                    (s < ev->nbuckets && (uint32_t)(b & (int64_t)(ev->nbuckets - 1)) != s))
                    add_failure(err, &nfail, "particle %u is in the wrong calendar bucket",
                                C[i].label);
                prev = i;
            }
        }
        if (seen != ev->n)
            add_failure(err, &nfail, "the calendar holds %zu events for %u particles", seen,
                        ev->n);
    }
    *pnfail = nfail;
}

/* The conserved quantities: energy without a field, momentum along periodic axes. */
static void check_conserved(const mote_ev *ev, mote_err *err, int *pnfail)
{
    int nfail = *pnfail;
    const int d = ev->dim;
    const mote_particle *P = ev->p;
    double e = mote_ev_energy(ev);
    if (!ev->field && ev->energy_ref > 0 && fabs(e - ev->energy_ref) > 1e-12 * ev->energy_ref)
        add_failure(err, &nfail, "energy %.17g differs from its reference %.17g by %.3g relative",
                    e, ev->energy_ref, (e - ev->energy_ref) / ev->energy_ref);
    double Pm[3], mabs = 0;
    mote_ev_momentum(ev, Pm);
    for (uint32_t i = 0; i < ev->n; i++) {
        double s = 0;
        for (int a = 0; a < d; a++)
            s += P[i].v[a] * P[i].v[a];
        mabs += mote_ev_mass(ev, i) * sqrt(s);
    }
    for (int a = 0; a < d; a++)
        if (ev->periodic[a] && fabs(Pm[a] - ev->momentum_ref[a]) > 1e-12 * mabs)
            add_failure(err, &nfail, "momentum along %c changed from %.17g to %.17g", "xyz"[a],
                        ev->momentum_ref[a], Pm[a]);
    *pnfail = nfail;
}

int mote_ev_check(const mote_ev *ev, mote_err *err)
{
    const mote_ev_cold *C = ev->pc;
    int nfail = 0;
    if (err) {
        err->msg[0] = '\0';
        err->located = 0;
    }
    if (!ev->ready)
        return not_ready(err, "check");

    gap_acc g = {INFINITY, 0, 0, 0};
    for_near_pairs(ev, gap_visit, &g);
    if (g.overlaps)
        add_failure(err, &nfail, "%zu overlapping pairs; worst %u-%u at %.17g of contact",
                    g.overlaps, C[g.worst_i].label, C[g.worst_j].label, g.min_ratio);
    check_particles(ev, err, &nfail);
    check_cells(ev, err, &nfail);
    check_neighbours(ev, err, &nfail);
    check_calendar(ev, err, &nfail);
    check_conserved(ev, err, &nfail);
    if (nfail) {
        if (err) {
            err->code = MOTE_ERUNTIME;
            if (nfail > 20) {
                size_t used = strlen(err->msg);
                snprintf(err->msg + used, sizeof err->msg - used, "; ... %d failures in all",
                         nfail);
            }
        }
        return MOTE_ERUNTIME;
    }
    return MOTE_OK;
}
