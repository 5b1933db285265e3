/* run.c: validation and execution of a parsed script, and the commands every model shares
 * (`model`, `output_dir`, `echo`, `threads`). Validation runs every command's `check` on a dry
 * model, so a typo on the last line is found before the first line has run for hours; execution
 * then runs every command on a fresh model and prints the model's status line after each. */
#include "script_internal.h"
#include "mote/datafile.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <strings.h>
#include <sys/stat.h>
#include <sys/types.h>

/* ---- common commands ------------------------------------------------------------------------ */

/* The folder of the script (its path up to the last '/'), or "" for the current directory:
 * where the script's relative file names start from. */
static void script_folder(const mote_context *ctx, char *buf, size_t cap)
{
    const char *p = ctx->script_path ? ctx->script_path : "";
    const char *slash = strrchr(p, '/');
    size_t n = slash ? (size_t)(slash - p) : 0;
    if (slash && n == 0)
        n = 1; /* a script in / */
    if (n >= cap)
        n = 0;
    memcpy(buf, p, n);
    buf[n] = '\0';
}

/* DIR as stored in ctx->output_dir: trailing slashes dropped, "." meaning the script's folder,
 * a relative DIR taken from the script's folder ("" is the current directory). */
static int output_dir_value(const mote_call *c, char *buf, size_t cap, mote_err *err)
{
    const char *dir = c->args[0].text;
    size_t n = strlen(dir);
    while (n > 1 && dir[n - 1] == '/')
        n--;
    if (n == 1 && dir[0] == '.')
        n = 0;
    char base[4096];
    script_folder(c->ctx, base, sizeof base);
    if (dir[0] == '/')
        base[0] = '\0';
    size_t nb = strlen(base), sep = nb && n && base[nb - 1] != '/';
    if (nb + sep + n >= cap)
        return mote_call_fail(err, c, 0, MOTE_EINVAL,
                              "output_dir: the directory name is too long (at most %zu bytes)",
                              cap - 1 - nb - sep);
    memcpy(buf, base, nb);
    if (sep)
        buf[nb] = '/';
    memcpy(buf + nb + sep, dir, n);
    buf[nb + sep + n] = '\0';
    return 0;
}

static int output_dir_check(void *model, const mote_call *c, mote_err *err)
{
    mote_context *ctx = c->ctx;
    char dir[sizeof ctx->output_dir];
    int rc = output_dir_value(c, dir, sizeof dir, err);
    if (rc)
        return rc;
    if (dir[0]) {
        struct stat st;
        if (stat(dir, &st) == 0) {
            if (!S_ISDIR(st.st_mode))
                return mote_call_fail(err, c, 0, MOTE_EINVAL,
                                      "output_dir: '%s' exists and is not a directory", dir);
        } else if (errno != ENOENT) {
            return mote_call_fail(err, c, 0, MOTE_EINVAL, "output_dir: cannot use '%s': %s", dir,
                                  strerror(errno));
        } else {
            int known = 0;
            for (int i = 0; i < ctx->npending_dirs; i++)
                known |= strcmp(ctx->pending_dirs[i], dir) == 0;
            if (!known) {
                int cap = (int)(sizeof ctx->pending_dirs / sizeof ctx->pending_dirs[0]);
                if (ctx->npending_dirs >= cap)
                    return mote_call_fail(err, c, 0, MOTE_EINVAL,
                                          "output_dir: too many new directories in one script "
                                          "(at most %d); create '%s' beforehand", cap, dir);
                memcpy(ctx->pending_dirs[ctx->npending_dirs++], dir, strlen(dir) + 1);
            }
        }
    }
    memcpy(ctx->output_dir, dir, strlen(dir) + 1);
    return 0;
}

/* mkdir -p: make dir and any missing parents. Returns 0 or an errno value. */
static int make_dirs(const char *dir)
{
    char buf[4096];
    size_t n = strlen(dir);
    if (n >= sizeof buf)
        return ENAMETOOLONG;
    memcpy(buf, dir, n + 1);
    for (size_t i = 1; i <= n; i++) {
        if (buf[i] != '/' && buf[i] != '\0')
            continue;
        if (buf[i - 1] == '/')
            continue;
        char save = buf[i];
        buf[i] = '\0';
        if (mkdir(buf, 0777) != 0) {
            int e = errno;
            struct stat st;
            if (e != EEXIST)
                return e;
            if (stat(buf, &st) != 0)
                return errno;
            if (!S_ISDIR(st.st_mode))
                return ENOTDIR;
        }
        buf[i] = save;
    }
    return 0;
}

static int output_dir_run(void *model, const mote_call *c, mote_err *err)
{
    mote_context *ctx = c->ctx;
    char dir[sizeof ctx->output_dir];
    int rc = output_dir_value(c, dir, sizeof dir, err);
    if (rc)
        return rc;
    if (dir[0]) {
        int e = make_dirs(dir);
        if (e)
            return mote_call_fail(err, c, 0, MOTE_EIO,
                                  "output_dir: cannot create directory '%s': %s", dir,
                                  strerror(e));
    }
    memcpy(ctx->output_dir, dir, strlen(dir) + 1);
    return 0;
}

static int echo_run(void *model, const mote_call *c, mote_err *err)
{
    FILE *out = c->ctx->out;
    for (int i = 0; i < c->nargs; i++)
        fprintf(out, "%s%s", i ? " " : "", c->args[i].text);
    fputc('\n', out);
    return 0;
}

static int quiet_run(void *model, const mote_call *c, mote_err *err)
{
    c->ctx->quiet = c->args[0].i == 0; /* on|off */
    return MOTE_OK;
}

static int threads_run(void *model, const mote_call *c, mote_err *err)
{
    mote_script *s = model; /* common commands receive the script, not the model */
    c->ctx->threads = c->args[0].i > 4096 ? 4096 : (int)c->args[0].i;
    if (!s->model->threaded && !s->threads_noted && !s->nens) {
        s->threads_noted = 1;
        fprintf(c->ctx->diag,
                "%s:%d:%d: note: threads: the %s model runs on one thread; 'threads %lld' has "
                "no effect on it\n",
                c->file, c->line, c->col, s->model->name, (long long)c->args[0].i);
    }
    return 0;
}

/* ---- the live view (issue 25) ---------------------------------------------------------------- */

/* The context's hook: a frame when one is due, then wait while the page holds the run. The
 * frame only reads the model, so a run is the same with and without a view. */
static void live_frame(mote_script *s, int now)
{
    if (!s->live || !s->instance)
        return;
    if (s->model->live && mote_live_due(s->live, now)) {
        const double t0 = mote_wall_seconds();
        mote_buf *b = &s->frame;
        b->n = 0;
        b->failed = 0;
        mote_buf_printf(b, "{\"frame\":%llu", (unsigned long long)mote_live_frames(s->live) + 1);
        mote_buf_string(b, "model", s->model->name);
        s->model->live(s->instance, b);
        mote_buf_printf(b, "}");
        if (!b->failed) /* (a frame without memory is dropped) */
            mote_live_publish(s->live, b->s, b->n, mote_wall_seconds() - t0);
    }
    mote_live_hold(s->live);
}

static void live_tick(void *arg) { live_frame(arg, 0); }

int mote_script_live_start(mote_script *s, const char *bind, int port, mote_err *err)
{
    if (s->live)
        return MOTE_OK;
    char url[128];
    int rc = mote_live_start(&s->live, bind, port, url, err);
    if (rc)
        return rc;
    s->ctx.tick = live_tick;
    s->ctx.tick_arg = s;
    fprintf(s->ctx.out, "live: open %s in a browser (the run never waits for it)%s\n", url,
            s->model->live ? "" : "; this model has no live picture yet");
    fflush(s->ctx.out);
    return MOTE_OK;
}

/* `live http [PORT] [bind=ADDRESS]`: the port (8080 by default; 0: any free one) and the
 * address to bind (by default the loopback). */
static int live_run(void *model, const mote_call *c, mote_err *err)
{
    const mote_arg *port = mote_call_opt(c, "port"), *bind = mote_call_opt(c, "bind");
    return mote_script_live_start(model, bind ? bind->text : NULL, port ? (int)port->i : 8080,
                                  err);
}

/* (`set`, `for` and `end` act as the script is read: see vars.c and parse.c) */
static int set_run(void *model, const mote_call *c, mote_err *err) { return MOTE_OK; }

/* `reset`: the model's system is destroyed and a fresh one made, as at the start of the script
 * (dry while validating, real while running); the run-wide settings stay. */
static int reset_to(mote_script *s, const mote_call *c, int dry, mote_err *err)
{
    void *fresh = s->model->create(&s->ctx, dry);
    if (!fresh)
        return mote_call_fail(err, c, -1, MOTE_ENOMEM, "reset: cannot create a new %s system "
                              "(out of memory)", s->model->name);
    s->model->destroy(s->instance);
    s->instance = fresh;
    return MOTE_OK;
}

static int reset_check(void *model, const mote_call *c, mote_err *err)
{
    return reset_to(model, c, 1, err);
}

static int reset_run(void *model, const mote_call *c, mote_err *err)
{
    mote_script *s = model;
    int rc = reset_to(s, c, 0, err);
    if (!rc)
        fprintf(c->ctx->out, "reset: a new %s system\n", s->model->name);
    return rc;
}

static int seed_check(void *model, const mote_call *c, mote_err *err)
{
    mote_script *s = model;
    if (!s->model->seed)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "seed: the %s model draws no random numbers", s->model->name);
    return 0;
}

static int seed_run(void *model, const mote_call *c, mote_err *err)
{
    mote_script *s = model;
    s->model->seed(s->instance, c->args[0].u);
    fprintf(c->ctx->out, "seed: %llu\n", (unsigned long long)c->args[0].u);
    return 0;
}

/* `plot`: the data files, and the picture: to=PNG, or else the last argument when there are two
 * or more and it ends in .png. Returns the number of data files, or -1 (err set). */
static int plot_files(const mote_call *c, const char **png, mote_err *err)
{
    const mote_arg *to = mote_call_opt(c, "to");
    int n = c->nargs;
    const char *last = c->args[n - 1].text;
    size_t ll = strlen(last);
    int last_png = ll > 4 && strcasecmp(last + ll - 4, ".png") == 0;
    if (to) {
        *png = to->path;
        for (int i = 0; i < n; i++) {
            const char *t = c->args[i].text;
            size_t tl = strlen(t);
            if (tl > 4 && strcasecmp(t + tl - 4, ".png") == 0)
                return mote_call_fail(err, c, i, MOTE_EINVAL, "plot: %s is a picture, not a data "
                                      "file (the picture is to=%s)", t, to->text), -1;
        }
        return n;
    }
    if (n < 2 || !last_png)
        return mote_call_fail(err, c, n < 2 ? -1 : n - 1, MOTE_EINVAL,
                              "plot: name the picture: 'plot DATAFILE PNGFILE', or 'plot A.dat "
                              "B.dat ... to=PNGFILE'%s", n < 2 ? "" : " (a PNGFILE ends in .png)"),
               -1;
    *png = c->args[n - 1].path;
    return n - 1;
}

/* The model's own picture (one data file, none of labels= x= y=), or lines. */
static int plot_own(const mote_script *s, const mote_call *c, int nin)
{
    return nin == 1 && s->model->plot && s->model->plot_kinds && !mote_call_opt(c, "labels") &&
           !mote_call_opt(c, "x") && !mote_call_opt(c, "y");
}

static int plot_check(void *model, const mote_call *c, mote_err *err)
{
    mote_script *s = model;
    const char *png;
    int nin = plot_files(c, &png, err);
    if (nin < 0)
        return err->code;
    if (!mote_call_opt(c, "to")) {
        int rc = mote_outputs_note_path(&c->ctx->outputs, c, nin, png, "png", 0, err);
        if (rc)
            return rc;
    }
    int own = plot_own(s, c, nin), later = 0;
    for (int i = 0; i < nin; i++) {
        if (mote_path_is_csv(c->args[i].path) &&
            !(mote_call_opt(c, "x") && mote_call_opt(c, "y")))
            return mote_call_fail(err, c, i, MOTE_EINVAL,
                                  "plot: %s is a CSV file, which keeps its column names but not "
                                  "what kind of file it is: give x= and y= (column names of its "
                                  "first row)", c->args[i].text);
        int rc = mote_args_check_input(c, i, own ? s->model->plot_kinds : NULL, err);
        if (rc)
            return rc;
        later |= mote_outputs_find(&c->ctx->outputs, c->args[i].path) != NULL;
    }
    if (own)
        return s->model->plot_check ? s->model->plot_check(s->instance, c, err) : 0;
    int rc = mote_plot_lines_labels(c, nin, err);
    if (!rc && !later) /* files that exist now: their columns are checked before anything runs */
        rc = mote_plot_lines(c, nin, s->model->plot_lines, png, 1, err);
    return rc;
}

static int plot_run(void *model, const mote_call *c, mote_err *err)
{
    mote_script *s = model;
    const char *png;
    int nin = plot_files(c, &png, err);
    if (nin < 0)
        return err->code;
    int rc = plot_own(s, c, nin) ? s->model->plot(s->instance, c->args[0].path, png, c, err)
                                 : mote_plot_lines(c, nin, s->model->plot_lines, png, 0, err);
    if (!rc)
        fprintf(c->ctx->out, "plot: wrote %s\n", png);
    return rc;
}

/* `picture FILE.png`: the model's picture of its state now. */
static int picture_check(void *model, const mote_call *c, mote_err *err)
{
    mote_script *s = model;
    if (!s->model->picture)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "picture: the %s model draws no picture of its state (its files "
                              "and `plot` do)", s->model->name);
    const char *t = c->args[0].text;
    const size_t n = strlen(t);
    if (n < 5 || strcasecmp(t + n - 4, ".png") != 0)
        return mote_call_fail(err, c, 0, MOTE_EINVAL, "picture: FILE must end in .png, found "
                              "'%s'", t);
    return MOTE_OK;
}

static int picture_run(void *model, const mote_call *c, mote_err *err)
{
    mote_script *s = model;
    int rc = s->model->picture(s->instance, c->args[0].path, err);
    if (rc && !err->located) { /* (the model's message, at the command) */
        char msg[sizeof err->msg];
        snprintf(msg, sizeof msg, "%s", err->msg);
        rc = mote_call_fail(err, c, -1, err->code, "picture: %s", msg);
    }
    if (!rc)
        fprintf(c->ctx->out, "picture: wrote %s\n", c->args[0].path);
    return rc;
}

const mote_cmd mote_script_common_cmds[] = {
    {"model", NULL, "*", "model NAME [VARIANT]", "select the model; must be the first command",
     "Select the model the script drives (`mote help` lists the models of this\n"
     "build), and for a model that has variants (nbody: gravity or coulomb) the\n"
     "variant; without one, the model's first. It must be the first command of the\n"
     "script and may appear only once.\n"
     "A script without a `model` line is a " MOTE_DEFAULT_MODEL " script, so the original\n"
     "program's program.txt files run unchanged.\n",
     NULL, NULL},
    {"output_dir", NULL, "f", "output_dir DIR",
     "create DIR and write the files of later commands there",
     "Create the directory DIR, with any missing parents (like `mkdir -p`), when\n"
     "the command runs, and resolve the relative file names of all later commands\n"
     "against it. A relative DIR, like every relative file name of a script, starts\n"
     "from the folder that holds the script (so a script does the same run from any\n"
     "current directory), not from an earlier `output_dir`; `output_dir .` returns\n"
     "to the script's folder. Absolute file names are not affected. Validation knows\n"
     "that DIR will exist, so later commands may write into it.\n",
     output_dir_check, output_dir_run},
    {"set", NULL, "s s", "set NAME VALUE", "a variable: ${NAME} in the lines after it",
     "Define the variable NAME (a letter or `_`, then letters, digits or `_`) as VALUE\n"
     "(one word; quote it to keep spaces) for the lines after it; a later `set` replaces\n"
     "it. `${NAME}` in any word of a later line stands for the value, inside the word\n"
     "(`file=rho_${eta}.dat`; a value never splits a word in two). `${EXPR}` is\n"
     "arithmetic on numbers and variables with + - * / ^ and parentheses (`${eta*2}`,\n"
     "`${(a+b)/2}`, `${2^10}`; no spaces inside, as a space ends a word), the functions\n"
     "sqrt exp log log10 sin cos tan asin acos atan abs floor ceil round of one argument\n"
     "and atan2 min max pow of two (`${sqrt(2*kT)}`, `${max(a,b)}`), and pi (unless a\n"
     "variable is named so). The result is written with 15 significant digits as a\n"
     "calculator shows it (`${0.1*3}` is 0.3, `${1/3}` 0.333333333333333, `${2^60}`\n"
     "1.15292150460685e+18), a whole number up to 2^53 with every digit (`${2^53}` is\n"
     "9007199254740992, so a seed computed in `${...}` is exact). `$$` writes one `$`.\n"
     "Expressions nest at most 200 levels deep.\n"
     "\n"
     "Parameters on the command line, `mote run study.mote eta=0.45 out=run1`, fix their\n"
     "variables: a `set` of the same name then keeps the command line's value, so `set`\n"
     "gives the defaults, and a parameter that no `${NAME}` uses is warned about. `mote\n"
     "run - NAME=VALUE` reads the script from standard input. The values are put in as\n"
     "the script is read, so `mote check` checks the commands as they will run, and\n"
     "data-file headers show the command with its values. An undefined variable, a word\n"
     "that is not a number in `${...}`, a result that is not finite, or a parameter\n"
     "value holding a line break or another control character is an error naming the\n"
     "line, and nothing runs.\n",
     NULL, set_run},
    {"for", NULL, "*", "for NAME in V1 V2 ... | for NAME from A to B [step S]",
     "repeat the lines up to `end` for each value of NAME",
     "    for NAME in V1 V2 ...\n"
     "    for NAME from A to B [step S]\n"
     "        ...\n"
     "    end\n"
     "\n"
     "Read the lines up to the matching `end` once for each value, with the variable\n"
     "NAME set to it (see `set`): the words after `in`, or the numbers A, A + S, A + 2S,\n"
     "... up to B (B itself when (B - A)/S is a whole number; each value is A + kS, not\n"
     "a running sum, written as `${...}` writes numbers; S is 1 unless given, and may be\n"
     "negative). Loops nest, up to 16 deep; after the loop NAME keeps its last value.\n"
     "The check lists every pass: `mote check` checks each command as each pass will run\n"
     "it, and an error names the line and the pass, `(in the loop: eta=0.45, k=2)`. A\n"
     "loop reads its body at most 10^6 times, and all loops together at most 10^6 lines\n"
     "(`end` is not one; a pass of an empty body is), and the whole script expands to at\n"
     "most 64 MiB of commands. `end` takes nothing after it.\n"
     "A loop works on the system the script has: to sweep fresh systems, begin each pass\n"
     "with `reset`.\n",
     NULL, set_run},
    {"end", NULL, "", "end", "close the loop of the last `for`",
     "Close the loop opened by the last `for` that is still open (see `for`).\n", NULL, set_run},
    {"reset", NULL, "", "reset", "start again from a new, empty system of the model",
     "Discard the model's system and start a new one, as at the start of the script:\n"
     "no particles or bodies, every setting of the model back to its default and the\n"
     "random stream back to `seed 1` (give `seed` after `reset` for another stream).\n"
     "What belongs to the run stays: `threads`, `output_dir`, variables, the live view,\n"
     "and the files written so far. In a loop it makes every pass an independent\n"
     "run:\n"
     "\n"
     "    for v in 0.5 1 2\n"
     "        reset\n"
     "        generate ring nb=30\n"
     "        ...\n"
     "    end\n"
     "\n"
     "Prints `reset: a new MODEL system`.\n",
     reset_check, reset_run},
    {"ensemble", NULL, "i[1,100000] seed=u file=f>ensemble summary=f",
     "ensemble K [seed=S] [file=FILE] [summary=FILE]",
     "run the lines up to `end` K times, each a new system: means and errors",
     "    ensemble K [seed=S] [file=FILE] [summary=FILE]\n"
     "        ...\n"
     "    end\n"
     "\n"
     "Run the lines up to `end` as K independent replicas, each on a new system of the\n"
     "model (as after `reset`) whose random stream starts from the seed S + r - 1 for\n"
     "replica r = 1 ... K (S is 1 unless given; the variable ${replica} is r). The\n"
     "replicas run at the same time on the threads `threads` gives (by default every\n"
     "processor of the machine), each on one thread; what they print is shown after\n"
     "them, replica by replica, and nothing of it depends on the number of threads.\n"
     "Each number a command of the body gives as its result (pressure's Z and P_wall,\n"
     "chempot's mu_ex, order's fractions, tromp's d50 and kappa, float's U_f, the mixing\n"
     "box run's mixing_fraction and slit fluxes) is then combined over the replicas into its\n"
     "mean, its standard error s/sqrt(K) and the half-width of its 95% confidence\n"
     "interval, Student's t(0.975, K - 1) times the standard error, printed as\n"
     "`ensemble: pressure.Z = 4.12 ± 0.07 (95% confidence; standard error 0.03,\n"
     "Student's t 2.365 with 7 degrees of freedom; 8 replicas)` (COMMAND.KEY; a second\n"
     "result of the same name in a replica gets _2). Below 4 replicas a warning says\n"
     "how little so few values tell about the error. file= writes each replica's values,\n"
     "with the means and errors in its header; summary= adds one row to a table that\n"
     "every ensemble naming it extends: the values of the loops around the ensemble,\n"
     "then each mean, its standard error and its 95% half-width (columns Q, Q_err,\n"
     "Q_ci95), ready for `plot summary.dat to=z.png x=eta y=pressure.Z`:\n"
     "\n"
     "    for eta in 0.3 0.4\n"
     "        ensemble 8 summary=eos.dat\n"
     "            bulk 500 ${eta}\n"
     "            step 2000\n"
     "            pressure 2000 p_${eta}_${replica}.dat\n"
     "        end\n"
     "    end\n"
     "\n"
     "The ensemble leaves the script's own system as it was. Every replica is checked\n"
     "before anything runs, an error naming it `(in the loop: replica=3)`; an error in a\n"
     "replica stops the script after the ensemble, with the earliest replica's message.\n"
     "An ensemble cannot hold another, nor `live`; a model that draws no random numbers\n"
     "(nbody) has no ensembles. Under mpirun (make MPI=1) the replicas are spread over\n"
     "the ranks, with the single process's results.\n",
     NULL, set_run},
    {"echo", NULL, "*", "echo TEXT...", "print the arguments",
     "Print the arguments, separated by single spaces, on standard output. Quote\n"
     "text to keep runs of spaces or a `#` in it.\n",
     NULL, echo_run},
    {"quiet", NULL, "e{on|off}", "quiet on|off", "no status line after each command",
     "`quiet on`: the commands that follow print no status line after them (what they\n"
     "print of their own, results, warnings and errors still show); `quiet off` brings\n"
     "the status lines back. `mote run --quiet SCRIPT` starts quiet. For a script of\n"
     "many setup commands whose status lines say nothing new.\n",
     NULL, quiet_run},
    {"threads", NULL, "i>=1", "threads N", "number of threads for the commands that follow",
     "Set the number of threads (OpenMP) for the commands that follow, N >= 1\n"
     "(default 1). Results never depend on it: the models that use threads (listed\n"
     "below) sum in a fixed order for any number of threads, so they are\n"
     "bit-identical (the separator runs on one thread below 4096 particles and while\n"
     "dispersion draws random kicks, which come from one stream). In the models that\n"
     "run on one thread the first `threads` command prints a note and none has an\n"
     "effect, except on an `ensemble`, whose replicas run side by side on N threads\n"
     "in every model (its results never depend on N).\n"
     "Threads wait for each other without spinning for long (mote sets libgomp's\n"
     "GOMP_SPINCOUNT to 1000 unless GOMP_SPINCOUNT or OMP_WAIT_POLICY is set), so on a\n"
     "machine whose other cores are busy two threads are no slower than one in the\n"
     "runs measured (bench/threads.sh; the separator's contact hertz at 7500\n"
     "particles: bench/README.md, \"Threads on a busy machine\").\n",
     NULL, threads_run},
    {"seed", NULL, "u", "seed S", "restart the random stream from S (default 1)",
     "Restart the run's random stream from the unsigned 64-bit integer S\n"
     "(0 <= S <= 2^64 - 1). The default is 1: a script without `seed` behaves as if\n"
     "it began with `seed 1`. The generator is xoshiro256** (Blackman & Vigna), its\n"
     "four state words the first four outputs of SplitMix64 started from S; there is\n"
     "one stream per run, and `seed` acts at its place in the script, so a second\n"
     "`seed 7` restarts the same stream. A model's `load` restores the stream saved\n"
     "in the state file, so a continued run draws what the uninterrupted run would\n"
     "have drawn. Runs are bit-for-bit reproducible for a given seed on the same\n"
     "build and machine type; on another platform (another libm) they agree\n"
     "statistically. Prints `seed: S`.\n",
     seed_check, seed_run},
    {"live", NULL, "e{http} @port=i[0,65535] bind=s", "live http [PORT] [bind=ADDRESS]",
     "watch the run in a browser: a live view on PORT (8080)",
     "Start the live view: a small web server inside the run, on 127.0.0.1 unless\n"
     "bind=ADDRESS says otherwise, on PORT (default 8080; 0: any free port). Open the\n"
     "address it prints: the page shows the system as it runs, up to 30 frames a second\n"
     "(fewer when making a frame would take more than a tenth of the run's time), with\n"
     "the model's status line and a frame counter, and can pause and resume the run;\n"
     "nothing else on the page changes the simulation. The run never waits for the page\n"
     "and its results are the same with and without it. `mote run --live[=PORT] SCRIPT`\n"
     "starts it before the first command. See docs/live-view.md.\n",
     NULL, live_run},
    {"picture", NULL, "f>png", "picture FILE.png", "a picture of the model's state now",
     "    picture FILE.png\n"
     "\n"
     "Draw the state as it is now into FILE.png (written atomically), as the model\n"
     "draws its own pictures (below). The same picture is what a Python notebook shows\n"
     "for a simulation (docs/python.md). Prints `picture: wrote FILE`.\n",
     picture_check, picture_run},
    {"plot", NULL, "f+ to=f>png labels=s x=s y=s",
     "plot DATAFILE... [PNGFILE] [to=PNGFILE] [labels=A,B,...] [x=COLUMN] [y=COLUMN]",
     "draw data files as a PNG: a model's picture, or lines with a legend",
     "    plot DATAFILE PNGFILE [options]\n"
     "    plot A.dat B.dat ... to=PNGFILE [labels=A,B,...] [x=COLUMN] [y=COLUMN]\n"
     "\n"
     "Draw data files written earlier (by this script or another) by the model's\n"
     "measuring commands as a PNG picture, written atomically; the picture is to=PNGFILE,\n"
     "or the last argument when it ends in .png. Each DATAFILE must be written earlier in\n"
     "the script, or exist. Prints `plot: wrote PNGFILE`.\n"
     "\n"
     "One data file, without labels=, x= or y=, in a model with pictures of its own\n"
     "(below): the model's picture of that kind of file, which follows from the file's\n"
     "first header line; some models take key=value options that shape it.\n"
     "\n"
     "Otherwise, in any model: lines. Column y= against column x= of every file, one\n"
     "line per file in one frame, with a legend: labels= (one per file, separated by\n"
     "commas), or else each file's name without folder and extension. A column name may\n"
     "leave out its [unit] (`y=rho` is `rho[R^-3]`). Without x= and y=, the model's\n"
     "columns for that kind of file (below), and where a file has a column Y_err or\n"
     "sigma_Y (or the kind's own), its error bars. A file of several blocks gives the\n"
     "rows of its last block (after its last `# columns:` line). mote's CSV files\n"
     "(*.csv) are read too, by the names of their first row, always with x= and y=.\n"
     "Files that exist when the script is checked have their columns checked then,\n"
     "before anything runs:\n"
     "\n"
     "    for eta in 0.3 0.4\n"
     "        reset\n"
     "        new 3 ${eta}\n"
     "        image 100 4 rho_${eta}.dat\n"
     "    end\n"
     "    plot rho_0.3.dat rho_0.4.dat to=rho.png labels=0.3,0.4\n",
     plot_check, plot_run},
};
const size_t mote_script_common_ncmds = sizeof mote_script_common_cmds /
                                        sizeof mote_script_common_cmds[0];

int mote_script_is_common(const mote_script *s, const mote_cmd *def)
{
    return (def >= mote_script_common_cmds &&
            def < mote_script_common_cmds + mote_script_common_ncmds) ||
           def == &s->plot_def;
}

const mote_cmd *mote_script_plot_def(mote_script *s)
{
    const mote_cmd *common = mote_cmd_lookup(mote_script_common_cmds, mote_script_common_ncmds,
                                             "plot");
    if (!s->model || !s->model->plot_opts)
        return common;
    if (!s->plot_def.name) {
        size_t len = strlen(common->args) + strlen(s->model->plot_opts) + 2;
        char *args = mote_arena_alloc(&s->arena, len);
        if (!args)
            return NULL;
        snprintf(args, len, "%s %s", common->args, s->model->plot_opts);
        s->plot_def = *common;
        s->plot_def.args = args;
    }
    return &s->plot_def;
}

const mote_cmd *mote_script_common_model_cmd(void) { return &mote_script_common_cmds[0]; }

const mote_cmd *mote_script_command_at(const mote_model *m, size_t k)
{
    if (k < mote_script_common_ncmds)
        return &mote_script_common_cmds[k];
    k -= mote_script_common_ncmds;
    return m && k < m->ncmds ? &m->cmds[k] : NULL;
}

/* ---- validation and execution --------------------------------------------------------------- */

static void reset_context(mote_context *ctx)
{
    ctx->threads = 0;
    script_folder(ctx, ctx->output_dir, sizeof ctx->output_dir); /* names start from there */
    ctx->npending_dirs = 0;
    mote_outputs_free(&ctx->outputs);
}

static void clear(mote_err *err)
{
    err->code = MOTE_OK;
    err->located = 0;
    err->msg[0] = '\0';
}

int mote_script_check_call(mote_script *s, mote_call *c, mote_err *err)
{
    clear(err);
    int rc = mote_args_resolve(c, err);
    if (!rc)
        rc = mote_args_check_before(c, err);
    if (!rc && c->def->check)
        rc = c->def->check(mote_script_is_common(s, c->def) ? (void *)s : s->instance, c, err);
    if (!rc)
        rc = mote_args_check_after(c, err);
    if (rc)
        mote_script_locate(err, c);
    return rc;
}

int mote_script_validate(mote_script *s, mote_err *err)
{
    clear(err);
    s->validated = 0;
    reset_context(&s->ctx);
    void *dry = s->model->create(&s->ctx, 1);
    if (!dry)
        return mote_script_fail_at(err, s->ctx.script_path, 1, 1, MOTE_ENOMEM,
                                   "cannot create the %s model (out of memory)", s->model->name);
    s->instance = dry;
    int rc = 0;
    for (size_t i = 0; i < s->ncalls && !rc; i++) {
        rc = mote_script_check_call(s, &s->calls[i], err);
        const mote_ensemble *e = rc ? NULL : mote_ensemble_at(s, i);
        if (e) { /* its replicas, each from a new system; then on after them */
            rc = mote_ensemble_check(s, e, err);
            if (rc && !err->located) /* (a replica's error is located at its call) */
                mote_script_locate(err, &s->calls[i]);
            i = e->start[e->K] - 1;
        }
    }
    s->model->destroy(s->instance); /* (`reset` may have replaced it) */
    s->instance = NULL;
    reset_context(&s->ctx);
    if (rc)
        return err->code ? (int)err->code : (int)MOTE_EINVAL;
    s->validated = 1;
    return 0;
}

int mote_script_run_calls(mote_script *s, size_t from, size_t to, mote_err *err)
{
    /* under mpirun, a model that does not share its work runs its commands in rank 0; the other
     * ranks keep the run-wide settings and take part in the ensembles */
    const mote_ranks *rk = s->ctx.ranks;
    const int elsewhere = rk && rk->size > 1 && rk->rank != 0 && !s->model->mpi;
    int rc = 0;
    for (size_t i = from; i < to && !rc; i++) {
        mote_call *c = &s->calls[i];
        c->ctx = &s->ctx; /* (a replica's context while an ensemble runs it) */
        int common = mote_script_is_common(s, c->def);
        if (elsewhere && !mote_ensemble_at(s, i) &&
            !(common && (!strcmp(c->name, "output_dir") || !strcmp(c->name, "threads"))))
            continue;
        clear(err);
        rc = mote_args_resolve(c, err);
        const mote_ensemble *e = mote_ensemble_at(s, i);
        if (!rc && e) {
            rc = mote_ensemble_run(s, e, err);
            i = e->start[e->K] - 1;
        } else if (!rc && c->def->run) {
            rc = c->def->run(common ? (void *)s : s->instance, c, err);
            if (!rc && !common && s->model->settle)
                rc = s->model->settle(s->instance, err);
        }
        if (rc) {
            if (!(e && err->located)) /* (a replica's error is located at its call) */
                mote_script_locate(err, c);
            rc = err->code ? (int)err->code : (int)MOTE_ERUNTIME;
        } else if (!common && s->model->status && !s->ctx.quiet) {
            s->model->status(s->instance, s->ctx.out);
        }
        fflush(s->ctx.out);
        if (!rc && s->live) /* a frame of the state after every command */
            live_frame(s, 1);
    }
    return rc;
}

int mote_script_execute(mote_script *s, mote_err *err)
{
    if (!s->validated) {
        int rc = mote_script_validate(s, err);
        if (rc)
            return rc;
    }
    clear(err);
    reset_context(&s->ctx);
    s->threads_noted = 0;
    mote_ensemble_free_summaries(s);
    void *first = s->model->create(&s->ctx, 0);
    if (!first)
        return mote_script_fail_at(err, s->ctx.script_path, 1, 1, MOTE_ENOMEM,
                                   "cannot create the %s model (out of memory)", s->model->name);
    s->instance = first;
    int rc = 0;
    if (s->live_port >= 0 && (rc = mote_script_live_start(s, s->live_bind, s->live_port, err)))
        rc = err->code;
    s->ranks_finished = 0;
    if (!rc)
        rc = mote_script_run_calls(s, 0, s->ncalls, err);
    mote_ranks_sync(s, 1); /* (under mpirun: the last meeting of the ranks) */
    if (s->live && s->ctx.terminal && isatty(STDIN_FILENO)) {
        /* a short run would take its page away before anyone looked: on a terminal the last
         * frame stays served until Enter (issue 52) */
        fprintf(s->ctx.out, "live: the run is over; its page keeps the last frame until you "
                            "press Enter\n");
        fflush(s->ctx.out);
        int ch;
        while ((ch = getchar()) != EOF && ch != '\n')
            ;
    }
    if (s->live) {
        mote_live_stop(s->live);
        s->live = NULL;
        s->ctx.tick = NULL;
        mote_buf_free(&s->frame);
    }
    void *model = s->instance; /* (`reset` may have replaced the first) */
    s->instance = NULL;
    reset_context(&s->ctx);
    s->model->destroy(model);
    return rc;
}

int mote_script_run_file(const char *path, const mote_model *const *models, size_t nmodels,
                         const mote_script_options *opt)
{
    mote_err err;
    clear(&err);
    mote_script *s;
    if (mote_script_load_params(&s, path, opt->params, opt->nparams, models, nmodels, &err)) {
        fprintf(opt->diag, "%s\n", err.msg);
        return 1;
    }
    char unused[256];
    mote_script_unused_params(s, unused, sizeof unused);
    if (unused[0])
        fprintf(opt->diag, "%s: warning: the script uses no ${NAME} of the parameter%s %s\n",
                mote_script_context(s)->script_path, strchr(unused, ',') ? "s" : "", unused);
    mote_context *ctx = mote_script_context(s);
    s->live_port = opt->live ? opt->live_port : -1;
    s->live_bind = opt->live_bind;
    ctx->out = opt->out;
    ctx->diag = opt->diag;
    ctx->terminal = opt->terminal;
    ctx->check_only = opt->check_only;
    ctx->quiet = opt->quiet;
    ctx->ranks = opt->ranks;
    ctx->interrupt = opt->interrupt;
    ctx->interrupt_arg = opt->interrupt_arg;
    if (s->ncalls == 0)
        fprintf(opt->diag, "%s: warning: the script has no commands\n", path);
    int status = 0;
    if (mote_script_validate(s, &err)) {
        fprintf(opt->diag, "%s\n", err.msg);
        status = 1;
    } else if (opt->check_only) {
        fprintf(opt->out, "%s: ok: %zu command%s for model %s\n", path, s->ncalls,
                s->ncalls == 1 ? "" : "s", s->model->name);
    } else if (mote_script_execute(s, &err)) {
        fflush(opt->out);
        fprintf(opt->diag, "%s\n", err.msg);
        status = 2;
    }
    fflush(opt->out);
    mote_script_free(s);
    return status;
}
