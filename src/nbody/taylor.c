/* taylor.c: the general Taylor integrator of spec 4.4 (after Jorba & Zou 2005 and TIDES): every
 * Taylor coefficient of every body's trajectory comes exactly from the recurrences of automatic
 * differentiation, none from differences. In normalized coefficients u^[n] = u^(n)/n!, for each
 * ordered pair (i, k):
 *
 *     R^[n] = x_i^[n] - x_k^[n],   s^[n] = sum_j R^[j] . R^[n-j]          (s = |R|^2)
 *
 * (with compensated summation R^[0] and R^[1] also take the difference of the two bodies'
 * compensation terms: the state is x - xc, and a close pair's separation computed from the
 * rounded positions alone would lose the digits the terms hold)
 *     f^[0] = s^[0]^(-3/2),  f^[n] = 1/(n s^[0]) sum_{j<n} (j/2 - 3n/2) s^[n-j] f^[j]
 *     G^[n] = sum_j f^[j] R^[n-j],   a_i^[n] = c_i sum_k w_k G^[n],   x^[n+2] = a^[n]/((n+1)(n+2))
 *
 * Order n of the acceleration needs x^[n] and x^[n+1], so one pass over all pairs yields two
 * orders: a step of order p takes ceil((p-1)/2) passes. The per-pair histories s^[j], f^[j] are
 * either kept from pass to pass (`store`, with R^[0] and R^[1]: (p + 2) N (N - 1) reals) or computed again in every pass
 * (`recompute`, no pair memory): both run the same arithmetic in the same order, so they give the
 * same bits. The step sums x(T+h) and v(T+h) by Horner's rule as increments, added with
 * compensation like the Galactica scheme. Targets are shared among OpenMP threads; each sums its
 * sources in index order. */
#include "mote/nbody.h"

#include <tgmath.h>
#include <stdlib.h>
#include <string.h>

#include "nb.h"

/* s^[n] and f^[n] of one pair from R^[0..n] and the lower orders (s, f hold orders 0 .. n-1).
 * s^[n] = sum_j R^[j] . R^[n-j] is symmetric in j <-> n - j, so half of it is formed and
 * doubled; the sums run on two accumulators (even and odd j), which shortens the chain of
 * dependent additions. */
static inline void sf_order(int n, mote_real (*R)[3], mote_real *s, mote_real *f,
                            mote_real f0inv, mote_real e2)
{
    mote_real s0 = 0, s1 = 0;
    int j = 0;
    for (; 2 * j + 2 < n; j += 2) { /* pairs (j, n - j) with j < n - j, two at a time */
        s0 += R[j][0] * R[n - j][0] + R[j][1] * R[n - j][1] + R[j][2] * R[n - j][2];
        s1 += R[j + 1][0] * R[n - j - 1][0] + R[j + 1][1] * R[n - j - 1][1] +
              R[j + 1][2] * R[n - j - 1][2];
    }
    for (; 2 * j < n; j++)
        s0 += R[j][0] * R[n - j][0] + R[j][1] * R[n - j][1] + R[j][2] * R[n - j][2];
    mote_real sn = 2 * (s0 + s1);
    if (n % 2 == 0) /* the middle term j = n/2 once */
        sn += R[n / 2][0] * R[n / 2][0] + R[n / 2][1] * R[n / 2][1] + R[n / 2][2] * R[n / 2][2];
    s[n] = sn;
    if (n == 0) { /* the softening enters s^[0] only: s = |R|^2 + e2 */
        sn += e2;
        s[0] = sn;
        f[0] = 1.0 / (sn * sqrt(sn));
        return;
    }
    mote_real a0 = 0, a1 = 0;
    j = 0;
    for (; j + 1 < n; j += 2) {
        a0 += (0.5 * j - 1.5 * n) * s[n - j] * f[j];
        a1 += (0.5 * (j + 1) - 1.5 * n) * s[n - j - 1] * f[j + 1];
    }
    if (j < n)
        a0 += (0.5 * j - 1.5 * n) * s[n - j] * f[j];
    f[n] = (a0 + a1) * (f0inv / n); /* f0inv = 1 / s^[0], so f^[n] = sum / (n s^[0]) */
}

/* The index of the unordered pair i < k among N bodies. */
static inline size_t upair(uint32_t i, uint32_t k, uint32_t N)
{
    return (size_t)i * N - (size_t)i * (i + 1) / 2 + (k - i - 1);
}

/* The pair (i, k)'s G^[n0 .. n1] (i < k) into G, its s, f histories kept or restored. */
static inline void pair_G(mote_nb *nb, const mote_real *X, size_t blk, uint32_t i, uint32_t k,
                          size_t q, size_t npairs, int n0, int n1, int store, mote_real G[2][3])
{
    mote_real R[64][3], s[64], f[64];
    const int kept = store && n0 > 0; /* R^[0], R^[1] as the first pass left them */
    for (int j = kept ? 2 : 0; j <= n1; j++)
        for (int a = 0; a < 3; a++)
            R[j][a] = X[j * blk + 3 * i + a] - X[j * blk + 3 * k + a];
    if (kept) {
        for (int a = 0; a < 6; a++)
            R[a / 3][a % 3] = nb->tr[(size_t)a * npairs + q];
    } else {
        if (nb->compensated) /* the state is x - xc: a close pair's separation keeps its digits */
            for (int a = 0; a < 3; a++) {
                R[0][a] -= nb->xc[3 * i + a] - nb->xc[3 * (size_t)k + a];
                R[1][a] -= nb->vc[3 * i + a] - nb->vc[3 * (size_t)k + a];
            }
        for (int a = 0; store && a < 6; a++)
            nb->tr[(size_t)a * npairs + q] = R[a / 3][a % 3];
    }
    int from = 0;
    if (store && n0 > 0) { /* the histories of the earlier passes */
        s[0] = nb->ts[q]; /* spelled out: the compiler then sees s[0] set on this path */
        f[0] = nb->tf[q];
        for (int j = 1; j < n0; j++) {
            s[j] = nb->ts[(size_t)j * npairs + q];
            f[j] = nb->tf[(size_t)j * npairs + q];
        }
        from = n0;
    } else {
        sf_order(0, R, s, f, 0, nb->soft * nb->soft);
    }
    const mote_real f0inv = 1 / s[0];
    for (int n = from > 0 ? from : 1; n <= n1; n++)
        sf_order(n, R, s, f, f0inv, 0);
    if (store)
        for (int n = n0; n <= n1; n++) {
            nb->ts[(size_t)n * npairs + q] = s[n];
            nb->tf[(size_t)n * npairs + q] = f[n];
        }
    for (int n = n0; n <= n1; n++) {
        mote_real g[3] = {0, 0, 0};
        for (int j = 0; j <= n; j++)
            for (int a = 0; a < 3; a++)
                g[a] += f[j] * R[n - j][a];
        for (int a = 0; a < 3; a++)
            G[n - n0][a] = g[a];
    }
}

/* One pass: orders n0 and n0 + 1 (the latter when <= top) of every active body's acceleration,
 * into x^[n+2]. X: (p + 1) blocks of 3 n_bodies coefficients.
 *
 * Each unordered pair is solved once (phase 1): for (k, i) every quantity is that of (i, k)
 * with R negated, which IEEE arithmetic does exactly (a - b = -(b - a), and a sum of negated
 * terms is the negated sum), so s and f are the same and G is exactly -G. Then each target sums
 * w_k G over its sources in index order (phase 2), exactly the sums a pass over ordered pairs
 * would form: the result is the same bits, with half the pair work, for any number of threads.
 * That needs the G of every pair (6 reals each): store mode only. Recompute mode keeps memory
 * O(N): each target solves all its pairs itself (twice the pair work), in the same order and
 * with the same negation, so both modes give the same bits. */
/* Target i's sums of w_k G over its sources in index order from the pairs' table (store mode),
 * for no orders: the sources below i (G negated: the exact -w G) and above it, each pair's G
 * found by a step through the table, not upair. */
static inline void source_sums(const mote_nb *nb, mote_real (*Gb)[2][3], uint32_t i, int no,
                               mote_real sum[2][3])
{
    const uint32_t N = nb->n;
    mote_real acc[2][3] = {{0, 0, 0}, {0, 0, 0}};
    size_t q = i > 0 ? upair(0, i, N) : 0;
    for (uint32_t k = 0; k < i; q += N - k - 2, k++)
        if (nb->active[k])
            for (int n = 0; n < no; n++)
                for (int a = 0; a < 3; a++)
                    acc[n][a] -= nb->w[k] * Gb[q][n][a];
    q = i + 1 < N ? upair(i, i + 1, N) : 0;
    for (uint32_t k = i + 1; k < N; q++, k++)
        if (nb->active[k])
            for (int n = 0; n < no; n++)
                for (int a = 0; a < 3; a++)
                    acc[n][a] += nb->w[k] * Gb[q][n][a];
    memcpy(sum, acc, sizeof acc);
}

/* Phase 2 for target i: sum w_k G over the sources in index order into x^[n+2] (n = n0 .. n1),
 * with each pair's G from Gb (store mode) or solved here (recompute mode). */
static void target(mote_nb *nb, mote_real *X, size_t blk, uint32_t i, int n0, int n1,
                   mote_real (*Gb)[2][3])
{
    const uint32_t N = nb->n;
    const size_t npairs = (size_t)N * (N - 1) / 2;
    mote_real sum[2][3] = {{0, 0, 0}, {0, 0, 0}};
    if (Gb) { /* store mode: the same sums, in registers (the orders a constant) */
        if (n1 > n0)
            source_sums(nb, Gb, i, 2, sum);
        else
            source_sums(nb, Gb, i, 1, sum);
        for (int n = n0; n <= n1; n++)
            for (int a = 0; a < 3; a++)
                X[(size_t)(n + 2) * blk + 3 * i + a] =
                    nb->c[i] * sum[n - n0][a] / ((mote_real)(n + 1) * (n + 2));
        return;
    }
    for (uint32_t k = 0; k < N; k++) {
        if (k == i || !nb->active[k])
            continue;
        const uint32_t lo = k > i ? i : k, hi = k > i ? k : i;
        mote_real Gk[2][3], (*G)[3] = Gk;
        if (Gb)
            G = Gb[upair(lo, hi, N)];
        else
            pair_G(nb, X, blk, lo, hi, upair(lo, hi, N), npairs, n0, n1, 0, Gk);
        const mote_real wk = nb->w[k], sg = k > i ? 1.0 : -1.0;
        for (int n = n0; n <= n1; n++)
            for (int a = 0; a < 3; a++)
                sum[n - n0][a] += wk * (sg * G[n - n0][a]);
    }
    for (int n = n0; n <= n1; n++)
        for (int a = 0; a < 3; a++)
            X[(size_t)(n + 2) * blk + 3 * i + a] =
                nb->c[i] * sum[n - n0][a] / ((mote_real)(n + 1) * (n + 2));
}

#if MOTE_NB_PRECISION == 1 && defined(__x86_64__) && defined(__GNUC__)
/* The pair kernel on 2, 4 and 8 pairs at once (SSE2, AVX2, AVX-512F), each giving the bits of
 * pair_G: pair_lanes.inc. */
#define NB_LANE_PAIRS 1
#define NB_LANES 2
#define NB_KNAME pair_G2
#define NB_KATTR
#include "pair_lanes.inc"
#undef NB_LANES
#undef NB_KNAME
#undef NB_KATTR
#define NB_LANES 4
#define NB_KNAME pair_G4
#define NB_KATTR __attribute__((target("avx2")))
#include "pair_lanes.inc"
#undef NB_LANES
#undef NB_KNAME
#undef NB_KATTR
#define NB_LANES 8
#define NB_KNAME pair_G8
#define NB_KATTR __attribute__((target("avx512f")))
#include "pair_lanes.inc"
#undef NB_LANES
#undef NB_KNAME
#undef NB_KATTR

/* The widest kernel the processor runs, at most nb->simd lanes when that is set (tests). */
static int lanes(const mote_nb *nb)
{
    int w = 2;
    if (__builtin_cpu_supports("avx512f"))
        w = 8;
    else if (__builtin_cpu_supports("avx2"))
        w = 4;
    return nb->simd > 0 && nb->simd < w ? nb->simd : w;
}

/* Whether bodies k .. k + w - 1 are all active. */
static int all_active(const mote_nb *nb, uint32_t k, int w)
{
    for (int l = 0; l < w; l++)
        if (!nb->active[k + (uint32_t)l])
            return 0;
    return 1;
}
#endif

/* Phase 1 for the pairs (i, k > i) of body i (store mode). */
static void pairs_of(mote_nb *nb, mote_real *X, size_t blk, uint32_t i, int n0, int n1,
                     mote_real (*Gb)[2][3])
{
    const uint32_t N = nb->n;
    const size_t npairs = (size_t)N * (N - 1) / 2;
    if (!nb->active[i])
        return;
    uint32_t k = i + 1;
#ifdef NB_LANE_PAIRS
    /* w pairs at a time while their bodies are active, then fewer (the same bits) */
    const int w = lanes(nb);
    for (; w >= 8 && k + 7 < N && all_active(nb, k, 8); k += 8)
        pair_G8(nb, X, blk, i, k, upair(i, k, N), npairs, n0, n1, Gb);
    for (; w >= 4 && k + 3 < N && all_active(nb, k, 4); k += 4)
        pair_G4(nb, X, blk, i, k, upair(i, k, N), npairs, n0, n1, Gb);
    for (; w >= 2 && k + 1 < N && all_active(nb, k, 2); k += 2)
        pair_G2(nb, X, blk, i, k, upair(i, k, N), npairs, n0, n1, Gb);
#endif
    for (; k < N; k++)
        if (nb->active[k])
            pair_G(nb, X, blk, i, k, upair(i, k, N), npairs, n0, n1, 1, Gb[upair(i, k, N)]);
}

/* Tree forces (spec 6.2): target i's sum over its interaction list, every source's s, f
 * histories computed afresh from order 0 (no pair memory); a cell's coefficients are its block
 * of the tree's cell data, order by order. */
typedef struct {
    const mote_nb *nb;
    const mote_real *X, *C; /* the bodies' and the cells' coefficients */
    size_t blk, cblk;
    uint32_t i;
    int n0, n1;
    mote_real sum[2][3];
} tree_sum;

static void tree_visit(uint32_t k, int cell, void *arg)
{
    tree_sum *q = arg;
    const mote_real *S = cell ? q->C : q->X;
    const size_t sb = cell ? q->cblk : q->blk;
    mote_real R[64][3], s[64], f[64];
    for (int j = 0; j <= q->n1; j++)
        for (int a = 0; a < 3; a++)
            R[j][a] = q->X[j * q->blk + 3 * q->i + a] - S[j * sb + 3 * (size_t)k + a];
    if (!cell && q->nb->compensated) /* a body: its separation with the compensation terms */
        for (int a = 0; a < 3; a++) {
            R[0][a] -= q->nb->xc[3 * q->i + a] - q->nb->xc[3 * (size_t)k + a];
            R[1][a] -= q->nb->vc[3 * q->i + a] - q->nb->vc[3 * (size_t)k + a];
        }
    sf_order(0, R, s, f, 0, q->nb->soft * q->nb->soft);
    const mote_real f0inv = 1 / s[0];
    for (int n = 1; n <= q->n1; n++)
        sf_order(n, R, s, f, f0inv, 0);
    const mote_real w = cell ? nb_tree_weight(q->nb, k) : q->nb->w[k];
    for (int n = q->n0; n <= q->n1; n++) {
        mote_real g[3] = {0, 0, 0};
        for (int j = 0; j <= n; j++)
            for (int a = 0; a < 3; a++)
                g[a] += f[j] * R[n - j][a];
        for (int a = 0; a < 3; a++)
            q->sum[n - q->n0][a] += w * g[a];
    }
}

static void tree_target(mote_nb *nb, mote_real *X, size_t blk, uint32_t i, int n0, int n1)
{
    tree_sum q = {nb, X, nb_tree_block(nb, 0), blk, 0, i, n0, n1, {{0, 0, 0}, {0, 0, 0}}};
    q.cblk = (size_t)(nb_tree_block(nb, 1) - q.C);
    nb_tree_walk(nb, i, tree_visit, &q);
    for (int n = n0; n <= n1; n++)
        for (int a = 0; a < 3; a++)
            X[(size_t)(n + 2) * blk + 3 * i + a] =
                nb->c[i] * q.sum[n - n0][a] / ((mote_real)(n + 1) * (n + 2));
}

static void tree_pass(mote_nb *nb, mote_real *X, int n0, int n1)
{
    const size_t blk = 3 * (size_t)nb->n;
    for (int n = n0; n <= n1; n++) /* the cells' orders that the last pass made known */
        nb_tree_fill(nb, n, X + (size_t)n * blk);
    const int nt = nb->threads > 1 ? nb->threads : 1;
    uint32_t na; /* targets in tree order: neighbours share their sources in the cache */
    const uint32_t *order = nb_tree_order(nb, &na);
#pragma omp parallel for num_threads(nt) schedule(dynamic, 64) if (nt > 1 && na >= nb->threads_min_n)
    for (uint32_t k = 0; k < na; k++)
        tree_target(nb, X, blk, order[k], n0, n1);
}

/* One pass over every body; OpenMP only where it pays (an OpenMP region costs an allocation and
 * a wake-up even on one thread), with the same bits either way. */
static void pass(mote_nb *nb, mote_real *X, int n0, int top, int store)
{
    const uint32_t N = nb->n;
    const size_t blk = 3 * (size_t)N;
    const int n1 = n0 + 1 <= top ? n0 + 1 : n0;
    if (nb->tree_on) {
        tree_pass(nb, X, n0, n1);
        return;
    }
    if (nb->mpi_size > 1) { /* this rank's targets (recompute mode), then every body's orders */
        const int nt = nb->threads > 1 ? nb->threads : 1;
#pragma omp parallel for num_threads(nt) schedule(dynamic, 16) if (nt > 1 && nb->hi - nb->lo >= nb->threads_min_n)
        for (uint32_t i = nb->lo; i < nb->hi; i++)
            if (nb->active[i])
                target(nb, X, blk, i, n0, n1, NULL);
        for (int n = n0; n <= n1; n++)
            nb_mpi_gather(nb, X + (size_t)(n + 2) * blk, 3);
        return;
    }
    const int nt = nb->threads > 1 ? nb->threads : 1;
    mote_real (*Gb)[2][3] = store ? (mote_real (*)[2][3])nb->tg : NULL;
    if (nt > 1 && N >= nb->threads_min_n) {
        if (store) { /* phase 1: each unordered pair once */
#pragma omp parallel for num_threads(nt) schedule(dynamic, 16)
            for (uint32_t i = 0; i < N; i++)
                pairs_of(nb, X, blk, i, n0, n1, Gb);
        }
#pragma omp parallel for num_threads(nt) schedule(dynamic, 16)
        for (uint32_t i = 0; i < N; i++)
            if (nb->active[i])
                target(nb, X, blk, i, n0, n1, Gb);
        return;
    }
    if (store)
        for (uint32_t i = 0; i < N; i++)
            pairs_of(nb, X, blk, i, n0, n1, Gb);
    for (uint32_t i = 0; i < N; i++)
        if (nb->active[i])
            target(nb, X, blk, i, n0, n1, Gb);
}

static int scratch(mote_nb *nb, int p, int store, mote_err *err);

int mote_nb_taylor_coefficients(mote_nb *nb, int p, int store, mote_real *X)
{
    mote_err e = {0};
    int rc = scratch(nb, p, store, &e); /* (a no-op when a run has sized it) */
    if (!rc && nb->tree_on)
        rc = nb_tree_check(nb, p + 1, &e);
    if (rc)
        return rc;
    const size_t blk = 3 * (size_t)nb->n;
    memcpy(X, nb->x, blk * sizeof *X);
    memcpy(X + blk, nb->v, blk * sizeof *X);
    if (nb->tree_on)
        nb_tree_build(nb);
    for (int n0 = 0; n0 <= p - 2; n0 += 2)
        pass(nb, X, n0, p - 2, store);
    return MOTE_OK;
}

/* y += d with the compensation term of kahan_add (cs = y - the true sum), the sum formed in
 * nb_wide (long double; quad in the quad build): in the double build the increment's rounding
 * and the Horner sums' roundings are 2^-11 of a double's, which keeps the energy drift of long
 * runs at the level of the force's rounding. */
static inline void ext_add(mote_real *y, mote_real *cs, nb_wide d)
{
    nb_wide t = (nb_wide)*y - *cs + d;
    mote_real r = (mote_real)t;
    *cs = (mote_real)((nb_wide)r - t);
    *y = r;
}

/* Room for the coefficients and, in store mode, the pairs' G of a pass and their histories. */
static int scratch(mote_nb *nb, int p, int store, mote_err *err)
{
    size_t need = (size_t)(p + 1) * 3 * nb->n;
    if (need > nb->tx_cap) {
        mote_real *q = realloc(nb->tx, need * sizeof *q);
        if (!q)
            return mote_fail(err, MOTE_ENOMEM, "taylor: out of memory for the coefficients");
        nb->tx = q;
        nb->tx_cap = need;
    }
    const size_t npairs = (size_t)nb->n * (nb->n ? nb->n - 1 : 0) / 2;
    if (store && 6 * npairs > nb->tg_cap) {
        mote_real *g = realloc(nb->tg, (npairs > 0 ? 6 * npairs : 1) * sizeof *g);
        if (!g)
            return mote_fail(err, MOTE_ENOMEM, "taylor: out of memory for the pairs (%zu)",
                             npairs);
        nb->tg = g;
        nb->tg_cap = 6 * npairs;
    }
    if (store && 6 * npairs > nb->tr_cap) {
        mote_real *r = realloc(nb->tr, (npairs > 0 ? 6 * npairs : 1) * sizeof *r);
        if (!r)
            return mote_fail(err, MOTE_ENOMEM, "taylor: out of memory for the pairs (%zu)",
                             npairs);
        nb->tr = r;
        nb->tr_cap = 6 * npairs;
    }
    if (store) {
        size_t pairs = (size_t)(p - 1) * npairs;
        if (pairs > nb->tsf_cap) {
            mote_real *a = realloc(nb->ts, pairs * sizeof *a);
            if (a)
                nb->ts = a;
            mote_real *b = realloc(nb->tf, pairs * sizeof *b);
            if (b)
                nb->tf = b;
            if (!a || !b)
                return mote_fail(err, MOTE_ENOMEM,
                                 "taylor: out of memory for the pair histories (use "
                                 "memory=recompute)");
            nb->tsf_cap = pairs;
        }
    }
    return MOTE_OK;
}

int mote_nb_taylor_memory_store(const mote_nb *nb, int p)
{
    if (nb->tree_on || nb->mpi_size > 1) /* tree forces and MPI ranks keep no pair histories */
        return 0;
    if (nb->taylor_memory == 1)
        return 1;
    if (nb->taylor_memory == 2)
        return 0;
    /* automatic: store while the histories fit in the budget (1 GiB) */
    mote_real bytes = (p + 2) * (mote_real)nb->n * (mote_real)nb->n * sizeof(mote_real);
    return bytes <= (mote_real)(1u << 30);
}

int nb_taylor_check(mote_nb *nb, mote_err *err)
{
    const int p = nb->taylor_order;
    if (p < 2 || p > MOTE_NB_TAYLOR_MAX)
        return mote_fail(err, MOTE_EINVAL, "taylor: order must be in 2 ... %d (found %d)",
                         MOTE_NB_TAYLOR_MAX, p);
    if (nb->adaptive ? !(nb->tol > 0 && nb->tol < 1) : !(nb->dt > 0) || !isfinite(nb->dt))
        return mote_fail(err, MOTE_EINVAL, nb->adaptive ? "taylor: tol must be in (0, 1)"
                                                        : "taylor: the step dt must be > 0");
    return scratch(nb, p, mote_nb_taylor_memory_store(nb, p), err);
}

/* The adaptive step of spec 4.5: for each body the step at which its two highest terms stay
 * below tol times the distance to its nearest neighbour, h_i = min_{j = p-1, p}
 * (tol l_i / |x_i^[j]|_inf)^(1/j); then h = safety min_i h_i, at most twice the previous step,
 * clamped to [hmin, hmax]. */
static mote_real adaptive_step(mote_nb *nb, const mote_real *X, int p)
{
    const uint32_t N = nb->n;
    const size_t blk = 3 * (size_t)N;
    mote_real h = INFINITY;
    if (nb->adaptive == MOTE_NB_NORM_GLOBAL) { /* Jorba-Zou: one infinity norm over all bodies */
        mote_real x0 = 0, nj[2] = {0, 0};
        for (uint32_t i = 0; i < N; i++) {
            if (!nb->active[i])
                continue;
            for (int c = 0; c < 3; c++) {
                x0 = fmax(x0, fabs(X[3 * i + c]));
                for (int j = p - 1; j <= p; j++)
                    nj[j - p + 1] = fmax(nj[j - p + 1], fabs(X[(size_t)j * blk + 3 * i + c]));
            }
        }
        const mote_real eps = fmax(nb->tol, nb->tol * x0);
        for (int j = p - 1; j <= p; j++)
            if (nj[j - p + 1] > 0)
                h = fmin(h, pow(eps / nj[j - p + 1], (mote_real)1 / j));
        return nb_step_bounds(nb, h, nb->hmax > 0 ? nb->hmax : 1);
    }
    /* min_i (tol l_i / |x_i^[j]|)^(1/j) = (min_i tol l_i / |x_i^[j]|)^(1/j): one pow per order */
    mote_real ratio[2] = {INFINITY, INFINITY};
    for (uint32_t i = 0; i < N; i++) {
        if (!nb->active[i])
            continue;
        mote_real l2 = INFINITY;
        for (uint32_t k = 0; k < N; k++) {
            if (k == i || !nb->active[k])
                continue;
            mote_real d0 = X[3 * i] - X[3 * k], d1 = X[3 * i + 1] - X[3 * k + 1],
                   d2 = X[3 * i + 2] - X[3 * k + 2];
            const mote_real r2 = d0 * d0 + d1 * d1 + d2 * d2;
            l2 = r2 < l2 ? r2 : l2; /* (not fmin: a libm call per pair) */
        }
        mote_real l = isfinite(l2) ? sqrt(l2) : 1.0; /* a single body: its own scale */
        for (int j = p - 1; j <= p; j++) {
            const mote_real *c = X + (size_t)j * blk + 3 * i;
            mote_real nrm = fmax(fabs(c[0]), fmax(fabs(c[1]), fabs(c[2])));
            if (nrm > 0 && nb->tol * l / nrm < ratio[j - p + 1])
                ratio[j - p + 1] = nb->tol * l / nrm;
        }
    }
    for (int j = p - 1; j <= p; j++)
        if (ratio[j - p + 1] < INFINITY)
            h = fmin(h, pow(ratio[j - p + 1], (mote_real)1 / j));
    return nb_step_bounds(nb, h, nb->hmax > 0 ? nb->hmax : 1);
}

/* The accelerations at the step's start, 2 x^[2], in long double from the compensated state x -
 * xc (double builds, direct sums, at most NB_WIDE_ACC_MAX bodies, where the passes run on one
 * thread anyway): the update's leading terms a h^2 / 2 and a h then carry the state's digits,
 * where the double x^[2] put a rounding error of the force's size into every step (the largest
 * part of the round-off walk of an eccentric orbit's energy). Each pair once, R f negated
 * exactly for its second body, and every body's sum in index order of its sources (the same
 * bits for any number of threads). 0 when not made; then x^[2] serves. */
#define NB_WIDE_ACC_MAX 1024
static int wide_accelerations(mote_nb *nb)
{
    const uint32_t N = nb->n;
    if (sizeof(nb_wide) <= sizeof(mote_real) || !nb->compensated || N > NB_WIDE_ACC_MAX ||
        nb->tree_on)
        return 0;
    if (3 * (size_t)N > nb->taw_cap) {
        long double *q = realloc(nb->taw, 3 * (size_t)N * sizeof *q);
        if (!q)
            return 0; /* (the double terms serve) */
        nb->taw = q;
        nb->taw_cap = 3 * (size_t)N;
    }
    long double *acc = nb->taw;
    for (size_t o = 0; o < 3 * (size_t)N; o++)
        acc[o] = 0;
    const long double e2 = (long double)nb->soft * nb->soft;
    for (uint32_t i = 0; i < N; i++) {
        if (!nb->active[i])
            continue;
        for (uint32_t k = i + 1; k < N; k++) {
            if (!nb->active[k])
                continue;
            long double R[3], s = e2;
            for (int a = 0; a < 3; a++) {
                R[a] = ((long double)nb->x[3 * i + a] - nb->x[3 * (size_t)k + a]) -
                       ((long double)nb->xc[3 * i + a] - nb->xc[3 * (size_t)k + a]);
                s += R[a] * R[a];
            }
            const long double f = 1 / (s * sqrtl(s));
            for (int a = 0; a < 3; a++) {
                const long double g = f * R[a];
                acc[3 * i + a] += nb->w[k] * g;
                acc[3 * (size_t)k + a] -= nb->w[i] * g;
            }
        }
        for (int a = 0; a < 3; a++) /* (i's sum is complete: its sources below and above) */
            acc[3 * i + a] *= nb->c[i];
    }
    return 1;
}

mote_real nb_taylor_step(mote_nb *nb, mote_real rest)
{
    const int p = nb->taylor_order;
    const int store = mote_nb_taylor_memory_store(nb, p);
    const size_t blk = 3 * (size_t)nb->n;
    mote_real *X = nb->tx;
    mote_nb_taylor_coefficients(nb, p, store, X);
    mote_real h = nb->adaptive ? adaptive_step(nb, X, p) : nb->dt;
    if (h > rest)
        h = rest;
    const int wide = wide_accelerations(nb);
    for (uint32_t i = 0; i < nb->n; i++) {
        if (!nb->active[i])
            continue;
        for (int a = 0; a < 3; a++) {
            const size_t o = 3 * (size_t)i + a;
            nb_wide dx = 0, dv = 0;
            for (int n = p; n >= 3; n--)
                dx = dx * h + X[n * blk + o];
            for (int n = p; n >= 3; n--)
                dv = dv * h + n * X[n * blk + o];
            if (wide) {
                dx = dx * h + 0.5L * nb->taw[o];
                dv = dv * h + nb->taw[o];
            } else {
                dx = dx * h + X[2 * blk + o];
                dv = dv * h + 2 * X[2 * blk + o];
            }
            dx = dx * h + X[blk + o];
            if (nb->compensated) {
                /* the velocity is v - vc: its first term carries the compensation too */
                dx -= nb->vc[o];
                ext_add(&nb->x[o], &nb->xc[o], dx * h);
                ext_add(&nb->v[o], &nb->vc[o], dv * h);
            } else {
                nb->x[o] += (mote_real)(dx * h);
                nb->v[o] += (mote_real)(dv * h);
            }
        }
    }
    kahan_add(&nb->T, &nb->Tc, h, nb->compensated);
    nb->steps++;
    if (h < rest) /* a step shortened to an end time says nothing about the next one */
        nb->hprev = h;
    nb->dtp = 0; /* a Galactica step after this one restarts */
    nb->restart = 1;
    return h;
}

void mote_nb_taylor_dense(const mote_nb *nb, mote_real s, mote_real *x, mote_real *v)
{
    const int p = nb->taylor_order;
    const size_t blk = 3 * (size_t)nb->n;
    const mote_real *X = nb->tx;
    for (size_t o = 0; o < blk; o++) {
        if (!nb->active[o / 3]) {
            x[o] = nb->x[o];
            v[o] = nb->v[o];
            continue;
        }
        nb_wide dx = 0, dv = 0;
        for (int n = p; n >= 1; n--)
            dx = dx * s + X[n * blk + o];
        for (int n = p; n >= 2; n--)
            dv = dv * s + n * X[n * blk + o];
        x[o] = (mote_real)(X[o] + dx * s);
        v[o] = (mote_real)(X[blk + o] + dv * s);
    }
}

int mote_nb_taylor(mote_nb *nb, uint64_t steps, mote_err *err)
{
    return nb_run_as(nb, MOTE_NB_TAYLOR, steps, err);
}

int mote_nb_taylor_auto_order(mote_real tol)
{
    int p = (int)ceil(1 - 0.5 * log(tol));
    return p < 2 ? 2 : p > MOTE_NB_TAYLOR_MAX ? MOTE_NB_TAYLOR_MAX : p;
}
