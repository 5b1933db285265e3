/* model.h: the N-body model's script state (nb_model) and the command handlers its files
 * share: commands.c holds the table, the model's life and the setup commands (bodies, units,
 * generators, integrator); outputs.c the output commands; run.c integrate, which drives them
 * through the run loop; files.c the state and Galactica files and jobs; live.c the live view; help.inc
 * the help text. Internal to src/nbody. */
#ifndef MOTE_NB_MODEL_H
#define MOTE_NB_MODEL_H

#include "mote/command.h"
#include "mote/stats.h"
#include "mote/nbody.h"

#include <stdio.h>

#include "nb.h"

typedef struct nb_model {
    mote_nb nb;
    mote_sf_field sf[NB_STATE_FIELDS]; /* the state file's table, for the bound parameters */
    mote_context *ctx;
    FILE *log;          /* ctx->out when running, NULL when validating */
    int dry;
    /* what validation knows */
    uint32_t d_bodies;
    int d_ring;
    int d_scales;       /* are physical scales known (units or a generator)? */
    /* units (spec 3.5): body values in SI, and while `raw`, held in SI until the total mass is
     * known (mass=auto): the scales then come from `req` */
    int input_si, raw;
    struct nb_units_req {
        int preset;       /* UNITS_CUSTOM, UNITS_SOLAR, UNITS_ATOMIC, UNITS_NONE */
        int mass_auto, input_si;
        double mass, length, time; /* kg, m, s (length or time: the other is 0) */
    } req;
    /* the ring generated last (the reference of `check ring`) */
    mote_nb_ring ring;
    int have_ring;
    /* the monitor and the trajectory: a sample every `every` steps of integrate into `path` */
    struct nb_sampler {
        uint64_t every;     /* 0: off */
        char *path, *origin;
        double *rows;       /* cols per sample */
        size_t nrows, cap, cols;
        double L0[3];       /* trajectory: L + S when it started (the invariable plane) */
        int on, format;     /* format: FMT_TABLE, FMT_CSV, FMT_JSONL, FMT_H5MD (path
                             * NULL: the terminal) */
        mote_real dt, t0;   /* by time: samples at t0 + k dt (dt 0: every `every` steps) */
        mote_schedule at;   /* the same in double, the run loop's schedule */
        double ekmax, t_ekmax; /* monitor: the largest kinetic energy of a body so far */
        double cpu0, wall0;    /* monitor: clocks when it started */
        uint32_t *sel, nsel;   /* trajectory: the bodies recorded (0-based), and how many */
        uint32_t n0;           /* trajectory: the number of bodies when it started */
        int vel;               /* trajectory: velocities too */
        char tunit[16];        /* unit= of the command ("" none): a last column T_UNIT, */
        double tscale;         /* T / tscale, the time in that unit */
        mote_rows out;         /* PATH's rows as text (PATH.partial during integrate) */
    } mon, traj;
    /* checkpoints: the exact state into `path` every `every` steps and at the end of integrate */
    struct {
        char *path;
        uint64_t every;
    } ckpt;
    /* periodic snapshots: PREFIX STEP .snap (galactica: .dat) every `every` steps, or PREFIX
     * INDEX .snap every dt of time (at: its schedule; index: the next file's number) (0: off) */
    struct {
        char *prefix, *origin;
        uint64_t every, index;
        double dt;
        mote_schedule at;
        int galactica;
    } snap;
    /* closest approaches of one body (spec 7.9, 10.4): a row every `every` steps into path */
    struct {
        nb_approach a;
        uint64_t every;   /* 0: off */
        char *path, *origin;
        int galactica;    /* dice.dat's three columns (time, body, distance) */
    } appr;
    /* Galactica-style pictures (spec 7.13) every `every` steps or dt of time: PREFIX_000001.png,
     * ... */
    struct {
        uint64_t every, count;
        double dt;          /* by time instead (at: its schedule); 0: by steps */
        mote_schedule at;
        char *prefix;
        nb_galctl ctl;      /* the graphics values and trios */
        nb_frame_opts f;
    } frames;
    /* the live view: the plane shown (0 xy, 1 xz, 2 yz) and the recent paths of up to
     * LIVE_PATHS bodies, LIVE_LEN points each (a ring per body; view state only) */
    struct {
        int plane;
        double *pts;
        uint32_t nb;
        size_t len, head;
    } live;
    /* the header of the last Galactica file read (its Em and area fields are carried over) */
    int have_galhead;
    mote_real galhead[25];
    /* validation: the format each monitor or trajectory file is written in ("table", "csv",
     * "jsonl"), so that `plot` of one it cannot read fails before the run */
    mote_outputs formats;
} nb_model;

typedef struct nb_sampler nb_sampler;
typedef struct nb_units_req nb_units_req;
enum { UNITS_CUSTOM, UNITS_SOLAR, UNITS_ATOMIC, UNITS_NONE };

/* ---- arrays.c: the bodies as arrays (mote_model.arrays, set_array) ---- */
int nb_model_arrays(void *vm, mote_array *out, int cap);
int nb_model_set_array(void *vm, const char *name, const double *v, size_t rows, size_t cols,
                       mote_err *err);

/* ---- commands.c: helpers the other files share ---- */
void nb_settle_units(nb_model *m);
mote_real nb_opt_real_or(const mote_call *c, const char *key, mote_real dflt);
int nb_need_bodies(nb_model *m, const mote_call *c, mote_err *err);
/* `body` with orbital elements (orbit.c): their options checked; the body's x and v (in the
 * model's units, its mass already in them) from them when given, else x and v unchanged. */
int nb_body_elements_check(const nb_model *m, const mote_call *c, mote_err *err);
int nb_body_elements(nb_model *m, const mote_call *c, mote_real mass, mote_real x[3],
                     mote_real v[3], mote_err *err);

/* ---- outputs.c ---- */
/* The words of format=e{native|galactica} (snapshot, approaches) by their place */
enum { NB_FORMAT_NATIVE, NB_FORMAT_GALACTICA };
/* outputs.c: what integrate (run.c) shares with the output commands */
int nb_sample(nb_model *m, int traj, const mote_nb *nb, mote_err *err);
int nb_sampler_finish(nb_model *m, nb_sampler *s, int traj, int rc, mote_err *err);
int nb_frame_now(nb_model *m, mote_err *err);
int nb_frame_of(nb_model *m, const mote_nb *nb, mote_err *err);
int nb_approaches_write(nb_model *m, mote_err *err);
int nb_time_scale(const nb_model *m, const mote_call *c, double *scale, mote_err *err);
int nb_check_time_unit(nb_model *m, const mote_call *c, mote_err *err);

int nb_opt_on_off(const mote_call *c, const char *key, int dflt);
int nb_check_sampler(void *vm, const mote_call *c, mote_err *err);
int nb_run_monitor(void *vm, const mote_call *c, mote_err *err);
int nb_check_trajectory(void *vm, const mote_call *c, mote_err *err);
int nb_run_trajectory(void *vm, const mote_call *c, mote_err *err);
int nb_check_approaches(void *vm, const mote_call *c, mote_err *err);
int nb_run_approaches(void *vm, const mote_call *c, mote_err *err);
int nb_check_frames(void *vm, const mote_call *c, mote_err *err);
int nb_run_frames(void *vm, const mote_call *c, mote_err *err);
/* The frames' default view (no control file): the whole system from +z, body 1's arrow yellow,
 * the others green; and `picture FILE.png`, drawn with it now. */
void nb_frame_default(const nb_model *m, nb_galctl *g, nb_frame_opts *f);
int nb_picture(void *vm, const char *path, mote_err *err);
int nb_check_snapshot(void *vm, const mote_call *c, mote_err *err);
int nb_run_snapshot(void *vm, const mote_call *c, mote_err *err);
/* the stops of monitor, trajectory, frames, snapshot (and, in files.c, checkpoint) */
int nb_run_monitor_stop(void *vm, const mote_call *c, mote_err *err);
int nb_run_trajectory_stop(void *vm, const mote_call *c, mote_err *err);
int nb_run_frames_stop(void *vm, const mote_call *c, mote_err *err);
int nb_run_snapshot_stop(void *vm, const mote_call *c, mote_err *err);
int nb_check_integrate(void *vm, const mote_call *c, mote_err *err);
int nb_run_integrate(void *vm, const mote_call *c, mote_err *err);

/* ---- files.c ---- */
int nb_write_galactica(nb_model *m, const char *path, int info_line, mote_err *err);
int nb_check_save(void *vm, const mote_call *c, mote_err *err);
int nb_run_save(void *vm, const mote_call *c, mote_err *err);
int nb_check_load(void *vm, const mote_call *c, mote_err *err);
int nb_run_load(void *vm, const mote_call *c, mote_err *err);
int nb_check_restart(void *vm, const mote_call *c, mote_err *err);
int nb_run_restart(void *vm, const mote_call *c, mote_err *err);
int nb_check_checkpoint(void *vm, const mote_call *c, mote_err *err);
int nb_run_checkpoint(void *vm, const mote_call *c, mote_err *err);
int nb_run_checkpoint_stop(void *vm, const mote_call *c, mote_err *err);
int nb_check_write(void *vm, const mote_call *c, mote_err *err);
int nb_run_write(void *vm, const mote_call *c, mote_err *err);
int nb_check_read(void *vm, const mote_call *c, mote_err *err);
int nb_run_read(void *vm, const mote_call *c, mote_err *err);
int nb_check_steps_between(void *vm, const mote_call *c, mote_err *err);
int nb_run_steps_between(void *vm, const mote_call *c, mote_err *err);
int nb_check_run(void *vm, const mote_call *c, mote_err *err);
int nb_run_run(void *vm, const mote_call *c, mote_err *err);
int nb_check_check(void *vm, const mote_call *c, mote_err *err);
int nb_run_check(void *vm, const mote_call *c, mote_err *err);

/* ---- live.c ---- */
int nb_run_live_plane(void *vm, const mote_call *c, mote_err *err);
void nb_model_live(void *vm, mote_buf *b);

#endif
