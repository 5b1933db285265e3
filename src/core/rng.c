/* rng.c: the random stream of a simulation: xoshiro256** (Blackman & Vigna 2021) seeded from one
 * 64-bit integer through four SplitMix64 outputs, and Marsaglia polar normal variates. The whole
 * generator state is four words, so it can be saved in a state file and restored exactly. */
#include "mote/core.h"

#include <math.h>

static uint64_t splitmix64(uint64_t *x)
{
    uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

void mote_rng_seed(mote_rng *rng, uint64_t seed)
{
    uint64_t x = seed;
    for (int k = 0; k < 4; k++)
        rng->s[k] = splitmix64(&x);
}

static inline uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

uint64_t mote_rng_next(mote_rng *rng)
{
    uint64_t *s = rng->s;
    uint64_t result = rotl(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

double mote_rng_uniform(mote_rng *rng) { return (double)(mote_rng_next(rng) >> 11) * 0x1.0p-53; }

void mote_normal_init(mote_normal *g, mote_rng *rng)
{
    g->rng = rng;
    g->has_spare = 0;
    g->spare = 0.0;
    g->uniforms = 0;
}

double mote_normal_next(mote_normal *g)
{
    if (g->has_spare) {
        g->has_spare = 0;
        return g->spare;
    }
    double u, v, s;
    do {
        u = 2.0 * mote_rng_uniform(g->rng) - 1.0;
        v = 2.0 * mote_rng_uniform(g->rng) - 1.0;
        s = u * u + v * v;
        g->uniforms += 2;
    } while (s >= 1.0 || s == 0.0);
    double f = sqrt(-2.0 * log(s) / s);
    g->spare = v * f;
    g->has_spare = 1;
    return u * f;
}
