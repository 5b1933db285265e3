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

typedef struct {
    char format[32];
    double A, L, mean_density, x1, x2;
    double p_wall, p_virial, mu_level; /* NaN unless in the header */
    int dim;
    char command[256];
    long *row_line;                    /* file line of each data row (for messages) */
} header;

static void parse_header_line(header *h, const char *line)
{
    char key[64];
    double val;
    if (sscanf(line, "# mote %31s 1", h->format) == 1 && h->format[0])
        return;
    if (strncmp(line, "# command: ", 11) == 0) {
        snprintf(h->command, sizeof h->command, "%s", line + 11);
        h->command[strcspn(h->command, "\r\n")] = '\0';
        return;
    }
    if (sscanf(line, "# %63s = %lf", key, &val) == 2) {
        if (!strcmp(key, "A"))
            h->A = val;
        else if (!strcmp(key, "L"))
            h->L = val;
        else if (!strcmp(key, "mean_density"))
            h->mean_density = val;
        else if (!strcmp(key, "d"))
            h->dim = val == 2 ? 2 : 3; /* a file of mote's has 2 or 3 (never convert others) */
        else if (!strcmp(key, "x1"))
            h->x1 = val;
        else if (!strcmp(key, "x2"))
            h->x2 = val;
        else if (!strcmp(key, "P_wall"))
            h->p_wall = val;
        else if (!strcmp(key, "P_virial"))
            h->p_virial = val;
        else if (!strcmp(key, "ln_n_plus_mu_ex"))
            h->mu_level = val;
    }
}

/* A data file's rows: numbers per row (text tokens read as NaN), the block each row is in
 * (blocks are separated by blank lines), and the first token of each row as text. */
typedef struct {
    vec num;          /* rows * MAXCOL numbers */
    int *ncol, *block;
    char (*first)[16];
    size_t rows, cap;
} table;

#define MAXCOL 64

static int table_add(table *t, char *line, int block)
{
    if (t->rows == t->cap) {
        size_t cap = t->cap ? 2 * t->cap : 256;
        int *nc = realloc(t->ncol, cap * sizeof *nc);
        if (nc)
            t->ncol = nc;
        int *bl = realloc(t->block, cap * sizeof *bl);
        if (bl)
            t->block = bl;
        char(*fi)[16] = realloc(t->first, cap * sizeof *fi);
        if (fi)
            t->first = fi;
        if (!nc || !bl || !fi)
            return 0;
        t->cap = cap;
    }
    int n = 0;
    char *p = line;
    sscanf(line, "%15s", t->first[t->rows]);
    for (;;) {
        while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')
            p++;
        if (!*p)
            break;
        char *end;
        double v = strtod(p, &end);
        if (end == p) { /* a text token */
            v = NAN;
            while (*end && *end != ' ' && *end != '\t' && *end != '\r' && *end != '\n')
                end++;
        }
        if (n < MAXCOL && !vec_push(&t->num, v))
            return 0;
        n++;
        p = end;
    }
    for (int k = n; k < MAXCOL; k++)
        if (!vec_push(&t->num, NAN))
            return 0;
    t->ncol[t->rows] = n;
    t->block[t->rows] = block;
    t->rows++;
    return 1;
}

static double cell(const table *t, size_t row, int col)
{
    return col < MAXCOL ? t->num.v[row * MAXCOL + (size_t)col] : NAN;
}

static void table_free(table *t)
{
    free(t->num.v);
    free(t->ncol);
    free(t->block);
    free(t->first);
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
    FILE *f = fopen(data_path, "r");
    if (!f)
        return mote_fail(err, MOTE_EIO, "plot: cannot read '%s': %s", data_path, strerror(errno));
    header h;
    memset(&h, 0, sizeof h);
    h.dim = 3;
    h.p_wall = h.p_virial = h.mu_level = NAN;
    table t;
    memset(&t, 0, sizeof t);
    char *line = NULL;
    size_t cap = 0;
    long lineno = 0;
    int rc = MOTE_OK, block = 0, blank = 0;
    while (getline(&line, &cap, f) >= 0) {
        lineno++;
        if (line[0] == '#') {
            parse_header_line(&h, line);
            continue;
        }
        if (line[strspn(line, " \t\r\n")] == '\0') {
            blank = t.rows > 0;
            continue;
        }
        if (!h.format[0]) {
            rc = mote_fail(err, MOTE_EFORMAT,
                           "%s:%ld: not a mote data file (expected a '# mote image 1' or similar "
                           "header first)",
                           data_path, lineno);
            break;
        }
        if (strcmp(h.format, "image") && strcmp(h.format, "profile") &&
            strcmp(h.format, "pressure") && strcmp(h.format, "chempot") &&
            strcmp(h.format, "order") && strcmp(h.format, "rdf") && strcmp(h.format, "msd")) {
            rc = mote_fail(err, MOTE_EFORMAT,
                           "%s:1: plot knows the data of image, profile, pressure, chempot, "
                           "order, rdf and msd, not '%s'",
                           data_path, h.format);
            break;
        }
        if (blank) {
            block++;
            blank = 0;
        }
        long *rl = realloc(h.row_line, (t.rows + 1) * sizeof *rl);
        if (!rl || !table_add(&t, line, block)) {
            if (rl)
                h.row_line = rl;
            rc = mote_fail(err, MOTE_ENOMEM, "plot: out of memory");
            break;
        }
        h.row_line = rl;
        h.row_line[t.rows - 1] = lineno;
    }
    free(line);
    fclose(f);
    if (!rc && !h.format[0])
        rc = mote_fail(err, MOTE_EFORMAT, "%s: no mote data header found", data_path);
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
        else
            rc = plot_order(&t, &h, png_path, err);
    }
    free(h.row_line);
    table_free(&t);
    return rc;
}
