/* commands.c: the N-body model's script commands (spec 8): the table the script language reads,
 * the model's life and status, and the setup commands (bodies, units, generators, integrator,
 * forces, merging). The checks of state that crosses commands (are there bodies? a ring to
 * compare with?) run on a dry model; argument ranges and files are the table's. The output
 * commands and integrate are in outputs.c, the files in files.c, the live view in live.c and
 * the help text in help.inc. */
#include "mote/h5md.h"
#include "mote/datafile.h"
#include "mote/nbody.h"

#include <tgmath.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "model.h"

#include "help.inc"

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
    /* a script without an `integrator` line gets the adaptive Taylor integrator at its default
     * order and tolerance (as REBOUND users expect of IAS15), not a fixed step of 1e-6 */
    m->nb.integrator = MOTE_NB_TAYLOR;
    m->nb.adaptive = 1;
    m->nb.tol = MOTE_NB_TAYLOR_TOL;
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
        mote_rows_free(&smp[k]->out);
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
void nb_settle_units(nb_model *m)
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
    fprintf(out, "N=%u interaction=%s T=%s steps=%llu dt=%s E=%s %s=%s dMz=%.3e merges=%llu\n",
            nb->n, nb->kind == MOTE_NB_GRAVITY ? "gravity" : "coulomb", mote_real_str(nb->T, t),
            (unsigned long long)nb->steps,
            mote_real_str(nb->adaptive && nb->steps ? nb->hlast : nb->dt, h), e,
            mote_nb_de_absolute(nb) ? "dE_abs" : "dE", de,
            dmz, (unsigned long long)nb->merges);
}

/* A real option to the build's full precision (its text read again), or dflt when not given. */
mote_real nb_opt_real_or(const mote_call *c, const char *key, mote_real dflt)
{
    const mote_arg *a = mote_call_opt(c, key);
    return a ? mote_real_parse(a->text, NULL) : dflt;
}
static mote_real opt_real(const mote_call *c, const char *key) { return nb_opt_real_or(c, key, 0); }

int nb_need_bodies(nb_model *m, const mote_call *c, mote_err *err)
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
    int rc = nb_body_elements_check(m, c, err);
    if (rc)
        return rc;
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
    int rc = nb_body_elements(m, c, mass, x, v, err);
    if (rc)
        return rc;
    const mote_arg *nm = mote_call_opt(c, "name");
    if (nm && mote_nb_find(&m->nb, nm->text) >= 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "name"), MOTE_EINVAL,
                              "body: the name '%s' is taken by body %ld", nm->text,
                              mote_nb_find(&m->nb, nm->text) + 1);
    rc = mote_nb_add(&m->nb, mass, opt_real(c, "charge"), x, v, ra, err);
    if (!rc)
        for (int a = 0; a < 3; a++)
            m->nb.sp[3 * (size_t)(m->nb.n - 1) + a] = sp[a];
    if (!rc && nm)
        rc = mote_nb_set_name(&m->nb, m->nb.n - 1, nm->text, err);
    return rc;
}

/* ---- units and constants ------------------------------------------------------------------------ */

/* Read `units` from the table: a preset (solar, atomic or dimensionless, also bare) and the
 * options mass=KG|auto length=M time=S input=si|dimensionless. */
static int units_parse(const nb_model *m, const mote_call *c, nb_units_req *q, mote_err *err)
{
    memset(q, 0, sizeof *q);
    const mote_arg *preset = mote_call_opt(c, "preset"), *mass = mote_call_opt(c, "mass"),
                   *input = mote_call_opt(c, "input");
    q->preset = preset ? UNITS_SOLAR + preset->i : UNITS_CUSTOM; /* (the table's word order) */
    q->length = mote_call_opt_r(c, "length", 0);
    q->time = mote_call_opt_r(c, "time", 0);
    q->mass_auto = !mass || mass->word;
    q->mass = q->mass_auto ? 0 : mass->r;
    const char *name = preset ? preset->text : "";
    if (q->preset == UNITS_NONE) {
        if (c->nopts > 1)
            return mote_call_fail(err, c, mote_call_opt_index(c, "preset"), MOTE_EINVAL,
                                  "units dimensionless: takes no options");
        return MOTE_OK;
    }
    const int ti = mote_call_opt_index(c, "time"), li = mote_call_opt_index(c, "length");
    if (q->length > 0 && q->time > 0) /* (at the second of the two) */
        return mote_call_fail(err, c, ti > li ? ti : li, MOTE_EINVAL,
                              "units: give length= or time=, not both (the other follows from "
                              "eq. 6)");
    if (q->preset != UNITS_CUSTOM && (q->length > 0 || q->time > 0))
        return mote_call_fail(err, c, mote_call_opt_index(c, "preset"), MOTE_EINVAL,
                              "units %s: the preset fixes the time unit; leave out length= and "
                              "time=", name);
    if (q->preset == UNITS_SOLAR)
        q->time = 100 * MOTE_NB_SIDEREAL_YEAR_DAYS * 86400;
    if (q->preset == UNITS_ATOMIC) {
        if (m->nb.kind != MOTE_NB_COULOMB)
            return mote_call_fail(err, c, mote_call_opt_index(c, "preset"), MOTE_EINVAL,
                                  "units atomic: is for Coulomb runs (model nbody coulomb)");
        q->time = 1e-15;
    }
    if (!(q->length > 0 || q->time > 0))
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "units: give length=M or time=S (or a preset: solar, atomic)");
    q->input_si = !input || input->i == 0;
    if (q->mass_auto && !q->input_si) {
        if (q->preset == UNITS_SOLAR && !mass) { /* the Solar-System mass of spec 3.6 */
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
    return nb_need_bodies(vm, c, err); /* (e{barycentric}: the only frame) */
}
static int run_frame(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    mote_real xc[3], vc[3];
    nb_settle_units(m);
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

static int merge_inner_opt(const mote_call *c)
{
    const mote_arg *a = mote_call_opt(c, "merge_inner"); /* on|off */
    return a && a->i == 0;
}

/* `generate solar_system`: read the data file now (its errors are the script's), count bodies. */
static int check_solar(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    if (m->nb.kind != MOTE_NB_GRAVITY)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "generate solar_system: this is a Coulomb run; it needs 'model "
                              "nbody gravity'");
    const mote_arg *d = mote_call_opt(c, "data");
    if (m->d_bodies)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "generate: the system already has bodies; a generator starts empty "
                              "('reset' gives a new one)");
    const int inner = merge_inner_opt(c);
    int rc;
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

static int run_solar(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    m->raw = 0; /* a generator sets its own scales */
    const int inner = merge_inner_opt(c);
    mote_nb_solar s;
    int rc = mote_nb_solar_read(mote_call_opt(c, "data")->path, &s, err);
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
    a->dt = nb_opt_real_or(c, "dt", a->dt);
    static const char *const vec[3] = {"origin", "sep_pos", "sep_vel"}; /* (vectors: v3) */
    double *dst[3] = {a->X0, a->Xs, a->Us};
    for (int k = 0; k < 3; k++)
        if ((o = mote_call_opt(c, vec[k])))
            memcpy(dst[k], o->v, sizeof o->v);
    if ((o = mote_call_opt(c, "axis"))) {
        a->X01 = o->v[0];
        a->Y01 = o->v[1];
    }
    (void)err;
    return MOTE_OK;
}

static int check_area(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    if (m->nb.kind != MOTE_NB_GRAVITY)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "generate area: this is a Coulomb run; the "
                              "area of matter needs 'model nbody gravity'");
    if (m->d_bodies)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "generate: the system already has bodies; the area starts empty "
                              "('reset' gives a new one)");
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

static int run_area(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    m->raw = 0;
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

/* `generate plummer n=N [seed=S]` */
static int check_plummer(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const mote_arg *n = mote_call_opt(c, "n");
    if (n->i > NB_MAX_GENERATED)
        return mote_call_fail(err, c, mote_call_opt_index(c, "n"), MOTE_EINVAL,
                              "generate plummer: n= the number of bodies (1 ... 10^7)");
    mote_err e2 = {0};
    if (mote_mem_check((double)n->i * NB_BODY_BYTES, "generate plummer: the bodies", &e2))
        return mote_call_fail(err, c, mote_call_opt_index(c, "n"), e2.code, "%s", e2.msg);
    if (m->nb.kind != MOTE_NB_GRAVITY || m->d_bodies)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "generate plummer: %s",
                              m->d_bodies ? "the system already has bodies "
                                            "('reset' gives a new one)"
                                          : "a Plummer sphere needs 'model nbody gravity'");
    m->d_bodies = (uint32_t)n->i;
    m->d_ring = 0;
    m->d_scales = 1;
    return MOTE_OK;
}

static int run_plummer(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    m->raw = 0;
    const mote_arg *sd = mote_call_opt(c, "seed");
    m->have_ring = 0;
    int rc = mote_nb_plummer(&m->nb, (uint32_t)mote_call_opt(c, "n")->i,
                             sd ? (uint64_t)sd->i : 1, err);
    if (!rc && m->log)
        fprintf(m->log, "generate plummer: %u equal masses, Plummer radius 1, G = 1 units, "
                        "barycentric\n", m->nb.n);
    return rc;
}

/* `generate ring` (gravity) and `generate atom_ring` (Coulomb) */
static int check_ring(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    const int ring = strcmp(c->name, "generate ring") == 0;
    if (ring != (m->nb.kind == MOTE_NB_GRAVITY))
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "%s: this is a %s run; the %s needs 'model nbody %s'", c->name,
                              m->nb.kind == MOTE_NB_GRAVITY ? "gravity" : "Coulomb",
                              ring ? "gravity ring" : "Coulomb ring", ring ? "gravity" : "coulomb");
    if (m->d_bodies)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "generate: the system already has bodies; a ring starts empty "
                              "('reset' gives a new one)");
    const mote_arg *nbo = mote_call_opt(c, "nb");
    m->d_bodies = nbo ? (uint32_t)nbo->i : ring ? 30 : 9;
    m->d_ring = 1;
    m->d_scales = 1;
    return MOTE_OK;
}
static int run_ring(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    m->raw = 0; /* a generator sets its own scales */
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
    r->dt = nb_opt_real_or(c, "dt", r->dt);
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

/* The order option (its range is the table's): an integer, or for taylor `auto` (then from
 * tol=). */
static void set_order(const mote_call *c, int *order)
{
    const mote_arg *a = mote_call_opt(c, "order");
    if (a && a->word) /* auto */
        *order = mote_nb_taylor_auto_order(nb_opt_real_or(c, "tol", MOTE_NB_TAYLOR_TOL));
    else if (a)
        *order = (int)a->i;
}

/* `integrator galactica`, `integrator taylor` and `integrator wh`: one table row each, with its
 * own options, checked and applied by the row's functions; what the plug-in (integrators.c)
 * sets when it is chosen comes first (nb_integrator.chosen), the options after. */

/* The step options galactica and taylor share (dt=, hmin=, hmax=, norm=, tol=). */
static int check_step_options(const mote_call *c, const char *name, mote_err *err)
{
    if (mote_call_opt(c, "norm") && mote_call_opt(c, "dt"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "norm"), MOTE_EINVAL,
                              "integrator taylor: norm= is for the adaptive step (tol=), not "
                              "with dt=");
    const mote_arg *hmin = mote_call_opt(c, "hmin"), *hmax = mote_call_opt(c, "hmax");
    if (hmin && hmax && mote_real_parse(hmin->text, NULL) > mote_real_parse(hmax->text, NULL))
        return mote_call_fail(err, c, mote_call_opt_index(c, "hmin"), MOTE_EINVAL,
                              "integrator %s: hmin= (%s) is greater than hmax= (%s)", name,
                              hmin->text, hmax->text);
    return MOTE_OK;
}

/* The plug-in chosen, its own defaults set (the previous step stays: a restart continues as
 * the run would have). */
static mote_nb *choose(void *vm, int id)
{
    mote_nb *nb = &((nb_model *)vm)->nb;
    nb->integrator = id;
    nb_integrator_of(id)->chosen(nb);
    return nb;
}

static int check_wh(void *vm, const mote_call *c, mote_err *err)
{
    const mote_arg *k = mote_call_opt(c, "corrector");
    if (k && k->i != 0 && k->i != 3 && k->i != 5 && k->i != 7 && k->i != 11 && k->i != 17)
        return mote_call_fail(err, c, mote_call_opt_index(c, "corrector"), MOTE_EINVAL,
                              "integrator wh: corrector= must be 0, 3, 5, 7, 11 or 17 (the "
                              "orders of Wisdom, Holman and Touma's correctors), found %s",
                              k->text);
    return MOTE_OK;
}
static int run_wh(void *vm, const mote_call *c, mote_err *err)
{
    mote_nb *nb = choose(vm, MOTE_NB_WH);
    nb->dt = nb_opt_real_or(c, "dt", nb->dt);
    const mote_arg *k = mote_call_opt(c, "corrector");
    if (k)
        nb->wh_corrector = (int)k->i;
    return MOTE_OK;
}

static int check_taylor(void *vm, const mote_call *c, mote_err *err)
{
    if (mote_call_opt(c, "dt") && mote_call_opt(c, "tol") &&
        !(mote_call_opt(c, "order") && mote_call_opt(c, "order")->word))
        return mote_call_fail(err, c, mote_call_opt_index(c, "tol"), MOTE_EINVAL,
                              "integrator taylor: dt= fixes the step and tol= makes it adaptive; "
                              "give one (tol= may come with order=auto)");
    return check_step_options(c, "taylor", err);
}

/* The options galactica and taylor both apply. */
static void step_options(mote_nb *nb, const mote_call *c, int *order)
{
    nb->dt = nb_opt_real_or(c, "dt", nb->dt);
    set_order(c, order);
    nb->tol = nb_opt_real_or(c, "tol", nb->tol);
    nb->safety = nb_opt_real_or(c, "safety", nb->safety);
    nb->hmin = nb_opt_real_or(c, "hmin", nb->hmin);
    nb->hmax = nb_opt_real_or(c, "hmax", nb->hmax);
}

static int run_taylor(void *vm, const mote_call *c, mote_err *err)
{
    mote_nb *nb = choose(vm, MOTE_NB_TAYLOR);
    nb->first_step = nb_opt_real_or(c, "first_step", nb->first_step);
    const mote_arg *mem = mote_call_opt(c, "memory");
    if (mem) /* store|recompute|auto */
        nb->taylor_memory = mem->i == 0 ? 1 : mem->i == 1 ? 2 : 0;
    nb->adaptive = mote_call_opt(c, "dt") == NULL; /* adaptive: without dt= */
    enum { NORM_NEAREST, NORM_GLOBAL }; /* norm=e{nearest|global} */
    if (nb->adaptive && mote_call_word(c, "norm", NORM_NEAREST) == NORM_GLOBAL)
        nb->adaptive = MOTE_NB_NORM_GLOBAL;
    step_options(nb, c, &nb->taylor_order);
    return MOTE_OK;
}

static int check_galactica(void *vm, const mote_call *c, mote_err *err)
{
    const mote_arg *st = mote_call_opt(c, "step");
    const char *mode = st ? st->text : mote_call_opt(c, "tol") ? "adaptive" : "fixed";
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
    int rc = check_step_options(c, "galactica", err);
    int order = 6;
    set_order(c, &order);
    if (!rc && strcmp(mode, "adaptive") == 0 && mote_call_opt(c, "order") && order != 6)
        return mote_call_fail(err, c, mote_call_opt_index(c, "tol"), MOTE_EINVAL,
                              "integrator galactica: the adaptive step (tol=) needs order=6");
    return rc;
}
static int run_galactica(void *vm, const mote_call *c, mote_err *err)
{
    mote_nb *nb = choose(vm, MOTE_NB_GALACTICA);
    nb->first_step = nb_opt_real_or(c, "first_step", nb->first_step);
    /* adaptive: with step=adaptive, or with tol= */
    enum { STEP_FIXED, STEP_ADAPTIVE, STEP_DOUBLING, STEP_NONE }; /* step=e{fixed|adaptive|doubling} */
    const int st = mote_call_word(c, "step", STEP_NONE);
    nb->adaptive = st != STEP_NONE ? st == STEP_ADAPTIVE : mote_call_opt(c, "tol") != NULL;
    nb->doubling = st == STEP_DOUBLING;
    nb->dt_max = nb_opt_real_or(c, "dt_max", 0);
    if (nb->adaptive && mote_call_opt(c, "dt_max") && !mote_call_opt(c, "hmax"))
        nb->hmax = nb->dt_max; /* dt_max bounds the adaptive step too */
    step_options(nb, c, &nb->order);
    return MOTE_OK;
}

static int run_merge(void *vm, const mote_call *c, mote_err *err)
{
    mote_nb *nb = &((nb_model *)vm)->nb;
    nb->merging = c->args[0].i == 0; /* on|off */
    nb->bt = nb_opt_real_or(c, "bt", nb->bt);
    nb->bt_hmin = nb_opt_real_or(c, "hmin", nb->bt_hmin);
    return MOTE_OK;
}

/* The parameter commands bound to a value of the state (its descriptor in state.c's table:
 * the line's key and the value's name): what they set is what save writes and load reads. */
static const mote_param nb_params[] = {
    {"compensated", "scheme.compensated"}, /* (its words off|on: 0, 1) */
    {"softening", "scheme.softening"},
};
static void *nb_state_fields(void *vm, const struct mote_sf_field **f, size_t *n)
{
    nb_model *m = vm;
    *n = nb_state_table(m->sf);
    *f = m->sf;
    return &m->nb;
}

/* forces direct (spec 6.1); the tree of spec 6.2 belongs to the large-N work */
static int check_forces(void *vm, const mote_call *c, mote_err *err)
{
    if (c->args[0].i == 0 && mote_call_opt(c, "theta")) /* direct|tree */
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
    m->nb.tree_on = c->args[0].i == 1; /* direct|tree */
    m->nb.theta = m->nb.tree_on ? (mote_real)(t ? t->r : 0.5) : 0;
    if (m->log && m->nb.tree_on)
        fprintf(m->log, "forces: Barnes-Hut tree, theta %g (approximate: every output says so)\n",
                (double)m->nb.theta);
    return MOTE_OK;
}

/* ---- monitor and integrate ------------------------------------------------------------------- */

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
    return MOTE_OK; /* (plane= is one of the table's words) */
}


static const mote_cmd nb_commands[] = {
    {"body", NULL,
     "mass=r>0! x=r y=r z=r vx=r vy=r vz=r radius=r>=0 density=r>0 charge=r spin=s name=s "
     "a=r e=r>=0 inc=r Omega=r omega=r f=r M=r primary=s",
     "body mass=M [x=X] [y=Y] [z=Z] [vx=VX] [vy=VY] [vz=VZ] [radius=R|density=RHO] [charge=Q] "
     "[spin=SX,SY,SZ] [name=NAME] [a=A] [e=E] [inc=I] [Omega=O] [omega=W] [f=F|M=M] "
     "[primary=BODY]",
     "add a body (dimensionless units)", HELP_BODY, check_body, run_body},
    {"units", NULL,
     "@preset=e{solar|atomic|dimensionless} mass=r>0{auto} length=r>0 time=r>0 "
     "input=e{si|dimensionless}", "units [solar|atomic|dimensionless] [mass=KG|auto] [length=M] [time=S] "
     "[input=si|dimensionless]", "physical scales, and the units of body values", HELP_UNITS,
     check_units, run_units},
    {"constant", NULL, "G=r>0 e=r>0 e2=r>0 permittivity=r>0",
     "constant [G=X] [e=X] [e2=X] [permittivity=X]", "replace a physical constant",
     HELP_CONSTANT, check_constant, run_constant},
    {"frame", NULL, "e{barycentric}", "frame barycentric", "shift to the barycentre (centre of mass at rest)",
     HELP_FRAME, check_frame, run_frame},
    {"generate ring", NULL,
     "nb=i>=2 ka=r>0 e=r[0,1) tilt=r central_mass=r>0 total_mass=r>0 density=r>0 dt=r>0",
     "generate ring [options]", "the exact gravity ring of the seed document (spec 9.1)",
     HELP_GEN_RING, check_ring, run_ring},
    {"generate atom_ring", NULL,
     "nb=i>=2 ka=r>0 e=r[0,1) tilt=r A=i>=1 Z=i>=1 n=i>=1 l=i permittivity=r>0 time_unit=r>0 "
     "dt=r>0",
     "generate atom_ring [options]", "the exact Coulomb ring of the seed document (spec 9.2)",
     HELP_GEN_RING, check_ring, run_ring},
    {"generate solar_system", NULL, "data=f<solar! bodies=s merge_inner=e{on|off}",
     "generate solar_system data=FILE [options]", "the bodies of a Solar-System data file",
     HELP_GEN_SOLAR, check_solar, run_solar},
    {"generate area", NULL,
     "b=r>0 c=r>0 origin=v3 mu=i>=1 sep_density=r>=0 sep_pos=v3 sep_vel=v3 omega=r axis=v2 "
     "rho_area=r>0 rho_body=r>=0 dt=r>0 length=r>0",
     "generate area [options]", "Galactica's area of matter (spec 9.4)", HELP_GEN_AREA,
     check_area, run_area},
    {"generate plummer", NULL, "n=i>=1! seed=i>=0", "generate plummer n=N [seed=S]",
     "a Plummer sphere of equal masses", HELP_GEN_PLUMMER, check_plummer, run_plummer},
    {"integrator galactica", NULL,
     "dt=r>0 order=i[2,6] first_step=r(0,1] tol=r(0,1) safety=r>0 hmin=r>=0 hmax=r>0 "
     "step=e{fixed|adaptive|doubling} dt_max=r>0",
     "integrator galactica [dt=H] [order=K] [first_step=F] [tol=E] [safety=S] [hmin=A] "
     "[hmax=B] [step=fixed|adaptive|doubling] [dt_max=D]",
     "Galactica's Taylor scheme (spec 4.2), fixed or adaptive", HELP_INTEGRATOR,
     check_galactica, run_galactica},
    {"integrator taylor", NULL,
     "dt=r>0 order=i[2,60]{auto} tol=r(0,1) memory=e{store|recompute|auto} safety=r>0 "
     "hmin=r>=0 hmax=r>0 norm=e{nearest|global}",
     "integrator taylor [dt=H] [order=P|auto] [tol=E] [memory=M] [safety=S] [hmin=A] "
     "[hmax=B] [norm=nearest|global]",
     "the general Taylor integrator of any order (spec 4.4)", HELP_INTEGRATOR,
     check_taylor, run_taylor},
    {"integrator wh", NULL, "dt=r>0! corrector=i[0,17]", "integrator wh dt=H [corrector=K]",
     "the Wisdom-Holman symplectic map for planetary systems", HELP_INTEGRATOR,
     check_wh, run_wh},
    {"softening", NULL, "eps=r>=0!", "softening eps=E",
     "Plummer softening of every pair's force and potential energy", HELP_SOFTENING,
     mote_cmd_set, mote_cmd_set},
    {"compensated", NULL, "e{off|on}", "compensated on|off", "compensated summation (default on)",
     HELP_COMPENSATED, mote_cmd_set, mote_cmd_set},
    {"forces", NULL, "e{direct|tree} theta=r>=0", "forces direct|tree [theta=T]",
     "how forces are summed: every pair, or the approximate Barnes-Hut tree",
     HELP_FORCES, check_forces, run_forces},
    {"merge", NULL, "e{on|off} bt=r(0,1] hmin=r(0,1]", "merge on|off [bt=F] [hmin=H]", "merge bodies that touch (default: on when any has a radius)",
     HELP_MERGE, NULL, run_merge},
    {"monitor", NULL, "every=i>=1 dt=r>0 unit=e{s|day|year|century} format=e{table|csv|jsonl} file=f>monitor",
     "monitor every=K|dt=T [unit=U] [format=table|csv|jsonl] [file=FILE]",
     "record energy, momenta and centre of mass every K steps or every T of time", HELP_MONITOR,
     nb_check_sampler, nb_run_monitor},
    {"trajectory", NULL,
     "every=i>=1 dt=r>0 unit=e{s|day|year|century} format=e{table|csv|jsonl|h5md} "
     "file=f>trajectory! bodies=s velocities=e{on|off}",
     "trajectory every=K|dt=T file=FILE [unit=U] [format=table|csv|jsonl|h5md] [bodies=LIST] "
     "[velocities=on|off]",
     "record the positions of every body (plot draws the orbits)", HELP_TRAJECTORY,
     nb_check_trajectory, nb_run_trajectory},
    MOTE_CMD_STOP(monitor, NULL, NULL, nb_run_monitor_stop),
    MOTE_CMD_STOP(trajectory, NULL, NULL, nb_run_trajectory_stop),
    {"approaches", NULL, "body=s! every=i>=1! refine=e{on|off} file=f>approaches! "
     "format=e{native|galactica}",
     "approaches body=B every=K file=FILE [refine=on] [format=native|galactica]",
     "record the closest approach of body B to the others in every K steps", HELP_APPROACHES,
     nb_check_approaches, nb_run_approaches},
    {"frames", NULL, "every=i>=1 dt=r>0 unit=e{s|day|year|century} prefix=f control=f<control",
     "frames every=K|dt=T [unit=U] [prefix=frame_] [control=galacf26.dat]",
     "Galactica-style pictures every K steps or every T of time (spec 7.13)", HELP_FRAMES, nb_check_frames,
     nb_run_frames},
    MOTE_CMD_STOP(frames, NULL, NULL, nb_run_frames_stop),
    {"integrate", NULL, "steps=i>=1 to=r for=r>0 unit=e{s|day|year|century}",
     "integrate [steps=N] [to=T] [for=D] [unit=U]",
     "advance by N steps, to the time T, or for the time D (ends exactly)", HELP_INTEGRATE,
     nb_check_integrate, nb_run_integrate},
    {"save", NULL, "f>state", "save FILE", "write the exact state to FILE", HELP_SAVE, nb_check_save,
     nb_run_save},
    {"load", NULL, "f<state", "load FILE", "continue from a state written by save", HELP_LOAD,
     nb_check_load, nb_run_load},
    {"checkpoint", NULL, "file=f>state! every=i>=1!", "checkpoint file=FILE every=K",
     "keep the exact state in FILE every K steps (restart continues from it)", HELP_CHECKPOINT,
     nb_check_checkpoint, nb_run_checkpoint},
    MOTE_CMD_STOP(checkpoint, NULL, NULL, nb_run_checkpoint_stop),
    {"restart", NULL, "file=f<state!", "restart file=FILE",
     "continue from a checkpoint (or a saved state)", HELP_RESTART, nb_check_restart, nb_run_restart},
    {"check", NULL, "e{ring}", "check ring", "compare with the exact ring solution", HELP_CHECK,
     nb_check_check, nb_run_check},
    {"write", NULL, "e{snapshot|galactica} file=f>snapshot! format=e{native} info_line=e{on|off}", "write snapshot|galactica file=FILE",
     "write the bodies and the run's state as a snapshot table (spec 10.2)", HELP_WRITE,
     nb_check_write, nb_run_write},
    {"read", NULL, "e{snapshot|galactica} file=f<snapshot! format=e{native} n=i>=1", "read snapshot|galactica file=FILE",
     "continue from a snapshot (replaces the bodies)", HELP_READ, nb_check_read, nb_run_read},
    {"steps_between", NULL, "jd1=r! jd2=r! dt=r>0! fresh=e{on|off}", "steps_between jd1= jd2= dt= [fresh=on]",
     "the steps and the corrected step between two dates", HELP_STEPS_BETWEEN,
     nb_check_steps_between, nb_run_steps_between},
    {"live_plane", NULL, "e{xy|xz|yz}", "live_plane xy|xz|yz",
     "the plane the live view shows (xy by default)",
     "The plane of the live view (`mote run --live`, `live http`): the bodies and the recent\n"
     "paths of the first 64 are drawn projected on xy (the default), xz or yz.\n",
     NULL, nb_run_live_plane},
    {"run", NULL,
     "e{galactica} control=f<control interaction=e{gravity|coulomb} frames=e{on|off} "
     "step_tol=r(0,1) force=e{on|off} lenient=e{on|off} trio_layout=e{prose|packed} "
     "max_files=i>=1",
     "run galactica [control=galacf26.dat] [interaction=gravity|coulomb] [frames=on] "
     "[step_tol=E] [force=on] [lenient=on] [trio_layout=packed] [max_files=N]",
     "run a Galactica job: its control file, bodies and result files", HELP_RUN, nb_check_run,
     nb_run_run},
    {"snapshot", NULL, "every=i>=1 dt=r>0 unit=e{s|day|year|century} prefix=f "
     "format=e{native|galactica} file=f>snapshot",
     "snapshot file=FILE|every=K|dt=T [unit=U] [prefix=P] [format=native|galactica]",
     "a snapshot now (file=), or every K steps (every T of time) of integrate", HELP_SNAPSHOT, nb_check_snapshot,
     nb_run_snapshot},
    MOTE_CMD_STOP(snapshot, NULL, NULL, nb_run_snapshot_stop),
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
    .plot_lines = "nbody-monitor:T,dE",
    .plot_opts = "bodies=s relative_to=s plane=e{invariable|xy|xz|yz} size=i[64,8192]",
    .state = nb_state_fields,
    .params = nb_params,
    .nparams = sizeof nb_params / sizeof nb_params[0],
    .plot_check = model_plot_check,
    .live = nb_model_live,
    .arrays = nb_model_arrays,
    .set_array = nb_model_set_array,
    .picture = nb_picture,
    .picture_help = "The picture of `frames` without a control file: the bodies seen from +z, the\n"
                    "whole system in view, each with its velocity's arrow (Galactica's screen).\n",
    .program = "galactica",
    .program_main = mote_nb_galactica_main,
    .mpi = 1,
};

