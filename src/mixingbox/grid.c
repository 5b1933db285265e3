/* grid.c: the mixing-box model's cell grid (see grid.h): sizing the cells for the box and the
 * number of disks, the counting sort of disks into cells, and the sweep for close pairs. */
#include "grid.h"

#include <math.h>
#include <stdlib.h>

int mb_grid_setup(mb_grid *g, double x0, double x1, double y0, double y1, double min_w,
                  uint32_t n)
{
    double W = x1 - x0, H = y1 - y0;
    double m = n ? (double)n : 1.0;
    /* About one disk per cell in a sparse gas (measured fastest); never narrower than
     * min_w; in a long, thin box never more cells along it than about 4n. */
    double w = fmax(min_w, sqrt(W) * sqrt(H / m)); /* W * H could overflow */
    w = fmax(w, fmax(W, H) / (4.0 * m + 64.0));
    if (!(w > 0) || !isfinite(w))
        return -1; /* a box the parameter check refuses (not finite) */
    /* at most 4n + 64 cells along a side (compared as doubles: no conversion out of range) */
    const double most = 4.0 * m + 64.0;
    double fx = fmin(ceil(W / w), most), fy = fmin(ceil(H / w), most);
    int nx = fx < 1 ? 1 : (int)fx;
    int ny = fy < 1 ? 1 : (int)fy;
    size_t cells = (size_t)nx * (size_t)ny;
    if (cells + 1 > g->cap_cells) {
        int32_t *s = realloc(g->start, (cells + 1) * sizeof *s);
        if (!s)
            return -1;
        g->start = s;
        g->cap_cells = cells + 1;
    }
    if (n > g->cap_n || !g->idx) {
        size_t k = n ? n : 1;
        uint32_t *idx = realloc(g->idx, k * sizeof *idx);
        if (idx)
            g->idx = idx;
        double *xs = realloc(g->xs, k * sizeof *xs);
        if (xs)
            g->xs = xs;
        double *ys = realloc(g->ys, k * sizeof *ys);
        if (ys)
            g->ys = ys;
        int32_t *c = realloc(g->cell, k * sizeof *c);
        if (c)
            g->cell = c;
        if (!idx || !xs || !ys || !c)
            return -1;
        g->cap_n = k;
    }
    g->x0 = x0;
    g->y0 = y0;
    g->w = w;
    g->inv_w = 1.0 / w;
    g->nx = nx;
    g->ny = ny;
    g->n = 0;
    for (size_t k = 0; k <= cells; k++)
        g->start[k] = 0;
    return 0;
}

void mb_grid_free(mb_grid *g)
{
    free(g->start);
    free(g->idx);
    free(g->xs);
    free(g->ys);
    free(g->cell);
    g->start = g->cell = NULL;
    g->idx = NULL;
    g->xs = g->ys = NULL;
    g->cap_cells = g->cap_n = 0;
}

void mb_grid_build(mb_grid *g, uint32_t n, const double *x, const double *y)
{
    size_t cells = (size_t)g->nx * (size_t)g->ny;
    int32_t *start = g->start;
    for (size_t k = 0; k < cells; k++)
        start[k] = 0;
    for (uint32_t i = 0; i < n; i++) {
        int c = mb_grid_cell_of(g, x[i], y[i]);
        g->cell[i] = c;
        start[c]++;
    }
    /* inclusive sums (start[c] = end of cell c), then a backward scatter moves each start[c] to
     * the beginning of its cell and keeps increasing index order within a cell */
    for (size_t k = 1; k < cells; k++)
        start[k] += start[k - 1];
    start[cells] = (int32_t)n;
    for (uint32_t i = n; i-- > 0;) {
        int32_t at = --start[g->cell[i]];
        g->idx[at] = i;
        g->xs[at] = x[i];
        g->ys[at] = y[i];
    }
    g->n = n;
}

static int push_pair(mb_pairs *out, uint32_t a, uint32_t b)
{
    if (out->n == out->cap) {
        size_t cap = out->cap ? 2 * out->cap : 256;
        uint64_t *p = realloc(out->p, cap * sizeof *p);
        if (!p)
            return -1;
        out->p = p;
        out->cap = cap;
    }
    out->p[out->n++] = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
    return 0;
}

uint64_t mb_grid_close_pairs(const mb_grid *g, double s, mb_pairs *out)
{
    const double s2 = s * s;
    const int32_t *start = g->start;
    const double *xs = g->xs, *ys = g->ys;
    const int nx = g->nx, ny = g->ny;
    uint64_t count = 0;
    /* Each pair of neighbouring cells once: a disk against the later disks of its own cell and
     * the cell to its right (one contiguous range), and against the three cells below-left,
     * below and below-right in the next row (another contiguous range). */
    for (int cy = 0; cy < ny; cy++) {
        for (int cx = 0; cx < nx; cx++) {
            int c = cy * nx + cx;
            int32_t a0 = start[c], a1 = start[c + 1];
            if (a0 == a1)
                continue;
            int32_t same_end = start[cx + 1 < nx ? c + 2 : c + 1];
            int32_t up0 = 0, up1 = 0;
            if (cy + 1 < ny) {
                int d = c + nx;
                up0 = start[cx > 0 ? d - 1 : d];
                up1 = start[cx + 1 < nx ? d + 2 : d + 1];
            }
            for (int32_t a = a0; a < a1; a++) {
                const double xa = xs[a], ya = ys[a];
                for (int32_t b = a + 1; b < same_end; b++) {
                    double dx = xs[b] - xa, dy = ys[b] - ya;
                    if (dx * dx + dy * dy < s2) {
                        count++;
                        if (out && push_pair(out, g->idx[a], g->idx[b]))
                            return UINT64_MAX;
                    }
                }
                for (int32_t b = up0; b < up1; b++) {
                    double dx = xs[b] - xa, dy = ys[b] - ya;
                    if (dx * dx + dy * dy < s2) {
                        count++;
                        if (out && push_pair(out, g->idx[a], g->idx[b]))
                            return UINT64_MAX;
                    }
                }
            }
        }
    }
    return count;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

void mb_pairs_sort(mb_pairs *pairs)
{
    if (pairs->n > 1)
        qsort(pairs->p, pairs->n, sizeof *pairs->p, cmp_u64);
}

void mb_pairs_free(mb_pairs *pairs)
{
    free(pairs->p);
    pairs->p = NULL;
    pairs->n = pairs->cap = 0;
}
