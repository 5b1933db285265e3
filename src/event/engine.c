/* engine.c: the event-driven engine for hard spheres and disks: storage, the cell grid, the event
 * calendar (an indexed binary min-heap on the total key (time, index)), synchronisation
 * (rebuilds), conserved quantities and the invariant checker. The per-event hot path lives in
 * engine_dim.inc and is compiled once for 2D and once for 3D below. */
#include "mote/event.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- calendar --------------------------------------------------------------------------------- */

static inline int ev_before(const mote_particle *P, uint32_t a, uint32_t b)
{
    double ta = P[a].t_ev, tb = P[b].t_ev;
    return ta < tb || (ta == tb && a < b);
}

static void heap_sift_up(mote_ev *ev, uint32_t k)
{
    uint32_t *H = ev->heap;
    mote_particle *P = ev->p;
    uint32_t x = H[k];
    while (k > 0) {
        uint32_t parent = (k - 1) / 2;
        if (!ev_before(P, x, H[parent]))
            break;
        H[k] = H[parent];
        P[H[k]].heap_pos = k;
        k = parent;
    }
    H[k] = x;
    P[x].heap_pos = k;
}

static void heap_sift_down(mote_ev *ev, uint32_t k)
{
    uint32_t *H = ev->heap;
    mote_particle *P = ev->p;
    uint32_t n = ev->n, x = H[k];
    for (;;) {
        uint32_t c = 2 * k + 1;
        if (c >= n)
            break;
        if (c + 1 < n && ev_before(P, H[c + 1], H[c]))
            c++;
        if (!ev_before(P, H[c], x))
            break;
        H[k] = H[c];
        P[H[k]].heap_pos = k;
        k = c;
    }
    H[k] = x;
    P[x].heap_pos = k;
}

static inline void heap_update(mote_ev *ev, uint32_t i)
{
    uint32_t k = ev->p[i].heap_pos;
    if (k > 0 && ev_before(ev->p, i, ev->heap[(k - 1) / 2]))
        heap_sift_up(ev, k);
    else
        heap_sift_down(ev, k);
}

/* ---- cells -------------------------------------------------------------------------------------- */

static void cell_unlink(mote_ev *ev, uint32_t i)
{
    mote_particle *p = &ev->p[i];
    if (p->cprev >= 0)
        ev->p[p->cprev].cnext = p->cnext;
    else
        ev->cell_head[p->cell] = p->cnext;
    if (p->cnext >= 0)
        ev->p[p->cnext].cprev = p->cprev;
}

static void cell_link(mote_ev *ev, uint32_t i, int32_t cell)
{
    mote_particle *p = &ev->p[i];
    p->cell = cell;
    p->cprev = -1;
    p->cnext = ev->cell_head[cell];
    if (p->cnext >= 0)
        ev->p[p->cnext].cprev = (int32_t)i;
    ev->cell_head[cell] = (int32_t)i;
}

/* Move i to the neighbouring cell along axis a; on a periodic axis crossing the outer face wraps
 * the coordinate by one box length. */
static void cell_move(mote_ev *ev, uint32_t i, int a, int up)
{
    mote_particle *p = &ev->p[i];
    int32_t c = p->cell;
    int32_t stride = 1;
    for (int b = 0; b < a; b++)
        stride *= ev->ncell[b];
    int ca = (c / stride) % ev->ncell[a];
    int nc = up ? ca + 1 : ca - 1;
    if (nc >= ev->ncell[a]) {
        nc = 0;
        p->r[a] -= ev->len[a];
    } else if (nc < 0) {
        nc = ev->ncell[a] - 1;
        p->r[a] += ev->len[a];
    }
    cell_unlink(ev, i);
    cell_link(ev, i, c + (nc - ca) * stride);
}

/* ---- the hot loop, instantiated for 2D and 3D --------------------------------------------------- */

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
    ev->p = calloc(n, sizeof *ev->p);
    ev->heap = calloc(n, sizeof *ev->heap);
    if (polydisperse) {
        ev->radius = calloc(n, sizeof *ev->radius);
        ev->mass = calloc(n, sizeof *ev->mass);
    }
    if (!ev->p || !ev->heap || (polydisperse && (!ev->radius || !ev->mass))) {
        mote_ev_free(ev);
        return mote_fail(err, MOTE_ENOMEM, "out of memory for %u particles", n);
    }
    return MOTE_OK;
}

void mote_ev_free(mote_ev *ev)
{
    free(ev->p);
    free(ev->heap);
    free(ev->radius);
    free(ev->mass);
    free(ev->cell_head);
    memset(ev, 0, sizeof *ev);
}

static double wrap_coord(double x, double len)
{
    while (x < 0)
        x += len;
    while (x >= len)
        x -= len;
    return x;
}

int mote_ev_rebuild(mote_ev *ev, mote_err *err)
{
    const int d = ev->dim;
    const uint32_t n = ev->n;
    mote_particle *P = ev->p;

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
        double dt = ev->clock - p->t;
        for (int a = 0; a < d; a++) {
            p->r[a] += p->v[a] * dt;
            if (ev->periodic[a])
                p->r[a] = wrap_coord(p->r[a], ev->len[a]);
        }
        p->t = 0;
    }
    ev->time_total += ev->clock;
    ev->clock = 0;

    /* 3. cells (index order), counters, calendar */
    size_t ncells = 1;
    for (int a = 0; a < 3; a++) {
        if (a < d) {
            double k = floor(ev->len[a] / ev->sigma_max);
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
    if (ncells > ev->ncells_alloc) {
        int32_t *h = realloc(ev->cell_head, ncells * sizeof *h);
        if (!h)
            return mote_fail(err, MOTE_ENOMEM, "out of memory for %zu cells", ncells);
        ev->cell_head = h;
        ev->ncells_alloc = ncells;
    }
    for (size_t c = 0; c < ncells; c++)
        ev->cell_head[c] = -1;
    for (uint32_t i = 0; i < n; i++) {
        int32_t lin = 0, stride = 1;
        for (int a = 0; a < d; a++) {
            int k = (int)floor(P[i].r[a] / ev->cell_w[a]);
            if (k < 0)
                k = 0;
            if (k >= ev->ncell[a])
                k = ev->ncell[a] - 1;
            lin += k * stride;
            stride *= ev->ncell[a];
        }
        P[i].count = 0;
        cell_link(ev, i, lin);
    }

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

    /* 4. predict in index order; the heap is built by insertion in index order */
    for (uint32_t i = 0; i < n; i++) {
        if (d == 2)
            predict_2d(ev, i);
        else
            predict_3d(ev, i);
        ev->heap[i] = i;
        P[i].heap_pos = i;
        heap_sift_up(ev, i);
    }
    return MOTE_OK;
}

int mote_ev_run(mote_ev *ev, uint64_t ncoll, mote_err *err)
{
    if (ncoll == 0)
        return MOTE_OK;
    return ev->dim == 2 ? run_2d(ev, ncoll, err) : run_3d(ev, ncoll, err);
}

/* ---- measurements of the state ---------------------------------------------------------------- */

void mote_ev_position(const mote_ev *ev, uint32_t i, double out[3])
{
    const mote_particle *p = &ev->p[i];
    double dt = ev->clock - p->t;
    out[2] = 0;
    for (int a = 0; a < ev->dim; a++) {
        out[a] = p->r[a] + p->v[a] * dt;
        if (ev->periodic[a])
            out[a] = wrap_coord(out[a], ev->len[a]);
    }
}

double mote_ev_energy(const mote_ev *ev)
{
    mote_ksum e = {0, 0};
    for (uint32_t i = 0; i < ev->n; i++) {
        double v2 = 0;
        for (int a = 0; a < ev->dim; a++)
            v2 += ev->p[i].v[a] * ev->p[i].v[a];
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
    for (uint32_t i = 0; i < ev->n; i++)
        for (int a = 0; a < ev->dim; a++)
            ev->p[i].v[a] *= f;
}

int mote_ev_move_walls(mote_ev *ev, int axis, double shift, double new_len, mote_err *err)
{
    if (axis < 0 || axis >= ev->dim || ev->periodic[axis])
        return mote_fail(err, MOTE_EINVAL, "move_walls: axis %d has no walls", axis);
    for (uint32_t i = 0; i < ev->n; i++)
        ev->p[i].r[axis] -= shift;
    ev->len[axis] = new_len;
    double lo = ev->cell_lo[axis] - shift;
    if (lo > 0 || lo + ev->len_grid[axis] < new_len)
        return mote_ev_rebuild(ev, err); /* the grid no longer covers the box */
    ev->cell_lo[axis] = lo;
    /* re-predict the particles whose cell can hold a wall contact plane */
    const double rmax = 0.5 * ev->sigma_max, w = ev->cell_w[axis];
    int32_t stride = 1;
    for (int b = 0; b < axis; b++)
        stride *= ev->ncell[b];
    for (uint32_t i = 0; i < ev->n; i++) {
        mote_particle *p = &ev->p[i];
        int k = (p->cell / stride) % ev->ncell[axis];
        double face_lo = lo + k * w;
        double face_hi = k + 1 == ev->ncell[axis] ? lo + ev->len_grid[axis] : face_lo + w;
        if (face_lo < rmax || face_hi > new_len - rmax) {
            double dt = ev->clock - p->t;
            for (int a = 0; a < ev->dim; a++)
                p->r[a] += p->v[a] * dt;
            p->t = ev->clock;
            if (ev->dim == 2)
                predict_2d(ev, i);
            else
                predict_3d(ev, i);
            heap_update(ev, i);
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
    double bytes = (double)ev->n * (sizeof(mote_particle) + sizeof(uint32_t));
    if (ev->radius)
        bytes += (double)ev->n * 2 * sizeof(double);
    bytes += (double)ev->ncells_alloc * sizeof(int32_t);
    return bytes / ev->n;
}

/* ---- invariant checker --------------------------------------------------------------------------- */

/* Visit every unordered pair (i < j by index, each minimum image once) that lies in neighbouring
 * cells, with positions projected to the clock. */
typedef void (*pair_fn)(void *ctx, uint32_t i, uint32_t j, double dist, double sigma);

static void for_near_pairs(const mote_ev *ev, pair_fn fn, void *ctx)
{
    const int d = ev->dim;
    const mote_particle *P = ev->p;
    for (uint32_t i = 0; i < ev->n; i++) {
        double ri[3];
        double dti = ev->clock - P[i].t;
        for (int a = 0; a < 3; a++)
            ri[a] = P[i].r[a] + P[i].v[a] * dti;
        int cc[3];
        int32_t c = P[i].cell;
        cc[0] = c % ev->ncell[0];
        c /= ev->ncell[0];
        cc[1] = c % ev->ncell[1];
        cc[2] = c / ev->ncell[1];
        int lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
        for (int a = 0; a < d; a++) {
            lo[a] = -1;
            hi[a] = 1;
            if (!ev->periodic[a]) {
                if (cc[a] == 0)
                    lo[a] = 0;
                if (cc[a] == ev->ncell[a] - 1)
                    hi[a] = 0;
            }
        }
        for (int oz = lo[2]; oz <= hi[2]; oz++)
            for (int oy = lo[1]; oy <= hi[1]; oy++)
                for (int ox = lo[0]; ox <= hi[0]; ox++) {
                    int o[3] = {ox, oy, oz}, nc[3];
                    double s[3] = {0, 0, 0};
                    for (int a = 0; a < 3; a++) {
                        nc[a] = cc[a] + o[a];
                        if (nc[a] < 0) {
                            nc[a] += ev->ncell[a];
                            s[a] = -ev->len[a];
                        } else if (nc[a] >= ev->ncell[a]) {
                            nc[a] -= ev->ncell[a];
                            s[a] = ev->len[a];
                        }
                    }
                    int32_t cell = (nc[2] * ev->ncell[1] + nc[1]) * ev->ncell[0] + nc[0];
                    for (int32_t j = ev->cell_head[cell]; j >= 0; j = P[j].cnext) {
                        if ((uint32_t)j <= i)
                            continue;
                        double dtj = ev->clock - P[j].t, r2 = 0;
                        for (int a = 0; a < d; a++) {
                            double dx = ri[a] - (P[j].r[a] + P[j].v[a] * dtj + s[a]);
                            r2 += dx * dx;
                        }
                        double sig = mote_ev_radius(ev, i) + mote_ev_radius(ev, (uint32_t)j);
                        if (r2 < 4 * sig * sig)
                            fn(ctx, i, (uint32_t)j, sqrt(r2), sig);
                    }
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
    int nfail = 0;
    if (err) {
        err->msg[0] = '\0';
        err->located = 0;
    }

    gap_acc g = {INFINITY, 0, 0, 0};
    for_near_pairs(ev, gap_visit, &g);
    if (g.overlaps)
        add_failure(err, &nfail, "%zu overlapping pairs; worst %u-%u at %.17g of contact",
                    g.overlaps, g.worst_i, g.worst_j, g.min_ratio);

    const double tol = 1e-10 * ev->sigma_max;
    size_t *cell_count = calloc(ev->ncells_alloc ? ev->ncells_alloc : 1, sizeof *cell_count);
    for (uint32_t i = 0; i < ev->n; i++) {
        double r[3];
        double dt = ev->clock - P[i].t;
        for (int a = 0; a < 3; a++)
            r[a] = P[i].r[a] + P[i].v[a] * dt;
        double Ri = mote_ev_radius(ev, i);
        int32_t c = P[i].cell;
        int cc[3] = {c % ev->ncell[0], (c / ev->ncell[0]) % ev->ncell[1],
                     c / (ev->ncell[0] * ev->ncell[1])};
        for (int a = 0; a < d; a++) {
            if (!ev->periodic[a] &&
                (r[a] < Ri * (1 - 1e-10) || r[a] > ev->len[a] - Ri * (1 - 1e-10)))
                add_failure(err, &nfail, "particle %u at %c = %.17g is outside the walls [%g, %g]",
                            i, "xyz"[a], r[a], Ri, ev->len[a] - Ri);
            double lo = ev->cell_lo[a] + cc[a] * ev->cell_w[a], hi = lo + ev->cell_w[a];
            if (r[a] < lo - tol || r[a] > hi + tol)
                add_failure(err, &nfail, "particle %u at %c = %.17g is outside its cell [%g, %g]",
                            i, "xyz"[a], r[a], lo, hi);
        }
        if (P[i].t_ev < ev->clock)
            add_failure(err, &nfail, "particle %u has an event at %.17g before the clock %.17g", i,
                        P[i].t_ev, ev->clock);
        if (P[i].heap_pos >= ev->n || ev->heap[P[i].heap_pos] != i)
            add_failure(err, &nfail, "particle %u is not in the calendar where it should be", i);
        if (cell_count && (size_t)c < ev->ncells_alloc)
            cell_count[c]++;
    }
    /* calendar: heap order */
    for (uint32_t k = 1; k < ev->n; k++)
        if (ev_before(P, ev->heap[k], ev->heap[(k - 1) / 2]))
            add_failure(err, &nfail, "calendar order broken at slot %u", k);
    /* cell lists: every list holds exactly the particles that say they are in it */
    if (cell_count) {
        size_t ncells = (size_t)ev->ncell[0] * ev->ncell[1] * ev->ncell[2];
        for (size_t c = 0; c < ncells; c++) {
            size_t k = 0;
            int32_t prev = -1;
            for (int32_t j = ev->cell_head[c]; j >= 0 && k <= ev->n; j = P[j].cnext, k++) {
                if (P[j].cell != (int32_t)c || P[j].cprev != prev)
                    add_failure(err, &nfail, "cell list %zu is inconsistent at particle %d", c, j);
                prev = j;
            }
            if (k != cell_count[c])
                add_failure(err, &nfail, "cell %zu lists %zu particles but %zu belong to it", c, k,
                            cell_count[c]);
        }
        free(cell_count);
    }
    /* conserved quantities */
    double e = mote_ev_energy(ev);
    if (ev->energy_ref > 0 && fabs(e - ev->energy_ref) > 1e-12 * ev->energy_ref)
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
