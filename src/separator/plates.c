/* plates.c: the separator's perforated grids (specs/separator.md 2.4): horizontal plates with
 * rectangular holes, from a pattern or a list; the checks of their geometry; a bin index that
 * finds the hole under a point in O(1); and the contact features a particle meets: the hole's
 * side faces when its centre is over a hole, the top or bottom face when it is over solid.
 * (Decision: pattern holes are listed and found through the same bin index as explicit lists,
 * one code path at the same O(1) cost as arithmetic.) */
#include "mote/separator.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sep.h"

void mote_sep_plate_free(mote_sep_plate *p)
{
    free(p->h);
    free(p->bin_start);
    free(p->bin_idx);
    memset(p, 0, sizeof *p);
}

/* Append a hole; -1 out of memory. */
static int add_hole(mote_sep_plate *p, double x1, double x2, double y1, double y2, size_t *cap)
{
    if (p->nh == *cap) {
        const size_t c = *cap ? 2 * *cap : 64;
        double *h = realloc(p->h, 4 * c * sizeof *h);
        if (!h)
            return -1;
        p->h = h;
        *cap = c;
    }
    double *h = p->h + 4 * p->nh++;
    h[0] = x1;
    h[1] = x2;
    h[2] = y1;
    h[3] = y2;
    return 0;
}

int mote_sep_plate_pattern(mote_sep_plate *p, int dim, double W, double D, double zb, double t,
                           const double a[2], const double pitch[2], const double off[2],
                           mote_err *err)
{
    memset(p, 0, sizeof *p);
    p->zb = zb;
    p->t = t;
    size_t cap = 0;
    const double Dy = dim == 3 ? D : 1;
    const double ay = dim == 3 ? a[1] : 1, py = dim == 3 ? pitch[1] : 2, oy = dim == 3 ? off[1] : 0;
    /* holes start at off + i pitch; those wholly inside the cross-section are kept */
    const double nx = floor((W - off[0]) / pitch[0]) + 1, ny = floor((Dy - oy) / py) + 1;
    if (nx * ny > MOTE_SEP_MAX_HOLES)
        return mote_fail(err, MOTE_EINVAL, "grid: the pattern makes %.3g holes (at most %g a "
                         "plate: about %.3g GB)", nx * ny, (double)MOTE_SEP_MAX_HOLES,
                         nx * ny * MOTE_SEP_HOLE_BYTES / 1e9);
    if (mote_mem_check(nx * ny * MOTE_SEP_HOLE_BYTES, "grid: the pattern's holes", err))
        return err ? (int)err->code : MOTE_ENOMEM;
    for (long j = 0; j < (long)ny; j++)
        for (long i = 0; i < (long)nx; i++) {
            const double x1 = off[0] + (double)i * pitch[0], x2 = x1 + a[0];
            const double y1 = dim == 3 ? oy + (double)j * py : 0, y2 = dim == 3 ? y1 + ay : 0;
            if (x1 < 0 || x2 > W || (dim == 3 && (y1 < 0 || y2 > D))) {
                p->dropped++;
                continue;
            }
            if (add_hole(p, x1, x2, y1, y2, &cap))
                return mote_fail(err, MOTE_ENOMEM, "grid: out of memory for the holes");
        }
    return MOTE_OK;
}

int mote_sep_plate_list(mote_sep_plate *p, double zb, double t, const double *h, size_t nh,
                        mote_err *err)
{
    memset(p, 0, sizeof *p);
    p->zb = zb;
    p->t = t;
    p->listed = 1;
    if (nh > MOTE_SEP_MAX_HOLES)
        return mote_fail(err, MOTE_EINVAL, "grid: %zu holes (at most %d a plate)", nh,
                         MOTE_SEP_MAX_HOLES);
    p->h = malloc((nh ? nh : 1) * 4 * sizeof *p->h);
    if (!p->h)
        return mote_fail(err, MOTE_ENOMEM, "grid: out of memory for the holes");
    memcpy(p->h, h, nh * 4 * sizeof *h);
    p->nh = nh;
    return MOTE_OK;
}

/* The bins a range [lo, hi] of a coordinate covers. */
static void bin_range(double lo, double hi, double w, int n, int *b0, int *b1)
{
    *b0 = (int)fmax(0, fmin(n - 1, floor(lo / w))); /* (fmax, fmin: NaN gives the bound) */
    *b1 = (int)fmax(0, fmin(n - 1, floor(hi / w)));
}

int mote_sep_plate_index(mote_sep_plate *p, int dim, double W, double D, mote_err *err)
{
    free(p->bin_start);
    free(p->bin_idx);
    p->bin_start = NULL;
    p->bin_idx = NULL;
    /* about one hole per bin (a bounded number per bin keeps the index and the overlap check
     * linear in the holes): up to 2^24 bins in 2D, 8192 a side in 3D */
    const double side = dim == 3 ? sqrt((double)p->nh) : (double)p->nh;
    p->nbx = (int)fmax(1, fmin(dim == 3 ? 8192 : 16777216, ceil(side)));
    p->nby = dim == 3 ? p->nbx : 1;
    p->bwx = W / p->nbx;
    p->bwy = dim == 3 ? D / p->nby : 1;
    const size_t nb = (size_t)p->nbx * (size_t)p->nby;
    p->bin_start = calloc(nb + 1, sizeof *p->bin_start);
    if (!p->bin_start)
        return mote_fail(err, MOTE_ENOMEM, "grid: out of memory for the hole index");
    for (int pass = 0; pass < 2; pass++) {
        for (size_t k = 0; k < p->nh; k++) {
            const double *h = p->h + 4 * k;
            int x0, x1, y0 = 0, y1 = 0;
            bin_range(h[0], h[1], p->bwx, p->nbx, &x0, &x1);
            if (dim == 3)
                bin_range(h[2], h[3], p->bwy, p->nby, &y0, &y1);
            for (int by = y0; by <= y1; by++)
                for (int bx = x0; bx <= x1; bx++) {
                    const size_t b = (size_t)by * (size_t)p->nbx + (size_t)bx;
                    if (pass == 0)
                        p->bin_start[b + 1]++;
                    else
                        p->bin_idx[p->bin_start[b]++] = (uint32_t)k;
                }
        }
        if (pass == 0) {
            for (size_t b = 0; b < nb; b++)
                p->bin_start[b + 1] += p->bin_start[b];
            p->bin_idx = malloc((p->bin_start[nb] ? p->bin_start[nb] : 1) * sizeof *p->bin_idx);
            if (!p->bin_idx)
                return mote_fail(err, MOTE_ENOMEM, "grid: out of memory for the hole index");
        }
    }
    for (size_t b = nb; b > 0; b--)
        p->bin_start[b] = p->bin_start[b - 1];
    p->bin_start[0] = 0;
    return MOTE_OK;
}

long mote_sep_plate_hole_at(const mote_sep_plate *p, int dim, double x, double y)
{
    const double qx = x / p->bwx, qy = dim == 3 ? y / p->bwy : 0;
    const int bx = !(qx > 0) ? 0 : qx >= p->nbx - 1 ? p->nbx - 1 : (int)qx;
    const int by = !(qy > 0) ? 0 : qy >= p->nby - 1 ? p->nby - 1 : (int)qy;
    const size_t b = (size_t)by * (size_t)p->nbx + (size_t)bx;
    for (uint32_t q = p->bin_start[b]; q < p->bin_start[b + 1]; q++) {
        const double *h = p->h + 4 * p->bin_idx[q];
        if (x >= h[0] && x <= h[1] && (dim < 3 || (y >= h[2] && y <= h[3])))
            return (long)p->bin_idx[q];
    }
    return -1;
}

int mote_sep_plate_check(const mote_sep_plate *p, int index, int dim, double W, double D,
                         double H, double dmin, mote_err *err)
{
    const double zt = p->zb + p->t;
    if (p->zb < 0 || zt > H)
        return mote_fail(err, MOTE_EINVAL, "grid %d: the plate %g ... %g m is not inside the "
                         "channel (0 ... %g m)", index, p->zb, zt, H);
    if (p->nh == 0)
        return mote_fail(err, MOTE_EINVAL, "grid %d: no hole lies inside the cross-section (the "
                         "open area would be 0; a closed end closes the channel)", index);
    double area = 0;
    for (size_t k = 0; k < p->nh; k++) {
        const double *h = p->h + 4 * k;
        const double wx = h[1] - h[0], wy = h[3] - h[2];
        if (!(wx > 0) || (dim == 3 && !(wy > 0)))
            return mote_fail(err, MOTE_EINVAL, "grid %d: hole %zu is empty (x %g ... %g%s)", index,
                             k + 1, h[0], h[1], dim == 3 ? ", y as given" : "");
        if (h[0] < 0 || h[1] > W || (dim == 3 && (h[2] < 0 || h[3] > D)))
            return mote_fail(err, MOTE_EINVAL, "grid %d: hole %zu (x %g ... %g m) crosses a wall "
                             "of the channel (0 ... %g m)", index, k + 1, h[0], h[1], W);
        const double narrow = dim == 3 ? fmin(wx, wy) : wx;
        if (dmin > 0 && narrow < dmin)
            return mote_fail(err, MOTE_EINVAL, "grid %d: hole %zu is %g m wide, narrower than the "
                             "finest particle (%g m): nothing could pass", index, k + 1, narrow,
                             dmin);
        area += dim == 3 ? wx * wy : wx;
    }
    /* overlaps: each hole against those sharing its bins */
    for (size_t k = 0; k < p->nh; k++) {
        const double *h = p->h + 4 * k;
        int x0, x1, y0 = 0, y1 = 0;
        bin_range(h[0], h[1], p->bwx, p->nbx, &x0, &x1);
        if (dim == 3)
            bin_range(h[2], h[3], p->bwy, p->nby, &y0, &y1);
        for (int by = y0; by <= y1; by++)
            for (int bx = x0; bx <= x1; bx++) {
                const size_t b = (size_t)by * (size_t)p->nbx + (size_t)bx;
                for (uint32_t q = p->bin_start[b]; q < p->bin_start[b + 1]; q++) {
                    const size_t j = p->bin_idx[q];
                    if (j <= k)
                        continue;
                    const double *g = p->h + 4 * j;
                    if (h[0] < g[1] && g[0] < h[1] && (dim < 3 || (h[2] < g[3] && g[2] < h[3])))
                        return mote_fail(err, MOTE_EINVAL, "grid %d: holes %zu and %zu overlap",
                                         index, k + 1, j + 1);
                }
            }
    }
    (void)area;
    return MOTE_OK;
}

double mote_sep_plate_open(const mote_sep_plate *p, int dim, double W, double D)
{
    double area = 0;
    for (size_t k = 0; k < p->nh; k++) {
        const double *h = p->h + 4 * k;
        area += dim == 3 ? (h[1] - h[0]) * (h[3] - h[2]) : h[1] - h[0];
    }
    return area / (dim == 3 ? W * D : W);
}

int mote_sep_plate_features(const mote_sep_plate *p, int dim, const double c[3], double r,
                            double delta[4], double n[4][3])
{
    const double zt = p->zb + p->t;
    if (c[2] > zt + r || c[2] < p->zb - r)
        return 0;
    const long k = mote_sep_plate_hole_at(p, dim, c[0], c[1]);
    if (k < 0) { /* over solid: the top or the bottom face, or inside the slab */
        if (c[2] > zt) {
            delta[0] = r - (c[2] - zt);
            n[0][0] = n[0][1] = 0;
            n[0][2] = 1;
            return delta[0] > 0;
        }
        if (c[2] < p->zb) {
            delta[0] = r - (p->zb - c[2]);
            n[0][0] = n[0][1] = 0;
            n[0][2] = -1;
            return delta[0] > 0;
        }
        return -1;
    }
    /* over a hole: each side face, its closest point by clamping */
    const double *h = p->h + 4 * k;
    const double zc = fmin(fmax(c[2], p->zb), zt);
    int nf = 0;
    for (int f = 0; f < (dim == 3 ? 4 : 2); f++) {
        double q[3];
        if (f < 2) { /* the faces x = x1, x = x2 */
            q[0] = h[f];
            q[1] = dim == 3 ? fmin(fmax(c[1], h[2]), h[3]) : c[1];
        } else { /* y = y1, y = y2 */
            q[0] = fmin(fmax(c[0], h[0]), h[1]);
            q[1] = h[f];
        }
        q[2] = zc;
        const double v[3] = {c[0] - q[0], c[1] - q[1], c[2] - q[2]};
        const double dist = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (dist < r && dist > 0) {
            delta[nf] = r - dist;
            n[nf][0] = v[0] / dist;
            n[nf][1] = v[1] / dist;
            n[nf][2] = v[2] / dist;
            nf++;
        }
    }
    return nf;
}
