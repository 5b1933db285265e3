/* parse.c: turns script text into a list of mote_call. One pass over the lines: each line is cut
 * into tokens (spaces and tabs separate, `#` at a token start begins a comment, double quotes
 * group with \" and \\ as the only escapes), its command is looked up (common commands first,
 * then the model's table), and its arguments are converted by the table's type letters (args.c
 * and convert.c). The first
 * error stops the parse with a FILE:LINE:COL message naming the command, the expected form and
 * what was found. Columns count characters (UTF-8 continuation bytes do not start a column). */
#include "script_internal.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static const char *loop_text(mote_script *s);

/* ---- commands ------------------------------------------------------------------------------- */

static void list_models(char *buf, size_t cap, const mote_model *const *models, size_t nmodels)
{
    size_t k = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < nmodels && k < cap; i++) {
        int n = snprintf(buf + k, cap - k, "%s%s", i ? ", " : "", models[i]->name);
        if (n < 0)
            break;
        k += (size_t)n;
    }
}

static const char *plural(int n) { return n == 1 ? "" : "s"; }

static int unknown_command(mote_script *s, const token *t, mote_err *err)
{
    mote_suggest sg;
    mote_suggest_init(&sg, t->text);
    for (size_t i = 0; i < mote_script_common_ncmds; i++)
        mote_suggest_feed_cmd(&sg, &mote_script_common_cmds[i]);
    if (s->model)
        for (size_t i = 0; i < s->model->ncmds; i++)
            mote_suggest_feed_cmd(&sg, &s->model->cmds[i]);
    char found[80], best[80];
    mote_script_shown(t, found, sizeof found);
    if (mote_suggest_result(&sg, best, sizeof best)) {
        int differs_in_case_only = strlen(best) == strlen(t->text) && mote_script_contains_ci(t->text, best);
        return mote_script_fail_at(err, s->ctx.script_path, t->line, t->col, MOTE_EINVAL,
                                   "unknown command %s; did you mean '%s'?%s", found, best,
                                   differs_in_case_only ? " (command names are lower-case)" : "");
    }
    return mote_script_fail_at(err, s->ctx.script_path, t->line, t->col, MOTE_EINVAL,
                               "unknown command %s (model %s; 'mote help' lists the commands)",
                               found, s->model ? s->model->name : "none");
}

/* The variant of `model NAME VARIANT` (argument 1), checked against the model's list. */
static int select_variant(mote_script *s, const mote_call *c, mote_err *err)
{
    const mote_model *m = s->model;
    const char *list = m->variants ? m->variants : "";
    s->ctx.model_variant[0] = '\0';
    if (c->nargs < 2) { /* the default: the first of the list */
        size_t n = strcspn(list, "|");
        if (n < sizeof s->ctx.model_variant) {
            memcpy(s->ctx.model_variant, list, n);
            s->ctx.model_variant[n] = '\0';
        }
        return 0;
    }
    const mote_arg *a = &c->args[1];
    if (!m->variants)
        return mote_script_fail_at(err, s->ctx.script_path, a->line, a->col, MOTE_EINVAL,
                                   "model: the %s model has no variants, found '%s'", m->name,
                                   a->text);
    size_t want = strlen(a->text);
    for (const char *p = list; *p;) {
        size_t n = strcspn(p, "|");
        if (n == want && memcmp(p, a->text, n) == 0 && n < sizeof s->ctx.model_variant) {
            memcpy(s->ctx.model_variant, p, n + 1);
            s->ctx.model_variant[n] = '\0';
            return 0;
        }
        p += n;
        if (*p == '|')
            p++;
    }
    return mote_script_fail_at(err, s->ctx.script_path, a->line, a->col, MOTE_EINVAL,
                               "model: the %s model's variant is one of %s, found '%s'", m->name,
                               list, a->text);
}

static int select_model(mote_script *s, const mote_call *c, const mote_model *const *models,
                        size_t nmodels, mote_err *err)
{
    if (c->nargs < 1 || c->nargs > 2) {
        const mote_arg *x = c->nargs ? &c->args[2] : NULL;
        return mote_script_fail_at(err, s->ctx.script_path, x ? x->line : c->line,
                                   x ? x->col : c->col, MOTE_EINVAL,
                                   "model: expected 'model NAME [VARIANT]', found %d argument%s",
                                   c->nargs, c->nargs == 1 ? "" : "s");
    }
    const mote_arg *a = &c->args[0];
    s->model = mote_model_find(models, nmodels, a->text);
    s->ctx.model = s->model;
    s->model_line = c->line;
    if (s->model)
        return select_variant(s, c, err);
    char known[512], best[80], found[80];
    token t = {a->text, a->line, a->col, a->quoted};
    mote_script_shown(&t, found, sizeof found);
    list_models(known, sizeof known, models, nmodels);
    mote_suggest sg;
    mote_suggest_init(&sg, a->text);
    for (size_t i = 0; i < nmodels; i++)
        mote_suggest_feed(&sg, models[i]->name, strlen(models[i]->name));
    if (mote_suggest_result(&sg, best, sizeof best))
        return mote_script_fail_at(err, s->ctx.script_path, a->line, a->col, MOTE_EINVAL,
                                   "model: unknown model %s; did you mean '%s'? (known models: %s)",
                                   found, best, known);
    return mote_script_fail_at(err, s->ctx.script_path, a->line, a->col, MOTE_EINVAL,
                               "model: unknown model %s (known models: %s)", found, known);
}

static int push_call(mote_script *s, const mote_call *c)
{
    if (s->ncalls == s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 32;
        mote_call *nc = realloc(s->calls, cap * sizeof *nc);
        if (!nc)
            return -1;
        s->calls = nc;
        s->cap = cap;
    }
    s->calls[s->ncalls++] = *c;
    return 0;
}

/* The command a line names: a common command, the model's, or a row of the model's ("generate
 * ring": then *ptl becomes the tokens from the second on, in *rows); the model chosen first
 * when the script has no `model` line. */
static int find_command(mote_script *s, const token_list **ptl, token_list *rows,
                        const mote_model *const *models, size_t nmodels, const mote_cmd **pdef,
                        mote_err *err)
{
    const char *file = s->ctx.script_path;
    const token_list *tl = *ptl;
    const token *name = &tl->t[0];
    char found[80];
    const mote_cmd *model_cmd = mote_script_common_model_cmd();
    int is_model = strcmp(name->text, model_cmd->name) == 0;
    if (s->ncalls == 0 && !is_model) {
        s->ctx.model = s->model = mote_model_find(models, nmodels, MOTE_DEFAULT_MODEL);
        if (!s->model) {
            char known[512];
            list_models(known, sizeof known, models, nmodels);
            return mote_script_fail_at(err, file, name->line, name->col, MOTE_EINVAL,
                                       "the first command must be 'model NAME' "
                                       "(known models: %s)", known);
        }
    }
    const mote_cmd *def = mote_cmd_lookup(mote_script_common_cmds, mote_script_common_ncmds,
                                          name->text);
    if (!def && s->model)
        def = mote_cmd_lookup(s->model->cmds, s->model->ncmds, name->text);
    if (!def && s->model && mote_cmd_has_rows(s->model->cmds, s->model->ncmds, name->text)) {
        const token *sub = tl->n > 1 ? &tl->t[1] : NULL;
        char full[96];
        int w = sub && !sub->quoted
                    ? snprintf(full, sizeof full, "%s %s", name->text, sub->text)
                    : -1;
        if (w > 0 && (size_t)w < sizeof full)
            def = mote_cmd_lookup(s->model->cmds, s->model->ncmds, full);
        if (!def) {
            char list[512];
            mote_cmd_rows_text(s->model->cmds, s->model->ncmds, name->text, list, sizeof list);
            if (!sub)
                return mote_script_fail_at(err, file, name->line, name->col, MOTE_EINVAL,
                                           "%s: expected %s after it", name->text, list);
            return mote_script_fail_at(err, file, sub->line, sub->col, MOTE_EINVAL,
                                       "%s: expected %s, found %s", name->text, list,
                                       mote_script_shown(sub, found, sizeof found));
        }
        /* the row's name stands for the first two tokens, at the first one's place */
        char *text = mote_arena_strndup(&s->arena, full, strlen(full));
        if (!text)
            return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
        tl->t[1].text = text;
        tl->t[1].line = name->line;
        tl->t[1].col = name->col;
        *rows = *tl;
        rows->t = tl->t + 1;
        rows->n = tl->n - 1;
        tl = rows;
        name = &tl->t[0];
    }
    if (!def)
        return unknown_command(s, name, err);
    if (strcmp(def->name, "plot") == 0 && mote_script_is_common(s, def) &&
        !(def = mote_script_plot_def(s)))
        return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    if (def == model_cmd && s->ncalls != 0) {
        if (s->model_line)
            return mote_script_fail_at(err, file, name->line, name->col, MOTE_EINVAL,
                                       "model: only one 'model' command is allowed, as the first "
                                       "command (line %d already selected '%s')",
                                       s->model_line, s->model->name);
        return mote_script_fail_at(err, file, name->line, name->col, MOTE_EINVAL,
                                   "model: 'model' must be the first command of the script "
                                   "(without it, the script is a %s script)", s->model->name);
    }

    *ptl = tl;
    *pdef = def;
    return MOTE_OK;
}

/* The line's tokens after the name as the command's positional arguments (pos) and key=value
 * options (opt): bare tokens beyond the positional arguments fill the '@' options; the count
 * checked against the synopsis. */
static int place_tokens(mote_script *s, const mote_cmd *def, const token_list *tl,
                        const token ***ppos, int *pnargs, const token ***popt, int *pnopts,
                        mote_err *err)
{
    const char *file = s->ctx.script_path;
    const token *name = &tl->t[0];
    /* key=value tokens are options when the command declares options */
    const int nopt_specs = def->args[0] == '*' ? 0 : mote_argspec_noptions(def->args);
    int ntok = tl->n - 1, nopts = 0;
    const token **pos = NULL, **opt = NULL;
    int nargs = 0;
    if (ntok > 0) {
        pos = mote_arena_alloc(&s->arena, (size_t)ntok * sizeof *pos);
        opt = mote_arena_alloc(&s->arena, (size_t)ntok * sizeof *opt);
        if (!pos || !opt)
            return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    }
    for (int k = 1; k <= ntok; k++) {
        const token *t = &tl->t[k];
        if (nopt_specs > 0 && !t->quoted && mote_option_key_len(t->text) > 0)
            opt[nopts++] = t;
        else
            pos[nargs++] = t;
    }
    int star = def->args[0] == '*';
    int want = star ? nargs : mote_argspec_count(def->args);
    if (!star && nargs > want && mote_argspec_many(def->args))
        want = nargs; /* (the last spec takes the rest) */
    const char *syn = def->synopsis ? def->synopsis : def->name;
    /* bare tokens beyond the positional arguments fill the '@' options not given as key=value,
     * in order */
    for (int q = 0; q < nopt_specs && nargs > want; q++) {
        mote_argspec o;
        if (mote_argspec_option_at(def->args, q, &o) || !o.positional)
            continue;
        int given = 0;
        for (int k = 0; k < nopts; k++)
            given |= strncmp(opt[k]->text, o.key, strlen(o.key)) == 0 &&
                     opt[k]->text[strlen(o.key)] == '=';
        if (given)
            continue;
        const token *t = pos[want];
        token *v = mote_arena_alloc(&s->arena, sizeof *v);
        size_t klen = strlen(o.key), tlen = strlen(t->text);
        char *text = mote_arena_alloc(&s->arena, klen + tlen + 2);
        if (!v || !text)
            return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
        memcpy(text, o.key, klen);
        text[klen] = '=';
        memcpy(text + klen + 1, t->text, tlen + 1);
        *v = *t;
        v->text = text;
        v->col = t->col - (int)klen - 1; /* (the value's column stays the token's) */
        opt[nopts++] = v;
        for (int k = want; k + 1 < nargs; k++)
            pos[k] = pos[k + 1];
        nargs--;
    }
    if (nargs > want) {
        const token *extra = pos[want];
        char keys[256] = "";
        size_t used = 0;
        for (int q = 0; q < nopt_specs; q++) { /* the '@' options a bare value can fill */
            mote_argspec o;
            if (!mote_argspec_option_at(def->args, q, &o) && o.positional && used < sizeof keys) {
                int w = snprintf(keys + used, sizeof keys - used, "%s%s=", used ? ", " : "",
                                 o.key);
                used += w > 0 ? (size_t)w : 0;
            }
        }
        if (used)
            return mote_script_fail_at(err, file, extra->line, extra->col, MOTE_EINVAL,
                                       "%s: too many arguments: expected '%s' (bare values "
                                       "fill %s in this order, unless given as key=value), "
                                       "found '%s' left over", name->text, syn, keys,
                                       extra->text);
        return mote_script_fail_at(err, file, extra->line, extra->col, MOTE_EINVAL,
                                   "%s: too many arguments: expected '%s' (%d argument%s), "
                                   "found %d", name->text, syn, want, plural(want), nargs);
    }
    if (nargs < want)
        return mote_script_fail_at(err, file, name->line, name->col, MOTE_EINVAL,
                                   "%s: too few arguments: expected '%s' (%d argument%s), "
                                   "found %d", name->text, syn, want, plural(want), nargs);

    *ppos = pos;
    *pnargs = nargs;
    *popt = opt;
    *pnopts = nopts;
    return MOTE_OK;
}

static int parse_command(mote_script *s, const token_list *tl, const mote_model *const *models,
                         size_t nmodels, mote_err *err)
{
    const char *file = s->ctx.script_path;
    const token *name = &tl->t[0];
    char found[80];
    if (name->quoted)
        return mote_script_fail_at(err, file, name->line, name->col, MOTE_EINVAL,
                                   "expected a command name, found a quoted string %s",
                                   mote_script_shown(name, found, sizeof found));
    const mote_cmd *model_cmd = mote_script_common_model_cmd(), *def = NULL;
    token_list rows; /* a command of rows ("generate ring"): the tokens from the second on */
    int rc = find_command(s, &tl, &rows, models, nmodels, &def, err);
    if (rc)
        return rc;
    name = &tl->t[0];
    const int nopt_specs = def->args[0] == '*' ? 0 : mote_argspec_noptions(def->args);
    const token **pos = NULL, **opt = NULL;
    int nargs = 0, nopts = 0;
    if ((rc = place_tokens(s, def, tl, &pos, &nargs, &opt, &nopts, err)))
        return rc;

    mote_call c;
    memset(&c, 0, sizeof c);
    mote_arg *args = NULL;
    if (nargs > 0) {
        args = mote_arena_alloc(&s->arena, (size_t)nargs * sizeof *args);
        if (!args)
            return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
        for (int i = 0; i < nargs; i++) {
            if ((rc = mote_script_convert_arg(s, def, name->text, i, NULL, pos[i], &args[i],
                                              err)))
                return rc;
        }
    }
    mote_opt *opts = NULL;
    if ((nopts > 0 || nopt_specs > 0) &&
        (rc = mote_script_convert_options(s, def, name, opt, nopts, &opts, err)))
        return rc;
    c.file = file;
    c.line = name->line;
    c.col = name->col;
    c.name = def->name;
    c.written = name->text;
    c.source = mote_arena_strndup(&s->arena, tl->src_begin,
                                  (size_t)(tl->src_end - tl->src_begin));
    c.nargs = nargs;
    c.args = args;
    c.nopts = nopts;
    c.opts = opts;
    c.def = def;
    c.ctx = &s->ctx;
    c.loop = loop_text(s);
    if (!c.source)
        return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    if (def == model_cmd && (rc = select_model(s, &c, models, nmodels, err)))
        return rc;
    if (push_call(s, &c))
        return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    return 0;
}

/* ---- variables ------------------------------------------------------------------------------ */

/* Replace the variables in the line's words (not in `set`'s NAME); when any changed, the line's
 * source (for data-file headers) becomes its words as expanded, quoted where they were. */
static int expand_line(mote_script *s, token_list *tl, int is_set, mote_err *err)
{
    int changed = 0;
    for (int k = 0; k < tl->n; k++) {
        token *t = &tl->t[k];
        const char *x;
        if (is_set && k == 1)
            continue;
        int rc = mote_vars_expand(s, s->ctx.script_path, t->line, t->col, t->text, &x, err);
        if (rc)
            return rc;
        changed |= x != t->text;
        t->text = x;
    }
    if (!changed)
        return 0;
    size_t n = 1;
    for (int k = 0; k < tl->n; k++)
        n += 2 * strlen(tl->t[k].text) + 3;
    char *src = mote_arena_alloc(&s->arena, n), *q = src;
    if (!src)
        return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    for (int k = 0; k < tl->n; k++) {
        const token *t = &tl->t[k];
        if (k)
            *q++ = ' ';
        if (t->quoted)
            *q++ = '"';
        for (const char *c = t->text; *c; c++) {
            if (t->quoted && (*c == '"' || *c == '\\'))
                *q++ = '\\';
            *q++ = *c;
        }
        if (t->quoted)
            *q++ = '"';
    }
    *q = '\0';
    tl->src_begin = src;
    tl->src_end = q;
    return 0;
}

/* `set NAME VALUE` (its arguments checked by the table): NAME defined for the lines after it. */
static int define_variable(mote_script *s, const token_list *tl, mote_err *err)
{
    const token *name = &tl->t[1];
    if (name->quoted || !mote_var_name_ok(name->text, strlen(name->text)))
        return mote_script_fail_at(err, s->ctx.script_path, name->line, name->col, MOTE_EINVAL,
                                   "set: a variable name is a letter or '_', then letters, "
                                   "digits or '_', found '%s'", name->text);
    if (mote_vars_set(s, name->text, tl->t[2].text, 0))
        return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    return 0;
}

/* ---- the whole script ----------------------------------------------------------------------- */

/* ---- loops ---------------------------------------------------------------------------------- */

/* The most passes of one loop, and the most lines read with every pass of every loop: a script
 * is text a person writes, and its check lists every command it will run. */
#define LOOP_MAX_PASSES 1000000L
#define LOOP_MAX_LINES 1000000L
/* The most bytes of commands a script may expand to (its text is at most 64 MiB too). */
#define SCRIPT_MAX_EXPANDED ((size_t)64 << 20)

static int is_word(const token_list *tl, int k, const char *w)
{
    return tl->n > k && !tl->t[k].quoted && strcmp(tl->t[k].text, w) == 0;
}

/* "eta=0.3, n=2": the passes of the open loops (in the arena), or NULL outside loops. */
static const char *loop_text(mote_script *s)
{
    if (!s->nloops)
        return NULL;
    char buf[512];
    size_t n = 0;
    buf[0] = '\0';
    for (int k = 0; k < s->nloops && n < sizeof buf; k++) {
        int w = snprintf(buf + n, sizeof buf - n, "%s%s=%s", k ? ", " : "", s->loops[k].name,
                         s->loops[k].value);
        n += w > 0 ? (size_t)w : 0;
    }
    return mote_arena_strndup(&s->arena, buf, strlen(buf));
}

static int parse_lines(mote_script *s, const char *p, const char *end, int line,
                       const mote_model *const *models, size_t nmodels, mote_err *err);

/* The `end` of the loop whose body starts at p, line `line`: *body_end the start of the `end`
 * line, *after the text after it (NULL: the text ends there), *after_line its number. */
static int find_end(mote_script *s, const token *for_tok, const char *p, const char *end,
                    int line, const char **body_end, const char **after, int *after_line,
                    mote_err *err)
{
    token_list tl = {NULL, 0, 0, NULL, NULL};
    int depth = 0, rc = 0, found = 0;
    for (; p <= end && !rc && !found; line++) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *le = nl ? nl : end;
        if (le > p && le[-1] == '\r')
            le--;
        rc = mote_lex_line(s, (cursor){p, le, line, 1}, &tl, err);
        if (!rc && (is_word(&tl, 0, "for") || is_word(&tl, 0, "ensemble")))
            depth++;
        else if (!rc && is_word(&tl, 0, "end") && depth-- == 0) {
            if (tl.n > 1) {
                rc = mote_script_fail_at(err, s->ctx.script_path, tl.t[1].line, tl.t[1].col,
                                         MOTE_EINVAL, "end: expected nothing after 'end', found "
                                         "'%.60s'", tl.t[1].text);
                break;
            }
            *body_end = p;
            *after = nl ? nl + 1 : NULL;
            *after_line = line + 1;
            found = 1;
        }
        if (!nl)
            break;
        p = nl + 1;
    }
    free(tl.t);
    if (!rc && !found)
        rc = mote_script_fail_at(err, s->ctx.script_path, for_tok->line, for_tok->col,
                                 MOTE_EINVAL, "%s: this %s has no 'end' (a line 'end' closes "
                                 "it)", for_tok->text,
                                 strcmp(for_tok->text, "for") ? "ensemble" : "loop");
    return rc;
}

static int read_loop_number(mote_script *s, const token *t, const char *what, double *v,
                            mote_err *err)
{
    char *e;
    *v = strtod(t->text, &e);
    if (t->quoted || e == t->text || *e || !isfinite(*v) || strpbrk(t->text, "xXnN"))
        return mote_script_fail_at(err, s->ctx.script_path, t->line, t->col, MOTE_EINVAL,
                                   "for: expected a number for %s, found '%s'", what, t->text);
    return 0;
}

/* `for NAME in V1 V2 ...` or `for NAME from A to B [step S]` ... `end`: the body read once per
 * value, with NAME set to it; *next and *next_line where reading goes on. */
static int parse_loop(mote_script *s, token_list *tl, const char *body, const char *end,
                      int body_line, const char **next, int *next_line,
                      const mote_model *const *models, size_t nmodels, mote_err *err)
{
    const char *file = s->ctx.script_path;
    const token *t = tl->t;
    const int in = is_word(tl, 2, "in"), from = is_word(tl, 2, "from");
    if (tl->n < 4 || (!in && !from) ||
        (from && !(is_word(tl, 4, "to") && (tl->n == 6 || (tl->n == 8 && is_word(tl, 6, "step"))))))
        return mote_script_fail_at(err, file, t[0].line, t[0].col, MOTE_EINVAL,
                                   "for: expected 'for NAME in V1 V2 ...' or 'for NAME from A "
                                   "to B [step S]'");
    const token *name = &t[1];
    if (name->quoted || !mote_var_name_ok(name->text, strlen(name->text)))
        return mote_script_fail_at(err, file, name->line, name->col, MOTE_EINVAL,
                                   "for: a variable name is a letter or '_', then letters, "
                                   "digits or '_', found '%s'", name->text);
    const mote_var *fixed = mote_vars_find(s, name->text, strlen(name->text));
    if (fixed && fixed->fixed)
        return mote_script_fail_at(err, file, name->line, name->col, MOTE_EINVAL,
                                   "for: '%s' is a parameter given on the command line; loop "
                                   "over another name", name->text);
    if (s->nloops == MOTE_LOOP_DEPTH)
        return mote_script_fail_at(err, file, t[0].line, t[0].col, MOTE_EINVAL,
                                   "for: more than %d loops inside each other", MOTE_LOOP_DEPTH);
    double a = 0, b = 0, step = 1;
    long passes = tl->n - 3;
    if (from) {
        int rc = read_loop_number(s, &t[3], "A", &a, err);
        if (!rc)
            rc = read_loop_number(s, &t[5], "B", &b, err);
        if (!rc && tl->n == 8)
            rc = read_loop_number(s, &t[7], "S", &step, err);
        if (rc)
            return rc;
        const double q = (b - a) / step;
        if (step == 0 || !(q > -1e-9) || !(q < (double)LOOP_MAX_PASSES))
            return mote_script_fail_at(err, file, t[0].line, t[0].col, MOTE_EINVAL,
                                       "for: from %s to %s step %s gives %s values (1 to "
                                       "%ld)", t[3].text, t[5].text,
                                       tl->n == 8 ? t[7].text : "1",
                                       step == 0 || !(q > -1e-9) ? "no" : "too many",
                                       LOOP_MAX_PASSES);
        passes = (long)floor(q + 1e-9) + 1; /* B itself when it is a whole number of steps */
    }
    const char *body_end = NULL, *after = NULL;
    int after_line = 0;
    int rc = find_end(s, &t[0], body, end, body_line, &body_end, &after, &after_line, err);
    if (rc)
        return rc;
    mote_loop_pass *lp = &s->loops[s->nloops++];
    lp->name = name->text;
    lp->line = t[0].line;
    for (long k = 0; k < passes && !rc; k++) {
        /* a pass of an empty body counts as a line, so nested empty loops stay bounded too */
        if (body_end == body && ++s->lines_read > LOOP_MAX_LINES) {
            rc = mote_script_fail_at(err, file, s->loops[0].line, 1, MOTE_EINVAL,
                                     "for: the loops read more than %ld lines (every pass "
                                     "counts)", LOOP_MAX_LINES);
            break;
        }
        char num[64];
        if (from) /* A + k S: no sum carried from pass to pass */
            mote_vars_format(a + (double)k * step, num, sizeof num);
        const char *value = from ? num : t[3 + k].text;
        if (mote_vars_set(s, name->text, value, 0))
            rc = mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
        const mote_var *var = mote_vars_find(s, name->text, strlen(name->text));
        if (var) /* (for messages: the stored copy, which outlives num) */
            lp->value = var->value;
        if (!rc)
            rc = parse_lines(s, body, body_end, body_line, models, nmodels, err);
    }
    s->nloops--;
    *next = after;
    *next_line = after_line;
    return rc;
}

/* `ensemble K [options]` ... `end`: the line as a call, then the body read once per replica
 * with the variable `replica` = 1 ... K (ensemble.c runs them); *next and *next_line where
 * reading goes on. */
static int parse_ensemble(mote_script *s, token_list *tl, const char *body, const char *end,
                          int body_line, const char **next, int *next_line,
                          const mote_model *const *models, size_t nmodels, mote_err *err)
{
    const char *file = s->ctx.script_path;
    const token *t = tl->t;
    if (s->in_ensemble)
        return mote_script_fail_at(err, file, t[0].line, t[0].col, MOTE_EINVAL,
                                   "ensemble: an ensemble inside an ensemble (a replica is one "
                                   "run; loop inside it, or around it)");
    const mote_var *given = mote_vars_find(s, "replica", 7);
    if (given && given->fixed)
        return mote_script_fail_at(err, file, t[0].line, t[0].col, MOTE_EINVAL,
                                   "ensemble: 'replica' is a parameter given on the command line, "
                                   "but inside an ensemble it numbers the replicas");
    if (s->nloops == MOTE_LOOP_DEPTH)
        return mote_script_fail_at(err, file, t[0].line, t[0].col, MOTE_EINVAL,
                                   "ensemble: more than %d loops inside each other",
                                   MOTE_LOOP_DEPTH);
    int rc = parse_command(s, tl, models, nmodels, err);
    if (rc)
        return rc;
    const size_t call = s->ncalls - 1;
    const int K = (int)s->calls[call].args[0].i;
    const char *body_end = NULL, *after = NULL;
    int after_line = 0;
    rc = find_end(s, &t[0], body, end, body_line, &body_end, &after, &after_line, err);
    mote_ensemble *e = NULL;
    if (!rc && mote_ensemble_add(s, call, K, &e))
        rc = mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    if (rc)
        return rc;
    size_t *start = e->start; /* (e moves when a later ensemble is added; start does not) */
    mote_loop_pass *lp = &s->loops[s->nloops++];
    lp->name = "replica";
    lp->line = t[0].line;
    s->in_ensemble = 1;
    for (int r = 0; r < K && !rc; r++) {
        char num[32];
        snprintf(num, sizeof num, "%d", r + 1);
        if (mote_vars_set(s, "replica", num, 0))
            rc = mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
        const mote_var *var = mote_vars_find(s, "replica", 7);
        if (var)
            lp->value = var->value;
        start[r] = s->ncalls;
        if (!rc)
            rc = parse_lines(s, body, body_end, body_line, models, nmodels, err);
    }
    start[K] = s->ncalls;
    s->in_ensemble = 0;
    s->nloops--;
    *next = after;
    *next_line = after_line;
    return rc;
}

/* Read the lines of text [p, end), the first of them line `line`. */
static int parse_lines(mote_script *s, const char *p, const char *end, int line,
                       const mote_model *const *models, size_t nmodels, mote_err *err)
{
    token_list tl = {NULL, 0, 0, NULL, NULL};
    int rc = 0;
    while (p && p < end && !rc) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        const char *le = nl ? nl : end;
        if (le > p && le[-1] == '\r')
            le--;
        /* (the lines outside loops, read once, do not count) */
        if (s->nloops && ++s->lines_read > LOOP_MAX_LINES)
            rc = mote_script_fail_at(err, s->ctx.script_path, s->loops[0].line, 1, MOTE_EINVAL,
                                     "for: the loops read more than %ld lines (every pass "
                                     "counts)", LOOP_MAX_LINES);
        if (!rc)
            rc = mote_lex_line(s, (cursor){p, le, line, 1}, &tl, err);
        const int is_set = !rc && is_word(&tl, 0, "set"), is_for = !rc && is_word(&tl, 0, "for");
        if (!rc && tl.n > 0)
            rc = expand_line(s, &tl, is_set || is_for, err);
        if (!rc && tl.n > 0 &&
            (s->bytes_read += (size_t)(tl.src_end - tl.src_begin) + 1) > SCRIPT_MAX_EXPANDED)
            rc = mote_script_fail_at(err, s->ctx.script_path, line, 1, MOTE_EINVAL,
                                     "the script's commands, with every pass of its loops and "
                                     "its variables replaced, exceed %d MiB",
                                     (int)(SCRIPT_MAX_EXPANDED >> 20));
        if (!rc && is_word(&tl, 0, "ensemble")) {
            const char *next = NULL;
            int next_line = line;
            rc = parse_ensemble(s, &tl, nl ? nl + 1 : end, end, line + 1, &next, &next_line,
                                models, nmodels, err);
            if (rc && s->nloops && err->msg[0] && !strstr(err->msg, " (in the loop: "))
                mote_script_note_loop(err, loop_text(s));
            p = next;
            line = next_line;
            continue;
        }
        if (!rc && is_for) {
            const char *next = NULL;
            int next_line = line;
            rc = parse_loop(s, &tl, nl ? nl + 1 : end, end, line + 1, &next, &next_line, models,
                            nmodels, err);
            p = next;
            line = next_line;
            continue;
        }
        if (!rc && is_word(&tl, 0, "end"))
            rc = mote_script_fail_at(err, s->ctx.script_path, line, tl.t[0].col, MOTE_EINVAL,
                                     "end: no loop to end (for NAME in ... or for NAME from ... "
                                     "opens one)");
        if (!rc && tl.n > 0)
            rc = parse_command(s, &tl, models, nmodels, err);
        if (!rc && is_set)
            rc = define_variable(s, &tl, err);
        if (rc && s->nloops && err->msg[0] && !strstr(err->msg, " (in the loop: "))
            mote_script_note_loop(err, loop_text(s));
        if (!nl)
            break;
        p = nl + 1;
        line++;
    }
    free(tl.t);
    return rc;
}

static int parse_text(mote_script *s, const char *text, size_t len,
                      const mote_model *const *models, size_t nmodels, mote_err *err)
{
    const char *p = text, *end = text + len;
    if (len >= 3 && memcmp(p, "\xEF\xBB\xBF", 3) == 0) /* UTF-8 byte-order mark */
        p += 3;
    int rc = parse_lines(s, p, end, 1, models, nmodels, err);
    if (!rc && !s->model) {
        /* An empty script: it still belongs to a model, for `check` and for status output. */
        s->ctx.model = s->model = mote_model_find(models, nmodels, MOTE_DEFAULT_MODEL);
        if (!s->model)
            rc = mote_script_fail_at(err, s->ctx.script_path, 1, 1, MOTE_EINVAL,
                                     "the script is empty and has no 'model' line");
    }
    return rc;
}

void mote_script_drop(mote_script *s, size_t from)
{
    for (size_t i = from; i < s->ncalls; i++) {
        for (int k = 0; k < s->calls[i].nargs; k++) {
            free(((mote_arg *)s->calls[i].args)[k].path);
            ((mote_arg *)s->calls[i].args)[k].path = NULL;
        }
        for (int k = 0; k < s->calls[i].nopts; k++) {
            free(((mote_opt *)s->calls[i].opts)[k].value.path);
            ((mote_opt *)s->calls[i].opts)[k].value.path = NULL;
        }
    }
    if (from < s->ncalls)
        s->ncalls = from;
    while (s->nens && s->ens[s->nens - 1].call >= from)
        s->nens--;
}

int mote_script_append(mote_script *s, const char *text, size_t len, int line, mote_err *err)
{
    const size_t before = s->ncalls;
    if (len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0) { /* a byte-order mark, as in a file */
        text += 3;
        len -= 3;
    }
    int rc = parse_lines(s, text, text + len, line, s->models, s->nmodels, err);
    if (rc) /* (what the text added goes; its arena memory stays until the script is freed) */
        mote_script_drop(s, before);
    return rc;
}

int mote_script_parse(mote_script **out, const char *file, const char *text, size_t len,
                      const mote_model *const *models, size_t nmodels, mote_err *err)
{
    return mote_script_parse_params(out, file, text, len, NULL, 0, models, nmodels, err);
}

/* The parameters NAME=VALUE as fixed variables; an error names the one that is wrong. */
static int define_params(mote_script *s, const char *const *params, int nparams, mote_err *err)
{
    for (int i = 0; i < nparams; i++) {
        const char *eq = strchr(params[i], '=');
        const size_t n = eq ? (size_t)(eq - params[i]) : 0;
        if (!eq || n > 255 || !mote_var_name_ok(params[i], n))
            return mote_script_fail_plain(err, MOTE_EINVAL, "mote: error: parameter '%s': "
                                          "expected NAME=VALUE, NAME a letter or '_', then "
                                          "letters, digits or '_'", params[i]);
        for (int j = 0; j < i; j++)
            if (strncmp(params[j], params[i], n + 1) == 0)
                return mote_script_fail_plain(err, MOTE_EINVAL, "mote: error: parameter '%.*s' "
                                              "is given twice ('%s' and '%s')", (int)n,
                                              params[i], params[j], params[i]);
        const char *bad = mote_var_value_bad(eq + 1);
        if (bad)
            return mote_script_fail_plain(err, MOTE_EINVAL, "mote: error: parameter '%.*s': the "
                                          "value holds %s (a value becomes words of the "
                                          "script, file names and header lines)", (int)n,
                                          params[i], bad);
        char name[256];
        snprintf(name, sizeof name, "%.*s", (int)n, params[i]);
        if (mote_vars_set(s, name, eq + 1, 1))
            return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    }
    return 0;
}

int mote_script_parse_params(mote_script **out, const char *file, const char *text, size_t len,
                             const char *const *params, int nparams,
                             const mote_model *const *models, size_t nmodels, mote_err *err)
{
    *out = NULL;
    mote_script *s = calloc(1, sizeof *s);
    if (!s)
        return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    s->ctx.out = stdout;
    s->ctx.diag = stderr;
    s->live_port = -1; /* no live view unless asked for */
    s->models = models;
    s->nmodels = nmodels;
    s->ctx.script_path = mote_arena_strndup(&s->arena, file, strlen(file));
    if (!s->ctx.script_path) {
        mote_script_free(s);
        return mote_script_fail_plain(err, MOTE_ENOMEM, "out of memory reading the script");
    }
    int rc = define_params(s, params, nparams, err);
    if (!rc)
        rc = parse_text(s, text, len, models, nmodels, err);
    if (rc) {
        mote_script_free(s);
        return rc;
    }
    *out = s;
    return 0;
}

/* The largest script read (a script is text a person writes: this bounds /dev/zero and the like) */
#define MOTE_SCRIPT_MAX_BYTES ((size_t)64 << 20)

int mote_script_load(mote_script **out, const char *path, const mote_model *const *models,
                     size_t nmodels, mote_err *err)
{
    return mote_script_load_params(out, path, NULL, 0, models, nmodels, err);
}

int mote_script_load_params(mote_script **out, const char *path, const char *const *params,
                            int nparams, const mote_model *const *models, size_t nmodels,
                            mote_err *err)
{
    *out = NULL;
    const int in = strcmp(path, "-") == 0; /* standard input: named <stdin> in messages */
    FILE *f = in ? stdin : fopen(path, "rb");
    if (in)
        path = "<stdin>";
    if (!f)
        return mote_script_fail_plain(err, MOTE_EIO, "mote: error: cannot open script '%s': %s",
                                      path, strerror(errno));
    size_t len = 0, cap = 65536;
    char *buf = malloc(cap);
    int rc = 0;
    if (!buf)
        rc = mote_script_fail_plain(err, MOTE_ENOMEM, "mote: error: out of memory reading '%s'",
                                    path);
    while (!rc) {
        if (len >= MOTE_SCRIPT_MAX_BYTES) {
            rc = mote_script_fail_plain(err, MOTE_EFORMAT, "mote: error: %s: a script larger than "
                                        "64 MiB (not a script?)", path);
            break;
        }
        if (len == cap) {
            char *nb = cap <= SIZE_MAX / 2 ? realloc(buf, cap * 2) : NULL;
            if (!nb) {
                rc = mote_script_fail_plain(err, MOTE_ENOMEM,
                                            "mote: error: out of memory reading '%s'", path);
                break;
            }
            buf = nb;
            cap *= 2;
        }
        size_t n = fread(buf + len, 1, cap - len, f);
        len += n;
        if (n == 0) {
            if (ferror(f))
                rc = mote_script_fail_plain(err, MOTE_EIO, "mote: error: cannot read script "
                                            "'%s': %s", path, strerror(errno));
            break;
        }
    }
    if (!in)
        fclose(f);
    /* the core readers' line limit holds for scripts too */
    for (size_t i = 0, start = 0, line = 1; !rc && i <= len; i++)
        if (i == len || buf[i] == '\n') {
            if (i - start > MOTE_LINE_MAX)
                rc = mote_script_fail_plain(err, MOTE_EFORMAT, "mote: error: %s:%zu: line longer "
                                            "than 1 MiB (not a script?)", path, line);
            start = i + 1;
            line++;
        }
    if (!rc)
        rc = mote_script_parse_params(out, path, buf, len, params, nparams, models, nmodels, err);
    free(buf);
    return rc;
}

void mote_script_free(mote_script *s)
{
    if (!s)
        return;
    for (size_t i = 0; i < s->ncalls; i++)
        for (int k = 0; k < s->calls[i].nargs; k++)
            free(((mote_arg *)s->calls[i].args)[k].path);
    for (size_t i = 0; i < s->ncalls; i++)
        for (int k = 0; k < s->calls[i].nopts; k++)
            free(((mote_opt *)s->calls[i].opts)[k].value.path);
    mote_outputs_free(&s->ctx.outputs);
    mote_ensemble_free_summaries(s);
    free(s->ens);
    free(s->vars);
    free(s->vhash);
    free(s->calls);
    mote_arena_free(&s->arena);
    free(s);
}

mote_context *mote_script_context(mote_script *s) { return &s->ctx; }
const mote_model *mote_script_model(const mote_script *s) { return s->model; }
size_t mote_script_ncalls(const mote_script *s) { return s->ncalls; }

const mote_call *mote_script_call(const mote_script *s, size_t i)
{
    return i < s->ncalls ? &s->calls[i] : NULL;
}

const mote_model *mote_model_find(const mote_model *const *models, size_t nmodels,
                                  const char *name)
{
    for (size_t i = 0; i < nmodels; i++)
        if (models[i] && strcmp(models[i]->name, name) == 0)
            return models[i];
    return NULL;
}
