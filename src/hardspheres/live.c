/* live.c: the hard-spheres model's frame of the live view. */
#include "mote/hardspheres.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "plot.h"

/* The live view (docs/live-view.md): the box and the spheres in 3D (disks in 2D), positions
 * projected to the engine's clock (read only), at most 20 000 of them (every k-th beyond), the
 * walls' axis x; and the density profile along x beside it (100 bins, relative to the mean). */
void hs_live_frame(const mote_hs *hs, mote_buf *b)
{
    const mote_ev *ev = &hs->ev;
    if (!hs->has_system) {
        mote_buf_printf(b, ",\"view\":\"2d\",\"box\":[0,0,1,1]");
        mote_buf_string(b, "status", "no system yet");
        return;
    }
    const int d3 = ev->dim == 3;
    const uint32_t n = ev->n, step = n > 20000 ? (n + 19999) / 20000 : 1, m = (n + step - 1) / step;
    double *v = malloc(4 * (size_t)(m ? m : 1) * sizeof *v);
    if (!v) {
        b->failed = 1;
        return;
    }
    enum { NB = 100 };
    double prof[NB] = {0}, xs[NB];
    uint32_t k = 0;
    for (uint32_t i = 0; i < n; i++) {
        double r[3];
        mote_ev_position(ev, i, r);
        const int bin = (int)(r[0] / ev->len[0] * NB);
        prof[bin < 0 ? 0 : bin >= NB ? NB - 1 : bin] += 1;
        if (i % step)
            continue;
        v[k] = r[0];
        v[m + k] = r[1];
        v[2 * (size_t)m + k] = r[2];
        v[3 * (size_t)m + k] = mote_ev_radius(ev, i);
        k++;
    }
    if (d3) {
        mote_buf_printf(b, ",\"view\":\"3d\"");
        const double box[6] = {0, 0, 0, ev->len[0], ev->len[1], ev->len[2]};
        mote_buf_doubles(b, "box", box, 6, 1);
        mote_buf_fixed(b, "z", v + 2 * (size_t)m, k, 1, ev->len[2]);
    } else {
        mote_buf_printf(b, ",\"view\":\"2d\"");
        const double box[4] = {0, 0, ev->len[0], ev->len[1]};
        mote_buf_doubles(b, "box", box, 4, 1);
        const double lines[8] = {0, 0, 0, ev->len[1], ev->len[0], 0, ev->len[0], ev->len[1]};
        if (!ev->periodic[0])
            mote_buf_doubles(b, "lines", lines, 8, 1);
    }
    const double size = fmax(ev->len[0], ev->len[1]);
    mote_buf_fixed(b, "x", v, k, 1, size);
    mote_buf_fixed(b, "y", v + m, k, 1, size);
    mote_buf_fixed(b, "r", v + 3 * (size_t)m, k, 1, size);
    free(v);
    for (int j = 0; j < NB; j++) {
        xs[j] = (j + 0.5) * ev->len[0] / NB;
        prof[j] = n ? prof[j] * NB / n : 0;
    }
    mote_buf_printf(b, ",\"profile\":{\"label\":\"density along x / mean\"");
    mote_buf_doubles(b, "x", xs, NB, 1);
    mote_buf_doubles(b, "y", prof, NB, 1);
    mote_buf_printf(b, "},\"classes\":[{\"name\":\"%s\",\"color\":\"#5ec45a\"}]",
                    d3 ? "spheres" : "disks");
    char st[256];
    char shown[48] = "";
    if (step > 1)
        snprintf(shown, sizeof shown, " (every %u-th shown)", step);
    snprintf(st, sizeof st, "t = %.6g   N = %u%s   E = %.6g   collisions %llu   walls %s",
             mote_ev_time(ev), n, shown, mote_ev_energy(ev), (unsigned long long)ev->collisions,
             ev->periodic[0] ? "none (periodic)" : "at x = 0 and x = L");
    mote_buf_string(b, "status", st);
}
