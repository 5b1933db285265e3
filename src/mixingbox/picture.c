/* picture.c: what the user sees of the mixing box: PNG snapshots (disks in their two colours, the
 * box as the frame, the partition drawn as a dense band of grey disks because the renderer has
 * no rectangle primitive, the slit as the gap in it), extended XYZ snapshots for OVITO and VMD,
 * numbered frames for a movie, the movie itself through ffmpeg when it is installed, and `plot`
 * of the model's data files (the mixing curve, the density profile with the barometric law). */
#include "mb.h"
#include "mote/h5md.h"
#include "mote/vtk.h"
#include "mote/vtk.h"

#include "mote/datafile.h"
#include "mote/render.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- snapshots ------------------------------------------------------------------------------- */

enum { PARTITION_CLASS = 7 }; /* grey in the renderer's palette */

/* Disks of radius rho covering [x0, x1] x [y0, y1] (their union stays inside it), appended at
 * index k; returns the new count. With x == NULL it only counts. */
static size_t band_disks(double x0, double x1, double y0, double y1, double rho, double *x,
                         double *y, double *r, int *c, size_t k)
{
    if (!(x1 > x0) || !(y1 > y0))
        return k;
    double rx = fmin(rho, 0.5 * (x1 - x0)), ry = fmin(rho, 0.5 * (y1 - y0));
    double rr = fmin(rx, ry), step = 0.5 * rr;
    size_t nx = (size_t)ceil((x1 - x0 - 2 * rr) / step) + 1;
    size_t ny = (size_t)ceil((y1 - y0 - 2 * rr) / step) + 1;
    for (size_t a = 0; a < nx; a++)
        for (size_t b = 0; b < ny; b++) {
            if (x) {
                double fx = nx > 1 ? (double)a / (double)(nx - 1) : 0.5;
                double fy = ny > 1 ? (double)b / (double)(ny - 1) : 0.5;
                x[k] = x0 + rr + fx * (x1 - x0 - 2 * rr);
                y[k] = y0 + rr + fy * (y1 - y0 - 2 * rr);
                r[k] = rr;
                c[k] = PARTITION_CLASS;
            }
            k++;
        }
    return k;
}

static size_t partition_disks(const mote_mb_params *p, double *x, double *y, double *r, int *c,
                              size_t k)
{
    double h = p->x_t - p->x_b;
    double rho = fmax(fmin(0.5 * p->a, h / 100.0), p->a / 200.0);
    double x1l = mote_mb_x1_l(p), x1r = mote_mb_x1_r(p);
    if (p->b > 0) {
        k = band_disks(x1l, x1r, p->x_b, mote_mb_x2_b(p), rho, x, y, r, c, k);
        k = band_disks(x1l, x1r, mote_mb_x2_t(p), p->x_t, rho, x, y, r, c, k);
    } else {
        k = band_disks(x1l, x1r, p->x_b, p->x_t, rho, x, y, r, c, k);
    }
    return k;
}

/* Picture size: disks at least about 3 pixels in radius, within 600 .. 1600 pixels. */
static int picture_width(const mote_mb_params *p)
{
    double longer = fmax(p->x_r - p->x_l, p->x_t - p->x_b);
    double w = 3.0 * longer / p->r;
    return w < 600 ? 600 : w > 1600 ? 1600 : (int)w;
}

int mb_snapshot_png(const mote_mb *sys, const char *path, mote_err *err)
{
    const mote_mb_params *p = &sys->p;
    size_t extra = partition_disks(p, NULL, NULL, NULL, NULL, 0);
    size_t n = sys->n + extra;
    double *x = malloc(n * sizeof *x), *y = malloc(n * sizeof *y), *r = malloc(n * sizeof *r);
    int *c = malloc(n * sizeof *c);
    int rc;
    if (!x || !y || !r || !c) {
        rc = mote_fail(err, MOTE_ENOMEM, "%s: out of memory", path);
    } else {
        for (uint32_t i = 0; i < sys->n; i++) {
            x[i] = sys->x[i];
            y[i] = sys->y[i];
            r[i] = p->r;
            c[i] = sys->colour[i];
        }
        partition_disks(p, x, y, r, c, sys->n);
        mote_mb_tally t = mote_mb_counts(sys);
        char title[256];
        snprintf(title, sizeof title,
                 "t = %.6g s   m = %.3f   left %llu + %llu   right %llu + %llu (colour 0 + 1)",
                 sys->time, mote_mb_mixing_fraction(&t), (unsigned long long)t.n[0][0],
                 (unsigned long long)t.n[0][1], (unsigned long long)t.n[1][0],
                 (unsigned long long)t.n[1][1]);
        mote_scatter_opts o = {0};
        o.title = title;
        o.xlabel = "x (m)";
        o.ylabel = "y (m)";
        o.width = picture_width(p);
        o.xmin = p->x_l;
        o.xmax = p->x_r;
        o.ymin = p->x_b;
        o.ymax = p->x_t;
        rc = mote_disks_png(path, &o, x, y, r, c, n, err);
    }
    free(x);
    free(y);
    free(r);
    free(c);
    return rc;
}

int mb_xyz_frame(FILE *f, const void *arg, mote_err *err)
{
    const mote_mb *sys = ((const mb_xyz_of *)arg)->sys;
    const char *origin = ((const mb_xyz_of *)arg)->origin;
    const mote_mb_params *p = &sys->p;
    fprintf(f, "%u\n", sys->n);
    /* The comment line may not hold double quotes inside a value: replace them. */
    char org[512];
    snprintf(org, sizeof org, "%s", origin ? origin : "");
    for (char *q = org; *q; q++)
        if (*q == '"')
            *q = '\'';
    fprintf(f,
            "Lattice=\"%.17g 0 0 0 %.17g 0 0 0 %.17g\" Origin=\"%.17g %.17g 0\" "
            "Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1:colour:I:1 Time=%.17g "
            "pbc=\"F F F\" model=mixing-box command=\"%s\"\n",
            p->x_r - p->x_l, p->x_t - p->x_b, 2 * p->r, p->x_l, p->x_b, sys->time, org);
    for (uint32_t i = 0; i < sys->n; i++)
        fprintf(f, "%s %.17g %.17g 0 %.17g %.17g 0 %.17g %d\n", sys->colour[i] ? "Ar" : "He",
                sys->x[i], sys->y[i], sys->vx[i], sys->vy[i], p->r, sys->colour[i]);
    return MOTE_OK;
}

/* The frame as H5MD (h5md.h; SI units): made anew (how 0) or added at the end (1); or as VTK
 * (2, vtk.h). The box's edges are its width and height; positions are the model's own (the box
 * spans x_l..x_r, x_b..x_t). */
static int mb_h5md(const mote_mb *sys, const char *path, const char *origin, int how,
                   mote_err *err)
{
    const size_t n = sys->n;
    double *buf = malloc((n ? n : 1) * 5 * sizeof *buf);
    int32_t *species = malloc((n ? n : 1) * sizeof *species);
    int rc;
    if (!buf || !species) {
        rc = mote_fail(err, MOTE_ENOMEM, "%s: out of memory for a frame of %zu disks", path, n);
    } else {
        double *pos = buf, *vel = buf + 2 * n, *rad = buf + 4 * n;
        for (size_t i = 0; i < n; i++) {
            pos[2 * i] = sys->x[i];
            pos[2 * i + 1] = sys->y[i];
            vel[2 * i] = sys->vx[i];
            vel[2 * i + 1] = sys->vy[i];
            rad[i] = sys->p.r;
            species[i] = sys->colour[i];
        }
        mote_h5md_frame fr = {.model = "mixing-box", .origin = origin, .seed = sys->seed,
                              .dim = 2, .n = n, .pos = pos, .vel = vel, .species = species,
                              .nscalar = 1, .has_box = 1,
                              .edges = {sys->p.x_r - sys->p.x_l, sys->p.x_t - sys->p.x_b},
                              .time = sys->time, .step = (int64_t)sys->collisions,
                              .length_unit = "m", .time_unit = "s"};
        fr.scalar[0] = (mote_h5md_scalar){"radius", "m", rad};
        rc = how == 2   ? mote_vtk_particles(path, &fr, err)
             : how == 1 ? mote_h5md_append(path, &fr, err)
                        : mote_h5md_first(path, &fr, err);
    }
    free(buf);
    free(species);
    return rc;
}

int mb_snapshot_xyz(const mote_mb *sys, const char *path, const char *origin, mote_err *err)
{
    if (mote_path_is_h5md(path))
        return mb_h5md(sys, path, origin, 0, err);
    if (mote_path_is_vtk(path))
        return mb_h5md(sys, path, origin, 2, err);
    const mb_xyz_of x = {sys, origin};
    return mote_frames_first(path, mb_xyz_frame, &x, err);
}

int mb_trajectory_fire(void *ctx, void *subject, mote_err *err)
{
    const mb_trajectory *t = ctx;
    if (mote_path_is_h5md(t->path))
        return mb_h5md(subject, t->path, t->origin, 1, err);
    const mb_xyz_of x = {subject, t->origin};
    return mote_frames_append(t->path, mb_xyz_frame, &x, err);
}

/* ---- frames and movies ----------------------------------------------------------------------- */

char *mb_frame_name(const char *prefix, uint64_t k)
{
    return mote_series_path(prefix, k, 6, ".png");
}

int mb_frames_sample(void *ctx, void *subject, mote_err *err)
{
    mote_mb *sys = subject;
    mb_frames *fr = ctx;
    char *name = mote_series_path(fr->prefix, fr->next_index, 6,
                                  fr->xyz == MB_SERIES_H5MD  ? ".h5"
                                  : fr->xyz == MB_SERIES_VTK ? ".vtk"
                                  : fr->xyz                  ? ".xyz"
                                                             : ".png");
    if (name)
        mote_make_dir_of(name); /* (a prefix= makes its folder) */
    if (!name)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", fr->xyz ? "snapshot" : "frames");
    int rc = fr->xyz ? mb_snapshot_xyz(sys, name, fr->origin, err) : mb_snapshot_png(sys, name, err);
    free(name);
    if (!rc)
        fr->next_index++;
    return rc;
}

/* ---- plot ------------------------------------------------------------------------------------ */

typedef mote_table table;

/* Read a data file of this model: the format is one of ours, there is a '# columns:' line, and
 * every row holds a number for each column (named by file and line otherwise). */
static int read_table(const char *path, table *t, mote_err *err)
{
    int rc = mote_table_read(t, path, err);
    if (rc) {
        char why[sizeof err->msg];
        snprintf(why, sizeof why, "%s", err->msg);
        return mote_fail(err, (mote_status)rc, "plot: %s", why);
    }
    if (strcmp(t->format, "mixing") != 0 && strcmp(t->format, "mixing-density") != 0)
        rc = mote_fail(err, MOTE_EFORMAT,
                       "plot: '%s' is not a mixing-box data file (its first line should be "
                       "'# mote mixing 1' or '# mote mixing-density 1')",
                       path);
    else if (t->rows && t->ncolnames == 0)
        rc = mote_fail(err, MOTE_EFORMAT, "plot: %s:%ld: data before the '# columns:' line",
                       path, t->line[0]);
    for (size_t r = 0; !rc && r < t->rows; r++) {
        if (t->ncol[r] < t->ncolnames) /* a word where a number belongs reads as NaN */
            rc = mote_fail(err, MOTE_EFORMAT,
                           "plot: %s:%ld: expected %d numbers (columns %s ...), found %d", path,
                           t->line[r], t->ncolnames, t->colname[0], t->ncol[r]);
    }
    if (rc)
        mote_table_free(t);
    return rc;
}

static double *column(const table *t, int k)
{
    double *c = malloc((t->rows ? t->rows : 1) * sizeof *c);
    if (c)
        for (size_t r = 0; r < t->rows; r++)
            c[r] = mote_table_at(t, r, k);
    return c;
}

static int need_cols(const table *t, const char *path, const char *const *names, int *idx,
                     int n, mote_err *err)
{
    for (int k = 0; k < n; k++) {
        idx[k] = mote_table_col(t, names[k]);
        if (idx[k] < 0)
            return mote_fail(err, MOTE_EFORMAT, "plot: '%s' has no column '%s'", path, names[k]);
    }
    return MOTE_OK;
}

static int plot_mixing(const table *t, const char *in, const char *out, mote_err *err)
{
    static const char *const names[] = {"t", "m", "S_mix"};
    int idx[3];
    int rc = need_cols(t, in, names, idx, 3, err);
    if (rc)
        return rc;
    double *tt = column(t, idx[0]), *m = column(t, idx[1]), *s = column(t, idx[2]);
    if (!tt || !m || !s) {
        rc = mote_fail(err, MOTE_ENOMEM, "plot: out of memory");
    } else {
        for (size_t r = 0; r < t->rows; r++)
            s[r] /= log(2.0);
        mote_series ser[2] = {
            {tt, m, t->rows, "mixing fraction m", 0},
            {tt, s, t->rows, "mixing entropy S_mix / ln 2", 0},
        };
        mote_plot_opts o = {0};
        o.title = "mixing curve";
        o.xlabel = "t (s)";
        o.ylabel = "m,  S_mix / ln 2";
        o.ymin = 0;
        o.ymax = 1.05;
        double m_eq = mote_table_key(t, "m_eq");
        o.has_yref = isfinite(m_eq);
        o.yref = m_eq;
        o.yref_label = "m of a uniform mixture";
        rc = mote_plot_png(out, &o, ser, 2, err);
    }
    free(tt);
    free(m);
    free(s);
    return rc;
}

static int plot_density(const table *t, const char *in, const char *out, mote_err *err)
{
    static const char *const names[] = {"y", "n_left", "n_right", "baro_left", "baro_right"};
    int idx[5];
    int rc = need_cols(t, in, names, idx, 5, err);
    if (rc)
        return rc;
    const double g = mote_table_has(t, "g") ? mote_table_key(t, "g") : 0.0;
    double *c[5] = {0};
    for (int k = 0; k < 5; k++)
        c[k] = column(t, idx[k]);
    if (!c[0] || !c[1] || !c[2] || !c[3] || !c[4]) {
        rc = mote_fail(err, MOTE_ENOMEM, "plot: out of memory");
    } else {
        mote_series ser[4] = {
            {c[0], c[1], t->rows, "left chamber", 2},
            {c[0], c[2], t->rows, "right chamber", 2},
            {c[0], c[3], t->rows, g != 0 ? "barometric law, left" : "uniform, left", 0},
            {c[0], c[4], t->rows, g != 0 ? "barometric law, right" : "uniform, right", 0},
        };
        mote_plot_opts o = {0};
        o.title = "density profile in y";
        o.xlabel = "y (m)";
        o.ylabel = "number density (m^-2)";
        rc = mote_plot_png(out, &o, ser, 4, err);
    }
    for (int k = 0; k < 5; k++)
        free(c[k]);
    return rc;
}

int mb_plot_file(const char *in, const char *out, mote_err *err)
{
    table t;
    int rc = read_table(in, &t, err);
    if (rc)
        return rc;
    if (strcmp(t.format, "mixing") == 0)
        rc = plot_mixing(&t, in, out, err);
    else
        rc = plot_density(&t, in, out, err);
    mote_table_free(&t);
    return rc;
}
