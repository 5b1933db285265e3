/* galactica_main.c: `mote galactica [options]` and `mote galactica edit KEY=VALUE ...`, the
 * N-body model's own program (its registry entry's program_main): the command line of a
 * Galactica job folder, run by job.c. */
#include "mote/nbody.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void job_usage(FILE *f)
{
    fprintf(f,
            "Usage: mote galactica [--coulomb] [--frames] [--threads N] [--control FILE]\n"
            "                      [--lenient] [--packed] [--step-tol E] [--max-files N] [--force]\n"
            "       mote galactica edit [--coulomb] KEY=VALUE ...\n"
            "Run the Galactica job of this folder: read galacf26.dat (or --control FILE, whose\n"
            "folder then holds the job) and write Galactica's files under Galactica's names\n"
            "(garez28.dat, 1, 2, ..., 1t, ..., traekt.prn, dice.dat, galgon4, ErrGlctca).\n"
            "  --coulomb      the Coulomb module (garek29.dat, galgok2, 25/16 layout)\n"
            "  --frames       PNG pictures frame_000000.png, ... at every monitor block\n"
            "  --threads N    OpenMP threads of the force passes (results do not depend on it)\n"
            "  --lenient      take each control line's last token instead of column 60\n"
            "  --packed       trios at lines 51-53, 54-56, ... (default: by description, or the\n"
            "                 prose layout with line 53 reserved)\n"
            "  --step-tol E   the step tolerance of Kl4 = 2 or 3 (default 1e-16)\n"
            "  --max-files N  refuse to start above N output files (default 10000); --force\n"
            "edit changes the checkpoint galgon4 (galgok2) for the next launch: Ltk, Ltk2 (the\n"
            "next launch runs Ltk * Ltk2 steps), Kl3, Kl7, Kl12, Kli, Nbd, dT.\n"
            "Exit status: 0 success, 1 bad job (nothing ran), 2 failure during the run.\n"
            "See docs/galactica.md.\n");
}

int mote_nb_galactica_main(int argc, char **argv, FILE *out, FILE *diag)
{
    mote_nb_job o;
    memset(&o, 0, sizeof o);
    o.control = "galacf26.dat";
    o.out = out;
    o.threads = 1;
    int edit = argc > 1 && strcmp(argv[1], "edit") == 0, nedit = 0;
    char **edits = argv + 2;
    for (int k = 1 + edit; k < argc; k++) {
        const char *a = argv[k];
        const int more = k + 1 < argc;
        if (edit && a[0] != '-') {
            edits[nedit++] = argv[k]; /* (argv is rearranged: KEY=VALUE words first) */
            continue;
        }
        char *end = NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            job_usage(out);
            return 0;
        } else if (strcmp(a, "--coulomb") == 0) {
            o.coulomb = 1;
        } else if (strcmp(a, "--frames") == 0) {
            o.frames = 1;
        } else if (strcmp(a, "--lenient") == 0) {
            o.lenient = 1;
        } else if (strcmp(a, "--packed") == 0) {
            o.packed = 1;
        } else if (strcmp(a, "--force") == 0) {
            o.force = 1;
        } else if (strcmp(a, "--control") == 0 && more) {
            o.control = argv[++k];
        } else if (strcmp(a, "--threads") == 0 && more) {
            long t = strtol(argv[++k], &end, 10);
            if (*end || end == argv[k] || t < 1 || t > 4096) {
                fprintf(diag, "mote galactica: error: --threads needs a count 1 ... 4096, found "
                              "'%s'\n", argv[k]);
                return 1;
            }
            o.threads = (int)t;
        } else if (strcmp(a, "--max-files") == 0 && more) {
            long t = strtol(argv[++k], &end, 10);
            if (*end || end == argv[k] || t < 1) {
                fprintf(diag, "mote galactica: error: --max-files needs a count >= 1, found "
                              "'%s'\n", argv[k]);
                return 1;
            }
            o.max_files = t;
        } else if (strcmp(a, "--step-tol") == 0 && more) {
            double t = strtod(argv[++k], &end);
            if (*end || end == argv[k] || !(t > 0 && t < 1)) {
                fprintf(diag, "mote galactica: error: --step-tol needs a tolerance in (0, 1), "
                              "found '%s'\n", argv[k]);
                return 1;
            }
            o.step_tol = t;
        } else {
            fprintf(diag, "mote galactica: error: %s '%s'\n",
                    a[0] == '-' && !more ? "unknown option or missing value after" : "unknown "
                    "argument", a);
            job_usage(diag);
            return 1;
        }
    }
    mote_err err = {0};
    int started = 0;
    if (edit) {
        if (!nedit) {
            fprintf(diag, "mote galactica: error: edit needs KEY=VALUE words\n");
            return 1;
        }
        int rc = mote_nb_job_edit(&o, nedit, edits, &err);
        if (rc)
            fprintf(diag, "mote galactica: error: %s\n", err.msg);
        return rc ? 1 : 0;
    }
    /* progress when the monitor goes to a terminal */
    static const mote_context blank; /* (read-only: a zero context) */
    mote_context *ctx = malloc(sizeof *ctx);
    if (ctx) {
        *ctx = blank;
        ctx->terminal = out == stdout && isatty(STDOUT_FILENO);
        o.ctx = ctx;
    }
    int rc = mote_nb_job_run(&o, &started, &err);
    free(ctx);
    if (rc) {
        fprintf(diag, "mote galactica: error: %s\n", err.msg);
        return started ? 2 : 1;
    }
    return 0;
}
