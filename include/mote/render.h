/* render.h: PNG pictures for users: line plots of data series and scatter pictures of particles
 * (disks drawn to scale in a periodic or walled frame). Built on cairo; every PNG is written
 * atomically (temporary file, then rename). Independent of any model. */
#ifndef MOTE_RENDER_H
#define MOTE_RENDER_H

#include "mote/core.h"

#include <stddef.h>

typedef struct {
    const double *x, *y; /* n points */
    size_t n;
    const char *label;   /* legend text, or NULL */
    int style;           /* 0 = line, 1 = points, 2 = line with points */
} mote_series;

typedef struct {
    const char *title;
    const char *xlabel, *ylabel;
    int width, height;   /* pixels; 0 = defaults (1000 x 650) */
    /* Axis ranges; when lo == hi the range is taken from the data with a small margin. */
    double xmin, xmax, ymin, ymax;
    /* Optional horizontal reference line (e.g. the mean density); drawn when has_yref. */
    int has_yref;
    double yref;
    const char *yref_label;
} mote_plot_opts;

/* Line plot of one or more series with axes, ticks, labels, title and a legend. */
int mote_plot_png(const char *path, const mote_plot_opts *opts, const mote_series *series,
                  size_t nseries, mote_err *err);

typedef struct {
    const char *title;
    const char *xlabel, *ylabel;
    int width;                 /* pixels of the longer side; 0 = 900 */
    double xmin, xmax, ymin, ymax; /* the frame shown (e.g. 0..A by 0..A) */
    int periodic;              /* 1: disks crossing the frame are also drawn wrapped */
} mote_scatter_opts;

/* Disks of radius r[i] (in data units) at (x[i], y[i]), filled with colour class c[i]
 * (0 .. 7, a fixed distinct palette; c may be NULL). Equal aspect ratio, a frame, axes labels. */
int mote_disks_png(const char *path, const mote_scatter_opts *opts, const double *x,
                   const double *y, const double *r, const int *c, size_t n, mote_err *err);

#endif
