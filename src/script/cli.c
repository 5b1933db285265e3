/* cli.c: the `mote` program's argument handling (run, check, help, --version), kept in the
 * library so that main() is a few lines naming the models and tests can drive the whole program
 * with their own registry and streams. */
#include "script_internal.h"

#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/signalfd.h>
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
            "Exit status: 0 success, 1 usage or script error (nothing ran), 2 runtime error,\n"
            "130 stopped by Ctrl-C (128 + the signal: SIGTERM 143, SIGHUP 129).\n";

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

/* ---- Ctrl-C: the run stops at a safe point ------------------------------------------------------
 *
 * While `mote run` runs a script, SIGINT, SIGTERM and SIGHUP are blocked in every thread (the
 * run's threads are made after, and inherit the mask) and read by a watcher thread from a
 * signalfd. The first one is handed to the run through the context's interrupt hook, which long
 * commands ask at their progress updates (within about a tenth of a second): the command stops
 * at a safe point, its outputs end as for a failure (written, or their rows so far left in
 * FILE.partial, as each output says; an H5MD trajectory keeps every frame whole) and the
 * program exits with 128 + the signal's number (130 for Ctrl-C), as a shell expects. A second
 * signal, or a run that has not taken the first within 3 s (a command that never asks), ends
 * the program at once, as the signal would have without mote. Everything lives in this struct
 * on main_with's stack. */
typedef struct {
    sigset_t set, old;
    int fd;              /* the signalfd (-1: no guard, the signals act as they would) */
    int quit[2];         /* the watcher's stop: a byte written when the run is over */
    pthread_t watcher;
    atomic_int got;      /* the first signal (0: none yet) */
    atomic_int taken;    /* the run took it (the interrupt hook said so) */
} stop_guard;

static int stop_asked(void *arg)
{
    stop_guard *g = arg;
    if (!atomic_load(&g->got))
        return 0;
    atomic_store(&g->taken, 1);
    return 1;
}

/* The signal's default action, now (the program ends as the signal would end it). */
static void die_by(int sig)
{
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, sig);
    signal(sig, SIG_DFL);
    pthread_sigmask(SIG_UNBLOCK, &one, NULL);
    raise(sig);
    _exit(128 + sig); /* (only if the signal did not end it) */
}

static void *watch(void *arg)
{
    stop_guard *g = arg;
    struct pollfd p[2] = {{g->fd, POLLIN, 0}, {g->quit[0], POLLIN, 0}};
    for (;;) {
        const int first = atomic_load(&g->got) != 0;
        /* after the first: 3 s for the run to take it, then nothing more to wait for */
        const int r = poll(p, 2, first && !atomic_load(&g->taken) ? 3000 : -1);
        if (r < 0)
            continue;
        if (p[1].revents)
            return NULL;
        if (r == 0) { /* 3 s since the first signal: unless the run took it meanwhile (and is
                       * still ending the command), it never will */
            if (!atomic_load(&g->taken))
                die_by(atomic_load(&g->got));
            continue;
        }
        if (p[0].revents) {
            struct signalfd_siginfo si;
            if (read(g->fd, &si, sizeof si) != (ssize_t)sizeof si)
                continue;
            if (first)
                die_by((int)si.ssi_signo); /* a second signal */
            atomic_store(&g->got, (int)si.ssi_signo);
        }
    }
}

static void guard_start(stop_guard *g)
{
    atomic_init(&g->got, 0);
    atomic_init(&g->taken, 0);
    g->fd = -1;
    sigemptyset(&g->set);
    sigaddset(&g->set, SIGINT);
    sigaddset(&g->set, SIGTERM);
    sigaddset(&g->set, SIGHUP);
    if (pthread_sigmask(SIG_BLOCK, &g->set, &g->old) != 0)
        return;
    g->fd = signalfd(-1, &g->set, SFD_CLOEXEC);
    if (g->fd >= 0 && pipe(g->quit) == 0) {
        if (pthread_create(&g->watcher, NULL, watch, g) == 0)
            return;
        close(g->quit[0]);
        close(g->quit[1]);
    }
    if (g->fd >= 0)
        close(g->fd);
    g->fd = -1;
    pthread_sigmask(SIG_SETMASK, &g->old, NULL);
}

/* The watcher stopped, the mask as before; the signal the run stopped for (0: none). */
static int guard_end(stop_guard *g)
{
    if (g->fd < 0)
        return 0;
    (void)!write(g->quit[1], "", 1);
    pthread_join(g->watcher, NULL);
    close(g->quit[0]);
    close(g->quit[1]);
    close(g->fd);
    pthread_sigmask(SIG_SETMASK, &g->old, NULL);
    return atomic_load(&g->got);
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
    /* (under mpirun with several ranks the signals act as they always did: a rank stopped on
     * its own would leave the others waiting in a collective) */
    if (opt.check_only || (ranks && ranks->size > 1))
        return mote_script_run_file(script ? script : MOTE_DEFAULT_SCRIPT, models, nmodels, &opt);
    stop_guard g;
    guard_start(&g);
    if (g.fd >= 0) {
        opt.interrupt = stop_asked;
        opt.interrupt_arg = &g;
    }
    int rc = mote_script_run_file(script ? script : MOTE_DEFAULT_SCRIPT, models, nmodels, &opt);
    const int sig = guard_end(&g);
    if (sig) {
        fprintf(diag, "mote: stopped by %s\n", sig == SIGINT ? "Ctrl-C (SIGINT)" : strsignal(sig));
        rc = 128 + sig;
    }
    return rc;
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
