/* main_libfuzzer.c: one libFuzzer binary per target; the target is chosen at build time by
 * -DMOTE_FUZZ_TARGET="name" (see `make fuzz`). */
#include "fuzz.h"

#include <stdio.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const mote_fuzz_target *t; /* looked up once */
    if (!t && !(t = mote_fuzz_find(MOTE_FUZZ_TARGET))) {
        fprintf(stderr, "no fuzz target '%s'\n", MOTE_FUZZ_TARGET);
        abort();
    }
    return t->run(data, size);
}
