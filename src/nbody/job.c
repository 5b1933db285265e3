/* job.c: a Galactica job (spec 7): the control file galacf26.dat of a folder decides where the
 * bodies come from (Kl1: the area, garez28.dat, the file FIMA4, with or without checkpoints), how
 * time and the step run (Kl4), how many steps (Ltk cycles of Ltk2... Ltk * Ltk2), and what is
 * written: the monitor block every Kl3 steps (7.12), the result files 1, 2, ... (7.7), the
 * trajectory files 1t, 2t, ... traekt.prn (7.8), dice.dat (7.9), the checkpoint galgon4 (7.10),
 * pictures (7.13), and always garez28.dat at the end (Coulomb: garek29.dat, galgok2). Errors go
 * to the caller and are appended to ErrGlctca with Galactica's "*nnG" codes (7.11). Everything is
 * checked, and the number of files counted, before the first file is written; every file is
 * written atomically, so a failed launch leaves the folder's earlier files as they were. */
#include "mote/loop.h"
#include "mote/nbody.h"
#include "mote/statefile.h"

#include <errno.h>
#include <stddef.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <tgmath.h>
#include <unistd.h>

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

/* ---- paths, messages, ErrGlctca ----------------------------------------------------------------- */

static const char *jpath(const job *j, const char *name, char buf[PATH_CAP])
{
    const size_t a = strlen(j->dir);
    size_t b = strlen(name);
    if (a + b + 1 > PATH_CAP) /* (cannot happen: the folder's and the names' lengths are bounded) */
        b = 0;
    memcpy(buf, j->dir, a);
    memcpy(buf + a, name, b);
    buf[a + b] = '\0';
    return buf;
}

static void say(const job *j, const char *fmt, ...)
{
    if (!j->o->out)
        return;
    va_list ap;
    va_start(ap, fmt);
    vfprintf(j->o->out, fmt, ap);
    va_end(ap);
}

/* Append "*nnG message" to ErrGlctca (best effort: the message also goes to the caller). */
static void errfile(const job *j, int code, const char *msg)
{
    if (j->dry || nb_mpi_rank() != 0) /* (MPI: every rank has the message; rank 0 keeps it) */
        return;
    char p[PATH_CAP];
    FILE *f = fopen(jpath(j, "ErrGlctca", p), "a");
    if (!f)
        return;
    fprintf(f, "*%02dG %s\n", code, msg);
    fclose(f);
}

/* The Galactica code of a failure: 01 a file could not be opened or written, 02 a read error
 * (a malformed file or value), 12 the output volume. */
static int fail_code(int rc) { return rc == MOTE_EIO ? 1 : 2; }

static int jfail(const job *j, int code, mote_err *err, int rc)
{
    errfile(j, code ? code : fail_code(rc), err->msg);
    return rc;
}

/* A bad control value: named with the control file's line, or the checkpoint it came from. */
static int ctl_fail(const job *j, const char *src, int from_ctl, mote_err *err, const char *name,
                    const char *fmt, ...)
{
    char why[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    if (from_ctl)
        mote_fail(err, MOTE_EFORMAT, "%s:%d: %s %s", src, nb_galctl_index(name) + 1, name, why);
    else
        mote_fail(err, MOTE_EFORMAT, "%s: the control value %s %s", src, name, why);
    return jfail(j, 2, err, MOTE_EFORMAT);
}

static double cv(const job *j, const char *name) { return nb_galctl_get(&j->c, name); }
/* an integer value (the control file's reader admits only integers within +-9.2e18; a value
 * from a damaged checkpoint beyond that is clamped, and then refused by the checks) */
static long ci(const job *j, const char *name)
{
    const double v = cv(j, name);
    return v >= 9e18 ? 9000000000000000000L : v <= -9e18 ? -9000000000000000000L : (long)v;
}

/* Check the control values that do not depend on the bodies, and size the trajectory buffer. */
static int setup(job *j, const char *src, int from_ctl, mote_err *err)
{
    static const char *const keys[] = {"Kl7", "Kl12", "Kl15", "Kl10", "Kl14"};
    const long kl1 = ci(j, "Kl1"), kl4 = ci(j, "Kl4");
    if (kl1 < 0 || kl1 > 4)
        return ctl_fail(j, src, from_ctl, err, "Kl1", "= %ld, expected 0 (area), 1 (%s), 2 "
                        "(FIMA4), 3 or 4 (as 1 or 2, with checkpoints)", kl1,
                        j->coulomb ? "garek29.dat" : "garez28.dat");
    if (kl4 < 0 || kl4 > 3)
        return ctl_fail(j, src, from_ctl, err, "Kl4", "= %ld, expected 0, 1, 2 or 3", kl4);
    const char *pos[] = {"Ltk", "Ltk2", "Kl3"};
    for (int k = 0; k < 3; k++)
        if (ci(j, pos[k]) < 1)
            return ctl_fail(j, src, from_ctl, err, pos[k], "= %ld, expected at least 1",
                            ci(j, pos[k]));
    if ((double)ci(j, "Ltk") * (double)ci(j, "Ltk2") > 9e18)
        return ctl_fail(j, src, from_ctl, err, "Ltk2", "makes Ltk * Ltk2 beyond 9e18 steps");
    for (int k = 0; k < 5; k++)
        if (ci(j, keys[k]) != 0 && ci(j, keys[k]) != 1)
            return ctl_fail(j, src, from_ctl, err, keys[k], "= %ld, expected 0 or 1",
                            ci(j, keys[k]));
    if (ci(j, "Kl11") < 0)
        return ctl_fail(j, src, from_ctl, err, "Kl11", "= %ld, expected 0 (off) or a step",
                        ci(j, "Kl11"));
    const double bt = cv(j, "bt");
    if (!(bt >= 0 && bt <= 1))
        return ctl_fail(j, src, from_ctl, err, "bt", "= %g, expected 0 < bt <= 1 (0: no "
                        "shortening)", bt);
    if (kl1 == 0) {
        if (j->coulomb)
            return ctl_fail(j, src, from_ctl, err, "Kl1", "= 0 (the area) is a gravity mode: "
                            "Galactica's Coulomb module has no area");
        if (cv(j, "Ro0") != 1)
            return ctl_fail(j, src, from_ctl, err, "Ro0", "= %g, expected 1 (the area's "
                            "relative density)", cv(j, "Ro0"));
        if (!(cv(j, "dt") > 0))
            return ctl_fail(j, src, from_ctl, err, "dt", "= %g, expected a step > 0 for Kl1 = 0",
                            cv(j, "dt"));
        if (ci(j, "Mu") < 1)
            return ctl_fail(j, src, from_ctl, err, "Mu", "= %ld, expected at least 1",
                            ci(j, "Mu"));
        const char *pp[] = {"B", "C", "Roa"};
        for (int k = 0; k < 3; k++)
            if (!(cv(j, pp[k]) > 0))
                return ctl_fail(j, src, from_ctl, err, pp[k], "= %g, expected > 0", cv(j, pp[k]));
        if (!(cv(j, "Rob") >= 0) || !(cv(j, "RoS") >= 0))
            return ctl_fail(j, src, from_ctl, err, cv(j, "Rob") >= 0 ? "RoS" : "Rob",
                            "is negative");
    } else if (ci(j, "k2") < 1 || ci(j, "k2") > 100000000) {
        return ctl_fail(j, src, from_ctl, err, "k2", "= %ld, expected the number of bodies "
                        "(1 ... 10^8)", ci(j, "k2"));
    }
    if ((kl1 == 2 || kl1 == 4) && !j->c.fima4[0])
        return ctl_fail(j, src, from_ctl, err, "FIMA4", "is empty: Kl1 = %ld reads the bodies "
                        "from the file it names", kl1);
    j->trw = 0;
    if (ci(j, "Kl12") == 1) {
        const long np = ci(j, "Np");
        if (ci(j, "Kli") < 1)
            return ctl_fail(j, src, from_ctl, err, "Kli", "= %ld, expected at least 1 step "
                            "between trajectory records", ci(j, "Kli"));
        if (np < 1 || np > j->c.ntrio)
            return ctl_fail(j, src, from_ctl, err, "Np", "= %ld, expected 1 ... %d (the trios "
                            "ipp, jpp, kpp given from line 51)", np, j->c.ntrio);
        j->trw = (size_t)(3 * (ci(j, "Kl15") + 1) * np + 2);
        const long kmax = ci(j, "Klmax");
        if (kmax < 1 || (double)kmax * (double)j->trw > 1.3e8)
            return ctl_fail(j, src, from_ctl, err, "Klmax", "= %ld, expected 1 ... %.0f "
                            "(records of %zu numbers in memory)", kmax, 1.3e8 / (double)j->trw,
                            j->trw);
        j->trcap = (size_t)kmax;
        double *tr = realloc(j->tr, j->trcap * j->trw * sizeof *j->tr); /* (records kept) */
        if (tr)
            j->tr = tr;
        if (!tr)
            return jfail(j, 2, err, mote_fail(err, MOTE_ENOMEM, "galactica: out of memory for "
                                              "%zu trajectory records", j->trcap));
    }
    return MOTE_OK;
}

/* The checks that need the bodies: selected bodies and Nbd within 1 ... N. */
static int check_selection(job *j, const char *src, int from_ctl, mote_err *err)
{
    const long n = (long)j->nb.n;
    if (ci(j, "Nbd") < 0 || ci(j, "Nbd") > n)
        return ctl_fail(j, src, from_ctl, err, "Nbd", "= %ld, expected 0 (off) or a body 1 ... "
                        "%ld", ci(j, "Nbd"), n);
    for (long t = 0; t < (ci(j, "Kl12") == 1 ? ci(j, "Np") : 0); t++)
        if (j->c.trio[t][2] < 1 || j->c.trio[t][2] > n)
            return jfail(j, 2, err, mote_fail(err, MOTE_EFORMAT, "%s: kpp(%ld) = %ld (the body "
                                              "of trajectory column %ld), expected 1 ... %ld",
                                              src, t + 1, j->c.trio[t][2], t + 1, n));
    return MOTE_OK;
}

/* ---- measures of the state -------------------------------------------------------------------- */

/* Kinetic energy, largest speed and mass (active bodies), z moment (orbital) in O(N). */
static void quick_measure(const mote_nb *nb, double *ekin, double *vmax, double *mmax, double *mz)
{
    nb_ksum e = {0, 0}, l = {0, 0};
    mote_real v2max = 0, mm = 0;
    for (uint32_t i = 0; i < nb->n; i++) {
        const mote_real *x = nb->x + 3 * i, *v = nb->v + 3 * i, m = nb->m[i];
        const mote_real v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        nb_ksum_add(&e, m * v2 / 2);
        nb_ksum_add(&l, m * (x[0] * v[1] - x[1] * v[0]));
        if (nb->active[i]) {
            v2max = v2 > v2max ? v2 : v2max;
            mm = m > mm ? m : mm;
        }
    }
    *ekin = (double)nb_ksum_value(&e);
    *vmax = (double)sqrt(v2max);
    *mmax = (double)mm;
    *mz = (double)nb_ksum_value(&l);
}

/* ---- the run's outputs ------------------------------------------------------------------------ */

/* The 19 quantities of Galactica's screen (spec 7.12), three to a line. */
static void monitor_block(job *j)
{
    FILE *f = j->o->out;
    if (!f)
        return;
    const mote_nb *nb = &j->nb;
    mote_nb_monitor mon;
    mote_nb_measure(nb, &mon);
    double ek, vmax, mmax, mz;
    quick_measure(nb, &ek, &vmax, &mmax, &mz);
    const double v[19] = {(double)nb->T, mmax, vmax, (double)nb->hlast,
                          (double)mon.P[0], (double)mon.P[1], (double)mon.P[2],
                          (double)mon.L[0], (double)mon.L[1], (double)mon.L[2],
                          (double)mon.S[0], (double)mon.S[1], (double)mon.S[2],
                          (double)mon.ekin, j->Em, (double)nb->e_heat, (double)j->Lt,
                          (double)nb->dt, (double)mon.dMz};
    fputc('\n', f);
    for (int k = 0; k < 19; k++) {
        if (k == 16)
            fprintf(f, "%23llu", (unsigned long long)j->Lt);
        else
            fprintf(f, "%24.15E", v[k]);
        fputc(k % 3 == 2 || k == 18 ? '\n' : ' ', f);
    }
    fflush(f);
}

static int result_file(job *j, const char *name, mote_err *err)
{
    nb_galfile g;
    const size_t W = j->coulomb ? 16 : 15;
    mote_real *body = malloc(W * (j->nb.n ? j->nb.n : 1) * sizeof *body);
    if (!body)
        return mote_fail(err, MOTE_ENOMEM, "galactica: out of memory for %s", name);
    j->head[14] = (mote_real)j->Em;
    nb_to_galfile(&j->nb, j->head, &g, body);
    char p[PATH_CAP];
    int rc = nb_galfile_write(jpath(j, name, p), &g, 1, err);
    free(body);
    return rc;
}

/* A trajectory file: the records, one a line, then (traekt.prn) the ten-number summary. */
static int trajectory_file(job *j, const char *name, int summary, mote_err *err)
{
    char p[PATH_CAP];
    mote_afile af;
    int rc = mote_afile_open(&af, jpath(j, name, p), err);
    if (rc)
        return rc;
    for (size_t r = 0; r < j->trn; r++) {
        for (size_t k = 0; k < j->trw; k++)
            fprintf(af.f, "%s%.16E", k ? "  " : "", j->tr[r * j->trw + k]);
        fputc('\n', af.f);
    }
    if (summary) {
        double ek, vmax, mmax, mz;
        quick_measure(&j->nb, &ek, &vmax, &mmax, &mz);
        const double s[10] = {(double)j->nb.T, j->Tem, j->Em, (double)j->nb.e_heat, j->AMz1,
                              (double)j->Nb0, (double)j->nb.merges, j->Um, mmax, mz};
        for (int k = 0; k < 10; k++)
            fprintf(af.f, "%s%.16E", k ? "  " : "", s[k]);
        fputc('\n', af.f);
    }
    return mote_afile_commit(&af, err);
}

static int trajectory_record(job *j, mote_err *err)
{
    const long np = ci(j, "Np"), vel = ci(j, "Kl15") == 1;
    double ek, vmax, mmax, mz;
    quick_measure(&j->nb, &ek, &vmax, &mmax, &mz);
    double *r = j->tr + j->trn * j->trw;
    r[0] = (double)j->nb.T;
    r[1] = ek;
    size_t k = 2;
    for (long b = 0; b < np; b++) {
        const uint32_t i = (uint32_t)(j->c.trio[b][2] - 1);
        for (int a = 0; a < 3; a++)
            r[k++] = (double)j->nb.x[3 * i + (uint32_t)a];
        if (vel)
            for (int a = 0; a < 3; a++)
                r[k++] = (double)j->nb.v[3 * i + (uint32_t)a];
    }
    if (++j->trn < j->trcap)
        return MOTE_OK;
    char name[32];
    snprintf(name, sizeof name, "%llut", (unsigned long long)(j->ntfile + 1));
    int rc = trajectory_file(j, name, 0, err);
    if (!rc) {
        j->ntfile++;
        j->trn = 0;
    }
    return rc;
}

static int dice_file(job *j, mote_err *err)
{
    char p[PATH_CAP];
    mote_afile af;
    int rc = mote_afile_open(&af, jpath(j, "dice.dat", p), err);
    if (rc)
        return rc;
    for (size_t r = 0; r < j->dice.nrows; r++) /* time, body, distance */
        fprintf(af.f, "%.16E  %.0f  %.16E\n", j->dice.rows[4 * r], j->dice.rows[4 * r + 1],
                j->dice.rows[4 * r + 2]);
    return mote_afile_commit(&af, err);
}

/* ---- pictures (spec 7.13, frames.c) ------------------------------------------------------------ */

static int frame(job *j, mote_err *err)
{
    nb_frame_opts f;
    nb_frame_from_ctl(&f, &j->c, j->head);
    f.zoom = j->zoom;
    char name[64], p[PATH_CAP];
    snprintf(name, sizeof name, "frame_%06llu.png", (unsigned long long)j->nframe);
    int rc = nb_frame_png(&j->nb, &f, jpath(j, name, p), j->Lt, err);
    j->zoom = f.zoom;
    j->nframe += !rc;
    return rc;
}

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

static int ckpt_write(job *j, mote_err *err)
{
    char p[PATH_CAP];
    mote_afile af;
    int rc = mote_afile_open(&af, jpath(j, j->coulomb ? "galgok2" : "galgon4", p), err);
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

static int ckpt_read(job *j, const char *path, mote_err *err)
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
        if ((rc = setup(j, path, 0, err)) == MOTE_OK)
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

/* ---- the job ---------------------------------------------------------------------------------- */

/* The bodies, time and step of a first launch (spec 7.4). */
static int load_bodies(job *j, mote_err *err)
{
    const long kl1 = ci(j, "Kl1"), kl4 = ci(j, "Kl4");
    mote_nb *nb = &j->nb;
    int rc;
    memset(j->head, 0, sizeof j->head);
    if (kl1 == 0) {
        mote_nb_area a;
        mote_nb_area_defaults(&a);
        a.B = cv(j, "B");
        a.C = cv(j, "C");
        a.X0[0] = cv(j, "X0");
        a.X0[1] = cv(j, "Y0");
        a.X0[2] = cv(j, "Z0");
        a.Mu = (int)ci(j, "Mu");
        a.RoS = cv(j, "RoS");
        const char *sx[6] = {"Xs", "Ys", "Zs", "Us", "Vs", "Ws"};
        for (int k = 0; k < 3; k++) {
            a.Xs[k] = cv(j, sx[k]);
            a.Us[k] = cv(j, sx[3 + k]);
        }
        a.wu = cv(j, "wu");
        a.X01 = cv(j, "X01");
        a.Y01 = cv(j, "Y01");
        a.Roa = cv(j, "Roa");
        a.Rob = cv(j, "Rob");
        a.dt = cv(j, "dt");
        rc = mote_nb_area_build(nb, &a, err);
        if (rc)
            return jfail(j, 2, err, rc);
        const double h[7] = {a.nx, a.ny, a.nz, 1, a.B, a.C, a.Mu};
        for (int k = 0; k < 7; k++)
            j->head[17 + k] = h[k];
        say(j, "galactica: the area, %d x %d x %d bodies%s\n", a.nx, a.ny, a.nz,
            a.sep_added ? " and the separate body"
            : a.RoS > 0 ? " (the separate body is closer than 1/Mu to a node: not added)" : "");
    } else {
        char p[PATH_CAP];
        const char *path = kl1 == 1 || kl1 == 3
                               ? jpath(j, j->coulomb ? "garek29.dat" : "garez28.dat", p)
                               : jpath(j, j->c.fima4, p);
        if (j->c.fima4_long && (kl1 == 2 || kl1 == 4))
            say(j, "galactica: warning: FIMA4 '%s' is longer than Galactica's 12 characters\n",
                j->c.fima4);
        nb_galfile g;
        rc = nb_galfile_read(path, j->coulomb, ci(j, "k2"), &g, err);
        if (rc)
            return jfail(j, fail_code(rc), err, rc);
        /* masses: fractions of the total (spec 7.1): else the other layout is likely */
        const size_t W = j->coulomb ? 16 : 15;
        nb_ksum sum = {0, 0};
        int bad = 0;
        for (uint32_t i = 0; i < g.n; i++) {
            const mote_real m = g.body[W * i];
            bad |= !(m >= 0 && m <= 1);
            nb_ksum_add(&sum, m);
        }
        const mote_real total = nb_ksum_value(&sum);
        if (bad || !(fabs((double)(total - 1)) <= 1e-12)) {
            rc = mote_fail(err, MOTE_EFORMAT, "%s: the %ld masses do not look like fractions of "
                           "the total (each in [0, 1], sum %.17g instead of 1): is it a %s file? "
                           "(%s)", path, ci(j, "k2"), (double)total,
                           j->coulomb ? "gravity (24/15 layout)" : "Coulomb (25/16 layout)",
                           j->coulomb ? "drop --coulomb" : "use --coulomb or interaction=coulomb");
            nb_galfile_free(&g);
            return jfail(j, 2, err, rc);
        }
        if (!(g.head[16] > 0)) {
            rc = mote_fail(err, MOTE_EFORMAT, "%s: the step dT (header number 17) is %g, "
                           "expected > 0", path, (double)g.head[16]);
            nb_galfile_free(&g);
            return jfail(j, 2, err, rc);
        }
        rc = nb_from_galfile(nb, &g, path, err);
        if (!rc)
            nb_units_from_info(nb, &g);
        for (int k = 0; k < 25; k++)
            j->head[k] = g.head[k];
        nb_galfile_free(&g);
        if (rc)
            return jfail(j, 2, err, rc);
        if (kl1 == 2 || kl1 == 4) { /* a fresh start: the first step is 0.001 dT */
            nb->restart = 1;
            nb->dtp = 0;
        }
        say(j, "galactica: %u bodies from %s, T0 = %.16E, dT = %.16E\n", nb->n, path,
            (double)nb->T, (double)nb->dt);
    }
    if (kl4 == 0 || kl4 == 2)
        nb->T = nb->Tc = 0;
    nb->integrator = MOTE_NB_GALACTICA;
    nb->order = 6;
    if (kl4 >= 2) { /* step correction: the adaptive control of spec 4.5 (decision, 7.4) */
        nb->adaptive = 1;
        nb->tol = j->o->step_tol > 0 ? (mote_real)j->o->step_tol : MOTE_REAL_TOL;
        nb->hmax = 16 * nb->dt;
    }
    nb->bt = cv(j, "bt") > 0 ? (mote_real)cv(j, "bt") : 1;
    return MOTE_OK;
}

/* Count what the run will write, print it, and refuse above the limit (spec 7.4). */
static int plan(job *j, mote_err *err)
{
    const uint64_t L0 = j->Lt, L1 = j->Ltot, kl3 = (uint64_t)ci(j, "Kl3");
    const double n = j->nb.n;
    double files = 1, bytes = (n + 3) * 15 * 25;
    if (ci(j, "Kl7") == 1) {
        files += (double)(L1 / kl3 - L0 / kl3);
        bytes += (double)(L1 / kl3 - L0 / kl3) * (n + 3) * 15 * 25;
    }
    if (ci(j, "Kl12") == 1) {
        const uint64_t kli = (uint64_t)ci(j, "Kli");
        const double rec = (double)(L1 / kli - L0 / kli) + (double)j->trn;
        files += floor(rec / (double)j->trcap) + 1;
        bytes += rec * (double)j->trw * 25;
    }
    if (j->o->frames) {
        const double f = (double)((L1 - L0) / kl3) + 2 + (ci(j, "Kl11") > 0 ? 10 : 0);
        files += f;
        bytes += f * 30000;
    }
    files += (ci(j, "Nbd") > 0) + (ci(j, "Kl1") >= 3);
    const long limit = j->o->max_files > 0 ? j->o->max_files : 10000;
    say(j, "galactica: %llu steps (Lt %llu to %llu), about %.0f files, %.3g MB\n",
        (unsigned long long)(L1 - L0), (unsigned long long)L0, (unsigned long long)L1, files,
        bytes / 1e6);
    if (files > (double)limit && !j->o->force) {
        mote_fail(err, MOTE_EINVAL, "galactica: the job would write about %.0f files, above the "
                  "limit of %ld: raise Kl3 or Kli or Klmax, or force it (--force, force=on)",
                  files, limit);
        return jfail(j, 12, err, MOTE_EINVAL);
    }
    return MOTE_OK;
}

/* After step Lt: the run maxima and the approaches of body Nbd, every step. */
static void after_step(job *j)
{
    double ek, vmax, mmax, mz;
    quick_measure(&j->nb, &ek, &vmax, &mmax, &mz);
    if (ek > j->Em) {
        j->Em = ek;
        j->Tem = (double)j->nb.T;
    }
    j->Um = vmax > j->Um ? vmax : j->Um;
    if (!j->have_amz1) {
        j->AMz1 = mz;
        j->have_amz1 = 1;
    }
    if (ci(j, "Nbd") > 0) {
        j->dice.body = (uint32_t)(ci(j, "Nbd") - 1); /* (Nbd may have been edited) */
        nb_approach_after(&j->dice, &j->nb, j->nb.T, 0);
    }
}

/* The monitor block (and with frames on, a picture). */
static int show(job *j, mote_err *err)
{
    if (j->prog)
        mote_progress_clear(j->prog); /* (the block starts on a clean line) */
    monitor_block(j);
    return j->o->frames ? frame(j, err) : MOTE_OK;
}

static int fire_record(void *ctx, void *subject, mote_err *err)
{
    int rc = trajectory_record(ctx, err);
    return rc ? jfail(ctx, fail_code(rc), err, rc) : MOTE_OK;
}
static int fire_stage(void *ctx, void *subject, mote_err *err)
{
    job *j = ctx;
    int rc = show(j, err);
    if (!rc && ci(j, "Nbd") > 0)
        rc = nb_approach_close(&j->dice, j->nb.T, err);
    if (!rc && ci(j, "Kl7") == 1) {
        char name[32];
        snprintf(name, sizeof name, "%llu", (unsigned long long)(j->nfile + 1));
        rc = result_file(j, name, err);
        j->nfile += !rc;
    }
    if (!rc && ci(j, "Kl1") >= 3 && j->Lt < j->Ltot) {
        if (ci(j, "Nbd") > 0)
            rc = dice_file(j, err);
        if (!rc)
            rc = ckpt_write(j, err);
    }
    return rc ? jfail(j, fail_code(rc), err, rc) : MOTE_OK;
}
/* Besides the stages, the monitor block shows the first step, the ten from Kl11 and the last. */
static int fire_show(void *ctx, void *subject, mote_err *err)
{
    job *j = ctx;
    const uint64_t kl3 = (uint64_t)ci(j, "Kl3"), kl11 = (uint64_t)ci(j, "Kl11");
    int rc = MOTE_OK;
    if (j->Lt % kl3 != 0 &&
        (j->Lt == 1 || (kl11 > 0 && j->Lt >= kl11 && j->Lt < kl11 + 10) || j->Lt == j->Ltot))
        rc = show(j, err);
    return rc ? jfail(j, fail_code(rc), err, rc) : MOTE_OK;
}

/* The job's side of the core loop: one step at a time (the maxima and approaches look at every
 * step end), counted in Lt. */
static uint64_t job_count(const void *vj) { return ((const job *)vj)->Lt; }
static double job_clock(const void *vj) { return (double)((const job *)vj)->nb.T; }
static int job_advance(void *vj, mote_loop *l, double t_stop, uint64_t n_stop, mote_err *err)
{
    job *j = vj;
    const uint64_t before = j->nb.steps;
    int rc = mote_nb_integrate(&j->nb, 1, INFINITY, err);
    if (!rc && j->nb.steps == before)
        rc = mote_fail(err, MOTE_ERUNTIME, "galactica: no step could be taken at T = %.16E",
                       (double)j->nb.T);
    if (rc)
        return jfail(j, 2, err, rc);
    j->Lt++;
    after_step(j);
    return MOTE_OK;
}

/* Steps Lt .. Ltot through the core loop; its observers, counted in steps Lt: a trajectory
 * record every Kli steps, the stage every Kl3 (the monitor block, the closest approach of the
 * stage, the result file (Kl7 = 1), and with checkpoints (Kl1 >= 3) dice.dat and the
 * checkpoint), and the monitor block's other steps. */
static int run_steps(job *j, mote_err *err)
{
    mote_observer obs[3];
    size_t n = 0;
    if (ci(j, "Kl12") == 1)
        obs[n++] = (mote_observer){.ctx = j, .fire = fire_record, .every = (uint64_t)ci(j, "Kli")};
    obs[n++] = (mote_observer){.ctx = j, .fire = fire_stage, .every = (uint64_t)ci(j, "Kl3")};
    obs[n++] = (mote_observer){.ctx = j, .fire = fire_show, .every = 1};
    mote_progress prog;
    mote_progress_begin(&prog, j->o->ctx, "galactica");
    j->prog = &prog;
    const mote_runner r = {.what = "galactica", .sys = j, .ctx = j->o->ctx, .clock = job_clock,
                           .count = job_count, .advance = job_advance};
    int rc = mote_run(&r, obs, n, &prog, INFINITY, j->Ltot, err);
    mote_progress_end(&prog);
    j->prog = NULL;
    return rc;
}

/* The end: the result file always, the last trajectory file with its summary, dice.dat, and
 * the checkpoint (a relaunch then adds a block of Ltk * Ltk2 steps). */
static int finish(job *j, mote_err *err)
{
    int rc = result_file(j, j->coulomb ? "garek29.dat" : "garez28.dat", err);
    if (!rc && ci(j, "Kl12") == 1)
        rc = trajectory_file(j, "traekt.prn", 1, err);
    if (!rc && ci(j, "Nbd") > 0)
        rc = dice_file(j, err);
    if (!rc && ci(j, "Kl1") >= 3)
        rc = ckpt_write(j, err);
    return rc;
}

static void job_free(job *j)
{
    mote_nb_free(&j->nb);
    free(j->tr);
    nb_approach_free(&j->dice);
}

/* The folder of the control file into j->dir. */
static int job_dir(job *j, const char *control, mote_err *err)
{
    const char *slash = strrchr(control, '/');
    if (slash && (size_t)(slash - control) + 2 > sizeof j->dir)
        return mote_fail(err, MOTE_EINVAL, "galactica: the folder name is too long");
    if (slash)
        snprintf(j->dir, sizeof j->dir, "%.*s/", (int)(slash - control), control);
    return MOTE_OK;
}

int mote_nb_job_check(const mote_nb_job *o, long *k2, mote_err *err)
{
    job J;
    memset(&J, 0, sizeof J);
    job *j = &J;
    j->o = o;
    j->coulomb = o->coulomb;
    j->dry = 1;
    *k2 = 0;
    int rc = job_dir(j, o->control, err);
    if (rc || access(o->control, F_OK) != 0)
        return rc; /* no control file yet: an earlier command or a checkpoint may provide it */
    rc = nb_galctl_read(o->control, o->lenient, o->packed, &j->c, err);
    if (!rc && ci(j, "Kl1") < 3) /* (with 3, 4 a checkpoint may replace it) */
        rc = setup(j, o->control, 1, err);
    if (!rc && ci(j, "Kl1") != 0)
        *k2 = ci(j, "k2");
    free(j->tr);
    return rc;
}

int mote_nb_job_run(const mote_nb_job *o, int *started, mote_err *err)
{
    if (started)
        *started = 0;
    job J;
    memset(&J, 0, sizeof J);
    job *j = &J;
    j->o = o;
    j->coulomb = o->coulomb;
    int rc = job_dir(j, o->control, err);
    if (rc)
        return rc;
    mote_nb_init(&j->nb, o->coulomb ? MOTE_NB_COULOMB : MOTE_NB_GRAVITY);
    nb_approach_init(&j->dice, 0, 0, NULL);
    j->zoom = 1;
    char ck[PATH_CAP];
    jpath(j, o->coulomb ? "galgok2" : "galgon4", ck);
    const int have_ctl = access(o->control, F_OK) == 0, have_ck = access(ck, F_OK) == 0;
    if (have_ctl && (rc = nb_galctl_read(o->control, o->lenient, o->packed, &j->c, err)))
        rc = jfail(j, fail_code(rc), err, rc);
    const int resume = !rc && have_ck && (!have_ctl || ci(j, "Kl1") >= 3);
    if (!rc && !have_ctl && !resume)
        rc = jfail(j, 1, err, mote_fail(err, MOTE_EIO, "%s: cannot open: %s (a Galactica job "
                                        "needs its control file)", o->control, strerror(ENOENT)));
    if (!rc && resume) { /* a relaunch: the checkpoint holds everything (spec 7.10) */
        memset(&j->c, 0, sizeof j->c);
        rc = ckpt_read(j, ck, err);
        if (rc)
            rc = jfail(j, fail_code(rc), err, rc);
        if (!rc)
            rc = check_selection(j, ck, 0, err);
        if (!rc && j->Lt >= j->Ltot)
            j->Ltot += (uint64_t)ci(j, "Ltk") * (uint64_t)ci(j, "Ltk2");
        if (!rc)
            say(j, "galactica: resuming from %s at step %llu, T = %.16E\n", ck,
                (unsigned long long)j->Lt, (double)j->nb.T);
    } else if (!rc) {
        rc = setup(j, o->control, 1, err);
        if (!rc)
            rc = load_bodies(j, err);
        if (!rc)
            rc = check_selection(j, o->control, 1, err);
        if (!rc) {
            j->Ltot = (uint64_t)ci(j, "Ltk") * (uint64_t)ci(j, "Ltk2");
            double ek, vmax, mmax, mz;
            quick_measure(&j->nb, &ek, &vmax, &mmax, &mz);
            j->Em = j->head[14] > ek ? (double)j->head[14] : ek;
            j->Tem = (double)j->nb.T;
            j->Um = vmax;
            for (uint32_t i = 0; i < j->nb.n; i++)
                j->Nb0 += j->nb.active[i];
            j->warned = j->nb.approach_warnings;
        }
    }
    if (!rc)
        rc = plan(j, err);
    j->nb.threads = o->threads;
    if (!rc && o->out)
        fprintf(o->out, "galactica: the monitor: T omm Um / dTp Px Py / Pz Mx My / Mz Sx Sy / "
                        "Sz E Em / Ett Lt dT / dMz\n");
    if (!rc && started)
        *started = 1;
    if (!rc)
        rc = run_steps(j, err);
    if (!rc && (rc = finish(j, err)) != MOTE_OK)
        rc = jfail(j, fail_code(rc), err, rc);
    if (j->nb.approach_warnings > j->warned) {
        char msg[256];
        snprintf(msg, sizeof msg, "merge accuracy not ensured: %llu merges overlapped by more "
                 "than 10%% of the radii after a step at the shortest length (largest overlap "
                 "%.3g): lower bt", (unsigned long long)(j->nb.approach_warnings - j->warned),
                 (double)j->nb.max_overlap);
        errfile(j, 11, msg);
        say(j, "galactica: warning: %s\n", msg);
    }
    if (!rc) {
        say(j, "galactica: %llu steps done, T = %.16E; wrote %s%s\n",
            (unsigned long long)j->Lt, (double)j->nb.T,
            o->coulomb ? "garek29.dat" : "garez28.dat",
            ci(j, "Kl12") == 1 ? ", traekt.prn" : "");
        if (o->final && o->final->kind == j->nb.kind) {
            mote_nb_free(o->final);
            *o->final = j->nb;
            mote_nb_init(&j->nb, j->nb.kind);
        }
    }
    job_free(j);
    return rc;
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
    int rc = job_dir(j, o->control, err);
    if (rc)
        return rc;
    mote_nb_init(&j->nb, o->coulomb ? MOTE_NB_COULOMB : MOTE_NB_GRAVITY);
    char ck[PATH_CAP];
    jpath(j, o->coulomb ? "galgok2" : "galgon4", ck);
    rc = ckpt_read(j, ck, err);
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
        rc = setup(j, ck, 0, err);
    if (!rc)
        rc = check_selection(j, ck, 0, err);
    if (!rc && plan_changed) /* the next launch runs Ltk * Ltk2 steps from here */
        j->Ltot = j->Lt + (uint64_t)ci(j, "Ltk") * (uint64_t)ci(j, "Ltk2");
    if (!rc && j->trn > j->trcap)
        rc = mote_fail(err, MOTE_EINVAL, "galactica edit: the checkpoint holds %zu trajectory "
                       "records, more than Klmax", j->trn);
    if (!rc)
        rc = ckpt_write(j, err);
    if (!rc)
        say(j, "galactica edit: %s now plans steps %llu to %llu, dT = %.16E\n", ck,
            (unsigned long long)j->Lt, (unsigned long long)j->Ltot, (double)j->nb.dt);
    job_free(j);
    return rc;
}
