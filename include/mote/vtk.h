/* vtk.h: legacy VTK files ("# vtk DataFile Version 3.0"; ParaView, VisIt and VTK's own readers)
 * for every model: the numbers' writer the charging model's surface files use, and particle
 * snapshots (`snapshot ... format=vtk` in the hard-sphere, mixing-box and separator models)
 * made from the same frame a model fills for H5MD (h5md.h), so that the two formats hold the
 * same arrays under the same names.
 *
 * A particle file is POLYDATA: the positions as POINTS (a 2D frame's (a, b) as (a, b, 0), as
 * Python's to_ase places them), one VERTEX per particle (so that ParaView shows them without a
 * filter), FIELD data TIME (ParaView's time of the file) and STEP, and POINT_DATA: the velocity
 * (VECTORS), species (SCALARS int), id (SCALARS double: exact to 2^53), each per-particle number
 * of the frame (SCALARS double, under its name: diameter, radius, mass) and each per-particle
 * vector (VECTORS: contact_force). Numbers are big-endian binary doubles and 32-bit ints (exact;
 * the format's BINARY form); the title line names the model, the time and the species. The file
 * is written atomically (mote_afile): an earlier one is replaced only by a complete file. */
#ifndef MOTE_VTK_H
#define MOTE_VTK_H

#include "mote/h5md.h"

#include <stddef.h>
#include <stdio.h>

/* The paragraph every model's `snapshot` help gives about format=vtk (the same words in each). */
#define MOTE_VTK_HELP                                                                            \
    "format=vtk (or a FILE named .vtk) writes a legacy VTK file instead, for\n"                 \
    "ParaView and VisIt: the particles as points (a 2D frame's plane as x, y with\n"             \
    "z = 0), one vertex each, the time as the file's TIME, and the per-particle\n"               \
    "numbers of the H5MD frame as point data under the same names (velocity,\n"                 \
    "species, id, radius or diameter, ...), exact binary doubles, written\n"                    \
    "atomically; a series is P_000000.vtk, ..., which ParaView opens as one time\n"             \
    "series. In ParaView, Glyph with a sphere scaled by the diameter (2 x radius)\n"             \
    "shows the particles at their size. A trajectory is not offered in VTK: one\n"              \
    "frame a file (docs/file-formats.md, VTK).\n"

/* n numbers of legacy VTK data: as text with `digits` significant digits, one to a line, or
 * (binary) big-endian doubles, or 32-bit ints when is_int is 1 (is_int 2: whole numbers kept as
 * doubles, written as text without a fraction); a binary block ends with a newline. */
void mote_vtk_put(FILE *f, const double *v, size_t n, int binary, int is_int, int digits);

/* PATH (made anew, atomically) holding the particles of one frame. */
int mote_vtk_particles(const char *path, const mote_h5md_frame *fr, mote_err *err);

/* Does path end in ".vtk" (any case)? Such a name asks for format=vtk. */
int mote_path_is_vtk(const char *path);

#endif
