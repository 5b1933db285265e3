/* commands.c: the separator model's script commands (specs/separator.md 2.13): the channel and
 * grids, the gas, species and sizes, the feed, contacts, dispersion, the run with its scheduled
 * outputs (frames, live, snapshots, balance), the Tromp table and profiles, save and load. Every value is checked before
 * anything runs, on a dry model that follows the script's settings. (Decision: the optional
 * positional arguments of the spec's table are options here, e.g. `feed z=0.5 rate=0.01`,
 * as in the toolkit's other models.) */
#include "mote/h5md.h"
#include "mote/vtk.h"
#include "mote/separator.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


#include "mote/datafile.h"
#include "model.h"


static void *model_create(mote_context *ctx, int dry)
{
    sep_model *m = calloc(1, sizeof *m);
    if (!m)
        return NULL;
    m->ctx = ctx;
    m->dry = dry;
    m->log = dry || !ctx ? NULL : ctx->out;
    mote_sep_init(&m->sys);
    m->seed = 1;
    return m;
}

static void model_destroy(void *vm)
{
    sep_model *m = vm;
    if (!m)
        return;
    mote_sep_free(&m->sys);
    free(m->frames.prefix);
    free(m->frames.movie_path);
    free(m->live.path);
    free(m->snaps.prefix);
    mote_rows_free(&m->bal.out);
    free(m->traj.path);
    free(m->traj.origin);
    free(m->snaps.origin);
    free(m->ckpt.path);
    free(m->bal.origin);
    free(m->bal.row);
    free(m);
}

static void model_seed(void *vm, uint64_t seed)
{
    ((sep_model *)vm)->seed = seed;
    mote_rng_seed(&((sep_model *)vm)->sys.rng, seed);
}

/* The species called name, or -1. */
int sep_find_species(const mote_sep_system *s, const char *name)
{
    for (int k = 0; k < s->nsp; k++)
        if (!strcmp(s->sp[k].name, name))
            return k;
    return -1;
}

/* ---- the commands ----------------------------------------------------------------------------
 * Each applies its setting to the model it is given: the dry one during validation, the real
 * one when the script runs, so the same checks see the same state. */

static int do_dim(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    const long d = (long)c->args[0].i;
    if (d != 2 && d != 3)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "dim: expected 2 or 3, found %ld", d);
    if (m->sys.n)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "dim: give it before any particle");
    if (d == 3 && m->have_channel && !(m->sys.D > 0))
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "dim: the channel was given in 2D: a 3D "
                              "channel needs its depth (give dim 3 first, then channel W H D=)");
    m->sys.dim = (int)d;
    return MOTE_OK;
}

static int do_channel(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    const mote_arg *D = mote_call_opt(c, "D");
    if (m->sys.dim == 3 && !D)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "channel: a 3D channel needs its depth "
                              "D= (m)");
    if (m->sys.dim == 2 && D)
        return mote_call_fail(err, c, mote_call_opt_index(c, "D"), MOTE_EINVAL,
                              "channel: D= is the depth of a 3D channel (dim 3)");
    m->sys.W = c->args[0].r;
    m->sys.H = c->args[1].r;
    m->sys.D = D ? D->r : 0;
    m->have_channel = 1;
    return MOTE_OK;
}

static int do_depth2d(void *vm, const mote_call *c, mote_err *err)
{
    ((sep_model *)vm)->sys.D2 = c->args[0].r;
    return MOTE_OK;
}

static int do_ends(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    m->sys.open_bottom = c->args[0].i == 0; /* open|closed */
    m->sys.open_top = c->args[1].i == 0;
    return MOTE_OK;
}

static int do_gas(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    m->sys.U0 = c->args[0].r;
    m->sys.rho_g = mote_call_opt_r(c, "rho", m->sys.rho_g);
    m->sys.mu_g = mote_call_opt_r(c, "mu", m->sys.mu_g);
    m->have_gas = 1;
    return MOTE_OK;
}

/* `gas_profile FILE`: rows z rho_g [mu_g] (spec 2.6). */
static int do_gas_profile(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    const char *path = c->args[0].path;
    mote_table t;
    mote_err e2 = {0};
    int rc = mote_table_read(&t, path, &e2);
    if (rc)
        return mote_call_fail(err, c, 0, rc, "%s", e2.msg);
    double *v = malloc(3 * (t.rows ? t.rows : 1) * sizeof *v);
    if (!v) {
        mote_table_free(&t);
        return mote_fail(err, MOTE_ENOMEM, "gas_profile: out of memory");
    }
    const int width = t.rows ? t.ncol[0] : 0;
    for (size_t r = 0; r < t.rows && !rc; r++) {
        if (t.ncol[r] != width || width < 2 || width > 3) {
            rc = mote_call_fail(err, c, 0, MOTE_EINVAL, "%s:%ld: expected z rho_g [mu_g] on every "
                                "row alike, found %d value%s", path, t.line[r], t.ncol[r],
                                t.ncol[r] == 1 ? "" : "s");
            break;
        }
        for (int q = 0; q < 3; q++)
            v[3 * r + (size_t)q] = q < width ? mote_table_at(&t, r, q) : NAN;
        const double *x = v + 3 * r;
        if (!isfinite(x[0]) || !isfinite(x[1]) || (width == 3 && !isfinite(x[2])))
            rc = mote_call_fail(err, c, 0, MOTE_EINVAL, "%s:%ld: expected numbers", path,
                                t.line[r]);
        else if (r > 0 && !(x[0] > v[3 * (r - 1)]))
            rc = mote_call_fail(err, c, 0, MOTE_EINVAL, "%s:%ld: the heights must increase (z = "
                                "%g after %g)", path, t.line[r], x[0], v[3 * (r - 1)]);
        else if (!(x[1] > 0))
            rc = mote_call_fail(err, c, 0, MOTE_EINVAL, "%s:%ld: the gas density must be > 0, "
                                "found %g", path, t.line[r], x[1]);
        else if (width == 3 && !(x[2] > 0))
            rc = mote_call_fail(err, c, 0, MOTE_EINVAL, "%s:%ld: the gas viscosity must be > 0, "
                                "found %g", path, t.line[r], x[2]);
    }
    if (!rc && t.rows < 2)
        rc = mote_call_fail(err, c, 0, MOTE_EINVAL, "%s: a gas profile needs at least 2 rows, "
                            "found %zu", path, t.rows);
    const size_t n = t.rows;
    mote_table_free(&t);
    if (!rc) {
        double *z = malloc(3 * n * sizeof *z);
        if (!z) {
            free(v);
            return mote_fail(err, MOTE_ENOMEM, "gas_profile: out of memory");
        }
        for (size_t r = 0; r < n; r++) {
            z[r] = v[3 * r];
            z[n + r] = v[3 * r + 1];
            z[2 * n + r] = v[3 * r + 2];
        }
        rc = mote_sep_set_gas_profile(&m->sys, n, z, z + n, z + 2 * n, &e2);
        if (rc)
            rc = mote_call_fail(err, c, 0, rc, "%s: %s", path, e2.msg);
        free(z);
    }
    free(v);
    return rc;
}

static int do_species(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    mote_sep_system *s = &m->sys;
    const char *name = mote_call_opt(c, "name")->text;
    const int at = mote_call_opt_index(c, "name");
    if (sep_find_species(s, name) >= 0)
        return mote_call_fail(err, c, at, MOTE_EINVAL, "species: '%s' exists already", name);
    if (strpbrk(name, " \t,=#\""))
        return mote_call_fail(err, c, at, MOTE_EINVAL, "species: a name without spaces, commas, "
                              "'=', '#' or '\"' (it names columns of the data files), found '%s'",
                              name);
    if (strlen(name) >= sizeof s->sp[0].name)
        return mote_call_fail(err, c, at, MOTE_EINVAL, "species: the name is longer than %d "
                              "characters", (int)sizeof s->sp[0].name - 1);
    if (s->nsp == MOTE_SEP_MAX_SPECIES)
        return mote_call_fail(err, c, at, MOTE_EINVAL, "species: at most %d species",
                              MOTE_SEP_MAX_SPECIES);
    mote_sep_species *sp = &s->sp[s->nsp++];
    memset(sp, 0, sizeof *sp);
    snprintf(sp->name, sizeof sp->name, "%s", name);
    sp->rho = mote_call_opt_r(c, "density", 0);
    sp->E = mote_call_opt_r(c, "E", 0);
    sp->nu = mote_call_opt_r(c, "nu", 0.3);
    sp->w = s->nsp == 1 ? 1 : 0; /* one species: all the feed */
    if (s->nsp == 2)
        s->sp[0].w = 0; /* several: the fractions must be given */
    return MOTE_OK;
}

/* the distributions in the order of `size`'s word list (MOTE_SEP_MONO ...) */
static const char *const DIST_NAMES[] = {"mono", "lognormal", "rosin_rammler", "loguniform",
                                         "table", NULL};

static int do_size(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    mote_sep_system *s = &m->sys;
    const int k = sep_find_species(s, c->args[0].text);
    if (k < 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "size: no species '%s' (species NAME RHO "
                              "first)", c->args[0].text);
    const int type = (int)c->args[1].i; /* the order of DIST_NAMES */
    static const char *const need[5][2] = {{"d", NULL}, {"d50", "sigma"}, {"d", "n"}, {NULL, NULL},
                                           {"file", NULL}};
    for (int q = 0; q < 2; q++)
        if (need[type][q] && !mote_call_opt(c, need[type][q]))
            return mote_call_fail(err, c, 1, MOTE_EINVAL, "size %s: give %s=", DIST_NAMES[type],
                                  need[type][q]);
    if (type != MOTE_SEP_MONO && type != MOTE_SEP_TABLE &&
        (!mote_call_opt(c, "min") || !mote_call_opt(c, "max")))
        return mote_call_fail(err, c, 1, MOTE_EINVAL, "size %s: give the truncation min= and "
                              "max= (m)", DIST_NAMES[type]);
    const mote_arg *b = mote_call_opt(c, "basis"); /* mass|number */
    mote_sep_dist *dd = &s->sp[k].dist;
    mote_sep_dist_free(dd);
    memset(dd, 0, sizeof *dd);
    dd->type = type;
    dd->a = mote_call_opt_r(c, type == MOTE_SEP_LOGNORMAL ? "d50" : "d", 0);
    dd->b = mote_call_opt_r(c, type == MOTE_SEP_LOGNORMAL ? "sigma" : "n", 0);
    dd->lo = mote_call_opt_r(c, "min", 0);
    dd->hi = mote_call_opt_r(c, "max", 0);
    dd->number_basis = b && b->i == 1;
    mote_err e2 = {0};
    if (type == MOTE_SEP_TABLE) { /* rows d F */
        const char *path = mote_call_opt(c, "file")->path;
        mote_table t;
        if (mote_table_read(&t, path, &e2))
            return mote_call_fail(err, c, mote_call_opt_index(c, "file"), e2.code, "%s", e2.msg);
        double *v = malloc(2 * (t.rows ? t.rows : 1) * sizeof *v);
        int rc = v ? MOTE_OK : mote_fail(&e2, MOTE_ENOMEM, "size table: out of memory");
        for (size_t r = 0; r < t.rows && !rc; r++) {
            v[r] = mote_table_at(&t, r, 0);
            v[t.rows + r] = mote_table_at(&t, r, 1);
            if (t.ncol[r] != 2 || !isfinite(v[r]) || !isfinite(v[t.rows + r]))
                rc = mote_fail(&e2, MOTE_EINVAL, "%s:%ld: expected d (m) and the cumulative "
                               "undersize fraction F", path, t.line[r]);
        }
        if (!rc && t.rows > 100000)
            rc = mote_fail(&e2, MOTE_EINVAL, "%s: more than 1e5 rows", path);
        if (!rc && mote_sep_dist_table(dd, (int)t.rows, v, v + t.rows, &e2)) {
            long line = 0;
            int row = 0;
            if (sscanf(e2.msg, "row %d", &row) == 1 && row >= 1 && (size_t)row <= t.rows)
                line = t.line[row - 1];
            char msg[sizeof e2.msg];
            snprintf(msg, sizeof msg, "%s", strchr(e2.msg, ':') ? strchr(e2.msg, ':') + 2 : e2.msg);
            rc = line ? mote_fail(&e2, MOTE_EINVAL, "%s:%ld: %s", path, line, msg)
                      : mote_fail(&e2, MOTE_EINVAL, "%s: %s", path, msg);
        }
        free(v);
        mote_table_free(&t);
        if (rc)
            return mote_call_fail(err, c, mote_call_opt_index(c, "file"), rc, "%s", e2.msg);
    }
    if (mote_sep_dist_build(dd, &e2))
        return mote_call_fail(err, c, 1, MOTE_EINVAL, "%s", e2.msg);
    s->sp[k].have_dist = 1;
    return MOTE_OK;
}

static int do_feed(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    mote_sep_system *s = &m->sys;
    if (!m->have_channel)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "feed: give the channel first");
    const double z = mote_call_opt(c, "z")->r;
    if (!(z > 0 && z < s->H))
        return mote_call_fail(err, c, mote_call_opt_index(c, "z"), MOTE_EINVAL,
                              "feed: z must lie inside the channel (0 < z < H = %g m), found %g",
                              s->H, z);
    s->zf = z;
    s->hf = mote_call_opt_r(c, "hf", 0);
    s->rate = mote_call_opt_r(c, "rate", 0);
    s->t_start = mote_call_opt_r(c, "start", 0);
    s->t_stop = mote_call_opt_r(c, "stop", INFINITY);
    if (!(s->t_stop > s->t_start))
        return mote_call_fail(err, c, mote_call_opt_index(c, "stop"), MOTE_EINVAL,
                              "feed: stop must come after start");
    return MOTE_OK;
}

static int do_feed_window(void *vm, const mote_call *c, mote_err *err)
{
    mote_sep_system *s = &((sep_model *)vm)->sys;
    s->fx1 = c->args[0].r;
    s->fx2 = c->args[1].r;
    if (!(s->fx2 > s->fx1) || s->fx1 < 0 || s->fx2 > s->W)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "feed_window: need 0 <= X1 < X2 <= W = %g "
                              "m", s->W);
    const mote_arg *y1 = mote_call_opt(c, "y1"), *y2 = mote_call_opt(c, "y2");
    if ((y1 || y2) && s->dim != 3)
        return mote_call_fail(err, c, mote_call_opt_index(c, y1 ? "y1" : "y2"), MOTE_EINVAL,
                              "feed_window: y1= and y2= are for 3D");
    if (!y1 != !y2)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "feed_window: give both y1= and y2=");
    if (y1) {
        s->fy1 = y1->r;
        s->fy2 = y2->r;
        if (!(s->fy2 > s->fy1) || s->fy1 < 0 || s->fy2 > s->D)
            return mote_call_fail(err, c, mote_call_opt_index(c, "y1"), MOTE_EINVAL,
                                  "feed_window: need 0 <= y1 < y2 <= D = %g m", s->D);
    }
    return MOTE_OK;
}

static int do_feed_velocity(void *vm, const mote_call *c, mote_err *err)
{
    mote_sep_system *s = &((sep_model *)vm)->sys;
    s->vf[0] = c->args[0].r;
    s->vf[2] = c->args[1].r;
    const mote_arg *vy = mote_call_opt(c, "vy");
    if (vy && s->dim != 3)
        return mote_call_fail(err, c, mote_call_opt_index(c, "vy"), MOTE_EINVAL,
                              "feed_velocity: vy= is for 3D");
    s->vf[1] = vy ? vy->r : 0;
    return MOTE_OK;
}

static int do_feed_fraction(void *vm, const mote_call *c, mote_err *err)
{
    mote_sep_system *s = &((sep_model *)vm)->sys;
    const int k = sep_find_species(s, c->args[0].text);
    if (k < 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "feed_fraction: no species '%s'",
                              c->args[0].text);
    s->sp[k].w = c->args[1].r;
    return MOTE_OK;
}

/* The holes of a file: x1 x2 per row in 2D, x1 x2 y1 y2 in 3D (m). */
static int read_holes(const char *path, int dim, double **out, size_t *nh, mote_err *err)
{
    mote_table t;
    int rc = mote_table_read(&t, path, err);
    if (rc)
        return rc;
    const int want = dim == 3 ? 4 : 2;
    double *h = calloc(4 * (t.rows ? t.rows : 1), sizeof *h);
    if (!h) {
        mote_table_free(&t);
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", path);
    }
    for (size_t r = 0; r < t.rows && !rc; r++) {
        if (t.ncol[r] != want) {
            rc = mote_fail(err, MOTE_EINVAL, "%s:%ld: expected %s (m), found %d value%s", path,
                           t.line[r], dim == 3 ? "x1 x2 y1 y2" : "x1 x2", t.ncol[r],
                           t.ncol[r] == 1 ? "" : "s");
            break;
        }
        for (int q = 0; q < want; q++) {
            const double v = mote_table_at(&t, r, q);
            if (!isfinite(v)) {
                rc = mote_fail(err, MOTE_EINVAL, "%s:%ld: value %d is not a finite number", path,
                               t.line[r], q + 1);
                break;
            }
            h[4 * r + q] = v;
        }
        if (!rc && !(h[4 * r + 1] > h[4 * r] && (dim < 3 || h[4 * r + 3] > h[4 * r + 2])))
            rc = mote_fail(err, MOTE_EINVAL, "%s:%ld: a hole needs x1 < x2%s", path, t.line[r],
                           dim == 3 ? " and y1 < y2" : "");
    }
    if (!rc && t.rows == 0)
        rc = mote_fail(err, MOTE_EINVAL, "%s: no holes in the file", path);
    *nh = t.rows;
    mote_table_free(&t);
    if (rc) {
        free(h);
        return rc;
    }
    *out = h;
    return MOTE_OK;
}

/* `grid ZB T pattern a= p= [offset=] [a_y= p_y= offset_y=]` or `grid ZB T holes file=FILE`. */
static int do_grid(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    mote_sep_system *s = &m->sys;
    if (!m->have_channel)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "grid: give the channel first");
    if (s->nplate == MOTE_SEP_MAX_PLATES)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "grid: at most %d grids",
                              MOTE_SEP_MAX_PLATES);
    const double zb = c->args[0].r, t = c->args[1].r;
    if (zb + t > s->H)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "grid: the plate %g ... %g m does not fit "
                              "the channel (H = %g m)", zb, zb + t, s->H);
    const int holes = c->args[2].i == 1; /* pattern|holes */
    mote_sep_plate p = {0}; /* freed on every error path, whichever reader failed */
    mote_err e2 = {0};
    int rc;
    if (!holes) {
        const char *need[2] = {"a", "p"};
        for (int q = 0; q < 2; q++)
            if (!mote_call_opt(c, need[q]))
                return mote_call_fail(err, c, 2, MOTE_EINVAL, "grid pattern: give %s=", need[q]);
        if (mote_call_opt(c, "file"))
            return mote_call_fail(err, c, mote_call_opt_index(c, "file"), MOTE_EINVAL,
                                  "grid pattern: file= goes with holes");
        if (s->dim == 2 && (mote_call_opt(c, "a_y") || mote_call_opt(c, "p_y") ||
                            mote_call_opt(c, "offset_y")))
            return mote_call_fail(err, c, 2, MOTE_EINVAL, "grid pattern: a_y=, p_y= and "
                                  "offset_y= are for 3D");
        const double a[2] = {mote_call_opt_r(c, "a", 0), mote_call_opt_r(c, "a_y", mote_call_opt_r(c, "a", 0))};
        const double pp[2] = {mote_call_opt_r(c, "p", 0), mote_call_opt_r(c, "p_y", mote_call_opt_r(c, "p", 0))};
        const double off[2] = {mote_call_opt_r(c, "offset", 0),
                               mote_call_opt_r(c, "offset_y", mote_call_opt_r(c, "offset", 0))};
        for (int q = 0; q < (s->dim == 3 ? 2 : 1); q++) {
            const double across = q ? s->D : s->W;
            if (a[q] >= across)
                return mote_call_fail(err, c, mote_call_opt_index(c, q ? "a_y" : "a"),
                                      MOTE_EINVAL, "grid: a hole of %g m is not narrower than "
                                      "the channel (%g m across)", a[q], across);
            if (!(pp[q] > a[q]))
                return mote_call_fail(err, c, mote_call_opt_index(c, q ? "p_y" : "p"),
                                      MOTE_EINVAL, "grid: the pitch (%g m) must exceed the hole "
                                      "(%g m), or the holes would overlap", pp[q], a[q]);
        }
        rc = mote_sep_plate_pattern(&p, s->dim, s->W, s->D, zb, t, a, pp, off, &e2);
    } else {
        const mote_arg *f = mote_call_opt(c, "file");
        if (!f)
            return mote_call_fail(err, c, 2, MOTE_EINVAL, "grid holes: give file=FILE");
        double *h = NULL;
        size_t nh = 0;
        rc = read_holes(f->path, s->dim, &h, &nh, &e2);
        if (!rc)
            rc = mote_sep_plate_list(&p, zb, t, h, nh, &e2);
        free(h);
    }
    if (!rc) {
        /* the geometry alone (the particle sizes are checked before the run) */
        rc = mote_sep_plate_index(&p, s->dim, s->W, s->D, &e2);
        if (!rc)
            rc = mote_sep_plate_check(&p, s->nplate + 1, s->dim, s->W, s->D, s->H, 0, &e2);
    }
    if (rc) {
        mote_sep_plate_free(&p);
        return mote_call_fail(err, c, -1, e2.code, "%s", e2.msg);
    }
    s->plate[s->nplate++] = p;
    if (m->log && p.dropped)
        fprintf(m->log, "grid %d: %ld pattern holes dropped for crossing a wall\n", s->nplate,
                p.dropped);
    return MOTE_OK;
}

/* restitution_pair / friction_pair / rolling_friction_pair / cohesion_pair A B VALUE: the
 * value of the species pair, both ways */
static int do_pair(void *vm, const mote_call *c, mote_err *err)
{
    mote_sep_system *s = &((sep_model *)vm)->sys;
    int k[2];
    for (int q = 0; q < 2; q++) {
        k[q] = sep_find_species(s, c->args[q].text);
        if (k[q] < 0)
            return mote_call_fail(err, c, q, MOTE_EINVAL, "%s: no species '%s'", c->name,
                                  c->args[q].text);
    }
    double(*t)[MOTE_SEP_MAX_SPECIES] = !strcmp(c->name, "restitution_pair") ? s->e_pair
                                       : !strcmp(c->name, "friction_pair")  ? s->mu_pair
                                       : !strcmp(c->name, "cohesion_pair")  ? s->coh_pair
                                                                            : s->mur_pair;
    t[k[0]][k[1]] = t[k[1]][k[0]] = c->args[2].r;
    return MOTE_OK;
}

static int do_contact(void *vm, const mote_call *c, mote_err *err)
{
    mote_sep_system *s = &((sep_model *)vm)->sys;
    s->hertz = c->args[0].word == 2;
    const mote_arg *r = mote_call_opt(c, "restitution");
    if (r && !s->hertz)
        return mote_call_fail(err, c, mote_call_opt_index(c, "restitution"), MOTE_EINVAL,
                              "contact: restitution= goes with hertz (the linear law's "
                              "restitution is exact)");
    s->e_true = !r || r->word == 1;
    return MOTE_OK;
}

/* wall_mesh file=FILE [the mesh options] [solid=yes] [velocity=] [omega= axis= centre=]: a wall
 * of triangles, read and repaired by the core (mesh.h) on both the dry and the real model, so a
 * bad file fails at check */
static int do_wall_mesh(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    mote_sep_system *s = &m->sys;
    const int fi = mote_call_opt_index(c, "file");
    const char *path = mote_call_opt(c, "file")->path;
    if (s->nmesh == MOTE_SEP_MAX_MESHES)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "wall_mesh: at most %d mesh walls",
                              MOTE_SEP_MAX_MESHES);
    mote_mesh_opts o;
    int rc = mote_mesh_call_opts(c, "wall_mesh", &o, err);
    if (rc)
        return rc;
    const mote_arg *a;
    const double zero[3] = {0, 0, 0};
    const double *vel = (a = mote_call_opt(c, "velocity")) ? a->v : zero;
    const double *axis = (a = mote_call_opt(c, "axis")) ? a->v : zero;
    const double *centre = (a = mote_call_opt(c, "centre")) ? a->v : zero;
    const double omega = mote_call_opt_r(c, "omega", 0);
    if (omega != 0 && (!mote_call_opt(c, "axis") || !mote_call_opt(c, "centre")))
        return mote_call_fail(err, c, mote_call_opt_index(c, "omega"), MOTE_EINVAL,
                              "wall_mesh: omega= turns the wall about a line: give axis=X,Y,Z "
                              "and centre=X,Y,Z too");
    if (omega == 0 && (mote_call_opt(c, "axis") || mote_call_opt(c, "centre")))
        return mote_call_fail(err, c, mote_call_opt_index(c, mote_call_opt(c, "axis") ? "axis"
                                                                                      : "centre"),
                              MOTE_EINVAL, "wall_mesh: axis= and centre= go with omega=");
    for (int q = 0; q < 3; q++)
        if (!isfinite(vel[q]) || !isfinite(axis[q]) || !isfinite(centre[q]) ||
            !isfinite(omega))
            return mote_call_fail(err, c, -1, MOTE_EINVAL, "wall_mesh: velocity=, omega=, "
                                  "axis= and centre= must be finite");
    mote_mesh mesh = {0};
    mote_mesh_report rep;
    rc = mote_mesh_load(&mesh, path, &o, &rep, err);
    if (!rc)
        rc = sep_mesh_add(s, &mesh, path, (a = mote_call_opt(c, "solid")) && a->i == 1, vel,
                          axis, omega, centre, err);
    mote_mesh_free(&mesh);
    if (rc) { /* (the file's name, and line, are in the message) */
        char why[sizeof err->msg];
        snprintf(why, sizeof why, "%s", err->msg);
        return mote_call_fail(err, c, fi, (mote_status)rc, "wall_mesh: %s", why);
    }
    if (m->log && !m->dry)
        mote_mesh_report_line(m->log, "wall_mesh", path, &rep);
    return MOTE_OK;
}

static int do_wall_material(void *vm, const mote_call *c, mote_err *err)
{
    mote_sep_system *s = &((sep_model *)vm)->sys;
    if (!mote_call_opt(c, "E"))
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "wall_material: give E=PASCAL [nu=RATIO]");
    s->E_w = mote_call_opt_r(c, "E", 0);
    s->nu_w = mote_call_opt_r(c, "nu", 0.3);
    return MOTE_OK;
}

static int do_stiffness(void *vm, const mote_call *c, mote_err *err)
{
    mote_sep_system *s = &((sep_model *)vm)->sys;
    const mote_arg *o = mote_call_opt(c, "overlap"), *k = mote_call_opt(c, "khat");
    if (!o == !k)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "stiffness: give overlap=DF [vimp=V] or "
                              "khat=K");
    if (k && mote_call_opt(c, "vimp"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "vimp"), MOTE_EINVAL,
                              "stiffness: vimp= goes with overlap=");
    s->khat = k ? k->r : 0;
    s->delta_f = o ? o->r : 0.05;
    s->v_imp = mote_call_opt_r(c, "vimp", 0);
    return MOTE_OK;
}

static int do_timestep(void *vm, const mote_call *c, mote_err *err)
{
    mote_sep_system *s = &((sep_model *)vm)->sys;
    const mote_arg *nc = mote_call_opt(c, "nc");
    if (c->args[0].word) { /* auto */
        s->dt_user = 0;
        if (nc)
            s->nc = (int)nc->i;
        return MOTE_OK;
    }
    if (nc)
        return mote_call_fail(err, c, mote_call_opt_index(c, "nc"), MOTE_EINVAL,
                              "timestep: nc= goes with auto");
    s->dt_user = c->args[0].r;
    return MOTE_OK;
}

static int do_classes(void *vm, const mote_call *c, mote_err *err)
{
    mote_sep_system *s = &((sep_model *)vm)->sys;
    const int K = (int)c->args[0].i;
    const double lo = mote_call_opt_r(c, "min", 0), hi = mote_call_opt_r(c, "max", 0);
    if ((lo > 0) != (hi > 0) || (lo > 0 && !(hi > lo)))
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "classes: give both min= and max= with "
                              "min < max, or neither");
    free(s->class_edge);
    s->class_edge = NULL;
    sep_tallies_free(s);
    s->nclass = K;
    if (lo > 0) {
        s->class_edge = malloc((size_t)(K + 1) * sizeof *s->class_edge);
        if (!s->class_edge)
            return mote_fail(err, MOTE_ENOMEM, "classes: out of memory");
        for (int k = 0; k <= K; k++)
            s->class_edge[k] = exp(log(lo) + (log(hi) - log(lo)) * k / K);
    }
    return MOTE_OK;
}

/* `classes_file FILE`: explicit class edges, one per row, increasing (spec 3.1). */
static int do_classes_file(void *vm, const mote_call *c, mote_err *err)
{
    mote_sep_system *s = &((sep_model *)vm)->sys;
    const char *path = c->args[0].path;
    mote_table t;
    mote_err e2 = {0};
    int rc = mote_table_read(&t, path, &e2);
    if (rc)
        return mote_call_fail(err, c, 0, rc, "%s", e2.msg);
    for (size_t r = 0; r < t.rows && !rc; r++) {
        const double v = mote_table_at(&t, r, 0);
        if (t.ncol[r] != 1 || !(v > 0) || !isfinite(v) ||
            (r > 0 && !(v > mote_table_at(&t, r - 1, 0))))
            rc = mote_call_fail(err, c, 0, MOTE_EINVAL, "%s:%ld: expected one class edge (m) per "
                                "row, > 0 and increasing", path, t.line[r]);
    }
    if (!rc && (t.rows < 3 || t.rows > 1001))
        rc = mote_call_fail(err, c, 0, MOTE_EINVAL, "%s: 3 to 1001 edges (2 to 1000 classes), "
                            "found %zu", path, t.rows);
    double *e = rc ? NULL : malloc(t.rows * sizeof *e);
    if (!rc && !e)
        rc = mote_fail(err, MOTE_ENOMEM, "classes_file: out of memory");
    if (!rc) {
        for (size_t r = 0; r < t.rows; r++)
            e[r] = mote_table_at(&t, r, 0);
        free(s->class_edge);
        sep_tallies_free(s);
        s->class_edge = e;
        s->nclass = (int)t.rows - 1;
    }
    mote_table_free(&t);
    return rc;
}

/* the checks every command that moves or adds particles needs */
int sep_need_ready(sep_model *m, const mote_call *c, mote_err *err)
{
    mote_err e2 = {0};
    if (mote_sep_prepare(&m->sys, &e2))
        return mote_call_fail(err, c, -1, e2.code, "%s: %s", c->name,
                              e2.msg + (strncmp(e2.msg, "separator: ", 11) ? 0 : 11));
    return MOTE_OK;
}

/* `insert NAME COUNT`, `insert_mass NAME KG`: checked on the dry model, run on the real one */
static int check_insert(void *vm, const mote_call *c, mote_err *err)
{
    sep_model *m = vm;
    if (sep_find_species(&m->sys, c->args[0].text) < 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "%s: no species '%s'", c->name,
                              c->args[0].text);
    if (!(m->sys.zf > 0))
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "%s: give the feed zone first (feed z=)",
                              c->name);
    int rc = sep_need_ready(m, c, err);
    if (!rc && m->dry) /* the estimates' account: the particles it adds */
        m->est_n += strcmp(c->name, "insert") == 0
                        ? (double)c->args[1].i
                        : c->args[1].r / (m->sys.parcel * sep_mean_mass(&m->sys,
                                                        sep_find_species(&m->sys, c->args[0].text)));
    return rc;
}

static int insert(sep_model *m, const mote_call *c, uint64_t count, double mass, mote_err *err)
{
    int rc = check_insert(m, c, err);
    if (!rc)
        rc = mote_sep_insert(&m->sys, sep_find_species(&m->sys, c->args[0].text), count, mass,
                             err);
    if (!rc)
        rc = mote_sep_gas_update(&m->sys, 0, err);
    return rc;
}

static int run_insert(void *vm, const mote_call *c, mote_err *err)
{
    return insert(vm, c, (uint64_t)c->args[1].i, 0, err);
}

static int run_insert_mass(void *vm, const mote_call *c, mote_err *err)
{
    return insert(vm, c, 0, c->args[1].r, err);
}

static int do_average_from(void *vm, const mote_call *c, mote_err *err)
{
    (void)err;
    ((sep_model *)vm)->sys.avg_from = c->args[0].r;
    return MOTE_OK;
}

static int do_reset_stats(void *vm, const mote_call *c, mote_err *err)
{
    (void)c;
    (void)err;
    mote_sep_reset_stats(&((sep_model *)vm)->sys);
    return MOTE_OK;
}

/* ---- the table ------------------------------------------------------------------------------ */

#include "help.inc"


static void *sep_state_fields(void *vm, const struct mote_sf_field **f, size_t *n)
{
    *f = sep_scalar_fields(n);
    return &((sep_model *)vm)->sys;
}

/* The parameter commands bound to a value of the state (the key of its descriptor in state.c's
 * table): what such a command sets is what save writes and load reads (mote_cmd_set). */
static const mote_param sep_params[] = {
    {"gravity", "real g"},
    {"slices", "int K"},
    {"eps_gas_min", "real eps_gas_min"},
    {"relax", "real tau_eps"},
    {"hindered", "real chi"},
    {"dispersion", "real D_t"},
    {"brownian", "real T_gas"},
    {"restitution", "real e_pp"},
    {"restitution_wall", "real e_pw"},
    {"coupling", "int coupling"}, /* (its words off|on: 0, 1) */
    {"collisions", "int dem"},    /* (off|dem) */
    {"neighbours", "int brute"},  /* (cells|brute) */
    {"parcel", "real parcel"},
    {"friction", "real mu_pp"},
    {"friction_wall", "real mu_pw"},
    {"rolling_friction", "real mur_pp"},
    {"rolling_friction_wall", "real mur_pw"},
    {"cohesion", "real coh_pp"},
    {"cohesion_wall", "real coh_pw"},
};
#define SET mote_cmd_set, mote_cmd_set

static const mote_cmd sep_commands[] = {
    {"dim", NULL, "i", "dim 2|3", "the dimension", HELP_DIM, do_dim, do_dim},
    {"channel", NULL, "r>0 r>0 D=r>0", "channel W H [D=DEPTH]", "the channel", HELP_CHANNEL,
     do_channel, do_channel},
    {"depth2d", NULL, "r>0", "depth2d D2", "the nominal 2D depth", HELP_DEPTH2D, do_depth2d,
     do_depth2d},
    {"ends", NULL, "e{open|closed} e{open|closed}", "ends BOTTOM TOP", "open or closed ends", HELP_ENDS, do_ends, do_ends},
    {"gas", NULL, "r>=0 rho=r>=0 mu=r>=0", "gas U0 [rho=R] [mu=M]", "the gas upflow", HELP_GAS,
     do_gas, do_gas},
    {"gravity", NULL, "r>=0", "gravity g", "gravity", HELP_GRAVITY, SET},
    {"coupling", NULL, "e{off|on}", "coupling on|off", "the solids' feedback on the gas", HELP_COUPLING,
     SET},
    {"slices", NULL, "i[10,1000]", "slices K", "the gas model's slices", HELP_SLICES,
     SET},
    {"eps_gas_min", NULL, "r(0,1]", "eps_gas_min V", "the clamp on the gas fraction",
     HELP_EPSMIN, SET},
    {"gas_profile", NULL, "f<gasprofile", "gas_profile FILE", "the gas density along the height",
     HELP_GAS_PROFILE, do_gas_profile, do_gas_profile},
    {"relax", NULL, "r>=0", "relax TAU", "relaxation time of the solids fraction", HELP_RELAX,
     SET},
    {"hindered", NULL, "r>=0", "hindered CHI", "hindered-drag exponent", HELP_HINDERED,
     SET},
    {"dispersion", NULL, "r>=0", "dispersion D", "turbulent dispersion coefficient",
     HELP_DISPERSION, SET},
    {"brownian", NULL, "r>=0", "brownian T", "Brownian diffusion at gas temperature T",
     HELP_DISPERSION, SET},
    {"species", NULL, "@name=s! @density=r>0! E=r>0 nu=r(-1,0.5)",
     "species name=S density=RHO [E=PA nu=0.3]", "a species", HELP_SPECIES, do_species,
     do_species},
    {"size", NULL, "s e{mono|lognormal|rosin_rammler|loguniform|table} d=r>0 d50=r>0 sigma=r>=1 "
     "n=r>0 min=r>0 max=r>0 basis=e{mass|number} file=f<sizes",
     "size NAME TYPE [options]", "a species' size distribution", HELP_SIZE, do_size, do_size},
    {"feed", NULL, "z=r! hf=r>0 rate=r>=0 start=r>=0 stop=r>0", "feed z=Z [hf=] [rate=]",
     "the feed band and rate", HELP_FEED, do_feed, do_feed},
    {"feed_window", NULL, "r>=0 r>0 y1=r>=0 y2=r>0", "feed_window X1 X2 [y1= y2=]", "the feed's extent",
     HELP_FEED_WINDOW, do_feed_window, do_feed_window},
    {"feed_velocity", NULL, "r r vy=r", "feed_velocity VX VZ [vy=]", "new particles' velocity",
     HELP_FEED_VELOCITY, do_feed_velocity, do_feed_velocity},
    {"feed_fraction", NULL, "s r[0,1]", "feed_fraction NAME W", "a species' share of the feed",
     HELP_FEED_FRACTION, do_feed_fraction, do_feed_fraction},
    {"insert", NULL, "s i>=1", "insert NAME COUNT", "a batch of particles", HELP_INSERT,
     check_insert, run_insert},
    {"insert_mass", NULL, "s r>0", "insert_mass NAME KG", "a batch by mass", HELP_INSERT,
     check_insert, run_insert_mass},
    {"grid", NULL, "r>=0 r>0 e{pattern|holes} a=r>0 p=r>0 offset=r>=0 a_y=r>0 p_y=r>0 offset_y=r>=0 file=f<holes",
     "grid ZB T pattern|holes [options]", "a perforated plate", HELP_GRID, do_grid, do_grid},
    {"collisions", NULL, "e{off|dem}", "collisions dem|off", "the collision model", HELP_COLLISIONS,
     SET},
    {"restitution", NULL, "r(0,1]", "restitution E", "restitution between particles",
     HELP_RESTITUTION, SET},
    {"restitution_wall", NULL, "r(0,1]", "restitution_wall E", "restitution at walls",
     HELP_RESTITUTION, SET},
    {"restitution_pair", NULL, "s s r(0,1]", "restitution_pair A B E",
     "restitution between two species", HELP_RESTITUTION, do_pair, do_pair},
    {"contact", NULL, "e{linear|hertz} restitution=e{exact|liggghts}",
     "contact linear|hertz [restitution=exact|liggghts]", "the contact law", HELP_CONTACT,
     do_contact, do_contact},
    {"friction", NULL, "r>=0", "friction MU", "sliding friction between particles",
     HELP_FRICTION, SET},
    {"friction_wall", NULL, "r>=0", "friction_wall MU", "sliding friction at walls and grids",
     HELP_FRICTION, SET},
    {"friction_pair", NULL, "s s r>=0", "friction_pair A B MU",
     "sliding friction between two species", HELP_FRICTION, do_pair, do_pair},
    {"rolling_friction", NULL, "r>=0", "rolling_friction MU_R",
     "rolling friction between particles", HELP_FRICTION, SET},
    {"rolling_friction_wall", NULL, "r>=0", "rolling_friction_wall MU_R",
     "rolling friction at walls and grids", HELP_FRICTION, SET},
    {"rolling_friction_pair", NULL, "s s r>=0", "rolling_friction_pair A B MU_R",
     "rolling friction between two species", HELP_FRICTION, do_pair, do_pair},
    {"cohesion", NULL, "r>=0", "cohesion K", "cohesion between particles (SJKR)",
     HELP_COHESION, SET},
    {"cohesion_wall", NULL, "r>=0", "cohesion_wall K", "cohesion at walls and grids",
     HELP_COHESION, SET},
    {"cohesion_pair", NULL, "s s r>=0", "cohesion_pair A B K", "cohesion between two species",
     HELP_COHESION, do_pair, do_pair},
    {"wall_mesh", NULL,
     "file=f<mesh! " MOTE_MESH_CALL_OPTS " solid=e{no|yes} velocity=v3 omega=r axis=v3 centre=v3",
     "wall_mesh file=FILE [options]", "a wall of triangles from a mesh file", HELP_WALL_MESH,
     do_wall_mesh, do_wall_mesh},
    {"wall_material", NULL, "E=r>0 nu=r(-1,0.5)", "wall_material E=PA [nu=0.3]",
     "the walls' and grids' elastic constants", HELP_CONTACT, do_wall_material,
     do_wall_material},
    {"stiffness", NULL, "overlap=r(0,0.1] vimp=r>0 khat=r>0",
     "stiffness [overlap=DF] [vimp=V] [khat=K]", "the contact stiffness",
     HELP_STIFFNESS, do_stiffness, do_stiffness},
    {"neighbours", NULL, "e{cells|brute}", "neighbours cells|brute", "the neighbour search",
     HELP_NEIGHBOURS, SET},
    {"parcel", NULL, "r>=1", "parcel W", "each particle stands for W of its size (dilute mode)",
     HELP_PARCEL, SET},
    {"timestep", NULL, "r>0{auto} nc=i>=20", "timestep auto|DT [nc=50]", "the time step",
     HELP_TIMESTEP, do_timestep, do_timestep},
    {"classes", NULL, "i[2,1000] min=r>0 max=r>0", "classes K [min=A max=B]",
     "the Tromp size classes", HELP_CLASSES, do_classes, do_classes},
    {"classes_file", NULL, "f<classes", "classes_file FILE", "the Tromp size classes from a file",
     HELP_CLASSES_FILE, do_classes_file, do_classes_file},
    {"run", NULL, "r>0", "run T", "advance the simulated time", HELP_RUN, sep_check_run, sep_run},
    {"tromp", NULL, "@file=f>tromp!", "tromp file=FILE", "write the grade-efficiency curve", HELP_TROMP,
     sep_check_table, sep_tromp},
    {"profiles", NULL, "@file=f>profiles!", "profiles file=FILE", "write the profiles along the height",
     HELP_PROFILES, sep_check_table, sep_profiles},
    {"average_from", NULL, "r>=0", "average_from T", "start of the profile averaging",
     HELP_AVERAGE_FROM, do_average_from, do_average_from},
    {"reset_stats", NULL, "", "reset_stats", "start a new statistics window", HELP_RESET_STATS,
     do_reset_stats, do_reset_stats},
    {"frames", NULL, "@dir=f @dt=r>0 prefix=f every=i>=1 px=i[16,16384] color=e{size|species} "
     "y1=r y2=r movie=e{on|off} fps=i[1,1000]",
     "frames dt=DT|every=K [prefix=P|dir=DIR] [options]", "PNG pictures on a schedule, and the movie", HELP_FRAMES,
     sep_frames, sep_frames},
    {"live_png", NULL, "@file=f>image! hz=r>0 px=i[16,16384] color=e{size|species}",
     "live_png file=FILE [hz=30]",
     "a picture rewritten while runs go on", HELP_LIVE, sep_live_png, sep_live_png},
    {"snapshot", "snapshots", "@dir=f @dt=r>0 prefix=f every=i>=1 file=f>xyz format=e{xyz|h5md|vtk}",
     "snapshot file=FILE|dt=DT|every=K [prefix=P|dir=DIR] [format=xyz|h5md|vtk]",
     "an extended XYZ (or H5MD, VTK) snapshot now, or on a schedule",
     HELP_SNAPSHOTS, sep_snapshots, sep_snapshots},
    {"monitor", "balance", "@file=f>balance! @dt=r>0 every=i>=1 format=e{table|csv|jsonl}",
     "monitor file=FILE dt=DT|every=K [format=table|csv|jsonl]", "the bookkeeping time series",
     HELP_BALANCE, sep_balance, sep_balance},
    {"trajectory", NULL, "@every=i>=1 @file=f>xyz! dt=r>0 format=e{xyz|h5md}",
     "trajectory every=K|dt=T file=FILE.xyz|FILE.h5 [format=xyz|h5md]",
     "particle paths: an XYZ frame every K steps or T s of the following runs, appended",
     HELP_TRAJECTORY, sep_trajectory, sep_trajectory},
    MOTE_CMD_STOP(trajectory, NULL, sep_trajectory_stop, sep_trajectory_stop),
    MOTE_CMD_STOP(frames, NULL, sep_frames_stop, sep_frames_stop),
    MOTE_CMD_STOP(snapshot, NULL, sep_snapshot_stop, sep_snapshot_stop),
    MOTE_CMD_STOP(monitor, NULL, sep_monitor_stop, sep_monitor_stop),
    {"checkpoint", NULL, "every=i>=1! file=f>state!", "checkpoint every=K file=FILE",
     "keep the exact state in FILE every K time steps (load continues from it)",
     HELP_CHECKPOINT, sep_checkpoint, sep_checkpoint},
    MOTE_CMD_STOP(checkpoint, NULL, sep_checkpoint_stop, sep_checkpoint_stop),
    {"save", NULL, "f>state", "save FILE", "write the whole state", HELP_SAVE, sep_check_ready, sep_save},
    {"load", NULL, "f<state", "load FILE", "continue from a saved state", HELP_SAVE, sep_check_load,
     sep_load},
    {"summary", NULL, "", "summary", "print the status and the bookkeeping", HELP_SUMMARY,
     NULL, sep_summary},
};

/* The particles as arrays: positions and velocities (copies, rows of x y z), radii (d/2),
 * masses and species (views); with contact hertz the angular velocities (a view, rows of
 * x y z; 2D: about y). */
static int sep_model_arrays(void *vm, mote_array *out, int cap)
{
    mote_sep_system *s = &((sep_model *)vm)->sys;
    if (cap < 5)
        return 0;
    const double *x[3] = {s->x, s->y, s->z}, *v[3] = {s->vx, s->vy, s->vz}, *d[1] = {s->d};
    int k = 0;
    if (!mote_array_gather(&out[k], "positions", "m", x, 3, s->n, 1.0) && ++k &&
        !mote_array_gather(&out[k], "velocities", "m/s", v, 3, s->n, 1.0) && ++k &&
        !mote_array_gather(&out[k], "radii", "m", d, 1, s->n, 0.5) && ++k) {
        mote_array_view(&out[3], "masses", "kg", s->m, 'd', s->n, 1);
        mote_array_view(&out[4], "species", "index of `species`", s->s, 'i', s->n, 1);
        if (!(s->hertz && s->w && cap >= 6))
            return 5;
        mote_array_view(&out[5], "angular_velocities", "rad/s", s->w, 'd', s->n, 3);
        return 6;
    }
    while (k-- > 0)
        free(out[k].data);
    return -1;
}

/* set_array: positions or velocities (rows of x y z), finite (speeds up to MOTE_SEP_SPEED_MAX, as a
 * state file's), centres inside the channel (x in
 * [0, W], z in [0, H], in 3D y in [0, D]), not inside a plate's solid; new positions make the pair
 * list be built again. */
static int sep_model_set_array(void *vm, const char *name, const double *v, size_t rows,
                               size_t cols, mote_err *err)
{
    mote_sep_system *s = &((sep_model *)vm)->sys;
    const int pos = !strcmp(name, "positions"), vel = !strcmp(name, "velocities");
    if (!pos && !vel)
        return mote_fail(err, MOTE_EINVAL, "set %s: the separator model sets positions or "
                         "velocities", name);
    if (rows != s->n || cols != 3)
        return mote_fail(err, MOTE_EINVAL, "set %s: expected %zu x 3 numbers (one row per "
                         "particle), found %zu x %zu", name, s->n, rows, cols);
    const double hi[3] = {s->W, s->dim == 3 ? s->D : INFINITY, s->H};
    for (size_t i = 0; i < rows; i++)
        for (int a = 0; a < 3; a++) {
            const double x = v[3 * i + (size_t)a];
            if (!isfinite(x))
                return mote_fail(err, MOTE_EINVAL, "set %s: particle %zu: %c = %g is not finite",
                                 name, i, "xyz"[a], x);
            if (vel && !(fabs(x) <= MOTE_SEP_SPEED_MAX))
                return mote_fail(err, MOTE_EINVAL, "set velocities: particle %zu: v%c = %g m/s "
                                 "is beyond %g m/s", i, "xyz"[a], x, MOTE_SEP_SPEED_MAX);
            if (pos && (a != 1 || s->dim == 3) && !(x >= 0 && x <= hi[a]))
                return mote_fail(err, MOTE_EINVAL, "set positions: particle %zu: %c = %g is "
                                 "outside the channel [0, %g]", i, "xyz"[a], x, hi[a]);
        }
    for (size_t i = 0; pos && i < rows; i++) /* a centre inside a plate's solid: no way out */
        for (int q = 0; q < s->nplate; q++) {
            const double c[3] = {v[3 * i], s->dim == 3 ? v[3 * i + 1] : 0, v[3 * i + 2]};
            double delta[4], nrm[4][3];
            if (mote_sep_plate_features(&s->plate[q], s->dim, c, 0.5 * s->d[i], delta, nrm) < 0)
                return mote_fail(err, MOTE_EINVAL, "set positions: particle %zu: its centre "
                                 "(x = %g, z = %g) is inside the solid of plate %d (z from %g "
                                 "to %g), not in a hole", i, c[0], c[2], q + 1,
                                 s->plate[q].zb, s->plate[q].zb + s->plate[q].t);
        }
    for (size_t i = 0; pos && i < rows; i++) { /* a centre inside a solid mesh wall */
        const double c[3] = {v[3 * i], s->dim == 3 ? v[3 * i + 1] : 0, v[3 * i + 2]};
        const int k = s->nmesh ? sep_mesh_blocks(s, s->t, c, 0) : 0;
        if (k)
            return mote_fail(err, MOTE_EINVAL, "set positions: particle %zu: its centre (%g, %g, "
                             "%g) is inside the solid wall %d (%s)", i, c[0], c[1], c[2], k,
                             s->mesh[k - 1].name);
    }
    double *dst[3] = {pos ? s->x : s->vx, pos ? s->y : s->vy, pos ? s->z : s->vz};
    for (size_t i = 0; i < rows; i++)
        for (int a = 0; a < 3; a++)
            dst[a][i] = v[3 * i + (size_t)a];
    if (pos)
        s->list_ok = 0; /* (the pair list is built again at the next step) */
    return MOTE_OK;
}

/* `picture FILE.png`: the picture of `frames`, now, with its defaults. */
static int model_picture(void *vm, const char *path, mote_err *err)
{
    const sep_model *m = vm;
    const sep_frame_opts fo = {.px = 900};
    return sep_frame_png(&m->sys, path, &fo, err);
}

/* The channel: W wide, D deep (2D: the nominal depth, as the XYZ files' Lattice), H high. */
static int model_cell(void *vm, double edges[3], double origin[3], int periodic[3])
{
    const mote_sep_system *s = &((sep_model *)vm)->sys;
    if (!(s->W > 0 && s->H > 0))
        return -1;
    double dmin, dmax;
    mote_sep_size_range(s, &dmin, &dmax);
    const double e[3] = {s->W, s->dim == 3 ? s->D : s->D2 > 0 ? s->D2 : dmax, s->H};
    for (int a = 0; a < 3; a++) {
        edges[a] = e[a];
        origin[a] = 0;
        periodic[a] = 0;
    }
    return 0;
}

const mote_model mote_model_separator = {
    .name = "separator",
    .summary = "gravitational separator: particles in a gas upflow, the grade-efficiency curve",
    .threaded = 1,
    .cmds = sep_commands,
    .ncmds = sizeof sep_commands / sizeof sep_commands[0],
    .create = model_create,
    .destroy = model_destroy,
    .seed = model_seed,
    .seed_help = "The feed draws from the stream: each particle's species and size, then its\n"
                 "position tries.\n",
    .plot_lines = "separator-tromp:d_mean_m,T_mass,sigma_T,log separator-profiles:z_m,eps_s",
    .status = sep_status,
    .live = sep_model_live,
    .arrays = sep_model_arrays,
    .set_array = sep_model_set_array,
    .state = sep_state_fields,
    .params = sep_params,
    .nparams = sizeof sep_params / sizeof sep_params[0],
    .cell = model_cell,
    .picture = model_picture,
    .picture_help = "The picture of `frames` with its defaults: the channel seen from the front,\n"
                    "each particle a disc of its size coloured by its diameter (log scale), the\n"
                    "plates; the time and the counts fed and classified under the title.\n",
};
