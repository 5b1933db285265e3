/* run.c: the charging model's long commands: the hit-probability self-test, `run` (the
 * Monte Carlo currents to the uncharged body), `float` (the floating potential) and `output`
 * (which files each run writes, spec 8); `evolve` (U(t)) is in timeseries.c. */
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
mote_ch_run_opts ch_run_opts(const ch_model *m, const mote_call *c, const mote_ch_geometry *g)
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
                          .progress_label = c->name,
                          .tree = m->field_solved && !m->field_off ? m->ftree : NULL,
                          .fcache = m->field_solved && !m->field_off ? m->fcache : NULL};
    return o;
}

int ch_need_setup(ch_model *m, const mote_call *c, mote_err *err)
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
mote_ch_tracer *ch_model_tracer(const ch_model *m, mote_err *err)
{
    mote_ch_tracer *t = mote_ch_tracer_new(&m->body, err);
    if (t && m->embree_only)
        ch_tracer_walk(t, 0);
    return t;
}

int ch_run_test(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    mote_ch_plasma p;
    mote_ch_plasma_preset(&p, "single", 1e6, 1000, err);
    p.nsp = 1;
    mote_ch_run_opts o = ch_run_opts(m, c, &g);
    o.field = 0;
    o.tri_material = NULL;
    o.sun = 0;
    mote_ch_tracer *t = ch_model_tracer(m, err);
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
int ch_note_prefixed(ch_model *m, const mote_call *c, const char *suffix, const char *kind,
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
    int rc = ch_need_setup(m, c, err);
    if (!rc)
        m->have_run = 1;
    if (!rc)
        rc = ch_note_prefixed(m, c, "_summary.txt", "charging-summary", err);
    return rc;
}

int ch_run_run(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    if (ch_field_prepare(m, c, err))
        return err->code;
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    if (ch_build_tri_materials(m, err))
        return err->code;
    ch_diagnose(m, "run");
    mote_ch_run_opts o = ch_run_opts(m, c, &g);
    o.potential = mote_call_opt_r(c, "potential", 0);
    mote_ch_tracer *t = ch_model_tracer(m, err);
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
    if (m->res.tri_photo && m->res.photo_paths)
        fprintf(m->log, "run: photoelectrons I = %+.10g +- %.3g A (sun from %g,%g,%g, intensity "
                        "%g; %llu followed in the solved field)\n", m->res.photo,
                m->res.photo_sigma, m->sun_dir[0], m->sun_dir[1], m->sun_dir[2], m->sun_int,
                (unsigned long long)m->res.photo_paths);
    else if (m->res.tri_photo)
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
    if (m->ndiel > 0 && (mote_call_opt(c, "replicas") || mote_call_opt(c, "roots")))
        return mote_call_fail(err, c, mote_call_opt_index(c, mote_call_opt(c, "replicas") ?
                                                                 "replicas" : "roots"),
                              MOTE_EINVAL, "float: replicas= and roots= are for a body that is "
                              "one conductor; with dielectric parts float finds their steady "
                              "state (particles=, tolerance=, U0=)");
    int rc = ch_need_setup(m, c, err);
    if (m->ndiel > 0)
        return rc;
    return rc ? rc : ch_note_prefixed(m, c, "_summary.txt", "charging-summary", err);
}

/* float roots=all (spec 6.5): the characteristic on a grid from 0 by 0.1 kT_min/e doubling, both
 * ways, to twice the farthest of U_f, U0 and the OML root; each sign change is a root
 * (interpolated linearly), stable where dI/dU < 0. */
static int float_roots(ch_model *m, const mote_ch_tracer *t, const mote_ch_run_opts *o, double U,
                       double oml, mote_progress *prog, mote_err *err)
{
    int rc = MOTE_OK;
    double kTmin = INFINITY;
    for (int sp = 0; sp < m->plasma.nsp; sp++)
        for (int k = 0; k < m->plasma.sp[sp].ncomp; k++)
            kTmin = fmin(kTmin, m->plasma.sp[sp].kT[k] / abs(m->plasma.sp[sp].Z));
    const double far = 2 * fmax(fmax(fabs(U), fabs(o->U0)), fabs(oml));
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
        mote_ch_run_opts ok = *o;
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
            mote_progress_clear(prog);
            if (m->log)
                fprintf(m->log, "float: a root of I(U) between %g and %g V: %s %.6g V, %s "
                                "(dI/dU %s 0)\n", grid[k - 1], grid[k],
                        here ? "U_f =" : "about (linear)", Ur,
                        I < Iprev ? "stable" : "unstable", I < Iprev ? "<" : ">");
            nr++;
        }
        Iprev = I;
    }
    mote_progress_clear(prog);
    if (!rc && m->log)
        fprintf(m->log, "float: %d sign change%s of I(U) at %d potentials from %g to %g V\n",
                nr, nr == 1 ? "" : "s", ng, grid[0], grid[ng - 1]);
    return rc;
}

int ch_run_float(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    if (ch_field_prepare(m, c, err))
        return err->code;
    if (m->ndiel > 0) {
        ch_diagnose(m, "float");
        return ch_float_patches(m, c, err);
    }
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    if (ch_build_tri_materials(m, err))
        return err->code;
    ch_diagnose(m, "float");
    mote_ch_run_opts o = ch_run_opts(m, c, &g); /* (the field on: full mode) */
    o.U0 = mote_call_opt_r(c, "U0", 0);
    mote_ch_tracer *t = ch_model_tracer(m, err);
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
    enum { ROOTS_ONE, ROOTS_ALL }; /* roots=e{one|all} */
    if (!rc && mote_call_word(c, "roots", ROOTS_ONE) == ROOTS_ALL)
        rc = float_roots(m, t, &o, U, oml, &prog, err);
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
    enum { SCALE_LINEAR, SCALE_LOG };  /* png_scale=e{linear|log} */
    enum { VTK_ASCII, VTK_BINARY };    /* vtk_format=e{ascii|binary} */
    m->png_log = mote_call_word(c, "png_scale", SCALE_LINEAR) == SCALE_LOG;
    m->vtk_binary = mote_call_word(c, "vtk_format", VTK_ASCII) == VTK_BINARY;
    on_off(c, "timeseries", 1, &m->out_timeseries, err);
    on_off(c, "legacy_stdout", 0, &m->legacy_stdout, err);
    m->png_q = (a = mote_call_opt(c, "png_quantity")) ? parse_quantity(m, a->text, &m->png_sp)
                                                      : CH_Q_JNET;
    if (m->png_q < 0) /* (a species since removed) */
        return mote_call_fail(err, c, mote_call_opt_index(c, "png_quantity"), MOTE_EINVAL,
                              "output: png_quantity: no species '%s'", a->text + 2);
    return MOTE_OK;
}

