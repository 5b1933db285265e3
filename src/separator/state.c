/* state.c: the separator's state file (`save`, `load`; specs/separator.md 2.12): the parameters,
 * species, plates, size classes, the particle arrays with their ids and last contact forces, the
 * random stream, the feed accounts and backlog, the relaxed solids fraction, the exit tallies,
 * the profile sums, counters, time and step number, every number exact (%.17g reads back to the
 * same double), so that save, load, save gives the same bytes and a run continued from a file
 * is bit for bit the run that never stopped. The schedules of frames, snapshots and the balance
 * belong to the script and are not in the file.
 *
 * The file is a sequence of lines "KEY value ...", read back in the order written; reading is
 * strict and names FILE:LINE for every fault. Counts are checked against what follows before
 * anything is allocated for them. */
#include "mote/separator.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "mote/statefile.h"

#include "sep.h"

#define SEP_PI 3.14159265358979323846

/* A real for the file: exact, with inf written "inf" (t_stop may be) and nan "nan" */
static void real_put(char out[64], const void *v)
{
    const double x = *(const double *)v;
    if (isinf(x))
        snprintf(out, 64, "%s", x > 0 ? "inf" : "-inf");
    else if (isnan(x))
        snprintf(out, 64, "nan");
    else
        mote_sf_exact_put(out, v);
}
static size_t real_get(const char *t, void *v)
{
    static const char *const words[3] = {"inf", "-inf", "nan"};
    const double values[3] = {INFINITY, -INFINITY, NAN};
    for (int k = 0; k < 3; k++) {
        const size_t n = strlen(words[k]);
        if (strncmp(t, words[k], n) == 0 && (t[n] == '\0' || t[n] == ' ' || t[n] == '\t')) {
            *(double *)v = values[k];
            return n;
        }
    }
    return mote_sf_exact_get(t, v);
}
static const mote_sf_codec REAL = {sizeof(double), real_put, real_get, NULL};

static void put(FILE *f, double x)
{
    char b[64];
    real_put(b, &x);
    fprintf(f, " %s", b);
}

/* The scalar parameters by name ("real W 0.05", "int dim 2"), the counters and the random
 * stream, as descriptor tables (statefile.h); the seed is read into a scratch. */
#define SR(NAME, M)                                                                          \
    {.key = "real " NAME, .name = NAME, .type = MOTE_SF_CODEC,                            \
     .offset = offsetof(mote_sep_system, M), .codec = &REAL}
#define SI(NAME, M)                                                                          \
    {.key = "int " NAME, .name = NAME, .type = MOTE_SF_INT,                               \
     .offset = offsetof(mote_sep_system, M), .lo = -1, .hi = 1000000}
#define SU(K, NAME, M)                                                                       \
    {.key = K, .name = NAME, .type = MOTE_SF_U64, .offset = offsetof(mote_sep_system, M),    \
     .lo = MOTE_SF_ANY}
static const mote_sf_field SCALARS[] = {
    SR("W", W), SR("H", H), SR("D", D), SR("D2", D2), SR("U0", U0), SR("rho_g", rho_g),
    SR("mu_g", mu_g), SR("g", g), SR("eps_gas_min", eps_gas_min), SR("chi", chi),
    SR("D_t", D_t), SR("T_gas", T_gas), SR("e_pw", e_pw), SR("dt_user", dt_user),
    SR("e_pp", e_pp), SR("khat", khat), SR("delta_f", delta_f), SR("v_imp", v_imp),
    SR("tau_eps", tau_eps), SR("zf", zf), SR("hf", hf), SR("rate", rate),
    SR("t_start", t_start), SR("t_stop", t_stop), SR("fx1", fx1), SR("fx2", fx2),
    SR("fy1", fy1), SR("fy2", fy2), SR("vfx", vf[0]), SR("vfy", vf[1]), SR("vfz", vf[2]),
    SR("avg_from", avg_from), SR("prof_time", prof_time), SR("prof_wait", prof_wait),
    SR("max_overlap", max_overlap), SR("t", t),
    SI("dim", dim), SI("open_bottom", open_bottom), SI("open_top", open_top),
    SI("coupling", coupling), SI("K", K), SI("dem", dem), SI("brute", brute), SI("nc", nc),
    SI("nsort", nsort), SI("eps_r_valid", eps_r_valid),
    SU("counters", "steps", steps), SU(NULL, "next_id", next_id),
    SU(NULL, "fast_moves", fast_moves), SU(NULL, "last_sort", last_sort),
    {.key = "rng", .name = "s", .type = MOTE_SF_HEX64, .offset = offsetof(mote_sep_system, rng.s),
     .count = 4},
};
static const mote_sf_field SEED[] = {
    {.key = "seed", .name = "S", .type = MOTE_SF_U64, .offset = 0, .lo = MOTE_SF_ANY},
};
#define NF(t) (sizeof t / sizeof t[0])

int mote_sep_save(const mote_sep_system *s, uint64_t seed, const char *path, mote_err *err)
{
    if (!s->class_edge || !s->eps_r || !s->prof_n)
        return mote_fail(err, MOTE_EINVAL, "%s: nothing to save before the system is prepared",
                         path);
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc)
        return rc;
    FILE *f = af.f;
    mote_sf_write_head(f, "separator", 1);
    mote_sf_write(f, SEED, NF(SEED), &seed, 1);
    mote_sf_write(f, SCALARS, NF(SCALARS), s, 1);
    fprintf(f, "gasprofile %zu\n", s->gp_n);
    for (size_t k = 0; k < s->gp_n; k++) {
        fprintf(f, "gp");
        put(f, s->gp_z[k]);
        put(f, s->gp_rho[k]);
        put(f, s->gp_mu[k]);
        fputc('\n', f);
    }
    fprintf(f, "species %d\n", s->nsp);
    for (int k = 0; k < s->nsp; k++) {
        const mote_sep_species *p = &s->sp[k];
        fprintf(f, "sp %s %d %d %d", p->name, p->have_dist, p->dist.type, p->dist.number_basis);
        put(f, p->rho);
        put(f, p->w);
        put(f, p->dist.a);
        put(f, p->dist.b);
        put(f, p->dist.lo);
        put(f, p->dist.hi);
        fputc('\n', f);
        fprintf(f, "table %d\n", p->dist.tn);
        for (int j = 0; j < p->dist.tn; j++) {
            fprintf(f, "row");
            put(f, p->dist.td[j]);
            put(f, p->dist.tF[j]);
            fputc('\n', f);
        }
        const mote_sep_count *c = &s->cnt[k];
        fprintf(f, "count %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64, c->fed, c->fines, c->coarse,
                c->lost);
        put(f, c->m_fed);
        put(f, c->m_fines);
        put(f, c->m_coarse);
        put(f, c->m_lost);
        put(f, c->m_gen);
        fputc('\n', f);
        fprintf(f, "epair");
        for (int j = 0; j < s->nsp; j++)
            put(f, s->e_pair[k][j]);
        fputc('\n', f);
    }
    fprintf(f, "plates %d\n", s->nplate);
    for (int q = 0; q < s->nplate; q++) {
        const mote_sep_plate *p = &s->plate[q];
        fprintf(f, "plate %zu %d %ld", p->nh, p->listed, p->dropped);
        put(f, p->zb);
        put(f, p->t);
        fputc('\n', f);
        for (size_t h = 0; h < p->nh; h++) {
            fprintf(f, "hole");
            for (int j = 0; j < 4; j++)
                put(f, p->h[4 * h + (size_t)j]);
            fputc('\n', f);
        }
    }
    fprintf(f, "classes %d\n", s->nclass);
    for (int i = 0; i <= s->nclass; i++) {
        fprintf(f, "edge");
        put(f, s->class_edge[i]);
        if (i < s->nclass) {
            fprintf(f, " %" PRIu64 " %" PRIu64, s->cl_nf[i], s->cl_nc[i]);
            put(f, s->cl_mf[i]);
            put(f, s->cl_mc[i]);
            for (int k = 0; k < s->nsp; k++) {
                const size_t q = (size_t)i * MOTE_SEP_MAX_SPECIES + (size_t)k;
                fprintf(f, " %" PRIu64 " %" PRIu64, s->cls_nf[q], s->cls_nc[q]);
                put(f, s->cls_mf[q]);
                put(f, s->cls_mc[q]);
            }
        }
        fputc('\n', f);
    }
    fprintf(f, "slices %d\n", s->K);
    for (int k = 0; k < s->K; k++) {
        fprintf(f, "slice");
        put(f, s->eps_r[k]);
        put(f, s->prof_n[k]);
        put(f, s->prof_mvz[k]);
        put(f, s->prof_m[k]);
        put(f, s->prof_ug[k]);
        put(f, s->prof_fd[k]);
        for (int j = 0; j < s->nsp; j++)
            put(f, s->prof_eps[(size_t)k * MOTE_SEP_MAX_SPECIES + (size_t)j]);
        fputc('\n', f);
    }
    fprintf(f, "backlog %zu\n", s->nback);
    for (size_t b = 0; b < s->nback; b++) {
        fprintf(f, "b %d", s->back_s[b]);
        put(f, s->back_d[b]);
        fputc('\n', f);
    }
    /* the pair list when it still serves (nothing added or removed since its build), so that a
     * continued run sums the contact forces in the same order */
    const int live = s->list_ok && s->mods == s->list_mods && s->xref_cap >= 3 * s->n;
    fprintf(f, "pairlist %d %" PRIu64 " %" PRIu64 " %" PRIu64 " %zu\n", live, s->mods,
            s->list_mods, s->list_builds, live ? s->npl : (size_t)0);
    for (size_t k = 0; live && k < s->npl; k++)
        fprintf(f, "l %u %u\n", s->plist[2 * k], s->plist[2 * k + 1]);
    fprintf(f, "particles %zu\n", s->n);
    for (size_t i = 0; i < s->n; i++) {
        fprintf(f, "p %" PRIu64 " %d", s->id[i], s->s[i]);
        const double v[11] = {s->d[i], s->m[i], s->x[i], s->y[i], s->z[i], s->vx[i],
                              s->vy[i], s->vz[i], s->fx[i], s->fy[i], s->fz[i]};
        for (int j = 0; j < 11; j++)
            put(f, v[j]);
        for (int j = 0; live && j < 3; j++) /* where the list was built */
            put(f, s->xref[3 * i + (size_t)j]);
        fputc('\n', f);
    }
    fprintf(f, "end\n");
    return mote_afile_commit(&af, err);
}

/* ---- reading -------------------------------------------------------------------------------- */

typedef struct {
    mote_lines in;
    char *tok[64];
    int ntok;
    mote_err *err;
} reader;

static int bad(reader *r, const char *what, const char *found)
{
    return mote_fail(r->err, MOTE_EINVAL, "%s:%ld: %s%s%s%s", r->in.path, r->in.line, what,
                     found ? " (found '" : "", found ? found : "", found ? "')" : "");
}

/* The next line, split; it must start with key and hold n values after it (n < 0: at least
 * -n). */
static int line(reader *r, const char *key, int n, const char *what)
{
    char *l = mote_lines_next(&r->in);
    if (!l) {
        r->in.line++;
        return bad(r, what, "the end of the file");
    }
    r->ntok = 0;
    char *save = NULL;
    for (char *t = strtok_r(l, " \t", &save); t; t = strtok_r(NULL, " \t", &save)) {
        if (r->ntok == 64)
            return bad(r, what, "too many values");
        r->tok[r->ntok++] = t;
    }
    if (r->ntok == 0 || strcmp(r->tok[0], key) || (n >= 0 ? r->ntok != n + 1 : r->ntok < 1 - n))
        return bad(r, what, r->ntok ? r->tok[0] : "an empty line");
    return MOTE_OK;
}

static int real_at(reader *r, int k, double *x)
{
    const char *t = r->tok[k];
    if (!strcmp(t, "inf") || !strcmp(t, "-inf")) {
        *x = t[0] == '-' ? -INFINITY : INFINITY;
        return MOTE_OK;
    }
    if (!strcmp(t, "nan")) {
        *x = NAN;
        return MOTE_OK;
    }
    char *end;
    errno = 0;
    *x = strtod(t, &end);
    if (end == t || *end || errno == ERANGE || strchr(t, 'x') || strchr(t, 'X'))
        return bad(r, "expected a decimal number", t);
    return MOTE_OK;
}

static int u64_at(reader *r, int k, uint64_t *x, int base)
{
    const char *t = r->tok[k];
    char *end;
    errno = 0;
    if (*t == '-' || *t == '+')
        return bad(r, "expected an unsigned integer", t);
    *x = strtoull(t, &end, base);
    if (end == t || *end || errno == ERANGE)
        return bad(r, base == 16 ? "expected a 64-bit hexadecimal word" : "expected an unsigned "
                   "integer", t);
    return MOTE_OK;
}

static int int_at(reader *r, int k, long lo, long hi, long *x)
{
    const char *t = r->tok[k];
    char *end;
    errno = 0;
    *x = strtol(t, &end, 10);
    if (end == t || *end || errno == ERANGE || *x < lo || *x > hi) {
        char what[96];
        snprintf(what, sizeof what, "expected an integer from %ld to %ld", lo, hi);
        return bad(r, what, t);
    }
    return MOTE_OK;
}

/* Reals tok[k0 ...] into x[0 .. n-1]. */
static int reals(reader *r, int k0, int n, double *x)
{
    int rc = MOTE_OK;
    for (int j = 0; j < n && !rc; j++)
        rc = real_at(r, k0 + j, &x[j]);
    return rc;
}

static int read_body(reader *r, mote_sep_system *s, uint64_t *seed)
{
    int version;
    int rc = mote_sf_read_head(&r->in, "separator", 1, &version, r->err);
    if (!rc)
        rc = mote_sf_read(&r->in, SEED, NF(SEED), seed, version, r->err);
    if (!rc)
        rc = mote_sf_read(&r->in, SCALARS, NF(SCALARS), s, version, r->err);
    if (rc)
        return rc;
    if (s->dim != 2 && s->dim != 3)
        return bad(r, "dim must be 2 or 3", NULL);
    if (s->K < 1 || s->K > 1000)
        return bad(r, "the slices must number 1 to 1000", NULL);
    if (!(s->rng.s[0] | s->rng.s[1] | s->rng.s[2] | s->rng.s[3]))
        rc = bad(r, "the random stream's state must not be all zero", NULL);
    long v;
    uint64_t ngp = 0;
    if (!rc)
        rc = line(r, "gasprofile", 1, "expected 'gasprofile N'");
    if (!rc)
        rc = u64_at(r, 1, &ngp, 10);
    if (!rc && ngp > 1000000)
        rc = bad(r, "a gas profile of more than 1e6 rows", r->tok[1]);
    if (!rc && ngp) {
        double *g = malloc(3 * (size_t)ngp * sizeof *g);
        if (!g)
            return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
        for (uint64_t k = 0; k < ngp && !rc; k++) {
            double x[3] = {0, 0, 0};
            rc = line(r, "gp", 3, "expected 'gp Z RHO MU'");
            if (!rc)
                rc = reals(r, 1, 3, x);
            g[k] = x[0];
            g[ngp + k] = x[1];
            g[2 * ngp + k] = x[2];
        }
        mote_err e2 = {0};
        if (!rc && mote_sep_set_gas_profile(s, (size_t)ngp, g, g + ngp, g + 2 * ngp, &e2))
            rc = bad(r, e2.msg, NULL);
        free(g);
    }
    if (!rc)
        rc = line(r, "species", 1, "expected 'species N'");
    if (!rc)
        rc = int_at(r, 1, 1, MOTE_SEP_MAX_SPECIES, &v);
    if (rc)
        return rc;
    const int nsp = (int)v;
    for (int k = 0; k < nsp && !rc; k++) {
        mote_sep_species *p = &s->sp[k];
        long hd, ty, nb;
        rc = line(r, "sp", 10, "expected 'sp NAME HAVE TYPE BASIS RHO W A B LO HI'");
        if (!rc && strlen(r->tok[1]) >= sizeof p->name)
            rc = bad(r, "a species name too long", r->tok[1]);
        if (!rc)
            rc = int_at(r, 2, 0, 1, &hd);
        if (!rc)
            rc = int_at(r, 3, 0, MOTE_SEP_LOGUNIFORM, &ty);
        if (!rc)
            rc = int_at(r, 4, 0, 1, &nb);
        double x[6];
        if (!rc)
            rc = reals(r, 5, 6, x);
        if (rc)
            return rc;
        snprintf(p->name, sizeof p->name, "%s", r->tok[1]);
        p->have_dist = (int)hd;
        p->rho = x[0];
        p->w = x[1];
        p->dist = (mote_sep_dist){.type = (int)ty, .a = x[2], .b = x[3], .lo = x[4], .hi = x[5],
                                  .number_basis = (int)nb};
        s->nsp = k + 1;
        if (!(p->rho > 0))
            return bad(r, "a species density must be > 0", r->tok[5]);
        long tn;
        rc = line(r, "table", 1, "expected 'table N'");
        if (!rc)
            rc = int_at(r, 1, 0, 100000, &tn);
        if (rc)
            return rc;
        if (tn) {
            double *tab = malloc(2 * (size_t)tn * sizeof *tab);
            if (!tab)
                return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
            for (long j = 0; j < tn && !rc; j++) {
                rc = line(r, "row", 2, "expected 'row D F'");
                if (!rc)
                    rc = real_at(r, 1, &tab[j]);
                if (!rc)
                    rc = real_at(r, 2, &tab[tn + j]);
            }
            mote_err e2 = {0};
            const double lo = p->dist.lo, hi = p->dist.hi;
            if (!rc && mote_sep_dist_table(&p->dist, (int)tn, tab, tab + tn, &e2))
                rc = bad(r, e2.msg, NULL);
            p->dist.lo = lo;
            p->dist.hi = hi;
            free(tab);
            if (rc)
                return rc;
        }
        if (p->have_dist && mote_sep_dist_build(&p->dist, r->err))
            return mote_fail(r->err, MOTE_EINVAL, "%s:%ld: %s", r->in.path, r->in.line,
                             r->err->msg);
        mote_sep_count *c = &s->cnt[k];
        rc = line(r, "count", 9, "expected 'count FED FINES COARSE LOST' and 5 masses");
        if (!rc)
            rc = u64_at(r, 1, &c->fed, 10);
        if (!rc)
            rc = u64_at(r, 2, &c->fines, 10);
        if (!rc)
            rc = u64_at(r, 3, &c->coarse, 10);
        if (!rc)
            rc = u64_at(r, 4, &c->lost, 10);
        if (!rc)
            rc = real_at(r, 5, &c->m_fed);
        if (!rc)
            rc = real_at(r, 6, &c->m_fines);
        if (!rc)
            rc = real_at(r, 7, &c->m_coarse);
        if (!rc)
            rc = real_at(r, 8, &c->m_lost);
        if (!rc)
            rc = real_at(r, 9, &c->m_gen);
        if (!rc)
            rc = line(r, "epair", nsp, "expected 'epair' and one restitution per species");
        if (!rc)
            rc = reals(r, 1, nsp, s->e_pair[k]);
    }
    if (!rc)
        rc = line(r, "plates", 1, "expected 'plates N'");
    if (!rc)
        rc = int_at(r, 1, 0, MOTE_SEP_MAX_PLATES, &v);
    const int np = rc ? 0 : (int)v;
    for (int q = 0; q < np && !rc; q++) {
        uint64_t nh;
        long listed, dropped;
        double zt[2];
        rc = line(r, "plate", 5, "expected 'plate NHOLES LISTED DROPPED ZB T'");
        if (!rc)
            rc = u64_at(r, 1, &nh, 10);
        if (!rc)
            rc = int_at(r, 2, 0, 1, &listed);
        if (!rc)
            rc = int_at(r, 3, 0, 2000000000, &dropped);
        if (!rc)
            rc = reals(r, 4, 2, zt);
        if (!rc && (nh == 0 || nh > 100000000))
            rc = bad(r, "a plate needs 1 to 1e8 holes", r->tok[1]);
        if (rc)
            break;
        double *h = malloc((size_t)nh * 4 * sizeof *h);
        if (!h)
            return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
        for (uint64_t k = 0; k < nh && !rc; k++) {
            rc = line(r, "hole", 4, "expected 'hole X1 X2 Y1 Y2'");
            if (!rc)
                rc = reals(r, 1, 4, h + 4 * k);
        }
        if (!rc) {
            rc = mote_sep_plate_list(&s->plate[q], zt[0], zt[1], h, (size_t)nh, r->err);
            s->plate[q].listed = (int)listed;
            s->plate[q].dropped = dropped;
            if (!rc)
                s->nplate = q + 1;
        }
        free(h);
    }
    if (!rc)
        rc = line(r, "classes", 1, "expected 'classes N'");
    if (!rc)
        rc = int_at(r, 1, 2, 1000, &v);
    if (rc)
        return rc;
    s->nclass = (int)v;
    const size_t nc = (size_t)s->nclass;
    s->class_edge = malloc((nc + 1) * sizeof *s->class_edge);
    if (!s->class_edge)
        return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
    if (sep_tallies_alloc(s, r->err))
        return r->err->code;
    for (size_t i = 0; i <= nc && !rc; i++) {
        const int last = i == nc;
        rc = line(r, "edge", last ? 1 : 5 + 4 * nsp, "expected 'edge' with a class's edge and tallies");
        if (!rc)
            rc = real_at(r, 1, &s->class_edge[i]);
        if (last || rc)
            break;
        rc = u64_at(r, 2, &s->cl_nf[i], 10);
        if (!rc)
            rc = u64_at(r, 3, &s->cl_nc[i], 10);
        if (!rc)
            rc = real_at(r, 4, &s->cl_mf[i]);
        if (!rc)
            rc = real_at(r, 5, &s->cl_mc[i]);
        for (int k = 0; k < nsp && !rc; k++) {
            const size_t q = i * MOTE_SEP_MAX_SPECIES + (size_t)k;
            rc = u64_at(r, 6 + 4 * k, &s->cls_nf[q], 10);
            if (!rc)
                rc = u64_at(r, 7 + 4 * k, &s->cls_nc[q], 10);
            if (!rc)
                rc = real_at(r, 8 + 4 * k, &s->cls_mf[q]);
            if (!rc)
                rc = real_at(r, 9 + 4 * k, &s->cls_mc[q]);
        }
    }
    for (size_t i = 0; i < nc && !rc; i++)
        if (!(s->class_edge[i + 1] > s->class_edge[i]) || !(s->class_edge[0] > 0))
            rc = bad(r, "the class edges must increase from above 0", NULL);
    if (!rc)
        rc = line(r, "slices", 1, "expected 'slices K'");
    if (!rc && (int_at(r, 1, 1, 1000, &v) || v != s->K))
        rc = bad(r, "the slices must match the parameter K", r->tok[1]);
    if (rc)
        return rc;
    const size_t K = (size_t)s->K;
    s->eps_s = calloc(K, sizeof *s->eps_s);
    s->u_g = calloc(K, sizeof *s->u_g);
    s->eps_r = calloc(K, sizeof *s->eps_r);
    if (!s->eps_s || !s->u_g || !s->eps_r)
        return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
    const double prof_time = s->prof_time; /* (read with the parameters) */
    if (sep_profiles_alloc(s, r->err))
        return r->err->code;
    s->prof_time = prof_time;
    for (size_t k = 0; k < K && !rc; k++) {
        double x[6];
        rc = line(r, "slice", 6 + nsp, "expected 'slice' and the slice's values");
        if (!rc)
            rc = reals(r, 1, 6, x);
        if (rc)
            break;
        s->eps_r[k] = x[0];
        s->prof_n[k] = x[1];
        s->prof_mvz[k] = x[2];
        s->prof_m[k] = x[3];
        s->prof_ug[k] = x[4];
        s->prof_fd[k] = x[5];
        rc = reals(r, 7, nsp, s->prof_eps + k * MOTE_SEP_MAX_SPECIES);
    }
    uint64_t nb = 0;
    if (!rc)
        rc = line(r, "backlog", 1, "expected 'backlog N'");
    if (!rc)
        rc = u64_at(r, 1, &nb, 10);
    if (!rc && nb > 100000000)
        rc = bad(r, "a backlog of more than 1e8", r->tok[1]);
    if (rc)
        return rc;
    s->back_s = malloc((nb ? nb : 1) * sizeof *s->back_s);
    s->back_d = malloc((nb ? nb : 1) * sizeof *s->back_d);
    if (!s->back_s || !s->back_d)
        return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
    s->back_cap = nb ? nb : 1;
    for (uint64_t b = 0; b < nb && !rc; b++) {
        rc = line(r, "b", 2, "expected 'b SPECIES D'");
        if (!rc)
            rc = int_at(r, 1, 0, nsp - 1, &v);
        if (!rc)
            rc = real_at(r, 2, &s->back_d[b]);
        if (!rc)
            s->back_s[b] = (int)v;
        s->nback = rc ? s->nback : b + 1;
    }
    uint64_t lmods = 0, npl = 0, fmods = 0;
    long lok = 0;
    if (!rc)
        rc = line(r, "pairlist", 5, "expected 'pairlist OK MODS LIST_MODS BUILDS N'");
    if (!rc)
        rc = int_at(r, 1, 0, 1, &lok);
    if (!rc)
        rc = u64_at(r, 2, &fmods, 10);
    if (!rc)
        rc = u64_at(r, 3, &lmods, 10);
    if (!rc)
        rc = u64_at(r, 4, &s->list_builds, 10);
    if (!rc)
        rc = u64_at(r, 5, &npl, 10);
    if (!rc && npl > 2000000000)
        rc = bad(r, "a pair list of more than 2e9 pairs", r->tok[5]);
    for (uint64_t k = 0; k < npl && !rc; k++) {
        uint64_t a, b;
        rc = line(r, "l", 2, "expected 'l I J'");
        if (!rc)
            rc = u64_at(r, 1, &a, 10);
        if (!rc)
            rc = u64_at(r, 2, &b, 10);
        if (!rc && (a > UINT32_MAX || b > UINT32_MAX))
            rc = bad(r, "a particle index beyond 2^32", r->tok[1]);
        if (!rc && s->npl == s->pl_cap) {
            const size_t cap = s->pl_cap ? 2 * s->pl_cap : 1024;
            uint32_t *p = realloc(s->plist, 2 * cap * sizeof *p);
            if (!p)
                return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
            s->plist = p;
            s->pl_cap = cap;
        }
        if (!rc) {
            s->plist[2 * s->npl] = (uint32_t)a;
            s->plist[2 * s->npl + 1] = (uint32_t)b;
            s->npl++;
        }
    }
    uint64_t n = 0;
    if (!rc)
        rc = line(r, "particles", 1, "expected 'particles N'");
    if (!rc)
        rc = u64_at(r, 1, &n, 10);
    if (!rc && n > 1000000000)
        rc = bad(r, "more than 1e9 particles", r->tok[1]);
    if (rc)
        return rc;
    /* the arrays grow as the lines come, so a false count allocates nothing large */
    for (uint64_t i = 0; i < n && !rc; i++) {
        rc = line(r, "p", lok ? 16 : 13, lok ? "expected 'p ID SPECIES D M X Y Z VX VY VZ FX FY FZ' "
                  "and the position at the list's build" : "expected 'p ID SPECIES D M X Y Z VX "
                  "VY VZ FX FY FZ'");
        uint64_t id;
        double x[11], xr[3];
        if (!rc)
            rc = u64_at(r, 1, &id, 10);
        if (!rc)
            rc = int_at(r, 2, 0, nsp - 1, &v);
        if (!rc)
            rc = reals(r, 3, 11, x);
        if (!rc && lok)
            rc = reals(r, 14, 3, xr);
        if (!rc && !(x[0] > 0 && x[1] > 0 && isfinite(x[0]) && isfinite(x[1])))
            rc = bad(r, "a particle needs a finite diameter and mass > 0", r->tok[3]);
        for (int q = 2; !rc && q < 11; q++)
            if (!isfinite(x[q]))
                rc = bad(r, "a particle's position, velocity and force must be finite",
                         r->tok[3 + q]);
        if (!rc)
            rc = sep_append(s, (int)v, id, x, r->err);
        if (!rc && lok) {
            if (3 * (i + 1) > s->xref_cap) {
                const size_t cap = 6 * (i + 1);
                double *p = realloc(s->xref, cap * sizeof *p);
                if (!p)
                    return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
                s->xref = p;
                s->xref_cap = cap;
            }
            memcpy(s->xref + 3 * i, xr, sizeof xr);
        }
    }
    /* sep_append counted the particles as additions: the counts of the file stand */
    for (size_t k = 0; !rc && k < 2 * s->npl; k++)
        if (s->plist[k] >= s->n)
            rc = bad(r, "the pair list names a particle beyond the last", NULL);
    if (!rc) {
        s->mods = fmods;
        s->list_ok = (int)lok;
        s->list_mods = lmods;
    }
    if (!rc)
        rc = line(r, "end", 0, "expected 'end'");
    if (!rc && mote_lines_next(&r->in))
        rc = bad(r, "something after 'end'", NULL);
    return rc;
}

int mote_sep_load(mote_sep_system *s, uint64_t *seed, const char *path, mote_err *err)
{
    reader r = {.err = err};
    int rc = mote_lines_open(&r.in, path, err);
    if (rc)
        return rc;
    mote_sep_system t;
    mote_sep_init(&t);
    rc = read_body(&r, &t, seed);
    const int rc2 = mote_lines_close(&r.in, err);
    rc = rc2 ? rc2 : rc;
    if (rc) {
        mote_sep_free(&t);
        return rc;
    }
    mote_sep_free(s);
    *s = t;
    s->dz = s->H / s->K;
    mote_sep_gas_update(s, 0);
    return MOTE_OK;
}
