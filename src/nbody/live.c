/* live.c: the N-body model's live view (docs/live-view.md): the bodies in a plane with their
 * recent paths, and live_plane. */
#include "mote/datafile.h"
#include "mote/nbody.h"

#include <tgmath.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "model.h"

/* ---- the live view (docs/live-view.md) -------------------------------------------------------- */

enum { LIVE_PATHS = 64, LIVE_LEN = 64 };

int nb_run_live_plane(void *vm, const mote_call *c, mote_err *err)
{
    nb_model *m = vm;
    m->live.plane = (int)c->args[0].i; /* xy|xz|yz */
    m->live.len = m->live.head = 0; /* the paths start again in the new plane */
    return MOTE_OK;
}

/* The bodies in the chosen plane at their true radii (at least a pixel on the page), the most
 * massive in yellow, and the recent paths of the first bodies; only reads the system. */
void nb_model_live(void *vm, mote_buf *b)
{
    nb_model *m = vm;
    const mote_nb *nb = &m->nb;
    const int a0 = m->live.plane == 2 ? 1 : 0, a1 = m->live.plane == 0 ? 1 : 2;
    const uint32_t np = nb->n < LIVE_PATHS ? nb->n : LIVE_PATHS;
    if (m->live.nb != np || !m->live.pts) { /* (re)start the paths */
        free(m->live.pts);
        m->live.pts = malloc(2 * (size_t)LIVE_LEN * (np ? np : 1) * sizeof *m->live.pts);
        m->live.nb = np;
        m->live.len = m->live.head = 0;
        if (!m->live.pts) {
            b->failed = 1;
            return;
        }
    }
    for (uint32_t i = 0; i < np; i++) {
        double *q = m->live.pts + 2 * ((size_t)i * LIVE_LEN + m->live.head);
        q[0] = (double)nb->x[3 * i + (uint32_t)a0];
        q[1] = (double)nb->x[3 * i + (uint32_t)a1];
    }
    m->live.head = (m->live.head + 1) % LIVE_LEN;
    m->live.len += m->live.len < LIVE_LEN;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, mmax = 0;
    uint32_t heavy = 0, na = 0;
    for (uint32_t i = 0; i < nb->n; i++) {
        if (!nb->active[i])
            continue;
        na++;
        for (int k = 0; k < 2; k++) {
            const double v = (double)nb->x[3 * i + (uint32_t)(k ? a1 : a0)];
            lo[k] = fmin(lo[k], v);
            hi[k] = fmax(hi[k], v);
        }
        if ((double)nb->m[i] > mmax) {
            mmax = (double)nb->m[i];
            heavy = i;
        }
    }
    double half = 0.55 * fmax(hi[0] - lo[0], hi[1] - lo[1]);
    if (!(half > 0))
        half = 1;
    const double cx = na ? (lo[0] + hi[0]) / 2 : 0, cy = na ? (lo[1] + hi[1]) / 2 : 0;
    mote_buf_printf(b, ",\"view\":\"2d\"");
    const double box[4] = {cx - half, cy - half, cx + half, cy + half};
    mote_buf_doubles(b, "box", box, 4, 1);
    mote_buf_printf(b, ",\"classes\":[{\"name\":\"most massive\",\"color\":\"#e8c23a\"},"
                       "{\"name\":\"bodies\",\"color\":\"#9ecbff\"}]");
    double *v = malloc(4 * (size_t)(na ? na : 1) * sizeof *v);
    if (!v) {
        b->failed = 1;
        return;
    }
    uint32_t k = 0;
    for (uint32_t i = 0; i < nb->n; i++)
        if (nb->active[i]) {
            v[k] = (double)nb->x[3 * i + (uint32_t)a0];
            v[na + k] = (double)nb->x[3 * i + (uint32_t)a1];
            v[2 * (size_t)na + k] = (double)nb->ra[i];
            v[3 * (size_t)na + k] = i == heavy ? 0 : 1;
            k++;
        }
    mote_buf_fixed(b, "x", v, na, 1, 2 * half);
    mote_buf_fixed(b, "y", v + na, na, 1, 2 * half);
    mote_buf_doubles(b, "r", v + 2 * (size_t)na, na, 1);
    mote_buf_doubles(b, "c", v + 3 * (size_t)na, na, 1);
    free(v);
    mote_buf_printf(b, ",\"paths\":[");
    for (uint32_t i = 0; i < np && !b->failed; i++) {
        mote_buf_printf(b, i ? ",[" : "[");
        for (size_t j = 0; j < m->live.len; j++) { /* oldest first */
            const size_t at = (m->live.head + LIVE_LEN - m->live.len + j) % LIVE_LEN;
            const double *q = m->live.pts + 2 * ((size_t)i * LIVE_LEN + at);
            mote_buf_printf(b, j ? ",%.7g,%.7g" : "%.7g,%.7g", q[0], q[1]);
        }
        mote_buf_printf(b, "]");
    }
    mote_buf_printf(b, "]");
    double ek = 0;
    for (uint32_t i = 0; i < nb->n; i++) {
        const mote_real *w = nb->v + 3 * (size_t)i;
        ek += 0.5 * (double)(nb->m[i] * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]));
    }
    char st[256];
    snprintf(st, sizeof st, "T = %.10g   step %llu   N = %u active   E_kin = %.10g   merges %llu"
             "   plane %s%s", (double)nb->T, (unsigned long long)nb->steps, na, ek,
             (unsigned long long)nb->merges,
             m->live.plane == 0 ? "xy" : m->live.plane == 1 ? "xz" : "yz",
             nb->tree_on ? "   tree forces (approximate)" : "");
    mote_buf_string(b, "status", st);
}

