/* main.c: the `mote` program. It only names the models this build knows; everything else (run,
 * check, help) lives in the script layer (src/script). */
#include "mote/charging.h"
#include "mote/hardspheres.h"
#include "mote/mixingbox.h"
#include "mote/nbody.h"
#include "mote/script.h"

static const mote_model *const models[] = {
    &mote_model_hardspheres,
    &mote_model_mixingbox,
    &mote_model_nbody,
    &mote_model_charging,
};

int main(int argc, char **argv)
{
    return mote_script_main(argc, argv, models, sizeof models / sizeof models[0]);
}
