/* script_internal.h: what the files of src/script share and nobody else needs: the parsed-script
 * struct, the string arena its text lives in, the table of common commands, command lookup and
 * "did you mean" suggestions. */
#ifndef MOTE_SCRIPT_INTERNAL_H
#define MOTE_SCRIPT_INTERNAL_H

#include "mote/script.h"
#include "mote/live.h"

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

/* A script variable: `set NAME VALUE`, or NAME=VALUE on the command line (fixed: a later `set`
 * of it keeps the command line's value). */
typedef struct {
    const char *name, *value; /* (in the arena) */
    int fixed, used;
} mote_var;

/* The loops open around the line being read (`for NAME ...` / `end`). */
enum { MOTE_LOOP_DEPTH = 16 };
typedef struct {
    const char *name, *value; /* the loop's variable and its value in this pass */
    int line;                 /* of the `for` */
} mote_loop_pass;

/* An `ensemble K ... end` (ensemble.c): its call, and the calls of each replica. */
typedef struct {
    size_t call;   /* the `ensemble` line's call */
    size_t *start; /* replica r (0-based) is calls start[r] ... start[r + 1] - 1 (in the arena) */
    int K;
} mote_ensemble;

/* A summary= file of ensembles: its header and the rows so far (rewritten after each). */
typedef struct {
    char *path, *origin;
    mote_buf head, rows;
    char (*cols)[64];
    int ncols;
} mote_ens_summary;

struct mote_script {
    mote_context ctx;
    mote_var *vars; /* malloc'ed */
    int nvars, capvars;
    int *vhash, vhcap; /* the variables by name (vars.c; malloc'ed) */
    size_t bytes_read; /* the bytes of the lines read, each pass of a loop's body again (bounded) */
    mote_loop_pass loops[MOTE_LOOP_DEPTH];
    int nloops;
    long lines_read; /* lines read, each pass of a loop's body again (bounded) */
    const mote_model *model;
    int model_line;       /* line of the `model` command, 0 when the model is the default */
    mote_call *calls;     /* malloc'ed; everything the calls point to lives in `arena` */
    size_t ncalls, cap;
    mote_arena arena;
    int validated;
    int threads_noted;    /* the "threads has no effect yet" note was printed */
    void *instance;       /* the model the commands act on while validating or running */
    mote_cmd plot_def;    /* `plot` with the model's plot options (name NULL until needed) */
    /* the live view: asked for by `mote run --live` (port >= 0) or started by `live http` */
    int live_port;
    const char *live_bind;
    mote_live *live;
    mote_buf frame;
    mote_ensemble *ens;   /* malloc'ed, in the order of their calls */
    size_t nens, capens;
    int in_ensemble;      /* reading an ensemble's body */
    mote_ens_summary *sums; /* running: the summary= files written so far */
    int ens_warned;         /* the warning about few replicas was printed */
    size_t nsums;
    const mote_model *const *models; /* the registry it was read with (for more text) */
    size_t nmodels;
    /* a session (session.c): the dry model that has checked every call so far, the lines read */
    void *dry;
    int session_lines;
    FILE *session_out;    /* what the commands print, read back after each */
    int ranks_finished;   /* under mpirun: the ranks' last meeting has happened */
};

/* Read more text into the script (its calls added after the others), the first line numbered
 * `line`; on an error nothing is added. */
int mote_script_append(mote_script *s, const char *text, size_t len, int line, mote_err *err);
/* Forget the calls from `from` on (and the ensembles among them). */
void mote_script_drop(mote_script *s, size_t from);

/* ---- ensembles (ensemble.c) ---- */

/* The ensemble whose `ensemble` line is call `call`, or NULL. */
const mote_ensemble *mote_ensemble_at(const mote_script *s, size_t call);
/* A new ensemble of K replicas at call `call` (its start[] to be filled as the body is read). */
int mote_ensemble_add(mote_script *s, size_t call, int K, mote_ensemble **out);
/* Check the replicas' calls, each replica on a new dry model. */
int mote_ensemble_check(mote_script *s, const mote_ensemble *e, mote_err *err);
/* Run the replicas on the threads, print their output in order, combine their measurements. */
int mote_ensemble_run(mote_script *s, const mote_ensemble *e, mote_err *err);
void mote_ensemble_free_summaries(mote_script *s);
/* Under mpirun: every rank meets here, at an ensemble (finished = 0) or at the end of the script
 * (1, also after an error); returns 1 when some rank has finished, so that a rank whose script
 * stopped early never leaves the others waiting at their next ensemble. */
int mote_ranks_sync(mote_script *s, int finished);
/* run.c: check one call (its arguments, its command's check, its outputs), the error located;
 * run the calls [from, to) on s->instance, with their context s->ctx. */
int mote_script_check_call(mote_script *s, mote_call *c, mote_err *err);
int mote_script_run_calls(mote_script *s, size_t from, size_t to, mote_err *err);

/* ---- lexing (lex.c) ---- */

typedef struct {
    const char *text;
    int line, col, quoted;
} token;

typedef struct {
    token *t;
    int n, cap;
    const char *src_begin, *src_end; /* the line without comment and surrounding blanks */
} token_list;

/* A position inside one line. */
typedef struct {
    const char *p, *end;
    int line, col;
} cursor;

/* Cut one line (cursor c: its text without the line end) into tl's tokens. */
int mote_lex_line(mote_script *s, cursor c, token_list *tl, mote_err *err);
int mote_push_token(token_list *tl, token t);

/* ---- variables (vars.c) ---- */

/* Is s[0 .. n) a variable name (a letter or '_', then letters, digits, '_')? */
int mote_var_name_ok(const char *s, size_t n);
/* The variable NAME (n bytes), or NULL. */
mote_var *mote_vars_find(mote_script *s, const char *name, size_t n);
/* What a value holds that no variable may ("a line break", ...; a value becomes words, file
 * names and header lines), or NULL when it is fine. */
const char *mote_var_value_bad(const char *value);
/* Define or replace NAME (fixed: from the command line; a later non-fixed set keeps it).
 * -1 when out of memory. */
int mote_vars_set(mote_script *s, const char *name, const char *value, int fixed);
/* A number as variables hold it: a whole number to 2^53 with every digit, else 15 significant
 * digits, "%.15g" (0.3, 2000, 1e+20). */
void mote_vars_format(double x, char *buf, size_t cap);
/* text with its ${NAME}, ${EXPR} and $$ replaced (*out: text itself when it has no '$', else a
 * string in the arena); errors located at FILE:LINE:COL, the word's position. */
int mote_vars_expand(mote_script *s, const char *file, int line, int col, const char *text,
                     const char **out, mote_err *err);

/* Append " (in the loop: eta=0.3, n=2)" to a message. */
void mote_script_note_loop(mote_err *err, const char *loop);

/* Start the live view of a running script (port 0: any free one), print its address. */
int mote_script_live_start(mote_script *s, const char *bind, int port, mote_err *err);

/* ---- common commands (handled by the script layer; their `model` argument is the script) ----- */

extern const mote_cmd mote_script_common_cmds[];
extern const size_t mote_script_common_ncmds;

int mote_script_is_common(const mote_script *s, const mote_cmd *def);
/* The definition of `plot` for the script's model: the common one, or with its options. */
const mote_cmd *mote_script_plot_def(mote_script *s);
const mote_cmd *mote_script_common_model_cmd(void);

/* Does `name` equal the command's name or one of its aliases? */
int mote_cmd_matches(const mote_cmd *def, const char *name);
/* The command of the table called `name` (by name or alias), or NULL. */
const mote_cmd *mote_cmd_lookup(const mote_cmd *cmds, size_t n, const char *name);
/* The index of word w in "a|b|c" (-1: none), and "a, b or c" ('a', ... when quoted). */
int mote_word_index(const char *words, const char *w);
void mote_words_text(const char *words, int quoted, char *buf, size_t cap);
/* A command of rows: table names "NAME SUB" ("generate ring"), one row per sub-command, each
 * with its own options. Whether name has rows, and "ring, area or plummer" (their words). */
/* The program's usage text (cli.c; also the manual page's synopsis). */
extern const char mote_usage_text[];
int mote_cmd_has_rows(const mote_cmd *cmds, size_t n, const char *name);
void mote_cmd_rows_text(const mote_cmd *cmds, size_t n, const char *name, char *buf, size_t cap);

/* ---- argument specs (mote_cmd.args, see command.h) ------------------------------------------ */

typedef struct {
    char type;                  /* 'i' 'u' 'r' 'f' 's' 'e' 'v' */
    int count;                  /* 'v': the vector's length (2 or 3) */
    char words[96];             /* "a|b|c": the words of an 'e', or allowed beside a number */
    char role;                  /* files: '>' output, '<' input, 0 neither */
    unsigned char lo_set, hi_set, lo_open, hi_open;
    double lo, hi;
    char lo_text[24], hi_text[24]; /* the bounds as written in the table */
    char kinds[96];             /* files: the output's kind, or the input's kinds "a|b" */
    char key[32];               /* options: the key ("" for a positional argument) */
    int required;               /* options: must be given */
    int positional;             /* options: '@KEY=': may be given as a bare token instead */
    int many;                   /* the last positional spec written "SPEC+": one or more */
} mote_argspec;

/* The number of positional specs in `args`: -2 for "*", -1 when malformed. */
int mote_argspec_count(const char *args);
/* `plot` as lines (lines.c): the first nin arguments of c are data files; with check_only the
 * files are read and their columns checked, else png is drawn. defaults: mote_model.plot_lines. */
int mote_plot_lines(const mote_call *c, int nin, const char *defaults, const char *png,
                    int check_only, mote_err *err);
/* labels= gives one label per data file */
int mote_plot_lines_labels(const mote_call *c, int nin, mote_err *err);
/* Does the last positional spec take one or more arguments ("f+")? */
int mote_argspec_many(const char *args);
/* Positional spec number `index` of `args` (0-based). Returns 0, or -1 when there is none or it
 * is malformed. */
int mote_argspec_get(const char *args, int index, mote_argspec *out);
/* The number of option specs (KEY=SPEC), -1 when malformed; option number `index`; the option
 * of `key` (0, or -1 when there is none). */
int mote_argspec_noptions(const char *args);
int mote_argspec_option_at(const char *args, int index, mote_argspec *out);
int mote_argspec_option(const char *args, const char *key, mote_argspec *out);
/* Are the specs well formed (positional before options, no key twice)? */
int mote_argspec_valid(const char *args);
/* The length of the option key that starts p (a token "key=..."), or 0. */
size_t mote_option_key_len(const char *p);
/* The name of argument i as the command's synopsis gives it ("argument 3" if none). */
void mote_arg_name(const mote_cmd *def, int i, char *buf, size_t cap);
/* Resolve every file argument of c against the context's current `output_dir` (args[i].path). */
int mote_args_resolve(mote_call *c, mote_err *err);
/* Before a command's `check`: ranges, and input files ("f<"). */
int mote_args_check_before(const mote_call *c, mote_err *err);
/* After a successful `check`: record the outputs ("f>"). */
int mote_args_check_after(const mote_call *c, mote_err *err);
/* Argument i must be written earlier in the script by a command of one of `kinds` ("a|b"; NULL:
 * any), or else exist now. */
int mote_args_check_input(const mote_call *c, int i, const char *kinds, mote_err *err);

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

/* convert.c: argument i of a command (optkey: the option's key, or NULL for a positional one)
 * converted by its table type into a; the token as a message shows it (quoted, cut at cap); a
 * case-insensitive substring test. */
/* The options of a call: each key declared, given at most once, its value converted by its
 * spec (the token after the '='); every required option given (convert.c). */
int mote_script_convert_options(mote_script *s, const mote_cmd *def, const token *name,
                                const token *const *opt, int nopts, mote_opt **out,
                                mote_err *err);
int mote_script_convert_arg(mote_script *s, const mote_cmd *def, const char *written, int i,
                            const char *optkey, const token *t, mote_arg *a, mote_err *err);
const char *mote_script_shown(const token *t, char *buf, size_t cap);
int mote_script_contains_ci(const char *s, const char *w);

#endif
