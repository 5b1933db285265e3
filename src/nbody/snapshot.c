/* snapshot.c: the N-body model's snapshot (spec 10.2), a data file of the run's state that people
 * and programs read: `#` header lines (the run header every output shares, then the fields a
 * Galactica-scheme continuation needs: T, dT, h_prev, the references E_corr,0 and Mza1, the merge
 * count Lsls and heat Ett), then one row per body
 *     id name active mass charge x y z vx vy vz radius sx sy sz Et d5x d5y d5z
 * with every number to the digits that read back to the same value (MOTE_REAL_DIG).
 * Reading restores bodies, time, step history and references; the Kahan compensation terms are
 * not part of a snapshot, so a continuation agrees with the uninterrupted run to rounding (bit
 * for bit when compensated summation is off); `save`/`load` keep everything. Only N and the
 * rows are required, so a snapshot can also be written by hand or by another program. */
#include "mote/datafile.h"
#include "mote/nbody.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <tgmath.h>

#include "nb.h"

void nb_write_header(FILE *f, const mote_nb *nb)
{
    fprintf(f, "# interaction = %s\n# N = %u\n", nb->kind == MOTE_NB_GRAVITY ? "gravity" : "coulomb",
            nb->n);
    nb_integrator_of(nb->integrator)->header(f, nb);
    fprintf(f, "# compensated = %d\n", nb->compensated);
    if (nb->soft > 0) {
        char e[MOTE_REAL_BUF];
        fprintf(f, "# softening = %s\n", mote_real_str(nb->soft, e));
    }
    if (nb->tree_on) {
        char t[MOTE_REAL_BUF];
        fprintf(f, "# forces = tree\n# theta = %s\n# approximate: Barnes-Hut tree forces (spec "
                   "6.2); momentum is not conserved exactly\n", mote_real_str(nb->theta, t));
    } else if (nb->tree_used) {
        fprintf(f, "# forces = direct\n# approximate: some steps of this run used Barnes-Hut tree "
                   "forces (spec 6.2)\n");
    } else
        fprintf(f, "# forces = direct\n");
    fprintf(f, "# precision = %s\n", MOTE_REAL_NAME);
}

void nb_write_units(FILE *f, const mote_nb *nb)
{
    if (nb->u.set)
        fprintf(f, "# M_Ss = %.17g\n# Am = %.17g\n# kv = %.17g\n# kt = %.17g\n", nb->u.M,
                nb->u.Am, nb->u.kv, nb->u.kt);
    fprintf(f, "# G = %.17g\n# e2 = %.17g\n# permittivity = %.17g\n", nb->G, nb->e2, nb->eps);
    fprintf(f, "# units: dimensionless (G = 1 or the Coulomb constant 1, total mass 1; spec "
               "3.5)\n");
}

/* The real-valued header fields a snapshot carries (after the shared header), in order. */
enum { K_T, K_DTP, K_FIRST, K_E0, K_MZA1, K_LNORM1, K_L1X, K_L1Y, K_L1Z, K_EHEAT, K_ESPIN,
       K_DEMERGE, K_NREAL };
static const char *const KEY[K_NREAL] = {"T",      "h_prev", "first_step", "E_corr0",
                                         "Mza1",   "Lnorm1", "L1x",        "L1y",
                                         "L1z",    "Ett",    "E_spin",     "dE_merge"};

int nb_snapshot_write(const mote_nb *nb, const char *path, const char *origin, mote_err *err)
{
    mote_datafile d;
    int rc = mote_datafile_open(&d, path, "nbody-snapshot", origin, 0, err);
    if (rc)
        return rc;
    FILE *f = d.f;
    nb_write_header(f, nb);
    nb_write_units(f, nb);
    const mote_real v[K_NREAL] = {nb->T,      nb->dtp,   nb->first_step, nb->E0,
                                  nb->Mza1,   nb->Lnorm1, nb->L1[0],     nb->L1[1],
                                  nb->L1[2],  nb->e_heat, nb->e_spin,    nb->de_merge};
    char b[MOTE_REAL_BUF];
    for (int k = 0; k < K_NREAL; k++)
        fprintf(f, "# %s = %s\n", KEY[k], mote_real_str(v[k], b));
    fprintf(f, "# steps = %llu\n# restart = %d\n# reference = %d\n# Lsls = %llu\n",
            (unsigned long long)nb->steps, nb->restart, nb->ref_set,
            (unsigned long long)nb->merges);
    fprintf(f, "# h_prev is the last step of the Galactica scheme (0: the next step restarts); "
               "d5 its fifth derivative at that step's start; Et the heat of merges per body\n");
    fputs("# columns: id name active mass charge x y z vx vy vz radius sx sy sz Et d5x d5y d5z\n",
          f);
    for (uint32_t i = 0; i < nb->n; i++) {
        fprintf(f, "%u %s %d", i + 1, nb->name[i][0] ? nb->name[i] : "-", nb->active[i]);
        const mote_real one[2] = {nb->m[i], nb->q[i]};
        for (int k = 0; k < 2; k++)
            fprintf(f, " %s", mote_real_str(one[k], b));
        for (int a = 0; a < 6; a++)
            fprintf(f, " %s", mote_real_str(a < 3 ? nb->x[3 * i + a] : nb->v[3 * i + a - 3], b));
        fprintf(f, " %s", mote_real_str(nb->ra[i], b));
        for (int a = 0; a < 3; a++)
            fprintf(f, " %s", mote_real_str(nb->sp[3 * i + a], b));
        fprintf(f, " %s", mote_real_str(nb->et[i], b));
        for (int a = 0; a < 3; a++)
            fprintf(f, " %s", mote_real_str(nb->d5p[3 * i + a], b));
        fputc('\n', f);
    }
    return mote_datafile_commit(&d, err);
}

/* ---- reading ---------------------------------------------------------------------------------- */

typedef struct {
    mote_lines l;
    mote_err *err;
} rd;

static int bad(rd *r, const char *fmt, const char *what)
{
    return mote_fail(r->err, MOTE_EFORMAT, "%s:%ld: %s%.60s%s", r->l.path, r->l.line, fmt,
                     what ? what : "", what ? "'" : "");
}

/* One finite real from text that must hold nothing else; 0 on success. */
static int real_of(const char *t, mote_real *v)
{
    char *end;
    *v = mote_real_parse(t, &end);
    while (*end == ' ' || *end == '\t')
        end++;
    return end == t || *end || !isfinite(*v) ? -1 : 0;
}

/* One unsigned integer from text that must hold nothing else; 0 on success. */
static int count_of(const char *t, unsigned long long *v)
{
    char *end;
    if (!isdigit((unsigned char)*t))
        return -1;
    *v = strtoull(t, &end, 10);
    while (*end == ' ' || *end == '\t')
        end++;
    return *end ? -1 : 0;
}

/* What a snapshot's header says: the keys a continuation needs (the others are notes). */
typedef struct {
    mote_real v[K_NREAL], dt, tol, safety, soft;
    int have[K_NREAL], integ, order, taylor_adaptive;
    unsigned long long n, steps, restart, ref, lsls;
    int have_n, have_ref, compensated, norm_global, corrector;
    double units[7]; /* M_Ss Am kv kt G e2 permittivity */
} snap_head;

static const char *const UKEY[7] = {"M_Ss", "Am", "kv", "kt", "G", "e2", "permittivity"};

/* The whole numbers of the header: N, steps, restart, Lsls, reference, order, compensated. */
static int head_count(rd *r, snap_head *h, const char *key, const char *val)
{
    unsigned long long u;
    if (count_of(val, &u))
        return bad(r, "expected a whole number >= 0 after '# ", key);
    if (key[0] == 'N') {
        h->n = u;
        h->have_n = 1;
        if (h->n > 100000000ull)
            return bad(r, "expected N <= 10^8", NULL);
    } else if (key[0] == 's')
        h->steps = u;
    else if (strcmp(key, "restart") == 0)
        h->restart = u;
    else if (key[0] == 'L')
        h->lsls = u;
    else if (key[0] == 'r') {
        h->ref = u;
        h->have_ref = 1;
    } else if (key[0] == 'o')
        h->order = u > 1000 ? 1000 : (int)u;
    else
        h->compensated = u != 0;
    return h->restart > 1 || h->ref > 1 ? bad(r, "expected 0 or 1 after '# ", key) : MOTE_OK;
}

/* The words and positive reals of the header, and the scales. */
static int head_other(rd *r, snap_head *h, const char *key, const char *val, const mote_nb *nb)
{
    mote_real x;
    unsigned long long u;
    if (strcmp(key, "interaction") == 0) {
        int grav = strcmp(val, "gravity") == 0;
        if (!grav && strcmp(val, "coulomb") != 0)
            return bad(r, "expected gravity or coulomb after '# ", "interaction");
        if ((grav ? MOTE_NB_GRAVITY : MOTE_NB_COULOMB) != nb->kind)
            return mote_fail(r->err, MOTE_EINVAL, "%s:%ld: the snapshot is a %s run, this "
                             "script is a %s run", r->l.path, r->l.line, grav ? "gravity" :
                             "Coulomb", nb->kind == MOTE_NB_GRAVITY ? "gravity" : "Coulomb");
    } else if (strcmp(key, "norm") == 0) {
        if (strcmp(val, "global") == 0)
            h->norm_global = 1;
        else if (strcmp(val, "nearest") != 0)
            return bad(r, "expected nearest or global after '# ", "norm");
    } else if (strcmp(key, "integrator") == 0) {
        if ((h->integ = nb_integrator_named(val)) < 0)
            return bad(r, "expected galactica, taylor or wh after '# ", "integrator");
    } else if (strcmp(key, "softening") == 0) {
        if (real_of(val, &x) || !(x >= 0))
            return bad(r, "expected a number >= 0 after '# ", key);
        h->soft = x;
    } else if (strcmp(key, "corrector") == 0) {
        if (count_of(val, &u) || (u != 0 && u != 3 && u != 5 && u != 7 && u != 11 && u != 17))
            return bad(r, "expected 0, 3, 5, 7, 11 or 17 after '# ", key);
        h->corrector = (int)u;
    } else if (strcmp(key, "N") == 0 || strcmp(key, "steps") == 0 ||
               strcmp(key, "restart") == 0 || strcmp(key, "Lsls") == 0 ||
               strcmp(key, "reference") == 0 || strcmp(key, "order") == 0 ||
               strcmp(key, "compensated") == 0) {
        return head_count(r, h, key, val);
    } else if (strcmp(key, "dt") == 0 || strcmp(key, "tol") == 0 ||
               strcmp(key, "safety") == 0) {
        if (real_of(val, &x) || !(x > 0))
            return bad(r, "expected a number > 0 after '# ", key);
        if (key[0] == 'd')
            h->dt = x;
        else if (key[0] == 't') {
            h->tol = x;
            h->taylor_adaptive = 1;
        } else
            h->safety = x;
    } else {
        for (int j = 0; j < 7; j++)
            if (strcmp(key, UKEY[j]) == 0 && (real_of(val, &x) || !(x > 0)))
                return bad(r, "expected a number > 0 after '# ", key);
            else if (strcmp(key, UKEY[j]) == 0)
                h->units[j] = (double)x;
    }
    return MOTE_OK;
}

/* A header line "# key = value" (others are notes). */
static int head_line(rd *r, snap_head *h, const char *s, const mote_nb *nb)
{
    char key[40];
    int used = 0;
    if (sscanf(s, "# %39[A-Za-z0-9_] =%n", key, &used) != 1 || !used)
        return MOTE_OK;
    const char *val = s + used;
    while (*val == ' ')
        val++;
    int k = 0;
    while (k < K_NREAL && strcmp(KEY[k], key) != 0)
        k++;
    if (k == K_NREAL)
        return head_other(r, h, key, val, nb);
    h->have[k] = 1;
    return real_of(val, &h->v[k]) ? bad(r, "expected a finite number after '# ", key) : MOTE_OK;
}

/* Body row number `row` (0-based) into t. */
static int body_row(rd *r, const snap_head *h, mote_nb *t, char *s, uint32_t row)
{
    const char *path = r->l.path;
    mote_err *err = r->err;
    if (!h->have_n)
        return bad(r, "expected the header line '# N = COUNT' before the bodies", NULL);
    if (row == h->n)
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: more body rows than N = %llu", path,
                         r->l.line, h->n);
    char *tok[20], *save = NULL;
    int nt = 0;
    for (char *p = strtok_r(s, " \t", &save); p && nt < 20; p = strtok_r(NULL, " \t", &save))
        tok[nt++] = p;
    unsigned long long id, act;
    mote_real w[16];
    int ok = nt == 19 && !count_of(tok[0], &id) && id == row + 1 && !count_of(tok[2], &act) &&
             act <= 1 && (strcmp(tok[1], "-") == 0 || mote_nb_name_ok(tok[1]));
    for (int k = 0; ok && k < 16; k++)
        ok = !real_of(tok[3 + k], &w[k]);
    if (!ok)
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: body %u: expected 19 fields: id (%u) name "
                         "(or -) active (0 or 1) mass charge x y z vx vy vz radius sx sy sz Et "
                         "d5x d5y d5z, all finite", path, r->l.line, row + 1, row + 1);
    /* a merged-away body has mass 0: added with mass 1, then set (it stays inactive) */
    int gone = act == 0 && w[0] == 0;
    int rc = mote_nb_add(t, gone ? 1 : w[0], gone ? 0 : w[1], w + 2, w + 5, gone ? 0 : w[8], err);
    if (!rc && strcmp(tok[1], "-") != 0)
        rc = mote_nb_set_name(t, row, tok[1], err);
    if (rc) {
        char why[sizeof err->msg];
        snprintf(why, sizeof why, "%s", err->msg);
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: %s", path, r->l.line, why);
    }
    if (gone)
        t->m[row] = t->q[row] = 0;
    t->active[row] = (uint8_t)act;
    t->et[row] = w[12];
    for (int a = 0; a < 3; a++) {
        t->sp[3 * row + a] = w[9 + a];
        t->d5p[3 * row + a] = w[13 + a];
    }
    return MOTE_OK;
}

/* The file as a whole: its bodies all there, its values in range. */
static int snap_complete(rd *r, const snap_head *h, uint32_t rows)
{
    const char *path = r->l.path;
    mote_err *err = r->err;
    if (!h->have_n)
        return mote_fail(err, MOTE_EFORMAT, "%s: no header line '# N = COUNT' (not a snapshot)",
                         path);
    if (rows != h->n)
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: file ends early: N = %llu, but only %u body "
                         "rows", path, r->l.line + 1, h->n, rows);
    if (h->n == 0)
        return mote_fail(err, MOTE_EFORMAT, "%s: the snapshot has no bodies", path);
    if (h->have[K_DTP] && !(h->v[K_DTP] >= 0))
        return mote_fail(err, MOTE_EFORMAT, "%s: h_prev must be >= 0", path);
    if (h->have[K_FIRST] && !(h->v[K_FIRST] > 0 && h->v[K_FIRST] <= 1))
        return mote_fail(err, MOTE_EFORMAT, "%s: first_step must be in (0, 1]", path);
    const nb_integrator *in = nb_integrator_of(h->integ);
    const int lo = 2, hi = in->order_max ? in->order_max : 6;
    if (h->order >= 0 && (h->order < lo || h->order > hi))
        return mote_fail(err, MOTE_EFORMAT, "%s: order must be %d to %d for the %s integrator",
                         path, lo, hi, in->name);
    return MOTE_OK;
}

/* The integrator and its settings from the header (the rest as they are in the script now). */
static void snap_settings(mote_nb *t, const snap_head *h, const mote_nb *nb)
{
    t->integrator = h->integ;
    t->wh_corrector = h->corrector;
    t->soft = h->soft;
    t->order = nb->order;
    t->taylor_order = nb->taylor_order;
    if (h->order >= 0 && h->integ == MOTE_NB_TAYLOR)
        t->taylor_order = h->order;
    else if (h->order >= 0)
        t->order = h->order;
    t->dt = h->dt;
    t->adaptive = h->integ == MOTE_NB_TAYLOR
                      ? h->taylor_adaptive * (h->norm_global ? MOTE_NB_NORM_GLOBAL : 1)
                      : nb->adaptive;
    t->tol = h->tol;
    t->safety = h->safety;
    t->hmin = nb->hmin;
    t->hmax = nb->hmax;
    t->taylor_memory = nb->taylor_memory;
    t->compensated = h->compensated;
    t->merging = nb->merging;
    t->bt = nb->bt;
    t->bt_hmin = nb->bt_hmin;
    t->first_step = h->have[K_FIRST] ? h->v[K_FIRST] : nb->first_step;
    t->doubling = nb->doubling; /* (the rule's blocks start afresh) */
    t->dt_max = nb->dt_max;
}

/* The time, the step history, the references and the scales from the header. */
static void snap_state(mote_nb *t, const snap_head *h, const mote_nb *nb)
{
    const mote_real *v = h->v;
    t->T = v[K_T];
    t->steps = h->steps;
    t->merges = h->lsls;
    t->e_heat = v[K_EHEAT];
    t->e_spin = v[K_ESPIN];
    t->de_merge = v[K_DEMERGE];
    t->dtp = v[K_DTP];
    t->restart = !(t->dtp > 0) || h->restart;
    if (t->restart)
        t->dtp = 0;
    t->ref_set = h->have_ref ? (int)h->ref : h->have[K_E0] && h->have[K_MZA1];
    t->E0 = v[K_E0];
    t->Mza1 = v[K_MZA1];
    t->Lnorm1 = v[K_LNORM1];
    for (int a = 0; a < 3; a++)
        t->L1[a] = v[K_L1X + a];
    if (t->ref_set &&
        !(h->have[K_LNORM1] && h->have[K_L1X] && h->have[K_L1Y] && h->have[K_L1Z])) {
        mote_nb_monitor mon;
        mote_nb_measure(t, &mon);
        mote_real l2 = 0;
        for (int a = 0; a < 3; a++) {
            t->L1[a] = mon.L[a] + mon.S[a];
            l2 += t->L1[a] * t->L1[a];
        }
        if (!h->have[K_LNORM1])
            t->Lnorm1 = sqrt(l2);
    }
    const double *units = h->units;
    if (units[0] > 0 && units[1] > 0 && units[2] > 0 && units[3] > 0) { /* all the scales */
        t->u.M = units[0];
        t->u.Am = t->u.Am_first = units[1];
        t->u.kv = units[2];
        t->u.kt = units[3];
        t->u.G = units[4] > 0 ? units[4] : nb->G;
        t->u.e2 = units[5] > 0 ? units[5] : nb->e2;
        t->u.eps = units[6] > 0 ? units[6] : nb->eps;
        t->u.set = 1;
    }
    if (units[4] > 0)
        t->G = units[4];
    if (units[5] > 0)
        t->e2 = units[5];
    if (units[6] > 0)
        t->eps = units[6];
}

int nb_snapshot_read(mote_nb *nb, const char *path, mote_err *err)
{
    rd r = {.err = err};
    int rc = mote_lines_open(&r.l, path, err);
    if (rc)
        return rc;
    mote_nb t;
    mote_nb_init(&t, nb->kind);
    t.G = nb->G;
    t.e2 = nb->e2;
    t.eps = nb->eps;
    snap_head h = {.dt = nb->dt, .tol = nb->tol, .safety = nb->safety, .soft = nb->soft,
                   .integ = MOTE_NB_GALACTICA, .order = -1, .restart = 1,
                   .compensated = nb->compensated, .corrector = nb->wh_corrector};
    char *s;
    uint32_t row = 0;
    while (!rc && (s = mote_lines_next(&r.l)) != NULL) {
        if (s[0] == '#')
            rc = head_line(&r, &h, s, nb);
        else if (!(rc = body_row(&r, &h, &t, s, row)))
            row++;
    }
    int crc = mote_lines_close(&r.l, err);
    rc = crc ? crc : rc;
    if (!rc)
        rc = snap_complete(&r, &h, row);
    if (rc) {
        mote_nb_free(&t);
        return rc;
    }
    snap_settings(&t, &h, nb);
    snap_state(&t, &h, nb);
    t.tree_on = nb->tree_on; /* the force method is a setting, not state */
    t.theta = nb->theta;
    t.tree_used = nb->tree_used;
    mote_nb_free(nb);
    *nb = t;
    return MOTE_OK;
}
