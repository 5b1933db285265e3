/* nb.h: internal to the N-body model: what its files share. */
#ifndef MOTE_NB_INTERNAL_H
#define MOTE_NB_INTERNAL_H

#include "mote/nbody.h"

/* Render an N-body data file (trajectory: orbits; monitor: drifts) as a PNG (plot.c). */
int nb_plot_file(const char *data_path, const char *png_path, mote_err *err);

/* The state file (state.c): save, load (replacing nb on success only, which must have the
 * file's interaction), and the body count of a file's header (for validation). */
int nb_state_save(const mote_nb *nb, const char *path, mote_err *err);
int nb_state_load(mote_nb *nb, const char *path, mote_err *err);
int nb_state_peek(const char *path, uint32_t *n, mote_err *err);

/* The integrators' parts (galactica.c, taylor.c): the settings checked (and scratch sized),
 * and one step of at most `rest` (returns the step taken). */
int nb_galactica_check(const mote_nb *nb, mote_err *err);
double nb_galactica_step(mote_nb *nb, double rest);
int nb_taylor_check(mote_nb *nb, mote_err *err);
double nb_taylor_step(mote_nb *nb, double rest);

/* y += d with the compensation term *cs (Kahan: the rounding error of one addition is carried
 * into the next; cs = y - the true sum). `on` = 0: a plain addition. */
static inline void kahan_add(double *y, double *cs, double d, int on)
{
    if (!on) {
        *y += d;
        return;
    }
    double t = d - *cs, s = *y + t;
    *cs = (s - *y) - t;
    *y = s;
}

/* Run nb's integrator as `integrator` for at most `steps` steps (integrate.c). */
int nb_run_as(mote_nb *nb, int integrator, uint64_t steps, mote_err *err);

/* Is merging on for this system (the default: when any active body has a radius)? */
int nb_merging_on(const mote_nb *nb);

#endif
