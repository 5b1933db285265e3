/* util.c: small helpers used across layers: a monotonic wall clock for progress and rates, the
 * peak resident set size for memory reports, and exact real formatting for state files. */
#include "mote/core.h"

#include <stdio.h>
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
