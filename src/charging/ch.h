/* ch.h: internal to the charging model: what its files share. */
#ifndef MOTE_CH_INTERNAL_H
#define MOTE_CH_INTERNAL_H

#include "mote/charging.h"

/* The index of the part called name, added when new; -1 with err when out of room. */
int ch_body_part(mote_ch_body *b, const char *name, mote_err *err);
/* Add the triangle (p, q, r) of part `part`, turned so that its normal points away from `inside`
 * when that is given; a triangle of zero area is dropped. */
int ch_add_tri(mote_ch_body *b, const double p[3], const double q[3], const double r[3],
               const double *inside, int closed, int part, mote_err *err);

#endif
