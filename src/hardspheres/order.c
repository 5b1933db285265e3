/* order.c: `order K FILE` (hard-spheres spec 8.6): crystallinity per particle at every sample,
 * Steinhardt q6 with ten Wolde-Frenkel solid-like bonds and the in-layer bond order psi6,
 * accumulated in fine bins along x, then per wall layer (layers found after sampling from the
 * averaged density profile), and as a time series.
 *
 * Per particle i at each sample (positions projected to the sample instant, minimum image on
 * periodic axes, sigma_ij = R_i + R_j):
 * - q6: neighbours j with |r_ij| < 1.4 sigma_ij; q6m(i) = (1/n_i) sum_j Y6m(r_ij/|r_ij|) with the
 *   orthonormal spherical harmonics (Condon-Shortley phase, polar axis z; the results are
 *   rotation invariant); q6(i) = sqrt(4 pi/13 sum_m |q6m(i)|^2). A bond i-j (a q6 neighbour
 *   pair) is solid-like when sum_m qh6m(i) qh6m(j)* > 0.7 with qh = q6m normalised to unit
 *   length (the sum is real: the -m terms are the conjugates of the +m terms); i is crystal-like
 *   with at least 8 solid-like bonds. No neighbours: q6 = 0, not crystal-like. The unit vectors
 *   qh are stored in single precision (52 bytes per particle instead of 104), so the 0.7 test is
 *   exact to about 1e-7.
 * - psi6 (3D): neighbours with |x_j - x_i| < 0.4 sigma_ij and sqrt(dy^2 + dz^2) < 1.4 sigma_ij;
 *   psi6(i) = (1/n_i) sum_j exp(6 i theta_ij), theta the angle of (dy, dz); ordered when
 *   |psi6| > 0.7; no neighbours: psi6 = 0, not ordered. In 2D psi6 uses every neighbour within
 *   1.4 sigma_ij and the angle of (dx, dy), q6 is not computed (NaN in the file, no q6 results)
 *   and crystal-like means ordered.
 * Neighbours come from the shared cell grid (grid.h; cells >= 1.4 sigma_max on every axis; the psi6
 * neighbourhood fits in it too, since it needs |dx| < 0.4 sigma and |dy|, |dz| < 1.4 sigma).
 * Particles are sorted by cell at each sample for locality; results are sums per x bin, so the
 * order of summation is fixed by the state and the output is deterministic.
 *
 * Fine bins along x have width R/20 (hs_xbins with p = 20; R the mean radius). Per bin and per
 * block (spec 8.1: B = min(10, S) blocks of consecutive samples) the counts, sum q6,
 * crystal-like, sum |psi6| and ordered are kept.
 *
 * Layers (slit only), after sampling: the summed density profile is smoothed with a 5-bin
 * moving average (truncated at the ends); from each wall, alternately the next local maximum
 * and the next local minimum are taken, each minimum being a boundary; at most 6 layers per
 * wall; the search stops at a minimum above 0.9 of the smaller of its two neighbouring maxima,
 * or when the boundary would not lie in a bin whose centre is on the wall's side of L/2.
 * Decisions (the spec assumes a smooth profile; a sampled one at R/20 resolution is not):
 * - a fall after a maximum, or a rise after a minimum, makes it a local extremum only when it
 *   exceeds 3 block errors of the difference (with two blocks or more; with one sample any fall
 *   or rise counts, as in the spec). Otherwise a single noise wiggle in a flat minimum ends the
 *   search at the first layer.
 * - each extremum must be confirmed within 2.5 R of the previous one (the layering of hard
 *   spheres has a period of about 2R: 1 ... 2.3 R from crystal planes to a dilute fluid).
 *   Otherwise a slow density variation across a wide slit (long-wavelength fluctuations that
 *   relax slowly and so pass the block-error test) is reported as layers 5 ... 10 R wide.
 * - a flat minimum (an empty gap between crystal layers) is split in its middle.
 * Layer k of a wall runs from boundary k-1 (the wall for k = 1) to boundary k; what lies between
 * the innermost boundaries of the two walls is "bulk" (it is never empty). A periodic box has a
 * single row, "all".
 *
 * File (opened before the run, so that a bad path fails before any dynamics; committed
 * atomically only after a successful run; on an error nothing is written):
 * - the common header (spec 9.3, format "order"); `# samples`, `# blocks`, `# bin_width`,
 *   `# time_rows`, `# samples_per_row`, in a slit `# layers_left`, `# layers_right`; the
 *   results as `# key = value ± error`; `# thresholds:` lines with every criterion;
 *   `# columns:` lines for the three blocks (dimensionless columns carry no unit);
 * - block 1, one row per layer in x order: left 1 (at the wall) ... left n, bulk, right n ...
 *   right 1 (periodic: one row "all"). Columns: side (left, right, bulk, all), index (from the
 *   wall, 1 = contact layer; 0 for bulk and all), x_from, x_to [R], n_mean (particles per
 *   sample), rho_area = n_mean / A^2 [R^-2] (2D: n_mean / A [R^-1]), q6 and its block error,
 *   xtal_frac (crystal-like fraction) and its error, psi6 = <|psi6|> and its error, ordered_frac
 *   and its error. Means over an empty region are nan; errors are nan with fewer than 2 blocks
 *   or when a block saw no particle in the region;
 * - two blank lines, block 2, the fine profile, one row per bin: x_lo, x_hi, x_mid [R], count
 *   (summed over samples), rho [R^-3] (2D: R^-2), rho_smooth (the 5-bin average the layers were
 *   found from), q6, xtal_frac, psi6, ordered_frac (nan in empty bins);
 * - two blank lines, block 3, the time series: one row per sample (when there are more than
 *   1000 samples, row r averages the consecutive samples s with floor(s * 1000 / S) = r, so the
 *   memory stays bounded). Columns: sample_first, sample_last (1-based), time (mean over the
 *   row's samples), xtal_frac of the whole system, then for each row of block 1, in its order,
 *   xtal_frac[side index] and psi6[side index] (ratios of sums over the row's samples). Per
 *   sample and fine bin the count, crystal-like count (32-bit) and sum |psi6| (single precision)
 *   are kept, so that the layers found at the end can be evaluated at every sample.
 *
 * Results (mote_result, with block errors): xtal_fraction, q6_mean (3D only), psi6_mean
 * (whole system); in a slit also layers_left, layers_right, xtal_layerK and psi6_layerK for the
 * left wall's layers K = 1 ... layers_left, xtal_bulk and psi6_bulk. The function prints
 * nothing; it advances the system exactly as `step K` would. */
#include "mote/grid.h"
#include "mote/hardspheres.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "measure.h"

#define NEIGH_CUT 1.4       /* neighbour distance in units of sigma_ij (q6 and psi6) */
#define LAYER_DX_CUT 0.4    /* in-layer: |dx| < 0.4 sigma_ij */
#define BOND_DOT 0.7        /* solid-like bond threshold */
#define MIN_BONDS 8         /* solid-like bonds for a crystal-like particle */
#define PSI_ORDERED 0.7     /* |psi6| threshold */
#define BINS_PER_R 20
#define SMOOTH_BINS 5
#define MAX_LAYERS 6
#define LAYER_CONTRAST 0.9
#define LAYER_SIGNIF 3.0     /* block errors a fall or rise must exceed to make an extremum */
#define LAYER_WINDOW 2.5     /* largest distance between successive extrema, in R */
#define MAX_TIME_ROWS 1000
#define NQ 13               /* re q60, (re, im) q6m for m = 1 ... 6 */

enum { B_COUNT, B_Q6, B_XTAL, B_PSI, B_ORD, NB_Q };

typedef struct {
    /* geometry and particles */
    int dim;
    uint32_t n;
    int periodic[3];
    double len[3];
    double r0;            /* radius when monodisperse */
    /* the particles sorted into cells (positions in cell order in grid.pos; grid.order[k] is
     * the engine record at place k); everything per particle below is in cell order */
    mote_grid grid;
    double *raw;          /* [3n] positions by engine record, for the build */
    double *rad;          /* [n] sorted radii (polydisperse only) */
    float *qhat;          /* [NQ n] normalised q6m, sorted (3D only) */
    uint8_t *bonds;       /* [n] solid-like bonds (saturating; 3D only) */
    double rmax;          /* largest radius */
    /* per-particle output (hs_local_order only; NULL otherwise), by engine record */
    float *local;         /* [n] q6 (3D) or |psi6| (2D) */
    uint8_t *flag;        /* [n] crystal-like (3D) or ordered (2D) */
    double ylm_c[7];      /* Y6m normalisation with the Condon-Shortley sign and the 1/16 */
    /* bins */
    hs_xbins xb;
    size_t nb;
    uint64_t S;
    int B;
    double *cur;          /* [nb][NB_Q] this sample */
    double *blk;          /* [B][nb][NB_Q] */
    /* time rows */
    size_t nrows;
    uint32_t *row_count;  /* [nrows][nb] */
    uint32_t *row_xtal;
    float *row_psi;
    double *row_time;     /* [nrows] sum of sample times */
    uint64_t *row_first, *row_last, *row_ns;
} order_acc;

/* ---- spherical harmonics -------------------------------------------------------------------- */

/* Y6m(u) = c_m P6^(m)(z) (x + i y)^m for a unit vector u = (x, y, z), m >= 0, where P6^(m) is the
 * m-th derivative of the Legendre polynomial P6 (times 16 below): the associated Legendre
 * function P6^m(cos theta) = (-1)^m sin^m(theta) P6^(m)(cos theta) with sin^m(theta) e^(i m phi) =
 * (x + i y)^m. No trigonometric calls. Adds the 7 values into re[], im[]. */
static void ylm_c_init(double c[7])
{
    double f = 1; /* (6 - m)! / (6 + m)! built up from m = 0 */
    for (int m = 0; m <= 6; m++) {
        if (m > 0)
            f /= (double)(6 - m + 1) * (double)(6 + m);
        c[m] = (m % 2 ? -1.0 : 1.0) * sqrt(13.0 / (4 * MOTE_PI) * f) / 16.0;
    }
}

static inline void ylm6_add(const double c[7], double x, double y, double z, double re[7],
                            double im[7])
{
    double z2 = z * z, z4 = z2 * z2;
    double p[7];
    p[0] = 231 * z4 * z2 - 315 * z4 + 105 * z2 - 5;
    p[1] = z * (1386 * z4 - 1260 * z2 + 210);
    p[2] = 6930 * z4 - 3780 * z2 + 210;
    p[3] = z * (27720 * z2 - 7560);
    p[4] = 83160 * z2 - 7560;
    p[5] = 166320 * z;
    p[6] = 166320;
    re[0] += c[0] * p[0];
    double wr = 1, wi = 0; /* (x + i y)^m */
    for (int m = 1; m <= 6; m++) {
        double t = wr * x - wi * y;
        wi = wr * y + wi * x;
        wr = t;
        re[m] += c[m] * p[m] * wr;
        im[m] += c[m] * p[m] * wi;
    }
}

/* exp(6 i theta) of the in-plane vector (a, b), without trigonometric calls. */
static inline void psi6_add(double a, double b, double *pr, double *pi)
{
    double r2 = a * a + b * b;
    double sr = a * a - b * b, si = 2 * a * b;       /* (a + ib)^2 */
    double tr = sr * sr - si * si, ti = 2 * sr * si; /* ^4 */
    double ur = tr * sr - ti * si, ui = tr * si + ti * sr; /* ^6 */
    double r6 = r2 * r2 * r2;
    *pr += ur / r6;
    *pi += ui / r6;
}

/* ---- cells -------------------------------------------------------------------------------------- */

/* Cells at least the neighbour cut-off of the largest pair wide (grid.h sizes them). */
static int setup_cells(order_acc *a, const mote_ev *ev)
{
    double rmax = ev->radius0;
    if (ev->radius) {
        rmax = 0;
        for (uint32_t i = 0; i < ev->n; i++)
            rmax = fmax(rmax, ev->radius[i]);
    }
    a->rmax = rmax;
    const double origin[3] = {0, 0, 0};
    return mote_grid_setup(&a->grid, a->dim, origin, a->len, a->periodic, NEIGH_CUT * 2 * rmax,
                           a->n);
}

/* Sort the particles (positions at the sample instant) into the cells. */
static void sort_particles(order_acc *a, const mote_ev *ev)
{
    for (uint32_t i = 0; i < a->n; i++)
        mote_ev_position(ev, i, a->raw + 3 * (size_t)i);
    const double *coord[3] = {a->raw, a->raw + 1, a->raw + 2};
    mote_grid_build(&a->grid, a->n, coord, 3);
    if (a->rad)
        for (uint32_t k = 0; k < a->n; k++)
            a->rad[k] = ev->radius[a->grid.order[k]];
}

static inline double radius_of(const order_acc *a, uint32_t k)
{
    return a->rad ? a->rad[k] : a->r0;
}

/* ---- one sample ------------------------------------------------------------------------------- */

/* Pass 1, per particle: q6 (stored as a unit vector), |psi6|; both binned. */
static void pass_local(order_acc *a)
{
    const int dim = a->dim;
    const mote_grid *g = &a->grid;
    for (size_t c = 0; c < g->ncells; c++) {
        if (g->start[c] == g->start[c + 1])
            continue;
        size_t nbr[27];
        double shift[27][3];
        int nn = mote_grid_neighbours(g, c, nbr, shift);
        for (uint32_t i = g->start[c]; i < g->start[c + 1]; i++) {
            double re[7] = {0}, im[7] = {0}, pr = 0, pi = 0, ri = radius_of(a, i);
            /* neighbours of either kind are closer than sqrt(0.4^2 + 1.4^2) sigma < 1.46 sigma */
            double far = 1.46 * (ri + a->rmax), far2 = far * far;
            uint32_t nq = 0, np = 0;
            for (int q = 0; q < nn; q++)
                for (uint32_t j = g->start[nbr[q]]; j < g->start[nbr[q] + 1]; j++) {
                    if (j == i)
                        continue;
                    double d[3];
                    double r2 = mote_grid_sep(g, i, j, shift[q], d);
                    if (r2 >= far2 || !(r2 > 0))
                        continue;
                    double sig = ri + radius_of(a, j), cut2 = NEIGH_CUT * NEIGH_CUT * sig * sig;
                    if (dim == 3) {
                        if (r2 < cut2) {
                            double inv = 1 / sqrt(r2);
                            ylm6_add(a->ylm_c, d[0] * inv, d[1] * inv, d[2] * inv, re, im);
                            nq++;
                        }
                        double rho2 = d[1] * d[1] + d[2] * d[2];
                        if (fabs(d[0]) < LAYER_DX_CUT * sig && rho2 < cut2 && rho2 > 0) {
                            psi6_add(d[1], d[2], &pr, &pi);
                            np++;
                        }
                    } else if (r2 < cut2) {
                        psi6_add(d[0], d[1], &pr, &pi);
                        np++;
                    }
                }
            double psi = np ? sqrt(pr * pr + pi * pi) / np : 0;
            int ordered = psi > PSI_ORDERED;
            double *bin = a->cur + hs_xbins_of(&a->xb, a->grid.pos[3 * (size_t)i]) * NB_Q;
            bin[B_COUNT] += 1;
            bin[B_PSI] += psi;
            bin[B_ORD] += ordered;
            if (dim == 2) {
                bin[B_XTAL] += ordered;
                if (a->local) {
                    a->local[a->grid.order[i]] = (float)psi;
                    a->flag[a->grid.order[i]] = (uint8_t)ordered;
                }
                continue;
            }
            float *qh = a->qhat + (size_t)NQ * i;
            double norm2 = re[0] * re[0];
            for (int m = 1; m <= 6; m++)
                norm2 += 2 * (re[m] * re[m] + im[m] * im[m]);
            /* q6m = sum / nq, so q6 = sqrt(4 pi / 13 * norm2) / nq */
            double q6 = nq ? sqrt(4 * MOTE_PI / 13 * norm2) / nq : 0;
            bin[B_Q6] += q6;
            if (a->local)
                a->local[a->grid.order[i]] = (float)q6;
            double inv = norm2 > 0 ? 1 / sqrt(norm2) : 0;
            qh[0] = (float)(re[0] * inv);
            for (int m = 1; m <= 6; m++) {
                qh[2 * m - 1] = (float)(re[m] * inv);
                qh[2 * m] = (float)(im[m] * inv);
            }
        }
    }
}

/* Pass 2 (3D): solid-like bonds, each pair once (j > i in cell order), counted for both
 * particles; then crystal-like particles binned. */
static void pass_bonds(order_acc *a)
{
    memset(a->bonds, 0, a->n * sizeof *a->bonds);
    const mote_grid *g = &a->grid;
    for (size_t c = 0; c < g->ncells; c++) {
        if (g->start[c] == g->start[c + 1])
            continue;
        size_t nbr[27];
        double shift[27][3];
        int nn = mote_grid_neighbours(g, c, nbr, shift);
        for (uint32_t i = g->start[c]; i < g->start[c + 1]; i++) {
            const float *qi = a->qhat + (size_t)NQ * i;
            double ri = radius_of(a, i);
            double far = NEIGH_CUT * (ri + a->rmax), far2 = far * far;
            for (int q = 0; q < nn; q++) {
                uint32_t j0 = g->start[nbr[q]] > i + 1 ? g->start[nbr[q]] : i + 1;
                for (uint32_t j = j0; j < g->start[nbr[q] + 1]; j++) {
                    double d[3];
                    double r2 = mote_grid_sep(g, i, j, shift[q], d);
                    double sig = ri + radius_of(a, j);
                    if (r2 >= far2 || !(r2 > 0) || !(r2 < NEIGH_CUT * NEIGH_CUT * sig * sig))
                        continue;
                    const float *qj = a->qhat + (size_t)NQ * j;
                    double dot = (double)qi[0] * qj[0];
                    for (int k = 1; k < NQ; k++)
                        dot += 2.0 * (double)qi[k] * qj[k];
                    if (dot > BOND_DOT) {
                        /* saturate: only >= MIN_BONDS matters */
                        a->bonds[i] += a->bonds[i] < 255;
                        a->bonds[j] += a->bonds[j] < 255;
                    }
                }
            }
        }
    }
    for (uint32_t i = 0; i < a->n; i++) {
        if (a->bonds[i] >= MIN_BONDS)
            a->cur[hs_xbins_of(&a->xb, a->grid.pos[3 * (size_t)i]) * NB_Q + B_XTAL] += 1;
        if (a->flag)
            a->flag[a->grid.order[i]] = a->bonds[i] >= MIN_BONDS;
    }
}

static size_t row_of(uint64_t s, uint64_t S, size_t nrows)
{
    return (size_t)((long double)s * (long double)nrows / (long double)S);
}

static void order_sample(void *ctx, mote_hs *hs, uint64_t s, uint64_t nsamples)
{
    order_acc *a = ctx;
    memset(a->cur, 0, a->nb * NB_Q * sizeof *a->cur);
    sort_particles(a, &hs->ev);
    pass_local(a);
    if (a->dim == 3)
        pass_bonds(a);
    double *blk = a->blk + (size_t)hs_block_of(s, nsamples) * a->nb * NB_Q;
    for (size_t k = 0; k < a->nb * NB_Q; k++)
        blk[k] += a->cur[k];
    size_t r = row_of(s, nsamples, a->nrows);
    uint32_t *rc = a->row_count + r * a->nb, *rx = a->row_xtal + r * a->nb;
    float *rp = a->row_psi + r * a->nb;
    for (size_t b = 0; b < a->nb; b++) {
        rc[b] += (uint32_t)a->cur[b * NB_Q + B_COUNT];
        rx[b] += (uint32_t)a->cur[b * NB_Q + B_XTAL];
        rp[b] += (float)a->cur[b * NB_Q + B_PSI];
    }
    if (a->row_ns[r] == 0)
        a->row_first[r] = s + 1;
    a->row_last[r] = s + 1;
    a->row_ns[r]++;
    a->row_time[r] += mote_ev_time(&hs->ev);
}

/* ---- layers --------------------------------------------------------------------------------- */

/* The smoothed density profile seen from one wall: g(k) is bin k counted from that wall. With
 * two or more blocks, the smoothed profile of each block gives the error of a difference. */
typedef struct {
    const double *sm;  /* [nb] smoothed density of the whole run */
    const double *smb; /* [B][nb] smoothed density of each block */
    size_t nb;
    int B, mirror;
    double *tmp; /* [B] */
} profile_view;

static double pv_g(const profile_view *v, size_t k) { return v->sm[v->mirror ? v->nb - 1 - k : k]; }

/* g(hi) - g(lo) > 3 block errors of that difference; with fewer than 2 blocks (no errors),
 * simply g(hi) > g(lo). */
static int pv_significant(const profile_view *v, size_t hi, size_t lo)
{
    double d = pv_g(v, hi) - pv_g(v, lo);
    if (v->B < 2)
        return d > 0;
    size_t h = v->mirror ? v->nb - 1 - hi : hi, l = v->mirror ? v->nb - 1 - lo : lo;
    for (int b = 0; b < v->B; b++)
        v->tmp[b] = v->smb[(size_t)b * v->nb + h] - v->smb[(size_t)b * v->nb + l];
    return d > LAYER_SIGNIF * hs_block_error(v->tmp, v->B);
}

/* From bin k on, the next maximum: the running maximum, confirmed when the profile falls
 * significantly below it, at most `window` bins after `prev` (the previous extremum). Returns
 * 1 with its value in *M and its bin in *at, *k left at the bin where the fall was seen; 0 when
 * no maximum is confirmed in the window. */
static int next_max(const profile_view *v, size_t *k, size_t prev, size_t window, double *M,
                    size_t *at)
{
    size_t im = *k, end = prev + window < v->nb ? prev + window + 1 : v->nb;
    *M = pv_g(v, im);
    for (; *k < end; (*k)++) {
        double g = pv_g(v, *k);
        if (g > *M) {
            *M = g;
            im = *k;
        } else if (pv_significant(v, im, *k)) {
            *at = im;
            return 1;
        }
    }
    return 0;
}

/* Layer boundaries seen from one wall; limit is the number of bins whose centre lies on the
 * wall's side of L/2, window the largest distance between successive extrema (bins). bnd[k] is
 * the first bin (counted from the wall) after layer k + 1. Returns the number of layers.
 * From the wall, alternately the next local maximum and the next local minimum of the smoothed
 * profile. A fall after a maximum or a rise after a minimum only makes it an extremum when it
 * exceeds 3 block errors (from the per-block profiles; with a single block any fall or rise
 * counts), so a wiggle of the sampling noise does not end the search; and each extremum must be
 * confirmed within `window` of the previous one, so a slow density variation across the slit
 * is not taken for layers. Each minimum m is a boundary if m <= 0.9 min(M_before, M_after) and
 * it lies before L/2; otherwise, or after 6 layers, or when an extremum is missing, the search
 * stops. A flat minimum (an empty gap between crystal layers) is split in its middle. */
static int find_layers(const profile_view *v, size_t limit, size_t window,
                       size_t bnd[MAX_LAYERS])
{
    const size_t nb = v->nb;
    int nl = 0;
    size_t k = 0, at = 0;
    double M, M2;
    if (!next_max(v, &k, 0, window, &M, &at))
        return 0;
    while (nl < MAX_LAYERS) {
        size_t end = at + window < nb ? at + window + 1 : nb;
        double m = pv_g(v, k);
        size_t first = k, last = k;
        int found = 0;
        for (; k < end; k++) {
            double g = pv_g(v, k);
            if (g < m) {
                m = g;
                first = last = k;
            } else if (g == m && last + 1 == k) {
                last = k;
            } else if (pv_significant(v, k, first)) {
                found = 1;
                break;
            }
        }
        if (!found)
            break; /* no clear rise after this minimum */
        size_t b = (first + last + 1) / 2;
        if (b >= limit)
            break;
        if (!next_max(v, &k, last, window, &M2, &at))
            break;
        if (m > LAYER_CONTRAST * fmin(M, M2))
            break; /* no clear layering */
        bnd[nl++] = b;
        M = M2;
    }
    return nl;
}

typedef struct {
    const char *side;
    int index;
    size_t lo, hi; /* bins [lo, hi) */
} region;

/* 5-bin moving average (truncated at the ends). */
static void smooth(const double *in, double *out, size_t nb)
{
    for (size_t b = 0; b < nb; b++) {
        double s = 0;
        int m = 0;
        for (long q = (long)b - SMOOTH_BINS / 2; q <= (long)b + SMOOTH_BINS / 2; q++)
            if (q >= 0 && (size_t)q < nb) {
                s += in[q];
                m++;
            }
        out[b] = s / m;
    }
}

/* Sum quantity q over bins [lo, hi) of one block's (or the total's) table. */
static double region_sum(const double *tab, size_t lo, size_t hi, int q)
{
    double s = 0;
    for (size_t b = lo; b < hi; b++)
        s += tab[b * NB_Q + q];
    return s;
}

/* Mean of quantity q per particle over a region, and its block error. */
static double region_mean(const order_acc *a, const double *tot, const region *r, int q,
                          double *err, double *bm)
{
    double n = region_sum(tot, r->lo, r->hi, B_COUNT);
    double v = n > 0 ? region_sum(tot, r->lo, r->hi, q) / n : NAN;
    for (int b = 0; b < a->B; b++) {
        const double *t = a->blk + (size_t)b * a->nb * NB_Q;
        double nb = region_sum(t, r->lo, r->hi, B_COUNT);
        bm[b] = nb > 0 ? region_sum(t, r->lo, r->hi, q) / nb : NAN;
    }
    *err = hs_block_error(bm, a->B);
    return v;
}

/* ---- the command ------------------------------------------------------------------------------ */

static void acc_free(order_acc *a)
{
    mote_grid_free(&a->grid);
    free(a->raw);
    free(a->rad);
    free(a->qhat);
    free(a->bonds);
    free(a->cur);
    free(a->blk);
    free(a->row_count);
    free(a->row_xtal);
    free(a->row_psi);
    free(a->row_time);
    free(a->row_first);
    free(a->row_last);
    free(a->row_ns);
}

static void *alloc_n(size_t n, size_t size, int *fail)
{
    if (n == 0)
        n = 1;
    if (n > SIZE_MAX / size) {
        *fail = 1;
        return NULL;
    }
    void *p = calloc(n, size);
    if (!p)
        *fail = 1;
    return p;
}

static void fmt_opt(FILE *f, double v) { fprintf(f, " %.12g", v); }

/* The geometry, cells, bins and per-sample arrays of one order sample. Returns 1 when an
 * allocation failed (acc_free then frees what was allocated). */
static int acc_init(order_acc *a, const mote_hs *hs)
{
    const mote_ev *ev = &hs->ev;
    memset(a, 0, sizeof *a);
    a->dim = ev->dim;
    a->n = ev->n;
    a->r0 = ev->radius0;
    for (int d = 0; d < 3; d++) {
        a->periodic[d] = d < ev->dim ? ev->periodic[d] : 0;
        a->len[d] = d < ev->dim ? ev->len[d] : 1;
    }
    ylm_c_init(a->ylm_c);
    hs_xbins_init(&a->xb, hs, BINS_PER_R);
    a->nb = a->xb.nb;
    int fail = setup_cells(a, ev) != 0;
    a->raw = alloc_n((size_t)a->n * 3, sizeof *a->raw, &fail);
    if (ev->radius)
        a->rad = alloc_n(a->n, sizeof *a->rad, &fail);
    if (a->dim == 3) {
        a->qhat = alloc_n((size_t)a->n * NQ, sizeof *a->qhat, &fail);
        a->bonds = alloc_n(a->n, sizeof *a->bonds, &fail);
    }
    a->cur = alloc_n(a->nb * NB_Q, sizeof *a->cur, &fail);
    return fail;
}

int hs_local_order(const mote_hs *hs, float *local, uint8_t *flag, mote_err *err)
{
    order_acc a;
    int fail = acc_init(&a, hs);
    a.local = local;
    a.flag = flag;
    if (!fail) {
        sort_particles(&a, &hs->ev);
        pass_local(&a);
        if (a.dim == 3)
            pass_bonds(&a);
    }
    a.local = NULL;
    a.flag = NULL;
    acc_free(&a);
    return fail ? mote_fail(err, MOTE_ENOMEM, "out of memory for the local order of %u particles",
                            a.n)
                : MOTE_OK;
}

/* The end of `order`: the totals, profiles, regions and results of the samples. */
typedef struct {
    double *tot, *rho, *sm, *gr, *bm, *smb;
    region *reg;
    int nreg, nl, nr;
} order_work;

static void work_free(order_work *w)
{
    free(w->tot);
    free(w->rho);
    free(w->sm);
    free(w->gr);
    free(w->bm);
    free(w->smb);
    free(w->reg);
}

/* The sampler's accumulators for k collisions per particle, and the end's room: 1 when out of
 * memory. Everything the end needs is allocated before the run, so that a lack of memory fails
 * before any dynamics has run. */
static int order_alloc(order_acc *a, order_work *w, const mote_hs *hs, uint64_t k)
{
    int fail = acc_init(a, hs);
    a->S = k == 0 ? 1 : k;
    a->B = hs_nblocks(a->S);
    a->nrows = a->S < MAX_TIME_ROWS ? (size_t)a->S : MAX_TIME_ROWS;
    a->blk = alloc_n((size_t)a->B * a->nb * NB_Q, sizeof *a->blk, &fail);
    size_t cells_t = a->nrows > SIZE_MAX / (a->nb ? a->nb : 1) ? SIZE_MAX : a->nrows * a->nb;
    a->row_count = alloc_n(cells_t, sizeof *a->row_count, &fail);
    a->row_xtal = alloc_n(cells_t, sizeof *a->row_xtal, &fail);
    a->row_psi = alloc_n(cells_t, sizeof *a->row_psi, &fail);
    a->row_time = alloc_n(a->nrows, sizeof *a->row_time, &fail);
    a->row_first = alloc_n(a->nrows, sizeof *a->row_first, &fail);
    a->row_last = alloc_n(a->nrows, sizeof *a->row_last, &fail);
    a->row_ns = alloc_n(a->nrows, sizeof *a->row_ns, &fail);
    if (fail)
        return 1;
    const size_t nb = a->nb;
    w->tot = calloc(nb * NB_Q, sizeof *w->tot);
    w->rho = calloc(nb, sizeof *w->rho);
    w->sm = calloc(nb, sizeof *w->sm);
    w->gr = calloc(nb, sizeof *w->gr);
    w->bm = calloc((size_t)a->B, sizeof *w->bm);
    w->smb = calloc((size_t)a->B * nb, sizeof *w->smb);
    w->reg = calloc(2 * MAX_LAYERS + 1, sizeof *w->reg);
    return !w->tot || !w->rho || !w->sm || !w->gr || !w->bm || !w->smb || !w->reg;
}

/* The totals over the blocks, the density profile and its smoothing, per block too. */
static void order_profiles(const order_acc *a, order_work *w, const mote_hs *hs)
{
    const size_t nb = a->nb;
    const int B = a->B;
    const double area = mote_hs_cross_section(hs), S = (double)a->S;
    for (int b = 0; b < B; b++)
        for (size_t q = 0; q < nb * NB_Q; q++)
            w->tot[q] += a->blk[(size_t)b * nb * NB_Q + q];
    for (size_t b = 0; b < nb; b++) {
        double width = hs_xbins_hi(&a->xb, b) - hs_xbins_lo(&a->xb, b);
        w->rho[b] = w->tot[b * NB_Q + B_COUNT] / (S * area * width);
    }
    smooth(w->rho, w->sm, nb);
    for (int b = 0; b < B; b++) { /* per-block smoothed densities (gr is scratch) */
        const double *t = a->blk + (size_t)b * nb * NB_Q;
        double ns = (double)hs_block_size(b, a->S);
        for (size_t q = 0; q < nb; q++) {
            double width = hs_xbins_hi(&a->xb, q) - hs_xbins_lo(&a->xb, q);
            w->gr[q] = t[q * NB_Q + B_COUNT] / (ns * area * width);
        }
        smooth(w->gr, w->smb + (size_t)b * nb, nb);
    }
}

/* The regions in x order: the layers of each wall and the bulk (a slit), or all. */
static void order_regions(const order_acc *a, order_work *w, const mote_hs *hs)
{
    const size_t nb = a->nb;
    region *reg = w->reg;
    w->nreg = w->nl = w->nr = 0;
    if (hs->geometry != MOTE_HS_SLIT) {
        reg[w->nreg++] = (region){"all", 0, 0, nb};
        return;
    }
    const double L = a->xb.L;
    size_t lim_l = 0, lim_r = 0;
    for (size_t b = 0; b < nb; b++) {
        double mid = 0.5 * (hs_xbins_lo(&a->xb, b) + hs_xbins_hi(&a->xb, b));
        lim_l += mid < 0.5 * L;
        lim_r += mid > 0.5 * L;
    }
    size_t bl[MAX_LAYERS], br[MAX_LAYERS];
    profile_view pv = {w->sm, w->smb, nb, a->B, 0, w->bm};
    size_t window = (size_t)(LAYER_WINDOW * mote_hs_mean_radius(hs) / a->xb.dx);
    const int nl = w->nl = find_layers(&pv, lim_l, window, bl);
    pv.mirror = 1;
    const int nr = w->nr = find_layers(&pv, lim_r, window, br);
    size_t lo = 0;
    for (int q = 0; q < nl; q++) {
        reg[w->nreg++] = (region){"left", q + 1, lo, bl[q]};
        lo = bl[q];
    }
    size_t bulk_hi = nr ? nb - br[nr - 1] : nb;
    reg[w->nreg++] = (region){"bulk", 0, lo, bulk_hi};
    for (int q = nr - 1; q >= 0; q--)
        reg[w->nreg++] = (region){"right", q + 1, nb - br[q], q ? nb - br[q - 1] : nb};
}

/* The results: crystal fraction and order over all, per layer and in the bulk. */
static void order_results(order_acc *a, order_work *w, int slit, mote_result *res)
{
    region all = {"all", 0, 0, a->nb};
    double e, v;
    v = region_mean(a, w->tot, &all, B_XTAL, &e, w->bm);
    mote_result_add(res, "xtal_fraction", v, e);
    if (a->dim == 3) {
        v = region_mean(a, w->tot, &all, B_Q6, &e, w->bm);
        mote_result_add(res, "q6_mean", v, e);
    }
    v = region_mean(a, w->tot, &all, B_PSI, &e, w->bm);
    mote_result_add(res, "psi6_mean", v, e);
    if (!slit)
        return;
    mote_result_add(res, "layers_left", w->nl, NAN);
    mote_result_add(res, "layers_right", w->nr, NAN);
    for (int q = 0; q < w->nl; q++) {
        char key[32];
        snprintf(key, sizeof key, "xtal_layer%d", q + 1);
        v = region_mean(a, w->tot, &w->reg[q], B_XTAL, &e, w->bm);
        mote_result_add(res, key, v, e);
        snprintf(key, sizeof key, "psi6_layer%d", q + 1);
        v = region_mean(a, w->tot, &w->reg[q], B_PSI, &e, w->bm);
        mote_result_add(res, key, v, e);
    }
    v = region_mean(a, w->tot, &w->reg[w->nl], B_XTAL, &e, w->bm);
    mote_result_add(res, "xtal_bulk", v, e);
    v = region_mean(a, w->tot, &w->reg[w->nl], B_PSI, &e, w->bm);
    mote_result_add(res, "psi6_bulk", v, e);
}

/* The file's header lines after the common header: the numbers, results and thresholds, and
 * the columns of the three blocks. */
static void order_header(FILE *f, const order_acc *a, const order_work *w, int slit,
                         const mote_result *loc)
{
    const int d3 = a->dim == 3;
    const char *rho_unit = d3 ? "R^-3" : "R^-2", *area_unit = d3 ? "R^-2" : "R^-1";
    fprintf(f, "# samples = %llu\n# blocks = %d\n# bin_width = %.17g\n",
            (unsigned long long)a->S, a->B, a->xb.dx);
    fprintf(f, "# time_rows = %zu\n# samples_per_row = %.17g\n", a->nrows,
            (double)a->S / (double)a->nrows);
    if (slit)
        fprintf(f, "# layers_left = %d\n# layers_right = %d\n", w->nl, w->nr);
    mote_result_write(loc, f);
    if (d3) {
        fprintf(f, "# thresholds: q6 neighbours |r_ij| < %.1f sigma_ij (sigma_ij = R_i + R_j, "
                   "minimum image); q6m(i) = mean over neighbours of Y6m(r_ij/|r_ij|); "
                   "q6 = sqrt(4 pi/13 sum_m |q6m|^2)\n",
                NEIGH_CUT);
        fprintf(f, "# thresholds: solid-like bond: sum_m q6m(i) q6m(j)* / (|q6(i)| |q6(j)|) "
                   "> %.1f; crystal-like: >= %d solid-like bonds; no neighbours: q6 = 0, not "
                   "crystal-like\n",
                BOND_DOT, MIN_BONDS);
        fprintf(f, "# thresholds: in-layer psi6 neighbours |x_j - x_i| < %.1f sigma_ij and "
                   "sqrt(dy^2 + dz^2) < %.1f sigma_ij; psi6(i) = mean of exp(6 i theta_ij), "
                   "theta the angle of (dy, dz); ordered: |psi6| > %.1f; no neighbours: "
                   "psi6 = 0\n",
                LAYER_DX_CUT, NEIGH_CUT, PSI_ORDERED);
    } else {
        fprintf(f, "# thresholds: psi6 neighbours |r_ij| < %.1f sigma_ij (sigma_ij = R_i + "
                   "R_j, minimum image); psi6(i) = mean of exp(6 i theta_ij), theta the angle "
                   "of (dx, dy); ordered: |psi6| > %.1f; no neighbours: psi6 = 0; q6 not "
                   "computed (nan); crystal-like = ordered\n",
                NEIGH_CUT, PSI_ORDERED);
    }
    fprintf(f, "# thresholds: layers: density in bins of R/%d smoothed over %d bins; from "
               "each wall alternately the next local maximum and the next local minimum, each "
               "minimum a boundary; a fall or rise makes an extremum only when it exceeds %g "
               "block errors (with >= 2 blocks) within %g R of the previous extremum; at most "
               "%d layers per wall; stop when a minimum exceeds %.1f of the smaller "
               "neighbouring maximum, or at L/2\n",
            BINS_PER_R, SMOOTH_BINS, LAYER_SIGNIF, LAYER_WINDOW, MAX_LAYERS, LAYER_CONTRAST);
    fprintf(f, "# block 1: one row per layer in x order (left 1 = contact layer of the left "
               "wall ... bulk ... right 1 = contact layer of the right wall; periodic: one row "
               "\"all\"); errors from %d blocks\n",
            a->B);
    fprintf(f, "# columns: side index x_from[R] x_to[R] n_mean rho_area[%s] q6 q6_err "
               "xtal_frac xtal_frac_err psi6 psi6_err ordered_frac ordered_frac_err\n",
            area_unit);
    fprintf(f, "# block 2: fine profile, bins of width R/%d\n", BINS_PER_R);
    fprintf(f, "# columns: x_lo[R] x_hi[R] x_mid[R] count rho[%s] rho_smooth[%s] q6 "
               "xtal_frac psi6 ordered_frac\n",
            rho_unit, rho_unit);
    fprintf(f, "# block 3: time series, one row per sample (or per group of consecutive "
               "samples when there are more than %d)\n",
            MAX_TIME_ROWS);
    fprintf(f, "# columns: sample_first sample_last time[sqrt(mR^2/kT)] xtal_frac");
    for (int q = 0; q < w->nreg; q++) {
        char name[32];
        if (w->reg[q].index)
            snprintf(name, sizeof name, "%s%d", w->reg[q].side, w->reg[q].index);
        else
            snprintf(name, sizeof name, "%s", w->reg[q].side);
        fprintf(f, " xtal_frac[%s] psi6[%s]", name, name);
    }
    fputc('\n', f);
}

/* Block 1: a row per region. */
static void order_block_regions(FILE *f, order_acc *a, const order_work *w, double area)
{
    const double S = (double)a->S;
    double e, v;
    for (int q = 0; q < w->nreg; q++) {
        const region *r = &w->reg[q];
        double n = region_sum(w->tot, r->lo, r->hi, B_COUNT) / S;
        double x0 = hs_xbins_lo(&a->xb, r->lo);
        double x1 = r->hi > r->lo ? hs_xbins_hi(&a->xb, r->hi - 1) : x0;
        fprintf(f, "%s %d %.12g %.12g %.12g %.12g", r->side, r->index, x0, x1, n, n / area);
        static const int qs[4] = {B_Q6, B_XTAL, B_PSI, B_ORD};
        for (int t = 0; t < 4; t++) {
            if (qs[t] == B_Q6 && a->dim != 3) {
                fprintf(f, " nan nan");
                continue;
            }
            v = region_mean(a, w->tot, r, qs[t], &e, w->bm);
            fmt_opt(f, v);
            fmt_opt(f, e);
        }
        fputc('\n', f);
    }
}

/* Blocks 2 and 3: the fine profile and the time series. */
static void order_block_profile_times(FILE *f, const order_acc *a, const order_work *w)
{
    const size_t nb = a->nb;
    const int d3 = a->dim == 3;
    fprintf(f, "\n\n");
    for (size_t b = 0; b < nb; b++) {
        const double *t = w->tot + b * NB_Q;
        double lo = hs_xbins_lo(&a->xb, b), hi = hs_xbins_hi(&a->xb, b), n = t[B_COUNT];
        fprintf(f, "%.12g %.12g %.12g %.12g %.12g %.12g", lo, hi, 0.5 * (lo + hi), n, w->rho[b],
                w->sm[b]);
        fmt_opt(f, n > 0 && d3 ? t[B_Q6] / n : NAN);
        fmt_opt(f, n > 0 ? t[B_XTAL] / n : NAN);
        fmt_opt(f, n > 0 ? t[B_PSI] / n : NAN);
        fmt_opt(f, n > 0 ? t[B_ORD] / n : NAN);
        fputc('\n', f);
    }
    fprintf(f, "\n\n");
    for (size_t r = 0; r < a->nrows; r++) {
        const uint32_t *rc_ = a->row_count + r * nb, *rx = a->row_xtal + r * nb;
        const float *rp = a->row_psi + r * nb;
        double n = 0, x = 0;
        for (size_t b = 0; b < nb; b++) {
            n += rc_[b];
            x += rx[b];
        }
        fprintf(f, "%llu %llu %.12g", (unsigned long long)a->row_first[r],
                (unsigned long long)a->row_last[r], a->row_time[r] / (double)a->row_ns[r]);
        fmt_opt(f, n > 0 ? x / n : NAN);
        for (int q = 0; q < w->nreg; q++) {
            double rn = 0, rx_ = 0, rpsi = 0;
            for (size_t b = w->reg[q].lo; b < w->reg[q].hi; b++) {
                rn += rc_[b];
                rx_ += rx[b];
                rpsi += rp[b];
            }
            fmt_opt(f, rn > 0 ? rx_ / rn : NAN);
            fmt_opt(f, rn > 0 ? rpsi / rn : NAN);
        }
        fputc('\n', f);
    }
}

int mote_hs_order(mote_hs *hs, uint64_t k, const char *path, const char *origin,
                  mote_result *res, mote_err *err)
{
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "order: no system");
    order_acc a;
    order_work w = {0};
    if (order_alloc(&a, &w, hs, k)) {
        work_free(&w);
        acc_free(&a);
        return mote_fail(err, MOTE_ENOMEM,
                         "order: out of memory (N = %u, %zu bins, %zu time rows)", a.n, a.nb,
                         a.nrows);
    }
    /* the file is opened first, so that a bad path fails before any dynamics has run */
    const int slit = hs->geometry == MOTE_HS_SLIT;
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    hs_snap start, end;
    hs_snapshot(hs, &start);
    double tau;
    if (!rc) {
        rc = hs_run_samples(hs, k, a.S, order_sample, &a, "order", &tau, err);
        if (rc)
            mote_afile_abort(&af);
    }
    if (rc) {
        work_free(&w);
        acc_free(&a);
        return rc;
    }
    hs_snapshot(hs, &end);
    order_profiles(&a, &w, hs);
    order_regions(&a, &w, hs);
    mote_result loc; /* (kept here too, so the file has them when res is NULL) */
    memset(&loc, 0, sizeof loc);
    order_results(&a, &w, slit, &loc);
    hs_write_header(af.f, hs, "order", origin, &start, &end);
    order_header(af.f, &a, &w, slit, &loc);
    order_block_regions(af.f, &a, &w, mote_hs_cross_section(hs));
    order_block_profile_times(af.f, &a, &w);
    rc = mote_afile_commit(&af, err);
    if (!rc)
        for (int q = 0; q < loc.n; q++)
            mote_result_add(res, loc.kv[q].key, loc.kv[q].value, loc.kv[q].error);
    work_free(&w);
    acc_free(&a);
    return rc;
}
