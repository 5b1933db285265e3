/* loop.h: the run loop long commands share (issue 34). A model advances its system; the loop
 * says where to stop and what happens there. Observers (samples, frames, snapshots, balance
 * rows, ...) each have one schedule, mote_schedule: exact times t0 + k dt, never accumulated
 * sums. A command fills a mote_loop and then, until its end:
 *
 *     double stop = mote_loop_stop(&l, t_end);  the next observer time, or t_end
 *     advance to stop (an event-driven model exactly; a fixed-step model one step at a time),
 *         calling mote_loop_progress(&l, t, n) now and then (it is cheap);
 *     rc = mote_loop_fire(&l, subject, t, err); every observer due at t, once
 *
 * and stops early once its count (collisions, steps, histories) reaches l.n_end. Progress goes
 * through l.progress (percent and time left on a terminal, nothing when output is not one) and
 * the live view's tick. Plain C, no allocation: the observers are the caller's array. */
#ifndef MOTE_LOOP_H
#define MOTE_LOOP_H

#include "mote/command.h"
#include "mote/core.h"
#include "mote/stats.h"

#include <stdint.h>

/* An observer: fire(ctx, subject, err) at the times at.t0 + k at.dt, k = at.k, at.k + 1, ...
 * (at.k counts the calls so far; the command that installs an observer takes k = 0 itself or
 * lets the loop take it at the start). subject is what the loop was given: the model's system.
 * A count observer (every > 0; its `at` unused) fires instead when the loop's count (steps,
 * collisions, histories) is from + j every (j = 0, 1, ...; from 0: the multiples of every): a
 * model with a count calls mote_loop_count_stop and mote_loop_fire_count, and the time calls
 * pass it by. */
typedef struct mote_observer {
    mote_schedule at;
    void *ctx;
    int (*fire)(void *ctx, void *subject, mote_err *err);
    uint64_t every, from;
} mote_observer;

typedef struct mote_loop {
    mote_observer *obs;      /* the caller's array */
    size_t nobs;
    uint64_t n_end;          /* stop once the count reaches this; UINT64_MAX: no limit */
    mote_progress *progress; /* may be NULL */
    double t_begin, t_end;   /* of the whole command, for the progress fraction */
    uint64_t n_begin;
} mote_loop;

/* The earliest pending observer time (INFINITY when there is none). */
double mote_loop_next(const mote_loop *l);
/* The time to stop at next: min(next observer time, t_end), where an observer time within
 * 1e-9 of its interval before t_end counts as t_end. */
double mote_loop_stop(const mote_loop *l, double t_end);
/* Whether an observer is due at time t (as mote_loop_fire would fire it). */
int mote_loop_due(const mote_loop *l, double t);
/* Fire every observer due at time t (its next time <= t + 1e-9 of its interval), in order, once
 * each; its schedule then moves past t (times a longer step stepped over are skipped, not fired
 * late). Returns the first observer's error, at once. */
int mote_loop_fire(mote_loop *l, void *subject, double t, mote_err *err);
/* The count to stop at next, after n: the smallest count above n at which a count observer
 * fires, or n_end when that comes first (or there is no count observer). */
uint64_t mote_loop_count_stop(const mote_loop *l, uint64_t n, uint64_t n_end);
/* Fire every count observer due at count n, in order. Returns the first error, at once. */
int mote_loop_fire_count(mote_loop *l, void *subject, uint64_t n, mote_err *err);
/* The progress at time t and count n: the larger of the time fraction (t_begin .. t_end, when
 * finite) and the count fraction (n_begin .. n_end, when n_end is a limit). */
int mote_loop_progress(mote_loop *l, double t, uint64_t n);

#endif
