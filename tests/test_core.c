/* test_core.c: the shared core every model stands on: data files written and read back (header,
 * keys, results, columns, blocks, file lines, words among numbers, hostile files), results,
 * block statistics and sampling schedules, data files named .csv (RFC 4180), the run loop. */
#include "mote/datafile.h"
#include "mote/grid.h"
#include "mote/stats.h"
#include "test.h"
#include "mote/core.h"
#include "mote/loop.h"
#include "mote/statefile.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char tmpdir[256];

static void path_in(char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "%s/%s", tmpdir, name);
}

static void test_datafile_round_trip(void)
{
    printf("data files: written, then read back\n");
    char path[512];
    path_in(path, sizeof path, "d.dat");
    mote_err err = {0};
    mote_datafile d;
    CHECK_INT(mote_datafile_open(&d, path, "probe", "probe 3 d.dat   (x.mote:4)", 42, &err), 0);
    fprintf(d.f, "# L = 12.5\n# A = 3\n");
    mote_result res = {0};
    mote_result_add(&res, "Z", 3.25, 0.01);
    mote_result_add(&res, "mu", -1.5, NAN);
    mote_result_write(&res, d.f);
    mote_datafile_columns(&d, "x rho side");
    fprintf(d.f, "0.5 1.25 left\n1.5 2.5e-3 left\n\n\n2 -7 right\n");
    CHECK_INT(mote_datafile_commit(&d, &err), 0);

    mote_table t;
    CHECK_INT(mote_table_read(&t, path, &err), 0);
    CHECK_STR(t.format, "probe");
    CHECK_STR(t.command, "probe 3 d.dat   (x.mote:4)");
    CHECK(mote_table_key(&t, "L") == 12.5, "L = %g", mote_table_key(&t, "L"));
    CHECK(mote_table_key(&t, "Z") == 3.25, "Z = %g (a result's value)", mote_table_key(&t, "Z"));
    CHECK(isnan(mote_table_key(&t, "nosuch")) && !mote_table_has(&t, "nosuch"), "absent key");
    CHECK(mote_table_has(&t, "A"), "A present");
    CHECK_INT(t.ncolnames, 3);
    CHECK_INT(mote_table_col(&t, "rho"), 1);
    CHECK_INT(mote_table_col(&t, "nosuch"), -1);
    CHECK_INT((int)t.rows, 3);
    CHECK(mote_table_at(&t, 1, 1) == 2.5e-3, "row 1 rho");
    CHECK(isnan(mote_table_at(&t, 0, 2)), "a word reads as NaN");
    CHECK_STR(t.first[2], "2");
    CHECK_INT(t.block[0], 0);
    CHECK_INT(t.block[1], 0);
    CHECK_INT(t.block[2], 1); /* two blank lines start one new block */
    CHECK_INT(t.ncol[2], 3);
    CHECK(isnan(mote_table_at(&t, 2, 3)) && isnan(mote_table_at(&t, 2, 99)), "beyond the row");
    /* lines: 3 preamble + 2 keys + 2 results + columns = 8 header lines, rows at 9, 10, 13 */
    CHECK_INT((int)t.line[0], 9);
    CHECK_INT((int)t.line[2], 13);
    mote_table_free(&t);

    /* results */
    double e = 0;
    const double *z = mote_result_get(&res, "Z", &e);
    CHECK(z && *z == 3.25 && e == 0.01, "result get");
    CHECK(mote_result_get(&res, "nosuch", NULL) == NULL, "absent result");
    mote_result_add(NULL, "x", 1, 1); /* ignored, no crash */
    mote_result full = {0};
    for (int k = 0; k < MOTE_RESULT_MAX + 5; k++)
        mote_result_add(&full, "k", k, 0);
    CHECK_INT(full.n, MOTE_RESULT_MAX);
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    mote_result_print(&res, "probe", m);
    fclose(m);
    CHECK_STR(buf, "probe: Z=3.25 Z_err=0.01 mu=-1.5\n");
    free(buf);
}

static void test_datafile_hostile(void)
{
    printf("data files: hostile input\n");
    char path[512];
    mote_err err = {0};
    mote_table t;
    path_in(path, sizeof path, "nosuch.dat");
    CHECK(mote_table_read(&t, path, &err) == MOTE_EIO, "a missing file is an I/O error");
    CHECK_HAS(err.msg, "nosuch.dat");

    path_in(path, sizeof path, "nul.dat");
    FILE *f = fopen(path, "wb");
    fwrite("# mote x 1\n1 2\n3\0 4\n", 1, 20, f);
    fclose(f);
    CHECK(mote_table_read(&t, path, &err) == MOTE_EFORMAT, "a NUL byte is refused");
    CHECK_HAS(err.msg, "nul.dat:3:");

    /* no header at all, numbers that overflow, very long rows: a table, never a crash */
    path_in(path, sizeof path, "odd.dat");
    f = fopen(path, "wb");
    fputs("1e999 -1e999 nan inf 0x10\n# columns: a\n# k = 1e400\n", f);
    for (int k = 0; k < 200; k++)
        fputs(" 7", f);
    fputs("\n", f);
    fclose(f);
    CHECK_INT(mote_table_read(&t, path, &err), 0);
    CHECK_STR(t.format, "");
    CHECK_INT((int)t.rows, 2);
    CHECK_INT(t.ncol[1], 200);
    CHECK(isinf(mote_table_key(&t, "k")), "an overflowing key value reads as inf");
    mote_table_free(&t);

    /* rows of growing width: earlier rows padded with NaN; beyond MOTE_TABLE_MAXCOL counted only */
    path_in(path, sizeof path, "wide.dat");
    f = fopen(path, "wb");
    fputs("1 2 3\n", f);
    for (int k = 0; k < 100; k++)
        fprintf(f, "%d ", k);
    fputs("\n", f);
    for (int k = 0; k < MOTE_TABLE_MAXCOL + 10; k++)
        fprintf(f, "%d ", k);
    fputs("\n", f);
    fclose(f);
    CHECK_INT(mote_table_read(&t, path, &err), 0);
    CHECK(t.rows == 3 && t.ncol[1] == 100 && t.ncol[2] == MOTE_TABLE_MAXCOL + 10 &&
              t.width == MOTE_TABLE_MAXCOL,
          "wide rows: %zu rows, widths %d %d, kept %zu", t.rows, t.ncol[1], t.ncol[2], t.width);
    CHECK(mote_table_at(&t, 0, 2) == 3 && isnan(mote_table_at(&t, 0, 3)) &&
              mote_table_at(&t, 1, 99) == 99 && mote_table_at(&t, 2, MOTE_TABLE_MAXCOL - 1) ==
                                                    MOTE_TABLE_MAXCOL - 1 &&
              isnan(mote_table_at(&t, 2, MOTE_TABLE_MAXCOL)),
          "wide rows: values after widening");
    mote_table_free(&t);
}

static void test_blocks_and_schedules(void)
{
    printf("blocks and schedules\n");
    /* every sample in exactly one block; sizes agree with mote_block_of and differ by <= 1 */
    static const uint64_t ns[] = {1, 2, 9, 10, 11, 99, 1000, 1234567};
    for (size_t q = 0; q < sizeof ns / sizeof ns[0]; q++) {
        uint64_t n = ns[q];
        int B = mote_blocks_count(n, 10);
        CHECK_INT(B, (int)(n < 10 ? n : 10));
        uint64_t count[10] = {0}, total = 0, lo = UINT64_MAX, hi = 0;
        int last = 0, monotone = 1;
        for (uint64_t s = 0; s < n; s++) {
            int b = mote_block_of(s, n, 10);
            monotone &= b >= last && b < B;
            last = b;
            count[b]++;
        }
        for (int b = 0; b < B; b++) {
            CHECK(count[b] == mote_block_size(b, n, 10), "n %llu block %d: %llu vs %llu",
                  (unsigned long long)n, b, (unsigned long long)count[b],
                  (unsigned long long)mote_block_size(b, n, 10));
            total += count[b];
            lo = count[b] < lo ? count[b] : lo;
            hi = count[b] > hi ? count[b] : hi;
        }
        CHECK(monotone && total == n && hi - lo <= 1, "n %llu: blocks", (unsigned long long)n);
    }
    double means[4] = {1, 2, 3, 4};
    CHECK_NEAR(mote_block_error(means, 4), sqrt(5.0 / 12.0), 1e-15);
    CHECK(isnan(mote_block_error(means, 1)), "one block: no error");

    /* counted: S samples over C events end exactly at C and never go back */
    static const uint64_t cs[][2] = {{7, 3}, {1000, 1000}, {5, 100}, {UINT64_MAX, 10},
                                     {(1ull << 40) + 3, (1ull << 33) + 1}};
    for (size_t q = 0; q < sizeof cs / sizeof cs[0]; q++) {
        uint64_t C = cs[q][0], S = cs[q][1], prev = 0;
        int ok = 1;
        for (uint64_t s = 1; s <= S && s < 100000; s++) {
            uint64_t at = mote_schedule_count_at(s, S, C);
            ok &= at >= prev;
            prev = at;
        }
        CHECK(ok, "C %llu S %llu: monotone", (unsigned long long)C, (unsigned long long)S);
        CHECK(mote_schedule_count_at(S, S, C) == C, "C %llu S %llu: last at C",
              (unsigned long long)C, (unsigned long long)S);
    }
    CHECK(mote_schedule_count_at(1, 3, 7) == 2 && mote_schedule_count_at(2, 3, 7) == 4,
          "floor(s C / S)");
    /* timed: the millionth sample time is computed afresh, as exact as the first */
    mote_schedule sch = {0.1, 0.1, 1000000};
    CHECK(mote_schedule_next(&sch) == 0.1 + 1e6 * 0.1, "t0 + k dt");
}

/* ---- the cell grid against brute force ---------------------------------------------------------- */

typedef struct {
    uint32_t n;
    unsigned char *seen; /* n * n: the pair (i, j) reported */
    double (*d)[3];      /* n * n: its separation */
    int bad;             /* order or duplicates wrong */
    uint32_t stop_after;
    uint64_t calls;
} pair_log;

static int log_pair(void *ctx, uint32_t i, uint32_t j, const double d[3], double r2)
{
    pair_log *L = ctx;
    if (!(i < j) || j >= L->n || L->seen[(size_t)i * L->n + j])
        L->bad = 1;
    else {
        L->seen[(size_t)i * L->n + j] = 1;
        memcpy(L->d[(size_t)i * L->n + j], d, sizeof L->d[0]);
    }
    L->calls++;
    return L->stop_after && L->calls >= L->stop_after;
}

static double min_image(double d, double len, int periodic)
{
    if (periodic)
        d -= len * round(d / len);
    return d;
}

/* One configuration: n particles in a box lo + [0, len), some of them outside it. */
static void grid_case(const char *what, int dim, const double len[3], const int periodic[3],
                      double s, uint32_t n, uint64_t seed)
{
    mote_rng rng;
    mote_rng_seed(&rng, seed);
    const double lo[3] = {-1.5, 2.0, 0.25};
    double *x = malloc(3 * (size_t)n * sizeof *x);
    for (uint32_t i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) {
            double u = mote_rng_uniform(&rng);
            if (i % 17 == 3) /* a few outside the region (wall axes: clamped; periodic: wrapped) */
                u = u * 1.4 - 0.2;
            x[3 * (size_t)i + a] = lo[a] + u * len[a];
        }
    mote_grid g = {0};
    CHECK_INT(mote_grid_setup(&g, dim, lo, len, periodic, s, n), 0);
    const double *coord[3] = {x, x + 1, x + 2};
    mote_grid_build(&g, n, coord, 3);
    pair_log L = {n, calloc((size_t)n * n, 1), malloc((size_t)n * n * sizeof *L.d), 0, 0, 0};
    uint64_t count = mote_grid_pairs(&g, s, log_pair, &L);
    uint64_t expect = 0, missing = 0, wrong_d = 0;
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t j = i + 1; j < n; j++) {
            double d[3] = {0, 0, 0}, r2 = 0;
            for (int a = 0; a < dim; a++) {
                d[a] = min_image(x[3 * (size_t)j + a] - x[3 * (size_t)i + a], len[a],
                                 periodic[a]);
                r2 += d[a] * d[a];
            }
            int close = r2 < s * s, seen = L.seen[(size_t)i * n + j];
            expect += close;
            /* the boundary is a rounding decision: only pairs clearly inside or out count */
            if (close != seen && fabs(sqrt(r2) - s) > 1e-9 * s)
                missing++;
            if (seen)
                for (int a = 0; a < 3; a++)
                    wrong_d += fabs(L.d[(size_t)i * n + j][a] - d[a]) > 1e-9 * (len[a] + 1);
        }
    CHECK(!L.bad && missing == 0 && wrong_d == 0 && count == L.calls,
          "%s: %llu pairs, %llu expected, %llu wrong, %llu separations wrong, bad %d", what,
          (unsigned long long)count, (unsigned long long)expect, (unsigned long long)missing,
          (unsigned long long)wrong_d, L.bad);
    /* the cell of every particle holds it */
    int held = 1;
    for (uint32_t k = 0; k < n; k++) {
        uint32_t i = g.order[k];
        held &= k >= g.start[g.cell[i]] && k < g.start[g.cell[i] + 1];
        /* and its coordinates on the axes name the same cell */
        int c[3];
        mote_grid_coords(&g, x + 3 * (size_t)i, c);
        for (int a = 0; a < 3; a++)
            held &= c[a] >= 0 && c[a] < g.nc[a] && (a < dim || c[a] == 0);
        held &= ((size_t)c[2] * (size_t)g.nc[1] + (size_t)c[1]) * (size_t)g.nc[0] +
                    (size_t)c[0] == g.cell[i];
    }
    CHECK(held, "%s: every particle in its cell, which its coordinates name", what);
    /* a stop from the callback ends the sweep */
    if (count > 3) {
        memset(L.seen, 0, (size_t)n * n);
        L.calls = 0;
        L.stop_after = 3;
        CHECK(mote_grid_pairs(&g, s, log_pair, &L) == UINT64_MAX && L.calls == 3,
              "%s: stop after 3", what);
    }
    printf("  %s: %llu close pairs, cells %d x %d x %d%s\n", what, (unsigned long long)count,
           g.nc[0], g.nc[1], g.nc[2], g.generic ? " (minimum image per pair)" : "");
    free(L.seen);
    free(L.d);
    free(x);
    mote_grid_free(&g);
}

static void test_grid(void)
{
    printf("cell grid against brute force\n");
    const int walls[3] = {0, 0, 0}, per[3] = {1, 1, 1}, mixed[3] = {0, 1, 1};
    const double cube[3] = {10, 10, 10}, flat[3] = {30, 7, 1}, tiny[3] = {2.5, 3.7, 9};
    grid_case("3D walls", 3, cube, walls, 1.1, 900, 1);
    grid_case("3D periodic", 3, cube, per, 1.1, 900, 2);
    grid_case("3D slit", 3, cube, mixed, 1.1, 900, 3);
    grid_case("3D periodic, 2 and 3 cells", 3, tiny, per, 1.2, 300, 4);
    grid_case("3D dilute (cells merged)", 3, cube, per, 2.5, 60, 5);
    grid_case("2D walls", 2, flat, walls, 0.6, 800, 6);
    grid_case("2D periodic", 2, flat, per, 0.6, 800, 7);
    grid_case("2D periodic, one cell across", 2, tiny, per, 1.2, 200, 8);
    grid_case("2D mixed", 2, flat, mixed, 0.6, 800, 9);
    /* refusals */
    mote_grid g = {0};
    const double bad[3] = {1, NAN, 1}, zero[3] = {1, 0, 1}, lo[3] = {0, 0, 0};
    CHECK(mote_grid_setup(&g, 3, lo, bad, per, 1, 10) != 0, "NaN length refused");
    CHECK(mote_grid_setup(&g, 3, lo, zero, per, 1, 10) != 0, "zero length refused");
    CHECK(mote_grid_setup(&g, 3, lo, cube, per, 0, 10) != 0, "zero width refused");
    const double huge[3] = {1e300, 1e300, 1e300};
    CHECK(mote_grid_setup(&g, 3, lo, huge, walls, 1e-300, 10) == 0 && g.ncells <= 37,
          "a huge region with few particles gets few cells (%zu)", g.ncells);
    mote_grid_free(&g);
}


/* A data file written under a .csv name is RFC 4180 (issue 34): the column names as the header
 * row, commas, CR LF, quotes where needed, a block column for several blocks, no '#' lines; an
 * earlier file is replaced only when the new one is complete; other files are left alone. */
static void read_all(const char *path, char *buf, size_t n)
{
    FILE *f = fopen(path, "rb");
    size_t k = f ? fread(buf, 1, n - 1, f) : 0;
    buf[k] = 0;
    if (f)
        fclose(f);
}

static void test_csv(void)
{
    printf("data files named .csv: RFC 4180\n");
    char path[512], buf[4096];
    mote_err err = {0};
    mote_datafile d;
    path_in(path, sizeof path, "one.CSV");
    CHECK_INT(mote_datafile_open(&d, path, "probe", "probe one.CSV   (x.mote:1)", 7, &err), 0);
    fprintf(d.f, "# L = 12.5\n");
    mote_datafile_columns(&d, "x rho name");
    fprintf(d.f, "0.5 1.25 left\n1.5   2.5e-3\ta\"b\n2 3 a,b\n4,5,c\n");
    CHECK_INT(mote_datafile_commit(&d, &err), 0);
    read_all(path, buf, sizeof buf);
    CHECK_STR(buf, "x,rho,name\r\n0.5,1.25,left\r\n1.5,2.5e-3,\"a\"\"b\"\r\n2,3,\"a,b\"\r\n"
                   "4,5,c\r\n");

    path_in(path, sizeof path, "blocks.csv");
    CHECK_INT(mote_datafile_open(&d, path, "probe", NULL, 7, &err), 0);
    mote_datafile_columns(&d, "x y");
    fprintf(d.f, "1 2\n3 4\n\n\n5 6\n\n");
    CHECK_INT(mote_datafile_commit(&d, &err), 0);
    read_all(path, buf, sizeof buf);
    CHECK_STR(buf, "block,x,y\r\n0,1,2\r\n0,3,4\r\n1,5,6\r\n");

    /* a file that is not a data file keeps its bytes under any name */
    path_in(path, sizeof path, "plain.csv");
    mote_afile af;
    CHECK_INT(mote_afile_open(&af, path, &err), 0);
    fputs("a b\n# c\n", af.f);
    CHECK_INT(mote_afile_commit(&af, &err), 0);
    read_all(path, buf, sizeof buf);
    CHECK_STR(buf, "a b\n# c\n");

    /* a data file under another name stays one */
    path_in(path, sizeof path, "one.csv.dat");
    CHECK_INT(mote_datafile_open(&d, path, "probe", NULL, 7, &err), 0);
    mote_datafile_columns(&d, "x");
    fprintf(d.f, "1\n");
    CHECK_INT(mote_datafile_commit(&d, &err), 0);
    read_all(path, buf, sizeof buf);
    CHECK(strncmp(buf, "# mote probe 1\n", 15) == 0, "not converted: %.40s", buf);
    /* rows longer than the 1 MiB that readers of users' files accept: 3 MiB of fields */
    path_in(path, sizeof path, "wide.csv");
    CHECK_INT(mote_datafile_open(&d, path, "probe", NULL, 7, &err), 0);
    mote_datafile_columns(&d, "x");
    const int nf = 3 << 19; /* fields "1 " */
    for (int k = 0; k < nf; k++)
        fputs(k ? " 1" : "1", d.f);
    fputs("\n2\n", d.f);
    CHECK_INT(mote_datafile_commit(&d, &err), 0);
    FILE *w = fopen(path, "rb");
    long commas = 0, size = 0;
    int ch, last[4] = {0};
    while (w && (ch = getc(w)) != EOF) {
        commas += ch == ',';
        size++;
        memmove(last, last + 1, 3 * sizeof *last);
        last[3] = ch;
    }
    if (w)
        fclose(w);
    CHECK(commas == nf - 1 && size == 3 + 2L * nf + 1 + 3 && last[1] == '2' && last[2] == '\r' &&
              last[3] == '\n',
          "a 3 MiB row converted: %ld commas, %ld bytes", commas, size);
    /* format=jsonl: one object a row, numbers as JSON reads them, nan null, words strings */
    path_in(path, sizeof path, "rows.jsonl");
    CHECK_INT(mote_datafile_open(&d, path, "probe", NULL, 7, &err), 0);
    d.af.as = MOTE_AS_JSONL;
    mote_datafile_columns(&d, "x rho name");
    fprintf(d.f, "0.5 2.5e-3 left\n.5 1. a\"b\n+3 nan -inf\n-0 1E+2 x y\n");
    CHECK_INT(mote_datafile_commit(&d, &err), 0);
    read_all(path, buf, sizeof buf);
    CHECK_STR(buf, "{\"format\":\"probe\",\"x\":0.5,\"rho\":2.5e-3,\"name\":\"left\"}\n"
                   "{\"format\":\"probe\",\"x\":0.5,\"rho\":1,\"name\":\"a\\\"b\"}\n"
                   "{\"format\":\"probe\",\"x\":3,\"rho\":null,\"name\":null}\n"
                   "{\"format\":\"probe\",\"x\":-0,\"rho\":1E+2,\"name\":\"x\","
                   "\"column_4\":\"y\"}\n");
    path_in(path, sizeof path, "blocks.jsonl");
    CHECK_INT(mote_datafile_open(&d, path, "probe", NULL, 7, &err), 0);
    d.af.as = MOTE_AS_JSONL;
    mote_datafile_columns(&d, "x");
    fprintf(d.f, "1\n\n2\n");
    CHECK_INT(mote_datafile_commit(&d, &err), 0);
    read_all(path, buf, sizeof buf);
    CHECK_STR(buf, "{\"format\":\"probe\",\"block\":0,\"x\":1}\n"
                   "{\"format\":\"probe\",\"block\":1,\"x\":2}\n");
    /* a row of 5000 fields (wider than any fixed table of words): every one kept, in order */
    path_in(path, sizeof path, "wide.jsonl");
    CHECK_INT(mote_datafile_open(&d, path, "probe", NULL, 7, &err), 0);
    d.af.as = MOTE_AS_JSONL;
    mote_datafile_columns(&d, "a b");
    for (int k = 0; k < 5000; k++)
        fprintf(d.f, k ? " %d" : "%d", k);
    fputc('\n', d.f);
    CHECK_INT(mote_datafile_commit(&d, &err), 0);
    FILE *wj = fopen(path, "rb");
    char *wide = calloc(1, 1 << 18);
    const size_t got = wj && wide ? fread(wide, 1, (1 << 18) - 1, wj) : 0;
    if (wj)
        fclose(wj);
    CHECK(wide && got > 43 && memcmp(wide, "{\"format\":\"probe\",\"a\":0,\"b\":1,\"column_3\":2,", 43) == 0 &&
              strstr(wide, ",\"column_5000\":4999}\n") != NULL,
          "a row of 5000 fields as JSON: %.60s ... %s", wide, got > 40 ? wide + got - 40 : "");
    free(wide);
    CHECK(mote_path_is_csv("a.csv") && mote_path_is_csv("A.Csv") && !mote_path_is_csv("csv") &&
              !mote_path_is_csv("a.csvx") && !mote_path_is_csv(".cs"),
          "mote_path_is_csv");
}

/* A monitor's rows (mote_rows): PATH.partial follows every row, PATH is written whole at the
 * end and again after a later run, and memory stays bounded (rows past `spill` bytes move to
 * the disk and are read back): the files hold every row, in order, whatever the spill. */
static void rows_header(FILE *f, const void *arg, int growing)
{
    fprintf(f, "# %s %s\n", (const char *)arg, growing ? "growing" : "whole");
}

static void expect_rows(const char *path, const char *head, int n, const char *what)
{
    static char got[65536], want[65536];
    read_all(path, got, sizeof got);
    size_t k = (size_t)snprintf(want, sizeof want, "%s", head);
    for (int i = 0; i < n && k < sizeof want; i++)
        k += (size_t)snprintf(want + k, sizeof want - k, "row %d %g\n", i, 0.5 * i);
    CHECK(strcmp(got, want) == 0, "%s: %d rows (%zu bytes read, %zu expected)", what, n,
          strlen(got), strlen(want));
}

static void test_rows(void)
{
    printf("monitor rows: followed, written whole, bounded memory\n");
    char path[512], part[600];
    for (int spill = 0; spill <= 1; spill++) {
        path_in(path, sizeof path, spill ? "rows/spilled.dat" : "rows/mon.dat");
        snprintf(part, sizeof part, "%s.partial", path);
        mote_err err = {0};
        mote_rows r;
        CHECK_INT(mote_rows_open(&r, path, rows_header, "mon", &err), 0);
        r.spill = spill ? 200 : 0;
        size_t most = 0;
        int i = 0;
        for (; i < 1500; i++) {
            fprintf(r.text, "row %d %g\n", i, 0.5 * i);
            CHECK_INT(i ? mote_rows_follow(&r, &err) : mote_rows_start(&r, &err), 0);
            most = r.len > most ? r.len : most;
            if (i == 0)
                expect_rows(path, "# mon whole\n", 1, "PATH at the start");
            if (i == 700)
                expect_rows(part, "# mon growing\n", 701, "PATH.partial during the run");
        }
        expect_rows(path, "# mon whole\n", 1, "PATH before the end: the complete one kept");
        CHECK_INT(mote_rows_write(&r, &err), 0);
        expect_rows(path, "# mon whole\n", 1500, "PATH at the end");
        CHECK(access(part, F_OK) != 0, "PATH.partial removed at the end");
        for (; i < 1600; i++) { /* a later run: its partial file begins with every row so far */
            fprintf(r.text, "row %d %g\n", i, 0.5 * i);
            CHECK_INT(mote_rows_follow(&r, &err), 0);
        }
        expect_rows(part, "# mon growing\n", 1600, "PATH.partial of a later run");
        CHECK_INT(mote_rows_write(&r, &err), 0);
        expect_rows(path, "# mon whole\n", 1600, "PATH after a later run");
        if (spill)
            CHECK(most <= 200 + 16 && r.stored > 0, "rows in memory: at most %zu bytes", most);
        else
            CHECK(most >= 1600 * 8 && r.stored == 0, "below the spill: in memory (%zu)", most);
        mote_rows_free(&r);
    }
}

/* The run loop's observers (include/mote/loop.h): exact times t0 + k dt, the stop, once per
 * stop even when a step passes several times, a time a hair before the end taken at the end. */
typedef struct {
    int calls;
    double t[16];
} loop_probe;

static int probe_fire(void *ctx, void *subject, mote_err *err)
{
    loop_probe *p = ctx;
    if (p->calls < 16)
        p->t[p->calls] = *(const double *)subject;
    p->calls++;
    return MOTE_OK;
}

static void test_loop(void)
{
    printf("the run loop: observers on exact schedules\n");
    loop_probe a = {0}, b = {0};
    mote_schedule sa = {0.0, 0.1, 1}, sb = {0.0, 0.25, 1};
    mote_observer obs[2] = {{.at = &sa, .ctx = &a, .fire = probe_fire},
                            {.at = &sb, .ctx = &b, .fire = probe_fire}};
    mote_loop l = {obs, 2, UINT64_MAX, NULL, 0, 1, 0, 0};
    mote_err err = {0};
    double t = 0;
    int stops = 0;
    while (t < 1 && stops < 100) {
        t = mote_loop_stop(&l, 1.0);
        stops++;
        CHECK_INT(mote_loop_fire(&l, &t, t, &err), 0);
    }
    CHECK_INT(a.calls, 10);
    CHECK_INT(b.calls, 4);
    CHECK(a.t[2] == 0.0 + 3 * 0.1 && a.t[9] == 1.0, "times %.17g %.17g", a.t[2], a.t[9]);
    CHECK_INT(stops, 12); /* 0.1 ... 1.0 and 0.25, 0.75 (0.5 coincides with one of a's) */
    CHECK(mote_loop_next(&l) == 0.0 + 11 * 0.1, "next %.17g", mote_loop_next(&l));
    /* a fixed step of 0.35 passes several times: each observer fires once per stop, and its
     * schedule moves past the step's time (no late burst) */
    loop_probe c = {0};
    mote_schedule s1 = {0.0, 0.1, 1};
    mote_observer o1 = {.at = &s1, .ctx = &c, .fire = probe_fire};
    mote_loop l1 = {&o1, 1, UINT64_MAX, NULL, 0, 1, 0, 0};
    double ts = 0.35;
    CHECK_INT(mote_loop_fire(&l1, &ts, ts, &err), 0);
    CHECK_INT(c.calls, 1);
    CHECK(mote_loop_next(&l1) == 0.0 + 4 * 0.1, "after 0.35 the next is %.17g", mote_loop_next(&l1));
    /* a time within 1e-9 of the interval before the end is taken at the end */
    mote_schedule s2 = {0.0, 0.1, 10};
    mote_observer o2 = {.at = &s2, .ctx = &c, .fire = probe_fire};
    mote_loop l2 = {&o2, 1, UINT64_MAX, NULL, 0, 1, 0, 0};
    CHECK(mote_loop_stop(&l2, 1.0 + 1e-12) == 1.0 + 1e-12, "stop %.17g",
          mote_loop_stop(&l2, 1.0 + 1e-12));
    /* count observers (every 3 and every 5 steps) beside a time observer: a stepping model
     * stops at 3, 5, 6, 9, 10, ... and the time calls pass the count observers by */
    loop_probe p3 = {0}, p5 = {0}, pt = {0};
    mote_schedule st = {0.0, 0.5, 1};
    mote_observer oc[3] = {{.ctx = &p3, .fire = probe_fire, .every = 3},
                           {.at = &st, .ctx = &pt, .fire = probe_fire},
                           {.ctx = &p5, .fire = probe_fire, .every = 5}};
    mote_loop lc = {oc, 3, 14, NULL, 0, INFINITY, 0, 0};
    uint64_t n = 0, nstops = 0, stops_at[16];
    while (n < lc.n_end && nstops < 16) {
        n = mote_loop_count_stop(&lc, n, lc.n_end);
        stops_at[nstops++] = n;
        double tn = (double)n;
        CHECK_INT(mote_loop_fire_count(&lc, &tn, n, &err), 0);
    }
    const uint64_t want[] = {3, 5, 6, 9, 10, 12, 14};
    CHECK_INT(nstops, 7);
    for (size_t k = 0; k < 7 && k < nstops; k++)
        CHECK(stops_at[k] == want[k], "stop %zu at %llu, not %llu", k,
              (unsigned long long)stops_at[k], (unsigned long long)want[k]);
    CHECK_INT(p3.calls, 4);
    CHECK_INT(p5.calls, 2);
    CHECK(p5.t[1] == 10.0, "every 5: second call at %g", p5.t[1]);
    CHECK_INT(pt.calls, 0);
    CHECK(mote_loop_next(&lc) == 0.5, "the time observer is next at %g", mote_loop_next(&lc));
    double tt = 1.0;
    CHECK_INT(mote_loop_fire(&lc, &tt, tt, &err), 0);
    CHECK_INT(pt.calls, 1);
    CHECK_INT(p3.calls, 4); /* a time call fires no count observer */
    CHECK(mote_loop_count_stop(&lc, UINT64_MAX - 1, UINT64_MAX) == UINT64_MAX,
          "no multiple fits above UINT64_MAX - 1");
    /* from: every 4 counted from 6 (a dump started at collision 6) fires at 6, 10, 14, 18 */
    loop_probe pf = {0};
    mote_observer of = {.ctx = &pf, .fire = probe_fire, .every = 4, .from = 6};
    mote_loop lf = {&of, 1, 20, NULL, 0, INFINITY, 0, 0};
    uint64_t nf = 0, fstops[8], nfs = 0;
    while (nf < lf.n_end && nfs < 8) {
        nf = mote_loop_count_stop(&lf, nf, lf.n_end);
        fstops[nfs++] = nf;
        double tn = (double)nf;
        CHECK_INT(mote_loop_fire_count(&lf, &tn, nf, &err), 0);
    }
    CHECK(nfs == 5 && fstops[0] == 6 && fstops[1] == 10 && fstops[3] == 18 && fstops[4] == 20,
          "from 6 every 4: %llu stops, first %llu", (unsigned long long)nfs,
          (unsigned long long)fstops[0]);
    CHECK(pf.calls == 4 && pf.t[0] == 6.0 && pf.t[3] == 18.0, "from 6 every 4: %d calls",
          pf.calls);
}

/* A model whose advance goes 7 counts at a time, whatever stop the loop asks for (a step of
 * several collisions): an observer every 5 fires once at each count reached past one or more of
 * its counts (7, 14, 21, 28: past 5, 10, 15 and 20, 25), never twice, never late. */
typedef struct {
    uint64_t n;
    double seen; /* what the probe records: the count */
} coarse_model;
static uint64_t coarse_count(const void *s) { return ((const coarse_model *)s)->n; }
static int coarse_advance(void *s, mote_loop *l, double t_stop, uint64_t n_stop, mote_err *err)
{
    coarse_model *c = s;
    c->n += 7;
    c->seen = (double)c->n;
    return MOTE_OK;
}

static void test_loop_overshoot(void)
{
    mote_err err = {0};
    coarse_model cm = {0, 0};
    loop_probe p = {0};
    const mote_observer o = {.ctx = &p, .fire = probe_fire, .every = 5};
    const mote_runner r = {.what = "test", .sys = &cm, .subject = &cm.seen,
                           .count = coarse_count, .advance = coarse_advance};
    CHECK_INT(mote_run(&r, &o, 1, NULL, INFINITY, 28, &err), 0);
    CHECK_INT(p.calls, 4);
    CHECK(p.t[0] == 7 && p.t[1] == 14 && p.t[2] == 21 && p.t[3] == 28,
          "every 5 past by steps of 7: calls at %g %g %g %g", p.t[0], p.t[1], p.t[2], p.t[3]);
}

/* State files through descriptor tables (statefile.h): what is written reads back the same,
 * older versions skip newer values, and each kind of damage is refused with FILE:LINE. */
typedef struct {
    double t, box[3];
    int order, kind;
    uint32_t n;
    uint64_t steps, rng[2];
    char name[8];
    float w; /* through a codec */
} sf_probe;

static void put_float(char out[64], const void *v) { snprintf(out, 64, "%.9g", (double)*(const float *)v); }
static size_t get_float(const char *t, void *v)
{
    char *end;
    *(float *)v = strtof(t, &end);
    return (size_t)(end - t);
}
static const mote_sf_codec FLOAT_CODEC = {sizeof(float), put_float, get_float, NULL};

#define SFO(m) offsetof(sf_probe, m)
static const mote_sf_field SF_FIELDS[] = {
    {.key = "time", .name = "t", .type = MOTE_SF_DOUBLE, .offset = SFO(t), .lo = 0, .hi = INFINITY},
    {.key = "box", .name = "L", .type = MOTE_SF_DOUBLE, .offset = SFO(box), .count = 3, .lo = 0,
     .hi = 1e300},
    {.key = "scheme", .name = "order", .type = MOTE_SF_INT, .offset = SFO(order), .lo = 2, .hi = 6},
    {.name = "kind", .type = MOTE_SF_ENUM, .offset = SFO(kind), .words = "gravity|coulomb"},
    {.name = "n", .type = MOTE_SF_U32, .offset = SFO(n), .lo = MOTE_SF_ANY},
    {.name = "steps", .type = MOTE_SF_U64, .offset = SFO(steps), .lo = MOTE_SF_ANY, .since = 2},
    {.key = "rng", .name = "s", .type = MOTE_SF_HEX64, .offset = SFO(rng), .count = 2},
    {.key = "name", .name = "name", .type = MOTE_SF_WORD, .offset = SFO(name), .size = 8, .since = 2},
    {.key = "weight", .name = "w", .type = MOTE_SF_CODEC, .offset = SFO(w), .codec = &FLOAT_CODEC},
};
#define SF_N (sizeof SF_FIELDS / sizeof SF_FIELDS[0])

/* Write text into a file of the temporary folder, read it with the table (version v), and
 * return the status; the message into msg. */
static int sf_read_text(const char *text, int v, sf_probe *out, char msg[256])
{
    char path[512];
    snprintf(path, sizeof path, "%s/sf.state", tmpdir);
    FILE *f = fopen(path, "w");
    fputs(text, f);
    fclose(f);
    mote_lines in;
    mote_err err = {0};
    int rc = mote_lines_open(&in, path, &err);
    int version = 0;
    if (!rc)
        rc = mote_sf_read_head(&in, "probe", 2, &version, &err);
    if (!rc && version != v)
        rc = mote_fail(&err, MOTE_EFORMAT, "version %d, not %d", version, v);
    if (!rc)
        rc = mote_sf_read(&in, SF_FIELDS, SF_N, out, version, &err);
    int crc = mote_lines_close(&in, &err);
    snprintf(msg, 256, "%.250s", err.msg);
    const char *base = strstr(msg, "sf.state");
    if (base) /* (the message from the file name on) */
        memmove(msg, base, strlen(base) + 1);
    return crc ? crc : rc;
}

static void test_statefile(void)
{
    printf("state files through descriptor tables\n");
    sf_probe a = {0.1, {1, 2.5, 1e-300}, 4, 1, 7, 12345678901234ull,
                  {0x0123456789abcdefull, 0xfedcba9876543210ull}, "ring", 0.25f};
    char path[512];
    snprintf(path, sizeof path, "%s/sf.state", tmpdir);
    FILE *f = fopen(path, "w");
    mote_sf_write_head(f, "probe", 2);
    mote_sf_write(f, SF_FIELDS, SF_N, &a, 2);
    fclose(f);
    f = fopen(path, "r");
    char text[1024] = "";
    size_t got = fread(text, 1, sizeof text - 1, f);
    text[got] = '\0';
    fclose(f);
    CHECK_STR(text, "mote-state 2\nmodel probe\ntime 0.10000000000000001\nbox 1 2.5 1e-300\n"
                    "scheme 4 coulomb 7 12345678901234\nrng 0123456789abcdef fedcba9876543210\n"
                    "name ring\nweight 0.25\n");
    sf_probe b;
    memset(&b, 0, sizeof b);
    char msg[256];
    CHECK_INT(sf_read_text(text, 2, &b, msg), MOTE_OK);
    CHECK(a.t == b.t && memcmp(a.box, b.box, sizeof a.box) == 0 && a.order == b.order &&
              a.kind == b.kind && a.n == b.n && a.steps == b.steps && a.rng[0] == b.rng[0] &&
              a.rng[1] == b.rng[1] && strcmp(a.name, b.name) == 0 && a.w == b.w,
          "read back differs: t %g n %u steps %llu name %s", b.t, b.n,
          (unsigned long long)b.steps, b.name);
    /* version 1: no steps value, no name line; those fields keep what they had */
    sf_probe c;
    memset(&c, 0, sizeof c);
    c.steps = 99;
    CHECK_INT(sf_read_text("mote-state 1\nmodel probe\ntime 0\nbox 1 1 1\nscheme 2 gravity 3\n"
                           "rng 1 2\nweight -1.5\n", 1, &c, msg), MOTE_OK);
    CHECK(c.steps == 99 && c.name[0] == '\0' && c.n == 3 && c.rng[1] == 2 && c.w == -1.5f,
          "version 1: steps %llu n %u", (unsigned long long)c.steps, c.n);
    /* "-" is the empty word, and it is written so */
    CHECK_INT(sf_read_text("mote-state 2\nmodel probe\ntime inf\nbox 1 1 1\nscheme 2 gravity 3 4\n"
                           "rng 1 2\nname -\nweight 1\n", 2, &c, msg), MOTE_OK);
    CHECK(c.name[0] == '\0' && isinf(c.t), "name '%s' t %g", c.name, c.t);
    /* damage, each with its line and what was expected */
    static const char *const H = "mote-state 2\nmodel probe\n";
    struct { const char *body, *want; } bad[] = {
        {"tim 0\n", "sf.state:3: expected 'time t' (found 'tim 0')"},
        {"time 0\nbox 1 2\n", "sf.state:4: expected 'box L[3]': L[2] is missing (found 'box 1 2')"},
        {"time 0\nbox 1 2 x\n", "sf.state:4: L[2]: expected a real number, found 'x'"},
        {"time -1\n", "sf.state:3: t must be in [0, inf], found -1"},
        {"time nan\n", "sf.state:3: t: expected a real number, found 'nan'"},
        {"time 0\nbox 1 1 1\nscheme 7 gravity 1 1\n", "sf.state:5: order must be in [2, 6], found 7"},
        {"time 0\nbox 1 1 1\nscheme 2 gravitation 1 1\n",
         "sf.state:5: kind: expected one of the words gravity|coulomb, found 'gravitation'"},
        {"time 0\nbox 1 1 1\nscheme 2 gravity -1 1\n", "sf.state:5: n: expected a non-negative integer, found '-1'"},
        {"time 0\nbox 1 1 1\nscheme 2 gravity 1 1 5\n", "sf.state:5: unexpected text after 'scheme order kind n steps' ('5')"},
        {"time 0\nbox 1 1 1\nscheme 2 gravity 1 1\nrng 1 g\n", "sf.state:6: s[1]: expected 16 hexadecimal digits, found 'g'"},
        {"time 0\nbox 1 1 1\nscheme 2 gravity 1 1\nrng 1 2\nname toolongname\n", "sf.state:7: name: expected a word, found 'toolongname'"},
        {"time 0\nbox 1 1 1\nscheme 2 gravity 1 1\nrng 1 2\nname a\n", "sf.state:8: expected 'weight w' (found 'end of file')"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char t[512];
        snprintf(t, sizeof t, "%s%s", H, bad[k].body);
        int rc = sf_read_text(t, 2, &c, msg);
        CHECK(rc == MOTE_EFORMAT && strcmp(msg, bad[k].want) == 0, "damage %zu: '%s', not '%s'",
              k, msg, bad[k].want);
    }
    /* a descriptor that gives no range accepts any finite value (a range left out is not [0, 0]) */
    static const mote_sf_field NORANGE[] = {{.key = "x", .name = "x", .type = MOTE_SF_DOUBLE}};
    snprintf(path, sizeof path, "%s/nr.state", tmpdir);
    f = fopen(path, "w");
    fputs("x 5\n", f);
    fclose(f);
    mote_lines in;
    mote_err err = {0};
    double x = 0;
    CHECK_INT(mote_lines_open(&in, path, &err), MOTE_OK);
    CHECK_INT(mote_sf_read(&in, NORANGE, 1, &x, 1, &err), MOTE_OK);
    CHECK(x == 5, "no range: read %g, %s", x, err.msg);
    mote_lines_close(&in, &err);
    CHECK_INT(sf_read_text("mote-state 3\nmodel probe\n", 2, &c, msg), MOTE_EFORMAT);
    CHECK_STR(msg, "sf.state:1: unsupported state file version 3 (this mote reads 1 to 2)");
    CHECK_INT(sf_read_text("mote-state 2\nmodel other\n", 2, &c, msg), MOTE_EFORMAT);
    CHECK_STR(msg, "sf.state:2: expected 'model probe' (a state of the probe model; found 'model other')");
}

int main(void)
{
    if (!test_tmpdir_make(tmpdir, sizeof tmpdir, "mote_test_core"))
        return 1;
    test_datafile_round_trip();
    test_datafile_hostile();
    test_blocks_and_schedules();
    test_grid();
    test_csv();
    test_rows();
    test_loop();
    test_loop_overshoot();
    test_statefile();
    test_remove_tree(tmpdir);
    return test_summary();
}
