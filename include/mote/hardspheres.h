/* hardspheres.h: the hard-spheres-near-a-wall model (specs/hard-spheres.md): seeding, the original
 * program's commands (new, save, load, step, compress_*, image, profile) and their file formats,
 * built on the event engine. Also fully periodic boxes and 2D disks. */
#ifndef MOTE_HARDSPHERES_H
#define MOTE_HARDSPHERES_H

#include "mote/command.h"
#include "mote/datafile.h"
#include "mote/event.h"

enum { MOTE_HS_SLIT = 0, MOTE_HS_PERIODIC = 1 };
enum { MOTE_HS_LEFT = 0, MOTE_HS_RIGHT = 1, MOTE_HS_BOTH = 2 };

typedef struct {
    mote_ev ev;
    int has_system;
    int geometry;        /* MOTE_HS_SLIT or MOTE_HS_PERIODIC */
    mote_rng rng;        /* the run's single random stream */
    uint64_t seed;       /* last seed given (default 1) */
    uint64_t rng_draws;  /* uniform draws since the last seed (informative) */
    int rng_from_file;   /* the stream was restored from a state file */
    mote_context *ctx;   /* may be NULL when used as a library */
    FILE *log;           /* progress/status messages; NULL = quiet */
    int64_t bins;        /* bins per R for the pressure and chempot profiles (`bins`, default 10) */
    struct hs_dump *dump; /* the trajectory being written (`dump`), or NULL */
    struct hs_dump *snaps; /* the snapshots on a schedule (`snapshot every=|dt=`), or NULL */
    struct hs_dump *frames; /* the pictures on a schedule (`frames`), or NULL */
    struct hs_monitor *monitor; /* the monitor being written (`monitor`), or NULL */
    int monitor_as;       /* its file's form (format=: MOTE_AS_NAME, _CSV, _JSONL), set before
                           * mote_hs_monitor_start */
    struct hs_dump *ckpt; /* the state kept on a schedule (`checkpoint`), or NULL */
} mote_hs;

/* The scalar results of a measuring command (pressure, chempot, order, ...) are a mote_result
 * (datafile.h): named values with their block errors, in the order of the summary line. */

/* The model as registered with the script language. */
extern const mote_model mote_model_hardspheres;

void mote_hs_init(mote_hs *hs, mote_context *ctx);
void mote_hs_free(mote_hs *hs);

/* ---- seeding (spec 5) ---- */
int mote_hs_new(mote_hs *hs, int64_t nn, double eta, mote_err *err);
int mote_hs_bulk(mote_hs *hs, int64_t n, double eta, mote_err *err);
int mote_hs_new_disks(mote_hs *hs, int64_t nx, int64_t ny, double eta, mote_err *err);
int mote_hs_bulk_disks(mote_hs *hs, int64_t n, double eta, mote_err *err);
/* Checks without building (for validation); return MOTE_OK or an error naming the limits. */
int mote_hs_new_ok(int64_t nn, double eta, mote_err *err);
int mote_hs_bulk_ok(int64_t n, double eta, mote_err *err);
int mote_hs_new_disks_ok(int64_t nx, int64_t ny, double eta, mote_err *err);
int mote_hs_bulk_disks_ok(int64_t n, double eta, mote_err *err);
/* N(NN) = (4NN-1)(2NN-1)^2 + 1 and eta_max(NN) of `new`. */
uint64_t mote_hs_new_count(int64_t nn);
double mote_hs_new_eta_max(int64_t nn);
void mote_hs_seed(mote_hs *hs, uint64_t seed);

/* ---- state ---- */
double mote_hs_eta(const mote_hs *hs);   /* relative density (spec 2.4) */
double mote_hs_phi(const mote_hs *hs);   /* plain packing fraction */
double mote_hs_cross_section(const mote_hs *hs); /* A_y A_z (3D) or A_y (2D) */
double mote_hs_particle_volume_sum(const mote_hs *hs);
double mote_hs_mean_radius(const mote_hs *hs);
int mote_hs_temperature(mote_hs *hs, double kt, mote_err *err);
int mote_hs_check(mote_hs *hs, mote_err *err);
/* Replace the positions or velocities (`name`), rows x cols = N x d numbers in the particles'
 * numbering, after checking them: finite, centres between the walls, no two spheres overlapping
 * (positions; periodic coordinates wrapped into the box). On an error the system is unchanged.
 * Energies are measured from the new state. */
int mote_hs_set_array(mote_hs *hs, const char *name, const double *val, size_t rows, size_t cols,
                      mote_err *err);

/* ---- dynamics ---- */
/* step K: floor(K N / 2) pair collisions, with a progress display when hs->ctx->terminal. */
int mote_hs_step(mote_hs *hs, uint64_t k, mote_err *err);
int mote_hs_compress(mote_hs *hs, int which, double eta, double dlmax, uint64_t k, mote_err *err);
/* compress_box eta dLmax K: a periodic box scaled affinely, centres and all, move by move (each
 * limited by the closest pair's gap and by dLmax, K collisions per particle after each), ending at
 * phi = eta exactly; expansion in one move. */
int mote_hs_compress_box(mote_hs *hs, double eta, double dlmax, uint64_t k, mote_err *err);
/* The wall position L* for a target eta (slit). */
double mote_hs_target_length(const mote_hs *hs, double eta);

/* ---- files ---- */
/* The canonical state (every particle at the current time, coordinates wrapped, lists, cells and
 * calendar rebuilt): what `save` writes and `load` rebuilds bit for bit. The script layer settles
 * after every command; a library caller who wants `A; B` to run exactly as `A; save; load; B`
 * settles after A too. Settling a settled system changes nothing. */
int mote_hs_settle(mote_hs *hs, mote_err *err);
int mote_hs_save(mote_hs *hs, const char *path, mote_err *err);
/* The file save writes, without synchronising the engine (each particle brought to the present
 * in the file only: the same numbers; a run is not changed by it): the checkpoint's writer. */
int mote_hs_write_state(const mote_hs *hs, const char *path, mote_err *err);
int mote_hs_load(mote_hs *hs, const char *path, mote_err *err);
/* Read just enough of a state file (either format) to know its geometry, dimension and N. */
int mote_hs_peek(const char *path, int *geometry, int *dim, uint64_t *n, mote_err *err);

/* ---- configurations for viewers (extended XYZ: OVITO, VMD, ASE) ---- */
/* One frame of the current state: box as Lattice, pbc, per particle (by number) species X,
 * position, velocity, radius, and the local order of this configuration (3D q6 and the
 * crystal-like flag `solid`, 2D |psi6| and `ordered`, as `order` defines them). Atomic. */
int mote_hs_snapshot(mote_hs *hs, const char *path, const char *origin, mote_err *err);
/* A path ending in .h5 or .h5md (mote_path_is_h5md) is written as H5MD instead (h5md.h: the
 * same positions, velocities, radius and local order, the box and its periodic axes, time and
 * collisions as the step), here and in the trajectories and series below. */
/* Write a frame now (atomically replacing path) and then one every k collisions per particle
 * (k N / 2 pair collisions) during every later step, compression or measurement, appended;
 * replaces an earlier dump. Frames only read the state: the run is the same with or without. */
int mote_hs_dump_start(mote_hs *hs, uint64_t k, const char *path, const char *origin,
                       mote_err *err);
/* The same with a frame every K collisions per particle (k > 0) or every dt of time (dt > 0,
 * k = 0): frames at t0 + j dt exactly (the run stops there), t0 the time now. */
int mote_hs_dump_start_on(mote_hs *hs, uint64_t k, double dt, const char *path,
                          const char *origin, mote_err *err);
/* The monitor (`monitor`): a row of t, collisions, wall collisions, kT and the pressure of the
 * interval since the previous row now (atomically replacing path), then one every k collisions
 * per particle (k > 0) or every dt of time (dt > 0, k = 0) during every later step, compression
 * or measurement, appended whole. Rows only read the state: the run is the same with or
 * without. */
int mote_hs_monitor_start(mote_hs *hs, uint64_t k, double dt, const char *path,
                          const char *origin, mote_err *err);
void mote_hs_monitor_stop(mote_hs *hs);
uint64_t mote_hs_monitor_rows(const mote_hs *hs);
void mote_hs_dump_stop(mote_hs *hs);
uint64_t mote_hs_dump_frames(const mote_hs *hs);
/* Snapshots on a schedule (`snapshot every=K|dt=T prefix=P`): one now and one every k
 * collisions per particle (k > 0) or every dt of time (dt > 0, k = 0) during every later step,
 * compression or measurement, each its own file P_000000.xyz, P_000001.xyz, ... (mote_series_path,
 * written atomically; the same prefix again continues the numbering); replaces an earlier
 * series. */
int mote_hs_snapshots_start(mote_hs *hs, uint64_t k, double dt, const char *prefix,
                            const char *origin, mote_err *err);
/* The same with files P_000000.EXT (ext ".xyz" or ".h5"). */
int mote_hs_snapshots_start_as(mote_hs *hs, uint64_t k, double dt, const char *prefix,
                               const char *ext, const char *origin, mote_err *err);
void mote_hs_snapshots_stop(mote_hs *hs);
/* Pictures on a schedule (`frames every=K|dt=T prefix=P`), as the snapshots: P_000000.png on,
 * the box seen along z, each particle coloured by its local order (crystal-like or not). */
int mote_hs_frames_start(mote_hs *hs, uint64_t k, double dt, const char *prefix,
                         const char *origin, mote_err *err);
void mote_hs_frames_stop(mote_hs *hs);
/* The exact state on a schedule (`checkpoint every=K file=FILE`): written now and every k
 * collisions per particle of every later step, compression or measurement, each time the file
 * `save` would write (mote_hs_write_state; FILE replaced atomically). It only reads the run;
 * `load` of it continues as a run split there into two commands. */
int mote_hs_checkpoint_start(mote_hs *hs, uint64_t k, const char *path, const char *origin,
                             mote_err *err);
void mote_hs_checkpoint_stop(mote_hs *hs);

/* ---- measurements (spec 8); `origin` names the generating command for file headers ---- */
int mote_hs_image(mote_hs *hs, uint64_t k, int64_t p, const char *path, const char *origin,
                  mote_err *err);
#define MOTE_HS_PROFILE_DOTS_MAX 1000000
int mote_hs_profile(mote_hs *hs, double x1, double x2, int64_t dots, uint64_t k,
                    const char *path, const char *origin, mote_err *err);

/* pressure K FILE (spec 8.4): wall pressures, collisional virial, pressure-tensor profiles with
 * bins of width R/hs->bins, contact densities. res may be NULL. */
int mote_hs_pressure(mote_hs *hs, uint64_t k, const char *path, const char *origin,
                     mote_result *res, mote_err *err);
/* chempot K TRIALS FILE (spec 8.5): Widom test-particle insertion. */
int mote_hs_chempot(mote_hs *hs, uint64_t k, int64_t trials, const char *path,
                    const char *origin, mote_result *res, mote_err *err);
/* order K FILE (spec 8.6): Steinhardt q6 and in-layer psi6, per wall layer and over time. */
int mote_hs_order(mote_hs *hs, uint64_t k, const char *path, const char *origin,
                  mote_result *res, mote_err *err);

/* rdf K RMAX FILE: g(r) in a periodic box (with g(sigma+) and Z = 1 + 2^(d-1) eta g(sigma+)),
 * the lateral g(s) of the wall layer and a mid-slit layer in a slit; src/hardspheres/structure.c.
 * mote_hs_rdf_ok checks RMAX against the box (a diameter < RMAX <= half a periodic length). */
int mote_hs_rdf_ok(const mote_hs *hs, double rmax, mote_err *err);
int mote_hs_rdf(mote_hs *hs, uint64_t k, double rmax, const char *path, const char *origin,
                mote_result *res, mote_err *err);
/* msd K FILE (K >= 4): mean-squared displacement, unwrapped (in a slit parallel to the walls),
 * and the self-diffusion coefficient D with its error (results D, fit_from, fit_to). */
int mote_hs_msd(mote_hs *hs, uint64_t k, const char *path, const char *origin,
                mote_result *res, mote_err *err);

/* Print the key=value status line. */
void mote_hs_status(const mote_hs *hs, FILE *out);

#endif
