/* fcache.c: a cache of the solved field for the paths (issue 55). Most of a path's steps are
 * away from the surface, where the treecode (ftree.c) still costs microseconds an evaluation;
 * the cache answers there from an octree of cells with the potential and the field at their
 * corners, interpolated trilinearly. A cell is kept when the interpolation at its centre and the
 * centres of its faces is within the tolerance of the tree's values; otherwise it is cut in
 * eight, down to the smallest size, where it is left to the tree. A cell that holds a triangle
 * (its bounding box widened by half the cell) is always cut, and at the smallest size left to
 * the tree: the field jumps across a sheet and is singular at edges, which no interpolation
 * follows. With several conductors (each at its own potential) the cache holds each one's field
 * per volt (the same cells for all), and a run combines them with its potentials. */
#include "ch.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#define FC_MIN_LEVEL 2   /* cells are cut at least this many times (the root is coarse) */

/* Nodes and leaves' values: the whole cache's, or one subtree's while it is built (the 64
 * cells two cuts below the root are built side by side, each into its own arena, then joined) */
typedef struct {
    int nc, levels;
    int32_t *child;       /* per node: the first of its 8 children, or -1 for a leaf */
    int32_t *data;        /* per leaf: its corner values' index, or -1 (the tree answers) */
    float *vals;          /* per data index: [nc][8 corners][phi, E] (single precision: 1e-7,
                           * far below the tolerance) */
    size_t nnodes, ndata, cap_nodes, cap_data;
    long cached_leaves, tree_leaves;
} fc_arena;

struct ch_fcache {
    double lo[3], size;   /* the root cube */
    fc_arena a;
};

typedef struct {
    fc_arena *c;
    const mote_ch_body *b;
    mote_ch_ftree *const *trees;
    const double (*tlo)[3], (*thi)[3]; /* the triangles' bounding boxes */
    double tol, escale;
    atomic_long *cells;   /* the cells made so far by every subtree, against max_cells */
    long max_cells;
} fc_build;

static int grow(fc_arena *c, int nodes, int data)
{
    if (nodes && c->nnodes + 8 > c->cap_nodes) {
        const size_t cap = c->cap_nodes ? 2 * c->cap_nodes : 1024;
        int32_t *ch = realloc(c->child, cap * sizeof *ch);
        if (!ch)
            return -1;
        c->child = ch;
        int32_t *d = realloc(c->data, cap * sizeof *d);
        if (!d)
            return -1;
        c->data = d;
        c->cap_nodes = cap;
    }
    if (data && c->ndata + 1 > c->cap_data) {
        const size_t cap = c->cap_data ? 2 * c->cap_data : 256;
        float *v = realloc(c->vals, cap * (size_t)c->nc * 32 * sizeof *v);
        if (!v)
            return -1;
        c->vals = v;
        c->cap_data = cap;
    }
    return 0;
}

/* Trilinear interpolation of the 8 corners' (phi, E) at the fractions f of the cell. */
static void trilinear(const float *v, const double f[3], double out[4])
{
    const double g[3] = {1 - f[0], 1 - f[1], 1 - f[2]};
    for (int q = 0; q < 4; q++)
        out[q] = 0;
    for (int k = 0; k < 8; k++) {
        const double w = (k & 1 ? f[0] : g[0]) * (k & 2 ? f[1] : g[1]) * (k & 4 ? f[2] : g[2]);
        for (int q = 0; q < 4; q++)
            out[q] += w * (double)v[4 * k + q];
    }
}

/* Does triangle i meet the cube of centre cc and half-width h? The separating axes of a box and
 * a triangle (Akenine-Moeller 2001): the box's three, the triangle's normal and the nine cross
 * products of their edges. */
static int tri_meets_cube(const mote_ch_body *b, uint32_t i, const double cc[3], double h)
{
    double v[3][3], e[3][3];
    for (int k = 0; k < 3; k++)
        for (int a = 0; a < 3; a++)
            v[k][a] = b->v[i][k][a] - cc[a];
    for (int a = 0; a < 3; a++) {
        e[0][a] = v[1][a] - v[0][a];
        e[1][a] = v[2][a] - v[1][a];
        e[2][a] = v[0][a] - v[2][a];
    }
    for (int j = 0; j < 3; j++)      /* the box's axis j */
        for (int k = 0; k < 3; k++) { /* crossed with edge k */
            double ax[3] = {0, 0, 0};
            ax[(j + 1) % 3] = -e[k][(j + 2) % 3];
            ax[(j + 2) % 3] = e[k][(j + 1) % 3];
            double lo = INFINITY, hi = -INFINITY;
            for (int q = 0; q < 3; q++) {
                const double p = ax[0] * v[q][0] + ax[1] * v[q][1] + ax[2] * v[q][2];
                lo = fmin(lo, p);
                hi = fmax(hi, p);
            }
            const double r = h * (fabs(ax[0]) + fabs(ax[1]) + fabs(ax[2]));
            if (lo > r || hi < -r)
                return 0;
        }
    const double n[3] = {e[0][1] * e[1][2] - e[0][2] * e[1][1],
                         e[0][2] * e[1][0] - e[0][0] * e[1][2],
                         e[0][0] * e[1][1] - e[0][1] * e[1][0]};
    const double d = n[0] * v[0][0] + n[1] * v[0][1] + n[2] * v[0][2];
    return fabs(d) <= h * (fabs(n[0]) + fabs(n[1]) + fabs(n[2]));
}

/* The triangles that meet the cell widened by pad on every side (first by their boxes, then
 * exactly): idx the parent's candidates, the cell's own into out (count returned). */
static size_t cell_triangles(const fc_build *B, const double lo[3], double h, double pad,
                             const uint32_t *idx, size_t n, uint32_t *out)
{
    size_t m = 0;
    const double cc[3] = {lo[0] + 0.5 * h, lo[1] + 0.5 * h, lo[2] + 0.5 * h};
    for (size_t j = 0; j < n; j++) {
        const uint32_t i = idx[j];
        int in = 1;
        for (int a = 0; a < 3 && in; a++)
            in = B->thi[i][a] + pad >= lo[a] && B->tlo[i][a] - pad <= lo[a] + h;
        if (in && tri_meets_cube(B->b, i, cc, 0.5 * h + pad))
            out[m++] = i;
    }
    return m;
}

static int build_node(const fc_build *B, size_t node, const double lo[3], double h, int level,
                      const uint32_t *idx, size_t n)
{
    fc_arena *c = B->c;
    const int nc = c->nc;
    uint32_t *mine = n ? malloc(n * sizeof *mine) : NULL;
    if (n && !mine)
        return -1;
    const size_t m = cell_triangles(B, lo, h, 0.5 * h, idx, n, mine);
    int keep = 0;
    double corner[8 * 4 * MOTE_CH_BEM_MAX_CONDUCTORS];
    float cf[8 * 4 * MOTE_CH_BEM_MAX_CONDUCTORS];
    if (m == 0 && level >= FC_MIN_LEVEL) {
        /* the corners, then the centre and the face centres against the interpolation */
        for (int k = 0; k < 8; k++) {
            const double x[3] = {lo[0] + (k & 1 ? h : 0), lo[1] + (k & 2 ? h : 0),
                                 lo[2] + (k & 4 ? h : 0)};
            for (int s = 0; s < nc; s++) {
                double *v = corner + 32 * s + 4 * k;
                mote_ch_ftree_eval(B->trees[s], x, &v[0], v + 1);
                for (int q = 0; q < 4; q++)
                    cf[32 * s + 4 * k + q] = (float)v[q];
            }
        }
        static const double probe[7][3] = {{0.5, 0.5, 0.5}, {0, 0.5, 0.5}, {1, 0.5, 0.5},
                                           {0.5, 0, 0.5},   {0.5, 1, 0.5}, {0.5, 0.5, 0},
                                           {0.5, 0.5, 1}};
        keep = 1;
        for (int p = 0; p < 7 && keep; p++) {
            const double x[3] = {lo[0] + probe[p][0] * h, lo[1] + probe[p][1] * h,
                                 lo[2] + probe[p][2] * h};
            for (int s = 0; s < nc && keep; s++) {
                double ex[4], in[4];
                mote_ch_ftree_eval(B->trees[s], x, &ex[0], ex + 1);
                trilinear(cf + 32 * s, probe[p], in);
                const double dE = sqrt((in[1] - ex[1]) * (in[1] - ex[1]) +
                                       (in[2] - ex[2]) * (in[2] - ex[2]) +
                                       (in[3] - ex[3]) * (in[3] - ex[3]));
                const double Em = sqrt(ex[1] * ex[1] + ex[2] * ex[2] + ex[3] * ex[3]);
                keep = fabs(in[0] - ex[0]) <= B->tol && dE <= B->tol * (Em + B->escale);
            }
        }
    }
    if (keep || level == c->levels) {
        free(mine);
        c->child[node] = -1;
        if (!keep) {
            c->data[node] = -1;
            c->tree_leaves++;
            return 0;
        }
        if (grow(c, 0, 1))
            return -1;
        c->data[node] = (int32_t)c->ndata;
        memcpy(c->vals + c->ndata * (size_t)nc * 32, cf, (size_t)nc * 32 * sizeof *cf);
        c->ndata++;
        c->cached_leaves++;
        return 0;
    }
    if (atomic_fetch_add(B->cells, 8) + 8 > B->max_cells) { /* the memory bound */
        free(mine);
        return -2;
    }
    if (grow(c, 1, 0)) {
        free(mine);
        return -1;
    }
    const size_t first = c->nnodes;
    c->nnodes += 8;
    c->child[node] = (int32_t)first;
    c->data[node] = -1;
    int rc = 0;
    for (int k = 0; k < 8 && !rc; k++) {
        const double l2[3] = {lo[0] + (k & 1 ? 0.5 * h : 0), lo[1] + (k & 2 ? 0.5 * h : 0),
                              lo[2] + (k & 4 ? 0.5 * h : 0)};
        rc = build_node(B, first + (size_t)k, l2, 0.5 * h, level + 1, mine, m);
    }
    free(mine);
    return rc;
}

ch_fcache *ch_fcache_build(const mote_ch_body *b, const mote_ch_bem *f, double theta,
                           const double centre[3], double half, double hmin, double tol,
                           double max_bytes, int threads, mote_err *err)
{
    const int nc = f->nc;
    enum { NSUB = 64 }; /* the subtrees two cuts below the root */
    ch_fcache *c = calloc(1, sizeof *c);
    mote_ch_ftree *trees[MOTE_CH_BEM_MAX_CONDUCTORS] = {0};
    double(*tlo)[3] = malloc((size_t)b->ntri * sizeof *tlo);
    double(*thi)[3] = malloc((size_t)b->ntri * sizeof *thi);
    uint32_t *idx = malloc((size_t)b->ntri * sizeof *idx);
    fc_arena *sub = calloc(NSUB, sizeof *sub);
    int rc = !c || !tlo || !thi || !idx || !sub || nc < 1 || nc > MOTE_CH_BEM_MAX_CONDUCTORS;
    for (int s = 0; !rc && s < nc; s++)
        rc = !(trees[s] = mote_ch_ftree_build(b, nc == 1 ? f->sigma : f->basis + (size_t)s * f->n,
                                              theta, err));
    if (!rc) {
        c->size = 2 * half;
        for (int a = 0; a < 3; a++)
            c->lo[a] = centre[a] - half;
        int levels = FC_MIN_LEVEL;
        while (c->size / (double)(1 << levels) > hmin && levels < 12)
            levels++;
        for (uint32_t i = 0; i < b->ntri; i++) {
            idx[i] = i;
            for (int a = 0; a < 3; a++) {
                tlo[i][a] = fmin(b->v[i][0][a], fmin(b->v[i][1][a], b->v[i][2][a]));
                thi[i][a] = fmax(b->v[i][0][a], fmax(b->v[i][1][a], b->v[i][2][a]));
            }
        }
        /* the 64 subtrees side by side (the tree's evaluation is read-only), each from its
         * cell two cuts below the root, into its own arena */
        const double q = 0.25 * c->size;
        /* at most max_bytes: a cell's values are nc 128 bytes, its node 8 */
        const long max_cells = (long)(max_bytes / ((double)nc * 128 + 8));
        atomic_long cells;
        atomic_init(&cells, 0);
        int bad = 0, over = 0;
#pragma omp parallel for num_threads(threads > 1 ? threads : 1) schedule(dynamic, 1) \
    reduction(| : bad, over)
        for (int k = 0; k < NSUB; k++) {
            fc_arena *A = &sub[k];
            A->nc = nc;
            A->levels = levels;
            const double lo[3] = {c->lo[0] + q * (k & 3), c->lo[1] + q * ((k >> 2) & 3),
                                  c->lo[2] + q * (k >> 4)};
            fc_build B = {A,   b,        trees, (const double(*)[3])tlo, (const double(*)[3])thi,
                          tol, 1 / half, &cells, max_cells};
            if (grow(A, 1, 0)) {
                bad = 1;
                continue;
            }
            A->nnodes = 1;
            const int r = build_node(&B, 0, lo, q, FC_MIN_LEVEL, idx, b->ntri);
            over |= r == -2;
            bad |= r != 0;
        }
        if (over) {
            rc = 1;
            mote_fail(err, MOTE_ENOMEM, "field solved: the paths' cache would take more than "
                      "%.0f MB (%d conductors' fields in every cell): use cache=off",
                      max_bytes / 1e6, nc);
        }
        /* joined: the root, its 8 children, their 64, then each arena's own below its root */
        fc_arena *W = &c->a;
        W->nc = nc;
        W->levels = levels;
        size_t nn = 1 + 8 + NSUB, nd = 0;
        for (int k = 0; k < NSUB; k++) {
            nn += sub[k].nnodes - 1;
            nd += sub[k].ndata;
        }
        W->child = malloc(nn * sizeof *W->child);
        W->data = malloc(nn * sizeof *W->data);
        rc = rc || bad || !W->child || !W->data;
        if (!rc) {
            W->cap_nodes = W->nnodes = nn;
            W->cap_data = W->ndata = nd;
            W->child[0] = 1;
            W->data[0] = -1;
            for (int o = 0; o < 8; o++) { /* the level-1 octant o: children 9 + 8 o ... */
                W->child[1 + o] = 9 + 8 * o;
                W->data[1 + o] = -1;
            }
            size_t nbase = 1 + 8 + NSUB, dbase = 0;
            for (int o = 0; o < 8 && !rc; o++)
                for (int j = 0; j < 8 && !rc; j++) {
                    /* octant o's child j covers quarter cell (x, y, z) = 2 o_bits + j_bits */
                    const int ix = 2 * (o & 1) + (j & 1), iy = 2 * ((o >> 1) & 1) + ((j >> 1) & 1),
                              iz = 2 * ((o >> 2) & 1) + ((j >> 2) & 1);
                    fc_arena *A = &sub[ix + 4 * iy + 16 * iz];
                    const size_t at = 9 + 8 * (size_t)o + (size_t)j;
                    for (size_t i = 0; i < A->nnodes; i++) {
                        const size_t to = i == 0 ? at : nbase + i - 1;
                        W->child[to] = A->child[i] < 0 ? -1
                                                       : (int32_t)(nbase + (size_t)A->child[i] - 1);
                        W->data[to] = A->data[i] < 0 ? -1 : (int32_t)(dbase + (size_t)A->data[i]);
                    }
                    /* (the values appended arena by arena, each freed once copied: the
                     * peak is the cache and one arena, not two caches) */
                    float *nv = realloc(W->vals, (dbase + A->ndata + 1) * (size_t)nc * 32 *
                                                     sizeof *nv);
                    if (!nv) {
                        rc = 1;
                        break;
                    }
                    W->vals = nv;
                    memcpy(W->vals + dbase * (size_t)nc * 32, A->vals,
                           A->ndata * (size_t)nc * 32 * sizeof *A->vals);
                    free(A->vals);
                    A->vals = NULL;
                    nbase += A->nnodes - 1;
                    dbase += A->ndata;
                    W->cached_leaves += A->cached_leaves;
                    W->tree_leaves += A->tree_leaves;
                }
        }
        if (rc && !over)
            mote_fail(err, MOTE_ENOMEM, "field solved: out of memory for the field's cache");
    }
    for (int k = 0; sub && k < NSUB; k++) {
        free(sub[k].child);
        free(sub[k].data);
        free(sub[k].vals);
    }
    free(sub);
    for (int s = 0; s < nc && s < MOTE_CH_BEM_MAX_CONDUCTORS; s++)
        mote_ch_ftree_free(trees[s]);
    free(tlo);
    free(thi);
    free(idx);
    if (rc) {
        ch_fcache_free(c);
        return NULL;
    }
    return c;
}

int ch_fcache_eval(const ch_fcache *c, const double *coef, const double x[3], double *phi,
                   double E[3])
{
    double f[3], h = c->size;
    for (int a = 0; a < 3; a++) {
        f[a] = (x[a] - c->lo[a]) / h;
        if (!(f[a] >= 0 && f[a] < 1))
            return 1; /* outside the cube (or not finite) */
    }
    const fc_arena *A = &c->a;
    size_t node = 0;
    while (A->child[node] >= 0) {
        int k = 0;
        for (int a = 0; a < 3; a++) {
            f[a] *= 2;
            if (f[a] >= 1) {
                f[a] -= 1;
                k |= 1 << a;
            }
        }
        node = (size_t)A->child[node] + (size_t)k;
    }
    if (A->data[node] < 0)
        return 1;
    const float *v = A->vals + (size_t)A->data[node] * (size_t)A->nc * 32;
    double out[4];
    if (A->nc == 1 && !coef) {
        trilinear(v, f, out);
    } else {
        double comb[32] = {0};
        for (int s = 0; s < A->nc; s++) {
            const double w = coef ? coef[s] : 1;
            for (int q = 0; q < 32; q++)
                comb[q] += w * (double)v[32 * s + q];
        }
        float cb[32];
        for (int q = 0; q < 32; q++)
            cb[q] = (float)comb[q];
        trilinear(cb, f, out);
    }
    *phi = out[0];
    E[0] = out[1];
    E[1] = out[2];
    E[2] = out[3];
    return 0;
}

void ch_fcache_stats(const ch_fcache *c, long *cached, long *tree, size_t *bytes)
{
    *cached = c->a.cached_leaves;
    *tree = c->a.tree_leaves;
    *bytes = sizeof *c + c->a.cap_nodes * 2 * sizeof(int32_t) +
             c->a.cap_data * (size_t)c->a.nc * 32 * sizeof(float);
}

void ch_fcache_free(ch_fcache *c)
{
    if (!c)
        return;
    free(c->a.child);
    free(c->a.data);
    free(c->a.vals);
    free(c);
}
