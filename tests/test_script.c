/* test_script.c: the script language and the `mote` program, driven with fake models: lexing
 * (blank lines, comments, CRLF, quotes), argument conversion and its error messages (exact
 * FILE:LINE:COL prefixes), model selection, validation before execution (nothing runs when a
 * later line is wrong), runtime errors (exit status 2, located), output_dir, help and usage. */
#include "mote/script.h"
#include "test.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- a fake model that records what ran ------------------------------------------------------ */

/* What the fake model's commands did; reset before each script. Tests may keep globals. */
static struct {
    int creates_dry, creates_real, destroys;
    int checks, runs;
    int settles, settles_at_status; /* settle calls; settles seen by the latest status line */
    int settle_fail_at;             /* the settle call (1-based) that fails; 0 = none */
    long long last_k;
    unsigned long long last_seed;
    int last_nargs;
    char last_path[1024];
    char plot_in[1024], plot_out[1024]; /* the paths the model's plot hook received */
    char load_kind[32];                 /* the kind load's check found for its input ("" none) */
    char variant[32];                   /* ctx->model_variant when the model was created */
    double opt_mass, opt_x;             /* the options `place` received (NAN: not given) */
    int opt_n;
} LOG;

typedef struct {
    int dry;
    int has_system;
} fake;

static void *fake_create(mote_context *ctx, int dry)
{
    snprintf(LOG.variant, sizeof LOG.variant, "%s", ctx ? ctx->model_variant : "");
    fake *f = calloc(1, sizeof *f);
    if (f)
        f->dry = dry;
    if (dry)
        LOG.creates_dry++;
    else
        LOG.creates_real++;
    return f;
}

static void fake_destroy(void *m)
{
    LOG.destroys++;
    free(m);
}

static void fake_status(void *m, FILE *out)
{
    LOG.settles_at_status = LOG.settles;
    fprintf(out, "status runs=%d\n", LOG.runs);
}

static int fake_settle(void *m, mote_err *err)
{
    if (++LOG.settles == LOG.settle_fail_at)
        return mote_fail(err, MOTE_ENOMEM, "settle: simulated failure");
    return 0;
}

static int new_check(void *m, const mote_call *c, mote_err *err)
{
    LOG.checks++; /* the ranges of NN and eta are the table's (checked by the script layer) */
    ((fake *)m)->has_system = 1;
    return 0;
}

static int new_run(void *m, const mote_call *c, mote_err *err)
{
    LOG.runs++;
    ((fake *)m)->has_system = 1;
    return 0;
}

static int step_check(void *m, const mote_call *c, mote_err *err)
{
    LOG.checks++;
    if (!((fake *)m)->has_system)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "step: no system yet");
    return 0;
}

static int step_run(void *m, const mote_call *c, mote_err *err)
{
    LOG.runs++;
    LOG.last_k = c->args[0].i;
    return 0;
}

static int compress_run(void *m, const mote_call *c, mote_err *err)
{
    LOG.runs++;
    LOG.last_k = c->args[2].i;
    return 0;
}

static void fake_seed(void *m, uint64_t seed)
{
    LOG.runs++;
    LOG.last_seed = seed;
}

static int save_check(void *m, const mote_call *c, mote_err *err)
{
    LOG.checks++;
    char *path = mote_ctx_path(c->ctx, c->args[0].text);
    if (!path)
        return mote_call_fail(err, c, 0, MOTE_ENOMEM, "out of memory");
    int ok = mote_ctx_dir_ok(c->ctx, path);
    int rc = ok ? 0
                : mote_call_fail(err, c, 0, MOTE_EINVAL, "save: the directory of '%s' does not "
                                 "exist", path);
    free(path);
    return rc;
}

static int save_run(void *m, const mote_call *c, mote_err *err)
{
    LOG.runs++;
    char *path = mote_ctx_path(c->ctx, c->args[0].text);
    if (!path)
        return mote_call_fail(err, c, 0, MOTE_ENOMEM, "out of memory");
    snprintf(LOG.last_path, sizeof LOG.last_path, "%s", path);
    FILE *f = fopen(path, "w");
    int rc = 0;
    if (!f)
        rc = mote_call_fail(err, c, 0, MOTE_EIO, "save: cannot write '%s'", path);
    else
        fclose(f);
    free(path);
    return rc;
}

static int load_check(void *m, const mote_call *c, mote_err *err)
{
    LOG.checks++;
    const char *kind = mote_outputs_find(&c->ctx->outputs, c->args[0].path);
    snprintf(LOG.load_kind, sizeof LOG.load_kind, "%s", kind ? kind : "");
    return 0;
}

static int fake_plot(void *m, const char *in, const char *out, const mote_call *c, mote_err *err)
{
    LOG.runs++;
    snprintf(LOG.plot_in, sizeof LOG.plot_in, "%s", in);
    snprintf(LOG.plot_out, sizeof LOG.plot_out, "%s", out);
    return 0;
}

static int place_run(void *m, const mote_call *c, mote_err *err)
{
    LOG.runs++;
    LOG.opt_mass = mote_call_opt_r(c, "mass", NAN);
    LOG.opt_x = mote_call_opt_r(c, "x", NAN);
    LOG.opt_n = c->nopts;
    LOG.last_nargs = c->nargs;
    return 0;
}

static int opts_run(void *m, const mote_call *c, mote_err *err)
{
    LOG.runs++;
    LOG.last_nargs = c->nargs;
    return 0;
}

/* A runtime failure whose message the command did not locate. */
static int boom_run(void *m, const mote_call *c, mote_err *err)
{
    LOG.runs++;
    err->code = MOTE_ERUNTIME;
    err->located = 0;
    snprintf(err->msg, sizeof err->msg, "boom: simulated failure");
    return MOTE_ERUNTIME;
}

static int boom_at_run(void *m, const mote_call *c, mote_err *err)
{
    LOG.runs++;
    return mote_call_fail(err, c, 0, MOTE_EIO, "boom_at: cannot write '%s'", c->args[0].text);
}

static const mote_cmd fake_cmds[] = { /* the model every test script drives by default */
    {"new", NULL, "i>=2 r(0,0.74)", "new NN eta", "make a system", "Make a system of NN x NN spheres.",
     new_check, new_run},
    {"step", NULL, "i>=1", "step K", "run K collisions per particle", "Run.", step_check, step_run},
    {"compress_left_wall", "compressl", "rri", "compress_left_wall eta dLmax K",
     "move the left wall", "Compress.", NULL, compress_run},
    {"compress_two_walls", "compresst compress_both_walls", "rri",
     "compress_two_walls eta dLmax K", "move both walls", "Compress both.", NULL, compress_run},
    {"save", NULL, "f>state", "save FILE", "write the state", "Save.", save_check, save_run},
    {"load", NULL, "f<state", "load FILE", "read a state", "Load.", load_check, opts_run},
    {"measure", NULL, "i r[0,1] u<=100 f>data", "measure K x u FILE", "write data", "Measure.",
     NULL, opts_run},
    {"place", NULL, "s mass=r>0! x=r file=f>data", "place NAME mass=M [x=X] [file=F]",
     "place a body", "Place.", NULL, place_run},
    {"opts", NULL, "*", "opts KEY=VALUE...", "any tokens", "Options.", NULL, opts_run},
    {"name", NULL, "s", "name S", "a string", "Name.", NULL, opts_run},
    {"boom", NULL, "", "boom", "fail at run time", "Fails.", NULL, boom_run},
    {"boom_at", NULL, "f", "boom_at FILE", "fail at run time, located", "Fails at FILE.", NULL,
     boom_at_run},
};

static const mote_model fake_model = {
    .name = "hard-spheres",
    .summary = "fake hard spheres",
    .cmds = fake_cmds,
    .ncmds = sizeof fake_cmds / sizeof fake_cmds[0],
    .create = fake_create,
    .destroy = fake_destroy,
    .status = fake_status,
    .settle = fake_settle,
    .seed = fake_seed,
    .seed_help = "Fake seeding.",
    .plot_kinds = "data|other",
    .plot = fake_plot,
    .plot_help = "Fake pictures.",
};

static const mote_cmd other_cmds[] = {
    {"ping", NULL, "", "ping", "count a run", "Ping.", NULL, opts_run},
};

static const mote_model other_model = {
    .name = "mixing-box",
    .summary = "another fake",
    .variants = "alpha|beta",
    .cmds = other_cmds,
    .ncmds = 1,
    .create = fake_create,
    .destroy = fake_destroy,
};

static const mote_model *const MODELS[] = {&fake_model, &other_model};
static const size_t NMODELS = 2;

/* ---- helpers -------------------------------------------------------------------------------- */

static char TMP[256]; /* the test's scratch directory, also its working directory */

typedef struct {
    int status;
    char path[512];
    char out[65536];
    char err[65536];
} result;

static void slurp(FILE *f, char *buf, size_t cap)
{
    rewind(f);
    size_t n = fread(buf, 1, cap - 1, f);
    buf[n] = '\0';
    fclose(f);
}

static void write_file(const char *path, const char *text, size_t len)
{
    FILE *f = fopen(path, "wb");
    if (!f) {
        printf("cannot write %s\n", path);
        return;
    }
    fwrite(text, 1, len, f);
    fclose(f);
}

/* Write `text` to NAME in the scratch directory and run (or check) it. */
static result *run_text(result *r, const char *name, const char *text, int check_only)
{
    memset(&LOG, 0, sizeof LOG);
    snprintf(r->path, sizeof r->path, "%s", name);
    write_file(r->path, text, strlen(text));
    FILE *out = tmpfile(), *diag = tmpfile();
    mote_script_options opt = {.out = out, .diag = diag, .check_only = check_only};
    r->status = mote_script_run_file(r->path, MODELS, NMODELS, &opt);
    slurp(out, r->out, sizeof r->out);
    slurp(diag, r->err, sizeof r->err);
    return r;
}

/* Does the error output start with "NAME:LINE:COL: error: " and contain each key word? */
static void expect_error(const result *r, int status, int line, int col, const char *k1,
                         const char *k2, const char *k3)
{
    char prefix[600];
    snprintf(prefix, sizeof prefix, "%s:%d:%d: error: ", r->path, line, col);
    CHECK_INT(r->status, status);
    CHECK(strncmp(r->err, prefix, strlen(prefix)) == 0, "expected prefix '%s' in: %s", prefix,
          r->err);
    CHECK(strstr(r->err + strlen(prefix), "error:") == NULL, "location given twice: %s", r->err);
    const char *keys[3] = {k1, k2, k3};
    for (int i = 0; i < 3; i++)
        if (keys[i])
            CHECK_HAS(r->err, keys[i]);
    /* exactly one line of diagnostics */
    const char *nl = strchr(r->err, '\n');
    CHECK(nl && nl[1] == '\0', "one diagnostic line expected, got: %s", r->err);
}

static mote_script *parse(const char *text, size_t len, mote_err *err)
{
    mote_script *s = NULL;
    mote_script_parse(&s, "mem.mote", text, len, MODELS, NMODELS, err);
    return s;
}

/* Run the whole program on argv, capturing both streams. */
static int main_io(result *r, int argc, const char **argv)
{
    memset(&LOG, 0, sizeof LOG);
    FILE *out = tmpfile(), *diag = tmpfile();
    char *args[16];
    for (int i = 0; i < argc && i < 16; i++)
        args[i] = (char *)argv[i];
    r->status = mote_script_main_io(argc, args, MODELS, NMODELS, out, diag, 0);
    slurp(out, r->out, sizeof r->out);
    slurp(diag, r->err, sizeof r->err);
    return r->status;
}

/* ---- tests ---------------------------------------------------------------------------------- */

static void test_lexing(void)
{
    const char *text = "# a comment line\n"
                       "\n"
                       "   \t  \n"
                       "new 10 0.3   # trailing comment\n"
                       "\tstep\t+25 \n"
                       "save \"my file.dat\"\n"
                       "save \"a\\\"b\\\\c\"   #\"not a string\n"
                       "opts a=1 \"b c\" #x d\n"
                       "name x#y\n"
                       "save \"\xc3\xa9t\xc3\xa9.dat\"";
    mote_err err = {0};
    mote_script *s = parse(text, strlen(text), &err);
    CHECK(s != NULL, "parse failed: %s", err.msg);
    if (!s)
        return;
    CHECK_INT(mote_script_ncalls(s), 7);
    CHECK_STR(mote_script_model(s)->name, "hard-spheres");
    const mote_call *c = mote_script_call(s, 0);
    CHECK_STR(c->name, "new");
    CHECK_INT(c->line, 4);
    CHECK_INT(c->col, 1);
    CHECK_INT(c->nargs, 2);
    CHECK_INT(c->args[0].i, 10);
    CHECK_NEAR(c->args[1].r, 0.3, 0);
    CHECK_INT(c->args[1].col, 8);
    CHECK_STR(c->source, "new 10 0.3");
    CHECK_STR(c->file, "mem.mote");
    c = mote_script_call(s, 1);
    CHECK_INT(c->line, 5);
    CHECK_INT(c->col, 2);
    CHECK_INT(c->args[0].i, 25);
    CHECK_INT(c->args[0].col, 7);
    CHECK_STR(c->source, "step\t+25");
    c = mote_script_call(s, 2);
    CHECK_STR(c->args[0].text, "my file.dat");
    CHECK_INT(c->args[0].quoted, 1);
    CHECK_INT(c->args[0].col, 6);
    c = mote_script_call(s, 3);
    CHECK_STR(c->args[0].text, "a\"b\\c");
    CHECK_STR(c->source, "save \"a\\\"b\\\\c\"");
    c = mote_script_call(s, 4);
    CHECK_INT(c->nargs, 2);
    CHECK_STR(c->args[1].text, "b c");
    c = mote_script_call(s, 5);
    CHECK_STR(c->args[0].text, "x#y"); /* '#' inside a word is not a comment */
    c = mote_script_call(s, 6);
    CHECK_STR(c->args[0].text, "\xc3\xa9t\xc3\xa9.dat");
    CHECK_INT(c->line, 10);
    mote_script_free(s);

    /* CRLF gives the same calls; so does a byte-order mark */
    const char *crlf = "\xEF\xBB\xBFnew 10 0.3\r\n\r\nstep 5 # c\r\nsave \"x y\"\r\n";
    s = parse(crlf, strlen(crlf), &err);
    CHECK(s != NULL, "CRLF parse failed: %s", err.msg);
    if (s) {
        CHECK_INT(mote_script_ncalls(s), 3);
        CHECK_STR(mote_script_call(s, 1)->source, "step 5");
        CHECK_INT(mote_script_call(s, 1)->line, 3);
        CHECK_STR(mote_script_call(s, 2)->args[0].text, "x y");
        CHECK_INT(mote_script_call(s, 0)->col, 1);
        mote_script_free(s);
    }

    /* no line-length limit */
    size_t big = 200000;
    char *line = malloc(big + 16);
    if (line) {
        memcpy(line, "opts ", 5);
        size_t k = 5;
        while (k + 2 < big + 5) {
            line[k++] = 'a';
            line[k++] = ' ';
        }
        line[k] = '\0';
        s = parse(line, k, &err);
        CHECK(s != NULL, "long line: %s", err.msg);
        if (s) {
            CHECK_INT(mote_script_call(s, 0)->nargs, (int)((k - 5) / 2));
            mote_script_free(s);
        }
        free(line);
    }

    /* an empty script and a comments-only script are valid and do nothing */
    s = parse("", 0, &err);
    CHECK(s && mote_script_ncalls(s) == 0, "empty script");
    mote_script_free(s);
    result r;
    run_text(&r, "comments.mote", "# nothing\n\n   # here\n", 0);
    CHECK_INT(r.status, 0);
    CHECK_INT(LOG.creates_real, 1);
    CHECK_HAS(r.err, "warning: the script has no commands");
}

static void test_lexical_errors(void)
{
    result r;
    run_text(&r, "quote.mote", "new 10 0.3\nsave \"never closed.dat\n", 0);
    expect_error(&r, 1, 2, 6, "unterminated quoted string", NULL, NULL);
    CHECK_INT(LOG.runs, 0);

    run_text(&r, "quote2.mote", "save \"ends with backslash\\\"\n", 0);
    expect_error(&r, 1, 1, 6, "unterminated", NULL, NULL);

    run_text(&r, "escape.mote", "save \"C:\\data\"\n", 0);
    expect_error(&r, 1, 1, 9, "unknown escape '\\d'", NULL, NULL);

    run_text(&r, "mid.mote", "save abc\"def\"\n", 0);
    expect_error(&r, 1, 1, 9, "unexpected '\"' inside a word", NULL, NULL);

    run_text(&r, "after.mote", "save \"abc\"def\n", 0);
    expect_error(&r, 1, 1, 11, "expected a space after the closing quote", NULL, NULL);

    run_text(&r, "qcmd.mote", "\"step\" 10\n", 0);
    expect_error(&r, 1, 1, 1, "expected a command name", "\"step\"", NULL);

    run_text(&r, "ctrl.mote", "new 10 0.3\nstep\f10\n", 0);
    expect_error(&r, 1, 2, 5, "control character", "0x0c", NULL);

    run_text(&r, "cr.mote", "new 10 0.3\rstep 10\n", 0);
    expect_error(&r, 1, 1, 11, "carriage return", NULL, NULL);

    char nul[] = "new 10 0.3\nstep 1\0 0\n";
    write_file("nul.mote", nul, sizeof nul - 1);
    memset(&LOG, 0, sizeof LOG);
    FILE *out = tmpfile(), *diag = tmpfile();
    mote_script_options opt = {.out = out, .diag = diag, .check_only = 0};
    r.status = mote_script_run_file("nul.mote", MODELS, NMODELS, &opt);
    snprintf(r.path, sizeof r.path, "nul.mote");
    slurp(out, r.out, sizeof r.out);
    slurp(diag, r.err, sizeof r.err);
    expect_error(&r, 1, 2, 7, "control character", "0x00", NULL);

    /* columns count characters, not bytes */
    run_text(&r, "utf8.mote", "save \"\xc3\xa9\" x\n", 0);
    expect_error(&r, 1, 1, 10, "too many arguments", NULL, NULL);
}

static void test_commands_and_arity(void)
{
    result r;
    run_text(&r, "typo.mote", "new 10 0.3\n  stpe 10\n", 0);
    expect_error(&r, 1, 2, 3, "unknown command 'stpe'", "did you mean 'step'?", NULL);

    run_text(&r, "typo2.mote", "new 10 0.3\ncompresl 0.4 0.1 10\n", 0);
    expect_error(&r, 1, 2, 1, "unknown command 'compresl'", "did you mean 'compressl'?", NULL);

    run_text(&r, "upper.mote", "new 10 0.3\nSTEP 10\n", 0);
    expect_error(&r, 1, 2, 1, "unknown command 'STEP'", "did you mean 'step'?", "lower-case");

    run_text(&r, "far.mote", "new 10 0.3\nfrobnicate 10\n", 0);
    expect_error(&r, 1, 2, 1, "unknown command 'frobnicate'", "mote help", NULL);
    CHECK(strstr(r.err, "did you mean") == NULL, "no suggestion expected: %s", r.err);

    /* the original document's example: 4 numbers where 3 are expected */
    run_text(&r, "many.mote", "new 10 0.3\ncompressl 0.49 0.503423 0.000001 10\n", 0);
    expect_error(&r, 1, 2, 34, "compressl: too many arguments",
                 "expected 'compress_left_wall eta dLmax K' (3 arguments)", "found 4");
    CHECK_INT(LOG.runs, 0);

    run_text(&r, "few.mote", "new 10 0.3\n   step\n", 0);
    expect_error(&r, 1, 2, 4, "step: too few arguments", "expected 'step K' (1 argument)",
                 "found 0");

    run_text(&r, "none.mote", "boom now\n", 0);
    expect_error(&r, 1, 1, 6, "boom: too many arguments", "(0 arguments)", NULL);

    /* aliases resolve to the canonical name */
    mote_err err = {0};
    const char *text = "compresst 0.4 0.1 5\ncompress_both_walls 0.4 0.1 6\n";
    mote_script *s = parse(text, strlen(text), &err);
    CHECK(s != NULL, "%s", err.msg);
    if (s) {
        CHECK_STR(mote_script_call(s, 0)->name, "compress_two_walls");
        CHECK_STR(mote_script_call(s, 0)->written, "compresst");
        CHECK_STR(mote_script_call(s, 1)->name, "compress_two_walls");
        CHECK_INT(mote_script_call(s, 1)->args[2].i, 6);
        mote_script_free(s);
    }
}

static void test_numbers(void)
{
    result r;
    run_text(&r, "i1.mote", "new 10 0.3\nstep 1e3\n", 0);
    expect_error(&r, 1, 2, 6, "step: expected an integer for K, found '1e3'", NULL, NULL);

    run_text(&r, "i2.mote", "new 10 0.3\nstep -5\n", 0);
    expect_error(&r, 1, 2, 6, "step: expected a non-negative integer for K, found '-5'", NULL,
                 NULL);

    run_text(&r, "i3.mote", "new 10 0.3\nstep 12x\n", 0);
    expect_error(&r, 1, 2, 6, "step: expected an integer for K, found '12x'", NULL, NULL);

    /* a count is an int: 2^31 is too large (it wrapped to a negative int, issue 52) */
    run_text(&r, "i4.mote", "new 10 0.3\nstep 2147483648\n", 0);
    expect_error(&r, 1, 2, 6, "step: K is too large (at most 2147483647)", NULL, NULL);

    run_text(&r, "i5.mote", "new 10 0.3\nstep \"10\"\n", 0);
    expect_error(&r, 1, 2, 6, "expected an integer for K", "without quotes", NULL);

    run_text(&r, "i6.mote", "new 10 0.3\nstep +\n", 0);
    expect_error(&r, 1, 2, 6, "expected an integer for K, found '+'", NULL, NULL);

    run_text(&r, "u1.mote", "seed 18446744073709551616\n", 0);
    expect_error(&r, 1, 1, 6, "seed: S is too large", "18446744073709551615", NULL);

    run_text(&r, "u2.mote", "seed 18446744073709551615\nstep 1\n", 1);
    expect_error(&r, 1, 2, 1, "step: no system yet", NULL, NULL);

    run_text(&r, "u3.mote", "seed +18446744073709551615\nnew 2 0.5\nstep 2147483647\n", 0);
    CHECK_INT(r.status, 0);
    CHECK(LOG.last_seed == 18446744073709551615ull, "seed %llu", LOG.last_seed);
    CHECK(LOG.last_k == 2147483647ll, "k %lld", LOG.last_k);

    static const struct {
        const char *value, *key;
    } bad_reals[] = {
        {"abc", "found 'abc'"},
        {"nan", "NaN are not accepted"},
        {"inf", "NaN are not accepted"},
        {"-Infinity", "NaN are not accepted"},
        {"0x10", "hexadecimal"},
        {"1e", "found '1e'"},
        {".", "found '.'"},
        {"0,5", "decimal point is '.'"},
        {"1.5.2", "found '1.5.2'"},
        {"1e5x", "found '1e5x'"},
        {"--1", "found '--1'"},
    };
    for (size_t i = 0; i < sizeof bad_reals / sizeof bad_reals[0]; i++) {
        char text[128];
        snprintf(text, sizeof text, "new 10 %s\n", bad_reals[i].value);
        run_text(&r, "r.mote", text, 0);
        expect_error(&r, 1, 1, 8, "new: expected a real number for eta", bad_reals[i].key,
                     NULL);
    }
    run_text(&r, "r2.mote", "new 10 1e999\n", 0);
    expect_error(&r, 1, 1, 8, "new: eta is out of the range", "'1e999'", NULL);

    static const struct {
        const char *value;
        double x;
    } good_reals[] = {{".5", 0.5}, {"5.", 5.0}, {"-1e-3", -1e-3}, {"+2.5E+1", 25.0},
                      {"0", 0.0},  {"007", 7.0}, {"1e-400", 0.0}};
    for (size_t i = 0; i < sizeof good_reals / sizeof good_reals[0]; i++) {
        char text[128];
        snprintf(text, sizeof text, "compressl %s 0.1 1\n", good_reals[i].value);
        mote_err err = {0};
        mote_script *s = parse(text, strlen(text), &err);
        CHECK(s != NULL, "'%s' rejected: %s", good_reals[i].value, err.msg);
        if (s) {
            CHECK_NEAR(mote_script_call(s, 0)->args[0].r, good_reals[i].x, 0);
            mote_script_free(s);
        }
    }

    /* an empty quoted file name */
    run_text(&r, "f.mote", "save \"\"\n", 0);
    expect_error(&r, 1, 1, 6, "save: expected a file name for FILE", "empty", NULL);
}

static void test_models(void)
{
    result r;
    run_text(&r, "m1.mote", "# choose\n\nmodel mixing-box\nping\n", 0);
    CHECK_INT(r.status, 0);
    CHECK_INT(LOG.runs, 1);
    CHECK_STR(r.out, ""); /* mixing-box has no status function */

    run_text(&r, "m2.mote", "model mixing-box\nstep 10\n", 0);
    expect_error(&r, 1, 2, 1, "unknown command 'step'", NULL, NULL);

    run_text(&r, "m3.mote", "new 10 0.3\nmodel hard-spheres\n", 0);
    expect_error(&r, 1, 2, 1, "model", "first command", NULL);

    run_text(&r, "m4.mote", "model hard-spheres\nnew 10 0.3\nmodel hard-spheres\n", 0);
    expect_error(&r, 1, 3, 1, "only one 'model' command", "line 1", NULL);

    run_text(&r, "m5.mote", "model hardspheres\n", 0);
    expect_error(&r, 1, 1, 7, "unknown model 'hardspheres'", "did you mean 'hard-spheres'?",
                 "known models: hard-spheres, mixing-box");

    run_text(&r, "m6.mote", "model galaxy\n", 0);
    expect_error(&r, 1, 1, 7, "unknown model 'galaxy'", "known models: hard-spheres, mixing-box",
                 NULL);

    run_text(&r, "m7.mote", "model\n", 0);
    expect_error(&r, 1, 1, 1, "model: expected 'model NAME [VARIANT]', found 0 arguments", NULL,
                 NULL);

    /* variants: the default is the first; others are checked against the model's list */
    run_text(&r, "v1.mote", "model mixing-box\nping\n", 0);
    CHECK_INT(r.status, 0);
    CHECK_STR(LOG.variant, "alpha");
    run_text(&r, "v2.mote", "model mixing-box beta\nping\n", 0);
    CHECK_INT(r.status, 0);
    CHECK_STR(LOG.variant, "beta");
    run_text(&r, "v3.mote", "model mixing-box gamma\n", 0);
    expect_error(&r, 1, 1, 18, "model: the mixing-box model's variant is one of alpha|beta, found 'gamma'",
                 NULL, NULL);
    run_text(&r, "v4.mote", "model hard-spheres beta\n", 0);
    expect_error(&r, 1, 1, 20, "model: the hard-spheres model has no variants, found 'beta'", NULL,
                 NULL);
    run_text(&r, "v5.mote", "model mixing-box beta extra\n", 0);
    expect_error(&r, 1, 1, 23, "model: expected 'model NAME [VARIANT]', found 3 arguments", NULL,
                 NULL);

    /* a registry without the default model needs a model line */
    const mote_model *const only_other[] = {&other_model};
    mote_script *s = NULL;
    mote_err err = {0};
    CHECK(mote_script_parse(&s, "x.mote", "ping\n", 5, only_other, 1, &err) != 0, "accepted");
    CHECK_HAS(err.msg, "x.mote:1:1: error: the first command must be 'model NAME'");
    CHECK(s == NULL, "script returned on error");
}

static void test_validation_first(void)
{
    result r;
    /* a range error on the last line: nothing runs, no real model is created */
    run_text(&r, "late.mote", "new 10 0.3\nstep 10\nsave out.dat\nstep 0\n", 0);
    expect_error(&r, 1, 4, 6, "step: K must be >= 1, found 0", NULL, NULL);
    CHECK_INT(LOG.runs, 0);
    CHECK_INT(LOG.creates_real, 0);
    CHECK_INT(LOG.creates_dry, 1);
    CHECK_INT(LOG.destroys, 1);
    CHECK(access("out.dat", F_OK) != 0, "out.dat was written");
    CHECK_STR(r.out, "");

    /* a dependency checked on the dry model: step before any new */
    run_text(&r, "nosys.mote", "seed 1\nstep 10\nnew 10 0.3\n", 0);
    expect_error(&r, 1, 2, 1, "step: no system yet", NULL, NULL);
    CHECK_INT(LOG.runs, 0);

    /* a valid script runs every command in order, with a status line after each model command */
    run_text(&r, "good.mote", "new 10 0.3\necho hello   \"big  world\"  # c\nstep 7\n", 0);
    CHECK_INT(r.status, 0);
    CHECK_INT(LOG.runs, 2);
    CHECK_INT(LOG.last_k, 7);
    CHECK_INT(LOG.creates_dry, 1);
    CHECK_INT(LOG.creates_real, 1);
    CHECK_INT(LOG.destroys, 2);
    CHECK_STR(r.out, "status runs=1\nhello big  world\nstatus runs=2\n");
    CHECK_STR(r.err, "");

    /* check only: validates, runs nothing */
    run_text(&r, "good.mote", "new 10 0.3\nstep 7\n", 1);
    CHECK_INT(r.status, 0);
    CHECK_INT(LOG.runs, 0);
    CHECK_INT(LOG.creates_real, 0);
    CHECK_HAS(r.out, "good.mote: ok: 2 commands for model hard-spheres");

    /* threads */
    run_text(&r, "t0.mote", "threads 0\n", 0);
    expect_error(&r, 1, 1, 9, "threads: N must be >= 1, found 0", NULL, NULL);
    run_text(&r, "t4.mote", "threads 4\nthreads 2\n", 0);
    CHECK_INT(r.status, 0);
    CHECK_HAS(r.err, "t4.mote:1:1: note: threads");
    CHECK(strstr(r.err, "t4.mote:2:1") == NULL, "note printed twice: %s", r.err);

    /* star arguments */
    run_text(&r, "opts.mote", "opts\nopts a b \"c d\" 4\n", 0);
    CHECK_INT(r.status, 0);
    CHECK_INT(LOG.last_nargs, 4);
}

/* The argument specs of the tables: ranges checked and files tracked by the script layer. */
static void test_argument_specs(void)
{
    result r;
    /* ranges: closed and open bounds, intervals, named as the synopsis names them */
    run_text(&r, "r1.mote", "new 1 0.3\n", 0);
    expect_error(&r, 1, 1, 5, "new: NN must be >= 2, found 1", NULL, NULL);
    run_text(&r, "r2.mote", "new 2 0.74\n", 0);
    expect_error(&r, 1, 1, 7, "new: eta must be in (0, 0.74), found 0.74", NULL, NULL);
    run_text(&r, "r3.mote", "new 2 0\n", 0);
    expect_error(&r, 1, 1, 7, "new: eta must be in (0, 0.74), found 0", NULL, NULL);
    run_text(&r, "r4.mote", "new 2 0.7399\nmeasure 1 1.5 3 d.dat\n", 0);
    expect_error(&r, 1, 2, 11, "measure: x must be in [0, 1], found 1.5", NULL, NULL);
    run_text(&r, "r5.mote", "measure 1 0 101 d.dat\n", 0);
    expect_error(&r, 1, 1, 13, "measure: u must be <= 100, found 101", NULL, NULL);
    run_text(&r, "r6.mote", "measure 0 1 100 d.dat\nmeasure 0 0 0 e.dat\n", 1);
    CHECK_INT(r.status, 0);
    /* a range error comes before the command's own check, which never sees the bad value */
    run_text(&r, "r7.mote", "new 0 0.3\n", 0);
    CHECK_INT(LOG.checks, 0);

    /* outputs: recorded with their kind; inputs must be written earlier or exist */
    run_text(&r, "f1.mote", "save s.state\nload s.state\n", 1);
    CHECK_INT(r.status, 0);
    CHECK_STR(LOG.load_kind, "state");
    run_text(&r, "f2.mote", "measure 1 0 1 d.dat\nload d.dat\n", 0);
    expect_error(&r, 1, 2, 6, "load: 'd.dat' is written earlier in this script as a file of kind "
                              "data; expected a file of kind state", NULL, NULL);
    run_text(&r, "f3.mote", "load nosuch.state\n", 0);
    expect_error(&r, 1, 1, 6, "load: 'nosuch.state' does not exist and no earlier command writes it",
                 NULL, NULL);
    write_file("old.state", "x", 1); /* a file that exists is accepted as it is */
    run_text(&r, "f4.mote", "load old.state\n", 1);
    CHECK_INT(r.status, 0);
    CHECK_STR(LOG.load_kind, ""); /* an existing file has no kind in this script */
    run_text(&r, "f5.mote", "measure 1 0 1 nodir/d.dat\n", 0);
    expect_error(&r, 1, 1, 15, "measure: the directory of output file 'nodir/d.dat' does not exist",
                 NULL, NULL);
    run_text(&r, "f6.mote", "measure 1 0 1 d.dat\nmeasure 1 0 1 d.dat\n", 1);
    CHECK_INT(r.status, 0);
    CHECK_HAS(r.err, "f6.mote:2:1: warning: measure: 'd.dat' is written more than once");

    /* the common plot: inputs of the model's plot kinds, paths resolved against output_dir */
    run_text(&r, "p1.mote", "output_dir pd\nmeasure 1 0 1 d.dat\nplot d.dat d.png\n", 0);
    CHECK_INT(r.status, 0);
    CHECK_STR(LOG.plot_in, "pd/d.dat");
    CHECK_STR(LOG.plot_out, "pd/d.png");
    CHECK_HAS(r.out, "plot: wrote pd/d.png");
    run_text(&r, "p2.mote", "save s.state\nplot s.state s.png\n", 0);
    expect_error(&r, 1, 2, 6, "expected a file of kind data or other", NULL, NULL);
    CHECK_INT(LOG.runs, 0);
    /* (a model without pictures of its own draws lines of any data file) */
    run_text(&r, "p3.mote", "model mixing-box\nplot a.dat a.png\n", 0);
    expect_error(&r, 1, 2, 6, "plot: 'a.dat' does not exist and no earlier command writes it",
                 NULL, NULL);
    run_text(&r, "p4.mote", "model mixing-box\nseed 3\n", 0);
    expect_error(&r, 1, 2, 1, "seed: the mixing-box model draws no random numbers", NULL, NULL);
    run_text(&r, "p5.mote", "seed 3\n", 0);
    CHECK_INT(r.status, 0);
    CHECK(LOG.last_seed == 3, "seed hook got %llu", LOG.last_seed);
    CHECK_STR(r.out, "seed: 3\n");

    /* options: key=value in any order, converted and range-checked by their specs */
    run_text(&r, "o1.mote", "place sun x=-2.5 mass=3\nplace moon mass=1e-3\n", 0);
    CHECK_INT(r.status, 0);
    CHECK(LOG.opt_mass == 1e-3 && isnan(LOG.opt_x) && LOG.opt_n == 1 && LOG.last_nargs == 1,
          "options: mass %g x %g n %d nargs %d", LOG.opt_mass, LOG.opt_x, LOG.opt_n,
          LOG.last_nargs);
    run_text(&r, "o2.mote", "place sun x=1\n", 0);
    expect_error(&r, 1, 1, 1, "place: option mass= is required", NULL, NULL);
    run_text(&r, "o3.mote", "place sun mass=0\n", 0);
    expect_error(&r, 1, 1, 16, "place: mass must be > 0, found 0", NULL, NULL);
    run_text(&r, "o4.mote", "place sun mass=1 mas=2\n", 0);
    expect_error(&r, 1, 1, 18, "place: unknown option 'mas'; did you mean 'mass'?",
                 "(options: mass, x, file)", NULL);
    run_text(&r, "o5.mote", "place sun mass=1 mass=2\n", 0);
    expect_error(&r, 1, 1, 18, "place: option 'mass' given twice", NULL, NULL);
    run_text(&r, "o6.mote", "place sun mass=heavy\n", 0);
    expect_error(&r, 1, 1, 16, "place: expected a real number for mass, found 'heavy'", NULL,
                 NULL);
    run_text(&r, "o7.mote", "place sun moon mass=1\n", 0);
    expect_error(&r, 1, 1, 11, "place: too many arguments", NULL, NULL);
    run_text(&r, "o8.mote", "place \"mass=1\" mass=2\n", 0); /* a quoted token is positional */
    CHECK_INT(r.status, 0);
    run_text(&r, "o9.mote", "place sun mass=1 file=nodir/p.dat\n", 0);
    expect_error(&r, 1, 1, 23, "place: the directory of output file 'nodir/p.dat' does not exist",
                 NULL, NULL);
    run_text(&r, "o10.mote", "place sun mass=1 file=p.dat\nplot p.dat p.png\n", 1);
    CHECK_INT(r.status, 0); /* an option's output is tracked like an argument's */

    /* malformed specs are caught by the table check */
    static const char *const bad_specs[] = {"i>=", "r[1,0]", "f>a|b", "x", "s>0", "f>", "r(0,1",
                                            "i>=1x", "f<A", "i>=1 f>", "k=r i", "k=r k=i",
                                            "k=", "k=q", "9=r"};
    for (size_t k = 0; k < sizeof bad_specs / sizeof bad_specs[0]; k++) {
        mote_cmd cmd = {"go", NULL, bad_specs[k], "go A", "go", "Go.", NULL, opts_run};
        mote_model model = {.name = "bad", .summary = "bad", .cmds = &cmd, .ncmds = 1,
                            .create = fake_create, .destroy = fake_destroy};
        const mote_model *const one[] = {&model};
        mote_err err = {0};
        CHECK(mote_models_verify(one, 1, &err) != 0, "spec \"%s\" accepted", bad_specs[k]);
    }
}

static void test_runtime_errors(void)
{
    result r;
    run_text(&r, "rt.mote", "new 10 0.3\nstep 1\n  boom\nstep 2\n", 0);
    expect_error(&r, 2, 3, 3, "boom: simulated failure", NULL, NULL);
    CHECK_INT(LOG.runs, 3); /* new, step, boom; the last step never ran */
    CHECK_INT(LOG.last_k, 1);
    CHECK_INT(LOG.destroys, 2);
    CHECK_STR(r.out, "status runs=1\nstatus runs=2\n");

    /* the model settles after every model command (not after common ones), before its
     * status line; a failing settle stops the run there, located at its command */
    run_text(&r, "settle.mote", "new 10 0.3\necho hi\nstep 1\nstep 2\n", 0);
    CHECK_INT(r.status, 0);
    CHECK_INT(LOG.settles, 3);
    CHECK_INT(LOG.settles_at_status, 3);
    memset(&LOG, 0, sizeof LOG);
    LOG.settle_fail_at = 2;
    const char *settle2 = "new 10 0.3\nstep 1\nstep 2\n";
    write_file("settle2.mote", settle2, strlen(settle2));
    {
        FILE *o = tmpfile(), *d = tmpfile();
        mote_script_options so = {.out = o, .diag = d, .check_only = 0};
        snprintf(r.path, sizeof r.path, "settle2.mote");
        r.status = mote_script_run_file(r.path, MODELS, NMODELS, &so);
        slurp(o, r.out, sizeof r.out);
        slurp(d, r.err, sizeof r.err);
    }
    expect_error(&r, 2, 2, 1, "settle: simulated failure", NULL, NULL);
    CHECK_INT(LOG.runs, 2); /* new, step 1; step 2 never ran */
    CHECK_STR(r.out, "status runs=1\n");

    run_text(&r, "rt2.mote", "new 10 0.3\nboom_at \"some file\"\n", 0);
    expect_error(&r, 2, 2, 9, "boom_at: cannot write 'some file'", NULL, NULL);

    /* unreadable script files name the file */
    memset(&LOG, 0, sizeof LOG);
    FILE *out = tmpfile(), *diag = tmpfile();
    mote_script_options opt = {.out = out, .diag = diag, .check_only = 0};
    r.status = mote_script_run_file("no-such-script.mote", MODELS, NMODELS, &opt);
    slurp(out, r.out, sizeof r.out);
    slurp(diag, r.err, sizeof r.err);
    CHECK_INT(r.status, 1);
    CHECK_HAS(r.err, "cannot open script 'no-such-script.mote'");
    CHECK_HAS(r.err, "No such file");
    CHECK_INT(LOG.creates_dry, 0);

    mkdir("adir.mote", 0777);
    out = tmpfile();
    diag = tmpfile();
    mote_script_options opt2 = {.out = out, .diag = diag};
    r.status = mote_script_run_file("adir.mote", MODELS, NMODELS, &opt2);
    slurp(out, r.out, sizeof r.out);
    slurp(diag, r.err, sizeof r.err);
    CHECK_INT(r.status, 1);
    CHECK_HAS(r.err, "'adir.mote'");
}

static void test_output_dir(void)
{
    result r;
    /* validation knows out/sub will exist; files land inside it */
    run_text(&r, "od.mote",
             "new 10 0.3\noutput_dir out/sub/\nsave x.dat\nsave /dev/null\noutput_dir .\n"
             "save y.dat\noutput_dir out\nsave sub/z.dat\n",
             0);
    CHECK_INT(r.status, 0);
    CHECK(r.status == 0, "%s", r.err);
    CHECK(access("out/sub/x.dat", F_OK) == 0, "out/sub/x.dat missing");
    CHECK(access("y.dat", F_OK) == 0, "y.dat missing");
    CHECK(access("out/sub/z.dat", F_OK) == 0, "out/sub/z.dat missing");
    CHECK_STR(LOG.last_path, "out/sub/z.dat");

    /* a directory nobody creates is a validation error, and nothing is created */
    run_text(&r, "od2.mote", "output_dir made\nnew 10 0.3\nsave nowhere/x.dat\n", 0);
    expect_error(&r, 1, 3, 6, "save: the directory of 'made/nowhere/x.dat' does not exist", NULL,
                 NULL);
    CHECK(access("made", F_OK) != 0, "output_dir ran during validation");

    /* parents of a pending directory exist too; ".." is understood */
    run_text(&r, "od3.mote", "output_dir p/q/r\noutput_dir .\nsave p/q/a.dat\n"
                             "save p/q/r/../b.dat\nsave ./p/q/r/c.dat\n", 1);
    CHECK(r.status == 0, "%s", r.err);
    CHECK(access("p", F_OK) != 0, "check-only created p");

    /* command.h gives room for 8 new directories; the 9th is a clear error, not an overflow */
    char many[1024] = "";
    for (int i = 1; i <= 9; i++) {
        char line[64];
        snprintf(line, sizeof line, "output_dir n%d\noutput_dir n1\n", i);
        strcat(many, line);
    }
    run_text(&r, "od9.mote", many, 1);
    expect_error(&r, 1, 17, 12, "output_dir: too many new directories", "'n9'", NULL);

    /* a file in the way */
    write_file("plainfile", "x", 1);
    run_text(&r, "od4.mote", "output_dir plainfile\n", 0);
    expect_error(&r, 1, 1, 12, "output_dir: 'plainfile' exists and is not a directory", NULL,
                 NULL);
    run_text(&r, "od5.mote", "output_dir plainfile/sub\n", 0);
    expect_error(&r, 1, 1, 12, "output_dir: cannot use 'plainfile/sub'", NULL, NULL);

    /* mote_ctx_path and mote_ctx_dir_ok directly */
    mote_context ctx;
    memset(&ctx, 0, sizeof ctx);
    char *p = mote_ctx_path(&ctx, "a.dat");
    CHECK_STR(p, "a.dat");
    free(p);
    snprintf(ctx.output_dir, sizeof ctx.output_dir, "res");
    p = mote_ctx_path(&ctx, "a.dat");
    CHECK_STR(p, "res/a.dat");
    free(p);
    p = mote_ctx_path(&ctx, "/abs/a.dat");
    CHECK_STR(p, "/abs/a.dat");
    free(p);
    snprintf(ctx.output_dir, sizeof ctx.output_dir, "/tmp/");
    p = mote_ctx_path(&ctx, "a.dat");
    CHECK_STR(p, "/tmp/a.dat");
    free(p);
    snprintf(ctx.pending_dirs[0], sizeof ctx.pending_dirs[0], "new1/new2/new3");
    ctx.npending_dirs = 1;
    CHECK(mote_ctx_dir_ok(&ctx, "new1/new2/new3/x"), "pending dir");
    CHECK(mote_ctx_dir_ok(&ctx, "new1//new2/x"), "parent of pending dir");
    CHECK(mote_ctx_dir_ok(&ctx, "./new1/x"), "parent of pending dir");
    CHECK(mote_ctx_dir_ok(&ctx, "new1/new2/new3/../x"), "..");
    CHECK(!mote_ctx_dir_ok(&ctx, "new1/other/x"), "sibling of pending dir accepted");
    CHECK(!mote_ctx_dir_ok(&ctx, "new1/new2/new3/deeper/x"), "child of pending dir accepted");
    CHECK(!mote_ctx_dir_ok(&ctx, "new1/new2/new33/x"), "prefix match accepted");
    CHECK(!mote_ctx_dir_ok(&ctx, "new1/ne/x"), "partial component accepted");
    CHECK(mote_ctx_dir_ok(&ctx, "x.dat"), "current directory");

    /* progress is silent off a terminal */
    mote_progress pr;
    mote_progress_begin(&pr, &ctx, "step");
    CHECK_INT(pr.enabled, 0);
    mote_progress_update(&pr, 0.5);
    mote_progress_end(&pr);
}

static void test_help_and_usage(void)
{
    result r;
    const char *a1[] = {"mote"};
    CHECK_INT(main_io(&r, 1, a1), 1);
    CHECK_HAS(r.err, "Usage: mote run");

    const char *a2[] = {"mote", "--version"};
    CHECK_INT(main_io(&r, 2, a2), 0);
    CHECK_STR(r.out, "mote " MOTE_VERSION "\n");

    const char *a3[] = {"mote", "help"};
    CHECK_INT(main_io(&r, 2, a3), 0);
    CHECK_HAS(r.out, "compress_left_wall (compressl)");
    CHECK_HAS(r.out, "compress_two_walls (compresst, compress_both_walls)");
    CHECK_HAS(r.out, "output_dir");
    CHECK_HAS(r.out, "Model mixing-box: another fake");
    CHECK_HAS(r.out, "ping");

    const char *a4[] = {"mote", "help", "compresst"};
    CHECK_INT(main_io(&r, 3, a4), 0);
    CHECK_HAS(r.out, "compress_two_walls eta dLmax K\n");
    CHECK_HAS(r.out, "aliases: compresst, compress_both_walls");
    CHECK_HAS(r.out, "Compress both.");

    const char *a5[] = {"mote", "help", "stpe"};
    CHECK_INT(main_io(&r, 3, a5), 1);
    CHECK_HAS(r.err, "no command or model named 'stpe'; did you mean 'step'?");

    const char *a6[] = {"mote", "help", "--markdown"};
    CHECK_INT(main_io(&r, 3, a6), 0);
    CHECK_HAS(r.out, "# mote command reference");
    CHECK_HAS(r.out, "## Model `hard-spheres`");
    CHECK_HAS(r.out, "### `compress_left_wall`\n\n```\ncompress_left_wall eta dLmax K\n```");
    CHECK_HAS(r.out, "Aliases: `compresst`, `compress_both_walls`");
    CHECK_HAS(r.out, "### `output_dir`");
    CHECK_HAS(r.out, "### `ping`");

    const char *a7[] = {"mote", "help", "output_dir"};
    CHECK_INT(main_io(&r, 3, a7), 0);
    CHECK_HAS(r.out, "mkdir -p");

    const char *a7b[] = {"mote", "help", "mixing-box"};
    CHECK_INT(main_io(&r, 3, a7b), 0);
    CHECK_HAS(r.out, "Model mixing-box: another fake");
    CHECK_HAS(r.out, "  ping");
    CHECK(strstr(r.out, "compressl") == NULL, "other models listed: %s", r.out);

    const char *a8[] = {"mote", "rn", "x"};
    CHECK_INT(main_io(&r, 3, a8), 1);
    CHECK_HAS(r.err, "did you mean 'run'?");

    write_file("cli.mote", "new 4 0.2\nstep 3\n", 17);
    const char *a9[] = {"mote", "run", "--check", "cli.mote"};
    CHECK_INT(main_io(&r, 4, a9), 0);
    CHECK_INT(LOG.runs, 0);
    const char *a10[] = {"mote", "check", "cli.mote"};
    CHECK_INT(main_io(&r, 3, a10), 0);
    CHECK_INT(LOG.runs, 0);
    const char *a11[] = {"mote", "run", "cli.mote"};
    CHECK_INT(main_io(&r, 3, a11), 0);
    CHECK_INT(LOG.runs, 2);
    const char *a12[] = {"mote", "run", "--fast", "cli.mote"};
    CHECK_INT(main_io(&r, 4, a12), 1);
    CHECK_HAS(r.err, "unknown option '--fast'");
    const char *a13[] = {"mote", "run", "a.mote", "b.mote"};
    CHECK_INT(main_io(&r, 4, a13), 1);

    /* `mote run` alone runs program.txt */
    const char *a14[] = {"mote", "run"};
    CHECK_INT(main_io(&r, 2, a14), 1);
    CHECK_HAS(r.err, "'program.txt'");
    write_file("program.txt", "new 4 0.2\r\nstep 3\r\n", 19);
    CHECK_INT(main_io(&r, 2, a14), 0);
    CHECK_INT(LOG.runs, 2);
    const char *a15[] = {"mote", "run", "--", "cli.mote"};
    CHECK_INT(main_io(&r, 4, a15), 0);

    /* a broken table is caught before anything runs */
    static const mote_cmd bad_cmds[] = {
        {"go", NULL, "ii", "go K", "go", "Go.", NULL, opts_run},
    };
    static const mote_model bad_model = {.name = "bad", .summary = "bad", .cmds = bad_cmds,
                                         .ncmds = 1, .create = fake_create,
                                         .destroy = fake_destroy};
    const mote_model *const bad[] = {&bad_model};
    mote_err err = {0};
    CHECK(mote_models_verify(bad, 1, &err) != 0, "bad synopsis accepted");
    CHECK_HAS(err.msg, "go");
    static const mote_cmd clash_cmds[] = {
        {"go", "echo", "", "go", "go", "Go.", NULL, opts_run},
    };
    static const mote_model clash_model = {.name = "clash", .summary = "c", .cmds = clash_cmds,
                                           .ncmds = 1, .create = fake_create,
                                           .destroy = fake_destroy};
    const mote_model *const clash[] = {&clash_model};
    CHECK(mote_models_verify(clash, 1, &err) != 0, "alias clash accepted");
    CHECK(mote_models_verify(MODELS, NMODELS, &err) == 0, "good tables rejected: %s", err.msg);
}

int main(void)
{
    snprintf(TMP, sizeof TMP, "/tmp/mote-test-script-XXXXXX");
    if (!mkdtemp(TMP) || chdir(TMP) != 0) {
        printf("cannot make a scratch directory\n");
        printf("0 passed, 1 failed\n");
        return 1;
    }
    test_lexing();
    test_lexical_errors();
    test_commands_and_arity();
    test_numbers();
    test_models();
    test_validation_first();
    test_argument_specs();
    test_runtime_errors();
    test_output_dir();
    test_help_and_usage();
    if (chdir("/") == 0) {
        char cmd[300];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", TMP);
        if (system(cmd) != 0)
            printf("note: could not remove %s\n", TMP);
    }
    return test_summary();
}
