/* path.c: curved paths in the field of a charged mesh (spec 6.1, 6.3). Outside the equivalent
 * sphere of radius R_f about the centre c the potential is U R_f / |r - c|, so a particle of
 * charge q and mass m accelerates by k r / |r|^3 with k = q U R_f / m (r from c); inside it
 * moves straight. The path is integrated by the classical fourth-order Runge-Kutta method with
 * steps dt = eta |r| / max(|v|, sqrt(|k| / |r|)) (the spec's eta |r| / |v|, with the free-fall
 * speed as a floor so that a particle turning back takes small steps); each step's chord is traced against the mesh (the nearest hit ends
 * the history). A step that would end inside R_f is cut where it meets the sphere (a few
 * regula falsi iterations on the step length), so no step straddles the kink of the field, and
 * the straight part inside ends exactly on the sphere again. Outside the sphere that holds
 * both the body and R_f the path is a conic, taken in closed form (conic_to): no steps until
 * the particle comes near the body, and none at all for one that passes it by. */
#include "ch.h"

#include <math.h>

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void accel(double k, const double r[3], double a[3])
{
    const double r2 = dot3(r, r), f = k / (r2 * sqrt(r2));
    for (int i = 0; i < 3; i++)
        a[i] = f * r[i];
}

/* One RK4 step of r'' = k r / |r|^3 (the exterior field everywhere: smooth). */
static void rk4(double k, const double r[3], const double v[3], double dt, double r1[3],
                double v1[3])
{
    double a1[3], a2[3], a3[3], a4[3], x[3], v2[3], v3[3], v4[3];
    accel(k, r, a1);
    for (int i = 0; i < 3; i++) {
        x[i] = r[i] + 0.5 * dt * v[i];
        v2[i] = v[i] + 0.5 * dt * a1[i];
    }
    accel(k, x, a2);
    for (int i = 0; i < 3; i++) {
        x[i] = r[i] + 0.5 * dt * v2[i];
        v3[i] = v[i] + 0.5 * dt * a2[i];
    }
    accel(k, x, a3);
    for (int i = 0; i < 3; i++) {
        x[i] = r[i] + dt * v3[i];
        v4[i] = v[i] + dt * a3[i];
    }
    accel(k, x, a4);
    for (int i = 0; i < 3; i++) {
        r1[i] = r[i] + dt / 6 * (v[i] + 2 * v2[i] + 2 * v3[i] + v4[i]);
        v1[i] = v[i] + dt / 6 * (a1[i] + 2 * a2[i] + 2 * a3[i] + a4[i]);
    }
}

/* Whether the segment from a to b (absolute) can meet the box lo..hi. */
static int seg_meets_box(const double a[3], const double b[3], const double lo[3],
                         const double hi[3])
{
    for (int i = 0; i < 3; i++)
        if (fmax(a[i], b[i]) < lo[i] || fmin(a[i], b[i]) > hi[i])
            return 0;
    return 1;
}

/* Trace the chord from c + r0 to c + r1; the hit's triangle (and *side, the hit point in x) or
 * -1. */
static long chord(const ch_path *P, const double r0[3], const double r1[3], int *side,
                  double x[3], double dir[3])
{
    double a[3], b[3], d[3], len = 0;
    for (int i = 0; i < 3; i++) {
        a[i] = P->c[i] + r0[i];
        b[i] = P->c[i] + r1[i];
        d[i] = b[i] - a[i];
        len += d[i] * d[i];
    }
    len = sqrt(len);
    if (!(len > 0) || !seg_meets_box(a, b, P->lo, P->hi))
        return -1;
    /* chords overlap by P->overlap at both ends: Embree's rays are in single precision, and a
     * surface crossed at a joint must not fall between two chords (a hit ends the history, so
     * no surface behind the start can have been crossed already) */
    for (int i = 0; i < 3; i++) {
        d[i] /= len;
        a[i] -= P->overlap * d[i];
    }
    double s;
    const long tri = mote_ch_trace_seg(P->t, a, d, 0, len + 2 * P->overlap, side, &s);
    if (tri >= 0)
        for (int i = 0; i < 3; i++) {
            x[i] = a[i] + s * d[i] - P->c[i];
            dir[i] = d[i];
        }
    return tri;
}

/* Specific energy (J/kg): kinetic plus the potential's q phi / m. */
static double energy(const ch_path *P, const double r[3], const double v[3])
{
    const double rho = sqrt(dot3(r, r));
    return 0.5 * dot3(v, v) + P->k / fmax(rho, P->rf);
}

/* Outside P->rj (at least R_f and the body's bounding radius) the path is a conic section of
 * the Coulomb field, known in closed form: move an inbound particle (r, v) to where it first
 * reaches rj; 1 when it never comes that close (its periapsis is beyond rj). */
static int conic_to(const ch_path *P, double r[3], double v[3])
{
    const double k = P->k, rj = P->rj, rho0 = sqrt(dot3(r, r));
    const double eps = 0.5 * dot3(v, v) + k / rho0; /* > 0, or 0: the injection is exact */
    const double h[3] = {r[1] * v[2] - r[2] * v[1], r[2] * v[0] - r[0] * v[2],
                         r[0] * v[1] - r[1] * v[0]};
    const double L2 = dot3(h, h), L = sqrt(L2), D = sqrt(k * k + 2 * eps * L2);
    /* the periapsis: the larger root of eps rho^2 - k rho - L^2/2, without cancellation */
    const double rp = k > 0 ? (k + D) / (2 * eps) : L2 / (D - k);
    if (rp >= rj)
        return 1;
    const double vr = -sqrt(fmax(0, 2 * (eps - k / rj) - L2 / (rj * rj))); /* inbound */
    double rh[3], th[3];
    for (int i = 0; i < 3; i++)
        rh[i] = r[i] / rho0;
    if (!(L > 0)) { /* radial */
        for (int i = 0; i < 3; i++) {
            r[i] = rj * rh[i];
            v[i] = vr * rh[i];
        }
        return 0;
    }
    /* the true anomaly nu(rho) from rho = p / (1 + e cos nu) (attracted) or p / (e cos nu - 1)
     * (repelled), p = L^2 / |k|, e = D / |k|; the angle swept is |nu(rho0)| - |nu(rj)| */
    const double p = L2 / fabs(k), e = D / fabs(k), sg = k > 0 ? 1 : -1;
    const double c0 = fmax(-1, fmin(1, (p / rho0 + sg) / e));
    const double c1 = fmax(-1, fmin(1, (p / rj + sg) / e));
    const double dth = acos(c0) - acos(c1), cs = cos(dth), sn = sin(dth);
    for (int i = 0; i < 3; i++) /* the direction of motion about h: h x r / |h x r| */
        th[i] = (h[(i + 1) % 3] * rh[(i + 2) % 3] - h[(i + 2) % 3] * rh[(i + 1) % 3]) / L;
    for (int i = 0; i < 3; i++) {
        const double nr = cs * rh[i] + sn * th[i], nt = cs * th[i] - sn * rh[i];
        r[i] = rj * nr;
        v[i] = vr * nr + L / rj * nt;
    }
    return 0;
}

/* ---- the solved field (`field solved`): the treecode's field of the body's own charge ---- */

/* The potential (per volt on the body) and the acceleration at c + r: the tree's within rfar,
 * the monopole's beyond. */
static double solved_at(const ch_path *P, const double r[3], double a[3])
{
    const double r2 = dot3(r, r);
    if (r2 >= P->rfar * P->rfar) {
        const double rho = sqrt(r2), f = P->k / (r2 * rho);
        for (int i = 0; i < 3; i++)
            a[i] = f * r[i];
        return P->rf / rho;
    }
    const double x[3] = {P->c[0] + r[0], P->c[1] + r[1], P->c[2] + r[2]};
    double phi, E[3];
    if (!P->cache || ch_fcache_eval(P->cache, P->coef, x, &phi, E))
        mote_ch_ftree_eval(P->tree, x, &phi, E);
    for (int i = 0; i < 3; i++)
        a[i] = P->qu * E[i];
    return phi;
}

static double solved_energy(const ch_path *P, const double r[3], const double v[3])
{
    double a[3];
    return 0.5 * dot3(v, v) + P->qu * solved_at(P, r, a);
}

/* One RK4 step in the solved field from (r, v), whose acceleration a1 is known. */
static void solved_rk4(const ch_path *P, const double r[3], const double v[3],
                       const double a1[3], double dt, double r1[3], double v1[3])
{
    double a2[3], a3[3], a4[3], x[3], v2[3], v3[3], v4[3];
    for (int i = 0; i < 3; i++) {
        x[i] = r[i] + 0.5 * dt * v[i];
        v2[i] = v[i] + 0.5 * dt * a1[i];
    }
    solved_at(P, x, a2);
    for (int i = 0; i < 3; i++) {
        x[i] = r[i] + 0.5 * dt * v2[i];
        v3[i] = v[i] + 0.5 * dt * a2[i];
    }
    solved_at(P, x, a3);
    for (int i = 0; i < 3; i++) {
        x[i] = r[i] + dt * v3[i];
        v4[i] = v[i] + dt * a3[i];
    }
    solved_at(P, x, a4);
    for (int i = 0; i < 3; i++) {
        r1[i] = r[i] + dt / 6 * (v[i] + 2 * v2[i] + 2 * v3[i] + v4[i]);
        v1[i] = v[i] + dt / 6 * (a1[i] + 2 * a2[i] + 2 * a3[i] + a4[i]);
    }
}

/* A path in the solved field: conics beyond rj (>= rfar), RK4 within, each step's chord traced
 * (an ambient particle from the injection sphere, or an electron emitted from the surface).
 * The step: the time to move eta |r| (as in the sphere's field, bounded by the free fall from
 * |r|, and counting the acceleration), and to turn the velocity by eta radians by the
 * acceleration across it (small steps where the field bends paths, near edges and booms), but
 * not shorter than a fall of eta^2 |r| from rest (turning points). The speed at a hit from
 * the energy: the body is at U (phi1 = 1 there), or its triangle at its own. */
static void follow_solved(const ch_path *P, double r[3], double v[3], ch_hit *out)
{
    double a0[3];
    const double qphi = P->qu * solved_at(P, r, a0), e0 = 0.5 * dot3(v, v) + qphi;
    const double scale = 0.5 * dot3(v, v) + fabs(qphi); /* (K_0 + |q phi_0|) / m */
    const double R2 = P->R * P->R;
    double x[3];
    for (long n = 0; n < P->max_steps; n++) {
        out->steps = n + 1;
        double a[3], r1[3], v1[3];
        solved_at(P, r, a);
        const double rho = sqrt(dot3(r, r)), sp = sqrt(dot3(v, v)), am = sqrt(dot3(a, a));
        double dt = P->eta * rho / fmax(sp, sqrt(fabs(P->k) / rho));
        if (am > 0) {
            /* the chord at most eta rho long; the velocity turned by at most eta radians (by
             * the acceleration across it), unless that is shorter than a fall of eta^2 rho
             * from rest (a turning point) */
            const double av = sp > 0 ? dot3(a, v) / sp : 0;
            const double across = sqrt(fmax(0, am * am - av * av));
            const double turn = across > 0 ? P->eta * sp / across : INFINITY;
            const double fall = P->eta * sqrt(2 * rho / am);
            dt = fmin(dt, 2 * P->eta * rho / (sp + sqrt(sp * sp + 2 * am * P->eta * rho)));
            dt = fmin(dt, fmax(turn, fall));
        }
        solved_rk4(P, r, v, a, dt, r1, v1);
        const long tri = chord(P, r, r1, &out->side, x, out->dir);
        if (tri >= 0) {
            out->tri = tri;
            for (int i = 0; i < 3; i++)
                out->x[i] = x[i];
            out->v2 = fmax(0, 2 * (e0 - P->qu * (P->tri_phi ? P->tri_phi[tri] : 1)));
            out->eerr = scale > 0 ? fabs(solved_energy(P, r, v) - e0) / scale : 0;
            return;
        }
        for (int i = 0; i < 3; i++) {
            r[i] = r1[i];
            v[i] = v1[i];
        }
        /* out through the injection sphere, or beyond rj, moving outward: gone, unless it is
         * an emitted electron that is bound (from a positive body with less than its
         * potential energy: it turns back, and is followed on; an ambient particle came from
         * infinity, though the injection's mean potential can make its energy a little
         * negative here) */
        const double rr2 = dot3(r, r);
        if ((e0 >= 0 || !P->emitted) && (rr2 > R2 || rr2 > P->rj * P->rj) && dot3(r, v) > 0) {
            out->eerr = scale > 0 ? fabs(solved_energy(P, r, v) - e0) / scale : 0;
            return;
        }
    }
    out->tri = -2;
    out->eerr = scale > 0 ? fabs(solved_energy(P, r, v) - e0) / scale : 0;
}

void ch_path_follow(const ch_path *P, const double r_in[3], const double v_in[3], ch_hit *out)
{
    double r[3] = {r_in[0], r_in[1], r_in[2]}, v[3] = {v_in[0], v_in[1], v_in[2]};
    const double e0 = energy(P, r, v), scale = 0.5 * dot3(v, v) + fabs(P->k) / sqrt(dot3(r, r));
    const double rf2 = P->rf * P->rf, R2 = P->R * P->R;
    out->tri = -1;
    out->side = 0;
    out->v2 = 0;
    out->steps = 0;
    out->eerr = 0;
    if (P->rj > 0 && dot3(r, r) > P->rj * P->rj && dot3(r, v) < 0 && conic_to(P, r, v))
        return; /* passes the body by */
    if (P->tree) {
        follow_solved(P, r, v, out);
        return;
    }
    double x[3];
    for (long n = 0; n < P->max_steps; n++) {
        out->steps = n + 1;
        const double rho2 = dot3(r, r);
        double r1[3], v1[3];
        if (rho2 <= rf2 * (1 + 1e-12) && dot3(r, v) < 0) { /* into R_f: straight across */
            const double sp = sqrt(dot3(v, v)), b = dot3(r, v) / sp;
            const double s = -b + sqrt(fmax(0, b * b - (rho2 - rf2)));
            const double rr = sqrt(dot3(r, r) + 2 * s * b + s * s);
            for (int i = 0; i < 3; i++)
                r1[i] = (r[i] + s * v[i] / sp) * (P->rf / rr);
            for (int i = 0; i < 3; i++)
                v1[i] = v[i];
        } else {
            /* dt = eta rho / |v|, bounded by eta times the time to fall rho from rest where
             * the particle is slow (a repelled one turning back) */
            const double rho = sqrt(rho2);
            const double dt = P->eta * rho / fmax(sqrt(dot3(v, v)), sqrt(fabs(P->k) / rho));
            rk4(P->k, r, v, dt, r1, v1);
            double f1 = dot3(r1, r1) - rf2;
            if (f1 < 0) { /* the step enters R_f: cut it where it meets the sphere (Illinois) */
                double ta = 0, fa = rho2 - rf2, tb = dt, fb = f1;
                for (int it = 0; it < 60; it++) {
                    const double tau = tb - fb * (tb - ta) / (fb - fa);
                    rk4(P->k, r, v, tau, r1, v1);
                    const double f = dot3(r1, r1) - rf2;
                    if (fabs(f) <= 1e-13 * rf2)
                        break;
                    if ((f < 0) != (fb < 0)) {
                        ta = tb;
                        fa = fb;
                    } else {
                        fa *= 0.5;
                    }
                    tb = tau;
                    fb = f;
                }
                const double rr = sqrt(dot3(r1, r1));
                for (int i = 0; i < 3; i++)
                    r1[i] *= P->rf / rr;
            }
        }
        const long tri = chord(P, r, r1, &out->side, x, out->dir);
        if (tri >= 0) { /* the speed at the hit from the energy (spec 6.7: phi(x_hit)) */
            out->tri = tri;
            for (int i = 0; i < 3; i++)
                out->x[i] = x[i];
            out->v2 = fmax(0, 2 * (e0 - P->k / fmax(sqrt(dot3(x, x)), P->rf)));
            out->eerr = scale > 0 ? fabs(energy(P, r, v) - e0) / scale : 0;
            return;
        }
        for (int i = 0; i < 3; i++) {
            r[i] = r1[i];
            v[i] = v1[i];
        }
        /* outward beyond the body (rj), or through the injection sphere: gone (with E > 0 in
         * a central field the distance from c has a single minimum, spec 6.2) */
        const double rr2 = dot3(r, r);
        if ((rr2 > R2 || (P->rj > 0 && rr2 > P->rj * P->rj)) && dot3(r, v) > 0) {
            out->eerr = scale > 0 ? fabs(energy(P, r, v) - e0) / scale : 0;
            return;
        }
    }
    out->tri = -2; /* lost */
    out->eerr = scale > 0 ? fabs(energy(P, r, v) - e0) / scale : 0;
}
