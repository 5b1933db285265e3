/* statefile.c: state files through descriptor tables (statefile.h): one writer and one strict
 * reader for every model's states and checkpoints. */
#include "mote/statefile.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static int present(const mote_sf_field *f, int version) { return f->since <= version; }
/* Does the descriptor give a range (lo <= hi, not both left at 0)? */
static int ranged(const mote_sf_field *f) { return f->lo <= f->hi && (f->lo != 0 || f->hi != 0); }
static int count_of(const mote_sf_field *f) { return f->count > 0 ? f->count : 1; }

/* The descriptors of the line that starts at f[0]: f[0] and the NULL-keyed ones after it. */
static size_t line_len(const mote_sf_field *f, size_t n)
{
    size_t k = 1;
    while (k < n && f[k].key == NULL)
        k++;
    return k;
}

static size_t type_size(const mote_sf_field *f)
{
    switch (f->type) {
    case MOTE_SF_DOUBLE:
        return sizeof(double);
    case MOTE_SF_INT:
    case MOTE_SF_ENUM:
        return sizeof(int);
    case MOTE_SF_U32:
        return sizeof(uint32_t);
    case MOTE_SF_I64:
    case MOTE_SF_U64:
    case MOTE_SF_HEX64:
        return sizeof(uint64_t);
    case MOTE_SF_WORD:
        return f->size;
    case MOTE_SF_CODEC:
        return f->codec->size;
    }
    return 0;
}

/* The enum word k of "a|b|c" into out (empty when there is none). */
static void enum_word(const char *words, int k, char out[64])
{
    const char *p = words;
    for (int i = 0; i < k && p; i++) {
        p = strchr(p, '|');
        p = p ? p + 1 : NULL;
    }
    size_t len = p ? strcspn(p, "|") : 0;
    snprintf(out, 64, "%.*s", (int)(len < 63 ? len : 63), p ? p : "");
}

/* ---- the exact double codec ------------------------------------------------------------------ */

void mote_sf_exact_put(char out[64], const void *value)
{
    mote_fmt_exact(out, *(const double *)value);
}

size_t mote_sf_exact_get(const char *text, void *value)
{
    char *end;
    errno = 0;
    const double x = strtod(text, &end);
    if (end == text || errno == ERANGE || !isfinite(x) ||
        strcspn(text, "xX") < (size_t)(end - text)) /* (no hexadecimal) */
        return 0;
    *(double *)value = x;
    return (size_t)(end - text);
}

const mote_sf_codec mote_sf_exact = {sizeof(double), mote_sf_exact_put, mote_sf_exact_get, NULL};

/* ---- writing --------------------------------------------------------------------------------- */

void mote_sf_write_head(FILE *out, const char *model, int version)
{
    fprintf(out, "mote-state %d\nmodel %s\n", version, model);
}

static void put_value(FILE *out, const mote_sf_field *f, const void *p)
{
    char b[64];
    switch (f->type) {
    case MOTE_SF_DOUBLE:
        fprintf(out, "%.17g", *(const double *)p);
        break;
    case MOTE_SF_INT:
        fprintf(out, "%d", *(const int *)p);
        break;
    case MOTE_SF_U32:
        fprintf(out, "%lu", (unsigned long)*(const uint32_t *)p);
        break;
    case MOTE_SF_I64:
        fprintf(out, "%lld", (long long)*(const int64_t *)p);
        break;
    case MOTE_SF_U64:
        fprintf(out, "%llu", (unsigned long long)*(const uint64_t *)p);
        break;
    case MOTE_SF_HEX64:
        fprintf(out, "%016llx", (unsigned long long)*(const uint64_t *)p);
        break;
    case MOTE_SF_ENUM:
        enum_word(f->words, *(const int *)p, b);
        fputs(b, out);
        break;
    case MOTE_SF_WORD:
        fputs(*(const char *)p ? (const char *)p : "-", out);
        break;
    case MOTE_SF_CODEC:
        f->codec->put(b, p);
        fputs(b, out);
        break;
    }
}

size_t mote_sf_find(const mote_sf_field *f, size_t n, const char *key)
{
    const char *dot = strchr(key, '.');
    const size_t len = dot ? (size_t)(dot - key) : strlen(key);
    size_t k = 0;
    while (k < n && !(f[k].key && strlen(f[k].key) == len && !strncmp(f[k].key, key, len)))
        k++;
    if (!dot || k == n)
        return k;
    for (size_t j = k; j < n && (j == k || !f[j].key); j++) /* (the line's values) */
        if (f[j].name && !strcmp(f[j].name, dot + 1))
            return j;
    return n;
}

void mote_sf_write(FILE *out, const mote_sf_field *f, size_t n, const void *base, int version)
{
    for (size_t i = 0; i < n;) {
        const size_t len = line_len(f + i, n - i);
        if (present(&f[i], version)) {
            int first = 1;
            if (f[i].key[0]) {
                fputs(f[i].key, out);
                first = 0;
            }
            for (size_t k = i; k < i + len; k++) {
                if (!present(&f[k], version))
                    continue;
                for (int c = 0; c < count_of(&f[k]); c++) {
                    if (!first)
                        fputc(' ', out);
                    first = 0;
                    put_value(out, &f[k],
                              (const char *)base + f[k].offset + (size_t)c * type_size(&f[k]));
                }
            }
            fputc('\n', out);
        }
        i += len;
    }
}

/* ---- reading --------------------------------------------------------------------------------- */

/* "KEY NAME1 NAME2 ..." of the line (the names of an array as NAME1 ... NAMEk): what a message
 * says was expected. */
static void expected_text(const mote_sf_field *f, size_t len, int version, char *out, size_t cap)
{
    size_t used = (size_t)snprintf(out, cap, "%s", f[0].key[0] ? f[0].key : "");
    for (size_t k = 0; k < len && used < cap; k++) {
        if (!present(&f[k], version))
            continue;
        int w = count_of(&f[k]) > 1
                    ? snprintf(out + used, cap - used, "%s%s[%d]", used ? " " : "", f[k].name,
                               count_of(&f[k]))
                    : snprintf(out + used, cap - used, "%s%s", used ? " " : "", f[k].name);
        used += w > 0 ? (size_t)w : 0;
    }
}

static const char *type_text(const mote_sf_field *f)
{
    switch (f->type) {
    case MOTE_SF_DOUBLE:
    case MOTE_SF_CODEC:
        return "a real number";
    case MOTE_SF_INT:
    case MOTE_SF_I64:
        return "an integer";
    case MOTE_SF_U32:
    case MOTE_SF_U64:
        return "a non-negative integer";
    case MOTE_SF_HEX64:
        return "16 hexadecimal digits";
    case MOTE_SF_ENUM:
        return "one of the words";
    case MOTE_SF_WORD:
        return "a word";
    }
    return "a value";
}

/* Read one value of f from the token at t (ending at a blank or the end) into p; 0 when the
 * token is not one, 1 when it is, 2 when it is out of range (its number into *v). */
static int get_value(const mote_sf_field *f, const char *t, size_t tlen, void *p, double *v)
{
    char tok[128];
    if (tlen == 0 || tlen >= sizeof tok)
        return 0;
    memcpy(tok, t, tlen);
    tok[tlen] = '\0';
    char *end = NULL;
    errno = 0;
    *v = NAN;
    switch (f->type) {
    case MOTE_SF_DOUBLE: {
        double d = strtod(tok, &end);
        if (*end || end == tok || isnan(d) || (isinf(d) && !(ranged(f) && isinf(f->hi))))
            return 0;
        *(double *)p = *v = d;
        break;
    }
    case MOTE_SF_INT: {
        long long x = strtoll(tok, &end, 10);
        if (*end || end == tok || errno || x < INT_MIN || x > INT_MAX)
            return 0;
        *(int *)p = (int)x;
        *v = (double)x;
        break;
    }
    case MOTE_SF_I64: {
        long long x = strtoll(tok, &end, 10);
        if (*end || end == tok || errno)
            return 0;
        *(int64_t *)p = (int64_t)x;
        *v = (double)x;
        break;
    }
    case MOTE_SF_U32:
    case MOTE_SF_U64: {
        if (tok[0] == '-' || tok[0] == '+')
            return 0;
        unsigned long long x = strtoull(tok, &end, 10);
        if (*end || end == tok || errno || (f->type == MOTE_SF_U32 && x > UINT32_MAX))
            return 0;
        if (f->type == MOTE_SF_U32)
            *(uint32_t *)p = (uint32_t)x;
        else
            *(uint64_t *)p = (uint64_t)x;
        *v = (double)x;
        break;
    }
    case MOTE_SF_HEX64: {
        if (tlen > 16 || strspn(tok, "0123456789abcdefABCDEF") != tlen)
            return 0;
        *(uint64_t *)p = (uint64_t)strtoull(tok, NULL, 16);
        return 1;
    }
    case MOTE_SF_ENUM: {
        char w[64];
        for (int k = 0;; k++) {
            enum_word(f->words, k, w);
            if (!w[0])
                return 0;
            if (strcmp(w, tok) == 0) {
                *(int *)p = k;
                return 1;
            }
        }
    }
    case MOTE_SF_WORD:
        if (tlen >= f->size)
            return 0;
        memcpy(p, tok, tlen + 1);
        if (strcmp(tok, "-") == 0)
            *(char *)p = '\0';
        return 1;
    case MOTE_SF_CODEC: {
        size_t used = f->codec->get(tok, p);
        if (used != tlen || (f->codec->finite && !f->codec->finite(p)))
            return 0;
        return 1;
    }
    }
    if (ranged(f) && !(*v >= f->lo && *v <= f->hi))
        return 2;
    return 1;
}

static const char *skip_blanks(const char *s)
{
    while (*s == ' ' || *s == '\t')
        s++;
    return s;
}

int mote_sf_parse_line(const mote_lines *in, const char *s, const mote_sf_field *f, size_t n,
                       void *base, int version, mote_err *err)
{
    const size_t len = line_len(f, n);
    char want[512]; /* (written only for a message) */
#define WANT (expected_text(f, len, version, want, sizeof want), want)
    const char *p = s;
    if (f[0].key[0]) {
        size_t k = strlen(f[0].key);
        if (!s || strncmp(s, f[0].key, k) != 0 || (s[k] != ' ' && s[k] != '\t' && s[k] != '\0'))
            return mote_fail(err, MOTE_EFORMAT, "%s:%ld: expected '%s' (found '%.60s')",
                             in->path, in->line, WANT, s ? s : "end of file");
        p = s + k;
    } else if (!s) {
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: expected a row '%s' (found 'end of file')",
                         in->path, in->line, WANT);
    }
    for (size_t k = 0; k < len; k++) {
        if (!present(&f[k], version))
            continue;
        for (int c = 0; c < count_of(&f[k]); c++) {
            p = skip_blanks(p);
            const size_t tlen = strcspn(p, " \t");
            char name[80];
            if (count_of(&f[k]) > 1)
                snprintf(name, sizeof name, "%s[%d]", f[k].name, c);
            else
                snprintf(name, sizeof name, "%s", f[k].name);
            if (tlen == 0 && f[k].optional && c == 0)
                goto end; /* (an older line: the rest keeps its values) */
            if (tlen == 0)
                return mote_fail(err, MOTE_EFORMAT, "%s:%ld: expected '%s': %s is missing "
                                 "(found '%.60s')", in->path, in->line, WANT, name, s);
            double v;
            void *dst = (char *)base + f[k].offset + (size_t)c * type_size(&f[k]);
            int got = get_value(&f[k], p, tlen, dst, &v);
            if (got == 0) {
                char words[128] = "";
                if (f[k].type == MOTE_SF_ENUM)
                    snprintf(words, sizeof words, " %s", f[k].words);
                return mote_fail(err, MOTE_EFORMAT, "%s:%ld: %s: expected %s%s, found '%.*s'",
                                 in->path, in->line, name, type_text(&f[k]), words,
                                 (int)(tlen < 40 ? tlen : 40), p);
            }
            if (got == 2)
                return mote_fail(err, MOTE_EFORMAT, "%s:%ld: %s must be in [%.17g, %.17g], "
                                 "found %.*s", in->path, in->line, name, f[k].lo, f[k].hi,
                                 (int)(tlen < 40 ? tlen : 40), p);
            p += tlen;
        }
    }
end:
    p = skip_blanks(p);
    if (*p)
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: unexpected text after '%s' ('%.40s')",
                         in->path, in->line, WANT, p);
    return MOTE_OK;
#undef WANT
}

int mote_sf_read(mote_lines *in, const mote_sf_field *f, size_t n, void *base, int version,
                 mote_err *err)
{
    for (size_t i = 0; i < n;) {
        const size_t len = line_len(f + i, n - i);
        if (present(&f[i], version)) {
            const char *s = mote_lines_next(in);
            if (!s)
                in->line++; /* (the line that is missing) */
            int rc = mote_sf_parse_line(in, s, f + i, len, base, version, err);
            if (rc)
                return rc;
        }
        i += len;
    }
    return MOTE_OK;
}

int mote_sf_read_head(mote_lines *in, const char *model, int vmax, int *version, mote_err *err)
{
    const char *s = mote_lines_next(in);
    char *end;
    long v = s && strncmp(s, "mote-state ", 11) == 0 ? strtol(s + 11, &end, 10) : -1;
    if (!s || v < 0 || *end)
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: expected 'mote-state %d' (found '%.60s')",
                         in->path, in->line + !s, vmax, s ? s : "end of file");
    if (v < 1 || v > vmax)
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: unsupported state file version %ld (this "
                         "mote reads 1 to %d)", in->path, in->line, v, vmax);
    *version = (int)v;
    s = mote_lines_next(in);
    if (!s || strncmp(s, "model ", 6) != 0 || strcmp(s + 6, model) != 0)
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: expected 'model %s' (a state of the %s "
                         "model; found '%.60s')", in->path, in->line + !s, model, model,
                         s ? s : "end of file");
    return MOTE_OK;
}
