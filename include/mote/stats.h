/* stats.h: what every model's measurements share: block statistics (the standard error of a
 * time average from the scatter of its block means) and sampling schedules (when the samples of
 * a measurement are taken, by simulated time or by event count). Plain functions of numbers:
 * nothing here knows a model. */
#ifndef MOTE_STATS_H
#define MOTE_STATS_H

#include <stdint.h>

/* ---- blocks: samples 0 .. n-1 split into B = min(n, max_blocks) consecutive blocks ------------ */

/* The number of blocks B. */
int mote_blocks_count(uint64_t nsamples, int max_blocks);
/* The block of sample s: floor(s B / n), so block sizes differ by at most one. */
int mote_block_of(uint64_t s, uint64_t nsamples, int max_blocks);
/* The number of samples in block b (exactly those mote_block_of puts there). */
uint64_t mote_block_size(int b, uint64_t nsamples, int max_blocks);
/* Standard error of the mean from block means: sqrt(sum (m_b - m)^2 / (B (B - 1))); NaN with
 * fewer than two blocks. */
double mote_block_error(const double *block_means, int nblocks);

/* Student's t quantile t(0.975, dof): the half-width of a 95% confidence interval of a mean of
 * n = dof + 1 independent normal values is t s / sqrt(n) (s: their sample standard deviation).
 * dof 1 ... 30 from the standard table (Abramowitz & Stegun, Table 26.10), above it the
 * Cornish-Fisher expansion (A&S 26.7.5, four terms: within 3e-8); NaN for dof < 1. */
double mote_t95(int dof);

/* ---- schedules -------------------------------------------------------------------------------- */

/* Timed samples: sample k falls at t0 + k dt, computed afresh each time (never accumulated, so
 * the 10^6-th sample is as exact as the first). k counts the samples taken. */
typedef struct {
    double t0, dt;
    uint64_t k;
} mote_schedule;

static inline double mote_schedule_next(const mote_schedule *s)
{
    return s->t0 + (double)s->k * s->dt;
}

/* Counted samples: of S samples spread over C events, sample s (1 ... S) is taken right after
 * event floor(s C / S) (exact, without overflow, for any s <= S). */
uint64_t mote_schedule_count_at(uint64_t s, uint64_t S, uint64_t C);

#endif
