/* trace.c: rays against the spacecraft body (spec 5.5). Triangles are traced with Embree (its
 * robust, watertight mode: no ray slips through a shared edge of a closed mesh), which returns
 * the nearest intersection; the side comes from the sign of the direction against the geometric
 * normal Embree returns with the hit (the vertices' winding, as mote's own normals), so a hit
 * reads no table of mote's: on a mesh of 10^6 triangles that table costs a cache miss per hit.
 * The exact sphere is intersected analytically. A body proved convex is walked over its
 * triangles instead (convex.c), Embree answering only what the walk cannot decide. */
#include "ch.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <stdlib.h>

struct mote_ch_tracer {
    const mote_ch_body *body;
    RTCDevice dev;
    RTCScene scene;
    ch_convex *cv; /* the walk for a convex body (convex.c), or NULL */
    int walk;      /* 0: Embree alone */
};

int ch_tracer_convex(const mote_ch_tracer *t) { return t->cv != NULL; }

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
