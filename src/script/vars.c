/* vars.c: script variables. `set NAME VALUE` defines NAME for the lines after it, NAME=VALUE
 * after the script's name on the command line fixes it (a `set` of it then keeps that value),
 * and `${NAME}` in a word of a later line is replaced by its value; `${EXPR}` is arithmetic on
 * numbers and variables (+ - * / ^, parentheses), written back with 15 significant digits
 * (as a calculator shows them: ${0.1*3} is 0.3). The replacement happens inside the word: a value never splits
 * a word in two. `$$` writes one `$`. Expansion happens as the script is read, so the
 * whole-script check sees the values. */
#include "script_internal.h"

#include <math.h>
#include <stdint.h>
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

/* The variables by name: open addressing over s->vhash (index + 1; 0 empty), rebuilt at twice
 * the size when half full, so `set` and `${NAME}` cost the same with 40 000 variables as with 4. */
static uint64_t name_hash(const char *name, size_t n)
{
    uint64_t h = 1469598103934665603ull; /* FNV-1a */
    for (size_t k = 0; k < n; k++)
        h = (h ^ (unsigned char)name[k]) * 1099511628211ull;
    return h;
}

mote_var *mote_vars_find(mote_script *s, const char *name, size_t n)
{
    if (!s->vhcap)
        return NULL;
    for (size_t k = (size_t)name_hash(name, n) & (size_t)(s->vhcap - 1);; k = (k + 1) & (size_t)(s->vhcap - 1)) {
        const int i = s->vhash[k];
        if (i == 0)
            return NULL;
        mote_var *v = &s->vars[i - 1];
        if (strlen(v->name) == n && memcmp(v->name, name, n) == 0)
            return v;
    }
}

static int vhash_put(mote_script *s, int index)
{
    if (2 * (s->nvars + 1) > s->vhcap) {
        const int cap = s->vhcap ? 2 * s->vhcap : 64;
        int *h = calloc((size_t)cap, sizeof *h);
        if (!h)
            return -1;
        free(s->vhash);
        s->vhash = h;
        s->vhcap = cap;
        for (int k = 0; k < s->nvars; k++)
            if (k != index && vhash_put(s, k))
                return -1;
    }
    const char *name = s->vars[index].name;
    size_t k = (size_t)name_hash(name, strlen(name)) & (size_t)(s->vhcap - 1);
    while (s->vhash[k])
        k = (k + 1) & (size_t)(s->vhcap - 1);
    s->vhash[k] = index + 1;
    return 0;
}

const char *mote_var_value_bad(const char *value)
{
    for (const unsigned char *p = (const unsigned char *)value; *p; p++)
        if ((*p < 0x20 && *p != '\t') || *p == 0x7f)
            return *p == '\n' ? "a line break" : *p == '\r' ? "a carriage return"
                                                           : "a control character";
    return NULL;
}

int mote_vars_set(mote_script *s, const char *name, const char *value, int fixed)
{
    mote_var *v = mote_vars_find(s, name, strlen(name));
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
        mote_var *w = &s->vars[s->nvars];
        memset(w, 0, sizeof *w);
        w->name = mote_arena_strndup(&s->arena, name, strlen(name));
        if (!w->name || vhash_put(s, s->nvars))
            return -1;
        v = &s->vars[s->nvars++];
    }
    v->value = val;
    v->fixed = fixed;
    return 0;
}

/* ---- arithmetic ------------------------------------------------------------------------------ */

/* Parentheses, signs and function calls nest at most this deep (a person writes a few levels;
 * the bound keeps the recursion off the end of the stack). */
#define EXPR_DEPTH_MAX 200

typedef struct {
    mote_script *s;
    const char *p, *end;
    int depth;
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

/* One level deeper (0), or the error and -1. */
static int deeper(expr *e)
{
    if (++e->depth <= EXPR_DEPTH_MAX)
        return 0;
    fail(e, "nested more than 200 levels deep");
    return -1;
}

/* A number as the scripts write them: decimal, finite (no hexadecimal, inf or nan). */
static int read_number(const char *t, size_t n, double *v)
{
    char buf[64];
    if (n == 0 || n >= sizeof buf)
        return -1;
    for (size_t k = 0; k < n; k++)
        if (!strchr("0123456789.eE+-", t[k]) || t[k] == '\0')
            return -1;
    memcpy(buf, t, n);
    buf[n] = '\0';
    char *end;
    *v = strtod(buf, &end);
    return *end == '\0' && end != buf && isfinite(*v) ? 0 : -1;
}

static int is_name_char(char c, int first)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' ||
           (!first && c >= '0' && c <= '9');
}

/* The functions of ${...}: name, arguments, and the function of one or two of them. */
typedef struct {
    const char *name;
    int nargs;
    double (*f1)(double);
    double (*f2)(double, double);
} expr_fn;

static double fn_min(double a, double b) { return a < b ? a : b; }
static double fn_max(double a, double b) { return a > b ? a : b; }

static const expr_fn FUNCTIONS[] = {
    {"sqrt", 1, sqrt, NULL},   {"exp", 1, exp, NULL},      {"log", 1, log, NULL},
    {"log10", 1, log10, NULL}, {"sin", 1, sin, NULL},      {"cos", 1, cos, NULL},
    {"tan", 1, tan, NULL},     {"asin", 1, asin, NULL},    {"acos", 1, acos, NULL},
    {"atan", 1, atan, NULL},   {"abs", 1, fabs, NULL},     {"floor", 1, floor, NULL},
    {"ceil", 1, ceil, NULL},   {"round", 1, round, NULL},  {"atan2", 2, NULL, atan2},
    {"min", 2, NULL, fn_min},  {"max", 2, NULL, fn_max},   {"pow", 2, NULL, pow},
};

/* NAME(ARGS): e->p just after the '('. */
static double expr_call(expr *e, const char *name, size_t n)
{
    const expr_fn *fn = NULL;
    for (size_t k = 0; k < sizeof FUNCTIONS / sizeof *FUNCTIONS; k++)
        if (strlen(FUNCTIONS[k].name) == n && memcmp(FUNCTIONS[k].name, name, n) == 0)
            fn = &FUNCTIONS[k];
    char what[160];
    if (!fn) {
        snprintf(what, sizeof what, "unknown function '%.*s' (sqrt exp log log10 sin cos tan "
                 "asin acos atan atan2 abs floor ceil round min max pow)", (int)(n > 40 ? 40 : n),
                 name);
        return fail(e, what);
    }
    double a[2] = {0, 0};
    for (int k = 0; k < fn->nargs; k++) {
        if (k) {
            skip(e);
            if (e->p >= e->end || *e->p != ',') {
                snprintf(what, sizeof what, "%s takes %d arguments, separated by ','", fn->name,
                         fn->nargs);
                return fail(e, what);
            }
            e->p++;
        }
        a[k] = expr_sum(e);
    }
    skip(e);
    if (e->p >= e->end || *e->p != ')') {
        snprintf(what, sizeof what, "expected ')' after the %s of %s", fn->nargs == 1 ?
                 "argument" : "arguments", fn->name);
        return fail(e, what);
    }
    e->p++;
    return fn->nargs == 1 ? fn->f1(a[0]) : fn->f2(a[0], a[1]);
}

static double expr_atom(expr *e)
{
    skip(e);
    if (e->p >= e->end)
        return fail(e, "expected a number, a variable or '(' at the end");
    if (deeper(e))
        return NAN;
    double v;
    if (*e->p == '(') {
        e->p++;
        v = expr_sum(e);
        skip(e);
        if (e->p >= e->end || *e->p != ')')
            return fail(e, "expected ')'");
        e->p++;
        e->depth--;
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
        if (read_number(b, (size_t)(q - b), &v))
            return fail(e, "a malformed number");
        e->p = q;
        e->depth--;
        return v;
    }
    const char *q = b;
    while (q < e->end && is_name_char(*q, q == b))
        q++;
    if (q == b) {
        char what[64];
        snprintf(what, sizeof what, "unexpected '%c'", *b);
        return fail(e, what);
    }
    const size_t n = (size_t)(q - b);
    e->p = q;
    skip(e);
    if (e->p < e->end && *e->p == '(') { /* a function */
        e->p++;
        v = expr_call(e, b, n);
        e->depth--;
        return v;
    }
    mote_var *var = mote_vars_find(e->s, b, n);
    char what[160];
    const int shown = (int)(n > 60 ? 60 : n);
    if (!var && n == 2 && memcmp(b, "pi", 2) == 0) {
        e->depth--;
        return MOTE_PI;
    }
    if (!var) {
        snprintf(what, sizeof what, "undefined variable '%.*s%s'", shown, b, n > 60 ? "..." : "");
        return fail(e, what);
    }
    var->used = 1;
    if (read_number(var->value, strlen(var->value), &v)) {
        snprintf(what, sizeof what, "variable '%.*s' is '%.40s', not a number", shown, b,
                 var->value);
        return fail(e, what);
    }
    e->depth--;
    return v;
}

static double expr_unary(expr *e)
{
    skip(e);
    if (e->p < e->end && (*e->p == '-' || *e->p == '+')) {
        const int minus = *e->p++ == '-';
        if (deeper(e))
            return NAN;
        double v = expr_unary(e);
        e->depth--;
        return minus ? -v : v;
    }
    double v = expr_atom(e);
    skip(e);
    if (e->p < e->end && *e->p == '^') { /* right-associative, above the unary minus's operand */
        e->p++;
        if (deeper(e))
            return NAN;
        v = pow(v, expr_unary(e));
        e->depth--;
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
    if (x == floor(x) && fabs(x) <= 9007199254740992.0) /* whole numbers to 2^53: every digit */
        snprintf(buf, cap, "%.0f", x == 0 ? 0.0 : x); /* (-0 as 0) */
    else
        snprintf(buf, cap, "%.15g", x);
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
            mote_var *v = mote_var_name_ok(b, k) ? mote_vars_find(s, b, k) : NULL;
            if (v) {
                v->used = 1;
                add = v->value;
                len = strlen(v->value);
            } else if (mote_var_name_ok(b, k) && !(k == 2 && memcmp(b, "pi", 2) == 0)) {
                const int w = k > 60 ? 60 : (int)k; /* (a name of any length fits the message) */
                const char *more = k > 60 ? "..." : "";
                rc = mote_script_fail_at(err, file, line, col, MOTE_EINVAL,
                                         "undefined variable '%.*s%s' (define it with 'set %.*s%s "
                                         "VALUE' above, or give %.*s%s=VALUE after the script's "
                                         "name)", w, b, more, w, b, more, w, b, more);
                break;
            } else {
                expr e = {s, b, close, 0, ""};
                double x = expr_sum(&e);
                skip(&e);
                if (!e.why[0] && e.p < e.end)
                    fail(&e, "an operator (+ - * / ^) or the end expected");
                if (!e.why[0] && !isfinite(x))
                    fail(&e, "the result is not a finite number");
                if (e.why[0]) {
                    rc = mote_script_fail_at(err, file, line, col, MOTE_EINVAL,
                                             "in '${%.*s%s}': %s", k > 60 ? 60 : (int)k, b,
                                             k > 60 ? "..." : "", e.why);
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
