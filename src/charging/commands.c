/* commands.c: the charging model's script commands (spec 7.4): the table, the model's life and
 * status, and the setup commands: the plasma presets and species, the generated and loaded
 * bodies, the injection sphere, the field, the sun, the integrator and the materials. The long
 * commands (test, run, float, evolve) and `output` are in run.c, the help text in help.inc. */
#include "mote/charging.h"
#include "mote/datafile.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model.h"

#include "help.inc"

static void *model_create(mote_context *ctx, int dry)
{
    ch_model *m = calloc(1, sizeof *m);
    if (!m)
        return NULL;
    m->ctx = ctx;
    m->dry = dry;
    m->log = dry || !ctx ? NULL : ctx->out;
    m->faithful = ctx && strcmp(ctx->model_variant, "faithful") == 0;
    snprintf(m->radius, sizeof m->radius, "auto");
    m->seed = 1;
    if (m->faithful) { /* spec 7.4: faithful loads thesis-hot unless a plasma is defined */
        mote_err e;
        mote_ch_plasma_preset(&m->plasma, "thesis-hot", 0, 0, &e);
        m->have_plasma = 1;
    }
    return m;
}

static void model_destroy(void *vm)
{
    ch_model *m = vm;
    if (!m)
        return;
    ch_field_drop(m);
    mote_ch_body_free(&m->body);
    mote_ch_result_free(&m->res);
    free(m->prefix);
    free(m->origin);
    free(m->check_prefix);
    free(m->monitor.path);
    free(m->tri_mat);
    free(m->warnings);
    free(m);
}

static void model_seed(void *vm, uint64_t seed) { ((ch_model *)vm)->seed = seed; }

static void model_status(void *vm, FILE *out)
{
    ch_model *m = vm;
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    fprintf(out, "mode=%s species=%d triangles=%u area=%.10g C=%.10g\n",
            m->faithful ? "faithful" : "full", m->plasma.nsp,
            m->body.sphere ? 0 : m->body.ntri, g.area, g.capacitance);
}

/* three numbers X,Y,Z (any sign) */
int ch_parse3any(const char *t, double v[3])
{
    for (int a = 0; a < 3; a++) {
        char *end;
        v[a] = strtod(t, &end);
        if (end == t || !isfinite(v[a]) || *end != (a < 2 ? ',' : '\0'))
            return -1;
        t = end + 1;
    }
    return 0;
}


/* ---- plasma --------------------------------------------------------------------------------- */

static int check_plasma(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    const char *name = c->args[1].text; /* geo-worst-case|thesis-hot|single */
    const int single = c->args[1].i == 2;
    if (single && (!mote_call_opt(c, "n") || !mote_call_opt(c, "kT")))
        return mote_call_fail(err, c, 1, MOTE_EINVAL, "plasma preset single: give n= (m^-3) and "
                              "kT= (eV)");
    if (!single && (mote_call_opt(c, "n") || mote_call_opt(c, "kT")))
        return mote_call_fail(err, c, 1, MOTE_EINVAL, "plasma preset %s: n= and kT= are for "
                              "single", name);
    m->have_plasma = 1;
    mote_err ignored;
    mote_ch_plasma_preset(&m->plasma, name, mote_call_opt_r(c, "n", 1), mote_call_opt_r(c, "kT", 1),
                          &ignored);
    return MOTE_OK;
}

/* ---- species and maxwellian (spec 3.1, 7.4) ------------------------------------------------- */

/* `species clear`, or `species [name=]S charge=Z mass=electron|proton|KG | amu=A
 * [drift=VX,VY,VZ]` (its options from the table). */
static int parse_species(const mote_call *c, mote_ch_species *sp, int *clear, mote_err *err)
{
    memset(sp, 0, sizeof *sp);
    const mote_arg *name = mote_call_opt(c, "name"), *charge = mote_call_opt(c, "charge"),
                   *mass = mote_call_opt(c, "mass"), *amu = mote_call_opt(c, "amu"),
                   *drift = mote_call_opt(c, "drift");
    *clear = name && !strcmp(name->text, "clear");
    if (*clear) {
        if (c->nopts > 1)
            return mote_call_fail(err, c, -1, MOTE_EINVAL, "species clear: takes no options "
                                  "('clear' is no species name)");
        return MOTE_OK;
    }
    if (!name || !charge || !!mass == !!amu)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "species: give name=, charge= and "
                              "mass= or amu= (or 'species clear')");
    const int ni = mote_call_opt_index(c, "name");
    if (strlen(name->text) >= sizeof sp->name || strpbrk(name->text, " ,=#"))
        return mote_call_fail(err, c, ni, MOTE_EINVAL, "species: name must be 1 to %d "
                              "characters without spaces, commas or '=', found '%s'",
                              (int)sizeof sp->name - 1, name->text);
    if (charge->r == 0 || charge->r != floor(charge->r))
        return mote_call_fail(err, c, mote_call_opt_index(c, "charge"), MOTE_EINVAL,
                              "species: charge must be a whole number of elementary charges, "
                              "not 0 (e.g. -1, 1, 2), found '%s'", charge->text);
    snprintf(sp->name, sizeof sp->name, "%s", name->text);
    sp->Z = (int)charge->r;
    sp->m = amu ? amu->r * MOTE_CH_AMU
                : mass->word == 1 ? MOTE_CH_ME : mass->word == 2 ? MOTE_CH_MP : mass->r;
    if (drift)
        memcpy(sp->drift, drift->v, sizeof sp->drift);
    return MOTE_OK;
}

/* Apply `species` to the plasma p (the dry model's during validation, the real one after). */
static int apply_species(mote_ch_plasma *p, const mote_call *c, mote_err *err)
{
    mote_ch_species sp;
    int clear;
    int rc = parse_species(c, &sp, &clear, err);
    if (rc)
        return rc;
    if (clear) {
        memset(p, 0, sizeof *p);
        return MOTE_OK;
    }
    for (int s = 0; s < p->nsp; s++)
        if (!strcmp(p->sp[s].name, sp.name))
            return mote_call_fail(err, c, -1, MOTE_EINVAL, "species: '%s' exists already",
                                  sp.name);
    if (p->nsp == MOTE_CH_MAX_SPECIES)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "species: at most %d species",
                              MOTE_CH_MAX_SPECIES);
    p->sp[p->nsp++] = sp;
    return MOTE_OK;
}

static int check_species(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    int rc = apply_species(&m->plasma, c, err);
    if (!rc)
        m->have_plasma = m->plasma.nsp > 0;
    return rc;
}
static int run_species(void *vm, const mote_call *c, mote_err *err)
{
    ((ch_model *)vm)->diagnosed = 0;
    return apply_species(&((ch_model *)vm)->plasma, c, err);
}

static int apply_maxwellian(mote_ch_plasma *p, const mote_call *c, mote_err *err)
{
    const char *name = mote_call_opt(c, "species")->text;
    for (int s = 0; s < p->nsp; s++)
        if (!strcmp(p->sp[s].name, name)) {
            mote_ch_species *sp = &p->sp[s];
            if (sp->ncomp == MOTE_CH_MAX_COMPONENTS)
                return mote_call_fail(err, c, -1, MOTE_EINVAL, "maxwellian: at most %d "
                                      "components a species", MOTE_CH_MAX_COMPONENTS);
            sp->n[sp->ncomp] = mote_call_opt(c, "density")->r;
            sp->kT[sp->ncomp++] = mote_call_opt(c, "temperature")->r;
            return MOTE_OK;
        }
    return mote_call_fail(err, c, mote_call_opt_index(c, "species"), MOTE_EINVAL,
                          "maxwellian: no species '%s' (add it with species name=...)", name);
}
static int check_maxwellian(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    int rc = apply_maxwellian(&m->plasma, c, err);
    if (!rc)
        m->have_plasma = 1;
    return rc;
}
static int run_maxwellian(void *vm, const mote_call *c, mote_err *err)
{
    ((ch_model *)vm)->diagnosed = 0;
    return apply_maxwellian(&((ch_model *)vm)->plasma, c, err);
}

static int run_plasma(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    int rc = mote_ch_plasma_preset(&m->plasma, c->args[1].text, mote_call_opt_r(c, "n", 0),
                                   mote_call_opt_r(c, "kT", 0), err);
    m->diagnosed = 0;
    const mote_arg *dr = mote_call_opt(c, "drift");
    if (!rc && dr) { /* the plasma flows past the body: every species drifts alike */
        for (int s = 0; s < m->plasma.nsp; s++)
            memcpy(m->plasma.sp[s].drift, dr->v, sizeof dr->v);
    }
    if (rc || !m->log)
        return rc;
    for (int s = 0; s < m->plasma.nsp; s++) {
        const mote_ch_species *sp = &m->plasma.sp[s];
        for (int k = 0; k < sp->ncomp; k++)
            fprintf(m->log, "plasma: %s component %d: n %.6g m^-3, kT %.6g eV, j0 %.5e A/m^2, "
                            "mean speed %.5e m/s\n",
                    sp->name, k + 1, sp->n[k], sp->kT[k], mote_ch_j0(sp->n[k], sp->kT[k], sp->m, sp->Z),
                    mote_ch_mean_speed(sp->kT[k], sp->m));
    }
    fprintf(m->log, "plasma: Debye length %.5g m\n", mote_ch_debye(&m->plasma));
    return MOTE_OK;
}

/* ---- body ----------------------------------------------------------------------------------- */

/* `body KIND`: one table row per kind (its options are the row's), in this order */
static const char *const BODY_KINDS[] = {"sphere", "icosphere", "uvsphere", "box", "twocubes",
                                         "load", "capacitance", NULL};
static int body_kind(const mote_call *c)
{
    int k = 0;
    while (BODY_KINDS[k] && strcmp(BODY_KINDS[k], c->name + 5)) /* ("body KIND") */
        k++;
    return k;
}

/* `body capacitance value=auto|solve|F` (spec 4.3): the capacitance, F > 0, or 0 for auto
 * and solve (value=r>0{auto|solve}: word 1 auto, 2 solve) */
enum { CAP_AUTO = 1, CAP_SOLVE = 2 };
static double capacitance_value(const mote_call *c)
{
    const mote_arg *a = mote_call_opt(c, "value");
    return a->word ? 0 : a->r;
}

static int check_body(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    const int k = body_kind(c);
    const char *kind = BODY_KINDS[k];
    if (k == 6) { /* the capacitance of the body there is (spec 4.3) */
        if (!m->have_body)
            return mote_call_fail(err, c, -1, MOTE_EINVAL, "body capacitance: give the body first");
        if (m->have_sphere && mote_call_opt(c, "value")->word != CAP_AUTO)
            return mote_call_fail(err, c, -1, MOTE_EINVAL, "body capacitance: the exact sphere's "
                                  "capacitance is 4 pi eps0 a (its field is exact)");
        return MOTE_OK;
    }
    if (k == 5) {
        mote_ch_load_opts o;
        if (m->have_sphere)
            return mote_call_fail(err, c, -1, MOTE_EINVAL, "body load: the body is the exact "
                                  "sphere, which takes no other parts");
        int rc = mote_mesh_call_opts(c, "body load", &o, err);
        if (rc)
            return rc;
        mote_err e2 = {0};
        if (strcmp(o.format, "plain") != 0 && mote_mesh_precheck(mote_call_opt(c, "file")->path, &e2))
            return mote_call_fail(err, c, mote_call_opt_index(c, "file"), e2.code, "body load: %s",
                                  e2.msg);
        m->have_body = 1;
        return MOTE_OK;
    }
    const mote_arg *size = mote_call_opt(c, "size");
    if (k == 3 && !(size->v[0] > 0 && size->v[1] > 0 && size->v[2] > 0))
        return mote_call_fail(err, c, mote_call_opt_index(c, "size"), MOTE_EINVAL,
                              "body box: size=SX,SY,SZ: three lengths > 0 (m)");
    if ((k == 0 && m->have_body) || (k > 0 && m->have_sphere))
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "body %s: the exact sphere is a body "
                              "on its own (no other parts)", kind);
    m->have_sphere |= k == 0;
    /* the triangles asked for, against the body's limit and the machine's memory */
    const mote_arg *o1 = mote_call_opt(c, k == 2 ? "nlon" : "subdiv"), *o2 = mote_call_opt(c, "nlat");
    const double n1 = o1 ? (double)o1->i : k == 2 ? 100 : 1, n2 = o2 ? (double)o2->i : 50;
    double ntri = 0;
    if (k == 2)
        ntri = 2.0 * n1 * (n2 - 1);
    else if (k == 3)
        ntri = 12.0 * n1 * n1;
    if (ntri > MOTE_CH_MAX_TRI)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "body %s: %.3g triangles (at most %g, "
                              "about %.3g GB)", kind, ntri, (double)MOTE_CH_MAX_TRI,
                              ntri * MOTE_CH_TRI_BYTES / 1e9);
    mote_err e2 = {0};
    if (mote_mem_check(ntri * MOTE_CH_TRI_BYTES, "the body's triangles", &e2))
        return mote_call_fail(err, c, -1, e2.code, "body %s: %s", kind, e2.msg);
    m->have_body = 1;
    return MOTE_OK;
}

static int run_body(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    const char *kind = BODY_KINDS[body_kind(c)];
    const double r = mote_call_opt_r(c, "radius", 1);
    const mote_arg *a;
    int rc;
    /* an integer option, or its default */
#define OPT_I(key, dflt) ((a = mote_call_opt(c, key)) != NULL ? (int)a->i : (dflt))
    if (strcmp(kind, "capacitance") == 0) {
        double C = capacitance_value(c);
        mote_ch_geometry g;
        mote_ch_body_geometry(&m->body, &g);
        if (mote_call_opt(c, "value")->word == CAP_SOLVE) {
            mote_ch_bem f;
            rc = mote_ch_bem_solve(&m->body, c->ctx->threads, c->ctx, "solve", &f, err);
            if (rc) {
                char why[sizeof err->msg];
                snprintf(why, sizeof why, "%s", err->msg);
                return mote_call_fail(err, c, mote_call_opt_index(c, "value"), (mote_status)rc,
                                      "body capacitance: %s", why);
            }
            C = f.capacitance;
            mote_ch_bem_free(&f);
            if (m->log)
                fprintf(m->log, "body capacitance: solved by boundary elements on %u panels: C "
                                "= %.10g F = 4 pi eps0 x %.10g m (the equal-area sphere's: %.10g "
                                "m)\n", m->body.ntri, C, C / (4 * MOTE_CH_PI * MOTE_CH_EPS0),
                        g.r_eq);
        }
        const int vi = mote_call_opt_index(c, "value");
        const int given = mote_call_opt(c, "value")->word == 0; /* (a solve has its own
                                                                  * error, O(h^2): bem.c) */
        if (given && C > g.c_max * (1 + 1e-12))
            return mote_call_fail(err, c, vi, MOTE_EINVAL,
                                  "body capacitance: C = %.6g F is above the body's rigorous "
                                  "bound 4 pi eps0 R_bound = %.6g F (the ball of R_bound = %.6g "
                                  "m about its centre holds it, and a body inside another has "
                                  "the smaller capacitance)", C, g.c_max, g.r_bound);
        const double c_vol = 4 * MOTE_CH_PI * MOTE_CH_EPS0 * cbrt(3 * g.volume / (4 * MOTE_CH_PI));
        if (given && C < g.c_min * (1 - 1e-12))
            return mote_call_fail(err, c, vi, MOTE_EINVAL,
                                  "body capacitance: C = %.6g F is below the body's rigorous "
                                  "bound %.6g F (%s)", C, g.c_min,
                                  g.c_min > c_vol * (1 + 1e-12)
                                      ? "8 eps0 r_in of the disk inscribed in its largest "
                                        "triangle, which it holds"
                                      : "the sphere of its volume, which has the least "
                                        "capacitance of all bodies of that volume");
        m->body.capacitance = C;
        if (m->log) {
            mote_ch_body_geometry(&m->body, &g);
            fprintf(m->log, "body: capacitance %.10g F (%s), field radius R_f %.10g m\n",
                    g.capacitance,
                    mote_call_opt(c, "value")->word == CAP_SOLVE ? "solved"
                    : m->body.capacitance > 0                    ? "given"
                                                 : "auto: 4 pi eps0 R_eq, within the bounds",
                    g.r_field);
        }
        return MOTE_OK;
    }
    ch_field_drop(m); /* (a new body: its field is solved again when used) */
    if (strcmp(kind, "sphere") == 0)
        rc = mote_ch_body_sphere(&m->body, r, err);
    else if (strcmp(kind, "icosphere") == 0)
        rc = mote_ch_body_icosphere(&m->body, r, OPT_I("level", 4), err);
    else if (strcmp(kind, "uvsphere") == 0)
    {
        const int nlon = OPT_I("nlon", 100), nlat = OPT_I("nlat", 50);
        const mote_arg *pa = mote_call_opt(c, "parts");
        rc = mote_ch_body_uvsphere(&m->body, r, nlon, nlat, pa && pa->i == 1, err);
    }
    else if (strcmp(kind, "load") == 0) {
        mote_ch_load_opts o;
        mote_ch_load_report rep;
        rc = mote_mesh_call_opts(c, "body load", &o, err);
        if (!rc)
            rc = mote_ch_body_load(&m->body, mote_call_opt(c, "file")->path, &o, &rep, err);
        if (rc) { /* the file's name and line are in the message; the command's place too */
            char why[sizeof err->msg];
            snprintf(why, sizeof why, "%s", err->msg);
            return mote_call_fail(err, c, mote_call_opt_index(c, "file"), (mote_status)rc,
                                  "body load: %s", why);
        }
        if (m->log)
            mote_mesh_report_line(m->log, "body load", mote_call_opt(c, "file")->path, &rep);
    } else if (strcmp(kind, "box") == 0) {
        double centre[3] = {0, 0, 0};
        rc = mote_ch_body_box(&m->body, mote_call_opt(c, "size")->v, centre, OPT_I("subdiv", 1),
                              err);
    } else
        rc = mote_ch_body_twocubes(&m->body, mote_call_opt_r(c, "side", 1),
                                   mote_call_opt_r(c, "gap", 1), err);
#undef OPT_I
    if (rc)
        return rc;
    mote_ch_result_free(&m->res);
    m->have_run = 0;
    m->diagnosed = 0;
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    /* Embree traces in single precision: bodies far from a metre lose their hits (a cube of
     * 1e-15 m: 0.32 of the 0.58 hit fraction; 1e19 m: none; exact from 1e-12 to 1e15 m) */
    if (!m->body.sphere && !(g.r_bound >= MOTE_CH_SIZE_MIN && g.r_bound <= MOTE_CH_SIZE_MAX))
        return mote_fail(err, MOTE_EINVAL, "body %s: the body's size R_bound = %g m is outside "
                         "%g ... %g m, the range that traces correctly (Embree works in single "
                         "precision): check units= and scale=", kind, g.r_bound,
                         MOTE_CH_SIZE_MIN, MOTE_CH_SIZE_MAX);
    if (m->log) {
        fprintf(m->log, "body: %u triangles, area %.10g m^2, R_eq %.10g m, R_bound %.10g m, "
                        "C %.10g F\n", m->body.sphere ? 0 : m->body.ntri, g.area, g.r_eq,
                g.r_bound, g.capacitance);
        if (!m->body.sphere && m->body.capacitance <= 0 && g.r_eq > g.r_bound)
            fprintf(m->log, "body: warning: the sphere of equal area (R_eq = %.6g m) is larger "
                            "than the ball of R_bound = %.6g m that holds the body (a thin or "
                            "concave body), whose capacitance 4 pi eps0 R_bound = %.6g F bounds "
                            "the body's: C is that bound, and the whole body lies inside the "
                            "field-free sphere R_f = R_bound; charged runs reach it on straight "
                            "chords (docs/charging.md); body capacitance value= sets C if it is "
                            "known\n", g.r_eq, g.r_bound, g.c_max);
    }
    return MOTE_OK;
}

/* ---- injector ------------------------------------------------------------------------------- */

static int check_injector(void *vm, const mote_call *c, mote_err *err)
{
    const int box = c->args[0].i == 1; /* sphere|box */
    if (box && mote_call_opt(c, "radius"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "radius"), MOTE_EINVAL,
                              "injector box: radius= is for the sphere (give margin= or margin_m=)");
    if (!box && (mote_call_opt(c, "margin") || mote_call_opt(c, "margin_m")))
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "injector sphere: margin= and margin_m= "
                              "are for the box");
    return MOTE_OK; /* (radius= is a length > 0 or auto|debye|thesis: the table's) */
}
static int run_injector(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    const mote_arg *r = mote_call_opt(c, "radius");
    snprintf(m->radius, sizeof m->radius, "%s", r ? r->text : "auto");
    enum { INJECT_SPHERE, INJECT_BOX }; /* e{sphere|box} */
    m->box = c->args[0].i == INJECT_BOX;
    m->margin = mote_call_opt_r(c, "margin", 0.05);
    m->margin_m = mote_call_opt_r(c, "margin_m", 0);
    return MOTE_OK;
}

/* The injection radius (spec 5.2): auto = 1.05 R_bound (at least 1.05 R_eq), the Debye length,
 * the thesis's 131.41 m, or a length. */
double ch_injection_radius(const ch_model *m, const mote_ch_geometry *g)
{
    if (strcmp(m->radius, "auto") == 0)
        return 1.05 * fmax(g->r_bound, g->r_field);
    if (strcmp(m->radius, "debye") == 0)
        return mote_ch_debye(&m->plasma);
    if (strcmp(m->radius, "thesis") == 0)
        return 131.41;
    return strtod(m->radius, NULL);
}

/* ---- field and bfield (spec 6.1, 3.4) ---- */

static int apply_field(ch_model *m, const mote_call *c, mote_err *err)
{
    const char *w = c->args[0].text; /* none|sphere|solved */
    if (m->faithful && strcmp(w, "none"))
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "field %s: faithful mode has no field "
                              "(the thesis's scope, spec 1.2); use model charging", w);
    if (strcmp(w, "solved") && mote_call_opt(c, "theta"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "theta"), MOTE_EINVAL,
                              "field %s: theta= is the solved field's (field solved theta=)", w);
    m->field_off = !strcmp(w, "none");
    m->field_solved = !strcmp(w, "solved");
    const double theta = mote_call_opt_r(c, "theta", 0.4);
    const int mode = mote_call_word(c, "cache", 0) == 1; /* off|on */
    if ((theta != m->theta || mode != m->fcache_mode) && m->ftree) { /* a new tree and cache
                                                                     * for the same solution */
        mote_ch_ftree_free(m->ftree);
        m->ftree = NULL;
        ch_fcache_free(m->fcache);
        m->fcache = NULL;
    }
    m->theta = theta;
    m->fcache_mode = mode;
    return MOTE_OK;
}

void ch_field_drop(ch_model *m)
{
    mote_ch_ftree_free(m->ftree);
    m->ftree = NULL;
    ch_fcache_free(m->fcache);
    m->fcache = NULL;
    mote_ch_bem_free(&m->fbem);
}

/* The paths' cache of the solved field, over the default injection sphere (fcache.c). */
static int field_cache(ch_model *m, const mote_call *c, mote_err *err)
{
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    const double t0 = mote_wall_seconds();
    ch_fcache_free(m->fcache);
    m->fcache = ch_fcache_build(&m->body, &m->fbem, m->theta, g.centre,
                                CH_FCACHE_REACH * g.r_bound, g.r_bound / CH_FCACHE_CELLS,
                                CH_FCACHE_TOL, CH_FCACHE_MAX_BYTES, c->ctx->threads, err);
    if (!m->fcache)
        return mote_call_fail(err, c, -1, err->code, "%s: %s", c->name, err->msg);
    long nk, nt;
    size_t bytes;
    ch_fcache_stats(m->fcache, &nk, &nt, &bytes);
    if (m->log)
        fprintf(m->log, "field solved: the paths' cache: %ld cells interpolated, %ld left to "
                        "the tree (cells of %.3g m and up, tolerance %g), %.3g s, %.3g MB\n", nk,
                nt, g.r_bound / CH_FCACHE_CELLS, CH_FCACHE_TOL, mote_wall_seconds() - t0,
                bytes / 1e6);
    return MOTE_OK;
}

int ch_field_prepare(ch_model *m, const mote_call *c, mote_err *err)
{
    if (!m->field_solved || m->field_off || m->faithful || m->body.sphere)
        return MOTE_OK;
    /* the paths' cache: cache=on */
    const int want_cache = m->fcache_mode == 1;
    if (m->ftree && (m->fcache || !want_cache)) { /* (a later `body capacitance` does not
                                                  * replace the solved one) */
        m->body.capacitance = m->fbem.capacitance;
        return MOTE_OK;
    }
    if (m->ftree)
        return field_cache(m, c, err);
    double t0 = mote_wall_seconds(), t1 = t0;
    if (!m->fbem.sigma) {
        /* the conductors: the frame (the triangles of no dielectric part), then each
         * dielectric part, those with triangles */
        int *cond = NULL, nc = 1;
        if (m->ndiel > 0) {
            int count[CH_MAX_PATCHES + 1] = {0}, idx[CH_MAX_PATCHES + 1];
            if (!(cond = malloc((size_t)m->body.ntri * sizeof *cond)))
                return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", c->name);
            for (uint32_t i = 0; i < m->body.ntri; i++) {
                const char *name = m->body.part_name[m->body.part[i]];
                int s = 0;
                for (int p = 0; p < m->ndiel && !s; p++)
                    if (!strcmp(name, m->diel[p].part))
                        s = 1 + p;
                cond[i] = s;
                count[s]++;
            }
            nc = 0;
            for (int s = 0; s <= m->ndiel; s++)
                if (count[s]) {
                    idx[s] = nc;
                    m->fstate[nc++] = s;
                }
            for (uint32_t i = 0; i < m->body.ntri; i++)
                cond[i] = idx[cond[i]];
        } else {
            m->fstate[0] = 0;
        }
        int rc = mote_ch_bem_solve_conductors(&m->body, cond, nc, c->ctx->threads, c->ctx, "solve",
                                              &m->fbem, err);
        free(cond);
        if (rc) {
            char why[sizeof err->msg];
            snprintf(why, sizeof why, "%s", err->msg);
            return mote_call_fail(err, c, -1, (mote_status)rc, "%s: the solved field (field "
                                  "solved): %s", c->name, why);
        }
        t1 = mote_wall_seconds();
    }
    m->ftree = mote_ch_ftree_build(&m->body, m->fbem.sigma, m->theta, err);
    if (!m->ftree)
        return mote_call_fail(err, c, -1, err->code, "%s: %s", c->name, err->msg);
    m->body.capacitance = m->fbem.capacitance;
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    if (m->log)
        fprintf(m->log, "field solved: %u panels, C = %.10g F (R_f %.10g m; the equal-area "
                        "sphere's R_eq %.10g m); solve %.3g s, %.3g MB; tree theta %g, %.3g s, "
                        "%.3g MB\n", m->body.ntri, m->fbem.capacitance, g.r_field, g.r_eq,
                t1 - t0, mote_ch_bem_bytes(m->body.ntri) / 1e6, m->theta,
                mote_wall_seconds() - t1, mote_ch_ftree_bytes(m->ftree) / 1e6);
    if (want_cache) {
        const int rc = field_cache(m, c, err);
        if (rc)
            return rc;
    }
    if (m->log && m->ndiel > 0) { /* the conductors' capacitance matrix */
        const int nc = m->fbem.nc;
        fprintf(m->log, "field solved: the capacitance matrix (F; the charge on the row's "
                        "conductor per volt on the column's, the others at 0):");
        for (int k = 0; k < nc; k++)
            fprintf(m->log, " %s", m->fstate[k] ? m->diel[m->fstate[k] - 1].part : "frame");
        fputc('\n', m->log);
        for (int k = 0; k < nc; k++) {
            fprintf(m->log, "field solved:   %-12s",
                    m->fstate[k] ? m->diel[m->fstate[k] - 1].part : "frame");
            for (int l = 0; l < nc; l++)
                fprintf(m->log, " %13.6e", m->fbem.cmat[k * nc + l]);
            fputc('\n', m->log);
        }
    }
    return MOTE_OK;
}
static int check_field(void *vm, const mote_call *c, mote_err *err)
{
    return apply_field(vm, c, err);
}
static int run_field(void *vm, const mote_call *c, mote_err *err)
{
    return apply_field(vm, c, err);
}

static int run_bfield(void *vm, const mote_call *c, mote_err *err)
{
    ((ch_model *)vm)->bfield = mote_call_opt_r(c, "B", 0);
    ((ch_model *)vm)->diagnosed = 0;
    return MOTE_OK;
}

/* The validity diagnostics of spec 3.4 (warnings only): a thin sheath (Debye length below
 * 5 R_bound), Larmor radii below 10 R_bound (with `bfield`), kT/(m c^2) above 0.02. Printed on
 * the diagnostic stream before the first run, float or evolve of a plasma and body. */
void ch_diagnose(ch_model *m, const char *cmd)
{
    if (m->dry || m->diagnosed)
        return;
    m->diagnosed = 1; /* once, until the plasma, the body or bfield change */
    /* the lines go to a memory stream (kept for the summary files), then to the diagnostics */
    free(m->warnings);
    m->warnings = NULL;
    size_t wlen = 0;
    FILE *w = open_memstream(&m->warnings, &wlen);
    if (!w)
        return;
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    const double ld = mote_ch_debye(&m->plasma), c2 = 299792458.0 * 299792458.0;
    if (ld < 5 * g.r_bound)
        fprintf(w, "%s: warning: the Debye length %.4g m is below 5 R_bound = %.4g m: a thin "
                   "sheath, where the vacuum-field (OML) model of spec 6 does not hold\n",
                cmd, ld, 5 * g.r_bound);
    for (int s = 0; s < m->plasma.nsp; s++) {
        const mote_ch_species *sp = &m->plasma.sp[s];
        for (int k = 0; k < sp->ncomp; k++) {
            const double E = sp->kT[k] * MOTE_CH_E, v = sqrt(2 * E / sp->m);
            const double rl = m->bfield > 0 ? sp->m * v / (abs(sp->Z) * MOTE_CH_E * m->bfield) : 0;
            if (m->bfield > 0 && rl < 10 * g.r_bound)
                fprintf(w, "%s: warning: %s component %d: Larmor radius %.4g m in B = %g T is "
                           "below 10 R_bound = %.4g m (the model has no magnetic field)\n",
                        cmd, sp->name, k + 1, rl, m->bfield, 10 * g.r_bound);
            if (E / (sp->m * c2) > 0.02)
                fprintf(w, "%s: warning: %s component %d: kT/(m c^2) = %.3g > 0.02 (the model is "
                           "not relativistic; expect errors of a few per cent)\n",
                        cmd, sp->name, k + 1, E / (sp->m * c2));
        }
    }
    fclose(w);
    if (m->ctx && m->ctx->diag && ch_mpi_rank(m->ctx->solo) == 0 && m->warnings)
        fputs(m->warnings, m->ctx->diag);
}

/* ---- sun (spec 6.8) ---- */

/* `sun off`, or `sun [on] direction=X,Y,Z [intensity=1]` (the options from the table). */
static int apply_sun(ch_model *m, const mote_call *c, mote_err *err)
{
    const mote_arg *light = mote_call_opt(c, "light"), *dir = mote_call_opt(c, "direction");
    if (light && light->i == 1) { /* off */
        if (c->nopts > 1)
            return mote_call_fail(err, c, -1, MOTE_EINVAL, "sun off: takes no options");
        m->sun = 0;
        return MOTE_OK;
    }
    if (!dir)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "sun: give direction=X,Y,Z (or 'sun off')");
    const double n = sqrt(dir->v[0] * dir->v[0] + dir->v[1] * dir->v[1] + dir->v[2] * dir->v[2]);
    if (!(n > 0) || !isfinite(n))
        return mote_call_fail(err, c, mote_call_opt_index(c, "direction"), MOTE_EINVAL,
                              "sun: direction: expected X,Y,Z toward the sun, not all 0, found "
                              "'%s'", dir->text);
    if (m->faithful)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "sun: faithful mode has no emission (the "
                              "thesis's scope, spec 1.2); use model charging");
    m->sun = 1;
    for (int a = 0; a < 3; a++)
        m->sun_dir[a] = dir->v[a] / n;
    m->sun_int = mote_call_opt_r(c, "intensity", 1);
    return MOTE_OK;
}
static int check_sun(void *vm, const mote_call *c, mote_err *err)
{
    return apply_sun(vm, c, err);
}
static int run_sun(void *vm, const mote_call *c, mote_err *err)
{
    return apply_sun(vm, c, err);
}

/* ---- integrator (spec 6.3) ---- */

static int check_integrator(void *vm, const mote_call *c, mote_err *err)
{
    const mote_arg *n = mote_call_opt(c, "max_steps");
    if (n && (n->r != floor(n->r) || n->r > 1e12))
        return mote_call_fail(err, c, mote_call_opt_index(c, "max_steps"), MOTE_EINVAL,
                              "integrator: max_steps must be a whole number (1 ... 1e12)");
    return MOTE_OK;
}

static int run_integrator(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    m->eta = mote_call_opt_r(c, "eta", 0.01);
    m->max_steps = (long)mote_call_opt_r(c, "max_steps", 1e5);
    return MOTE_OK;
}

/* ---- materials (spec 6.7, 6.9) ----------------------------------------------------------------- */

/* The material called name: a defined one, else a preset; 0 when found. */
static int find_material(const ch_model *m, const char *name, mote_ch_material *out)
{
    for (int k = m->ndefined - 1; k >= 0; k--)
        if (!strcmp(m->defined[k].name, name)) {
            *out = m->defined[k];
            return 0;
        }
    return mote_ch_material_preset(name, out);
}

/* Whether the body has a part called name. */
static int has_part(const ch_model *m, const char *name)
{
    if (m->body.sphere)
        return strcmp(name, "sphere") == 0;
    for (int k = 0; k < m->body.nparts; k++)
        if (strcmp(m->body.part_name[k], name) == 0)
            return 1;
    return 0;
}

/* `material define` and `material assign`: a table row each; the same function for the dry and
 * the real model (the materials so far are part of what later commands check). */
static int material_define(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    {
        const mote_arg *n = mote_call_opt(c, "name");
        if (!*n->text || strlen(n->text) >= sizeof m->defined[0].name)
            return mote_call_fail(err, c, mote_call_opt_index(c, "name"), MOTE_EINVAL, "material define: give name= (1 to %d "
                                  "characters)", (int)sizeof m->defined[0].name - 1);
        if (m->ndefined == (int)(sizeof m->defined / sizeof m->defined[0]))
            return mote_call_fail(err, c, -1, MOTE_EINVAL, "material define: at most %d materials",
                                  m->ndefined);
        mote_ch_material x;
        if (find_material(m, n->text, &x)) { /* new: no emission unless given */
            memset(&x, 0, sizeof x);
            x.see_emax = 1;
            x.ion_emax = 1;
            x.kT_s = 2;
            x.kT_ph = 2;
        }
        snprintf(x.name, sizeof x.name, "%s", n->text);
        x.see_dmax = mote_call_opt_r(c, "see_dmax", x.see_dmax);
        x.see_emax = mote_call_opt_r(c, "see_emax", x.see_emax);
        x.photo_j = mote_call_opt_r(c, "photo_j", x.photo_j);
        x.kT_s = mote_call_opt_r(c, "see_kT", x.kT_s);
        x.kT_ph = mote_call_opt_r(c, "photo_kT", x.kT_ph);
        x.ion_dmax = mote_call_opt_r(c, "ion_dmax", x.ion_dmax);
        x.ion_emax = mote_call_opt_r(c, "ion_emax", x.ion_emax);
        x.Z = mote_call_opt_r(c, "Z", x.Z);
        x.eps_r = mote_call_opt_r(c, "eps_r", x.eps_r);
        x.sigma = mote_call_opt_r(c, "sigma", x.sigma);
        snprintf(x.source, sizeof x.source, "defined"); /* (its values are the script's now) */
        const mote_arg *a;
        if ((a = mote_call_opt(c, "see_law"))) /* universal|sternglass|range */
            x.see_law = (int)a->i;
        if ((a = mote_call_opt(c, "see_angle"))) /* none|sec */
            x.see_angle = (int)a->i;
        static const char *const rkey[4] = {"see_r1", "see_n1", "see_r2", "see_n2"};
        for (int k = 0; k < 4; k++)
            x.see_r[k] = mote_call_opt_r(c, rkey[k], x.see_r[k]);
        if (x.see_angle && x.see_law)
            return mote_call_fail(err, c, -1, MOTE_EINVAL, "material define: see_angle=sec is the "
                                  "universal law's angular form, not %s",
                                  x.see_law == 1 ? "Sternglass's" : "the range law's (its angle "
                                  "is its own)");
        if (x.see_law == 2 && mote_ch_see_range_fit(&x, err)) {
            char why[sizeof err->msg];
            snprintf(why, sizeof why, "%s", err->msg);
            return mote_call_fail(err, c, -1, MOTE_EINVAL, "material define: %s", why);
        }
        m->defined[m->ndefined++] = x;
        return MOTE_OK;
    }
}

static int check_backscatter(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    if (m->faithful && c->args[0].i == 0)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "backscatter: faithful mode has no "
                              "emission (the thesis's scope, spec 1.2); use model charging");
    return MOTE_OK;
}

static int run_tracer(void *vm, const mote_call *c, mote_err *err)
{
    ((ch_model *)vm)->embree_only = c->args[0].i != 0; /* auto|embree */
    return MOTE_OK;
}

static int run_backscatter(void *vm, const mote_call *c, mote_err *err)
{
    if (check_backscatter(vm, c, err))
        return MOTE_EINVAL;
    ((ch_model *)vm)->no_backscatter = c->args[0].i != 0; /* on|off */
    return MOTE_OK;
}

/* The material last assigned to part (or to *), or NULL. */
static const mote_ch_material *assigned(const ch_model *m, const char *part)
{
    for (int k = m->nassign - 1; k >= 0; k--)
        if (!strcmp(m->assign[k].part, "*") || !strcmp(m->assign[k].part, part))
            return &m->assign[k].m;
    return NULL;
}

double ch_part_eps(const ch_model *m, const char *part)
{
    const mote_ch_material *x = assigned(m, part);
    return x ? x->eps_r : 0;
}

double ch_part_sigma(const ch_model *m, const char *part)
{
    const mote_ch_material *x = assigned(m, part);
    return x ? x->sigma : 0;
}

double ch_smallest_kT(const ch_model *m)
{
    double s = INFINITY;
    for (int i = 0; i < m->plasma.nsp; i++)
        for (int k = 0; k < m->plasma.sp[i].ncomp; k++)
            s = fmin(s, m->plasma.sp[i].kT[k] / abs(m->plasma.sp[i].Z));
    for (int k = 0; k < m->nassign; k++) {
        const mote_ch_material *x = &m->assign[k].m;
        if (x->see_dmax > 0 || x->ion_dmax > 0)
            s = fmin(s, x->kT_s);
        if (x->photo_j > 0)
            s = fmin(s, x->kT_ph);
    }
    return isfinite(s) ? s : 1;
}

/* `dielectric part=NAME thickness=D [eps_r=E] [sigma=S]` (spec 6.10): the same function for
 * the dry and the real model. */
static int dielectric(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    const mote_arg *part = mote_call_opt(c, "part");
    if (strlen(part->text) >= sizeof m->diel[0].part)
        return mote_call_fail(err, c, mote_call_opt_index(c, "part"), MOTE_EINVAL,
                              "dielectric: a part name longer than %zu characters",
                              sizeof m->diel[0].part - 1);
    if (m->dry && !m->have_body)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "dielectric: give the body first (the "
                              "parts are its parts)");
    if (!m->dry && !has_part(m, part->text))
        return mote_call_fail(err, c, mote_call_opt_index(c, "part"), MOTE_EINVAL,
                              "dielectric: the body has no part '%s' (%s)", part->text,
                              m->body.sphere ? "the exact sphere's part is sphere"
                                             : "see the parts body printed");
    if (m->faithful && !mote_call_opt(c, "eps_r"))
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "dielectric: faithful mode has no "
                              "materials: give eps_r=");
    const double d = mote_call_opt(c, "thickness")->r;
    if (!m->dry) { /* a layer over the surface, thinner than the body */
        mote_ch_geometry g;
        mote_ch_body_geometry(&m->body, &g);
        if (!(d < g.r_bound))
            return mote_call_fail(err, c, mote_call_opt_index(c, "thickness"), MOTE_EINVAL,
                                  "dielectric: thickness %g m is not smaller than the body "
                                  "(R_bound %g m): the layer's capacitance eps0 eps_r A / d "
                                  "is that of a layer over the body's surface", d, g.r_bound);
    }
    int k = 0;
    while (k < m->ndiel && strcmp(m->diel[k].part, part->text))
        k++;
    if (k == CH_MAX_PATCHES)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "dielectric: at most %d dielectric parts",
                              CH_MAX_PATCHES);
    snprintf(m->diel[k].part, sizeof m->diel[k].part, "%s", part->text);
    m->diel[k].d = d;
    m->diel[k].eps_r = mote_call_opt_r(c, "eps_r", 0);
    m->diel[k].sigma = mote_call_opt_r(c, "sigma", -1); /* (-1: the part's material's) */
    if (k == m->ndiel) {
        m->ndiel++;
        if (!m->dry) /* (a new conductor in the solved field: solved again when used) */
            ch_field_drop(m);
    }
    return MOTE_OK;
}

static int material_assign(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    if (m->faithful)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "material assign: faithful mode has no "
                              "emission (the thesis's scope, spec 1.2); use model charging");
    const mote_arg *part = mote_call_opt(c, "part"), *mat = mote_call_opt(c, "material");
    if (strlen(part->text) >= sizeof m->assign[0].part)
        return mote_call_fail(err, c, mote_call_opt_index(c, "part"), MOTE_EINVAL,
                              "material assign: a part name longer than %zu characters",
                              sizeof m->assign[0].part - 1);
    if (m->dry && !m->have_body)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "material assign: give the body first "
                              "(the parts are its parts)");
    if (!m->dry && strcmp(part->text, "*") && !has_part(m, part->text))
        return mote_call_fail(err, c, mote_call_opt_index(c, "part"), MOTE_EINVAL,
                              "material assign: the body has no part '%s' (%s)", part->text,
                              m->body.sphere ? "the exact sphere's part is sphere"
                                             : "the parts are listed by body load");
    mote_ch_material x;
    if (find_material(m, mat->text, &x))
        return mote_call_fail(err, c, mote_call_opt_index(c, "material"), MOTE_EINVAL,
                              "material assign: no material '%s' (the presets bare, aluminium, "
                              "gold, kapton, teflon, cover-glass; the library's al2k, au2k, ka2k, "
                              "te2k, sc2k, gr2k, itoc, blkp; or one made with material define)",
                              mat->text);
    if (m->nassign == (int)(sizeof m->assign / sizeof m->assign[0]))
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "material assign: at most %d assignments",
                              m->nassign);
    snprintf(m->assign[m->nassign].part, sizeof m->assign[0].part, "%s", part->text);
    m->assign[m->nassign++].m = x;
    return MOTE_OK;
}

/* The material of a part (the last assignment that names it or *), or NULL when bare. */
static const mote_ch_material *part_material(const ch_model *m, const char *part)
{
    const mote_ch_material *x = assigned(m, part);
    return x && (x->see_dmax > 0 || x->photo_j > 0 || x->ion_dmax > 0 ||
                 (x->Z > 0 && !m->no_backscatter))
               ? x
               : NULL;
}

/* Per triangle (the exact sphere: one), for a run; NULL when nothing emits. */
int ch_build_tri_materials(ch_model *m, mote_err *err)
{
    free(m->tri_mat);
    m->tri_mat = NULL;
    const uint32_t n = m->body.sphere ? 1 : m->body.ntri;
#define PART_OF(i) (m->body.sphere ? "sphere" : m->body.part_name[m->body.part[i]])
    int any = 0;
    for (uint32_t i = 0; i < n && !any; i++)
        any = part_material(m, PART_OF(i)) != NULL;
    if (!any)
        return MOTE_OK;
    m->tri_mat = malloc((size_t)n * sizeof *m->tri_mat);
    if (!m->tri_mat)
        return mote_fail(err, MOTE_ENOMEM, "out of memory for the materials");
    static const mote_ch_material bare = {"bare", 0, 1, 0, 2, 0, 0, 0, 1, 2, 0, 0, 0, "", {0, 0, 0, 0}, 0, 0};
    for (uint32_t i = 0; i < n; i++) {
        const mote_ch_material *x = part_material(m, PART_OF(i));
        m->tri_mat[i] = x ? x : &bare;
    }
#undef PART_OF
    return MOTE_OK;
}

/* The secondary current (A) the impacts of species s knock out, with its variance. */
int ch_backscatter_in(const ch_model *m)
{
    if (m->faithful || m->no_backscatter || !m->tri_mat)
        return 0;
    const uint32_t n = m->body.sphere ? 1 : m->body.ntri;
    for (uint32_t i = 0; i < n; i++)
        if (m->tri_mat[i]->Z > 0)
            return 1;
    return 0;
}

const char *ch_emitted_words(const ch_model *m, int s)
{
    return m->plasma.sp[s].Z < 0 && ch_backscatter_in(m) ? "secondaries and backscattered "
                                                           "electrons"
                                                         : "secondaries";
}

double ch_species_see(const mote_ch_result *r, int s, double *var)
{
    double see = 0;
    *var = 0;
    for (int k = 0; k < MOTE_CH_MAX_COMPONENTS; k++) {
        see += r->see[s][k];
        *var += r->see_sigma[s][k] * r->see_sigma[s][k];
    }
    return see;
}

/* The curved paths of the last run (spec 6.3): steps, losses, the energy error. */
void ch_report_paths(const ch_model *m, const char *cmd)
{
    const mote_ch_result *r = &m->res;
    if (!m->log || r->steps == 0)
        return;
    const double total = (double)r->ncomp * (double)r->histories;
    fprintf(m->log, "%s: curved paths: %.4g steps per history, %llu lost, largest relative "
                    "energy error %.3g\n", cmd, (double)r->steps / total,
            (unsigned long long)r->lost, r->max_energy_err);
}

/* What the output files are written from: the last run at the potential U. */
ch_output ch_output_of(ch_model *m, const mote_ch_geometry *g, const mote_ch_run_opts *o,
                       double U)
{
    ch_output out = {.prefix = m->prefix,
                     .solo = m->ctx ? m->ctx->solo : 0,
                     .origin = m->origin,
                     .mode = m->faithful ? "faithful" : "full",
                     .seed = m->seed,
                     .plasma = &m->plasma,
                     .body = &m->body,
                     .res = &m->res,
                     .geom = *g,
                     .r_gen = o->r_gen,
                     .potential = U,
                     .threads = o->threads > 1 ? o->threads : 1,
                     .triangles = m->out_triangles,
                     .vtk = m->out_vtk,
                     .png = m->out_png,
                     .ply = m->out_ply,
                     .vtk_binary = m->vtk_binary,
                     .png_w = m->png_w,
                     .png_h = m->png_h,
                     .png_log = m->png_log,
                     .tri_mat = m->tri_mat,
                     .backscatter = ch_backscatter_in(m),
                     .nviews = m->nviews,
                     .views = m->view,
                     .view_names = m->view_name,
                     .warnings = m->warnings,
                     .png_q = m->png_q,
                     .png_sp = m->png_sp};
    memcpy(out.view, m->view[0], sizeof out.view);
    return out;
}


static const mote_cmd ch_commands[] = {
    {"plasma", NULL, "e{preset} e{geo-worst-case|thesis-hot|single} n=r>0 kT=r>0 drift=v3", "plasma preset NAME [n=N] [kT=T] [drift=V]",
     "the plasma environment (a preset of spec 3.2)", HELP_PLASMA, check_plasma, run_plasma},
    {"species", NULL, "@name=s charge=r[-100,100] mass=r>0{electron|proton} amu=r>0 drift=v3",
     "species name=S|clear charge=Z mass=M|amu=A [drift=V]",
     "add a species (or empty the list)", HELP_SPECIES, check_species, run_species},
    {"maxwellian", NULL, "species=s! density=r>0! temperature=r>0!",
     "maxwellian species=S density=N temperature=T", "add a Maxwellian component to a species",
     HELP_MAXWELLIAN, check_maxwellian, run_maxwellian},
    {"body sphere", NULL, "radius=r>0!", "body sphere radius=A",
     "the exact sphere (spec 4.1)", HELP_BODY, check_body, run_body},
    {"body icosphere", NULL, "radius=r>0! level=i[0,8]", "body icosphere radius=A [level=4]",
     "a sphere of triangles by subdivision", HELP_BODY, check_body, run_body},
    {"body uvsphere", NULL, "radius=r>0! nlon=i>=3 nlat=i>=2 parts=e{one|hemispheres}",
     "body uvsphere radius=A [nlon=100] [nlat=50] [parts=one|hemispheres]", "a sphere of triangles by longitude and "
     "latitude", HELP_BODY, check_body, run_body},
    {"body box", NULL, "size=v3! subdiv=i>=1", "body box size=SX,SY,SZ [subdiv=1]",
     "a box of triangles", HELP_BODY, check_body, run_body},
    {"body twocubes", NULL, "side=r>0 gap=r>=0", "body twocubes [side=1] [gap=1]",
     "two cubes side by side (the thesis's test body)", HELP_BODY, check_body, run_body},
    {"body load", NULL,
     "file=f<mesh! " MOTE_MESH_CALL_OPTS,
     "body load file=FILE [options]", "a mesh file (Assimp's formats, or plain triangles)",
     HELP_BODY, check_body, run_body},
    {"body capacitance", NULL, "value=r>0{auto|solve}!", "body capacitance value=auto|solve|F",
     "the body's capacitance (spec 4.3)", HELP_BODY, check_body, run_body},
    {"injector", NULL, "e{sphere|box} radius=r>0{auto|debye|thesis} margin=r>0 margin_m=r>0",
     "injector sphere|box [options]",
     "where histories start", HELP_INJECTOR, check_injector, run_injector},
    {"field", NULL, "e{none|sphere|solved} theta=r(0,1) cache=e{off|on}",
     "field none|sphere|solved [theta=0.4] [cache=off|on]",
     "straight paths, the equivalent sphere's field, or the body's own (solved)",
     HELP_FIELD, check_field, run_field},
    {"bfield", NULL, "B=r>=0!", "bfield B=T", "a magnetic field for the validity warnings only",
     HELP_BFIELD, NULL, run_bfield},
    {"sun", NULL, "@light=e{on|off} direction=v3 intensity=r>=0",
     "sun [on|off] [direction=X,Y,Z] [intensity=1]",
     "light for photoemission (spec 6.8)", HELP_SUN, check_sun, run_sun},
    {"test", NULL, "e{hitprob} particles=r>=1", "test hitprob [particles=1e6]",
     "the hit-probability self-test (spec 10 M3)", HELP_TEST, ch_check_test, ch_run_test},
    {"integrator", NULL, "eta=r(0,1) max_steps=r>=1", "integrator [eta=0.01] [max_steps=1e5]",
     "the curved paths' step and limit (spec 6.3)", HELP_INTEGRATOR, check_integrator,
     run_integrator},
    {"run", NULL, "particles=r>=1 potential=r relerr=r(0,1) max_particles=r>=1",
     "run [particles=N] [relerr=E [max_particles=M]] [potential=0]",
     "Monte Carlo currents to the uncharged body", HELP_RUN, ch_check_run, ch_run_run},
    {"float", NULL, "particles=r>=1 tolerance=r(0,0.1] U0=r replicas=i>=1 roots=e{one|all}",
     "float [particles=N] [tolerance=1e-4] [U0=0] [replicas=1] [roots=one|all]",
     "the floating potential of the charged body", HELP_FLOAT, ch_check_float,
     ch_run_float},
    {"material define", NULL,
     "name=s! see_dmax=r>=0 see_emax=r>0 see_law=e{universal|sternglass|range} see_angle=e{none|sec} see_r1=r>=0 see_n1=r>=0 see_r2=r>=0 see_n2=r>=0 "
     "see_kT=r>0 ion_dmax=r>=0 ion_emax=r>0 photo_j=r>=0 photo_kT=r>0 Z=r[0,100] eps_r=r>=1 "
     "sigma=r>=0",
     "material define name=NAME [options]", "define a material (spec 6.9)", HELP_MATERIAL,
     material_define, material_define},
    {"tracer", NULL, "e{auto|embree}", "tracer auto|embree",
     "how paths meet the body: mote's walk and early exits, or Embree alone", HELP_TRACER, NULL,
     run_tracer},
    {"backscatter", NULL, "e{on|off}", "backscatter on|off",
     "backscattered electrons in the emission (default on)", HELP_BACKSCATTER, check_backscatter,
     run_backscatter},
    {"material assign", NULL, "part=s! material=s!", "material assign part=NAME|* material=NAME",
     "give a part of the body a material (spec 6.9)", HELP_MATERIAL, material_assign,
     material_assign},
    {"dielectric", NULL, "part=s! thickness=r>0! eps_r=r>=1 sigma=r>=0",
     "dielectric part=NAME thickness=D [eps_r=E] [sigma=S]",
     "a part with a surface potential of its own (spec 6.10)", HELP_DIELECTRIC, dielectric,
     dielectric},
    {"output", NULL,
     "prefix=f! timeseries=e{on|off} triangles=e{on|off} vtk=e{on|off} vtk_format=e{ascii|binary} "
     "png=e{on|off} ply=e{on|off} png_view=s png_size=s png_scale=e{linear|log} png_quantity=s "
     "legacy_stdout=e{on|off}",
     "output prefix=P [triangles=on] [vtk=on] [png=on] [ply=off] [png_view=V] [png_size=WxH] "
     "[png_scale=linear|log]",
     "the files of spec 8 after each run (tables, VTK, summary, surface picture)", HELP_OUTPUT,
     ch_check_output, ch_run_output},
    {"monitor", NULL, "@dt=r>0! @file=f>timeseries! format=e{table|csv|jsonl}",
     "monitor dt=T file=FILE [format=table|csv|jsonl]",
     "the time series of every later evolve into FILE, a row every T", HELP_MONITOR,
     ch_run_monitor, ch_run_monitor},
    MOTE_CMD_STOP(monitor, NULL, ch_run_monitor_stop, ch_run_monitor_stop),
    {"evolve", NULL, "time=r>0! dt=r>0 dt_out=r>0 file=f>timeseries U0=r particles=r>=1",
     "evolve time=T [dt=D] [file=FILE] [U0=0] [particles=N]",
     "U(t) of faithful mode (constant currents)", HELP_EVOLVE, ch_check_evolve, ch_run_evolve},
};

const mote_model mote_model_charging = {
    .name = "charging",
    .summary = "spacecraft charging: Monte Carlo plasma currents to a triangle-mesh body",
    .variants = "full|faithful",
    .threaded = 1,
    .cmds = ch_commands,
    .ncmds = sizeof ch_commands / sizeof ch_commands[0],
    .create = model_create,
    .destroy = model_destroy,
    .status = model_status,
    .seed = model_seed,
    .seed_help = "Each history's random numbers are Philox4x32-10 keyed by the seed, with the\n"
                 "history and component as counter (a straight history's first test draws\n"
                 "from SplitMix64 at the same counter): results do not depend on threads.\n",
    .plot_lines = "charging-timeseries:t_s,U_V,sigma_U_V",
    .mpi = 1,
};

