/* float.c: the floating potential of the charging model (spec 6.5): the net current of a run,
 * and the potential where it vanishes, found by bracketing with the OML estimate and then
 * bisecting on Monte Carlo runs with common random numbers (mc.c). */
#include "ch.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the floating potential (spec 6.5) ------------------------------------------------------ */

/* The net OML current of the plasma to a sphere of area A at U. */
static double oml_net(const mote_ch_plasma *p, double A, double U)
{
    double I = 0;
    for (int s = 0; s < p->nsp; s++)
        for (int k = 0; k < p->sp[s].ncomp; k++)
            I += mote_ch_oml(A, U, p->sp[s].n[k], p->sp[s].kT[k], p->sp[s].m, p->sp[s].Z);
    return I;
}

double mote_ch_net(const mote_ch_result *r, double *sigma)
{
    double I = r->photo, v = r->photo_sigma * r->photo_sigma;
    for (int s = 0; s < r->nsp; s++) {
        I += r->current[s];
        v += r->sigma[s] * r->sigma[s];
        for (int k = 0; k < MOTE_CH_MAX_COMPONENTS; k++) { /* secondaries leave: a gain */
            I += r->see[s][k];
            v += r->see_sigma[s][k] * r->see_sigma[s][k];
        }
    }
    if (sigma)
        *sigma = sqrt(v);
    return I;
}

int mote_ch_float(const mote_ch_plasma *p, const mote_ch_body *b, const mote_ch_tracer *t,
                  const mote_ch_run_opts *o, double tol, double *U_f, double *sigma_U,
                  double *oml, int *evals, mote_ch_result *r, mote_err *err)
{
    memset(r, 0, sizeof *r);
    *evals = 0;
    mote_ch_geometry g;
    mote_ch_body_geometry(b, &g);
    /* the analytic root: I_net(U) falls with U (electrons gain, ions lose) */
    double lo = -1e7, hi = 1e7;
    if (!(oml_net(p, g.area, lo) > 0 && oml_net(p, g.area, hi) < 0))
        return mote_fail(err, MOTE_EINVAL, "float: the net current does not change sign between "
                         "-10 MV and +10 MV (a plasma of one sign?)");
    for (int it = 0; it < 200; it++) {
        const double mid = 0.5 * (lo + hi);
        if (oml_net(p, g.area, mid) > 0)
            lo = mid;
        else
            hi = mid;
    }
    *oml = 0.5 * (lo + hi);
    double kTmin = INFINITY;
    for (int s = 0; s < p->nsp; s++)
        for (int k = 0; k < p->sp[s].ncomp; k++)
            kTmin = fmin(kTmin, p->sp[s].kT[k] / abs(p->sp[s].Z));
    mote_ch_run_opts q = *o;
    mote_ch_result ra, rb;
    double Ia, Ib, sa;
    /* the Monte Carlo bracket: from U0, steps growing geometrically the way the current drives
     * U, so the root found is the one time evolution from U0 reaches */
    double Ua = o->U0, step = 0.1 * kTmin;
    q.potential = Ua;
    int rc = mote_ch_run(p, b, t, &q, &ra, err);
    ++*evals;
    if (rc)
        return rc;
    Ia = mote_ch_net(&ra, &sa);
    double Ub = Ua;
    Ib = Ia;
    rb = ra;
    memset(&ra, 0, sizeof ra);
    for (int it = 0; it < 60 && !rc; it++) {
        mote_ch_result_free(&ra);
        ra = rb; /* the last point becomes the other end */
        Ua = Ub;
        Ia = Ib;
        Ub = Ua + (Ia > 0 ? step : -step); /* I > 0: U must rise */
        q.potential = Ub;
        rc = mote_ch_run(p, b, t, &q, &rb, err);
        ++*evals;
        if (rc)
            break;
        Ib = mote_ch_net(&rb, NULL);
        if ((Ia > 0) != (Ib > 0))
            break;
        step *= 2;
    }
    if (!rc && (Ia > 0) == (Ib > 0))
        rc = mote_fail(err, MOTE_EINVAL, "float: no sign change of the net current found");
    /* refine: regula falsi with the Illinois weights, bisection when it stalls */
    int side = 0;
    for (int it = 0; it < 100 && !rc; it++) {
        double s_now;
        const double Ibest = fabs(Ia) < fabs(Ib) ? mote_ch_net(&ra, &s_now) : mote_ch_net(&rb, &s_now);
        const double slope = (Ib - Ia) / (Ub - Ua);
        const double sU = slope != 0 ? s_now / fabs(slope) : INFINITY;
        (void)Ibest;
        if (fabs(Ub - Ua) <= fmax(0.1 * sU, tol * fmax(fabs(Ua), fabs(Ub))))
            break;
        double Um = (Ua * Ib - Ub * Ia) / (Ib - Ia);
        if (!(Um > fmin(Ua, Ub) && Um < fmax(Ua, Ub)) || it % 4 == 3)
            Um = 0.5 * (Ua + Ub);
        q.potential = Um;
        mote_ch_result rm;
        rc = mote_ch_run(p, b, t, &q, &rm, err);
        ++*evals;
        if (rc)
            break;
        const double Im = mote_ch_net(&rm, NULL);
        if ((Im > 0) == (Ia > 0)) {
            mote_ch_result_free(&ra);
            ra = rm;
            Ua = Um;
            Ia = Im;
            if (side == -1)
                Ib *= 0.5;
            side = -1;
        } else {
            mote_ch_result_free(&rb);
            rb = rm;
            Ub = Um;
            Ib = Im;
            if (side == 1)
                Ia *= 0.5;
            side = 1;
        }
    }
    if (!rc) {
        /* the root by linear interpolation of the (unweighted) end currents */
        double sI;
        const double Ia0 = mote_ch_net(&ra, &sI), Ib0 = mote_ch_net(&rb, NULL);
        const double slope = (Ib0 - Ia0) / (Ub - Ua);
        *U_f = Ib0 != Ia0 ? (Ua * Ib0 - Ub * Ia0) / (Ib0 - Ia0) : 0.5 * (Ua + Ub);
        *sigma_U = slope != 0 ? sI / fabs(slope) : INFINITY;
        q.potential = *U_f;
        rc = mote_ch_run(p, b, t, &q, r, err);
        ++*evals;
    }
    mote_ch_result_free(&ra);
    mote_ch_result_free(&rb);
    return rc;
}
