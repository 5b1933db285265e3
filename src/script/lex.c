/* lex.c: cuts a script line into tokens: spaces and tabs separate, `#` at a token start begins a
 * comment, double quotes group with \" and \\ as the only escapes. Columns count characters
 * (UTF-8 continuation bytes do not start a column). */
#include "script_internal.h"

#include <stdlib.h>
#include <string.h>

static int is_blank(int c) { return c == ' ' || c == '\t'; }
static int is_control(int c) { return (c < 0x20 && c != '\t') || c == 0x7f; }
static int is_continuation(int c) { return (c & 0xC0) == 0x80; }

static void advance(cursor *c)
{
    c->p++;
    if (c->p < c->end && !is_continuation((unsigned char)*c->p))
        c->col++;
}

static int fail_control(mote_err *err, const char *file, const cursor *c)
{
    unsigned char ch = (unsigned char)*c->p;
    if (ch == '\r')
        return mote_script_fail_at(err, file, c->line, c->col, MOTE_EINVAL,
                                   "stray carriage return (a CR not followed by LF)");
    return mote_script_fail_at(err, file, c->line, c->col, MOTE_EINVAL,
                               "unexpected control character (byte 0x%02x)", ch);
}

int mote_push_token(token_list *tl, token t)
{
    if (tl->n == tl->cap) {
        int cap = tl->cap ? 2 * tl->cap : 16;
        token *nt = realloc(tl->t, (size_t)cap * sizeof *nt);
        if (!nt)
            return -1;
        tl->t = nt;
        tl->cap = cap;
    }
    tl->t[tl->n++] = t;
    return 0;
}

/* Lex a quoted string starting at the opening quote; leaves *c after the closing quote. */
static int lex_quoted(mote_script *s, cursor *c, token *t, mote_err *err)
{
    const char *file = s->ctx.script_path;
    cursor scan = *c;
    size_t n = 0;
    advance(&scan);
    for (;;) {
        if (scan.p == scan.end)
            return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                       "unterminated quoted string (no closing '\"' on this line)");
        int ch = (unsigned char)*scan.p;
        if (ch == '"')
            break;
        if (ch == '\\') {
            cursor bs = scan;
            advance(&scan);
            if (scan.p == scan.end)
                return mote_script_fail_at(err, file, t->line, t->col, MOTE_EINVAL,
                                           "unterminated quoted string (no closing '\"' on this line)");
            int e = (unsigned char)*scan.p;
            if (e != '"' && e != '\\') {
                if (e > 0x20 && e < 0x7f)
                    return mote_script_fail_at(err, file, bs.line, bs.col, MOTE_EINVAL,
                                               "unknown escape '\\%c' in a quoted string "
                                               "(the only escapes are \\\" and \\\\)", e);
                return mote_script_fail_at(err, file, bs.line, bs.col, MOTE_EINVAL,
                                           "unknown escape in a quoted string "
                                           "(the only escapes are \\\" and \\\\)");
            }
        } else if (is_control(ch)) {
            return fail_control(err, file, &scan);
        }
        n++;
        advance(&scan);
    }
    char *text = mote_arena_alloc(&s->arena, n + 1);
    if (!text)
        return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    size_t k = 0;
    for (const char *p = c->p + 1; p < scan.p; p++) {
        if (*p == '\\')
            p++;
        text[k++] = *p;
    }
    text[k] = '\0';
    t->text = text;
    t->quoted = 1;
    advance(&scan); /* the closing quote */
    if (scan.p < scan.end && !is_blank(*scan.p))
        return mote_script_fail_at(err, file, scan.line, scan.col, MOTE_EINVAL,
                                   "expected a space after the closing quote");
    *c = scan;
    return 0;
}

int mote_lex_line(mote_script *s, cursor c, token_list *tl, mote_err *err)
{
    const char *file = s->ctx.script_path;
    tl->n = 0;
    tl->src_begin = tl->src_end = NULL;
    for (;;) {
        while (c.p < c.end && is_blank(*c.p))
            advance(&c);
        if (c.p == c.end || *c.p == '#')
            return 0;
        token t = {NULL, c.line, c.col, 0};
        const char *start = c.p;
        if (*c.p == '"') {
            int rc = lex_quoted(s, &c, &t, err);
            if (rc)
                return rc;
        } else {
            while (c.p < c.end && !is_blank(*c.p)) {
                if (*c.p == '"')
                    return mote_script_fail_at(err, file, c.line, c.col, MOTE_EINVAL,
                                               "unexpected '\"' inside a word (quote the whole "
                                               "argument: \"like this\")");
                if (is_control((unsigned char)*c.p))
                    return fail_control(err, file, &c);
                advance(&c);
            }
            t.text = mote_arena_strndup(&s->arena, start, (size_t)(c.p - start));
            if (!t.text)
                return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
        }
        if (!tl->src_begin)
            tl->src_begin = start;
        tl->src_end = c.p;
        if (mote_push_token(tl, t))
            return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    }
}

