/* help.c: documentation generated from the command tables: `mote help` (one line per command),
 * `mote help CMD` (a command's full text), `mote help --markdown` (the reference that
 * docs/commands.md is generated from), and the check that the tables are well-formed. */
#include "script_internal.h"

#include <string.h>

/* ---- one line per command ------------------------------------------------------------------- */

/* "name (alias, alias)" */
static void names_of(const mote_cmd *def, char *buf, size_t cap)
{
    size_t k = (size_t)snprintf(buf, cap, "%s", def->name);
    int first = 1;
    for (const char *p = def->aliases; p && *p && k < cap;) {
        while (*p == ' ')
            p++;
        size_t n = strcspn(p, " ");
        if (n == 0)
            break;
        int w = snprintf(buf + k, cap - k, "%s%.*s", first ? " (" : ", ", (int)n, p);
        if (w < 0)
            break;
        k += (size_t)w;
        first = 0;
        p += n;
    }
    if (!first && k < cap)
        snprintf(buf + k, cap - k, ")");
}

static int names_width(const mote_cmd *cmds, size_t n, int width)
{
    char buf[256];
    for (size_t i = 0; i < n; i++) {
        names_of(&cmds[i], buf, sizeof buf);
        int w = (int)strlen(buf);
        if (w > width)
            width = w;
    }
    return width;
}

enum { NAMES_MAX_WIDTH = 32 }; /* longer names put their summary on the next line */

static void list_cmds(FILE *out, const mote_cmd *cmds, size_t n, int width)
{
    char buf[256];
    if (width > NAMES_MAX_WIDTH)
        width = NAMES_MAX_WIDTH;
    for (size_t i = 0; i < n; i++) {
        names_of(&cmds[i], buf, sizeof buf);
        const char *summary = cmds[i].summary ? cmds[i].summary : "";
        if ((int)strlen(buf) > width)
            fprintf(out, "  %s\n  %-*s  %s\n", buf, width, "", summary);
        else
            fprintf(out, "  %-*s  %s\n", width, buf, summary);
    }
}

static void list_model(FILE *out, const mote_model *m, int width)
{
    fprintf(out, "\nModel %s: %s\n%s", m->name, m->summary ? m->summary : "",
            strcmp(m->name, MOTE_DEFAULT_MODEL) == 0
                ? "(the default: a script without a 'model' line uses it)\n"
                : "");
    list_cmds(out, m->cmds, m->ncmds, width);
}

void mote_help_list(FILE *out, const mote_model *const *models, size_t nmodels)
{
    int width = names_width(mote_script_common_cmds, mote_script_common_ncmds, 0);
    for (size_t i = 0; i < nmodels; i++)
        width = names_width(models[i]->cmds, models[i]->ncmds, width);
    fprintf(out,
            "mote %s: particle simulation toolkit\n"
            "\n"
            "A script has one command per line with its arguments separated by spaces; '#' starts a\n"
            "comment and double quotes keep spaces in a file name. The whole script is checked\n"
            "before anything runs.\n"
            "\n"
            "Commands of every model:\n",
            MOTE_VERSION);
    list_cmds(out, mote_script_common_cmds, mote_script_common_ncmds, width);
    for (size_t i = 0; i < nmodels; i++)
        list_model(out, models[i], width);
    fprintf(out, "\n'mote help CMD' documents a command, 'mote help MODEL' lists one model.\n");
}

/* ---- one command ---------------------------------------------------------------------------- */

static void print_aliases(FILE *out, const char *aliases, const char *sep)
{
    int first = 1;
    for (const char *p = aliases; p && *p;) {
        while (*p == ' ')
            p++;
        size_t n = strcspn(p, " ");
        if (n == 0)
            break;
        fprintf(out, "%s%.*s", first ? "" : sep, (int)n, p);
        first = 0;
        p += n;
    }
}

/* A model's columns for `plot` as lines (mote_model.plot_lines), one line per format. */
static void print_plot_lines(FILE *out, const char *lines, int after, int markdown)
{
    fprintf(out, "%sLines (several files, or labels=, x= or y=): by default\n", after ? "\n" : "");
    const char *q = markdown ? "`" : "";
    for (const char *p = lines; *p;) {
        p += strspn(p, " ");
        size_t n = strcspn(p, " ");
        if (!n)
            break;
        char e[400];
        snprintf(e, sizeof e, "%.*s", (int)(n < sizeof e ? n : sizeof e - 1), p);
        char *colon = strchr(e, ':');
        if (colon) {
            *colon = '\0';
            char *f[4] = {0};
            int k = 0;
            for (char *sv = NULL, *t = strtok_r(colon + 1, ",", &sv); t && k < 4;
                 t = strtok_r(NULL, ",", &sv))
                f[k++] = t;
            char alt[2][200]; /* "a|b": "a or b" (the first the file has) */
            for (int j = 0; j < 2 && j < k; j++) {
                size_t m = 0;
                for (const char *c = f[j]; *c && m + 5 < sizeof alt[j]; c++)
                    m += (size_t)(*c == '|' ? snprintf(alt[j] + m, 5, " or ") : (alt[j][m] = *c, 1));
                alt[j][m] = '\0';
                f[j] = alt[j];
            }
            int xlog = 0;
            for (int j = 0; j < k; j++)
                xlog |= strcmp(f[j], "log") == 0;
            fprintf(out, "- %s%s%s files: %s%s%s against %s%s%s%s", q, e, q, q, f[1] ? f[1] : "?",
                     q, q, f[0] ? f[0] : "?", q, xlog ? " (logarithmic)" : "");
            if (k >= 3 && strcmp(f[2], "log") != 0)
                fprintf(out, ", error bars %s%s%s", q, f[2], q);
            fprintf(out, "\n");
        }
        p += n;
    }
}

/* What a model adds to a common command's text (`seed`, `plot`), or NULL. */
static const char *model_addendum(const mote_model *m, const mote_cmd *def)
{
    if (strcmp(def->name, "seed") == 0)
        return m->seed ? m->seed_help : NULL;
    if (strcmp(def->name, "plot") == 0)
        return m->plot ? m->plot_help : NULL;
    if (strcmp(def->name, "picture") == 0)
        return m->picture ? m->picture_help : NULL;
    return NULL;
}

/* `threads`: which models use threads and which run on one, from the registry. */
static void print_threaded(FILE *out, const mote_model *const *models, size_t nmodels,
                           int markdown)
{
    for (int threaded = 1; threaded >= 0; threaded--) {
        fprintf(out, "%s", threaded ? "\nModels that use threads:" : "\nModels on one thread:");
        int k = 0;
        for (size_t i = 0; i < nmodels; i++)
            if (!models[i]->threaded == !threaded)
                fprintf(out, markdown ? "%s `%s`" : "%s %s", k++ ? "," : "", models[i]->name);
        fprintf(out, "%s.\n", k ? "" : " none");
    }
}

/* markdown: headings name the model in backquotes */
static void print_addenda(FILE *out, const mote_cmd *def, const mote_model *const *models,
                          size_t nmodels, int markdown)
{
    if (strcmp(def->name, "threads") == 0)
        print_threaded(out, models, nmodels, markdown);
    for (size_t i = 0; i < nmodels; i++) {
        const char *add = model_addendum(models[i], def);
        const char *lines = strcmp(def->name, "plot") == 0 ? models[i]->plot_lines : NULL;
        if ((!add || !add[0]) && !lines)
            continue;
        fprintf(out, markdown ? "\nIn the `%s` model:\n\n" : "\nIn the %s model:\n\n",
                models[i]->name);
        if (add && add[0]) {
            size_t n = strlen(add);
            fprintf(out, "%s%s", add, add[n - 1] == '\n' ? "" : "\n");
        }
        if (lines)
            print_plot_lines(out, lines, add && add[0], markdown);
    }
}

static void print_command(FILE *out, const mote_cmd *def, const char *model)
{
    fprintf(out, "%s\n", def->synopsis ? def->synopsis : def->name);
    if (model)
        fprintf(out, "  model: %s\n", model);
    else
        fprintf(out, "  common to every model\n");
    if (def->aliases && def->aliases[0]) {
        fprintf(out, "  aliases: ");
        print_aliases(out, def->aliases, ", ");
        fputc('\n', out);
    }
    fprintf(out, "\n%s\n", def->summary ? def->summary : "");
    if (def->help && def->help[0]) {
        size_t n = strlen(def->help);
        fprintf(out, "\n%s%s", def->help, def->help[n - 1] == '\n' ? "" : "\n");
    }
}

int mote_help_command(FILE *out, FILE *diag, const char *name, const mote_model *const *models,
                      size_t nmodels)
{
    int found = 0;
    const mote_cmd *def = mote_cmd_lookup(mote_script_common_cmds, mote_script_common_ncmds, name);
    if (def) {
        print_command(out, def, NULL);
        print_addenda(out, def, models, nmodels, 0);
        found = 1;
    }
    for (size_t i = 0; i < nmodels; i++) {
        def = mote_cmd_lookup(models[i]->cmds, models[i]->ncmds, name);
        if (def) {
            if (found)
                fputc('\n', out);
            print_command(out, def, models[i]->name);
            found = 1;
        }
    }
    for (size_t i = 0; i < nmodels; i++) { /* a command of rows: each row */
        const size_t len = strlen(name);
        if (mote_cmd_lookup(models[i]->cmds, models[i]->ncmds, name))
            continue;
        for (size_t j = 0; j < models[i]->ncmds; j++) {
            const mote_cmd *r = &models[i]->cmds[j];
            if (strncmp(r->name, name, len) != 0 || r->name[len] != ' ')
                continue;
            if (found++)
                fputc('\n', out);
            mote_cmd shown = *r; /* rows that share their text print it once */
            if (j > 0 && r->help == models[i]->cmds[j - 1].help)
                shown.help = "";
            print_command(out, &shown, models[i]->name);
        }
    }
    if (found)
        return 0;
    const mote_model *m = mote_model_find(models, nmodels, name);
    if (m) {
        list_model(out, m, names_width(m->cmds, m->ncmds, 0));
        return 0;
    }
    mote_suggest sg;
    mote_suggest_init(&sg, name);
    for (size_t i = 0; i < mote_script_common_ncmds; i++)
        mote_suggest_feed_cmd(&sg, &mote_script_common_cmds[i]);
    for (size_t i = 0; i < nmodels; i++) {
        mote_suggest_feed(&sg, models[i]->name, strlen(models[i]->name));
        for (size_t j = 0; j < models[i]->ncmds; j++)
            mote_suggest_feed_cmd(&sg, &models[i]->cmds[j]);
    }
    char best[80];
    if (mote_suggest_result(&sg, best, sizeof best))
        fprintf(diag, "mote: error: no command or model named '%s'; did you mean '%s'?\n", name,
                best);
    else
        fprintf(diag, "mote: error: no command or model named '%s' ('mote help' lists them)\n",
                name);
    return 1;
}

/* The words the models share (issues 34, 53): the reference's opening section. The table is
 * built from the registry: a column per model, a row per shared word, each cell the word's
 * options in that model's command table. */
static const char VOCABULARY_HEAD[] =
    "## One vocabulary\n"
    "\n"
    "The output commands take the same `key=value` options in every model: `every=K` puts\n"
    "them on a schedule counted in the model's steps (collisions per particle for hard\n"
    "spheres, steps for nbody), `dt=T` on a schedule in simulated time, `file=FILE` names one\n"
    "file, `prefix=P` a numbered series of files, and `format=` chooses a file format where\n"
    "there is a choice. A numbered series is named alike everywhere: the prefix, `_` (unless\n"
    "the prefix ends in `_` or `/`), the number, the extension (`frames ... prefix=out/a`\n"
    "writes `out/a_000000.png`, ...; a prefix's folder is made when missing); the same prefix\n"
    "again continues the numbering, and `mote check` warns when one command's files would\n"
    "replace another's. A command that had a short positional form keeps it: the values are\n"
    "given bare, in the order of the synopsis (`trajectory 10 t.xyz` is\n"
    "`trajectory every=10 file=t.xyz`), so the hard-sphere program's commands and its\n"
    "`program.txt` files run unchanged. Every scheduled output is an observer of the core's\n"
    "run loop, which every long command of every model goes through. A `monitor`'s rows (and\n"
    "nbody's trajectory table, charging's time series) follow one file policy: they go to\n"
    "FILE.partial as they are taken (`tail -f FILE.partial`; a run that is stopped leaves it,\n"
    "with every row so far), and FILE is written whole, atomically, when a command's run ends\n"
    "(and when the output starts, if there is no FILE yet), so an earlier complete FILE is\n"
    "only ever replaced by a complete one (the rows past 1 MiB wait on the disk, not in\n"
    "memory). Each output on a schedule ends with `WORD_stop` (`frames_stop`, `snapshot_stop`,\n"
    "`trajectory_stop`, `monitor_stop`, `checkpoint_stop`): what it wrote stays. The same word\n"
    "means the same thing in every model that has it (this table is made from the models'\n"
    "command tables):\n"
    "\n";

static const struct {
    const char *word, *what;
} SHARED_WORDS[] = {
    {"snapshot", "the configuration (now, or on a schedule)"},
    {"trajectory", "particle paths (a growing file)"},
    {"frames", "pictures on a schedule"},
    {"monitor", "the run's quantities over time"},
    {"checkpoint", "the exact state on a schedule"},
    {"save", "the exact state now"},
    {"load", "continue from an exact state"},
};

static const char VOCABULARY_TAIL[] =
    "\n"
    "Where the words still differ: `run` advances simulated time in the mixing box and the\n"
    "separator, but runs Monte Carlo histories in the charging model (which has no time but\n"
    "`evolve`'s) and a Galactica job folder in nbody (`run galactica`); hard spheres advance\n"
    "by collisions with the original program's `step`, nbody with `integrate`.\n"
    "\n";

/* A cell: `word key= key=` (the options of the word's command), or an em dash. */
static void vocabulary_cell(FILE *out, const mote_model *m, const char *word)
{
    const mote_cmd *c = mote_cmd_lookup(m->cmds, m->ncmds, word);
    if (!c || strcmp(c->name, word) != 0) {
        fputs(" \u2014 |", out);
        return;
    }
    char keys[MOTE_CMD_OPTIONS_MAX][32];
    const size_t n = mote_cmd_option_keys(c, keys, MOTE_CMD_OPTIONS_MAX);
    fprintf(out, " `%s", word);
    static const char *const order[] = {"every", "dt", "file", "prefix", "format"};
    for (size_t o = 0; o < sizeof order / sizeof order[0]; o++)
        for (size_t k = 0; k < n; k++)
            if (!strcmp(keys[k], order[o]))
                fprintf(out, " %s=", keys[k]);
    fputs("` |", out);
}

static void vocabulary(FILE *out, const mote_model *const *models, size_t nmodels)
{
    fputs(VOCABULARY_HEAD, out);
    fputs("| What is written |", out);
    for (size_t i = 0; i < nmodels; i++)
        fprintf(out, " %s |", models[i]->name);
    fputs("\n|---|", out);
    for (size_t i = 0; i < nmodels; i++)
        fputs("---|", out);
    fputc('\n', out);
    for (size_t w = 0; w < sizeof SHARED_WORDS / sizeof SHARED_WORDS[0]; w++) {
        fprintf(out, "| %s |", SHARED_WORDS[w].what);
        for (size_t i = 0; i < nmodels; i++)
            vocabulary_cell(out, models[i], SHARED_WORDS[w].word);
        fputc('\n', out);
    }
    fputs("\nOther names kept as aliases (`mote help` marks them):", out);
    int first = 1;
    for (size_t i = 0; i < nmodels; i++)
        for (size_t w = 0; w < sizeof SHARED_WORDS / sizeof SHARED_WORDS[0]; w++) {
            const mote_cmd *c = mote_cmd_lookup(models[i]->cmds, models[i]->ncmds,
                                                SHARED_WORDS[w].word);
            if (!c || !c->aliases || strcmp(c->name, SHARED_WORDS[w].word) != 0)
                continue;
            fprintf(out, "%s `%s` (%s's `%s`)", first ? "" : ",", c->aliases, models[i]->name,
                    c->name);
            first = 0;
        }
    fputs(first ? " none.\n" : ".\n", out);
    fputs(VOCABULARY_TAIL, out);
}

/* ---- Markdown reference --------------------------------------------------------------------- */

/* Text for a table cell: '|' escaped, line breaks as spaces. */
static void md_cell(FILE *out, const char *s)
{
    for (; s && *s; s++) {
        if (*s == '|')
            fputs("\\|", out);
        else if (*s == '\n' || *s == '\r')
            fputc(' ', out);
        else
            fputc(*s, out);
    }
}

/* models: for the common commands, whose text the models add to (NULL otherwise) */
static void md_commands(FILE *out, const mote_cmd *cmds, size_t n, const mote_model *const *models,
                        size_t nmodels)
{
    fprintf(out, "| Command | Aliases | Summary |\n|---|---|---|\n");
    for (size_t i = 0; i < n; i++) {
        fprintf(out, "| `%s` | ", cmds[i].synopsis ? cmds[i].synopsis : cmds[i].name);
        if (cmds[i].aliases && cmds[i].aliases[0]) {
            fputc('`', out);
            print_aliases(out, cmds[i].aliases, "`, `");
            fputc('`', out);
        } else {
            fputs("—", out);
        }
        fputs(" | ", out);
        md_cell(out, cmds[i].summary);
        fputs(" |\n", out);
    }
    for (size_t i = 0; i < n; i++) {
        const mote_cmd *d = &cmds[i];
        fprintf(out, "\n### `%s`\n\n```\n%s\n```\n\n", d->name, d->synopsis ? d->synopsis : d->name);
        if (d->aliases && d->aliases[0]) {
            fputs("Aliases: `", out);
            print_aliases(out, d->aliases, "`, `");
            fputs("`\n\n", out);
        }
        fprintf(out, "%s\n", d->summary ? d->summary : "");
        size_t first = i; /* rows of one command that share their text: it comes once */
        while (first > 0 && cmds[first - 1].help == d->help)
            first--;
        if (first < i)
            fprintf(out, "\nSee `%s` above.\n", cmds[first].name);
        else if (d->help && d->help[0]) {
            size_t len = strlen(d->help);
            fprintf(out, "\n%s%s", d->help, d->help[len - 1] == '\n' ? "" : "\n");
        }
        if (models)
            print_addenda(out, d, models, nmodels, 1);
    }
}

void mote_help_markdown(FILE *out, const mote_model *const *models, size_t nmodels)
{
    fprintf(out,
            "# mote command reference\n"
            "\n"
            "<!-- Generated by `mote help --markdown` from the command tables; do not edit. -->\n"
            "\n"
            "A script has one command per line: the command name, then its arguments separated by\n"
            "spaces or tabs. Blank lines are ignored and `#` at the start of a word begins a comment.\n"
            "A file name with spaces is written in double quotes, where `\\\"` and `\\\\` are the only\n"
            "escapes. Integers are decimal digits with an optional `+`; real numbers are finite\n"
            "decimal literals such as `0.49` or `1e-6`. The first command may select the model\n"
            "(`model NAME`); a script without one is a `%s` script. The whole script is checked\n"
            "before anything runs: `mote check SCRIPT` only checks, `mote run SCRIPT` checks and runs.\n"
            "On a terminal, the long commands of every model (`step` and the compressions, `run`,\n"
            "`run_collisions`, `integrate`, `run galactica`, the charging model's `run`, `float`,\n"
            "`evolve` and `test`) show their progress, the percentage done and the time left, on\n"
            "one line that is wiped when they end; into a file or a pipe they write nothing extra.\n"
            "\n",
            MOTE_DEFAULT_MODEL);
    vocabulary(out, models, nmodels);
    fputs("## Commands of every model\n\n", out);
    md_commands(out, mote_script_common_cmds, mote_script_common_ncmds, models, nmodels);
    for (size_t i = 0; i < nmodels; i++) {
        const mote_model *m = models[i];
        fprintf(out, "\n## Model `%s`\n\n%s\n\n", m->name, m->summary ? m->summary : "");
        md_commands(out, m->cmds, m->ncmds, NULL, 0);
    }
}

/* ---- table checks --------------------------------------------------------------------------- */

/* The words of a synopsis that name positional arguments (the command name included): options
 * ("key=VALUE", "[key=VALUE]") are not counted. */
static int count_positional(const char *syn)
{
    int n = 0;
    for (const char *p = syn; p && *p;) {
        while (*p == ' ')
            p++;
        size_t len = strcspn(p, " ");
        if (len == 0)
            break;
        if (p[0] != '[' && memchr(p, '=', len) == NULL)
            n++;
        p += len;
    }
    return n;
}

static int valid_name(const char *s, size_t n)
{
    if (n == 0 || !(s[0] >= 'a' && s[0] <= 'z'))
        return 0;
    for (size_t i = 0; i < n; i++)
        if (!((s[i] >= 'a' && s[i] <= 'z') || (s[i] >= '0' && s[i] <= '9') || s[i] == '_' ||
              s[i] == '-'))
            return 0;
    return 1;
}

/* Is `name` (n bytes) already used by the common commands or by the model's commands before j? */
static int name_taken(const mote_model *m, size_t j, const char *name, size_t n, char *buf,
                      size_t cap)
{
    snprintf(buf, cap, "%.*s", (int)n, name);
    if (mote_cmd_lookup(mote_script_common_cmds, mote_script_common_ncmds, buf))
        return 1;
    return mote_cmd_lookup(m->cmds, j, buf) != NULL;
}

static int verify_cmd(const mote_model *m, size_t j, mote_err *err)
{
    const mote_cmd *d = &m->cmds[j];
    const char *mn = m->name;
    char buf[128];
    /* a name, or a row of a command: "NAME SUB" (whose NAME is no command of its own) */
    const char *sp = d->name ? strchr(d->name, ' ') : NULL;
    const size_t nw = sp ? (size_t)(sp - d->name) : d->name ? strlen(d->name) : 0;
    if (!d->name || !valid_name(d->name, nw) || (sp && !valid_name(sp + 1, strlen(sp + 1))) ||
        (sp && name_taken(m, m->ncmds, d->name, nw, buf, sizeof buf)))
        return mote_script_fail_plain(err, MOTE_EINVAL, "model %s, command %zu: bad name '%s' "
                                      "(lower-case letters, digits, '_' and '-'; a row: two such "
                                      "words, the first no command of its own)", mn, j,
                                      d->name ? d->name : "(null)");
    if (name_taken(m, j, d->name, strlen(d->name), buf, sizeof buf))
        return mote_script_fail_plain(err, MOTE_EINVAL, "model %s: command name '%s' is used "
                                      "twice or clashes with a common command", mn, d->name);
    for (const char *p = d->aliases; p && *p;) {
        while (*p == ' ')
            p++;
        size_t n = strcspn(p, " ");
        if (n == 0)
            break;
        if (!valid_name(p, n) || name_taken(m, j, p, n, buf, sizeof buf) ||
            (n == strlen(d->name) && memcmp(p, d->name, n) == 0))
            return mote_script_fail_plain(err, MOTE_EINVAL, "model %s, command %s: alias '%.*s' "
                                          "is malformed, used twice or clashes with another "
                                          "command", mn, d->name, (int)n, p);
        p += n;
    }
    if (!d->args)
        return mote_script_fail_plain(err, MOTE_EINVAL, "model %s, command %s: no argument "
                                      "types (use \"\" for none)", mn, d->name);
    int nspec = mote_argspec_count(d->args);
    int star = nspec == -2;
    if (nspec == -1 || !mote_argspec_valid(d->args))
        return mote_script_fail_plain(err, MOTE_EINVAL, "model %s, command %s: argument types "
                                      "\"%s\" are malformed: specs of \"iurfse\" with a range "
                                      "(\"i>=1\", \"r(0,1]\"), words (\"e{a|b}\", "
                                      "\"r>0{auto}\") or a file role (\"f>kind\", "
                                      "\"f<kind|kind\"), then options KEY=SPEC[!] with distinct "
                                      "keys, or \"*\" alone", mn, d->name, d->args);
    if (!d->synopsis || !d->summary || !d->help)
        return mote_script_fail_plain(err, MOTE_EINVAL, "model %s, command %s: synopsis, summary "
                                      "and help are required", mn, d->name);
    size_t nl = strlen(d->name);
    if (strncmp(d->synopsis, d->name, nl) != 0 || (d->synopsis[nl] && d->synopsis[nl] != ' '))
        return mote_script_fail_plain(err, MOTE_EINVAL, "model %s, command %s: synopsis '%s' "
                                      "must start with the command name", mn, d->name,
                                      d->synopsis);
    const int name_words = count_positional(d->name); /* ("generate ring": 2) */
    if (!star && count_positional(d->synopsis) - name_words != nspec)
        return mote_script_fail_plain(err, MOTE_EINVAL, "model %s, command %s: synopsis '%s' "
                                      "names %d arguments but the types \"%s\" give %d", mn,
                                      d->name, d->synopsis, count_positional(d->synopsis) - name_words, d->args,
                                      nspec);
    return 0;
}

int mote_models_verify(const mote_model *const *models, size_t nmodels, mote_err *err)
{
    for (size_t i = 0; i < nmodels; i++) {
        const mote_model *m = models[i];
        if (!m || !m->name || !valid_name(m->name, strlen(m->name)))
            return mote_script_fail_plain(err, MOTE_EINVAL, "model %zu: missing or bad name", i);
        if (mote_model_find(models, i, m->name))
            return mote_script_fail_plain(err, MOTE_EINVAL, "model %s is registered twice",
                                          m->name);
        if (!m->create || !m->destroy || (m->ncmds > 0 && !m->cmds))
            return mote_script_fail_plain(err, MOTE_EINVAL, "model %s: create, destroy and the "
                                          "command table are required", m->name);
        for (size_t j = 0; j < m->ncmds; j++) {
            int rc = verify_cmd(m, j, err);
            if (rc)
                return rc;
        }
    }
    return 0;
}
