/* frames.c: Galactica-style pictures (spec 7.13): every body a disc of radius
 * max(1, 100 Rd (m / m_max)^(1/3)) pixels with its velocity arrow of length 0.1 aix amv |v| / v_max,
 * in the barycentric frame or relative to body kpp(1) (Kl10 = 1), turned by al about x and bet
 * about y, at pixel (Xe0 + aix x', Ye0 - biy y'), on black, in the 16 colours of the VGA palette
 * (ipp for the selected bodies' arrows, jpp(1) for the others'), one Z layer of an area when
 * Ke >= 1, and zoomed out when a body would leave the picture (Kl14 = 1). Pixel-exact agreement
 * with Galactica is not sought. Used by Galactica jobs (--frames) and the `frames` command. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mote/render.h"
#include "nb.h"

static const unsigned VGA[16] = {0x000000, 0x0000AA, 0x00AA00, 0x00AAAA, 0xAA0000, 0xAA00AA,
                                 0xAA5500, 0xAAAAAA, 0x555555, 0x5555FF, 0x55FF55, 0x55FFFF,
                                 0xFF5555, 0xFF55FF, 0xFFFF55, 0xFFFFFF};

void nb_frame_from_ctl(nb_frame_opts *f, const nb_galctl *c, const mote_real head[25])
{
    memset(f, 0, sizeof *f);
    f->al = nb_galctl_get(c, "al");
    f->bet = nb_galctl_get(c, "bet");
    f->Xe0 = nb_galctl_get(c, "Xe0");
    f->Ye0 = nb_galctl_get(c, "Ye0");
    f->aix = nb_galctl_get(c, "aix");
    f->biy = nb_galctl_get(c, "biy");
    f->Rd = nb_galctl_get(c, "Rd");
    f->amv = nb_galctl_get(c, "amv");
    f->Kl10 = nb_galctl_get(c, "Kl10") == 1;
    f->Kl14 = nb_galctl_get(c, "Kl14") == 1;
    const double ke = nb_galctl_get(c, "Ke");
    f->Ke = ke >= 1 && ke < 1e9 ? (long)ke : 0;
    f->ntrio = c->ntrio;
    f->trio = c->trio;
    const double np = nb_galctl_get(c, "Np");
    f->np = np >= 0 && np <= c->ntrio ? (long)np : c->ntrio;
    f->per_layer = head ? (long)(head[17] * head[18]) : 0;
    f->nlayers = head ? (long)head[19] : 0;
    f->zoom = 1;
}

int nb_frame_png(const mote_nb *nb, nb_frame_opts *f, const char *path, uint64_t Lt,
                 mote_err *err)
{
    const int W = 1024, H = 768;
    const double pi = 3.14159265358979323846;
    const double al = f->al * pi / 180, be = f->bet * pi / 180;
    const double Xe0 = f->Xe0, Ye0 = f->Ye0, Rd = f->Rd, amv = f->amv;
    const double aix = f->aix > 0 ? f->aix : 150, biy = f->biy > 0 ? f->biy : aix;
    /* the origin: the barycentre, or body kpp(1) with Kl10 = 1 */
    double o[3] = {0, 0, 0}, ov[3] = {0, 0, 0};
    const long ref = f->Kl10 && f->ntrio > 0 ? f->trio[0][2] : 0;
    if (ref >= 1 && ref <= (long)nb->n)
        for (int a = 0; a < 3; a++) {
            o[a] = (double)nb->x[3 * (ref - 1) + a];
            ov[a] = (double)nb->v[3 * (ref - 1) + a];
        }
    double mmax = 0, vmax = 0;
    for (uint32_t i = 0; i < nb->n; i++)
        if (nb->active[i]) {
            mmax = fmax(mmax, (double)nb->m[i]);
            double v2 = 0;
            for (int a = 0; a < 3; a++)
                v2 += pow((double)nb->v[3 * i + (uint32_t)a] - ov[a], 2);
            vmax = fmax(vmax, sqrt(v2));
        }
    double *disc = malloc((nb->n ? nb->n : 1) * 7 * sizeof *disc);
    unsigned *rgb = malloc((nb->n ? nb->n : 1) * 2 * sizeof *rgb);
    if (!disc || !rgb) {
        free(disc);
        free(rgb);
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory for a picture", path);
    }
    double *seg = disc + 3 * (size_t)nb->n;
    size_t nd = 0;
    double need = 1;
    for (uint32_t i = 0; i < nb->n; i++) {
        if (!nb->active[i])
            continue;
        if (f->Ke >= 1 && f->per_layer > 0 && (long)i < f->per_layer * f->nlayers &&
            (long)i / f->per_layer + 1 != f->Ke)
            continue;
        double p[3], w[3];
        for (int a = 0; a < 3; a++) {
            p[a] = (double)nb->x[3 * i + (uint32_t)a] - o[a];
            w[a] = (double)nb->v[3 * i + (uint32_t)a] - ov[a];
        }
        double *vv[2] = {p, w}; /* turned by al about x, then by bet about y */
        for (int k = 0; k < 2; k++) {
            double *q = vv[k];
            double y = q[1] * cos(al) - q[2] * sin(al), z = q[1] * sin(al) + q[2] * cos(al);
            double x = q[0] * cos(be) + z * sin(be);
            z = -q[0] * sin(be) + z * cos(be);
            q[0] = x;
            q[1] = y;
            q[2] = z;
        }
        const double dx = p[0] * aix * f->zoom, dy = p[1] * biy * f->zoom;
        if (f->Kl14) { /* the scale that keeps this body in the picture */
            if (dx > W - Xe0 && dx > 0)
                need = fmin(need, (W - Xe0) / dx);
            if (dx < -Xe0 && dx < 0)
                need = fmin(need, -Xe0 / dx);
            if (dy > Ye0 && dy > 0)
                need = fmin(need, Ye0 / dy);
            if (dy < Ye0 - H && dy < 0)
                need = fmin(need, (Ye0 - H) / dy);
        }
        disc[3 * nd] = p[0];
        disc[3 * nd + 1] = p[1];
        disc[3 * nd + 2] = fmax(1, 100 * Rd * cbrt((double)nb->m[i] / mmax));
        const double sp = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        const double len = vmax > 0 && sp > 0 ? 0.1 * aix * amv * sp / vmax : 0;
        seg[4 * nd] = seg[4 * nd + 1] = 0;
        seg[4 * nd + 2] = len > 0 ? len * w[0] / sp : 0;
        seg[4 * nd + 3] = len > 0 ? len * w[1] / sp : 0;
        long colour = f->ntrio > 0 ? f->trio[0][1] : 15;
        for (long t = 0; t < f->ntrio && t < f->np; t++)
            if (f->trio[t][2] == (long)i + 1)
                colour = f->trio[t][0];
        rgb[2 * nd] = VGA[15];
        rgb[2 * nd + 1] = VGA[colour >= 0 && colour < 16 ? colour : 15];
        nd++;
    }
    if (need < 1)
        f->zoom *= 0.9 * need;
    for (size_t k = 0; k < nd; k++) { /* to pixels */
        const double x = Xe0 + aix * f->zoom * disc[3 * k];
        const double y = Ye0 - biy * f->zoom * disc[3 * k + 1];
        disc[3 * k] = x;
        disc[3 * k + 1] = y;
        seg[4 * k] = x;
        seg[4 * k + 1] = y;
        seg[4 * k + 2] = x + seg[4 * k + 2];
        seg[4 * k + 3] = y - seg[4 * k + 3];
    }
    char t1[160], t2[160];
    snprintf(t1, sizeof t1, "T = %.15E   Lt = %llu   N = %u", (double)nb->T,
             (unsigned long long)Lt, nb->n);
    snprintf(t2, sizeof t2, "%s%s", f->zoom < 1 ? "zoomed out " : "",
             ref >= 1 ? "relative to body kpp(1)" : "barycentric");
    const char *text[2] = {t1, t2};
    mote_sketch sk = {W, H, 0x000000, disc, rgb, nd, seg, rgb + 1, nd, text, 2};
    int rc = mote_sketch_png(path, &sk, err);
    free(disc);
    free(rgb);
    return rc;
}
