/* test_sep_mesh.c: the separator's walls from meshes (issue 56) against analytic results: a
 * sphere hitting a sheet of triangles rebounds as from the channel's own floor wherever it lands
 * (a face, an edge, a vertex where six triangles meet), and from a roof's ridge and a pyramid's
 * apex (each feature counted once); rests in a V groove on two faces with Hertz's overlap;
 * rolls down an incline at 5/7 g sin(theta) and slides at g (sin - mu cos), on a sheet of many
 * triangles as on two; is carried by a moving belt to 2/7 of its speed; rolls on a turntable on
 * a circle at 2/7 of the table's rate; and a hopper's pour gives the same bits on 1, 2 and 3
 * threads and across save and load. */
#include "mote/separator.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../src/separator/sep.h"
#include "test.h"

#define PI 3.14159265358979323846

/* ---- meshes made here ---- */

typedef struct {
    size_t nv, nt, vcap, tcap;
    double (*v)[3];
    uint32_t (*t)[3];
} soup;

static uint32_t vtx(soup *m, double x, double y, double z)
{
    if (m->nv == m->vcap) {
        m->vcap = m->vcap ? 2 * m->vcap : 64;
        m->v = realloc(m->v, m->vcap * sizeof *m->v);
    }
    m->v[m->nv][0] = x, m->v[m->nv][1] = y, m->v[m->nv][2] = z;
    return (uint32_t)m->nv++;
}

static void tri(soup *m, uint32_t a, uint32_t b, uint32_t c)
{
    if (m->nt == m->tcap) {
        m->tcap = m->tcap ? 2 * m->tcap : 64;
        m->t = realloc(m->t, m->tcap * sizeof *m->t);
    }
    m->t[m->nt][0] = a, m->t[m->nt][1] = b, m->t[m->nt++][2] = c;
}

/* A flat square sheet of side L centred at (cx, cy, cz), n x n squares of two triangles each,
 * tilted by theta about the y axis through its centre (positive: its +x end goes down). */
static void sheet(soup *m, double cx, double cy, double cz, double L, int n, double theta)
{
    const uint32_t base = (uint32_t)m->nv;
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            const double u = -0.5 * L + L * i / n, w = -0.5 * L + L * j / n;
            vtx(m, cx + u * cos(theta), cy + w, cz - u * sin(theta));
        }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            const uint32_t a = base + (uint32_t)(j * (n + 1) + i), b = a + 1,
                           c = a + (uint32_t)(n + 1), d = c + 1;
            tri(m, a, b, d);
            tri(m, a, d, c);
        }
}

/* Add the soup as a wall (the closed flags all 0: a sheet) and free it. */
static void add_wall(mote_sep_system *s, soup *m, const double vel[3], double omega,
                     const double axis[3], const double centre[3])
{
    mote_mesh mm = {.nv = m->nv, .nt = m->nt, .v = m->v, .t = m->t};
    mm.closed = calloc(m->nt, 1);
    mote_err err = {0};
    const double zero[3] = {0, 0, 0};
    CHECK(sep_mesh_add(s, &mm, "test", 0, vel ? vel : zero, axis ? axis : zero, omega,
                       centre ? centre : zero, &err) == MOTE_OK, "mesh: %s", err.msg);
    free(mm.closed);
    free(m->v);
    free(m->t);
    memset(m, 0, sizeof *m);
}

/* A closed box in vacuum (gravity g), one species of glass-like spheres of diameter d (E 5
 * MPa), contact hertz (hertz 1) or linear; no particles. */
static void box(mote_sep_system *s, double W, double D, double H, double g, double d, int hertz,
                double e, double mu)
{
    mote_sep_init(s);
    s->dim = 3;
    s->W = W, s->D = D, s->H = H;
    s->open_bottom = s->open_top = 0;
    s->U0 = 0, s->rho_g = 0, s->mu_g = 0, s->g = g;
    s->nsp = 1;
    snprintf(s->sp[0].name, sizeof s->sp[0].name, "p");
    s->sp[0].rho = 2500;
    s->sp[0].w = 1;
    s->sp[0].dist = (mote_sep_dist){.type = MOTE_SEP_MONO, .a = d};
    s->sp[0].have_dist = 1;
    s->sp[0].E = 5e6;
    s->sp[0].nu = 0.3;
    s->zf = 0.5 * H;
    s->hf = 0.5 * H;
    s->hertz = hertz;
    s->e_pp = e;
    s->mu_pp = mu;
    s->v_imp = 1;
    s->nc = 100;
}

/* One particle at p with velocity v (prepared first: the walls' grids). */
static void one(mote_sep_system *s, const double p[3], const double v[3])
{
    mote_err err = {0};
    CHECK(mote_sep_prepare(s, &err) == MOTE_OK, "prepare: %s", err.msg);
    const double d = s->sp[0].dist.a;
    const double row[11] = {d, 2500 * PI * d * d * d / 6, p[0], p[1], p[2], v[0], v[1], v[2],
                            0, 0, 0};
    CHECK(sep_append(s, 0, 1, row, &err) == MOTE_OK, "append: %s", err.msg);
    s->cnt[0].fed++; /* (in the balance: fed and in the channel) */
    s->cnt[0].m_fed += row[1];
    s->cnt[0].m_gen += row[1];
    if (s->hertz)
        CHECK(sep_rot_reserve(s, &err) == MOTE_OK, "rotation: %s", err.msg);
}

static void run(mote_sep_system *s, double T)
{
    mote_err err = {0};
    CHECK(mote_sep_run(s, T, &err) == MOTE_OK, "run: %s", err.msg);
}

/* ---- single impacts: every feature once ---- */

/* A sphere (d 2 mm) at (x, y) falling at 1 m/s (and sliding at vt along x) onto: kind 0 the
 * box's floor, 1 a horizontal sheet 5 mm up (8 x 8 squares of 2.5 mm, a vertex at the box's
 * centre), 2 a roof (two faces sloping 30 degrees down from a ridge along y at 5 mm), 3 a
 * pyramid's apex (four faces), 4 the sheet of 1 at 3 cm, hit from below (an open sheet's both
 * sides are walls; out mirrored); out: vz, vx, wy after it leaves. */
static void impact(int kind, int hertz, double x, double y, double vt, double out[3])
{
    mote_sep_system s;
    box(&s, 0.04, 0.04, 0.04, 0, 2e-3, hertz, 0.5, 0.3);
    soup m = {0};
    double z0 = 0;
    if (kind == 1 || kind == 4) {
        z0 = kind == 1 ? 0.005 : 0.03;
        sheet(&m, 0.02, 0.02, z0, 0.02, 8, 0);
    } else if (kind == 2) {
        z0 = 0.005;
        const double t = tan(PI / 6);
        const uint32_t a = vtx(&m, 0.02, 0.01, z0), b = vtx(&m, 0.02, 0.03, z0),
                       c = vtx(&m, 0.01, 0.01, z0 - 0.01 * t), d = vtx(&m, 0.01, 0.03, z0 - 0.01 * t),
                       e = vtx(&m, 0.03, 0.01, z0 - 0.01 * t), f = vtx(&m, 0.03, 0.03, z0 - 0.01 * t);
        tri(&m, a, b, d), tri(&m, a, d, c), tri(&m, a, e, f), tri(&m, a, f, b);
    } else if (kind == 3) {
        z0 = 0.005;
        const uint32_t a = vtx(&m, 0.02, 0.02, z0);
        uint32_t c[4];
        for (int k = 0; k < 4; k++)
            c[k] = vtx(&m, 0.02 + 0.01 * cos(PI / 2 * k), 0.02 + 0.01 * sin(PI / 2 * k), z0 - 0.006);
        for (int k = 0; k < 4; k++)
            tri(&m, a, c[k], c[(k + 1) % 4]);
    }
    if (kind)
        add_wall(&s, &m, NULL, 0, NULL, NULL);
    const double up = kind == 4 ? -1 : 1; /* (kind 4: from below, upwards) */
    one(&s, (double[3]){x, y, z0 + up * (1e-3 + 1e-6)}, (double[3]){vt, 0, -up});
    run(&s, 1e-6 + 4 * s.nc * s.dt);
    CHECK(up * (s.z[0] - z0) > 1e-3, "kind %d: the sphere left (z %.6g)", kind, s.z[0]);
    out[0] = up * s.vz[0], out[1] = s.vx[0], out[2] = s.hertz ? up * s.w[1] : 0;
    mote_sep_free(&s);
}

static void test_impacts(void)
{
    printf("mesh walls: single impacts on faces, edges and vertices rebound as from the floor\n");
    for (int hertz = 0; hertz < 2; hertz++)
        for (int slide = 0; slide < 1 + hertz; slide++) {
            const double vt = slide ? 0.3 : 0;
            double ref[3], o[3];
            impact(0, hertz, 0.02, 0.02, vt, ref);
            CHECK(fabs(ref[0] - 0.5) < 0.02, "floor: rebound %.6f", ref[0]);
            static const struct {
                int kind;
                double x, y;
                const char *what;
            } at[] = {{1, 0.02, 0.02, "a vertex of six triangles"},
                      {1, 0.02125, 0.02, "an edge's middle"},
                      {1, 0.02125, 0.02125, "a diagonal edge"},
                      {1, 0.0208, 0.0217, "a face"},
                      {4, 0.0208, 0.0217, "a face from below"},
                      {2, 0.02, 0.02, "a roof's ridge"},
                      {3, 0.02, 0.02, "a pyramid's apex"}};
            for (size_t k = 0; k < sizeof at / sizeof at[0]; k++) {
                if (slide && (at[k].kind == 2 || at[k].kind == 3))
                    continue; /* (sliding off a ridge is not the floor's case) */
                impact(at[k].kind, hertz, at[k].x, at[k].y, vt, o);
                CHECK(fabs(o[0] - ref[0]) <= 1e-9 && fabs(o[1] - ref[1]) <= 1e-9 &&
                          fabs(o[2] - ref[2]) <= 1e-9 * fmax(1, fabs(ref[2])),
                      "%s, %s%s: vz %.12f vx %.12f wy %.9g against the floor's %.12f %.12f %.9g",
                      at[k].what, hertz ? "hertz" : "linear", slide ? " sliding" : "", o[0],
                      o[1], o[2], ref[0], ref[1], ref[2]);
            }
            printf("  %s%s: rebound %.6f (vx %.4f, wy %.4f) on the floor, and on each feature "
                   "to 1e-9\n", hertz ? "hertz" : "linear", slide ? ", sliding at 0.3 m/s" : "",
                   ref[0], ref[1], ref[2]);
        }
}

/* ---- resting in a groove: two faces, Hertz's overlap ---- */

static void test_groove(void)
{
    printf("mesh walls: a sphere at rest in a 90 degree groove on two faces\n");
    mote_sep_system s;
    box(&s, 0.04, 0.04, 0.04, 9.81, 2e-3, 1, 0.5, 0);
    soup m = {0};
    /* the groove's line along y at (0.02, z 0.01), faces rising at 45 degrees, 4 x 4 each */
    for (int side = -1; side <= 1; side += 2) {
        const uint32_t b0 = (uint32_t)m.nv;
        for (int j = 0; j <= 4; j++)
            for (int i = 0; i <= 4; i++)
                vtx(&m, 0.02 + side * 0.002 * i, 0.01 + 0.005 * j, 0.01 + 0.002 * i);
        for (int j = 0; j < 4; j++)
            for (int i = 0; i < 4; i++) {
                const uint32_t a = b0 + (uint32_t)(j * 5 + i);
                tri(&m, a, a + 1, a + 6);
                tri(&m, a, a + 6, a + 5);
            }
    }
    add_wall(&s, &m, NULL, 0, NULL, NULL);
    const double r = 1e-3;
    one(&s, (double[3]){0.02, 0.02, 0.01 + r * sqrt(2.0) + 1e-6}, (double[3]){0, 0, 0});
    run(&s, 0.3);
    /* each face: N = m g / (2 cos 45) = 4/3 Y* sqrt(r) delta^3/2, Y* = E / (2 (1 - nu^2)) */
    const double mass = 2500 * PI * 8e-9 / 6, N = mass * 9.81 / sqrt(2.0);
    const double Ys = 5e6 / (2 * (1 - 0.09));
    const double delta = pow(N / (4.0 / 3.0 * Ys * sqrt(r)), 2.0 / 3.0);
    const double got = r - (s.z[0] - 0.01) / sqrt(2.0);
    CHECK(fabs(got / delta - 1) < 1e-8 && fabs(s.x[0] - 0.02) < 1e-12 && fabs(s.vz[0]) < 1e-9,
          "overlap %.9g against Hertz's %.9g; x %.15g", got, delta, s.x[0]);
    printf("  overlap on each face %.6e m against Hertz's %.6e (%.1e relative)\n", got, delta,
           fabs(got / delta - 1));
    mote_sep_free(&s);
}

/* ---- a mesh finer than the contact ---- */

/* A sphere (d 2 mm) dropped onto a sheet of 1 x 1 mm cut into n x n squares, at rest after
 * 0.05 s: its height. */
static double rest_height(int n)
{
    mote_sep_system s;
    box(&s, 0.04, 0.04, 0.04, 9.81, 2e-3, 1, 0.5, 0);
    soup m = {0};
    sheet(&m, 0.02, 0.02, 0.01, 1e-3, n, 0);
    add_wall(&s, &m, NULL, 0, NULL, NULL);
    one(&s, (double[3]){0.02 + 1.3e-6, 0.02 - 0.7e-6, 0.011 + 1e-7}, (double[3]){0, 0, 0});
    run(&s, 0.05);
    const double z = s.z[0];
    mote_sep_free(&s);
    return z;
}

/* On a sheet of 12 800 triangles of 12.5 um, about 80 of them lie within the sphere's reach
 * around its contact (of radius sqrt(2 r delta), 45 um): more than the candidates kept per wall
 * (32). The sphere rests where it rests on two triangles: the nearest are kept (a version that
 * kept the first 32 in the cell's order rested 7e-8 m off: checked). */
static void test_fine(void)
{
    printf("mesh walls: a sheet finer than the contact\n");
    const double z1 = rest_height(1), z100 = rest_height(80);
    CHECK(fabs(z100 - z1) <= 1e-12, "resting at z %.15g on 12 800 triangles, %.15g on 2", z100,
          z1);
    printf("  at rest %.9f m up on 12 800 triangles and on 2 (%.1e m apart)\n", z100,
           fabs(z100 - z1));
}

/* ---- an incline: rolling and sliding ---- */

static int every_step(void *ctx, const mote_sep_system *s)
{
    (void)ctx, (void)s;
    return 1;
}

/* The speed down an incline of 20 degrees (a sheet of n x n squares) at t1 and t2 after a
 * sphere is put on it at rest, and the time between (v[0], v[1], v[2]), with friction mu (the
 * rolling friction 0); *dev the spread of the contact's force along the slope over the steps
 * between, relative to it (the spring's force holds the rolling sphere: lost where it
 * crosses a triangle's edge, it would fall to zero there; the speeds would not show it, as the
 * sphere's angular momentum about the contact point does not depend on the friction). */
static void incline(int n, double mu, double v[3], double *dev)
{
    mote_sep_system s;
    box(&s, 0.2, 0.04, 0.1, 9.81, 2e-3, 1, 0.5, mu);
    const double th = 20 * PI / 180;
    soup m = {0};
    sheet(&m, 0.1, 0.02, 0.05, 0.16, n, th);
    add_wall(&s, &m, NULL, 0, NULL, NULL);
    const double r = 1e-3, u = -0.06; /* (up the slope from the centre) */
    const double p[3] = {0.1 + u * cos(th) + (r + 1e-7) * sin(th), 0.0201,
                         0.05 - u * sin(th) + (r + 1e-7) * cos(th)};
    one(&s, p, (double[3]){0, 0, 0});
    run(&s, 0.05);
    v[0] = s.vx[0] * cos(th) - s.vz[0] * sin(th);
    const double t1 = s.t;
    /* (step by step: the run's advance returns after each step the hook wants to see) */
    mote_err err = {0};
    const double t2 = s.t + 0.1;
    double lo = INFINITY, hi = -INFINITY;
    int rc = mote_sep_prepare(&s, &err);
    while (!rc && s.t < t2 - 0.5 * s.dt) {
        rc = mote_sep_advance(&s, t2, every_step, NULL, &err);
        const double f = s.fx[0] * cos(th) - s.fz[0] * sin(th);
        lo = fmin(lo, f), hi = fmax(hi, f);
    }
    CHECK(mote_sep_run_end(&s, rc, &err) == MOTE_OK, "run: %s", err.msg);
    *dev = (hi - lo) / fmax(fabs(hi), fabs(lo));
    v[1] = s.vx[0] * cos(th) - s.vz[0] * sin(th);
    v[2] = s.t - t1; /* (the time between) */
    mote_sep_free(&s);
}

static void test_incline(void)
{
    printf("mesh walls: down an incline of 20 degrees (over the triangles' edges)\n");
    const double th = 20 * PI / 180, g = 9.81;
    double v[3], v2[3], dev, dev2;
    /* rolling (mu 0.5 > 2/7 tan 20 = 0.104): a = 5/7 g sin */
    incline(40, 0.5, v, &dev);
    incline(1, 0.5, v2, &dev2);
    CHECK(dev < 1e-6 && dev2 < 1e-6, "the rolling sphere's friction force varies by %.3g (3200 "
          "triangles) and %.3g (2) of itself", dev, dev2);
    double a = (v[1] - v[0]) / v[2], want = 5.0 / 7.0 * g * sin(th);
    CHECK(fabs(a / want - 1) < 1e-9, "rolling: a %.6f against 5/7 g sin %.6f", a, want);
    CHECK(fabs(v2[1] / v[1] - 1) < 1e-9, "rolling on 2 triangles %.12f against on 3200 %.12f",
          v2[1], v[1]);
    printf("  rolling: a %.5f m/s^2 against 5/7 g sin(20) %.5f (%.1e); on 2 triangles as on "
           "3200 to %.1e; its friction force steady to %.1e across the triangles' edges\n", a,
           want, fabs(a / want - 1), fabs(v2[1] / v[1] - 1), dev);
    /* sliding (mu 0.05): a = g (sin - mu cos) */
    incline(40, 0.05, v, &dev);
    a = (v[1] - v[0]) / v[2], want = g * (sin(th) - 0.05 * cos(th));
    CHECK(fabs(a / want - 1) < 1e-9, "sliding: a %.6f against g (sin - mu cos) %.6f", a, want);
    printf("  sliding: a %.5f m/s^2 against g (sin - mu cos) %.5f (%.1e)\n", a, want,
           fabs(a / want - 1));
}

/* ---- moving walls ----
 * (the rigid-body results hold for the soft contact to rounding once the contact sticks: the
 * sphere's angular momentum about the contact point is kept, as its normal force passes
 * through the centre; measured to 1e-8, tested to 1e-6: a contact counted twice where a sheet's
 * triangles meet, as the first version did, was 1e-3 off) */

/* A belt: a horizontal sheet moving at V along x; a sphere put on it at rest slides until its
 * contact point moves with the belt, then rolls at 2/7 V (friction's impulse J gives v = J/m
 * and a contact-point speed of 7/2 of it). */
static void test_belt(void)
{
    printf("mesh walls: a moving belt carries a sphere to 2/7 of its speed\n");
    mote_sep_system s;
    box(&s, 0.1, 0.04, 0.04, 9.81, 2e-3, 1, 0.5, 0.3);
    soup m = {0};
    sheet(&m, 0.05, 0.02, 0.01, 0.08, 16, 0);
    const double V = 0.1;
    add_wall(&s, &m, (double[3]){V, 0, 0}, 0, NULL, NULL);
    one(&s, (double[3]){0.03, 0.02, 0.011 + 1e-7}, (double[3]){0, 0, 0});
    run(&s, 0.1);
    const double slip = s.vx[0] - 1e-3 * s.w[1] - V; /* (the contact point's speed on the belt) */
    CHECK(fabs(s.vx[0] / (2.0 / 7.0 * V) - 1) < 1e-6 && fabs(slip) < 1e-6 * V,
          "v %.9f against 2/7 V %.9f; slip %.3g", s.vx[0], 2.0 / 7.0 * V, slip);
    printf("  v %.6f m/s against 2/7 V = %.6f (%.1e); slip at the contact %.1e m/s\n", s.vx[0],
           2.0 / 7.0 * V, fabs(s.vx[0] / (2.0 / 7.0 * V) - 1), slip);
    mote_sep_free(&s);
}

/* A turntable: a horizontal sheet turning at W about the vertical through the box's centre; a
 * sphere rolling on it without slipping moves on a circle at 2/7 W (its velocity turns at that
 * rate: m dv/dt = F, I dw/dt = -r n x F and the rolling condition give dv/dt = 2/7 W x v). */
static void test_turntable(void)
{
    printf("mesh walls: a sphere rolling on a turntable circles at 2/7 of its rate\n");
    mote_sep_system s;
    box(&s, 0.2, 0.2, 0.04, 9.81, 2e-3, 1, 0.5, 0.5);
    soup m = {0};
    sheet(&m, 0.1, 0.1, 0.01, 0.16, 16, 0);
    const double W = 2;
    add_wall(&s, &m, NULL, W, (double[3]){0, 0, 1}, (double[3]){0.1, 0.1, 0.01});
    one(&s, (double[3]){0.12, 0.1, 0.011 + 1e-7}, (double[3]){0, 0, 0});
    run(&s, 0.2); /* (the slip ends) */
    const double a0 = atan2(s.vy[0], s.vx[0]), sp0 = hypot(s.vx[0], s.vy[0]);
    run(&s, 1.0);
    double turned = atan2(s.vy[0], s.vx[0]) - a0;
    turned += turned < 0 ? 2 * PI : 0;
    const double sp1 = hypot(s.vx[0], s.vy[0]), want = 2.0 / 7.0 * W;
    CHECK(fabs(turned / want - 1) < 1e-6 && fabs(sp1 / sp0 - 1) < 1e-6,
          "turned %.6f rad in 1 s against 2/7 W = %.6f; speed %.6g -> %.6g", turned, want, sp0,
          sp1);
    printf("  the velocity turned %.5f rad/s against 2/7 W = %.5f (%.1e); speed %.4f -> %.4f "
           "m/s\n", turned, want, fabs(turned / want - 1), sp0, sp1);
    mote_sep_free(&s);
}

/* ---- keeping new particles out ---- */

/* A closed cube of side 1 cm at (2, 2, 2) cm, solid, turned by 30 degrees about z through its
 * centre (12 triangles wound outward): a centre inside it (the winding number, 1), a sphere
 * touching a face, an edge or a vertex, are blocked; one clear of it is not; the same cube with
 * a triangle missing is refused as solid; a wall turning at omega is found where it is at t. */
static void test_blocks(void)
{
    printf("mesh walls: particles kept out of a solid wall\n");
    mote_sep_system s;
    box(&s, 0.04, 0.04, 0.04, 0, 1e-3, 1, 0.5, 0.3);
    soup m = {0};
    uint32_t v[8];
    for (int k = 0; k < 8; k++)
        v[k] = vtx(&m, 0.015 + 0.01 * (k & 1), 0.015 + 0.01 * (k >> 1 & 1),
                   0.015 + 0.01 * (k >> 2 & 1));
    static const int f[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int k = 0; k < 6; k++) {
        tri(&m, v[f[k][0]], v[f[k][1]], v[f[k][2]]);
        tri(&m, v[f[k][0]], v[f[k][2]], v[f[k][3]]);
    }
    mote_mesh open = {.nv = m.nv, .nt = m.nt - 1, .v = m.v, .t = m.t};
    open.closed = calloc(m.nt, 1);
    mote_err err = {0};
    const double zero[3] = {0, 0, 0};
    CHECK(sep_mesh_add(&s, &open, "open.stl", 1, zero, zero, 0, zero, &err) != MOTE_OK &&
              strstr(err.msg, "open.stl: solid=yes needs a closed mesh"),
          "an open mesh as solid: '%s'", err.msg);
    memset(open.closed, 1, m.nt);
    open.nt = m.nt;
    CHECK(sep_mesh_add(&s, &open, "cube.stl", 1, zero, (double[3]){0, 0, 1}, PI / 6 / 0.5,
                       (double[3]){0.02, 0.02, 0.02}, &err) == MOTE_OK, "cube: %s", err.msg);
    free(open.closed);
    free(m.v);
    free(m.t);
    memset(&m, 0, sizeof m);
    CHECK(mote_sep_prepare(&s, &err) == MOTE_OK, "prepare: %s", err.msg);
    /* at t = 0.5 s the cube has turned 30 degrees: its corner (2.5, 2.5) cm is at radius
     * 0.707 cm, angle 75 degrees about the centre */
    const double t = 0.5, rc = 0.005 * sqrt(2.0), an = 75 * PI / 180;
    const double corner[3] = {0.02 + rc * cos(an), 0.02 + rc * sin(an), 0.025};
    static const struct {
        double p[3], r;
        int blocked;
        const char *what;
    } cases[] = {{{0.02, 0.02, 0.02}, 0, 1, "the centre"},
                 {{0.024, 0.0205, 0.0199}, 0, 1, "inside near a face"},
                 {{0.02, 0.02, 0.0254}, 5e-4, 1, "touching the top face"},
                 {{0.02, 0.02, 0.0256}, 5e-4, 0, "clear of the top face"},
                 {{0.0, 0.0, 0.0}, 0, 0, "far away"}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const int b = sep_mesh_blocks(&s, t, cases[k].p, cases[k].r);
        CHECK(b == cases[k].blocked, "%s: blocked %d", cases[k].what, b);
    }
    const double near[3] = {corner[0] + 4e-4 * cos(an), corner[1] + 4e-4 * sin(an), 0.025};
    const double far[3] = {corner[0] + 6e-4 * cos(an), corner[1] + 6e-4 * sin(an), 0.025};
    CHECK(sep_mesh_blocks(&s, t, near, 5e-4) == 1 && sep_mesh_blocks(&s, t, far, 5e-4) == 0 &&
              sep_mesh_blocks(&s, 0, near, 5e-4) == 0,
          "the turned corner: near %d, far %d, near at t = 0 %d", sep_mesh_blocks(&s, t, near, 5e-4),
          sep_mesh_blocks(&s, t, far, 5e-4), sep_mesh_blocks(&s, 0, near, 5e-4));
    mote_sep_free(&s);
    /* the feed's placements: 300 spheres inserted into a zone that a tilted sheet cuts through,
     * none touching it */
    box(&s, 0.04, 0.04, 0.04, 0, 2e-3, 0, 0.5, 0);
    sheet(&m, 0.02, 0.02, 0.02, 0.05, 5, 0.4);
    add_wall(&s, &m, NULL, 0, NULL, NULL);
    CHECK(mote_sep_prepare(&s, &err) == MOTE_OK, "prepare: %s", err.msg);
    CHECK(mote_sep_insert(&s, 0, 300, 0, &err) == MOTE_OK, "insert: %s", err.msg);
    size_t touching = 0, above = 0;
    for (size_t i = 0; i < s.n; i++) {
        touching += sep_mesh_blocks(&s, s.t, (double[3]){s.x[i], s.y[i], s.z[i]}, 1e-3) != 0;
        above += s.z[i] - 0.02 > -tan(0.4) * (s.x[i] - 0.02);
    }
    CHECK(s.n + s.nback == 300 && touching == 0 && above > 50 && s.n - above > 50,
          "300 inserted across a sheet: %zu placed (%zu waiting), %zu touching it, %zu above it",
          s.n, s.nback, touching, above);
    mote_sep_free(&s);
}

/* ---- threads, save and load ---- */

/* A pour through a square hopper (an open sheet: four sloping sides from a 3.6 cm mouth at 3 cm
 * up to a 1 cm outlet at 1.5 cm) turning at 5 rad/s about the vertical, fed from above with 1-2
 * mm spheres placed inside it (clear of its sides), onto a tilted plate below it; the law linear or hertz (friction, rolling
 * friction, cohesion); `steps` steps on nt threads (from 1 particle up), with save and load
 * half way when reload; the state into path. */
static void pour(int hertz, int nt, int reload, int steps, const char *path)
{
    mote_sep_system s;
    box(&s, 0.04, 0.04, 0.05, 9.81, 1.5e-3, hertz, 0.5, 0.5);
    s.sp[0].dist = (mote_sep_dist){.type = MOTE_SEP_LOGUNIFORM, .lo = 1e-3, .hi = 2e-3,
                                   .number_basis = 1};
    mote_err err = {0};
    CHECK(mote_sep_dist_build(&s.sp[0].dist, &err) == MOTE_OK, "dist: %s", err.msg);
    s.mur_pp = 0.05;
    s.coh_pp = hertz ? 1e4 : 0;
    s.zf = 0.024, s.hf = 0.006, s.rate = 0.1;
    s.fx1 = 0.01, s.fx2 = 0.03, s.fy1 = 0.01, s.fy2 = 0.03;
    s.vf[2] = -1;
    s.nsort = 40;
    s.v_imp = 2;
    s.nc = 30;
    soup m = {0};
    const double c = 0.02, a = 0.018, b = 0.005, zt = 0.03, zb = 0.015;
    uint32_t top[4], bot[4];
    for (int k = 0; k < 4; k++) {
        const double sx = k == 0 || k == 3 ? -1 : 1, sy = k < 2 ? -1 : 1;
        top[k] = vtx(&m, c + sx * a, c + sy * a, zt);
        bot[k] = vtx(&m, c + sx * b, c + sy * b, zb);
    }
    for (int k = 0; k < 4; k++) {
        tri(&m, bot[k], bot[(k + 1) % 4], top[(k + 1) % 4]);
        tri(&m, bot[k], top[(k + 1) % 4], top[k]);
    }
    add_wall(&s, &m, NULL, 5, (double[3]){0, 0, 1}, (double[3]){c, c, 0});
    sheet(&m, 0.02, 0.02, 0.006, 0.03, 6, 0.3);
    add_wall(&s, &m, NULL, 0, NULL, NULL);
    CHECK(mote_sep_prepare(&s, &err) == MOTE_OK, "prepare: %s", err.msg);
    s.threads = nt;
    s.threads_min_n = 1;
    const double half = 0.5 * steps * s.dt;
    run(&s, half);
    if (reload) {
        CHECK(mote_sep_save(&s, 1, path, &err) == MOTE_OK, "save: %s", err.msg);
        mote_sep_free(&s);
        mote_sep_init(&s);
        uint64_t seed;
        CHECK(mote_sep_load(&s, &seed, path, &err) == MOTE_OK, "load: %s", err.msg);
        s.threads = nt;
        s.threads_min_n = 1;
    }
    run(&s, half);
    CHECK(mote_sep_save(&s, 1, path, &err) == MOTE_OK, "save: %s", err.msg);
    if (nt == 1 && !reload) {
        size_t springs = 0, below = 0;
        for (size_t k = 0; s.mh && k < 4 * SEP_MESH_SLOTS * s.n; k += 4)
            springs += s.mh[k] != 0;
        for (size_t i = 0; i < s.n; i++)
            below += s.z[i] < zb;
        CHECK(s.n > 200 && below > 20 && (!hertz || springs > 20),
              "the pour exercises the walls: %zu particles, %zu through the hopper, %zu wall "
              "springs", s.n, below, springs);
        printf("  %s: %zu particles, %zu through the hopper, %zu wall springs, largest overlap "
               "%.3f d\n", hertz ? "hertz" : "linear", s.n, below, springs, s.max_overlap);
    }
    mote_sep_free(&s);
}

static void test_threads(void)
{
    printf("mesh walls: a pour through a turning hopper, the same bits on 1, 2, 3 threads and "
           "across save and load\n");
    for (int hertz = 0; hertz < 2; hertz++) {
        static const int how[4][2] = {{1, 0}, {2, 0}, {3, 0}, {2, 1}};
        char path[4][64];
        for (int k = 0; k < 4; k++) {
            snprintf(path[k], sizeof path[0], "/tmp/mote_sep_mesh_%d_%d.state", hertz, k);
            pour(hertz, how[k][0], how[k][1], 8000, path[k]);
        }
        for (int k = 1; k < 4; k++)
            CHECK(test_same_file(path[0], path[k]), "%s: way %d's state equals the one on 1 thread",
                  hertz ? "hertz" : "linear", k);
        for (int k = 0; k < 4; k++)
            if (!getenv("KEEP"))
                remove(path[k]);
    }
}

int main(int argc, char **argv)
{
    static const struct {
        const char *name;
        void (*fn)(void);
    } tests[] = {{"impacts", test_impacts}, {"groove", test_groove},
                 {"fine", test_fine},       {"incline", test_incline}, {"belt", test_belt},
                 {"turntable", test_turntable}, {"blocks", test_blocks},
                 {"threads", test_threads}};
    for (size_t k = 0; k < sizeof tests / sizeof tests[0]; k++)
        if (argc < 2 || !strcmp(argv[1], tests[k].name))
            tests[k].fn();
    return test_summary();
}
