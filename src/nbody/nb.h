/* nb.h: internal to the N-body model: what its files share. */
#ifndef MOTE_NB_INTERNAL_H
#define MOTE_NB_INTERNAL_H

#include "mote/datafile.h"
#include "mote/nbody.h"
#include "mote/statefile.h"

#include <stddef.h>
#include <tgmath.h>
#include <math.h> /* isfinite */

/* Render an N-body data file (trajectory: orbits; monitor: drifts) as a PNG (plot.c). */
int nb_plot_file(const char *data_path, const char *png_path, const mote_call *c, mote_err *err);
/* The time axis of a plot of data file t whose times T run from t0 to t1: with the physical
 * scales in its header (kt), the unit that reads best over the span (s, day or year)
 * and *scale such that T * *scale is in it; without them "dimensionless", scale 1. */
const char *nb_plot_time_unit(const mote_table *t, double t0, double t1, double *scale);

/* The state file (state.c): save, load (replacing nb on success only, which must have the
 * file's interaction), and the body count of a file's header (for validation). */
int nb_state_save(const mote_nb *nb, const char *path, mote_err *err);
/* The state file's descriptor table (its lines after the head: the common lines, then each
 * integrator's own, nb_integrator.fields), made into out (NB_STATE_FIELDS entries); its length.
 * For the bound parameter commands. */
#define NB_STATE_FIELDS 96
size_t nb_state_table(struct mote_sf_field *out);
/* mote_real to the digits that read back the same (MOTE_REAL_DIG): the state file's number
 * codec, and descriptors of mote_nb's values with it (an integrator's fields use them too) */
extern const mote_sf_codec nb_real_codec;
#define NB_SF_R(K, NAME, M)                                                                  \
    {.key = K, .name = NAME, .type = MOTE_SF_CODEC, .offset = offsetof(mote_nb, M),          \
     .codec = &nb_real_codec}
#define NB_SF_I(K, NAME, M, LO, HI)                                                          \
    {.key = K, .name = NAME, .type = MOTE_SF_INT, .offset = offsetof(mote_nb, M), .lo = LO,  \
     .hi = HI}
int nb_state_load(mote_nb *nb, const char *path, mote_err *err);
int nb_state_peek(const char *path, uint32_t *n, mote_err *err);
/* The same on an open stream: write the state's lines to f; read them from l (tail: lines may
 * follow the state's `end`, left for the caller; else nothing may). */
void nb_state_put(FILE *f, const mote_nb *nb);
int nb_state_get(mote_nb *nb, mote_lines *l, int tail, mote_err *err);

/* Orbital elements (orbit.c): the semi-major axis a (< 0 for a hyperbola), the eccentricity
 * e (not 1), the inclination, the longitude of the ascending node Omega, the argument of
 * pericentre omega, and the true anomaly f or (mean) the mean anomaly M (e < 1); radians. */
typedef struct {
    mote_real a, e, inc, Omega, omega, f, M;
    int mean;
} nb_elements;
/* The position and velocity relative to the primary on that orbit, mu = G (M_primary + m). */
void nb_orbit_xv(const nb_elements *el, mote_real mu, mote_real x[3], mote_real v[3]);

/* Galactica's initial-condition and result files (galfile.c, spec 7.5, 7.6): the header (24
 * numbers, Coulomb 25), the bodies (15 numbers each, Coulomb 16: om x y z u v w dUp(3) Sp(3) Ra
 * Et [Qo]) and the info line (date, k2, M_Ss, Am, k_v; info 0 none, 1 five numbers, 2 padded to
 * a body row). */
typedef struct {
    int coulomb, info;
    uint32_t n;
    mote_real head[25];
    mote_real *body;
    mote_real infov[5];
} nb_galfile;

/* Read (k2 >= 0: exactly k2 bodies; < 0: inferred from the count); err names the file, and the
 * line of a bad token or mass. */
int nb_galfile_read(const char *path, int coulomb, long k2, nb_galfile *g, mote_err *err);
void nb_galfile_free(nb_galfile *g);
/* Write (atomically) the header on two lines, a body per line, the info line when info_line. */
int nb_galfile_write(const char *path, const nb_galfile *g, int info_line, mote_err *err);
/* Replace nb's bodies, time and steps by the file's (its settings kept); nb unchanged on error. */
int nb_from_galfile(mote_nb *nb, const nb_galfile *g, const char *path, mote_err *err);
/* The scales of the file's info line (M_Ss, Am, k_v), when it has them and nb has none. */
void nb_units_from_info(mote_nb *nb, const nb_galfile *g);
/* The file of nb's state: the header computed (carry: the header read, for Em and the area
 * fields, or NULL); body holds n * (15 or 16) reals and becomes g->body. */
void nb_to_galfile(const mote_nb *nb, const mote_real carry[25], nb_galfile *g, mote_real *body);

/* Galactica's control file galacf26.dat (galctl.c, spec 7.2, 7.3): the 50 fixed lines (v[k] is
 * line k + 1; FIMA4 as text) and the trios ipp, jpp, kpp of the selected bodies. */
#define NB_GALCTL_FIXED 50
#define NB_GALCTL_TRIOS 256
typedef struct {
    double v[NB_GALCTL_FIXED];
    int have[NB_GALCTL_FIXED];  /* the line gave a value (else the default 0) */
    char fima4[256];
    int fima4_long;             /* longer than Galactica's 12 characters */
    char date[16];              /* the date of the file variant, from line 1 */
    int ntrio;
    long trio[NB_GALCTL_TRIOS][3];
} nb_galctl;

/* Read a control file: lenient takes each line's last token, packed the trios at 51-53, 54-56;
 * err names the file, line and parameter. */
int nb_galctl_read(const char *path, int lenient, int packed, nb_galctl *g, mote_err *err);
/* Write the prose layout: descriptions, values from column 60, line 53 reserved. */
int nb_galctl_write(const char *path, const nb_galctl *g, mote_err *err);
/* The line index of a parameter name (A, B, ..., Kl15), or -1; its value (NAN: no such). */
int nb_galctl_index(const char *name);
double nb_galctl_get(const nb_galctl *g, const char *name);

/* Galactica-style pictures (frames.c, spec 7.13): the graphics values (from a control file and
 * the header's area fields, or set by hand), and one 1024 x 768 PNG of nb; zoom is the Kl14
 * scale, which shrinks as bodies would leave the picture. */
typedef struct {
    double al, bet, Xe0, Ye0, aix, biy, Rd, amv;
    int Kl10, Kl14;
    long Ke;                    /* the Z layer of an area to draw (0: all) */
    int ntrio;
    const long (*trio)[3];      /* ipp, jpp, kpp */
    long np;                    /* selected bodies (Np) */
    long per_layer, nlayers;    /* an area's bodies per Z layer, and its layers */
    double zoom;
} nb_frame_opts;
void nb_frame_from_ctl(nb_frame_opts *f, const nb_galctl *c, const mote_real head[25]);
int nb_frame_png(const mote_nb *nb, nb_frame_opts *f, const char *path, uint64_t Lt,
                 mote_err *err);

/* The snapshot (snapshot.c, spec 10.2): the header every output shares (interaction, N,
 * integrator, precision) and the scales and constants; write; read (replacing nb on success
 * only; the file's interaction must be nb's). */
void nb_write_header(FILE *f, const mote_nb *nb);
void nb_write_units(FILE *f, const mote_nb *nb);
int nb_snapshot_write(const mote_nb *nb, const char *path, const char *origin, mote_err *err);
int nb_snapshot_read(mote_nb *nb, const char *path, mote_err *err);

/* An integrator as a plug-in (integrators.c): its name (as snapshot files write it), its check
 * (the settings, and the scratch sized), and how it advances: `step`, one step of at most `rest`
 * (returns the step taken), or `run`, a synchronised run of at most max_steps steps ending at
 * t_end exactly (the Wisdom-Holman map: merges and bounds are looked at where it ends); the
 * blocks its force tree needs; dense: the state at any time inside the step just taken
 * (mote_nb_taylor_dense); synchronised: its steps leave the state between its own stops in
 * another form (an output by time makes it stop there); order_max: the highest order= (0:
 * none). */
typedef struct nb_integrator {
    const char *name;
    int (*check)(mote_nb *nb, mote_err *err);
    mote_real (*step)(mote_nb *nb, mote_real rest);
    int (*run)(mote_nb *nb, uint64_t max_steps, mote_real t_end, mote_err *err);
    int (*tree_blocks)(const mote_nb *nb);
    /* its defaults, set when it is chosen (`integrator NAME`, before the command's options) */
    void (*chosen)(mote_nb *nb);
    /* its settings as `# KEY = VALUE` lines of the output headers (integrator = NAME first) */
    void (*header)(FILE *f, const mote_nb *nb);
    int dense, synchronised, order_max;
    /* its own lines of the state file (version 4 on; every integrator's are written, in the
     * order of their numbers, so a later choice finds its settings), and what is wrong with the
     * values of its line `key` just read (nonzero: why, "KEY: need ...", into why) */
    const struct mote_sf_field *fields;
    size_t nfields;
    int (*state_bad)(const mote_nb *nb, const char *key, char *why, size_t size);
} nb_integrator;
/* How many integrators there are (their numbers 0 .. NB_INTEGRATORS - 1). */
#define NB_INTEGRATORS 3
/* By its number (MOTE_NB_GALACTICA, MOTE_NB_TAYLOR, MOTE_NB_WH); its number by name, -1 none. */
const nb_integrator *nb_integrator_of(int id);
int nb_integrator_named(const char *name);

/* The integrators' parts (galactica.c, taylor.c): the settings checked (and scratch sized),
 * and one step of at most `rest` (returns the step taken). */
int nb_galactica_check(const mote_nb *nb, mote_err *err);
mote_real nb_galactica_step(mote_nb *nb, mote_real rest);
int nb_taylor_check(mote_nb *nb, mote_err *err);
mote_real nb_taylor_step(mote_nb *nb, mote_real rest);
/* The Wisdom-Holman map (wh.c): its settings checked; at most max_steps steps of dt, the last
 * shortened to end at t_end exactly, from the inertial state back to it (one synchronisation). */
int nb_wh_check(const mote_nb *nb, mote_err *err);
int nb_wh_integrate(mote_nb *nb, uint64_t max_steps, mote_real t_end, mote_err *err);
/* Room for the map's state of every body (nb->wh_map; 0 when out of memory), and body i's 13
 * reals there: Jacobi q (3), u (3), the synchronised x (3), v (3) and mass (state.c). */
int nb_wh_reserve(mote_nb *nb);
mote_real *nb_wh_map(const mote_nb *nb, uint32_t i);

/* y += d with the compensation term *cs (Kahan: the rounding error of one addition is carried
 * into the next; cs = y - the true sum). `on` = 0: a plain addition. */
static inline void kahan_add(mote_real *y, mote_real *cs, mote_real d, int on)
{
    if (!on) {
        *y += d;
        return;
    }
    mote_real t = d - *cs, s = *y + t;
    *cs = (s - *y) - t;
    *y = s;
}

/* A type at least as wide as long double: the Taylor update's sums, Kepler's equation */
#if MOTE_NB_PRECISION == 4
typedef mote_real nb_wide;
#else
typedef long double nb_wide;
#endif

/* Compensated (Neumaier) sum in the real type, for the energies */
typedef struct {
    mote_real sum, comp;
} nb_ksum;
static inline void nb_ksum_add(nb_ksum *k, mote_real x)
{
    mote_real t = k->sum + x;
    if ((k->sum >= 0 ? k->sum : -k->sum) >= (x >= 0 ? x : -x))
        k->comp += (k->sum - t) + x;
    else
        k->comp += (x - t) + k->sum;
    k->sum = t;
}
static inline mote_real nb_ksum_value(const nb_ksum *k) { return k->sum + k->comp; }

/* The adaptive step's bounds (spec 4.5, both integrators): h times safety, at most twice the
 * previous step, within [hmin, hmax]; `idle` when nothing moves (h infinite). */
static inline mote_real nb_step_bounds(mote_nb *nb, mote_real h, mote_real idle)
{
    h *= nb->safety > 0 ? nb->safety : 1;
    if (nb->hprev > 0 && h > 2 * nb->hprev)
        h = 2 * nb->hprev;
    if (nb->hmax > 0 && h > nb->hmax)
        h = nb->hmax;
    if (h < nb->hmin) { /* longer than the tolerance allows: counted, and integrate warns */
        h = nb->hmin;
        nb->hmin_forced++;
    }
    return isfinite(h) ? h : idle;
}

/* Closest approaches of one body (approach.c, spec 7.9, 10.4): sampled at step ends, refined
 * inside steps from the step's polynomial; one row (T_min, body 1..n or 0, distance, relative
 * speed) per interval. */
typedef struct {
    uint32_t body;       /* 0-based */
    int refine;
    mote_real *x0;       /* Galactica refine: x, v and d5p before the step (3 blocks of 3n) */
    size_t cap;
    mote_real dtp0;
    int restart0;
    mote_real best, t, speed; /* this interval's closest approach (best < 0: none yet) */
    uint32_t with;
    double *rows;        /* 4 per interval */
    size_t nrows, rowcap;
} nb_approach;
int nb_approach_init(nb_approach *a, uint32_t body, int refine, mote_err *err);
void nb_approach_free(nb_approach *a);
/* Before a step (saves what the Galactica scheme's polynomial needs), after it (from Tb; merged:
 * a merge changed the bodies, so the polynomial is not theirs), and at an interval's end. */
int nb_approach_before(nb_approach *a, const mote_nb *nb, mote_err *err);
void nb_approach_after(nb_approach *a, const mote_nb *nb, mote_real Tb, int merged);
int nb_approach_close(nb_approach *a, mote_real T, mote_err *err);
/* Append a row (T_min, body, distance, speed), as a checkpoint restores them. */
int nb_approach_push(nb_approach *a, const double row[4], mote_err *err);

/* The Barnes-Hut tree (tree.c, spec 6.2). check: room for `blocks` blocks of cell data (and the
 * charges of one sign); build: from the positions, at a step's start; fill: the cells' block b
 * from the bodies' 3-per-body src; walk: every source of target i in a fixed order (a body, or
 * a cell with nb_tree_weight and its data at nb_tree_block(b) + 3 cell). */
typedef struct nb_tree nb_tree;
int nb_tree_check(mote_nb *nb, int blocks, mote_err *err);
void nb_tree_free(mote_nb *nb);
void nb_tree_build(mote_nb *nb);
void nb_tree_fill(mote_nb *nb, int block, const mote_real *src);
const mote_real *nb_tree_block(const mote_nb *nb, int block);
void nb_tree_walk(const mote_nb *nb, uint32_t i, void (*visit)(uint32_t, int, void *), void *arg);
mote_real nb_tree_weight(const mote_nb *nb, uint32_t cell);
/* The walk of target i as a list in *src (grown as needed: *cap), a body's index or NB_TREE_CELL
 * | a cell's; the count, or (size_t)-1 when memory ran out. */
#define NB_TREE_CELL 0x80000000u
/* The active bodies in tree order (neighbours next to each other): targets taken in this order
 * find their sources in the cache; *count of them. */
const uint32_t *nb_tree_order(const mote_nb *nb, uint32_t *count);
size_t nb_tree_list(const mote_nb *nb, uint32_t i, uint32_t **src, size_t *cap);

/* The pair terms of the Galactica scheme's passes (spec 4.2) for target i and source k: pass 1
 * adds A0 and A1 to a and j; pass 2 adds A2 and A3 to s4 and s5 (w: the source's weight; e2 the
 * softening squared, added to r^2: the derivatives of s = r^2 + e2 are those of r^2, so the
 * terms keep their form). */
static inline void nb_pair1(const mote_real *xi, const mote_real *vi, const mote_real *xk,
                            const mote_real *vk, mote_real w, mote_real e2, mote_real a[3],
                            mote_real j[3])
{
    mote_real r[3] = {xi[0] - xk[0], xi[1] - xk[1], xi[2] - xk[2]};
    mote_real u[3] = {vi[0] - vk[0], vi[1] - vk[1], vi[2] - vk[2]};
    mote_real r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + e2;
    mote_real i2 = 1 / r2, wr3 = w * i2 * sqrt(i2);
    mote_real alpha = (r[0] * u[0] + r[1] * u[1] + r[2] * u[2]) * i2;
    for (int c = 0; c < 3; c++) {
        mote_real A0 = wr3 * r[c];
        a[c] += A0;
        j[c] += wr3 * u[c] - 3 * alpha * A0;
    }
}

static inline void nb_pair2(const mote_real *xi, const mote_real *vi, const mote_real *ai,
                            const mote_real *ji, const mote_real *xk, const mote_real *vk,
                            const mote_real *ak, const mote_real *jk, mote_real w,
                            mote_real e2, mote_real s4[3], mote_real s5[3])
{
    mote_real r[3], u[3], ac[3], jc[3];
    for (int c = 0; c < 3; c++) {
        r[c] = xi[c] - xk[c];
        u[c] = vi[c] - vk[c];
        ac[c] = ai[c] - ak[c];
        jc[c] = ji[c] - jk[c];
    }
    mote_real r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + e2;
    mote_real i2 = 1 / r2, wr3 = w * i2 * sqrt(i2);
    mote_real rv = r[0] * u[0] + r[1] * u[1] + r[2] * u[2];
    mote_real vv = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    mote_real ra = r[0] * ac[0] + r[1] * ac[1] + r[2] * ac[2];
    mote_real va = u[0] * ac[0] + u[1] * ac[1] + u[2] * ac[2];
    mote_real rj = r[0] * jc[0] + r[1] * jc[1] + r[2] * jc[2];
    mote_real alpha = rv * i2;
    mote_real beta = (vv + ra) * i2 + alpha * alpha;
    mote_real gamma = (3 * va + rj) * i2 + alpha * (3 * beta - 4 * alpha * alpha);
    for (int c = 0; c < 3; c++) {
        mote_real A0 = wr3 * r[c];
        mote_real A1 = wr3 * u[c] - 3 * alpha * A0;
        mote_real A2 = wr3 * ac[c] - 6 * alpha * A1 - 3 * beta * A0;
        mote_real A3 = wr3 * jc[c] - 9 * alpha * A2 - 9 * beta * A1 - 3 * gamma * A0;
        s4[c] += A2;
        s5[c] += A3;
    }
}

/* MPI (mpi.c, spec 6.3): this rank's block of bodies into nb (lo, hi, rank, size; one process:
 * all); the rank (0 without MPI); the all-gather of `per` reals a body of array a from every
 * rank's block. */
void nb_mpi_layout(mote_nb *nb);
int nb_mpi_rank(void);
void nb_mpi_gather(const mote_nb *nb, mote_real *a, size_t per);

/* Run nb's integrator as `integrator` for at most `steps` steps (integrate.c). */
int nb_run_as(mote_nb *nb, int integrator, uint64_t steps, mote_err *err);
/* Threads are used for the pair passes from this many bodies up: below it a pass is shorter than
 * the cost of waking threads, and on a loaded machine a thread waiting for a descheduled one
 * made N = 100 with 2 threads 7x slower than one (measured with two busy processes beside it on
 * 2 cores: N = 300 2.8x slower, N = 1000 1.3x faster; quiet, the two are even near N = 300). */
#define NB_THREADS_MIN_N 1000
/* Bounds on what an input can ask for (issue 33): the bodies `generate plummer` makes, the nodes
 * of a Galactica area, the memory a body takes (arrays of the Galactica scheme, capacity doubled:
 * measured 400 B a body at N = 10^5), and the bodies above which the status line leaves out the
 * energy (an O(N^2) sum; the monitor measures it). */
#define NB_MAX_GENERATED 10000000
#define NB_MAX_AREA 1000000
#define NB_BODY_BYTES 600.0
#define NB_STATUS_MAX_N 50000
/* Every active body's position, velocity and mass within NB_VALUE_MAX in magnitude (so that
 * energies and squared distances cannot overflow) and the time finite; else MOTE_ERUNTIME naming
 * the body and the value. Checked before a run and after every step. */
#define NB_VALUE_MAX 1e100
int nb_state_bounded(const mote_nb *nb, mote_err *err);

/* Is merging on for this system (the default: when any active body has a radius)? */
int nb_merging_on(const mote_nb *nb);

#endif
