/* mb.h: declarations shared inside the mixing-box model (src/mixingbox/) and with its tests:
 * the parameter check that also says which parameter groups a failure involves, the document's
 * wall rules of the time-stepped reference mode, one time step, the recording and picture
 * helpers the commands use. Nothing outside src/mixingbox/ and tests/ includes it. */
#ifndef MOTE_MB_INTERNAL_H
#define MOTE_MB_INTERNAL_H

#include "mote/mixingbox.h"
#include "mote/buf.h"

#include <stdio.h>

/* Parameter groups, one per command that sets them (bit masks for mb_params_check). */
enum {
    MB_P_BOX = 1 << 0,
    MB_P_PARTITION = 1 << 1,
    MB_P_SLIT = 1 << 2,
    MB_P_RADIUS = 1 << 3,
    MB_P_DISKS = 1 << 4,
    MB_P_VINIT = 1 << 5,
    MB_P_KICKS = 1 << 6,
    MB_P_LOSS = 1 << 7,
    MB_P_TC = 1 << 8,
    MB_P_NGROUPS = 9
};

/* mote_mb_params_check, also reporting in *groups (may be NULL) the parameter groups the failure
 * involves. */
int mb_params_check(const mote_mb_params *p, int *groups, mote_err *err);

/* Allocate sys->grid and lay it out for the placed system if not done yet. 0 or -1 (memory). */
int mb_ensure_grid(mote_mb *sys);
/* Lay a grid over the box for n disks (cells at least 2R wide). 0 or -1 (memory). */
int mb_grid_setup(mote_grid *g, const mote_mb_params *p, uint32_t n);
/* Sort disks 0 .. n-1 of the arrays x, y into the grid. */
void mb_grid_build(mote_grid *g, uint32_t n, const double *x, const double *y);

/* The live view's members of a frame (docs/live-view.md, live.c): the placed system, or before
 * it the box the commands have set (set); reads only. */
void mb_live_frame(const mote_mb *s, const mote_mb_params *set, mote_buf *b);

/* Largest N the model accepts. */
#define MB_N_MAX 10000000

/* ---- the time-stepped reference mode (timestep.c) -------------------------------------------- */

/* The document's wall rules (spec 2.4, 2.5) for disk i, in the document's order: top, bottom,
 * left, right walls, then the partition band. Counts wall_hits, slit_hits, partition_hits. */
void mb_ts_walls(mote_mb *sys, uint32_t i);
/* The disk-disk part of a step for the pair (i, j) at time t: when closer than 2R and
 * approaching ((r_j - r_i).(v_j - v_i) < 0), collide with mote_mb_collide; then, when closer
 * than 2R, move the upper disk (larger y; none when level) away from the lower one along the
 * line of centres to distance 2R. Returns 1 when they collided. */
int mb_ts_pair(mote_mb *sys, uint32_t i, uint32_t j, double t);
/* The step length R / (8 V) from the fastest speed V (V_init when all are at rest, 0.1 when that
 * is 0 too); NaN when a speed is not finite. */
double mb_ts_dt(const mote_mb *sys);
/* One whole step of length dt ending at time t_new: move, pairs, walls, chambers, overlaps. */
int mb_ts_step(mote_mb *sys, double dt, double t_new, mote_err *err);

/* ---- measurements (measure.c) ---------------------------------------------------------------- */

/* One row of the mixing curve. */
typedef struct {
    double t;
    mote_mb_tally c;
    uint64_t cross_lr, cross_rl;
    double kt[2];     /* mean kinetic energy per disk per chamber */
    double e, e_kin;
    uint64_t collisions, overlaps;
} mb_row;

/* The `monitor DT FILE` recording: the rows as numbers (a row's interval columns need the one
 * before) and as text, through the core's rows (mote_rows: FILE.partial during a run, FILE
 * whole after each run). */
typedef struct {
    int active;
    char *origin; /* the command line that started it (for the header) */
    double dt;      /* by time (0: by count) */
    uint64_t every; /* by count: disk-disk collisions between rows (0: by time) */
    mb_row *rows;
    size_t nrows, cap;
    const mote_mb *sys; /* (for the header) */
    mote_rows out;
} mb_record;

void mb_record_free(mb_record *r);
/* Start recording into path: the first row now (into FILE.partial, and into FILE when there is
 * none yet). */
int mb_record_start(mb_record *r, const mote_mb *sys, const char *path, int as, mote_err *err);
/* The run loop's observer: a row, streamed to FILE.partial (begun with the rows so far). */
int mb_record_observe(void *ctx, void *subject, mote_err *err);

/* The `density_y DT NBINS FILE` profile: y histograms per chamber summed over samples. */
typedef struct {
    int active;
    char *path, *origin;
    double dt;
    int64_t nbins;
    double y0, h;        /* lowest bin edge (X_B) and bin height */
    double *count[2];    /* summed counts per bin per chamber */
    double ke[2];        /* summed kinetic energy per chamber */
    double disks[2];     /* summed disk counts per chamber */
    uint64_t samples;
    double t_first, t_last;
} mb_density;

void mb_density_free(mb_density *d);
int mb_density_sample(void *ctx, void *subject, mote_err *err);
int mb_density_write(const mb_density *d, const mote_mb *sys, mote_err *err);

/* The header lines every mixing-box data file starts with: the common preamble (datafile.h) of
 * `format`, then the parameters. */
void mb_write_params(FILE *f, const mote_mb *sys, const char *format, const char *origin);

/* ---- the state file (state.c) ---------------------------------------------------------------- */

/* Write the placed system and `next`, the parameters the script has set for the next run or
 * placement, exactly; atomically. */
int mb_save(const mote_mb *sys, const mote_mb_params *next, const char *path, mote_err *err);
/* Read a state file written by mb_save: on success *sys is the saved system and *next the
 * saved parameters; on any failure (FILE:LINE in the message) both are untouched. */
int mb_load(mote_mb *sys, mote_mb_params *next, const char *path, mote_err *err);
/* The number of disks of a state file, from its header (for validation). */
int mb_peek(const char *path, uint64_t *n, mote_err *err);

/* ---- pictures (picture.c) -------------------------------------------------------------------- */

/* A PNG of the disks in their colours, the partition (as grey disks) and the box as the frame. */
int mb_snapshot_png(const mote_mb *sys, const char *path, mote_err *err);
/* Extended XYZ (OVITO, VMD): one frame with species, positions, velocities, radius, colour;
 * H5MD (h5md.h) when path ends in .h5 or .h5md, here and in the trajectory; VTK (vtk.h) when it
 * ends in .vtk (a snapshot). */
enum { MB_SERIES_XYZ = 1, MB_SERIES_H5MD = 2, MB_SERIES_VTK = 3 };
/* the words of `snapshot`'s format=e{xyz|h5md|vtk} and `trajectory`'s e{xyz|h5md} */
enum { MB_FORMAT_XYZ, MB_FORMAT_H5MD, MB_FORMAT_VTK };
int mb_snapshot_xyz(const mote_mb *sys, const char *path, const char *origin, mote_err *err);
/* One extended XYZ frame of sys into f (a mote_frame_writer: arg is an mb_xyz_of). */
typedef struct {
    const mote_mb *sys;
    const char *origin;
} mb_xyz_of;
int mb_xyz_frame(FILE *f, const void *arg, mote_err *err);
/* `trajectory every=K|dt=T file=FILE.xyz`: the core's growing file of frames. */
typedef struct {
    int active;
    char *path, *origin;
} mb_trajectory;
/* The run loop's observer (ctx: the mb_trajectory; subject: the system): a frame appended. */
int mb_trajectory_fire(void *ctx, void *subject, mote_err *err);

typedef struct {
    int active;
    char *prefix;
    double dt;      /* by time (0: by count) */
    uint64_t every; /* by count: disk-disk collisions between frames (0: by time) */
    int xyz;        /* snapshots (`snapshot every=|dt= prefix=`), not pictures: MB_SERIES_XYZ
                     * (extended XYZ) or MB_SERIES_H5MD */
    char *origin;   /* xyz: the command (the files' comment line) */
    uint64_t next_index; /* frame number of the next PNG */
} mb_frames;

/* PREFIX_%06d.png for index k (malloc'ed). */
char *mb_frame_name(const char *prefix, uint64_t k);
int mb_frames_sample(void *ctx, void *subject, mote_err *err);

/* Render a mixing-box data file (mixing curve or density profile) as a PNG. */
int mb_plot_file(const char *in, const char *out, mote_err *err);


/* state.c: the descriptors of the next run's parameters (offsets in mote_mb_params), for the
 * parameter commands bound to them */
struct mote_sf_field;
const struct mote_sf_field *mb_next_fields(size_t *n);

#endif
