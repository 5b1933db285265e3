/* render.h: PNG pictures for users: line plots of data series and scatter pictures of particles
 * (disks drawn to scale in a periodic or walled frame). Built on cairo; every PNG is written
 * atomically (temporary file, then rename). Independent of any model. */
#ifndef MOTE_RENDER_H
#define MOTE_RENDER_H

#include "mote/core.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef struct {
    const double *x, *y; /* n points; a point with a NaN or infinite coordinate is skipped and
                          * breaks the line there */
    size_t n;
    const char *label;   /* legend text, or NULL (or "") to leave the series out of the legend */
    int style;           /* 0 = line, 1 = points, 2 = line with points */
} mote_series;

typedef struct {
    const char *title;
    const char *xlabel, *ylabel;
    int width, height;   /* pixels, 16 .. 16384; 0 = defaults (1000 x 650) */
    /* Axis ranges; when lo == hi the range is taken from the data with a small margin (the
     * automatic y range covers the points inside the x range, and the reference line).
     * xmin > xmax draws a reversed axis. Values beyond 1e300 cannot be drawn. */
    double xmin, xmax, ymin, ymax;
    /* Optional horizontal reference line (e.g. the mean density), dashed, with its label at the
     * right end; drawn when has_yref and yref is finite. */
    int has_yref;
    double yref;
    const char *yref_label;
    /* 1: one data unit is as long on both axes (orbits, paths); the frame takes the shape of
     * the ranges and the picture's longer side is `width` pixels */
    int equal_axes;
    /* 1: a logarithmic x axis (points with x <= 0 are skipped; ticks 1-2-5 per decade) */
    int xlog;
    /* Vertical dashed marks at xmark[k] with their labels at the top (up to 8), e.g. a cut size */
    int nxmark;
    const double *xmark;
    const char *const *xmark_label;
    /* A short text in the frame's bottom-right corner (e.g. "kappa = 0.83"), or NULL */
    const char *note;
    /* Symmetric error bars: yerr[k] for series k (n values; NaN: none at a point), or NULL for
     * none at all; a NULL entry: none on that series */
    const double *const *yerr;
} mote_plot_opts;

/* Line plot of one or more series with axes, ticks, labels, title and a legend (placed in the
 * corner of the frame that hides the least data). opts may be NULL for all defaults; any text may
 * be NULL. Empty series, single points and constant data are fine. Fails with MOTE_EINVAL for
 * zero series, n > 0 without x or y, an unknown style, a bad size or range, or text that is not
 * UTF-8; with MOTE_EIO when the file cannot be written. The PNG is written atomically. */
int mote_plot_png(const char *path, const mote_plot_opts *opts, const mote_series *series,
                  size_t nseries, mote_err *err);

/* One panel of a picture of several plots side by side. */
typedef struct {
    mote_plot_opts opts;       /* width, height and equal_axes are set by the picture */
    const mote_series *series;
    size_t nseries;
} mote_plot_panel;

/* npanels (1 .. 8) plots side by side in one PNG of width x height pixels (0: 400 per panel x
 * 650); each as mote_plot_png draws it. Written atomically. */
int mote_plot_panels_png(const char *path, const mote_plot_panel *panels, int npanels,
                         int width, int height, mote_err *err);

typedef struct {
    const char *title;
    const char *xlabel, *ylabel;
    int width;                 /* pixels of the picture's longer side, 16 .. 16384; 0 = 900 */
    /* The frame shown (e.g. 0..A by 0..A); on an axis with lo == hi it is taken from the disks'
     * extent. Disks are clipped to the frame. */
    double xmin, xmax, ymin, ymax;
    int periodic;              /* 1: positions are wrapped into the frame, and disks crossing
                                * its edges are also drawn at their wrapped positions */
} mote_scatter_opts;

/* Disks of radius r[i] (in data units) at (x[i], y[i]), filled with colour class c[i]
 * (0 .. 7, a fixed colour-blind-safe palette, taken modulo 8; c may be NULL for class 0), with a
 * thin darker outline when they are large enough to show one. Disks are drawn class by class,
 * so where disks overlap a higher class lies on top. Disks with a non-finite coordinate or a
 * radius <= 0 are skipped. Equal aspect ratio, a frame, axes labels. opts may be NULL. Errors
 * as for mote_plot_png; the PNG is written atomically. */
int mote_disks_png(const char *path, const mote_scatter_opts *opts, const double *x,
                   const double *y, const double *r, const int *c, size_t n, mote_err *err);
/* The colour of class k (modulo 8) of that palette as "#rrggbb", for the live views, so that a
 * class has the same colour in the browser as in the PNGs. */
const char *mote_class_colour_hex(int k);

typedef struct {
    const char *title;
    const char *bar_label;     /* above the colour bar, e.g. "J_net (A/m^2)" */
    int width, height;         /* pixels (0: 1024 x 768) */
    double vmin, vmax;         /* the colour bar's range (vmax <= vmin: that of the values) */
    int log_scale;             /* colour by log10 |value| */
} mote_surface_opts;

/* A surface of n triangles seen orthographically: xy holds each triangle's three projected
 * vertices (x, y, 6 numbers a triangle, in any length unit: the picture scales them equally),
 * depth its distance toward the viewer (larger: nearer), value what colours it (viridis), shade
 * a factor in [0, 1] for its brightness (NULL: 1). Drawn back to front, with a colour bar and
 * title; written atomically. */
int mote_surface_png(const char *path, const mote_surface_opts *o, const double *xy,
                     const double *depth, const double *value, const double *shade, size_t n,
                     mote_err *err);
typedef struct {
    const char *title, *xlabel, *ylabel;
    const char *subtitle;      /* a line of text under the picture (time, counts), or NULL */
    int height;                /* pixels of the frame's picture's longer side (0: 900) */
    double xmin, xmax, ymin, ymax; /* the frame (data units), drawn to scale */
    /* colour by value on viridis over [vmin, vmax] (vmax <= vmin: the values' range), log_scale
     * for a logarithmic map; the bar's labels are value / bar_unit (0: 1) under bar_label */
    double vmin, vmax;
    int log_scale;
    double bar_unit;
    const char *bar_label;
    /* or, when ncat > 0, value is a class 0 .. ncat - 1 named in a legend (up to 8) */
    int ncat;
    const char *const *cat_names;
    /* thin dark lines over the solids, under the particles (walls of triangles seen side on):
     * nline segments of 4 numbers (x0 y0 x1 y1), or none */
    const double *lines;
    size_t nline;
} mote_particles_opts;

/* Particles in a walled frame, to scale: discs of radius r[i] at (x[i], y[i]) (at least one
 * pixel across) coloured by value[i], drawn in the order given (sort them for depth), over the
 * solid rectangles rects (x0 y0 x1 y1 each, grey); a colour bar or a legend, the title and axes,
 * and the subtitle under it all. Written atomically. */
int mote_particles_png(const char *path, const mote_particles_opts *o, const double *x,
                       const double *y, const double *r, const double *value, size_t n,
                       const double *rects, size_t nrect, mote_err *err);

/* A picture in pixel coordinates (y down), for pictures laid out by a model's own rules (the
 * Galactica frames): a background, filled discs (x, y, radius each) and arrows (x0, y0, x1, y1
 * each, the head at the second point), colours as 0xRRGGBB, and lines of text at the top left. */
typedef struct {
    int width, height;
    unsigned background;
    const double *disc;
    const unsigned *disc_rgb;  /* a colour per disc, read at a stride of 2 (as arrow_rgb) */
    size_t ndisc;
    const double *arrow;
    const unsigned *arrow_rgb; /* read at a stride of 2: one array can interleave both */
    size_t narrow;
    const char *const *text;
    int ntext;
} mote_sketch;

/* Draw s and write it atomically. Discs and arrows outside the picture are clipped. */
int mote_sketch_png(const char *path, const mote_sketch *s, mote_err *err);

/* Run ffmpeg on PREFIX_%06d.png (mote_series_path's names, the frames from 0 on) into out at fps frames per second (the
 * container from out's extension; .gif without yuv420p); written through a temporary file.
 * When ffmpeg is not on PATH, print the command to `diag` and return MOTE_OK with *ran = 0. */
int mote_movie(const char *prefix, int64_t fps, const char *out, FILE *diag, int *ran,
               mote_err *err);

/* The viridis colour of t in [0, 1] (clamped). */
void mote_viridis(double t, double rgb[3]);

#endif
