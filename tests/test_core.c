/* test_core.c: the shared core every model stands on: data files written and read back (header,
 * keys, results, columns, blocks, file lines, words among numbers, hostile files), results,
 * block statistics and sampling schedules. */
#include "mote/datafile.h"
#include "mote/stats.h"
#include "test.h"

#include <math.h>
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

int main(void)
{
    if (!test_tmpdir_make(tmpdir, sizeof tmpdir, "mote_test_core"))
        return 1;
    test_datafile_round_trip();
    test_datafile_hostile();
    test_blocks_and_schedules();
    test_remove_tree(tmpdir);
    return test_summary();
}
