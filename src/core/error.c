/* error.c: errors as values. A failing library function records a code and a message naming what
 * was wrong and where, and returns the code; callers decide how to report it. */
#include "mote/core.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

int mote_fail(mote_err *err, mote_status code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
        err->code = code;
        err->located = 0;
    }
    return (int)code;
}

void mote_err_clear(mote_err *err)
{
    if (err) {
        err->code = MOTE_OK;
        err->located = 0;
        err->msg[0] = '\0';
    }
}
