/* mixingbox.h: the mixing-box model (specs/mixing-box.md): 2D disks of two colours in a box split
 * by a partition with a slit. This header holds the model's parameters, the system struct every
 * integrator works on, the rules every integrator shares (collision rules with the TC model,
 * wall kicks, chamber bookkeeping) and the integrator plug-in point:
 *
 *     int mb_run_timestep(mote_mb *sys, double t_end, const mote_loop *spec, mote_err *err);
 *     int mb_run_event   (mote_mb *sys, double t_end, const mote_loop *spec, mote_err *err);
 *
 * mote_mb_run dispatches to one of them by sys->p.integrator. Each is an advance of the core's
 * run loop (mote_run, loop.h; the contract in full above mote_mb_progress): advance the state in
 * sys (plain arrays of positions and velocities) to the stop the loop asks for, with the state
 * synchronised there, keep the counters and the chamber of every disk up to date, and stop
 * early once the collision count asked for is reached; the loop fires the samplers.
 * Measurements, pictures and files live above this contract (src/mixingbox/measure.c,
 * picture.c), so a new integrator gets all of them for free. */
#ifndef MOTE_MIXINGBOX_H
#define MOTE_MIXINGBOX_H

#include "mote/command.h"
#include "mote/core.h"
#include "mote/loop.h"
#include "mote/event.h"
#include "mote/grid.h"
#include "mote/stats.h"

#include <stdint.h>

/* ---- parameters ------------------------------------------------------------------------------ */

enum { MOTE_MB_TIMESTEP = 0, MOTE_MB_EVENT = 1 };      /* mote_mb_params.integrator */
enum { MOTE_MB_RESTITUTION = 0, MOTE_MB_SEEDRULE = 1 }; /* mote_mb_params.rule */

/* The default integrator. The spec's default is `event`; while the event integrator is not
 * written yet (src/mixingbox/event.c), the time-stepped reference mode is the default. */
#define MOTE_MB_DEFAULT_INTEGRATOR MOTE_MB_EVENT

/* Every parameter of the spec's table, in SI units (m, s, m/s, m/s^2, kg). */
typedef struct {
    double x_l, x_r, x_b, x_t; /* box: left, right, bottom, top walls */
    double x1_c, a;            /* partition: centre x and thickness; spans x_b .. x_t */
    double x2_c, b;            /* slit: centre y and height; b = 0 closes the partition */
    double r;                  /* disk radius */
    int64_t n_left, n_right;   /* disks placed in the left / right chamber */
    double v_init;             /* initial speed of every disk */
    double dv_b, dv_t, dv_s;   /* kicks: speed added on a bounce off bottom / top / side walls */
    double loss;               /* fraction of kinetic energy lost in a disk-disk collision */
    double g;                  /* gravitational acceleration, acting in -y */
    double t_c;                /* TC model time (s); NaN = automatic: r / (100 v_ref) */
    double mass;               /* disk mass (kg), 1; enters energies and temperatures only */
    int integrator;            /* MOTE_MB_TIMESTEP or MOTE_MB_EVENT */
    int rule;                  /* MOTE_MB_RESTITUTION or MOTE_MB_SEEDRULE */
} mote_mb_params;

/* The defaults of the command reference (a 2 m x 1 m box with a 2 cm partition at x = 1 and a
 * 10 cm slit at mid-height, R = 5 mm, 500 + 500 disks at 1 m/s, no kicks, loss or gravity). */
void mote_mb_params_default(mote_mb_params *p);

/* Derived geometry. */
static inline double mote_mb_x1_l(const mote_mb_params *p) { return p->x1_c - 0.5 * p->a; }
static inline double mote_mb_x1_r(const mote_mb_params *p) { return p->x1_c + 0.5 * p->a; }
static inline double mote_mb_x2_b(const mote_mb_params *p) { return p->x2_c - 0.5 * p->b; }
static inline double mote_mb_x2_t(const mote_mb_params *p) { return p->x2_c + 0.5 * p->b; }

/* The t_c in force: p->t_c, or when it is NaN r / (100 v_ref) with v_ref = v_init (0.1 m/s when
 * v_init is 0, the document's fallback speed). */
double mote_mb_tc(const mote_mb_params *p);

/* Area fraction n pi r^2 / (chamber area) of a chamber (0 left, 1 right). */
double mote_mb_area_fraction(const mote_mb_params *p, int chamber);

/* Random placement jams near this area fraction (random sequential addition in 2D); denser
 * chambers are rejected before anything runs. */
#define MOTE_MB_PHI_MAX 0.54

/* Check the whole parameter set (box, partition and slit inside the box, chambers and slit wide
 * enough for a disk, counts, densities, speeds, loss in [0, 1], kicks >= 0, t_c >= 0). The
 * message names the parameters and their values. */
int mote_mb_params_check(const mote_mb_params *p, mote_err *err);

/* ---- the system ------------------------------------------------------------------------------ */


typedef struct mote_mb {
    mote_mb_params p;  /* geometry fixed at placement; the physics fields are updated by the
                        * commands (kicks, loss, g, t_c, integrator, rule) between runs */
    int placed;
    uint32_t n;        /* N = n_left + n_right */
    double *x, *y;     /* centres (m) */
    double *vx, *vy;   /* velocities (m/s) */
    int *colour;       /* 0 (placed left) or 1 (placed right) */
    uint8_t *side;     /* chamber of the centre: 0 when x < X1_C, else 1 (mote_mb_note_side) */
    double *t_last;    /* time of the disk's last disk-disk collision (TC model); -inf: none */
    double time;       /* simulated time since placement (s) */
    /* During an event run, the engine whose positions (projected, read only) a live view may
     * show between events: mote_mb_live_position (NULL between runs: x, y are current) */
    const void *live_ev; /* (a const mote_ev *) */
    double live_x0, live_y0, live_t0;

    /* Counters since placement; every integrator keeps them. */
    uint64_t collisions;     /* disk-disk collisions (each application of a collision rule) */
    uint64_t collisions_tc;  /* ... of which were made elastic by the TC model */
    uint64_t wall_hits;      /* bounces off the four box walls */
    uint64_t partition_hits; /* bounces off the partition's side faces */
    uint64_t slit_hits;      /* bounces off the slit's top and bottom edges */
    uint64_t corner_hits;    /* bounces off the slit's four corners (event integrator only) */
    uint64_t cross_lr;       /* slit crossings left -> right (see mote_mb_note_side) */
    uint64_t cross_rl;       /* slit crossings right -> left */
    uint64_t steps;          /* time steps (timestep integrator only) */

    /* Overlap bookkeeping: pairs closer than 2R (1 - MOTE_MB_OVERLAP_TOL). The driver counts
     * them at the start and end of every run, the recording at every sample, the timestep
     * integrator after every step; overlaps_max and overlap_steps are reset when a run starts. */
    uint64_t overlaps_last; /* at the last count */
    uint64_t overlaps_max;  /* most seen at one count during the current run */
    uint64_t overlap_steps; /* timestep integrator: steps of the current run ending with any */

    mote_rng rng;      /* the placement stream (dynamics draw no random numbers) */
    uint64_t seed;     /* the last seed given (default 1) */

    /* Bumped whenever the state is changed outside an integrator (placement) and by every
     * integrator when it returns, so an integrator that keeps a cache (an event calendar) knows
     * whether it is still valid: cache it with the generation it was built for. */
    uint64_t generation;
    void *integrator_cache;
    uint64_t integrator_cache_generation;
    void (*integrator_cache_free)(void *cache);

    mote_grid *grid;      /* scratch cell grid for overlap counts and the timestep integrator */
    int grid_ready;       /* its layout fits the placed system (reset by placement) */
} mote_mb;

#define MOTE_MB_OVERLAP_TOL 1e-9

void mote_mb_init(mote_mb *sys);
void mote_mb_free(mote_mb *sys);

/* Re-seed the placement stream (xoshiro256** through SplitMix64). */
void mote_mb_seed(mote_mb *sys, uint64_t seed);

/* Place n_left disks of colour 0 in the left chamber and n_right of colour 1 in the right, at
 * random (uniform, rejection of any disk closer than 2R to a placed one or closer than R to a
 * wall or the partition), each with speed v_init in a direction uniform on [0, 2 pi); per disk
 * the draws are x, y (repeated until it fits), then the angle, left chamber first. The draws
 * continue sys->rng. Replaces any earlier system; time and counters start at 0. Fails (with
 * the chamber's area fraction in the message) when a disk cannot be placed after
 * MOTE_MB_PLACE_TRIES random tries; the earlier system is then kept. */
#define MOTE_MB_PLACE_TRIES 1000000
int mote_mb_place(mote_mb *sys, const mote_mb_params *p, mote_err *err);

/* ---- shared rules ---------------------------------------------------------------------------- */

/* The document's collision rule (spec 2.3) on velocities only: d = |r2 - r1|,
 * sin a = |y2 - y1| / d, cos a = |x2 - x1| / d (absolute values, as written), dV = v1 - v2, then
 *   v1x' = (dVx sin^2 - dVy sin cos + v2x) f     v1y' = (dVy cos^2 - dVx sin cos + v2y) f
 *   v2x' = (dVx cos^2 + dVy sin cos + v2x) f     v2y' = (dVy sin^2 + dVx sin cos + v2y) f.
 * Returns 0 (nothing changed) when the centres coincide. */
int mote_mb_rule_seed(double x1, double y1, double x2, double y2, double v1[2], double v2[2],
                      double f);
/* Normal restitution: with n = (r2 - r1)/|r2 - r1| and u = (v1 - v2).n, v1 -= (1+e)/2 u n,
 * v2 += (1+e)/2 u n (equal masses). Returns 0 when the centres coincide. */
int mote_mb_rule_restitution(double x1, double y1, double x2, double y2, double v1[2],
                             double v2[2], double e);

/* Collide disks i and j at time t with the rule of sys->p.rule: the velocity factor is
 * sqrt(1 - loss), or 1 when either disk collided less than t_c before t (the TC model of
 * Luding & McNamara). Updates vx, vy, t_last, collisions and collisions_tc. The caller has
 * decided that the pair collides now (in contact and approaching). */
void mote_mb_collide(mote_mb *sys, uint32_t i, uint32_t j, double t);

/* The rules of the event integrator (spec 3), as the event engine calls them in field mode
 * (mote_ev_rules, event.h), in the engine's frame (box from the origin, time from the engine's
 * start): disk-disk collisions with normal restitution e, or with `scale_rule` (collision_rule
 * seed) an elastic collision after which both velocities are scaled by e, both elastic within
 * tc of either disk's previous collision (the TC model); box walls and obstacle faces reflect
 * and add their kick along the normal, and a wall or face the field pulls towards sends a disk
 * off at no less than g tc (a bounce lasts at least tc, so a disk settling on a floor does not
 * bounce ever faster); corners reflect without a kick. The counters count what happened. */
typedef struct {
    double e;                /* restitution, sqrt(1 - loss) */
    int scale_rule;          /* 1: collision_rule seed (elastic, then both scaled by e) */
    double tc;               /* TC model time */
    double g[2];             /* the field, as the engine has it */
    double kick[2][2];       /* [axis][side]: speed added away from that box wall */
    const double *face_kick; /* per obstacle face: speed added along its normal */
    double *t_last;          /* per disk: time of its last disk-disk collision */
    uint64_t *face_hits;     /* per obstacle face */
    uint64_t corner_hits, tc_elastic;
} mote_mb_rules;

/* The engine's view of r (which must outlive the engine's runs). */
mote_ev_rules mote_mb_event_rules(mote_mb_rules *r);

/* Bounce off a wall with a kick: the velocity component normal to the wall, v, moving into it,
 * becomes -(v + dv) when moving in +axis direction (top, right, partition left face, slit top
 * edge) and -(v - dv) in -axis direction, so a positive kick always adds speed away from the
 * wall (spec 2.4). */
static inline double mote_mb_bounce(double v, double dv) { return v > 0 ? -(v + dv) : -(v - dv); }

/* The chamber of a centre: 0 (left) when x < X1_C, else 1. */
static inline int mote_mb_chamber(const mote_mb *sys, double x) { return x < sys->p.x1_c ? 0 : 1; }

/* A slit crossing is a change of the chamber of a disk's centre, i.e. the centre passing the
 * partition's midline x = X1_C (which, with the partition in place, happens inside the slit).
 * Call this whenever disk i may have moved to the other chamber (after every step, or at the
 * event where the centre passes X1_C): it compares the chamber of x[i] with side[i] and counts
 * cross_lr or cross_rl when it changed. Returns 1 when a crossing was counted. */
static inline int mote_mb_note_side(mote_mb *sys, uint32_t i)
{
    uint8_t s = (uint8_t)mote_mb_chamber(sys, sys->x[i]);
    if (s == sys->side[i])
        return 0;
    if (s)
        sys->cross_lr++;
    else
        sys->cross_rl++;
    sys->side[i] = s;
    return 1;
}

/* ---- measurements on the state --------------------------------------------------------------- */

/* Disks per chamber (by side[]) and colour. */
typedef struct {
    uint64_t n[2][2]; /* [chamber][colour] */
} mote_mb_tally;

mote_mb_tally mote_mb_counts(const mote_mb *sys);
/* Mixing fraction m = (colour 0 on the right + colour 1 on the left) / N (0 for N = 0). */
double mote_mb_mixing_fraction(const mote_mb_tally *t);
/* Mixing entropy of a chamber holding n0 and n1 disks of the two colours:
 * S = -sum_c x_c ln x_c with x_c = n_c / (n0 + n1) (nats; 0 for an empty or pure chamber,
 * ln 2 for an even mixture). */
double mote_mb_entropy(uint64_t n0, uint64_t n1);
/* The mixing fraction of a uniform mixture, each colour spread over both chambers in proportion
 * to their areas: (n_left A_R + n_right A_L) / (N (A_L + A_R)); 1/2 for equal chambers. */
double mote_mb_mixing_equilibrium(const mote_mb_params *p);

/* Total energy sum (m v^2 / 2 + m g (y - X_B)) (J); *kinetic gets the kinetic part when not
 * NULL. Compensated sums. */
double mote_mb_energy(const mote_mb *sys, double *kinetic);
/* Mean kinetic energy per disk of a chamber (J; with two degrees of freedom this is kT);
 * *count gets the number of disks in it. 0 for an empty chamber. */
double mote_mb_chamber_kt(const mote_mb *sys, int chamber, uint64_t *count);

/* Pairs closer than 2R (1 - tol), with a cell grid (O(N)). Fails only on allocation failure,
 * returning UINT64_MAX. */
uint64_t mote_mb_count_overlaps(mote_mb *sys, double tol);
/* Record an overlap count in the bookkeeping fields (last and max). */
void mote_mb_note_overlaps(mote_mb *sys, uint64_t count);

/* ---- the integrator plug-in point ------------------------------------------------------------ */

/* The core's run loop (mote_run, include/mote/loop.h) is the integrators' plug-in point: its
 * observers are the samplers (fire(ctx, subject, err) with subject the mote_mb), its count the
 * collisions; spec gives the samplers (obs, nobs), the collision limit (n_end; UINT64_MAX: none)
 * and the progress. What an integrator's advance(t_stop, n_stop) must honour:
 *
 * - Sample times. t_stop is the earliest pending sample time t0 + k dt, or t_end (a sample
 *   within 1e-9 dt before t_end is taken at t_end). The integrator advances the system to
 *   exactly t_stop (never past it; the timestep integrator may stop a step earlier, where
 *   mote_loop_due says a sample is due within its tolerance) and sets sys->time (assigned, not
 *   accumulated) with x, y, vx, vy, side and every counter synchronised to that instant.
 * - Collision limit. When sys->collisions >= n_stop it stops (the event integrator right after
 *   that collision, with the state synchronised to its time; the timestep integrator at the end
 *   of that step). t_end may be INFINITY when there is a limit.
 * - Counters and chambers: collisions (through mote_mb_collide), wall_hits, partition_hits,
 *   slit_hits, corner_hits, and mote_mb_note_side for every centre that may have passed X1_C.
 * - Progress: call mote_mb_progress(loop, sys) now and then (it is cheap).
 * - On return from the run: state synchronised to sys->time, sys->generation bumped.
 * Overlaps are counted by the driver (mote_mb_run) at the start and end of a run and by the
 * recording at every sample; an integrator may count more often (the timestep one does). */

/* The loop's progress at the run's present time (mote_mb_live_time: during an event run the
 * engine's clock, ahead of sys->time) and collision count. */
int mote_mb_progress(mote_loop *loop, const mote_mb *sys); /* 1: the user asked to stop */
/* Disk i's centre now, and the time now, for a live view during a run (only reads). */
void mote_mb_live_position(const mote_mb *sys, uint32_t i, double xy[2]);
void mote_mb_live_velocity(const mote_mb *sys, uint32_t i, double v[2]);
double mote_mb_live_time(const mote_mb *sys);

/* The two integrators. mb_run_event lives in src/mixingbox/event.c on the event engine. */
int mb_run_timestep(mote_mb *sys, double t_end, const mote_loop *spec, mote_err *err);
int mb_run_event(mote_mb *sys, double t_end, const mote_loop *spec, mote_err *err);

/* Run to t_end (or the collision limit) with the integrator of sys->p.integrator: resets the
 * per-run overlap bookkeeping and counts overlaps at the start and at the end. spec (the
 * samplers, the collision limit, the progress) may be NULL: no samplers, no limit. */
int mote_mb_run(mote_mb *sys, double t_end, const mote_loop *spec, mote_err *err);

/* The model as registered with the script language. */
extern const mote_model mote_model_mixingbox;

#endif
