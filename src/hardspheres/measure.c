/* measure.c: sampling during a run (spec 8.1) and the structure measurements `image` (density
 * profile along x, 8.2) and `profile` (layer cut, 8.3), with the common data-file header (9.3).
 * Sampling projects positions to sample instants and never perturbs the trajectory: a measuring
 * command advances the system exactly as `step` with the same K would. */
#include "mote/hardspheres.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "measure.h"

/* ---- sampling ---------------------------------------------------------------------------------- */

void hs_snapshot(const mote_hs *hs, hs_snap *s)
{
    s->time = mote_ev_time(&hs->ev);
    s->collisions = hs->ev.collisions;
    s->wall_collisions = hs->ev.wall_collisions;
}

/* A sample as an observer of the run: the callback with its index. */
typedef struct {
    hs_sample_fn fn;
    void *ctx;
    mote_hs *hs;
    uint64_t s, nsamples;
} hs_sampler;

static int sample_fire(void *vs, void *subject, mote_err *err)
{
    hs_sampler *x = vs;
    if (x->s < x->nsamples)
        x->fn(x->ctx, x->hs, x->s++, x->nsamples);
    return MOTE_OK;
}

int hs_run_samples(mote_hs *hs, uint64_t k, uint64_t nsamples, hs_sample_fn fn, void *ctx,
                   const char *label, double *tau, mote_err *err)
{
    mote_ev *ev = &hs->ev;
    double t0 = mote_ev_time(ev);
    if (k == 0) {
        fn(ctx, hs, 0, 1);
        *tau = 0;
        return MOTE_OK;
    }
    /* sample s (1 ... S) right after collision floor(s C / S) of the run's C */
    const uint64_t C = k * ev->n / 2;
    hs_sampler x = {fn, ctx, hs, 0, nsamples};
    mote_observer o = {.ctx = &x, .fire = sample_fire, .from = ev->collisions,
                       .spread = nsamples, .over = C};
    mote_progress prog;
    mote_progress_begin(&prog, hs->ctx, label);
    int rc = hs_run_observed(hs, C, &o, 1, &prog, label, err);
    mote_progress_end(&prog);
    rc = hs_monitor_end(hs, rc, err);
    if (rc)
        return rc;
    while (x.s < nsamples) /* (a system in which nothing more can happen: the samples left) */
        fn(ctx, hs, x.s++, nsamples);
    *tau = mote_ev_time(ev) - t0;
    return MOTE_OK;
}

/* ---- the data-file header (spec 9.3) ----------------------------------------------------------- */

void hs_write_header(FILE *f, const mote_hs *hs, const char *format, const char *origin,
                     const hs_snap *start, const hs_snap *end)
{
    const mote_ev *ev = &hs->ev;
    mote_datafile_preamble(f, format, origin, hs->seed);
    fprintf(f, "# N = %u\n# d = %d\n# geometry = %s\n", ev->n, ev->dim,
            hs->geometry == MOTE_HS_SLIT ? "slit" : "periodic");
    fprintf(f, "# A = %.17g\n# L = %.17g\n", ev->len[1], ev->len[0]);
    if (ev->dim == 3 && ev->len[2] != ev->len[1])
        fprintf(f, "# A_z = %.17g\n", ev->len[2]);
    fprintf(f, "# eta = %.15g\n# phi = %.15g\n# kT_kin = %.15g\n", mote_hs_eta(hs),
            mote_hs_phi(hs), mote_ev_kt(ev));
    fprintf(f, "# start: time = %.15g, collisions = %llu, wall_collisions = %llu\n", start->time,
            (unsigned long long)start->collisions, (unsigned long long)start->wall_collisions);
    fprintf(f, "# end: time = %.15g, collisions = %llu, wall_collisions = %llu\n", end->time,
            (unsigned long long)end->collisions, (unsigned long long)end->wall_collisions);
    fprintf(f, "# units: length R (sphere radius); time sqrt(m R^2 / kT); number density R^-%d\n",
            ev->dim);
}

/* ---- bins along x -------------------------------------------------------------------------------- */

void hs_xbins_init(hs_xbins *xb, const mote_hs *hs, int64_t p)
{
    const mote_ev *ev = &hs->ev;
    xb->L = ev->len[0];
    xb->periodic = ev->periodic[0];
    double w = mote_hs_mean_radius(hs) / (double)p;
    if (xb->periodic) {
        xb->nb = (size_t)fmax(1.0, round(xb->L / w));
        xb->dx = xb->L / (double)xb->nb;
    } else {
        xb->dx = w;
        xb->nb = (size_t)fmax(1.0, ceil(xb->L / w));
        if (xb->nb > 1 && (double)(xb->nb - 1) * w >= xb->L)
            xb->nb--;
    }
}

size_t hs_xbins_of(const hs_xbins *xb, double x)
{
    double b = floor(x / xb->dx);
    if (!(b >= 0))
        return 0;
    if (b >= (double)xb->nb)
        return xb->nb - 1;
    return (size_t)b;
}

double hs_xbins_lo(const hs_xbins *xb, size_t b) { return (double)b * xb->dx; }

double hs_xbins_hi(const hs_xbins *xb, size_t b)
{
    return b + 1 == xb->nb ? xb->L : (double)(b + 1) * xb->dx;
}


/* ---- image: density profile along x ------------------------------------------------------------- */

typedef struct {
    double delta;       /* bin width */
    size_t nbins;
    double *count;      /* summed over samples */
    double *vol;        /* particle volume summed over samples */
    double *block;      /* [block][bin] counts */
} image_acc;

static void image_sample(void *ctx, mote_hs *hs, uint64_t s, uint64_t nsamples)
{
    image_acc *a = ctx;
    const mote_ev *ev = &hs->ev;
    double *blk = a->block + (size_t)hs_block_of(s, nsamples) * a->nbins;
    for (uint32_t i = 0; i < ev->n; i++) {
        double r[3];
        mote_ev_position(ev, i, r);
        long b = (long)floor(r[0] / a->delta);
        if (b < 0)
            b = 0;
        if ((size_t)b >= a->nbins)
            b = (long)a->nbins - 1;
        double R = mote_ev_radius(ev, i);
        a->count[b] += 1;
        a->vol[b] += ev->dim == 3 ? 4.0 / 3.0 * MOTE_PI * R * R * R : MOTE_PI * R * R;
        blk[b] += 1;
    }
}

int mote_hs_image(mote_hs *hs, uint64_t k, int64_t p, const char *path, const char *origin,
                  mote_err *err)
{
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "image: no system");
    if (p < 1)
        return mote_fail(err, MOTE_EINVAL, "image: points per radius must be >= 1");
    const mote_ev *ev = &hs->ev;
    image_acc a;
    a.delta = 1.0 / (double)p;
    a.nbins = (size_t)ceil(ev->len[0] / a.delta);
    if (a.nbins < 1)
        a.nbins = 1;
    if ((double)(a.nbins - 1) * a.delta >= ev->len[0] && a.nbins > 1)
        a.nbins--;
    uint64_t S = k == 0 ? 1 : k;
    int B = hs_nblocks(S);
    a.count = calloc(a.nbins, sizeof *a.count);
    a.vol = calloc(a.nbins, sizeof *a.vol);
    a.block = calloc((size_t)B * a.nbins, sizeof *a.block);
    double *bm = calloc((size_t)B, sizeof *bm);
    if (!a.count || !a.vol || !a.block || !bm) {
        free(a.count);
        free(a.vol);
        free(a.block);
        free(bm);
        return mote_fail(err, MOTE_ENOMEM, "image: out of memory for %zu bins", a.nbins);
    }
    hs_snap start, end;
    hs_snapshot(hs, &start);
    double tau;
    int rc = hs_run_samples(hs, k, S, image_sample, &a, "image", &tau, err);
    mote_afile af;
    if (!rc)
        rc = mote_afile_open(&af, path, err);
    if (!rc) {
        hs_snapshot(hs, &end);
        FILE *f = af.f;
        double area = mote_hs_cross_section(hs);
        hs_write_header(f, hs, "image", origin, &start, &end);
        fprintf(f, "# samples = %llu\n# blocks = %d\n# bin_width = %.17g\n",
                (unsigned long long)S, B, a.delta);
        fprintf(f, "# mean_density = %.15g\n", ev->n / (area * ev->len[0]));
        fprintf(f, "# columns: x_lo[R] x_hi[R] x_mid[R] count rho[R^-%d] rho_err[R^-%d] "
                   "rho_v\n",
                ev->dim, ev->dim);
        for (size_t b = 0; b < a.nbins; b++) {
            double lo = (double)b * a.delta;
            double hi = b + 1 == a.nbins ? ev->len[0] : (double)(b + 1) * a.delta;
            double w = hi - lo;
            for (int q = 0; q < B; q++)
                bm[q] = a.block[(size_t)q * a.nbins + b] / ((double)hs_block_size(q, S) * area * w);
            fprintf(f, "%.12g %.12g %.12g %.12g %.12g %.12g %.12g\n", lo, hi, 0.5 * (lo + hi),
                    a.count[b], a.count[b] / ((double)S * area * w), hs_block_error(bm, B),
                    a.vol[b] / ((double)S * area * w));
        }
        rc = mote_afile_commit(&af, err);
    }
    free(a.count);
    free(a.vol);
    free(a.block);
    free(bm);
    return rc;
}

/* ---- profile: layer cut ---------------------------------------------------------------------------- */

typedef struct {
    double x1, x2;
    FILE *body;
    uint64_t rows;
} cut_acc;

static void cut_sample(void *ctx, mote_hs *hs, uint64_t s, uint64_t nsamples)
{
    cut_acc *c = ctx;
    const mote_ev *ev = &hs->ev;
    (void)nsamples;
    for (uint32_t id = 0; id < ev->n; id++) { /* by particle number */
        double r[3];
        mote_ev_position(ev, mote_ev_slot(ev, id), r);
        if (r[0] < c->x1 || r[0] > c->x2)
            continue;
        if (ev->dim == 3)
            fprintf(c->body, "%llu %u %.12g %.12g %.12g\n", (unsigned long long)s + 1, id, r[1],
                    r[2], r[0]);
        else
            fprintf(c->body, "%llu %u %.12g %.12g\n", (unsigned long long)s + 1, id, r[1], r[0]);
        c->rows++;
    }
}

int mote_hs_profile(mote_hs *hs, double x1, double x2, int64_t dots, uint64_t k,
                    const char *path, const char *origin, mote_err *err)
{
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "profile: no system");
    if (!(x1 <= x2))
        return mote_fail(err, MOTE_EINVAL, "profile: x1 must not exceed x2 (got %g > %g)", x1, x2);
    if (dots < 1 || dots > MOTE_HS_PROFILE_DOTS_MAX)
        return mote_fail(err, MOTE_EINVAL, "profile: dots must be in 1 ... 1000000");
    if (k == 0 && dots != 1)
        return mote_fail(err, MOTE_EINVAL, "profile: K = 0 (no dynamics) allows only dots = 1");
    cut_acc c = {x1, x2, NULL, 0};
    char *buf = NULL;
    size_t len = 0;
    c.body = open_memstream(&buf, &len);
    if (!c.body)
        return mote_fail(err, MOTE_ENOMEM, "profile: out of memory");
    hs_snap start, end;
    hs_snapshot(hs, &start);
    double tau;
    int rc = hs_run_samples(hs, k, (uint64_t)dots, cut_sample, &c, "profile", &tau, err);
    fclose(c.body);
    mote_afile af;
    if (!rc)
        rc = mote_afile_open(&af, path, err);
    if (!rc) {
        hs_snapshot(hs, &end);
        FILE *f = af.f;
        hs_write_header(f, hs, "profile", origin, &start, &end);
        fprintf(f, "# x1 = %.17g\n# x2 = %.17g\n# samples = %lld\n# rows = %llu\n", x1, x2,
                (long long)dots, (unsigned long long)c.rows);
        fprintf(f, hs->ev.dim == 3 ? "# columns: sample id y[R] z[R] x[R]\n"
                                   : "# columns: sample id y[R] x[R]\n");
        if (len)
            fwrite(buf, 1, len, f);
        rc = mote_afile_commit(&af, err);
    }
    free(buf);
    return rc;
}
