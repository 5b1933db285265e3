/* draw.h: private helpers shared by the two renderers in src/render/ (line plots in plot.c, disk
 * pictures in disks.c): sizes of text and strokes, "nice" axis ticks and their labels, the layout
 * of a framed plot area inside an image, drawing of the frame, ticks, labels and title, and the
 * atomic PNG write. Nothing outside src/render/ includes this header. */
#ifndef MOTE_RENDER_DRAW_H
#define MOTE_RENDER_DRAW_H

#include "mote/core.h"

#include <cairo.h>

/* Every size in pixels, all derived from one scale factor so large images keep their proportions. */
typedef struct {
    double scale;
    double tick_font, label_font, title_font, legend_font;
    double pad;     /* free space around the whole picture */
    double gap;     /* space between a text and what it labels */
    double ticklen; /* tick marks point out of the frame */
    double frame_width;
} mote_rnd_style;

/* Ticks at value(i) = i * mant * 10^exp10 for integer i in [i0, i1]. The step is kept as mantissa
 * and exponent so values like 0.3 come out as the nearest double to 0.3, not 3 * 0.1. */
typedef struct {
    int mant, exp10;
    double i0, i1;
    int sci;        /* labels in scientific notation (very large or very small values) */
    int sci_digits; /* mantissa digits after the point in scientific notation */
} mote_rnd_ticks;

/* What a layout is asked for. Either a fixed image size (img_w, img_h) or, when aspect > 0, a
 * frame of height/width = aspect whose picture's longer side is longer_side pixels. */
typedef struct {
    const char *title, *xlabel, *ylabel;
    double x0, x1, y0, y1; /* data values at the left, right, bottom and top edges of the frame */
    int img_w, img_h;
    double aspect;
    int longer_side;
    int xlog; /* x0, x1 are log10 of the values: ticks at 1, 2, 5 (or 1, 2, 3, 5) per decade */
} mote_rnd_layout_in;

typedef struct {
    int img_w, img_h;
    double left, top, width, height; /* the frame, in whole pixels */
    double x0, x1, y0, y1;
    mote_rnd_ticks xt, yt;
    int nxlist;        /* a log x axis: its ticks (log10 of the values) replace xt */
    double xlist[48];
} mote_rnd_layout;

/* Vertical anchors for text: the text box runs from the top of the digits to the bottom of the
 * descenders, so single lines of digits and of words line up the same way. */
enum { MOTE_RND_TOP, MOTE_RND_MIDDLE, MOTE_RND_BASELINE, MOTE_RND_BOTTOM };

mote_rnd_style mote_rnd_style_for(double scale);

/* Check an image dimension requested by a caller (positive, and small enough for cairo and RAM). */
int mote_rnd_check_size(const char *path, const char *what, int pixels, mote_err *err);

/* Replace a degenerate or non-finite range [*lo, *hi] by a usable one; pad both ends by
 * pad_frac of the span (a constant gets a margin of 5% of its magnitude, or 0.5 around zero).
 * Fails when the range reaches beyond 1e300, where tick steps would overflow. */
int mote_rnd_fix_range(const char *path, const char *axis, double *lo, double *hi,
                       double pad_frac, mote_err *err);

int mote_rnd_layout_compute(const mote_rnd_layout_in *in, const mote_rnd_style *st,
                            mote_rnd_layout *out, mote_err *err);

/* A white image of the given size; on failure nothing is left allocated. */
int mote_rnd_canvas(const char *path, int w, int h, cairo_surface_t **surface, cairo_t **cr,
                    mote_err *err);

void mote_rnd_font(cairo_t *cr, double px, int bold);
void mote_rnd_text(cairo_t *cr, double x, double y, const char *s, double halign, int valign);
/* Width of s and the height of a line of text (digit top to descender bottom) in the current font. */
double mote_rnd_text_width(cairo_t *cr, const char *s);
double mote_rnd_line_height(cairo_t *cr);
/* Select the font at px and shrink it (not below min_scale * px) until s fits in max_w pixels;
 * if it still does not fit, return a copy cut at a character boundary and ended with "..." in
 * buf, else s itself. */
const char *mote_rnd_fit_text(cairo_t *cr, const char *s, double px, int bold, double min_scale,
                              double max_w, char *buf, size_t cap);

double mote_rnd_tick_value(const mote_rnd_ticks *t, double i);
/* The label of a log axis tick at log10 value v: the value 10^v, to 3 digits. */
void mote_rnd_log_label(double v, char buf[64]);
void mote_rnd_tick_label(const mote_rnd_ticks *t, double v, char buf[64]);

/* Light grid lines at the inner ticks (plots only; over disks a grid is noise). */
void mote_rnd_draw_grid(cairo_t *cr, const mote_rnd_style *st, const mote_rnd_layout *lay);
/* Frame, ticks, tick labels, axis labels and title. */
void mote_rnd_draw_axes(cairo_t *cr, const mote_rnd_style *st, const mote_rnd_layout *lay,
                        const mote_rnd_layout_in *in);

/* Check the drawing succeeded, write the PNG atomically, and free the surface and context. */
int mote_rnd_finish(const char *path, cairo_surface_t *surface, cairo_t *cr, mote_err *err);

static inline double mote_rnd_px(const mote_rnd_layout *l, double x)
{
    return l->left + (x - l->x0) * (l->width / (l->x1 - l->x0));
}
static inline double mote_rnd_py(const mote_rnd_layout *l, double y)
{
    return l->top + (l->y1 - y) * (l->height / (l->y1 - l->y0));
}

#endif
