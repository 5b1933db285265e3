/* diff.c: differential charging (spec 6.10). Dielectric patches p have their own surface
 * potential V_p over the body's U; with dV_p = V_p - U the circuit is
 *
 *     C   dU/dt    = I_c(U) + sum_p I_p(U, dV_p)           (the whole body)
 *     C_p dV_p/dt' = I_p(U, dV_p) - dV_p / R_p            (each patch; d(V_p - U)/dt)
 *
 * with C_p = eps0 eps_r A_p / d_p and R_p = d_p / (sigma_p A_p). With the body's solved field
 * (issue 55) the vacuum capacitance matrix Cv of the conductor (0) and the patches' outer
 * surfaces (1 + p) replaces C: the charges q = M V, M = Cv + the layers (C_p between the
 * patch's surface and the conductor beneath), change with the currents (the conductor's own
 * and the leaks, each patch's less its leak), dV/dt = M^-1 dq/dt; with Cv = C on the conductor
 * alone this is the circuit above. The currents come from Monte
 * Carlo runs at nodes U_j = U0 + s sinh(0.2 j) (s: the smallest temperature, in volts), made
 * when the solution first needs them; each run tallies every patch's net current at every dV
 * of a grid dV_g = s sinh(0.2 g) up to DV_MAX (mc.c). Between nodes and grid points the
 * currents are interpolated by cubics with the slopes of three-point differences (exact for
 * quadratics). The system is stiff (the body follows its currents in
 * microseconds to seconds, a patch in minutes to days), so it is integrated by implicit Euler
 * steps with Newton's method (Jacobian by differences), extrapolated from one step and two
 * half steps (second order, L-stable), the step chosen from the difference of the two. */
#include "mote/charging.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ch.h"

#define DU_STEP 0.2    /* the node lattice's asinh step */
#define DV_STEP 0.2    /* the patch grid's asinh step */
#define DV_MAX 1e6     /* V: the grid's reach either side of the body */
#define RTOL 1e-7      /* the step control's tolerances: relative, and absolute in volts */
#define ATOL 1e-7

void ch_patches_free(ch_patches *P)
{
    free(P->dv);
    free(P->node_j);
    free(P->node_Ic);
    free(P->node_sig);
    free(P->node_Ip);
    memset(P, 0, sizeof *P);
}

int ch_patches_init(ch_patches *P, int np, double scale, double U0, mote_err *err)
{
    const int half = (int)ceil(asinh(DV_MAX / scale) / DV_STEP);
    P->np = np;
    P->scale = scale;
    P->U0 = U0;
    P->ndv = 2 * half + 1;
    if (!(P->dv = malloc((size_t)P->ndv * sizeof *P->dv)))
        return mote_fail(err, MOTE_ENOMEM, "evolve: out of memory");
    for (int g = 0; g < P->ndv; g++)
        P->dv[g] = g == half ? 0 : scale * sinh(DV_STEP * (g - half));
    return MOTE_OK;
}

static double node_U(const ch_patches *P, int j)
{
    return j == 0 ? P->U0 : P->U0 + P->scale * sinh(DU_STEP * j);
}

/* The slot of node j, run when new; -1 with err. */
static int node_slot(ch_patches *P, int j, mote_err *err)
{
    for (int k = 0; k < P->nn; k++)
        if (P->node_j[k] == j)
            return k;
    if (P->nn == 4096) {
        mote_fail(err, MOTE_ERUNTIME, "evolve: the body's potential wandered over 4096 nodes");
        return -1;
    }
    const size_t n = (size_t)P->nn + 1, w = (size_t)P->np * (size_t)P->ndv;
    int *nj = realloc(P->node_j, n * sizeof *nj);
    if (nj)
        P->node_j = nj;
    double *nc = realloc(P->node_Ic, n * sizeof *nc);
    if (nc)
        P->node_Ic = nc;
    double *ns = realloc(P->node_sig, n * sizeof *ns);
    if (ns)
        P->node_sig = ns;
    double *np = realloc(P->node_Ip, n * w * sizeof *np);
    if (np)
        P->node_Ip = np;
    if (!nj || !nc || !ns || !np) {
        mote_fail(err, MOTE_ENOMEM, "evolve: out of memory");
        return -1;
    }
    const int k = P->nn;
    if (P->node(P->ctx, node_U(P, j), &P->node_Ic[k], &P->node_sig[k], P->node_Ip + (size_t)k * w,
                err))
        return -1;
    P->node_j[k] = j;
    P->nn++;
    return k;
}

/* The cubic through (x1, f1) and (x2, f2) with slopes from the three-point differences
 * (exact for quadratics; one-sided where x0 or x3 is missing: NAN), at x in [x1, x2]. */
static double cubic(const double x[4], const double f[4], double at)
{
    const double h = x[2] - x[1], d = (f[2] - f[1]) / h;
    double d1 = d, d2 = d;
    if (!isnan(x[0])) {
        const double h0 = x[1] - x[0], s0 = (f[1] - f[0]) / h0;
        d1 = (h * s0 + h0 * d) / (h0 + h);
    }
    if (!isnan(x[3])) {
        const double h2 = x[3] - x[2], s2 = (f[3] - f[2]) / h2;
        d2 = (h2 * d + h * s2) / (h + h2);
    }
    const double s = (at - x[1]) / h;
    return (1 + 2 * s) * (1 - s) * (1 - s) * f[1] + s * (1 - s) * (1 - s) * h * d1 +
           s * s * (3 - 2 * s) * f[2] + s * s * (s - 1) * h * d2;
}

/* Patch p's current at node slot k and dV (cubic between grid points); *off = 1 when dV is off
 * the grid. */
static double patch_at(const ch_patches *P, int k, int p, double dV, int *off)
{
    const double *I = P->node_Ip + ((size_t)k * (size_t)P->np + (size_t)p) * (size_t)P->ndv;
    const int half = P->ndv / 2;
    const double x = asinh(dV / P->scale) / DV_STEP + half;
    if (!(x >= 0 && x <= P->ndv - 1)) {
        *off = 1;
        return 0;
    }
    int g = (int)floor(x);
    if (g >= P->ndv - 1)
        g = P->ndv - 2;
    double xs[4], fs[4];
    for (int q = 0; q < 4; q++) {
        const int gq = g - 1 + q;
        const int in = gq >= 0 && gq < P->ndv;
        xs[q] = in ? P->dv[gq] : NAN;
        fs[q] = in ? I[gq] : 0;
    }
    return cubic(xs, fs, dV);
}

int ch_patches_currents(ch_patches *P, double U, const double *dV, double *Ic, double *Ip,
                        double *sig, mote_err *err)
{
    if (P->direct) { /* the last state's (floated) */
        *Ic = P->J[0];
        for (int p = 0; p < P->np; p++)
            Ip[p] = P->J[1 + p];
        if (sig)
            *sig = P->sig;
        return MOTE_OK;
    }
    const double x = asinh((U - P->U0) / P->scale) / DU_STEP;
    if (!isfinite(x))
        return mote_fail(err, MOTE_ERUNTIME, "evolve: the body's potential is not finite");
    /* the nodes j - 1 ... j + 2 about the interval j, j + 1 that holds U */
    const int j = (int)floor(x);
    int k[4];
    double xs[4], fs[4];
    for (int q = 0; q < 4; q++) {
        if ((k[q] = node_slot(P, j - 1 + q, err)) < 0)
            return err->code;
        xs[q] = node_U(P, j - 1 + q);
        fs[q] = P->node_Ic[k[q]];
    }
    *Ic = cubic(xs, fs, U);
    if (sig) {
        const double f = (U - xs[1]) / (xs[2] - xs[1]);
        *sig = (1 - f) * P->node_sig[k[1]] + f * P->node_sig[k[2]];
    }
    int off = 0;
    for (int p = 0; p < P->np; p++) {
        for (int q = 0; q < 4; q++)
            fs[q] = patch_at(P, k[q], p, dV[p], &off);
        Ip[p] = cubic(xs, fs, U);
        if (off)
            return mote_fail(err, MOTE_ERUNTIME, "evolve: the potential of dielectric "
                             "part %d (in the order given) left the tabulated range: |V_p - U| "
                             "> %g V", p + 1, DV_MAX);
    }
    return MOTE_OK;
}

/* Solve the n x n system J x = J[][n] in place by Gaussian elimination with partial
 * pivoting (x into x); 1 when singular. */
static int solve_small(int n, double J[][CH_MAX_PATCHES + 2], double *x)
{
    for (int c = 0; c < n; c++) {
        int piv = c;
        for (int r = c + 1; r < n; r++)
            if (fabs(J[r][c]) > fabs(J[piv][c]))
                piv = r;
        if (!(fabs(J[piv][c]) > 0))
            return 1;
        if (piv != c)
            for (int q = 0; q <= n; q++) {
                const double tmp = J[c][q];
                J[c][q] = J[piv][q];
                J[piv][q] = tmp;
            }
        for (int r = c + 1; r < n; r++) {
            const double m = J[r][c] / J[c][c];
            for (int q = c; q <= n; q++)
                J[r][q] -= m * J[c][q];
        }
    }
    for (int r = n - 1; r >= 0; r--) {
        double s = J[r][n];
        for (int q = r + 1; q < n; q++)
            s -= J[r][q] * x[q];
        x[r] = s / J[r][r];
    }
    return 0;
}

double ch_patches_charge(const ch_patches *P, const double *y)
{
    if (!P->have_cv)
        return P->C * y[0];
    const int n = P->np + 1;
    double Q = 0;
    for (int k = 0; k < n; k++)
        for (int l = 0; l < n; l++)
            Q += P->Cv[k * n + l] * (y[0] + (l ? y[l] : 0));
    return Q;
}

/* y' = F(y) from the currents Ic (the conductor's) and Ip (each patch's) at y. */
static int rates(const ch_patches *P, const double *y, double Ic, const double *Ip, double *F,
                 mote_err *err)
{
    if (P->have_cv) { /* M dV/dt = dq/dt */
        const int n = P->np + 1;
        double M[CH_MAX_PATCHES + 1][CH_MAX_PATCHES + 2], dV[CH_MAX_PATCHES + 1];
        for (int k = 0; k < n; k++)
            for (int l = 0; l < n; l++)
                M[k][l] = P->Cv[k * n + l];
        M[0][n] = Ic;
        for (int p = 0; p < P->np; p++) {
            const double leak = isfinite(P->Rp[p]) ? y[1 + p] / P->Rp[p] : 0;
            M[0][0] += P->Cp[p];
            M[0][1 + p] -= P->Cp[p];
            M[1 + p][0] -= P->Cp[p];
            M[1 + p][1 + p] += P->Cp[p];
            M[0][n] += leak;
            M[1 + p][n] = Ip[p] - leak;
        }
        if (solve_small(n, M, dV))
            return mote_fail(err, MOTE_ERUNTIME, "evolve: the capacitance matrix is singular");
        F[0] = dV[0];
        for (int p = 0; p < P->np; p++)
            F[1 + p] = dV[1 + p] - dV[0];
        return MOTE_OK;
    }
    double I = Ic;
    for (int p = 0; p < P->np; p++) {
        I += Ip[p];
        F[1 + p] = (Ip[p] - (isfinite(P->Rp[p]) ? y[1 + p] / P->Rp[p] : 0)) / P->Cp[p];
    }
    F[0] = I / P->C;
    return MOTE_OK;
}

/* y' = F(y), y = (U, dV_1 ... dV_np). */
static int rhs(ch_patches *P, const double *y, double *F, mote_err *err)
{
    double Ic, Ip[CH_MAX_PATCHES];
    int rc = ch_patches_currents(P, y[0], y + 1, &Ic, Ip, NULL, err);
    return rc ? rc : rates(P, y, Ic, Ip, F, err);
}

/* One implicit Euler step z = y + h F(z) by Newton's method; 1 when it does not converge. */
static int be_step(ch_patches *P, const double *y, double h, double *z, mote_err *err)
{
    const int n = P->np + 1;
    double F[CH_MAX_PATCHES + 1], G[CH_MAX_PATCHES + 1], J[CH_MAX_PATCHES + 1][CH_MAX_PATCHES + 2];
    memcpy(z, y, (size_t)n * sizeof *z);
    for (int it = 0; it < 30; it++) {
        if (rhs(P, z, F, err))
            return -1;
        /* the residual r = z - y - h F(z) and its Jacobian I - h dF/dz, by differences */
        for (int c = 0; c < n; c++) {
            const double e = 1e-7 * fmax(fabs(z[c]), P->scale);
            double zc[CH_MAX_PATCHES + 1];
            memcpy(zc, z, (size_t)n * sizeof *z);
            zc[c] += e;
            if (rhs(P, zc, G, err))
                return -1;
            for (int r = 0; r < n; r++)
                J[r][c] = (r == c) - h * (G[r] - F[r]) / e;
        }
        for (int r = 0; r < n; r++)
            J[r][n] = -(z[r] - y[r] - h * F[r]);
        double dz[CH_MAX_PATCHES + 1], big = 0;
        if (solve_small(n, J, dz))
            return 1;
        for (int r = 0; r < n; r++) {
            z[r] += dz[r];
            big = fmax(big, fabs(dz[r]) / (ATOL + RTOL * fabs(z[r])));
        }
        if (!isfinite(big))
            return 1;
        if (big < 1e-3)
            return 0;
    }
    return 1;
}

/* direct: the net current at U with the differentials of y, the currents into J (and their
 * errors into sJ, unless NULL). */
static int direct_net_s(ch_patches *P, const double *y, double U, double *J, double *sJ,
                        double *sig, double *I, mote_err *err)
{
    double V[CH_MAX_PATCHES + 1];
    V[0] = U;
    for (int p = 0; p < P->np; p++)
        V[1 + p] = U + y[1 + p];
    double sj[CH_MAX_PATCHES + 1];
    int rc = P->direct(P->ctx, V, J, sJ ? sJ : sj, sig, err);
    if (rc)
        return rc;
    P->runs++;
    *I = 0;
    for (int k = 0; k <= P->np; k++)
        *I += J[k];
    return MOTE_OK;
}

static int direct_net(ch_patches *P, const double *y, double U, double *J, double *sig,
                      double *I, mote_err *err)
{
    return direct_net_s(P, y, U, J, NULL, sig, I, err);
}

int ch_patches_float(ch_patches *P, double *y, mote_err *err)
{
    const int n = P->np + 1;
    double J0[CH_MAX_PATCHES + 1], J1[CH_MAX_PATCHES + 1], s0, s1, I0, I1;
    double U0 = y[0], U1;
    int rc = direct_net(P, y, U0, J0, &s0, &I0, err);
    if (rc)
        return rc;
    if (P->slope > 0 && fabs(I0) <= s0 / 3) { /* there already, within the noise: the last
                                                * slope's correction (no run) */
        y[0] = U0 + I0 / P->slope;
        memcpy(P->J, J0, (size_t)n * sizeof *J0);
        P->sig = s0;
        P->sigma_U = s0 / P->slope;
        return MOTE_OK;
    }
    /* the bracket: steps from U, doubling, the way the net current points (it falls as U
     * rises: electrons gain, ions lose); the first a little past the root the last float's
     * slope predicts */
    double step = fmax(P->scale, 0.05 * fabs(U0));
    if (P->slope > 0 && I0 != 0)
        step = fmax(0.5 * P->scale, 1.2 * fabs(I0) / P->slope);
    for (int it = 0;; it++) {
        U1 = U0 + (I0 > 0 ? step : -step);
        if ((rc = direct_net(P, y, U1, J1, &s1, &I1, err)) != 0)
            return rc;
        if ((I0 > 0) != (I1 > 0) || I1 == 0)
            break;
        if (it == 40)
            return mote_fail(err, MOTE_ERUNTIME, "evolve: the net current keeps its sign from "
                             "%g V to %g V", y[0], U1);
        U0 = U1;
        I0 = I1;
        s0 = s1;
        memcpy(J0, J1, sizeof J0);
        step *= 2;
    }
    /* the Illinois variant of the false position, to 1e-2 of the potential, a quarter of
     * the smallest kT, or a third of the statistical error the net current's gives U, or 12
     * runs */
    int side = 0, at = 0; /* at: U1 is the root (its net current within the noise) */
    double w0 = I0;       /* the kept end's weight: its current, halved when kept twice */
    for (int it = 0; it < 12 && I1 != 0; it++) {
        if (fabs(I1) <= s1 / 3) {
            at = 1;
            break;
        }
        const double slope = fabs((I1 - I0) / (U1 - U0));
        const double tol = fmax(fmax(1e-2 * fabs(U1), 0.25 * P->scale), (s0 + s1) / 6 / slope);
        const double lo = fmin(U0, U1), wd = fabs(U1 - U0);
        if (!(wd > tol))
            break;
        /* (kept off the ends: a Monte Carlo current is flat in stretches) */
        const double U = fmin(fmax(U1 - I1 * (U1 - U0) / (I1 - w0), lo + 0.1 * wd), lo + 0.9 * wd);
        double J[CH_MAX_PATCHES + 1], s, I;
        if ((rc = direct_net(P, y, U, J, &s, &I, err)) != 0)
            return rc;
        if ((I > 0) == (I1 > 0)) { /* it replaces U1, U0 kept */
            if (side == 1)
                w0 *= 0.5;
            side = 1;
        } else { /* U1 becomes the kept end */
            U0 = U1;
            I0 = w0 = I1;
            s0 = s1;
            memcpy(J0, J1, sizeof J0);
            side = -1;
        }
        U1 = U;
        I1 = I;
        s1 = s;
        memcpy(J1, J, sizeof J1);
    }
    /* the root and its currents (linear between the ends; the last evaluation when it is the
     * root) */
    const double f = at || I1 == 0 || I1 == I0 ? 1 : I0 / (I0 - I1);
    y[0] = U0 + f * (U1 - U0);
    for (int k = 0; k < n; k++)
        P->J[k] = J0[k] + f * (J1[k] - J0[k]);
    P->sig = s0 + f * (s1 - s0);
    const double slope = U1 != U0 ? fabs((I1 - I0) / (U1 - U0)) : 0;
    double Ct = 0;
    for (int q = 0; P->have_cv && q < n * n; q++)
        Ct += P->Cv[q];
    if (!P->have_cv)
        Ct = P->C;
    if (slope > 0)
        P->slope = slope;
    P->sigma_U = slope > 0 ? P->sig / slope : 0;
    P->tau_c = slope > 0 ? Ct / slope : INFINITY;
    return MOTE_OK;
}

/* The steady state's residual at y: F[0] the whole net current, F[1 + p] patch p's net current
 * less its leak (what charges its layer); *sig the net current's error. direct: a run at y's
 * potentials (P->J, P->sig its currents). */
static int steady_residual(ch_patches *P, const double *y, double *F, double *sig, double *sF,
                           mote_err *err)
{
    double Ic, Ip[CH_MAX_PATCHES];
    if (P->direct) {
        double J[CH_MAX_PATCHES + 1], sJ[CH_MAX_PATCHES + 1], I;
        const int rc = direct_net_s(P, y, y[0], J, sJ, sig, &I, err);
        if (rc)
            return rc;
        memcpy(P->J, J, sizeof J);
        P->sig = *sig;
        Ic = J[0];
        memcpy(Ip, J + 1, (size_t)P->np * sizeof *Ip);
        if (sF)
            memcpy(sF, sJ, (size_t)(P->np + 1) * sizeof *sF);
    } else {
        const int rc = ch_patches_currents(P, y[0], y + 1, &Ic, Ip, sig, err);
        if (rc)
            return rc;
        if (sF)
            for (int k = 0; k <= P->np; k++)
                sF[k] = NAN; /* (the tables keep no part's error) */
    }
    F[0] = Ic;
    for (int p = 0; p < P->np; p++) {
        F[0] += Ip[p];
        F[1 + p] = Ip[p] - (isfinite(P->Rp[p]) ? y[1 + p] / P->Rp[p] : 0);
    }
    return MOTE_OK;
}

/* The statistical errors of the potentials at a root of F from the currents' errors sF
 * (sF[0] the conductor's, sF[1 + p] part p's, independent): dy = -J^-1 dF with F = B g, g the
 * conductor's and the parts' currents (F[0] holds them all, F[1 + p] part p's); 1 when J is
 * singular. */
static int steady_errors(int n, double Jk[][CH_MAX_PATCHES + 1], const double *sF, double *sy)
{
    double Jinv[CH_MAX_PATCHES + 1][CH_MAX_PATCHES + 1];
    for (int c = 0; c < n; c++) { /* column c of J^-1 */
        double A[CH_MAX_PATCHES + 1][CH_MAX_PATCHES + 2], col[CH_MAX_PATCHES + 1];
        for (int r = 0; r < n; r++) {
            memcpy(A[r], Jk[r], (size_t)n * sizeof **Jk);
            A[r][n] = r == c;
        }
        if (solve_small(n, A, col))
            return 1;
        for (int r = 0; r < n; r++)
            Jinv[r][c] = col[r];
    }
    for (int c = 0; c < n; c++) {
        double v = 0;
        for (int k = 0; k < n; k++) {
            const double a = Jinv[c][0] + (k > 0 ? Jinv[c][k] : 0); /* (J^-1 B)[c][k] */
            v += a * a * sF[k] * sF[k];
        }
        sy[c] = sqrt(v);
    }
    return 0;
}

/* The tables' steady state by pseudo-transient continuation: implicit Euler steps of the
 * circuit itself (be_step: L-stable, each solved by Newton's method), the step growing fourfold
 * when one is taken (a quarter when Newton fails), from a nanosecond until a step of 10^15 s
 * changes no potential by more than tol of it: the state time evolution from y reaches, where
 * Newton on the currents alone can cycle (the currents are not monotonic where emitted electrons
 * turn back, a few volts about zero). */
static int steady_tables(ch_patches *P, double *y, double tol, int *iters, mote_err *err)
{
    const int n = P->np + 1;
    double h = 1e-9;
    for (int it = 0; it < 400; it++) {
        double z[CH_MAX_PATCHES + 1];
        const int rc = be_step(P, y, h, z, err);
        if (rc < 0)
            return err->code;
        if (rc) {
            h *= 0.25;
            if (h < 1e-15)
                break;
            continue;
        }
        double big = 0;
        for (int c = 0; c < n; c++) {
            const double V = z[0] + (c ? z[c] : 0);
            big = fmax(big, fabs(z[c] - y[c]) / fmax(tol * fabs(V), 1e-3 * P->scale));
            y[c] = z[c];
        }
        if (!isfinite(y[0]))
            break;
        *iters = it + 1;
        if (h >= 1e15 && big <= 1)
            return MOTE_OK;
        h = fmin(4 * h, 1e15);
    }
    return mote_fail(err, MOTE_ERUNTIME, "float: no steady state found (U = %g V): the "
                     "potentials still move after 400 implicit steps", y[0]);
}

int ch_patches_steady(ch_patches *P, double *y, double tol, int *iters, double *sy, mote_err *err)
{
    const int n = P->np + 1;
    if (!P->direct) { /* the tables: the way time takes */
        for (int c = 0; c < n; c++)
            sy[c] = NAN;
        int rc = steady_tables(P, y, tol, iters, err);
        double F[CH_MAX_PATCHES + 1], sig, G[CH_MAX_PATCHES + 1], s2;
        if (!rc)
            rc = steady_residual(P, y, F, &sig, NULL, err);
        if (rc)
            return rc;
        /* the common mode's slope there, for U's error */
        const double e = fmax(1e-6 * fabs(y[0]), 1e-3 * P->scale);
        double yc[CH_MAX_PATCHES + 1];
        memcpy(yc, y, (size_t)n * sizeof *y);
        yc[0] += e;
        if ((rc = steady_residual(P, yc, G, &s2, NULL, err)) != 0)
            return rc;
        P->slope = fabs(G[0] - F[0]) / e;
        P->sig = sig;
        P->sigma_U = P->slope > 0 ? sig / P->slope : 0;
        sy[0] = P->sigma_U;
        return MOTE_OK;
    }
    double Jk[CH_MAX_PATCHES + 1][CH_MAX_PATCHES + 1];
    /* the differences: tiny on the interpolated tables; in a direct run (common random numbers:
     * the currents are steps, a history changing its fate at a time) wide enough to span many */
    const double rel = P->direct ? 0.02 : 1e-6;
    const double floor_ = P->direct ? 0.5 * P->scale : 1e-3 * P->scale;
    double F[CH_MAX_PATCHES + 1], G[CH_MAX_PATCHES + 1], J[CH_MAX_PATCHES + 1][CH_MAX_PATCHES + 2];
    double sF[CH_MAX_PATCHES + 1], sig = 0;
    int it, done = 0;
    for (int c = 0; c < n; c++)
        sy[c] = NAN;
    for (it = 0; it < 60 && !done; it++) {
        int rc = steady_residual(P, y, F, &sig, sF, err);
        if (rc)
            return rc;
        for (int c = 0; c < n; c++) { /* the Jacobian by forward differences */
            const double V = y[0] + (c ? y[c] : 0), e = fmax(rel * fabs(V), floor_);
            double yc[CH_MAX_PATCHES + 1], s;
            memcpy(yc, y, (size_t)n * sizeof *y);
            yc[c] += e;
            if ((rc = steady_residual(P, yc, G, &s, NULL, err)) != 0)
                return rc;
            for (int r = 0; r < n; r++)
                J[r][c] = (G[r] - F[r]) / e;
        }
        /* the slope of the net current in the common mode, the Jacobian kept for the errors */
        P->slope = fabs(J[0][0]);
        for (int r = 0; r < n; r++) {
            memcpy(Jk[r], J[r], (size_t)n * sizeof **Jk);
            J[r][n] = -F[r];
        }
        double dz[CH_MAX_PATCHES + 1];
        if (solve_small(n, J, dz))
            return mote_fail(err, MOTE_ERUNTIME, "float: the currents do not change with the "
                             "potentials here (U = %g V): no steady state found", y[0]);
        double sz[CH_MAX_PATCHES + 1];
        const int have_err = isfinite(sF[0]) && !steady_errors(n, Jk, sF, sz);
        /* no potential moves by more than 5 kT or half of itself in one step */
        double shrink = 1;
        for (int c = 0; c < n; c++) {
            const double V = y[0] + (c ? y[c] : 0), lim = fmax(5 * P->scale, 0.5 * fabs(V));
            if (fabs(dz[c]) * shrink > lim)
                shrink = lim / fabs(dz[c]);
        }
        /* done when every step is within the tolerance of its potential, or (with errors)
         * within its statistical error: Newton's step is then below what the noise decides */
        int within_tol = shrink == 1, within_noise = shrink == 1 && have_err;
        for (int c = 0; c < n; c++) {
            const double V = y[0] + (c ? y[c] : 0), step = fabs(shrink * dz[c]);
            within_tol &= step <= fmax(tol * fabs(V), 1e-3 * P->scale);
            within_noise &= have_err && step <= sz[c];
            y[c] += shrink * dz[c];
        }
        if (!isfinite(y[0]))
            return mote_fail(err, MOTE_ERUNTIME, "float: the potentials ran off to infinity");
        done = within_tol || within_noise;
    }
    if (!done)
        return mote_fail(err, MOTE_ERUNTIME, "float: no steady state within 60 Newton steps "
                         "(U = %g V)", y[0]);
    /* the currents there, and the potentials' errors from theirs */
    int rc = steady_residual(P, y, F, &sig, sF, err);
    if (rc)
        return rc;
    P->sig = sig;
    P->sigma_U = P->slope > 0 ? sig / P->slope : 0;
    if (isfinite(sF[0]) && steady_errors(n, Jk, sF, sy))
        for (int c = 0; c < n; c++)
            sy[c] = NAN;
    *iters = it;
    return MOTE_OK;
}

/* direct: explicit steps of the differentials, the common mode floated after each. */
static int advance_direct(ch_patches *P, double *y, double *h, double t1, double *t,
                          mote_err *err)
{
    while (*t < t1) {
        double F[CH_MAX_PATCHES + 1];
        int rc = rates(P, y, P->J[0], P->J + 1, F, err);
        if (rc)
            return rc;
        /* no differential changes by more than dv_step (or 0.2 of itself, when more) */
        double hh = t1 - *t;
        if (P->steps > 0) /* (growing at most twofold a step) */
            hh = fmin(hh, 2 * *h);
        for (int p = 0; p < P->np; p++) {
            const double lim = fmax(P->dv_step, 0.25 * fabs(y[1 + p]));
            if (fabs(F[1 + p]) * hh > lim)
                hh = lim / fabs(F[1 + p]);
        }
        const int last = hh >= t1 - *t;
        for (int p = 0; p < P->np; p++)
            y[1 + p] += hh * F[1 + p];
        *t = last ? t1 : *t + hh;
        *h = hh;
        P->steps++;
        if ((rc = ch_patches_float(P, y, err)) != 0)
            return rc;
    }
    return MOTE_OK;
}

int ch_patches_advance(ch_patches *P, double *y, double *h, double t1, double *t, mote_err *err)
{
    if (P->direct)
        return advance_direct(P, y, h, t1, t, err);
    const int n = P->np + 1;
    while (*t < t1) {
        double hh = fmin(*h, t1 - *t);
        const int last = hh == t1 - *t;
        double y1[CH_MAX_PATCHES + 1], ym[CH_MAX_PATCHES + 1], y2[CH_MAX_PATCHES + 1];
        int rc = be_step(P, y, hh, y1, err);
        if (!rc)
            rc = be_step(P, y, 0.5 * hh, ym, err);
        if (!rc)
            rc = be_step(P, ym, 0.5 * hh, y2, err);
        if (rc < 0)
            return err->code;
        double en = 0;
        for (int k = 0; !rc && k < n; k++)
            en = fmax(en, fabs(y2[k] - y1[k]) / (ATOL + RTOL * fabs(y2[k])));
        if (rc || en > 1) { /* refused: a shorter step */
            *h = hh * (rc ? 0.25 : fmax(0.1, 0.9 / sqrt(en)));
            if (*h < 1e-15 * fmax(1, fabs(*t)))
                return mote_fail(err, MOTE_ERUNTIME, "evolve: the step fell below %g s at t = %g "
                                 "s", *h, *t);
            continue;
        }
        for (int k = 0; k < n; k++)
            y[k] = 2 * y2[k] - y1[k];
        *t = last ? t1 : *t + hh;
        P->steps++;
        const double grow = en > 0 ? fmin(4, 0.9 / sqrt(en)) : 4;
        if (!last || grow < 1)
            *h = hh * grow;
    }
    return MOTE_OK;
}
