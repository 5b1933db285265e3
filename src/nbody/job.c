/* job.c: a Galactica job (spec 7): the control file galacf26.dat of a folder decides where the
 * bodies come from (Kl1: the area, garez28.dat, the file FIMA4, with or without checkpoints), how
 * time and the step run (Kl4), how many steps (Ltk cycles of Ltk2... Ltk * Ltk2), and what is
 * written: the monitor block every Kl3 steps (7.12), the result files 1, 2, ... (7.7), the
 * trajectory files 1t, 2t, ... traekt.prn (7.8), dice.dat (7.9), the checkpoint galgon4 (7.10),
 * pictures (7.13), and always garez28.dat at the end (Coulomb: garek29.dat, galgok2). Errors go
 * to the caller and are appended to ErrGlctca with Galactica's "*nnG" codes (7.11). Everything is
 * checked, and the number of files counted, before the first file is written; every file is
 * written atomically, so a failed launch leaves the folder's earlier files as they were. The
 * checkpoint (written, read, edited): checkpoint.c; the job's state: job.h. */
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

#include "job.h"
#include "nb.h"


/* ---- paths, messages, ErrGlctca ----------------------------------------------------------------- */

const char *nb_job_path(const job *j, const char *name, char buf[PATH_CAP])
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

void nb_job_say(const job *j, const char *fmt, ...)
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
    FILE *f = fopen(nb_job_path(j, "ErrGlctca", p), "a");
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
long nb_job_ci(const job *j, const char *name)
{
    const double v = cv(j, name);
    return v >= 9e18 ? 9000000000000000000L : v <= -9e18 ? -9000000000000000000L : (long)v;
}

/* Check the control values that do not depend on the bodies, and size the trajectory buffer. */
int nb_job_setup(job *j, const char *src, int from_ctl, mote_err *err)
{
    static const char *const keys[] = {"Kl7", "Kl12", "Kl15", "Kl10", "Kl14"};
    const long kl1 = nb_job_ci(j, "Kl1"), kl4 = nb_job_ci(j, "Kl4");
    if (kl1 < 0 || kl1 > 4)
        return ctl_fail(j, src, from_ctl, err, "Kl1", "= %ld, expected 0 (area), 1 (%s), 2 "
                        "(FIMA4), 3 or 4 (as 1 or 2, with checkpoints)", kl1,
                        j->coulomb ? "garek29.dat" : "garez28.dat");
    if (kl4 < 0 || kl4 > 3)
        return ctl_fail(j, src, from_ctl, err, "Kl4", "= %ld, expected 0, 1, 2 or 3", kl4);
    const char *pos[] = {"Ltk", "Ltk2", "Kl3"};
    for (int k = 0; k < 3; k++)
        if (nb_job_ci(j, pos[k]) < 1)
            return ctl_fail(j, src, from_ctl, err, pos[k], "= %ld, expected at least 1",
                            nb_job_ci(j, pos[k]));
    if ((double)nb_job_ci(j, "Ltk") * (double)nb_job_ci(j, "Ltk2") > 9e18)
        return ctl_fail(j, src, from_ctl, err, "Ltk2", "makes Ltk * Ltk2 beyond 9e18 steps");
    for (int k = 0; k < 5; k++)
        if (nb_job_ci(j, keys[k]) != 0 && nb_job_ci(j, keys[k]) != 1)
            return ctl_fail(j, src, from_ctl, err, keys[k], "= %ld, expected 0 or 1",
                            nb_job_ci(j, keys[k]));
    if (nb_job_ci(j, "Kl11") < 0)
        return ctl_fail(j, src, from_ctl, err, "Kl11", "= %ld, expected 0 (off) or a step",
                        nb_job_ci(j, "Kl11"));
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
        if (nb_job_ci(j, "Mu") < 1)
            return ctl_fail(j, src, from_ctl, err, "Mu", "= %ld, expected at least 1",
                            nb_job_ci(j, "Mu"));
        const char *pp[] = {"B", "C", "Roa"};
        for (int k = 0; k < 3; k++)
            if (!(cv(j, pp[k]) > 0))
                return ctl_fail(j, src, from_ctl, err, pp[k], "= %g, expected > 0", cv(j, pp[k]));
        if (!(cv(j, "Rob") >= 0) || !(cv(j, "RoS") >= 0))
            return ctl_fail(j, src, from_ctl, err, cv(j, "Rob") >= 0 ? "RoS" : "Rob",
                            "is negative");
    } else if (nb_job_ci(j, "k2") < 1 || nb_job_ci(j, "k2") > 100000000) {
        return ctl_fail(j, src, from_ctl, err, "k2", "= %ld, expected the number of bodies "
                        "(1 ... 10^8)", nb_job_ci(j, "k2"));
    }
    if ((kl1 == 2 || kl1 == 4) && !j->c.fima4[0])
        return ctl_fail(j, src, from_ctl, err, "FIMA4", "is empty: Kl1 = %ld reads the bodies "
                        "from the file it names", kl1);
    j->trw = 0;
    if (nb_job_ci(j, "Kl12") == 1) {
        const long np = nb_job_ci(j, "Np");
        if (nb_job_ci(j, "Kli") < 1)
            return ctl_fail(j, src, from_ctl, err, "Kli", "= %ld, expected at least 1 step "
                            "between trajectory records", nb_job_ci(j, "Kli"));
        if (np < 1 || np > j->c.ntrio)
            return ctl_fail(j, src, from_ctl, err, "Np", "= %ld, expected 1 ... %d (the trios "
                            "ipp, jpp, kpp given from line 51)", np, j->c.ntrio);
        j->trw = (size_t)(3 * (nb_job_ci(j, "Kl15") + 1) * np + 2);
        const long kmax = nb_job_ci(j, "Klmax");
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
int nb_job_check_selection(job *j, const char *src, int from_ctl, mote_err *err)
{
    const long n = (long)j->nb.n;
    if (nb_job_ci(j, "Nbd") < 0 || nb_job_ci(j, "Nbd") > n)
        return ctl_fail(j, src, from_ctl, err, "Nbd", "= %ld, expected 0 (off) or a body 1 ... "
                        "%ld", nb_job_ci(j, "Nbd"), n);
    for (long t = 0; t < (nb_job_ci(j, "Kl12") == 1 ? nb_job_ci(j, "Np") : 0); t++)
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
    int rc = nb_galfile_write(nb_job_path(j, name, p), &g, 1, err);
    free(body);
    return rc;
}

/* A trajectory file: the records, one a line, then (traekt.prn) the ten-number summary. */
static int trajectory_file(job *j, const char *name, int summary, mote_err *err)
{
    char p[PATH_CAP];
    mote_afile af;
    int rc = mote_afile_open(&af, nb_job_path(j, name, p), err);
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
    const long np = nb_job_ci(j, "Np"), vel = nb_job_ci(j, "Kl15") == 1;
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
    int rc = mote_afile_open(&af, nb_job_path(j, "dice.dat", p), err);
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
    int rc = nb_frame_png(&j->nb, &f, nb_job_path(j, name, p), j->Lt, err);
    j->zoom = f.zoom;
    j->nframe += !rc;
    return rc;
}

/* ---- the job ---------------------------------------------------------------------------------- */

/* The bodies, time and step of a first launch (spec 7.4). */
static int load_bodies(job *j, mote_err *err)
{
    const long kl1 = nb_job_ci(j, "Kl1"), kl4 = nb_job_ci(j, "Kl4");
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
        a.Mu = (int)nb_job_ci(j, "Mu");
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
        nb_job_say(j, "galactica: the area, %d x %d x %d bodies%s\n", a.nx, a.ny, a.nz,
            a.sep_added ? " and the separate body"
            : a.RoS > 0 ? " (the separate body is closer than 1/Mu to a node: not added)" : "");
    } else {
        char p[PATH_CAP];
        const char *path = kl1 == 1 || kl1 == 3
                               ? nb_job_path(j, j->coulomb ? "garek29.dat" : "garez28.dat", p)
                               : nb_job_path(j, j->c.fima4, p);
        if (j->c.fima4_long && (kl1 == 2 || kl1 == 4))
            nb_job_say(j, "galactica: warning: FIMA4 '%s' is longer than Galactica's 12 characters\n",
                j->c.fima4);
        nb_galfile g;
        rc = nb_galfile_read(path, j->coulomb, nb_job_ci(j, "k2"), &g, err);
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
                           "(%s)", path, nb_job_ci(j, "k2"), (double)total,
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
        nb_job_say(j, "galactica: %u bodies from %s, T0 = %.16E, dT = %.16E\n", nb->n, path,
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
    const uint64_t L0 = j->Lt, L1 = j->Ltot, kl3 = (uint64_t)nb_job_ci(j, "Kl3");
    const double n = j->nb.n;
    double files = 1, bytes = (n + 3) * 15 * 25;
    if (nb_job_ci(j, "Kl7") == 1) {
        files += (double)(L1 / kl3 - L0 / kl3);
        bytes += (double)(L1 / kl3 - L0 / kl3) * (n + 3) * 15 * 25;
    }
    if (nb_job_ci(j, "Kl12") == 1) {
        const uint64_t kli = (uint64_t)nb_job_ci(j, "Kli");
        const double rec = (double)(L1 / kli - L0 / kli) + (double)j->trn;
        files += floor(rec / (double)j->trcap) + 1;
        bytes += rec * (double)j->trw * 25;
    }
    if (j->o->frames) {
        const double f = (double)((L1 - L0) / kl3) + 2 + (nb_job_ci(j, "Kl11") > 0 ? 10 : 0);
        files += f;
        bytes += f * 30000;
    }
    files += (nb_job_ci(j, "Nbd") > 0) + (nb_job_ci(j, "Kl1") >= 3);
    const long limit = j->o->max_files > 0 ? j->o->max_files : 10000;
    nb_job_say(j, "galactica: %llu steps (Lt %llu to %llu), about %.0f files, %.3g MB\n",
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
    if (nb_job_ci(j, "Nbd") > 0) {
        j->dice.body = (uint32_t)(nb_job_ci(j, "Nbd") - 1); /* (Nbd may have been edited) */
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
    if (!rc && nb_job_ci(j, "Nbd") > 0)
        rc = nb_approach_close(&j->dice, j->nb.T, err);
    if (!rc && nb_job_ci(j, "Kl7") == 1) {
        char name[32];
        snprintf(name, sizeof name, "%llu", (unsigned long long)(j->nfile + 1));
        rc = result_file(j, name, err);
        j->nfile += !rc;
    }
    if (!rc && nb_job_ci(j, "Kl1") >= 3 && j->Lt < j->Ltot) {
        if (nb_job_ci(j, "Nbd") > 0)
            rc = dice_file(j, err);
        if (!rc)
            rc = nb_ckpt_write(j, err);
    }
    return rc ? jfail(j, fail_code(rc), err, rc) : MOTE_OK;
}
/* Besides the stages, the monitor block shows the first step, the ten from Kl11 and the last. */
static int fire_show(void *ctx, void *subject, mote_err *err)
{
    job *j = ctx;
    const uint64_t kl3 = (uint64_t)nb_job_ci(j, "Kl3"), kl11 = (uint64_t)nb_job_ci(j, "Kl11");
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
    if (nb_job_ci(j, "Kl12") == 1)
        obs[n++] = (mote_observer){.ctx = j, .fire = fire_record, .every = (uint64_t)nb_job_ci(j, "Kli")};
    obs[n++] = (mote_observer){.ctx = j, .fire = fire_stage, .every = (uint64_t)nb_job_ci(j, "Kl3")};
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
    if (!rc && nb_job_ci(j, "Kl12") == 1)
        rc = trajectory_file(j, "traekt.prn", 1, err);
    if (!rc && nb_job_ci(j, "Nbd") > 0)
        rc = dice_file(j, err);
    if (!rc && nb_job_ci(j, "Kl1") >= 3)
        rc = nb_ckpt_write(j, err);
    return rc;
}

void nb_job_free(job *j)
{
    mote_nb_free(&j->nb);
    free(j->tr);
    nb_approach_free(&j->dice);
}

/* The folder of the control file into j->dir. */
int nb_job_dir(job *j, const char *control, mote_err *err)
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
    int rc = nb_job_dir(j, o->control, err);
    if (rc || access(o->control, F_OK) != 0)
        return rc; /* no control file yet: an earlier command or a checkpoint may provide it */
    rc = nb_galctl_read(o->control, o->lenient, o->packed, &j->c, err);
    if (!rc && nb_job_ci(j, "Kl1") < 3) /* (with 3, 4 a checkpoint may replace it) */
        rc = nb_job_setup(j, o->control, 1, err);
    if (!rc && nb_job_ci(j, "Kl1") != 0)
        *k2 = nb_job_ci(j, "k2");
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
    int rc = nb_job_dir(j, o->control, err);
    if (rc)
        return rc;
    mote_nb_init(&j->nb, o->coulomb ? MOTE_NB_COULOMB : MOTE_NB_GRAVITY);
    nb_approach_init(&j->dice, 0, 0, NULL);
    j->zoom = 1;
    char ck[PATH_CAP];
    nb_job_path(j, o->coulomb ? "galgok2" : "galgon4", ck);
    const int have_ctl = access(o->control, F_OK) == 0, have_ck = access(ck, F_OK) == 0;
    if (have_ctl && (rc = nb_galctl_read(o->control, o->lenient, o->packed, &j->c, err)))
        rc = jfail(j, fail_code(rc), err, rc);
    const int resume = !rc && have_ck && (!have_ctl || nb_job_ci(j, "Kl1") >= 3);
    if (!rc && !have_ctl && !resume)
        rc = jfail(j, 1, err, mote_fail(err, MOTE_EIO, "%s: cannot open: %s (a Galactica job "
                                        "needs its control file)", o->control, strerror(ENOENT)));
    if (!rc && resume) { /* a relaunch: the checkpoint holds everything (spec 7.10) */
        memset(&j->c, 0, sizeof j->c);
        rc = nb_ckpt_read(j, ck, err);
        if (rc)
            rc = jfail(j, fail_code(rc), err, rc);
        if (!rc)
            rc = nb_job_check_selection(j, ck, 0, err);
        if (!rc && j->Lt >= j->Ltot)
            j->Ltot += (uint64_t)nb_job_ci(j, "Ltk") * (uint64_t)nb_job_ci(j, "Ltk2");
        if (!rc)
            nb_job_say(j, "galactica: resuming from %s at step %llu, T = %.16E\n", ck,
                (unsigned long long)j->Lt, (double)j->nb.T);
    } else if (!rc) {
        rc = nb_job_setup(j, o->control, 1, err);
        if (!rc)
            rc = load_bodies(j, err);
        if (!rc)
            rc = nb_job_check_selection(j, o->control, 1, err);
        if (!rc) {
            j->Ltot = (uint64_t)nb_job_ci(j, "Ltk") * (uint64_t)nb_job_ci(j, "Ltk2");
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
        nb_job_say(j, "galactica: warning: %s\n", msg);
    }
    if (!rc) {
        nb_job_say(j, "galactica: %llu steps done, T = %.16E; wrote %s%s\n",
            (unsigned long long)j->Lt, (double)j->nb.T,
            o->coulomb ? "garek29.dat" : "garez28.dat",
            nb_job_ci(j, "Kl12") == 1 ? ", traekt.prn" : "");
        if (o->final && o->final->kind == j->nb.kind) {
            mote_nb_free(o->final);
            *o->final = j->nb;
            mote_nb_init(&j->nb, j->nb.kind);
        }
    }
    nb_job_free(j);
    return rc;
}
