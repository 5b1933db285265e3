/* mesh.h: triangle meshes from files, read and repaired once for every model that takes them
 * (the charging model's spacecraft, the separator's walls). Files are read through Assimp (STL
 * ASCII and binary, OBJ, PLY, glTF and the rest; OBJ groups and STL solids become parts), in a
 * child process with bounded memory and time, or in the plain format of the charging program
 * (9 numbers per triangle). The triangles are scaled, turned about an axis and moved, then
 * repaired as a whole: degenerate and duplicate triangles dropped, vertices welded, components
 * formed across shared edges, closed components (every edge shared by exactly two triangles)
 * oriented consistently and outward, open ones kept as sheets. */
#ifndef MOTE_MESH_H
#define MOTE_MESH_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "mote/command.h"
#include "mote/core.h"

/* Part names are kept whole up to MOTE_MESH_NAME_LEN - 1 bytes; a longer one is an error. */
#define MOTE_MESH_NAME_LEN 256

typedef struct {
    const char *format;    /* "auto", "plain" or "assimp" */
    double scale;          /* length of one file unit in m */
    double offset[3];      /* m, added after scaling and turning */
    int rot_axis;          /* -1: none; 0, 1, 2: x, y, z */
    double rot_deg;
    const char *part;      /* the part name when the file gives none (NULL: the file name) */
    int strict;            /* plain format: an abandoned line is an error */
} mote_mesh_opts;

typedef struct {
    uint32_t read, degenerate, duplicates, welded, flipped, closed_components, open_components;
    uint32_t abandoned_lines;
    int trailing_numbers;  /* plain format: numbers of an unfinished last triangle (dropped) */
} mote_mesh_report;

/* A repaired mesh: welded vertices, triangles as vertex indices (closed components wound
 * outward by the right-hand rule), each triangle's part, component and whether that component
 * is closed and whether its winding is the file's turned round. */
typedef struct {
    size_t nv, nt;
    double (*v)[3];
    uint32_t (*t)[3];
    int *part;
    uint32_t *comp;        /* components numbered from 0 in the order of their first triangle */
    uint8_t *closed, *flipped;
    size_t ncomp;
    char (*names)[MOTE_MESH_NAME_LEN];
    int nnames;
} mote_mesh;

/* Read, transform and repair the mesh file path (m replaced; errors name the file and, in the
 * plain format, the line). An error also when every triangle is degenerate or a duplicate. */
int mote_mesh_load(mote_mesh *m, const char *path, const mote_mesh_opts *o,
                   mote_mesh_report *rep, mote_err *err);
void mote_mesh_free(mote_mesh *m);
/* The cheap checks of a mesh file made before Assimp reads it (OFF and PLY header counts against
 * the file's size, NUL bytes in a text header, a PLY header's end): 0, or "FILE: reason". For
 * commands' checks, so a damaged header fails before anything runs. */
int mote_mesh_precheck(const char *path, mote_err *err);
/* Whether the format named (o->format, and the name's extension when "auto") is the plain one. */
int mote_mesh_is_plain(const char *path, const char *format);
/* A command's options for a mesh file, the same words in every model: format=, units= (or
 * scale=), offset=, rotate=AXIS,DEGREES, part=, strict= (MOTE_MESH_CALL_OPTS, for the command's
 * table after its file=); -1 and an error at the option when one is bad (cmd names the
 * command). */
#define MOTE_MESH_CALL_OPTS                                                                     \
    "format=e{auto|plain|assimp} units=e{m|cm|mm|in} scale=r>0 part=s offset=v3 rotate=s "     \
    "strict=e{yes|no}"
int mote_mesh_call_opts(const mote_call *c, const char *cmd, mote_mesh_opts *o,
                        mote_err *err);
/* The report of a load as one line to log (and a warning line for a plain file's unfinished
 * last triangle). */
void mote_mesh_report_line(FILE *log, const char *cmd, const char *path,
                           const mote_mesh_report *rep);
/* Assimp's import of a file through mote's streaming reader (meshio.c): an OBJ's object names
 * keep their blanks as '_' (`o panel left` is the part panel_left). */
struct aiScene;
const struct aiScene *mote_mesh_assimp_import(const char *path, unsigned flags);

#endif
