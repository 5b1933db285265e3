/* session.c: a model driven command by command (the Python package's Simulation, a C program
 * that reacts to its results). The session is one script that grows: each text is read into it,
 * its calls checked on a dry model that has checked all calls before them, then run on the
 * session's model; what they print is written to a temporary file and handed back. */
#include "script_internal.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int mote_session_open(mote_script **out, const char *name, const char *model_line,
                      const mote_model *const *models, size_t nmodels, mote_err *err)
{
    *out = NULL;
    char text[256];
    if (snprintf(text, sizeof text, "model %s\n", model_line ? model_line : "") >= (int)sizeof text)
        return mote_script_fail_plain(err, MOTE_EINVAL, "%s: the model line is too long", name);
    mote_script *s;
    int rc = mote_script_parse(&s, name, text, strlen(text), models, nmodels, err);
    if (rc)
        return rc;
    s->session_lines = 1;
    s->session_out = tmpfile();
    s->ctx.out = s->session_out;
    /* the context as a run has it (output_dir: the current folder for a name without '/') */
    s->ctx.threads = 0;
    s->ctx.output_dir[0] = '\0';
    s->instance = s->session_out ? s->model->create(&s->ctx, 0) : NULL;
    s->dry = s->instance ? s->model->create(&s->ctx, 1) : NULL;
    if (!s->dry) {
        mote_session_close(s);
        return mote_script_fail_plain(err, MOTE_ENOMEM, "%s: cannot create the %s model (out "
                                      "of memory)", name, s->model->name);
    }
    s->validated = 1;
    *out = s;
    return MOTE_OK;
}

/* Check calls [from, ncalls) on the dry model; on an error, a new dry model that has checked
 * only the calls before them (the failed text's checks may have changed the old one). */
static int check_new(mote_script *s, size_t from, mote_err *err)
{
    void *real = s->instance;
    s->instance = s->dry;
    int rc = 0;
    for (size_t i = from; i < s->ncalls && !rc; i++) {
        rc = mote_script_check_call(s, &s->calls[i], err);
        const mote_ensemble *e = rc ? NULL : mote_ensemble_at(s, i);
        if (e) {
            rc = mote_ensemble_check(s, e, err);
            if (rc && !err->located)
                mote_script_locate(err, &s->calls[i]);
            i = e->start[e->K] - 1;
        }
    }
    if (rc) {
        mote_err e2 = {0};
        s->model->destroy(s->instance);
        s->instance = s->model->create(&s->ctx, 1);
        for (size_t i = 0; s->instance && i < from; i++) {
            const mote_ensemble *e = mote_ensemble_at(s, i);
            mote_script_check_call(s, &s->calls[i], &e2);
            if (e)
                i = e->start[e->K] - 1;
        }
    }
    s->dry = s->instance;
    s->instance = real;
    return rc;
}

/* What the session's file holds now (malloc'ed), the file emptied. */
static char *take_output(mote_script *s)
{
    FILE *f = s->session_out;
    fflush(f);
    long n = ftell(f);
    char *buf = malloc(n > 0 ? (size_t)n + 1 : 1);
    if (!buf)
        return NULL;
    rewind(f);
    size_t got = n > 0 ? fread(buf, 1, (size_t)n, f) : 0;
    buf[got] = '\0';
    rewind(f);
    if (ftruncate(fileno(f), 0) != 0)
        buf[0] = '\0';
    return buf;
}

int mote_session_command(mote_script *s, const char *text, char **printed, mote_err *err)
{
    if (printed)
        *printed = NULL;
    if (!s->dry)
        return mote_script_fail_plain(err, MOTE_ENOMEM, "the session has no model (out of "
                                      "memory earlier)");
    const size_t from = s->ncalls;
    const int line = s->session_lines + 1;
    int rc = mote_script_append(s, text, strlen(text), line, err);
    for (const char *p = text; *p; p++) /* (the next text's lines follow this one's) */
        s->session_lines += *p == '\n';
    if (*text && text[strlen(text) - 1] != '\n')
        s->session_lines++;
    if (!rc)
        rc = check_new(s, from, err);
    if (rc) {
        mote_script_drop(s, from);
        return rc;
    }
    rc = mote_script_run_calls(s, from, s->ncalls, err);
    if (printed)
        *printed = take_output(s);
    else
        free(take_output(s));
    return rc;
}

char *mote_session_status(mote_script *s)
{
    if (!s->instance || !s->model->status)
        return NULL;
    free(take_output(s));
    s->model->status(s->instance, s->session_out);
    return take_output(s);
}

void *mote_session_instance(mote_script *s) { return s->instance; }

void mote_session_close(mote_script *s)
{
    if (!s)
        return;
    if (s->instance)
        s->model->destroy(s->instance);
    if (s->dry)
        s->model->destroy(s->dry);
    s->instance = s->dry = NULL;
    if (s->session_out)
        fclose(s->session_out);
    mote_script_free(s);
}
