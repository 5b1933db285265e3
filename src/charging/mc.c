/* mc.c: the Monte Carlo current estimate of the charging model with straight paths (spec 5).
 * For each Maxwellian component k, N histories start on the injection sphere of radius R about
 * the body's centre: the position uniform on the sphere, the direction by the cosine law about
 * the inward normal (the inward flux of an isotropic Maxwellian). Each carries the current
 * weight w_k = q Gamma_k / N with Gamma_k = 4 pi R^2 n_k sqrt(kT_k / (2 pi m)), and its first
 * hit (nearest, spec 5.5) is tallied per triangle and side. Without a field the path does not
 * depend on the speed, so none is drawn. Random numbers are Philox4x32-10 keyed by the seed with
 * the counter (history, component, draw): every history has its own stream, so the tallies
 * (integers) are the same for any number of threads. */
#include "mote/charging.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

/* ---- Philox4x32-10 (J. K. Salmon, M. A. Moraes, R. O. Dror, D. E. Shaw, SC11) ---------------- */

void mote_ch_philox(const uint32_t ctr[4], const uint32_t key[2], uint32_t out[4])
{
    uint32_t c[4] = {ctr[0], ctr[1], ctr[2], ctr[3]}, k[2] = {key[0], key[1]};
    for (int round = 0; round < 10; round++) {
        if (round > 0) {
            k[0] += 0x9E3779B9u;
            k[1] += 0xBB67AE85u;
        }
        const uint64_t p0 = (uint64_t)0xD2511F53u * c[0], p1 = (uint64_t)0xCD9E8D57u * c[2];
        const uint32_t n0 = (uint32_t)(p1 >> 32) ^ c[1] ^ k[0], n1 = (uint32_t)p1;
        const uint32_t n2 = (uint32_t)(p0 >> 32) ^ c[3] ^ k[1], n3 = (uint32_t)p0;
        c[0] = n0;
        c[1] = n1;
        c[2] = n2;
        c[3] = n3;
    }
    memcpy(out, c, sizeof c);
}

/* Four uniforms in (0, 1) (32 bits each, never 0 or 1) from one Philox block. */
static void uniforms4(const uint32_t key[2], uint64_t history, uint32_t comp, double u[4])
{
    const uint32_t ctr[4] = {(uint32_t)history, (uint32_t)(history >> 32), comp, 0};
    uint32_t w[4];
    mote_ch_philox(ctr, key, w);
    for (int j = 0; j < 4; j++)
        u[j] = ((double)w[j] + 0.5) * (1.0 / 4294967296.0);
}

void mote_ch_result_free(mote_ch_result *r)
{
    free(r->tri_hits);
    memset(r, 0, sizeof *r);
}

enum { BLOCK = 4096 };

int mote_ch_run(const mote_ch_plasma *p, const mote_ch_body *b, const mote_ch_tracer *t,
                const mote_ch_run_opts *o, mote_ch_result *r, mote_err *err)
{
    memset(r, 0, sizeof *r);
    if (p->nsp == 0)
        return mote_fail(err, MOTE_EINVAL, "run: the plasma has no species (plasma preset ...)");
    if (o->particles == 0)
        return mote_fail(err, MOTE_EINVAL, "run: particles must be >= 1");
    mote_ch_geometry g;
    mote_ch_body_geometry(b, &g);
    const double R = o->r_gen;
    if (!(R > g.r_bound))
        return mote_fail(err, MOTE_EINVAL, "run: the injection radius %.6g m must exceed the "
                         "body's bounding radius %.6g m", R, g.r_bound);
    const uint32_t ntri = b->sphere ? 1 : b->ntri;
    r->nsp = p->nsp;
    r->ntri = ntri;
    r->histories = o->particles;
    for (int s = 0; s < p->nsp; s++)
        r->ncomp += p->sp[s].ncomp;
    r->tri_hits = calloc((size_t)r->ncomp * ntri * 2, sizeof *r->tri_hits);
    if (!r->tri_hits)
        return mote_fail(err, MOTE_ENOMEM, "run: out of memory for the tallies");
    const uint32_t key[2] = {(uint32_t)o->seed, (uint32_t)(o->seed >> 32)};
    const double tmin = 1e-9 * (2 * g.r_bound);
    /* the bounding sphere about the centre, a little enlarged for rounding */
    const double rb = g.r_bound * (1 + 1e-9) / R, miss_below = rb < 1 ? 1 - rb * rb : 0;
    const int nt = o->threads > 1 ? o->threads : 1;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    int comp = 0;
    for (int s = 0; s < p->nsp; s++)
        for (int k = 0; k < p->sp[s].ncomp; k++, comp++) {
            const mote_ch_species *sp = &p->sp[s];
            const double gamma = 4 * MOTE_CH_PI * R * R * sp->n[k] *
                                 sqrt(sp->kT[k] * MOTE_CH_E / (2 * MOTE_CH_PI * sp->m));
            r->weight[s][k] = sp->Z * MOTE_CH_E * gamma / (double)o->particles;
            const uint64_t nblocks = (o->particles + BLOCK - 1) / BLOCK;
            uint64_t hits = 0, back = 0;
            uint64_t *tally = r->tri_hits + (size_t)comp * ntri * 2;
            /* each thread tallies into its own copy; integer sums merge exactly */
            uint64_t *priv = nt > 1 ? calloc((size_t)nt * ntri * 2, sizeof *priv) : NULL;
            if (nt > 1 && !priv) {
                mote_ch_result_free(r);
                return mote_fail(err, MOTE_ENOMEM, "run: out of memory for %d threads' tallies",
                                 nt);
            }
#pragma omp parallel num_threads(nt) if (nt > 1) reduction(+ : hits, back)
            {
#ifdef _OPENMP
                const int tid = omp_get_thread_num();
#else
                const int tid = 0;
#endif
                uint64_t *mine = nt > 1 ? priv + (size_t)tid * ntri * 2 : tally;
#pragma omp for schedule(dynamic, 1)
                for (uint64_t blk = 0; blk < nblocks; blk++) {
                    const uint64_t h1 = (blk + 1) * BLOCK < o->particles ? (blk + 1) * BLOCK
                                                                           : o->particles;
                    for (uint64_t h = blk * BLOCK; h < h1; h++) {
                        double u[4];
                        uniforms4(key, h, (uint32_t)comp, u);
                        /* the direction's cos^2(theta) is uniform (the cosine law): a path
                         * with cos^2 < 1 - (R_bound/R)^2 passes the body's bounding sphere */
                        if (u[2] < miss_below)
                            continue;
                        /* the position: z uniform in [-1, 1], azimuth uniform (spec 5.2) */
                        const double z = 2 * u[0] - 1, rho = sqrt(fmax(0, 1 - z * z));
                        const double ph = 2 * MOTE_CH_PI * u[1];
                        const double nrm[3] = {rho * cos(ph), rho * sin(ph), z};
                        /* the direction: cos(theta) = sqrt(u2) about the inward normal -nrm */
                        const double ct = sqrt(u[2]), st = sqrt(fmax(0, 1 - u[2]));
                        const double ps = 2 * MOTE_CH_PI * u[3];
                        double e1[3], e2[3]; /* a basis perpendicular to nrm */
                        if (fabs(nrm[2]) < 0.9) {
                            const double l = sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1]);
                            e1[0] = -nrm[1] / l;
                            e1[1] = nrm[0] / l;
                            e1[2] = 0;
                        } else {
                            const double l = sqrt(nrm[1] * nrm[1] + nrm[2] * nrm[2]);
                            e1[0] = 0;
                            e1[1] = -nrm[2] / l;
                            e1[2] = nrm[1] / l;
                        }
                        e2[0] = nrm[1] * e1[2] - nrm[2] * e1[1];
                        e2[1] = nrm[2] * e1[0] - nrm[0] * e1[2];
                        e2[2] = nrm[0] * e1[1] - nrm[1] * e1[0];
                        double org[3], dir[3];
                        for (int a = 0; a < 3; a++) {
                            org[a] = g.centre[a] + R * nrm[a];
                            dir[a] = -ct * nrm[a] + st * (cos(ps) * e1[a] + sin(ps) * e2[a]);
                        }
                        int side;
                        double dist;
                        const long tri = mote_ch_trace(t, org, dir, tmin, &side, &dist);
                        if (tri < 0)
                            continue;
                        hits++;
                        if (side && (b->sphere || b->closed[tri]))
                            back++;
                        mine[2 * (size_t)tri + (size_t)side]++;
                    }
                }
            }
            for (int th = 0; priv && th < nt; th++)
                for (size_t q = 0; q < (size_t)ntri * 2; q++)
                    tally[q] += priv[(size_t)th * ntri * 2 + q];
            free(priv);
            r->hits[s][k] = hits;
            r->backface_hits += back;
        }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    r->seconds = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    r->traces_per_s = r->seconds > 0 ? (double)comp * (double)o->particles / r->seconds : 0;
    for (int s = 0; s < p->nsp; s++) {
        double var = 0;
        for (int k = 0; k < p->sp[s].ncomp; k++) {
            const double w = r->weight[s][k], h = (double)r->hits[s][k], N = (double)o->particles;
            r->current[s] += w * h;
            var += w * w * h * (1 - h / N);
        }
        r->sigma[s] = sqrt(var);
    }
    return MOTE_OK;
}
