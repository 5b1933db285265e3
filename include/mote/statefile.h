/* statefile.h: state files and checkpoints written and read through descriptor tables (issue
 * 34). A state file is text: "mote-state V", "model NAME", then lines "KEY v1 v2 ..." in a fixed
 * order, and tables of rows. A model describes each value once (its key, name, type, offset in
 * a structure, count and allowed range); the core writes the lines and reads them back strictly,
 * refusing a malformed line with "FILE:LINE: expected 'KEY NAME1 NAME2 ...' (found '...')" or the
 * value that is out of range, so every model's files are read alike.
 *
 * A line is a descriptor with a key followed by descriptors with key NULL (more values on the
 * same line); a row of a table is a line whose first descriptor's key is "". A value appears
 * from file version `since` on: reading an older file skips it (the structure keeps what it
 * had), and a line whose first value is skipped is absent from the older file; a line may also
 * end at an `optional` value. */
#ifndef MOTE_STATEFILE_H
#define MOTE_STATEFILE_H

#include "mote/core.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef enum {
    MOTE_SF_DOUBLE, /* double, written with 17 significant digits (reads back the same) */
    MOTE_SF_INT,    /* int */
    MOTE_SF_U32,    /* uint32_t */
    MOTE_SF_I64,    /* int64_t */
    MOTE_SF_U64,    /* uint64_t, decimal */
    MOTE_SF_HEX64,  /* uint64_t, 16 hexadecimal digits (random-stream states) */
    MOTE_SF_ENUM,   /* int: the index of a word of `words` ("gravity|coulomb") */
    MOTE_SF_WORD,   /* char[size]: one word without blanks; "-" stands for the empty word */
    MOTE_SF_CODEC   /* a type of the model's (e.g. long double) through `codec` */
} mote_sf_type;

/* A model's own number type: its size, how to write one (at most 63 characters) and how to read
 * one (returns the characters used, 0 when the text is not a valid value). */
typedef struct {
    size_t size;
    void (*put)(char out[64], const void *value);
    size_t (*get)(const char *text, void *value);
    int (*finite)(const void *value); /* NULL: every value read is accepted */
} mote_sf_codec;

/* Doubles as mote_fmt_exact writes them (17 digits, -0 as 0), read back as finite decimal
 * numbers only (no hexadecimal, inf or nan): the codec of the files that always wrote so. Its
 * two functions also serve a model's codec that adds words ("auto", "none"). */
void mote_sf_exact_put(char out[64], const void *value);
size_t mote_sf_exact_get(const char *text, void *value);
extern const mote_sf_codec mote_sf_exact;

typedef struct mote_sf_field {
    const char *key;    /* the line's key ("time", "placed x_l"); NULL: the same line; "": a row */
    const char *name;   /* the value's name, for messages ("T") */
    mote_sf_type type;
    size_t offset;      /* of the (first) value in the structure */
    int count;          /* consecutive values of this type (an array); 0 counts as 1 */
    double lo, hi;      /* numbers: the allowed range (lo <= v <= hi); lo > hi, or both 0 (not
                         * given): any finite value */
    int since;          /* the first file version with this value (0 or 1: every version) */
    int optional;       /* the line may end before this value (one added to the format within a
                         * version): it and the values after it then keep what they had */
    const char *words;  /* ENUM: the allowed words, "a|b|c" */
    size_t size;        /* WORD: the size of the char array */
    const mote_sf_codec *codec; /* CODEC */
} mote_sf_field;

/* An allowed range for a descriptor's lo, hi (MOTE_SF_ANY: none, as leaving both out). */
#define MOTE_SF_ANY 1.0, 0.0

/* "mote-state VERSION\nmodel MODEL\n" */
void mote_sf_write_head(FILE *out, const char *model, int version);
/* The two head lines: the version (1 ... vmax) into *version, and the model's name. */
int mote_sf_read_head(mote_lines *in, const char *model, int vmax, int *version, mote_err *err);

/* Write the lines of f[0 .. n) for `version` (values newer than it are left out). */
void mote_sf_write(FILE *out, const mote_sf_field *f, size_t n, const void *base, int version);
/* The descriptor named by key: a line's key ("gravity"), or a line's key, a dot and the name of
 * one of that line's values ("scheme.compensated"); its index, or n when there is none. */
size_t mote_sf_find(const mote_sf_field *f, size_t n, const char *key);
/* Read the lines of f[0 .. n) written by `version`, in their order, into base. On an error base
 * may hold part of the values: read into a scratch structure and keep it only on success. */
int mote_sf_read(mote_lines *in, const mote_sf_field *f, size_t n, void *base, int version,
                 mote_err *err);
/* Read one line of f[0 .. n) (one key and its values, or one row) from the text s, the line
 * in->line of in->path; for a model that reads its own line first (a table that may end). */
int mote_sf_parse_line(const mote_lines *in, const char *s, const mote_sf_field *f, size_t n,
                       void *base, int version, mote_err *err);

#endif
