/* script.c: a mote script run from C: parsed, checked as a whole, then run, with its output on
 * standard output and any error as the message `mote run` prints (FILE:LINE:COLUMN: ...).
 *
 *     cc script.c $(pkg-config --cflags --libs mote) -o script && ./script
 *
 * The script sweeps two densities of hard spheres, each from a fresh system; exit status 0 when
 * it ran. */
#include <mote/command.h>
#include <mote/script.h>

#include <stdio.h>
#include <string.h>

static const char text[] = "model hard-spheres\n"
                           "for eta in 0.2 0.3\n"
                           "    reset\n"
                           "    bulk 108 ${eta}\n"
                           "    step 50\n"
                           "    pressure 50 p_${eta}.dat\n"
                           "end\n";

int main(void)
{
    mote_script *s;
    mote_err err = {0};
    if (mote_script_parse(&s, "sweep.mote", text, strlen(text), mote_models, mote_nmodels,
                          &err) != MOTE_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return 1;
    }
    int rc = mote_script_validate(s, &err);
    if (rc == MOTE_OK)
        rc = mote_script_execute(s, &err);
    if (rc != MOTE_OK)
        fprintf(stderr, "%s\n", err.msg);
    mote_script_free(s);
    return rc == MOTE_OK ? 0 : 1;
}
