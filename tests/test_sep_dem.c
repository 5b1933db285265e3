/* test_sep_dem.c: the separator's contacts against specs/separator.md section 4: V3 (the cell
 * search finds exactly the pairs brute force finds), V4a (momentum), V4b (energy of elastic
 * binary collisions), V4c (many-body elastic energy), V4d (restitution of binary and wall
 * collisions), V4e (the overlap bound), V5 (the balance in a dense feed with a backlog), V9
 * (grids). */
#include "mote/separator.h"

#include <math.h>
#include <stdlib.h>

#include "test.h"

#define SEP_TEST_PI 3.14159265358979323846

/* (src/separator/sep.h's sep_rot_reserve: the rotation arrays) */
int sep_rot_reserve(mote_sep_system *s, mote_err *err);
static int sep_rot_reserve_for_test(mote_sep_system *s)
{
    mote_err err = {0};
    return sep_rot_reserve(s, &err);
}

#define PI 3.14159265358979323846

/* A system in vacuum without gravity, one species of density rho with the given distribution,
 * a closed box W x H (x D); no particles. */
static void vacuum_box(mote_sep_system *s, int dim, double W, double H, double D, double rho,
                       mote_sep_dist dist)
{
    mote_err err = {0};
    mote_sep_init(s);
    s->dim = dim;
    s->W = W;
    s->H = H;
    s->D = D;
    s->open_bottom = s->open_top = 0;
    s->U0 = 0;
    s->rho_g = 0;
    s->mu_g = 0;
    s->g = 0;
    s->nsp = 1;
    snprintf(s->sp[0].name, sizeof s->sp[0].name, "p");
    s->sp[0].rho = rho;
    s->sp[0].w = 1;
    s->sp[0].dist = dist;
    if (dist.type != MOTE_SEP_MONO)
        CHECK(mote_sep_dist_build(&s->sp[0].dist, &err) == MOTE_OK, "dist: %s", err.msg);
    s->sp[0].have_dist = 1;
    s->zf = 0.5 * H;
    s->hf = H;
}

/* Add n particles anywhere in the box (overlaps allowed unless s->dem), then prepare. */
static void fill(mote_sep_system *s, size_t n)
{
    mote_err err = {0};
    CHECK(mote_sep_prepare(s, &err) == MOTE_OK, "prepare: %s", err.msg);
    CHECK(mote_sep_insert(s, 0, n, 0, &err) == MOTE_OK, "insert: %s", err.msg);
}

/* V3: random polydisperse sets in 2D and 3D with particles exactly on cell boundaries and on
 * walls, pairs at exactly d_max, and W not a multiple of the cell edge: the sorted pair lists
 * of the cells and brute force are equal. */
static void test_pairs(void)
{
    printf("V3: cell search against brute force\n");
    const size_t ns[3] = {150, 2000, 10000};
    for (int dim = 2; dim <= 3; dim++)
        for (int q = 0; q < 3; q++) {
            mote_sep_system s;
            const double dmax = 1e-3;
            /* area/volume fraction about 0.3, W = 37.3 d_max (not a multiple of the edge) */
            const double W = 37.3 * dmax;
            const double vfrac = dim == 2 ? PI / 4 * 0.56e-6 : PI / 6 * 0.42e-9;
            const double H = ns[q] * vfrac / (0.3 * W * (dim == 3 ? W : 1));
            vacuum_box(&s, dim, W, fmax(H, 3 * dmax), W,
                       2500, (mote_sep_dist){.type = MOTE_SEP_LOGUNIFORM, .lo = 0.4e-3, .hi = dmax});
            s.dem = 0; /* place anywhere, overlaps allowed */
            fill(&s, ns[q]);
            mote_err err = {0};
            CHECK(mote_sep_prepare(&s, &err) == MOTE_OK, "prepare: %s", err.msg);
            /* the cell edges, as the search makes them (the core grid: edges of at least d_max
             * plus the skin, merged where there would be more cells than particles) */
            CHECK(mote_sep_pairs(&s, 0, NULL, 0) > 0 || s.n == 0, "a first search");
            const int ncx = s.grid.nc[0], ncz = s.grid.nc[dim == 3 ? 2 : 1];
            const int ncy = dim == 3 ? s.grid.nc[1] : 1;
            const double hx = s.W / ncx, hz = s.H / ncz;
            for (size_t i = 0; i < s.n / 10; i++) { /* on cell boundaries */
                s.x[i] = hx * (double)(i % (size_t)ncx);
                s.z[i] = hz * (double)((i / 7) % (size_t)ncz);
                if (dim == 3)
                    s.y[i] = s.D / ncy * (double)((i / 3) % (size_t)ncy);
            }
            for (size_t i = s.n / 10; i < s.n / 5; i++) /* on walls */
                s.x[i] = (i & 1) ? s.W : 0;
            for (size_t i = s.n / 5; i + 1 < s.n / 4; i += 2) { /* pairs at exactly d_max */
                s.d[i] = s.d[i + 1] = dmax;
                s.x[i + 1] = s.x[i] + dmax;
                s.z[i + 1] = s.z[i];
                if (dim == 3)
                    s.y[i + 1] = s.y[i];
            }
            for (size_t i = s.n / 4; i + 1 < s.n * 3 / 10; i += 2) { /* just inside d_max */
                s.d[i] = s.d[i + 1] = dmax;
                s.x[i + 1] = s.x[i];
                s.z[i + 1] = s.z[i] + dmax * (1 - 1e-15);
                if (dim == 3)
                    s.y[i + 1] = s.y[i];
            }
            const size_t cap = 40 * s.n;
            uint32_t *a = malloc(2 * cap * sizeof *a), *b = malloc(2 * cap * sizeof *b);
            const size_t na = mote_sep_pairs(&s, 0, a, cap), nb = mote_sep_pairs(&s, 1, b, cap);
            int same = na == nb && na < cap;
            for (size_t k = 0; same && k < 2 * na; k++)
                same = a[k] == b[k];
            printf("  %dD N %zu: %zu pairs by cells, %zu by brute force, %s (cells %d x %d x %d)\n",
                   dim, s.n, na, nb, same ? "identical" : "DIFFERENT", s.grid.nc[0], s.grid.nc[1], s.grid.nc[2]);
            CHECK(same && na >= s.n / 40, "V3 %dD N %zu: %zu against %zu", dim, s.n, na, nb);
            free(a);
            free(b);
            mote_sep_free(&s);
        }
}

/* Kinetic energy, and the potential energy of the springs in contact (pairs and walls). */
static double kinetic(const mote_sep_system *s)
{
    double e = 0;
    for (size_t i = 0; i < s->n; i++)
        e += 0.5 * s->m[i] * (s->vx[i] * s->vx[i] + s->vy[i] * s->vy[i] + s->vz[i] * s->vz[i]);
    return e;
}

static double potential(mote_sep_system *s)
{
    double e = 0;
    const size_t cap = 20 * s->n + 16;
    uint32_t *p = malloc(2 * cap * sizeof *p);
    const size_t np = mote_sep_pairs(s, 1, p, cap);
    for (size_t k = 0; k < np && k < cap; k++) {
        const size_t i = p[2 * k], j = p[2 * k + 1];
        const double dx = s->x[j] - s->x[i], dy = s->y[j] - s->y[i], dz = s->z[j] - s->z[i];
        const double delta = 0.5 * (s->d[i] + s->d[j]) - sqrt(dx * dx + dy * dy + dz * dz);
        const double kk = s->khat_used * 2 * s->d[i] * s->d[j] / (s->d[i] + s->d[j]);
        e += 0.5 * kk * delta * delta;
    }
    free(p);
    for (size_t i = 0; i < s->n; i++) {
        const double r = 0.5 * s->d[i], kk = s->khat_used * s->d[i];
        const double pos[3] = {s->x[i], s->y[i], s->z[i]}, hi[3] = {s->W, s->D, s->H};
        for (int a = 0; a < 3; a++) {
            if (a == 1 && s->dim == 2)
                continue;
            const double lo = r - pos[a], up = pos[a] + r - hi[a];
            if (lo > 0)
                e += 0.5 * kk * lo * lo;
            if (up > 0)
                e += 0.5 * kk * up * up;
        }
    }
    return e;
}

/* V4a: many contacts, no walls in reach, no gas, no gravity: the contact forces sum to zero
 * within 1e-12 of the sum of their magnitudes, every step. */
static void test_momentum(void)
{
    printf("V4a: momentum in a dense cluster\n");
    for (int dim = 2; dim <= 3; dim++) {
        mote_sep_system s;
        const double d = 1e-3;
        vacuum_box(&s, dim, 0.03, 0.03, 0.03, 2500,
                   (mote_sep_dist){.type = MOTE_SEP_LOGUNIFORM, .lo = 0.5 * d, .hi = d});
        s.dem = 0;
        s.zf = 0.015;
        s.hf = 8 * d;
        s.fx1 = 0.015 - 4 * d;
        s.fx2 = 0.015 + 4 * d;
        s.fy1 = 0.015 - 4 * d;
        s.fy2 = 0.015 + 4 * d;
        fill(&s, dim == 2 ? 60 : 300); /* overlapping: a cluster that flies apart */
        s.dem = 1;
        s.v_imp = 1;
        mote_err err = {0};
        CHECK(mote_sep_prepare(&s, &err) == MOTE_OK, "prepare: %s", err.msg);
        double worst = 0;
        int steps = 0, contacts = 0;
        for (int k = 0; k < 200; k++) {
            CHECK(mote_sep_run(&s, s.dt > 0 ? s.dt : 1e-7, &err) == MOTE_OK, "run: %s", err.msg);
            double F[3] = {0, 0, 0}, mag = 0;
            for (size_t i = 0; i < s.n; i++) {
                F[0] += s.fx[i];
                F[1] += s.fy[i];
                F[2] += s.fz[i];
                mag += sqrt(s.fx[i] * s.fx[i] + s.fy[i] * s.fy[i] + s.fz[i] * s.fz[i]);
            }
            if (mag > 0) {
                worst = fmax(worst, sqrt(F[0] * F[0] + F[1] * F[1] + F[2] * F[2]) / mag);
                steps++;
                contacts += (int)s.contacts_pp;
            }
        }
        printf("  %dD: %d steps with contacts (%d contacts), worst |sum F| / sum |F| = %.2e\n",
               dim, steps, contacts, worst);
        CHECK(steps > 100 && worst <= 1e-12, "V4a %dD: %.3e over %d steps", dim, worst, steps);
        mote_sep_free(&s);
    }
}

/* One binary collision (pair, or wall when wall is set) of particles of diameters d1, d2 at
 * closing speed v, the contact starting at the fraction phase of a step: the restitution
 * measured (normal separation speed after / before) and the relative kinetic energy change.
 * The pair meets obliquely at angle ang (radians) in the x-z plane. */
static double binary(int dim, int wall, double d1, double d2, double v, double e, double phase,
                     double ang, double *dE, double *max_overlap)
{
    mote_sep_system s;
    vacuum_box(&s, dim, 0.01, 0.01, 0.01, 2500,
               (mote_sep_dist){.type = MOTE_SEP_LOGUNIFORM, .lo = fmin(d1, d2), .hi = fmax(d1, d2) * 1.0001});
    s.dem = 0;
    s.zf = 0.005;
    s.hf = 0.002;
    fill(&s, wall ? 1 : 2);
    s.dem = 1;
    s.e_pp = e;
    s.e_pw = e;
    s.v_imp = v;
    mote_err err = {0};
    CHECK(mote_sep_prepare(&s, &err) == MOTE_OK, "prepare: %s", err.msg);
    const double dt = s.dt, nx = sin(ang), nz = cos(ang);
    /* the gap closes at v: contact after (3 + phase) steps */
    const double gap = v * (3 + phase) * dt;
    if (wall) {
        s.d[0] = d1;
        s.m[0] = 2500 * PI * d1 * d1 * d1 / 6;
        s.x[0] = 0.005;
        s.z[0] = 0.5 * d1 + gap;
        s.vx[0] = 0;
        s.vz[0] = -v;
    } else {
        s.d[0] = d1;
        s.d[1] = d2;
        s.m[0] = 2500 * PI * d1 * d1 * d1 / 6;
        s.m[1] = 2500 * PI * d2 * d2 * d2 / 6;
        const double R = 0.5 * (d1 + d2) + gap;
        const double M = s.m[0] + s.m[1];
        s.x[0] = 0.005;
        s.z[0] = 0.005;
        s.x[1] = 0.005 + R * nx;
        s.z[1] = 0.005 + R * nz;
        /* centre of mass at rest; closing along the line of centres */
        s.vx[0] = v * nx * s.m[1] / M;
        s.vz[0] = v * nz * s.m[1] / M;
        s.vx[1] = -v * nx * s.m[0] / M;
        s.vz[1] = -v * nz * s.m[0] / M;
        if (dim == 3)
            s.y[0] = s.y[1] = 0.005;
    }
    s.cnt[0].m_fed = s.m[0] + (wall ? 0 : s.m[1]); /* the masses were set by hand */
    s.im[0] = 1 / s.m[0];
    if (!wall)
        s.im[1] = 1 / s.m[1];
    const double E0 = kinetic(&s);
    /* the contact lasts at most N_c steps; run well past it */
    CHECK(mote_sep_run(&s, (3 + 1 + 3.0 * s.nc) * dt, &err) == MOTE_OK, "run: %s", err.msg);
    double after;
    if (wall) {
        after = s.vz[0] / v;
    } else {
        const double rvx = s.vx[1] - s.vx[0], rvz = s.vz[1] - s.vz[0];
        after = (rvx * nx + rvz * nz) / v;
    }
    *dE = kinetic(&s) / E0 - 1;
    *max_overlap = s.max_overlap;
    mote_sep_free(&s);
    return after;
}

/* V4b: isolated elastic binary collisions (e = 1, N_c = 50: equal particles of d_min, whose
 * contact lasts exactly N_c steps), onset phases spread over a step, in 2D and 3D, head-on and
 * oblique: the relative kinetic energy change at most 1e-4 per collision. Unequal pairs, whose
 * contacts end at another phase of the step than they began, are reported (the error of the
 * onset and of the release then no longer cancel; it stays zero on average). */
static void test_elastic(void)
{
    printf("V4b: elastic binary collisions\n");
    double worst = 0, mean = 0, worst_u = 0, mean_u = 0;
    int n = 0;
    for (int dim = 2; dim <= 3; dim++)
        for (int k = 0; k < 50; k++) {
            double dE, ov;
            binary(dim, 0, 1e-3, 1e-3, 1.0, 1.0, (k + 0.5) / 50, 0.6 * k / 50, &dE, &ov);
            worst = fmax(worst, fabs(dE));
            mean += dE;
            binary(dim, 0, 1e-3, 0.6e-3, 1.0, 1.0, (k + 0.5) / 50, 0.6 * k / 50, &dE, &ov);
            worst_u = fmax(worst_u, fabs(dE));
            mean_u += dE;
            n++;
        }
    printf("  %d collisions: worst |dE|/E %.2e, mean %.2e (spec's indication: <= 3e-5)\n", n,
           worst, mean / n);
    printf("  unequal pairs (1 mm on 0.6 mm): worst |dE|/E %.2e, mean %.2e (reported)\n",
           worst_u, mean_u / n);
    CHECK(worst <= 1e-4, "V4b worst %.3e", worst);
}

/* V4d: binary and wall collisions with e 0.3, 0.5, 0.9 (N_c = 50, 100 onset phases): the mean
 * restitution within 1% of nominal, each within 10%. V4e: the densest particle hitting a wall
 * at v_imp with e = 1 and the default stiffness overlaps at most 1.01 delta_f d. */
static void test_restitution(void)
{
    printf("V4d: restitution; V4e: the overlap bound\n");
    const double es[3] = {0.3, 0.5, 0.9};
    for (int wall = 0; wall <= 1; wall++)
        for (int q = 0; q < 3; q++) {
            double mean = 0, worst = 0;
            for (int k = 0; k < 100; k++) {
                double dE, ov;
                const double r = binary(2, wall, 1e-3, k & 1 ? 0.7e-3 : 1e-3, 2.0, es[q],
                                        (k + 0.5) / 100, 0, &dE, &ov);
                mean += r / 100;
                worst = fmax(worst, fabs(r / es[q] - 1));
            }
            printf("  %s e %.1f: mean %.5f (%+.3f%%), worst single %.2f%%\n",
                   wall ? "wall" : "pair", es[q], mean, 100 * (mean / es[q] - 1), 100 * worst);
            CHECK(fabs(mean / es[q] - 1) <= 0.01 && worst <= 0.10, "V4d %s e %.1f: mean %.5f worst %.3f",
                  wall ? "wall" : "pair", es[q], mean, worst);
        }
    double worst_ov = 0;
    for (int k = 0; k < 20; k++) {
        double dE, ov;
        binary(2, 1, 1e-3, 1e-3, 2.0, 1.0, (k + 0.5) / 20, 0, &dE, &ov);
        worst_ov = fmax(worst_ov, ov);
    }
    printf("  V4e: largest overlap %.5f d (delta_f 0.05; bound 1.01 delta_f = 0.0505)\n", worst_ov);
    CHECK(worst_ov <= 1.01 * 0.05 && worst_ov > 0.9 * 0.05, "V4e %.5f", worst_ov);
}

/* V4c: 1000 particles in a closed box, no gas, no gravity, e = 1 (particles and walls): the
 * total energy (kinetic plus springs) changes by at most 1e-3 after 1e4 collisions. Equal
 * sizes make every contact last exactly N_c steps, so collisions = contact-steps / N_c. */
static void test_many_body(void)
{
    printf("V4c: many-body elastic energy\n");
    mote_sep_system s;
    const double d = 1e-3;
    vacuum_box(&s, 2, 0.05, 0.05, 0, 2500, (mote_sep_dist){.type = MOTE_SEP_MONO, .a = d});
    s.zf = 0.025;
    s.hf = 0.049;
    s.e_pp = s.e_pw = 1;
    s.v_imp = 2;
    fill(&s, 1000); /* placed without overlaps */
    mote_rng rng;
    mote_rng_seed(&rng, 5);
    mote_normal g;
    mote_normal_init(&g, &rng);
    for (size_t i = 0; i < s.n; i++) {
        s.vx[i] = mote_normal_next(&g);
        s.vz[i] = mote_normal_next(&g);
    }
    mote_err err = {0};
    const double E0 = kinetic(&s) + potential(&s);
    double contact_steps = 0, worst = 0;
    int k = 0;
    while (contact_steps < 1e4 * s.nc && k < 200000) {
        CHECK(mote_sep_run(&s, s.dt, &err) == MOTE_OK, "run: %s", err.msg);
        contact_steps += (double)s.contacts_pp;
        if (++k % 500 == 0)
            worst = fmax(worst, fabs((kinetic(&s) + potential(&s)) / E0 - 1));
    }
    const double dE = (kinetic(&s) + potential(&s)) / E0 - 1;
    printf("  %d steps, about %.0f collisions: dE/E %.2e at the end, worst sampled %.2e\n", k,
           contact_steps / s.nc, dE, worst);
    CHECK(contact_steps >= 1e4 * s.nc && fabs(dE) <= 1e-3 && worst <= 1e-3, "V4c %.3e", dE);
    mote_sep_free(&s);
}

/* V5 in a dense feed: a feed band far too small for the rate builds a backlog; the balance
 * holds after every step, nothing is lost, and the backlog drains into the channel. */
static void test_backlog(void)
{
    printf("V5: the balance with a feed backlog\n");
    mote_sep_system s;
    mote_sep_init(&s);
    s.W = 0.01;
    s.H = 0.05;
    s.U0 = 0;
    s.open_top = 0;
    s.nsp = 1;
    snprintf(s.sp[0].name, sizeof s.sp[0].name, "p");
    s.sp[0].rho = 2500;
    s.sp[0].w = 1;
    s.sp[0].dist = (mote_sep_dist){.type = MOTE_SEP_LOGUNIFORM, .lo = 0.5e-3, .hi = 1e-3};
    mote_err err = {0};
    CHECK(mote_sep_dist_build(&s.sp[0].dist, &err) == MOTE_OK, "dist: %s", err.msg);
    s.sp[0].have_dist = 1;
    s.zf = 0.04;
    s.hf = 1e-3;
    s.rate = 2e-3; /* kg/s: about 3000 particles a second into a 1 mm band */
    s.t_stop = 0.015;
    s.v_imp = 1;
    CHECK(mote_sep_prepare(&s, &err) == MOTE_OK, "prepare: %s", err.msg);
    size_t most = 0;
    int bad = 0;
    while (s.t < 0.03 && !bad) {
        CHECK(mote_sep_run(&s, 20 * s.dt, &err) == MOTE_OK, "run: %s", err.msg);
        most = most > s.nback ? most : s.nback;
        bad = mote_sep_check_balance(&s) != 0 || s.cnt[0].lost != 0;
    }
    printf("  largest backlog %zu, at the end %zu; fed %llu, coarse %llu, lost %llu\n", most,
           s.nback, (unsigned long long)s.cnt[0].fed, (unsigned long long)s.cnt[0].coarse,
           (unsigned long long)s.cnt[0].lost);
    CHECK(!bad && most > 10 && s.cnt[0].fed > 50, "V5 backlog: balance %d, backlog %zu", bad, most);
    mote_sep_free(&s);
}

/* Usage: test_sep_dem [NAME]: all tests, or the one named (pairs, momentum, elastic,
 * restitution, many_body, backlog). */
/* restitution_pair: species a and b with e_pp 0.9 and the pair (a, b) at 0.3: an a-b collision
 * ends with 0.3, an a-a one with 0.9 (mean over 20 phases within 1%). */
static void test_pair_restitution(void)
{
    printf("restitution_pair\n");
    for (int same = 0; same <= 1; same++) {
        double mean = 0;
        for (int k = 0; k < 20; k++) {
            mote_sep_system s;
            mote_err err = {0};
            vacuum_box(&s, 2, 0.01, 0.01, 0, 2500, (mote_sep_dist){.type = MOTE_SEP_MONO, .a = 1e-3});
            s.nsp = 2;
            s.sp[1] = s.sp[0];
            snprintf(s.sp[1].name, sizeof s.sp[1].name, "b");
            s.sp[0].w = s.sp[1].w = 0.5;
            s.dem = 0;
            s.zf = 0.005;
            s.hf = 0.002;
            s.e_pp = 0.9;
            s.e_pair[0][1] = s.e_pair[1][0] = 0.3;
            s.v_imp = 1;
            CHECK(mote_sep_prepare(&s, &err) == MOTE_OK && mote_sep_insert(&s, 0, 1, 0, &err) == MOTE_OK &&
                  mote_sep_insert(&s, same ? 0 : 1, 1, 0, &err) == MOTE_OK, "setup: %s", err.msg);
            s.dem = 1;
            CHECK(mote_sep_prepare(&s, &err) == MOTE_OK, "prepare: %s", err.msg);
            s.x[0] = s.x[1] = 0.005;
            s.z[0] = 0.004;
            s.z[1] = 0.005 + 1.0 * (3 + (k + 0.5) / 20) * s.dt;
            s.vz[0] = 0.5;
            s.vz[1] = -0.5;
            CHECK(mote_sep_run(&s, 200 * s.dt, &err) == MOTE_OK, "run: %s", err.msg);
            mean += (s.vz[1] - s.vz[0]) / 20;
            mote_sep_free(&s);
        }
        const double want = same ? 0.9 : 0.3;
        printf("  %s: mean restitution %.5f (%.1f)\n", same ? "a-a" : "a-b", mean, want);
        CHECK(fabs(mean / want - 1) <= 0.01, "pair restitution %s: %.5f", same ? "a-a" : "a-b",
              mean);
    }
}

/* A particle of diameter d in still air over a plate at z 0.01 ... 0.0105 m of a channel
 * 5 mm across (3D: 5 x 5 mm) with one square hole of side a centred at (xh, yh), or (a = 0) a
 * hole at the side; v_imp 1 m/s. The particle starts at rest at (x, y, z). */
static void plate_case(mote_sep_system *s, int dim, double d, double a, double x, double y,
                       double z)
{
    mote_err err = {0};
    mote_sep_init(s);
    s->dim = dim;
    s->W = s->D = 5e-3;
    s->H = 0.03;
    s->open_bottom = 0;
    s->U0 = 0;
    s->nsp = 1;
    snprintf(s->sp[0].name, sizeof s->sp[0].name, "p");
    s->sp[0].rho = 2500;
    s->sp[0].w = 1;
    /* sizes down to 0.4 d, so that a hole of 0.8 d passes the finest */
    s->sp[0].dist = (mote_sep_dist){.type = MOTE_SEP_LOGUNIFORM, .lo = 0.4 * d, .hi = d};
    CHECK(mote_sep_dist_build(&s->sp[0].dist, &err) == MOTE_OK, "dist: %s", err.msg);
    s->sp[0].have_dist = 1;
    s->zf = 0.02;
    s->hf = 2e-3;
    s->v_imp = 1;
    const double c = 2.5e-3;
    double h[4] = {c - 0.5 * a, c + 0.5 * a, c - 0.5 * a, c + 0.5 * a};
    if (!(a > 0)) { /* a slot by the wall, away from the particle */
        h[0] = 4e-3;
        h[1] = 5e-3;
        h[2] = 0;
        h[3] = 5e-3;
    }
    CHECK(mote_sep_plate_list(&s->plate[0], 0.01, 0.5e-3, h, 1, &err) == MOTE_OK, "plate: %s",
          err.msg);
    s->nplate = 1;
    CHECK(mote_sep_prepare(s, &err) == MOTE_OK, "prepare: %s", err.msg);
    CHECK(mote_sep_insert(s, 0, 1, 0, &err) == MOTE_OK && s->n == 1, "insert: %s", err.msg);
    s->x[0] = x;
    s->y[0] = dim == 3 ? y : 0;
    s->z[0] = z;
    s->d[0] = d;
    s->m[0] = s->cnt[0].m_fed = 2500 * PI * d * d * d / 6;
    s->im[0] = 1 / s->m[0];
}

/* V9: a sphere on a square hole of side 0.8 d rests (no drift over 1 s; centred, the horizontal
 * contact force is 0 to 1e-12); a sphere of 0.5 a over a hole of side a passes; a particle on
 * solid plate rests at the static overlap m g' / (k_hat d) within 1%. In 2D and 3D. */
static void test_grids(void)
{
    printf("V9: grids\n");
    const double d = 1e-3, c = 2.5e-3, zt = 0.0105;
    mote_err err = {0};
    /* under the sanitizers (MOTE_SANITIZED) 3D only, whose faces include 2D's: the plain build
     * runs both (each is seconds of simulated rest at the contacts' step) */
    const int dim0 = getenv("MOTE_SANITIZED") ? 3 : 2;
    if (dim0 == 3)
        printf("  MOTE_SANITIZED: 3D only (2D in the plain build)\n");
    for (int dim = dim0; dim <= 3; dim++) {
        mote_sep_system s;
        /* resting on the hole's edges */
        plate_case(&s, dim, d, 0.8 * d, c, c, zt + 0.4 * d);
        CHECK(mote_sep_run(&s, 0.2, &err) == MOTE_OK, "run: %s", err.msg);
        const double x5 = s.x[0], y5 = s.y[0], z5 = s.z[0];
        CHECK(mote_sep_run(&s, 0.2, &err) == MOTE_OK, "run: %s", err.msg);
        const double drift = sqrt((s.x[0] - x5) * (s.x[0] - x5) + (s.y[0] - y5) * (s.y[0] - y5) +
                                  (s.z[0] - z5) * (s.z[0] - z5));
        const double fh = sqrt(s.fx[0] * s.fx[0] + s.fy[0] * s.fy[0]) / fabs(s.fz[0]);
        /* the rest height: the centre above the edges' corner circle */
        const double rest = zt + 0.3 * d; /* touching the faces' top edges at 0.4 d */
        printf("  %dD on a hole of 0.8 d: z %.6g m (rest without overlap %.6g), drift over "
               "0.5 s %.2e m, |F_h|/F_z %.2e, lost %llu\n", dim, s.z[0], rest, drift, fh,
               (unsigned long long)s.cnt[0].lost);
        CHECK(s.n == 1 && s.z[0] > zt && s.z[0] < rest && drift <= 1e-9 && fh <= 1e-12,
              "V9 rests %dD: z %.6g drift %.3e fh %.3e", dim, s.z[0], drift, fh);
        mote_sep_free(&s);
        /* off centre it slides to the centre and stays */
        plate_case(&s, dim, d, 0.8 * d, c + 0.05 * d, c - 0.03 * d, zt + 0.4 * d);
        CHECK(mote_sep_run(&s, 0.2, &err) == MOTE_OK, "run: %s", err.msg);
        const double xo = s.x[0], yo = s.y[0], zo = s.z[0];
        CHECK(mote_sep_run(&s, 0.2, &err) == MOTE_OK, "run: %s", err.msg);
        const double drift2 = sqrt((s.x[0] - xo) * (s.x[0] - xo) + (s.y[0] - yo) * (s.y[0] - yo) +
                                   (s.z[0] - zo) * (s.z[0] - zo));
        const double off = sqrt((s.x[0] - c) * (s.x[0] - c) + (dim == 3 ? (s.y[0] - c) * (s.y[0] - c) : 0));
        printf("  %dD started off centre: %.2e m from the centre at 0.4 s, drift over the last "
               "0.2 s %.2e m\n", dim, off, drift2);
        CHECK(s.n == 1 && drift2 <= 1e-9 && off <= 1e-9, "V9 off centre %dD: %.3e %.3e", dim,
              drift2, off);
        mote_sep_free(&s);
        /* passing: 0.5 a over a hole of side a */
        plate_case(&s, dim, d, 2 * d, c, c, zt + d);
        CHECK(mote_sep_run(&s, 0.03, &err) == MOTE_OK, "run: %s", err.msg);
        printf("  %dD 0.5 a over a hole of a: z %.4g m after 0.03 s (plate at 0.01 m), largest "
               "overlap %.3g\n", dim, s.z[0], s.max_overlap);
        CHECK(s.n == 1 && s.z[0] < 0.01 - 0.5 * d && s.max_overlap == 0, "V9 passes %dD: z %.5g",
              dim, s.z[0]);
        mote_sep_free(&s);
        /* on solid: the static overlap */
        plate_case(&s, dim, d, 0, c, c, zt + 0.6 * d);
        CHECK(mote_sep_run(&s, 0.3, &err) == MOTE_OK, "run: %s", err.msg);
        const double gp = s.g * (1 - s.rho_g / 2500);
        const double want = s.m[0] * gp / (s.khat_used * d), got = zt + 0.5 * d - s.z[0];
        printf("  %dD on solid: overlap %.6g m, m g'/(k_hat d) = %.6g m (%+.2e; m %.4g d %.4g)\n",
               dim, got, want, got / want - 1, s.m[0], s.d[0]);
        CHECK(fabs(got / want - 1) <= 0.01, "V9 static overlap %dD: %.6g against %.6g", dim, got,
              want);
        mote_sep_free(&s);
    }
}

/* A channel far taller than its particles (9 km for millimetre grains, found by fuzzing: each
 * search cleared 10^8 cells) gets about one cell per particle, and its pairs are still those of
 * brute force; filling an empty channel sorts the cells again as it grows. */
static void test_tall(void)
{
    printf("a tall channel\n");
    mote_sep_system s;
    vacuum_box(&s, 2, 0.01, 9291, 0.01, 2500, (mote_sep_dist){.type = MOTE_SEP_MONO, .a = 1e-3});
    s.zf = 0.05;
    s.hf = 0.1;
    fill(&s, 300);
    uint32_t a[2 * 2000], b[2 * 2000];
    const size_t na = mote_sep_pairs(&s, 0, a, 2000), nb = mote_sep_pairs(&s, 1, b, 2000);
    CHECK(s.n == 300 && s.grid.ncells <= s.n + 27, "%zu particles in %zu cells", s.n,
          s.grid.ncells);
    CHECK(na == nb && na < 2000 && !memcmp(a, b, 2 * na * sizeof *a),
          "cells %zu pairs, brute force %zu", na, nb);
    printf("  300 particles placed without overlap in %zu cells (%d x %d), %zu close pairs\n",
           s.grid.ncells, s.grid.nc[0], s.grid.nc[1], na);
    mote_sep_free(&s);
}

/* The first list build puts particles placed at random in the order of their cells (memory
 * locality from the first step, not only after nsort steps): after one step the cells of the
 * particles never decrease along the arrays. */
static void test_first_sort(void)
{
    printf("particles sorted by cell at the first list build\n");
    for (int dim = 2; dim <= 3; dim++) {
        mote_sep_system s;
        vacuum_box(&s, dim, 0.04, 0.08, 0.04, 2500,
                   (mote_sep_dist){.type = MOTE_SEP_MONO, .a = 1e-3});
        s.v_imp = 1;
        fill(&s, dim == 2 ? 500 : 4000);
        mote_err err = {0};
        CHECK(mote_sep_run(&s, s.dt, &err) == MOTE_OK, "run: %s", err.msg);
        size_t down = 0;
        for (size_t i = 1; i < s.n; i++)
            down += s.grid.cell[i] < s.grid.cell[i - 1];
        CHECK(s.list_builds == 1 && s.last_sort == s.steps && down == 0,
              "%dD: %llu builds, sorted at step %llu of %llu, %zu descents in the cell order",
              dim, (unsigned long long)s.list_builds, (unsigned long long)s.last_sort,
              (unsigned long long)s.steps, down);
        printf("  %dD: %zu particles, %zu cells, %zu descents\n", dim, s.n, s.grid.ncells, down);
        mote_sep_free(&s);
    }
}

/* One case of the thread test: a channel open at both ends with a gas upflow felt by the solids
 * (coupling), a perforated plate, a feed, n particles to start; runs `steps` steps on nt
 * threads (used from 1 particle up) and writes its state to path. flags: 1 every row searched
 * (no_gap_skip), 2 every step completed (no_pending), 4 contact hertz (friction, rolling
 * friction, cohesion, rotation; 8: stop half way, save, load and go on; 16, 32: its law on
 * at most 2, 4 lanes; 64: no plate, so that the box's walls are made by lanes too). */
static void threads_case(mote_sep_system *s, int dim, size_t n, int steps, int nt, int disperse,
                         int flags, const char *path)
{
    mote_err err = {0};
    mote_sep_init(s);
    s->dim = dim;
    s->W = s->D = dim == 3 ? 0.015 : 0.05;
    s->H = dim == 3 ? 0.04 : 0.1;
    s->U0 = 1.2;
    s->nsp = 1;
    snprintf(s->sp[0].name, sizeof s->sp[0].name, "p");
    s->sp[0].rho = 2500;
    s->sp[0].w = 1;
    s->sp[0].dist = (mote_sep_dist){.type = MOTE_SEP_LOGUNIFORM, .lo = 0.5e-3, .hi = 1e-3,
                                    .number_basis = 1};
    CHECK(mote_sep_dist_build(&s->sp[0].dist, &err) == MOTE_OK, "dist: %s", err.msg);
    s->sp[0].have_dist = 1;
    s->zf = 0.5 * s->H;
    s->hf = 0.9 * s->H;
    s->v_imp = 1;
    s->rate = dim == 3 ? 0.05 : 0.02; /* kg/s: a few particles each step */
    if (disperse)
        s->D_t = 1e-3;
    /* a plate of square holes of 2 mm at 2 mm pitch near the bottom */
    double h[4 * 64];
    size_t nh = 0;
    const int nx = (int)(s->W / 4e-3);
    for (int a = 0; a < nx; a++)
        for (int b = 0; b < (dim == 3 ? nx : 1); b++) {
            h[4 * nh] = 1e-3 + 4e-3 * a;
            h[4 * nh + 1] = h[4 * nh] + 2e-3;
            h[4 * nh + 2] = 1e-3 + 4e-3 * b;
            h[4 * nh + 3] = h[4 * nh + 2] + 2e-3;
            nh++;
        }
    if (!(flags & 64)) {
        CHECK(mote_sep_plate_list(&s->plate[0], 0.005, 1e-3, h, nh, &err) == MOTE_OK,
              "plate: %s", err.msg);
        s->nplate = 1;
    }
    s->nsort = 40; /* (reorders within the run) */
    if (flags & 4) {
        s->hertz = 1;
        s->sp[0].E = 5e6;
        s->sp[0].nu = 0.3;
        s->mu_pp = 0.5;
        s->mu_pw = 0.3;
        s->mur_pp = 0.05;
        s->coh_pp = 1e4;
    }
    CHECK(mote_sep_prepare(s, &err) == MOTE_OK, "prepare: %s", err.msg);
    CHECK(mote_sep_insert(s, 0, n, 0, &err) == MOTE_OK, "insert: %s", err.msg);
    s->nback = 0;
    s->avg_from = 0;
    /* velocities of about 1 m/s in all directions, so that contacts come soon; every 300th
     * particle just below the open top, leaving upwards */
    for (size_t i = 0; i < s->n; i++) {
        s->vx[i] = sin((double)i);
        s->vy[i] = dim == 3 ? cos(1.3 * (double)i) : 0;
        s->vz[i] = sin(0.7 * (double)i);
        if (i % 300 == 0) {
            s->z[i] = s->H - 1e-5;
            s->vz[i] = 3;
        }
    }
    s->mods++; /* (positions set by hand) */
    s->threads = nt;
    s->threads_min_n = 1;
    s->no_gap_skip = flags & 1;
    s->no_pending = (flags & 2) != 0;
    s->simd = flags & 16 ? 2 : flags & 32 ? 4 : 0;
    if (flags & 4) { /* two halves (with 8 saved and loaded into a new system between) */
        const double T = 0.5 * steps * s->dt;
        CHECK(mote_sep_run(s, T, &err) == MOTE_OK, "run: %s", err.msg);
        if (flags & 8) {
            CHECK(mote_sep_save(s, 1, path, &err) == MOTE_OK, "save: %s", err.msg);
            mote_sep_free(s);
            mote_sep_init(s);
            uint64_t seed;
            CHECK(mote_sep_load(s, &seed, path, &err) == MOTE_OK, "load: %s", err.msg);
            s->threads = nt;
            s->threads_min_n = 1;
            s->no_pending = (flags & 2) != 0;
            s->simd = flags & 16 ? 2 : flags & 32 ? 4 : 0;
        }
        CHECK(mote_sep_run(s, T, &err) == MOTE_OK, "run: %s", err.msg);
    } else {
        CHECK(mote_sep_run(s, steps * s->dt, &err) == MOTE_OK, "run: %s", err.msg);
    }
    CHECK(mote_sep_save(s, 1, path, &err) == MOTE_OK, "save: %s", err.msg);
}

/* contact hertz: one sphere (d 2 mm, glass-like, E 5 MPa) hits the floor of a closed box in
 * vacuum without gravity at normal speed vn and tangential speed vt (x), spinning at w0 about y;
 * the velocities and spin after it leaves the floor into out[0..2] (vz, vx, wy). */
static void hertz_impact(double vn, double vt, double w0, double e, double mu, int liggghts,
                         int nc, double out[3])
{
    mote_sep_system s;
    vacuum_box(&s, 3, 0.02, 0.02, 0.02, 2500, (mote_sep_dist){.type = MOTE_SEP_MONO, .a = 2e-3});
    s.hertz = 1;
    s.e_true = !liggghts;
    s.sp[0].E = 5e6;
    s.sp[0].nu = 0.3;
    s.e_pp = e;
    s.mu_pp = mu;
    s.v_imp = vn;
    s.nc = nc;
    fill(&s, 1);
    s.x[0] = s.y[0] = 0.01;
    s.z[0] = 1e-3 + 1e-6;
    s.vx[0] = vt;
    s.vy[0] = 0;
    s.vz[0] = -vn;
    s.mods++; /* (set by hand) */
    mote_err err = {0};
    CHECK(sep_rot_reserve_for_test(&s) == 0, "rotation arrays");
    s.w[1] = w0;
    /* the contact lasts about N_c steps: 4 N_c steps and the approach */
    CHECK(mote_sep_run(&s, 1e-6 / vn + 4 * s.nc * s.dt, &err) == MOTE_OK, "run: %s", err.msg);
    CHECK(s.z[0] > 1e-3, "the sphere left the floor (z %.6g)", s.z[0]);
    out[0] = s.vz[0];
    out[1] = s.vx[0];
    out[2] = s.w[1];
    mote_sep_free(&s);
}

/* Single impacts on a wall against their analytic results (the rigid-body limits of Maw,
 * Barber and Fawcett's problem as Thornton et al., Powder Technol. 233 (2013) 30, normalise
 * them: psi = 2 v_c / (mu (1 + e) v_n), v_c the contact point's tangential speed): head-on, the
 * restitution given (restitution=exact; within the step's error at dt = t_c/50, measured below
 * 1e-3; the contact's start and end fall between steps, an error of order dt / t_c, so it
 * shrinks with N_c: below 5e-4 at N_c = 400) and LIGGGHTS's beta giving 0.55 for 0.5; in gross sliding (psi1 = 13.3 > 7) the
 * tangential impulse is mu times the normal one and the spin 5/2 of it over r, to rounding, so
 * psi2 = psi1 - 7; at every angle no energy is gained; a spinning sphere dropped straight down
 * leaves with the spin and speed the same laws give. */
static void test_hertz_impacts(void)
{
    printf("contact hertz: oblique impacts on a wall (Thornton's normalised angles)\n");
    double o[3];
    const double es[3] = {0.3, 0.5, 0.9};
    for (int k = 0; k < 3; k++) {
        double o2[3];
        hertz_impact(1, 0, 0, es[k], 0, 0, 50, o);
        hertz_impact(1, 0, 0, es[k], 0, 0, 400, o2);
        CHECK(fabs(o[0] / es[k] - 1) <= 5e-3 && fabs(o2[0] / es[k] - 1) <= 5e-4 && o[1] == 0,
              "head-on e %.1f: %.6f (N_c 50), %.6f (N_c 400)", es[k], o[0], o2[0]);
        printf("  head-on e %.1f: rebound %.6f at N_c 50, %.6f at N_c 400 (restitution=exact)\n",
               es[k], o[0], o2[0]);
    }
    hertz_impact(1, 0, 0, 0.5, 0, 1, 400, o);
    CHECK(fabs(o[0] - 0.550) <= 1e-3, "liggghts e 0.5: %.6f", o[0]);
    printf("  head-on e 0.5, restitution=liggghts: rebound %.4f\n", o[0]);
    hertz_impact(3, 0, 0, 0.5, 0, 0, 400, o);
    CHECK(fabs(o[0] / 1.5 - 1) <= 5e-4, "head-on at 3 m/s: %.6f", o[0]);
    const double mu = 0.3, e = 0.5, r = 1e-3;
    hertz_impact(1, 0, 0, e, mu, 0, 50, o);
    const double en = o[0];
    printf("  psi1     psi2     (v_t in, out; w r out)\n");
    const double vts[6] = {0.02, 0.1, 0.3, 0.6, 1.0, 3.0};
    for (int k = 0; k < 6; k++) {
        hertz_impact(1, vts[k], 0, e, mu, 0, 50, o);
        const double psi1 = 2 * vts[k] / (mu * (1 + en)), vc = o[1] - o[2] * r;
        const double psi2 = 2 * vc / (mu * (1 + en));
        const double E0 = 0.5 * (1 + vts[k] * vts[k]);
        const double E1 = 0.5 * (o[0] * o[0] + o[1] * o[1]) + 0.5 * 0.4 * r * r * o[2] * o[2];
        CHECK(E1 <= E0 && fabs(o[0] / en - 1) <= 1e-12,
              "psi1 %.3f: energy %.6g -> %.6g, normal rebound %.6f", psi1, E0, E1, o[0]);
        if (psi1 > 7.5) {
            const double dvt = vts[k] - o[1], jn = o[0] + 1;
            CHECK(fabs(dvt / (mu * jn) - 1) <= 1e-9 && fabs(o[2] * r / (2.5 * dvt) - 1) <= 1e-9 &&
                  fabs(psi2 - (psi1 - 7)) <= 1e-8 * psi1,
                  "gross sliding psi1 %.3f: dv_t %.12g against mu J_n %.12g, w r %.12g against "
                  "5/2 dv_t, psi2 %.9f against %.9f", psi1, dvt, mu * jn, o[2] * r, psi2, psi1 - 7);
        } else {
            CHECK(psi2 < psi1 && psi2 > -psi1, "psi1 %.3f: psi2 %.4f", psi1, psi2);
        }
        printf("  %7.3f  %7.3f  (%.3f, %.4f; %.4f)\n", psi1, psi2, vts[k], o[1], o[2] * r);
    }
}

/* contact hertz: a free cluster (no gravity, no wall reached) of 125 spheres of two sizes,
 * 2D and 3D, started close with random velocities and spins, with friction, rolling friction
 * and damping: the momentum and the angular momentum about the origin (orbital and spin) are
 * kept to rounding (the forces are exact opposites and their couple about the contact point is
 * zero), while the energy falls. */
static void test_hertz_momentum(void)
{
    printf("contact hertz: momentum and angular momentum of a free cluster\n");
    for (int dim = 2; dim <= 3; dim++) {
        mote_sep_system s;
        vacuum_box(&s, dim, 0.2, 0.2, 0.2, 2500,
                   (mote_sep_dist){.type = MOTE_SEP_LOGUNIFORM, .lo = 1e-3, .hi = 2e-3,
                                   .number_basis = 1});
        s.hertz = 1;
        s.sp[0].E = 5e6;
        s.sp[0].nu = 0.3;
        s.mu_pp = 0.5;
        s.mur_pp = 0.1;
        s.e_pp = 0.7;
        s.v_imp = 1;
        s.rate = 0;
        fill(&s, 0);
        mote_err err = {0};
        CHECK(sep_rot_reserve_for_test(&s) == 0, "rotation arrays");
        const int side = dim == 3 ? 5 : 11;
        size_t n = 0;
        for (int a = 0; a < side; a++)
            for (int b = 0; b < side; b++)
                for (int c = 0; c < (dim == 3 ? side : 1); c++)
                    n++;
        CHECK(mote_sep_insert(&s, 0, n, 0, &err) == MOTE_OK && s.n == n, "insert: %s", err.msg);
        /* a lattice at 2.1 mm, velocities towards the centre and sideways, spins */
        size_t i = 0;
        for (int a = 0; a < side; a++)
            for (int b = 0; b < side; b++)
                for (int c = 0; c < (dim == 3 ? side : 1); c++, i++) {
                    s.x[i] = 0.1 + 2.1e-3 * (a - side / 2);
                    s.y[i] = dim == 3 ? 0.1 + 2.1e-3 * (c - side / 2) : 0;
                    s.z[i] = 0.1 + 2.1e-3 * (b - side / 2);
                    s.vx[i] = -200 * (s.x[i] - 0.1) + 0.2 * sin(3.0 * (double)i);
                    s.vy[i] = dim == 3 ? -200 * (s.y[i] - 0.1) + 0.2 * cos(2.0 * (double)i) : 0;
                    s.vz[i] = -200 * (s.z[i] - 0.1) + 0.2 * sin(5.0 * (double)i);
                    s.w[3 * i] = dim == 3 ? 300 * sin(7.0 * (double)i) : 0;
                    s.w[3 * i + 1] = 300 * cos(11.0 * (double)i);
                    s.w[3 * i + 2] = dim == 3 ? 300 * sin(13.0 * (double)i) : 0;
                }
        s.mods++;
        double P0[3], L0[3], E0, P1[3], L1[3], E1;
        uint64_t contacts = 0;
        for (int pass = 0; pass < 2; pass++) {
            double *P = pass ? P1 : P0, *L = pass ? L1 : L0, *E = pass ? &E1 : &E0;
            if (pass)
                for (int k = 0; k < 40; k++) {
                    CHECK(mote_sep_run(&s, 25 * s.dt, &err) == MOTE_OK, "run: %s", err.msg);
                    contacts += s.contacts_pp;
                }
            memset(P, 0, 3 * sizeof *P);
            memset(L, 0, 3 * sizeof *L);
            *E = 0;
            for (size_t j = 0; j < s.n; j++) {
                const double m = s.m[j], I = 0.1 * m * s.d[j] * s.d[j];
                const double x[3] = {s.x[j], dim == 3 ? s.y[j] : 0, s.z[j]};
                const double v[3] = {s.vx[j], s.vy[j], s.vz[j]};
                for (int a = 0; a < 3; a++) {
                    P[a] += m * v[a];
                    L[a] += I * s.w[3 * j + a] +
                            m * (x[(a + 1) % 3] * v[(a + 2) % 3] - x[(a + 2) % 3] * v[(a + 1) % 3]);
                    *E += 0.5 * m * v[a] * v[a] + 0.5 * I * s.w[3 * j + a] * s.w[3 * j + a];
                }
            }
        }
        double dP = 0, dL = 0, Ls = 0;
        for (size_t j = 0; j < s.n; j++)
            Ls += s.m[j] * 0.1 * 2; /* (a scale for L: m |x| |v|, |x| ~ 0.14, |v| ~ 1) */
        for (int a = 0; a < 3; a++) {
            dP = fmax(dP, fabs(P1[a] - P0[a]));
            dL = fmax(dL, fabs(L1[a] - L0[a]));
        }
        int walls = 0;
        for (size_t j = 0; j < s.n; j++)
            walls += fabs(s.x[j] - 0.1) > 0.09 || fabs(s.z[j] - 0.1) > 0.09;
        CHECK(contacts > 10 * s.n && s.n == n && walls == 0 && E1 < 0.9 * E0 && dP <= 1e-13 * Ls &&
              dL <= 1e-13 * 0.14 * Ls, "%dD: %llu contacts, energy %.4g -> %.4g, |dP| %.3g, |dL| "
              "%.3g (scale %.3g)", dim, (unsigned long long)contacts, E0, E1, dP, dL, Ls);
        printf("  %dD N %zu: %llu contact-steps, energy %.4g -> %.4g J, |dP| %.2g, |dL| %.2g "
               "(|L| scale %.2g)\n", dim, s.n, (unsigned long long)contacts, E0, E1, dP, dL,
               0.14 * Ls);
        mote_sep_free(&s);
    }
}

/* The overlap where f(delta) = 0, f increasing through it on [lo, hi], by bisection. */
static double root(double (*f)(double, const double *), const double *par, double lo, double hi)
{
    for (int k = 0; k < 200; k++) {
        const double mid = 0.5 * (lo + hi);
        if (f(mid, par) > 0)
            hi = mid;
        else
            lo = mid;
    }
    return 0.5 * (lo + hi);
}
/* par: Y*, R*, k_c, r, m g: Hertz's force minus the cohesion (two spheres of radius r: the
 * circle's area pi (r delta - delta^2 / 4); a sphere on a wall: pi (2 r delta - delta^2)), minus
 * the weight */
static double f_pair(double delta, const double *p)
{
    return 4.0 / 3.0 * p[0] * sqrt(p[1]) * delta * sqrt(delta) -
           p[2] * PI * (p[3] * delta - 0.25 * delta * delta) - p[4];
}
static double f_wall(double delta, const double *p)
{
    return 4.0 / 3.0 * p[0] * sqrt(p[1]) * delta * sqrt(delta) -
           p[2] * PI * (2 * p[3] * delta - delta * delta) - p[4];
}

/* contact hertz with cohesion (SJKR): two spheres set touching without gravity pull each
 * other into the overlap where Hertz's repulsion equals k_c times the contact area; a sphere on
 * the floor under gravity rests where Hertz's force is its weight plus the cohesion: both
 * within 1e-9 d of the roots (the dashpots damp the rest away); without cohesion the pair, set
 * 0.1 um into contact, is pushed apart. */
static void test_hertz_cohesion(void)
{
    printf("contact hertz: cohesion's equilibrium overlaps\n");
    const double E = 5e6, nu = 0.3, d = 3e-3, r = 0.5 * d, kc = 1e5;
    const double Y = 1 / (2 * (1 - nu * nu) / E), m = 2500 * PI / 6 * d * d * d;
    for (int wall = 0; wall < 2; wall++)
        for (int coh = 0; coh < 2; coh++) {
            mote_sep_system s;
            vacuum_box(&s, 3, 0.02, 0.02, 0.02, 2500,
                       (mote_sep_dist){.type = MOTE_SEP_MONO, .a = d});
            s.hertz = 1;
            s.sp[0].E = E;
            s.sp[0].nu = nu;
            s.mu_pp = 0.5;
            s.coh_pp = coh ? kc : 0;
            s.g = wall ? 9.81 : 0;
            fill(&s, wall ? 1 : 2);
            s.x[0] = s.y[0] = 0.01;
            s.z[0] = wall ? r : 0.01;
            s.vx[0] = s.vy[0] = s.vz[0] = 0;
            if (!wall) {
                s.x[1] = 0.01 + d - 1e-7, s.y[1] = 0.01, s.z[1] = 0.01; /* (touching) */
                s.vx[1] = s.vy[1] = s.vz[1] = 0;
            }
            s.mods++;
            mote_err err = {0};
            CHECK(mote_sep_run(&s, 0.1, &err) == MOTE_OK, "run: %s", err.msg);
            const double got = wall ? r - s.z[0] : d - fabs(s.x[1] - s.x[0]);
            const double par[5] = {Y, wall ? r : 0.5 * r, coh ? kc : 0, r, wall ? m * 9.81 : 0};
            const double want = !coh && !wall ? 0 : root(wall ? f_wall : f_pair, par, 1e-12, 0.5 * r);
            CHECK(!coh && !wall ? got < 0 : fabs(got - want) <= 1e-9 * d, "%s, cohesion %g: overlap %.9g against %.9g",
                  wall ? "on the floor" : "a pair", par[2], got, want);
            printf("  %s, k_c %g J/m^3: overlap %.6e m (root %.6e)\n",
                   wall ? "a sphere on the floor" : "two spheres", par[2], got, want);
            mote_sep_free(&s);
        }
}

/* contact hertz at the box's walls: the walls made by lanes (no plate) give the bits of the
 * walls made one by one (the same run with a plate far above the particles, which sends every
 * wall to the scalar law): three spinning spheres dropped against a side wall and the floor,
 * sliding and rolling, with cohesion and rolling friction. (A particle touching both walls of
 * an axis, which share one spring and go one by one, needs a box narrower than the particle,
 * which prepare refuses.) */
static void hertz_walls_run(double W, int plate, const char *path, size_t *lanes, size_t *twice)
{
    mote_sep_system s;
    const double d = 2e-3, H = 0.02;
    vacuum_box(&s, 3, W, H, 0.01, 2500, (mote_sep_dist){.type = MOTE_SEP_MONO, .a = d});
    s.g = 9.81;
    s.hertz = 1;
    s.sp[0].E = 5e6;
    s.sp[0].nu = 0.3;
    s.mu_pp = 0.3;
    s.mur_pp = 0.05;
    s.coh_pp = 1e3;
    s.v_imp = 1;
    mote_err err = {0};
    if (plate) { /* (2 mm thick, 5 mm below the top, one hole) */
        const double h[4] = {0, 3e-3, 0, 3e-3};
        CHECK(mote_sep_plate_list(&s.plate[0], H - 5e-3, 2e-3, h, 1, &err) == MOTE_OK,
              "plate: %s", err.msg);
        s.nplate = 1;
    }
    const size_t n = W > d ? 3 : 1;
    fill(&s, n);
    CHECK(sep_rot_reserve_for_test(&s) == 0 && s.n == n, "particles and rotation");
    for (size_t i = 0; i < n; i++) {
        s.x[i] = W > d ? 0.5 * d + 2e-5 * (double)i : 0.5 * W;
        s.y[i] = 2.5e-3 + 2.5e-3 * (double)i;
        s.z[i] = 0.5 * d + 1e-4 + 1e-3 * (double)i;
        s.vx[i] = -0.05 * (double)(i + 1);
        s.vy[i] = 0.1;
        s.vz[i] = -0.2;
        s.w[3 * i] = 50, s.w[3 * i + 1] = -30, s.w[3 * i + 2] = 20;
    }
    s.mods++;
    *lanes = *twice = 0;
    for (int k = 0; k < 100; k++) {
        CHECK(mote_sep_run(&s, 20 * s.dt, &err) == MOTE_OK, "run: %s", err.msg);
        for (size_t i = 0; !plate && i < s.n; i++) { /* (wflag: the lanes' only) */
            *lanes += s.wflag[i] == 1;
            *twice += s.wflag[i] == 2;
        }
    }
    CHECK(mote_sep_save(&s, 1, path, &err) == MOTE_OK, "save: %s", err.msg);
    mote_sep_free(&s);
}

/* Whether two state files are the same but for their plates' lines (plates, plate, hole). */
static int same_but_plates(const char *a, const char *b)
{
    FILE *f[2] = {fopen(a, "r"), fopen(b, "r")};
    int same = f[0] && f[1];
    char line[2][4096];
    while (same) {
        int got[2];
        for (int k = 0; k < 2; k++)
            do
                got[k] = fgets(line[k], sizeof line[k], f[k]) != NULL;
            while (got[k] && (!strncmp(line[k], "plates ", 7) || !strncmp(line[k], "plate ", 6) ||
                              !strncmp(line[k], "hole ", 5)));
        same = got[0] == got[1] && (!got[0] || !strcmp(line[0], line[1]));
        if (!got[0] || !got[1])
            break;
    }
    for (int k = 0; k < 2; k++)
        if (f[k])
            fclose(f[k]);
    return same;
}

static void test_hertz_walls(void)
{
    printf("contact hertz: the box's walls by lanes give the bits of the walls one by one\n");
    const double Ws[1] = {0.01};
    for (int c = 0; c < 1; c++) {
        char path[2][64];
        size_t lanes[2], twice[2];
        for (int p = 0; p < 2; p++) {
            snprintf(path[p], sizeof path[p], "/tmp/mote_sep_hwalls_%d_%d.state", c, p);
            hertz_walls_run(Ws[c], p, path[p], &lanes[p], &twice[p]);
        }
        CHECK(lanes[0] > 0, "W %g: walls by lanes %zu times", Ws[c], lanes[0]);
        CHECK(same_but_plates(path[0], path[1]), "W %g: the state with the walls by lanes equals "
              "the one with the walls one by one (but for the plate's lines)", Ws[c]);
        printf("  W %g mm: %zu particle-steps at the walls by lanes (%zu both walls of an axis)\n",
               Ws[c] * 1e3, lanes[0], twice[0]);
        for (int p = 0; p < 2; p++)
            if (!getenv("KEEP"))
                remove(path[p]);
    }
}

/* contact hertz with two materials (E 5 and 20 MPa): head-on collisions a-a, a-b and b-b at
 * once (one block of the law's lanes holding three sets of constants) each last the Hertz
 * contact time of the pair's own Y* = 1 / ((1 - nu^2) / E_1 + (1 - nu^2) / E_2), R* and m*,
 * t_c = 2.868 (m*^2 / (R* Y*^2 v))^(1/5) (e = 1: no damping), within 2 steps (a contact starts
 * and ends between steps); a-b's is 17% from a-a's, so a pair given another pair's constants
 * fails. */
static void test_hertz_pairs(void)
{
    printf("contact hertz: two materials, the constants of each pair\n");
    mote_sep_system s;
    const double d = 2e-3, E[2] = {5e6, 2e7}, nu = 0.3, v = 1;
    vacuum_box(&s, 3, 0.06, 0.02, 0.02, 2500, (mote_sep_dist){.type = MOTE_SEP_MONO, .a = d});
    s.nsp = 2;
    s.sp[1] = s.sp[0];
    snprintf(s.sp[1].name, sizeof s.sp[1].name, "b");
    s.sp[0].w = s.sp[1].w = 0.5;
    s.hertz = 1;
    s.e_pp = 1;
    s.mu_pp = 0.5;
    s.v_imp = v;
    for (int k = 0; k < 2; k++) {
        s.sp[k].E = E[k];
        s.sp[k].nu = nu;
    }
    mote_err err = {0};
    CHECK(mote_sep_prepare(&s, &err) == MOTE_OK, "prepare: %s", err.msg);
    CHECK(mote_sep_insert(&s, 0, 3, 0, &err) == MOTE_OK &&
          mote_sep_insert(&s, 1, 3, 0, &err) == MOTE_OK && s.n == 6, "insert: %s", err.msg);
    /* the pairs (a, a), (a, b), (b, b) along x at x = 10, 30, 50 mm, closing at v */
    static const int who[3][2] = {{0, 1}, {2, 3}, {4, 5}};
    uint64_t id[6];
    for (int p = 0; p < 3; p++)
        for (int k = 0; k < 2; k++) {
            const int i = who[p][k];
            CHECK(s.s[i] == (i < 3 ? 0 : 1), "particle %d is of species %d", i, s.s[i]);
            s.x[i] = 0.01 + 0.02 * p + (k ? 1 : -1) * (0.5 * d + 1e-6);
            s.y[i] = s.z[i] = 0.01;
            s.vx[i] = (k ? -0.5 : 0.5) * v;
            s.vy[i] = s.vz[i] = 0;
            id[i] = s.id[i];
        }
    s.mods++;
    int steps[3] = {0, 0, 0};
    for (int k = 0; k < 3000; k++) {
        CHECK(mote_sep_run(&s, s.dt, &err) == MOTE_OK, "run: %s", err.msg);
        for (int p = 0; p < 3; p++) {
            size_t at[2] = {0, 0};
            for (size_t i = 0; i < s.n; i++)
                for (int q = 0; q < 2; q++)
                    if (s.id[i] == id[who[p][q]])
                        at[q] = i;
            steps[p] += fabs(s.x[at[1]] - s.x[at[0]]) < d;
        }
    }
    for (int p = 0; p < 3; p++) {
        const int a = p == 2, b = p > 0;
        const double Y = 1 / ((1 - nu * nu) / E[a] + (1 - nu * nu) / E[b]);
        const double m = 2500 * SEP_TEST_PI / 6 * d * d * d, tc =
            2.868 * pow(0.25 * m * m / (0.25 * d * Y * Y * v), 0.2);
        CHECK(fabs(steps[p] * s.dt - tc) <= 2 * s.dt, "pair %d: contact for %d steps of %.4g s "
              "(%.5g s) against t_c %.5g s", p, steps[p], s.dt, steps[p] * s.dt, tc);
        printf("  E %g and %g MPa: %d steps (%.5g s), t_c %.5g s\n", E[a] / 1e6, E[b] / 1e6,
               steps[p], steps[p] * s.dt, tc);
    }
    mote_sep_free(&s);
}

/* contact hertz: the same bits on 1, 2 and 3 threads, with every step completed, and after a
 * save and load half way (the springs of the pairs by id, the rotation and the wall springs in
 * the state file), with the law on 2 and 4 lanes as on the widest the processor runs, with a
 * plate and without (the box's walls then by lanes too); the run had sliding contacts, spin,
 * rebuilds, reorders and exits. */
static void test_hertz_threads(void)
{
    printf("contact hertz: the same bits on 1, 2, 3 threads, completed steps, save and load, "
           "2 and 4 lanes\n");
    static const struct {
        int dim;
        size_t n;
        int steps;
    } cases[] = {{3, 4000, 160}, {2, 2000, 300}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        /* with the plate; without (the box's walls by lanes): each set the same bits */
        enum { WAYS = 12, SET2 = 7 };
        static const int how[WAYS][2] = {{1, 4}, {2, 4}, {3, 4}, {1, 6}, {2, 12}, {1, 4 | 16},
                                         {3, 4 | 32}, {1, 68}, {2, 68}, {3, 68 | 32},
                                         {1, 68 | 16 | 8}, {2, 68 | 2}};
        char path[WAYS][64];
        mote_sep_system s[WAYS];
        for (int k = 0; k < WAYS; k++) {
            snprintf(path[k], sizeof path[0], "/tmp/mote_sep_hertz_%d_%d.state", (int)c, k);
            threads_case(&s[k], cases[c].dim, cases[c].n, cases[c].steps, how[k][0], 0, how[k][1],
                         path[k]);
        }
        size_t lane_walls = 0;
        for (size_t i = 0; i < s[SET2].n; i++)
            lane_walls += s[SET2].wflag[i] == 1;
        CHECK(lane_walls > 0, "case %zu: particles at the walls by lanes (%zu)", c, lane_walls);
        double spin = 0;
        for (size_t i = 0; i < 3 * s[0].n; i++)
            spin = fmax(spin, fabs(s[0].w[i]));
        size_t springs = 0;
        for (size_t e = 0; s[0].hist_ok && e < 3 * (size_t)s[0].nb_start[s[0].nb_n]; e++)
            springs += s[0].hist[e] != 0;
        CHECK(s[0].list_builds > 1 && s[0].last_sort > 0 && s[0].cnt[0].fines > 0 &&
              s[0].contacts_pp > 0 && spin > 1 && springs > 0,
              "case %zu exercises rebuilds (%llu), a reorder, exits, contacts (%llu), spin (%g "
              "rad/s), springs (%zu)", c, (unsigned long long)s[0].list_builds,
              (unsigned long long)s[0].contacts_pp, spin, springs);
        for (int k = 1; k < WAYS; k++)
            CHECK(test_same_file(path[k < SET2 ? 0 : SET2], path[k]), "case %zu (%dD): the state "
                  "of way %d equals the one on 1 thread", c, cases[c].dim, k);
        CHECK(!test_same_file(path[0], path[SET2]), "case %zu: the plate makes a difference", c);
        printf("  %dD N %zu: %llu list builds, %llu contacts, max spin %.3g rad/s\n",
               cases[c].dim, s[0].n, (unsigned long long)s[0].list_builds,
               (unsigned long long)s[0].contacts_pp, spin);
        for (int k = 0; k < WAYS; k++) {
            mote_sep_free(&s[k]);
            if (!getenv("KEEP")) remove(path[k]);
        }
    }
}

/* The passes over the particles on 1, 2 and 3 threads give the same bits: the states written
 * after a run with contacts, plates, exits, the feed, list rebuilds and reorders, the gas
 * coupling (deposited in more than one block in 3D) and the profiles; in 2D also with the
 * dispersion (which runs its drift on one thread). */
static void test_threads(void)
{
    printf("threads: the same bits on 1, 2 and 3 threads\n");
    static const struct {
        int dim;
        size_t n;
        int steps, disperse;
    } cases[] = {{3, 9000, 90, 0}, {2, 3000, 200, 0}, {2, 1000, 60, 1}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        char path[3][64];
        mote_sep_system s[3];
        for (int nt = 1; nt <= 3; nt++) {
            snprintf(path[nt - 1], sizeof path[0], "/tmp/mote_sep_threads_%d_%d.state", (int)c, nt);
            threads_case(&s[nt - 1], cases[c].dim, cases[c].n, cases[c].steps, nt,
                         cases[c].disperse, 0, path[nt - 1]);
        }
        CHECK(s[0].list_builds > 1 && s[0].last_sort > 0 && s[0].cnt[0].fines > 0 && s[0].contacts_pp > 0,
              "case %zu exercises rebuilds (%llu), a reorder (step %llu), exits and contacts (%llu)",
              c, (unsigned long long)s[0].list_builds, (unsigned long long)s[0].last_sort,
              (unsigned long long)s[0].contacts_pp);
        for (int k = 1; k < 3; k++)
            CHECK(test_same_file(path[0], path[k]), "case %zu (%dD, N %zu): the state on %d threads "
                  "equals the one on 1", c, cases[c].dim, cases[c].n, k + 1);
        printf("  %dD N %zu -> %zu after %d steps: %llu list builds, %llu contacts at the end\n",
               cases[c].dim, cases[c].n, s[0].n, cases[c].steps,
               (unsigned long long)s[0].list_builds, (unsigned long long)s[0].contacts_pp);
        for (int k = 0; k < 3; k++) {
            mote_sep_free(&s[k]);
            remove(path[k]);
        }
    }
}

/* The rows skipped by their gap at the build (no contact possible) change nothing: the same
 * runs as the thread test, and a column settling onto its floor in vacuum (many contacts, the
 * displacements' box growing from a common fall), with every row searched and with the skip,
 * on 1 and 2 threads, give the same state files; the skip happened in each. */
#define SEP_EBLK_TEST 64 /* (SEP_EBLK of src/separator/sep.h) */
static void test_gap_skip(void)
{
    printf("rows skipped by their gap: the same bits as every row searched\n");
    for (int c = 0; c < 4; c++) { /* (case 3: case 2 never sorted, its rows' pairs far apart in
                                   * the arrays: the blocks' reach over a wide window) */
        char path[3][64];
        mote_sep_system s[3];
        for (int k = 0; k < 3; k++) {
            snprintf(path[k], sizeof path[0], "/tmp/mote_sep_gap_%d_%d.state", c, k);
            const int nt = k == 2 ? 2 : 1, noskip = k == 0;
            if (c < 2) {
                threads_case(&s[k], c == 0 ? 3 : 2, c == 0 ? 6000 : 3000, 90, nt, 0, noskip,
                             path[k]);
                continue;
            }
            vacuum_box(&s[k], 3, 0.02, 0.03, 0.02, 2500,
                       (mote_sep_dist){.type = MOTE_SEP_MONO, .a = 1e-3});
            s[k].v_imp = 3;
            s[k].g = 9.81;
            fill(&s[k], 3000);
            for (size_t i = 0; i < s[k].n; i++) { /* a common fall of 2 m/s, a little spread */
                s[k].vx[i] = 0.05 * sin((double)i);
                s[k].vy[i] = 0.05 * cos(1.3 * (double)i);
                s[k].vz[i] = -2 + 0.05 * sin(0.7 * (double)i);
            }
            s[k].mods++; /* (velocities set by hand) */
            s[k].threads = nt;
            s[k].threads_min_n = 1;
            s[k].no_gap_skip = noskip;
            if (c == 3)
                s[k].nsort = 0;
            mote_err err = {0};
            CHECK(mote_sep_run(&s[k], 1500 * s[k].dt, &err) == MOTE_OK, "run: %s", err.msg);
            CHECK(mote_sep_save(&s[k], 1, path[k], &err) == MOTE_OK, "save: %s", err.msg);
        }
        CHECK(s[0].gap_skips == 0 && s[1].gap_skips > 0 && s[1].gap_skips == s[2].gap_skips,
              "case %d: rows skipped %llu, %llu, %llu", c, (unsigned long long)s[0].gap_skips,
              (unsigned long long)s[1].gap_skips, (unsigned long long)s[2].gap_skips);
        CHECK(s[1].contacts_pp > 0 || c < 2, "case %d: contacts at the end (%llu)", c,
              (unsigned long long)s[1].contacts_pp);
        CHECK(c < 3 || 2 * ((s[1].nb_w + SEP_EBLK_TEST - 1) / SEP_EBLK_TEST) + 1 > 32,
              "case 3: the rows' pairs far apart in the arrays (nb_w %zu)", s[1].nb_w);
        for (int k = 1; k < 3; k++)
            CHECK(test_same_file(path[0], path[k]), "case %d: the state with the skip (%d threads) "
                  "equals the one with every row searched", c, k);
        printf("  case %d: N %zu, %llu list builds, %.1f%% of the rows skipped, %llu contacts\n", c,
               s[1].n, (unsigned long long)s[1].list_builds,
               100.0 * (double)s[1].gap_skips / ((double)s[1].n * (double)s[1].steps),
               (unsigned long long)s[1].contacts_pp);
        for (int k = 0; k < 3; k++) {
            mote_sep_free(&s[k]);
            remove(path[k]);
        }
    }
}

/* A hook that wants to see every 7th step: it must see it complete (no kick pending). */
typedef struct {
    int calls, wanted, pending;
} hook_log;

static int log_hook(void *ctx, mote_sep_system *s, mote_err *err)
{
    (void)err;
    hook_log *l = ctx;
    l->calls++;
    l->wanted += s->steps % 7 == 0;
    l->pending += s->kick_h != 0;
    return 0;
}

static int every_7th(void *ctx, const mote_sep_system *s)
{
    (void)ctx;
    return s->steps % 7 == 0;
}

/* A run whose loop sees the steps every_7th wants (as the core's loop does): the pieces of
 * mote_sep_run, the hook after each step seen. */
static int run_with_hook(mote_sep_system *s, double T, hook_log *log, mote_err *err)
{
    int rc = mote_sep_prepare(s, err);
    const double t_end = s->t + T;
    while (!rc && s->t < t_end) {
        const double t0 = s->t;
        rc = mote_sep_advance(s, t_end, every_7th, log, err);
        if (rc || s->t == t0)
            break;
        if (!(s->kick_h > 0)) /* (a step seen; the last one may not be) */
            rc = log_hook(log, s, err);
    }
    return mote_sep_run_end(s, rc, err);
}

/* A step's second half kick left for the next drift (steps the hook does not see) gives the
 * bits of every step completed: the thread test's runs (contacts, plates, exits, the feed, the
 * gas coupling, the profiles' samples) on 1 and 3 threads, with every step completed and with
 * the kicks left pending; and a run whose hook wants every 7th step (it sees each of them
 * complete, and fewer than all) against the plain run. */
static void test_pending(void)
{
    printf("second half kicks left for the next drift: the same bits as every step completed\n");
    for (int c = 0; c < 2; c++) {
        char path[4][64];
        mote_sep_system s[4];
        for (int k = 0; k < 4; k++) {
            snprintf(path[k], sizeof path[0], "/tmp/mote_sep_pend_%d_%d.state", c, k);
            const int nt = k < 2 ? 1 : 3, nofuse = k % 2 == 0;
            threads_case(&s[k], c == 0 ? 3 : 2, c == 0 ? 6000 : 3000, 90, nt, 0, nofuse ? 2 : 0,
                         path[k]);
        }
        CHECK(s[0].contacts_pp > 0 && s[0].cnt[0].fines > 0, "case %d has contacts and exits", c);
        for (int k = 1; k < 4; k++)
            CHECK(test_same_file(path[0], path[k]), "case %d: run %d (%d threads, %s) equals every step "
                  "completed on 1 thread", c, k, k < 2 ? 1 : 3,
                  k % 2 ? "kicks pending" : "every step completed");
        for (int k = 0; k < 4; k++) {
            mote_sep_free(&s[k]);
            remove(path[k]);
        }
    }
    /* the hook */
    char path[2][64];
    mote_sep_system s[2];
    hook_log log = {0, 0, 0};
    for (int k = 0; k < 2; k++) {
        snprintf(path[k], sizeof path[0], "/tmp/mote_sep_pend_hook_%d.state", k);
        vacuum_box(&s[k], 3, 0.02, 0.03, 0.02, 2500,
                   (mote_sep_dist){.type = MOTE_SEP_MONO, .a = 1e-3});
        s[k].v_imp = 3;
        s[k].g = 9.81;
        fill(&s[k], 2000);
        for (size_t i = 0; i < s[k].n; i++) { /* a fall of 2 m/s onto the floor, spread */
            s[k].vx[i] = 0.3 * sin((double)i);
            s[k].vy[i] = 0.3 * cos(1.3 * (double)i);
            s[k].vz[i] = -2 + 0.3 * sin(0.7 * (double)i);
        }
        s[k].mods++; /* (velocities set by hand) */
        mote_err err = {0};
        if (k == 0)
            CHECK(mote_sep_run(&s[k], 300 * s[k].dt, &err) == MOTE_OK, "run: %s", err.msg);
        else
            CHECK(run_with_hook(&s[k], 300 * s[k].dt, &log, &err) == MOTE_OK,
                  "run with the hook: %s", err.msg);
        CHECK(s[k].kick_h == 0, "run %d ends complete", k);
        CHECK(mote_sep_save(&s[k], 1, path[k], &err) == MOTE_OK, "save: %s", err.msg);
    }
    /* (it also sees the steps that end complete anyway: the profiles' samples) */
    CHECK(log.wanted == 300 / 7 && log.calls < 300 && log.pending == 0,
          "the hook saw %d of the %d steps it wanted (every 7th of 300), %d in all, %d with a "
          "kick pending", log.wanted, 300 / 7, log.calls, log.pending);
    CHECK(s[0].contacts_pp > 0, "the box has contacts (%llu)", (unsigned long long)s[0].contacts_pp);
    CHECK(test_same_file(path[0], path[1]), "the run with the hook equals the plain run");
    for (int k = 0; k < 2; k++) {
        mote_sep_free(&s[k]);
        remove(path[k]);
    }
}

/* The drift's lean kinds (DEM with the pair list, no plates, no gas profile, no dispersion) find
 * the exits as exit_code does: in vacuum and in gas, 3D and 2D, two particles sent across the
 * open top, one across the open bottom and one (by more than its radius) across a side wall in
 * one step leave as two fines, one coarse and one lost, and nothing else leaves. */
static void test_lean_exits(void)
{
    printf("the lean drifts' exits\n");
    for (int c = 0; c < 4; c++) {
        const int dim = c < 2 ? 3 : 2, gas = c % 2;
        mote_sep_system s;
        vacuum_box(&s, dim, 0.02, 0.03, 0.02, 2500,
                   (mote_sep_dist){.type = MOTE_SEP_MONO, .a = 1e-3});
        s.open_top = s.open_bottom = 1;
        s.v_imp = 3;
        if (gas) {
            s.rho_g = 1.2;
            s.mu_g = 1.8e-5;
        }
        fill(&s, dim == 3 ? 2000 : 300);
        mote_err err = {0};
        CHECK(mote_sep_run(&s, 3 * s.dt, &err) == MOTE_OK, "run: %s", err.msg);
        const uint64_t f0 = s.cnt[0].fines, c0 = s.cnt[0].coarse, l0 = s.cnt[0].lost;
        const double r = 0.5e-3, step = 5 * s.dt; /* (how far 5 m/s goes in a step) */
        /* (positions moved by hand but not reordered: the list still checks, the kind is lean) */
        s.z[1] = s.H - 0.5 * step, s.vz[1] = 5;
        s.z[4] = s.H - 0.5 * step, s.vz[4] = 5;
        s.z[2] = 0.5 * step, s.vz[2] = -5;
        s.x[3] = -r + 0.5 * step, s.vx[3] = -5;
        CHECK(mote_sep_run(&s, s.dt, &err) == MOTE_OK, "run: %s", err.msg);
        CHECK(s.cnt[0].fines == f0 + 2 && s.cnt[0].coarse == c0 + 1 && s.cnt[0].lost == l0 + 1,
              "case %d (%dD, %s): fines +%llu, coarse +%llu, lost +%llu (2, 1, 1)", c, dim,
              gas ? "gas" : "vacuum", (unsigned long long)(s.cnt[0].fines - f0),
              (unsigned long long)(s.cnt[0].coarse - c0), (unsigned long long)(s.cnt[0].lost - l0));
        CHECK(mote_sep_check_balance(&s) == 0, "case %d: the balance holds", c);
        mote_sep_free(&s);
    }
}

int main(int argc, char **argv)
{
    static const struct {
        const char *name;
        void (*fn)(void);
    } tests[] = {{"pairs", test_pairs},           {"momentum", test_momentum},
                 {"elastic", test_elastic},       {"restitution", test_restitution},
                 {"many_body", test_many_body},   {"backlog", test_backlog},
                 {"grids", test_grids},           {"pair", test_pair_restitution},
                 {"tall", test_tall},             {"threads", test_threads},
                 {"first_sort", test_first_sort}, {"gap_skip", test_gap_skip},
                 {"pending", test_pending},       {"lean_exits", test_lean_exits},
                 {"hertz_threads", test_hertz_threads}, {"hertz_pairs", test_hertz_pairs},
                 {"hertz_walls", test_hertz_walls}, {"hertz_impacts", test_hertz_impacts},
                 {"hertz_momentum", test_hertz_momentum},
                 {"hertz_cohesion", test_hertz_cohesion}};
    for (size_t k = 0; k < sizeof tests / sizeof tests[0]; k++)
        if (argc < 2 || !strcmp(argv[1], tests[k].name))
            tests[k].fn();
    return test_summary();
}
