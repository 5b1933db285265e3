/* files.c: the N-body model's file commands: the exact state (save, load, checkpoint,
 * restart), snapshots and Galactica's body files (write, read), steps_between, Galactica jobs
 * (run galactica) and the ring check. */
#include "mote/datafile.h"
#include "mote/nbody.h"

#include <tgmath.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "model.h"

/* ---- state files ------------------------------------------------------------------------------ */

int nb_check_save(void *vm, const mote_call *c, mote_err *err) { return nb_need_bodies(vm, c, err); }
int nb_run_save(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    nb_settle_units(m);
    int rc = nb_state_save(&m->nb, c->args[0].path, err);
    if (!rc && m->log)
        fprintf(m->log, "save: wrote %s\n", c->args[0].path);
    return rc;
}

static int check_state_input(nb_model *m, const mote_call *c, const char *path, int argi,
                             mote_err *err)
{
    uint32_t n = 1;
    if (!mote_outputs_find(&c->ctx->outputs, path)) {
        int rc = nb_state_peek(path, &n, err);
        if (rc) {
            char why[sizeof err->msg];
            snprintf(why, sizeof why, "%s", err->msg);
            return mote_call_fail(err, c, argi, (mote_status)rc, "%s: %s",
                                  c->name, why);
        }
    }
    m->d_bodies = n;
    m->d_ring = 0;
    m->d_scales = 1;
    return MOTE_OK;
}
static int load_state(nb_model *m, const mote_call *c, const char *path, mote_err *err)
{
    int rc = nb_state_load(&m->nb, path, err);
    if (!rc) {
        m->have_ring = 0;
        m->raw = 0;
        if (!m->nb.u.set && m->input_si) { /* nothing to convert SI values with */
            m->input_si = 0;
            if (m->log)
                fprintf(m->log, "%s: the state has no physical scales; later bodies are read "
                                "in dimensionless units\n", c->name);
        }
        char t[MOTE_REAL_BUF];
        if (m->log)
            fprintf(m->log, "%s: %u bodies at T = %s (step %llu) from %s\n", c->name, m->nb.n,
                    mote_real_str(m->nb.T, t), (unsigned long long)m->nb.steps, path);
    }
    return rc;
}
int nb_check_load(void *vm, const mote_call *c, mote_err *err)
{
    return check_state_input(vm, c, c->args[0].path, 0, err);
}
int nb_run_load(void *vm, const mote_call *c, mote_err *err)
{
    return load_state(vm, c, c->args[0].path, err);
}
int nb_check_restart(void *vm, const mote_call *c, mote_err *err)
{
    return check_state_input(vm, c, mote_call_opt(c, "file")->path,
                             mote_call_opt_index(c, "file"), err);
}
int nb_run_restart(void *vm, const mote_call *c, mote_err *err)
{
    return load_state(vm, c, mote_call_opt(c, "file")->path, err);
}

int nb_check_checkpoint(void *vm, const mote_call *c, mote_err *err)
{
    return nb_need_bodies(vm, c, err);
}
int nb_run_checkpoint(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    nb_settle_units(m);
    free(m->ckpt.path);
    m->ckpt.path = strdup(mote_call_opt(c, "file")->path);
    if (!m->ckpt.path)
        return mote_fail(err, MOTE_ENOMEM, "checkpoint: out of memory");
    m->ckpt.every = (uint64_t)mote_call_opt(c, "every")->i;
    return nb_state_save(&m->nb, m->ckpt.path, err);
}

int nb_run_checkpoint_stop(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    free(m->ckpt.path); /* (its file stays: the state at the last checkpoint) */
    m->ckpt.path = NULL;
    return MOTE_OK;
}

/* ---- write and read: snapshots and Galactica files (spec 10.2, 7.5, 7.6) -----------------  */

/* write/read KIND: snapshot (spec 10.2) or galactica (Galactica's files, spec 7.5, 7.6) */
static int check_kind(const mote_call *c, mote_err *err)
{
    const int gal = c->args[0].i == 1; /* snapshot|galactica */
    const char *gal_only = mote_call_opt(c, "n") ? "n" : mote_call_opt(c, "info_line") ? "info_line" : NULL;
    if (!gal && gal_only)
        return mote_call_fail(err, c, mote_call_opt_index(c, gal_only), MOTE_EINVAL,
                              "%s snapshot: %s= is for galactica files", c->name, gal_only);
    if (gal && mote_call_opt(c, "format"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "format"), MOTE_EINVAL,
                              "%s galactica: format= is for snapshots", c->name);
    return MOTE_OK; /* (format= is native: `write galactica` writes Galactica's layout) */
}

int nb_check_write(void *vm, const mote_call *c, mote_err *err)
{
    int rc = check_kind(c, err);
    return rc ? rc : nb_need_bodies(vm, c, err);
}
/* The system as a Galactica file (spec 7.5): the header computed, its area fields and Em
 * carried from the file read or the generator. */
int nb_write_galactica(nb_model *m, const char *path, int info_line, mote_err *err)
{
    const size_t W = m->nb.kind == MOTE_NB_COULOMB ? 16 : 15;
    mote_real *body = malloc(W * (m->nb.n ? m->nb.n : 1) * sizeof *body);
    if (!body)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", path);
    nb_galfile g;
    nb_to_galfile(&m->nb, m->have_galhead ? m->galhead : NULL, &g, body);
    int rc = nb_galfile_write(path, &g, info_line, err);
    free(body);
    return rc;
}

/* write and read: e{snapshot|galactica}, by their place */
enum { FILE_SNAPSHOT, FILE_GALACTICA };

int nb_run_write(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    nb_settle_units(m);
    char *origin = mote_call_origin(c);
    if (!origin)
        return mote_fail(err, MOTE_ENOMEM, "write: out of memory");
    const char *path = mote_call_opt(c, "file")->path;
    int rc;
    if (c->args[0].i == FILE_GALACTICA) {
        rc = nb_write_galactica(m, path, mote_call_on(c, "info_line", 1), err);
    } else {
        rc = nb_snapshot_write(&m->nb, path, origin, err);
    }
    free(origin);
    if (!rc && m->log)
        fprintf(m->log, "write %s: wrote %s (%u bodies at T = %.17g)\n", c->args[0].text, path,
                m->nb.n, (double)m->nb.T);
    return rc;
}

int nb_check_read(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int rc = check_kind(c, err);
    if (rc)
        return rc;
    const mote_arg *f = mote_call_opt(c, "file");
    uint32_t n = 1;
    if (!mote_outputs_find(&c->ctx->outputs, f->path)) { /* read it whole now: errors before the run */
        mote_nb t;
        mote_nb_init(&t, m->nb.kind);
        if (c->args[0].i == FILE_GALACTICA) {
            nb_galfile g;
            const mote_arg *k2 = mote_call_opt(c, "n");
            rc = nb_galfile_read(f->path, m->nb.kind == MOTE_NB_COULOMB, k2 ? (long)k2->i : -1,
                                 &g, err);
            if (!rc)
                rc = nb_from_galfile(&t, &g, f->path, err);
            nb_galfile_free(&g);
        } else {
            rc = nb_snapshot_read(&t, f->path, err);
        }
        n = t.n;
        mote_nb_free(&t);
        if (rc) {
            char why[sizeof err->msg];
            snprintf(why, sizeof why, "%s", err->msg);
            return mote_call_fail(err, c, mote_call_opt_index(c, "file"), (mote_status)rc,
                                  "read: %s", why);
        }
    }
    /* a file of the ring's size keeps the ring as the reference of check ring (a result file) */
    m->d_ring = m->d_ring && n == m->d_bodies;
    m->d_bodies = n;
    m->d_scales = 1;
    return MOTE_OK;
}
int nb_run_read(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const char *path = mote_call_opt(c, "file")->path;
    const int gal = c->args[0].i == FILE_GALACTICA;
    int rc;
    if (gal) {
        nb_galfile g;
        const mote_arg *k2 = mote_call_opt(c, "n");
        rc = nb_galfile_read(path, m->nb.kind == MOTE_NB_COULOMB, k2 ? (long)k2->i : -1, &g, err);
        if (!rc)
            rc = nb_from_galfile(&m->nb, &g, path, err);
        if (!rc) {
            memcpy(m->galhead, g.head, sizeof m->galhead);
            m->have_galhead = 1;
            nb_units_from_info(&m->nb, &g); /* the scales of the info line, if any */
        }
        nb_galfile_free(&g);
    } else {
        rc = nb_snapshot_read(&m->nb, path, err);
    }
    if (rc) {
        char why[sizeof err->msg];
        snprintf(why, sizeof why, "%s", err->msg);
        return mote_call_fail(err, c, mote_call_opt_index(c, "file"), (mote_status)rc, "read: %s",
                              why);
    }
    m->have_ring = m->have_ring && (int)m->nb.n == m->ring.nb;
    m->raw = 0;
    if (!m->nb.u.set)
        m->input_si = 0;
    char t[MOTE_REAL_BUF];
    if (m->log)
        fprintf(m->log, "read %s: %u bodies at T = %s (step %llu) from %s\n", c->args[0].text,
                m->nb.n, mote_real_str(m->nb.T, t), (unsigned long long)m->nb.steps, path);
    return MOTE_OK;
}

/* `steps_between jd1= jd2= dt= [fresh=on]` (spec 9.5) */
int nb_check_steps_between(void *vm, const mote_call *c, mote_err *err)
{
    (void)vm;
    if (!(mote_call_opt(c, "jd2")->r > mote_call_opt(c, "jd1")->r))
        return mote_call_fail(err, c, mote_call_opt_index(c, "jd2"), MOTE_EINVAL,
                              "steps_between: jd2 must come after jd1");
    return MOTE_OK;
}
int nb_run_steps_between(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const int fresh = mote_call_on(c, "fresh", 0);
    /* the time unit: the run's scales when set, else the sidereal century (Galactica's) */
    const double days = m->nb.u.set ? 1 / (86400 * m->nb.u.kt) : 100 * MOTE_NB_SIDEREAL_YEAR_DAYS;
    mote_nb_steps st;
    int rc = mote_nb_steps_between(mote_call_opt(c, "jd1")->r, mote_call_opt(c, "jd2")->r, days,
                                   (mote_real)mote_call_opt(c, "dt")->r, fresh, m->nb.first_step,
                                   &st, err);
    if (rc) {
        char why[sizeof err->msg];
        snprintf(why, sizeof why, "%s", err->msg);
        return mote_call_fail(err, c, -1, rc, "%s", why);
    }
    char b[2][MOTE_REAL_BUF];
    if (m->log)
        fprintf(m->log, "steps_between: DeltaT=%s Ltk=%llu dT=%s (%s) T_end-T_target=%.3e\n",
                mote_real_str(st.DeltaT, b[0]), (unsigned long long)st.Ltk,
                mote_real_str(st.dtc, b[1]), fresh ? "fresh start: the first step is "
                "first_step dT" : "continuation", (double)(st.t_end - st.DeltaT));
    return MOTE_OK;
}

/* ---- run galactica (spec 7) ------------------------------------------------------------------ */

/* The words of run galactica's options by their place: interaction=e{gravity|coulomb},
 * trio_layout=e{prose|packed} */
enum { GRAVITY, COULOMB };
enum { TRIO_PROSE, TRIO_PACKED };

static int job_coulomb(const nb_model *m, const mote_call *c)
{
    const int k = mote_call_word(c, "interaction", -1);
    return k >= 0 ? k == COULOMB : m->nb.kind == MOTE_NB_COULOMB;
}

int nb_check_run(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const mote_arg *a = mote_call_opt(c, "control"); /* (the words are the table's) */
    mote_nb_job o;
    memset(&o, 0, sizeof o);
    o.control = a ? a->path : "galacf26.dat";
    o.coulomb = job_coulomb(m, c);
    o.lenient = nb_opt_on_off(c, "lenient", 0) == 1;
    o.packed = mote_call_word(c, "trio_layout", TRIO_PROSE) == TRIO_PACKED;
    long k2 = 0;
    uint32_t n = 1;
    if (!mote_outputs_find(&c->ctx->outputs, o.control)) {
        /* the control file's errors now, before anything runs */
        int rc = mote_nb_job_check(&o, &k2, err);
        if (rc) {
            char why[sizeof err->msg];
            snprintf(why, sizeof why, "%s", err->msg);
            return mote_call_fail(err, c, mote_call_opt_index(c, "control"), (mote_status)rc,
                                  "run galactica: %s", why);
        }
        if (k2 > 0)
            n = (uint32_t)k2;
    }
    m->d_ring = m->d_ring && n == m->d_bodies;
    if (job_coulomb(m, c) == (m->nb.kind == MOTE_NB_COULOMB)) {
        m->d_bodies = n;
        m->d_scales = 1;
    }
    return MOTE_OK;
}

int nb_run_run(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const mote_arg *a = mote_call_opt(c, "control");
    mote_nb_job o;
    memset(&o, 0, sizeof o);
    o.control = a ? a->path : "galacf26.dat";
    o.coulomb = job_coulomb(m, c);
    o.frames = nb_opt_on_off(c, "frames", 0) == 1;
    o.force = nb_opt_on_off(c, "force", 0) == 1;
    o.lenient = nb_opt_on_off(c, "lenient", 0) == 1;
    o.packed = mote_call_word(c, "trio_layout", TRIO_PROSE) == TRIO_PACKED;
    o.step_tol = (a = mote_call_opt(c, "step_tol")) ? a->r : 0;
    o.max_files = (a = mote_call_opt(c, "max_files")) ? (long)a->i : 0;
    o.threads = c->ctx->threads;
    o.out = m->log;
    o.final = &m->nb;
    o.ctx = c->ctx;
    const int ring = m->have_ring;
    int rc = mote_nb_job_run(&o, NULL, err);
    if (rc) {
        char why[sizeof err->msg];
        snprintf(why, sizeof why, "%s", err->msg);
        return mote_call_fail(err, c, -1, (mote_status)rc, "%s", why);
    }
    m->have_ring = ring && (int)m->nb.n == m->ring.nb;
    m->raw = 0;
    return MOTE_OK;
}

int nb_check_check(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    if (!m->d_ring)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "check ring: no ring was generated (generate ring or atom_ring)");
    return MOTE_OK;
}
int nb_run_check(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    nb_settle_units(m);
    mote_real plane;
    mote_real e = mote_nb_ring_error(&m->nb, &m->ring, &plane);
    mote_nb_monitor mon;
    mote_nb_measure(&m->nb, &mon);
    char t[MOTE_REAL_BUF];
    if (m->log)
        fprintf(m->log,
                "check ring: T = %s (%.6g periods): error %.3e, out of the orbit plane %.3e "
                "of a, dE %.3e, dMz %.3e\n",
                mote_real_str(m->nb.T, t), (double)(m->nb.T / m->ring.period), (double)e,
                (double)(plane / m->ring.a_o), (double)mon.dE, (double)mon.dMz);
    return MOTE_OK;
}


