/* plot.c: the `plot` command: read a data file written by `image` (density profile) or `profile`
 * (layer cut), recognised by its first header line, and render it as a PNG: a line plot of the
 * number density against x, or the first sample of the cut drawn to scale as disks. */
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
    int dim;
    char command[256];
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
            h->dim = (int)val;
        else if (!strcmp(key, "x1"))
            h->x1 = val;
        else if (!strcmp(key, "x2"))
            h->x2 = val;
    }
}

/* Split a data row into at most max numbers; returns count or -1 if a token is not a number. */
static int row_numbers(char *line, double *out, int max)
{
    int n = 0;
    for (char *p = line;;) {
        while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')
            p++;
        if (!*p)
            break;
        char *end;
        double v = strtod(p, &end);
        if (end == p)
            return -1;
        if (n < max)
            out[n] = v;
        n++;
        p = end;
    }
    return n;
}

int hs_plot_file(const char *data_path, const char *png_path, mote_err *err)
{
    FILE *f = fopen(data_path, "r");
    if (!f)
        return mote_fail(err, MOTE_EIO, "plot: cannot read '%s': %s", data_path, strerror(errno));
    header h;
    memset(&h, 0, sizeof h);
    h.dim = 3;
    vec xs = {0}, ys = {0};
    char *line = NULL;
    size_t cap = 0;
    long lineno = 0;
    int rc = MOTE_OK;
    while (getline(&line, &cap, f) >= 0) {
        lineno++;
        if (line[0] == '#') {
            parse_header_line(&h, line);
            continue;
        }
        double v[8];
        int n = row_numbers(line, v, 8);
        if (n == 0)
            continue;
        if (!h.format[0]) {
            rc = mote_fail(err, MOTE_EFORMAT,
                           "%s:%ld: not a mote data file (expected a '# mote image 1' or '# mote "
                           "profile 1' header first)",
                           data_path, lineno);
            break;
        }
        int ok = 1;
        if (!strcmp(h.format, "image")) {
            ok = n == 7 && vec_push(&xs, v[2]) && vec_push(&ys, v[4]);
        } else if (!strcmp(h.format, "profile")) {
            int want = h.dim == 3 ? 5 : 4;
            ok = n == want;
            if (ok && v[0] == 1.0)
                ok = vec_push(&xs, v[2]) && vec_push(&ys, v[3]);
        } else {
            rc = mote_fail(err, MOTE_EFORMAT,
                           "%s:1: plot knows the data of image and profile, not '%s'", data_path,
                           h.format);
            break;
        }
        if (!ok) {
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: malformed data row (%d numbers)",
                           data_path, lineno, n);
            break;
        }
    }
    free(line);
    fclose(f);
    if (!rc && !h.format[0])
        rc = mote_fail(err, MOTE_EFORMAT, "%s: no mote data header found", data_path);
    if (!rc && !strcmp(h.format, "image")) {
        mote_series s = {xs.v, ys.v, xs.n, "number density", 0};
        char title[320];
        snprintf(title, sizeof title, "Density profile: %s", h.command);
        mote_plot_opts o;
        memset(&o, 0, sizeof o);
        o.title = title;
        o.xlabel = "x  [R]";
        o.ylabel = h.dim == 2 ? "number density  [R^-2]" : "number density  [R^-3]";
        o.has_yref = h.mean_density > 0;
        o.yref = h.mean_density;
        o.yref_label = "mean density N/(A^2 L)";
        rc = mote_plot_png(png_path, &o, &s, 1, err);
    } else if (!rc) {
        size_t n = xs.n;
        double *r = malloc((n ? n : 1) * sizeof *r);
        if (!r) {
            rc = mote_fail(err, MOTE_ENOMEM, "plot: out of memory");
        } else {
            for (size_t k = 0; k < n; k++)
                r[k] = 1.0;
            char title[320];
            snprintf(title, sizeof title, "Layer cut %.3g <= x <= %.3g (first sample, %zu spheres)",
                     h.x1, h.x2, n);
            mote_scatter_opts o;
            memset(&o, 0, sizeof o);
            o.title = title;
            if (h.dim == 3) {
                o.xlabel = "y  [R]";
                o.ylabel = "z  [R]";
                o.xmin = 0;
                o.xmax = h.A;
                o.ymin = 0;
                o.ymax = h.A;
                o.periodic = 1;
            } else {
                o.xlabel = "y  [R]";
                o.ylabel = "x  [R]";
                o.xmin = 0;
                o.xmax = h.A;
                o.ymin = h.x1 - 1;
                o.ymax = h.x2 + 1;
                o.periodic = 0;
            }
            rc = mote_disks_png(png_path, &o, xs.v, ys.v, r, NULL, n, err);
            free(r);
        }
    }
    free(xs.v);
    free(ys.v);
    return rc;
}
