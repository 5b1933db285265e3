/* datafile.c: results, and the writing and reading of mote's text data files (datafile.h). The
 * reader is what `plot` stands on in every model: it keeps the header's numbers by name, the
 * column names, and every row with its file line and block, and leaves the meaning of the rows
 * to the format's own code. It reads untrusted files: any byte sequence gives a table or an
 * error, never a crash, and memory grows with the file, never with a number inside it. */
#include "mote/datafile.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- results ---------------------------------------------------------------------------------- */

void mote_result_add(mote_result *res, const char *key, double value, double error)
{
    if (!res || res->n >= MOTE_RESULT_MAX)
        return;
    snprintf(res->kv[res->n].key, sizeof res->kv[0].key, "%s", key);
    res->kv[res->n].value = value;
    res->kv[res->n].error = error;
    res->n++;
}

const double *mote_result_get(const mote_result *res, const char *key, double *error)
{
    for (int k = 0; k < res->n; k++)
        if (strcmp(res->kv[k].key, key) == 0) {
            if (error)
                *error = res->kv[k].error;
            return &res->kv[k].value;
        }
    return NULL;
}

/* NaN as "nan" (a NaN made by 0/0 or sqrt(-x) has its sign bit set and prints as "-nan") */
static double nan_plain(double x) { return isnan(x) ? NAN : x; }

void mote_result_print(const mote_result *res, const char *label, FILE *out)
{
    if (!out)
        return;
    fprintf(out, "%s:", label);
    for (int k = 0; k < res->n; k++) {
        fprintf(out, " %s=%.8g", res->kv[k].key, nan_plain(res->kv[k].value));
        if (!isnan(res->kv[k].error))
            fprintf(out, " %s_err=%.3g", res->kv[k].key, res->kv[k].error);
    }
    fputc('\n', out);
}

void mote_result_write(const mote_result *res, FILE *f)
{
    for (int k = 0; k < res->n; k++)
        fprintf(f, "# %s = %.12g ± %.6g\n", res->kv[k].key, nan_plain(res->kv[k].value),
                nan_plain(res->kv[k].error));
}

/* ---- writing ---------------------------------------------------------------------------------- */

void mote_datafile_preamble(FILE *f, const char *format, const char *origin, uint64_t seed)
{
    fprintf(f, "# mote %s 1\n", format);
    fprintf(f, "# command: %s\n", origin ? origin : "(library call)");
    fprintf(f, "# program: mote %s; seed = %llu\n", MOTE_VERSION, (unsigned long long)seed);
}

int mote_datafile_open(mote_datafile *d, const char *path, const char *format, const char *origin,
                       uint64_t seed, mote_err *err)
{
    int rc = mote_afile_open(&d->af, path, err);
    if (rc) {
        d->f = NULL;
        return rc;
    }
    d->f = d->af.f;
    mote_datafile_preamble(d->f, format, origin, seed);
    return MOTE_OK;
}

void mote_datafile_columns(mote_datafile *d, const char *names)
{
    fprintf(d->f, "# columns: %s\n", names);
}

int mote_datafile_commit(mote_datafile *d, mote_err *err)
{
    d->f = NULL;
    return mote_afile_commit(&d->af, err);
}

void mote_datafile_abort(mote_datafile *d)
{
    d->f = NULL;
    mote_afile_abort(&d->af);
}

/* ---- CSV ---------------------------------------------------------------------------------------- */

int mote_path_is_csv(const char *path)
{
    size_t n = strlen(path);
    return n >= 4 && path[n - 4] == '.' && (path[n - 3] | 32) == 'c' && (path[n - 2] | 32) == 's' &&
           (path[n - 1] | 32) == 'v';
}

/* One field, quoted when it must be (RFC 4180, 2.6-2.7). */
static void csv_field(FILE *out, const char *s, size_t n, int first)
{
    if (!first)
        fputc(',', out);
    int quote = 0;
    for (size_t k = 0; k < n && !quote; k++)
        quote = s[k] == ',' || s[k] == '"' || s[k] == '\r' || s[k] == '\n';
    if (!quote) {
        fwrite(s, 1, n, out);
        return;
    }
    fputc('"', out);
    for (size_t k = 0; k < n; k++) {
        if (s[k] == '"')
            fputc('"', out);
        fputc(s[k], out);
    }
    fputc('"', out);
}

/* The fields of row s (separated by blanks; in a row without blanks, by commas: nbody's
 * format=csv rows) as one CSV record (after a leading "block" field when block >= 0). */
static void csv_record(FILE *out, const char *s, long block)
{
    int first = 1;
    if (block >= 0) {
        fprintf(out, "%ld", block);
        first = 0;
    }
    while (*s == ' ' || *s == '\t')
        s++;
    /* a row without blanks is one of comma-separated fields; otherwise blanks separate them and
     * a comma belongs to its field (a part name "a,b" is one field, quoted) */
    const char *seps = strpbrk(s, " \t") ? " \t" : ",";
    while (*s) {
        while (*s && strchr(seps, *s))
            s++;
        const char *b = s;
        while (*s && !strchr(seps, *s))
            s++;
        if (s > b) {
            csv_field(out, b, (size_t)(s - b), first);
            first = 0;
        }
    }
    fputs("\r\n", out);
}

static int blank(const char *s)
{
    while (*s == ' ' || *s == '\t')
        s++;
    return !*s;
}

/* The input is mote's own file, just written: its rows may be of any length (a trajectory row of
 * 10^5 bodies), so only memory bounds them. */
#define CSV_LINE_MAX ((size_t)1 << 40)

int mote_datafile_csv(const char *in_path, FILE *out, mote_err *err)
{
    /* pass 1: is it a data file, and how many blocks of rows does it hold? */
    mote_lines in;
    int rc = mote_lines_open(&in, in_path, err);
    if (rc)
        return rc;
    in.max = CSV_LINE_MAX;
    long blocks = 0;
    int datafile = 0, gap = 1;
    char *line;
    for (long k = 0; (line = mote_lines_next(&in)); k++) {
        if (k == 0)
            datafile = strncmp(line, "# mote ", 7) == 0;
        if (!datafile)
            break;
        if (line[0] == '#')
            continue;
        if (blank(line)) {
            gap = 1;
        } else if (gap) {
            blocks++;
            gap = 0;
        }
    }
    rc = mote_lines_close(&in, err);
    if (rc)
        return rc;
    /* pass 2: the header row and the records (or the file as it is) */
    rc = mote_lines_open(&in, in_path, err);
    if (rc)
        return rc;
    in.max = CSV_LINE_MAX;
    long block = -1;
    gap = 1;
    while ((line = mote_lines_next(&in))) {
        if (!datafile) {
            fputs(line, out);
            fputc('\n', out);
        } else if (strncmp(line, "# columns:", 10) == 0) {
            if (blocks > 1)
                fputs("block,", out);
            csv_record(out, line + 10, -1);
        } else if (line[0] == '#') {
            continue;
        } else if (blank(line)) {
            gap = 1;
        } else {
            if (gap)
                block++;
            gap = 0;
            csv_record(out, line, blocks > 1 ? block : -1);
        }
    }
    return mote_lines_close(&in, err);
}

/* ---- JSON lines ------------------------------------------------------------------------------ */

/* Is [s, s+n) a number in JSON's syntax: -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)? */
static int json_number(const char *s, size_t n)
{
    size_t k = 0;
    if (k < n && s[k] == '-')
        k++;
    if (k < n && s[k] == '0')
        k++;
    else if (k < n && s[k] >= '1' && s[k] <= '9')
        while (k < n && s[k] >= '0' && s[k] <= '9')
            k++;
    else
        return 0;
    if (k < n && s[k] == '.') {
        const size_t d = ++k;
        while (k < n && s[k] >= '0' && s[k] <= '9')
            k++;
        if (k == d)
            return 0;
    }
    if (k < n && (s[k] == 'e' || s[k] == 'E')) {
        k++;
        if (k < n && (s[k] == '+' || s[k] == '-'))
            k++;
        const size_t d = k;
        while (k < n && s[k] >= '0' && s[k] <= '9')
            k++;
        if (k == d)
            return 0;
    }
    return k == n;
}

/* A string in JSON: quoted, with '"', '\\' and control characters escaped. */
static void json_string(FILE *out, const char *s, size_t n)
{
    fputc('"', out);
    for (size_t k = 0; k < n; k++) {
        const unsigned char c = (unsigned char)s[k];
        if (c == '"' || c == '\\')
            fprintf(out, "\\%c", c);
        else if (c < 0x20)
            fprintf(out, "\\u%04x", c);
        else
            fputc(c, out);
    }
    fputc('"', out);
}

/* One value: a JSON number as written, another number to 17 digits, nan/inf null, a string. */
static void json_value(FILE *out, const char *s, size_t n)
{
    char buf[128];
    if (json_number(s, n)) {
        fwrite(s, 1, n, out);
        return;
    }
    if (n < sizeof buf) {
        memcpy(buf, s, n);
        buf[n] = '\0';
        char *end;
        const double x = strtod(buf, &end);
        if (end == buf + n && n > 0) {
            if (isfinite(x))
                fprintf(out, "%.17g", x);
            else
                fputs("null", out);
            return;
        }
    }
    json_string(out, s, n);
}

/* The next word at *p (blanks skipped), its length in *n, *p moved past it; NULL at the end. */
static const char *next_word(const char **p, size_t *n)
{
    const char *q = *p;
    while (*q == ' ' || *q == '\t')
        q++;
    if (!*q)
        return NULL;
    const char *b = q;
    while (*q && *q != ' ' && *q != '\t')
        q++;
    *n = (size_t)(q - b);
    *p = q;
    return b;
}

/* How many blocks of rows a data file holds (0: not a data file, or no rows). */
static int count_blocks(const char *in_path, long *blocks, mote_err *err)
{
    mote_lines in;
    int rc = mote_lines_open(&in, in_path, err);
    if (rc)
        return rc;
    in.max = CSV_LINE_MAX;
    int gap = 1;
    char *line;
    *blocks = 0;
    for (long k = 0; (line = mote_lines_next(&in)); k++) {
        if (k == 0 && strncmp(line, "# mote ", 7) != 0)
            break;
        if (line[0] == '#')
            continue;
        if (blank(line))
            gap = 1;
        else if (gap) {
            ++*blocks;
            gap = 0;
        }
    }
    return mote_lines_close(&in, err);
}

int mote_datafile_jsonl(const char *in_path, FILE *out, mote_err *err)
{
    long blocks = 0;
    int rc = count_blocks(in_path, &blocks, err);
    mote_lines in;
    if (rc || (rc = mote_lines_open(&in, in_path, err)))
        return rc;
    in.max = CSV_LINE_MAX;
    char *kind = NULL, *cols = NULL;
    int datafile = 0, gap = 1;
    long block = -1;
    char *line;
    for (long k = 0; (line = mote_lines_next(&in)); k++) {
        if (k == 0 && strncmp(line, "# mote ", 7) == 0) {
            datafile = 1;
            kind = strndup(line + 7, strcspn(line + 7, " "));
            continue;
        }
        if (!datafile) {
            fputs(line, out);
            fputc('\n', out);
        } else if (strncmp(line, "# columns:", 10) == 0) {
            free(cols);
            cols = strdup(line + 10);
        } else if (line[0] == '#') {
            continue;
        } else if (blank(line)) {
            gap = 1;
        } else {
            block += gap;
            gap = 0;
            fputs("{\"format\":", out);
            json_string(out, kind ? kind : "", kind ? strlen(kind) : 0);
            if (blocks > 1)
                fprintf(out, ",\"block\":%ld", block);
            /* the row's words beside the columns' names, however many (column_N past them) */
            const char *p = line, *c = cols ? cols : "", *w, *name;
            size_t n, nn = 0;
            for (size_t j = 1; (w = next_word(&p, &n)); j++) {
                fputc(',', out);
                if ((name = next_word(&c, &nn)))
                    json_string(out, name, nn);
                else
                    fprintf(out, "\"column_%zu\"", j);
                fputc(':', out);
                json_value(out, w, n);
            }
            fputs("}\n", out);
        }
    }
    free(kind);
    free(cols);
    return mote_lines_close(&in, err);
}

/* ---- reading ---------------------------------------------------------------------------------- */

#define TABLE_MAX_BYTES ((long)1 << 30)

void mote_table_free(mote_table *t)
{
    free(t->key);
    free(t->keyval);
    free(t->num);
    free(t->ncol);
    free(t->block);
    free(t->line);
    free(t->first);
    free(t->colname);
    memset(t, 0, sizeof *t);
}

double mote_table_key(const mote_table *t, const char *key)
{
    for (size_t k = t->nkeys; k-- > 0;) /* the last of repeated keys */
        if (strcmp(t->key[k], key) == 0)
            return t->keyval[k];
    return NAN;
}

int mote_table_has(const mote_table *t, const char *key)
{
    for (size_t k = 0; k < t->nkeys; k++)
        if (strcmp(t->key[k], key) == 0)
            return 1;
    return 0;
}

int mote_table_col(const mote_table *t, const char *name)
{
    for (int k = 0; k < t->ncolnames; k++)
        if (strcmp(t->colname[k], name) == 0)
            return k;
    return -1;
}

static int grow(void **p, size_t count, size_t size)
{
    void *q = realloc(*p, count * size);
    if (!q)
        return -1;
    *p = q;
    return 0;
}

/* "# key = number" (also "# key = number ± error": the value counts) */
static int add_key(mote_table *t, const char *line)
{
    char key[32];
    double v;
    int used = 0;
    if (sscanf(line, "# %31s = %lf%n", key, &v, &used) != 2 || strcmp(key, "columns:") == 0)
        return 0;
    if ((t->nkeys & (t->nkeys + 1)) == 0 || t->nkeys == 0) { /* capacity: powers of two */
        size_t cap = t->nkeys ? 2 * (t->nkeys + 1) : 16;
        if (grow((void **)&t->key, cap, sizeof *t->key) ||
            grow((void **)&t->keyval, cap, sizeof *t->keyval))
            return -1;
    }
    memcpy(t->key[t->nkeys], key, sizeof key);
    t->keyval[t->nkeys++] = v;
    return 0;
}

static int read_columns(mote_table *t, char *s)
{
    t->ncolnames = 0;
    if (!t->colname && !(t->colname = malloc(MOTE_TABLE_MAXCOL * sizeof *t->colname)))
        return -1;
    char *sv = NULL; /* (strtok_r: tables are read on several threads in an ensemble) */
    for (char *tok = strtok_r(s, " \t\r\n", &sv); tok && t->ncolnames < MOTE_TABLE_MAXCOL;
         tok = strtok_r(NULL, " \t\r\n", &sv))
        snprintf(t->colname[t->ncolnames++], sizeof t->colname[0], "%s", tok);
    return 0;
}

/* Make rows hold `width` numbers (moving the rows read so far; new places NaN). */
static int widen(mote_table *t, size_t width)
{
    if (t->cap && width * t->cap > MOTE_TABLE_MAXCELLS)
        return -2;
    double *p = malloc((t->cap ? t->cap : 1) * width * sizeof *p);
    if (!p)
        return -1;
    for (size_t r = 0; r < t->rows; r++)
        for (size_t c = 0; c < width; c++)
            p[r * width + c] = c < t->width ? t->num[r * t->width + c] : NAN;
    free(t->num);
    t->num = p;
    t->width = width;
    return 0;
}

/* Tokens of a row (the first MOTE_TABLE_MAXCOL of them count towards the width). */
static size_t count_tokens(const char *p)
{
    size_t n = 0;
    for (;;) {
        p += strspn(p, " \t\r\n");
        if (!*p)
            return n;
        n++;
        p += strcspn(p, " \t\r\n");
    }
}

/* Returns 0, -1 (out of memory) or -2 (beyond MOTE_TABLE_MAXCELLS). */
static int add_row(mote_table *t, const char *line, int block, long lineno)
{
    size_t ntok = count_tokens(line);
    size_t want = ntok < MOTE_TABLE_MAXCOL ? ntok : MOTE_TABLE_MAXCOL;
    if (want < 1)
        want = 1;
    if (want > t->width) {
        size_t w = t->width ? t->width : 1;
        while (w < want)
            w *= 2;
        int rc = widen(t, w < MOTE_TABLE_MAXCOL ? w : MOTE_TABLE_MAXCOL);
        if (rc)
            return rc;
    }
    if (t->rows == t->cap) {
        size_t cap = t->cap ? 2 * t->cap : 256;
        if (cap * t->width > MOTE_TABLE_MAXCELLS) {
            cap = MOTE_TABLE_MAXCELLS / t->width;
            if (cap <= t->rows)
                return -2;
        }
        if (grow((void **)&t->num, cap * t->width, sizeof *t->num) ||
            grow((void **)&t->ncol, cap, sizeof *t->ncol) ||
            grow((void **)&t->block, cap, sizeof *t->block) ||
            grow((void **)&t->line, cap, sizeof *t->line) ||
            grow((void **)&t->first, cap, sizeof *t->first))
            return -1;
        t->cap = cap;
    }
    double *row = t->num + t->rows * t->width;
    int n = 0;
    const char *p = line;
    t->first[t->rows][0] = '\0';
    sscanf(line, "%15s", t->first[t->rows]);
    for (;;) {
        p += strspn(p, " \t\r\n");
        if (!*p)
            break;
        char *end;
        double v = strtod(p, &end);
        if (end == p || (*end && !strchr(" \t\r\n", *end))) { /* a text token */
            v = NAN;
            end = (char *)p + strcspn(p, " \t\r\n");
        }
        if ((size_t)n < t->width)
            row[n] = v;
        n++;
        p = end;
    }
    for (size_t k = (size_t)n; k < t->width; k++)
        row[k] = NAN;
    t->ncol[t->rows] = n;
    t->block[t->rows] = block;
    t->line[t->rows] = lineno;
    t->rows++;
    return 0;
}

/* One CSV record (RFC 4180, on one line) as the words of a data file's line (malloc'ed; NULL out
 * of memory): fields separated by blanks, a quoted field unquoted ("" is "), blanks inside a
 * field as '_', an empty field "nan". */
static char *csv_words(const char *p)
{
    char *out = malloc(4 * strlen(p) + 8), *q = out;
    if (!out)
        return NULL;
    for (int field = 0;; field++) {
        if (field)
            *q++ = ' ';
        char *body = q;
        if (*p == '"') {
            for (p++; *p && !(*p == '"' && p[1] != '"'); p++) {
                if (*p == '"')
                    p++; /* ("" is one ") */
                *q++ = *p == ' ' || *p == '\t' ? '_' : *p;
            }
            if (*p == '"')
                p++;
        }
        for (; *p && *p != ',' && *p != '\r' && *p != '\n'; p++)
            *q++ = *p == ' ' || *p == '\t' ? '_' : *p;
        if (q == body) {
            memcpy(q, "nan", 3);
            q += 3;
        }
        if (*p != ',')
            break;
        p++;
    }
    *q = '\0';
    return out;
}

int mote_table_read(mote_table *t, const char *path, mote_err *err)
{
    memset(t, 0, sizeof *t);
    FILE *f = fopen(path, "r");
    if (!f)
        return mote_fail(err, MOTE_EIO, "cannot read '%s': %s", path, strerror(errno));
    const int csv = mote_path_is_csv(path);
    int csv_head = csv, csv_block = 0; /* a CSV file: its first record names the columns */
    char *line = NULL;
    size_t cap = 0;
    long lineno = 0, bytes = 0;
    int rc = MOTE_OK, block = 0, blank = 0;
    size_t len;
    int got;
    while ((got = mote_read_line(&line, &cap, &len, f, MOTE_LINE_MAX)) != 0) {
        lineno++;
        if (got < 0) {
            rc = got == -1 ? mote_fail(err, MOTE_EFORMAT, "%s:%ld: line longer than 1 MiB (not a "
                                       "text file?)", path, lineno)
                           : mote_fail(err, MOTE_ENOMEM, "out of memory reading '%s'", path);
            break;
        }
        bytes += (long)len;
        if (bytes > TABLE_MAX_BYTES) {
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: the file is larger than 1 GiB", path,
                           lineno);
            break;
        }
        if (strlen(line) != len) {
            rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: a NUL byte in the line (not a text file)",
                           path, lineno);
            break;
        }
        if (csv && line[0] != '#' && line[strspn(line, " \t\r\n")] != '\0') {
            /* a CSV record: the first names the columns, the others are rows (mote's CSV of a
             * file of several blocks starts each row with its block) */
            char *w = csv_words(line);
            if (!w) {
                rc = mote_fail(err, MOTE_ENOMEM, "out of memory reading '%s'", path);
                break;
            }
            int ar = 0;
            if (csv_head || (csv_block && strncmp(w, "block ", 6) == 0)) {
                /* (mote's CSV of blocks with columns of their own repeats the header row) */
                csv_head = 0;
                ar = read_columns(t, w) ? -1 : 0;
                csv_block = t->ncolnames > 0 && strcmp(t->colname[0], "block") == 0;
            } else {
                char *e;
                const double b = csv_block ? strtod(w, &e) : -1;
                ar = add_row(t, w, b >= 0 && b < 1e9 ? (int)b : block, lineno);
            }
            free(w);
            if (ar) {
                rc = ar == -2 ? mote_fail(err, MOTE_EFORMAT, "%s:%ld: too many numbers for a "
                                          "plot (more than %zu)", path, lineno,
                                          MOTE_TABLE_MAXCELLS)
                              : mote_fail(err, MOTE_ENOMEM, "out of memory reading '%s'", path);
                break;
            }
            continue;
        }
        if (line[0] == '#') {
            if (lineno == 1 && sscanf(line, "# mote %31s 1", t->format) != 1)
                t->format[0] = '\0';
            else if (strncmp(line, "# command: ", 11) == 0) {
                snprintf(t->command, sizeof t->command, "%s", line + 11);
                t->command[strcspn(t->command, "\r\n")] = '\0';
            } else if (strncmp(line, "# columns:", 10) == 0) {
                if (read_columns(t, line + 10)) {
                    rc = mote_fail(err, MOTE_ENOMEM, "out of memory reading '%s'", path);
                    break;
                }
            } else if (add_key(t, line)) {
                rc = mote_fail(err, MOTE_ENOMEM, "out of memory reading '%s'", path);
                break;
            }
            continue;
        }
        if (line[strspn(line, " \t\r\n")] == '\0') {
            blank = t->rows > 0;
            continue;
        }
        if (blank) {
            block++;
            blank = 0;
        }
        int ar = add_row(t, line, block, lineno);
        if (ar) {
            rc = ar == -2 ? mote_fail(err, MOTE_EFORMAT,
                                      "%s:%ld: too many numbers for a plot (more than %zu)", path,
                                      lineno, MOTE_TABLE_MAXCELLS)
                          : mote_fail(err, MOTE_ENOMEM, "out of memory reading '%s'", path);
            break;
        }
    }
    if (!rc && ferror(f))
        rc = mote_fail(err, MOTE_EIO, "cannot read '%s': %s", path, strerror(errno));
    free(line);
    fclose(f);
    if (rc)
        mote_table_free(t);
    return rc;
}
