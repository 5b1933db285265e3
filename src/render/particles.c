/* particles.c: a picture of particles in a walled frame drawn to scale: solid rectangles (plates,
 * obstacles) in grey, each particle a filled disc of its true radius (at least one pixel across)
 * coloured by a value on the viridis map, linear or logarithmic, with a labelled colour bar, or
 * by class with a legend; a title, axes, and a line of text under the picture. */
#include "mote/render.h"

#include "draw.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* The palette of classes (colour-blind safe, as the disks pictures). */
static const double CLASS_RGB[8][3] = {{0.00, 0.45, 0.70}, {0.90, 0.62, 0.00}, {0.00, 0.62, 0.45},
                                       {0.80, 0.40, 0.00}, {0.35, 0.70, 0.90}, {0.80, 0.60, 0.70},
                                       {0.94, 0.89, 0.26}, {0.30, 0.30, 0.30}};

/* Colour-bar ticks between lo and hi (display units, lo < hi): 1-2-5 (or 1-2-3-5, or every digit)
 * per decade on a log bar, else (or when those give fewer than 3) evenly spaced nice values; at
 * most 12. */
static int bar_ticks(double lo, double hi, int log_scale, double *t)
{
    int n = 0;
    if (log_scale && lo > 0) {
        static const int sets[4][9] = {{1, 0}, {1, 2, 5, 0}, {1, 2, 3, 5, 0}, {1, 2, 3, 4, 5, 6, 7, 8, 9}};
        for (int q = 0; q < 4; q++) {
            n = 0;
            for (int e = (int)floor(log10(lo)) - 1; e <= (int)ceil(log10(hi)) && n < 12; e++)
                for (int k = 0; k < 9 && sets[q][k] && n < 12; k++) {
                    const double v = sets[q][k] * pow(10.0, e);
                    if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9))
                        t[n++] = v;
                }
            if (n >= 3)
                return n;
        }
        /* a range narrower than the 1-9 steps: evenly spaced ticks, as a linear bar */
    }
    const double raw = (hi - lo) / 5, mag = pow(10.0, floor(log10(raw)));
    const double step = raw / mag < 1.5 ? mag : raw / mag < 3.5 ? 2 * mag : raw / mag < 7.5 ? 5 * mag : 10 * mag;
    for (double v = ceil(lo / step) * step; v <= hi * (1 + 1e-12) && n < 12; v += step)
        t[n++] = fabs(v) < 1e-12 * step ? 0 : v;
    return n;
}

/* The key right of the frame: the legend of the classes (ncat > 0), or the colour bar over
 * [vlo, vhi] (clo, chi: the same in display units) with its ticks and label. */
static void draw_key(cairo_t *cr, const mote_rnd_style *stp, const mote_rnd_layout *layp,
                     const mote_particles_opts *o, double bar_gap, double bar_w, double vlo,
                     double vhi, double clo, double chi)
{
    const mote_rnd_style st = *stp;
    const mote_rnd_layout lay = *layp;
    const double bx = lay.left + lay.width + bar_gap, btop = lay.top, bh = lay.height;
    mote_rnd_font(cr, st.tick_font, 0);
    if (o->ncat > 0) {
        const double row = 1.6 * st.tick_font;
        for (int c = 0; c < o->ncat && c < 8; c++) {
            const double *q = CLASS_RGB[c];
            cairo_set_source_rgb(cr, q[0], q[1], q[2]);
            cairo_arc(cr, bx + 0.5 * st.tick_font, btop + (c + 0.5) * row, 0.4 * st.tick_font, 0,
                      2 * MOTE_PI);
            cairo_fill(cr);
            cairo_set_source_rgb(cr, 0, 0, 0);
            mote_rnd_text(cr, bx + 1.5 * st.tick_font, btop + (c + 0.5) * row,
                          o->cat_names && o->cat_names[c] ? o->cat_names[c] : "?", 0,
                          MOTE_RND_MIDDLE);
        }
    } else {
        const double bar_h = fmin(bh, fmax(0.5 * bh, 200 * st.scale));
        const double top = btop + (o->bar_label ? 2 * st.tick_font : 0);
        const double hh = fmin(bar_h, btop + bh - top);
        for (int k = 0; k < (int)hh; k++) {
            double rgb[3];
            mote_viridis(1 - (k + 0.5) / hh, rgb);
            cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
            cairo_rectangle(cr, bx, top + k, bar_w, 1.5);
            cairo_fill(cr);
        }
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_set_line_width(cr, fmax(1, st.scale));
        cairo_rectangle(cr, bx, top, bar_w, hh);
        cairo_stroke(cr);
        const double unit = o->bar_unit > 0 ? o->bar_unit : 1;
        double t[12];
        const int nt = bar_ticks(vlo / unit, vhi / unit, o->log_scale, t);
        for (int k = 0; k < nt; k++) {
            const double cv = o->log_scale ? log(t[k] * unit) : t[k] * unit;
            const double yy = top + hh * (1 - (cv - clo) / (chi - clo));
            cairo_move_to(cr, bx + bar_w, yy);
            cairo_line_to(cr, bx + bar_w + st.ticklen, yy);
            cairo_stroke(cr);
            char lab[32];
            snprintf(lab, sizeof lab, "%g", t[k]);
            mote_rnd_text(cr, bx + bar_w + st.ticklen + st.gap, yy, lab, 0, MOTE_RND_MIDDLE);
        }
        if (o->bar_label)
            mote_rnd_text(cr, bx, btop, o->bar_label, 0, MOTE_RND_TOP);
    }
}

int mote_particles_png(const char *path, const mote_particles_opts *o, const double *x,
                       const double *y, const double *r, const double *value, size_t n,
                       const double *rects, size_t nrect, mote_err *err)
{
    if (!path || !*path)
        return mote_fail(err, MOTE_EINVAL, "particles: no output file name given");
    if (!(o->xmax > o->xmin) || !(o->ymax > o->ymin) || !isfinite(o->xmax - o->xmin) ||
        !isfinite(o->ymax - o->ymin))
        return mote_fail(err, MOTE_EINVAL, "%s: the frame [%g, %g] x [%g, %g] is empty", path,
                         o->xmin, o->xmax, o->ymin, o->ymax);
    const int L = o->height > 0 ? o->height : 900;
    int rc = mote_rnd_check_size(path, "height", L, err);
    if (rc)
        return rc;
    const double aspect = (o->ymax - o->ymin) / (o->xmax - o->xmin);
    if (!(aspect >= 1e-3 && aspect <= 1e4))
        return mote_fail(err, MOTE_EINVAL, "%s: the frame's height/width %g cannot be drawn", path,
                         aspect);
    mote_rnd_style st = mote_rnd_style_for(L / 900.0);
    mote_rnd_layout_in in = {o->title, o->xlabel, o->ylabel, o->xmin, o->xmax, o->ymin, o->ymax,
                             0, 0, aspect, L, 0};
    mote_rnd_layout lay;
    rc = mote_rnd_layout_compute(&in, &st, &lay, err);
    if (rc)
        return rc;
    /* room on the right for the colour bar or the legend, and below for the text line */
    const double bar_w = fmax(8, 18 * st.scale), bar_gap = 3 * st.gap;
    double extra = bar_gap + bar_w + st.gap + 7 * st.tick_font + st.pad;
    if (o->ncat > 0)
        extra = bar_gap + 12 * st.tick_font + st.pad;
    const double text_h = o->subtitle ? 1.8 * st.tick_font : 0;
    const int W = (int)ceil(lay.img_w + extra), H = (int)ceil(lay.img_h + text_h);
    cairo_surface_t *surface;
    cairo_t *cr;
    rc = mote_rnd_canvas(path, W, H, &surface, &cr, err);
    if (rc)
        return rc;
    /* the colour range, in display units (log10 on a log bar) */
    double vlo = o->vmin, vhi = o->vmax;
    if (!(vhi > vlo)) {
        vlo = INFINITY;
        vhi = -INFINITY;
        for (size_t i = 0; i < n && value; i++)
            if (isfinite(value[i]) && (!o->log_scale || value[i] > 0)) {
                vlo = fmin(vlo, value[i]);
                vhi = fmax(vhi, value[i]);
            }
        if (!(vhi > vlo)) {
            vlo = vlo < INFINITY ? vlo * 0.9 : 0;
            vhi = vhi > -INFINITY ? vlo / 0.9 * 1.1 : 1;
            if (!(vhi > vlo))
                vhi = vlo + 1;
        }
    }
    if (o->log_scale && !(vlo > 0))
        vlo = vhi * 1e-3;
    const double clo = o->log_scale ? log(vlo) : vlo, chi = o->log_scale ? log(vhi) : vhi;

    cairo_save(cr);
    cairo_rectangle(cr, lay.left, lay.top, lay.width, lay.height);
    cairo_clip(cr);
    cairo_set_source_rgb(cr, 0.97, 0.97, 0.97);
    cairo_paint(cr);
    /* solids */
    cairo_set_source_rgb(cr, 0.45, 0.45, 0.48);
    for (size_t k = 0; k < nrect; k++) {
        const double *q = rects + 4 * k;
        const double px0 = mote_rnd_px(&lay, q[0]), px1 = mote_rnd_px(&lay, q[2]);
        const double py0 = mote_rnd_py(&lay, q[1]), py1 = mote_rnd_py(&lay, q[3]);
        /* at least one pixel, so thin plates show */
        const double w = fmax(fabs(px1 - px0), 1), h = fmax(fabs(py1 - py0), 1);
        cairo_rectangle(cr, fmin(px0, px1), fmin(py0, py1), w, h);
    }
    cairo_fill(cr);
    if (o->nline) {
        cairo_set_source_rgba(cr, 0.25, 0.25, 0.3, 0.8);
        cairo_set_line_width(cr, 1);
        for (size_t k = 0; k < o->nline; k++) {
            const double *q = o->lines + 4 * k;
            cairo_move_to(cr, mote_rnd_px(&lay, q[0]), mote_rnd_py(&lay, q[1]));
            cairo_line_to(cr, mote_rnd_px(&lay, q[2]), mote_rnd_py(&lay, q[3]));
        }
        cairo_stroke(cr);
    }
    /* particles, in the order given (the caller sorts for depth) */
    cairo_set_tolerance(cr, 0.25);
    const double s = lay.width / (o->xmax - o->xmin);
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(x[i]) || !isfinite(y[i]) || !(r[i] > 0))
            continue;
        double rgb[3];
        if (o->ncat > 0) {
            const int c = value ? (int)value[i] : 0;
            const double *q = CLASS_RGB[((c % 8) + 8) % 8];
            rgb[0] = q[0];
            rgb[1] = q[1];
            rgb[2] = q[2];
        } else {
            const double v = value ? value[i] : vlo;
            const double cv = o->log_scale ? log(fmax(v, 1e-300)) : v;
            mote_viridis((cv - clo) / (chi - clo), rgb);
        }
        cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
        const double rp = fmax(r[i] * s, 0.5);
        cairo_new_path(cr);
        cairo_arc(cr, mote_rnd_px(&lay, x[i]), mote_rnd_py(&lay, y[i]), rp, 0, 2 * MOTE_PI);
        cairo_fill(cr);
    }
    cairo_restore(cr);
    mote_rnd_draw_axes(cr, &st, &lay, &in);

    draw_key(cr, &st, &lay, o, bar_gap, bar_w, vlo, vhi, clo, chi);
    if (o->subtitle) {
        cairo_set_source_rgb(cr, 0, 0, 0);
        char fitted[512];
        const char *sub = mote_rnd_fit_text(cr, o->subtitle, st.tick_font, 0, 0.6, W - 2 * st.pad,
                                            fitted, sizeof fitted);
        mote_rnd_text(cr, st.pad, lay.img_h, sub, 0, MOTE_RND_TOP);
    }
    return mote_rnd_finish(path, surface, cr, err);
}
