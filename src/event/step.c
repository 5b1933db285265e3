/* step.c: the event loop of the engine: predicting a particle's next event, renewing its
 * neighbour list, and running from event to event, in three builds: 2D and 3D hard particles and
 * 2D field mode. */
#include "internal.h"

/* ---- the hot loop, instantiated for 2D and 3D --------------------------------------------------- */

#define FIELD 0
#define D 2
#define FN(name) name##_2d
#include "engine_dim.inc"
#undef D
#undef FN
#define D 3
#define FN(name) name##_3d
#include "engine_dim.inc"
#undef D
#undef FN
#undef FIELD
/* field mode (2D, gravity, obstacles, the model's rules): a third build of the same loop */
#define FIELD 1
#define D 2
#define FN(name) name##_2f
#include "engine_dim.inc"
#undef D
#undef FN
#undef FIELD

void ev_predict(mote_ev *ev, uint32_t i)
{
    if (ev->field)
        predict_2f(ev, i);
    else if (ev->dim == 2)
        predict_2d(ev, i);
    else
        predict_3d(ev, i);
}


int mote_ev_run(mote_ev *ev, uint64_t ncoll, mote_err *err)
{
    if (!ev->ready)
        return not_ready(err, "run");
    if (ncoll == 0)
        return MOTE_OK;
    ev->canonical = 0;
    if (ev->field)
        return run_2f(ev, ncoll, INFINITY, err);
    return ev->dim == 2 ? run_2d(ev, ncoll, INFINITY, err) : run_3d(ev, ncoll, INFINITY, err);
}

int mote_ev_run_to(mote_ev *ev, double t_stop, uint64_t ncoll, mote_err *err)
{
    if (!ev->ready)
        return not_ready(err, "run");
    if (ncoll == 0 || !(t_stop > mote_ev_time(ev)))
        return MOTE_OK;
    if (ncoll > UINT64_MAX - ev->collisions)
        ncoll = UINT64_MAX - ev->collisions;
    ev->canonical = 0;
    if (ev->field)
        return run_2f(ev, ncoll, t_stop, err);
    return ev->dim == 2 ? run_2d(ev, ncoll, t_stop, err) : run_3d(ev, ncoll, t_stop, err);
}
