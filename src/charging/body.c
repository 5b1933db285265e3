/* body.c: the charging model's spacecraft body (spec 4): a list of triangles with outward normals
 * and areas, each of a closed component (one outer side) or of a two-sided sheet, or the exact
 * analytic sphere; the generated bodies of spec 4.4 (icosphere, UV sphere, box, two cubes); and
 * the derived quantities of spec 4.3 (area with sheets counted twice, area-weighted centre,
 * R_bound, R_eq and the capacitance of the sphere of equal area). */
#include "mote/charging.h"

#include "ch.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void mote_ch_body_free(mote_ch_body *b)
{
    free(b->v);
    free(b->nrm);
    free(b->area);
    free(b->closed);
    free(b->part);
    free(b->part_name);
    memset(b, 0, sizeof *b);
}

static void cross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* Add the triangle (p, q, r), turned so that its normal points away from `inside` when that is
 * given (convex generated bodies); a degenerate triangle is dropped. */
int ch_body_part(mote_ch_body *b, const char *name, mote_err *err)
{
    for (int k = 0; k < b->nparts; k++)
        if (strcmp(b->part_name[k], name) == 0)
            return k;
    if (strlen(name) >= sizeof b->part_name[0])
        return mote_fail(err, MOTE_EINVAL, "body: the part name '%.40s...' is longer than %zu "
                         "characters", name, sizeof b->part_name[0] - 1), -1;
    if (b->nparts == 65535)
        return mote_fail(err, MOTE_EINVAL, "body: too many parts"), -1;
    char(*pn)[MOTE_CH_NAME_LEN] = realloc(b->part_name, (size_t)(b->nparts + 1) * sizeof *pn);
    if (!pn)
        return mote_fail(err, MOTE_ENOMEM, "body: out of memory"), -1;
    b->part_name = pn;
    snprintf(b->part_name[b->nparts], sizeof b->part_name[0], "%s", name);
    return b->nparts++;
}

int ch_add_tri(mote_ch_body *b, const double p[3], const double q[3], const double r[3],
               const double *inside, int closed, int part, mote_err *err)
{
    if (b->ntri == b->cap) {
        if (b->ntri >= MOTE_CH_MAX_TRI)
            return mote_fail(err, MOTE_EINVAL, "body: more than %d triangles", MOTE_CH_MAX_TRI);
        uint32_t cap = b->cap ? 2 * b->cap : 256; /* (never past 2^28: no wrap) */
        double(*v)[3][3] = realloc(b->v, cap * sizeof *v);
        if (v)
            b->v = v;
        double(*n)[3] = realloc(b->nrm, cap * sizeof *n);
        if (n)
            b->nrm = n;
        double *a = realloc(b->area, cap * sizeof *a);
        if (a)
            b->area = a;
        uint8_t *c = realloc(b->closed, cap);
        if (c)
            b->closed = c;
        uint16_t *pt = realloc(b->part, cap * sizeof *pt);
        if (pt)
            b->part = pt;
        if (!v || !n || !a || !c || !pt)
            return mote_fail(err, MOTE_ENOMEM, "body: out of memory (%u triangles)", b->ntri);
        b->cap = cap;
    }
    double e1[3], e2[3], nn[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = q[k] - p[k];
        e2[k] = r[k] - p[k];
    }
    cross(e1, e2, nn);
    double len = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
    if (!(len > 0))
        return MOTE_OK;
    const double *pts[3] = {p, q, r};
    if (inside) {
        double d = 0;
        for (int k = 0; k < 3; k++)
            d += nn[k] * ((p[k] + q[k] + r[k]) / 3 - inside[k]);
        if (d < 0) { /* reverse the winding */
            pts[1] = r;
            pts[2] = q;
            for (int k = 0; k < 3; k++)
                nn[k] = -nn[k];
        }
    }
    uint32_t i = b->ntri++;
    for (int j = 0; j < 3; j++)
        memcpy(b->v[i][j], pts[j], sizeof b->v[i][j]);
    for (int k = 0; k < 3; k++)
        b->nrm[i][k] = nn[k] / len;
    b->area[i] = 0.5 * len;
    b->closed[i] = (uint8_t)closed;
    b->part[i] = (uint16_t)part;
    return MOTE_OK;
}

int mote_ch_body_sphere(mote_ch_body *b, double r, mote_err *err)
{
    if (!(r > 0))
        return mote_fail(err, MOTE_EINVAL, "body sphere: radius must be > 0");
    if (b->ntri || b->sphere)
        return mote_fail(err, MOTE_EINVAL, "body sphere: the exact sphere is a body on its own "
                         "(no other parts)");
    b->sphere = 1;
    b->sphere_r = r;
    memset(b->sphere_c, 0, sizeof b->sphere_c);
    return MOTE_OK;
}

static int no_sphere(const mote_ch_body *b, const char *what, mote_err *err)
{
    return b->sphere ? mote_fail(err, MOTE_EINVAL, "body %s: the body is the exact sphere, which "
                                 "takes no other parts", what)
                     : MOTE_OK;
}

static void unit_scale(double p[3], double r)
{
    double n = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int k = 0; k < 3; k++)
        p[k] *= r / n;
}

/* One icosahedron face subdivided `level` times, every vertex on the sphere of radius r. */
static int ico_face(mote_ch_body *b, const double a[3], const double c[3], const double d[3],
                    int level, double r, int part, mote_err *err)
{
    static const double origin[3] = {0, 0, 0};
    if (level == 0)
        return ch_add_tri(b, a, c, d, origin, 1, part, err);
    double ac[3], cd[3], da[3];
    for (int k = 0; k < 3; k++) {
        ac[k] = 0.5 * (a[k] + c[k]);
        cd[k] = 0.5 * (c[k] + d[k]);
        da[k] = 0.5 * (d[k] + a[k]);
    }
    unit_scale(ac, r);
    unit_scale(cd, r);
    unit_scale(da, r);
    int rc = ico_face(b, a, ac, da, level - 1, r, part, err);
    if (!rc)
        rc = ico_face(b, ac, c, cd, level - 1, r, part, err);
    if (!rc)
        rc = ico_face(b, da, cd, d, level - 1, r, part, err);
    if (!rc)
        rc = ico_face(b, ac, cd, da, level - 1, r, part, err);
    return rc;
}

int mote_ch_body_icosphere(mote_ch_body *b, double r, int level, mote_err *err)
{
    int rc = no_sphere(b, "icosphere", err);
    if (rc)
        return rc;
    if (!(r > 0) || level < 0 || level > 8)
        return mote_fail(err, MOTE_EINVAL, "body icosphere: need radius > 0 and 0 <= level <= 8");
    const double f = (1 + sqrt(5.0)) / 2; /* the icosahedron (0, +-1, +-f) and its cyclic turns */
    double v[12][3] = {{-1, f, 0}, {1, f, 0},  {-1, -f, 0}, {1, -f, 0}, {0, -1, f}, {0, 1, f},
                       {0, -1, -f}, {0, 1, -f}, {f, 0, -1}, {f, 0, 1},  {-f, 0, -1}, {-f, 0, 1}};
    static const int F[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (int i = 0; i < 12; i++)
        unit_scale(v[i], r);
    const int part = ch_body_part(b, "icosphere", err);
    if (part < 0)
        return err->code;
    for (int k = 0; k < 20 && !rc; k++)
        rc = ico_face(b, v[F[k][0]], v[F[k][1]], v[F[k][2]], level, r, part, err);
    return rc;
}

int mote_ch_body_uvsphere(mote_ch_body *b, double r, int nlon, int nlat, int halves,
                          mote_err *err)
{
    int rc = no_sphere(b, "uvsphere", err);
    if (rc)
        return rc;
    if (!(r > 0) || nlon < 3 || nlat < 2)
        return mote_fail(err, MOTE_EINVAL, "body uvsphere: need radius > 0, nlon >= 3, nlat >= 2");
    if (halves && nlat % 2)
        return mote_fail(err, MOTE_EINVAL, "body uvsphere: parts=hemispheres needs an even "
                         "nlat (the equator is a ring), found %d", nlat);
    static const double origin[3] = {0, 0, 0};
    const int part = ch_body_part(b, halves ? "north" : "uvsphere", err);
    const int south = part < 0 || !halves ? part : ch_body_part(b, "south", err);
    if (south < 0)
        return err->code;
    /* rings at polar angles pi j / nlat, j = 0 (north pole) ... nlat (south pole) */
    for (int j = 0; j < nlat && !rc; j++)
        for (int i = 0; i < nlon && !rc; i++) {
            double p[4][3];
            for (int c = 0; c < 4; c++) {
                /* the seam's and the poles' vertices computed once, so that the triangles
                 * sharing them share them bit for bit (sin(2 pi) and sin(pi) are not 0) */
                const int jj = j + (c >= 2), ii = (i + (c == 1 || c == 2)) % nlon;
                const double th = MOTE_CH_PI * jj / nlat, ph = 2 * MOTE_CH_PI * ii / nlon;
                const double st = jj == 0 || jj == nlat ? 0 : sin(th);
                p[c][0] = r * st * cos(ph);
                p[c][1] = r * st * sin(ph);
                p[c][2] = jj == 0 ? r : jj == nlat ? -r : r * cos(th);
            }
            const int pj = 2 * j < nlat ? part : south;
            if (j > 0) /* (the cap at the north pole has one triangle per column) */
                rc = ch_add_tri(b, p[0], p[1], p[2], origin, 1, pj, err);
            if (!rc && j < nlat - 1)
                rc = ch_add_tri(b, p[0], p[2], p[3], origin, 1, pj, err);
        }
    return rc;
}

static int box_part(mote_ch_body *b, const double size[3], const double centre[3], int subdiv,
                    const char *name, mote_err *err)
{
    int rc = no_sphere(b, "box", err);
    if (rc)
        return rc;
    if (!(size[0] > 0 && size[1] > 0 && size[2] > 0) || subdiv < 1 || subdiv > 1000)
        return mote_fail(err, MOTE_EINVAL, "body box: need sizes > 0 and 1 <= subdiv <= 1000");
    const int part = ch_body_part(b, name, err);
    if (part < 0)
        return err->code;
    for (int ax = 0; ax < 3 && !rc; ax++) /* the faces normal to axis ax, at -s/2 and +s/2 */
        for (int sgn = -1; sgn <= 1 && !rc; sgn += 2) {
            const int u = (ax + 1) % 3, w = (ax + 2) % 3;
            for (int i = 0; i < subdiv && !rc; i++)
                for (int j = 0; j < subdiv && !rc; j++) {
                    double p[4][3];
                    for (int c = 0; c < 4; c++) {
                        const int ii = i + (c == 1 || c == 2), jj = j + (c >= 2);
                        p[c][ax] = centre[ax] + sgn * 0.5 * size[ax];
                        p[c][u] = centre[u] + size[u] * ((double)ii / subdiv - 0.5);
                        p[c][w] = centre[w] + size[w] * ((double)jj / subdiv - 0.5);
                    }
                    rc = ch_add_tri(b, p[0], p[1], p[2], centre, 1, part, err);
                    if (!rc)
                        rc = ch_add_tri(b, p[0], p[2], p[3], centre, 1, part, err);
                }
        }
    return rc;
}

int mote_ch_body_box(mote_ch_body *b, const double size[3], const double centre[3], int subdiv,
                     mote_err *err)
{
    return box_part(b, size, centre, subdiv, "box", err);
}

int mote_ch_body_twocubes(mote_ch_body *b, double side, double gap, mote_err *err)
{
    if (!(side > 0) || !(gap >= 0))
        return mote_fail(err, MOTE_EINVAL, "body twocubes: need side > 0 and gap >= 0");
    const double s[3] = {side, side, side};
    const double c1[3] = {-0.5 * (gap + side), 0, 0}, c2[3] = {0.5 * (gap + side), 0, 0};
    int rc = box_part(b, s, c1, 1, "cube1", err);
    return rc ? rc : box_part(b, s, c2, 1, "cube2", err);
}

void mote_ch_body_geometry(const mote_ch_body *b, mote_ch_geometry *g)
{
    memset(g, 0, sizeof *g);
    if (b->sphere) {
        g->area = 4 * MOTE_CH_PI * b->sphere_r * b->sphere_r;
        memcpy(g->centre, b->sphere_c, sizeof g->centre);
        g->r_bound = b->sphere_r;
    } else {
        double wsum = 0;
        for (uint32_t i = 0; i < b->ntri; i++) {
            const double a = b->area[i] * (b->closed[i] ? 1 : 2);
            g->area += a;
            wsum += b->area[i];
            for (int k = 0; k < 3; k++)
                g->centre[k] += b->area[i] * (b->v[i][0][k] + b->v[i][1][k] + b->v[i][2][k]) / 3;
        }
        for (int k = 0; k < 3; k++)
            g->centre[k] = wsum > 0 ? g->centre[k] / wsum : 0;
        for (uint32_t i = 0; i < b->ntri; i++)
            for (int j = 0; j < 3; j++) {
                double d2 = 0;
                for (int k = 0; k < 3; k++)
                    d2 += (b->v[i][j][k] - g->centre[k]) * (b->v[i][j][k] - g->centre[k]);
                g->r_bound = fmax(g->r_bound, sqrt(d2));
            }
    }
    g->r_eq = sqrt(g->area / (4 * MOTE_CH_PI));
    g->c_max = 4 * MOTE_CH_PI * MOTE_CH_EPS0 * g->r_bound;
    if (b->sphere) {
        g->c_min = g->capacitance = g->c_max;
        g->r_field = g->r_bound;
        g->volume = 4 * MOTE_CH_PI / 3 * b->sphere_r * b->sphere_r * b->sphere_r;
        return;
    }
    double vol = 0, r_in = 0;
    for (uint32_t i = 0; i < b->ntri; i++) {
        double(*t)[3] = b->v[i];
        double per = 0;
        for (int j = 0; j < 3; j++) {
            const double *p = t[j], *q = t[(j + 1) % 3];
            per += sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                        (q[2] - p[2]) * (q[2] - p[2]));
        }
        if (per > 0)
            r_in = fmax(r_in, 2 * b->area[i] / per);
        if (b->closed[i]) { /* (the divergence theorem, about the centre) */
            double a[3], c[3], d[3];
            for (int k = 0; k < 3; k++) {
                a[k] = t[0][k] - g->centre[k];
                c[k] = t[1][k] - g->centre[k];
                d[k] = t[2][k] - g->centre[k];
            }
            vol += (a[0] * (c[1] * d[2] - c[2] * d[1]) - a[1] * (c[0] * d[2] - c[2] * d[0]) +
                    a[2] * (c[0] * d[1] - c[1] * d[0])) / 6;
        }
    }
    g->volume = fabs(vol);
    g->c_min = fmax(8 * MOTE_CH_EPS0 * r_in,
                    4 * MOTE_CH_PI * MOTE_CH_EPS0 * cbrt(3 * g->volume / (4 * MOTE_CH_PI)));
    g->c_min = fmin(g->c_min, g->c_max); /* (rounding) */
    /* auto: the sphere of equal area, held within the bounds (a thin or concave body's area
     * makes R_eq larger than the ball that holds it) */
    const double c_eq = 4 * MOTE_CH_PI * MOTE_CH_EPS0 * g->r_eq;
    g->capacitance = b->capacitance > 0 ? b->capacitance : fmax(g->c_min, fmin(c_eq, g->c_max));
    g->r_field = g->capacitance / (4 * MOTE_CH_PI * MOTE_CH_EPS0);
}

/* A mesh file's triangles (the core's reader and repairs, mesh.h) into the body, its parts by
 * name, made when a kept triangle needs them. */
int mote_ch_body_load(mote_ch_body *b, const char *path, const mote_ch_load_opts *o,
                      mote_ch_load_report *rep, mote_err *err)
{
    memset(rep, 0, sizeof *rep);
    if (b->sphere)
        return mote_fail(err, MOTE_EINVAL, "body load: the body is the exact sphere, which takes "
                         "no other parts");
    mote_mesh m = {0};
    int rc = mote_mesh_load(&m, path, o, rep, err);
    if (rc)
        return rc;
    int *pmap = malloc((size_t)(m.nnames ? m.nnames : 1) * sizeof *pmap);
    if (!pmap)
        rc = mote_fail(err, MOTE_ENOMEM, "mesh: out of memory");
    for (int k = 0; !rc && k < m.nnames; k++)
        pmap[k] = -1;
    for (size_t k = 0; !rc && k < m.nt; k++) {
        int *pm = &pmap[m.part[k]];
        if (*pm < 0 && (*pm = ch_body_part(b, m.names[m.part[k]], err)) < 0) {
            rc = err->code;
            break;
        }
        const uint32_t before = b->ntri;
        rc = ch_add_tri(b, m.v[m.t[k][0]], m.v[m.t[k][1]], m.v[m.t[k][2]], NULL, m.closed[k], *pm,
                        err);
        if (!rc && b->ntri == before) { /* (too thin for the body's own test) */
            rep->degenerate++;
            rep->flipped -= m.flipped[k];
        }
    }
    free(pmap);
    mote_mesh_free(&m);
    return rc;
}
