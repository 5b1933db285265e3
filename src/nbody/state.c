/* state.c: the N-body model's state file (save / load): everything a continuation needs, every
 * number to the digits that read back to the same value (17 for double, 21 for long double, 36
 * for quad: MOTE_REAL_DIG; the SI scales to 17), the compensation terms,
 * the previous fifth derivative and step of the Galactica scheme and the monitor references
 * included, so `A; save F; load F; B` runs bit for bit like `A; B`. The reader is strict: a
 * malformed file is refused with FILE:LINE and what was expected, and nothing is allocated for
 * bodies before their lines are counted. */
#include "mote/nbody.h"

#include <errno.h>
#include <tgmath.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define NB_STATE_VERSION 2 /* 2: a name ends each body line, a doubling line (1: neither) */

static void put(FILE *f, mote_real v)
{
    char b[MOTE_REAL_BUF];
    fprintf(f, " %s", mote_real_str(v, b));
}

#include "nb.h"

void nb_state_put(FILE *f, const mote_nb *nb)
{
    fprintf(f, "mote-state %d\nmodel nbody\ninteraction %s\nn %u\n", NB_STATE_VERSION,
            nb->kind == MOTE_NB_GRAVITY ? "gravity" : "coulomb", nb->n);
    fprintf(f, "time");
    put(f, nb->T);
    put(f, nb->Tc);
    fprintf(f, "\nstep");
    put(f, nb->dt);
    put(f, nb->dtp);
    put(f, nb->first_step);
    put(f, nb->hlast);
    fprintf(f, "\nscheme %d %d %d %llu\n", nb->order, nb->compensated, nb->restart,
            (unsigned long long)nb->steps);
    fprintf(f, "taylor %d %d %d %d", nb->integrator, nb->taylor_order, nb->taylor_memory,
            nb->adaptive);
    put(f, nb->tol);
    put(f, nb->safety);
    put(f, nb->hmin);
    put(f, nb->hmax);
    put(f, nb->hprev);
    fprintf(f, "\ndoubling %d %d %d", nb->doubling, nb->dbl_have, nb->dbl_count);
    put(f, nb->dt_max);
    put(f, nb->dbl_prev);
    put(f, nb->dbl_sum);
    put(f, nb->dbl_mean);
    fputc('\n', f);
    fprintf(f, "merging %d %llu %llu", nb->merging, (unsigned long long)nb->merges,
            (unsigned long long)nb->approach_warnings);
    put(f, nb->e_heat);
    put(f, nb->e_spin);
    put(f, nb->de_merge);
    put(f, nb->bt);
    put(f, nb->bt_hmin);
    put(f, nb->happ);
    put(f, nb->max_overlap);
    fprintf(f, "\nreference %d", nb->ref_set);
    put(f, nb->E0);
    put(f, nb->Mza1);
    put(f, nb->Lnorm1);
    for (int a = 0; a < 3; a++)
        put(f, nb->L1[a]);
    fprintf(f, "\nunits %d", nb->u.set);
    const double *u = &nb->u.M;
    for (int k = 0; k < 8; k++)
        fprintf(f, " %.17g", u[k]);
    fprintf(f, "\nbodies: m q active radius x y z vx vy vz cx cy cz cvx cvy cvz sx sy sz d5x d5y "
               "d5z Et name\n");
    for (uint32_t i = 0; i < nb->n; i++) {
        char mb[MOTE_REAL_BUF];
        fputs(mote_real_str(nb->m[i], mb), f);
        put(f, nb->q[i]);
        fprintf(f, " %d", nb->active[i]);
        put(f, nb->ra[i]);
        const mote_real *blocks[6] = {nb->x, nb->v, nb->xc, nb->vc, nb->sp, nb->d5p};
        for (int b = 0; b < 6; b++)
            for (int a = 0; a < 3; a++)
                put(f, blocks[b][3 * (size_t)i + a]);
        put(f, nb->et[i]);
        fprintf(f, " %s\n", nb->name[i][0] ? nb->name[i] : "-");
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

typedef struct {
    mote_lines *l;
    mote_err *err;
} reader;

static char *next_line(reader *r) { return mote_lines_next(r->l); }

static int fail(reader *r, const char *what, const char *found)
{
    return mote_fail(r->err, MOTE_EFORMAT, "%s:%ld: expected %s (found '%.60s')", r->l->path, r->l->line,
                     what, found ? found : "end of file");
}

/* Read `n` finite reals after the keyword `key` (NULL: none) from line s. */
static int reals(reader *r, char *s, const char *key, mote_real *out, int n)
{
    char *p = s;
    if (key) {
        size_t k = strlen(key);
        if (strncmp(p, key, k) != 0 || (p[k] != ' ' && p[k] != '\0'))
            return fail(r, key, s);
        p += k;
    }
    for (int i = 0; i < n; i++) {
        char *end;
        errno = 0;
        out[i] = mote_real_parse(p, &end);
        if (end == p || !isfinite(out[i]) || (*end && *end != ' '))
            return mote_fail(r->err, MOTE_EFORMAT, "%s:%ld: value %d is not a finite real number",
                             r->l->path, r->l->line, i + 1);
        p = end;
    }
    while (*p == ' ')
        p++;
    if (*p)
        return mote_fail(r->err, MOTE_EFORMAT, "%s:%ld: unexpected text after %d numbers ('%.40s')",
                         r->l->path, r->l->line, n, p);
    return MOTE_OK;
}

/* The header up to the `n` line: version, model, interaction, n. */
static int read_head(reader *r, mote_nb_interaction *kind, uint32_t *n, int *version)
{
    char *s = next_line(r);
    int v;
    if (!s || sscanf(s, "mote-state %d", &v) != 1)
        return fail(r, "'mote-state 2'", s);
    if (v < 1 || v > NB_STATE_VERSION)
        return mote_fail(r->err, MOTE_EFORMAT, "%s:%ld: unsupported state file version %d (this "
                                               "mote reads 1 to %d)", r->l->path, r->l->line, v,
                         NB_STATE_VERSION);
    *version = v;
    s = next_line(r);
    if (!s || strcmp(s, "model nbody") != 0)
        return fail(r, "'model nbody' (a state of the N-body model)", s);
    s = next_line(r);
    if (s && strcmp(s, "interaction gravity") == 0)
        *kind = MOTE_NB_GRAVITY;
    else if (s && strcmp(s, "interaction coulomb") == 0)
        *kind = MOTE_NB_COULOMB;
    else
        return fail(r, "'interaction gravity' or 'interaction coulomb'", s);
    s = next_line(r);
    unsigned long long nn;
    char extra;
    if (!s || sscanf(s, "n %llu %c", &nn, &extra) != 1 || nn > 100000000ull || s[2] == '-')
        return fail(r, "'n N' with 0 <= N <= 10^8", s);
    *n = (uint32_t)nn;
    return MOTE_OK;
}

int nb_state_peek(const char *path, uint32_t *n, mote_err *err)
{
    mote_lines lines;
    reader r = {.l = &lines, .err = err};
    int rc = mote_lines_open(r.l, path, err);
    if (rc)
        return rc;
    mote_nb_interaction kind;
    int version;
    rc = read_head(&r, &kind, n, &version);
    int crc = mote_lines_close(r.l, err);
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

int nb_state_get(mote_nb *nb, mote_lines *l, int tail, mote_err *err)
{
    reader r = {.l = l, .err = err};
    const char *path = l->path;
    int rc = MOTE_OK;
    mote_nb_interaction kind;
    uint32_t n = 0;
    mote_nb t;
    mote_nb_init(&t, MOTE_NB_GRAVITY);
    int l1_missing = 0, version = NB_STATE_VERSION;
    rc = read_head(&r, &kind, &n, &version);
    if (!rc && kind != nb->kind)
        rc = mote_fail(err, MOTE_EINVAL, "%s:3: the state is a %s run, this script is a %s run",
                       path, kind == MOTE_NB_GRAVITY ? "gravity" : "Coulomb",
                       nb->kind == MOTE_NB_GRAVITY ? "gravity" : "Coulomb");
    t.kind = kind;
    mote_real v[8];
    char *s;
    if (!rc) {
        s = next_line(&r);
        rc = s ? reals(&r, s, "time", v, 2) : fail(&r, "'time T Tc'", s);
        t.T = v[0];
        t.Tc = v[1];
    }
    if (!rc) {
        s = next_line(&r);
        rc = s ? reals(&r, s, "step", v, 4) : fail(&r, "'step dt dtp first_step hlast'", s);
        t.dt = v[0];
        t.dtp = v[1];
        t.first_step = v[2];
        t.hlast = v[3];
        if (!rc && (!(t.dt > 0) || !(t.dtp >= 0) || !(t.first_step > 0 && t.first_step <= 1)))
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: need dt > 0, dtp >= 0, 0 < first_step <= 1",
                           path, r.l->line);
    }
    if (!rc) {
        s = next_line(&r);
        int order, comp, restart;
        unsigned long long steps;
        char extra;
        if (!s || sscanf(s, "scheme %d %d %d %llu %c", &order, &comp, &restart, &steps, &extra) != 4 ||
            order < 2 || order > 6 || (comp != 0 && comp != 1) || (restart != 0 && restart != 1))
            rc = fail(&r, "'scheme ORDER(2..6) COMPENSATED(0|1) RESTART(0|1) STEPS'", s);
        t.order = order;
        t.compensated = comp;
        t.restart = restart;
        t.steps = steps;
    }
    if (!rc) {
        s = next_line(&r);
        int integ, order, mem, adapt, used = 0;
        if (!s || sscanf(s, "taylor %d %d %d %d%n", &integ, &order, &mem, &adapt, &used) != 4 ||
            (integ != MOTE_NB_GALACTICA && integ != MOTE_NB_TAYLOR) || order < 2 ||
            order > MOTE_NB_TAYLOR_MAX || mem < 0 || mem > 2 || adapt < 0 ||
            adapt > MOTE_NB_NORM_GLOBAL)
            rc = fail(&r, "'taylor INTEGRATOR(0|1) ORDER(2..60) MEMORY(0..2) ADAPTIVE(0..2)' and "
                          "tol safety hmin hmax hprev", s);
        else
            rc = reals(&r, s + used, NULL, v, 5);
        t.integrator = integ;
        t.taylor_order = order;
        t.taylor_memory = mem;
        t.adaptive = adapt;
        t.tol = v[0];
        t.safety = v[1];
        t.hmin = v[2];
        t.hmax = v[3];
        t.hprev = v[4];
    }
    if (!rc && version >= 2) { /* Galactica's literal step rule (step=doubling) */
        s = next_line(&r);
        int on, have, count, used = 0;
        if (!s || sscanf(s, "doubling %d %d %d%n", &on, &have, &count, &used) != 3 ||
            (on != 0 && on != 1) || (have != 0 && have != 1) || count < 0 || count > 4)
            rc = fail(&r, "'doubling ON(0|1) HAVE(0|1) COUNT(0..4)' and dt_max dMz_prev sum mean",
                      s);
        else
            rc = reals(&r, s + used, NULL, v, 4);
        if (!rc && (!(v[0] >= 0) || !(v[2] >= 0) || !(v[3] >= -2)))
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: doubling: need dt_max >= 0, sum >= 0, "
                           "mean >= -2", path, r.l->line);
        t.doubling = on;
        t.dbl_have = have;
        t.dbl_count = count;
        t.dt_max = v[0];
        t.dbl_prev = v[1];
        t.dbl_sum = v[2];
        t.dbl_mean = v[3];
    }
    if (!rc) {
        s = next_line(&r);
        int mode, used = 0;
        unsigned long long merges, warns;
        if (!s || sscanf(s, "merging %d %llu %llu%n", &mode, &merges, &warns, &used) != 3 ||
            mode < -1 || mode > 1)
            rc = fail(&r, "'merging MODE(-1..1) MERGES WARNINGS' and E_heat E_spin dE_merge bt "
                          "hmin happ max_overlap", s);
        else
            rc = reals(&r, s + used, NULL, v, 7);
        if (!rc && (!(v[3] > 0 && v[3] <= 1) || !(v[4] > 0 && v[4] <= 1) || !(v[5] >= 0) ||
                    !(v[6] >= 0 && v[6] <= 1)))
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: merging: need 0 < bt <= 1, 0 < hmin <= 1, "
                           "happ >= 0, 0 <= max_overlap <= 1", path, r.l->line);
        t.merging = mode;
        t.merges = merges;
        t.approach_warnings = warns;
        t.e_heat = v[0];
        t.e_spin = v[1];
        t.de_merge = v[2];
        t.bt = v[3];
        t.bt_hmin = v[4];
        t.happ = v[5];
        t.max_overlap = v[6];
    }
    if (!rc) {
        s = next_line(&r);
        if (!s || strncmp(s, "reference ", 10) != 0 || (s[10] != '0' && s[10] != '1') ||
            s[11] != ' ')
            rc = fail(&r, "'reference SET(0|1) E0 Mza1 Lnorm1 L1x L1y L1z'", s);
        else {
            t.ref_set = s[10] == '1';
            /* files of the first version have no L1: it is taken from the loaded state */
            int words = 0;
            for (const char *p = s + 11; *p; p++)
                words += *p != ' ' && (p == s + 11 || p[-1] == ' ');
            l1_missing = words == 3;
            rc = reals(&r, s + 11, NULL, v, l1_missing ? 3 : 6);
            t.E0 = v[0];
            t.Mza1 = v[1];
            t.Lnorm1 = v[2];
            if (!l1_missing)
                memcpy(t.L1, v + 3, sizeof t.L1);
        }
    }
    if (!rc) {
        s = next_line(&r);
        if (!s || strncmp(s, "units ", 6) != 0 || (s[6] != '0' && s[6] != '1') || s[7] != ' ')
            rc = fail(&r, "'units SET(0|1)' and 8 numbers", s);
        else {
            rc = reals(&r, s + 8, NULL, v, 8);
            t.u.set = s[6] == '1';
            double *u = &t.u.M;
            for (int k = 0; k < 8; k++)
                u[k] = (double)v[k];
        }
    }
    if (!rc) {
        s = next_line(&r);
        if (!s || strncmp(s, "bodies:", 7) != 0)
            rc = fail(&r, "'bodies: ...' (the column names)", s);
    }
    /* the bodies, counted as read: nothing is allocated for lines that are not there */
    /* mote_nb_add marks a restart and drops the reference: the file's values are put back after */
    const int file_restart = t.restart, file_ref = t.ref_set;
    const mote_real file_dtp = t.dtp;
    for (uint32_t i = 0; i < n && !rc; i++) {
        s = next_line(&r);
        if (!s || strcmp(s, "end") == 0) {
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: file ends early: n = %u, but only %u body "
                                              "lines follow", path, s ? r.l->line : r.l->line + 1, n, i);
            break;
        }
        mote_real w[23];
        char *p = s;
        int ok = 1, act = 0;
        for (int k = 0; k < 23 && ok; k++) {
            char *end;
            if (k == 2) { /* the active flag */
                long a = strtol(p, &end, 10);
                ok = end != p && (a == 0 || a == 1) && (*end == ' ');
                act = (int)a;
                w[k] = 0;
            } else {
                w[k] = mote_real_parse(p, &end);
                ok = end != p && isfinite(w[k]) &&
                     (*end == ' ' || (*end == '\0' && k == 22 && version == 1));
            }
            p = end;
        }
        const char *name = "-";
        if (ok && version >= 2) { /* the name, "-" when unnamed */
            name = p + 1;
            ok = strchr(name, ' ') == NULL && (strcmp(name, "-") == 0 || mote_nb_name_ok(name));
            p += strlen(p);
        }
        if (!ok || *p) {
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: body %u: expected 23 numbers (m q active "
                                              "radius x y z vx vy vz cx cy cz cvx cvy cvz sx sy "
                                              "sz d5x d5y d5z Et), all finite%s",
                           path, r.l->line, i + 1, version >= 2 ? ", and a name or -" : "");
            break;
        }
        /* a merged-away body has mass 0: added with mass 1, then set (it stays inactive) */
        rc = act == 0 && w[0] == 0 ? mote_nb_add(&t, 1, 0, w + 4, w + 7, 0, err)
                                   : mote_nb_add(&t, w[0], w[1], w + 4, w + 7, w[3], err);
        if (!rc && act == 0 && w[0] == 0)
            t.m[i] = t.q[i] = 0;
        if (!rc)
            t.et[i] = w[22];
        if (!rc && strcmp(name, "-") != 0)
            rc = mote_nb_set_name(&t, i, name, err);
        if (rc) {
            char why[sizeof err->msg];
            snprintf(why, sizeof why, "%s", err->msg);
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: %s", path, r.l->line, why);
            break;
        }
        t.active[i] = (uint8_t)act;
        for (int a = 0; a < 3; a++) {
            t.xc[3 * i + a] = w[10 + a];
            t.vc[3 * i + a] = w[13 + a];
            t.sp[3 * i + a] = w[16 + a];
            t.d5p[3 * i + a] = w[19 + a];
        }
    }
    if (!rc) {
        s = next_line(&r);
        if (!s || strcmp(s, "end") != 0)
            rc = fail(&r, "'end' after the bodies", s);
        else if (!tail && (s = next_line(&r)) != NULL)
            rc = fail(&r, "nothing after 'end'", s);
    }
    if (rc) {
        mote_nb_free(&t);
        return rc;
    }
    t.restart = file_restart;
    t.ref_set = file_ref;
    if (l1_missing) {
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
