/* galfile.c: Galactica's initial-condition and result files (specs/nbody-galactica.md 7.5,
 * 7.6): a stream of numbers in Fortran's list-directed form (blanks, commas and line ends
 * separate; exponents with E, e, D, d or only a sign, as in 1.0-100; r*value repeats), 24 header
 * numbers and 15 per body (Coulomb: 25 and 16), and an optional info line (date, k2, M_Ss, Am,
 * k_v), 5 wide or zero-padded to a body row. The reader keeps every number as written; the
 * writer puts header numbers 1-15 on line 1, the rest of the header on line 2, a body per line
 * and the info line, each number with the digits that read back to the same value. */
#include "mote/nbody.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <tgmath.h>
#include <time.h>

#include "nb.h"

/* ---- the number stream ------------------------------------------------------------------------- */

typedef struct {
    mote_real *v;
    long *line; /* the line each number came from */
    size_t n, cap;
} numbers;

static int push(numbers *s, mote_real x, long line)
{
    if (s->n == s->cap) {
        const size_t cap = s->cap ? 2 * s->cap : 256;
        mote_real *v = realloc(s->v, cap * sizeof *v);
        if (v)
            s->v = v;
        long *l = realloc(s->line, cap * sizeof *l);
        if (l)
            s->line = l;
        if (!v || !l)
            return -1;
        s->cap = cap;
    }
    s->v[s->n] = x;
    s->line[s->n++] = line;
    return 0;
}

/* One list-directed real from tok (no blanks inside): D exponents become E, an exponent with a
 * sign but no letter (1.0-100) gets its E; 0 when it is a number. */
static int fortran_real(const char *tok, mote_real *x)
{
    char b[96];
    size_t n = strlen(tok), k = 0;
    if (n == 0 || n > 80)
        return -1;
    for (size_t i = 0; i < n; i++) {
        char c = tok[i];
        if (c == 'd' || c == 'D')
            c = 'E';
        /* a sign after a digit or a point, with no letter before it: the exponent's */
        if ((c == '+' || c == '-') && i > 0 && (isdigit((unsigned char)tok[i - 1]) || tok[i - 1] == '.') &&
            !strpbrk(b, "Ee"))
            b[k++] = 'E';
        b[k++] = c;
        b[k] = 0;
    }
    for (size_t i = 0; i < k; i++)
        if (!strchr("0123456789+-.Ee", b[i]))
            return -1;
    char *end;
    errno = 0;
    *x = mote_real_parse(b, &end);
    return end == b || *end || !isfinite(*x) ? -1 : 0;
}

/* The numbers of a file; err names the file and line of a token that is not one. */
static int read_numbers(const char *path, numbers *s, mote_err *err)
{
    mote_lines in;
    int rc = mote_lines_open(&in, path, err);
    if (rc)
        return rc;
    /* repeats may not blow a file up beyond 16 numbers a byte (real files stay far below) */
    struct stat st;
    const double most = (stat(path, &st) == 0 ? 16.0 * (double)st.st_size : 0) + 10000;
    char *l;
    while (!rc && (l = mote_lines_next(&in)) != NULL) {
        char *save = NULL;
        for (char *t = strtok_r(l, " \t,\r", &save); t && !rc; t = strtok_r(NULL, " \t,\r", &save)) {
            long rep = 1;
            char *star = strchr(t, '*');
            if (star) { /* r*value */
                char *e;
                rep = strtol(t, &e, 10);
                if (e != star || rep < 1 || rep > 100000000) {
                    rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: expected a repeat count r*value, "
                                   "found '%s'", path, in.line, t);
                    break;
                }
                t = star + 1;
            }
            mote_real x;
            if (fortran_real(t, &x)) {
                rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: expected a number, found '%s'", path,
                               in.line, t);
                break;
            }
            if ((double)s->n + (double)rep > most) {
                rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: the repeats make more than %.0f numbers, "
                               "16 a byte of the file: not a body file", path, in.line, most);
                break;
            }
            for (long r = 0; r < rep && !rc; r++)
                if (push(s, x, in.line))
                    rc = mote_fail(err, MOTE_ENOMEM, "%s: out of memory", path);
        }
    }
    const int crc = mote_lines_close(&in, err);
    return crc ? crc : rc;
}

/* ---- the layout ------------------------------------------------------------------------------- */

int nb_galfile_read(const char *path, int coulomb, long k2, nb_galfile *g, mote_err *err)
{
    memset(g, 0, sizeof *g);
    numbers s = {0};
    int rc = read_numbers(path, &s, err);
    const size_t H = coulomb ? 25 : 24, W = coulomb ? 16 : 15;
    size_t n = 0;
    if (!rc) {
        if (k2 >= 0) {
            n = (size_t)k2;
            const size_t need = H + W * n;
            g->info = s.n == need + 5 ? 1 : s.n == need + W ? 2 : 0;
            if (s.n != need && !g->info)
                rc = mote_fail(err, MOTE_EFORMAT, "%s: %zu numbers, but %zu header numbers and %zu "
                               "bodies of %zu make %zu (with an info line %zu or %zu)%s", path, s.n,
                               H, n, W, need, need + 5, need + W,
                               coulomb ? "" : " (a Coulomb file has 25 and 16: interaction=coulomb)");
        } else if (s.n >= H && (s.n - H) % W == 0) {
            n = (s.n - H) / W;
            /* a last row whose "mass" exceeds 1 is the zero-padded info line (date first) */
            if (n > 1 && s.v[H + W * (n - 1)] > 1) {
                n--;
                g->info = 2;
            }
        } else if (s.n >= H + 5 && (s.n - H - 5) % W == 0) {
            n = (s.n - H - 5) / W;
            g->info = 1;
        } else {
            rc = mote_fail(err, MOTE_EFORMAT, "%s: %zu numbers are not %zu header numbers and %zu "
                           "per body, with or without an info line of 5%s", path, s.n, H, W,
                           coulomb ? "" : " (a Coulomb file has 25 and 16: interaction=coulomb)");
        }
    }
    if (!rc && n == 0)
        rc = mote_fail(err, MOTE_EFORMAT, "%s: no bodies", path);
    if (!rc && n > 100000000)
        rc = mote_fail(err, MOTE_EFORMAT, "%s: more than 10^8 bodies", path);
    if (!rc) {
        g->coulomb = coulomb;
        g->n = (uint32_t)n;
        memcpy(g->head, s.v, H * sizeof *s.v);
        g->body = malloc(W * n * sizeof *g->body);
        if (!g->body)
            rc = mote_fail(err, MOTE_ENOMEM, "%s: out of memory", path);
        else
            memcpy(g->body, s.v + H, W * n * sizeof *s.v);
        if (!rc && g->info)
            for (int k = 0; k < 5; k++)
                g->infov[k] = s.v[H + W * n + (size_t)k];
        /* every mass a fraction of the total */
        for (size_t i = 0; !rc && i < n; i++) {
            const mote_real m = g->body[W * i];
            if (!(m >= 0 && m <= 1))
                rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: body %zu: the mass %g is not a fraction "
                               "of the total (0 ... 1)%s", path, s.line[H + W * i], i + 1,
                               (double)m, coulomb ? "" : "; is it a Coulomb file? (interaction=coulomb)");
        }
    }
    free(s.v);
    free(s.line);
    if (rc)
        nb_galfile_free(g);
    return rc;
}

void nb_galfile_free(nb_galfile *g)
{
    free(g->body);
    g->body = NULL;
    g->n = 0;
}

/* A number as written: %.16E for double, else the digits of its precision. */
static void put(FILE *f, mote_real x, int first)
{
    char b[MOTE_REAL_BUF];
#if MOTE_NB_PRECISION == 1
    snprintf(b, sizeof b, "%.16E", x == 0 ? 0.0 : x);
#else
    mote_real_str(x, b);
#endif
    fprintf(f, first ? "%s" : "  %s", b);
}

int nb_galfile_write(const char *path, const nb_galfile *g, int info_line, mote_err *err)
{
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc)
        return rc;
    FILE *f = af.f;
    const size_t H = g->coulomb ? 25 : 24, W = g->coulomb ? 16 : 15;
    for (size_t k = 0; k < H; k++) {
        put(f, g->head[k], k == 0 || k == 15);
        if (k == 14 || k == H - 1)
            fputc('\n', f);
    }
    for (uint32_t i = 0; i < g->n; i++) {
        for (size_t k = 0; k < W; k++)
            put(f, g->body[W * i + k], k == 0);
        fputc('\n', f);
    }
    if (info_line) {
        for (int k = 0; k < 5; k++)
            put(f, g->infov[k], k == 0);
        fputc('\n', f);
    }
    return mote_afile_commit(&af, err);
}

/* ---- to and from the system -------------------------------------------------------------------- */

int nb_from_galfile(mote_nb *nb, const nb_galfile *g, const char *path, mote_err *err)
{
    const size_t W = g->coulomb ? 16 : 15;
    mote_nb t;
    mote_nb_init(&t, nb->kind);
    t.G = nb->G;
    t.e2 = nb->e2;
    t.eps = nb->eps;
    int rc = MOTE_OK;
    for (uint32_t i = 0; i < g->n && !rc; i++) {
        const mote_real *b = g->body + W * i;
        /* a merged-away body has mass 0: added with mass 1, then set (it stays inactive) */
        const int gone = !(b[0] > 0);
        rc = mote_nb_add(&t, gone ? 1 : b[0], g->coulomb ? b[15] : 0, b + 1, b + 4, b[13], err);
        if (rc) {
            char why[sizeof err->msg];
            snprintf(why, sizeof why, "%s", err->msg);
            rc = mote_fail(err, MOTE_EFORMAT, "%s: body %u: %s", path, i + 1, why);
            break;
        }
        if (gone) {
            t.m[i] = t.q[i] = 0;
            t.active[i] = 0;
        }
        for (int a = 0; a < 3; a++) {
            t.d5p[3 * i + (uint32_t)a] = b[7 + a];
            t.sp[3 * i + (uint32_t)a] = b[10 + a];
        }
        t.et[i] = b[14];
    }
    if (rc) {
        mote_nb_free(&t);
        return rc;
    }
    /* time and steps: T0, dTp (0: a fresh start), dT (0: keep the script's) */
    t.T = g->head[0];
    t.dtp = g->head[3] > 0 ? g->head[3] : 0;
    t.restart = !(t.dtp > 0);
    t.dt = g->head[16] > 0 ? g->head[16] : nb->dt;
    t.integrator = nb->integrator;
    t.order = nb->order;
    t.taylor_order = nb->taylor_order;
    t.adaptive = nb->adaptive;
    t.tol = nb->tol;
    t.safety = nb->safety;
    t.hmin = nb->hmin;
    t.hmax = nb->hmax;
    t.taylor_memory = nb->taylor_memory;
    t.compensated = nb->compensated;
    t.merging = nb->merging;
    t.bt = nb->bt;
    t.bt_hmin = nb->bt_hmin;
    t.first_step = nb->first_step;
    t.doubling = nb->doubling;
    t.dt_max = nb->dt_max;
    t.threads = nb->threads;
    t.u = nb->u;
    t.tree_on = nb->tree_on; /* the force method is a setting, not state */
    t.theta = nb->theta;
    t.tree_used = nb->tree_used;
    mote_nb_free(nb);
    *nb = t;
    return MOTE_OK;
}

void nb_units_from_info(mote_nb *nb, const nb_galfile *g)
{
    if (!g->info || !(g->infov[2] > 0) || !(g->infov[3] > 0) || !(g->infov[4] > 0) || nb->u.set)
        return;
    nb->u.M = (double)g->infov[2];
    nb->u.Am = nb->u.Am_first = (double)g->infov[3];
    nb->u.kv = (double)g->infov[4];
    nb->u.kt = 1 / (nb->u.Am * nb->u.kv);
    nb->u.G = nb->G;
    nb->u.e2 = nb->e2;
    nb->u.eps = nb->eps;
    nb->u.set = 1;
}

void nb_to_galfile(const mote_nb *nb, const mote_real carry[25], nb_galfile *g, mote_real *body)
{
    const int coulomb = nb->kind == MOTE_NB_COULOMB;
    const size_t W = coulomb ? 16 : 15;
    memset(g, 0, sizeof *g);
    g->coulomb = coulomb;
    g->n = nb->n;
    g->body = body;
    mote_real omm = 0, um2 = 0, P[3] = {0, 0, 0}, AM[3] = {0, 0, 0}, S[3] = {0, 0, 0}, E = 0, Ett = 0;
    for (uint32_t i = 0; i < nb->n; i++) {
        const mote_real *x = nb->x + 3 * i, *v = nb->v + 3 * i, m = nb->m[i];
        mote_real *b = body + W * i;
        b[0] = m;
        for (int a = 0; a < 3; a++) {
            b[1 + a] = x[a];
            b[4 + a] = v[a];
            b[7 + a] = nb->d5p[3 * i + (uint32_t)a];
            b[10 + a] = nb->sp[3 * i + (uint32_t)a];
            P[a] += m * v[a];
            S[a] += nb->sp[3 * i + (uint32_t)a];
        }
        b[13] = nb->ra[i];
        b[14] = nb->et[i];
        if (coulomb)
            b[15] = nb->q[i];
        AM[0] += m * (x[1] * v[2] - x[2] * v[1]);
        AM[1] += m * (x[2] * v[0] - x[0] * v[2]);
        AM[2] += m * (x[0] * v[1] - x[1] * v[0]);
        const mote_real v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        E += m * v2 / 2;
        Ett += nb->et[i];
        if (nb->active[i]) {
            omm = m > omm ? m : omm;
            um2 = v2 > um2 ? v2 : um2;
        }
    }
    mote_real *h = g->head;
    h[0] = nb->T;
    h[1] = omm;
    h[2] = sqrt(um2);
    h[3] = nb->dtp;
    for (int a = 0; a < 3; a++) {
        h[4 + a] = P[a];
        h[7 + a] = AM[a];
        h[10 + a] = S[a];
    }
    h[13] = E;
    h[14] = carry && carry[14] > E ? carry[14] : E; /* Em: the largest kinetic energy seen */
    h[15] = Ett;
    h[16] = nb->dt;
    for (int k = 17; k < 24; k++) /* i2b, j2b, k2b, A, B, C, Mu: carried over */
        h[k] = carry ? carry[k] : 0;
    if (coulomb)
        h[24] = nb->eps;
    /* the info line: the date of writing, k2 and the scales */
    const time_t now = time(NULL);
    struct tm tmv;
    gmtime_r(&now, &tmv);
    g->infov[0] = (mote_real)((tmv.tm_year + 1900) * 10000 + (tmv.tm_mon + 1) * 100 + tmv.tm_mday);
    g->infov[1] = nb->n;
    g->infov[2] = nb->u.set ? nb->u.M : 0;
    g->infov[3] = nb->u.set ? nb->u.Am : 0;
    g->infov[4] = nb->u.set ? nb->u.kv : 0;
    g->info = 1;
}

/* ---- steps between two dates (spec 9.5) -------------------------------------------------------- */

int mote_nb_steps_between(double jd1, double jd2, double days, mote_real dT, int fresh,
                          mote_real first, mote_nb_steps *out, mote_err *err)
{
    if (!(jd2 > jd1) || !isfinite(jd2 - jd1))
        return mote_fail(err, MOTE_EINVAL, "steps_between: need jd1 < jd2 (found %.17g and %.17g)",
                         jd1, jd2);
    if (!(dT > 0) || !(days > 0) || !(first > 0 && first <= 1))
        return mote_fail(err, MOTE_EINVAL, "steps_between: need dt > 0");
    const mote_real DT = ((mote_real)jd2 - (mote_real)jd1) / (mote_real)days;
    const mote_real q = DT / dT;
    if (!(q < 1e15))
        return mote_fail(err, MOTE_EINVAL, "steps_between: %.3g steps is too many", (double)q);
    uint64_t L = (uint64_t)(q + (mote_real)0.5);
    if (L < 1)
        L = 1;
    out->DeltaT = DT;
    out->Ltk = L;
    out->dtc = fresh ? DT / ((mote_real)(L - 1) + first) : DT / (mote_real)L;
    /* the time as the integrator sums it (compensated): the first step, then the others */
    mote_real t = 0, c = 0;
    for (uint64_t k = 0; k < L; k++)
        kahan_add(&t, &c, fresh && k == 0 ? first * out->dtc : out->dtc, 1);
    out->t_end = t;
    return MOTE_OK;
}
