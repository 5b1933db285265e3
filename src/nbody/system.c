/* system.c: the N-body system: its arrays (structure of arrays, grown as bodies are added), the
 * kernel coefficients of spec 3.3 (one code path for gravity and Coulomb), the scales of spec
 * 3.5, the barycentric reduction of 3.4 and the conserved quantities of 3.7. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <tgmath.h>

#include "nb.h"

void mote_nb_units_from_time(mote_nb_units *u, mote_nb_interaction kind, double M, double kt,
                             double G, double e2, double eps)
{
    memset(u, 0, sizeof *u);
    u->M = M;
    u->kt = kt;
    u->G = G;
    u->e2 = e2;
    u->eps = eps;
    if (kind == MOTE_NB_GRAVITY) {
        u->Am_first = cbrt(G * M / (kt * kt));
        u->kv = sqrt(u->Am_first / (G * M));
    } else {
        u->Am_first = cbrt(e2 / (eps * M * kt * kt));
        u->kv = sqrt(eps * M * u->Am_first / e2);
    }
    u->Am = 1.0 / (kt * u->kv); /* the refinement: the three scales agree to the last bit */
    u->set = 1;
}

void mote_nb_units_from_length(mote_nb_units *u, mote_nb_interaction kind, double M, double Am,
                               double G, double e2, double eps)
{
    memset(u, 0, sizeof *u);
    u->M = M;
    u->Am = u->Am_first = Am;
    u->G = G;
    u->e2 = e2;
    u->eps = eps;
    u->kv = kind == MOTE_NB_GRAVITY ? sqrt(Am / (G * M)) : sqrt(eps * M * Am / e2);
    u->kt = 1.0 / (Am * u->kv);
    u->set = 1;
}

double mote_nb_time_unit(const char *name)
{
    static const struct {
        const char *name;
        double s;
    } units[] = {{"s", 1},
                 {"day", 86400},
                 {"year", 365.25 * 86400},
                 {"century", 100 * MOTE_NB_SIDEREAL_YEAR_DAYS * 86400}};
    for (size_t k = 0; k < sizeof units / sizeof units[0]; k++)
        if (strcmp(name, units[k].name) == 0)
            return units[k].s;
    return 0;
}

void mote_nb_from_si(mote_nb *nb, const mote_nb_units *u)
{
    for (uint32_t i = 0; i < nb->n; i++) {
        nb->m[i] /= u->M;
        nb->ra[i] /= u->Am;
        for (int a = 0; a < 3; a++) {
            nb->x[3 * i + a] /= u->Am;
            nb->v[3 * i + a] *= u->kv;
            nb->sp[3 * i + a] *= u->kv / (u->M * u->Am); /* m x v */
        }
    }
    nb->u = *u;
    nb->dtp = 0;
    nb->ref_set = 0;
}

void mote_nb_init(mote_nb *nb, mote_nb_interaction kind)
{
    memset(nb, 0, sizeof *nb);
    nb->kind = kind;
    nb->order = 6;
    nb->first_step = (mote_real)1 / 1000;
    nb->compensated = 1;
    nb->threads_min_n = NB_THREADS_MIN_N;
    nb->dt = 1e-6;
    nb->taylor_order = MOTE_NB_TAYLOR_ORDER;
    nb->merging = -1;
    nb->bt = 0.5;
    nb->bt_hmin = 1e-6;
    nb->tol = MOTE_NB_TAYLOR_TOL;
    nb->safety = 1.0;
    nb->dbl_mean = -1;
    nb->G = MOTE_NB_G;
    nb->e2 = 1e-9 * MOTE_NB_E_CGSE * MOTE_NB_E_CGSE;
    nb->eps = 1;
}

static void free_arrays(mote_nb *nb)
{
    void *arr[] = {nb->m,   nb->q,  nb->c,      nb->w,   nb->x,   nb->v,    nb->xc,
                   nb->vc,  nb->ra, nb->sp,     nb->active, nb->d5p, nb->acc, nb->jerk,
                   nb->d4,  nb->d5, nb->tx,     nb->ts,  nb->tf, nb->tg,  nb->et, nb->name,
                   nb->wh_map, nb->tr, nb->taw};
    for (size_t k = 0; k < sizeof arr / sizeof arr[0]; k++)
        free(arr[k]);
}

void mote_nb_free(mote_nb *nb)
{
    free_arrays(nb);
    nb_tree_free(nb);
    mote_nb_interaction kind = nb->kind;
    const double G = nb->G, e2 = nb->e2, eps = nb->eps;
    memset(nb, 0, sizeof *nb);
    nb->kind = kind;
    nb->G = G;
    nb->e2 = e2;
    nb->eps = eps;
}

/* Grow every array to hold cap bodies (new entries zero). */
static int grow(mote_nb *nb, uint32_t cap)
{
    mote_real **d1[] = {&nb->m, &nb->q, &nb->c, &nb->w, &nb->ra, &nb->et};
    mote_real **d3[] = {&nb->x, &nb->v, &nb->xc, &nb->vc, &nb->sp, &nb->d5p, &nb->acc, &nb->jerk,
                     &nb->d4, &nb->d5};
    for (size_t k = 0; k < sizeof d1 / sizeof d1[0]; k++) {
        mote_real *p = realloc(*d1[k], cap * sizeof *p);
        if (!p)
            return -1;
        memset(p + nb->cap, 0, (cap - nb->cap) * sizeof *p);
        *d1[k] = p;
    }
    for (size_t k = 0; k < sizeof d3 / sizeof d3[0]; k++) {
        mote_real *p = realloc(*d3[k], 3 * (size_t)cap * sizeof *p);
        if (!p)
            return -1;
        memset(p + 3 * (size_t)nb->cap, 0, 3 * (size_t)(cap - nb->cap) * sizeof *p);
        *d3[k] = p;
    }
    uint8_t *a = realloc(nb->active, cap);
    if (!a)
        return -1;
    memset(a + nb->cap, 0, cap - nb->cap);
    nb->active = a;
    char(*nm)[MOTE_NB_NAME] = realloc(nb->name, (size_t)cap * sizeof *nm);
    if (!nm)
        return -1;
    memset(nm + nb->cap, 0, (size_t)(cap - nb->cap) * sizeof *nm);
    nb->name = nm;
    nb->cap = cap;
    return 0;
}

int mote_nb_add(mote_nb *nb, mote_real m, mote_real q, const mote_real x[3], const mote_real v[3],
                mote_real ra, mote_err *err)
{
    int finite = isfinite(m) && isfinite(q) && isfinite(ra);
    for (int a = 0; a < 3; a++)
        finite &= isfinite(x[a]) && isfinite(v[a]);
    if (!finite)
        return mote_fail(err, MOTE_EINVAL, "body %u: every value must be finite", nb->n + 1);
    if (!(m > 0))
        return mote_fail(err, MOTE_EINVAL, "body %u: the mass must be > 0 (found %g)", nb->n + 1,
                         (double)m);
    if (!(ra >= 0))
        return mote_fail(err, MOTE_EINVAL, "body %u: the radius must be >= 0 (found %g)",
                         nb->n + 1, (double)ra);
    if (nb->n == UINT32_MAX - 1)
        return mote_fail(err, MOTE_EINVAL, "too many bodies");
    if (nb->n == nb->cap && grow(nb, nb->cap ? 2 * nb->cap : 16))
        return mote_fail(err, MOTE_ENOMEM, "out of memory adding body %u", nb->n + 1);
    uint32_t i = nb->n++;
    nb->m[i] = m;
    nb->q[i] = q;
    nb->ra[i] = ra;
    nb->active[i] = 1;
    for (int a = 0; a < 3; a++) {
        nb->x[3 * i + a] = x[a];
        nb->v[3 * i + a] = v[a];
        nb->xc[3 * i + a] = nb->vc[3 * i + a] = 0;
    }
    nb->dtp = 0; /* a new body: no valid previous fifth derivative, the next step restarts */
    nb->restart = 1;
    nb->ref_set = 0;
    nb->wh_live = 0;
    return MOTE_OK;
}

int mote_nb_name_ok(const char *name)
{
    size_t len = strlen(name);
    if (len == 0 || len >= MOTE_NB_NAME || !isalpha((unsigned char)name[0]))
        return 0;
    for (size_t k = 1; k < len; k++)
        if (!isalnum((unsigned char)name[k]) && !strchr("_.+-", name[k]))
            return 0;
    return 1;
}

long mote_nb_find(const mote_nb *nb, const char *token)
{
    if (isdigit((unsigned char)token[0])) {
        char *end;
        unsigned long k = strtoul(token, &end, 10);
        return *end || k < 1 || k > nb->n ? -1 : (long)k - 1;
    }
    for (uint32_t i = 0; i < nb->n; i++)
        if (strcmp(nb->name[i], token) == 0)
            return (long)i;
    return -1;
}

int mote_nb_set_name(mote_nb *nb, uint32_t i, const char *name, mote_err *err)
{
    if (!mote_nb_name_ok(name))
        return mote_fail(err, MOTE_EINVAL, "body %u: the name '%.40s' is not valid: 1 to %d "
                         "characters, a letter first, then letters, digits and _ . + -", i + 1,
                         name, MOTE_NB_NAME - 1);
    long k = mote_nb_find(nb, name);
    if (k >= 0 && (uint32_t)k != i)
        return mote_fail(err, MOTE_EINVAL, "body %u: the name '%s' is taken by body %ld", i + 1,
                         name, k + 1);
    strcpy(nb->name[i], name);
    return MOTE_OK;
}

typedef struct {
    mote_real x[3];
    uint32_t i;
} nb_point;

/* by x, y, z (-0 and 0 equal, as the test of equal points has them), then by index */
static int point_cmp_x(const nb_point *p, const nb_point *q)
{
    for (int c = 0; c < 3; c++)
        if (p->x[c] != q->x[c])
            return p->x[c] < q->x[c] ? -1 : 1;
    return 0;
}
static int point_cmp(const void *a, const void *b)
{
    const nb_point *p = a, *q = b;
    const int c = point_cmp_x(p, q);
    return c ? c : p->i < q->i ? -1 : p->i > q->i;
}

int nb_state_bounded(const mote_nb *nb, mote_err *err)
{
    static const char *const what[6] = {"x", "y", "z", "vx", "vy", "vz"};
    if (!isfinite((double)nb->T))
        return mote_fail(err, MOTE_ERUNTIME, "the time is not a finite number");
    for (uint32_t i = 0; i < nb->n; i++) {
        if (!nb->active[i])
            continue;
        for (int a = 0; a < 6; a++) {
            const mote_real v = a < 3 ? nb->x[3 * (size_t)i + a] : nb->v[3 * (size_t)i + a - 3];
            if (!(fabs((double)v) <= NB_VALUE_MAX))
                return mote_fail(err, MOTE_ERUNTIME, "body %u: %s = %g %s", i + 1, what[a],
                                 (double)v, isfinite((double)v) ? "is beyond 1e100 (its energy "
                                 "would overflow)" : "is not a finite number");
        }
        if (!(fabs((double)nb->m[i]) <= NB_VALUE_MAX))
            return mote_fail(err, MOTE_ERUNTIME, "body %u: the mass %g is beyond 1e100", i + 1,
                             (double)nb->m[i]);
    }
    return MOTE_OK;
}

int mote_nb_prepare(mote_nb *nb, mote_err *err)
{
    if (nb->n == 0)
        return mote_fail(err, MOTE_EINVAL, "there are no bodies");
    int charged = 0;
    for (uint32_t i = 0; i < nb->n; i++) {
        if (nb->kind == MOTE_NB_GRAVITY) {
            nb->c[i] = -1;
            nb->w[i] = nb->m[i];
        } else {
            nb->c[i] = nb->q[i] / nb->m[i];
            nb->w[i] = nb->q[i];
            charged |= nb->q[i] != 0;
        }
    }
    if (nb->kind == MOTE_NB_COULOMB && !charged)
        return mote_fail(err, MOTE_EINVAL, "a Coulomb run needs charged bodies: every charge is 0");
    int rc = nb_state_bounded(nb, err);
    if (rc)
        return rc;
    /* two active bodies at one point: sorted by position (then index), equal neighbours; the
     * pair reported is the one of lowest indices */
    nb_point *p = malloc((nb->n ? nb->n : 1) * sizeof *p);
    if (!p)
        return mote_fail(err, MOTE_ENOMEM, "out of memory for %u bodies", nb->n);
    uint32_t np = 0;
    for (uint32_t i = 0; i < nb->n; i++)
        if (nb->active[i]) {
            memcpy(p[np].x, nb->x + 3 * (size_t)i, sizeof p[np].x);
            p[np++].i = i;
        }
    qsort(p, np, sizeof *p, point_cmp);
    uint32_t bi = UINT32_MAX, bk = UINT32_MAX;
    for (uint32_t k = 1; k < np; k++)
        if (point_cmp_x(p + k, p + k - 1) == 0) {
            /* the first two of a group have its lowest indices */
            const int first = k == 1 || point_cmp_x(p + k - 1, p + k - 2) != 0;
            if (first && (p[k - 1].i < bi || (p[k - 1].i == bi && p[k].i < bk))) {
                bi = p[k - 1].i;
                bk = p[k].i;
            }
        }
    free(p);
    if (bi != UINT32_MAX)
        return mote_fail(err, MOTE_EINVAL, "bodies %u and %u are at the same point", bi + 1,
                         bk + 1);
    return MOTE_OK;
}

void mote_nb_barycentric(mote_nb *nb, mote_real xc[3], mote_real vc[3])
{
    mote_real M = 0, X[3] = {0, 0, 0}, V[3] = {0, 0, 0};
    for (uint32_t i = 0; i < nb->n; i++) {
        if (!nb->active[i])
            continue;
        M += nb->m[i];
        for (int a = 0; a < 3; a++) {
            X[a] += nb->m[i] * nb->x[3 * i + a];
            V[a] += nb->m[i] * nb->v[3 * i + a];
        }
    }
    for (int a = 0; a < 3; a++) {
        X[a] /= M;
        V[a] /= M;
    }
    for (uint32_t i = 0; i < nb->n; i++)
        for (int a = 0; a < 3; a++) {
            nb->x[3 * i + a] -= X[a];
            nb->v[3 * i + a] -= V[a];
        }
    for (int a = 0; a < 3; a++) {
        if (xc)
            xc[a] = X[a];
        if (vc)
            vc[a] = V[a];
    }
    nb->ref_set = 0;
}

mote_real mote_nb_dmz(const mote_nb *nb)
{
    nb_ksum mz = {0, 0};
    for (uint32_t i = 0; i < nb->n; i++) {
        if (!nb->active[i])
            continue;
        const mote_real *x = nb->x + 3 * (size_t)i, *v = nb->v + 3 * (size_t)i;
        nb_ksum_add(&mz, nb->m[i] * (x[0] * v[1] - x[1] * v[0]));
        nb_ksum_add(&mz, nb->sp[3 * (size_t)i + 2]);
    }
    return (nb_ksum_value(&mz) - nb->Mza1) / (nb->Lnorm1 != 0 ? nb->Lnorm1 : 1);
}

void mote_nb_measure(const mote_nb *nb, mote_nb_monitor *mon)
{
    memset(mon, 0, sizeof *mon);
    nb_ksum ek = {0, 0}, u = {0, 0};
    for (uint32_t i = 0; i < nb->n; i++) {
        if (!nb->active[i])
            continue;
        const mote_real *x = nb->x + 3 * (size_t)i, *v = nb->v + 3 * (size_t)i, m = nb->m[i];
        nb_ksum_add(&ek, 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
        mon->mtot += m;
        for (int a = 0; a < 3; a++) {
            mon->P[a] += m * v[a];
            mon->R[a] += m * x[a];
            mon->S[a] += nb->sp[3 * i + a];
        }
        mon->L[0] += m * (x[1] * v[2] - x[2] * v[1]);
        mon->L[1] += m * (x[2] * v[0] - x[0] * v[2]);
        mon->L[2] += m * (x[0] * v[1] - x[1] * v[0]);
        for (uint32_t k = i + 1; k < nb->n; k++) {
            if (!nb->active[k])
                continue;
            const mote_real *y = nb->x + 3 * (size_t)k;
            mote_real d0 = x[0] - y[0], d1 = x[1] - y[1], d2 = x[2] - y[2];
            mote_real r = sqrt(d0 * d0 + d1 * d1 + d2 * d2 + nb->soft * nb->soft);
            if (nb->kind == MOTE_NB_GRAVITY)
                nb_ksum_add(&u, -m * nb->m[k] / r);
            else
                nb_ksum_add(&u, nb->q[i] * nb->q[k] / r);
        }
    }
    mon->ekin = nb_ksum_value(&ek);
    mon->u = nb_ksum_value(&u);
    mon->etot = mon->ekin + mon->u;
    mon->ecorr = mon->etot - nb->de_merge;
    if (nb->ref_set) {
        /* relative to |E0|; absolute when E0 is 0 (one body, a parabolic pair), never a
         * division by zero (callers name it dE_abs then: mote_nb_de_absolute) */
        mon->dE = nb->E0 != 0 ? (mon->ecorr - nb->E0) / fabs(nb->E0) : mon->ecorr - nb->E0;
        mon->dMz = (mon->L[2] + mon->S[2] - nb->Mza1) / (nb->Lnorm1 != 0 ? nb->Lnorm1 : 1);
        mote_real d2 = 0, l2 = 0;
        for (int a = 0; a < 3; a++) {
            mote_real d = mon->L[a] + mon->S[a] - nb->L1[a];
            d2 += d * d;
            l2 += nb->L1[a] * nb->L1[a];
        }
        mon->dL = l2 > 0 ? sqrt(d2 / l2) : 0;
    }
}

void mote_nb_set_reference(mote_nb *nb)
{
    nb->ref_set = 0;
    mote_nb_monitor mon;
    mote_nb_measure(nb, &mon);
    nb->E0 = mon.ecorr;
    nb->Mza1 = mon.L[2] + mon.S[2];
    for (int a = 0; a < 3; a++)
        nb->L1[a] = mon.L[a] + mon.S[a];
    /* spec 3.7: normalise by Mza1 unless it is below 1e-14 of sum m |x x v| */
    mote_real sum = 0;
    for (uint32_t i = 0; i < nb->n; i++) {
        if (!nb->active[i])
            continue;
        const mote_real *x = nb->x + 3 * (size_t)i, *v = nb->v + 3 * (size_t)i;
        mote_real c0 = x[1] * v[2] - x[2] * v[1], c1 = x[2] * v[0] - x[0] * v[2],
               c2 = x[0] * v[1] - x[1] * v[0];
        sum += nb->m[i] * sqrt(c0 * c0 + c1 * c1 + c2 * c2);
    }
    nb->Lnorm1 = fabs(nb->Mza1) >= 1e-14 * sum ? nb->Mza1 : sum;
    if (nb->Lnorm1 == 0) /* no angular momentum at all: dMz is the absolute change */
        nb->Lnorm1 = 1;
    nb->ref_set = 1;
}

const char *mote_real_str(mote_real v, char buf[MOTE_REAL_BUF])
{
#if MOTE_NB_PRECISION == 4
    strfromf128(buf, MOTE_REAL_BUF, "%.36g", v);
#elif MOTE_NB_PRECISION == 2
    snprintf(buf, MOTE_REAL_BUF, "%.21Lg", v);
#else
    snprintf(buf, MOTE_REAL_BUF, "%.17g", v);
#endif
    return buf;
}

mote_real mote_real_parse(const char *s, char **end)
{
#if MOTE_NB_PRECISION == 4
    return strtof128(s, end);
#elif MOTE_NB_PRECISION == 2
    return strtold(s, end);
#else
    return strtod(s, end);
#endif
}
