/* run.c: the charging model's long commands: the hit-probability self-test, `run` (the
 * Monte Carlo currents to the uncharged body), `float` (the floating potential), `evolve` (U(t))
 * and `output` (which files each run writes, spec 8). */
#include "mote/charging.h"
#include "mote/datafile.h"
#include "mote/loop.h"
#include "mote/stats.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model.h"

/* ---- run and evolve ------------------------------------------------------------------------- */

/* The run options of a command: the seed, its particles= (default 1e6), the injector, threads. */
static mote_ch_run_opts run_opts(const ch_model *m, const mote_call *c, const mote_ch_geometry *g)
{
    mote_ch_run_opts o = {.seed = m->seed,
                          .solo = c->ctx->solo,
                          .particles = (uint64_t)mote_call_opt_r(c, "particles", 1e6),
                          .r_gen = ch_injection_radius(m, g),
                          .threads = c->ctx->threads,
                          .field = !m->faithful && !m->field_off,
                          .box = m->box,
                          .margin = m->margin,
                          .margin_m = m->margin_m,
                          .tri_material = m->tri_mat,
                          .backscatter = !m->faithful && !m->no_backscatter,
                          .sun = m->sun,
                          .sun_dir = {m->sun_dir[0], m->sun_dir[1], m->sun_dir[2]},
                          .sun_intensity = m->sun_int,
                          .eta = m->eta,
                          .max_steps = m->max_steps,
                          .progress_ctx = c->ctx,
                          .progress_label = c->name};
    return o;
}

static int need_setup(ch_model *m, const mote_call *c, mote_err *err)
{
    if (!m->have_body)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "%s: there is no body yet (body sphere, "
                              "icosphere, uvsphere, box or twocubes)", c->name);
    if (!m->have_plasma || m->plasma.nsp == 0)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "%s: there is no plasma yet (plasma "
                              "preset ..., or species and maxwellian)", c->name);
    for (int s = 0; s < m->plasma.nsp; s++)
        if (m->plasma.sp[s].ncomp == 0)
            return mote_call_fail(err, c, -1, MOTE_EINVAL, "%s: species '%s' has no component "
                                  "(maxwellian species=%s density= temperature=)", c->name,
                                  m->plasma.sp[s].name, m->plasma.sp[s].name);
    return MOTE_OK;
}

/* ---- test hitprob (spec 10 M3; the original's -t) ---- */

int ch_check_test(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    if (strcmp(c->args[0].text, "hitprob"))
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "test: expected hitprob, found '%s'",
                              c->args[0].text);
    const mote_arg *n = mote_call_opt(c, "particles");
    if (n && (n->r != floor(n->r) || n->r > 1e15))
        return mote_call_fail(err, c, mote_call_opt_index(c, "particles"), MOTE_EINVAL,
                              "test: particles must be a whole number (1 ... 1e15)");
    if (!m->have_body)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "test hitprob: there is no body yet");
    return MOTE_OK;
}

/* Straight paths from the injector (the plasma does not matter): the share of histories that
 * hit, against A / (4 pi R^2) (Cauchy-Crofton: exact for a convex body) or A / A_box. */
int ch_run_test(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    mote_ch_plasma p;
    mote_ch_plasma_preset(&p, "single", 1e6, 1000, err);
    p.nsp = 1;
    mote_ch_run_opts o = run_opts(m, c, &g);
    o.field = 0;
    o.tri_material = NULL;
    o.sun = 0;
    mote_ch_tracer *t = mote_ch_tracer_new(&m->body, err);
    if (!t)
        return err->code;
    mote_ch_result r;
    int rc = mote_ch_run(&p, &m->body, t, &o, &r, err);
    mote_ch_tracer_free(t);
    if (rc)
        return rc;
    const double N = (double)o.particles, h = (double)r.hits[0][0], f = h / N;
    const double sf = sqrt(f * (1 - f) / N);
    double want = g.area / (4 * MOTE_CH_PI * o.r_gen * o.r_gen);
    if (m->box) { /* the box injector's area, as mote_ch_run builds it: A / A_box */
        const double A_box = (double)r.histories > 0 ? r.weight[0][0] * N /
                             (MOTE_CH_E * p.sp[0].Z * p.sp[0].n[0] *
                              sqrt(p.sp[0].kT[0] * MOTE_CH_E / (2 * MOTE_CH_PI * p.sp[0].m)))
                                                     : 0;
        want = g.area / fabs(A_box);
    }
    if (m->log)
        fprintf(m->log, "test hitprob: %.0f histories, %.0f hits: P = %.6g +- %.2g; A/%s = %.6g "
                        "(exact for a convex body): %+.2f sigma\n", N, h, f, sf,
                m->box ? "A_box" : "(4 pi R^2)", want, sf > 0 ? (f - want) / sf : 0);
    mote_ch_result_free(&r);
    return MOTE_OK;
}

/* Validation: record the file PREFIX + suffix that the command c will write after `output`
 * (its summary stands for the set), so that a later writer of the same file gets the
 * whole-script check's warning instead of overwriting it silently. */
static int note_prefixed(ch_model *m, const mote_call *c, const char *suffix, const char *kind,
                         mote_err *err)
{
    if (!m->check_prefix)
        return MOTE_OK;
    const size_t len = strlen(m->check_prefix) + strlen(suffix) + 1;
    char *path = malloc(len);
    if (!path)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", c->name);
    snprintf(path, len, "%s%s", m->check_prefix, suffix);
    int rc = mote_outputs_note_path(&c->ctx->outputs, c, -1, path, kind, 0, err);
    free(path);
    return rc;
}

int ch_check_run(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    const mote_arg *n = mote_call_opt(c, "particles");
    if (n && (n->r != floor(n->r) || n->r > 1e15))
        return mote_call_fail(err, c, mote_call_opt_index(c, "particles"), MOTE_EINVAL,
                              "run: particles must be a whole number (1 ... 1e15)");
    const mote_arg *mp = mote_call_opt(c, "max_particles");
    if (mp && (mp->r != floor(mp->r) || mp->r > 1e15))
        return mote_call_fail(err, c, mote_call_opt_index(c, "max_particles"), MOTE_EINVAL,
                              "run: max_particles must be a whole number (1 ... 1e15)");
    if (mp && !mote_call_opt(c, "relerr"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "max_particles"), MOTE_EINVAL,
                              "run: max_particles is the limit of relerr=; give relerr too");
    int rc = need_setup(m, c, err);
    if (!rc)
        m->have_run = 1;
    if (!rc)
        rc = note_prefixed(m, c, "_summary.txt", "charging-summary", err);
    return rc;
}

int ch_run_run(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    if (ch_build_tri_materials(m, err))
        return err->code;
    ch_diagnose(m, "run");
    mote_ch_run_opts o = run_opts(m, c, &g);
    o.potential = mote_call_opt_r(c, "potential", 0);
    mote_ch_tracer *t = mote_ch_tracer_new(&m->body, err);
    if (!t)
        return err->code;
    mote_ch_result_free(&m->res);
    /* relerr=: more histories until every species' relative error is below it (spec 5.3): the
     * count for it from the last run's errors (they fall as 1/sqrt(N)), in whole blocks of 4096,
     * at most max_particles; the histories are the same streams, so the runs are nested */
    const mote_arg *re = mote_call_opt(c, "relerr");
    const double maxp = mote_call_opt_r(c, "max_particles", 1e8);
    if (re && !mote_call_opt(c, "particles"))
        o.particles = 100000;
    if (re && (double)o.particles > maxp)
        o.particles = (uint64_t)maxp;
    int rc, reached = 0;
    double worst = 0;
    mote_progress prog; /* relerr=: one line for all the runs */
    if (re) {
        mote_progress_begin(&prog, c->ctx, c->name);
        o.progress = &prog;
    }
    for (int pass = 0;; pass++) {
        mote_ch_result_free(&m->res);
        rc = mote_ch_run(&m->plasma, &m->body, t, &o, &m->res, err);
        if (rc || !re)
            break;
        worst = 0;
        for (int s = 0; s < m->plasma.nsp; s++)
            worst = fmax(worst, m->res.current[s] != 0
                                    ? m->res.sigma[s] / fabs(m->res.current[s]) : INFINITY);
        reached = worst <= re->r;
        if (reached || (double)o.particles >= maxp || pass == 8)
            break;
        double want = isfinite(worst) ? (double)o.particles * (worst / re->r) * (worst / re->r) * 1.05
                                      : 16.0 * (double)o.particles;
        want = fmin(maxp, fmax(want, 1.25 * (double)o.particles));
        o.particles = (uint64_t)(ceil(want / 4096) * 4096);
        if ((double)o.particles > maxp)
            o.particles = (uint64_t)maxp;
    }
    if (re)
        mote_progress_end(&prog);
    mote_ch_tracer_free(t);
    if (rc)
        return rc;
    if (re && m->log)
        fprintf(m->log, "run: relerr %g %s with %llu histories per component (largest relative "
                        "error %.3g)\n", re->r, reached ? "reached" : "NOT reached: max_particles",
                (unsigned long long)o.particles, worst);
    m->have_run = 1;
    m->r_gen_used = o.r_gen;
    if (m->prefix) {
        const ch_output out = ch_output_of(m, &g, &o, o.field ? o.potential : 0);
        rc = ch_write_outputs(&out, m->log, err);
        if (rc)
            return rc;
    }
    if (!m->log)
        return MOTE_OK;
    double var;
    const double inet = mote_ch_net(&m->res, &var);
    var *= var;
    uint64_t hits = 0;
    int ncomp = 0;
    for (int s = 0; s < m->plasma.nsp; s++) {
        double see_v;
        const double see = ch_species_see(&m->res, s, &see_v);
        fprintf(m->log, "run: %-4s I = %.10g A +- %.3g (%.3g%%)", m->plasma.sp[s].name,
                m->res.current[s], m->res.sigma[s],
                100 * m->res.sigma[s] / fmax(fabs(m->res.current[s]), 1e-300));
        if (see > 0)
            fprintf(m->log, "; %s it knocks out: %+.10g A +- %.3g", ch_emitted_words(m, s), see,
                    sqrt(see_v));
        fputc('\n', m->log);
        for (int k = 0; k < m->plasma.sp[s].ncomp; k++, ncomp++)
            hits += m->res.hits[s][k];
    }
    if (m->res.tri_photo)
        fprintf(m->log, "run: photoelectrons I = %+.10g A (sun from %g,%g,%g, intensity %g)\n",
                m->res.photo, m->sun_dir[0], m->sun_dir[1], m->sun_dir[2], m->sun_int);
    fprintf(m->log, "run: net I = %.10g A +- %.3g; %llu histories per component from R = %.6g m, "
                    "hit fraction %.6g, back-face hits %llu, %.3g traces/s\n",
            inet, sqrt(var), (unsigned long long)o.particles, o.r_gen,
            (double)hits / ((double)ncomp * (double)o.particles),
            (unsigned long long)m->res.backface_hits, m->res.traces_per_s);
    ch_report_paths(m, "run");
    return MOTE_OK;
}

int ch_check_float(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    if (m->faithful)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "float: in faithful mode the currents do "
                              "not depend on U, so no floating potential exists");
    if (m->field_off)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "float: with field none the currents do "
                              "not depend on U, so no floating potential exists");
    const mote_arg *n = mote_call_opt(c, "particles");
    if (n && (n->r != floor(n->r) || n->r > 1e15))
        return mote_call_fail(err, c, mote_call_opt_index(c, "particles"), MOTE_EINVAL,
                              "float: particles must be a whole number (1 ... 1e15)");
    int rc = need_setup(m, c, err);
    return rc ? rc : note_prefixed(m, c, "_summary.txt", "charging-summary", err);
}

int ch_run_float(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    if (ch_build_tri_materials(m, err))
        return err->code;
    ch_diagnose(m, "float");
    mote_ch_run_opts o = run_opts(m, c, &g); /* (the field on: full mode) */
    o.U0 = mote_call_opt_r(c, "U0", 0);
    mote_ch_tracer *t = mote_ch_tracer_new(&m->body, err);
    if (!t)
        return err->code;
    double U, sU, oml;
    int evals;
    const double tol = mote_call_opt_r(c, "tolerance", 1e-4);
    mote_ch_result_free(&m->res);
    mote_progress prog; /* one line for all the runs */
    mote_progress_begin(&prog, c->ctx, c->name);
    o.progress = &prog;
    int rc = mote_ch_float(&m->plasma, &m->body, t, &o, tol, &U, &sU, &oml, &evals, &m->res, err);
    /* replicas=k (spec 6.5): the roots for seeds seed+1 ... seed+k-1 as well; U_f is then
     * their mean, its error the standard error of the mean (with its 95% interval), and the
     * currents and files are those at the mean */
    const int reps = (int)mote_call_opt_r(c, "replicas", 1);
    double sum = rc ? 0 : U, sq = rc ? 0 : U * U;
    if (!rc && reps > 1 && m->log) {
        mote_progress_clear(&prog);
        fprintf(m->log, "float: replica 1 (seed %llu): U_f = %.6g V +- %.3g\n",
                (unsigned long long)o.seed, U, sU);
    }
    for (int k = 1; k < reps && !rc; k++) {
        mote_ch_run_opts ok = o;
        ok.seed = o.seed + (uint64_t)k;
        double Uk, sUk, omk;
        int ek;
        mote_ch_result rk;
        rc = mote_ch_float(&m->plasma, &m->body, t, &ok, tol, &Uk, &sUk, &omk, &ek, &rk, err);
        if (!rc) {
            mote_ch_result_free(&rk);
            sum += Uk;
            sq += Uk * Uk;
            mote_progress_clear(&prog);
            if (m->log)
                fprintf(m->log, "float: replica %d (seed %llu): U_f = %.6g V +- %.3g\n", k + 1,
                        (unsigned long long)ok.seed, Uk, sUk);
        }
    }
    /* roots=all (spec 6.5): the characteristic on a grid from 0 by 0.1 kT_min/e doubling, both
     * ways, to twice the farthest of U_f, U0 and the OML root; each sign change is a root
     * (interpolated linearly), stable where dI/dU < 0 */
    const mote_arg *ra = mote_call_opt(c, "roots");
    if (!rc && ra && !strcmp(ra->text, "all")) {
        double kTmin = INFINITY;
        for (int sp = 0; sp < m->plasma.nsp; sp++)
            for (int k = 0; k < m->plasma.sp[sp].ncomp; k++)
                kTmin = fmin(kTmin, m->plasma.sp[sp].kT[k] / abs(m->plasma.sp[sp].Z));
        const double far = 2 * fmax(fmax(fabs(U), fabs(o.U0)), fabs(oml));
        double grid[200];
        int ng = 0, nr = 0;
        for (double step = 0.1 * kTmin; step < far && ng < 90; step *= 2)
            grid[ng++] = -step;
        for (int k = 0; k < ng / 2; k++) { /* ascending */
            const double x = grid[k];
            grid[k] = grid[ng - 1 - k];
            grid[ng - 1 - k] = x;
        }
        grid[ng++] = 0;
        for (double step = 0.1 * kTmin; step < far && ng < 190; step *= 2)
            grid[ng++] = step;
        double Iprev = 0;
        for (int k = 0; k < ng && !rc; k++) {
            mote_ch_run_opts ok = o;
            ok.potential = grid[k];
            mote_ch_result rk;
            rc = mote_ch_run(&m->plasma, &m->body, t, &ok, &rk, err);
            if (rc)
                break;
            const double I = mote_ch_net(&rk, NULL);
            mote_ch_result_free(&rk);
            if (k > 0 && (I < 0) != (Iprev < 0)) {
                const int here = U >= grid[k - 1] && U <= grid[k]; /* U_f's interval: U_f */
                const double Ur = here ? U : (grid[k - 1] * I - grid[k] * Iprev) / (I - Iprev);
                mote_progress_clear(&prog);
                if (m->log)
                    fprintf(m->log, "float: a root of I(U) between %g and %g V: %s %.6g V, %s "
                                    "(dI/dU %s 0)\n", grid[k - 1], grid[k],
                            here ? "U_f =" : "about (linear)", Ur,
                            I < Iprev ? "stable" : "unstable", I < Iprev ? "<" : ">");
                nr++;
            }
            Iprev = I;
        }
        mote_progress_clear(&prog);
        if (!rc && m->log)
            fprintf(m->log, "float: %d sign change%s of I(U) at %d potentials from %g to %g V\n",
                    nr, nr == 1 ? "" : "s", ng, grid[0], grid[ng - 1]);
    }
    double Uf = U, sUf = sU; /* what the command reports: replica 1, or the replicas' mean */
    if (!rc && reps > 1) {
        const double mean = sum / reps;
        const double sd = sqrt(fmax(0, (sq - reps * mean * mean) / (reps - 1)));
        const double se = sd / sqrt((double)reps), t95 = mote_t95(reps - 1);
        mote_progress_clear(&prog);
        if (m->log)
            fprintf(m->log, "float: %d replicas: mean U_f = %.6g V +- %.3g (standard error of the "
                            "mean; 95%% confidence +- %.3g, Student's t %.4g with %d degree%s of "
                            "freedom; standard deviation %.3g V, the single run's sigma_U %.3g "
                            "V)\n", reps, mean, se, t95 * se, t95, reps - 1,
                    reps == 2 ? "" : "s", sd, sU);
        Uf = mean;
        sUf = se;
        /* the currents at the mean, with replica 1's histories (common random numbers) */
        mote_ch_result_free(&m->res);
        mote_ch_run_opts om = o;
        om.potential = mean;
        rc = mote_ch_run(&m->plasma, &m->body, t, &om, &m->res, err);
    }
    mote_progress_end(&prog);
    mote_ch_tracer_free(t);
    if (rc)
        return rc;
    U = Uf;
    sU = sUf;
    m->have_run = 1;
    mote_call_result(c, "U_f", U);
    if (m->prefix) { /* the files at U_f (spec 8.2) */
        ch_output out = ch_output_of(m, &g, &o, U);
        out.have_float = 1;
        out.sigma_U = sU;
        out.oml = oml;
        rc = ch_write_outputs(&out, m->log, err);
        if (rc)
            return rc;
    }
    if (m->log) {
        fprintf(m->log, "float: U_f = %.6g V +- %.3g (OML estimate, no emission, for the "
                        "equivalent sphere %.6g V; %d runs of %llu histories per component, "
                        "common random numbers)\n", U, sU, oml, evals, (unsigned long long)o.particles);
        for (int s = 0; s < m->plasma.nsp; s++) {
            double see_v;
            const double see = ch_species_see(&m->res, s, &see_v);
            fprintf(m->log, "float: %-4s I = %.6g A +- %.3g at U_f (%.6g A/m^2)",
                    m->plasma.sp[s].name, m->res.current[s], m->res.sigma[s],
                    m->res.current[s] / g.area);
            if (see > 0)
                fprintf(m->log, "; %s it knocks out: %+.6g A +- %.3g", ch_emitted_words(m, s),
                        see, sqrt(see_v));
            fputc('\n', m->log);
        }
        if (m->res.tri_photo)
            fprintf(m->log, "float: photoelectrons I = %+.6g A at U_f\n", m->res.photo);
        ch_report_paths(m, "float");
    }
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
        int rc = need_setup(m, c, err);
        if (rc)
            return rc;
    } else if (!m->have_run)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "evolve: no currents yet: run first");
    const mote_arg *dt = mote_call_opt(c, "dt_out");
    if (dt && dt->r > mote_call_opt(c, "time")->r)
        return mote_call_fail(err, c, mote_call_opt_index(c, "dt_out"), MOTE_EINVAL,
                              "evolve: dt_out must not exceed time");
    int rc = MOTE_OK;
    if (m->ndiel > 0 && !m->have_sphere) /* the map of the surface potential */
        if (!(rc = note_prefixed(m, c, "_potential.vtk", "potential", err)))
            rc = note_prefixed(m, c, "_potential.png", "potential", err);
    if (!rc && !mote_call_opt(c, "file") && m->check_timeseries)
        rc = note_prefixed(m, c, "_timeseries.csv", "timeseries", err);
    return rc;
}

/* The time-series file of evolve (spec 8.1): file= if given, else P_timeseries.csv after
 * `output prefix=P` (unless timeseries=off); only MPI rank 0 writes. 1 when one is open. */
static int open_timeseries(ch_model *m, const mote_call *c, mote_datafile *d, mote_err *err,
                           int *rc)
{
    *rc = MOTE_OK;
    if (ch_mpi_rank(m->ctx ? m->ctx->solo : 0) != 0)
        return 0;
    const mote_arg *f = mote_call_opt(c, "file");
    char *path = NULL;
    if (!f && (!m->prefix || !m->out_timeseries))
        return 0;
    if (!f) {
        const size_t len = strlen(m->prefix) + 32;
        if (!(path = malloc(len))) {
            *rc = mote_fail(err, MOTE_ENOMEM, "evolve: out of memory");
            return 0;
        }
        snprintf(path, len, "%s_timeseries.csv", m->prefix);
    }
    char *origin = mote_call_origin(c);
    *rc = mote_datafile_open(d, f ? f->path : path, "charging-timeseries",
                             origin ? origin : "evolve", m->seed, err);
    free(origin);
    if (!*rc && m->log && !f)
        fprintf(m->log, "output: writing %s\n", path);
    free(path);
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

static int evolve_clock_run_with(const mote_call *call, int (*row)(void *, void *, mote_err *),
                                 void *rows, mote_schedule *at, double T,
                                 int (*advance)(void *, double, mote_err *), void *ctx,
                                 mote_err *err)
{
    evolve_clock c = {0, advance, ctx};
    const mote_runner r = {.what = "evolve", .sys = &c, .ctx = call->ctx,
                           .clock = evolve_clock_now, .advance = evolve_clock_advance};
    const mote_observer o = {.at = at, .ctx = rows, .fire = row};
    return mote_run(&r, &o, 1, NULL, T, UINT64_MAX, err);
}

static int evolve_clock_run(const mote_call *call, int (*row)(void *, void *, mote_err *),
                            void *rows, mote_schedule *at, double T, mote_err *err)
{
    return evolve_clock_run_with(call, row, rows, at, T, NULL, NULL, err);
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
    const double T = mote_call_opt(c, "time")->r, dt = mote_call_opt_r(c, "dt_out", T);
    const double U0 = mote_call_opt_r(c, "U0", 0), C = g.capacitance;
    if (ch_build_tri_materials(m, err))
        return err->code;
    mote_ch_run_opts o = run_opts(m, c, &g); /* (the field on: full mode) */
    mote_ch_tracer *tr = mote_ch_tracer_new(&m->body, err);
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
    mote_datafile d;
    const int f = open_timeseries(m, c, &d, err, &rc);
    if (rc) {
        ch_table_free(&t);
        return rc;
    }
    FILE *out = f ? d.f : m->log;
    if (f) {
        fprintf(out, "# mode = full (C dU/dt = I_net(U), the characteristic tabulated at %d "
                     "potentials, %llu histories per component each; the species' and emission "
                     "currents interpolated linearly between them; sigma_U = sigma_I min(t, tau) "
                     "/ C, an estimate)\n# C_F = %.10g\n# U_f_V = %.10g\n# tau_s = %.10g\n",
                t.n, (unsigned long long)o.particles, C, t.Uf, t.tau);
        timeseries_columns(m, out);
    }
    if (m->log)
        fprintf(m->log, "evolve: I(U) tabulated at %d potentials from %g V to %g V; U_f = %.6g V, "
                        "tau = C/|dI/dU| = %.4g s; 50%% of U_f at %.4g s, 90%% at %.4g s\n",
                t.n, t.U[0], t.U[t.n - 1], t.Uf, t.tau, ch_table_t_at(&t, U0 + 0.5 * (t.Uf - U0)),
                ch_table_t_at(&t, U0 + 0.9 * (t.Uf - U0)));
    full_rows x = {m, &t, C, f, out, {0}, 0, {0, dt, 0}};
    int rc2 = evolve_clock_run(c, full_row, &x, &x.at, T, err); /* (rows when there is an out) */
    if (!rc2 && out && fabs(x.last - T) > 1e-12 * T) /* the end, between two rows */
        full_row_at(&x, T);
    if (rc2) {
        ch_table_free(&t);
        if (f)
            mote_datafile_abort(&d);
        return rc2;
    }
    ch_table_free(&t);
    return f ? mote_datafile_commit(&d, err) : MOTE_OK;
}

/* ---- differential charging (spec 6.10) ---- */

typedef struct {
    ch_model *m;
    const mote_ch_tracer *tr;
    mote_ch_run_opts o;
    const int *tri_patch;
    int runs;
    double Ic, sig, Ip[CH_MAX_PATCHES]; /* faithful: the run's constant currents */
} patch_node_ctx;

/* The currents of the triangles of patch p (-1: the conductor) in a run: collected, emitted,
 * photoelectrons. */
static double part_current(const ch_model *m, const mote_ch_result *r, const int *tri_patch,
                           int p)
{
    const uint32_t ntri = r->ntri;
    double I = 0;
    int comp = 0;
    for (int s = 0; s < r->nsp; s++)
        for (int k = 0; k < m->plasma.sp[s].ncomp; k++, comp++) {
            uint64_t h = 0;
            double see = 0;
            for (uint32_t i = 0; i < ntri; i++) {
                if (tri_patch[i] != p)
                    continue;
                const size_t q = (size_t)comp * ntri * 2 + 2 * (size_t)i;
                h += r->tri_hits[q] + r->tri_hits[q + 1];
                if (r->tri_see)
                    see += r->tri_see[q] + r->tri_see[q + 1];
            }
            I += r->weight[s][k] * (double)h + see;
        }
    for (uint32_t i = 0; r->tri_photo && i < ntri; i++)
        if (tri_patch[i] == p)
            I += r->tri_photo[2 * (size_t)i] + r->tri_photo[2 * (size_t)i + 1];
    return I;
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
        if (!m->faithful) {
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
        fprintf(out, "%.10g %.10g %.10g %.10g %.10g", time, C * y[0], y[0], sU, I);
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

static int evolve_patches(ch_model *m, const mote_call *c, mote_err *err)
{
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    const double T = mote_call_opt(c, "time")->r, dt = mote_call_opt_r(c, "dt_out", T);
    const double U0 = m->faithful ? 0 : mote_call_opt_r(c, "U0", 0), C = g.capacitance;
    const uint32_t ntri = m->body.sphere ? 1 : m->body.ntri;
    const int np = m->ndiel;
    int *tri_patch = malloc((size_t)ntri * sizeof *tri_patch);
    if (!tri_patch)
        return mote_fail(err, MOTE_ENOMEM, "evolve: out of memory");
    ch_patches P;
    memset(&P, 0, sizeof P);
    double area[CH_MAX_PATCHES] = {0}, eps[CH_MAX_PATCHES];
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
            rc = mote_call_fail(err, c, -1, MOTE_EINVAL, "evolve: dielectric part '%s' has no "
                                "permittivity: give eps_r= to dielectric, or assign it a "
                                "material with one (kapton, teflon, cover-glass)",
                                m->diel[p].part);
        else if (!(area[p] > 0))
            rc = mote_call_fail(err, c, -1, MOTE_EINVAL, "evolve: dielectric part '%s' has no "
                                "triangles", m->diel[p].part);
        P.Cp[p] = MOTE_CH_EPS0 * eps[p] * area[p] / m->diel[p].d;
        const double sig = /* (sigma= of dielectric, else the part's material's) */
            m->diel[p].sigma >= 0 ? m->diel[p].sigma : ch_part_sigma(m, m->diel[p].part);
        P.Rp[p] = sig > 0 ? m->diel[p].d / (sig * area[p]) : INFINITY;
    }
    if (!rc)
        rc = ch_patches_init(&P, np, ch_smallest_kT(m), U0, err);
    if (!rc && !m->faithful)
        rc = ch_build_tri_materials(m, err);
    patch_node_ctx x = {.m = m, .tri_patch = tri_patch};
    mote_ch_tracer *tr = NULL;
    if (!rc && m->faithful) { /* the last run's currents */
        x.Ic = part_current(m, &m->res, tri_patch, -1);
        for (int p = 0; p < np; p++)
            x.Ip[p] = part_current(m, &m->res, tri_patch, p);
        mote_ch_net(&m->res, &x.sig);
    } else if (!rc && !(tr = mote_ch_tracer_new(&m->body, err)))
        rc = err->code;
    if (rc) {
        free(tri_patch);
        ch_patches_free(&P);
        return rc;
    }
    x.tr = tr;
    x.o = run_opts(m, c, &g);
    x.o.tri_patch = tri_patch;
    x.o.npatch = np;
    x.o.dv = P.dv;
    x.o.ndv = P.ndv;
    P.C = C;
    P.node = patch_node;
    P.ctx = &x;
    mote_progress prog; /* one line for all the runs */
    mote_progress_begin(&prog, c->ctx, c->name);
    x.o.progress = &prog;
    mote_datafile d;
    const int f = open_timeseries(m, c, &d, err, &rc);
    FILE *out = f ? d.f : m->log;
    if (f) {
        fprintf(out, "# mode = %s with %d dielectric part%s (spec 6.10: C dU/dt = sum I, C_p "
                     "d(V_p - U)/dt = I_p - (V_p - U)/R_p; implicit Euler extrapolated, "
                     "tolerance 1e-7)\n# C_F = %.10g\n",
                m->faithful ? "faithful" : "full", np, np > 1 ? "s" : "", C);
        for (int p = 0; p < np; p++)
            fprintf(out, "# A_%s_m2 = %.10g\n# C_p_%s_F = %.10g\n# R_p_%s_ohm = %.10g\n",
                    m->diel[p].part, area[p], m->diel[p].part, P.Cp[p], m->diel[p].part, P.Rp[p]);
        fprintf(out, "# columns: t_s Q_C U_V sigma_U_V I_net_A");
        for (int p = 0; p < np; p++)
            fprintf(out, " V_%s_V", m->diel[p].part);
        fputs(" dV_max_V\n", out);
    }
    patch_rows r = {m, &P, C, f, out, np, {U0}, 0, 1e-9 * T, 0, 0, 0, -1, {0, dt, 0}};
    if (!rc)
        rc = evolve_clock_run_with(c, patch_row, &r, &r.at, T, patch_advance, &r, err);
    if (!rc && fabs(r.last - T) > 1e-12 * T) /* the end, between two rows */
        rc = patch_row_at(&r, T, err);
    double *y = r.y, dvmax = r.dvmax, t_dvmax = r.t_dvmax;
    const int p_dvmax = r.p_dvmax;
    mote_progress_end(&prog);
    if (!rc && m->log) {
        fprintf(m->log, "evolve: %d dielectric part%s; %ld steps, currents from %d node%s%s\n", np,
                np > 1 ? "s" : "", P.steps, P.nn, P.nn == 1 ? "" : "s",
                m->faithful ? " (faithful: the last run's constant currents)" : "");
        for (int p = 0; p < np; p++) {
            const double tau = P.Cp[p] * P.Rp[p];
            fprintf(m->log, "evolve: dielectric %s: A = %.6g m^2, C_p = %.6g F, R_p = %.6g ohm, "
                            "tau_p = %.6g s; at t = %g s V_p = %.8g V, V_p - U = %.8g V\n",
                    m->diel[p].part, area[p], P.Cp[p], P.Rp[p], tau, T, y[0] + y[1 + p],
                    y[1 + p]);
        }
        fprintf(m->log, "evolve: at t = %g s U = %.8g V; the largest |V_p - U| %.6g V (%s, at t "
                        "= %g s)\n", T, y[0], dvmax, m->diel[p_dvmax].part, t_dvmax);
    }
    if (!rc && m->prefix && !m->body.sphere) { /* the map of the surface potential at T */
        double *V = malloc((size_t)ntri * sizeof *V);
        if (!V)
            rc = mote_fail(err, MOTE_ENOMEM, "evolve: out of memory");
        for (uint32_t i = 0; V && i < ntri; i++)
            V[i] = y[0] + (tri_patch[i] >= 0 ? y[1 + tri_patch[i]] : 0);
        ch_output oo = ch_output_of(m, &g, &x.o, y[0]);
        oo.tri_V = V;
        oo.time = T;
        if (!rc)
            rc = ch_write_potential(&oo, m->log, err);
        free(V);
    }
    mote_ch_tracer_free(tr);
    free(tri_patch);
    ch_patches_free(&P);
    if (f)
        return rc ? (mote_datafile_abort(&d), rc) : mote_datafile_commit(&d, err);
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
    const double dt = mote_call_opt_r(c, "dt_out", T);
    double inet = 0, var = 0;
    for (int s = 0; s < m->plasma.nsp; s++) {
        inet += m->res.current[s];
        var += m->res.sigma[s] * m->res.sigma[s];
    }
    const double C = g.capacitance, sig = sqrt(var);
    mote_datafile d;
    int rc;
    const int f = open_timeseries(m, c, &d, err, &rc);
    if (rc)
        return rc;
    FILE *out = f ? d.f : m->log;
    if (f) {
        fprintf(out, "# mode = faithful (constant currents, Q = I t, U = Q / C)\n# C_F = %.10g\n"
                     "# area_m2 = %.10g\n# histories = %llu\n", C, g.area,
                (unsigned long long)m->res.histories);
        timeseries_columns(m, out);
    } else if (out) {
        fprintf(out, "evolve: dU/dt = %.10g V/s (I = %.10g A, C = %.10g F)\n", inet / C, inet, C);
    }
    faithful_rows x = {m, inet, C, sig, f, out, -1, {0, dt, 0}};
    rc = evolve_clock_run(c, faithful_row, &x, &x.at, T, err); /* (rows when there is an out) */
    if (!rc && out && fabs(x.last - T) > 1e-12 * T) /* the end, between two rows */
        faithful_row_at(&x, T);
    if (rc) {
        if (f)
            mote_datafile_abort(&d);
        return rc;
    }
    return f ? mote_datafile_commit(&d, err) : MOTE_OK;
}

/* ---- output (spec 8) ------------------------------------------------------------------------ */

static int on_off(const mote_call *c, const char *key, int dflt, int *out, mote_err *err)
{
    const mote_arg *a = mote_call_opt(c, key);
    *out = dflt;
    if (!a)
        return MOTE_OK;
    *out = a->i == 0; /* on|off */
    return MOTE_OK;
}

/* one view of png_view: iso|+x|-x|+y|-y|+z|-z|X,Y,Z: the unit vector toward the viewer */
static int parse_view(const char *t, double v[3])
{
    if (strcmp(t, "iso") == 0) {
        v[0] = v[1] = v[2] = 1 / sqrt(3.0);
        return 0;
    }
    if ((t[0] == '+' || t[0] == '-') && t[1] >= 'x' && t[1] <= 'z' && !t[2]) {
        v[0] = v[1] = v[2] = 0;
        v[t[1] - 'x'] = t[0] == '+' ? 1 : -1;
        return 0;
    }
    if (ch_parse3any(t, v))
        return -1;
    const double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(l > 0))
        return -1;
    for (int a = 0; a < 3; a++)
        v[a] /= l;
    return 0;
}

/* png_view=V1/V2/...: up to 8 views, each with a name for its file (iso, px, mz, ...; a
 * vector: viewK); the count, or -1 (*bad: the view that is not one). */
static int parse_views(const char *t, double v[8][3], char name[8][16], char bad[64])
{
    int n = 0;
    for (const char *p = t;; n++) {
        const char *e = strchr(p, '/');
        const size_t l = e ? (size_t)(e - p) : strlen(p);
        snprintf(bad, 64, "%.*s", (int)(l < 63 ? l : 63), p);
        if (n == 8 || l == 0 || l >= 64 || parse_view(bad, v[n]))
            return -1;
        if (bad[0] == '+' || bad[0] == '-')
            snprintf(name[n], 16, "%c%c", bad[0] == '+' ? 'p' : 'm', bad[1]);
        else if (!strcmp(bad, "iso"))
            snprintf(name[n], 16, "iso");
        else
            snprintf(name[n], 16, "view%d", n + 1);
        if (!e)
            return n + 1;
        p = e + 1;
    }
}

/* png_quantity=J_net|J_<species>|J_see|J_photo|sigma_J|relerr|sunlit_fraction|hits: the code and
 * species, or -1 */
static int parse_quantity(const ch_model *m, const char *t, int *sp)
{
    static const char *const names[] = {"J_net", "", "J_see", "J_photo", "sigma_J", "relerr",
                                        "sunlit_fraction", "hits"};
    *sp = 0;
    for (int q = 0; q < 8; q++)
        if (q != CH_Q_SPECIES && !strcmp(t, names[q]))
            return q;
    for (int s = 0; s < m->plasma.nsp; s++)
        if (!strncmp(t, "J_", 2) && !strcmp(t + 2, m->plasma.sp[s].name)) {
            *sp = s;
            return CH_Q_SPECIES;
        }
    return -1;
}

int ch_check_output(void *vm, const mote_call *c, mote_err *err)
{
    int x;
    double v[8][3];
    char names[8][16], bad[64];
    const mote_arg *a;
    int rc = on_off(c, "triangles", 1, &x, err);
    if (!rc)
        rc = on_off(c, "timeseries", 1, &x, err);
    if (!rc)
        rc = on_off(c, "legacy_stdout", 0, &x, err);
    if (!rc)
        rc = on_off(c, "vtk", 1, &x, err);
    if (!rc)
        rc = on_off(c, "png", 1, &x, err);
    if (!rc)
        rc = on_off(c, "ply", 0, &x, err);
    if (rc)
        return rc;
    if ((a = mote_call_opt(c, "png_view")) && parse_views(a->text, v, names, bad) < 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "png_view"), MOTE_EINVAL,
                              "output: png_view must be iso, +x, -x, +y, -y, +z, -z or X,Y,Z, "
                              "or up to 8 of them as V1/V2/..., found '%s'", bad);
    int w, h;
    char extra;
    if ((a = mote_call_opt(c, "png_size")) &&
        (sscanf(a->text, "%dx%d%c", &w, &h, &extra) != 2 || w < 64 || h < 64 || w > 8192 ||
         h > 8192))
        return mote_call_fail(err, c, mote_call_opt_index(c, "png_size"), MOTE_EINVAL,
                              "output: png_size must be WxH, 64 to 8192 pixels each, found '%s'",
                              a->text);
    int sp;
    if ((a = mote_call_opt(c, "png_quantity")) && parse_quantity(vm, a->text, &sp) < 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "png_quantity"), MOTE_EINVAL,
                              "output: png_quantity must be J_net, J_<species> (of the plasma so "
                              "far), J_see, J_photo, sigma_J, relerr, sunlit_fraction or hits, "
                              "found '%s'", a->text);
    const mote_arg *p = mote_call_opt(c, "prefix");
    /* the prefix's folder is made if its parent exists (as every prefix= and dir=) */
    char *dir = strdup(p->path), *slash = dir ? strrchr(dir, '/') : NULL;
    if (slash && slash != dir)
        *slash = '\0';
    const int dir_ok =
        dir && (mote_ctx_dir_ok(c->ctx, p->path) || (slash && mote_ctx_dir_ok(c->ctx, dir)));
    if (dir_ok && slash && !mote_ctx_dir_ok(c->ctx, p->path))
        mote_ctx_note_dir(c->ctx, dir); /* (the summary and tables in it pass their checks) */
    free(dir);
    if (!dir_ok)
        return mote_call_fail(err, c, mote_call_opt_index(c, "prefix"), MOTE_EINVAL,
                              "output: the directory that would hold prefix '%s' does not exist",
                              p->text);
    ch_model *m = vm;
    free(m->check_prefix);
    if (!(m->check_prefix = strdup(p->path)))
        return mote_fail(err, MOTE_ENOMEM, "output: out of memory");
    on_off(c, "timeseries", 1, &m->check_timeseries, err);
    return MOTE_OK;
}

int ch_run_output(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    free(m->prefix);
    free(m->origin);
    m->prefix = strdup(mote_call_opt(c, "prefix")->path);
    m->origin = mote_call_origin(c);
    if (!m->prefix || !m->origin)
        return mote_fail(err, MOTE_ENOMEM, "output: out of memory");
    on_off(c, "triangles", 1, &m->out_triangles, err);
    on_off(c, "vtk", 1, &m->out_vtk, err);
    on_off(c, "png", 1, &m->out_png, err);
    on_off(c, "ply", 0, &m->out_ply, err);
    const mote_arg *a = mote_call_opt(c, "png_view");
    char bad[64];
    m->nviews = parse_views(a ? a->text : "iso", m->view, m->view_name, bad);
    m->png_w = 1024;
    m->png_h = 768;
    if ((a = mote_call_opt(c, "png_size")))
        sscanf(a->text, "%dx%d", &m->png_w, &m->png_h);
    m->png_log = (a = mote_call_opt(c, "png_scale")) && strcmp(a->text, "log") == 0;
    m->vtk_binary = (a = mote_call_opt(c, "vtk_format")) && strcmp(a->text, "binary") == 0;
    on_off(c, "timeseries", 1, &m->out_timeseries, err);
    on_off(c, "legacy_stdout", 0, &m->legacy_stdout, err);
    m->png_q = (a = mote_call_opt(c, "png_quantity")) ? parse_quantity(m, a->text, &m->png_sp)
                                                      : CH_Q_JNET;
    if (m->png_q < 0) /* (a species since removed) */
        return mote_call_fail(err, c, mote_call_opt_index(c, "png_quantity"), MOTE_EINVAL,
                              "output: png_quantity: no species '%s'", a->text + 2);
    return MOTE_OK;
}

