/* bench_hs.c: collision-rate benchmark of the event engine on the hard-sphere workloads of the
 * spec (section 11) and issue 5: periodic FCC cubes `bulk N eta` and slits `new NN eta`.
 * Each workload: seed, warm up 20 collisions per particle (not timed), then time `step K`
 * (K = 200 by default), counting only sphere-sphere collisions. Prints one key=value line per
 * workload: the settings, the rate, events per collision (and how many of them were stale pair
 * events, list renewals and wall hits), bytes per particle held by the engine,
 * and the peak resident memory of the process so far.
 *
 * Usage: bench_hs [K] [workload...]
 *   workload: bulkN:ETA (N = 4 n^3, e.g. bulk32000:0.45, bulk1048576:0.50) or slitNN:ETA
 *   (`new NN eta`, e.g. slit13:0.45, N = 31876), optionally @K to override K for it
 *   (bulk1048576:0.45@20). Default: bulk32000 and slit13 at eta 0.45 and 0.50. */
#include "mote/hardspheres.h"

#include <stdlib.h>
#include <string.h>

static int run(const char *spec, uint64_t k)
{
    mote_hs hs;
    mote_err err = {0};
    mote_hs_init(&hs, NULL);
    int is_bulk = strncmp(spec, "bulk", 4) == 0;
    const char *num = spec + 4;
    double eta = 0.45;
    if (!is_bulk && strncmp(spec, "slit", 4) != 0) {
        fprintf(stderr, "bench_hs: unknown workload '%s'\n", spec);
        return 1;
    }
    long long n = atoll(num);
    const char *colon = strchr(spec, ':');
    if (colon)
        eta = atof(colon + 1);
    const char *at = strchr(spec, '@');
    if (at)
        k = strtoull(at + 1, NULL, 10);
    double w0 = mote_wall_seconds();
    int rc = is_bulk ? mote_hs_bulk(&hs, n, eta, &err) : mote_hs_new_slit(&hs, n, eta, &err);
    if (!rc)
        rc = mote_ev_run(&hs.ev, 20ull * hs.ev.n / 2, &err);
    if (rc) {
        fprintf(stderr, "bench_hs: %s: %s\n", spec, err.msg);
        mote_hs_free(&hs);
        return 1;
    }
    double setup = mote_wall_seconds() - w0;
    const mote_ev c0 = hs.ev; /* the counters before the timed run */
    double t0 = mote_wall_seconds();
    rc = mote_ev_run(&hs.ev, k * hs.ev.n / 2, &err);
    double secs = mote_wall_seconds() - t0;
    if (rc) {
        fprintf(stderr, "bench_hs: %s: %s\n", spec, err.msg);
        mote_hs_free(&hs);
        return 1;
    }
    uint64_t coll = hs.ev.collisions - c0.collisions;
    double per = 1.0 / (double)coll;
    double rss = (double)mote_peak_rss_bytes();
    printf("workload=%s N=%u eta=%.4g geometry=%s warmup_per_particle=20 timed_per_particle=%llu "
           "collisions=%llu events_per_collision=%.3f stale_per_collision=%.4f "
           "renewals_per_collision=%.4f wall_hits_per_collision=%.4f "
           "seconds=%.3f collisions_per_second=%.4g "
           "engine_bytes_per_particle=%.1f peak_rss_MiB=%.1f peak_rss_bytes_per_particle=%.1f "
           "setup_seconds=%.2f\n",
           spec, hs.ev.n, mote_hs_eta(&hs), hs.geometry == MOTE_HS_SLIT ? "slit" : "periodic",
           (unsigned long long)k, (unsigned long long)coll,
           (double)(hs.ev.events - c0.events) * per,
           (double)(hs.ev.stale_events - c0.stale_events) * per,
           (double)(hs.ev.renewals - c0.renewals) * per,
           (double)(hs.ev.wall_collisions - c0.wall_collisions) * per, secs,
           (double)coll / secs, mote_ev_bytes_per_particle(&hs.ev), rss / 1048576.0,
           rss / hs.ev.n, setup);
    fflush(stdout);
    mote_hs_free(&hs);
    return 0;
}

int main(int argc, char **argv)
{
    static const char *const defaults[] = {"bulk32000:0.45", "slit13:0.45", "bulk32000:0.50",
                                           "slit13:0.50"};
    uint64_t k = 200;
    int first = 1;
    if (argc > 1 && argv[1][0] >= '0' && argv[1][0] <= '9') {
        k = strtoull(argv[1], NULL, 10);
        first = 2;
    }
    int rc = 0;
    if (first >= argc) {
        for (size_t w = 0; w < sizeof defaults / sizeof *defaults; w++)
            rc |= run(defaults[w], k);
    } else {
        for (int a = first; a < argc; a++)
            rc |= run(argv[a], k);
    }
    return rc;
}
