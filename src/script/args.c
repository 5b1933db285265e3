/* args.c: the argument descriptions of command tables (mote_cmd.args, see command.h) and what the
 * script layer does with them: it reads each argument's type, range and file role, checks the
 * range and the files during validation (with messages that name the argument as the synopsis
 * does), and resolves file names against `output_dir`. A command's own `check` is left with what
 * depends on state that crosses commands. */
#include "script_internal.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static int is_type(int ch) { return ch && strchr("iurfsev", ch) != NULL; }

/* A number of a range bound: strtod syntax, at most 23 characters. */
static int read_bound(const char **pp, double *v, char *text, size_t cap)
{
    const char *p = *pp;
    size_t n = strcspn(p, ",]) {");
    char *end;
    if (n == 0 || n >= cap)
        return -1;
    memcpy(text, p, n);
    text[n] = '\0';
    *v = strtod(text, &end);
    if (end != text + n)
        return -1;
    *pp = p + n;
    return 0;
}

static int is_key_start(int ch)
{
    return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || ch == '_';
}
static int is_key_char(int ch) { return is_key_start(ch) || (ch >= '0' && ch <= '9'); }

/* The length of the option key at p ("mass" in "mass=r>0"), or 0 when p does not start one. */
size_t mote_option_key_len(const char *p)
{
    size_t n = 0;
    if (!is_key_start((unsigned char)p[0]))
        return 0;
    while (is_key_char((unsigned char)p[n]))
        n++;
    return p[n] == '=' ? n : 0;
}

static int parse_spec(const char **pp, mote_argspec *sp);

/* Parse the spec at *pp (one token: an optional KEY=, a type letter and its qualifier, for an
 * option an optional trailing '!') into sp; leaves *pp after it. Returns 0, or -1 when
 * malformed. */
static int parse_one(const char **pp, mote_argspec *sp)
{
    const char *p = *pp;
    const int at = *p == '@'; /* an option that may also be given as a bare token */
    p += at;
    size_t k = mote_option_key_len(p);
    if (!k)
        return at ? -1 : parse_spec(pp, sp);
    if (k >= sizeof sp->key)
        return -1;
    char tok[160];
    const char *v = p + k + 1;
    size_t n = strcspn(v, " ");
    if (n == 0 || n >= sizeof tok)
        return -1;
    memcpy(tok, v, n);
    tok[n] = '\0';
    int required = tok[n - 1] == '!';
    if (required)
        tok[n - 1] = '\0';
    const char *q = tok;
    if (parse_spec(&q, sp) || *q || sp->many)
        return -1;
    memcpy(sp->key, p, k);
    sp->key[k] = '\0';
    sp->required = required;
    sp->positional = at;
    *pp = v + n;
    return 0;
}

static int parse_spec1(const char **pp, mote_argspec *sp);

/* A positional spec (no key), or an option's: a trailing '+' ("f+") makes it many (one or
 * more arguments; only the last positional spec may be, see walk). */
static int parse_spec(const char **pp, mote_argspec *sp)
{
    const char *p = *pp;
    size_t n = strcspn(p, " ");
    if (n < 2 || p[n - 1] != '+')
        return parse_spec1(pp, sp);
    char tok[200];
    if (n >= sizeof tok)
        return -1;
    memcpy(tok, p, n - 1);
    tok[n - 1] = '\0';
    const char *q = tok;
    if (parse_spec1(&q, sp) || *q)
        return -1;
    sp->many = 1;
    *pp = p + n;
    return 0;
}

static int parse_spec1(const char **pp, mote_argspec *sp)
{
    const char *p = *pp;
    memset(sp, 0, sizeof *sp);
    if (!is_type(*p))
        return -1;
    sp->type = *p++;
    if (sp->type == 'v') { /* "v2", "v3" */
        if (*p != '2' && *p != '3')
            return -1;
        sp->count = *p++ - '0';
        if (*p != '\0' && *p != ' ')
            return -1;
        *pp = p;
        return 0;
    }
    if (sp->type != 'e' && (*p == '\0' || *p == ' ' || is_type(*p))) { /* plain letter */
        *pp = p;
        return 0;
    }
    size_t n = strcspn(p, " ");
    const char *end = p + n, *after = end;
    /* the words: "e{a|b}", or beside a number "r>0{auto}" */
    const char *brace = memchr(p, '{', n);
    if (brace) {
        size_t k = (size_t)(end - brace) - 2;
        if (end[-1] != '}' || k == 0 || k >= sizeof sp->words || sp->type == 'f' ||
            sp->type == 's' || strspn(brace + 1, "abcdefghijklmnopqrstuvwxyz0123456789_-|") < k)
            return -1;
        memcpy(sp->words, brace + 1, k);
        sp->words[k] = '\0';
        end = brace;
    } else if (sp->type == 'e') {
        return -1;
    }
    if (p == end) { /* (words only) */
        *pp = after;
        return 0;
    }
    if (sp->type == 'e')
        return -1;
    if (sp->type == 'f' && (*p == '>' || *p == '<')) {
        sp->role = *p++;
        size_t k = (size_t)(end - p);
        if (k == 0 || k >= sizeof sp->kinds || strspn(p, "abcdefghijklmnopqrstuvwxyz0123456789_|")
                                                    < k)
            return -1;
        memcpy(sp->kinds, p, k);
        sp->kinds[k] = '\0';
        if (sp->role == '>' && strchr(sp->kinds, '|'))
            return -1; /* an output has one kind */
        *pp = end;
        return 0;
    }
    if (sp->type == 'f' || sp->type == 's')
        return -1;
    if (*p == '[' || *p == '(') {
        sp->lo_set = sp->hi_set = 1;
        sp->lo_open = *p++ == '(';
        if (read_bound(&p, &sp->lo, sp->lo_text, sizeof sp->lo_text) || *p++ != ',')
            return -1;
        if (read_bound(&p, &sp->hi, sp->hi_text, sizeof sp->hi_text))
            return -1;
        if (*p != ']' && *p != ')')
            return -1;
        sp->hi_open = *p++ == ')';
        if (!(sp->lo <= sp->hi))
            return -1;
    } else if (*p == '>' || *p == '<') {
        int lower = *p++ == '>';
        int open = 1;
        if (*p == '=') {
            open = 0;
            p++;
        }
        double v;
        char text[sizeof sp->lo_text];
        if (read_bound(&p, &v, text, sizeof text))
            return -1;
        if (lower) {
            sp->lo_set = 1, sp->lo_open = open, sp->lo = v;
            memcpy(sp->lo_text, text, sizeof text);
        } else {
            sp->hi_set = 1, sp->hi_open = open, sp->hi = v;
            memcpy(sp->hi_text, text, sizeof text);
        }
    } else {
        return -1;
    }
    if (p != end)
        return -1;
    *pp = after;
    return 0;
}

/* Walk the specs: positional ones (opt = 0) or options (opt = 1). With index >= 0, the spec of
 * that index of its kind goes to *out; with key, the option of that key. Returns the number of
 * specs of the kind (index < 0 and no key), 0 when found, or -1 (malformed, or not found). */
static int walk(const char *args, int opt, int index, const char *key, mote_argspec *out)
{
    if (!args)
        return -1;
    if (strcmp(args, "*") == 0)
        return index < 0 && !key ? -2 : -1;
    int n = 0, seen_opt = 0, seen_many = 0;
    const char *p = args;
    for (;;) {
        while (*p == ' ')
            p++;
        if (!*p)
            return index < 0 && !key ? n : -1;
        mote_argspec sp;
        if (parse_one(&p, &sp))
            return -1;
        int is_opt = sp.key[0] != '\0';
        if (!is_opt && (seen_opt || seen_many))
            return -1; /* positional specs come first, and one of many comes last */
        seen_many |= sp.many;
        seen_opt |= is_opt;
        if (is_opt != opt)
            continue;
        if ((index >= 0 && n == index) || (key && strcmp(sp.key, key) == 0)) {
            *out = sp;
            return 0;
        }
        n++;
    }
}

int mote_argspec_count(const char *args) { return walk(args, 0, -1, NULL, NULL); }

int mote_argspec_get(const char *args, int index, mote_argspec *out)
{
    int rc = walk(args, 0, index, NULL, out);
    if (rc == -1 && index > 0) { /* beyond the last spec: it, when it takes many */
        int n = walk(args, 0, -1, NULL, NULL);
        if (n > 0 && n <= index && !walk(args, 0, n - 1, NULL, out) && out->many)
            return 0;
    }
    return rc;
}

int mote_argspec_many(const char *args)
{
    mote_argspec sp;
    int n = walk(args, 0, -1, NULL, NULL);
    return n > 0 && !walk(args, 0, n - 1, NULL, &sp) && sp.many;
}

int mote_argspec_noptions(const char *args)
{
    int n = walk(args, 1, -1, NULL, NULL);
    return n == -2 ? 0 : n;
}

int mote_argspec_option_at(const char *args, int index, mote_argspec *out)
{
    return walk(args, 1, index, NULL, out);
}

int mote_argspec_option(const char *args, const char *key, mote_argspec *out)
{
    return walk(args, 1, -1, key, out);
}

int mote_argspec_valid(const char *args)
{
    if (mote_argspec_count(args) == -1 || mote_argspec_noptions(args) < 0)
        return 0;
    /* no key twice */
    mote_argspec a, b;
    int n = mote_argspec_noptions(args);
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++)
            if (!mote_argspec_option_at(args, i, &a) && !mote_argspec_option_at(args, j, &b) &&
                strcmp(a.key, b.key) == 0)
                return 0;
    return 1;
}

/* The name of argument i as the synopsis gives it ("argument 3" when it has none). */
void mote_arg_name(const mote_cmd *def, int i, char *buf, size_t cap)
{
    const char *p = def->synopsis ? def->synopsis : "";
    const size_t nl = strlen(def->name); /* (a row's name has two words) */
    p += strncmp(p, def->name, nl) == 0 ? nl : strcspn(p, " ");
    for (int k = 0; *p; k++) {
        p += strspn(p, " ");
        size_t n = strcspn(p, " ");
        if (k == i && n > 0) {
            snprintf(buf, cap, "%.*s", (int)n, p);
            return;
        }
        p += n;
    }
    snprintf(buf, cap, "argument %d", i + 1);
}

/* ---- validation of one call ---------------------------------------------------------------- */

/* A call's arguments and options as one sequence of slots: slot u < nargs is positional argument
 * u, slot nargs + k is option k (the argi mote_call_fail locates). */
static int nslots(const mote_call *c) { return c->nargs + c->nopts; }

static mote_arg *slot_arg(const mote_call *c, int u)
{
    return (mote_arg *)(u < c->nargs ? &c->args[u] : &c->opts[u - c->nargs].value);
}

static int slot_spec(const mote_call *c, int u, mote_argspec *sp)
{
    return u < c->nargs ? mote_argspec_get(c->def->args, u, sp)
                        : mote_argspec_option(c->def->args, c->opts[u - c->nargs].key, sp);
}

static void slot_name(const mote_call *c, int u, char *buf, size_t cap)
{
    if (u < c->nargs)
        mote_arg_name(c->def, u, buf, cap);
    else
        snprintf(buf, cap, "%s", c->opts[u - c->nargs].key);
}

static int range_fail(mote_err *err, const mote_call *c, int i, const mote_argspec *sp)
{
    char name[64];
    slot_name(c, i, name, sizeof name);
    const char *found = slot_arg(c, i)->text;
    if (sp->lo_set && sp->hi_set)
        return mote_call_fail(err, c, i, MOTE_EINVAL, "%s: %s must be in %c%s, %s%c, found %s",
                              c->name, name, sp->lo_open ? '(' : '[', sp->lo_text, sp->hi_text,
                              sp->hi_open ? ')' : ']', found);
    if (sp->lo_set)
        return mote_call_fail(err, c, i, MOTE_EINVAL, "%s: %s must be %s %s, found %s", c->name,
                              name, sp->lo_open ? ">" : ">=", sp->lo_text, found);
    return mote_call_fail(err, c, i, MOTE_EINVAL, "%s: %s must be %s %s, found %s", c->name, name,
                          sp->hi_open ? "<" : "<=", sp->hi_text, found);
}

static int in_range(const mote_argspec *sp, const mote_arg *a)
{
    /* integers compare exactly where a double could round: bounds of integer specs are whole
     * numbers far below 2^53 in practice, and a value beyond 2^53 is compared as a double */
    double v = sp->type == 'r' ? a->r : sp->type == 'i' ? (double)a->i : (double)a->u;
    if (sp->lo_set && (sp->lo_open ? !(v > sp->lo) : !(v >= sp->lo)))
        return 0;
    if (sp->hi_set && (sp->hi_open ? !(v < sp->hi) : !(v <= sp->hi)))
        return 0;
    return 1;
}

/* The index of word w in "a|b|c", or -1 (the words of an argument spec, the kinds of a file). */
int mote_word_index(const char *words, const char *w)
{
    size_t n = strlen(w);
    int k = 0;
    for (const char *p = words; *p; k++) {
        size_t m = strcspn(p, "|");
        if (m == n && memcmp(p, w, n) == 0)
            return k;
        p += m;
        if (*p == '|')
            p++;
    }
    return -1;
}

/* "a, b or c" from "a|b|c" (quoted: "'a', 'b' or 'c'"). */
void mote_words_text(const char *words, int quoted, char *buf, size_t cap)
{
    const char *q = quoted ? "'" : "";
    size_t used = 0;
    buf[0] = '\0';
    for (const char *p = words; *p && used < cap;) {
        size_t m = strcspn(p, "|");
        const int last = p[m] == '\0';
        int w = snprintf(buf + used, cap - used, "%s%s%.*s%s",
                         used == 0 ? "" : last ? " or " : ", ", q, (int)m, p, q);
        if (w < 0)
            break;
        used += (size_t)w;
        p += m + !last;
    }
}

int mote_args_resolve(mote_call *c, mote_err *err)
{
    if (c->def->args[0] == '*')
        return MOTE_OK;
    for (int u = 0; u < nslots(c); u++) {
        mote_argspec sp;
        if (slot_spec(c, u, &sp) || sp.type != 'f')
            continue;
        mote_arg *a = slot_arg(c, u);
        free(a->path);
        a->path = mote_ctx_path(c->ctx, a->text);
        if (!a->path)
            return mote_call_fail(err, c, u, MOTE_ENOMEM, "out of memory");
    }
    return MOTE_OK;
}

int mote_args_check_input(const mote_call *c, int i, const char *kinds, mote_err *err)
{
    const mote_arg *a = slot_arg(c, i);
    const char *path = a->path ? a->path : a->text;
    const char *kind = mote_outputs_find(&c->ctx->outputs, path);
    struct stat st;
    if (kind && kinds && mote_word_index(kinds, kind) < 0) {
        char what[160];
        mote_words_text(kinds, 0, what, sizeof what);
        return mote_call_fail(err, c, i, MOTE_EINVAL,
                              "%s: '%s' is written earlier in this script as a file of kind %s; "
                              "expected a file of kind %s",
                              c->name, path, kind, what);
    }
    if (!kind && stat(path, &st) != 0)
        return mote_call_fail(err, c, i, MOTE_EIO,
                              "%s: '%s' does not exist and no earlier command writes it", c->name,
                              path);
    return MOTE_OK;
}

int mote_args_check_before(const mote_call *c, mote_err *err)
{
    if (c->def->args[0] == '*')
        return MOTE_OK;
    for (int u = 0; u < nslots(c); u++) {
        mote_argspec sp;
        if (slot_spec(c, u, &sp))
            return mote_call_fail(err, c, u, MOTE_EINVAL, "internal: bad argument types");
        if ((sp.lo_set || sp.hi_set) && !slot_arg(c, u)->word && !in_range(&sp, slot_arg(c, u)))
            return range_fail(err, c, u, &sp);
        if (sp.role == '<') {
            int rc = mote_args_check_input(c, u, sp.kinds, err);
            if (rc)
                return rc;
        }
    }
    return MOTE_OK;
}

int mote_args_check_after(const mote_call *c, mote_err *err)
{
    if (c->def->args[0] == '*')
        return MOTE_OK;
    for (int u = 0; u < nslots(c); u++) {
        mote_argspec sp;
        if (slot_spec(c, u, &sp))
            return mote_call_fail(err, c, u, MOTE_EINVAL, "internal: bad argument types");
        if (sp.role == '>') {
            int rc = mote_outputs_note_path(&c->ctx->outputs, c, u, slot_arg(c, u)->path,
                                            sp.kinds, 0, err);
            if (rc)
                return rc;
        }
    }
    return MOTE_OK;
}
