/* commands.c: the mixing-box model's script commands: the table the script language reads, the
 * validation of each command on a dry model (parameter ranges at their arguments, the whole
 * geometry at `place`, which files earlier commands write), and the calls into the model when
 * the script runs, with the recording, density and frame samplers kept across runs. */
#include "model.h"
#include "mote/h5md.h"
#include "mote/vtk.h"
#include "mote/render.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <sys/stat.h>

#include "help.inc"


static void *model_create(mote_context *ctx, int dry)
{
    mb_model *m = calloc(1, sizeof *m);
    if (!m)
        return NULL;
    mote_mb_init(&m->sys);
    mote_mb_params_default(&m->p);
    m->dry = dry;
    m->ctx = ctx;
    m->log = dry || !ctx ? NULL : ctx->out;
    return m;
}

static void model_destroy(void *vm)
{
    mb_model *m = vm;
    if (!m)
        return;
    mote_mb_free(&m->sys);
    mb_record_free(&m->rec);
    mb_density_free(&m->dens);
    free(m->frames.prefix);
    free(m->snaps.prefix);
    free(m->snaps.origin);
    free(m->traj.path);
    free(m->ckpt.path);
    free(m->traj.origin);
    free(m);
}

static const char *integrator_name(int k) { return k == MOTE_MB_EVENT ? "event" : "timestep"; }
static const char *rule_name(int k) { return k == MOTE_MB_SEEDRULE ? "seed" : "restitution"; }

/* The disks as arrays: positions and velocities (copies, rows of x y), radii, colours. */
static int model_arrays(void *vm, mote_array *out, int cap)
{
    mote_mb *s = &((mb_model *)vm)->sys;
    const size_t n = s->placed ? s->n : 0;
    if (cap < 4)
        return 0;
    double *r = malloc((n ? n : 1) * sizeof *r);
    const double *xy[2] = {s->x, s->y}, *v[2] = {s->vx, s->vy};
    if (!r || mote_array_gather(&out[0], "positions", "m", xy, 2, n, 1.0)) {
        free(r);
        return -1;
    }
    if (mote_array_gather(&out[1], "velocities", "m/s", v, 2, n, 1.0)) {
        free(r);
        free(out[0].data);
        return -1;
    }
    for (size_t i = 0; i < n; i++)
        r[i] = s->p.r;
    mote_array_view(&out[2], "radii", "m", r, 'd', n, 1);
    out[2].owned = 1;
    mote_array_view(&out[3], "species", "0: placed left, 1: placed right", s->colour, 'i', n, 1);
    return 4;
}

/* set_array: positions or velocities (rows of x y), checked as `load` checks a state: centres
 * inside the box, speeds up to 10^6 m/s; each disk's chamber follows its new centre. */
static int model_set_array(void *vm, const char *name, const double *v, size_t rows,
                           size_t cols, mote_err *err)
{
    mote_mb *s = &((mb_model *)vm)->sys;
    const int pos = !strcmp(name, "positions"), vel = !strcmp(name, "velocities");
    if (!pos && !vel)
        return mote_fail(err, MOTE_EINVAL, "set %s: the mixing-box model sets positions or "
                         "velocities", name);
    if (!s->placed)
        return mote_fail(err, MOTE_EINVAL, "set %s: no disks yet ('place' puts them)", name);
    if (rows != s->n || cols != 2)
        return mote_fail(err, MOTE_EINVAL, "set %s: expected %u x 2 numbers (one row per disk), "
                         "found %zu x %zu", name, s->n, rows, cols);
    const mote_mb_params *p = &s->p;
    for (size_t i = 0; i < rows; i++) {
        const double a = v[2 * i], b = v[2 * i + 1];
        if (pos && !(a >= p->x_l && a <= p->x_r && b >= p->x_b && b <= p->x_t))
            return mote_fail(err, MOTE_EINVAL, "set positions: disk %zu: (%g, %g) is outside "
                             "the box [%g, %g] x [%g, %g]", i, a, b, p->x_l, p->x_r, p->x_b,
                             p->x_t);
        if (vel && !(fabs(a) <= 1e6 && fabs(b) <= 1e6))
            return mote_fail(err, MOTE_EINVAL, "set velocities: disk %zu: (%g, %g): a component "
                             "that is not finite or above 10^6 m/s", i, a, b);
    }
    for (size_t i = 0; i < rows; i++) {
        (pos ? s->x : s->vx)[i] = v[2 * i];
        (pos ? s->y : s->vy)[i] = v[2 * i + 1];
        if (pos)
            s->side[i] = (uint8_t)mote_mb_chamber(s, s->x[i]);
    }
    s->generation++; /* (an integrator's cache is stale) */
    return MOTE_OK;
}

static void model_status(void *vm, FILE *out)
{
    mb_model *m = vm;
    const mote_mb *s = &m->sys;
    mote_mb_tally t = {{{0, 0}, {0, 0}}};
    double e = 0, ek = 0;
    if (s->placed) {
        t = mote_mb_counts(s);
        e = mote_mb_energy(s, &ek);
    }
    fprintf(out,
            "N=%u t=%.10g m=%.6g nL0=%llu nL1=%llu nR0=%llu nR1=%llu cross_lr=%llu "
            "cross_rl=%llu collisions=%llu wall_hits=%llu partition_hits=%llu slit_hits=%llu "
            "E=%.10g E_kin=%.10g overlaps=%llu integrator=%s collision_rule=%s\n",
            s->n, s->time, mote_mb_mixing_fraction(&t), (unsigned long long)t.n[0][0],
            (unsigned long long)t.n[0][1], (unsigned long long)t.n[1][0],
            (unsigned long long)t.n[1][1], (unsigned long long)s->cross_lr,
            (unsigned long long)s->cross_rl, (unsigned long long)s->collisions,
            (unsigned long long)s->wall_hits, (unsigned long long)s->partition_hits,
            (unsigned long long)s->slit_hits, e, ek, (unsigned long long)s->overlaps_last,
            integrator_name(m->p.integrator), rule_name(m->p.rule));
}

/* ---- validation helpers ------------------------------------------------------------------------ */

int mb_need_placed(mb_model *m, const mote_call *c, mote_err *err)
{
    if (!m->d_placed)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "%s: no disks are placed yet; set the parameters, then 'place'",
                              c->name);
    return MOTE_OK;
}

/* ---- parameters ----------------------------------------------------------------------------------- */

/* Parameter commands also run during validation: they only set the dry model's parameters,
 * which later checks (place, run_collisions) read. */
static int run_partition(void *vm, const mote_call *c, mote_err *err);
static int run_slit(void *vm, const mote_call *c, mote_err *err);
static int run_disks(void *vm, const mote_call *c, mote_err *err);
static int run_kicks(void *vm, const mote_call *c, mote_err *err);
static int run_box(void *vm, const mote_call *c, mote_err *err);

static const char *const group_names[MB_P_NGROUPS] = {
    "box", "partition", "slit", "radius", "disks", "v_init", "kicks", "loss", "t_c",
};

static int group_index(int bit)
{
    for (int k = 0; k < MB_P_NGROUPS; k++)
        if (bit == 1 << k)
            return k;
    return 0;
}

/* Note that a placement parameter was set; after a `place` it waits for the next one. */
static void set_group(mb_model *m, const mote_call *c, int group)
{
    m->set_line[group_index(group)] = c->line;
    if (m->dry && m->d_placed)
        mote_call_warn(c,
                       "%s: the disks placed on line %d keep their geometry; this takes effect "
                       "at the next 'place'",
                       c->name, m->d_place_line);
}

static int check_box(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    if (!(c->args[0].r < c->args[1].r))
        return mote_call_fail(err, c, 1, MOTE_EINVAL, "box: X_R must be above X_L = %s, found %s",
                              c->args[0].text, c->args[1].text);
    if (!(c->args[2].r < c->args[3].r))
        return mote_call_fail(err, c, 3, MOTE_EINVAL, "box: X_T must be above X_B = %s, found %s",
                              c->args[2].text, c->args[3].text);
    set_group(m, c, MB_P_BOX);
    return run_box(vm, c, err);
}
static int run_box(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    m->p.x_l = c->args[0].r;
    m->p.x_r = c->args[1].r;
    m->p.x_b = c->args[2].r;
    m->p.x_t = c->args[3].r;
    return MOTE_OK;
}

static int check_partition(void *vm, const mote_call *c, mote_err *err)
{
    set_group(vm, c, MB_P_PARTITION);
    return run_partition(vm, c, err);
}
static int run_partition(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    m->p.x1_c = c->args[0].r;
    m->p.a = c->args[1].r;
    return MOTE_OK;
}

static int check_slit(void *vm, const mote_call *c, mote_err *err)
{
    set_group(vm, c, MB_P_SLIT);
    return run_slit(vm, c, err);
}
static int run_slit(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    m->p.x2_c = c->args[0].r;
    m->p.b = c->args[1].r;
    return MOTE_OK;
}

static int check_radius(void *vm, const mote_call *c, mote_err *err)
{
    set_group(vm, c, MB_P_RADIUS);
    return mote_cmd_set(vm, c, err);
}

static int check_disks(void *vm, const mote_call *c, mote_err *err)
{
    int64_t l = c->args[0].i, r = c->args[1].i;
    if (l > MB_N_MAX || r > MB_N_MAX || l + r > MB_N_MAX)
        return mote_call_fail(err, c, l > MB_N_MAX ? 0 : 1, MOTE_EINVAL,
                              "disks: nLeft + nRight must be at most %d, found %s + %s", MB_N_MAX,
                              c->args[0].text, c->args[1].text);
    if (l + r < 1)
        return mote_call_fail(err, c, 1, MOTE_EINVAL,
                              "disks: nLeft + nRight must be at least 1, found 0 + 0");
    set_group(vm, c, MB_P_DISKS);
    return run_disks(vm, c, err);
}
static int run_disks(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    m->p.n_left = c->args[0].i;
    m->p.n_right = c->args[1].i;
    return MOTE_OK;
}

static int check_v_init(void *vm, const mote_call *c, mote_err *err)
{
    set_group(vm, c, MB_P_VINIT);
    return mote_cmd_set(vm, c, err);
}

/* Physics parameters apply from the next run; they need no warning. */
static void set_physics(mb_model *m, const mote_call *c, int group)
{
    if (group)
        m->set_line[group_index(group)] = c->line;
}

static int check_kicks(void *vm, const mote_call *c, mote_err *err)
{
    set_physics(vm, c, MB_P_KICKS);
    return run_kicks(vm, c, err);
}
static int run_kicks(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    m->p.dv_b = c->args[0].r;
    m->p.dv_t = c->args[1].r;
    m->p.dv_s = c->args[2].r;
    return MOTE_OK;
}

static int check_loss(void *vm, const mote_call *c, mote_err *err)
{
    set_physics(vm, c, MB_P_LOSS);
    return mote_cmd_set(vm, c, err);
}


static int check_t_c(void *vm, const mote_call *c, mote_err *err)
{
    set_physics(vm, c, MB_P_TC);
    return mote_cmd_set(vm, c, err);
}



/* ---- state files ---------------------------------------------------------------------------- */

static int check_save(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    return mb_need_placed(m, c, err);
}
static int run_save(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    const char *path = c->args[0].path;
    int rc = mb_save(&m->sys, &m->p, path, err);
    if (!rc && m->log)
        fprintf(m->log, "save: wrote %s\n", path);
    return rc;
}

static int check_load(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    const char *path = c->args[0].path;
    uint64_t n = (uint64_t)m->d_n;
    if (!mote_outputs_find(&c->ctx->outputs, path) && mb_peek(path, &n, err)) {
        char why[sizeof err->msg];
        snprintf(why, sizeof why, "%s", err->msg);
        return mote_call_fail(err, c, 0, err->code, "load: %s", why);
    }
    m->d_placed = 1; /* a state saved earlier in the script: the system of that save */
    m->d_place_line = c->line;
    m->d_n = (int64_t)n;
    return MOTE_OK;
}
static int run_load(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    const char *path = c->args[0].path;
    double t_before = m->sys.time;
    int rc = mb_load(&m->sys, &m->p, path, err);
    if (!rc && m->sys.time != t_before) {
        /* samplers running from an earlier time go on from the loaded one */
        mote_observer *s[5] = {m->rec.active ? &m->rec_s : NULL,
                               m->dens.active ? &m->dens_s : NULL,
                               m->frames.active ? &m->frames_s : NULL,
                               m->snaps.active ? &m->snaps_s : NULL,
                               m->traj.active ? &m->traj_s : NULL};
        for (int k = 0; k < 5; k++)
            if (s[k] && s[k]->at) {
                s[k]->at->t0 = m->sys.time;
                s[k]->at->k = 1;
            }
    }
    if (!rc) { /* those by count go on from the loaded count */
        mote_observer *s[5] = {m->rec.active ? &m->rec_s : NULL,
                               m->frames.active ? &m->frames_s : NULL,
                               m->snaps.active ? &m->snaps_s : NULL,
                               m->traj.active ? &m->traj_s : NULL,
                               m->ckpt.active ? &m->ckpt_s : NULL};
        for (int k = 0; k < 5; k++)
            if (s[k] && !s[k]->at)
                s[k]->from = m->sys.collisions;
    }
    if (!rc && m->log)
        fprintf(m->log, "load: %u disks at t = %.10g s from %s\n", m->sys.n, m->sys.time, path);
    return rc;
}

/* ---- placement ------------------------------------------------------------------------------------ */

/* End the samplers of an earlier experiment (their files were written at its last run). */
static void end_samplers(mb_model *m)
{
    mb_record_free(&m->rec);
    mb_density_free(&m->dens);
    m->frames.active = m->snaps.active = m->traj.active = m->ckpt.active = 0;
    m->d_record_dt = m->d_density_dt = m->d_frames_dt = m->d_snaps_dt = m->d_traj_dt = 0;
}

static int check_place(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    int groups = 0;
    mote_err e2 = {0};
    if (mb_params_check(&m->p, &groups, &e2)) {
        char where[512] = "";
        size_t k = 0;
        for (int g = 0; g < MB_P_NGROUPS && k < sizeof where; g++) {
            if (!(groups & (1 << g)))
                continue;
            int w;
            if (m->set_line[g])
                w = snprintf(where + k, sizeof where - k, "%s%s on line %d", k ? ", " : "",
                             group_names[g], m->set_line[g]);
            else
                w = snprintf(where + k, sizeof where - k, "%s%s (default)", k ? ", " : "",
                             group_names[g]);
            if (w < 0)
                break;
            k += (size_t)w;
        }
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "place: %s [set by: %s]", e2.msg, where);
    }
    m->d_placed = 1;
    m->d_place_line = c->line;
    m->d_n = m->p.n_left + m->p.n_right;
    end_samplers(m);
    return MOTE_OK;
}
static int run_place(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    int rc = mote_mb_place(&m->sys, &m->p, err);
    if (rc)
        return rc;
    end_samplers(m);
    if (m->log)
        fprintf(m->log,
                "place: %u disks (%lld left, %lld right), area fractions %.4g and %.4g, seed %llu, "
                "t_c %.6g s\n",
                m->sys.n, (long long)m->p.n_left, (long long)m->p.n_right,
                mote_mb_area_fraction(&m->p, 0), mote_mb_area_fraction(&m->p, 1),
                (unsigned long long)m->sys.seed, mote_mb_tc(&m->p));
    return MOTE_OK;
}

/* ---- running ------------------------------------------------------------------------------------ */

static int check_samples(const mb_model *m, const mote_call *c, int argi, double t,
                         mote_err *err)
{
    if (m->d_record_dt > 0 && t / m->d_record_dt > 1e7)
        return mote_call_fail(err, c, argi, MOTE_EINVAL,
                              "%s: %s s with a record every %g s would take %.3g samples (at most "
                              "10^7 per run); use a larger DT",
                              c->name, c->args[argi].text, m->d_record_dt, t / m->d_record_dt);
    if (m->d_density_dt > 0 && t / m->d_density_dt > 1e8)
        return mote_call_fail(err, c, argi, MOTE_EINVAL,
                              "%s: %s s with a density sample every %g s would take %.3g samples "
                              "(at most 10^8 per run); use a larger DT",
                              c->name, c->args[argi].text, m->d_density_dt, t / m->d_density_dt);
    if (m->d_traj_dt > 0 && t / m->d_traj_dt > 1e6)
        return mote_call_fail(err, c, argi, MOTE_EINVAL,
                              "%s: %s s with a trajectory frame every %g s would write %.3g "
                              "frames (at most 10^6 per run); use a larger DT",
                              c->name, c->args[argi].text, m->d_traj_dt, t / m->d_traj_dt);
    if (m->d_snaps_dt > 0 && t / m->d_snaps_dt > 1e5)
        return mote_call_fail(err, c, argi, MOTE_EINVAL,
                              "%s: %s s with a snapshot every %g s would write %.3g files (at "
                              "most 10^5 per run); use a larger DT",
                              c->name, c->args[argi].text, m->d_snaps_dt, t / m->d_snaps_dt);
    if (m->d_frames_dt > 0 && t / m->d_frames_dt > 1e5)
        return mote_call_fail(err, c, argi, MOTE_EINVAL,
                              "%s: %s s with a frame every %g s would write %.3g PNG files (at "
                              "most 10^5 per run); use a larger DT",
                              c->name, c->args[argi].text, m->d_frames_dt, t / m->d_frames_dt);
    return MOTE_OK;
}

static int check_run(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    int rc = mb_need_placed(m, c, err);
    return rc ? rc : check_samples(m, c, 0, c->args[0].r, err);
}

static int check_run_collisions(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    int rc = mb_need_placed(m, c, err);
    if (rc)
        return rc;
    if (m->d_n < 2)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "run_collisions: there is only one disk, which never collides");
    return check_samples(m, c, 1, c->args[1].r, err);
}

/* Copy the physics parameters the commands set into the placed system. */
static void apply_physics(mb_model *m)
{
    mote_mb_params *s = &m->sys.p;
    s->dv_b = m->p.dv_b;
    s->dv_t = m->p.dv_t;
    s->dv_s = m->p.dv_s;
    s->loss = m->p.loss;
    s->g = m->p.g;
    s->t_c = m->p.t_c;
    s->integrator = m->p.integrator;
    s->rule = m->p.rule;
}

/* The run's files, also after a failure (every sample so far); run_rc: the run's result (a run
 * stopped by the user keeps the monitor's rows in FILE.partial, mote_rows_end, and writes no
 * density profile). Returns run_rc, or a write's error after a run that succeeded. */
static int write_outputs(mb_model *m, int run_rc, mote_err *err)
{
    int rc = m->rec.active ? mote_rows_end(&m->rec.out, run_rc, err) : run_rc;
    if (m->dens.active && run_rc != MOTE_EINTR && (!rc || run_rc)) {
        mote_err werr = {0};
        const int wrc = mb_density_write(&m->dens, &m->sys, run_rc ? &werr : err);
        rc = rc ? rc : wrc;
    }
    return rc;
}

/* run and run_collisions warn when at least this share of at least this many collisions of
 * the run were made elastic by the TC rule (with loss > 0) */
#define TC_WARN_SHARE 0.9
#define TC_WARN_COLLISIONS 10000

static int do_run(mb_model *m, const mote_call *c, double t_end, uint64_t collisions_end,
                  mote_err *err)
{
    mote_mb *s = &m->sys;
    apply_physics(m);
    mote_observer samplers[6];
    size_t ns = 0;
    if (m->rec.active)
        samplers[ns++] = m->rec_s;
    if (m->dens.active)
        samplers[ns++] = m->dens_s;
    if (m->frames.active)
        samplers[ns++] = m->frames_s;
    if (m->snaps.active)
        samplers[ns++] = m->snaps_s;
    if (m->traj.active)
        samplers[ns++] = m->traj_s;
    if (m->ckpt.active) /* (the last at its count) */
        samplers[ns++] = m->ckpt_s;
    mote_progress prog;
    mote_progress_begin(&prog, c->ctx, c->name);
    const mote_loop loop = {samplers, ns, collisions_end, &prog, 0, 0, 0, 0};
    double e0 = mote_mb_energy(s, NULL), t0 = s->time, wall = mote_wall_seconds();
    mote_mb before = *s;
    int rc = mote_mb_run(s, t_end, &loop, err);
    mote_progress_end(&prog);
    /* Rewrite the files in any case: a failing run keeps every sample taken so far. */
    rc = write_outputs(m, rc, err);
    if (rc)
        return rc;
    {
        mote_mb_tally t = mote_mb_counts(s);
        mote_call_result(c, "mixing_fraction", mote_mb_mixing_fraction(&t));
        const double span = s->time - t0;
        if (span > 0) { /* the flux through the slit in each direction during the run (1/s) */
            mote_call_result(c, "flux_lr", (double)(s->cross_lr - before.cross_lr) / span);
            mote_call_result(c, "flux_rl", (double)(s->cross_rl - before.cross_rl) / span);
        }
    }
    if (m->log) {
        mote_mb_tally t = mote_mb_counts(s);
        double e1 = mote_mb_energy(s, NULL);
        double drift = e0 != 0 ? (e1 - e0) / fabs(e0) : (e1 == 0 ? 0.0 : INFINITY);
        fprintf(m->log,
                "%s: t=%.10g run_time=%.10g steps=%llu collisions=%llu mixing_fraction=%.6g "
                "E=%.10g E_rel_drift=%.3e overlaps=%llu overlaps_end=%llu overlap_steps=%llu "
                "cross_lr=%llu cross_rl=%llu wall_hits=%llu partition_hits=%llu slit_hits=%llu "
                "corner_hits=%llu collisions_tc=%llu wall_seconds=%.3f\n",
                c->name, s->time, s->time - t0, (unsigned long long)(s->steps - before.steps),
                (unsigned long long)(s->collisions - before.collisions),
                mote_mb_mixing_fraction(&t), e1, drift, (unsigned long long)s->overlaps_max,
                (unsigned long long)s->overlaps_last, (unsigned long long)s->overlap_steps,
                (unsigned long long)(s->cross_lr - before.cross_lr),
                (unsigned long long)(s->cross_rl - before.cross_rl),
                (unsigned long long)(s->wall_hits - before.wall_hits),
                (unsigned long long)(s->partition_hits - before.partition_hits),
                (unsigned long long)(s->slit_hits - before.slit_hits),
                (unsigned long long)(s->corner_hits - before.corner_hits),
                (unsigned long long)(s->collisions_tc - before.collisions_tc),
                mote_wall_seconds() - wall);
    }
    /* Nearly every collision made elastic by the TC rule: little of the loss asked for acts,
     * and where the disks pile up the event integrator slows down by orders of magnitude
     * (docs/mixing-box.md, "The cost of a pile"). Said once per run, after enough collisions
     * for the share to mean something. */
    const uint64_t nc = s->collisions - before.collisions;
    const uint64_t ntc = s->collisions_tc - before.collisions_tc;
    if (s->p.loss > 0 && nc >= TC_WARN_COLLISIONS && (double)ntc >= TC_WARN_SHARE * (double)nc)
        mote_call_warn(c,
                       "%s: %.1f%% of this run's %llu collisions were made elastic by the TC "
                       "rule (t_c = %g s), so little of the loss acts; where disks pile up "
                       "this also slows the event integrator down (docs/mixing-box.md, "
                       "'The cost of a pile')",
                       c->name, 100.0 * (double)ntc / (double)nc, (unsigned long long)nc,
                       mote_mb_tc(&s->p));
    return MOTE_OK;
}

static int run_run(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    return do_run(m, c, m->sys.time + c->args[0].r, UINT64_MAX, err);
}

static int run_run_collisions(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    uint64_t k = (uint64_t)c->args[0].i;
    uint64_t end = m->sys.collisions > UINT64_MAX - k ? UINT64_MAX : m->sys.collisions + k;
    return do_run(m, c, m->sys.time + c->args[1].r, end, err);
}

static void model_seed(void *vm, uint64_t seed) { mote_mb_seed(&((mb_model *)vm)->sys, seed); }

static int model_plot(void *vm, const char *data_path, const char *png_path,
                      const mote_call *c, mote_err *err)
{
    return mb_plot_file(data_path, png_path, err);
}

/* The parameter commands bound to the next run's parameters (the state file's "next" lines,
 * state.c): what such a command sets is what save writes and load reads (mote_cmd_set). */
static const mote_param mb_params[] = {
    {"radius", "next r"},         {"v_init", "next v_init"},
    {"loss", "next loss"},        {"gravity", "next g"},
    {"t_c", "next t_c"},          {"integrator", "next integrator"},
    {"collision_rule", "next collision_rule"},
};

static void *model_state(void *vm, const struct mote_sf_field **f, size_t *n)
{
    *f = mb_next_fields(n);
    return &((mb_model *)vm)->p;
}

/* ---- the table ----------------------------------------------------------------------------------- */

static const mote_cmd mb_commands[] = {
    {"box", NULL, "rrrr", "box X_L X_R X_B X_T", "the box walls (m)", MB_HELP_BOX, check_box,
     run_box},
    {"partition", NULL, "r r>0", "partition X1_C a", "partition centre x and thickness (m)",
     MB_HELP_PARTITION, check_partition, run_partition},
    {"slit", NULL, "r r>=0", "slit X2_C b", "slit centre y and height (m); b = 0 closes it",
     MB_HELP_SLIT, check_slit, run_slit},
    {"radius", NULL, "r>0", "radius R", "disk radius (m)", MB_HELP_RADIUS, check_radius,
     mote_cmd_set},
    {"disks", NULL, "ii", "disks nLeft nRight", "disk counts of the left and right chamber",
     MB_HELP_DISKS, check_disks, run_disks},
    {"v_init", NULL, "r[0,1e6]", "v_init V", "initial speed of every disk (m/s)", MB_HELP_VINIT,
     check_v_init, mote_cmd_set},
    {"kicks", NULL, "r>=0 r>=0 r>=0", "kicks dV_B dV_T dV_S",
     "speed added on bounces off bottom, top, side walls (m/s)", MB_HELP_KICKS, check_kicks,
     run_kicks},
    {"loss", NULL, "r[0,1]", "loss LOSS", "fraction of kinetic energy lost per disk-disk collision",
     MB_HELP_LOSS, check_loss, mote_cmd_set},
    {"gravity", NULL, "r[-1e100,1e100]", "gravity g", "gravitational acceleration in -y (m/s^2)",
     MB_HELP_GRAVITY, mote_cmd_set, mote_cmd_set},
    {"t_c", NULL, "r>=0", "t_c T", "TC-model time (s): collisions closer than T are elastic",
     MB_HELP_TC, check_t_c, mote_cmd_set},
    {"integrator", NULL, "e{timestep|event}", "integrator NAME", "event (exact, default) or timestep (the document's scheme)",
     MB_HELP_INTEGRATOR, mote_cmd_set, mote_cmd_set},
    {"collision_rule", NULL, "e{restitution|seed}", "collision_rule NAME",
     "restitution (default) or seed (the document's rule)", MB_HELP_RULE, mote_cmd_set, mote_cmd_set},
    {"checkpoint", NULL, "every=i>=1! file=f>state!", "checkpoint every=K file=FILE",
     "keep the exact state in FILE every K collisions (load continues from it)",
     MB_HELP_CHECKPOINT, mb_check_checkpoint, mb_run_checkpoint},
    MOTE_CMD_STOP(checkpoint, NULL, NULL, mb_run_checkpoint_stop),
    {"save", NULL, "f>state", "save FILE", "write the exact state to FILE", MB_HELP_SAVE, check_save,
     run_save},
    {"load", NULL, "f<state", "load FILE", "continue from a state written by save", MB_HELP_LOAD,
     check_load, run_load},
    {"place", NULL, "", "place", "place the disks at random in their chambers", MB_HELP_PLACE,
     check_place, run_place},
    {"run", NULL, "r>0", "run T", "advance by the simulated time T (s)", MB_HELP_RUN, check_run,
     run_run},
    {"run_collisions", NULL, "i>=1 r>0", "run_collisions K T_MAX",
     "advance by K disk-disk collisions (at most T_MAX s)", MB_HELP_RUN_COLLISIONS,
     check_run_collisions, run_run_collisions},
    {"monitor", "record", "@dt=r>0 @file=f>record! every=i>=1 format=e{table|csv|jsonl}",
     "monitor dt=DT|every=K file=FILE [format=table|csv|jsonl]",
     "record the mixing curve every DT s (or K collisions) into FILE",
     MB_HELP_RECORD, mb_check_record, mb_run_record},
    MOTE_CMD_STOP(monitor, NULL, mb_check_record_stop, mb_run_record_stop),
    {"density_y", NULL, "@dt=r>0! @bins=i[1,1000000]! @file=f>density_y!",
     "density_y dt=DT bins=NBINS file=FILE",
     "time-averaged density profile in y, sampled every DT s", MB_HELP_DENSITY, mb_check_density,
     mb_run_density},
    {"snapshot", NULL, "@file=f>snapshot every=i>=1 dt=r>0 prefix=f format=e{xyz|h5md|vtk}",
     "snapshot file=FILE|every=K|dt=T prefix=P [format=xyz|h5md|vtk]",
     "picture (.png), extended XYZ (.xyz), H5MD (.h5) or VTK (.vtk) of the state; or a series",
     MB_HELP_SNAPSHOT, mb_check_snapshot, mb_run_snapshot},
    {"frames", NULL, "@dt=r>0 @prefix=f! every=i>=1", "frames dt=DT|every=K prefix=PREFIX",
     "a picture every DT s (or K collisions): PREFIX_000000.png ...",
     MB_HELP_FRAMES, mb_check_frames, mb_run_frames},
    MOTE_CMD_STOP(frames, NULL, mb_check_frames_stop, mb_run_frames_stop),
    {"trajectory", NULL, "@every=i>=1 @file=f>xyz! dt=r>0 format=e{xyz|h5md}",
     "trajectory every=K|dt=T file=FILE.xyz|FILE.h5 [format=xyz|h5md]",
     "particle paths: an XYZ (or H5MD) frame now and every K collisions or T s, appended to FILE",
     MB_HELP_TRAJECTORY, mb_check_trajectory, mb_run_trajectory},
    MOTE_CMD_STOP(trajectory, NULL, mb_check_trajectory_stop, mb_run_trajectory_stop),
    MOTE_CMD_STOP(snapshot, NULL, mb_check_snapshot_stop, mb_run_snapshot_stop),
    {"movie", NULL, "@prefix=f! @fps=i[1,1000]! @file=f>movie!",
     "movie prefix=PREFIX fps=FPS file=FILE", "make a movie of the frames (needs ffmpeg)",
     MB_HELP_MOVIE, mb_check_movie, mb_run_movie},
};

/* No settle: the arrays are the whole state after every command, and each run builds its engine
 * afresh. */
static void model_live(void *vm, mote_buf *b)
{
    mb_model *m = vm;
    mb_live_frame(&m->sys, &m->p, b);
}

/* `picture FILE.png`: the picture of `snapshot FILE.png`, now. */
static int model_picture(void *vm, const char *path, mote_err *err)
{
    const mb_model *m = vm;
    if (!m->sys.placed)
        return mote_fail(err, MOTE_EINVAL, "no disks are placed yet; set the parameters, then "
                         "'place'");
    return mb_snapshot_png(&m->sys, path, err);
}

/* The box of the placed disks: x_l .. x_r by x_b .. x_t, walls on every side. */
static int model_cell(void *vm, double edges[3], double origin[3], int periodic[3])
{
    const mb_model *m = vm;
    if (!m->sys.placed)
        return -1;
    const mote_mb_params *p = &m->sys.p;
    const double e[3] = {p->x_r - p->x_l, p->x_t - p->x_b, 0}, o[3] = {p->x_l, p->x_b, 0};
    for (int a = 0; a < 3; a++) {
        edges[a] = e[a];
        origin[a] = o[a];
        periodic[a] = 0;
    }
    return 0;
}

const mote_model mote_model_mixingbox = {
    .name = "mixing-box",
    .summary = "2D disks of two colours mixing through a slit in a partition (spec mixing-box)",
    .cmds = mb_commands,
    .ncmds = sizeof mb_commands / sizeof mb_commands[0],
    .create = model_create,
    .destroy = model_destroy,
    .status = model_status,
    .seed = model_seed,
    .seed_help = MB_HELP_SEED,
    .plot_kinds = "record|density_y",
    .plot = model_plot,
    .plot_help = MB_HELP_PLOT,
    .plot_lines = "mixing:t,S_mix mixing-density:y,n_all",
    .live = model_live,
    .arrays = model_arrays,
    .set_array = model_set_array,
    .state = model_state,
    .params = mb_params,
    .nparams = sizeof mb_params / sizeof mb_params[0],
    .cell = model_cell,
    .picture = model_picture,
    .picture_help = "The picture of `snapshot FILE.png`: the box, the disks in their colours, the\n"
                    "partition with its slit; the time, mixing fraction and counts in the title.\n",
};
