/* bench_separator.c: the separator's speed (specs/separator.md 5). Never a timed test; the
 * figures go to bench/README.md.
 *
 *   ref2d [N [STEPS]]    the 2D reference case: N (default 1e5) particles, d from 1 to 2 mm
 *                        (ln d uniform), rho_p 2500, solids area fraction 0.2, DEM with e = 0.5,
 *                        coupling on, air rising at 1 m/s, gravity, closed box; target >= 30
 *                        steps/s
 *   ref3d [N [STEPS]]    the same in 3D (volume fraction 0.2), default N = 1e6; target >= 1
 *                        step/s and <= 256 bytes per particle
 *   scan2d|scan3d [NMAX] the article's comparison extended: Brownian particles (dispersion,
 *                        gas at rest, no gravity, closed box, fraction 0.2, DEM), N = 150, 300,
 *                        600, ... up to NMAX (4e5 in 2D, 1e6 in 3D): cells and, while one step
 *                        takes under a second, brute force, with the speed-up and whether both
 *                        found the same contacts; then the largest N each sustains at 30 steps/s
 *   column N [STEPS]     the gas-free granular column of the LIGGGHTS comparison (3D, d = 2 mm,
 *                        rho_p 2500, k_hat and dt printed so the LIGGGHTS input can use them)
 *   poly N [STEPS]       its polydisperse version (bench/liggghts_poly.in): five sizes from
 *                        1.07 to 1.87 mm (ln d evenly spaced over 1 ... 2 mm), N / 5 of each, a
 *                        60 x 60 mm box; the pair stiffnesses and dampings printed for LIGGGHTS
 *   bed N SETTLE STEPS   the contact-dominated case (issue 56, item 5; bench/liggghts_bed.in):
 *                        the poly column with contact hertz, friction and rolling friction,
 *                        settled for SETTLE steps (untimed), then STEPS timed
 *
 * One key=value line per run: steps_per_s, ns_per_particle_step, candidates and contacts per
 * particle, bytes_per_particle (the model's arrays, cells included) and the peak RSS. */
#include "mote/separator.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

MOTE_PROGRAM_THREADS

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A closed box holding n particles of d in [d1, d2] (ln d uniform, number basis) at solids
 * fraction phi (2D: area, 3D: volume), square (cube) shaped; gas air at rest; brownian: no
 * gravity and a dispersion coefficient. */
static int setup(mote_sep_system *s, int dim, size_t n, double d1, double d2, double phi,
                 int brownian, mote_err *err)
{
    mote_sep_init(s);
    s->dim = dim;
    s->open_bottom = s->open_top = 0;
    s->U0 = brownian ? 0 : 1; /* an upflow, so the solids fraction feeds back on the gas */
    s->nsp = 1;
    snprintf(s->sp[0].name, sizeof s->sp[0].name, "p");
    s->sp[0].rho = 2500;
    s->sp[0].w = 1;
    s->sp[0].dist = d1 < d2 ? (mote_sep_dist){.type = MOTE_SEP_LOGUNIFORM, .lo = d1, .hi = d2,
                                              .number_basis = 1}
                            : (mote_sep_dist){.type = MOTE_SEP_MONO, .a = d1};
    if (d1 < d2 && mote_sep_dist_build(&s->sp[0].dist, err))
        return -1;
    s->sp[0].have_dist = 1;
    /* the mean particle area (volume) of the ln d uniform law on a number basis */
    const double L = log(d2 / d1);
    const double m2 = d1 < d2 ? (d2 * d2 - d1 * d1) / (2 * L) : d1 * d1;
    const double m3 = d1 < d2 ? (d2 * d2 * d2 - d1 * d1 * d1) / (3 * L) : d1 * d1 * d1;
    const double each = dim == 2 ? 3.14159265358979 / 4 * m2 : 3.14159265358979 / 6 * m3;
    const double side = pow((double)n * each / phi, 1.0 / dim);
    s->W = s->H = s->D = fmax(side, 3 * d2);
    s->D2 = d2;
    s->zf = 0.5 * s->H;
    s->hf = s->H;
    s->v_imp = 1;
    if (brownian) {
        s->g = 0;
        s->D_t = 1e-2; /* velocity spread sqrt(D / tau) of a few cm/s */
    }
    if (mote_sep_prepare(s, err) || mote_sep_insert(s, 0, n, 0, err))
        return -1;
    s->nback = 0; /* those that found no room are dropped: N is what was placed */
    return 0;
}

/* The bytes the model's arrays hold per particle (capacities: the particle arrays, the
 * scratch, the neighbour rows and their reference positions, the cells and their lists). */
static double bytes_per_particle(const mote_sep_system *s)
{
    const double per = 12 * sizeof(double) + sizeof(int) + sizeof(uint64_t);
    const double b = (double)s->cap * per + (double)s->pv_cap * sizeof(double) +
                     (double)s->xref_cap * sizeof(double) + (double)s->gap_cap * sizeof(double) +
                     (double)s->nb_cap * sizeof(uint32_t) +
                     (double)s->nbs_cap * sizeof(uint32_t) + (double)s->exc_cap +
                     (double)s->blk_cap * sizeof(double) +
                     (double)s->ebox_cap * sizeof(double) + 3.0 * (double)s->g_cap * sizeof(double) +
                     (double)s->nnext_cap * sizeof(int32_t) +
                     (double)s->nhead_cap * sizeof(int32_t) +
                     (double)s->grid.cap_cells * sizeof(uint32_t) +
                     (double)s->grid.cap_n * (2 * sizeof(uint32_t) +
                                              (s->grid.pos ? 3 * sizeof(double) : 0)) +
                     /* contact hertz: rotation, torques (two sets), wall springs; the pairs'
                      * springs, slots, slot indices, mirrors, owner counts; the walls' sums */
                     (s->w ? 18.0 * (double)s->rot_cap * sizeof(double) : 0) +
                     (double)s->hist_cap * sizeof(double) + (double)s->pbuf_cap * sizeof(double) +
                     (double)(s->mir_cap + s->cidx_cap + s->ostart_cap) * sizeof(uint32_t) +
                     (double)s->wres_cap * sizeof(double) + (double)s->wflag_cap +
                     (double)s->hmap_cap * (2 * sizeof(uint64_t) + 3 * sizeof(double));
    return s->n ? b / (double)s->n : 0;
}

static size_t peak_rss(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    size_t kb = 0;
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "VmHWM: %zu", &kb) == 1)
            break;
    if (f)
        fclose(f);
    return kb * 1024;
}

/* Time `steps` steps after `warm` untimed ones; the rate, and the contacts of the last step. */
static double timed(mote_sep_system *s, int warm, int steps, uint64_t *contacts, mote_err *err)
{
    if (warm && mote_sep_run(s, warm * s->dt, err))
        return -1;
    const double t0 = now();
    if (mote_sep_run(s, steps * s->dt, err))
        return -1;
    const double el = now() - t0;
    *contacts = s->contacts_pp;
    return steps / el;
}

static int reference(int dim, size_t n, int steps, int nt)
{
    mote_err err = {0};
    mote_sep_system s;
    if (setup(&s, dim, n, 1e-3, 2e-3, 0.2, 0, &err)) {
        fprintf(stderr, "bench_separator: %s\n", err.msg);
        return 1;
    }
    s.threads = nt;
    uint64_t contacts;
    const double rate = timed(&s, 20, steps, &contacts, &err);
    if (rate < 0) {
        fprintf(stderr, "bench_separator: %s\n", err.msg);
        return 1;
    }
    printf("workload=ref%dd N=%zu steps=%d dt=%.4g steps_per_s=%.2f ns_per_particle_step=%.1f "
           "candidates_per_particle=%.2f contacts_per_particle=%.3f bytes_per_particle=%.0f "
           "peak_rss_MB=%.1f threads=%d\n",
           dim, s.n, steps, s.dt, rate, 1e9 / (rate * (double)s.n),
           (double)s.candidates / (double)s.n, 2.0 * (double)contacts / (double)s.n,
           bytes_per_particle(&s), peak_rss() / 1048576.0, nt);
    mote_sep_free(&s);
    return 0;
}

/* The article's comparison: cells against brute force on Brownian particles. */
static int scan(int dim, size_t nmax)
{
    size_t best_cells = 0, best_brute = 0;
    int brute_on = 1;
    for (size_t n = 150; n <= nmax; n *= 2) {
        mote_err err = {0};
        mote_sep_system s;
        if (setup(&s, dim, n, 1e-3, 2e-3, 0.2, 1, &err)) {
            fprintf(stderr, "bench_separator: %s\n", err.msg);
            return 1;
        }
        /* a warm-up, then a copy of the state for each method: both start alike */
        if (mote_sep_run(&s, 20 * s.dt, &err)) {
            fprintf(stderr, "bench_separator: %s\n", err.msg);
            return 1;
        }
        const int steps = n <= 10000 ? 200 : 20;
        uint64_t cc = 0, cb = 0;
        const double rc = timed(&s, 0, steps, &cc, &err);
        const double cand = (double)s.candidates / (double)s.n;
        double rb = 0;
        if (brute_on) {
            mote_sep_system b;
            if (setup(&b, dim, n, 1e-3, 2e-3, 0.2, 1, &err) || mote_sep_run(&b, 20 * b.dt, &err)) {
                fprintf(stderr, "bench_separator: %s\n", err.msg);
                return 1;
            }
            b.brute = 1;
            /* brute force costs n^2/2 tests a step: a few steps when that is large */
            const int bs = n <= 2400 ? steps : n <= 20000 ? 5 : 2;
            rb = timed(&b, 0, bs, &cb, &err);
            /* the same contacts on the same configuration: compare the step both reach */
            mote_sep_system c2;
            setup(&c2, dim, n, 1e-3, 2e-3, 0.2, 1, &err);
            mote_sep_run(&c2, (20 + bs) * c2.dt, &err);
            const int same = c2.contacts_pp == b.contacts_pp;
            mote_sep_free(&c2);
            printf("workload=scan%dd N=%zu cells_steps_per_s=%.1f brute_steps_per_s=%.1f "
                   "speedup=%.2f same_contacts=%s contacts_per_particle=%.3f "
                   "candidates_per_particle=%.2f ns_per_particle_step=%.1f\n",
                   dim, n, rc, rb, rc / rb, same ? "yes" : "NO",
                   2.0 * (double)cc / (double)n, cand, 1e9 / (rc * (double)n));
            if (rb >= 30)
                best_brute = n;
            if (rb < 1)
                brute_on = 0;
            mote_sep_free(&b);
        } else {
            printf("workload=scan%dd N=%zu cells_steps_per_s=%.1f brute_steps_per_s=- "
                   "contacts_per_particle=%.3f candidates_per_particle=%.2f "
                   "ns_per_particle_step=%.1f\n",
                   dim, n, rc, 2.0 * (double)cc / (double)n, cand, 1e9 / (rc * (double)n));
        }
        if (rc >= 30)
            best_cells = n;
        mote_sep_free(&s);
    }
    printf("workload=scan%dd_summary largest_N_at_30_steps_per_s cells=%zu brute=%zu "
           "(of the N tried, doubling from 150)\n", dim, best_cells, best_brute);
    return 0;
}

/* The granular column for the LIGGGHTS comparison: 3D, mono d = 2 mm, rho 2500, e = 0.5, no
 * gas, gravity, a closed box of 20 x 20 d2 cross-section, the particles poured at fraction 0.3
 * and settling. */
/* A closed gas-free box W x W x H in 3D (rho_p 2500, e = 0.5, v_imp = 1 m/s) with nsp species
 * of one size each (d[k]), count[k] particles of each poured at random over the whole height
 * (those that find no room are dropped: N is what was placed). */
static int gas_free_box(mote_sep_system *s, double W, double H, int nsp, const double *d,
                        size_t count, mote_err *err)
{
    mote_sep_init(s);
    s->dim = 3;
    s->W = s->D = W;
    s->H = H;
    s->open_bottom = s->open_top = 0;
    s->U0 = 0;
    s->rho_g = 0;
    s->mu_g = 0;
    s->nsp = nsp;
    for (int k = 0; k < nsp; k++) {
        snprintf(s->sp[k].name, sizeof s->sp[k].name, "p%d", k);
        s->sp[k].rho = 2500;
        s->sp[k].w = 1.0 / nsp;
        s->sp[k].dist = (mote_sep_dist){.type = MOTE_SEP_MONO, .a = d[k]};
        s->sp[k].have_dist = 1;
    }
    s->zf = 0.5 * s->H;
    s->hf = s->H;
    s->v_imp = 1;
    if (mote_sep_prepare(s, err))
        return err->code;
    for (int k = 0; k < nsp; k++)
        if (mote_sep_insert(s, k, count, 0, err))
            return err->code;
    s->nback = 0;
    return MOTE_OK;
}

static int column(size_t n, int steps, int nt)
{
    mote_err err = {0};
    mote_sep_system s;
    const double d = 2e-3, W = 20 * d;
    if (gas_free_box(&s, W, (double)n * 3.14159265358979 / 6 * d * d * d / (0.3 * W * W) + 2 * d,
                     1, &d, n, &err)) {
        fprintf(stderr, "bench_separator: %s\n", err.msg);
        return 1;
    }
    s.threads = nt;
    uint64_t contacts;
    const double rate = timed(&s, 20, steps, &contacts, &err);
    if (rate < 0) {
        fprintf(stderr, "bench_separator: %s\n", err.msg);
        return 1;
    }
    printf("workload=column N=%zu box=%.4gx%.4gx%.4g khat=%.6g k_pair=%.6g dt=%.6g steps=%d "
           "steps_per_s=%.2f ns_per_particle_step=%.1f contacts_per_particle=%.3f "
           "list_builds=%llu pairs_per_particle=%.2f threads=%d\n",
           s.n, s.W, s.D, s.H, s.khat_used, s.khat_used * d, s.dt, steps, rate,
           1e9 / (rate * (double)s.n), 2.0 * (double)contacts / (double)s.n,
           (unsigned long long)s.list_builds, (double)s.npl / (double)s.n, nt);
    mote_sep_free(&s);
    return 0;
}

/* The polydisperse column's box: five species of one size each (d_k = 1 mm 2^((k + 1/2) / 5),
 * into d), N / 5 particles of each, in a 60 x 60 mm box at fraction 0.3. */
static int poly_box(mote_sep_system *s, size_t n, double d[5], mote_err *err)
{
    double vol = 0;
    for (int k = 0; k < 5; k++) {
        d[k] = 1e-3 * pow(2, (k + 0.5) / 5);
        vol += (double)(n / 5) * 3.14159265358979 / 6 * d[k] * d[k] * d[k];
    }
    return gas_free_box(s, 0.06, vol / (0.3 * 0.06 * 0.06) + 2 * d[4], 5, d, n / 5, err);
}

/* The polydisperse column: as column, with the five sizes of poly_box. */
static int poly(size_t n, int steps, int nt)
{
    mote_err err = {0};
    mote_sep_system s;
    double d[5];
    if (poly_box(&s, n, d, &err)) {
        fprintf(stderr, "bench_separator: %s\n", err.msg);
        return 1;
    }
    s.threads = nt;
    /* LIGGGHTS's per type pair constants: k_n = k_hat dbar (dbar = 2 d_i d_j / (d_i + d_j)),
     * gamma_n (times the effective mass) = 2 zeta(e) sqrt(k_n / m_eff) */
    const double l = log(0.5), zeta = -l / sqrt(3.14159265358979 * 3.14159265358979 + l * l);
    printf("liggghts_kn");
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 5; j++)
            printf(" %.6g", s.khat_used * 2 * d[i] * d[j] / (d[i] + d[j]));
    printf("\nliggghts_gamman");
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 5; j++) {
            const double mi = 2500 * 3.14159265358979 / 6 * d[i] * d[i] * d[i],
                         mj = 2500 * 3.14159265358979 / 6 * d[j] * d[j] * d[j];
            const double k = s.khat_used * 2 * d[i] * d[j] / (d[i] + d[j]);
            printf(" %.6g", 2 * zeta * sqrt(k / (mi * mj / (mi + mj))));
        }
    printf("\n");
    uint64_t contacts;
    const double rate = timed(&s, 20, steps, &contacts, &err);
    if (rate < 0) {
        fprintf(stderr, "bench_separator: %s\n", err.msg);
        return 1;
    }
    printf("workload=poly N=%zu box=%.4gx%.4gx%.6g khat=%.6g dt=%.6g steps=%d steps_per_s=%.2f "
           "ns_per_particle_step=%.1f contacts_per_particle=%.3f list_builds=%llu "
           "pairs_per_particle=%.2f threads=%d\n",
           s.n, s.W, s.D, s.H, s.khat_used, s.dt, steps, rate, 1e9 / (rate * (double)s.n),
           2.0 * (double)contacts / (double)s.n, (unsigned long long)s.list_builds,
           (double)s.npl / (double)s.n, nt);
    mote_sep_free(&s);
    return 0;
}

/* The settled bed: the poly column (five sizes, N / 5 each, 60 x 60 mm, fraction 0.3 poured)
 * with contact hertz: E 5 MPa, nu 0.3, e 0.5 (restitution=liggghts, as LIGGGHTS takes it),
 * mu 0.5, mu_r 0.1 (walls alike), the automatic time step (printed: LIGGGHTS takes the same);
 * SETTLE steps untimed, then STEPS timed. */
static int bed(size_t n, int settle, int steps, int nt)
{
    mote_err err = {0};
    mote_sep_system s;
    double d[5];
    if (poly_box(&s, n, d, &err)) {
        fprintf(stderr, "bench_separator: %s\n", err.msg);
        return 1;
    }
    s.hertz = 1;
    s.e_true = 0;
    for (int k = 0; k < 5; k++) {
        s.sp[k].E = 5e6;
        s.sp[k].nu = 0.3;
    }
    s.mu_pp = 0.5;
    s.mur_pp = 0.1;
    s.threads = nt;
    if (mote_sep_prepare(&s, &err)) {
        fprintf(stderr, "bench_separator: %s\n", err.msg);
        return 1;
    }
    uint64_t contacts;
    const double t0 = now();
    const double rate = timed(&s, settle, steps, &contacts, &err);
    const double total = now() - t0;
    if (rate < 0) {
        fprintf(stderr, "bench_separator: %s\n", err.msg);
        return 1;
    }
    double ke = 0;
    for (size_t i = 0; i < s.n; i++)
        ke += 0.5 * s.m[i] * (s.vx[i] * s.vx[i] + s.vy[i] * s.vy[i] + s.vz[i] * s.vz[i]);
    printf("workload=bed N=%zu box=%.4gx%.4gx%.6g dt=%.6g settle=%d steps=%d "
           "settle_and_steps_s=%.2f steps_per_s=%.2f ns_per_particle_step=%.1f "
           "contacts_per_particle=%.3f list_builds=%llu pairs_per_particle=%.2f kinetic_J=%.3g "
           "bytes_per_particle=%.0f peak_rss_MB=%.1f threads=%d\n",
           s.n, s.W, s.D, s.H, s.dt, settle, steps, total, rate, 1e9 / (rate * (double)s.n),
           2.0 * (double)contacts / (double)s.n, (unsigned long long)s.list_builds,
           (double)s.npl / (double)s.n, ke, bytes_per_particle(&s), peak_rss() / 1048576.0, nt);
    mote_sep_free(&s);
    return 0;
}

int main(int argc, char **argv)
{
    const char *w = argc > 1 ? argv[1] : "ref2d";
    const double a = argc > 2 ? atof(argv[2]) : 0, b = argc > 3 ? atof(argv[3]) : 0;
    const int nt = argc > 4 && atoi(argv[4]) > 1 ? atoi(argv[4]) : 1; /* threads (ref, column) */
    if (!strcmp(w, "ref2d"))
        return reference(2, a > 0 ? (size_t)a : 100000, b > 0 ? (int)b : 100, nt);
    if (!strcmp(w, "ref3d"))
        return reference(3, a > 0 ? (size_t)a : 1000000, b > 0 ? (int)b : 5, nt);
    if (!strcmp(w, "scan2d"))
        return scan(2, a > 0 ? (size_t)a : 400000);
    if (!strcmp(w, "scan3d"))
        return scan(3, a > 0 ? (size_t)a : 1000000);
    if (!strcmp(w, "column"))
        return column(a > 0 ? (size_t)a : 100000, b > 0 ? (int)b : 200, nt);
    if (!strcmp(w, "poly"))
        return poly(a > 0 ? (size_t)a : 100000, b > 0 ? (int)b : 200, nt);
    if (!strcmp(w, "bed")) /* (bed N SETTLE STEPS [THREADS]) */
        return bed(a > 0 ? (size_t)a : 20000, b > 0 ? (int)b : 30000,
                   argc > 4 && atoi(argv[4]) > 0 ? atoi(argv[4]) : 1000,
                   argc > 5 && atoi(argv[5]) > 1 ? atoi(argv[5]) : 1);
    fprintf(stderr, "bench_separator: unknown workload '%s' (ref2d, ref3d, scan2d, scan3d, "
                    "column, poly, bed)\n", w);
    return 2;
}
