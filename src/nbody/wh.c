/* wh.c: the Wisdom-Holman symplectic map in Jacobi coordinates (Wisdom & Holman 1991, AJ 102,
 * 1528), for long integrations of planetary systems: the Hamiltonian split into the Kepler
 * motions of the Jacobi coordinates about the interior masses and the interaction left over,
 * a step being drift(h/2) kick(h) drift(h/2). The drift is the exact Kepler flow in universal
 * variables (Stumpff functions); the symplectic correctors of Wisdom, Holman & Touma (1996,
 * Fields Inst. Commun. 10, 217) of order 3, 5, 7, 11 or 17 remove the map's error terms of
 * first order in the mass ratio; the split with the Kepler parameter mu_i = G eta_i and the
 * first pair left out of the interaction is that of Rein & Tamayo (2015, MNRAS 452, 376).
 *
 * The map runs in its own coordinates (the corrector applied, half a drift ahead: each step a
 * kick and a whole drift); where a run stops (its end, an output, every 1000 steps) a copy is
 * synchronised into the bodies' inertial x and v (half a drift back, the corrector undone), and
 * the map goes on from its own state while the bodies are those it left: where the runs stop
 * does not change a bit of the trajectory, and the state file carries the map (continuation bit
 * for bit). A run that ends at a time inside a step takes that last step alone, from and back to
 * inertial coordinates. The first active body is the central one. */
#include "mote/nbody.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>
#include <tgmath.h>

#include "nb.h"

/* the real type's rounding unit */
#if MOTE_NB_PRECISION == 4
#define REAL_EPS (ldexp((mote_real)1, -112))
#elif MOTE_NB_PRECISION == 2
#define REAL_EPS ((mote_real)LDBL_EPSILON)
#else
#define REAL_EPS ((mote_real)DBL_EPSILON)
#endif
#define FACT_N (2 * STUMPFF_TERMS + 2) /* 1/k! for k = 0 ... FACT_N - 1 */

/* ---- the Kepler drift ------------------------------------------------------------------------ */

/* Terms of the Stumpff series c_k(z) = sum_j (-z)^j / (k + 2j)! kept for |z| < 0.1: the first
 * term left out is below the real type's rounding (0.1^j / (2j + 3)!: 7e-19 at j = 7, 3e-22 at
 * j = 8, 6e-37 at j = 12). */
#if MOTE_NB_PRECISION == 4
#define STUMPFF_TERMS 12 /* (the series serves |z| < 0.1; closed forms from |z| = 1) */
#elif MOTE_NB_PRECISION == 2
#define STUMPFF_TERMS 8
#else
#define STUMPFF_TERMS 7
#endif

/* c0 ... c3 of z. Below |z| = 1: the series at z / 4^k with |z / 4^k| < 0.1 (k <= 2), then k
 * times the quadrupling rules c0(4z) = 2 c0^2 - 1, c1(4z) = c0 c1, c2(4z) = c1^2 / 2,
 * c3(4z) = (c2 + c0 c3) / 4 (Danby 1988, Fundamentals of Celestial Mechanics, 6.9); from 1 on,
 * the closed forms in sin and cos (z > 0) or sinh and cosh (z < 0) of s = sqrt(|z|), with
 * c2 = 2 sin^2(s/2) / z against the cancellation of 1 - cos s. */
static void stumpff(const mote_real *ifact, mote_real z, mote_real c[4])
{
    if (fabs(z) >= 1) {
        const mote_real s = sqrt(fabs(z));
        if (z > 0) {
            const mote_real sn = sin(s), h = sin(s / 2);
            c[0] = cos(s);
            c[1] = sn / s;
            c[2] = 2 * h * h / z;
            c[3] = (s - sn) / (z * s);
        } else {
            const mote_real sn = sinh(s), h = sinh(s / 2);
            c[0] = cosh(s);
            c[1] = sn / s;
            c[2] = 2 * h * h / -z;
            c[3] = (sn - s) / (-z * s);
        }
        return;
    }
    int k = 0;
    while (fabs(z) >= (mote_real)0.1) {
        z *= (mote_real)0.25;
        k++;
    }
    mote_real c2 = 0, c3 = 0;
    for (int j = STUMPFF_TERMS - 1; j >= 0; j--) {
        c2 = ifact[2 * j + 2] - z * c2;
        c3 = ifact[2 * j + 3] - z * c3;
    }
    mote_real c0 = 1 - z * c2, c1 = 1 - z * c3;
    for (; k > 0; k--) {
        mote_real n3 = (c2 + c0 * c3) * (mote_real)0.25;
        c2 = c1 * c1 * (mote_real)0.5;
        c1 = c0 * c1;
        c0 = 2 * c0 * c0 - 1;
        c3 = n3;
    }
    c[0] = c0;
    c[1] = c1;
    c[2] = c2;
    c[3] = c3;
}

/* Kepler's equation in the universal variable: h = r0 X + eta0 G2 + zeta0 G3 with G_k =
 * X^k c_k(beta X^2). */
typedef struct {
    mote_real r0, eta0, zeta0, beta, h;
    mote_real G1, G2, G3, rn; /* at the solution; rn = r0 + eta0 G1 + zeta0 G2 */
} kep_eq;

/* Halley's iteration from X, at most `iters` steps, kept inside [lo, hi] by bisection where
 * bracket is set; 1 when |dX| fell to the rounding of X (the G's then those of the X before
 * the last correction, which differ from the final X's by that rounding), else 0. */
static int halley(const mote_real *ifact, kep_eq *k, mote_real X, int iters, int bracket,
                  mote_real lo, mote_real hi)
{
    mote_real c[4];
    for (int it = 0; it < iters; it++) {
        const mote_real X2 = X * X;
        stumpff(ifact, k->beta * X2, c);
        k->G1 = X * c[1];
        k->G2 = X2 * c[2];
        k->G3 = X2 * X * c[3];
        const mote_real f = k->r0 * X + k->eta0 * k->G2 + k->zeta0 * k->G3 - k->h;
        k->rn = k->r0 + k->eta0 * k->G1 + k->zeta0 * k->G2;
        const mote_real fpp = k->eta0 * c[0] + k->zeta0 * k->G1;
        mote_real dX = -f / (k->rn - (mote_real)0.5 * f / k->rn * fpp);
        if (bracket) {
            if (f < 0)
                lo = X;
            else if (f > 0)
                hi = X;
            if (!(X + dX > lo && X + dX < hi))
                dX = (lo + hi) / 2 - X; /* bisect */
        }
        X += dX;
        if (!(fabs(dX) > 4 * REAL_EPS * fabs(X)))
            return k->rn > 0;
        if (!isfinite(X))
            return 0;
    }
    return 0;
}

/* The Kepler flow of (r, v) about mu for a time h: Kepler's equation solved by Halley's
 * iteration from X = h / r0 - h^2 eta0 / (2 r0^3); where 8 steps do not converge (long steps,
 * near-radial or fast orbits) a bound orbit's h is reduced by whole periods and the iteration
 * kept inside a bracket (dX/dt = 1/r: X between 0 and h / r_p, with r_p = L^2 / (mu + sqrt(mu^2
 * - beta L^2)) the pericentre distance) by bisection. Then the f and g functions. Returns 0, or
 * -1 when the iteration did not converge (the state is left unchanged). */
static int kepler(const mote_real *ifact, mote_real *r, mote_real *v, mote_real mu, mote_real h)
{
    const mote_real r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    const mote_real r0 = sqrt(r2), ir0 = 1 / r0;
    const mote_real eta0 = r[0] * v[0] + r[1] * v[1] + r[2] * v[2];
    const mote_real v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    const mote_real beta = 2 * mu * ir0 - v2;
    kep_eq k = {r0, eta0, mu - beta * r0, beta, h, 0, 0, 0, 0};
    const mote_real X0 = h * ir0 * (1 - (mote_real)0.5 * h * eta0 * ir0 * ir0);
    if (!halley(ifact, &k, X0, 8, 0, 0, 0)) {
        if (beta > 0) { /* bound: whole periods 2 pi mu / beta^(3/2) change nothing */
            const mote_real P = 8 * atan((mote_real)1) * mu / (beta * sqrt(beta));
            if (fabs(h) > P)
                k.h = h - P * trunc(h / P);
        }
        const mote_real L2 = r2 * v2 - eta0 * eta0;
        const mote_real disc = mu * mu - beta * (L2 > 0 ? L2 : 0);
        const mote_real rp = L2 > 0 ? L2 / (mu + sqrt(disc > 0 ? disc : 0)) : 0;
        const mote_real lo = k.h >= 0 ? 0 : rp > 0 ? k.h / rp : -INFINITY;
        const mote_real hi = k.h >= 0 ? (rp > 0 ? k.h / rp : INFINITY) : 0;
        const int bracket = isfinite(lo) && isfinite(hi);
        mote_real X = k.h * ir0;
        if (bracket && !(X > lo && X < hi))
            X = (lo + hi) / 2;
        if (!halley(ifact, &k, X, 200, bracket, lo, hi))
            return -1;
    }
    const mote_real fm1 = -mu * k.G2 * ir0, g = k.h - mu * k.G3;
    const mote_real fd = -mu * k.G1 * ir0 / k.rn, gdm1 = -mu * k.G2 / k.rn;
    for (int a = 0; a < 3; a++) {
        const mote_real ra = r[a], va = v[a];
        r[a] = ra + (fm1 * ra + g * va);
        v[a] = va + (fd * ra + gdm1 * va);
    }
    return 0;
}

/* ---- the map's parts on the active bodies, packed ------------------------------------------ */

typedef struct {
    uint32_t n;            /* active bodies */
    uint32_t *idx;         /* their indices in nb */
    mote_real *m, *eta;    /* masses, eta_i = m_0 + ... + m_i */
    mote_real *q, *u;      /* Jacobi positions and velocities (q_0, u_0: the centre of mass) */
    mote_real *x, *a;      /* inertial positions and accelerations (the kick's scratch) */
    int failed;            /* a Kepler drift did not converge */
    mote_real ifact[FACT_N];
} wh_state;

static void wh_free(wh_state *w)
{
    free(w->idx);
    free(w->m);
}

static int wh_alloc(wh_state *w, const mote_nb *nb)
{
    memset(w, 0, sizeof *w);
    uint32_t n = 0;
    for (uint32_t i = 0; i < nb->n; i++)
        n += nb->active[i] != 0;
    const size_t nn = n ? n : 1;
    w->idx = malloc(nn * sizeof *w->idx);
    w->m = malloc(14 * nn * sizeof *w->m);
    if (!w->idx || !w->m) {
        wh_free(w);
        return -1;
    }
    w->eta = w->m + nn;
    w->q = w->eta + nn;
    w->u = w->q + 3 * nn;
    w->x = w->u + 3 * nn;
    w->a = w->x + 3 * nn;
    w->ifact[0] = 1;
    for (int k = 1; k < FACT_N; k++)
        w->ifact[k] = w->ifact[k - 1] / k;
    for (uint32_t i = 0; i < nb->n; i++)
        if (nb->active[i]) {
            w->idx[w->n] = i;
            w->m[w->n] = nb->w[i]; /* gravity: the mass, G = 1 */
            w->eta[w->n] = w->m[w->n] + (w->n ? w->eta[w->n - 1] : 0);
            w->n++;
        }
    return 0;
}

/* Jacobi coordinates of inertial ones (positions or velocities, 3 per body): the body less the
 * centre of mass of those before it; the total centre of mass in slot 0. */
static void to_jacobi(const wh_state *w, const mote_real *in, mote_real *out)
{
    mote_real s[3] = {w->m[0] * in[0], w->m[0] * in[1], w->m[0] * in[2]};
    for (uint32_t i = 1; i < w->n; i++) {
        const mote_real ie = 1 / w->eta[i - 1];
        for (int c = 0; c < 3; c++) {
            out[3 * i + c] = in[3 * i + c] - s[c] * ie;
            s[c] += w->m[i] * in[3 * i + c];
        }
    }
    const mote_real ie = 1 / w->eta[w->n - 1];
    for (int c = 0; c < 3; c++)
        out[c] = s[c] * ie;
}

/* The inverse: R_(i-1) = R_i - (m_i / eta_i) q_i from the centre of mass R_(n-1) down, and
 * x_i = q_i + R_(i-1). */
static void from_jacobi(const wh_state *w, const mote_real *in, mote_real *out)
{
    mote_real R[3] = {in[0], in[1], in[2]};
    for (uint32_t i = w->n - 1; i >= 1; i--) {
        const mote_real f = w->m[i] / w->eta[i];
        for (int c = 0; c < 3; c++) {
            R[c] -= f * in[3 * i + c];
            out[3 * i + c] = in[3 * i + c] + R[c];
        }
    }
    for (int c = 0; c < 3; c++)
        out[c] = R[c];
}

/* The drift: each Jacobi coordinate's Kepler flow about mu_i = eta_i (G = 1); the centre of mass
 * moves on a straight line. */
static void drift(wh_state *w, mote_real h)
{
    for (uint32_t i = 1; i < w->n; i++)
        if (kepler(w->ifact, w->q + 3 * i, w->u + 3 * i, w->eta[i], h))
            w->failed = 1;
    for (int c = 0; c < 3; c++)
        w->q[c] += h * w->u[c];
}

/* The kick: the interaction's accelerations in Jacobi coordinates, from the inertial ones
 * without the pair of the first two bodies (its force is body 1's Kepler motion), less the
 * Kepler terms -eta_i q_i / |q_i|^3 of the bodies from 2 on. */
static void kick(wh_state *w, mote_real h)
{
    const uint32_t n = w->n;
    mote_real *restrict x = w->x, *restrict a = w->a;
    from_jacobi(w, w->q, x);
    memset(a, 0, 3 * (size_t)n * sizeof *a);
    for (uint32_t i = 0; i < n; i++) {
        mote_real ai[3] = {0, 0, 0};
        for (uint32_t k = i + 1; k < n; k++) {
            if (i == 0 && k == 1)
                continue;
            const mote_real d0 = x[3 * k] - x[3 * i], d1 = x[3 * k + 1] - x[3 * i + 1],
                            d2 = x[3 * k + 2] - x[3 * i + 2];
            const mote_real r2 = d0 * d0 + d1 * d1 + d2 * d2;
            const mote_real ir3 = 1 / (r2 * sqrt(r2));
            const mote_real fi = w->m[k] * ir3, fk = w->m[i] * ir3;
            ai[0] += fi * d0;
            ai[1] += fi * d1;
            ai[2] += fi * d2;
            a[3 * k] -= fk * d0;
            a[3 * k + 1] -= fk * d1;
            a[3 * k + 2] -= fk * d2;
        }
        a[3 * i] += ai[0];
        a[3 * i + 1] += ai[1];
        a[3 * i + 2] += ai[2];
    }
    mote_real s[3] = {w->m[0] * a[0], w->m[0] * a[1], w->m[0] * a[2]};
    for (uint32_t i = 1; i < n; i++) {
        const mote_real ie = 1 / w->eta[i - 1];
        mote_real kq = 0;
        const mote_real *q = w->q + 3 * i;
        if (i >= 2) {
            const mote_real q2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
            kq = w->eta[i] / (q2 * sqrt(q2));
        }
        for (int c = 0; c < 3; c++) {
            const mote_real aj = a[3 * i + c] - s[c] * ie + kq * q[c];
            s[c] += w->m[i] * a[3 * i + c];
            w->u[3 * i + c] += h * aj;
        }
    }
}

/* ---- the correctors (Wisdom, Holman & Touma 1996) ------------------------------------------ */

/* Z(a, b) = drift(a) kick(-b) drift(-2a) kick(b) drift(a) */
static void corrector_z(wh_state *w, mote_real a, mote_real b)
{
    drift(w, a);
    kick(w, -b);
    drift(w, -2 * a);
    kick(w, b);
    drift(w, a);
}

/* The coefficients b_(k, j) of the corrector of order k (WHT96; the values as tabulated with
 * 50 digits by Rein, Tamayo & Brown 2019, MNRAS 489, 4632); a_j = j sqrt(7/40). */
static const double B3[] = {-0.024900596027799867499350357910273437184309981229127};
static const double B5[] = {-0.0083001986759332891664501193034244790614366604097090,
                            0.041500993379666445832250596517122395307183302048545};
static const double B7[] = {0.0024926811426922105779030593952776964450539008582219,
                            -0.018270923246702131478062356884535264841652263842597,
                            0.053964399093127498721765893493510877532452806339655};
static const double B11[] = {0.00020361579647854651301632818774633716473696537436847,
                             -0.0023487215292295354188307328851055489876255097419754,
                             0.012309078592019946317544564763237909911330686448336,
                             -0.038121613681288650508647613260247372125243616270670,
                             0.072593394748842738674253180742744961827622366521517};
static const double B17[] = {-0.0000043347415473373580190650223498124944896789841432241,
                             0.000076436355227935738363241846979413475106795392377415,
                             -0.00063599983075817658983166881625078545864140848560259,
                             0.0033132577069380655655490196833451994080066801611459,
                             -0.012071760822342291062449751726959664253913904872527,
                             0.032422198864713580293681523029577130832258806467604,
                             -0.065192863576377893658290760803725762027864651086787,
                             0.093056103771425958591541059067553547100903397724386};

/* The corrector of order k (sign +1) or its inverse (-1) for the step h: for the J coefficients
 * b_1 ... b_J (b_J nearest the middle), Z(-a_(J+1-j) h, -s b_j h) for j = 1 ... J, then the
 * mirror Z(a_(J+1-j) h, s b_j h) for j = J ... 1; the third order has the mirror first. */
static void corrector(wh_state *w, int order, int s, mote_real h)
{
    const double *b;
    int J;
    switch (order) {
    case 3: b = B3; J = 1; break;
    case 5: b = B5; J = 2; break;
    case 7: b = B7; J = 3; break;
    case 11: b = B11; J = 5; break;
    case 17: b = B17; J = 8; break;
    default: return;
    }
    const mote_real a1 = sqrt((mote_real)7 / 40);
    const mote_real sg = order == 3 ? -1 : 1;
    for (int j = 0; j < J; j++)
        corrector_z(w, -sg * (J - j) * a1 * h, -s * (mote_real)b[j] * h);
    for (int j = J - 1; j >= 0; j--)
        corrector_z(w, sg * (J - j) * a1 * h, s * (mote_real)b[j] * h);
}

/* ---- the run -------------------------------------------------------------------------------- */

int nb_wh_check(const mote_nb *nb, mote_err *err)
{
    if (nb->kind != MOTE_NB_GRAVITY)
        return mote_fail(err, MOTE_EINVAL, "integrator wh: the Wisdom-Holman map is for gravity "
                                           "(this system is Coulomb): use taylor or galactica");
    if (!(nb->dt > 0) || !isfinite(nb->dt))
        return mote_fail(err, MOTE_EINVAL, "integrator wh: the step dt must be > 0");
    const int k = nb->wh_corrector;
    if (k != 0 && k != 3 && k != 5 && k != 7 && k != 11 && k != 17)
        return mote_fail(err, MOTE_EINVAL, "integrator wh: corrector must be 0, 3, 5, 7, 11 or "
                                           "17 (found %d)", k);
    if (nb->tree_on)
        return mote_fail(err, MOTE_EINVAL, "integrator wh: the map sums its interaction directly "
                                           "(forces tree is for the Taylor integrators)");
    if (nb->soft > 0)
        return mote_fail(err, MOTE_EINVAL, "integrator wh: the map's Kepler drifts are those of "
                                           "point masses: softening is for taylor or galactica "
                                           "(softening eps=0 turns it off)");
    return MOTE_OK;
}

/* Per body in nb->wh_map: q (3), u (3), then the x, v and mass it was synchronised to. */
#define MAP_PER 13

/* Is the map of nb live for this step and corrector, the bodies those it left (same activity,
 * masses, positions and velocities, bit for bit)? */
static int map_live(const mote_nb *nb, mote_real h)
{
    if (!nb->wh_live || nb->wh_h != h || nb->wh_k != nb->wh_corrector || nb->wh_cap < nb->n)
        return 0;
    for (uint32_t i = 0; i < nb->n; i++) {
        const mote_real *p = nb->wh_map + MAP_PER * (size_t)i;
        if (!nb->active[i]) {
            if (p[12] != 0)
                return 0;
            continue;
        }
        if (p[12] != nb->w[i])
            return 0;
        for (int c = 0; c < 3; c++)
            if (p[6 + c] != nb->x[3 * (size_t)i + c] || p[9 + c] != nb->v[3 * (size_t)i + c])
                return 0;
    }
    return 1;
}

/* Synchronise: from the map's state (half a drift ahead) a copy drifted back by h/2, the
 * corrector undone, to inertial coordinates in nb's x and v (the map's own state unchanged). */
static void synchronise(wh_state *w, mote_nb *nb, mote_real h, mote_real *q, mote_real *u)
{
    const size_t n3 = 3 * (size_t)w->n;
    memcpy(q, w->q, n3 * sizeof *q);
    memcpy(u, w->u, n3 * sizeof *u);
    mote_real *mq = w->q, *mu = w->u;
    w->q = q;
    w->u = u;
    drift(w, -h / 2);
    corrector(w, nb->wh_corrector, -1, h);
    from_jacobi(w, q, w->x);
    from_jacobi(w, u, w->a);
    w->q = mq;
    w->u = mu;
    for (uint32_t j = 0; j < w->n; j++)
        for (int c = 0; c < 3; c++) {
            const size_t o = 3 * (size_t)w->idx[j] + c;
            nb->x[o] = w->x[3 * j + c];
            nb->v[o] = w->a[3 * j + c];
            nb->xc[o] = 0;
            nb->vc[o] = 0;
        }
}

/* Into the map from nb's inertial state: Jacobi coordinates, the corrector, half a drift (the
 * kick's scratch x and a hold the inertial positions and velocities on the way). */
static void start_map(wh_state *w, const mote_nb *nb, mote_real h)
{
    for (uint32_t j = 0; j < w->n; j++)
        for (int c = 0; c < 3; c++) {
            w->x[3 * j + c] = nb->x[3 * (size_t)w->idx[j] + c];
            w->a[3 * j + c] = nb->v[3 * (size_t)w->idx[j] + c];
        }
    to_jacobi(w, w->x, w->q);
    to_jacobi(w, w->a, w->u);
    corrector(w, nb->wh_corrector, 1, h);
    drift(w, h / 2);
}

/* `steps` steps of h: a kick and a whole drift each (the state stays half a drift ahead). */
static void run_map(wh_state *w, uint64_t steps, mote_real h)
{
    for (uint64_t s = 0; s < steps; s++) {
        kick(w, h);
        drift(w, h);
    }
}

int nb_wh_integrate(mote_nb *nb, uint64_t max_steps, mote_real t_end, mote_err *err)
{
    const mote_real dt = nb->dt;
    /* the full steps that end before t_end, the time summed as the steps will sum it; an end
     * time within 10^-12 of the run's time scale of a step's end is that step's end (the
     * rounding of T + k dt must not make a step of the rounding error, nor a last step that
     * falls short of dt by it) */
    const int finite = t_end < INFINITY;
    const mote_real slack = finite ? (mote_real)1e-12 * fmax(fabs(t_end), dt) : 0;
    uint64_t full = 0;
    mote_real T = nb->T, Tc = nb->Tc;
    while (full < max_steps && (!finite || t_end - T > dt + slack)) {
        kahan_add(&T, &Tc, dt, nb->compensated);
        full++;
    }
    int snap = 0; /* T set to t_end after the full steps */
    if (finite && full < max_steps && fabs(t_end - T - dt) <= slack) {
        kahan_add(&T, &Tc, dt, nb->compensated);
        full++;
        snap = 1;
    } else if (finite && fabs(t_end - T) <= slack)
        snap = 1;
    const int last = !snap && finite && full < max_steps && t_end - T > 0;
    if (!full && !last) {
        if (snap) {
            nb->T = t_end;
            nb->Tc = 0;
        }
        return MOTE_OK;
    }
    wh_state w;
    if (wh_alloc(&w, nb))
        return mote_fail(err, MOTE_ENOMEM, "integrator wh: out of memory for %u bodies", nb->n);
    const size_t n3 = 3 * (size_t)(w.n ? w.n : 1);
    mote_real *tmp = malloc(2 * n3 * sizeof *tmp);
    if (!tmp || (nb->wh_cap < nb->n && !nb_wh_reserve(nb))) {
        free(tmp);
        wh_free(&w);
        return mote_fail(err, MOTE_ENOMEM, "integrator wh: out of memory for %u bodies", nb->n);
    }
    if (full && w.n >= 2) {
        if (map_live(nb, dt)) /* on from where the last run left the map */
            for (uint32_t j = 0; j < w.n; j++)
                for (int c = 0; c < 3; c++) {
                    const mote_real *p = nb->wh_map + MAP_PER * (size_t)w.idx[j];
                    w.q[3 * j + c] = p[c];
                    w.u[3 * j + c] = p[3 + c];
                }
        else
            start_map(&w, nb, dt);
        run_map(&w, full, dt);
        synchronise(&w, nb, dt, tmp, tmp + n3);
        /* the map kept, with what it synchronised to */
        memset(nb->wh_map, 0, MAP_PER * (size_t)nb->n * sizeof *nb->wh_map);
        for (uint32_t j = 0; j < w.n; j++) {
            mote_real *p = nb->wh_map + MAP_PER * (size_t)w.idx[j];
            for (int c = 0; c < 3; c++) {
                p[c] = w.q[3 * j + c];
                p[3 + c] = w.u[3 * j + c];
                p[6 + c] = nb->x[3 * (size_t)w.idx[j] + c];
                p[9 + c] = nb->v[3 * (size_t)w.idx[j] + c];
            }
            p[12] = w.m[j];
        }
        nb->wh_live = 1;
        nb->wh_h = dt;
        nb->wh_k = nb->wh_corrector;
    }
    if (last && w.n >= 2) { /* the step to the end time, alone: from and back to inertial */
        start_map(&w, nb, t_end - T);
        run_map(&w, 1, t_end - T);
        synchronise(&w, nb, t_end - T, tmp, tmp + n3);
        nb->wh_live = 0;
    }
    if (w.n == 1) { /* one body moves on a straight line */
        const size_t o = 3 * (size_t)w.idx[0];
        const mote_real span = (last ? t_end : T) - nb->T;
        for (int c = 0; c < 3; c++)
            nb->x[o + c] += span * nb->v[o + c];
        nb->wh_live = 0;
    }
    const int failed = w.failed;
    free(tmp);
    wh_free(&w);
    nb->steps += full + (uint64_t)last;
    nb->T = last || snap ? t_end : T;
    nb->Tc = last || snap ? 0 : Tc;
    nb->hlast = last ? t_end - T : dt;
    nb->dtp = 0; /* a Galactica step after this one restarts */
    nb->restart = 1;
    if (failed) {
        nb->wh_live = 0;
        return mote_fail(err, MOTE_ERUNTIME, "integrator wh: Kepler's equation did not converge "
                         "in a drift before t = %.17g (an orbit too close to the central body "
                         "for the step, or unbound: a smaller dt, or the taylor integrator)",
                         (double)nb->T);
    }
    return MOTE_OK;
}

int nb_wh_reserve(mote_nb *nb)
{
    if (nb->wh_cap >= nb->n)
        return 1;
    mote_real *p = realloc(nb->wh_map, MAP_PER * (size_t)(nb->n ? nb->n : 1) * sizeof *p);
    if (!p)
        return 0;
    nb->wh_map = p;
    nb->wh_cap = nb->n;
    nb->wh_live = 0;
    return 1;
}

mote_real *nb_wh_map(const mote_nb *nb, uint32_t i)
{
    return nb->wh_map + MAP_PER * (size_t)i;
}
