/* rebuild.c: everything the engine builds afresh (spec 6.7): the cell blocks, the neighbour
 * lists of every particle, the records renumbered in spatial order, the full synchronisation of
 * mote_ev_rebuild, and moving walls without a rebuild. */
#include "internal.h"


/* Give the grid blocks of `stride` words for `ncells` cells; the members of the first `keep`
 * cells move along when the stride widens. */
int ev_cell_blocks(mote_ev *ev, size_t ncells, uint32_t stride, size_t keep)
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
        ev_hint_huge_pages(b, words * sizeof *b);
        memset(b + words - GATHER_WORDS, 0, GATHER_WORDS * sizeof *b);
    }
    if (keep && stride > old) /* last first: a block only ever moves up */
        for (size_t c = keep; c-- > 0;)
            memmove(ev->cell_block + c * stride, ev->cell_block + c * old,
                    ((size_t)ev->cell_block[c * old] + 1) * sizeof(uint32_t));
    ev->cell_stride = stride;
    return MOTE_OK;
}

/* The distinct cells next to (and including) `cell`: 3 per axis, or all of them on an axis of
 * fewer than 3 cells (where -1 and +1 would name the same cell twice); on a wall axis nothing
 * beyond the grid. Returns how many were written to out[27]. */
int ev_cell_neighbours(const mote_ev *ev, int32_t cell, int32_t out[27])
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

/* Make room for more entries per particle (rare: lists are sized at each rebuild). The lists
 * move to a wider stride; their content and order are unchanged, so the trajectory is too. */
int ev_nbr_grow(mote_ev *ev)
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
    ev_hint_huge_pages(b, (size_t)ev->n * cap * sizeof *b);
    return MOTE_OK;
}

/* Neighbour lists of every particle, in index order, with storage sized from an exact count. */
static int ev_nbr_build_all(mote_ev *ev, mote_err *err)
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
        int nc = ev_cell_neighbours(ev, C[i].cell, cells);
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
        ev_hint_huge_pages(b, (size_t)n * cap * sizeof *b);
    }
    /* pass 2: fill */
    for (uint32_t i = 0; i < n; i++)
        P[i].nnbr = 0;
    for (uint32_t i = 0; i < n; i++) {
        int nc = ev_cell_neighbours(ev, C[i].cell, cells);
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

/* The shell: SHELL_FRACTION of the contact distance, but small enough on short periodic axes
 * that sigma_max + 2 shell < len / 2, so a listed pair is always seen through one image (its
 * minimum image) until either list expires. */
static double rebuild_shell(const mote_ev *ev)
{
    const int d = ev->dim;
    double shell = SHELL_FRACTION * ev->sigma_max;
    if (ev->field) {
        /* field-mode systems are often dilute (a gas in a box): there a shell of half a
         * diameter expires dozens of times per free flight. Widen it until a list holds about
         * FIELD_NEIGHBOURS particles at the mean density, within a quarter of the box. */
        double area = ev->len[0] * ev->len[1];
        double wide = sqrt(FIELD_NEIGHBOURS * area / (MOTE_PI * ev->n)) - ev->sigma_max;
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
    return shell;
}

/* 3. Cells at least sigma_max + shell wide (at most a few per particle), each particle's
 * reference, flags, counter and cell, the cells' blocks wide enough for the fullest cell with
 * room to spare (they widen if needed). */
static int rebuild_cells(mote_ev *ev, mote_err *err)
{
    const int d = ev->dim;
    const uint32_t n = ev->n;
    mote_particle *P = ev->p;
    mote_ev_cold *C = ev->pc;
    size_t ncells = 1;
    const double wmin = ev->sigma_max + ev->shell;
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
    while (ncells > 8 * (size_t)n + 64) {
        int amax = 0;
        for (int a = 1; a < d; a++)
            if (ev->ncell[a] > ev->ncell[amax])
                amax = a;
        ev->ncell[amax] = (ev->ncell[amax] + 1) / 2;
        ev->cell_w[amax] = ev->len[amax] / ev->ncell[amax];
        ncells = (size_t)ev->ncell[0] * ev->ncell[1] * ev->ncell[2];
    }
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
    if (ev_cell_blocks(ev, ncells, stride, 0))
        return mote_fail(err, MOTE_ENOMEM, "out of memory for %zu cells", ncells);
    for (size_t c = 0; c < ncells; c++)
        ev->cell_block[c * stride] = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t *B = cell_members(ev, C[i].cell);
        B[++B[0]] = i;
    }
    return MOTE_OK;
}

/* The automatic rebuild horizon: 64 R / v_rms with v_rms from sum m v^2 / sum m, or 16 shells
 * where the shell was widened (a dilute field-mode gas): tied to the radius alone, ten tiny
 * fast disks in a large box rebuilt 10^11 times a simulated second, each rebuild costing more
 * than the few events between two. */
static double rebuild_horizon(const mote_ev *ev)
{
    mote_ksum mv2 = {0, 0}, msum = {0, 0};
    for (uint32_t i = 0; i < ev->n; i++) {
        double m = mote_ev_mass(ev, i), v2 = 0;
        for (int a = 0; a < ev->dim; a++)
            v2 += ev->p[i].v[a] * ev->p[i].v[a];
        mote_ksum_add(&mv2, m * v2);
        mote_ksum_add(&msum, m);
    }
    double vrms = sqrt(mote_ksum_value(&mv2) / mote_ksum_value(&msum));
    const double horizon = fmax(32.0 * ev->sigma_max, 16.0 * ev->shell);
    return vrms > 0 ? horizon / vrms : INFINITY;
}

int mote_ev_rebuild(mote_ev *ev, mote_err *err)
{
    const int d = ev->dim;
    const uint32_t n = ev->n;
    mote_particle *P = ev->p;
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

    const double shell = rebuild_shell(ev);
    ev->shell = shell;
    ev->nbr_reach = 0.5 * shell * (1 - 1e-9); /* expire a hair early: rounding never matters */

    int rc = rebuild_cells(ev, err);
    if (rc)
        return rc;
    if ((rc = ev_nbr_build_all(ev, err)))
        return rc;

    ev->t_rebuild = rebuild_horizon(ev);

    /* 4. predict in index order, then fill the calendar in index order */
    for (uint32_t i = 0; i < n; i++)
        ev_predict(ev, i);
    rc = ev_cal_init(ev, err);
    ev->ready = ev->canonical = rc == MOTE_OK;
    return rc;
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
            ev_predict(ev, i);
            cal_insert(ev, i);
        }
    }
    return MOTE_OK;
}
