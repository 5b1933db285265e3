/* vars.c: script variables. `set NAME VALUE` defines NAME for the lines after it, NAME=VALUE
 * after the script's name on the command line fixes it (a `set` of it then keeps that value),
 * and `${NAME}` in a word of a later line is replaced by its value; `${EXPR}` is arithmetic on
 * numbers and variables (+ - * / ^, parentheses), written back with 15 significant digits
 * (as a calculator shows them: ${0.1*3} is 0.3). The replacement happens inside the word: a value never splits
 * a word in two. `$$` writes one `$`. Expansion happens as the script is read, so the
 * whole-script check sees the values. */
#include "script_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int mote_var_name_ok(const char *s, size_t n)
{
    if (n == 0 || !((s[0] >= 'a' && s[0] <= 'z') || (s[0] >= 'A' && s[0] <= 'Z') || s[0] == '_'))
        return 0;
    for (size_t k = 1; k < n; k++)
        if (!((s[k] >= 'a' && s[k] <= 'z') || (s[k] >= 'A' && s[k] <= 'Z') || s[k] == '_' ||
              (s[k] >= '0' && s[k] <= '9')))
            return 0;
    return 1;
}

static mote_var *find(mote_script *s, const char *name, size_t n)
{
    for (int k = 0; k < s->nvars; k++)
        if (strlen(s->vars[k].name) == n && memcmp(s->vars[k].name, name, n) == 0)
            return &s->vars[k];
    return NULL;
}

int mote_vars_set(mote_script *s, const char *name, const char *value, int fixed)
{
    mote_var *v = find(s, name, strlen(name));
    if (v && v->fixed && !fixed)
        return 0; /* the command line's value stays */
    const char *val = mote_arena_strndup(&s->arena, value, strlen(value));
    if (!val)
        return -1;
    if (!v) {
        if (s->nvars == s->capvars) {
            int cap = s->capvars ? 2 * s->capvars : 16;
            mote_var *nv = realloc(s->vars, (size_t)cap * sizeof *nv);
            if (!nv)
                return -1;
            s->vars = nv;
            s->capvars = cap;
        }
        v = &s->vars[s->nvars++];
        memset(v, 0, sizeof *v);
        v->name = mote_arena_strndup(&s->arena, name, strlen(name));
        if (!v->name)
            return -1;
    }
    v->value = val;
    v->fixed = fixed;
    return 0;
}

/* ---- arithmetic ------------------------------------------------------------------------------ */

typedef struct {
    mote_script *s;
    const char *p, *end;
    char why[160]; /* the first error */
} expr;

static double expr_sum(expr *e);

static void skip(expr *e)
{
    while (e->p < e->end && (*e->p == ' ' || *e->p == '\t'))
        e->p++;
}

static double fail(expr *e, const char *what)
{
    if (!e->why[0])
        snprintf(e->why, sizeof e->why, "%s", what);
    e->p = e->end;
    return NAN;
}

/* A number as the scripts write them: decimal, finite (no hexadecimal, inf or nan). */
static int read_number(const char *t, size_t n, double *v)
{
    char buf[64];
    if (n == 0 || n >= sizeof buf || strspn(t, "0123456789.eE+-") < n)
        return -1;
    memcpy(buf, t, n);
    buf[n] = '\0';
    char *end;
    *v = strtod(buf, &end);
    return *end == '\0' && end != buf && isfinite(*v) ? 0 : -1;
}

static double expr_atom(expr *e)
{
    skip(e);
    if (e->p >= e->end)
        return fail(e, "expected a number, a variable or '(' at the end");
    if (*e->p == '(') {
        e->p++;
        double v = expr_sum(e);
        skip(e);
        if (e->p >= e->end || *e->p != ')')
            return fail(e, "expected ')'");
        e->p++;
        return v;
    }
    const char *b = e->p;
    if ((*b >= '0' && *b <= '9') || *b == '.') {
        /* digits, a point, an exponent with its sign */
        const char *q = b;
        while (q < e->end && ((*q >= '0' && *q <= '9') || *q == '.'))
            q++;
        if (q < e->end && (*q == 'e' || *q == 'E')) {
            const char *x = q + 1;
            if (x < e->end && (*x == '+' || *x == '-'))
                x++;
            if (x < e->end && *x >= '0' && *x <= '9') {
                q = x;
                while (q < e->end && *q >= '0' && *q <= '9')
                    q++;
            }
        }
        double v;
        if (read_number(b, (size_t)(q - b), &v))
            return fail(e, "a malformed number");
        e->p = q;
        return v;
    }
    const char *q = b;
    while (q < e->end && mote_var_name_ok(b, (size_t)(q - b + 1)))
        q++;
    if (q == b) {
        char what[64];
        snprintf(what, sizeof what, "unexpected '%c'", *b);
        return fail(e, what);
    }
    e->p = q;
    mote_var *v = find(e->s, b, (size_t)(q - b));
    char what[160];
    if (!v) {
        snprintf(what, sizeof what, "undefined variable '%.*s'", (int)(q - b), b);
        return fail(e, what);
    }
    v->used = 1;
    double x;
    if (read_number(v->value, strlen(v->value), &x)) {
        snprintf(what, sizeof what, "variable '%.*s' is '%.40s', not a number", (int)(q - b), b,
                 v->value);
        return fail(e, what);
    }
    return x;
}

static double expr_unary(expr *e)
{
    skip(e);
    if (e->p < e->end && (*e->p == '-' || *e->p == '+')) {
        const int minus = *e->p++ == '-';
        double v = expr_unary(e);
        return minus ? -v : v;
    }
    double v = expr_atom(e);
    skip(e);
    if (e->p < e->end && *e->p == '^') { /* right-associative, above the unary minus's operand */
        e->p++;
        v = pow(v, expr_unary(e));
    }
    return v;
}

static double expr_product(expr *e)
{
    double v = expr_unary(e);
    for (;;) {
        skip(e);
        if (e->p >= e->end || (*e->p != '*' && *e->p != '/'))
            return v;
        const int div = *e->p++ == '/';
        double w = expr_unary(e);
        v = div ? v / w : v * w;
    }
}

static double expr_sum(expr *e)
{
    double v = expr_product(e);
    for (;;) {
        skip(e);
        if (e->p >= e->end || (*e->p != '+' && *e->p != '-'))
            return v;
        const int minus = *e->p++ == '-';
        double w = expr_product(e);
        v = minus ? v - w : v + w;
    }
}

void mote_vars_format(double x, char *buf, size_t cap)
{
    snprintf(buf, cap, "%.15g", x == 0 ? 0.0 : x); /* (-0 as 0) */
}

/* ---- expansion ------------------------------------------------------------------------------- */

int mote_vars_expand(mote_script *s, const char *file, int line, int col, const char *text,
                     const char **out, mote_err *err)
{
    *out = text;
    if (!strchr(text, '$'))
        return 0;
    size_t cap = strlen(text) + 64, n = 0;
    char *buf = malloc(cap);
    if (!buf)
        return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    int rc = 0;
    for (const char *p = text; *p && !rc;) {
        char piece[160];
        const char *add = p;
        size_t len = 1;
        if (p[0] == '$' && p[1] == '$') {
            len = 1;
            p += 2;
        } else if (p[0] == '$' && p[1] == '{') {
            const char *close = strchr(p + 2, '}');
            if (!close) {
                rc = mote_script_fail_at(err, file, line, col, MOTE_EINVAL,
                                         "'${' without its '}' in '%.60s'", text);
                break;
            }
            const char *b = p + 2;
            const size_t k = (size_t)(close - b);
            mote_var *v = mote_var_name_ok(b, k) ? find(s, b, k) : NULL;
            if (v) {
                v->used = 1;
                add = v->value;
                len = strlen(v->value);
            } else if (mote_var_name_ok(b, k)) {
                rc = mote_script_fail_at(err, file, line, col, MOTE_EINVAL,
                                         "undefined variable '%.*s' (define it with 'set %.*s "
                                         "VALUE' above, or give %.*s=VALUE after the script's "
                                         "name)", (int)k, b, (int)k, b, (int)k, b);
                break;
            } else {
                expr e = {s, b, close, ""};
                double x = expr_sum(&e);
                skip(&e);
                if (!e.why[0] && e.p < e.end)
                    fail(&e, "an operator (+ - * / ^) or the end expected");
                if (!e.why[0] && !isfinite(x))
                    fail(&e, "the result is not a finite number");
                if (e.why[0]) {
                    rc = mote_script_fail_at(err, file, line, col, MOTE_EINVAL,
                                             "in '${%.*s}': %s", (int)k, b, e.why);
                    break;
                }
                mote_vars_format(x, piece, sizeof piece);
                add = piece;
                len = strlen(piece);
            }
            p = close + 1;
        } else {
            p++;
        }
        if (n + len + 1 > cap) {
            while (n + len + 1 > cap)
                cap *= 2;
            char *nb = cap <= MOTE_LINE_MAX * 4 ? realloc(buf, cap) : NULL;
            if (!nb) {
                rc = mote_script_fail_at(err, file, line, col, MOTE_EINVAL,
                                         "a word longer than 4 MiB after its variables");
                break;
            }
            buf = nb;
        }
        memcpy(buf + n, add, len);
        n += len;
    }
    if (!rc) {
        buf[n] = '\0';
        *out = mote_arena_strndup(&s->arena, buf, n);
        if (!*out)
            rc = mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    }
    free(buf);
    return rc;
}

void mote_script_unused_params(const mote_script *s, char *buf, size_t cap)
{
    size_t n = 0;
    buf[0] = '\0';
    for (int k = 0; k < s->nvars && n < cap; k++)
        if (s->vars[k].fixed && !s->vars[k].used) {
            int w = snprintf(buf + n, cap - n, "%s%s", n ? ", " : "", s->vars[k].name);
            n += w > 0 ? (size_t)w : 0;
        }
}
