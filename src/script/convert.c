/* convert.c: one argument of a script command converted by its table type letter (integers,
 * real numbers, words of an enumeration, file names and their kinds), with the FILE:LINE:COL
 * message naming the command, the expected form and what was found (parse.c calls it). */
#include "script_internal.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static int is_continuation(int c) { return (c & 0xC0) == 0x80; }

/* ---- argument conversion -------------------------------------------------------------------- */

/* The value as shown in messages: quoted as found, long values shortened. */
/* Length of the valid UTF-8 sequence at s (at most n bytes), 0 when it is not one. */
static size_t utf8_len(const unsigned char *s, size_t n)
{
    size_t len = s[0] < 0x80 ? 1 : (s[0] & 0xE0) == 0xC0 ? 2 : (s[0] & 0xF0) == 0xE0 ? 3
                                  : (s[0] & 0xF8) == 0xF0 ? 4 : 0;
    if (!len || len > n || (len == 2 && s[0] < 0xC2))
        return 0;
    for (size_t k = 1; k < len; k++)
        if (!is_continuation(s[k]))
            return 0;
    return len;
}

/* A token for a message: quoted as written, at most 60 bytes of it, with bytes that are not
 * valid UTF-8 (or are control characters) written as \xNN so that a terminal shows them. */
const char *mote_script_shown(const token *t, char *buf, size_t cap)
{
    const unsigned char *p = (const unsigned char *)t->text;
    const size_t max = 60, n = strlen(t->text);
    const char q = t->quoted ? '"' : '\'';
    size_t k = 0, i = 0;
    buf[k++] = q;
    while (i < n && i < max && k + 8 < cap) {
        size_t len = utf8_len(p + i, n - i);
        if (len == 1 && p[i] < 0x20)
            len = 0;
        if (len == 0) {
            k += (size_t)snprintf(buf + k, cap - k, "\\x%02X", p[i]);
            i++;
        } else {
            if (i + len > max || k + len + 5 >= cap)
                break;
            memcpy(buf + k, p + i, len);
            k += len;
            i += len;
        }
    }
    if (i < n)
        k += (size_t)snprintf(buf + k, cap - k, "...");
    snprintf(buf + k, cap - k, "%c", q);
    return buf;
}

/* The name of a positional argument (from the synopsis) or an option (its key). */
static void arg_label(const mote_cmd *def, int i, const char *optkey, char *buf, size_t cap)
{
    if (optkey)
        snprintf(buf, cap, "%s", optkey);
    else
        mote_arg_name(def, i, buf, cap);
}

static int is_digit(int c) { return c >= '0' && c <= '9'; }

/* Decimal digits with an optional '+'. 0 ok, 1 not an integer, 2 negative, 3 too large. */
static int parse_unsigned(const char *t, uint64_t max, uint64_t *out)
{
    const char *p = t;
    int negative = 0;
    if (*p == '+')
        p++;
    else if (*p == '-') {
        negative = 1;
        p++;
    }
    if (!*p)
        return 1;
    for (const char *q = p; *q; q++)
        if (!is_digit(*q))
            return 1;
    if (negative)
        return 2;
    uint64_t v = 0;
    for (; *p; p++) {
        unsigned d = (unsigned)(*p - '0');
        if (v > (max - d) / 10)
            return 3;
        v = v * 10 + d;
    }
    *out = v;
    return 0;
}

/* A finite decimal real: [+-] (digits [. digits] | . digits) [(e|E) [+-] digits].
 * 0 ok, 1 not a real, 2 out of range. */
static int parse_real(const char *t, double *out)
{
    const char *p = t;
    if (*p == '+' || *p == '-')
        p++;
    size_t mant = 0;
    while (is_digit(*p)) {
        p++;
        mant++;
    }
    if (*p == '.') {
        p++;
        while (is_digit(*p)) {
            p++;
            mant++;
        }
    }
    if (mant == 0)
        return 1;
    if (*p == 'e' || *p == 'E') {
        p++;
        if (*p == '+' || *p == '-')
            p++;
        if (!is_digit(*p))
            return 1;
        while (is_digit(*p))
            p++;
    }
    if (*p)
        return 1;
    char *end;
    double v = strtod(t, &end);
    if (*end || !isfinite(v))
        return 2;
    *out = v;
    return 0;
}

static int to_lower(int c) { return c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c; }

/* Does s contain w, ignoring the case of s? (w is lower-case) */
int mote_script_contains_ci(const char *s, const char *w)
{
    size_t n = strlen(w);
    for (; *s; s++) {
        size_t k = 0;
        while (k < n && s[k] && to_lower((unsigned char)s[k]) == w[k])
            k++;
        if (k == n)
            return 1;
    }
    return 0;
}

/* Why a token that is not a real number was rejected, when the reason is a common one. */
static const char *real_hint(const char *t)
{
    if (mote_script_contains_ci(t, "nan") || mote_script_contains_ci(t, "inf"))
        return " (infinities and NaN are not accepted)";
    if (mote_script_contains_ci(t, "0x"))
        return " (hexadecimal is not accepted)";
    if (strchr(t, ',') && !strchr(t, '.'))
        return " (the decimal point is '.')";
    return "";
}

/* Convert token t by spec sp (optkey: the option's key, NULL for positional argument i). */
int mote_script_convert_arg(mote_script *s, const mote_cmd *def, const char *written, int i,
                            const char *optkey, const token *t, mote_arg *a, mote_err *err)
{
    const char *file = s->ctx.script_path;
    char name[64], found[80];
    a->text = t->text;
    a->line = t->line;
    a->col = t->col;
    a->quoted = t->quoted;
    a->i = 0;
    a->u = 0;
    a->r = 0.0;
    a->path = NULL;
    a->word = 0;
    mote_argspec sp = {.type = '*'};
    if (def->args[0] != '*' && (optkey ? mote_argspec_option(def->args, optkey, &sp)
                                       : mote_argspec_get(def->args, i, &sp)))
        return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                   "%s: internal: malformed argument types \"%s\"", written,
                                   def->args);
    char type = sp.type;
    char or_words[160] = "";
    if (sp.words[0])
        mote_words_text(sp.words, 1, or_words, sizeof or_words);
    if (sp.words[0]) {
        int k = t->quoted ? -1 : mote_word_index(sp.words, t->text);
        if (k >= 0) {
            a->i = k;
            a->word = k + 1;
            return 0;
        }
        if (type == 'e') {
            arg_label(def, i, optkey, name, sizeof name);
            mote_script_shown(t, found, sizeof found);
            if (strcmp(name, sp.words) == 0) /* (the synopsis names it by its one word) */
                return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                           "%s: expected %s, found %s", written, or_words, found);
            return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                       "%s: expected %s for %s, found %s", written, or_words, name,
                                       found);
        }
    }
    switch (type) {
    case 'i':
    case 'u': {
        /* an integer is a count the commands hold in an int: at most 2^31 - 1 unless its
         * table allows more ('u', seeds, takes any 64-bit value) */
        uint64_t max = type == 'u'                              ? UINT64_MAX
                       : sp.hi_set && sp.hi > (double)INT_MAX ? (uint64_t)INT64_MAX
                                                              : (uint64_t)INT_MAX;
        const char *what = type == 'i' ? "an integer" : "an unsigned integer";
        uint64_t v = 0;
        int rc = t->quoted ? 1 : parse_unsigned(t->text, max, &v);
        if (rc == 0) {
            a->u = v;
            a->i = v <= (uint64_t)INT64_MAX ? (int64_t)v : 0;
            a->r = (double)v;
            return 0;
        }
        arg_label(def, i, optkey, name, sizeof name);
        mote_script_shown(t, found, sizeof found);
        double dummy;
        if (rc == 2)
            return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                       "%s: expected a non-negative integer for %s, found %s",
                                       written, name, found);
        if (rc == 3)
            return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                       "%s: %s is too large (at most %llu), found %s", written,
                                       name, (unsigned long long)max, found);
        return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                   "%s: expected %s%s%s for %s, found %s%s", written, what,
                                   sp.words[0] ? " or " : "", or_words, name, found,
                                   t->quoted ? " (numbers are written without quotes)"
                                   : !parse_real(t->text, &dummy)
                                       ? " (an integer is written with digits only)"
                                       : "");
    }
    case 'r': {
        int rc = t->quoted ? 1 : parse_real(t->text, &a->r);
        if (rc == 0)
            return 0;
        arg_label(def, i, optkey, name, sizeof name);
        mote_script_shown(t, found, sizeof found);
        if (rc == 2)
            return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                       "%s: %s is out of the range of real numbers, found %s",
                                       written, name, found);
        return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                   "%s: expected a real number%s%s for %s, found %s%s", written,
                                   sp.words[0] ? " or " : "", or_words, name, found,
                                   t->quoted ? " (numbers are written without quotes)"
                                             : real_hint(t->text));
    }
    case 'v': {
        const char *q = t->text;
        int ok = !t->quoted;
        for (int k = 0; ok && k < sp.count; k++) {
            double x = 0;
            size_t n = strcspn(q, ",");
            char num[64];
            ok = n > 0 && n < sizeof num && (q[n] == ',') == (k + 1 < sp.count);
            if (ok) {
                memcpy(num, q, n);
                num[n] = '\0';
                ok = parse_real(num, &x) == 0;
            }
            if (ok)
                a->v[k] = x;
            q += n + (q[n] == ',');
        }
        if (ok && *q == '\0')
            return 0;
        arg_label(def, i, optkey, name, sizeof name);
        mote_script_shown(t, found, sizeof found);
        return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                   "%s: expected %s (%d finite numbers separated by commas) for "
                                   "%s, found %s", written, sp.count == 3 ? "X,Y,Z" : "X,Y",
                                   sp.count, name, found);
    }
    case 'f':
    case 's':
        if (t->text[0] == '\0' && (type == 'f' || !t->quoted)) {
            arg_label(def, i, optkey, name, sizeof name);
            return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                       "%s: expected %s for %s, found %s", written,
                                       type == 'f' ? "a file name" : "a value", name,
                                       t->quoted ? "an empty string" : "nothing");
        }
        return 0;
    default: /* '*' */
        return 0;
    }
}

/* The options of a call: each key declared, given at most once, its value converted by its spec
 * (the token after the '='); every required option given. */
int mote_script_convert_options(mote_script *s, const mote_cmd *def, const token *name,
                                const token *const *opt, int nopts, mote_opt **out,
                                mote_err *err)
{
    const char *file = s->ctx.script_path;
    mote_opt *opts = NULL;
    if (nopts > 0) {
        opts = mote_arena_alloc(&s->arena, (size_t)nopts * sizeof *opts);
        if (!opts)
            return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    }
    for (int k = 0; k < nopts; k++) {
        const token *t = opt[k];
        size_t klen = mote_option_key_len(t->text);
        char *key = mote_arena_strndup(&s->arena, t->text, klen);
        if (!key)
            return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
        mote_argspec sp;
        if (mote_argspec_option(def->args, key, &sp)) {
            mote_suggest sg;
            mote_suggest_init(&sg, key);
            char keys[512];
            size_t used = 0;
            keys[0] = '\0';
            for (int q = 0; q < mote_argspec_noptions(def->args); q++) {
                mote_argspec o;
                if (mote_argspec_option_at(def->args, q, &o))
                    continue;
                int w = snprintf(keys + used, sizeof keys - used, "%s%s", used ? ", " : "", o.key);
                if (w > 0 && (size_t)w < sizeof keys - used) {
                    /* the suggestion points into keys, which stays put */
                    mote_suggest_feed(&sg, keys + used + (used ? 2 : 0), strlen(o.key));
                    used += (size_t)w;
                }
            }
            char best[80];
            if (mote_suggest_result(&sg, best, sizeof best))
                return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                           "%s: unknown option '%s'; did you mean '%s'? (options: %s)",
                                           name->text, key, best, keys);
            return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                       "%s: unknown option '%s' (options: %s)", name->text, key,
                                       keys);
        }
        for (int q = 0; q < k; q++)
            if (strcmp(opts[q].key, key) == 0)
                return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                           "%s: option '%s' given twice", name->text, key);
        token v = *t;
        v.text = t->text + klen + 1;
        v.col = t->col + (int)klen + 1;
        opts[k].key = key;
        int rc = mote_script_convert_arg(s, def, name->text, -1, key, &v, &opts[k].value, err);
        if (rc)
            return rc;
    }
    for (int q = 0; q < mote_argspec_noptions(def->args); q++) {
        mote_argspec o;
        if (mote_argspec_option_at(def->args, q, &o) || !o.required)
            continue;
        int given = 0;
        for (int k = 0; k < nopts; k++)
            given |= strcmp(opts[k].key, o.key) == 0;
        if (!given)
            return mote_script_fail_at(err, file, name->line, name->col, MOTE_EINVAL,
                                       "%s: option %s= is required (%s)", name->text, o.key,
                                       def->synopsis ? def->synopsis : def->name);
    }
    *out = opts;
    return MOTE_OK;
}
