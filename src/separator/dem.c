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

#define SEP_PI 3.14159265358979323846

/* zeta(e) = -ln e / sqrt(pi^2 + ln^2 e): the damping ratio giving restitution e */
static double zeta_of(double e)
{
    const double l = log(e);
    return -l / sqrt(SEP_PI * SEP_PI + l * l);
}

double mote_sep_khat(const mote_sep_system *s)
{
    if (s->khat > 0)
        return s->khat;
    double rho_max = 0, vt = 0, dmin, dmax;
    mote_sep_size_range(s, &dmin, &dmax);
    for (int k = 0; k < s->nsp; k++) {
        rho_max = fmax(rho_max, s->sp[k].rho);
        const double v = mote_sep_terminal_velocity(mote_sep_dist_max(&s->sp[k].dist),
                                                    s->sp[k].rho, s->rho_g, s->mu_g, s->g, NULL);
        if (isfinite(v))
            vt = fmax(vt, v);
    }
    const double vf = sqrt(s->vf[0] * s->vf[0] + s->vf[1] * s->vf[1] + s->vf[2] * s->vf[2]);
    double vimp = s->v_imp > 0 ? s->v_imp : fmax(fmax(s->U0, vt), vf);
    if (!(vimp > 0))
        vimp = 1; /* nothing moves: any stiffness; 1 m/s */
    const double df = s->delta_f > 0 ? s->delta_f : 0.05;
    return SEP_PI * rho_max * vimp * vimp / (6 * df * df);
}

double mote_sep_dt_limit(const mote_sep_system *s)
{
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

static void each_pair_reach(mote_sep_system *s, int brute, double skin, pair_fn fn, void *ctx);

static void each_pair(mote_sep_system *s, int brute, pair_fn fn, void *ctx)
{
    each_pair_reach(s, brute, 0, fn, ctx);
}

/* Pairs closer than r_i + r_j (skin 0: fn gets the overlap test's dx and d2) or r_i + r_j +
 * skin (skin > 0: fn gets dx = NULL). */
#define SEP_VISIT(i, j)                                                                           \
    do {                                                                                          \
        if (skin > 0) {                                                                           \
            if (near(s, i, j, skin))                                                              \
                fn(s, i, j, NULL, 0, ctx);                                                        \
        } else if (overlap(s, i, j, dx, &d2)) {                                                   \
            fn(s, i, j, dx, d2, ctx);                                                             \
        }                                                                                         \
    } while (0)

static void each_pair_reach(mote_sep_system *s, int brute, double skin, pair_fn fn, void *ctx)
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

typedef struct {
    double khat, half_dt;
    double g_pp[MOTE_SEP_MAX_SPECIES * MOTE_SEP_MAX_SPECIES]; /* 2 zeta(e) per species pair */
    double *pvx, *pvy, *pvz;    /* predicted velocities */
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

static void list_add(mote_sep_system *s, size_t i, size_t j, const double dx[3], double d2,
                     void *ctx)
{
    (void)dx;
    (void)d2;
    int *fail = ctx;
    if (s->npl == s->pl_cap) {
        const size_t cap = s->pl_cap ? 2 * s->pl_cap : 1024;
        uint32_t *p = realloc(s->plist, 2 * cap * sizeof *p);
        if (!p) {
            *fail = 1;
            return;
        }
        s->plist = p;
        s->pl_cap = cap;
    }
    s->plist[2 * s->npl] = (uint32_t)i;
    s->plist[2 * s->npl + 1] = (uint32_t)j;
    s->npl++;
}

static int list_build(mote_sep_system *s, mote_err *err)
{
    int rc = sep_cells_build(s, err);
    if (rc)
        return rc;
    if (3 * s->n > s->xref_cap) {
        const size_t cap = 3 * s->n + 3 * s->n / 2 + 3;
        double *p = realloc(s->xref, cap * sizeof *p);
        if (!p)
            return mote_fail(err, MOTE_ENOMEM, "separator: out of memory for the pair list");
        s->xref = p;
        s->xref_cap = cap;
    }
    for (size_t i = 0; i < s->n; i++) {
        s->xref[3 * i] = s->x[i];
        s->xref[3 * i + 1] = s->y[i];
        s->xref[3 * i + 2] = s->z[i];
    }
    s->npl = 0;
    int fail = 0;
    each_pair_reach(s, 0, s->skin_used, list_add, &fail);
    if (fail)
        return mote_fail(err, MOTE_ENOMEM, "separator: out of memory for the pair list");
    s->list_ok = 1;
    s->list_mods = s->mods;
    s->list_builds++;
    return MOTE_OK;
}

/* The contact forces of every particle from the current positions; the dashpots with the
 * predicted velocities v + dt/2 F_old/m (spec 2.10 step 6). */
int sep_contact_forces(mote_sep_system *s, double dt, mote_err *err)
{
    const size_t n = s->n;
    if (!s->pv || 3 * n > s->pv_cap) { /* (allocated even for no particle: pv + n is then valid) */
        const size_t cap = 3 * n + 3 * n / 2 + 3;
        double *p = realloc(s->pv, cap * sizeof *p);
        if (!p)
            return mote_fail(err, MOTE_ENOMEM, "separator: out of memory for the contacts");
        s->pv = p;
        s->pv_cap = cap;
    }
    double *pv = s->pv;
    force_ctx c = {.khat = s->khat_used, .half_dt = 0.5 * dt, .pvx = pv, .pvy = pv + n,
                   .pvz = pv + 2 * n};
    for (int a = 0; a < s->nsp; a++)
        for (int b = 0; b < s->nsp; b++) {
            const double e = s->e_pair[a][b] > 0 ? s->e_pair[a][b] : s->e_pp;
            c.g_pp[a * MOTE_SEP_MAX_SPECIES + b] = e < 1 ? 2 * zeta_of(e) : 0;
        }
    /* one pass: the predicted velocities, the forces zeroed, the walls and closed ends (k =
     * k_hat d, m = m_i, the wall at rest), and whether the pair list still holds (nothing added,
     * removed or reordered, no particle moved more than skin/2 since its build) */
    double dmin, dmax;
    mote_sep_size_range(s, &dmin, &dmax);
    s->skin_used = s->brute || s->skin < 0 ? 0 : s->skin > 0 ? s->skin : 0.3 * dmin;
    int valid = !s->brute && s->list_ok && s->mods == s->list_mods && s->skin_used > 0;
    const double lim = 0.25 * s->skin_used * s->skin_used;
    const double e_w = s->e_pw >= 0 ? s->e_pw : s->e_pp, g_w = e_w < 1 ? 2 * zeta_of(e_w) : 0;
    const double hi[3] = {s->W, s->D, s->H};
    s->contacts_pp = 0;
    for (size_t i = 0; i < n; i++) {
        const double h = 0.5 * dt * s->im[i];
        const double pvel[3] = {s->vx[i] + h * s->fx[i], s->vy[i] + h * s->fy[i],
                                s->vz[i] + h * s->fz[i]};
        c.pvx[i] = pvel[0];
        c.pvy[i] = pvel[1];
        c.pvz[i] = pvel[2];
        double F[3] = {0, 0, 0};
        const double pos[3] = {s->x[i], s->y[i], s->z[i]}, r = 0.5 * s->d[i];
        for (int a = 0; a < 3; a++) {
            if (a == 1 && s->dim == 2)
                continue;
            const int lo_wall = a < 2 || !s->open_bottom, hi_wall = a < 2 || !s->open_top;
            const double dlo = r - pos[a], dhi = pos[a] + r - hi[a];
            if ((lo_wall && dlo > 0) || (hi_wall && dhi > 0)) {
                const double k = c.khat * s->d[i], gam = g_w * sqrt(s->m[i] * k);
                if (lo_wall && dlo > 0) /* the wall's normal +a; approach rate -v_a */
                    F[a] += k * dlo - gam * pvel[a];
                if (hi_wall && dhi > 0) /* normal -a; approach rate +v_a */
                    F[a] -= k * dhi + gam * pvel[a];
                const double ov = (dlo > dhi ? dlo : dhi) / s->d[i];
                if (ov > s->max_overlap)
                    s->max_overlap = ov;
            }
        }
        s->fx[i] = F[0];
        s->fy[i] = F[1];
        s->fz[i] = F[2];
        if (valid) {
            const double *q = s->xref + 3 * i;
            const double dx = pos[0] - q[0], dy = pos[1] - q[1], dz = pos[2] - q[2];
            if (dx * dx + dy * dy + dz * dz > lim)
                valid = 0;
        }
    }
    if (s->brute) {
        each_pair(s, 1, pair_force, &c);
    } else if (s->skin_used > 0) {
        if (!valid) {
            /* the periodic reorder by cells (spec 2.9) rides on a rebuild */
            int rc = MOTE_OK;
            if (s->nsort > 0 && s->steps - s->last_sort >= (uint64_t)s->nsort) {
                rc = sep_cells_build(s, err);
                if (!rc)
                    rc = sep_reorder(s, err);
            }
            if (!rc)
                rc = list_build(s, err);
            if (rc)
                return rc;
        }
        /* the listed pairs, with the overlap test of the search */
        double dx[3], d2;
        for (size_t k = 0; k < s->npl; k++) {
            const size_t i = s->plist[2 * k], j = s->plist[2 * k + 1];
            if (overlap(s, i, j, dx, &d2))
                pair_force(s, i, j, dx, d2, &c);
        }
    } else {
        /* no list: the cells as built for this step's feed serve when nothing was added */
        if (!(s->built_step == s->steps + 1 && s->n_built == s->n)) {
            int rc = sep_cells_build(s, err);
            if (rc)
                return rc;
        }
        each_pair(s, 0, pair_force, &c);
    }
    /* plates: one contact per feature (a hole's side faces, or the top or bottom face) */
    for (int q = 0; q < s->nplate; q++)
        for (size_t i = 0; i < n; i++) {
            const double r = 0.5 * s->d[i], c3[3] = {s->x[i], s->y[i], s->z[i]};
            double delta[4], nrm[4][3];
            const int nf = mote_sep_plate_features(&s->plate[q], s->dim, c3, r, delta, nrm);
            if (nf <= 0)
                continue;
            const double k = c.khat * s->d[i], gam = g_w * sqrt(s->m[i] * k);
            for (int f = 0; f < nf; f++) {
                const double vn = c.pvx[i] * nrm[f][0] + c.pvy[i] * nrm[f][1] + c.pvz[i] * nrm[f][2];
                const double F = k * delta[f] - gam * vn;
                s->fx[i] += F * nrm[f][0];
                s->fy[i] += F * nrm[f][1];
                s->fz[i] += F * nrm[f][2];
                s->max_overlap = fmax(s->max_overlap, delta[f] / s->d[i]);
            }
        }
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
    /* the predicted velocities too, when they are current (the contacts' pass) */
    for (int b = 0; b < 3 && s->pv_cap >= 3 * n; b++) {
        double *t_ = tmp, *f = s->pv + (size_t)b * n;
        for (size_t k = 0; k < n; k++)
            t_[k] = f[p[k]];
        memcpy(f, t_, n * sizeof *f);
    }
    s->last_sort = s->steps;
    free(tmp);
    s->built_step = 0; /* the lists now point at the old order */
    s->list_ok = 0;
    return MOTE_OK;
}
