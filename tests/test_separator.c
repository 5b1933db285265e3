/* test_separator.c: the separator model against specs/separator.md section 4: the reference
 * terminal velocities and cut sizes, V1 (terminal velocity) and V1b (the transient against an
 * RK4 solution), V2 (the dilute cut size), V5 (the mass balance), V6 (size sampling), V8 (gas
 * continuity). */
#include "mote/separator.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "test.h"

static const double RHO_G = 1.204, MU_G = 1.81e-5, G = 9.81;

/* Spec 4, the reference values (rho_p = 2500, buoyancy included), to their printed digits. */
static void test_reference(void)
{
    printf("reference terminal velocities and cut sizes\n");
    const double d[4] = {50e-6, 200e-6, 1e-3, 2e-3};
    const double Re[4] = {0.5679, 18.83, 453.7, 1478}, vt[4] = {0.17074, 1.41508, 6.82116, 11.1082};
    for (int k = 0; k < 4; k++) {
        double re;
        const double v = mote_sep_terminal_velocity(d[k], 2500, RHO_G, MU_G, G, &re);
        printf("  d %g m: Re_t %.5g, v_t %.6g m/s\n", d[k], re, v);
        CHECK(fabs(v / vt[k] - 1) < 5e-5 && fabs(re / Re[k] - 1) < 1e-3, "d %g: v_t %.6g Re %.5g",
              d[k], v, re);
    }
    const double U[2] = {1, 2}, ds[2] = {151.84e-6, 270.87e-6};
    for (int k = 0; k < 2; k++) {
        const double c = mote_sep_cut_size(U[k], 2500, RHO_G, MU_G, G);
        printf("  U0 %g m/s: d* %.5g um\n", U[k], c * 1e6);
        CHECK(fabs(c / ds[k] - 1) < 5e-5, "cut size at U0 %g: %.6g", U[k], c);
    }
}

/* The drag factor f(Re) = 1 + 0.15 Re^0.687 (Re <= 1000), 0.44 Re / 24 above (spec 2.3):
 * mote evaluates the power through exp and log; within 2e-15 relative of pow()'s value on
 * 1e-6 <= Re <= 1000, exact at 0 and above 1000. */
static void test_drag_factor(void)
{
    printf("drag factor against pow()\n");
    double worst = 0;
    for (int k = 0; k <= 90000; k++) {
        const double Re = 1e-6 * pow(10, k / 10000.0);
        const double ref = Re <= 1000 ? 1 + 0.15 * pow(Re, 0.687) : 0.44 * Re / 24;
        worst = fmax(worst, fabs(mote_sep_drag_f(Re) / ref - 1));
    }
    printf("  largest relative difference %.3g\n", worst);
    CHECK(worst <= 2e-15, "f(Re) differs from pow()'s by %.3g", worst);
    CHECK(mote_sep_drag_f(0) == 1 && mote_sep_drag_f(2000) == 0.44 * 2000 / 24,
          "f(0) = %.17g, f(2000) = %.17g", mote_sep_drag_f(0), mote_sep_drag_f(2000));
}

/* A system with one species of mono size d in still gas, one particle from rest high up. */
static void one_particle(mote_sep_system *s, double d, double dt)
{
    mote_err err = {0};
    mote_sep_init(s);
    s->W = 0.1;
    s->H = 1000;
    s->U0 = 0;
    s->coupling = 0;
    s->nsp = 1;
    snprintf(s->sp[0].name, sizeof s->sp[0].name, "p");
    s->sp[0].rho = 2500;
    s->sp[0].w = 1;
    s->sp[0].dist.type = MOTE_SEP_MONO;
    s->sp[0].dist.a = d;
    s->sp[0].have_dist = 1;
    s->zf = 900;
    s->hf = 1e-3;
    s->dt_user = dt;
    s->dem = 0;
    CHECK(mote_sep_prepare(s, &err) == MOTE_OK, "prepare: %s", err.msg);
    CHECK(mote_sep_insert(s, 0, 1, 0, &err) == MOTE_OK, "insert: %s", err.msg);
}

/* m dv/dt = -m g' + 3 pi mu d f(Re) (u - v), by RK4 with steps h, from rest, to time T. */
static double rk4_speed(double d, double T, double h)
{
    const double gp = G * (1 - RHO_G / 2500);
    double v = 0, t = 0;
#define ACC(w) (-gp + 18 * MU_G * mote_sep_drag_f(RHO_G * fabs(w) * d / MU_G) * (-(w)) / (2500 * d * d))
    while (t < T - 1e-15) {
        const double hh = fmin(h, T - t);
        const double k1 = ACC(v), k2 = ACC(v + 0.5 * hh * k1), k3 = ACC(v + 0.5 * hh * k2),
                     k4 = ACC(v + hh * k3);
        v += hh / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
        t += hh;
    }
#undef ACC
    return v;
}

/* V1: after 20 v_t/g' from rest the speed is v_t within 0.5%; V1b: v(t) at v_t/g' and
 * 3 v_t/g' within 0.5% of RK4 with steps of tau/1000; dt <= tau/50 at the terminal state. */
static void test_terminal(void)
{
    printf("V1, V1b: terminal velocity and transient\n");
    const double d[4] = {50e-6, 200e-6, 1e-3, 2e-3};
    const double gp = G * (1 - RHO_G / 2500);
    for (int k = 0; k < 4; k++) {
        const double vt = mote_sep_terminal_velocity(d[k], 2500, RHO_G, MU_G, G, NULL);
        const double tau = vt / gp; /* the relaxation time at the terminal state */
        mote_sep_system s;
        one_particle(&s, d[k], tau / 50);
        mote_err err = {0};
        double v1 = 0, v3 = 0;
        const int ok = mote_sep_run(&s, tau, &err) == MOTE_OK && (v1 = -s.vz[0], 1) &&
                       mote_sep_run(&s, 2 * tau, &err) == MOTE_OK && (v3 = -s.vz[0], 1) &&
                       mote_sep_run(&s, 17 * tau, &err) == MOTE_OK;
        CHECK(ok && s.n == 1, "run: %s", err.msg);
        const double v20 = s.n ? -s.vz[0] : 0;
        const double r1 = -rk4_speed(d[k], tau, tau / 1000), r3 = -rk4_speed(d[k], 3 * tau, tau / 1000);
        printf("  d %g m: v(20 tau) / v_t - 1 = %.2e; v(tau) %.6g against RK4 %.6g; v(3 tau) "
               "%.6g against %.6g\n", d[k], v20 / vt - 1, v1, r1, v3, r3);
        CHECK(fabs(v20 / vt - 1) <= 0.005, "V1 d %g: %.6g against %.6g", d[k], v20, vt);
        CHECK(fabs(v1 / r1 - 1) <= 0.005 && fabs(v3 / r3 - 1) <= 0.005, "V1b d %g", d[k]);
        mote_sep_free(&s);
    }
}

/* V2: the dilute cut size. 2D, W 0.05 m, H 1 m, U0 1 m/s, rho_p 2500, loguniform 75-300 um
 * (number basis), 4000 particles fed at 0.5 m at rest, collisions off, coupling off, dt 1 ms,
 * 30 s, 40 classes per decade: d50 within 2% of 151.84 um, kappa within one class-width ratio
 * of 1. Also V5: the balance holds, nothing lost. */
static void test_dilute_cut(void)
{
    printf("V2, V5: the dilute cut size, the balance\n");
    mote_err err = {0};
    mote_sep_system s;
    mote_sep_init(&s);
    s.W = 0.05;
    s.H = 1;
    s.U0 = 1;
    s.coupling = 0;
    s.nsp = 1;
    snprintf(s.sp[0].name, sizeof s.sp[0].name, "quartz");
    s.sp[0].rho = 2500;
    s.sp[0].w = 1;
    s.sp[0].dist = (mote_sep_dist){.type = MOTE_SEP_LOGUNIFORM, .lo = 75e-6, .hi = 300e-6,
                                   .number_basis = 1};
    CHECK(mote_sep_dist_build(&s.sp[0].dist, &err) == MOTE_OK, "dist: %s", err.msg);
    s.sp[0].have_dist = 1;
    s.zf = 0.5;
    s.dt_user = 1e-3;
    s.dem = 0;
    /* 40 classes per decade from 75 um */
    s.nclass = (int)ceil(40 * log10(300.0 / 75));
    s.class_edge = malloc((size_t)(s.nclass + 1) * sizeof *s.class_edge);
    for (int k = 0; k <= s.nclass; k++)
        s.class_edge[k] = 75e-6 * pow(10, k / 40.0);
    int ok = mote_sep_prepare(&s, &err) == MOTE_OK && mote_sep_insert(&s, 0, 4000, 0, &err) == MOTE_OK &&
             mote_sep_run(&s, 30, &err) == MOTE_OK;
    CHECK(ok, "run: %s", err.msg);
    double *T = malloc((size_t)s.nclass * sizeof *T);
    mote_sep_cut cut;
    mote_sep_tromp(&s, T, &cut);
    printf("  d50 %.5g um (151.84), kappa %.4f (>= %.4f), %zu still in the channel, %llu lost\n",
           cut.d50 * 1e6, cut.kappa, pow(10, -1 / 40.0), s.n, (unsigned long long)s.cnt[0].lost);
    CHECK(fabs(cut.d50 / 151.84e-6 - 1) <= 0.02, "V2 d50 %.5g", cut.d50);
    CHECK(cut.kappa >= pow(10, -1 / 40.0) && cut.kappa <= 1, "V2 kappa %.4f", cut.kappa);
    CHECK(mote_sep_check_balance(&s) == 0 && s.cnt[0].lost == 0 && s.cnt[0].fed == 4000,
          "V5: the balance");
    free(T);
    mote_sep_free(&s);
}

/* V6: 1e6 draws of lognormal d50 100 um, sigma_g 1.5, mass basis, wide truncation: the mass
 * median 100 um and the number median 61.07 um (Hatch-Choate), each within 0.5%. */
static int cmp_d(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void test_sampling(void)
{
    printf("V6: size sampling\n");
    mote_err err = {0};
    mote_sep_dist ds = {.type = MOTE_SEP_LOGNORMAL, .a = 100e-6, .b = 1.5, .lo = 5e-6, .hi = 2e-3};
    CHECK(mote_sep_dist_build(&ds, &err) == MOTE_OK, "dist: %s", err.msg);
    const size_t n = 1000000;
    double *d = malloc(n * sizeof *d);
    mote_rng rng;
    mote_rng_seed(&rng, 11);
    double mtot = 0;
    for (size_t i = 0; i < n; i++) {
        d[i] = mote_sep_dist_sample(&ds, mote_rng_uniform(&rng));
        mtot += d[i] * d[i] * d[i];
    }
    qsort(d, n, sizeof *d, cmp_d);
    const double number_median = 0.5 * (d[n / 2 - 1] + d[n / 2]);
    double acc = 0, mass_median = 0;
    for (size_t i = 0; i < n; i++) {
        acc += d[i] * d[i] * d[i];
        if (acc >= 0.5 * mtot) {
            mass_median = d[i];
            break;
        }
    }
    const double hc = 100e-6 * exp(-3 * log(1.5) * log(1.5));
    printf("  mass median %.5g um (100), number median %.5g um (%.5g)\n", mass_median * 1e6,
           number_median * 1e6, hc * 1e6);
    CHECK(fabs(mass_median / 100e-6 - 1) <= 0.005, "V6 mass median %.5g", mass_median);
    CHECK(fabs(number_median / hc - 1) <= 0.005, "V6 number median %.5g", number_median);
    /* a table (a sieve analysis): rows d F, piecewise linear in ln d; three rows that make a
     * mass-basis ln d uniform law from 100 to 400 um: the mass median is 200 um */
    mote_sep_dist_free(&ds);
    ds = (mote_sep_dist){.type = MOTE_SEP_TABLE};
    const double td[3] = {100e-6, 200e-6, 400e-6}, tF[3] = {0, 0.5, 1};
    CHECK(mote_sep_dist_table(&ds, 3, td, tF, &err) == MOTE_OK &&
          mote_sep_dist_build(&ds, &err) == MOTE_OK, "table: %s", err.msg);
    mtot = 0;
    for (size_t i = 0; i < n; i++) {
        d[i] = mote_sep_dist_sample(&ds, mote_rng_uniform(&rng));
        mtot += d[i] * d[i] * d[i];
    }
    qsort(d, n, sizeof *d, cmp_d);
    acc = 0;
    for (size_t i = 0; i < n; i++) {
        acc += d[i] * d[i] * d[i];
        if (acc >= 0.5 * mtot) {
            mass_median = d[i];
            break;
        }
    }
    printf("  table: mass median %.5g um (200), range %.4g ... %.4g um\n", mass_median * 1e6,
           d[0] * 1e6, d[n - 1] * 1e6);
    CHECK(fabs(mass_median / 200e-6 - 1) <= 0.005 && d[0] >= 100e-6 && d[n - 1] <= 400e-6,
          "table mass median %.5g", mass_median);
    const double bd[2] = {1e-4, 1e-4}, bF[2] = {0, 1};
    CHECK(mote_sep_dist_table(&ds, 2, bd, bF, &err) != MOTE_OK &&
          strstr(err.msg, "row 2: the diameters must be > 0 and increase"), "bad table: %s", err.msg);
    free(d);
    mote_sep_dist_free(&ds);
}

/* V8: a frozen set with known volumes: the deposited volume is the particles' volume (1e-12),
 * and u_g eps_g rho_g = G in every unclamped slice (1e-12). */
static void test_gas(void)
{
    printf("V8: gas continuity\n");
    mote_err err = {0};
    mote_sep_system s;
    mote_sep_init(&s);
    s.W = 0.02;
    s.H = 0.5;
    s.U0 = 1.5;
    s.nsp = 1;
    snprintf(s.sp[0].name, sizeof s.sp[0].name, "p");
    s.sp[0].rho = 2500;
    s.sp[0].w = 1;
    s.sp[0].dist = (mote_sep_dist){.type = MOTE_SEP_LOGUNIFORM, .lo = 0.5e-3, .hi = 1.5e-3};
    mote_sep_dist_build(&s.sp[0].dist, &err);
    s.sp[0].have_dist = 1;
    s.zf = 0.25;
    s.hf = 0.49;
    s.dem = 0;
    CHECK(mote_sep_prepare(&s, &err) == MOTE_OK && mote_sep_insert(&s, 0, 3000, 0, &err) == MOTE_OK,
          "setup: %s", err.msg);
    CHECK(mote_sep_gas_update(&s, 0, &err) == MOTE_OK, "gas update: %s", err.msg);
    double vol = 0, dep = 0;
    for (size_t i = 0; i < s.n; i++)
        vol += 3.14159265358979323846 * s.d[i] * s.d[i] * s.d[i] / 6;
    const double Ac = s.W * 1.5e-3;
    double worst = 0;
    int unclamped = 0;
    for (int k = 0; k < s.K; k++) {
        dep += s.eps_s[k] * Ac * s.dz;
        const double eg = 1 - s.eps_s[k];
        if (eg >= s.eps_gas_min) {
            unclamped++;
            worst = fmax(worst, fabs(s.u_g[k] * eg * s.rho_g / (s.rho_g * s.U0) - 1));
        }
    }
    printf("  deposited / particle volume - 1 = %.2e; %d unclamped slices of %d, worst flux "
           "error %.2e; %d clamped\n", dep / vol - 1, unclamped, s.K, worst, s.clamped);
    CHECK(fabs(dep / vol - 1) <= 1e-12, "V8 volume %.3e", dep / vol - 1);
    CHECK(unclamped > 0 && worst <= 1e-12, "V8 flux %.3e", worst);
    /* with a gas profile (density halving up the channel): u_g eps_g rho_g(z) = rho_g(0) U0 */
    const double gz[3] = {0, 0.2, 0.5}, gr[3] = {1.2, 0.9, 0.6}, gm[3] = {NAN, NAN, NAN};
    CHECK(mote_sep_set_gas_profile(&s, 3, gz, gr, gm, &err) == MOTE_OK &&
          mote_sep_prepare(&s, &err) == MOTE_OK, "profile: %s", err.msg);
    worst = 0;
    unclamped = 0;
    for (int k = 0; k < s.K; k++) {
        const double z = (k + 0.5) * s.dz;
        const double rho = z < 0.2 ? 1.2 - 0.3 * z / 0.2 : 0.9 - 0.3 * (z - 0.2) / 0.3;
        const double eg = 1 - s.eps_s[k];
        if (eg >= s.eps_gas_min) {
            unclamped++;
            worst = fmax(worst, fabs(s.u_g[k] * eg * rho / (1.2 * s.U0) - 1));
        }
    }
    printf("  with a gas profile: worst flux error %.2e over %d slices\n", worst, unclamped);
    CHECK(unclamped > 0 && worst <= 1e-12, "V8 flux with a profile %.3e", worst);
    /* the reference cut uses the gas at the feed height (z_f = 0.25: rho 0.85) */
    const double d0 = mote_sep_d0_star(&s, 0), want = mote_sep_cut_size(1.2 * 1.5 / 0.85, 2500,
                                                                          0.85, 1.81e-5, 9.81);
    printf("  d0* with the profile %.6g um (G / rho(z_f) = %.5g m/s)\n", d0 * 1e6, 1.2 * 1.5 / 0.85);
    CHECK(fabs(d0 / want - 1) < 1e-12, "d0* %.10g against %.10g", d0, want);
    mote_sep_free(&s);
}

/* V7: 3e4 free particles, gas at rest, no gravity, D given, h = dt/tau 0.1 and 10: the mean
 * square displacement of each component is that of an Ornstein-Uhlenbeck velocity started at
 * rest, 2Dt - D tau (3 - 4E + E^2) with E = exp(-t/tau) (2Dt for t >> tau), and the velocity
 * variance D/tau (1 - E^2), each within 3%: three standard errors of a variance from 3e4
 * Gaussian samples are 3 sqrt(2/3e4) = 2.4%. In 2D and 3D. The gas density is tiny so that
 * the drag stays Stokes (tau constant, as the exact update assumes). */
static void test_dispersion(void)
{
    printf("V7: dispersion\n");
    const double hs[2] = {0.1, 10};
    for (int dim = 2; dim <= 3; dim++)
        for (int q = 0; q < 2; q++) {
            mote_err err = {0};
            mote_sep_system s;
            mote_sep_init(&s);
            s.dim = dim;
            s.W = s.H = s.D = 10;
            s.U0 = 0;
            s.rho_g = 1e-6;
            s.g = 0;
            s.coupling = 0;
            s.dem = 0;
            s.nsp = 1;
            snprintf(s.sp[0].name, sizeof s.sp[0].name, "p");
            s.sp[0].rho = 2500;
            s.sp[0].w = 1;
            s.sp[0].dist = (mote_sep_dist){.type = MOTE_SEP_MONO, .a = 10e-6};
            s.sp[0].have_dist = 1;
            s.zf = 5;
            s.hf = 1;
            s.fx1 = 4.5;
            s.fx2 = 5.5;
            s.fy1 = 4.5;
            s.fy2 = 5.5;
            const double d = 10e-6, tau = 2500 * d * d / (18 * MU_G), D = 1e-4;
            s.D_t = D;
            s.dt_user = hs[q] * tau;
            s.K = 10;
            const size_t n = 30000;
            CHECK(mote_sep_prepare(&s, &err) == MOTE_OK && mote_sep_insert(&s, 0, n, 0, &err) == MOTE_OK,
                  "setup: %s", err.msg);
            double *x0 = malloc(3 * n * sizeof *x0);
            for (size_t i = 0; i < n; i++) {
                x0[3 * i] = s.x[i];
                x0[3 * i + 1] = s.y[i];
                x0[3 * i + 2] = s.z[i];
            }
            const double T = 50 * tau;
            CHECK(mote_sep_run(&s, T, &err) == MOTE_OK && s.n == n, "run: %s", err.msg);
            const double E = exp(-T / tau);
            const double msd_want = 2 * D * T - D * tau * (3 - 4 * E + E * E);
            const double var_want = D / tau * (1 - E * E);
            double worst_x = 0, worst_v = 0;
            for (int a = 0; a < 3; a++) {
                if (a == 1 && dim == 2)
                    continue;
                const double *p = a == 0 ? s.x : a == 1 ? s.y : s.z;
                const double *v = a == 0 ? s.vx : a == 1 ? s.vy : s.vz;
                double msd = 0, var = 0;
                for (size_t i = 0; i < n; i++) {
                    msd += (p[i] - x0[3 * i + a]) * (p[i] - x0[3 * i + a]);
                    var += v[i] * v[i];
                }
                msd /= n;
                var /= n;
                worst_x = fmax(worst_x, fabs(msd / msd_want - 1));
                worst_v = fmax(worst_v, fabs(var / var_want - 1));
            }
            printf("  %dD h %g: MSD worst component %.2f%% off, velocity variance %.2f%% off "
                   "(3%% allowed)\n", dim, hs[q], 100 * worst_x, 100 * worst_v);
            CHECK(worst_x <= 0.03 && worst_v <= 0.03, "V7 %dD h %g: %.4f %.4f", dim, hs[q],
                  worst_x, worst_v);
            free(x0);
            mote_sep_free(&s);
        }
}

/* The pace of the outputs made for a watcher (live_png, and the live view's frames): hz a
 * second while a picture is cheap, ten times its cost when it is not, so they take at most a
 * tenth of the run. */
static void test_live_pace(void)
{
    const double c[] = {0.001, 0.05, 0.05, NAN, -1, 0.03}; /* (-1: a clock that stepped back) */
    const double g0[] = {1.0 / 30, 1.0 / 30, 0.5, 1.0 / 30, 1.0 / 30, 1.0 / 30};
    const double want[] = {1.0 / 30, 0.5, 0.5, 1.0 / 30, 1.0 / 30, 0.3};
    for (int i = 0; i < 6; i++) {
        const double g = mote_pace_gap(g0[i], c[i]);
        CHECK(fabs(g - want[i]) <= 1e-15, "gap(%g, %g) = %.17g, expected %.17g", g0[i], c[i], g,
              want[i]);
        CHECK(!(c[i] > 0) || c[i] / g <= 0.1 + 1e-15, "cost %g takes %g of the run", c[i],
              c[i] / g);
    }
}

int main(void)
{
    test_live_pace();
    test_reference();
    test_drag_factor();
    test_terminal();
    test_dilute_cut();
    test_sampling();
    test_gas();
    test_dispersion();
    return test_summary();
}
