/* model.h: the mixing-box model's command state (commands.c: the table, parameters, runs;
 * outputs.c: the outputs' commands). */
#ifndef MB_MODEL_H
#define MB_MODEL_H

#include "mb.h"

typedef struct {
    mote_mb sys;
    mote_mb_params p;  /* the parameters as the commands so far have set them */
    int dry;
    mote_context *ctx;
    FILE *log;         /* ctx->out when running, NULL when validating */
    int set_line[MB_P_NGROUPS]; /* script line that last set each parameter group, 0 = default */

    /* validation state */
    int d_placed;
    int d_place_line;
    int64_t d_n; /* disks the last place puts */
    double d_record_dt, d_density_dt, d_frames_dt, d_snaps_dt, d_traj_dt; /* 0 = not active */

    /* samplers kept across runs */
    mb_record rec;
    mb_density dens;
    mb_frames frames, snaps; /* pictures; snapshots (xyz) on a schedule */
    mb_trajectory traj;
    struct {
        int active;
        char *path; /* the state, replaced at each checkpoint */
    } ckpt;
    mote_observer rec_s, dens_s, frames_s, snaps_s, traj_s, ckpt_s;
    mote_schedule rec_at, dens_at, frames_at, snaps_at, traj_at, ckpt_at; /* theirs */
} mb_model;

/* A located error unless disks are placed (the commands that need a system). */
int mb_need_placed(mb_model *m, const mote_call *c, mote_err *err);

/* outputs.c: monitor (record), density_y, snapshot, frames, trajectory, their stops, movie */
int mb_check_record(void *vm, const mote_call *c, mote_err *err);
int mb_run_record(void *vm, const mote_call *c, mote_err *err);
int mb_check_checkpoint(void *vm, const mote_call *c, mote_err *err);
int mb_run_checkpoint(void *vm, const mote_call *c, mote_err *err);
int mb_run_checkpoint_stop(void *vm, const mote_call *c, mote_err *err);
int mb_check_record_stop(void *vm, const mote_call *c, mote_err *err);
int mb_run_record_stop(void *vm, const mote_call *c, mote_err *err);
int mb_check_density(void *vm, const mote_call *c, mote_err *err);
int mb_run_density(void *vm, const mote_call *c, mote_err *err);
int mb_check_snapshot(void *vm, const mote_call *c, mote_err *err);
int mb_run_snapshot(void *vm, const mote_call *c, mote_err *err);
int mb_check_frames(void *vm, const mote_call *c, mote_err *err);
int mb_run_frames(void *vm, const mote_call *c, mote_err *err);
int mb_check_trajectory(void *vm, const mote_call *c, mote_err *err);
int mb_run_trajectory(void *vm, const mote_call *c, mote_err *err);
int mb_check_trajectory_stop(void *vm, const mote_call *c, mote_err *err);
int mb_run_trajectory_stop(void *vm, const mote_call *c, mote_err *err);
int mb_check_snapshot_stop(void *vm, const mote_call *c, mote_err *err);
int mb_run_snapshot_stop(void *vm, const mote_call *c, mote_err *err);
int mb_check_frames_stop(void *vm, const mote_call *c, mote_err *err);
int mb_run_frames_stop(void *vm, const mote_call *c, mote_err *err);
int mb_check_movie(void *vm, const mote_call *c, mote_err *err);
int mb_run_movie(void *vm, const mote_call *c, mote_err *err);

#endif
