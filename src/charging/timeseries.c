/* timeseries.c: the charging model's `evolve` (spec 6.6, 6.10, 8.1): U(t) of the body, and of
 * its dielectric parts, as a time series. The rows are observers of the core's run loop on the
 * evolution's clock (t = k dt_out and the end): the faithful mode's constant currents, the full
 * mode's tabulated characteristic I(U) (evolve.c), the differential charging's equations
 * integrated from row to row (diff.c). */
#include "mote/charging.h"
#include "mote/datafile.h"
#include "mote/loop.h"
#include "mote/stats.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model.h"

/* The rows' interval: dt= (dt_out=, its earlier name), the monitor's, or the whole time. */
static double evolve_dt(const ch_model *m, const mote_call *c, double T)
{
    const double dflt = m->monitor.path && !mote_call_opt(c, "file") ? m->monitor.dt : T;
    return fmin(mote_call_opt_r(c, "dt", mote_call_opt_r(c, "dt_out", dflt)), T);
}

int ch_run_monitor(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    char *p = strdup(mote_call_opt(c, "file")->path);
    if (!p)
        return mote_fail(err, MOTE_ENOMEM, "monitor: out of memory");
    free(m->monitor.path);
    m->monitor.path = p;
    m->monitor.dt = mote_call_opt(c, "dt")->r;
    m->monitor.as = mote_call_word(c, "format", MOTE_AS_NAME);
    if (m->log && !m->dry)
        fprintf(m->log, "monitor: the time series of every later evolve into %s, a row every "
                        "%g s\n", p, m->monitor.dt);
    return MOTE_OK;
}

int ch_run_monitor_stop(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    free(m->monitor.path); /* (later evolves write no time series unless given file=) */
    m->monitor.path = NULL;
    return MOTE_OK;
}

int ch_check_evolve(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    if (!m->faithful) {
        if (m->field_off)
            return mote_call_fail(err, c, -1, MOTE_EINVAL, "evolve: with field none the currents "
                                  "do not depend on U (use model charging faithful for constant "
                                  "currents)");
        int rc = ch_need_setup(m, c, err);
        if (rc)
            return rc;
    } else if (!m->have_run)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "evolve: no currents yet: run first");
    const mote_arg *dt = mote_call_opt(c, "dt"), *dto = mote_call_opt(c, "dt_out");
    if (dt && dto)
        return mote_call_fail(err, c, mote_call_opt_index(c, "dt_out"), MOTE_EINVAL,
                              "evolve: give dt= (the rows' interval) or dt_out= (its earlier "
                              "name), not both");
    if (dto)
        dt = dto;
    if (dt && dt->r > mote_call_opt(c, "time")->r)
        return mote_call_fail(err, c, mote_call_opt_index(c, dto ? "dt_out" : "dt"),
                              MOTE_EINVAL, "evolve: %s must not exceed time",
                              dto ? "dt_out" : "dt");
    int rc = MOTE_OK;
    if (m->ndiel > 0 && !m->have_sphere) /* the map of the surface potential */
        if (!(rc = ch_note_prefixed(m, c, "_potential.vtk", "potential", err)))
            rc = ch_note_prefixed(m, c, "_potential.png", "potential", err);
    if (!rc && !mote_call_opt(c, "file") && !m->monitor.path && m->check_timeseries)
        rc = ch_note_prefixed(m, c, "_timeseries.csv", "timeseries", err);
    return rc;
}

/* evolve's time-series file, through the core's rows (mote_rows): FILE.partial while evolve
 * goes on (a row at a time: `tail -f`), FILE whole when it ends. The mode's header lines go to
 * head first (series_rows then gives the stream of the rows). */
typedef struct {
    mote_rows rows;
    FILE *head;
    char *head_buf;
    size_t head_len;
    char *origin;
    uint64_t seed;
} ch_series;

static void series_header(FILE *f, const void *vs, int growing)
{
    const ch_series *s = vs;
    mote_datafile_preamble(f, "charging-timeseries", s->origin ? s->origin : "evolve", s->seed);
    if (s->head_buf)
        fwrite(s->head_buf, 1, s->head_len, f);
}

static void series_free(ch_series *s)
{
    mote_rows_free(&s->rows);
    if (s->head)
        fclose(s->head);
    free(s->head_buf);
    free(s->origin);
    memset(s, 0, sizeof *s);
}

/* The header written: where the rows go. */
static FILE *series_rows(ch_series *s)
{
    fflush(s->head);
    return s->rows.text;
}

/* The row just written, followed (s NULL: no file). */
static int series_follow(ch_series *s, mote_err *err)
{
    return s ? mote_rows_follow(&s->rows, err) : MOTE_OK;
}

/* The end of evolve (rc: its result): FILE whole with every row so far (also after a failure),
 * FILE.partial kept when it cannot be written. */
static int series_end(ch_series *s, int rc, mote_err *err)
{
    rc = mote_rows_end(&s->rows, rc, err);
    series_free(s);
    return rc;
}

/* The time-series file of evolve (spec 8.1): file= if given, else the monitor's FILE, else
 * P_timeseries.csv after `output prefix=P` (unless timeseries=off); only MPI rank 0 writes. 1
 * when one is open (its header lines then go to s->head). */
static int open_timeseries(ch_model *m, const mote_call *c, ch_series *s, mote_err *err, int *rc)
{
    *rc = MOTE_OK;
    memset(s, 0, sizeof *s);
    if (ch_mpi_rank(m->ctx ? m->ctx->solo : 0) != 0)
        return 0;
    const mote_arg *f = mote_call_opt(c, "file");
    const char *given = f ? f->path : m->monitor.path;
    char *path = NULL;
    if (!given && (!m->prefix || !m->out_timeseries))
        return 0;
    if (!given) {
        const size_t len = strlen(m->prefix) + 32;
        if (!(path = malloc(len))) {
            *rc = mote_fail(err, MOTE_ENOMEM, "evolve: out of memory");
            return 0;
        }
        snprintf(path, len, "%s_timeseries.csv", m->prefix);
    }
    s->origin = mote_call_origin(c);
    s->seed = m->seed;
    s->head = open_memstream(&s->head_buf, &s->head_len);
    *rc = !s->head ? mote_fail(err, MOTE_ENOMEM, "evolve: out of memory")
                   : mote_rows_open(&s->rows, given ? given : path, series_header, s, err);
    if (!*rc && !f && given) /* (the monitor's file: its format=) */
        s->rows.as = m->monitor.as;
    if (!*rc && m->log && !given)
        fprintf(m->log, "output: writing %s\n", path);
    free(path);
    if (*rc)
        series_free(s);
    return *rc == MOTE_OK;
}

/* The columns of the time series after t_s Q_C U_V sigma_U_V I_net_A (spec 8.1). */
static void timeseries_columns(const ch_model *m, FILE *out)
{
    fprintf(out, "# columns: t_s Q_C U_V sigma_U_V I_net_A");
    for (int s = 0; s < m->plasma.nsp; s++)
        fprintf(out, " I_%s_A Nreal_%s", m->plasma.sp[s].name, m->plasma.sp[s].name);
    fprintf(out, " I_see_A I_photo_A\n");
}

/* Full mode (spec 6.6): C dU/dt = I_net(U) from the tabulated characteristic. */
/* evolve's rows at t = k dt (and at T), through the core's loop: the clock moves from stop to
 * stop (the table or the equations give the state at any time; advance() integrates them), the
 * row is the observer. */
typedef struct {
    double t;
    int (*advance)(void *ctx, double t, mote_err *err); /* NULL: nothing to integrate */
    void *ctx;
} evolve_clock;

static double evolve_clock_now(const void *vc) { return ((const evolve_clock *)vc)->t; }
static int evolve_clock_advance(void *vc, mote_loop *l, double t_stop, uint64_t n_stop,
                                mote_err *err)
{
    evolve_clock *c = vc;
    int rc = c->advance ? c->advance(c->ctx, t_stop, err) : MOTE_OK;
    if (!rc)
        c->t = t_stop;
    return rc;
}

/* A row, then followed in the time series' partial file. */
typedef struct {
    int (*row)(void *rows, void *subject, mote_err *err);
    void *rows;
    ch_series *series;
} followed_row;

static int followed_fire(void *vx, void *subject, mote_err *err)
{
    followed_row *x = vx;
    int rc = x->row(x->rows, subject, err);
    return rc ? rc : series_follow(x->series, err);
}

static int evolve_clock_run_with(const mote_call *call, int (*row)(void *, void *, mote_err *),
                                 void *rows, ch_series *series, mote_schedule *at, double T,
                                 int (*advance)(void *, double, mote_err *), void *ctx,
                                 mote_err *err)
{
    evolve_clock c = {0, advance, ctx};
    const mote_runner r = {.what = "evolve", .sys = &c, .ctx = call->ctx,
                           .clock = evolve_clock_now, .advance = evolve_clock_advance};
    followed_row x = {row, rows, series};
    const mote_observer o = {.at = at, .ctx = &x, .fire = followed_fire};
    return mote_run(&r, &o, 1, NULL, T, UINT64_MAX, err);
}

static int evolve_clock_run(const mote_call *call, int (*row)(void *, void *, mote_err *),
                            void *rows, ch_series *series, mote_schedule *at, double T,
                            mote_err *err)
{
    return evolve_clock_run_with(call, row, rows, series, at, T, NULL, NULL, err);
}

/* A row of the full mode's time series at `time`. */
typedef struct {
    ch_model *m;
    const ch_table *t;
    double C;
    int f;
    FILE *out;
    double nreal[MOTE_CH_MAX_SPECIES];
    double last; /* the time of the last row */
    mote_schedule at;
} full_rows;

static void full_row_at(full_rows *x, double time)
{
    ch_model *m = x->m;
    const ch_table *t = x->t;
    const double C = x->C, U = ch_table_u_at(t, time);
    const int nsp = m->plasma.nsp;
    FILE *out = x->out;
    /* the real particles collected since the last row: 32 trapezoids */
    for (int q = 0; q < 32 && time > x->last; q++) {
        const double ta = x->last + (time - x->last) * q / 32;
        const double tb = x->last + (time - x->last) * (q + 1) / 32;
        const double ua = ch_table_u_at(t, ta), ub = ch_table_u_at(t, tb);
        for (int s = 0; s < nsp; s++)
            x->nreal[s] += 0.5 * (tb - ta) *
                           (fabs(ch_table_col(t, ua, s)) + fabs(ch_table_col(t, ub, s))) /
                           (abs(m->plasma.sp[s].Z) * MOTE_CH_E);
    }
    x->last = time;
    const double sU = ch_table_col(t, U, nsp + 2) * fmin(time, t->tau) / C;
    if (x->f) {
        fprintf(out, "%.10g %.10g %.10g %.10g %.10g", time, C * U, U, sU, ch_table_eval(t, U));
        for (int s = 0; s < nsp; s++)
            fprintf(out, " %.10g %.10g", ch_table_col(t, U, s), x->nreal[s]);
        fprintf(out, " %.10g %.10g\n", ch_table_col(t, U, nsp), ch_table_col(t, U, nsp + 1));
    } else {
        fprintf(out, "evolve: t %.10g s Q %.10g C U %.10g V I %.10g A\n", time, C * U, U,
                ch_table_eval(t, U));
    }
    if (m->legacy_stdout && m->log) { /* the original's columns: Q U t collisions */
        double ntot = 0;
        for (int s = 0; s < nsp; s++)
            ntot += x->nreal[s];
        fprintf(m->log, "%.10g %.10g %.10g %.10g\n", C * U, U, time, ntot);
    }
}

static int full_row(void *vx, void *subject, mote_err *err)
{
    full_rows *x = vx;
    if (x->out)
        full_row_at(x, mote_schedule_next(&x->at));
    return MOTE_OK;
}

static int evolve_full(ch_model *m, const mote_call *c, mote_err *err)
{
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    const double T = mote_call_opt(c, "time")->r, dt = evolve_dt(m, c, T);
    const double U0 = mote_call_opt_r(c, "U0", 0), C = g.capacitance;
    if (ch_build_tri_materials(m, err))
        return err->code;
    mote_ch_run_opts o = ch_run_opts(m, c, &g); /* (the field on: full mode) */
    mote_ch_tracer *tr = ch_model_tracer(m, err);
    if (!tr)
        return err->code;
    ch_table t;
    mote_progress prog; /* one line for all the runs of the table */
    mote_progress_begin(&prog, c->ctx, c->name);
    o.progress = &prog;
    int rc = ch_table_build(&m->plasma, &m->body, tr, &o, U0, &t, err);
    mote_progress_end(&prog);
    mote_ch_tracer_free(tr);
    if (!rc)
        rc = ch_table_times(&t, C, err);
    if (rc) {
        ch_table_free(&t);
        return rc;
    }
    ch_series d;
    const int f = open_timeseries(m, c, &d, err, &rc);
    if (rc) {
        ch_table_free(&t);
        return rc;
    }
    FILE *out = f ? d.head : m->log;
    if (f) {
        fprintf(out, "# mode = full (C dU/dt = I_net(U), the characteristic tabulated at %d "
                     "potentials, %llu histories per component each; the species' and emission "
                     "currents interpolated linearly between them; sigma_U = sigma_I min(t, tau) "
                     "/ C, an estimate)\n# C_F = %.10g\n# U_f_V = %.10g\n# tau_s = %.10g\n",
                t.n, (unsigned long long)o.particles, C, t.Uf, t.tau);
        timeseries_columns(m, out);
        out = series_rows(&d);
    }
    if (m->log)
        fprintf(m->log, "evolve: I(U) tabulated at %d potentials from %g V to %g V; U_f = %.6g V, "
                        "tau = C/|dI/dU| = %.4g s; 50%% of U_f at %.4g s, 90%% at %.4g s\n",
                t.n, t.U[0], t.U[t.n - 1], t.Uf, t.tau, ch_table_t_at(&t, U0 + 0.5 * (t.Uf - U0)),
                ch_table_t_at(&t, U0 + 0.9 * (t.Uf - U0)));
    full_rows x = {m, &t, C, f, out, {0}, 0, {0, dt, 0}};
    int rc2 = evolve_clock_run(c, full_row, &x, f ? &d : NULL, &x.at, T, err);
    if (!rc2 && out && fabs(x.last - T) > 1e-12 * T) { /* the end, between two rows */
        full_row_at(&x, T);
        rc2 = series_follow(f ? &d : NULL, err);
    }
    ch_table_free(&t);
    return f ? series_end(&d, rc2, err) : rc2;
}

/* ---- differential charging (spec 6.10) ---- */

typedef struct {
    ch_model *m;
    const mote_ch_tracer *tr;
    mote_ch_run_opts o;
    const int *tri_patch;
    int runs;
    double Ic, sig, Ip[CH_MAX_PATCHES]; /* faithful: the run's constant currents */
    int *tri_cond;                      /* direct: each triangle's conductor in m->fbem */
    double cV[CH_MAX_PATCHES + 1];      /* and theirs potentials */
} patch_node_ctx;

/* The currents of the triangles of patch p (-1: the conductor) in a run: collected, emitted,
 * photoelectrons; with var, its variance: the collected current's binomial one, and the
 * emitted and photoelectron currents' variances shared in proportion to the part's share of
 * those currents (the run keeps them for the whole body only). */
static double part_current_v(const ch_model *m, const mote_ch_result *r, const int *tri_patch,
                             int p, double *var)
{
    const uint32_t ntri = r->ntri;
    double I = 0, v = 0;
    int comp = 0;
    for (int s = 0; s < r->nsp; s++)
        for (int k = 0; k < m->plasma.sp[s].ncomp; k++, comp++) {
            uint64_t h = 0;
            double see = 0, see_all = 0;
            for (uint32_t i = 0; i < ntri; i++) {
                const size_t q = (size_t)comp * ntri * 2 + 2 * (size_t)i;
                const double si = r->tri_see ? r->tri_see[q] + r->tri_see[q + 1] : 0;
                see_all += si;
                if (tri_patch[i] != p)
                    continue;
                h += r->tri_hits[q] + r->tri_hits[q + 1];
                see += si;
            }
            const double w = r->weight[s][k], N = (double)r->histories;
            I += w * (double)h + see;
            v += w * w * (double)h * (N > 0 ? 1 - (double)h / N : 1);
            if (see_all != 0)
                v += r->see_sigma[s][k] * r->see_sigma[s][k] * fabs(see / see_all);
        }
    double ph = 0, ph_all = 0;
    for (uint32_t i = 0; r->tri_photo && i < ntri; i++) {
        const double x = r->tri_photo[2 * (size_t)i] + r->tri_photo[2 * (size_t)i + 1];
        ph_all += x;
        if (tri_patch[i] == p)
            ph += x;
    }
    I += ph;
    if (ph_all != 0)
        v += r->photo_sigma * r->photo_sigma * fabs(ph / ph_all);
    if (var)
        *var = v;
    return I;
}

static double part_current(const ch_model *m, const mote_ch_result *r, const int *tri_patch,
                           int p)
{
    return part_current_v(m, r, tri_patch, p, NULL);
}

static int patch_node(void *vx, double U, double *Ic, double *sig, double *Ip, mote_err *err)
{
    patch_node_ctx *x = vx;
    if (x->m->faithful) { /* constant currents, whatever the potentials */
        *Ic = x->Ic;
        *sig = x->sig;
        for (int p = 0; p < x->m->ndiel; p++)
            for (int g = 0; g < x->o.ndv; g++)
                Ip[(size_t)p * (size_t)x->o.ndv + (size_t)g] = x->Ip[p];
        return MOTE_OK;
    }
    mote_ch_run_opts q = x->o;
    q.potential = U;
    mote_ch_result r;
    int rc = mote_ch_run(&x->m->plasma, &x->m->body, x->tr, &q, &r, err);
    if (rc)
        return rc;
    x->runs++;
    mote_ch_net(&r, sig);
    *Ic = part_current(x->m, &r, x->tri_patch, -1);
    memcpy(Ip, r.patch_I, (size_t)x->m->ndiel * (size_t)q.ndv * sizeof *Ip);
    mote_ch_result_free(&r);
    return MOTE_OK;
}

/* The solved field with the conductors at their own potentials V (the state's order: the
 * conductor, then the parts): a run there, each one's net current into J. */
static int patch_direct(void *vx, const double *V, double *J, double *sJ, double *sig,
                        mote_err *err)
{
    patch_node_ctx *x = vx;
    const ch_model *m = x->m;
    for (int k = 0; k < m->fbem.nc; k++)
        x->cV[k] = V[m->fstate[k]];
    mote_ch_run_opts q = x->o;
    q.potential = V[0];
    q.tree = NULL;
    q.bem = &m->fbem;
    q.tri_cond = x->tri_cond;
    q.cond_V = x->cV;
    q.theta = m->theta;
    q.tri_patch = NULL;
    q.npatch = q.ndv = 0;
    q.dv = NULL;
    mote_ch_result r;
    int rc = mote_ch_run(&m->plasma, &m->body, x->tr, &q, &r, err);
    if (rc)
        return rc;
    x->runs++;
    mote_ch_net(&r, sig);
    for (int p = -1; p < m->ndiel; p++) {
        double v;
        J[1 + p] = part_current_v(m, &r, x->tri_patch, p, &v);
        sJ[1 + p] = sqrt(v);
    }
    mote_ch_result_free(&r);
    return MOTE_OK;
}

/* The name of triangle i's part (the exact sphere: its one part). */
static const char *body_part_name(const ch_model *m, uint32_t i)
{
    return m->body.sphere ? "sphere" : m->body.part_name[m->body.part[i]];
}

/* A row of the differential charging's time series at `time` (the state integrated to it). */
typedef struct {
    ch_model *m;
    ch_patches *P;
    double C;
    int f;
    FILE *out;
    int np;
    double y[CH_MAX_PATCHES + 1], t, h; /* the state, its time, the integrator's step */
    double dvmax, t_dvmax;
    int p_dvmax;
    double last; /* the time of the last row (-1: none) */
    mote_schedule at;
} patch_rows;

static int patch_advance(void *vr, double time, mote_err *err)
{
    patch_rows *r = vr;
    return ch_patches_advance(r->P, r->y, &r->h, time, &r->t, err);
}

static int patch_row_at(patch_rows *r, double time, mote_err *err)
{
    ch_model *m = r->m;
    ch_patches *P = r->P;
    const double *y = r->y, C = r->C;
    const int np = r->np;
    FILE *out = r->out;
    int rc = time > r->t ? patch_advance(r, time, err) : MOTE_OK;
    r->last = time;
    double Ic, Ip[CH_MAX_PATCHES], sig, I;
    if (rc || (rc = ch_patches_currents(P, y[0], y + 1, &Ic, Ip, &sig, err)) != 0)
        return rc;
    I = Ic;
    double dm = 0;
    for (int p = 0; p < np; p++) {
        I += Ip[p];
        dm = fmax(dm, fabs(y[1 + p]));
        if (fabs(y[1 + p]) > r->dvmax) {
            r->dvmax = fabs(y[1 + p]);
            r->p_dvmax = p;
            r->t_dvmax = time;
        }
    }
    if (r->f) {
        /* sigma_U: the net current's error over min(t, tau), tau = C / |dI/dU| (faithful:
         * sigma_I t / C) */
        double sU = sig * time / C;
        if (P->direct) /* the float's */
            sU = P->sigma_U;
        else if (!m->faithful) {
            const double e = 1e-3 * P->scale;
            double Ic2, Ip2[CH_MAX_PATCHES], I2 = 0;
            if ((rc = ch_patches_currents(P, y[0] + e, y + 1, &Ic2, Ip2, NULL, err)) != 0)
                return rc;
            I2 = Ic2;
            for (int p = 0; p < np; p++)
                I2 += Ip2[p];
            const double slope = fabs(I2 - I) / e;
            sU = sig * fmin(time, slope > 0 ? C / slope : time) / C;
        }
        fprintf(out, "%.10g %.10g %.10g %.10g %.10g", time, ch_patches_charge(P, y), y[0], sU, I);
        for (int p = 0; p < np; p++)
            fprintf(out, " %.10g", y[0] + y[1 + p]);
        fprintf(out, " %.10g\n", dm);
    } else if (out) {
        fprintf(out, "evolve: t %.10g s U %.10g V", time, y[0]);
        for (int p = 0; p < np; p++)
            fprintf(out, " V_%s %.10g V", m->diel[p].part, y[0] + y[1 + p]);
        fputc('\n', out);
    }
    return MOTE_OK;
}

static int patch_row(void *vr, void *subject, mote_err *err)
{
    patch_rows *r = vr;
    return patch_row_at(r, mote_schedule_next(&r->at), err);
}

/* What evolve and float share for a body with dielectric parts: each triangle's part (-1: the
 * conductor), the parts' areas, the circuit P (its layers, leaks, and in the solved field its
 * capacitance matrix and the conductors' labels), the node's and the direct run's context x,
 * and the tracer (none in faithful mode). */
typedef struct {
    ch_patches P;
    patch_node_ctx x;
    int *tri_patch;
    mote_ch_tracer *tr;
    double area[CH_MAX_PATCHES], C;
    uint32_t ntri;
} patch_setup;

static void patches_close(patch_setup *s)
{
    mote_ch_tracer_free(s->tr);
    free(s->tri_patch);
    free(s->x.tri_cond);
    ch_patches_free(&s->P);
}

static int patches_setup(ch_model *m, const mote_call *c, const char *cmd, double U0,
                         patch_setup *s, mote_err *err)
{
    memset(s, 0, sizeof *s);
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    const double C = g.capacitance;
    const uint32_t ntri = m->body.sphere ? 1 : m->body.ntri;
    const int np = m->ndiel;
    ch_patches *P = &s->P;
    double *area = s->area, eps[CH_MAX_PATCHES];
    s->C = C;
    s->ntri = ntri;
    int *tri_patch = s->tri_patch = malloc((size_t)ntri * sizeof *tri_patch);
    if (!tri_patch)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", cmd);
    for (uint32_t i = 0; i < ntri; i++) {
        tri_patch[i] = -1;
        for (int p = 0; p < np; p++)
            if (!strcmp(body_part_name(m, i), m->diel[p].part)) {
                tri_patch[i] = p;
                area[p] += m->body.sphere ? 4 * MOTE_CH_PI * m->body.sphere_r * m->body.sphere_r
                                          : m->body.area[i] * (m->body.closed[i] ? 1 : 2);
            }
    }
    int rc = MOTE_OK;
    for (int p = 0; p < np && !rc; p++) {
        eps[p] = m->diel[p].eps_r > 0 ? m->diel[p].eps_r : ch_part_eps(m, m->diel[p].part);
        if (!(eps[p] >= 1))
            rc = mote_call_fail(err, c, -1, MOTE_EINVAL, "%s: dielectric part '%s' has no "
                                "permittivity: give eps_r= to dielectric, or assign it a "
                                "material with one (kapton, teflon, cover-glass)", cmd,
                                m->diel[p].part);
        else if (!(area[p] > 0))
            rc = mote_call_fail(err, c, -1, MOTE_EINVAL, "%s: dielectric part '%s' has no "
                                "triangles", cmd, m->diel[p].part);
        P->Cp[p] = MOTE_CH_EPS0 * eps[p] * area[p] / m->diel[p].d;
        const double sig = /* (sigma= of dielectric, else the part's material's) */
            m->diel[p].sigma >= 0 ? m->diel[p].sigma : ch_part_sigma(m, m->diel[p].part);
        P->Rp[p] = sig > 0 ? m->diel[p].d / (sig * area[p]) : INFINITY;
    }
    if (!rc)
        rc = ch_patches_init(P, np, ch_smallest_kT(m), U0, err);
    if (!rc && !m->faithful)
        rc = ch_build_tri_materials(m, err);
    patch_node_ctx *x = &s->x;
    x->m = m;
    x->tri_patch = tri_patch;
    if (!rc && m->faithful) { /* the last run's currents */
        x->Ic = part_current(m, &m->res, tri_patch, -1);
        for (int p = 0; p < np; p++)
            x->Ip[p] = part_current(m, &m->res, tri_patch, p);
        mote_ch_net(&m->res, &x->sig);
    } else if (!rc && !(s->tr = ch_model_tracer(m, err)))
        rc = err->code;
    if (rc)
        return rc;
    x->tr = s->tr;
    x->o = ch_run_opts(m, c, &g);
    x->o.tri_patch = tri_patch;
    x->o.npatch = np;
    x->o.dv = P->dv;
    x->o.ndv = P->ndv;
    P->C = C;
    if (m->field_solved && !m->field_off && m->ftree && !m->faithful) { /* the solved field
                                     * (not a tree kept from before `field sphere`): its
                                     * capacitance matrix (symmetrized:
                                     * collocation makes it reciprocal to the discretization's
                                     * error), the conductors at their own potentials */
        const int nc = m->fbem.nc, n = np + 1;
        P->have_cv = 1;
        for (int k = 0; k < nc; k++)
            for (int l = 0; l < nc; l++)
                P->Cv[m->fstate[k] * n + m->fstate[l]] =
                    0.5 * (m->fbem.cmat[k * nc + l] + m->fbem.cmat[l * nc + k]);
        int cond_of[CH_MAX_PATCHES + 1];
        for (int k = 0; k < nc; k++)
            cond_of[m->fstate[k]] = k;
        if (!(x->tri_cond = malloc((size_t)ntri * sizeof *x->tri_cond)))
            return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", cmd);
        for (uint32_t i = 0; i < ntri; i++)
            x->tri_cond[i] = cond_of[tri_patch[i] + 1];
        P->direct = patch_direct;
        P->dv_step = 5 * P->scale;
    }
    P->node = patch_node;
    P->ctx = x;
    return MOTE_OK;
}

/* patches_setup, and on failure what it made freed */
static int patches_open(ch_model *m, const mote_call *c, const char *cmd, double U0,
                        patch_setup *s, mote_err *err)
{
    const int rc = patches_setup(m, c, cmd, U0, s, err);
    if (rc)
        patches_close(s);
    return rc;
}

/* The map of the surface potential at the state y (time: the evolution's, or -1 for a steady
 * state), when output asks for files (not the exact sphere). */
static int patches_map(ch_model *m, const patch_setup *S, const double *y, double time,
                       const char *cmd, mote_err *err)
{
    if (!m->prefix || m->body.sphere)
        return MOTE_OK;
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    double *V = malloc((size_t)S->ntri * sizeof *V);
    if (!V)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", cmd);
    for (uint32_t i = 0; i < S->ntri; i++)
        V[i] = y[0] + (S->tri_patch[i] >= 0 ? y[1 + S->tri_patch[i]] : 0);
    ch_output oo = ch_output_of(m, &g, &S->x.o, y[0]);
    oo.tri_V = V;
    oo.time = time;
    const int rc = ch_write_potential(&oo, m->log, err);
    free(V);
    return rc;
}

static int evolve_patches(ch_model *m, const mote_call *c, mote_err *err)
{
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    const double T = mote_call_opt(c, "time")->r, dt = evolve_dt(m, c, T);
    const double U0 = m->faithful ? 0 : mote_call_opt_r(c, "U0", 0);
    const int np = m->ndiel;
    patch_setup S;
    int rc = patches_open(m, c, "evolve", U0, &S, err);
    if (rc)
        return rc;
    ch_patches *P = &S.P;
    patch_node_ctx *x = &S.x;
    const double C = S.C;
    mote_progress prog; /* one line for all the runs */
    mote_progress_begin(&prog, c->ctx, c->name);
    x->o.progress = &prog;
    ch_series d;
    const int f = open_timeseries(m, c, &d, err, &rc);
    FILE *out = f ? d.head : m->log;
    if (f) {
        if (P->direct)
            fprintf(out, "# mode = full with %d dielectric part%s in the solved field, the "
                         "conductors at their own potentials (issue 55): (Cv + layers) dV/dt = "
                         "the currents, each step's from runs at its potentials; the common mode "
                         "floated at every step, the differentials by explicit steps of at most "
                         "%g V or a quarter of themselves\n# C_F = %.10g\n", np, np > 1 ? "s" : "",
                    P->dv_step, C);
        else
            fprintf(out, "# mode = %s with %d dielectric part%s (spec 6.10: C dU/dt = sum I, C_p "
                         "d(V_p - U)/dt = I_p - (V_p - U)/R_p; implicit Euler extrapolated, "
                         "tolerance 1e-7)\n# C_F = %.10g\n",
                    m->faithful ? "faithful" : "full", np, np > 1 ? "s" : "", C);
        if (P->have_cv) {
            if (!P->direct)
                fprintf(out, "# circuit: C replaced by the solved field's capacitance matrix Cv "
                             "of the conductor and the parts' outer surfaces (issue 55): (Cv + "
                             "layers) dV/dt = the currents\n");
            fputs("# Cv_F =", out);
            for (int q = 0; q < (np + 1) * (np + 1); q++)
                fprintf(out, " %.10g", P->Cv[q]);
            fputc('\n', out);
        }
        for (int p = 0; p < np; p++)
            fprintf(out, "# A_%s_m2 = %.10g\n# C_p_%s_F = %.10g\n# R_p_%s_ohm = %.10g\n",
                    m->diel[p].part, S.area[p], m->diel[p].part, P->Cp[p], m->diel[p].part,
                    P->Rp[p]);
        fprintf(out, "# columns: t_s Q_C U_V sigma_U_V I_net_A");
        for (int p = 0; p < np; p++)
            fprintf(out, " V_%s_V", m->diel[p].part);
        fputs(" dV_max_V\n", out);
        out = series_rows(&d);
    }
    patch_rows r = {m, P, C, f, out, np, {U0}, 0, 1e-9 * T, 0, 0, 0, -1, {0, dt, 0}};
    if (!rc && P->direct) { /* the common mode floats at once */
        rc = ch_patches_float(P, r.y, err);
        if (!rc && m->log)
            fprintf(m->log, "evolve: the conductors at their own potentials in the solved field: "
                            "the common mode floated at every step (at the start U = %.6g V, "
                            "its time constant %.3g s), the differentials in steps of at most "
                            "%g V or a quarter of themselves\n", r.y[0], P->tau_c, P->dv_step);
    }
    if (!rc)
        rc = evolve_clock_run_with(c, patch_row, &r, f ? &d : NULL, &r.at, T, patch_advance, &r,
                                   err);
    if (!rc && fabs(r.last - T) > 1e-12 * T) /* the end, between two rows */
        if (!(rc = patch_row_at(&r, T, err)))
            rc = series_follow(f ? &d : NULL, err);
    double *y = r.y, dvmax = r.dvmax, t_dvmax = r.t_dvmax;
    const int p_dvmax = r.p_dvmax;
    mote_progress_end(&prog);
    if (!rc && m->log && P->direct)
        fprintf(m->log, "evolve: %d dielectric part%s; %ld steps, currents from %ld runs; the "
                        "common mode's time constant at the end %.3g s\n", np, np > 1 ? "s" : "",
                P->steps, P->runs, P->tau_c);
    else if (!rc && m->log)
        fprintf(m->log, "evolve: %d dielectric part%s; %ld steps, currents from %d node%s%s\n", np,
                np > 1 ? "s" : "", P->steps, P->nn, P->nn == 1 ? "" : "s",
                m->faithful ? " (faithful: the last run's constant currents)" : "");
    if (!rc && m->log) {
        for (int p = 0; p < np; p++) {
            const double tau = P->Cp[p] * P->Rp[p];
            fprintf(m->log, "evolve: dielectric %s: A = %.6g m^2, C_p = %.6g F, R_p = %.6g ohm, "
                            "tau_p = %.6g s; at t = %g s V_p = %.8g V, V_p - U = %.8g V\n",
                    m->diel[p].part, S.area[p], P->Cp[p], P->Rp[p], tau, T, y[0] + y[1 + p],
                    y[1 + p]);
        }
        fprintf(m->log, "evolve: at t = %g s U = %.8g V; the largest |V_p - U| %.6g V (%s, at t "
                        "= %g s)\n", T, y[0], dvmax, m->diel[p_dvmax].part, t_dvmax);
    }
    if (!rc)
        rc = patches_map(m, &S, y, T, "evolve", err);
    patches_close(&S);
    return f ? series_end(&d, rc, err) : rc;
}

/* float with dielectric parts (issue 55): the steady state of the conductor and the parts, where
 * the whole net current is zero and each part's current equals its leak (none: zero). In the
 * solved field each evaluation is a run with the conductors at their own potentials; otherwise
 * the currents come from the tables evolve uses (spec 6.10). The capacitance matrix does not
 * enter a steady state; evolve is what uses it. */
int ch_float_patches(ch_model *m, const mote_call *c, mote_err *err)
{
    const double U0 = mote_call_opt_r(c, "U0", 0), tol = mote_call_opt_r(c, "tolerance", 1e-4);
    const int np = m->ndiel;
    patch_setup S;
    int rc = patches_open(m, c, "float", U0, &S, err);
    if (rc)
        return rc;
    ch_patches *P = &S.P;
    mote_progress prog; /* one line for all the runs */
    mote_progress_begin(&prog, c->ctx, c->name);
    S.x.o.progress = &prog;
    double y[CH_MAX_PATCHES + 1] = {U0}, sy[CH_MAX_PATCHES + 1];
    int iters = 0;
    if (P->direct) /* the common mode first: a start near the root */
        rc = ch_patches_float(P, y, err);
    if (!rc)
        rc = ch_patches_steady(P, y, tol, &iters, sy, err);
    double Ic = 0, Ip[CH_MAX_PATCHES] = {0}, sig = 0;
    if (!rc)
        rc = ch_patches_currents(P, y[0], y + 1, &Ic, Ip, &sig, err);
    mote_progress_end(&prog);
    if (!rc && m->log) {
        fprintf(m->log, "float: the steady state of the conductor and %d dielectric part%s (%s): "
                        "U = %.6g V +- %.3g; %d %s steps, ",
                np, np > 1 ? "s" : "",
                P->direct ? "the solved field, each at its own potential"
                          : "the patches' circuit of spec 6.10",
                y[0], isfinite(sy[0]) ? sy[0] : P->sigma_U, iters,
                P->direct ? "Newton" : "implicit");
        if (P->direct)
            fprintf(m->log, "%ld runs of %llu histories per component\n", P->runs,
                    (unsigned long long)S.x.o.particles);
        else
            fprintf(m->log, "currents from %d node%s\n", P->nn, P->nn == 1 ? "" : "s");
        double leaks = 0, I = Ic;
        for (int p = 0; p < np; p++) {
            leaks += isfinite(P->Rp[p]) ? y[1 + p] / P->Rp[p] : 0;
            I += Ip[p];
        }
        fprintf(m->log, "float: conductor: I = %+.6g A", Ic);
        if (leaks != 0)
            fprintf(m->log, " and %+.6g A through the dielectrics", leaks);
        fprintf(m->log, "; the whole net current %+.3g A +- %.3g\n", I, sig);
        if (fabs(I) > 3 * sig) /* (Newton stopped inside the noise of its steps, not of I) */
            fprintf(m->log, "float: warning: the whole net current there is %.1f sigma from "
                            "zero: the steady state is looser than its errors say; more "
                            "particles= tighten it\n", fabs(I) / sig);
        for (int p = 0; p < np; p++) {
            fprintf(m->log, "float: dielectric %s: V_p = %.6g V, V_p - U = %.6g V", m->diel[p].part,
                    y[0] + y[1 + p], y[1 + p]);
            if (isfinite(sy[1 + p]))
                fprintf(m->log, " +- %.3g", sy[1 + p]);
            fprintf(m->log, "; its current %+.6g A, its leak %+.6g A\n", Ip[p],
                    isfinite(P->Rp[p]) ? y[1 + p] / P->Rp[p] : 0.0);
        }
    }
    if (!rc) {
        mote_call_result(c, "U_f", y[0]);
        for (int p = 0; p < np; p++) {
            char key[64];
            snprintf(key, sizeof key, "V_%s", m->diel[p].part);
            mote_call_result(c, key, y[0] + y[1 + p]);
        }
        rc = patches_map(m, &S, y, -1, "float", err);
    }
    patches_close(&S);
    return rc;
}

/* Faithful mode (spec 1.2): constant currents, Q = I t and U = Q / C. */
/* A row of the faithful mode's time series (constant currents: Q = I t). */
typedef struct {
    ch_model *m;
    double inet, C, sig;
    int f;
    FILE *out;
    double last; /* the time of the last row (-1: none) */
    mote_schedule at;
} faithful_rows;

static void faithful_row_at(faithful_rows *x, double t)
{
    ch_model *m = x->m;
    FILE *out = x->out;
    const int f = x->f;
    const double inet = x->inet, C = x->C;
    x->last = t;
    fprintf(out, f ? "%.10g %.10g %.10g %.10g %.10g" : "evolve: t %.10g s Q %.10g C U %.10g V "
                                                      "+- %.3g I %.10g A",
            t, inet * t, inet * t / C, x->sig * t / C, inet);
    for (int s = 0; s < m->plasma.nsp; s++) {
        const double nreal = fabs(m->res.current[s]) * t / (abs(m->plasma.sp[s].Z) * MOTE_CH_E);
        if (f)
            fprintf(out, " %.10g %.10g", m->res.current[s], nreal);
        else
            fprintf(out, " N_%s %.10g", m->plasma.sp[s].name, nreal);
    }
    fputs(f ? " 0 0\n" : "\n", out); /* (faithful: no emission) */
    if (m->legacy_stdout && m->log) { /* the original's columns: Q U t collisions */
        double ntot = 0;
        for (int s = 0; s < m->plasma.nsp; s++)
            ntot += fabs(m->res.current[s]) * t / (abs(m->plasma.sp[s].Z) * MOTE_CH_E);
        fprintf(m->log, "%.10g %.10g %.10g %.10g\n", inet * t + 0.0, inet * t / C + 0.0, t, ntot);
    }
}

static int faithful_row(void *vx, void *subject, mote_err *err)
{
    faithful_rows *x = vx;
    if (x->out)
        faithful_row_at(x, mote_schedule_next(&x->at));
    return MOTE_OK;
}

int ch_run_evolve(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    if (ch_field_prepare(m, c, err))
        return err->code;
    if (m->ndiel > 0) {
        if (!m->faithful)
            ch_diagnose(m, "evolve");
        return evolve_patches(m, c, err);
    }
    if (!m->faithful) {
        ch_diagnose(m, "evolve");
        return evolve_full(m, c, err);
    }
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    const double T = mote_call_opt(c, "time")->r;
    const double dt = evolve_dt(m, c, T);
    double inet = 0, var = 0;
    for (int s = 0; s < m->plasma.nsp; s++) {
        inet += m->res.current[s];
        var += m->res.sigma[s] * m->res.sigma[s];
    }
    const double C = g.capacitance, sig = sqrt(var);
    ch_series d;
    int rc;
    const int f = open_timeseries(m, c, &d, err, &rc);
    if (rc)
        return rc;
    FILE *out = f ? d.head : m->log;
    if (f) {
        fprintf(out, "# mode = faithful (constant currents, Q = I t, U = Q / C)\n# C_F = %.10g\n"
                     "# area_m2 = %.10g\n# histories = %llu\n", C, g.area,
                (unsigned long long)m->res.histories);
        timeseries_columns(m, out);
        out = series_rows(&d);
    } else if (out) {
        fprintf(out, "evolve: dU/dt = %.10g V/s (I = %.10g A, C = %.10g F)\n", inet / C, inet, C);
    }
    faithful_rows x = {m, inet, C, sig, f, out, -1, {0, dt, 0}};
    rc = evolve_clock_run(c, faithful_row, &x, f ? &d : NULL, &x.at, T, err);
    if (!rc && out && fabs(x.last - T) > 1e-12 * T) { /* the end, between two rows */
        faithful_row_at(&x, T);
        rc = series_follow(f ? &d : NULL, err);
    }
    return f ? series_end(&d, rc, err) : rc;
}
