/* main.c: the `mote` program. It only names the models this build knows; everything else (run,
 * check, help) lives in the script layer (src/script).
 *
 * The MPI build (make MPI=1) starts MPI here. With more than one rank every rank runs the same
 * script: the charging model shares each run's histories among the ranks and sums their
 * tallies, the N-body model shares the bodies of every force pass and gathers their results,
 * so every rank holds the single process's numbers; rank 0 prints, the others are silent. The
 * other models have no use for ranks and are not offered.
 * `mote galactica` runs a Galactica job folder (the N-body model's own entry point). */
#include "mote/charging.h"
#include "mote/hardspheres.h"
#include "mote/mixingbox.h"
#include "mote/nbody.h"
#include "mote/script.h"
#include "mote/separator.h"

#include <stdio.h>
#include <string.h>

#ifdef MOTE_MPI
#include <mpi.h>
#endif

static const mote_model *const models[] = {
    &mote_model_hardspheres,
    &mote_model_mixingbox,
    &mote_model_nbody,
    &mote_model_charging,
    &mote_model_separator,
};

int main(int argc, char **argv)
{
#ifndef MOTE_MPI
    if (argc > 1 && strcmp(argv[1], "galactica") == 0) /* a Galactica job folder (spec 7) */
        return mote_nb_galactica_main(argc - 1, argv + 1, stdout, stderr);
#endif
#ifdef MOTE_MPI
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    int rc;
    if (size > 1) {
        static const mote_model *const mpi_models[] = {&mote_model_charging, &mote_model_nbody};
        if (rank != 0) {
            if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr))
                MPI_Abort(MPI_COMM_WORLD, 1);
        } else {
            fprintf(stderr, "mote: %d MPI ranks share the work (the charging model's histories, "
                            "the N-body model's bodies; the other models do not run under "
                            "MPI)\n", size);
        }
        if (argc > 1 && strcmp(argv[1], "galactica") == 0)
            rc = mote_nb_galactica_main(argc - 1, argv + 1, stdout, stderr);
        else
            rc = mote_script_main(argc, argv, mpi_models, 2);
    } else if (argc > 1 && strcmp(argv[1], "galactica") == 0) {
        rc = mote_nb_galactica_main(argc - 1, argv + 1, stdout, stderr);
    } else {
        rc = mote_script_main(argc, argv, models, sizeof models / sizeof models[0]);
    }
    MPI_Finalize();
    return rc;
#else
    return mote_script_main(argc, argv, models, sizeof models / sizeof models[0]);
#endif
}
