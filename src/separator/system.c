/* system.c: the separator's particles in time (specs/separator.md 2.3, 2.6, 2.8, 2.10, 2.11,
 * 3.1): the exact drag drift, the dilute mode's reflections at walls and closed ends, exits and
 * bookkeeping, and the one-dimensional gas profile with solids-fraction coupling (the feed and
 * the particles' arrays: feed.c; the contacts and cells: dem.c; the gas properties and the
 * checks and set-up before a run: prepare.c; the Tromp curve: output.c). */
#include "mote/loop.h"
#include "mote/separator.h"

#include "sep.h"

#ifdef _OPENMP
#include <omp.h>
#endif

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SEP_PI 3.14159265358979323846

void mote_sep_init(mote_sep_system *s)
{
    memset(s, 0, sizeof *s);
    s->dim = 2;
    s->open_bottom = s->open_top = 1;
    s->U0 = -1; /* required */
    s->rho_g = 1.204;
    s->mu_g = 1.81e-5;
    s->g = 9.81;
    s->coupling = 1;
    s->eps_gas_min = 0.35;
    s->e_pw = -1;
    s->parcel = 1;
    s->e_pp = 0.5;
    s->mu_pw = s->mur_pw = s->coh_pw = -1;
    s->e_true = 1;
    for (int a = 0; a < MOTE_SEP_MAX_SPECIES; a++)
        for (int b = 0; b < MOTE_SEP_MAX_SPECIES; b++)
            s->mu_pair[a][b] = s->mur_pair[a][b] = s->coh_pair[a][b] = -1;
    s->dem = 1;
    s->delta_f = 0.05;
    s->nc = 50;
    s->nsort = 100;
    s->threads_min_n = SEP_THREADS_MIN_N;
    s->t_stop = INFINITY;
    mote_rng_seed(&s->rng, 1);
}

void mote_sep_free(mote_sep_system *s)
{
    free(s->x);
    free(s->y);
    free(s->z);
    free(s->vx);
    free(s->vy);
    free(s->vz);
    free(s->d);
    free(s->m);
    free(s->im);
    free(s->s);
    free(s->id);
    free(s->eps_s);
    free(s->u_g);
    free(s->eps_r);
    free(s->gp_z);
    free(s->gp_rho);
    free(s->gp_mu);
    free(s->rho_sl);
    free(s->mu_sl);
    free(s->class_edge);
    sep_tallies_free(s);
    free(s->prof_eps);
    free(s->prof_n);
    free(s->prof_mvz);
    free(s->prof_m);
    free(s->prof_ug);
    free(s->prof_fd);
    free(s->fx);
    free(s->fy);
    free(s->fz);
    mote_grid_free(&s->grid);
    free(s->pv);
    free(s->gx);
    free(s->gy);
    free(s->gz);
    free(s->nhead);
    free(s->nnext);
    free(s->nb);
    free(s->nb_start);
    free(s->exc);
    free(s->blk);
    free(s->xref);
    free(s->gap);
    free(s->ebox);
    free(s->ex_i);
    free(s->ex_c);
    free(s->back_s);
    free(s->back_d);
    free(s->w);
    free(s->tq);
    free(s->tq2);
    free(s->wh);
    free(s->mh);
    free(s->hist);
    free(s->hmap);
    free(s->pbuf);
    free(s->mir);
    free(s->cidx);
    free(s->ostart);
    free(s->wres);
    free(s->wflag);
    for (int k = 0; k < s->nsp; k++)
        mote_sep_dist_free(&s->sp[k].dist);
    for (int k = 0; k < s->nplate; k++)
        mote_sep_plate_free(&s->plate[k]);
    for (int k = 0; k < s->nmesh; k++)
        mote_sep_mesh_free(&s->mesh[k]);
    memset(s, 0, sizeof *s);
}

void mote_sep_size_range(const mote_sep_system *s, double *dmin, double *dmax)
{
    *dmin = INFINITY;
    *dmax = 0;
    for (int k = 0; k < s->nsp; k++)
        if (s->sp[k].have_dist) {
            *dmin = fmin(*dmin, mote_sep_dist_min(&s->sp[k].dist));
            *dmax = fmax(*dmax, mote_sep_dist_max(&s->sp[k].dist));
        }
}

/* The cross-section area (spec 2.3). */
double mote_sep_cross_section(const mote_sep_system *s)
{
    double dmin, dmax;
    mote_sep_size_range(s, &dmin, &dmax);
    return s->dim == 3 ? s->W * s->D : s->W * (s->D2 > 0 ? s->D2 : dmax);
}


/* ---- gas (spec 2.6) ------------------------------------------------------------------------- */

/* Particle i's volume into the slices: cloud in cell between the two nearest slice centres;
 * beyond the end centres, all to the end slice. */
static inline void deposit(const mote_sep_system *s, double *eps, size_t i)
{
    const int K = s->K;
    const double vol = s->parcel * SEP_PI * s->d[i] * s->d[i] * s->d[i] / 6;
    const double q = s->z[i] / s->dz - 0.5;
    if (!(q > 0)) {
        eps[0] += vol;
    } else if (q >= K - 1) {
        eps[K - 1] += vol;
    } else {
        const int k = (int)q;
        const double f = q - k;
        eps[k] += (1 - f) * vol;
        eps[k + 1] += f * vol;
    }
}

static void gas_finish(mote_sep_system *s, double dt);

/* The particles' volumes deposited in blocks of SEP_BLOCK particles, each block's sums made
 * alone (on the threads) and added in block order, so that the sums do not depend on the
 * threads; up to SEP_BLOCK particles, one block: in particle order. */
#define SEP_BLOCK 8192
static int deposit_all(mote_sep_system *s, mote_err *err)
{
    const int K = s->K;
    const size_t n = s->n, nblk = (n + SEP_BLOCK - 1) / SEP_BLOCK;
    for (int k = 0; k < K; k++)
        s->eps_s[k] = 0;
    if (nblk <= 1) {
        for (size_t i = 0; i < n; i++)
            deposit(s, s->eps_s, i);
        return MOTE_OK;
    }
    if (sep_reserve((void **)&s->blk, &s->blk_cap, nblk * (size_t)K, sizeof *s->blk, err))
        return err->code;
    double *blk = s->blk;
    const int nt = sep_threads(s);
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
    for (size_t b = 0; b < nblk; b++) {
        double *e = blk + b * (size_t)K;
        for (int k = 0; k < K; k++)
            e[k] = 0;
        const size_t hi = (b + 1) * SEP_BLOCK < n ? (b + 1) * SEP_BLOCK : n;
        for (size_t i = b * SEP_BLOCK; i < hi; i++)
            deposit(s, e, i);
    }
    for (size_t b = 0; b < nblk; b++)
        for (int k = 0; k < K; k++)
            s->eps_s[k] += blk[b * (size_t)K + (size_t)k];
    return MOTE_OK;
}

int mote_sep_gas_update(mote_sep_system *s, double dt, mote_err *err)
{
    if (s->K <= 0)
        return MOTE_OK;
    const int rc = deposit_all(s, err);
    if (!rc)
        gas_finish(s, dt);
    return rc;
}

/* From the deposited volumes: the fractions, their relaxation, and the gas velocity. */
static void gas_finish(mote_sep_system *s, double dt)
{
    const int K = s->K;
    double r0, m0;
    sep_profile_at(s, 0, &r0, &m0);
    const double Ac = mote_sep_cross_section(s), G = r0 * s->U0;
    s->clamped = 0;
    const double w = s->tau_eps > 0 && s->eps_r_valid ? fmin(dt / s->tau_eps, 1) : 1;
    for (int k = 0; k < K; k++) {
        s->eps_s[k] /= Ac * s->dz;
        s->eps_r[k] = w == 1 ? s->eps_s[k] : s->eps_r[k] + w * (s->eps_s[k] - s->eps_r[k]);
        double eg = 1 - s->eps_r[k];
        if (eg < s->eps_gas_min) {
            eg = s->eps_gas_min;
            s->clamped++;
        }
        const double rho = s->rho_sl ? s->rho_sl[k] : s->rho_g;
        s->u_g[k] = rho > 0 ? G / (rho * (s->coupling ? eg : 1)) : s->U0;
    }
    s->eps_r_valid = 1;
}

double mote_sep_gas_at(const mote_sep_system *s, double z)
{
    const double q = z / s->dz - 0.5;
    if (!(q > 0))
        return s->u_g[0];
    if (q >= s->K - 1)
        return s->u_g[s->K - 1];
    const int k = (int)q;
    const double f = q - k;
    return (1 - f) * s->u_g[k] + f * s->u_g[k + 1];
}

/* The voidage at z (for hindered drag). */
static double eps_gas_at(const mote_sep_system *s, double z)
{
    const double q = fmin(fmax(z / s->dz - 0.5, 0), s->K - 1);
    const int k = (int)fmin(q, s->K - 2 >= 0 ? s->K - 2 : 0);
    const double f = s->K > 1 ? q - k : 0;
    const double e = 1 - ((1 - f) * s->eps_r[k] + f * s->eps_r[s->K > 1 ? k + 1 : k]);
    return fmax(e, s->eps_gas_min);
}

/* ---- profiles (spec 3.2) ---------------------------------------------------------------------- */

/* The slice holding height z (clamped to the channel). */
static inline int slice_of(const mote_sep_system *s, double z)
{
    const double q = z / s->dz;
    return !(q > 0) ? 0 : q >= s->K - 1 ? s->K - 1 : (int)q;
}

/* Particle i's slice values into the sums eps (each species' solids fraction, stride `stride`
 * per slice), cnt, mvz, m (per slice), weighted by dt and scaled (sample_profiles). */
static inline void sample_one(const mote_sep_system *s, size_t i, double dt, double scale,
                              double *eps, size_t stride, double *cnt, double *mvz, double *m)
{
    const int K = s->K;
    const double vol = s->parcel * SEP_PI * s->d[i] * s->d[i] * s->d[i] / 6 * scale;
    const double q = s->z[i] / s->dz - 0.5;
    double *e = eps + s->s[i];
    if (!(q > 0)) {
        e[0] += vol;
    } else if (q >= K - 1) {
        e[(size_t)(K - 1) * stride] += vol;
    } else {
        const int k = (int)q;
        const double f = q - k;
        e[(size_t)k * stride] += (1 - f) * vol;
        e[(size_t)(k + 1) * stride] += f * vol;
    }
    const int k = slice_of(s, s->z[i]);
    cnt[k] += dt;
    mvz[k] += dt * s->parcel * s->m[i] * s->vz[i];
    m[k] += dt * s->parcel * s->m[i];
}

/* Add this step's slice values, weighted by dt: each species' solids fraction (cloud in cell,
 * as the gas model), the particle count and m v_z, m by the slice holding the centre, u_g.
 * Up to SEP_PBLOCK particles in particle order; beyond, as the gas's deposit: each block's sums
 * made alone (on the threads), added in block order, so that they do not depend on the
 * threads (blocks smaller than the deposit's: the samples cost more per particle, and a few
 * blocks would not share out evenly). */
#define SEP_PBLOCK 2048
static void sample_profiles(mote_sep_system *s, double dt)
{
    const int K = s->K;
    const double scale = dt / (mote_sep_cross_section(s) * s->dz);
    const size_t n = s->n, nblk = (n + SEP_PBLOCK - 1) / SEP_PBLOCK, nsp = (size_t)s->nsp;
    mote_err err;
    /* per block and slice: the species' fractions, the count, m v_z, m */
    const size_t w = nsp + 3, per = (size_t)K * w;
    if (nblk <= 1 || sep_reserve((void **)&s->blk, &s->blk_cap, nblk * per, sizeof *s->blk, &err)) {
        /* (one block, or no room for the blocks' sums: in particle order) */
        for (size_t i = 0; i < n; i++)
            sample_one(s, i, dt, scale, s->prof_eps, MOTE_SEP_MAX_SPECIES, s->prof_n,
                       s->prof_mvz, s->prof_m);
    } else {
        double *blk = s->blk;
        const int nt = sep_threads(s);
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
        for (size_t b = 0; b < nblk; b++) {
            double *e = blk + b * per, *cnt = e + (size_t)K * nsp, *mvz = cnt + K, *m = mvz + K;
            for (size_t k = 0; k < per; k++)
                e[k] = 0;
            const size_t hi = (b + 1) * SEP_PBLOCK < n ? (b + 1) * SEP_PBLOCK : n;
            for (size_t i = b * SEP_PBLOCK; i < hi; i++)
                sample_one(s, i, dt, scale, e, nsp, cnt, mvz, m);
        }
        for (size_t b = 0; b < nblk; b++) {
            const double *e = blk + b * per, *cnt = e + (size_t)K * nsp, *mvz = cnt + K,
                         *m = mvz + K;
            for (int k = 0; k < K; k++) {
                for (size_t j = 0; j < nsp; j++)
                    s->prof_eps[(size_t)k * MOTE_SEP_MAX_SPECIES + j] += e[(size_t)k * nsp + j];
                s->prof_n[k] += cnt[k];
                s->prof_mvz[k] += mvz[k];
                s->prof_m[k] += m[k];
            }
        }
    }
    for (int k = 0; k < K; k++)
        s->prof_ug[k] += dt * s->u_g[k];
    s->prof_time += dt;
}

void mote_sep_reset_stats(mote_sep_system *s)
{
    const size_t nc = s->cl_mf ? (size_t)s->nclass : 0, K = s->prof_n ? (size_t)s->prof_K : 0;
    for (size_t i = 0; i < nc; i++) {
        s->cl_mf[i] = s->cl_mc[i] = 0;
        s->cl_nf[i] = s->cl_nc[i] = 0;
    }
    for (size_t i = 0; i < nc * MOTE_SEP_MAX_SPECIES; i++) {
        s->cls_mf[i] = s->cls_mc[i] = 0;
        s->cls_nf[i] = s->cls_nc[i] = 0;
    }
    for (size_t k = 0; k < K; k++) {
        s->prof_n[k] = s->prof_mvz[k] = s->prof_m[k] = s->prof_ug[k] = s->prof_fd[k] = 0;
        for (int j = 0; j < MOTE_SEP_MAX_SPECIES; j++)
            s->prof_eps[k * MOTE_SEP_MAX_SPECIES + (size_t)j] = 0;
    }
    s->prof_time = 0;
    s->prof_wait = 0;
    s->avg_from = s->t;
}

/* ---- exits (spec 2.11) ----------------------------------------------------------------------- */

static int class_of(const mote_sep_system *s, double d);

/* Remember that particle i leaves (its outcome out). */
static int note_exit(mote_sep_system *s, size_t i, int out, mote_err *err)
{
    if (s->nex == s->ex_cap) {
        const size_t cap = s->ex_cap ? 2 * s->ex_cap : 64;
        size_t *a = realloc(s->ex_i, cap * sizeof *a);
        if (a)
            s->ex_i = a;
        int *b = realloc(s->ex_c, cap * sizeof *b);
        if (b)
            s->ex_c = b;
        if (!a || !b)
            return mote_fail(err, MOTE_ENOMEM, "separator: out of memory for the exits");
        s->ex_cap = cap;
    }
    s->ex_i[s->nex] = i;
    s->ex_c[s->nex++] = out;
    return MOTE_OK;
}

/* The tallies of particle i leaving with outcome out. */
static void tally_exit(mote_sep_system *s, size_t i, int out)
{
    const int k = s->s[i];
    const double m = s->parcel * s->m[i];
    const int c = class_of(s, s->d[i]);
    const size_t cs = (size_t)c * MOTE_SEP_MAX_SPECIES + (size_t)k;
    if (out == 1) {
        s->cnt[k].fines++;
        s->cnt[k].m_fines += m;
        if (c >= 0) {
            s->cl_nf[c]++;
            s->cl_mf[c] += m;
            s->cls_nf[cs]++;
            s->cls_mf[cs] += m;
        }
    } else if (out == 2) {
        s->cnt[k].coarse++;
        s->cnt[k].m_coarse += m;
        if (c >= 0) {
            s->cl_nc[c]++;
            s->cl_mc[c] += m;
            s->cls_nc[cs]++;
            s->cls_mc[cs] += m;
        }
    } else {
        s->cnt[k].lost++;
        s->cnt[k].m_lost += m;
    }
}

/* ---- one step (spec 2.10) ------------------------------------------------------------------- */

/* Whether a sphere of radius r at (x, y, z) touches or is inside a plate. */
int sep_touches_plate(const mote_sep_system *s, double x, double y, double z, double r)
{
    const double c[3] = {x, y, z};
    double delta[4], n[4][3];
    for (int k = 0; k < s->nplate; k++)
        if (mote_sep_plate_features(&s->plate[k], s->dim, c, r, delta, n) != 0)
            return 1;
    return 0;
}

/* The gas velocity a particle at height z feels: in a plate's holes u_g / phi. */
static double gas_for(const mote_sep_system *s, double z)
{
    const double u = mote_sep_gas_at(s, z);
    for (int k = 0; k < s->nplate; k++)
        if (z >= s->plate[k].zb && z <= s->plate[k].zb + s->plate[k].t)
            return u / s->plate[k].phi;
    return u;
}

/* A centre that a dilute step carried into a plate's solid (from c0, outside it): the face it
 * crossed, as one feature whose overlap is the radius plus the depth. 0 when c0 gives no
 * answer (then the particle is lost). */
static int crossed_face(const mote_sep_plate *p, int dim, const double c[3], const double c0[3],
                        double r, double delta[4], double n[4][3])
{
    const double zt = p->zb + p->t;
    n[0][0] = n[0][1] = n[0][2] = 0;
    if (c0[2] >= zt || c0[2] <= p->zb) { /* from above or below */
        const int top = c0[2] >= zt;
        delta[0] = r + (top ? zt - c[2] : c[2] - p->zb);
        n[0][2] = top ? 1 : -1;
        return 1;
    }
    const long k = mote_sep_plate_hole_at(p, dim, c0[0], c0[1]);
    if (k < 0)
        return 0;
    /* from inside a hole: the side face it is furthest beyond */
    const double *h = p->h + 4 * k;
    const double beyond[4] = {h[0] - c[0], c[0] - h[1], dim == 3 ? h[2] - c[1] : -1,
                              dim == 3 ? c[1] - h[3] : -1};
    int f = 0;
    for (int q = 1; q < 4; q++)
        if (beyond[q] > beyond[f])
            f = q;
    if (!(beyond[f] >= 0))
        return 0;
    delta[0] = r + beyond[f];
    n[0][f / 2 == 0 ? 0 : 1] = f % 2 == 0 ? 1 : -1;
    return 1;
}

/* 1 - exp(-h) for h >= 0: below 1e-4 by its series to h^4 (the next term is under 1e-18 of
 * the sum), which the steps of large particles always are, in a fraction of expm1()'s time */
static inline double one_minus_exp_neg(double h)
{
    return h < 1e-4 ? h * (1 - h * (0.5 - h * (1.0 / 6 - h * (1.0 / 24)))) : -expm1(-h);
}

/* Two independent standard normal variates from two uniforms (Box-Muller: no spare is kept,
 * so the generator's state is the whole state). */
static void normal_pair(mote_rng *rng, double *a, double *b)
{
    const double u1 = mote_rng_uniform(rng), u2 = mote_rng_uniform(rng);
    const double r = sqrt(-2 * log1p(-u1));
    *a = r * cos(2 * SEP_PI * u2);
    *b = r * sin(2 * SEP_PI * u2);
}

/* The Langevin kick of one component over dt (spec 2.10): the correlated Gaussian pair (dx, dv)
 * of an Ornstein-Uhlenbeck velocity with stationary variance sig2 = D / tau, exact for any
 * h = dt / tau. */
static void disperse1(mote_rng *rng, double *x, double *v, double sig2, double tau, double dt)
{
    const double h = dt / tau, omE = one_minus_exp_neg(h), E = 1 - omE;
    const double var_v = sig2 * omE * (1 + E);
    /* 2h - 3 + 4E - E^2, by its series for small h */
    const double q = h < 1e-2 ? h * h * h * (2.0 / 3 - h / 2 + 7 * h * h / 30 - h * h * h / 12)
                              : 2 * h - 3 + 4 * E - E * E;
    const double var_x = sig2 * tau * tau * q, cov = sig2 * tau * omE * omE;
    double a, b;
    normal_pair(rng, &a, &b);
    const double dv = sqrt(var_v) * a;
    const double cond = fmax(var_x - cov * cov / var_v, 0);
    *v += dv;
    *x += cov / var_v * dv + sqrt(cond) * b;
}

/* Reflect particle i from the walls, closed ends and plates (spec 2.8, collisions off); (x0,
 * y0, z0) is where the step began. */
static void reflect(mote_sep_system *s, size_t i, double x0, double y0, double z0)
{
    const double r = 0.5 * s->d[i], e = s->e_pw >= 0 ? s->e_pw : s->e_pp;
    for (int k = 0; k < s->nplate; k++) {
        const double c[3] = {s->x[i], s->y[i], s->z[i]}, c0[3] = {x0, y0, z0};
        double delta[4], n[4][3];
        int nf = mote_sep_plate_features(&s->plate[k], s->dim, c, r, delta, n);
        if (nf < 0)
            nf = crossed_face(&s->plate[k], s->dim, c, c0, r, delta, n);
        for (int f = 0; f < nf; f++) {
            s->x[i] += (1 + e) * delta[f] * n[f][0];
            s->y[i] += (1 + e) * delta[f] * n[f][1];
            s->z[i] += (1 + e) * delta[f] * n[f][2];
            const double vn = s->vx[i] * n[f][0] + s->vy[i] * n[f][1] + s->vz[i] * n[f][2];
            if (vn < 0) {
                s->vx[i] -= (1 + e) * vn * n[f][0];
                s->vy[i] -= (1 + e) * vn * n[f][1];
                s->vz[i] -= (1 + e) * vn * n[f][2];
            }
        }
    }
    double *pos[3] = {&s->x[i], &s->y[i], &s->z[i]}, *vel[3] = {&s->vx[i], &s->vy[i], &s->vz[i]};
    const double hi[3] = {s->W, s->D, s->H};
    for (int a = 0; a < 3; a++) {
        if (a == 1 && s->dim == 2)
            continue;
        if (a == 2 && s->open_bottom && s->open_top)
            continue;
        const int lo_wall = a < 2 || !s->open_bottom, hi_wall = a < 2 || !s->open_top;
        double delta = r - *pos[a]; /* the low wall, normal +a */
        if (lo_wall && delta > 0) {
            *pos[a] += (1 + e) * delta;
            if (*vel[a] < 0)
                *vel[a] = -e * *vel[a];
        }
        delta = *pos[a] + r - hi[a]; /* the high wall, normal -a */
        if (hi_wall && delta > 0) {
            *pos[a] -= (1 + e) * delta;
            if (*vel[a] > 0)
                *vel[a] = -e * *vel[a];
        }
    }
}

/* The class of diameter d (-1 outside the classes). */
static int class_of(const mote_sep_system *s, double d)
{
    if (!(d >= s->class_edge[0]) || d > s->class_edge[s->nclass])
        return -1;
    int lo = 0, hi = s->nclass;
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        if (s->class_edge[mid] <= d)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* Remove particle i (the last one takes its place). */
static void remove_particle(mote_sep_system *s, size_t i)
{
    s->mods++;
    const size_t l = --s->n;
    s->x[i] = s->x[l];
    s->y[i] = s->y[l];
    s->z[i] = s->z[l];
    s->vx[i] = s->vx[l];
    s->vy[i] = s->vy[l];
    s->vz[i] = s->vz[l];
    s->d[i] = s->d[l];
    s->m[i] = s->m[l];
    s->im[i] = s->im[l];
    s->s[i] = s->s[l];
    s->id[i] = s->id[l];
    s->fx[i] = s->fx[l];
    s->fy[i] = s->fy[l];
    s->fz[i] = s->fz[l];
    if (s->w) {
        memcpy(s->w + 3 * i, s->w + 3 * l, 3 * sizeof *s->w);
        memcpy(s->tq + 3 * i, s->tq + 3 * l, 3 * sizeof *s->tq);
        memcpy(s->wh + 9 * i, s->wh + 9 * l, 9 * sizeof *s->wh);
    }
    if (s->mh)
        memcpy(s->mh + 4 * SEP_MESH_SLOTS * i, s->mh + 4 * SEP_MESH_SLOTS * l,
               4 * SEP_MESH_SLOTS * sizeof *s->mh);
    s->nb_idx_ok = 0; /* (the rows' indices: sep_hist_stash kept the springs first) */
}

/* What the drift's pass reads and writes: the arrays and the settings, copied into each thread
 * as a local value (the compiler keeps them in registers across the calls of the drag's
 * functions and the stores of the particle), and what it predicts for the contacts' pass. The
 * arrays it only reads are restrict (nothing writes them in the pass); the positions and
 * velocities are not, as the dilute mode's reflect() writes them again through s. */
typedef struct {
    double *x, *y, *z, *vx, *vy, *vz;
    const double *restrict fx, *restrict fy, *restrict fz, *restrict im, *restrict d,
        *restrict m;
    const int *restrict sp;
    double dt, half_dt, wdt, g, rho_g, mu_g, chi, W, D, H;
    int dim, dem, gp_n, disperse, open_top, open_bottom, nplate;
    size_t n;
    double *fd, *fdz;        /* the drag's z force and the height (sampling), or NULL */
    double kick2;            /* the last step's pending second half kick (0: none) */
    const double *xref;      /* with the list's positions at its build (or NULL): */
    double lim;              /* the squared half skin a particle may move */
    /* per species, with the gas of constant density (no profile): the density and the
     * acceleration of gravity and buoyancy, -g (1 - rho_g / rho_p) */
    double rho_p[MOTE_SEP_MAX_SPECIES], acc[MOTE_SEP_MAX_SPECIES];
} drift_view;

/* The passes' kinds of drift, each compiled on its own (drift_one's constant arguments): the
 * contacts' usual step (the predictions and the list's check, no profile of the gas, no
 * sampling, no dispersion, no plates) in 3D or 2D, in vacuum or gas; anything else. */
enum { DRIFT_ANY, DRIFT_3D_VAC, DRIFT_3D_GAS, DRIFT_2D_VAC, DRIFT_2D_GAS };

/* 0 in the channel, 1 fines (above an open top), 2 coarse (below an open bottom), 3 lost
 * (outside a side wall by more than its radius, inside a plate's solid, not finite: the range
 * tests fail for NaN and the infinities). */
static inline int exit_code(const mote_sep_system *s, const drift_view *v, double x, double y,
                            double z, double r, int dim, int lean)
{
    /* one comparison for the usual case: the largest excursion beyond a side wall (the sign of
     * each difference is that of the comparison it stands for), and whether x, y, z are finite
     * (the sum of their differences from themselves is then 0, else NaN) */
    double out = -r - x > x - (v->W + r) ? -r - x : x - (v->W + r);
    if (dim == 3) {
        const double oy = -r - y > y - (v->D + r) ? -r - y : y - (v->D + r);
        out = oy > out ? oy : out;
    }
    if (!(out <= 0 && (x - x) + (y - y) + (z - z) == 0))
        return 3;
    for (int q = 0; !lean && q < v->nplate; q++) {
        const mote_sep_plate *p = &s->plate[q];
        if (z >= p->zb && z <= p->zb + p->t && mote_sep_plate_hole_at(p, v->dim, x, y) < 0)
            return 3;
    }
    if (v->open_top && z > v->H)
        return 1;
    if (v->open_bottom && z < 0)
        return 2;
    return 0;
}

/* What a drift's pass finds: the largest squared displacement, the displacements' box since the
 * list's build, whether a particle moved too far for the list, how many leave. */
typedef struct {
    double move2, box[6];
    int moved;
    size_t nexit;
} drift_sums;

/* What one particle's drift gives them: its squared displacement in the step and (with the
 * list's check) its displacement since the list's build. */
typedef struct {
    double mv, e[3];
    int wall; /* (SEP_EXC_WALL when it ends near a wall) */
} drift_res;

/* Particle i's half kick with the last contact forces (spec 2.10 step 1), then its drift, exact
 * under drag, gravity and buoyancy with the gas of the last profile; its squared displacement
 * into res->mv and its exit code returned; first, with v->kick2, the last step's pending second
 * half kick. With v->fd, the drag's z force at the step's start (weighted by wdt) goes to
 * fd[i], its height to fdz[i]; with the dispersion on, it draws from the system's one stream.
 * With v->xref (always for the lean kinds), its displacement since the list's build into
 * res->e. */
static inline __attribute__((always_inline)) int
drift_one(mote_sep_system *s, const drift_view *v, size_t i, drift_res *res, const int kind)
{
    /* the kind's constants: lean (the contacts' usual step), its dimension and gas */
    const int lean = kind != DRIFT_ANY;
    const int dim = kind == DRIFT_3D_VAC || kind == DRIFT_3D_GAS ? 3 : lean ? 2 : v->dim;
    const int vac = kind == DRIFT_3D_VAC || kind == DRIFT_2D_VAC;
    const double dt = v->dt;
    /* the particle in registers: loaded once, stored once */
    double vx = v->vx[i], vy = v->vy[i], vz = v->vz[i];
    const double x0 = v->x[i], y0 = v->y[i], z0 = v->z[i];
    if (lean || v->dem) {
        if (v->kick2 > 0) { /* the last step's second half kick (as the contacts' pass had it) */
            const double h2 = v->kick2 * v->im[i];
            vx += h2 * v->fx[i];
            vy += h2 * v->fy[i];
            vz += h2 * v->fz[i];
        }
        const double hk = 0.5 * dt * v->im[i];
        vx += hk * v->fx[i];
        vy += hk * v->fy[i];
        vz += hk * v->fz[i];
    }
    double x = x0, y = y0, z = z0;
    const int spi = v->sp[i];
    const double d = v->d[i];
    double rho_g = v->rho_g, mu_g = v->mu_g;
    if (!lean && v->gp_n)
        mote_sep_gas_props(s, z0, &rho_g, &mu_g);
    const int drag = !vac && mu_g > 0 && rho_g > 0;
    const double rho_p = v->rho_p[spi];
    const double a = !lean && v->gp_n ? -v->g * (1 - rho_g / rho_p) : v->acc[spi];
    if (v->fd) {
        v->fd[i] = 0;
        v->fdz[i] = z0;
    }
    if (drag) {
        const double u = gas_for(s, z0);
        const double wz = u - vz;
        const double Re = rho_g * sqrt(vx * vx + vy * vy + wz * wz) * d / mu_g;
        double f = mote_sep_drag_f(Re);
        if (!lean && v->chi != 0)
            f *= pow(eps_gas_at(s, z0), -v->chi);
        const double tau = rho_p * d * d / (18 * mu_g * f);
        if (v->fd)
            v->fd[i] = v->wdt * v->m[i] * (u - vz) / tau;
        /* the factors of the exact drift, once for the three components: sideways the gas
         * and the acceleration are 0 */
        const double h = dt / tau, omE = one_minus_exp_neg(h), E = 1 - omE;
        const double hm = h < 1e-4 ? h * h / 2 - h * h * h / 6 + h * h * h * h / 24 : h - omE;
        x += tau * vx * omE;
        vx *= E;
        if (dim == 3) {
            y += tau * vy * omE;
            vy *= E;
        }
        const double dv0 = vz - u;
        z += u * dt + tau * dv0 * omE + tau * tau * a * hm;
        vz = u + dv0 * E + tau * a * omE;
        if (!lean && v->disperse) {
            /* D = D_t + D_B, D_B = k_B T / (3 pi mu_g d) (Stokes-Einstein) */
            const double D = s->D_t + 1.380649e-23 * s->T_gas / (3 * SEP_PI * mu_g * d);
            disperse1(&s->rng, &x, &vx, D / tau, tau, dt);
            if (dim == 3)
                disperse1(&s->rng, &y, &vy, D / tau, tau, dt);
            disperse1(&s->rng, &z, &vz, D / tau, tau, dt);
        }
    } else { /* vacuum: constant acceleration */
        x += vx * dt;
        if (dim == 3)
            y += vy * dt;
        z += vz * dt + 0.5 * a * dt * dt;
        vz += a * dt;
    }
    const double ddx = x - x0, ddy = y - y0, ddz = z - z0;
    res->mv = ddx * ddx + ddy * ddy + ddz * ddz;
    if (lean || v->xref) {
        const double *q = v->xref + 3 * i;
        res->e[0] = x - q[0], res->e[1] = y - q[1], res->e[2] = z - q[2];
    }
    v->x[i] = x;
    v->y[i] = y;
    v->z[i] = z;
    v->vx[i] = vx;
    v->vy[i] = vy;
    v->vz[i] = vz;
    if (!lean && !v->dem) { /* the dilute mode's walls move the particle again */
        reflect(s, i, x0, y0, z0);
        x = v->x[i];
        y = v->y[i];
        z = v->z[i];
    }
    if (lean) { /* (no plates: the wall test and exit_code's from the same differences) */
        const double r = 0.5 * d;
        const double wx = r - x > x + r - v->W ? r - x : x + r - v->W;
        const double wz = r - z > z + r - v->H ? r - z : z + r - v->H;
        double side = wx;
        if (dim == 3) {
            const double wy = r - y > y + r - v->D ? r - y : y + r - v->D;
            side = wy > side ? wy : side;
        }
        const double wall = side > wz ? side : wz; /* (sep_near_wall's expression) */
        res->wall = wall > 0 ? SEP_EXC_WALL : 0;
        /* lost: beyond a side wall by more than the radius (r - x > 2 r: x < -r), or not finite */
        const int lost = !(side <= 2 * r) | !((x - x) + (y - y) + (z - z) == 0);
        const int top = v->open_top & (z > v->H), bottom = v->open_bottom & (z < 0);
        return lost ? 3 : top ? 1 : bottom ? 2 : 0;
    }
    res->wall = sep_near_wall(0.5 * d, x, y, z, v->W, v->D, v->H, dim) ? SEP_EXC_WALL : 0;
    return exit_code(s, v, x, y, z, 0.5 * d, dim, lean);
}

/* The drifts of the particles lo <= i < hi into *r, their exit codes into s->exc. */
static inline __attribute__((always_inline)) void
drift_range(mote_sep_system *s, const drift_view *v, size_t lo, size_t hi, drift_sums *r,
            const int kind)
{
    /* (the sums in local variables: registers, no chain through memory) */
    double move2 = r->move2, lx = r->box[0], ly = r->box[1], lz = r->box[2], hx = r->box[3],
           hy = r->box[4], hz = r->box[5];
    int moved = r->moved;
    size_t nexit = r->nexit;
    const int check = kind != DRIFT_ANY || v->xref;
    const double lim = v->lim;
    unsigned char *exc = s->exc;
    for (size_t i = lo; i < hi; i++) {
        drift_res d;
        const int e = drift_one(s, v, i, &d, kind);
        exc[i] = (unsigned char)(e | d.wall);
        nexit += e != 0;
        move2 = d.mv > move2 ? d.mv : move2;
        if (check) {
            const double ex = d.e[0], ey = d.e[1], ez = d.e[2];
            moved |= ex * ex + ey * ey + ez * ez > lim;
            lx = ex < lx ? ex : lx, ly = ey < ly ? ey : ly, lz = ez < lz ? ez : lz;
            hx = ex > hx ? ex : hx, hy = ey > hy ? ey : hy, hz = ez > hz ? ez : hz;
        }
    }
    *r = (drift_sums){move2, {lx, ly, lz, hx, hy, hz}, moved, nexit};
}

static int step(mote_sep_system *s, double dt, mote_err *err)
{
    /* per particle: the half kick and the drift; the largest displacement is watched (spec
     * 2.8's guard: r_min / 4) */
    double dmin, dmax, move2 = 0;
    mote_sep_size_range(s, &dmin, &dmax);
    /* the profiles are sampled every 10th step, each sample standing for the time since the
     * last (the drag of the step's start with them) */
    const int averaging = s->t + dt >= s->avg_from;
    if (averaging)
        s->prof_wait += dt;
    const int sampling = averaging && s->steps % 10 == 9;
    const double wdt = s->prof_wait;
    const size_t n = s->n;
    if (sep_reserve((void **)&s->exc, &s->exc_cap, n, 1, err) ||
        (sampling && sep_g_reserve(s, err)))
        return err->code;
    /* (the other forces' arrays are free between the contacts' passes; in vacuum, everywhere,
     * there is no drag to record: its sums would add zeros) */
    const int drag_somewhere = s->gp_n || (s->mu_g > 0 && s->rho_g > 0);
    double *fd = sampling && drag_somewhere ? s->gx : NULL;
    double *fdz = fd ? s->gy : NULL;
    /* the pair list's check in this pass, used when no particle leaves or enters */
    drift_view dv = {
        .x = s->x, .y = s->y, .z = s->z, .vx = s->vx, .vy = s->vy, .vz = s->vz, .fx = s->fx,
        .fy = s->fy, .fz = s->fz, .im = s->im, .d = s->d, .m = s->m, .sp = s->s, .dt = dt,
        .half_dt = 0.5 * dt, .wdt = wdt * s->parcel, .g = s->g, .rho_g = s->rho_g, .mu_g = s->mu_g,
        .chi = s->chi, .W = s->W, .D = s->D, .H = s->H, .dim = s->dim, .dem = s->dem,
        .gp_n = s->gp_n != 0, .disperse = s->D_t > 0 || s->T_gas > 0,
        .open_top = s->open_top, .open_bottom = s->open_bottom, .nplate = s->nplate, .n = n,
        .fd = fd, .fdz = fdz, .kick2 = s->kick_h};
    if (s->dem && !s->brute && s->skin_used > 0 && s->list_ok && s->mods == s->list_mods) {
        dv.xref = s->xref;
        dv.lim = 0.25 * s->skin_used * s->skin_used;
    }
    for (int k = 0; k < s->nsp; k++) {
        dv.rho_p[k] = s->sp[k].rho;
        dv.acc[k] = -dv.g * (1 - dv.rho_g / dv.rho_p[k]);
    }
    /* the kind of drift this pass is */
    int kind = DRIFT_ANY;
    if (dv.dem && !dv.gp_n && !dv.disperse && dv.xref && !dv.nplate && dv.chi == 0) {
        const int vac = !(dv.mu_g > 0 && dv.rho_g > 0);
        kind = dv.dim == 3 ? (vac ? DRIFT_3D_VAC : DRIFT_3D_GAS) : vac ? DRIFT_2D_VAC : DRIFT_2D_GAS;
    }
    const uint64_t mods0 = s->mods;
    int moved = 0;
    /* with the list's check, each block's box of the displacements since the build */
    if (dv.xref && sep_ebox_reserve(s, err))
        return err->code;
    double *ebox = dv.xref ? s->ebox : NULL;
    /* the dispersion draws from one stream in particle order: one thread */
    const int nt = dv.disperse ? 1 : sep_threads(s);
    size_t nexit = 0;
    const unsigned char *exc = s->exc;
    const size_t nblk = (n + SEP_EBLK - 1) / SEP_EBLK;
#pragma omp parallel num_threads(nt) if (nt > 1) reduction(max : move2) reduction(+ : nexit) \
    reduction(| : moved)
    {
        const drift_view v = dv; /* (this thread's own copy) */
#pragma omp for schedule(static) nowait
        for (size_t b = 0; b < nblk; b++) {
            /* a block by a loop compiled for the pass's kind */
            const size_t lo = b * SEP_EBLK, hi = lo + SEP_EBLK < n ? lo + SEP_EBLK : n;
            drift_sums r = {move2, {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY},
                            moved, nexit};
            switch (kind) {
            case DRIFT_3D_VAC: drift_range(s, &v, lo, hi, &r, DRIFT_3D_VAC); break;
            case DRIFT_3D_GAS: drift_range(s, &v, lo, hi, &r, DRIFT_3D_GAS); break;
            case DRIFT_2D_VAC: drift_range(s, &v, lo, hi, &r, DRIFT_2D_VAC); break;
            case DRIFT_2D_GAS: drift_range(s, &v, lo, hi, &r, DRIFT_2D_GAS); break;
            default: drift_range(s, &v, lo, hi, &r, DRIFT_ANY); break;
            }
            move2 = r.move2, moved = r.moved, nexit = r.nexit;
            if (ebox)
                memcpy(ebox + 6 * b, r.box, sizeof r.box);
        }
    }
    if (fd) { /* the drag's force by slice, summed in particle order (each slice's sum held in
               * a register while the particles stay in it: the same additions) */
        int k = -1;
        double sum = 0;
        for (size_t i = 0; i < n; i++) {
            const int ki = slice_of(s, fdz[i]);
            if (ki != k) {
                if (k >= 0)
                    s->prof_fd[k] = sum;
                k = ki;
                sum = s->prof_fd[k];
            }
            sum += fd[i];
        }
        if (k >= 0)
            s->prof_fd[k] = sum;
    }
    for (size_t i = 0; nexit && i < n; i++)
        if ((exc[i] & 15) && note_exit(s, i, exc[i] & 15, err))
            return err->code;
    /* (contact hertz: the angular kicks of this step, the pending one and the first half,
     * are made by the contacts' pass that follows, in its first loop over the particles) */
    s->rot_h1 = s->hertz ? s->kick_h : 0;
    s->rot_h2 = s->hertz ? 0.5 * dt : 0;
    s->kick_h = 0; /* (made in the drift) */
    if (s->dem && move2 > 0.0625 * 0.25 * dmin * dmin)
        s->fast_moves++;
    s->t += dt;
    s->steps++;
    /* exits and losses (spec 2.11), found in the drift's pass: the highest index first, so
     * that the last particle, moved into each place, is never one that leaves (the springs
     * kept by id first) */
    if (s->nex && sep_hist_stash(s, err))
        return err->code;
    for (size_t e = s->nex; e-- > 0;) {
        tally_exit(s, s->ex_i[e], s->ex_c[e]);
        remove_particle(s, s->ex_i[e]);
    }
    s->nex = 0;
    /* the feed (spec 2.5) */
    if (sep_feed(s, err))
        return err->code;
    /* the contacts from the new positions with the second half kick, then the particles'
     * volume for the gas (steps 5-8) */
    /* (when the gas does not feel the solids, no flow, no coupling, no hindrance and no
     * relaxation, the fractions wait for the end of the run or an output) */
    const int gas_sees = (s->coupling && s->U0 > 0 && s->rho_g > 0) || s->chi != 0 ||
                         s->tau_eps > 0;
    if (s->dem) {
        /* (the pass's predictions stand while the particles are the same: no exit, no feed) */
        const int pred = s->n == n && s->mods == mods0 ? (dv.xref ? moved : 2) : -1;
        const int rc = sep_contact_forces(s, dt, 1, pred, err);
        if (rc)
            return rc;
    }
    if (gas_sees && mote_sep_gas_update(s, dt, err))
        return err->code;
    if (sampling) {
        mote_sep_complete(s); /* (the velocities with their second half kick) */
        sample_profiles(s, wdt);
        s->prof_wait = 0;
    }
    return MOTE_OK;
}

void mote_sep_complete(mote_sep_system *s)
{
    if (!(s->kick_h > 0))
        return;
    const size_t n = s->n;
    const int rot = s->hertz && s->w;
    const int nt = sep_threads(s);
    const double kh = s->kick_h;
    double *vx = s->vx, *vy = s->vy, *vz = s->vz;
    const double *fx = s->fx, *fy = s->fy, *fz = s->fz, *im = s->im;
#pragma omp parallel for num_threads(nt) schedule(static) if (nt > 1)
    for (size_t i = 0; i < n; i++) { /* (the contacts' pass's expression: the same bits) */
        const double h = kh * im[i];
        vx[i] += h * fx[i];
        vy[i] += h * fy[i];
        vz[i] += h * fz[i];
        if (rot) /* (the angular velocities' half kick: the contacts' pass's expression) */
            sep_rot_kick(s, i, kh, 0);
    }
    s->kick_h = 0;
}


int mote_sep_advance(mote_sep_system *s, double t_end, int (*need)(void *, const mote_sep_system *),
                     void *ctx, mote_err *err)
{
    while (s->t < t_end) {
        const double dt = fmin(s->dt, t_end - s->t);
        if (!(dt > 1e-9 * s->dt)) /* a remainder from rounding the sum of the steps */
            return MOTE_OK;
        /* a run that cannot finish is an error, not a run without end (SEP_STEPS_MAX: some 10^4
         * years at 10^5 steps a second); nor can one whose step no longer moves the clock */
        if (!((t_end - s->t) / s->dt <= SEP_STEPS_MAX) || s->t + dt == s->t)
            return mote_fail(err, MOTE_ERUNTIME, "run: the time step %.3g s would take %.2g "
                             "steps to reach t = %g s: this run cannot finish (the gas speed, the "
                             "stiffness or the sizes make the step this small; `timestep DT` "
                             "sets it)", s->dt, (t_end - s->t) / s->dt, t_end);
        int rc = step(s, dt, err);
        if (rc)
            return rc;
        /* s->no_pending: every step completed, as a test's reference */
        if (s->no_pending)
            mote_sep_complete(s);
        if (need && (!(s->kick_h > 0) || need(ctx, s))) {
            mote_sep_complete(s);
            return MOTE_OK;
        }
    }
    return MOTE_OK;
}

int mote_sep_run_end(mote_sep_system *s, int rc, mote_err *err)
{
    mote_sep_complete(s); /* (also after an error) */
    /* the fractions of the present positions (for the outputs), also after an error */
    mote_err e2;
    if (mote_sep_gas_update(s, 0, rc ? &e2 : err) && !rc)
        rc = err->code;
    if (!rc && mote_sep_check_balance(s))
        rc = mote_fail(err, MOTE_ERUNTIME, "separator: the mass balance does not hold (fed = in "
                       "channel + fines + coarse + lost)");
    return rc;
}

/* mote_sep_run through the core's loop: no observers, the clock to t_end. */
static double sep_clock(const void *vs) { return ((const mote_sep_system *)vs)->t; }
static int sep_advance_plain(void *vs, mote_loop *l, double t_stop, uint64_t n_stop, mote_err *err)
{
    return mote_sep_advance(vs, l->t_end, NULL, NULL, err);
}

int mote_sep_run(mote_sep_system *s, double T, mote_err *err)
{
    int rc = mote_sep_prepare(s, err);
    const mote_runner r = {.what = "run", .sys = s, .clock = sep_clock,
                           .advance = sep_advance_plain};
    if (!rc)
        rc = mote_run(&r, NULL, 0, NULL, s->t + T, UINT64_MAX, err);
    return mote_sep_run_end(s, rc, err);
}
