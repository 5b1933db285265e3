/* plot.c: mote_plot_png, line plots of data series for users (density profiles, energy against
 * time, ...): automatic ranges, a light grid, series in the Okabe-Ito colour-blind-safe palette
 * with distinct marker shapes, gaps where the data are NaN or infinite, an optional dashed
 * reference line, and a legend placed in the corner of the frame that hides the least data. */
#include "mote/render.h"

#include "draw.h"

#include <math.h>
#include <string.h>
#include <stdlib.h>

typedef struct {
    double r, g, b;
} rgb;

/* Okabe & Ito (2008), ordered so that the first few are the most distinct on white; yellow is
 * last because thin yellow lines are hard to see. */
static const rgb series_colours[8] = {
    {0.000, 0.447, 0.698}, /* blue */
    {0.835, 0.369, 0.000}, /* vermillion */
    {0.000, 0.620, 0.451}, /* bluish green */
    {0.800, 0.475, 0.655}, /* reddish purple */
    {0.902, 0.624, 0.000}, /* orange */
    {0.337, 0.706, 0.914}, /* sky blue */
    {0.000, 0.000, 0.000}, /* black */
    {0.941, 0.894, 0.259}, /* yellow */
};

/* Beyond eight series the colours repeat, so the line pattern changes with each round. */
static const double dash_patterns[3][2] = {{0, 0}, {8, 4}, {2, 3}};

static const double PI = 3.14159265358979323846;

/* Markers and line segments per cairo fill or stroke. Cairo's scan converter slows down sharply
 * on one path of many overlapping pieces (10^6 markers took 30 s in one path); in batches they
 * take about a second. With round caps and joins a line split into batches looks unbroken. */
enum { BATCH = 512 };

typedef struct {
    double line_width, marker_r;
} series_style;

static void set_series_source(cairo_t *cr, size_t k)
{
    rgb c = series_colours[k % 8];
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
}

static void set_series_dash(cairo_t *cr, size_t k, double scale)
{
    const double *p = dash_patterns[(k / 8) % 3];
    if (p[0] == 0) {
        cairo_set_dash(cr, NULL, 0, 0);
    } else {
        double d[2] = {p[0] * scale, p[1] * scale};
        cairo_set_dash(cr, d, 2, 0);
    }
}

/* Marker shapes of about equal area, one per series, so series differ by more than colour. */
static void marker_path(cairo_t *cr, size_t k, double x, double y, double r)
{
    double t = 1.4 * r; /* triangles: circumradius */
    double d = 1.25 * r; /* diamond: half diagonal */
    double s = 0.886 * r; /* square: half side */
    cairo_new_sub_path(cr);
    switch (k % 5) {
    case 0: cairo_arc(cr, x, y, r, 0, 2 * PI); break;
    case 1: cairo_rectangle(cr, x - s, y - s, 2 * s, 2 * s); break;
    case 2:
        cairo_move_to(cr, x, y - t);
        cairo_line_to(cr, x + 0.866 * t, y + 0.5 * t);
        cairo_line_to(cr, x - 0.866 * t, y + 0.5 * t);
        cairo_close_path(cr);
        break;
    case 3:
        cairo_move_to(cr, x, y - d);
        cairo_line_to(cr, x + d, y);
        cairo_line_to(cr, x, y + d);
        cairo_line_to(cr, x - d, y);
        cairo_close_path(cr);
        break;
    default:
        cairo_move_to(cr, x, y + t);
        cairo_line_to(cr, x + 0.866 * t, y - 0.5 * t);
        cairo_line_to(cr, x - 0.866 * t, y - 0.5 * t);
        cairo_close_path(cr);
        break;
    }
}

/* Where segment a-b crosses boundary k of box (0: x = xmin, 1: x = xmax, 2: y = ymin,
 * 3: y = ymax), t along a-b. The boundary coordinate is set exactly and the other one is
 * interpolated from the nearer end: with an outlier at 1e200 the crossing must come out right,
 * not as the difference of two huge numbers. */
static void crossing(const double box[4], const double a[2], const double b[2], const double qa[4],
                     const double qb[4], int k, double t, double out[2])
{
    static const int box_index[4] = {0, 2, 1, 3};
    int along = k / 2, other = 1 - along;
    double d = b[other] - a[other];
    out[along] = box[box_index[k]];
    if (t <= 0.5) out[other] = a[other] + t * d;
    else out[other] = b[other] - qb[k] / (qb[k] - qa[k]) * d;
}

/* Cut the segment a-b to box (xmin, ymin, xmax, ymax) (Liang-Barsky, with the crossing
 * parameters computed from each end's own distance to the boundary). Returns 0 when nothing of
 * it is inside; *cut_a / *cut_b say whether an end moved. Cairo works in 24.8 fixed point, so
 * points far outside the image must be cut here rather than handed to it. */
static int clip_segment(const double box[4], double *ax, double *ay, double *bx, double *by,
                        int *cut_a, int *cut_b)
{
    const double a[2] = {*ax, *ay}, b[2] = {*bx, *by};
    /* Signed distance inside each boundary; negative = outside. */
    const double qa[4] = {a[0] - box[0], box[2] - a[0], a[1] - box[1], box[3] - a[1]};
    const double qb[4] = {b[0] - box[0], box[2] - b[0], b[1] - box[1], box[3] - b[1]};
    double t0 = 0.0, t1 = 1.0;
    int k0 = -1, k1 = -1;
    for (int k = 0; k < 4; k++) {
        if (qa[k] < 0.0 && qb[k] < 0.0) return 0;
        if (qa[k] < 0.0) { /* entering through boundary k */
            double t = qa[k] / (qa[k] - qb[k]);
            if (t > t0) {
                t0 = t;
                k0 = k;
            }
        } else if (qb[k] < 0.0) { /* leaving through boundary k */
            double t = qa[k] / (qa[k] - qb[k]);
            if (t < t1) {
                t1 = t;
                k1 = k;
            }
        }
    }
    if (t0 > t1) return 0;
    double pa[2] = {a[0], a[1]}, pb[2] = {b[0], b[1]};
    if (k0 >= 0) crossing(box, a, b, qa, qb, k0, t0, pa);
    if (k1 >= 0) crossing(box, a, b, qa, qb, k1, t1, pb);
    /* When both ends are astronomically far the crossing can still be inexact; keep whatever
     * comes out within reach of cairo's fixed point (its own clip makes the visible edge). */
    double w = box[2] - box[0] + box[3] - box[1];
    for (int i = 0; i < 2; i++) {
        pa[i] = fmin(fmax(pa[i], box[i] - w), box[i + 2] + w);
        pb[i] = fmin(fmax(pb[i], box[i] - w), box[i + 2] + w);
    }
    *cut_a = k0 >= 0;
    *cut_b = k1 >= 0;
    *ax = pa[0];
    *ay = pa[1];
    *bx = pb[0];
    *by = pb[1];
    return 1;
}

/* Pixel position of point i, or 0 when the point is missing (NaN, infinite, off any scale). */
static int point_px(const mote_rnd_layout *lay, const mote_series *s, size_t i, double *px,
                    double *py)
{
    if (!isfinite(s->x[i]) || !isfinite(s->y[i])) return 0;
    *px = mote_rnd_px(lay, s->x[i]);
    *py = mote_rnd_py(lay, s->y[i]);
    return isfinite(*px) && isfinite(*py);
}

static void draw_series_line(cairo_t *cr, const mote_rnd_layout *lay, const double box[4],
                             const mote_series *s, const series_style *ss)
{
    double pax = 0, pay = 0;
    int have_prev = 0, pen_down = 0;
    size_t pending = 0;
    cairo_new_path(cr);
    for (size_t i = 0; i < s->n; i++) {
        double px, py;
        if (!point_px(lay, s, i, &px, &py)) {
            have_prev = pen_down = 0;
            continue;
        }
        if (have_prev) {
            double ax = pax, ay = pay, bx = px, by = py;
            int cut_a, cut_b;
            if (clip_segment(box, &ax, &ay, &bx, &by, &cut_a, &cut_b)) {
                if (!pen_down || cut_a) cairo_move_to(cr, ax, ay);
                cairo_line_to(cr, bx, by);
                pen_down = !cut_b;
                if (++pending >= BATCH) {
                    cairo_stroke(cr);
                    pending = 0;
                    if (pen_down) cairo_move_to(cr, bx, by);
                }
            } else {
                pen_down = 0;
            }
        }
        pax = px;
        pay = py;
        have_prev = 1;
    }
    cairo_stroke(cr);

    /* A point with no drawable neighbour would vanish from a line plot; show it as a dot. */
    cairo_set_dash(cr, NULL, 0, 0);
    pending = 0;
    for (size_t i = 0; i < s->n; i++) {
        double px, py, qx, qy;
        if (!point_px(lay, s, i, &px, &py)) continue;
        if (i > 0 && point_px(lay, s, i - 1, &qx, &qy)) continue;
        if (i + 1 < s->n && point_px(lay, s, i + 1, &qx, &qy)) continue;
        if (px < box[0] || px > box[2] || py < box[1] || py > box[3]) continue;
        cairo_new_sub_path(cr);
        cairo_arc(cr, px, py, ss->line_width * 1.2, 0, 2 * PI);
        if (++pending >= BATCH) {
            cairo_fill(cr);
            pending = 0;
        }
    }
    cairo_fill(cr);
}

static void draw_series_points(cairo_t *cr, const mote_rnd_layout *lay, const double box[4],
                               const mote_series *s, size_t k, const series_style *ss)
{
    size_t pending = 0;
    double last_x = -INFINITY, last_y = -INFINITY;
    cairo_new_path(cr);
    for (size_t i = 0; i < s->n; i++) {
        double px, py;
        if (!point_px(lay, s, i, &px, &py)) continue;
        if (px < box[0] || px > box[2] || py < box[1] || py > box[3]) continue;
        /* A marker within half a pixel of the previous one adds nothing visible (dense series). */
        if (fabs(px - last_x) < 0.5 && fabs(py - last_y) < 0.5) continue;
        last_x = px;
        last_y = py;
        marker_path(cr, k, px, py, ss->marker_r);
        if (++pending >= BATCH) {
            cairo_fill(cr);
            pending = 0;
        }
    }
    cairo_fill(cr);
}

/* Error bars: a vertical line from y - e to y + e with short caps. */
static void draw_series_errors(cairo_t *cr, const mote_rnd_layout *lay, const mote_series *s,
                               const double *yerr, const series_style *ss)
{
    if (!yerr)
        return;
    cairo_save(cr);
    cairo_set_dash(cr, NULL, 0, 0);
    cairo_set_line_width(cr, fmax(1.0, 0.6 * ss->line_width));
    for (size_t i = 0; i < s->n; i++) {
        double px, py;
        const double e = yerr[i];
        if (!point_px(lay, s, i, &px, &py) || !isfinite(e) || e <= 0)
            continue;
        const double y0 = mote_rnd_py(lay, s->y[i] - e), y1 = mote_rnd_py(lay, s->y[i] + e);
        const double cap = 1.2 * ss->marker_r;
        cairo_move_to(cr, px, y0);
        cairo_line_to(cr, px, y1);
        cairo_move_to(cr, px - cap, y0);
        cairo_line_to(cr, px + cap, y0);
        cairo_move_to(cr, px - cap, y1);
        cairo_line_to(cr, px + cap, y1);
    }
    cairo_stroke(cr);
    cairo_restore(cr);
}

/* A text on a pale backing, its top-left (halign 0) or top-right (1) corner at (x, y). */
static void backed_text(cairo_t *cr, double x, double y, const char *t, double halign)
{
    const double h = mote_rnd_line_height(cr), w = mote_rnd_text_width(cr, t);
    const double x0 = x - halign * w;
    cairo_rectangle(cr, x0 - 2, y - 1, w + 4, h + 2);
    cairo_set_source_rgba(cr, 1, 1, 1, 0.8);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    mote_rnd_text(cr, x0, y, t, 0.0, MOTE_RND_TOP);
}

static double legend_cover(const mote_rnd_layout *lay, const double rect[4],
                           const mote_series *series, size_t nseries, const mote_plot_opts *o);

/* Vertical marks (their x already on the axis's scale) and the note. Each mark's label goes
 * beside its line where it hides the least: right or left of the line, in one of three rows
 * at the top or at the bottom of the frame, counting the data points and segments under it
 * (legend_cover), the labels already placed and the note (each worth 100 points) and the
 * other marks' lines (3: a label's white backing lets a line show through); ties keep
 * the first of: its own top row (k mod 3, so neighbouring marks are staggered), right. */
static void draw_marks(cairo_t *cr, const mote_rnd_style *st, const mote_rnd_layout *lay,
                       const mote_plot_opts *o, const double *xm, int label_pass,
                       const mote_series *series, size_t nseries)
{
    cairo_save(cr);
    mote_rnd_font(cr, st->tick_font, 0);
    const double lh = mote_rnd_line_height(cr);
    double placed[8][4], note[4] = {0, 0, -1, -1};
    int nplaced = 0;
    if (label_pass && o->note && *o->note) {
        const double w = mote_rnd_text_width(cr, o->note);
        note[2] = lay->left + lay->width - st->gap;
        note[0] = note[2] - w;
        note[1] = lay->top + lay->height - st->gap - lh;
        note[3] = note[1] + lh;
    }
    for (int k = 0; k < o->nxmark && k < 8; k++) {
        if (!isfinite(xm[k]))
            continue;
        const double x = round(mote_rnd_px(lay, xm[k])) + 0.5;
        if (x < lay->left || x > lay->left + lay->width)
            continue;
        if (!label_pass) {
            const double dash[2] = {6.0 * st->scale, 4.0 * st->scale};
            cairo_set_dash(cr, dash, 2, 0);
            cairo_set_line_width(cr, fmax(1.0, round(1.5 * st->scale)));
            cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
            cairo_move_to(cr, x, lay->top);
            cairo_line_to(cr, x, lay->top + lay->height);
            cairo_stroke(cr);
        } else if (o->xmark_label && o->xmark_label[k] && *o->xmark_label[k]) {
            const double w = mote_rnd_text_width(cr, o->xmark_label[k]);
            double best = INFINITY, bx = x + 4, by = lay->top + st->gap, br[4] = {0, 0, 0, 0};
            int bright = 1;
            for (int c = 0; c < 12; c++) {
                const int bottom = c / 6, row = (k + c / 2) % 3, right = c % 2 == 0;
                const double tx = right ? x + 4 : x - 4,
                             ty = bottom ? lay->top + lay->height - st->gap - (row + 1) * (lh + 4)
                                         : lay->top + st->gap + row * (lh + 4);
                const double r[4] = {right ? tx - 2 : tx - w - 2, ty - 1, right ? tx + w + 2 : tx + 2,
                                     ty + lh + 1};
                if (r[0] < lay->left || r[2] > lay->left + lay->width)
                    continue;
                double cover = legend_cover(lay, r, series, nseries, o);
                for (int q = 0; q < nplaced; q++)
                    if (r[0] < placed[q][2] && placed[q][0] < r[2] && r[1] < placed[q][3] &&
                        placed[q][1] < r[3])
                        cover += 100;
                if (r[0] < note[2] && note[0] < r[2] && r[1] < note[3] && note[1] < r[3])
                    cover += 100;
                for (int q = 0; q < o->nxmark && q < 8; q++) { /* another mark's line */
                    const double xq = round(mote_rnd_px(lay, xm[q])) + 0.5;
                    if (q != k && isfinite(xq) && xq > r[0] && xq < r[2])
                        cover += 3;
                }
                if (cover < best) {
                    best = cover;
                    bx = tx;
                    by = ty;
                    bright = right;
                    memcpy(br, r, sizeof br);
                }
            }
            backed_text(cr, bx, by, o->xmark_label[k], bright ? 0.0 : 1.0);
            memcpy(placed[nplaced++], br, sizeof br);
        }
    }
    if (label_pass && o->note && *o->note)
        backed_text(cr, lay->left + lay->width - st->gap, lay->top + lay->height - st->gap - lh,
                    o->note, 1.0);
    cairo_restore(cr);
}

/* ---- legend -------------------------------------------------------------------------------- */

typedef struct {
    double w, h, row_h, sample_w, inner;
    size_t entries;
} legend_size;

/* Legend text, cut when longer than half the frame so the legend never hides the plot. */
static const char *legend_text(cairo_t *cr, const mote_rnd_style *st, const mote_rnd_layout *lay,
                               const char *label, char *buf, size_t cap)
{
    return mote_rnd_fit_text(cr, label, st->legend_font, 0, 1.0, 0.5 * lay->width, buf, cap);
}

static legend_size measure_legend(cairo_t *cr, const mote_rnd_style *st, const mote_rnd_layout *lay,
                                  const mote_series *series, size_t nseries, const series_style *ss)
{
    legend_size L = {0};
    double widest = 0.0;
    char buf[512];
    for (size_t k = 0; k < nseries; k++) {
        if (!series[k].label || !*series[k].label) continue;
        L.entries++;
        const char *text = legend_text(cr, st, lay, series[k].label, buf, sizeof buf);
        widest = fmax(widest, mote_rnd_text_width(cr, text));
    }
    mote_rnd_font(cr, st->legend_font, 0);
    L.inner = st->gap * 1.3;
    L.sample_w = 30.0 * st->scale;
    L.row_h = fmax(mote_rnd_line_height(cr) * 1.45, 2.8 * ss->marker_r);
    L.w = L.inner + L.sample_w + st->gap + widest + L.inner;
    L.h = 2 * L.inner + L.entries * L.row_h - (L.row_h - mote_rnd_line_height(cr));
    return L;
}

/* How much of the data a legend at rect (x0, y0, x1, y1) would hide: points inside it plus line
 * segments crossing it. */
static double legend_cover(const mote_rnd_layout *lay, const double rect[4],
                           const mote_series *series, size_t nseries, const mote_plot_opts *o)
{
    double cover = 0.0;
    for (size_t k = 0; k < nseries; k++) {
        const mote_series *s = &series[k];
        double pax = 0, pay = 0;
        int have_prev = 0;
        for (size_t i = 0; i < s->n; i++) {
            double px, py;
            if (!point_px(lay, s, i, &px, &py)) {
                have_prev = 0;
                continue;
            }
            if (s->style != 0 && px >= rect[0] && px <= rect[2] && py >= rect[1] && py <= rect[3])
                cover += 1.0;
            if (s->style != 1 && have_prev) {
                double ax = pax, ay = pay, bx = px, by = py;
                int ca, cb;
                if (clip_segment(rect, &ax, &ay, &bx, &by, &ca, &cb)) cover += 1.0;
            }
            pax = px;
            pay = py;
            have_prev = 1;
        }
    }
    if (o->has_yref && isfinite(o->yref)) {
        double y = mote_rnd_py(lay, o->yref);
        if (y >= rect[1] && y <= rect[3]) cover += 1.0;
    }
    return cover;
}

static void draw_legend(cairo_t *cr, const mote_rnd_style *st, const mote_rnd_layout *lay,
                        const mote_series *series, size_t nseries, const series_style *ss,
                        const mote_plot_opts *o)
{
    legend_size L = measure_legend(cr, st, lay, series, nseries, ss);
    if (L.entries == 0) return;
    double inset = 8.0 * st->scale;
    double right = lay->left + lay->width, bottom = lay->top + lay->height;
    /* Corners in order of preference: upper right, upper left, lower right, lower left. */
    double corners[4][2] = {
        {right - inset - L.w, lay->top + inset},
        {lay->left + inset, lay->top + inset},
        {right - inset - L.w, bottom - inset - L.h},
        {lay->left + inset, bottom - inset - L.h},
    };
    int best = 0;
    double best_cover = INFINITY;
    for (int c = 0; c < 4; c++) {
        double rect[4] = {corners[c][0], corners[c][1], corners[c][0] + L.w, corners[c][1] + L.h};
        double cover = legend_cover(lay, rect, series, nseries, o);
        if (cover < best_cover) {
            best_cover = cover;
            best = c;
        }
    }
    double x = round(corners[best][0]), y = round(corners[best][1]);

    cairo_save(cr);
    cairo_rectangle(cr, x + 0.5, y + 0.5, round(L.w), round(L.h));
    cairo_set_source_rgba(cr, 1, 1, 1, 0.88);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
    cairo_set_line_width(cr, 1.0);
    cairo_stroke(cr);

    mote_rnd_font(cr, st->legend_font, 0);
    double line_h = mote_rnd_line_height(cr);
    double row_y = y + L.inner + line_h / 2; /* centre of the first row */
    for (size_t k = 0; k < nseries; k++) {
        const mote_series *s = &series[k];
        if (!s->label || !*s->label) continue;
        double sx = x + L.inner;
        set_series_source(cr, k);
        if (s->style != 1) {
            cairo_set_line_width(cr, ss->line_width);
            set_series_dash(cr, k, st->scale);
            cairo_move_to(cr, sx, row_y);
            cairo_line_to(cr, sx + L.sample_w, row_y);
            cairo_stroke(cr);
            cairo_set_dash(cr, NULL, 0, 0);
        }
        if (s->style != 0) {
            marker_path(cr, k, sx + L.sample_w / 2, row_y, ss->marker_r);
            cairo_fill(cr);
        }
        cairo_set_source_rgb(cr, 0, 0, 0);
        char buf[512];
        const char *text = legend_text(cr, st, lay, s->label, buf, sizeof buf);
        mote_rnd_text(cr, sx + L.sample_w + st->gap, row_y, text, 0.0, MOTE_RND_MIDDLE);
        row_y += L.row_h;
    }
    cairo_restore(cr);
}

/* ---- reference line ------------------------------------------------------------------------ */

static void draw_yref(cairo_t *cr, const mote_rnd_style *st, const mote_rnd_layout *lay,
                      const mote_plot_opts *o, int label_pass)
{
    if (!o->has_yref || !isfinite(o->yref)) return;
    double y = mote_rnd_py(lay, o->yref);
    if (!(y >= lay->top && y <= lay->top + lay->height)) return;
    double lw = fmax(1.0, round(1.5 * st->scale));
    y = ((int)lw % 2) ? floor(y) + 0.5 : round(y);
    cairo_save(cr);
    cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
    if (!label_pass) {
        double dash[2] = {7.0 * st->scale, 4.0 * st->scale};
        cairo_set_dash(cr, dash, 2, 0);
        cairo_set_line_width(cr, lw);
        cairo_move_to(cr, lay->left, y);
        cairo_line_to(cr, lay->left + lay->width, y);
        cairo_stroke(cr);
    } else if (o->yref_label && *o->yref_label) {
        /* Above the line at the right end, or below it when the line hugs the top; on a pale
         * backing so data underneath do not make it unreadable. */
        mote_rnd_font(cr, st->tick_font, 0);
        double h = mote_rnd_line_height(cr), w = mote_rnd_text_width(cr, o->yref_label);
        double off = 3.0 * st->scale;
        double x1 = lay->left + lay->width - st->gap;
        double top = y - off - h;
        if (top < lay->top + 2) top = y + off;
        cairo_rectangle(cr, x1 - w - 2, top - 1, w + 4, h + 2);
        cairo_set_source_rgba(cr, 1, 1, 1, 0.75);
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
        mote_rnd_text(cr, x1, top, o->yref_label, 1.0, MOTE_RND_TOP);
    }
    cairo_restore(cr);
}

/* ---- ranges -------------------------------------------------------------------------------- */

/* Data range of the finite points; for y only the points within [xlo, xhi] count, so a zoomed x
 * range zooms y as well. Empty data leave lo = +inf, hi = -inf. */
static void data_range(const mote_series *series, size_t nseries, int want_y, double xlo,
                       double xhi, double *lo, double *hi)
{
    *lo = INFINITY;
    *hi = -INFINITY;
    for (size_t k = 0; k < nseries; k++) {
        const mote_series *s = &series[k];
        for (size_t i = 0; i < s->n; i++) {
            double x = s->x[i], y = s->y[i];
            if (!isfinite(x) || !isfinite(y)) continue;
            if (want_y && (x < xlo || x > xhi)) continue;
            double v = want_y ? y : x;
            if (v < *lo) *lo = v;
            if (v > *hi) *hi = v;
        }
    }
}

static int plot_png(const char *path, const mote_plot_opts *opts, const mote_series *series,
                    size_t nseries, mote_err *err, cairo_t *into);

/* A log x axis: the same plot of log10 x, its axis labelled with the values. */
/* The plot drawn into `into` (whose size is opts' width x height) when given, else written. */
static int plot_any(const char *path, const mote_plot_opts *opts, const mote_series *series,
                    size_t nseries, mote_err *err, cairo_t *into)
{
    if (!opts || !opts->xlog || !series)
        return plot_png(path, opts, series, nseries, err, into);
    size_t total = 0;
    for (size_t k = 0; k < nseries; k++)
        total += series[k].x ? series[k].n : 0;
    double *lx = malloc((total ? total : 1) * sizeof *lx);
    mote_series *ls = malloc((nseries ? nseries : 1) * sizeof *ls);
    if (!lx || !ls) {
        free(lx);
        free(ls);
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", path ? path : "plot");
    }
    size_t at = 0;
    for (size_t k = 0; k < nseries; k++) {
        ls[k] = series[k];
        if (!series[k].x)
            continue;
        ls[k].x = lx + at;
        for (size_t i = 0; i < series[k].n; i++)
            lx[at++] = series[k].x[i] > 0 ? log10(series[k].x[i]) : NAN;
    }
    mote_plot_opts o = *opts;
    if (o.xmin > 0 && o.xmax > 0) {
        o.xmin = log10(o.xmin);
        o.xmax = log10(o.xmax);
    }
    double xm[8];
    for (int k = 0; k < o.nxmark && k < 8; k++)
        xm[k] = o.xmark[k] > 0 ? log10(o.xmark[k]) : NAN;
    o.xmark = xm;
    const int rc = plot_png(path, &o, ls, nseries, err, into);
    free(lx);
    free(ls);
    return rc;
}

int mote_plot_png(const char *path, const mote_plot_opts *opts, const mote_series *series,
                  size_t nseries, mote_err *err)
{
    return plot_any(path, opts, series, nseries, err, NULL);
}

int mote_plot_panels_png(const char *path, const mote_plot_panel *panels, int npanels,
                         int width, int height, mote_err *err)
{
    if (!path || !*path) return mote_fail(err, MOTE_EINVAL, "plot: no output file name given");
    if (npanels < 1 || npanels > 8)
        return mote_fail(err, MOTE_EINVAL, "%s: 1 to 8 panels, not %d", path, npanels);
    const int W = width ? width : 400 * npanels, H = height ? height : 650;
    int rc = mote_rnd_check_size(path, "width", W, err);
    if (rc == MOTE_OK) rc = mote_rnd_check_size(path, "height", H, err);
    if (rc != MOTE_OK) return rc;
    cairo_surface_t *surface;
    cairo_t *cr;
    rc = mote_rnd_canvas(path, W, H, &surface, &cr, err);
    if (rc != MOTE_OK) return rc;
    for (int k = 0; k < npanels && rc == MOTE_OK; k++) {
        mote_plot_opts o = panels[k].opts;
        o.width = W / npanels;
        o.height = H;
        o.equal_axes = 0;
        cairo_save(cr);
        cairo_translate(cr, (double)k * (W / npanels), 0);
        rc = plot_any(path, &o, panels[k].series, panels[k].nseries, err, cr);
        cairo_restore(cr);
    }
    if (rc != MOTE_OK) {
        cairo_destroy(cr);
        cairo_surface_destroy(surface);
        return rc;
    }
    return mote_rnd_finish(path, surface, cr, err);
}

static int plot_png(const char *path, const mote_plot_opts *opts, const mote_series *series,
                    size_t nseries, mote_err *err, cairo_t *into)
{
    static const mote_plot_opts defaults = {0};
    if (!path || !*path) return mote_fail(err, MOTE_EINVAL, "plot: no output file name given");
    if (!opts) opts = &defaults;
    if (nseries == 0 || !series)
        return mote_fail(err, MOTE_EINVAL, "%s: a plot needs at least one data series", path);
    int any_points = 0;
    for (size_t k = 0; k < nseries; k++) {
        const mote_series *s = &series[k];
        if (s->n > 0 && (!s->x || !s->y))
            return mote_fail(err, MOTE_EINVAL, "%s: series %zu has %zu points but no %s array",
                             path, k, s->n, !s->x ? "x" : "y");
        if (s->style < 0 || s->style > 2)
            return mote_fail(err, MOTE_EINVAL,
                             "%s: series %zu has style %d; expected 0 (line), 1 (points) or 2 "
                             "(line with points)",
                             path, k, s->style);
        if (s->style != 0) any_points = 1;
    }
    int W = opts->width ? opts->width : 1000, H = opts->height ? opts->height : 650;
    int rc = mote_rnd_check_size(path, "width", W, err);
    if (rc == MOTE_OK) rc = mote_rnd_check_size(path, "height", H, err);
    if (rc != MOTE_OK) return rc;
    if (!isfinite(opts->xmin) || !isfinite(opts->xmax) || !isfinite(opts->ymin) ||
        !isfinite(opts->ymax))
        return mote_fail(err, MOTE_EINVAL, "%s: axis range [%g, %g] x [%g, %g] is not finite", path,
                         opts->xmin, opts->xmax, opts->ymin, opts->ymax);

    double x0 = opts->xmin, x1 = opts->xmax, y0 = opts->ymin, y1 = opts->ymax;
    if (x0 == x1) {
        data_range(series, nseries, 0, 0, 0, &x0, &x1);
        /* Markers at the very edge would be cut in half; lines may run edge to edge. */
        rc = mote_rnd_fix_range(path, "x", &x0, &x1, any_points ? 0.02 : 0.0, err);
    } else {
        rc = mote_rnd_fix_range(path, "x", &x0, &x1, 0.0, err);
    }
    if (rc != MOTE_OK) return rc;
    if (y0 == y1) {
        data_range(series, nseries, 1, fmin(x0, x1), fmax(x0, x1), &y0, &y1);
        if (opts->has_yref && isfinite(opts->yref)) {
            y0 = fmin(y0, opts->yref);
            y1 = fmax(y1, opts->yref);
        }
        rc = mote_rnd_fix_range(path, "y", &y0, &y1, 0.05, err);
    } else {
        rc = mote_rnd_fix_range(path, "y", &y0, &y1, 0.0, err);
    }
    if (rc != MOTE_OK) return rc;

    mote_rnd_style st = mote_rnd_style_for(fmin(W / 1000.0, H / 650.0));
    mote_rnd_layout_in in = {opts->title, opts->xlabel, opts->ylabel, x0, x1, y0, y1, W, H, 0.0, 0,
                             opts->xlog};
    if (opts->equal_axes) {
        in.aspect = fabs(y1 - y0) / fabs(x1 - x0);
        if (!(in.aspect >= 1e-3 && in.aspect <= 1e3))
            return mote_fail(err, MOTE_EINVAL,
                             "%s: equal axes need comparable ranges (height/width %g)", path,
                             in.aspect);
        in.longer_side = W; /* (width, default 1000) */
    }
    mote_rnd_layout lay;
    rc = mote_rnd_layout_compute(&in, &st, &lay, err);
    if (rc != MOTE_OK) return rc;
    cairo_surface_t *surface = NULL;
    cairo_t *cr = into;
    if (!into) {
        rc = mote_rnd_canvas(path, lay.img_w, lay.img_h, &surface, &cr, err);
        if (rc != MOTE_OK) return rc;
    }

    series_style ss = {fmax(1.0, 2.0 * st.scale), fmax(2.5, 3.5 * st.scale)};
    mote_rnd_draw_grid(cr, &st, &lay);

    cairo_save(cr);
    cairo_rectangle(cr, lay.left, lay.top, lay.width, lay.height);
    cairo_clip(cr);
    draw_yref(cr, &st, &lay, opts, 0);
    /* Segments are cut a little outside the frame so cairo's clip, not ours, makes the edge. */
    double margin = 20.0 * st.scale;
    double box[4] = {lay.left - margin, lay.top - margin, lay.left + lay.width + margin,
                     lay.top + lay.height + margin};
    if (opts->nxmark > 0 && opts->xmark)
        draw_marks(cr, &st, &lay, opts, opts->xmark, 0, series, nseries);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    cairo_set_line_width(cr, ss.line_width);
    for (size_t k = 0; k < nseries; k++) {
        const mote_series *s = &series[k];
        if (s->n == 0) continue;
        set_series_source(cr, k);
        draw_series_errors(cr, &lay, s, opts->yerr ? opts->yerr[k] : NULL, &ss);
        if (s->style != 1) {
            set_series_dash(cr, k, st.scale);
            draw_series_line(cr, &lay, box, s, &ss);
        }
        if (s->style != 0) draw_series_points(cr, &lay, box, s, k, &ss);
    }
    cairo_set_dash(cr, NULL, 0, 0);
    draw_yref(cr, &st, &lay, opts, 1);
    if ((opts->nxmark > 0 && opts->xmark) || opts->note)
        draw_marks(cr, &st, &lay, opts, opts->xmark, 1, series, nseries);
    cairo_restore(cr);

    mote_rnd_draw_axes(cr, &st, &lay, &in);
    draw_legend(cr, &st, &lay, series, nseries, &ss, opts);
    if (into)
        return MOTE_OK;
    if (into)
        return MOTE_OK;
    return mote_rnd_finish(path, surface, cr, err);
}
