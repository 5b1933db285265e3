/* test_sep_contact.c: the Hertz-Mindlin law with tangential history and Coulomb friction
 * (src/separator/contact.c, issue 56), on single impacts of a sphere on a flat wall integrated
 * here (velocity Verlet, rotation included, steps of a five-hundredth of the contact time):
 * - the restitution of this damping (gamma ~ delta^1/4, Tsuji et al. 1992) does not depend on
 *   the impact speed; it grows with the e given;
 * - gross sliding throughout the contact (a large incidence angle): the tangential impulse is
 *   mu times the normal one, dv_t = mu (1 + e') v_n and omega = 5/2 mu (1 + e') v_n / R with
 *   e' the rebound's own restitution, to rounding;
 * - the angular momentum about the contact point, I omega + R n x m v, is kept through any
 *   impact (both forces act at the contact point), to rounding;
 * - the kinetic energy never grows. */
#include <math.h>
#include <stdio.h>

#include "../src/separator/sep.h"
#include "test.h"

typedef struct {
    double v[3], w[3]; /* after */
    double e_n;        /* -v_n' / v_n */
    double Lerr, Egain, Jn;
} impact;

static void cross(const double a[3], const double b[3], double r[3])
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

/* A sphere (radius R, density 2500) at (0, 0, R) just touching the wall z = 0, velocity v0, no
 * spin, no gravity; material steel-like on both sides scaled down: E = 1e7 Pa, nu = 0.3. */
static impact collide(double e, double mu, const double v0[3])
{
    const double R = 1e-3, m = 2500 * 4.0 / 3.0 * SEP_PI * R * R * R, I = 0.4 * m * R * R;
    const sep_material mat = {1e7, 0.3};
    sep_hm h;
    sep_hm_pair(&h, &mat, R, m, &mat, INFINITY, INFINITY, e, mu);
    const double vn0 = fabs(v0[2]);
    const double tc = 2.87 * pow(h.m * h.m / (h.R * h.Y * h.Y * vn0), 0.2);
    const double dt = tc / 500;
    const double n[3] = {0, 0, 1};
    double x[3] = {0, 0, R}, v[3] = {v0[0], v0[1], v0[2]}, w[3] = {0, 0, 0}, xi[3] = {0, 0, 0};
    double F[3] = {0, 0, 0}, T[3] = {0, 0, 0};
    impact r = {{0}, {0}, 0, 0, 0, 0};
    double L0[3], nv[3];
    cross(n, v, nv);
    for (int a = 0; a < 3; a++)
        L0[a] = I * w[a] + R * m * nv[a];
    const double E0 = 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    int touching = 1;
    for (long s = 0; s < 100000 && (touching || x[2] < R); s++) {
        for (int a = 0; a < 3; a++) { /* first half kick, drift */
            v[a] += 0.5 * dt * F[a] / m;
            w[a] += 0.5 * dt * T[a] / I;
        }
        for (int a = 0; a < 3; a++)
            x[a] += dt * v[a];
        const double delta = R - x[2];
        touching = delta > 0;
        F[0] = F[1] = F[2] = T[0] = T[1] = T[2] = 0;
        if (touching) {
            /* the contact point -R n from the centre: its velocity v + w x (-R n) */
            double wr[3], vc[3];
            const double rc[3] = {-R * n[0], -R * n[1], -R * n[2]};
            cross(w, rc, wr);
            for (int a = 0; a < 3; a++)
                vc[a] = v[a] + wr[a];
            /* (the kicks use the velocities half a step behind: the law's v) */
            r.Jn += dt * sep_hm_force(&h, delta, n, vc, dt, xi, F);
            cross(rc, F, T);
        } else {
            xi[0] = xi[1] = xi[2] = 0;
        }
        for (int a = 0; a < 3; a++) {
            v[a] += 0.5 * dt * F[a] / m;
            w[a] += 0.5 * dt * T[a] / I;
        }
        cross(n, v, nv);
        for (int a = 0; a < 3; a++)
            r.Lerr = fmax(r.Lerr, fabs(I * w[a] + R * m * nv[a] - L0[a]) / (R * m * vn0));
        const double E = 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) +
                         0.5 * I * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        if (!touching)
            r.Egain = fmax(r.Egain, (E - E0) / E0);
    }
    for (int a = 0; a < 3; a++) {
        r.v[a] = v[a];
        r.w[a] = w[a];
    }
    r.e_n = v[2] / vn0;
    r.Jn /= m * vn0; /* (the normal impulse in units of m v_n) */
    return r;
}

int main(void)
{
    /* the restitution: the same at 0.5 and 2 m/s; growing with e */
    double prev = 0;
    for (int k = 0; k < 3; k++) {
        const double e = k == 0 ? 0.3 : k == 1 ? 0.5 : 0.9;
        const double v1[3] = {0, 0, -0.5}, v2[3] = {0, 0, -2};
        const impact a = collide(e, 0.5, v1), b = collide(e, 0.5, v2);
        printf("e = %g: rebound %.6f at 0.5 m/s, %.6f at 2 m/s\n", e, a.e_n, b.e_n);
        CHECK(fabs(a.e_n - b.e_n) < 2e-3 && a.e_n > prev && a.e_n < 1,
              "e = %g: restitution %.6f at 0.5 m/s, %.6f at 2 m/s", e, a.e_n, b.e_n);
        prev = a.e_n;
    }
    /* gross sliding: tangential impulse = mu x normal impulse */
    for (int k = 0; k < 2; k++) {
        const double mu = k ? 0.3 : 0.1, vn = 1, vt = 3;
        const double v0[3] = {vt, 0, -vn};
        const impact r = collide(0.6, mu, v0);
        const double R = 1e-3, dvt = vt - r.v[0], want = mu * (1 + r.e_n) * vn;
        printf("sliding, mu = %g: dv_t %.9g (mu (1 + e') v_n %.9g), omega R %.9g (%.9g)\n", mu,
               dvt, want, r.w[1] * R, 2.5 * want);
        CHECK(fabs(dvt - want) <= 1e-9 * want && fabs(r.Jn - (1 + r.e_n)) <= 1e-6,
              "sliding, mu = %g: dv_t = %.12g, mu (1 + e') v_n = %.12g (J_n %.9g)", mu, dvt,
              want, r.Jn);
        CHECK(fabs(r.w[1] * R - 2.5 * want) <= 1e-9 * want && r.w[0] == 0 && r.w[2] == 0,
              "sliding, mu = %g: omega R = %.12g, not 5/2 dv_t = %.12g", mu, r.w[1] * R,
              2.5 * want);
    }
    /* any impact: angular momentum about the contact point kept, energy not gained */
    double worstL = 0, worstE = -1;
    for (int k = 0; k < 24; k++) {
        const double ang = (k + 0.5) / 24 * 1.5, mu = k % 3 == 0 ? 0.05 : k % 3 == 1 ? 0.5 : 5;
        const double e = k % 2 ? 0.4 : 0.95;
        const double v0[3] = {sin(ang), 0.3 * sin(2 * ang), -cos(ang)};
        const impact r = collide(e, mu, v0);
        worstL = fmax(worstL, r.Lerr);
        worstE = fmax(worstE, r.Egain);
    }
    printf("24 impacts: angular momentum about the contact point kept to %.2g, energy gained "
           "at most %.2g\n", worstL, worstE);
    CHECK(worstL < 1e-12 && worstE <= 1e-12, "angular momentum error %.3g, energy gain %.3g",
          worstL, worstE);
    return test_summary();
}
