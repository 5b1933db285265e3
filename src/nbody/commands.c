/* commands.c: the N-body model's script commands (spec 8): the table the script language reads,
 * the checks of state that crosses commands (are there bodies? a ring to compare with?) on a
 * dry model, and the calls into the model. Argument ranges and files are the table's. */
#include "mote/datafile.h"
#include "mote/nbody.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "nb.h"

typedef struct {
    mote_nb nb;
    mote_context *ctx;
    FILE *log;          /* ctx->out when running, NULL when validating */
    int dry;
    /* what validation knows */
    uint32_t d_bodies;
    int d_ring;
    /* the ring generated last (the reference of `check ring`) */
    mote_nb_ring ring;
    int have_ring;
    /* the monitor and the trajectory: a sample every `every` steps of integrate into `path` */
    struct nb_sampler {
        uint64_t every;     /* 0: off */
        char *path, *origin;
        double *rows;       /* cols per sample */
        size_t nrows, cap, cols;
        double L0[3];       /* trajectory: L + S when it started (the invariable plane) */
    } mon, traj;
} nb_model;

typedef struct nb_sampler nb_sampler;

static mote_nb_interaction variant_kind(const mote_context *ctx)
{
    return ctx && strcmp(ctx->model_variant, "coulomb") == 0 ? MOTE_NB_COULOMB : MOTE_NB_GRAVITY;
}

static void *model_create(mote_context *ctx, int dry)
{
    nb_model *m = calloc(1, sizeof *m);
    if (!m)
        return NULL;
    mote_nb_init(&m->nb, variant_kind(ctx));
    m->ctx = ctx;
    m->dry = dry;
    m->log = dry || !ctx ? NULL : ctx->out;
    return m;
}

static void model_destroy(void *vm)
{
    nb_model *m = vm;
    if (!m)
        return;
    mote_nb_free(&m->nb);
    nb_sampler *smp[2] = {&m->mon, &m->traj};
    for (int k = 0; k < 2; k++) {
        free(smp[k]->path);
        free(smp[k]->origin);
        free(smp[k]->rows);
    }
    free(m);
}

static void model_status(void *vm, FILE *out)
{
    nb_model *m = vm;
    const mote_nb *nb = &m->nb;
    mote_nb_monitor mon;
    mote_nb_measure(nb, &mon);
    fprintf(out,
            "N=%u interaction=%s T=%.17g steps=%llu dt=%.17g E=%.17g dE=%.3e dMz=%.3e merges=%llu\n",
            nb->n, nb->kind == MOTE_NB_GRAVITY ? "gravity" : "coulomb", nb->T,
            (unsigned long long)nb->steps, nb->dt, mon.etot, mon.dE, mon.dMz,
            (unsigned long long)nb->merges);
}

static int need_bodies(nb_model *m, const mote_call *c, mote_err *err)
{
    if (!m->d_bodies)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "%s: there are no bodies yet; add them with body or generate",
                              c->name);
    return MOTE_OK;
}

/* ---- bodies ------------------------------------------------------------------------------------ */

static int check_body(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    if (m->nb.kind == MOTE_NB_GRAVITY && mote_call_opt(c, "charge"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "charge"), MOTE_EINVAL,
                              "body: charge= is for the coulomb variant (model nbody coulomb)");
    m->d_bodies++;
    return MOTE_OK;
}
static int run_body(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    double x[3] = {mote_call_opt_r(c, "x", 0), mote_call_opt_r(c, "y", 0), mote_call_opt_r(c, "z", 0)};
    double v[3] = {mote_call_opt_r(c, "vx", 0), mote_call_opt_r(c, "vy", 0),
                   mote_call_opt_r(c, "vz", 0)};
    return mote_nb_add(&m->nb, mote_call_opt_r(c, "mass", 0), mote_call_opt_r(c, "charge", 0), x,
                       v, mote_call_opt_r(c, "radius", 0), err);
}

static int check_frame(void *vm, const mote_call *c, mote_err *err)
{
    if (strcmp(c->args[0].text, "barycentric") != 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "frame: expected 'barycentric', found '%s'",
                              c->args[0].text);
    return need_bodies(vm, c, err);
}
static int run_frame(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    double xc[3], vc[3];
    mote_nb_barycentric(&m->nb, xc, vc);
    if (m->log)
        fprintf(m->log,
                "frame: barycentric; centre of mass before: x %.17g %.17g %.17g, v %.17g %.17g "
                "%.17g\n",
                xc[0], xc[1], xc[2], vc[0], vc[1], vc[2]);
    return MOTE_OK;
}

/* ---- generators -------------------------------------------------------------------------------- */

static const char *const RING_OPTS[] = {"nb", "ka", "e", "tilt", "central_mass", "total_mass",
                                        "density", "dt", NULL};
static const char *const ATOM_OPTS[] = {"nb", "ka", "e", "tilt", "A", "Z", "n", "l",
                                        "permittivity", "time_unit", "dt", NULL};
static int listed(const char *const *list, const char *key)
{
    for (; *list; list++)
        if (strcmp(*list, key) == 0)
            return 1;
    return 0;
}

static const char *const SOLAR_OPTS[] = {"data", "bodies", "merge_inner", NULL};

static int merge_inner_opt(const mote_call *c, int *on, mote_err *err)
{
    const mote_arg *a = mote_call_opt(c, "merge_inner");
    *on = 0;
    if (!a)
        return MOTE_OK;
    if (strcmp(a->text, "on") == 0 || strcmp(a->text, "off") == 0) {
        *on = a->text[1] == 'n';
        return MOTE_OK;
    }
    return mote_call_fail(err, c, -1, MOTE_EINVAL,
                          "generate solar_system: merge_inner: expected on or off, found '%s'",
                          a->text);
}

/* `generate solar_system`: read the data file now (its errors are the script's), count bodies. */
static int check_solar(nb_model *m, const mote_call *c, mote_err *err)
{
    for (int k = 0; k < c->nopts; k++)
        if (!listed(SOLAR_OPTS, c->opts[k].key))
            return mote_call_fail(err, c, c->nargs + k, MOTE_EINVAL,
                                  "generate solar_system: option %s= belongs to a ring",
                                  c->opts[k].key);
    const mote_arg *d = mote_call_opt(c, "data");
    if (!d)
        return mote_call_fail(err, c, 0, MOTE_EINVAL,
                              "generate solar_system: data=FILE is required (for example "
                              "data/outer_solar_system.dat)");
    if (m->d_bodies)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "generate: the system already has bodies; a generator starts empty");
    int inner;
    int rc = merge_inner_opt(c, &inner, err);
    if (rc)
        return rc;
    m->d_bodies = 2;
    m->d_ring = 0;
    if (access(d->path, R_OK) != 0)
        return MOTE_OK; /* written by an earlier command: read when it runs */
    mote_nb_solar s;
    char msg[sizeof err->msg];
    if ((rc = mote_nb_solar_read(d->path, &s, err)) != MOTE_OK) {
        snprintf(msg, sizeof msg, "%s", err->msg);
        return mote_call_fail(err, c, -1, rc, "%s", msg);
    }
    mote_nb t;
    mote_nb_init(&t, MOTE_NB_GRAVITY);
    const mote_arg *b = mote_call_opt(c, "bodies");
    rc = mote_nb_solar_build(&t, &s, b ? b->text : NULL, inner, err);
    if (!rc)
        m->d_bodies = t.n;
    mote_nb_free(&t);
    mote_nb_solar_free(&s);
    if (!rc)
        return MOTE_OK;
    snprintf(msg, sizeof msg, "%s", err->msg);
    return mote_call_fail(err, c, -1, rc, "%s", msg);
}

static int run_solar(nb_model *m, const mote_call *c, mote_err *err)
{
    int inner;
    int rc = merge_inner_opt(c, &inner, err);
    mote_nb_solar s;
    if (!rc)
        rc = mote_nb_solar_read(mote_call_opt(c, "data")->path, &s, err);
    if (rc)
        return rc;
    const mote_arg *b = mote_call_opt(c, "bodies");
    rc = mote_nb_solar_build(&m->nb, &s, b ? b->text : NULL, inner, err);
    mote_nb_solar_free(&s);
    if (!rc && m->log)
        fprintf(m->log,
                "generate solar_system: %u bodies; M %.16e kg, Am %.16e m, kv %.16e s/m, "
                "kt %.16e 1/s (time unit: the sidereal century)\n",
                m->nb.n, m->nb.u.M, m->nb.u.Am, m->nb.u.kv, m->nb.u.kt);
    m->have_ring = 0;
    return rc;
}


static int check_generate(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const char *what = c->args[0].text;
    int ring = strcmp(what, "ring") == 0, atom = strcmp(what, "atom_ring") == 0;
    if (strcmp(what, "solar_system") == 0) {
        if (m->nb.kind != MOTE_NB_GRAVITY)
            return mote_call_fail(err, c, 0, MOTE_EINVAL,
                                  "generate solar_system: this is a Coulomb run; it needs 'model "
                                  "nbody gravity'");
        return check_solar(m, c, err);
    }
    if (!ring && !atom)
        return mote_call_fail(err, c, 0, MOTE_EINVAL,
                              "generate: expected ring, atom_ring or solar_system, found '%s'", what);
    if (ring != (m->nb.kind == MOTE_NB_GRAVITY))
        return mote_call_fail(err, c, 0, MOTE_EINVAL,
                              "generate %s: this is a %s run; the %s needs 'model nbody %s'", what,
                              m->nb.kind == MOTE_NB_GRAVITY ? "gravity" : "Coulomb",
                              ring ? "gravity ring" : "Coulomb ring", ring ? "gravity" : "coulomb");
    for (int k = 0; k < c->nopts; k++)
        if (!listed(ring ? RING_OPTS : ATOM_OPTS, c->opts[k].key))
            return mote_call_fail(err, c, c->nargs + k, MOTE_EINVAL,
                                  "generate %s: option %s= belongs to the other ring", what,
                                  c->opts[k].key);
    if (m->d_bodies)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "generate: the system already has bodies; a ring starts empty");
    const mote_arg *nbo = mote_call_opt(c, "nb");
    m->d_bodies = nbo ? (uint32_t)nbo->i : ring ? 30 : 9;
    m->d_ring = 1;
    return MOTE_OK;
}
static int run_generate(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    if (strcmp(c->args[0].text, "solar_system") == 0)
        return run_solar(m, c, err);
    mote_nb_ring *r = &m->ring;
    mote_nb_ring_defaults(r, m->nb.kind);
    const mote_arg *a;
    if ((a = mote_call_opt(c, "nb")))
        r->nb = (int)a->i;
    r->ka = mote_call_opt_r(c, "ka", r->ka);
    r->e = mote_call_opt_r(c, "e", r->e);
    r->tilt = mote_call_opt_r(c, "tilt", r->tilt);
    r->central_mass = mote_call_opt_r(c, "central_mass", r->central_mass);
    r->total_mass = mote_call_opt_r(c, "total_mass", r->total_mass);
    r->density = mote_call_opt_r(c, "density", r->density);
    r->dt = mote_call_opt_r(c, "dt", r->dt);
    if ((a = mote_call_opt(c, "A")))
        r->A = (int)a->i;
    if ((a = mote_call_opt(c, "Z")))
        r->Z = (int)a->i;
    if ((a = mote_call_opt(c, "n")))
        r->nq = (int)a->i;
    if ((a = mote_call_opt(c, "l")))
        r->lq = (int)a->i;
    r->permittivity = mote_call_opt_r(c, "permittivity", r->permittivity);
    r->time_unit = mote_call_opt_r(c, "time_unit", r->time_unit);
    int rc = mote_nb_ring_build(&m->nb, r, err);
    if (rc)
        return rc;
    m->have_ring = 1;
    if (m->log)
        fprintf(m->log,
                "generate: %d bodies; Am %.16e m, kv %.16e s/m, kt %.16e 1/s; Rp/Am %.16g, "
                "vp kv %.16g, period %.17g; centre of mass before the shift: %.3e (x), %.3e (v)\n",
                r->nb, m->nb.u.Am, m->nb.u.kv, m->nb.u.kt, r->rp_o, r->vp_o, r->period,
                fmax(fabs(r->xc[0]), fmax(fabs(r->xc[1]), fabs(r->xc[2]))),
                fmax(fabs(r->vc[0]), fmax(fabs(r->vc[1]), fabs(r->vc[2]))));
    return MOTE_OK;
}

/* ---- the integrator ---------------------------------------------------------------------------- */

/* The order option: an integer in [lo, hi], or for taylor `auto` (then from tol=). */
static int parse_order(const mote_call *c, int taylor, int *order, mote_err *err)
{
    const mote_arg *a = mote_call_opt(c, "order");
    int argi = mote_call_opt_index(c, "order");
    if (!a)
        return MOTE_OK;
    if (taylor && strcmp(a->text, "auto") == 0) {
        *order = mote_nb_taylor_auto_order(mote_call_opt_r(c, "tol", 1e-16));
        return MOTE_OK;
    }
    char *end;
    long v = strtol(a->text, &end, 10);
    int lo = 2, hi = taylor ? MOTE_NB_TAYLOR_MAX : 6;
    if (end == a->text || *end || v < lo || v > hi)
        return mote_call_fail(err, c, argi, MOTE_EINVAL,
                              "integrator %s: order must be an integer in [%d, %d]%s, found '%s'",
                              taylor ? "taylor" : "galactica", lo, hi, taylor ? " or auto" : "",
                              a->text);
    *order = (int)v;
    return MOTE_OK;
}

static const char *const GALACTICA_OPTS[] = {"dt", "order", "first_step", NULL};
static const char *const TAYLOR_OPTS[] = {"dt",     "order", "tol",  "memory",
                                          "safety", "hmin",  "hmax", NULL};

static int check_integrator(void *vm, const mote_call *c, mote_err *err)
{
    const char *name = c->args[0].text;
    int taylor = strcmp(name, "taylor") == 0;
    if (!taylor && strcmp(name, "galactica") != 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL,
                              "integrator: expected galactica or taylor, found '%s'", name);
    for (int k = 0; k < c->nopts; k++)
        if (!listed(taylor ? TAYLOR_OPTS : GALACTICA_OPTS, c->opts[k].key))
            return mote_call_fail(err, c, c->nargs + k, MOTE_EINVAL,
                                  "integrator %s: no option %s= (options: %s)", name,
                                  c->opts[k].key,
                                  taylor ? "dt, order, tol, memory, safety, hmin, hmax"
                                         : "dt, order, first_step");
    if (taylor && mote_call_opt(c, "dt") && mote_call_opt(c, "tol") &&
        strcmp(mote_call_opt(c, "order") ? mote_call_opt(c, "order")->text : "", "auto") != 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "tol"), MOTE_EINVAL,
                              "integrator taylor: dt= fixes the step and tol= makes it adaptive; "
                              "give one (tol= may come with order=auto)");
    const mote_arg *mem = mote_call_opt(c, "memory");
    if (mem && strcmp(mem->text, "store") != 0 && strcmp(mem->text, "recompute") != 0 &&
        strcmp(mem->text, "auto") != 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "memory"), MOTE_EINVAL,
                              "integrator taylor: memory must be store, recompute or auto, "
                              "found '%s'", mem->text);
    int order = 0;
    return parse_order(c, taylor, &order, err);
}
static int run_integrator(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int taylor = strcmp(c->args[0].text, "taylor") == 0;
    m->nb.integrator = taylor ? MOTE_NB_TAYLOR : MOTE_NB_GALACTICA;
    m->nb.dt = mote_call_opt_r(c, "dt", m->nb.dt);
    int rc = parse_order(c, taylor, taylor ? &m->nb.taylor_order : &m->nb.order, err);
    if (rc)
        return rc;
    m->nb.first_step = mote_call_opt_r(c, "first_step", m->nb.first_step);
    const mote_arg *mem = mote_call_opt(c, "memory");
    if (mem)
        m->nb.taylor_memory = strcmp(mem->text, "store") == 0       ? 1
                              : strcmp(mem->text, "recompute") == 0 ? 2
                                                                    : 0;
    if (taylor) {
        m->nb.adaptive = mote_call_opt(c, "dt") == NULL;
        m->nb.tol = mote_call_opt_r(c, "tol", m->nb.tol);
        m->nb.safety = mote_call_opt_r(c, "safety", m->nb.safety);
        m->nb.hmin = mote_call_opt_r(c, "hmin", m->nb.hmin);
        m->nb.hmax = mote_call_opt_r(c, "hmax", m->nb.hmax);
        m->nb.hprev = 0;
    }
    return MOTE_OK;
}

static int check_merge(void *vm, const mote_call *c, mote_err *err)
{
    const char *s = c->args[0].text;
    if (strcmp(s, "on") != 0 && strcmp(s, "off") != 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "merge: expected on or off, found '%s'", s);
    return MOTE_OK;
}
static int run_merge(void *vm, const mote_call *c, mote_err *err)
{
    mote_nb *nb = &((nb_model *)vm)->nb;
    nb->merging = strcmp(c->args[0].text, "on") == 0;
    nb->bt = mote_call_opt_r(c, "bt", nb->bt);
    nb->bt_hmin = mote_call_opt_r(c, "hmin", nb->bt_hmin);
    return MOTE_OK;
}

static int check_compensated(void *vm, const mote_call *c, mote_err *err)
{
    const char *s = c->args[0].text;
    if (strcmp(s, "on") != 0 && strcmp(s, "off") != 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "compensated: expected on or off, found '%s'",
                              s);
    return MOTE_OK;
}
static int run_compensated(void *vm, const mote_call *c, mote_err *err)
{
    ((nb_model *)vm)->nb.compensated = strcmp(c->args[0].text, "on") == 0;
    return MOTE_OK;
}

/* ---- monitor and integrate ------------------------------------------------------------------- */

enum { MON_COLS = 25 };
static const char MON_NAMES[] = "step T h E_kin U E_tot dE Px Py Pz Lx Ly Lz Sx Sy Sz dMz Xcm Ycm "
                                "Zcm E_corr E_heat E_spin merges N_active";

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

static int monitor_sample(nb_model *m, mote_err *err)
{
    double *r = sampler_row(&m->mon);
    if (!r)
        return mote_fail(err, MOTE_ENOMEM, "monitor: out of memory");
    const mote_nb *nb = &m->nb;
    mote_nb_monitor mon;
    mote_nb_measure(nb, &mon);
    uint32_t active = 0;
    for (uint32_t i = 0; i < nb->n; i++)
        active += nb->active[i];
    double row[MON_COLS] = {(double)nb->steps, nb->T,       nb->hlast,   mon.ekin,
                            mon.u,             mon.etot,    mon.dE,      mon.P[0],
                            mon.P[1],          mon.P[2],    mon.L[0],    mon.L[1],
                            mon.L[2],          mon.S[0],    mon.S[1],    mon.S[2],
                            mon.dMz,           mon.R[0] / mon.mtot,      mon.R[1] / mon.mtot,
                            mon.R[2] / mon.mtot, mon.ecorr, nb->e_heat,  nb->e_spin,
                            (double)nb->merges, (double)active};
    memcpy(r, row, sizeof row);
    return MOTE_OK;
}

static int trajectory_sample(nb_model *m, mote_err *err)
{
    nb_sampler *s = &m->traj;
    if (s->cols != 3 + 3 * (size_t)m->nb.n)
        return mote_fail(err, MOTE_EINVAL, "trajectory: the number of bodies changed (%u now)",
                         m->nb.n);
    double *r = sampler_row(s);
    if (!r)
        return mote_fail(err, MOTE_ENOMEM, "trajectory: out of memory");
    mote_nb_monitor mon;
    mote_nb_measure(&m->nb, &mon);
    r[0] = m->nb.T;
    r[1] = mon.ekin;
    r[2] = mon.etot;
    memcpy(r + 3, m->nb.x, 3 * (size_t)m->nb.n * sizeof *r);
    return MOTE_OK;
}

/* The header lines both files share after the preamble. */
static void run_header(FILE *f, const mote_nb *nb, uint64_t every)
{
    fprintf(f, "# interaction = %s\n# N = %u\n# integrator = galactica\n# order = %d\n",
            nb->kind == MOTE_NB_GRAVITY ? "gravity" : "coulomb", nb->n, nb->order);
    fprintf(f, "# dt = %.17g\n# compensated = %d\n# every = %llu\n", nb->dt, nb->compensated,
            (unsigned long long)every);
    if (nb->u.set)
        fprintf(f, "# M_Ss = %.17g\n# Am = %.17g\n# kv = %.17g\n# kt = %.17g\n", nb->u.M,
                nb->u.Am, nb->u.kv, nb->u.kt);
    fprintf(f, "# units: dimensionless (G = 1 or the Coulomb constant 1, total mass 1; spec "
               "3.5)\n");
}

static int sampler_write(nb_model *m, nb_sampler *s, int traj, mote_err *err)
{
    mote_datafile d;
    int rc = mote_datafile_open(&d, s->path, traj ? "nbody-trajectory" : "nbody-monitor",
                                s->origin, 0, err);
    if (rc)
        return rc;
    run_header(d.f, &m->nb, s->every);
    if (traj) {
        fprintf(d.f, "# Lx0 = %.17g\n# Ly0 = %.17g\n# Lz0 = %.17g\n", s->L0[0], s->L0[1],
                s->L0[2]);
        fprintf(d.f, "# a row per sample: T, E_kin, E_tot, then x y z of each body\n# columns: "
                     "T E_kin E_tot");
        for (size_t b = 1; 3 + 3 * (b - 1) < s->cols; b++)
            fprintf(d.f, " x%zu y%zu z%zu", b, b, b);
        fputc('\n', d.f);
    } else {
        fprintf(d.f, "# dE is (E_corr - E0)/|E0| with E_corr = E_tot minus the energy changes of "
                     "merges, dMz the aggregated z moment's (Lz + Sz) relative change from the "
                     "run's start\n");
        mote_datafile_columns(&d, MON_NAMES);
    }
    for (size_t k = 0; k < s->nrows; k++) {
        const double *r = s->rows + k * s->cols;
        for (size_t c = 0; c < s->cols; c++)
            fprintf(d.f, c == 0 && !traj ? "%.0f" : c ? " %.17g" : "%.17g", r[c]);
        fputc('\n', d.f);
    }
    return mote_datafile_commit(&d, err);
}

/* Start a sampler for the call (K FILE): now, then every K steps of integrate. */
static int sampler_start(nb_model *m, nb_sampler *s, const mote_call *c, size_t cols,
                         mote_err *err)
{
    free(s->path);
    free(s->origin);
    s->path = strdup(c->args[1].path);
    s->origin = mote_call_origin(c);
    s->every = (uint64_t)c->args[0].i;
    s->nrows = 0;
    s->cols = cols;
    if (!s->path || !s->origin)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", c->name);
    if (!m->nb.ref_set && m->nb.n)
        mote_nb_set_reference(&m->nb);
    return MOTE_OK;
}

static int run_monitor(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int rc = sampler_start(m, &m->mon, c, MON_COLS, err);
    if (!rc && m->nb.n)
        rc = monitor_sample(m, err);
    return rc ? rc : sampler_write(m, &m->mon, 0, err);
}

static int check_trajectory(void *vm, const mote_call *c, mote_err *err)
{
    return need_bodies(vm, c, err);
}
static int run_trajectory(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int rc = sampler_start(m, &m->traj, c, 3 + 3 * (size_t)m->nb.n, err);
    if (rc)
        return rc;
    mote_nb_monitor mon;
    mote_nb_measure(&m->nb, &mon);
    for (int a = 0; a < 3; a++)
        m->traj.L0[a] = mon.L[a] + mon.S[a];
    rc = trajectory_sample(m, err);
    return rc ? rc : sampler_write(m, &m->traj, 1, err);
}

static int check_integrate(void *vm, const mote_call *c, mote_err *err)
{
    int given = (mote_call_opt(c, "steps") != NULL) + (mote_call_opt(c, "to") != NULL) +
                (mote_call_opt(c, "for") != NULL);
    if (given != 1)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "integrate: give exactly one of steps=N, to=T and for=D (found %d)",
                              given);
    return need_bodies(vm, c, err);
}

/* Steps to the next sample of s (at most `left`). */
static uint64_t until_sample(const nb_sampler *s, uint64_t steps, uint64_t left)
{
    if (!s->path)
        return left;
    uint64_t next = (steps / s->every + 1) * s->every - steps;
    return next < left ? next : left;
}

static int run_integrate(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    m->nb.threads = c->ctx->threads;
    const mote_arg *a = mote_call_opt(c, "steps");
    uint64_t steps = a ? (uint64_t)a->i : UINT64_MAX, done = 0;
    const double t0 = m->nb.T;
    double t_end = INFINITY;
    if ((a = mote_call_opt(c, "to")))
        t_end = a->r;
    else if ((a = mote_call_opt(c, "for")))
        t_end = m->nb.T + a->r;
    mote_progress prog;
    mote_progress_begin(&prog, c->ctx, "integrate");
    int rc = MOTE_OK;
    const uint64_t warned = m->nb.approach_warnings;
    while (done < steps && !rc && m->nb.T < t_end) {
        uint64_t chunk = until_sample(&m->mon, m->nb.steps, steps - done);
        chunk = until_sample(&m->traj, m->nb.steps, chunk);
        if (chunk > 1000)
            chunk = 1000;
        uint64_t before = m->nb.steps;
        rc = mote_nb_integrate(&m->nb, chunk, t_end, err);
        done += m->nb.steps - before;
        if (!rc && m->mon.path && (m->nb.steps % m->mon.every == 0 || m->nb.T == t_end))
            rc = monitor_sample(m, err);
        if (!rc && m->traj.path && (m->nb.steps % m->traj.every == 0 || m->nb.T == t_end))
            rc = trajectory_sample(m, err);
        if (!rc && m->nb.steps == before) /* no step could be taken: the end is reached */
            break;
        mote_progress_update(&prog, t_end < INFINITY ? (m->nb.T - t0) / (t_end - t0)
                                                     : (double)done / (double)steps);
    }
    mote_progress_end(&prog);
    if (m->nb.approach_warnings > warned && m->log)
        fprintf(m->log,
                "integrate: warning: %llu merge%s overlapped by more than 10%% of the radii after "
                "a step at the shortest length (merge accuracy not ensured; largest overlap "
                "%.3g): lower hmin= or bt= of 'merge'\n",
                (unsigned long long)(m->nb.approach_warnings - warned),
                m->nb.approach_warnings - warned > 1 ? "s" : "", m->nb.max_overlap);
    /* the samples so far, even after a failure */
    nb_sampler *smp[2] = {&m->mon, &m->traj};
    for (int k = 0; k < 2; k++) {
        if (!smp[k]->path)
            continue;
        mote_err werr = {0};
        int wrc = sampler_write(m, smp[k], k, rc ? &werr : err);
        rc = rc ? rc : wrc;
    }
    return rc;
}

/* ---- state files ------------------------------------------------------------------------------ */

static int check_save(void *vm, const mote_call *c, mote_err *err) { return need_bodies(vm, c, err); }
static int run_save(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int rc = nb_state_save(&m->nb, c->args[0].path, err);
    if (!rc && m->log)
        fprintf(m->log, "save: wrote %s\n", c->args[0].path);
    return rc;
}

static int check_load(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    uint32_t n = 1;
    if (!mote_outputs_find(&c->ctx->outputs, c->args[0].path)) {
        int rc = nb_state_peek(c->args[0].path, &n, err);
        if (rc) {
            char why[sizeof err->msg];
            snprintf(why, sizeof why, "%s", err->msg);
            return mote_call_fail(err, c, 0, (mote_status)rc, "load: %s", why);
        }
    }
    m->d_bodies = n;
    m->d_ring = 0;
    return MOTE_OK;
}
static int run_load(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int rc = nb_state_load(&m->nb, c->args[0].path, err);
    if (!rc) {
        m->have_ring = 0;
        if (m->log)
            fprintf(m->log, "load: %u bodies at T = %.17g from %s\n", m->nb.n, m->nb.T,
                    c->args[0].path);
    }
    return rc;
}

static int check_check(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    if (strcmp(c->args[0].text, "ring") != 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "check: expected 'ring', found '%s'",
                              c->args[0].text);
    if (!m->d_ring)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "check ring: no ring was generated (generate ring or atom_ring)");
    return MOTE_OK;
}
static int run_check(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    double plane;
    double e = mote_nb_ring_error(&m->nb, &m->ring, &plane);
    mote_nb_monitor mon;
    mote_nb_measure(&m->nb, &mon);
    if (m->log)
        fprintf(m->log,
                "check ring: T = %.17g (%.6g periods): error %.3e, out of the orbit plane %.3e "
                "of a, dE %.3e, dMz %.3e\n",
                m->nb.T, m->nb.T / m->ring.period, e, plane / m->ring.a_o, mon.dE, mon.dMz);
    return MOTE_OK;
}

/* ---- the table ---------------------------------------------------------------------------------- */

static const char HELP_BODY[] =
    "    body mass=M [x= y= z= vx= vy= vz= radius= charge=]\n"
    "\n"
    "Add a body, in dimensionless units (G = 1 or the Coulomb constant 1; spec\n"
    "3.5): mass > 0, position, velocity, radius >= 0, and for `model nbody coulomb`\n"
    "its charge in elementary charges. Unset values are 0. Bad values (NaN,\n"
    "infinite, a mass <= 0) stop the run at this line; two bodies at one point are\n"
    "refused when the integrator starts.\n";

static const char HELP_FRAME[] =
    "    frame barycentric\n"
    "\n"
    "Shift every body so that the centre of mass is at rest at the origin (spec\n"
    "3.4); prints the centre of mass position and velocity before the shift.\n";

static const char HELP_GENERATE[] =
    "    generate ring [nb= ka= e= tilt= central_mass= total_mass= density= dt=]\n"
    "    generate atom_ring [nb= A= Z= n= l= ka= e= tilt= permittivity= time_unit= dt=]\n"
    "    generate solar_system data=FILE [bodies=Sun,Jupiter,...] [merge_inner=on|off]\n"
    "\n"
    "The exact axisymmetric rings of the seed document (spec 9.1 and 9.2): a\n"
    "central body and nb - 1 equal bodies at the vertices of a regular polygon,\n"
    "all at pericentre of identical Kepler ellipses (eccentricity e) in a plane\n"
    "tilted by `tilt` radians about x, an exact solution of the N-body problem.\n"
    "`ring` (gravity, Appendix 1): defaults nb = 30, a = ka AU with ka = 1,\n"
    "e = 0.2056, tilt 0.409, the Sun's mass at the centre (kg), the Solar-System\n"
    "mass in all (kg), density 5000 kg/m^3 for the radii, time unit one sidereal\n"
    "century, dt = 1e-6. `atom_ring` (Coulomb, Appendix 3): an oxygen-like atom,\n"
    "nb = 9, A = 16, Z = 8, n = 2, l = 1, e = 0.15, time unit 1e-15 s, dt = 1e-7.\n"
    "The scales follow spec 3.5 (time unit first, Am refined so that\n"
    "Am = 1/(kt kv) exactly); the system is reduced to the barycentre. Prints the\n"
    "scales, the pericentre distance and speed, the period and the centre of mass\n"
    "before the shift. Fails when neighbours are less than 50 diameters apart.\n"
    "`solar_system` (spec 9.3): the bodies of a Solar-System data file (format in\n"
    "docs/nbody.md; data/outer_solar_system.dat holds the outer Solar System of\n"
    "Hairer, Lubich & Wanner), all or those listed in `bodies=`, in the file's\n"
    "order; merge_inner=on adds Mercury, Venus, Earth, Moon and Mars to the Sun.\n"
    "Masses relative to the total, time unit the sidereal century, Am from eq. 8\n"
    "refined, barycentric.\n";

static const char HELP_INTEGRATOR[] =
    "    integrator galactica [dt=H] [order=K] [first_step=F]\n"
    "    integrator taylor [dt=H] [order=P|auto] [tol=E] [memory=store|recompute|auto]\n"
    "\n"
    "`galactica`: Galactica's Taylor scheme (spec 4.2): two passes over all\n"
    "ordered pairs give the acceleration, jerk and the fourth and fifth\n"
    "derivatives; the sixth is the difference of fifth derivatives over the\n"
    "previous step. order=K (2 ... 6, default 6) keeps the terms up to x^(K) (spec\n"
    "4.3). A start without a previous fifth derivative takes a first step of F dt\n"
    "(default 0.001).\n"
    "\n"
    "`taylor`: the general Taylor integrator (spec 4.4): every coefficient up to\n"
    "order P (2 ... 60, default 20) from exact recurrences (automatic\n"
    "differentiation), ceil((P-1)/2) passes over the pairs per step. With dt=H the\n"
    "step is fixed; without it the step is adaptive (spec 4.5): for each body the\n"
    "step at which its two highest Taylor terms stay below tol=E (default 1e-16)\n"
    "times the distance to its nearest neighbour, the smallest of them times\n"
    "safety=S (default 1), at most twice the previous step, within [hmin, hmax].\n"
    "order=auto takes P = ceil(1 - ln(E)/2) (E = 1e-16: P = 20).\n"
    "memory=store keeps the pairs' histories between passes (2 (P-1) N^2 reals),\n"
    "recompute does without them; auto (default) stores up to 1 GiB. Both give the\n"
    "same bits.\n";

static const char HELP_COMPENSATED[] =
    "    compensated on|off\n"
    "\n"
    "Compensated (Kahan) summation of positions, velocities and time (default on;\n"
    "spec 4.6). With it the seed document's read-back times are reproduced to the\n"
    "last bit.\n";

static const char HELP_MERGE[] =
    "    merge on|off [bt=F] [hmin=H]\n"
    "\n"
    "Collisions with merging (spec 5), on by default when any body has a radius.\n"
    "After every step, bodies closer than the sum of their radii merge: the\n"
    "heavier survives (equal masses: the lower number) with the summed mass and\n"
    "charge at the pair's centre of mass and its velocity (momentum kept); the\n"
    "pair's orbital moment about that centre becomes spin (L + S kept); the volume\n"
    "is kept (Ra^3 = Ra_i^3 + Ra_k^3); the radial part of the relative kinetic\n"
    "energy becomes heat (Galactica's eq. 11), the tangential part spin energy.\n"
    "The lighter body keeps its number with mass, charge and radius 0, inactive.\n"
    "Closest pairs (relative to their radii) merge first, each body at most once\n"
    "per sweep, sweeps repeating until nothing touches. The monitor's dE follows\n"
    "E_corr = E_tot minus the energy changes of the merges; the step after a merge\n"
    "restarts.\n"
    "Close approaches (spec 4.7, Galactica's bt; the Galactica scheme): before a\n"
    "step h, a pair with |r| - |v| h - |a| h^2/2 < Ra_i + Ra_k (relative position,\n"
    "velocity, acceleration) is approaching contact; the step is multiplied by\n"
    "bt (default 0.5; 1 turns the control off) until none is, but not below\n"
    "hmin dt (default hmin = 1e-6), and afterwards grows by 1/bt per step back to\n"
    "dt. A merge whose overlap exceeds 10% of Ra_i + Ra_k after a step at the\n"
    "shortest length is counted as a warning (merge accuracy not ensured), which\n"
    "`integrate` prints. The adaptive Taylor step needs no such control: its\n"
    "error scale is the distance to the nearest neighbour.\n";

static const char HELP_MONITOR[] =
    "    monitor K FILE\n"
    "\n"
    "Record the conserved quantities (spec 3.7) now and every K steps of later\n"
    "`integrate` commands into the data file FILE (columns: step T h E_kin U E_tot\n"
    "dE Px Py Pz Lx Ly Lz Sx Sy Sz dMz Xcm Ycm Zcm E_corr E_heat E_spin merges\n"
    "N_active; dE = (E_corr - E0)/|E0| and dMz the aggregated z moment's relative\n"
    "change since the start of the run). The file is rewritten, atomically, at the\n"
    "end of every integrate.\n";

static const char HELP_TRAJECTORY[] =
    "    trajectory K FILE\n"
    "\n"
    "Record T, E_kin, E_tot and the position of every body now and every K steps\n"
    "of later `integrate` commands into the data file FILE (spec 10.3), rewritten\n"
    "atomically at the end of every integrate. Its header keeps the total angular\n"
    "momentum at the start, so `plot FILE orbits.png` draws the orbits in the\n"
    "invariable plane.\n";

static const char HELP_INTEGRATE[] =
    "    integrate steps=N\n"
    "    integrate to=T\n"
    "    integrate for=D\n"
    "\n"
    "Advance with the chosen integrator: N steps, or up to the dimensionless time T\n"
    "(or for the time D from now), shortening the last step so that T is reached\n"
    "exactly (the monitor and the trajectory then also sample at T). Exactly one of\n"
    "the three is given.\n";

static const char HELP_SAVE[] =
    "    save FILE\n"
    "\n"
    "Write the exact state: every body (mass, charge, radius, position, velocity,\n"
    "their compensation terms, spin, the previous fifth derivative), the time with\n"
    "its compensation, the step, the scheme's settings and previous step, the\n"
    "monitor references and the scales, each number to 17 significant digits. So\n"
    "`A; save F; load F; B` and `A; B` give the same numbers, bit for bit, and\n"
    "save -> load -> save gives the same file. Written atomically.\n";

static const char HELP_LOAD[] =
    "    load FILE\n"
    "\n"
    "Continue from a state written by `save` (of the same interaction). The file is\n"
    "read strictly: a malformed line is reported with its number and nothing of the\n"
    "current system changes.\n";

static const char HELP_CHECK[] =
    "    check ring\n"
    "\n"
    "Print the deviation from the exact ring solution (spec 9.1, 9.2): the largest\n"
    "|x - x_exact| / |x_exact| over the ring bodies, the largest distance from the\n"
    "orbit plane (in units of a), and the energy and moment drifts.\n";

static const char HELP_PLOT[] =
    "Data files of `trajectory` and `monitor`: a trajectory as the orbits of every\n"
    "body projected on the invariable plane (perpendicular to the total angular\n"
    "momentum when the recording started; a tilted ring shows its true ellipses),\n"
    "equal scales on both axes, one colour per body, the first body with its\n"
    "points; a monitor file as the relative drifts of the energy and of the\n"
    "aggregated z moment against time.\n";

static int model_plot(void *vm, const char *data_path, const char *png_path, mote_err *err)
{
    return nb_plot_file(data_path, png_path, err);
}

static const mote_cmd nb_commands[] = {
    {"body", NULL,
     "mass=r>0! x=r y=r z=r vx=r vy=r vz=r radius=r>=0 charge=r",
     "body mass=M [x=X] [y=Y] [z=Z] [vx=VX] [vy=VY] [vz=VZ] [radius=R] [charge=Q]",
     "add a body (dimensionless units)", HELP_BODY, check_body, run_body},
    {"frame", NULL, "s", "frame barycentric", "shift to the barycentre (centre of mass at rest)",
     HELP_FRAME, check_frame, run_frame},
    {"generate", NULL,
     "s nb=i>=2 ka=r>0 e=r[0,1) tilt=r central_mass=r>0 total_mass=r>0 density=r>0 dt=r>0 "
     "A=i>=1 Z=i>=1 n=i>=1 l=i permittivity=r>0 time_unit=r>0 data=f<solar bodies=s "
     "merge_inner=s",
     "generate KIND [options]", "the exact gravity ring or Coulomb ring of the seed document",
     HELP_GENERATE, check_generate, run_generate},
    {"integrator", NULL,
     "s dt=r>0 order=s first_step=r(0,1] tol=r(0,1) memory=s safety=r>0 hmin=r>=0 hmax=r>0",
     "integrator NAME [dt=H] [order=K] [first_step=F] [tol=E] [memory=M] [safety=S] "
     "[hmin=A] [hmax=B]",
     "choose and set the integrator (galactica or taylor)",
     HELP_INTEGRATOR, check_integrator, run_integrator},
    {"compensated", NULL, "s", "compensated on|off", "compensated summation (default on)",
     HELP_COMPENSATED, check_compensated, run_compensated},
    {"merge", NULL, "s bt=r(0,1] hmin=r(0,1]", "merge on|off [bt=F] [hmin=H]", "merge bodies that touch (default: on when any has a radius)",
     HELP_MERGE, check_merge, run_merge},
    {"monitor", NULL, "i>=1 f>monitor", "monitor K FILE",
     "record energy, momentum, moment and centre of mass every K steps", HELP_MONITOR,
     NULL, run_monitor},
    {"trajectory", NULL, "i>=1 f>trajectory", "trajectory K FILE",
     "record the positions of every body every K steps (plot draws the orbits)", HELP_TRAJECTORY,
     check_trajectory, run_trajectory},
    {"integrate", NULL, "steps=i>=1 to=r for=r>0", "integrate [steps=N] [to=T] [for=D]",
     "advance by N steps, to the time T, or for the time D (ends exactly)", HELP_INTEGRATE,
     check_integrate, run_integrate},
    {"save", NULL, "f>state", "save FILE", "write the exact state to FILE", HELP_SAVE, check_save,
     run_save},
    {"load", NULL, "f<state", "load FILE", "continue from a state written by save", HELP_LOAD,
     check_load, run_load},
    {"check", NULL, "s", "check ring", "compare with the exact ring solution", HELP_CHECK,
     check_check, run_check},
};

const mote_model mote_model_nbody = {
    .name = "nbody",
    .summary = "gravitational or Coulomb N-body integration with Galactica's Taylor scheme",
    .variants = "gravity|coulomb",
    .threaded = 1,
    .cmds = nb_commands,
    .ncmds = sizeof nb_commands / sizeof nb_commands[0],
    .create = model_create,
    .destroy = model_destroy,
    .status = model_status,
    .plot_kinds = "monitor|trajectory",
    .plot = model_plot,
    .plot_help = HELP_PLOT,
};
