/* buf.c: the growing text buffer a model writes its live frame into (mote_buf, buf.h): printf,
 * arrays of numbers (full or fixed precision), JSON strings. Plain libc; the server that sends
 * the frames is src/http/live.c. */
#include "mote/buf.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void buf_reserve(mote_buf *b, size_t more)
{
    if (b->failed || b->n + more + 1 <= b->cap)
        return;
    size_t cap = b->cap ? b->cap : 4096;
    while (cap < b->n + more + 1)
        cap *= 2;
    char *s = realloc(b->s, cap);
    if (!s) {
        b->failed = 1;
        return;
    }
    b->s = s;
    b->cap = cap;
}

void mote_buf_append(mote_buf *b, const void *data, size_t n)
{
    buf_reserve(b, n);
    if (b->failed || !n)
        return;
    memcpy(b->s + b->n, data, n);
    b->n += n;
    b->s[b->n] = '\0';
}

void mote_buf_printf(mote_buf *b, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char tmp[256];
    int k = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    if (k < 0) {
        b->failed = 1;
        return;
    }
    buf_reserve(b, (size_t)k);
    if (b->failed)
        return;
    if ((size_t)k < sizeof tmp) {
        memcpy(b->s + b->n, tmp, (size_t)k + 1);
    } else {
        va_start(ap, fmt);
        vsnprintf(b->s + b->n, (size_t)k + 1, fmt, ap);
        va_end(ap);
    }
    b->n += (size_t)k;
}

void mote_buf_doubles(mote_buf *b, const char *key, const double *v, size_t n, size_t stride)
{
    mote_buf_printf(b, ",\"%s\":[", key);
    for (size_t i = 0; i < n && !b->failed; i++) {
        const double x = v[i * stride];
        if (isfinite(x))
            mote_buf_printf(b, i ? ",%.7g" : "%.7g", x);
        else
            mote_buf_printf(b, i ? ",null" : "null");
    }
    mote_buf_printf(b, "]");
}

void mote_buf_fixed(mote_buf *b, const char *key, const double *v, size_t n, size_t stride,
                    double size)
{
    /* decimals for 5 significant digits of `size` (a picture's width: finer is invisible) */
    int dec = size > 0 && isfinite(size) ? (int)ceil(5 - log10(size)) : 6;
    dec = dec < 0 ? 0 : dec > 15 ? 15 : dec;
    double p10 = 1;
    for (int k = 0; k < dec; k++)
        p10 *= 10;
    mote_buf_printf(b, ",\"%s\":[", key);
    buf_reserve(b, n * 24);
    for (size_t i = 0; i < n && !b->failed; i++) {
        const double x = v[i * stride] * p10;
        char t[40], *e = t + sizeof t, *q = e;
        if (!(fabs(x) < 9e15)) { /* beyond the integer path: the general one */
            mote_buf_printf(b, i ? "," : "");
            if (isfinite(v[i * stride]))
                mote_buf_printf(b, "%.7g", v[i * stride]);
            else
                mote_buf_printf(b, "null");
            continue;
        }
        long long k = llround(x);
        const int neg = k < 0;
        unsigned long long u = neg ? (unsigned long long)(-k) : (unsigned long long)k;
        for (int d = 0; d < dec; d++) { /* the fraction, trailing zeros dropped */
            const int digit = (int)(u % 10);
            u /= 10;
            if (q != e || digit)
                *--q = (char)('0' + digit);
        }
        if (q != e)
            *--q = '.';
        do {
            *--q = (char)('0' + u % 10);
            u /= 10;
        } while (u);
        if (neg)
            *--q = '-';
        if (i)
            *--q = ',';
        buf_reserve(b, (size_t)(e - q));
        if (b->failed)
            return;
        memcpy(b->s + b->n, q, (size_t)(e - q));
        b->n += (size_t)(e - q);
        b->s[b->n] = '\0';
    }
    mote_buf_printf(b, "]");
}

void mote_buf_string(mote_buf *b, const char *key, const char *text)
{
    mote_buf_printf(b, ",\"%s\":\"", key);
    for (const unsigned char *p = (const unsigned char *)text; *p && !b->failed; p++) {
        if (*p == '"' || *p == '\\')
            mote_buf_printf(b, "\\%c", *p);
        else if (*p < 0x20)
            mote_buf_printf(b, "\\u%04x", *p);
        else
            mote_buf_printf(b, "%c", *p);
    }
    mote_buf_printf(b, "\"");
}

void mote_buf_free(mote_buf *b)
{
    free(b->s);
    memset(b, 0, sizeof *b);
}
