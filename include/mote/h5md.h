/* h5md.h: trajectories and snapshots in H5MD 1.1 (HDF5 for molecular data; de Buyl, Colberg
 * and Höfling, Comput. Phys. Commun. 185 (2014) 1546), the format h5py, MDAnalysis and OVITO
 * read: the output layer's `trajectory ... format=h5md` and `snapshot ... format=h5md` in every
 * particle model. A model fills one mote_h5md_frame from its state; this layer knows no model.
 *
 * The file (the particle group is "all"):
 *
 *     /h5md                      version = [1, 1]; author (name), creator (name = "mote",
 *                                version); modules/units when the frame has units
 *     /parameters/mote           attributes: model, command (the one that wrote the file), seed
 *     /particles/all/box         attributes dimension, boundary ("periodic" | "none" per axis);
 *                                edges/{step,time,value[F][D]} when the model has a box
 *     /particles/all/position    step[F] (int64), time[F] (float64), value[F][N][D]
 *     /particles/all/velocity    value[F][N][D] (step, time: links to position's)
 *     /particles/all/species     value[F][N] int32, when the model has species (the group's
 *                                attribute names: their names, when the model has them)
 *     /particles/all/id          value[F][N] int64, when its particles have numbers that last
 *     /particles/all/NAME        value[F][N] float64: the model's per-particle numbers (radius,
 *                                mass, diameter, ...)
 *
 * F grows by one per frame; N is the most particles any frame had: a frame with fewer leaves
 * the rest of its rows at the fill value (NaN, and -1 for species and id, as H5MD asks for
 * particles that are absent). Datasets are chunked one frame at a time and compressed
 * (shuffle + deflate), with no object times, so a file depends only on what was written.
 * Units: a `unit` attribute on each value (and on time) in the frame's units; none (the
 * model's reduced units) when the frame gives no length unit.
 *
 * The first frame is written atomically (the whole file built in memory, then renamed over
 * PATH by mote_afile: an earlier file is replaced only by a complete one); later frames are
 * appended in place, the file opened and closed around each, so a run that fails (or a command
 * stopped at a safe point: Ctrl-C in `mote run` and in Python) keeps every frame written so
 * far, and a frame that fails to write is cut off again; room for it is taken first, so a full
 * disk refuses it before the file is touched. A process killed hard (SIGKILL, a second Ctrl-C)
 * while it adds a frame can leave the file unreadable: HDF5 keeps no journal of its records. */
#ifndef MOTE_H5MD_H
#define MOTE_H5MD_H

#include "mote/core.h"

#include <stddef.h>
#include <stdint.h>

/* The paragraph every model's `trajectory` and `snapshot` help gives (the same words in each). */
#define MOTE_H5MD_HELP                                                                           \
    "format=h5md (or a FILE named .h5 or .h5md) writes H5MD instead, HDF5 for\n"                  \
    "molecular data (h5py, MDAnalysis, OVITO): /particles/all/position, velocity\n"                \
    "and the model's per-particle numbers as value[frame][particle][axis] with their\n"            \
    "step and time, the box with its boundary, units where the model has them;\n"                 \
    "chunked and compressed. A trajectory's first frame makes the file atomically,\n"             \
    "later frames are added at its end with the file closed after each: a run that\n"             \
    "fails or is stopped by Ctrl-C (at a safe point) keeps every frame so far; only a\n"          \
    "hard kill while it adds a frame can leave the file unreadable, as HDF5 keeps no\n"           \
    "journal (docs/file-formats.md, H5MD).\n"

#define MOTE_H5MD_SCALARS 4
#define MOTE_H5MD_VECTORS 2

typedef struct {
    const char *name; /* "radius" */
    const char *unit; /* "m", or NULL (reduced units) */
    const double *v;  /* n values */
} mote_h5md_scalar;

typedef struct {
    const char *model;  /* "hard-spheres", "mixing-box", "nbody", "separator" */
    const char *origin; /* the command that writes the file (NULL: "(library call)") */
    uint64_t seed;
    int dim;            /* 2 or 3 */
    size_t n;           /* particles in this frame */
    const double *pos;  /* n * dim */
    const double *vel;  /* n * dim, or NULL */
    const int32_t *species; /* n, or NULL */
    const char *const *species_names; /* the names of species 0, 1, ... (NULL: none): the
                                       * attribute `names` of /particles/all/species */
    int nspecies_names;
    const int64_t *id;  /* n, or NULL */
    int nscalar;
    mote_h5md_scalar scalar[MOTE_H5MD_SCALARS];
    int nvector;        /* per-particle vectors (v: n * dim values): contact_force */
    mote_h5md_scalar vector[MOTE_H5MD_VECTORS];
    int has_box;        /* edges[] holds the box's lengths */
    double edges[3];
    int periodic[3];    /* per axis: periodic, or "none" */
    double time;
    int64_t step;
    const char *length_unit, *time_unit; /* e.g. "m", "s"; NULL: reduced units */
} mote_h5md_frame;

/* PATH made anew with this one frame, atomically. */
int mote_h5md_first(const char *path, const mote_h5md_frame *fr, mote_err *err);
/* One more frame at the end of PATH (a file mote_h5md_first made). */
int mote_h5md_append(const char *path, const mote_h5md_frame *fr, mote_err *err);

/* Does path end in ".h5" or ".h5md" (any case)? Such a name asks for format=h5md. */
int mote_path_is_h5md(const char *path);

#endif
