/* job.h: a Galactica job's state and the helpers its two files share (job.c runs the job,
 * checkpoint.c writes, reads and edits its checkpoint). Private to src/nbody. */
#ifndef MOTE_NBODY_JOB_H
#define MOTE_NBODY_JOB_H

#include "mote/nbody.h"
#include "mote/command.h"

#include "nb.h"

#define CKPT_MAGIC "mote-galactica-checkpoint"
#define CKPT_VERSION 1
#define PATH_CAP 4096

typedef struct {
    const mote_nb_job *o;
    char dir[PATH_CAP - 512]; /* the folder of the control file, with its '/' (or "") */
    nb_galctl c;
    int coulomb;
    mote_nb nb;
    mote_real head[25];  /* the header carried into result files (area fields, Em) */
    uint64_t Lt, Ltot;   /* steps done and planned, across cycles and relaunches */
    uint64_t nfile, ntfile, nframe; /* result files 1, 2, ...; trajectory files 1t, ...; frames */
    /* the trajectory buffer: Klmax records of `trw` numbers */
    double *tr;
    size_t trw, trn, trcap;
    /* dice.dat: the closest approaches of body Nbd, sampled at step ends (approach.c) */
    nb_approach dice;
    /* run maxima and references (the trajectory summary) */
    double Em, Tem, Um, AMz1, zoom;
    uint32_t Nb0;
    int have_amz1;
    uint64_t warned;     /* approach warnings already reported */
    int dry;             /* a check: nothing written, ErrGlctca included */
    mote_progress *prog; /* while the steps run */
} job;

/* PATH: the job folder's NAME */
const char *nb_job_path(const job *j, const char *name, char buf[PATH_CAP]);
/* a line on the terminal (nothing in a check) */
void nb_job_say(const job *j, const char *fmt, ...);
long nb_job_ci(const job *j, const char *name);
/* the control values checked and applied (src: the file they came from) */
int nb_job_setup(job *j, const char *src, int from_ctl, mote_err *err);
int nb_job_check_selection(job *j, const char *src, int from_ctl, mote_err *err);
void nb_job_free(job *j);
/* the folder of the control file */
int nb_job_dir(job *j, const char *control, mote_err *err);
int nb_ckpt_write(job *j, mote_err *err);
int nb_ckpt_read(job *j, const char *path, mote_err *err);

#endif
