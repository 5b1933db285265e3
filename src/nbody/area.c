/* area.c: Galactica's area of matter (spec 9.4, the control file's Kl1 = 0): a box A x B x C
 * (A = 1, the length unit) cut into equal bodies at the nodes of a grid of Mu intervals along x,
 * optionally turning rigidly about an axis parallel to z, plus an optional separate body. The
 * grid is put in its centre-of-mass frame before the separate body's mass enters (so a run with
 * one drifts, as in Galactica). Masses are equal shares of the area's mass; the time scale is
 * k_t = sqrt(G Roa A B C (1 + RoS / n_nodes)), which with the length unit Am (1 AU unless given)
 * only affects the conversion back to SI. */
#include <string.h>
#include <tgmath.h>

#include "nb.h"

void mote_nb_area_defaults(mote_nb_area *a)
{
    memset(a, 0, sizeof *a);
    a->B = a->C = 1;
    a->Mu = 2;
    a->X01 = a->Y01 = 0.5;
    a->Roa = 1e-7;
    a->Rob = 5000;
    a->Am = MOTE_NB_AU;
    a->dt = 5e-4;
}

/* n = round(v) + 1 nodes (round half up) for a side v in units of the x interval */
static long nodes_along(double side, int mu) { return (long)floor(side * mu + 0.5) + 1; }

int mote_nb_area_build(mote_nb *nb, mote_nb_area *a, mote_err *err)
{
    if (nb->n)
        return mote_fail(err, MOTE_EINVAL, "generate area: the system already has %u bodies",
                         nb->n);
    if (nb->kind != MOTE_NB_GRAVITY)
        return mote_fail(err, MOTE_EINVAL, "generate area: the area of matter is a gravity "
                                           "system (Galactica's Coulomb module has no area mode)");
    if (a->Mu < 1)
        return mote_fail(err, MOTE_EINVAL, "generate area: Mu = %d, need at least 1 interval "
                                           "along x", a->Mu);
    if (!(a->B > 0) || !(a->C > 0) || !(a->B <= 1e6) || !(a->C <= 1e6))
        return mote_fail(err, MOTE_EINVAL, "generate area: need B > 0 and C > 0 (found %g, %g)",
                         a->B, a->C);
    if (!(a->Roa > 0) || !(a->Rob >= 0) || !(a->RoS >= 0) || !(a->Am > 0) || !(a->dt > 0))
        return mote_fail(err, MOTE_EINVAL, "generate area: need Roa > 0, Rob >= 0, RoS >= 0, a "
                                           "length unit > 0 and dt > 0");
    const long nx = a->Mu + 1L, ny = nodes_along(a->B, a->Mu), nz = nodes_along(a->C, a->Mu);
    const double nn = (double)nx * (double)ny * (double)nz;
    if (nn > NB_MAX_AREA)
        return mote_fail(err, MOTE_EINVAL, "generate area: %ld x %ld x %ld = %.0f nodes is more "
                                           "than the 10^6 this generator builds (about %.3g GB, "
                                           "and a Galactica step of direct sums over them takes "
                                           "hours)", nx, ny, nz, nn, nn * NB_BODY_BYTES / 1e9);
    if (mote_mem_check(nn * NB_BODY_BYTES, "generate area: the nodes", err))
        return err ? (int)err->code : MOTE_ENOMEM;
    const long n = nx * ny * nz;
    const mote_real hx = (mote_real)1 / a->Mu, hy = ny > 1 ? a->B / (mote_real)(ny - 1) : 0,
                    hz = nz > 1 ? a->C / (mote_real)(nz - 1) : 0;
    /* the separate body: only when no node is closer than the x interval 1/Mu */
    int sep = a->RoS > 0;
    for (long k = 0; k < nz && sep; k++)
        for (long j = 0; j < ny && sep; j++)
            for (long i = 0; i < nx && sep; i++) {
                mote_real d[3] = {a->Xs[0] - (a->X0[0] + i * hx), a->Xs[1] - (a->X0[1] + j * hy),
                                  a->Xs[2] - (a->X0[2] + k * hz)};
                if (sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) < hx)
                    sep = 0;
            }
    a->sep_added = sep;
    a->nx = (int)nx;
    a->ny = (int)ny;
    a->nz = (int)nz;
    /* scales: the area's mass Roa A B C Am^3 (plus RoS node masses), time unit first */
    const double share = sep ? 1 + a->RoS / (double)n : 1;
    const double V = a->B * a->C; /* A = 1 */
    const double M = a->Roa * V * a->Am * a->Am * a->Am * share;
    const double kt = sqrt(nb->G * a->Roa * V * share);
    mote_nb_units u;
    mote_nb_units_from_time(&u, MOTE_NB_GRAVITY, M, kt, nb->G, nb->e2, nb->eps);
    /* dimensionless masses and radii (sphere masses of density Rob; 0: points) */
    const mote_real mn = 1 / ((mote_real)n + (sep ? (mote_real)a->RoS : 0));
    const mote_real ms = sep ? (mote_real)a->RoS * mn : 0;
    const double node_kg = a->Roa * V * a->Am * a->Am * a->Am / (double)n;
    const mote_real pi = 4 * atan((mote_real)1);
    mote_real ran = 0, ras = 0;
    if (a->Rob > 0) {
        ran = cbrt(3 * (mote_real)node_kg / (4 * pi * (mote_real)a->Rob)) / (mote_real)u.Am;
        ras = cbrt((mote_real)a->RoS) * ran;
    }
    /* the grid, then its centre of mass (equal masses: the mean) taken out */
    mote_real cx[3] = {0, 0, 0}, cv[3] = {0, 0, 0};
    int rc = MOTE_OK;
    for (long k = 0; k < nz && !rc; k++)
        for (long j = 0; j < ny && !rc; j++)
            for (long i = 0; i < nx && !rc; i++) {
                mote_real x[3] = {a->X0[0] + i * hx, a->X0[1] + j * hy, a->X0[2] + k * hz};
                mote_real v[3] = {-(mote_real)a->wu * (x[1] - a->Y01),
                                  (mote_real)a->wu * (x[0] - a->X01), 0};
                for (int c = 0; c < 3; c++) {
                    cx[c] += x[c];
                    cv[c] += v[c];
                }
                rc = mote_nb_add(nb, mn, 0, x, v, ran, err);
            }
    if (!rc && sep) {
        mote_real xs[3] = {a->Xs[0], a->Xs[1], a->Xs[2]}, vs[3] = {a->Us[0], a->Us[1], a->Us[2]};
        rc = mote_nb_add(nb, ms, 0, xs, vs, ras, err);
    }
    if (rc) {
        mote_nb_free(nb);
        mote_nb_init(nb, MOTE_NB_GRAVITY);
        return rc;
    }
    for (int c = 0; c < 3; c++) {
        cx[c] /= (mote_real)n;
        cv[c] /= (mote_real)n;
    }
    for (uint32_t b = 0; b < nb->n; b++)
        for (int c = 0; c < 3; c++) {
            nb->x[3 * b + (uint32_t)c] -= cx[c];
            nb->v[3 * b + (uint32_t)c] -= cv[c];
        }
    nb->u = u;
    nb->dt = a->dt;
    nb->dtp = 0;
    nb->restart = 1;
    nb->T = nb->Tc = 0;
    nb->steps = 0;
    nb->ref_set = 0;
    return MOTE_OK;
}
