/* contact.c: the Hertz-Mindlin contact law (no-slip) with a tangential spring history and
 * Coulomb friction (issue 56, item 1), as LIGGGHTS's `gran model hertz tangential history`
 * defines it (its documentation's formulas; the constants per pair from Young's moduli, Poisson
 * ratios, restitution and friction). The law itself, sep_hm_force, is inline in sep.h (the pair
 * loop's cost is there); here the constants and the damping for a restitution. The pair loop,
 * the walls, rotation and the state file take it in (dem.c); the tests drive it with a
 * two-body integrator of their own.
 *
 *   Y* = 1 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)      G* = 1 / (2 (2 - nu1)(1 + nu1)/E1 + ...)
 *   R* = R1 R2 / (R1 + R2)                          m* = m1 m2 / (m1 + m2)
 *   S_n = 2 Y* sqrt(R* delta)    k_n = 4/3 Y* sqrt(R* delta)    gamma_n = -2 sqrt(5/6) beta sqrt(S_n m*)
 *   S_t = 8 G* sqrt(R* delta)    k_t = S_t                      gamma_t = -2 sqrt(5/6) beta sqrt(S_t m*)
 *   beta = ln e / sqrt(ln^2 e + pi^2)
 *   F_n = (k_n delta - gamma_n v_n) n,   F_t = -k_t xi - gamma_t v_t,   |F_t| <= mu |F_n|
 *
 * with v_n, v_t the normal and tangential parts of the contact point's relative velocity and xi
 * the tangential displacement since the contact began (rotated onto the tangent plane each
 * step); when |F_t| would exceed mu |F_n| the contact slides: F_t is cut to mu |F_n| (its
 * direction kept) and xi set to give that force by the spring alone, -F_t / k_t. (LIGGGHTS cuts
 * only the spring's part and lets the dashpot add to it, so its tangential impulse can exceed
 * mu times the normal one; here it cannot.) A wall: R2 and m2 infinite.
 *
 * Measured (tests/test_sep_contact.c, a sphere on a wall): the rebound's restitution does not
 * depend on the impact speed (0.5 and 2 m/s alike to 6 digits), but it is not the e given:
 * 0.397, 0.550, 0.902 for e = 0.3, 0.5, 0.9 (the mapping beta(e) is exact for a linear spring,
 * not for Hertz's); in gross sliding the tangential impulse is mu times the normal one to
 * rounding. */
#include "sep.h"

#include <math.h>

void sep_hm_pair(sep_hm *h, const sep_material *a, double R1, double m1, const sep_material *b,
                 double R2, double m2, double e, double mu)
{
    h->Y = 1 / ((1 - a->nu * a->nu) / a->E + (1 - b->nu * b->nu) / b->E);
    h->G = 1 / (2 * (2 - a->nu) * (1 + a->nu) / a->E + 2 * (2 - b->nu) * (1 + b->nu) / b->E);
    h->R = isinf(R2) ? R1 : R1 * R2 / (R1 + R2);
    h->m = isinf(m2) ? m1 : m1 * m2 / (m1 + m2);
    h->mu = mu;
    sep_hm_damping(h, sep_hm_beta_liggghts(e));
}

void sep_hm_damping(sep_hm *h, double beta)
{
    h->beta = beta;
    h->cn = -2 * sqrt(5.0 / 6.0) * beta * sqrt(2 * h->Y);
    h->gr = sqrt(4 * h->G / h->Y);
}

double sep_hm_beta_liggghts(double e)
{
    const double l = log(e);
    return e < 1 ? l / sqrt(l * l + SEP_PI * SEP_PI) : 0;
}

double sep_hm_contact_time(double Y, double R, double m, double v)
{
    return 2.868 * pow(m * m / (R * Y * Y * v), 0.2);
}

/* The head-on impact in units where Y* = R* = m* = 1 and the speed 1: the overlap u obeys
 * u'' = -max(0, 4/3 u^(3/2) + c sqrt(2) u^(1/4) u'), c = -2 sqrt(5/6) beta, from u = 0, u' = 1
 * until u returns to 0 (the force cut at zero as sep_hm_force cuts it); the rebound speed by
 * classical Runge-Kutta (step 1e-3 of a contact time of about 2.87; the crossing by linear
 * interpolation). Rounding and the step's error are below 1e-7 (halving it changes the 8th
 * digit). */
static double hm_rebound(double c)
{
    const double h = 1e-3;
#define SEP_ACC(u, v) (-fmax(0.0, (u) > 0 ? 4.0 / 3.0 * (u) * sqrt(u) + c * 1.4142135623730951 * sqrt(sqrt(u)) * (v) : 0))
    double u = 0, v = 1;
    for (int k = 0; k < 100000; k++) {
        const double a1 = SEP_ACC(u, v);
        const double u2 = u + 0.5 * h * v, v2 = v + 0.5 * h * a1, a2 = SEP_ACC(u2, v2);
        const double u3 = u + 0.5 * h * v2, v3 = v + 0.5 * h * a2, a3 = SEP_ACC(u3, v3);
        const double u4 = u + h * v3, v4 = v + h * a3, a4 = SEP_ACC(u4, v4);
        const double un = u + h / 6 * (v + 2 * v2 + 2 * v3 + v4);
        const double vn = v + h / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
        if (un <= 0 && k > 0) /* (back at contact: the speed there, between the two steps) */
            return -(v + (vn - v) * (u / (u - un)));
        u = un;
        v = vn;
    }
#undef SEP_ACC
    return 0;
}

double sep_hm_beta_exact(double e)
{
    if (!(e < 1))
        return 0;
    /* the rebound falls as the damping grows: bisect c in [0, 64] (e down to about 1e-6) on
     * the rebound */
    double lo = 0, hi = 1;
    while (hm_rebound(hi) > e && hi < 64)
        hi *= 2;
    for (int k = 0; k < 48; k++) {
        const double mid = 0.5 * (lo + hi);
        if (hm_rebound(mid) > e)
            lo = mid;
        else
            hi = mid;
    }
    return -0.5 * (lo + hi) / (2 * sqrt(5.0 / 6.0));
}
