/* plot.h: internal to the hard-spheres model: its pictures: a data file of `image` or `profile`
 * turned into a PNG (the `plot` command, plot.c), and the live view's frame (live.c). */
#ifndef MOTE_HS_PLOT_H
#define MOTE_HS_PLOT_H

#include "mote/core.h"
#include "mote/hardspheres.h"
#include "mote/buf.h"

int hs_plot_file(const char *data_path, const char *png_path, mote_err *err);
/* The live view's members of a frame (docs/live-view.md); reads the system only. */
void hs_live_frame(const mote_hs *hs, mote_buf *b);

#endif
