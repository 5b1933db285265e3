/* chempot.c: `chempot K TRIALS FILE` (hard-spheres spec 8.5): the excess chemical potential by
 * Widom test-particle insertion. At each of the K samples, TRIALS test spheres of radius R_t = 1
 * are placed uniformly where their centres can be (x in [R_t, L - R_t] in a slit, anywhere in a
 * periodic box); an insertion succeeds when the test sphere overlaps no sphere. For hard spheres
 * exp(-beta dU) is 1 or 0, so beta mu_ex = -ln(success fraction).
 *
 * Insertion uses a cell grid built from the sample's positions (cells at least R_t + R_max wide),
 * so a trial costs O(1). The trials draw from the run's random stream; the trajectory does not
 * depend on it, so measuring never changes the dynamics. */
#include "mote/grid.h"
#include "mote/hardspheres.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "measure.h"

#define R_TEST 1.0

typedef struct {
    mote_hs *hs;
    hs_xbins xb;
    int64_t trials;
    int B;
    /* per block: [B] totals and [B][nb] profiles */
    double *tr, *ok;        /* trials, successes */
    double *ptr, *pok, *pn; /* per bin: trials, successes, centres counted */
    /* the sample's positions and radii (by particle) and their cell grid */
    double *pos;            /* [N][3] */
    double *rad;            /* [N] */
    mote_grid grid;
} wacc;

/* The positions at the sample instant, sorted into the grid. */
static void build_cells(wacc *a, const mote_ev *ev)
{
    for (uint32_t i = 0; i < ev->n; i++) {
        mote_ev_position(ev, i, a->pos + 3 * (size_t)i);
        a->rad[i] = mote_ev_radius(ev, i);
    }
    const double *coord[3] = {a->pos, a->pos + 1, a->pos + 2};
    mote_grid_build(&a->grid, ev->n, coord, 3);
}

/* Does a test sphere at t overlap any sphere? */
static int overlaps(const wacc *a, const mote_ev *ev, const double t[3])
{
    const mote_grid *g = &a->grid;
    size_t cells[27];
    double shift[27][3];
    int nn = mote_grid_neighbours(g, mote_grid_cell_of(g, t), cells, shift);
    for (int q = 0; q < nn; q++)
        for (uint32_t k = g->start[cells[q]]; k < g->start[cells[q] + 1]; k++) {
            uint32_t j = g->order[k];
            const double *r = a->pos + 3 * (size_t)j;
            double d2 = 0;
            for (int ax = 0; ax < ev->dim; ax++) {
                double d = t[ax] - r[ax];
                if (ev->periodic[ax]) {
                    if (d > 0.5 * ev->len[ax])
                        d -= ev->len[ax];
                    else if (d < -0.5 * ev->len[ax])
                        d += ev->len[ax];
                }
                d2 += d * d;
            }
            double sr = R_TEST + a->rad[j];
            if (d2 < sr * sr)
                return 1;
        }
    return 0;
}

static void sample(void *ctx, mote_hs *hs, uint64_t s, uint64_t nsamples)
{
    wacc *a = ctx;
    const mote_ev *ev = &hs->ev;
    const size_t nb = a->xb.nb;
    int b = hs_block_of(s, nsamples);
    build_cells(a, ev);
    for (uint32_t i = 0; i < ev->n; i++)
        a->pn[(size_t)b * nb + hs_xbins_of(&a->xb, a->pos[3 * (size_t)i])] += 1;
    double xlo = ev->periodic[0] ? 0 : R_TEST;
    double xlen = ev->periodic[0] ? ev->len[0] : ev->len[0] - 2 * R_TEST;
    for (int64_t k = 0; k < a->trials; k++) {
        double t[3] = {0, 0, 0};
        t[0] = xlo + xlen * mote_rng_uniform(&hs->rng);
        for (int ax = 1; ax < ev->dim; ax++)
            t[ax] = ev->len[ax] * mote_rng_uniform(&hs->rng);
        hs->rng_draws += (uint64_t)ev->dim;
        int ok = !overlaps(a, ev, t);
        size_t bin = hs_xbins_of(&a->xb, t[0]);
        a->tr[b] += 1;
        a->ok[b] += ok;
        a->ptr[(size_t)b * nb + bin] += 1;
        a->pok[(size_t)b * nb + bin] += ok;
    }
}

/* Mean centre density over the region open to centres (spec 8.5). */
static double mean_density(const mote_hs *hs)
{
    const mote_ev *ev = &hs->ev;
    double area = mote_hs_cross_section(hs);
    return ev->n / (area * (ev->periodic[0] ? ev->len[0] : ev->len[0] - 2 * R_TEST));
}

static int write_file(const wacc *a, const char *path, const char *origin, const hs_snap *start,
                      uint64_t S, const mote_result *res, double tau, mote_err *err)
{
    const mote_hs *hs = a->hs;
    const int B = a->B, d = hs->ev.dim;
    const size_t nb = a->xb.nb;
    double area = mote_hs_cross_section(hs);
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc)
        return rc;
    FILE *f = af.f;
    hs_snap end;
    hs_snapshot(hs, &end);
    hs_write_header(f, hs, "chempot", origin, start, &end);
    fprintf(f, "# samples = %llu\n# trials_per_sample = %lld\n# blocks = %d\n# tau = %.15g\n",
            (unsigned long long)S, (long long)a->trials, B, tau);
    fprintf(f, "# test_radius = %g\n# bin_width = %.17g\n", R_TEST, a->xb.dx);
    fprintf(f, "# mean_centre_density = %.15g\n", mean_density(hs));
    fprintf(f, "# errors: standard error of the %d block values (nan with fewer than 2 blocks); "
               "mu_ex errors propagated from the success fraction\n",
            B);
    mote_result_write(res, f);
    fprintf(f, "# in equilibrium column 8 is constant and equal to ln_n_plus_mu_ex\n");
    fprintf(f, "# columns: x_mid[R] trials successes p mu_ex[kT] rho[R^-%d] ln_rho_plus_mu_ex "
               "ln_rho_plus_mu_ex_err\n",
            d);
    double *bv = malloc(2 * (size_t)B * sizeof *bv);
    if (!bv) {
        mote_afile_abort(&af);
        return mote_fail(err, MOTE_ENOMEM, "chempot: out of memory");
    }
    for (size_t k = 0; k < nb; k++) {
        double lo = hs_xbins_lo(&a->xb, k), hi = hs_xbins_hi(&a->xb, k), w = hi - lo;
        double tr = 0, ok = 0, n = 0;
        for (int b = 0; b < B; b++) {
            double tb = a->ptr[(size_t)b * nb + k], ob = a->pok[(size_t)b * nb + k];
            double nbk = a->pn[(size_t)b * nb + k];
            tr += tb;
            ok += ob;
            n += nbk;
            bv[b] = tb > 0 ? ob / tb : NAN;
            bv[B + b] = nbk / ((double)hs_block_size(b, S) * area * w);
        }
        double p = tr > 0 ? ok / tr : NAN;
        double rho = n / ((double)S * area * w);
        double mu = p > 0 ? -log(p) : (tr > 0 ? INFINITY : NAN);
        double ep = hs_block_error(bv, B), er = hs_block_error(bv + B, B);
        double e = sqrt((ep / p) * (ep / p) + (er / rho) * (er / rho));
        double col = rho > 0 && p > 0 ? log(rho) + mu : NAN;
        fprintf(f, "%.12g %.12g %.12g %.12g %.12g %.12g %.12g %.12g\n", 0.5 * (lo + hi), tr, ok, p,
                mu, rho, col, p > 0 && rho > 0 ? e : NAN);
    }
    free(bv);
    return mote_afile_commit(&af, err);
}

int mote_hs_chempot(mote_hs *hs, uint64_t k, int64_t trials, const char *path,
                    const char *origin, mote_result *res, mote_err *err)
{
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "chempot: no system");
    if (trials < 1)
        return mote_fail(err, MOTE_EINVAL, "chempot: TRIALS must be >= 1");
    if (hs->bins < 1)
        return mote_fail(err, MOTE_EINVAL, "chempot: bins must be >= 1");
    const mote_ev *ev = &hs->ev;
    if (!ev->periodic[0] && ev->len[0] <= 2 * R_TEST)
        return mote_fail(err, MOTE_EINVAL, "chempot: the slit is too narrow for a test sphere");
    wacc a;
    memset(&a, 0, sizeof a);
    a.hs = hs;
    a.trials = trials;
    hs_xbins_init(&a.xb, hs, hs->bins);
    uint64_t S = k == 0 ? 1 : k;
    a.B = hs_nblocks(S);
    size_t B = (size_t)a.B, nb = a.xb.nb;
    /* cells at least the largest test-sphere contact distance wide */
    const double origin0[3] = {0, 0, 0};
    int grid_rc = mote_grid_setup(&a.grid, ev->dim, origin0, ev->len, ev->periodic,
                                  R_TEST + 0.5 * ev->sigma_max, ev->n);
    a.tr = calloc(B, sizeof *a.tr);
    a.ok = calloc(B, sizeof *a.ok);
    a.ptr = calloc(B * nb, sizeof *a.ptr);
    a.pok = calloc(B * nb, sizeof *a.pok);
    a.pn = calloc(B * nb, sizeof *a.pn);
    a.pos = malloc(3 * (size_t)ev->n * sizeof *a.pos);
    a.rad = malloc((size_t)ev->n * sizeof *a.rad);
    int rc = MOTE_OK;
    if (grid_rc || !a.tr || !a.ok || !a.ptr || !a.pok || !a.pn || !a.pos || !a.rad)
        rc = mote_fail(err, MOTE_ENOMEM, "chempot: out of memory");
    hs_snap start;
    hs_snapshot(hs, &start);
    double tau = 0;
    if (!rc)
        rc = hs_run_samples(hs, k, S, sample, &a, "chempot", &tau, err);
    if (!rc) {
        mote_result r = {0};
        double tr = 0, ok = 0, bp[HS_BLOCKS];
        for (int b = 0; b < a.B; b++) {
            tr += a.tr[b];
            ok += a.ok[b];
            bp[b] = a.ok[b] / a.tr[b];
        }
        double p = ok / tr, ep = hs_block_error(bp, a.B);
        double mu = ok > 0 ? -log(p) : INFINITY;
        mote_result_add(&r, "mu_ex", mu, ok > 0 ? ep / p : NAN);
        mote_result_add(&r, "p_insert", p, ep);
        mote_result_add(&r, "successes", ok, NAN);
        mote_result_add(&r, "ln_n_plus_mu_ex", log(mean_density(hs)) + mu,
                           ok > 0 ? ep / p : NAN);
        if (hs->geometry == MOTE_HS_PERIODIC && ev->dim == 3) {
            double e = mote_hs_eta(hs);
            mote_result_add(&r, "mu_ex_CS",
                               (8 * e - 9 * e * e + 3 * e * e * e) / pow(1 - e, 3), NAN);
        }
        if (ok == 0 && hs->log)
            fprintf(stderr, "warning: chempot: none of the %.0f insertions succeeded; mu_ex is "
                            "infinite (use more trials or samples)\n",
                    tr);
        rc = write_file(&a, path, origin, &start, S, &r, tau, err);
        if (!rc && res)
            *res = r;
    }
    free(a.tr);
    free(a.ok);
    free(a.ptr);
    free(a.pok);
    free(a.pn);
    free(a.pos);
    free(a.rad);
    mote_grid_free(&a.grid);
    return rc;
}
