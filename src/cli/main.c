/* main.c: the `mote` program. It names no model: the registry (mote_models, command.h) lists
 * them, and everything else (run, check, help) lives in the script layer (src/script). A
 * model's own program (`mote galactica`, the N-body model's Galactica job folder) is a field of
 * its registry entry.
 *
 * The MPI build (make MPI=1) starts MPI here. With more than one rank every rank runs the same
 * script, and only the models whose entry says they share their work among ranks are offered
 * (the charging model shares each run's histories and sums the tallies, the N-body model the
 * bodies of every force pass), so every rank holds the single process's numbers; rank 0 prints,
 * the others are silent. */
#include "mote/command.h"
#include "mote/script.h"

#include <stdio.h>
#include <string.h>

#ifdef MOTE_MPI
#include <mpi.h>
#endif

/* The model whose own program argv[1] names, or NULL. */
static const mote_model *program_of(int argc, char **argv)
{
    for (size_t k = 0; argc > 1 && k < mote_nmodels; k++)
        if (mote_models[k]->program && strcmp(argv[1], mote_models[k]->program) == 0)
            return mote_models[k];
    return NULL;
}

int main(int argc, char **argv)
{
    const mote_model *prog = program_of(argc, argv);
#ifdef MOTE_MPI
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    int rc;
    if (size > 1) {
        const mote_model *shared[16];
        size_t n = 0;
        char names[256] = "";
        for (size_t k = 0; k < mote_nmodels && n < 16; k++)
            if (mote_models[k]->mpi) {
                size_t used = strlen(names);
                snprintf(names + used, sizeof names - used, "%s%s", n ? ", " : "",
                         mote_models[k]->name);
                shared[n++] = mote_models[k];
            }
        if (rank != 0) {
            if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr))
                MPI_Abort(MPI_COMM_WORLD, 1);
        } else {
            fprintf(stderr, "mote: %d MPI ranks share the work of the models %s (the other "
                            "models do not run under MPI)\n", size, names);
        }
        if (prog && prog->mpi)
            rc = prog->program_main(argc - 1, argv + 1, stdout, stderr);
        else
            rc = mote_script_main(argc, argv, shared, n);
    } else if (prog) {
        rc = prog->program_main(argc - 1, argv + 1, stdout, stderr);
    } else {
        rc = mote_script_main(argc, argv, mote_models, mote_nmodels);
    }
    MPI_Finalize();
    return rc;
#else
    if (prog)
        return prog->program_main(argc - 1, argv + 1, stdout, stderr);
    return mote_script_main(argc, argv, mote_models, mote_nmodels);
#endif
}
