/* stats.c: block statistics and counted schedules (stats.h). */
#include "mote/stats.h"

#include <math.h>

int mote_blocks_count(uint64_t nsamples, int max_blocks)
{
    return (int)(nsamples < (uint64_t)max_blocks ? nsamples : (uint64_t)max_blocks);
}

int mote_block_of(uint64_t s, uint64_t nsamples, int max_blocks)
{
    uint64_t B = (uint64_t)mote_blocks_count(nsamples, max_blocks);
    return (int)((long double)s * (long double)B / (long double)nsamples);
}

uint64_t mote_block_size(int b, uint64_t nsamples, int max_blocks)
{
    /* the samples s with floor(s B / n) = b are ceil(b n / B) <= s < ceil((b + 1) n / B) */
    int B = mote_blocks_count(nsamples, max_blocks);
    uint64_t lo = (uint64_t)ceill((long double)b * (long double)nsamples / (long double)B);
    uint64_t hi = (uint64_t)ceill((long double)(b + 1) * (long double)nsamples / (long double)B);
    return hi - lo;
}

double mote_block_error(const double *block_means, int nblocks)
{
    if (nblocks < 2)
        return NAN;
    double m = 0;
    for (int b = 0; b < nblocks; b++)
        m += block_means[b];
    m /= nblocks;
    double v = 0;
    for (int b = 0; b < nblocks; b++)
        v += (block_means[b] - m) * (block_means[b] - m);
    return sqrt(v / ((double)nblocks * (nblocks - 1)));
}

uint64_t mote_schedule_count_at(uint64_t s, uint64_t S, uint64_t C)
{
    uint64_t q = C / S, r = C % S;
    if (S < (1ull << 32))
        return s * q + (s * r) / S;
    return s * q + (uint64_t)floorl((long double)s * (long double)r / (long double)S);
}
