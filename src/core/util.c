/* util.c: small helpers used across layers: a monotonic wall clock for progress and rates, the
 * peak resident set size for memory reports, and exact real formatting for state files. */
#include "mote/core.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

double mote_wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double mote_pace_gap(double min_gap, double cost)
{
    const double g = MOTE_PACE_SHARE_INV * cost;
    return g > min_gap ? g : min_gap; /* (a NaN cost gives min_gap) */
}

size_t mote_peak_rss_bytes(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0)
        return 0;
    return (size_t)ru.ru_maxrss * 1024u; /* Linux reports kilobytes */
}

double mote_mem_physical(void)
{
    const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    return pages > 0 && size > 0 ? (double)pages * (double)size : 0;
}

int mote_mem_check(double bytes, const char *what, mote_err *err)
{
    const double phys = mote_mem_physical();
    if (phys > 0 && !(bytes <= 0.75 * phys)) /* (NaN is refused too) */
        return mote_fail(err, MOTE_ENOMEM, "%s needs about %.3g GB, more than 3/4 of this "
                         "machine's %.3g GB", what, bytes / 1e9, phys / 1e9);
    return MOTE_OK;
}

void mote_fmt_exact(char *buf, double x)
{
    if (x == 0.0)
        x = 0.0; /* turns -0 into +0 */
    snprintf(buf, 32, "%.17g", x);
}

void mote_fmt_short(char *buf, double x)
{
    if (x == 0.0)
        x = 0.0;
    for (int digits = 15; digits < 17; digits++) {
        snprintf(buf, 32, "%.*g", digits, x);
        if (strtod(buf, NULL) == x)
            return;
    }
    snprintf(buf, 32, "%.17g", x);
}

int mote_read_line(char **buf, size_t *cap, size_t *len, FILE *f, size_t max)
{
    size_t n = 0;
    int c = EOF;
    flockfile(f);
    while ((c = getc_unlocked(f)) != EOF) {
        if (n + 2 > *cap) {
            if (n >= max) {
                funlockfile(f);
                *len = n;
                return -1;
            }
            size_t want = *cap ? 2 * *cap : 256;
            if (want > max + 2)
                want = max + 2;
            char *nb = realloc(*buf, want);
            if (!nb) {
                funlockfile(f);
                return -2;
            }
            *buf = nb;
            *cap = want;
        }
        (*buf)[n++] = (char)c;
        if (c == '\n')
            break;
        if (n > max) {
            funlockfile(f);
            *len = n;
            return -1;
        }
    }
    funlockfile(f);
    *len = n;
    if (n == 0 && c == EOF)
        return 0;
    (*buf)[n] = '\0';
    return 1;
}

int mote_lines_open(mote_lines *r, const char *path, mote_err *err)
{
    memset(r, 0, sizeof *r);
    r->path = path;
    r->max = MOTE_LINE_MAX;
    r->f = fopen(path, "r");
    if (!r->f)
        return mote_fail(err, MOTE_EIO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(r->f), &st) == 0 && S_ISDIR(st.st_mode)) {
        fclose(r->f);
        r->f = NULL;
        return mote_fail(err, MOTE_EIO, "%s: cannot open: it is a directory", path);
    }
    return MOTE_OK;
}

char *mote_lines_next(mote_lines *r)
{
    if (r->failed || !r->f)
        return NULL;
    size_t len;
    int got = mote_read_line(&r->buf, &r->cap, &len, r->f, r->max);
    if (got <= 0) {
        if (got < 0) {
            r->line++;
            r->failed = got;
        }
        return NULL;
    }
    r->line++;
    if (len != strlen(r->buf)) {
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
    if (r->failed == -1)
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: line longer than %zu %s (not a text file?)",
                         r->path, r->line, r->max >> 20 ? r->max >> 20 : r->max,
                         r->max >> 20 ? "MiB" : "bytes");
    if (r->failed == -2)
        return mote_fail(err, MOTE_ENOMEM, "%s:%ld: out of memory reading the line", r->path,
                         r->line);
    return bad ? mote_fail(err, MOTE_EIO, "%s: read error", r->path) : MOTE_OK;
}

void mote_threads_quiet(void)
{
    if (!getenv("GOMP_SPINCOUNT") && !getenv("OMP_WAIT_POLICY"))
        setenv("GOMP_SPINCOUNT", "1000", 0);
}

struct timespec mote_deadline(double seconds)
{
    struct timespec t;
    clock_gettime(CLOCK_REALTIME, &t);
    const long ns = (long)(seconds * 1e9);
    t.tv_sec += ns / 1000000000L;
    t.tv_nsec += ns % 1000000000L;
    if (t.tv_nsec >= 1000000000L) {
        t.tv_sec++;
        t.tv_nsec -= 1000000000L;
    }
    return t;
}
