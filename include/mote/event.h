/* event.h: the event-driven engine for hard particles (spheres in 3D, disks in 2D).
 *
 * Particles fly in straight lines between events; the engine jumps from one event to the next:
 * pair collisions, wall hits and neighbour-list expiries. Each axis is either periodic or bounded
 * by two hard walls at 0 and len[axis]. Every particle has exactly one scheduled event (the
 * single-event scheme with collision counters, hard-spheres spec section 6.4). The calendar is the
 * two-level structure of Paul (2007) (spec 6.5): a small indexed binary heap holds the events of
 * the current time bucket, later buckets are unsorted linked lists; the key (time, particle index)
 * is a total order, so runs are deterministic and the event sequence does not depend on how the
 * calendar is tuned. Pair candidates come from per-particle neighbour lists with a shell (spec
 * 6.6, neighbour-list mode); a cell grid bins the lists' reference positions. Particles are
 * advanced lazily: a particle's stored position is valid at its own local time p.t.
 *
 * The engine knows no model: models configure the box, place particles, call mote_ev_rebuild,
 * run collisions and read positions through mote_ev_position. */
#ifndef MOTE_EVENT_H
#define MOTE_EVENT_H

#include "mote/core.h"

#include <stdint.h>

/* Event kinds: a pair collision, a wall hit, a neighbour-list expiry, and in field mode a hit on
 * an obstacle's face or corner. */
enum { MOTE_EV_NONE = 0, MOTE_EV_PAIR, MOTE_EV_WALL, MOTE_EV_NBR, MOTE_EV_SEG, MOTE_EV_CORNER };

/* Per-particle data, in two arrays of 64-byte records. The hot record holds everything a
 * neighbour's prediction reads (position, velocity, local time, counter), so that with the array
 * 64-byte aligned each neighbour costs one cache line; the cold record is touched only by the
 * particle's own events, its calendar links and list renewals (as the list reference of a
 * renewal's candidates). Kept apart they ran 2-5% faster than one 128-byte record with a hot and
 * a cold half (see engine.c). */
typedef struct {
    double r[3];            /* position at local time t (z unused in 2D) */
    double v[3];            /* velocity */
    double t;               /* local time of r */
    uint32_t count;         /* collision counter: incremented whenever v changes */
    uint16_t nnbr;          /* entries in the neighbour list */
    uint8_t kind;           /* MOTE_EV_* of the scheduled event */
    uint8_t flags;          /* MOTE_EV_EDGE: reference near a periodic face (minimum images),
                             * with MOTE_EV_WRAP_X << a for each such axis a;
                             * MOTE_EV_NEAR_WALL: reference within half a shell of a wall's
                             * contact plane (only then can a wall hit come before the list
                             * expires); MOTE_EV_MARK: scratch of a list renewal (clear between
                             * events) */
} mote_particle;

typedef struct {
    double t_ev;            /* time of the scheduled event */
    double r_ref[3];        /* reference position of the neighbour list */
    uint32_t partner;       /* PAIR: partner index; WALL: 2*axis + (upper wall ? 1 : 0) */
    uint32_t partner_count; /* PAIR: partner's counter when predicted */
    int32_t cell;           /* linear index of the cell holding r_ref */
    uint32_t label;         /* the model's number for the particle: its index at mote_ev_init,
                             * carried along when a rebuild reorders the records */
    uint32_t label_slot;    /* pc[k].label_slot is the index of the record labelled k */
    int32_t cal_slot;       /* calendar: -1 in the heap, 0..nbuckets-1 a bucket, nbuckets overflow */
    uint32_t cal_next;      /* in a bucket: next in its list; in the heap: position in the heap */
    uint32_t cal_prev;      /* in a bucket: previous in its list (MOTE_EV_NIL at the head) */
} mote_ev_cold;

#define MOTE_EV_NIL UINT32_MAX
enum { MOTE_EV_EDGE = 1, MOTE_EV_MARK = 2, MOTE_EV_NEAR_WALL = 4, MOTE_EV_WRAP_X = 8 };

/* Observer hooks (spec 6.9). rij = r_i - r_j at contact (minimum image), J = impulse on i.
 * on_event (field mode only, see mote_ev_field) is called after every event of particle i (both
 * partners of a pair), once i's new velocity is set: between two calls for the same particle it
 * flew along one parabola. */
typedef struct {
    void *ctx;
    void (*on_pair)(void *ctx, uint32_t i, uint32_t j, const double rij[3], const double J[3],
                    double t);
    void (*on_wall)(void *ctx, uint32_t i, int axis, int side, double momentum, double t);
    void (*on_event)(void *ctx, uint32_t i);
} mote_ev_observer;

/* ---- field mode (2D): uniform acceleration, fixed obstacles, the model's collision rules ----
 * For models such as the mixing box (specs/mixing-box.md). Every axis has walls (no periodic
 * axes). Flights are parabolas; pair collision times are unchanged by a uniform field (relative
 * motion stays straight), wall and segment times solve quadratics, corner times quartics.
 *
 * The engine finds the events; what happens at one is the model's (REBOUND's split between
 * finding and resolving collisions): at each event the engine brings the particles to the event
 * time and calls the model's rule, which sets the velocities after it. */

/* A flat face of a fixed obstacle: the segment a-b, hit from the side its unit normal n points
 * to (out of the solid). */
typedef struct {
    double a[2], b[2], n[2];
} mote_ev_segment;

/* The model's collision rules. Particles are named by their labels (the model's numbers), t is
 * the time since the engine's creation, velocities are updated in place. NULL members (or NULL
 * rules) are elastic: equal and opposite impulses along the line of centres; specular walls and
 * faces. */
typedef struct {
    void *ctx;
    /* two particles at contact, dr = r_i - r_j (their velocities approach: dr . (vi - vj) < 0) */
    void (*pair)(void *ctx, uint32_t i, uint32_t j, const double dr[2], double vi[2],
                 double vj[2], double t);
    /* particle i at the box wall of axis `axis` (side 0 at 0, 1 at len), moving into it or just
     * reflected by rounding */
    void (*wall)(void *ctx, uint32_t i, int axis, int side, double v[2], double t);
    /* particle i at obstacle face `which` (kind MOTE_EV_SEG) or corner `which` (MOTE_EV_CORNER),
     * n the unit normal out of the obstacle (at a corner, from the corner to the centre); called
     * only when it moves in (v . n < 0). Returns 1 when the velocity changed. */
    int (*face)(void *ctx, uint32_t i, int kind, uint32_t which, const double n[2], double v[2],
                double t);
} mote_ev_rules;

typedef struct {
    double g[2];             /* uniform acceleration */
    const mote_ev_segment *seg; /* obstacle faces (copied by mote_ev_set_field) */
    int nseg;
    const double (*corner)[2];  /* obstacle corners: points hit like disks of radius 0 */
    int ncorner;
    mote_ev_rules rules;
} mote_ev_field;

typedef struct {
    /* ---- geometry (set by the model before mote_ev_rebuild) ---- */
    int dim;              /* 2 or 3 */
    int periodic[3];      /* 1 = periodic axis, 0 = walls at 0 and len */
    double len[3];        /* box lengths; len[2] unused in 2D */

    /* ---- particles ---- */
    uint32_t n;
    mote_particle *p;     /* hot records */
    mote_ev_cold *pc;     /* cold records, same index */
    int spatial_order;    /* set by the model: every rebuild renumbers the records in spatial order
                           * (neighbours close in memory); users' numbers stay in `label` */
    double *radius;       /* NULL when monodisperse (then radius0/mass0 apply) */
    double *mass;
    double radius0, mass0;
    double sigma_max;     /* largest contact distance, 2 * max radius */

    /* ---- time and counters ---- */
    double clock;         /* time since the last rebuild */
    double time_total;    /* simulated time accumulated before the last rebuild */
    uint64_t collisions;      /* pair collisions since creation */
    uint64_t wall_collisions; /* wall hits since creation */
    uint64_t events;          /* all processed events (including stale and list) since creation */
    int halt;             /* set by an observer (field mode): the run returns after this event,
                           * and clears it */
    uint64_t stale_events;    /* pair events found stale (the partner changed course first) */
    uint64_t renewals;        /* neighbour-list renewals (list expiries) */
    uint64_t rebuilds;        /* automatic rebuilds (the clock reached t_rebuild) */
    double t_rebuild;     /* the clock value that triggers an automatic rebuild */
    int ready;            /* 1 after a successful mote_ev_rebuild; 0 before the first and after
                           * a failed one (lists, cells or calendar may be missing): running,
                           * moving walls and checking then fail until a rebuild succeeds */
    int canonical;        /* 1 right after a successful mote_ev_rebuild, until a run, a wall move
                           * or a velocity rescaling changes the system: a rebuild now would
                           * change nothing (a model's settle may skip it) */

    /* ---- neighbour lists (spec 6.6): pairs with |r_ref_i - r_ref_j| < sigma_ij + shell ---- */
    double shell;         /* delta, chosen at rebuild */
    double nbr_reach;     /* a list expires when |r - r_ref| reaches this (just under shell/2) */
    uint32_t *nbr;        /* n * nbr_cap entries; particle i's list starts at i * nbr_cap */
    uint32_t nbr_cap;     /* entries per particle; grows when a list would overflow */
    uint32_t *nbr_new;    /* nbr_cap entries: a renewing particle's new list while it is built */

    /* ---- cell grid binning the reference positions (cells at least sigma_max + shell wide) --- */
    int ncell[3];
    double cell_w[3];
    double cell_lo[3];    /* grid origin: 0 after a rebuild; wall moves shift it (see below) */
    double len_grid[3];   /* extent of the grid: the box length at the last rebuild */
    uint32_t *cell_block; /* per cell `cell_stride` words: a count, then that many particles */
    uint32_t cell_stride; /* grows when a cell would overflow */
    size_t cell_words;    /* words allocated for the blocks */

    /* ---- calendar (spec 6.5): heap of the current bucket, circular bucket lists, overflow ---- */
    int heap_only;        /* set by the caller: 1 = one plain indexed heap (the reference) */
    uint32_t *heap;       /* particle indices, heap ordered by (t_ev, index); capacity n */
    double *heap_t;       /* their event times, side by side with heap[] */
    uint32_t heap_n;
    uint32_t *bucket;     /* nbuckets + 1 list heads (the last is the overflow list) */
    uint32_t nbuckets;    /* a power of two */
    double bucket_inv;    /* 1 / bucket width (0 when heap_only) */
    int64_t bucket_cur;   /* absolute index of the bucket the heap holds */
    uint32_t walk;        /* the record of the next bucket's list fetched last (cal_walk) */

    /* ---- conserved-quantity references for the checker ---- */
    double energy_ref;
    double momentum_ref[3];

    mote_ev_observer obs;

    /* ---- field mode (NULL: plain hard particles); set with mote_ev_set_field ---- */
    mote_ev_field *field;
} mote_ev;

/* Allocate storage for n particles (positions etc. zeroed). The geometry fields are set by the
 * caller afterwards. polydisperse != 0 allocates per-particle radius and mass arrays. */
int mote_ev_init(mote_ev *ev, uint32_t n, int dim, int polydisperse, mote_err *err);
void mote_ev_free(mote_ev *ev);

static inline double mote_ev_radius(const mote_ev *ev, uint32_t i)
{
    return ev->radius ? ev->radius[i] : ev->radius0;
}
static inline double mote_ev_mass(const mote_ev *ev, uint32_t i)
{
    return ev->mass ? ev->mass[i] : ev->mass0;
}

/* Switch a 2D system with walls on both axes to field mode (copies f, its segments and
 * corners); call before mote_ev_rebuild. */
int mote_ev_set_field(mote_ev *ev, const mote_ev_field *f, mote_err *err);

/* Full synchronisation (spec 6.7): advance all particles to the clock, wrap periodic coordinates,
 * fold the clock into time_total, choose the shell, rebuild cells, neighbour lists and the
 * calendar, predict every event. Also sets sigma_max and t_rebuild. Fails if a periodic length
 * is not > 2 sigma_max. With spatial_order the records are first renumbered in Morton order of
 * cells 1.5 contact distances wide (ties by label), every per-particle datum moving along. The
 * result depends on the particles (with their labels) and the box only, not on history or on
 * the records' order before, so save -> load continues bit for bit. On failure (bad geometry,
 * out of memory) the particles keep their state but the engine is not `ready`. */
int mote_ev_rebuild(mote_ev *ev, mote_err *err);

/* Move the walls of wall axis `axis` without a full rebuild: every particle (and its list
 * reference) is shifted by -shift along the axis, with the cell grid, so cells and lists stay
 * valid, and the upper wall is put at new_len (the lower wall stays at 0). Only particles whose
 * list reference lies within half a shell of a wall contact plane (or with a wall hit scheduled)
 * are re-predicted, since no other prediction can involve a wall. When the moved grid would no
 * longer cover [0, new_len] (expansion), this falls back to a full rebuild. The caller
 * guarantees that no particle ends up beyond a wall. */
int mote_ev_move_walls(mote_ev *ev, int axis, double shift, double new_len, mote_err *err);

/* The index of the record that carries `label` (the model's particle number). Without
 * spatial_order the two are the same. */
static inline uint32_t mote_ev_slot(const mote_ev *ev, uint32_t label)
{
    return ev->pc[label].label_slot;
}

/* Record the current energy and momentum as the references the checker compares with. */
void mote_ev_set_reference(mote_ev *ev);

/* Run until `ncoll` further pair collisions have happened; stops right after the last one. */
int mote_ev_run(mote_ev *ev, uint64_t ncoll, mote_err *err);

/* Run until the time since creation reaches t_stop, or `ncoll` further pair collisions have
 * happened, whichever comes first. At t_stop the clock is set to it, so positions project to
 * that instant; after the ncoll-th collision it stops right there. */
int mote_ev_run_to(mote_ev *ev, double t_stop, uint64_t ncoll, mote_err *err);

/* Position of particle i projected to the current clock (periodic axes wrapped into [0, len)). */
void mote_ev_position(const mote_ev *ev, uint32_t i, double out[3]);

/* Velocity of particle i at the current clock (differs from p[i].v only in field mode). */
void mote_ev_velocity(const mote_ev *ev, uint32_t i, double out[3]);

/* Current simulated time since creation. */
static inline double mote_ev_time(const mote_ev *ev) { return ev->time_total + ev->clock; }

/* Kinetic energy sum m v^2 / 2 (compensated) and momentum. */
double mote_ev_energy(const mote_ev *ev);
void mote_ev_momentum(const mote_ev *ev, double P[3]);
/* kT_kin = sum m v^2 / (d N). */
double mote_ev_kt(const mote_ev *ev);
/* Rescale velocities so kT_kin = kt (then the caller should rebuild). */
void mote_ev_set_kt(mote_ev *ev, double kt);

/* Invariant checker (spec 6.10). Returns MOTE_OK or MOTE_ERUNTIME with every failure named in
 * err->msg (truncated if very long): overlaps, walls, cells, neighbour lists (symmetric, complete,
 * every particle within half a shell of its reference), the calendar, conserved quantities.
 * Messages name particles by their labels. O(N) with the cell grid. */
int mote_ev_check(const mote_ev *ev, mote_err *err);

/* Smallest pair distance ratio |r_ij| / sigma_ij over pairs in neighbouring cells (O(N)); the
 * pair's record indices are stored in *wi, *wj when those are not NULL (both 0 when N < 2). */
double mote_ev_min_gap_ratio(const mote_ev *ev, uint32_t *wi, uint32_t *wj);

/* List the pairs with |r_ij| < sigma_ij (1 - tol), ordered by (i, j) with i < j; stores at most
 * `max` of them and returns how many there are in all. Needs a rebuilt system (cells). */
size_t mote_ev_overlaps(const mote_ev *ev, double tol, uint32_t (*pairs)[2], size_t max);

/* Bytes of heap memory held per particle: records, neighbour lists, calendar, cells. */
double mote_ev_bytes_per_particle(const mote_ev *ev);

#endif
