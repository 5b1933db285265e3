/* cli.c: the `mote` program's argument handling (run, check, help, --version), kept in the
 * library so that main() is a few lines naming the models and tests can drive the whole program
 * with their own registry and streams. */
#include "script_internal.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

const char mote_usage_text[] =
            "Usage: mote run [--check] [--quiet] [--live[=PORT]] [--bind ADDRESS] [SCRIPT]\n"
            "                [NAME=VALUE...]     run a script (default: " MOTE_DEFAULT_SCRIPT "; -:\n"
            "                                    standard input), with parameters for its\n"
            "                                    ${NAME}, with --live watched in a browser,\n"
            "                                    --quiet without a status line after each\n"
            "                                    command\n"
            "       mote check [SCRIPT] [NAME=VALUE...]  check a script; run nothing\n"
            "       mote help [CMD | MODEL]      list the commands, or document one\n"
            "       mote help --markdown         the command reference in Markdown\n"
            "       mote help --man              the manual page mote(1), in roff\n"
            "       mote help --bash-completion  the bash completion of mote's commands\n"
            "       mote galactica [--help]      run the Galactica job of this folder (N-body)\n"
            "       mote --version\n"
            "Exit status: 0 success, 1 usage or script error (nothing ran), 2 runtime error.\n";

static void usage(FILE *f) { fputs(mote_usage_text, f); }

__attribute__((format(printf, 2, 3))) static int usage_error(FILE *diag, const char *fmt, ...)
{
    fputs("mote: error: ", diag);
    va_list ap;
    va_start(ap, fmt);
    vfprintf(diag, fmt, ap);
    va_end(ap);
    fputc('\n', diag);
    usage(diag);
    return 1;
}

static int run_or_check_with(int argc, char **argv, const char **params,
                             const mote_model *const *models, size_t nmodels, FILE *out,
                             FILE *diag, int terminal, const mote_ranks *ranks)
{
    mote_script_options opt = {.out = out, .diag = diag, .terminal = terminal,
                               .check_only = strcmp(argv[1], "check") == 0, .ranks = ranks};
    const char *script = NULL;
    int options_done = 0, nparams = 0;
    for (int i = 2; i < argc; i++) {
        const char *a = argv[i];
        if (!options_done && strcmp(a, "--") == 0) {
            options_done = 1;
        } else if (!options_done && strncmp(a, "--live", 6) == 0 && (a[6] == '\0' || a[6] == '=')) {
            opt.live = 1;
            opt.live_port = 8080;
            if (a[6] == '=') {
                char *end;
                long p = strtol(a + 7, &end, 10);
                if (*end || end == a + 7 || p < 0 || p > 65535)
                    return usage_error(diag, "--live=PORT: the port must be 0 ... 65535 (0: any "
                                             "free one), found '%s'", a + 7);
                opt.live_port = (int)p;
            }
        } else if (!options_done && strcmp(a, "--bind") == 0 && i + 1 < argc) {
            opt.live_bind = argv[++i];
        } else if (!options_done && (strcmp(a, "--quiet") == 0 || strcmp(a, "-q") == 0)) {
            opt.quiet = 1;
        } else if (!options_done && a[0] == '-' && a[1] != '\0') {
            if (strcmp(a, "--check") != 0)
                return usage_error(diag, "unknown option '%s'", a);
            opt.check_only = 1;
        } else if (script && strchr(a, '=')) { /* NAME=VALUE after the script */
            params[nparams++] = a;
        } else if (script) {
            return usage_error(diag, "more than one script given ('%s'); parameters are "
                                     "written NAME=VALUE", a);
        } else if (strchr(a, '=') && a[0] != '-' && a[0] != '.' && a[0] != '/') {
            return usage_error(diag, "'%s' looks like a parameter; parameters come after the "
                                     "script's name (mote run SCRIPT NAME=VALUE)", a);
        } else {
            script = a;
        }
    }
    opt.params = params;
    opt.nparams = nparams;
    return mote_script_run_file(script ? script : MOTE_DEFAULT_SCRIPT, models, nmodels, &opt);
}

static int run_or_check(int argc, char **argv, const mote_model *const *models, size_t nmodels,
                        FILE *out, FILE *diag, int terminal, const mote_ranks *ranks)
{
    const char **params = malloc((size_t)argc * sizeof *params);
    if (!params) {
        fprintf(diag, "mote: error: out of memory\n");
        return 1;
    }
    int rc = run_or_check_with(argc, argv, params, models, nmodels, out, diag, terminal, ranks);
    free(params);
    return rc;
}

static int main_with(int argc, char **argv, const mote_model *const *models, size_t nmodels,
                     FILE *out, FILE *diag, int terminal, const mote_ranks *ranks)
{
    if (argc < 2) {
        usage(diag);
        return 1;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "--version") == 0) {
        if (argc > 2)
            return usage_error(diag, "unexpected argument '%s'", argv[2]);
        fprintf(out, "mote %s\n", MOTE_VERSION);
        return 0;
    }
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0) {
        usage(out);
        return 0;
    }
    mote_err err;
    if (mote_models_verify(models, nmodels, &err)) {
        fprintf(diag, "mote: internal error in a command table: %s\n", err.msg);
        return 1;
    }
    if (strcmp(cmd, "run") == 0 || strcmp(cmd, "check") == 0)
        return run_or_check(argc, argv, models, nmodels, out, diag, terminal, ranks);
    if (strcmp(cmd, "help") == 0) {
        if (argc == 2) {
            mote_help_list(out, models, nmodels);
            return 0;
        }
        if (argc > 4 || (argc == 4 && argv[2][0] == '-'))
            return usage_error(diag, "'help' takes one name (or a command and its row, "
                               "'help generate ring'), found also '%s'", argv[argc - 1]);
        if (strcmp(argv[2], "--markdown") == 0) {
            mote_help_markdown(out, models, nmodels);
            return 0;
        }
        if (strcmp(argv[2], "--man") == 0) {
            mote_help_man(out, models, nmodels);
            return 0;
        }
        if (strcmp(argv[2], "--bash-completion") == 0) {
            mote_help_completion(out, models, nmodels);
            return 0;
        }
        if (argc == 4) { /* a command's row: `mote help generate ring` */
            char both[160];
            snprintf(both, sizeof both, "%s %s", argv[2], argv[3]);
            return mote_help_command(out, diag, both, models, nmodels);
        }
        return mote_help_command(out, diag, argv[2], models, nmodels);
    }
    mote_suggest sg;
    mote_suggest_init(&sg, cmd);
    static const char *const verbs[] = {"run", "check", "help"};
    for (size_t i = 0; i < sizeof verbs / sizeof verbs[0]; i++)
        mote_suggest_feed(&sg, verbs[i], strlen(verbs[i]));
    char best[16];
    if (mote_suggest_result(&sg, best, sizeof best)) {
        fprintf(diag, "mote: error: unknown command '%s'; did you mean '%s'?\n", cmd, best);
    } else if (access(cmd, F_OK) == 0) {
        fprintf(diag, "mote: error: unknown command '%s'; to run this script: mote run %s\n", cmd,
                cmd);
    } else {
        fprintf(diag, "mote: error: unknown command '%s'\n", cmd);
    }
    usage(diag);
    return 1;
}

int mote_script_main_io(int argc, char **argv, const mote_model *const *models, size_t nmodels,
                        FILE *out, FILE *diag, int terminal)
{
    return main_with(argc, argv, models, nmodels, out, diag, terminal, NULL);
}

int mote_script_main_ranks(int argc, char **argv, const mote_model *const *models,
                           size_t nmodels, const mote_ranks *ranks)
{
    return main_with(argc, argv, models, nmodels, stdout, stderr, isatty(fileno(stdout)),
                     ranks);
}

int mote_script_main(int argc, char **argv, const mote_model *const *models, size_t nmodels)
{
    return mote_script_main_ranks(argc, argv, models, nmodels, NULL);
}

const mote_model *mote_program_of(int argc, char **argv, const mote_model *const *models,
                                  size_t nmodels)
{
    for (size_t k = 0; argc > 1 && k < nmodels; k++)
        if (models[k]->program && strcmp(argv[1], models[k]->program) == 0)
            return models[k];
    return NULL;
}

int mote_main(int argc, char **argv, const mote_model *const *models, size_t nmodels)
{
    const mote_model *prog = mote_program_of(argc, argv, models, nmodels);
    if (prog)
        return prog->program_main(argc - 1, argv + 1, stdout, stderr);
    return mote_script_main(argc, argv, models, nmodels);
}
