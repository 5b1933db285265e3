/* internal.h: what the files of the event engine share and nobody else needs: its tuning
 * constants, the small functions of the calendar, the cells and the neighbour lists that the hot
 * path inlines, and the engine's internal functions. The files: engine.c (storage and the state's
 * measurements), calendar.c (the calendar's buckets), rebuild.c (cells, lists and spatial order
 * built afresh; moving walls), step.c (the event loop), check.c (the invariant checker). */
#ifndef MOTE_EVENT_INTERNAL_H
#define MOTE_EVENT_INTERNAL_H

#include "mote/event.h"

#include "roots.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* The shell delta of the neighbour lists in units of the largest contact distance, and the
 * number of events the calendar aims to keep in its heap (spec 6.5: 10 to 50). Both only trade
 * list expiries against candidates and list moves against sifting; the first changes rounding
 * (so trajectories), the second never changes the event sequence. */
#ifndef SHELL_FRACTION
#define SHELL_FRACTION 0.5
#endif
#define HEAP_TARGET 24.0
/* A list renewal copies a neighbouring cell's members as one block of this many words (see
 * refresh in step.c); cells with more take a loop. */
#define GATHER_WORDS 8
/* A prediction asks for the record of the list entry this many places ahead of the one it
 * tests; the list array has this many words of padding at its end, so that read stays inside
 * it even for the last list. */
#define PREFETCH_AHEAD 4
#define FIELD_NEIGHBOURS 12.0

/* ---- internal functions (prefix ev_) ---------------------------------------------------------- */

/* Ask for transparent huge pages on a large array (a hint only; engine.c). */
void ev_hint_huge_pages(void *p, size_t bytes);
/* Move the next bucket's events into the heap (calendar.c). */
int ev_cal_refill(mote_ev *ev);
/* Size the calendar for the current events and file every particle (calendar.c). */
int ev_cal_init(mote_ev *ev, mote_err *err);
/* (Re)allocate the cell blocks (rebuild.c). */
int ev_cell_blocks(mote_ev *ev, size_t ncells, uint32_t stride, size_t keep);
/* The distinct neighbouring cells of a cell (rebuild.c). */
int ev_cell_neighbours(const mote_ev *ev, int32_t cell, int32_t out[27]);
/* Double the capacity of every neighbour list (rebuild.c). */
int ev_nbr_grow(mote_ev *ev);
/* Predict particle i's next event with the build for its mode and dimension (step.c). */
void ev_predict(mote_ev *ev, uint32_t i);


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

static inline void heap_sift_up(mote_ev *ev, uint32_t k)
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

static inline void heap_sift_down(mote_ev *ev, uint32_t k)
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

/* Move particle i from its cell to `cell`. The blocks widen first if `cell` is full; if that
 * fails nothing has changed. */
static inline int cell_move(mote_ev *ev, uint32_t i, int32_t cell)
{
    if (cell_members(ev, cell)[0] + 1 >= ev->cell_stride) {
        size_t ncells = (size_t)ev->ncell[0] * ev->ncell[1] * ev->ncell[2];
        if (ev->cell_stride > UINT32_MAX / 2 ||
            ev_cell_blocks(ev, ncells, ev->cell_stride + ev->cell_stride / 2 + 1, ncells))
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

static inline int nbr_add_pair(mote_ev *ev, uint32_t i, uint32_t j)
{
    mote_particle *P = ev->p;
    if (P[i].nnbr >= ev->nbr_cap || P[j].nnbr >= ev->nbr_cap) {
        int rc = ev_nbr_grow(ev);
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
    if (ev->p[j].nnbr >= ev->nbr_cap && ev_nbr_grow(ev))
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
static inline void nbr_renewed(mote_ev *ev, uint32_t i, uint32_t nold, uint32_t nnew)
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

static inline double wrap_coord(double x, double len)
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

/* The error of an engine that is not ready (see mote_ev_rebuild). */
static inline int not_ready(mote_err *err, const char *what)
{
    return mote_fail(err, MOTE_ERUNTIME,
                     "%s: the event engine has no valid neighbour lists or calendar (never "
                     "built, or its last rebuild failed); rebuild it first", what);
}

#endif
