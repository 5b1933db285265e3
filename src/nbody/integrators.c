/* integrators.c: nbody's integrators as plug-ins, in REBOUND's manner: each is a table of its
 * name, its check (the settings, and the scratch sized), how it advances (one step of at most
 * the time left, or a whole synchronised run of the map), the room its force tree needs, and
 * what it offers the outputs (the state between step ends), the defaults it sets when chosen
 * and its settings in the outputs' headers. mote_nb_integrate runs whichever
 * nb->integrator names; the snapshot files name it by its name. */
#include "mote/nbody.h"

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

static const nb_integrator GALACTICA = {
    .name = "galactica", .check = galactica_check, .step = nb_galactica_step,
    .tree_blocks = galactica_tree, .chosen = galactica_chosen, .header = galactica_header,
    .order_max = 6};
static const nb_integrator TAYLOR = {
    .name = "taylor", .check = nb_taylor_check, .step = nb_taylor_step,
    .tree_blocks = taylor_tree, .chosen = taylor_chosen, .header = taylor_header, .dense = 1,
    .order_max = MOTE_NB_TAYLOR_MAX};
static const nb_integrator WH = {
    .name = "wh", .check = wh_check, .run = nb_wh_integrate, .tree_blocks = wh_tree,
    .chosen = wh_chosen, .header = wh_header, .synchronised = 1};

/* by their numbers (MOTE_NB_GALACTICA, MOTE_NB_TAYLOR, MOTE_NB_WH) */
static const nb_integrator *const ALL[] = {&GALACTICA, &TAYLOR, &WH};

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
