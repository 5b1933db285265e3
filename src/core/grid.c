/* grid.c: the shared cell grid (grid.h): sizing the cells for the region and the number of
 * particles, the counting sort, neighbour cells with their periodic shifts, and the sweep for
 * close pairs. */
#include "mote/grid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int mote_grid_setup(mote_grid *g, int dim, const double lo[3], const double len[3],
                    const int periodic[3], double min_w, uint32_t n)
{
    if (dim < 2 || dim > 3 || !(min_w > 0))
        return -1;
    for (int a = 0; a < dim; a++)
        if (!(len[a] > 0) || !isfinite(len[a]) || !isfinite(lo[a]))
            return -1;
    g->dim = dim;
    g->generic = 0;
    for (int a = 0; a < 3; a++) {
        g->periodic[a] = a < dim ? periodic[a] : 0;
        g->lo[a] = a < dim ? lo[a] : 0;
        g->len[a] = a < dim ? len[a] : 1;
        double q = a < dim ? floor(len[a] / min_w) : 1; /* compared as doubles: no overflow */
        g->nc[a] = q < 1 ? 1 : q > 1e6 ? 1000000 : (int)q;
    }
    /* no more cells than particles (and a few): halve the longest run of cells until so */
    for (;;) {
        double tot = (double)g->nc[0] * (double)g->nc[1] * (double)g->nc[2];
        if (tot <= (double)n + 27)
            break;
        int big = 0;
        for (int a = 1; a < 3; a++)
            if (g->nc[a] > g->nc[big])
                big = a;
        g->nc[big] = g->nc[big] / 2 > 1 ? g->nc[big] / 2 : 1;
    }
    for (int a = 0; a < 3; a++) {
        g->w[a] = g->len[a] / g->nc[a];
        g->inv_w[a] = 1.0 / g->w[a];
        g->generic |= g->periodic[a] && g->nc[a] < 3;
    }
    g->ncells = (size_t)g->nc[0] * (size_t)g->nc[1] * (size_t)g->nc[2];
    if (g->ncells + 1 > g->cap_cells) {
        uint32_t *s = realloc(g->start, (g->ncells + 1) * sizeof *s);
        if (!s)
            return -1;
        g->start = s;
        g->cap_cells = g->ncells + 1;
    }
    if (n > g->cap_n || !g->order) {
        size_t k = n ? n : 1;
        uint32_t *o = realloc(g->order, k * sizeof *o);
        if (o)
            g->order = o;
        uint32_t *c = realloc(g->cell, k * sizeof *c);
        if (c)
            g->cell = c;
        double *p = g->no_pos ? NULL : realloc(g->pos, 3 * k * sizeof *p);
        if (p)
            g->pos = p;
        if (!o || !c || (!p && !g->no_pos))
            return -1;
        g->cap_n = k;
    }
    g->n = 0;
    memset(g->start, 0, (g->ncells + 1) * sizeof *g->start);
    return 0;
}

void mote_grid_free(mote_grid *g)
{
    free(g->start);
    free(g->order);
    free(g->cell);
    free(g->pos);
    memset(g, 0, sizeof *g);
}

/* A coordinate on a periodic axis brought into [lo, lo + len) (a wall axis keeps it). */
static inline double wrapped(const mote_grid *g, int a, double x)
{
    if (!g->periodic[a])
        return x;
    double u = x - g->lo[a];
    if (u >= 0 && u < g->len[a])
        return x;
    u -= g->len[a] * floor(u / g->len[a]);
    if (!(u < g->len[a]) || u < 0) /* rounding to len itself (or below 0), or not finite */
        u = 0;
    return g->lo[a] + u;
}

/* The cell coordinate along axis a of a position: wrapped first on a periodic axis, then
 * clamped, so a position and its cell always agree (a wrapped coordinate that rounds up to the
 * region's end stays in the last cell, next to where it is). */
static inline int coord_of(const mote_grid *g, int a, double x)
{
    double q = floor((wrapped(g, a, x) - g->lo[a]) * g->inv_w[a]);
    int n = g->nc[a];
    if (!(q >= 0)) /* also NaN */
        return 0;
    return q >= n ? n - 1 : (int)q;
}

void mote_grid_coords(const mote_grid *g, const double x[3], int c[3])
{
    for (int a = 0; a < 3; a++)
        c[a] = a < g->dim ? coord_of(g, a, x[a]) : 0;
}

size_t mote_grid_cell_of(const mote_grid *g, const double x[3])
{
    size_t c = 0;
    for (int a = g->dim; a-- > 0;)
        c = c * (size_t)g->nc[a] + (size_t)coord_of(g, a, x[a]);
    return c;
}

void mote_grid_build(mote_grid *g, uint32_t n, const double *const coord[3], size_t stride)
{
    uint32_t *start = g->start;
    memset(start, 0, (g->ncells + 1) * sizeof *start);
    for (uint32_t i = 0; i < n; i++) {
        double x[3] = {0, 0, 0};
        for (int a = 0; a < g->dim; a++)
            x[a] = coord[a][(size_t)i * stride];
        size_t c = mote_grid_cell_of(g, x);
        g->cell[i] = (uint32_t)c;
        start[c + 1]++;
    }
    for (size_t c = 0; c < g->ncells; c++)
        start[c + 1] += start[c];
    /* scatter in index order: start[c] advances as cell c fills, then is moved back */
    for (uint32_t i = 0; i < n; i++) {
        uint32_t k = start[g->cell[i]]++;
        g->order[k] = i;
        if (g->no_pos)
            continue;
        double *p = g->pos + 3 * (size_t)k;
        for (int a = 0; a < 3; a++)
            p[a] = a < g->dim ? wrapped(g, a, coord[a][(size_t)i * stride]) : 0.0;
    }
    for (size_t c = g->ncells; c > 0; c--)
        start[c] = start[c - 1];
    start[0] = 0;
    g->n = n;
}

int mote_grid_neighbours(const mote_grid *g, size_t c, size_t out[27], double shift[27][3])
{
    int cc[3] = {(int)(c % (size_t)g->nc[0]), (int)(c / (size_t)g->nc[0] % (size_t)g->nc[1]),
                 (int)(c / ((size_t)g->nc[0] * (size_t)g->nc[1]))};
    int list[3][3], cnt[3];
    double sh[3][3];
    for (int a = 0; a < 3; a++) {
        int n = g->nc[a], x = cc[a];
        cnt[a] = 0;
        if (n == 1) {
            sh[a][0] = 0;
            list[a][cnt[a]++] = 0;
        } else if (g->periodic[a] && n == 2) { /* both cells, once, minimum image per pair */
            sh[a][cnt[a]] = 0;
            list[a][cnt[a]++] = x;
            sh[a][cnt[a]] = 0;
            list[a][cnt[a]++] = 1 - x;
        } else {
            for (int o = -1; o <= 1; o++) {
                int t = x + o;
                double s = 0;
                if (t < 0 || t >= n) {
                    if (!g->periodic[a])
                        continue;
                    s = t < 0 ? -g->len[a] : g->len[a];
                    t = t < 0 ? t + n : t - n;
                }
                sh[a][cnt[a]] = s;
                list[a][cnt[a]++] = t;
            }
        }
    }
    int k = 0;
    for (int z = 0; z < cnt[2]; z++)
        for (int y = 0; y < cnt[1]; y++)
            for (int x = 0; x < cnt[0]; x++) {
                out[k] = ((size_t)list[2][z] * (size_t)g->nc[1] + (size_t)list[1][y]) *
                             (size_t)g->nc[0] +
                         (size_t)list[0][x];
                shift[k][0] = sh[0][x];
                shift[k][1] = sh[1][y];
                shift[k][2] = sh[2][z];
                k++;
            }
    return k;
}

uint64_t mote_grid_pairs(const mote_grid *g, double s, mote_grid_pair_fn fn, void *ctx)
{
    const double s2 = s * s;
    uint64_t count = 0;
    size_t nbr[27];
    double shift[27][3];
    /* each pair of neighbouring cells once, from the lower-numbered one (the neighbour relation
     * is symmetric and the lists are distinct); within a cell, each pair once */
    for (size_t c = 0; c < g->ncells; c++) {
        uint32_t a0 = g->start[c], a1 = g->start[c + 1];
        if (a0 == a1)
            continue;
        int nn = mote_grid_neighbours(g, c, nbr, shift);
        for (int q = 0; q < nn; q++) {
            size_t c2 = nbr[q];
            if (c2 < c)
                continue;
            uint32_t b1 = g->start[c2 + 1];
            for (uint32_t a = a0; a < a1; a++)
                for (uint32_t b = c2 == c ? a + 1 : g->start[c2]; b < b1; b++) {
                    double d[3];
                    double r2 = mote_grid_sep(g, a, b, shift[q], d);
                    if (r2 >= s2)
                        continue;
                    count++;
                    if (fn) {
                        uint32_t i = g->order[a], j = g->order[b];
                        int stop;
                        if (i < j) {
                            stop = fn(ctx, i, j, d, r2);
                        } else {
                            double m[3] = {-d[0], -d[1], -d[2]};
                            stop = fn(ctx, j, i, m, r2);
                        }
                        if (stop)
                            return UINT64_MAX;
                    }
                }
        }
    }
    return count;
}
