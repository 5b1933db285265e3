/* lines.c: `plot` as lines: chosen columns of one or more data files drawn as lines in one
 * frame, one line per file, with a legend (overlays of a sweep: density profiles at several eta,
 * Tromp curves at several speeds, energy errors of several integrators). Works in every model,
 * with any data file: the columns are named by x= and y=, or by the model's defaults for the
 * file's format (mote_model.plot_lines). Nothing here knows a model. */
#include "script_internal.h"
#include "mote/datafile.h"
#include "mote/render.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* Does column name `col` answer to `want`: the same, or the same before its unit ("rho" is
 * "rho[R^-3]")? */
static int col_is(const char *col, const char *want)
{
    size_t n = strlen(want);
    return strncmp(col, want, n) == 0 && (col[n] == '\0' || (col[n] == '[' && !strchr(want, '[')));
}

static int find_col(const mote_table *t, const char *want)
{
    for (int k = 0; k < t->ncolnames; k++)
        if (col_is(t->colname[k], want))
            return k;
    return -1;
}

/* The first of "a|b|c" that the table has (its index, and the name into buf), or -1. */
static int find_alt(const mote_table *t, const char *alts, char *buf, size_t cap)
{
    for (const char *p = alts; *p;) {
        size_t n = strcspn(p, "|");
        if (n < cap) {
            memcpy(buf, p, n);
            buf[n] = '\0';
            int k = find_col(t, buf);
            if (k >= 0)
                return k;
        }
        p += n + (p[n] == '|');
    }
    return -1;
}

/* The model's defaults for a format: "FORMAT:X,Y[,ERR][,log] ..." -> the fields of the entry. */
typedef struct {
    char x[96], y[96], err[96];
    int xlog;
} line_defaults;

static int defaults_for(const char *list, const char *format, line_defaults *d)
{
    memset(d, 0, sizeof *d);
    size_t fl = strlen(format);
    for (const char *p = list ? list : ""; *p;) {
        p += strspn(p, " ");
        size_t n = strcspn(p, " ");
        if (n > fl && strncmp(p, format, fl) == 0 && p[fl] == ':') {
            char entry[400];
            size_t m = n - fl - 1;
            if (m >= sizeof entry)
                return 0;
            memcpy(entry, p + fl + 1, m);
            entry[m] = '\0';
            char *field[4] = {d->x, d->y, d->err, NULL};
            int k = 0;
            for (char *sv = NULL, *tok = strtok_r(entry, ",", &sv); tok;
                 tok = strtok_r(NULL, ",", &sv), k++) {
                if (strcmp(tok, "log") == 0)
                    d->xlog = 1;
                else if (k < 3)
                    snprintf(field[k], sizeof d->x, "%s", tok);
            }
            return d->x[0] && d->y[0];
        }
        p += n;
    }
    return 0;
}

/* The column names of a table as "a, b, c" (for messages). */
static void col_list(const mote_table *t, char *buf, size_t cap)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int k = 0; k < t->ncolnames && used + 1 < cap; k++) {
        int w = snprintf(buf + used, cap - used, "%s%s", k ? ", " : "", t->colname[k]);
        if (w < 0 || (size_t)w >= cap - used) {
            if (cap > 4)
                memcpy(buf + cap - 4, "...", 4);
            break;
        }
        used += (size_t)w;
    }
}

/* The label of file i: the i-th of labels= ("a,b,c"), or the file's name without folder and
 * extension. */
static void label_of(const char *labels, int i, const char *path, char *buf, size_t cap)
{
    if (labels) {
        const char *p = labels;
        for (int k = 0; k < i; k++)
            p += strcspn(p, ",") + (p[strcspn(p, ",")] == ',');
        snprintf(buf, cap, "%.*s", (int)strcspn(p, ","), p);
        return;
    }
    const char *b = strrchr(path, '/');
    b = b ? b + 1 : path;
    const char *dot = strrchr(b, '.');
    snprintf(buf, cap, "%.*s", (int)(dot && dot != b ? (size_t)(dot - b) : strlen(b)), b);
}

static int count_labels(const char *labels)
{
    int n = 1;
    for (const char *p = labels; *p; p++)
        n += *p == ',';
    return n;
}

int mote_plot_lines_labels(const mote_call *c, int nin, mote_err *err)
{
    const mote_arg *labels = mote_call_opt(c, "labels");
    int ni = mote_call_opt_index(c, "labels");
    if (labels && count_labels(labels->text) != nin)
        return mote_call_fail(err, c, ni, MOTE_EINVAL,
                              "plot: labels= gives %d label%s for %d data file%s (one per file, "
                              "separated by commas)", count_labels(labels->text),
                              count_labels(labels->text) == 1 ? "" : "s", nin, nin == 1 ? "" : "s");
    return MOTE_OK;
}

int mote_plot_lines(const mote_call *c, int nin, const char *defaults, const char *png,
                    int check_only, mote_err *err)
{
    const mote_arg *xo = mote_call_opt(c, "x"), *yo = mote_call_opt(c, "y"),
                   *lo = mote_call_opt(c, "labels");
    int rc = mote_plot_lines_labels(c, nin, err);
    if (rc)
        return rc;
    mote_table *t = calloc((size_t)nin, sizeof *t);
    mote_series *series = calloc((size_t)nin, sizeof *series);
    double **xs = calloc((size_t)nin, sizeof *xs), **ys = calloc((size_t)nin, sizeof *ys),
           **es = calloc((size_t)nin, sizeof *es);
    char(*label)[128] = calloc((size_t)nin, sizeof *label);
    if (!t || !series || !xs || !ys || !es || !label) {
        rc = mote_call_fail(err, c, -1, MOTE_ENOMEM, "plot: out of memory");
        goto done;
    }
    line_defaults d = {0};
    char xname[96] = "", yname[96] = "", xfull[32] = "", yfull[32] = "";
    int any_err = 0;
    for (int i = 0; i < nin && !rc; i++) {
        const char *path = c->args[i].path;
        mote_err e2 = {0};
        if (mote_table_read(&t[i], path, &e2)) {
            rc = mote_call_fail(err, c, i, e2.code, "%s", e2.msg);
            break;
        }
        if (!t[i].format[0] && !mote_path_is_csv(path)) { /* (a CSV file keeps no format) */
            rc = mote_call_fail(err, c, i, MOTE_EFORMAT, "%s:1: not a mote data file (its first "
                                "line is not '# mote FORMAT 1')", path);
            break;
        }
        if (i == 0) {
            int have = defaults_for(defaults, t[0].format, &d);
            if ((!xo || !yo) && !have) {
                char cols[512];
                col_list(&t[0], cols, sizeof cols);
                rc = mote_call_fail(err, c, -1, MOTE_EINVAL,
                                    "plot: give x=COLUMN and y=COLUMN for a %s file such as %s "
                                    "(its columns: %s)", t[0].format, path, cols);
                break;
            }
            snprintf(xname, sizeof xname, "%s", xo ? xo->text : d.x);
            snprintf(yname, sizeof yname, "%s", yo ? yo->text : d.y);
        }
        if (i > 0 && (!xo || !yo) && strcmp(t[i].format, t[0].format) != 0) {
            rc = mote_call_fail(err, c, i, MOTE_EINVAL,
                                "plot: %s holds %s data and %s %s data: lines drawn by default "
                                "come from files of one kind (or give x= and y=)", path,
                                t[i].format, c->args[0].text, t[0].format);
            break;
        }
        char found[96];
        int xc = find_alt(&t[i], xname, found, sizeof found);
        int yc = find_alt(&t[i], yname, found, sizeof found);
        if (xc < 0 || yc < 0) {
            char cols[512];
            col_list(&t[i], cols, sizeof cols);
            int argi = xc < 0 ? mote_call_opt_index(c, "x") : mote_call_opt_index(c, "y");
            rc = mote_call_fail(err, c, argi >= 0 ? argi : i,
                                MOTE_EINVAL, "plot: %s has no column %s (its columns: %s)",
                                path, xc < 0 ? xname : yname, cols[0] ? cols : "none");
            break;
        }
        if (i == 0) {
            snprintf(xfull, sizeof xfull, "%s", t[i].colname[xc]);
            snprintf(yfull, sizeof yfull, "%s", t[i].colname[yc]);
        }
        /* the error bars: the defaults' column, or "<y>_err", or "sigma_<y>" */
        char base[96], alt[300];
        snprintf(base, sizeof base, "%.*s", (int)strcspn(t[i].colname[yc], "["), t[i].colname[yc]);
        snprintf(alt, sizeof alt, "%s%s%s_err|sigma_%s", !yo && d.err[0] ? d.err : "",
                 !yo && d.err[0] ? "|" : "", base, base);
        int ec = find_alt(&t[i], alt, found, sizeof found);
        /* the rows after the last "# columns:" line: the file's last block */
        int last = 0;
        for (size_t r = 0; r < t[i].rows; r++)
            last = t[i].block[r] > last ? t[i].block[r] : last;
        size_t n = 0;
        xs[i] = malloc((t[i].rows + 1) * sizeof **xs);
        ys[i] = malloc((t[i].rows + 1) * sizeof **ys);
        es[i] = ec >= 0 ? malloc((t[i].rows + 1) * sizeof **es) : NULL;
        if (!xs[i] || !ys[i] || (ec >= 0 && !es[i])) {
            rc = mote_call_fail(err, c, -1, MOTE_ENOMEM, "plot: out of memory");
            break;
        }
        for (size_t r = 0; r < t[i].rows; r++) {
            if (t[i].block[r] != last)
                continue;
            xs[i][n] = mote_table_at(&t[i], r, xc);
            ys[i][n] = mote_table_at(&t[i], r, yc);
            if (es[i])
                es[i][n] = mote_table_at(&t[i], r, ec);
            n++;
        }
        any_err |= es[i] != NULL;
        label_of(lo ? lo->text : NULL, i, path, label[i], sizeof label[i]);
        series[i] = (mote_series){.x = xs[i], .y = ys[i], .n = n, .label = label[i],
                                  .style = n <= 30 ? 2 : 0};
    }
    if (!rc && !check_only) {
        char title[128];
        snprintf(title, sizeof title, "%s against %s", yfull, xfull);
        mote_plot_opts o = {.title = title, .xlabel = xfull, .ylabel = yfull,
                            .xlog = d.xlog && !xo, .yerr = any_err ? (const double *const *)es
                                                                   : NULL};
        rc = mote_plot_png(png, &o, series, (size_t)nin, err);
        if (rc)
            rc = mote_call_fail(err, c, -1, err->code, "plot: %s", err->msg);
    }
done:
    for (int i = 0; t && i < nin; i++) {
        mote_table_free(&t[i]);
        if (xs)
            free(xs[i]);
        if (ys)
            free(ys[i]);
        if (es)
            free(es[i]);
    }
    free(t);
    free(series);
    free(xs);
    free(ys);
    free(es);
    free(label);
    return rc;
}
