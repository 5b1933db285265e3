/* plot.c: the `plot` command: read a data file written by a measuring command, recognised by its
 * first header line, and render it as a PNG:
 * - image: the number density against x;
 * - profile: the first sample of the cut drawn to scale as disks;
 * - pressure: P_N(x) and P_T(x) with the wall (or virial) pressure as a reference line;
 * - chempot: beta mu_ex(x) and ln rho(x) + beta mu_ex(x), with the equilibrium constant;
 * - order: the crystal-like fraction of the whole system and of each left-wall layer and the
 *   bulk against time (block 3); with a single sample, the fine profile against x instead;
 * - rdf: g(r) (periodic box) or the wall and mid-slit layers' lateral g(s), with g = 1;
 * - msd: the mean-squared displacement against the lag time. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mote/datafile.h"
#include "mote/render.h"
#include "plot.h"

typedef struct {
    double *v;
    size_t n, cap;
} vec;

static int vec_push(vec *a, double x)
{
    if (a->n == a->cap) {
        size_t cap = a->cap ? 2 * a->cap : 256;
        double *p = realloc(a->v, cap * sizeof *p);
        if (!p)
            return 0;
        a->v = p;
        a->cap = cap;
    }
    a->v[a->n++] = x;
    return 1;
}

/* What the pictures use of a data file's header. */
typedef struct {
    const char *format;
    double A, L, mean_density, x1, x2;
    double p_wall, p_virial, mu_level; /* NaN unless in the header */
    int dim;
    const char *command;
    const long *row_line;              /* file line of each data row (for messages) */
} header;

typedef mote_table table;

static double cell(const table *t, size_t row, int col) { return mote_table_at(t, row, col); }

/* A geometric header value: 0 when absent (a malformed file then fails its checks, never draws
 * from NaN). */
static double key0(const table *t, const char *key)
{
    double v = mote_table_key(t, key);
    return isnan(v) && !mote_table_has(t, key) ? 0.0 : v;
}

/* Columns (x_col, y_col) of the rows of one block as a series. */
static int block_series(const table *t, int block, int xc, int yc, vec *xs, vec *ys)
{
    for (size_t r = 0; r < t->rows; r++)
        if (t->block[r] == block && (!vec_push(xs, cell(t, r, xc)) || !vec_push(ys, cell(t, r, yc))))
            return 0;
    return 1;
}

/* The rows a format must have, per block: columns expected (0 = any). */
static int check_rows(const table *t, const header *h, const char *path, mote_err *err)
{
    for (size_t r = 0; r < t->rows; r++) {
        int n = t->ncol[r], want = -1;
        if (!strcmp(h->format, "image"))
            want = 7;
        else if (!strcmp(h->format, "profile"))
            want = h->dim == 3 ? 5 : 4;
        else if (!strcmp(h->format, "pressure"))
            want = t->block[r] == 0 ? 10 : 5;
        else if (!strcmp(h->format, "chempot"))
            want = 8;
        else if (!strcmp(h->format, "order"))
            want = t->block[r] == 0 ? 14 : t->block[r] == 1 ? 10 : 0;
        else if (!strcmp(h->format, "rdf"))
            want = t->ncol[0] == 7 ? 7 : 5; /* slit or periodic box */
        else if (!strcmp(h->format, "msd"))
            want = 4;
        else if (!strcmp(h->format, "hard-spheres-monitor"))
            want = 7;
        if (want > 0 && n != want)
            return mote_fail(err, MOTE_EFORMAT, "%s:%ld: malformed data row (%d numbers)", path,
                             h->row_line[r], n);
    }
    return MOTE_OK;
}


static void title_for(char *buf, size_t n, const char *what, const header *h)
{
    snprintf(buf, n, "%s: %s", what, h->command[0] ? h->command : "(no command recorded)");
}

static int plot_image(const table *t, const header *h, const char *png, mote_err *err)
{
    vec xs = {0}, ys = {0};
    int rc = MOTE_OK;
    if (!block_series(t, 0, 2, 4, &xs, &ys))
        rc = mote_fail(err, MOTE_ENOMEM, "plot: out of memory");
    if (!rc) {
        mote_series s = {xs.v, ys.v, xs.n, "number density", 0};
        char title[320];
        title_for(title, sizeof title, "Density profile", h);
        mote_plot_opts o;
        memset(&o, 0, sizeof o);
        o.title = title;
        o.xlabel = "x  [R]";
        o.ylabel = h->dim == 2 ? "number density  [R^-2]" : "number density  [R^-3]";
        o.has_yref = h->mean_density > 0;
        o.yref = h->mean_density;
        o.yref_label = "mean density N/(A^2 L)";
        rc = mote_plot_png(png, &o, &s, 1, err);
    }
    free(xs.v);
    free(ys.v);
    return rc;
}

static int plot_profile(const table *t, const header *h, const char *png, mote_err *err)
{
    vec xs = {0}, ys = {0};
    for (size_t r = 0; r < t->rows; r++)
        if (cell(t, r, 0) == 1.0 &&
            (!vec_push(&xs, cell(t, r, 2)) || !vec_push(&ys, cell(t, r, 3)))) {
            free(xs.v);
            free(ys.v);
            return mote_fail(err, MOTE_ENOMEM, "plot: out of memory");
        }
    size_t n = xs.n;
    double *rad = malloc((n ? n : 1) * sizeof *rad);
    int rc;
    if (!rad) {
        rc = mote_fail(err, MOTE_ENOMEM, "plot: out of memory");
    } else {
        for (size_t k = 0; k < n; k++)
            rad[k] = 1.0;
        char title[320];
        snprintf(title, sizeof title, "Layer cut %.3g <= x <= %.3g (first sample, %zu spheres)",
                 h->x1, h->x2, n);
        mote_scatter_opts o;
        memset(&o, 0, sizeof o);
        o.title = title;
        o.xlabel = "y  [R]";
        o.xmin = 0;
        o.xmax = h->A;
        if (h->dim == 3) {
            o.ylabel = "z  [R]";
            o.ymin = 0;
            o.ymax = h->A;
            o.periodic = 1;
        } else {
            o.ylabel = "x  [R]";
            o.ymin = h->x1 - 1;
            o.ymax = h->x2 + 1;
        }
        rc = mote_disks_png(png, &o, xs.v, ys.v, rad, NULL, n, err);
        free(rad);
    }
    free(xs.v);
    free(ys.v);
    return rc;
}

/* Several y columns of one block against one x column. */
static int plot_columns(const table *t, int block, int xc, const int *yc, const char *const *labels,
                        int ny, mote_plot_opts *o, const char *png, mote_err *err)
{
    vec xs[8] = {{0}}, ys[8] = {{0}};
    mote_series s[8];
    int rc = MOTE_OK;
    if (ny > 8)
        ny = 8;
    for (int k = 0; k < ny && !rc; k++) {
        if (!block_series(t, block, xc, yc[k], &xs[k], &ys[k]))
            rc = mote_fail(err, MOTE_ENOMEM, "plot: out of memory");
        s[k] = (mote_series){xs[k].v, ys[k].v, xs[k].n, labels[k], xs[k].n > 60 ? 0 : 2};
    }
    if (!rc)
        rc = mote_plot_png(png, o, s, (size_t)ny, err);
    for (int k = 0; k < 8; k++) {
        free(xs[k].v);
        free(ys[k].v);
    }
    return rc;
}

static int plot_pressure(const table *t, const header *h, const char *png, mote_err *err)
{
    char title[320];
    title_for(title, sizeof title, "Pressure tensor", h);
    mote_plot_opts o;
    memset(&o, 0, sizeof o);
    o.title = title;
    o.xlabel = "x  [R]";
    o.ylabel = h->dim == 2 ? "pressure  [kT R^-2]" : "pressure  [kT R^-3]";
    int slit = isfinite(h->p_wall);
    o.has_yref = slit || isfinite(h->p_virial);
    o.yref = slit ? h->p_wall : h->p_virial;
    o.yref_label = slit ? "wall pressure" : "virial pressure";
    const int yc[] = {4, 5};
    const char *const labels[] = {"P_N (normal)", "P_T (tangential)"};
    return plot_columns(t, 0, 0, yc, labels, 2, &o, png, err);
}

/* `monitor`'s rows: the pressure of each interval against time (the walls' in a slit). */
static int plot_monitor(const table *t, const header *h, const char *png, mote_err *err)
{
    char title[320];
    title_for(title, sizeof title, "Pressure over time", h);
    mote_plot_opts o;
    memset(&o, 0, sizeof o);
    o.title = title;
    o.xlabel = "t  [sqrt(m R^2 / kT)]";
    o.ylabel = h->dim == 2 ? "pressure  [kT R^-2]" : "pressure  [kT R^-3]";
    const int slit = t->rows > 1 && isfinite(cell(t, 1, 5));
    const int yc_slit[] = {5, 6}, yc_box[] = {4};
    const char *const labels_slit[] = {"P_left", "P_right"}, *const labels_box[] = {"P_virial"};
    return slit ? plot_columns(t, 0, 0, yc_slit, labels_slit, 2, &o, png, err)
                : plot_columns(t, 0, 0, yc_box, labels_box, 1, &o, png, err);
}

static int plot_chempot(const table *t, const header *h, const char *png, mote_err *err)
{
    char title[320];
    title_for(title, sizeof title, "Widom insertion", h);
    mote_plot_opts o;
    memset(&o, 0, sizeof o);
    o.title = title;
    o.xlabel = "x  [R]";
    o.ylabel = "[kT]";
    o.has_yref = isfinite(h->mu_level);
    o.yref = h->mu_level;
    o.yref_label = "ln n + mu_ex (whole system)";
    const int yc[] = {4, 6};
    const char *const labels[] = {"mu_ex(x) = -ln p(x)", "ln rho(x) + mu_ex(x)"};
    return plot_columns(t, 0, 0, yc, labels, 2, &o, png, err);
}

static int plot_rdf(const table *t, const header *h, const char *png, mote_err *err)
{
    const int slit = t->rows > 0 && t->ncol[0] == 7;
    char title[320];
    title_for(title, sizeof title, slit ? "Lateral g(s) in a layer" : "Radial distribution", h);
    mote_plot_opts o;
    memset(&o, 0, sizeof o);
    o.title = title;
    o.xlabel = slit ? "s (lateral distance)  [R]" : "r  [R]";
    o.ylabel = "g";
    o.has_yref = 1;
    o.yref = 1;
    o.yref_label = "uncorrelated (g = 1)";
    const int yc[] = {3, 5};
    const char *const labels[] = {slit ? "layer at the walls" : "g(r)", "layer at mid-slit"};
    return plot_columns(t, 0, 2, yc, labels, slit ? 2 : 1, &o, png, err);
}

static int plot_msd(const table *t, const header *h, const char *png, mote_err *err)
{
    char title[320];
    title_for(title, sizeof title, "Mean-squared displacement", h);
    mote_plot_opts o;
    memset(&o, 0, sizeof o);
    o.title = title;
    o.xlabel = "lag time  [sqrt(m R^2 / kT)]";
    o.ylabel = "msd  [R^2]";
    const int yc[] = {1};
    const char *const labels[] = {"msd"};
    return plot_columns(t, 0, 0, yc, labels, 1, &o, png, err);
}

static int plot_order(const table *t, const header *h, const char *png, mote_err *err)
{
    size_t nlayers = 0, ntime = 0;
    for (size_t r = 0; r < t->rows; r++) {
        nlayers += t->block[r] == 0;
        ntime += t->block[r] == 2;
    }
    char title[320];
    mote_plot_opts o;
    memset(&o, 0, sizeof o);
    o.title = title;
    o.ymin = 0;
    o.ymax = 1;
    if (ntime < 2) { /* one sample: the fine profile */
        title_for(title, sizeof title, "Crystallinity profile", h);
        o.xlabel = "x  [R]";
        o.ylabel = "fraction";
        const int yc[] = {7, 8};
        const char *const labels[] = {"crystal-like (q6 bonds)", "ordered in layer (|psi6|)"};
        return plot_columns(t, 1, 2, yc, labels, h->dim == 3 ? 2 : 1, &o, png, err);
    }
    /* over time: the whole system, then the left wall's layers and the bulk (block 1 order) */
    title_for(title, sizeof title, "Crystal-like fraction over time", h);
    o.xlabel = "time  [sqrt(m R^2 / kT)]";
    o.ylabel = "crystal-like fraction";
    int yc[8];
    char names[8][32];
    const char *labels[8];
    int ny = 0;
    yc[ny] = 3;
    labels[ny++] = "whole system";
    size_t k = 0;
    for (size_t r = 0; r < t->rows && ny < 8; r++) {
        if (t->block[r] != 0)
            continue;
        const char *side = t->first[r];
        if (!strcmp(side, "left") || !strcmp(side, "bulk")) {
            if (!strcmp(side, "left"))
                snprintf(names[ny], sizeof names[ny], "layer %d", (int)cell(t, r, 1));
            else
                snprintf(names[ny], sizeof names[ny], "bulk");
            yc[ny] = 4 + 2 * (int)k;
            labels[ny] = names[ny];
            ny++;
        }
        k++;
    }
    return plot_columns(t, 2, 2, yc, labels, ny, &o, png, err);
}

int hs_plot_file(const char *data_path, const char *png_path, mote_err *err)
{
    table t;
    int rc = mote_table_read(&t, data_path, err);
    if (rc)
        return rc;
    header h = {
        .format = t.format,
        .A = key0(&t, "A"),
        .L = key0(&t, "L"),
        .mean_density = key0(&t, "mean_density"),
        .x1 = key0(&t, "x1"),
        .x2 = key0(&t, "x2"),
        .p_wall = mote_table_key(&t, "P_wall"),
        .p_virial = mote_table_key(&t, "P_virial"),
        .mu_level = mote_table_key(&t, "ln_n_plus_mu_ex"),
        .dim = mote_table_key(&t, "d") == 2 ? 2 : 3, /* mote writes 2 or 3 (never convert others) */
        .command = t.command,
        .row_line = t.line,
    };
    if (!t.format[0])
        rc = mote_fail(err, MOTE_EFORMAT,
                       "%s:1: not a mote data file (expected a '# mote image 1' or similar "
                       "header first)",
                       data_path);
    else if (strcmp(h.format, "image") && strcmp(h.format, "profile") &&
             strcmp(h.format, "pressure") && strcmp(h.format, "chempot") &&
             strcmp(h.format, "order") && strcmp(h.format, "rdf") && strcmp(h.format, "msd") &&
             strcmp(h.format, "hard-spheres-monitor"))
        rc = mote_fail(err, MOTE_EFORMAT,
                       "%s:1: plot knows the data of image, profile, pressure, chempot, "
                       "order, rdf, msd and monitor, not '%s'",
                       data_path, h.format);
    if (!rc)
        rc = check_rows(&t, &h, data_path, err);
    if (!rc) {
        if (!strcmp(h.format, "image"))
            rc = plot_image(&t, &h, png_path, err);
        else if (!strcmp(h.format, "profile"))
            rc = plot_profile(&t, &h, png_path, err);
        else if (!strcmp(h.format, "pressure"))
            rc = plot_pressure(&t, &h, png_path, err);
        else if (!strcmp(h.format, "chempot"))
            rc = plot_chempot(&t, &h, png_path, err);
        else if (!strcmp(h.format, "rdf"))
            rc = plot_rdf(&t, &h, png_path, err);
        else if (!strcmp(h.format, "msd"))
            rc = plot_msd(&t, &h, png_path, err);
        else if (!strcmp(h.format, "hard-spheres-monitor"))
            rc = plot_monitor(&t, &h, png_path, err);
        else
            rc = plot_order(&t, &h, png_path, err);
    }
    mote_table_free(&t);
    return rc;
}
