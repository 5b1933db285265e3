/* plot.h: internal to the hard-spheres model: turn a data file of `image` or `profile` into a PNG
 * (the `plot` command). */
#ifndef MOTE_HS_PLOT_H
#define MOTE_HS_PLOT_H

#include "mote/core.h"

int hs_plot_file(const char *data_path, const char *png_path, mote_err *err);

#endif
