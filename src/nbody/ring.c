/* ring.c: the exact axisymmetric rings of the seed document (spec 9.1 gravity, Appendix 1; 9.2
 * Coulomb, Appendix 3): a central body and N = nb - 1 equal bodies at the vertices of a regular
 * polygon, all at pericentre of identical Kepler ellipses, which stay a regular polygon for all
 * time (Smulsky 2003). The generator follows the document's algorithm step by step, in SI units,
 * then scales (time unit first, refined); the dimensionless state and the exact solution (Kepler's
 * equation in long double, or quad in the quad build) are computed in the build's real type from
 * the same dimensionless values, so that the reference is exact to that precision. */
#include <string.h>
#include <tgmath.h>

#include "nb.h"

static mote_real real_pi(void) { return 4 * atan((mote_real)1); }

mote_real mote_nb_ring_fN(int N)
{
    const mote_real pi = real_pi();
    mote_real s = 0;
    for (int j = 1; j <= N - 1; j++)
        s += 1 / sin(j * pi / N);
    return s / 4;
}

void mote_nb_ring_defaults(mote_nb_ring *r, mote_nb_interaction kind)
{
    memset(r, 0, sizeof *r);
    r->ka = 1;
    r->tilt = 0.409;
    r->permittivity = 1;
    if (kind == MOTE_NB_GRAVITY) {
        r->nb = 30;
        r->e = 0.2056;
        r->central_mass = MOTE_NB_SUN_EARTHS * MOTE_NB_EARTH_MASS;
        r->total_mass = MOTE_NB_SOLAR_SYSTEM_MASS;
        r->density = 5000;
        r->dt = 1e-6;
        r->time_unit = 100 * MOTE_NB_SIDEREAL_YEAR_DAYS * 86400; /* a sidereal century, s */
    } else {
        r->nb = 9;
        r->e = 0.15;
        r->A = 16;
        r->Z = 8;
        r->nq = 2;
        r->lq = 1;
        r->dt = 1e-7;
        r->time_unit = 1e-15;
    }
}

/* Rotate (y, z) about x by the tilt. */
static void tilt(mote_real c, mote_real s, mote_real p[3])
{
    mote_real y = p[1] * c - p[2] * s, z = p[1] * s + p[2] * c;
    p[1] = y;
    p[2] = z;
}

int mote_nb_ring_build(mote_nb *nb, mote_nb_ring *r, mote_err *err)
{
    const int coulomb = nb->kind == MOTE_NB_COULOMB;
    if (r->nb < 2)
        return mote_fail(err, MOTE_EINVAL, "ring: nb must be >= 2 (found %d)", r->nb);
    if (!(r->e >= 0 && r->e < 1))
        return mote_fail(err, MOTE_EINVAL, "ring: e must be in [0, 1) (found %g)", r->e);
    if (!(r->ka > 0))
        return mote_fail(err, MOTE_EINVAL, "ring: ka must be > 0 (found %g)", r->ka);
    if (nb->n != 0)
        return mote_fail(err, MOTE_EINVAL, "ring: the system already has %u bodies", nb->n);
    const int N = r->nb - 1;
    const double e2 = nb->e2, G = nb->G; /* the constants in use (spec 3.6) */
    double M;
    if (!coulomb) {
        r->a = r->ka * MOTE_NB_AU;
        r->m0 = r->central_mass;
        r->m1 = (r->total_mass - r->m0) / N;
        if (!(r->m1 > 0))
            return mote_fail(err, MOTE_EINVAL, "ring: the central mass leaves nothing for the ring");
        r->ra0 = cbrt(3 * r->m0 / (4 * MOTE_PI * r->density));
        r->ra1 = cbrt(3 * r->m1 / (4 * MOTE_PI * r->density));
        M = r->total_mass;
    } else {
        if (r->Z < 1 || r->A < r->Z)
            return mote_fail(err, MOTE_EINVAL, "atom_ring: need 1 <= Z <= A (found Z %d, A %d)",
                             r->Z, r->A);
        r->rn = MOTE_NB_R0 * cbrt((double)r->A);
        double rm = MOTE_NB_BOHR * (3.0 * r->nq * r->nq - r->lq * (r->lq + 1.0)) / (2.0 * r->Z);
        r->a = r->ka * rm;
        r->m0 = r->Z * MOTE_NB_MP + (r->A - r->Z) * MOTE_NB_MN;
        r->m1 = MOTE_NB_ME;
        r->ra0 = r->rn;
        r->ra1 = MOTE_NB_RE;
        M = r->m0 + N * r->m1;
    }
    r->alpha1 = -1.0 / (1.0 + r->e);
    r->rp = r->a * (2 * r->alpha1 + 1) / r->alpha1;
    const mote_real fN = mote_nb_ring_fN(N);
    r->fN = (double)fN;
    if (!coulomb)
        r->mu1 = -G * (r->m0 + r->m1 * r->fN);
    else
        r->mu1 = -(e2 / (r->m1 * r->permittivity)) * (N - r->fN);
    r->vp = sqrt(r->mu1 / (r->alpha1 * r->rp));
    if (!(r->vp > 0))
        return mote_fail(err, MOTE_EINVAL, "ring: no bound orbit (the ring repels its bodies)");
    /* spacing between neighbours in units of the body diameter */
    double phi1 = 2 * MOTE_PI / N;
    double dx = r->rp * (cos(phi1) - 1), dy = r->rp * sin(phi1);
    r->d = N > 1 ? sqrt(dx * dx + dy * dy) / (2 * r->ra1) : INFINITY;
    if (r->d < 50)
        return mote_fail(err, MOTE_EINVAL,
                         "ring: neighbours are only %.3g diameters apart (at least 50): use a "
                         "larger ka", r->d);
    mote_nb_units_from_time(&nb->u, nb->kind, M, 1.0 / r->time_unit, G, e2,
                            r->permittivity);
    const mote_nb_units *u = &nb->u;
    /* the dimensionless ring, every value from mo0, mo1, rp_o and e in the real type, so that
     * the initial state and the exact solution agree to its last digit */
    const mote_real pi = real_pi(), e = r->e;
    const mote_real ct = cos((mote_real)r->tilt), st = sin((mote_real)r->tilt);
    r->mo0 = (mote_real)r->m0 / (mote_real)M;
    r->mo1 = (mote_real)r->m1 / (mote_real)M;
    r->rp_o = (mote_real)r->rp / (mote_real)u->Am;
    r->a_o = r->rp_o / (1 - e);
    /* the Kepler parameter of a ring body in dimensionless units */
    r->mu = coulomb ? (N - fN) / r->mo1 : r->mo0 + r->mo1 * fN;
    r->vp_o = sqrt(r->mu * (1 + e) / r->rp_o);
    r->M00 = N * r->mo1 * r->rp_o * r->vp_o;
    r->period = 2 * pi * sqrt(r->a_o * r->a_o * r->a_o / r->mu);
    const mote_real zero[3] = {0, 0, 0};
    int rc = mote_nb_add(nb, r->mo0, coulomb ? r->Z : 0, zero, zero,
                         (mote_real)r->ra0 / (mote_real)u->Am, err);
    for (int k = 1; k <= N && !rc; k++) {
        const mote_real phi = (k - 1) * 2 * pi / N;
        mote_real x[3] = {r->rp_o * cos(phi), r->rp_o * sin(phi), 0};
        mote_real v[3] = {-r->vp_o * sin(phi), r->vp_o * cos(phi), 0};
        tilt(ct, st, x);
        tilt(ct, st, v);
        rc = mote_nb_add(nb, r->mo1, coulomb ? -1 : 0, x, v, (mote_real)r->ra1 / (mote_real)u->Am,
                         err);
    }
    if (rc)
        return rc;
    nb->dt = r->dt;
    mote_nb_barycentric(nb, r->xc, r->vc);
    return MOTE_OK;
}

/* Kepler's equation is solved in nb_wide, at least as wide as long double */
typedef nb_wide wide;

void mote_nb_ring_exact(const mote_nb_ring *r, int b, mote_real T, mote_real x[3])
{
    const wide a = r->a_o, e = r->e, mu = r->mu, pi = 4 * atan((wide)1);
    const wide n = sqrt(mu / (a * a * a));
    wide Mm = fmod(n * (wide)T, 2 * pi);
    wide E = Mm + e * sin(Mm); /* Newton on E - e sin E = M */
    for (int it = 0; it < 60; it++) {
        wide f = E - e * sin(E) - Mm, d = f / (1 - e * cos(E));
        E -= d;
        if (fabs(d) < (wide)1e-40)
            break;
    }
    wide xo = a * (cos(E) - e), yo = a * sqrt(1 - e * e) * sin(E);
    wide phi = (b - 1) * 2 * pi / (r->nb - 1);
    wide c = cos(phi), s = sin(phi);
    wide p[3] = {xo * c - yo * s, xo * s + yo * c, 0};
    wide ct = cos((wide)r->tilt), st = sin((wide)r->tilt);
    x[0] = (mote_real)p[0];
    x[1] = (mote_real)(p[1] * ct - p[2] * st);
    x[2] = (mote_real)(p[1] * st + p[2] * ct);
}

mote_real mote_nb_ring_error(const mote_nb *nb, const mote_nb_ring *r, mote_real *out_of_plane)
{
    mote_real worst = 0, plane = 0;
    const mote_real ct = cos((mote_real)r->tilt), st = sin((mote_real)r->tilt);
    const mote_real nrm[3] = {0, -st, ct}; /* the tilted orbit plane's normal */
    for (uint32_t b = 1; b < nb->n && (int)b < r->nb; b++) {
        mote_real xe[3];
        mote_nb_ring_exact(r, (int)b, nb->T, xe);
        const mote_real *xn = nb->x + 3 * (size_t)b;
        mote_real d2 = 0, e2 = 0, h = 0;
        for (int a = 0; a < 3; a++) {
            d2 += (xn[a] - xe[a]) * (xn[a] - xe[a]);
            e2 += xe[a] * xe[a];
            h += xn[a] * nrm[a];
        }
        worst = fmax(worst, sqrt(d2 / e2));
        plane = fmax(plane, fabs(h));
    }
    if (out_of_plane)
        *out_of_plane = plane;
    return worst;
}
