/* fuzz.h: the entry points of mote's fuzz targets, one per input the program reads from users:
 * scripts (parse and validate), hard-sphere state files (mote's and the original program's),
 * mixing-box and N-body state files, and the data files `plot` reads (every model). Each takes arbitrary
 * bytes and must return without crashing, hanging or leaking, whatever they are.
 *
 * They are built two ways: with libFuzzer (`make fuzz`, clang -fsanitize=fuzzer,address,undefined:
 * fuzz/main_libfuzzer.c), and with tests/test_fuzz.c, which replays the corpus and every crasher
 * kept in fuzz/corpus/<target>/ in `make check` (plain and under the sanitizers). */
#ifndef MOTE_FUZZ_H
#define MOTE_FUZZ_H

#include <stddef.h>
#include <stdint.h>

typedef struct {
    const char *name;
    int (*run)(const uint8_t *data, size_t size);
} mote_fuzz_target;

extern const mote_fuzz_target mote_fuzz_targets[];
extern const size_t mote_fuzz_ntargets;

/* The target called name, or NULL. */
const mote_fuzz_target *mote_fuzz_find(const char *name);

#endif
