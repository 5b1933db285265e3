/* test_files.c: state files and atomic output (spec 9).
 *
 * - save -> load -> save is byte-identical (slit, bulk, 2D, polydisperse) and the file has the
 *   layout of 9.1; a run continued from a saved state is bit-identical to the uninterrupted run,
 *   including the random stream;
 * - load errors name the file and line: missing file, truncated file, missing `end`, malformed
 *   numbers, wrong particle count, overlaps (naming both particles and lines), particles outside
 *   the walls, a periodic length too small, bad version; after a failed load the previous system
 *   is intact;
 * - import of the original program's format (9.2, 10 item 18): images skipped, coordinates
 *   wrapped, a cross-face overlap repaired and reported, the random stream untouched, a wrong
 *   record index named by line;
 * - atomic writes (9.4): a save into a missing directory or onto a directory fails and leaves
 *   nothing; a write that runs out of file space keeps the earlier file; abort and commit of
 *   mote_afile;
 * - H5MD (h5md.h): the first frame replaces an earlier file only when complete (out of file
 *   space: the earlier file kept); a frame that fails to append (one of another dimension, one
 *   that runs out of file space) is cut off again: the file keeps its frames, and the next good
 *   frame follows them; appending to a file that is not HDF5 names it. */
#include "mote/hardspheres.h"
#include "mote/h5md.h"

#include <hdf5.h>

#include <dirent.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test.h"

static char tmpdir[256];

static void tmp_path(char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "%s/%s", tmpdir, name);
}

/* Whole file into a NUL-terminated buffer (NULL if unreadable). */
static char *read_text(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 4096, n = 0;
    char *buf = malloc(cap);
    size_t got;
    while ((got = fread(buf + n, 1, cap - n - 1, f)) > 0) {
        n += got;
        if (cap - n < 2) {
            cap *= 2;
            buf = realloc(buf, cap);
        }
    }
    fclose(f);
    buf[n] = '\0';
    if (len)
        *len = n;
    return buf;
}

static void write_text(const char *path, const char *text, size_t len)
{
    FILE *f = fopen(path, "wb");
    if (f) {
        fwrite(text, 1, len, f);
        fclose(f);
    }
}

static int files_equal(const char *a, const char *b)
{
    size_t la = 0, lb = 0;
    char *x = read_text(a, &la), *y = read_text(b, &lb);
    int eq = x && y && la == lb && memcmp(x, y, la) == 0;
    free(x);
    free(y);
    return eq;
}

static int count_entries(void)
{
    DIR *d = opendir(tmpdir);
    if (!d)
        return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    closedir(d);
    return n;
}

/* Lines of a text (the buffer is modified: LFs become NULs). */
typedef struct {
    char **line;
    int n;
} lines;

static lines split_lines(char *text)
{
    lines L = {NULL, 0};
    int cap = 0;
    char *p = text;
    while (*p) {
        if (L.n == cap) {
            cap = cap ? 2 * cap : 64;
            L.line = realloc(L.line, (size_t)cap * sizeof *L.line);
        }
        L.line[L.n++] = p;
        char *nl = strchr(p, '\n');
        if (!nl)
            break;
        *nl = '\0';
        p = nl + 1;
    }
    return L;
}

/* Write lines [0, n) of `base` to path, with line `which` (0-based) replaced by `repl` (NULL: no
 * replacement; "" deletes nothing but writes an empty line). */
static void write_variant(const char *path, const lines *base, int n, int which, const char *repl)
{
    FILE *f = fopen(path, "wb");
    for (int k = 0; k < n && k < base->n; k++)
        fprintf(f, "%s\n", k == which && repl ? repl : base->line[k]);
    fclose(f);
}

static int same_state(const mote_ev *a, const mote_ev *b)
{
    return a->n == b->n && memcmp(a->p, b->p, a->n * sizeof *a->p) == 0 &&
           memcmp(a->pc, b->pc, a->n * sizeof *a->pc) == 0 &&
           memcmp(a->heap, b->heap, a->n * sizeof *a->heap) == 0 && a->clock == b->clock &&
           a->time_total == b->time_total && a->collisions == b->collisions &&
           a->wall_collisions == b->wall_collisions &&
           memcmp(a->len, b->len, sizeof a->len) == 0;
}

/* ---- round trips --------------------------------------------------------------------------------- */

/* exact: the loaded state must equal the saved one bit for bit (not so when a velocity was -0,
 * which the file writes as 0, spec 9.1). */
static void round_trip(mote_hs *hs, const char *label, int exact)
{
    mote_err err = {0};
    char f1[512], f2[512], f3[512];
    tmp_path(f1, sizeof f1, "rt1.state");
    tmp_path(f2, sizeof f2, "rt2.state");
    tmp_path(f3, sizeof f3, "rt3.state");
    CHECK(mote_hs_save(hs, f1, &err) == MOTE_OK, "%s: save: %s", label, err.msg);
    mote_hs b;
    mote_hs_init(&b, NULL);
    CHECK(mote_hs_load(&b, f1, &err) == MOTE_OK, "%s: load: %s", label, err.msg);
    CHECK(mote_hs_save(&b, f2, &err) == MOTE_OK, "%s: save 2: %s", label, err.msg);
    CHECK(files_equal(f1, f2), "%s: save -> load -> save is not byte-identical", label);
    /* the loaded state is the saved one (save synchronised the original) */
    CHECK(!exact || same_state(&hs->ev, &b.ev), "%s: loaded state differs from the saved one",
          label);
    CHECK(b.geometry == hs->geometry && memcmp(b.rng.s, hs->rng.s, sizeof b.rng.s) == 0,
          "%s: geometry or random stream not restored", label);
    CHECK(mote_ev_check(&b.ev, &err) == MOTE_OK, "%s: %s", label, err.msg);

    /* layout of spec 9.1 */
    size_t len;
    char *text = read_text(f1, &len);
    lines L = split_lines(text);
    int d = hs->ev.dim;
    char want[256];
    CHECK(L.n == 12 + (int)hs->ev.n, "%s: %d lines, expected 12 + N", label, L.n);
    CHECK(L.n > 11 && strcmp(L.line[0], "mote-state 1") == 0 &&
              strcmp(L.line[1], "model hard-spheres") == 0 &&
              strncmp(L.line[4], "box ", 4) == 0 && strncmp(L.line[6], "time ", 5) == 0 &&
              strncmp(L.line[7], "collisions ", 11) == 0 &&
              strncmp(L.line[8], "wall_collisions ", 16) == 0 &&
              strncmp(L.line[9], "rng ", 4) == 0 && strcmp(L.line[L.n - 1], "end") == 0,
          "%s: the header is not the layout of spec 9.1", label);
    snprintf(want, sizeof want, "dim %d", d);
    CHECK(L.n > 2 && strcmp(L.line[2], want) == 0, "%s: line 3 '%s'", label, L.line[2]);
    snprintf(want, sizeof want, "geometry %s", hs->geometry == MOTE_HS_SLIT ? "slit" : "periodic");
    CHECK(L.n > 3 && strcmp(L.line[3], want) == 0, "%s: line 4 '%s'", label, L.line[3]);
    snprintf(want, sizeof want, "n %u", hs->ev.n);
    CHECK(L.n > 5 && strcmp(L.line[5], want) == 0, "%s: line 6 '%s'", label, L.line[5]);
    snprintf(want, sizeof want, "rng %016llx %016llx %016llx %016llx",
             (unsigned long long)hs->rng.s[0], (unsigned long long)hs->rng.s[1],
             (unsigned long long)hs->rng.s[2], (unsigned long long)hs->rng.s[3]);
    CHECK(L.n > 9 && strcmp(L.line[9], want) == 0, "%s: line 10 '%s', expected '%s'", label,
          L.line[9], want);
    CHECK(L.n > 10 && strcmp(L.line[10], d == 3 ? "particles x y z vx vy vz radius mass"
                                                : "particles x y vx vy radius mass") == 0,
          "%s: line 11 '%s'", label, L.line[10]);
    int fields_ok = 1, negzero = 0;
    for (int k = 11; k < L.n - 1; k++) {
        int nf = 0;
        for (char *p = L.line[k]; *p;) {
            while (*p == ' ')
                p++;
            if (!*p)
                break;
            nf++;
            if (strncmp(p, "-0 ", 3) == 0 || strcmp(p, "-0") == 0)
                negzero = 1;
            while (*p && *p != ' ')
                p++;
        }
        fields_ok &= nf == 2 * d + 2 && !strchr(L.line[k], '\r') && !strstr(L.line[k], "  ");
    }
    CHECK(fields_ok, "%s: particle lines are not 2d+2 fields separated by one space", label);
    CHECK(!negzero, "%s: negative zero written as -0", label);
    free(L.line);
    free(text);

    /* load -> save once more: still identical */
    mote_hs c;
    mote_hs_init(&c, NULL);
    CHECK(mote_hs_load(&c, f2, &err) == MOTE_OK && mote_hs_save(&c, f3, &err) == MOTE_OK, "%s",
          err.msg);
    CHECK(files_equal(f1, f3), "%s: a second round trip is not byte-identical", label);
    mote_hs_free(&b);
    mote_hs_free(&c);
}

static void test_round_trips(void)
{
    printf("save -> load -> save (spec 9.1)\n");
    mote_err err = {0};
    mote_hs hs;

    mote_hs_init(&hs, NULL);
    mote_hs_seed(&hs, test_seed(17));
    mote_hs_new(&hs, 3, 0.45, &err);
    round_trip(&hs, "fresh slit", 1);
    mote_hs_step(&hs, 37, &err);
    round_trip(&hs, "slit after step", 1);
    hs.ev.p[3].v[1] = -0.0; /* a negative zero must be written as 0 */
    mote_ev_set_reference(&hs.ev);
    round_trip(&hs, "slit after step, with a -0 velocity", 0);
    mote_hs_free(&hs);

    mote_hs_init(&hs, NULL);
    mote_hs_bulk(&hs, 256, 0.5, &err);
    mote_hs_step(&hs, 20, &err);
    round_trip(&hs, "bulk", 1);
    mote_hs_free(&hs);

    mote_hs_init(&hs, NULL);
    mote_hs_new_disks(&hs, 6, 8, 0.6, &err);
    mote_hs_step(&hs, 20, &err);
    round_trip(&hs, "new_disks", 1);
    mote_hs_free(&hs);

    mote_hs_init(&hs, NULL);
    mote_hs_bulk_disks(&hs, 64, 0.6, &err);
    mote_hs_step(&hs, 20, &err);
    round_trip(&hs, "bulk_disks", 1);
    mote_hs_free(&hs);

    /* Polydisperse: a state file with radii 0.8 and masses 2.5 on every third sphere (smaller
     * spheres cannot overlap). It loads, survives round trips and runs with every invariant
     * (the unequal-mass collision rule) intact. */
    {
        char base[512], poly[512];
        tmp_path(base, sizeof base, "mono.state");
        tmp_path(poly, sizeof poly, "poly.state");
        mote_hs_init(&hs, NULL);
        mote_hs_new(&hs, 2, 0.4, &err);
        mote_hs_step(&hs, 10, &err);
        mote_hs_save(&hs, base, &err);
        mote_hs_free(&hs);
        char *text = read_text(base, NULL);
        lines L = split_lines(text);
        FILE *f = fopen(poly, "wb");
        for (int k = 0; k < L.n; k++) {
            int i = k - 11;
            if (i >= 0 && k < L.n - 1 && i % 3 == 0) {
                /* replace the last two fields */
                char *line = L.line[k], *p = line + strlen(line);
                for (int sp = 0; sp < 2; p--)
                    if (p[-1] == ' ')
                        sp++;
                *p = '\0';
                fprintf(f, "%s 0.8 2.5\n", line);
            } else {
                fprintf(f, "%s\n", L.line[k]);
            }
        }
        fclose(f);
        free(L.line);
        free(text);
        mote_hs_init(&hs, NULL);
        CHECK(mote_hs_load(&hs, poly, &err) == MOTE_OK, "polydisperse load: %s", err.msg);
        /* by particle number (the file's order); the engine's records are in spatial order */
        const uint32_t s0 = mote_ev_slot(&hs.ev, 0), s1 = mote_ev_slot(&hs.ev, 1),
                       s3 = mote_ev_slot(&hs.ev, 3);
        CHECK(hs.ev.radius && hs.ev.mass && hs.ev.radius[s0] == 0.8 && hs.ev.mass[s3] == 2.5 &&
                  hs.ev.radius[s1] == 1.0 && hs.ev.mass[s1] == 1.0,
              "polydisperse radii and masses not loaded");
        round_trip(&hs, "polydisperse", 1);
        double E0 = mote_ev_energy(&hs.ev), P0[3], P1[3];
        mote_ev_momentum(&hs.ev, P0);
        CHECK(mote_ev_run(&hs.ev, 20000, &err) == MOTE_OK, "%s", err.msg);
        CHECK(mote_ev_check(&hs.ev, &err) == MOTE_OK, "polydisperse run: %s", err.msg);
        mote_ev_momentum(&hs.ev, P1);
        CHECK(fabs(mote_ev_energy(&hs.ev) - E0) <= 1e-12 * E0 &&
                  fabs(P1[1] - P0[1]) <= 1e-12 * E0 && fabs(P1[2] - P0[2]) <= 1e-12 * E0,
              "polydisperse run: energy or momentum not conserved");
        mote_hs_free(&hs);
    }
}

/* A run that saves and continues equals a run that loads and continues (spec 6.8, 9.1). */
static void test_continuation(void)
{
    printf("continuation from a saved state\n");
    mote_err err = {0};
    char f[512], g1[512], g2[512];
    tmp_path(f, sizeof f, "mid.state");
    tmp_path(g1, sizeof g1, "g1.state");
    tmp_path(g2, sizeof g2, "g2.state");
    struct {
        int bulk;
        uint64_t a, b;
        const char *label;
    } cases[] = {{0, 40, 600, "slit new 3 0.45, step 40 | step 600"},
                 {1, 30, 600, "bulk 256 0.45, step 30 | step 600"}};
    for (int c = 0; c < 2; c++) {
        mote_hs A, B;
        mote_hs_init(&A, NULL);
        mote_hs_init(&B, NULL);
        mote_hs_seed(&A, test_seed(5));
        if (cases[c].bulk)
            mote_hs_bulk(&A, 256, 0.45, &err);
        else
            mote_hs_new(&A, 3, 0.45, &err);
        mote_hs_step(&A, cases[c].a, &err);
        CHECK(mote_hs_save(&A, f, &err) == MOTE_OK, "%s", err.msg);
        double t_f = mote_ev_time(&A.ev), t_rb = A.ev.t_rebuild;
        mote_hs_step(&A, cases[c].b, &err);
        double t_end = mote_ev_time(&A.ev);
        mote_hs_seed(&B, test_seed(999)); /* the load must replace this stream */
        CHECK(mote_hs_load(&B, f, &err) == MOTE_OK, "%s", err.msg);
        mote_hs_step(&B, cases[c].b, &err);
        CHECK(same_state(&A.ev, &B.ev), "%s: continued run differs from the uninterrupted one",
              cases[c].label);
        CHECK(mote_hs_save(&A, g1, &err) == MOTE_OK, "%s", err.msg);
        CHECK(mote_hs_save(&B, g2, &err) == MOTE_OK, "%s", err.msg);
        CHECK(files_equal(g1, g2), "%s: the final files differ", cases[c].label);
        CHECK(t_end - t_f > t_rb, "%s: the continuation (%.1f) does not cross an automatic "
              "rebuild (%.1f)", cases[c].label, t_end - t_f, t_rb);
        /* the random stream continues identically */
        mote_hs_new(&A, 2, 0.3, &err);
        mote_hs_new(&B, 2, 0.3, &err);
        CHECK(same_state(&A.ev, &B.ev), "%s: the random stream was not restored", cases[c].label);
        printf("  %s: identical (t = %.2f)\n", cases[c].label, t_end);
        mote_hs_free(&A);
        mote_hs_free(&B);
    }
}

/* ---- load errors --------------------------------------------------------------------------------- */

typedef struct {
    mote_particle *p;
    mote_ev_cold *pc;
    uint32_t n;
    double len[3];
    mote_rng rng;
} snapshot;

static void snap_take(const mote_hs *hs, snapshot *s)
{
    s->n = hs->ev.n;
    s->p = malloc(s->n * sizeof *s->p);
    memcpy(s->p, hs->ev.p, s->n * sizeof *s->p);
    s->pc = malloc(s->n * sizeof *s->pc);
    memcpy(s->pc, hs->ev.pc, s->n * sizeof *s->pc);
    memcpy(s->len, hs->ev.len, sizeof s->len);
    s->rng = hs->rng;
}

static int snap_same(const mote_hs *hs, const snapshot *s)
{
    return hs->has_system && hs->ev.n == s->n && memcmp(hs->ev.p, s->p, s->n * sizeof *s->p) == 0 &&
           memcmp(hs->ev.pc, s->pc, s->n * sizeof *s->pc) == 0 &&
           memcmp(hs->ev.len, s->len, sizeof s->len) == 0 &&
           memcmp(hs->rng.s, s->rng.s, sizeof s->rng.s) == 0;
}

/* Load `path` into a model holding another system: the load must fail with a message containing
 * every string in `want` (NULL-terminated), and leave the held system untouched. */
static void expect_load_error(mote_hs *hs, const snapshot *snap, const char *path,
                              const char *label, const char *const *want)
{
    mote_err err = {0};
    int rc = mote_hs_load(hs, path, &err);
    CHECK(rc != MOTE_OK, "%s: the load succeeded", label);
    for (int k = 0; want[k]; k++)
        CHECK(strstr(err.msg, want[k]) != NULL, "%s: message \"%s\" lacks \"%s\"", label, err.msg,
              want[k]);
    CHECK(snap_same(hs, snap), "%s: the failed load changed the system held before", label);
    printf("  %s: %s\n", label, err.msg);
}

static void test_load_errors(void)
{
    printf("load errors\n");
    mote_err err = {0};
    char base[512], bad[512], msg[600];
    tmp_path(base, sizeof base, "base.state");
    tmp_path(bad, sizeof bad, "bad.state");

    /* base: N = 64, header lines 1-11, particles on lines 12..75, end on 76 */
    mote_hs src;
    mote_hs_init(&src, NULL);
    mote_hs_new(&src, 2, 0.40, &err);
    mote_hs_step(&src, 5, &err);
    mote_hs_save(&src, base, &err);
    mote_hs_free(&src);
    char *text = read_text(base, NULL);
    lines L = split_lines(text);
    CHECK(L.n == 76, "base file has %d lines", L.n);

    /* the model holds a different system throughout */
    mote_hs hs;
    mote_hs_init(&hs, NULL);
    mote_hs_seed(&hs, test_seed(3));
    mote_hs_new(&hs, 3, 0.3, &err);
    snapshot snap;
    snap_take(&hs, &snap);

    char missing[512];
    tmp_path(missing, sizeof missing, "no_such.state");
    expect_load_error(&hs, &snap, missing, "missing file",
                      (const char *[]){"no_such.state", NULL});

    write_variant(bad, &L, 20, -1, NULL);
    snprintf(msg, sizeof msg, "%s:21:", bad);
    expect_load_error(&hs, &snap, bad, "truncated after line 20",
                      (const char *[]){msg, "ends early", NULL});

    {   /* a line cut in the middle, no final LF */
        FILE *f = fopen(bad, "wb");
        for (int k = 0; k < 20; k++)
            fprintf(f, "%s\n", L.line[k]);
        fprintf(f, "%.20s", L.line[20]);
        fclose(f);
        snprintf(msg, sizeof msg, "%s:21:", bad);
        expect_load_error(&hs, &snap, bad, "line 21 cut short", (const char *[]){msg, NULL});
    }

    write_variant(bad, &L, 75, -1, NULL);
    snprintf(msg, sizeof msg, "%s:76:", bad);
    expect_load_error(&hs, &snap, bad, "no end line",
                      (const char *[]){msg, "truncated", NULL});

    {   /* malformed numbers in particle 18 (line 30) */
        const char *bads[4] = {"1.2.3", "nan", "0x1p3", "inf"};
        for (int q = 0; q < 4; q++) {
            char line[512];
            snprintf(line, sizeof line, "%s", L.line[29]);
            char *sp = strchr(line, ' ');
            char repl[600];
            snprintf(repl, sizeof repl, "%.*s %s%s", (int)(sp - line), line, bads[q],
                     strchr(sp + 1, ' '));
            write_variant(bad, &L, L.n, 29, repl);
            snprintf(msg, sizeof msg, "%s:30:", bad);
            char label[64];
            snprintf(label, sizeof label, "malformed number '%s'", bads[q]);
            expect_load_error(&hs, &snap, bad, label, (const char *[]){msg, bads[q], NULL});
        }
    }

    write_variant(bad, &L, L.n, 5, "n 65");
    snprintf(msg, sizeof msg, "%s:76:", bad);
    expect_load_error(&hs, &snap, bad, "n says 65, file has 64", (const char *[]){msg, NULL});
    write_variant(bad, &L, L.n, 5, "n 63");
    snprintf(msg, sizeof msg, "%s:75:", bad);
    expect_load_error(&hs, &snap, bad, "n says 63, file has 64",
                      (const char *[]){msg, "end", NULL});
    write_variant(bad, &L, L.n, 5, "n many");
    snprintf(msg, sizeof msg, "%s:6:", bad);
    expect_load_error(&hs, &snap, bad, "n not a number", (const char *[]){msg, NULL});

    {   /* overlap: particle 10 (line 22) placed 0.3 from particle 11 (line 23) */
        double r[8];
        sscanf(L.line[22], "%lf %lf %lf %lf %lf %lf %lf %lf", &r[0], &r[1], &r[2], &r[3], &r[4],
               &r[5], &r[6], &r[7]);
        double x = r[0] + (r[0] < 5 ? 0.3 : -0.3);
        char repl[512];
        snprintf(repl, sizeof repl, "%.17g %.17g %.17g 0.5 0.5 0.5 1 1", x, r[1], r[2]);
        write_variant(bad, &L, L.n, 21, repl);
        expect_load_error(&hs, &snap, bad, "overlap",
                          (const char *[]){"10", "11", "22", "23", "overlap", NULL});
    }

    {   /* a sphere outside the walls: particle 5 (line 17) at x = 0.5 */
        char repl[512];
        snprintf(repl, sizeof repl, "0.5%s", strchr(L.line[16], ' '));
        write_variant(bad, &L, L.n, 16, repl);
        snprintf(msg, sizeof msg, "%s:17:", bad);
        expect_load_error(&hs, &snap, bad, "outside the walls",
                          (const char *[]){msg, "outside the walls", NULL});
    }

    write_variant(bad, &L, L.n, 0, "mote-state 2");
    snprintf(msg, sizeof msg, "%s:1:", bad);
    expect_load_error(&hs, &snap, bad, "bad version", (const char *[]){msg, "version", NULL});
    write_variant(bad, &L, L.n, 1, "model nbody");
    snprintf(msg, sizeof msg, "%s:2:", bad);
    expect_load_error(&hs, &snap, bad, "wrong model", (const char *[]){msg, "nbody", NULL});
    write_variant(bad, &L, L.n, 3, "geometry sphere");
    snprintf(msg, sizeof msg, "%s:4:", bad);
    expect_load_error(&hs, &snap, bad, "bad geometry", (const char *[]){msg, NULL});
    write_variant(bad, &L, L.n, 6, "collisions 12");
    snprintf(msg, sizeof msg, "%s:7:", bad);
    expect_load_error(&hs, &snap, bad, "keys out of order", (const char *[]){msg, "time", NULL});
    {
        char repl[512];
        snprintf(repl, sizeof repl, "%s", L.line[40]);
        char *last = strrchr(repl, ' ');
        *last = '\0';
        last = strrchr(repl, ' ');
        strcpy(last, " 0 1");
        write_variant(bad, &L, L.n, 40, repl);
        snprintf(msg, sizeof msg, "%s:41:", bad);
        expect_load_error(&hs, &snap, bad, "radius 0", (const char *[]){msg, "radius", NULL});
    }
    {   /* text after end */
        FILE *f = fopen(bad, "wb");
        for (int k = 0; k < L.n; k++)
            fprintf(f, "%s\n", L.line[k]);
        fprintf(f, "0 0 0\n");
        fclose(f);
        snprintf(msg, sizeof msg, "%s:77:", bad);
        expect_load_error(&hs, &snap, bad, "text after end", (const char *[]){msg, NULL});
    }
    write_text(bad, "", 0);
    expect_load_error(&hs, &snap, bad, "empty file", (const char *[]){"bad.state", NULL});
    write_text(bad, "hello world\n", 12);
    expect_load_error(&hs, &snap, bad, "not a state file", (const char *[]){"bad.state:1:", NULL});

    {   /* a periodic length must exceed 2 sigma_max = 4 */
        const char *p = "mote-state 1\nmodel hard-spheres\ndim 3\ngeometry periodic\n"
                        "box 3.9 8 8\nn 2\ntime 0\ncollisions 0\nwall_collisions 0\n"
                        "rng 0000000000000001 0000000000000002 0000000000000003 "
                        "0000000000000004\nparticles x y z vx vy vz radius mass\n"
                        "1 1 1 1 0 0 1 1\n1 5 5 -1 0 0 1 1\nend\n";
        write_text(bad, p, strlen(p));
        expect_load_error(&hs, &snap, bad, "periodic length too small",
                          (const char *[]){"bad.state", "periodic length", NULL});
        /* the same file with a long enough box loads (so the error above is the length) */
        char ok[1024];
        snprintf(ok, sizeof ok, "%s", p);
        memcpy(strstr(ok, "3.9"), "4.1", 3);
        write_text(bad, ok, strlen(ok));
        mote_hs t;
        mote_hs_init(&t, NULL);
        CHECK(mote_hs_load(&t, bad, &err) == MOTE_OK, "box 4.1 rejected: %s", err.msg);
        mote_hs_free(&t);
    }

    {   /* CRLF line ends are accepted and give the same state */
        size_t len;
        char *raw = read_text(base, &len);
        char *crlf = malloc(2 * len + 1);
        size_t m = 0;
        for (size_t k = 0; k < len; k++) {
            if (raw[k] == '\n')
                crlf[m++] = '\r';
            crlf[m++] = raw[k];
        }
        write_text(bad, crlf, m);
        mote_hs a, b;
        mote_hs_init(&a, NULL);
        mote_hs_init(&b, NULL);
        CHECK(mote_hs_load(&a, bad, &err) == MOTE_OK, "CRLF file rejected: %s", err.msg);
        CHECK(mote_hs_load(&b, base, &err) == MOTE_OK, "%s", err.msg);
        CHECK(same_state(&a.ev, &b.ev), "CRLF file loads a different state");
        mote_hs_free(&a);
        mote_hs_free(&b);
        free(raw);
        free(crlf);
    }

    /* finally a good load replaces the system */
    CHECK(mote_hs_load(&hs, base, &err) == MOTE_OK && hs.ev.n == 64, "good load: %s", err.msg);
    free(snap.p);
    free(snap.pc);
    mote_hs_free(&hs);
    free(L.line);
    free(text);
}

/* ---- the original program's format --------------------------------------------------------------- */

/* N = 4 in a slit of A = 10, L = 12, one image record. Spheres 0 and 1 overlap through the
 * periodic y face (y = 0.8 and 9.5: 1.3 apart, 0.7 deeper than contact); sphere 2 sits at
 * y = 10 (wraps to 0), sphere 3 at z = -1 (wraps to 9). */
static const char original_file[] =
    "4\n"
    "1\n"
    "10.00000000000000\n"
    "12.00000000000000\n"
    "0 0\n"
    "3.000000000000000 0.8000000000000000 5.000000000000000\n"
    "0.5000000000000000 0.1000000000000000 -0.2000000000000000\n"
    "1 1\n"
    "3.000000000000000 9.500000000000000 5.000000000000000\n"
    "-0.3000000000000000 0.2000000000000000 0.1000000000000000\n"
    "2 2\n"
    "8.000000000000000 10.00000000000000 3.000000000000000\n"
    "0.0000000000000000 0.0000000000000000 1.000000000000000\n"
    "3 3\n"
    "8.000000000000000 5.000000000000000 -1.000000000000000\n"
    "0.4000000000000000 -0.4000000000000000 0.0000000000000000\n"
    "0 0\n"
    "3.000000000000000 -0.2000000000000000 5.000000000000000\n"
    "0.5000000000000000 0.1000000000000000 -0.2000000000000000\n";

static void test_original_format(void)
{
    printf("original-format import (spec 9.2, 10 item 18)\n");
    mote_err err = {0};
    char path[512], logpath[512];
    tmp_path(path, sizeof path, "original.txt");
    tmp_path(logpath, sizeof logpath, "import.log");
    write_text(path, original_file, strlen(original_file));

    int geometry = -1, dim = 0;
    uint64_t n = 0;
    CHECK(mote_hs_peek(path, &geometry, &dim, &n, &err) == MOTE_OK && n == 4 && dim == 3 &&
              geometry == MOTE_HS_SLIT,
          "peek: N = %llu dim %d geometry %d: %s", (unsigned long long)n, dim, geometry, err.msg);

    mote_hs hs;
    mote_hs_init(&hs, NULL);
    mote_hs_seed(&hs, test_seed(77));
    mote_hs_new(&hs, 2, 0.3, &err); /* a system and a used stream before the import */
    mote_rng before = hs.rng;
    FILE *log = fopen(logpath, "w");
    hs.log = log;
    int rc = mote_hs_load(&hs, path, &err);
    fclose(log);
    hs.log = NULL;
    CHECK(rc == MOTE_OK, "import failed: %s", err.msg);
    if (rc == MOTE_OK) {
        mote_ev *ev = &hs.ev;
        CHECK(ev->n == 4 && hs.geometry == MOTE_HS_SLIT && ev->len[0] == 12 &&
                  ev->len[1] == 10 && ev->len[2] == 10,
              "import: N = %u, box %g %g %g", ev->n, ev->len[0], ev->len[1], ev->len[2]);
        CHECK(memcmp(before.s, hs.rng.s, sizeof before.s) == 0,
              "import changed the random stream");
        CHECK(mote_ev_time(ev) == 0 && ev->collisions == 0 && ev->wall_collisions == 0,
              "import: time and counters not zero");
        /* velocities as they are (not rescaled) */
        /* particles by number (the file's order): the engine's records are in spatial order */
        const mote_particle *q[4];
        double r[4][3];
        for (uint32_t i = 0; i < 4; i++) {
            q[i] = &ev->p[mote_ev_slot(ev, i)];
            mote_ev_position(ev, mote_ev_slot(ev, i), r[i]);
        }
        CHECK(q[0]->v[0] == 0.5 && q[0]->v[1] == 0.1 && q[0]->v[2] == -0.2 &&
                  q[1]->v[0] == -0.3 && q[3]->v[1] == -0.4,
              "import: velocities changed");
        CHECK(r[2][1] == 0 && r[3][2] == 9 && r[2][0] == 8 && r[3][1] == 5,
              "import: y, z not wrapped: sphere 2 y = %.17g, sphere 3 z = %.17g", r[2][1],
              r[3][2]);
        /* the repair: pushed apart symmetrically along y (the line of centres) to 2 (1 + 1e-9) */
        double dy = r[0][1] - r[1][1];
        dy -= 10 * nearbyint(dy / 10);
        CHECK(fabs(fabs(dy) - 2 * (1 + 1e-9)) < 1e-12,
              "repair: spheres 0 and 1 are %.17g apart, expected 2 (1 + 1e-9)", fabs(dy));
        double mid = r[1][1] + 0.5 * dy; /* across the face: was (0.8 + 9.5 - 10) / 2 = 0.15 */
        mid -= 10 * floor(mid / 10);
        CHECK(fabs(mid - 0.15) < 1e-12, "repair not symmetric: midpoint at y = %.17g", mid);
        CHECK(r[0][0] == 3 && r[1][0] == 3 && r[0][2] == 5 && r[1][2] == 5,
              "repair moved x or z of spheres 0, 1");
        CHECK(mote_hs_check(&hs, &err) == MOTE_OK, "checker after import: %s", err.msg);
        CHECK(mote_ev_min_gap_ratio(ev, NULL, NULL) >= 1, "overlap left after the repair");
        char *logtext = read_text(logpath, NULL);
        CHECK(logtext && strstr(logtext, "1 image record"), "the log does not report the skipped "
              "image: %s", logtext ? logtext : "(none)");
        CHECK(logtext && strstr(logtext, "moved 2 particles"),
              "the log does not report the repair: %s", logtext ? logtext : "(none)");
        printf("  import log: %s", logtext ? logtext : "(none)\n");
        free(logtext);
        /* and it runs */
        CHECK(mote_ev_run(ev, 200, &err) == MOTE_OK, "%s", err.msg);
        CHECK(mote_ev_check(ev, &err) == MOTE_OK, "after running the import: %s", err.msg);
    }

    /* a record with the wrong index: record 2 (its index line is line 11) says 5 */
    {
        char *t = malloc(sizeof original_file);
        memcpy(t, original_file, sizeof original_file);
        char *rec = strstr(t, "\n2 2\n");
        rec[1] = '5';
        write_text(path, t, strlen(t));
        snapshot snap;
        snap_take(&hs, &snap);
        char msg[600];
        snprintf(msg, sizeof msg, "%s:11:", path);
        expect_load_error(&hs, &snap, path, "original: wrong record index",
                          (const char *[]){msg, NULL});
        /* missing image record (file ends early) */
        memcpy(t, original_file, sizeof original_file);
        t[strlen(t) - 60] = '\0';
        write_text(path, t, strlen(t));
        expect_load_error(&hs, &snap, path, "original: truncated", (const char *[]){"early", NULL});
        /* a sphere outside the walls */
        memcpy(t, original_file, sizeof original_file);
        memcpy(strstr(t, "8.000000000000000 5.0"), "11.50000000000000", 17);
        write_text(path, t, strlen(t));
        expect_load_error(&hs, &snap, path, "original: outside the walls",
                          (const char *[]){"outside", NULL});
        free(snap.p);
        free(snap.pc);
        free(t);
    }
    mote_hs_free(&hs);
}

/* ---- atomic writes --------------------------------------------------------------------------------- */

static void test_atomic(void)
{
    printf("atomic writes (spec 9.4)\n");
    mote_err err = {0};
    mote_hs hs;
    mote_hs_init(&hs, NULL);
    mote_hs_new(&hs, 3, 0.4, &err);

    /* a missing directory: error naming the path, nothing created */
    char path[512];
    tmp_path(path, sizeof path, "no_dir/sub/state.txt");
    int before = count_entries();
    CHECK(mote_hs_save(&hs, path, &err) == MOTE_EIO, "save into a missing directory: rc %d",
          (int)err.code);
    CHECK_HAS(err.msg, "no_dir/sub/state.txt");
    CHECK(count_entries() == before, "a failed save left files behind");

    /* onto an existing directory: the rename fails; the directory and its file survive */
    char dir[512], inner[600];
    tmp_path(dir, sizeof dir, "adir");
    mkdir(dir, 0777);
    snprintf(inner, sizeof inner, "%s/keep.txt", dir);
    write_text(inner, "keep\n", 5);
    before = count_entries();
    CHECK(mote_hs_save(&hs, dir, &err) != MOTE_OK, "saving over a directory succeeded");
    CHECK(count_entries() == before, "saving over a directory left a temporary file");
    char *k = read_text(inner, NULL);
    CHECK(k && strcmp(k, "keep\n") == 0, "the directory's content was damaged");
    free(k);
    unlink(inner);
    rmdir(dir);

    /* running out of file space half way (RLIMIT_FSIZE): the earlier file is kept */
    char target[512];
    tmp_path(target, sizeof target, "target.state");
    write_text(target, "old content\n", 12);
    before = count_entries();
    struct rlimit saved, tiny;
    getrlimit(RLIMIT_FSIZE, &saved);
    tiny = saved;
    tiny.rlim_cur = 4096; /* the state of N = 276 is ~30 kB */
    void (*prev)(int) = signal(SIGXFSZ, SIG_IGN);
    int limited = setrlimit(RLIMIT_FSIZE, &tiny) == 0;
    int rc = mote_hs_save(&hs, target, &err);
    setrlimit(RLIMIT_FSIZE, &saved);
    signal(SIGXFSZ, prev);
    CHECK(limited, "could not set RLIMIT_FSIZE");
    CHECK(rc == MOTE_EIO, "a save that runs out of space returned %d: %s", rc, err.msg);
    char *now = read_text(target, NULL);
    CHECK(now && strcmp(now, "old content\n") == 0, "the earlier file was damaged: '%.40s'",
          now ? now : "(gone)");
    free(now);
    CHECK(count_entries() == before, "a failed save left a temporary file");

    /* mote_afile: abort keeps the target and removes the temporary file; commit replaces */
    mote_afile af;
    CHECK(mote_afile_open(&af, target, &err) == MOTE_OK, "%s", err.msg);
    fputs("new content\n", af.f);
    fflush(af.f);
    /* while written the data has no name where the file system allows (O_TMPFILE), so a run
     * killed now leaves nothing (issue 52: NAME.tmp.* files were left); else one temporary
     * file in the target's own directory */
    CHECK(af.anon ? count_entries() == before : count_entries() == before + 1,
          "the temporary file: %d entries, %d before (unnamed: %d)", count_entries(), before,
          af.anon);
    CHECK(af.anon || getenv("MOTE_NO_TMPFILE"), "this file system gave no unnamed temporary file "
          "(O_TMPFILE); MOTE_NO_TMPFILE=1 accepts that");
    mote_afile_abort(&af);
    now = read_text(target, NULL);
    CHECK(now && strcmp(now, "old content\n") == 0, "abort changed the target");
    free(now);
    CHECK(count_entries() == before, "abort left a temporary file");
    CHECK(mote_afile_open(&af, target, &err) == MOTE_OK, "%s", err.msg);
    fputs("new content\n", af.f);
    CHECK(mote_afile_commit(&af, &err) == MOTE_OK, "%s", err.msg);
    now = read_text(target, NULL);
    CHECK(now && strcmp(now, "new content\n") == 0, "commit did not replace the target");
    free(now);
    CHECK(count_entries() == before, "commit left a temporary file");
    /* a successful save overwrites an existing file */
    CHECK(mote_hs_save(&hs, target, &err) == MOTE_OK, "%s", err.msg);
    now = read_text(target, NULL);
    CHECK(now && strncmp(now, "mote-state 1\n", 13) == 0, "save did not overwrite");
    free(now);
    CHECK(count_entries() == before, "save left a temporary file");
    mote_hs_free(&hs);
}

/* Frames in an H5MD file (the first dimension of position/value and of position/step, which
 * must agree), or -1 when it cannot be read. */
static long h5md_frames(const char *path)
{
    H5E_auto2_t fn;
    void *data;
    H5Eget_auto2(H5E_DEFAULT, &fn, &data);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    long frames = -1;
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    hid_t v = f >= 0 ? H5Dopen2(f, "particles/all/position/value", H5P_DEFAULT) : -1;
    hid_t st = f >= 0 ? H5Dopen2(f, "particles/all/position/step", H5P_DEFAULT) : -1;
    if (v >= 0 && st >= 0) {
        hsize_t dv[3], ds[1];
        hid_t sv = H5Dget_space(v), ss = H5Dget_space(st);
        if (H5Sget_simple_extent_dims(sv, dv, NULL) == 3 &&
            H5Sget_simple_extent_dims(ss, ds, NULL) == 1 && dv[0] == ds[0]) {
            double *buf = malloc(dv[0] * dv[1] * dv[2] * sizeof *buf + 1);
            if (buf && H5Dread(v, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) >= 0)
                frames = (long)dv[0];
            free(buf);
        }
        H5Sclose(sv);
        H5Sclose(ss);
    }
    if (st >= 0)
        H5Dclose(st);
    if (v >= 0)
        H5Dclose(v);
    if (f >= 0)
        H5Fclose(f);
    H5Eset_auto2(H5E_DEFAULT, fn, data);
    return frames;
}

static void test_h5md(void)
{
    printf("H5MD files: atomic first frame, appended frames cut back on failure\n");
    mote_err err = {0};
    enum { N = 400 };
    static double pos[3 * N], vel[3 * N], rad[N];
    for (int i = 0; i < 3 * N; i++) {
        pos[i] = 0.01 * i;
        vel[i] = 1 - 0.001 * i;
    }
    for (int i = 0; i < N; i++)
        rad[i] = 0.5;
    mote_h5md_frame fr = {.model = "test", .dim = 2, .n = N, .pos = pos, .vel = vel,
                          .nscalar = 1, .has_box = 1, .edges = {20, 20}, .periodic = {1, 1}};
    fr.scalar[0] = (mote_h5md_scalar){"radius", NULL, rad};
    char path[512];
    tmp_path(path, sizeof path, "t.h5");
    write_text(path, "old content\n", 12);
    int before = count_entries();

    /* out of file space in the first frame: the earlier file stays */
    struct rlimit saved, tiny;
    getrlimit(RLIMIT_FSIZE, &saved);
    tiny = saved;
    tiny.rlim_cur = 4096;
    void (*prev)(int) = signal(SIGXFSZ, SIG_IGN);
    CHECK(setrlimit(RLIMIT_FSIZE, &tiny) == 0, "could not set RLIMIT_FSIZE");
    int rc = mote_h5md_first(path, &fr, &err);
    setrlimit(RLIMIT_FSIZE, &saved);
    CHECK(rc == MOTE_EIO, "a first frame that runs out of space returned %d: %s", rc, err.msg);
    char *now = read_text(path, NULL);
    CHECK(now && strcmp(now, "old content\n") == 0, "the earlier file was damaged");
    free(now);
    CHECK(count_entries() == before, "a failed first frame left a temporary file");

    /* two good frames */
    CHECK(mote_h5md_first(path, &fr, &err) == MOTE_OK, "%s", err.msg);
    fr.step = 1;
    fr.time = 0.5;
    CHECK(mote_h5md_append(path, &fr, &err) == MOTE_OK, "%s", err.msg);
    CHECK_INT(h5md_frames(path), 2);

    /* a frame of another dimension: refused after the step and time grew, cut back */
    fr.dim = 3;
    rc = mote_h5md_append(path, &fr, &err);
    CHECK(rc == MOTE_EIO, "a 3D frame appended to a 2D file returned %d", rc);
    CHECK_HAS(err.msg, "t.h5: cannot add a frame to the H5MD trajectory; it keeps the frames");
    CHECK_INT(h5md_frames(path), 2);
    fr.dim = 2;

    /* out of file space while a frame is added (the frames are ~16 kB): cut back */
    struct stat st;
    stat(path, &st);
    tiny.rlim_cur = (rlim_t)st.st_size + 2048;
    CHECK(setrlimit(RLIMIT_FSIZE, &tiny) == 0, "could not set RLIMIT_FSIZE");
    for (int i = 0; i < 3 * N; i++)
        pos[i] = sin(1.7 * i) * 1e3; /* (no longer compressible) */
    fr.step = 2;
    rc = mote_h5md_append(path, &fr, &err);
    setrlimit(RLIMIT_FSIZE, &saved);
    signal(SIGXFSZ, prev);
    CHECK(rc == MOTE_EIO, "a frame that runs out of space returned %d: %s", rc, err.msg);
    CHECK_INT(h5md_frames(path), 2);
    /* and the next frame follows the two */
    CHECK(mote_h5md_append(path, &fr, &err) == MOTE_OK, "%s", err.msg);
    CHECK_INT(h5md_frames(path), 3);

    /* appending to a file that is not HDF5 */
    char text[512];
    tmp_path(text, sizeof text, "text.h5");
    write_text(text, "not hdf5\n", 9);
    rc = mote_h5md_append(text, &fr, &err);
    CHECK(rc == MOTE_EIO, "appending to a text file returned %d", rc);
    CHECK_HAS(err.msg, "text.h5: cannot open the H5MD trajectory to add a frame");
    unlink(text);
    unlink(path);
}

int main(void)
{
    if (!test_tmpdir_make(tmpdir, sizeof tmpdir, "mote_test_files"))
        return 1;
    double w0 = mote_wall_seconds();
    test_round_trips();
    test_continuation();
    test_load_errors();
    test_original_format();
    test_atomic();
    test_h5md();
    test_remove_tree(tmpdir);
    printf("test_files: %.1f s\n", mote_wall_seconds() - w0);
    return test_summary();
}
