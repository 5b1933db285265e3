/* test_mixingbox.c: the mixing-box model (specs/mixing-box.md) through its library API and
 * through scripts.
 *
 * - the document's collision rule and normal restitution on hand-computed cases (head-on,
 *   oblique, with loss, the rule's wrong axis when the line of centres slopes down), their
 *   conservation laws, and the TC model;
 * - the time-stepped reference mode's pair rule (approach test, push of the upper disk) and
 *   every wall, partition and slit rule with its kick, including the two typo fixes;
 * - placement: no pair closer than 2R, every disk inside its chamber and clear of the walls,
 *   speed V_init, colours, isotropic directions, a clear failure when the disks do not fit;
 * - counts, mixing fraction, mixing entropy, m_eq, crossings;
 * - runs: kinetic energy kept to rounding without gravity (every rule preserves speeds), energy
 *   and overlaps reported as a direct recomputation finds them, the overlap defect showing in
 *   a dense gas, the drift showing under gravity, the inelastic gas cooling without a stall;
 * - the integrator contract: samples at exact times t0 + k DT, a sample a hair before the end
 *   taken at the end, the collision limit;
 * - scripts: the record file's columns and exact sample times, its E and overlaps agreeing
 *   with the run's summary line, same seed same bytes, another seed other bytes, the event
 *   integrator rejected while it is missing. */
#include "mote/mixingbox.h"
#include "mote/script.h"

#include "../src/mixingbox/mb.h"

#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test.h"

static char tmpdir[256];

/* ---- helpers ----------------------------------------------------------------------------------- */

/* A system of n disks at given positions and velocities (no placement), for rule tests. */
static void hand_system(mote_mb *s, const mote_mb_params *p, uint32_t n, const double *x,
                        const double *y, const double *vx, const double *vy)
{
    mote_mb_init(s);
    s->p = *p;
    s->n = n;
    s->x = malloc(n * sizeof *s->x);
    s->y = malloc(n * sizeof *s->y);
    s->vx = malloc(n * sizeof *s->vx);
    s->vy = malloc(n * sizeof *s->vy);
    s->colour = calloc(n, sizeof *s->colour);
    s->side = calloc(n, sizeof *s->side);
    s->t_last = malloc(n * sizeof *s->t_last);
    for (uint32_t i = 0; i < n; i++) {
        s->x[i] = x[i];
        s->y[i] = y[i];
        s->vx[i] = vx[i];
        s->vy[i] = vy[i];
        s->side[i] = (uint8_t)mote_mb_chamber(s, x[i]);
        s->t_last[i] = -INFINITY;
    }
    s->placed = 1;
}

static uint64_t brute_overlaps(const mote_mb *s)
{
    double c = 2 * s->p.r * (1 - MOTE_MB_OVERLAP_TOL);
    uint64_t n = 0;
    for (uint32_t i = 0; i < s->n; i++)
        for (uint32_t j = i + 1; j < s->n; j++) {
            double dx = s->x[i] - s->x[j], dy = s->y[i] - s->y[j];
            n += dx * dx + dy * dy < c * c;
        }
    return n;
}

static double brute_energy(const mote_mb *s, double *kin)
{
    long double e = 0, k = 0;
    for (uint32_t i = 0; i < s->n; i++) {
        long double ki = 0.5L * s->p.mass * ((long double)s->vx[i] * s->vx[i] +
                                             (long double)s->vy[i] * s->vy[i]);
        k += ki;
        e += ki + (long double)s->p.mass * s->p.g * (s->y[i] - s->p.x_b);
    }
    if (kin)
        *kin = (double)k;
    return (double)e;
}

static char *read_all(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    if (s && fread(s, 1, (size_t)n, f) != (size_t)n) {
        free(s);
        s = NULL;
    }
    if (s)
        s[n] = '\0';
    fclose(f);
    return s;
}

/* Run script text with the mixing-box model; stdout goes to *out (malloc'ed). Returns the
 * status: 0 ok, 1 invalid, 2 failed. */
static int run_script(const char *name, const char *text, char **out, char *errmsg, size_t cap)
{
    static const mote_model *const models[] = {&mote_model_mixingbox};
    mote_err err = {0};
    mote_script *s = NULL;
    char *buf = NULL;
    size_t len = 0;
    FILE *mem = open_memstream(&buf, &len);
    int status = 0;
    if (mote_script_parse(&s, name, text, strlen(text), models, 1, &err)) {
        status = 1;
    } else {
        mote_context *ctx = mote_script_context(s);
        ctx->out = mem;
        ctx->diag = mem;
        if (mote_script_validate(s, &err))
            status = 1;
        else if (mote_script_execute(s, &err))
            status = 2;
    }
    mote_script_free(s);
    fclose(mem);
    if (errmsg)
        snprintf(errmsg, cap, "%s", status ? err.msg : "");
    if (out)
        *out = buf;
    else
        free(buf);
    return status;
}

static double value_of(const char *text, const char *line_prefix, const char *key)
{
    const char *l = text;
    while (l && *l) {
        if (strncmp(l, line_prefix, strlen(line_prefix)) == 0) {
            const char *end = strchr(l, '\n');
            size_t n = end ? (size_t)(end - l) : strlen(l);
            char line[2048];
            snprintf(line, sizeof line, "%.*s", (int)n, l);
            char pat[64];
            snprintf(pat, sizeof pat, " %s=", key);
            const char *v = strstr(line, pat);
            return v ? strtod(v + strlen(pat), NULL) : NAN;
        }
        l = strchr(l, '\n');
        if (l)
            l++;
    }
    return NAN;
}

/* ---- collision rules ----------------------------------------------------------------------------- */

static void test_rules(void)
{
    printf("collision rules\n");
    const double R = 0.5;
    /* head-on along x, the document's rule: the velocities swap */
    double v1[2] = {1, 0}, v2[2] = {-1, 0};
    CHECK(mote_mb_rule_seed(0, 0, 2 * R * 0.99, 0, v1, v2, 1.0), "seed rule refused");
    CHECK_NEAR(v1[0], -1, 1e-15);
    CHECK_NEAR(v1[1], 0, 1e-15);
    CHECK_NEAR(v2[0], 1, 1e-15);
    CHECK_NEAR(v2[1], 0, 1e-15);
    /* with loss 0.36: f = 0.8 scales both */
    v1[0] = 1, v1[1] = 0, v2[0] = -1, v2[1] = 0;
    mote_mb_rule_seed(0, 0, 1, 0, v1, v2, sqrt(1 - 0.36));
    CHECK_NEAR(v1[0], -0.8, 1e-15);
    CHECK_NEAR(v2[0], 0.8, 1e-15);
    /* oblique at 45 degrees, disk 2 up and right, 2 at rest: 2 takes the normal part */
    v1[0] = 1, v1[1] = 0, v2[0] = 0, v2[1] = 0;
    mote_mb_rule_seed(0, 0, 0.7, 0.7, v1, v2, 1.0);
    CHECK_NEAR(v1[0], 0.5, 1e-15);
    CHECK_NEAR(v1[1], -0.5, 1e-15);
    CHECK_NEAR(v2[0], 0.5, 1e-15);
    CHECK_NEAR(v2[1], 0.5, 1e-15);
    /* the same with f = 0.8: tangential parts scaled too */
    v1[0] = 1, v1[1] = 0, v2[0] = 0, v2[1] = 0;
    mote_mb_rule_seed(0, 0, 0.7, 0.7, v1, v2, 0.8);
    CHECK_NEAR(v1[0], 0.4, 1e-15);
    CHECK_NEAR(v1[1], -0.4, 1e-15);
    CHECK_NEAR(v2[0], 0.4, 1e-15);
    CHECK_NEAR(v2[1], 0.4, 1e-15);
    /* disk 2 down and right: the absolute values make the rule reflect about (1, 1)/sqrt 2,
     * not the true normal (1, -1)/sqrt 2, so disk 2 moves up (the document's defect) */
    v1[0] = 1, v1[1] = 0, v2[0] = 0, v2[1] = 0;
    mote_mb_rule_seed(0, 0, 0.7, -0.7, v1, v2, 1.0);
    CHECK_NEAR(v2[0], 0.5, 1e-15);
    CHECK_NEAR(v2[1], 0.5, 1e-15);
    /* restitution on the same pair uses the true normal */
    v1[0] = 1, v1[1] = 0, v2[0] = 0, v2[1] = 0;
    mote_mb_rule_restitution(0, 0, 0.7, -0.7, v1, v2, 1.0);
    CHECK_NEAR(v2[0], 0.5, 1e-15);
    CHECK_NEAR(v2[1], -0.5, 1e-15);
    CHECK_NEAR(v1[0], 0.5, 1e-15);
    CHECK_NEAR(v1[1], 0.5, 1e-15);
    /* restitution head-on with e = 0.8, and oblique: only the normal part loses */
    v1[0] = 1, v1[1] = 0, v2[0] = -1, v2[1] = 0;
    mote_mb_rule_restitution(0, 0, 1, 0, v1, v2, 0.8);
    CHECK_NEAR(v1[0], -0.8, 1e-15);
    CHECK_NEAR(v2[0], 0.8, 1e-15);
    v1[0] = 1, v1[1] = 0, v2[0] = 0, v2[1] = 0;
    mote_mb_rule_restitution(0, 0, 0.7, 0.7, v1, v2, 0.8);
    CHECK_NEAR(v1[0], 0.55, 1e-15);
    CHECK_NEAR(v1[1], -0.45, 1e-15);
    CHECK_NEAR(v2[0], 0.45, 1e-15);
    CHECK_NEAR(v2[1], 0.45, 1e-15);
    /* coincident centres: nothing to do */
    v1[0] = 1, v1[1] = 2;
    CHECK(!mote_mb_rule_seed(1, 1, 1, 1, v1, v2, 1) && v1[0] == 1 && v1[1] == 2,
          "coincident centres changed velocities");
    CHECK(!mote_mb_rule_restitution(1, 1, 1, 1, v1, v2, 1), "coincident centres accepted");

    /* random cases: momentum always kept; energy kept for f = e = 1; restitution reverses the
     * normal relative velocity times e, keeps the tangential one, loses (1 - e^2) u^2 / 4 */
    mote_rng rng;
    mote_rng_seed(&rng, test_seed(7));
    double worst_p = 0, worst_e = 0, worst_n = 0;
    for (int k = 0; k < 1000; k++) {
        double dx = mote_rng_uniform(&rng) - 0.5, dy = mote_rng_uniform(&rng) - 0.5;
        double a[2] = {mote_rng_uniform(&rng) - 0.5, mote_rng_uniform(&rng) - 0.5};
        double b[2] = {mote_rng_uniform(&rng) - 0.5, mote_rng_uniform(&rng) - 0.5};
        double e = k % 2 ? 1.0 : 0.7;
        for (int rule = 0; rule < 2; rule++) {
            double p1[2] = {a[0], a[1]}, p2[2] = {b[0], b[1]};
            double f = rule ? 1.0 : e;
            if (rule)
                mote_mb_rule_seed(0, 0, dx, dy, p1, p2, f);
            else
                mote_mb_rule_restitution(0, 0, dx, dy, p1, p2, f);
            double e0 = a[0] * a[0] + a[1] * a[1] + b[0] * b[0] + b[1] * b[1];
            double e1 = p1[0] * p1[0] + p1[1] * p1[1] + p2[0] * p2[0] + p2[1] * p2[1];
            worst_p = fmax(worst_p, fabs(p1[0] + p2[0] - a[0] - b[0]) +
                                        fabs(p1[1] + p2[1] - a[1] - b[1]));
            double d = sqrt(dx * dx + dy * dy), nx = dx / d, ny = dy / d;
            double u0 = (a[0] - b[0]) * nx + (a[1] - b[1]) * ny;
            if (rule == 1) {
                worst_e = fmax(worst_e, fabs(e1 - e0));
            } else {
                double u1 = (p1[0] - p2[0]) * nx + (p1[1] - p2[1]) * ny;
                double t0 = (a[0] - b[0]) * -ny + (a[1] - b[1]) * nx;
                double t1 = (p1[0] - p2[0]) * -ny + (p1[1] - p2[1]) * nx;
                worst_n = fmax(worst_n, fabs(u1 + e * u0) + fabs(t1 - t0));
                /* kinetic energy with m = 1 is half of e0, e1 */
                worst_e = fmax(worst_e, fabs(0.5 * (e0 - e1) - (1 - e * e) * u0 * u0 / 4));
            }
        }
    }
    CHECK(worst_p < 1e-15, "momentum changed by %g", worst_p);
    CHECK(worst_e < 1e-15, "energy balance off by %g", worst_e);
    CHECK(worst_n < 1e-15, "normal/tangential velocities off by %g", worst_n);
}

static void test_tc(void)
{
    printf("TC model\n");
    mote_mb_params p;
    mote_mb_params_default(&p);
    p.loss = 0.36;
    p.t_c = 0.01;
    double x[3] = {0.5, 0.51, 0.52}, y[3] = {0.5, 0.5, 0.5};
    double vx[3] = {1, -1, 0}, vy[3] = {0, 0, 0};
    for (int rule = 0; rule < 2; rule++) {
        mote_mb s;
        p.rule = rule ? MOTE_MB_SEEDRULE : MOTE_MB_RESTITUTION;
        hand_system(&s, &p, 3, x, y, vx, vy);
        mote_mb_collide(&s, 0, 1, 1.0); /* inelastic: f = 0.8 */
        CHECK_NEAR(s.vx[0], -0.8, 1e-15);
        CHECK_NEAR(s.vx[1], 0.8, 1e-15);
        CHECK(s.t_last[0] == 1.0 && s.t_last[1] == 1.0, "t_last not updated");
        mote_mb_collide(&s, 1, 2, 1.005); /* 1 collided 0.005 s ago < t_c: elastic */
        CHECK_NEAR(s.vx[1], 0.0, 1e-15);
        CHECK_NEAR(s.vx[2], 0.8, 1e-15);
        s.vx[0] = 1, s.vx[1] = -1;
        mote_mb_collide(&s, 0, 1, 1.02); /* both last collided >= t_c ago: inelastic */
        CHECK_NEAR(s.vx[0], -0.8, 1e-15);
        CHECK_INT(s.collisions, 3);
        CHECK_INT(s.collisions_tc, 1);
        mote_mb_free(&s);
    }
    /* t_c = 0 switches it off; automatic t_c = R / (100 V_init), V_init = 0 -> 0.1 m/s */
    mote_mb s;
    p.t_c = 0;
    p.rule = MOTE_MB_RESTITUTION;
    hand_system(&s, &p, 3, x, y, vx, vy);
    mote_mb_collide(&s, 0, 1, 1.0);
    s.vx[0] = 1, s.vx[1] = -1;
    mote_mb_collide(&s, 0, 1, 1.0);
    CHECK_NEAR(s.vx[0], -0.8, 1e-15);
    CHECK_INT(s.collisions_tc, 0);
    mote_mb_free(&s);
    mote_mb_params_default(&p);
    CHECK_NEAR(mote_mb_tc(&p), 0.005 / 100, 1e-18);
    p.v_init = 0;
    CHECK_NEAR(mote_mb_tc(&p), 0.005 / 10, 1e-18);
}

/* ---- the time-stepped rules ------------------------------------------------------------------------ */

static void test_pair_rule(void)
{
    printf("timestep: pair rule\n");
    mote_mb_params p;
    mote_mb_params_default(&p);
    p.r = 0.01;
    /* approaching and overlapping, disk 1 above: it is pushed out to contact along the line of
     * centres, disk 0 stays */
    double x[2] = {0.5, 0.51}, y[2] = {0.5, 0.515};
    double vx[2] = {0.3, -0.2}, vy[2] = {0.1, -0.4};
    mote_mb s;
    hand_system(&s, &p, 2, x, y, vx, vy);
    CHECK(mb_ts_pair(&s, 0, 1, 0.0) == 1, "approaching overlapping pair did not collide");
    double dx = s.x[1] - s.x[0], dy = s.y[1] - s.y[0];
    CHECK_NEAR(sqrt(dx * dx + dy * dy), 0.02, 1e-15);
    CHECK_NEAR(dy / dx, 1.5, 1e-12); /* along the old line of centres */
    CHECK(s.x[0] == 0.5 && s.y[0] == 0.5, "the lower disk moved");
    /* momentum kept */
    CHECK_NEAR(s.vx[0] + s.vx[1], 0.1, 1e-15);
    CHECK_NEAR(s.vy[0] + s.vy[1], -0.3, 1e-15);
    /* now receding (after the collision): nothing happens, even when overlapping again */
    s.x[1] = 0.51, s.y[1] = 0.515;
    CHECK(mb_ts_pair(&s, 0, 1, 0.0) == 0, "receding pair collided");
    CHECK(s.x[1] == 0.51 && s.y[1] == 0.515, "receding pair pushed");
    mote_mb_free(&s);
    /* disk 0 above: disk 0 is pushed (the document's second case, sign fixed) */
    double y2[2] = {0.515, 0.5}, vy2[2] = {-0.4, 0.1};
    hand_system(&s, &p, 2, x, y2, vx, vy2);
    CHECK(mb_ts_pair(&s, 0, 1, 0.0) == 1, "no collision");
    CHECK(s.x[1] == 0.51 && s.y[1] == 0.5, "the lower disk moved");
    dx = s.x[1] - s.x[0], dy = s.y[1] - s.y[0];
    CHECK_NEAR(sqrt(dx * dx + dy * dy), 0.02, 1e-15);
    CHECK(s.y[0] > 0.515, "the upper disk did not move up");
    mote_mb_free(&s);
    /* level pair: collides, nobody is pushed */
    double y3[2] = {0.5, 0.5}, vy3[2] = {0, 0};
    hand_system(&s, &p, 2, x, y3, vx, vy3);
    CHECK(mb_ts_pair(&s, 0, 1, 0.0) == 1, "no collision");
    CHECK(s.x[0] == 0.5 && s.x[1] == 0.51, "a level pair was pushed");
    CHECK_NEAR(s.vx[0], -0.2, 1e-15);
    CHECK_NEAR(s.vx[1], 0.3, 1e-15);
    /* apart: nothing */
    s.x[1] = 0.53;
    CHECK(mb_ts_pair(&s, 0, 1, 0.0) == 0, "separated pair collided");
    mote_mb_free(&s);
}

/* One disk at (x, y) with (vx, vy) through mb_ts_walls; returns it in the arrays. */
static void wall_case(const mote_mb_params *p, double *x, double *y, double *vx, double *vy,
                      uint64_t *wall, uint64_t *part, uint64_t *slit)
{
    mote_mb s;
    hand_system(&s, p, 1, x, y, vx, vy);
    mb_ts_walls(&s, 0);
    *x = s.x[0], *y = s.y[0], *vx = s.vx[0], *vy = s.vy[0];
    *wall = s.wall_hits, *part = s.partition_hits, *slit = s.slit_hits;
    mote_mb_free(&s);
}

#define WALL(x0, y0, vx0, vy0, x1, y1, vx1, vy1, nw, np, ns)                                     \
    do {                                                                                         \
        double x_ = (x0), y_ = (y0), vx_ = (vx0), vy_ = (vy0);                                   \
        uint64_t w_, p_, s_;                                                                     \
        wall_case(&p, &x_, &y_, &vx_, &vy_, &w_, &p_, &s_);                                      \
        CHECK(x_ == (x1) && y_ == (y1) && vx_ == (vx1) && vy_ == (vy1) && w_ == (nw) &&          \
                  p_ == (np) && s_ == (ns),                                                      \
              "(%g, %g) v (%g, %g) -> (%.17g, %.17g) v (%.17g, %.17g) hits %llu %llu %llu", x0,  \
              y0, vx0, vy0, x_, y_, vx_, vy_, (unsigned long long)w_, (unsigned long long)p_,    \
              (unsigned long long)s_);                                                           \
    } while (0)

static void test_wall_rules(void)
{
    printf("timestep: wall, partition and slit rules with kicks\n");
    mote_mb_params p;
    mote_mb_params_default(&p); /* box 0 2 0 1, partition 1 +- 0.01, slit 0.45 .. 0.55 */
    p.r = 0.01;
    p.dv_b = 0.25;
    p.dv_t = 0.5;
    p.dv_s = 0.125;
    const double R = 0.01, top = 1 - R, bot = R, left = R, right = 2 - R;
    /* box walls: put on the wall, normal velocity reversed with the kick away from it */
    WALL(0.5, 0.995, 0.1, 0.5, 0.5, top, 0.1, -1.0, 1, 0, 0);
    WALL(0.5, 0.005, 0.1, -0.5, 0.5, bot, 0.1, 0.75, 1, 0, 0);
    WALL(0.005, 0.5, -0.5, 0.1, left, 0.5, 0.625, 0.1, 1, 0, 0);
    WALL(1.995, 0.5, 0.5, 0.1, right, 0.5, -0.625, 0.1, 1, 0, 0);
    /* past a wall but moving away from it: left alone */
    WALL(0.5, 0.995, 0.1, -0.5, 0.5, 0.995, 0.1, -0.5, 0, 0, 0);
    WALL(0.005, 0.5, 0.5, 0.1, 0.005, 0.5, 0.5, 0.1, 0, 0, 0);
    /* a corner: both walls */
    WALL(1.995, 0.995, 0.5, 0.5, right, top, -0.625, -1.0, 2, 0, 0);
    /* partition faces away from the slit: x = X1_L - R with -(vx + dV_S), X1_R + R with
     * -(vx - dV_S) */
    WALL(0.985, 0.8, 0.5, 0.1, 0.99 - R, 0.8, -0.625, 0.1, 0, 1, 0);
    WALL(1.015, 0.2, -0.5, 0.1, 1.01 + R, 0.2, 0.625, 0.1, 0, 1, 0);
    /* moving away from the face: nothing */
    WALL(0.985, 0.8, -0.5, 0.1, 0.985, 0.8, -0.5, 0.1, 0, 0, 0);
    /* in the slit channel: its top edge y = X2_T - R with the top kick, its bottom edge (the
     * document's condition has a sign typo) y = X2_B + R with the bottom kick */
    WALL(1.0, 0.545, 0.3, 0.5, 1.0, 0.55 - R, 0.3, -1.0, 0, 0, 1);
    WALL(1.0, 0.455, 0.3, -0.5, 1.0, 0.45 + R, 0.3, 0.75, 0, 0, 1);
    /* in the channel, clear of the edges: passes */
    WALL(1.0, 0.5, 0.3, 0.5, 1.0, 0.5, 0.3, 0.5, 0, 0, 0);
    /* in the approach band at slit height (centre inside the slit rows): passes, even when the
     * disk overlaps the slit's corner (corners are not handled) */
    WALL(0.985, 0.545, 0.5, 0.1, 0.985, 0.545, 0.5, 0.1, 0, 0, 0);
    /* the slit's edges only act on centres inside the channel */
    WALL(0.985, 0.455, 0.5, -0.5, 0.985, 0.455, 0.5, -0.5, 0, 0, 0);
}

/* ---- placement ------------------------------------------------------------------------------------- */

static void test_placement(void)
{
    printf("placement\n");
    mote_mb_params p;
    mote_mb_params_default(&p);
    p.x_r = 1.0;
    p.x1_c = 0.5;
    p.x2_c = 0.5;
    p.b = 0.1;
    p.r = 0.01;
    p.n_left = 300;
    p.n_right = 200;
    p.v_init = 2.5;
    mote_mb s;
    mote_mb_init(&s);
    mote_mb_seed(&s, test_seed(11));
    mote_err err = {0};
    CHECK(mote_mb_place(&s, &p, &err) == MOTE_OK, "place: %s", err.msg);
    CHECK_INT(s.n, 500);
    CHECK_INT(brute_overlaps(&s), 0);
    double dmin = INFINITY;
    for (uint32_t i = 0; i < s.n; i++)
        for (uint32_t j = i + 1; j < s.n; j++)
            dmin = fmin(dmin, hypot(s.x[i] - s.x[j], s.y[i] - s.y[j]));
    CHECK(dmin >= 2 * p.r, "closest pair %.17g < 2R", dmin);
    int bad_place = 0, bad_colour = 0, bad_speed = 0;
    double sum_cos = 0, sum_sin = 0;
    for (uint32_t i = 0; i < s.n; i++) {
        int left = i < 300;
        double xlo = left ? p.r : 0.51 + p.r, xhi = left ? 0.49 - p.r : 1 - p.r;
        bad_place += !(s.x[i] >= xlo && s.x[i] <= xhi && s.y[i] >= p.r && s.y[i] <= 1 - p.r);
        bad_colour += s.colour[i] != (left ? 0 : 1) || s.side[i] != (left ? 0 : 1);
        double v = hypot(s.vx[i], s.vy[i]);
        bad_speed += fabs(v - 2.5) > 1e-14;
        sum_cos += s.vx[i] / v;
        sum_sin += s.vy[i] / v;
    }
    CHECK_INT(bad_place, 0);
    CHECK_INT(bad_colour, 0);
    CHECK_INT(bad_speed, 0);
    /* uniform directions: the means of cos and sin are 0 with standard error sqrt(1/2N) */
    double se = sqrt(0.5 / s.n);
    CHECK(fabs(sum_cos / s.n) < 4 * se && fabs(sum_sin / s.n) < 4 * se,
          "mean direction (%g, %g), standard error %g", sum_cos / s.n, sum_sin / s.n, se);
    CHECK(s.time == 0 && s.collisions == 0 && s.cross_lr == 0, "counters not reset");
    /* the same seed gives the same placement; the stream continues otherwise */
    mote_mb s2;
    mote_mb_init(&s2);
    mote_mb_seed(&s2, test_seed(11));
    mote_mb_place(&s2, &p, &err);
    CHECK(memcmp(s.x, s2.x, s.n * sizeof *s.x) == 0 && memcmp(s.vy, s2.vy, s.n * sizeof *s.vy) == 0,
          "same seed, different placement");
    mote_mb_place(&s2, &p, &err);
    CHECK(memcmp(s.x, s2.x, s.n * sizeof *s.x) != 0, "second place repeated the first");
    mote_mb_free(&s2);

    /* too dense for the check: rejected with the area fraction */
    p.n_left = 1400; /* 1400 pi 1e-4 / 0.49 = 0.90 */
    CHECK(mote_mb_place(&s, &p, &err) == MOTE_EINVAL, "dense chamber accepted");
    CHECK_HAS(err.msg, "area fraction");
    CHECK_INT(s.n, 500); /* the earlier system is kept */
    /* inside the check's limit but not placeable at random: a chamber of 10R x 10R holds 17
     * disks (area fraction 0.534) only with luck; seed 1 runs out of tries */
    mote_mb_params q;
    mote_mb_params_default(&q);
    q.r = 0.01;
    q.x_l = 0;
    q.x1_c = 0.105;
    q.a = 0.01;
    q.x_r = 0.21;
    q.x_b = 0;
    q.x_t = 0.1;
    q.x2_c = 0.05;
    q.b = 0.03;
    q.n_left = 17;
    q.n_right = 1;
    CHECK(mote_mb_params_check(&q, &err) == MOTE_OK, "check: %s", err.msg);
    mote_mb_seed(&s, 1);
    int rc = mote_mb_place(&s, &q, &err);
    CHECK(rc == MOTE_ERUNTIME, "17 disks in 10R x 10R placed (rc %d)", rc);
    CHECK_HAS(err.msg, "left chamber did not fit after 1000000 random tries");
    CHECK_HAS(err.msg, "area fraction n pi R^2 / area = 0.534");
    CHECK_INT(s.n, 500);
    mote_mb_free(&s);
}

/* ---- measurements ----------------------------------------------------------------------------------- */

static void test_measures(void)
{
    printf("counts, mixing fraction, entropy, crossings\n");
    mote_mb_tally t = {{{70, 30}, {20, 80}}};
    CHECK_NEAR(mote_mb_mixing_fraction(&t), 0.25, 1e-16);
    mote_mb_tally z = {{{0, 0}, {0, 0}}};
    CHECK(mote_mb_mixing_fraction(&z) == 0, "empty");
    CHECK_NEAR(mote_mb_entropy(70, 30), -(0.7 * log(0.7) + 0.3 * log(0.3)), 1e-15);
    CHECK_NEAR(mote_mb_entropy(50, 50), log(2.0), 1e-15);
    CHECK(mote_mb_entropy(0, 10) == 0 && mote_mb_entropy(0, 0) == 0, "pure chambers");
    mote_mb_params p;
    mote_mb_params_default(&p);
    CHECK_NEAR(mote_mb_mixing_equilibrium(&p), 0.5, 1e-16);
    p.x_r = 3; /* chambers 0.99 and 1.99 wide */
    p.n_left = 150;
    p.n_right = 50;
    CHECK_NEAR(mote_mb_mixing_equilibrium(&p), (150 * 1.99 + 50 * 0.99) / (200 * 2.98), 1e-15);

    /* counts follow side[]; a centre passing X1_C is a crossing */
    mote_mb_params_default(&p);
    double x[4] = {0.2, 0.5, 1.5, 1.7}, y[4] = {0.5, 0.5, 0.5, 0.5}, v[4] = {0, 0, 0, 0};
    mote_mb s;
    hand_system(&s, &p, 4, x, y, v, v);
    s.colour[2] = s.colour[3] = 1;
    s.colour[1] = 1; /* a colour-1 disk on the left */
    t = mote_mb_counts(&s);
    CHECK(t.n[0][0] == 1 && t.n[0][1] == 1 && t.n[1][0] == 0 && t.n[1][1] == 2, "counts");
    CHECK_NEAR(mote_mb_mixing_fraction(&t), 0.25, 1e-16);
    s.x[0] = 1.0; /* exactly on the midline counts as right */
    CHECK(mote_mb_note_side(&s, 0) == 1 && s.cross_lr == 1 && s.cross_rl == 0, "l->r");
    CHECK(mote_mb_note_side(&s, 0) == 0, "counted twice");
    s.x[0] = 0.999;
    CHECK(mote_mb_note_side(&s, 0) == 1 && s.cross_rl == 1, "r->l");
    /* energies with gravity, temperature per chamber */
    s.p.g = 2.0;
    s.vx[0] = 3;
    s.vy[3] = 4;
    double ek;
    double e = mote_mb_energy(&s, &ek);
    CHECK_NEAR(ek, 0.5 * 9 + 0.5 * 16, 1e-14);
    CHECK_NEAR(e, ek + 4 * 2.0 * 0.5, 1e-14);
    uint64_t c;
    CHECK_NEAR(mote_mb_chamber_kt(&s, 1, &c), 8.0 / 2, 1e-14);
    CHECK_INT(c, 2);
    mote_mb_free(&s);
}

/* ---- runs -------------------------------------------------------------------------------------------- */

static int sample_log(void *ctx, void *subject, mote_err *err)
{
    mote_mb *sys = subject;
    double *log_ = ctx;
    size_t k = (size_t)log_[0]++;
    if (k < 64)
        log_[1 + k] = sys->time;
    return MOTE_OK;
}

static void test_runs(void)
{
    printf("timestep runs: energy, overlaps, the integrator contract\n");
    mote_mb_params p;
    mote_mb_params_default(&p);
    p.x_r = 1.0;
    p.x1_c = 0.5;
    p.r = 0.01;
    p.n_left = p.n_right = 150;
    p.integrator = MOTE_MB_TIMESTEP;
    mote_mb s;
    mote_mb_init(&s);
    mote_err err = {0};
    CHECK(mote_mb_place(&s, &p, &err) == MOTE_OK, "place: %s", err.msg);
    double k0;
    brute_energy(&s, &k0);
    /* samples at t0 + k DT, exactly; k = 0 belongs to the caller */
    double log_[65] = {0};
    mote_schedule smp_at = {0.0, 0.1, 1};
    mote_observer smp = {.at = &smp_at, .ctx = log_, .fire = sample_log};
    mote_loop hooks = {&smp, 1, UINT64_MAX, NULL, 0, 0, 0, 0};
    CHECK(mote_mb_run(&s, 0.3, &hooks, &err) == MOTE_OK, "run: %s", err.msg);
    /* 3 * 0.1 = 0.30000000000000004 lies a hair past 0.3: taken at the end */
    CHECK_INT(log_[0], 3);
    CHECK(log_[1] == 0.1 && log_[2] == 0.2, "sample times %.17g %.17g", log_[1], log_[2]);
    CHECK(log_[3] == 0.3 && s.time == 0.3, "last sample %.17g, time %.17g", log_[3], s.time);
    CHECK(mote_mb_run(&s, 0.7, &hooks, &err) == MOTE_OK, "run: %s", err.msg);
    CHECK_INT(log_[0], 7);
    int exact = 1;
    for (int k = 4; k <= 7; k++)
        exact &= log_[k] == 0.0 + (double)k * 0.1 || (k == 7 && log_[k] == 0.7);
    CHECK(exact, "sample times not at t0 + k DT");
    CHECK(s.steps > 1000, "only %llu steps", (unsigned long long)s.steps);
    /* no gravity, no loss, no kicks: every rule keeps speeds, so kinetic energy is kept to
     * rounding even though disks overlap */
    double k1, e1 = brute_energy(&s, &k1);
    CHECK(fabs(k1 - k0) / k0 < 1e-12, "kinetic energy drifted by %g", (k1 - k0) / k0);
    double ek, e = mote_mb_energy(&s, &ek);
    CHECK_NEAR(e, e1, 1e-12 * e1);
    CHECK_INT(s.overlaps_last, brute_overlaps(&s));
    CHECK(s.overlaps_max >= s.overlaps_last, "max %llu < last %llu",
          (unsigned long long)s.overlaps_max, (unsigned long long)s.overlaps_last);
    CHECK(s.collisions > 100 && s.wall_hits > 100, "collisions %llu, wall hits %llu",
          (unsigned long long)s.collisions, (unsigned long long)s.wall_hits);
    /* the collision limit: stops at the end of the step that reaches it */
    uint64_t c0 = s.collisions, st0 = s.steps;
    hooks.n_end = c0 + 50;
    CHECK(mote_mb_run(&s, INFINITY, &hooks, &err) == MOTE_OK, "run: %s", err.msg);
    CHECK(s.collisions >= c0 + 50 && s.collisions < c0 + 80, "collisions %llu -> %llu",
          (unsigned long long)c0, (unsigned long long)s.collisions);
    CHECK(s.steps > st0, "no step");
    mote_mb_free(&s);

    /* a dense gas: the scheme's overlaps show, and are counted right */
    p.n_left = p.n_right = 700; /* area fraction 0.45 */
    mote_mb_init(&s);
    CHECK(mote_mb_place(&s, &p, &err) == MOTE_OK, "place: %s", err.msg);
    /* the count after each step (without a new grid) equals a direct count */
    int steps_bad = 0;
    for (int k = 0; k < 40; k++) {
        double dt = mb_ts_dt(&s);
        CHECK(mb_ts_step(&s, dt, s.time + dt, &err) == MOTE_OK, "step: %s", err.msg);
        steps_bad += s.overlaps_last != brute_overlaps(&s);
    }
    CHECK_INT(steps_bad, 0);
    CHECK(mote_mb_run(&s, 0.05, NULL, &err) == MOTE_OK, "run: %s", err.msg);
    CHECK(s.overlaps_max > 0 && s.overlap_steps > 0, "no overlaps in a dense gas (max %llu)",
          (unsigned long long)s.overlaps_max);
    CHECK_INT(s.overlaps_last, brute_overlaps(&s));
    printf("  dense gas, 0.05 s: %llu steps, %llu with overlaps, at most %llu at once\n",
           (unsigned long long)s.steps, (unsigned long long)s.overlap_steps,
           (unsigned long long)s.overlaps_max);
    mote_mb_free(&s);

    /* gravity: the scheme does not keep the total energy (pushes and wall placement move
     * disks without a change of speed); the energy it reports is the direct sum */
    p.n_left = p.n_right = 200;
    p.g = 9.81;
    p.v_init = 2;
    mote_mb_init(&s);
    mote_mb_place(&s, &p, &err);
    double eg0 = mote_mb_energy(&s, NULL);
    CHECK(mote_mb_run(&s, 0.5, NULL, &err) == MOTE_OK, "run: %s", err.msg);
    double eg1 = mote_mb_energy(&s, NULL);
    CHECK_NEAR(eg1, brute_energy(&s, NULL), 1e-12 * eg1);
    CHECK(fabs(eg1 - eg0) / eg0 > 1e-6, "energy kept to %g under gravity", (eg1 - eg0) / eg0);
    printf("  gravity, 0.5 s: relative energy drift %.3g\n", (eg1 - eg0) / eg0);
    /* inelastic under gravity: energy decays and the run does not stall */
    s.p.loss = 0.5;
    double ek0;
    mote_mb_energy(&s, &ek0);
    CHECK(mote_mb_run(&s, s.time + 0.5, NULL, &err) == MOTE_OK, "run: %s", err.msg);
    double ek1;
    mote_mb_energy(&s, &ek1);
    CHECK(ek1 < 0.5 * ek0, "kinetic energy %g -> %g with loss 0.5", ek0, ek1);
    CHECK(s.collisions_tc > 0, "the TC model never acted");
    mote_mb_free(&s);

    /* the event integrator on the same system runs */
    p.integrator = MOTE_MB_EVENT;
    p.g = 0;
    mote_mb_init(&s);
    mote_mb_place(&s, &p, &err);
    int rc = mote_mb_run(&s, 0.1, NULL, &err);
    CHECK(rc == MOTE_OK, "event: %d %s", rc, err.msg);
    mote_mb_free(&s);
}

/* ---- scripts ------------------------------------------------------------------------------------------ */

static const char *const SCRIPT =
    "model mixing-box\n"
    "integrator timestep\n"
    "output_dir %s\n"
    "seed %d\n"
    "box 0 1 0 0.5\n"
    "partition 0.5 0.02\n"
    "slit 0.25 0.08\n"
    "radius 0.008\n"
    "disks 150 150\n"
    "gravity %s\n"
    "place\n"
    "record 0.05 mix.dat\n"
    "density_y 0.05 10 dens.dat\n"
    "run 0.3\n"
    "plot mix.dat mix.png\n"
    "plot dens.dat dens.png\n";

static int count_fields(const char *line)
{
    int n = 0;
    while (*line && *line != '\n') {
        while (*line == ' ')
            line++;
        if (!*line || *line == '\n')
            break;
        n++;
        while (*line && *line != ' ' && *line != '\n')
            line++;
    }
    return n;
}

static void test_scripts(void)
{
    printf("scripts: record file, summary line, reproducibility\n");
    char dir[3][300], text[2048], msg[1024], path[400];
    char *out[3] = {NULL, NULL, NULL};
    const int seeds[3] = {5, 5, 6};
    for (int k = 0; k < 3; k++) {
        snprintf(dir[k], sizeof dir[k], "%s/run%d", tmpdir, k);
        snprintf(text, sizeof text, SCRIPT, dir[k], seeds[k], "9.81");
        int st = run_script("mb.mote", text, &out[k], msg, sizeof msg);
        CHECK(st == 0, "script %d: status %d: %s", k, st, msg);
    }
    snprintf(path, sizeof path, "%s/mix.dat", dir[0]);
    char *a = read_all(path);
    snprintf(path, sizeof path, "%s/mix.dat", dir[1]);
    char *b = read_all(path);
    snprintf(path, sizeof path, "%s/mix.dat", dir[2]);
    char *c = read_all(path);
    CHECK(a && b && c, "mix.dat missing");
    if (!a || !b || !c)
        return;
    /* the header names the directory through output_dir only in the paths of commands, not
     * in the file, so two runs with the same seed are byte-identical */
    CHECK(strcmp(a, b) == 0, "same seed, different mix.dat");
    CHECK(strcmp(a, c) != 0, "different seeds, same mix.dat");
    CHECK_HAS(a, "# mote mixing 1\n");
    CHECK_HAS(a, "# command: record 0.05 mix.dat   (mb.mote:12)\n");
    CHECK_HAS(a, "; seed = 5\n");
    const char *cols = "# columns: t nL0 nL1 nR0 nR1 m S_left S_right S_mix cross_lr cross_rl "
                       "dcross_lr dcross_rl flux_lr flux_rl kT_left kT_right E E_kin "
                       "collisions overlaps\n";
    CHECK_HAS(a, cols);
    /* rows: 21 numbers, at t = k 0.05 exactly (the last one at the end, 0.3) */
    int rows = 0, bad_fields = 0, bad_time = 0, bad_counts = 0;
    double e_first = NAN, e_last = NAN, ov_max = 0, ov_last = -1, m_last = NAN;
    for (const char *l = a; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL) {
        if (*l == '#' || *l == '\n')
            continue;
        bad_fields += count_fields(l) != 21;
        double v[21];
        const char *q = l;
        for (int f = 0; f < 21; f++) {
            char *end;
            v[f] = strtod(q, &end);
            q = end;
        }
        double want = rows == 6 ? 0.3 : 0.0 + (double)rows * 0.05;
        bad_time += v[0] != want;
        bad_counts += v[1] + v[2] + v[3] + v[4] != 300;
        bad_counts += fabs(v[5] - (v[3] + v[2]) / 300) > 1e-9;
        if (rows == 0)
            e_first = v[17];
        e_last = v[17];
        ov_max = fmax(ov_max, v[20]);
        ov_last = v[20];
        m_last = v[5];
        rows++;
    }
    CHECK_INT(rows, 7);
    CHECK_INT(bad_fields, 0);
    CHECK_INT(bad_time, 0);
    CHECK_INT(bad_counts, 0);
    /* the run's summary line agrees with the file */
    double drift = value_of(out[0], "run:", "E_rel_drift");
    CHECK(fabs(drift - (e_last - e_first) / fabs(e_first)) < 1e-8 + 1e-3 * fabs(drift),
          "E_rel_drift %g, from the file %g", drift, (e_last - e_first) / fabs(e_first));
    CHECK(value_of(out[0], "run:", "overlaps") >= ov_max, "overlaps below the file's maximum");
    CHECK(value_of(out[0], "run:", "overlaps_end") == ov_last, "overlaps_end");
    CHECK_NEAR(value_of(out[0], "run:", "mixing_fraction"), m_last, 1e-6);
    CHECK(strstr(out[0], "\nN=300 t=0.3 ") != NULL, "status line after the run");
    /* no temporary files left behind, the pictures written */
    DIR *d = opendir(dir[0]);
    int tmp = 0, pngs = 0;
    struct dirent *de;
    while (d && (de = readdir(d))) {
        tmp += strstr(de->d_name, ".tmp") != NULL;
        pngs += strstr(de->d_name, ".png") != NULL;
    }
    if (d)
        closedir(d);
    CHECK_INT(tmp, 0);
    CHECK_INT(pngs, 2);
    snprintf(path, sizeof path, "%s/dens.dat", dir[0]);
    char *dens = read_all(path);
    CHECK(dens && strstr(dens, "# mote mixing-density 1\n") && strstr(dens, "# samples = 7\n"),
          "dens.dat header");
    free(dens);
    free(a);
    free(b);
    free(c);
    for (int k = 0; k < 3; k++)
        free(out[k]);

}

/* A run in which nearly every collision was made elastic by the TC rule says so (file:line),
 * since the loss asked for then hardly acts; a run with a short t_c does not. */
static void test_tc_warning(void)
{
    printf("scripts: the TC-rule warning\n");
    char text[1024], msg[1024];
    char *out = NULL;
    snprintf(text, sizeof text,
             "model mixing-box\nseed 3\noutput_dir %s/tcw\ndisks 1000 1000\nloss 0.5\n"
             "t_c 10\nplace\nrun 3\nt_c 0.00005\nrun 3\n",
             tmpdir);
    int st = run_script("tcw.mote", text, &out, msg, sizeof msg);
    CHECK(st == 0, "status %d: %s", st, msg);
    if (!out)
        return;
    /* the first run: 99% of about 80 000 collisions within 10 s of a disk's previous one */
    const char *w = strstr(out, "tcw.mote:8:1: warning: run: ");
    CHECK(w != NULL, "no warning for the first run:\n%s", out);
    if (w)
        CHECK(strstr(w, "collisions were made elastic by the TC rule (t_c = 10 s)") != NULL,
              "warning text: %.300s", w);
    CHECK(strstr(out, "tcw.mote:10:1: warning") == NULL, "a warning for the second run");
    double share = value_of(out, "run:", "collisions_tc") / value_of(out, "run:", "collisions");
    CHECK(share >= 0.9, "first run: TC share %.3f", share);
    printf("  first run: TC share %.4f, warned; second run (t_c 5e-5): no warning\n", share);
    free(out);
}

int main(void)
{
    if (!test_tmpdir_make(tmpdir, sizeof tmpdir, "mote_test_mb"))
        return 1;
    double w0 = mote_wall_seconds();
    test_rules();
    test_tc();
    test_pair_rule();
    test_wall_rules();
    test_placement();
    test_measures();
    test_runs();
    test_scripts();
    test_tc_warning();
    test_remove_tree(tmpdir);
    printf("test_mixingbox: %.1f s\n", mote_wall_seconds() - w0);
    return test_summary();
}
