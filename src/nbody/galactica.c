/* galactica.c: Galactica's sixth-order Taylor scheme, reproduced as spec 4.2 states it: two
 * passes over all ordered pairs give the acceleration and jerk (pass 1), then the fourth and
 * fifth derivatives from the pairwise recurrences of Nitadori & Makino (pass 2); the sixth
 * derivative is the backward difference of fifth derivatives over the previous step; positions
 * and velocities advance by their Taylor series summed from the highest term down and added with
 * compensation (Kahan), as is the time. A start without a valid previous fifth derivative takes
 * a first step of first_step * dt (0.001 dt), which the seed document's read-back times confirm.
 * The truncated orders of spec 4.3 drop the terms above x^(K). With a tolerance the step is
 * adaptive (spec 4.5; Galactica's step correction, Kl4 = 2 or 3), dt then being the first step's
 * nominal length.
 *
 * Sums over sources run in a fixed order for every target (increasing index; in double
 * precision with SSE2, two lanes taking alternate sources, each in increasing index, added at the
 * end), and each target is one thread's (OpenMP over targets, spec 6.1), so a result depends on
 * nothing but the state: 1, 2 or 4 threads give the same bits. */
#include "mote/nbody.h"

#include <stdlib.h>
#include <string.h>
#include <tgmath.h>

#include "nb.h"

/* Are all bodies active? (the pair loops then skip the test) */
static int all_active(const mote_nb *nb)
{
    for (uint32_t i = 0; i < nb->n; i++)
        if (!nb->active[i])
            return 0;
    return 1;
}

/* The sources of a pass: positions, velocities, accelerations, jerks (3 a source), weights and
 * the active flags (NULL: all active): the bodies, or a tree target's gathered list. */
typedef struct {
    const mote_real *x, *v, *A, *J, *w;
    const uint8_t *active;
    mote_real e2; /* the softening squared */
} nb_src;

/* Pass 1 for the target at xi, vi over the sources k0 <= k < k1: the sums of A0 and A1. */
static inline void pass1_range(const nb_src *s, int all, const mote_real *xi, const mote_real *vi,
                               uint32_t k0, uint32_t k1, mote_real a[3], mote_real j[3])
{
    const mote_real *x = s->x, *v = s->v, *w = s->w;
    for (uint32_t k = k0; k < k1; k++)
        if (all || s->active[k])
            nb_pair1(xi, vi, x + 3 * (size_t)k, v + 3 * (size_t)k, w[k], s->e2, a, j);
}

#if MOTE_NB_PRECISION == 1 && defined(__SSE2__)
#define NB_SSE2 1
#include <emmintrin.h>

/* Two lanes of three coordinates of sources k and k + 1 (AoS) */
static inline void load2(const double *p, __m128d out[3])
{
    for (int c = 0; c < 3; c++)
        out[c] = _mm_set_pd(p[3 + c], p[c]); /* lane 0: k, lane 1: k + 1 */
}
static inline double hsum(__m128d v) /* lane 0 + lane 1 */
{
    return _mm_cvtsd_f64(_mm_add_sd(v, _mm_unpackhi_pd(v, v)));
}

/* pass1_range for double with SSE2 (every body active): two sources per iteration, k in lane
 * 0 and k + 1 in lane 1, each lane summed in index order and the lanes added at the end (a fixed
 * order: the result depends on nothing but the state). The same arithmetic as the scalar loop. */
static inline void pass1_sse2(const nb_src *s, const double *xi, const double *vi, uint32_t k0,
                              uint32_t k1, mote_real a[3], mote_real j[3])
{
    const double *x = s->x, *v = s->v, *w = s->w;
    __m128d XI[3], VI[3], SA[3], SJ[3];
    for (int c = 0; c < 3; c++) {
        XI[c] = _mm_set1_pd(xi[c]);
        VI[c] = _mm_set1_pd(vi[c]);
        SA[c] = SJ[c] = _mm_setzero_pd();
    }
    const __m128d one = _mm_set1_pd(1), three = _mm_set1_pd(3), E2 = _mm_set1_pd(s->e2);
    uint32_t k = k0;
    for (; k + 1 < k1; k += 2) {
        __m128d r[3], u[3];
        load2(x + 3 * (size_t)k, r);
        load2(v + 3 * (size_t)k, u);
        for (int c = 0; c < 3; c++) {
            r[c] = _mm_sub_pd(XI[c], r[c]);
            u[c] = _mm_sub_pd(VI[c], u[c]);
        }
        __m128d r2 = _mm_add_pd(
            _mm_add_pd(_mm_add_pd(_mm_mul_pd(r[0], r[0]), _mm_mul_pd(r[1], r[1])),
                       _mm_mul_pd(r[2], r[2])),
            E2);
        __m128d i2 = _mm_div_pd(one, r2);
        __m128d wr3 = _mm_mul_pd(_mm_mul_pd(_mm_loadu_pd(w + k), i2), _mm_sqrt_pd(i2));
        __m128d ru = _mm_add_pd(_mm_add_pd(_mm_mul_pd(r[0], u[0]), _mm_mul_pd(r[1], u[1])),
                                _mm_mul_pd(r[2], u[2]));
        __m128d al3 = _mm_mul_pd(three, _mm_mul_pd(ru, i2));
        for (int c = 0; c < 3; c++) {
            __m128d A0 = _mm_mul_pd(wr3, r[c]);
            SA[c] = _mm_add_pd(SA[c], A0);
            SJ[c] = _mm_add_pd(SJ[c], _mm_sub_pd(_mm_mul_pd(wr3, u[c]), _mm_mul_pd(al3, A0)));
        }
    }
    for (int c = 0; c < 3; c++) {
        a[c] += hsum(SA[c]);
        j[c] += hsum(SJ[c]);
    }
    if (k < k1)
        pass1_range(s, 1, xi, vi, k, k1, a, j);
}
#endif

static void tree_target(mote_nb *nb, uint32_t i, int second, mote_real *out0, mote_real *out1);

/* Pass 1 for target i: a_i = c_i sum A0, j_i = c_i sum A1. */
static void pass1_target(mote_nb *nb, int all, uint32_t i)
{
    const uint32_t n = nb->n;
    mote_real a[3] = {0, 0, 0}, j[3] = {0, 0, 0};
    if (nb->tree_on) {
        tree_target(nb, i, 0, nb->acc, nb->jerk);
        return;
    }
    if (nb->active[i]) {
        const nb_src src = {nb->x, nb->v, nb->acc, nb->jerk, nb->w, nb->active,
                            nb->soft * nb->soft};
        const mote_real *xi = nb->x + 3 * (size_t)i, *vi = nb->v + 3 * (size_t)i;
#ifdef NB_SSE2
        if (all) {
            pass1_sse2(&src, xi, vi, 0, i, a, j);
            pass1_sse2(&src, xi, vi, i + 1, n, a, j);
        } else
#endif
        {
            pass1_range(&src, all, xi, vi, 0, i, a, j);
            pass1_range(&src, all, xi, vi, i + 1, n, a, j);
        }
    }
    for (int c = 0; c < 3; c++) {
        nb->acc[3 * i + c] = nb->c[i] * a[c];
        nb->jerk[3 * i + c] = nb->c[i] * j[c];
    }
}

/* Every target through fn; OpenMP only where it pays (an OpenMP region costs an allocation and
 * a wake-up even on one thread), with the same bits either way. */
static void over_targets(mote_nb *nb, void (*fn)(mote_nb *, int, uint32_t))
{
    /* this rank's bodies (all of them on one process; spec 6.3) */
    const uint32_t lo = nb->mpi_size > 1 ? nb->lo : 0, hi = nb->mpi_size > 1 ? nb->hi : nb->n;
    const int nt = nb->threads > 1 ? nb->threads : 1, all = all_active(nb);
    if (nb->tree_on) { /* targets in tree order: neighbours share their sources in the cache */
        uint32_t na;
        const uint32_t *order = nb_tree_order(nb, &na);
        for (uint32_t i = 0; i < nb->n; i++)
            if (!nb->active[i])
                fn(nb, all, i);
#pragma omp parallel for num_threads(nt) schedule(dynamic, 64) if (nt > 1 && na >= nb->threads_min_n)
        for (uint32_t k = 0; k < na; k++)
            fn(nb, all, order[k]);
        return;
    }
    if (nt > 1 && hi - lo >= nb->threads_min_n) {
#pragma omp parallel for num_threads(nt) schedule(static)
        for (uint32_t i = lo; i < hi; i++)
            fn(nb, all, i);
    } else {
        for (uint32_t i = lo; i < hi; i++)
            fn(nb, all, i);
    }
}

/* Pass 1 (spec 4.2 step 1) over every target; with the tree, built here from the step's
 * starting positions, and the cells' x and v filled first. */
static void pass1(mote_nb *nb)
{
    if (nb->tree_on) {
        nb_tree_build(nb);
        nb_tree_fill(nb, 0, nb->x);
        nb_tree_fill(nb, 1, nb->v);
    }
    over_targets(nb, pass1_target);
    nb_mpi_gather(nb, nb->acc, 3);
    nb_mpi_gather(nb, nb->jerk, 3);
}

/* Pass 2 for the target at xi, vi, ai, ji over the sources k0 <= k < k1: the sums of A2, A3. */
static inline void pass2_range(const nb_src *s, int all, const mote_real *const t[4], uint32_t k0,
                               uint32_t k1, mote_real s4[3], mote_real s5[3])
{
    const mote_real *x = s->x, *v = s->v, *w = s->w, *A = s->A, *J = s->J;
    const mote_real *xi = t[0], *vi = t[1], *ai = t[2], *ji = t[3];
    for (uint32_t k = k0; k < k1; k++) {
        if (!all && !s->active[k])
            continue;
        const size_t o = 3 * (size_t)k;
        nb_pair2(xi, vi, ai, ji, x + o, v + o, A + o, J + o, w[k], s->e2, s4, s5);
    }
}

#ifdef NB_SSE2
static inline __m128d dot3(const __m128d p[3], const __m128d q[3])
{
    return _mm_add_pd(_mm_add_pd(_mm_mul_pd(p[0], q[0]), _mm_mul_pd(p[1], q[1])),
                      _mm_mul_pd(p[2], q[2]));
}

/* pass2_range for double with SSE2, lanes as in pass1_sse2. */
static inline void pass2_sse2(const nb_src *s, const double *const t[4], uint32_t k0, uint32_t k1,
                              mote_real s4[3], mote_real s5[3])
{
    const double *x = s->x, *v = s->v, *w = s->w, *A = s->A, *J = s->J;
    __m128d XI[3], VI[3], AI[3], JI[3], S4[3], S5[3];
    for (int c = 0; c < 3; c++) {
        XI[c] = _mm_set1_pd(t[0][c]);
        VI[c] = _mm_set1_pd(t[1][c]);
        AI[c] = _mm_set1_pd(t[2][c]);
        JI[c] = _mm_set1_pd(t[3][c]);
        S4[c] = S5[c] = _mm_setzero_pd();
    }
    const __m128d one = _mm_set1_pd(1), three = _mm_set1_pd(3), four = _mm_set1_pd(4),
                  six = _mm_set1_pd(6), nine = _mm_set1_pd(9), E2 = _mm_set1_pd(s->e2);
    uint32_t k = k0;
    for (; k + 1 < k1; k += 2) {
        const size_t o = 3 * (size_t)k;
        __m128d r[3], u[3], ac[3], jc[3];
        load2(x + o, r);
        load2(v + o, u);
        load2(A + o, ac);
        load2(J + o, jc);
        for (int c = 0; c < 3; c++) {
            r[c] = _mm_sub_pd(XI[c], r[c]);
            u[c] = _mm_sub_pd(VI[c], u[c]);
            ac[c] = _mm_sub_pd(AI[c], ac[c]);
            jc[c] = _mm_sub_pd(JI[c], jc[c]);
        }
        __m128d r2 = _mm_add_pd(dot3(r, r), E2);
        __m128d i2 = _mm_div_pd(one, r2);
        __m128d wr3 = _mm_mul_pd(_mm_mul_pd(_mm_loadu_pd(w + k), i2), _mm_sqrt_pd(i2));
        __m128d rv = dot3(r, u), vv = dot3(u, u), ra = dot3(r, ac), va = dot3(u, ac),
                rj = dot3(r, jc);
        __m128d alpha = _mm_mul_pd(rv, i2);
        __m128d beta = _mm_add_pd(_mm_mul_pd(_mm_add_pd(vv, ra), i2), _mm_mul_pd(alpha, alpha));
        __m128d gamma = _mm_add_pd(
            _mm_mul_pd(_mm_add_pd(_mm_mul_pd(three, va), rj), i2),
            _mm_mul_pd(alpha, _mm_sub_pd(_mm_mul_pd(three, beta),
                                         _mm_mul_pd(_mm_mul_pd(four, alpha), alpha))));
        const __m128d a3 = _mm_mul_pd(three, alpha), a6 = _mm_mul_pd(six, alpha),
                      a9 = _mm_mul_pd(nine, alpha), b3 = _mm_mul_pd(three, beta),
                      b9 = _mm_mul_pd(nine, beta), g3 = _mm_mul_pd(three, gamma);
        for (int c = 0; c < 3; c++) {
            __m128d A0 = _mm_mul_pd(wr3, r[c]);
            __m128d A1 = _mm_sub_pd(_mm_mul_pd(wr3, u[c]), _mm_mul_pd(a3, A0));
            __m128d A2 = _mm_sub_pd(_mm_sub_pd(_mm_mul_pd(wr3, ac[c]), _mm_mul_pd(a6, A1)),
                                    _mm_mul_pd(b3, A0));
            __m128d A3 = _mm_sub_pd(
                _mm_sub_pd(_mm_sub_pd(_mm_mul_pd(wr3, jc[c]), _mm_mul_pd(a9, A2)),
                           _mm_mul_pd(b9, A1)),
                _mm_mul_pd(g3, A0));
            S4[c] = _mm_add_pd(S4[c], A2);
            S5[c] = _mm_add_pd(S5[c], A3);
        }
    }
    for (int c = 0; c < 3; c++) {
        s4[c] += hsum(S4[c]);
        s5[c] += hsum(S5[c]);
    }
    if (k < k1)
        pass2_range(s, 1, t, k, k1, s4, s5);
}
#endif

/* Tree forces (spec 6.2): the passes over target i's interaction list, bodies and cells (whose
 * x, v, a, j are the cell data blocks 0 to 3). Without memory for a list: the walk itself,
 * calling the pair terms source by source. */
typedef struct {
    const mote_nb *nb;
    uint32_t i;
    int second;
    mote_real s[2][3];
} tree_sum;

static void visit(uint32_t k, int cell, void *arg)
{
    tree_sum *q = arg;
    const mote_nb *nb = q->nb;
    const size_t oi = 3 * (size_t)q->i, o = 3 * (size_t)k;
    const mote_real *src[4] = {nb->x, nb->v, nb->acc, nb->jerk};
    if (cell)
        for (int b = 0; b < 4; b++)
            src[b] = nb_tree_block(nb, b);
    const mote_real w = cell ? nb_tree_weight(nb, k) : nb->w[k];
    if (q->second)
        nb_pair2(nb->x + oi, nb->v + oi, nb->acc + oi, nb->jerk + oi, src[0] + o, src[1] + o,
                 src[2] + o, src[3] + o, w, nb->soft * nb->soft, q->s[0], q->s[1]);
    else
        nb_pair1(nb->x + oi, nb->v + oi, src[0] + o, src[1] + o, w, nb->soft * nb->soft, q->s[0],
                 q->s[1]);
}

/* The list's sources gathered into contiguous arrays in list order, then summed by the direct
 * passes' kernels (in double precision two sources at a time in SSE2 lanes): a fixed order. */
static void tree_target(mote_nb *nb, uint32_t i, int second, mote_real *out0, mote_real *out1)
{
    mote_real s0[3] = {0, 0, 0}, s1[3] = {0, 0, 0};
    uint32_t *src = NULL;
    size_t cap = 0, n = nb->active[i] ? nb_tree_list(nb, i, &src, &cap) : 0;
    const int blocks = second ? 4 : 2;
    mote_real *g = n && n != (size_t)-1 ? malloc(n * (3 * (size_t)blocks + 1) * sizeof *g) : NULL;
    const size_t oi = 3 * (size_t)i;
    if (nb->active[i] && !g && n != 0) { /* out of memory: the walk itself */
        tree_sum q = {nb, i, second, {{0, 0, 0}, {0, 0, 0}}};
        nb_tree_walk(nb, i, visit, &q);
        memcpy(s0, q.s[0], sizeof s0);
        memcpy(s1, q.s[1], sizeof s1);
    } else if (n) {
        const mote_real *cell[4] = {nb_tree_block(nb, 0), nb_tree_block(nb, 1),
                                    nb_tree_block(nb, 2), nb_tree_block(nb, 3)};
        const mote_real *body[4] = {nb->x, nb->v, nb->acc, nb->jerk};
        mote_real *w = g + 3 * (size_t)blocks * n;
        for (size_t k = 0; k < n; k++) {
            const uint32_t sidx = src[k] & ~NB_TREE_CELL;
            const int isc = (src[k] & NB_TREE_CELL) != 0;
            for (int b = 0; b < blocks; b++)
                memcpy(g + (size_t)b * 3 * n + 3 * k, (isc ? cell[b] : body[b]) + 3 * (size_t)sidx,
                       3 * sizeof *g);
            w[k] = isc ? nb_tree_weight(nb, sidx) : nb->w[sidx];
        }
        const nb_src gs = {g, g + 3 * n, second ? g + 6 * n : NULL, second ? g + 9 * n : NULL, w,
                           NULL, nb->soft * nb->soft};
        const mote_real *const t[4] = {nb->x + oi, nb->v + oi, nb->acc + oi, nb->jerk + oi};
#ifdef NB_SSE2
        if (second)
            pass2_sse2(&gs, t, 0, (uint32_t)n, s0, s1);
        else
            pass1_sse2(&gs, t[0], t[1], 0, (uint32_t)n, s0, s1);
#else
        if (second)
            pass2_range(&gs, 1, t, 0, (uint32_t)n, s0, s1);
        else
            pass1_range(&gs, 1, t[0], t[1], 0, (uint32_t)n, s0, s1);
#endif
    }
    free(g);
    free(src);
    for (int c = 0; c < 3; c++) {
        out0[oi + c] = nb->c[i] * s0[c];
        out1[oi + c] = nb->c[i] * s1[c];
    }
}

/* Pass 2 for target i: d4_i = c_i sum A2, d5_i = c_i sum A3 from the relative acceleration and
 * jerk of pass 1 (spec 4.2 step 2); r, alpha and r^3 are recomputed, not stored. */
static void pass2_target(mote_nb *nb, int all, uint32_t i)
{
    const uint32_t n = nb->n;
    mote_real s4[3] = {0, 0, 0}, s5[3] = {0, 0, 0};
    if (nb->tree_on) {
        tree_target(nb, i, 1, nb->d4, nb->d5);
        return;
    }
    if (nb->active[i]) {
        const nb_src src = {nb->x, nb->v, nb->acc, nb->jerk, nb->w, nb->active,
                            nb->soft * nb->soft};
        const size_t oi = 3 * (size_t)i;
        const mote_real *const t[4] = {nb->x + oi, nb->v + oi, nb->acc + oi, nb->jerk + oi};
#ifdef NB_SSE2
        if (all) {
            pass2_sse2(&src, t, 0, i, s4, s5);
            pass2_sse2(&src, t, i + 1, n, s4, s5);
        } else
#endif
        {
            pass2_range(&src, all, t, 0, i, s4, s5);
            pass2_range(&src, all, t, i + 1, n, s4, s5);
        }
    }
    for (int c = 0; c < 3; c++) {
        nb->d4[3 * i + c] = nb->c[i] * s4[c];
        nb->d5[3 * i + c] = nb->c[i] * s5[c];
    }
}

static void pass2(mote_nb *nb)
{
    if (nb->tree_on) { /* the cells' acceleration and jerk from pass 1 */
        nb_tree_fill(nb, 2, nb->acc);
        nb_tree_fill(nb, 3, nb->jerk);
    }
    over_targets(nb, pass2_target);
    nb_mpi_gather(nb, nb->d4, 3);
    nb_mpi_gather(nb, nb->d5, 3);
}

/* Does a pair approach contact within h (spec 4.7)? |r| - |v| h - |a| h^2 / 2 < Ra_i + Ra_k,
 * with the relative position, velocity and acceleration. */
static int approaching(const mote_nb *nb, mote_real h)
{
    /* a bound for every pair first: no pair can come closer than |r| - D */
    mote_real vmax = 0, amax = 0, rmax = 0;
    for (uint32_t i = 0; i < nb->n; i++) {
        if (!nb->active[i] || !(nb->ra[i] > 0))
            continue;
        const mote_real *v = nb->v + 3 * (size_t)i, *a = nb->acc + 3 * (size_t)i;
        vmax = fmax(vmax, v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        amax = fmax(amax, a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        rmax = fmax(rmax, nb->ra[i]);
    }
    const mote_real D = 2 * rmax + 2 * sqrt(vmax) * h + sqrt(amax) * h * h;
    for (uint32_t i = 0; i < nb->n; i++) {
        if (!nb->active[i] || !(nb->ra[i] > 0))
            continue;
        for (uint32_t k = i + 1; k < nb->n; k++) {
            if (!nb->active[k] || !(nb->ra[k] > 0))
                continue;
            mote_real r2 = 0, v2 = 0, a2 = 0;
            for (int c = 0; c < 3; c++) {
                mote_real dr = nb->x[3 * i + c] - nb->x[3 * k + c];
                r2 += dr * dr;
            }
            if (r2 >= D * D)
                continue;
            for (int c = 0; c < 3; c++) {
                mote_real dv = nb->v[3 * i + c] - nb->v[3 * k + c];
                mote_real da = nb->acc[3 * i + c] - nb->acc[3 * k + c];
                v2 += dv * dv;
                a2 += da * da;
            }
            if (sqrt(r2) - sqrt(v2) * h - 0.5 * sqrt(a2) * h * h < nb->ra[i] + nb->ra[k])
                return 1;
        }
    }
    return 0;
}

/* The step after the close-approach control (spec 4.7): while a pair approaches contact the
 * step is multiplied by bt, not below bt_hmin dt; after an approach it grows by 1/bt per step
 * back to the nominal h. */
static mote_real approach_step(mote_nb *nb, mote_real h)
{
    const mote_real nominal = h, hmin = nb->bt_hmin * nb->dt;
    if (nb->happ > 0 && nb->happ / nb->bt < h)
        h = nb->happ / nb->bt;
    while (h > hmin && approaching(nb, h))
        h = fmax(h * nb->bt, hmin);
    nb->happ = h < nominal ? h : 0;
    return h;
}

/* The adaptive step (spec 4.5, Galactica's Kl4 = 2 or 3): for each body the step at which its
 * two highest terms, x^[5] = d5/120 and x^[6] = p/720 (p the sixth derivative from the last two
 * fifth derivatives), stay below tol times the distance to its nearest neighbour; the smallest
 * times safety, at most twice the previous step, within [hmin, hmax]. */
static mote_real adaptive_step(mote_nb *nb)
{
    const uint32_t n = nb->n;
    mote_real h = INFINITY;
    for (uint32_t i = 0; i < n; i++) {
        if (!nb->active[i])
            continue;
        const mote_real *xi = nb->x + 3 * (size_t)i;
        mote_real l2 = INFINITY;
        for (uint32_t k = 0; k < n; k++) {
            if (k == i || !nb->active[k])
                continue;
            const mote_real *xk = nb->x + 3 * (size_t)k;
            const mote_real d0 = xi[0] - xk[0], d1 = xi[1] - xk[1], d2 = xi[2] - xk[2];
            l2 = fmin(l2, d0 * d0 + d1 * d1 + d2 * d2);
        }
        const mote_real l = isfinite(l2) ? sqrt(l2) : 1;
        mote_real n5 = 0, n6 = 0;
        for (int c = 0; c < 3; c++) {
            const size_t o = 3 * (size_t)i + c;
            n5 = fmax(n5, fabs(nb->d5[o]) / 120);
            n6 = fmax(n6, fabs((nb->d5[o] - nb->d5p[o]) / nb->dtp) / 720);
        }
        if (n5 > 0)
            h = fmin(h, pow(nb->tol * l / n5, (mote_real)1 / 5));
        if (n6 > 0)
            h = fmin(h, pow(nb->tol * l / n6, (mote_real)1 / 6));
    }
    return nb_step_bounds(nb, h, nb->dt);
}

/* One step of length h (nominal: the close-approach control may shorten it; 0: the adaptive
 * step), not beyond rest; returns the length taken. */
static mote_real step(mote_nb *nb, mote_real h, mote_real rest)
{
    pass1(nb);
    if (nb->order >= 4)
        pass2(nb);
    const int adaptive = h == 0;
    if (adaptive)
        h = adaptive_step(nb);
    if (nb->bt < 1 && nb_merging_on(nb))
        h = approach_step(nb, h);
    if (h > rest)
        h = rest;
    const int K = nb->order;
    const int have6 = K >= 6 && nb->dtp > 0;
    for (uint32_t i = 0; i < nb->n; i++) {
        if (!nb->active[i])
            continue;
        for (int c = 0; c < 3; c++) {
            const size_t o = 3 * (size_t)i + c;
            mote_real d[7] = {0, nb->v[o], nb->acc[o], nb->jerk[o], 0, 0, 0};
            if (K >= 4) {
                d[4] = nb->d4[o];
                d[5] = nb->d5[o];
            }
            if (have6)
                d[6] = (nb->d5[o] - nb->d5p[o]) / nb->dtp;
            /* from the highest term down: dx = sum_{k=1..K} d_k h^k / k!, dv = sum_{k=2..K}
             * d_k h^(k-1) / (k-1)! */
            mote_real dx = 0, dv = 0;
            for (int k = K; k >= 1; k--) {
                dx = dx * h / (k + 1) + d[k];
                if (k >= 2)
                    dv = dv * h / k + d[k];
            }
            dx *= h;
            dv *= h;
            kahan_add(&nb->x[o], &nb->xc[o], dx, nb->compensated);
            kahan_add(&nb->v[o], &nb->vc[o], dv, nb->compensated);
        }
    }
    memcpy(nb->d5p, nb->d5, 3 * (size_t)nb->n * sizeof *nb->d5p);
    nb->dtp = h;
    if (nb->adaptive && h < rest) /* a step shortened to an end time says nothing of the next */
        nb->hprev = h;
    nb->restart = 0;
    kahan_add(&nb->T, &nb->Tc, h, nb->compensated);
    nb->steps++;
    return h;
}

int mote_nb_derivatives(mote_nb *nb, mote_err *err)
{
    nb_mpi_layout(nb);
    int rc = mote_nb_prepare(nb, err);
    if (!rc)
        rc = nb_tree_check(nb, 4, err);
    if (rc)
        return rc;
    pass1(nb);
    pass2(nb);
    return MOTE_OK;
}

int nb_galactica_check(const mote_nb *nb, mote_err *err)
{
    if (nb->order < 2 || nb->order > 6)
        return mote_fail(err, MOTE_EINVAL, "galactica: order must be in 2 ... 6 (found %d)",
                         nb->order);
    if (!(nb->dt > 0) || !isfinite(nb->dt))
        return mote_fail(err, MOTE_EINVAL, "galactica: the step dt must be > 0");
    if (nb->adaptive && nb->order != 6)
        return mote_fail(err, MOTE_EINVAL, "galactica: the adaptive step (tol=) needs order 6 "
                                           "(found %d)", nb->order);
    if (nb->adaptive && !(nb->tol > 0 && nb->tol < 1))
        return mote_fail(err, MOTE_EINVAL, "galactica: tol must be in (0, 1)");
    if (nb->doubling && !(nb->dt_max >= nb->dt))
        return mote_fail(err, MOTE_EINVAL, "galactica: step=doubling needs dt_max >= dt");
    return MOTE_OK;
}

/* Galactica's literal step rule (spec 7.4, step=doubling) after a step: D = |dMz_n - dMz_(n-1)|
 * summed over non-overlapping blocks of 5 steps; when a block's mean exceeds 1.1 times the
 * previous block's, dt doubles (never above dt_max) and the next block is not compared; blocks
 * with a step shortened by a close approach (bt) are not compared either. */
static void doubling_rule(mote_nb *nb)
{
    const mote_real dmz = mote_nb_dmz(nb);
    if (nb->dbl_have) {
        nb->dbl_sum += fabs(dmz - nb->dbl_prev);
        nb->dbl_count++;
    }
    nb->dbl_prev = dmz;
    nb->dbl_have = 1;
    if (nb->happ > 0)
        nb->dbl_mean = -2; /* this block has an approach step: not compared */
    if (nb->dbl_count < 5)
        return;
    const mote_real mean = nb->dbl_sum / 5;
    nb->dbl_sum = 0;
    nb->dbl_count = 0;
    if (nb->dbl_mean >= 0 && mean > (mote_real)1.1 * nb->dbl_mean && nb->dt < nb->dt_max) {
        nb->dt = 2 * nb->dt < nb->dt_max ? 2 * nb->dt : nb->dt_max;
        nb->dbl_mean = -1; /* the first block after a change is not compared */
    } else {
        nb->dbl_mean = nb->dbl_mean == -2 ? -1 : mean;
    }
}

mote_real nb_galactica_step(mote_nb *nb, mote_real rest)
{
    const int fresh = nb->restart || nb->dtp == 0;
    if (fresh)
        nb->hprev = 0;
    mote_real h = fresh ? nb->first_step * nb->dt : nb->adaptive ? 0 : nb->dt;
    h = step(nb, h, rest);
    if (nb->doubling)
        doubling_rule(nb);
    return h;
}

int mote_nb_galactica(mote_nb *nb, uint64_t steps, mote_err *err)
{
    return nb_run_as(nb, MOTE_NB_GALACTICA, steps, err);
}
