/* ring.c: the gravity ring of the N-body spec (30 bodies on a circle about a central mass, whose
 * exact motion is known) integrated with Galactica's order-6 scheme through libmote's C API, and
 * its error against the exact solution printed and checked.
 *
 *     cc ring.c $(pkg-config --cflags --libs mote) -o ring && ./ring
 *
 * Exit status 0 when the largest relative position error after one period (1000 steps of
 * 1e-5) is at most 1e-10 (the spec's bound for this step), 1 otherwise. */
#include <mote/nbody.h>

#include <stdio.h>

int main(void)
{
    mote_nb nb;
    mote_nb_ring ring;
    mote_err err = {0};
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    mote_nb_ring_defaults(&ring, MOTE_NB_GRAVITY);
    if (mote_nb_ring_build(&nb, &ring, &err) != MOTE_OK) {
        fprintf(stderr, "ring: %s\n", err.msg);
        return 1;
    }
    nb.dt = 1e-5; /* dimensionless time; the ring's period is about 0.01 */
    nb.order = 6; /* Galactica's scheme of order 6 */
    if (mote_nb_galactica(&nb, 1000, &err) != MOTE_OK) {
        fprintf(stderr, "ring: %s\n", err.msg);
        mote_nb_free(&nb);
        return 1;
    }
    mote_real plane;
    double error = (double)mote_nb_ring_error(&nb, &ring, &plane);
    printf("ring: %u bodies, T = %.6g after %d steps: largest relative error %.3e, out of "
           "plane %.3e\n", nb.n, (double)nb.T, 1000, error, (double)plane);
    mote_nb_free(&nb);
    return error <= 1e-10 ? 0 : 1;
}
