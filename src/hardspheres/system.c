/* system.c: the hard-sphere system: seeding (`new`, `bulk`, `new_disks`, `bulk_disks`, spec 5),
 * Maxwell-Boltzmann velocities, the density definitions (spec 2.4), `step`, `temperature` and the
 * status line. The dynamics itself is the event engine's. */
#include "mote/hardspheres.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "measure.h"

#define SPHERE_VOLUME (4.0 / 3.0 * MOTE_PI)
#define ETA_CP_3D 0.74048048969306104 /* pi / (3 sqrt 2) */
#define ETA_CP_2D 0.90689968211710892 /* pi / (2 sqrt 3) */

void mote_hs_init(mote_hs *hs, mote_context *ctx)
{
    memset(hs, 0, sizeof *hs);
    hs->ctx = ctx;
    hs->log = ctx ? ctx->out : NULL;
    hs->bins = 10;
    mote_hs_seed(hs, 1);
}

void hs_drop_system(mote_hs *hs)
{
    if (hs->has_system)
        mote_ev_free(&hs->ev);
    hs->has_system = 0;
}

void mote_hs_free(mote_hs *hs)
{
    hs_drop_system(hs);
    mote_hs_dump_stop(hs);
    mote_hs_snapshots_stop(hs);
    mote_hs_frames_stop(hs);
    mote_hs_monitor_stop(hs);
    mote_hs_checkpoint_stop(hs);
}

void mote_hs_seed(mote_hs *hs, uint64_t seed)
{
    hs->seed = seed;
    hs->rng_draws = 0;
    hs->rng_from_file = 0;
    mote_rng_seed(&hs->rng, seed);
}

/* ---- densities ---------------------------------------------------------------------------------- */

double mote_hs_particle_volume_sum(const mote_hs *hs)
{
    const mote_ev *ev = &hs->ev;
    mote_ksum s = {0, 0};
    for (uint32_t i = 0; i < ev->n; i++) {
        double r = mote_ev_radius(ev, i);
        mote_ksum_add(&s, ev->dim == 3 ? SPHERE_VOLUME * r * r * r : MOTE_PI * r * r);
    }
    return mote_ksum_value(&s);
}

double mote_hs_mean_radius(const mote_hs *hs)
{
    const mote_ev *ev = &hs->ev;
    if (!ev->radius)
        return ev->radius0;
    mote_ksum s = {0, 0};
    for (uint32_t i = 0; i < ev->n; i++)
        mote_ksum_add(&s, ev->radius[i]);
    return mote_ksum_value(&s) / ev->n;
}

double mote_hs_cross_section(const mote_hs *hs)
{
    return hs->ev.dim == 3 ? hs->ev.len[1] * hs->ev.len[2] : hs->ev.len[1];
}

double mote_hs_eta(const mote_hs *hs)
{
    double v = mote_hs_particle_volume_sum(hs);
    if (hs->geometry == MOTE_HS_PERIODIC)
        return v / (hs->ev.len[0] * mote_hs_cross_section(hs));
    return v / (mote_hs_cross_section(hs) * (hs->ev.len[0] - 2 * mote_hs_mean_radius(hs)));
}

double mote_hs_phi(const mote_hs *hs)
{
    return mote_hs_particle_volume_sum(hs) / (hs->ev.len[0] * mote_hs_cross_section(hs));
}

double mote_hs_target_length(const mote_hs *hs, double eta)
{
    return 2 * mote_hs_mean_radius(hs) +
           mote_hs_particle_volume_sum(hs) / (eta * mote_hs_cross_section(hs));
}

/* ---- velocities (spec 5.4) ------------------------------------------------------------------- */

static void seed_velocities(mote_hs *hs)
{
    mote_ev *ev = &hs->ev;
    const int d = ev->dim;
    mote_normal g;
    mote_normal_init(&g, &hs->rng);
    for (uint32_t i = 0; i < ev->n; i++) {
        double s = sqrt(1.0 / mote_ev_mass(ev, i));
        for (int a = 0; a < d; a++)
            ev->p[i].v[a] = s * mote_normal_next(&g);
    }
    double P[3], M = 0;
    mote_ev_momentum(ev, P);
    for (uint32_t i = 0; i < ev->n; i++)
        M += mote_ev_mass(ev, i);
    for (uint32_t i = 0; i < ev->n; i++)
        for (int a = 0; a < d; a++)
            ev->p[i].v[a] -= P[a] / M;
    mote_ev_set_kt(ev, 1.0);
    hs->rng_draws += g.uniforms;
}

/* Common tail of every seed: velocities, rebuild, references, report. */
static int finish_seed(mote_hs *hs, const char *what, mote_err *err)
{
    seed_velocities(hs); /* in the spec's numbering, which stays the particles' numbers */
    hs->ev.spatial_order = 1; /* from here on the engine keeps its records in space order */
    int rc = mote_ev_rebuild(&hs->ev, err);
    if (rc)
        return rc;
    mote_ev_set_reference(&hs->ev);
    hs->has_system = 1;
    if (hs->log)
        fprintf(hs->log, "%s: N=%u seed=%llu rng_draws=%llu%s\n", what, hs->ev.n,
                (unsigned long long)hs->seed, (unsigned long long)hs->rng_draws,
                hs->rng_from_file ? " (stream continued from a state file)" : "");
    return MOTE_OK;
}

static int alloc_system(mote_hs *hs, uint64_t n, int dim, mote_err *err)
{
    if (n > 0xFFFFFFF0ull)
        return mote_fail(err, MOTE_EINVAL, "N = %llu is too large (at most 4294967280)",
                         (unsigned long long)n);
    mote_ev fresh;
    int rc = mote_ev_init(&fresh, (uint32_t)n, dim, 0, err);
    if (rc)
        return rc;
    hs_drop_system(hs);
    hs->ev = fresh;
    return MOTE_OK;
}

/* ---- `new NN eta`: 3D slit (spec 5.2) ----------------------------------------------------------- */

uint64_t mote_hs_new_count(int64_t nn)
{
    uint64_t a = (uint64_t)(4 * nn - 1), b = (uint64_t)(2 * nn - 1);
    return a * b * b + 1;
}

static void new_block_sizes(int64_t nn, double *A0, double *L0)
{
    const double s = MOTE_SQRT2;
    *A0 = 2 + (double)(2 * nn - 2) * s;
    *L0 = 2 + (double)(4 * nn - 2) * s;
}

static double new_density(double n, double A0, double L0, double beta)
{
    return n * SPHERE_VOLUME / (beta * beta * A0 * A0 * (2 * beta * L0 - 2));
}

double mote_hs_new_eta_max(int64_t nn)
{
    double A0, L0;
    new_block_sizes(nn, &A0, &L0);
    return new_density((double)mote_hs_new_count(nn), A0, L0, 1.0);
}

int mote_hs_new_ok(int64_t nn, double eta, mote_err *err)
{
    if (nn < 2)
        return mote_fail(err, MOTE_EINVAL, "new: NN must be at least 2, got %lld", (long long)nn);
    if (nn > 2000)
        return mote_fail(err, MOTE_EINVAL, "new: NN = %lld is far too large (N would exceed 2^32)",
                         (long long)nn);
    if (mote_hs_new_count(nn) > 0xFFFFFFF0ull)
        return mote_fail(err, MOTE_EINVAL, "new: NN = %lld gives too many spheres", (long long)nn);
    double emax = mote_hs_new_eta_max(nn);
    if (!(eta > 0) || eta > emax)
        return mote_fail(err, MOTE_EINVAL,
                         "new: eta = %.17g is outside (0, eta_max]; for NN = %lld eta_max = %.6f "
                         "(a larger NN allows a slightly higher density)",
                         eta, (long long)nn, emax);
    return MOTE_OK;
}

/* Solve new_density(beta) = eta for beta >= 1: Newton from (eta_max/eta)^(1/3), bracketed. */
static double new_solve_beta(double n, double A0, double L0, double eta)
{
    double emax = new_density(n, A0, L0, 1.0);
    if (eta >= emax)
        return 1.0;
    double lo = 1.0, hi = 2.0;
    while (new_density(n, A0, L0, hi) > eta)
        hi *= 2;
    double beta = cbrt(emax / eta);
    if (!(beta > lo && beta < hi))
        beta = 0.5 * (lo + hi);
    for (int it = 0; it < 200; it++) {
        double f = new_density(n, A0, L0, beta) - eta;
        if (f > 0)
            lo = beta;
        else
            hi = beta;
        /* d/dbeta of n v / (A0^2 (2 L0 beta^3 - 2 beta^2)) */
        double den = A0 * A0 * (2 * L0 * beta * beta * beta - 2 * beta * beta);
        double dden = A0 * A0 * (6 * L0 * beta * beta - 4 * beta);
        double df = -n * SPHERE_VOLUME * dden / (den * den);
        double next = beta - f / df;
        if (!(next > lo && next < hi))
            next = 0.5 * (lo + hi);
        if (next == beta || hi - lo <= 4 * 2.220446049250313e-16 * beta)
            return next;
        beta = next;
    }
    return beta;
}

int mote_hs_new(mote_hs *hs, int64_t nn, double eta, mote_err *err)
{
    int rc = mote_hs_new_ok(nn, eta, err);
    if (rc)
        return rc;
    uint64_t n = mote_hs_new_count(nn);
    if ((rc = alloc_system(hs, n, 3, err)))
        return rc;
    double A0, L0;
    new_block_sizes(nn, &A0, &L0);
    double beta = new_solve_beta((double)n, A0, L0, eta);
    double A = beta * A0;
    double L = 2 + (double)n * SPHERE_VOLUME / (eta * A * A);
    mote_ev *ev = &hs->ev;
    ev->periodic[0] = 0;
    ev->periodic[1] = ev->periodic[2] = 1;
    ev->len[0] = L;
    ev->len[1] = ev->len[2] = A;
    hs->geometry = MOTE_HS_SLIT;
    const double s = MOTE_SQRT2, xs = L / (2 * L0);
    uint32_t k = 0;
    for (int b = 0; b < 2; b++)
        for (int64_t i = 0; i <= 4 * nn - 2; i++)
            for (int64_t j = 0; j <= 2 * nn - 2; j++)
                for (int64_t q = 0; q <= 2 * nn - 2; q++) {
                    if ((i + j + q) % 2)
                        continue;
                    mote_particle *p = &ev->p[k++];
                    p->r[0] = xs * (1 + (double)i * s + b * L0);
                    p->r[1] = beta * (1 + (double)j * s);
                    p->r[2] = beta * (1 + (double)q * s);
                }
    return finish_seed(hs, "new", err);
}

/* ---- `bulk N eta`: periodic FCC cube ------------------------------------------------------------ */

static int64_t cube_root_exact(int64_t m)
{
    int64_t c = (int64_t)llround(cbrt((double)m));
    for (int64_t t = c - 1; t <= c + 1; t++)
        if (t >= 0 && t * t * t == m)
            return t;
    return -1;
}

int mote_hs_bulk_ok(int64_t n, double eta, mote_err *err)
{
    int64_t c = (n > 0 && n % 4 == 0) ? cube_root_exact(n / 4) : -1;
    if (c < 2 || n > 0xFFFFFFF0ll) {
        int64_t m = (int64_t)floor(cbrt((double)(n > 0 ? n : 1) / 4.0));
        if (m < 2)
            m = 2;
        int64_t lo = 4 * m * m * m, hi = 4 * (m + 1) * (m + 1) * (m + 1);
        if (lo > n && m > 2) {
            hi = lo;
            m--;
            lo = 4 * m * m * m;
        }
        if (n <= 32)
            return mote_fail(err, MOTE_EINVAL,
                             "bulk: N must be 4 n^3 with n >= 2 (32, 108, 256, ...); got %lld",
                             (long long)n);
        return mote_fail(err, MOTE_EINVAL,
                         "bulk: N must be 4 n^3 with n >= 2; got %lld, nearest valid values are "
                         "%lld and %lld",
                         (long long)n, (long long)lo, (long long)hi);
    }
    if (!(eta > 0) || eta > ETA_CP_3D)
        return mote_fail(err, MOTE_EINVAL,
                         "bulk: eta = %.17g is outside (0, %.5f] (FCC close packing)", eta,
                         ETA_CP_3D);
    return MOTE_OK;
}

int mote_hs_bulk(mote_hs *hs, int64_t n, double eta, mote_err *err)
{
    int rc = mote_hs_bulk_ok(n, eta, err);
    if (rc)
        return rc;
    int64_t m = cube_root_exact(n / 4);
    if ((rc = alloc_system(hs, (uint64_t)n, 3, err)))
        return rc;
    mote_ev *ev = &hs->ev;
    double a = cbrt(4 * SPHERE_VOLUME / eta);
    for (int ax = 0; ax < 3; ax++) {
        ev->periodic[ax] = 1;
        ev->len[ax] = (double)m * a;
    }
    hs->geometry = MOTE_HS_PERIODIC;
    static const double basis[4][3] = {{0, 0, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}, {0.5, 0.5, 0}};
    uint32_t k = 0;
    for (int64_t i = 0; i < m; i++)
        for (int64_t j = 0; j < m; j++)
            for (int64_t q = 0; q < m; q++)
                for (int b = 0; b < 4; b++) {
                    mote_particle *p = &ev->p[k++];
                    p->r[0] = a * ((double)i + basis[b][0] + 0.25);
                    p->r[1] = a * ((double)j + basis[b][1] + 0.25);
                    p->r[2] = a * ((double)q + basis[b][2] + 0.25);
                }
    return finish_seed(hs, "bulk", err);
}

/* ---- `new_disks nx ny eta`: 2D slit -------------------------------------------------------------- */

int mote_hs_new_disks_ok(int64_t nx, int64_t ny, double eta, mote_err *err)
{
    if (nx < 2)
        return mote_fail(err, MOTE_EINVAL, "new_disks: nx must be at least 2, got %lld",
                         (long long)nx);
    if (ny < 3)
        return mote_fail(err, MOTE_EINVAL, "new_disks: ny must be at least 3, got %lld",
                         (long long)ny);
    if (nx > 0xFFFFFFF0ll / ny)
        return mote_fail(err, MOTE_EINVAL, "new_disks: nx * ny is too large");
    double emax = (double)nx * MOTE_PI / (2 * sqrt(3.0) * (double)(nx - 1));
    if (!(eta > 0) || eta > emax)
        return mote_fail(err, MOTE_EINVAL,
                         "new_disks: eta = %.17g is outside (0, eta_max]; for nx = %lld eta_max = "
                         "%.6f",
                         eta, (long long)nx, emax);
    return MOTE_OK;
}

int mote_hs_new_disks(mote_hs *hs, int64_t nx, int64_t ny, double eta, mote_err *err)
{
    int rc = mote_hs_new_disks_ok(nx, ny, eta, err);
    if (rc)
        return rc;
    uint64_t n = (uint64_t)(nx * ny);
    if ((rc = alloc_system(hs, n, 2, err)))
        return rc;
    const double s3 = sqrt(3.0);
    double A0 = 2.0 * (double)ny, L0 = 2 + (double)(nx - 1) * s3;
    double beta = (A0 + sqrt(A0 * A0 + A0 * L0 * (double)n * MOTE_PI / eta)) / (A0 * L0);
    if (beta < 1)
        beta = 1;
    double A = beta * A0;
    double L = 2 + (double)n * MOTE_PI / (eta * A);
    mote_ev *ev = &hs->ev;
    ev->periodic[0] = 0;
    ev->periodic[1] = 1;
    ev->len[0] = L;
    ev->len[1] = A;
    hs->geometry = MOTE_HS_SLIT;
    uint32_t k = 0;
    for (int64_t i = 0; i < nx; i++)
        for (int64_t j = 0; j < ny; j++) {
            mote_particle *p = &ev->p[k++];
            p->r[0] = (L / L0) * (1 + (double)i * s3);
            p->r[1] = beta * (2.0 * (double)j + 0.5 + (double)(i % 2));
        }
    return finish_seed(hs, "new_disks", err);
}

/* ---- `bulk_disks N eta`: 2D periodic triangular lattice ---------------------------------------- */

int mote_hs_bulk_disks_ok(int64_t n, double eta, mote_err *err)
{
    int64_t m = (int64_t)llround(sqrt((double)(n > 0 ? n : 0)));
    if (n <= 0 || m * m != n || m % 2 || m < 4 || n > 0xFFFFFFF0ll) {
        int64_t e = (int64_t)floor(sqrt((double)(n > 0 ? n : 0)));
        if (e % 2)
            e--;
        if (e < 4)
            e = 4;
        int64_t lo = e * e, hi = (e + 2) * (e + 2);
        if (lo > n && e > 4) {
            hi = lo;
            lo = (e - 2) * (e - 2);
        }
        return mote_fail(err, MOTE_EINVAL,
                         "bulk_disks: N must be n^2 with n even and n >= 4; got %lld, nearest valid "
                         "values are %lld and %lld",
                         (long long)n, (long long)lo, (long long)hi);
    }
    if (!(eta > 0) || eta > ETA_CP_2D)
        return mote_fail(err, MOTE_EINVAL,
                         "bulk_disks: eta = %.17g is outside (0, %.5f] (hexagonal close packing)",
                         eta, ETA_CP_2D);
    return MOTE_OK;
}

int mote_hs_bulk_disks(mote_hs *hs, int64_t n, double eta, mote_err *err)
{
    int rc = mote_hs_bulk_disks_ok(n, eta, err);
    if (rc)
        return rc;
    int64_t m = (int64_t)llround(sqrt((double)n));
    if ((rc = alloc_system(hs, (uint64_t)n, 2, err)))
        return rc;
    mote_ev *ev = &hs->ev;
    double a = sqrt(2 * MOTE_PI / (sqrt(3.0) * eta));
    ev->periodic[0] = ev->periodic[1] = 1;
    ev->len[0] = (double)m * a;
    ev->len[1] = (double)m * a * sqrt(3.0) / 2;
    hs->geometry = MOTE_HS_PERIODIC;
    uint32_t k = 0;
    for (int64_t j = 0; j < m; j++)
        for (int64_t i = 0; i < m; i++) {
            mote_particle *p = &ev->p[k++];
            p->r[0] = a * ((double)i + 0.5 * (double)(j % 2) + 0.25);
            p->r[1] = a * (sqrt(3.0) / 2) * ((double)j + 0.5);
        }
    return finish_seed(hs, "bulk_disks", err);
}

/* ---- dynamics ---------------------------------------------------------------------------------- */

/* The model's side of the core loop: the engine's clock and collisions; an advance runs to the
 * next stop in slices of at most 1/100 of the run and 2^16 collisions, so that a terminal shows
 * progress and a live view gets frames (some 20 a second); slicing does not change the
 * trajectory. */
static double hs_clock(const void *sys) { return mote_ev_time(&((const mote_hs *)sys)->ev); }
static uint64_t hs_count(const void *sys) { return ((const mote_hs *)sys)->ev.collisions; }

static int hs_advance(void *sys, mote_loop *l, double t_stop, uint64_t n_stop, mote_err *err)
{
    mote_ev *ev = &((mote_hs *)sys)->ev;
    uint64_t slice = (l->n_end - l->n_begin) / 100 + 1;
    if (slice > 65536)
        slice = 65536;
    uint64_t n = n_stop - ev->collisions;
    if (n > slice)
        n = slice;
    return isfinite(t_stop) ? mote_ev_run_to(ev, t_stop, n, err) : mote_ev_run(ev, n, err);
}

int hs_run_observed(mote_hs *hs, uint64_t ncoll, mote_observer *obs, size_t nobs,
                    mote_progress *prog, const char *what, mote_err *err)
{
    mote_ev *ev = &hs->ev;
    const uint64_t end = ncoll < UINT64_MAX - ev->collisions ? ev->collisions + ncoll : UINT64_MAX;
    mote_observer all[8];
    size_t n = 0;
    for (; n < nobs && n < 3; n++)
        all[n] = obs[n];
    n += hs_dump_observer(hs, &all[n]);
    n += hs_monitor_observer(hs, &all[n]);
    n += hs_checkpoint_observer(hs, &all[n]);
    const mote_runner r = {.what = what, .sys = hs, .ctx = hs->ctx, .clock = hs_clock,
                           .count = hs_count, .advance = hs_advance};
    hs_monitor_hooks(hs, 1);
    const int rc = mote_run(&r, all, n, prog, INFINITY, end, err);
    hs_monitor_hooks(hs, 0);
    return rc;
}

int hs_run(mote_hs *hs, uint64_t ncoll, mote_err *err)
{
    return hs_run_observed(hs, ncoll, NULL, 0, NULL, "run", err);
}

int mote_hs_step(mote_hs *hs, uint64_t k, mote_err *err)
{
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "step: no system (use new, bulk or load first)");
    mote_ev *ev = &hs->ev;
    uint64_t total = k * ev->n / 2;
    mote_progress prog;
    mote_progress_begin(&prog, hs->ctx, "step");
    double w0 = mote_wall_seconds(), t0 = mote_ev_time(ev);
    uint64_t c0 = ev->collisions, wall0 = ev->wall_collisions;
    int rc = hs_run_observed(hs, total, NULL, 0, &prog, "step", err);
    mote_progress_end(&prog);
    rc = hs_monitor_end(hs, rc, err);
    if (rc)
        return rc;
    double secs = mote_wall_seconds() - w0;
    if (hs->log)
        fprintf(hs->log,
                "step: collisions=%llu time=%.6g wall_hits=%llu seconds=%.3f "
                "collisions_per_second=%.4g\n",
                (unsigned long long)(ev->collisions - c0), mote_ev_time(ev) - t0,
                (unsigned long long)(ev->wall_collisions - wall0), secs,
                secs > 0 ? (double)(ev->collisions - c0) / secs : 0.0);
    return MOTE_OK;
}

int mote_hs_temperature(mote_hs *hs, double kt, mote_err *err)
{
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "temperature: no system");
    if (!(kt > 0))
        return mote_fail(err, MOTE_EINVAL, "temperature: T must be > 0, got %g", kt);
    int rc = mote_ev_rebuild(&hs->ev, err);
    if (rc)
        return rc;
    mote_ev_set_kt(&hs->ev, kt);
    rc = mote_ev_rebuild(&hs->ev, err);
    if (rc)
        return rc;
    mote_ev_set_reference(&hs->ev);
    return MOTE_OK;
}

int mote_hs_set_array(mote_hs *hs, const char *name, const double *val, size_t rows, size_t cols,
                      mote_err *err)
{
    const int pos = !strcmp(name, "positions"), vel = !strcmp(name, "velocities");
    if (!pos && !vel)
        return mote_fail(err, MOTE_EINVAL, "set %s: the hard-spheres model sets positions or "
                         "velocities", name);
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "set %s: no system exists yet; create one first with "
                         "new, bulk, new_disks, bulk_disks or load", name);
    mote_ev *ev = &hs->ev;
    const size_t n = ev->n, d = (size_t)ev->dim;
    if (rows != n || cols != d)
        return mote_fail(err, MOTE_EINVAL, "set %s: expected %zu x %zu numbers (one row per "
                         "particle), found %zu x %zu", name, n, d, rows, cols);
    for (size_t id = 0; id < n; id++)
        for (size_t a = 0; a < d; a++) {
            const double x = val[id * d + a];
            const double R = mote_ev_radius(ev, mote_ev_slot(ev, (uint32_t)id));
            if (!isfinite(x) || (vel && !(fabs(x) <= 1e100)))
                return mote_fail(err, MOTE_EINVAL, "set %s: particle %zu: %s%c = %g is not a "
                                 "finite number%s", name, id, vel ? "v" : "", "xyz"[a], x,
                                 vel ? " up to 1e100" : "");
            const double lo = R * (1 - 1e-10), hi = ev->len[a] - lo;
            if (pos && !ev->periodic[a] && !(x >= lo && x <= hi))
                return mote_fail(err, MOTE_EINVAL, "set positions: particle %zu: %c = %.17g is "
                                 "outside the walls [%.17g, %.17g]", id, "xyz"[a], x, R,
                                 ev->len[a] - R);
        }
    int rc = mote_ev_rebuild(ev, err); /* (every particle at the clock: r and v are now) */
    if (rc)
        return rc;
    double *old = malloc(n * d * sizeof *old);
    if (!old)
        return mote_fail(err, MOTE_ENOMEM, "set %s: out of memory", name);
    for (size_t id = 0; id < n; id++) {
        mote_particle *p = &ev->p[mote_ev_slot(ev, (uint32_t)id)];
        for (size_t a = 0; a < d; a++) {
            double *q = pos ? &p->r[a] : &p->v[a], x = val[id * d + a];
            old[id * d + a] = *q;
            if (pos && ev->periodic[a]) { /* into [0, L) */
                x = fmod(x, ev->len[a]);
                x = x < 0 ? x + ev->len[a] : x;
                x = x < ev->len[a] ? x : 0;
            }
            *q = x;
        }
    }
    rc = mote_ev_rebuild(ev, err);
    uint32_t wi, wj;
    const double ratio = rc || !pos ? 1 : mote_ev_min_gap_ratio(ev, &wi, &wj);
    if (!rc && ratio < 1 - 1e-10)
        rc = mote_fail(err, MOTE_EINVAL, "set positions: particles %u and %u overlap: their "
                       "distance is %.12g of contact", ev->pc[wi].label, ev->pc[wj].label, ratio);
    if (rc) { /* the system as it was (found by label: the rebuild may have renumbered) */
        for (size_t id = 0; id < n; id++) {
            mote_particle *p = &ev->p[mote_ev_slot(ev, (uint32_t)id)];
            for (size_t a = 0; a < d; a++)
                *(pos ? &p->r[a] : &p->v[a]) = old[id * d + a];
        }
        mote_err e2 = {0};
        mote_ev_rebuild(ev, &e2);
    } else {
        mote_ev_set_reference(ev);
    }
    free(old);
    return rc;
}

int mote_hs_check(mote_hs *hs, mote_err *err)
{
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "check: no system");
    return mote_ev_check(&hs->ev, err);
}

void mote_hs_status(const mote_hs *hs, FILE *out)
{
    if (!out || !hs->has_system)
        return;
    const mote_ev *ev = &hs->ev;
    fprintf(out,
            "N=%u d=%d geometry=%s A=%.10g L=%.10g eta=%.10g phi=%.10g t=%.10g collisions=%llu "
            "wall_collisions=%llu E=%.15g kT=%.12g\n",
            ev->n, ev->dim, hs->geometry == MOTE_HS_SLIT ? "slit" : "periodic", ev->len[1],
            ev->len[0], mote_hs_eta(hs), mote_hs_phi(hs), mote_ev_time(ev),
            (unsigned long long)ev->collisions, (unsigned long long)ev->wall_collisions,
            mote_ev_energy(ev), mote_ev_kt(ev));
}
