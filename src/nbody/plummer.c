/* plummer.c: a Plummer sphere of n equal masses (total mass 1, Plummer radius 1, G = 1 units),
 * drawn as Aarseth, Henon & Wielen (1974) describe: the radius from the cumulative mass (cut at
 * 30), the speed by rejection from q^2 (1 - q^2)^(7/2) times the escape speed, isotropic
 * directions; then the barycentric frame. The test problem of spec 6.2 and 11 (T18, T19) and of
 * the tree benchmark. */
#include <math.h>

#include "nb.h"

int mote_nb_plummer(mote_nb *nb, uint32_t n, uint64_t seed, mote_err *err)
{
    if (nb->n)
        return mote_fail(err, MOTE_EINVAL, "generate plummer: the system already has %u bodies",
                         nb->n);
    if (nb->kind != MOTE_NB_GRAVITY)
        return mote_fail(err, MOTE_EINVAL, "generate plummer: a Plummer sphere is a gravity "
                                           "system");
    mote_rng rng;
    mote_rng_seed(&rng, seed);
    for (uint32_t i = 0; i < n; i++) {
        double rr, q, g;
        do
            rr = 1 / sqrt(pow(mote_rng_uniform(&rng) * 0.999 + 1e-9, -2.0 / 3) - 1);
        while (rr > 30);
        do { /* q^2 (1 - q^2)^3.5, whose largest value is below 0.1 */
            q = mote_rng_uniform(&rng);
            g = 0.1 * mote_rng_uniform(&rng);
        } while (g > q * q * pow(1 - q * q, 3.5));
        const double ve = q * sqrt(2.0) * pow(1 + rr * rr, -0.25);
        mote_real x[3], v[3];
        for (int pass = 0; pass < 2; pass++) { /* isotropic directions */
            const double z = 2 * mote_rng_uniform(&rng) - 1,
                         ph = 2 * MOTE_PI * mote_rng_uniform(&rng);
            const double sxy = sqrt(1 - z * z), len = pass ? ve : rr;
            mote_real *o = pass ? v : x;
            o[0] = (mote_real)(len * sxy * cos(ph));
            o[1] = (mote_real)(len * sxy * sin(ph));
            o[2] = (mote_real)(len * z);
        }
        int rc = mote_nb_add(nb, (mote_real)1 / n, 0, x, v, 0, err);
        if (rc) {
            mote_nb_free(nb);
            return rc;
        }
    }
    mote_nb_barycentric(nb, NULL, NULL);
    return MOTE_OK;
}
