/* photo.c: photoemission (spec 6.8). A triangle whose outward normal faces the sun (a sheet:
 * the side that does) emits j_ph I A (n . s) f times the escape fraction, f its sunlit fraction:
 * the share of 16 stratified points on it (the centroids of the 16 triangles of its 4 x 4
 * subdivision) from which a shadow ray toward the sun leaves the body unobstructed. No random
 * numbers: the same geometry gives the same currents. */
#include "ch.h"

#include <math.h>

double mote_ch_escape(double U, double kT)
{
    return U > 0 ? (1 + U / kT) * exp(-U / kT) : 1;
}

int mote_ch_sunlit(const mote_ch_body *b, const mote_ch_tracer *t, const double sun[3],
                   double *frac, int *side, int threads)
{
    mote_ch_geometry g;
    mote_ch_body_geometry(b, &g);
    /* above the surface by more than the single-precision rounding of the tracer */
    const double lift = 1e-6 * (g.r_bound + fabs(g.centre[0]) + fabs(g.centre[1]) +
                                fabs(g.centre[2]));
    /* the 16 points in barycentric coordinates (u, v): 10 upward and 6 downward sub-triangles */
    double pu[16], pv[16];
    int np = 0;
    for (int i = 0; i < 4; i++)
        for (int j = 0; i + j < 4; j++) {
            pu[np] = (i + 1.0 / 3) / 4;
            pv[np++] = (j + 1.0 / 3) / 4;
            if (i + j < 3) {
                pu[np] = (i + 2.0 / 3) / 4;
                pv[np++] = (j + 2.0 / 3) / 4;
            }
        }
    const long n = (long)b->ntri;
    const int nt = threads > 1 ? threads : 1;
#pragma omp parallel for num_threads(nt) if (nt > 1) schedule(dynamic, 256)
    for (long i = 0; i < n; i++) {
        const double *nr = b->nrm[i];
        const double c = nr[0] * sun[0] + nr[1] * sun[1] + nr[2] * sun[2];
        int sd = c > 0 ? 0 : 1;
        if (c == 0 || (sd == 1 && b->closed[i])) { /* edge-on, or a closed surface's back */
            frac[i] = 0;
            side[i] = -1;
            continue;
        }
        const double sg = sd ? -1 : 1;
        int lit = 0;
        for (int k = 0; k < 16; k++) {
            double o[3];
            for (int a = 0; a < 3; a++)
                o[a] = b->v[i][0][a] + pu[k] * (b->v[i][1][a] - b->v[i][0][a]) +
                       pv[k] * (b->v[i][2][a] - b->v[i][0][a]) + sg * lift * nr[a];
            lit += !mote_ch_occluded(t, o, sun, 0, INFINITY);
        }
        frac[i] = lit / 16.0;
        side[i] = sd;
    }
    return MOTE_OK;
}
