/* mesh.c: the separator's walls from meshes (issue 56): rigid walls of triangles read by the
 * core's mesh layer (mesh.h), at rest, translating or turning about an axis; the contacts of a
 * sphere with their faces, edges and vertices, each feature once; the tests that keep new
 * particles out of them. The triangles are found through a grid in the wall's own frame (a
 * moving wall's particles are taken into that frame), each cell listing the triangles within
 * reach of the largest particle anywhere in it, so a particle looks in one cell. */
#include "sep.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void mote_sep_mesh_free(mote_sep_mesh *w)
{
    free(w->v);
    free(w->t);
    free(w->cstart);
    free(w->ctri);
    free(w->fe);
    free(w->plane);
    memset(w, 0, sizeof *w);
}

/* (an edge: its ends, lower first, and its triangle) */
typedef struct {
    uint32_t a, b, t;
} edge_rec;

static int cmp_edge_rec(const void *x, const void *y)
{
    const edge_rec *p = x, *q = y;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    if (p->b != q->b)
        return p->b < q->b ? -1 : 1;
    return (p->t > q->t) - (p->t < q->t);
}

static void tri_normal(const mote_sep_mesh *w, uint32_t t, double n[3])
{
    const double *a = w->v[w->t[t][0]], *b = w->v[w->t[t][1]], *c = w->v[w->t[t][2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                 v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    const double l = sqrt(sep_dot3(n, n));
    for (int k = 0; k < 3; k++)
        n[k] = l > 0 ? n[k] / l : 0;
}

/* The wall's outline for pictures (w->fe), and how many of its edges are not shared by exactly
 * two triangles (*open). */
static int feature_edges(mote_sep_mesh *w, size_t *open)
{
    edge_rec *e = malloc((3 * w->nt + 1) * sizeof *e);
    w->fe = malloc((3 * w->nt + 1) * sizeof *w->fe);
    if (!e || !w->fe) {
        free(e);
        return -1;
    }
    for (size_t t = 0; t < w->nt; t++)
        for (int j = 0; j < 3; j++) {
            const uint32_t p = w->t[t][j], q = w->t[t][(j + 1) % 3];
            e[3 * t + (size_t)j] = (edge_rec){p < q ? p : q, p < q ? q : p, (uint32_t)t};
        }
    qsort(e, 3 * w->nt, sizeof *e, cmp_edge_rec);
    w->nfe = 0;
    for (size_t i = 0; i < 3 * w->nt;) {
        size_t j = i;
        while (j < 3 * w->nt && e[j].a == e[i].a && e[j].b == e[i].b)
            j++;
        int keep = j - i != 2;
        *open += keep;
        if (!keep) { /* (the normals' angle, whichever way the triangles are wound) */
            double n1[3], n2[3];
            tri_normal(w, e[i].t, n1);
            tri_normal(w, e[i + 1].t, n2);
            keep = fabs(sep_dot3(n1, n2)) < cos(20 * SEP_PI / 180);
        }
        if (keep) {
            w->fe[w->nfe][0] = e[i].a;
            w->fe[w->nfe++][1] = e[i].b;
        }
        i = j;
    }
    free(e);
    return 0;
}

int sep_mesh_add(mote_sep_system *s, const mote_mesh *m, const char *path, int solid,
                 const double vel[3], const double axis[3], double omega, const double centre[3],
                 mote_err *err)
{
    if (s->nmesh == MOTE_SEP_MAX_MESHES)
        return mote_fail(err, MOTE_EINVAL, "%s: more than %d mesh walls", path,
                         MOTE_SEP_MAX_MESHES);
    if (solid) {
        size_t open = 0;
        for (size_t k = 0; k < m->nt; k++)
            open += !m->closed[k];
        if (open)
            return mote_fail(err, MOTE_EINVAL, "%s: solid=yes needs a closed mesh (every edge "
                             "shared by exactly two triangles); %zu of its %zu triangles are in "
                             "open components", path, open, m->nt);
    }
    double k[3] = {axis[0], axis[1], axis[2]};
    const double kl = sqrt(sep_dot3(k, k));
    if (omega != 0 && !(kl > 0 && isfinite(kl)))
        return mote_fail(err, MOTE_EINVAL, "%s: omega= needs an axis= of non-zero length", path);
    mote_sep_mesh w = {0};
    const char *base = strrchr(path, '/');
    snprintf(w.name, sizeof w.name, "%s", base ? base + 1 : path);
    for (char *q = w.name; *q; q++) /* (one word in a state file) */
        if (*q == ' ' || *q == '\t' || *q == '\n' || *q == '\r')
            *q = '_';
    if (!w.name[0])
        snprintf(w.name, sizeof w.name, "mesh");
    w.nv = m->nv;
    w.nt = m->nt;
    w.v = malloc((m->nv ? m->nv : 1) * sizeof *w.v);
    w.t = malloc((m->nt ? m->nt : 1) * sizeof *w.t);
    if (!w.v || !w.t) {
        mote_sep_mesh_free(&w);
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", path);
    }
    memcpy(w.v, m->v, m->nv * sizeof *w.v);
    memcpy(w.t, m->t, m->nt * sizeof *w.t);
    w.plane = malloc((m->nt ? m->nt : 1) * sizeof *w.plane);
    for (size_t t = 0; w.plane && t < m->nt; t++) {
        tri_normal(&w, (uint32_t)t, w.plane[t]);
        w.plane[t][3] = sep_dot3(w.plane[t], w.v[w.t[t][0]]);
    }
    size_t open_edges = 0;
    if (!w.plane || feature_edges(&w, &open_edges)) {
        mote_sep_mesh_free(&w);
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", path);
    }
    if (solid && open_edges) { /* (a state file's wall, whose components are not known) */
        mote_sep_mesh_free(&w);
        return mote_fail(err, MOTE_EINVAL, "%s: solid=yes needs a closed mesh (every edge "
                         "shared by exactly two triangles); %zu of its edges are not", path,
                         open_edges);
    }
    w.solid = solid;
    w.omega = omega;
    for (int a = 0; a < 3; a++) {
        w.vel[a] = vel[a];
        w.axis[a] = kl > 0 ? k[a] / kl : 0;
        w.centre[a] = centre[a];
    }
    s->mesh[s->nmesh++] = w;
    return MOTE_OK;
}

void sep_mesh_frame_at(const mote_sep_mesh *w, double t, sep_mesh_frame *f)
{
    const double th = w->omega * t, c = cos(th), sn = sin(th), *k = w->axis;
    /* Rodrigues: R = c I + sn [k]x + (1 - c) k k^T */
    const double K[3][3] = {{0, -k[2], k[1]}, {k[2], 0, -k[0]}, {-k[1], k[0], 0}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            f->R[i][j] = (i == j ? c : 0) + sn * K[i][j] + (1 - c) * k[i] * k[j];
    for (int a = 0; a < 3; a++) {
        f->c0[a] = w->centre[a];
        f->C[a] = w->centre[a] + w->vel[a] * t;
        f->vel[a] = w->vel[a];
        f->w[a] = w->omega * k[a];
    }
    f->moving = w->omega != 0 || w->vel[0] != 0 || w->vel[1] != 0 || w->vel[2] != 0;
}

/* The point q of triangle (a, b, c) closest to p, and its feature: 0 the face, 1, 2, 3 the edges
 * ab, bc, ca, 4, 5, 6 the vertices a, b, c (from the signs of the dot products that bound each
 * feature's Voronoi region: Ericson, Real-Time Collision Detection, 2005, 5.1.5). */
static int closest_on_tri(const double p[3], const double a[3], const double b[3],
                          const double c[3], double q[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    for (int x = 0; x < 3; x++) {
        ab[x] = b[x] - a[x], ac[x] = c[x] - a[x];
        ap[x] = p[x] - a[x], bp[x] = p[x] - b[x], cp[x] = p[x] - c[x];
    }
    const double d1 = sep_dot3(ab, ap), d2 = sep_dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0) {
        memcpy(q, a, 3 * sizeof *q);
        return 4;
    }
    const double d3 = sep_dot3(ab, bp), d4 = sep_dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3) {
        memcpy(q, b, 3 * sizeof *q);
        return 5;
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        for (int x = 0; x < 3; x++)
            q[x] = a[x] + v * ab[x];
        return 1;
    }
    const double d5 = sep_dot3(ab, cp), d6 = sep_dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6) {
        memcpy(q, c, 3 * sizeof *q);
        return 6;
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double u = d2 / (d2 - d6);
        for (int x = 0; x < 3; x++)
            q[x] = a[x] + u * ac[x];
        return 3;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
        const double u = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int x = 0; x < 3; x++)
            q[x] = b[x] + u * (c[x] - b[x]);
        return 2;
    }
    const double den = 1 / (va + vb + vc), v = vb * den, u = vc * den;
    for (int x = 0; x < 3; x++)
        q[x] = a[x] + v * ab[x] + u * ac[x];
    return 0;
}

static double dist2_to_tri(const mote_sep_mesh *w, size_t k, const double p[3])
{
    double q[3];
    closest_on_tri(p, w->v[w->t[k][0]], w->v[w->t[k][1]], w->v[w->t[k][2]], q);
    const double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    return sep_dot3(d, d);
}

/* the most cells a wall's grid has */
#define MESH_CELLS_MAX (1u << 22)

int sep_mesh_grid(mote_sep_mesh *w, double rmax, mote_err *err)
{
    if (w->cstart && w->rmax == rmax)
        return MOTE_OK;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t v = 0; v < w->nv; v++)
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], w->v[v][a]);
            hi[a] = fmax(hi[a], w->v[v][a]);
        }
    double ext = 0;
    for (int a = 0; a < 3; a++)
        ext = fmax(ext, hi[a] - lo[a]);
    const double margin = rmax + 1e-9 * ext;
    double h = fmax(2 * rmax, ext / 1024);
    int nc[3];
    for (;;) {
        double cells = 1;
        for (int a = 0; a < 3; a++) {
            nc[a] = (int)ceil((hi[a] - lo[a] + 2 * margin) / h);
            nc[a] = nc[a] < 1 ? 1 : nc[a];
            cells *= nc[a];
        }
        if (cells <= MESH_CELLS_MAX)
            break;
        h *= 1.25;
    }
    for (int a = 0; a < 3; a++)
        lo[a] -= margin;
    const size_t ncell = (size_t)nc[0] * (size_t)nc[1] * (size_t)nc[2];
    uint32_t *start = calloc(ncell + 1, sizeof *start);
    if (!start)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory for its grid", w->name);
    const double half = 0.5 * h * sqrt(3.0), reach = rmax + half + 1e-9 * ext;
    uint32_t *list = NULL;
    size_t total = 0;
    /* two passes: count, then fill (each cell's triangles in increasing order) */
    for (int pass = 0; pass < 2; pass++) {
        for (size_t k = 0; k < w->nt; k++) {
            int c0[3], c1[3];
            for (int a = 0; a < 3; a++) {
                double tl = INFINITY, th = -INFINITY;
                for (int j = 0; j < 3; j++) {
                    tl = fmin(tl, w->v[w->t[k][j]][a]);
                    th = fmax(th, w->v[w->t[k][j]][a]);
                }
                c0[a] = (int)floor((tl - reach - lo[a]) / h);
                c1[a] = (int)floor((th + reach - lo[a]) / h);
                c0[a] = c0[a] < 0 ? 0 : c0[a];
                c1[a] = c1[a] >= nc[a] ? nc[a] - 1 : c1[a];
            }
            for (int z = c0[2]; z <= c1[2]; z++)
                for (int y = c0[1]; y <= c1[1]; y++)
                    for (int x = c0[0]; x <= c1[0]; x++) {
                        const double p[3] = {lo[0] + (x + 0.5) * h, lo[1] + (y + 0.5) * h,
                                             lo[2] + (z + 0.5) * h};
                        if (dist2_to_tri(w, k, p) > reach * reach)
                            continue;
                        const size_t cell = ((size_t)z * (size_t)nc[1] + (size_t)y) *
                                                (size_t)nc[0] + (size_t)x;
                        if (pass == 0)
                            start[cell + 1]++;
                        else
                            list[start[cell]++] = (uint32_t)k;
                    }
        }
        if (pass == 0) {
            for (size_t c = 0; c < ncell; c++)
                start[c + 1] += start[c];
            total = start[ncell];
            mote_err e2 = {0};
            if (mote_mem_check((double)total * sizeof *list, "a mesh wall's grid", &e2)) {
                free(start);
                return mote_fail(err, e2.code, "%s: %s", w->name, e2.msg);
            }
            list = malloc((total ? total : 1) * sizeof *list);
            if (!list) {
                free(start);
                return mote_fail(err, MOTE_ENOMEM, "%s: out of memory for its grid (%zu "
                                 "entries)", w->name, total);
            }
        }
    }
    /* (the fill moved each start to the next cell's: shift back) */
    for (size_t c = ncell; c > 0; c--)
        start[c] = start[c - 1];
    start[0] = 0;
    free(w->cstart);
    free(w->ctri);
    w->cstart = start;
    w->ctri = list;
    memcpy(w->lo, lo, sizeof lo);
    memcpy(w->nc, nc, sizeof nc);
    w->h = h;
    w->rmax = rmax;
    return MOTE_OK;
}

/* (a candidate contact: the triangle, its feature, the closest point and distance) */
typedef struct {
    uint32_t tri;
    int feat;
    double q[3], dist;
} cand;

/* whether triangle t has vertex v */
static inline int has_vertex(const uint32_t t[3], uint32_t v)
{
    return t[0] == v || t[1] == v || t[2] == v;
}

/* the most candidates kept per wall for one particle */
#define MESH_CANDS 32

int sep_mesh_contacts(const mote_sep_system *s, const sep_mesh_frame *fr, const double p[3],
                      double r, sep_mc *out)
{
    int n = 0;
    for (int k = 0; k < s->nmesh; k++) {
        const mote_sep_mesh *w = &s->mesh[k];
        const sep_mesh_frame *f = &fr[k];
        /* the centre in the wall's frame: c0 + R^T (p - C) */
        double pb[3];
        const double d[3] = {p[0] - f->C[0], p[1] - f->C[1], p[2] - f->C[2]};
        for (int a = 0; a < 3; a++)
            pb[a] = f->c0[a] + f->R[0][a] * d[0] + f->R[1][a] * d[1] + f->R[2][a] * d[2];
        int ci[3];
        for (int a = 0; a < 3; a++) {
            const double u = floor((pb[a] - w->lo[a]) / w->h);
            if (!(u >= 0 && u < w->nc[a]))
                break;
            ci[a] = (int)u;
            if (a == 2)
                goto found;
        }
        continue;
    found:;
        const size_t cell = ((size_t)ci[2] * (size_t)w->nc[1] + (size_t)ci[1]) * (size_t)w->nc[0] +
                            (size_t)ci[0];
        cand c[MESH_CANDS];
        int nc = 0;
        for (uint32_t e = w->cstart[cell]; e < w->cstart[cell + 1]; e++) {
            const uint32_t t = w->ctri[e];
            const double *pl = w->plane[t];
            if (!(fabs(sep_dot3(pl, pb) - pl[3]) < r))
                continue; /* (the plane is out of reach, so is the triangle) */
            /* (so is its bounding box: on a mesh finer than the contact most of a cell's
             * triangles are ruled out here, before the closest point; the box's distance is
             * at most the triangle's, and the margin keeps every triangle whose own distance
             * rounds below r) */
            const double *v0 = w->v[w->t[t][0]], *v1 = w->v[w->t[t][1]], *v2 = w->v[w->t[t][2]];
            double b2 = 0;
            for (int a = 0; a < 3; a++) {
                const double m01 = v0[a] < v1[a] ? v0[a] : v1[a];
                const double n01 = v0[a] < v1[a] ? v1[a] : v0[a];
                const double lo = m01 < v2[a] ? m01 : v2[a], hi = n01 > v2[a] ? n01 : v2[a];
                const double o = pb[a] < lo ? lo - pb[a] : pb[a] > hi ? pb[a] - hi : 0;
                b2 += o * o;
            }
            if (b2 > r * r * (1 + 1e-9))
                continue;
            cand x = {.tri = t};
            x.feat = closest_on_tri(pb, v0, v1, v2, x.q);
            const double dq[3] = {pb[0] - x.q[0], pb[1] - x.q[1], pb[2] - x.q[2]};
            const double d2 = sep_dot3(dq, dq);
            if (!(d2 < r * r) || !(d2 > 0))
                continue; /* (a centre on the surface has no direction) */
            x.dist = sqrt(d2);
            if (nc < MESH_CANDS) {
                c[nc++] = x;
                continue;
            }
            /* (more triangles within reach than room: the nearest are kept, so the contact's
             * own face is never lost on a mesh finer than the contact) */
            int far = 0;
            for (int j = 1; j < nc; j++)
                far = c[j].dist > c[far].dist ? j : far;
            if (x.dist < c[far].dist)
                c[far] = x;
        }
        for (int i = 1; i < nc; i++) /* (in the triangles' order, as listed) */
            for (int j = i; j > 0 && c[j - 1].tri > c[j].tri; j--) {
                const cand y = c[j];
                c[j] = c[j - 1];
                c[j - 1] = y;
            }
        /* each feature once: a contact goes when an earlier one is at the same point (to
         * rounding: an edge or vertex seen from each of its triangles, or a point on an edge
         * that both triangles call their face's); an edge's when a face beside it touches, or
         * a triangle with one of its ends comes nearer (the surface around the edge is nearer
         * than the edge: a sheet's edges near a face contact on the same plane); a vertex's when
         * a face or edge of a triangle around it touches */
        const double tol2 = 1e-18 * r * r;
        for (int i = 0; i < nc && n < SEP_MESH_MAXC; i++) {
            const uint32_t *ti = w->t[c[i].tri];
            int keep = 1;
            for (int j = 0; keep && j < i; j++) {
                const double dq[3] = {c[i].q[0] - c[j].q[0], c[i].q[1] - c[j].q[1],
                                      c[i].q[2] - c[j].q[2]};
                keep = sep_dot3(dq, dq) > tol2;
            }
            if (c[i].feat >= 1 && c[i].feat <= 3) {
                const uint32_t u = ti[c[i].feat - 1], v = ti[c[i].feat % 3];
                for (int j = 0; keep && j < nc; j++) {
                    const uint32_t *tj = w->t[c[j].tri];
                    const int hu = has_vertex(tj, u), hv = has_vertex(tj, v);
                    if (j == i || !(hu || hv))
                        continue;
                    keep = !(c[j].feat == 0 && hu && hv) && !(c[j].dist < c[i].dist - 1e-9 * r);
                }
            } else if (c[i].feat >= 4) {
                const uint32_t u = ti[c[i].feat - 4];
                for (int j = 0; keep && j < nc; j++) {
                    const uint32_t *tj = w->t[c[j].tri];
                    if (j != i && has_vertex(tj, u))
                        keep = !(c[j].feat <= 3) && !(c[j].dist < c[i].dist - 1e-9 * r);
                }
            }
            if (!keep)
                continue;
            sep_mc *o = &out[n++];
            double nb[3], qb[3];
            for (int a = 0; a < 3; a++) {
                nb[a] = (pb[a] - c[i].q[a]) / c[i].dist;
                qb[a] = c[i].q[a] - f->c0[a];
            }
            for (int a = 0; a < 3; a++)
                o->n[a] = f->R[a][0] * nb[0] + f->R[a][1] * nb[1] + f->R[a][2] * nb[2];
            o->delta = r - c[i].dist;
            if (f->moving) { /* the wall's velocity at the contact point q */
                double qw[3], wq[3];
                for (int a = 0; a < 3; a++)
                    qw[a] = f->R[a][0] * qb[0] + f->R[a][1] * qb[1] + f->R[a][2] * qb[2];
                wq[0] = f->w[1] * qw[2] - f->w[2] * qw[1];
                wq[1] = f->w[2] * qw[0] - f->w[0] * qw[2];
                wq[2] = f->w[0] * qw[1] - f->w[1] * qw[0];
                for (int a = 0; a < 3; a++)
                    o->vw[a] = f->vel[a] + wq[a];
            } else
                o->vw[0] = o->vw[1] = o->vw[2] = 0;
            memcpy(o->ww, f->w, sizeof o->ww);
            o->key = (double)(k + 1) * 4294967296.0 + (double)c[i].tri;
        }
    }
    return n;
}

/* The solid angle of triangle (a, b, c) seen from the origin (Van Oosterom and Strackee, IEEE
 * Trans. Biomed. Eng. 30 (1983) 125): signed, positive when the triangle winds anticlockwise
 * seen from there. */
static double solid_angle(const double a[3], const double b[3], const double c[3])
{
    const double la = sqrt(sep_dot3(a, a)), lb = sqrt(sep_dot3(b, b)), lc = sqrt(sep_dot3(c, c));
    const double bc[3] = {b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2],
                          b[0] * c[1] - b[1] * c[0]};
    const double num = sep_dot3(a, bc);
    const double den = la * lb * lc + sep_dot3(a, b) * lc + sep_dot3(a, c) * lb +
                       sep_dot3(b, c) * la;
    return 2 * atan2(num, den);
}

int sep_mesh_blocks(const mote_sep_system *s, double t, const double p[3], double r)
{
    for (int k = 0; k < s->nmesh; k++) {
        const mote_sep_mesh *w = &s->mesh[k];
        sep_mesh_frame f;
        sep_mesh_frame_at(w, t, &f);
        double pb[3];
        const double d[3] = {p[0] - f.C[0], p[1] - f.C[1], p[2] - f.C[2]};
        for (int a = 0; a < 3; a++)
            pb[a] = f.c0[a] + f.R[0][a] * d[0] + f.R[1][a] * d[1] + f.R[2][a] * d[2];
        /* touching: through the grid (outside it, nothing is near), else every triangle */
        const int grid = w->cstart && r <= w->rmax;
        size_t cell = 0;
        int in = grid;
        for (int a = 2; in && a >= 0; a--) {
            const double u = floor((pb[a] - w->lo[a]) / w->h);
            in = u >= 0 && u < w->nc[a];
            cell = in ? cell * (size_t)w->nc[a] + (size_t)u : 0;
        }
        for (uint32_t e = in ? w->cstart[cell] : 0; in && e < w->cstart[cell + 1]; e++)
            if (dist2_to_tri(w, w->ctri[e], pb) <= r * r)
                return k + 1;
        for (size_t q = 0; !grid && q < w->nt; q++)
            if (dist2_to_tri(w, q, pb) <= r * r)
                return k + 1;
        /* inside a solid one (outside its grid's box, which holds it, it is not) */
        if (!w->solid || (grid && !in))
            continue;
        double wind = 0;
        for (size_t q = 0; q < w->nt; q++) {
            double a[3][3];
            for (int j = 0; j < 3; j++)
                for (int x = 0; x < 3; x++)
                    a[j][x] = w->v[w->t[q][j]][x] - pb[x];
            wind += solid_angle(a[0], a[1], a[2]);
        }
        if (w->solid && fabs(wind) > 2 * SEP_PI) /* (the winding number, 0 or 1: above 1/2) */
            return k + 1;
    }
    return 0;
}
