/* ftree.c: the potential and the electric field of the body's panel charges anywhere, fast (issue
 * 55, item 1): a treecode (Barnes and Hut, Nature 324 (1986) 446) over the boundary-element
 * solution of bem.c, so that curved paths can be traced through the solved field.
 *
 * The panels' centroids are sorted into an octree (at most CH_FT_LEAF panels a leaf). Each node
 * keeps the multipole moments of its panels' charge about its centre (the area-weighted centroid
 * of its panels) up to the quadrupole, with each panel's own extent in its second moment (exact
 * for uniformly charged flat triangles), and its radius: the farthest vertex from that centre.
 * At a point x, a node whose radius is below theta times its distance is taken as its expansion;
 * otherwise its children, and at a leaf each panel exactly (the closed-form integrals of bem.c
 * and their gradient, so the field next to the surface is as accurate as the solve). The first
 * term left out is the octupole: each node's contribution is in error by at most about theta^3
 * of its charge's |q| / d (tests/test_bem.c measures the error against the direct sum).
 * Costs: the build O(n log n) time and O(n) memory (a few hundred bytes a panel); an evaluation
 * O(log n) node expansions plus the O(1) leaves near x (the direct sum is O(n)). The tree is read
 * only after the build: any number of threads evaluate it at once. */
#include "mote/charging.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { CH_FT_LEAF = 8 };

typedef struct {
    double c[3], r;        /* the expansion's centre, the radius of the node's panels about it */
    double q, p[3], Q[6];  /* monopole, dipole, traceless quadrupole (xx yy zz xy xz yz) */
    uint32_t first, count; /* the panels (an interval of the sorted order) */
    uint32_t child, nchild;/* the children (an interval of the nodes); nchild 0: a leaf */
} ft_node;

struct mote_ch_ftree {
    const mote_ch_body *b;
    double theta, scale;   /* scale: 1 / (4 pi eps0) */
    uint32_t n, nnode, cap;
    uint32_t *idx;         /* the panels in tree order */
    double *sig;           /* their charge densities (C/m^2 per volt) */
    double (*cen)[3];
    ft_node *pan;          /* each panel as a one-panel node (its own expansion) */
    ft_node *node;
};

/* Sort the panels first .. first + count - 1 into a node and its children (recursively). */
static int build(mote_ch_ftree *T, uint32_t ni, int depth)
{
    ft_node *nd = &T->node[ni];
    const mote_ch_body *b = T->b;
    /* the centre: the panels' area-weighted centroid; the box of the centroids */
    double c[3] = {0, 0, 0}, A = 0, lo[3] = {INFINITY, INFINITY, INFINITY},
           hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t k = nd->first; k < nd->first + nd->count; k++) {
        const uint32_t j = T->idx[k];
        for (int a = 0; a < 3; a++) {
            c[a] += b->area[j] * T->cen[j][a];
            lo[a] = fmin(lo[a], T->cen[j][a]);
            hi[a] = fmax(hi[a], T->cen[j][a]);
        }
        A += b->area[j];
    }
    for (int a = 0; a < 3; a++)
        nd->c[a] = A > 0 ? c[a] / A : 0.5 * (lo[a] + hi[a]);
    /* the moments about it; each panel's second moment exact for its triangle:
     * integral of y y^T dA = A/12 (sum_i v_i v_i^T + 9 c c^T) (about the centre) */
    nd->r = 0;
    for (uint32_t k = nd->first; k < nd->first + nd->count; k++) {
        const uint32_t j = T->idx[k];
        const double q = T->sig[j] * b->area[j];
        double d[3], S[6] = {0, 0, 0, 0, 0, 0};
        for (int a = 0; a < 3; a++)
            d[a] = T->cen[j][a] - nd->c[a];
        nd->q += q;
        for (int a = 0; a < 3; a++)
            nd->p[a] += q * d[a];
        for (int v = 0; v < 3; v++) {
            double e[3], e2 = 0;
            for (int a = 0; a < 3; a++) {
                e[a] = b->v[j][v][a] - nd->c[a];
                e2 += e[a] * e[a];
            }
            nd->r = fmax(nd->r, sqrt(e2));
            S[0] += e[0] * e[0];
            S[1] += e[1] * e[1];
            S[2] += e[2] * e[2];
            S[3] += e[0] * e[1];
            S[4] += e[0] * e[2];
            S[5] += e[1] * e[2];
        }
        S[0] += 9 * d[0] * d[0];
        S[1] += 9 * d[1] * d[1];
        S[2] += 9 * d[2] * d[2];
        S[3] += 9 * d[0] * d[1];
        S[4] += 9 * d[0] * d[2];
        S[5] += 9 * d[1] * d[2];
        const double w = T->sig[j] * b->area[j] / 12; /* sigma times the area's 1/12 */
        const double tr = S[0] + S[1] + S[2];
        for (int a = 0; a < 3; a++)
            nd->Q[a] += w * (3 * S[a] - tr);
        for (int a = 3; a < 6; a++)
            nd->Q[a] += w * 3 * S[a];
    }
    nd->child = 0;
    nd->nchild = 0;
    double span = 0;
    for (int a = 0; a < 3; a++)
        span = fmax(span, hi[a] - lo[a]);
    if (nd->count <= CH_FT_LEAF || !(span > 0) || depth > 60)
        return MOTE_OK;
    /* the octants about the middle of the centroids' box: counting sort of the interval */
    double mid[3];
    for (int a = 0; a < 3; a++)
        mid[a] = 0.5 * (lo[a] + hi[a]);
    uint32_t cnt[8] = {0}, start[8], *tmp = malloc((size_t)nd->count * sizeof *tmp);
    if (!tmp)
        return MOTE_ENOMEM;
    for (uint32_t k = 0; k < nd->count; k++) {
        const uint32_t j = T->idx[nd->first + k];
        const int o = (T->cen[j][0] > mid[0]) | (T->cen[j][1] > mid[1]) << 1 |
                      (T->cen[j][2] > mid[2]) << 2;
        cnt[o]++;
    }
    start[0] = 0;
    for (int o = 1; o < 8; o++)
        start[o] = start[o - 1] + cnt[o - 1];
    for (uint32_t k = 0; k < nd->count; k++) {
        const uint32_t j = T->idx[nd->first + k];
        const int o = (T->cen[j][0] > mid[0]) | (T->cen[j][1] > mid[1]) << 1 |
                      (T->cen[j][2] > mid[2]) << 2;
        tmp[start[o]++] = j;
    }
    memcpy(T->idx + nd->first, tmp, (size_t)nd->count * sizeof *tmp);
    free(tmp);
    uint32_t nch = 0;
    for (int o = 0; o < 8; o++)
        nch += cnt[o] > 0;
    if (T->nnode + nch > T->cap) {
        uint32_t cap = 2 * T->cap + nch;
        ft_node *nn = realloc(T->node, (size_t)cap * sizeof *nn);
        if (!nn)
            return MOTE_ENOMEM;
        T->node = nn;
        T->cap = cap;
        nd = &T->node[ni];
    }
    const uint32_t first_child = T->nnode, first = nd->first;
    nd->child = first_child;
    nd->nchild = nch;
    T->nnode += nch;
    uint32_t at = first, ch = first_child;
    for (int o = 0; o < 8; o++) {
        if (!cnt[o])
            continue;
        memset(&T->node[ch], 0, sizeof T->node[ch]);
        T->node[ch].first = at;
        T->node[ch].count = cnt[o];
        at += cnt[o];
        ch++;
    }
    for (uint32_t k = 0; k < nch; k++) {
        const int rc = build(T, first_child + k, depth + 1);
        if (rc)
            return rc;
    }
    return MOTE_OK;
}

mote_ch_ftree *mote_ch_ftree_build(const mote_ch_body *b, const double *sigma, double theta,
                                   mote_err *err)
{
    if (!(theta > 0 && theta < 1)) {
        mote_fail(err, MOTE_EINVAL, "the field's tree: theta must be in (0, 1), found %g", theta);
        return NULL;
    }
    if (b->sphere || b->ntri == 0) {
        mote_fail(err, MOTE_EINVAL, "the field's tree: no panels");
        return NULL;
    }
    mote_ch_ftree *T = calloc(1, sizeof *T);
    const uint32_t n = b->ntri;
    if (T) {
        T->b = b;
        T->theta = theta;
        T->scale = 1 / (4 * MOTE_CH_PI * MOTE_CH_EPS0);
        T->n = n;
        T->cap = n / 2 + 16;
        T->idx = malloc((size_t)n * sizeof *T->idx);
        T->sig = malloc((size_t)n * sizeof *T->sig);
        T->cen = malloc((size_t)n * sizeof *T->cen);
        T->node = calloc(T->cap, sizeof *T->node);
        T->pan = malloc((size_t)n * sizeof *T->pan);
    }
    if (!T || !T->idx || !T->sig || !T->cen || !T->node || !T->pan) {
        mote_ch_ftree_free(T);
        mote_fail(err, MOTE_ENOMEM, "out of memory for the field's tree of %u panels", n);
        return NULL;
    }
    for (uint32_t j = 0; j < n; j++) {
        T->idx[j] = j;
        T->sig[j] = sigma[j];
        for (int a = 0; a < 3; a++)
            T->cen[j][a] = (b->v[j][0][a] + b->v[j][1][a] + b->v[j][2][a]) / 3;
    }
    for (uint32_t j = 0; j < n; j++) { /* (each panel's own moments: the same code) */
        mote_ch_ftree one = *T;
        uint32_t self = j;
        one.idx = &self;
        one.node = &T->pan[j];
        memset(one.node, 0, sizeof *one.node);
        one.node->first = 0;
        one.node->count = 1;
        build(&one, 0, 0);
    }
    T->nnode = 1;
    T->node[0].first = 0;
    T->node[0].count = n;
    if (build(T, 0, 0)) {
        mote_ch_ftree_free(T);
        mote_fail(err, MOTE_ENOMEM, "out of memory for the field's tree of %u panels", n);
        return NULL;
    }
    return T;
}

size_t mote_ch_ftree_bytes(const mote_ch_ftree *T)
{
    return sizeof *T + (size_t)T->n * (sizeof *T->idx + sizeof *T->sig + sizeof *T->cen) +
           (size_t)T->cap * sizeof *T->node + (size_t)T->n * sizeof *T->pan;
}

/* A node's expansion at x: adds to *phi and E (per 1 / (4 pi eps0)). */
static void expansion(const ft_node *nd, const double x[3], double *phi, double E[3])
{
    const double r[3] = {x[0] - nd->c[0], x[1] - nd->c[1], x[2] - nd->c[2]};
    const double r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2], ir2 = 1 / r2, ir = sqrt(ir2);
    const double ir3 = ir * ir2, ir5 = ir3 * ir2;
    const double pr = nd->p[0] * r[0] + nd->p[1] * r[1] + nd->p[2] * r[2];
    const double *Q = nd->Q;
    const double Qr[3] = {Q[0] * r[0] + Q[3] * r[1] + Q[4] * r[2],
                          Q[3] * r[0] + Q[1] * r[1] + Q[5] * r[2],
                          Q[4] * r[0] + Q[5] * r[1] + Q[2] * r[2]};
    const double rQr = r[0] * Qr[0] + r[1] * Qr[1] + r[2] * Qr[2];
    /* phi = q / r + p.r / r^3 + r.Q.r / (2 r^5); E = -grad phi */
    *phi += nd->q * ir + pr * ir3 + 0.5 * rQr * ir5;
    const double radial = nd->q * ir3 + 3 * pr * ir5 + 2.5 * rQr * ir5 * ir2;
    for (int a = 0; a < 3; a++)
        E[a] += radial * r[a] - nd->p[a] * ir3 - Qr[a] * ir5;
}

/* The 7-point rule of degree 5 on a triangle (Strang and Fix 1973; Dunavant 1985): the weights
 * and barycentric coordinates of its centroid and two orbits of three. */
static const double Q7_W[3] = {0.225, 0.13239415278850619, 0.12593918054482714};
static const double Q7_A[3] = {1.0 / 3, 0.059715871789769820, 0.79742698535308732};
static const double Q7_B[3] = {1.0 / 3, 0.47014206410511509, 0.10128650732345634};

/* Panel j's potential and field at x (per unit charge density) by the 7-point rule: within
 * 1.6e-4 (phi) and 1.2e-3 (the field) of the exact integral beyond 1.75 radii of the panel
 * (measured on an equilateral and a thin triangle), below the tree's own error. */
static void panel_rule(const mote_ch_ftree *T, uint32_t j, const double x[3], double *phi,
                       double E[3], double sig)
{
    double(*v)[3] = T->b->v[j];
    const double qa = sig * T->b->area[j];
    for (int o = 0; o < 3; o++)
        for (int k = 0; k < (o ? 3 : 1); k++) {
            const double a = Q7_A[o], b = Q7_B[o];
            const double w0 = k == 0 ? a : b, w1 = k == 1 ? a : b, w2 = k == 2 ? a : b;
            double d[3];
            for (int c = 0; c < 3; c++)
                d[c] = x[c] - (w0 * v[0][c] + w1 * v[1][c] + w2 * v[2][c]);
            const double id = 1 / sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            const double q = qa * Q7_W[o] * id;
            *phi += q;
            for (int c = 0; c < 3; c++)
                E[c] += q * id * id * d[c];
        }
}

void mote_ch_ftree_eval(const mote_ch_ftree *T, const double x[3], double *phi, double E[3])
{
    double ph = 0, e[3] = {0, 0, 0};
    uint32_t stack[64 * 8];
    int top = 0;
    stack[top++] = 0;
    const double th2 = T->theta * T->theta;
    while (top > 0) {
        const ft_node *nd = &T->node[stack[--top]];
        const double d[3] = {x[0] - nd->c[0], x[1] - nd->c[1], x[2] - nd->c[2]};
        const double d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        if (nd->r * nd->r < th2 * d2) {
            expansion(nd, x, &ph, e);
            continue;
        }
        if (nd->nchild == 0) {
            for (uint32_t k = nd->first; k < nd->first + nd->count; k++) {
                const uint32_t j = T->idx[k];
                const ft_node *pn = &T->pan[j];
                const double dp[3] = {x[0] - pn->c[0], x[1] - pn->c[1], x[2] - pn->c[2]};
                const double dp2 = dp[0] * dp[0] + dp[1] * dp[1] + dp[2] * dp[2];
                if (pn->r * pn->r < th2 * dp2) {
                    expansion(pn, x, &ph, e); /* far enough for its own expansion */
                    continue;
                }
                if (1.75 * 1.75 * pn->r * pn->r < dp2) { /* far enough for a rule */
                    panel_rule(T, j, x, &ph, e, T->sig[j]);
                    continue;
                }
                double g[3];
                ph += T->sig[j] * mote_ch_triangle_gradient(T->b->v[j], x, g);
                for (int a = 0; a < 3; a++)
                    e[a] -= T->sig[j] * g[a];
            }
            continue;
        }
        for (uint32_t k = 0; k < nd->nchild; k++)
            stack[top++] = nd->child + k;
    }
    *phi = ph * T->scale;
    for (int a = 0; a < 3; a++)
        E[a] = e[a] * T->scale;
}

void mote_ch_ftree_moments(const mote_ch_ftree *T, double c[3], double *q, double p[3],
                           double Q[6], double *r)
{
    const ft_node *nd = &T->node[0];
    for (int a = 0; a < 3; a++) {
        c[a] = nd->c[a];
        p[a] = nd->p[a];
    }
    for (int a = 0; a < 6; a++)
        Q[a] = nd->Q[a];
    *q = nd->q;
    *r = nd->r;
}

double mote_ch_ftree_monopole_radius(const mote_ch_ftree *T, const double c[3], double tol)
{
    const ft_node *nd = &T->node[0];
    const double q = nd->q;
    if (!(q > 0) || !(tol > 0))
        return INFINITY;
    /* the dipole and quadrupole about c (shifted by d = root - c):
     * p' = p + q d, Q' = Q + 3 (p d^T + d p^T) - 2 (p.d) I + q (3 d d^T - d^2 I) */
    const double d[3] = {nd->c[0] - c[0], nd->c[1] - c[1], nd->c[2] - c[2]};
    double p[3], Q[3][3], pd = 0, d2 = 0;
    for (int a = 0; a < 3; a++) {
        p[a] = nd->p[a] + q * d[a];
        pd += nd->p[a] * d[a];
        d2 += d[a] * d[a];
    }
    static const int at[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};
    double qf = 0, pn = 0;
    for (int a = 0; a < 3; a++) {
        pn += p[a] * p[a];
        for (int b = 0; b < 3; b++) {
            Q[a][b] = nd->Q[at[a][b]] + 3 * (nd->p[a] * d[b] + d[a] * nd->p[b]) +
                      q * 3 * d[a] * d[b] - (a == b ? 2 * pd + q * d2 : 0);
            qf += Q[a][b] * Q[a][b];
        }
    }
    /* the field of the dipole is at most 2 |p| / rho^3, the quadrupole's 3.5 |Q| / rho^4: their
     * sum against the monopole's q / rho^2 equal to tol */
    const double A = 2 * sqrt(pn) / q, B = 3.5 * sqrt(qf) / q;
    const double rho = (A + sqrt(A * A + 4 * tol * B)) / (2 * tol);
    const double reach = nd->r + sqrt(d2); /* (the panels' radius about c) */
    return fmax(rho, 2 * reach);
}

double mote_ch_ftree_charge(const mote_ch_ftree *T) { return T->node[0].q; }

void mote_ch_ftree_free(mote_ch_ftree *T)
{
    if (!T)
        return;
    free(T->idx);
    free(T->sig);
    free(T->cen);
    free(T->node);
    free(T->pan);
    free(T);
}
