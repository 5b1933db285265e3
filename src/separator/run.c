/* run.c: the separator's run and what it writes (specs/separator.md 2.13, 3): `run` through the
 * core's loop with the scheduled outputs (frames, the live picture, snapshots, the balance) as
 * its observers, the status line, `tromp`, `profiles`, `save`, `load` and `summary`. A command
 * checked on the dry model (sep_check_*) runs on the real one only after the whole script
 * passed. */
#include "mote/h5md.h"
#include "mote/vtk.h"
#include "mote/separator.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "mote/datafile.h"
#include "mote/loop.h"
#include "mote/render.h"
#include "model.h"

/* The status line of spec 2.13 (key=value), after every command (the model's status hook). */
void sep_status(void *vm, FILE *out)
{
    const mote_sep_system *s = &((sep_model *)vm)->sys;
    uint64_t fed = 0, fines = 0, coarse = 0, lost = 0;
    for (int k = 0; k < s->nsp; k++) {
        fed += s->cnt[k].fed;
        fines += s->cnt[k].fines;
        coarse += s->cnt[k].coarse;
        lost += s->cnt[k].lost;
    }
    double *T = malloc((size_t)(s->nclass > 0 ? s->nclass : 1) * sizeof *T);
    mote_sep_cut cut = {NAN, NAN, NAN, NAN, NAN, NAN, 0};
    if (T && s->class_edge && s->cl_nf)
        mote_sep_tromp(s, T, &cut);
    free(T);
    double eps_max = 0;
    for (int k = 0; s->eps_s && k < s->K; k++)
        eps_max = fmax(eps_max, s->eps_s[k]);
    fprintf(out, "t=%.10g steps=%llu dt=%.6g N=%zu fed=%llu fines=%llu coarse=%llu lost=%llu "
                 "backlog=%zu d50=%.6g kappa=%.4g eps_max=%.4g max_overlap=%.4g fast_moves=%llu\n",
            s->t, (unsigned long long)s->steps, s->dt, s->n, (unsigned long long)fed,
            (unsigned long long)fines, (unsigned long long)coarse, (unsigned long long)lost,
            s->nback, cut.d50, cut.kappa, eps_max, s->max_overlap,
            (unsigned long long)s->fast_moves);
}

/* What a run leaves to be said: overlaps beyond the allowed, a backlog. */
static void run_notes(sep_model *m)
{
    const mote_sep_system *s = &m->sys;
    if (s->dem && s->max_overlap > 2 * s->delta_f && !(s->khat > 0))
        fprintf(m->log, "note: the largest overlap %.3g of a diameter is more than twice the "
                        "allowed %.3g: raise vimp= (stiffness) or lower the impact speeds\n",
                s->max_overlap, s->delta_f);
    if (s->nback > 0)
        fprintf(m->log, "warning: %zu particles wait in the feed's backlog: the feed outruns its "
                        "band (lower the rate, or widen the band: feed hf= and feed_window)\n",
                s->nback);
}

/* Particles lost in this run (beyond a side wall, inside a plate, or not finite: a velocity
 * that overflowed) leave a state that cannot be trusted: the run ends with an error naming
 * them (exit 2), the state kept as it is for a look (`save`, snapshots). */
static uint64_t lost_count(const mote_sep_system *s)
{
    uint64_t lost = 0;
    for (int k = 0; k < s->nsp; k++)
        lost += s->cnt[k].lost;
    return lost;
}

static int run_advance(void *vm, mote_loop *l, double t_stop, uint64_t n_stop, mote_err *err);
static double run_clock(const void *vm);
static uint64_t run_count(const void *vm);
static int live_picture(sep_model *m, mote_err *err);
static int fire_frame(void *ctx, void *subject, mote_err *err);
static int fire_snapshot(void *ctx, void *subject, mote_err *err);
static int fire_balance(void *ctx, void *subject, mote_err *err);
static int fire_trajectory(void *ctx, void *subject, mote_err *err);
static int run_end(sep_model *m, mote_err *err);
static int make_series_dir(const char *prefix, const char *ext, mote_err *err);

/* `summary`: each species' bookkeeping (the status line follows, as after every command). */
int sep_summary(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    (void)c;
    (void)err;
    if (!m->log)
        return MOTE_OK;
    const mote_sep_system *s = &m->sys;
    for (int k = 0; k < s->nsp; k++) {
        const mote_sep_count *q = &s->cnt[k];
        fprintf(m->log, "species %s: fed %llu (%.6g kg), fines %llu (%.6g kg), coarse %llu "
                        "(%.6g kg), lost %llu\n",
                s->sp[k].name, (unsigned long long)q->fed, q->m_fed,
                (unsigned long long)q->fines, q->m_fines, (unsigned long long)q->coarse,
                q->m_coarse, (unsigned long long)q->lost);
    }
    fprintf(m->log, "balance: fed = in channel + fines + coarse + lost %s\n",
            mote_sep_check_balance(s) ? "DOES NOT HOLD" : "holds");
    return MOTE_OK;
}

/* What `run`, `save`, `tromp` and `profiles` need: a system that prepares. */
int sep_check_ready(void *vm, const mote_call *c, mote_err *err)
{
    return sep_need_ready(vm, c, err);
}

double sep_mean_mass(const mote_sep_system *s, int k)
{
    enum { M = 1024 }; /* the distribution's table at M midpoints of its number-basis CDF */
    double sum = 0;
    for (int i = 0; i < M; i++) {
        const double d = mote_sep_dist_sample(&s->sp[k].dist, (i + 0.5) / M);
        sum += d * d * d;
    }
    return s->sp[k].rho * SEP_PI / 6 * sum / M;
}

/* The cost model of a run's estimate, from this machine's measurements (bench/README.md, the
 * separator; AMD EPYC, one thread, -O3): a step's fixed cost (the gas slices, the schedules:
 * 10 particles, 1.7e5 steps in 1.09 s) and a particle-step's (the 2D reference case, 92.5 ns
 * with contacts and coupling; the dilute mode costs about as much, 1e-7 s); the memory per
 * particle (255 B in the reference case) and the program's own; a run over an hour is long. */
#define SEP_EST_STEP_S 6.5e-6
#define SEP_EST_PARTICLE_STEP_S 1.0e-7
#define SEP_EST_BYTES 260.0
/* contact hertz (bench_separator bed: a settled bed, 3.6-4.4 contacts per particle, 95-133 ns
 * per particle-step over settling and steps on one thread, 1191-1601 B per particle) */
#define SEP_EST_HERTZ_PARTICLE_STEP_S 1.4e-7
#define SEP_EST_HERTZ_BYTES 1600.0
#define SEP_EST_BASE_BYTES 3e7
#define SEP_EST_LONG_S 3600.0

/* A duration in words: "40 s", "12 min", "3.1 h", "17 days". */
static void duration_words(double t, char *out, size_t cap)
{
    if (t < 120)
        snprintf(out, cap, "%.2g s", t);
    else if (t < 7200)
        snprintf(out, cap, "%.2g min", t / 60);
    else if (t < 2 * 86400)
        snprintf(out, cap, "%.2g h", t / 3600);
    else if (t < 2 * 365.25 * 86400)
        snprintf(out, cap, "%.2g days", t / 86400);
    else
        snprintf(out, cap, "%.2g years", t / (365.25 * 86400));
}

int sep_check_run(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    int rc = sep_need_ready(m, c, err);
    if (rc || !m->dry)
        return rc;
    const mote_sep_system *s = &m->sys;
    if (s->hertz && (s->khat > 0 || s->delta_f != 0.05) && !m->warned_stiffness) {
        m->warned_stiffness = 1;
        mote_call_warn(c, "contact hertz takes its stiffness from the species' E and nu: "
                          "stiffness overlap= and khat= do not apply (vimp= still sets the "
                          "impact speed of the time step)");
    }
    const double T = c->args[0].r, t0 = fmax(m->est_t, s->t); /* (s->t: a state loaded) */
    const double steps = ceil(T / s->dt - 1e-9);
    /* a run that cannot finish is refused before anything runs, as the run would refuse it */
    if (!(T / s->dt <= SEP_STEPS_MAX))
        return mote_call_fail(err, c, -1, MOTE_ERUNTIME,
                              "run: the time step %.3g s would take %.2g steps to reach t = %g "
                              "s: this run cannot finish (the gas speed, the stiffness or the "
                              "sizes make the step this small; `timestep DT` sets it)",
                              s->dt, T / s->dt, t0 + T);
    /* the particles fed in this run's time (the feed's window), by the feed's mass fractions,
     * and how long each stays: from the feed to the exit its still-gas slip U0 - v_t(d) takes
     * it to (for ever towards a closed end, or hovering at the cut size), at most the run */
    double fed = 0, stay_avg = 0, stay_end = 0;
    const double a = fmax(t0, s->t_start), b = fmin(t0 + T, s->t_stop);
    if (s->rate > 0 && b > a) {
        double rho_g, mu_g;
        mote_sep_gas_props(s, s->zf, &rho_g, &mu_g);
        const double L = b - a;
        enum { M = 256 };
        for (int k = 0; k < s->nsp; k++) {
            if (!(s->sp[k].w > 0 && s->sp[k].have_dist))
                continue;
            const double nk = s->rate * L * s->sp[k].w / (s->parcel * sep_mean_mass(s, k));
            double avg = 0, end = 0;
            for (int i = 0; i < M; i++) {
                const double d = mote_sep_dist_sample(&s->sp[k].dist, (i + 0.5) / M);
                const double slip =
                    s->U0 - mote_sep_terminal_velocity(d, s->sp[k].rho, rho_g, mu_g, s->g, NULL);
                double tau = INFINITY;
                if (slip > 0 && s->open_top)
                    tau = (s->H - s->zf) / slip;
                else if (slip < 0 && s->open_bottom)
                    tau = s->zf / -slip;
                /* fed uniformly at u in [a, b], each in the channel until min(u + tau, E),
                 * E = t0 + T: over x = E - u in [x0, x1] the mean of min(tau, x) (its share of
                 * the run's mean count) and the fraction with x < tau (still there at the end) */
                const double x0 = t0 + T - b, x1 = t0 + T - a;
                avg += tau >= x1   ? 0.5 * (x0 + x1)
                       : tau <= x0 ? tau
                                   : (0.5 * (tau * tau - x0 * x0) + tau * (x1 - tau)) / L;
                end += fmin(fmax((fmin(tau, x1) - x0) / L, 0), 1);
            }
            fed += nk;
            stay_avg += nk * (avg / M) / T;
            stay_end += nk * end / M;
        }
    }
    const double n0 = fmax(m->est_n, (double)s->n), nmax = n0 + stay_end, navg = n0 + stay_avg;
    const int threads = c->ctx && c->ctx->threads > 1 ? c->ctx->threads : 1;
    const double ps = s->hertz ? SEP_EST_HERTZ_PARTICLE_STEP_S : SEP_EST_PARTICLE_STEP_S;
    const double wall = steps * (SEP_EST_STEP_S + ps * navg / threads);
    /* (with mesh walls and hertz, each particle's wall springs: 4 numbers a slot) */
    const double wall_springs = s->hertz && s->nmesh ? 4.0 * SEP_MESH_SLOTS * sizeof(double) : 0;
    const double mem = SEP_EST_BASE_BYTES +
                       nmax * (s->hertz ? SEP_EST_HERTZ_BYTES + wall_springs : SEP_EST_BYTES);
    m->est_n = nmax;
    m->est_t = t0 + T;
    char w[32];
    duration_words(wall, w, sizeof w);
    if (c->ctx && c->ctx->check_only)
        mote_call_note(c, "run %g s: %.3g steps of %.3g s; %.3g %s fed, about %.3g in the "
                          "channel on average, %.3g at the end; about %s on %d thread%s, "
                          "about %.3g MB",
                       T, steps, s->dt, fed, s->parcel > 1 ? "parcels" : "particles", navg, nmax,
                       w, threads, threads == 1 ? "" : "s", mem / 1e6);
    if (wall > SEP_EST_LONG_S)
        mote_call_warn(c, "run %g s would take about %s (%.3g steps of %.3g s, about %.3g "
                          "particles); coarser sizes (size ... min=), a softer contact "
                          "(stiffness overlap= vimp=), collisions off with parcels (parcel W) "
                          "where the solids are dilute, a lower feed rate or a shorter run "
                          "shorten it (docs/separator.md, \"How long a run takes\")",
                       T, w, steps, s->dt, navg);
    return MOTE_OK;
}

/* `tromp` and `profiles`: also the picture beside the table (FILE's stem + .png), recorded so
 * that the check reports a later command that writes it again. */
int sep_check_table(void *vm, const mote_call *c, mote_err *err)
{
    int rc = sep_need_ready(vm, c, err);
    const mote_arg *f = mote_call_opt(c, "file");
    if (rc || !f->path || !c->ctx)
        return rc;
    char *png = sep_png_name(f->path);
    rc = png ? mote_outputs_note_path(&c->ctx->outputs, c, mote_call_opt_index(c, "file"), png,
                                      "image", 0, err)
             : mote_fail(err, MOTE_ENOMEM, "%s: out of memory", c->name);
    free(png);
    return rc;
}

int sep_run(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    int rc = sep_need_ready(m, c, err);
    if (!rc && m->frames.on)
        rc = make_series_dir(m->frames.prefix, ".png", err);
    if (!rc && m->snaps.on)
        rc = make_series_dir(m->snaps.prefix, ".xyz", err);
    /* the run loop: the scheduled outputs as observers, progress on a terminal */
    mote_observer obs[5];
    size_t nobs = 0;
    sep_schedule *outs[5] = {m->frames.on ? &m->frames.when : NULL,
                             m->snaps.on ? &m->snaps.when : NULL,
                             m->bal.on ? &m->bal.when : NULL,
                             m->traj.on ? &m->traj.when : NULL,
                             m->ckpt.on ? &m->ckpt.when : NULL};
    for (int k = 0; k < 5; k++)
        if (outs[k])
            obs[nobs++] = outs[k]->o;
    for (int k = 0; k < 5 && !rc; k++) /* every=K: the first at the start, as dt='s */
        if (outs[k] && outs[k]->first) {
            outs[k]->first = 0;
            rc = outs[k]->o.fire(NULL, m, err);
        }
    mote_progress prog;
    mote_progress_begin(&prog, m->ctx, "run");
    /* the passes over the particles on the script's threads (the same bits on any number) */
    m->sys.threads = m->ctx && m->ctx->threads > 1 ? m->ctx->threads : 1;
    if (!rc)
        rc = live_picture(m, err);
    const uint64_t lost_before = lost_count(&m->sys);
    const mote_runner r = {.what = "run", .sys = m, .ctx = m->ctx, .clock = run_clock,
                           .count = run_count, .advance = run_advance};
    m->prepared = 0;
    if (!rc)
        rc = mote_run(&r, obs, nobs, &prog, m->sys.t + c->args[0].r, UINT64_MAX, err);
    if (!rc && !m->prepared && !(rc = mote_sep_prepare(&m->sys, err)))
        m->prepared = 1;
    if (m->prepared) /* (outputs that failed before the first step: nothing ran) */
        rc = mote_sep_run_end(&m->sys, rc, err);
    if (!rc && m->live.on) { /* (the live picture ends on the state the run ended in) */
        m->live.last = -INFINITY;
        rc = live_picture(m, err);
    }
    if (!rc && lost_count(&m->sys) > lost_before)
        rc = mote_fail(err, MOTE_ERUNTIME, "run: %llu particles were lost by t = %g s (beyond a "
                       "side wall, inside a plate, or not finite: a speed or force that "
                       "overflowed; check the gas speed, the stiffness and the time step)",
                       (unsigned long long)(lost_count(&m->sys) - lost_before), m->sys.t);
    mote_progress_end(&prog);
    m->loop = NULL;
    if (!rc)
        rc = run_end(m, err);
    mote_rows_keep(&m->bal.out); /* a run that failed: its rows so far stay */
    if (!rc && m->log)
        run_notes(m);
    return rc;
}

/* `tromp FILE`: the grade-efficiency table and its plot (spec 3.1). */
int sep_tromp(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    int rc = sep_need_ready(m, c, err);
    if (rc)
        return rc;
    char *origin = mote_call_origin(c);
    mote_sep_cut cut;
    const mote_arg *file = mote_call_opt(c, "file");
    rc = sep_write_tromp(&m->sys, file->path, origin ? origin : "tromp", m->seed, &cut, err);
    free(origin);
    if (!rc) {
        mote_call_result(c, "d50", cut.d50);
        mote_call_result(c, "kappa", cut.kappa);
    }
    if (!rc && m->log)
        fprintf(m->log, "tromp: wrote %s and its plot: d50 %.6g m, kappa %.4g\n", file->text,
                cut.d50, cut.kappa);
    return rc;
}

/* `save FILE`: the whole state (spec 2.12). */
int sep_save(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    int rc = sep_need_ready(m, c, err);
    if (rc)
        return rc;
    rc = mote_sep_save(&m->sys, m->seed, c->args[0].path, err);
    if (!rc && m->log)
        fprintf(m->log, "save: wrote %s (t = %.10g s, %zu particles)\n", c->args[0].text,
                m->sys.t, m->sys.n);
    return rc;
}

/* `load FILE`: continue from a saved state. The dry model reads it too when it exists and no
 * earlier `save` of the script writes it (then the dry model already is that state). */
static int load(sep_model *m, const mote_call *c, mote_err *err)
{
    uint64_t seed;
    mote_err e2 = {0};
    int rc = mote_sep_load(&m->sys, &seed, c->args[0].path, &e2);
    if (rc)
        return mote_call_fail(err, c, 0, rc, "%s", e2.msg);
    m->seed = seed;
    m->have_channel = m->have_gas = 1;
    return MOTE_OK;
}

int sep_check_load(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    if (m->ctx && mote_outputs_find(&m->ctx->outputs, c->args[0].path))
        return MOTE_OK;
    return load(m, c, err);
}

int sep_load(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    int rc = load(m, c, err);
    if (!rc && m->log)
        fprintf(m->log, "load: read %s (t = %.10g s, %zu particles)\n", c->args[0].text,
                m->sys.t, m->sys.n);
    return rc;
}

/* `profiles FILE`: the height profiles and their plot (spec 3.2). */
int sep_profiles(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    int rc = sep_need_ready(m, c, err);
    if (rc)
        return rc;
    char *origin = mote_call_origin(c);
    const mote_arg *file = mote_call_opt(c, "file");
    rc = sep_write_profiles(&m->sys, file->path, origin ? origin : "profiles", m->seed, err);
    free(origin);
    if (rc == MOTE_EINVAL) { /* (nothing averaged yet): located at the command */
        char why[sizeof err->msg];
        snprintf(why, sizeof why, "%s", err->msg);
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "%s", why);
    }
    if (!rc && m->log)
        fprintf(m->log, "profiles: wrote %s and its plot (averaged over %.6g s)\n", file->text,
                m->sys.prof_time);
    return rc;
}

/* The frame options shared by `frames` and `live`. */
static int frame_opts(const mote_call *c, sep_frame_opts *fo, mote_err *err)
{
    fo->px = (int)mote_call_opt_r(c, "px", 900);
    const mote_arg *col = mote_call_opt(c, "color"); /* size|species */
    fo->by_species = col && col->i == 1;
    fo->y1 = mote_call_opt_r(c, "y1", 0);
    fo->y2 = mote_call_opt_r(c, "y2", 0);
    if ((mote_call_opt(c, "y1") || mote_call_opt(c, "y2")) && !(fo->y2 > fo->y1))
        return mote_call_fail(err, c, mote_call_opt_index(c, "y1"), MOTE_EINVAL,
                              "%s: the slab needs y1 < y2", c->name);
    return MOTE_OK;
}

/* The balance file's header: the preamble, whether the invariant held, the columns. */
static void balance_header(FILE *f, const void *vm, int growing)
{
    const sep_model *m = vm;
    mote_datafile_preamble(f, "separator-balance", m->bal.origin, m->seed);
    sep_balance_text(f, &m->sys, m->bal.held, NULL, 0, 0, 1);
}

/* An output's schedule from its call: dt=T or every=K steps, the first at the next run's start
 * (the loop fires a time due at its start; the run itself fires the first of every=K). */
static void schedule_set(sep_schedule *w, const mote_call *c, const mote_sep_system *s,
                         int (*fire)(void *, void *, mote_err *))
{
    w->o = mote_call_observer(c, &w->at, s->t, s->steps, 1, NULL, fire);
    w->at.k = 0;
    w->first = w->o.at == NULL;
}

/* A series of numbered files PREFIX_NNNNNN.EXT (prefix=P; dir=DIR is the prefix DIR/NAME, the
 * earlier form): exactly one of the two; the prefix's folder is made when the run starts. The
 * same prefix again continues the numbering (*index), another starts it at 0. Validation records
 * the series, so that check reports files that would overwrite each other. */
static int out_series(sep_model *m, const mote_call *c, char **prefix, uint64_t *index,
                      const char *name, const char *ext, mote_err *err)
{
    const mote_arg *d = mote_call_opt(c, "dir"), *p = mote_call_opt(c, "prefix");
    const int at = mote_call_opt_index(c, p ? "prefix" : "dir");
    if (!!d == !!p)
        return mote_call_fail(err, c, d && p ? at : -1, MOTE_EINVAL, "%s: give prefix=P (files "
                              "P_000000%s, ...) or dir=DIR (DIR/%s_000000%s, ...)%s", c->name,
                              ext, name, ext, d ? ", not both" : "");
    const size_t n = strlen(d ? d->path : p->path) + strlen(name) + 2;
    char *pre = malloc(n);
    if (!pre)
        return mote_call_fail(err, c, at, MOTE_ENOMEM, "out of memory");
    if (d)
        snprintf(pre, n, "%s/%s", d->path, name);
    else
        snprintf(pre, n, "%s", p->path);
    int rc = m->dry ? mote_outputs_note_series(&m->ctx->outputs, c, at, pre, ext, c->name,
                                               MOTE_SERIES_MAKES_DIR, err)
                    : MOTE_OK;
    if (rc) {
        free(pre);
        return rc;
    }
    if (!*prefix || strcmp(*prefix, pre) != 0)
        *index = 0;
    free(*prefix);
    *prefix = pre;
    return MOTE_OK;
}

int sep_frames(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    int rc = mote_call_check_every_dt(c, 1, err);
    if (!rc)
        rc = frame_opts(c, &m->frames.fo, err);
    if (!rc)
        rc = out_series(m, c, &m->frames.prefix, &m->frames.index, "frame", ".png", err);
    if (rc)
        return rc;
    /* the movie: DIR/movie.mp4, or P.mp4 (P ending in '/': Pmovie.mp4) */
    const mote_arg *dir = mote_call_opt(c, "dir");
    const char *base = dir ? dir->path : m->frames.prefix;
    const size_t n = strlen(base) + 16, bl = strlen(base);
    char *mp = malloc(n);
    if (!mp)
        return mote_fail(err, MOTE_ENOMEM, "frames: out of memory");
    snprintf(mp, n, "%s%s", base, dir ? "/movie.mp4" : bl && base[bl - 1] == '/' ? "movie.mp4" : ".mp4");
    free(m->frames.movie_path);
    m->frames.movie_path = mp;
    const mote_arg *mv = mote_call_opt(c, "movie"); /* on|off */
    const int movie_off = mv && mv->i == 1;
    m->frames.on = 1;
    schedule_set(&m->frames.when, c, &m->sys, fire_frame);
    m->frames.movie = !movie_off;
    m->frames.fps = (int)mote_call_opt_r(c, "fps", 20);
    return MOTE_OK;
}

int sep_live_png(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    int rc = frame_opts(c, &m->live.fo, err);
    if (rc)
        return rc;
    char *p = strdup(mote_call_opt(c, "file")->path);
    if (!p)
        return mote_fail(err, MOTE_ENOMEM, "live_png: out of memory");
    free(m->live.path);
    m->live.path = p;
    m->live.on = 1;
    m->live.hz = fmin(mote_call_opt_r(c, "hz", 30), 30);
    m->live.last = -INFINITY;
    m->live.gap = 1 / m->live.hz;
    return MOTE_OK;
}

enum { FORMAT_XYZ, FORMAT_H5MD, FORMAT_VTK }; /* format=e{xyz|h5md|vtk} (vtk: snapshot) */

/* A trajectory's or snapshot's file: FILE.xyz, FILE.h5|.h5md or (a snapshot) FILE.vtk, as
 * format= says when given; 1 for H5MD, 2 for VTK, 0 for XYZ, -1 after a located error. */
static int particles_format(const mote_call *c, int snapshot, mote_err *err)
{
    const int vtk = mote_call_vtk(c, "file", snapshot ? FORMAT_VTK : -1, err);
    if (vtk)
        return vtk < 0 ? -1 : FORMAT_VTK;
    const int h5md = mote_call_h5md(c, "file", FORMAT_H5MD, err);
    const mote_arg *f = mote_call_opt(c, "file");
    const size_t n = f ? strlen(f->text) : 0;
    if (h5md == 0 && f && (n < 4 || strcmp(f->text + n - 4, ".xyz") != 0)) {
        mote_call_fail(err, c, mote_call_opt_index(c, "file"), MOTE_EINVAL,
                       "%s: FILE must end in .xyz (extended XYZ)%s .h5 (H5MD)%s, found '%s'",
                       c->name, snapshot ? "," : " or", snapshot ? " or .vtk (VTK)" : "",
                       f->text);
        return -1;
    }
    return h5md;
}

static const char *const format_ext[] = {".xyz", ".h5", ".vtk"};

/* The command's text for the files it writes (the origin kept in *slot). */
static int keep_origin(char **slot, const mote_call *c, mote_err *err)
{
    char *o = mote_call_origin(c);
    if (!o)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", c->name);
    free(*slot);
    *slot = o;
    return MOTE_OK;
}

int sep_snapshots(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    const mote_arg *f = mote_call_opt(c, "file");
    const int sched = mote_call_opt(c, "dt") || mote_call_opt(c, "every");
    const int h5md = particles_format(c, 1, err);
    if (h5md < 0)
        return err->code;
    if (f) { /* the configuration now */
        if (sched || mote_call_opt(c, "dir") || mote_call_opt(c, "prefix"))
            return mote_call_fail(err, c, mote_call_opt_index(c, "file"), MOTE_EINVAL,
                                  "%s: file= writes one snapshot now; a series on a schedule "
                                  "takes dt= or every= and prefix= (or dir=), not file=", c->name);
        if (m->dry)
            return MOTE_OK;
        if (h5md == FORMAT_XYZ)
            return sep_write_xyz(&m->sys, f->path, err);
        if (h5md == FORMAT_VTK)
            return sep_write_vtk(&m->sys, f->path, err);
        char *o = mote_call_origin(c);
        int rc = o ? sep_write_h5md(&m->sys, f->path, o, m->seed, 0, err)
                   : mote_fail(err, MOTE_ENOMEM, "%s: out of memory", c->name);
        free(o);
        return rc;
    }
    if (!sched)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "%s: give file=FILE (one snapshot now) or "
                              "dt=DT or every=K with prefix=P or dir=DIR (a series)", c->name);
    int rc = mote_call_check_every_dt(c, 1, err);
    if (rc)
        return rc;
    rc = out_series(m, c, &m->snaps.prefix, &m->snaps.index, "snapshot", format_ext[h5md],
                    err);
    if (!rc)
        rc = keep_origin(&m->snaps.origin, c, err);
    if (rc)
        return rc;
    m->snaps.h5md = h5md;
    m->snaps.on = 1;
    schedule_set(&m->snaps.when, c, &m->sys, fire_snapshot);
    return MOTE_OK;
}

int sep_balance(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    int rc = mote_call_check_every_dt(c, 1, err);
    if (rc)
        return rc;
    char *p = strdup(mote_call_opt(c, "file")->path), *o = mote_call_origin(c);
    if (!p || !o) {
        free(p);
        free(o);
        return mote_fail(err, MOTE_ENOMEM, "balance: out of memory");
    }
    free(m->bal.origin);
    m->bal.origin = o;
    mote_rows_free(&m->bal.out);
    rc = mote_rows_open(&m->bal.out, p, balance_header, m, err);
    free(p);
    if (rc)
        return rc;
    m->bal.out.as = mote_call_word(c, "format", MOTE_AS_NAME);
    m->bal.on = 1;
    schedule_set(&m->bal.when, c, &m->sys, fire_balance);
    m->bal.held = 1;
    return MOTE_OK;
}


/* The scheduled outputs, observers of the run loop (subject: the model). */
static int fire_frame(void *ctx, void *subject, mote_err *err)
{
    sep_model *m = subject;
    char *p = mote_series_path(m->frames.prefix, m->frames.index++, 6, ".png");
    int rc = p ? sep_frame_png(&m->sys, p, &m->frames.fo, err) : mote_fail(err, MOTE_ENOMEM, "frames");
    free(p);
    return rc;
}

static int fire_snapshot(void *ctx, void *subject, mote_err *err)
{
    sep_model *m = subject;
    char *p = mote_series_path(m->snaps.prefix, m->snaps.index++, 6, format_ext[m->snaps.h5md]);
    int rc = !p ? mote_fail(err, MOTE_ENOMEM, "snapshots")
             : m->snaps.h5md == FORMAT_H5MD
                 ? sep_write_h5md(&m->sys, p, m->snaps.origin, m->seed, 0, err)
             : m->snaps.h5md == FORMAT_VTK ? sep_write_vtk(&m->sys, p, err)
                                           : sep_write_xyz(&m->sys, p, err);
    free(p);
    return rc;
}

static int fire_balance(void *ctx, void *subject, mote_err *err)
{
    sep_model *m = subject;
    if (!m->bal.row && !(m->bal.row = malloc(sep_balance_width(&m->sys) * sizeof *m->bal.row)))
        return mote_fail(err, MOTE_ENOMEM, "balance: out of memory");
    sep_balance_row(&m->sys, m->bal.row);
    if (mote_sep_check_balance(&m->sys))
        m->bal.held = 0;
    /* the row once as text; followed as it grows in PATH.partial (the core's rows) */
    sep_balance_text(m->bal.out.text, &m->sys, m->bal.held, m->bal.row, 0, 1, 0);
    return mote_rows_follow(&m->bal.out, err);
}

/* A frame of the trajectory: the first replaces FILE (atomically), the others are appended. */
static int fire_trajectory(void *ctx, void *subject, mote_err *err)
{
    sep_model *m = subject;
    const int more = m->traj.frames > 0;
    int rc = mote_path_is_h5md(m->traj.path)
                 ? sep_write_h5md(&m->sys, m->traj.path, m->traj.origin, m->seed, more, err)
             : more ? mote_frames_append(m->traj.path, sep_xyz_frame, &m->sys, err)
                    : mote_frames_first(m->traj.path, sep_xyz_frame, &m->sys, err);
    m->traj.frames += !rc;
    return rc;
}

int sep_trajectory(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    int rc = mote_call_check_every_dt(c, 1, err);
    if (rc)
        return rc;
    const mote_arg *f = mote_call_opt(c, "file");
    if (particles_format(c, 0, err) < 0)
        return err->code;
    rc = keep_origin(&m->traj.origin, c, err);
    char *p = rc ? NULL : strdup(f->path);
    if (!p)
        return rc ? rc : mote_fail(err, MOTE_ENOMEM, "trajectory: out of memory");
    free(m->traj.path);
    m->traj.path = p;
    m->traj.frames = 0;
    m->traj.on = 1;
    schedule_set(&m->traj.when, c, &m->sys, fire_trajectory);
    return MOTE_OK;
}

/* The exact state, as save writes it (at an observer's stop the pending half kick is done). */
static int fire_checkpoint(void *ctx, void *subject, mote_err *err)
{
    sep_model *m = subject;
    return mote_sep_save(&m->sys, m->seed, m->ckpt.path, err);
}

int sep_checkpoint(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    char *p = strdup(mote_call_opt(c, "file")->path);
    if (!p)
        return mote_fail(err, MOTE_ENOMEM, "checkpoint: out of memory");
    free(m->ckpt.path);
    m->ckpt.path = p;
    m->ckpt.on = 1;
    schedule_set(&m->ckpt.when, c, &m->sys, fire_checkpoint);
    m->ckpt.when.first = 0; /* (the first after K steps: the state is there once prepared) */
    return MOTE_OK;
}

int sep_checkpoint_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((sep_model *)vm)->ckpt.on = 0;
    return MOTE_OK;
}

int sep_trajectory_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((sep_model *)vm)->traj.on = 0;
    return MOTE_OK;
}
int sep_frames_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((sep_model *)vm)->frames.on = 0; /* (the movie of the frames so far was made at run end) */
    return MOTE_OK;
}
int sep_snapshot_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((sep_model *)vm)->snaps.on = 0;
    return MOTE_OK;
}
int sep_monitor_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((sep_model *)vm)->bal.on = 0; /* (FILE was written whole when the last run ended) */
    return MOTE_OK;
}

/* The live picture, when one is due (wall-clock: hz a second, and at most a tenth of the run's
 * time however long a picture takes). */
static int live_picture(sep_model *m, mote_err *err)
{
    if (!m->live.on)
        return MOTE_OK;
    const double now = mote_wall_seconds();
    if (now - m->live.last < m->live.gap)
        return MOTE_OK;
    m->live.last = now;
    const int rc = sep_frame_png(&m->sys, m->live.path, &m->live.fo, err);
    m->live.gap = mote_pace_gap(1 / m->live.hz, mote_wall_seconds() - now);
    return rc;
}

/* Whether the loop wants to see the step just made: an output due at its end, a live view (its
 * tick, every step), the live picture due, the progress line or report due (at their own
 * interval). Otherwise the step's second half kick rides on the next step's drift (the same
 * bits) and the loop sees a later step. */
static int run_need(void *vm, const mote_sep_system *s)
{
    sep_model *m = vm;
    if (mote_loop_due(m->loop, s->t) || s->steps >= m->n_stop || (m->ctx && m->ctx->tick))
        return 1;
    const double now = mote_wall_seconds();
    if (m->live.on && now - m->live.last >= m->live.gap)
        return 1;
    const mote_progress *p = m->loop->progress;
    return p && ((p->enabled && now - p->last >= p->interval) ||
                 (p->ctx && p->ctx->report && now - p->last_report >= p->interval));
}

/* The model's side of the core loop: steps until one the loop wants to see (the outputs due
 * there fire, the progress shows), the live picture when due. The system prepares at the first
 * advance, after the outputs due at the start. */
static double run_clock(const void *vm) { return ((const sep_model *)vm)->sys.t; }
static uint64_t run_count(const void *vm) { return ((const sep_model *)vm)->sys.steps; }
static int run_advance(void *vm, mote_loop *l, double t_stop, uint64_t n_stop, mote_err *err)
{
    sep_model *m = vm;
    m->loop = l;
    m->n_stop = n_stop;
    if (!m->prepared) {
        int rc = mote_sep_prepare(&m->sys, err);
        if (rc)
            return rc;
        m->prepared = 1;
    }
    int rc = mote_sep_advance(&m->sys, l->t_end, run_need, m, err);
    return rc ? rc : live_picture(m, err);
}

void sep_model_live(void *vm, mote_buf *b) { sep_live_frame(&((sep_model *)vm)->sys, b); }

/* After a run: the balance file and the movie of the frames so far. */
static int run_end(sep_model *m, mote_err *err)
{
    int rc = MOTE_OK;
    if (m->bal.on && m->bal.out.rows)
        rc = mote_rows_write(&m->bal.out, err); /* (the complete file is there) */
    if (!rc && m->frames.on && m->frames.movie && m->frames.index > 1) {
        int ran = 0;
        rc = mote_movie(m->frames.prefix, m->frames.fps, m->frames.movie_path,
                        m->ctx ? m->ctx->diag : NULL, &ran, err);
        if (!rc && ran && m->log)
            fprintf(m->log, "frames: %llu frames %s_*.png, the movie %s\n",
                    (unsigned long long)m->frames.index, m->frames.prefix, m->frames.movie_path);
    }
    return rc;
}

/* Make the folders of a series' files unless they exist. */
static int make_series_dir(const char *prefix, const char *ext, mote_err *err)
{
    char *first = mote_series_path(prefix, 0, 6, ext);
    if (!first)
        return mote_fail(err, MOTE_ENOMEM, "run: out of memory");
    const int e = mote_make_dir_of(first);
    free(first);
    return e ? mote_fail(err, MOTE_EIO, "%s: cannot make the folder: %s", prefix, strerror(e))
             : MOTE_OK;
}

