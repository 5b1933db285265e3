/* surface.c: mote_surface_png, a flat-shaded picture of triangles seen orthographically (a
 * spacecraft coloured by the current density on its surface): the triangles, already projected
 * to the screen plane, are filled back to front by depth with the viridis colour of their value
 * darkened by a shading factor, scaled equally on both axes to fit beside a colour bar labelled
 * with its minimum and maximum. The same inputs give the same image, bit for bit. */
#include "mote/render.h"

#include "draw.h"

#include <math.h>
#include <stdlib.h>

/* viridis (S. van der Walt and N. Smith, matplotlib's default colour map, CC0): eleven points of
 * it, interpolated linearly */
static const double VIRIDIS[11][3] = {
    {0.267, 0.005, 0.329}, {0.283, 0.141, 0.458}, {0.254, 0.265, 0.530}, {0.207, 0.372, 0.553},
    {0.164, 0.471, 0.558}, {0.128, 0.567, 0.551}, {0.135, 0.659, 0.518}, {0.267, 0.749, 0.441},
    {0.478, 0.821, 0.318}, {0.741, 0.873, 0.150}, {0.993, 0.906, 0.144}};

void mote_viridis(double t, double rgb[3])
{
    t = !(t > 0) ? 0 : t > 1 ? 1 : t;
    const double x = t * 10;
    int k = (int)x;
    if (k > 9)
        k = 9;
    const double f = x - k;
    for (int c = 0; c < 3; c++)
        rgb[c] = VIRIDIS[k][c] + f * (VIRIDIS[k + 1][c] - VIRIDIS[k][c]);
}

typedef struct {
    const double *depth;
} sort_ctx;

static int cmp_depth(const void *a, const void *b, void *ctx)
{
    const double *d = ((const sort_ctx *)ctx)->depth;
    const size_t i = *(const size_t *)a, j = *(const size_t *)b;
    if (d[i] != d[j])
        return d[i] < d[j] ? -1 : 1;
    return i < j ? -1 : i > j; /* a fixed order for equal depths: the same image every time */
}

/* insertion-free merge sort with a context (qsort_r is not in C11 or POSIX) */
static void sort_idx(size_t *a, size_t *tmp, size_t n, const sort_ctx *ctx)
{
    if (n < 2)
        return;
    const size_t h = n / 2;
    sort_idx(a, tmp, h, ctx);
    sort_idx(a + h, tmp, n - h, ctx);
    size_t i = 0, j = h, k = 0;
    while (i < h && j < n)
        tmp[k++] = cmp_depth(&a[j], &a[i], (void *)ctx) < 0 ? a[j++] : a[i++];
    while (i < h)
        tmp[k++] = a[i++];
    while (j < n)
        tmp[k++] = a[j++];
    for (k = 0; k < n; k++)
        a[k] = tmp[k];
}

int mote_surface_png(const char *path, const mote_surface_opts *o, const double *xy,
                     const double *depth, const double *value, const double *shade, size_t n,
                     mote_err *err)
{
    const int W = o->width > 0 ? o->width : 1024, H = o->height > 0 ? o->height : 768;
    int rc = mote_rnd_check_size(path, "width", W, err);
    if (!rc)
        rc = mote_rnd_check_size(path, "height", H, err);
    if (rc)
        return rc;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, vmin = o->vmin,
           vmax = o->vmax;
    int auto_range = !(vmax > vmin);
    if (auto_range) {
        vmin = INFINITY;
        vmax = -INFINITY;
    }
    for (size_t i = 0; i < n; i++) {
        for (int v = 0; v < 3; v++)
            for (int a = 0; a < 2; a++) {
                lo[a] = fmin(lo[a], xy[6 * i + 2 * v + a]);
                hi[a] = fmax(hi[a], xy[6 * i + 2 * v + a]);
            }
        const double val = o->log_scale ? log10(fabs(value[i])) : value[i];
        if (auto_range && isfinite(val)) {
            vmin = fmin(vmin, val);
            vmax = fmax(vmax, val);
        }
    }
    if (!(vmax >= vmin)) {
        vmin = 0;
        vmax = 1;
    }
    if (vmax == vmin) {
        vmin -= 0.5 * fmax(fabs(vmin), 1e-300);
        vmax += 0.5 * fmax(fabs(vmax), 1e-300);
    }
    cairo_surface_t *surface;
    cairo_t *cr;
    rc = mote_rnd_canvas(path, W, H, &surface, &cr, err);
    if (rc)
        return rc;
    const mote_rnd_style st = mote_rnd_style_for(fmin(W / 1024.0, H / 768.0) * 1.2);
    /* the title on top, the colour bar on the right, the body in the rest */
    const double top = st.pad + (o->title ? 1.6 * st.title_font : 0);
    const double bar_w = 0.025 * W, bar_x = W - st.pad - 7 * st.tick_font - bar_w;
    const double area_w = bar_x - 2 * st.pad, area_h = H - top - st.pad;
    double s = 1, cx = 0, cy = 0;
    if (n && hi[0] > lo[0] && hi[1] > lo[1]) {
        s = 0.95 * fmin(area_w / (hi[0] - lo[0]), area_h / (hi[1] - lo[1]));
        cx = 0.5 * (lo[0] + hi[0]);
        cy = 0.5 * (lo[1] + hi[1]);
    }
    const double ox = st.pad + 0.5 * area_w, oy = top + 0.5 * area_h;
    size_t *idx = malloc((n ? n : 1) * sizeof *idx), *tmp = malloc((n ? n : 1) * sizeof *tmp);
    if (!idx || !tmp) {
        free(idx);
        free(tmp);
        cairo_destroy(cr);
        cairo_surface_destroy(surface);
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory for %zu triangles", path, n);
    }
    for (size_t i = 0; i < n; i++)
        idx[i] = i;
    sort_ctx ctx = {depth};
    sort_idx(idx, tmp, n, &ctx); /* far (small depth) first */
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_GRAY);
    for (size_t k = 0; k < n; k++) {
        const size_t i = idx[k];
        const double val = o->log_scale ? log10(fabs(value[i])) : value[i];
        double rgb[3];
        mote_viridis(isfinite(val) ? (val - vmin) / (vmax - vmin) : 0, rgb);
        const double sh = shade ? shade[i] : 1;
        cairo_set_source_rgb(cr, rgb[0] * sh, rgb[1] * sh, rgb[2] * sh);
        cairo_new_path(cr);
        for (int v = 0; v < 3; v++) {
            const double px = ox + s * (xy[6 * i + 2 * v] - cx);
            const double py = oy - s * (xy[6 * i + 2 * v + 1] - cy);
            if (v == 0)
                cairo_move_to(cr, px, py);
            else
                cairo_line_to(cr, px, py);
        }
        cairo_close_path(cr);
        cairo_fill_preserve(cr);
        cairo_set_line_width(cr, 0.5); /* closes the hairline gaps between neighbours */
        cairo_stroke(cr);
    }
    free(idx);
    free(tmp);
    /* the colour bar: bottom vmin, top vmax */
    const double bar_top = top + 0.1 * area_h, bar_h = 0.8 * area_h;
    for (int y = 0; y < (int)bar_h; y++) {
        double rgb[3];
        mote_viridis(1 - (y + 0.5) / bar_h, rgb);
        cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
        cairo_rectangle(cr, bar_x, bar_top + y, bar_w, 1.5);
        cairo_fill(cr);
    }
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, st.frame_width);
    cairo_rectangle(cr, bar_x, bar_top, bar_w, bar_h);
    cairo_stroke(cr);
    char lab[64];
    mote_rnd_font(cr, st.tick_font, 0);
    snprintf(lab, sizeof lab, o->log_scale ? "1e%.3g" : "%.3g", vmax);
    mote_rnd_text(cr, bar_x + bar_w + st.gap, bar_top, lab, 0, MOTE_RND_MIDDLE);
    snprintf(lab, sizeof lab, o->log_scale ? "1e%.3g" : "%.3g", vmin);
    mote_rnd_text(cr, bar_x + bar_w + st.gap, bar_top + bar_h, lab, 0, MOTE_RND_MIDDLE);
    if (o->bar_label) {
        mote_rnd_font(cr, st.tick_font, 0);
        mote_rnd_text(cr, bar_x + 0.5 * bar_w, bar_top - st.gap - st.tick_font, o->bar_label, 0.5,
                      MOTE_RND_BOTTOM);
    }
    if (o->title) {
        char buf[256];
        const char *t = mote_rnd_fit_text(cr, o->title, st.title_font, 1, 0.6, W - 2 * st.pad,
                                          buf, sizeof buf);
        mote_rnd_text(cr, 0.5 * W, st.pad, t, 0.5, MOTE_RND_TOP);
    }
    return mote_rnd_finish(path, surface, cr, err);
}
