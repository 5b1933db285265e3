/* arrays.c: the bodies as arrays for other programs (mote_model.arrays; the Python package's
 * NumPy arrays): positions, velocities, masses and charges in the model's dimensionless units.
 * In the double build they are views of the model's own arrays; in the long double and quad
 * builds, copies in double. set_array replaces positions, velocities or masses after checking
 * them, and makes the next step a fresh start. */
#include "mote/nbody.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "model.h"

static int one(mote_array *a, const char *name, mote_real *v, size_t n, size_t cols,
               const char *unit)
{
    *a = (mote_array){.name = name, .type = 'd', .rows = n, .cols = cols, .unit = unit};
    if (sizeof(mote_real) == sizeof(double)) { /* the model's own numbers */
        a->data = v;
        a->row_stride = (long)(cols * sizeof(double));
        a->col_stride = sizeof(double);
        return 0;
    }
    double *c = malloc((n ? n : 1) * cols * sizeof *c);
    if (!c)
        return -1;
    for (size_t i = 0; i < n * cols; i++)
        c[i] = (double)v[i];
    a->data = c;
    a->owned = 1;
    a->row_stride = (long)(cols * sizeof *c);
    a->col_stride = sizeof *c;
    return 0;
}

int nb_model_arrays(void *vm, mote_array *out, int cap)
{
    mote_nb *nb = &((nb_model *)vm)->nb;
    const char *u = "dimensionless (see units)";
    struct {
        const char *name;
        mote_real *v;
        size_t cols;
    } t[4] = {{"positions", nb->x, 3}, {"velocities", nb->v, 3}, {"masses", nb->m, 1},
              {"charges", nb->q, 1}};
    int k = 0;
    for (; k < 4 && k < cap; k++)
        if (one(&out[k], t[k].name, t[k].v, nb->n, t[k].cols, u)) {
            while (k-- > 0)
                if (out[k].owned)
                    free(out[k].data);
            return -1;
        }
    return k;
}

int nb_model_set_array(void *vm, const char *name, const double *v, size_t rows, size_t cols,
                       mote_err *err)
{
    mote_nb *nb = &((nb_model *)vm)->nb;
    const int pos = !strcmp(name, "positions"), vel = !strcmp(name, "velocities"),
              mass = !strcmp(name, "masses");
    if (!pos && !vel && !mass)
        return mote_fail(err, MOTE_EINVAL, "set %s: the nbody model sets positions, velocities "
                         "or masses", name);
    const size_t want = mass ? 1 : 3;
    if (rows != nb->n || cols != want)
        return mote_fail(err, MOTE_EINVAL, "set %s: expected %u x %zu numbers (one row per body), "
                         "found %zu x %zu", name, nb->n, want, rows, cols);
    for (size_t i = 0; i < rows * cols; i++)
        if (!(fabs(v[i]) <= NB_VALUE_MAX) || (mass && !(v[i] > 0)))
            return mote_fail(err, MOTE_EINVAL, "set %s: body %zu: %s, found %g", name,
                             i / cols + 1, mass ? "a mass is > 0 and up to 1e100"
                                                : "a finite number up to 1e100 in magnitude "
                                                  "(beyond, its energy would overflow)",
                             v[i]);
    mote_real *dst = pos ? nb->x : vel ? nb->v : nb->m;
    mote_real *comp = pos ? nb->xc : vel ? nb->vc : NULL;
    for (size_t i = 0; i < rows * cols; i++) {
        dst[i] = (mote_real)v[i];
        if (comp)
            comp[i] = 0; /* (a new value: no compensation carried) */
    }
    nb->dtp = 0; /* the next step is a fresh start, and energies are measured from here */
    nb->restart = 1;
    mote_nb_set_reference(nb);
    return MOTE_OK;
}
