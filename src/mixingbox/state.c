/* state.c: the mixing-box state file (`save`, `load`): every number that steers what follows,
 * written exactly (%.17g, which reads back to the same double), so that `A; save F; load F; B`
 * runs bit for bit as `A; B`. That is the placed system (its parameters, positions, velocities,
 * colours, chambers, TC times, time, counters, random stream and seed) and the parameters the
 * script has set for the next run or placement, which may differ from the placed ones until
 * then. Samplers (record, density_y, frames) belong to the script and are not in the file.
 *
 * Reading is strict and names FILE:LINE for every fault; the disk lines are counted as they are
 * read, so a header's N allocates nothing before the disks are there. */
#include "mb.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

#define FORMAT_LINE "mote-state 1"
#define MB_SPEED_MAX 1e6 /* m/s; a state with a faster disk is refused */
#define MODEL_LINE "model mixing-box"

/* The real-valued parameters, by the names of the state file. */
static const struct {
    const char *key;
    size_t off;
} REALS[] = {
    {"x_l", offsetof(mote_mb_params, x_l)},       {"x_r", offsetof(mote_mb_params, x_r)},
    {"x_b", offsetof(mote_mb_params, x_b)},       {"x_t", offsetof(mote_mb_params, x_t)},
    {"x1_c", offsetof(mote_mb_params, x1_c)},     {"a", offsetof(mote_mb_params, a)},
    {"x2_c", offsetof(mote_mb_params, x2_c)},     {"b", offsetof(mote_mb_params, b)},
    {"r", offsetof(mote_mb_params, r)},           {"v_init", offsetof(mote_mb_params, v_init)},
    {"dv_b", offsetof(mote_mb_params, dv_b)},     {"dv_t", offsetof(mote_mb_params, dv_t)},
    {"dv_s", offsetof(mote_mb_params, dv_s)},     {"loss", offsetof(mote_mb_params, loss)},
    {"g", offsetof(mote_mb_params, g)},           {"t_c", offsetof(mote_mb_params, t_c)},
    {"mass", offsetof(mote_mb_params, mass)},
};
#define NREALS (sizeof REALS / sizeof REALS[0])
/* after the reals: n_left, n_right, integrator, collision_rule */
#define NPARAMS (NREALS + 4)

static double *real_field(mote_mb_params *p, size_t k) { return (double *)((char *)p + REALS[k].off); }

static void fmt(char b[32], double x)
{
    if (isnan(x))
        snprintf(b, 32, "auto"); /* t_c: chosen from R and V_init */
    else if (isinf(x))
        snprintf(b, 32, "none"); /* t_last: no collision yet */
    else
        mote_fmt_exact(b, x);
}

static void write_params(FILE *f, const char *set, const mote_mb_params *p)
{
    char b[32];
    for (size_t k = 0; k < NREALS; k++) {
        fmt(b, *real_field((mote_mb_params *)p, k));
        fprintf(f, "%s %s %s\n", set, REALS[k].key, b);
    }
    fprintf(f, "%s n_left %" PRId64 "\n%s n_right %" PRId64 "\n", set, p->n_left, set,
            p->n_right);
    fprintf(f, "%s integrator %s\n%s collision_rule %s\n", set,
            p->integrator == MOTE_MB_EVENT ? "event" : "timestep", set,
            p->rule == MOTE_MB_SEEDRULE ? "seed" : "restitution");
}

int mb_save(const mote_mb *sys, const mote_mb_params *next, const char *path, mote_err *err)
{
    if (!sys->placed)
        return mote_fail(err, MOTE_EINVAL, "save: no disks are placed yet");
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc)
        return rc;
    FILE *f = af.f;
    char b[7][32];
    fmt(b[0], sys->time);
    fprintf(f, FORMAT_LINE "\n" MODEL_LINE "\nn %" PRIu32 "\ntime %s\n", sys->n, b[0]);
    fprintf(f,
            "counters %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64
            " %" PRIu64 " %" PRIu64 " %" PRIu64 " %" PRIu64 "\n",
            sys->collisions, sys->collisions_tc, sys->wall_hits, sys->partition_hits,
            sys->slit_hits, sys->corner_hits, sys->cross_lr, sys->cross_rl, sys->steps,
            sys->overlaps_last);
    fprintf(f, "rng %016" PRIx64 " %016" PRIx64 " %016" PRIx64 " %016" PRIx64 "\nseed %" PRIu64 "\n",
            sys->rng.s[0], sys->rng.s[1], sys->rng.s[2], sys->rng.s[3], sys->seed);
    write_params(f, "placed", &sys->p);
    write_params(f, "next", next);
    fprintf(f, "disks x y vx vy colour side t_last\n");
    for (uint32_t i = 0; i < sys->n; i++) {
        fmt(b[0], sys->x[i]);
        fmt(b[1], sys->y[i]);
        fmt(b[2], sys->vx[i]);
        fmt(b[3], sys->vy[i]);
        fmt(b[4], sys->t_last[i]);
        fprintf(f, "%s %s %s %s %d %d %s\n", b[0], b[1], b[2], b[3], sys->colour[i],
                sys->side[i], b[4]);
    }
    fprintf(f, "end\n");
    return mote_afile_commit(&af, err);
}

/* ---- reading ------------------------------------------------------------------------------ */

typedef struct {
    FILE *f;
    const char *path;
    long line;
    char *buf;
    size_t cap;
    char *tok[12];
    int ntok;
} reader;

/* The next line split into tokens; 0 at the end of the file. */
static int next(reader *r)
{
    size_t n;
    int got = mote_read_line(&r->buf, &r->cap, &n, r->f, MOTE_LINE_MAX);
    if (got == 0)
        return 0;
    r->line++;
    if (got < 0) /* too long (or out of memory): a line no parse accepts */
        return r->ntok = -2, 1;
    r->ntok = 0;
    char *save = NULL;
    for (char *t = strtok_r(r->buf, " \t\r\n", &save); t; t = strtok_r(NULL, " \t\r\n", &save)) {
        if (r->ntok == (int)(sizeof r->tok / sizeof r->tok[0]))
            return r->ntok = -1, 1; /* too many */
        r->tok[r->ntok++] = t;
    }
    return 1;
}

static int fail(const reader *r, mote_err *err, const char *fmt_, const char *what)
{
    if (r->ntok == -2) /* the line was not read at all: that is the error */
        return mote_fail(err, MOTE_EFORMAT, "%s:%ld: line longer than 1 MiB (not a text file?)",
                         r->path, r->line);
    return mote_fail(err, MOTE_EINVAL, "%s:%ld: %s%s%s%s", r->path, r->line, fmt_,
                     what ? " (found '" : "", what ? what : "", what ? "')" : "");
}

/* A line "KEY v1 ... vn" with exactly n values; 0 or an error. */
static int expect(reader *r, const char *key, int n, const char *what, mote_err *err)
{
    if (!next(r)) {
        r->line++;
        return fail(r, err, what, "end of file");
    }
    if (r->ntok != n + 1 || strcmp(r->tok[0], key) != 0)
        return fail(r, err, what, r->ntok > 0 ? r->tok[0] : "");
    return 0;
}

static int real(const reader *r, const char *s, double *x, int special, mote_err *err)
{
    if (special && strcmp(s, special == 1 ? "auto" : "none") == 0) {
        *x = special == 1 ? NAN : -INFINITY;
        return 0;
    }
    char *end;
    errno = 0;
    *x = strtod(s, &end);
    if (end == s || *end || errno == ERANGE || !isfinite(*x) || strchr(s, 'x') || strchr(s, 'X'))
        return fail(r, err, "expected a finite decimal number", s);
    return 0;
}

static int u64(const reader *r, const char *s, uint64_t *x, int base, mote_err *err)
{
    char *end;
    errno = 0;
    if (*s == '-' || *s == '+')
        return fail(r, err, "expected an unsigned integer", s);
    unsigned long long v = strtoull(s, &end, base);
    if (end == s || *end || errno == ERANGE)
        return fail(r, err, base == 16 ? "expected a 64-bit hexadecimal word"
                                       : "expected an unsigned integer",
                    s);
    *x = v;
    return 0;
}

static int read_params(reader *r, const char *set, mote_mb_params *p, mote_err *err)
{
    char what[96];
    for (size_t k = 0; k < NPARAMS; k++) {
        const char *key = k < NREALS                ? REALS[k].key
                          : k == NREALS             ? "n_left"
                          : k == NREALS + 1         ? "n_right"
                          : k == NREALS + 2         ? "integrator"
                                                    : "collision_rule";
        snprintf(what, sizeof what, "expected '%s %s VALUE'", set, key);
        int rc = expect(r, set, 2, what, err);
        if (!rc && strcmp(r->tok[1], key) != 0)
            rc = fail(r, err, what, r->tok[1]);
        if (rc)
            return rc;
        const char *v = r->tok[2];
        if (k < NREALS) {
            rc = real(r, v, real_field(p, k), strcmp(key, "t_c") == 0, err);
        } else if (k < NREALS + 2) {
            uint64_t u;
            rc = u64(r, v, &u, 10, err);
            if (!rc && u > MB_N_MAX)
                rc = fail(r, err, "a disk count must be at most 10^7", v);
            if (!rc)
                *(k == NREALS ? &p->n_left : &p->n_right) = (int64_t)u;
        } else if (k == NREALS + 2) {
            if (strcmp(v, "event") && strcmp(v, "timestep"))
                rc = fail(r, err, "expected integrator event or timestep", v);
            p->integrator = strcmp(v, "event") == 0 ? MOTE_MB_EVENT : MOTE_MB_TIMESTEP;
        } else {
            if (strcmp(v, "restitution") && strcmp(v, "seed"))
                rc = fail(r, err, "expected collision_rule restitution or seed", v);
            p->rule = strcmp(v, "seed") == 0 ? MOTE_MB_SEEDRULE : MOTE_MB_RESTITUTION;
        }
        if (rc)
            return rc;
    }
    return 0;
}

/* The header up to and including "n N". */
static int read_head(reader *r, uint64_t *n, mote_err *err)
{
    if (!next(r) || r->ntok != 2 || strcmp(r->tok[0], "mote-state") != 0)
        return fail(r, err, "not a mote state file: expected '" FORMAT_LINE "' on the first line",
                    NULL);
    if (strcmp(r->tok[1], "1") != 0)
        return fail(r, err, "unsupported state format version (this mote reads 1)", r->tok[1]);
    int rc = expect(r, "model", 1, "expected '" MODEL_LINE "'", err);
    if (!rc && strcmp(r->tok[1], "mixing-box") != 0)
        return fail(r, err, "this is a state of another model; the mixing box loads only "
                            "'" MODEL_LINE "'",
                    r->tok[1]);
    if (!rc)
        rc = expect(r, "n", 1, "expected 'n N'", err);
    if (!rc)
        rc = u64(r, r->tok[1], n, 10, err);
    if (!rc && (*n < 1 || *n > MB_N_MAX))
        rc = fail(r, err, "N must be in 1 ... 10^7", r->tok[1]);
    return rc;
}

static int open_reader(reader *r, const char *path, mote_err *err)
{
    memset(r, 0, sizeof *r);
    r->path = path;
    r->f = fopen(path, "r");
    if (!r->f)
        return mote_fail(err, MOTE_EIO, "cannot open state file '%s': %s", path, strerror(errno));
    return 0;
}

static void close_reader(reader *r)
{
    if (r->f)
        fclose(r->f);
    free(r->buf);
}

int mb_peek(const char *path, uint64_t *n, mote_err *err)
{
    reader r;
    int rc = open_reader(&r, path, err);
    if (!rc)
        rc = read_head(&r, n, err);
    close_reader(&r);
    return rc;
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

static int read_state(reader *r, mote_mb *s, mote_mb_params *next_p, mote_err *err)
{
    uint64_t n, w[10];
    int rc = read_head(r, &n, err);
    if (!rc)
        rc = expect(r, "time", 1, "expected 'time T'", err);
    if (!rc)
        rc = real(r, r->tok[1], &s->time, 0, err);
    if (!rc)
        rc = expect(r, "counters", 10, "expected 'counters' and 10 counts", err);
    for (int k = 0; !rc && k < 10; k++)
        rc = u64(r, r->tok[k + 1], &w[k], 10, err);
    if (rc)
        return rc;
    s->collisions = w[0];
    s->collisions_tc = w[1];
    s->wall_hits = w[2];
    s->partition_hits = w[3];
    s->slit_hits = w[4];
    s->corner_hits = w[5];
    s->cross_lr = w[6];
    s->cross_rl = w[7];
    s->steps = w[8];
    s->overlaps_last = w[9];
    rc = expect(r, "rng", 4, "expected 'rng' and four 64-bit hexadecimal words", err);
    for (int k = 0; !rc && k < 4; k++)
        rc = u64(r, r->tok[k + 1], &s->rng.s[k], 16, err);
    if (!rc && !(s->rng.s[0] | s->rng.s[1] | s->rng.s[2] | s->rng.s[3]))
        rc = fail(r, err, "the random stream's state must not be all zero", NULL);
    if (!rc)
        rc = expect(r, "seed", 1, "expected 'seed S'", err);
    if (!rc)
        rc = u64(r, r->tok[1], &s->seed, 10, err);
    if (!rc)
        rc = read_params(r, "placed", &s->p, err);
    if (!rc)
        rc = read_params(r, "next", next_p, err);
    if (rc)
        return rc;
    mote_err perr = {0};
    if (mote_mb_params_check(&s->p, &perr) ||
        (uint64_t)s->p.n_left + (uint64_t)s->p.n_right != n)
        return fail(r, err, perr.code ? perr.msg : "placed n_left + n_right must equal n", NULL);
    if (mote_mb_params_check(next_p, &perr))
        return fail(r, err, perr.msg, NULL);
    rc = expect(r, "disks", 7, "expected 'disks x y vx vy colour side t_last'", err);
    if (rc)
        return rc;
    size_t cap = 0;
    const mote_mb_params *p = &s->p;
    for (uint64_t i = 0; i < n; i++) {
        if (!next(r)) {
            r->line++;
            return fail(r, err, "file ends early: fewer disk lines than n (truncated file?)",
                        NULL);
        }
        if (r->ntok != 7)
            return fail(r, err, "expected 7 numbers: x y vx vy colour side t_last",
                        r->ntok > 0 ? r->tok[0] : "");
        if (grow(s, &cap, i + 1))
            return mote_fail(err, MOTE_ENOMEM, "%s: out of memory for %" PRIu64 " disks", r->path,
                             n);
        double v[5];
        for (int k = 0; k < 5 && !rc; k++)
            rc = real(r, r->tok[k < 4 ? k : 6], &v[k], k == 4 ? 2 : 0, err);
        if (rc)
            return rc;
        if (!(v[0] >= p->x_l && v[0] <= p->x_r && v[1] >= p->x_b && v[1] <= p->x_t))
            return fail(r, err, "the disk's centre is outside the box", r->tok[0]);
        if (!(fabs(v[2]) <= MB_SPEED_MAX && fabs(v[3]) <= MB_SPEED_MAX))
            return fail(r, err, "a velocity component above 10^6 m/s (the event integrator would "
                                "need billions of events per simulated second)",
                        r->tok[fabs(v[2]) > MB_SPEED_MAX ? 2 : 3]);
        if (!(v[4] <= s->time))
            return fail(r, err, "t_last is after the state's time", r->tok[6]);
        int colour = r->tok[4][0] - '0', side = r->tok[5][0] - '0';
        if (r->tok[4][1] || (colour != 0 && colour != 1))
            return fail(r, err, "colour must be 0 or 1", r->tok[4]);
        if (r->tok[5][1] || (side != 0 && side != 1))
            return fail(r, err, "side must be 0 or 1", r->tok[5]);
        s->x[i] = v[0];
        s->y[i] = v[1];
        s->vx[i] = v[2];
        s->vy[i] = v[3];
        s->t_last[i] = v[4];
        s->colour[i] = colour;
        s->side[i] = (uint8_t)side;
        s->n = (uint32_t)(i + 1);
    }
    if (!next(r)) {
        r->line++;
        return fail(r, err, "file ends early: expected 'end' after the disks (truncated file?)",
                    NULL);
    }
    if (r->ntok != 1 || strcmp(r->tok[0], "end") != 0)
        return fail(r, err, "expected 'end' after the n disk lines", r->ntok > 0 ? r->tok[0] : "");
    while (next(r))
        if (r->ntok != 0)
            return fail(r, err, "unexpected text after 'end'", r->ntok > 0 ? r->tok[0] : "");
    return 0;
}

int mb_load(mote_mb *sys, mote_mb_params *next_p, const char *path, mote_err *err)
{
    reader r;
    int rc = open_reader(&r, path, err);
    if (rc)
        return rc;
    mote_mb fresh;
    mote_mb_init(&fresh);
    mote_mb_params np = *next_p;
    rc = read_state(&r, &fresh, &np, err);
    if (!rc && ferror(r.f))
        rc = mote_fail(err, MOTE_EIO, "%s: read error", path);
    close_reader(&r);
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
