/* model.h: internal to the separator model: its script-level state (the system, the settings
 * of the script, the scheduled outputs) and the commands that run.c holds. */
#ifndef MOTE_SEP_MODEL_H
#define MOTE_SEP_MODEL_H

#include "mote/command.h"
#include "mote/loop.h"
#include "sep.h"

/* An output's schedule (every=K steps or dt=T; the first at the next run's start) */
typedef struct {
    mote_schedule at;
    mote_observer o;
    int first; /* every=K: the first is still to be written at the next run's start */
} sep_schedule;

typedef struct {
    mote_context *ctx;
    int dry;
    FILE *log;
    mote_sep_system sys;
    int have_channel, have_gas;
    /* the dry model's account for the estimates of `run` (check): the particles there may be
     * (fed or inserted, none leaving: an upper bound) and the time the runs have reached */
    double est_n, est_t;
    int warned_stiffness; /* (contact hertz with stiffness overlap= or khat=: said once) */
    uint64_t seed;
    /* the outputs on a schedule (spec 3): frames, the live picture, snapshots, the balance */
    struct {
        int on, movie, fps;
        char *prefix, *movie_path; /* PREFIX_000000.png ...; the movie beside them */
        sep_schedule when;
        uint64_t index;
        sep_frame_opts fo;
    } frames;
    struct {
        int on;
        char *path;
        double hz, last, gap; /* (gap: mote_pace_gap after the last picture) */
        sep_frame_opts fo;
    } live;
    struct {
        int on;
        char *prefix; /* PREFIX_000000.xyz (or .h5, .vtk) ... */
        char *origin; /* the command (H5MD files keep it) */
        int h5md;     /* format=xyz|h5md|vtk (0, 1, 2) */
        sep_schedule when;
        uint64_t index;
    } snaps;
    struct {
        int on;
        char *origin;
        char *path;      /* FILE.xyz (or .h5: H5MD), the core's growing file of frames */
        uint64_t frames; /* written so far (0: the next replaces FILE) */
        sep_schedule when;
    } traj;
    struct {
        int on, held;
        char *origin;
        sep_schedule when;
        double *row;   /* room for one row */
        mote_rows out; /* PATH.partial during a run, PATH after it (the core's policy) */
    } bal;
    struct {
        int on;
        char *path; /* the state, replaced at each checkpoint */
        sep_schedule when;
    } ckpt;
    mote_loop *loop; /* during a run: the core's loop (the outputs above as observers, and the
                      * progress) */
    int prepared;    /* during a run: the system prepared at its first advance */
    uint64_t n_stop; /* during a run: the step count the loop stops at next */
} sep_model;

/* commands.c: the species called name, or -1; the system prepares (else the call's error) */
int sep_find_species(const mote_sep_system *s, const char *name);
int sep_need_ready(sep_model *m, const mote_call *c, mote_err *err);

/* run.c: the commands' check (on the dry model) and run functions */
int sep_check_ready(void *vm, const mote_call *c, mote_err *err);
/* `run T` checked: ready, and (the dry model) the run's estimate: its steps, particles, wall
 * time and memory, printed by `mote check` and a warning when it would take over an hour. */
int sep_check_run(void *vm, const mote_call *c, mote_err *err);
/* The number-basis mean mass of species k's particles (kg). */
double sep_mean_mass(const mote_sep_system *s, int k);
int sep_check_table(void *vm, const mote_call *c, mote_err *err);
int sep_run(void *vm, const mote_call *c, mote_err *err);
int sep_tromp(void *vm, const mote_call *c, mote_err *err);
int sep_profiles(void *vm, const mote_call *c, mote_err *err);
int sep_save(void *vm, const mote_call *c, mote_err *err);
int sep_check_load(void *vm, const mote_call *c, mote_err *err);
int sep_load(void *vm, const mote_call *c, mote_err *err);
int sep_summary(void *vm, const mote_call *c, mote_err *err);
/* the scheduled outputs: the same function sets them on either model */
int sep_frames(void *vm, const mote_call *c, mote_err *err);
int sep_live_png(void *vm, const mote_call *c, mote_err *err);
int sep_snapshots(void *vm, const mote_call *c, mote_err *err);
int sep_balance(void *vm, const mote_call *c, mote_err *err);
int sep_trajectory(void *vm, const mote_call *c, mote_err *err);
int sep_trajectory_stop(void *vm, const mote_call *c, mote_err *err);
int sep_frames_stop(void *vm, const mote_call *c, mote_err *err);
int sep_snapshot_stop(void *vm, const mote_call *c, mote_err *err);
int sep_monitor_stop(void *vm, const mote_call *c, mote_err *err);
int sep_checkpoint(void *vm, const mote_call *c, mote_err *err);
int sep_checkpoint_stop(void *vm, const mote_call *c, mote_err *err);
/* the model's hooks */
void sep_status(void *vm, FILE *out);
void sep_model_live(void *vm, mote_buf *b);

#endif
