/* disks.c: mote_disks_png, pictures of particles as disks drawn to scale in data units inside a
 * frame with equal aspect ratio (a slice of a hard-sphere crystal, the two gases of the mixing
 * box). Colour classes 0..7 use a fixed colour-blind-safe palette; in a periodic frame a disk
 * crossing an edge also appears at its wrapped positions. Disks are drawn in batches per class,
 * which keeps 10^5 disks well under a second. */
#include "mote/render.h"

#include "draw.h"

#include <math.h>

typedef struct {
    double r, g, b;
} rgb;

/* Okabe & Ito (2008); classes 0 and 1 (blue, vermillion) stay distinct for every common form of
 * colour blindness, which matters most for two-species pictures. Black is replaced by grey
 * because the outline is a darker shade of the fill. */
static const rgb class_colours[8] = {
    {0.000, 0.447, 0.698}, /* blue */
    {0.835, 0.369, 0.000}, /* vermillion */
    {0.000, 0.620, 0.451}, /* bluish green */
    {0.902, 0.624, 0.000}, /* orange */
    {0.337, 0.706, 0.914}, /* sky blue */
    {0.800, 0.475, 0.655}, /* reddish purple */
    {0.941, 0.894, 0.259}, /* yellow */
    {0.600, 0.600, 0.600}, /* grey */
};
/* the same, as the live page writes them */
static const char *const class_hex[8] = {"#0072b2", "#d55e00", "#009e73", "#e69f00",
                                         "#56b4e9", "#cc79a7", "#f0e442", "#999999"};

const char *mote_class_colour_hex(int k) { return class_hex[((k % 8) + 8) % 8]; }


enum {
    N_CLASSES = 8,
    /* Disks per cairo path: enough to amortise each fill and stroke; larger batches measured
     * no faster. */
    BATCH = 256,
    /* A disk larger than the periodic frame would need ever more images; this many per axis
     * (each side) is plenty for any sensible picture. */
    MAX_WRAPS = 4,
};

static const double PI = 3.14159265358979323846;

static int disk_class(const int *c, size_t i)
{
    if (!c) return 0;
    int k = c[i] % N_CLASSES;
    return k < 0 ? k + N_CLASSES : k;
}

static int disk_valid(const double *x, const double *y, const double *r, size_t i)
{
    return isfinite(x[i]) && isfinite(y[i]) && isfinite(r[i]) && r[i] > 0.0;
}

typedef struct {
    cairo_t *cr;
    const mote_rnd_layout *lay;
    double xlo, xhi, ylo, yhi; /* the frame in data units, sorted */
    double scale;              /* pixels per data unit */
    double outline;            /* outline width in pixels, 0 = none */
    int periodic;
    size_t pending;            /* disks in the current path */
    rgb fill, edge;
} painter;

static void flush(painter *p)
{
    if (p->pending == 0) return;
    cairo_set_source_rgb(p->cr, p->fill.r, p->fill.g, p->fill.b);
    if (p->outline > 0) {
        cairo_fill_preserve(p->cr);
        cairo_set_source_rgb(p->cr, p->edge.r, p->edge.g, p->edge.b);
        cairo_stroke(p->cr);
    } else {
        cairo_fill(p->cr);
    }
    p->pending = 0;
}

static void add_disk(painter *p, double x, double y, double r)
{
    /* Disks wholly outside the frame cost nothing. */
    if (x + r <= p->xlo || x - r >= p->xhi || y + r <= p->ylo || y - r >= p->yhi) return;
    /* The outline lies inside the disk's true radius, so the disk keeps its size on screen;
     * a minimum size keeps tiny particles visible. */
    double rpx = fmax(r * p->scale - p->outline / 2, 0.5);
    cairo_new_sub_path(p->cr);
    cairo_arc(p->cr, mote_rnd_px(p->lay, x), mote_rnd_py(p->lay, y), rpx, 0, 2 * PI);
    if (++p->pending >= BATCH) flush(p);
}

/* Integer shifts k with centre + k*period overlapping [lo, hi] for a disk of radius r. */
static void wrap_range(double centre, double r, double lo, double hi, double period, int *k0,
                       int *k1)
{
    double a = ceil((lo - r - centre) / period), b = floor((hi + r - centre) / period);
    *k0 = (int)fmax(a, -MAX_WRAPS);
    *k1 = (int)fmin(b, MAX_WRAPS);
}

static void draw_disk(painter *p, double x, double y, double r)
{
    if (!p->periodic) {
        add_disk(p, x, y, r);
        return;
    }
    /* Bring unwrapped coordinates into the frame first, then add each image that reaches it. */
    double lx = p->xhi - p->xlo, ly = p->yhi - p->ylo;
    x = p->xlo + fmod(x - p->xlo, lx);
    if (x < p->xlo) x += lx;
    y = p->ylo + fmod(y - p->ylo, ly);
    if (y < p->ylo) y += ly;
    int kx0, kx1, ky0, ky1;
    wrap_range(x, r, p->xlo, p->xhi, lx, &kx0, &kx1);
    wrap_range(y, r, p->ylo, p->yhi, ly, &ky0, &ky1);
    for (int kx = kx0; kx <= kx1; kx++)
        for (int ky = ky0; ky <= ky1; ky++) add_disk(p, x + kx * lx, y + ky * ly, r);
}

/* Frame from the data when the caller gave none: the disks' extent. */
static void disk_extent(const double *v, const double *r, const double *other, size_t n,
                        double *lo, double *hi)
{
    *lo = INFINITY;
    *hi = -INFINITY;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(v[i]) || !isfinite(other[i]) || !isfinite(r[i]) || r[i] <= 0.0) continue;
        *lo = fmin(*lo, v[i] - r[i]);
        *hi = fmax(*hi, v[i] + r[i]);
    }
}

int mote_disks_png(const char *path, const mote_scatter_opts *opts, const double *x,
                   const double *y, const double *r, const int *c, size_t n, mote_err *err)
{
    static const mote_scatter_opts defaults = {0};
    if (!path || !*path) return mote_fail(err, MOTE_EINVAL, "disks: no output file name given");
    if (!opts) opts = &defaults;
    if (n > 0 && (!x || !y || !r))
        return mote_fail(err, MOTE_EINVAL, "%s: %zu disks but no %s array", path, n,
                         !x ? "x" : !y ? "y" : "radius");
    int L = opts->width ? opts->width : 900;
    int rc = mote_rnd_check_size(path, "width", L, err);
    if (rc != MOTE_OK) return rc;
    if (!isfinite(opts->xmin) || !isfinite(opts->xmax) || !isfinite(opts->ymin) ||
        !isfinite(opts->ymax))
        return mote_fail(err, MOTE_EINVAL, "%s: frame [%g, %g] x [%g, %g] is not finite", path,
                         opts->xmin, opts->xmax, opts->ymin, opts->ymax);

    double x0 = opts->xmin, x1 = opts->xmax, y0 = opts->ymin, y1 = opts->ymax;
    if (x0 == x1) {
        disk_extent(x, r, y, n, &x0, &x1);
        rc = mote_rnd_fix_range(path, "x", &x0, &x1, 0.02, err);
    } else {
        rc = mote_rnd_fix_range(path, "x", &x0, &x1, 0.0, err);
    }
    if (rc != MOTE_OK) return rc;
    if (y0 == y1) {
        disk_extent(y, r, x, n, &y0, &y1);
        rc = mote_rnd_fix_range(path, "y", &y0, &y1, 0.02, err);
    } else {
        rc = mote_rnd_fix_range(path, "y", &y0, &y1, 0.0, err);
    }
    if (rc != MOTE_OK) return rc;

    mote_rnd_style st = mote_rnd_style_for(L / 900.0);
    mote_rnd_layout_in in = {opts->title, opts->xlabel, opts->ylabel, x0, x1, y0, y1, 0, 0,
                             fabs(y1 - y0) / fabs(x1 - x0), L, 0};
    mote_rnd_layout lay;
    rc = mote_rnd_layout_compute(&in, &st, &lay, err);
    if (rc != MOTE_OK) return rc;
    cairo_surface_t *surface;
    cairo_t *cr;
    rc = mote_rnd_canvas(path, lay.img_w, lay.img_h, &surface, &cr, err);
    if (rc != MOTE_OK) return rc;

    painter p = {0};
    p.cr = cr;
    p.lay = &lay;
    p.xlo = fmin(x0, x1);
    p.xhi = fmax(x0, x1);
    p.ylo = fmin(y0, y1);
    p.yhi = fmax(y0, y1);
    p.scale = lay.width / (p.xhi - p.xlo);
    p.periodic = opts->periodic != 0;

    /* One outline width for the whole picture, from the mean radius: outlines on disks of a few
     * pixels would swallow the fill, so small disks get none. */
    double sum_r = 0.0;
    size_t n_valid = 0;
    for (size_t i = 0; i < n; i++) {
        if (!disk_valid(x, y, r, i)) continue;
        sum_r += r[i];
        n_valid++;
    }
    double mean_rpx = n_valid ? sum_r / (double)n_valid * p.scale : 0.0;
    p.outline = mean_rpx < 2.5 ? 0.0 : fmin(0.12 * mean_rpx, fmax(1.0, st.scale));

    cairo_save(cr);
    cairo_rectangle(cr, lay.left, lay.top, lay.width, lay.height);
    cairo_clip(cr);
    cairo_set_line_width(cr, p.outline);
    /* Circles flattened to within a quarter pixel look the same and draw faster. */
    cairo_set_tolerance(cr, 0.25);
    for (int k = 0; k < N_CLASSES; k++) {
        p.fill = class_colours[k];
        p.edge = (rgb){0.55 * p.fill.r, 0.55 * p.fill.g, 0.55 * p.fill.b};
        cairo_new_path(cr);
        for (size_t i = 0; i < n; i++)
            if (disk_class(c, i) == k && disk_valid(x, y, r, i)) draw_disk(&p, x[i], y[i], r[i]);
        flush(&p);
    }
    cairo_restore(cr);

    mote_rnd_draw_axes(cr, &st, &lay, &in);
    return mote_rnd_finish(path, surface, cr, err);
}
