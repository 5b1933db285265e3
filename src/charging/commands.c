/* commands.c: the charging model's script commands (spec 7.4), the part written so far: the
 * plasma presets, the generated bodies, the injection sphere, `run` (straight-line currents at
 * U = 0) and `evolve` in faithful mode (constant currents: Q = I t, U = Q / C). */
#include "mote/charging.h"
#include "mote/datafile.h"

#include "ch.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    mote_context *ctx;
    FILE *log;
    int dry, faithful;
    int have_plasma, have_body, have_sphere; /* what validation knows */
    mote_ch_plasma plasma;
    mote_ch_body body;
    char radius[32];            /* injector sphere radius= (auto, debye, thesis or metres) */
    mote_ch_result res;         /* the last run */
    int have_run;
    uint64_t seed;
    double r_gen_used;          /* the injection radius of the last run */
    int box;                    /* the box injector (spec 5.2) */
    double margin, margin_m;
    int field_off;              /* `field none` (spec 6.1): straight paths whatever U */
    double bfield;              /* `bfield B=` (spec 3.4, diagnostics only), T */
    int diagnosed;              /* the warnings of spec 3.4 printed for this plasma and body */
    char *warnings;             /* their text, for the summary files */
    int sun;                    /* `sun` (spec 6.8): on, the unit vector toward it, intensity */
    double sun_dir[3], sun_int;
    double eta;                 /* `integrator` (spec 6.3): curved paths' step and limit */
    long max_steps;
    /* materials (spec 6.9): the defined ones (presets are found by name) and the assignments,
     * in order (a later one wins) */
    mote_ch_material defined[32];
    int ndefined;
    struct {
        char part[MOTE_CH_NAME_LEN];
        mote_ch_material m;
    } assign[64];
    int nassign;
    const mote_ch_material **tri_mat; /* per triangle, built for a run (NULL: none emits) */
    /* `output`: the files of spec 8 after each run (prefix NULL: none) */
    char *prefix, *origin;
    int out_triangles, out_vtk, out_png, out_ply, png_w, png_h, png_log, vtk_binary;
    int out_timeseries;
    int png_q, png_sp;          /* png_quantity */
    int legacy_stdout;          /* the original's four columns from evolve (spec 8.1) */
    double view[8][3];          /* png_view: the views, and their names for the file names */
    char view_name[8][16];
    int nviews;
    /* validation: the prefix and time-series switch of the last `output`, so that the files
     * `run`, `float` and `evolve` will write are known to the whole-script check */
    char *check_prefix;
    int check_timeseries;
} ch_model;

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
    mote_ch_body_free(&m->body);
    mote_ch_result_free(&m->res);
    free(m->prefix);
    free(m->origin);
    free(m->check_prefix);
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
static int parse3any(const char *t, double v[3])
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

/* size=SX,SY,SZ: three lengths > 0 */
static int parse3(const char *t, double v[3])
{
    return parse3any(t, v) || !(v[0] > 0 && v[1] > 0 && v[2] > 0) ? -1 : 0;
}

/* ---- plasma --------------------------------------------------------------------------------- */

static int check_plasma(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    if (strcmp(c->args[0].text, "preset") != 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "plasma: expected 'preset', found '%s'",
                              c->args[0].text);
    const char *name = c->args[1].text;
    int single = strcmp(name, "single") == 0;
    if (!single && strcmp(name, "geo-worst-case") != 0 && strcmp(name, "thesis-hot") != 0)
        return mote_call_fail(err, c, 1, MOTE_EINVAL, "plasma preset: expected geo-worst-case, "
                              "thesis-hot or single, found '%s'", name);
    if (single && (!mote_call_opt(c, "n") || !mote_call_opt(c, "kT")))
        return mote_call_fail(err, c, 1, MOTE_EINVAL, "plasma preset single: give n= (m^-3) and "
                              "kT= (eV)");
    if (!single && (mote_call_opt(c, "n") || mote_call_opt(c, "kT")))
        return mote_call_fail(err, c, 1, MOTE_EINVAL, "plasma preset %s: n= and kT= are for "
                              "single", name);
    double d[3];
    const mote_arg *dr = mote_call_opt(c, "drift");
    if (dr && parse3any(dr->text, d))
        return mote_call_fail(err, c, mote_call_opt_index(c, "drift"), MOTE_EINVAL,
                              "plasma: drift: expected VX,VY,VZ (m/s), found '%s'", dr->text);
    m->have_plasma = 1;
    mote_err ignored;
    mote_ch_plasma_preset(&m->plasma, name, mote_call_opt_r(c, "n", 1), mote_call_opt_r(c, "kT", 1),
                          &ignored);
    return MOTE_OK;
}

/* ---- species and maxwellian (spec 3.1, 7.4) ------------------------------------------------- */

/* `species clear` or `species name=S charge=Z mass=electron|proton|amu:A|KG [drift=VX,VY,VZ]`
 * (the tokens come as written: the command takes "*"). */
static int parse_species(const mote_call *c, mote_ch_species *sp, int *clear, mote_err *err)
{
    memset(sp, 0, sizeof *sp);
    *clear = c->nargs == 1 && strcmp(c->args[0].text, "clear") == 0;
    if (*clear)
        return MOTE_OK;
    int have[3] = {0, 0, 0};
    for (int k = 0; k < c->nargs; k++) {
        const char *t = c->args[k].text, *eq = strchr(t, '=');
        if (!eq)
            return mote_call_fail(err, c, k, MOTE_EINVAL, "species: expected 'clear' or KEY=VALUE "
                                  "(name=, charge=, mass=, drift=), found '%s'", t);
        const size_t kl = (size_t)(eq - t);
        const char *v = eq + 1;
        char *end;
        if (kl == 4 && !strncmp(t, "name", 4)) {
            if (!*v || strlen(v) >= sizeof sp->name || strpbrk(v, " ,=#"))
                return mote_call_fail(err, c, k, MOTE_EINVAL, "species: name must be 1 to %d "
                                      "characters without spaces, commas or '=', found '%s'",
                                      (int)sizeof sp->name - 1, v);
            snprintf(sp->name, sizeof sp->name, "%s", v);
            have[0] = 1;
        } else if (kl == 6 && !strncmp(t, "charge", 6)) {
            long z = strtol(v, &end, 10);
            if (end == v || *end || z == 0 || z < -100 || z > 100)
                return mote_call_fail(err, c, k, MOTE_EINVAL, "species: charge must be a whole "
                                      "number of elementary charges, not 0 (e.g. -1, 1, 2), found "
                                      "'%s'", v);
            sp->Z = (int)z;
            have[1] = 1;
        } else if (kl == 4 && !strncmp(t, "mass", 4)) {
            if (!strcmp(v, "electron"))
                sp->m = MOTE_CH_ME;
            else if (!strcmp(v, "proton"))
                sp->m = MOTE_CH_MP;
            else if (!strncmp(v, "amu:", 4)) {
                double a = strtod(v + 4, &end);
                sp->m = end != v + 4 && !*end && a > 0 && isfinite(a) ? a * MOTE_CH_AMU : -1;
            } else {
                double kg = strtod(v, &end);
                sp->m = end != v && !*end && kg > 0 && isfinite(kg) ? kg : -1;
            }
            if (!(sp->m > 0))
                return mote_call_fail(err, c, k, MOTE_EINVAL, "species: mass must be electron, "
                                      "proton, amu:A or a mass in kg > 0, found '%s'", v);
            have[2] = 1;
        } else if (kl == 5 && !strncmp(t, "drift", 5)) {
            if (parse3any(v, sp->drift))
                return mote_call_fail(err, c, k, MOTE_EINVAL, "species: drift: expected "
                                      "VX,VY,VZ (m/s), found '%s'", v);
        } else {
            return mote_call_fail(err, c, k, MOTE_EINVAL, "species: unknown option '%.*s' "
                                  "(name, charge, mass, drift)", (int)kl, t);
        }
    }
    if (!have[0] || !have[1] || !have[2])
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "species: give name=, charge= and mass= "
                              "(or 'species clear')");
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
        double d[3];
        parse3any(dr->text, d);
        for (int s = 0; s < m->plasma.nsp; s++)
            memcpy(m->plasma.sp[s].drift, d, sizeof d);
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

static const char *const BODY_KINDS[] = {"sphere", "icosphere", "uvsphere", "box", "twocubes",
                                         "load", "capacitance", NULL};

/* `body capacitance value=auto|F` (spec 4.3): the capacitance, F > 0, or 0 for auto; -1 bad */
static double capacitance_value(const mote_call *c)
{
    const mote_arg *a = mote_call_opt(c, "value");
    if (!a)
        return -1;
    if (!strcmp(a->text, "auto"))
        return 0;
    char *end;
    const double C = strtod(a->text, &end);
    return end != a->text && !*end && C > 0 && isfinite(C) ? C : -1;
}

/* The options of `body load` (spec 7.1-7.3) into o; -1 and a located error when one is bad. */
static int load_opts(const mote_call *c, mote_ch_load_opts *o, mote_err *err)
{
    memset(o, 0, sizeof *o);
    o->format = "auto";
    o->scale = 1;
    o->rot_axis = -1;
    const mote_arg *a;
    if ((a = mote_call_opt(c, "format"))) {
        if (strcmp(a->text, "auto") && strcmp(a->text, "plain") && strcmp(a->text, "assimp"))
            return mote_call_fail(err, c, mote_call_opt_index(c, "format"), MOTE_EINVAL,
                                  "body load: format must be auto, plain or assimp, found '%s'",
                                  a->text);
        o->format = a->text;
    }
    if ((a = mote_call_opt(c, "units"))) {
        static const char *const U[] = {"m", "cm", "mm", "in"};
        static const double F[] = {1, 0.01, 0.001, 0.0254};
        int k = 0;
        while (k < 4 && strcmp(U[k], a->text))
            k++;
        if (k == 4)
            return mote_call_fail(err, c, mote_call_opt_index(c, "units"), MOTE_EINVAL,
                                  "body load: units must be m, cm, mm or in, found '%s'", a->text);
        if (mote_call_opt(c, "scale"))
            return mote_call_fail(err, c, mote_call_opt_index(c, "scale"), MOTE_EINVAL,
                                  "body load: give units= or scale=, not both");
        o->scale = F[k];
    }
    o->scale = mote_call_opt_r(c, "scale", o->scale);
    if ((a = mote_call_opt(c, "offset")) && parse3any(a->text, o->offset))
        return mote_call_fail(err, c, mote_call_opt_index(c, "offset"), MOTE_EINVAL,
                              "body load: offset: expected X,Y,Z (m), found '%s'", a->text);
    if ((a = mote_call_opt(c, "rotate"))) {
        char *end;
        const char ax = a->text[0];
        double deg = a->text[0] && a->text[1] == ',' ? strtod(a->text + 2, &end) : NAN;
        if ((ax != 'x' && ax != 'y' && ax != 'z') || !isfinite(deg) || *end)
            return mote_call_fail(err, c, mote_call_opt_index(c, "rotate"), MOTE_EINVAL,
                                  "body load: rotate: expected AXIS,DEGREES (x, y or z), found "
                                  "'%s'", a->text);
        o->rot_axis = ax - 'x';
        o->rot_deg = deg;
    }
    if ((a = mote_call_opt(c, "strict"))) {
        if (strcmp(a->text, "yes") && strcmp(a->text, "no"))
            return mote_call_fail(err, c, mote_call_opt_index(c, "strict"), MOTE_EINVAL,
                                  "body load: strict must be yes or no, found '%s'", a->text);
        o->strict = a->text[0] == 'y';
    }
    o->part = (a = mote_call_opt(c, "part")) ? a->text : NULL;
    return MOTE_OK;
}

static int check_body(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    const char *kind = c->args[0].text;
    int k = 0;
    while (BODY_KINDS[k] && strcmp(BODY_KINDS[k], kind) != 0)
        k++;
    if (!BODY_KINDS[k])
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "body: expected sphere, icosphere, "
                              "uvsphere, box, twocubes, load or capacitance, found '%s'", kind);
    if (k == 6) { /* the capacitance of the body there is (spec 4.3) */
        if (capacitance_value(c) < 0)
            return mote_call_fail(err, c, mote_call_opt(c, "value") ? mote_call_opt_index(c, "value")
                                                                    : 0,
                                  MOTE_EINVAL, "body capacitance: give value=auto or a "
                                  "capacitance in F > 0");
        if (!m->have_body)
            return mote_call_fail(err, c, 0, MOTE_EINVAL, "body capacitance: give the body first");
        if (m->have_sphere && capacitance_value(c) > 0)
            return mote_call_fail(err, c, 0, MOTE_EINVAL, "body capacitance: the exact sphere's "
                                  "capacitance is 4 pi eps0 a (its field is exact)");
        return MOTE_OK;
    }
    if (mote_call_opt(c, "value"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "value"), MOTE_EINVAL,
                              "body %s: value= is for body capacitance", kind);
    if (k == 5) {
        mote_ch_load_opts o;
        if (!mote_call_opt(c, "file"))
            return mote_call_fail(err, c, 0, MOTE_EINVAL, "body load: give file=FILE");
        if (m->have_sphere)
            return mote_call_fail(err, c, 0, MOTE_EINVAL, "body load: the body is the exact "
                                  "sphere, which takes no other parts");
        int rc = load_opts(c, &o, err);
        if (rc)
            return rc;
        mote_err e2 = {0};
        if (strcmp(o.format, "plain") != 0 && ch_mesh_precheck(mote_call_opt(c, "file")->path, &e2))
            return mote_call_fail(err, c, mote_call_opt_index(c, "file"), e2.code, "body load: %s",
                                  e2.msg);
        m->have_body = 1;
        return MOTE_OK;
    }
    if (mote_call_opt(c, "file"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "file"), MOTE_EINVAL,
                              "body %s: file= is for body load", kind);
    double v[3];
    if (k == 3 && (!mote_call_opt(c, "size") || parse3(mote_call_opt(c, "size")->text, v)))
        return mote_call_fail(err, c, mote_call_opt(c, "size") ? mote_call_opt_index(c, "size") : 0,
                              MOTE_EINVAL, "body box: give size=SX,SY,SZ (three lengths > 0, m)");
    if (k <= 2 && !mote_call_opt(c, "radius"))
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "body %s: give radius= (m)", kind);
    if ((k == 0 && m->have_body) || (k > 0 && m->have_sphere))
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "body %s: the exact sphere is a body "
                              "on its own (no other parts)", kind);
    m->have_sphere |= k == 0;
    if (k == 1 && mote_call_opt(c, "level") && mote_call_opt(c, "level")->i > 8)
        return mote_call_fail(err, c, mote_call_opt_index(c, "level"), MOTE_EINVAL,
                              "body icosphere: level must be 0 ... 8");
    /* the triangles asked for, against the body's limit and the machine's memory */
    const mote_arg *o1 = mote_call_opt(c, k == 2 ? "nlon" : "subdiv"), *o2 = mote_call_opt(c, "nlat");
    const double n1 = o1 ? (double)o1->i : k == 2 ? 100 : 1, n2 = o2 ? (double)o2->i : 50;
    double ntri = 0;
    if (k == 2)
        ntri = 2.0 * n1 * (n2 - 1);
    else if (k == 3)
        ntri = 12.0 * n1 * n1;
    if (ntri > MOTE_CH_MAX_TRI)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "body %s: %.3g triangles (at most %g, about "
                              "%.3g GB)", kind, ntri, (double)MOTE_CH_MAX_TRI,
                              ntri * MOTE_CH_TRI_BYTES / 1e9);
    mote_err e2 = {0};
    if (mote_mem_check(ntri * MOTE_CH_TRI_BYTES, "the body's triangles", &e2))
        return mote_call_fail(err, c, 0, e2.code, "body %s: %s", kind, e2.msg);
    m->have_body = 1;
    return MOTE_OK;
}

static int run_body(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    const char *kind = c->args[0].text;
    const double r = mote_call_opt_r(c, "radius", 1);
    const mote_arg *a;
    int rc;
    /* an integer option, or its default */
#define OPT_I(key, dflt) ((a = mote_call_opt(c, key)) != NULL ? (int)a->i : (dflt))
    if (strcmp(kind, "capacitance") == 0) {
        m->body.capacitance = capacitance_value(c);
        if (m->log) {
            mote_ch_geometry g;
            mote_ch_body_geometry(&m->body, &g);
            fprintf(m->log, "body: capacitance %.10g F (%s), field radius R_f %.10g m\n",
                    g.capacitance, m->body.capacitance > 0 ? "given" : "auto: 4 pi eps0 R_eq",
                    g.r_field);
        }
        return MOTE_OK;
    }
    if (strcmp(kind, "sphere") == 0)
        rc = mote_ch_body_sphere(&m->body, r, err);
    else if (strcmp(kind, "icosphere") == 0)
        rc = mote_ch_body_icosphere(&m->body, r, OPT_I("level", 4), err);
    else if (strcmp(kind, "uvsphere") == 0)
    {
        const int nlon = OPT_I("nlon", 100), nlat = OPT_I("nlat", 50);
        rc = mote_ch_body_uvsphere(&m->body, r, nlon, nlat, err);
    }
    else if (strcmp(kind, "load") == 0) {
        mote_ch_load_opts o;
        mote_ch_load_report rep;
        rc = load_opts(c, &o, err);
        if (!rc)
            rc = mote_ch_body_load(&m->body, mote_call_opt(c, "file")->path, &o, &rep, err);
        if (rc) { /* the file's name and line are in the message; the command's place too */
            char why[sizeof err->msg];
            snprintf(why, sizeof why, "%s", err->msg);
            return mote_call_fail(err, c, mote_call_opt_index(c, "file"), (mote_status)rc,
                                  "body load: %s", why);
        }
        if (m->log)
            fprintf(m->log, "body load: %u triangles read; %u degenerate and %u duplicate dropped, "
                            "%u vertices welded, %u turned to face outward; %u closed and %u "
                            "open components (open ones are two-sided sheets)%s\n",
                    rep.read, rep.degenerate, rep.duplicates, rep.welded, rep.flipped,
                    rep.closed_components, rep.open_components,
                    rep.abandoned_lines ? "; some lines abandoned (see strict=yes)" : "");
        if (m->log && rep.trailing_numbers)
            fprintf(m->log, "body load: warning: %s ends inside a triangle (%d of 9 numbers, "
                            "dropped; strict=yes makes this an error)\n",
                    mote_call_opt(c, "file")->path, rep.trailing_numbers);
    } else if (strcmp(kind, "box") == 0) {
        double size[3], centre[3] = {0, 0, 0};
        parse3(mote_call_opt(c, "size")->text, size);
        rc = mote_ch_body_box(&m->body, size, centre, OPT_I("subdiv", 1), err);
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
        if (!m->body.sphere && g.r_field > g.r_bound)
            fprintf(m->log, "body: warning: the field's radius R_f = %.6g m exceeds R_bound = "
                            "%.6g m (a thin or concave body: its area makes R_eq large), so the "
                            "whole body lies inside the field-free sphere of R_f; charged runs "
                            "then collect as that sphere's field allows and reach the body on "
                            "straight chords (docs/charging.md); body capacitance value= sets "
                            "C if it is known\n", g.r_field, g.r_bound);
    }
    return MOTE_OK;
}

/* ---- injector ------------------------------------------------------------------------------- */

static int check_injector(void *vm, const mote_call *c, mote_err *err)
{
    const int box = strcmp(c->args[0].text, "box") == 0;
    if (!box && strcmp(c->args[0].text, "sphere") != 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "injector: expected sphere or box, found "
                              "'%s'", c->args[0].text);
    if (box && mote_call_opt(c, "radius"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "radius"), MOTE_EINVAL,
                              "injector box: radius= is for the sphere (give margin= or margin_m=)");
    if (!box && (mote_call_opt(c, "margin") || mote_call_opt(c, "margin_m")))
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "injector sphere: margin= and margin_m= "
                              "are for the box");
    const mote_arg *r = mote_call_opt(c, "radius");
    if (r && strcmp(r->text, "auto") && strcmp(r->text, "debye") && strcmp(r->text, "thesis")) {
        char *end;
        double v = strtod(r->text, &end);
        if (end == r->text || *end || !(v > 0) || !isfinite(v))
            return mote_call_fail(err, c, mote_call_opt_index(c, "radius"), MOTE_EINVAL,
                                  "injector sphere: radius must be auto, debye, thesis or a "
                                  "length > 0 (m), found '%s'", r->text);
    }
    return MOTE_OK;
}
static int run_injector(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    const mote_arg *r = mote_call_opt(c, "radius");
    snprintf(m->radius, sizeof m->radius, "%s", r ? r->text : "auto");
    m->box = strcmp(c->args[0].text, "box") == 0;
    m->margin = mote_call_opt_r(c, "margin", 0.05);
    m->margin_m = mote_call_opt_r(c, "margin_m", 0);
    return MOTE_OK;
}

/* The injection radius (spec 5.2): auto = 1.05 R_bound (at least 1.05 R_eq), the Debye length,
 * the thesis's 131.41 m, or a length. */
static double injection_radius(const ch_model *m, const mote_ch_geometry *g)
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
    const char *w = c->args[0].text;
    if (strcmp(w, "none") && strcmp(w, "sphere"))
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "field: expected none or sphere, found "
                              "'%s'", w);
    if (m->faithful && !strcmp(w, "sphere"))
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "field sphere: faithful mode has no field "
                              "(the thesis's scope, spec 1.2); use model charging");
    m->field_off = !strcmp(w, "none");
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
static void diagnose(ch_model *m, const char *cmd)
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
    if (m->ctx && m->ctx->diag && ch_mpi_rank() == 0 && m->warnings)
        fputs(m->warnings, m->ctx->diag);
}

/* ---- sun (spec 6.8) ---- */

/* `sun off` or `sun direction=X,Y,Z [intensity=1]` (the tokens as written: "*"). */
static int apply_sun(ch_model *m, const mote_call *c, mote_err *err)
{
    if (c->nargs == 1 && !strcmp(c->args[0].text, "off")) {
        m->sun = 0;
        return MOTE_OK;
    }
    double d[3] = {0, 0, 0}, inten = 1;
    int have = 0;
    for (int k = 0; k < c->nargs; k++) {
        const char *t = c->args[k].text;
        char *end;
        if (!strncmp(t, "direction=", 10)) {
            const double n = parse3any(t + 10, d) ? 0 : sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            if (!(n > 0) || !isfinite(n))
                return mote_call_fail(err, c, k, MOTE_EINVAL, "sun: direction: expected X,Y,Z "
                                      "(toward the sun, not all 0), found '%s'", t + 10);
            for (int a = 0; a < 3; a++)
                d[a] /= n;
            have = 1;
        } else if (!strncmp(t, "intensity=", 10)) {
            inten = strtod(t + 10, &end);
            if (end == t + 10 || *end || !(inten >= 0) || !isfinite(inten))
                return mote_call_fail(err, c, k, MOTE_EINVAL, "sun: intensity must be a number "
                                      ">= 0 (1: 1 AU), found '%s'", t + 10);
        } else {
            return mote_call_fail(err, c, k, MOTE_EINVAL, "sun: expected 'off' or direction=X,Y,Z "
                                  "[intensity=I], found '%s'", t);
        }
    }
    if (!have)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "sun: give direction=X,Y,Z (or 'sun off')");
    if (m->faithful)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "sun: faithful mode has no emission (the "
                              "thesis's scope, spec 1.2); use model charging");
    m->sun = 1;
    memcpy(m->sun_dir, d, sizeof d);
    m->sun_int = inten;
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

static int apply_material(ch_model *m, const mote_call *c, mote_err *err)
{
    const char *what = c->args[0].text;
    if (!strcmp(what, "define")) {
        const mote_arg *n = mote_call_opt(c, "name");
        if (!n || !*n->text || strlen(n->text) >= sizeof m->defined[0].name)
            return mote_call_fail(err, c, 0, MOTE_EINVAL, "material define: give name= (1 to %d "
                                  "characters)", (int)sizeof m->defined[0].name - 1);
        if (m->ndefined == (int)(sizeof m->defined / sizeof m->defined[0]))
            return mote_call_fail(err, c, 0, MOTE_EINVAL, "material define: at most %d materials",
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
        const mote_arg *a;
        if ((a = mote_call_opt(c, "see_law"))) {
            if (strcmp(a->text, "universal") && strcmp(a->text, "sternglass"))
                return mote_call_fail(err, c, mote_call_opt_index(c, "see_law"), MOTE_EINVAL,
                                      "material define: see_law must be universal or sternglass, "
                                      "found '%s'", a->text);
            x.see_law = !strcmp(a->text, "sternglass");
        }
        if ((a = mote_call_opt(c, "see_angle"))) {
            if (strcmp(a->text, "none") && strcmp(a->text, "sec"))
                return mote_call_fail(err, c, mote_call_opt_index(c, "see_angle"), MOTE_EINVAL,
                                      "material define: see_angle must be none or sec, found '%s'",
                                      a->text);
            x.see_angle = !strcmp(a->text, "sec");
        }
        if (x.see_angle && x.see_law)
            return mote_call_fail(err, c, 0, MOTE_EINVAL, "material define: see_angle=sec is the "
                                  "universal law's angular form, not Sternglass's");
        m->defined[m->ndefined++] = x;
        return MOTE_OK;
    }
    if (strcmp(what, "assign"))
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "material: expected define or assign, found "
                              "'%s'", what);
    if (m->faithful)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "material assign: faithful mode has no "
                              "emission (the thesis's scope, spec 1.2); use model charging");
    const mote_arg *part = mote_call_opt(c, "part"), *mat = mote_call_opt(c, "material");
    if (!part || !mat)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "material assign: give part=NAME|* and "
                              "material=NAME");
    if (strlen(part->text) >= sizeof m->assign[0].part)
        return mote_call_fail(err, c, mote_call_opt_index(c, "part"), MOTE_EINVAL,
                              "material assign: a part name longer than %zu characters",
                              sizeof m->assign[0].part - 1);
    if (m->dry && !m->have_body)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "material assign: give the body first "
                              "(the parts are its parts)");
    if (!m->dry && strcmp(part->text, "*") && !has_part(m, part->text))
        return mote_call_fail(err, c, mote_call_opt_index(c, "part"), MOTE_EINVAL,
                              "material assign: the body has no part '%s' (%s)", part->text,
                              m->body.sphere ? "the exact sphere's part is sphere"
                                             : "the parts are listed by body load");
    mote_ch_material x;
    if (find_material(m, mat->text, &x))
        return mote_call_fail(err, c, mote_call_opt_index(c, "material"), MOTE_EINVAL,
                              "material assign: no material '%s' (bare, aluminium, gold, kapton, "
                              "teflon, cover-glass, or one made with material define)",
                              mat->text);
    if (m->nassign == (int)(sizeof m->assign / sizeof m->assign[0]))
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "material assign: at most %d assignments",
                              m->nassign);
    snprintf(m->assign[m->nassign].part, sizeof m->assign[0].part, "%s", part->text);
    m->assign[m->nassign++].m = x;
    return MOTE_OK;
}
static int check_material(void *vm, const mote_call *c, mote_err *err)
{
    return apply_material(vm, c, err);
}
static int run_material(void *vm, const mote_call *c, mote_err *err)
{
    return apply_material(vm, c, err);
}

/* The material of a part (the last assignment that names it or *), or NULL when bare. */
static const mote_ch_material *part_material(const ch_model *m, const char *part)
{
    for (int k = m->nassign - 1; k >= 0; k--)
        if (!strcmp(m->assign[k].part, "*") || !strcmp(m->assign[k].part, part))
            return m->assign[k].m.see_dmax > 0 || m->assign[k].m.photo_j > 0 ||
                           m->assign[k].m.ion_dmax > 0
                       ? &m->assign[k].m
                       : NULL;
    return NULL;
}

/* Per triangle (the exact sphere: one), for a run; NULL when nothing emits. */
static int build_tri_materials(ch_model *m, mote_err *err)
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
    static const mote_ch_material bare = {"bare", 0, 1, 0, 2, 0, 0, 0, 1, 2};
    for (uint32_t i = 0; i < n; i++) {
        const mote_ch_material *x = part_material(m, PART_OF(i));
        m->tri_mat[i] = x ? x : &bare;
    }
#undef PART_OF
    return MOTE_OK;
}

/* The secondary current (A) the impacts of species s knock out, with its variance. */
static double species_see(const mote_ch_result *r, int s, double *var)
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
static void report_paths(const ch_model *m, const char *cmd)
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
static ch_output output_of(ch_model *m, const mote_ch_geometry *g, const mote_ch_run_opts *o,
                           double U)
{
    ch_output out = {.prefix = m->prefix,
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
                     .nviews = m->nviews,
                     .views = m->view,
                     .view_names = m->view_name,
                     .warnings = m->warnings,
                     .png_q = m->png_q,
                     .png_sp = m->png_sp};
    memcpy(out.view, m->view[0], sizeof out.view);
    return out;
}

/* ---- run and evolve ------------------------------------------------------------------------- */

/* The run options of a command: the seed, its particles= (default 1e6), the injector, threads. */
static mote_ch_run_opts run_opts(const ch_model *m, const mote_call *c, const mote_ch_geometry *g)
{
    mote_ch_run_opts o = {.seed = m->seed,
                          .particles = (uint64_t)mote_call_opt_r(c, "particles", 1e6),
                          .r_gen = injection_radius(m, g),
                          .threads = c->ctx->threads,
                          .field = !m->faithful && !m->field_off,
                          .box = m->box,
                          .margin = m->margin,
                          .margin_m = m->margin_m,
                          .tri_material = m->tri_mat,
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

static int check_test(void *vm, const mote_call *c, mote_err *err)
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
static int run_test(void *vm, const mote_call *c, mote_err *err)
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

static int check_run(void *vm, const mote_call *c, mote_err *err)
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

static int run_run(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    if (build_tri_materials(m, err))
        return err->code;
    diagnose(m, "run");
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
        const ch_output out = output_of(m, &g, &o, o.field ? o.potential : 0);
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
        const double see = species_see(&m->res, s, &see_v);
        fprintf(m->log, "run: %-4s I = %.10g A +- %.3g (%.3g%%)", m->plasma.sp[s].name,
                m->res.current[s], m->res.sigma[s],
                100 * m->res.sigma[s] / fmax(fabs(m->res.current[s]), 1e-300));
        if (see > 0)
            fprintf(m->log, "; secondaries it knocks out: %+.10g A +- %.3g", see, sqrt(see_v));
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
    report_paths(m, "run");
    return MOTE_OK;
}

static int check_float(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    const mote_arg *ra = mote_call_opt(c, "roots");
    if (ra && strcmp(ra->text, "one") && strcmp(ra->text, "all"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "roots"), MOTE_EINVAL,
                              "float: roots must be one or all, found '%s'", ra->text);
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

static int run_float(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    if (build_tri_materials(m, err))
        return err->code;
    diagnose(m, "float");
    mote_ch_run_opts o = run_opts(m, c, &g); /* (the field on: full mode) */
    o.U0 = mote_call_opt_r(c, "U0", 0);
    mote_ch_tracer *t = mote_ch_tracer_new(&m->body, err);
    if (!t)
        return err->code;
    double U, sU, oml;
    int evals;
    const double tol = mote_call_opt_r(c, "tolerance", 1e-4);
    mote_ch_result_free(&m->res);
    int rc = mote_ch_float(&m->plasma, &m->body, t, &o, tol, &U, &sU, &oml, &evals, &m->res, err);
    /* replicas=k (spec 6.5): the roots for seeds seed+1 ... seed+k-1 as well, their spread */
    const int reps = (int)mote_call_opt_r(c, "replicas", 1);
    double sum = rc ? 0 : U, sq = rc ? 0 : U * U;
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
                if (m->log)
                    fprintf(m->log, "float: a root of I(U) between %g and %g V: %s %.6g V, %s "
                                    "(dI/dU %s 0)\n", grid[k - 1], grid[k],
                            here ? "U_f =" : "about (linear)", Ur,
                            I < Iprev ? "stable" : "unstable", I < Iprev ? "<" : ">");
                nr++;
            }
            Iprev = I;
        }
        if (!rc && m->log)
            fprintf(m->log, "float: %d sign change%s of I(U) at %d potentials from %g to %g V\n",
                    nr, nr == 1 ? "" : "s", ng, grid[0], grid[ng - 1]);
    }
    mote_ch_tracer_free(t);
    if (rc)
        return rc;
    if (reps > 1 && m->log) {
        const double mean = sum / reps, sd = sqrt(fmax(0, (sq - reps * mean * mean) / (reps - 1)));
        fprintf(m->log, "float: %d replicas: mean U_f = %.6g V, standard deviation %.3g V (the "
                        "single run's sigma_U %.3g V)\n", reps, mean, sd, sU);
    }
    m->have_run = 1;
    if (m->prefix) { /* the files at U_f (spec 8.2) */
        ch_output out = output_of(m, &g, &o, U);
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
            const double see = species_see(&m->res, s, &see_v);
            fprintf(m->log, "float: %-4s I = %.6g A +- %.3g at U_f (%.6g A/m^2)",
                    m->plasma.sp[s].name, m->res.current[s], m->res.sigma[s],
                    m->res.current[s] / g.area);
            if (see > 0)
                fprintf(m->log, "; secondaries it knocks out: %+.6g A +- %.3g", see, sqrt(see_v));
            fputc('\n', m->log);
        }
        if (m->res.tri_photo)
            fprintf(m->log, "float: photoelectrons I = %+.6g A at U_f\n", m->res.photo);
        report_paths(m, "float");
    }
    return MOTE_OK;
}

static int check_evolve(void *vm, const mote_call *c, mote_err *err)
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
    if (!mote_call_opt(c, "file") && m->check_timeseries)
        return note_prefixed(m, c, "_timeseries.csv", "timeseries", err);
    return MOTE_OK;
}

/* The time-series file of evolve (spec 8.1): file= if given, else P_timeseries.csv after
 * `output prefix=P` (unless timeseries=off); only MPI rank 0 writes. 1 when one is open. */
static int open_timeseries(ch_model *m, const mote_call *c, mote_datafile *d, mote_err *err,
                           int *rc)
{
    *rc = MOTE_OK;
    if (ch_mpi_rank() != 0)
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
static int evolve_full(ch_model *m, const mote_call *c, mote_err *err)
{
    mote_ch_geometry g;
    mote_ch_body_geometry(&m->body, &g);
    const double T = mote_call_opt(c, "time")->r, dt = mote_call_opt_r(c, "dt_out", T);
    const double U0 = mote_call_opt_r(c, "U0", 0), C = g.capacitance;
    if (build_tri_materials(m, err))
        return err->code;
    mote_ch_run_opts o = run_opts(m, c, &g); /* (the field on: full mode) */
    mote_ch_tracer *tr = mote_ch_tracer_new(&m->body, err);
    if (!tr)
        return err->code;
    ch_table t;
    int rc = ch_table_build(&m->plasma, &m->body, tr, &o, U0, &t, err);
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
    const int nsp = m->plasma.nsp;
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
    const long nout = (long)floor(T / dt + 1e-9);
    double nreal[MOTE_CH_MAX_SPECIES] = {0}, tprev = 0;
    for (long k = 0; k <= nout + (fabs(nout * dt - T) > 1e-12 * T) && out; k++) {
        const double time = k <= nout ? k * dt : T, U = ch_table_u_at(&t, time);
        /* the real particles collected since the last row: 32 trapezoids */
        for (int q = 0; q < 32 && time > tprev; q++) {
            const double ta = tprev + (time - tprev) * q / 32, tb = tprev + (time - tprev) * (q + 1) / 32;
            const double ua = ch_table_u_at(&t, ta), ub = ch_table_u_at(&t, tb);
            for (int s = 0; s < nsp; s++)
                nreal[s] += 0.5 * (tb - ta) *
                            (fabs(ch_table_col(&t, ua, s)) + fabs(ch_table_col(&t, ub, s))) /
                            (abs(m->plasma.sp[s].Z) * MOTE_CH_E);
        }
        tprev = time;
        const double sU = ch_table_col(&t, U, nsp + 2) * fmin(time, t.tau) / C;
        if (f) {
            fprintf(out, "%.10g %.10g %.10g %.10g %.10g", time, C * U, U, sU, ch_table_eval(&t, U));
            for (int s = 0; s < nsp; s++)
                fprintf(out, " %.10g %.10g", ch_table_col(&t, U, s), nreal[s]);
            fprintf(out, " %.10g %.10g\n", ch_table_col(&t, U, nsp), ch_table_col(&t, U, nsp + 1));
        } else {
            fprintf(out, "evolve: t %.10g s Q %.10g C U %.10g V I %.10g A\n", time, C * U, U,
                    ch_table_eval(&t, U));
        }
        if (m->legacy_stdout && m->log) { /* the original's columns: Q U t collisions */
            double ntot = 0;
            for (int s = 0; s < nsp; s++)
                ntot += nreal[s];
            fprintf(m->log, "%.10g %.10g %.10g %.10g\n", C * U, U, time, ntot);
        }
    }
    ch_table_free(&t);
    return f ? mote_datafile_commit(&d, err) : MOTE_OK;
}

/* Faithful mode (spec 1.2): constant currents, Q = I t and U = Q / C. */
static int run_evolve(void *vm, const mote_call *c, mote_err *err)
{
    ch_model *m = vm;
    if (!m->faithful) {
        diagnose(m, "evolve");
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
    const long nout = (long)floor(T / dt + 1e-9);
    for (long k = 0; k <= nout + (fabs(nout * dt - T) > 1e-12 * T) && out; k++) {
        const double t = k <= nout ? k * dt : T;
        fprintf(out, f ? "%.10g %.10g %.10g %.10g %.10g" : "evolve: t %.10g s Q %.10g C U %.10g V "
                                                              "+- %.3g I %.10g A",
                t, inet * t, inet * t / C, sig * t / C, inet);
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
    return f ? mote_datafile_commit(&d, err) : MOTE_OK;
}

/* ---- output (spec 8) ------------------------------------------------------------------------ */

static int on_off(const mote_call *c, const char *key, int dflt, int *out, mote_err *err)
{
    const mote_arg *a = mote_call_opt(c, key);
    *out = dflt;
    if (!a)
        return MOTE_OK;
    if (strcmp(a->text, "on") && strcmp(a->text, "off"))
        return mote_call_fail(err, c, mote_call_opt_index(c, key), MOTE_EINVAL,
                              "output: %s must be on or off, found '%s'", key, a->text);
    *out = a->text[1] == 'n';
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
    if (parse3any(t, v))
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

static int check_output(void *vm, const mote_call *c, mote_err *err)
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
    if ((a = mote_call_opt(c, "vtk_format")) && strcmp(a->text, "ascii") && strcmp(a->text, "binary"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "vtk_format"), MOTE_EINVAL,
                              "output: vtk_format must be ascii or binary, found '%s'", a->text);
    if ((a = mote_call_opt(c, "png_scale")) && strcmp(a->text, "linear") && strcmp(a->text, "log"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "png_scale"), MOTE_EINVAL,
                              "output: png_scale must be linear or log, found '%s'", a->text);
    const mote_arg *p = mote_call_opt(c, "prefix");
    if (!mote_ctx_dir_ok(c->ctx, p->path))
        return mote_call_fail(err, c, mote_call_opt_index(c, "prefix"), MOTE_EINVAL,
                              "output: the directory of prefix '%s' does not exist", p->text);
    ch_model *m = vm;
    free(m->check_prefix);
    if (!(m->check_prefix = strdup(p->path)))
        return mote_fail(err, MOTE_ENOMEM, "output: out of memory");
    on_off(c, "timeseries", 1, &m->check_timeseries, err);
    return MOTE_OK;
}

static int run_output(void *vm, const mote_call *c, mote_err *err)
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

/* ---- the table ------------------------------------------------------------------------------ */

static const char HELP_PLASMA[] =
    "    plasma preset geo-worst-case|thesis-hot\n"
    "    plasma preset single n=N kT=T\n"
    "    ... [drift=VX,VY,VZ]\n"
    "\n"
    "Replace the plasma by a preset (spec 3.2): `geo-worst-case`, the thesis's\n"
    "Table 1 (the NASA worst-case geostationary environment: electrons 0.2 cm^-3 at\n"
    "0.4 keV and 1.2 cm^-3 at 27.5 keV, protons 0.6 cm^-3 at 0.2 keV and 1.3 cm^-3\n"
    "at 28 keV); `thesis-hot`, its hot components only (the original program's\n"
    "setting and the default of faithful mode); `single`, one electron and one\n"
    "proton Maxwellian with density N (m^-3) and temperature T (eV). Prints each\n"
    "component's thermal current density j0 = e n sqrt(kT/(2 pi m)), its mean speed\n"
    "and the Debye length of the whole plasma.\n"
    "drift=VX,VY,VZ (m/s) makes the plasma flow past the body at that velocity\n"
    "(every species alike, e.g. the ram flow of an orbit; spec 5.4): histories then\n"
    "start where the local inward flux n (sigma phi(s) + u_n Phi(s)) is, with the\n"
    "normal speed drawn from w N(w; u_n, sigma) and the tangential ones from\n"
    "N(u_t, sigma). Straight paths only: with the field on, or with the box\n"
    "injector, the drift is ignored.\n";

static const char HELP_SPECIES[] =
    "    species name=S charge=Z mass=electron|proton|amu:A|KG [drift=VX,VY,VZ]\n"
    "    species clear\n"
    "\n"
    "Add a species of charge Z e (a whole number, not 0) and mass m: electron,\n"
    "proton, A atomic mass units (amu:16 for O+) or kilograms (spec 3.1); its\n"
    "components come from `maxwellian`. drift= as for `plasma` (spec 5.4).\n"
    "`species clear` empties the list (a preset replaces it too).\n";

static const char HELP_MAXWELLIAN[] =
    "    maxwellian species=S density=N temperature=T\n"
    "\n"
    "Add a Maxwellian component of density N (m^-3) and temperature T (kT in eV)\n"
    "to species S (at most 8 components a species, 16 species).\n";

static const char HELP_BODY[] =
    "    body sphere radius=A\n"
    "    body icosphere radius=A [level=4]\n"
    "    body uvsphere radius=A [nlon=100] [nlat=50]\n"
    "    body box size=SX,SY,SZ [subdiv=1]\n"
    "    body twocubes [side=1] [gap=1]\n"
    "    body load file=FILE [format=auto|plain|assimp] [units=m|cm|mm|in] [scale=S]\n"
    "              [part=NAME] [offset=X,Y,Z] [rotate=AXIS,DEG] [strict=no|yes]\n"
    "    body capacitance value=auto|F\n"
    "\n"
    "`body capacitance` replaces the body's capacitance C (default auto: 4 pi eps0\n"
    "R_eq) by F farads, and with it the field's radius R_f = C/(4 pi eps0) (spec\n"
    "4.3, 6.1); not for the exact sphere, whose field is exact. (Decision: the value\n"
    "is the option value= rather than a second word.)\n"
    "\n"
    "Add a generated body (spec 4.4; lengths in m): the exact analytic sphere (a\n"
    "body on its own), an icosphere of 20 4^L triangles (level 4: 5 120; 5: 20 480),\n"
    "a UV sphere of 2 nlon (nlat - 1) triangles (the benchmark's 9 800), a box\n"
    "centred at the origin with each face cut into subdiv^2 squares, or two cubes\n"
    "of side `side` whose facing faces are `gap` apart along x (the shadowing\n"
    "test). Normals point outward. Prints the triangle count, the area, R_eq,\n"
    "R_bound and the capacitance C = 4 pi eps0 R_eq of the sphere of equal area.\n"
    "\n"
    "`body load` adds the triangles of a mesh file (spec 7.1): STL (ASCII or\n"
    "binary), OBJ, PLY, glTF and the other formats of Assimp, or the original\n"
    "program's plain format (numbers as a stream, 9 per triangle; taken for the\n"
    "extensions .txt, .dat, .tri and none, or with format=plain; `#` comments; a\n"
    "word that is not a number abandons the partial triangle and its line, an\n"
    "error with strict=yes). Coordinates are scaled (units= or scale=, the length\n"
    "of one file unit in m), turned about an axis and moved, then repaired (spec\n"
    "4.2): triangles below 1e-12 L^2 dropped, vertices closer than 1e-9 L welded\n"
    "(L the bounding-box diagonal), duplicate triangles dropped, closed components\n"
    "turned to face outward, open components kept as two-sided sheets; the counts\n"
    "are printed. Parts come from OBJ groups, STL solid names and Assimp mesh or\n"
    "material names, else part=, else the file name. The file may be given again\n"
    "to assemble a body from several files.\n";

static const char HELP_INJECTOR[] =
    "    injector sphere [radius=auto|debye|thesis|R]\n"
    "    injector box [margin=0.05] [margin_m=M]\n"
    "\n"
    "Histories start on a sphere about the body's area-weighted centre (spec 5.2):\n"
    "radius=auto (default) is 1.05 times the larger of R_bound and R_eq; debye the\n"
    "plasma's Debye length; thesis the thesis's 131.41 m; or R metres. Without a\n"
    "field the collected current does not depend on the radius, only the share of\n"
    "histories that hit does.\n"
    "\n"
    "`injector box` starts them on the body's bounding box enlarged on each side by\n"
    "margin times its diagonal (default 0.05), or by margin_m metres: a face chosen\n"
    "in proportion to its area, a point uniform on it, the cosine law about its\n"
    "inward normal, Gamma = A_box n sqrt(kT/(2 pi m)). It suits long thin bodies;\n"
    "with the field on it is refused (a particle leaving a box in a central field\n"
    "can come back).\n";

static const char HELP_RUN[] =
    "    run [particles=1e6] [potential=0]\n"
    "    run relerr=E [particles=1e5] [max_particles=1e8] [potential=0]\n"
    "\n"
    "With relerr, histories are added until every species' current has a relative\n"
    "standard error <= E (spec 5.3), from particles (1e5) up to max_particles: the\n"
    "count for E is estimated from the last run's errors (they fall as 1/sqrt(N))\n"
    "and rounded up to whole blocks of 4096; run prints the count reached.\n"
    "\n"
    "Estimate the current each species brings to the uncharged body (spec 5):\n"
    "for every Maxwellian component, N histories start on the injection sphere,\n"
    "positions uniform, directions by the cosine law about the inward normal (the\n"
    "flux of an isotropic Maxwellian), each carrying the current q Gamma / N with\n"
    "Gamma = 4 pi R^2 n sqrt(kT/(2 pi m)). The first triangle each straight path\n"
    "meets (nearest, traced with Embree in robust mode) is tallied. Prints the\n"
    "current of each species with its standard error |w| sqrt(h (1 - h/N)), the\n"
    "hit fraction and back-face hits. Random numbers are Philox4x32-10 keyed by\n"
    "`seed`, one stream per history, so the tallies do not depend on `threads`.\n"
    "potential=U (V) charges the body: the histories move in the Coulomb field of\n"
    "the equivalent sphere (spec 6.1; radius R_eq, or the exact sphere's), injected\n"
    "exactly (spec 6.2). On the exact sphere they hit by the OML test (see\n"
    "`float`); on a mesh each path is integrated (spec 6.3, see `integrator`) and\n"
    "its chords traced, and run prints the steps per history, the histories lost\n"
    "and the largest relative energy error. In faithful mode the field is off and\n"
    "U changes nothing.\n";

static const char HELP_EVOLVE[] =
    "    evolve time=T [dt_out=D] [file=FILE] [U0=0] [particles=1e6]\n"
    "\n"
    "Full mode (the charged body): C dU/dt = I_net(U) from U0 (default\n"
    "0 V). The net current is tabulated by runs of N histories per component\n"
    "(default 1e6, common random numbers) on an adaptive grid of potentials (spec\n"
    "6.6), interpolated monotonically, and t(U) = C integral dU / I_net(U) is\n"
    "integrated and inverted; prints U_f, tau = C/|dI/dU| there and the times to\n"
    "50% and 90% of U_f, then a line every D to T.\n"
    "\n"
    "Faithful mode (model charging faithful): the thesis's charging with\n"
    "constant currents, Q = I t and U = Q / C with C of the sphere of equal area,\n"
    "from the last `run`, at t = 0, D, 2D, ... and T.\n"
    "\n"
    "The lines go to FILE, or without file= to P_timeseries.csv after `output\n"
    "prefix=P` (unless timeseries=off), else to the screen. The file (spec 8.1,\n"
    "written atomically) has the columns t_s Q_C U_V sigma_U_V I_net_A, per species\n"
    "I_s_A and Nreal_s (the real particles collected so far), I_see_A and\n"
    "I_photo_A; in full mode the species' and emission currents are interpolated\n"
    "linearly between the tabulated potentials and sigma_U = sigma_I min(t, tau)/C\n"
    "is an estimate.\n";

static const char HELP_FLOAT[] =
    "    float [particles=1e6] [tolerance=1e-4] [U0=0] [replicas=1] [roots=one|all]\n"
    "\n"
    "The floating potential U_f, where the net collected current is zero (spec\n"
    "6.5), of the charged body in the Coulomb field of its equivalent sphere (spec\n"
    "6.1): every history starts with the exact injection of spec 6.2 (the rate\n"
    "times exp(-chi) or 1 - chi, the energy law of the repelled or attracted\n"
    "component) and, on the exact sphere, hits when it passes the OML test\n"
    "E - qU >= L^2/(2 m a^2); on a mesh its path is followed (see `integrator`). Each\n"
    "I(U) is a run with the same seed and histories (common random numbers); the\n"
    "root is bracketed by steps from U0 (0.1 kT_min/e, doubling) the way the net\n"
    "current drives U, so it is the root time evolution from U0 reaches (with\n"
    "emission there can be several), and refined until the bracket is below\n"
    "max(0.1 sigma_U, tolerance |U|). Prints U_f with sigma_U = sigma_I / |dI/dU|,\n"
    "the analytic OML estimate for the equivalent sphere without emission, and each\n"
    "species' current at U_f. replicas=k repeats the search with the seeds\n"
    "seed+1 ... seed+k-1 and prints the roots' mean and standard deviation (the\n"
    "files and U_f stay the first seed's). roots=all also tabulates I(U) from 0 V\n"
    "both ways (steps of 0.1 kT_min/e, doubling, to twice the farthest of U_f, U0\n"
    "and the OML root) and prints every sign change, flagged stable where\n"
    "dI/dU < 0 (two roots in one interval are not seen). Faithful mode has no\n"
    "floating potential (its currents do not depend on U).\n";

static const char HELP_FIELD[] =
    "    field none|sphere\n"
    "\n"
    "sphere (the default in full mode): a charged body's particles move in the\n"
    "Coulomb field of its equivalent sphere (spec 6.1), phi = U R_f / |r - c| outside\n"
    "R_f = R_eq (the exact sphere: its radius). none: straight paths whatever the\n"
    "potential, as in faithful mode (which has no field).\n";

static const char HELP_BFIELD[] =
    "    bfield B=T\n"
    "\n"
    "A magnetic field strength (tesla) for the validity warnings of spec 3.4 only:\n"
    "run, float and evolve warn when a component's Larmor radius m v / (|q| B),\n"
    "v = sqrt(2 kT / m), is below 10 R_bound. The model itself has no magnetic\n"
    "field. They also warn, always, when the Debye length is below 5 R_bound (a thin\n"
    "sheath) and when kT/(m c^2) > 0.02 (relativistic speeds). At GEO (B about\n"
    "100 nT) the radii are kilometres.\n";

static const char HELP_SUN[] =
    "    sun direction=X,Y,Z [intensity=1]\n"
    "    sun off\n"
    "\n"
    "Sunlight for photoemission (spec 6.8); off (eclipse) by default. direction is\n"
    "toward the sun (normalised); intensity 1 is 1 AU at normal incidence. A\n"
    "triangle whose outward normal faces the sun (a sheet: its side that does)\n"
    "emits photo_j intensity A (n . s) f times the escape fraction (1 at U <= 0,\n"
    "(1 + eU/kT) exp(-eU/kT) above, kT the material's see_kT, 2 eV), with photo_j\n"
    "its material's (see `material`; bare emits nothing) and f its sunlit fraction:\n"
    "the share of 16 stratified points on it from which a shadow ray toward the sun\n"
    "leaves the body. The exact sphere emits photo_j intensity pi a^2. No random\n"
    "numbers are used. run prints the photocurrent; float and evolve include it.\n";

static const char HELP_TEST[] =
    "    test hitprob [particles=1e6]\n"
    "\n"
    "The original program's -t self-test, done right (spec 10 M3): straight paths\n"
    "from the injector (sphere or box; the plasma does not matter), and the share P\n"
    "of them that hit the body with its binomial error, against A/(4 pi R^2) for\n"
    "the sphere injector (Cauchy-Crofton) or A/A_box for the box, exact for a convex\n"
    "body (a concave one is hit less often), and their difference in sigmas.\n";

static const char HELP_INTEGRATOR[] =
    "    integrator [eta=0.01] [max_steps=1e5]\n"
    "\n"
    "Curved paths on a charged mesh (spec 6.3): outside the equivalent sphere\n"
    "(radius R_f = R_eq about the body's centre c) a particle accelerates by\n"
    "q U R_f (r - c) / (m |r - c|^3), inside it moves straight. Each path is\n"
    "integrated by the classical fourth-order Runge-Kutta method with steps\n"
    "dt = eta |r - c| / |v|, a step entering R_f being cut where it meets the\n"
    "sphere; each step's chord is traced against the mesh, and the nearest hit\n"
    "ends the history. A path leaving the injection sphere outward is gone; one\n"
    "still going after max_steps steps is counted as lost; more than 1e-6 of the\n"
    "histories lost is an error (nothing is written). The impact energy is\n"
    "K = E - q phi(x_hit).\n";

static const char HELP_MATERIAL[] =
    "    material assign part=NAME|* material=NAME\n"
    "    material define name=NAME [see_dmax=D] [see_emax=E] [see_law=universal]\n"
    "             [see_angle=none] [see_kT=2] [ion_dmax=DI] [ion_emax=EI]\n"
    "             [photo_j=J] [photo_kT=2]\n"
    "\n"
    "Give a part (or every part: *) a material (spec 6.9); later assignments win.\n"
    "The presets: bare (the default: no emission), aluminium (secondary yield peak\n"
    "0.97 at 0.30 keV), gold (0.88, 0.80), kapton (2.1, 0.15), teflon (3.0, 0.30),\n"
    "cover-glass (2.4, 0.40); all with secondaries and photoelectrons at 2 eV and\n"
    "no ion yield. The exact sphere's part is called sphere. `material define`\n"
    "makes a material (or changes one, a preset included, keeping what is not given).\n"
    "Each electron that hits a surface of a material scores the expected number of\n"
    "secondaries (spec 6.7) at its impact energy E (keV), x = E/see_emax:\n"
    "universal (the default): D K x^-0.35 (1 - exp(-2.28 x^1.35)), K = 1/(1 - e^-2.28);\n"
    "with see_angle=sec, 2.28 cos(theta) x^1.35 in the exponent and the whole divided\n"
    "by cos(theta), theta the impact angle from the normal; see_law=sternglass:\n"
    "D x exp(2 - 2 sqrt(x)) (it falls far too steeply above a few keV). Ions score\n"
    "2 DI sqrt(y) / (1 + y), y = E/ion_emax, when ion_dmax is given. The score is\n"
    "times the fraction that escapes ((1 + eU/kT) exp(-eU/kT) above U = 0, else 1;\n"
    "kT = see_kT); the emitted current is a gain (electrons leave), printed by `run`\n"
    "and counted in `float` and `evolve`. photo_j (A/m^2 at normal incidence;\n"
    "presets: aluminium 4e-5, gold 2.9e-5, the others 2e-5) is the photoemission of\n"
    "a sunlit surface (see `sun`), its electrons at photo_kT.\n";

static const char HELP_OUTPUT[] =
    "    output prefix=P [timeseries=on] [triangles=on] [vtk=on]\n"
    "           [vtk_format=ascii|binary] [png=on] [png_view=iso] [png_size=1024x768]\n"
    "           [png_scale=linear|log] [png_quantity=J_net] [ply=off]\n"
    "           [legacy_stdout=off]\n"
    "\n"
    "After every later `run` (at its potential) and `float` (at U_f), write the\n"
    "files of spec 8 (P may name a directory; `evolve` writes P_timeseries.csv):\n"
    "P_triangles.csv, one row per triangle and side that collects (the front of a\n"
    "closed surface, both sides of a sheet): part, material, side, area, centre,\n"
    "normal, sunlit fraction, per species the hits and the current, the secondary\n"
    "and photoelectron currents, then the net current, its density J_net and\n"
    "standard error; P_parts.csv, the currents summed per part;\n"
    "P_summary.txt and P_summary.json, the body, the plasma and the currents per\n"
    "species and component; P_surface.vtk, legacy VTK POLYDATA for ParaView (ASCII\n"
    "or big-endian binary) with cell arrays J_net (both sides of a sheet),\n"
    "J_net_front, J_net_back, sigma_J, relerr, J_<species>, J_see, J_photo,\n"
    "sunlit_fraction, hits_total and part_id; P_surface.png, the body\n"
    "seen orthographically from png_view (iso: from (1, 1, 1); +x, -x, ... or a\n"
    "vector X,Y,Z; several as V1/V2/... give one file each, P_surface_iso.png,\n"
    "P_surface_pz.png, P_surface_mx.png, P_surface_view4.png ...), each triangle\n"
    "filled with the viridis colour of its png_quantity (J_net, the default;\n"
    "J_<species>, J_see, J_photo, sigma_J, relerr, sunlit_fraction or hits; its\n"
    "log10 |.| with png_scale=log) times a shading 0.35 + 0.65 |n . view|,\n"
    "back faces of closed surfaces culled, with a colour bar. The exact sphere has\n"
    "no triangles: no VTK or PNG for it. With ply=on also P_surface.ply (binary\n"
    "little-endian: the vertices, faces with the picture's viridis colour and a\n"
    "float J_net). legacy_stdout=on makes `evolve` also print the original\n"
    "program's four columns: Q (C), U (V), t (s) and the real particles collected.\n"
    "Headers give the mode, seed, histories,\n"
    "the body's measures and the plasma; files are written atomically.\n";

static const mote_cmd ch_commands[] = {
    {"plasma", NULL, "s s n=r>0 kT=r>0 drift=s", "plasma preset NAME [n=N] [kT=T] [drift=V]",
     "the plasma environment (a preset of spec 3.2)", HELP_PLASMA, check_plasma, run_plasma},
    {"species", NULL, "*", "species name=S charge=Z mass=M [drift=V] | species clear",
     "add a species (or empty the list)", HELP_SPECIES, check_species, run_species},
    {"maxwellian", NULL, "species=s! density=r>0! temperature=r>0!",
     "maxwellian species=S density=N temperature=T", "add a Maxwellian component to a species",
     HELP_MAXWELLIAN, check_maxwellian, run_maxwellian},
    {"body", NULL,
     "s radius=r>0 level=i nlon=i>=3 nlat=i>=2 size=s subdiv=i>=1 side=r>0 gap=r>=0 "
     "file=f<mesh format=s units=s scale=r>0 part=s offset=s rotate=s strict=s value=s",
     "body KIND [options]",
     "add a generated body (sphere, icosphere, uvsphere, box, twocubes) or a mesh file (load)",
     HELP_BODY, check_body, run_body},
    {"injector", NULL, "s radius=s margin=r>0 margin_m=r>0",
     "injector sphere|box [options]",
     "where histories start", HELP_INJECTOR, check_injector, run_injector},
    {"field", NULL, "s", "field none|sphere", "straight paths, or the equivalent sphere's field",
     HELP_FIELD, check_field, run_field},
    {"bfield", NULL, "B=r>=0!", "bfield B=T", "a magnetic field for the validity warnings only",
     HELP_BFIELD, NULL, run_bfield},
    {"sun", NULL, "*", "sun direction=X,Y,Z [intensity=1] | sun off",
     "light for photoemission (spec 6.8)", HELP_SUN, check_sun, run_sun},
    {"test", NULL, "s particles=r>=1", "test hitprob [particles=1e6]",
     "the hit-probability self-test (spec 10 M3)", HELP_TEST, check_test, run_test},
    {"integrator", NULL, "eta=r(0,1) max_steps=r>=1", "integrator [eta=0.01] [max_steps=1e5]",
     "the curved paths' step and limit (spec 6.3)", HELP_INTEGRATOR, check_integrator,
     run_integrator},
    {"run", NULL, "particles=r>=1 potential=r relerr=r(0,1) max_particles=r>=1",
     "run [particles=N] [relerr=E [max_particles=M]] [potential=0]",
     "Monte Carlo currents to the uncharged body", HELP_RUN, check_run, run_run},
    {"float", NULL, "particles=r>=1 tolerance=r(0,0.1] U0=r replicas=i>=1 roots=s",
     "float [particles=N] [tolerance=1e-4] [U0=0] [replicas=1] [roots=one|all]",
     "the floating potential of the charged body", HELP_FLOAT, check_float,
     run_float},
    {"material", NULL,
     "s name=s see_dmax=r>=0 see_emax=r>0 see_law=s see_angle=s see_kT=r>0 ion_dmax=r>=0 "
     "ion_emax=r>0 photo_j=r>=0 photo_kT=r>0 part=s material=s",
     "material define|assign [options]", "define a material, or give a part one (spec 6.9)",
     HELP_MATERIAL, check_material, run_material},
    {"output", NULL,
     "prefix=f! timeseries=s triangles=s vtk=s vtk_format=s png=s ply=s png_view=s png_size=s "
     "png_scale=s png_quantity=s legacy_stdout=s",
     "output prefix=P [triangles=on] [vtk=on] [png=on] [ply=off] [png_view=V] [png_size=WxH] "
     "[png_scale=linear|log]",
     "the files of spec 8 after each run (tables, VTK, summary, surface picture)", HELP_OUTPUT,
     check_output, run_output},
    {"evolve", NULL, "time=r>0! dt_out=r>0 file=f>timeseries U0=r particles=r>=1",
     "evolve time=T [dt_out=D] [file=FILE] [U0=0] [particles=N]",
     "U(t) of faithful mode (constant currents)", HELP_EVOLVE, check_evolve, run_evolve},
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
                 "history and component as counter: results do not depend on threads.\n",
};
