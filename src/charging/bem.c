/* bem.c: the body's own electrostatic field in vacuum (issue 55, item 1, its first part): the
 * charge on a conducting body at the potential U = 1 V solved by the boundary-element method,
 * and from it the body's capacitance C = Q / U.
 *
 * The method: the single-layer potential of a surface charge density sigma that is constant on
 * each triangle (panel) j,
 *
 *     phi(x) = sum_j sigma_j / (4 pi eps0) * integral over T_j of dS / |x - y|,
 *
 * set equal to U at each panel's centroid (collocation); a two-sided sheet (an open component)
 * carries the charge of both its sides in one sigma, as a single layer does. Each integral is
 * the exact one of a flat triangle (Wilton, Rao, Glisson, Schaubert, Al-Bundak and Butler, IEEE
 * Trans. Antennas Propag. 32 (1984) 276, eq. 5 for the scalar potential of a uniform triangle):
 * no quadrature, so the self and near terms are as accurate as the far ones. The n x n system is
 * solved by LU with partial pivoting (LAPACK's blocked algorithm from its dgetrf, dlaswp and
 * BLAS's dtrsm and dgemm, panel by panel so that progress and Ctrl-C are heard, then dgetrs;
 * in place; Debian's OpenBLAS where it is installed). Costs: the matrix n^2 entries (memory 8 n^2 bytes, the assembly O(n^2) on the
 * model's threads), the solve O(n^3) (2/3 n^3 flops). Accuracy: flat panels on a smooth body
 * give C with an error O(h^2) in the panel size h (tests/test_bem.c: the sphere); edges and
 * corners (the cube, a disk's rim) make the charge singular there and the error larger, O(h)
 * (tests/test_bem.c states each). */
#include "mote/charging.h"

#include <cblas.h>
#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The integral of dS / |p - y| over the flat triangle t, exactly (Wilton et al. 1984, eq. 5: the
 * sum over the edges of P0 times the edge's integral of 1/R, less |w| times the solid angle the
 * triangle subtends at p, w the height of p over its plane), and its exact gradient with
 * respect to p in g: in the plane, minus the sum of the edges' outward normals times their
 * integrals of 1/R (the divergence theorem); across it, minus the signed solid angle. */
double mote_ch_triangle_gradient(double t[3][3], const double p[3], double g[3])
{
    double e1[3], e2[3], n[3];
    g[0] = g[1] = g[2] = 0;
    for (int k = 0; k < 3; k++) {
        e1[k] = t[1][k] - t[0][k];
        e2[k] = t[2][k] - t[0][k];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    const double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(nn > 0))
        return 0;
    for (int k = 0; k < 3; k++)
        n[k] /= nn;
    const double w = (p[0] - t[0][0]) * n[0] + (p[1] - t[0][1]) * n[1] + (p[2] - t[0][2]) * n[2];
    const double aw = fabs(w);
    double sum = 0, omega = 0;
    for (int i = 0; i < 3; i++) {
        const double *a = t[i], *b = t[(i + 1) % 3];
        double s[3], len = 0;
        for (int k = 0; k < 3; k++) {
            s[k] = b[k] - a[k];
            len += s[k] * s[k];
        }
        len = sqrt(len);
        if (!(len > 0))
            continue;
        for (int k = 0; k < 3; k++)
            s[k] /= len;
        const double u[3] = {s[1] * n[2] - s[2] * n[1], s[2] * n[0] - s[0] * n[2],
                             s[0] * n[1] - s[1] * n[0]};
        double ap[3], bp[3];
        for (int k = 0; k < 3; k++) {
            ap[k] = a[k] - p[k];
            bp[k] = b[k] - p[k];
        }
        const double P0 = ap[0] * u[0] + ap[1] * u[1] + ap[2] * u[2];
        const double lm = ap[0] * s[0] + ap[1] * s[1] + ap[2] * s[2];
        const double lp = bp[0] * s[0] + bp[1] * s[1] + bp[2] * s[2];
        const double Rm = sqrt(ap[0] * ap[0] + ap[1] * ap[1] + ap[2] * ap[2]);
        const double Rp = sqrt(bp[0] * bp[0] + bp[1] * bp[1] + bp[2] * bp[2]);
        const double R02 = P0 * P0 + w * w;
        /* the edge's integral of 1/R, ln((R+ + l+) / (R- + l-)), its digits kept where l < 0 */
        const double num = lp >= 0 ? Rp + lp : R02 / (Rp - lp);
        const double den = lm >= 0 ? Rm + lm : R02 / (Rm - lm);
        const double f = num > 0 && den > 0 ? log(num / den) : 0; /* (0: p on the edge) */
        sum += P0 * f;
        for (int k = 0; k < 3; k++)
            g[k] -= u[k] * f;
        if (aw > 0)
            omega += atan(P0 * lp / (R02 + aw * Rp)) - atan(P0 * lm / (R02 + aw * Rm));
    }
    const double sg = w > 0 ? 1 : w < 0 ? -1 : 0;
    for (int k = 0; k < 3; k++)
        g[k] -= sg * omega * n[k];
    return sum - aw * omega;
}

/* The integral alone (the boundary elements' matrix). */
double mote_ch_triangle_integral(double t[3][3], const double p[3])
{
    double g[3];
    return mote_ch_triangle_gradient(t, p, g);
}

/* The centroid of triangle t. */
static void centroid(double t[3][3], double c[3])
{
    for (int k = 0; k < 3; k++)
        c[k] = (t[0][k] + t[1][k] + t[2][k]) / 3;
}

size_t mote_ch_bem_bytes(uint32_t n) { return (size_t)n * n * sizeof(double); }

/* The LU factors of the n x n column-major M in place, with partial pivoting (piv 1-based, as
 * LAPACK's): LAPACK's own blocked algorithm, panel by panel (dgetrf on the panel, the rows
 * swapped beside it, dtrsm and dgemm on the rest), so that the progress line moves and Ctrl-C
 * is heard between panels. 0, the first zero pivot's column (1-based), or -1 when stopped. */
static lapack_int blocked_lu(double *M, lapack_int n, lapack_int *piv, mote_progress *prog,
                             double done0, double share)
{
    enum { NB = 128 };
    lapack_int info = 0;
    for (lapack_int j = 0; j < n; j += NB) {
        const lapack_int jb = n - j < NB ? n - j : NB, rest = n - j - jb;
        const lapack_int pinfo = LAPACKE_dgetrf(LAPACK_COL_MAJOR, n - j, jb, M + j + (size_t)j * n,
                                                n, piv + j);
        if (pinfo > 0 && info == 0)
            info = pinfo + j;
        for (lapack_int i = j; i < j + jb; i++)
            piv[i] += j;
        if (j > 0)
            LAPACKE_dlaswp(LAPACK_COL_MAJOR, j, M, n, j + 1, j + jb, piv, 1);
        if (rest > 0) {
            double *right = M + (size_t)(j + jb) * n;
            LAPACKE_dlaswp(LAPACK_COL_MAJOR, rest, right, n, j + 1, j + jb, piv, 1);
            cblas_dtrsm(CblasColMajor, CblasLeft, CblasLower, CblasNoTrans, CblasUnit, jb, rest,
                        1.0, M + j + (size_t)j * n, n, right + j, n);
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, rest, rest, jb, -1.0,
                        M + j + jb + (size_t)j * n, n, right + j, n, 1.0, right + j + jb, n);
        }
        /* the work done: 1 - (rest / n)^3 of the 2/3 n^3 flops */
        const double left = (double)rest / (double)n;
        if (prog && mote_progress_update(prog, done0 + share * (1 - left * left * left)))
            return -1;
    }
    return info;
}

int mote_ch_bem_solve(const mote_ch_body *b, int threads, const mote_context *ctx,
                      const char *label, mote_ch_bem *f, mote_err *err)
{
    return mote_ch_bem_solve_conductors(b, NULL, 1, threads, ctx, label, f, err);
}

int mote_ch_bem_solve_conductors(const mote_ch_body *b, const int *cond, int nc, int threads,
                                 const mote_context *ctx, const char *label, mote_ch_bem *f,
                                 mote_err *err)
{
    memset(f, 0, sizeof *f);
    if (b->sphere)
        return mote_fail(err, MOTE_EINVAL, "the exact sphere's field is exact already (no panels "
                         "to solve)");
    const uint32_t n = b->ntri;
    if (n == 0)
        return mote_fail(err, MOTE_EINVAL, "no body to solve");
    if (nc < 1 || nc > MOTE_CH_BEM_MAX_CONDUCTORS || (nc > 1 && !cond))
        return mote_fail(err, MOTE_EINVAL, "%d conductors: give 1 to %d, each panel's", nc,
                         MOTE_CH_BEM_MAX_CONDUCTORS);
    if (cond) { /* every panel on a conductor, every conductor with a panel */
        uint32_t count[MOTE_CH_BEM_MAX_CONDUCTORS] = {0};
        for (uint32_t j = 0; j < n; j++) {
            if (cond[j] < 0 || cond[j] >= nc)
                return mote_fail(err, MOTE_EINVAL, "panel %u is on conductor %d (of 0 to %d)",
                                 j + 1, cond[j], nc - 1);
            count[cond[j]]++;
        }
        for (int k = 0; k < nc; k++)
            if (count[k] == 0)
                return mote_fail(err, MOTE_EINVAL, "conductor %d has no panels", k);
    }
    if (n > MOTE_CH_BEM_MAX)
        return mote_fail(err, MOTE_ENOMEM, "%u panels are more than the field's solve takes "
                         "(at most %u: its matrix is 8 n^2 bytes, %.3g GB here); coarsen the "
                         "mesh", n, (unsigned)MOTE_CH_BEM_MAX, 8.0 * n * (double)n / 1e9);
    double *A = malloc(mote_ch_bem_bytes(n));
    double *basis = malloc((size_t)n * (size_t)nc * sizeof *basis);
    double *sigma = nc > 1 ? malloc((size_t)n * sizeof *sigma) : NULL;
    double *cmat = malloc((size_t)nc * (size_t)nc * sizeof *cmat);
    lapack_int *piv = malloc((size_t)n * sizeof *piv);
    if (!A || !basis || (nc > 1 && !sigma) || !cmat || !piv) {
        free(A);
        free(basis);
        free(sigma);
        free(cmat);
        free(piv);
        return mote_fail(err, MOTE_ENOMEM, "out of memory for the field's matrix of %u panels "
                         "(%.3g GB)", n, 8.0 * n * (double)n / 1e9);
    }
    const double k = 1 / (4 * MOTE_CH_PI * MOTE_CH_EPS0);
    /* the progress line: the assembly its first share (n^2 integrals), the LU the rest (2/3 n^3
     * flops), as they take about that on this kind of machine at a few thousand panels */
    mote_progress own, *prog = NULL;
    if (ctx) {
        mote_progress_begin(&own, ctx, label ? label : "solve");
        prog = &own;
    }
    const double share_a = 1 / (1 + (double)n / 3000);
    int stopped = 0;
    /* row i: the potential at centroid i of unit charge density on each panel j (A row-major),
     * in blocks of rows, the progress between them */
    for (uint32_t i0 = 0; i0 < n && !stopped; i0 += 256) {
        const uint32_t i1 = n - i0 < 256 ? n : i0 + 256;
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads > 0 ? threads : 1)
        for (uint32_t i = i0; i < i1; i++) {
            double c[3];
            centroid(b->v[i], c);
            for (uint32_t j = 0; j < n; j++)
                A[(size_t)i * n + j] = k * mote_ch_triangle_integral(b->v[j], c);
        }
        stopped = prog && mote_progress_update(prog, share_a * i1 / n);
    }
    /* the right-hand sides, one a conductor: 1 V on its panels, 0 on the others' */
    for (int l = 0; l < nc; l++)
        for (uint32_t i = 0; i < n; i++)
            basis[(size_t)l * n + i] = !cond || cond[i] == l;
    /* A row by row is, read column by column, A^T: LAPACK factors that in place (no copy of
     * the matrix) and solves (A^T)^T sigma = rhs, all the right-hand sides on the one LU */
    lapack_int info = stopped ? -1 : blocked_lu(A, (lapack_int)n, piv, prog, share_a, 1 - share_a);
    if (info == 0)
        info = LAPACKE_dgetrs(LAPACK_COL_MAJOR, 'T', (lapack_int)n, (lapack_int)nc, A,
                              (lapack_int)n, piv, basis, (lapack_int)n);
    if (prog)
        mote_progress_end(prog);
    free(A);
    free(piv);
    if (info != 0) {
        free(basis);
        free(sigma);
        free(cmat);
        if (info < 0)
            return mote_interrupted(err, label ? label : "solve");
        return mote_fail(err, MOTE_EINVAL, "the field's system of %u panels is singular (LAPACK "
                         "dgetrf: %d): two panels in the same place (coincident conductors)?",
                         n, (int)info);
    }
    /* C[k][l]: the charge on conductor k with conductor l at 1 V and the others at 0 */
    memset(cmat, 0, (size_t)nc * (size_t)nc * sizeof *cmat);
    for (int l = 0; l < nc; l++)
        for (uint32_t j = 0; j < n; j++)
            cmat[(cond ? cond[j] : 0) * nc + l] += basis[(size_t)l * n + j] * b->area[j];
    double Q = 0;
    for (int q = 0; q < nc * nc; q++)
        Q += cmat[q];
    if (nc > 1) { /* all at 1 V: the sum of the columns */
        for (uint32_t j = 0; j < n; j++) {
            double s = 0;
            for (int l = 0; l < nc; l++)
                s += basis[(size_t)l * n + j];
            sigma[j] = s;
        }
    } else {
        sigma = basis;
        basis = NULL;
    }
    f->n = n;
    f->nc = nc;
    f->sigma = sigma;
    f->basis = basis;
    f->cmat = cmat;
    f->capacitance = Q; /* (all at U = 1 V) */
    return MOTE_OK;
}

double mote_ch_bem_potential(const mote_ch_body *b, const mote_ch_bem *f, const double x[3])
{
    double phi = 0;
    for (uint32_t j = 0; j < f->n; j++)
        phi += f->sigma[j] * mote_ch_triangle_integral(b->v[j], x);
    return phi / (4 * MOTE_CH_PI * MOTE_CH_EPS0);
}

void mote_ch_bem_free(mote_ch_bem *f)
{
    free(f->sigma);
    free(f->basis);
    free(f->cmat);
    memset(f, 0, sizeof *f);
}
