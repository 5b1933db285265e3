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

double mote_t95(int dof)
{
    static const double table[30] = {
        12.706205, 4.302653, 3.182446, 2.776445, 2.570582, 2.446912, 2.364624, 2.306004,
        2.262157,  2.228139, 2.200985, 2.178813, 2.160369, 2.144787, 2.131450, 2.119905,
        2.109816,  2.100922, 2.093024, 2.085963, 2.079614, 2.073873, 2.068658, 2.063899,
        2.059539,  2.055529, 2.051831, 2.048407, 2.045230, 2.042272};
    if (dof < 1)
        return NAN;
    if (dof <= 30)
        return table[dof - 1];
    const double z = 1.959963984540054, n = dof; /* the normal quantile, then powers of 1/n */
    const double z2 = z * z;
    const double g1 = z * (z2 + 1) / 4;
    const double g2 = z * ((5 * z2 + 16) * z2 + 3) / 96;
    const double g3 = z * (((3 * z2 + 19) * z2 + 17) * z2 - 15) / 384;
    const double g4 = z * ((((79 * z2 + 776) * z2 + 1482) * z2 - 1920) * z2 - 945) / 92160;
    return z + g1 / n + g2 / (n * n) + g3 / (n * n * n) + g4 / (n * n * n * n);
}
