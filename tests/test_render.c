/* test_render.c: checks of the PNG renderers (mote_plot_png, mote_disks_png): the files are real
 * PNGs of the requested size, they show what was asked (series colours, disk classes, periodic
 * wrapping), awkward data (empty, single point, constant, NaN, huge) render without failing,
 * bad input fails with a message and no file, and writes are atomic: a failed write, including
 * one that runs out of file space half way, leaves an earlier file untouched and no temporary
 * file behind. */
#include "mote/render.h"
#include "../src/http/live_page.h"

#include <errno.h>
#include <cairo.h>
#include <dirent.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test.h"

/* fontconfig 2.14 leaks a few hundred bytes once while parsing its configuration (a bare cairo
 * program that measures one string shows it too). LeakSanitizer calls this hook, when the test is
 * built with it, so that it reports only leaks of mote's own memory. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) { return "leak:libfontconfig.so\n"; }
const char *__lsan_default_options(void);
const char *__lsan_default_options(void) { return "print_suppressions=0"; }

typedef struct {
    char dir[256]; /* a fresh temporary directory for every file this test writes */
} ctx;

/* One line per check: CHECK (tests/test.h) counts it and explains a failure with file and line;
 * passes are printed too, so the log shows everything that was checked. cond is evaluated once. */
#define CHECK_LINE(cond, what, detail)                                                        \
    do {                                                                                      \
        int ok_ = (cond) != 0;                                                                \
        const char *d_ = (detail);                                                            \
        if (ok_) printf("ok: %s%s%s\n", (what), d_ && *d_ ? " -- " : "", d_ ? d_ : "");        \
        CHECK(ok_, "%s [%s] %s", (what), #cond, d_ ? d_ : "");                                \
    } while (0)

static void path_in(const ctx *t, char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "%s/%s", t->dir, name);
}

static int file_exists(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0;
}

/* Entries in the temporary directory: a failed write must not leave a temporary file behind. */
static int count_entries(const ctx *t)
{
    DIR *d = opendir(t->dir);
    if (!d) return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) n++;
    closedir(d);
    return n;
}

/* 1 if the file starts with the PNG signature and an IHDR chunk; fills width and height. */
static int png_size(const char *p, long *w, long *h)
{
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    unsigned char b[24];
    FILE *f = fopen(p, "rb");
    if (!f) return 0;
    size_t got = fread(b, 1, sizeof b, f);
    fclose(f);
    if (got != sizeof b || memcmp(b, sig, 8) != 0 || memcmp(b + 12, "IHDR", 4) != 0) return 0;
    *w = ((long)b[16] << 24) | ((long)b[17] << 16) | ((long)b[18] << 8) | b[19];
    *h = ((long)b[20] << 24) | ((long)b[21] << 16) | ((long)b[22] << 8) | b[23];
    return 1;
}

/* Pixels of exactly this colour (0xRRGGBB) in a PNG, or -1 if it cannot be read. */
/* The live page's lines joined (src/http/live_page.h). */
static const char *page_text(void)
{
    static char buf[1 << 16];
    if (!buf[0])
        for (size_t k = 0; k < sizeof mote_live_page_lines / sizeof mote_live_page_lines[0]; k++)
            strncat(buf, mote_live_page_lines[k], sizeof buf - strlen(buf) - 1);
    return buf;
}

static long count_colour(const char *p, unsigned rgb)
{
    cairo_surface_t *s = cairo_image_surface_create_from_png(p);
    if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(s);
        return -1;
    }
    cairo_surface_flush(s);
    const unsigned char *data = cairo_image_surface_get_data(s);
    int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
    int stride = cairo_image_surface_get_stride(s);
    long n = 0;
    for (int y = 0; y < h; y++) {
        const unsigned *row = (const unsigned *)(const void *)(data + (size_t)y * stride);
        for (int x = 0; x < w; x++)
            if ((row[x] & 0xffffffu) == rgb) n++;
    }
    cairo_surface_destroy(s);
    return n;
}

static int read_all(const char *p, char *buf, size_t cap, size_t *len)
{
    FILE *f = fopen(p, "rb");
    if (!f) return 0;
    *len = fread(buf, 1, cap, f);
    fclose(f);
    return 1;
}

static int write_text(const char *p, const char *text)
{
    FILE *f = fopen(p, "wb");
    if (!f) return 0;
    fputs(text, f);
    return fclose(f) == 0;
}

/* Okabe-Ito colours as the renderers use them (blue, vermillion, bluish green). */
enum { BLUE = 0x0072b2, VERMILLION = 0xd55e00, GREEN = 0x009e73 };

#define NPTS 200

static int sample_plot(const char *path, int width, int height, mote_err *err)
{
    double x[NPTS], y1[NPTS], y2[NPTS], y3[NPTS];
    for (int i = 0; i < NPTS; i++) {
        x[i] = i * 0.05;
        y1[i] = sin(x[i]);
        y2[i] = (i > 80 && i < 90) ? NAN : 0.5 * cos(x[i]); /* a gap in the line */
        y3[i] = 0.3 + 0.1 * sin(3 * x[i]);
    }
    mote_series s[3] = {
        {x, y1, NPTS, "sin x", 0},
        {x, y2, NPTS, "cos x / 2", 2},
        {x, y3, NPTS, "ripple", 1},
    };
    mote_plot_opts o = {0};
    o.title = "Test plot";
    o.xlabel = "x";
    o.ylabel = "f(x)";
    o.width = width;
    o.height = height;
    o.has_yref = 1;
    o.yref = 0.25;
    o.yref_label = "mean";
    return mote_plot_png(path, &o, s, 3, err);
}

static void test_plot(ctx *t)
{
    char p[512], msg[256];
    mote_err err = {0};
    long w = 0, h = 0;

    path_in(t, p, sizeof p, "plot.png");
    int rc = sample_plot(p, 800, 500, &err);
    CHECK_LINE(rc == MOTE_OK, "plot: three series with a reference line", rc ? err.msg : "");
    CHECK_LINE(file_exists(p), "plot: file exists", p);
    int is_png = png_size(p, &w, &h);
    CHECK_LINE(is_png, "plot: PNG signature and IHDR", "");
    snprintf(msg, sizeof msg, "got %ld x %ld", w, h);
    CHECK_LINE(is_png && w == 800 && h == 500, "plot: 800 x 500 as requested", msg);
    long blue = count_colour(p, BLUE), verm = count_colour(p, VERMILLION),
         green = count_colour(p, GREEN);
    snprintf(msg, sizeof msg, "%ld blue, %ld vermillion, %ld green pixels", blue, verm, green);
    CHECK_LINE(blue > 300 && verm > 300 && green > 100, "plot: all three series are drawn", msg);

    path_in(t, p, sizeof p, "default.png");
    rc = sample_plot(p, 0, 0, &err);
    is_png = rc == MOTE_OK && png_size(p, &w, &h);
    snprintf(msg, sizeof msg, "got %ld x %ld", w, h);
    CHECK_LINE(is_png && w == 1000 && h == 650, "plot: default size 1000 x 650", msg);
}

/* Equal axes: a range twice as tall as wide gives a picture taller than wide. */
static void test_plot_equal(ctx *t)
{
    char p[512], msg[1200];
    mote_err err = {0};
    double x[65], y[65];
    for (int k = 0; k <= 64; k++) {
        x[k] = cos(2 * 3.14159265358979 * k / 64);
        y[k] = 2 * sin(2 * 3.14159265358979 * k / 64);
    }
    mote_series s = {x, y, 65, "ellipse", 0};
    mote_plot_opts o;
    memset(&o, 0, sizeof o);
    o.equal_axes = 1;
    o.width = 600;
    o.xmin = -1;
    o.xmax = 1;
    o.ymin = -2;
    o.ymax = 2;
    path_in(t, p, sizeof p, "equal.png");
    int rc = mote_plot_png(p, &o, &s, 1, &err);
    long w = 0, h = 0;
    int is_png = rc == MOTE_OK && png_size(p, &w, &h);
    snprintf(msg, sizeof msg, "got %ld x %ld (%s)", w, h, rc ? err.msg : "");
    CHECK_LINE(is_png && h == 600 && w < h && w > h / 3, "plot: equal axes, 1 x 2 range", msg);
    o.ymin = -1e6;
    o.ymax = 1e6;
    rc = mote_plot_png(p, &o, &s, 1, &err);
    CHECK_LINE(rc == MOTE_EINVAL && strstr(err.msg, "equal axes"),
               "plot: equal axes refuse a 1 : 10^6 range", err.msg);
}

/* Data that have no natural scale must still give a picture. */
static void test_plot_awkward(ctx *t)
{
    char p[512];
    mote_err err = {0};
    double one_x[1] = {3.0}, one_y[1] = {7.0};
    double cx[4] = {0, 1, 2, 3}, cy[4] = {5, 5, 5, 5};
    double zx[3] = {0, 0, 0}, zy[3] = {0, 0, 0};
    double nx[3] = {NAN, INFINITY, 2}, ny[3] = {1, 2, NAN};
    double hx[2] = {1e-300, 3e-300}, hy[2] = {1e250, -2e250};
    double wx[3] = {1e9, 1e9, 1e9}, wy[3] = {1e9, 1e9 + 1e-7, 1e9 + 2e-7};
    struct {
        const char *name;
        mote_series s;
        double xmin, xmax;
    } cases[] = {
        {"empty series", {NULL, NULL, 0, "nothing", 0}, 0, 0},
        {"single point (line)", {one_x, one_y, 1, "one", 0}, 0, 0},
        {"single point (points)", {one_x, one_y, 1, NULL, 1}, 0, 0},
        {"constant data", {cx, cy, 4, "flat", 2}, 0, 0},
        {"all zeros", {zx, zy, 3, NULL, 2}, 0, 0},
        {"only NaN and inf", {nx, ny, 3, NULL, 0}, 0, 0},
        {"tiny x, huge y", {hx, hy, 2, NULL, 2}, 0, 0},
        {"span far below magnitude", {wx, wy, 3, NULL, 2}, 0, 0},
        {"reversed x range", {cx, cy, 4, "flat", 2}, 3, 0},
        {"range excluding all data", {cx, cy, 4, NULL, 2}, 100, 200},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        path_in(t, p, sizeof p, "awkward.png");
        mote_plot_opts o = {0};
        o.title = cases[k].name;
        o.xmin = cases[k].xmin;
        o.xmax = cases[k].xmax;
        long w, h;
        int rc = mote_plot_png(p, &o, &cases[k].s, 1, &err);
        char what[128];
        snprintf(what, sizeof what, "plot: %s renders", cases[k].name);
        CHECK_LINE(rc == MOTE_OK && png_size(p, &w, &h), what, rc ? err.msg : "");
        remove(p);
    }
    /* An outlier segment from +1e200 to -1e200 crosses the frame as a vertical line at x = 1,
     * exactly like a plain line from y = -1 to 2 there: cutting it to the frame must not lose it
     * to rounding. */
    {
        double ox[2] = {0, 2}, oy[2] = {1e200, -1e200}, vx[2] = {1, 1}, vy[2] = {-1, 2};
        mote_series outlier = {ox, oy, 2, NULL, 0}, plain = {vx, vy, 2, NULL, 0};
        mote_plot_opts o = {0};
        o.xmax = 2;
        o.ymax = 1;
        char q[512], msg[128];
        path_in(t, p, sizeof p, "outlier.png");
        path_in(t, q, sizeof q, "vertical.png");
        int rc1 = mote_plot_png(p, &o, &outlier, 1, &err);
        int rc2 = mote_plot_png(q, &o, &plain, 1, &err);
        long n1 = count_colour(p, BLUE), n2 = count_colour(q, BLUE);
        snprintf(msg, sizeof msg, "%ld pixels, expected %ld", n1, n2);
        CHECK_LINE(rc1 == MOTE_OK && rc2 == MOTE_OK && n2 > 300 && labs(n1 - n2) <= n2 / 50,
              "plot: a segment between +-1e200 is cut to the frame correctly", msg);
    }
    /* Text far too long for the picture is shortened at a character boundary: cutting inside
     * a two-byte character would make cairo reject the string. */
    {
        char title[700] = "", label[400] = "";
        for (int i = 0; i < 30; i++) strcat(title, "Плотность "); /* 19 bytes each */
        for (int i = 0; i < 30; i++) strcat(label, "σ-слой ");
        mote_series ls = {cx, cy, 4, label, 2};
        mote_plot_opts o = {0};
        o.title = title;
        o.xlabel = title;
        o.ylabel = label;
        o.width = 400;
        o.height = 300;
        path_in(t, p, sizeof p, "long-text.png");
        int rc = mote_plot_png(p, &o, &ls, 1, &err);
        CHECK_LINE(rc == MOTE_OK, "plot: very long UTF-8 texts are shortened", rc ? err.msg : "");
    }
    path_in(t, p, sizeof p, "null-opts.png");
    int rc = mote_plot_png(p, NULL, &cases[3].s, 1, &err);
    CHECK_LINE(rc == MOTE_OK && file_exists(p), "plot: NULL options mean defaults", rc ? err.msg : "");
}

static void test_plot_errors(ctx *t)
{
    char p[512];
    mote_err err = {0};
    double x[2] = {0, 1};
    path_in(t, p, sizeof p, "bad.png");
    int before = count_entries(t);

    mote_series s = {x, NULL, 2, NULL, 0};
    int rc = mote_plot_png(p, NULL, &s, 1, &err);
    CHECK_LINE(rc == MOTE_EINVAL && strstr(err.msg, "bad.png"), "plot: n > 0 with NULL y fails",
          err.msg);
    rc = mote_plot_png(p, NULL, &s, 0, &err);
    CHECK_LINE(rc == MOTE_EINVAL, "plot: zero series fails", err.msg);
    mote_series bad_style = {x, x, 2, NULL, 7};
    rc = mote_plot_png(p, NULL, &bad_style, 1, &err);
    CHECK_LINE(rc == MOTE_EINVAL, "plot: unknown style fails", err.msg);
    mote_plot_opts o = {0};
    o.width = 5;
    s.y = x;
    rc = mote_plot_png(p, &o, &s, 1, &err);
    CHECK_LINE(rc == MOTE_EINVAL, "plot: 5-pixel width fails", err.msg);
    o.width = 0;
    o.xmin = 0;
    o.xmax = NAN;
    rc = mote_plot_png(p, &o, &s, 1, &err);
    CHECK_LINE(rc == MOTE_EINVAL, "plot: NaN axis range fails", err.msg);
    o.xmax = 0;
    o.title = "bad \xff\xfe UTF-8";
    rc = mote_plot_png(p, &o, &s, 1, &err);
    CHECK_LINE(rc == MOTE_EINVAL, "plot: invalid UTF-8 title fails", err.msg);
    double big[2] = {0, 1e305};
    mote_series huge = {x, big, 2, NULL, 0};
    rc = mote_plot_png(p, NULL, &huge, 1, &err);
    CHECK_LINE(rc == MOTE_EINVAL, "plot: values beyond 1e300 fail", err.msg);
    CHECK_LINE(!file_exists(p) && count_entries(t) == before, "plot: failures leave no file", "");
}

/* A simple two-species configuration: a jittered lattice in a periodic square box. */
static void lattice(double *x, double *y, double *r, int *c, int n, double box)
{
    int side = (int)ceil(sqrt(n));
    double a = box / side;
    unsigned s = 12345;
    for (int i = 0; i < n; i++) {
        s = s * 1103515245u + 12345u;
        double jx = ((s >> 8) % 1000) / 1000.0 - 0.5;
        s = s * 1103515245u + 12345u;
        double jy = ((s >> 8) % 1000) / 1000.0 - 0.5;
        x[i] = (i % side + 0.5 + 0.3 * jx) * a;
        y[i] = (i / side + 0.5 + 0.3 * jy) * a;
        r[i] = 0.3 * a;
        c[i] = (s >> 16) % 2;
    }
}

static void test_disks(ctx *t)
{
    char p[512], msg[256];
    mote_err err = {0};
    enum { N = 2000 };
    double x[N], y[N], r[N];
    int c[N];
    lattice(x, y, r, c, N, 50.0);
    mote_scatter_opts o = {0};
    o.title = "Disks";
    o.xlabel = "x";
    o.ylabel = "y";
    o.width = 600;
    o.xmax = 50;
    o.ymax = 50;
    o.periodic = 1;

    path_in(t, p, sizeof p, "disks.png");
    long w = 0, h = 0;
    int rc = mote_disks_png(p, &o, x, y, r, c, N, &err);
    CHECK_LINE(rc == MOTE_OK, "disks: 2000 periodic disks in two classes", rc ? err.msg : "");
    int is_png = png_size(p, &w, &h);
    CHECK_LINE(is_png, "disks: PNG signature and IHDR", p);
    snprintf(msg, sizeof msg, "got %ld x %ld", w, h);
    CHECK_LINE(is_png && (w > h ? w : h) == 600, "disks: longer side is the requested 600", msg);
    long blue = count_colour(p, BLUE), verm = count_colour(p, VERMILLION);
    snprintf(msg, sizeof msg, "%ld blue, %ld vermillion pixels", blue, verm);
    CHECK_LINE(blue > 10000 && verm > 10000, "disks: both classes are drawn", msg);

    /* A frame twice as wide as high gives a landscape picture. */
    o.ymax = 25;
    path_in(t, p, sizeof p, "wide.png");
    rc = mote_disks_png(p, &o, x, y, r, NULL, N, &err);
    is_png = rc == MOTE_OK && png_size(p, &w, &h);
    snprintf(msg, sizeof msg, "got %ld x %ld", w, h);
    CHECK_LINE(is_png && w == 600 && h < 400 && h > 250, "disks: 2:1 frame gives a wide picture",
          msg);
    CHECK_LINE(count_colour(p, VERMILLION) == 0 && count_colour(p, BLUE) > 10000,
          "disks: c == NULL draws class 0 only", "");

    /* One disk centred on the left edge: half of it shows, and in a periodic frame the other
     * half appears at the right edge, so the disk's colour covers about twice the area. */
    double dx[1] = {0.0}, dy[1] = {5.0}, dr[1] = {1.0};
    int dc[1] = {2};
    mote_scatter_opts e = {0};
    e.width = 500;
    e.xmax = 10;
    e.ymax = 10;
    char p1[512], p2[512];
    path_in(t, p1, sizeof p1, "edge-walled.png");
    path_in(t, p2, sizeof p2, "edge-periodic.png");
    int rc1 = mote_disks_png(p1, &e, dx, dy, dr, dc, 1, &err);
    e.periodic = 1;
    int rc2 = mote_disks_png(p2, &e, dx, dy, dr, dc, 1, &err);
    long a1 = count_colour(p1, GREEN), a2 = count_colour(p2, GREEN);
    snprintf(msg, sizeof msg, "%ld pixels walled, %ld periodic", a1, a2);
    CHECK_LINE(rc1 == MOTE_OK && rc2 == MOTE_OK && a1 > 100 && a2 > 1.8 * a1 && a2 < 2.2 * a1,
          "disks: periodic frame wraps a disk across the edge", msg);
    /* Unwrapped coordinates (a whole box length away) land in the same place. */
    dx[0] = 30.0;
    dy[0] = -5.0;
    rc2 = mote_disks_png(p2, &e, dx, dy, dr, dc, 1, &err);
    long a3 = count_colour(p2, GREEN);
    snprintf(msg, sizeof msg, "%ld pixels, expected %ld", a3, a2);
    CHECK_LINE(rc2 == MOTE_OK && a3 == a2, "disks: periodic frame wraps unwrapped coordinates", msg);

    path_in(t, p, sizeof p, "empty-disks.png");
    rc = mote_disks_png(p, NULL, NULL, NULL, NULL, NULL, 0, &err);
    CHECK_LINE(rc == MOTE_OK && png_size(p, &w, &h), "disks: no disks and no options render",
          rc ? err.msg : "");
    double nan_x[2] = {NAN, 1}, ny[2] = {1, 1}, nr[2] = {1, -1};
    rc = mote_disks_png(p, NULL, nan_x, ny, nr, NULL, 2, &err);
    CHECK_LINE(rc == MOTE_OK, "disks: NaN position and negative radius are skipped",
          rc ? err.msg : "");

    int before = count_entries(t);
    path_in(t, p, sizeof p, "bad-disks.png");
    rc = mote_disks_png(p, &o, x, y, NULL, c, N, &err);
    CHECK_LINE(rc == MOTE_EINVAL && strstr(err.msg, "bad-disks.png"),
          "disks: n > 0 with NULL radii fails", err.msg);
    CHECK_LINE(!file_exists(p) && count_entries(t) == before, "disks: failure leaves no file", "");
}

static void test_atomic(ctx *t)
{
    char p[512], msg[256];
    mote_err err = {0};

    /* The directory does not exist: an error naming the path, and no file. */
    path_in(t, p, sizeof p, "no-such-dir/plot.png");
    int rc = sample_plot(p, 400, 300, &err);
    CHECK_LINE(rc != MOTE_OK && strstr(err.msg, "no-such-dir/plot.png") != NULL,
          "atomic: missing directory fails and names the path", err.msg);
    CHECK_LINE(!file_exists(p), "atomic: no file in a missing directory", "");

    /* The target is a directory: the rename fails after the PNG was written, and the temporary
     * file must be removed. */
    int before = count_entries(t);
    path_in(t, p, sizeof p, "a-directory");
    mkdir(p, 0755);
    rc = sample_plot(p, 400, 300, &err);
    snprintf(msg, sizeof msg, "%d entries before, %d after", before + 1, count_entries(t));
    CHECK_LINE(rc != MOTE_OK && count_entries(t) == before + 1,
          "atomic: failed rename leaves no temporary file", msg);
    rmdir(p);

    /* Success replaces an existing file. */
    path_in(t, p, sizeof p, "replace.png");
    write_text(p, "old contents\n");
    long w = 0, h = 0;
    rc = sample_plot(p, 400, 300, &err);
    CHECK_LINE(rc == MOTE_OK && png_size(p, &w, &h) && w == 400,
          "atomic: success replaces an existing file", rc ? err.msg : "");

    /* Running out of file space half way through: the earlier PNG stays as it was. */
    enum { CAP = 1 << 20 };
    char *old = malloc(CAP), *now = malloc(CAP);
    size_t old_len = 0, now_len = 0;
    if (!old || !now) {
        free(old);
        free(now);
        CHECK_LINE(0, "atomic: memory for file copies", "");
        return;
    }
    read_all(p, old, CAP, &old_len);
    before = count_entries(t);
    struct rlimit saved, tiny;
    getrlimit(RLIMIT_FSIZE, &saved);
    tiny = saved;
    tiny.rlim_cur = 2000;
    void (*prev)(int) = signal(SIGXFSZ, SIG_IGN);
    int limited = setrlimit(RLIMIT_FSIZE, &tiny) == 0;
    rc = sample_plot(p, 700, 400, &err);
    setrlimit(RLIMIT_FSIZE, &saved);
    signal(SIGXFSZ, prev);
    read_all(p, now, CAP, &now_len);
    CHECK_LINE(limited && rc == MOTE_EIO, "atomic: write failing half way returns an I/O error",
          err.msg);
    CHECK_LINE(strstr(err.msg, strerror(EFBIG)) != NULL, "the failed write names its cause",
               err.msg);
    CHECK_LINE(now_len == old_len && memcmp(old, now, old_len) == 0,
          "atomic: failed write keeps the earlier file", "");
    snprintf(msg, sizeof msg, "%d entries before, %d after", before, count_entries(t));
    CHECK_LINE(count_entries(t) == before, "atomic: failed write leaves no temporary file", msg);
    free(old);
    free(now);
}

static void remove_tree(const ctx *t)
{
    DIR *d = opendir(t->dir);
    if (!d) return;
    struct dirent *e;
    char p[512];
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
        path_in(t, p, sizeof p, e->d_name);
        remove(p);
    }
    closedir(d);
    rmdir(t->dir);
}

/* The live views give each class the colour the PNGs draw it in (issue 34: colour 0 was red
 * live and blue in the PNGs): mote_class_colour_hex matches the pixels of a disk of each class,
 * and the page's own palette (for a view that names no colour) is the same list. */
static void test_class_hex(ctx *t)
{
    printf("class colours: the live view's are the PNGs'\n");
    char p[600];
    snprintf(p, sizeof p, "%s/hex.png", t->dir);
    for (int k = 0; k < 8; k++) {
        double x = 0.5, y = 0.5, r = 0.3;
        int c = k;
        mote_scatter_opts o = {0};
        o.width = 64;
        o.xmin = o.ymin = 0;
        o.xmax = o.ymax = 1;
        mote_err err = {0};
        int rc = mote_disks_png(p, &o, &x, &y, &r, &c, 1, &err);
        const char *hex = mote_class_colour_hex(k);
        unsigned rgb = (unsigned)strtoul(hex + 1, NULL, 16);
        CHECK_LINE(rc == MOTE_OK && count_colour(p, rgb) > 100, "class colour drawn as its hex",
                   hex);
        CHECK_LINE(strstr(page_text(), hex) != NULL, "the live page's palette has it", hex);
    }
    CHECK_LINE(strcmp(mote_class_colour_hex(9), mote_class_colour_hex(1)) == 0 &&
                   strcmp(mote_class_colour_hex(-1), mote_class_colour_hex(7)) == 0,
               "class colours modulo 8", "");
}

int main(void)
{
    const char *base = getenv("TMPDIR");
    ctx t = {{0}};
    snprintf(t.dir, sizeof t.dir, "%s/mote-render-XXXXXX", base && *base ? base : "/tmp");
    if (!mkdtemp(t.dir)) {
        perror("mkdtemp");
        CHECK(0, "cannot create a temporary directory under %s", t.dir);
        return test_summary();
    }
    test_plot(&t);
    test_plot_equal(&t);
    test_plot_awkward(&t);
    test_plot_errors(&t);
    test_disks(&t);
    test_class_hex(&t);
    test_atomic(&t);
    remove_tree(&t);
    /* Free cairo's font and surface caches so the leak checker sees only our own memory. */
    cairo_debug_reset_static_data();
    return test_summary();
}
