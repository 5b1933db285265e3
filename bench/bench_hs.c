/* bench_hs.c: collision-rate benchmark of the event engine on the hard-sphere workloads of the
 * spec (section 11) and issue 5: periodic FCC cubes `bulk N eta` and slits `new NN eta`.
 * Each workload: seed, warm up 20 collisions per particle (not timed), then time `step K`
 * (K = 200 by default), counting only sphere-sphere collisions. Prints one key=value line per
 * workload: the settings, the rate, events per collision (and how many of them were stale pair
 * events, list renewals and wall hits), bytes per particle held by the engine,
 * and the peak resident memory of the process so far.
 *
 * A pair A/B of workloads is measured interleaved in one process, to compare their rates on a
 * noisy machine: both are seeded and warmed up, then the timed K collisions per particle run in
 * CHUNKS chunks per workload, alternating A B, B A, A B, ... so that whatever else the machine
 * does falls on both alike. Prints each workload's line, then one line with the ratio of the
 * rates A / B over the whole run and the median and quartiles of the per-chunk ratios.
 *
 * Usage: bench_hs [K] [workload...]
 *   workload: bulkN:ETA (N = 4 n^3, e.g. bulk32000:0.45, bulk1048576:0.50), slitNN:ETA
 *   (`new NN eta`, e.g. slit13:0.45, N = 31876) or twinNN:ETA (the slit's periodic twin: same
 *   N and eta, no walls; see make_twin), optionally @K to override K for it
 *   (bulk1048576:0.45@20), or A/B (slit13:0.45/twin13:0.45) for an interleaved pair.
 *   Default: bulk32000 and slit13 at eta 0.45 and 0.50. */
#include "mote/hardspheres.h"

#include <stdlib.h>
#include <string.h>

MOTE_PROGRAM_THREADS

#define CHUNKS 20

typedef struct {
    char spec[128];
    uint64_t k; /* timed collisions per particle */
    mote_hs hs;
    mote_ev c0; /* the counters before the timed run */
    double setup, secs;
    double settle; /* seconds of one mote_hs_settle after the timed run (what every script
                    * command ends with); 0 when not measured */
} workload;

/* The slit's periodic twin: the box of `new NN eta` made periodic along x with the length the
 * centres can reach, L - 2R, so that N and eta are the slit's (in a periodic box eta is the
 * packing fraction) and only the walls differ. The seed's x coordinates are scaled by
 * (L - 2R) / L, which with spec 5.2's x = (L / 2 L0) X makes the x spacing (L - 2R) / (2 L0) per
 * unit of X: no pair comes closer than 2R, across the new periodic face included, as long as
 * that factor is at least 1 (beta >= 1 + 1/L0, true well below eta_max: 1.15 at NN 13 and eta
 * 0.45). The invariant checker confirms it. */
static int make_twin(mote_hs *hs, mote_err *err)
{
    mote_ev *ev = &hs->ev;
    const double L = ev->len[0], Lp = L - 2 * mote_hs_mean_radius(hs);
    for (uint32_t i = 0; i < ev->n; i++)
        ev->p[i].r[0] *= Lp / L;
    ev->len[0] = Lp;
    ev->periodic[0] = 1;
    hs->geometry = MOTE_HS_PERIODIC;
    int rc = mote_ev_rebuild(ev, err);
    if (!rc && mote_ev_check(ev, err))
        rc = 1; /* err names the overlap: eta too close to eta_max for a twin */
    return rc;
}

/* Parse, seed and warm up w from `spec` (up to a '/' or the end). */
static int setup(workload *w, const char *spec, size_t len, uint64_t k)
{
    mote_err err = {0};
    if (len >= sizeof w->spec) {
        fprintf(stderr, "bench_hs: workload name too long: '%.*s'\n", (int)len, spec);
        return 1;
    }
    memcpy(w->spec, spec, len);
    w->spec[len] = '\0';
    w->k = k;
    w->secs = 0;
    w->settle = 0;
    mote_hs_init(&w->hs, NULL);
    int is_bulk = strncmp(w->spec, "bulk", 4) == 0, is_twin = strncmp(w->spec, "twin", 4) == 0;
    if (!is_bulk && !is_twin && strncmp(w->spec, "slit", 4) != 0) {
        fprintf(stderr,
                "bench_hs: unknown workload '%s' (expected bulkN:ETA, slitNN:ETA or twinNN:ETA)\n",
                w->spec);
        return 1;
    }
    long long n = atoll(w->spec + 4);
    double eta = 0.45;
    const char *colon = strchr(w->spec, ':');
    if (colon)
        eta = atof(colon + 1);
    const char *at = strchr(w->spec, '@');
    if (at)
        w->k = strtoull(at + 1, NULL, 10);
    double w0 = mote_wall_seconds();
    int rc = is_bulk ? mote_hs_bulk(&w->hs, n, eta, &err)
                     : mote_hs_new(&w->hs, n, eta, &err);
    if (!rc && is_twin)
        rc = make_twin(&w->hs, &err);
    if (!rc)
        rc = mote_ev_run(&w->hs.ev, 20ull * w->hs.ev.n / 2, &err);
    if (rc) {
        fprintf(stderr, "bench_hs: %s: %s\n", w->spec, err.msg);
        mote_hs_free(&w->hs);
        return 1;
    }
    w->setup = mote_wall_seconds() - w0;
    w->c0 = w->hs.ev;
    return 0;
}

/* Run `coll` more timed collisions of w; *secs gets their wall time. */
static int timed(workload *w, uint64_t coll, double *secs)
{
    mote_err err = {0};
    double t0 = mote_wall_seconds();
    int rc = mote_ev_run(&w->hs.ev, coll, &err);
    *secs = mote_wall_seconds() - t0;
    w->secs += *secs;
    if (rc)
        fprintf(stderr, "bench_hs: %s: %s\n", w->spec, err.msg);
    return rc;
}

static double rate(const workload *w)
{
    return (double)(w->hs.ev.collisions - w->c0.collisions) / w->secs;
}

static void report(const workload *w)
{
    const mote_ev *ev = &w->hs.ev, *c0 = &w->c0;
    uint64_t coll = ev->collisions - c0->collisions;
    double per = 1.0 / (double)coll;
    double rss = (double)mote_peak_rss_bytes();
    printf("workload=%s N=%u eta=%.4g geometry=%s warmup_per_particle=20 timed_per_particle=%llu "
           "collisions=%llu events_per_collision=%.3f stale_per_collision=%.4f "
           "renewals_per_collision=%.4f wall_hits_per_collision=%.4f "
           "seconds=%.3f collisions_per_second=%.4g "
           "engine_bytes_per_particle=%.1f peak_rss_MiB=%.1f peak_rss_bytes_per_particle=%.1f "
           "setup_seconds=%.2f settle_seconds=%.4f settle_per_particle_in_collisions=%.2f\n",
           w->spec, ev->n, mote_hs_eta(&w->hs), w->hs.geometry == MOTE_HS_SLIT ? "slit" : "periodic",
           (unsigned long long)w->k, (unsigned long long)coll,
           (double)(ev->events - c0->events) * per,
           (double)(ev->stale_events - c0->stale_events) * per,
           (double)(ev->renewals - c0->renewals) * per,
           (double)(ev->wall_collisions - c0->wall_collisions) * per, w->secs, rate(w),
           mote_ev_bytes_per_particle(ev), rss / 1048576.0, rss / ev->n, w->setup, w->settle,
           w->settle * rate(w) * 2.0 / ev->n);
    fflush(stdout);
}

static int run(const char *spec, uint64_t k)
{
    workload w;
    if (setup(&w, spec, strlen(spec), k))
        return 1;
    double secs;
    int rc = timed(&w, w.k * w.hs.ev.n / 2, &secs);
    if (!rc) {
        mote_err err = {0};
        double t0 = mote_wall_seconds();
        rc = mote_hs_settle(&w.hs, &err);
        w.settle = mote_wall_seconds() - t0;
        if (rc)
            fprintf(stderr, "bench_hs: %s: %s\n", w.spec, err.msg);
    }
    if (!rc)
        report(&w);
    mote_hs_free(&w.hs);
    return rc;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The interleaved pair A/B (see the top of the file). */
static int run_pair(const char *spec, uint64_t k)
{
    const char *slash = strchr(spec, '/');
    workload *w = calloc(2, sizeof *w);
    if (!w) {
        fprintf(stderr, "bench_hs: out of memory\n");
        return 1;
    }
    int rc = setup(&w[0], spec, (size_t)(slash - spec), k);
    if (!rc && setup(&w[1], slash + 1, strlen(slash + 1), k)) {
        mote_hs_free(&w[0].hs);
        rc = 1;
    }
    if (rc) {
        free(w);
        return 1;
    }
    for (int s = 0; s < 2; s++)
        if (w[s].k * w[s].hs.ev.n / 2 < 100 * CHUNKS) {
            fprintf(stderr, "bench_hs: %s: too few timed collisions to split into %d chunks\n",
                    w[s].spec, CHUNKS);
            rc = 1;
        }
    double ratio[CHUNKS];
    for (int c = 0; c < CHUNKS && !rc; c++) {
        double secs[2] = {0, 0};
        uint64_t coll[2];
        for (int s = 0; s < 2; s++) { /* chunk c of the collisions, rounded so the total is exact */
            uint64_t total = w[s].k * w[s].hs.ev.n / 2;
            coll[s] = total * (uint64_t)(c + 1) / CHUNKS - total * (uint64_t)c / CHUNKS;
        }
        for (int q = 0; q < 2 && !rc; q++) {
            int s = (c & 1) ? 1 - q : q; /* A B, then B A, ... */
            rc = timed(&w[s], coll[s], &secs[s]);
        }
        ratio[c] = (double)coll[0] / secs[0] / ((double)coll[1] / secs[1]);
    }
    if (!rc) {
        report(&w[0]);
        report(&w[1]);
        qsort(ratio, CHUNKS, sizeof *ratio, cmp_double);
        printf("pair=%s chunks=%d rate_ratio=%.4f chunk_ratio_median=%.4f chunk_ratio_q1=%.4f "
               "chunk_ratio_q3=%.4f chunk_ratio_min=%.4f chunk_ratio_max=%.4f\n",
               spec, CHUNKS, rate(&w[0]) / rate(&w[1]),
               0.5 * (ratio[CHUNKS / 2 - 1] + ratio[CHUNKS / 2]), ratio[CHUNKS / 4],
               ratio[(3 * CHUNKS) / 4 - 1], ratio[0], ratio[CHUNKS - 1]);
        fflush(stdout);
    }
    mote_hs_free(&w[0].hs);
    mote_hs_free(&w[1].hs);
    free(w);
    return rc;
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
            rc |= strchr(argv[a], '/') ? run_pair(argv[a], k) : run(argv[a], k);
    }
    return rc;
}
