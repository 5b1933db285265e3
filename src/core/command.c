/* command.c: the helpers that command.h promises to models: resolving file names against the
 * script's output directory, checking during validation that an output file's directory will
 * exist, located error and warning messages for a command, and a progress line on a terminal.
 * Everything works on the values passed in; nothing is kept between calls. */
#include "mote/command.h"
#include "mote/h5md.h"
#include "mote/vtk.h"
#include "mote/statefile.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

char *mote_ctx_path(const mote_context *ctx, const char *name)
{
    const char *dir = ctx ? ctx->output_dir : "";
    size_t nd = strlen(dir), nn = strlen(name);
    if (nd == 0 || name[0] == '/') {
        char *p = malloc(nn + 1);
        if (p)
            memcpy(p, name, nn + 1);
        return p;
    }
    int slash = dir[nd - 1] != '/';
    char *p = malloc(nd + (size_t)slash + nn + 1);
    if (!p)
        return NULL;
    memcpy(p, dir, nd);
    if (slash)
        p[nd] = '/';
    memcpy(p + nd + (size_t)slash, name, nn + 1);
    return p;
}

/* Append component s[0..n) to out[0..*k), separated by '/' after `base`. */
static int push_component(char *out, size_t *k, size_t base, size_t cap, const char *s, size_t n)
{
    size_t sep = *k > base;
    if (*k + sep + n >= cap)
        return -1;
    if (sep)
        out[(*k)++] = '/';
    memcpy(out + *k, s, n);
    *k += n;
    return 0;
}

/* Lexical normal form of a directory name: no empty or "." components, "x/.." removed, no
 * trailing slash; "" is the current directory. Returns 0, or -1 if it does not fit. */
static int normalize_dir(const char *in, size_t len, char *out, size_t cap)
{
    size_t k = 0;
    if (cap < 2)
        return -1;
    int absolute = len > 0 && in[0] == '/';
    if (absolute)
        out[k++] = '/';
    const size_t base = k;
    for (size_t i = 0; i < len;) {
        while (i < len && in[i] == '/')
            i++;
        size_t j = i;
        while (j < len && in[j] != '/')
            j++;
        size_t n = j - i;
        if (n == 2 && in[i] == '.' && in[i + 1] == '.') {
            size_t last = k; /* start of the last component */
            while (last > base && out[last - 1] != '/')
                last--;
            int last_is_up = k - last == 2 && out[last] == '.' && out[last + 1] == '.';
            if (k > base && !last_is_up)
                k = last > base ? last - 1 : base;
            else if (!absolute && push_component(out, &k, base, cap, "..", 2))
                return -1;
        } else if (n > 0 && !(n == 1 && in[i] == '.')) {
            if (push_component(out, &k, base, cap, in + i, n))
                return -1;
        }
        i = j;
    }
    out[k] = '\0';
    return 0;
}

int mote_ctx_dir_ok(const mote_context *ctx, const char *path)
{
    if (mote_dir_of_exists(path))
        return 1;
    if (!ctx)
        return 0;
    const char *slash = strrchr(path, '/');
    char dir[4096], pending[4096];
    if (normalize_dir(path, slash ? (size_t)(slash - path) + (slash == path) : 0, dir,
                      sizeof dir))
        return 0;
    size_t n = strlen(dir);
    for (int i = 0; i < ctx->npending_dirs && i < 8; i++) {
        if (normalize_dir(ctx->pending_dirs[i], strlen(ctx->pending_dirs[i]), pending,
                          sizeof pending))
            continue;
        /* `output_dir` creates the directory and all its parents. */
        if (strncmp(pending, dir, n) == 0 && (pending[n] == '\0' || pending[n] == '/'))
            return 1;
    }
    return 0;
}

int mote_ctx_note_dir(mote_context *ctx, const char *dir)
{
    const int cap = (int)(sizeof ctx->pending_dirs / sizeof ctx->pending_dirs[0]);
    for (int i = 0; i < ctx->npending_dirs; i++)
        if (strcmp(ctx->pending_dirs[i], dir) == 0)
            return 0;
    if (ctx->npending_dirs >= cap || strlen(dir) >= sizeof ctx->pending_dirs[0])
        return -1;
    memcpy(ctx->pending_dirs[ctx->npending_dirs++], dir, strlen(dir) + 1);
    return 0;
}

int mote_call_fail(mote_err *err, const mote_call *c, int argi, mote_status code, const char *fmt,
                   ...)
{
    if (!err)
        return (int)code;
    int line = c->line, col = c->col;
    if (argi >= 0 && argi < c->nargs) {
        line = c->args[argi].line;
        col = c->args[argi].col;
    } else if (argi >= c->nargs && argi < c->nargs + c->nopts) { /* an option's value */
        line = c->opts[argi - c->nargs].value.line;
        col = c->opts[argi - c->nargs].value.col;
    }
    err->code = code;
    err->located = 1;
    int n = snprintf(err->msg, sizeof err->msg, "%s:%d:%d: error: ", c->file ? c->file : "?",
                     line, col);
    if (n < 0)
        n = 0;
    if ((size_t)n < sizeof err->msg) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg + n, sizeof err->msg - (size_t)n, fmt, ap);
        va_end(ap);
    }
    return (int)code;
}

/* "FILE:LINE:COL: KIND: <message>" to f */
static void located(FILE *f, const mote_call *c, const char *kind, const char *fmt, va_list ap)
{
    fprintf(f, "%s:%d:%d: %s: ", c->file ? c->file : "?", c->line, c->col, kind);
    vfprintf(f, fmt, ap);
    fputc('\n', f);
}

void mote_call_warn(const mote_call *c, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    located(c->ctx && c->ctx->diag ? c->ctx->diag : stderr, c, "warning", fmt, ap);
    va_end(ap);
}

void mote_call_note(const mote_call *c, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    located(c->ctx && c->ctx->out ? c->ctx->out : stdout, c, "note", fmt, ap);
    va_end(ap);
}

/* ---- progress ------------------------------------------------------------------------------- */

enum { PROGRESS_PAD = 40 }; /* room for the percentage and time after the label */

void mote_progress_begin(mote_progress *p, const mote_context *ctx, const char *label)
{
    p->enabled = ctx && ctx->terminal;
    p->shown = 0;
    p->run = 0;
    p->ctx = ctx;
    p->start = p->last = p->begun = p->enabled ? mote_wall_seconds() : 0.0;
    p->last_report = -1e300; /* (the first update reports) */
    p->last_interrupt = -1e300;
    snprintf(p->label, sizeof p->label, "%s", label ? label : "");
    const char *iv = getenv("MOTE_PROGRESS_INTERVAL");
    char *end = NULL;
    double v = iv && *iv ? strtod(iv, &end) : 0.25;
    p->interval = iv && *iv && end && !*end && v >= 0 && v <= 3600 ? v : 0.25;
}

/* "12 s", "5 min", "1.5 h" */
static void duration_text(char *buf, size_t cap, double seconds)
{
    if (seconds < 120.0)
        snprintf(buf, cap, "%.0f s", seconds);
    else if (seconds < 7200.0)
        snprintf(buf, cap, "%.0f min", seconds / 60.0);
    else
        snprintf(buf, cap, "%.1f h", seconds / 3600.0);
}

int mote_interrupted(mote_err *err, const char *command)
{
    return mote_fail(err, MOTE_EINTR, "%s: interrupted; it stopped at a safe point, and the "
                     "state is consistent (it can be saved or run on)", command);
}

int mote_progress_update(mote_progress *p, double fraction)
{
    int stop = 0;
    if (p->ctx && p->ctx->interrupt) {
        const double t = mote_wall_seconds();
        if (t - p->last_interrupt >= 0.05) {
            p->last_interrupt = t;
            stop = p->ctx->interrupt(p->ctx->interrupt_arg) != 0;
        }
    }
    if (p->ctx && p->ctx->tick)
        p->ctx->tick(p->ctx->tick_arg);
    if (p->ctx && p->ctx->report && !stop) { /* (stopping: nothing more to report) */
        double t = mote_wall_seconds();
        if (t - p->last_report >= p->interval) {
            p->last_report = t;
            p->ctx->report(p->ctx->report_arg, p->label, fraction < 0 ? 0 : fraction > 1 ? 1
                                                                                      : fraction);
        }
    }
    if (!p->enabled)
        return stop;
    double now = mote_wall_seconds();
    if (now - p->last < p->interval) /* at most four lines a second by default */
        return stop;
    p->last = now;
    p->shown = 1;
    if (!(fraction >= 0.0))
        fraction = 0.0;
    if (fraction > 1.0)
        fraction = 1.0;
    double elapsed = now - p->start;
    char head[96], left[48] = "", sofar[48] = "";
    if (p->run > 0)
        snprintf(head, sizeof head, "%s: run %d,", p->label, p->run);
    else
        snprintf(head, sizeof head, "%s", p->label);
    if (fraction > 0.0)
        duration_text(left, sizeof left, elapsed * (1.0 - fraction) / fraction);
    if (p->run > 0) /* the time left is this run's: the command's end is not known */
        duration_text(sofar, sizeof sofar, now - p->begun);
    if (fraction > 0.0 && p->run > 0)
        printf("\r%s %.1f%%  ~%s left in this run, %s so far   ", head, 100.0 * fraction, left,
               sofar);
    else if (fraction > 0.0)
        printf("\r%s %.1f%%  ~%s left   ", head, 100.0 * fraction, left);
    else
        printf("\r%s %.1f%%   ", head, 0.0);
    fflush(stdout);
    return stop;
}

void mote_progress_next_run(mote_progress *p)
{
    p->run++;
    if (p->enabled)
        p->start = mote_wall_seconds();
}

void mote_progress_clear(mote_progress *p)
{
    /* wipe a line that was printed, so the next output starts on a clean line */
    if (p->enabled && p->shown) {
        printf("\r%*s\r", (int)strlen(p->label) + PROGRESS_PAD + (p->run > 0 ? 48 : 0), "");
        fflush(stdout);
        p->shown = 0;
    }
}

void mote_progress_end(mote_progress *p)
{
    mote_progress_clear(p);
    p->enabled = 0;
}

/* ---- the files a script writes ------------------------------------------------------------------ */

void mote_outputs_free(mote_outputs *o)
{
    for (size_t k = 0; k < o->n; k++) {
        free(o->e[k].path);
        free(o->e[k].kind);
        free(o->e[k].stem);
        free(o->e[k].ext);
    }
    free(o->e);
    free(o->series);
    free(o->slot);
    memset(o, 0, sizeof *o);
}

static size_t path_hash(const char *s)
{
    uint64_t h = 1469598103934665603ull; /* FNV-1a */
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 1099511628211ull;
    return (size_t)h;
}

/* The slot of path: where it is, or the empty one where it would go. */
static size_t find_slot(const mote_outputs *o, const char *path)
{
    size_t k = path_hash(path) & (o->nslot - 1);
    while (o->slot[k] && strcmp(o->e[o->slot[k] - 1].path, path) != 0)
        k = (k + 1) & (o->nslot - 1);
    return k;
}

const char *mote_outputs_find(const mote_outputs *o, const char *path)
{
    if (!o->nslot)
        return NULL;
    const size_t k = find_slot(o, path);
    return o->slot[k] ? o->e[o->slot[k] - 1].kind : NULL;
}

/* Room for one more path in the index; -1 out of memory. */
static int index_grow(mote_outputs *o)
{
    if (2 * (o->n + 1) <= o->nslot)
        return 0;
    mote_outputs t = *o;
    t.nslot = o->nslot ? 2 * o->nslot : 64;
    t.slot = calloc(t.nslot, sizeof *t.slot);
    if (!t.slot)
        return -1;
    for (size_t k = 0; k < o->nslot; k++)
        if (o->slot[k])
            t.slot[find_slot(&t, o->e[o->slot[k] - 1].path)] = o->slot[k];
    free(o->slot);
    o->slot = t.slot;
    o->nslot = t.nslot;
    return 0;
}

static char *copy_string(const char *s)
{
    size_t len = strlen(s) + 1;
    char *copy = malloc(len);
    if (copy)
        memcpy(copy, s, len);
    return copy;
}

/* Is path one of the names of series e (its stem, digits, its ext)? */
static int in_series(const mote_output *e, const char *path)
{
    const size_t ns = strlen(e->stem), nx = strlen(e->ext), n = strlen(path);
    if (n <= ns + nx || strncmp(path, e->stem, ns) != 0 || strcmp(path + n - nx, e->ext) != 0)
        return 0;
    for (size_t k = ns; k < n - nx; k++)
        if (path[k] < '0' || path[k] > '9')
            return 0;
    return 1;
}

/* Room in *arr (of *cap elements of `size` bytes) for element n: doubled when full; -1 out of
 * memory. */
static int room_for(void **arr, size_t *cap, size_t n, size_t size)
{
    if (n < *cap)
        return 0;
    size_t want = *cap ? 2 * *cap : 16;
    void *p = realloc(*arr, want * size);
    if (!p)
        return -1;
    *arr = p;
    *cap = want;
    return 0;
}

/* Add an entry (stem and ext NULL for one file); MOTE_ENOMEM fails at argi. */
static int add_entry(mote_outputs *o, const mote_call *c, int argi, const char *path,
                     const char *kind, const char *stem, const char *ext, mote_err *err)
{
    if (index_grow(o) ||
        (stem && room_for((void **)&o->series, &o->capseries, o->nseries, sizeof *o->series)) ||
        room_for((void **)&o->e, &o->cap, o->n, sizeof *o->e))
        return mote_call_fail(err, c, argi, MOTE_ENOMEM, "out of memory");
    const size_t prev = o->nslot ? o->slot[find_slot(o, path)] : 0;
    mote_output e = {copy_string(path), copy_string(kind), stem ? copy_string(stem) : NULL,
                     ext ? copy_string(ext) : NULL, c->line, prev ? o->e[prev - 1].warned : 0};
    if (!e.path || !e.kind || (stem && !e.stem) || (ext && !e.ext)) {
        free(e.path);
        free(e.kind);
        free(e.stem);
        free(e.ext);
        return mote_call_fail(err, c, argi, MOTE_ENOMEM, "out of memory");
    }
    if (stem)
        o->series[o->nseries++] = o->n;
    o->e[o->n++] = e;
    o->slot[find_slot(o, e.path)] = o->n; /* (a path noted again: its latest entry) */
    return MOTE_OK;
}

int mote_outputs_note_path(mote_outputs *o, const mote_call *c, int argi, const char *path,
                           const char *kind, int repeat_ok, mote_err *err)
{
    if (!mote_ctx_dir_ok(c->ctx, path))
        return mote_call_fail(err, c, argi, MOTE_EIO,
                              "%s: the directory of output file '%s' does not exist", c->name,
                              path);
    const size_t prev = o->nslot ? o->slot[find_slot(o, path)] : 0;
    if (!repeat_ok && prev && !o->e[prev - 1].warned) { /* once a file: 10^5 saves, one line */
        mote_call_warn(c, "%s: '%s' is written more than once in this script; the last one wins "
                       "(later writes of it are not warned about)", c->name, path);
        o->e[prev - 1].warned = 1;
    }
    for (size_t q = 0; q < o->nseries; q++) {
        const mote_output *e = &o->e[o->series[q]];
        if (in_series(e, path)) {
            mote_call_warn(c, "%s: '%s' is also one of the numbered files (%s) of line %d",
                           c->name, path, e->kind, e->line);
            break;
        }
    }
    return add_entry(o, c, argi, path, kind, NULL, NULL, err);
}

int mote_outputs_note_series(mote_outputs *o, const mote_call *c, int argi, const char *prefix,
                             const char *ext, const char *kind, int flags, mote_err *err)
{
    char *first = mote_series_path(prefix, 0, 1, ext);
    if (!first)
        return mote_call_fail(err, c, argi, MOTE_ENOMEM, "out of memory");
    char *slash = strrchr(first, '/');
    /* the folder of a prefix= is made as dir='s is (issue 52): its parent must exist */
    const int makes_dir = (flags & MOTE_SERIES_MAKES_DIR) || slash;
    if (makes_dir && slash)
        *slash = '\0';
    int rc = MOTE_OK;
    if (makes_dir && slash && !mote_ctx_dir_ok(c->ctx, first))
        rc = mote_call_fail(err, c, argi, MOTE_EIO,
                            "%s: the directory that would hold '%s' does not exist", c->name,
                            first);
    else if (makes_dir && slash && !mote_dir_of_exists(prefix) && c->ctx)
        mote_ctx_note_dir(c->ctx, first); /* (files in it pass later checks; full: they fail) */
    else if (!makes_dir && !mote_ctx_dir_ok(c->ctx, first))
        rc = mote_call_fail(err, c, argi, MOTE_EIO,
                            "%s: the directory of the numbered files '%s' does not exist",
                            c->name, prefix);
    if (makes_dir && slash)
        *slash = '/';
    first[strlen(first) - 1 - strlen(ext)] = '\0'; /* the stem */
    const mote_output *latest = NULL; /* the latest series of this kind */
    for (size_t q = o->nseries; !rc && q-- > 0;)
        if (strcmp(o->e[o->series[q]].kind, kind) == 0) {
            latest = &o->e[o->series[q]];
            break;
        }
    const int continues = (flags & MOTE_SERIES_BY_STEP) ||
                          (latest && !strcmp(latest->stem, first) && !strcmp(latest->ext, ext));
    char ext_copy[32];
    snprintf(ext_copy, sizeof ext_copy, "%s", ext);
    const mote_output probe = {.stem = first, .ext = ext_copy}; /* this series */
    for (size_t k = 0; !rc && k < o->n; k++) { /* (few series a script: O(n) each is fine) */
        const mote_output *e = &o->e[k];
        if (e->stem ? !continues && !strcmp(e->stem, first) && !strcmp(e->ext, ext)
                    : in_series(&probe, e->path)) {
            if (e->stem)
                mote_call_warn(c, "%s: its numbered files start again from 0 and overwrite "
                               "those of line %d (%s*%s)", c->name, e->line, first, ext);
            else
                mote_call_warn(c, "%s: '%s', written by line %d, is also one of its numbered "
                               "files", c->name, e->path, e->line);
            break;
        }
    }
    if (!rc)
        rc = add_entry(o, c, argi, prefix, kind, first, ext, err);
    free(first);
    return rc;
}

char *mote_call_origin(const mote_call *c)
{
    size_t n = strlen(c->source) + strlen(c->file) + 64;
    char *s = malloc(n);
    if (s)
        snprintf(s, n, "%s   (%s:%d)", c->source, c->file, c->line);
    return s;
}

const mote_arg *mote_call_opt(const mote_call *c, const char *key)
{
    for (int k = 0; k < c->nopts; k++)
        if (strcmp(c->opts[k].key, key) == 0)
            return &c->opts[k].value;
    return NULL;
}

double mote_call_opt_r(const mote_call *c, const char *key, double dflt)
{
    const mote_arg *a = mote_call_opt(c, key);
    return a ? a->r : dflt;
}

int mote_call_word(const mote_call *c, const char *key, int dflt)
{
    const mote_arg *a = mote_call_opt(c, key);
    return a ? (int)a->i : dflt;
}

int mote_call_on(const mote_call *c, const char *key, int dflt)
{
    const mote_arg *a = mote_call_opt(c, key);
    return a ? a->i == 0 : dflt; /* (on|off: on is word 0) */
}

int mote_call_h5md(const mote_call *c, const char *file_key, int h5md_word, mote_err *err)
{
    const mote_arg *fmt = mote_call_opt(c, "format");
    const mote_arg *file = file_key ? mote_call_opt(c, file_key) : NULL;
    const int named = file && mote_path_is_h5md(file->text);
    if (!fmt)
        return named;
    const int h5md = fmt->i == h5md_word;
    if (file && h5md != named)
        return mote_call_fail(err, c, mote_call_opt_index(c, file_key), MOTE_EINVAL,
                              "%s: %s", c->name,
                              h5md ? "format=h5md writes H5MD: name the file FILE.h5 or FILE.h5md"
                                   : "a file named .h5 or .h5md is H5MD: give format=h5md or "
                                     "another name"),
               -1;
    return h5md;
}

int mote_call_vtk(const mote_call *c, const char *file_key, int vtk_word, mote_err *err)
{
    const mote_arg *fmt = mote_call_opt(c, "format");
    const mote_arg *file = file_key ? mote_call_opt(c, file_key) : NULL;
    const int named = file && mote_path_is_vtk(file->text);
    const int at = mote_call_opt_index(c, file_key ? file_key : "format");
    if (named && vtk_word < 0)
        return mote_call_fail(err, c, at, MOTE_EINVAL,
                              "%s: a VTK file holds one frame: write a series with snapshot "
                              "every=K prefix=P format=vtk (or a trajectory .xyz or .h5)",
                              c->name),
               -1;
    const int vtk = fmt ? vtk_word >= 0 && fmt->i == vtk_word : named;
    if (file && vtk != named)
        return mote_call_fail(err, c, at, MOTE_EINVAL, "%s: %s", c->name,
                              vtk ? "format=vtk writes VTK: name the file FILE.vtk"
                                  : "a file named .vtk is VTK: give format=vtk or another name"),
               -1;
    return vtk;
}

int mote_call_opt_index(const mote_call *c, const char *key)
{
    for (int k = 0; k < c->nopts; k++)
        if (strcmp(c->opts[k].key, key) == 0)
            return c->nargs + k;
    return -1;
}

/* ---- measurements of ensemble replicas -------------------------------------------------------- */

static int results_has(const mote_results *r, const char *name)
{
    for (size_t i = 0; i < r->n; i++)
        if (strcmp(r->name[i], name) == 0)
            return 1;
    return 0;
}

void mote_call_result(const mote_call *c, const char *key, double value)
{
    mote_results *r = c->ctx ? c->ctx->results : NULL;
    if (!r || r->failed)
        return;
    char base[64], name[64];
    snprintf(base, sizeof base, "%s.%s", c->name, key);
    for (char *p = base; *p; p++)
        if (*p == ' ')
            *p = '_'; /* (a row: "generate ring") */
    snprintf(name, sizeof name, "%s", base);
    for (int k = 2; results_has(r, name) && k < 1000000; k++)
        snprintf(name, sizeof name, "%.50s_%d", base, k);
    if (r->n == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 16;
        char(*nn)[64] = realloc(r->name, cap * sizeof *nn);
        if (nn)
            r->name = nn;
        double *nv = nn ? realloc(r->value, cap * sizeof *nv) : NULL;
        if (nv)
            r->value = nv;
        if (!nn || !nv) {
            r->failed = 1;
            return;
        }
        r->cap = cap;
    }
    memcpy(r->name[r->n], name, sizeof name);
    r->value[r->n++] = value;
}

void mote_results_free(mote_results *r)
{
    free(r->name);
    free(r->value);
    memset(r, 0, sizeof *r);
}

/* ---- arrays for other programs ------------------------------------------------------------- */

void mote_array_view(mote_array *a, const char *name, const char *unit, void *data, char type,
                     size_t n, size_t cols)
{
    const size_t size = type == 'i' ? sizeof(int) : sizeof(double);
    *a = (mote_array){.name = name, .unit = unit, .data = data, .type = type, .rows = n,
                      .cols = cols, .row_stride = (long)(cols * size), .col_stride = (long)size};
}

int mote_array_gather(mote_array *a, const char *name, const char *unit,
                      const double *const *columns, size_t ncols, size_t n, double scale)
{
    double *d = malloc((n ? n : 1) * ncols * sizeof *d);
    if (!d)
        return -1;
    for (size_t i = 0; i < n; i++)
        for (size_t k = 0; k < ncols; k++)
            d[i * ncols + k] = columns[k][i] * scale;
    mote_array_view(a, name, unit, d, 'd', n, ncols);
    a->owned = 1;
    return 0;
}

size_t mote_cmd_option_keys(const mote_cmd *c, char keys[][32], size_t cap)
{
    size_t n = 0;
    for (const char *p = c->args; p && *p && n < cap;) {
        while (*p == ' ')
            p++;
        const char *end = p;
        while (*end && *end != ' ')
            end++;
        const char *eq = memchr(p, '=', (size_t)(end - p));
        if (eq) {
            const char *k = *p == '@' ? p + 1 : p;
            size_t len = (size_t)(eq - k);
            if (len > 31)
                len = 31;
            memcpy(keys[n], k, len);
            keys[n++][len] = 0;
        }
        p = end;
    }
    return n;
}

int mote_vocabulary_option(const char *key)
{
    static const char *const shared[] = {"every", "dt", "file", "prefix", "format"};
    for (size_t k = 0; k < sizeof shared / sizeof shared[0]; k++)
        if (!strcmp(key, shared[k]))
            return 1;
    return 0;
}

/* ---- parameter commands bound to the state's descriptors ---------------------------------- */

int mote_cmd_set(void *model, const mote_call *c, mote_err *err)
{
    const mote_model *m = c->ctx ? c->ctx->model : NULL;
    const char *key = NULL;
    for (size_t q = 0; m && q < m->nparams && !key; q++)
        if (strcmp(m->params[q].command, c->name) == 0)
            key = m->params[q].key;
    const mote_sf_field *f = NULL;
    size_t n = 0;
    char *base = key && m->state ? m->state(model, &f, &n) : NULL;
    const size_t k = base ? mote_sf_find(f, n, key) : n;
    /* the value: the first argument, or the command's one option (`softening eps=E`) */
    const mote_arg *a = c->nargs >= 1 ? &c->args[0] : c->nopts == 1 ? &c->opts[0].value : NULL;
    if (!base || k == n || !a)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "%s: not bound to a value of the "
                              "model's state (a defect of the model's command table)", c->name);
    void *at = base + f[k].offset;
    if (f[k].type == MOTE_SF_DOUBLE) {
        const double v = a->r;
        memcpy(at, &v, sizeof v);
    } else if (f[k].type == MOTE_SF_CODEC) { /* (the model's number type, read from the text) */
        _Alignas(16) char tmp[64];
        if (f[k].codec->size > sizeof tmp || f[k].codec->get(a->text, tmp) == 0)
            return mote_call_fail(err, c, c->nargs >= 1 ? 0 : -1, MOTE_EINVAL,
                                  "%s: '%s' is not a value of its kind", c->name, a->text);
        memcpy(at, tmp, f[k].codec->size);
    } else if (f[k].type == MOTE_SF_INT || f[k].type == MOTE_SF_ENUM) {
        const int v = (int)a->i;
        memcpy(at, &v, sizeof v);
    } else {
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "%s: its value's type cannot be set by a "
                              "command (a defect of the model's command table)", c->name);
    }
    return MOTE_OK;
}
