/* dem.c: the separator's soft-sphere contacts (specs/separator.md 2.8, 2.9): the core's cell
 * grid (grid.h) with edges of at least d_max, sorted again at each search; the pair loop over a
 * half stencil (each pair once); linear spring-dashpot forces between particles and with the
 * side walls and closed ends, frictionless; the stiffness from an allowed overlap and the time
 * step from the shortest contact. */
#include "mote/separator.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sep.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif


/* zeta(e) = -ln e / sqrt(pi^2 + ln^2 e): the damping ratio giving restitution e */
static double zeta_of(double e)
{
    const double l = log(e);
    return -l / sqrt(SEP_PI * SEP_PI + l * l);
}

/* The impact speed the contacts are sized for: vimp=, else the largest of U0, the largest
 * terminal velocity and the feed's speed, else 1 m/s. */
static double impact_speed(const mote_sep_system *s)
{
    double vt = 0;
    for (int k = 0; k < s->nsp; k++) {
        const double v = mote_sep_terminal_velocity(mote_sep_dist_max(&s->sp[k].dist),
                                                    s->sp[k].rho, s->rho_g, s->mu_g, s->g, NULL);
        if (isfinite(v))
            vt = fmax(vt, v);
    }
    const double vf = sqrt(s->vf[0] * s->vf[0] + s->vf[1] * s->vf[1] + s->vf[2] * s->vf[2]);
    const double vimp = s->v_imp > 0 ? s->v_imp : fmax(fmax(s->U0, vt), vf);
    return vimp > 0 ? vimp : 1; /* nothing moves: any stiffness; 1 m/s */
}

double mote_sep_khat(const mote_sep_system *s)
{
    if (s->khat > 0)
        return s->khat;
    double rho_max = 0;
    for (int k = 0; k < s->nsp; k++)
        rho_max = fmax(rho_max, s->sp[k].rho);
    const double vimp = impact_speed(s);
    const double df = s->delta_f > 0 ? s->delta_f : 0.05;
    return SEP_PI * rho_max * vimp * vimp / (6 * df * df);
}

/* contact hertz: the shortest Hertz contact time at the impact speed, over the pairs of
 * species (each at its smallest size) and each species at a wall. */
static double hertz_tc_min(const mote_sep_system *s)
{
    const double v = impact_speed(s);
    double tc = INFINITY;
    for (int a = 0; a < s->nsp; a++) {
        const sep_material A = {s->sp[a].E, s->sp[a].nu};
        const double ra = 0.5 * mote_sep_dist_min(&s->sp[a].dist);
        const double ma = s->sp[a].rho * SEP_PI / 6 * 8 * ra * ra * ra;
        for (int b = a; b < s->nsp; b++) {
            const sep_material B = {s->sp[b].E, s->sp[b].nu};
            const double rb = 0.5 * mote_sep_dist_min(&s->sp[b].dist);
            const double mb = s->sp[b].rho * SEP_PI / 6 * 8 * rb * rb * rb;
            sep_hm h;
            sep_hm_pair(&h, &A, ra, ma, &B, rb, mb, 1, 0);
            tc = fmin(tc, sep_hm_contact_time(h.Y, h.R, h.m, v));
        }
        const sep_material Wm = {s->E_w > 0 ? s->E_w : A.E, s->E_w > 0 ? s->nu_w : A.nu};
        sep_hm h;
        sep_hm_pair(&h, &A, ra, ma, &Wm, INFINITY, INFINITY, 1, 0);
        tc = fmin(tc, sep_hm_contact_time(h.Y, h.R, h.m, v));
    }
    return tc;
}

double mote_sep_dt_limit(const mote_sep_system *s)
{
    if (s->hertz)
        return hertz_tc_min(s) / (s->nc > 0 ? s->nc : 50);
    double rho_min = INFINITY, dmin, dmax;
    mote_sep_size_range(s, &dmin, &dmax);
    for (int k = 0; k < s->nsp; k++)
        rho_min = fmin(rho_min, s->sp[k].rho);
    const double w2 = 12 * mote_sep_khat(s) / (SEP_PI * rho_min * dmin * dmin);
    return SEP_PI / sqrt(w2) / (s->nc > 0 ? s->nc : 50);
}

/* ---- cells ---------------------------------------------------------------------------------- */

/* The channel's axes on the grid's: x, y, z in 3D; x, z in 2D. */
static void grid_coords(const mote_sep_system *s, const double *c[3])
{
    c[0] = s->x;
    c[1] = s->dim == 3 ? s->y : s->z;
    c[2] = s->dim == 3 ? s->z : NULL;
}

int sep_cells_build(mote_sep_system *s, mote_err *err)
{
    double dmin, dmax;
    mote_sep_size_range(s, &dmin, &dmax);
    s->skin_used = s->brute || s->skin < 0 ? 0 : s->skin > 0 ? s->skin : 0.3 * dmin;
    const double h = dmax + s->skin_used; /* the cells serve the pair list's reach too */
    const double lo[3] = {0, 0, 0};
    const double len[3] = {s->W, s->dim == 3 ? s->D : s->H, s->dim == 3 ? s->H : 1};
    const int walls[3] = {0, 0, 0};
    if (s->n >= UINT32_MAX)
        return mote_fail(err, MOTE_EINVAL, "separator: more than 2^32 - 1 particles");
    s->grid.no_pos = 1; /* (the searches read the particles' own arrays) */
    if (mote_grid_setup(&s->grid, s->dim, lo, len, walls, h, (uint32_t)s->n))
        return mote_fail(err, MOTE_ENOMEM, "separator: no cells for a channel %g x %g of "
                         "particles up to %g (out of memory, or not finite)", s->W, s->H, h);
    const size_t nc = s->grid.ncells;
    if (nc + 1 > s->nhead_cap) {
        int32_t *hd = realloc(s->nhead, (nc + 1) * sizeof *hd);
        if (!hd)
            return mote_fail(err, MOTE_ENOMEM, "separator: out of memory for %zu cells", nc);
        s->nhead = hd;
        s->nhead_cap = nc + 1;
    }
    memset(s->nhead, 0xff, (nc + 1) * sizeof *s->nhead); /* no particle added since: -1 */
    const double *c[3];
    grid_coords(s, c);
    mote_grid_build(&s->grid, (uint32_t)s->n, c, 1);
    s->n_built = s->n;
    s->built_step = s->steps + 1;
    return MOTE_OK;
}

int sep_cells_add(mote_sep_system *s, size_t i, mote_err *err)
{
    /* the cells were sized for the particles sorted into them (about one cell each): when the
     * additions outnumber those twice over, sort again, so that filling an empty channel costs
     * O(N) in all, not O(N^2) in a few large cells */
    if (s->n > 2 * s->n_built + 64)
        return sep_cells_build(s, err);
    if (i + 1 > s->nnext_cap) {
        const size_t cap = 2 * (i + 1);
        int32_t *p = realloc(s->nnext, cap * sizeof *p);
        if (!p)
            return mote_fail(err, MOTE_ENOMEM, "separator: out of memory for the cells");
        s->nnext = p;
        s->nnext_cap = cap;
    }
    const size_t c = sep_cell_of(s, i);
    s->nnext[i] = s->nhead[c];
    s->nhead[c] = (int32_t)i;
    return MOTE_OK;
}

/* The point (x, y, z) of the channel on the grid's axes (x, z in 2D). */
#define GRID_POINT(s, px, py, pz) {(px), (s)->dim == 3 ? (py) : (pz), (pz)}

int sep_overlaps_any(const mote_sep_system *s, double px, double py, double pz, double d)
{
#define SEP_TEST(j)                                                                               \
    do {                                                                                          \
        const double dx_ = s->x[j] - px, dy_ = s->dim == 3 ? s->y[j] - py : 0, dz_ = s->z[j] - pz; \
        const double R_ = 0.5 * (d + s->d[j]);                                                    \
        if (dx_ * dx_ + dy_ * dy_ + dz_ * dz_ < R_ * R_)                                          \
            return 1;                                                                             \
    } while (0)
    /* through the cells around the point (their edges are at least d_max): those there when
     * they were built, and those added since; the channel's axes have walls, no images */
    const mote_grid *g = &s->grid;
    const double at[3] = GRID_POINT(s, px, py, pz);
    int c0[3];
    mote_grid_coords(g, at, c0);
    int lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = c0[a] > 0 ? c0[a] - 1 : 0;
        hi[a] = c0[a] + 1 < g->nc[a] ? c0[a] + 1 : g->nc[a] - 1;
    }
    for (int k2 = lo[2]; k2 <= hi[2]; k2++)
        for (int k1 = lo[1]; k1 <= hi[1]; k1++)
            for (int k0 = lo[0]; k0 <= hi[0]; k0++) {
                const size_t c = ((size_t)k2 * (size_t)g->nc[1] + (size_t)k1) * (size_t)g->nc[0] +
                                 (size_t)k0;
                for (uint32_t p = g->start[c]; p < g->start[c + 1]; p++)
                    SEP_TEST(g->order[p]);
                for (int32_t j = s->nhead[c]; j >= 0; j = s->nnext[j])
                    SEP_TEST((size_t)j);
            }
#undef SEP_TEST
    return 0;
}

size_t sep_cell_of(const mote_sep_system *s, size_t i)
{
    const double at[3] = GRID_POINT(s, s->x[i], s->y[i], s->z[i]);
    return mote_grid_cell_of(&s->grid, at);
}

/* The overlap test, one expression for the cells and brute force (spec 2.9: the same floating
 * point), and the pair's distance vector and squared distance. */
static inline int overlap(const mote_sep_system *s, size_t i, size_t j, double dx[3], double *d2)
{
    dx[0] = s->x[j] - s->x[i];
    dx[1] = s->dim == 3 ? s->y[j] - s->y[i] : 0;
    dx[2] = s->z[j] - s->z[i];
    *d2 = dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2];
    const double R = 0.5 * (s->d[i] + s->d[j]);
    return *d2 < R * R;
}

/* The same test with the reach widened by the skin (for the pair list). */
static inline int near(const mote_sep_system *s, size_t i, size_t j, double skin)
{
    const double dx = s->x[j] - s->x[i], dy = s->dim == 3 ? s->y[j] - s->y[i] : 0,
                 dz = s->z[j] - s->z[i];
    const double R = 0.5 * (s->d[i] + s->d[j]) + skin;
    return dx * dx + dy * dy + dz * dz < R * R;
}

/* Call fn(s, i, j, dx, d2, ctx) for each pair in contact, i and j in any order, each once. */
typedef void (*pair_fn)(mote_sep_system *s, size_t i, size_t j, const double dx[3], double d2,
                        void *ctx);

/* Pairs closer than r_i + r_j: fn gets the overlap test's dx and d2. */
#define SEP_VISIT(i, j)                                                                           \
    do {                                                                                          \
        if (overlap(s, i, j, dx, &d2))                                                            \
            fn(s, i, j, dx, d2, ctx);                                                             \
    } while (0)

static void each_pair(mote_sep_system *s, int brute, pair_fn fn, void *ctx)
{
    double dx[3], d2;
    if (brute) {
        for (size_t i = 0; i < s->n; i++)
            for (size_t j = i + 1; j < s->n; j++)
                SEP_VISIT(i, j);
        s->candidates = (uint64_t)s->n * (s->n ? s->n - 1 : 0) / 2;
        return;
    }
    uint64_t cand = 0;
    /* the half stencil: the own cell (pairs within it once), then the forward neighbours:
     * 4 in 2D, 13 in 3D */
    static const int st2[4][3] = {{1, 0, 0}, {-1, 0, 1}, {0, 0, 1}, {1, 0, 1}};
    int st3[13][3], n3 = 0;
    for (int dz = 0; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dxx = -1; dxx <= 1; dxx++) {
                const int fwd = dz > 0 || (dz == 0 && (dy > 0 || (dy == 0 && dxx > 0)));
                if (fwd) {
                    st3[n3][0] = dxx;
                    st3[n3][1] = dy;
                    st3[n3][2] = dz;
                    n3++;
                }
            }
    const int ns = s->dim == 3 ? 13 : 4;
    /* the grid's cells in the channel's axes (2D: the grid's second axis is z) */
    const mote_grid *g = &s->grid;
    const int cx = g->nc[0], cy = s->dim == 3 ? g->nc[1] : 1, cz = g->nc[s->dim == 3 ? 2 : 1];
    const uint32_t *start = g->start, *idx = g->order;
    for (int iz = 0; iz < cz; iz++)
        for (int iy = 0; iy < cy; iy++)
            for (int ix = 0; ix < cx; ix++) {
                const size_t c = ((size_t)iz * (size_t)cy + (size_t)iy) * (size_t)cx + (size_t)ix;
                const uint32_t a0 = start[c], a1 = start[c + 1];
                if (a0 == a1)
                    continue;
                cand += (uint64_t)(a1 - a0) * (a1 - a0 - 1) / 2;
                for (uint32_t p = a0; p < a1; p++)
                    for (uint32_t q = p + 1; q < a1; q++)
                        SEP_VISIT(idx[p], idx[q]);
                for (int k = 0; k < ns; k++) {
                    const int *o = s->dim == 3 ? st3[k] : st2[k];
                    const int jx = ix + o[0], jy = iy + o[1], jz = iz + o[2];
                    if (jx < 0 || jx >= cx || jy < 0 || jy >= cy || jz >= cz)
                        continue;
                    const size_t c2 = ((size_t)jz * (size_t)cy + (size_t)jy) * (size_t)cx + (size_t)jx;
                    const uint32_t b0 = start[c2], b1 = start[c2 + 1];
                    cand += (uint64_t)(a1 - a0) * (b1 - b0);
                    for (uint32_t p = a0; p < a1; p++)
                        for (uint32_t q = b0; q < b1; q++)
                            SEP_VISIT(idx[p], idx[q]);
                }
            }
    s->candidates = cand;
}
#undef SEP_VISIT

typedef struct {
    uint32_t *pairs;
    size_t n, cap;
} pair_list;

static void collect(mote_sep_system *s, size_t i, size_t j, const double dx[3], double d2,
                    void *ctx)
{
    (void)s;
    (void)dx;
    (void)d2;
    pair_list *l = ctx;
    if (l->n < l->cap) {
        l->pairs[2 * l->n] = (uint32_t)(i < j ? i : j);
        l->pairs[2 * l->n + 1] = (uint32_t)(i < j ? j : i);
    }
    l->n++;
}

static int cmp_pair(const void *a, const void *b)
{
    const uint32_t *x = a, *y = b;
    return x[0] != y[0] ? (x[0] > y[0]) - (x[0] < y[0]) : (x[1] > y[1]) - (x[1] < y[1]);
}

size_t mote_sep_pairs(mote_sep_system *s, int brute, uint32_t *pairs, size_t cap)
{
    mote_err err;
    if (!brute && sep_cells_build(s, &err))
        return 0;
    pair_list l = {pairs, 0, cap};
    each_pair(s, brute, collect, &l);
    if (pairs && cap && l.n)
        qsort(pairs, l.n < cap ? l.n : cap, 2 * sizeof *pairs, cmp_pair);
    return l.n;
}

/* ---- forces --------------------------------------------------------------------------------- */

/* The Hertz-Mindlin constants of a species pair (or a species at the walls, hm_w): the law's
 * (R and m per contact) and the rolling friction. */
typedef struct {
    sep_hm h;
    double mur, coh;
} hm_pp;

typedef struct {
    double khat, half_dt, dt;
    double g_pp[MOTE_SEP_MAX_SPECIES * MOTE_SEP_MAX_SPECIES]; /* 2 zeta(e) per species pair */
    double *pvx, *pvy, *pvz;    /* predicted velocities */
    int hertz;
    hm_pp hm[MOTE_SEP_MAX_SPECIES * MOTE_SEP_MAX_SPECIES], hm_w[MOTE_SEP_MAX_SPECIES];
    int hm_one, hm_w_one; /* every species pair's constants (the walls') are hm[0]'s (hm_w[0]'s) */
    sep_mesh_frame fr[MOTE_SEP_MAX_MESHES]; /* the mesh walls where they are now */
} force_ctx;

static inline void pair_force(mote_sep_system *s, size_t i, size_t j, const double dx[3], double d2,
                       void *vctx)
{
    force_ctx *c = vctx;
    const double dist = sqrt(d2), R = 0.5 * (s->d[i] + s->d[j]);
    if (!(dist > 0))
        return; /* coincident centres: no direction (the feed never makes them) */
    const double delta = R - dist;
    const double n[3] = {dx[0] / dist, dx[1] / dist, dx[2] / dist};
    const double vn = (c->pvx[i] - c->pvx[j]) * n[0] + (c->pvy[i] - c->pvy[j]) * n[1] +
                      (c->pvz[i] - c->pvz[j]) * n[2];
    const double dbar = 2 * s->d[i] * s->d[j] / (s->d[i] + s->d[j]);
    const double k = c->khat * dbar, mij = s->m[i] * s->m[j] / (s->m[i] + s->m[j]);
    const double F = k * delta + c->g_pp[s->s[i] * MOTE_SEP_MAX_SPECIES + s->s[j]] * sqrt(mij * k) * vn;
    s->fx[j] += F * n[0];
    s->fy[j] += F * n[1];
    s->fz[j] += F * n[2];
    s->fx[i] -= F * n[0];
    s->fy[i] -= F * n[1];
    s->fz[i] -= F * n[2];
    const double ov = delta / (s->d[i] < s->d[j] ? s->d[i] : s->d[j]);
    if (ov > s->max_overlap)
        s->max_overlap = ov;
    s->contacts_pp++;
}

/* ---- the pair list -------------------------------------------------------------------------- */

int sep_reserve(void **p, size_t *cap, size_t need, size_t size, mote_err *err)
{
    if (*p && need <= *cap)
        return MOTE_OK;
    const size_t c = need + need / 2 + 64;
    void *q = realloc(*p, c * size);
    if (!q)
        return mote_fail(err, MOTE_ENOMEM, "separator: out of memory (%zu entries of %zu bytes)",
                         c, size);
    *p = q;
    *cap = c;
    return MOTE_OK;
}

/* A neighbour row in increasing index (rows are short: insertion sort). */
static void sort_row(uint32_t *row, size_t len)
{
    for (size_t a = 1; a < len; a++) {
        const uint32_t v = row[a];
        size_t b = a;
        for (; b > 0 && row[b - 1] > v; b--)
            row[b] = row[b - 1];
        row[b] = v;
    }
}

/* Particle i's neighbours within r_i + r_j + skin through the cells around its own (the full
 * stencil: every j != i), written to out when it is not NULL; their number. */
static size_t row_scan(const mote_sep_system *s, size_t i, double skin, uint32_t *out)
{
    const mote_grid *g = &s->grid;
    const size_t c = g->cell[i];
    const int n0 = g->nc[0], n1 = g->nc[1], n2 = g->nc[2];
    const int c0 = (int)(c % (size_t)n0), c1 = (int)(c / (size_t)n0 % (size_t)n1),
              c2 = (int)(c / ((size_t)n0 * (size_t)n1));
    const int lo0 = c0 > 0 ? c0 - 1 : 0, hi0 = c0 + 1 < n0 ? c0 + 1 : n0 - 1;
    const int lo1 = c1 > 0 ? c1 - 1 : 0, hi1 = c1 + 1 < n1 ? c1 + 1 : n1 - 1;
    const int lo2 = c2 > 0 ? c2 - 1 : 0, hi2 = c2 + 1 < n2 ? c2 + 1 : n2 - 1;
    size_t k = 0;
    for (int k2 = lo2; k2 <= hi2; k2++)
        for (int k1 = lo1; k1 <= hi1; k1++) {
            /* the cells lo0..hi0 of a row are consecutive: one run of the order */
            const size_t r = ((size_t)k2 * (size_t)n1 + (size_t)k1) * (size_t)n0;
            const uint32_t p0 = g->start[r + (size_t)lo0], p1 = g->start[r + (size_t)hi0 + 1];
            for (uint32_t p = p0; p < p1; p++) {
                const uint32_t j = g->order[p];
                if (j != i && near(s, i, j, skin)) {
                    if (out)
                        out[k] = j;
                    k++;
                }
            }
        }
    return k;
}

/* The largest |i - j| over the listed pairs (each row sorted: its ends). */
static size_t list_width(const mote_sep_system *s)
{
    size_t w = 0;
    for (size_t i = 0; i < s->n; i++) {
        const uint32_t a = s->nb_start[i], b = s->nb_start[i + 1];
        if (a == b)
            continue;
        const size_t lo = s->nb[a], hi = s->nb[b - 1];
        w = lo < i && i - lo > w ? i - lo : w;
        w = hi > i && hi - i > w ? hi - i : w;
    }
    return w;
}

/* The neighbour rows, built afresh from the cells just built: the rows are counted, then
 * filled and sorted, on the threads (the rows do not depend on them). */
static int list_build(mote_sep_system *s, mote_err *err)
{
    int rc = sep_cells_build(s, err);
    if (rc)
        return rc;
    const size_t n = s->n;
    if (sep_reserve((void **)&s->xref, &s->xref_cap, 3 * n, sizeof *s->xref, err) ||
        sep_reserve((void **)&s->nb_start, &s->nbs_cap, n + 1, sizeof *s->nb_start, err))
        return err->code;
    const int nt = sep_threads(s);
    const double skin = s->skin_used;
    double *xref = s->xref;
    uint32_t *start = s->nb_start;
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
    for (size_t i = 0; i < n; i++) {
        xref[3 * i] = s->x[i];
        xref[3 * i + 1] = s->y[i];
        xref[3 * i + 2] = s->z[i];
        start[i + 1] = (uint32_t)row_scan(s, i, skin, NULL);
    }
    start[0] = 0;
    size_t total = 0;
    for (size_t i = 0; i < n; i++) {
        total += start[i + 1];
        if (total > UINT32_MAX)
            return mote_fail(err, MOTE_ENOMEM, "separator: more than 2^32 - 1 neighbours");
        start[i + 1] = (uint32_t)total;
    }
    if (sep_reserve((void **)&s->nb, &s->nb_cap, total, sizeof *s->nb, err))
        return err->code;
    uint32_t *nb = s->nb;
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
    for (size_t i = 0; i < n; i++) {
        uint32_t *row = nb + start[i];
        sort_row(row, row_scan(s, i, skin, row));
    }
    s->npl = total / 2;
    s->nb_w = list_width(s);
    s->gap_ok = 0;
    s->hist_ok = 0;
    s->nb_idx_ok = 1;
    s->nb_n = n;
    s->list_ok = 1;
    s->list_mods = s->mods;
    s->list_builds++;
    return MOTE_OK;
}

int sep_list_from_pairs(mote_sep_system *s, const uint32_t *pairs, size_t np, mote_err *err)
{
    const size_t n = s->n;
    if (sep_reserve((void **)&s->nb_start, &s->nbs_cap, n + 1, sizeof *s->nb_start, err) ||
        sep_reserve((void **)&s->nb, &s->nb_cap, 2 * np + 1, sizeof *s->nb, err))
        return err->code;
    uint32_t *start = s->nb_start, *nb = s->nb;
    memset(start, 0, (n + 1) * sizeof *start);
    for (size_t k = 0; k < 2 * np; k++) {
        if (pairs[k] >= n)
            return mote_fail(err, MOTE_EINVAL, "the pair list names a particle beyond the last");
        start[pairs[k] + 1]++;
    }
    for (size_t i = 0; i < n; i++)
        start[i + 1] += start[i];
    /* each row filled in order of its partners, then the rows put back at their starts */
    for (size_t k = 0; k < np; k++) {
        nb[start[pairs[2 * k]]++] = pairs[2 * k + 1];
        nb[start[pairs[2 * k + 1]]++] = pairs[2 * k];
    }
    for (size_t i = n; i > 0; i--)
        start[i] = start[i - 1];
    start[0] = 0;
    for (size_t i = 0; i < n; i++)
        sort_row(nb + start[i], start[i + 1] - start[i]);
    s->npl = np;
    s->nb_w = list_width(s);
    s->gap_ok = 0;
    s->hist_ok = 0;
    s->nb_idx_ok = 1;
    s->nb_n = n;
    return MOTE_OK;
}

/* ---- forces per particle -------------------------------------------------------------------- */

/* The walls and closed ends on particle i (k = k_hat d, m = m_i, the wall at rest) with its
 * predicted velocity pvel, added to F; the largest overlap into *mo. */
static inline void wall_force(const mote_sep_system *s, size_t i, double khat, double g_w,
                              const double pvel[3], double F[3], double *mo)
{
    const double pos[3] = {s->x[i], s->y[i], s->z[i]}, r = 0.5 * s->d[i];
    const double hi[3] = {s->W, s->D, s->H};
    for (int a = 0; a < 3; a++) {
        if (a == 1 && s->dim == 2)
            continue;
        const int lo_wall = a < 2 || !s->open_bottom, hi_wall = a < 2 || !s->open_top;
        const double dlo = r - pos[a], dhi = pos[a] + r - hi[a];
        if ((lo_wall && dlo > 0) || (hi_wall && dhi > 0)) {
            const double k = khat * s->d[i], gam = g_w * sqrt(s->m[i] * k);
            if (lo_wall && dlo > 0) /* the wall's normal +a; approach rate -v_a */
                F[a] += k * dlo - gam * pvel[a];
            if (hi_wall && dhi > 0) /* normal -a; approach rate +v_a */
                F[a] -= k * dhi + gam * pvel[a];
            const double ov = (dlo > dhi ? dlo : dhi) / s->d[i];
            if (ov > *mo)
                *mo = ov;
        }
    }
}

/* The plates on particle i: one contact per feature (a hole's side faces, or the top or bottom
 * face), added to F. */
static inline void plate_force(const mote_sep_system *s, size_t i, double khat, double g_w,
                               const double pvel[3], double F[3], double *mo)
{
    for (int q = 0; q < s->nplate; q++) {
        const double r = 0.5 * s->d[i], c3[3] = {s->x[i], s->y[i], s->z[i]};
        double delta[4], nrm[4][3];
        const int nf = mote_sep_plate_features(&s->plate[q], s->dim, c3, r, delta, nrm);
        if (nf <= 0)
            continue;
        const double k = khat * s->d[i], gam = g_w * sqrt(s->m[i] * k);
        for (int f = 0; f < nf; f++) {
            const double vn = pvel[0] * nrm[f][0] + pvel[1] * nrm[f][1] + pvel[2] * nrm[f][2];
            const double Fm = k * delta[f] - gam * vn;
            F[0] += Fm * nrm[f][0];
            F[1] += Fm * nrm[f][1];
            F[2] += Fm * nrm[f][2];
            *mo = fmax(*mo, delta[f] / s->d[i]);
        }
    }
}

/* The mesh walls on particle i (linear law): one contact per face, edge or vertex touched, the
 * dashpot on the approach against the wall's own velocity there. */
static inline void mesh_force(const mote_sep_system *s, const force_ctx *c, size_t i, double g_w,
                              const double pvel[3], double F[3], double *mo)
{
    sep_mc mc[SEP_MESH_MAXC];
    const double p[3] = {s->x[i], s->y[i], s->z[i]};
    const int nm = sep_mesh_contacts(s, c->fr, p, 0.5 * s->d[i], mc);
    if (!nm)
        return;
    const double k = c->khat * s->d[i], gam = g_w * sqrt(s->m[i] * k);
    for (int q = 0; q < nm; q++) {
        const double *n = mc[q].n, *vw = mc[q].vw;
        const double vn = (pvel[0] - vw[0]) * n[0] + (pvel[1] - vw[1]) * n[1] +
                          (pvel[2] - vw[2]) * n[2];
        const double Fm = k * mc[q].delta - gam * vn;
        F[0] += Fm * n[0];
        F[1] += Fm * n[1];
        F[2] += Fm * n[2];
        *mo = fmax(*mo, mc[q].delta / s->d[i]);
    }
}

/* The arrays the contacts' pass reads and writes, as restrict pointers: the compiler may keep a
 * particle's values in registers across the stores of its force. It reads the velocities (not
 * yet given the second half kick) and the last forces, for the predicted velocities, and
 * writes the new forces to the other arrays (g). */
typedef struct {
    const double *restrict x, *restrict y, *restrict z, *restrict d, *restrict m, *restrict im;
    const double *restrict vx, *restrict vy, *restrict vz, *restrict fx, *restrict fy,
        *restrict fz;
    const int *restrict sp;
    const uint32_t *restrict nb, *restrict nb_start;
    double *restrict gx, *restrict gy, *restrict gz;
    /* hertz: ids, angular velocities, last torques, new torques, the springs of the row
     * entries and of the walls */
    const uint64_t *restrict id;
    const double *w, *restrict tq; /* (w: kicked through s in the first loop) */
    double *restrict tq2, *restrict hist, *restrict wh;
} force_arrays;

/* Particle j's predicted velocity v + dt/2 F_old/m (spec 2.10 step 6), made where a contact
 * needs it (the expression of the drift's and the brute force's predictions: the same bits). */
static inline void pv_of(const force_arrays *a, const force_ctx *c, size_t j, double pv[3])
{
    const double h = c->half_dt * a->im[j];
    pv[0] = a->vx[j] + h * a->fx[j];
    pv[1] = a->vy[j] + h * a->fy[j];
    pv[2] = a->vz[j] + h * a->fz[j];
}

/* Particle i's contacts with its listed neighbours, subtracted from F in the row's order: the
 * force on i from j is minus the one on j from i, bit for bit, as every factor is symmetric in
 * i and j (the difference vector's sign flips exactly). dim is a constant of each caller. */
static inline void row_force(const force_arrays *a, const force_ctx *c, size_t i, int dim,
                             double F[3], double *mo, uint64_t *contacts)
{
    const uint32_t *row = a->nb + a->nb_start[i], *end = a->nb + a->nb_start[i + 1];
    const double xi = a->x[i], yi = dim == 3 ? a->y[i] : 0, zi = a->z[i], di = a->d[i];
    double pvi[3] = {0, 0, 0};
    int have_pvi = 0; /* (made at the first contact) */
    for (; row < end; row++) {
        const size_t j = *row;
        const double dx[3] = {a->x[j] - xi, dim == 3 ? a->y[j] - yi : 0, a->z[j] - zi};
        const double d2 = dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2];
        const double dj = a->d[j], R = 0.5 * (di + dj);
        if (!(d2 < R * R))
            continue;
        const double dist = sqrt(d2);
        if (!(dist > 0))
            continue; /* coincident centres: no direction (the feed never makes them) */
        const double delta = R - dist;
        const double n[3] = {dx[0] / dist, dx[1] / dist, dx[2] / dist};
        if (!have_pvi) {
            pv_of(a, c, i, pvi);
            have_pvi = 1;
        }
        double pvj[3];
        pv_of(a, c, j, pvj);
        const double vn = (pvi[0] - pvj[0]) * n[0] + (pvi[1] - pvj[1]) * n[1] +
                          (pvi[2] - pvj[2]) * n[2];
        const double dbar = 2 * di * dj / (di + dj);
        const double mi = a->m[i], mj = a->m[j];
        const double k = c->khat * dbar, mij = mi * mj / (mi + mj);
        const int p = a->sp[i], q = a->sp[j];
        const double g = c->g_pp[p < q ? p * MOTE_SEP_MAX_SPECIES + q : q * MOTE_SEP_MAX_SPECIES + p];
        const double Fm = k * delta + g * sqrt(mij * k) * vn;
        F[0] -= Fm * n[0];
        F[1] -= Fm * n[1];
        F[2] -= Fm * n[2];
        const double ov = delta / (di < dj ? di : dj);
        if (ov > *mo)
            *mo = ov;
        *contacts += j > i;
    }
}

static inline void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* The Hertz-Mindlin contacts of listed pairs, several at once: hm_lanes.inc, on 2, 4 and 8
 * lanes (x86-64: SSE2, AVX2, AVX-512F, whichever the processor runs), every width giving every
 * pair the same bits. */
typedef double (*hm_kernel)(const force_arrays *a, const force_ctx *c, const double *restrict pvw,
                            double *restrict slot, const uint32_t *ent, const uint32_t *own,
                            int cnt, int dim);
typedef double (*hm_wkernel)(const force_arrays *a, const force_ctx *c, const double *restrict pvw,
                             double *restrict res, const uint32_t *own, const int *ax,
                             const double *sg, const double *dl, int cnt);
#define HM_LANES 2
#define HM_KNAME hm_pairs2
#define HM_WNAME hm_walls2
#define HM_KATTR
#include "hm_lanes.inc"
#undef HM_LANES
#undef HM_KNAME
#undef HM_WNAME
#undef HM_KATTR
#if defined(__x86_64__) && defined(__GNUC__)
#define HM_WIDE 1
#define HM_LANES 4
#define HM_KNAME hm_pairs4
#define HM_WNAME hm_walls4
#define HM_KATTR __attribute__((target("avx2")))
#include "hm_lanes.inc"
#undef HM_LANES
#undef HM_KNAME
#undef HM_WNAME
#undef HM_KATTR
#define HM_LANES 8
#define HM_KNAME hm_pairs8
#define HM_WNAME hm_walls8
#define HM_KATTR __attribute__((target("avx512f")))
#include "hm_lanes.inc"
#undef HM_LANES
#undef HM_KNAME
#undef HM_WNAME
#undef HM_KATTR
#endif

/* The widest kernels the processor runs (at most s->simd lanes when that is set: tests), and
 * their lanes. */
static int hm_pick(const mote_sep_system *s, hm_kernel *pairs, hm_wkernel *walls)
{
    int w = 2;
#ifdef HM_WIDE
    if (__builtin_cpu_supports("avx512f"))
        w = 8;
    else if (__builtin_cpu_supports("avx2"))
        w = 4;
#endif
    if (s->simd > 0 && s->simd < w)
        w = s->simd >= 4 ? 4 : 2;
    *pairs = hm_pairs2;
    *walls = hm_walls2;
#ifdef HM_WIDE
    if (w == 8)
        *pairs = hm_pairs8, *walls = hm_walls8;
    if (w == 4)
        *pairs = hm_pairs4, *walls = hm_walls4;
#endif
    return w;
}

/* One Hertz-Mindlin contact of particle i with a wall (n from the wall to the centre, overlap
 * delta; the wall's velocity vw at the contact point and its angular velocity ww; xi the
 * contact's spring): added to F and T. */
static inline void contact_wall_hm(const force_arrays *a, const force_ctx *c, size_t i,
                                   const double n[3], double delta, const double pv[3],
                                   const double pw[3], const double vw[3], const double ww[3],
                                   double *xi, double F[3], double T[3])
{
    const double r = 0.5 * a->d[i];
    double cw[3], Fw[3], nf[3];
    cross3(pw, n, cw);
    const double v[3] = {pv[0] - r * cw[0] - vw[0], pv[1] - r * cw[1] - vw[1],
                         pv[2] - r * cw[2] - vw[2]};
    const hm_pp *k = &c->hm_w[a->sp[i]];
    sep_hm h = k->h;
    h.R = r;
    h.m = a->m[i];
    sep_hm_force(&h, delta, n, v, c->dt, xi, Fw);
    cross3(n, Fw, nf);
    if (k->coh > 0) { /* SJKR at a wall: the contact circle's area pi (2 r delta - delta^2) */
        const double fc = -k->coh * SEP_PI * (2 * r - delta) * delta;
        Fw[0] += fc * n[0], Fw[1] += fc * n[1], Fw[2] += fc * n[2];
    }
    for (int b = 0; b < 3; b++) {
        F[b] += Fw[b];
        T[b] -= r * nf[b];
    }
    /* rolling friction: as between particles, the spin relative to the wall's (LIGGGHTS takes
     * the particle's own, the same at a wall at rest) */
    const double wr[3] = {pw[0] - ww[0], pw[1] - ww[1], pw[2] - ww[2]};
    const double wl = sqrt(wr[0] * wr[0] + wr[1] * wr[1] + wr[2] * wr[2]);
    if (k->mur > 0 && wl > 0) {
        const double fe = 4.0 / 3.0 * h.Y * sqrt(h.R * delta) * delta;
        const double f = -k->mur * r * fe / wl, wn = sep_dot3(wr, n);
        for (int b = 0; b < 3; b++)
            T[b] += f * (wr[b] - wn * n[b]);
    }
}

/* A contact with a channel wall or a plate (at rest), its spring the one of the normal's axis. */
static inline void wall_hm(const force_arrays *a, const force_ctx *c, size_t i, const double n[3],
                           double delta, const double pv[3], const double pw[3], double F[3],
                           double T[3], unsigned *used)
{
    const double ax = fabs(n[0]), ay = fabs(n[1]), az = fabs(n[2]);
    const int slot = ax >= ay && ax >= az ? 0 : ay >= az ? 1 : 2;
    *used |= 1u << slot;
    static const double zero[3] = {0, 0, 0};
    contact_wall_hm(a, c, i, n, delta, pv, pw, zero, zero, a->wh + 9 * i + 3 * slot, F, T);
}

/* The mesh walls on particle i (contact hertz). Each contact's spring is kept in one of the
 * particle's slots under the contact's key (wall and triangle); a contact new to its triangle
 * takes over a spring of the same wall that lost its own (a particle rolling from one triangle
 * onto the next keeps its spring); springs left without a contact are zeroed. */
static inline void meshes_hm(const mote_sep_system *s, const force_arrays *a, const force_ctx *c,
                             size_t i, const double pv[3], const double pw[3], double F[3],
                             double T[3], double *mo)
{
    sep_mc mc[SEP_MESH_MAXC];
    const double p[3] = {a->x[i], a->y[i], a->z[i]};
    const int nm = sep_mesh_contacts(s, c->fr, p, 0.5 * a->d[i], mc);
    double *sl = s->mh + 4 * SEP_MESH_SLOTS * i;
    int slot[SEP_MESH_MAXC];
    unsigned used = 0;
    for (int q = 0; q < nm; q++) { /* the same triangle */
        slot[q] = -1;
        for (int j = 0; j < SEP_MESH_SLOTS; j++)
            if (!(used >> j & 1) && sl[4 * j] == mc[q].key) {
                slot[q] = j;
                used |= 1u << j;
                break;
            }
    }
    for (int pass = 0; pass < 3; pass++) /* the same wall's lost spring; a free slot; any */
        for (int q = 0; q < nm; q++) {
            if (slot[q] >= 0)
                continue;
            for (int j = 0; j < SEP_MESH_SLOTS; j++) {
                const double kj = sl[4 * j];
                if ((used >> j & 1) ||
                    (pass == 0 && !(kj != 0 && floor(kj / 4294967296.0) ==
                                                   floor(mc[q].key / 4294967296.0))) ||
                    (pass == 1 && kj != 0))
                    continue;
                if (pass > 0)
                    sl[4 * j + 1] = sl[4 * j + 2] = sl[4 * j + 3] = 0;
                sl[4 * j] = mc[q].key;
                slot[q] = j;
                used |= 1u << j;
                break;
            }
        }
    for (int q = 0; q < nm; q++) {
        double spare[3] = {0, 0, 0}; /* (more contacts than slots: no history) */
        double *xi = slot[q] >= 0 ? sl + 4 * slot[q] + 1 : spare;
        contact_wall_hm(a, c, i, mc[q].n, mc[q].delta, pv, pw, mc[q].vw, mc[q].ww, xi, F, T);
        *mo = fmax(*mo, mc[q].delta / a->d[i]);
    }
    for (int j = 0; j < SEP_MESH_SLOTS; j++)
        if (!(used >> j & 1))
            sl[4 * j] = sl[4 * j + 1] = sl[4 * j + 2] = sl[4 * j + 3] = 0;
}

/* The box's plane walls that particle i touches, in the order x, y, z, the lower wall first:
 * their axes, the signs of their normals (into the box) and the overlaps; their number. */
static inline int box_contacts(const mote_sep_system *s, const force_arrays *a, size_t i,
                               int ax[6], double sg[6], double dl[6])
{
    const double pos[3] = {a->x[i], a->y[i], a->z[i]}, r = 0.5 * a->d[i];
    const double hi[3] = {s->W, s->D, s->H};
    int k = 0;
    for (int b = 0; b < 3; b++) {
        if (b == 1 && s->dim == 2)
            continue;
        const int lo_wall = b < 2 || !s->open_bottom, hi_wall = b < 2 || !s->open_top;
        const double dlo = r - pos[b], dhi = pos[b] + r - hi[b];
        if (lo_wall && dlo > 0)
            ax[k] = b, sg[k] = 1, dl[k++] = dlo;
        if (hi_wall && dhi > 0)
            ax[k] = b, sg[k] = -1, dl[k++] = dhi;
    }
    return k;
}

/* Particle i's walls and plates by Hertz-Mindlin (pvw: the predicted velocities and angular
 * velocities, 6 a particle); the springs of the axes not touched zeroed. */
static inline void walls_hm(const mote_sep_system *s, const force_arrays *a, const force_ctx *c,
                            const double *pvw, size_t i, int wall, double F[3], double T[3],
                            double *mo)
{
    unsigned used = 0;
    if (wall || s->nplate || s->nmesh) {
        const double *pv = pvw + 6 * i, *pw = pv + 3;
        const double pos[3] = {a->x[i], a->y[i], a->z[i]}, r = 0.5 * a->d[i];
        int ax[6];
        double sg[6], dl[6];
        const int nw = wall ? box_contacts(s, a, i, ax, sg, dl) : 0;
        for (int k = 0; k < nw; k++) {
            double n[3] = {0, 0, 0};
            n[ax[k]] = sg[k];
            wall_hm(a, c, i, n, dl[k], pv, pw, F, T, &used);
            *mo = fmax(*mo, dl[k] / a->d[i]);
        }
        for (int q = 0; q < s->nplate; q++) {
            double delta[4], nrm[4][3];
            const int nf = mote_sep_plate_features(&s->plate[q], s->dim, pos, r, delta, nrm);
            for (int f = 0; f < nf; f++) {
                wall_hm(a, c, i, nrm[f], delta[f], pv, pw, F, T, &used);
                *mo = fmax(*mo, delta[f] / a->d[i]);
            }
        }
        if (s->nmesh)
            meshes_hm(s, a, c, i, pv, pw, F, T, mo);
    }
    for (int slot = 0; slot < 3; slot++)
        if (!(used >> slot & 1)) {
            double *x = a->wh + 9 * i + 3 * slot;
            x[0] = x[1] = x[2] = 0;
        }
}

/* Each row's smallest gap at the build, from the build's positions (so a loaded list gets the
 * values its build had); 0 when there is no room for them (then no row is skipped). */
static int list_gaps(mote_sep_system *s)
{
    const size_t n = s->n;
    mote_err err = {0};
    if (s->xref_cap < 3 * n ||
        sep_reserve((void **)&s->gap, &s->gap_cap, n + 1, sizeof *s->gap, &err))
        return 0;
    const double *q = s->xref, *d = s->d;
    const uint32_t *nb = s->nb, *start = s->nb_start;
    const int nt = sep_threads(s), three = s->dim == 3;
    double *gap = s->gap;
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
    for (size_t i = 0; i < n; i++) {
        double g = INFINITY;
        for (uint32_t e = start[i]; e < start[i + 1]; e++) {
            const size_t j = nb[e];
            const double dx = q[3 * j] - q[3 * i], dy = three ? q[3 * j + 1] - q[3 * i + 1] : 0,
                         dz = q[3 * j + 2] - q[3 * i + 2];
            const double gj = sqrt(dx * dx + dy * dy + dz * dz) - 0.5 * (d[i] + d[j]);
            g = gj < g ? gj : g;
        }
        gap[i] = g;
    }
    s->gap_ok = 1;
    return 1;
}

int sep_ebox_reserve(mote_sep_system *s, mote_err *err)
{
    const size_t nblk = (s->n + SEP_EBLK - 1) / SEP_EBLK;
    return sep_reserve((void **)&s->ebox, &s->ebox_cap, 10 * nblk + 10, sizeof *s->ebox, err);
}

/* The reach of each block's rows (into s->ebox + 6 nblk): a row of particle i holds particles
 * j within nb_w of i, so in the blocks b - K ... b + K around i's block b (K = nb_w / SEP_EBLK
 * rounded up); the displacements since the build of both lie in the union U of those blocks'
 * boxes, so the separation changed by at most U's diagonal. The unions by windows of 2 K + 1
 * blocks (van Herk's prefix and suffix within segments of that length: a window's union is its
 * first block's suffix with its last block's prefix, or a larger box where a clipped window
 * lies in one segment). fresh: the list was built from the present positions (all boxes 0). */
static const double *block_reach(mote_sep_system *s, int fresh, double dmin)
{
    const size_t nblk = (s->n + SEP_EBLK - 1) / SEP_EBLK;
    double *box = s->ebox, *reach = box + 6 * nblk, *pre = reach + nblk, *suf = pre + nblk,
           *low = suf + nblk;
    const double margin = 1e-6 * dmin;
    if (fresh) {
        for (size_t b = 0; b < nblk; b++)
            reach[b] = margin;
        return reach;
    }
    const size_t K = (s->nb_w + SEP_EBLK - 1) / SEP_EBLK, L = 2 * K + 1;
    for (size_t b = 0; b < nblk; b++)
        reach[b] = 0; /* (the squared diagonal, summed over the axes) */
    for (int a = 0; a < 3; a++)
        for (int hi = 0; hi < 2; hi++) { /* the windows' lower ends (min), then upper (max) */
            const double *v = box + 3 * hi + a;
#define SEP_JOIN(x, y) (hi ? ((x) > (y) ? (x) : (y)) : ((x) < (y) ? (x) : (y)))
            /* (q: b's place in its segment, counted rather than divided) */
            for (size_t b = 0, q = 0; b < nblk; b++, q = q + 1 == L ? 0 : q + 1)
                pre[b] = q == 0 ? v[6 * b] : SEP_JOIN(v[6 * b], pre[b - 1]);
            for (size_t b = nblk, q = (nblk - 1) % L; b-- > 0; q = q == 0 ? L - 1 : q - 1)
                suf[b] = q == L - 1 || b + 1 == nblk ? v[6 * b] : SEP_JOIN(v[6 * b], suf[b + 1]);
            for (size_t b = 0; b < nblk; b++) {
                const size_t l = b > K ? b - K : 0, r = b + K < nblk ? b + K : nblk - 1;
                const double u = SEP_JOIN(suf[l], pre[r]);
                if (!hi)
                    low[b] = u;
                else if (u >= low[b]) /* (an empty box: nothing) */
                    reach[b] += (u - low[b]) * (u - low[b]);
            }
#undef SEP_JOIN
        }
    for (size_t b = 0; b < nblk; b++)
        reach[b] = sqrt(reach[b]) + margin;
    return reach;
}

/* The reach of block b's rows, as block_reach makes it, from the union of the boxes of the
 * blocks b - K ... b + K (within 0 ... nblk - 1). */
static double window_reach(const double *box, size_t nblk, size_t b, size_t K, double margin)
{
    const size_t l = b > K ? b - K : 0, r = b + K < nblk ? b + K : nblk - 1;
    double u[6];
    memcpy(u, box + 6 * l, sizeof u);
    for (size_t c = l + 1; c <= r; c++) {
        const double *v = box + 6 * c;
        for (int a = 0; a < 3; a++) {
            u[a] = v[a] < u[a] ? v[a] : u[a];
            u[3 + a] = v[3 + a] > u[3 + a] ? v[3 + a] : u[3 + a];
        }
    }
    double d2 = 0;
    for (int a = 0; a < 3; a++)
        if (u[3 + a] >= u[a])
            d2 += (u[3 + a] - u[a]) * (u[3 + a] - u[a]);
    return sqrt(d2) + margin;
}

/* After a pass of the listed contacts: the new forces (in g) become the present ones, the
 * second half kick is left pending (kick), the pass's largest overlap and contacts kept. */
static void forces_done(mote_sep_system *s, const force_ctx *c, int kick, double mo,
                        uint64_t contacts)
{
    double *t;
    t = s->fx, s->fx = s->gx, s->gx = t;
    t = s->fy, s->fy = s->gy, s->gy = t;
    t = s->fz, s->fz = s->gz, s->gz = t;
    s->g_cap = s->cap;
    s->kick_h = kick ? c->half_dt : 0;
    s->max_overlap = mo;
    s->contacts_pp = contacts;
    s->candidates = 2 * s->npl; /* (each row's entries tested) */
}

/* contact hertz: the listed contacts in two passes on the threads. Each pair is made once, from
 * its owner entry (the row of its lower index): the pairs in contact, by blocks of the
 * kernel's lanes, each into a slot of its own (s->pbuf: the force on the owner and the torques
 * on both), its index at the owner entry (s->cidx; 0, the zero slot, out of contact); then
 * each particle sums its walls and plates and its row's pairs in the row's order (a partner
 * entry's pair through s->mir, with minus the force), so every sum is the same whatever the
 * threads. The new forces and torques become the present ones; the second half kick is left
 * pending (kick). */
static void list_forces_hm(mote_sep_system *s, const force_ctx *c, int kick, const unsigned char *exc)
{
    const size_t n = s->n;
    const int nt = sep_threads(s), dim = s->dim;
    const force_arrays a = {s->x,  s->y,  s->z,  s->d,  s->m,  s->im,       s->vx,
                            s->vy, s->vz, s->fx, s->fy, s->fz, s->s, s->nb, s->nb_start,
                            s->gx, s->gy, s->gz, s->id, s->w, s->tq, s->tq2, s->hist, s->wh};
    const uint32_t *start = s->nb_start, *nb = s->nb, *mir = s->mir, *ostart = s->ostart;
    uint32_t *restrict cidx = s->cidx;
    double *restrict slots = s->pbuf, *restrict hist = s->hist;
    const double W = s->W, D = s->D, H = s->H;
    double mo = s->max_overlap;
    uint64_t contacts = 0;
    double *restrict pvw = s->pv;
    const double h1 = s->rot_h1, h2 = s->rot_h2;
    s->rot_h1 = s->rot_h2 = 0;
    hm_kernel kern;
    hm_wkernel wkern;
    const int lanes = hm_pick(s, &kern, &wkern);
    /* the box's walls by lanes too where there are no plates or mesh walls (their springs share
     * the walls' slots): per particle wflag 1, its walls' sums in wres; 2, a particle touching
     * both walls of an axis (one spring), its walls made in the sums' pass */
    const int lw = !s->nplate && !s->nmesh;
    double *restrict wres = s->wres;
    unsigned char *restrict wflag = s->wflag;
#pragma omp parallel num_threads(nt) if (nt > 1) reduction(max : mo) reduction(+ : contacts)
    {
        /* this step's angular kicks (step() left them here: one pass fewer), then the
         * predicted velocities and angular velocities, once a particle */
#pragma omp for schedule(static)
        for (size_t i = 0; i < n; i++) {
            /* (sep_rot_kick's and pv_of's expressions; the angular velocity predicted as the
             * velocity, w + dt/2 T_old / I) */
            const double iI = sep_inv_inertia(a.im[i], a.d[i]), hw = c->half_dt * iI;
            const double hv = c->half_dt * a.im[i];
            double *w = s->w + 3 * i, *o = pvw + 6 * i;
            const double *tq = a.tq + 3 * i;
            o[0] = a.vx[i] + hv * a.fx[i];
            o[1] = a.vy[i] + hv * a.fy[i];
            o[2] = a.vz[i] + hv * a.fz[i];
            for (int b = 0; b < 3; b++) {
                double wb = w[b];
                if (h1 > 0)
                    wb += h1 * iI * tq[b];
                if (h2 > 0)
                    wb += h2 * iI * tq[b];
                w[b] = wb;
                o[3 + b] = wb + hw * tq[b];
            }
        }
        /* the pairs from their owner entries (a row's last: j > i). A thread's slots follow
         * the owner entries before its first row (one chunk a thread: no two share a slot). */
        uint32_t ent[8], own[8], off[16], wown[8];
        int cnt = 0, noff = 0, wcnt = 0, wax[8];
        double wsg[8], wdl[8];
        uint32_t next = 0, first = 0; /* (the next slot; the block's first) */
        double mo_t = 0;
#pragma omp for schedule(static) nowait
        for (size_t i = 0; i < n; i++) {
            if (!next)
                next = first = 1 + ostart[i];
            const double xi = a.x[i], yi = a.y[i], zi = a.z[i], ri = 0.5 * a.d[i];
            if (lw) {
                const int wall = exc ? exc[i] & SEP_EXC_WALL
                                     : sep_near_wall(ri, xi, yi, zi, W, D, H, dim);
                int bax[6], nw = 0;
                double bsg[6], bdl[6];
                unsigned used = 0, twice = 0;
                if (wall)
                    nw = box_contacts(s, &a, i, bax, bsg, bdl);
                for (int k = 0; k < nw; k++) {
                    twice |= used & 1u << bax[k];
                    used |= 1u << bax[k];
                }
                wflag[i] = twice ? 2 : nw > 0;
                if (!twice) {
                    for (int b = 0; b < 3; b++)
                        if (!(used >> b & 1)) {
                            double *x = a.wh + 9 * i + 3 * b;
                            x[0] = x[1] = x[2] = 0;
                        }
                    if (nw)
                        for (int b = 0; b < 6; b++)
                            wres[6 * i + b] = 0;
                    for (int k = 0; k < nw; k++) {
                        wown[wcnt] = (uint32_t)i;
                        wax[wcnt] = bax[k];
                        wsg[wcnt] = bsg[k];
                        wdl[wcnt] = bdl[k];
                        if (++wcnt == lanes) {
                            const double m = wkern(&a, c, pvw, wres, wown, wax, wsg, wdl, wcnt);
                            mo_t = m > mo_t ? m : mo_t;
                            wcnt = 0;
                        }
                    }
                }
            }
            for (uint32_t e = start[i + 1] - (ostart[i + 1] - ostart[i]); e < start[i + 1]; e++) {
                const size_t j = nb[e];
                /* (the kernel's d2 and R, bit for bit: a - b is -(b - a)) */
                const double dx = a.x[j] - xi, dy = dim == 3 ? a.y[j] - yi : 0,
                             dz = a.z[j] - zi;
                const double d2 = dx * dx + dy * dy + dz * dz, R = ri + 0.5 * a.d[j];
                const int in = (d2 < R * R) & (d2 > 0);
                /* (both lists written, one counted: no branch to mispredict) */
                ent[cnt] = e;
                own[cnt] = (uint32_t)i;
                off[noff] = e;
                cidx[e] = in ? next : 0;
                next += (uint32_t)in;
                cnt += in;
                noff += !in;
                if (cnt == lanes) {
                    const double m = kern(&a, c, pvw, slots + 9 * (size_t)first, ent, own, cnt, dim);
                    mo_t = m > mo_t ? m : mo_t;
                    contacts += (uint64_t)cnt;
                    cnt = 0;
                    first = next;
                }
                if (noff == 16) { /* (out of contact: the springs zero) */
                    for (int k = 0; k < noff; k++) {
                        double *h = hist + 3 * (size_t)off[k];
                        h[0] = h[1] = h[2] = 0;
                    }
                    noff = 0;
                }
            }
        }
        if (cnt) {
            const double m = kern(&a, c, pvw, slots + 9 * (size_t)first, ent, own, cnt, dim);
            mo_t = m > mo_t ? m : mo_t;
            contacts += (uint64_t)cnt;
        }
        for (int k = 0; k < noff; k++) {
            double *h = hist + 3 * (size_t)off[k];
            h[0] = h[1] = h[2] = 0;
        }
        if (wcnt) {
            const double m = wkern(&a, c, pvw, wres, wown, wax, wsg, wdl, wcnt);
            mo_t = m > mo_t ? m : mo_t;
        }
        mo = mo_t > mo ? mo_t : mo;
#pragma omp barrier
        /* each particle: its walls and plates, then its row's pairs in order */
#pragma omp for schedule(static)
        for (size_t i = 0; i < n; i++) {
            double F[3] = {0, 0, 0}, T[3] = {0, 0, 0};
            if (lw && wflag[i] == 1) {
                const double *o = wres + 6 * i;
                F[0] = o[0], F[1] = o[1], F[2] = o[2];
                T[0] = o[3], T[1] = o[4], T[2] = o[5];
            } else if (!lw || wflag[i] == 2) {
                const int wall = lw || (exc ? exc[i] & SEP_EXC_WALL
                                            : sep_near_wall(0.5 * a.d[i], a.x[i], a.y[i], a.z[i],
                                                            W, D, H, dim));
                walls_hm(s, &a, c, pvw, i, wall, F, T, &mo);
            }
            const uint32_t mid = start[i + 1] - (ostart[i + 1] - ostart[i]);
            for (uint32_t e = start[i]; e < mid; e++) { /* (partner entries: j < i) */
                const double *b = slots + 9 * (size_t)cidx[mir[e]];
                F[0] -= b[0], F[1] -= b[1], F[2] -= b[2];
                T[0] += b[6], T[1] += b[7], T[2] += b[8];
            }
            for (uint32_t e = mid; e < start[i + 1]; e++) {
                const double *b = slots + 9 * (size_t)cidx[e];
                F[0] += b[0], F[1] += b[1], F[2] += b[2];
                T[0] += b[3], T[1] += b[4], T[2] += b[5];
            }
            a.gx[i] = F[0];
            a.gy[i] = F[1];
            a.gz[i] = F[2];
            a.tq2[3 * i] = T[0];
            a.tq2[3 * i + 1] = T[1];
            a.tq2[3 * i + 2] = T[2];
        }
    }
    double *t = s->tq;
    s->tq = s->tq2, s->tq2 = t;
    forces_done(s, c, kick, mo, contacts);
}

/* The listed contacts of every particle, on the threads: walls, neighbours, plates, into the
 * other forces' arrays, which then become the present ones; with kick, the second half kick
 * v += dt/2 F/m is left pending (s->kick_h). Each particle's force is its own sum, in a fixed
 * order.
 * The particles' displacements since the list's build lie, block by block of SEP_EBLK
 * particles, in boxes (s->ebox, lo and hi); a row whose gap at the build exceeds the reach of
 * its block (block_reach: how much the separation of any pair it lists can have shrunk, and
 * a margin far above the roundings) holds no contact and is not searched: the forces are those
 * of the search, bit for bit. A common drift (a falling column) leaves the boxes small, and a
 * block far from the particles that move otherwise keeps its reach small. fresh: the list was
 * built from the present positions. exc: the drift's codes with the wall bit (SEP_EXC_WALL),
 * or NULL (the test made here). */
static void list_forces(mote_sep_system *s, const force_ctx *c, double g_w, int kick, int fresh,
                        const unsigned char *exc, double dmin)
{
    const double *gap = s->no_gap_skip ? NULL : s->gap_ok || list_gaps(s) ? s->gap : NULL;
    /* the blocks' reach: a short window (the usual sorted order), each thread its blocks' as
     * it comes to them; else all at once (block_reach) */
    const size_t K = (s->nb_w + SEP_EBLK - 1) / SEP_EBLK, nblk = (s->n + SEP_EBLK - 1) / SEP_EBLK;
    const int local = gap && !fresh && 2 * K + 1 <= 32;
    const double *reach = gap && !local ? block_reach(s, fresh, dmin) : NULL;
    const double margin = 1e-6 * dmin, *ebox = s->ebox;
    const size_t n = s->n;
    const int nt = sep_threads(s), dim = s->dim, nplate = s->nplate, nmesh = s->nmesh;
    const force_arrays a = {s->x,  s->y,  s->z,  s->d,  s->m,  s->im,       s->vx,
                            s->vy, s->vz, s->fx, s->fy, s->fz, s->s, s->nb, s->nb_start,
                            s->gx, s->gy, s->gz, s->id, s->w, s->tq, s->tq2, s->hist, s->wh};

    const double W = s->W, D = s->D, H = s->H;
    double mo = s->max_overlap;
    uint64_t contacts = 0, skips = 0;
#pragma omp parallel num_threads(nt) if (nt > 1) reduction(max : mo) reduction(+ : contacts, skips)
    {
    size_t cb = SIZE_MAX; /* (this thread's present block and its reach) */
    double cr = 0;
#pragma omp for schedule(static) nowait
    for (size_t i = 0; i < n; i++) {
        double F[3] = {0, 0, 0};
        /* the walls' own test, widened to both ends however open (where it finds no wall
         * within reach, wall_force would add nothing; where a difference is NaN, wall_force
         * decides), made by the drift when it knew the present positions */
        const int wall = exc ? exc[i] & SEP_EXC_WALL
                             : sep_near_wall(0.5 * a.d[i], a.x[i], a.y[i], a.z[i], W, D, H, dim);
        if (wall) {
            double pvel[3];
            pv_of(&a, c, i, pvel);
            wall_force(s, i, c->khat, g_w, pvel, F, &mo);
        }
        if (local && i / SEP_EBLK != cb) {
            cb = i / SEP_EBLK;
            cr = window_reach(ebox, nblk, cb, K, margin);
        }
        if (gap && !(gap[i] <= (local ? cr : reach[i / SEP_EBLK])))
            skips++; /* (no contact in the row) */
        else if (dim == 3)
            row_force(&a, c, i, 3, F, &mo, &contacts);
        else
            row_force(&a, c, i, 2, F, &mo, &contacts);
        if (nplate || nmesh) {
            double pvel[3];
            pv_of(&a, c, i, pvel);
            plate_force(s, i, c->khat, g_w, pvel, F, &mo);
            if (nmesh)
                mesh_force(s, c, i, g_w, pvel, F, &mo);
        }
        a.gx[i] = F[0];
        a.gy[i] = F[1];
        a.gz[i] = F[2];
    }
    }
    /* the new forces become the present ones; the second half kick waits for the next drift
     * (or mote_sep_complete) */
    s->gap_skips += skips;
    forces_done(s, c, kick, mo, contacts);
}

int sep_g_reserve(mote_sep_system *s, mote_err *err)
{
    /* (the particle arrays' capacity: the two sets swap, and grow() reallocates fx, fy, fz to
     * the new capacity) */
    if (s->gx && s->g_cap >= s->cap)
        return MOTE_OK;
    const size_t c = s->cap ? s->cap : 1;
    double **g[3] = {&s->gx, &s->gy, &s->gz};
    for (int a = 0; a < 3; a++) {
        double *p = realloc(*g[a], c * sizeof *p);
        if (!p)
            return mote_fail(err, MOTE_ENOMEM, "separator: out of memory for the forces of %zu "
                             "particles", c);
        *g[a] = p;
    }
    s->g_cap = c;
    return MOTE_OK;
}

int sep_pv_reserve(mote_sep_system *s, mote_err *err)
{
    /* (allocated even for no particle: pv + n is then valid) */
    return sep_reserve((void **)&s->pv, &s->pv_cap, 3 * s->n + 3, sizeof *s->pv, err);
}

/* The contact forces of every particle from the current positions; the dashpots with the
 * predicted velocities v + dt/2 F_old/m (spec 2.10 step 6); with kick, the second half kick. */
int sep_contact_forces(mote_sep_system *s, double dt, int kick, int pred, mote_err *err)
{
    const size_t n = s->n;
    force_ctx c = {.khat = s->khat_used, .half_dt = 0.5 * dt, .dt = dt, .hertz = s->hertz};
    for (int k = 0; k < s->nmesh; k++)
        sep_mesh_frame_at(&s->mesh[k], s->t, &c.fr[k]);
    for (int a = 0; a < s->nsp; a++)
        for (int b = 0; b < s->nsp; b++) {
            const double e = s->e_pair[a][b] > 0 ? s->e_pair[a][b] : s->e_pp;
            c.g_pp[a * MOTE_SEP_MAX_SPECIES + b] = e < 1 ? 2 * zeta_of(e) : 0;
        }
    if (s->hertz) {
        /* the pairs' constants (the damping from prepare) */
        const int M = MOTE_SEP_MAX_SPECIES;
        for (int a = 0; a < s->nsp; a++) {
            const sep_material A = {s->sp[a].E, s->sp[a].nu};
            for (int b = 0; b < s->nsp; b++) {
                const sep_material B = {s->sp[b].E, s->sp[b].nu};
                hm_pp *k = &c.hm[a * M + b];
                const double mu = s->mu_pair[a][b] >= 0 ? s->mu_pair[a][b] : s->mu_pp;
                sep_hm_pair(&k->h, &A, 1, 1, &B, 1, 1, 1, mu);
                sep_hm_damping(&k->h, s->hm_beta[a * M + b]);
                k->mur = s->mur_pair[a][b] >= 0 ? s->mur_pair[a][b] : s->mur_pp;
                k->coh = s->coh_pair[a][b] >= 0 ? s->coh_pair[a][b] : s->coh_pp;
            }
            const sep_material Wm = {s->E_w > 0 ? s->E_w : A.E, s->E_w > 0 ? s->nu_w : A.nu};
            hm_pp *k = &c.hm_w[a];
            sep_hm_pair(&k->h, &A, 1, 1, &Wm, 1, 1, 1, s->mu_pw >= 0 ? s->mu_pw : s->mu_pp);
            sep_hm_damping(&k->h, s->hm_beta[M * M + a]);
            k->mur = s->mur_pw >= 0 ? s->mur_pw : s->mur_pp;
            k->coh = s->coh_pw >= 0 ? s->coh_pw : s->coh_pp;
        }
        /* (one set of constants for all: the lanes take them once, not pair by pair) */
        c.hm_one = c.hm_w_one = 1;
        for (int a = 0; a < s->nsp; a++) {
            c.hm_w_one &= !memcmp(&c.hm_w[a], &c.hm_w[0], sizeof c.hm_w[0]);
            for (int b = 0; b < s->nsp; b++)
                c.hm_one &= !memcmp(&c.hm[a * M + b], &c.hm[0], sizeof c.hm[0]);
        }
        if (sep_rot_reserve(s, err))
            return err->code;
    }
    /* whether the pair list still holds (nothing added, removed or reordered, no particle moved
     * more than skin/2 since its build); without it, the predicted velocities */
    double dmin, dmax;
    mote_sep_size_range(s, &dmin, &dmax);
    const double skin0 = s->skin_used;
    s->skin_used = s->brute || s->skin < 0 ? 0 : s->skin > 0 ? s->skin : 0.3 * dmin;
    const int listed = !s->brute && s->skin_used > 0;
    if (s->hertz && !listed)
        return mote_fail(err, MOTE_EINVAL, "separator: contact hertz needs the pair list "
                         "(neighbours cells)");
    if (s->hertz && (sep_reserve((void **)&s->pv, &s->pv_cap, 6 * n + 6, sizeof *s->pv, err) ||
                     sep_reserve((void **)&s->wres, &s->wres_cap, 6 * n + 6, sizeof *s->wres, err) ||
                     sep_reserve((void **)&s->wflag, &s->wflag_cap, n + 1, 1, err)))
        return err->code;
    const int can = listed && s->list_ok && s->mods == s->list_mods;
    const double lim = 0.25 * s->skin_used * s->skin_used;
    const double e_w = s->e_pw >= 0 ? s->e_pw : s->e_pp, g_w = e_w < 1 ? 2 * zeta_of(e_w) : 0;
    const int nt = sep_threads(s);
    /* the drift's pass checked the list with this skin (and left the blocks' boxes of the
     * displacements in s->ebox), or the check is made here */
    const int checked = (pred == 0 || pred == 1) && s->skin_used == skin0;
    int moved = checked ? pred : 0, reordered = 0;
    if (listed ? sep_ebox_reserve(s, err) || sep_g_reserve(s, err) : sep_pv_reserve(s, err))
        return err->code;
    if (!listed)
        c.pvx = s->pv, c.pvy = s->pv + n, c.pvz = s->pv + 2 * n;
    const double *xref = s->xref;
    if (!listed || (can && !checked)) {
        const int predict = !listed;
        const size_t nblk = (n + SEP_EBLK - 1) / SEP_EBLK;
        double *ebox = s->ebox;
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1) reduction(| : moved)
        for (size_t b = 0; b < nblk; b++) {
            double lx = INFINITY, ly = INFINITY, lz = INFINITY, hx = -INFINITY, hy = -INFINITY,
                   hz = -INFINITY;
            const size_t end = (b + 1) * SEP_EBLK < n ? (b + 1) * SEP_EBLK : n;
            for (size_t i = b * SEP_EBLK; i < end; i++) {
                if (predict) {
                    const double h = c.half_dt * s->im[i];
                    c.pvx[i] = s->vx[i] + h * s->fx[i];
                    c.pvy[i] = s->vy[i] + h * s->fy[i];
                    c.pvz[i] = s->vz[i] + h * s->fz[i];
                }
                if (can) {
                    const double *q = xref + 3 * i;
                    const double dx = s->x[i] - q[0], dy = s->y[i] - q[1], dz = s->z[i] - q[2];
                    moved |= dx * dx + dy * dy + dz * dz > lim;
                    lx = dx < lx ? dx : lx, ly = dy < ly ? dy : ly, lz = dz < lz ? dz : lz;
                    hx = dx > hx ? dx : hx, hy = dy > hy ? dy : hy, hz = dz > hz ? dz : hz;
                }
            }
            if (can) {
                double *e = ebox + 6 * b;
                e[0] = lx, e[1] = ly, e[2] = lz, e[3] = hx, e[4] = hy, e[5] = hz;
            }
        }
    }
    if (listed) {
        if (!can || moved) {
            /* the periodic reorder by cells (spec 2.9) rides on a rebuild, and on the first:
             * particles placed at random have neighbours anywhere in the arrays, which costs
             * cache misses on one thread and the other thread's cache lines on two */
            int rc = sep_hist_stash(s, err);
            if (!rc && s->nsort > 0 &&
                (s->list_builds == 0 || s->steps - s->last_sort >= (uint64_t)s->nsort)) {
                rc = sep_cells_build(s, err);
                if (!rc)
                    rc = sep_reorder(s, err);
                reordered = 1;
            }
            if (!rc)
                rc = list_build(s, err);
            if (rc)
                return rc;
        }
        if (s->hertz && !s->hist_ok && sep_hist_fill(s, err))
            return err->code;
        /* (the drift's wall tests hold for the particles as they are: checked, not reordered) */
        if (s->hertz)
            list_forces_hm(s, &c, kick, checked && !reordered ? s->exc : NULL);
        else
            list_forces(s, &c, g_w, kick, !can || moved, checked && !reordered ? s->exc : NULL,
                        dmin);
        return MOTE_OK;
    }
    /* brute force, or no list (the cells as built for this step's feed serve when nothing was
     * added): walls, the pairs once each, plates, in that order per particle */
    if (!s->brute && !(s->built_step == s->steps + 1 && s->n_built == s->n)) {
        int rc = sep_cells_build(s, err);
        if (rc)
            return rc;
    }
    double mo = s->max_overlap;
    for (size_t i = 0; i < n; i++) {
        double F[3] = {0, 0, 0};
        const double pvel[3] = {c.pvx[i], c.pvy[i], c.pvz[i]};
        wall_force(s, i, c.khat, g_w, pvel, F, &mo);
        s->fx[i] = F[0];
        s->fy[i] = F[1];
        s->fz[i] = F[2];
    }
    s->max_overlap = mo;
    s->contacts_pp = 0;
    each_pair(s, s->brute, pair_force, &c);
    mo = s->max_overlap;
    for (size_t i = 0; i < n; i++) {
        double F[3] = {s->fx[i], s->fy[i], s->fz[i]};
        const double pvel[3] = {c.pvx[i], c.pvy[i], c.pvz[i]};
        plate_force(s, i, c.khat, g_w, pvel, F, &mo);
        if (s->nmesh)
            mesh_force(s, &c, i, g_w, pvel, F, &mo);
        s->fx[i] = F[0];
        s->fy[i] = F[1];
        s->fz[i] = F[2];
        if (kick) {
            const double h = c.half_dt * s->im[i];
            s->vx[i] += h * F[0];
            s->vy[i] += h * F[1];
            s->vz[i] += h * F[2];
        }
    }
    s->max_overlap = mo;
    return MOTE_OK;
}

/* ---- the order of the particles ------------------------------------------------------------ */

/* Put the particles in the order of the cell lists just built from the present positions (spec
 * 2.9: memory locality; the ids do not change, and the order is a function of the positions,
 * so runs stay reproducible). */
int sep_reorder(mote_sep_system *s, mote_err *err)
{
    const size_t n = s->n;
    void *tmp = malloc((n ? n : 1) * sizeof(double));
    if (!tmp)
        return mote_fail(err, MOTE_ENOMEM, "separator: out of memory to reorder");
    const uint32_t *p = s->grid.order;
#define PERMUTE(f, T)                                                                             \
    do {                                                                                          \
        T *t_ = tmp;                                                                              \
        for (size_t k = 0; k < n; k++)                                                            \
            t_[k] = s->f[p[k]];                                                                   \
        memcpy(s->f, t_, n * sizeof(T));                                                          \
    } while (0)
    PERMUTE(x, double);
    PERMUTE(y, double);
    PERMUTE(z, double);
    PERMUTE(vx, double);
    PERMUTE(vy, double);
    PERMUTE(vz, double);
    PERMUTE(d, double);
    PERMUTE(m, double);
    PERMUTE(im, double);
    PERMUTE(fx, double);
    PERMUTE(fy, double);
    PERMUTE(fz, double);
    PERMUTE(s, int);
    PERMUTE(id, uint64_t);
#undef PERMUTE
    /* the rotation's arrays: k values a particle */
    double *rot[4] = {s->w, s->tq, s->wh, s->mh};
    const int kr[4] = {3, 3, 9, 4 * SEP_MESH_SLOTS};
    for (int a = 0; a < 4 && s->w; a++) {
        if (!rot[a])
            continue;
        double *t_ = malloc((n ? n : 1) * (size_t)kr[a] * sizeof *t_);
        if (!t_) {
            free(tmp);
            return mote_fail(err, MOTE_ENOMEM, "separator: out of memory to reorder");
        }
        for (size_t k = 0; k < n; k++)
            memcpy(t_ + (size_t)kr[a] * k, rot[a] + (size_t)kr[a] * p[k], (size_t)kr[a] * sizeof *t_);
        memcpy(rot[a], t_, n * (size_t)kr[a] * sizeof *t_);
        free(t_);
    }
    s->nb_idx_ok = 0;
    /* (the predicted velocities are made where they are needed, after any reorder) */
    s->last_sort = s->steps;
    free(tmp);
    s->built_step = 0; /* the lists now point at the old order */
    s->list_ok = 0;
    return MOTE_OK;
}

/* ---- rotation and the tangential springs (contact hertz) ------------------------------------ */

int sep_rot_reserve(mote_sep_system *s, mote_err *err)
{
    const size_t cap = s->cap ? s->cap : 1;
    if (s->nmesh && s->mh_cap < cap) { /* (the walls' springs: 4 numbers a slot) */
        const size_t k = 4 * SEP_MESH_SLOTS, old = s->mh ? s->mh_cap : 0;
        double *p = realloc(s->mh, cap * k * sizeof *p);
        if (!p)
            return mote_fail(err, MOTE_ENOMEM, "separator: out of memory for the wall springs "
                             "of %zu particles", cap);
        memset(p + old * k, 0, (cap - old) * k * sizeof *p);
        s->mh = p;
        s->mh_cap = cap;
    }
    if (s->w && s->rot_cap >= cap)
        return MOTE_OK;
    double **a[4] = {&s->w, &s->tq, &s->tq2, &s->wh};
    const size_t k[4] = {3, 3, 3, 9};
    const size_t old = s->w ? s->rot_cap : 0;
    for (int q = 0; q < 4; q++) {
        double *p = realloc(*a[q], cap * k[q] * sizeof *p);
        if (!p)
            return mote_fail(err, MOTE_ENOMEM, "separator: out of memory for the rotation of %zu "
                             "particles", cap);
        memset(p + old * k[q], 0, (cap - old) * k[q] * sizeof *p);
        *a[q] = p;
    }
    s->rot_cap = cap;
    return MOTE_OK;
}

static int cmp_hrec(const void *x, const void *y)
{
    const struct sep_hrec *a = x, *b = y;
    return a->a != b->a ? (a->a > b->a) - (a->a < b->a) : (a->b > b->b) - (a->b < b->b);
}

/* The list's springs that are not zero, by id (each pair once: from its owner entry, in the
 * row of its lower index; the spring is in the order lower id first), appended to *out (of
 * *cap), sorted. */
static int hist_from_list(const mote_sep_system *s, struct sep_hrec **out, size_t *n,
                          size_t *cap, mote_err *err)
{
    const size_t nr = s->nb_n < s->n ? s->nb_n : s->n;
    for (size_t i = 0; i < nr; i++)
        for (uint32_t e = s->nb_start[i]; e < s->nb_start[i + 1]; e++) {
            const size_t j = s->nb[e];
            const double *xi = s->hist + 3 * (size_t)e;
            if (j >= s->n || !(i < j) || (xi[0] == 0 && xi[1] == 0 && xi[2] == 0))
                continue;
            if (sep_reserve((void **)out, cap, *n + 1, sizeof **out, err))
                return err->code;
            const uint64_t ia = s->id[i], ib = s->id[j];
            (*out)[(*n)++] = (struct sep_hrec){ia < ib ? ia : ib, ia < ib ? ib : ia,
                                               {xi[0], xi[1], xi[2]}};
        }
    if (*n > 1)
        qsort(*out, *n, sizeof **out, cmp_hrec);
    return MOTE_OK;
}

int sep_hist_stash(mote_sep_system *s, mote_err *err)
{
    if (!s->hertz || s->hmap_pending)
        return MOTE_OK;
    s->nhmap = 0;
    if (s->hist_ok && s->nb_idx_ok && s->hist &&
        hist_from_list(s, &s->hmap, &s->nhmap, &s->hmap_cap, err))
        return err->code;
    s->hmap_pending = 1;
    return MOTE_OK;
}

int sep_hist_collect(const mote_sep_system *s, struct sep_hrec **out, size_t *n, mote_err *err)
{
    size_t cap = 0;
    *out = NULL;
    *n = 0;
    if (!s->hertz)
        return MOTE_OK;
    if (s->hmap_pending) {
        if (s->nhmap) {
            *out = malloc(s->nhmap * sizeof **out);
            if (!*out)
                return mote_fail(err, MOTE_ENOMEM, "separator: out of memory");
            memcpy(*out, s->hmap, s->nhmap * sizeof **out);
            *n = s->nhmap;
        }
        return MOTE_OK;
    }
    if (s->hist_ok && s->nb_idx_ok && s->hist && hist_from_list(s, out, n, &cap, err)) {
        free(*out);
        *out = NULL;
        return err->code;
    }
    return MOTE_OK;
}

int sep_hist_fill(mote_sep_system *s, mote_err *err)
{
    const size_t nr = s->nb_n, ne = s->nb_start ? s->nb_start[nr] : 0;
    if (sep_reserve((void **)&s->hist, &s->hist_cap, 3 * ne + 3, sizeof *s->hist, err) ||
        sep_reserve((void **)&s->mir, &s->mir_cap, ne + 1, sizeof *s->mir, err) ||
        sep_reserve((void **)&s->cidx, &s->cidx_cap, ne + 1, sizeof *s->cidx, err) ||
        sep_reserve((void **)&s->ostart, &s->ostart_cap, nr + 1, sizeof *s->ostart, err))
        return err->code;
    /* (rows sorted: a row's owner entries are its last) */
    uint32_t *ostart = s->ostart;
    ostart[0] = 0;
    for (size_t i = 0; i < nr; i++) {
        uint32_t e = s->nb_start[i + 1];
        while (e > s->nb_start[i] && s->nb[e - 1] > i)
            e--;
        ostart[i + 1] = ostart[i] + (s->nb_start[i + 1] - e);
    }
    if (sep_reserve((void **)&s->pbuf, &s->pbuf_cap, 9 * ((size_t)ostart[nr] + 1),
                    sizeof *s->pbuf, err))
        return err->code;
    for (int b = 0; b < 9; b++)
        s->pbuf[b] = 0;
    const struct sep_hrec *map = s->hmap_pending ? s->hmap : NULL;
    const size_t nm = map ? s->nhmap : 0;
    const int nt = sep_threads(s);
    double *hist = s->hist;
    const uint64_t *id = s->id;
    const uint32_t *nb = s->nb, *start = s->nb_start;
    uint32_t *mir = s->mir;
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
    for (size_t i = 0; i < nr; i++)
        for (uint32_t e = start[i]; e < start[i + 1]; e++) {
            double *xi = hist + 3 * (size_t)e;
            /* an owner entry's (i, j > i) partner entry: j's entry for i (rows sorted) */
            const size_t jj = nb[e];
            if (jj > i) {
                uint32_t lo = start[jj], hi = start[jj + 1];
                while (lo < hi) {
                    const uint32_t mid = lo + (hi - lo) / 2;
                    if (nb[mid] < i)
                        lo = mid + 1;
                    else
                        hi = mid;
                }
                mir[e] = lo;
                mir[lo] = (uint32_t)e; /* (its only writer) */
            }
            xi[0] = xi[1] = xi[2] = 0;
            if (!nm || jj < i) /* (a spring lives at its owner entry only) */
                continue;
            const size_t j = jj;
            const struct sep_hrec key = {id[i] < id[j] ? id[i] : id[j],
                                         id[i] < id[j] ? id[j] : id[i], {0, 0, 0}};
            const struct sep_hrec *r = bsearch(&key, map, nm, sizeof *map, cmp_hrec);
            if (r)
                memcpy(xi, r->xi, sizeof r->xi);
        }
    s->hmap_pending = 0;
    s->nhmap = 0;
    s->hist_ok = 1;
    return MOTE_OK;
}
