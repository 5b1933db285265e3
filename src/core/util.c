/* util.c: small helpers used across layers: a monotonic wall clock for progress and rates, the
 * peak resident set size for memory reports, and exact real formatting for state files. */
#include "mote/core.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

double mote_wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

size_t mote_peak_rss_bytes(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0)
        return 0;
    return (size_t)ru.ru_maxrss * 1024u; /* Linux reports kilobytes */
}

void mote_fmt_exact(char *buf, double x)
{
    if (x == 0.0)
        x = 0.0; /* turns -0 into +0 */
    snprintf(buf, 32, "%.17g", x);
}

int mote_lines_open(mote_lines *r, const char *path, mote_err *err)
{
    memset(r, 0, sizeof *r);
    r->path = path;
    r->f = fopen(path, "r");
    if (!r->f)
        return mote_fail(err, MOTE_EIO, "%s: cannot open: %s", path, strerror(errno));
    return MOTE_OK;
}

char *mote_lines_next(mote_lines *r)
{
    ssize_t len = getline(&r->buf, &r->cap, r->f);
    if (len < 0)
        return NULL;
    r->line++;
    if ((size_t)len != strlen(r->buf)) {
        r->buf[0] = '\0'; /* a NUL byte: not a text file */
        return r->buf;
    }
    r->buf[strcspn(r->buf, "\r\n")] = '\0';
    return r->buf;
}

int mote_lines_close(mote_lines *r, mote_err *err)
{
    int bad = r->f && ferror(r->f);
    if (r->f)
        fclose(r->f);
    free(r->buf);
    r->f = NULL;
    r->buf = NULL;
    return bad ? mote_fail(err, MOTE_EIO, "%s: read error", r->path) : MOTE_OK;
}
