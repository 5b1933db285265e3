/* main.c: the `mote` program. It names no model: the registry (mote_models, command.h) lists
 * them, and everything else (run, check, help) lives in the script layer (src/script). A
 * model's own program (`mote galactica`, the N-body model's Galactica job folder) is a field of
 * its registry entry.
 *
 * The MPI build (make MPI=1) starts MPI here. With more than one rank every rank runs the same
 * script. The models whose entry says they share their work among ranks (the charging model
 * shares each run's histories and sums the tallies, the N-body model the bodies of every force
 * pass) run every command in every rank, so every rank holds the single process's numbers; the
 * other models run their commands in rank 0, and every rank takes part in their ensembles,
 * whose replicas are spread over the ranks (the script layer's mote_ranks, given here). Rank 0
 * prints, the others are silent. */
#include "mote/command.h"
#include "mote/script.h"

#include <stdio.h>
#include <string.h>

MOTE_PROGRAM_THREADS

#ifdef MOTE_MPI
#include <mpi.h>
#include <stdlib.h>

/* mote_ranks.allgather over MPI_COMM_WORLD: the lengths, then the bytes (in chunks below 2^31) */
static char *allgather(const mote_ranks *r, const char *buf, size_t n, size_t *lens)
{
    unsigned long long mine = n, *all = malloc((size_t)r->size * sizeof *all);
    int ok = all != NULL, every = 0;
    MPI_Allreduce(&ok, &every, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
    if (!every) {
        free(all);
        return NULL;
    }
    MPI_Allgather(&mine, 1, MPI_UNSIGNED_LONG_LONG, all, 1, MPI_UNSIGNED_LONG_LONG,
                  MPI_COMM_WORLD);
    size_t total = 0;
    for (int k = 0; k < r->size; k++)
        total += lens[k] = (size_t)all[k];
    char *out = malloc(total ? total : 1);
    ok = out != NULL;
    MPI_Allreduce(&ok, &every, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
    if (!every) {
        free(all);
        free(out);
        return NULL;
    }
    size_t at = 0; /* each rank's bytes in turn, broadcast from it */
    for (int k = 0; k < r->size; k++) {
        if (k == r->rank && lens[k])
            memcpy(out + at, buf, lens[k]);
        for (size_t done = 0; done < lens[k];) {
            int chunk = lens[k] - done > (1u << 30) ? 1 << 30 : (int)(lens[k] - done);
            MPI_Bcast(out + at + done, chunk, MPI_BYTE, k, MPI_COMM_WORLD);
            done += (size_t)chunk;
        }
        at += lens[k];
    }
    free(all);
    return out;
}
#endif

int main(int argc, char **argv)
{
#ifdef MOTE_MPI
    const mote_model *prog = mote_program_of(argc, argv, mote_models, mote_nmodels);
    MPI_Init(&argc, &argv);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    int rc;
    if (size > 1) {
        char names[256] = "";
        for (size_t k = 0, n = 0; k < mote_nmodels; k++)
            if (mote_models[k]->mpi) {
                size_t used = strlen(names);
                snprintf(names + used, sizeof names - used, "%s%s", n++ ? ", " : "",
                         mote_models[k]->name);
            }
        const mote_ranks ranks = {rank, size, allgather};
        if (rank != 0) {
            if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr))
                MPI_Abort(MPI_COMM_WORLD, 1);
        } else {
            fprintf(stderr, "mote: %d MPI ranks share the work of the models %s; the other "
                            "models run in rank 0, and spread their ensembles' replicas over "
                            "the ranks\n", size, names);
        }
        if (prog && prog->mpi)
            rc = prog->program_main(argc - 1, argv + 1, stdout, stderr);
        else
            rc = mote_script_main_ranks(argc, argv, mote_models, mote_nmodels, &ranks);
    } else if (prog) {
        rc = prog->program_main(argc - 1, argv + 1, stdout, stderr);
    } else {
        rc = mote_script_main(argc, argv, mote_models, mote_nmodels);
    }
    MPI_Finalize();
    return rc;
#else
    return mote_main(argc, argv, mote_models, mote_nmodels);
#endif
}
