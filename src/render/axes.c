/* axes.c: the parts of a picture that line plots and disk pictures share: sizes derived from one
 * scale factor, ranges made drawable, "nice" ticks (1, 2 or 5 times a power of ten) spaced so
 * their labels never overlap, the layout that sizes the margins from the text they must hold, the
 * frame with its ticks, labels and title, and the atomic write of the finished PNG through
 * mote_afile. All state lives in the cairo context and the structs passed in. */
#include "draw.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Cairo's image surfaces are limited to 32767 pixels a side; far below that an image already
 * takes a gigabyte, so refuse sizes that can only be a mistake. */
enum { MIN_PIXELS = 16, MAX_PIXELS = 16384 };

/* Tick steps are powers of ten times 1, 2 or 5 and must stay normal, finite doubles. */
static const double MAX_MAGNITUDE = 1e300, MIN_SPAN = 1e-250;

mote_rnd_style mote_rnd_style_for(double scale)
{
    if (!(scale >= 0.5)) scale = 0.5;
    if (scale > 4.0) scale = 4.0;
    mote_rnd_style st;
    st.scale = scale;
    st.tick_font = fmax(9.0, 13.0 * scale);
    st.label_font = fmax(10.0, 15.0 * scale);
    st.title_font = fmax(11.0, 18.0 * scale);
    st.legend_font = fmax(9.0, 13.0 * scale);
    st.pad = fmax(8.0, 10.0 * scale);
    st.gap = 6.0 * scale;
    st.ticklen = 5.0 * scale;
    /* A whole number of pixels keeps the frame crisp. */
    st.frame_width = fmax(1.0, round(scale));
    return st;
}

int mote_rnd_check_size(const char *path, const char *what, int pixels, mote_err *err)
{
    if (pixels < MIN_PIXELS || pixels > MAX_PIXELS)
        return mote_fail(err, MOTE_EINVAL, "%s: image %s %d pixels is outside %d .. %d", path,
                         what, pixels, (int)MIN_PIXELS, (int)MAX_PIXELS);
    return MOTE_OK;
}

int mote_rnd_fix_range(const char *path, const char *axis, double *lo, double *hi,
                       double pad_frac, mote_err *err)
{
    double a = *lo, b = *hi;
    if (!isfinite(a) || !isfinite(b)) { /* no data at all: any range will do */
        a = 0.0;
        b = 1.0;
    }
    if (a == b) {
        double m = fabs(a) * 0.05;
        if (m == 0.0) m = 0.5;
        a -= m;
        b += m;
    } else if (pad_frac > 0.0) {
        double pad = pad_frac * (b - a);
        a -= pad;
        b += pad;
    }
    /* Ticks are i * step in doubles; a span below ~1e-10 of the magnitude cannot be resolved,
     * so widen it to a span the labels can still tell apart. */
    double mag = fmax(fabs(a), fabs(b));
    if (mag > MAX_MAGNITUDE)
        return mote_fail(err, MOTE_EINVAL,
                         "%s: %s range [%g, %g] reaches beyond %g and cannot be drawn", path, axis,
                         *lo, *hi, MAX_MAGNITUDE);
    if (fabs(b - a) < fmax(mag * 1e-10, MIN_SPAN)) {
        double c = a / 2 + b / 2, h = fmax(mag * 5e-10, MIN_SPAN);
        if (b < a) h = -h;
        a = c - h;
        b = c + h;
    }
    if (!isfinite(a) || !isfinite(b) || !isfinite(b - a))
        return mote_fail(err, MOTE_EINVAL, "%s: %s range [%g, %g] is too large to draw", path,
                         axis, *lo, *hi);
    *lo = a;
    *hi = b;
    return MOTE_OK;
}

/* ---- text ---------------------------------------------------------------------------------- */

void mote_rnd_font(cairo_t *cr, double px, int bold)
{
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                           bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, px);
}

/* Height of the digits: the top of a text box. The font's own ascent includes room for accents
 * and would leave labels visibly low. */
static double digit_height(cairo_t *cr)
{
    cairo_text_extents_t te;
    cairo_text_extents(cr, "0", &te);
    return -te.y_bearing;
}

static double descent(cairo_t *cr)
{
    cairo_font_extents_t fe;
    cairo_font_extents(cr, &fe);
    return fe.descent;
}

double mote_rnd_line_height(cairo_t *cr) { return digit_height(cr) + descent(cr); }

double mote_rnd_text_width(cairo_t *cr, const char *s)
{
    cairo_text_extents_t te;
    cairo_text_extents(cr, s, &te);
    return te.x_advance;
}

void mote_rnd_text(cairo_t *cr, double x, double y, const char *s, double halign, int valign)
{
    double top = digit_height(cr), desc = descent(cr), base = y;
    switch (valign) {
    case MOTE_RND_TOP: base = y + top; break;
    case MOTE_RND_MIDDLE: base = y + (top - desc) / 2; break;
    case MOTE_RND_BOTTOM: base = y - desc; break;
    default: break;
    }
    cairo_move_to(cr, x - halign * mote_rnd_text_width(cr, s), base);
    cairo_show_text(cr, s);
}

static int has_text(const char *s) { return s && *s; }

static int is_continuation(char c) { return ((unsigned char)c & 0xC0) == 0x80; }

const char *mote_rnd_fit_text(cairo_t *cr, const char *s, double px, int bold, double min_scale,
                              double max_w, char *buf, size_t cap)
{
    /* Never shrink below a readable size. */
    double smallest = fmin(px, fmax(min_scale * px, 9.0));
    double size = px;
    mote_rnd_font(cr, size, bold);
    /* Hinted advances do not scale exactly with the font size, so shrink in a few steps. */
    for (int k = 0; k < 8; k++) {
        double w = mote_rnd_text_width(cr, s);
        if (w <= max_w || size <= smallest) break;
        size = fmax(smallest, size * fmin(0.97, max_w / w));
        mote_rnd_font(cr, size, bold);
    }
    if (mote_rnd_text_width(cr, s) <= max_w || cap < 8) return s;
    /* Still too wide: keep the longest prefix that fits with "..." after it. Binary search over
     * character boundaries (bytes that are not UTF-8 continuation bytes); lo is always one. */
    size_t lo = 0, hi = strlen(s);
    if (hi > cap - 4) hi = cap - 4;
    while (lo < hi) {
        size_t n = lo + (hi - lo + 1) / 2;
        while (n > lo && is_continuation(s[n])) n--;
        if (n == lo) { /* no boundary in (lo, middle]: try the first one after it */
            n = lo + (hi - lo + 1) / 2;
            while (n < hi && is_continuation(s[n])) n++;
            if (is_continuation(s[n])) break;
        }
        memcpy(buf, s, n);
        memcpy(buf + n, "...", 4);
        if (mote_rnd_text_width(cr, buf) <= max_w) lo = n;
        else hi = n - 1;
    }
    memcpy(buf, s, lo);
    memcpy(buf + lo, "...", 4);
    return buf;
}

/* ---- ticks --------------------------------------------------------------------------------- */

static double pow10i(int e) { return pow(10.0, (double)e); }

double mote_rnd_tick_value(const mote_rnd_ticks *t, double i)
{
    /* Dividing by an exact power of ten gives the double nearest to the decimal value. */
    if (t->exp10 < 0) return i * t->mant / pow10i(-t->exp10);
    return i * t->mant * pow10i(t->exp10);
}

/* "1.5e+06" -> "1.5e6", "2.0e-05" -> "2.0e-5". */
static void tidy_exponent(char *buf)
{
    char *e = strchr(buf, 'e');
    if (!e) return;
    char *src = e + 1, *dst = e + 1;
    if (*src == '+') src++;
    else if (*src == '-') *dst++ = *src++;
    while (*src == '0' && src[1] != '\0') src++;
    memmove(dst, src, strlen(src) + 1);
}

void mote_rnd_tick_label(const mote_rnd_ticks *t, double v, char buf[64])
{
    /* ceil() just below zero gives tick index -0; its label must not read "-0". */
    if (v == 0.0) v = fabs(v);
    if (!t->sci) {
        snprintf(buf, 64, "%.*f", t->exp10 < 0 ? -t->exp10 : 0, v);
    } else if (v == 0.0) {
        snprintf(buf, 64, "0");
    } else {
        snprintf(buf, 64, "%.*e", t->sci_digits, v);
        tidy_exponent(buf);
    }
}

/* Decimal exponent of v read from its printed form, which is exact where log10 is not. */
static int decimal_exponent(double v)
{
    char probe[64];
    snprintf(probe, sizeof probe, "%.15e", v);
    const char *e = strchr(probe, 'e');
    return e ? (int)strtol(e + 1, NULL, 10) : 0;
}

static void set_sci(mote_rnd_ticks *t)
{
    double a = fabs(mote_rnd_tick_value(t, t->i0)), b = fabs(mote_rnd_tick_value(t, t->i1));
    double mag = fmax(a, b);
    t->sci = mag >= 1e6 || t->exp10 < -4;
    /* One mantissa precision for all labels: enough digits for the step at the largest value. */
    int digits = mag > 0 ? decimal_exponent(mag) - t->exp10 : 0;
    t->sci_digits = digits < 0 ? 0 : digits > 15 ? 15 : digits;
}

/* Pick the smallest nice step at least target_px apart on screen whose labels do not touch:
 * along x the widest label plus a gap must fit between ticks, along y one line of text. */
static mote_rnd_ticks choose_ticks(cairo_t *cr, const mote_rnd_style *st, double lo, double hi,
                                   double len_px, double target_px, int horizontal)
{
    double mn = fmin(lo, hi), mx = fmax(lo, hi), span = mx - mn;
    if (len_px < 1.0) len_px = 1.0;
    double raw = span / len_px * target_px;
    mote_rnd_ticks t;
    t.exp10 = (int)floor(log10(raw));
    double m = raw / pow10i(t.exp10);
    if (m <= 1.0 + 1e-9) t.mant = 1;
    else if (m <= 2.0 + 1e-9) t.mant = 2;
    else if (m <= 5.0 + 1e-9) t.mant = 5;
    else {
        t.mant = 1;
        t.exp10++;
    }

    mote_rnd_font(cr, st->tick_font, 0);
    double line_h = mote_rnd_line_height(cr);
    for (int attempt = 0; attempt < 60; attempt++) {
        double step = mote_rnd_tick_value(&t, 1.0);
        t.i0 = ceil(mn / step - 1e-9);
        t.i1 = floor(mx / step + 1e-9);
        set_sci(&t);
        double step_px = step / span * len_px, need = 0.0;
        if (horizontal) {
            double widest = 0.0;
            for (double i = t.i0; i <= t.i1; i++) {
                char buf[64];
                mote_rnd_tick_label(&t, mote_rnd_tick_value(&t, i), buf);
                widest = fmax(widest, mote_rnd_text_width(cr, buf));
            }
            need = widest + 1.5 * st->tick_font;
        } else {
            need = line_h + 0.8 * st->tick_font;
        }
        if (t.i1 < t.i0 || need <= step_px || t.exp10 >= 300) break;
        if (t.mant == 1) t.mant = 2;
        else if (t.mant == 2) t.mant = 5;
        else {
            t.mant = 1;
            t.exp10++;
        }
    }
    return t;
}

/* ---- layout -------------------------------------------------------------------------------- */

void mote_rnd_log_label(double v, char buf[64])
{
    snprintf(buf, 64, "%.3g", pow(10.0, v));
    tidy_exponent(buf);
}

/* Ticks of a log axis over log10 values [x0, x1]: decades, or 1-2-5, or 1-2-3-5, or every digit,
 * the first set giving at least 4 ticks (at most 48). */
static void log_ticks(double x0, double x1, double *list, int *n)
{
    static const int sets[4][10] = {{1, 0}, {1, 2, 5, 0}, {1, 2, 3, 5, 0}, {1, 2, 3, 4, 5, 6, 7, 8, 9, 0}};
    const double lo = fmin(x0, x1), hi = fmax(x0, x1);
    for (int q = 0; q < 4; q++) {
        *n = 0;
        for (int e = (int)floor(lo) - 1; e <= (int)ceil(hi) && *n < 48; e++)
            for (int k = 0; sets[q][k] && *n < 48; k++) {
                const double v = e + log10((double)sets[q][k]);
                if (v >= lo - 1e-12 && v <= hi + 1e-12)
                    list[(*n)++] = v;
            }
        if (*n >= 4 || q == 3)
            return;
    }
}

typedef struct {
    double l, r, t, b;
} margins;

/* Margins that hold the ticks and labels of a frame of size fw x fh. */
static margins needed_margins(cairo_t *cr, const mote_rnd_style *st, const mote_rnd_layout_in *in,
                              const mote_rnd_ticks *xt, const mote_rnd_ticks *yt, double fw)
{
    double lw = st->frame_width;
    mote_rnd_font(cr, st->tick_font, 0);
    double tick_h = mote_rnd_line_height(cr);
    double widest_y = 0.0;
    for (double i = yt->i0; i <= yt->i1; i++) {
        char buf[64];
        mote_rnd_tick_label(yt, mote_rnd_tick_value(yt, i), buf);
        widest_y = fmax(widest_y, mote_rnd_text_width(cr, buf));
    }
    /* How far the first and last x labels reach past the frame's left and right edges. */
    double over_l = 0.0, over_r = 0.0;
    if (in->xlog) {
        double list[48];
        int n;
        log_ticks(in->x0, in->x1, list, &n);
        for (int k = 0; k < n; k += (n > 1 ? n - 1 : 1)) {
            char buf[64];
            mote_rnd_log_label(list[k], buf);
            double half = mote_rnd_text_width(cr, buf) / 2;
            double at = (list[k] - in->x0) / (in->x1 - in->x0) * fw;
            over_l = fmax(over_l, half - at);
            over_r = fmax(over_r, at + half - fw);
        }
    } else if (xt->i0 <= xt->i1) {
        double ends[2] = {xt->i0, xt->i1};
        for (int k = 0; k < 2; k++) {
            char buf[64];
            double v = mote_rnd_tick_value(xt, ends[k]);
            mote_rnd_tick_label(xt, v, buf);
            double half = mote_rnd_text_width(cr, buf) / 2;
            double at = (v - in->x0) / (in->x1 - in->x0) * fw;
            over_l = fmax(over_l, half - at);
            over_r = fmax(over_r, at + half - fw);
        }
    }
    mote_rnd_font(cr, st->label_font, 0);
    double label_h = mote_rnd_line_height(cr);
    mote_rnd_font(cr, st->title_font, 1);
    double title_h = mote_rnd_line_height(cr);

    margins m;
    m.b = lw + st->ticklen + st->gap + tick_h + st->pad;
    if (has_text(in->xlabel)) m.b += 1.5 * st->gap + label_h;
    m.l = lw + st->ticklen + st->gap + widest_y + st->pad;
    if (has_text(in->ylabel)) m.l += 1.5 * st->gap + label_h;
    m.l = fmax(m.l, st->pad + over_l);
    m.r = st->pad + fmax(over_r, 0.0);
    m.t = st->pad + tick_h / 2; /* the top y label is centred on the frame's top edge */
    if (has_text(in->title)) m.t = fmax(m.t, st->pad + title_h + 2.0 * st->gap);
    m.l = ceil(m.l);
    m.r = ceil(m.r);
    m.t = ceil(m.t);
    m.b = ceil(m.b);
    return m;
}

int mote_rnd_layout_compute(const mote_rnd_layout_in *in, const mote_rnd_style *st,
                            mote_rnd_layout *out, mote_err *err)
{
    /* Text is measured on a scratch surface of the same kind as the real one, so the metrics
     * agree; the real surface's size is only known at the end for fixed-aspect pictures. */
    cairo_surface_t *scratch = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1);
    cairo_t *cr = cairo_create(scratch);
    if (cairo_status(cr) != CAIRO_STATUS_SUCCESS) {
        cairo_status_t s = cairo_status(cr);
        cairo_destroy(cr);
        cairo_surface_destroy(scratch);
        return mote_fail(err, MOTE_ENOMEM, "cannot measure text: %s", cairo_status_to_string(s));
    }

    margins m = {8 * st->pad, 3 * st->pad, 5 * st->pad, 7 * st->pad};
    double fw = 1, fh = 1;
    int W = in->img_w, H = in->img_h;
    mote_rnd_ticks xt, yt;
    /* Margins depend on the tick labels, which depend on the frame's size, which depends on the
     * margins. Iterate; after a few rounds let margins only grow, so the loop settles. */
    for (int iter = 0; iter < 8; iter++) {
        if (in->aspect > 0) {
            double L = in->longer_side;
            double aw = fmax(1.0, L - m.l - m.r), ah = fmax(1.0, L - m.t - m.b);
            if (aw * in->aspect <= ah) {
                fw = aw;
                fh = fmax(1.0, round(aw * in->aspect));
            } else {
                fh = ah;
                fw = fmax(1.0, round(ah / in->aspect));
            }
            W = (int)(m.l + fw + m.r);
            H = (int)(m.t + fh + m.b);
        } else {
            fw = fmax(1.0, W - m.l - m.r);
            fh = fmax(1.0, H - m.t - m.b);
        }
        xt = choose_ticks(cr, st, in->x0, in->x1, fw, 90.0 * st->scale, 1);
        yt = choose_ticks(cr, st, in->y0, in->y1, fh, 55.0 * st->scale, 0);
        margins need = needed_margins(cr, st, in, &xt, &yt, fw);
        if (iter >= 3) {
            need.l = fmax(need.l, m.l);
            need.r = fmax(need.r, m.r);
            need.t = fmax(need.t, m.t);
            need.b = fmax(need.b, m.b);
        }
        int same = need.l == m.l && need.r == m.r && need.t == m.t && need.b == m.b;
        m = need;
        if (same) break;
    }
    /* A tall, narrow picture would squeeze its title; widen it (up to the longer side) instead,
     * keeping the frame centred under the title. */
    if (in->aspect > 0 && has_text(in->title)) {
        mote_rnd_font(cr, st->title_font, 1);
        double need = ceil(mote_rnd_text_width(cr, in->title) + 2 * st->pad);
        double target = fmin(need, (double)in->longer_side);
        if (target > W) {
            double extra = target - W;
            m.l += floor(extra / 2);
            m.r += extra - floor(extra / 2);
            W = (int)target;
        }
    }
    cairo_destroy(cr);
    cairo_surface_destroy(scratch);

    out->img_w = W;
    out->img_h = H;
    out->left = m.l;
    out->top = m.t;
    out->width = fw;
    out->height = fh;
    out->x0 = in->x0;
    out->x1 = in->x1;
    out->y0 = in->y0;
    out->y1 = in->y1;
    out->xt = xt;
    out->yt = yt;
    out->nxlist = 0;
    if (in->xlog) {
        log_ticks(in->x0, in->x1, out->xlist, &out->nxlist);
        out->xt.i0 = 1; /* no linear ticks */
        out->xt.i1 = 0;
    }
    return MOTE_OK;
}

/* ---- drawing ------------------------------------------------------------------------------- */

int mote_rnd_canvas(const char *path, int w, int h, cairo_surface_t **surface, cairo_t **cr,
                    mote_err *err)
{
    /* RGB24: pictures are opaque, and PNGs without alpha are smaller. */
    cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
    cairo_t *c = cairo_create(s);
    if (cairo_status(c) != CAIRO_STATUS_SUCCESS) {
        cairo_status_t st = cairo_status(c);
        cairo_destroy(c);
        cairo_surface_destroy(s);
        return mote_fail(err, MOTE_ENOMEM, "%s: cannot create a %d x %d image: %s", path, w, h,
                         cairo_status_to_string(st));
    }
    cairo_set_source_rgb(c, 1, 1, 1);
    cairo_paint(c);
    *surface = s;
    *cr = c;
    return MOTE_OK;
}

/* Centre of the pixel column or row nearest to v, so 1-pixel lines are not smeared over two. */
static double crisp(double v, double width)
{
    return ((int)round(width) % 2) ? floor(v) + 0.5 : round(v);
}

void mote_rnd_draw_grid(cairo_t *cr, const mote_rnd_style *st, const mote_rnd_layout *lay)
{
    cairo_save(cr);
    cairo_set_source_rgb(cr, 0.90, 0.90, 0.90);
    double lw = fmax(1.0, round(st->scale));
    cairo_set_line_width(cr, lw);
    double right = lay->left + lay->width, bottom = lay->top + lay->height;
    for (double i = lay->xt.i0; i <= lay->xt.i1; i++) {
        double x = crisp(mote_rnd_px(lay, mote_rnd_tick_value(&lay->xt, i)), lw);
        if (x <= lay->left + 1 || x >= right - 1) continue;
        cairo_move_to(cr, x, lay->top);
        cairo_line_to(cr, x, bottom);
    }
    for (int k = 0; k < lay->nxlist; k++) {
        double x = crisp(mote_rnd_px(lay, lay->xlist[k]), lw);
        if (x <= lay->left + 1 || x >= right - 1) continue;
        cairo_move_to(cr, x, lay->top);
        cairo_line_to(cr, x, bottom);
    }
    for (double i = lay->yt.i0; i <= lay->yt.i1; i++) {
        double y = crisp(mote_rnd_py(lay, mote_rnd_tick_value(&lay->yt, i)), lw);
        if (y <= lay->top + 1 || y >= bottom - 1) continue;
        cairo_move_to(cr, lay->left, y);
        cairo_line_to(cr, right, y);
    }
    cairo_stroke(cr);
    cairo_restore(cr);
}

void mote_rnd_draw_axes(cairo_t *cr, const mote_rnd_style *st, const mote_rnd_layout *lay,
                        const mote_rnd_layout_in *in)
{
    double lw = st->frame_width;
    double bottom = lay->top + lay->height;
    cairo_save(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, lw);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_SQUARE);
    /* The frame line lies just outside the plot area, which stays fully visible. */
    cairo_rectangle(cr, lay->left - lw / 2, lay->top - lw / 2, lay->width + lw, lay->height + lw);
    cairo_stroke(cr);

    cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
    mote_rnd_font(cr, st->tick_font, 0);
    double tick_h = mote_rnd_line_height(cr);
    char buf[64];
    for (double i = lay->xt.i0; i <= lay->xt.i1; i++) {
        double v = mote_rnd_tick_value(&lay->xt, i);
        double x = crisp(mote_rnd_px(lay, v), lw);
        cairo_move_to(cr, x, bottom + lw);
        cairo_line_to(cr, x, bottom + lw + st->ticklen);
        cairo_stroke(cr);
        mote_rnd_tick_label(&lay->xt, v, buf);
        mote_rnd_text(cr, x, bottom + lw + st->ticklen + st->gap, buf, 0.5, MOTE_RND_TOP);
    }
    for (int k = 0; k < lay->nxlist; k++) {
        double x = crisp(mote_rnd_px(lay, lay->xlist[k]), lw);
        cairo_move_to(cr, x, bottom + lw);
        cairo_line_to(cr, x, bottom + lw + st->ticklen);
        cairo_stroke(cr);
        mote_rnd_log_label(lay->xlist[k], buf);
        mote_rnd_text(cr, x, bottom + lw + st->ticklen + st->gap, buf, 0.5, MOTE_RND_TOP);
    }
    double widest_y = 0.0;
    for (double i = lay->yt.i0; i <= lay->yt.i1; i++) {
        double v = mote_rnd_tick_value(&lay->yt, i);
        double y = crisp(mote_rnd_py(lay, v), lw);
        cairo_move_to(cr, lay->left - lw, y);
        cairo_line_to(cr, lay->left - lw - st->ticklen, y);
        cairo_stroke(cr);
        mote_rnd_tick_label(&lay->yt, v, buf);
        widest_y = fmax(widest_y, mote_rnd_text_width(cr, buf));
        mote_rnd_text(cr, lay->left - lw - st->ticklen - st->gap, y, buf, 1.0, MOTE_RND_MIDDLE);
    }

    double avail_w = lay->img_w - 2 * st->pad;
    char fitted[512];
    if (has_text(in->xlabel)) {
        const char *s = mote_rnd_fit_text(cr, in->xlabel, st->label_font, 0, 0.7, avail_w, fitted,
                                          sizeof fitted);
        double y = bottom + lw + st->ticklen + st->gap + tick_h + 1.5 * st->gap;
        double w = mote_rnd_text_width(cr, s);
        double x = fmin(fmax(lay->left + lay->width / 2 - w / 2, st->pad), lay->img_w - st->pad - w);
        mote_rnd_text(cr, x, y, s, 0.0, MOTE_RND_TOP);
    }
    if (has_text(in->ylabel)) {
        const char *s = mote_rnd_fit_text(cr, in->ylabel, st->label_font, 0, 0.7,
                                          lay->img_h - 2 * st->pad, fitted, sizeof fitted);
        double h = mote_rnd_line_height(cr), w = mote_rnd_text_width(cr, s);
        /* The label's column sits just left of the widest tick label, not at the image edge,
         * which may be further out when the first x label needed room. */
        double cx = lay->left - lw - st->ticklen - st->gap - widest_y - 1.5 * st->gap - h / 2;
        double cy = lay->top + lay->height / 2;
        cy = fmin(fmax(cy, st->pad + w / 2), lay->img_h - st->pad - w / 2);
        cairo_save(cr);
        cairo_translate(cr, cx, cy);
        cairo_rotate(cr, -acos(0.0));
        mote_rnd_text(cr, 0, 0, s, 0.5, MOTE_RND_MIDDLE);
        cairo_restore(cr);
    }
    if (has_text(in->title)) {
        const char *s = mote_rnd_fit_text(cr, in->title, st->title_font, 1, 0.7, avail_w, fitted,
                                          sizeof fitted);
        double w = mote_rnd_text_width(cr, s);
        /* Centred over the frame, but kept on the image when the title is wide. */
        double x = fmin(fmax(lay->left + lay->width / 2 - w / 2, st->pad), lay->img_w - st->pad - w);
        mote_rnd_text(cr, x, st->pad, s, 0.0, MOTE_RND_TOP);
    }
    cairo_restore(cr);
}

/* ---- output -------------------------------------------------------------------------------- */

/* The PNG stream's sink: the file, and the errno of the first failed write (the cause). */
typedef struct {
    FILE *f;
    int err;
} png_sink;

static cairo_status_t write_to_file(void *closure, const unsigned char *data, unsigned int length)
{
    png_sink *k = closure;
    errno = 0;
    if (fwrite(data, 1, length, k->f) == length)
        return CAIRO_STATUS_SUCCESS;
    if (!k->err)
        k->err = errno ? errno : EIO;
    return CAIRO_STATUS_WRITE_ERROR;
}

static int save_png(cairo_surface_t *surface, const char *path, mote_err *err)
{
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc != MOTE_OK) return rc;
    png_sink sink = {af.f, 0};
    cairo_status_t s = cairo_surface_write_to_png_stream(surface, write_to_file, &sink);
    if (s != CAIRO_STATUS_SUCCESS) {
        mote_afile_abort(&af);
        return mote_fail(err, MOTE_EIO, "%s: cannot write PNG: %s", path,
                         sink.err ? strerror(sink.err) : cairo_status_to_string(s));
    }
    return mote_afile_commit(&af, err);
}

int mote_rnd_finish(const char *path, cairo_surface_t *surface, cairo_t *cr, mote_err *err)
{
    cairo_status_t s = cairo_status(cr);
    int rc = MOTE_OK;
    if (s == CAIRO_STATUS_INVALID_STRING)
        rc = mote_fail(err, MOTE_EINVAL, "%s: a title, axis label or legend text is not valid UTF-8",
                       path);
    else if (s == CAIRO_STATUS_NO_MEMORY)
        rc = mote_fail(err, MOTE_ENOMEM, "%s: out of memory while drawing", path);
    else if (s != CAIRO_STATUS_SUCCESS)
        rc = mote_fail(err, MOTE_ERUNTIME, "%s: drawing failed: %s", path,
                       cairo_status_to_string(s));
    cairo_destroy(cr);
    if (rc == MOTE_OK) {
        cairo_surface_flush(surface);
        rc = save_png(surface, path, err);
    }
    cairo_surface_destroy(surface);
    return rc;
}
