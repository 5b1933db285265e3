/* tally.c: the parts of the Monte Carlo run (mc.c) outside its histories: the tallies summed
 * across MPI ranks (spec 5.6: ranks share the blocks of histories, block b on rank b mod size;
 * the integer tallies are summed, so the result is the single process's), and the
 * photoemission of the sunlit triangles (spec 6.8), which draws no random numbers. */
#include "ch.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef MOTE_MPI
#include <mpi.h>
#endif

/* (solo: a run that stays in this process, an ensemble's replica on one rank) */
void ch_mpi_layout(int solo, int *rank, int *size)
{
    *rank = 0;
    *size = 1;
#ifdef MOTE_MPI
    int init = 0;
    if (solo)
        return;
    MPI_Initialized(&init);
    if (init) {
        MPI_Comm_rank(MPI_COMM_WORLD, rank);
        MPI_Comm_size(MPI_COMM_WORLD, size);
    }
#endif
}

int ch_mpi_size(int solo)
{
    int rank, size;
    ch_mpi_layout(solo, &rank, &size);
    return size;
}

int ch_mpi_rank(int solo)
{
    int rank, size;
    ch_mpi_layout(solo, &rank, &size);
    return rank;
}

#ifdef MOTE_MPI
/* an MPI reduction: the sum of 128-bit integers (copied, for buffers of any alignment) */
static void sum_i128(void *in, void *inout, int *len, MPI_Datatype *type)
{
    (void)type;
    for (int i = 0; i < *len; i++) {
        ch_i128 a, b;
        memcpy(&a, (char *)in + 16 * (size_t)i, 16);
        memcpy(&b, (char *)inout + 16 * (size_t)i, 16);
        b += a;
        memcpy((char *)inout + 16 * (size_t)i, &b, 16);
    }
}
#endif

/* Sum n 128-bit integers over the ranks (in place). */
void ch_mpi_sum128(int solo, ch_i128 *v, size_t n)
{
#ifdef MOTE_MPI
    int rank, size;
    ch_mpi_layout(solo, &rank, &size);
    if (size < 2 || !v)
        return;
    MPI_Datatype t128;
    MPI_Op op;
    MPI_Type_contiguous(16, MPI_BYTE, &t128);
    MPI_Type_commit(&t128);
    MPI_Op_create(sum_i128, 1, &op);
    MPI_Allreduce(MPI_IN_PLACE, v, (int)n, t128, op, MPI_COMM_WORLD);
    MPI_Op_free(&op);
    MPI_Type_free(&t128);
#else
    (void)solo;
    (void)v;
    (void)n;
#endif
}

/* Sum the tallies of one component over the ranks: the hit counts per triangle and side, the
 * counters, the largest energy error, the secondary scores (n128 128-bit integers). */
void ch_mpi_merge(int solo, uint64_t *tally, size_t ntally, uint64_t cnt[4], double *eerr,
                  ch_i128 *see, size_t n128)
{
#ifdef MOTE_MPI
    int rank, size;
    ch_mpi_layout(solo, &rank, &size);
    if (size < 2)
        return;
    MPI_Allreduce(MPI_IN_PLACE, tally, (int)ntally, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, cnt, 4, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, eerr, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
#else
    (void)tally;
    (void)ntally;
    (void)cnt;
    (void)eerr;
#endif
    ch_mpi_sum128(solo, see, n128);
}

/* Differential charging: the photocurrent I0 (escape 1) of a triangle of patch pp, escaping by
 * the patch's potential U_s + dv at each dv of the grid. */
static void patch_photo(mote_ch_result *r, const mote_ch_run_opts *o, int pp, double I0,
                        double U_s, double kT_ph)
{
    for (int g = 0; g < o->ndv; g++)
        r->patch_I[(size_t)pp * (size_t)o->ndv + (size_t)g] += I0 * mote_ch_escape(U_s + o->dv[g], kT_ph);
}

/* Photoemission (spec 6.8): the sunlit triangles' photocurrents; no random numbers, unless the
 * photoelectrons are traced (tr not NULL). */
int ch_photoemission(const mote_ch_body *b, const mote_ch_tracer *t,
                     const mote_ch_run_opts *o, mote_ch_result *r, uint32_t ntri, double U_s,
                     int patchy, const ch_photo_tracer *tr, mote_err *err)
{
    r->tri_photo = calloc((size_t)ntri * 2, sizeof *r->tri_photo);
    r->tri_sunlit = calloc((size_t)ntri * 2, sizeof *r->tri_sunlit);
    int *side = b->sphere ? NULL : malloc((size_t)ntri * sizeof *side);
    double *frac = b->sphere ? NULL : malloc((size_t)ntri * sizeof *frac);
    double *I0 = b->sphere ? NULL : malloc((size_t)ntri * sizeof *I0);
    double *esc = b->sphere ? NULL : malloc((size_t)ntri * sizeof *esc);
    uint64_t *first = tr ? malloc(((size_t)ntri + 1) * sizeof *first) : NULL;
    if (!r->tri_photo || !r->tri_sunlit ||
        (!b->sphere && (!side || !frac || !I0 || !esc || (tr && !first)))) {
        free(side);
        free(frac);
        free(I0);
        free(esc);
        free(first);
        return mote_fail(err, MOTE_ENOMEM, "run: out of memory for the photoemission");
    }
    const double inten = o->sun_intensity;
    if (b->sphere) { /* the lit half: the projected disc */
        const mote_ch_material *mat = o->tri_material[0];
        r->tri_sunlit[0] = 0.5;
        const double J0 = mat->photo_j * inten * MOTE_CH_PI * b->sphere_r * b->sphere_r;
        r->tri_photo[0] = J0 * mote_ch_escape(U_s, mat->kT_ph);
        r->photo = r->tri_photo[0];
        if (patchy && o->tri_patch[0] >= 0)
            patch_photo(r, o, o->tri_patch[0], J0, U_s, mat->kT_ph);
        return MOTE_OK;
    }
    mote_ch_sunlit(b, t, o->sun_dir, frac, side, o->threads);
    double total = 0;
    for (uint32_t i = 0; i < ntri; i++) {
        I0[i] = 0;
        if (side[i] < 0)
            continue;
        const double *nr = b->nrm[i];
        const double cs = fabs(nr[0] * o->sun_dir[0] + nr[1] * o->sun_dir[1] +
                               nr[2] * o->sun_dir[2]);
        I0[i] = o->tri_material[i]->photo_j * inten * b->area[i] * cs * frac[i];
        esc[i] = mote_ch_escape(U_s, o->tri_material[i]->kT_ph);
        total += I0[i];
    }
    if (tr && total > 0) {
        /* the photoelectrons followed: tr->paths of them shared among the sunlit triangles by
         * their photocurrent (at least two each: the error of each share is estimated from
         * its own), each triangle's escaping share estimated from its own; the triangles' histories numbered in order, so that any number of
         * threads gives the same bits */
        first[0] = 0;
        for (uint32_t i = 0; i < ntri; i++) {
            uint64_t n = 0;
            if (I0[i] > 0)
                n = (uint64_t)fmax(2, llround((double)tr->paths * I0[i] / total));
            first[i + 1] = first[i] + n;
        }
        const long n = (long)ntri;
        const int nt = o->threads > 1 ? o->threads : 1;
#pragma omp parallel for num_threads(nt) if (nt > 1) schedule(dynamic, 4)
        for (long i = 0; i < n; i++)
            if (first[i + 1] > first[i])
                esc[i] = tr->escape(tr->ctx, (uint32_t)i, side[i], first[i], first[i + 1] - first[i],
                                    o->tri_material[i]->kT_ph);
        r->photo_paths = first[ntri];
    }
    for (uint32_t i = 0; i < ntri; i++) {
        if (side[i] < 0)
            continue;
        r->tri_sunlit[2 * (size_t)i + (size_t)side[i]] = frac[i];
        const double I = I0[i] * esc[i];
        if (tr && first[i + 1] > first[i]) /* (binomial: the unbiased estimate, n >= 2) */
            r->photo_sigma += I0[i] * I0[i] * esc[i] * (1 - esc[i]) /
                              (double)(first[i + 1] - first[i] - 1);
        if (patchy && o->tri_patch[i] >= 0)
            patch_photo(r, o, o->tri_patch[i], I0[i], U_s, o->tri_material[i]->kT_ph);
        r->tri_photo[2 * (size_t)i + (size_t)side[i]] = I;
        r->photo += I;
    }
    r->photo_sigma = sqrt(r->photo_sigma);
    free(side);
    free(frac);
    free(I0);
    free(esc);
    free(first);
    return MOTE_OK;
}
