/* core.h: the bottom layer of mote: error values, the seeded random generator, compensated sums
 * and atomic file output. Everything above (engines, models, the script language) builds on these
 * and nothing here knows about any model. No function in this layer keeps global state. */
#ifndef MOTE_CORE_H
#define MOTE_CORE_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <time.h>

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
    MOTE_ERUNTIME, /* the simulation itself failed (stall, watchdog, failed check) */
    MOTE_EINTR     /* stopped by the user (Ctrl-C) at a safe point: mote_interrupted */
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
    char *tmp;   /* where the data is while written: a name, or /proc/self/fd/N (anon) */
    int anon;    /* the data has no name until commit (O_TMPFILE): a killed run leaves none */
    int as;      /* a data file's form on the disk: MOTE_AS_NAME (CSV under a .csv name, else
                  * as written; set by open), MOTE_AS_CSV or MOTE_AS_JSONL (a .csv name: CSV) */
} mote_afile;
enum { MOTE_AS_NAME, MOTE_AS_CSV, MOTE_AS_JSONL };

int mote_afile_open(mote_afile *af, const char *path, mote_err *err);
int mote_afile_commit(mote_afile *af, mote_err *err);
void mote_afile_abort(mote_afile *af);

/* A file followed while a run writes it: PATH.partial, its rows appended and flushed as they
 * come (a user can `tail -f` it; a run that is stopped or fails leaves it, readable, with every
 * row so far). The complete PATH is still written atomically when the run ends, and then the
 * partial file is removed (mote_partial_done): an earlier complete PATH is never touched by a
 * run that does not end. f is NULL when the file could not be made (the run goes on: the
 * complete file is the result; the open returns the errno value). */
typedef struct {
    FILE *f;
    char *path; /* PATH.partial */
} mote_partial;

int mote_partial_open(mote_partial *p, const char *path);
/* The row just written is flushed to the disk's cache (readers see it). */
void mote_partial_flush(mote_partial *p);
/* Closed and removed (the complete file is written). */
void mote_partial_done(mote_partial *p);
/* Closed, kept (the run stopped: its rows so far). */
void mote_partial_keep(mote_partial *p);

/* The rows of a monitor or time series (the output layer's file policy, every model alike): each
 * row is formatted once, into a memory stream of all the rows (text); while a run goes on they
 * are followed in PATH.partial (mote_rows_follow: flushed at each row, `tail -f`; a run that is
 * stopped or fails leaves it, readable); PATH is written whole and atomically when a run ends
 * (mote_rows_write: also after a failure, every row so far), and when the output starts if
 * there is no PATH yet (mote_rows_start): an earlier complete PATH is replaced only by a
 * complete one. Memory stays bounded: past `spill` bytes the rows move to an unnamed file in
 * PATH's folder (the system's temporary folder when that fails; memory when both do), read back
 * for PATH. A .csv PATH becomes RFC 4180 CSV when written (mote_afile_commit). The
 * model's header(f, arg, growing) writes the header lines (growing: for the partial file, whose
 * rows are still coming). */
#define MOTE_ROWS_SPILL ((size_t)1 << 20)
typedef struct {
    char *path;
    FILE *text;   /* the model prints its rows here (the same FILE for the whole output) */
    char *buf;    /* (the memory stream's bytes) */
    size_t len;
    size_t sent;  /* bytes of buf already in PATH.partial */
    size_t rows;  /* rows counted by mote_rows_follow */
    FILE *store;  /* rows moved out of memory (an unnamed file beside PATH), when any */
    size_t stored; /* bytes of rows in store (before those in buf) */
    size_t spill; /* memory kept before rows move to store (0: MOTE_ROWS_SPILL) */
    int as;       /* PATH's form (mote_afile.as: format=table|csv|jsonl, their indexes); the
                   * partial file is always the table */
    mote_partial partial;
    void (*header)(FILE *f, const void *arg, int growing);
    const void *arg;
} mote_rows;

int mote_rows_open(mote_rows *r, const char *path,
                   void (*header)(FILE *f, const void *arg, int growing), const void *arg,
                   mote_err *err);
/* The row (or rows) just printed into r->text, to PATH.partial: begun with the header and every
 * row so far when it is not open (the first row; the first of a later run). */
int mote_rows_follow(mote_rows *r, mote_err *err);
/* The first row(s), printed at the command: followed, and PATH written when there is none. */
int mote_rows_start(mote_rows *r, mote_err *err);
/* PATH whole: the header and every row, atomically; PATH.partial removed. */
int mote_rows_write(mote_rows *r, mote_err *err);
/* A run that ended without writing PATH: PATH.partial closed and kept. */
void mote_rows_keep(mote_rows *r);
/* The end of a run whose result is rc: PATH whole (also after a failure: every row so far),
 * PATH.partial kept when that cannot be written; a run stopped by the user (rc MOTE_EINTR)
 * keeps its rows in PATH.partial and leaves an earlier PATH as it was, as a run killed would.
 * Returns rc, or the write's error after a run that succeeded. */
int mote_rows_end(mote_rows *r, int rc, mote_err *err);
/* Freed (PATH.partial kept); a zeroed mote_rows may be freed. */
void mote_rows_free(mote_rows *r);

/* A growing file of frames (a trajectory, extended XYZ: the output layer's `trajectory` in
 * every model): the first frame is written atomically (mote_frames_first: an earlier file is
 * replaced only by a complete frame), later frames are appended whole (mote_frames_append: a
 * frame that fails to write is cut off again, so the file always ends with a complete frame;
 * `tail -f` follows it, and a run that is stopped keeps every frame so far). frame(f, arg, err)
 * writes one frame. */
typedef int (*mote_frame_writer)(FILE *f, const void *arg, mote_err *err);
int mote_frames_first(const char *path, mote_frame_writer frame, const void *arg, mote_err *err);
int mote_frames_append(const char *path, mote_frame_writer frame, const void *arg, mote_err *err);

/* The CLOCK_REALTIME time `seconds` from now, for pthread_cond_timedwait (a wait that also
 * looks at something else now and then). */
struct timespec mote_deadline(double seconds);

/* Does the directory that would hold `path` exist? (used by script validation) */
int mote_dir_of_exists(const char *path);
/* Make the folders of path that do not exist yet (the folder of a prefix=, which the script's
 * check allowed when its parent exists); 0 or an errno value. A numbered file's writer calls it
 * before it opens the file; mote_afile_open itself never makes folders. */
int mote_make_dir_of(const char *path);

/* The name of file k of a numbered series: prefix, an '_' unless the prefix is empty or ends in
 * '_' or '/', k in `digits` digits, ext ("out/f", 3, 6, ".png": "out/f_000003.png"). Malloc'ed
 * (NULL when out of memory). Every model names its numbered files so. */
char *mote_series_path(const char *prefix, uint64_t k, int digits, const char *ext);
/* The '_' or "" that goes between the prefix and the number. */
const char *mote_series_sep(const char *prefix);

/* ---- text input, line by line -------------------------------------------------------------- */

/* The longest line any mote reader accepts (1 MiB): a file with a longer line (/dev/zero, a binary
 * file) is refused with "FILE:LINE: line longer than 1 MiB" instead of growing a buffer without
 * bound. */
#define MOTE_LINE_MAX ((size_t)1 << 20)

/* Read one line (with its '\n', if any) into *buf (grown as needed, NUL-terminated); *len gets its
 * length in bytes, which may exceed strlen(*buf) when the line holds a NUL byte. Returns 1 for a
 * line, 0 at the end of the file or on a read error (ferror tells), -1 for a line longer than
 * `max` bytes (the rest of that line is not read), -2 when memory runs out. */
int mote_read_line(char **buf, size_t *cap, size_t *len, FILE *f, size_t max);

/* A text file read one line at a time, at most `max` bytes a line (MOTE_LINE_MAX unless raised),
 * with the line number for messages. */
typedef struct {
    FILE *f;
    const char *path; /* as given to mote_lines_open (not copied) */
    long line;        /* number of the line last returned, from 1 */
    char *buf;
    size_t cap;
    int failed;       /* 0, or why reading stopped early: -1 a line too long, -2 out of memory */
    size_t max;       /* the longest line accepted: MOTE_LINE_MAX after mote_lines_open (a reader
                         of mote's own files may raise it) */
} mote_lines;

/* Open path for reading; fails with "PATH: cannot open: REASON" (a directory is refused too). */
int mote_lines_open(mote_lines *r, const char *path, mote_err *err);
/* The next line without its LF or CRLF, or NULL at the end of the file, on a read error, or on a
 * line longer than MOTE_LINE_MAX (mote_lines_close reports the last two). A line holding a NUL
 * byte comes back empty: not a text file. */
char *mote_lines_next(mote_lines *r);
/* Close. If reading stopped on an error (a read error, a line too long, memory), that error is
 * written to err (replacing any message there: it is the cause) and returned; else MOTE_OK and
 * err is left alone. Callers write `crc = mote_lines_close(&in, err); return crc ? crc : rc;`. */
int mote_lines_close(mote_lines *r, mote_err *err);

/* ---- small helpers -------------------------------------------------------------------------- */

/* The machine's physical memory in bytes (0 if unknown). */
double mote_mem_physical(void);
/* Memory a command would need, checked before it allocates: above 3/4 of the machine's physical
 * memory the command is refused with "WHAT needs about X GB, more than 3/4 of this machine's
 * Y GB" (MOTE_ENOMEM). Each command also has its own documented count limits. */
int mote_mem_check(double bytes, const char *what, mote_err *err);

/* Wall-clock seconds from a monotonic clock (for progress and rates only; never for results). */
double mote_wall_seconds(void);
/* The wall-clock gap before an output made for a watcher (the live picture, a live view's frame)
 * is due again, when the last one took `cost` seconds to make: at least min_gap, and at least
 * MOTE_PACE_SHARE_INV times the cost, so such outputs take at most a tenth of a run's time
 * however large the system (a picture of 10^4 particles takes tens of milliseconds). */
enum { MOTE_PACE_SHARE_INV = 10 };
double mote_pace_gap(double min_gap, double cost);

/* Peak resident set size of this process in bytes, or 0 if unknown. */
size_t mote_peak_rss_bytes(void);

/* Format a double like "%.17g" but write negative zero as "0". buf must hold 32 bytes. */
void mote_fmt_exact(char *buf, double x);
/* The shortest of "%.15g", "%.16g" and "%.17g" that reads back as x (0.015, not
 * 0.014999999999999999), negative zero as "0". buf must hold 32 bytes. */
void mote_fmt_short(char *buf, double x);

/* ---- threads that never spin on a busy machine ---------------------------------------------- */

/* libgomp's threads spin 300 000 rounds at every barrier before they sleep: on a machine whose
 * other cores are busy, a thread spins while the partner it waits for is descheduled, and two
 * threads ran 25x slower than one (the separator's column, two busy processes beside it). A
 * spin count of 1000 (libgomp's own count for an oversubscribed machine) keeps a quiet machine's
 * speed within the noise and a loaded one's; OMP_WAIT_POLICY=PASSIVE cost a quiet machine 16%
 * (bench/threads.sh, bench/README.md). This sets GOMP_SPINCOUNT=1000 unless the user set
 * GOMP_SPINCOUNT or OMP_WAIT_POLICY. libgomp reads them once, when it starts, so it must run
 * before: MOTE_PROGRAM_THREADS in a program that links libgomp statically (as the Makefile links
 * mote, the tests and the benchmarks) does it in a constructor that runs first; the Python
 * package sets it before it loads its extension. */
void mote_threads_quiet(void);
#define MOTE_PROGRAM_THREADS                                                                      \
    __attribute__((constructor(101))) static void mote_program_threads_(void)                  \
    {                                                                                           \
        mote_threads_quiet();                                                                   \
    }

#endif
