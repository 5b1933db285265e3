/* bench_charging.c: the charging model's tracing benchmarks (specs/spacecraft-charging.md 9):
 *
 *   b1 [N [T]]     straight-line histories against the UV sphere of 9 800 triangles (radius 1 m)
 *                  from an injection sphere of radius 3 m (hit fraction 1/9), one species,
 *                  N histories (default 1e7) on T threads (default 1): sampling, traversal and
 *                  tallying timed, the BVH build not
 *   b2near [N [T]] the same with R = 1.05 R_bound (deep traversals dominate)
 *   b2far [N [T]]  the same with R = 131.41 m (early misses dominate)
 *   mesh K [N [T]] the icosphere of level K (20 4^K triangles, K = 8: 1.3e6) from R = 3 m
 *   cubes [N [T]]  two cubes of 1 m, 0.5 m apart (a body that is not convex: Embree traces it,
 *                  not the walk of convex bodies) from R = 3 m
 *   craft FILE K [N [T]]  a spacecraft's mesh file (examples/data/spacecraft.obj: a bus and two
 *                  panels, 312 triangles; examples/data/spacecraft-full.obj: with yokes, a
 *                  boom and a dish, 556) with each triangle cut into 4 K times (K = 3: 2.0e4,
 *                  K = 5: 3.2e5 triangles of the first), from the default injection sphere,
 *                  R = 1.05 R_bound (not convex: Embree traces it behind the early-exit boxes)
 *   field FILE K [T]  the solved field (issue 55) of a mesh file refined K times as craft:
 *                  the boundary-element solve's time and matrix memory, the treecode's build
 *                  time and memory, and its evaluation time (theta 0.4) at 1e5 points on
 *                  spheres of 1.02 to 2 R_bound about the centre; T threads for the solve
 *   b3 [N [T]]     curved paths (spec 6.3, eta = 0.01): the B1 sphere at U = -10 kV in the
 *                  geo-worst-case plasma (four components, N histories each) from R = 3 m
 *
 * Built with MPI (make MPI=1), run under mpirun: the ranks share the histories (rank 0
 * prints; traces_per_s counts all ranks').
 *
 * One key=value line per run: traces_per_s (per second, all threads), per_thread, the hit
 * fraction, the build time, the peak memory and walk (1: the body was proved convex and its first
 * hits are found by walking over its triangles, src/charging/convex.c; 0: Embree). For the straight workloads also plain_per_thread
 * and mote_over_plain: the rate, on one thread, of a plain loop that a user of Embree would
 * write for the same histories (the same mesh in a scene of Embree's default settings, a
 * SplitMix64 stream, the same bounding-sphere early exit, one rtcIntersect1 per history and a
 * hit count), timed in the same process just before mote's run. Never a timed test; bench/README.md keeps the
 * figures. */
#include "mote/charging.h"
#include "../src/charging/ch.h" /* ch_tracer_convex */

#include <embree3/rtcore.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#ifdef MOTE_MPI
#include <mpi.h>
#endif
#include <string.h>
#include <time.h>

MOTE_PROGRAM_THREADS

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* SplitMix64 (Steele, Lea, Flood 2014): the plain loop's uniforms in [0, 1). */
static double plain_uniform(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

/* The plain loop's rate (histories per second, one thread) and hit fraction: n histories from
 * the sphere of radius R about the body's centre, the cosine law inwards; a direction whose
 * cos^2 is below 1 - (r_bound / R)^2 misses the bounding sphere and is not traced. */
static double plain_loop(const mote_ch_body *b, double R, double n, double *hit_fraction)
{
    mote_ch_geometry g;
    mote_ch_body_geometry(b, &g);
    RTCDevice dev = rtcNewDevice("threads=1");
    RTCScene scene = rtcNewScene(dev);
    RTCGeometry geo = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *vb = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                        3 * sizeof(float), 3 * (size_t)b->ntri);
    unsigned *ib = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                           3 * sizeof(unsigned), b->ntri);
    for (uint32_t i = 0; i < b->ntri; i++)
        for (int j = 0; j < 3; j++) {
            for (int k = 0; k < 3; k++)
                vb[9 * (size_t)i + 3 * j + k] = (float)b->v[i][j][k];
            ib[3 * (size_t)i + j] = 3 * i + (unsigned)j;
        }
    rtcCommitGeometry(geo);
    rtcAttachGeometry(scene, geo);
    rtcReleaseGeometry(geo);
    rtcCommitScene(scene);
    const double rb = g.r_bound / R, miss_below = rb < 1 ? 1 - rb * rb : 0;
    uint64_t st = 12345, hits = 0;
    const uint64_t N = (uint64_t)n;
    const double t0 = now();
    for (uint64_t h = 0; h < N; h++) {
        const double u0 = plain_uniform(&st), u1 = plain_uniform(&st), u2 = plain_uniform(&st),
                     u3 = plain_uniform(&st);
        if (u2 < miss_below)
            continue;
        const double z = 2 * u0 - 1, rho = sqrt(1 - z * z), ph = 2 * 3.14159265358979 * u1;
        const double nrm[3] = {rho * cos(ph), rho * sin(ph), z};
        /* a basis perpendicular to nrm */
        const double a[3] = {fabs(nrm[0]) < 0.9 ? 1 : 0, fabs(nrm[0]) < 0.9 ? 0 : 1, 0};
        double e1[3] = {a[1] * nrm[2] - a[2] * nrm[1], a[2] * nrm[0] - a[0] * nrm[2],
                        a[0] * nrm[1] - a[1] * nrm[0]};
        const double l = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
        for (int k = 0; k < 3; k++)
            e1[k] /= l;
        const double e2[3] = {nrm[1] * e1[2] - nrm[2] * e1[1], nrm[2] * e1[0] - nrm[0] * e1[2],
                              nrm[0] * e1[1] - nrm[1] * e1[0]};
        const double ct = sqrt(u2), sn = sqrt(1 - u2), ps = 2 * 3.14159265358979 * u3;
        struct RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        struct RTCRayHit rh;
        rh.ray.org_x = (float)(g.centre[0] + R * nrm[0]);
        rh.ray.org_y = (float)(g.centre[1] + R * nrm[1]);
        rh.ray.org_z = (float)(g.centre[2] + R * nrm[2]);
        rh.ray.dir_x = (float)(-ct * nrm[0] + sn * (cos(ps) * e1[0] + sin(ps) * e2[0]));
        rh.ray.dir_y = (float)(-ct * nrm[1] + sn * (cos(ps) * e1[1] + sin(ps) * e2[1]));
        rh.ray.dir_z = (float)(-ct * nrm[2] + sn * (cos(ps) * e1[2] + sin(ps) * e2[2]));
        rh.ray.tnear = 0;
        rh.ray.tfar = INFINITY;
        rh.ray.time = 0;
        rh.ray.mask = 0xFFFFFFFFu;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
    const double el = now() - t0;
    rtcReleaseScene(scene);
    rtcReleaseDevice(dev);
    *hit_fraction = (double)hits / n;
    return n / el;
}

static int bench(const char *name, mote_ch_body *b, double R, double n, int threads)
{
    mote_err err = {0};
    mote_ch_plasma p;
    const int curved = strcmp(name, "b3") == 0;
    if (curved) {
        mote_ch_plasma_preset(&p, "geo-worst-case", 0, 0, &err);
    } else {
        mote_ch_plasma_preset(&p, "single", 1e6, 1000, &err);
        p.nsp = 1; /* electrons only */
    }
    mote_ch_geometry g;
    mote_ch_body_geometry(b, &g);
    if (R <= 0)
        R = 1.05 * g.r_bound;
    double t0 = now();
    mote_ch_tracer *t = mote_ch_tracer_new(b, &err);
    double build = now() - t0;
    if (!t) {
        fprintf(stderr, "bench_charging: %s\n", err.msg);
        return 1;
    }
    /* the plain loop first (straight paths on a mesh), as many histories, one thread */
    double plain = 0, plain_hits = 0;
    if (!curved && !b->sphere)
        plain = plain_loop(b, R, n, &plain_hits);
    mote_ch_run_opts o = {.seed = 1, .particles = (uint64_t)n, .r_gen = R, .threads = threads,
                          .field = curved, .potential = curved ? -1e4 : 0, .eta = 0.01};
    mote_ch_result r;
    int rc = mote_ch_run(&p, b, t, &o, &r, &err);
    if (rc) {
        fprintf(stderr, "bench_charging: %s\n", err.msg);
        mote_ch_tracer_free(t);
        return 1;
    }
    uint64_t hits = 0;
    for (int s = 0; s < p.nsp; s++)
        for (int k = 0; k < p.sp[s].ncomp; k++)
            hits += r.hits[s][k];
    int rank = 0, ranks = 1;
#ifdef MOTE_MPI
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
#endif
    if (rank != 0) {
        mote_ch_result_free(&r);
        mote_ch_tracer_free(t);
        return 0;
    }
    printf("workload=%s triangles=%u R_gen=%g histories=%.0f threads=%d ranks=%d seconds=%.3f "
           "traces_per_s=%.4g per_thread=%.4g hit_fraction=%.5f build_seconds=%.3f "
           "peak_rss_mb=%.1f walk=%d",
           name, b->ntri, R, n * r.ncomp, threads, ranks, r.seconds, r.traces_per_s,
           r.traces_per_s / threads, (double)hits / (n * r.ncomp), build,
           (double)mote_peak_rss_bytes() / 1048576.0, b->sphere ? 0 : ch_tracer_convex(t));
    if (plain > 0)
        printf(" plain_per_thread=%.4g plain_hit_fraction=%.5f mote_over_plain=%.3f", plain,
               plain_hits, r.traces_per_s / threads / plain);
    if (curved)
        printf(" steps_per_history=%.2f lost=%llu max_energy_err=%.3g",
               (double)r.steps / (n * r.ncomp), (unsigned long long)r.lost, r.max_energy_err);
    putchar('\n');
    mote_ch_result_free(&r);
    mote_ch_tracer_free(t);
    return 0;
}

static int run_main(int argc, char **argv);

int main(int argc, char **argv)
{
#ifdef MOTE_MPI
    MPI_Init(&argc, &argv);
    const int rc = run_main(argc, argv);
    MPI_Finalize();
    return rc;
#else
    return run_main(argc, argv);
#endif
}

/* Each triangle of b cut into 4 at its edges' midpoints (the same surface, 4 times the
 * triangles). */
static int refine(mote_ch_body *b, mote_err *err)
{
    mote_ch_body r = {0};
    for (uint32_t i = 0; i < b->ntri; i++) {
        double m[3][3];
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++)
                m[j][k] = 0.5 * (b->v[i][j][k] + b->v[i][(j + 1) % 3][k]);
        const double *t[4][3] = {{b->v[i][0], m[0], m[2]},
                                 {m[0], b->v[i][1], m[1]},
                                 {m[2], m[1], b->v[i][2]},
                                 {m[0], m[1], m[2]}};
        for (int q = 0; q < 4; q++)
            if (ch_add_tri(&r, t[q][0], t[q][1], t[q][2], NULL, b->closed[i], 0, err)) {
                mote_ch_body_free(&r);
                return err->code;
            }
    }
    mote_ch_body_free(b);
    *b = r;
    return MOTE_OK;
}

/* `field FILE K [T]`: the solved field's set-up and evaluation costs (one line). */
static int bench_field(mote_ch_body *b, int threads)
{
    mote_err err = {0};
    mote_ch_geometry g;
    mote_ch_body_geometry(b, &g);
    mote_ch_bem f;
    double t0 = mote_wall_seconds();
    if (mote_ch_bem_solve(b, threads, NULL, NULL, &f, &err)) {
        fprintf(stderr, "bench_charging: %s\n", err.msg);
        return 1;
    }
    const double t1 = mote_wall_seconds();
    mote_ch_ftree *T = mote_ch_ftree_build(b, f.sigma, 0.4, &err);
    const double t2 = mote_wall_seconds();
    if (!T) {
        fprintf(stderr, "bench_charging: %s\n", err.msg);
        mote_ch_bem_free(&f);
        return 1;
    }
    const int N = 100000;
    double acc = 0;
    uint64_t s = 1;
    const double t3 = mote_wall_seconds();
    for (int i = 0; i < N; i++) {
        double u[3];
        for (int k = 0; k < 3; k++) {
            s = s * 6364136223846793005ull + 1442695040888963407ull;
            u[k] = (double)(s >> 11) / 9007199254740992.0;
        }
        const double z = 2 * u[0] - 1, ph = 2 * MOTE_CH_PI * u[1];
        const double r = g.r_bound * (1.02 + 0.98 * u[2]);
        const double x[3] = {g.centre[0] + r * sqrt(1 - z * z) * cos(ph),
                             g.centre[1] + r * sqrt(1 - z * z) * sin(ph), g.centre[2] + r * z};
        double phi, E[3];
        mote_ch_ftree_eval(T, x, &phi, E);
        acc += phi;
    }
    const double t4 = mote_wall_seconds();
    printf("bench=field panels=%u threads=%d solve_s=%.4g matrix_bytes=%zu tree_s=%.4g "
           "tree_bytes=%zu eval_us=%.4g capacitance_F=%.10g mean_phi=%.6g peak_rss_bytes=%zu\n",
           b->ntri, threads, t1 - t0, mote_ch_bem_bytes(b->ntri), t2 - t1,
           mote_ch_ftree_bytes(T), (t4 - t3) / N * 1e6, f.capacitance, acc / N,
           mote_peak_rss_bytes());
    mote_ch_ftree_free(T);
    mote_ch_bem_free(&f);
    return 0;
}

static int run_main(int argc, char **argv)
{
    const char *w = argc > 1 ? argv[1] : "b1";
    int mesh = strcmp(w, "mesh") == 0, field = strcmp(w, "field") == 0;
    int craft = field || strcmp(w, "craft") == 0;
    int a = craft ? 4 : mesh ? 3 : 2;
    double n = argc > a ? atof(argv[a]) : 1e7;
    int threads = argc > a + 1 ? atoi(argv[a + 1]) : 1;
    mote_err err = {0};
    mote_ch_body b = {0};
    double R;
    if (craft) {
        mote_ch_load_opts lo = {.format = "auto", .scale = 1, .rot_axis = -1};
        mote_ch_load_report rep;
        int rc = argc > 3 ? mote_ch_body_load(&b, argv[2], &lo, &rep, &err) : -1;
        for (int k = 0; !rc && k < atoi(argv[3]); k++)
            rc = refine(&b, &err);
        if (rc) {
            fprintf(stderr, "bench_charging: %s\n", argc > 3 ? err.msg : "craft FILE K");
            return 1;
        }
        R = 0; /* 1.05 R_bound */
        if (field) {
            const int rc2 = bench_field(&b, argc > 4 ? atoi(argv[4]) : 1);
            mote_ch_body_free(&b);
            return rc2;
        }
    } else if (mesh) {
        int level = argc > 2 ? atoi(argv[2]) : 8;
        if (mote_ch_body_icosphere(&b, 1, level, &err)) {
            fprintf(stderr, "bench_charging: %s\n", err.msg);
            return 1;
        }
        R = 3;
    } else if (strcmp(w, "cubes") == 0) {
        if (mote_ch_body_twocubes(&b, 1, 0.5, &err)) {
            fprintf(stderr, "bench_charging: %s\n", err.msg);
            return 1;
        }
        R = 3;
    } else {
        mote_ch_body_uvsphere(&b, 1, 100, 50, 0, &err);
        if (strcmp(w, "b1") == 0 || strcmp(w, "b3") == 0)
            R = 3;
        else if (strcmp(w, "b2near") == 0)
            R = 0; /* 1.05 R_bound */
        else if (strcmp(w, "b2far") == 0)
            R = 131.41;
        else {
            fprintf(stderr, "usage: bench_charging [b1|b2near|b2far|b3|cubes [N [THREADS]] | mesh K [N "
                            "[THREADS]] | craft FILE K [N [THREADS]] | field FILE K [THREADS]]\n");
            return 2;
        }
    }
    int rc = bench(w, &b, R, n, threads);
    mote_ch_body_free(&b);
    return rc;
}
