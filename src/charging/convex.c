/* convex.c: first hits on a convex body by walking over its triangles (spec 5.5).
 *
 * When every triangle of the body belongs to one closed surface that bounds a convex solid, a
 * line from outside meets the surface first on the one front-facing triangle it passes through,
 * and a ray's first hit needs no search of a hierarchy: seen along the ray, the front-facing
 * triangles tile the body's outline, and a walk from a triangle near the ray to its neighbours
 * finds the one that holds it. Each step asks, for each edge, on which side of it the ray passes
 * (the permuted inner product of the ray's and the edge's Pluecker coordinates, as
 * d . ((p - o) x (q - o)): the two triangles sharing the edge compute it from the same two
 * vertices in opposite order, exact negatives, so no ray slips between them), and crosses an
 * edge the ray passes outside of.
 * Crossing onto a back-facing triangle means the ray passes outside the outline: a miss. The walk
 * starts at the triangle a map of directions (a cube map about a centre inside the body) gives
 * for the point where the ray enters the body's bounding sphere.
 *
 * The body is taken as convex only when it is proved so at build time: a closed surface (every
 * edge shared by exactly two triangles, wound oppositely), every triangle facing away from the
 * centre, the solid angles of the triangles seen from the centre summing to 4 pi (the surface
 * goes round the centre once), and every edge convex (the far vertex of each neighbour on or
 * behind the triangle's plane, to 1e-10 of the body's size). A surface that goes round an inner
 * point once and is locally convex everywhere bounds a convex solid.
 *
 * Whatever the walk cannot decide (a ray starting inside the body or on it, more than
 * MAX_STEPS steps, a start on a back-facing triangle) it hands back to Embree. */
#include "ch.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* the walk's most steps (in a trace; in the cube map's fill, where a cell's walk starts from
 * the last cell's triangle); the cube map's cells per triangle (a start one step from the
 * answer or less for most rays) and its most cells (32 MB) */
enum { MAX_STEPS = 256, FILL_STEPS = 4096, CELLS_PER_TRI = 16, MAX_CELLS = 8000000 };

struct ch_convex {
    const double (*v)[3][3]; /* the body's triangles */
    uint32_t (*nb)[3];       /* across edge k: 4 * neighbour + its edge index */
    double c[3], r2;    /* a centre inside, the squared radius of a sphere about it holding all */
    int m;              /* the cube map's side */
    uint32_t *cube;     /* 6 m^2 cells: a triangle in the cell's direction from c */
};

void ch_convex_free(ch_convex *cv)
{
    if (!cv)
        return;
    free(cv->nb);
    free(cv->cube);
    free(cv);
}

static uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return z ^ (z >> 31);
}

static uint64_t bits_of(double x)
{
    x = x == 0 ? 0 : x; /* -0 and 0 are the same point */
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

/* The cube map's cell of the direction u (not necessarily a unit vector; not zero). */
static inline uint32_t cube_cell(int m, const double u[3])
{
    const double ax = fabs(u[0]), ay = fabs(u[1]), az = fabs(u[2]);
    const int a = ax >= ay && ax >= az ? 0 : ay >= az ? 1 : 2; /* the largest component */
    const int a1 = a == 2 ? 0 : a + 1, a2 = a == 0 ? 2 : a - 1;
    const double h = 0.5 * m / (a == 0 ? ax : a == 1 ? ay : az);
    int i = (int)((u[a1] * h) + 0.5 * m), j = (int)((u[a2] * h) + 0.5 * m);
    i = i < 0 ? 0 : i >= m ? m - 1 : i;
    j = j < 0 ? 0 : j >= m ? m - 1 : j;
    return (uint32_t)(((2 * a + (u[a] < 0)) * m + i) * m + j);
}

/* Number the distinct vertices (equal coordinates, bit for bit: the body's vertices are welded)
 * into vid; the number of them, or 0 when out of memory. */
static uint32_t number_vertices(const mote_ch_body *b, uint32_t (*vid)[3], double (**pos)[3])
{
    const size_t n = 3 * (size_t)b->ntri;
    size_t cap = 16;
    while (cap < 2 * n)
        cap *= 2;
    uint32_t *tab = malloc(cap * sizeof *tab);
    double(*p)[3] = malloc(n * sizeof *p);
    if (!tab || !p) {
        free(tab);
        free(p);
        return 0;
    }
    memset(tab, 0xff, cap * sizeof *tab);
    uint32_t nv = 0;
    for (uint32_t f = 0; f < b->ntri; f++)
        for (int k = 0; k < 3; k++) {
            const double *x = b->v[f][k];
            const uint64_t h = mix64(bits_of(x[0]) ^ mix64(bits_of(x[1]) ^ mix64(bits_of(x[2]))));
            size_t q = h & (cap - 1);
            while (tab[q] != UINT32_MAX &&
                   !(p[tab[q]][0] == x[0] && p[tab[q]][1] == x[1] && p[tab[q]][2] == x[2]))
                q = (q + 1) & (cap - 1);
            if (tab[q] == UINT32_MAX) {
                tab[q] = nv;
                memcpy(p[nv], x, sizeof p[0]);
                nv++;
            }
            vid[f][k] = tab[q];
        }
    free(tab);
    *pos = p;
    return nv;
}

/* Each directed edge's twin (the same edge, the other way, in the neighbour): 0, or 1 when the
 * surface is not closed and two-sided (an edge without a twin, or one met twice the same way). */
static int link_edges(uint32_t ntri, uint32_t (*vid)[3], uint32_t (*nb)[3])
{
    const size_t n = 3 * (size_t)ntri;
    size_t cap = 16;
    while (cap < 2 * n)
        cap *= 2;
    uint64_t *key = malloc(cap * sizeof *key);
    uint32_t *val = malloc(cap * sizeof *val);
    int bad = !key || !val;
    if (!bad)
        memset(key, 0xff, cap * sizeof *key);
    /* every directed edge once */
    for (uint32_t f = 0; f < ntri && !bad; f++)
        for (int k = 0; k < 3 && !bad; k++) {
            const uint64_t e = (uint64_t)vid[f][k] << 32 | vid[f][(k + 1) % 3];
            size_t q = mix64(e) & (cap - 1);
            while (key[q] != UINT64_MAX && key[q] != e)
                q = (q + 1) & (cap - 1);
            if (key[q] == e || vid[f][k] == vid[f][(k + 1) % 3])
                bad = 1;
            key[q] = e;
            val[q] = 4 * f + (uint32_t)k;
        }
    for (uint32_t f = 0; f < ntri && !bad; f++)
        for (int k = 0; k < 3 && !bad; k++) {
            const uint64_t e = (uint64_t)vid[f][(k + 1) % 3] << 32 | vid[f][k];
            size_t q = mix64(e) & (cap - 1);
            while (key[q] != UINT64_MAX && key[q] != e)
                q = (q + 1) & (cap - 1);
            if (key[q] != e)
                bad = 1;
            else
                nb[f][k] = val[q];
        }
    free(key);
    free(val);
    return bad;
}

static void sub3(const double a[3], const double b[3], double r[3])
{
    for (int k = 0; k < 3; k++)
        r[k] = a[k] - b[k];
}

static void cross3(const double a[3], const double b[3], double r[3])
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Is the closed surface convex about the centre c (the tests of the file's head)? */
static int proved_convex(const mote_ch_body *b, uint32_t (*nb)[3], const double c[3],
                         double size)
{
    double omega = 0; /* the solid angles, summed */
    for (uint32_t f = 0; f < b->ntri; f++) {
        double a[3], p[3], q[3], n[3];
        sub3(b->v[f][0], c, a);
        sub3(b->v[f][1], c, p);
        sub3(b->v[f][2], c, q);
        double e1[3], e2[3];
        sub3(b->v[f][1], b->v[f][0], e1);
        sub3(b->v[f][2], b->v[f][0], e2);
        cross3(e1, e2, n);
        const double nl = sqrt(dot3(n, n));
        if (!(dot3(n, a) > 1e-9 * size * nl))
            return 0; /* faces the centre, or passes through it */
        /* the solid angle (Van Oosterom and Strackee, IEEE Trans. Biomed. Eng. 30, 125, 1983) */
        double pq[3];
        cross3(p, q, pq);
        const double la = sqrt(dot3(a, a)), lp = sqrt(dot3(p, p)), lq = sqrt(dot3(q, q));
        omega += 2 * atan2(dot3(a, pq),
                           la * lp * lq + dot3(a, p) * lq + dot3(a, q) * lp + dot3(p, q) * la);
        for (int k = 0; k < 3; k++) {
            const uint32_t g = nb[f][k] / 4, kg = nb[f][k] % 4;
            /* the neighbour's vertex off the shared edge: the one after its edge's end */
            const double *w = b->v[g][(kg + 2) % 3];
            double wa[3];
            sub3(w, b->v[f][0], wa);
            if (dot3(wa, n) > 1e-10 * size * nl)
                return 0;
        }
    }
    return fabs(omega - 4 * MOTE_CH_PI) < 1e-6;
}

/* The three edges' sides of the line o + s d for the triangle f: sd[k] = d . ((p - o) x (q - o))
 * for edge k from p to q, > 0 when the line passes outside that edge of a front-facing
 * triangle; the neighbour across the edge computes q x p where f computes p x q, the exact
 * negative, so that every line is inside exactly one of two triangles sharing an edge or on
 * the edge (0 for both). sd[3] = their sum, d . N for the triangle's normal N = (B - A) x (C - A)
 * (< 0: it faces the line's origin), and sd[4] = N . (A - o), the determinant of the vertices
 * seen from o: the line meets the triangle's plane at s = sd[4] / sd[3]. */
static inline void sides(const double (*w)[3], const double o[3], const double d[3], double sd[5])
{
    double a[3][3], x[3][3];
    for (int k = 0; k < 3; k++)
        sub3(w[k], o, a[k]);
    for (int k = 0; k < 3; k++) {
        cross3(a[k], a[k == 2 ? 0 : k + 1], x[k]);
        sd[k] = dot3(d, x[k]);
    }
    sd[3] = sd[0] + sd[1] + sd[2];
    sd[4] = dot3(a[0], x[1]);
}

/* The edge to leave a triangle by, from the edges the line passes outside of (bit k: edge k)
 * and the edge the walk came in by (3: none): the first after the way in. */
static const signed char leave[4][8] = {
    {-1, -1, 1, 1, 2, 2, 1, 1},  /* came by edge 0: edges 1, 2 in turn */
    {-1, 0, -1, 0, 2, 2, 2, 2},  /* by 1: 2, 0 */
    {-1, 0, 1, 0, -1, 0, 1, 0},  /* by 2: 0, 1 */
    {-1, 0, 1, 0, 2, 0, 1, 0}}; /* the start: 0, 1, 2 */

/* Walk from the front-facing triangle *f (sd its sides) to the one the line o + s d passes
 * through: 1 (in *f), 0 when the line passes outside the body, -1 after max_steps. */
static inline int walk(const ch_convex *cv, const double o[3], const double d[3], uint32_t *f,
                       double sd[5], int max_steps)
{
    int came = 3;
    uint32_t g = *f;
    for (int step = 0; step < max_steps; step++) {
        const int mask = (sd[0] > 0) | (sd[1] > 0) << 1 | (sd[2] > 0) << 2;
        const int out = leave[came][mask];
        if (out < 0) {
            *f = g;
            return 1;
        }
        const uint32_t nb = cv->nb[g][out];
        g = nb / 4;
        came = (int)(nb % 4);
        sides(cv->v[g], o, d, sd);
        if (!(sd[3] < 0))
            return 0; /* across the outline */
    }
    return -1;
}

ch_convex *ch_convex_build(const mote_ch_body *b, struct RTCSceneTy *scene)
{
    if (b->sphere || b->ntri < 4 || b->ntri > (UINT32_MAX - 3) / 4)
        return NULL;
    for (uint32_t f = 0; f < b->ntri; f++)
        if (!b->closed[f])
            return NULL;
    ch_convex *cv = calloc(1, sizeof *cv);
    double(*pos)[3] = NULL;
    uint32_t(*vid)[3] = malloc(b->ntri * sizeof *vid), (*nb)[3] = malloc(b->ntri * sizeof *nb);
    if (!cv || !vid || !nb)
        goto no;
    uint32_t nv = number_vertices(b, vid, &pos);
    if (nv == 0 || link_edges(b->ntri, vid, nb))
        goto no;
    /* the centre: the vertices' mean; the radius about it */
    for (uint32_t i = 0; i < nv; i++)
        for (int k = 0; k < 3; k++)
            cv->c[k] += pos[i][k] / nv;
    for (uint32_t i = 0; i < nv; i++) {
        double r[3];
        sub3(pos[i], cv->c, r);
        cv->r2 = fmax(cv->r2, dot3(r, r));
    }
    free(pos);
    pos = NULL;
    cv->r2 *= 1 + 1e-9;
    if (!(cv->r2 > 0) || !proved_convex(b, nb, cv->c, sqrt(cv->r2)))
        goto no;
    cv->v = (const double(*)[3][3])b->v;
    cv->nb = nb;
    free(vid);
    vid = NULL;
    nb = NULL;
    /* the cube map, each cell filled by a walk from the last cell's triangle along the line
     * from outside through c (Embree's ray from c where that fails) */
    const double cells = fmin(CELLS_PER_TRI * (double)b->ntri, MAX_CELLS);
    cv->m = (int)ceil(sqrt(cells / 6));
    cv->m = cv->m < 2 ? 2 : cv->m;
    const size_t ncell = 6 * (size_t)cv->m * (size_t)cv->m;
    cv->cube = malloc(ncell * sizeof *cv->cube);
    if (!cv->cube)
        goto no;
    const double far = 2 * sqrt(cv->r2);
    uint32_t last = 0;
    for (size_t q = 0; q < ncell; q++) {
        const size_t m2 = (size_t)cv->m * (size_t)cv->m;
        const int a = (int)(q / m2) / 2, neg = (int)(q / m2) % 2;
        const int i = (int)(q / cv->m % cv->m), j = (int)(q % cv->m);
        double u[3], o[3], d[3];
        u[a] = neg ? -1 : 1;
        u[(a + 1) % 3] = (i + 0.5) / cv->m * 2 - 1;
        u[(a + 2) % 3] = (j + 0.5) / cv->m * 2 - 1;
        const double ul = sqrt(dot3(u, u));
        for (int k = 0; k < 3; k++) {
            d[k] = -u[k] / ul;
            o[k] = cv->c[k] - far * d[k];
        }
        uint32_t f = last;
        double sd[5];
        sides(cv->v[f], o, d, sd);
        if (!(sd[3] < 0) ||
            walk(cv, o, d, &f, sd, FILL_STEPS) != 1) {
            /* Embree's ray from c: from inside a closed surface it always meets it (any
             * triangle would do to start a walk) */
            int side;
            double s;
            const long e = ch_embree_first(scene, cv->c, u, 0, INFINITY, &side, &s);
            f = e >= 0 ? (uint32_t)e : 0;
        }
        cv->cube[q] = last = f;
    }
    return cv;
no:
    free(pos);
    free(vid);
    free(nb);
    ch_convex_free(cv);
    return NULL;
}

/* The walk's start for the line o + s d: 1 with the cube map's cell in *cell, or a result
 * already known (-1: no hit in tmin < s <= tmax; -2: a direction of zero or not finite, for
 * Embree). */
static inline long start_cell(const ch_convex *cv, const double o[3], const double d[3],
                              double tmin, double tmax, uint32_t *cell)
{
    double oc[3];
    sub3(o, cv->c, oc);
    const double dd = dot3(d, d), idd = 1 / dd, tc = -dot3(oc, d) * idd;
    double p[3];
    for (int k = 0; k < 3; k++)
        p[k] = oc[k] + tc * d[k];
    const double p2 = dot3(p, p);
    if (!(p2 < cv->r2)) /* the line passes the sphere holding the body; NaN: Embree decides */
        return p2 >= cv->r2 ? -1 : -2;
    const double half = sqrt((cv->r2 - p2) * idd);
    if (tc + half <= tmin || tc - half > tmax)
        return -1; /* the segment ends before that sphere or starts after it */
    double q[3];
    for (int k = 0; k < 3; k++)
        q[k] = p[k] - half * d[k]; /* where the line enters the sphere, from c */
    *cell = cube_cell(cv->m, q);
    return 1;
}

/* From the start cell to the result: the triangle, -1 (no hit), -2 (Embree decides). */
static inline long finish(const ch_convex *cv, const double o[3], const double d[3], double tmin,
                          double tmax, uint32_t f, int *side, double *s)
{
    double sd[5];
    sides(cv->v[f], o, d, sd);
    if (!(sd[3] < 0)) {
        const double nd[3] = {-d[0], -d[1], -d[2]};
        f = cv->cube[cube_cell(cv->m, nd)];
        sides(cv->v[f], o, d, sd);
        if (!(sd[3] < 0))
            return -2;
    }
    const int r = walk(cv, o, d, &f, sd, MAX_STEPS);
    if (r <= 0)
        return r == 0 ? -1 : -2;
    const double ts = sd[4] / sd[3];
    if (!(ts > tmin))
        return -2; /* starts inside or on the body: Embree decides */
    if (ts > tmax)
        return -1;
    *side = 0;
    *s = ts;
    return (long)f;
}

long ch_convex_trace(const ch_convex *cv, const double o[3], const double d[3], double tmin,
                     double tmax, int *side, double *s)
{
    uint32_t cell;
    const long r = start_cell(cv, o, d, tmin, tmax, &cell);
    return r < 0 ? r : finish(cv, o, d, tmin, tmax, cv->cube[cell], side, s);
}

void ch_convex_trace_many(const ch_convex *cv, int n, const double (*o)[3], const double (*d)[3],
                          double tmin, long *tri, int *side, double *s)
{
    uint32_t cell[CH_TRACE_MANY];
    for (int j = 0; j < n; j++) { /* the starts, side by side: their divisions overlap */
        tri[j] = start_cell(cv, o[j], d[j], tmin, INFINITY, &cell[j]);
        if (tri[j] > 0)
            __builtin_prefetch(&cv->cube[cell[j]]);
    }
    /* then their start triangles, fetched side by side (on a large mesh each is a cache miss) */
    uint32_t f[CH_TRACE_MANY];
    for (int j = 0; j < n; j++)
        if (tri[j] > 0) {
            f[j] = cv->cube[cell[j]];
            __builtin_prefetch(cv->v[f[j]]);
            __builtin_prefetch((const char *)cv->v[f[j]] + 64);
            __builtin_prefetch(cv->nb[f[j]]);
        }
    for (int j = 0; j < n; j++)
        if (tri[j] > 0)
            tri[j] = finish(cv, o[j], d[j], tmin, INFINITY, f[j], &side[j], &s[j]);
}
