/* command.h: the contract between models and the script language.
 *
 * A model describes its commands in a constant table of mote_cmd (name, aliases, argument types,
 * documentation, and two functions: `check`, run on a dry model during validation, and `run`).
 * The script layer (src/script) lexes and parses a whole script, converts arguments to the types
 * the table asks for, runs every `check` on a dry model, and only then runs the commands. These
 * types live in the core layer so that models need not include anything from the layers above. */
#ifndef MOTE_COMMAND_H
#define MOTE_COMMAND_H

#include "mote/core.h"
#include "mote/buf.h"

#include <stdint.h>
#include <stdio.h>

/* One argument of a parsed command. `text` is the token with quotes and escapes removed. The
 * numeric fields hold the value converted according to the command's type letter. */
typedef struct {
    const char *text;
    int line, col; /* 1-based position of the token in the script */
    int quoted;
    int64_t i;     /* type 'i' */
    uint64_t u;    /* type 'u' */
    double r;      /* type 'r' */
    char *path;    /* type 'f': the name resolved against `output_dir` (set by the script layer
                    * before the command's check and run; owned by the script) */
    double v[3];   /* type 'v2' or 'v3': the numbers of "X,Y,Z" */
    int word;      /* a spec with words ("e{a|b}", "r>0{auto}"): 1 + the index of the word given
                    * (also in i), 0 when a number was given */
} mote_arg;

/* One key=value option of a parsed command; value.text is what follows the '='. */
typedef struct {
    const char *key;
    mote_arg value;
} mote_opt;

struct mote_cmd;
struct mote_context;
struct mote_sf_field; /* (statefile.h) */

/* One command line of a script, after parsing. */
typedef struct {
    const char *file;           /* script path as given on the command line */
    int line, col;              /* position of the command name */
    const char *name;           /* canonical command name */
    const char *written;        /* the command name as written (may be an alias) */
    const char *source;         /* the line as written, without comment and surrounding blanks */
    int nargs;
    const mote_arg *args;       /* the positional arguments */
    int nopts;
    const mote_opt *opts;       /* the key=value options given, in the order written */
    const struct mote_cmd *def;
    struct mote_context *ctx;   /* run-wide settings (output directory, terminal, streams) */
    const char *loop;           /* inside loops: their values in this pass, "eta=0.3, n=2" */
} mote_call;

/* mote_cmd.args describes the arguments, one spec per argument, separated by spaces (plain
 * letters may also be run together: "ir" is "i r"), or "*" alone:
 *   'i'  non-negative decimal integer that fits in int64 (an optional leading '+')
 *   'u'  unsigned 64-bit decimal integer (0 ... 2^64-1)
 *   'r'  finite real in decimal notation (strtod syntax without hex, inf or nan)
 *   'f'  file name: one bare token or a double-quoted string (escapes \" and \\)
 *   's'  any single token (string)
 *   'e{a|b|c}'  one of the words (an enumeration): its index in i and word (1 + index)
 *   'v3', 'v2'  a vector: three (two) finite reals separated by commas, "1,0,-2.5", into v
 *   '*'  as the only spec: any number of tokens of any kind; the command checks them itself
 * A number may also accept words, "r>0{auto}" or "i>=1{all|none}": the word given sets word
 * (1 + its index) and i, a number leaves word 0; the range applies to numbers only.
 * A number may carry a range, checked by the script layer before the command's `check`, with a
 * message naming the argument as the synopsis does: "i>=1", "r>0", "r<=1", "r[0,1]", "r(0,1]".
 * A file may carry its role: "f>KIND" is an output of kind KIND (a short lower-case word such as
 * "state" or "image"): the script layer checks that its directory will exist, warns when a script
 * writes a file twice, and records it; "f<KIND1|KIND2" is an input that an earlier command of the
 * script must write with one of these kinds, or else must exist now. Kinds are the models' own
 * names; a command's `check` can ask for the kind of an input with mote_outputs_find.
 * Options follow the positional specs as KEY=SPEC, e.g. "f>image mass=r>0! x=r name=s": a call
 * gives them as key=value tokens in any order after or among its positional arguments; each
 * key at most once; a trailing '!' makes one required. mote_call_opt finds one. An option
 * written '@KEY=SPEC' may also be given bare: the bare tokens after the positional arguments
 * fill the '@' options in their order ("@every=i>=1! @file=f>xyz!" reads `dump 10 t.xyz` as
 * `dump every=10 file=t.xyz`), so a command keeps a short positional form beside its options. */
typedef struct mote_cmd {
    const char *name;
    const char *aliases;  /* space-separated alternative names, or NULL */
    const char *args;     /* argument specs, e.g. "i>=1 r(0,1) f>image" (see above) */
    const char *synopsis; /* e.g. "compress_left_wall eta dLmax K" */
    const char *summary;  /* one line for `mote help` */
    const char *help;     /* full documentation for `mote help CMD` */
    /* Validation on a dry model: must not write files or run dynamics (it may read an input that
     * exists already, so that its errors come before anything runs). NULL = always valid. */
    int (*check)(void *model, const mote_call *c, mote_err *err);
    int (*run)(void *model, const mote_call *c, mote_err *err);
} mote_cmd;

/* The command that stops an output (`frames_stop`, `snapshot_stop`, `trajectory_stop`,
 * `monitor_stop`, `checkpoint_stop`): one row made here, so its name, help and meaning are the same in every model;
 * the model gives its check and run (which clear the output's schedule), ALIASES as above. */
#define MOTE_STOPS_frames "the pictures of `frames`"
#define MOTE_STOPS_snapshot "the series of `snapshot every=K|dt=T prefix=P`"
#define MOTE_STOPS_trajectory "the particle paths of `trajectory`"
#define MOTE_STOPS_monitor "the rows of `monitor`"
#define MOTE_STOPS_checkpoint "the states of `checkpoint`"
#define MOTE_CMD_STOP(WORD, ALIASES, CHECK, RUN)                                                 \
    {#WORD "_stop", ALIASES, "", #WORD "_stop", "stop " MOTE_STOPS_##WORD,                      \
     "    " #WORD "_stop\n\nStop " MOTE_STOPS_##WORD " in the commands that follow; what it "   \
     "wrote stays as\nit is. Nothing happens when it is not on.\n",                             \
     CHECK, RUN}

/* A parameter command bound to a value of the model's state: the command's name and the key of
 * the value's descriptor (statefile.h) in the table the model's `state` hook gives ("gravity",
 * "real g"), listed in mote_model.params. The command's check and run are mote_cmd_set, which
 * writes its first argument (or, without one, its only option) there (a real into a double or
 * through the descriptor's codec, an integer or the index of an e{...} word into an int): it
 * sets exactly the value that `save` writes and `load` reads, and the model writes no setter of
 * its own. */
typedef struct {
    const char *command, *key;
} mote_param;

int mote_cmd_set(void *model, const mote_call *c, mote_err *err);

/* The option keys of a command's argument spec, in order (at most cap; each cut to 31
 * characters): "every", "file", ... Returns how many. */
#define MOTE_CMD_OPTIONS_MAX 32
size_t mote_cmd_option_keys(const mote_cmd *c, char keys[][32], size_t cap);
/* Whether an option key is one of the output layer's shared words (every, dt, file, prefix,
 * format): the ones that mean the same in every model. */
int mote_vocabulary_option(const char *key);

/* The output files of a script, recorded as validation walks the script (by the script layer for
 * "f>KIND" arguments, by a command's `check` for files it names otherwise): later commands can
 * ask whether a path is written earlier and by what kind of command, and a path written twice
 * gets a warning. A series of numbered files (frames, snapshots on a schedule) is recorded by its
 * prefix and extension, so that a file of another command that falls among its names, or a
 * second series that would number the same names from 0 again, is reported too. */
typedef struct {
    char *path;   /* the file, or a series' prefix as given */
    char *kind;
    char *stem;   /* a series: the names' common start (see mote_series_path, core.h); NULL: one file */
    char *ext;    /* a series: the names' ending, ".png" */
    int line;     /* the script line that writes it */
    int warned;   /* a second write of it was warned about (a third is not) */
} mote_output;

typedef struct {
    mote_output *e;
    size_t n, cap;
    size_t *series;   /* the entries that are series, in order (a script has few of them) */
    size_t nseries, capseries;
    size_t *slot;     /* open-addressing index: 1 + the latest entry of a path, 0 empty */
    size_t nslot;     /* a power of two, at least twice n (lookups O(1): scripts of 10^5 saves) */
} mote_outputs;

/* The measurements of one replica of an `ensemble` (src/script/ensemble.c): named values in
 * the order the commands gave them. */
typedef struct {
    char (*name)[64];
    double *value;
    size_t n, cap;
    int failed; /* out of memory: the ensemble fails rather than average fewer values */
} mote_results;

/* The MPI ranks of a run under mpirun, as the program (src/cli/main.c, MPI build) gives them:
 * the library itself does not call MPI. allgather: every rank calls it at the same point with
 * its n bytes; it returns every rank's bytes in rank order (malloc'ed) with their lengths in
 * lens[0 ... size-1], or NULL when out of memory (then in every rank). */
typedef struct mote_ranks {
    int rank, size;
    char *(*allgather)(const struct mote_ranks *r, const char *buf, size_t n, size_t *lens);
} mote_ranks;

/* Run-wide settings shared by the script layer and the model's commands. */
typedef struct mote_context {
    const char *script_path;
    char output_dir[4096];  /* "" = current directory; set by the `output_dir` command */
    char pending_dirs[8][4096]; /* during validation: directories `output_dir` will create */
    int npending_dirs;
    mote_outputs outputs;   /* during validation: the files the script writes, so far */
    char model_variant[32]; /* the variant the `model` line chose ("" when the model has none) */
    int threads;            /* set by the common `threads` command (0 = not set: one thread) */
    int terminal;           /* stdout is a terminal: show progress */
    int check_only;         /* `mote check`: the script is only checked; a model may print
                             * what each run would cost (mote_call_note) */
    int quiet;              /* no status line after each command (`quiet on`, --quiet) */
    FILE *out;              /* status lines (stdout) */
    FILE *diag;             /* warnings and errors (stderr) */
    /* Called from every progress update of a long command (and after each command) while a
     * run has a live view: it publishes a frame when one is due and holds the run while the
     * page has paused it (NULL: no live view). */
    void (*tick)(void *arg);
    void *tick_arg;
    /* Inside a replica of an `ensemble`: where mote_call_result puts the measurements (NULL
     * elsewhere). */
    mote_results *results;
    /* Progress for a program that drives mote (the Python package's callback): the command
     * under way and the fraction done, at most every progress interval (NULL: none). */
    void (*report)(void *arg, const char *label, double fraction);
    void *report_arg;
    /* Asked at progress updates (at most 20 times a second) whether the user wants the command
     * stopped (the Python package's KeyboardInterrupt; NULL: never). A command that supports it
     * stops at its next safe point with mote_interrupted's error, its state consistent. */
    int (*interrupt)(void *arg);
    void *interrupt_arg;
    /* The model the script selected (its registry entry), once its `model` line (or the
     * default) is read. */
    const struct mote_model *model;
    /* Under mpirun (the MPI build, more than one rank; NULL otherwise): the ranks, for the
     * ensembles, whose replicas are spread over them. */
    const struct mote_ranks *ranks;
    /* 1: this run stays in this process even under mpirun (a replica of an ensemble on one
     * rank): a model that shares its work among the ranks must not, and writes its own files. */
    int solo;
    /* Observers that join every run of every model (mote_run, loop.h): a program that drives
     * mote, a test. The caller's array; their schedules are theirs. */
    const struct mote_observer *observers;
    size_t nobservers;
} mote_context;

/* An array of a model's state for other programs (the Python package's NumPy arrays): rows
 * (particles) by cols numbers of one type, row and column strides in bytes. `owned`: the model
 * made it for this call (malloc'ed; the caller frees it) because its own layout differs (another
 * order, another precision); otherwise it points into the model and stays valid until the next
 * command. */
typedef struct {
    const char *name; /* "positions", "velocities", "radii", "masses", "charges", "species" */
    void *data;
    char type;        /* 'd' double, 'i' int32 */
    size_t rows, cols;
    long row_stride, col_stride;
    int owned, writable; /* writable: a view the caller may write into (then the model's `set`
                          * hook must be called) */
    const char *unit; /* the unit of its numbers ("R", "m/s", "dimensionless (units)") */
} mote_array;

/* Helpers for mote_model.arrays: a view of n x cols doubles (cols 1) or ints in the model's own
 * memory; an owned copy gathering `ncols` columns of n doubles each times `scale` (structure of
 * arrays into rows). Return 0, or -1 out of memory. */
void mote_array_view(mote_array *a, const char *name, const char *unit, void *data, char type,
                     size_t n, size_t cols);
int mote_array_gather(mote_array *a, const char *name, const char *unit,
                      const double *const *columns, size_t ncols, size_t n, double scale);

/* A model: its name as used by `model NAME`, its command table, and its lifetime functions.
 * `create(ctx, dry)` makes an empty model; with dry != 0 it will only receive `check` calls. */
typedef struct mote_model {
    const char *name;
    const char *summary;
    /* Variants the `model NAME VARIANT` line may choose, as "a|b" (the first is the default), or
     * NULL; the choice is in ctx->model_variant when create is called. */
    const char *variants;
    /* 1: the model's commands use ctx->threads (the common `threads` command); 0: it runs on
     * one thread, and `threads` prints a note saying so */
    int threaded;
    const mote_cmd *cmds;
    size_t ncmds;
    void *(*create)(mote_context *ctx, int dry);
    void (*destroy)(void *model);
    /* Print the one-line key=value status after each command (NULL: none). */
    void (*status)(void *model, FILE *out);
    /* Bring the model to its canonical state; the script layer calls it after every model
     * command, before the status line. The canonical state is exactly what the model's `save`
     * writes and its `load` rebuilds, so for any commands A and B, `A; B`, `A; save F; B` and
     * `A; save F; load F; B` run bit for bit alike. A model whose state between commands is
     * always canonical (no lazy updates, no caches that steer the dynamics) leaves it NULL. */
    int (*settle)(void *model, mote_err *err);
    /* The live view (issue 25, docs/live-view.md): write the model's part of a frame into out,
     * as JSON members after the frame's own (",\"view\":...", the box, status, particles; the
     * members are listed in docs/live-view.md). Called between steps of a long command: it must
     * only read the model. NULL: the model has no live view. */
    void (*live)(void *model, mote_buf *out);
    /* The common command `seed S`: restart the model's random stream from S (NULL: the model
     * draws no random numbers, and `seed` is refused). */
    void (*seed)(void *model, uint64_t seed);
    const char *seed_help;  /* what draws from the stream in this model (for `mote help seed`) */
    /* The common command `plot DATAFILE PNGFILE [options]`: render a data file of one of the
     * kinds in plot_kinds ("image|profile", as in an "f<" spec) as a PNG (NULL: nothing to
     * plot). The call c carries the options plot_opts declares (an options-only spec such as
     * "plane=s size=i>=64", or NULL: none); plot_check (NULL: none) checks them before the
     * run, on the dry model. */
    const char *plot_kinds;
    int (*plot)(void *model, const char *data_path, const char *png_path, const mote_call *c,
                mote_err *err);
    const char *plot_help;  /* the pictures of this model's kinds (for `mote help plot`) */
    const char *plot_opts;
    int (*plot_check)(void *model, const mote_call *c, mote_err *err);
    /* `plot` as lines (several files, or x= / y=; src/script/lines.c): the columns drawn by
     * default for each data-file format of the model, "FORMAT:X,Y[,ERR][,log] ...": X and Y
     * name columns (a name may leave out its [unit]; "a|b": the first the file has), ERR the
     * column of Y's error bars (else Y_err or sigma_Y where the file has one), log a logarithmic
     * X axis. NULL: none (x= and y= must then be given). */
    const char *plot_lines;
    /* The model's state as arrays (NULL: none): fills up to cap entries of out and returns how
     * many, or -1 when out of memory. */
    int (*arrays)(void *model, mote_array *out, int cap);
    /* Replace array `name` by rows x cols doubles (row-major) after checking them (the shape,
     * finite values, the model's own conditions), then bring the model to its canonical state
     * again; NULL: no array can be set. */
    int (*set_array)(void *model, const char *name, const double *v, size_t rows, size_t cols,
                     mote_err *err);
    /* The model's own program beside `mote run`: `mote PROGRAM [ARGS]` calls program_main with
     * argv[0] = PROGRAM and exits with its status (NULL: none; nbody's is `galactica`, a
     * Galactica job folder). */
    const char *program;
    int (*program_main)(int argc, char **argv, FILE *out, FILE *diag);
    /* 1: under MPI (make MPI=1) the model shares its work among the ranks; 0: it is not offered
     * when there is more than one rank */
    int mpi;
    /* `picture FILE.png` (a common command): a picture of the state now, drawn as the model
     * draws its own pictures (NULL: none; the script refuses the command); picture_help says
     * what it shows (for `mote help picture`). The notebook's picture of a simulation. */
    int (*picture)(void *model, const char *png_path, mote_err *err);
    const char *picture_help;
    /* The model's state as descriptors (statefile.h), for the commands bound to them
     * (mote_cmd.sets): returns the structure the offsets are in and sets the table (NULL: none). */
    void *(*state)(void *model, const struct mote_sf_field **fields, size_t *n);
    /* The parameter commands bound to it (mote_param) */
    const mote_param *params;
    size_t nparams;
    /* The box the particles are in (NULL: none, as N-body's open space): its edges along x, y,
     * z in the units of the positions (0 along an axis the positions lack), its lower corner,
     * and which axes are periodic: Python's to_ase() cell, as the XYZ files' Lattice. Returns
     * 0, or -1 when there is no box yet. */
    int (*cell)(void *model, double edges[3], double origin[3], int periodic[3]);
} mote_model;

/* The registry: every model this build knows, in the order `mote help` lists them
 * (src/script/registry.c; adding a model adds one line there and touches no other model). */
extern const mote_model *const mote_models[];
extern const size_t mote_nmodels;

/* The option `key` of a call (its converted value), or NULL when not given. */
const mote_arg *mote_call_opt(const mote_call *c, const char *key);
/* Its real value, or `dflt` when not given. */
double mote_call_opt_r(const mote_call *c, const char *key, double dflt);
/* The word given for an e{a|b|c} option: its index in the spec's words (the script layer has
 * refused any other word), or `dflt` when the option is not given. Handlers compare it with
 * named indices, never the option's text. */
int mote_call_word(const mote_call *c, const char *key, int dflt);
/* An e{on|off} option: 1 for on, 0 for off, `dflt` when not given. */
int mote_call_on(const mote_call *c, const char *key, int dflt);

/* The shared format= of `trajectory` and `snapshot` (h5md.h): is the output H5MD? Yes when
 * format= gives the word of index h5md_word of the command's e{...} or, without format=, when
 * the file of option file_key (NULL or absent: a series' prefix) ends in .h5 or .h5md. 1 or 0;
 * -1 (err set, located at the option) when the two disagree: format=h5md and a file not named
 * .h5/.h5md, or another format and a file so named. */
int mote_call_h5md(const mote_call *c, const char *file_key, int h5md_word, mote_err *err);
/* The VTK choice of `snapshot` (vtk.h), checked first: 1 when format= gives the word of index
 * vtk_word or, without format=, the file of option file_key ends in .vtk; 0 otherwise; -1 (err
 * set, located) when they disagree. vtk_word < 0 (a trajectory: a VTK file holds one frame): a
 * .vtk file is refused, naming the series that writes one file a frame. */
int mote_call_vtk(const mote_call *c, const char *file_key, int vtk_word, mote_err *err);

/* Resolve a file name given to a command: relative names are taken relative to ctx->output_dir
 * when one is set. Returns a malloc'ed string (NULL on allocation failure). */
char *mote_ctx_path(const mote_context *ctx, const char *name);

/* Validation helper: does the directory that will hold `path` exist now, or will `output_dir`
 * create it earlier in the script? */
int mote_ctx_dir_ok(const mote_context *ctx, const char *path);
/* Validation: the folder dir will be made before files are written in it (a prefix='s; at most
 * 8 a script with output_dir's): later checks of files in it pass. -1 when the list is full. */
int mote_ctx_note_dir(mote_context *ctx, const char *dir);

/* The argi of option `key` for mote_call_fail (-1 when it was not given). */
int mote_call_opt_index(const mote_call *c, const char *key);

/* Format an error located at argument `argi` of the call (argi < 0: the command name; nargs + k:
 * the value of option k, see mote_call_opt_index):
 * "FILE:LINE:COL: error: <message>". Returns code. */
int mote_call_fail(mote_err *err, const mote_call *c, int argi, mote_status code, const char *fmt,
                   ...) __attribute__((format(printf, 5, 6)));

/* A measurement of call c, `key` = value (pressure's Z, the separator's d50, ...): inside an
 * `ensemble` it is what the replicas' means and standard errors are made of, named
 * "COMMAND.KEY" (a second one of the same name in a replica gets "_2", "_3", ...); elsewhere
 * nothing. Commands call it for the numbers they print as their results. */
void mote_call_result(const mote_call *c, const char *key, double value);
void mote_results_free(mote_results *r);

/* Print a warning located at the call to ctx->diag: "FILE:LINE:COL: warning: <message>". */
void mote_call_warn(const mote_call *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Print a note located at the call to ctx->out: "FILE:LINE:COL: note: <message>". */
void mote_call_note(const mote_call *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* ---- the files a script writes (validation) -------------------------------------------------- */

void mote_outputs_free(mote_outputs *o);
/* The kind of the latest record of `path`, or NULL. */
const char *mote_outputs_find(const mote_outputs *o, const char *path);
/* Record `path` (already resolved with mote_ctx_path) as written by call c: fails, located at
 * argument argi, when its directory does not exist (and no earlier `output_dir` creates it);
 * warns when it is written for the second time unless `repeat_ok`. */
int mote_outputs_note_path(mote_outputs *o, const mote_call *c, int argi, const char *path,
                           const char *kind, int repeat_ok, mote_err *err);

/* Record a numbered series (mote_series_path(prefix, ..., ext), core.h) written by call c: fails when its
 * directory does not exist; warns when another command's file falls among its names, or when an
 * earlier series of the same names is not the one this continues (the latest series of this
 * kind): a series that names the prefix of the one before it continues its numbering, any other
 * starts from 0 and would overwrite the earlier files. flags: MOTE_SERIES_MAKES_DIR (the command
 * makes the directory of the files; only its parent must exist), MOTE_SERIES_BY_STEP (the numbers
 * are step counts, which only grow, so series of the same names do not overwrite each other). */
enum { MOTE_SERIES_MAKES_DIR = 1, MOTE_SERIES_BY_STEP = 2 };
int mote_outputs_note_series(mote_outputs *o, const mote_call *c, int argi, const char *prefix,
                             const char *ext, const char *kind, int flags, mote_err *err);

/* "SOURCE   (FILE:LINE)": the command as written, for data-file headers (malloc'ed; NULL when
 * out of memory). */
char *mote_call_origin(const mote_call *c);

/* ---- progress on a terminal ---------------------------------------------------------------- */

typedef struct {
    int enabled, shown; /* shown: a line is on the terminal (end wipes it) */
    int run;            /* a command of several runs: the run under way (1, 2, ...); 0: one */
    double start, last;
    double begun;       /* when the command began (start: when its run under way began) */
    double interval; /* seconds between lines: 0.25, or MOTE_PROGRESS_INTERVAL (tests use 0) */
    char label[64];
    const mote_context *ctx; /* (its live-view hook and its report) */
    double last_report;
    double last_interrupt; /* when the interrupt hook was last asked */
} mote_progress;

void mote_progress_begin(mote_progress *p, const mote_context *ctx, const char *label);
/* fraction in [0, 1]; prints "\rlabel 42.0%  ~12 s left" to stdout at most 4 times a second
 * (every `interval` seconds) when stdout is a terminal; nothing otherwise. */
int mote_progress_update(mote_progress *p, double fraction);
/* mote_progress_update returns 1 when the context's interrupt hook asked to stop the command (0
 * otherwise); the command then returns this error ("interrupted ..."), its state consistent. */
int mote_interrupted(mote_err *err, const char *command);
/* A command that makes several runs of unknown number (a root search, a table built until it is
 * fine enough) keeps one line for all of them: each run calls this as it starts, and the line
 * reads "\rlabel: run 3, 42.0%  ~2 s left in this run, 35 s so far": the fraction and the time
 * left of that run (the command's own end is not known), and the time since the command began. */
void mote_progress_next_run(mote_progress *p);
/* Wipe the line shown (if any), so that a line of the command's own output starts clean; the
 * next update draws it again. */
void mote_progress_clear(mote_progress *p);
void mote_progress_end(mote_progress *p);

#endif
