/* plot.c: the N-body model's pictures of its data files (the common `plot` command): a
 * trajectory file as orbits projected on the invariable plane (perpendicular to the total
 * angular momentum at the start, so a tilted ring shows its true ellipses), with equal scales on
 * both axes and one colour per body; a monitor file as the relative drifts of energy and of the
 * aggregated z moment against time. */
#include "mote/datafile.h"
#include "mote/nbody.h"
#include "mote/render.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "nb.h"

static void unit(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int a = 0; a < 3; a++)
        v[a] /= n;
}

/* Two unit vectors spanning the plane perpendicular to n: e1 the x axis projected on the plane
 * (the y axis when n is along x), e2 = n x e1. */
static void plane_basis(const double n[3], double e1[3], double e2[3])
{
    double ax[3] = {1, 0, 0};
    if (fabs(n[0]) > 0.9) {
        ax[0] = 0;
        ax[1] = 1;
    }
    double d = ax[0] * n[0] + ax[1] * n[1] + ax[2] * n[2];
    for (int a = 0; a < 3; a++)
        e1[a] = ax[a] - d * n[a];
    unit(e1);
    e2[0] = n[1] * e1[2] - n[2] * e1[1];
    e2[1] = n[2] * e1[0] - n[0] * e1[2];
    e2[2] = n[0] * e1[1] - n[1] * e1[0];
}

/* One body of a trajectory file: its x column (y and z follow) and its legend label. */
typedef struct {
    int col;
    char label[40];
} traj_body;

/* The bodies of a trajectory file, from the column names x_NAME / xK (y and z after them; vx vy
 * vz may follow); returns the count, or -1 when the columns do not have that shape. */
static int traj_bodies(const mote_table *t, traj_body *b)
{
    int n = 0;
    for (int c = 3; c < t->ncolnames; c++) {
        const char *x = t->colname[c];
        if (x[0] != 'x')
            continue;
        char y[40], z[40];
        snprintf(y, sizeof y, "y%s", x + 1);
        snprintf(z, sizeof z, "z%s", x + 1);
        if (c + 2 >= t->ncolnames || strcmp(t->colname[c + 1], y) != 0 ||
            strcmp(t->colname[c + 2], z) != 0)
            return -1;
        b[n].col = c;
        if (x[1] == '_')
            snprintf(b[n].label, sizeof b[n].label, "%s", x + 2);
        else
            snprintf(b[n].label, sizeof b[n].label, "body %s", x + 1);
        n++;
    }
    return n;
}

/* The body of a file a token names (a name, or the body's number in the run); -1: none. */
static int traj_find(const mote_table *t, const traj_body *b, int n, const char *tok)
{
    char key[40];
    snprintf(key, sizeof key, "body_%s", tok);
    for (int k = 0; k < n; k++) {
        const char *x = t->colname[b[k].col];
        if (x[1] == '_' ? strcmp(x + 2, tok) == 0 ||
                              (isdigit((unsigned char)tok[0]) &&
                               (snprintf(key, sizeof key, "body_%s", x + 2),
                                mote_table_has(t, key) && mote_table_key(t, key) == atof(tok)))
                        : strcmp(x + 1, tok) == 0)
            return k;
    }
    return -1;
}


/* The bodies drawn (bodies=LIST, or all but the one the view is centred on) into pick[0 ..
 * *nbod) and relative_to=BODY's index in *rel (-1: none): names or numbers of bodies the file
 * holds. */
static int orbit_selection(const mote_table *t, const traj_body *all, int nall, const char *in,
                           const mote_call *c, int *pick, int *nbod, int *rel, mote_err *err)
{
    const mote_arg *sel = c ? mote_call_opt(c, "bodies") : NULL;
    const mote_arg *ra = c ? mote_call_opt(c, "relative_to") : NULL;
    *nbod = 0;
    *rel = -1;
    if (ra && (*rel = traj_find(t, all, nall, ra->text)) < 0)
        return mote_call_fail(err, c, mote_call_opt_index(c, "relative_to"), MOTE_EINVAL,
                              "plot: relative_to: %s holds no body '%s'", in, ra->text);
    if (!sel) {
        for (int k = 0; k < nall; k++)
            if (k != *rel) /* the body the view is centred on stays at the origin */
                pick[(*nbod)++] = k;
        if (!*nbod)
            pick[(*nbod)++] = *rel;
        return MOTE_OK;
    }
    for (const char *p = sel->text;;) {
        char tok[64];
        size_t len = strcspn(p, ",");
        snprintf(tok, sizeof tok, "%.*s", (int)(len < 63 ? len : 63), p);
        int k = traj_find(t, all, nall, tok);
        if (k < 0)
            return mote_call_fail(err, c, mote_call_opt_index(c, "bodies"), MOTE_EINVAL,
                                  "plot: bodies: %s holds no body '%s'", in, tok);
        pick[(*nbod)++] = k;
        if (!p[len] || *nbod == nall)
            return MOTE_OK;
        p += len + 1;
    }
}

/* The plane's two unit vectors and the axes' names: xy, xz, yz, or the invariable plane (the
 * header's total angular momentum at the start; xy when there is none). */
static void orbit_plane(const mote_table *t, const char *plane, double e1[3], double e2[3],
                        const char **lx, const char **ly)
{
    static const double x[3] = {1, 0, 0}, y[3] = {0, 1, 0};
    memcpy(e1, x, sizeof x);
    memcpy(e2, y, sizeof y);
    *lx = "x";
    *ly = "y";
    if (strcmp(plane, "xz") == 0) {
        e2[1] = 0;
        e2[2] = 1;
        *ly = "z";
    } else if (strcmp(plane, "yz") == 0) {
        e1[0] = 0;
        e1[1] = 1;
        e2[1] = 0;
        e2[2] = 1;
        *lx = "y";
        *ly = "z";
    } else if (strcmp(plane, "invariable") == 0) {
        double n[3] = {mote_table_key(t, "Lx0"), mote_table_key(t, "Ly0"),
                       mote_table_key(t, "Lz0")};
        double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(nn > 0) || !isfinite(nn)) { /* no angular momentum: the xy plane */
            n[0] = n[1] = 0;
            n[2] = 1;
        } else {
            unit(n);
        }
        plane_basis(n, e1, e2);
        *lx = "x'";
        *ly = "y'";
    }
}

/* The title: the bodies, the time span (in years when the file carries the time scale), the
 * plane, the centre. */
static void orbit_title(char *title, size_t size, const mote_table *t, int nbod,
                        const char *plane, const char *centre)
{
    double t0 = t->rows ? mote_table_at(t, 0, 0) : 0;
    double t1 = t->rows ? mote_table_at(t, t->rows - 1, 0) : 0;
    double kt = mote_table_has(t, "kt") ? mote_table_key(t, "kt") : 0;
    char span[96];
    if (kt > 0 && isfinite(kt))
        snprintf(span, sizeof span, "t = %.6g to %.6g years", t0 / (kt * 31557600.0),
                 t1 / (kt * 31557600.0));
    else
        snprintf(span, sizeof span, "T = %.6g to %.6g", t0, t1);
    snprintf(title, size, "orbits of %d bod%s, %s (%s plane)%s%s", nbod, nbod == 1 ? "y" : "ies",
             span, plane, centre ? ", relative to " : "", centre ? centre : "");
}

static int plot_orbits(const mote_table *t, const char *in, const char *png, const mote_call *c,
                       mote_err *err)
{
    traj_body *all = malloc((size_t)(t->ncolnames + 1) * sizeof *all);
    int *pick = malloc((size_t)(t->ncolnames + 1) * sizeof *pick);
    double *px = NULL, *py = NULL;
    mote_series *s = NULL;
    int rc = MOTE_OK, nall = all ? traj_bodies(t, all) : 0, nbod = 0, rel = -1;
    if (!all || !pick) {
        rc = mote_fail(err, MOTE_ENOMEM, "plot: out of memory");
        goto done;
    }
    if (t->ncolnames < 6 || nall <= 0 || strcmp(t->colname[0], "T") != 0) {
        rc = mote_fail(err, MOTE_EFORMAT, "plot: %s: expected columns T E_kin E_tot, then x y z "
                                          "per body", in);
        goto done;
    }
    for (size_t r = 0; r < t->rows; r++)
        if (t->ncol[r] != t->ncolnames) {
            rc = mote_fail(err, MOTE_EFORMAT, "plot: %s:%ld: expected %d numbers, found %d", in,
                           t->line[r], t->ncolnames, t->ncol[r]);
            goto done;
        }
    if ((rc = orbit_selection(t, all, nall, in, c, pick, &nbod, &rel, err)))
        goto done;
    const char *plane = c && mote_call_opt(c, "plane") ? mote_call_opt(c, "plane")->text
                                                        : "invariable";
    double e1[3], e2[3];
    const char *lx, *ly;
    orbit_plane(t, plane, e1, e2, &lx, &ly);
    /* lengths in AU (or m) when the file carries the length scale */
    double Am = mote_table_has(t, "Am") ? mote_table_key(t, "Am") : 0, scale = 1;
    const char *unit_name = "dimensionless length";
    size_t rows = t->rows ? t->rows : 1;
    px = malloc((size_t)nbod * rows * sizeof *px);
    py = malloc((size_t)nbod * rows * sizeof *py);
    s = calloc((size_t)nbod, sizeof *s);
    if (!px || !py || !s) {
        rc = mote_fail(err, MOTE_ENOMEM, "plot: out of memory");
        goto done;
    }
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int j = 0; j < nbod; j++) {
        int col = all[pick[j]].col;
        for (size_t r = 0; r < t->rows; r++) {
            double x[3];
            for (int a = 0; a < 3; a++)
                x[a] = mote_table_at(t, r, col + a) -
                       (rel >= 0 ? mote_table_at(t, r, all[rel].col + a) : 0);
            double u = x[0] * e1[0] + x[1] * e1[1] + x[2] * e1[2];
            double v = x[0] * e2[0] + x[1] * e2[1] + x[2] * e2[2];
            px[(size_t)j * rows + r] = u;
            py[(size_t)j * rows + r] = v;
            if (isfinite(u) && isfinite(v)) {
                lo[0] = fmin(lo[0], u);
                hi[0] = fmax(hi[0], u);
                lo[1] = fmin(lo[1], v);
                hi[1] = fmax(hi[1], v);
            }
        }
        s[j].x = px + (size_t)j * rows;
        s[j].y = py + (size_t)j * rows;
        s[j].n = t->rows;
        s[j].style = j == 0 && rel < 0 ? 2 : 0; /* the first body (a ring's centre) as points */
        /* up to 8 bodies each has its own colour and legend entry; beyond, colours repeat */
        if (nbod <= 8)
            s[j].label = all[pick[j]].label;
        else
            s[j].label = j == 0 ? all[pick[0]].label : j == 1 ? "the others (colours repeat)"
                                                               : NULL;
    }
    /* a square frame around everything, so one unit is as long on both axes */
    double cx = 0.5 * (lo[0] + hi[0]), cy = 0.5 * (lo[1] + hi[1]);
    double half = 0.55 * fmax(hi[0] - lo[0], hi[1] - lo[1]);
    if (!(half > 0) || !isfinite(half))
        half = 1;
    if (Am > 0 && isfinite(Am)) {
        const double au = 149597870700.0; /* m (IAU 2012 Resolution B2) */
        int in_au = half * Am >= 1e-3 * au;
        scale = in_au ? Am / au : Am;
        unit_name = in_au ? "AU" : "m";
        for (size_t k = 0; k < (size_t)nbod * rows; k++) {
            px[k] *= scale;
            py[k] *= scale;
        }
        cx *= scale;
        cy *= scale;
        half *= scale;
    }
    char title[400], xl[64], yl[64];
    orbit_title(title, sizeof title, t, nbod, plane, rel >= 0 ? all[rel].label : NULL);
    snprintf(xl, sizeof xl, "%s (%s)", lx, unit_name);
    snprintf(yl, sizeof yl, "%s (%s)", ly, unit_name);
    mote_plot_opts o;
    memset(&o, 0, sizeof o);
    o.title = title;
    o.xlabel = xl;
    o.ylabel = yl;
    o.width = c && mote_call_opt(c, "size") ? (int)mote_call_opt(c, "size")->i : 1024;
    o.equal_axes = 1;
    o.xmin = cx - half;
    o.xmax = cx + half;
    o.ymin = cy - half;
    o.ymax = cy + half;
    rc = mote_plot_png(png, &o, s, (size_t)nbod, err);
done:
    free(all);
    free(pick);
    free(px);
    free(py);
    free(s);
    return rc;
}

const char *nb_plot_time_unit(const mote_table *t, double t0, double t1, double *scale)
{
    double kt = mote_table_has(t, "kt") ? mote_table_key(t, "kt") : 0;
    *scale = 1;
    if (!(kt > 0 && isfinite(kt)))
        return "dimensionless";
    /* seconds per unit (Julian years, as unit= takes them) */
    static const struct {
        const char *name;
        double s;
    } U[3] = {{"year", 31557600.0}, {"day", 86400.0}, {"s", 1.0}};
    const double span = fabs(t1 - t0) / kt;
    int k = 0;
    while (k < 2 && span < 2 * U[k].s)
        k++;
    *scale = 1 / (kt * U[k].s);
    return U[k].name;
}

static int plot_monitor(const mote_table *t, const char *in, const char *png, mote_err *err)
{
    int cT = mote_table_col(t, "T"), cE = mote_table_col(t, "dE"), cM = mote_table_col(t, "dMz");
    if (cT < 0 || cE < 0 || cM < 0)
        return mote_fail(err, MOTE_EFORMAT, "plot: %s has no columns T, dE and dMz", in);
    size_t rows = t->rows ? t->rows : 1;
    double *T = malloc(rows * sizeof *T), *E = malloc(rows * sizeof *E),
           *M = malloc(rows * sizeof *M);
    if (!T || !E || !M) {
        free(T);
        free(E);
        free(M);
        return mote_fail(err, MOTE_ENOMEM, "plot: out of memory");
    }
    double ts;
    const char *unit = nb_plot_time_unit(t, t->rows ? mote_table_at(t, 0, cT) : 0,
                                         t->rows ? mote_table_at(t, t->rows - 1, cT) : 0, &ts);
    for (size_t r = 0; r < t->rows; r++) {
        T[r] = mote_table_at(t, r, cT) * ts;
        E[r] = mote_table_at(t, r, cE);
        M[r] = mote_table_at(t, r, cM);
    }
    mote_series s[2] = {{T, E, t->rows, "dE = (E - E0)/|E0|", 2},
                        {T, M, t->rows, "dMz (aggregated z moment)", 2}};
    mote_plot_opts o;
    memset(&o, 0, sizeof o);
    o.title = "conserved quantities: relative drift";
    char xl[64];
    if (ts == 1)
        snprintf(xl, sizeof xl, "T (dimensionless time)");
    else
        snprintf(xl, sizeof xl, "t (%s)",
                 !strcmp(unit, "year") ? "years" : !strcmp(unit, "day") ? "days" : "s");
    o.xlabel = xl;
    o.ylabel = "relative change";
    o.has_yref = 1;
    o.yref = 0;
    int rc = mote_plot_png(png, &o, s, 2, err);
    free(T);
    free(E);
    free(M);
    return rc;
}

int nb_plot_file(const char *data_path, const char *png_path, const mote_call *c, mote_err *err)
{
    mote_table t;
    int rc = mote_table_read(&t, data_path, err);
    if (rc)
        return rc;
    if (strcmp(t.format, "nbody-trajectory") == 0)
        rc = plot_orbits(&t, data_path, png_path, c, err);
    else if (strcmp(t.format, "nbody-monitor") == 0 && c && c->nopts)
        rc = mote_call_fail(err, c, c->nargs, MOTE_EINVAL, "plot: %s= is for trajectory files "
                            "(%s is a monitor file)", c->opts[0].key, data_path);
    else if (strcmp(t.format, "nbody-monitor") == 0)
        rc = plot_monitor(&t, data_path, png_path, err);
    else
        rc = mote_fail(err, MOTE_EFORMAT,
                       "plot: '%s' is not an N-body data file (its first line should be '# mote "
                       "nbody-trajectory 1' or '# mote nbody-monitor 1')",
                       data_path);
    mote_table_free(&t);
    return rc;
}
