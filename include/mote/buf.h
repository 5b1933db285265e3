/* buf.h: a growing text buffer (JSON a model writes for its live frame, or any text built a
 * piece at a time): printf, arrays of numbers (full or fixed precision), JSON strings. Core
 * layer, plain libc (src/core/buf.c); the server that sends live frames is live.h's. */
#ifndef MOTE_BUF_H
#define MOTE_BUF_H

#include <stddef.h>

/* A growing text buffer for a frame (JSON). */
typedef struct {
    char *s;
    size_t n, cap;
    int failed; /* an allocation failed: the frame is dropped */
} mote_buf;

void mote_buf_printf(mote_buf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* ,"key":[v0,v1,...] with n values taken every `stride` from v, in %.7g (NaN/inf as null) */
void mote_buf_doubles(mote_buf *b, const char *key, const double *v, size_t n, size_t stride);
/* The same, written fast in fixed point: values of a picture `size` across, to 5 significant
 * digits of it (a coordinate need not be finer than a 10^5-th of the picture). */
void mote_buf_fixed(mote_buf *b, const char *key, const double *v, size_t n, size_t stride,
                    double size);
/* ,"key":"text" with the text escaped for JSON */
void mote_buf_string(mote_buf *b, const char *key, const char *text);
/* n bytes as they are (any bytes, a NUL kept), grown like the rest */
void mote_buf_append(mote_buf *b, const void *data, size_t n);
void mote_buf_free(mote_buf *b);

#endif
