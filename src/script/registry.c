/* registry.c: the models this build knows (mote_models, command.h), in the order `mote help`
 * lists them; the first is the default of a script without a `model` line. A new model adds
 * its line here; nothing else outside its folder names it. */
#include "mote/charging.h"
#include "mote/hardspheres.h"
#include "mote/mixingbox.h"
#include "mote/nbody.h"
#include "mote/separator.h"

const mote_model *const mote_models[] = {
    &mote_model_hardspheres, &mote_model_mixingbox, &mote_model_nbody, &mote_model_charging,
    &mote_model_separator,
};
const size_t mote_nmodels = sizeof mote_models / sizeof mote_models[0];
