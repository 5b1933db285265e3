/* orbit.c: a body from orbital elements (`body mass=M a= e= inc= Omega= omega= f=|M=
 * primary=`), as a REBOUND user adds planets: the position and velocity relative to its
 * primary of the two-body orbit with mu = G (M_primary + m) (G = 1 inside; Murray & Dermott,
 * Solar System Dynamics, 1999, eqs. 2.20, 2.36 and 2.122). Angles in radians. */
#include "mote/nbody.h"

#include <tgmath.h>

#include "model.h"
#include "nb.h"

/* The eccentric anomaly of the mean anomaly M (e < 1): Newton's method on E - e sin E = M,
 * started at pi for e > 0.8 (Danby's advice), to the last bits of mote_real. */
static mote_real kepler(mote_real M, mote_real e)
{
    const mote_real pi = 4 * atan((mote_real)1);
    M = fmod(M, 2 * pi);
    mote_real E = e > (mote_real)0.8 ? pi : M;
    for (int k = 0; k < 100; k++) {
        const mote_real d = (E - e * sin(E) - M) / (1 - e * cos(E));
        E -= d;
        if (fabs(d) <= MOTE_REAL_TOL * (1 + fabs(E)))
            break;
    }
    return E;
}

void nb_orbit_xv(const nb_elements *el, mote_real mu, mote_real x[3], mote_real v[3])
{
    const mote_real e = el->e;
    mote_real f = el->f;
    if (el->mean) {
        const mote_real E = kepler(el->M, e);
        f = 2 * atan2(sqrt(1 + e) * sin(E / 2), sqrt(1 - e) * cos(E / 2));
    }
    const mote_real p = el->a * (1 - e * e); /* the semi-latus rectum (> 0: ellipse, hyperbola) */
    const mote_real r = p / (1 + e * cos(f)), h = sqrt(mu * p);
    const mote_real cO = cos(el->Omega), sO = sin(el->Omega), ci = cos(el->inc),
                    si = sin(el->inc), cu = cos(el->omega + f), su = sin(el->omega + f),
                    cw = cos(el->omega), sw = sin(el->omega);
    x[0] = r * (cO * cu - sO * su * ci);
    x[1] = r * (sO * cu + cO * su * ci);
    x[2] = r * su * si;
    const mote_real k = mu / h, A = su + e * sw, B = cu + e * cw;
    v[0] = -k * (cO * A + sO * ci * B);
    v[1] = -k * (sO * A - cO * ci * B);
    v[2] = k * si * B;
}

/* ---- `body` with orbital elements -------------------------------------------------------------- */

static const char *const ELEMENTS[] = {"a", "e", "inc", "Omega", "omega", "f", "M", "primary"};

static int given(const mote_call *c)
{
    for (size_t k = 0; k < sizeof ELEMENTS / sizeof ELEMENTS[0]; k++)
        if (mote_call_opt(c, ELEMENTS[k]))
            return 1;
    return 0;
}

int nb_body_elements_check(const nb_model *m, const mote_call *c, mote_err *err)
{
    if (!given(c))
        return MOTE_OK;
    static const char *const xv[] = {"x", "y", "z", "vx", "vy", "vz"};
    for (size_t k = 0; k < 6; k++)
        if (mote_call_opt(c, xv[k]))
            return mote_call_fail(err, c, mote_call_opt_index(c, xv[k]), MOTE_EINVAL,
                                  "body: give the position and velocity (x= ... vz=) or "
                                  "orbital elements (a= e= ...), not both");
    if (m->nb.kind != MOTE_NB_GRAVITY)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "body: orbital elements are for gravity runs");
    if (!mote_call_opt(c, "a"))
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "body: orbital elements need the semi-major axis a=");
    if (mote_call_opt(c, "f") && mote_call_opt(c, "M"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "M"), MOTE_EINVAL,
                              "body: give the true anomaly f= or the mean anomaly M=, not both");
    const double a = mote_call_opt_r(c, "a", 0), e = mote_call_opt_r(c, "e", 0);
    const int ia = mote_call_opt_index(c, "a");
    if (e == 1)
        return mote_call_fail(err, c, mote_call_opt_index(c, "e"), MOTE_EINVAL,
                              "body: e = 1 (a parabola) has no semi-major axis; give x= ... vz=");
    if (e < 1 && !(a > 0))
        return mote_call_fail(err, c, ia, MOTE_EINVAL,
                              "body: a = %g: an ellipse (e < 1) needs a > 0", a);
    if (e > 1 && !(a < 0))
        return mote_call_fail(err, c, ia, MOTE_EINVAL,
                              "body: a = %g: a hyperbola (e > 1) needs a < 0", a);
    if (e > 1 && mote_call_opt(c, "M"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "M"), MOTE_EINVAL,
                              "body: M= is for an ellipse (e < 1); give f= for a hyperbola");
    if (!m->d_bodies)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "body: orbital elements need a primary: add it first (the "
                              "first body has x= ... vz=)");
    return MOTE_OK;
}

int nb_body_elements(nb_model *m, const mote_call *c, mote_real mass, mote_real x[3],
                     mote_real v[3], mote_err *err)
{
    if (!given(c))
        return MOTE_OK;
    mote_nb *nb = &m->nb;
    if (m->raw)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "body: orbital elements need the "
                              "scales known: give units mass=KG (or input=dimensionless) "
                              "before, not mass=auto");
    /* the primary: the body named, or the centre of mass of the bodies so far (Jacobi's) */
    mote_real mp = 0, xp[3] = {0, 0, 0}, vp[3] = {0, 0, 0};
    const mote_arg *pr = mote_call_opt(c, "primary");
    const long k = pr ? mote_nb_find(nb, pr->text) : -1;
    if (pr && (k < 0 || !nb->active[k]))
        return mote_call_fail(err, c, mote_call_opt_index(c, "primary"), MOTE_EINVAL,
                              "body: primary=%s: %s", pr->text,
                              k < 0 ? "no body of that name or number" : "that body merged away");
    for (uint32_t i = 0; i < nb->n; i++) {
        if (pr ? (long)i != k : !nb->active[i])
            continue;
        mp += nb->m[i];
        for (int a = 0; a < 3; a++) {
            xp[a] += nb->m[i] * nb->x[3 * (size_t)i + a];
            vp[a] += nb->m[i] * nb->v[3 * (size_t)i + a];
        }
    }
    if (!(mp > 0))
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "body: orbital elements need a primary "
                              "with mass (the bodies so far have none)");
    const mote_real scale = m->input_si ? 1 / nb->u.Am : 1; /* a in m with SI input */
    nb_elements el = {nb_opt_real_or(c, "a", 0) * scale, nb_opt_real_or(c, "e", 0),
                      nb_opt_real_or(c, "inc", 0), nb_opt_real_or(c, "Omega", 0),
                      nb_opt_real_or(c, "omega", 0), nb_opt_real_or(c, "f", 0),
                      nb_opt_real_or(c, "M", 0), mote_call_opt(c, "M") != NULL};
    mote_real dx[3], dv[3];
    nb_orbit_xv(&el, mp + mass, dx, dv);
    for (int a = 0; a < 3; a++) {
        x[a] = xp[a] / mp + dx[a];
        v[a] = vp[a] / mp + dv[a];
    }
    return MOTE_OK;
}
