/* sketch.c: pictures laid out in pixels by the caller (mote_sketch_png in render.h): discs,
 * arrows and a few lines of text on a plain background. */
#include "mote/render.h"

#include <math.h>

#include "draw.h"

static void set_rgb(cairo_t *cr, unsigned c)
{
    cairo_set_source_rgb(cr, ((c >> 16) & 255) / 255.0, ((c >> 8) & 255) / 255.0,
                         (c & 255) / 255.0);
}

int mote_sketch_png(const char *path, const mote_sketch *s, mote_err *err)
{
    int rc = mote_rnd_check_size(path, "width", s->width, err);
    if (!rc)
        rc = mote_rnd_check_size(path, "height", s->height, err);
    if (rc)
        return rc;
    cairo_surface_t *surface;
    cairo_t *cr;
    rc = mote_rnd_canvas(path, s->width, s->height, &surface, &cr, err);
    if (rc)
        return rc;
    set_rgb(cr, s->background);
    cairo_paint(cr);
    const double lw = fmax(1.0, s->width / 1024.0);
    cairo_set_line_width(cr, lw);
    for (size_t k = 0; k < s->narrow; k++) {
        const double *a = s->arrow + 4 * k;
        const double dx = a[2] - a[0], dy = a[3] - a[1], len = hypot(dx, dy);
        if (!(len >= 1) || !isfinite(len) || len > 1e6)
            continue;
        set_rgb(cr, s->arrow_rgb[2 * k]);
        cairo_move_to(cr, a[0], a[1]);
        cairo_line_to(cr, a[2], a[3]);
        cairo_stroke(cr);
        const double head = fmin(0.3 * len, 6 * lw), ux = dx / len, uy = dy / len;
        cairo_move_to(cr, a[2], a[3]);
        cairo_line_to(cr, a[2] - head * (ux - 0.5 * uy), a[3] - head * (uy + 0.5 * ux));
        cairo_line_to(cr, a[2] - head * (ux + 0.5 * uy), a[3] - head * (uy - 0.5 * ux));
        cairo_close_path(cr);
        cairo_fill(cr);
    }
    for (size_t k = 0; k < s->ndisc; k++) {
        const double *d = s->disc + 3 * k;
        if (!isfinite(d[0]) || !isfinite(d[1]) || !(d[2] > 0) || fabs(d[0]) > 1e6 ||
            fabs(d[1]) > 1e6 || d[2] > 1e6)
            continue;
        set_rgb(cr, s->disc_rgb[2 * k]);
        cairo_new_sub_path(cr);
        cairo_arc(cr, d[0], d[1], d[2], 0, 6.283185307179586);
        cairo_fill(cr);
    }
    const double px = 14 * s->width / 1024.0;
    mote_rnd_font(cr, px, 0);
    set_rgb(cr, ~s->background & 0xFFFFFFu);
    for (int t = 0; t < s->ntext; t++)
        mote_rnd_text(cr, px, px * (1.0 + 1.4 * t), s->text[t], 0, MOTE_RND_TOP);
    return mote_rnd_finish(path, surface, cr, err);
}
