/* vtk.c: legacy VTK files (vtk.h). */
#include "mote/vtk.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

void mote_vtk_put(FILE *f, const double *v, size_t n, int binary, int is_int, int digits)
{
    for (size_t k = 0; k < n; k++) {
        if (!binary) {
            if (is_int)
                fprintf(f, "%.0f\n", v[k]);
            else
                fprintf(f, "%.*g\n", digits, v[k]);
            continue;
        }
        unsigned char be[8];
        if (is_int == 1) {
            const uint32_t x = (uint32_t)(int32_t)v[k];
            for (int q = 0; q < 4; q++)
                be[q] = (unsigned char)(x >> (24 - 8 * q));
            fwrite(be, 1, 4, f);
        } else {
            uint64_t x;
            memcpy(&x, &v[k], 8);
            for (int q = 0; q < 8; q++)
                be[q] = (unsigned char)(x >> (56 - 8 * q));
            fwrite(be, 1, 8, f);
        }
    }
    if (binary)
        fputc('\n', f);
}

int mote_path_is_vtk(const char *path)
{
    const size_t n = strlen(path);
    return n >= 4 && strcasecmp(path + n - 4, ".vtk") == 0;
}

/* rows of dim numbers as rows of three (a 2D row's third 0), through the buffer b (3 n) */
static void put_rows(FILE *f, const double *v, size_t n, int dim, double *b)
{
    for (size_t i = 0; i < n; i++)
        for (int a = 0; a < 3; a++)
            b[3 * i + (size_t)a] = a < dim ? v[i * (size_t)dim + (size_t)a] : 0;
    mote_vtk_put(f, b, 3 * n, 1, 0, 17);
}

/* A name VTK keeps whole (no blanks): others become '_'. */
static void vtk_name(char *out, size_t cap, const char *name)
{
    snprintf(out, cap, "%s", name);
    for (char *q = out; *q; q++)
        if (*q == ' ' || *q == '\t' || *q == '\n' || *q == '\r')
            *q = '_';
}

int mote_vtk_particles(const char *path, const mote_h5md_frame *fr, mote_err *err)
{
    const size_t n = fr->n;
    const int dim = fr->dim == 2 ? 2 : 3;
    double *b = malloc(3 * (n ? n : 1) * sizeof *b);
    if (!b)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory for a VTK file of %zu particles",
                         path, n);
    if (n > (size_t)INT32_MAX / 2) {
        free(b);
        return mote_fail(err, MOTE_EINVAL, "%s: %zu particles are more than a legacy VTK file "
                         "holds (%d)", path, n, INT32_MAX / 2);
    }
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc) {
        free(b);
        return rc;
    }
    FILE *f = af.f;
    /* the title: one line of at most 255 characters */
    char title[256];
    int len = snprintf(title, sizeof title, "mote %s t=%.10g step=%lld", fr->model, fr->time,
                       (long long)fr->step);
    for (int k = 0; k < fr->nspecies_names && len > 0 && len < (int)sizeof title; k++)
        len += snprintf(title + len, sizeof title - (size_t)len, "%s %d=%s",
                        k ? "," : " species:", k, fr->species_names[k]);
    for (char *q = title; *q; q++)
        if (*q == '\n' || *q == '\r')
            *q = ' ';
    fprintf(f, "# vtk DataFile Version 3.0\n%s\nBINARY\nDATASET POLYDATA\n", title);
    fprintf(f, "FIELD FieldData 2\nTIME 1 1 double\n");
    mote_vtk_put(f, &fr->time, 1, 1, 0, 17);
    const double step = (double)fr->step;
    fprintf(f, "STEP 1 1 double\n");
    mote_vtk_put(f, &step, 1, 1, 0, 17);
    fprintf(f, "POINTS %zu double\n", n);
    put_rows(f, fr->pos, n, dim, b);
    fprintf(f, "VERTICES %zu %zu\n", n, 2 * n);
    for (size_t i = 0; i < n; i++) {
        b[2 * i] = 1;
        b[2 * i + 1] = (double)i;
    }
    mote_vtk_put(f, b, 2 * n, 1, 1, 17);
    fprintf(f, "POINT_DATA %zu\n", n);
    if (fr->vel) {
        fprintf(f, "VECTORS velocity double\n");
        put_rows(f, fr->vel, n, dim, b);
    }
    if (fr->species) {
        fprintf(f, "SCALARS species int 1\nLOOKUP_TABLE default\n");
        for (size_t i = 0; i < n; i++)
            b[i] = fr->species[i];
        mote_vtk_put(f, b, n, 1, 1, 17);
    }
    if (fr->id) {
        fprintf(f, "SCALARS id double 1\nLOOKUP_TABLE default\n");
        for (size_t i = 0; i < n; i++)
            b[i] = (double)fr->id[i];
        mote_vtk_put(f, b, n, 1, 0, 17);
    }
    char name[64];
    for (int s = 0; s < fr->nscalar && s < MOTE_H5MD_SCALARS; s++) {
        vtk_name(name, sizeof name, fr->scalar[s].name);
        fprintf(f, "SCALARS %s double 1\nLOOKUP_TABLE default\n", name);
        mote_vtk_put(f, fr->scalar[s].v, n, 1, 0, 17);
    }
    for (int s = 0; s < fr->nvector && s < MOTE_H5MD_VECTORS; s++) {
        vtk_name(name, sizeof name, fr->vector[s].name);
        fprintf(f, "VECTORS %s double\n", name);
        put_rows(f, fr->vector[s].v, n, dim, b);
    }
    free(b);
    if (ferror(f)) {
        mote_afile_abort(&af);
        return mote_fail(err, MOTE_EIO, "%s: could not write the VTK file", path);
    }
    return mote_afile_commit(&af, err);
}
