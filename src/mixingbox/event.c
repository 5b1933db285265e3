/* event.c: the exact event-driven integrator of the mixing-box model (spec 3), to be built on the
 * shared event engine: exact disk-disk, wall, partition-face and slit-corner events, parabolic
 * flights under gravity, the shared collision rules (mote_mb_collide) and wall kicks. Not
 * written yet: this placeholder reports so, and validation rejects `integrator event` while
 * mb_event_available() returns 0. The contract it must keep is described in mixingbox.h above
 * mote_mb_hooks. */
#include "mote/mixingbox.h"

int mb_event_available(void) { return 0; }

int mb_run_event(mote_mb *sys, double t_end, mote_mb_hooks *hooks, mote_err *err)
{
    (void)sys;
    (void)t_end;
    (void)hooks;
    return mote_fail(err, MOTE_ERUNTIME,
                     "integrator event: not implemented yet; use 'integrator timestep'");
}
