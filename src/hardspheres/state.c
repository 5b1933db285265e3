/* state.c: exact save and load of hard-sphere states (spec 9.1), import of the original program's
 * save format with overlap repair (spec 9.2), and a cheap header peek for script validation.
 * Loading is strict: every malformed, truncated or inconsistent file is an error that names the
 * file and line; the current system is replaced only when the whole file was read and checked. */
#include "mote/hardspheres.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mote/statefile.h"

#include <stddef.h>

#include "measure.h"

/* ---- save ---------------------------------------------------------------------------------------- */

int mote_hs_settle(mote_hs *hs, mote_err *err)
{
    /* a rebuild depends on the particles, their labels and the box only (event.h), and a
     * rebuild of a rebuilt system changes nothing, so this state is the one `load` makes; when
     * nothing has moved since the last rebuild, there is nothing to do */
    if (!hs->has_system || hs->ev.canonical)
        return MOTE_OK;
    return mote_ev_rebuild(&hs->ev, err);
}

/* ---- the descriptor tables (statefile.h) --------------------------------------------------------- */

/* the head, read into and written from this scratch */
typedef struct {
    int model, dim, geometry;
    double box[3];
    uint64_t n;
    double time;
    uint64_t collisions, wall_collisions, rng[4];
} hs_head;
#define HO(M) offsetof(hs_head, M)
static const mote_sf_field HEAD_A[] = {
    {.key = "model", .name = "NAME", .type = MOTE_SF_ENUM, .offset = HO(model),
     .words = "hard-spheres"},
    {.key = "dim", .name = "D", .type = MOTE_SF_INT, .offset = HO(dim), .lo = 2, .hi = 3},
    {.key = "geometry", .name = "G", .type = MOTE_SF_ENUM, .offset = HO(geometry),
     .words = "slit|periodic"},
};
/* the box: dim lengths (box_field) */
static mote_sf_field box_field(int dim)
{
    return (mote_sf_field){.key = "box", .name = "L", .type = MOTE_SF_CODEC, .offset = HO(box),
                           .count = dim, .codec = &mote_sf_exact};
}
static const mote_sf_field HEAD_B[] = {
    {.key = "n", .name = "N", .type = MOTE_SF_U64, .offset = HO(n), .lo = 2, .hi = 0xFFFFFFF0},
    {.key = "time", .name = "T", .type = MOTE_SF_CODEC, .offset = HO(time),
     .codec = &mote_sf_exact},
    {.key = "collisions", .name = "C", .type = MOTE_SF_U64, .offset = HO(collisions),
     .lo = MOTE_SF_ANY},
    {.key = "wall_collisions", .name = "W", .type = MOTE_SF_U64, .offset = HO(wall_collisions),
     .lo = MOTE_SF_ANY},
    {.key = "rng", .name = "s", .type = MOTE_SF_HEX64, .offset = HO(rng), .count = 4},
};

/* a particle's line: x y [z] vx vy [vz] radius mass */
typedef struct {
    double r[3], v[3], radius, mass;
} hs_row;
#define HR(K, NAME, M)                                                                       \
    {.key = K, .name = NAME, .type = MOTE_SF_CODEC, .offset = offsetof(hs_row, M),           \
     .codec = &mote_sf_exact}
static const mote_sf_field ROW3[] = {
    HR("", "x", r[0]),   HR(NULL, "y", r[1]),  HR(NULL, "z", r[2]),        HR(NULL, "vx", v[0]),
    HR(NULL, "vy", v[1]), HR(NULL, "vz", v[2]), HR(NULL, "radius", radius), HR(NULL, "mass", mass),
};
static const mote_sf_field ROW2[] = {
    HR("", "x", r[0]),   HR(NULL, "y", r[1]),           HR(NULL, "vx", v[0]),
    HR(NULL, "vy", v[1]), HR(NULL, "radius", radius), HR(NULL, "mass", mass),
};
#define NF(t) (sizeof t / sizeof t[0])

/* Particle i (a slot) now: its stored coordinates when the engine is synchronised, else brought
 * to the present as the synchronisation would (the same arithmetic: the same bits). */
static void particle_now(const mote_ev *ev, uint32_t i, double r[3], double v[3])
{
    const mote_particle *p = &ev->p[i];
    if (ev->canonical) {
        memcpy(r, p->r, sizeof p->r);
        memcpy(v, p->v, sizeof p->v);
        return;
    }
    mote_ev_position(ev, i, r);
    mote_ev_velocity(ev, i, v);
}

int mote_hs_save(mote_hs *hs, const char *path, mote_err *err)
{
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "save: no system to save");
    int rc = mote_hs_settle(hs, err); /* synchronise: local times 0, coordinates wrapped */
    return rc ? rc : mote_hs_write_state(hs, path, err);
}

int mote_hs_write_state(const mote_hs *hs, const char *path, mote_err *err)
{
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "save: no system to save");
    const mote_ev *ev = &hs->ev;
    /* never a state that load refuses: finite positions, speeds up to 1e100 */
    for (uint32_t i = 0; i < ev->n; i++) {
        double r[3], v[3];
        particle_now(ev, i, r, v);
        for (int a = 0; a < ev->dim; a++)
            if (!isfinite(r[a]) || !(fabs(v[a]) <= 1e100))
                return mote_fail(err, MOTE_ERUNTIME, "save: particle %u: %s%c = %.17g is not "
                                 "a state mote can continue (positions finite, speeds up to "
                                 "1e100); %s is left as it was", i, isfinite(r[a]) ? "v" : "",
                                 "xyz"[a], isfinite(r[a]) ? v[a] : r[a], path);
    }
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc)
        return rc;
    FILE *f = af.f;
    hs_head h = {0, ev->dim, hs->geometry == MOTE_HS_SLIT ? 0 : 1,
                 {ev->len[0], ev->len[1], ev->len[2]}, ev->n,
                 ev->canonical ? ev->time_total : mote_ev_time(ev), ev->collisions,
                 ev->wall_collisions, {hs->rng.s[0], hs->rng.s[1], hs->rng.s[2], hs->rng.s[3]}};
    fprintf(f, "mote-state 1\n");
    mote_sf_write(f, HEAD_A, NF(HEAD_A), &h, 1);
    const mote_sf_field box = box_field(ev->dim);
    mote_sf_write(f, &box, 1, &h, 1);
    mote_sf_write(f, HEAD_B, NF(HEAD_B), &h, 1);
    fprintf(f, ev->dim == 3 ? "particles x y z vx vy vz radius mass\n"
                            : "particles x y vx vy radius mass\n");
    for (uint32_t id = 0; id < ev->n; id++) { /* by particle number: the seed's or the file's */
        const uint32_t i = mote_ev_slot(ev, id);
        hs_row w = {{0}, {0}, mote_ev_radius(ev, i), mote_ev_mass(ev, i)};
        particle_now(ev, i, w.r, w.v);
        if (ev->dim == 3)
            mote_sf_write(f, ROW3, NF(ROW3), &w, 1);
        else
            mote_sf_write(f, ROW2, NF(ROW2), &w, 1);
    }
    fprintf(f, "end\n");
    return mote_afile_commit(&af, err);
}

/* After validation (whose messages name file lines, so it runs in file order): from now on the
 * engine keeps its records in spatial order; the file's order stays the particles' numbers. */
static int spatial_order(mote_ev *ev, mote_err *err)
{
    ev->spatial_order = 1;
    return mote_ev_rebuild(ev, err);
}

/* ---- a strict line reader ------------------------------------------------------------------------ */

typedef mote_lines reader;

/* Next line without its LF/CRLF (in r->buf); returns 0 at end of file. */
static int next_line(reader *r) { return mote_lines_next(r) != NULL; }

/* Split the current line into at most `max` whitespace-separated tokens; returns the count (a
 * count above max means too many). */
static int split(char *s, char **tok, int max)
{
    int n = 0;
    for (char *p = s;;) {
        while (*p == ' ' || *p == '\t')
            p++;
        if (!*p)
            break;
        if (n < max)
            tok[n] = p;
        n++;
        while (*p && *p != ' ' && *p != '\t')
            p++;
        if (*p)
            *p++ = '\0';
    }
    return n;
}

static int parse_real(const char *s, double *out)
{
    if (!*s || strchr(s, 'x') || strchr(s, 'X'))
        return 0;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (*end || !isfinite(v))
        return 0;
    *out = v;
    return 1;
}

static int parse_u64(const char *s, uint64_t *out, int base)
{
    if (!*s || *s == '-' || *s == '+')
        return 0;
    char *end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, base);
    if (*end || errno)
        return 0;
    *out = v;
    return 1;
}

static int rd_fail(reader *r, mote_err *err, const char *fmt, const char *found)
{
    char what[256];
    snprintf(what, sizeof what, "%s", found ? found : "");
    return mote_fail(err, MOTE_EFORMAT, "%s:%ld: %s%s%s%s", r->path, r->line, fmt,
                     found ? " (found '" : "", what, found ? "')" : "");
}

/* ---- load: the mote format ----------------------------------------------------------------------- */

/* Check containment, periodic lengths and overlaps of a freshly read system (rebuilt). */
/* Before anything is built from the particles: centres inside the walls, periodic coordinates
 * brought into [0, L) (a huge one in one step), speeds that double precision can integrate
 * (|v| <= 1e100 per component, so the energy is finite). */
static int validate_particles(mote_ev *ev, const char *path, long first_line, mote_err *err)
{
    for (uint32_t i = 0; i < ev->n; i++) {
        double R = mote_ev_radius(ev, i);
        for (int a = 0; a < ev->dim; a++) {
            double x = ev->p[i].r[a], v = ev->p[i].v[a];
            if (!ev->periodic[a] && !(x >= R * (1 - 1e-10) && x <= ev->len[a] - R * (1 - 1e-10)))
                return mote_fail(err, MOTE_EFORMAT,
                                 "%s:%ld: particle %u: %c = %.17g is outside the walls [%.17g, "
                                 "%.17g]",
                                 path, first_line + i, i, "xyz"[a], x, R, ev->len[a] - R);
            if (ev->periodic[a] && !(x >= 0 && x < ev->len[a])) {
                x = fmod(x, ev->len[a]);
                x = x < 0 ? x + ev->len[a] : x;
                ev->p[i].r[a] = x < ev->len[a] ? x : 0;
            }
            if (!(fabs(v) <= 1e100))
                return mote_fail(err, MOTE_EFORMAT,
                                 "%s:%ld: particle %u: v%c = %.17g: speeds above 1e100 cannot be "
                                 "integrated (the kinetic energy would overflow)",
                                 path, first_line + i, i, "xyz"[a], v);
        }
    }
    return MOTE_OK;
}

/* After the first rebuild (cells exist): no two particles overlap. */
static int validate_loaded(mote_hs *hs, const char *path, long first_line, mote_err *err)
{
    mote_ev *ev = &hs->ev;
    uint32_t wi, wj;
    double ratio = mote_ev_min_gap_ratio(ev, &wi, &wj);
    if (ratio < 1 - 1e-10)
        return mote_fail(err, MOTE_EFORMAT,
                         "%s:%ld: particles %u and %u (lines %ld and %ld) overlap: distance is "
                         "%.12g of contact",
                         path, first_line + wi, wi, wj, first_line + wi, first_line + wj, ratio);
    return MOTE_OK;
}

/* The head after "mote-state V" (already read): model, dim, geometry, box, n, time, the
 * counters and the random stream, through the tables; then the checks across values. */
static int read_head(reader *r, hs_head *h, mote_err *err)
{
    h->box[2] = 1;
    int rc = mote_sf_read(r, HEAD_A, NF(HEAD_A), h, 1, err);
    if (!rc) {
        const mote_sf_field box = box_field(h->dim);
        rc = mote_sf_read(r, &box, 1, h, 1, err);
    }
    for (int a = 0; !rc && a < h->dim; a++)
        if (!(h->box[a] > 0))
            rc = rd_fail(r, err, "box lengths must be positive real numbers", NULL);
    return rc ? rc : mote_sf_read(r, HEAD_B, NF(HEAD_B), h, 1, err);
}

/* "mote-state V" on the line just read: only version 1 */
static int check_version(reader *r, mote_err *err)
{
    char *all[12];
    int n = split(r->buf, all, 12);
    if (n != 2 || strcmp(all[1], "1") != 0)
        return rd_fail(r, err, "unsupported state file version (this mote reads 'mote-state 1')",
                       n > 1 ? all[1] : NULL);
    return MOTE_OK;
}

/* The 'particles' line: the columns of a system of dimension dim. */
static int particles_line(reader *r, int dim, mote_err *err)
{
    const char *want3 = "particles x y z vx vy vz radius mass";
    const char *want2 = "particles x y vx vy radius mass";
    char *ptok[12];
    char copy[256];
    snprintf(copy, sizeof copy, "%s", r->buf);
    int np = split(copy, ptok, 12);
    char joined[256] = "";
    for (int k = 0; k < np && k < 12; k++) {
        if (k)
            strcat(joined, " ");
        strncat(joined, ptok[k], sizeof joined - strlen(joined) - 2);
    }
    if (strcmp(joined, dim == 3 ? want3 : want2) != 0) {
        char msg[128];
        snprintf(msg, sizeof msg, "expected '%s'", dim == 3 ? want3 : want2);
        return rd_fail(r, err, msg, r->buf);
    }
    return MOTE_OK;
}

/* The header's n is not trusted with memory: count the lines that follow first. */
static int enough_lines(reader *r, uint64_t n64, mote_err *err)
{
    long here = ftell(r->f);
    if (here < 0)
        return MOTE_OK;
    uint64_t lines = 0;
    int c, last = '\n';
    while ((c = getc(r->f)) != EOF) {
        lines += c == '\n';
        last = c;
    }
    lines += last != '\n';
    if (fseek(r->f, here, SEEK_SET) != 0)
        return mote_fail(err, MOTE_EIO, "%s: cannot read the particles again: %s", r->path,
                         strerror(errno));
    if (lines < n64) {
        char msg[200];
        snprintf(msg, sizeof msg,
                 "file ends early: n = %llu, but only %llu lines follow the 'particles' line",
                 (unsigned long long)n64, (unsigned long long)lines);
        r->line += (long)lines + (last == '\n'); /* the cut line, or the first missing */
        return rd_fail(r, err, msg, NULL);
    }
    return MOTE_OK;
}

/* The particle rows into ev (its n, of dimension dim), then 'end' and nothing after it. */
static int particle_rows(reader *r, mote_ev *ev, int dim, mote_err *err)
{
    for (uint32_t i = 0; i < ev->n; i++) {
        if (!next_line(r)) {
            r->line++;
            char msg[160];
            snprintf(msg, sizeof msg, "file ends early: expected particle %u of %u", i, ev->n);
            return rd_fail(r, err, msg, NULL);
        }
        hs_row w = {{0, 0, 0}, {0, 0, 0}, 0, 0};
        int rc = dim == 3 ? mote_sf_parse_line(r, r->buf, ROW3, NF(ROW3), &w, 1, err)
                          : mote_sf_parse_line(r, r->buf, ROW2, NF(ROW2), &w, 1, err);
        if (rc) {
            char why[sizeof err->msg];
            const char *c = strchr(err->msg + strlen(r->path) + 1, ':');
            snprintf(why, sizeof why, "%s", c && c[1] == ' ' ? c + 2 : err->msg);
            char msg[sizeof err->msg + 32];
            snprintf(msg, sizeof msg, "particle %u: %s", i, why);
            return rd_fail(r, err, msg, NULL);
        }
        for (int a = 0; a < dim; a++) {
            ev->p[i].r[a] = w.r[a];
            ev->p[i].v[a] = w.v[a];
        }
        ev->radius[i] = w.radius;
        ev->mass[i] = w.mass;
        if (!(ev->radius[i] > 0) || !(ev->mass[i] > 0))
            return rd_fail(r, err, "radius and mass must be > 0", NULL);
    }
    if (!next_line(r)) {
        r->line++;
        return rd_fail(r, err, "file ends early: expected 'end' (truncated file?)", NULL);
    }
    char *et[2];
    if (split(r->buf, et, 2) != 1 || strcmp(et[0], "end") != 0)
        return rd_fail(r, err, "expected 'end' after the particles", r->buf);
    while (next_line(r))
        if (split(r->buf, et, 1) != 0)
            return rd_fail(r, err, "unexpected text after 'end'", r->buf);
    return MOTE_OK;
}

static int load_mote(mote_hs *hs, reader *r, mote_err *err)
{
    hs_head h;
    memset(&h, 0, sizeof h);
    int rc = check_version(r, err);
    if (!rc)
        rc = read_head(r, &h, err);
    if (rc)
        return rc;
    if (!(h.time >= 0))
        return rd_fail(r, err, "time must be a real number >= 0", NULL);
    if (!(h.rng[0] | h.rng[1] | h.rng[2] | h.rng[3]))
        return rd_fail(r, err, "rng state must not be all zero", NULL);
    const int dim = h.dim, geometry = h.geometry == 1 ? MOTE_HS_PERIODIC : MOTE_HS_SLIT;
    const double *box = h.box;
    const uint64_t n64 = h.n, coll = h.collisions, wcoll = h.wall_collisions;
    const double time_total = h.time;
    mote_rng rng;
    memcpy(rng.s, h.rng, sizeof rng.s);
    if (!next_line(r))
        return r->line++, rd_fail(r, err, "file ends early: expected the 'particles' line", NULL);
    if ((rc = particles_line(r, dim, err)))
        return rc;
    if ((rc = enough_lines(r, n64, err)))
        return rc;
    mote_ev ev;
    rc = mote_ev_init(&ev, (uint32_t)n64, dim, 1, err);
    if (rc)
        return rc;
    long first_line = r->line + 1;
    if ((rc = particle_rows(r, &ev, dim, err))) {
        mote_ev_free(&ev);
        return rc;
    }
    /* monodisperse systems use the fast equal-mass path */
    int mono = 1;
    for (uint32_t i = 1; i < ev.n; i++)
        if (ev.radius[i] != ev.radius[0] || ev.mass[i] != ev.mass[0])
            mono = 0;
    if (mono) {
        ev.radius0 = ev.radius[0];
        ev.mass0 = ev.mass[0];
        free(ev.radius);
        free(ev.mass);
        ev.radius = ev.mass = NULL;
    }
    for (int a = 0; a < 3; a++) {
        ev.len[a] = box[a];
        ev.periodic[a] = a < dim && (geometry == MOTE_HS_PERIODIC || a > 0);
    }
    ev.time_total = time_total;
    ev.collisions = coll;
    ev.wall_collisions = wcoll;

    mote_hs tmp = *hs;
    tmp.ev = ev;
    tmp.geometry = geometry;
    tmp.has_system = 1;
    rc = validate_particles(&tmp.ev, r->path, first_line, err);
    if (!rc)
        rc = mote_ev_rebuild(&tmp.ev, err);
    if (rc == MOTE_EFORMAT) {
        mote_ev_free(&tmp.ev);
        return rc;
    }
    if (rc) {
        char why[sizeof err->msg];
        snprintf(why, sizeof why, "%s", err->msg);
        mote_fail(err, rc, "%s: %s", r->path, why);
        mote_ev_free(&tmp.ev);
        return rc;
    }
    if ((rc = validate_loaded(&tmp, r->path, first_line, err)) ||
        (rc = spatial_order(&tmp.ev, err))) {
        mote_ev_free(&tmp.ev);
        return rc;
    }
    mote_ev_set_reference(&tmp.ev);
    hs_drop_system(hs); /* the rest of *hs (settings, a dump) goes on in tmp */
    *hs = tmp;
    hs->rng = rng;
    hs->rng_from_file = 1;
    hs->rng_draws = 0;
    return MOTE_OK;
}

/* ---- load: the original program's format (spec 9.2) --------------------------------------------- */

static int read_numbers(reader *r, double *v, int want, const char *what, mote_err *err)
{
    if (!next_line(r)) {
        r->line++;
        char msg[160];
        snprintf(msg, sizeof msg, "file ends early: expected %s", what);
        return rd_fail(r, err, msg, NULL);
    }
    char *tok[8];
    int n = split(r->buf, tok, 8);
    if (n != want) {
        char msg[160];
        snprintf(msg, sizeof msg, "expected %s (%d number%s), found %d", what, want,
                 want == 1 ? "" : "s", n);
        return rd_fail(r, err, msg, NULL);
    }
    for (int k = 0; k < n; k++)
        if (!parse_real(tok[k], &v[k])) {
            char msg[160];
            snprintf(msg, sizeof msg, "expected %s", what);
            return rd_fail(r, err, msg, tok[k]);
        }
    return MOTE_OK;
}

/* Push overlapping pairs apart symmetrically to sigma (1 + 1e-9), sweeps in index order. */
static int repair_overlaps(mote_hs *hs, const char *path, mote_err *err)
{
    mote_ev *ev = &hs->ev;
    size_t cap = ev->n;
    uint32_t(*pairs)[2] = malloc(cap * sizeof *pairs);
    double *moved = calloc(ev->n, sizeof *moved);
    if (!pairs || !moved) {
        free(pairs);
        free(moved);
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory while repairing overlaps", path);
    }
    const double tol = 1e-10;
    int sweeps = 0;
    size_t count;
    int rc = MOTE_OK;
    while ((count = mote_ev_overlaps(ev, tol, pairs, cap)) > 0 && sweeps < 1000) {
        size_t k = count < cap ? count : cap;
        for (size_t q = 0; q < k; q++) {
            uint32_t i = pairs[q][0], j = pairs[q][1];
            double d[3] = {0, 0, 0}, r2 = 0;
            for (int a = 0; a < ev->dim; a++) {
                d[a] = ev->p[i].r[a] - ev->p[j].r[a];
                if (ev->periodic[a]) {
                    if (d[a] > 0.5 * ev->len[a])
                        d[a] -= ev->len[a];
                    else if (d[a] < -0.5 * ev->len[a])
                        d[a] += ev->len[a];
                }
                r2 += d[a] * d[a];
            }
            double dist = sqrt(r2);
            if (dist == 0) {
                d[1] = 1;
                dist = 1;
                r2 = 0;
            }
            double sig = mote_ev_radius(ev, i) + mote_ev_radius(ev, j);
            double push = 0.5 * (sig * (1 + 1e-9) - sqrt(r2));
            if (push <= 0)
                continue;
            for (int a = 0; a < ev->dim; a++) {
                double s = push * d[a] / dist;
                ev->p[i].r[a] += s;
                ev->p[j].r[a] -= s;
            }
            uint32_t ij[2] = {i, j};
            for (int m = 0; m < 2; m++) {
                mote_particle *p = &ev->p[ij[m]];
                double R = mote_ev_radius(ev, ij[m]);
                if (p->r[0] < R)
                    p->r[0] = R;
                if (p->r[0] > ev->len[0] - R)
                    p->r[0] = ev->len[0] - R;
                moved[ij[m]] += push;
            }
        }
        sweeps++;
        if ((rc = mote_ev_rebuild(ev, err)))
            break;
    }
    if (!rc) {
        size_t nmoved = 0;
        double maxd = 0;
        for (uint32_t i = 0; i < ev->n; i++)
            if (moved[i] > 0) {
                nmoved++;
                if (moved[i] > maxd)
                    maxd = moved[i];
            }
        if (count > 0)
            rc = mote_fail(err, MOTE_EFORMAT,
                           "%s: %zu overlapping pairs remain after 1000 repair sweeps", path,
                           count);
        else if (nmoved && hs->log)
            fprintf(hs->log,
                    "load: repaired overlaps of the original format: moved %zu particles, largest "
                    "displacement %.3g R, in %d sweeps\n",
                    nmoved, maxd, sweeps);
    }
    free(pairs);
    free(moved);
    return rc;
}

static int load_original(mote_hs *hs, reader *r, mote_err *err)
{
    char *tok[4];
    uint64_t n64, nimg;
    if (split(r->buf, tok, 4) != 1 || !parse_u64(tok[0], &n64, 10) || n64 < 2 ||
        n64 > 0xFFFFFFF0ull)
        return rd_fail(r, err, "expected the number of particles N >= 2", r->buf);
    if (!next_line(r))
        return r->line++, rd_fail(r, err, "file ends early: expected the number of images", NULL);
    if (split(r->buf, tok, 4) != 1 || !parse_u64(tok[0], &nimg, 10))
        return rd_fail(r, err, "expected the number of images (an integer >= 0)", r->buf);
    double A, L;
    int rc;
    if ((rc = read_numbers(r, &A, 1, "the box width A", err)))
        return rc;
    if ((rc = read_numbers(r, &L, 1, "the box length L", err)))
        return rc;
    if (!(A > 4) || !(L >= 2))
        return rd_fail(r, err, "box sizes must satisfy A > 4 R and L >= 2 R", NULL);

    mote_ev ev;
    if ((rc = mote_ev_init(&ev, (uint32_t)n64, 3, 0, err)))
        return rc;
    long first_line = r->line + 1;
    for (uint64_t rec = 0; rec < n64 + nimg; rec++) {
        double idx[2], x[3], v[3];
        int is_img = rec >= n64;
        char what[96];
        snprintf(what, sizeof what, "the indices 'i i_copy' of %s %llu", is_img ? "image" : "particle",
                 (unsigned long long)(is_img ? rec - n64 : rec));
        if ((rc = read_numbers(r, idx, 2, what, err)) ||
            (rc = read_numbers(r, x, 3, "a position 'x y z'", err)) ||
            (rc = read_numbers(r, v, 3, "a velocity 'vx vy vz'", err))) {
            mote_ev_free(&ev);
            return rc;
        }
        if (is_img)
            continue;
        if (idx[0] != (double)rec) {
            r->line -= 2;
            mote_ev_free(&ev);
            char msg[96];
            snprintf(msg, sizeof msg, "particle records must be numbered 0 ... N-1: expected %llu",
                     (unsigned long long)rec);
            return rd_fail(r, err, msg, NULL);
        }
        mote_particle *p = &ev.p[rec];
        p->r[0] = x[0];
        p->r[1] = fmod(x[1], A);
        if (p->r[1] < 0)
            p->r[1] += A;
        p->r[2] = fmod(x[2], A);
        if (p->r[2] < 0)
            p->r[2] += A;
        for (int a = 0; a < 3; a++)
            p->v[a] = v[a];
        if (x[0] < 1 - 1e-10 || x[0] > L - 1 + 1e-10) {
            r->line -= 1;
            mote_ev_free(&ev);
            return rd_fail(r, err, "x is outside the walls [1, L-1]", NULL);
        }
        if (p->r[0] < 1)
            p->r[0] = 1;
        if (p->r[0] > L - 1)
            p->r[0] = L - 1;
    }
    while (next_line(r)) {
        char *et[1];
        if (split(r->buf, et, 1) != 0) {
            mote_ev_free(&ev);
            return rd_fail(r, err, "unexpected text after the last record", r->buf);
        }
    }
    ev.periodic[0] = 0;
    ev.periodic[1] = ev.periodic[2] = 1;
    ev.len[0] = L;
    ev.len[1] = ev.len[2] = A;

    mote_hs tmp = *hs;
    tmp.ev = ev;
    tmp.geometry = MOTE_HS_SLIT;
    tmp.has_system = 1;
    if ((rc = validate_particles(&tmp.ev, r->path, first_line, err)) ||
        (rc = mote_ev_rebuild(&tmp.ev, err)) || (rc = repair_overlaps(&tmp, r->path, err)) ||
        (rc = validate_loaded(&tmp, r->path, first_line, err)) ||
        (rc = spatial_order(&tmp.ev, err))) {
        mote_ev_free(&tmp.ev);
        return rc;
    }
    mote_ev_set_reference(&tmp.ev);
    if (hs->log)
        fprintf(hs->log,
                "load: imported the original program's format: N=%u, %llu image records skipped, "
                "kT_kin=%.6g (use 'temperature 1' to rescale)\n",
                tmp.ev.n, (unsigned long long)nimg, mote_ev_kt(&tmp.ev));
    hs_drop_system(hs); /* the rest of *hs (settings, a dump) goes on in tmp */
    *hs = tmp; /* the random stream is left unchanged */
    return MOTE_OK;
}

/* ---- entry points ------------------------------------------------------------------------------------ */

static int open_reader(reader *r, const char *path, mote_err *err)
{
    return mote_lines_open(r, path, err);
}

/* Close; a read error or a line too long (the cause of any error rc holds) replaces rc. */
static int close_reader(reader *r, int rc, mote_err *err)
{
    int crc = mote_lines_close(r, err);
    return crc ? crc : rc;
}

static int is_single_integer(char *line)
{
    char copy[64];
    if (strlen(line) >= sizeof copy)
        return 0;
    strcpy(copy, line);
    char *tok[2];
    uint64_t v;
    return split(copy, tok, 2) == 1 && parse_u64(tok[0], &v, 10);
}

int mote_hs_load(mote_hs *hs, const char *path, mote_err *err)
{
    reader r;
    int rc = open_reader(&r, path, err);
    if (rc)
        return rc;
    if (!next_line(&r))
        return close_reader(&r, mote_fail(err, MOTE_EFORMAT, "%s:1: the file is empty", path), err);
    if (strncmp(r.buf, "mote-state", 10) == 0 && (r.buf[10] == ' ' || r.buf[10] == '\t'))
        rc = load_mote(hs, &r, err);
    else if (is_single_integer(r.buf))
        rc = load_original(hs, &r, err);
    else
        rc = rd_fail(&r, err,
                     "not a state file: expected 'mote-state 1' or, for the original program's "
                     "format, the particle count",
                     r.buf);
    return close_reader(&r, rc, err);
}

int mote_hs_peek(const char *path, int *geometry, int *dim, uint64_t *n, mote_err *err)
{
    reader r;
    int rc = open_reader(&r, path, err);
    if (rc)
        return rc;
    char *tok[4];
    rc = MOTE_OK;
    if (!next_line(&r)) {
        rc = mote_fail(err, MOTE_EFORMAT, "%s:1: the file is empty", path);
    } else if (strncmp(r.buf, "mote-state", 10) == 0) {
        hs_head h;
        memset(&h, 0, sizeof h);
        rc = check_version(&r, err);
        if (!rc)
            rc = mote_sf_read(&r, HEAD_A, NF(HEAD_A), &h, 1, err);
        if (!rc) {
            const mote_sf_field box = box_field(h.dim);
            rc = mote_sf_read(&r, &box, 1, &h, 1, err);
        }
        if (!rc)
            rc = mote_sf_read(&r, HEAD_B, 1, &h, 1, err); /* (n) */
        *geometry = h.geometry == 1 ? MOTE_HS_PERIODIC : MOTE_HS_SLIT;
        *dim = h.dim ? h.dim : 3;
        *n = h.n;
    } else if (is_single_integer(r.buf)) {
        *geometry = MOTE_HS_SLIT;
        *dim = 3;
        split(r.buf, tok, 4);
        parse_u64(tok[0], n, 10);
    } else {
        rc = rd_fail(&r, err, "not a state file", r.buf);
    }
    return close_reader(&r, rc, err);
}
