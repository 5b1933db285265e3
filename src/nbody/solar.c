/* solar.c: Solar-System data files and the builder (spec 9.3). A data file is text: a format line
 * '# mote solar-system 1', header lines '# source:', '# epoch:', '# frame:', '# centre:', and
 * '# units:' which is 'km s GM' (the second column is GM in km^3/s^2, lengths in km,
 * velocities in km/s), 'AU day GM' (GM in AU^3/day^2, AU of DE405) or 'AU day Msun G=<value>' (the second column is the mass in solar masses,
 * written as a number or as 1/<number>, with G in AU^3 Msun^-1 day^-2); then one row per body:
 * name, GM or mass, x, y, z, vx, vy, vz, mean radius in km. A name NAME@CENTRE gives the state
 * relative to the body CENTRE of an earlier line (the geocentric Moon). A row 'EMB' (the Earth-Moon
 * barycentre with the GM of both) and a later 'Moon@Earth' with GM '-' are split with the mass
 * ratio of a '# emrat: R' line into the Earth and the Moon (spec 9.3). Values are converted to SI
 * on reading; the builder makes the dimensionless system with the sidereal century as time unit. */
#include "mote/nbody.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define SOLAR_FORMAT "# mote solar-system 1"

static int parse_real(const char *tok, double *out)
{
    char *end;
    errno = 0;
    double v;
    if (strncmp(tok, "1/", 2) == 0) {
        double d = strtod(tok + 2, &end);
        v = 1.0 / d;
    } else {
        v = strtod(tok, &end);
    }
    if (end == tok || *end || errno == ERANGE || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

void mote_nb_solar_free(mote_nb_solar *s)
{
    free(s->b);
    s->b = NULL;
    s->n = 0;
}

/* The reader of a solar-system file: the file's units (length L in m, time T in s, G for the
 * mass form) and the Earth/Moon mass ratio of an EMB row's split. */
typedef struct {
    const char *path;
    long ln;
    int have_units, mass_form, cap;
    double L, T, G, emrat;
} solar_rd;

/* A comment line: '# units: ...' and '# emrat: R' are read, the others are notes. */
static int solar_comment(solar_rd *r, const char *line, mote_err *err)
{
    if (strncmp(line, "# units:", 8) == 0) {
        char a[32], b[32], c[32], d[64], extra;
        int k = sscanf(line + 8, "%31s %31s %31s %63s %c", a, b, c, d, &extra);
        if (k == 3 && !strcmp(a, "km") && !strcmp(b, "s") && !strcmp(c, "GM")) {
            r->L = 1e3;
            r->T = 1;
        } else if (k == 3 && !strcmp(a, "AU") && !strcmp(b, "day") && !strcmp(c, "GM")) {
            r->L = MOTE_NB_AU;
            r->T = 86400;
        } else if (k == 4 && !strcmp(a, "AU") && !strcmp(b, "day") && !strcmp(c, "Msun") &&
                   !strncmp(d, "G=", 2) && !parse_real(d + 2, &r->G) && r->G > 0) {
            r->L = MOTE_NB_AU;
            r->T = 86400;
            r->mass_form = 1;
        } else {
            return mote_fail(err, MOTE_EFORMAT, "%s:%ld: expected '# units: km s GM', '# units: "
                             "AU day GM' or '# units: AU day Msun G=<value>'", r->path, r->ln);
        }
        r->have_units = 1;
    } else if (strncmp(line, "# emrat:", 8) == 0) {
        char extra;
        if (sscanf(line + 8, "%lf %c", &r->emrat, &extra) != 1 || !(r->emrat > 0) ||
            !isfinite(r->emrat))
            return mote_fail(err, MOTE_EFORMAT, "%s:%ld: expected '# emrat: R' with the "
                             "Earth/Moon mass ratio R > 0", r->path, r->ln);
    }
    return MOTE_OK;
}

/* A body's name tok into b: NAME, or NAME@CENTRE (the state relative to an earlier body: its
 * index in *centre), or Moon@Earth after an EMB row (the barycentre split, spec 9.3: the EMB
 * row's index in *split). */
static int solar_name(solar_rd *r, const mote_nb_solar *s, mote_nb_sbody *b, const char *tok,
                      int *centre, int *split, mote_err *err)
{
    *centre = *split = -1;
    if (strlen(tok) >= sizeof b->name)
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: body name longer than %d characters",
                         r->path, r->ln, (int)sizeof b->name - 1);
    strcpy(b->name, tok);
    char *at = strchr(b->name, '@');
    if (at) {
        *at++ = '\0';
        for (int j = 0; j < s->n; j++)
            if (strcmp(s->b[j].name, at) == 0)
                *centre = j;
        for (int j = 0; j < s->n && *centre < 0 && !strcmp(b->name, "Moon") &&
                        !strcmp(at, "Earth");
             j++)
            if (strcmp(s->b[j].name, "EMB") == 0)
                *split = j;
        if (*split >= 0 && !(r->emrat > 0))
            return mote_fail(err, MOTE_EFORMAT, "%s:%ld: Moon@Earth after an EMB row needs the "
                             "Earth/Moon mass ratio ('# emrat: R') before it", r->path, r->ln);
        if (!b->name[0] || (*centre < 0 && *split < 0))
            return mote_fail(err, MOTE_EFORMAT, "%s:%ld: %s@%s: expected NAME@CENTRE with the "
                             "centre on an earlier line", r->path, r->ln, b->name, at);
    }
    if (!mote_nb_name_ok(b->name))
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: '%s' is not a valid body name (a letter "
                         "first, then letters, digits and _ . + -; at most %d characters)",
                         r->path, r->ln, b->name, MOTE_NB_NAME - 1);
    return MOTE_OK;
}

/* The body b from its numbers v (GM or mass, x y z, vx vy vz, radius in km) in SI units, moved
 * by its centre, or splitting the EMB row into Earth and Moon. */
static int solar_place(solar_rd *r, mote_nb_solar *s, mote_nb_sbody *b, const double v[8],
                       int centre, int split, mote_err *err)
{
    const double L = r->L, T = r->T;
    b->gm = (r->mass_form ? r->G * v[0] : v[0]) * L * L * L / (T * T);
    for (int a = 0; a < 3; a++) {
        b->x[a] = v[1 + a] * L;
        b->v[a] = v[4 + a] * L / T;
    }
    b->ra = v[7] * 1e3;
    if (centre >= 0)
        for (int a = 0; a < 3; a++) {
            b->x[a] += s->b[centre].x[a];
            b->v[a] += s->b[centre].v[a];
        }
    if (split < 0)
        return MOTE_OK;
    /* EMB and the geocentric Moon r: Earth = EMB - r/(1+R), Moon = Earth + r */
    mote_nb_sbody *e = &s->b[split];
    const double f = 1 / (1 + r->emrat);
    for (int a = 0; a < 3; a++) {
        e->x[a] -= f * b->x[a];
        e->v[a] -= f * b->v[a];
        b->x[a] += e->x[a];
        b->v[a] += e->v[a];
    }
    e->gm -= b->gm;
    strcpy(e->name, "Earth");
    for (int j = 0; j < s->n; j++)
        if (j != split && strcmp(s->b[j].name, "Earth") == 0)
            return mote_fail(err, MOTE_EFORMAT, "%s:%ld: an EMB row and an Earth row", r->path,
                             r->ln);
    return MOTE_OK;
}

/* A body row: its name, its eight numbers, the body placed. */
static int solar_row(solar_rd *r, mote_nb_solar *s, char *line, mote_err *err)
{
    const char *path = r->path;
    const long ln = r->ln;
    char *save = NULL, *tok = strtok_r(line, " \t", &save);
    if (!tok)
        return MOTE_OK;
    if (!r->have_units)
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: a body before the '# units:' line", path,
                         ln);
    if (s->n == r->cap) {
        r->cap = r->cap ? 2 * r->cap : 16;
        mote_nb_sbody *p = realloc(s->b, (size_t)r->cap * sizeof *p);
        if (!p)
            return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", path);
        s->b = p;
    }
    mote_nb_sbody *b = &s->b[s->n];
    memset(b, 0, sizeof *b);
    b->line = ln;
    int centre, split;
    int rc = solar_name(r, s, b, tok, &centre, &split, err);
    if (rc)
        return rc;
    double v[8];
    int k = 0;
    for (; k < 8 && (tok = strtok_r(NULL, " \t", &save)); k++)
        if (k == 0 && split >= 0 && strcmp(tok, "-") == 0) /* the GM from the split */
            v[0] = s->b[split].gm / (1 + r->emrat) / (r->L * r->L * r->L / (r->T * r->T));
        else if (parse_real(tok, &v[k]))
            return mote_fail(err, MOTE_EFORMAT, "%s:%ld: %s: column %d: expected a number, "
                             "found '%.40s'", path, ln, b->name, k + 2, tok);
    if (k < 8 || strtok_r(NULL, " \t", &save))
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: %s: expected 8 numbers (%s x y z vx vy vz "
                         "radius_km)", path, ln, b->name, r->mass_form ? "mass" : "GM");
    if (!(v[0] > 0) || v[7] < 0)
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: %s: need %s > 0 and radius >= 0", path, ln,
                         b->name, r->mass_form ? "mass" : "GM");
    for (int j = 0; j < s->n; j++)
        if (strcmp(s->b[j].name, b->name) == 0)
            return mote_fail(err, MOTE_EFORMAT, "%s:%ld: %s is also on line %ld", path, ln,
                             b->name, s->b[j].line);
    if ((rc = solar_place(r, s, b, v, centre, split, err)))
        return rc;
    s->n++;
    return MOTE_OK;
}

int mote_nb_solar_read(const char *path, mote_nb_solar *s, mote_err *err)
{
    memset(s, 0, sizeof *s);
    mote_lines in;
    int rc = mote_lines_open(&in, path, err);
    if (rc)
        return rc;
    solar_rd r = {.path = path};
    char *line;
    while (!rc && (line = mote_lines_next(&in)) != NULL) {
        r.ln = in.line;
        if (r.ln == 1) {
            if (strcmp(line, SOLAR_FORMAT) != 0)
                rc = mote_fail(err, MOTE_EFORMAT, "%s:1: expected '%s', found '%.60s'", path,
                               SOLAR_FORMAT, line);
        } else if (line[0] == '#') {
            rc = solar_comment(&r, line, err);
        } else {
            rc = solar_row(&r, s, line, err);
        }
    }
    const long lines = in.line;
    int crc = mote_lines_close(&in, err);
    rc = crc ? crc : rc;
    if (!rc && lines == 0)
        rc = mote_fail(err, MOTE_EFORMAT, "%s: empty file (expected '%s')", path, SOLAR_FORMAT);
    if (!rc && s->n == 0)
        rc = mote_fail(err, MOTE_EFORMAT, "%s: no bodies", path);
    if (rc)
        mote_nb_solar_free(s);
    return rc;
}

static int inner(const char *name)
{
    static const char *const list[] = {"Mercury", "Venus", "Earth", "Moon", "Mars"};
    for (size_t k = 0; k < sizeof list / sizeof list[0]; k++)
        if (strcasecmp(name, list[k]) == 0)
            return 1;
    return 0;
}

int mote_nb_solar_build(mote_nb *nb, const mote_nb_solar *s, const char *bodies, int merge_inner,
                        mote_err *err)
{
    if (nb->kind != MOTE_NB_GRAVITY)
        return mote_fail(err, MOTE_EINVAL, "solar_system: this is a Coulomb run");
    uint8_t *take = calloc((size_t)s->n, 1);
    if (!take)
        return mote_fail(err, MOTE_ENOMEM, "solar_system: out of memory");
    int rc = MOTE_OK, sun = -1;
    for (int i = 0; i < s->n; i++)
        if (strcasecmp(s->b[i].name, "Sun") == 0)
            sun = i;
    if (bodies) {
        const char *p = bodies;
        while (!rc && *p) {
            size_t len = strcspn(p, ",");
            int found = 0;
            for (int i = 0; i < s->n; i++)
                if (strlen(s->b[i].name) == len && strncasecmp(s->b[i].name, p, len) == 0) {
                    take[i] = 1;
                    found = 1;
                }
            if (!found)
                rc = mote_fail(err, MOTE_EINVAL, "solar_system: no body '%.*s' in the data file",
                               (int)len, p);
            p += len + (p[len] == ',');
        }
    } else {
        memset(take, 1, (size_t)s->n);
    }
    if (!rc && merge_inner && (sun < 0 || !take[sun]))
        rc = mote_fail(err, MOTE_EINVAL, "solar_system: merge_inner needs the Sun");
    double gm_sun = sun >= 0 ? s->b[sun].gm : 0, total = 0;
    int count = 0;
    for (int i = 0; !rc && i < s->n; i++) {
        if (merge_inner && inner(s->b[i].name)) {
            gm_sun += s->b[i].gm;
            take[i] = 0;
        }
    }
    for (int i = 0; !rc && i < s->n; i++)
        if (take[i]) {
            total += i == sun ? gm_sun : s->b[i].gm;
            count++;
        }
    if (!rc && count < 2)
        rc = mote_fail(err, MOTE_EINVAL, "solar_system: need at least 2 bodies, have %d", count);
    if (!rc) {
        const double kt = 1.0 / (100 * MOTE_NB_SIDEREAL_YEAR_DAYS * 86400);
        mote_nb_units_from_time(&nb->u, MOTE_NB_GRAVITY, total / nb->G, kt, nb->G, nb->e2, 1);
        const mote_nb_units *u = &nb->u;
        for (int i = 0; !rc && i < s->n; i++) {
            if (!take[i])
                continue;
            const mote_nb_sbody *b = &s->b[i];
            mote_real x[3], v[3];
            for (int a = 0; a < 3; a++) {
                x[a] = (mote_real)b->x[a] / (mote_real)u->Am;
                v[a] = (mote_real)b->v[a] * (mote_real)u->kv;
            }
            rc = mote_nb_add(nb, (mote_real)(i == sun ? gm_sun : b->gm) / (mote_real)total, 0, x, v,
                             (mote_real)b->ra / (mote_real)u->Am, err);
            if (!rc)
                rc = mote_nb_set_name(nb, nb->n - 1, b->name, err);
        }
        if (!rc)
            mote_nb_barycentric(nb, NULL, NULL);
    }
    free(take);
    return rc;
}
