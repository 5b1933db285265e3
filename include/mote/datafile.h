/* datafile.h: the text data files every model writes and `plot` reads, and the result lines of
 * measurements. A data file is
 *
 *     # mote FORMAT 1                       what it is (the kind `plot` recognises)
 *     # command: SOURCE   (FILE:LINE)       the command that wrote it
 *     # program: mote VERSION; seed = S
 *     # key = value                         header numbers (the model's own)
 *     # key = value ± error                 results of the measurement
 *     # columns: name name ...              one name per column
 *     1 2 3                                 rows of numbers; a blank line starts a new block
 *
 * written atomically (mote_afile), and read back by mote_table_read with every row's file line
 * kept for messages. Nothing here knows a model. */
#ifndef MOTE_DATAFILE_H
#define MOTE_DATAFILE_H

#include "mote/core.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>

/* ---- results: named values with a statistical error ------------------------------------------ */

#define MOTE_RESULT_MAX 48

typedef struct {
    int n;
    struct {
        char key[32];
        double value, error; /* error NaN when unknown */
    } kv[MOTE_RESULT_MAX];
} mote_result;

/* Append (key, value, error); silently ignored when full or when res is NULL. */
void mote_result_add(mote_result *res, const char *key, double value, double error);
/* The entry named key, or NULL. */
const double *mote_result_get(const mote_result *res, const char *key, double *error);
/* Print "label: key=value key_err=error ..." on one line (errors only where known). */
void mote_result_print(const mote_result *res, const char *label, FILE *out);
/* Write "# key = value ± error" lines into a data file's header. */
void mote_result_write(const mote_result *res, FILE *f);

/* ---- writing ---------------------------------------------------------------------------------- */

typedef struct {
    mote_afile af;
    FILE *f; /* the open file: the model writes its header lines and rows here */
} mote_datafile;

/* The first three header lines of every data file ("# mote FORMAT 1", "# command: ...",
 * "# program: ..."), for writers that open the file themselves. */
void mote_datafile_preamble(FILE *f, const char *format, const char *origin, uint64_t seed);
/* Open `path` atomically and write the first three header lines. origin: the command as
 * mote_call_origin gives it (NULL: "(library call)"). */
int mote_datafile_open(mote_datafile *d, const char *path, const char *format, const char *origin,
                       uint64_t seed, mote_err *err);
/* "# columns: NAMES" */
void mote_datafile_columns(mote_datafile *d, const char *names);
/* Check the stream for write errors and rename the file into place. */
int mote_datafile_commit(mote_datafile *d, mote_err *err);
void mote_datafile_abort(mote_datafile *d);

/* ---- CSV ---------------------------------------------------------------------------------------- */

/* Does path name a CSV file (it ends in ".csv", any case)? A data file written under such a name
 * becomes RFC 4180 CSV when its atomic file is committed (mote_afile_commit): what pandas,
 * Python's csv and spreadsheets read. */
int mote_path_is_csv(const char *path);
/* Write the data file at in_path to out as RFC 4180 CSV: the "# columns:" names as the header
 * row, then every row (its fields separated by blanks, or by commas in a row without blanks),
 * fields separated by commas (quoted where they hold a comma or a quote; quotes doubled), lines
 * ended by CR LF. The other header lines are left out (the
 * data-file form keeps them); a file of several blocks gets a first column "block" (0, 1, ...).
 * A file that is not a data file (its first line is not "# mote ...") is copied unchanged. */
int mote_datafile_csv(const char *in_path, FILE *out, mote_err *err);
/* The data file in_path as JSON lines (format=jsonl): one object per row, {"format":"KIND",
 * "COLUMN":value, ...} in the columns' order (KIND from the first line; a file of several
 * blocks adds "block"); a number is written as JSON reads it (as written when it is JSON's
 * syntax, else to 17 digits), nan and inf as null, a word as a string; the header lines are
 * left out. A file that is not a data file is copied unchanged. */
int mote_datafile_jsonl(const char *in_path, FILE *out, mote_err *err);

/* ---- reading ---------------------------------------------------------------------------------- */

/* Columns kept per row (tokens beyond are counted in ncol, not stored), and the most numbers a
 * table holds (rows times its widest row): a larger file is refused, not allocated. */
#define MOTE_TABLE_MAXCOL 4096
#define MOTE_TABLE_MAXCELLS ((size_t)1 << 27)

typedef struct {
    char format[32];          /* from "# mote FORMAT 1" ("" when the first line is not that) */
    char command[256];        /* from "# command: " */
    size_t nkeys;             /* header lines "# key = number": */
    char (*key)[32];
    double *keyval;
    int ncolnames;            /* from "# columns:" (0 when absent) */
    char (*colname)[32];      /* their names */
    size_t rows;              /* data rows: */
    size_t width;             /* numbers kept per row: the widest row (at most MOTE_TABLE_MAXCOL) */
    double *num;              /* rows * width numbers (a text token reads as NaN, a short row is
                               * padded with NaN) */
    int *ncol;                /* tokens on each row */
    int *block;               /* 0, 1, ...: blocks are separated by blank lines */
    long *line;               /* the file line of each row */
    char (*first)[16];        /* the first token of each row as text */
    size_t cap;
} mote_table;

/* Read a whole data file. Fails (naming the file and line) when it cannot be read, when a line
 * holds a NUL byte or the file is larger than 1 GiB. Rows are not checked against the columns:
 * the reader of each format knows what its rows hold. */
int mote_table_read(mote_table *t, const char *path, mote_err *err);
void mote_table_free(mote_table *t);

/* The value of header key `key`, or NaN when absent. */
double mote_table_key(const mote_table *t, const char *key);
/* Does the header have key `key`? */
int mote_table_has(const mote_table *t, const char *key);
/* The index of the column called `name` in "# columns:", or -1. */
int mote_table_col(const mote_table *t, const char *name);
/* Row r, column c (NaN beyond the row). */
static inline double mote_table_at(const mote_table *t, size_t r, int c)
{
    return c >= 0 && (size_t)c < t->width ? t->num[r * t->width + (size_t)c] : NAN;
}

#endif
