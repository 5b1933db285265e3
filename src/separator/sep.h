/* sep.h: internal to the separator model: what its files share. */
#ifndef MOTE_SEP_INTERNAL_H
#define MOTE_SEP_INTERNAL_H

#include "mote/separator.h"

/* dem.c: rebuild the cell lists; the cell of particle i; the contact forces into fx, fy, fz
 * from the positions, with the dashpots on the predicted velocities v + dt/2 F_old/m. */
int sep_cells_build(mote_sep_system *s, mote_err *err);
size_t sep_cell_of(const mote_sep_system *s, size_t i);
/* Whether a particle of diameter d at (px, py, pz) would overlap one in the channel: through
 * the cells built after this step's exits, and the particles added since one by one. */
int sep_overlaps_any(const mote_sep_system *s, double px, double py, double pz, double d);
/* system.c: whether a sphere of radius r at (x, y, z) touches or is inside a plate. */
int sep_touches_plate(const mote_sep_system *s, double x, double y, double z, double r);
int sep_contact_forces(mote_sep_system *s, double dt, mote_err *err);

#endif
