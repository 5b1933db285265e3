/* system.c: the mixing-box system: parameters and their check, random placement of the two
 * gases, the state measurements every part of the model uses (chamber counts, mixing fraction
 * and entropy, energies, overlap counts), the sampling hooks integrators call, and mote_mb_run,
 * which dispatches a run to the time-stepped or the event-driven integrator. */
#include "mb.h"
#include "mote/event.h"


#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- parameters ------------------------------------------------------------------------------ */

void mote_mb_params_default(mote_mb_params *p)
{
    memset(p, 0, sizeof *p);
    p->x_l = 0.0;
    p->x_r = 2.0;
    p->x_b = 0.0;
    p->x_t = 1.0;
    p->x1_c = 1.0;
    p->a = 0.02;
    p->x2_c = 0.5;
    p->b = 0.1;
    p->r = 0.005;
    p->n_left = 500;
    p->n_right = 500;
    p->v_init = 1.0;
    p->t_c = NAN;
    p->mass = 1.0;
    p->integrator = MOTE_MB_DEFAULT_INTEGRATOR;
    p->rule = MOTE_MB_RESTITUTION;
}

double mote_mb_tc(const mote_mb_params *p)
{
    if (!isnan(p->t_c))
        return p->t_c;
    double v = p->v_init > 0 ? p->v_init : 0.1;
    return p->r / (100.0 * v);
}

static double chamber_width(const mote_mb_params *p, int chamber)
{
    return chamber == 0 ? mote_mb_x1_l(p) - p->x_l : p->x_r - mote_mb_x1_r(p);
}

double mote_mb_area_fraction(const mote_mb_params *p, int chamber)
{
    double area = chamber_width(p, chamber) * (p->x_t - p->x_b);
    double n = (double)(chamber == 0 ? p->n_left : p->n_right);
    return area > 0 ? n * MOTE_PI * p->r * p->r / area : INFINITY;
}

int mb_params_check(const mote_mb_params *p, int *groups, mote_err *err)
{
    int dummy;
    if (!groups)
        groups = &dummy;
#define FAIL(g, ...) return (*groups = (g), mote_fail(err, MOTE_EINVAL, __VA_ARGS__))
    if (!(p->x_l < p->x_r))
        FAIL(MB_P_BOX, "box: X_L = %g must be below X_R = %g", p->x_l, p->x_r);
    if (!(p->x_b < p->x_t))
        FAIL(MB_P_BOX, "box: X_B = %g must be below X_T = %g", p->x_b, p->x_t);
    if (!(p->r > 0))
        FAIL(MB_P_RADIUS, "radius: R = %g must be > 0", p->r);
    if (!(p->mass > 0) || !isfinite(p->mass))
        FAIL(0, "the disk mass = %g must be > 0 and finite", p->mass);
    /* positions are doubles: a box far larger than a disk cannot resolve the disks (and its
     * cell grid would not fit in memory) */
    if (!(p->x_r - p->x_l <= 1e9 * 2 * p->r) || !(p->x_t - p->x_b <= 1e9 * 2 * p->r))
        FAIL(MB_P_BOX | MB_P_RADIUS,
             "box: %g x %g is more than 10^9 disk diameters (2R = %g) wide or high",
             p->x_r - p->x_l, p->x_t - p->x_b, 2 * p->r);
    if (!(p->a > 0))
        FAIL(MB_P_PARTITION, "partition: the thickness a = %g must be > 0", p->a);
    double x1l = mote_mb_x1_l(p), x1r = mote_mb_x1_r(p);
    if (!(x1l > p->x_l && x1r < p->x_r))
        FAIL(MB_P_PARTITION | MB_P_BOX,
             "partition: its faces X1_C -/+ a/2 = %g, %g must lie inside the box, X_L = %g < "
             "X1_L and X1_R < X_R = %g",
             x1l, x1r, p->x_l, p->x_r);
    double d = 2 * p->r;
    if (!(p->x_t - p->x_b >= d))
        FAIL(MB_P_BOX | MB_P_RADIUS,
             "box: the height X_T - X_B = %g is less than a disk's diameter 2R = %g",
             p->x_t - p->x_b, d);
    if (!(x1l - p->x_l >= d))
        FAIL(MB_P_BOX | MB_P_PARTITION | MB_P_RADIUS,
             "the left chamber is %g wide (X1_L - X_L), less than a disk's diameter 2R = %g",
             x1l - p->x_l, d);
    if (!(p->x_r - x1r >= d))
        FAIL(MB_P_BOX | MB_P_PARTITION | MB_P_RADIUS,
             "the right chamber is %g wide (X_R - X1_R), less than a disk's diameter 2R = %g",
             p->x_r - x1r, d);
    if (!(p->b >= 0))
        FAIL(MB_P_SLIT, "slit: the height b = %g must be >= 0 (0 closes the partition)", p->b);
    if (p->b > 0) {
        if (!(p->b > d))
            FAIL(MB_P_SLIT | MB_P_RADIUS,
                 "slit: the height b = %g must exceed a disk's diameter 2R = %g so that disks "
                 "can pass (or be 0 to close the partition)",
                 p->b, d);
        double y2b = mote_mb_x2_b(p), y2t = mote_mb_x2_t(p);
        if (!(y2b >= p->x_b && y2t <= p->x_t))
            FAIL(MB_P_SLIT | MB_P_BOX,
                 "slit: X2_C -/+ b/2 = %g, %g must lie inside the box height X_B = %g .. X_T = "
                 "%g",
                 y2b, y2t, p->x_b, p->x_t);
    }
    if (p->n_left < 0 || p->n_right < 0 || p->n_left + p->n_right < 1 ||
        p->n_left + p->n_right > MB_N_MAX)
        FAIL(MB_P_DISKS, "disks: nLeft + nRight = %lld must be in 1 .. %d",
             (long long)(p->n_left + p->n_right), MB_N_MAX);
    for (int c = 0; c < 2; c++) {
        double phi = mote_mb_area_fraction(p, c);
        if (!(phi <= MOTE_MB_PHI_MAX))
            FAIL(MB_P_DISKS | MB_P_RADIUS | MB_P_BOX | MB_P_PARTITION,
                 "the %s chamber is too dense for random placement: %lld disks of R = %g in "
                 "%g x %g give the area fraction n pi R^2 / area = %.4g, above %.2f (random "
                 "placement jams near 0.547)",
                 c ? "right" : "left", (long long)(c ? p->n_right : p->n_left), p->r,
                 chamber_width(p, c), p->x_t - p->x_b, phi, MOTE_MB_PHI_MAX);
    }
    if (!(p->v_init >= 0))
        FAIL(MB_P_VINIT, "v_init: V_init = %g must be >= 0", p->v_init);
    if (!(p->dv_b >= 0 && p->dv_t >= 0 && p->dv_s >= 0))
        FAIL(MB_P_KICKS, "kicks: dV_B = %g, dV_T = %g, dV_S = %g must all be >= 0", p->dv_b,
             p->dv_t, p->dv_s);
    if (!(p->loss >= 0 && p->loss <= 1))
        FAIL(MB_P_LOSS, "loss: %g must be in [0, 1]", p->loss);
    if (!isnan(p->t_c) && !(p->t_c >= 0))
        FAIL(MB_P_TC, "t_c: %g must be >= 0", p->t_c);
#undef FAIL
    *groups = 0;
    return MOTE_OK;
}

int mote_mb_params_check(const mote_mb_params *p, mote_err *err)
{
    return mb_params_check(p, NULL, err);
}

/* ---- lifetime and placement ------------------------------------------------------------------ */

void mote_mb_init(mote_mb *sys)
{
    memset(sys, 0, sizeof *sys);
    mote_mb_params_default(&sys->p);
    sys->seed = 1;
    mote_rng_seed(&sys->rng, 1);
}

static void free_arrays(mote_mb *sys)
{
    free(sys->x);
    free(sys->y);
    free(sys->vx);
    free(sys->vy);
    free(sys->colour);
    free(sys->side);
    free(sys->t_last);
    sys->x = sys->y = sys->vx = sys->vy = sys->t_last = NULL;
    sys->colour = NULL;
    sys->side = NULL;
}

static void drop_cache(mote_mb *sys)
{
    if (sys->integrator_cache && sys->integrator_cache_free)
        sys->integrator_cache_free(sys->integrator_cache);
    sys->integrator_cache = NULL;
    sys->integrator_cache_free = NULL;
}

void mote_mb_free(mote_mb *sys)
{
    free_arrays(sys);
    drop_cache(sys);
    if (sys->grid) {
        mote_grid_free(sys->grid);
        free(sys->grid);
        sys->grid = NULL;
    }
    sys->placed = 0;
    sys->n = 0;
}

int mb_grid_setup(mote_grid *g, const mote_mb_params *p, uint32_t n)
{
    const double lo[3] = {p->x_l, p->x_b, 0}, len[3] = {p->x_r - p->x_l, p->x_t - p->x_b, 0};
    const int walls[3] = {0, 0, 0};
    return mote_grid_setup(g, 2, lo, len, walls, 2 * p->r, n);
}

void mb_grid_build(mote_grid *g, uint32_t n, const double *x, const double *y)
{
    const double *coord[3] = {x, y, NULL};
    mote_grid_build(g, n, coord, 1);
}

int mb_ensure_grid(mote_mb *sys)
{
    const mote_mb_params *p = &sys->p;
    if (!sys->grid) {
        sys->grid = calloc(1, sizeof *sys->grid);
        if (!sys->grid)
            return -1;
        sys->grid_ready = 0;
    }
    /* The layout depends only on the box, R and N, which are fixed from placement on. */
    if (!sys->grid_ready) {
        if (mb_grid_setup(sys->grid, p, sys->n))
            return -1;
        sys->grid_ready = 1;
    }
    return 0;
}

/* Placement, where disks arrive one at a time: the shared grid's cells, with a linked list of
 * the disks placed so far in each. */
typedef struct {
    mote_grid cells;
    int32_t *head, *next;
} place_grid;

static int place_grid_init(place_grid *g, const mote_mb_params *p, uint32_t n)
{
    if (mb_grid_setup(&g->cells, p, n))
        return -1;
    g->head = malloc(g->cells.ncells * sizeof *g->head);
    g->next = malloc((n ? n : 1) * sizeof *g->next);
    if (!g->head || !g->next)
        return -1;
    for (size_t k = 0; k < g->cells.ncells; k++)
        g->head[k] = -1;
    return 0;
}

/* Place one chamber's disks [first, first + count) in [xlo, xhi] x [ylo, yhi]. */
static int place_chamber(mote_mb *sys, place_grid *g, uint32_t first, uint32_t count,
                         double xlo, double xhi, double ylo, double yhi, int colour,
                         mote_err *err)
{
    const double d2 = 4.0 * sys->p.r * sys->p.r;
    for (uint32_t k = 0; k < count; k++) {
        uint32_t i = first + k;
        double x = 0, y = 0;
        long tries = 0;
        size_t c = 0;
        for (;;) {
            if (tries++ >= MOTE_MB_PLACE_TRIES) {
                const mote_mb_params *p = &sys->p;
                return mote_fail(err, MOTE_ERUNTIME,
                                 "place: disk %u of %u in the %s chamber did not fit after %d "
                                 "random tries: the chamber is too dense for random placement "
                                 "(area fraction n pi R^2 / area = %.4g; random placement jams "
                                 "near 0.547 and slows down well before); use fewer or smaller "
                                 "disks or a larger chamber",
                                 k + 1, count, colour ? "right" : "left", MOTE_MB_PLACE_TRIES,
                                 mote_mb_area_fraction(p, colour));
            }
            x = xlo + (xhi - xlo) * mote_rng_uniform(&sys->rng);
            y = ylo + (yhi - ylo) * mote_rng_uniform(&sys->rng);
            const double at[3] = {x, y, 0};
            c = mote_grid_cell_of(&g->cells, at);
            size_t near[27];
            double shift[27][3];
            int nn = mote_grid_neighbours(&g->cells, c, near, shift), free_spot = 1;
            for (int q = 0; q < nn && free_spot; q++)
                for (int32_t j = g->head[near[q]]; j >= 0; j = g->next[j]) {
                    double dx = sys->x[j] - x, dy = sys->y[j] - y;
                    if (dx * dx + dy * dy < d2) {
                        free_spot = 0;
                        break;
                    }
                }
            if (free_spot)
                break;
        }
        double angle = 2.0 * MOTE_PI * mote_rng_uniform(&sys->rng);
        sys->x[i] = x;
        sys->y[i] = y;
        sys->vx[i] = sys->p.v_init * cos(angle);
        sys->vy[i] = sys->p.v_init * sin(angle);
        sys->colour[i] = colour;
        sys->side[i] = (uint8_t)mote_mb_chamber(sys, x);
        sys->t_last[i] = -INFINITY;
        g->next[i] = g->head[c];
        g->head[c] = (int32_t)i;
    }
    return MOTE_OK;
}

void mote_mb_seed(mote_mb *sys, uint64_t seed)
{
    sys->seed = seed;
    mote_rng_seed(&sys->rng, seed);
}

int mote_mb_place(mote_mb *sys, const mote_mb_params *p, mote_err *err)
{
    int rc = mote_mb_params_check(p, err);
    if (rc)
        return rc;
    mote_mb old = *sys;
    mote_mb fresh;
    memset(&fresh, 0, sizeof fresh);
    fresh.p = *p;
    fresh.seed = old.seed;
    fresh.rng = old.rng;
    fresh.grid = old.grid;
    uint32_t n = (uint32_t)(p->n_left + p->n_right);
    fresh.n = n;
    fresh.x = malloc(n * sizeof *fresh.x);
    fresh.y = malloc(n * sizeof *fresh.y);
    fresh.vx = malloc(n * sizeof *fresh.vx);
    fresh.vy = malloc(n * sizeof *fresh.vy);
    fresh.colour = malloc(n * sizeof *fresh.colour);
    fresh.side = malloc(n * sizeof *fresh.side);
    fresh.t_last = malloc(n * sizeof *fresh.t_last);
    place_grid g = {0};
    if (!fresh.x || !fresh.y || !fresh.vx || !fresh.vy || !fresh.colour || !fresh.side ||
        !fresh.t_last || place_grid_init(&g, p, n)) {
        rc = mote_fail(err, MOTE_ENOMEM, "place: out of memory for %u disks", n);
    } else {
        double ylo = p->x_b + p->r, yhi = p->x_t - p->r;
        rc = place_chamber(&fresh, &g, 0, (uint32_t)p->n_left, p->x_l + p->r,
                           mote_mb_x1_l(p) - p->r, ylo, yhi, 0, err);
        if (!rc)
            rc = place_chamber(&fresh, &g, (uint32_t)p->n_left, (uint32_t)p->n_right,
                               mote_mb_x1_r(p) + p->r, p->x_r - p->r, ylo, yhi, 1, err);
    }
    free(g.head);
    free(g.next);
    mote_grid_free(&g.cells);
    if (rc) {
        free_arrays(&fresh);
        sys->rng = fresh.rng;
        return rc;
    }
    free_arrays(&old);
    if (old.integrator_cache && old.integrator_cache_free)
        old.integrator_cache_free(old.integrator_cache);
    fresh.placed = 1;
    fresh.generation = old.generation + 1;
    *sys = fresh;
    return MOTE_OK;
}

/* ---- measurements on the state --------------------------------------------------------------- */

mote_mb_tally mote_mb_counts(const mote_mb *sys)
{
    mote_mb_tally t = {{{0, 0}, {0, 0}}};
    for (uint32_t i = 0; i < sys->n; i++)
        t.n[sys->side[i] ? 1 : 0][sys->colour[i] ? 1 : 0]++;
    return t;
}

double mote_mb_mixing_fraction(const mote_mb_tally *t)
{
    uint64_t total = t->n[0][0] + t->n[0][1] + t->n[1][0] + t->n[1][1];
    return total ? (double)(t->n[1][0] + t->n[0][1]) / (double)total : 0.0;
}

double mote_mb_entropy(uint64_t n0, uint64_t n1)
{
    uint64_t n = n0 + n1;
    if (n == 0)
        return 0.0;
    double s = 0.0;
    if (n0) {
        double x = (double)n0 / (double)n;
        s -= x * log(x);
    }
    if (n1) {
        double x = (double)n1 / (double)n;
        s -= x * log(x);
    }
    return s;
}

double mote_mb_mixing_equilibrium(const mote_mb_params *p)
{
    double al = chamber_width(p, 0), ar = chamber_width(p, 1);
    double n = (double)(p->n_left + p->n_right);
    if (!(n > 0) || !(al + ar > 0))
        return 0.0;
    return ((double)p->n_left * ar + (double)p->n_right * al) / (n * (al + ar));
}

double mote_mb_energy(const mote_mb *sys, double *kinetic)
{
    mote_ksum ek = {0, 0}, ep = {0, 0};
    const double m = sys->p.mass, g = sys->p.g, yb = sys->p.x_b;
    for (uint32_t i = 0; i < sys->n; i++) {
        mote_ksum_add(&ek, 0.5 * m * (sys->vx[i] * sys->vx[i] + sys->vy[i] * sys->vy[i]));
        if (g != 0)
            mote_ksum_add(&ep, m * g * (sys->y[i] - yb));
    }
    double k = mote_ksum_value(&ek);
    if (kinetic)
        *kinetic = k;
    return k + mote_ksum_value(&ep);
}

double mote_mb_chamber_kt(const mote_mb *sys, int chamber, uint64_t *count)
{
    mote_ksum ek = {0, 0};
    uint64_t c = 0;
    for (uint32_t i = 0; i < sys->n; i++) {
        if ((sys->side[i] ? 1 : 0) != chamber)
            continue;
        c++;
        mote_ksum_add(&ek, 0.5 * sys->p.mass *
                               (sys->vx[i] * sys->vx[i] + sys->vy[i] * sys->vy[i]));
    }
    if (count)
        *count = c;
    return c ? mote_ksum_value(&ek) / (double)c : 0.0;
}

uint64_t mote_mb_count_overlaps(mote_mb *sys, double tol)
{
    if (sys->n < 2)
        return 0;
    const mote_mb_params *p = &sys->p;
    if (mb_ensure_grid(sys))
        return UINT64_MAX;
    mb_grid_build(sys->grid, sys->n, sys->x, sys->y);
    return mote_grid_pairs(sys->grid, 2 * p->r * (1 - tol), NULL, NULL);
}

void mote_mb_note_overlaps(mote_mb *sys, uint64_t count)
{
    sys->overlaps_last = count;
    if (count > sys->overlaps_max)
        sys->overlaps_max = count;
}

/* ---- progress ------------------------------------------------------------------------------- */

int mote_mb_progress(mote_loop *loop, const mote_mb *sys)
{
    return mote_loop_progress(loop, mote_mb_live_time(sys), sys->collisions);
}

/* ---- running --------------------------------------------------------------------------------- */

int mote_mb_run(mote_mb *sys, double t_end, const mote_loop *loop, mote_err *err)
{
    if (!sys->placed)
        return mote_fail(err, MOTE_EINVAL, "run: no disks are placed yet");
    const mote_loop none = {NULL, 0, UINT64_MAX, NULL, 0, 0, 0, 0};
    if (!loop)
        loop = &none;
    if (!(t_end >= sys->time))
        return mote_fail(err, MOTE_EINVAL, "run: the end time %g is before the current time %g",
                         t_end, sys->time);
    sys->overlaps_max = 0;
    sys->overlap_steps = 0;
    uint64_t ov = mote_mb_count_overlaps(sys, MOTE_MB_OVERLAP_TOL);
    if (ov == UINT64_MAX)
        return mote_fail(err, MOTE_ENOMEM, "run: out of memory");
    mote_mb_note_overlaps(sys, ov);
    if (sys->p.integrator == MOTE_MB_EVENT) {
        /* exact dynamics needs a start it can continue exactly: no overlap, every disk inside
         * the walls (the time-stepped mode, and states it saved, may have either) */
        if (ov > 0)
            return mote_fail(err, MOTE_EINVAL,
                             "run: the event integrator cannot start with overlapping disks (%llu "
                             "pairs closer than 2R); use 'integrator timestep' or place them anew",
                             (unsigned long long)ov);
        const mote_mb_params *p = &sys->p;
        const double in = p->r * (1 - MOTE_MB_OVERLAP_TOL);
        for (uint32_t i = 0; i < sys->n; i++)
            if (!(sys->x[i] - p->x_l >= in && p->x_r - sys->x[i] >= in &&
                  sys->y[i] - p->x_b >= in && p->x_t - sys->y[i] >= in))
                return mote_fail(err, MOTE_EINVAL,
                                 "run: the event integrator cannot start with disk %u at (%.17g, "
                                 "%.17g) less than R from a wall; use 'integrator timestep' or "
                                 "place the disks anew",
                                 i, sys->x[i], sys->y[i]);
    }
    int rc = sys->p.integrator == MOTE_MB_EVENT ? mb_run_event(sys, t_end, loop, err)
                                                : mb_run_timestep(sys, t_end, loop, err);
    ov = mote_mb_count_overlaps(sys, MOTE_MB_OVERLAP_TOL);
    if (ov != UINT64_MAX)
        mote_mb_note_overlaps(sys, ov);
    else if (!rc)
        rc = mote_fail(err, MOTE_ENOMEM, "run: out of memory");
    return rc;
}

void mote_mb_live_position(const mote_mb *sys, uint32_t i, double xy[2])
{
    if (sys->live_ev) {
        double r[3];
        mote_ev_position((const mote_ev *)sys->live_ev, i, r);
        xy[0] = r[0] + sys->live_x0;
        xy[1] = r[1] + sys->live_y0;
    } else {
        xy[0] = sys->x[i];
        xy[1] = sys->y[i];
    }
}

void mote_mb_live_velocity(const mote_mb *sys, uint32_t i, double v[2])
{
    if (sys->live_ev) {
        double w[3];
        mote_ev_velocity((const mote_ev *)sys->live_ev, i, w);
        v[0] = w[0];
        v[1] = w[1];
    } else {
        v[0] = sys->vx[i];
        v[1] = sys->vy[i];
    }
}

double mote_mb_live_time(const mote_mb *sys)
{
    return sys->live_ev ? sys->live_t0 + mote_ev_time((const mote_ev *)sys->live_ev) : sys->time;
}
