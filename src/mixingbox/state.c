/* state.c: the mixing-box state file (`save`, `load`): every number that steers what follows,
 * written exactly (%.17g, which reads back to the same double), so that `A; save F; load F; B`
 * runs bit for bit as `A; B`. That is the placed system (its parameters, positions, velocities,
 * colours, chambers, TC times, time, counters, random stream and seed) and the parameters the
 * script has set for the next run or placement, which may differ from the placed ones until
 * then. Samplers (record, density_y, frames) belong to the script and are not in the file.
 *
 * Reading is strict and names FILE:LINE for every fault; the disk lines are counted as they are
 * read, so a header's N allocates nothing before the disks are there. */
#include "mote/statefile.h"

#include "mb.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

#define MB_SPEED_MAX 1e6 /* m/s; a state with a faster disk is refused */
#define MB_STATE_VERSION 1

/* ---- the descriptor tables (statefile.h) --------------------------------------------------------- */

/* doubles as mote_fmt_exact writes them (the core's exact codec), with "auto" for NaN (t_c:
 * chosen from R and V_init) and "none" for -inf (t_last: no collision yet) where allowed */
static void word_put(char out[64], const void *v)
{
    const double x = *(const double *)v;
    if (isnan(x))
        snprintf(out, 64, "auto");
    else if (isinf(x))
        snprintf(out, 64, "none");
    else
        mote_sf_exact_put(out, v);
}
static size_t auto_get(const char *t, void *v)
{
    if (strncmp(t, "auto", 4) == 0) {
        *(double *)v = NAN;
        return 4;
    }
    return mote_sf_exact_get(t, v);
}
static size_t none_get(const char *t, void *v)
{
    if (strncmp(t, "none", 4) == 0) {
        *(double *)v = -INFINITY;
        return 4;
    }
    return mote_sf_exact_get(t, v);
}
#define EXACT mote_sf_exact
static const mote_sf_codec AUTO = {sizeof(double), word_put, auto_get, NULL};
static const mote_sf_codec NONE = {sizeof(double), word_put, none_get, NULL};

typedef struct {
    uint32_t n;
} mb_head;
static const mote_sf_field HEAD[] = {
    {.key = "n", .name = "N", .type = MOTE_SF_U32, .offset = 0, .lo = 1, .hi = MB_N_MAX},
};

#define MB_U64(K, NAME, M)                                                                   \
    {.key = K, .name = NAME, .type = MOTE_SF_U64, .offset = offsetof(mote_mb, M),            \
     .lo = MOTE_SF_ANY}
static const mote_sf_field SYSTEM[] = {
    {.key = "time", .name = "T", .type = MOTE_SF_CODEC, .offset = offsetof(mote_mb, time),
     .codec = &EXACT},
    MB_U64("counters", "collisions", collisions), MB_U64(NULL, "collisions_tc", collisions_tc),
    MB_U64(NULL, "wall_hits", wall_hits), MB_U64(NULL, "partition_hits", partition_hits),
    MB_U64(NULL, "slit_hits", slit_hits), MB_U64(NULL, "corner_hits", corner_hits),
    MB_U64(NULL, "cross_lr", cross_lr), MB_U64(NULL, "cross_rl", cross_rl),
    MB_U64(NULL, "steps", steps), MB_U64(NULL, "overlaps", overlaps_last),
    {.key = "rng", .name = "s", .type = MOTE_SF_HEX64, .offset = offsetof(mote_mb, rng.s),
     .count = 4},
    MB_U64("seed", "S", seed),
};

/* the parameters, once as placed and once for the next run ("placed x_l 0", "next x_l 0") */
#define MB_P(SET, NAME, C)                                                                   \
    {.key = SET " " #NAME, .name = #NAME, .type = MOTE_SF_CODEC,                             \
     .offset = offsetof(mote_mb_params, NAME), .codec = &C}
#define MB_PARAMS(SET)                                                                       \
    MB_P(SET, x_l, EXACT), MB_P(SET, x_r, EXACT), MB_P(SET, x_b, EXACT), MB_P(SET, x_t, EXACT), \
    MB_P(SET, x1_c, EXACT), MB_P(SET, a, EXACT), MB_P(SET, x2_c, EXACT), MB_P(SET, b, EXACT),   \
    MB_P(SET, r, EXACT), MB_P(SET, v_init, EXACT), MB_P(SET, dv_b, EXACT),                     \
    MB_P(SET, dv_t, EXACT), MB_P(SET, dv_s, EXACT), MB_P(SET, loss, EXACT),                    \
    MB_P(SET, g, EXACT), MB_P(SET, t_c, AUTO), MB_P(SET, mass, EXACT),                         \
    {.key = SET " n_left", .name = "n_left", .type = MOTE_SF_I64,                             \
     .offset = offsetof(mote_mb_params, n_left), .lo = 0, .hi = MB_N_MAX},                   \
    {.key = SET " n_right", .name = "n_right", .type = MOTE_SF_I64,                            \
     .offset = offsetof(mote_mb_params, n_right), .lo = 0, .hi = MB_N_MAX},                  \
    {.key = SET " integrator", .name = "integrator", .type = MOTE_SF_ENUM,                         \
     .offset = offsetof(mote_mb_params, integrator), .words = "timestep|event"},             \
    {.key = SET " collision_rule", .name = "collision_rule", .type = MOTE_SF_ENUM,            \
     .offset = offsetof(mote_mb_params, rule), .words = "restitution|seed"}
static const mote_sf_field PLACED[] = {MB_PARAMS("placed")};
static const mote_sf_field NEXT[] = {MB_PARAMS("next")};

const mote_sf_field *mb_next_fields(size_t *n)
{
    *n = sizeof NEXT / sizeof NEXT[0];
    return NEXT;
}

/* a disk's line */
typedef struct {
    double x, y, vx, vy;
    int colour, side;
    double t_last;
} mb_disk;
#define MB_R(K, NAME, C)                                                                     \
    {.key = K, .name = #NAME, .type = MOTE_SF_CODEC, .offset = offsetof(mb_disk, NAME),       \
     .codec = &C}
static const mote_sf_field ROW[] = {
    MB_R("", x, EXACT), MB_R(NULL, y, EXACT), MB_R(NULL, vx, EXACT), MB_R(NULL, vy, EXACT),
    {.name = "colour", .type = MOTE_SF_INT, .offset = offsetof(mb_disk, colour), .lo = 0, .hi = 1},
    {.name = "side", .type = MOTE_SF_INT, .offset = offsetof(mb_disk, side), .lo = 0, .hi = 1},
    MB_R(NULL, t_last, NONE),
};
#define COUNT(t) (sizeof t / sizeof t[0])

int mb_save(const mote_mb *sys, const mote_mb_params *next, const char *path, mote_err *err)
{
    if (!sys->placed)
        return mote_fail(err, MOTE_EINVAL, "save: no disks are placed yet");
    for (uint32_t i = 0; i < sys->n; i++) /* never a state that load refuses */
        if (!isfinite(sys->x[i]) || !isfinite(sys->y[i]) ||
            !(fabs(sys->vx[i]) <= MB_SPEED_MAX && fabs(sys->vy[i]) <= MB_SPEED_MAX))
            return mote_fail(err, MOTE_ERUNTIME, "save: disk %u is at (%g, %g) with velocity "
                             "(%g, %g) m/s: not a state mote can continue (finite, speeds up to "
                             "%g m/s); %s is left as it was", i, sys->x[i], sys->y[i],
                             sys->vx[i], sys->vy[i], MB_SPEED_MAX, path);
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc)
        return rc;
    FILE *f = af.f;
    mote_sf_write_head(f, "mixing-box", MB_STATE_VERSION);
    mb_head h = {sys->n};
    mote_sf_write(f, HEAD, COUNT(HEAD), &h, MB_STATE_VERSION);
    mote_sf_write(f, SYSTEM, COUNT(SYSTEM), sys, MB_STATE_VERSION);
    mote_sf_write(f, PLACED, COUNT(PLACED), &sys->p, MB_STATE_VERSION);
    mote_sf_write(f, NEXT, COUNT(NEXT), next, MB_STATE_VERSION);
    fprintf(f, "disks x y vx vy colour side t_last\n");
    for (uint32_t i = 0; i < sys->n; i++) {
        mb_disk r = {sys->x[i], sys->y[i], sys->vx[i], sys->vy[i], sys->colour[i], sys->side[i],
                    sys->t_last[i]};
        mote_sf_write(f, ROW, COUNT(ROW), &r, MB_STATE_VERSION);
    }
    fprintf(f, "end\n");
    return mote_afile_commit(&af, err);
}

/* ---- reading ------------------------------------------------------------------------------ */

static int fail(const mote_lines *l, mote_err *err, const char *what, const char *found)
{
    return mote_fail(err, MOTE_EINVAL, "%s:%ld: %s%s%s%s", l->path, l->line, what,
                     found ? " (found '" : "", found ? found : "", found ? "')" : "");
}

/* The head up to and including "n N". */
static int read_head(mote_lines *l, uint32_t *n, mote_err *err)
{
    int version;
    mb_head h = {0};
    int rc = mote_sf_read_head(l, "mixing-box", MB_STATE_VERSION, &version, err);
    if (!rc)
        rc = mote_sf_read(l, HEAD, COUNT(HEAD), &h, version, err);
    *n = h.n;
    return rc;
}

int mb_peek(const char *path, uint64_t *n, mote_err *err)
{
    mote_lines l;
    int rc = mote_lines_open(&l, path, err);
    if (rc)
        return rc;
    uint32_t n32 = 0;
    rc = read_head(&l, &n32, err);
    *n = n32;
    int crc = mote_lines_close(&l, err);
    return crc ? crc : rc;
}

/* Grow the disk arrays of s to hold at least `want` disks. */
static int grow(mote_mb *s, size_t *cap, size_t want)
{
    if (want <= *cap)
        return 0;
    size_t c = *cap ? 2 * *cap : 1024;
    while (c < want)
        c *= 2;
    void *p[7] = {realloc(s->x, c * sizeof *s->x), NULL};
    if (p[0])
        s->x = p[0];
    if ((p[1] = realloc(s->y, c * sizeof *s->y)))
        s->y = p[1];
    if ((p[2] = realloc(s->vx, c * sizeof *s->vx)))
        s->vx = p[2];
    if ((p[3] = realloc(s->vy, c * sizeof *s->vy)))
        s->vy = p[3];
    if ((p[4] = realloc(s->t_last, c * sizeof *s->t_last)))
        s->t_last = p[4];
    if ((p[5] = realloc(s->colour, c * sizeof *s->colour)))
        s->colour = p[5];
    if ((p[6] = realloc(s->side, c * sizeof *s->side)))
        s->side = p[6];
    for (int k = 0; k < 7; k++)
        if (!p[k])
            return -1;
    *cap = c;
    return 0;
}

static int read_state(mote_lines *l, mote_mb *s, mote_mb_params *next_p, mote_err *err)
{
    uint32_t n;
    int rc = read_head(l, &n, err);
    if (!rc)
        rc = mote_sf_read(l, SYSTEM, COUNT(SYSTEM), s, MB_STATE_VERSION, err);
    if (!rc && !(s->rng.s[0] | s->rng.s[1] | s->rng.s[2] | s->rng.s[3]))
        rc = fail(l, err, "the random stream's state must not be all zero", NULL);
    if (!rc)
        rc = mote_sf_read(l, PLACED, COUNT(PLACED), &s->p, MB_STATE_VERSION, err);
    if (!rc)
        rc = mote_sf_read(l, NEXT, COUNT(NEXT), next_p, MB_STATE_VERSION, err);
    if (rc)
        return rc;
    mote_err perr = {0};
    if (mote_mb_params_check(&s->p, &perr) ||
        (uint64_t)s->p.n_left + (uint64_t)s->p.n_right != n)
        return fail(l, err, perr.code ? perr.msg : "placed n_left + n_right must equal n", NULL);
    if (mote_mb_params_check(next_p, &perr))
        return fail(l, err, perr.msg, NULL);
    const char *line = mote_lines_next(l);
    if (!line || strcmp(line, "disks x y vx vy colour side t_last") != 0)
        return fail(l, err, "expected 'disks x y vx vy colour side t_last'",
                    line ? line : "end of file");
    size_t cap = 0;
    const mote_mb_params *p = &s->p;
    for (uint32_t i = 0; i < n; i++) {
        if (!(line = mote_lines_next(l))) {
            l->line++;
            return fail(l, err, "file ends early: fewer disk lines than n (truncated file?)",
                        NULL);
        }
        if (grow(s, &cap, (size_t)i + 1))
            return mote_fail(err, MOTE_ENOMEM, "%s: out of memory for %" PRIu32 " disks", l->path,
                             n);
        mb_disk r;
        if ((rc = mote_sf_parse_line(l, line, ROW, COUNT(ROW), &r, MB_STATE_VERSION, err)))
            return rc;
        if (!(r.x >= p->x_l && r.x <= p->x_r && r.y >= p->x_b && r.y <= p->x_t))
            return fail(l, err, "the disk's centre is outside the box", NULL);
        if (!(fabs(r.vx) <= MB_SPEED_MAX && fabs(r.vy) <= MB_SPEED_MAX))
            return fail(l, err, "a velocity component above 10^6 m/s (the event integrator would "
                                "need billions of events per simulated second)", NULL);
        if (!(r.t_last <= s->time))
            return fail(l, err, "t_last is after the state's time", NULL);
        s->x[i] = r.x;
        s->y[i] = r.y;
        s->vx[i] = r.vx;
        s->vy[i] = r.vy;
        s->t_last[i] = r.t_last;
        s->colour[i] = r.colour;
        s->side[i] = (uint8_t)r.side;
        s->n = i + 1;
    }
    if (!(line = mote_lines_next(l))) {
        l->line++;
        return fail(l, err, "file ends early: expected 'end' after the disks (truncated file?)",
                    NULL);
    }
    const char *t = line + strspn(line, " \t");
    if (strncmp(t, "end", 3) != 0 || t[3 + strspn(t + 3, " \t")] != '\0')
        return fail(l, err, "expected 'end' after the n disk lines", line);
    while ((line = mote_lines_next(l)))
        if (line[strspn(line, " \t")])
            return fail(l, err, "unexpected text after 'end'", line);
    return 0;
}

int mb_load(mote_mb *sys, mote_mb_params *next_p, const char *path, mote_err *err)
{
    mote_lines l;
    int rc = mote_lines_open(&l, path, err);
    if (rc)
        return rc;
    mote_mb fresh;
    mote_mb_init(&fresh);
    mote_mb_params np = *next_p;
    rc = read_state(&l, &fresh, &np, err);
    int crc = mote_lines_close(&l, err);
    rc = crc ? crc : rc;
    if (rc) {
        mote_mb_free(&fresh);
        return rc;
    }
    fresh.placed = 1;
    fresh.generation = sys->generation + 1;
    mote_mb_free(sys);
    *sys = fresh;
    *next_p = np;
    return MOTE_OK;
}
