/* targets.c: mote's fuzz targets (see fuzz.h). Inputs that name files go through a scratch
 * directory of the process's own; every target writes its input to a file there first where
 * the reader takes a path, exactly as a user's file would arrive. */
#include "fuzz.h"

#include "mote/datafile.h"
#include "mote/hardspheres.h"
#include "mote/live.h"
#include "mote/mixingbox.h"
#include "mote/charging.h"
#include "mote/nbody.h"
#include "mote/script.h"
#include "mote/separator.h"

#include "../src/hardspheres/plot.h"
#include "../src/mixingbox/mb.h"
#include "../src/nbody/nb.h"

#include <arpa/inet.h>
#include <math.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

/* A scratch directory made once per process (removed by the operating system's /tmp cleaning;
 * each target leaves only its fixed file names in it). */
static const char *scratch(void)
{
    static char dir[64]; /* set once, then only read: the targets are single-threaded */
    if (!dir[0]) {
        snprintf(dir, sizeof dir, "/tmp/mote-fuzz-XXXXXX");
        if (!mkdtemp(dir))
            snprintf(dir, sizeof dir, "/tmp");
    }
    return dir;
}

static int write_input(const char *name, const uint8_t *data, size_t size, char *path, size_t cap)
{
    snprintf(path, cap, "%s/%s", scratch(), name);
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    size_t w = fwrite(data, 1, size, f);
    fclose(f);
    return w == size ? 0 : -1;
}

static const mote_model *const MODELS[] = {&mote_model_hardspheres, &mote_model_mixingbox,
                                           &mote_model_nbody, &mote_model_separator};

/* Parse text with its parameters and validate it (nothing runs: validation only reads files,
 * never simulates). */
static void check_script(const char *text, size_t size, const char *const *params, int np)
{
    mote_err err = {0};
    mote_script *s = NULL;
    if (mote_script_parse_params(&s, "fuzz.mote", text, size, params, np, MODELS,
                                 sizeof MODELS / sizeof MODELS[0], &err) == 0) {
        mote_context *ctx = mote_script_context(s);
        FILE *null = fopen("/dev/null", "w");
        if (null) {
            ctx->out = ctx->diag = null;
            mote_script_validate(s, &err);
            fclose(null);
        }
        mote_script_free(s);
    }
}

static int fuzz_script(const uint8_t *data, size_t size)
{
    check_script((const char *)data, size, NULL, 0);
    return 0;
}

static int fuzz_hs_state(const uint8_t *data, size_t size)
{
    char path[256];
    if (write_input("in.state", data, size, path, sizeof path))
        return 0;
    mote_err err = {0};
    int geometry, dim;
    uint64_t n;
    mote_hs_peek(path, &geometry, &dim, &n, &err);
    mote_hs hs;
    mote_hs_init(&hs, NULL);
    if (mote_hs_load(&hs, path, &err) == 0) {
        /* a loaded state must run and save */
        mote_hs_step(&hs, 1, &err);
        snprintf(path, sizeof path, "%s/out.state", scratch());
        mote_hs_save(&hs, path, &err);
    }
    mote_hs_free(&hs);
    return 0;
}

static int fuzz_mb_state(const uint8_t *data, size_t size)
{
    char path[256];
    if (write_input("in.mbstate", data, size, path, sizeof path))
        return 0;
    mote_err err = {0};
    uint64_t n;
    mb_peek(path, &n, &err);
    mote_mb sys;
    mote_mb_init(&sys);
    mote_mb_params next;
    mote_mb_params_default(&next);
    if (mb_load(&sys, &next, path, &err) == 0)
        mote_mb_run(&sys, sys.time + 0.01, NULL, &err);
    mote_mb_free(&sys);
    return 0;
}

static int fuzz_nb_state(const uint8_t *data, size_t size)
{
    char path[256];
    if (write_input("in.nbstate", data, size, path, sizeof path))
        return 0;
    mote_err err = {0};
    uint32_t n;
    nb_state_peek(path, &n, &err);
    for (int kind = 0; kind < 2; kind++) {
        mote_nb nb;
        mote_nb_init(&nb, kind ? MOTE_NB_COULOMB : MOTE_NB_GRAVITY);
        if (nb_state_load(&nb, path, &err) == 0) {
            /* a loaded state must run and save */
            mote_nb_galactica(&nb, 2, &err);
            snprintf(path, sizeof path, "%s/out.nbstate", scratch());
            nb_state_save(&nb, path, &err);
        }
        mote_nb_free(&nb);
    }
    return 0;
}

static int fuzz_nb_snapshot(const uint8_t *data, size_t size)
{
    char path[256];
    if (write_input("in.snap", data, size, path, sizeof path))
        return 0;
    mote_err err = {0};
    for (int kind = 0; kind < 2; kind++) {
        mote_nb nb;
        mote_nb_init(&nb, kind ? MOTE_NB_COULOMB : MOTE_NB_GRAVITY);
        if (nb_snapshot_read(&nb, path, &err) == 0) {
            /* a snapshot read must run and be written again */
            mote_nb_galactica(&nb, 2, &err);
            snprintf(path, sizeof path, "%s/out.snap", scratch());
            nb_snapshot_write(&nb, path, "fuzz", &err);
        }
        mote_nb_free(&nb);
    }
    return 0;
}

static int fuzz_ch_plain(const uint8_t *data, size_t size)
{
    char path[256];
    if (write_input("in.tri", data, size, path, sizeof path))
        return 0;
    mote_err err = {0};
    for (int strict = 0; strict < 2; strict++) {
        mote_ch_body b = {0};
        mote_ch_load_opts o = {.format = "plain", .scale = 1, .rot_axis = -1, .strict = strict};
        mote_ch_load_report r;
        if (mote_ch_body_load(&b, path, &o, &r, &err) == 0) {
            /* a loaded mesh must have outward-consistent data and a finite geometry */
            mote_ch_geometry g;
            mote_ch_body_geometry(&b, &g);
            if (!(g.area > 0))
                __builtin_trap();
        }
        mote_ch_body_free(&b);
    }
    return 0;
}

static int fuzz_nb_solar(const uint8_t *data, size_t size)
{
    char path[256];
    if (write_input("in.solar", data, size, path, sizeof path))
        return 0;
    mote_err err = {0};
    mote_nb_solar s;
    if (mote_nb_solar_read(path, &s, &err) == 0) {
        mote_nb nb;
        mote_nb_init(&nb, MOTE_NB_GRAVITY);
        if (mote_nb_solar_build(&nb, &s, NULL, 1, &err) == 0)
            mote_nb_galactica(&nb, 2, &err); /* a built system must run */
        mote_nb_free(&nb);
        mote_nb_solar_free(&s);
    }
    return 0;
}

/* A Galactica body file, both layouts, counted and exact: one that reads goes into a system and
 * is written back. */
static int fuzz_nb_galactica(const uint8_t *data, size_t size)
{
    char path[256];
    if (write_input("in.gal", data, size, path, sizeof path))
        return 0;
    for (int coulomb = 0; coulomb < 2; coulomb++)
        for (long k2 = -1; k2 <= 1; k2 += 2) {
            mote_err err = {0};
            nb_galfile g;
            if (nb_galfile_read(path, coulomb, k2, &g, &err))
                continue;
            mote_nb nb;
            mote_nb_init(&nb, coulomb ? MOTE_NB_COULOMB : MOTE_NB_GRAVITY);
            if (nb_from_galfile(&nb, &g, path, &err) == 0) {
                mote_real *body = malloc((coulomb ? 16 : 15) * (size_t)(nb.n ? nb.n : 1) * sizeof *body);
                if (body) {
                    nb_galfile h;
                    nb_to_galfile(&nb, g.head, &h, body);
                    char out[256];
                    snprintf(out, sizeof out, "%s/out.gal", scratch());
                    nb_galfile_write(out, &h, 1, &err);
                    free(body);
                }
            }
            mote_nb_free(&nb);
            nb_galfile_free(&g);
        }
    return 0;
}

/* A Galactica control file, read every way; one that reads is written back. */
static int fuzz_nb_galctl(const uint8_t *data, size_t size)
{
    char path[256];
    if (write_input("galacf26.dat", data, size, path, sizeof path))
        return 0;
    for (int mode = 0; mode < 4; mode++) {
        mote_err err = {0};
        nb_galctl g;
        if (nb_galctl_read(path, mode & 1, mode >> 1, &g, &err) == 0) {
            char out[256];
            snprintf(out, sizeof out, "%s/out26.dat", scratch());
            nb_galctl_write(out, &g, &err);
        }
    }
    return 0;
}

/* A Galactica job's checkpoint (galgon4) edited, which reads it whole, checks it as a launch
 * would and writes it back; and the same bytes as a control file checked for a first launch. */
static int fuzz_nb_galjob(const uint8_t *data, size_t size)
{
    char path[256], ctl[256];
    if (write_input("galgon4", data, size, path, sizeof path) ||
        write_input("galacf26.dat", data, size, ctl, sizeof ctl))
        return 0;
    mote_nb_job o;
    memset(&o, 0, sizeof o);
    o.control = ctl;
    mote_err err = {0};
    char edit[] = "Kl7=1";
    char *edits[1] = {edit};
    mote_nb_job_edit(&o, 1, edits, &err);
    long k2;
    mote_nb_job_check(&o, &k2, &err);
    return 0;
}

/* A separator state: read; a state that reads must run a few steps and save. */
static int fuzz_sep_state(const uint8_t *data, size_t size)
{
    char path[256];
    if (write_input("in.sepstate", data, size, path, sizeof path))
        return 0;
    mote_err err = {0};
    mote_sep_system s;
    mote_sep_init(&s);
    uint64_t seed;
    /* (a state whose feed would add more than 1e4 particles in the three steps is read, not
     * run: that is a large run, not a fault) */
    double dmin = 0, dmax = 0, rho = 1e30;
    int ok = mote_sep_load(&s, &seed, path, &err) == 0 && mote_sep_prepare(&s, &err) == 0 &&
             s.n < 100000;
    if (ok) {
        mote_sep_size_range(&s, &dmin, &dmax);
        for (int k = 0; k < s.nsp; k++)
            rho = rho < s.sp[k].rho ? rho : s.sp[k].rho;
        /* the feed's mass owed up to then: its rate over the three steps, and what a state
         * says it owes already (a clock far ahead of the mass fed: a catch-up of millions) */
        double owed = 0;
        if (s.rate > 0)
            for (int k = 0; k < s.nsp; k++)
                owed += s.sp[k].w * s.rate * (fmin(s.t + 3 * s.dt, s.t_stop) - s.t_start) -
                        s.cnt[k].m_gen;
        ok = !(owed > 1e4 * rho * dmin * dmin * dmin / 2);
    }
    if (ok) {
        mote_sep_run(&s, 3 * s.dt, &err);
        snprintf(path, sizeof path, "%s/out.sepstate", scratch());
        mote_sep_save(&s, seed, path, &err);
    }
    mote_sep_free(&s);
    return 0;
}

/* A mesh file through the reader users get (Assimp in its child process, or the plain format):
 * the first byte picks the extension, the rest is the file. A mesh that loads must have a
 * finite, positive area. */
static int fuzz_ch_mesh(const uint8_t *data, size_t size)
{
    static const char *const ext[] = {"stl", "obj", "ply", "off", "gltf", "dae", "3ds", "tri"};
    if (size < 1)
        return 0;
    char name[32], path[256];
    snprintf(name, sizeof name, "in.%s", ext[data[0] % (sizeof ext / sizeof ext[0])]);
    if (write_input(name, data + 1, size - 1, path, sizeof path))
        return 0;
    mote_err err = {0};
    mote_ch_body b = {0};
    mote_ch_load_opts o = {.format = "auto", .scale = 1, .rot_axis = -1};
    mote_ch_load_report r;
    if (mote_ch_body_load(&b, path, &o, &r, &err) == 0) {
        mote_ch_geometry g;
        mote_ch_body_geometry(&b, &g);
        if (!(g.area > 0) || !isfinite(g.area))
            __builtin_trap();
    }
    mote_ch_body_free(&b);
    return 0;
}

/* The separator's input files (gas profile, size table, hole list, class edges): the same bytes
 * through each, as a script names them, validated (which reads them). */
static int fuzz_sep_files(const uint8_t *data, size_t size)
{
    static const char *const use[] = {
        "model separator\nchannel 0.05 1\ngas_profile ",
        "model separator\nchannel 0.05 1\nspecies a 2500\nsize a table file=",
        "model separator\nchannel 0.05 1\ngrid 0.3 0.01 holes file=",
        "model separator\ndim 3\nchannel 0.05 1 D=0.05\ngrid 0.3 0.01 holes file=",
        "model separator\nclasses_file ",
    };
    char path[256];
    if (write_input("in.txt", data, size, path, sizeof path))
        return 0;
    for (size_t k = 0; k < sizeof use / sizeof use[0]; k++) {
        char text[512];
        snprintf(text, sizeof text, "%s%s\n", use[k], path);
        fuzz_script((const uint8_t *)text, strlen(text));
    }
    return 0;
}

/* The live server's request handling: the bytes as one HTTP connection to a server started once
 * per process (with a frame published), read until it closes or 100 ms pass. */
static int fuzz_live_http(const uint8_t *data, size_t size)
{
    static mote_live *live; /* started once (the fuzz process is single-threaded) */
    static int port;
    if (!live) {
        char url[128];
        mote_err err = {0};
        if (mote_live_start(&live, NULL, 0, url, &err))
            return 0;
        const char *colon = strrchr(url, ':');
        port = colon ? atoi(colon + 1) : 0;
        static const char frame[] = "{\"model\":\"fuzz\",\"frame\":1}";
        mote_live_publish(live, frame, sizeof frame - 1, 0);
    }
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0)
        return 0;
    struct sockaddr_in a;
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_port = htons((uint16_t)port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    struct timeval tv = {0, 100000};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
    if (connect(fd, (struct sockaddr *)&a, sizeof a) == 0) {
        size_t off = 0;
        while (off < size) {
            ssize_t w = send(fd, data + off, size - off, MSG_NOSIGNAL);
            if (w <= 0)
                break;
            off += (size_t)w;
        }
        shutdown(fd, SHUT_WR);
        char buf[4096];
        while (recv(fd, buf, sizeof buf, 0) > 0)
            ;
    }
    close(fd);
    return 0;
}

static int fuzz_plot(const uint8_t *data, size_t size)
{
    char in[256], out[256];
    if (write_input("in.dat", data, size, in, sizeof in))
        return 0;
    snprintf(out, sizeof out, "%s/out.png", scratch());
    mote_err err = {0};
    hs_plot_file(in, out, &err);
    mb_plot_file(in, out, &err);
    nb_plot_file(in, out, NULL, &err);
    return 0;
}

/* Script parameters (issue 52): the lines up to the first empty one are NAME=VALUE parameters, the
 * rest is the script, parsed and validated with them (as `mote check SCRIPT NAME=VALUE ...`). */
static int fuzz_script_params(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    const char *params[64];
    int np = 0;
    char *p = text;
    while (np < 64 && p < text + size && *p != '\n') {
        char *nl = memchr(p, '\n', (size_t)(text + size - p));
        if (!nl)
            break;
        *nl = '\0';
        params[np++] = p;
        p = nl + 1;
    }
    if (p < text + size && *p == '\n')
        p++;
    check_script(p, (size_t)(text + size - p), params, np);
    free(text);
    return 0;
}

/* The CSV form of a data file and the table reader (issue 52): the input as a data file turned
 * into CSV (as a commit under a .csv name does), that CSV read back, and the input itself read as
 * a CSV file. */
static int fuzz_csv(const uint8_t *data, size_t size)
{
    char in[256], out[256], raw[256];
    if (write_input("in.dat", data, size, in, sizeof in) ||
        write_input("raw.csv", data, size, raw, sizeof raw))
        return 0;
    snprintf(out, sizeof out, "%s/out.csv", scratch());
    mote_err err = {0};
    FILE *f = fopen(out, "w");
    if (f) {
        const int rc = mote_datafile_csv(in, f, &err);
        fclose(f);
        mote_table t;
        if (!rc && mote_table_read(&t, out, &err) == 0)
            mote_table_free(&t);
    }
    mote_table t;
    if (mote_table_read(&t, raw, &err) == 0)
        mote_table_free(&t);
    return 0;
}

const mote_fuzz_target mote_fuzz_targets[] = {
    {"script", fuzz_script},
    {"hs_state", fuzz_hs_state},
    {"mb_state", fuzz_mb_state},
    {"nb_state", fuzz_nb_state},
    {"nb_snapshot", fuzz_nb_snapshot},
    {"nb_solar", fuzz_nb_solar},
    {"ch_plain", fuzz_ch_plain},
    {"plot", fuzz_plot},
    {"sep_state", fuzz_sep_state},
    {"nb_galactica", fuzz_nb_galactica},
    {"nb_galctl", fuzz_nb_galctl},
    {"nb_galjob", fuzz_nb_galjob},
    {"ch_mesh", fuzz_ch_mesh},
    {"sep_files", fuzz_sep_files},
    {"live_http", fuzz_live_http},
    {"script_params", fuzz_script_params},
    {"csv", fuzz_csv},
};
const size_t mote_fuzz_ntargets = sizeof mote_fuzz_targets / sizeof mote_fuzz_targets[0];

const mote_fuzz_target *mote_fuzz_find(const char *name)
{
    for (size_t i = 0; i < mote_fuzz_ntargets; i++)
        if (strcmp(mote_fuzz_targets[i].name, name) == 0)
            return &mote_fuzz_targets[i];
    return NULL;
}
