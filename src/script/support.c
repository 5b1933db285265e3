/* support.c: small pieces the script layer shares: the arena that holds a parsed script's text,
 * command lookup by name or alias, "did you mean" suggestions by edit distance, and the
 * formatting of located error messages. */
#include "script_internal.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---- arena ---------------------------------------------------------------------------------- */

struct mote_arena_chunk {
    mote_arena_chunk *next;
    size_t used, cap;
    max_align_t data[];
};

enum { ARENA_CHUNK = 16384 };

void *mote_arena_alloc(mote_arena *a, size_t n)
{
    const size_t align = sizeof(max_align_t);
    if (n > SIZE_MAX / 2)
        return NULL;
    n = (n + align - 1) / align * align;
    if (n == 0)
        n = align;
    mote_arena_chunk *h = a->head;
    if (!h || h->cap - h->used < n) {
        size_t cap = n > ARENA_CHUNK ? n : ARENA_CHUNK;
        h = malloc(sizeof *h + cap);
        if (!h)
            return NULL;
        h->next = a->head;
        h->used = 0;
        h->cap = cap;
        a->head = h;
    }
    void *p = (unsigned char *)h->data + h->used;
    h->used += n;
    return p;
}

char *mote_arena_strndup(mote_arena *a, const char *s, size_t n)
{
    char *p = mote_arena_alloc(a, n + 1);
    if (!p)
        return NULL;
    memcpy(p, s, n);
    p[n] = '\0';
    return p;
}

void mote_arena_free(mote_arena *a)
{
    mote_arena_chunk *h = a->head;
    while (h) {
        mote_arena_chunk *next = h->next;
        free(h);
        h = next;
    }
    a->head = NULL;
}

/* ---- command lookup ------------------------------------------------------------------------- */

int mote_cmd_matches(const mote_cmd *def, const char *name)
{
    if (strcmp(def->name, name) == 0)
        return 1;
    size_t len = strlen(name);
    for (const char *p = def->aliases; p && *p;) {
        while (*p == ' ')
            p++;
        size_t n = strcspn(p, " ");
        if (n == len && n > 0 && memcmp(p, name, n) == 0)
            return 1;
        p += n;
    }
    return 0;
}

int mote_cmd_has_rows(const mote_cmd *cmds, size_t n, const char *name)
{
    const size_t len = strlen(name);
    for (size_t i = 0; i < n; i++)
        if (strncmp(cmds[i].name, name, len) == 0 && cmds[i].name[len] == ' ')
            return 1;
    return 0;
}

void mote_cmd_rows_text(const mote_cmd *cmds, size_t n, const char *name, char *buf, size_t cap)
{
    const size_t len = strlen(name);
    size_t used = 0, total = 0, k = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < n; i++)
        total += strncmp(cmds[i].name, name, len) == 0 && cmds[i].name[len] == ' ';
    for (size_t i = 0; i < n && used < cap; i++) {
        if (strncmp(cmds[i].name, name, len) != 0 || cmds[i].name[len] != ' ')
            continue;
        int w = snprintf(buf + used, cap - used, "%s%s", k == 0 ? "" : k + 1 == total ? " or " : ", ",
                         cmds[i].name + len + 1);
        used += w > 0 ? (size_t)w : 0;
        k++;
    }
}

const mote_cmd *mote_cmd_lookup(const mote_cmd *cmds, size_t n, const char *name)
{
    for (size_t i = 0; i < n; i++)
        if (mote_cmd_matches(&cmds[i], name))
            return &cmds[i];
    return NULL;
}

/* ---- suggestions ---------------------------------------------------------------------------- */

enum { SUGGEST_MAX = 64 }; /* longer words get no suggestion */

static int lower(int c) { return c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c; }

/* Optimal-string-alignment distance (Levenshtein plus adjacent transpositions), ignoring case. */
static int edit_distance(const char *a, size_t n, const char *b, size_t m)
{
    int rows[3][SUGGEST_MAX + 1];
    int *pp = rows[0], *prev = rows[1], *cur = rows[2];
    for (size_t j = 0; j <= m; j++)
        prev[j] = (int)j;
    for (size_t i = 1; i <= n; i++) {
        cur[0] = (int)i;
        for (size_t j = 1; j <= m; j++) {
            int cost = lower((unsigned char)a[i - 1]) != lower((unsigned char)b[j - 1]);
            int d = prev[j] + 1;
            if (cur[j - 1] + 1 < d)
                d = cur[j - 1] + 1;
            if (prev[j - 1] + cost < d)
                d = prev[j - 1] + cost;
            if (i > 1 && j > 1 && lower((unsigned char)a[i - 1]) == lower((unsigned char)b[j - 2]) &&
                lower((unsigned char)a[i - 2]) == lower((unsigned char)b[j - 1]) && pp[j - 2] + 1 < d)
                d = pp[j - 2] + 1;
            cur[j] = d;
        }
        int *t = pp;
        pp = prev;
        prev = cur;
        cur = t;
    }
    return prev[m];
}

void mote_suggest_init(mote_suggest *sg, const char *word)
{
    sg->word = word;
    sg->wlen = strlen(word);
    sg->best = NULL;
    sg->blen = 0;
    sg->bestd = 3;
}

void mote_suggest_feed(mote_suggest *sg, const char *cand, size_t len)
{
    if (len == 0 || len > SUGGEST_MAX || sg->wlen > SUGGEST_MAX)
        return;
    int d = edit_distance(sg->word, sg->wlen, cand, len);
    /* A distance as large as the word itself would suggest anything for short typos. */
    if (d < sg->bestd && (size_t)d < sg->wlen) {
        sg->bestd = d;
        sg->best = cand;
        sg->blen = len;
    }
}

void mote_suggest_feed_cmd(mote_suggest *sg, const mote_cmd *def)
{
    mote_suggest_feed(sg, def->name, strlen(def->name));
    for (const char *p = def->aliases; p && *p;) {
        while (*p == ' ')
            p++;
        size_t n = strcspn(p, " ");
        mote_suggest_feed(sg, p, n);
        p += n;
    }
}

int mote_suggest_result(const mote_suggest *sg, char *buf, size_t cap)
{
    if (!sg->best || cap == 0)
        return 0;
    size_t n = sg->blen < cap - 1 ? sg->blen : cap - 1;
    memcpy(buf, sg->best, n);
    buf[n] = '\0';
    return 1;
}

/* ---- errors --------------------------------------------------------------------------------- */

__attribute__((format(printf, 6, 0))) static int fail_v(mote_err *err, const char *file, int line,
                                                         int col, mote_status code,
                                                         const char *fmt, va_list ap)
{
    if (!err)
        return (int)code;
    err->code = code;
    err->located = 1;
    int n = snprintf(err->msg, sizeof err->msg, "%s:%d:%d: error: ", file, line, col);
    if (n < 0)
        n = 0;
    if ((size_t)n < sizeof err->msg)
        vsnprintf(err->msg + n, sizeof err->msg - (size_t)n, fmt, ap);
    return (int)code;
}

int mote_script_fail_at(mote_err *err, const char *file, int line, int col, mote_status code,
                        const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fail_v(err, file, line, col, code, fmt, ap);
    va_end(ap);
    return (int)code;
}

int mote_script_fail_plain(mote_err *err, mote_status code, const char *fmt, ...)
{
    if (!err)
        return (int)code;
    err->code = code;
    err->located = 0;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
    return (int)code;
}

void mote_script_locate(mote_err *err, const mote_call *c)
{
    if (err->code == MOTE_OK)
        err->code = MOTE_ERUNTIME;
    if (!err->located) {
        char msg[sizeof err->msg];
        memcpy(msg, err->msg, sizeof msg);
        msg[sizeof msg - 1] = '\0';
        if (msg[0] == '\0')
            snprintf(msg, sizeof msg, "%s: failed without a message", c->name);
        mote_script_fail_at(err, c->file, c->line, c->col, err->code, "%s", msg);
    }
    if (c->loop) /* which pass of the loops failed */
        mote_script_note_loop(err, c->loop);
}

void mote_script_note_loop(mote_err *err, const char *loop)
{
    const size_t n = strlen(err->msg);
    if (n < sizeof err->msg)
        snprintf(err->msg + n, sizeof err->msg - n, " (in the loop: %s)", loop);
}
