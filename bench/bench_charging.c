/* bench_charging.c: the charging model's tracing benchmarks (specs/spacecraft-charging.md 9):
 *
 *   b1 [N [T]]     straight-line histories against the UV sphere of 9 800 triangles (radius 1 m)
 *                  from an injection sphere of radius 3 m (hit fraction 1/9), one species,
 *                  N histories (default 1e7) on T threads (default 1): sampling, traversal and
 *                  tallying timed, the BVH build not
 *   b2near [N [T]] the same with R = 1.05 R_bound (deep traversals dominate)
 *   b2far [N [T]]  the same with R = 131.41 m (early misses dominate)
 *   mesh K [N [T]] the icosphere of level K (20 4^K triangles, K = 8: 1.3e6) from R = 3 m
 *   b3 [N [T]]     curved paths (spec 6.3, eta = 0.01): the B1 sphere at U = -10 kV in the
 *                  geo-worst-case plasma (four components, N histories each) from R = 3 m
 *
 * Built with MPI (make MPI=1), run under mpirun: the ranks share the histories (rank 0
 * prints; traces_per_s counts all ranks').
 *
 * One key=value line per run: traces_per_s (per second, all threads), per_thread, the hit
 * fraction, the build time and the peak memory. Never a timed test; bench/README.md keeps the
 * figures. */
#include "mote/charging.h"

#include <stdio.h>
#include <stdlib.h>
#ifdef MOTE_MPI
#include <mpi.h>
#endif
#include <string.h>
#include <time.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
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
           "peak_rss_mb=%.1f",
           name, b->ntri, R, n * r.ncomp, threads, ranks, r.seconds, r.traces_per_s,
           r.traces_per_s / threads, (double)hits / (n * r.ncomp), build,
           (double)mote_peak_rss_bytes() / 1048576.0);
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

static int run_main(int argc, char **argv)
{
    const char *w = argc > 1 ? argv[1] : "b1";
    int mesh = strcmp(w, "mesh") == 0, a = mesh ? 3 : 2;
    double n = argc > a ? atof(argv[a]) : 1e7;
    int threads = argc > a + 1 ? atoi(argv[a + 1]) : 1;
    mote_err err = {0};
    mote_ch_body b = {0};
    double R;
    if (mesh) {
        int level = argc > 2 ? atoi(argv[2]) : 8;
        if (mote_ch_body_icosphere(&b, 1, level, &err)) {
            fprintf(stderr, "bench_charging: %s\n", err.msg);
            return 1;
        }
        R = 3;
    } else {
        mote_ch_body_uvsphere(&b, 1, 100, 50, &err);
        if (strcmp(w, "b1") == 0 || strcmp(w, "b3") == 0)
            R = 3;
        else if (strcmp(w, "b2near") == 0)
            R = 0; /* 1.05 R_bound */
        else if (strcmp(w, "b2far") == 0)
            R = 131.41;
        else {
            fprintf(stderr, "usage: bench_charging [b1|b2near|b2far|b3 [N [THREADS]] | mesh K [N "
                            "[THREADS]]]\n");
            return 2;
        }
    }
    int rc = bench(w, &b, R, n, threads);
    mote_ch_body_free(&b);
    return rc;
}
