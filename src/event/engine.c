/* engine.c: the event-driven engine for hard spheres and disks: storage, the event calendar,
 * the cell grid of reference positions, the neighbour lists, synchronisation (rebuilds),
 * conserved quantities and the invariant checker. The per-event hot path lives in
 * engine_dim.inc and is compiled once for 2D and once for 3D below.
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
#define _DEFAULT_SOURCE /* madvise (see hint_huge_pages) */
#endif
#include "mote/event.h"

#include "roots.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

/* The shell delta of the neighbour lists in units of the largest contact distance, and the
 * number of events the calendar aims to keep in its heap (spec 6.5: 10 to 50). Both only trade
 * list expiries against candidates and list moves against sifting; the first changes rounding
 * (so trajectories), the second never changes the event sequence. */
#ifndef SHELL_FRACTION
#define SHELL_FRACTION 0.5
#endif
#define HEAP_TARGET 24.0
/* A list renewal copies a neighbouring cell's members as one block of this many words (see
 * refresh in engine_dim.inc); cells with more take a loop. */
#define GATHER_WORDS 8
/* A prediction asks for the record of the list entry this many places ahead of the one it
 * tests; the list array has this many words of padding at its end, so that read stays inside
 * it even for the last list. */
#define PREFETCH_AHEAD 4
#define FIELD_NEIGHBOURS 12.0

/* ---- memory ----------------------------------------------------------------------------------- */

_Static_assert(sizeof(mote_particle) == 64 && sizeof(mote_ev_cold) == 64,
               "the hot and cold records must stay 64 bytes each");

/* Ask for transparent huge pages on a large array. Predictions and list updates jump around
 * hundreds of MB at N ~ 10^6 and beyond, and with 4 KiB pages nearly every such access also
 * misses the TLB; where the kernel hands out huge pages only on request (the `madvise` mode)
 * this doubles the rate at N = 10^6. A hint only: nothing depends on whether it is honoured. */
static void hint_huge_pages(void *p, size_t bytes)
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

/* ---- calendar: heap part ------------------------------------------------------------------------ */

static inline int ev_before(const mote_ev_cold *C, uint32_t a, uint32_t b)
{
    double ta = C[a].t_ev, tb = C[b].t_ev;
    return ta < tb || (ta == tb && a < b);
}

/* The heap keeps a copy of each event time next to the index (heap_t), so that sifting compares
 * within two small arrays instead of reading scattered records. */
static inline int key_before(double ta, uint32_t a, double tb, uint32_t b)
{
    return ta < tb || (ta == tb && a < b);
}

/* The same order for a coin toss (which child of a heap node comes first): the comparison
 * becomes a flag, not a branch that fails half the time; the rare tie is the only branch. */
static inline int key_before_flag(double ta, uint32_t a, double tb, uint32_t b)
{
    int before = ta < tb;
    if (__builtin_expect(ta == tb, 0))
        before = a < b;
    return before;
}

static void heap_sift_up(mote_ev *ev, uint32_t k)
{
    uint32_t *H = ev->heap;
    double *T = ev->heap_t;
    mote_ev_cold *C = ev->pc;
    const uint32_t x = H[k];
    const double tx = T[k];
    while (k > 0) {
        uint32_t parent = (k - 1) / 2;
        if (!key_before(tx, x, T[parent], H[parent]))
            break;
        H[k] = H[parent];
        T[k] = T[parent];
        C[H[k]].cal_next = k;
        k = parent;
    }
    H[k] = x;
    T[k] = tx;
    C[x].cal_next = k;
}

static void heap_sift_down(mote_ev *ev, uint32_t k)
{
    uint32_t *H = ev->heap;
    double *T = ev->heap_t;
    mote_ev_cold *C = ev->pc;
    const uint32_t n = ev->heap_n, x = H[k];
    const double tx = T[k];
    for (;;) {
        uint32_t c = 2 * k + 1;
        if (c >= n)
            break;
        if (c + 1 < n)
            c += (uint32_t)key_before_flag(T[c + 1], H[c + 1], T[c], H[c]);
        if (!key_before(T[c], H[c], tx, x))
            break;
        H[k] = H[c];
        T[k] = T[c];
        C[H[k]].cal_next = k;
        k = c;
    }
    H[k] = x;
    T[k] = tx;
    C[x].cal_next = k;
}

static inline void heap_push(mote_ev *ev, uint32_t i)
{
    uint32_t k = ev->heap_n++;
    ev->heap[k] = i;
    ev->heap_t[k] = ev->pc[i].t_ev;
    ev->pc[i].cal_slot = -1;
    ev->pc[i].cal_prev = MOTE_EV_NIL; /* unused in the heap; kept canonical (state comparisons) */
    heap_sift_up(ev, k);
}

static inline void heap_remove_at(mote_ev *ev, uint32_t k)
{
    const uint32_t m = --ev->heap_n, last = ev->heap[m];
    if (k == m)
        return;
    ev->heap[k] = last;
    ev->heap_t[k] = ev->heap_t[m];
    ev->pc[last].cal_next = k;
    if (k > 0 && key_before(ev->heap_t[k], last, ev->heap_t[(k - 1) / 2], ev->heap[(k - 1) / 2]))
        heap_sift_up(ev, k);
    else
        heap_sift_down(ev, k);
}

/* ---- calendar: buckets ------------------------------------------------------------------------- */

/* Absolute bucket of time t. floor(t / width) is monotonic in t, so an earlier bucket always
 * holds earlier events and the heap of the current bucket yields the global order (t, i).
 * Infinite times land at INT64_MAX, in the overflow list for good. */
static inline int64_t cal_index(const mote_ev *ev, double t)
{
    double x = t * ev->bucket_inv;
    return x < 4.0e18 ? (int64_t)x : INT64_MAX;
}

static inline void cal_insert(mote_ev *ev, uint32_t i)
{
    mote_ev_cold *C = ev->pc;
    int64_t b = cal_index(ev, C[i].t_ev);
    if (b <= ev->bucket_cur) {
        heap_push(ev, i);
        return;
    }
    uint32_t slot = b - ev->bucket_cur < (int64_t)ev->nbuckets
                        ? (uint32_t)(b & (int64_t)(ev->nbuckets - 1))
                        : ev->nbuckets;
    uint32_t head = ev->bucket[slot];
    C[i].cal_slot = (int32_t)slot;
    C[i].cal_prev = MOTE_EV_NIL;
    C[i].cal_next = head;
    if (head != MOTE_EV_NIL)
        C[head].cal_prev = i;
    ev->bucket[slot] = i;
}

static inline void cal_remove(mote_ev *ev, uint32_t i)
{
    mote_ev_cold *C = ev->pc;
    mote_ev_cold *p = &C[i];
    if (p->cal_slot < 0) {
        heap_remove_at(ev, p->cal_next);
        return;
    }
    if (p->cal_prev != MOTE_EV_NIL)
        C[p->cal_prev].cal_next = p->cal_next;
    else
        ev->bucket[p->cal_slot] = p->cal_next;
    if (p->cal_next != MOTE_EV_NIL)
        C[p->cal_next].cal_prev = p->cal_prev;
}

/* Detach a bucket's list and return its head. */
static inline uint32_t cal_take(mote_ev *ev, uint32_t slot)
{
    uint32_t h = ev->bucket[slot];
    ev->bucket[slot] = MOTE_EV_NIL;
    return h;
}

/* Fetch the next bucket's list ahead of cal_refill, one record per event. Following a list is a
 * chain of dependent cache misses (each record names the next); a step per event, reading the
 * record the previous step asked for, has the whole list in cache by the time the heap runs dry
 * (a bucket holds about as many events as the heap does). A list may change under the walk: a
 * record that left it sends the walk back to the head. Only prefetches: nothing depends on it.
 * ev->walk >= n means "start at the head", MOTE_EV_NIL "done". */
static inline void cal_walk(mote_ev *ev)
{
    const mote_ev_cold *C = ev->pc;
    uint32_t w = ev->walk;
    if (w == MOTE_EV_NIL)
        return;
    const uint32_t slot = (uint32_t)((ev->bucket_cur + 1) & (int64_t)(ev->nbuckets - 1));
    if (w >= ev->n || C[w].cal_slot != (int32_t)slot)
        w = ev->bucket[slot];
    else
        w = C[w].cal_next;
    if (w != MOTE_EV_NIL)
        __builtin_prefetch(&C[w].t_ev);
    ev->walk = w;
}

/* The heap is empty: move on bucket by bucket until one holds events, and load it into the
 * heap. Each time the circular array wraps, the overflow list is sorted out again (its events
 * were at least a full lap ahead when inserted, so none is missed). Returns -1 when no event
 * with a finite time is left. */
static int cal_refill(mote_ev *ev)
{
    mote_ev_cold *C = ev->pc;
    const uint32_t mask = ev->nbuckets - 1;
    uint32_t idle = 0;
    while (ev->heap_n == 0) {
        ev->bucket_cur++;
        uint32_t slot = (uint32_t)(ev->bucket_cur & (int64_t)mask);
        if (slot == 0) {
            for (uint32_t e = cal_take(ev, ev->nbuckets); e != MOTE_EV_NIL;) {
                uint32_t next = C[e].cal_next;
                cal_insert(ev, e);
                e = next;
            }
        }
        for (uint32_t e = cal_take(ev, slot); e != MOTE_EV_NIL;) {
            uint32_t next = C[e].cal_next;
            heap_push(ev, e);
            e = next;
        }
        ev->walk = ev->n;
        if (ev->heap_n == 0 && ++idle > ev->nbuckets) {
            /* a whole lap found nothing: jump to the lap of the earliest overflow event */
            int64_t first = INT64_MAX;
            for (uint32_t e = ev->bucket[ev->nbuckets]; e != MOTE_EV_NIL; e = C[e].cal_next) {
                int64_t b = cal_index(ev, C[e].t_ev);
                if (b < first)
                    first = b;
            }
            if (first == INT64_MAX)
                return -1;
            ev->bucket_cur = (first & ~(int64_t)mask) - 1;
            idle = 0;
        }
    }
    return 0;
}

/* Fill the calendar with every particle's predicted event (index order). The bucket width is
 * chosen so that about HEAP_TARGET events fall into one bucket, from the mean time to the next
 * event just predicted; the circular array spans about 8 such mean times. This tuning is a
 * function of the state alone and never changes the event order. */
static int cal_init(mote_ev *ev, mote_err *err)
{
    const uint32_t n = ev->n;
    mote_ev_cold *C = ev->pc;
    uint32_t nb = 1;
    double inv = 0;
    if (!ev->heap_only) {
        double sum = 0;
        uint32_t cnt = 0;
        for (uint32_t i = 0; i < n; i++) {
            double dt = C[i].t_ev - ev->clock;
            if (dt < ev->t_rebuild) {
                sum += dt;
                cnt++;
            }
        }
        double mean = cnt ? sum / cnt : 0;
        if (mean > 0) {
            double width = HEAP_TARGET * mean / n;
            double want = 8.0 * mean / width;
            while (nb < want && nb < (1u << 26))
                nb *= 2;
            inv = 1.0 / width;
        }
    }
    if (nb != ev->nbuckets || !ev->bucket) {
        free(ev->bucket); /* refilled below: free first, so old and new never coexist */
        ev->nbuckets = 0;
        uint32_t *b = malloc(((size_t)nb + 1) * sizeof *b);
        ev->bucket = b;
        if (!b)
            return mote_fail(err, MOTE_ENOMEM, "out of memory for %u calendar buckets", nb);
        ev->nbuckets = nb;
        hint_huge_pages(b, ((size_t)nb + 1) * sizeof *b);
    }
    for (uint32_t s = 0; s <= nb; s++)
        ev->bucket[s] = MOTE_EV_NIL;
    ev->bucket_inv = inv;
    ev->bucket_cur = cal_index(ev, ev->clock);
    ev->walk = n;
    ev->heap_n = 0;
    /* the slots beyond heap_n hold leftovers of the past; clear them so that a rebuilt state is
     * the same bytes whatever its history (save -> load must give back the saved state) */
    memset(ev->heap, 0, (size_t)n * sizeof *ev->heap);
    memset(ev->heap_t, 0, (size_t)n * sizeof *ev->heap_t);
    for (uint32_t i = 0; i < n; i++)
        cal_insert(ev, i);
    return MOTE_OK;
}

/* ---- cells of reference positions --------------------------------------------------------------- */

static inline int32_t cell_index(const mote_ev *ev, const double x[3])
{
    int32_t lin = 0, stride = 1;
    for (int a = 0; a < ev->dim; a++) {
        double f = (x[a] - ev->cell_lo[a]) / ev->cell_w[a];
        /* compared as doubles first: converting a value beyond int's range is undefined */
        int k = f >= ev->ncell[a] ? ev->ncell[a] - 1 : f > 0 ? (int)f : 0;
        lin += k * stride;
        stride *= ev->ncell[a];
    }
    return lin;
}

/* Cells keep their members in blocks of `cell_stride` words, a count followed by the particle
 * indices, so a list refresh reads each neighbouring cell as one contiguous run and can fetch
 * all candidates at once, instead of following a chain of records one cache miss at a time. */
static inline uint32_t *cell_members(const mote_ev *ev, int32_t cell)
{
    return ev->cell_block + (size_t)cell * ev->cell_stride;
}

/* Give the grid blocks of `stride` words for `ncells` cells; the members of the first `keep`
 * cells move along when the stride widens. */
static int cell_blocks(mote_ev *ev, size_t ncells, uint32_t stride, size_t keep)
{
    const uint32_t old = ev->cell_stride;
    const size_t words = ncells * stride + GATHER_WORDS; /* the last block can be read whole */
    if (words > ev->cell_words || !ev->cell_block) {
        uint32_t *b;
        if (keep) {
            b = realloc(ev->cell_block, words * sizeof *b);
        } else { /* nothing to keep: free first, so old and new never coexist (peak memory) */
            free(ev->cell_block);
            ev->cell_block = NULL;
            ev->cell_words = 0;
            b = malloc(words * sizeof *b);
        }
        if (!b)
            return MOTE_ENOMEM;
        ev->cell_block = b;
        ev->cell_words = words;
        hint_huge_pages(b, words * sizeof *b);
        memset(b + words - GATHER_WORDS, 0, GATHER_WORDS * sizeof *b);
    }
    if (keep && stride > old) /* last first: a block only ever moves up */
        for (size_t c = keep; c-- > 0;)
            memmove(ev->cell_block + c * stride, ev->cell_block + c * old,
                    ((size_t)ev->cell_block[c * old] + 1) * sizeof(uint32_t));
    ev->cell_stride = stride;
    return MOTE_OK;
}

/* Move particle i from its cell to `cell`. The blocks widen first if `cell` is full; if that
 * fails nothing has changed. */
static int cell_move(mote_ev *ev, uint32_t i, int32_t cell)
{
    if (cell_members(ev, cell)[0] + 1 >= ev->cell_stride) {
        size_t ncells = (size_t)ev->ncell[0] * ev->ncell[1] * ev->ncell[2];
        if (ev->cell_stride > UINT32_MAX / 2 ||
            cell_blocks(ev, ncells, ev->cell_stride + ev->cell_stride / 2 + 1, ncells))
            return MOTE_ENOMEM;
    }
    uint32_t *B = cell_members(ev, ev->pc[i].cell);
    const uint32_t n = B[0];
    for (uint32_t k = 1; k <= n; k++)
        if (B[k] == i) {
            B[k] = B[n];
            B[0] = n - 1;
            break;
        }
    B = cell_members(ev, cell);
    B[++B[0]] = i;
    ev->pc[i].cell = cell;
    return MOTE_OK;
}

/* The distinct cells next to (and including) `cell`: 3 per axis, or all of them on an axis of
 * fewer than 3 cells (where -1 and +1 would name the same cell twice); on a wall axis nothing
 * beyond the grid. Returns how many were written to out[27]. */
static int cell_neighbours(const mote_ev *ev, int32_t cell, int32_t out[27])
{
    int cc[3], lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    cc[0] = cell % ev->ncell[0];
    cc[1] = (cell / ev->ncell[0]) % ev->ncell[1];
    cc[2] = cell / (ev->ncell[0] * ev->ncell[1]);
    for (int a = 0; a < ev->dim; a++) {
        int n = ev->ncell[a];
        if (n < 3) {
            lo[a] = -cc[a];
            hi[a] = n - 1 - cc[a];
        } else {
            lo[a] = -1;
            hi[a] = 1;
            if (!ev->periodic[a]) {
                if (cc[a] == 0)
                    lo[a] = 0;
                if (cc[a] == n - 1)
                    hi[a] = 0;
            }
        }
    }
    int m = 0;
    for (int oz = lo[2]; oz <= hi[2]; oz++) {
        int z = (cc[2] + oz + ev->ncell[2]) % ev->ncell[2];
        for (int oy = lo[1]; oy <= hi[1]; oy++) {
            int y = (cc[1] + oy + ev->ncell[1]) % ev->ncell[1];
            for (int ox = lo[0]; ox <= hi[0]; ox++) {
                int x = (cc[0] + ox + ev->ncell[0]) % ev->ncell[0];
                out[m++] = (z * ev->ncell[1] + y) * ev->ncell[0] + x;
            }
        }
    }
    return m;
}

/* Minimum-image difference along every axis (periodic axes only); |d| < 1.5 len assumed. */
static inline void min_image(const mote_ev *ev, double d[3])
{
    for (int a = 0; a < ev->dim; a++)
        if (ev->periodic[a]) {
            if (d[a] > 0.5 * ev->len[a])
                d[a] -= ev->len[a];
            else if (d[a] < -0.5 * ev->len[a])
                d[a] += ev->len[a];
        }
}

/* The flags of particle i with list reference x. Edge: 0 when x lies so far from every
 * periodic face that each listed neighbour, and every position either of them reaches before
 * its list expires, is seen directly (no wrap), so predictions may skip the minimum-image test;
 * otherwise MOTE_EV_EDGE, plus MOTE_EV_WRAP_X << a for each axis a on which it is that close to
 * a face (only those axes need the test). A listed pair whose references are on opposite sides
 * of a face has both within sigma_max + shell of it; references lie in the box and positions
 * are stored consistently with them (a renewal shifts both by the period), so any other pair's
 * direct difference, of references or of positions, is its true separation. MOTE_EV_NEAR_WALL
 * when x lies within half a shell of a wall's contact plane, by the test predict applies per
 * wall: only then can i hit a wall before its list expires, so predict looks at walls only for
 * those. */
static inline uint8_t ref_flags(const mote_ev *ev, uint32_t i, const double x[3])
{
    const double m = ev->sigma_max + ev->shell, reach = 0.5 * ev->shell;
    const double R = mote_ev_radius(ev, i);
    unsigned f = 0;
    for (int a = 0; a < ev->dim; a++) {
        if (ev->periodic[a]) {
            if (x[a] < m || x[a] > ev->len[a] - m)
                f |= MOTE_EV_EDGE | (unsigned)MOTE_EV_WRAP_X << a;
        } else if (x[a] - R <= reach || ev->len[a] - R - x[a] <= reach) {
            f |= MOTE_EV_NEAR_WALL;
        }
    }
    return (uint8_t)f;
}

/* ---- neighbour lists ----------------------------------------------------------------------------- */

static inline uint32_t *nbr_list(const mote_ev *ev, uint32_t i)
{
    return ev->nbr + (size_t)i * ev->nbr_cap;
}

/* Ask for record j. j may be a word past the end of a list, stale but still a record's index:
 * the list array is zeroed when it is allocated and holds nothing but indices afterwards. */
static inline void prefetch_record(const mote_particle *P, uint32_t j)
{
    __builtin_prefetch(&P[j]);
}

/* Words of the list array for n lists of cap entries: the lists, then the padding that the
 * prediction's read-ahead may reach (see PREFETCH_AHEAD). */
static inline size_t nbr_words(uint32_t n, uint32_t cap)
{
    return (size_t)n * cap + PREFETCH_AHEAD;
}

/* Make room for more entries per particle (rare: lists are sized at each rebuild). The lists
 * move to a wider stride; their content and order are unchanged, so the trajectory is too. */
static int nbr_grow(mote_ev *ev)
{
    uint32_t old = ev->nbr_cap, cap = old + old / 4 + 4;
    if (cap > UINT16_MAX)
        cap = UINT16_MAX;
    if (cap <= old)
        return MOTE_ENOMEM;
    uint32_t *scratch = realloc(ev->nbr_new, cap * sizeof *scratch);
    if (!scratch)
        return MOTE_ENOMEM;
    ev->nbr_new = scratch;
    uint32_t *b = realloc(ev->nbr, nbr_words(ev->n, cap) * sizeof *b);
    if (!b)
        return MOTE_ENOMEM;
    const size_t had = nbr_words(ev->n, old); /* zero what was added (see prefetch_record) */
    memset(b + had, 0, (nbr_words(ev->n, cap) - had) * sizeof *b);
    for (uint32_t i = ev->n; i-- > 0;)
        memmove(b + (size_t)i * cap, b + (size_t)i * old, ev->p[i].nnbr * sizeof *b);
    ev->nbr = b;
    ev->nbr_cap = cap;
    hint_huge_pages(b, (size_t)ev->n * cap * sizeof *b);
    return MOTE_OK;
}

static inline int nbr_add_pair(mote_ev *ev, uint32_t i, uint32_t j)
{
    mote_particle *P = ev->p;
    if (P[i].nnbr >= ev->nbr_cap || P[j].nnbr >= ev->nbr_cap) {
        int rc = nbr_grow(ev);
        if (rc)
            return rc;
    }
    nbr_list(ev, i)[P[i].nnbr++] = j;
    nbr_list(ev, j)[P[j].nnbr++] = i;
    return MOTE_OK;
}

/* Append i to j's list only. */
static inline int nbr_push(mote_ev *ev, uint32_t j, uint32_t i)
{
    if (ev->p[j].nnbr >= ev->nbr_cap && nbr_grow(ev))
        return MOTE_ENOMEM;
    nbr_list(ev, j)[ev->p[j].nnbr++] = i;
    return MOTE_OK;
}

/* Remove i from j's list (swap with the last entry). */
static inline void nbr_drop(mote_ev *ev, uint32_t j, uint32_t i)
{
    uint32_t *L = nbr_list(ev, j);
    uint32_t n = ev->p[j].nnbr;
    for (uint32_t k = 0; k < n; k++)
        if (L[k] == i) {
            L[k] = L[n - 1];
            ev->p[j].nnbr = (uint16_t)(n - 1);
            return;
        }
}

/* End of a renewal of i (see refresh): old neighbours still marked were not found again and
 * i leaves their lists; the new list (ev->nbr_new, nnew entries) replaces the old. After a
 * failed renewal this leaves symmetric lists that may lack pairs: a rebuild restores them. */
static void nbr_renewed(mote_ev *ev, uint32_t i, uint32_t nold, uint32_t nnew)
{
    mote_particle *P = ev->p;
    uint32_t *Li = nbr_list(ev, i);
    for (uint32_t k = 0; k < nold; k++) {
        const uint32_t j = Li[k];
        if (P[j].flags & MOTE_EV_MARK) {
            P[j].flags &= (uint8_t)~MOTE_EV_MARK;
            nbr_drop(ev, j, i);
        }
    }
    memcpy(Li, ev->nbr_new, nnew * sizeof *Li);
    P[i].nnbr = (uint16_t)nnew;
}

static inline int nbr_within(const mote_ev *ev, uint32_t i, uint32_t j, double reach2_mono)
{
    const mote_ev_cold *C = ev->pc;
    double d[3] = {0, 0, 0}, r2 = 0;
    for (int a = 0; a < ev->dim; a++)
        d[a] = C[i].r_ref[a] - C[j].r_ref[a];
    min_image(ev, d);
    for (int a = 0; a < ev->dim; a++)
        r2 += d[a] * d[a];
    if (!ev->radius)
        return r2 < reach2_mono;
    double c = ev->radius[i] + ev->radius[j] + ev->shell;
    return r2 < c * c;
}

/* ---- the hot loop, instantiated for 2D and 3D --------------------------------------------------- */

#define FIELD 0
#define D 2
#define FN(name) name##_2d
#include "engine_dim.inc"
#undef D
#undef FN
#define D 3
#define FN(name) name##_3d
#include "engine_dim.inc"
#undef D
#undef FN
#undef FIELD
/* field mode (2D, gravity, obstacles, dissipation): a third build of the same loop */
#define FIELD 1
#define D 2
#define FN(name) name##_2f
#include "engine_dim.inc"
#undef D
#undef FN
#undef FIELD

static inline void predict(mote_ev *ev, uint32_t i)
{
    if (ev->field)
        predict_2f(ev, i);
    else if (ev->dim == 2)
        predict_2d(ev, i);
    else
        predict_3d(ev, i);
}

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
    hint_huge_pages(ev->p, bytes);
    hint_huge_pages(ev->pc, bytes);
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

/* Position (and velocity) of a record projected dt after its local time, along its flight
 * (a parabola in field mode). */
static inline void project(const mote_ev *ev, const mote_particle *p, double dt, double r[3],
                           double v[3])
{
    for (int a = 0; a < 3; a++) {
        double g = ev->field && a < 2 ? ev->field->g[a] : 0;
        r[a] = p->r[a] + (p->v[a] + 0.5 * g * dt) * dt;
        if (v)
            v[a] = p->v[a] + g * dt;
    }
}

static double wrap_coord(double x, double len)
{
    if (!(fabs(x) < 4 * len)) { /* far away (or not finite): one division, not a long loop */
        x = fmod(x, len);
        if (!isfinite(x))
            return 0;
    }
    while (x < 0)
        x += len;
    while (x >= len)
        x -= len;
    return x;
}

/* Neighbour lists of every particle, in index order, with storage sized from an exact count. */
static int nbr_build_all(mote_ev *ev, mote_err *err)
{
    const uint32_t n = ev->n;
    mote_particle *P = ev->p;
    mote_ev_cold *C = ev->pc;
    const double c = 2 * ev->radius0 + ev->shell, reach2 = c * c;
    int32_t cells[27];
    /* pass 1: count */
    for (uint32_t i = 0; i < n; i++)
        P[i].nnbr = 0;
    uint32_t most = 0;
    for (uint32_t i = 0; i < n; i++) {
        int nc = cell_neighbours(ev, C[i].cell, cells);
        for (int q = 0; q < nc; q++) {
            const uint32_t *B = cell_members(ev, cells[q]);
            for (uint32_t s = 1; s <= B[0]; s++) {
                uint32_t j = B[s];
                if (j > i && nbr_within(ev, i, j, reach2)) {
                    if (P[i].nnbr < UINT16_MAX)
                        P[i].nnbr++;
                    if (P[j].nnbr < UINT16_MAX)
                        P[j].nnbr++;
                }
            }
        }
        if (P[i].nnbr > most)
            most = P[i].nnbr;
    }
    /* room for the fluctuations of a fluid; lists grow if that is not enough */
    uint32_t cap = most + most / 4 + 4;
    if (cap > UINT16_MAX)
        cap = UINT16_MAX;
    if (cap != ev->nbr_cap || !ev->nbr) {
        free(ev->nbr); /* refilled below: free first, so old and new never coexist */
        free(ev->nbr_new);
        ev->nbr = calloc(nbr_words(n, cap), sizeof *ev->nbr);
        ev->nbr_new = malloc(cap * sizeof *ev->nbr_new);
        ev->nbr_cap = ev->nbr && ev->nbr_new ? cap : 0;
        if (!ev->nbr_cap)
            return mote_fail(err, MOTE_ENOMEM, "out of memory for neighbour lists (%u x %u)", n,
                             cap);
        uint32_t *b = ev->nbr;
        hint_huge_pages(b, (size_t)n * cap * sizeof *b);
    }
    /* pass 2: fill */
    for (uint32_t i = 0; i < n; i++)
        P[i].nnbr = 0;
    for (uint32_t i = 0; i < n; i++) {
        int nc = cell_neighbours(ev, C[i].cell, cells);
        for (int q = 0; q < nc; q++) {
            const uint32_t *B = cell_members(ev, cells[q]);
            for (uint32_t s = 1; s <= B[0]; s++)
                if (B[s] > i && nbr_within(ev, i, B[s], reach2) && nbr_add_pair(ev, i, B[s]))
                    return mote_fail(err, MOTE_ENOMEM, "out of memory for neighbour lists");
        }
    }
    return MOTE_OK;
}

/* ---- spatial order of the records -------------------------------------------------------------- */

/* Interleave the low 21 bits of x with two zero bits between each. */
static uint64_t morton_spread(uint64_t x)
{
    uint64_t r = 0;
    for (int b = 0; b < 21; b++)
        r |= ((x >> b) & 1u) << (3 * b);
    return r;
}

typedef struct {
    uint64_t key;
    uint32_t label, from;
} sort_item;

static int sort_item_cmp(const void *a, const void *b)
{
    const sort_item *x = a, *y = b;
    if (x->key != y->key)
        return x->key < y->key ? -1 : 1;
    return x->label < y->label ? -1 : (x->label > y->label);
}

/* Record k takes the data of record it[k].from, applied in place cycle by cycle. */
static void permute_records(mote_ev *ev, const sort_item *it, uint8_t *done)
{
    mote_particle *P = ev->p;
    mote_ev_cold *C = ev->pc;
    for (uint32_t s = 0; s < ev->n; s++) {
        if (done[s >> 3] & (1u << (s & 7)) || it[s].from == s)
            continue;
        mote_particle tmp = P[s];
        mote_ev_cold ctmp = C[s];
        double rt = ev->radius ? ev->radius[s] : 0, mt = ev->mass ? ev->mass[s] : 0;
        uint32_t k = s;
        for (;;) {
            done[k >> 3] |= (uint8_t)(1u << (k & 7));
            uint32_t j = it[k].from;
            if (j == s)
                break;
            P[k] = P[j];
            C[k] = C[j];
            if (ev->radius) {
                ev->radius[k] = ev->radius[j];
                ev->mass[k] = ev->mass[j];
            }
            k = j;
        }
        P[k] = tmp;
        C[k] = ctmp;
        if (ev->radius) {
            ev->radius[k] = rt;
            ev->mass[k] = mt;
        }
    }
}

/* Renumber the records in Morton order of cells 3 rmax wide (positions synchronised and
 * wrapped), ties by label, and index the labels. Called by a rebuild after it has freed the
 * lists and cells, so the scratch (16 bytes per particle and a bit, plus as much again that
 * glibc's qsort may take for its merge) stays below the lists' size and does not raise the
 * peak. */
static int sort_spatial(mote_ev *ev, double rmax, mote_err *err)
{
    const uint32_t n = ev->n;
    mote_particle *P = ev->p;
    mote_ev_cold *C = ev->pc;
    const double w = rmax > 0 ? 3.0 * rmax : 1.0;
    sort_item *it = malloc((size_t)n * sizeof *it);
    uint8_t *done = calloc((size_t)n / 8 + 1, 1);
    if (!it || !done) {
        free(it);
        free(done);
        return mote_fail(err, MOTE_ENOMEM, "out of memory sorting %u particles", n);
    }
    for (uint32_t i = 0; i < n; i++) {
        uint64_t key = 0;
        for (int a = 0; a < ev->dim; a++) {
            double f = P[i].r[a] / w;
            uint64_t c = f > 0 ? (uint64_t)fmin(f, 0x1FFFFF) : 0;
            key |= morton_spread(c) << a;
        }
        it[i] = (sort_item){key, C[i].label, i};
    }
    qsort(it, n, sizeof *it, sort_item_cmp);
    permute_records(ev, it, done);
    free(it);
    free(done);
    for (uint32_t k = 0; k < n; k++)
        C[C[k].label].label_slot = k;
    return MOTE_OK;
}

int mote_ev_rebuild(mote_ev *ev, mote_err *err)
{
    const int d = ev->dim;
    const uint32_t n = ev->n;
    mote_particle *P = ev->p;
    mote_ev_cold *C = ev->pc;
    ev->ready = 0; /* until every step below has succeeded */
    ev->canonical = 0;

    double rmax = 0;
    for (uint32_t i = 0; i < n; i++) {
        double r = mote_ev_radius(ev, i);
        if (r > rmax)
            rmax = r;
    }
    ev->sigma_max = 2 * rmax;
    for (int a = 0; a < d; a++) {
        if (!(ev->len[a] > 0) || !isfinite(ev->len[a]))
            return mote_fail(err, MOTE_EINVAL, "box length along axis %c is %g; it must be > 0",
                             "xyz"[a], ev->len[a]);
        if (ev->periodic[a] && !(ev->len[a] > 2 * ev->sigma_max))
            return mote_fail(err, MOTE_EINVAL,
                             "periodic length %.17g along %c must exceed twice the largest contact "
                             "distance (%.17g)",
                             ev->len[a], "xyz"[a], 2 * ev->sigma_max);
        if (!ev->periodic[a] && !(ev->len[a] >= ev->sigma_max))
            return mote_fail(err, MOTE_EINVAL,
                             "wall distance %.17g along %c is smaller than a particle diameter",
                             ev->len[a], "xyz"[a]);
    }

    /* 1-2. synchronise, wrap, fold the clock into the total time */
    for (uint32_t i = 0; i < n; i++) {
        mote_particle *p = &P[i];
        double dt = ev->clock - p->t, r[3], v[3];
        project(ev, p, dt, r, v);
        for (int a = 0; a < d; a++) {
            p->r[a] = ev->periodic[a] ? wrap_coord(r[a], ev->len[a]) : r[a];
            p->v[a] = v[a];
        }
        p->t = 0;
    }
    ev->time_total += ev->clock;
    ev->clock = 0;
    if (ev->spatial_order) { /* lists and cells are rebuilt below: free them before sorting */
        free(ev->nbr);
        ev->nbr = NULL;
        ev->nbr_cap = 0;
        free(ev->cell_block);
        ev->cell_block = NULL;
        ev->cell_words = 0;
        int rc = sort_spatial(ev, rmax, err);
        if (rc)
            return rc;
    }

    /* the shell: SHELL_FRACTION of the contact distance, but small enough on short periodic
     * axes that sigma_max + 2 shell < len / 2, so a listed pair is always seen through one
     * image (its minimum image) until either list expires */
    double shell = SHELL_FRACTION * ev->sigma_max;
    if (ev->field) {
        /* field-mode systems are often dilute (a gas in a box): there a shell of half a
         * diameter expires dozens of times per free flight. Widen it until a list holds about
         * FIELD_NEIGHBOURS particles at the mean density, within a quarter of the box. */
        double area = ev->len[0] * ev->len[1];
        double wide = sqrt(FIELD_NEIGHBOURS * area / (MOTE_PI * n)) - ev->sigma_max;
        double cap = 0.25 * fmin(ev->len[0], ev->len[1]);
        if (wide > cap)
            wide = cap;
        if (wide > shell)
            shell = wide;
    }
    for (int a = 0; a < d; a++)
        if (ev->periodic[a]) {
            double cap = 0.5 * (0.5 * ev->len[a] - ev->sigma_max) * (1 - 1e-6);
            if (shell > cap)
                shell = cap;
        }
    ev->shell = shell;
    ev->nbr_reach = 0.5 * shell * (1 - 1e-9); /* expire a hair early: rounding never matters */

    /* 3. cells at least sigma_max + shell wide (index order), counters, lists, calendar */
    size_t ncells = 1;
    const double wmin = ev->sigma_max + shell;
    for (int a = 0; a < 3; a++) {
        if (a < d) {
            double k = floor(ev->len[a] / wmin);
            if (k < 1)
                k = 1;
            if (k > 1 << 20)
                k = 1 << 20;
            ev->ncell[a] = (int)k;
            ev->cell_w[a] = ev->len[a] / ev->ncell[a];
        } else {
            ev->ncell[a] = 1;
            ev->cell_w[a] = ev->len[a];
        }
        ev->cell_lo[a] = 0;
        ev->len_grid[a] = ev->len[a];
        ncells *= (size_t)ev->ncell[a];
    }
    /* keep the grid at most a few cells per particle */
    while (ncells > 8 * (size_t)n + 64) {
        int amax = 0;
        for (int a = 1; a < d; a++)
            if (ev->ncell[a] > ev->ncell[amax])
                amax = a;
        ev->ncell[amax] = (ev->ncell[amax] + 1) / 2;
        ev->cell_w[amax] = ev->len[amax] / ev->ncell[amax];
        ncells = (size_t)ev->ncell[0] * ev->ncell[1] * ev->ncell[2];
    }
    /* blocks wide enough for the fullest cell with room to spare (they widen if needed) */
    for (uint32_t i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++)
            C[i].r_ref[a] = P[i].r[a];
        P[i].flags = ref_flags(ev, i, C[i].r_ref);
        P[i].count = 0;
        C[i].cell = cell_index(ev, C[i].r_ref);
    }
    uint32_t *fill = calloc(ncells, sizeof *fill), most = 0;
    if (!fill)
        return mote_fail(err, MOTE_ENOMEM, "out of memory for %zu cells", ncells);
    for (uint32_t i = 0; i < n; i++)
        if (++fill[C[i].cell] > most)
            most = fill[C[i].cell];
    free(fill);
    const uint32_t stride = most + most / 4 + 3; /* the count, the fullest cell, a margin */
    if (cell_blocks(ev, ncells, stride, 0))
        return mote_fail(err, MOTE_ENOMEM, "out of memory for %zu cells", ncells);
    for (size_t c = 0; c < ncells; c++)
        ev->cell_block[c * stride] = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t *B = cell_members(ev, C[i].cell);
        B[++B[0]] = i;
    }
    int rc = nbr_build_all(ev, err);
    if (rc)
        return rc;

    /* automatic rebuild horizon: 64 R / v_rms with v_rms from sum m v^2 / sum m */
    mote_ksum mv2 = {0, 0}, msum = {0, 0};
    for (uint32_t i = 0; i < n; i++) {
        double m = mote_ev_mass(ev, i), v2 = 0;
        for (int a = 0; a < d; a++)
            v2 += P[i].v[a] * P[i].v[a];
        mote_ksum_add(&mv2, m * v2);
        mote_ksum_add(&msum, m);
    }
    double vrms = sqrt(mote_ksum_value(&mv2) / mote_ksum_value(&msum));
    ev->t_rebuild = vrms > 0 ? 64.0 * (0.5 * ev->sigma_max) / vrms : INFINITY;

    /* 4. predict in index order, then fill the calendar in index order */
    for (uint32_t i = 0; i < n; i++)
        predict(ev, i);
    rc = cal_init(ev, err);
    ev->ready = ev->canonical = rc == MOTE_OK;
    return rc;
}

/* The error of an engine that is not ready (see mote_ev_rebuild). */
static int not_ready(mote_err *err, const char *what)
{
    return mote_fail(err, MOTE_ERUNTIME,
                     "%s: the event engine has no valid neighbour lists or calendar (never "
                     "built, or its last rebuild failed); rebuild it first", what);
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

int mote_ev_move_walls(mote_ev *ev, int axis, double shift, double new_len, mote_err *err)
{
    if (axis < 0 || axis >= ev->dim || ev->periodic[axis])
        return mote_fail(err, MOTE_EINVAL, "move_walls: axis %d has no walls", axis);
    if (!ev->ready)
        return not_ready(err, "move_walls");
    ev->canonical = 0;
    for (uint32_t i = 0; i < ev->n; i++) {
        ev->p[i].r[axis] -= shift;
        ev->pc[i].r_ref[axis] -= shift;
    }
    ev->len[axis] = new_len;
    double lo = ev->cell_lo[axis] - shift;
    if (lo > 0 || lo + ev->len_grid[axis] < new_len)
        return mote_ev_rebuild(ev, err); /* the grid no longer covers the box */
    ev->cell_lo[axis] = lo;
    for (uint32_t i = 0; i < ev->n; i++) /* the walls' distances changed */
        ev->p[i].flags = ref_flags(ev, i, ev->pc[i].r_ref);
    /* Re-predict the particles that can reach a wall before their list expires (reference
     * within half a shell of a contact plane: predict looks at walls only for those), and any
     * whose scheduled event is a wall hit. No other prediction can involve a wall. */
    const double reach = 0.5 * ev->shell;
    for (uint32_t i = 0; i < ev->n; i++) {
        mote_particle *p = &ev->p[i];
        double R = mote_ev_radius(ev, i), x = ev->pc[i].r_ref[axis];
        if (x - R <= reach || new_len - R - x <= reach || p->kind == MOTE_EV_WALL) {
            double dt = ev->clock - p->t;
            for (int a = 0; a < ev->dim; a++)
                p->r[a] += p->v[a] * dt;
            p->t = ev->clock;
            cal_remove(ev, i);
            predict(ev, i);
            cal_insert(ev, i);
        }
    }
    return MOTE_OK;
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
        int nc = cell_neighbours(ev, C[i].cell, cells);
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

int mote_ev_check(const mote_ev *ev, mote_err *err)
{
    const int d = ev->dim;
    const mote_particle *P = ev->p;
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

    const double tol = 1e-10 * ev->sigma_max;
    const size_t ncells = (size_t)ev->ncell[0] * ev->ncell[1] * ev->ncell[2];
    uint8_t *listed = calloc(ev->n, 1); /* times each particle appears in a cell block */
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
    /* cell blocks: each holds exactly the particles that say they are in it, once */
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
    /* neighbour lists: symmetric, no repeats, no stale entry, none missing (spec 6.6) */
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
            int nc = cell_neighbours(ev, C[i].cell, cells);
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
    /* calendar: heap positions and order, bucket lists, every particle exactly once */
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
    /* conserved quantities */
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
