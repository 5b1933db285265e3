/* integrate.c: the run of either integrator: steps up to a count and/or to an end time that is
 * hit exactly (the last step is shortened to it and the time set to it, spec 4.5). */
#include "mote/nbody.h"

#include <tgmath.h>

#include "nb.h"

int mote_nb_integrate(mote_nb *nb, uint64_t max_steps, mote_real t_end, mote_err *err)
{
    const nb_integrator *in = nb_integrator_of(nb->integrator);
    int rc = in->check(nb, err);
    if (!rc)
        rc = mote_nb_prepare(nb, err);
    nb_mpi_layout(nb);
    if (!rc && nb->tree_on && nb->mpi_size > 1)
        rc = mote_fail(err, MOTE_EINVAL, "forces tree and MPI ranks do not go together in this "
                                         "version (spec 6.3): use forces direct, or one rank");
    if (!rc)
        rc = nb_tree_check(nb, in->tree_blocks(nb), err);
    if (rc)
        return rc;
    nb->tree_used |= nb->tree_on;
    if (!(t_end > nb->T) && t_end < INFINITY)
        return MOTE_OK;
    if (!nb->ref_set)
        mote_nb_set_reference(nb);
    const int merge = nb_merging_on(nb);
    if (in->run) { /* one synchronised run; merges and bounds checked where it ends */
        rc = in->run(nb, max_steps, t_end, err);
        if (!rc && nb_state_bounded(nb, NULL)) {
            mote_err why = {0};
            nb_state_bounded(nb, &why);
            rc = mote_fail(err, MOTE_ERUNTIME, "integrate: the state stopped being finite by "
                           "step %llu (t = %.17g): %s; nothing more is written (a smaller dt "
                           "keeps a run finite)", (unsigned long long)nb->steps,
                           (double)nb->T, why.msg);
        }
        return !rc && merge ? mote_nb_merge(nb, err) : rc;
    }
    for (uint64_t s = 0; s < max_steps; s++) {
        mote_real rest = t_end < INFINITY ? t_end - nb->T : INFINITY;
        if (!(rest > 0))
            break;
        mote_real h = in->step(nb, rest);
        nb->hlast = h;
        if (!isfinite((double)h) || nb_state_bounded(nb, NULL)) {
            mote_err why = {0};
            nb_state_bounded(nb, &why);
            return mote_fail(err, MOTE_ERUNTIME, "integrate: the state stopped being finite in "
                             "step %llu (t = %.17g, h = %g): %s; nothing more is written (a "
                             "smaller dt, or hmax=, keeps a run finite)",
                             (unsigned long long)nb->steps, (double)nb->T, (double)h,
                             why.code ? why.msg : "the step is not a finite number");
        }
        if (merge && (rc = mote_nb_merge(nb, err)) != MOTE_OK)
            return rc;
        if (h >= rest) { /* the end time, exactly */
            nb->T = t_end;
            nb->Tc = 0;
            break;
        }
    }
    return MOTE_OK;
}

int nb_merging_on(const mote_nb *nb)
{
    if (nb->merging >= 0)
        return nb->merging;
    for (uint32_t i = 0; i < nb->n; i++)
        if (nb->active[i] && nb->ra[i] > 0)
            return 1;
    return 0;
}

int nb_run_as(mote_nb *nb, int integrator, uint64_t steps, mote_err *err)
{
    int was = nb->integrator;
    nb->integrator = integrator;
    int rc = mote_nb_integrate(nb, steps, INFINITY, err);
    nb->integrator = was;
    return rc;
}
