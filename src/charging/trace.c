/* trace.c: rays against the spacecraft body (spec 5.5). Triangles are traced with Embree (its
 * robust, watertight mode: no ray slips through a shared edge of a closed mesh), which returns
 * the nearest intersection; the side comes from the sign of the direction against the geometric
 * normal Embree returns with the hit (the vertices' winding, as mote's own normals), so a hit
 * reads no table of mote's: on a mesh of 10^6 triangles that table costs a cache miss per hit.
 * The exact sphere is intersected analytically. A body proved convex is walked over its
 * triangles instead (convex.c), Embree answering only what the walk cannot decide. A body that
 * is not convex gets a tighter early exit than its bounding sphere: up to CH_BOXES axis-aligned
 * boxes that hold all its triangles, chosen to make their total surface area (the chance that
 * a random line meets them) small; a ray that meets none of them misses the body without a
 * call to Embree. */
#include "ch.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <stdlib.h>

enum { CH_BOXES = 8, BOX_BINS = 16 };

/* The boxes, coordinates first (a loop over the boxes vectorises) */
typedef struct {
    int n; /* 0: none (the exact sphere, a convex body) */
    double c[3][CH_BOXES], h[3][CH_BOXES]; /* centres and half extents */
    double wc[3], wh[3]; /* the box of them all, tried first */
    double far2;         /* rays starting farther than sqrt(far2) go to Embree directly */
} ch_boxes;

struct mote_ch_tracer {
    const mote_ch_body *body;
    RTCDevice dev;
    RTCScene scene;
    ch_convex *cv; /* the walk for a convex body (convex.c), or NULL */
    int walk;      /* 0: Embree alone (no walk, no boxes) */
    ch_boxes bx;
};

int ch_tracer_convex(const mote_ch_tracer *t) { return t->cv != NULL; }

int ch_tracer_boxes(const mote_ch_tracer *t, double lo[][3], double hi[][3])
{
    for (int i = 0; i < t->bx.n; i++)
        for (int a = 0; a < 3; a++) {
            lo[i][a] = t->bx.c[a][i] - t->bx.h[a][i];
            hi[i][a] = t->bx.c[a][i] + t->bx.h[a][i];
        }
    return t->bx.n;
}

static double box_area(const double lo[3], const double hi[3])
{
    const double x = hi[0] - lo[0], y = hi[1] - lo[1], z = hi[2] - lo[2];
    return 2 * (x * y + y * z + z * x);
}

static void box_grow(double lo[3], double hi[3], const double (*v)[3], int nv)
{
    for (int j = 0; j < nv; j++)
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], v[j][a]);
            hi[a] = fmax(hi[a], v[j][a]);
        }
}

/* One leaf of the boxes' build: triangles idx[s..e), their box, and its best cut in two (by
 * the triangles' centroids in BOX_BINS bins along an axis): the area it saves. */
typedef struct {
    uint32_t s, e;
    double lo[3], hi[3];
    int axis, bin; /* the triangles of bins < bin go left */
    double cmin, cscale, gain;
} box_leaf;

static int centroid_bin(const mote_ch_body *b, uint32_t i, const box_leaf *l)
{
    const double c = (b->v[i][0][l->axis] + b->v[i][1][l->axis] + b->v[i][2][l->axis]) / 3;
    const int k = (int)((c - l->cmin) * l->cscale);
    return k < 0 ? 0 : k >= BOX_BINS ? BOX_BINS - 1 : k;
}

static void leaf_plan(const mote_ch_body *b, const uint32_t *idx, box_leaf *l)
{
    l->gain = 0;
    l->bin = -1;
    const double whole = box_area(l->lo, l->hi);
    for (int a = 0; a < 3; a++) {
        double cmin = INFINITY, cmax = -INFINITY;
        for (uint32_t j = l->s; j < l->e; j++) {
            const uint32_t i = idx[j];
            const double c = (b->v[i][0][a] + b->v[i][1][a] + b->v[i][2][a]) / 3;
            cmin = fmin(cmin, c);
            cmax = fmax(cmax, c);
        }
        if (!(cmax > cmin))
            continue;
        box_leaf t = *l;
        t.axis = a;
        t.cmin = cmin;
        t.cscale = BOX_BINS / (cmax - cmin);
        double blo[BOX_BINS][3], bhi[BOX_BINS][3];
        uint32_t cnt[BOX_BINS] = {0};
        for (int k = 0; k < BOX_BINS; k++)
            for (int c = 0; c < 3; c++) {
                blo[k][c] = INFINITY;
                bhi[k][c] = -INFINITY;
            }
        for (uint32_t j = l->s; j < l->e; j++) {
            const int k = centroid_bin(b, idx[j], &t);
            cnt[k]++;
            box_grow(blo[k], bhi[k], (const double(*)[3])b->v[idx[j]], 3);
        }
        /* the areas of the boxes left of each cut, then right of it */
        double left[BOX_BINS], llo[3] = {INFINITY, INFINITY, INFINITY},
                               lhi[3] = {-INFINITY, -INFINITY, -INFINITY};
        uint32_t nl = 0;
        for (int k = 0; k < BOX_BINS; k++) {
            if (cnt[k]) {
                box_grow(llo, lhi, (const double(*)[3])blo[k], 1);
                box_grow(llo, lhi, (const double(*)[3])bhi[k], 1);
            }
            nl += cnt[k];
            left[k] = nl ? box_area(llo, lhi) : 0;
        }
        double rlo[3] = {INFINITY, INFINITY, INFINITY}, rhi[3] = {-INFINITY, -INFINITY, -INFINITY};
        uint32_t nr = 0;
        for (int k = BOX_BINS - 1; k >= 1; k--) {
            if (cnt[k]) {
                box_grow(rlo, rhi, (const double(*)[3])blo[k], 1);
                box_grow(rlo, rhi, (const double(*)[3])bhi[k], 1);
            }
            nr += cnt[k];
            if (!nr || nr == l->e - l->s)
                continue;
            const double g = whole - left[k - 1] - box_area(rlo, rhi);
            if (g > l->gain) {
                *l = t;
                l->bin = k;
                l->gain = g;
            }
        }
    }
}

/* The boxes of a body that is not convex: the greedy cut of the leaf that saves the most area,
 * until CH_BOXES leaves or no cut saves 1 % of the area left; each box then widened by 1e-6 of
 * the body's size (more than the single-precision rounding of Embree's rays that start within
 * 1e3 body sizes, which is all the box test is used for). */
static int boxes_build(const mote_ch_body *b, ch_boxes *bx)
{
    uint32_t *idx = malloc(sizeof *idx * b->ntri);
    if (!idx)
        return -1;
    box_leaf L[CH_BOXES];
    int n = 1;
    L[0].s = 0;
    L[0].e = b->ntri;
    for (int a = 0; a < 3; a++) {
        L[0].lo[a] = INFINITY;
        L[0].hi[a] = -INFINITY;
    }
    for (uint32_t i = 0; i < b->ntri; i++) {
        idx[i] = i;
        box_grow(L[0].lo, L[0].hi, (const double(*)[3])b->v[i], 3);
    }
    double size = 0;
    for (int a = 0; a < 3; a++)
        size = fmax(size, L[0].hi[a] - L[0].lo[a]);
    leaf_plan(b, idx, &L[0]);
    while (n < CH_BOXES) {
        double total = 0;
        int best = 0;
        for (int k = 0; k < n; k++) {
            total += box_area(L[k].lo, L[k].hi);
            if (L[k].gain > L[best].gain)
                best = k;
        }
        if (L[best].bin < 0 || L[best].gain < 0.01 * total)
            break;
        box_leaf *l = &L[best], r = *l;
        uint32_t m = l->s;
        for (uint32_t j = l->s; j < l->e; j++)
            if (centroid_bin(b, idx[j], l) < l->bin) {
                const uint32_t x = idx[m];
                idx[m++] = idx[j];
                idx[j] = x;
            }
        r.s = m;
        l->e = m;
        box_leaf *two[2] = {l, &r};
        for (int q = 0; q < 2; q++) {
            for (int a = 0; a < 3; a++) {
                two[q]->lo[a] = INFINITY;
                two[q]->hi[a] = -INFINITY;
            }
            for (uint32_t j = two[q]->s; j < two[q]->e; j++)
                box_grow(two[q]->lo, two[q]->hi, (const double(*)[3])b->v[idx[j]], 3);
            leaf_plan(b, idx, two[q]);
        }
        L[n++] = r;
    }
    free(idx);
    const double pad = 1e-6 * size + 1e-300;
    bx->n = n;
    for (int a = 0; a < 3; a++) {
        double lo = INFINITY, hi = -INFINITY;
        for (int k = 0; k < n; k++) {
            bx->c[a][k] = 0.5 * (L[k].lo[a] + L[k].hi[a]);
            bx->h[a][k] = 0.5 * (L[k].hi[a] - L[k].lo[a]) + pad;
            lo = fmin(lo, L[k].lo[a]);
            hi = fmax(hi, L[k].hi[a]);
        }
        bx->wc[a] = 0.5 * (lo + hi);
        bx->wh[a] = 0.5 * (hi - lo) + pad;
    }
    bx->far2 = (1e3 * size) * (1e3 * size);
    return 0;
}

/* Does the line through o along d surely miss every box? (1: it does, and so does any ray or
 * segment on it; 0: it may meet one, and Embree is asked.) A line misses a box when an axis
 * d x e_a (e_a the box's edges) separates them: |(d x w)_a| > the box's half extents projected
 * on it, w = o - the box's centre (no division, no special case for a zero component). The box
 * of them all first: most lines that miss the body miss it. */
static int line_misses(const double c[3], const double h[3], const double o[3], const double d[3],
                       const double ad[3])
{
    const double w0 = o[0] - c[0], w1 = o[1] - c[1], w2 = o[2] - c[2];
    const double x = d[1] * w2 - d[2] * w1, y = d[2] * w0 - d[0] * w2, z = d[0] * w1 - d[1] * w0;
    return (fabs(x) > h[1] * ad[2] + h[2] * ad[1]) | (fabs(y) > h[0] * ad[2] + h[2] * ad[0]) |
           (fabs(z) > h[0] * ad[1] + h[1] * ad[0]);
}

static int boxes_miss(const ch_boxes *bx, const double o[3], const double d[3])
{
    if (!bx->n)
        return 0;
    double r2 = 0;
    for (int a = 0; a < 3; a++)
        r2 += (o[a] - bx->wc[a]) * (o[a] - bx->wc[a]);
    if (!(r2 < bx->far2))
        return 0;
    const double ad[3] = {fabs(d[0]), fabs(d[1]), fabs(d[2])};
    if (line_misses(bx->wc, bx->wh, o, d, ad))
        return 1;
    int meet = 0;
    for (int k = 0; k < bx->n; k++) {
        const double w0 = o[0] - bx->c[0][k], w1 = o[1] - bx->c[1][k], w2 = o[2] - bx->c[2][k];
        const double x = d[1] * w2 - d[2] * w1, y = d[2] * w0 - d[0] * w2,
                     z = d[0] * w1 - d[1] * w0;
        meet |= (fabs(x) <= bx->h[1][k] * ad[2] + bx->h[2][k] * ad[1]) &
                (fabs(y) <= bx->h[0][k] * ad[2] + bx->h[2][k] * ad[0]) &
                (fabs(z) <= bx->h[0][k] * ad[1] + bx->h[1][k] * ad[0]);
    }
    return !meet;
}

void ch_tracer_walk(mote_ch_tracer *t, int on) { t->walk = on; }

void mote_ch_tracer_free(mote_ch_tracer *t)
{
    if (!t)
        return;
    ch_convex_free(t->cv);
    if (t->scene)
        rtcReleaseScene(t->scene);
    if (t->dev)
        rtcReleaseDevice(t->dev);
    free(t);
}

mote_ch_tracer *mote_ch_tracer_new(const mote_ch_body *b, mote_err *err)
{
    mote_ch_tracer *t = calloc(1, sizeof *t);
    if (!t) {
        mote_fail(err, MOTE_ENOMEM, "tracer: out of memory");
        return NULL;
    }
    t->body = b;
    if (b->sphere)
        return t;
    if (b->ntri == 0) {
        free(t);
        mote_fail(err, MOTE_EINVAL, "there is no body: add one with body (sphere, icosphere, ...)");
        return NULL;
    }
    /* one thread for the build: the tracer is shared read-only by mote's own threads */
    t->dev = rtcNewDevice("threads=1");
    if (!t->dev) {
        free(t);
        mote_fail(err, MOTE_EINVAL, "tracer: Embree could not start (error %d)",
                  (int)rtcGetDeviceError(NULL));
        return NULL;
    }
    t->scene = rtcNewScene(t->dev);
    rtcSetSceneFlags(t->scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(t->scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry g = rtcNewGeometry(t->dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                        3 * sizeof(float), 3 * (size_t)b->ntri);
    unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                           3 * sizeof(unsigned), b->ntri);
    if (!vb || !ib) {
        rtcReleaseGeometry(g);
        mote_ch_tracer_free(t);
        mote_fail(err, MOTE_ENOMEM, "tracer: out of memory for %u triangles", b->ntri);
        return NULL;
    }
    for (uint32_t i = 0; i < b->ntri; i++)
        for (int j = 0; j < 3; j++) {
            for (int k = 0; k < 3; k++)
                vb[9 * (size_t)i + 3 * j + k] = (float)b->v[i][j][k];
            ib[3 * (size_t)i + j] = 3 * i + (unsigned)j;
        }
    rtcCommitGeometry(g);
    rtcAttachGeometry(t->scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(t->scene);
    if (rtcGetDeviceError(t->dev) != RTC_ERROR_NONE) {
        mote_ch_tracer_free(t);
        mote_fail(err, MOTE_EINVAL, "tracer: Embree could not build the scene");
        return NULL;
    }
    t->cv = ch_convex_build(b, t->scene);
    if (!t->cv && boxes_build(b, &t->bx)) {
        mote_ch_tracer_free(t);
        mote_fail(err, MOTE_ENOMEM, "tracer: out of memory for %u triangles", b->ntri);
        return NULL;
    }
    t->walk = 1;
    return t;
}

/* Does the ray's start fit single precision with room (|x| <= 1e30 m)? */
static int ray_fits(const double o[3])
{
    return fabs(o[0]) <= 1e30 && fabs(o[1]) <= 1e30 && fabs(o[2]) <= 1e30;
}

/* The exact sphere: the smaller root s > tmin of |org + s dir - c|^2 = r^2 (dir a unit vector). */
static long trace_sphere(const mote_ch_body *b, const double o[3], const double d[3], double tmin,
                         int *side, double *s)
{
    double oc[3], bq = 0, cq = 0;
    for (int k = 0; k < 3; k++) {
        oc[k] = o[k] - b->sphere_c[k];
        bq += oc[k] * d[k];
        cq += oc[k] * oc[k];
    }
    cq -= b->sphere_r * b->sphere_r;
    const double disc = bq * bq - cq;
    if (disc < 0)
        return -1;
    const double sq = sqrt(disc);
    /* the nearer root computed without cancellation */
    const double q = bq > 0 ? -bq - sq : -bq + sq;
    double r1 = q, r2 = q != 0 ? cq / q : 0;
    if (r1 > r2) {
        double x = r1;
        r1 = r2;
        r2 = x;
    }
    const double hit = r1 > tmin ? r1 : r2 > tmin ? r2 : -1;
    if (hit < 0)
        return -1;
    *s = hit;
    *side = hit == r1 && cq > 0 ? 0 : 1; /* from outside: the front face */
    return 0;
}

long mote_ch_trace(const mote_ch_tracer *t, const double org[3], const double dir[3], double tmin,
                   int *side, double *s)
{
    return mote_ch_trace_seg(t, org, dir, tmin, INFINITY, side, s);
}

long mote_ch_trace_seg(const mote_ch_tracer *t, const double org[3], const double dir[3],
                       double tmin, double tmax, int *side, double *s)
{
    const mote_ch_body *b = t->body;
    /* a ray not finite meets nothing (Embree would stop the program on it), nor one whose
     * start overflows single precision (to Embree an infinite one; the body lies within
     * MOTE_CH_SIZE_MAX of the origin) */
    if (!isfinite(org[0] + org[1] + org[2] + dir[0] + dir[1] + dir[2]) || !ray_fits(org))
        return -1;
    if (b->sphere) {
        const long k = trace_sphere(b, org, dir, tmin, side, s);
        return k >= 0 && *s <= tmax ? k : -1;
    }
    if (t->cv && t->walk) {
        const long f = ch_convex_trace(t->cv, org, dir, tmin, tmax, side, s);
        if (f != -2)
            return f;
    }
    if (t->walk && boxes_miss(&t->bx, org, dir))
        return -1;
    return ch_embree_first(t->scene, org, dir, tmin, tmax, side, s);
}

long ch_embree_first(struct RTCSceneTy *scene, const double org[3], const double dir[3],
                     double tmin, double tmax, int *side, double *s)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRayHit rh;
    rh.ray.org_x = (float)org[0];
    rh.ray.org_y = (float)org[1];
    rh.ray.org_z = (float)org[2];
    rh.ray.dir_x = (float)dir[0];
    rh.ray.dir_y = (float)dir[1];
    rh.ray.dir_z = (float)dir[2];
    rh.ray.tnear = (float)tmin;
    rh.ray.tfar = (float)tmax;
    rh.ray.time = 0;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
        return -1;
    const long i = (long)rh.hit.primID;
    *side = dir[0] * rh.hit.Ng_x + dir[1] * rh.hit.Ng_y + dir[2] * rh.hit.Ng_z < 0 ? 0 : 1;
    *s = rh.ray.tfar;
    return i;
}

void ch_trace_many(const mote_ch_tracer *t, int n, const double (*o)[3], const double (*d)[3],
                   double tmin, long *tri, int *side, double *s)
{
    if (t->cv && t->walk)
        ch_convex_trace_many(t->cv, n, o, d, tmin, tri, side, s);
    else
        for (int j = 0; j < n; j++)
            tri[j] = -2;
    for (int j = 0; j < n; j++)
        if (tri[j] == -2)
            tri[j] = mote_ch_trace(t, o[j], d[j], tmin, &side[j], &s[j]);
}

int mote_ch_occluded(const mote_ch_tracer *t, const double org[3], const double dir[3],
                     double tmin, double tmax)
{
    const mote_ch_body *b = t->body;
    if (!isfinite(org[0] + org[1] + org[2] + dir[0] + dir[1] + dir[2]) || !ray_fits(org))
        return 0; /* as mote_ch_trace_seg: a ray not finite meets nothing */
    if (b->sphere) {
        int side;
        double s;
        return trace_sphere(b, org, dir, tmin, &side, &s) >= 0 && s < tmax;
    }
    if (t->walk && boxes_miss(&t->bx, org, dir))
        return 0;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRay ray;
    ray.org_x = (float)org[0];
    ray.org_y = (float)org[1];
    ray.org_z = (float)org[2];
    ray.dir_x = (float)dir[0];
    ray.dir_y = (float)dir[1];
    ray.dir_z = (float)dir[2];
    ray.tnear = (float)tmin;
    ray.tfar = (float)tmax;
    ray.time = 0;
    ray.mask = 0xFFFFFFFFu;
    ray.id = 0;
    ray.flags = 0;
    rtcOccluded1(t->scene, &ctx, &ray);
    return ray.tfar < 0; /* Embree marks an occluded ray with tfar = -inf */
}
