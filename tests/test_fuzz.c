/* test_fuzz.c: every input kept in fuzz/corpus/<target>/ through its fuzz target
 * (fuzz/targets.c): the fuzzer's minimised corpus (files named by their SHA-1), the seeds and
 * every crasher or hang a fuzzer found (named after what it did; these also with their prefixes
 * at line ends, the truncated files users meet), plus the empty input and one byte of every
 * value. In `make check` this
 * runs plain and under ASan + UBSan, so an input that once crashed or leaked fails the suite. The
 * fuzzing itself is `make fuzz` (libFuzzer). */
#include "fuzz.h"
#include "test.h"

#include <dirent.h>
#include <sys/stat.h>

static int run_file(const mote_fuzz_target *t, const char *path, const char *name, size_t *count)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return 0;
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(f);
        return 0;
    }
    size_t n = (size_t)st.st_size;
    uint8_t *buf = malloc(n ? n : 1);
    size_t got = buf ? fread(buf, 1, n, f) : 0;
    fclose(f);
    if (!buf || got != n) {
        free(buf);
        return 0;
    }
    /* a slow-... input takes the reader's whole time bound (seconds of a child process running
     * Assimp, which is not itself sanitized): the plain pass runs it, the sanitized one does not */
    if (strncmp(name, "slow-", 5) == 0 && getenv("MOTE_SANITIZED")) {
        free(buf);
        (*count)++;
        return 1;
    }
    t->run(buf, n);
    if (strlen(name) == 40 && strspn(name, "0123456789abcdef") == 40) { /* a fuzzer's unit */
        free(buf);
        (*count)++;
        return 1;
    }
    /* a named one (a seed or a crasher): also prefixes at line ends, the truncated files users meet: at most about 24 per file
     * (a plot target renders a PNG each time); not for one named slow-...: an input a reader
     * takes its full time bound on (Assimp looping until the mesh reader's 10 s processor
     * limit), checked once whole */
    if (strncmp(name, "slow-", 5) == 0) {
        free(buf);
        (*count)++;
        return 1;
    }
    size_t lines = 0, seen = 0;
    for (size_t k = 0; k < n; k++)
        lines += buf[k] == '\n';
    const size_t every = lines / 24 + 1;
    for (size_t k = 0; k < n; k++)
        if (buf[k] == '\n' && ++seen % every == 0)
            t->run(buf, k + 1);
    free(buf);
    (*count)++;
    return 1;
}

int main(int argc, char **argv)
{
    const char *root = argc > 1 ? argv[1] : "fuzz/corpus";
    for (size_t i = 0; i < mote_fuzz_ntargets; i++) {
        const mote_fuzz_target *t = &mote_fuzz_targets[i];
        const double w0 = mote_wall_seconds();
        uint8_t b[1];
        t->run(b, 0);
        for (int v = 0; v < 256; v++) {
            b[0] = (uint8_t)v;
            t->run(b, 1);
        }
        char dir[512];
        snprintf(dir, sizeof dir, "%s/%s", root, t->name);
        DIR *d = opendir(dir);
        CHECK(d != NULL, "no corpus directory %s", dir);
        size_t count = 0;
        if (d) {
            struct dirent *e;
            while ((e = readdir(d))) {
                if (e->d_name[0] == '.')
                    continue;
                char path[1024];
                snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
                run_file(t, path, e->d_name, &count);
            }
            closedir(d);
        }
        CHECK(count > 0, "target %s: no corpus files in %s", t->name, dir);
        printf("fuzz target %s: %zu corpus files (and their prefixes) ran (%.1f s)\n", t->name,
               count, mote_wall_seconds() - w0);
    }
    return test_summary();
}
