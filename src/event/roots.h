/* roots.h: internal to the event engine: the earliest time a polynomial distance function
 * crosses zero, for event prediction under a uniform field (parabolic flights). */
#ifndef MOTE_EVENT_ROOTS_H
#define MOTE_EVENT_ROOTS_H

/* The smallest t in [0, tmax] at which the polynomial c[0] + c[1] t + ... + c[deg] t^deg
 * (deg <= 4) goes from positive to <= 0, or INFINITY when it stays positive on [0, tmax].
 * If p(0) <= 0 the answer is 0. The root is bracketed and refined by bisection to within a few
 * ulps of t, so it is never later than the true crossing by more than that. Works by isolating
 * monotone intervals between the real roots of the derivative (recursively). */
double mote_first_root(const double *c, int deg, double tmax);

/* The smallest t in [0, tmax] at which the polynomial goes from positive to <= 0, wherever it
 * starts: one that starts at or below 0 must first rise above it (a centre behind a face's
 * plane, or beside the face, that can still come down onto it). INFINITY when there is none. */
double mote_first_entry(const double *c, int deg, double tmax);

#endif
