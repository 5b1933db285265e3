/* structure.c: the two measurements users compute first: the radial distribution function
 * (`rdf K RMAX FILE`) and the mean-squared displacement with the self-diffusion coefficient
 * (`msd K FILE`). Both sample the run through hs_run_samples, so they advance the system exactly
 * as `step K` would.
 *
 * rdf, periodic box: g(r) over all pairs (minimum image, RMAX <= L/2), normalised by the ideal
 * pair count N(N-1)/2 * shell volume / V per sample; its contact value g(sigma+) by a quadratic
 * fit to the bins in [sigma, 1.1 sigma] extrapolated to sigma (sigma = 2 R, monodisperse), and
 * Z = 1 + 2^(d-1) eta g(sigma+) (3D: 1 + 4 eta g, 2D: 1 + 2 eta g), the pressure the contact
 * theorem gives. Slit: the lateral g(s) of pairs in one layer parallel to the walls, for the
 * layer at the walls (centres within R of a wall's contact plane, both walls together) and a
 * layer R thick at mid-slit, each normalised by its own pair count times the shell's share of
 * the wall area. Errors: block errors over the samples (spec 8.1).
 *
 * msd: unwrapped displacements (periodic axes; in a slit only the axes parallel to the walls),
 * sampled 4 times per collision per particle, so no particle moves half a box between samples
 * (checked); time origins every S/40 samples (36 of them: each lag is averaged over 36 origins),
 * lags up to S/8 (K/2 collisions per particle). D = slope / (2 d) fitted to the lags in the second
 * half of that range, with its error from 10 groups of particles (by number) fitted alike. The
 * origins' positions are kept as floats (their error, 1e-7 of a coordinate, is far below the
 * statistical error of any msd). */
#include "mote/grid.h"
#include "mote/hardspheres.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "measure.h"

#define RDF_BINS_PER_R 50   /* bin width R/50 = sigma/100 */
#define CONTACT_FIT 0.1     /* fit g over [sigma, (1 + CONTACT_FIT) sigma] */
#define LAYER_WIDTH 1.0     /* slit layers are R thick */
#define MSD_PER_COLLISION 4 /* samples per collision per particle */
#define MSD_ORIGINS 36      /* time origins at 0, S/40, ..., 35 S/40 */
#define MSD_LAGS 8          /* lags up to S/8 */
#define MSD_GROUPS 10

/* ---- rdf ------------------------------------------------------------------------------------ */

enum { L_BULK = 0, L_WALL = 0, L_MID = 1 };

typedef struct {
    const mote_hs *hs;
    int dim, slit, nlayer;
    double rmax, dr, len[3];
    size_t nbins;
    uint64_t S;
    int B;
    double *count; /* [B][nlayer][nbins] pair counts (each pair once) */
    double *ideal; /* [B][nlayer] ideal pair counts per unit "shell measure" */
    /* per sample scratch: the positions sorted into cells (grid.pos, in cell order) */
    mote_grid grid;
    double *raw;    /* [3 N] positions by engine record, for the build */
    double *rad;    /* per sorted particle: radius */
    uint8_t *layer; /* per sorted particle: layer + 1, 0 = none (slit) */
} rdf_acc;

/* The measure of a shell [a, b): volume (3D bulk), area (2D bulk), and in a slit the lateral
 * area share: 3D pi (b^2 - a^2), 2D 2 (b - a). */
static double shell_measure(const rdf_acc *a, double lo, double hi)
{
    int m = a->slit ? a->dim - 1 : a->dim;
    if (m == 3)
        return 4.0 / 3.0 * MOTE_PI * (hi * hi * hi - lo * lo * lo);
    if (m == 2)
        return MOTE_PI * (hi * hi - lo * lo);
    return 2 * (hi - lo);
}

static int layer_of(const rdf_acc *a, double x, double R)
{
    const double L = a->len[0];
    if (x <= 2 * R || x >= L - 2 * R) /* within R of the contact plane at R (or L - R) */
        return L_WALL + 1 + (x >= L - 2 * R ? 10 : 0); /* the two walls apart: pairs in one layer */
    if (fabs(x - 0.5 * L) < 0.5 * LAYER_WIDTH * R)
        return L_MID + 1;
    return 0;
}

static void rdf_sample(void *ctx, mote_hs *hs, uint64_t s, uint64_t nsamples)
{
    rdf_acc *a = ctx;
    const mote_ev *ev = &hs->ev;
    const uint32_t n = ev->n;
    const double R = mote_hs_mean_radius(hs);
    /* the positions at the sample instant, sorted by cell */
    for (uint32_t i = 0; i < n; i++)
        mote_ev_position(ev, i, a->raw + 3 * (size_t)i);
    const double *coord[3] = {a->raw, a->raw + 1, a->raw + 2};
    mote_grid_build(&a->grid, n, coord, 3);
    const mote_grid *g = &a->grid;
    uint64_t in_layer[12] = {0};
    for (uint32_t k = 0; k < n; k++) {
        a->rad[k] = mote_ev_radius(ev, g->order[k]);
        if (a->slit) {
            a->layer[k] = (uint8_t)layer_of(a, g->pos[3 * (size_t)k], R);
            in_layer[a->layer[k]]++;
        }
    }

    const int b = hs_block_of(s, nsamples);
    double *cnt = a->count + (size_t)b * (size_t)a->nlayer * a->nbins;
    double *ideal = a->ideal + (size_t)b * (size_t)a->nlayer;
    double area = mote_hs_cross_section(hs), vol = area * a->len[0];
    if (a->slit) {
        double pairs_wall = 0;
        for (int side = 0; side < 2; side++) {
            double m = (double)in_layer[L_WALL + 1 + 10 * side];
            pairs_wall += 0.5 * m * (m - 1);
        }
        double m = (double)in_layer[L_MID + 1];
        ideal[L_WALL] += pairs_wall / area;
        ideal[L_MID] += 0.5 * m * (m - 1) / area;
    } else {
        ideal[L_BULK] += 0.5 * (double)n * (double)(n - 1) / vol;
    }

    const double rmax2 = a->rmax * a->rmax, inv_dr = 1 / a->dr;
    for (size_t c = 0; c < g->ncells; c++) {
        if (g->start[c] == g->start[c + 1])
            continue;
        /* the distinct neighbour cells; separations take the minimum image below */
        size_t nb[27];
        double shift[27][3];
        int nn = mote_grid_neighbours(g, c, nb, shift);
        for (uint32_t i = g->start[c]; i < g->start[c + 1]; i++) {
            const double *pi = g->pos + 3 * (size_t)i;
            const int li = a->slit ? a->layer[i] : 1;
            if (!li)
                continue;
            for (int q = 0; q < nn; q++)
                for (uint32_t j = g->start[nb[q]]; j < g->start[nb[q] + 1]; j++) {
                    if (j <= i) /* each pair once: ordered by sorted index */
                        continue;
                    if (a->slit && a->layer[j] != li)
                        continue;
                    const double *pj = g->pos + 3 * (size_t)j;
                    double r2 = 0;
                    for (int d = a->slit ? 1 : 0; d < a->dim; d++) {
                        double dx = pj[d] - pi[d];
                        if (hs->ev.periodic[d]) {
                            if (dx > 0.5 * a->len[d])
                                dx -= a->len[d];
                            else if (dx < -0.5 * a->len[d])
                                dx += a->len[d];
                        }
                        r2 += dx * dx;
                    }
                    /* samples follow a collision, whose pair is exactly at contact then: a
                     * time-uniform sample finds no pair within 1e-9 sigma of contact, so such
                     * pairs are the sampling's, not the system's (they would bias g(sigma+)) */
                    double touch = (a->rad[i] + a->rad[j]) * (1 + 1e-9);
                    if (r2 >= rmax2 || (!a->slit && r2 < touch * touch))
                        continue;
                    size_t k = (size_t)(sqrt(r2) * inv_dr);
                    if (k >= a->nbins)
                        continue;
                    int layer = a->slit ? (li - 1) % 10 : L_BULK;
                    cnt[(size_t)layer * a->nbins + k] += 1;
                }
        }
    }
}

/* g of bin k of layer l over blocks [b0, b1). */
static double rdf_g(const rdf_acc *a, int l, size_t k, int b0, int b1)
{
    double c = 0, id = 0;
    for (int b = b0; b < b1; b++) {
        c += a->count[((size_t)b * (size_t)a->nlayer + (size_t)l) * a->nbins + k];
        id += a->ideal[(size_t)b * (size_t)a->nlayer + (size_t)l];
    }
    double m = shell_measure(a, (double)k * a->dr, (double)(k + 1) * a->dr);
    return id > 0 ? c / (id * m) : NAN;
}

/* Least-squares quadratic through the bins whose centres lie in [sigma, (1 + CONTACT_FIT)
 * sigma], evaluated at sigma. NaN with fewer than 3 such bins. */
static double rdf_contact(const rdf_acc *a, double sigma, int b0, int b1)
{
    double s[5] = {0}, t[3] = {0};
    int used = 0;
    for (size_t k = 0; k < a->nbins; k++) {
        double r = ((double)k + 0.5) * a->dr;
        if (r < sigma || r > (1 + CONTACT_FIT) * sigma || (double)k * a->dr < sigma * (1 - 1e-12))
            continue;
        double g = rdf_g(a, L_BULK, k, b0, b1), x = r - sigma, p = 1;
        if (!isfinite(g))
            continue;
        for (int e = 0; e < 5; e++, p *= x)
            s[e] += p;
        t[0] += g;
        t[1] += g * x;
        t[2] += g * x * x;
        used++;
    }
    if (used < 3)
        return NAN;
    /* normal equations [s0 s1 s2; s1 s2 s3; s2 s3 s4] c = t, solved for c0 by Cramer's rule */
    double m[3][3] = {{s[0], s[1], s[2]}, {s[1], s[2], s[3]}, {s[2], s[3], s[4]}};
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    double det0 = t[0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                  m[0][1] * (t[1] * m[2][2] - m[1][2] * t[2]) +
                  m[0][2] * (t[1] * m[2][1] - m[1][1] * t[2]);
    return det != 0 ? det0 / det : NAN;
}

int mote_hs_rdf_ok(const mote_hs *hs, double rmax, mote_err *err)
{
    const mote_ev *ev = &hs->ev;
    const double R = mote_hs_mean_radius(hs);
    if (!(rmax > 2 * R))
        return mote_fail(err, MOTE_EINVAL, "rdf: RMAX must exceed a diameter (%g), found %g",
                         2 * R, rmax);
    for (int d = 0; d < ev->dim; d++)
        if (ev->periodic[d] && rmax > 0.5 * ev->len[d])
            return mote_fail(err, MOTE_EINVAL,
                             "rdf: RMAX = %g exceeds half the periodic length along %c (%.10g): "
                             "pairs would be seen twice",
                             rmax, "xyz"[d], 0.5 * ev->len[d]);
    if (rmax / R * RDF_BINS_PER_R > 1e6)
        return mote_fail(err, MOTE_EINVAL, "rdf: RMAX = %g gives more than 10^6 bins", rmax);
    return MOTE_OK;
}

int mote_hs_rdf(mote_hs *hs, uint64_t k, double rmax, const char *path, const char *origin,
                mote_result *res, mote_err *err)
{
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "rdf: no system");
    int rc = mote_hs_rdf_ok(hs, rmax, err);
    if (rc)
        return rc;
    const mote_ev *ev = &hs->ev;
    const double R = mote_hs_mean_radius(hs), sigma = 2 * R;
    rdf_acc a;
    memset(&a, 0, sizeof a);
    a.hs = hs;
    a.dim = ev->dim;
    a.slit = hs->geometry == MOTE_HS_SLIT;
    a.nlayer = a.slit ? 2 : 1;
    a.rmax = rmax;
    a.dr = R / RDF_BINS_PER_R;
    a.nbins = (size_t)ceil(rmax / a.dr);
    a.S = k == 0 ? 1 : k;
    a.B = hs_nblocks(a.S);
    for (int d = 0; d < 3; d++)
        a.len[d] = d < a.dim ? ev->len[d] : 1;
    const double zero[3] = {0, 0, 0};
    int grid_fail = mote_grid_setup(&a.grid, a.dim, zero, a.len, ev->periodic, rmax, ev->n);
    a.count = calloc((size_t)a.B * (size_t)a.nlayer * a.nbins, sizeof *a.count);
    a.ideal = calloc((size_t)a.B * (size_t)a.nlayer, sizeof *a.ideal);
    a.raw = calloc(3 * (size_t)ev->n + 3, sizeof *a.raw);
    a.layer = calloc(ev->n + 1, 1);
    a.rad = calloc(ev->n + 1, sizeof *a.rad);
    hs_snap start, end;
    hs_snapshot(hs, &start);
    if (grid_fail || !a.count || !a.ideal || !a.raw || !a.layer || !a.rad)
        rc = mote_fail(err, MOTE_ENOMEM, "rdf: out of memory (%zu bins, N = %u)", a.nbins, ev->n);
    double tau = 0;
    if (!rc)
        rc = hs_run_samples(hs, k, a.S, rdf_sample, &a, "rdf", &tau, err);
    mote_result out = {0};
    double *gerr = NULL;
    if (!rc) {
        hs_snapshot(hs, &end);
        const double eta = mote_hs_phi(hs);
        mote_result_add(&out, "samples", (double)a.S, NAN);
        if (!a.slit && !ev->radius) {
            double bv[HS_BLOCKS];
            for (int b = 0; b < a.B; b++)
                bv[b] = rdf_contact(&a, sigma, b, b + 1);
            double g = rdf_contact(&a, sigma, 0, a.B), ge = hs_block_error(bv, a.B);
            double f = a.dim == 3 ? 4 * eta : 2 * eta;
            mote_result_add(&out, "g_contact", g, ge);
            mote_result_add(&out, "Z_contact", 1 + f * g, f * ge);
        }
        gerr = calloc(a.nbins * (size_t)a.nlayer, sizeof *gerr);
        if (!gerr)
            rc = mote_fail(err, MOTE_ENOMEM, "rdf: out of memory");
    }
    if (!rc) {
        double bv[HS_BLOCKS];
        for (int l = 0; l < a.nlayer; l++)
            for (size_t q = 0; q < a.nbins; q++) {
                for (int b = 0; b < a.B; b++)
                    bv[b] = rdf_g(&a, l, q, b, b + 1);
                gerr[(size_t)l * a.nbins + q] = hs_block_error(bv, a.B);
            }
        mote_afile af;
        rc = mote_afile_open(&af, path, err);
        if (!rc) {
            FILE *f = af.f;
            hs_write_header(f, hs, "rdf", origin, &start, &end);
            fprintf(f, "# K = %llu\n# samples = %llu\n# RMAX = %.17g\n# bin width = %.17g\n",
                    (unsigned long long)k, (unsigned long long)a.S, rmax, a.dr);
            mote_result_write(&out, f);
            if (a.slit)
                fprintf(f,
                        "# pairs in one layer parallel to the walls, lateral distance s: wall = "
                        "centres within R of a wall's contact plane (either wall), mid = centres "
                        "within R/2 of x = L/2; each g normalised by the layer's own pairs\n"
                        "# columns: s_lo[R] s_hi[R] s_mid[R] g_wall g_wall_err g_mid g_mid_err\n");
            else
                fprintf(f, "# g_contact: quadratic fit to g over [sigma, %.2g sigma], sigma = 2R, "
                           "at sigma; Z_contact = 1 + %d eta g_contact\n"
                           "# columns: r_lo[R] r_hi[R] r_mid[R] g g_err\n",
                        1 + CONTACT_FIT, a.dim == 3 ? 4 : 2);
            for (size_t q = 0; q < a.nbins; q++) {
                double lo = (double)q * a.dr, hi = lo + a.dr;
                fprintf(f, "%.10g %.10g %.10g", lo, hi, lo + 0.5 * a.dr);
                for (int l = 0; l < a.nlayer; l++)
                    fprintf(f, " %.10g %.6g", rdf_g(&a, l, q, 0, a.B),
                            gerr[(size_t)l * a.nbins + q]);
                fputc('\n', f);
            }
            rc = mote_afile_commit(&af, err);
        }
    }
    if (!rc && res)
        *res = out;
    free(gerr);
    free(a.count);
    free(a.ideal);
    mote_grid_free(&a.grid);
    free(a.raw);
    free(a.layer);
    free(a.rad);
    return rc;
}

/* ---- msd ------------------------------------------------------------------------------------ */

typedef struct {
    const mote_hs *hs;
    uint32_t n;
    int axis0, dim;  /* axes axis0 .. dim-1 are measured */
    uint64_t S;      /* samples */
    uint64_t every;  /* samples between time origins */
    uint64_t lags;   /* lags 0 .. lags */
    double *prev;    /* [n][3] wrapped positions at the previous sample */
    double *unwrap;  /* [n][3] unwrapped positions */
    float *origin;   /* [MSD_ORIGINS][n][3] */
    double *t_origin;
    double *msd;     /* [lags + 1][MSD_GROUPS] sums of squared displacements */
    double *tlag;    /* [lags + 1] sums of lag times */
    uint64_t *nlag;  /* [lags + 1] origin counts */
    double max_jump; /* largest displacement between two samples, in half box lengths */
} msd_acc;

static void save_origin(msd_acc *a, uint64_t o)
{
    float *r0 = a->origin + (size_t)o * 3 * a->n;
    for (size_t k = 0; k < 3 * (size_t)a->n; k++)
        r0[k] = (float)a->unwrap[k];
}

static void msd_sample(void *ctx, mote_hs *hs, uint64_t s, uint64_t nsamples)
{
    msd_acc *a = ctx;
    const mote_ev *ev = &hs->ev;
    const double t = mote_ev_time(ev);
    /* s counts the samples after the start (s = 0 is the first after it); sample index q = s + 1 */
    const uint64_t q = s + 1;
    for (uint32_t i = 0; i < a->n; i++) {
        double r[3];
        mote_ev_position(ev, mote_ev_slot(ev, i), r);
        for (int d = a->axis0; d < a->dim; d++) {
            double dx = r[d] - a->prev[3 * (size_t)i + d];
            if (ev->periodic[d]) {
                double half = 0.5 * ev->len[d];
                if (dx > half)
                    dx -= ev->len[d];
                else if (dx < -half)
                    dx += ev->len[d];
                if (fabs(dx) / half > a->max_jump)
                    a->max_jump = fabs(dx) / half;
            }
            a->unwrap[3 * (size_t)i + d] += dx;
            a->prev[3 * (size_t)i + d] = r[d];
        }
    }
    /* every origin o at sample o * every with a lag q - o * every in 1 .. lags */
    for (uint64_t o = 0; o < MSD_ORIGINS; o++) {
        uint64_t q0 = o * a->every;
        if (q0 >= q)
            break;
        uint64_t lag = q - q0;
        if (lag > a->lags)
            continue;
        const float *r0 = a->origin + (size_t)o * 3 * a->n;
        double *m = a->msd + (size_t)lag * MSD_GROUPS;
        for (uint32_t i = 0; i < a->n; i++) {
            double d2 = 0;
            for (int d = a->axis0; d < a->dim; d++) {
                double dx = a->unwrap[3 * (size_t)i + d] - (double)r0[3 * (size_t)i + d];
                d2 += dx * dx;
            }
            m[i % MSD_GROUPS] += d2;
        }
        a->tlag[lag] += t - a->t_origin[o];
        a->nlag[lag]++;
    }
    for (uint64_t o = 0; o < MSD_ORIGINS; o++)
        if (o * a->every == q) {
            save_origin(a, o);
            a->t_origin[o] = t;
        }
    (void)nsamples;
}

/* Least-squares slope of y against x over lags [l0, l1] of group g (g < 0: all groups). */
static double msd_slope(const msd_acc *a, uint64_t l0, uint64_t l1, int g)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0, m = 0;
    for (uint64_t l = l0; l <= l1; l++) {
        if (!a->nlag[l])
            continue;
        double x = a->tlag[l] / (double)a->nlag[l], y = 0, cnt = 0;
        for (int q = 0; q < MSD_GROUPS; q++) {
            if (g >= 0 && q != g)
                continue;
            y += a->msd[(size_t)l * MSD_GROUPS + (size_t)q];
            cnt += (double)((a->n + (uint32_t)(MSD_GROUPS - 1 - q)) / MSD_GROUPS);
        }
        y /= cnt * (double)a->nlag[l];
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
        m += 1;
    }
    double den = m * sxx - sx * sx;
    return m >= 2 && den > 0 ? (m * sxy - sx * sy) / den : NAN;
}

int mote_hs_msd(mote_hs *hs, uint64_t k, const char *path, const char *origin,
                mote_result *res, mote_err *err)
{
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "msd: no system");
    if (k < 4)
        return mote_fail(err, MOTE_EINVAL,
                         "msd: K must be >= 4 (the slope is fitted over lags of K/4 to K/2 "
                         "collisions per particle)");
    if (k > UINT64_MAX / MSD_PER_COLLISION / 64)
        return mote_fail(err, MOTE_EINVAL, "msd: K is too large");
    const mote_ev *ev = &hs->ev;
    msd_acc a;
    memset(&a, 0, sizeof a);
    a.hs = hs;
    a.n = ev->n;
    a.dim = ev->dim;
    a.axis0 = hs->geometry == MOTE_HS_SLIT ? 1 : 0;
    a.S = k * MSD_PER_COLLISION;
    a.every = a.S / 40 ? a.S / 40 : 1;
    a.lags = a.S / MSD_LAGS;
    const int dfree = a.dim - a.axis0;
    a.prev = calloc(3 * (size_t)a.n + 3, sizeof *a.prev);
    a.unwrap = calloc(3 * (size_t)a.n + 3, sizeof *a.unwrap);
    a.origin = calloc((size_t)MSD_ORIGINS * 3 * a.n + 3, sizeof *a.origin);
    a.t_origin = calloc(MSD_ORIGINS, sizeof *a.t_origin);
    a.msd = calloc((a.lags + 1) * MSD_GROUPS, sizeof *a.msd);
    a.tlag = calloc(a.lags + 1, sizeof *a.tlag);
    a.nlag = calloc(a.lags + 1, sizeof *a.nlag);
    int rc = MOTE_OK;
    if (!a.prev || !a.unwrap || !a.origin || !a.t_origin || !a.msd || !a.tlag || !a.nlag)
        rc = mote_fail(err, MOTE_ENOMEM, "msd: out of memory (N = %u, %llu lags)", a.n,
                       (unsigned long long)a.lags);
    hs_snap start, end;
    hs_snapshot(hs, &start);
    if (!rc) {
        for (uint32_t i = 0; i < a.n; i++) {
            mote_ev_position(ev, mote_ev_slot(ev, i), a.prev + 3 * (size_t)i);
            memcpy(a.unwrap + 3 * (size_t)i, a.prev + 3 * (size_t)i, 3 * sizeof(double));
        }
        save_origin(&a, 0);
        a.t_origin[0] = mote_ev_time(ev);
        double tau;
        rc = hs_run_samples(hs, k, a.S, msd_sample, &a, "msd", &tau, err);
    }
    if (!rc && a.max_jump > 0.5)
        rc = mote_fail(err, MOTE_ERUNTIME,
                       "msd: a particle moved %.2g half box lengths between two samples; the "
                       "unwrapped paths cannot be trusted (the box is too small for this "
                       "density)", a.max_jump);
    mote_result out = {0};
    if (!rc) {
        hs_snapshot(hs, &end);
        const uint64_t l0 = a.lags / 2, l1 = a.lags;
        double D = msd_slope(&a, l0, l1, -1) / (2 * dfree), bv[MSD_GROUPS];
        for (int g = 0; g < MSD_GROUPS; g++)
            bv[g] = msd_slope(&a, l0, l1, g) / (2 * dfree);
        double De = a.n >= MSD_GROUPS ? hs_block_error(bv, MSD_GROUPS) : NAN;
        mote_result_add(&out, "D", D, De);
        mote_result_add(&out, "fit_from", a.nlag[l0] ? a.tlag[l0] / (double)a.nlag[l0] : NAN,
                           NAN);
        mote_result_add(&out, "fit_to", a.nlag[l1] ? a.tlag[l1] / (double)a.nlag[l1] : NAN,
                           NAN);
        mote_result_add(&out, "dimensions", dfree, NAN);
        mote_afile af;
        rc = mote_afile_open(&af, path, err);
        if (!rc) {
            FILE *f = af.f;
            hs_write_header(f, hs, "msd", origin, &start, &end);
            fprintf(f, "# K = %llu\n# samples = %llu (%d per collision per particle)\n",
                    (unsigned long long)k, (unsigned long long)a.S, MSD_PER_COLLISION);
            fprintf(f, "# displacements along %s, unwrapped across periodic faces; time origins "
                       "every %llu samples, lags up to 1/8 of the run\n",
                    a.axis0 ? (a.dim == 3 ? "y and z (parallel to the walls)" : "y (parallel to "
                                                                                 "the walls)")
                            : (a.dim == 3 ? "x, y and z" : "x and y"),
                    (unsigned long long)a.every);
            fprintf(f, "# D = slope / (2 * %d), least squares over the lags from fit_from to "
                       "fit_to; D_err from %d groups of particles\n",
                    dfree, MSD_GROUPS);
            mote_result_write(&out, f);
            fprintf(f, "# columns: lag_time msd[R^2] msd_err[R^2] origins\n");
            for (uint64_t l = 1; l <= a.lags; l++) {
                if (!a.nlag[l])
                    continue;
                double y[MSD_GROUPS], tot = 0;
                for (int g = 0; g < MSD_GROUPS; g++) {
                    double cnt = (double)((a.n + (uint32_t)(MSD_GROUPS - 1 - g)) / MSD_GROUPS);
                    y[g] = a.msd[l * MSD_GROUPS + (size_t)g] / (cnt * (double)a.nlag[l]);
                    tot += a.msd[l * MSD_GROUPS + (size_t)g];
                }
                fprintf(f, "%.10g %.10g %.6g %llu\n", a.tlag[l] / (double)a.nlag[l],
                        tot / ((double)a.n * (double)a.nlag[l]),
                        a.n >= MSD_GROUPS ? hs_block_error(y, MSD_GROUPS) : NAN,
                        (unsigned long long)a.nlag[l]);
            }
            rc = mote_afile_commit(&af, err);
        }
    }
    if (!rc && res)
        *res = out;
    free(a.prev);
    free(a.unwrap);
    free(a.origin);
    free(a.t_origin);
    free(a.msd);
    free(a.tlag);
    free(a.nlag);
    return rc;
}
