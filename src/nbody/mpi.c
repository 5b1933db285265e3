/* mpi.c: the N-body model on several MPI ranks (spec 6.3; the MPI build, make MPI=1). Bodies are
 * split into contiguous, balanced index blocks, one per rank; in every pass each rank sums the
 * forces on its own bodies over all sources, in the same fixed order a single process uses, and
 * the new derivatives (or Taylor coefficients) of all bodies are then exchanged with an
 * all-gather. Every rank thus holds the whole state, bit for bit the single process's, and takes
 * every other decision (step, merges, outputs) itself from it. Without MPI (or on one rank)
 * these are no-ops. */
#include "nb.h"

#ifdef MOTE_MPI
#include <mpi.h>
#include <stdlib.h>
#endif

void nb_mpi_layout(mote_nb *nb)
{
    int rank = 0, size = 1;
#ifdef MOTE_MPI
    int init = 0, fin = 0;
    MPI_Initialized(&init);
    MPI_Finalized(&fin);
    if (init && !fin) {
        MPI_Comm_rank(MPI_COMM_WORLD, &rank);
        MPI_Comm_size(MPI_COMM_WORLD, &size);
    }
#endif
    nb->mpi_rank = rank;
    nb->mpi_size = size;
    nb->lo = (uint32_t)((uint64_t)nb->n * (uint64_t)rank / (uint64_t)size);
    nb->hi = (uint32_t)((uint64_t)nb->n * (uint64_t)(rank + 1) / (uint64_t)size);
}

int nb_mpi_rank(void)
{
    int rank = 0;
#ifdef MOTE_MPI
    int init = 0, fin = 0;
    MPI_Initialized(&init);
    MPI_Finalized(&fin);
    if (init && !fin)
        MPI_Comm_rank(MPI_COMM_WORLD, &rank);
#endif
    return rank;
}

void nb_mpi_gather(const mote_nb *nb, mote_real *a, size_t per)
{
#ifdef MOTE_MPI
    if (nb->mpi_size <= 1)
        return;
    const int size = nb->mpi_size;
    int *cnt = malloc(2 * (size_t)size * sizeof *cnt);
    if (!cnt)
        MPI_Abort(MPI_COMM_WORLD, 1);
    int *dsp = cnt + size;
#if MOTE_NB_PRECISION == 1
    const MPI_Datatype type = MPI_DOUBLE;
    const size_t unit = per;
#elif MOTE_NB_PRECISION == 2
    const MPI_Datatype type = MPI_LONG_DOUBLE;
    const size_t unit = per;
#else
    const MPI_Datatype type = MPI_BYTE;
    const size_t unit = per * sizeof(mote_real);
#endif
    for (int r = 0; r < size; r++) {
        const uint64_t lo = (uint64_t)nb->n * (uint64_t)r / (uint64_t)size,
                       hi = (uint64_t)nb->n * (uint64_t)(r + 1) / (uint64_t)size;
        cnt[r] = (int)((hi - lo) * unit);
        dsp[r] = (int)(lo * unit);
    }
    MPI_Allgatherv(MPI_IN_PLACE, 0, type, a, cnt, dsp, type, MPI_COMM_WORLD);
    free(cnt);
#else
    (void)nb;
    (void)a;
    (void)per;
#endif
}
