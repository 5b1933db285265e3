/* measure.h: internal to the hard-spheres model: running the dynamics (with a dump), the sampling
 * driver (spec 8.1), block errors and the common data-file header (spec 9.3), shared by every
 * measuring command. */
#ifndef MOTE_HS_MEASURE_H
#define MOTE_HS_MEASURE_H

#include "mote/hardspheres.h"
#include "mote/loop.h"
#include "mote/stats.h"

#define HS_BLOCKS 10

typedef struct {
    double time;
    uint64_t collisions, wall_collisions;
} hs_snap;

/* Called at each sample s (0-based) of nsamples, with positions available at the sample instant
 * through mote_ev_position. */
typedef void (*hs_sample_fn)(void *ctx, mote_hs *hs, uint64_t s, uint64_t nsamples);

void hs_snapshot(const mote_hs *hs, hs_snap *s);
/* Run floor(k N / 2) collisions taking nsamples samples right after collision floor(s C / S);
 * k == 0 takes one sample of the current state. tau = simulated time of the run. */
int hs_run_samples(mote_hs *hs, uint64_t k, uint64_t nsamples, hs_sample_fn fn, void *ctx,
                   const char *label, double *tau, mote_err *err);
/* The model's blocks: HS_BLOCKS of them (fewer with fewer samples), statistics from stats.h. */
static inline int hs_nblocks(uint64_t nsamples) { return mote_blocks_count(nsamples, HS_BLOCKS); }
static inline int hs_block_of(uint64_t s, uint64_t nsamples)
{
    return mote_block_of(s, nsamples, HS_BLOCKS);
}
static inline uint64_t hs_block_size(int b, uint64_t nsamples)
{
    return mote_block_size(b, nsamples, HS_BLOCKS);
}
static inline double hs_block_error(const double *block_means, int nblocks)
{
    return mote_block_error(block_means, nblocks);
}
void hs_write_header(FILE *f, const mote_hs *hs, const char *format, const char *origin,
                     const hs_snap *start, const hs_snap *end);

/* Run ncoll pair collisions (mote_ev_run) through the run loop, whose observer is an active
 * dump (its frames on the way); every command that runs the dynamics goes through here.
 * Dumping does not change the run. */
int hs_run(mote_hs *hs, uint64_t ncoll, mote_err *err);
/* The same through the core loop with observers of the caller's (at most 3) beside the dump,
 * progress (may be NULL) and the command's name for messages. */
int hs_run_observed(mote_hs *hs, uint64_t ncoll, mote_observer *obs, size_t nobs,
                    mote_progress *prog, const char *what, mote_err *err);
/* The trajectory, the snapshot series and the frames as observers of the run loop, into
 * o[0..2]: how many (xyz.c). */
size_t hs_dump_observer(mote_hs *hs, mote_observer *o);
size_t hs_checkpoint_observer(mote_hs *hs, mote_observer *o); /* (the last observer) */
/* monitor.c: the monitor's observer (0 or 1 filled), and its engine hooks on (1) for a run,
 * chained to those installed before, or off (0) again. */
size_t hs_monitor_observer(mote_hs *hs, mote_observer *o);
void hs_monitor_hooks(mote_hs *hs, int on);
/* After a command's runs (rc: their result): the monitor's FILE whole with every row so far (FILE.partial
 * kept when it cannot be written). Returns rc, or the write's error. */
int hs_monitor_end(mote_hs *hs, int rc, mote_err *err);
/* Free the system only (keeping settings and an active dump): for commands that replace it. */
void hs_drop_system(mote_hs *hs);
/* The local order of the current configuration with the `order` command's definitions, per
 * engine record: 3D q6 and crystal-like (>= 8 solid-like bonds), 2D |psi6| and ordered. */
int hs_local_order(const mote_hs *hs, float *local, uint8_t *flag, mote_err *err);
/* frame.c: the picture of `frames` (the box along z, coloured by local order), atomically. */
int hs_frame_png(const mote_hs *hs, const char *path, mote_err *err);

/* Bins along x for the profiles of pressure and chempot: width R/p from x = 0 in a slit (the last
 * bin may be narrower, as in `image`); in a periodic box nb equal bins tiling [0, L) exactly. */
typedef struct {
    size_t nb;
    double dx, L;
    int periodic;
} hs_xbins;

void hs_xbins_init(hs_xbins *xb, const mote_hs *hs, int64_t p);
size_t hs_xbins_of(const hs_xbins *xb, double x);
double hs_xbins_lo(const hs_xbins *xb, size_t b);
double hs_xbins_hi(const hs_xbins *xb, size_t b);

#endif
