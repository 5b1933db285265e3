/* galctl.c: Galactica's control file galacf26.dat (specs/nbody-galactica.md 7.2, 7.3): one
 * parameter per line, a free description in columns 1-59 and the value from column 60 (tabs
 * expanded to 8-column stops; the first token starting at or after column 60; a short line or
 * a blank there gives the default); `lenient` takes the last token of the line instead. Lines
 * 1-50 are fixed; from line 51 come the trios ipp, jpp, kpp of the selected bodies, told apart by
 * their descriptions, else in the prose layout (ipp(1) 51, jpp(1) 52, line 53 reserved, kpp(1)
 * 54, then ipp, jpp, kpp from 55) or, asked for, packed (51-53, 54-56, ...). The writer produces
 * the prose layout with the descriptions of Table 1 and the values from column 60. */
#include "mote/nbody.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "nb.h"

/* The 50 fixed lines: name, kind (r real, i integer, a file name) and the description. */
static const struct {
    const char *name;
    char kind;
    const char *text;
} LINES[NB_GALCTL_FIXED] = {
    {"A", 'r', "Length of area along axis X (A=1)"},
    {"B", 'r', "Height of area along axis Y (B <= 1)"},
    {"C", 'r', "Thickness of area along axis Z (C <= 1)"},
    {"X0", 'r', "Initial X coordinate of area"},
    {"Y0", 'r', "Initial Y coordinate of area"},
    {"Z0", 'r', "Initial Z coordinate of area"},
    {"Mu", 'i', "Number of divisions over axis X"},
    {"Ro0", 'r', "Relative initial density of the area"},
    {"RoS", 'r', "Relative initial density of point body"},
    {"Xs", 'r', "X - coordinate of a separate body"},
    {"Ys", 'r', "Y - coordinate of a separate body"},
    {"Zs", 'r', "Z - coordinate of a separate body"},
    {"Us", 'r', "Velocity of the separate body along axis X"},
    {"Vs", 'r', "Velocity of the separate body along axis Y"},
    {"Ws", 'r', "Velocity of the separate body along axis Z"},
    {"wu", 'r', "Angular velocity of rotation of area"},
    {"X01", 'r', "Relative X-coordinate of the axis of rotation"},
    {"Y01", 'r', "Relative Y-coordinate of the axis of rotation"},
    {"Roa", 'r', "Absolute average density of the area, kg/m3"},
    {"Rob", 'r', "Absolute density of bodies, kg/m3"},
    {"Kl10", 'i', "Depiction with respect to first body (below)"},
    {"dt", 'r', "Integration time step at Kl1=0"},
    {"Klmax", 'i', "Maximum dimension of TR array"},
    {"Ltk", 'i', "Number of integration steps in one cycle"},
    {"Ltk2", 'i', "Number of cycles"},
    {"Kl1", 'i', "Key: input data from file"},
    {"Kl4", 'i', "Key: start of counting time/Step correction"},
    {"Nbd", 'i', "Search of encounters of body No. at Kl3"},
    {"Kl7", 'i', "Key: writing data to file"},
    {"k2", 'i', "Number of interacting bodies"},
    {"Kl3", 'i', "Interval of data (picture) output (in steps)"},
    {"Kl11", 'i', "Beginning step-by-step of data (pctrs) output"},
    {"Kl12", 'i', "Key: writing trajectory parameters"},
    {"Kli", 'i', "Steps interval of trajectory parameters"},
    {"Nre", 'i', "Display mode"},
    {"Kl14", 'i', "Correction of the area size on the screen"},
    {"af", 'r', "Coefficient of area form on the screen"},
    {"Rd", 'r', "Coefficient of mass size of the screen"},
    {"amv", 'r', "Coefficient of velocity on the screen"},
    {"bt", 'r', "Crrctn factor of step dtk at bodies' approach"},
    {"Ke", 'r', "Flat depiction of layer to Z"},
    {"al", 'r', "Rotation of area relative to X-axis by angle"},
    {"bet", 'r', "Rotation of area relative to Y-axis by angle"},
    {"Xe0", 'r', "Begining of screen area along x"},
    {"Ye0", 'r', "Begining of screen area along y"},
    {"aix", 'r', "Image size in x"},
    {"biy", 'r', "Image size in y"},
    {"FIMA4", 'a', "Initial data file name"},
    {"Np", 'i', "Number of bodies in trajectory analysis"},
    {"Kl15", 'i', "Key: body velocity output"},
};

int nb_galctl_index(const char *name)
{
    for (int k = 0; k < NB_GALCTL_FIXED; k++)
        if (strcmp(LINES[k].name, name) == 0)
            return k;
    return -1;
}

/* The line with tabs expanded to 8-column stops, into out (at most cap - 1 characters). */
static void expand_tabs(const char *s, char *out, size_t cap)
{
    size_t k = 0;
    for (; *s && k + 1 < cap; s++) {
        if (*s == '\t') {
            do
                out[k++] = ' ';
            while (k % 8 && k + 1 < cap);
        } else if (*s != '\r') {
            out[k++] = *s;
        }
    }
    out[k] = 0;
}

/* The value token of a line (the first starting at or after column 60, or the last with
 * lenient) into tok; the description (columns 1-59, trimmed) into desc. 0: no value. */
static int value_of(const char *line, int lenient, char *tok, size_t tcap, char *desc, size_t dcap)
{
    const size_t n = strlen(line);
    size_t dn = n < 59 ? n : 59;
    while (dn > 0 && line[dn - 1] == ' ')
        dn--;
    snprintf(desc, dcap, "%.*s", (int)dn, line);
    size_t a = 0, b = 0;
    if (lenient) { /* the last token */
        b = n;
        while (b > 0 && line[b - 1] == ' ')
            b--;
        a = b;
        while (a > 0 && line[a - 1] != ' ')
            a--;
    } else { /* a token that starts at column 60 or later */
        size_t i = 59;
        if (n <= i)
            return 0;
        while (i > 0 && i < n && line[i] != ' ' && line[i - 1] != ' ')
            i++; /* a token running across column 60 started before it: skip it */
        while (i < n && line[i] == ' ')
            i++;
        a = i;
        b = a;
        while (b < n && line[b] != ' ')
            b++;
    }
    if (b <= a)
        return 0;
    snprintf(tok, tcap, "%.*s", (int)(b - a), line + a);
    return 1;
}

/* A real (Fortran's: D exponents) or an integer (written with a point when integral). */
static int parse_value(const char *tok, char kind, double *v)
{
    char b[96];
    snprintf(b, sizeof b, "%s", tok);
    for (char *p = b; *p; p++)
        if (*p == 'd' || *p == 'D')
            *p = 'E';
    char *end;
    errno = 0;
    const double x = strtod(b, &end);
    if (end == b || *end || errno == ERANGE || !isfinite(x))
        return -1;
    if (kind == 'i' && (x != floor(x) || fabs(x) > 9.2e18))
        return -1;
    *v = x;
    return 0;
}

/* What a trio line's description says it is: 0 ipp (a colour), 1 jpp (the other bodies' colour
 * or a free key), 2 kpp (a body number), -1 nothing known. */
static int trio_role(const char *desc, int first_trio, int seen_ipp)
{
    char low[128];
    size_t k = 0;
    for (; desc[k] && k + 1 < sizeof low; k++)
        low[k] = (char)tolower((unsigned char)desc[k]);
    low[k] = 0;
    if (strstr(low, "free key"))
        return 1;
    if (strstr(low, "number of the"))
        return 2;
    if (strstr(low, "colour") || strstr(low, "color"))
        return first_trio && seen_ipp ? 1 : 0; /* the first trio's second colour is jpp(1) */
    return -1;
}

int nb_galctl_read(const char *path, int lenient, int packed, nb_galctl *g, mote_err *err)
{
    memset(g, 0, sizeof *g);
    mote_lines in;
    int rc = mote_lines_open(&in, path, err);
    if (rc)
        return rc;
    char *raw, line[4096], tok[256], desc[128];
    /* the trio lines from 51 on: their values and descriptions, classified afterwards */
    size_t tcap = 0, tn = 0;
    double *tv = NULL;
    int *thave = NULL, *trole = NULL;
    long *tline = NULL;
    int described = 0, first = 1, seen_ipp = 0;
    while (!rc && (raw = mote_lines_next(&in)) != NULL) {
        const long ln = in.line;
        expand_tabs(raw, line, sizeof line);
        const int has = value_of(line, lenient, tok, sizeof tok, desc, sizeof desc);
        if (ln <= NB_GALCTL_FIXED) {
            const int k = (int)ln - 1;
            if (ln == 1) /* the date of the file variant, at the end of line 1's description */
                snprintf(g->date, sizeof g->date, "%s",
                         strrchr(desc, ' ') ? strrchr(desc, ' ') + 1 : "");
            if (!has)
                continue;
            if (LINES[k].kind == 'a') {
                snprintf(g->fima4, sizeof g->fima4, "%s", tok);
                g->fima4_long = strlen(tok) > 12;
            } else if (parse_value(tok, LINES[k].kind, &g->v[k])) {
                rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: %s (%s): expected %s from column 60, "
                               "found '%s'", path, ln, LINES[k].name, LINES[k].text,
                               LINES[k].kind == 'i' ? "a whole number" : "a number", tok);
            }
            g->have[k] = 1;
            continue;
        }
        if (tn == tcap) {
            tcap = tcap ? 2 * tcap : 16;
            double *a = realloc(tv, tcap * sizeof *a);
            int *b = realloc(thave, tcap * sizeof *b), *c = realloc(trole, tcap * sizeof *c);
            long *d = realloc(tline, tcap * sizeof *d);
            tv = a ? a : tv;
            thave = b ? b : thave;
            trole = c ? c : trole;
            tline = d ? d : tline;
            if (!a || !b || !c || !d) {
                rc = mote_fail(err, MOTE_ENOMEM, "%s: out of memory", path);
                break;
            }
        }
        tv[tn] = 0;
        thave[tn] = has;
        tline[tn] = ln;
        if (has && parse_value(tok, 'i', &tv[tn]))
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: a trio line: expected a whole number from "
                           "column 60, found '%s'", path, ln, tok);
        const int role = trio_role(desc, first, seen_ipp);
        trole[tn] = role;
        if (role >= 0)
            described = 1;
        if (role == 0)
            seen_ipp = 1;
        if (role == 2)
            first = 0;
        tn++;
    }
    const int crc = mote_lines_close(&in, err);
    rc = crc ? crc : rc;
    if (!rc && in.line < NB_GALCTL_FIXED)
        rc = mote_fail(err, MOTE_EFORMAT, "%s: %ld lines, but a control file has at least %d (its "
                       "fixed parameters)", path, in.line, NB_GALCTL_FIXED);
    /* the trios: by description (a colour or a free key opens a trio, a body number closes it),
     * else by the layout */
    int open = 0;
    for (size_t t = 0; !rc && t < tn; t++) {
        int role, trio;
        const long ln = tline[t];
        if (described && !packed) {
            role = trole[t];
            if (role < 0)
                continue; /* the reserved line, or a line that is none of the three */
            if (!open && role < 2) {
                if (g->ntrio == NB_GALCTL_TRIOS) {
                    rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: more than %d trios", path, ln,
                                   NB_GALCTL_TRIOS);
                    break;
                }
                g->ntrio++;
                open = 1;
            }
            if (g->ntrio == 0)
                continue; /* a body number before any colour */
            g->trio[g->ntrio - 1][role] = (long)tv[t];
            if (role == 2)
                open = 0;
            continue;
        }
        /* positions: prose (53 reserved; kpp(1) at 54, then 55.. in threes) or packed */
        if (packed) {
            trio = (int)((ln - 51) / 3);
            role = (int)((ln - 51) % 3);
        } else if (ln == 51 || ln == 52) {
            trio = 0;
            role = (int)(ln - 51);
        } else if (ln == 53) {
            continue;
        } else if (ln == 54) {
            trio = 0;
            role = 2;
        } else {
            trio = 1 + (int)((ln - 55) / 3);
            role = (int)((ln - 55) % 3);
        }
        if (trio >= NB_GALCTL_TRIOS) {
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: more than %d trios", path, ln,
                           NB_GALCTL_TRIOS);
            break;
        }
        if (trio + 1 > g->ntrio)
            g->ntrio = trio + 1;
        g->trio[trio][role] = (long)tv[t];
    }
    free(tv);
    free(thave);
    free(trole);
    free(tline);
    return rc;
}

double nb_galctl_get(const nb_galctl *g, const char *name)
{
    const int k = nb_galctl_index(name);
    return k >= 0 ? g->v[k] : NAN;
}

/* A real in the shortest form that reads back to the same double. */
static void short_real(double x, char *b, size_t cap)
{
    for (int p = 1; p <= 17; p++) {
        snprintf(b, cap, "%.*g", p, x);
        if (strtod(b, NULL) == x) {
            if (!strpbrk(b, ".eEn")) /* a point, so it reads as a real in Fortran too */
                snprintf(b + strlen(b), cap - strlen(b), ".");
            return;
        }
    }
}

int nb_galctl_write(const char *path, const nb_galctl *g, mote_err *err)
{
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc)
        return rc;
    FILE *f = af.f;
    char val[300], desc[128];
    for (int k = 0; k < NB_GALCTL_FIXED; k++) {
        if (k == 0) { /* line 1 carries the date of the file variant */
            const time_t now = time(NULL);
            struct tm tmv;
            gmtime_r(&now, &tmv);
            char date[16];
            if (g->date[0])
                snprintf(date, sizeof date, "%s", g->date);
            else
                strftime(date, sizeof date, "%d.%m.%Y", &tmv);
            snprintf(desc, sizeof desc, "%s %s", LINES[k].text, date);
        } else {
            snprintf(desc, sizeof desc, "%s", LINES[k].text);
        }
        if (LINES[k].kind == 'a')
            snprintf(val, sizeof val, "%s", g->fima4);
        else if (LINES[k].kind == 'i')
            snprintf(val, sizeof val, "%.0f", g->v[k]);
        else
            short_real(g->v[k], val, sizeof val);
        fprintf(f, "%-59.59s%s\n", desc, val);
    }
    for (int t = 0; t < g->ntrio; t++) {
        static const char *const what[3] = {"Velocity colour of body", "Free key of body",
                                            "Number of the selected body"};
        for (int r = 0; r < 3; r++) {
            if (t == 0 && r == 2) /* the reserved line 53 of the prose layout */
                fprintf(f, "%-59s%d\n", "Reserved line 53", 0);
            if (t == 0 && r == 1)
                snprintf(desc, sizeof desc, "Velocity colour of the other bodies");
            else
                snprintf(desc, sizeof desc, "%s %d", what[r], t + 1);
            fprintf(f, "%-59.59s%ld\n", desc, g->trio[t][r]);
        }
    }
    return mote_afile_commit(&af, err);
}
