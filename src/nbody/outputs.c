/* outputs.c: the N-body model's output commands (monitor, trajectory, approaches, frames,
 * snapshot every=K|dt=T): their options, files and samples; integrate (run.c) fires them as
 * observers of the core's run loop. */
#include "mote/h5md.h"
#include "mote/datafile.h"
#include "mote/nbody.h"

#include <tgmath.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "mote/loop.h"

#include "model.h"

/* The monitor's columns (spec 10.1; E_corr last). cpu_s and wall_s, the processor and wall
 * seconds since the monitor started, are the only ones that differ between identical runs. */
enum { MON_COLS = 36 };
static const char *const MON_NAME[MON_COLS] = {
    "step", "T",     "h",      "dT",     "N_active", "E_kin",  "U",      "E_tot",
    "dE",   "Px",    "Py",     "Pz",     "Lx",       "Ly",     "Lz",     "Sx",
    "Sy",   "Sz",    "dMz",    "dL",     "Xcm",      "Ycm",    "Zcm",    "Vxcm",
    "Vycm", "Vzcm",  "m_max",  "v_max",  "E_kin_max", "T_E_kin_max", "E_heat", "E_spin",
    "merges", "cpu_s", "wall_s", "E_corr"};
/* integer columns; and the columns the monitor prints on the terminal */
static int mon_integer(int c) { return c == 0 || c == 4 || c == 32; }
static const int MON_TERM[] = {0, 1, 2, 4, 7, 8, 18, 19, 32};

/* the words of format=e{table|csv|jsonl|h5md} (monitor: the first three) */
enum { FMT_TABLE, FMT_CSV, FMT_JSONL, FMT_H5MD };

/* Room for one more sample row; returns it or NULL (out of memory). */
static double *sampler_row(nb_sampler *s)
{
    if (s->nrows == s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 256;
        double *p = realloc(s->rows, cap * s->cols * sizeof *p);
        if (!p)
            return NULL;
        s->rows = p;
        s->cap = cap;
    }
    return s->rows + s->nrows++ * s->cols;
}

static double now_seconds(clockid_t id)
{
    struct timespec ts;
    return clock_gettime(id, &ts) == 0 ? (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec : 0;
}

static void print_terminal_row(FILE *f, const double *r)
{
    for (size_t k = 0; k < sizeof MON_TERM / sizeof MON_TERM[0]; k++) {
        int c = MON_TERM[k];
        if (mon_integer(c))
            fprintf(f, k ? " %10.0f" : "%12.0f", r[c]);
        else
            fprintf(f, " %23.16e", r[c]);
    }
    fputc('\n', f);
}

/* A monitor row of the state nb (the current one, or a dense-output view). */
static int monitor_sample(nb_model *m, const mote_nb *nb, mote_err *err)
{
    nb_sampler *s = &m->mon;
    double *r = sampler_row(s);
    if (!r)
        return mote_fail(err, MOTE_ENOMEM, "monitor: out of memory");
    mote_nb_monitor mon;
    mote_nb_measure(nb, &mon);
    uint32_t active = 0;
    double mmax = 0, vmax = 0;
    for (uint32_t i = 0; i < nb->n; i++) {
        if (!nb->active[i])
            continue;
        active++;
        const mote_real *v = nb->v + 3 * (size_t)i;
        mote_real v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        mmax = fmax(mmax, nb->m[i]);
        vmax = fmax(vmax, sqrt(v2));
        if (0.5 * nb->m[i] * v2 > s->ekmax) {
            s->ekmax = 0.5 * nb->m[i] * v2;
            s->t_ekmax = nb->T;
        }
    }
    double row[MON_COLS] = {(double)nb->steps, nb->T, nb->hlast, nb->dt, (double)active,
                            mon.ekin, mon.u, mon.etot, mon.dE, mon.P[0], mon.P[1], mon.P[2],
                            mon.L[0], mon.L[1], mon.L[2], mon.S[0], mon.S[1], mon.S[2], mon.dMz,
                            mon.dL, mon.R[0] / mon.mtot, mon.R[1] / mon.mtot,
                            mon.R[2] / mon.mtot, mon.P[0] / mon.mtot, mon.P[1] / mon.mtot,
                            mon.P[2] / mon.mtot, mmax, vmax, s->ekmax, s->t_ekmax, nb->e_heat,
                            nb->e_spin, (double)nb->merges,
                            now_seconds(CLOCK_PROCESS_CPUTIME_ID) - s->cpu0,
                            now_seconds(CLOCK_MONOTONIC) - s->wall0, mon.ecorr};
    memcpy(r, row, sizeof row);
    if (!s->path && m->log) { /* the terminal: one aligned line now */
        print_terminal_row(m->log, r);
        s->nrows = 0;
    }
    return MOTE_OK;
}

static int trajectory_sample(nb_model *m, const mote_nb *nb, mote_err *err)
{
    nb_sampler *s = &m->traj;
    if (nb->n != s->n0)
        return mote_fail(err, MOTE_EINVAL, "trajectory: the number of bodies changed (%u now, "
                         "%u when it started)", nb->n, s->n0);
    double *r = sampler_row(s);
    if (!r)
        return mote_fail(err, MOTE_ENOMEM, "trajectory: out of memory");
    mote_nb_monitor mon;
    mote_nb_measure(nb, &mon);
    r[0] = nb->T;
    r[1] = mon.ekin;
    r[2] = mon.etot;
    r += 3;
    for (uint32_t k = 0; k < s->nsel; k++) { /* (double samples of the real values) */
        size_t i = 3 * (size_t)s->sel[k];
        for (int a = 0; a < 3; a++)
            *r++ = (double)nb->x[i + a];
        for (int a = 0; a < 3 * s->vel; a++)
            *r++ = (double)nb->v[i + a];
    }
    return MOTE_OK;
}

/* The trajectory's frame as H5MD (h5md.h): the bodies recorded that are still there (merged
 * ones leave; id: the body's number from 0), positions, velocities with velocities=on, masses;
 * in SI units (m, m/s, s, kg) when the run has physical scales, else dimensionless (no unit
 * attributes). Made anew (append 0) or added at the end. */
static int trajectory_h5md(nb_model *m, const mote_nb *nb, int append, mote_err *err)
{
    const nb_sampler *s = &m->traj;
    const int si = nb->u.set;
    const double L = si ? nb->u.Am : 1, V = si ? 1 / nb->u.kv : 1, T = si ? 1 / nb->u.kt : 1,
                 M = si ? nb->u.M : 1;
    const size_t cap = s->nsel ? s->nsel : 1;
    double *buf = malloc(cap * 7 * sizeof *buf);
    int64_t *id = malloc(cap * sizeof *id);
    int rc;
    if (!buf || !id) {
        rc = mote_fail(err, MOTE_ENOMEM, "trajectory: out of memory");
    } else {
        double *pos = buf, *vel = buf + 3 * cap, *mass = buf + 6 * cap;
        size_t n = 0;
        for (uint32_t k = 0; k < s->nsel; k++) {
            const uint32_t i = s->sel[k];
            if (i >= nb->n || !nb->active[i])
                continue;
            for (int a = 0; a < 3; a++) {
                pos[3 * n + a] = (double)nb->x[3 * (size_t)i + a] * L;
                vel[3 * n + a] = (double)nb->v[3 * (size_t)i + a] * V;
            }
            mass[n] = (double)nb->m[i] * M;
            id[n++] = i;
        }
        mote_h5md_frame fr = {.model = "nbody", .origin = s->origin, .dim = 3, .n = n,
                              .pos = pos, .vel = s->vel ? vel : NULL, .id = id, .nscalar = 1,
                              .time = (double)nb->T * T, .step = (int64_t)nb->steps,
                              .length_unit = si ? "m" : NULL, .time_unit = si ? "s" : NULL};
        fr.scalar[0] = (mote_h5md_scalar){"mass", si ? "kg" : NULL, mass};
        rc = append ? mote_h5md_append(s->path, &fr, err) : mote_h5md_first(s->path, &fr, err);
    }
    free(buf);
    free(id);
    return rc;
}

static int sampler_stream(nb_model *m, nb_sampler *s, int traj, mote_err *err);

/* A sample of the run (the row also to PATH.partial). */
int nb_sample(nb_model *m, int traj, const mote_nb *nb, mote_err *err)
{
    if (traj && m->traj.format == FMT_H5MD)
        return trajectory_h5md(m, nb, 1, err);
    const int rc = traj ? trajectory_sample(m, nb, err) : monitor_sample(m, nb, err);
    return rc ? rc : sampler_stream(m, traj ? &m->traj : &m->mon, traj, err);
}

/* The header lines every output shares after the preamble (spec 10). */
static void run_header(FILE *f, const mote_nb *nb, const nb_sampler *s)
{
    char b[MOTE_REAL_BUF];
    nb_write_header(f, nb);
    if (s->dt > 0)
        fprintf(f, "# sample_dt = %s\n", mote_real_str(s->dt, b));
    else
        fprintf(f, "# every = %llu\n", (unsigned long long)s->every);
    nb_write_units(f, nb);
}

static void put_json(FILE *f, double x)
{
    if (isfinite(x))
        fprintf(f, "%.17g", x);
    else
        fputs("null", f);
}

/* The name of trajectory column c: T, E_kin, E_tot, then x_NAME ... or x3 ... per body. */
static const char *traj_column(const nb_model *m, size_t c, char name[40])
{
    static const char *const head[3] = {"T", "E_kin", "E_tot"};
    static const char *const q[6] = {"x", "y", "z", "vx", "vy", "vz"};
    if (c < 3)
        return head[c];
    const nb_sampler *s = &m->traj;
    size_t per = s->vel ? 6 : 3, k = (c - 3) / per;
    uint32_t i = s->sel[k];
    if (m->nb.name[i][0])
        snprintf(name, 40, "%s_%s", q[(c - 3) % per], m->nb.name[i]);
    else
        snprintf(name, 40, "%s%u", q[(c - 3) % per], i + 1);
    return name;
}

/* A sampler's header lines after the preamble (none in JSON lines). */
static void sampler_header(nb_model *m, const nb_sampler *s, int traj, FILE *f)
{
    if (s->format == FMT_JSONL)
        return;
    const char sep = s->format == FMT_CSV ? ',' : ' ';
    run_header(f, &m->nb, s);
    if (traj) {
        fprintf(f, "# Lx0 = %.17g\n# Ly0 = %.17g\n# Lz0 = %.17g\n", s->L0[0], s->L0[1],
                s->L0[2]);
        for (uint32_t k = 0; k < s->nsel; k++) /* the numbers of the named bodies */
            if (m->nb.name[s->sel[k]][0])
                fprintf(f, "# body_%s = %u\n", m->nb.name[s->sel[k]], s->sel[k] + 1);
        fprintf(f, "# a row per sample: T, E_kin, E_tot, then x y z%s of each recorded body "
                   "(columns x_NAME or xK, K its number)\n", s->vel ? " vx vy vz" : "");
    } else
        fprintf(f, "# dE is (E_corr - E0)/|E0| (absolute, E_corr - E0, when E0 = 0) with "
                   "E_corr = E_tot minus the energy changes "
                   "of merges, dMz the aggregated z moment's (Lz + Sz) relative change and dL "
                   "|L + S - (L + S)0| / |(L + S)0| from the run's start\n");
    if (s->tunit[0]) {
        const char *in = !strcmp(s->tunit, "s") ? "seconds" : !strcmp(s->tunit, "day") ? "days"
                         : !strcmp(s->tunit, "year") ? "Julian years" : "sidereal centuries";
        fprintf(f, "# T_%s = T / %.17g: the time in %s (unit=%s), the last column\n",
                s->tunit, s->tscale, in, s->tunit);
    }
    fputs(s->format == FMT_CSV ? "" : "# columns: ", f);
    if (traj) {
        char name[40];
        for (size_t c = 0; c < s->cols; c++)
            fprintf(f, "%s%s", c ? (char[2]){sep, 0} : "", traj_column(m, c, name));
    } else
        for (int c = 0; c < MON_COLS; c++) {
            if (c)
                fputc(sep, f);
            fputs(MON_NAME[c], f);
        }
    if (s->tunit[0])
        fprintf(f, "%cT_%s", sep, s->tunit);
    fputc('\n', f);
}

/* Sample k's row. */
static void sampler_line(nb_model *m, const nb_sampler *s, int traj, FILE *f, size_t k)
{
    const char *kind = traj ? "nbody-trajectory" : "nbody-monitor";
    const char sep = s->format == FMT_CSV ? ',' : ' ';
    const int tcol = traj ? 0 : 1; /* T */
    const double *r = s->rows + k * s->cols;
    if (s->format == FMT_JSONL) {
        fprintf(f, "{\"format\":\"%s\"", kind);
        for (size_t c = 0; c < s->cols; c++) {
            char name[40];
            fprintf(f, ",\"%s\":", traj ? traj_column(m, c, name) : MON_NAME[c]);
            put_json(f, r[c]);
        }
        if (s->tunit[0]) {
            fprintf(f, ",\"T_%s\":", s->tunit);
            put_json(f, r[tcol] / s->tscale);
        }
        fputs("}\n", f);
        return;
    }
    for (size_t c = 0; c < s->cols; c++) {
        if (c)
            fputc(sep, f);
        fprintf(f, !traj && mon_integer((int)c) ? "%.0f" : "%.17g", r[c]);
    }
    if (s->tunit[0])
        fprintf(f, "%c%.17g", sep, r[tcol] / s->tscale);
    fputc('\n', f);
}

/* A sampler's file header: the preamble (none in JSON lines), then its own lines. */
static void sampler_file_header(FILE *f, nb_model *m, int traj)
{
    const nb_sampler *s = traj ? &m->traj : &m->mon;
    if (s->format != FMT_JSONL)
        mote_datafile_preamble(f, traj ? "nbody-trajectory" : "nbody-monitor", s->origin, 0);
    sampler_header(m, s, traj, f);
}
static void monitor_header(FILE *f, const void *m, int growing)
{
    sampler_file_header(f, (nb_model *)m, 0);
}
static void trajectory_header(FILE *f, const void *m, int growing)
{
    sampler_file_header(f, (nb_model *)m, 1);
}

/* The sample just taken: formatted once, into the rows' text and PATH.partial (the core's rows:
 * followed as it grows; the complete PATH is written when integrate ends). */
static int sampler_stream(nb_model *m, nb_sampler *s, int traj, mote_err *err)
{
    if (!s->path || !s->nrows)
        return MOTE_OK;
    sampler_line(m, s, traj, s->out.text, s->nrows - 1);
    return mote_rows_follow(&s->out, err);
}

/* The end of a run whose result is rc: the complete file (also after a failure: every sample
 * so far), the partial file then removed; kept when the complete file could not be written,
 * or when the run was stopped by the user (mote_rows_end). */
int nb_sampler_finish(nb_model *m, nb_sampler *s, int traj, int rc, mote_err *err)
{
    if (!s->path || s->format == FMT_H5MD) /* (H5MD: every frame is in the file already) */
        return rc;
    return mote_rows_end(&s->out, rc, err);
}

/* At the command: the first sample into PATH.partial, and into PATH when there is none yet (an
 * earlier complete PATH is replaced only by the complete file a run writes). */
static int sampler_begin(nb_model *m, nb_sampler *s, int traj, mote_err *err)
{
    mote_rows_free(&s->out); /* (a new start) */
    if (!s->path)
        return MOTE_OK;
    int rc = mote_rows_open(&s->out, s->path, traj ? trajectory_header : monitor_header, m, err);
    if (rc || !s->nrows)
        return rc;
    sampler_line(m, s, traj, s->out.text, s->nrows - 1);
    return mote_rows_start(&s->out, err);
}

/* unit=NAME: a known unit, and physical scales to convert with. */
int nb_check_time_unit(nb_model *m, const mote_call *c, mote_err *err)
{
    const mote_arg *u = mote_call_opt(c, "unit");
    if (!u)
        return MOTE_OK;
    int k = mote_call_opt_index(c, "unit");
    if (!m->d_scales)
        return mote_call_fail(err, c, k, MOTE_EINVAL,
                              "%s: unit= needs physical scales: set them with units (or a "
                              "generator) first", c->name);
    return MOTE_OK;
}

/* The dimensionless time of one unit= (1 without it); fails at run time when the scales are
 * unknown (a loaded state without them). */
int nb_time_scale(const nb_model *m, const mote_call *c, double *scale, mote_err *err)
{
    const mote_arg *u = mote_call_opt(c, "unit");
    *scale = 1;
    if (!u)
        return MOTE_OK;
    if (!m->nb.u.set)
        return mote_call_fail(err, c, mote_call_opt_index(c, "unit"), MOTE_EINVAL,
                              "%s: unit= needs physical scales (units or a generator)", c->name);
    *scale = mote_nb_time_unit(u->text) * m->nb.u.kt;
    return MOTE_OK;
}

/* The sampler options: every=K or dt=T [unit=U], format=, file=. */
int nb_check_sampler(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int every = mote_call_opt(c, "every") != NULL, dt = mote_call_opt(c, "dt") != NULL;
    if (every + dt != 1)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "%s: give one of every=K (steps) and dt=T (time)", c->name);
    int rc = nb_check_time_unit(m, c, err);
    if (rc)
        return rc;
    const mote_arg *f = mote_call_opt(c, "format");
    if (f && !mote_call_opt(c, "file"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "format"), MOTE_EINVAL,
                              "%s: format= is for a file: give file=FILE", c->name);
    const mote_arg *file = mote_call_opt(c, "file");
    if (file && file->path) { /* (a .csv name is CSV whatever format= says) */
        const char *fmt = mote_path_is_csv(file->path) ? "csv" : f ? f->text : "table";
        if (!strcmp(c->name, "trajectory") && mote_path_is_h5md(file->path))
            fmt = "h5md";
        rc = mote_outputs_note_path(&m->formats, c, mote_call_opt_index(c, "file"), file->path,
                                    fmt, 1, err);
    }
    return rc;
}

/* Start a sampler: a sample now, then every K steps or every T of time during integrate. */
static int sampler_start(nb_model *m, nb_sampler *s, const mote_call *c, size_t cols,
                         mote_err *err)
{
    nb_settle_units(m);
    free(s->path);
    free(s->origin);
    const mote_arg *a = mote_call_opt(c, "file");
    s->path = a ? strdup(a->path) : NULL;
    s->origin = mote_call_origin(c);
    const mote_arg *ev = mote_call_opt(c, "every");
    s->every = ev ? (uint64_t)ev->i : 0;
    double scale;
    int rc = nb_time_scale(m, c, &scale, err);
    if (rc)
        return rc;
    s->dt = nb_opt_real_or(c, "dt", 0) * scale;
    const mote_arg *u = mote_call_opt(c, "unit"); /* the time in the unit the user chose too */
    snprintf(s->tunit, sizeof s->tunit, "%s", u ? u->text : "");
    s->tscale = scale;
    s->t0 = m->nb.T;
    s->at = (mote_schedule){(double)s->t0, (double)s->dt, 1};
    s->format = mote_call_word(c, "format", FMT_TABLE);
    if (s == &m->traj && a && mote_path_is_h5md(a->path))
        s->format = FMT_H5MD;
    s->on = 1;
    s->nrows = 0;
    s->cols = cols;
    s->ekmax = s->t_ekmax = 0;
    s->cpu0 = now_seconds(CLOCK_PROCESS_CPUTIME_ID);
    s->wall0 = now_seconds(CLOCK_MONOTONIC);
    if ((a && !s->path) || !s->origin)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", c->name);
    if (!m->nb.ref_set && m->nb.n)
        mote_nb_set_reference(&m->nb);
    return MOTE_OK;
}

int nb_run_monitor(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int rc = sampler_start(m, &m->mon, c, MON_COLS, err);
    if (!rc && !m->mon.path && m->log) {
        for (size_t k = 0; k < sizeof MON_TERM / sizeof MON_TERM[0]; k++)
            fprintf(m->log, k == 0 ? "%12s" : mon_integer(MON_TERM[k]) ? " %10s" : " %23s",
                    MON_NAME[MON_TERM[k]]);
        fputc('\n', m->log);
    }
    if (!rc && m->nb.n)
        rc = monitor_sample(m, &m->nb, err);
    return rc ? rc : sampler_begin(m, &m->mon, 0, err);
}

/* The stops: the schedule off (what was written stays; a later start begins afresh). */
int nb_run_monitor_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((nb_model *)vm)->mon.on = 0;
    return MOTE_OK;
}
int nb_run_trajectory_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((nb_model *)vm)->traj.on = 0;
    return MOTE_OK;
}
int nb_run_frames_stop(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    m->frames.every = 0;
    m->frames.dt = 0;
    return MOTE_OK;
}
int nb_run_snapshot_stop(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    m->snap.every = 0;
    m->snap.dt = 0;
    return MOTE_OK;
}

/* on|off option: 1 or 0 (dflt when not given) */
int nb_opt_on_off(const mote_call *c, const char *key, int dflt)
{
    return mote_call_on(c, key, dflt);
}

/* A list of bodies LIST (names or numbers, comma-separated) into sel (0-based; NULL: only
 * check the syntax, and numbers against nmax); the count, or -1 after a located error. */
static long body_list(const mote_call *c, const char *key, const mote_nb *nb, uint32_t nmax,
                      uint32_t *sel, mote_err *err)
{
    const char *p = mote_call_opt(c, key)->text;
    int argi = mote_call_opt_index(c, key);
    long k = 0;
    for (;;) {
        char tok[64];
        size_t len = strcspn(p, ",");
        snprintf(tok, sizeof tok, "%.*s", (int)(len < 63 ? len : 63), p);
        int number = len > 0 && strspn(tok, "0123456789") == len;
        if (!(number || mote_nb_name_ok(tok)) || len > 63) {
            mote_call_fail(err, c, argi, MOTE_EINVAL, "%s: %s: expected body names or numbers "
                           "separated by commas, found '%s'", c->name, key, tok);
            return -1;
        }
        long i = number ? (long)strtoul(tok, NULL, 10) - 1 : -1;
        if (number && (i < 0 || i >= (long)nmax)) {
            mote_call_fail(err, c, argi, MOTE_EINVAL, "%s: %s: there is no body %s (there are "
                           "%u)", c->name, key, tok, nmax);
            return -1;
        }
        if (nb) {
            i = mote_nb_find(nb, tok);
            if (i < 0) {
                mote_call_fail(err, c, argi, MOTE_EINVAL, "%s: %s: no body is named '%s'",
                               c->name, key, tok);
                return -1;
            }
            for (long j = 0; j < k; j++)
                if (sel[j] == (uint32_t)i) {
                    mote_call_fail(err, c, argi, MOTE_EINVAL, "%s: %s: body %ld is listed "
                                   "twice", c->name, key, i + 1);
                    return -1;
                }
            sel[k] = (uint32_t)i;
        }
        k++;
        if (!p[len])
            return k;
        p += len + 1;
    }
}

int nb_check_trajectory(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int rc = nb_check_sampler(vm, c, err);
    if (!rc)
        rc = nb_need_bodies(vm, c, err);
    if (!rc && mote_call_opt(c, "bodies") && body_list(c, "bodies", NULL, m->d_bodies, NULL, err) < 0)
        return err->code;
    const int h5md = rc ? 0 : mote_call_h5md(c, "file", FMT_H5MD, err);
    if (h5md < 0)
        return err->code;
    if (h5md && mote_call_opt(c, "unit"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "unit"), MOTE_EINVAL,
                              "trajectory: unit= names the table's time column; an H5MD file "
                              "carries SI units (seconds) when the run has physical scales");
    return rc;
}
int nb_run_trajectory(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    nb_sampler *s = &m->traj;
    nb_settle_units(m);
    free(s->sel);
    s->sel = malloc((m->nb.n ? m->nb.n : 1) * sizeof *s->sel);
    if (!s->sel)
        return mote_fail(err, MOTE_ENOMEM, "trajectory: out of memory");
    s->nsel = m->nb.n;
    for (uint32_t i = 0; i < m->nb.n; i++)
        s->sel[i] = i;
    if (mote_call_opt(c, "bodies")) {
        long k = body_list(c, "bodies", &m->nb, m->nb.n, s->sel, err);
        if (k < 0)
            return err->code;
        s->nsel = (uint32_t)k;
    }
    s->vel = nb_opt_on_off(c, "velocities", 0);
    s->n0 = m->nb.n;
    int rc = sampler_start(m, s, c, 3 + (s->vel ? 6 : 3) * (size_t)s->nsel, err);
    if (rc)
        return rc;
    if (s->format == FMT_H5MD) { /* the first frame, atomically; the others appended */
        mote_rows_free(&s->out);
        return trajectory_h5md(m, &m->nb, 0, err);
    }
    mote_nb_monitor mon;
    mote_nb_measure(&m->nb, &mon);
    for (int a = 0; a < 3; a++)
        m->traj.L0[a] = mon.L[a] + mon.S[a];
    rc = trajectory_sample(m, &m->nb, err);
    return rc ? rc : sampler_begin(m, &m->traj, 1, err);
}

/* ---- approaches (spec 7.9, 10.4) ------------------------------------------------------------- */

int nb_check_approaches(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int rc = nb_need_bodies(vm, c, err);
    if (rc)
        return rc;
    const long k = body_list(c, "body", NULL, m->d_bodies, NULL, err);
    if (k < 0)
        return err->code;
    return k == 1 ? MOTE_OK
                  : mote_call_fail(err, c, mote_call_opt_index(c, "body"), MOTE_EINVAL,
                                   "approaches: body= names one body (found %ld)", k);
}

int nb_approaches_write(nb_model *m, mote_err *err)
{
    if (!m->appr.path)
        return MOTE_OK;
    mote_datafile d;
    int rc = mote_datafile_open(&d, m->appr.path, "nbody-approaches", m->appr.origin, 0, err);
    if (rc)
        return rc;
    nb_write_header(d.f, &m->nb);
    fprintf(d.f, "# body = %u\n# refine = %s\n# a row per interval of %llu steps: the closest "
                 "approach of the body to any other, %s\n",
            m->appr.a.body + 1, m->appr.a.refine ? "on" : "off",
            (unsigned long long)m->appr.every,
            m->appr.a.refine ? "the true minimum inside a step, from the step's polynomial"
                             : "sampled at step ends");
    fprintf(d.f, "# columns: %s\n", m->appr.galactica ? "T_min body distance"
                                                      : "T_min body distance relative_speed");
    const nb_approach *a = &m->appr.a;
    for (size_t k = 0; k < a->nrows; k++) {
        const double *r = a->rows + 4 * k;
        if (m->appr.galactica)
            fprintf(d.f, "%.16E  %.0f  %.16E\n", r[0], r[1], r[2]);
        else
            fprintf(d.f, "%.17g %.0f %.17g %.17g\n", r[0], r[1], r[2], r[3]);
    }
    return mote_datafile_commit(&d, err);
}

int nb_run_approaches(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    nb_settle_units(m);
    uint32_t b = 0;
    if (body_list(c, "body", &m->nb, m->nb.n, &b, err) != 1)
        return err->code ? err->code : MOTE_EINVAL;
    nb_approach_free(&m->appr.a);
    nb_approach_init(&m->appr.a, b, nb_opt_on_off(c, "refine", 0) == 1, err);
    m->appr.every = (uint64_t)mote_call_opt(c, "every")->i;
    m->appr.galactica = mote_call_word(c, "format", NB_FORMAT_NATIVE) == NB_FORMAT_GALACTICA;
    free(m->appr.path);
    free(m->appr.origin);
    m->appr.path = strdup(mote_call_opt(c, "file")->path);
    m->appr.origin = mote_call_origin(c);
    if (!m->appr.path || !m->appr.origin)
        return mote_fail(err, MOTE_ENOMEM, "approaches: out of memory");
    return nb_approaches_write(m, err);
}

/* ---- frames (spec 7.13) ----------------------------------------------------------------------- */

int nb_check_frames(void *vm, const mote_call *c, mote_err *err)
{
    int rc = nb_need_bodies(vm, c, err);
    if (!rc)
        rc = mote_call_check_every_dt(c, 1, err);
    if (!rc)
        rc = nb_check_time_unit(vm, c, err);
    const mote_arg *p = mote_call_opt(c, "prefix");
    if (!rc)
        rc = mote_outputs_note_series(&c->ctx->outputs, c, mote_call_opt_index(c, "prefix"),
                                      p ? p->path : "frame_", ".png", "frames", 0, err);
    const mote_arg *f = mote_call_opt(c, "control");
    if (!rc && f && !mote_outputs_find(&c->ctx->outputs, f->path)) {
        nb_galctl g;
        if ((rc = nb_galctl_read(f->path, 0, 0, &g, err)) != MOTE_OK) {
            char why[sizeof err->msg];
            snprintf(why, sizeof why, "%s", err->msg);
            return mote_call_fail(err, c, mote_call_opt_index(c, "control"), (mote_status)rc,
                                  "frames: %s", why);
        }
    }
    return rc;
}

/* A frame of the bodies nb (the model's, or a view of them at an output time). */
int nb_frame_of(nb_model *m, const mote_nb *nb, mote_err *err)
{
    char *path = mote_series_path(m->frames.prefix, m->frames.count, 6, ".png");
    if (!path)
        return mote_fail(err, MOTE_ENOMEM, "frames: out of memory");
    mote_make_dir_of(path); /* (a prefix= makes its folder) */
    int rc = nb_frame_png(nb, &m->frames.f, path, m->nb.steps, err);
    m->frames.count += !rc;
    free(path);
    return rc;
}

int nb_frame_now(nb_model *m, mote_err *err) { return nb_frame_of(m, &m->nb, err); }

int nb_run_frames(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    nb_settle_units(m);
    double scale;
    int src = nb_time_scale(m, c, &scale, err);
    if (src)
        return src;
    const mote_arg *a = mote_call_opt(c, "prefix");
    char *prefix = strdup(a ? a->path : "frame_");
    if (!prefix)
        return mote_fail(err, MOTE_ENOMEM, "frames: out of memory");
    if (!m->frames.prefix || strcmp(m->frames.prefix, prefix) != 0)
        m->frames.count = 0; /* (the same prefix again continues the numbering) */
    free(m->frames.prefix);
    m->frames.prefix = prefix;
    m->frames.dt = nb_opt_real_or(c, "dt", 0) * scale;
    m->frames.every = m->frames.dt > 0 ? 0 : (uint64_t)mote_call_opt(c, "every")->i;
    m->frames.at = (mote_schedule){(double)m->nb.T, m->frames.dt, 1};
    memset(&m->frames.ctl, 0, sizeof m->frames.ctl);
    if ((a = mote_call_opt(c, "control"))) { /* the control file's graphics values */
        int rc = nb_galctl_read(a->path, 0, 0, &m->frames.ctl, err);
        if (rc)
            return rc;
        nb_frame_from_ctl(&m->frames.f, &m->frames.ctl, m->have_galhead ? m->galhead : NULL);
    } else {
        nb_frame_default(m, &m->frames.ctl, &m->frames.f);
    }
    return nb_frame_now(m, err);
}

void nb_frame_default(const nb_model *m, nb_galctl *g, nb_frame_opts *f)
{
    memset(g, 0, sizeof *g);
    g->ntrio = 1;
    g->trio[0][0] = 14;
    g->trio[0][1] = 10;
    g->trio[0][2] = 1;
    nb_frame_from_ctl(f, g, m->have_galhead ? m->galhead : NULL);
    double R = 0;
    for (uint32_t i = 0; i < m->nb.n; i++)
        if (m->nb.active[i])
            for (int k = 0; k < 3; k++)
                R = fmax(R, fabs((double)m->nb.x[3 * i + (uint32_t)k]));
    f->Xe0 = 512;
    f->Ye0 = 384;
    f->aix = f->biy = R > 0 ? 0.45 * 768 / R : 150;
    f->Rd = 0.08;
    f->amv = 600 / f->aix; /* the fastest body's arrow 60 pixels long */
    f->Kl14 = 1;
    f->np = 1;
}

int nb_picture(void *vm, const char *path, mote_err *err)
{
    const nb_model *m = vm;
    if (!m->nb.n)
        return mote_fail(err, MOTE_EINVAL, "there are no bodies yet");
    nb_galctl g;
    nb_frame_opts f;
    nb_frame_default(m, &g, &f);
    return nb_frame_png(&m->nb, &f, path, m->nb.steps, err);
}

/* ---- snapshot every=K (spec 10.2) ------------------------------------------------------------ */

int nb_check_snapshot(void *vm, const mote_call *c, mote_err *err)
{
    const mote_arg *every = mote_call_opt(c, "every"), *file = mote_call_opt(c, "file");
    const mote_arg *dt = mote_call_opt(c, "dt");
    if (!(every || dt) == !file)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "snapshot: give file=FILE (one now) or "
                              "every=K (one every K steps of integrate) or dt=T (one every T of "
                              "time), not %s", file ? "both" : "neither");
    int rc = mote_call_check_every_dt(c, 0, err);
    if (rc)
        return rc;
    if (file && mote_call_opt(c, "prefix"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "prefix"), MOTE_EINVAL,
                              "snapshot: prefix= is for every=K or dt=T (file= names the one "
                              "file)");
    const mote_arg *p = mote_call_opt(c, "prefix");
    rc = nb_need_bodies(vm, c, err);
    if (!rc)
        rc = nb_check_time_unit(vm, c, err);
    if (!rc && (every || dt)) /* (every=K: numbered by step, dt=T: in order) */
        rc = mote_outputs_note_series(&c->ctx->outputs, c, mote_call_opt_index(c, "prefix"),
                                      p ? p->path : "snapshot_",
                                      mote_call_word(c, "format", NB_FORMAT_NATIVE) ==
                                              NB_FORMAT_GALACTICA ? ".dat" : ".snap",
                                      "snapshots", every ? MOTE_SERIES_BY_STEP : 0, err);
    return rc;
}
int nb_run_snapshot(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const mote_arg *file = mote_call_opt(c, "file");
    if (file) { /* one now, as `write snapshot` (or `write galactica`) writes it */
        nb_settle_units(m);
        char *origin = mote_call_origin(c);
        int rc = !origin ? mote_fail(err, MOTE_ENOMEM, "snapshot: out of memory")
                 : mote_call_word(c, "format", NB_FORMAT_NATIVE) == NB_FORMAT_GALACTICA
                     ? nb_write_galactica(m, file->path, 1, err)
                     : nb_snapshot_write(&m->nb, file->path, origin, err);
        free(origin);
        if (!rc && m->log)
            fprintf(m->log, "snapshot: wrote %s (%u bodies at T = %.17g)\n", file->path,
                    m->nb.n, (double)m->nb.T);
        return rc;
    }
    const mote_arg *p = mote_call_opt(c, "prefix");
    double scale;
    int rc = nb_time_scale(m, c, &scale, err);
    if (rc)
        return rc;
    char *prefix = strdup(p ? p->path : "snapshot_");
    if (prefix && (!m->snap.prefix || strcmp(m->snap.prefix, prefix) != 0))
        m->snap.index = 0; /* (the same prefix again continues the numbering) */
    free(m->snap.prefix);
    free(m->snap.origin);
    m->snap.prefix = prefix;
    m->snap.origin = mote_call_origin(c);
    if (!m->snap.prefix || !m->snap.origin)
        return mote_fail(err, MOTE_ENOMEM, "snapshot: out of memory");
    m->snap.dt = nb_opt_real_or(c, "dt", 0) * scale;
    m->snap.every = m->snap.dt > 0 ? 0 : (uint64_t)mote_call_opt(c, "every")->i;
    m->snap.at = (mote_schedule){(double)m->nb.T, m->snap.dt, 1};
    m->snap.galactica = mote_call_word(c, "format", NB_FORMAT_NATIVE) == NB_FORMAT_GALACTICA;
    return MOTE_OK;
}

