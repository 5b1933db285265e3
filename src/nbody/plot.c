/* plot.c: the N-body model's pictures of its data files (the common `plot` command): a
 * trajectory file as orbits projected on the invariable plane (perpendicular to the total
 * angular momentum at the start, so a tilted ring shows its true ellipses), with equal scales on
 * both axes and one colour per body; a monitor file as the relative drifts of energy and of the
 * aggregated z moment against time. */
#include "mote/datafile.h"
#include "mote/nbody.h"
#include "mote/render.h"

#include <math.h>
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

static int plot_orbits(const mote_table *t, const char *in, const char *png, mote_err *err)
{
    int nbod = (t->ncolnames - 3) / 3;
    if (t->ncolnames < 6 || (t->ncolnames - 3) % 3 != 0)
        return mote_fail(err, MOTE_EFORMAT, "plot: %s: expected columns T E_kin E_tot and x y z "
                                            "per body", in);
    for (size_t r = 0; r < t->rows; r++)
        if (t->ncol[r] != t->ncolnames)
            return mote_fail(err, MOTE_EFORMAT, "plot: %s:%ld: expected %d numbers, found %d", in,
                             t->line[r], t->ncolnames, t->ncol[r]);
    double n[3] = {mote_table_key(t, "Lx0"), mote_table_key(t, "Ly0"), mote_table_key(t, "Lz0")};
    double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(nn > 0) || !isfinite(nn)) { /* no angular momentum: the xy plane */
        n[0] = n[1] = 0;
        n[2] = 1;
    } else {
        unit(n);
    }
    double e1[3], e2[3];
    plane_basis(n, e1, e2);
    size_t rows = t->rows ? t->rows : 1;
    double *px = malloc((size_t)nbod * rows * sizeof *px);
    double *py = malloc((size_t)nbod * rows * sizeof *py);
    mote_series *s = calloc((size_t)nbod, sizeof *s);
    if (!px || !py || !s) {
        free(px);
        free(py);
        free(s);
        return mote_fail(err, MOTE_ENOMEM, "plot: out of memory");
    }
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    char labels[8][24];
    for (int b = 0; b < nbod; b++) {
        for (size_t r = 0; r < t->rows; r++) {
            double x[3] = {mote_table_at(t, r, 3 + 3 * b), mote_table_at(t, r, 4 + 3 * b),
                           mote_table_at(t, r, 5 + 3 * b)};
            double u = x[0] * e1[0] + x[1] * e1[1] + x[2] * e1[2];
            double v = x[0] * e2[0] + x[1] * e2[1] + x[2] * e2[2];
            px[(size_t)b * rows + r] = u;
            py[(size_t)b * rows + r] = v;
            if (isfinite(u) && isfinite(v)) {
                lo[0] = fmin(lo[0], u);
                hi[0] = fmax(hi[0], u);
                lo[1] = fmin(lo[1], v);
                hi[1] = fmax(hi[1], v);
            }
        }
        s[b].x = px + (size_t)b * rows;
        s[b].y = py + (size_t)b * rows;
        s[b].n = t->rows;
        s[b].style = b == 0 ? 2 : 0; /* the first body (a ring's centre) with its points */
        /* up to 8 bodies each has its own colour and legend entry; beyond, colours repeat */
        if (nbod <= 8) {
            snprintf(labels[b], sizeof labels[b], "body %d", b + 1);
            s[b].label = labels[b];
        } else {
            s[b].label = b == 0 ? "body 1" : b == 1 ? "bodies 2 ... (colours repeat)" : NULL;
        }
    }
    /* a square frame around everything, so one unit is as long on both axes */
    double cx = 0.5 * (lo[0] + hi[0]), cy = 0.5 * (lo[1] + hi[1]);
    double half = 0.55 * fmax(hi[0] - lo[0], hi[1] - lo[1]);
    if (!(half > 0) || !isfinite(half))
        half = 1;
    char title[400];
    double t0 = t->rows ? mote_table_at(t, 0, 0) : 0, t1 = t->rows ? mote_table_at(t, t->rows - 1, 0) : 0;
    snprintf(title, sizeof title, "orbits of %d bodies, T = %.6g to %.6g (invariable plane)", nbod,
             t0, t1);
    mote_plot_opts o;
    memset(&o, 0, sizeof o);
    o.title = title;
    o.xlabel = "x' (dimensionless length)";
    o.ylabel = "y' (dimensionless length)";
    o.width = 1000;
    o.equal_axes = 1;
    o.xmin = cx - half;
    o.xmax = cx + half;
    o.ymin = cy - half;
    o.ymax = cy + half;
    int rc = mote_plot_png(png, &o, s, (size_t)nbod, err);
    free(px);
    free(py);
    free(s);
    return rc;
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
    for (size_t r = 0; r < t->rows; r++) {
        T[r] = mote_table_at(t, r, cT);
        E[r] = mote_table_at(t, r, cE);
        M[r] = mote_table_at(t, r, cM);
    }
    mote_series s[2] = {{T, E, t->rows, "dE = (E - E0)/|E0|", 2},
                        {T, M, t->rows, "dMz (aggregated z moment)", 2}};
    mote_plot_opts o;
    memset(&o, 0, sizeof o);
    o.title = "conserved quantities: relative drift";
    o.xlabel = "T (dimensionless time)";
    o.ylabel = "relative change";
    o.has_yref = 1;
    o.yref = 0;
    int rc = mote_plot_png(png, &o, s, 2, err);
    free(T);
    free(E);
    free(M);
    return rc;
}

int nb_plot_file(const char *data_path, const char *png_path, mote_err *err)
{
    mote_table t;
    int rc = mote_table_read(&t, data_path, err);
    if (rc)
        return rc;
    if (strcmp(t.format, "nbody-trajectory") == 0)
        rc = plot_orbits(&t, data_path, png_path, err);
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
