/* core.h: the bottom layer of mote: error values, the seeded random generator, compensated sums
 * and atomic file output. Everything above (engines, models, the script language) builds on these
 * and nothing here knows about any model. No function in this layer keeps global state. */
#ifndef MOTE_CORE_H
#define MOTE_CORE_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define MOTE_VERSION "0.1.0"

/* Constants (M_PI is not in ISO C). */
#define MOTE_PI 3.14159265358979323846
#define MOTE_SQRT2 1.41421356237309504880

/* ---- errors are values ------------------------------------------------------------------- */

typedef enum {
    MOTE_OK = 0,
    MOTE_EINVAL,   /* bad argument or value */
    MOTE_EIO,      /* a file could not be opened, read or written */
    MOTE_EFORMAT,  /* a file was readable but malformed */
    MOTE_ENOMEM,   /* allocation failed */
    MOTE_ERUNTIME  /* the simulation itself failed (stall, watchdog, failed check) */
} mote_status;

typedef struct {
    mote_status code;
    int located; /* msg already starts with "FILE:LINE:COL: error: " */
    char msg[1024];
} mote_err;

/* Record an error (printf-style message) and return its code, so callers can write
 * `return mote_fail(err, MOTE_EINVAL, "...", ...);`. err may be NULL. */
int mote_fail(mote_err *err, mote_status code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
void mote_err_clear(mote_err *err);

/* ---- random numbers: xoshiro256** seeded through SplitMix64 (Blackman & Vigna) ------------- */

typedef struct {
    uint64_t s[4];
} mote_rng;

void mote_rng_seed(mote_rng *rng, uint64_t seed);
uint64_t mote_rng_next(mote_rng *rng);
/* Uniform double in [0, 1): (next >> 11) * 2^-53. */
double mote_rng_uniform(mote_rng *rng);

/* Standard normal variates from the Marsaglia polar method. Both values of each pair are used,
 * in order; the spare lives in this small struct, not in the generator, so the generator's state
 * is exactly its four words. */
typedef struct {
    mote_rng *rng;
    int has_spare;
    double spare;
    uint64_t uniforms; /* uniform draws taken so far (to report the stream position) */
} mote_normal;

void mote_normal_init(mote_normal *g, mote_rng *rng);
double mote_normal_next(mote_normal *g);

/* ---- compensated (Neumaier) summation ------------------------------------------------------ */

typedef struct {
    double sum, comp;
} mote_ksum;

static inline void mote_ksum_add(mote_ksum *k, double x)
{
    double t = k->sum + x;
    if ((k->sum >= 0 ? k->sum : -k->sum) >= (x >= 0 ? x : -x))
        k->comp += (k->sum - t) + x;
    else
        k->comp += (x - t) + k->sum;
    k->sum = t;
}
static inline double mote_ksum_value(const mote_ksum *k) { return k->sum + k->comp; }

/* ---- atomic output files ------------------------------------------------------------------- */

/* A file written under a temporary name in the target's directory and renamed over the target
 * only by mote_afile_commit. mote_afile_abort (or a failed commit) removes the temporary file and
 * leaves any earlier target untouched. */
typedef struct {
    FILE *f;
    char *path;
    char *tmp;
} mote_afile;

int mote_afile_open(mote_afile *af, const char *path, mote_err *err);
int mote_afile_commit(mote_afile *af, mote_err *err);
void mote_afile_abort(mote_afile *af);

/* Does the directory that would hold `path` exist? (used by script validation) */
int mote_dir_of_exists(const char *path);

/* ---- text input, line by line -------------------------------------------------------------- */

/* A text file read one line at a time, any length, with the line number for messages. */
typedef struct {
    FILE *f;
    const char *path; /* as given to mote_lines_open (not copied) */
    long line;        /* number of the line last returned, from 1 */
    char *buf;
    size_t cap;
} mote_lines;

/* Open path for reading; fails with "PATH: cannot open: REASON". */
int mote_lines_open(mote_lines *r, const char *path, mote_err *err);
/* The next line without its LF or CRLF, or NULL at the end of the file (or on a read error, which
 * mote_lines_close reports). A line holding a NUL byte comes back empty: not a text file. */
char *mote_lines_next(mote_lines *r);
/* Close; MOTE_EIO with "PATH: read error" if reading failed, else MOTE_OK. */
int mote_lines_close(mote_lines *r, mote_err *err);

/* ---- small helpers -------------------------------------------------------------------------- */

/* Wall-clock seconds from a monotonic clock (for progress and rates only; never for results). */
double mote_wall_seconds(void);

/* Peak resident set size of this process in bytes, or 0 if unknown. */
size_t mote_peak_rss_bytes(void);

/* Format a double like "%.17g" but write negative zero as "0". buf must hold 32 bytes. */
void mote_fmt_exact(char *buf, double x);

#endif
