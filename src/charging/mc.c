/* mc.c: the Monte Carlo current estimate of the charging model with straight paths (spec 5).
 * For each Maxwellian component k, N histories start on the injection sphere of radius R about
 * the body's centre: the position uniform on the sphere, the direction by the cosine law about
 * the inward normal (the inward flux of an isotropic Maxwellian). Each carries the current
 * weight w_k = q Gamma_k / N with Gamma_k = 4 pi R^2 n_k sqrt(kT_k / (2 pi m)), and its first
 * hit (nearest, spec 5.5) is tallied per triangle and side. Without a field the path does not
 * depend on the speed, so none is drawn. Random numbers are Philox4x32-10 keyed by the seed with
 * the counter (history, component, draw): every history has its own stream, so the tallies
 * (integers) are the same for any number of threads; a straight history's first test draws
 * from SplitMix64 at the same counter (ch_uniform_cheap). */
#include "mote/loop.h"

#include "ch.h"

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

/* Four uniforms in (0, 1) (32 bits each, never 0 or 1) from one Philox block (block `draw` of
 * the history's stream). */
void ch_uniforms4(const uint32_t key[2], uint64_t history, uint32_t comp, uint32_t draw,
                  double u[4])
{
    const uint32_t ctr[4] = {(uint32_t)history, (uint32_t)(history >> 32), comp, draw};
    uint32_t w[4];
    mote_ch_philox(ctr, key, w);
    for (int j = 0; j < 4; j++)
        u[j] = ((double)w[j] + 0.5) * (1.0 / 4294967296.0);
}

/* One uniform in (0, 1) for the history's first test, from SplitMix64's output function
 * (Steele, Lea, Flood, OOPSLA 2014) at the position (key, component, history) of a stream of
 * its own: a few multiplications where a Philox block takes ten rounds, for the test that most
 * straight histories end at (they miss the bounding sphere). */
double ch_uniform_cheap(const uint32_t key[2], uint64_t history, uint32_t comp)
{
    uint64_t z = ((uint64_t)key[1] << 32 | key[0]) * 0xd1342543de82ef95u +
                 ((uint64_t)comp << 56 ^ history) * 0x9e3779b97f4a7c15u;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    z ^= z >> 31;
    return ((double)(z >> 11) + 0.5) * 0x1.0p-53;
}

/* ---- drift (spec 5.4) ----------------------------------------------------------------------- */

static double phi_n(double x) { return exp(-0.5 * x * x) / sqrt(2 * MOTE_CH_PI); }
static double Phi_n(double x) { return 0.5 * erfc(-x / sqrt(2.0)); }

/* The mean over the sphere of the local inward flux per unit density, for a drift of speed ud
 * and thermal speed sigma: sigma/(2 s0) ((s0^2 + 1) erf(s0/sqrt 2) + 2 s0 phi(s0))/2, s0 = ud /
 * sigma; sigma / sqrt(2 pi) without drift. */
static double mean_flux(double ud, double sigma)
{
    const double s0 = ud / sigma;
    if (s0 < 1e-8)
        return sigma / sqrt(2 * MOTE_CH_PI);
    return sigma / (2 * s0) * ((s0 * s0 + 1) * erf(s0 / sqrt(2.0)) + 2 * s0 * phi_n(s0)) / 2;
}

/* A normal speed w > 0 with density proportional to w N(w; un, sigma), by inverting its
 * distribution function at the uniform x: Newton steps kept inside a shrinking bracket. */
static double drift_normal_speed(double un, double sigma, double x)
{
    const double s = un / sigma, Z = sigma * phi_n(s) + un * Phi_n(s);
    const double F0 = un * Phi_n(-s) - sigma * phi_n(-s);
    double lo = 0, hi = fmax(un, 0) + 12 * sigma;
    double w = fmax(un, 0) + sigma; /* a start near the bulk */
    for (int it = 0; it < 100; it++) {
        const double z = (w - un) / sigma;
        const double F = (un * Phi_n(z) - sigma * phi_n(z) - F0) / Z - x;
        if (F < 0)
            lo = w;
        else
            hi = w;
        const double f = w * phi_n(z) / (sigma * Z); /* the density */
        double next = f > 0 ? w - F / f : 0.5 * (lo + hi);
        if (!(next > lo && next < hi))
            next = 0.5 * (lo + hi);
        if (fabs(next - w) <= 1e-13 * (sigma + fabs(un)) || hi - lo <= 1e-13 * (sigma + fabs(un)))
            return next;
        w = next;
    }
    return w;
}

/* Two unit vectors e1, e2 perpendicular to the unit vector n and to each other, (e1, e2, n)
 * right-handed, without a branch on n and with one division (Duff, Burgess, Christensen, Hery,
 * Kensler, Liani and Villemin, "Building an orthonormal basis, revisited", JCGT 6(1), 2017). */
static void perp_basis(const double n[3], double e1[3], double e2[3])
{
    const double sg = copysign(1.0, n[2]), a = -1 / (sg + n[2]), b = n[0] * n[1] * a;
    e1[0] = 1 + sg * n[0] * n[0] * a;
    e1[1] = sg * b;
    e1[2] = -sg * n[0];
    e2[0] = b;
    e2[1] = sg + n[1] * n[1] * a;
    e2[2] = -n[1];
}

/* cos(2 pi u) and sin(2 pi u) for u in [0, 1) with a few bits (a 32-bit draw): u in quarter
 * turns, 4 u = q + f with q whole and |f| <= 1/2 exact, then the Taylor series of cos and sin
 * at theta = f pi / 2 (|theta| <= pi / 4: terms to theta^18 and theta^17, the next below 1e-19)
 * and the quarter turns by swaps. Within 1e-15 of libm's cos(2 pi u) (test_charging; libm's
 * own argument 2 pi u is rounded by that much), without its range reduction. */
static inline void cossin_turn(double u, double *c, double *s)
{
    /* the coefficients of theta^(2k) in cos and of theta^(2k+1) / theta in sin, k = 0, 1, ... */
    static const double kc[10] = {1,
                                  -1.0 / 2,
                                  1.0 / 24,
                                  -1.0 / 720,
                                  1.0 / 40320,
                                  -1.0 / 3628800,
                                  1.0 / 479001600,
                                  -1.0 / 87178291200,
                                  1.0 / 20922789888000,
                                  -1.0 / 6402373705728000};
    static const double ks[9] = {1,
                                 -1.0 / 6,
                                 1.0 / 120,
                                 -1.0 / 5040,
                                 1.0 / 362880,
                                 -1.0 / 39916800,
                                 1.0 / 6227020800,
                                 -1.0 / 1307674368000,
                                 1.0 / 355687428096000};
    const double x = 4 * u;
    const int qn = (int)(x + 0.5); /* x >= 0: the nearest whole number (no libm call) */
    const double th = (x - qn) * (MOTE_CH_PI / 2), t2 = th * th;
    /* Estrin's scheme in t2 (pairs, then pairs of pairs): a chain of 5 operations, not 18 */
    const double t4 = t2 * t2, t8 = t4 * t4, t16 = t8 * t8;
    const double cs = ((kc[0] + kc[1] * t2) + (kc[2] + kc[3] * t2) * t4) +
                      ((kc[4] + kc[5] * t2) + (kc[6] + kc[7] * t2) * t4) * t8 +
                      (kc[8] + kc[9] * t2) * t16;
    const double sn = ((ks[0] + ks[1] * t2) + (ks[2] + ks[3] * t2) * t4) +
                      ((ks[4] + ks[5] * t2) + (ks[6] + ks[7] * t2) * t4) * t8 + ks[8] * t16;
    /* turned by q quarter turns without a branch (q is as random as u): (cs, sn) -> (-sn, cs) */
    static const double sc[4] = {1, -1, -1, 1}, ss[4] = {1, 1, -1, -1};
    const int qi = qn & 3;
    /* the swap by bit masks (an array indexed by q waits on a store, a branch mispredicts) */
    const double snt = sn * th;
    uint64_t bc, bs;
    memcpy(&bc, &cs, sizeof bc);
    memcpy(&bs, &snt, sizeof bs);
    const uint64_t m = (uint64_t)0 - (uint64_t)(qi & 1), rc = (bc & ~m) | (bs & m),
                   rs = (bs & ~m) | (bc & m);
    double vc, vs;
    memcpy(&vc, &rc, sizeof vc);
    memcpy(&vs, &rs, sizeof vs);
    *c = sc[qi] * vc;
    *s = ss[qi] * vs;
}

void ch_cossin_turn(double u, double *c, double *s) { cossin_turn(u, c, s); }

/* The injection point and direction from four uniforms (spec 5.2): nrm the outward unit
 * normal of the point on the sphere (z = 2 u0 - 1 uniform, azimuth 2 pi u1), dir the unit
 * direction, cos(theta) = sqrt(u2) about the inward normal (the cosine law), azimuth 2 pi u3. */
void ch_inject_dir(const double u[4], double nrm[3], double dir[3])
{
    const double z = 2 * u[0] - 1, r2 = 1 - z * z, rho = sqrt(r2 > 0 ? r2 : 0);
    double cp, sp, cq, sq;
    cossin_turn(u[1], &cp, &sp);
    nrm[0] = rho * cp;
    nrm[1] = rho * sp;
    nrm[2] = z;
    const double ct = sqrt(u[2]), st = sqrt(u[2] < 1 ? 1 - u[2] : 0);
    cossin_turn(u[3], &cq, &sq);
    double e1[3], e2[3]; /* a basis perpendicular to nrm */
    perp_basis(nrm, e1, e2);
    for (int a = 0; a < 3; a++)
        dir[a] = -ct * nrm[a] + st * (cq * e1[a] + sq * e2[a]);
}

/* The kinetic energy at injection in units of kT (spec 6.2) from four uniforms: Gamma(2, 1)
 * when repelled or uncharged (chi >= 0); attracted, |chi| plus Gamma(2, 1) with probability
 * 1/(1 + |chi|), else plus Exp(1). */
double ch_inject_energy(const double e[4], double chi)
{
    double K = -log(e[0] * e[1]);
    if (chi < 0) {
        if (e[2] >= 1 / (1 - chi))
            K = -log(e[0]);
        K += -chi;
    }
    return K;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* |cos| of the angle between a straight path and the normal where it hits (the exact sphere:
 * the radius at the hit point) */
static double hit_cos(const mote_ch_body *b, long tri, const double org[3], const double dir[3],
                      double dist)
{
    if (!b->sphere)
        return fabs(dot3(dir, b->nrm[tri]));
    double p[3];
    for (int a = 0; a < 3; a++)
        p[a] = org[a] + dist * dir[a] - b->sphere_c[a];
    return fabs(dot3(dir, p)) / b->sphere_r;
}

void mote_ch_result_free(mote_ch_result *r)
{
    free(r->tri_hits);
    free(r->tri_see);
    free(r->tri_photo);
    free(r->tri_sunlit);
    free(r->patch_I);
    memset(r, 0, sizeof *r);
}

enum { BLOCK = 4096 };

/* Differential charging (spec 6.10): score one hit of charge Z e and impact energy E (eV) in
 * the body's field on a patch's row: [ndv + 1] the collected counts as a difference array over
 * the grid dv (collected where E - Z dv > 0), then [ndv] its emission (mat: NULL for none) at
 * each collected dv, escaping by the patch's potential U_s + dv, in fixed point. */
static void patch_score(ch_i128 *row, const mote_ch_run_opts *o, int Z,
                        const mote_ch_material *mat, double U_s, double E, double c)
{
    const int n = o->ndv;
    const double *dv = o->dv, lim = E / Z;
    int a = 0, b = n, lo = 0, hi = n;
    while (a < b) { /* the first dv past the limit: > lim (electrons), >= lim (ions) */
        const int mid = (a + b) / 2;
        if (Z < 0 ? dv[mid] > lim : dv[mid] >= lim)
            b = mid;
        else
            a = mid + 1;
    }
    if (Z < 0)
        lo = a;
    else
        hi = a;
    row[lo] += 1;
    row[hi] -= 1;
    if (!mat)
        return;
    ch_i128 *em = row + n + 1;
    ch_yields y; /* (the material's constants once a hit, then one log a grid point) */
    ch_yields_prepare(mat, &y);
    const int bs = o->backscatter && Z < 0 && mat->Z > 0;
    for (int g = lo; g < hi; g++) {
        const double e = E - Z * dv[g], V = U_s + dv[g], ek = e / 1000;
        const double lnE = Z < 0 ? log(ek) : 0;
        double sc = (Z < 0 ? ch_see_ln(&y, ek, lnE, c) : mote_ch_ion_yield(mat, ek)) *
                    mote_ch_escape(V, mat->kT_s);
        if (bs)
            sc += ch_bs_ln(&y, ek, lnE, c) * mote_ch_backscatter_escape(V, e);
        em[g] += (ch_i128)llround(sc * FIX);
    }
}

/* ---- the run, in parts -------------------------------------------------------------------- */

/* The box injector (spec 5.2): the body's bounding box grown by the margin, its faces' areas
 * cumulated (fcum[6] the whole). */
static int box_injector(const mote_ch_body *b, const mote_ch_run_opts *o, double blo[3],
                        double bhi[3], double fcum[7], mote_err *err)
{
    if (o->field && o->potential != 0)
        return mote_fail(err, MOTE_EINVAL, "run: the box injector is for straight paths: a "
                         "particle leaving a box in a central field can come back (spec 5.2)");
    for (int a = 0; a < 3; a++) {
        blo[a] = INFINITY;
        bhi[a] = -INFINITY;
    }
    if (b->sphere)
        for (int a = 0; a < 3; a++) {
            blo[a] = b->sphere_c[a] - b->sphere_r;
            bhi[a] = b->sphere_c[a] + b->sphere_r;
        }
    for (uint32_t i = 0; i < (b->sphere ? 0 : b->ntri); i++)
        for (int j = 0; j < 3; j++)
            for (int a = 0; a < 3; a++) {
                blo[a] = fmin(blo[a], b->v[i][j][a]);
                bhi[a] = fmax(bhi[a], b->v[i][j][a]);
            }
    double diag = 0;
    for (int a = 0; a < 3; a++)
        diag += (bhi[a] - blo[a]) * (bhi[a] - blo[a]);
    const double pad = o->margin_m > 0 ? o->margin_m : o->margin * sqrt(diag);
    if (!(pad > 0))
        return mote_fail(err, MOTE_EINVAL, "run: the box injector needs a margin > 0");
    if (!(pad <= MOTE_CH_SIZE_MAX))
        return mote_fail(err, MOTE_EINVAL, "run: the box injector's margin %g m is beyond %g m, "
                         "where the rays' coordinates no longer trace (Embree works in single "
                         "precision)", pad, MOTE_CH_SIZE_MAX);
    for (int a = 0; a < 3; a++) {
        blo[a] -= pad;
        bhi[a] += pad;
    }
    fcum[0] = 0;
    for (int f = 0; f < 6; f++) {
        const int ax = f / 2, u = (ax + 1) % 3, w = (ax + 2) % 3;
        fcum[f + 1] = fcum[f] + (bhi[u] - blo[u]) * (bhi[w] - blo[w]);
    }
    return MOTE_OK;
}

/* What a history needs: the run's constants and its component's. */
typedef struct {
    const mote_ch_body *b;
    const mote_ch_tracer *t;
    const mote_ch_run_opts *o;
    const mote_ch_species *sp;
    int k;
    uint32_t comp, key[2];
    double R, centre[3], blo[3], bhi[3], fcum[7];
    int field, curved, box, drift, see, patchy;
    double chi, sigma, fmax_d, dq, ra2, phi_g, vscale, U_s, tmin, miss_below;
    ch_path pk;    /* the component's charge to mass */
    size_t nsee, pw;
    /* the solved field (field solved): the emitted electrons followed from the surface in it,
     * each secondary and backscattered electron scored only when it escapes */
    int traced;
    ch_path pe;    /* an electron's path constants */
} mc_comp;

/* A thread's tallies in a block: the hits logged (tallied when the block ends), the scores of
 * the emission and the patches (fixed point), the counts. */
typedef struct {
    size_t *hitlog, nlog;
    ch_i128 *msee, *mpat;
    uint64_t hits, back, lost, steps;
    double eerr;
} mc_tally;

/* An electron of energy E (eV) emitted at the hit's point, from the side it was hit on, in a
 * direction by the cosine law (draws u[0], u[1]), followed in the solved field: 1 when it
 * escapes (out through the injection sphere), 0 when it lands on the body (re-collected) or is
 * still going after max_steps. */
static int emitted_escapes(const mc_comp *x, const ch_hit *hit, double E, const double u[2])
{
    const mote_ch_body *b = x->b;
    const double sg = hit->side ? -1 : 1;
    const double n[3] = {sg * b->nrm[hit->tri][0], sg * b->nrm[hit->tri][1],
                         sg * b->nrm[hit->tri][2]};
    double e1[3], e2[3], cs, sn;
    perp_basis(n, e1, e2);
    ch_cossin_turn(u[1], &cs, &sn);
    const double ct = sqrt(u[0]), st = sqrt(fmax(0, 1 - u[0]));
    const double speed = sqrt(2 * E * MOTE_CH_E / MOTE_CH_ME);
    double r0[3], v0[3];
    for (int a = 0; a < 3; a++) { /* (off the surface by twice the chords' overlap) */
        r0[a] = hit->x[a] + 2 * x->pe.overlap * n[a];
        v0[a] = speed * (ct * n[a] + st * (cs * e1[a] + sn * e2[a]));
    }
    ch_hit out;
    ch_path_follow(&x->pe, r0, v0, &out);
    return out.tri == -1;
}

/* The photoelectrons of triangle tri's side, histories first .. first + n - 1 of the photo
 * stream (component CH_PHOTO_COMP): each from a point uniform on the triangle (draw 0), in a
 * direction by the cosine law, with the energy of a Maxwellian flux at kT_ph, Gamma(2, kT_ph)
 * (draw 1); the share that escapes. */
#define CH_PHOTO_COMP 0x70686f74u
static double photo_escapes(void *vx, uint32_t tri, int side, uint64_t first, uint64_t n,
                            double kT_ph)
{
    const mc_comp *x = vx;
    const mote_ch_body *b = x->b;
    uint64_t out = 0;
    for (uint64_t h = first; h < first + n; h++) {
        double u[4], w[4];
        ch_uniforms4(x->key, h, CH_PHOTO_COMP, 0, u);
        ch_uniforms4(x->key, h, CH_PHOTO_COMP, 1, w);
        double a = u[0], c = u[1];
        if (a + c > 1) { /* (the other half of the parallelogram, folded back) */
            a = 1 - a;
            c = 1 - c;
        }
        ch_hit hit = {.tri = tri, .side = side};
        for (int k = 0; k < 3; k++)
            hit.x[k] = b->v[tri][0][k] + a * (b->v[tri][1][k] - b->v[tri][0][k]) +
                       c * (b->v[tri][2][k] - b->v[tri][0][k]) - x->centre[k];
        const double dir[2] = {w[0], w[1]};
        out += (uint64_t)emitted_escapes(x, &hit, -kT_ph * log(u[2] * u[3]), dir);
    }
    return (double)out / (double)n;
}

/* The emission (spec 6.7) and the patches (6.10) of a hit of energy e (eV) at |cos| c; with
 * the solved field (hit given) the emitted electrons followed, each yield scored when its
 * electron escapes (draws 100 and 101 of history h) instead of the escape fractions. */
static void score(const mc_comp *x, mc_tally *y, long tri, int side, double e, double c,
                  uint64_t h, const ch_hit *hit)
{
    const mote_ch_run_opts *o = x->o;
    if (x->see) {
        const mote_ch_material *mat = o->tri_material[tri];
        const int traced = x->traced && hit;
        double u[4] = {0, 0, 0, 0}, w[4] = {0, 0, 0, 0};
        if (traced) {
            ch_uniforms4(x->key, h, x->comp, 100, u);
            ch_uniforms4(x->key, h, x->comp, 101, w);
        }
        const double yield = x->sp->Z < 0 ? mote_ch_see_yield(mat, e / 1000, c)
                                          : mote_ch_ion_yield(mat, e / 1000);
        double sc = 0;
        if (!traced) /* the escape fraction of a Maxwellian flux at kT_s */
            sc = yield * mote_ch_escape(x->U_s, mat->kT_s);
        else if (yield > 0) /* one secondary, its energy Gamma(2, kT_s) (the flux's) */
            sc = yield * emitted_escapes(x, hit, -mat->kT_s * log(u[2] * u[3]), u);
        if (o->backscatter && x->sp->Z < 0 && mat->Z > 0) {
            const double bs = mote_ch_backscatter_yield(mat, e / 1000, c);
            if (!traced)
                sc += bs * mote_ch_backscatter_escape(x->U_s, e);
            else if (bs > 0) /* its energy uniform on (0, e) */
                sc += bs * emitted_escapes(x, hit, w[2] * e, w);
        }
        const ch_i128 q = (ch_i128)llround(sc * FIX);
        y->msee[2 * (size_t)tri + (size_t)side] += q;
        y->msee[x->nsee - 2] += q;
        y->msee[x->nsee - 1] += (ch_i128)llround(sc * sc * FIX);
    }
    if (x->patchy && o->tri_patch[tri] >= 0)
        patch_score(y->mpat + (size_t)o->tri_patch[tri] * x->pw, o, x->sp->Z,
                    x->see ? o->tri_material[tri] : NULL, x->U_s, e, c);
}

/* A straight path's hit scored: its energy drawn from the flux's kinetic energy law, Gamma(2,
 * kT) (eV), and its angle. */
static void straight_score(const mc_comp *x, mc_tally *y, uint64_t h, long tri, int side,
                           const double org[3], const double dir[3], double dist)
{
    double e[4];
    ch_uniforms4(x->key, h, x->comp, 7, e);
    score(x, y, tri, side, -x->sp->kT[x->k] * log(e[0] * e[1]),
          hit_cos(x->b, tri, org, dir, dist), h, NULL);
}

/* A straight path's hit: counted, logged, scored (the energy and the angle only when they are
 * used). */
static void straight_hit(const mc_comp *x, mc_tally *y, uint64_t h, long tri, int side,
                         const double org[3], const double dir[3], double dist)
{
    y->hits++;
    if (side && (x->b->sphere || x->b->closed[tri]))
        y->back++;
    y->hitlog[y->nlog++] = 2 * (size_t)tri + (size_t)side;
    if (x->see || x->patchy)
        straight_score(x, y, h, tri, side, org, dir, dist);
}

/* Straight from the sphere: the direction's cos^2(theta) is uniform (the cosine law), and a path
 * with cos^2 < 1 - (R_bound / R)^2 passes the body's bounding sphere; that test comes first,
 * from its own cheap draw, and only paths that may hit draw the rest, gathered TB at a time so
 * that their draws, and then their traces, follow one another (each history's result is its
 * own: the same tallies in any grouping). */
static void block_straight(const mc_comp *x, mc_tally *y, uint64_t h0, uint64_t h1)
{
    /* (the constants and the counts in locals: the loop is the run's hottest) */
    const uint32_t comp = x->comp;
    const double miss_below = x->miss_below, R = x->R, tmin = x->tmin;
    const double c0 = x->centre[0], c1 = x->centre[1], c2c = x->centre[2];
    const mote_ch_body *b = x->b;
    const int scored = x->see || x->patchy;
    size_t *hitlog = y->hitlog, nlog = y->nlog;
    uint64_t hits = 0, back = 0;
    while (h0 < h1) {
        enum { TB = CH_TRACE_MANY };
        uint64_t th[TB];
        double tc2[TB], org[TB][3], dir[TB][3], tdist[TB];
        long ttri[TB];
        int tside[TB];
        int nb = 0;
        for (; h0 < h1 && nb < TB; h0++) {
            const double c2 = ch_uniform_cheap(x->key, h0, comp);
            if (c2 >= miss_below) {
                th[nb] = h0;
                tc2[nb++] = c2;
            }
        }
        for (int j = 0; j < nb; j++) {
            double u[4], nrm[3];
            ch_uniforms4(x->key, th[j], comp, 0, u);
            u[2] = tc2[j];
            ch_inject_dir(u, nrm, dir[j]);
            org[j][0] = c0 + R * nrm[0];
            org[j][1] = c1 + R * nrm[1];
            org[j][2] = c2c + R * nrm[2];
        }
        ch_trace_many(x->t, nb, (const double(*)[3])org, (const double(*)[3])dir, tmin, ttri,
                      tside, tdist);
        for (int j = 0; j < nb; j++) {
            const long tri = ttri[j];
            if (tri < 0)
                continue;
            const int side = tside[j];
            hits++;
            if (side && (b->sphere || b->closed[tri]))
                back++;
            hitlog[nlog++] = 2 * (size_t)tri + (size_t)side;
            if (scored) {
                y->nlog = nlog;
                straight_score(x, y, th[j], tri, side, org[j], dir[j], tdist[j]);
            }
        }
    }
    y->nlog = nlog;
    y->hits += hits;
    y->back += back;
}

/* In the body's field (spec 6.2, 6.3): the kinetic energy at injection, then the path followed
 * to a mesh, or the OML test of the exact sphere. */
static void history_field(const mc_comp *x, mc_tally *y, uint64_t h, const double u[4])
{
    const mote_ch_species *sp = x->sp;
    double e[4];
    ch_uniforms4(x->key, h, x->comp, 1, e);
    const double K = ch_inject_energy(e, x->chi); /* K / kT */
    if (x->curved) { /* a mesh: follow the path (spec 6.3) */
        double nrm[3], dir[3], r0[3], v0[3];
        ch_inject_dir(u, nrm, dir);
        const double speed = x->vscale * sqrt(K);
        for (int a = 0; a < 3; a++) {
            r0[a] = x->R * nrm[a];
            v0[a] = speed * dir[a];
        }
        ch_hit hit;
        ch_path_follow(&x->pk, r0, v0, &hit);
        y->steps += (uint64_t)hit.steps;
        y->eerr = fmax(y->eerr, hit.eerr);
        if (hit.tri == -2)
            y->lost++;
        if (hit.tri < 0)
            return;
        y->hits++;
        if (hit.side && x->b->closed[hit.tri])
            y->back++;
        y->hitlog[y->nlog++] = 2 * (size_t)hit.tri + (size_t)hit.side;
        if (x->see || x->patchy)
            score(x, y, hit.tri, hit.side, 0.5 * sp->m * hit.v2 / MOTE_CH_E,
                  fabs(dot3(hit.dir, x->b->nrm[hit.tri])), h, &hit);
        return;
    }
    /* sin^2(theta) = 1 - u2 by the cosine law */
    if (K + x->dq >= K * (1 - u[2]) * x->ra2) {
        y->hits++;
        y->hitlog[y->nlog++] = 0;
        /* the impact angle: L kept, sin^2 = K sin0^2 (R/a)^2 / (K + dq) */
        const double s2 = K + x->dq > 0 ? K * (1 - u[2]) * x->ra2 / (K + x->dq) : 0;
        if (x->see || x->patchy)
            score(x, y, 0, 0, sp->kT[x->k] * K + sp->Z * (x->phi_g - x->o->potential),
                  sqrt(fmax(0, 1 - s2)), h, NULL);
    }
}

/* From the box injector: a face by area, a point on it, the cosine law. */
static void history_box(const mc_comp *x, mc_tally *y, uint64_t h, const double u[4])
{
    double e[4];
    ch_uniforms4(x->key, h, x->comp, 1, e);
    const double *fcum = x->fcum, *blo = x->blo, *bhi = x->bhi;
    int f = 0;
    while (f < 5 && u[0] * fcum[6] >= fcum[f + 1])
        f++;
    const int ax = f / 2, ua = (ax + 1) % 3, wa = (ax + 2) % 3;
    const double inward = f % 2 ? -1 : 1; /* lo face: +axis is inward */
    double org[3], dir[3];
    org[ax] = f % 2 ? bhi[ax] : blo[ax];
    org[ua] = blo[ua] + u[1] * (bhi[ua] - blo[ua]);
    org[wa] = blo[wa] + e[0] * (bhi[wa] - blo[wa]);
    const double ct = sqrt(u[2]), st = sqrt(fmax(0, 1 - u[2]));
    const double ps = 2 * MOTE_CH_PI * u[3];
    dir[ax] = inward * ct;
    dir[ua] = st * cos(ps);
    dir[wa] = st * sin(ps);
    int side;
    double dist;
    const long tri = mote_ch_trace(x->t, org, dir, x->tmin, &side, &dist);
    if (tri >= 0)
        straight_hit(x, y, h, tri, side, org, dir, dist);
}

/* A drifting plasma (spec 5.4): points by rejection on the local flux, then the velocity. */
static void history_drift(const mc_comp *x, mc_tally *y, uint64_t h)
{
    const mote_ch_species *sp = x->sp;
    const double sigma = x->sigma;
    double nrm[3], un = 0;
    uint32_t draw = 1;
    for (;; draw++) {
        double e[4];
        ch_uniforms4(x->key, h, x->comp, draw, e);
        const double z = 2 * e[0] - 1, rho = sqrt(fmax(0, 1 - z * z));
        const double ph = 2 * MOTE_CH_PI * e[1];
        nrm[0] = rho * cos(ph);
        nrm[1] = rho * sin(ph);
        nrm[2] = z;
        un = -(sp->drift[0] * nrm[0] + sp->drift[1] * nrm[1] +
               sp->drift[2] * nrm[2]); /* along the inward normal */
        const double fl = sigma * phi_n(un / sigma) + un * Phi_n(un / sigma);
        if (e[2] * x->fmax_d <= fl || draw > 1000)
            break;
    }
    /* the velocity: normal part from w N(w; un, sigma), tangential ones N(u_t, sigma) */
    double e1[3], e2[3];
    perp_basis(nrm, e1, e2);
    double e[4];
    ch_uniforms4(x->key, h, x->comp, draw + 1, e);
    const double w = drift_normal_speed(un, sigma, e[0]);
    double ut1 = 0, ut2 = 0;
    for (int a = 0; a < 3; a++) {
        ut1 += sp->drift[a] * e1[a];
        ut2 += sp->drift[a] * e2[a];
    }
    /* two normals by Box and Muller */
    const double rr = sigma * sqrt(-2 * log(e[1]));
    const double v1 = ut1 + rr * cos(2 * MOTE_CH_PI * e[2]);
    const double v2 = ut2 + rr * sin(2 * MOTE_CH_PI * e[2]);
    double org[3], dir[3], len = 0;
    for (int a = 0; a < 3; a++) {
        org[a] = x->centre[a] + x->R * nrm[a];
        dir[a] = -w * nrm[a] + v1 * e1[a] + v2 * e2[a];
        len += dir[a] * dir[a];
    }
    len = sqrt(len);
    for (int a = 0; a < 3; a++)
        dir[a] /= len;
    int side;
    double dist;
    const long tri = mote_ch_trace(x->t, org, dir, x->tmin, &side, &dist);
    if (tri < 0)
        return;
    y->hits++;
    if (side && (x->b->sphere || x->b->closed[tri]))
        y->back++;
    y->hitlog[y->nlog++] = 2 * (size_t)tri + (size_t)side;
    if (x->see || x->patchy)
        score(x, y, tri, side, 0.5 * sp->m * len * len / MOTE_CH_E,
              hit_cos(x->b, tri, org, dir, dist), h, NULL);
}

/* The histories h0 .. h1 - 1 of a block. */
static void run_block(const mc_comp *x, mc_tally *y, uint64_t h0, uint64_t h1)
{
    if (!x->field && !x->box && !x->drift) {
        block_straight(x, y, h0, h1);
        return;
    }
    if (x->drift) { /* (its own draws: none at draw 0) */
        for (uint64_t h = h0; h < h1; h++)
            history_drift(x, y, h);
        return;
    }
    for (uint64_t h = h0; h < h1; h++) {
        double u[4];
        ch_uniforms4(x->key, h, x->comp, 0, u);
        if (x->field)
            history_field(x, y, h, u);
        else
            history_box(x, y, h, u);
    }
}

/* The run's shared state: its constants, the progress and the stop. */
typedef struct {
    const mote_ch_plasma *p;
    const mote_ch_body *b;
    const mote_ch_run_opts *o;
    mote_ch_result *r;
    mc_comp base;          /* the run's part of every component's constants */
    ch_path path;
    double a_f, gamma_area;
    uint32_t ntri;
    int nt, mrank, msize;
    size_t npw;
    mote_loop *loop;
    int asks;              /* the progress or the interrupt want to hear of blocks done */
    int stop;              /* the context's interrupt hook asked to stop (Python's Ctrl-C) */
    uint64_t blocks_done;
    uint64_t bsz; /* histories a block (BLOCK, fewer in a short run: every thread gets blocks) */
    /* the field's scale (V): the body's potential, or with conductors at their own potentials
     * the frame's (the largest in magnitude when it is 0); their tree, per volt of it, and each
     * triangle's potential per volt */
    double Uf;
    mote_ch_ftree *own_tree;
    double *tri_phi;
    double fc_coef[MOTE_CH_BEM_MAX_CONDUCTORS]; /* the cache's conductors per volt of Uf */
} mc_run_state;

/* The end of a component: the threads' tallies merged (integers: any order gives the same
 * sums), then the ranks'; the hits, emission and patch currents into r. Frees the scratch. */
static void component_end(mc_run_state *st, const mc_comp *x, int s, int k, double gamma,
                          ch_i128 *psee, ch_i128 *ppat, uint64_t *priv, uint64_t cnt[4],
                          double eerr)
{
    const mote_ch_run_opts *o = st->o;
    mote_ch_result *r = st->r;
    const int nt = st->nt;
    const uint32_t ntri = st->ntri;
    const size_t nsee = x->nsee, npw = st->npw;
    uint64_t *tally = r->tri_hits + (size_t)x->comp * ntri * 2;
    for (int th = 1; x->see && th < nt; th++)
        for (size_t q = 0; q < nsee; q++)
            psee[q] += psee[(size_t)th * nsee + q];
    for (int th = 0; priv && th < nt; th++)
        for (size_t q = 0; q < (size_t)ntri * 2; q++)
            tally[q] += priv[(size_t)th * ntri * 2 + q];
    free(priv);
    if (x->patchy) { /* (threads, then ranks) */
        for (int th = 1; th < nt; th++)
            for (size_t q = 0; q < npw; q++)
                ppat[q] += ppat[(size_t)th * npw + q];
        ch_mpi_sum128(o->solo, ppat, npw);
        const double w = r->weight[s][k];
        for (int pp = 0; pp < o->npatch; pp++) {
            const ch_i128 *row = ppat + (size_t)pp * x->pw;
            ch_i128 n = 0;
            for (int j = 0; j < o->ndv; j++) {
                n += row[j];
                r->patch_I[(size_t)pp * (size_t)o->ndv + (size_t)j] +=
                    w * (double)n + fabs(w) * (double)row[o->ndv + 1 + j] / FIX;
            }
        }
        free(ppat);
    }
    ch_mpi_merge(o->solo, tally, (size_t)ntri * 2, cnt, &eerr, psee, nsee);
    if (x->see) { /* the emitted current |w| sum, its error from the scores' spread */
        const double w = fabs(x->sp->Z * MOTE_CH_E * gamma / (double)o->particles);
        const double N = (double)o->particles;
        const double sum = (double)psee[nsee - 2] / FIX, sq = (double)psee[nsee - 1] / FIX;
        r->see[s][k] = w * sum;
        r->see_sigma[s][k] = w * sqrt(fmax(0, sq - sum * sum / N));
        for (size_t q = 0; q < (size_t)ntri * 2; q++)
            r->tri_see[(size_t)x->comp * ntri * 2 + q] = w * (double)psee[q] / FIX;
        free(psee);
    }
    r->hits[s][k] = cnt[0];
    r->backface_hits += cnt[1];
    r->lost += cnt[2];
    r->steps += cnt[3];
    r->max_energy_err = fmax(r->max_energy_err, eerr);
}

/* The emitted electrons' paths (the solved field only: traced). */
static void electron_paths(const mc_run_state *st, mc_comp *x)
{
    const double U = st->Uf;
    x->traced = st->path.tree != NULL;
    x->pe = st->path;
    x->pe.k = -MOTE_CH_E * U * st->a_f / MOTE_CH_ME;
    x->pe.qu = -MOTE_CH_E * U / MOTE_CH_ME;
    x->pe.emitted = 1;
}

/* Component k of species s (comp-th of the run): its histories, in blocks over the threads and
 * the ranks, tallied into r. */
static int run_component(mc_run_state *st, int s, int k, int comp, mote_err *err)
{
    const mote_ch_run_opts *o = st->o;
    mote_ch_result *r = st->r;
    const mote_ch_species *sp = &st->p->sp[s];
    const uint32_t ntri = st->ntri;
    const int nt = st->nt, field = st->base.field;
    mc_comp x = st->base;
    x.sp = sp;
    x.k = k;
    x.comp = (uint32_t)comp;
    /* chi = q phi_g / kT; the inward rate times g(chi) (spec 6.2, Liouville) */
    x.chi = sp->Z * x.phi_g / sp->kT[k];
    x.sigma = sqrt(sp->kT[k] * MOTE_CH_E / sp->m);
    const double ud = sqrt(sp->drift[0] * sp->drift[0] + sp->drift[1] * sp->drift[1] +
                           sp->drift[2] * sp->drift[2]);
    x.drift = ud > 0 && !field && !o->box;
    const double gamma = st->gamma_area * sp->n[k] *
                         (x.drift ? mean_flux(ud, x.sigma)
                                  : sqrt(sp->kT[k] * MOTE_CH_E / (2 * MOTE_CH_PI * sp->m))) *
                         (x.chi >= 0 ? exp(-x.chi) : 1 - x.chi);
    x.fmax_d = x.drift ? x.sigma * phi_n(ud / x.sigma) + ud * Phi_n(ud / x.sigma) : 0;
    /* the OML test (spec 6.3) in units of kT: hit when K + q phi_g - q U >= K sin^2 (R/a)^2, K
     * the kinetic energy at injection */
    x.dq = field ? sp->Z * (x.phi_g - st->Uf) / sp->kT[k] : 0;
    x.ra2 = field ? (x.R / st->a_f) * (x.R / st->a_f) : 0;
    r->weight[s][k] = sp->Z * MOTE_CH_E * gamma / (double)o->particles;
    const uint64_t bsz = st->bsz, nblocks = (o->particles + bsz - 1) / bsz;
    /* this MPI rank's blocks: rank, rank + size, ... */
    const uint64_t mrank = (uint64_t)st->mrank, msize = (uint64_t)st->msize;
    const uint64_t nmine = nblocks > mrank ? (nblocks - mrank + msize - 1) / msize : 0;
    uint64_t hits = 0, back = 0, lost = 0, steps = 0;
    double eerr = 0;
    x.pk = st->path;
    x.pk.k = sp->Z * MOTE_CH_E * st->Uf * st->a_f / sp->m;
    x.pk.qu = sp->Z * MOTE_CH_E * st->Uf / sp->m;
    electron_paths(st, &x);
    x.vscale = sqrt(2 * sp->kT[k] * MOTE_CH_E / sp->m); /* K = 1 kT */
    /* secondary emission by electron impacts (spec 6.7): each hit scores the expected yield
     * times the escape fraction; sums per block, added in block order (the same bits on any
     * number of threads); ions: when some material has ion-impact parameters */
    x.see = o->tri_material && sp->Z < 0;
    for (uint32_t i = 0; o->tri_material && sp->Z > 0 && !x.see && i < ntri; i++)
        x.see = o->tri_material[i]->ion_dmax > 0;
    x.U_s = field ? st->Uf : 0;
    /* scores in fixed point (2^-40) with 128-bit integers: sums that do not depend on the order
     * of addition (spec 5.6); per thread, per triangle and side, then the total and the sum of
     * squares */
    x.nsee = (size_t)ntri * 2 + 2;
    const size_t nsee = x.nsee, npw = st->npw;
    ch_i128 *psee = x.see ? calloc((size_t)nt * nsee, sizeof *psee) : NULL;
    ch_i128 *ppat = x.patchy ? calloc((size_t)nt * npw, sizeof *ppat) : NULL;
    uint64_t *tally = r->tri_hits + (size_t)comp * ntri * 2;
    /* each thread tallies into its own copy; integer sums merge exactly */
    uint64_t *priv = nt > 1 ? calloc((size_t)nt * ntri * 2, sizeof *priv) : NULL;
    if (x.see && !r->tri_see)
        r->tri_see = calloc((size_t)r->ncomp * ntri * 2, sizeof *r->tri_see);
    if ((x.see && (!psee || !r->tri_see)) || (x.patchy && !ppat) || (nt > 1 && !priv)) {
        free(priv);
        free(ppat);
        free(psee);
        return mote_fail(err, MOTE_ENOMEM, "run: out of memory for %d threads' tallies", nt);
    }
#pragma omp parallel num_threads(nt) if (nt > 1) reduction(+ : hits, back, lost, steps)          \
    reduction(max : eerr)
    {
#ifdef _OPENMP
        const int tid = omp_get_thread_num();
#else
        const int tid = 0;
#endif
        uint64_t *mine = nt > 1 ? priv + (size_t)tid * ntri * 2 : tally;
        /* a block's hits are logged as they come and tallied when it ends: the increments,
         * scattered over a large mesh's tallies, then wait on memory side by side instead of one
         * at a time between traversals */
        size_t hitlog[BLOCK];
        mc_tally y = {.hitlog = hitlog,
                      .msee = x.see ? psee + (size_t)tid * nsee : NULL,
                      .mpat = x.patchy ? ppat + (size_t)tid * npw : NULL};
#pragma omp for schedule(dynamic, 1)
        for (uint64_t jb = 0; jb < nmine; jb++) {
            int stopped;
#pragma omp atomic read
            stopped = st->stop;
            if (stopped) /* the rest of the blocks pass through */
                continue;
            const uint64_t blk = mrank + jb * msize;
            const uint64_t h1 = (blk + 1) * bsz < o->particles ? (blk + 1) * bsz : o->particles;
            run_block(&x, &y, blk * bsz, h1);
            for (size_t q = 0; q < y.nlog; q++)
                mine[hitlog[q]]++;
            y.nlog = 0;
            if (st->asks) {
                uint64_t done;
#pragma omp atomic capture
                done = ++st->blocks_done;
                if (tid == 0 && mote_loop_progress(st->loop, 0, done)) {
#pragma omp atomic write
                    st->stop = 1;
                }
            }
        }
        hits += y.hits;
        back += y.back;
        lost += y.lost;
        steps += y.steps;
        eerr = fmax(eerr, y.eerr);
    }
    if (st->stop) { /* (the interrupt hook is Python's: one process, no MPI partner) */
        free(priv);
        free(ppat);
        free(psee);
        return mote_interrupted(err, "run");
    }
    uint64_t cnt[4] = {hits, back, lost, steps};
    component_end(st, &x, s, k, gamma, psee, ppat, priv, cnt, eerr);
    return MOTE_OK;
}

/* The path of a history in the field of a charged mesh (spec 6.3): its constants and the
 * mesh's bounds. */
static ch_path path_of(const mote_ch_body *b, const mote_ch_tracer *t, const mote_ch_run_opts *o,
                       const mote_ch_geometry *g, double a_f, int curved)
{
    ch_path path = {.t = t,
                    .rf = a_f,
                    .R = o->r_gen,
                    .rj = fmax(g->r_bound, a_f) * (1 + 1e-6),
                    .eta = o->eta > 0 ? o->eta : 0.01,
                    .max_steps = o->max_steps > 0 ? o->max_steps : 100000,
                    .overlap = 1e-6 * (g->r_bound + fabs(g->centre[0]) + fabs(g->centre[1]) +
                                       fabs(g->centre[2]))};
    for (int a = 0; a < 3; a++) {
        path.c[a] = g->centre[a];
        path.lo[a] = INFINITY;
        path.hi[a] = -INFINITY;
    }
    for (uint32_t i = 0; curved && i < b->ntri; i++)
        for (int j = 0; j < 3; j++)
            for (int a = 0; a < 3; a++) {
                path.lo[a] = fmin(path.lo[a], b->v[i][j][a] - 4 * path.overlap);
                path.hi[a] = fmax(path.hi[a], b->v[i][j][a] + 4 * path.overlap);
            }
    return path;
}

/* Conductors at their own potentials (o->bem, o->tri_cond, o->cond_V): the field's scale Uf,
 * the tree of their charge per volt of it, each triangle's potential per volt. */
static int conductors_field(mc_run_state *st, const mote_ch_geometry *g, mote_err *err)
{
    const mote_ch_body *b = st->b;
    const mote_ch_run_opts *o = st->o;
    const mote_ch_bem *f = o->bem;
    (void)g;
    if (f->n != b->ntri)
        return mote_fail(err, MOTE_EINVAL, "run: the conductors' solution has %u panels, the "
                         "body %u", f->n, b->ntri);
    double big = 0;
    for (int k = 0; k < f->nc; k++)
        if (fabs(o->cond_V[k]) > fabs(big))
            big = o->cond_V[k];
    st->Uf = o->potential != 0 ? o->potential : big;
    if (st->Uf == 0) /* all at 0: no field */
        return MOTE_OK;
    double *sigma = malloc((size_t)f->n * sizeof *sigma);
    st->tri_phi = malloc((size_t)f->n * sizeof *st->tri_phi);
    if (!sigma || !st->tri_phi) {
        free(sigma);
        return mote_fail(err, MOTE_ENOMEM, "run: out of memory for the conductors' field");
    }
    for (uint32_t j = 0; j < f->n; j++) {
        double s = 0;
        if (f->nc == 1)
            s = o->cond_V[0] * f->sigma[j];
        else
            for (int k = 0; k < f->nc; k++)
                s += o->cond_V[k] * f->basis[(size_t)k * f->n + j];
        sigma[j] = s / st->Uf;
        st->tri_phi[j] = o->cond_V[o->tri_cond[j]] / st->Uf;
    }
    for (int k = 0; k < f->nc; k++)
        st->fc_coef[k] = o->cond_V[k] / st->Uf;
    st->own_tree = mote_ch_ftree_build(b, sigma, o->theta > 0 ? o->theta : 0.4, err);
    free(sigma);
    return st->own_tree ? MOTE_OK : err->code;
}

/* The run's constants checked and set (st->base, the path, the tallies' room). */
static int run_setup(mc_run_state *st, const mote_ch_tracer *t, mote_err *err)
{
    const mote_ch_body *b = st->b;
    const mote_ch_run_opts *o = st->o;
    mote_ch_result *r = st->r;
    mc_comp *x = &st->base;
    mote_ch_geometry g;
    mote_ch_body_geometry(b, &g);
    const double R = o->r_gen;
    if (o->box && box_injector(b, o, x->blo, x->bhi, x->fcum, err))
        return err->code;
    if (!o->box && !(R > g.r_bound))
        return mote_fail(err, MOTE_EINVAL, "run: the injection radius %.6g m must exceed the "
                         "body's bounding radius %.6g m", R, g.r_bound);
    if (!o->box && !(R <= MOTE_CH_SIZE_MAX))
        return mote_fail(err, MOTE_EINVAL, "run: the injection radius %.6g m is beyond %g m, "
                         "where the rays' coordinates no longer trace (Embree works in single "
                         "precision; a Debye length that long: give injector sphere radius=)",
                         R, MOTE_CH_SIZE_MAX);
    st->Uf = o->potential;
    const mote_ch_ftree *tree = o->tree;
    if (o->bem && o->cond_V && o->tri_cond && o->field && !b->sphere) {
        if (conductors_field(st, &g, err))
            return err->code;
        tree = st->own_tree;
    }
    const int field = o->field && st->Uf != 0;
    const int curved = field && !b->sphere; /* a charged mesh: curved paths (spec 6.3) */
    if (curved && !(o->eta >= 0 && o->eta < 1))
        return mote_fail(err, MOTE_EINVAL, "run: eta must be in (0, 1), found %g", o->eta);
    st->ntri = b->sphere ? 1 : b->ntri;
    /* the field (spec 6.1, 6.2): the equivalent sphere's radius, the potential on the
     * generation sphere */
    st->a_f = b->sphere ? b->sphere_r : g.r_field;
    if (curved && tree) /* the solved field's own capacitance (per volt of Uf) */
        st->a_f = mote_ch_ftree_charge(tree) / (4 * MOTE_CH_PI * MOTE_CH_EPS0);
    if (curved && !st->own_tree && !(R > st->a_f)) /* (conductors: any sign, any size) */
        return mote_fail(err, MOTE_EINVAL, "run: the injection radius %.6g m must exceed the "
                         "field radius R_f = C/(4 pi eps0) = %.6g m", R, st->a_f);
    st->path = path_of(b, t, o, &g, st->a_f, curved);
    if (curved && tree) { /* the monopole beyond where it is as good as the tree */
        st->path.tree = tree;
        st->path.tri_phi = st->tri_phi;
        st->path.cache = o->fcache;
        st->path.coef = st->own_tree ? st->fc_coef : NULL;
        st->path.rfar = mote_ch_ftree_monopole_radius(tree, g.centre, 1e-3);
        st->path.rj = fmax(st->path.rj, st->path.rfar);
    }
    r->nsp = st->p->nsp;
    r->ntri = st->ntri;
    r->histories = o->particles;
    for (int s = 0; s < st->p->nsp; s++)
        r->ncomp += st->p->sp[s].ncomp;
    r->tri_hits = calloc((size_t)r->ncomp * st->ntri * 2, sizeof *r->tri_hits);
    if (!r->tri_hits)
        return mote_fail(err, MOTE_ENOMEM, "run: out of memory for the tallies");
    x->b = b;
    x->t = t;
    x->o = o;
    x->key[0] = (uint32_t)o->seed;
    x->key[1] = (uint32_t)(o->seed >> 32);
    x->R = R;
    for (int a = 0; a < 3; a++)
        x->centre[a] = g.centre[a];
    x->field = field;
    x->curved = curved;
    x->box = o->box;
    x->phi_g = field ? st->Uf * st->a_f / R : 0;
    x->tmin = 1e-9 * (2 * g.r_bound);
    /* the bounding sphere about the centre, a little enlarged for rounding */
    const double rb = g.r_bound * (1 + 1e-9) / R;
    x->miss_below = rb < 1 ? 1 - rb * rb : 0;
    st->gamma_area = o->box ? x->fcum[6] : 4 * MOTE_CH_PI * R * R;
    st->nt = o->threads > 1 ? o->threads : 1;
    /* differential charging (spec 6.10): per patch a row of patch_score, per thread */
    x->patchy = o->npatch > 0 && o->tri_patch && o->dv && o->ndv > 0 && o->field;
    x->pw = x->patchy ? (size_t)(2 * o->ndv + 1) : 0;
    st->npw = x->pw * (size_t)o->npatch;
    if (x->patchy &&
        !(r->patch_I = calloc((size_t)o->npatch * (size_t)o->ndv, sizeof *r->patch_I)))
        return mote_fail(err, MOTE_ENOMEM, "run: out of memory for the patch tallies");
    ch_mpi_layout(o->solo, &st->mrank, &st->msize);
    return MOTE_OK;
}

static int mc_run(const mote_ch_plasma *p, const mote_ch_body *b, const mote_ch_tracer *t,
                  const mote_ch_run_opts *o, mote_ch_result *r, mote_err *err)
{
    memset(r, 0, sizeof *r);
    if (p->nsp == 0)
        return mote_fail(err, MOTE_EINVAL, "run: the plasma has no species (plasma preset ...)");
    if (o->particles == 0)
        return mote_fail(err, MOTE_EINVAL, "run: particles must be >= 1");
    mc_run_state st = {.p = p, .b = b, .o = o, .r = r};
    int rc = run_setup(&st, t, err);
    if (rc) {
        mote_ch_ftree_free(st.own_tree);
        free(st.tri_phi);
        mote_ch_result_free(r);
        return rc;
    }
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    /* progress: blocks done over all components (this rank's), shown by thread 0 */
    mote_progress own, *prog = o->progress ? o->progress : &own;
    if (o->progress)
        mote_progress_next_run(prog);
    else
        mote_progress_begin(&own, o->progress_ctx, o->progress_label);
    /* blocks of BLOCK histories, or fewer when the run is short (a path in a solved field takes a
     * millisecond): at least 8 a thread; the tallies are integers, so any blocks give the same */
    const uint64_t per = (o->particles + 8 * (uint64_t)st.nt * (uint64_t)st.msize - 1) /
                         (8 * (uint64_t)st.nt * (uint64_t)st.msize);
    st.bsz = per < 64 ? 64 : per > BLOCK ? BLOCK : per;
    const uint64_t nblocks_all = (o->particles + st.bsz - 1) / st.bsz;
    const uint64_t mrank = (uint64_t)st.mrank, msize = (uint64_t)st.msize;
    const uint64_t blocks_mine =
        nblocks_all > mrank ? (nblocks_all - mrank + msize - 1) / msize : 0;
    /* the run loop, counted in blocks of histories: no observer runs inside the Monte Carlo
     * (the tallies are written when it ends), the progress is the loop's */
    mote_loop loop = {NULL, 0, blocks_mine * r->ncomp, prog, 0, 0, 0, 0};
    st.loop = &loop;
    st.asks = prog->enabled || (prog->ctx && (prog->ctx->tick || prog->ctx->interrupt));
    int comp = 0;
    for (int s = 0; s < p->nsp && !rc; s++)
        for (int k = 0; k < p->sp[s].ncomp && !rc; k++, comp++)
            rc = run_component(&st, s, k, comp, err);
    if (!o->progress)
        mote_progress_end(&own);
    if (!rc && (double)r->lost > 1e-6 * (double)r->ncomp * (double)o->particles)
        rc = mote_fail(err, MOTE_ERUNTIME, "run: %llu of %.0f histories still going after "
                       "%ld steps (at U = %g V; the spec allows 1e-6 of them): raise "
                       "integrator max_steps= or eta=", (unsigned long long)r->lost,
                       (double)o->particles * (double)r->ncomp, st.path.max_steps,
                       o->potential);
    if (!rc && o->sun && o->tri_material) {
        /* in the solved field the photoelectrons are followed, as many as the histories of a
         * component */
        mc_comp xe = st.base;
        electron_paths(&st, &xe);
        const ch_photo_tracer tr = {photo_escapes, &xe, o->particles};
        rc = ch_photoemission(b, t, o, r, st.ntri, st.base.field ? st.Uf : 0,
                              st.base.patchy, xe.traced ? &tr : NULL, err);
    }
    mote_ch_ftree_free(st.own_tree);
    free(st.tri_phi);
    if (rc) {
        mote_ch_result_free(r);
        return rc;
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

/* A Monte Carlo run as one advance of the core's loop (mote_run), counted in histories: its
 * histories are shared among the threads in blocks, so it stops only at its end (its progress
 * and Ctrl-C are its own, at every block); the loop's observers (the context's) see it there. */
typedef struct {
    const mote_ch_plasma *p;
    const mote_ch_body *b;
    const mote_ch_tracer *t;
    const mote_ch_run_opts *o;
    mote_ch_result *r;
    uint64_t done;
} mc_runner;

static uint64_t mc_count(const void *vx) { return ((const mc_runner *)vx)->done; }
static int mc_advance(void *vx, mote_loop *l, double t_stop, uint64_t n_stop, mote_err *err)
{
    mc_runner *x = vx;
    int rc = mc_run(x->p, x->b, x->t, x->o, x->r, err);
    if (!rc)
        x->done = x->o->particles;
    return rc;
}

int mote_ch_run(const mote_ch_plasma *p, const mote_ch_body *b, const mote_ch_tracer *t,
                const mote_ch_run_opts *o, mote_ch_result *r, mote_err *err)
{
    if (o->particles == 0) { /* (the loop would not start) */
        memset(r, 0, sizeof *r);
        return mote_fail(err, MOTE_EINVAL, "run: particles must be >= 1");
    }
    mc_runner x = {p, b, t, o, r, 0};
    const mote_runner run = {.what = o->progress_label ? o->progress_label : "run", .sys = &x,
                             .ctx = o->progress_ctx, .count = mc_count, .advance = mc_advance};
    return mote_run(&run, NULL, 0, NULL, INFINITY, o->particles, err);
}
