/* nb.h: internal to the N-body model: what its files share. */
#ifndef MOTE_NB_INTERNAL_H
#define MOTE_NB_INTERNAL_H

#include "mote/core.h"

/* Render an N-body data file (trajectory: orbits; monitor: drifts) as a PNG (plot.c). */
int nb_plot_file(const char *data_path, const char *png_path, mote_err *err);

#endif
