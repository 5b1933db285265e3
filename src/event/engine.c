/* engine.c: the event-driven engine for hard spheres and disks: storage (records, lifetime, the
 * field), and what a model reads of the state (positions, velocities, energy, momentum). The
 * other files of src/event: calendar.c, rebuild.c, step.c (the event loop), check.c; internal.h
 * says what they share.
 *
 * Why this shape (issue 5, measured with callgrind and side by side with the reference code):
 * - Neighbour lists with a shell instead of cell-crossing events: a prediction scans ~14 listed
 *   neighbours instead of the ~30 occupants of 27 cells, and the frequent cell crossings (about
 *   one per collision) become rare list expiries.
 * - The calendar of Paul (2007): insertion is O(1) into a bucket list and the heap holds only the
 *   few dozen events of the current bucket, so sifting stays inside the cache even at N = 10^7.
 * - Two arrays of 64-byte records: the hot one holds all a neighbour's prediction reads, the
 *   cold one the particle's own event, list reference, cell and calendar links. (One 128-byte
 *   record with a hot and a cold half ran 2-5% slower, most likely because the processor
 *   fetches lines in aligned pairs: the pair of a hot line was its own cold line instead of
 *   the hot line of a neighbour.)
 * - At N ~ 10^6 the records no longer fit in any cache and the time goes into waiting for
 *   memory, so the code avoids chains of dependent misses: cells hold their members in
 *   contiguous blocks (a list refresh gathers all candidates, prefetches them, then tests
 *   them), the next calendar bucket is walked one record per event ahead of its use, and the
 *   heap keeps event times beside its indices.
 * - Mispredicted branches cost much of the time: callgrind's --branch-sim counted 40 per
 *   collision (at ~15 cycles each, about a quarter of a collision's time), so choices that are
 *   coin tosses are made without branches: minimum images in the pair test, the heap's child
 *   choice, which renewal candidates are in, and how many members a cell adds to them. */
#if defined(__linux__) && !defined(_DEFAULT_SOURCE)
#define _DEFAULT_SOURCE /* madvise (see ev_hint_huge_pages) */
#endif
#include "internal.h"

#if defined(__linux__)
#include <sys/mman.h>
#endif

/* ---- memory ----------------------------------------------------------------------------------- */

_Static_assert(sizeof(mote_particle) == 64 && sizeof(mote_ev_cold) == 64,
               "the hot and cold records must stay 64 bytes each");

/* Ask for transparent huge pages on a large array. Predictions and list updates jump around
 * hundreds of MB at N ~ 10^6 and beyond, and with 4 KiB pages nearly every such access also
 * misses the TLB; where the kernel hands out huge pages only on request (the `madvise` mode)
 * this doubles the rate at N = 10^6. A hint only: nothing depends on whether it is honoured. */
void ev_hint_huge_pages(void *p, size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    const uintptr_t page = 4096;
    if (!p || bytes < ((size_t)4 << 20))
        return;
    uintptr_t lo = ((uintptr_t)p + page - 1) & ~(page - 1);
    uintptr_t hi = ((uintptr_t)p + bytes) & ~(page - 1);
    if (hi > lo)
        (void)madvise((void *)lo, hi - lo, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

/* ---- lifetime ------------------------------------------------------------------------------------ */

/* ---- lifetime ------------------------------------------------------------------------------------ */

int mote_ev_init(mote_ev *ev, uint32_t n, int dim, int polydisperse, mote_err *err)
{
    memset(ev, 0, sizeof *ev);
    if (dim != 2 && dim != 3)
        return mote_fail(err, MOTE_EINVAL, "dimension must be 2 or 3, got %d", dim);
    if (n < 1)
        return mote_fail(err, MOTE_EINVAL, "a system needs at least one particle");
    ev->dim = dim;
    ev->n = n;
    ev->radius0 = 1.0;
    ev->mass0 = 1.0;
    ev->len[2] = 1.0;
    /* 64-byte alignment puts each record in one cache line (hot and cold are 64 bytes each) */
    size_t bytes = (size_t)n * sizeof(mote_particle), align = 64;
    if (bytes >= ((size_t)4 << 20)) { /* whole huge pages (see hint_huge_pages) */
        align = (size_t)2 << 20;
        bytes = (bytes + align - 1) / align * align;
    }
    ev->p = aligned_alloc(align, bytes);
    ev->pc = aligned_alloc(align, bytes);
    ev_hint_huge_pages(ev->p, bytes);
    ev_hint_huge_pages(ev->pc, bytes);
    if (ev->p)
        memset(ev->p, 0, bytes);
    if (ev->pc)
        memset(ev->pc, 0, bytes);
    ev->heap = calloc(n, sizeof *ev->heap);
    ev->heap_t = calloc(n, sizeof *ev->heap_t);
    if (ev->pc)
        for (uint32_t i = 0; i < n; i++)
            ev->pc[i].label = ev->pc[i].label_slot = i;
    if (polydisperse) {
        ev->radius = calloc(n, sizeof *ev->radius);
        ev->mass = calloc(n, sizeof *ev->mass);
    }
    if (!ev->p || !ev->pc || !ev->heap || !ev->heap_t ||
        (polydisperse && (!ev->radius || !ev->mass))) {
        mote_ev_free(ev);
        return mote_fail(err, MOTE_ENOMEM, "out of memory for %u particles", n);
    }
    return MOTE_OK;
}

void mote_ev_free(mote_ev *ev)
{
    free(ev->p);
    free(ev->pc);
    free(ev->heap);
    free(ev->heap_t);
    free(ev->radius);
    free(ev->mass);
    free(ev->cell_block);
    free(ev->nbr);
    free(ev->nbr_new);
    free(ev->bucket);
    free(ev->field);
    memset(ev, 0, sizeof *ev);
}

int mote_ev_set_field(mote_ev *ev, const mote_ev_field *f, mote_err *err)
{
    if (ev->dim != 2 || ev->periodic[0] || ev->periodic[1])
        return mote_fail(err, MOTE_EINVAL, "field mode needs a 2D box with walls on both axes");
    if (f->nseg < 0 || f->ncorner < 0 || !isfinite(f->g[0]) || !isfinite(f->g[1]))
        return mote_fail(err, MOTE_EINVAL, "field mode: bad field (counts or acceleration)");
    for (int k = 0; k < f->nseg; k++) {
        const mote_ev_segment *sk = &f->seg[k];
        double nn = sk->n[0] * sk->n[0] + sk->n[1] * sk->n[1];
        if (fabs(nn - 1) > 1e-12 || (sk->a[0] == sk->b[0] && sk->a[1] == sk->b[1]))
            return mote_fail(err, MOTE_EINVAL, "field mode: segment %d is empty or its normal is "
                                               "not a unit vector", k);
    }
    /* one block: the struct, then its segments, then its corners */
    size_t bytes = sizeof(mote_ev_field) + (size_t)f->nseg * sizeof(mote_ev_segment) +
                   (size_t)f->ncorner * sizeof(double[2]);
    mote_ev_field *copy = malloc(bytes);
    if (!copy)
        return mote_fail(err, MOTE_ENOMEM, "out of memory for the field");
    *copy = *f;
    mote_ev_segment *seg = (mote_ev_segment *)(copy + 1);
    double(*corner)[2] = (double(*)[2])(seg + f->nseg);
    if (f->nseg)
        memcpy(seg, f->seg, (size_t)f->nseg * sizeof *seg);
    if (f->ncorner)
        memcpy(corner, f->corner, (size_t)f->ncorner * sizeof *corner);
    copy->seg = seg;
    copy->corner = (const double(*)[2])corner;
    free(ev->field);
    ev->field = copy;
    return MOTE_OK;
}

/* ---- measurements of the state ---------------------------------------------------------------- */

void mote_ev_position(const mote_ev *ev, uint32_t i, double out[3])
{
    const mote_particle *p = &ev->p[i];
    double r[3];
    project(ev, p, ev->clock - p->t, r, NULL);
    out[2] = 0;
    for (int a = 0; a < ev->dim; a++)
        out[a] = ev->periodic[a] ? wrap_coord(r[a], ev->len[a]) : r[a];
}

void mote_ev_velocity(const mote_ev *ev, uint32_t i, double out[3])
{
    const mote_particle *p = &ev->p[i];
    double r[3];
    project(ev, p, ev->clock - p->t, r, out);
    if (ev->dim == 2)
        out[2] = 0;
}

double mote_ev_energy(const mote_ev *ev)
{
    mote_ksum e = {0, 0};
    for (uint32_t i = 0; i < ev->n; i++) {
        double v2 = 0, v[3];
        mote_ev_velocity(ev, i, v); /* at the clock: differs from p[i].v in field mode */
        for (int a = 0; a < ev->dim; a++)
            v2 += v[a] * v[a];
        mote_ksum_add(&e, 0.5 * mote_ev_mass(ev, i) * v2);
    }
    return mote_ksum_value(&e);
}

void mote_ev_momentum(const mote_ev *ev, double P[3])
{
    for (int a = 0; a < 3; a++) {
        mote_ksum s = {0, 0};
        if (a < ev->dim)
            for (uint32_t i = 0; i < ev->n; i++)
                mote_ksum_add(&s, mote_ev_mass(ev, i) * ev->p[i].v[a]);
        P[a] = mote_ksum_value(&s);
    }
}

double mote_ev_kt(const mote_ev *ev) { return 2.0 * mote_ev_energy(ev) / (ev->dim * (double)ev->n); }

void mote_ev_set_kt(mote_ev *ev, double kt)
{
    double now = mote_ev_kt(ev);
    if (!(now > 0))
        return;
    double f = sqrt(kt / now);
    ev->canonical = 0;
    for (uint32_t i = 0; i < ev->n; i++)
        for (int a = 0; a < ev->dim; a++)
            ev->p[i].v[a] *= f;
}

void mote_ev_set_reference(mote_ev *ev)
{
    ev->energy_ref = mote_ev_energy(ev);
    mote_ev_momentum(ev, ev->momentum_ref);
}

double mote_ev_bytes_per_particle(const mote_ev *ev)
{
    double bytes = (double)ev->n * (sizeof(mote_particle) + sizeof(mote_ev_cold) +
                                    sizeof(uint32_t) + sizeof(double));
    if (ev->radius)
        bytes += (double)ev->n * 2 * sizeof(double);
    bytes += (double)ev->n * ev->nbr_cap * sizeof(uint32_t);
    bytes += (double)ev->cell_words * sizeof(uint32_t);
    bytes += ((double)ev->nbuckets + 1) * sizeof(uint32_t);
    return bytes / ev->n;
}
