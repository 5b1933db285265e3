/* script.h: the mote script language and the `mote` program built on it.
 *
 * A script is parsed whole (lexing, command lookup in the model's table, argument conversion),
 * then validated by running every command's `check` on a dry model, and only then executed. The
 * models a program knows are passed in as a registry (an array of model pointers), so the `mote`
 * program is a few lines and tests can drive everything with their own fake models. Nothing here
 * keeps global state. */
#ifndef MOTE_SCRIPT_H
#define MOTE_SCRIPT_H

#include "mote/command.h"

#include <stddef.h>
#include <stdio.h>

/* A script with no `model` line drives this model, so the original program's program.txt runs. */
#define MOTE_DEFAULT_MODEL "hard-spheres"
/* `mote run` with no script runs this file in the current directory, as the original did. */
#define MOTE_DEFAULT_SCRIPT "program.txt"

/* ---- the model registry -------------------------------------------------------------------- */

/* The model called `name`, or NULL. */
const mote_model *mote_model_find(const mote_model *const *models, size_t nmodels,
                                  const char *name);

/* Check the registry's command tables for mistakes a model author can make: missing fields,
 * unknown type letters, a synopsis whose argument count disagrees with the type letters, names
 * or aliases used twice or clashing with the common commands. Returns MOTE_OK or MOTE_EINVAL
 * with a message naming the model and command. mote_script_main runs it before anything else. */
int mote_models_verify(const mote_model *const *models, size_t nmodels, mote_err *err);

/* ---- parsed scripts ------------------------------------------------------------------------ */

typedef struct mote_script mote_script;

/* Parse script text (`len` bytes; need not be NUL-terminated). `file` is the name used in
 * diagnostics. On success *out owns everything (free with mote_script_free); on failure *out is
 * NULL and err holds a located message "FILE:LINE:COL: error: ...". */
int mote_script_parse(mote_script **out, const char *file, const char *text, size_t len,
                      const mote_model *const *models, size_t nmodels, mote_err *err);
/* The same with parameters: `params` holds nparams strings NAME=VALUE, variables that a
 * `set` of the same name does not change (`mote run study.mote eta=0.45`). A malformed or
 * repeated parameter is an error. */
int mote_script_parse_params(mote_script **out, const char *file, const char *text, size_t len,
                             const char *const *params, int nparams,
                             const mote_model *const *models, size_t nmodels, mote_err *err);
/* Read the file at `path` ("-": standard input, named <stdin> in messages, its relative file
 * names from the current directory) and parse it. An unreadable file is an error naming it. */
int mote_script_load(mote_script **out, const char *path, const mote_model *const *models,
                     size_t nmodels, mote_err *err);
int mote_script_load_params(mote_script **out, const char *path, const char *const *params,
                            int nparams, const mote_model *const *models, size_t nmodels,
                            mote_err *err);
/* The parameters given that no line of the script uses (their names in "a, b", "" if none). */
void mote_script_unused_params(const mote_script *s, char *buf, size_t cap);
void mote_script_free(mote_script *s);

/* The run-wide context the calls point to. After parsing it has out = stdout, diag = stderr,
 * terminal = 0; set other streams or the terminal flag here before validating. */
mote_context *mote_script_context(mote_script *s);
const mote_model *mote_script_model(const mote_script *s);
size_t mote_script_ncalls(const mote_script *s);
const mote_call *mote_script_call(const mote_script *s, size_t i);

/* Run every command's `check` in order on a dry model. Nothing is run, nothing is written.
 * Errors are always located (the failing command's position is added when the check did not). */
int mote_script_validate(mote_script *s, mote_err *err);
/* Validate (unless already done), then run every command on a fresh model, printing the model's
 * status line after each model command. Stops at the first failing command; the error is located. */
int mote_script_execute(mote_script *s, mote_err *err);

/* ---- sessions: a model driven command by command ------------------------------------------- */

/* A session is a script that grows: each text given is read into it (variables and loops work
 * across texts), checked on a dry model that has checked every command before it, then run on
 * the session's model. Messages name `name` and the line counted over all texts so far.
 * `model_line` is "NAME [VARIANT]" as a `model` line takes it. */
int mote_session_open(mote_script **out, const char *name, const char *model_line,
                      const mote_model *const *models, size_t nmodels, mote_err *err);
/* Read, check and run text. What the commands print goes to *printed (malloc'ed, NUL-ended;
 * the caller frees it; NULL when out is not wanted); warnings go to the context's diag. On an
 * error in reading or checking nothing runs; in running, the commands before it have run. */
int mote_session_command(mote_script *s, const char *text, char **printed, mote_err *err);
/* The model's status line (malloc'ed), as printed after each command. */
char *mote_session_status(mote_script *s);
/* The model running the session's commands (for mote_model.arrays and set_array). */
void *mote_session_instance(mote_script *s);
void mote_session_close(mote_script *s);

/* ---- whole programs ------------------------------------------------------------------------ */

typedef struct {
    FILE *out;      /* status lines, echo, help */
    FILE *diag;     /* errors, warnings, notes */
    int terminal;   /* out is a terminal: show progress */
    int check_only; /* validate and stop */
    int quiet;      /* --quiet: no status line after each command (`quiet on`) */
    int live;       /* --live[=PORT]: start the live view before the first command */
    int live_port;  /* its port (0: any free one) */
    const char *live_bind; /* --bind ADDRESS (NULL: 127.0.0.1) */
    const char *const *params; /* NAME=VALUE after the script's name (mote_script_load_params) */
    int nparams;
    const mote_ranks *ranks; /* under mpirun: the ranks (mote_context.ranks), else NULL */
    int (*interrupt)(void *arg); /* the context's interrupt hook (mote_context), or NULL */
    void *interrupt_arg;
} mote_script_options;

/* Load, validate and (unless check_only) execute a script, printing any error to opt->diag.
 * Returns the exit status of `mote run`: 0 success, 1 unreadable file or validation error
 * (nothing ran), 2 runtime error. */
int mote_script_run_file(const char *path, const mote_model *const *models, size_t nmodels,
                         const mote_script_options *opt);

/* `mote help`: the common commands and every model's commands, one line each. */
void mote_help_list(FILE *out, const mote_model *const *models, size_t nmodels);
/* The commands a script of model m can give (the Python package's generated methods): the
 * common ones (model, seed, plot, picture, ...), then the model's own; the k-th, NULL past the
 * end. (`plot` takes the model's plot_opts besides its own arguments.) */
const mote_cmd *mote_script_command_at(const mote_model *m, size_t k);
/* `mote help NAME`: the full documentation of a command (found by name or alias in any model)
 * or the command list of a model. Unknown names are reported on diag with a suggestion.
 * Returns an exit status (0 or 1). */
int mote_help_command(FILE *out, FILE *diag, const char *name, const mote_model *const *models,
                      size_t nmodels);
/* `mote help --markdown`: the complete command reference (docs/commands.md). */
void mote_help_markdown(FILE *out, const mote_model *const *models, size_t nmodels);
/* The manual page mote(1) in roff (`mote help --man`), from the same tables. */
void mote_help_man(FILE *out, const mote_model *const *models, size_t nmodels);
/* A bash completion script for the program (`mote help --bash-completion`): its verbs, and for
 * `mote help` the models and the commands of the tables (with their rows). */
void mote_help_completion(FILE *out, const mote_model *const *models, size_t nmodels);

/* The whole `mote` program: argument handling for run, check, help and --version, on the given
 * streams. Returns the process exit status. */
int mote_script_main_io(int argc, char **argv, const mote_model *const *models, size_t nmodels,
                        FILE *out, FILE *diag, int terminal);
/* The same on stdout/stderr, with terminal = isatty(stdout): what main() calls. */
int mote_script_main(int argc, char **argv, const mote_model *const *models, size_t nmodels);
/* The model whose own program (mote_model.program, `mote galactica`) argv[1] names, or NULL. */
const mote_model *mote_program_of(int argc, char **argv, const mote_model *const *models,
                                  size_t nmodels);
/* The `mote` program (without MPI): the model's own program that argv[1] names, else
 * mote_script_main. The Python package's `python -m mote` is this. */
int mote_main(int argc, char **argv, const mote_model *const *models, size_t nmodels);
/* The same under mpirun: the ranks the ensembles spread their replicas over. */
int mote_script_main_ranks(int argc, char **argv, const mote_model *const *models,
                           size_t nmodels, const mote_ranks *ranks);

#endif
