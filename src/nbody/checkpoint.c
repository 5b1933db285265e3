/* checkpoint.c: a Galactica job's checkpoint (spec 7.10): the job's state, then the system's
 * exact state, written and read through descriptor tables (statefile.h); and the checkpoint's
 * editing program (`mote galactica edit`). The job itself: job.c. */
#include "mote/nbody.h"
#include "mote/statefile.h"

#include <errno.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <tgmath.h>

#include "job.h"
#include "nb.h"

/* ---- the checkpoint (spec 7.10): the job's state, then the system's exact state ----------------- */

/* The job's part of the checkpoint, as its descriptor tables (statefile.h) see it: the values
 * in double, the counts of the tables that follow. */
typedef struct {
    double control[NB_GALCTL_FIXED];
    char fima4[256];
    int ntrio;
    uint64_t Lt, Ltot, nfile, ntfile, nframe;
    uint32_t Nb0;
    int have_amz1;
    uint64_t warned;
    double Em, Tem, Um, AMz1, zoom;
    double head[25];
    double approach[4]; /* dmin, its time, the other body (0-based), the relative speed */
    uint64_t ndice, nrec, wrec;
} ckpt_job;

#define CK(K, NAME, T, M)                                                                    \
    {.key = K, .name = NAME, .type = T, .offset = offsetof(ckpt_job, M), .lo = MOTE_SF_ANY}
#define CKN(K, NAME, M, N)                                                                   \
    {.key = K, .name = NAME, .type = MOTE_SF_DOUBLE, .offset = offsetof(ckpt_job, M),        \
     .count = N, .lo = MOTE_SF_ANY}
/* up to the trios */
static const mote_sf_field CK_CONTROL[] = {
    CKN("control", "v", control, NB_GALCTL_FIXED),
    {.key = "fima4", .name = "NAME", .type = MOTE_SF_WORD, .offset = offsetof(ckpt_job, fima4),
     .size = 256},
    {.key = "trios", .name = "N", .type = MOTE_SF_INT, .offset = offsetof(ckpt_job, ntrio),
     .lo = 0, .hi = NB_GALCTL_TRIOS},
};
/* a trio */
typedef struct {
    int64_t t[3];
} ckpt_trio;
static const mote_sf_field CK_TRIO[] = {
    {.key = "", .name = "k", .type = MOTE_SF_I64, .offset = 0, .count = 3, .lo = MOTE_SF_ANY},
};
/* after the trios, up to the dice rows */
static const mote_sf_field CK_RUN[] = {
    CK("counters", "Lt", MOTE_SF_U64, Lt), CK(NULL, "Ltot", MOTE_SF_U64, Ltot),
    CK(NULL, "files", MOTE_SF_U64, nfile), CK(NULL, "trajectory_files", MOTE_SF_U64, ntfile),
    CK(NULL, "frames", MOTE_SF_U64, nframe), CK(NULL, "Nb", MOTE_SF_U32, Nb0),
    {.name = "have_AMz1", .type = MOTE_SF_INT, .offset = offsetof(ckpt_job, have_amz1), .lo = 0,
     .hi = 1},
    CK(NULL, "warned", MOTE_SF_U64, warned),
    CK("maxima", "Em", MOTE_SF_DOUBLE, Em), CK(NULL, "Tem", MOTE_SF_DOUBLE, Tem),
    CK(NULL, "Um", MOTE_SF_DOUBLE, Um), CK(NULL, "AMz1", MOTE_SF_DOUBLE, AMz1),
    CK(NULL, "zoom", MOTE_SF_DOUBLE, zoom),
    CKN("head", "h", head, 25),
    CKN("approach", "dmin", approach[0], 1), CKN(NULL, "time", approach[1], 1),
    {.name = "body", .type = MOTE_SF_DOUBLE, .offset = offsetof(ckpt_job, approach[2]),
     .lo = 0, .hi = 4294967294.0},
    CKN(NULL, "speed", approach[3], 1),
    CK("dice", "N", MOTE_SF_U64, ndice),
};
static const mote_sf_field CK_DICE[] = {
    {.key = "d", .name = "v", .type = MOTE_SF_DOUBLE, .offset = 0, .count = 4, .lo = MOTE_SF_ANY},
};
static const mote_sf_field CK_RECORDS[] = {
    CK("records", "N", MOTE_SF_U64, nrec), CK(NULL, "WIDTH", MOTE_SF_U64, wrec),
};
#define NF(t) (sizeof t / sizeof t[0])

/* A trajectory record of width w: "r" and w numbers. */
static mote_sf_field record_field(size_t w)
{
    return (mote_sf_field){.key = "r", .name = "v", .type = MOTE_SF_DOUBLE, .offset = 0,
                           .count = (int)w, .lo = MOTE_SF_ANY};
}

int nb_ckpt_write(job *j, mote_err *err)
{
    char p[PATH_CAP];
    mote_afile af;
    int rc = mote_afile_open(&af, nb_job_path(j, j->coulomb ? "galgok2" : "galgon4", p), err);
    if (rc)
        return rc;
    ckpt_job *c = calloc(1, sizeof *c);
    if (!c) {
        mote_afile_abort(&af);
        return mote_fail(err, MOTE_ENOMEM, "galactica: out of memory");
    }
    memcpy(c->control, j->c.v, sizeof c->control);
    snprintf(c->fima4, sizeof c->fima4, "%s", j->c.fima4);
    c->ntrio = j->c.ntrio;
    c->Lt = j->Lt;
    c->Ltot = j->Ltot;
    c->nfile = j->nfile;
    c->ntfile = j->ntfile;
    c->nframe = j->nframe;
    c->Nb0 = j->Nb0;
    c->have_amz1 = j->have_amz1;
    c->warned = j->warned;
    c->Em = j->Em;
    c->Tem = j->Tem;
    c->Um = j->Um;
    c->AMz1 = j->AMz1;
    c->zoom = j->zoom;
    for (int k = 0; k < 25; k++)
        c->head[k] = (double)j->head[k];
    c->approach[0] = (double)j->dice.best;
    c->approach[1] = (double)j->dice.t;
    c->approach[2] = j->dice.with;
    c->approach[3] = (double)j->dice.speed;
    c->ndice = j->dice.nrows;
    c->nrec = j->trn;
    c->wrec = j->trw;
    FILE *f = af.f;
    fprintf(f, "%s %d\nreal %s\n", CKPT_MAGIC, CKPT_VERSION, MOTE_REAL_NAME);
    mote_sf_write(f, CK_CONTROL, NF(CK_CONTROL), c, CKPT_VERSION);
    for (int t = 0; t < j->c.ntrio; t++) {
        ckpt_trio tr = {{j->c.trio[t][0], j->c.trio[t][1], j->c.trio[t][2]}};
        mote_sf_write(f, CK_TRIO, NF(CK_TRIO), &tr, CKPT_VERSION);
    }
    mote_sf_write(f, CK_RUN, NF(CK_RUN), c, CKPT_VERSION);
    for (size_t r = 0; r < j->dice.nrows; r++)
        mote_sf_write(f, CK_DICE, NF(CK_DICE), j->dice.rows + 4 * r, CKPT_VERSION);
    mote_sf_write(f, CK_RECORDS, NF(CK_RECORDS), c, CKPT_VERSION);
    const mote_sf_field rf = record_field(j->trw);
    for (size_t r = 0; r < j->trn; r++)
        mote_sf_write(f, &rf, 1, j->tr + r * j->trw, CKPT_VERSION);
    free(c);
    nb_state_put(f, &j->nb);
    return mote_afile_commit(&af, err);
}

int nb_ckpt_read(job *j, const char *path, mote_err *err)
{
    mote_lines l;
    int rc = mote_lines_open(&l, path, err);
    if (rc)
        return rc;
    ckpt_job *c = calloc(1, sizeof *c);
    if (!c) {
        mote_lines_close(&l, err);
        return mote_fail(err, MOTE_ENOMEM, "galactica: out of memory");
    }
    const char *what = NULL;
    char *s = mote_lines_next(&l);
    int version = 0;
    char real[32] = "";
    if (!s || sscanf(s, CKPT_MAGIC " %d", &version) != 1 || version != CKPT_VERSION)
        what = "'" CKPT_MAGIC " 1' (a checkpoint of this version of mote)";
    else if (!(s = mote_lines_next(&l)) || sscanf(s, "real %31[a-z ]", real) != 1 ||
             strcmp(real, MOTE_REAL_NAME) != 0)
        what = "'real " MOTE_REAL_NAME "' (a checkpoint of a build with this precision)";
    if (!what)
        rc = mote_sf_read(&l, CK_CONTROL, NF(CK_CONTROL), c, version, err);
    for (int t = 0; t < c->ntrio && !what && !rc; t++) {
        ckpt_trio tr;
        rc = mote_sf_read(&l, CK_TRIO, NF(CK_TRIO), &tr, version, err);
        for (int a = 0; a < 3; a++)
            j->c.trio[t][a] = (long)tr.t[a];
    }
    if (!what && !rc) {
        memcpy(j->c.v, c->control, sizeof j->c.v);
        snprintf(j->c.fima4, sizeof j->c.fima4, "%s", c->fima4);
        j->c.ntrio = c->ntrio;
        if ((rc = nb_job_setup(j, path, 0, err)) == MOTE_OK)
            rc = mote_sf_read(&l, CK_RUN, NF(CK_RUN), c, version, err);
    }
    if (!what && !rc && !(c->Lt <= c->Ltot && c->Ltot <= 9000000000000000000ull))
        what = "counters with Lt <= Ltot <= 9e18";
    if (!what && !rc) {
        j->Lt = c->Lt;
        j->Ltot = c->Ltot;
        j->nfile = c->nfile;
        j->ntfile = c->ntfile;
        j->nframe = c->nframe;
        j->Nb0 = c->Nb0;
        j->have_amz1 = c->have_amz1;
        j->warned = c->warned;
        j->Em = c->Em;
        j->Tem = c->Tem;
        j->Um = c->Um;
        j->AMz1 = c->AMz1;
        j->zoom = c->zoom > 0 && c->zoom <= 1 ? c->zoom : 1;
        for (int k = 0; k < 25; k++)
            j->head[k] = c->head[k];
        j->dice.best = (mote_real)c->approach[0];
        j->dice.t = (mote_real)c->approach[1];
        j->dice.with = (uint32_t)c->approach[2];
        j->dice.speed = (mote_real)c->approach[3];
    }
    for (uint64_t r = 0; r < c->ndice && !what && !rc; r++) { /* (counted as read) */
        double d[4];
        rc = mote_sf_read(&l, CK_DICE, NF(CK_DICE), d, version, err);
        if (!rc)
            rc = nb_approach_push(&j->dice, d, err);
    }
    if (!what && !rc)
        rc = mote_sf_read(&l, CK_RECORDS, NF(CK_RECORDS), c, version, err);
    if (!what && !rc && c->nrec > 0 && (c->wrec != j->trw || c->nrec > j->trcap))
        what = "'records N WIDTH' matching the control values (Klmax, Np, Kl15)";
    const mote_sf_field rf = record_field(j->trw);
    for (uint64_t r = 0; r < c->nrec && !what && !rc; r++)
        rc = mote_sf_read(&l, &rf, 1, j->tr + r * j->trw, version, err);
    if (!what && !rc)
        j->trn = (size_t)c->nrec;
    free(c);
    if (!what && !rc)
        rc = nb_state_get(&j->nb, &l, 0, err);
    if (what && !rc)
        rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: expected %s", path, l.line, what);
    int crc = mote_lines_close(&l, err);
    return crc ? crc : rc;
}


/* ---- checkpoint edit (spec 7.10): the separate editing program of the document --------------- */

static const char *const EDITABLE[] = {"Ltk", "Ltk2", "Kl3", "Kl7", "Kl12", "Kli", "Nbd", "dT"};

int mote_nb_job_edit(const mote_nb_job *o, int nedit, char *const *edits, mote_err *err)
{
    job J;
    memset(&J, 0, sizeof J);
    job *j = &J;
    j->o = o;
    j->coulomb = o->coulomb;
    nb_approach_init(&j->dice, 0, 0, NULL);
    j->zoom = 1;
    int rc = nb_job_dir(j, o->control, err);
    if (rc)
        return rc;
    mote_nb_init(&j->nb, o->coulomb ? MOTE_NB_COULOMB : MOTE_NB_GRAVITY);
    char ck[PATH_CAP];
    nb_job_path(j, o->coulomb ? "galgok2" : "galgon4", ck);
    rc = nb_ckpt_read(j, ck, err);
    int plan_changed = 0;
    for (int k = 0; k < nedit && !rc; k++) {
        const char *eq = strchr(edits[k], '=');
        size_t len = eq ? (size_t)(eq - edits[k]) : 0;
        int which = -1;
        for (int q = 0; q < 8 && eq; q++)
            if (strlen(EDITABLE[q]) == len && strncmp(edits[k], EDITABLE[q], len) == 0)
                which = q;
        char *end = NULL;
        const double v = eq ? strtod(eq + 1, &end) : 0;
        if (which < 0 || end == eq + 1 || *end || !isfinite(v))
            rc = mote_fail(err, MOTE_EINVAL, "galactica edit: '%s': expected KEY=VALUE with KEY "
                           "one of Ltk Ltk2 Kl3 Kl7 Kl12 Kli Nbd dT", edits[k]);
        else if (which == 7 && !(v > 0))
            rc = mote_fail(err, MOTE_EINVAL, "galactica edit: dT=%g, expected a step > 0", v);
        else if (which < 7 && v != floor(v))
            rc = mote_fail(err, MOTE_EINVAL, "galactica edit: %s=%g, expected an integer",
                           EDITABLE[which], v);
        else if (which == 7)
            j->nb.dt = (mote_real)v;
        else {
            j->c.v[nb_galctl_index(EDITABLE[which])] = v;
            plan_changed |= which < 2;
        }
    }
    if (!rc) /* the values as a first launch would check them, then the bodies they name */
        rc = nb_job_setup(j, ck, 0, err);
    if (!rc)
        rc = nb_job_check_selection(j, ck, 0, err);
    if (!rc && plan_changed) /* the next launch runs Ltk * Ltk2 steps from here */
        j->Ltot = j->Lt + (uint64_t)nb_job_ci(j, "Ltk") * (uint64_t)nb_job_ci(j, "Ltk2");
    if (!rc && j->trn > j->trcap)
        rc = mote_fail(err, MOTE_EINVAL, "galactica edit: the checkpoint holds %zu trajectory "
                       "records, more than Klmax", j->trn);
    if (!rc)
        rc = nb_ckpt_write(j, err);
    if (!rc)
        nb_job_say(j, "galactica edit: %s now plans steps %llu to %llu, dT = %.16E\n", ck,
            (unsigned long long)j->Lt, (unsigned long long)j->Ltot, (double)j->nb.dt);
    nb_job_free(j);
    return rc;
}
