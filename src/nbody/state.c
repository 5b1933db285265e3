/* state.c: the N-body model's state file (save / load): everything a continuation needs, every
 * number to the digits that read back to the same value (17 for double, 21 for long double, 36
 * for quad: MOTE_REAL_DIG; the SI scales to 17), the compensation terms,
 * the previous fifth derivative and step of the Galactica scheme and the monitor references
 * included, so `A; save F; load F; B` runs bit for bit like `A; B`. The reader is strict: a
 * malformed file is refused with FILE:LINE and what was expected, and nothing is allocated for
 * bodies before their lines are counted. */
#include "mote/nbody.h"

#include <assert.h>
#include <errno.h>
#include <tgmath.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define NB_STATE_VERSION 4 /* 4: each integrator's own lines; 3: the map's values and a map
                            * block; 2: a name ends each body line, a doubling line (1: neither) */

#include "mote/statefile.h"

#include <stddef.h>

#include "nb.h"

/* ---- the descriptor tables (statefile.h) --------------------------------------------------------- */

/* mote_real to the digits that read back the same (MOTE_REAL_DIG) */
static void real_put(char out[64], const void *v)
{
    char b[MOTE_REAL_BUF];
    snprintf(out, 64, "%s", mote_real_str(*(const mote_real *)v, b));
}
static size_t real_get(const char *t, void *v)
{
    char *end;
    *(mote_real *)v = mote_real_parse(t, &end);
    return (size_t)(end - t);
}
static int real_finite(const void *v) { return isfinite(*(const mote_real *)v) != 0; }
const mote_sf_codec nb_real_codec = {sizeof(mote_real), real_put, real_get, real_finite};
#define REAL nb_real_codec

/* the interaction and the count: the head, read alone by nb_state_peek */
typedef struct {
    int kind;
    uint32_t n;
} nb_head;
static const mote_sf_field HEAD[] = {
    {.key = "interaction", .name = "KIND", .type = MOTE_SF_ENUM,
     .offset = offsetof(nb_head, kind), .words = "gravity|coulomb"},
    {.key = "n", .name = "N", .type = MOTE_SF_U32, .offset = offsetof(nb_head, n), .lo = 0,
     .hi = 1e8},
};

#define SF_R NB_SF_R
#define SF_I NB_SF_I
#define SF_RS(K, NAME, M, S)                                                                 \
    {.key = K, .name = NAME, .type = MOTE_SF_CODEC, .offset = offsetof(mote_nb, M),          \
     .codec = &REAL, .since = S}
#define SF_IS(K, NAME, M, LO, HI, S)                                                         \
    {.key = K, .name = NAME, .type = MOTE_SF_INT, .offset = offsetof(mote_nb, M), .lo = LO,  \
     .hi = HI, .since = S}
#define SF_U64(K, NAME, M)                                                                   \
    {.key = K, .name = NAME, .type = MOTE_SF_U64, .offset = offsetof(mote_nb, M),            \
     .lo = MOTE_SF_ANY}
#define SF_D(K, NAME, M)                                                                     \
    {.key = K, .name = NAME, .type = MOTE_SF_DOUBLE, .offset = offsetof(mote_nb, M),         \
     .lo = MOTE_SF_ANY}
#define COUNT(t) (sizeof t / sizeof t[0])

/* The run's state after the head, in the order of the file (version 4): the common lines (the
 * time, the step and its controller, the scheme: which integrator, the compensation, the
 * softening, the restart and the step count), then every integrator's own lines
 * (nb_integrator.fields, integrators.c), then the common lines of TAIL. */
static const mote_sf_field COMMON[] = {
    SF_R("time", "T", T), SF_R(NULL, "Tc", Tc),
    SF_R("step", "dt", dt), SF_R(NULL, "dtp", dtp), SF_R(NULL, "first_step", first_step),
    SF_R(NULL, "hlast", hlast), SF_I(NULL, "adaptive", adaptive, 0, MOTE_NB_NORM_GLOBAL),
    SF_R(NULL, "tol", tol), SF_R(NULL, "safety", safety), SF_R(NULL, "hmin", hmin),
    SF_R(NULL, "hmax", hmax), SF_R(NULL, "hprev", hprev),
    SF_I("scheme", "integrator", integrator, MOTE_NB_GALACTICA, MOTE_NB_WH),
    SF_I(NULL, "compensated", compensated, 0, 1), SF_R(NULL, "softening", soft),
    SF_I(NULL, "restart", restart, 0, 1), SF_U64(NULL, "steps", steps),
};
static const mote_sf_field TAIL[] = {
    SF_I("merging", "mode", merging, -1, 1), SF_U64(NULL, "merges", merges),
    SF_U64(NULL, "warnings", approach_warnings), SF_R(NULL, "E_heat", e_heat),
    SF_R(NULL, "E_spin", e_spin), SF_R(NULL, "dE_merge", de_merge), SF_R(NULL, "bt", bt),
    SF_R(NULL, "hmin", bt_hmin), SF_R(NULL, "happ", happ), SF_R(NULL, "max_overlap", max_overlap),
    SF_I("reference", "set", ref_set, 0, 1), SF_R(NULL, "E0", E0), SF_R(NULL, "Mza1", Mza1),
    SF_R(NULL, "Lnorm1", Lnorm1),
    /* (the first files of version 1 end the line before L1) */
    {.name = "L1", .type = MOTE_SF_CODEC, .offset = offsetof(mote_nb, L1), .count = 3,
     .codec = &REAL, .optional = 1},
    SF_I("units", "set", u.set, 0, 1), SF_D(NULL, "M", u.M), SF_D(NULL, "Am", u.Am), SF_D(NULL, "kv", u.kv),
    SF_D(NULL, "kt", u.kt), SF_D(NULL, "G", u.G), SF_D(NULL, "e2", u.e2), SF_D(NULL, "eps", u.eps),
    SF_D(NULL, "Am_first", u.Am_first),
};
/* Versions 1 to 3 (read only): one scheme line and one taylor line held several integrators'
 * values; these lines came before TAIL. */
static const mote_sf_field OLD[] = {
    SF_R("time", "T", T), SF_R(NULL, "Tc", Tc),
    SF_R("step", "dt", dt), SF_R(NULL, "dtp", dtp), SF_R(NULL, "first_step", first_step),
    SF_R(NULL, "hlast", hlast),
    SF_I("scheme", "order", order, 2, 6), SF_I(NULL, "compensated", compensated, 0, 1),
    SF_I(NULL, "restart", restart, 0, 1), SF_U64(NULL, "steps", steps),
    SF_I("taylor", "integrator", integrator, MOTE_NB_GALACTICA, MOTE_NB_WH),
    SF_I(NULL, "order", taylor_order, 2, MOTE_NB_TAYLOR_MAX), SF_I(NULL, "memory", taylor_memory, 0, 2),
    SF_I(NULL, "adaptive", adaptive, 0, MOTE_NB_NORM_GLOBAL), SF_R(NULL, "tol", tol),
    SF_R(NULL, "safety", safety), SF_R(NULL, "hmin", hmin), SF_R(NULL, "hmax", hmax),
    SF_R(NULL, "hprev", hprev),
    /* the Wisdom-Holman map's corrector, and whether a map follows the bodies (its step and
     * corrector), from version 3 */
    SF_IS(NULL, "wh_corrector", wh_corrector, 0, 17, 3), SF_IS(NULL, "wh_live", wh_live, 0, 1, 3),
    SF_RS(NULL, "wh_h", wh_h, 3), SF_IS(NULL, "wh_k", wh_k, 0, 17, 3),
    SF_RS(NULL, "softening", soft, 3),
    /* Galactica's literal step rule (step=doubling), from version 2 */
    SF_IS("doubling", "on", doubling, 0, 1, 2), SF_IS(NULL, "have", dbl_have, 0, 1, 2),
    SF_IS(NULL, "count", dbl_count, 0, 4, 2), SF_RS(NULL, "dt_max", dt_max, 2),
    SF_RS(NULL, "dMz_prev", dbl_prev, 2), SF_RS(NULL, "sum", dbl_sum, 2), SF_RS(NULL, "mean", dbl_mean, 2),
};

static size_t append(mote_sf_field *out, size_t n, const mote_sf_field *f, size_t k)
{
    assert(n + k <= NB_STATE_FIELDS); /* (a new line's values: raise NB_STATE_FIELDS) */
    memcpy(out + n, f, k * sizeof *f);
    return n + k;
}
/* The table of a file of `version` into out (NB_STATE_FIELDS entries); its length. */
static size_t table_of(int version, mote_sf_field *out)
{
    size_t n = 0;
    if (version <= 3) {
        n = append(out, n, OLD, COUNT(OLD));
    } else {
        n = append(out, n, COMMON, COUNT(COMMON));
        for (int id = 0; id < NB_INTEGRATORS; id++)
            n = append(out, n, nb_integrator_of(id)->fields, nb_integrator_of(id)->nfields);
    }
    return append(out, n, TAIL, COUNT(TAIL));
}
size_t nb_state_table(mote_sf_field *out) { return table_of(NB_STATE_VERSION, out); }

/* a body's line */
typedef struct {
    mote_real m, q;
    int active;
    mote_real ra, x[3], v[3], xc[3], vc[3], sp[3], d5[3], et;
    char name[MOTE_NB_NAME];
} nb_row;
#define BR(K, NAME, M, C)                                                                    \
    {.key = K, .name = NAME, .type = MOTE_SF_CODEC, .offset = offsetof(nb_row, M), .count = C, \
     .codec = &REAL}
static const mote_sf_field ROW[] = {
    BR("", "m", m, 1), BR(NULL, "q", q, 1),
    {.name = "active", .type = MOTE_SF_INT, .offset = offsetof(nb_row, active), .lo = 0, .hi = 1},
    BR(NULL, "radius", ra, 1), BR(NULL, "x", x, 3), BR(NULL, "v", v, 3), BR(NULL, "cx", xc, 3),
    BR(NULL, "cv", vc, 3), BR(NULL, "s", sp, 3), BR(NULL, "d5", d5, 3), BR(NULL, "Et", et, 1),
    {.name = "name", .type = MOTE_SF_WORD, .offset = offsetof(nb_row, name),
     .size = MOTE_NB_NAME, .since = 2},
};
/* a line of the Wisdom-Holman map (version 3, while wh_live): a body's Jacobi q and u */
typedef struct {
    mote_real q[3], u[3];
} nb_maprow;
static const mote_sf_field MAPROW[] = {
    {.key = "", .name = "jq", .type = MOTE_SF_CODEC, .offset = offsetof(nb_maprow, q),
     .count = 3, .codec = &REAL},
    {.name = "ju", .type = MOTE_SF_CODEC, .offset = offsetof(nb_maprow, u), .count = 3,
     .codec = &REAL},
};
void nb_state_put(FILE *f, const mote_nb *nb)
{
    mote_sf_write_head(f, "nbody", NB_STATE_VERSION);
    nb_head h = {nb->kind, nb->n};
    mote_sf_write(f, HEAD, COUNT(HEAD), &h, NB_STATE_VERSION);
    mote_sf_field table[NB_STATE_FIELDS];
    mote_sf_write(f, table, nb_state_table(table), nb, NB_STATE_VERSION);
    fprintf(f, "bodies: m q active radius x y z vx vy vz cx cy cz cvx cvy cvz sx sy sz d5x d5y "
               "d5z Et name\n");
    for (uint32_t i = 0; i < nb->n; i++) {
        nb_row r;
        memset(&r, 0, sizeof r);
        r.m = nb->m[i];
        r.q = nb->q[i];
        r.active = nb->active[i];
        r.ra = nb->ra[i];
        for (int a = 0; a < 3; a++) {
            const size_t k = 3 * (size_t)i + (size_t)a;
            r.x[a] = nb->x[k];
            r.v[a] = nb->v[k];
            r.xc[a] = nb->xc[k];
            r.vc[a] = nb->vc[k];
            r.sp[a] = nb->sp[k];
            r.d5[a] = nb->d5p[k];
        }
        r.et = nb->et[i];
        memcpy(r.name, nb->name[i], MOTE_NB_NAME);
        mote_sf_write(f, ROW, COUNT(ROW), &r, NB_STATE_VERSION);
    }
    if (nb->wh_live && nb->wh_cap >= nb->n) { /* the Wisdom-Holman map's own state */
        fprintf(f, "map: jqx jqy jqz jux juy juz\n");
        for (uint32_t i = 0; i < nb->n; i++) {
            nb_maprow r;
            memcpy(r.q, nb_wh_map(nb, i), sizeof r.q);
            memcpy(r.u, nb_wh_map(nb, i) + 3, sizeof r.u);
            mote_sf_write(f, MAPROW, COUNT(MAPROW), &r, NB_STATE_VERSION);
        }
    }
    fprintf(f, "end\n");
}

int nb_state_save(const mote_nb *nb, const char *path, mote_err *err)
{
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc)
        return rc;
    nb_state_put(af.f, nb);
    return mote_afile_commit(&af, err);
}

/* ---- reading ------------------------------------------------------------------------------------ */

/* What is wrong with the values of the line `key` of a file of `version` just read into t
 * (nonzero: why into why): the common lines' checks here, an integrator's own lines' its own. */
static int line_bad(const mote_nb *t, const char *key, int version, char *why, size_t size)
{
    if (!strcmp(key, "step") && !(t->dt > 0 && t->dtp >= 0 && t->first_step > 0 &&
                                  t->first_step <= 1))
        return snprintf(why, size, "need dt > 0, dtp >= 0, 0 < first_step <= 1"), 1;
    if (!strcmp(key, "scheme") && version >= 4 && !(t->soft >= 0))
        return snprintf(why, size, "scheme: need softening >= 0 (found %g)", (double)t->soft), 1;
    if (!strcmp(key, "taylor") && version == 3 && !(t->soft >= 0 && t->wh_h >= 0))
        return snprintf(why, size, "taylor: need softening >= 0 and wh_h >= 0 (found %g, %g)",
                        (double)t->soft, (double)t->wh_h), 1;
    if (!strcmp(key, "merging") && !(t->bt > 0 && t->bt <= 1 && t->bt_hmin > 0 &&
                                     t->bt_hmin <= 1 && t->happ >= 0 && t->max_overlap >= 0 &&
                                     t->max_overlap <= 1))
        return snprintf(why, size, "merging: need 0 < bt <= 1, 0 < hmin <= 1, happ >= 0, "
                        "0 <= max_overlap <= 1"), 1;
    for (int id = 0; id < NB_INTEGRATORS; id++) {
        const nb_integrator *in = nb_integrator_of(id);
        for (size_t k = 0; k < in->nfields; k++)
            if (in->fields[k].key && !strcmp(in->fields[k].key, key))
                return in->state_bad(t, key, why, size);
    }
    return 0;
}

/* The lines of f[0 .. n) into t, each line checked as it is read. */
static int read_lines(mote_lines *l, const mote_sf_field *f, size_t n, mote_nb *t, int version,
                      mote_err *err)
{
    for (size_t k = 0, e; k < n; k = e) {
        for (e = k + 1; e < n && !f[e].key; e++)
            ;
        char why[200];
        int rc = mote_sf_read(l, f + k, e - k, t, version, err);
        if (!rc && line_bad(t, f[k].key, version, why, sizeof why))
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: %s", l->path, l->line, why);
        if (rc)
            return rc;
    }
    return MOTE_OK;
}

static int fail(mote_lines *l, mote_err *err, const char *what, const char *found)
{
    return mote_fail(err, MOTE_EFORMAT, "%s:%ld: expected %s (found '%.60s')", l->path, l->line,
                     what, found ? found : "end of file");
}

/* The head: version, model, interaction, n. */
static int read_head(mote_lines *l, nb_head *h, int *version, mote_err *err)
{
    int rc = mote_sf_read_head(l, "nbody", NB_STATE_VERSION, version, err);
    return rc ? rc : mote_sf_read(l, HEAD, COUNT(HEAD), h, *version, err);
}

int nb_state_peek(const char *path, uint32_t *n, mote_err *err)
{
    mote_lines lines;
    int rc = mote_lines_open(&lines, path, err);
    if (rc)
        return rc;
    nb_head h = {0, 0};
    int version;
    rc = read_head(&lines, &h, &version, err);
    *n = h.n;
    int crc = mote_lines_close(&lines, err);
    return crc ? crc : rc;
}

int nb_state_load(mote_nb *nb, const char *path, mote_err *err)
{
    mote_lines lines;
    int rc = mote_lines_open(&lines, path, err);
    if (rc)
        return rc;
    rc = nb_state_get(nb, &lines, 0, err);
    int crc = mote_lines_close(&lines, err);
    return crc ? crc : rc;
}

/* The pointers of t (a scratch system read into by the table, which overwrites every field the
 * file holds: they are kept apart and put back). */
/* The n body lines into t, counted as read: nothing is allocated for lines that are not there. */
static int read_bodies(mote_lines *l, mote_nb *t, uint32_t n, int version, mote_err *err)
{
    const char *path = l->path;
    char *s;
    int rc = MOTE_OK;
    for (uint32_t i = 0; i < n && !rc; i++) {
        s = mote_lines_next(l);
        if (!s || strcmp(s, "end") == 0) {
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: file ends early: n = %u, but only %u body "
                           "lines follow", path, s ? l->line : l->line + 1, n, i);
            break;
        }
        nb_row w;
        memset(&w, 0, sizeof w);
        mote_err e2 = {0};
        rc = mote_sf_parse_line(l, s, ROW, COUNT(ROW), &w, version, &e2);
        if (!rc && w.name[0] && !mote_nb_name_ok(w.name))
            rc = mote_fail(&e2, MOTE_EFORMAT, "'%s' is not a body name", w.name);
        if (rc) {
            const char *why = e2.msg; /* (the detail, without "PATH:LINE: ") */
            const size_t pl = strlen(path);
            if (strncmp(why, path, pl) == 0 && why[pl] == ':') {
                const char *c = strchr(why + pl + 1, ':');
                why = c && c[1] == ' ' ? c + 2 : why;
            }
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: body %u: expected 23 numbers (m q active "
                           "radius x y z vx vy vz cx cy cz cvx cvy cvz sx sy sz d5x d5y d5z Et), "
                           "all finite%s (%s)", path, l->line, i + 1,
                           version >= 2 ? ", and a name or -" : "", why);
            break;
        }
        /* a merged-away body has mass 0: added with mass 1, then set (it stays inactive) */
        rc = w.active == 0 && w.m == 0 ? mote_nb_add(t, 1, 0, w.x, w.v, 0, err)
                                       : mote_nb_add(t, w.m, w.q, w.x, w.v, w.ra, err);
        if (!rc && w.active == 0 && w.m == 0)
            t->m[i] = t->q[i] = 0;
        if (!rc)
            t->et[i] = w.et;
        if (!rc && w.name[0])
            rc = mote_nb_set_name(t, i, w.name, err);
        if (rc) {
            char why[sizeof err->msg];
            snprintf(why, sizeof why, "%s", err->msg);
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: %s", path, l->line, why);
            break;
        }
        t->active[i] = (uint8_t)w.active;
        for (int a = 0; a < 3; a++) {
            t->xc[3 * i + a] = w.xc[a];
            t->vc[3 * i + a] = w.vc[a];
            t->sp[3 * i + a] = w.sp[a];
            t->d5p[3 * i + a] = w.d5[a];
        }
    }
    return rc;
}

/* The Wisdom-Holman map: a line per body (its room only now that the bodies were there), with
 * the bodies it was synchronised to. */
static int read_map(mote_lines *l, mote_nb *t, uint32_t n, int version, mote_err *err)
{
    const char *path = l->path;
    char *s;
    int rc = MOTE_OK;
    s = mote_lines_next(l);
    if (!s || strncmp(s, "map:", 4) != 0)
        rc = fail(l, err, "'map: ...' (wh_live is 1: the Wisdom-Holman map follows)", s);
    else if (!nb_wh_reserve(t))
        rc = mote_fail(err, MOTE_ENOMEM, "%s: out of memory for %u bodies", path, n);
    for (uint32_t i = 0; i < n && !rc; i++) {
        nb_maprow w;
        s = mote_lines_next(l);
        if (!s || strcmp(s, "end") == 0)
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: file ends early: n = %u, but only %u "
                           "map lines follow", path, s ? l->line : l->line + 1, n, i);
        else if (mote_sf_parse_line(l, s, MAPROW, COUNT(MAPROW), &w, version, err))
            rc = MOTE_EFORMAT;
        else {
            mote_real *p = nb_wh_map(t, i);
            memcpy(p, w.q, sizeof w.q);
            memcpy(p + 3, w.u, sizeof w.u);
            memcpy(p + 6, t->x + 3 * (size_t)i, 3 * sizeof *p);
            memcpy(p + 9, t->v + 3 * (size_t)i, 3 * sizeof *p);
            p[12] = t->active[i] ? t->m[i] : 0;
        }
    }
    return rc;
}

int nb_state_get(mote_nb *nb, mote_lines *l, int tail, mote_err *err)
{
    const char *path = l->path;
    nb_head h = {0, 0};
    int version = NB_STATE_VERSION;
    int rc = read_head(l, &h, &version, err);
    if (!rc && h.kind != (int)nb->kind)
        rc = mote_fail(err, MOTE_EINVAL, "%s:3: the state is a %s run, this script is a %s run",
                       path, h.kind == MOTE_NB_GRAVITY ? "gravity" : "Coulomb",
                       nb->kind == MOTE_NB_GRAVITY ? "gravity" : "Coulomb");
    if (rc)
        return rc;
    mote_nb t;
    mote_nb_init(&t, (mote_nb_interaction)h.kind);
    /* the lines up to the bodies, each checked as it is read */
    mote_sf_field table[NB_STATE_FIELDS];
    const size_t nt = table_of(version, table);
    t.L1[0] = NAN; /* (stays NaN when the reference line ends before L1) */
    rc = read_lines(l, table, nt, &t, version, err);
    const int l1_missing = isnan(t.L1[0]);
    char *s = NULL;
    if (!rc) {
        s = mote_lines_next(l);
        if (!s || strncmp(s, "bodies:", 7) != 0)
            rc = fail(l, err, "'bodies: ...' (the column names)", s);
    }
    /* mote_nb_add marks a restart and drops the reference: the file's values are put back after */
    const int file_restart = t.restart, file_ref = t.ref_set, file_live = t.wh_live;
    const mote_real file_dtp = t.dtp;
    if (!rc)
        rc = read_bodies(l, &t, h.n, version, err);
    if (!rc && file_live)
        rc = read_map(l, &t, h.n, version, err);
    if (!rc) {
        s = mote_lines_next(l);
        if (!s || strcmp(s, "end") != 0)
            rc = fail(l, err, "'end' after the bodies", s);
        else if (!tail && (s = mote_lines_next(l)) != NULL)
            rc = fail(l, err, "nothing after 'end'", s);
    }
    if (rc) {
        mote_nb_free(&t);
        return rc;
    }
    t.wh_live = file_live;
    t.restart = file_restart;
    t.ref_set = file_ref;
    if (l1_missing) { /* the first files have no L1: it is taken from the loaded state */
        mote_nb_monitor mon;
        mote_nb_measure(&t, &mon);
        for (int a = 0; a < 3; a++)
            t.L1[a] = mon.L[a] + mon.S[a];
    }
    t.dtp = file_dtp;
    t.G = t.u.set && t.u.G > 0 ? t.u.G : nb->G; /* the constants of the file's scales */
    t.e2 = t.u.set && t.u.e2 > 0 ? t.u.e2 : nb->e2;
    t.eps = t.u.set && t.u.eps > 0 ? t.u.eps : nb->eps;
    t.tree_on = nb->tree_on; /* the force method is a setting, not state */
    t.theta = nb->theta;
    t.tree_used = nb->tree_used;
    mote_nb_free(nb);
    *nb = t;
    return MOTE_OK;
}
