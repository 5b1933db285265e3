/* integrators.c: nbody's integrators as plug-ins, in REBOUND's manner: each is a table of its
 * name, its check (the settings, and the scratch sized), how it advances (one step of at most
 * the time left, or a whole synchronised run of the map), the room its force tree needs, and
 * what it offers the outputs (the state between step ends), the defaults it sets when chosen,
 * its settings in the outputs' headers, and its own lines of the state file with their checks.
 * mote_nb_integrate runs whichever nb->integrator names; the snapshot files name it by its
 * name. (A synchronisation is not a separate hook: the map's `run` ends synchronised at every
 * stop the run loop gives it, its live Jacobi state kept beside the bodies for the next run.) */
#include "mote/nbody.h"

#include <stdio.h>
#include <string.h>

#include "nb.h"

static int galactica_check(mote_nb *nb, mote_err *err) { return nb_galactica_check(nb, err); }
static int wh_check(mote_nb *nb, mote_err *err) { return nb_wh_check(nb, err); }
static int galactica_tree(const mote_nb *nb) { return 4; } /* the scheme's four blocks */
static int taylor_tree(const mote_nb *nb) { return nb->taylor_order + 1; } /* every order */
static int wh_tree(const mote_nb *nb) { return 4; }

/* The defaults each one sets when chosen: the step rule's blocks afresh and the tolerance of
 * its kind (Galactica's of spec 7.4, Taylor's of issue 37), the fixed or adaptive step by the
 * options; the map's corrector of order 17 and a fixed step. */
static void step_rule_afresh(mote_nb *nb)
{
    nb->doubling = 0;
    nb->dt_max = 0;
    nb->dbl_have = 0;
    nb->dbl_count = 0;
    nb->dbl_sum = 0;
    nb->dbl_mean = -1;
}
static void galactica_chosen(mote_nb *nb)
{
    step_rule_afresh(nb);
    nb->tol = MOTE_REAL_TOL;
}
static void taylor_chosen(mote_nb *nb)
{
    step_rule_afresh(nb);
    nb->tol = MOTE_NB_TAYLOR_TOL;
}
static void wh_chosen(mote_nb *nb)
{
    nb->wh_corrector = 17;
    nb->adaptive = 0;
}

static void galactica_header(FILE *f, const mote_nb *nb)
{
    char b[MOTE_REAL_BUF];
    fprintf(f, "# integrator = galactica\n# order = %d\n# dt = %s\n", nb->order,
            mote_real_str(nb->dt, b));
}
static void taylor_header(FILE *f, const mote_nb *nb)
{
    char b[2][MOTE_REAL_BUF];
    fprintf(f, "# integrator = taylor\n# order = %d\n", nb->taylor_order);
    if (nb->adaptive)
        fprintf(f, "# tol = %s\n# safety = %s\n# norm = %s\n", mote_real_str(nb->tol, b[0]),
                mote_real_str(nb->safety, b[1]),
                nb->adaptive == MOTE_NB_NORM_GLOBAL ? "global" : "nearest");
    else
        fprintf(f, "# dt = %s\n", mote_real_str(nb->dt, b[0]));
}
static void wh_header(FILE *f, const mote_nb *nb)
{
    char b[MOTE_REAL_BUF];
    fprintf(f, "# integrator = wh\n# corrector = %d\n# dt = %s\n", nb->wh_corrector,
            mote_real_str(nb->dt, b));
}

/* Their own lines of the state file (from version 4; the common lines, state.c, hold the step,
 * its controller and the scheme). Galactica: the scheme's order, and its literal step rule
 * (step=doubling, spec 7.4) with that rule's running blocks. */
static const mote_sf_field GALACTICA_FIELDS[] = {
    NB_SF_I("galactica", "order", order, 2, 6),
    NB_SF_I("doubling", "on", doubling, 0, 1), NB_SF_I(NULL, "have", dbl_have, 0, 1),
    NB_SF_I(NULL, "count", dbl_count, 0, 4), NB_SF_R(NULL, "dt_max", dt_max),
    NB_SF_R(NULL, "dMz_prev", dbl_prev), NB_SF_R(NULL, "sum", dbl_sum),
    NB_SF_R(NULL, "mean", dbl_mean),
};
static int galactica_bad(const mote_nb *nb, const char *key, char *why, size_t size)
{
    if (strcmp(key, "doubling") != 0 ||
        (nb->dt_max >= 0 && nb->dbl_sum >= 0 && nb->dbl_mean >= -2))
        return 0;
    snprintf(why, size, "doubling: need dt_max >= 0, sum >= 0, mean >= -2");
    return 1;
}
/* Taylor: its order and how it keeps the pairs' coefficients (the adaptive step's settings are
 * the common step line's) */
static const mote_sf_field TAYLOR_FIELDS[] = {
    NB_SF_I("taylor", "order", taylor_order, 2, MOTE_NB_TAYLOR_MAX),
    NB_SF_I(NULL, "memory", taylor_memory, 0, 2),
};
static int taylor_bad(const mote_nb *nb, const char *key, char *why, size_t size) { return 0; }
/* the map: its corrector, and whether a map follows the bodies (live) with the step and
 * corrector it runs with (its lines per body follow the bodies', state.c) */
static const mote_sf_field WH_FIELDS[] = {
    NB_SF_I("wh", "corrector", wh_corrector, 0, 17), NB_SF_I(NULL, "live", wh_live, 0, 1),
    NB_SF_R(NULL, "h", wh_h), NB_SF_I(NULL, "k", wh_k, 0, 17),
};
static int wh_bad(const mote_nb *nb, const char *key, char *why, size_t size)
{
    if (nb->wh_h >= 0)
        return 0;
    snprintf(why, size, "wh: need h >= 0 (found %g)", (double)nb->wh_h);
    return 1;
}
#define FIELDS(T) .fields = T, .nfields = sizeof T / sizeof T[0]

static const nb_integrator GALACTICA = {
    .name = "galactica", .check = galactica_check, .step = nb_galactica_step,
    .tree_blocks = galactica_tree, .chosen = galactica_chosen, .header = galactica_header,
    .order_max = 6, FIELDS(GALACTICA_FIELDS), .state_bad = galactica_bad};
static const nb_integrator TAYLOR = {
    .name = "taylor", .check = nb_taylor_check, .step = nb_taylor_step,
    .tree_blocks = taylor_tree, .chosen = taylor_chosen, .header = taylor_header, .dense = 1,
    .order_max = MOTE_NB_TAYLOR_MAX, FIELDS(TAYLOR_FIELDS), .state_bad = taylor_bad};
static const nb_integrator WH = {
    .name = "wh", .check = wh_check, .run = nb_wh_integrate, .tree_blocks = wh_tree,
    .chosen = wh_chosen, .header = wh_header, .synchronised = 1,
    FIELDS(WH_FIELDS), .state_bad = wh_bad};

/* by their numbers (MOTE_NB_GALACTICA, MOTE_NB_TAYLOR, MOTE_NB_WH) */
static const nb_integrator *const ALL[NB_INTEGRATORS] = {&GALACTICA, &TAYLOR, &WH};

const nb_integrator *nb_integrator_of(int id)
{
    return id >= 0 && (size_t)id < sizeof ALL / sizeof ALL[0] ? ALL[id] : &GALACTICA;
}

int nb_integrator_named(const char *name)
{
    for (size_t k = 0; k < sizeof ALL / sizeof ALL[0]; k++)
        if (strcmp(ALL[k]->name, name) == 0)
            return (int)k;
    return -1;
}
