/* frame.c: a picture of the hard spheres (`frames`): the cut through the box's middle plane z =
 * Lz/2 (3D; each sphere it meets as the disc of its cross-section) or the plane of the disks
 * (2D), x across the slit (walls at the frame's left and right), coloured by local order as
 * `snapshot` and `order` define it (3D: the crystal-like flag of q6; 2D: |psi6| > 0.7). */
#include "mote/hardspheres.h"
#include "mote/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "measure.h"

typedef struct {
    double z;
    uint32_t i;
} depth_key;

static int by_depth(const void *a, const void *b)
{
    const double za = ((const depth_key *)a)->z, zb = ((const depth_key *)b)->z;
    return (za > zb) - (za < zb);
}

int hs_frame_png(const mote_hs *hs, const char *path, mote_err *err)
{
    const mote_ev *ev = &hs->ev;
    const uint32_t n = ev->n;
    const size_t cap = n ? n : 1;
    float *local = malloc(cap * sizeof *local);
    uint8_t *flag = malloc(cap);
    depth_key *key = malloc(cap * sizeof *key);
    double *x = malloc(4 * cap * sizeof *x);
    int rc = local && flag && key && x ? hs_local_order(hs, local, flag, err)
                                       : mote_fail(err, MOTE_ENOMEM, "frames: out of memory for "
                                                   "%u particles", n);
    if (!rc) {
        double *y = x + cap, *r = y + cap, *v = r + cap;
        /* 3D: the cut through the middle plane z = Lz/2, each sphere it meets as the disc of
         * its cross-section (radius sqrt(r^2 - dz^2), the nearest periodic image) */
        const int d3 = ev->dim == 3;
        const double zc = d3 ? 0.5 * ev->len[2] : 0, Lz = d3 ? ev->len[2] : 0;
        size_t m = 0;
        for (uint32_t i = 0; i < n; i++) {
            double p[3];
            mote_ev_position(ev, i, p);
            double dz = d3 ? p[2] - zc : 0;
            if (d3 && ev->periodic[2])
                dz -= Lz * floor(dz / Lz + 0.5);
            const double ri = mote_ev_radius(ev, i);
            if (fabs(dz) >= ri)
                continue;
            key[m++] = (depth_key){fabs(dz), i};
        }
        qsort(key, m, sizeof *key, by_depth); /* (those cut nearest their centre on top) */
        for (size_t k = 0; k < m; k++) {
            const uint32_t i = key[m - 1 - k].i;
            double p[3];
            mote_ev_position(ev, i, p);
            const double ri = mote_ev_radius(ev, i), dz = key[m - 1 - k].z;
            x[k] = p[0];
            y[k] = p[1];
            r[k] = sqrt(ri * ri - dz * dz);
            v[k] = flag[i] ? 1 : 0;
        }
        static const char *const names3[2] = {"fluid-like", "crystal-like (q6)"};
        static const char *const names2[2] = {"disordered", "ordered (|psi6| > 0.7)"};
        char title[128], sub[160];
        snprintf(title, sizeof title, "hard %s, %s", ev->dim == 3 ? "spheres" : "disks",
                 hs->geometry == MOTE_HS_SLIT ? "slit (walls left and right)" : "periodic box");
        if (d3)
            snprintf(sub, sizeof sub, "the cut at z = %.4g   t = %.6g   collisions = %llu   N = "
                     "%u   phi = %.4f", zc, mote_ev_time(ev), (unsigned long long)ev->collisions, n,
                     mote_hs_phi(hs));
        else
            snprintf(sub, sizeof sub, "t = %.6g   collisions = %llu   N = %u   phi = %.4f",
                     mote_ev_time(ev), (unsigned long long)ev->collisions, n, mote_hs_phi(hs));
        mote_particles_opts o = {0};
        o.title = title;
        o.xlabel = "x (R)";
        o.ylabel = "y (R)";
        o.subtitle = sub;
        o.xmin = 0;
        o.xmax = ev->len[0];
        o.ymin = 0;
        o.ymax = ev->len[1];
        o.ncat = 2;
        o.cat_names = ev->dim == 3 ? names3 : names2;
        rc = mote_particles_png(path, &o, x, y, r, v, m, NULL, 0, err);
    }
    free(local);
    free(flag);
    free(key);
    free(x);
    return rc;
}
