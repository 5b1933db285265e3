/* test_order.c: `order K FILE` (hard-spheres spec 8.6) through the library API.
 *
 * - perfect FCC (spec 10 item 10): q6 = 0.57452 to 1e-4 for every particle and every particle
 *   crystal-like, in three boxes (2, 3 and 4 cells per edge, eta 0.60 and 0.74); the value is
 *   also computed here from the 12 neighbour directions with the addition theorem;
 * - hexagonal layers (item 10): a 2D triangular lattice (bulk_disks) and a hand-built 3D slit of
 *   nine FCC (111) planes parallel to the walls give |psi6| = 1 for every particle; in that slit
 *   the layer finder puts one plane in each layer (4 per wall and the middle plane in bulk) and
 *   the inner planes have the FCC q6. (`new` builds FCC with (100) planes parallel to the walls,
 *   a square lattice in y-z whose psi6 is 0, not 1, so it cannot serve as the hexagonal case.)
 * - an independent brute-force computation (O(N^2) neighbours, q6 and the bond products from the
 *   Legendre addition theorem sum_m Y6m(a) Y6m(b)* = 13/(4 pi) P6(a.b), psi6 with atan2/cos/sin)
 *   reproduces the file's per-bin sums for 3D and 2D fluids, periodic and slit, and a
 *   polydisperse system (sigma_ij = R_i + R_j);
 * - melting and stability (item 11): bulk N = 2048 after 200 collisions per particle is
 *   crystal-like below 5% at eta 0.40 and above 90% at 0.60;
 * - layers in a fluid slit (new 6 0.40): at least 2 layers per wall, the first ending near
 *   2R and the second about 2R wide; a periodic box has one "all" row;
 * - the file: header, thresholds, columns, three blocks, consistency of the blocks with each
 *   other and with the results; the time series groups samples beyond 1000;
 * - order K advances the system exactly as step K (and K = 0 not at all); errors write nothing
 *   and leave an existing file and the state untouched.
 * Every case also runs under the sanitizers (about 7 s there, 3 s optimised). */
#include "mote/hardspheres.h"

#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test.h"

static char tmpdir[256];

#define FCC_Q6 0.57452 /* published value (spec 10 item 10) */

static void tmp_path(char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "%s/%s", tmpdir, name);
}

static int same_state(const mote_ev *a, const mote_ev *b)
{
    return a->n == b->n && memcmp(a->p, b->p, a->n * sizeof *a->p) == 0 &&
           memcmp(a->heap, b->heap, a->n * sizeof *a->heap) == 0 && a->clock == b->clock &&
           a->time_total == b->time_total && a->collisions == b->collisions &&
           a->wall_collisions == b->wall_collisions &&
           memcmp(a->len, b->len, sizeof a->len) == 0;
}

static double legendre6(double x)
{
    double x2 = x * x;
    return (((231 * x2 - 315) * x2 + 105) * x2 - 5) / 16;
}

/* ---- reading an order file --------------------------------------------------------------------- */

#define MAXCOL 64
typedef struct {
    int nrow, cap;
    int *ncol;
    char *(*cell)[MAXCOL];
} block;

typedef struct {
    int nthresholds, ncolumns_lines, nblocks, bad_blank;
    char columns[3][2048];
    double samples, bin_width, L, A, time_rows;
    double layers_left, layers_right;
    int has_layers;
    block blk[3];
    char header[16384];
} ofile;

static void ofile_free(ofile *o)
{
    for (int b = 0; b < 3; b++) {
        for (int r = 0; r < o->blk[b].nrow; r++)
            for (int c = 0; c < o->blk[b].ncol[r]; c++)
                free(o->blk[b].cell[r][c]);
        free(o->blk[b].ncol);
        free(o->blk[b].cell);
    }
    memset(o, 0, sizeof *o);
}

/* Parse the file; returns 0 on success. Blocks are separated by exactly two blank lines. */
static int ofile_read(const char *path, ofile *o)
{
    memset(o, 0, sizeof *o);
    o->layers_left = o->layers_right = -1;
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    char line[65536];
    int blanks = 0, b = 0, seen_data = 0;
    size_t hl = 0;
    while (fgets(line, sizeof line, f)) {
        size_t n = strlen(line);
        if (n && line[n - 1] == '\n')
            line[--n] = 0;
        if (line[0] == '#') {
            if (hl + n + 2 < sizeof o->header) {
                memcpy(o->header + hl, line, n);
                hl += n;
                o->header[hl++] = '\n';
                o->header[hl] = 0;
            }
            if (strncmp(line, "# thresholds:", 13) == 0)
                o->nthresholds++;
            if (strncmp(line, "# columns:", 10) == 0 && o->ncolumns_lines < 3) {
                char *dst = o->columns[o->ncolumns_lines++];
                size_t m = strlen(line + 10);
                if (m >= sizeof o->columns[0])
                    m = sizeof o->columns[0] - 1;
                memcpy(dst, line + 10, m);
                dst[m] = 0;
            }
            sscanf(line, "# samples = %lf", &o->samples);
            sscanf(line, "# bin_width = %lf", &o->bin_width);
            sscanf(line, "# L = %lf", &o->L);
            sscanf(line, "# A = %lf", &o->A);
            sscanf(line, "# time_rows = %lf", &o->time_rows);
            if (sscanf(line, "# layers_left = %lf", &o->layers_left) == 1)
                o->has_layers = 1;
            sscanf(line, "# layers_right = %lf", &o->layers_right);
            continue;
        }
        if (n == 0) {
            blanks++;
            continue;
        }
        if (seen_data && blanks) {
            if (blanks != 2)
                o->bad_blank = 1;
            b++;
        }
        blanks = 0;
        seen_data = 1;
        if (b >= 3) {
            o->bad_blank = 1;
            continue;
        }
        block *bk = &o->blk[b];
        if (bk->nrow == bk->cap) {
            bk->cap = bk->cap ? 2 * bk->cap : 64;
            bk->ncol = realloc(bk->ncol, (size_t)bk->cap * sizeof *bk->ncol);
            bk->cell = realloc(bk->cell, (size_t)bk->cap * sizeof *bk->cell);
        }
        int c = 0;
        for (char *tok = strtok(line, " "); tok && c < MAXCOL; tok = strtok(NULL, " "))
            bk->cell[bk->nrow][c++] = strdup(tok);
        bk->ncol[bk->nrow++] = c;
    }
    fclose(f);
    o->nblocks = seen_data ? b + 1 : 0;
    return 0;
}

static double num(const ofile *o, int b, int r, int c)
{
    if (r >= o->blk[b].nrow || c >= o->blk[b].ncol[r])
        return NAN;
    return strtod(o->blk[b].cell[r][c], NULL);
}

static const char *str(const ofile *o, int b, int r, int c)
{
    if (r >= o->blk[b].nrow || c >= o->blk[b].ncol[r])
        return "";
    return o->blk[b].cell[r][c];
}

static int count_words(const char *s)
{
    int n = 0, in = 0;
    for (; *s; s++) {
        if (*s != ' ' && !in)
            n++;
        in = *s != ' ';
    }
    return n;
}

/* Block 1 columns */
enum { C_SIDE, C_INDEX, C_XFROM, C_XTO, C_NMEAN, C_RHOA, C_Q6, C_Q6E, C_XTAL, C_XTALE, C_PSI,
       C_PSIE, C_ORD, C_ORDE, NC1 };
/* Block 2 columns */
enum { F_LO, F_HI, F_MID, F_COUNT, F_RHO, F_RHOS, F_Q6, F_XTAL, F_PSI, F_ORD, NC2 };

/* Structural checks every order file must pass; returns 1 if it could be read. */
static int check_file(const char *path, const mote_hs *hs, uint64_t S, const mote_result *res,
                      ofile *o, const char *label)
{
    if (ofile_read(path, o)) {
        CHECK(0, "%s: cannot read %s", label, path);
        return 0;
    }
    const mote_ev *ev = &hs->ev;
    int slit = hs->geometry == MOTE_HS_SLIT, d3 = ev->dim == 3;
    CHECK_HAS(o->header, "# mote order 1\n");
    /* 3D: q6, bonds, psi6, layers; 2D: psi6, layers */
    CHECK(o->nthresholds == (d3 ? 4 : 2), "%s: %d thresholds lines", label, o->nthresholds);
    CHECK_HAS(o->header, "1.4 sigma_ij");
    CHECK_HAS(o->header, "> 0.7");
    CHECK_HAS(o->header, d3 ? ">= 8 solid-like bonds" : "crystal-like = ordered");
    if (d3)
        CHECK_HAS(o->header, "< 0.4 sigma_ij");
    CHECK_HAS(o->header, "|psi6| > 0.7");
    CHECK(o->ncolumns_lines == 3, "%s: %d columns lines", label, o->ncolumns_lines);
    CHECK(o->nblocks == 3 && !o->bad_blank, "%s: %d blocks (bad separators: %d)", label,
          o->nblocks, o->bad_blank);
    CHECK(o->samples == (double)S, "%s: samples = %g, expected %llu", label, o->samples,
          (unsigned long long)S);
    for (int k = 0; k < res->n; k++) {
        char want[64];
        snprintf(want, sizeof want, "# %s = ", res->kv[k].key);
        CHECK_HAS(o->header, want);
    }
    if (o->nblocks != 3)
        return 1;
    /* columns lines match the rows */
    int w[3];
    for (int b = 0; b < 3; b++)
        w[b] = count_words(o->columns[b]);
    int widths_ok = 1;
    for (int b = 0; b < 3; b++)
        for (int r = 0; r < o->blk[b].nrow; r++)
            widths_ok &= o->blk[b].ncol[r] == w[b];
    CHECK(widths_ok, "%s: a row's width differs from its columns line (%d, %d, %d)", label, w[0],
          w[1], w[2]);
    CHECK(w[0] == NC1 && w[1] == NC2, "%s: block widths %d %d", label, w[0], w[1]);

    /* block 1: regions tile [0, L] in x order, hold N particles per sample */
    const block *b1 = &o->blk[0];
    double L = ev->len[0], nsum = 0, x = 0;
    int tile = 1, order_ok = 1, nl = 0, nr = 0;
    for (int r = 0; r < b1->nrow; r++) {
        tile &= fabs(num(o, 0, r, C_XFROM) - x) < 1e-9;
        x = num(o, 0, r, C_XTO);
        nsum += num(o, 0, r, C_NMEAN);
        const char *side = str(o, 0, r, C_SIDE);
        if (strcmp(side, "left") == 0) {
            order_ok &= num(o, 0, r, C_INDEX) == ++nl;
        } else if (strcmp(side, "right") == 0) {
            nr++;
        } else {
            order_ok &= strcmp(side, slit ? "bulk" : "all") == 0 && num(o, 0, r, C_INDEX) == 0;
        }
    }
    tile &= fabs(x - L) < 1e-9;
    CHECK(tile, "%s: block 1 does not tile [0, L]", label);
    CHECK(order_ok, "%s: block 1 rows out of order", label);
    CHECK(fabs(nsum - ev->n) < 1e-7 * ev->n, "%s: block 1 holds %.10g particles, N = %u", label,
          nsum, ev->n);
    if (slit) {
        CHECK(o->has_layers && o->layers_left == nl && o->layers_right == nr,
              "%s: header layers %g/%g, rows %d/%d", label, o->layers_left, o->layers_right, nl,
              nr);
        CHECK(b1->nrow == nl + nr + 1, "%s: %d rows for %d + %d layers", label, b1->nrow, nl, nr);
        /* right rows from the inside out: index nr ... 1 */
        int ok = 1;
        for (int q = 0; q < nr; q++)
            ok &= num(o, 0, nl + 1 + q, C_INDEX) == nr - q;
        CHECK(ok, "%s: right rows not numbered from the inside to the wall", label);
    } else {
        CHECK(b1->nrow == 1, "%s: periodic box gives %d rows, expected 1 (\"all\")", label,
              b1->nrow);
        CHECK(!o->has_layers, "%s: periodic box reports layers", label);
    }

    /* block 2: bins of the header's width, counts sum to N S */
    const block *b2 = &o->blk[1];
    double dx = o->bin_width, csum = 0;
    int bins_ok = b2->nrow >= 1;
    for (int r = 0; r < b2->nrow; r++) {
        bins_ok &= fabs(num(o, 1, r, F_LO) - r * dx) < 1e-9 &&
                   (r + 1 == b2->nrow ? fabs(num(o, 1, r, F_HI) - L) < 1e-9
                                      : fabs(num(o, 1, r, F_HI) - (r + 1) * dx) < 1e-9);
        csum += num(o, 1, r, F_COUNT);
    }
    double R = mote_hs_mean_radius(hs);
    CHECK(slit ? fabs(dx - R / 20) < 1e-15 : fabs(dx - R / 20) < R / 20 * 0.5 / b2->nrow + 1e-15,
          "%s: bin width %.17g, expected R/20 = %.17g", label, dx, R / 20);
    CHECK(bins_ok, "%s: block 2 bins are not [r dx, (r+1) dx) ending at L", label);
    CHECK(csum == (double)ev->n * (double)S, "%s: block 2 counts sum to %.17g, expected N S",
          label, csum);

    /* block 3: rows and samples; whole-system fraction averages to xtal_fraction (N is the same
     * at every sample, so the mean of the per-sample fractions is the overall fraction) */
    const block *b3 = &o->blk[2];
    uint64_t rows = S < 1000 ? S : 1000;
    CHECK(b3->nrow == (int)rows && o->time_rows == (double)rows,
          "%s: block 3 has %d rows (header %g), expected %llu", label, b3->nrow, o->time_rows,
          (unsigned long long)rows);
    CHECK(w[2] == 4 + 2 * b1->nrow, "%s: block 3 has %d columns for %d regions", label, w[2],
          b1->nrow);
    double next = 1, tprev = -1, fsum = 0, wsum = 0;
    int seq = 1;
    for (int r = 0; r < b3->nrow; r++) {
        double f0 = num(o, 2, r, 0), f1 = num(o, 2, r, 1), t = num(o, 2, r, 2);
        seq &= f0 == next && f1 >= f0 && t >= tprev;
        next = f1 + 1;
        tprev = t;
        fsum += num(o, 2, r, 3) * (f1 - f0 + 1);
        wsum += f1 - f0 + 1;
    }
    CHECK(seq && next == (double)S + 1, "%s: block 3 samples are not 1 ... S in order", label);
    const double *xf = mote_result_get(res, "xtal_fraction", NULL);
    CHECK(xf && fabs(fsum / wsum - *xf) < 1e-9, "%s: time series mean %.12g, xtal_fraction %.12g",
          label, fsum / wsum, xf ? *xf : NAN);
    /* with a single sample, block 3's region values are block 1's (psi6 sums are kept in single
     * precision per sample and bin: 1e-6) */
    if (S == 1) {
        int ok = 1;
        for (int r = 0; r < b1->nrow; r++) {
            double a1 = num(o, 0, r, C_XTAL), a3 = num(o, 2, 0, 4 + 2 * r);
            double p1 = num(o, 0, r, C_PSI), p3 = num(o, 2, 0, 5 + 2 * r);
            ok &= (isnan(a1) && isnan(a3)) || fabs(a1 - a3) < 1e-9;
            ok &= (isnan(p1) && isnan(p3)) || fabs(p1 - p3) < 1e-6;
        }
        CHECK(ok, "%s: block 3 differs from block 1 with one sample", label);
    }
    /* the results are the file's: whole system and left layers */
    const double *q6 = mote_result_get(res, "q6_mean", NULL);
    CHECK(d3 ? q6 != NULL : q6 == NULL, "%s: q6_mean %s", label, q6 ? "present" : "absent");
    if (slit && nl >= 1) {
        const double *x1 = mote_result_get(res, "xtal_layer1", NULL);
        const double *p1 = mote_result_get(res, "psi6_layer1", NULL);
        CHECK(x1 && p1 && fabs(*x1 - num(o, 0, 0, C_XTAL)) < 1e-9 &&
                  fabs(*p1 - num(o, 0, 0, C_PSI)) < 1e-9,
              "%s: layer 1 results differ from block 1", label);
        const double *xb = mote_result_get(res, "xtal_bulk", NULL);
        CHECK(xb && (isnan(*xb) ? isnan(num(o, 0, nl, C_XTAL))
                                : fabs(*xb - num(o, 0, nl, C_XTAL)) < 1e-9),
              "%s: xtal_bulk differs from block 1", label);
    }
    return 1;
}

/* ---- brute force ------------------------------------------------------------------------------- */

typedef struct {
    double q6_min, q6_max, psi_min, psi_max;
    int marginal; /* bonds or |psi6| within rounding of a threshold */
} brute_stats;

/* Recompute every particle's q6, crystal-like flag, |psi6| and ordered flag from scratch and
 * compare the per-bin sums with block 2 of the file (one sample, K = 0). */
static void brute_compare(const mote_hs *hs, const ofile *o, brute_stats *st, const char *label)
{
    const mote_ev *ev = &hs->ev;
    uint32_t n = ev->n;
    int d3 = ev->dim == 3;
    double(*r)[3] = malloc(n * sizeof *r);
    for (uint32_t i = 0; i < n; i++)
        mote_ev_position(ev, i, r[i]);
    /* neighbour unit vectors (q6) per particle */
    int *nq = calloc(n, sizeof *nq), cap = 64;
    uint32_t *nbr = malloc((size_t)n * cap * sizeof *nbr);
    double(*u)[3] = malloc((size_t)n * cap * sizeof *u);
    double *q6 = calloc(n, sizeof *q6), *psi = calloc(n, sizeof *psi);
    int overflow = 0;
    st->q6_min = st->psi_min = INFINITY;
    st->q6_max = st->psi_max = -INFINITY;
    st->marginal = 0;
    for (uint32_t i = 0; i < n; i++) {
        double pr = 0, pi = 0;
        int np = 0;
        for (uint32_t j = 0; j < n; j++) {
            if (j == i)
                continue;
            double d[3] = {0, 0, 0}, s2 = 0;
            for (int a = 0; a < ev->dim; a++) {
                d[a] = r[j][a] - r[i][a];
                if (ev->periodic[a])
                    d[a] -= ev->len[a] * nearbyint(d[a] / ev->len[a]);
                s2 += d[a] * d[a];
            }
            double sig = mote_ev_radius(ev, i) + mote_ev_radius(ev, j), dist = sqrt(s2);
            if (d3 && dist < 1.4 * sig) {
                if (nq[i] == cap) {
                    overflow = 1;
                    continue;
                }
                size_t k = (size_t)i * cap + (size_t)nq[i]++;
                nbr[k] = j;
                for (int a = 0; a < 3; a++)
                    u[k][a] = d[a] / dist;
            }
            double th = NAN;
            if (d3) {
                if (fabs(d[0]) < 0.4 * sig && hypot(d[1], d[2]) < 1.4 * sig)
                    th = atan2(d[2], d[1]);
            } else if (dist < 1.4 * sig) {
                th = atan2(d[1], d[0]);
            }
            if (!isnan(th)) {
                pr += cos(6 * th);
                pi += sin(6 * th);
                np++;
            }
        }
        psi[i] = np ? hypot(pr, pi) / np : 0;
        if (fabs(psi[i] - 0.7) < 1e-9)
            st->marginal++;
        st->psi_min = fmin(st->psi_min, psi[i]);
        st->psi_max = fmax(st->psi_max, psi[i]);
        if (d3 && nq[i]) {
            double s = 0;
            for (int a = 0; a < nq[i]; a++)
                for (int b = 0; b < nq[i]; b++) {
                    const double *ua = u[(size_t)i * cap + a], *ub = u[(size_t)i * cap + b];
                    s += legendre6(ua[0] * ub[0] + ua[1] * ub[1] + ua[2] * ub[2]);
                }
            q6[i] = sqrt(s) / nq[i];
        }
        if (d3) {
            st->q6_min = fmin(st->q6_min, q6[i]);
            st->q6_max = fmax(st->q6_max, q6[i]);
        }
    }
    CHECK(!overflow, "%s: more than %d neighbours", label, cap);
    /* crystal-like: solid-like bonds from the addition theorem */
    int *xtal = calloc(n, sizeof *xtal);
    for (uint32_t i = 0; d3 && i < n; i++) {
        int bonds = 0;
        for (int k = 0; k < nq[i]; k++) {
            uint32_t j = nbr[(size_t)i * cap + k];
            double s = 0;
            for (int a = 0; a < nq[i]; a++)
                for (int b = 0; b < nq[j]; b++) {
                    const double *ua = u[(size_t)i * cap + a], *ub = u[(size_t)j * cap + b];
                    s += legendre6(ua[0] * ub[0] + ua[1] * ub[1] + ua[2] * ub[2]);
                }
            double dot = q6[i] > 0 && q6[j] > 0 ? s / (nq[i] * nq[j] * q6[i] * q6[j]) : 0;
            if (fabs(dot - 0.7) < 1e-5)
                st->marginal++; /* the library keeps the unit vectors in single precision */
            bonds += dot > 0.7;
        }
        xtal[i] = bonds >= 8;
    }
    if (!d3)
        for (uint32_t i = 0; i < n; i++)
            xtal[i] = psi[i] > 0.7;
    /* bin as the library does: floor(x / dx), clamped */
    int nb = o->blk[1].nrow;
    double *bc = calloc((size_t)nb, sizeof *bc), *bq = calloc((size_t)nb, sizeof *bq);
    double *bx = calloc((size_t)nb, sizeof *bx), *bp = calloc((size_t)nb, sizeof *bp);
    double *bo = calloc((size_t)nb, sizeof *bo);
    for (uint32_t i = 0; i < n; i++) {
        double fb = floor(r[i][0] / o->bin_width);
        int b = fb < 0 ? 0 : fb >= nb ? nb - 1 : (int)fb;
        bc[b] += 1;
        bq[b] += q6[i];
        bx[b] += xtal[i];
        bp[b] += psi[i];
        bo[b] += psi[i] > 0.7;
    }
    int cnt_bad = 0, q_bad = 0, x_bad = 0, p_bad = 0, o_bad = 0;
    for (int b = 0; b < nb; b++) {
        double c = num(o, 1, b, F_COUNT);
        if (c != bc[b]) {
            cnt_bad++;
            continue;
        }
        if (c == 0)
            continue;
        if (d3 && fabs(num(o, 1, b, F_Q6) * c - bq[b]) > 1e-9 * c)
            q_bad++;
        x_bad += fabs(num(o, 1, b, F_XTAL) * c - bx[b]) > 1e-6;
        if (fabs(num(o, 1, b, F_PSI) * c - bp[b]) > 1e-9 * c)
            p_bad++;
        o_bad += fabs(num(o, 1, b, F_ORD) * c - bo[b]) > 1e-6;
    }
    CHECK(cnt_bad == 0, "%s: %d bins with other counts than the brute force", label, cnt_bad);
    CHECK(q_bad == 0, "%s: %d bins with another sum of q6", label, q_bad);
    CHECK(x_bad <= 2 * st->marginal, "%s: %d bins with other crystal-like counts (%d marginal)",
          label, x_bad, st->marginal);
    CHECK(p_bad == 0, "%s: %d bins with another sum of |psi6|", label, p_bad);
    CHECK(o_bad <= st->marginal, "%s: %d bins with other ordered counts", label, o_bad);
    double nx = 0;
    for (uint32_t i = 0; i < n; i++)
        nx += xtal[i];
    printf("  %s: N = %u, brute force: q6 in [%.5f, %.5f], |psi6| in [%.4f, %.4f], "
           "crystal-like %.4f, %d marginal, %d bins agree\n",
           label, n, st->q6_min, st->q6_max, st->psi_min, st->psi_max, nx / n, st->marginal, nb);
    free(r);
    free(nq);
    free(nbr);
    free(u);
    free(q6);
    free(psi);
    free(xtal);
    free(bc);
    free(bq);
    free(bx);
    free(bp);
    free(bo);
}

/* Run order into path, check its structure; the caller frees o. */
static int run_order(mote_hs *hs, uint64_t k, const char *path, mote_result *res, ofile *o,
                     const char *label)
{
    mote_err err = {0};
    memset(res, 0, sizeof *res);
    int rc = mote_hs_order(hs, k, path, "order K f", res, &err);
    CHECK(rc == MOTE_OK, "%s: %s", label, err.msg);
    if (rc) {
        memset(o, 0, sizeof *o);
        return 0;
    }
    return check_file(path, hs, k ? k : 1, res, o, label);
}

static double result(const mote_result *res, const char *key)
{
    const double *v = mote_result_get(res, key, NULL);
    return v ? *v : NAN;
}

/* ---- perfect lattices ----------------------------------------------------------------------- */

static void test_fcc(void)
{
    printf("perfect FCC (spec 10 item 10)\n");
    /* the FCC value from the 12 neighbour directions (+-1, +-1, 0)/sqrt 2 and permutations */
    double v[12][3];
    int m = 0;
    for (int a = 0; a < 3; a++)
        for (int s1 = -1; s1 <= 1; s1 += 2)
            for (int s2 = -1; s2 <= 1; s2 += 2) {
                double w[3] = {0, 0, 0};
                w[(a + 1) % 3] = s1 / sqrt(2.0);
                w[(a + 2) % 3] = s2 / sqrt(2.0);
                memcpy(v[m++], w, sizeof w);
            }
    double s = 0;
    for (int a = 0; a < 12; a++)
        for (int b = 0; b < 12; b++)
            s += legendre6(v[a][0] * v[b][0] + v[a][1] * v[b][1] + v[a][2] * v[b][2]);
    double q6_fcc = sqrt(s) / 12;
    printf("  FCC q6 from the addition theorem: %.8f\n", q6_fcc);
    CHECK_NEAR(q6_fcc, FCC_Q6, 5e-6); /* the published value has 5 decimals */

    const int cells[3] = {2, 3, 4};
    const double etas[3] = {0.60, 0.74, 0.60};
    char path[512];
    tmp_path(path, sizeof path, "fcc.dat");
    for (int t = 0; t < 3; t++) {
        mote_hs hs;
        mote_err err = {0};
        mote_hs_init(&hs, NULL);
        int64_t n = 4 * cells[t] * cells[t] * cells[t];
        CHECK(mote_hs_bulk(&hs, n, etas[t], &err) == MOTE_OK, "%s", err.msg);
        char label[64];
        snprintf(label, sizeof label, "FCC N=%lld eta=%.2f", (long long)n, etas[t]);
        mote_result res;
        ofile o;
        if (run_order(&hs, 0, path, &res, &o, label)) {
            double q6 = result(&res, "q6_mean");
            CHECK_NEAR(q6, FCC_Q6, 1e-4);
            CHECK_NEAR(q6, q6_fcc, 1e-12);
            CHECK(result(&res, "xtal_fraction") == 1, "%s: crystal-like fraction %.17g", label,
                  result(&res, "xtal_fraction"));
            /* every particle: per bin, and in the brute force */
            int bins_ok = 1;
            for (int r = 0; r < o.blk[1].nrow; r++)
                if (num(&o, 1, r, F_COUNT) > 0)
                    bins_ok &= fabs(num(&o, 1, r, F_Q6) - FCC_Q6) < 1e-4 &&
                               num(&o, 1, r, F_XTAL) == 1;
            CHECK(bins_ok, "%s: a bin's q6 or crystal-like fraction is off", label);
            brute_stats st;
            brute_compare(&hs, &o, &st, label);
            CHECK(fabs(st.q6_min - FCC_Q6) < 1e-4 && fabs(st.q6_max - FCC_Q6) < 1e-4,
                  "%s: q6 ranges over [%.6f, %.6f]", label, st.q6_min, st.q6_max);
            printf("  %s: q6_mean = %.8f, crystal-like %.4f\n", label, q6,
                   result(&res, "xtal_fraction"));
        }
        ofile_free(&o);
        mote_hs_free(&hs);
    }
}

static void test_disks_lattice(void)
{
    printf("triangular lattice of disks: |psi6| = 1\n");
    char path[512];
    tmp_path(path, sizeof path, "disks.dat");
    const double etas[2] = {0.85, 0.5};
    for (int t = 0; t < 2; t++) {
        mote_hs hs;
        mote_err err = {0};
        mote_hs_init(&hs, NULL);
        CHECK(mote_hs_bulk_disks(&hs, 400, etas[t], &err) == MOTE_OK, "%s", err.msg);
        char label[64];
        snprintf(label, sizeof label, "bulk_disks 400 %.2f", etas[t]);
        mote_result res;
        ofile o;
        if (run_order(&hs, 0, path, &res, &o, label)) {
            double p = result(&res, "psi6_mean");
            /* every |psi6| <= 1 (up to rounding), so a mean within 1e-13 of 1 puts every one
             * within N 1e-13 = 4e-11 of 1 */
            CHECK_NEAR(p, 1.0, 1e-13);
            CHECK(result(&res, "xtal_fraction") == 1, "%s: crystal-like %.17g", label,
                  result(&res, "xtal_fraction"));
            CHECK(isnan(num(&o, 0, 0, C_Q6)), "%s: q6 column is not nan in 2D", label);
            brute_stats st;
            brute_compare(&hs, &o, &st, label);
            CHECK(st.psi_min > 1 - 1e-12, "%s: brute-force |psi6| down to %.17g", label,
                  st.psi_min);
            printf("  %s: psi6_mean = %.15f\n", label, p);
        }
        ofile_free(&o);
        mote_hs_free(&hs);
    }
}

/* A slit of `planes` triangular layers (FCC (111) planes, ABC stacking, in-plane spacing a)
 * parallel to the walls, built by hand: ny x nz sites per plane (nz even), periodic in y, z. */
static int build_hex_slit(mote_hs *hs, int planes, int ny, int nz, double a, double gap,
                          mote_err *err)
{
    uint32_t n = (uint32_t)(planes * ny * nz);
    mote_hs_init(hs, NULL);
    int rc = mote_ev_init(&hs->ev, n, 3, 0, err);
    if (rc)
        return rc;
    mote_ev *ev = &hs->ev;
    double h = a * sqrt(3.0) / 2, d = a * sqrt(2.0 / 3.0);
    ev->periodic[0] = 0;
    ev->periodic[1] = ev->periodic[2] = 1;
    ev->len[0] = 2 * gap + (planes - 1) * d;
    ev->len[1] = ny * a;
    ev->len[2] = nz * h;
    hs->geometry = MOTE_HS_SLIT;
    mote_rng rng;
    mote_rng_seed(&rng, test_seed(5));
    uint32_t k = 0;
    for (int p = 0; p < planes; p++) {
        /* ABC: each plane shifted by (a/2, h/3) from the one below */
        double sy = (p % 3) * a / 2, sz = (p % 3) * h / 3;
        for (int j = 0; j < nz; j++)
            for (int i = 0; i < ny; i++, k++) {
                ev->p[k].r[0] = gap + p * d;
                ev->p[k].r[1] = fmod(a * (i + 0.5 * (j % 2)) + sy + 0.1, ev->len[1]);
                ev->p[k].r[2] = fmod(h * j + sz + 0.1, ev->len[2]);
                for (int q = 0; q < 3; q++)
                    ev->p[k].v[q] = mote_rng_uniform(&rng) - 0.5;
            }
    }
    rc = mote_ev_rebuild(ev, err);
    if (rc)
        return rc;
    mote_ev_set_reference(ev);
    hs->has_system = 1;
    return MOTE_OK;
}

static void test_hex_slit(void)
{
    printf("hexagonal (111) layers in a slit\n");
    mote_hs hs;
    mote_err err = {0};
    const int planes = 9, ny = 6, nz = 6;
    const double a = 2.1; /* neighbours at 2.1 in-plane and across planes; next shell 2.97 */
    int rc = build_hex_slit(&hs, planes, ny, nz, a, 1.2, &err);
    CHECK(rc == MOTE_OK, "build: %s", err.msg);
    if (rc)
        return;
    CHECK(mote_hs_check(&hs, &err) == MOTE_OK, "hand-built slit fails the checker: %s", err.msg);
    char path[512];
    tmp_path(path, sizeof path, "hex.dat");
    mote_result res;
    ofile o;
    const char *label = "hex slit";
    if (run_order(&hs, 0, path, &res, &o, label)) {
        CHECK_NEAR(result(&res, "psi6_mean"), 1.0, 1e-13);
        CHECK(result(&res, "layers_left") == 4 && result(&res, "layers_right") == 4,
              "%s: %g + %g layers, expected 4 + 4 (one plane each, the middle one is bulk)",
              label, result(&res, "layers_left"), result(&res, "layers_right"));
        double per = ny * nz, dpl = a * sqrt(2.0 / 3.0);
        int one_plane = o.blk[0].nrow == 9;
        for (int r = 0; r < o.blk[0].nrow; r++) {
            double xp = 1.2 + r * dpl; /* plane r */
            one_plane &= num(&o, 0, r, C_NMEAN) == per && num(&o, 0, r, C_XFROM) < xp &&
                         num(&o, 0, r, C_XTO) > xp;
        }
        CHECK(one_plane, "%s: the rows do not hold one plane each", label);
        /* planes 2 ... 8 have the 12 FCC neighbours */
        int q6_ok = 1;
        for (int r = 1; r < o.blk[0].nrow - 1; r++)
            q6_ok &= fabs(num(&o, 0, r, C_Q6) - FCC_Q6) < 1e-4 && num(&o, 0, r, C_XTAL) == 1 &&
                     num(&o, 0, r, C_PSI) > 1 - 1e-12 && num(&o, 0, r, C_ORD) == 1;
        CHECK(q6_ok, "%s: an inner plane is not FCC-like", label);
        printf("  %s: N = %u, layers %g + %g, q6 inner %.6f, wall plane q6 %.6f crystal-like "
               "%.3f, psi6_mean %.15f\n",
               label, hs.ev.n, result(&res, "layers_left"), result(&res, "layers_right"),
               num(&o, 0, 4, C_Q6), num(&o, 0, 0, C_Q6), num(&o, 0, 0, C_XTAL),
               result(&res, "psi6_mean"));
        brute_stats st;
        brute_compare(&hs, &o, &st, label);
    }
    ofile_free(&o);
    mote_hs_free(&hs);
}

/* ---- fluids against the brute force ----------------------------------------------------------- */

/* Make the radii polydisperse through a state file: R_i = 1 - 0.3 u_i (shrinking keeps the state
 * free of overlaps). */
static int make_polydisperse(mote_hs *hs, mote_err *err)
{
    char p1[512], p2[512];
    tmp_path(p1, sizeof p1, "mono.state");
    tmp_path(p2, sizeof p2, "poly.state");
    int rc = mote_hs_save(hs, p1, err);
    if (rc)
        return rc;
    FILE *in = fopen(p1, "r"), *out = fopen(p2, "w");
    if (!in || !out) {
        if (in)
            fclose(in);
        if (out)
            fclose(out);
        return mote_fail(err, MOTE_EIO, "cannot rewrite the state file");
    }
    char line[1024];
    int in_particles = 0;
    mote_rng rng;
    mote_rng_seed(&rng, test_seed(77));
    while (fgets(line, sizeof line, in)) {
        if (in_particles && strncmp(line, "end", 3) != 0) {
            double f[8];
            if (sscanf(line, "%lf %lf %lf %lf %lf %lf %lf %lf", &f[0], &f[1], &f[2], &f[3], &f[4],
                       &f[5], &f[6], &f[7]) == 8) {
                f[6] = 1 - 0.3 * mote_rng_uniform(&rng);
                fprintf(out, "%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", f[0], f[1],
                        f[2], f[3], f[4], f[5], f[6], f[7]);
                continue;
            }
        }
        if (strncmp(line, "particles", 9) == 0)
            in_particles = 1;
        fputs(line, out);
    }
    fclose(in);
    fclose(out);
    return mote_hs_load(hs, p2, err);
}

static void test_brute_force(void)
{
    printf("per-bin sums against a brute-force computation\n");
    char path[512];
    tmp_path(path, sizeof path, "brute.dat");
    for (int t = 0; t < 6; t++) {
        mote_hs hs;
        mote_err err = {0};
        mote_hs_init(&hs, NULL);
        mote_hs_seed(&hs, test_seed(100 + (uint64_t)t));
        const char *label = "";
        int rc = MOTE_OK;
        switch (t) {
        case 0:
            label = "bulk 500 eta 0.45 fluid";
            rc = mote_hs_bulk(&hs, 500, 0.45, &err);
            break;
        case 1:
            label = "bulk 500 eta 0.55 (hot FCC crystal)";
            rc = mote_hs_bulk(&hs, 500, 0.55, &err);
            break;
        case 2:
            label = "slit new 3 eta 0.45";
            rc = mote_hs_new(&hs, 3, 0.45, &err);
            break;
        case 3:
            label = "polydisperse bulk 256 eta 0.40";
            rc = mote_hs_bulk(&hs, 256, 0.40, &err);
            break;
        case 4:
            label = "bulk_disks 400 eta 0.60";
            rc = mote_hs_bulk_disks(&hs, 400, 0.60, &err);
            break;
        case 5:
            label = "new_disks 10 12 eta 0.5";
            rc = mote_hs_new_disks(&hs, 10, 12, 0.5, &err);
            break;
        }
        CHECK(rc == MOTE_OK, "%s: %s", label, err.msg);
        if (!rc)
            rc = mote_hs_step(&hs, 30, &err);
        if (!rc && t == 3) {
            rc = make_polydisperse(&hs, &err);
            CHECK(rc == MOTE_OK && hs.ev.radius != NULL, "polydisperse: %s", err.msg);
        }
        CHECK(rc == MOTE_OK, "%s: %s", label, err.msg);
        mote_result res;
        ofile o;
        if (!rc && run_order(&hs, 0, path, &res, &o, label)) {
            brute_stats st;
            brute_compare(&hs, &o, &st, label);
            ofile_free(&o);
        }
        mote_hs_free(&hs);
    }
}

/* ---- melting and stability -------------------------------------------------------------------- */

static void test_melting(void)
{
    printf("melting and stability (spec 10 item 11)\n");
    char path[512];
    tmp_path(path, sizeof path, "melt.dat");
    const double etas[2] = {0.40, 0.60};
    for (int t = 0; t < 2; t++) {
        mote_hs hs;
        mote_err err = {0};
        mote_hs_init(&hs, NULL);
        mote_hs_seed(&hs, test_seed(11));
        CHECK(mote_hs_bulk(&hs, 2048, etas[t], &err) == MOTE_OK, "%s", err.msg);
        double w0 = mote_wall_seconds();
        /* 200 collisions per particle, as the spec says, also under the sanitizer */
        CHECK(mote_hs_step(&hs, 200, &err) == MOTE_OK, "%s", err.msg);
        char label[64];
        snprintf(label, sizeof label, "bulk 2048 eta %.2f after step 200", etas[t]);
        mote_result res;
        ofile o;
        if (run_order(&hs, 0, path, &res, &o, label)) {
            double f = result(&res, "xtal_fraction");
            /* The targets are far from the measured values (about 0.001 and 0.99; a fluid
             * at 0.40 has almost no particle with 8 solid-like bonds, the crystal at 0.60
             * almost all), so no statistical margin is needed beyond the spec's bounds. */
            if (t == 0)
                CHECK(f < 0.05, "%s: crystal-like fraction %.4f, expected < 5%%", label, f);
            else
                CHECK(f > 0.90, "%s: crystal-like fraction %.4f, expected > 90%%", label, f);
            printf("  %s: crystal-like fraction %.4f, q6_mean %.4f (%.2f s)\n", label, f,
                   result(&res, "q6_mean"), mote_wall_seconds() - w0);
        }
        ofile_free(&o);
        /* averaged over 10 more collisions per particle: the same verdict, with errors */
        snprintf(label, sizeof label, "bulk 2048 eta %.2f, order 10", etas[t]);
        if (run_order(&hs, 10, path, &res, &o, label)) {
            double e = 0, f = *mote_result_get(&res, "xtal_fraction", &e);
            CHECK(t == 0 ? f < 0.05 : f > 0.90, "%s: crystal-like fraction %.4f", label, f);
            CHECK(e >= 0 && !isnan(e), "%s: no error with 10 samples", label);
            printf("  %s: crystal-like fraction %.4f +- %.4f\n", label, f, e);
        }
        ofile_free(&o);
        mote_hs_free(&hs);
    }
}

/* ---- layers in a fluid slit ------------------------------------------------------------------- */

static void test_layers(void)
{
    printf("layers in a fluid slit\n");
    char path[512];
    tmp_path(path, sizeof path, "layers.dat");
    mote_hs hs;
    mote_err err = {0};
    mote_hs_init(&hs, NULL);
    mote_hs_seed(&hs, test_seed(3));
    CHECK(mote_hs_new(&hs, 6, 0.40, &err) == MOTE_OK, "%s", err.msg);
    CHECK(mote_hs_step(&hs, 100, &err) == MOTE_OK, "%s", err.msg);
    double w0 = mote_wall_seconds();
    mote_result res;
    ofile o;
    const char *label = "new 6 0.40, order 400";
    /* K = 400: a second boundary counts only once the density rises again by 3 block errors
     * after it, and at eta 0.40 the third maximum is weak. With K = 200 one wall of 42 (21
     * seeds) showed a single layer (MOTE_TEST_SEED=15); with K = 400 none of 102 (51 seeds). */
    if (run_order(&hs, 400, path, &res, &o, label)) {
        double L = hs.ev.len[0];
        int nl = (int)result(&res, "layers_left"), nr = (int)result(&res, "layers_right");
        CHECK(nl >= 2 && nr >= 2, "%s: %d and %d layers, expected at least 2 per wall", label,
              nl, nr);
        /* At eta 0.40 the density at a hard wall has its first minimum about 2.1 R from the
         * wall and the next one about 2 R further (spec 10 item 7 puts the maxima 1.7 ... 2.3 R
         * apart). The boundaries sit in these minima up to the noise of a flat minimum: over 51
         * seeds of this run the first boundary was at 2.00 ... 2.30 R (mean 2.13, s.d. 0.07)
         * and the second layer 1.55 ... 2.25 R wide (mean 1.93, s.d. 0.12), so the bounds
         * below are at least 3.5 standard deviations from the mean. */
        if (nl >= 2 && nr >= 2) {
            int nrow = o.blk[0].nrow;
            double l1 = num(&o, 0, 0, C_XTO), l2 = num(&o, 0, 1, C_XTO) - l1;
            double r1 = L - num(&o, 0, nrow - 1, C_XFROM);
            double r2 = num(&o, 0, nrow - 1, C_XFROM) - num(&o, 0, nrow - 2, C_XFROM);
            CHECK(l1 > 1.7 && l1 < 2.6, "%s: left layer 1 ends %.3f R from the wall", label, l1);
            CHECK(r1 > 1.7 && r1 < 2.6, "%s: right layer 1 ends %.3f R from the wall", label, r1);
            CHECK(l2 > 1.5 && l2 < 2.5, "%s: left layer 2 is %.3f R wide", label, l2);
            CHECK(r2 > 1.5 && r2 < 2.5, "%s: right layer 2 is %.3f R wide", label, r2);
            printf("  %s: layers %d + %d; left boundaries", label, nl, nr);
            for (int r = 0; r < nl; r++)
                printf(" %.2f", num(&o, 0, r, C_XTO));
            printf("; right boundaries (from the right wall)");
            for (int r = nrow - 1; r > nrow - 1 - nr; r--)
                printf(" %.2f", L - num(&o, 0, r, C_XFROM));
            printf("\n  psi6_layer1 %.4f, psi6_bulk %.4f, crystal-like %.4f (%.2f s)\n",
                   result(&res, "psi6_layer1"), result(&res, "psi6_bulk"),
                   result(&res, "xtal_fraction"), mote_wall_seconds() - w0);
        }
        CHECK(result(&res, "xtal_fraction") < 0.05, "%s: fluid crystal-like %.4f", label,
              result(&res, "xtal_fraction"));
    }
    ofile_free(&o);
    mote_hs_free(&hs);
}

/* ---- time series ------------------------------------------------------------------------------- */

static void test_time_rows(void)
{
    printf("time series beyond 1000 samples\n");
    char path[512];
    tmp_path(path, sizeof path, "rows.dat");
    mote_hs hs;
    mote_err err = {0};
    mote_hs_init(&hs, NULL);
    CHECK(mote_hs_bulk(&hs, 32, 0.50, &err) == MOTE_OK, "%s", err.msg);
    mote_result res;
    ofile o;
    if (run_order(&hs, 1001, path, &res, &o, "bulk 32, order 1001")) {
        /* rows group the samples s (0-based) with floor(s 1000 / 1001) equal: the first two
         * samples share row 1 */
        CHECK(num(&o, 2, 0, 0) == 1 && num(&o, 2, 0, 1) == 2 && num(&o, 2, 1, 0) == 3 &&
                  num(&o, 2, 999, 1) == 1001,
              "rows: first %g-%g, second from %g, last to %g", num(&o, 2, 0, 0),
              num(&o, 2, 0, 1), num(&o, 2, 1, 0), num(&o, 2, 999, 1));
    }
    ofile_free(&o);
    mote_hs_free(&hs);
}

/* ---- determinism, no perturbation, errors ----------------------------------------------------- */

static int read_all(const char *path, char *buf, size_t n)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    size_t k = fread(buf, 1, n - 1, f);
    buf[k] = 0;
    fclose(f);
    return (int)k;
}

static int count_files(void)
{
    DIR *d = opendir(tmpdir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d)))
        n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
    if (d)
        closedir(d);
    return n;
}

static void test_no_perturbation(void)
{
    printf("order does not perturb the trajectory; errors write nothing\n");
    mote_err err = {0};
    char p1[512], p2[512];
    tmp_path(p1, sizeof p1, "det1.dat");
    tmp_path(p2, sizeof p2, "det2.dat");
    mote_hs a, b, c;
    mote_hs *hs[3] = {&a, &b, &c};
    for (int q = 0; q < 3; q++) {
        mote_hs_init(hs[q], NULL);
        mote_hs_seed(hs[q], test_seed(8));
        CHECK(mote_hs_new(hs[q], 3, 0.45, &err) == MOTE_OK, "%s", err.msg);
        CHECK(mote_hs_step(hs[q], 10, &err) == MOTE_OK, "%s", err.msg);
    }
    CHECK(same_state(&a.ev, &b.ev), "identical seeds differ");
    CHECK(mote_hs_order(&a, 17, p1, NULL, NULL, &err) == MOTE_OK, "%s", err.msg);
    CHECK(mote_hs_order(&c, 17, p2, NULL, NULL, &err) == MOTE_OK, "%s", err.msg);
    CHECK(mote_hs_step(&b, 17, &err) == MOTE_OK, "%s", err.msg);
    CHECK(same_state(&a.ev, &b.ev), "order 17 and step 17 end in different states");
    static char f1[1 << 20], f2[1 << 20];
    int n1 = read_all(p1, f1, sizeof f1), n2 = read_all(p2, f2, sizeof f2);
    CHECK(n1 > 0 && n1 == n2 && memcmp(f1, f2, (size_t)n1) == 0,
          "two identical runs wrote different files");
    /* res == NULL still writes the results into the file */
    CHECK_HAS(f1, "# xtal_fraction = ");
    /* K = 0 changes nothing */
    CHECK(mote_hs_order(&a, 0, p1, NULL, NULL, &err) == MOTE_OK, "%s", err.msg);
    CHECK(same_state(&a.ev, &b.ev), "order 0 changed the state");

    /* errors: a missing directory is named, nothing runs, nothing is written */
    int files = count_files();
    char bad[600];
    tmp_path(bad, sizeof bad, "nodir/order.dat");
    mote_result res = {0};
    CHECK(mote_hs_order(&a, 5, bad, NULL, &res, &err) != MOTE_OK, "order into a missing dir");
    CHECK_HAS(err.msg, "nodir/order.dat");
    CHECK(res.n == 0, "a failed order returned %d results", res.n);
    CHECK(same_state(&a.ev, &b.ev), "a failed order ran dynamics");
    CHECK(count_files() == files, "a failed order left a file behind");
    /* an existing target keeps its content when order fails */
    FILE *f = fopen(p1, "w");
    fputs("previous content\n", f);
    fclose(f);
    mote_hs empty;
    mote_hs_init(&empty, NULL);
    CHECK(mote_hs_order(&empty, 1, p1, NULL, NULL, &err) == MOTE_EINVAL, "order without system");
    CHECK_HAS(err.msg, "no system");
    read_all(p1, f1, sizeof f1);
    CHECK_STR(f1, "previous content\n");
    mote_hs_free(&empty);
    /* the directory is a file: opening fails, the target's content stays */
    char notdir[600];
    tmp_path(notdir, sizeof notdir, "det1.dat/x.dat");
    CHECK(mote_hs_order(&a, 1, notdir, NULL, NULL, &err) != MOTE_OK, "order into a file's path");
    CHECK_HAS(err.msg, "det1.dat/x.dat");
    read_all(p1, f1, sizeof f1);
    CHECK_STR(f1, "previous content\n");
    CHECK(count_files() == files, "a failed order left a file behind");
    for (int q = 0; q < 3; q++)
        mote_hs_free(hs[q]);
}

int main(void)
{
    /* every case runs in full under the sanitizer too (MOTE_SANITIZED is not consulted): the
     * whole program takes a few seconds there */
    if (!test_tmpdir_make(tmpdir, sizeof tmpdir, "mote_test_order"))
        return 1;
    double w0 = mote_wall_seconds();
    test_fcc();
    test_disks_lattice();
    test_hex_slit();
    test_brute_force();
    test_melting();
    test_layers();
    test_time_rows();
    test_no_perturbation();
    test_remove_tree(tmpdir);
    printf("test_order: %.1f s\n", mote_wall_seconds() - w0);
    return test_summary();
}
