/* live.c: the separator's frame of the live view. */
#include "mote/separator.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "mote/render.h"
#include "sep.h"

/* The live view's frame (docs/live-view.md): the channel to scale (x across, z up; a 3D
 * channel seen along y), the grids' plates, the particles at true size by species. */
void sep_live_frame(const mote_sep_system *s, mote_buf *b)
{
    mote_buf_printf(b, ",\"view\":\"2d\"");
    const double box[4] = {0, 0, s->W, s->H};
    mote_buf_doubles(b, "box", box, 4, 1);
    const double lines[12] = {0, 0, 0, s->H, s->W, 0, s->W, s->H, 0, 0, s->W, 0};
    mote_buf_doubles(b, "lines", lines, 12, 1);
    double *rects = NULL;
    size_t nrect = 0;
    if (sep_plate_rects(s, &rects, &nrect) == 0)
        mote_buf_doubles(b, "rects", rects, 4 * nrect, 1);
    free(rects);
    mote_buf_printf(b, ",\"classes\":[");
    for (int k = 0; k < s->nsp; k++) {
        mote_buf_printf(b, "%s{\"color\":\"%s\"", k ? "," : "", mote_class_colour_hex(k));
        mote_buf_string(b, "name", s->sp[k].name);
        mote_buf_printf(b, "}");
    }
    mote_buf_printf(b, "]");
    const size_t n = s->n;
    double *v = malloc((n ? n : 1) * sizeof *v);
    if (!v) {
        b->failed = 1;
        return;
    }
    const double size = fmax(s->W, s->H);
    mote_buf_fixed(b, "x", s->x, n, 1, size);
    mote_buf_fixed(b, "y", s->z, n, 1, size);
    for (size_t i = 0; i < n; i++)
        v[i] = 0.5 * s->d[i];
    mote_buf_doubles(b, "r", v, n, 1);
    for (size_t i = 0; i < n; i++)
        v[i] = s->s[i];
    mote_buf_fixed(b, "c", v, n, 1, 1e5);
    free(v);
    uint64_t fines = 0, coarse = 0, fed = 0;
    for (int k = 0; k < s->nsp; k++) {
        fines += s->cnt[k].fines;
        coarse += s->cnt[k].coarse;
        fed += s->cnt[k].fed;
    }
    double ek = 0;
    for (size_t i = 0; i < n; i++)
        ek += 0.5 * s->m[i] * (s->vx[i] * s->vx[i] + s->vz[i] * s->vz[i] +
                               (s->dim == 3 ? s->vy[i] * s->vy[i] : 0));
    char st[256];
    snprintf(st, sizeof st, "t = %.4f s   N = %zu   E_kin = %.4g J   fed %llu   fines %llu   "
             "coarse %llu   U0 = %g m/s", s->t, s->n, ek, (unsigned long long)fed,
             (unsigned long long)fines, (unsigned long long)coarse, s->U0);
    mote_buf_string(b, "status", st);
}
