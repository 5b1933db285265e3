/* grid.h: the mixing-box model's private cell grid. Square cells of at least a given width over
 * the box; a build sorts the disks by cell (counting sort) into contiguous copies of their
 * coordinates, and a sweep over each cell and its four forward neighbours finds every pair
 * closer than a distance in O(N). Positions outside the box are clamped into the edge cells,
 * which only brings cells closer, so no close pair is missed. */
#ifndef MOTE_MB_GRID_H
#define MOTE_MB_GRID_H

#include <stddef.h>
#include <stdint.h>

typedef struct mb_grid {
    double x0, y0, w;  /* origin (lower left) and cell width */
    double inv_w;      /* 1 / w */
    int nx, ny;
    int32_t *start;    /* nx * ny + 1: the disks of cell c are [start[c], start[c+1]) */
    uint32_t *idx;     /* disk indices in cell order */
    double *xs, *ys;   /* their coordinates, in cell order */
    int32_t *cell;     /* the cell of each disk (by disk index) */
    size_t cap_cells, cap_n;
    uint32_t n;
} mb_grid;

/* Pairs (i < j) packed as (uint64_t)i << 32 | j. */
typedef struct {
    uint64_t *p;
    size_t n, cap;
} mb_pairs;

/* Lay cells over [x0, x1] x [y0, y1] for n disks: at least min_w wide, and about one disk per
 * cell when the disks are sparse (a sweep then costs little per cell). Returns 0 or -1 when out
 * of memory. */
int mb_grid_setup(mb_grid *g, double x0, double x1, double y0, double y1, double min_w,
                  uint32_t n);
void mb_grid_free(mb_grid *g);

/* The cell coordinate of v along an axis starting at lo, clamped to 0 .. n-1. */
static inline int mb_grid_coord(double v, double lo, double inv_w, int n)
{
    double c = (v - lo) * inv_w;
    if (!(c >= 0)) /* also NaN */
        return 0;
    if (c >= (double)n)
        return n - 1;
    return (int)c;
}

static inline int mb_grid_cell_of(const mb_grid *g, double x, double y)
{
    return mb_grid_coord(y, g->y0, g->inv_w, g->ny) * g->nx +
           mb_grid_coord(x, g->x0, g->inv_w, g->nx);
}

/* Sort disks 0 .. n-1 into the cells (n at most the n given to setup). */
void mb_grid_build(mb_grid *g, uint32_t n, const double *x, const double *y);

/* Every pair closer than s (strictly) among the disks of the last build: their number, and
 * when out is not NULL the pairs appended to it (unsorted). Returns UINT64_MAX when out of
 * memory. */
uint64_t mb_grid_close_pairs(const mb_grid *g, double s, mb_pairs *out);

void mb_pairs_sort(mb_pairs *pairs);
void mb_pairs_free(mb_pairs *pairs);

#endif
