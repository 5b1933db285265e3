/* script_internal.h: what the files of src/script share and nobody else needs: the parsed-script
 * struct, the string arena its text lives in, the table of common commands, command lookup and
 * "did you mean" suggestions. */
#ifndef MOTE_SCRIPT_INTERNAL_H
#define MOTE_SCRIPT_INTERNAL_H

#include "mote/script.h"

#include <stdarg.h>
#include <stddef.h>

/* ---- arena: every string and argument array of a script, freed at once ---------------------- */

typedef struct mote_arena_chunk mote_arena_chunk;
typedef struct {
    mote_arena_chunk *head;
} mote_arena;

void *mote_arena_alloc(mote_arena *a, size_t n);
char *mote_arena_strndup(mote_arena *a, const char *s, size_t n);
void mote_arena_free(mote_arena *a);

/* ---- the parsed script ---------------------------------------------------------------------- */

struct mote_script {
    mote_context ctx;
    const mote_model *model;
    int model_line;       /* line of the `model` command, 0 when the model is the default */
    mote_call *calls;     /* malloc'ed; everything the calls point to lives in `arena` */
    size_t ncalls, cap;
    mote_arena arena;
    int validated;
    int threads_noted;    /* the "threads has no effect yet" note was printed */
};

/* ---- common commands (handled by the script layer; their `model` argument is the script) ----- */

extern const mote_cmd mote_script_common_cmds[];
extern const size_t mote_script_common_ncmds;

int mote_script_is_common(const mote_cmd *def);
const mote_cmd *mote_script_common_model_cmd(void);

/* Does `name` equal the command's name or one of its aliases? */
int mote_cmd_matches(const mote_cmd *def, const char *name);
/* The command of the table called `name` (by name or alias), or NULL. */
const mote_cmd *mote_cmd_lookup(const mote_cmd *cmds, size_t n, const char *name);

/* ---- suggestions ---------------------------------------------------------------------------- */

/* Feed candidate names; the nearest within edit distance 2 (case-insensitive, transpositions
 * count once) is the suggestion. */
typedef struct {
    const char *word;
    size_t wlen;
    const char *best;
    size_t blen;
    int bestd;
} mote_suggest;

void mote_suggest_init(mote_suggest *sg, const char *word);
void mote_suggest_feed(mote_suggest *sg, const char *cand, size_t len);
/* Feed a command's name and all its aliases. */
void mote_suggest_feed_cmd(mote_suggest *sg, const mote_cmd *def);
/* Copy the suggestion into buf and return 1, or return 0 when there is none. */
int mote_suggest_result(const mote_suggest *sg, char *buf, size_t cap);

/* ---- errors --------------------------------------------------------------------------------- */

/* "FILE:LINE:COL: error: message", located = 1. Returns code. */
int mote_script_fail_at(mote_err *err, const char *file, int line, int col, mote_status code,
                        const char *fmt, ...) __attribute__((format(printf, 6, 7)));
/* An unlocated message (used for errors about whole files). Returns code. */
int mote_script_fail_plain(mote_err *err, mote_status code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Make sure err is located: prefix the call's position when the command did not. */
void mote_script_locate(mote_err *err, const mote_call *c);

#endif
