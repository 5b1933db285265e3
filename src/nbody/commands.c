/* commands.c: the N-body model's script commands (spec 8): the table the script language reads,
 * the checks of state that crosses commands (are there bodies? a ring to compare with?) on a
 * dry model, and the calls into the model. Argument ranges and files are the table's. */
#include "mote/datafile.h"
#include "mote/nbody.h"

#include <tgmath.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
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
    int d_scales;       /* are physical scales known (units or a generator)? */
    /* units (spec 3.5): body values in SI, and while `raw`, held in SI until the total mass is
     * known (mass=auto): the scales then come from `req` */
    int input_si, raw;
    struct nb_units_req {
        int preset;       /* UNITS_CUSTOM, UNITS_SOLAR, UNITS_ATOMIC, UNITS_NONE */
        int mass_auto, input_si;
        double mass, length, time; /* kg, m, s (length or time: the other is 0) */
    } req;
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
        int on, format;     /* format: FMT_TABLE, FMT_CSV, FMT_JSONL (path NULL: the terminal) */
        mote_real dt, t0;   /* by time: samples at t0 + k dt (dt 0: every `every` steps) */
        uint64_t k;
        double ekmax, t_ekmax; /* monitor: the largest kinetic energy of a body so far */
        double cpu0, wall0;    /* monitor: clocks when it started */
        uint32_t *sel, nsel;   /* trajectory: the bodies recorded (0-based), and how many */
        uint32_t n0;           /* trajectory: the number of bodies when it started */
        int vel;               /* trajectory: velocities too */
    } mon, traj;
    /* checkpoints: the exact state into `path` every `every` steps and at the end of integrate */
    struct {
        char *path;
        uint64_t every;
    } ckpt;
    /* periodic snapshots: PREFIX STEP .snap (galactica: .dat) every `every` steps (0: off) */
    struct {
        char *prefix, *origin;
        uint64_t every;
        int galactica;
    } snap;
    /* closest approaches of one body (spec 7.9, 10.4): a row every `every` steps into path */
    struct {
        nb_approach a;
        uint64_t every;   /* 0: off */
        char *path, *origin;
        int galactica;    /* dice.dat's three columns (time, body, distance) */
    } appr;
    /* Galactica-style pictures (spec 7.13) every `every` steps: PREFIX000001.png, ... */
    struct {
        uint64_t every, count;
        char *prefix;
        nb_galctl ctl;      /* the graphics values and trios */
        nb_frame_opts f;
    } frames;
    /* the live view: the plane shown (0 xy, 1 xz, 2 yz) and the recent paths of up to
     * LIVE_PATHS bodies, LIVE_LEN points each (a ring per body; view state only) */
    struct {
        int plane;
        double *pts;
        uint32_t nb;
        size_t len, head;
    } live;
    /* the header of the last Galactica file read (its Em and area fields are carried over) */
    int have_galhead;
    mote_real galhead[25];
    /* validation: the format each monitor or trajectory file is written in ("table", "csv",
     * "jsonl"), so that `plot` of one it cannot read fails before the run */
    mote_outputs formats;
} nb_model;

typedef struct nb_sampler nb_sampler;
typedef struct nb_units_req nb_units_req;
enum { UNITS_CUSTOM, UNITS_SOLAR, UNITS_ATOMIC, UNITS_NONE };

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
    free(m->ckpt.path);
    free(m->snap.prefix);
    free(m->snap.origin);
    nb_approach_free(&m->appr.a);
    free(m->live.pts);
    free(m->frames.prefix);
    free(m->appr.path);
    free(m->appr.origin);
    mote_outputs_free(&m->formats);
    nb_sampler *smp[2] = {&m->mon, &m->traj};
    for (int k = 0; k < 2; k++) {
        free(smp[k]->path);
        free(smp[k]->origin);
        free(smp[k]->rows);
        free(smp[k]->sel);
    }
    free(m);
}

/* Scales from a request and the total mass M (kg). */
static void units_make(const mote_nb *nb, const nb_units_req *q, double M, mote_nb_units *u)
{
    if (q->time > 0)
        mote_nb_units_from_time(u, nb->kind, M, 1.0 / q->time, nb->G, nb->e2, nb->eps);
    else
        mote_nb_units_from_length(u, nb->kind, M, q->length, nb->G, nb->e2, nb->eps);
}

/* Bodies given in SI under mass=auto become dimensionless once a command needs the scales: the
 * mass unit is their total (spec 8). */
static void settle_units(nb_model *m)
{
    if (!m->raw || !m->nb.n)
        return;
    double M = 0;
    for (uint32_t i = 0; i < m->nb.n; i++)
        M += m->nb.m[i];
    mote_nb_units u;
    units_make(&m->nb, &m->req, M, &u);
    mote_nb_from_si(&m->nb, &u);
    m->raw = 0;
    if (m->log)
        fprintf(m->log,
                "units: mass unit %.17g kg (the total of %u bodies), Am %.17g m, kv %.17g s/m, "
                "kt %.17g 1/s\n",
                u.M, m->nb.n, u.Am, u.kv, u.kt);
}

static void model_status(void *vm, FILE *out)
{
    nb_model *m = vm;
    const mote_nb *nb = &m->nb;
    if (m->raw) { /* SI values: the scales wait for the total mass */
        fprintf(out, "N=%u interaction=%s (bodies in SI until the scales are fixed)\n", nb->n,
                nb->kind == MOTE_NB_GRAVITY ? "gravity" : "coulomb");
        return;
    }
    char t[MOTE_REAL_BUF], h[MOTE_REAL_BUF], e[MOTE_REAL_BUF], de[32];
    double dmz;
    if (nb->n > NB_STATUS_MAX_N) { /* the energy is an O(N^2) sum: the monitor measures it */
        snprintf(e, sizeof e, "-");
        snprintf(de, sizeof de, "-");
        dmz = nb->ref_set ? (double)mote_nb_dmz(nb) : 0;
    } else {
        mote_nb_monitor mon;
        mote_nb_measure(nb, &mon);
        mote_real_str(mon.etot, e);
        snprintf(de, sizeof de, "%.3e", (double)mon.dE);
        dmz = (double)mon.dMz;
    }
    fprintf(out, "N=%u interaction=%s T=%s steps=%llu dt=%s E=%s dE=%s dMz=%.3e merges=%llu\n",
            nb->n, nb->kind == MOTE_NB_GRAVITY ? "gravity" : "coulomb", mote_real_str(nb->T, t),
            (unsigned long long)nb->steps, mote_real_str(nb->dt, h), e, de,
            dmz, (unsigned long long)nb->merges);
}

/* A real option to the build's full precision (its text read again), or dflt when not given. */
static mote_real opt_real_or(const mote_call *c, const char *key, mote_real dflt)
{
    const mote_arg *a = mote_call_opt(c, key);
    return a ? mote_real_parse(a->text, NULL) : dflt;
}
static mote_real opt_real(const mote_call *c, const char *key) { return opt_real_or(c, key, 0); }

static int need_bodies(nb_model *m, const mote_call *c, mote_err *err)
{
    if (!m->d_bodies)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "%s: there are no bodies yet; add them with body or generate",
                              c->name);
    return MOTE_OK;
}

/* ---- bodies ------------------------------------------------------------------------------------ */

/* spin=SX,SY,SZ: three finite reals */
static int parse_spin(const char *t, mote_real sp[3])
{
    for (int a = 0; a < 3; a++) {
        char *end;
        sp[a] = mote_real_parse(t, &end);
        if (end == t || !isfinite(sp[a]) || *end != (a < 2 ? ',' : '\0'))
            return -1;
        t = end + 1;
    }
    return 0;
}

static int check_body(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    mote_real sp[3];
    if (mote_call_opt(c, "radius") && mote_call_opt(c, "density"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "density"), MOTE_EINVAL,
                              "body: give radius= or density=, not both");
    if (mote_call_opt(c, "spin") && parse_spin(mote_call_opt(c, "spin")->text, sp))
        return mote_call_fail(err, c, mote_call_opt_index(c, "spin"), MOTE_EINVAL,
                              "body: spin: expected three finite numbers SX,SY,SZ, found '%s'",
                              mote_call_opt(c, "spin")->text);
    const mote_arg *nm = mote_call_opt(c, "name");
    if (nm && !mote_nb_name_ok(nm->text))
        return mote_call_fail(err, c, mote_call_opt_index(c, "name"), MOTE_EINVAL,
                              "body: name: expected 1 to %d characters, a letter first, then "
                              "letters, digits and _ . + - (found '%s')", MOTE_NB_NAME - 1,
                              nm->text);
    if (m->nb.kind == MOTE_NB_GRAVITY && mote_call_opt(c, "charge"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "charge"), MOTE_EINVAL,
                              "body: charge= is for the coulomb variant (model nbody coulomb)");
    m->d_bodies++;
    return MOTE_OK;
}
static int run_body(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    mote_real x[3] = {opt_real(c, "x"), opt_real(c, "y"), opt_real(c, "z")};
    mote_real v[3] = {opt_real(c, "vx"), opt_real(c, "vy"), opt_real(c, "vz")};
    mote_real mass = opt_real(c, "mass"), ra = opt_real(c, "radius"), sp[3] = {0, 0, 0};
    if (mote_call_opt(c, "density")) /* a sphere of that mass, in the input's units */
        ra = cbrt(3 * mass / (16 * atan((mote_real)1) * opt_real(c, "density")));
    if (mote_call_opt(c, "spin"))
        parse_spin(mote_call_opt(c, "spin")->text, sp);
    if (m->input_si && !m->raw) { /* SI with the scales known: convert now (eq. 6) */
        const mote_nb_units *u = &m->nb.u;
        mass /= u->M;
        ra /= u->Am;
        for (int a = 0; a < 3; a++) {
            x[a] /= u->Am;
            v[a] *= u->kv;
            sp[a] *= u->kv / (u->M * u->Am); /* m x v */
        }
    }
    const mote_arg *nm = mote_call_opt(c, "name");
    if (nm && mote_nb_find(&m->nb, nm->text) >= 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "name"), MOTE_EINVAL,
                              "body: the name '%s' is taken by body %ld", nm->text,
                              mote_nb_find(&m->nb, nm->text) + 1);
    int rc = mote_nb_add(&m->nb, mass, opt_real(c, "charge"), x, v, ra, err);
    if (!rc)
        for (int a = 0; a < 3; a++)
            m->nb.sp[3 * (size_t)(m->nb.n - 1) + a] = sp[a];
    if (!rc && nm)
        rc = mote_nb_set_name(&m->nb, m->nb.n - 1, nm->text, err);
    return rc;
}

/* ---- units and constants ------------------------------------------------------------------------ */

/* Read `units` tokens: a preset and/or KEY=VALUE (mass=KG|auto length=M time=S
 * input=si|dimensionless). */
static int units_parse(const nb_model *m, const mote_call *c, nb_units_req *q, mote_err *err)
{
    memset(q, 0, sizeof *q);
    q->preset = UNITS_CUSTOM;
    q->mass_auto = 1;
    int input = -1, have_mass = 0;
    for (int k = 0; k < c->nargs; k++) {
        const char *t = c->args[k].text, *eq = strchr(t, '=');
        if (!eq) {
            static const char *const presets[] = {"", "solar", "atomic", "dimensionless"};
            int p = 1;
            while (p < 4 && strcmp(t, presets[p]) != 0)
                p++;
            if (p == 4 || k > 0)
                return mote_call_fail(err, c, k, MOTE_EINVAL,
                                      "units: expected solar, atomic or dimensionless first, or "
                                      "KEY=VALUE (mass=, length=, time=, input=), found '%s'", t);
            q->preset = p;
            continue;
        }
        size_t kl = (size_t)(eq - t);
        const char *val = eq + 1;
        char *end;
        double x = strtod(val, &end);
        int num = end != val && !*end && isfinite(x) && x > 0;
        if (kl == 5 && strncmp(t, "input", 5) == 0) {
            if (strcmp(val, "si") != 0 && strcmp(val, "dimensionless") != 0)
                return mote_call_fail(err, c, k, MOTE_EINVAL,
                                      "units: input must be si or dimensionless, found '%s'", val);
            input = val[0] == 's';
        } else if (kl == 4 && strncmp(t, "mass", 4) == 0) {
            if (strcmp(val, "auto") != 0 && !num)
                return mote_call_fail(err, c, k, MOTE_EINVAL,
                                      "units: mass must be a number > 0 (kg) or auto, found '%s'",
                                      val);
            q->mass_auto = !num;
            q->mass = num ? x : 0;
            have_mass = 1;
        } else if ((kl == 6 && strncmp(t, "length", 6) == 0) ||
                   (kl == 4 && strncmp(t, "time", 4) == 0)) {
            if (!num)
                return mote_call_fail(err, c, k, MOTE_EINVAL,
                                      "units: %.*s must be a number > 0 (%s), found '%s'", (int)kl,
                                      t, kl == 4 ? "s" : "m", val);
            if (q->length > 0 || q->time > 0)
                return mote_call_fail(err, c, k, MOTE_EINVAL,
                                      "units: give length= or time=, not both (the other follows "
                                      "from eq. 6)");
            *(kl == 4 ? &q->time : &q->length) = x;
        } else
            return mote_call_fail(err, c, k, MOTE_EINVAL,
                                  "units: no option '%.*s' (mass=, length=, time=, input=)",
                                  (int)kl, t);
    }
    if (q->preset == UNITS_NONE) {
        if (c->nargs > 1)
            return mote_call_fail(err, c, 1, MOTE_EINVAL,
                                  "units dimensionless: takes no options");
        return MOTE_OK;
    }
    if (q->preset != UNITS_CUSTOM && (q->length > 0 || q->time > 0))
        return mote_call_fail(err, c, 0, MOTE_EINVAL,
                              "units %s: the preset fixes the time unit; leave out length= and "
                              "time=", c->args[0].text);
    if (q->preset == UNITS_SOLAR)
        q->time = 100 * MOTE_NB_SIDEREAL_YEAR_DAYS * 86400;
    if (q->preset == UNITS_ATOMIC) {
        if (m->nb.kind != MOTE_NB_COULOMB)
            return mote_call_fail(err, c, 0, MOTE_EINVAL,
                                  "units atomic: is for Coulomb runs (model nbody coulomb)");
        q->time = 1e-15;
    }
    if (!(q->length > 0 || q->time > 0))
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "units: give length=M or time=S (or a preset: solar, atomic)");
    q->input_si = input != 0;
    if (q->mass_auto && !q->input_si) {
        if (q->preset == UNITS_SOLAR && !have_mass) { /* the Solar-System mass of spec 3.6 */
            q->mass_auto = 0;
            q->mass = MOTE_NB_SOLAR_SYSTEM_MASS;
        } else
            return mote_call_fail(err, c, -1, MOTE_EINVAL,
                                  "units: mass=auto (the total of the bodies) needs input=si; "
                                  "with dimensionless input give mass=KG");
    }
    return MOTE_OK;
}

static int check_units(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    nb_units_req q;
    int rc = units_parse(m, c, &q, err);
    if (rc)
        return rc;
    if (m->d_bodies)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "units: comes before the bodies (they are read in its units)");
    m->d_scales = q.preset != UNITS_NONE;
    return MOTE_OK;
}
static int run_units(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int rc = units_parse(m, c, &m->req, err);
    if (rc)
        return rc;
    m->raw = 0;
    m->input_si = m->req.input_si;
    if (m->req.preset == UNITS_NONE) {
        memset(&m->nb.u, 0, sizeof m->nb.u);
        return MOTE_OK;
    }
    if (m->req.mass_auto) { /* the scales wait for the bodies */
        m->raw = 1;
        if (m->log)
            fprintf(m->log, "units: bodies in SI; the mass unit will be their total\n");
        return MOTE_OK;
    }
    units_make(&m->nb, &m->req, m->req.mass, &m->nb.u);
    const mote_nb_units *u = &m->nb.u;
    if (m->log)
        fprintf(m->log,
                "units: M %.17g kg, Am %.17g m, kv %.17g s/m, kt %.17g 1/s; body values in %s\n",
                u->M, u->Am, u->kv, u->kt, m->input_si ? "SI" : "dimensionless units");
    return MOTE_OK;
}

static int check_constant(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    if (!c->nopts)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "constant: give at least one of G=, e=, e2=, permittivity=");
    if (mote_call_opt(c, "e") && mote_call_opt(c, "e2"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "e2"), MOTE_EINVAL,
                              "constant: e= and e2= set the same constant; give one");
    if (m->d_bodies || m->d_scales)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "constant: comes before units, the generators and the bodies");
    return MOTE_OK;
}
static int run_constant(void *vm, const mote_call *c, mote_err *err)
{
    (void)err;
    mote_nb *nb = &((nb_model *)vm)->nb;
    nb->G = mote_call_opt_r(c, "G", nb->G);
    const mote_arg *e = mote_call_opt(c, "e");
    if (e)
        nb->e2 = 1e-9 * e->r * e->r; /* CGSE to kg m^3 s^-2 (spec 3.2) */
    nb->e2 = mote_call_opt_r(c, "e2", nb->e2);
    nb->eps = mote_call_opt_r(c, "permittivity", nb->eps);
    return MOTE_OK;
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
    mote_real xc[3], vc[3];
    settle_units(m);
    mote_nb_barycentric(&m->nb, xc, vc);
    char b[6][MOTE_REAL_BUF];
    if (m->log)
        fprintf(m->log, "frame: barycentric; centre of mass before: x %s %s %s, v %s %s %s\n",
                mote_real_str(xc[0], b[0]), mote_real_str(xc[1], b[1]), mote_real_str(xc[2], b[2]),
                mote_real_str(vc[0], b[3]), mote_real_str(vc[1], b[4]), mote_real_str(vc[2], b[5]));
    return MOTE_OK;
}

/* max |v[a]| as a double (for the log) */
static double max_abs3(const mote_real v[3])
{
    double w = 0;
    for (int a = 0; a < 3; a++)
        w = fmax(w, fabs((double)v[a]));
    return w;
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
    m->d_scales = 1;
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


/* ---- generate area (spec 9.4) ---- */

static const char *const AREA_OPTS[] = {"b", "c", "origin", "mu", "sep_density", "sep_pos",
                                        "sep_vel", "omega", "axis", "rho_area", "rho_body",
                                        "dt", "length", NULL};

/* The area's options into a (mote_nb_area_defaults first); a located error for a bad list. */
static int area_opts(const mote_call *c, mote_nb_area *a, mote_err *err)
{
    mote_nb_area_defaults(a);
    a->B = mote_call_opt_r(c, "b", a->B);
    a->C = mote_call_opt_r(c, "c", a->C);
    const mote_arg *o = mote_call_opt(c, "mu");
    if (o)
        a->Mu = (int)o->i;
    a->RoS = mote_call_opt_r(c, "sep_density", a->RoS);
    a->wu = mote_call_opt_r(c, "omega", a->wu);
    a->Roa = mote_call_opt_r(c, "rho_area", a->Roa);
    a->Rob = mote_call_opt_r(c, "rho_body", a->Rob);
    a->Am = mote_call_opt_r(c, "length", a->Am);
    a->dt = opt_real_or(c, "dt", a->dt);
    static const char *const vec[3] = {"origin", "sep_pos", "sep_vel"};
    double *dst[3] = {a->X0, a->Xs, a->Us};
    for (int k = 0; k < 3; k++) {
        mote_real v[3];
        if (!(o = mote_call_opt(c, vec[k])))
            continue;
        if (parse_spin(o->text, v))
            return mote_call_fail(err, c, mote_call_opt_index(c, vec[k]), MOTE_EINVAL,
                                  "generate area: %s= expects X,Y,Z (three numbers), found '%s'",
                                  vec[k], o->text);
        for (int q = 0; q < 3; q++)
            dst[k][q] = (double)v[q];
    }
    if ((o = mote_call_opt(c, "axis"))) {
        char extra;
        if (sscanf(o->text, "%lf,%lf%c", &a->X01, &a->Y01, &extra) != 2 || !isfinite(a->X01) ||
            !isfinite(a->Y01))
            return mote_call_fail(err, c, mote_call_opt_index(c, "axis"), MOTE_EINVAL,
                                  "generate area: axis= expects X01,Y01 (two numbers), found "
                                  "'%s'", o->text);
    }
    return MOTE_OK;
}

static int check_area(nb_model *m, const mote_call *c, mote_err *err)
{
    for (int k = 0; k < c->nopts; k++)
        if (!listed(AREA_OPTS, c->opts[k].key))
            return mote_call_fail(err, c, c->nargs + k, MOTE_EINVAL,
                                  "generate area: option %s= is not an area option (b c origin mu "
                                  "sep_density sep_pos sep_vel omega axis rho_area rho_body dt "
                                  "length)", c->opts[k].key);
    if (m->nb.kind != MOTE_NB_GRAVITY)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "generate area: this is a Coulomb run; the "
                              "area of matter needs 'model nbody gravity'");
    if (m->d_bodies)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "generate: the system already has bodies; the area starts empty");
    mote_nb_area a;
    int rc = area_opts(c, &a, err);
    if (rc)
        return rc;
    mote_nb t; /* built now: a bad combination is the script's error */
    mote_nb_init(&t, MOTE_NB_GRAVITY);
    rc = mote_nb_area_build(&t, &a, err);
    m->d_bodies = t.n;
    mote_nb_free(&t);
    if (rc) {
        char why[sizeof err->msg];
        snprintf(why, sizeof why, "%s", err->msg);
        return mote_call_fail(err, c, -1, (mote_status)rc, "%s", why);
    }
    m->d_ring = 0;
    m->d_scales = 1;
    return MOTE_OK;
}

static int run_area(nb_model *m, const mote_call *c, mote_err *err)
{
    mote_nb_area a;
    int rc = area_opts(c, &a, err);
    if (!rc)
        rc = mote_nb_area_build(&m->nb, &a, err);
    if (rc)
        return rc;
    m->have_ring = 0;
    memset(m->galhead, 0, sizeof m->galhead); /* the header's area fields (spec 7.5) */
    const double h[7] = {a.nx, a.ny, a.nz, 1, a.B, a.C, a.Mu};
    for (int k = 0; k < 7; k++)
        m->galhead[17 + k] = h[k];
    m->have_galhead = 1;
    if (m->log)
        fprintf(m->log, "generate area: %d x %d x %d bodies%s; kt %.16e 1/s, Am %.16e m\n",
                a.nx, a.ny, a.nz,
                a.sep_added ? " and the separate body"
                : a.RoS > 0 ? " (the separate body is closer than 1/Mu to a node: not added)" : "",
                m->nb.u.kt, m->nb.u.Am);
    return MOTE_OK;
}

static int check_generate(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const char *what = c->args[0].text;
    if (strcmp(what, "area") == 0)
        return check_area(m, c, err);
    if (strcmp(what, "plummer") == 0) {
        for (int k = 0; k < c->nopts; k++)
            if (strcmp(c->opts[k].key, "n") != 0 && strcmp(c->opts[k].key, "seed") != 0)
                return mote_call_fail(err, c, c->nargs + k, MOTE_EINVAL,
                                      "generate plummer: option %s= (expected n= and seed=)",
                                      c->opts[k].key);
        const mote_arg *n = mote_call_opt(c, "n");
        if (!n || n->i > NB_MAX_GENERATED)
            return mote_call_fail(err, c, n ? mote_call_opt_index(c, "n") : 0, MOTE_EINVAL,
                                  "generate plummer: n= the number of bodies (1 ... 10^7)");
        mote_err e2 = {0};
        if (mote_mem_check((double)n->i * NB_BODY_BYTES, "generate plummer: the bodies", &e2))
            return mote_call_fail(err, c, mote_call_opt_index(c, "n"), e2.code, "%s", e2.msg);
        if (m->nb.kind != MOTE_NB_GRAVITY || m->d_bodies)
            return mote_call_fail(err, c, 0, MOTE_EINVAL, "generate plummer: %s",
                                  m->d_bodies ? "the system already has bodies"
                                              : "a Plummer sphere needs 'model nbody gravity'");
        m->d_bodies = (uint32_t)n->i;
        m->d_ring = 0;
        m->d_scales = 1;
        return MOTE_OK;
    }
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
                              "generate: expected ring, atom_ring, solar_system, area or plummer, "
                              "found "
                              "'%s'", what);
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
    m->d_scales = 1;
    return MOTE_OK;
}
static int run_generate(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    m->raw = 0; /* a generator sets its own scales */
    if (strcmp(c->args[0].text, "solar_system") == 0)
        return run_solar(m, c, err);
    if (strcmp(c->args[0].text, "area") == 0)
        return run_area(m, c, err);
    if (strcmp(c->args[0].text, "plummer") == 0) {
        const mote_arg *sd = mote_call_opt(c, "seed");
        m->have_ring = 0;
        int rc = mote_nb_plummer(&m->nb, (uint32_t)mote_call_opt(c, "n")->i,
                                 sd ? (uint64_t)sd->i : 1, err);
        if (!rc && m->log)
            fprintf(m->log, "generate plummer: %u equal masses, Plummer radius 1, G = 1 units, "
                            "barycentric\n", m->nb.n);
        return rc;
    }
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
    r->dt = opt_real_or(c, "dt", r->dt);
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
    /* the header's area fields (spec 9.1 step 7): Mu, B, C and the grid they make */
    memset(m->galhead, 0, sizeof m->galhead);
    const int mu = (int)ceil(cbrt((double)r->nb + 1) - 1e-9);
    const double B = r->nb == 30 ? 0.5 : r->nb == 300 ? 0.9 : r->nb == 3000 ? 0.9 : 1,
                 C = r->nb == 30 ? 0.25 : r->nb == 300 ? 0.6 : r->nb == 3000 ? 0.7955 : 1;
    const double h[7] = {1 + mu, floor(1 + mu * B + 0.5), floor(1 + mu * C + 0.5), 1, B, C, mu};
    for (int k = 0; k < 7; k++)
        m->galhead[17 + k] = h[k];
    m->have_galhead = 1;
    char per[MOTE_REAL_BUF];
    if (m->log)
        fprintf(m->log,
                "generate: %d bodies; Am %.16e m, kv %.16e s/m, kt %.16e 1/s; Rp/Am %.16g, "
                "vp kv %.16g, period %s; centre of mass before the shift: %.3e (x), %.3e (v)\n",
                r->nb, m->nb.u.Am, m->nb.u.kv, m->nb.u.kt, (double)r->rp_o, (double)r->vp_o,
                mote_real_str(r->period, per), max_abs3(r->xc), max_abs3(r->vc));
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
        *order = mote_nb_taylor_auto_order(opt_real_or(c, "tol", MOTE_REAL_TOL));
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

static const char *const GALACTICA_OPTS[] = {"dt",   "order", "first_step", "tol",    "safety",
                                             "hmin", "hmax",  "step",       "dt_max", NULL};
static const char *const TAYLOR_OPTS[] = {"dt",   "order", "tol",  "memory", "safety",
                                          "hmin", "hmax",  "norm", NULL};

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
                                  taylor ? "dt, order, tol, memory, safety, hmin, hmax, norm"
                                         : "dt, order, first_step, tol, safety, hmin, hmax, step, "
                                           "dt_max");
    const mote_arg *norm = mote_call_opt(c, "norm");
    if (norm && strcmp(norm->text, "nearest") != 0 && strcmp(norm->text, "global") != 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "norm"), MOTE_EINVAL,
                              "integrator taylor: norm must be nearest or global, found '%s'",
                              norm->text);
    if (norm && mote_call_opt(c, "dt"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "norm"), MOTE_EINVAL,
                              "integrator taylor: norm= is for the adaptive step (tol=), not "
                              "with dt=");
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
    const mote_arg *st = mote_call_opt(c, "step");
    const char *mode = st ? st->text : mote_call_opt(c, "tol") ? "adaptive" : "fixed";
    if (st && strcmp(mode, "fixed") != 0 && strcmp(mode, "adaptive") != 0 &&
        strcmp(mode, "doubling") != 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "step"), MOTE_EINVAL,
                              "integrator galactica: step must be fixed, adaptive or doubling, "
                              "found '%s'", mode);
    if (strcmp(mode, "adaptive") != 0 && mote_call_opt(c, "tol"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "tol"), MOTE_EINVAL,
                              "integrator galactica: tol= is for step=adaptive (found step=%s)",
                              mode);
    if (strcmp(mode, "doubling") == 0 && !mote_call_opt(c, "dt_max"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "step"), MOTE_EINVAL,
                              "integrator galactica: step=doubling needs dt_max=");
    if (strcmp(mode, "fixed") == 0 && mote_call_opt(c, "dt_max"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "dt_max"), MOTE_EINVAL,
                              "integrator galactica: dt_max= is for step=adaptive or doubling");
    const mote_arg *hmin = mote_call_opt(c, "hmin"), *hmax = mote_call_opt(c, "hmax");
    if (hmin && hmax && mote_real_parse(hmin->text, NULL) > mote_real_parse(hmax->text, NULL))
        return mote_call_fail(err, c, mote_call_opt_index(c, "hmin"), MOTE_EINVAL,
                              "integrator %s: hmin= (%s) is greater than hmax= (%s)", name,
                              hmin->text, hmax->text);
    int order = 6, rc = parse_order(c, taylor, &order, err);
    if (!rc && !taylor && strcmp(mode, "adaptive") == 0 && mote_call_opt(c, "order") && order != 6)
        return mote_call_fail(err, c, mote_call_opt_index(c, "tol"), MOTE_EINVAL,
                              "integrator galactica: the adaptive step (tol=) needs order=6");
    return rc;
}
static int run_integrator(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int taylor = strcmp(c->args[0].text, "taylor") == 0;
    m->nb.integrator = taylor ? MOTE_NB_TAYLOR : MOTE_NB_GALACTICA;
    m->nb.dt = opt_real_or(c, "dt", m->nb.dt);
    int rc = parse_order(c, taylor, taylor ? &m->nb.taylor_order : &m->nb.order, err);
    if (rc)
        return rc;
    m->nb.first_step = opt_real_or(c, "first_step", m->nb.first_step);
    const mote_arg *mem = mote_call_opt(c, "memory");
    if (mem)
        m->nb.taylor_memory = strcmp(mem->text, "store") == 0       ? 1
                              : strcmp(mem->text, "recompute") == 0 ? 2
                                                                    : 0;
    /* adaptive: a Taylor run without dt=, a Galactica run with tol= */
    const mote_arg *st = mote_call_opt(c, "step");
    m->nb.adaptive = taylor ? mote_call_opt(c, "dt") == NULL
                            : st ? strcmp(st->text, "adaptive") == 0
                                 : mote_call_opt(c, "tol") != NULL;
    m->nb.doubling = !taylor && st && strcmp(st->text, "doubling") == 0;
    m->nb.dt_max = opt_real_or(c, "dt_max", 0);
    if (!taylor && m->nb.adaptive && mote_call_opt(c, "dt_max") && !mote_call_opt(c, "hmax"))
        m->nb.hmax = m->nb.dt_max; /* dt_max bounds the adaptive step too */
    m->nb.dbl_have = 0; /* the rule's blocks start afresh */
    m->nb.dbl_count = 0;
    m->nb.dbl_sum = 0;
    m->nb.dbl_mean = -1;
    const mote_arg *norm = mote_call_opt(c, "norm");
    if (taylor && m->nb.adaptive && norm && strcmp(norm->text, "global") == 0)
        m->nb.adaptive = MOTE_NB_NORM_GLOBAL;
    m->nb.tol = opt_real_or(c, "tol", m->nb.tol);
    m->nb.safety = opt_real_or(c, "safety", m->nb.safety);
    m->nb.hmin = opt_real_or(c, "hmin", m->nb.hmin);
    m->nb.hmax = opt_real_or(c, "hmax", m->nb.hmax);
    return MOTE_OK; /* (the previous step stays: a restart continues as the run would have) */
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
    nb->bt = opt_real_or(c, "bt", nb->bt);
    nb->bt_hmin = opt_real_or(c, "hmin", nb->bt_hmin);
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

/* forces direct (spec 6.1); the tree of spec 6.2 belongs to the large-N work */
static int check_forces(void *vm, const mote_call *c, mote_err *err)
{
    const char *s = c->args[0].text;
    if (strcmp(s, "direct") != 0 && strcmp(s, "tree") != 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "forces: expected direct or tree, found '%s'",
                              s);
    if (strcmp(s, "direct") == 0 && mote_call_opt(c, "theta"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "theta"), MOTE_EINVAL,
                              "forces: theta= is for forces tree");
    const mote_arg *t = mote_call_opt(c, "theta");
    if (t && !(t->r < 2))
        return mote_call_fail(err, c, mote_call_opt_index(c, "theta"), MOTE_EINVAL,
                              "forces tree: theta = %g; the tree's opening angle must be below 2 "
                              "(0.5 is the default, 0.3 more accurate)", t->r);
    return MOTE_OK;
}
static int run_forces(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const mote_arg *t = mote_call_opt(c, "theta");
    m->nb.tree_on = strcmp(c->args[0].text, "tree") == 0;
    m->nb.theta = m->nb.tree_on ? (mote_real)(t ? t->r : 0.5) : 0;
    if (m->log && m->nb.tree_on)
        fprintf(m->log, "forces: Barnes-Hut tree, theta %g (approximate: every output says so)\n",
                (double)m->nb.theta);
    return MOTE_OK;
}

/* ---- monitor and integrate ------------------------------------------------------------------- */

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

enum { FMT_TABLE, FMT_CSV, FMT_JSONL };

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

static int sample(nb_model *m, int traj, const mote_nb *nb, mote_err *err)
{
    return traj ? trajectory_sample(m, nb, err) : monitor_sample(m, nb, err);
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

/* Rewrite the sampler's file (atomically) with every sample so far. */
static int sampler_write(nb_model *m, nb_sampler *s, int traj, mote_err *err)
{
    if (!s->path)
        return MOTE_OK;
    const char *kind = traj ? "nbody-trajectory" : "nbody-monitor";
    mote_datafile d;
    int rc;
    if (s->format == FMT_JSONL) {
        rc = mote_afile_open(&d.af, s->path, err);
        d.f = d.af.f;
    } else
        rc = mote_datafile_open(&d, s->path, kind, s->origin, 0, err);
    if (rc)
        return rc;
    FILE *f = d.f;
    const char sep = s->format == FMT_CSV ? ',' : ' ';
    if (s->format != FMT_JSONL) {
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
            fprintf(f, "# dE is (E_corr - E0)/|E0| with E_corr = E_tot minus the energy changes "
                       "of merges, dMz the aggregated z moment's (Lz + Sz) relative change and dL "
                       "|L + S - (L + S)0| / |(L + S)0| from the run's start\n");
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
        fputc('\n', f);
    }
    for (size_t k = 0; k < s->nrows; k++) {
        const double *r = s->rows + k * s->cols;
        if (s->format == FMT_JSONL) {
            fprintf(f, "{\"format\":\"%s\"", kind);
            for (size_t c = 0; c < s->cols; c++) {
                char name[40];
                fprintf(f, ",\"%s\":", traj ? traj_column(m, c, name) : MON_NAME[c]);
                put_json(f, r[c]);
            }
            fputs("}\n", f);
            continue;
        }
        for (size_t c = 0; c < s->cols; c++) {
            if (c)
                fputc(sep, f);
            fprintf(f, !traj && mon_integer((int)c) ? "%.0f" : "%.17g", r[c]);
        }
        fputc('\n', f);
    }
    if (s->format == FMT_JSONL)
        return mote_afile_commit(&d.af, err);
    return mote_datafile_commit(&d, err);
}

/* unit=NAME: a known unit, and physical scales to convert with. */
static int check_time_unit(nb_model *m, const mote_call *c, mote_err *err)
{
    const mote_arg *u = mote_call_opt(c, "unit");
    if (!u)
        return MOTE_OK;
    int k = mote_call_opt_index(c, "unit");
    if (!(mote_nb_time_unit(u->text) > 0))
        return mote_call_fail(err, c, k, MOTE_EINVAL,
                              "%s: unit must be s, day, year or century, found '%s'", c->name,
                              u->text);
    if (!m->d_scales)
        return mote_call_fail(err, c, k, MOTE_EINVAL,
                              "%s: unit= needs physical scales: set them with units (or a "
                              "generator) first", c->name);
    return MOTE_OK;
}

/* The dimensionless time of one unit= (1 without it); fails at run time when the scales are
 * unknown (a loaded state without them). */
static int time_scale(const nb_model *m, const mote_call *c, double *scale, mote_err *err)
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
static int check_sampler(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int every = mote_call_opt(c, "every") != NULL, dt = mote_call_opt(c, "dt") != NULL;
    if (every + dt != 1)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "%s: give one of every=K (steps) and dt=T (time)", c->name);
    int rc = check_time_unit(m, c, err);
    if (rc)
        return rc;
    const mote_arg *f = mote_call_opt(c, "format");
    if (f && strcmp(f->text, "table") != 0 && strcmp(f->text, "csv") != 0 &&
        strcmp(f->text, "jsonl") != 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "format"), MOTE_EINVAL,
                              "%s: format must be table, csv or jsonl, found '%s'", c->name,
                              f->text);
    if (f && !mote_call_opt(c, "file"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "format"), MOTE_EINVAL,
                              "%s: format= is for a file: give file=FILE", c->name);
    const mote_arg *file = mote_call_opt(c, "file");
    if (file && file->path) { /* (a .csv name is CSV whatever format= says) */
        const char *fmt = mote_path_is_csv(file->path) ? "csv" : f ? f->text : "table";
        rc = mote_outputs_note_path(&m->formats, c, mote_call_opt_index(c, "file"), file->path,
                                    fmt, 1, err);
    }
    return rc;
}

/* Start a sampler: a sample now, then every K steps or every T of time during integrate. */
static int sampler_start(nb_model *m, nb_sampler *s, const mote_call *c, size_t cols,
                         mote_err *err)
{
    settle_units(m);
    free(s->path);
    free(s->origin);
    const mote_arg *a = mote_call_opt(c, "file"), *f = mote_call_opt(c, "format");
    s->path = a ? strdup(a->path) : NULL;
    s->origin = mote_call_origin(c);
    const mote_arg *ev = mote_call_opt(c, "every");
    s->every = ev ? (uint64_t)ev->i : 0;
    double scale;
    int rc = time_scale(m, c, &scale, err);
    if (rc)
        return rc;
    s->dt = opt_real_or(c, "dt", 0) * scale;
    s->t0 = m->nb.T;
    s->k = 0;
    s->format = !f ? FMT_TABLE : f->text[0] == 'c' ? FMT_CSV : f->text[0] == 'j' ? FMT_JSONL
                                                                                 : FMT_TABLE;
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

static int run_monitor(void *vm, const mote_call *c, mote_err *err)
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
    return rc ? rc : sampler_write(m, &m->mon, 0, err);
}

/* on|off option: 1, 0, or -1 when it is neither (dflt when not given) */
static int opt_on_off(const mote_call *c, const char *key, int dflt)
{
    const mote_arg *a = mote_call_opt(c, key);
    return !a ? dflt : strcmp(a->text, "on") == 0 ? 1 : strcmp(a->text, "off") == 0 ? 0 : -1;
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

static int check_trajectory(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int rc = check_sampler(vm, c, err);
    if (!rc)
        rc = need_bodies(vm, c, err);
    if (!rc && opt_on_off(c, "velocities", 0) < 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "velocities"), MOTE_EINVAL,
                              "trajectory: velocities must be on or off, found '%s'",
                              mote_call_opt(c, "velocities")->text);
    if (!rc && mote_call_opt(c, "bodies") && body_list(c, "bodies", NULL, m->d_bodies, NULL, err) < 0)
        return err->code;
    return rc;
}
static int run_trajectory(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    nb_sampler *s = &m->traj;
    settle_units(m);
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
    s->vel = opt_on_off(c, "velocities", 0);
    s->n0 = m->nb.n;
    int rc = sampler_start(m, s, c, 3 + (s->vel ? 6 : 3) * (size_t)s->nsel, err);
    if (rc)
        return rc;
    mote_nb_monitor mon;
    mote_nb_measure(&m->nb, &mon);
    for (int a = 0; a < 3; a++)
        m->traj.L0[a] = mon.L[a] + mon.S[a];
    rc = trajectory_sample(m, &m->nb, err);
    return rc ? rc : sampler_write(m, &m->traj, 1, err);
}

/* ---- approaches (spec 7.9, 10.4) ------------------------------------------------------------- */

static int check_approaches(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    int rc = need_bodies(vm, c, err);
    if (rc)
        return rc;
    if (opt_on_off(c, "refine", 0) < 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "refine"), MOTE_EINVAL,
                              "approaches: refine must be on or off, found '%s'",
                              mote_call_opt(c, "refine")->text);
    const mote_arg *f = mote_call_opt(c, "format");
    if (f && strcmp(f->text, "native") != 0 && strcmp(f->text, "galactica") != 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "format"), MOTE_EINVAL,
                              "approaches: format must be native or galactica (dice.dat's "
                              "columns), found '%s'", f->text);
    const long k = body_list(c, "body", NULL, m->d_bodies, NULL, err);
    if (k < 0)
        return err->code;
    return k == 1 ? MOTE_OK
                  : mote_call_fail(err, c, mote_call_opt_index(c, "body"), MOTE_EINVAL,
                                   "approaches: body= names one body (found %ld)", k);
}

static int approaches_write(nb_model *m, mote_err *err)
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

static int run_approaches(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    settle_units(m);
    uint32_t b = 0;
    if (body_list(c, "body", &m->nb, m->nb.n, &b, err) != 1)
        return err->code ? err->code : MOTE_EINVAL;
    nb_approach_free(&m->appr.a);
    nb_approach_init(&m->appr.a, b, opt_on_off(c, "refine", 0) == 1, err);
    m->appr.every = (uint64_t)mote_call_opt(c, "every")->i;
    const mote_arg *f = mote_call_opt(c, "format");
    m->appr.galactica = f && strcmp(f->text, "galactica") == 0;
    free(m->appr.path);
    free(m->appr.origin);
    m->appr.path = strdup(mote_call_opt(c, "file")->path);
    m->appr.origin = mote_call_origin(c);
    if (!m->appr.path || !m->appr.origin)
        return mote_fail(err, MOTE_ENOMEM, "approaches: out of memory");
    return approaches_write(m, err);
}

/* ---- frames (spec 7.13) ----------------------------------------------------------------------- */

static int check_frames(void *vm, const mote_call *c, mote_err *err)
{
    int rc = need_bodies(vm, c, err);
    const mote_arg *p = mote_call_opt(c, "prefix");
    if (!rc && p && !mote_ctx_dir_ok(c->ctx, p->path))
        return mote_call_fail(err, c, mote_call_opt_index(c, "prefix"), MOTE_EINVAL,
                              "frames: the directory of prefix '%s' does not exist", p->text);
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

static int frame_now(nb_model *m, mote_err *err)
{
    const size_t len = strlen(m->frames.prefix) + 32;
    char *path = malloc(len);
    if (!path)
        return mote_fail(err, MOTE_ENOMEM, "frames: out of memory");
    snprintf(path, len, "%s%06llu.png", m->frames.prefix,
             (unsigned long long)(m->frames.count + 1));
    int rc = nb_frame_png(&m->nb, &m->frames.f, path, m->nb.steps, err);
    m->frames.count += !rc;
    free(path);
    return rc;
}

static int run_frames(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    settle_units(m);
    const mote_arg *a = mote_call_opt(c, "prefix");
    free(m->frames.prefix);
    m->frames.prefix = strdup(a ? a->path : "frame_");
    if (!m->frames.prefix)
        return mote_fail(err, MOTE_ENOMEM, "frames: out of memory");
    m->frames.every = (uint64_t)mote_call_opt(c, "every")->i;
    m->frames.count = 0;
    memset(&m->frames.ctl, 0, sizeof m->frames.ctl);
    if ((a = mote_call_opt(c, "control"))) { /* the control file's graphics values */
        int rc = nb_galctl_read(a->path, 0, 0, &m->frames.ctl, err);
        if (rc)
            return rc;
        nb_frame_from_ctl(&m->frames.f, &m->frames.ctl, m->have_galhead ? m->galhead : NULL);
    } else { /* the whole system in view, seen from +z; body 1's arrow yellow, the others green */
        nb_galctl *g = &m->frames.ctl;
        g->ntrio = 1;
        g->trio[0][0] = 14;
        g->trio[0][1] = 10;
        g->trio[0][2] = 1;
        nb_frame_from_ctl(&m->frames.f, g, m->have_galhead ? m->galhead : NULL);
        double R = 0;
        for (uint32_t i = 0; i < m->nb.n; i++)
            if (m->nb.active[i])
                for (int k = 0; k < 3; k++)
                    R = fmax(R, fabs((double)m->nb.x[3 * i + (uint32_t)k]));
        nb_frame_opts *f = &m->frames.f;
        f->Xe0 = 512;
        f->Ye0 = 384;
        f->aix = f->biy = R > 0 ? 0.45 * 768 / R : 150;
        f->Rd = 0.08;
        f->amv = 600 / f->aix; /* the fastest body's arrow 60 pixels long */
        f->Kl14 = 1;
        f->np = 1;
    }
    return frame_now(m, err);
}

static int check_integrate(void *vm, const mote_call *c, mote_err *err)
{
    int given = (mote_call_opt(c, "steps") != NULL) + (mote_call_opt(c, "to") != NULL) +
                (mote_call_opt(c, "for") != NULL);
    if (given != 1)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "integrate: give exactly one of steps=N, to=T and for=D (found %d)",
                              given);
    int rc = check_time_unit(vm, c, err);
    return rc ? rc : need_bodies(vm, c, err);
}

/* Steps to the next sample of a step sampler s (at most `left`); time samplers step singly. */
static uint64_t until_sample(const nb_sampler *s, uint64_t steps, uint64_t left)
{
    if (!s->on)
        return left;
    if (s->dt > 0)
        return left < 1 ? left : 1;
    uint64_t next = (steps / s->every + 1) * s->every - steps;
    return next < left ? next : left;
}

/* After a step from Tb: a step sampler samples on its step counts and at the end time; a time
 * sampler at every t0 + k dt passed, from the Taylor step's dense output (spec 4.5) or, for the
 * Galactica scheme, at the first step end at or after it (spec 10.3). */
static int after_step(nb_model *m, nb_sampler *s, int traj, mote_real Tb, uint64_t merges,
                      mote_real t_end, mote_real *xv, mote_err *err)
{
    if (!s->on)
        return MOTE_OK;
    mote_nb *nb = &m->nb;
    if (!(s->dt > 0))
        return nb->steps % s->every == 0 || nb->T == t_end ? sample(m, traj, nb, err) : MOTE_OK;
    int rc = MOTE_OK;
    for (;;) {
        mote_real ts = s->t0 + (mote_real)(s->k + 1) * s->dt;
        if (!(ts <= nb->T) || rc)
            break;
        s->k++;
        /* (after a merge the step's polynomial no longer matches the bodies: the step end) */
        if (nb->integrator == MOTE_NB_TAYLOR && ts < nb->T && ts > Tb && nb->merges == merges) {
            mote_nb view = *nb; /* the state at ts, from the step's polynomial */
            view.x = xv;
            view.v = xv + 3 * (size_t)nb->n;
            mote_nb_taylor_dense(nb, ts - Tb, view.x, view.v);
            view.T = ts;
            rc = sample(m, traj, &view, err);
        } else {
            rc = sample(m, traj, nb, err);
            while (s->t0 + (mote_real)(s->k + 1) * s->dt <= nb->T) /* one sample per step end */
                s->k++;
        }
    }
    return rc;
}

static int write_galactica(nb_model *m, const char *path, int info_line, mote_err *err);

/* The snapshot of `snapshot every=K`: PREFIX followed by the step count and .snap */
static int periodic_snapshot(nb_model *m, mote_err *err)
{
    size_t len = strlen(m->snap.prefix) + 32;
    char *path = malloc(len);
    if (!path)
        return mote_fail(err, MOTE_ENOMEM, "snapshot: out of memory");
    snprintf(path, len, "%s%010llu.%s", m->snap.prefix, (unsigned long long)m->nb.steps,
             m->snap.galactica ? "dat" : "snap");
    int rc = m->snap.galactica ? write_galactica(m, path, 1, err)
                               : nb_snapshot_write(&m->nb, path, m->snap.origin, err);
    free(path);
    return rc;
}

static int run_integrate(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    settle_units(m);
    m->nb.threads = c->ctx->threads;
    const mote_arg *a = mote_call_opt(c, "steps");
    uint64_t steps = a ? (uint64_t)a->i : UINT64_MAX, done = 0;
    const mote_real t0 = m->nb.T;
    mote_real t_end = INFINITY;
    double scale;
    int rc = time_scale(m, c, &scale, err);
    if (rc)
        return rc;
    if ((a = mote_call_opt(c, "to")))
        t_end = mote_real_parse(a->text, NULL) * scale;
    else if ((a = mote_call_opt(c, "for")))
        t_end = m->nb.T + mote_real_parse(a->text, NULL) * scale;
    if (!(t_end > m->nb.T))
        return mote_fail(err, MOTE_EINVAL, "integrate: %s=%s ends at or before the current time "
                         "%.17g (%s)", mote_call_opt(c, "to") ? "to" : "for", a ? a->text : "",
                         (double)(m->nb.T / scale),
                         t_end == m->nb.T ? "there is nothing to do" : "integration runs forward");
    if (m->nb.adaptive && m->nb.hmax > 0 && m->nb.hmin > m->nb.hmax)
        return mote_fail(err, MOTE_EINVAL, "integrate: hmin (%g) is greater than hmax (%g)",
                         (double)m->nb.hmin, (double)m->nb.hmax);
    const uint64_t forced = m->nb.hmin_forced;
    mote_real *xv = NULL;
    if ((m->mon.on && m->mon.dt > 0) || (m->traj.on && m->traj.dt > 0)) {
        xv = malloc(6 * (size_t)(m->nb.n ? m->nb.n : 1) * sizeof *xv);
        if (!xv)
            return mote_fail(err, MOTE_ENOMEM, "integrate: out of memory");
    }
    mote_progress prog;
    mote_progress_begin(&prog, c->ctx, "integrate");
    const uint64_t warned = m->nb.approach_warnings;
    while (done < steps && !rc && m->nb.T < t_end) {
        uint64_t chunk = until_sample(&m->mon, m->nb.steps, steps - done);
        chunk = until_sample(&m->traj, m->nb.steps, chunk);
        if (m->appr.every) /* every step end is looked at */
            chunk = 1;
        const uint64_t every[3] = {m->ckpt.path ? m->ckpt.every : 0, m->snap.every,
                                   m->frames.every};
        for (int k = 0; k < 3; k++)
            if (every[k]) {
                uint64_t next = (m->nb.steps / every[k] + 1) * every[k] - m->nb.steps;
                chunk = next < chunk ? next : chunk;
            }
        if (chunk > 1000)
            chunk = 1000;
        uint64_t before = m->nb.steps;
        const mote_real Tb = m->nb.T;
        const uint64_t merges = m->nb.merges;
        if (m->appr.every)
            rc = nb_approach_before(&m->appr.a, &m->nb, err);
        if (!rc)
            rc = mote_nb_integrate(&m->nb, chunk, t_end, err);
        done += m->nb.steps - before;
        if (!rc && m->appr.every && m->nb.steps != before) {
            nb_approach_after(&m->appr.a, &m->nb, Tb, m->nb.merges != merges);
            if (m->nb.steps % m->appr.every == 0)
                rc = nb_approach_close(&m->appr.a, m->nb.T, err);
        }
        if (!rc && m->nb.steps == before) /* no step could be taken: the end is reached */
            break;
        if (!rc)
            rc = after_step(m, &m->mon, 0, Tb, merges, t_end, xv, err);
        if (!rc)
            rc = after_step(m, &m->traj, 1, Tb, merges, t_end, xv, err);
        if (!rc && m->ckpt.path && m->nb.steps % m->ckpt.every == 0)
            rc = nb_state_save(&m->nb, m->ckpt.path, err);
        if (!rc && m->snap.every && m->nb.steps % m->snap.every == 0 && m->nb.steps != before)
            rc = periodic_snapshot(m, err);
        if (!rc && m->frames.every && m->nb.steps % m->frames.every == 0 &&
            m->nb.steps != before)
            rc = frame_now(m, err);
        mote_progress_update(&prog, t_end < INFINITY ? (double)((m->nb.T - t0) / (t_end - t0))
                                                     : (double)done / (double)steps);
    }
    mote_progress_end(&prog);
    free(xv);
    if (!rc && m->ckpt.path)
        rc = nb_state_save(&m->nb, m->ckpt.path, err);
    if (m->nb.hmin_forced > forced && m->log)
        fprintf(m->log, "integrate: warning: %llu adaptive step%s held at hmin = %g, longer than "
                "tol= allows (the accuracy is not ensured; watch dE): lower hmin=\n",
                (unsigned long long)(m->nb.hmin_forced - forced),
                m->nb.hmin_forced - forced > 1 ? "s" : "", (double)m->nb.hmin);
    if (m->nb.approach_warnings > warned && m->log)
        fprintf(m->log,
                "integrate: warning: %llu merge%s overlapped by more than 10%% of the radii after "
                "a step at the shortest length (merge accuracy not ensured; largest overlap "
                "%.3g): lower hmin= or bt= of 'merge'\n",
                (unsigned long long)(m->nb.approach_warnings - warned),
                m->nb.approach_warnings - warned > 1 ? "s" : "", (double)m->nb.max_overlap);
    if (!rc && m->appr.every && m->nb.steps % m->appr.every != 0 && m->appr.a.best >= 0)
        rc = nb_approach_close(&m->appr.a, m->nb.T, err); /* the last, partial interval */
    if (m->appr.every) {
        mote_err werr = {0};
        int wrc = approaches_write(m, rc ? &werr : err);
        rc = rc ? rc : wrc;
    }
    /* the samples so far, even after a failure */
    nb_sampler *smp[2] = {&m->mon, &m->traj};
    for (int k = 0; k < 2; k++) {
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
    settle_units(m);
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
static int check_load(void *vm, const mote_call *c, mote_err *err)
{
    return check_state_input(vm, c, c->args[0].path, 0, err);
}
static int run_load(void *vm, const mote_call *c, mote_err *err)
{
    return load_state(vm, c, c->args[0].path, err);
}
static int check_restart(void *vm, const mote_call *c, mote_err *err)
{
    return check_state_input(vm, c, mote_call_opt(c, "file")->path,
                             mote_call_opt_index(c, "file"), err);
}
static int run_restart(void *vm, const mote_call *c, mote_err *err)
{
    return load_state(vm, c, mote_call_opt(c, "file")->path, err);
}

static int check_checkpoint(void *vm, const mote_call *c, mote_err *err)
{
    return need_bodies(vm, c, err);
}
static int run_checkpoint(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    settle_units(m);
    free(m->ckpt.path);
    m->ckpt.path = strdup(mote_call_opt(c, "file")->path);
    if (!m->ckpt.path)
        return mote_fail(err, MOTE_ENOMEM, "checkpoint: out of memory");
    m->ckpt.every = (uint64_t)mote_call_opt(c, "every")->i;
    return nb_state_save(&m->nb, m->ckpt.path, err);
}

/* ---- snapshots (spec 10.2) ------------------------------------------------------------------ */

/* write/read KIND: snapshot (spec 10.2) or galactica (Galactica's files, spec 7.5, 7.6) */
static int check_kind(const mote_call *c, mote_err *err)
{
    const int gal = strcmp(c->args[0].text, "galactica") == 0;
    if (!gal && strcmp(c->args[0].text, "snapshot") != 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL,
                              "%s: expected snapshot (the native snapshot of spec 10.2) or "
                              "galactica (Galactica's body file), found '%s'", c->name,
                              c->args[0].text);
    const char *gal_only = mote_call_opt(c, "n") ? "n" : mote_call_opt(c, "info_line") ? "info_line" : NULL;
    if (!gal && gal_only)
        return mote_call_fail(err, c, mote_call_opt_index(c, gal_only), MOTE_EINVAL,
                              "%s snapshot: %s= is for galactica files", c->name, gal_only);
    const mote_arg *il = mote_call_opt(c, "info_line");
    if (il && strcmp(il->text, "on") && strcmp(il->text, "off"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "info_line"), MOTE_EINVAL,
                              "%s: info_line= is on or off, found '%s'", c->name, il->text);
    if (gal && mote_call_opt(c, "format"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "format"), MOTE_EINVAL,
                              "%s galactica: format= is for snapshots", c->name);
    const mote_arg *f = mote_call_opt(c, "format");
    if (f && strcmp(f->text, "native") != 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "format"), MOTE_EINVAL,
                              "%s: format must be native, found '%s' (Galactica's layout is not "
                              "in this version)", c->name, f->text);
    return MOTE_OK;
}

static int check_write(void *vm, const mote_call *c, mote_err *err)
{
    int rc = check_kind(c, err);
    return rc ? rc : need_bodies(vm, c, err);
}
/* The system as a Galactica file (spec 7.5): the header computed, its area fields and Em
 * carried from the file read or the generator. */
static int write_galactica(nb_model *m, const char *path, int info_line, mote_err *err)
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

static int run_write(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    settle_units(m);
    char *origin = mote_call_origin(c);
    if (!origin)
        return mote_fail(err, MOTE_ENOMEM, "write: out of memory");
    const char *path = mote_call_opt(c, "file")->path;
    int rc;
    if (strcmp(c->args[0].text, "galactica") == 0) {
        const mote_arg *il = mote_call_opt(c, "info_line");
        rc = write_galactica(m, path, !il || strcmp(il->text, "off") != 0, err);
    } else {
        rc = nb_snapshot_write(&m->nb, path, origin, err);
    }
    free(origin);
    if (!rc && m->log)
        fprintf(m->log, "write %s: wrote %s (%u bodies at T = %.17g)\n", c->args[0].text, path,
                m->nb.n, (double)m->nb.T);
    return rc;
}

static int check_read(void *vm, const mote_call *c, mote_err *err)
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
        if (strcmp(c->args[0].text, "galactica") == 0) {
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
static int run_read(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const char *path = mote_call_opt(c, "file")->path;
    const int gal = strcmp(c->args[0].text, "galactica") == 0;
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

static int check_snapshot(void *vm, const mote_call *c, mote_err *err)
{
    const mote_arg *f = mote_call_opt(c, "format");
    if (f && strcmp(f->text, "native") != 0 && strcmp(f->text, "galactica") != 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "format"), MOTE_EINVAL,
                              "snapshot: format must be native or galactica, found '%s'",
                              f->text);
    const mote_arg *p = mote_call_opt(c, "prefix");
    if (p && !mote_ctx_dir_ok(c->ctx, p->path))
        return mote_call_fail(err, c, mote_call_opt_index(c, "prefix"), MOTE_EINVAL,
                              "snapshot: the directory of prefix '%s' does not exist", p->text);
    return need_bodies(vm, c, err);
}
static int run_snapshot(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const mote_arg *p = mote_call_opt(c, "prefix");
    free(m->snap.prefix);
    free(m->snap.origin);
    m->snap.prefix = strdup(p ? p->path : "snapshot_");
    m->snap.origin = mote_call_origin(c);
    if (!m->snap.prefix || !m->snap.origin)
        return mote_fail(err, MOTE_ENOMEM, "snapshot: out of memory");
    m->snap.every = (uint64_t)mote_call_opt(c, "every")->i;
    const mote_arg *f = mote_call_opt(c, "format");
    m->snap.galactica = f && strcmp(f->text, "galactica") == 0;
    return MOTE_OK;
}

/* `steps_between jd1= jd2= dt= [fresh=on]` (spec 9.5) */
static int check_steps_between(void *vm, const mote_call *c, mote_err *err)
{
    (void)vm;
    const mote_arg *fr = mote_call_opt(c, "fresh");
    if (fr && strcmp(fr->text, "on") && strcmp(fr->text, "off"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "fresh"), MOTE_EINVAL,
                              "steps_between: fresh= is on or off, found '%s'", fr->text);
    if (!(mote_call_opt(c, "jd2")->r > mote_call_opt(c, "jd1")->r))
        return mote_call_fail(err, c, mote_call_opt_index(c, "jd2"), MOTE_EINVAL,
                              "steps_between: jd2 must come after jd1");
    return MOTE_OK;
}
static int run_steps_between(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const mote_arg *fr = mote_call_opt(c, "fresh");
    const int fresh = fr && strcmp(fr->text, "on") == 0;
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

static int job_coulomb(const nb_model *m, const mote_call *c)
{
    const mote_arg *a = mote_call_opt(c, "interaction");
    return a ? strcmp(a->text, "coulomb") == 0 : m->nb.kind == MOTE_NB_COULOMB;
}

static int check_run(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    if (strcmp(c->args[0].text, "galactica") != 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "run: expected 'galactica' (a Galactica "
                              "job), found '%s'", c->args[0].text);
    const mote_arg *a = mote_call_opt(c, "interaction");
    if (a && strcmp(a->text, "gravity") != 0 && strcmp(a->text, "coulomb") != 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "interaction"), MOTE_EINVAL,
                              "run galactica: interaction= gravity or coulomb, found '%s'",
                              a->text);
    static const char *const onoff[] = {"frames", "force", "lenient"};
    for (int k = 0; k < 3; k++)
        if (opt_on_off(c, onoff[k], 0) < 0)
            return mote_call_fail(err, c, mote_call_opt_index(c, onoff[k]), MOTE_EINVAL,
                                  "run galactica: %s= on or off", onoff[k]);
    a = mote_call_opt(c, "trio_layout");
    if (a && strcmp(a->text, "packed") != 0 && strcmp(a->text, "prose") != 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "trio_layout"), MOTE_EINVAL,
                              "run galactica: trio_layout= prose or packed, found '%s'", a->text);
    a = mote_call_opt(c, "control");
    mote_nb_job o;
    memset(&o, 0, sizeof o);
    o.control = a ? a->path : "galacf26.dat";
    o.coulomb = job_coulomb(m, c);
    o.lenient = opt_on_off(c, "lenient", 0) == 1;
    o.packed = (a = mote_call_opt(c, "trio_layout")) && strcmp(a->text, "packed") == 0;
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

static int run_run(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const mote_arg *a = mote_call_opt(c, "control");
    mote_nb_job o;
    memset(&o, 0, sizeof o);
    o.control = a ? a->path : "galacf26.dat";
    o.coulomb = job_coulomb(m, c);
    o.frames = opt_on_off(c, "frames", 0) == 1;
    o.force = opt_on_off(c, "force", 0) == 1;
    o.lenient = opt_on_off(c, "lenient", 0) == 1;
    o.packed = (a = mote_call_opt(c, "trio_layout")) && strcmp(a->text, "packed") == 0;
    o.step_tol = (a = mote_call_opt(c, "step_tol")) ? a->r : 0;
    o.max_files = (a = mote_call_opt(c, "max_files")) ? (long)a->i : 0;
    o.threads = c->ctx->threads;
    o.out = m->log;
    o.final = &m->nb;
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
    settle_units(m);
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

/* ---- the table ---------------------------------------------------------------------------------- */

static const char HELP_BODY[] =
    "    body mass=M [x= y= z= vx= vy= vz= radius=|density= charge= spin=SX,SY,SZ]\n"
    "         [name=NAME]\n"
    "\n"
    "Add a body, in dimensionless units (G = 1 or the Coulomb constant 1; spec\n"
    "3.5): mass > 0, position, velocity, radius >= 0, and for `model nbody coulomb`\n"
    "its charge in elementary charges. density=RHO > 0 gives the radius of a\n"
    "sphere of that mass, (3 M / (4 pi RHO))^(1/3) (kg/m^3 with SI input).\n"
    "spin= is its spin angular momentum (kg m^2/s with SI input), counted in S and\n"
    "L + S like the spins merges make (spec 5). Unset values are 0. Bad values (NaN,\n"
    "infinite, a mass <= 0) stop the run at this line; two bodies at one point are\n"
    "refused when the integrator starts.\n"
    "name=NAME names the body (a letter first, then letters, digits and _ . + -; at\n"
    "most 23 characters; unique): `trajectory bodies=` and `plot relative_to=` take\n"
    "a name or a body number (1 = the first body), and files show the names.\n"
    "`generate solar_system` names its bodies as the data file does.\n";

static const char HELP_UNITS[] =
    "    units solar|atomic|dimensionless [input=si|dimensionless]\n"
    "    units [mass=KG|auto] length=M|time=S [input=si|dimensionless]\n"
    "\n"
    "The physical scales of the run (spec 3.5): the mass unit M, the length unit\n"
    "Am, kv = sqrt(Am/(G M)) (Coulomb: sqrt(eps M Am / e^2)) and kt = 1/(Am kv),\n"
    "so that G = 1 (or the Coulomb constant 1) inside. With time=S the time unit\n"
    "is S seconds and Am follows from eq. 8, refined so that Am = 1/(kt kv)\n"
    "exactly, as Galactica's generators do; with length=M, Am = M.\n"
    "`solar`: the time unit is the sidereal century (100 x 365.25636042 days);\n"
    "`atomic` (Coulomb only): 1e-15 s; `dimensionless`: no scales (the default).\n"
    "input=si (the default with scales) reads the values of later `body`\n"
    "commands in kg, m, m/s (radius in m, charge in elementary charges) and\n"
    "converts them; input=dimensionless reads them as they are. mass=auto (the\n"
    "default with input=si) takes the total mass of the bodies, fixed when the\n"
    "first command after them needs the scales; `units solar` with dimensionless\n"
    "input takes the Solar-System mass 1.991787350282e30 kg. Scales are written\n"
    "in every output file's header and let `integrate` and `monitor` take times\n"
    "with unit=s|day|year|century (year: Julian, 365.25 days). Comes before the\n"
    "bodies; the generators set their own scales.\n";

static const char HELP_CONSTANT[] =
    "    constant [G=X] [e=X | e2=X] [permittivity=X]\n"
    "\n"
    "Replace a physical constant of the unit conversions and generators (spec\n"
    "3.6): G in m^3 kg^-1 s^-2 (default the seed document's 6.67259e-11), the\n"
    "elementary charge e in CGSE (default 4.80298e-10) or e2 = e^2 in\n"
    "kg m^3 s^-2 (SI, with the 1e-9 of spec 3.2), the relative permittivity\n"
    "(default 1). For example `constant G=6.6743e-11` for CODATA 2018. Comes\n"
    "before `units`, the generators and the bodies; output headers record the\n"
    "constants in use.\n";

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
    "Hairer, Lubich & Wanner, data/solar_system_j2000.dat the Sun, planets and\n"
    "Moon at J2000 from JPL Horizons), all or those listed in `bodies=`, in the file's\n"
    "order; merge_inner=on adds Mercury, Venus, Earth, Moon and Mars to the Sun.\n"
    "Masses relative to the total, time unit the sidereal century, Am from eq. 8\n"
    "refined, barycentric.\n"
    "\n"
    "`generate area` is Galactica's area of matter (its control file's Kl1 = 0): a box\n"
    "1 x b x c (defaults 1, 1) with its corner at origin=X,Y,Z, mu= intervals along x (2),\n"
    "round(b mu) + 1 and round(c mu) + 1 nodes along y and z, a body of equal mass at each\n"
    "node, radii from rho_body= (5000 kg/m^3; 0: points), the time unit from rho_area= (1e-7\n"
    "kg/m^3): kt = sqrt(G rho_area b c (1 + sep_density / nodes)); omega= turns the grid about\n"
    "the axis through axis=X01,Y01 (0.5,0.5) parallel to z; sep_density= (0: none) adds a\n"
    "separate body at sep_pos= with sep_vel=, only when no node is closer than 1/mu to it\n"
    "node. The grid's centre of mass is taken out before the separate body's mass enters.\n"
    "length= is Am (1 AU), used only to convert back to SI; dt= the nominal step (5e-4).\n"
    "\n"
    "`generate plummer n=N [seed=S]` is a Plummer sphere of N equal masses (total mass 1,\n"
    "Plummer radius 1, G = 1 units; Aarseth, Henon & Wielen 1974), barycentric: the test\n"
    "problem of the tree forces (forces tree).\n";

static const char HELP_INTEGRATOR[] =
    "    integrator galactica [dt=H] [order=K] [first_step=F] [tol=E]\n"
    "                         [step=fixed|adaptive|doubling] [dt_max=D]\n"
    "    integrator taylor [dt=H] [order=P|auto] [tol=E] [memory=store|recompute|auto]\n"
    "                      [norm=nearest|global]\n"
    "\n"
    "`galactica`: Galactica's Taylor scheme (spec 4.2): two passes over all\n"
    "ordered pairs give the acceleration, jerk and the fourth and fifth\n"
    "derivatives; the sixth is the difference of fifth derivatives over the\n"
    "previous step. order=K (2 ... 6, default 6) keeps the terms up to x^(K) (spec\n"
    "4.3). A start without a previous fifth derivative takes a first step of F dt\n"
    "(default 0.001). With tol=E the step is adaptive (Galactica's step\n"
    "correction, Kl4 = 2/3; spec 4.5): after the first step of F dt, the step at\n"
    "which x^[5] = d5/120 and x^[6] = p/720 of every body stay below E times the\n"
    "distance to its nearest neighbour, times safety=S, at most twice the\n"
    "previous step, within [hmin, hmax] (order 6 only); step=adaptive says the\n"
    "same without tol= (then E = 1e-16), and dt_max=D bounds it like hmax.\n"
    "step=doubling dt_max=D is Galactica's literal rule, for experiments (spec\n"
    "7.4): D_n = |dMz_n - dMz_(n-1)| is averaged over blocks of 5 steps, and when\n"
    "a block's mean exceeds 1.1 times the previous block's the nominal step\n"
    "doubles, never above D; the block after a change, and a block with a step\n"
    "shortened by a close approach, are not compared. step=fixed (the default\n"
    "without tol=) keeps dt.\n"
    "\n"
    "`taylor`: the general Taylor integrator (spec 4.4): every coefficient up to\n"
    "order P (2 ... 60, default 20) from exact recurrences (automatic\n"
    "differentiation), ceil((P-1)/2) passes over the pairs per step. With dt=H the\n"
    "step is fixed; without it the step is adaptive (spec 4.5): for each body the\n"
    "step at which its two highest Taylor terms stay below tol=E (default 1e-16;\n"
    "1e-19 and 1e-33 in the long-double and quad builds)\n"
    "times the distance to its nearest neighbour, the smallest of them times\n"
    "safety=S (default 1), at most twice the previous step, within [hmin, hmax].\n"
    "norm=global takes instead one scale for all bodies (Jorba and Zou): h from\n"
    "the largest |x^[j]| over every coordinate, j = P-1 and P, against\n"
    "max(E, E |x|_inf); the default norm=nearest lets each body's nearest\n"
    "neighbour set its own scale (satellites and close pairs control their own\n"
    "accuracy, which one global norm does not).\n"
    "order=auto takes P = ceil(1 - ln(E)/2) (E = 1e-16: P = 20).\n"
    "memory=store keeps the pairs' histories between passes (2 (P-1) N^2 reals),\n"
    "and each pair solved once; recompute keeps memory proportional to N (each\n"
    "body solves all its pairs, twice the pair work); auto (default) stores up to\n"
    "1 GiB. Both give the same bits.\n";

static const char HELP_FORCES[] =
    "    forces direct\n"
    "    forces tree [theta=0.5]\n"
    "\n"
    "`direct` (the default) sums the forces over every pair of bodies (spec 6.1), in a fixed\n"
    "order for each target, so that results do not depend on the number of threads.\n"
    "\n"
    "`tree` uses a Barnes-Hut octree (spec 6.2) for large N: built each step from the\n"
    "positions at its start (leaves of at most 8 bodies); a cell is taken as one pseudo-body\n"
    "when its side over its distance from the target is below theta, and its trajectory\n"
    "coefficients are the weighted means of its bodies', so both integrators work at any\n"
    "order. It is approximate: every output header says `# forces = tree` with theta, and\n"
    "momentum is no longer conserved exactly. Accuracy on a Plummer sphere (N = 30 000): a\n"
    "median relative acceleration error of about 1e-3 at theta 0.5 and 2e-4 at 0.3; theta 0\n"
    "opens every cell and gives the direct sums to rounding (docs/nbody.md). Gravity, or\n"
    "charges of one sign only. The results do not depend on the number of threads.\n";

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
    "    monitor every=K [file=FILE [format=table|csv|jsonl]]\n"
    "    monitor dt=T [unit=s|day|year|century] [file=FILE [format=...]]\n"
    "\n"
    "Record the conserved quantities (spec 3.7, 10.1) now and then every K steps\n"
    "of later `integrate` commands (and at an end time given by to= or for=), or\n"
    "at the times T0 + k T (T0 now): the adaptive Taylor integrator samples these\n"
    "inside its steps by dense output, without shortening them (in a step in\n"
    "which bodies merged, at its end); the Galactica scheme samples at the first\n"
    "step end at or after each. Columns: step T h dT\n"
    "N_active E_kin U E_tot dE Px Py Pz Lx Ly Lz Sx Sy Sz dMz dL Xcm Ycm Zcm\n"
    "Vxcm Vycm Vzcm m_max v_max E_kin_max T_E_kin_max E_heat E_spin merges cpu_s\n"
    "wall_s E_corr, where dE = (E_corr - E0)/|E0| (E_corr: E_tot less the energy\n"
    "changes of merges), dMz the aggregated z moment's relative change and dL =\n"
    "|L + S - (L + S)0| / |(L + S)0| since the start of the run, h the last step\n"
    "and dT the nominal one, E_kin_max the largest kinetic energy of a body over\n"
    "the samples and its time, cpu_s and wall_s the processor and wall seconds\n"
    "since the monitor started (the only columns that differ between identical\n"
    "runs). Without file= each sample prints a line on the terminal (step T h\n"
    "N_active E_tot dE dMz dL merges). With file= every column goes to FILE,\n"
    "rewritten atomically at the end of every integrate: `table` (default) is a\n"
    "mote data file (# header lines: the model, N, integrator, units and\n"
    "constants; `plot` draws its drifts), `csv` the same header then a row of\n"
    "column names and comma-separated rows, `jsonl` one JSON object per sample.\n"
    "Numbers are written to 17 significant digits.\n";

static const char HELP_TRAJECTORY[] =
    "    trajectory every=K file=FILE [format=table|csv|jsonl] [bodies=LIST]\n"
    "               [velocities=on|off]\n"
    "    trajectory dt=T [unit=U] file=FILE [format=...] [bodies=...] [velocities=...]\n"
    "\n"
    "Record T, E_kin, E_tot and the position of every body now and then every K\n"
    "steps or at the times T0 + k T (dense output of the Taylor integrator, as\n"
    "for `monitor`) into FILE (spec 10.3), rewritten atomically at the end of\n"
    "every integrate. Its header keeps the total angular momentum at the start,\n"
    "so `plot FILE orbits.png` draws the orbits in the invariable plane.\n"
    "bodies=LIST records only the bodies listed (names or numbers, 1 = the first\n"
    "body, separated by commas, in the order given); velocities=on adds vx vy vz\n"
    "after x y z of each. Columns are named x_NAME y_NAME z_NAME for a named body\n"
    "and x3 y3 z3 for an unnamed body 3.\n";

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

static const char HELP_CHECKPOINT[] =
    "    checkpoint file=FILE every=K\n"
    "\n"
    "Write the exact state (as `save` does) into FILE now, every K steps of later\n"
    "`integrate` commands and at the end of each, each time atomically, so that a\n"
    "run killed at any moment leaves the last complete checkpoint (spec 10.2).\n"
    "`restart file=FILE` in a new script continues bit for bit: n steps,\n"
    "checkpoint, restart, n steps give the same numbers as 2n steps in one run.\n";

static const char HELP_RESTART[] =
    "    restart file=FILE\n"
    "\n"
    "Continue from a checkpoint (or any state written by `save`); the same as\n"
    "`load FILE`. The step count, the time, the scales and the monitor references\n"
    "(E0, the initial moments) come from the file, so drifts stay relative to the\n"
    "original start.\n";

static const char HELP_CHECK[] =
    "    check ring\n"
    "\n"
    "Print the deviation from the exact ring solution (spec 9.1, 9.2): the largest\n"
    "|x - x_exact| / |x_exact| over the ring bodies, the largest distance from the\n"
    "orbit plane (in units of a), and the energy and moment drifts.\n";

static const char HELP_WRITE[] =
    "    write snapshot file=FILE [format=native]\n"
    "\n"
    "Write the state as a snapshot (spec 10.2): a data file with the run header\n"
    "(interaction, N, integrator, precision, scales) and the fields a\n"
    "Galactica-scheme continuation needs as `# KEY = VALUE` lines (T, h_prev the\n"
    "last step, first_step, E_corr0 and Mza1 the references of dE and dMz, Ett\n"
    "the heat of merges, Lsls their count, steps), then one row per body:\n"
    "    id name active mass charge x y z vx vy vz radius sx sy sz Et d5x d5y d5z\n"
    "(name - when unnamed; d5 the fifth derivative at the last step's start),\n"
    "every number with the digits that read back to the same value. Written\n"
    "atomically. Unlike `save`, it leaves out the compensation terms of\n"
    "compensated summation, so a run continued from it agrees with the\n"
    "uninterrupted run to rounding, and bit for bit with `compensated off`.\n"
    "\n"
    "    write galactica file=FILE [info_line=on|off]\n"
    "\n"
    "Write Galactica's body file (spec 7.5; Coulomb 7.6): line 1 the header\n"
    "numbers 1-15 (T0 omm Um dTp P(3) AM(3) Sps(3) E Em), line 2 the rest (Ett dT\n"
    "i2b j2b k2b A B C Mu, Coulomb also eps_d), then one line per body (om x y z u\n"
    "v w dUp(3) Sp(3) Ra Et, Coulomb also Qo) and the info line (date, k2, M_Ss,\n"
    "Am, k_v; info_line=off leaves it out). The header is computed from the state\n"
    "(Em and the area fields carried over from the last Galactica file read);\n"
    "numbers in %.16E form, which read back to the same double.\n";

static const char HELP_READ[] =
    "    read snapshot file=FILE\n"
    "\n"
    "Replace the bodies by those of a snapshot (written by `write snapshot`,\n"
    "`snapshot`, or by hand) and restore the time, the step history (h_prev and\n"
    "d5: the Galactica scheme continues without a restart step), the references\n"
    "of dE and dMz, the merge counters, the integrator and its step, and the\n"
    "scales. Only `# N = COUNT` and the body rows are required: without h_prev\n"
    "the next step is a restart step; without E_corr0 and Mza1 the references\n"
    "are taken when the run starts; settings the file does not give stay as the\n"
    "script set them. A file that exists before the run is read whole during\n"
    "validation, so a malformed one stops the script before anything runs.\n"
    "\n"
    "    read galactica file=FILE [n=K2]\n"
    "\n"
    "Replace the bodies by those of Galactica's body file (spec 7.5; Coulomb 7.6,\n"
    "with `model nbody coulomb`): a stream of numbers in Fortran's list-directed\n"
    "form (blanks, commas and line ends separate; exponents with E, D or only a\n"
    "sign, 1.0-100; r*value repeats; the line layout does not matter): 24 header\n"
    "numbers and 15 per body (Coulomb 25 and 16), and an optional info line of 5\n"
    "(or padded to a body row) whose M_Ss, Am and k_v become the scales when none\n"
    "are set. n= reads exactly that many bodies, as Galactica does with k2;\n"
    "without it the count follows from the numbers. T0, dTp (the Galactica scheme\n"
    "continues without a restart step when it is > 0), dT, the fifth derivatives,\n"
    "spins, radii and heats are kept. A count that fits no layout, a token that\n"
    "is not a number or a mass outside 0 ... 1 is an error naming the file (and\n"
    "line), before anything runs.\n";

static const char HELP_STEPS_BETWEEN[] =
    "    steps_between jd1=JD1 jd2=JD2 dt=DT [fresh=on|off]\n"
    "\n"
    "The steps of a run from Julian date JD1 to JD2 with nominal step DT (spec\n"
    "9.5): DeltaT = (JD2 - JD1) in the run's time unit (the sidereal century,\n"
    "36525.636042 days, unless the scales say otherwise), Ltk = round(DeltaT / DT),\n"
    "and the corrected step that lands exactly: DeltaT / Ltk for a continuation, or\n"
    "DeltaT / (Ltk - 1 + first_step) for a fresh start whose first step is\n"
    "first_step (0.001) of the others. Prints them and T_end - T_target, the\n"
    "steps summed as the integrator sums them.\n";

static const char HELP_SNAPSHOT[] =
    "    snapshot every=K [prefix=P] [format=native|galactica]\n"
    "\n"
    "During later `integrate` commands, write a snapshot (see `write`) every K\n"
    "steps, at the step counts that are multiples of K, to P followed by the step\n"
    "count in ten digits and .snap (default P: snapshot_, so\n"
    "snapshot_0000001000.snap). P may name a directory: prefix=snaps/ring_.\n"
    "format=galactica writes Galactica's result-file layout instead (spec 7.5, with the\n"
    "info line), named P, the step count and .dat.\n";

static const char HELP_APPROACHES[] =
    "From the next integrate on, looks at the distance from body B (a name or a number) to\n"
    "every other active body after each step, and writes one row per K steps to FILE (and a\n"
    "last one for a partial interval at the end of integrate): T_min body distance\n"
    "relative_speed, the closest approach in the interval (body 0 when B had no partner).\n"
    "Sampled at step ends by default; refine=on also finds the true minimum inside a step,\n"
    "where the relative radial velocity changes sign, from the step's own polynomial (the\n"
    "Taylor integrator's coefficients, or the Galactica scheme's derivatives at the step's\n"
    "start), to the last bit of the step. format=galactica writes dice.dat's columns (time,\n"
    "body, distance). Every step end is examined, so integrate takes one step at a time.\n";

static const char HELP_FRAMES[] =
    "Writes a picture now and every K steps of integrate: PREFIX000001.png, ... (1024 x 768,\n"
    "black), Galactica's screen (spec 7.13): every body a white disc of radius\n"
    "max(1, 100 Rd (m/m_max)^(1/3)) pixels with its velocity arrow, 0.1 aix amv |v|/v_max long.\n"
    "control= takes the graphics values of a Galactica control file: the view turned by al\n"
    "about x and bet about y, the origin (Xe0, Ye0) and scales aix, biy in pixels, the arrows'\n"
    "colours ipp, jpp (the VGA palette), the frame of body kpp(1) (Kl10 = 1), one layer of an\n"
    "area (Ke), zooming out when a body would leave (Kl14 = 1). Without it the whole system is\n"
    "in view from +z, body 1's arrow yellow and the others green, zooming out as needed.\n"
    "ffmpeg -i PREFIX%06d.png film.mp4 makes a film. (The spec's `plot frames`.)\n";

static const char HELP_RUN[] =
    "Runs the Galactica job whose control file is `control=` (default galacf26.dat; the job's\n"
    "files are in its folder), as `mote galactica` does from the command line: the bodies come\n"
    "from the area (Kl1 = 0), garez28.dat (1), the file FIMA4 (2), or with checkpoints (3, 4),\n"
    "and the job writes Galactica's files under Galactica's names: garez28.dat at the end\n"
    "(Coulomb: garek29.dat), the result files 1, 2, ... every Kl3 steps (Kl7 = 1), the\n"
    "trajectory files 1t, 2t, ... and traekt.prn (Kl12 = 1), dice.dat (Nbd > 0), the checkpoint\n"
    "galgon4 (galgok2), the 19-quantity monitor, and with frames=on PNG pictures. Errors are\n"
    "also appended to ErrGlctca. After the run the system holds the final bodies.\n"
    "`interaction=` (default: the model's) selects the Coulomb module; `step_tol=` the\n"
    "tolerance of Kl4 = 2, 3; `lenient=on` takes each control line's last token;\n"
    "`trio_layout=packed` reads the trios at lines 51-53, 54-56, ...; the job refuses to start\n"
    "above `max_files=` (10000) files unless `force=on`. See docs/galactica.md.\n";

static const char HELP_PLOT[] =
    "    plot TRAJECTORY PNG [bodies=LIST] [relative_to=BODY] [plane=P] [size=PX]\n"
    "    plot MONITOR PNG\n"
    "\n"
    "A trajectory file (`trajectory`) as the orbits of its bodies, projected on\n"
    "the plane P: `invariable` (the default: perpendicular to the total angular\n"
    "momentum L + S when the recording started, so a tilted ring shows its true\n"
    "ellipses), `xy`, `xz` or `yz`. Equal scales on both axes, in AU (m when the\n"
    "picture spans less than 0.001 AU) when the run has physical scales, else in\n"
    "dimensionless length; one colour and legend entry per body up to 8 bodies;\n"
    "the first body drawn with its points. bodies=LIST draws only those bodies\n"
    "(names or body numbers, separated by commas); relative_to=BODY draws the\n"
    "others relative to that body (a geocentric view: relative_to=Earth); size=PX\n"
    "is the picture's side in pixels (64 to 8192, default 1024).\n"
    "A monitor file (`monitor`) as the relative drifts of the energy and of the\n"
    "aggregated z moment against time (in years, days or seconds, whichever reads\n"
    "best, when the run has physical scales: `units` or a generator that sets them;\n"
    "else dimensionless); it takes no options.\n";

static int model_plot(void *vm, const char *data_path, const char *png_path, const mote_call *c,
                      mote_err *err)
{
    return nb_plot_file(data_path, png_path, c, err);
}
static int model_plot_check(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const char *fmt = c->args[0].path ? mote_outputs_find(&m->formats, c->args[0].path) : NULL;
    if (fmt && strcmp(fmt, "table") != 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL,
                              "plot: '%s' is written earlier in this script in format %s; plot "
                              "reads the table format (format=table, the default, under a name "
                              "not ending in .csv)", c->args[0].text, fmt);
    return nb_plot_check(c, err);
}

/* ---- the live view (docs/live-view.md) -------------------------------------------------------- */

enum { LIVE_PATHS = 64, LIVE_LEN = 64 };

static int check_live_plane(void *vm, const mote_call *c, mote_err *err)
{
    const char *p = c->args[0].text;
    if (strcmp(p, "xy") && strcmp(p, "xz") && strcmp(p, "yz"))
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "live_plane: expected xy, xz or yz, found "
                              "'%s'", p);
    return MOTE_OK;
}
static int run_live_plane(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const char *p = c->args[0].text;
    m->live.plane = p[0] == 'y' ? 2 : p[1] == 'z' ? 1 : 0;
    m->live.len = m->live.head = 0; /* the paths start again in the new plane */
    return MOTE_OK;
}

/* The bodies in the chosen plane at their true radii (at least a pixel on the page), the most
 * massive in yellow, and the recent paths of the first bodies; only reads the system. */
static void model_live(void *vm, mote_buf *b)
{
    nb_model *m = vm;
    const mote_nb *nb = &m->nb;
    const int a0 = m->live.plane == 2 ? 1 : 0, a1 = m->live.plane == 0 ? 1 : 2;
    const uint32_t np = nb->n < LIVE_PATHS ? nb->n : LIVE_PATHS;
    if (m->live.nb != np || !m->live.pts) { /* (re)start the paths */
        free(m->live.pts);
        m->live.pts = malloc(2 * (size_t)LIVE_LEN * (np ? np : 1) * sizeof *m->live.pts);
        m->live.nb = np;
        m->live.len = m->live.head = 0;
        if (!m->live.pts) {
            b->failed = 1;
            return;
        }
    }
    for (uint32_t i = 0; i < np; i++) {
        double *q = m->live.pts + 2 * ((size_t)i * LIVE_LEN + m->live.head);
        q[0] = (double)nb->x[3 * i + (uint32_t)a0];
        q[1] = (double)nb->x[3 * i + (uint32_t)a1];
    }
    m->live.head = (m->live.head + 1) % LIVE_LEN;
    m->live.len += m->live.len < LIVE_LEN;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, mmax = 0;
    uint32_t heavy = 0, na = 0;
    for (uint32_t i = 0; i < nb->n; i++) {
        if (!nb->active[i])
            continue;
        na++;
        for (int k = 0; k < 2; k++) {
            const double v = (double)nb->x[3 * i + (uint32_t)(k ? a1 : a0)];
            lo[k] = fmin(lo[k], v);
            hi[k] = fmax(hi[k], v);
        }
        if ((double)nb->m[i] > mmax) {
            mmax = (double)nb->m[i];
            heavy = i;
        }
    }
    double half = 0.55 * fmax(hi[0] - lo[0], hi[1] - lo[1]);
    if (!(half > 0))
        half = 1;
    const double cx = na ? (lo[0] + hi[0]) / 2 : 0, cy = na ? (lo[1] + hi[1]) / 2 : 0;
    mote_buf_printf(b, ",\"view\":\"2d\"");
    const double box[4] = {cx - half, cy - half, cx + half, cy + half};
    mote_buf_doubles(b, "box", box, 4, 1);
    mote_buf_printf(b, ",\"classes\":[{\"name\":\"most massive\",\"color\":\"#e8c23a\"},"
                       "{\"name\":\"bodies\",\"color\":\"#9ecbff\"}]");
    double *v = malloc(4 * (size_t)(na ? na : 1) * sizeof *v);
    if (!v) {
        b->failed = 1;
        return;
    }
    uint32_t k = 0;
    for (uint32_t i = 0; i < nb->n; i++)
        if (nb->active[i]) {
            v[k] = (double)nb->x[3 * i + (uint32_t)a0];
            v[na + k] = (double)nb->x[3 * i + (uint32_t)a1];
            v[2 * (size_t)na + k] = (double)nb->ra[i];
            v[3 * (size_t)na + k] = i == heavy ? 0 : 1;
            k++;
        }
    mote_buf_fixed(b, "x", v, na, 1, 2 * half);
    mote_buf_fixed(b, "y", v + na, na, 1, 2 * half);
    mote_buf_doubles(b, "r", v + 2 * (size_t)na, na, 1);
    mote_buf_doubles(b, "c", v + 3 * (size_t)na, na, 1);
    free(v);
    mote_buf_printf(b, ",\"paths\":[");
    for (uint32_t i = 0; i < np && !b->failed; i++) {
        mote_buf_printf(b, i ? ",[" : "[");
        for (size_t j = 0; j < m->live.len; j++) { /* oldest first */
            const size_t at = (m->live.head + LIVE_LEN - m->live.len + j) % LIVE_LEN;
            const double *q = m->live.pts + 2 * ((size_t)i * LIVE_LEN + at);
            mote_buf_printf(b, j ? ",%.7g,%.7g" : "%.7g,%.7g", q[0], q[1]);
        }
        mote_buf_printf(b, "]");
    }
    mote_buf_printf(b, "]");
    double ek = 0;
    for (uint32_t i = 0; i < nb->n; i++) {
        const mote_real *w = nb->v + 3 * (size_t)i;
        ek += 0.5 * (double)(nb->m[i] * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]));
    }
    char st[256];
    snprintf(st, sizeof st, "T = %.10g   step %llu   N = %u active   E_kin = %.10g   merges %llu"
             "   plane %s%s", (double)nb->T, (unsigned long long)nb->steps, na, ek,
             (unsigned long long)nb->merges,
             m->live.plane == 0 ? "xy" : m->live.plane == 1 ? "xz" : "yz",
             nb->tree_on ? "   tree forces (approximate)" : "");
    mote_buf_string(b, "status", st);
}

static const mote_cmd nb_commands[] = {
    {"body", NULL,
     "mass=r>0! x=r y=r z=r vx=r vy=r vz=r radius=r>=0 density=r>0 charge=r spin=s name=s",
     "body mass=M [x=X] [y=Y] [z=Z] [vx=VX] [vy=VY] [vz=VZ] [radius=R|density=RHO] [charge=Q] "
     "[spin=SX,SY,SZ] [name=NAME]",
     "add a body (dimensionless units)", HELP_BODY, check_body, run_body},
    {"units", NULL, "*", "units [solar|atomic|dimensionless] [mass=KG|auto] [length=M] [time=S] "
     "[input=si|dimensionless]", "physical scales, and the units of body values", HELP_UNITS,
     check_units, run_units},
    {"constant", NULL, "G=r>0 e=r>0 e2=r>0 permittivity=r>0",
     "constant [G=X] [e=X] [e2=X] [permittivity=X]", "replace a physical constant",
     HELP_CONSTANT, check_constant, run_constant},
    {"frame", NULL, "s", "frame barycentric", "shift to the barycentre (centre of mass at rest)",
     HELP_FRAME, check_frame, run_frame},
    {"generate", NULL,
     "s nb=i>=2 ka=r>0 e=r[0,1) tilt=r central_mass=r>0 total_mass=r>0 density=r>0 dt=r>0 "
     "A=i>=1 Z=i>=1 n=i>=1 l=i permittivity=r>0 time_unit=r>0 data=f<solar bodies=s "
     "merge_inner=s b=r>0 c=r>0 origin=s mu=i>=1 sep_density=r>=0 sep_pos=s sep_vel=s omega=r "
     "axis=s rho_area=r>0 rho_body=r>=0 length=r>0 seed=i>=0",
     "generate KIND [options]",
     "the exact rings of the seed document, the Solar System, or Galactica's area of matter",
     HELP_GENERATE, check_generate, run_generate},
    {"integrator", NULL,
     "s dt=r>0 order=s first_step=r(0,1] tol=r(0,1) memory=s safety=r>0 hmin=r>=0 hmax=r>0 "
     "norm=s step=s dt_max=r>0",
     "integrator NAME [dt=H] [order=K] [first_step=F] [tol=E] [memory=M] [safety=S] "
     "[hmin=A] [hmax=B] [norm=nearest|global] [step=fixed|adaptive|doubling] [dt_max=D]",
     "choose and set the integrator (galactica or taylor)",
     HELP_INTEGRATOR, check_integrator, run_integrator},
    {"compensated", NULL, "s", "compensated on|off", "compensated summation (default on)",
     HELP_COMPENSATED, check_compensated, run_compensated},
    {"forces", NULL, "s theta=r>=0", "forces direct|tree [theta=T]",
     "how forces are summed: every pair, or the approximate Barnes-Hut tree",
     HELP_FORCES, check_forces, run_forces},
    {"merge", NULL, "s bt=r(0,1] hmin=r(0,1]", "merge on|off [bt=F] [hmin=H]", "merge bodies that touch (default: on when any has a radius)",
     HELP_MERGE, check_merge, run_merge},
    {"monitor", NULL, "every=i>=1 dt=r>0 unit=s format=s file=f>monitor",
     "monitor every=K|dt=T [unit=U] [format=table|csv|jsonl] [file=FILE]",
     "record energy, momenta and centre of mass every K steps or every T of time", HELP_MONITOR,
     check_sampler, run_monitor},
    {"trajectory", NULL,
     "every=i>=1 dt=r>0 unit=s format=s file=f>trajectory! bodies=s velocities=s",
     "trajectory every=K|dt=T file=FILE [unit=U] [format=table|csv|jsonl] [bodies=LIST] "
     "[velocities=on|off]",
     "record the positions of every body (plot draws the orbits)", HELP_TRAJECTORY,
     check_trajectory, run_trajectory},
    {"approaches", NULL, "body=s! every=i>=1! refine=s file=f>approaches! format=s",
     "approaches body=B every=K file=FILE [refine=on] [format=native|galactica]",
     "record the closest approach of body B to the others in every K steps", HELP_APPROACHES,
     check_approaches, run_approaches},
    {"frames", NULL, "every=i>=1! prefix=f control=f<control",
     "frames every=K [prefix=frame_] [control=galacf26.dat]",
     "Galactica-style pictures every K steps (spec 7.13)", HELP_FRAMES, check_frames,
     run_frames},
    {"integrate", NULL, "steps=i>=1 to=r for=r>0 unit=s",
     "integrate [steps=N] [to=T] [for=D] [unit=U]",
     "advance by N steps, to the time T, or for the time D (ends exactly)", HELP_INTEGRATE,
     check_integrate, run_integrate},
    {"save", NULL, "f>state", "save FILE", "write the exact state to FILE", HELP_SAVE, check_save,
     run_save},
    {"load", NULL, "f<state", "load FILE", "continue from a state written by save", HELP_LOAD,
     check_load, run_load},
    {"checkpoint", NULL, "file=f>state! every=i>=1!", "checkpoint file=FILE every=K",
     "keep the exact state in FILE every K steps (restart continues from it)", HELP_CHECKPOINT,
     check_checkpoint, run_checkpoint},
    {"restart", NULL, "file=f<state!", "restart file=FILE",
     "continue from a checkpoint (or a saved state)", HELP_RESTART, check_restart, run_restart},
    {"check", NULL, "s", "check ring", "compare with the exact ring solution", HELP_CHECK,
     check_check, run_check},
    {"write", NULL, "s file=f>snapshot! format=s info_line=s", "write snapshot|galactica file=FILE",
     "write the bodies and the run's state as a snapshot table (spec 10.2)", HELP_WRITE,
     check_write, run_write},
    {"read", NULL, "s file=f<snapshot! format=s n=i>=1", "read snapshot|galactica file=FILE",
     "continue from a snapshot (replaces the bodies)", HELP_READ, check_read, run_read},
    {"steps_between", NULL, "jd1=r! jd2=r! dt=r>0! fresh=s", "steps_between jd1= jd2= dt= [fresh=on]",
     "the steps and the corrected step between two dates", HELP_STEPS_BETWEEN,
     check_steps_between, run_steps_between},
    {"live_plane", NULL, "s", "live_plane xy|xz|yz",
     "the plane the live view shows (xy by default)",
     "The plane of the live view (`mote run --live`, `live http`): the bodies and the recent\n"
     "paths of the first 64 are drawn projected on xy (the default), xz or yz.\n",
     check_live_plane, run_live_plane},
    {"run", NULL,
     "s control=f<control interaction=s frames=s step_tol=r(0,1) force=s lenient=s "
     "trio_layout=s max_files=i>=1",
     "run galactica [control=galacf26.dat] [interaction=gravity|coulomb] [frames=on] "
     "[step_tol=E] [force=on] [lenient=on] [trio_layout=packed] [max_files=N]",
     "run a Galactica job: its control file, bodies and result files", HELP_RUN, check_run,
     run_run},
    {"snapshot", NULL, "every=i>=1! prefix=f format=s",
     "snapshot every=K [prefix=P] [format=native|galactica]",
     "write a snapshot every K steps of integrate, to PSTEP.snap", HELP_SNAPSHOT, check_snapshot,
     run_snapshot},
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
    .plot_opts = "bodies=s relative_to=s plane=s size=i[64,8192]",
    .plot_check = model_plot_check,
    .live = model_live,
};
