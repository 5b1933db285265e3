/* feed.c: the separator's particles (specs/separator.md 2.5): the arrays and their growth, a
 * particle appended from a state, the feed's draws and placements clear of the walls, plates
 * and (DEM) the other particles, the backlog of those that found no room, and batches. */
#include "mote/separator.h"

#include "sep.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SEP_PI 3.14159265358979323846

static int grow(mote_sep_system *s, size_t need, mote_err *err)
{
    if (need <= s->cap)
        return MOTE_OK;
    size_t cap = s->cap ? s->cap : 256;
    while (cap < need)
        cap *= 2;
#define GROW(f)                                                                                   \
    do {                                                                                          \
        void *p_ = realloc(s->f, cap * sizeof *s->f);                                             \
        if (!p_)                                                                                  \
            return mote_fail(err, MOTE_ENOMEM, "separator: out of memory for %zu particles", cap); \
        s->f = p_;                                                                                \
    } while (0)
    GROW(x);
    GROW(y);
    GROW(z);
    GROW(vx);
    GROW(vy);
    GROW(vz);
    GROW(d);
    GROW(m);
    GROW(im);
    GROW(s);
    GROW(id);
    GROW(fx);
    GROW(fy);
    GROW(fz);
#undef GROW
    s->cap = cap;
    return s->w ? sep_rot_reserve(s, err) : MOTE_OK; /* (the rotation's, with hertz) */
}

/* A new particle i at rest in rotation, its wall springs zero. */
static void rot_zero(mote_sep_system *s, size_t i)
{
    if (!s->w)
        return;
    memset(s->w + 3 * i, 0, 3 * sizeof *s->w);
    memset(s->tq + 3 * i, 0, 3 * sizeof *s->tq);
    memset(s->wh + 9 * i, 0, 9 * sizeof *s->wh);
    if (s->mh)
        memset(s->mh + 4 * SEP_MESH_SLOTS * i, 0, 4 * SEP_MESH_SLOTS * sizeof *s->mh);
}

int sep_append(mote_sep_system *s, int k, uint64_t id, const double v[11], mote_err *err)
{
    if (grow(s, s->n + 1, err))
        return err->code;
    const size_t i = s->n++;
    s->mods++;
    s->s[i] = k;
    s->id[i] = id;
    s->d[i] = v[0];
    s->m[i] = v[1];
    s->im[i] = 1 / v[1];
    s->x[i] = v[2];
    s->y[i] = v[3];
    s->z[i] = v[4];
    s->vx[i] = v[5];
    s->vy[i] = v[6];
    s->vz[i] = v[7];
    s->fx[i] = v[8];
    s->fy[i] = v[9];
    s->fz[i] = v[10];
    rot_zero(s, i);
    return MOTE_OK;
}

static int place(mote_sep_system *s, int k, double d, mote_err *err);

/* Draw a particle of species k (its size first) and place it; when it cannot be placed it
 * waits in the backlog. *mass: its mass. */
static int add_particle(mote_sep_system *s, int k, int fifo, double *mass, mote_err *err)
{
    const double d = mote_sep_dist_sample(&s->sp[k].dist, mote_rng_uniform(&s->rng));
    *mass = s->parcel * s->sp[k].rho * SEP_PI * d * d * d / 6; /* (the mass it stands for) */
    /* the feed is first in, first out: behind a backlog a new particle waits without trying
     * (a batch tries each) */
    const int rc = fifo && s->nback ? 0 : place(s, k, d, err);
    if (rc == 0) { /* the backlog */
        if (s->nback == s->back_cap) {
            const size_t cap = s->back_cap ? 2 * s->back_cap : 64;
            int *bs = realloc(s->back_s, cap * sizeof *bs);
            if (bs)
                s->back_s = bs;
            double *bd = realloc(s->back_d, cap * sizeof *bd);
            if (bd)
                s->back_d = bd;
            if (!bs || !bd) {
                mote_fail(err, MOTE_ENOMEM, "separator: out of memory for the backlog");
                return -1;
            }
            s->back_cap = cap;
        }
        if (s->nback >= 1000000) {
            mote_fail(err, MOTE_ERUNTIME, "separator: the feed outruns its band: a million "
                      "particles wait to be placed at t = %g s (lower the rate or widen the band, "
                      "feed hf= and feed_window)", s->t);
            return -1;
        }
        s->back_s[s->nback] = k;
        s->back_d[s->nback++] = d;
    }
    return rc < 0 ? -1 : 1;
}

/* Place a particle of species k and diameter d in the feed zone: up to 100 tries, each clear
 * of the walls and (DEM) of the other particles. 1 placed, 0 not, -1 error. */
static int place(mote_sep_system *s, int k, double d, mote_err *err)
{
    const double r = 0.5 * d, m = s->sp[k].rho * SEP_PI * d * d * d / 6;
    double dmin, dmax;
    mote_sep_size_range(s, &dmin, &dmax);
    const double hf = s->hf > 0 ? s->hf : 2 * dmax;
    const double x1 = s->fx2 > s->fx1 ? s->fx1 : 0, x2 = s->fx2 > s->fx1 ? s->fx2 : s->W;
    const double y1 = s->fy2 > s->fy1 ? s->fy1 : 0, y2 = s->fy2 > s->fy1 ? s->fy2 : s->D;
    for (int tr = 0; tr < 100; tr++) {
        const double px = x1 + (x2 - x1) * mote_rng_uniform(&s->rng);
        const double py = s->dim == 3 ? y1 + (y2 - y1) * mote_rng_uniform(&s->rng) : 0;
        const double pz = s->zf - 0.5 * hf + hf * mote_rng_uniform(&s->rng);
        /* clear of the side walls, and of a closed end by the radius (an open end only needs the
         * centre inside) */
        const double zlo = s->open_bottom ? 0 : r, zhi = s->open_top ? s->H : s->H - r;
        if (px < r || px > s->W - r || (s->dim == 3 && (py < r || py > s->D - r)) || pz < zlo ||
            pz > zhi || sep_touches_plate(s, px, py, pz, r) ||
            (s->nmesh && sep_mesh_blocks(s, s->t, (const double[3]){px, py, pz}, r)) ||
            (s->dem && sep_overlaps_any(s, px, py, pz, d)))
            continue;
        if (grow(s, s->n + 1, err))
            return -1;
        const size_t i = s->n++;
        s->mods++;
        rot_zero(s, i);
        s->x[i] = px;
        s->y[i] = py;
        s->z[i] = pz;
        s->vx[i] = s->vf[0];
        s->vy[i] = s->dim == 3 ? s->vf[1] : 0;
        s->vz[i] = s->vf[2];
        s->d[i] = d;
        s->m[i] = m;
        s->im[i] = 1 / m;
        s->s[i] = k;
        s->id[i] = s->next_id++;
        s->fx[i] = s->fy[i] = s->fz[i] = 0;
        s->cnt[k].fed++;
        s->cnt[k].m_fed += s->parcel * m;
        if (s->dem && sep_cells_add(s, i, err))
            return -1;
        return 1;
    }
    return 0;
}

int mote_sep_insert(mote_sep_system *s, int sp, uint64_t count, double mass, mote_err *err)
{
    double done = 0, m;
    if (s->dem && sep_cells_build(s, err))
        return err->code;
    for (uint64_t k = 0; count ? k < count : done < mass; k++) {
        const int rc = add_particle(s, sp, 0, &m, err);
        if (rc < 0)
            return err->code;
        done += m;
    }
    return MOTE_OK;
}

/* Retry the backlog, oldest first, until one cannot be placed (the band is full: the rest wait
 * for the next step); those placed leave it. */
static int retry_backlog(mote_sep_system *s, mote_err *err)
{
    size_t b = 0;
    for (; b < s->nback; b++) {
        const int rc = place(s, s->back_s[b], s->back_d[b], err);
        if (rc < 0)
            return err->code;
        if (rc == 0) /* the band is full: the rest wait for the next step */
            break;
    }
    memmove(s->back_s, s->back_s + b, (s->nback - b) * sizeof *s->back_s);
    memmove(s->back_d, s->back_d + b, (s->nback - b) * sizeof *s->back_d);
    s->nback -= b;
    return MOTE_OK;
}

/* The feed of one step: the backlog first, then each species' account keeps its mass share
 * exact (spec 2.5); with contacts, placements are checked through cells built now. */
int sep_feed(mote_sep_system *s, mote_err *err)
{
    if (s->dem && (s->nback || s->rate > 0) && sep_cells_build(s, err))
        return err->code;
    if (s->nback && retry_backlog(s, err))
        return err->code;
    if (s->rate > 0 && s->t > s->t_start) {
        const double te = fmin(s->t, s->t_stop) - s->t_start;
        for (int k = 0; k < s->nsp; k++) {
            int guard = 0;
            while (s->cnt[k].m_gen < s->sp[k].w * s->rate * te && guard++ < 1000000) {
                double m;
                const int rc = add_particle(s, k, 1, &m, err);
                if (rc < 0)
                    return err->code;
                s->cnt[k].m_gen += m;
            }
        }
    }
    return MOTE_OK;
}
