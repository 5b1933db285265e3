/* test_observe.c: one toolkit (issue 53).
 * - One observer, added once to the context, fires in the long commands of all five models:
 *   they all run through the core's loop (mote_run), which adds the context's observers to the
 *   model's own. A time observer every 1e-3 (each model's time unit) from t = 0: a model that
 *   stops at the observer's times (the event engines, evolve) or catches up after its steps
 *   (nbody) fires it at t = 0 and at every multiple of 1e-3 up to the end.
 * - One vocabulary: a shared output word takes the same schedule and destination options
 *   (every=, dt=, file=, prefix=) in every model that has it, read from the registry's command
 *   tables; where a model lacks one, the reason is written here (and the test fails on any
 *   difference not listed, or a listed one that is gone). */
#include "mote/command.h"
#include "mote/loop.h"
#include "mote/script.h"
#include "mote/statefile.h"
#include "test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    int calls;
    int null_subject;
} probe;

static int probe_fire(void *ctx, void *subject, mote_err *err)
{
    probe *p = ctx;
    p->calls++;
    p->null_subject += subject == NULL;
    return MOTE_OK;
}

/* Run `text` in a session of `model` with the observer o in its context; the calls it saw. */
static int observed(const char *model, const char *text, mote_observer *o, probe *p)
{
    mote_script *s = NULL;
    mote_err err = {0};
    p->calls = p->null_subject = 0;
    o->at->k = 0;
    if (mote_session_open(&s, "observe.mote", model, mote_models, mote_nmodels, &err)) {
        CHECK(0, "%s: %s", model, err.msg);
        return -1;
    }
    mote_context *ctx = mote_script_context(s);
    FILE *null = fopen("/dev/null", "w");
    ctx->out = null;
    ctx->observers = o;
    ctx->nobservers = 1;
    int rc = mote_session_command(s, text, NULL, &err);
    CHECK(rc == MOTE_OK, "%s: %s", model, err.msg);
    mote_session_close(s);
    if (null)
        fclose(null);
    CHECK(p->null_subject == 0, "%s: an observer got no subject", model);
    printf("  %-13s %d calls\n", model, p->calls);
    return p->calls;
}

/* The differences the vocabulary keeps, each with its reason. */
static const struct {
    const char *word, *model, *option, *why;
} EXCEPTIONS[] = {
    {"monitor", "charging", "every", "its time is evolve's, which counts no steps"},
};

static int excepted(const char *word, const char *model, const char *option)
{
    for (size_t k = 0; k < sizeof EXCEPTIONS / sizeof EXCEPTIONS[0]; k++)
        if (!strcmp(EXCEPTIONS[k].word, word) && !strcmp(EXCEPTIONS[k].model, model) &&
            !strcmp(EXCEPTIONS[k].option, option))
            return 1;
    return 0;
}

static const mote_cmd *find_cmd(const mote_model *m, const char *word)
{
    for (size_t k = 0; k < m->ncmds; k++)
        if (!strcmp(m->cmds[k].name, word))
            return &m->cmds[k];
    return NULL;
}

static int has_option(const mote_cmd *c, const char *option)
{
    char keys[MOTE_CMD_OPTIONS_MAX][32];
    const size_t n = mote_cmd_option_keys(c, keys, MOTE_CMD_OPTIONS_MAX);
    for (size_t k = 0; k < n; k++)
        if (!strcmp(keys[k], option))
            return 1;
    return 0;
}

static void test_vocabulary(void)
{
    printf("one vocabulary: the shared words' options in every model that has them\n");
    static const char *const words[] = {"snapshot", "trajectory", "frames", "monitor",
                                        "checkpoint"};
    static const char *const options[] = {"every", "dt", "file", "prefix"};
    for (size_t w = 0; w < sizeof words / sizeof words[0]; w++)
        for (size_t o = 0; o < sizeof options / sizeof options[0]; o++) {
            int anyone = 0;
            for (size_t i = 0; i < mote_nmodels; i++) {
                const mote_cmd *c = find_cmd(mote_models[i], words[w]);
                anyone |= c && has_option(c, options[o]);
            }
            for (size_t i = 0; i < mote_nmodels; i++) {
                const mote_cmd *c = find_cmd(mote_models[i], words[w]);
                if (!c)
                    continue;
                const int has = has_option(c, options[o]);
                const int exc = excepted(words[w], mote_models[i]->name, options[o]);
                CHECK(!anyone || has || exc, "%s: %s has no %s= (another model's has; not a "
                      "listed difference)", mote_models[i]->name, words[w], options[o]);
                CHECK(!(has && exc), "%s: %s now has %s=: the listed difference is gone",
                      mote_models[i]->name, words[w], options[o]);
            }
        }
    for (size_t k = 0; k < sizeof EXCEPTIONS / sizeof EXCEPTIONS[0]; k++) {
        int model = 0;
        for (size_t i = 0; i < mote_nmodels; i++)
            model |= !strcmp(mote_models[i]->name, EXCEPTIONS[k].model) &&
                     find_cmd(mote_models[i], EXCEPTIONS[k].word);
        CHECK(model, "the listed difference %s %s %s= names no command", EXCEPTIONS[k].model,
              EXCEPTIONS[k].word, EXCEPTIONS[k].option);
    }
    /* every output on a schedule stops with WORD_stop, the core's row (the same text in every
     * model: MOTE_CMD_STOP) */
    for (size_t w = 0; w < sizeof words / sizeof words[0]; w++) {
        char stop[64];
        snprintf(stop, sizeof stop, "%s_stop", words[w]);
        const mote_cmd *first = NULL;
        for (size_t i = 0; i < mote_nmodels; i++) {
            const mote_cmd *c = find_cmd(mote_models[i], words[w]);
            if (!c || !(has_option(c, "every") || has_option(c, "dt")))
                continue;
            const mote_cmd *s = find_cmd(mote_models[i], stop);
            CHECK(s != NULL, "%s: %s has a schedule but no %s", mote_models[i]->name, words[w],
                  stop);
            if (!s)
                continue;
            CHECK(s->args && !s->args[0] && s->run, "%s: %s takes no arguments and runs",
                  mote_models[i]->name, stop);
            if (!first)
                first = s;
            CHECK(!strcmp(s->summary, first->summary) && !strcmp(s->help, first->help),
                  "%s: %s says what the others' say", mote_models[i]->name, stop);
        }
    }
    /* the aliases are the earlier words, and every model's shared words are their names */
    static const struct {
        const char *model, *alias, *word;
    } aliases[] = {{"hard-spheres", "dump", "trajectory"},
                   {"mixing-box", "record", "monitor"},
                   {"separator", "balance", "monitor"},
                   {"separator", "snapshots", "snapshot"}};
    for (size_t k = 0; k < sizeof aliases / sizeof aliases[0]; k++)
        for (size_t i = 0; i < mote_nmodels; i++) {
            if (strcmp(mote_models[i]->name, aliases[k].model))
                continue;
            const mote_cmd *c = find_cmd(mote_models[i], aliases[k].word);
            CHECK(c && c->aliases && strstr(c->aliases, aliases[k].alias),
                  "%s: %s is %s's alias", aliases[k].model, aliases[k].alias, aliases[k].word);
            CHECK(!find_cmd(mote_models[i], aliases[k].alias), "%s: %s is a name, not an alias",
                  aliases[k].model, aliases[k].alias);
        }
}

/* The parameter commands bound to the state's descriptors (mote_param): each names a command
 * of the model run by mote_cmd_set (its check may note more for the validation) and a
 * descriptor of the model's state that the setter can write; and every command run by
 * mote_cmd_set is listed. */
static void test_params(void)
{
    printf("parameter commands bound to the state's descriptors\n");
    size_t bound = 0;
    for (size_t i = 0; i < mote_nmodels; i++) {
        const mote_model *m = mote_models[i];
        CHECK(!m->nparams || m->state, "%s: parameters without a state table", m->name);
        mote_context ctx;
        memset(&ctx, 0, sizeof ctx);
        void *inst = m->nparams ? m->create(&ctx, 1) : NULL;
        const mote_sf_field *f = NULL;
        size_t n = 0;
        const void *base = inst && m->state ? m->state(inst, &f, &n) : NULL;
        for (size_t q = 0; q < m->nparams; q++) {
            const mote_cmd *c = find_cmd(m, m->params[q].command);
            CHECK(c && c->run == mote_cmd_set, "%s: %s is bound but not run by mote_cmd_set",
                  m->name, m->params[q].command);
            const size_t k = mote_sf_find(f, n, m->params[q].key);
            CHECK(base && k < n &&
                      (f[k].type == MOTE_SF_DOUBLE || f[k].type == MOTE_SF_INT ||
                       f[k].type == MOTE_SF_ENUM ||
                       (f[k].type == MOTE_SF_CODEC && f[k].codec->size == sizeof(double))),
                  "%s: %s's value '%s' is not a settable descriptor of the state", m->name,
                  m->params[q].command, m->params[q].key);
            bound++;
        }
        for (size_t k = 0; k < m->ncmds; k++) {
            int listed = 0;
            for (size_t q = 0; q < m->nparams; q++)
                listed |= !strcmp(m->params[q].command, m->cmds[k].name);
            CHECK(listed || m->cmds[k].run != mote_cmd_set, "%s: %s runs mote_cmd_set unbound",
                  m->name, m->cmds[k].name);
        }
        if (inst)
            m->destroy(inst);
    }
    CHECK(bound >= 21, "only %zu parameter commands are bound", bound);
}

int main(void)
{
    test_vocabulary();
    test_params();
    printf("one observer in the context fires in all five models\n");
    probe p = {0, 0};
    mote_schedule every_ms = {0, 1e-3, 0};
    mote_observer o = {.at = &every_ms, .ctx = &p, .fire = probe_fire};
    /* hard spheres: the event engine stops at each time (reduced units) */
    int n = observed("hard-spheres", "seed 3\nnew 2 0.3\nstep 2\n", &o, &p);
    CHECK(n >= 2, "hard spheres: %d calls", n);
    /* the mixing box, event-driven: t = 0, 0.001, ..., 0.1 s */
    n = observed("mixing-box",
                 "box 0 0.4 0 0.2\npartition 0.2 0.01\nslit 0.1 0.04\nradius 0.004\n"
                 "disks 30 20\nv_init 1\nplace\nrun 0.1\n", &o, &p);
    CHECK(n == 101, "mixing box: %d calls, expected 101 (t = 0 ... 0.1 s)", n);
    /* nbody, Taylor: every time a step passed, from its dense output: t = 0 ... 0.05 */
    n = observed("nbody", "generate ring nb=12\nintegrate to=0.05\n", &o, &p);
    CHECK(n == 51, "nbody: %d calls, expected 51 (t = 0 ... 0.05)", n);
    /* charging: the Monte Carlo run (counted in histories: no time) and evolve, whose rows and
     * the observer are on one clock: t = 0 ... 0.01 s */
    n = observed("charging faithful",
                 "body sphere radius=1\nrun particles=20000\nevolve time=1e-2 dt_out=2.5e-3\n",
                 &o, &p);
    CHECK(n == 11, "charging: %d calls, expected 11 (t = 0 ... 0.01 s)", n);
    /* the separator: steps of 1e-3 s; t = 0 ... 0.01 s */
    n = observed("separator",
                 "channel 0.05 1\ngas 1.5\ncollisions off\ntimestep 1e-3\nspecies quartz 2650\n"
                 "size quartz lognormal d50=150e-6 sigma=1.6 min=30e-6 max=600e-6\n"
                 "feed z=0.5 rate=2e-5\ninsert quartz 50\nrun 0.01\n", &o, &p);
    CHECK(n == 11, "separator: %d calls, expected 11 (t = 0 ... 0.01 s)", n);
    return test_summary();
}
