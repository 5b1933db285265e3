/* loop.h: the run loop every long command of every model goes through (issues 34, 53). A model
 * says how to advance its system to a stop; the core runs the loop: it chooses the stops (the
 * next observer time or count, or the end), calls the observers due there, shows the progress
 * and honours Ctrl-C. A command fills a mote_runner and calls
 *
 *     rc = mote_run(&runner, observers, nobservers, &progress, t_end, n_end, err);
 *
 * fires the time observers due at the start (a catching-up model's, see mote_runner.at, after
 * its first step) and then, until the clock reaches t_end or the count (collisions, steps, histories, moves)
 * reaches n_end, repeats: stop = the next observer time (or t_end) and the next observer count
 * (or n_end); advance(sys, loop, stop, count stop) (an event-driven model exactly there; a
 * fixed-step model step by step; it may return earlier, for example for the progress line, and
 * may call mote_loop_progress now and then); every count observer due at the new count (one
 * whose counts a model went past, a step of several collisions, fires there once); every
 * time observer due at the new time; the progress. An advance that moves neither the clock nor
 * the count ends the run (nothing more can happen).
 *
 * Observers (samples, frames, snapshots, monitor rows, dumps, ...) each have one schedule they
 * refer to, owned by whoever installed them (no copies): exact times t0 + k dt, never
 * accumulated sums, or counts. The context's observers (mote_context.observers: a program that
 * drives mote, a test) join every run of every model. Plain C, no allocation. */
#ifndef MOTE_LOOP_H
#define MOTE_LOOP_H

#include "mote/command.h"
#include "mote/core.h"
#include "mote/stats.h"

#include <stdint.h>

/* An observer: fire(ctx, subject, err), where subject is the runner's sys.
 * - A time observer (at != NULL) fires at the times at->t0 + k at->dt, k = at->k, at->k + 1, ...
 *   (at->k counts on as it fires; times a step went past are skipped, unless the runner catches
 *   up, see mote_runner.at).
 * - A count observer (at == NULL) fires when the loop's count is from + j every (j = 0, 1, ...;
 *   from 0: the multiples of every), or, with spread > 0, from + floor(j over / spread) for
 *   j = 1 ... spread (spread samples evenly over `over` counts). */
typedef struct mote_observer {
    mote_schedule *at;
    void *ctx;
    int (*fire)(void *ctx, void *subject, mote_err *err);
    uint64_t every, from;
    uint64_t spread, over;
} mote_observer;

#define MOTE_RUN_OBSERVERS_MAX 16

typedef struct mote_loop {
    mote_observer *obs;      /* the observers of this run */
    size_t nobs;
    uint64_t n_end;          /* stop once the count reaches this; UINT64_MAX: no limit */
    mote_progress *progress; /* may be NULL */
    double t_begin, t_end;   /* of the whole command, for the progress fraction */
    uint64_t n_begin;
    int done;                /* set by an advance: the model can go no further; the loop ends
                              * after this stop's observers */
} mote_loop;

/* A model's side of the loop. */
typedef struct mote_runner {
    const char *what;      /* the command, for messages ("run", "step", "integrate") */
    void *sys;             /* what advance gets */
    void *subject;         /* what the observers get (NULL: sys) */
    const mote_context *ctx; /* its observers join this run (NULL: none) */
    double (*clock)(const void *sys);   /* the model's time (NULL: it has none) */
    uint64_t (*count)(const void *sys); /* its count (NULL: it has none) */
    /* Advance towards time t_stop and count n_stop, stopping at whichever comes first (a model
     * that cannot stop inside its work may go past n_stop: a count observer it passed fires
     * once, at the count reached). The state must be complete at its clock on return. */
    int (*advance)(void *sys, mote_loop *l, double t_stop, uint64_t n_stop, mote_err *err);
    /* Optional: whether the model has reached its end by its own measure (instead of clock >=
     * t_end: a clock in a longer type than double). */
    int (*ended)(const void *sys);
    /* Optional: catch up. A model whose steps go past observer times (it does not stop at
     * t_stop) fires each observer time passed, in order, at the time at(sys, t) returns (t:
     * dense output between step ends; the clock: the state at the step's end). Without it, the
     * observers due at the clock fire once. */
    double (*at)(void *sys, double t);
    /* Optional: the fraction done for the progress line (instead of the clock's and the count's
     * fraction of the way to t_end and n_end). */
    double (*fraction)(const void *sys);
} mote_runner;

/* The schedule of an output command (the output layer's shared words every= and dt=): every=K
 * (a count of the model's steps, collisions, ...) or dt=T (simulated time), one of them.
 * mote_call_check_every_dt fails, located at the call, when both are given, or when neither is
 * and `required`. mote_call_observer makes the observer from now: every=K fires at the counts
 * n_now + j K scale (j = 1, 2, ...; scale: the model's count per unit of K, 1 for most; hard
 * spheres count K in collisions per particle), dt=T at the times t_now + k T (k = 1, 2, ...;
 * its schedule in *at, which must live as long as the observer). Neither: an observer that
 * never fires. */
int mote_call_check_every_dt(const mote_call *c, int required, mote_err *err);
mote_observer mote_call_observer(const mote_call *c, mote_schedule *at, double t_now,
                                 uint64_t n_now, uint64_t scale, void *ctx,
                                 int (*fire)(void *ctx, void *subject, mote_err *err));

/* Run r from its clock and count until t_end (INFINITY: none) or n_end (UINT64_MAX: none), with
 * the model's observers obs[0 .. nobs) and the context's. Returns the first error (an observer's,
 * the advance's, or mote_interrupted's when the user asked to stop at a progress update). */
int mote_run(const mote_runner *r, const mote_observer *obs, size_t nobs, mote_progress *progress,
             double t_end, uint64_t n_end, mote_err *err);

/* The pieces of the loop, for an advance that looks at them. */
/* The earliest pending observer time (INFINITY when there is none). */
double mote_loop_next(const mote_loop *l);
/* The time to stop at next: min(next observer time, t_end), where an observer time within
 * 1e-9 of its interval before t_end counts as t_end. */
double mote_loop_stop(const mote_loop *l, double t_end);
/* Whether an observer is due at time t (as mote_loop_fire would fire it). */
int mote_loop_due(const mote_loop *l, double t);
/* Fire every observer due at time t (its next time <= t + 1e-9 of its interval), in order, once
 * each; its schedule then moves past t. Returns the first observer's error, at once. */
int mote_loop_fire(mote_loop *l, void *subject, double t, mote_err *err);
/* The count to stop at next, after n: the smallest count above n at which a count observer
 * fires, or n_end when that comes first (or there is no count observer). */
uint64_t mote_loop_count_stop(const mote_loop *l, uint64_t n, uint64_t n_end);
/* Fire every count observer due at count n, in order. Returns the first error, at once. */
int mote_loop_fire_count(mote_loop *l, void *subject, uint64_t n, mote_err *err);
/* The progress at time t and count n: the larger of the time fraction (t_begin .. t_end, when
 * finite) and the count fraction (n_begin .. n_end, when n_end is a limit). 1: the user asked to
 * stop. */
int mote_loop_progress(mote_loop *l, double t, uint64_t n);

#endif
