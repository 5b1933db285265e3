/* measure.c: the mixing-box measurements (spec 4) and their data files: the mixing curve of
 * `record` (counts per chamber and colour, mixing fraction, mixing entropies, slit crossings and
 * fluxes, temperatures, energies, overlaps at every sample) and the time-averaged density
 * profile in y of `density_y` (per chamber, with the barometric law for comparison). Samples
 * are kept in memory and each file is rewritten whole and atomically, so an interrupted run
 * never leaves a half-written file. */
#include "mb.h"

#include "mote/datafile.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- common header --------------------------------------------------------------------------- */

static const char *integrator_name(int k) { return k == MOTE_MB_EVENT ? "event" : "timestep"; }
static const char *rule_name(int k) { return k == MOTE_MB_SEEDRULE ? "seed" : "restitution"; }

void mb_write_params(FILE *f, const mote_mb *sys, const char *format, const char *origin)
{
    const mote_mb_params *p = &sys->p;
    mote_datafile_preamble(f, format, origin, sys->seed);
    fprintf(f, "# parameters as of the last write (SI units):\n");
    fprintf(f, "# integrator = %s\n# collision_rule = %s\n", integrator_name(p->integrator),
            rule_name(p->rule));
    fprintf(f, "# X_L = %.17g\n# X_R = %.17g\n# X_B = %.17g\n# X_T = %.17g\n", p->x_l, p->x_r,
            p->x_b, p->x_t);
    fprintf(f, "# X1_C = %.17g\n# a = %.17g\n# X1_L = %.17g\n# X1_R = %.17g\n", p->x1_c, p->a,
            mote_mb_x1_l(p), mote_mb_x1_r(p));
    fprintf(f, "# X2_C = %.17g\n# b = %.17g\n# X2_B = %.17g\n# X2_T = %.17g\n", p->x2_c, p->b,
            mote_mb_x2_b(p), mote_mb_x2_t(p));
    fprintf(f, "# R = %.17g\n# nLeft = %lld\n# nRight = %lld\n# N = %u\n", p->r,
            (long long)p->n_left, (long long)p->n_right, sys->n);
    fprintf(f, "# V_init = %.17g\n# dV_B = %.17g\n# dV_T = %.17g\n# dV_S = %.17g\n", p->v_init,
            p->dv_b, p->dv_t, p->dv_s);
    fprintf(f, "# loss = %.17g\n# g = %.17g\n# t_c = %.17g\n# mass = %.17g\n", p->loss, p->g,
            mote_mb_tc(p), p->mass);
    fprintf(f, "# m_eq = %.17g\n", mote_mb_mixing_equilibrium(p));
}

/* ---- the mixing curve ------------------------------------------------------------------------ */

void mb_record_free(mb_record *r)
{
    mote_rows_free(&r->out);
    free(r->origin);
    free(r->rows);
    memset(r, 0, sizeof *r);
}

static int mb_record_sample(void *ctx, void *subject, mote_err *err)
{
    mote_mb *sys = subject;
    mb_record *r = ctx;
    if (r->nrows == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 256;
        mb_row *rows = realloc(r->rows, cap * sizeof *rows);
        if (!rows)
            return mote_fail(err, MOTE_ENOMEM, "record: out of memory after %zu samples",
                             r->nrows);
        r->rows = rows;
        r->cap = cap;
    }
    mb_row *w = &r->rows[r->nrows];
    w->t = sys->time;
    w->c = mote_mb_counts(sys);
    w->cross_lr = sys->cross_lr;
    w->cross_rl = sys->cross_rl;
    w->kt[0] = mote_mb_chamber_kt(sys, 0, NULL);
    w->kt[1] = mote_mb_chamber_kt(sys, 1, NULL);
    w->e = mote_mb_energy(sys, &w->e_kin);
    w->collisions = sys->collisions;
    uint64_t ov = mote_mb_count_overlaps(sys, MOTE_MB_OVERLAP_TOL);
    if (ov == UINT64_MAX)
        return mote_fail(err, MOTE_ENOMEM, "record: out of memory");
    mote_mb_note_overlaps(sys, ov);
    w->overlaps = ov;
    r->nrows++;
    return MOTE_OK;
}

static void put_real(FILE *f, double v)
{
    if (isnan(v))
        fputs(" nan", f);
    else
        fprintf(f, " %.10g", v);
}

static void record_header(FILE *f, const void *vr, int growing)
{
    const mb_record *r = vr;
    mb_write_params(f, r->sys, "mixing", r->origin);
    if (r->every)
        fprintf(f, "# every = %llu disk-disk collisions\n", (unsigned long long)r->every);
    else
        fprintf(f, "# DT = %.17g\n", r->dt);
    if (growing)
        fprintf(f, "# samples: the rows so far (a run in progress)\n");
    else
        fprintf(f, "# samples = %zu\n", r->nrows);
    fprintf(f,
            "# A row per sample: t (s; with DT the exact sample times); disks per chamber and colour (nL0 =\n"
            "# colour 0 in the left chamber, ...; the chamber of a disk is the side of X1_C its\n"
            "# centre is on); m = (nR0 + nL1) / N; mixing entropy per chamber S = -sum x ln x\n"
            "# over its colour fractions (nats, ln 2 = even), S_mix = (nL S_left + nR S_right) /\n"
            "# N; slit crossings (the centre passing X1_C) left->right and right->left,\n"
            "# cumulative and in the interval since the previous row, and per second; kT per\n"
            "# chamber = mean kinetic energy per disk (J); E = kinetic + m g (y - X_B) summed\n"
            "# (J); E_kin; disk-disk collisions so far; pairs overlapping now.\n");
    fprintf(f, "# columns: t nL0 nL1 nR0 nR1 m S_left S_right S_mix cross_lr cross_rl "
               "dcross_lr dcross_rl flux_lr flux_rl kT_left kT_right E E_kin collisions "
               "overlaps\n");
}

static void record_row(FILE *f, const mb_record *r, size_t k)
{
    const mb_row *w = &r->rows[k];
    uint64_t nl = w->c.n[0][0] + w->c.n[0][1], nr = w->c.n[1][0] + w->c.n[1][1];
    double sl = mote_mb_entropy(w->c.n[0][0], w->c.n[0][1]);
    double sr = mote_mb_entropy(w->c.n[1][0], w->c.n[1][1]);
    double smix = nl + nr ? ((double)nl * sl + (double)nr * sr) / (double)(nl + nr) : 0.0;
    uint64_t dlr = k ? w->cross_lr - r->rows[k - 1].cross_lr : 0;
    uint64_t drl = k ? w->cross_rl - r->rows[k - 1].cross_rl : 0;
    double interval = k ? w->t - r->rows[k - 1].t : 0.0;
    fprintf(f, "%.17g %llu %llu %llu %llu", w->t, (unsigned long long)w->c.n[0][0],
            (unsigned long long)w->c.n[0][1], (unsigned long long)w->c.n[1][0],
            (unsigned long long)w->c.n[1][1]);
    put_real(f, mote_mb_mixing_fraction(&w->c));
    put_real(f, sl);
    put_real(f, sr);
    put_real(f, smix);
    fprintf(f, " %llu %llu %llu %llu", (unsigned long long)w->cross_lr,
            (unsigned long long)w->cross_rl, (unsigned long long)dlr, (unsigned long long)drl);
    put_real(f, interval > 0 ? (double)dlr / interval : NAN);
    put_real(f, interval > 0 ? (double)drl / interval : NAN);
    put_real(f, w->kt[0]);
    put_real(f, w->kt[1]);
    put_real(f, w->e);
    put_real(f, w->e_kin);
    fprintf(f, " %llu %llu\n", (unsigned long long)w->collisions,
            (unsigned long long)w->overlaps);
}

int mb_record_observe(void *ctx, void *subject, mote_err *err)
{
    mb_record *r = ctx;
    int rc = mb_record_sample(ctx, subject, err);
    if (rc)
        return rc;
    record_row(r->out.text, r, r->nrows - 1); /* formatted once: the partial and whole files */
    return mote_rows_follow(&r->out, err);
}

int mb_record_start(mb_record *r, const mote_mb *sys, const char *path, int as, mote_err *err)
{
    r->sys = sys;
    int rc = mote_rows_open(&r->out, path, record_header, r, err);
    r->out.as = as;
    if (!rc)
        rc = mb_record_sample(r, (void *)sys, err);
    if (!rc) {
        record_row(r->out.text, r, 0);
        rc = mote_rows_start(&r->out, err);
    }
    return rc;
}

/* ---- the density profile in y ---------------------------------------------------------------- */

void mb_density_free(mb_density *d)
{
    free(d->path);
    free(d->origin);
    free(d->count[0]);
    free(d->count[1]);
    memset(d, 0, sizeof *d);
}

int mb_density_sample(void *ctx, void *subject, mote_err *err)
{
    mote_mb *sys = subject;
    mb_density *d = ctx;
    for (uint32_t i = 0; i < sys->n; i++) {
        int c = sys->side[i] ? 1 : 0;
        double b = floor((sys->y[i] - d->y0) / d->h);
        int64_t k = !(b >= 0) ? 0 : b >= (double)d->nbins ? d->nbins - 1 : (int64_t)b;
        d->count[c][k] += 1.0;
        d->ke[c] += 0.5 * sys->p.mass * (sys->vx[i] * sys->vx[i] + sys->vy[i] * sys->vy[i]);
        d->disks[c] += 1.0;
    }
    if (d->samples == 0)
        d->t_first = sys->time;
    d->t_last = sys->time;
    d->samples++;
    (void)err;
    return MOTE_OK;
}

/* Integral of exp(-lambda (y - lo)) from lo to y, for y >= lo (lambda of either sign or 0). */
static double baro_cdf(double lambda, double u)
{
    if (u <= 0)
        return 0.0;
    if (lambda == 0)
        return u;
    return -expm1(-lambda * u) / lambda;
}

int mb_density_write(const mb_density *d, const mote_mb *sys, mote_err *err)
{
    const mote_mb_params *p = &sys->p;
    mote_afile af;
    int rc = mote_afile_open(&af, d->path, err);
    if (rc)
        return rc;
    FILE *f = af.f;
    double width[2] = {mote_mb_x1_l(p) - p->x_l, p->x_r - mote_mb_x1_r(p)};
    double s = d->samples ? (double)d->samples : NAN;
    double kt[2], lambda[2], mean_n[2];
    for (int c = 0; c < 2; c++) {
        kt[c] = d->disks[c] > 0 ? d->ke[c] / d->disks[c] : NAN;
        lambda[c] = p->mass * p->g / kt[c];
        mean_n[c] = d->disks[c] / s;
    }
    mb_write_params(f, sys, "mixing-density", d->origin);
    fprintf(f, "# DT = %.17g\n# samples = %llu\n# t_first = %.17g\n# t_last = %.17g\n", d->dt,
            (unsigned long long)d->samples, d->t_first, d->t_last);
    fprintf(f, "# bins = %lld\n# bin_height = %.17g\n# width_left = %.17g\n# width_right = %.17g\n",
            (long long)d->nbins, d->h, width[0], width[1]);
    fprintf(f, "# kT_left = %.10g\n# kT_right = %.10g\n", kt[0], kt[1]);
    fprintf(f,
            "# Number densities (m^-2) of disk centres per bin of y, averaged over the samples:\n"
            "# mean count in the bin / (bin_height x chamber width), per chamber (by the side\n"
            "# of X1_C the centre is on) and for both together. baro_*: the barometric law\n"
            "# n(y) ~ exp(-m g (y - X_B - R) / kT) with the chamber's time-averaged kT (mean\n"
            "# kinetic energy per disk) over the centres' range X_B + R .. X_T - R, holding the\n"
            "# chamber's mean count, integrated over each bin (uniform when g = 0). It holds for\n"
            "# a dilute elastic gas.\n");
    fprintf(f, "# columns: y_lo y_hi y n_left n_right n_all count_left count_right baro_left "
               "baro_right\n");
    double lo = p->x_b + p->r, hi = p->x_t - p->r;
    for (int64_t k = 0; k < d->nbins; k++) {
        double ylo = d->y0 + (double)k * d->h;
        double yhi = k + 1 == d->nbins ? p->x_t : d->y0 + (double)(k + 1) * d->h;
        double cl = d->count[0][k] / s, cr = d->count[1][k] / s;
        double bh = yhi - ylo;
        fprintf(f, "%.10g %.10g %.10g", ylo, yhi, 0.5 * (ylo + yhi));
        put_real(f, cl / (bh * width[0]));
        put_real(f, cr / (bh * width[1]));
        put_real(f, (cl + cr) / (bh * (width[0] + width[1])));
        put_real(f, cl);
        put_real(f, cr);
        for (int c = 0; c < 2; c++) {
            double a = fmax(ylo, lo), b = fmin(yhi, hi);
            double total = baro_cdf(lambda[c], hi - lo);
            double part = b > a ? baro_cdf(lambda[c], b - lo) - baro_cdf(lambda[c], a - lo) : 0.0;
            double v = mean_n[c] * part / total / (bh * width[c]);
            put_real(f, isfinite(v) ? v : NAN);
        }
        fputc('\n', f);
    }
    return mote_afile_commit(&af, err);
}
