/* test.h: the assertions every mote test program uses. Each CHECK counts a pass or prints a
 * failure with its file and line; test_summary() prints "N passed, M failed" on its own line and
 * returns the exit status (non-zero when anything failed, or when nothing was checked at all,
 * since a test that checks nothing cannot fail). Include it in one .c file per test program. */
#ifndef MOTE_TEST_H
#define MOTE_TEST_H

#include <dirent.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "mote/core.h"

MOTE_PROGRAM_THREADS

static int test_passed_, test_failed_;

/* CHECK(cond, fmt, ...): fmt and its arguments explain a failure. */
#define CHECK(cond, ...)                                                                      \
    do {                                                                                      \
        if (cond) {                                                                           \
            test_passed_++;                                                                   \
        } else {                                                                              \
            test_failed_++;                                                                   \
            printf("%s:%d: FAILED: %s: ", __FILE__, __LINE__, #cond);                         \
            printf(__VA_ARGS__);                                                              \
            printf("\n");                                                                     \
            fflush(stdout);                                                                   \
        }                                                                                     \
    } while (0)

/* Integers compared as long long, printing both values. */
#define CHECK_INT(a, b)                                                                       \
    do {                                                                                      \
        long long a_ = (long long)(a), b_ = (long long)(b);                                   \
        CHECK(a_ == b_, "%s = %lld, expected %lld", #a, a_, b_);                              \
    } while (0)

/* Strings equal (NULL counts as different from everything). */
#define CHECK_STR(a, b)                                                                       \
    do {                                                                                      \
        const char *a_ = (a), *b_ = (b);                                                      \
        CHECK(a_ && b_ && strcmp(a_, b_) == 0, "%s = \"%s\", expected \"%s\"", #a,            \
              a_ ? a_ : "(null)", b_ ? b_ : "(null)");                                        \
    } while (0)

/* `hay` contains `needle`. */
#define CHECK_HAS(hay, needle)                                                                \
    do {                                                                                      \
        const char *h_ = (hay), *n_ = (needle);                                               \
        CHECK(h_ && n_ && strstr(h_, n_) != NULL, "%s = \"%s\" lacks \"%s\"", #hay,           \
              h_ ? h_ : "(null)", n_ ? n_ : "(null)");                                        \
    } while (0)

/* |a - b| <= tol (fails on NaN). */
#define CHECK_NEAR(a, b, tol)                                                                 \
    do {                                                                                      \
        double a_ = (a), b_ = (b), t_ = (tol);                                                \
        CHECK(fabs(a_ - b_) <= t_, "%s = %.17g, expected %.17g within %.3g", #a, a_, b_, t_); \
    } while (0)

/* The seed a test uses for its random start: `s` itself, unless MOTE_TEST_SEED=k (a whole number)
 * asks for another realisation, s + k * 1000003. `make seeds` runs the statistical tests this
 * way over many k, which shows whether a tolerance holds for realisations in general or only
 * for the one the fixed seed draws. Seeds that differ stay different. */
static inline uint64_t test_seed(uint64_t s)
{
    const char *e = getenv("MOTE_TEST_SEED");
    return e && *e ? s + strtoull(e, NULL, 10) * 1000003ull : s;
}

static inline int test_summary(void)
{
    printf("%d passed, %d failed\n", test_passed_, test_failed_);
    fflush(stdout);
    return test_failed_ > 0 || test_passed_ == 0;
}


/* A fresh directory /tmp/<name>.XXXXXX for a test's files, written into buf; 0 on failure
 * (after printing why). */
static inline int test_tmpdir_make(char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "/tmp/%s.XXXXXX", name);
    if (!mkdtemp(buf)) {
        printf("cannot create a temporary directory for %s\n", name);
        return 0;
    }
    return 1;
}

/* Whether two files hold the same bytes (both readable). */
static inline int test_same_file(const char *a, const char *b)
{
    FILE *f = fopen(a, "rb"), *g = fopen(b, "rb");
    int same = f && g;
    while (same) {
        const int x = fgetc(f), y = fgetc(g);
        same = x == y;
        if (x == EOF || y == EOF)
            break;
    }
    if (f)
        fclose(f);
    if (g)
        fclose(g);
    return same;
}

/* Remove a file or a directory tree. */
static inline void test_remove_tree(const char *p)
{
    DIR *d = opendir(p);
    if (!d) {
        remove(p);
        return;
    }
    struct dirent *de;
    while ((de = readdir(d))) {
        if (!strcmp(de->d_name, ".") || !strcmp(de->d_name, ".."))
            continue;
        size_t n = strlen(p) + strlen(de->d_name) + 2;
        char *sub = malloc(n);
        if (!sub)
            break;
        snprintf(sub, n, "%s/%s", p, de->d_name);
        test_remove_tree(sub);
        free(sub);
    }
    closedir(d);
    rmdir(p);
}

#endif
