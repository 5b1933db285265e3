/* integrators.c: nbody's integrators as plug-ins, in REBOUND's manner: each is a table of its
 * name, its check (the settings, and the scratch sized), how it advances (one step of at most
 * the time left, or a whole synchronised run of the map), the room its force tree needs, and
 * what it offers the outputs (the state between step ends). mote_nb_integrate runs whichever
 * nb->integrator names; the snapshot files name it by its name. */
#include "mote/nbody.h"

#include <string.h>

#include "nb.h"

static int galactica_check(mote_nb *nb, mote_err *err) { return nb_galactica_check(nb, err); }
static int wh_check(mote_nb *nb, mote_err *err) { return nb_wh_check(nb, err); }
static int galactica_tree(const mote_nb *nb) { return 4; } /* the scheme's four blocks */
static int taylor_tree(const mote_nb *nb) { return nb->taylor_order + 1; } /* every order */
static int wh_tree(const mote_nb *nb) { return 4; }

static const nb_integrator GALACTICA = {
    .name = "galactica", .check = galactica_check, .step = nb_galactica_step,
    .tree_blocks = galactica_tree, .order_max = 6};
static const nb_integrator TAYLOR = {
    .name = "taylor", .check = nb_taylor_check, .step = nb_taylor_step,
    .tree_blocks = taylor_tree, .dense = 1, .order_max = MOTE_NB_TAYLOR_MAX};
static const nb_integrator WH = {
    .name = "wh", .check = wh_check, .run = nb_wh_integrate, .tree_blocks = wh_tree,
    .synchronised = 1};

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
