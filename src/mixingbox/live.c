/* live.c: the mixing box's frame of the live view. */
#include "mote/mixingbox.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "mote/render.h"
#include "mb.h"

/* The live view (docs/live-view.md): the box to scale, the partition and its slit, the disks at
 * their true size in their two colours; during an event run the positions come from the engine
 * (projected, read only), so the run is the same with and without a view. */
void mb_live_frame(const mote_mb *s, const mote_mb_params *set, mote_buf *b)
{
    const mote_mb_params *p = s->placed ? &s->p : set;
    mote_buf_printf(b, ",\"view\":\"2d\"");
    const double box[4] = {p->x_l, p->x_b, p->x_r, p->x_t};
    mote_buf_doubles(b, "box", box, 4, 1);
    const double lines[16] = {p->x_l, p->x_b, p->x_r, p->x_b, p->x_r, p->x_b, p->x_r, p->x_t,
                              p->x_r, p->x_t, p->x_l, p->x_t, p->x_l, p->x_t, p->x_l, p->x_b};
    mote_buf_doubles(b, "lines", lines, 16, 1);
    const double x1l = mote_mb_x1_l(p), x1r = mote_mb_x1_r(p);
    if (p->b > 0) {
        const double rects[8] = {x1l, p->x_b, x1r, mote_mb_x2_b(p),
                                 x1l, mote_mb_x2_t(p), x1r, p->x_t};
        mote_buf_doubles(b, "rects", rects, 8, 1);
    } else {
        const double rects[4] = {x1l, p->x_b, x1r, p->x_t};
        mote_buf_doubles(b, "rects", rects, 4, 1);
    }
    mote_buf_printf(b, ",\"classes\":[{\"name\":\"colour 0 (placed left)\",\"color\":"
                       "\"%s\"},{\"name\":\"colour 1 (placed right)\",\"color\":\"%s\"}]",
                    mote_class_colour_hex(0), mote_class_colour_hex(1));
    const uint32_t n = s->placed ? s->n : 0;
    double *xy = malloc(2 * (size_t)(n ? n : 1) * sizeof *xy);
    double *c = malloc((size_t)(n ? n : 1) * sizeof *c);
    if (!xy || !c) {
        free(xy);
        free(c);
        b->failed = 1;
        return;
    }
    uint64_t wrong = 0;
    double ek = 0;
    for (uint32_t i = 0; i < n; i++) {
        double v[2];
        mote_mb_live_velocity(s, i, v);
        ek += 0.5 * p->mass * (v[0] * v[0] + v[1] * v[1]);
        mote_mb_live_position(s, i, xy + 2 * i);
        c[i] = s->colour[i];
        wrong += (xy[2 * i] >= p->x1_c) != (s->colour[i] == 1);
    }
    const double size = fmax(p->x_r - p->x_l, p->x_t - p->x_b);
    mote_buf_fixed(b, "x", xy, n, 2, size);
    mote_buf_fixed(b, "y", xy + 1, n, 2, size);
    mote_buf_fixed(b, "c", c, n, 1, 1e5); /* (integers) */
    mote_buf_printf(b, ",\"r0\":%.7g", p->r);
    char st[256];
    snprintf(st, sizeof st, "t = %.6g s   N = %u   E_kin = %.6g J   m = %.4f (the fraction of "
             "disks in the other chamber)", mote_mb_live_time(s), n, ek,
             n ? (double)wrong / n : 0.0);
    mote_buf_string(b, "status", s->placed ? st : "no disks placed yet");
    free(xy);
    free(c);
}
