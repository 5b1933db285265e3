/* grid.h: the cell grid every model's neighbour searches use (the event engine keeps its own,
 * tuned for its lists). Cells tile a region [lo, lo + len) in 2D or 3D, each axis bounded by
 * walls or periodic, and are at least a given width; a build sorts the particles into them by a
 * counting sort (stable in particle index) with their coordinates copied in cell order, so a
 * sweep reads memory in order. Then:
 *
 * - mote_grid_neighbours: the distinct cells around a cell (itself included), each with the
 *   shift that brings its particles to the images next to this cell;
 * - mote_grid_pairs: every pair closer than a distance, once, with its minimum-image separation.
 *
 * On a wall axis a position outside the region is counted in the edge cell (which only brings
 * cells closer, so no close pair is lost); on a periodic axis it is wrapped. A periodic axis of
 * fewer than three cells would list one neighbour twice: it is then given one or two cells that
 * are listed once with no shift, and separations take the minimum image pair by pair (generic).
 * Nothing here keeps global state. */
#ifndef MOTE_GRID_H
#define MOTE_GRID_H

#include <stddef.h>
#include <stdint.h>

typedef struct {
    int dim;
    int periodic[3];
    double lo[3], len[3];   /* the region; len is the period on periodic axes */
    int nc[3];              /* cells per axis (1 beyond dim) */
    double w[3], inv_w[3];  /* cell widths len / nc */
    int generic;            /* a periodic axis has two cells: minimum image pair by pair */
    size_t ncells;
    uint32_t *start;        /* [ncells + 1]: the particles of cell c are at [start[c], start[c+1]) */
    uint32_t *order;        /* [n] the particle at each place in cell order */
    double *pos;            /* [3 n] coordinates in cell order (0 beyond dim) */
    uint32_t *cell;         /* [n] the cell of each particle, by particle index */
    uint32_t n;
    size_t cap_cells, cap_n;
    int no_pos;             /* set before setup: keep no coordinate copies (pos stays NULL; for
                             * a caller that reads its own arrays, not mote_grid_pairs/_sep) */
} mote_grid;

/* Lay cells over the region for up to n particles: at least min_w wide on every axis (so a
 * pair closer than min_w lies in the same or neighbouring cells), and no more cells than about
 * one per particle (dilute systems get wider cells, so a sweep costs little per cell). Returns 0,
 * or -1 when out of memory or the region is not finite and positive. Reuses its memory. */
int mote_grid_setup(mote_grid *g, int dim, const double lo[3], const double len[3],
                    const int periodic[3], double min_w, uint32_t n);
void mote_grid_free(mote_grid *g);

/* The cell of a position (clamped on wall axes, wrapped on periodic ones), and its coordinates
 * on each axis (0 beyond dim); cell = (c[2] * nc[1] + c[1]) * nc[0] + c[0]. */
size_t mote_grid_cell_of(const mote_grid *g, const double x[3]);
void mote_grid_coords(const mote_grid *g, const double x[3], int c[3]);

/* Sort particles 0 .. n-1 (n at most the n given to setup) into the cells: coordinate a of
 * particle i is coord[a][i * stride] (coord[2] unused in 2D). The copies in pos are wrapped into
 * the region on periodic axes. */
void mote_grid_build(mote_grid *g, uint32_t n, const double *const coord[3], size_t stride);

/* The distinct cells around cell c, c itself included, and for each the shift to add to
 * r_j - r_i (i in c, j in that cell) to get the separation of the images next to each other
 * (zero except across a periodic face). Returns their number (at most 27). */
int mote_grid_neighbours(const mote_grid *g, size_t c, size_t out[27], double shift[27][3]);

/* d = r_j - r_i for the places a (in cell c) and b (in a neighbour cell with shift sh), as the
 * minimum image; returns |d|^2. */
static inline double mote_grid_sep(const mote_grid *g, uint32_t a, uint32_t b,
                                   const double sh[3], double d[3])
{
    const double *pa = g->pos + 3 * (size_t)a, *pb = g->pos + 3 * (size_t)b;
    d[0] = pb[0] - pa[0] + sh[0];
    d[1] = pb[1] - pa[1] + sh[1];
    d[2] = pb[2] - pa[2] + sh[2];
    if (g->generic)
        for (int ax = 0; ax < g->dim; ax++)
            if (g->periodic[ax]) {
                if (d[ax] > 0.5 * g->len[ax])
                    d[ax] -= g->len[ax];
                else if (d[ax] < -0.5 * g->len[ax])
                    d[ax] += g->len[ax];
            }
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

/* Called for each close pair: particles i < j, d = r_j - r_i (minimum image), r2 = |d|^2.
 * A non-zero return stops the sweep. */
typedef int (*mote_grid_pair_fn)(void *ctx, uint32_t i, uint32_t j, const double d[3], double r2);

/* Every pair closer than s (s at most the min_w of setup, and below half of every periodic
 * length), each once. Returns their number, or UINT64_MAX when fn stopped the sweep. */
uint64_t mote_grid_pairs(const mote_grid *g, double s, mote_grid_pair_fn fn, void *ctx);

#endif
