/* model.h: the charging model's script state (ch_model) and what its command files share:
 * commands.c holds the table, the model's life and the setup commands (plasma, species, body,
 * injector, field, sun, integrator, material); run.c the long commands (test, run, float,
 * evolve) and `output`; help.inc the help text. Internal to src/charging. */
#ifndef MOTE_CH_MODEL_H
#define MOTE_CH_MODEL_H

#include "mote/charging.h"
#include "mote/command.h"
#include "mote/datafile.h"

#include <stdio.h>

#include "ch.h"

typedef struct ch_model {
    mote_context *ctx;
    FILE *log;
    int dry, faithful;
    int have_plasma, have_body, have_sphere; /* what validation knows */
    mote_ch_plasma plasma;
    mote_ch_body body;
    char radius[32];            /* injector sphere radius= (auto, debye, thesis or metres) */
    mote_ch_result res;         /* the last run */
    int have_run;
    uint64_t seed;
    double r_gen_used;          /* the injection radius of the last run */
    int box;                    /* the box injector (spec 5.2) */
    double margin, margin_m;
    int field_off;              /* `field none` (spec 6.1): straight paths whatever U */
    int field_solved;           /* `field solved` (issue 55): the body's own field, solved */
    double theta;               /* its treecode's opening angle */
    mote_ch_bem fbem;           /* the solution for the body as it is (sigma NULL: none yet) */
    int fstate[CH_MAX_PATCHES + 1]; /* its conductor k's place in the patches' circuit: 0 the
                                     * conductor, 1 + p dielectric part p */
    mote_ch_ftree *ftree;       /* and its tree */
    ch_fcache *fcache;          /* and the paths' cache of it (NULL: none yet, or cache=off) */
    int fcache_mode;            /* `field solved cache=`: 0 off, 1 on */
    double bfield;              /* `bfield B=` (spec 3.4, diagnostics only), T */
    int diagnosed;              /* the warnings of spec 3.4 printed for this plasma and body */
    char *warnings;             /* their text, for the summary files */
    int no_backscatter;         /* `backscatter off` (issue 37) */
    int sun;                    /* `sun` (spec 6.8): on, the unit vector toward it, intensity */
    double sun_dir[3], sun_int;
    double eta;                 /* `integrator` (spec 6.3): curved paths' step and limit */
    long max_steps;
    int embree_only;            /* `tracer embree`: no walk, no early-exit boxes */
    /* materials (spec 6.9): the defined ones (presets are found by name) and the assignments,
     * in order (a later one wins) */
    mote_ch_material defined[32];
    int ndefined;
    struct {
        char part[MOTE_CH_NAME_LEN];
        mote_ch_material m;
    } assign[64];
    int nassign;
    const mote_ch_material **tri_mat; /* per triangle, built for a run (NULL: none emits) */
    /* `dielectric` (spec 6.10): the parts with a surface potential of their own, in order */
    struct {
        char part[MOTE_CH_NAME_LEN];
        double d, eps_r, sigma;   /* m; eps_r 0: the part's material's; S/m */
    } diel[CH_MAX_PATCHES];
    int ndiel;
    /* `output`: the files of spec 8 after each run (prefix NULL: none) */
    char *prefix, *origin;
    int out_triangles, out_vtk, out_png, out_ply, png_w, png_h, png_log, vtk_binary;
    int out_timeseries;
    int png_q, png_sp;          /* png_quantity */
    int legacy_stdout;          /* the original's four columns from evolve (spec 8.1) */
    double view[8][3];          /* png_view: the views, and their names for the file names */
    char view_name[8][16];
    int nviews;
    /* validation: the prefix and time-series switch of the last `output`, so that the files
     * `run`, `float` and `evolve` will write are known to the whole-script check */
    char *check_prefix;
    int check_timeseries;
    /* `monitor dt=T file=FILE`: the time series of every later `evolve` (without its own file=)
     * into FILE, a row every T (unless evolve's dt=); path NULL: none */
    struct {
        char *path;
        double dt;
        int as; /* format= (MOTE_AS_NAME, _CSV, _JSONL) */
    } monitor;
} ch_model;

/* ---- commands.c: helpers run.c uses ---- */
int ch_parse3any(const char *t, double v[3]);
double ch_injection_radius(const ch_model *m, const mote_ch_geometry *g);
void ch_diagnose(ch_model *m, const char *cmd);
int ch_build_tri_materials(ch_model *m, mote_err *err);
double ch_species_see(const mote_ch_result *r, int s, double *var);
/* Do the runs of m score backscattered electrons (on, and some triangle's material has Z)? */
int ch_backscatter_in(const ch_model *m);
/* The words for what species s knocks out: "secondaries" or, for electrons while backscatter
 * is in, "secondaries and backscattered electrons". */
const char *ch_emitted_words(const ch_model *m, int s);
void ch_report_paths(const ch_model *m, const char *cmd);
ch_output ch_output_of(ch_model *m, const mote_ch_geometry *g, const mote_ch_run_opts *o,
                       double U);

/* `field solved`: the body's field solved and its tree built when they are not yet (the
 * capacitance then the solved one); ch_field_drop forgets them (the body changed). */
int ch_field_prepare(ch_model *m, const mote_call *c, mote_err *err);
void ch_field_drop(ch_model *m);

/* The relative permittivity of part's material (0: none given). */
double ch_part_eps(const ch_model *m, const char *part);
double ch_part_sigma(const ch_model *m, const char *part); /* its material's bulk conductivity, or 0 */
/* The smallest temperature of the plasma and the emission (eV per unit charge). */
double ch_smallest_kT(const ch_model *m);

/* ---- run.c ---- */
int ch_check_test(void *vm, const mote_call *c, mote_err *err);
int ch_run_test(void *vm, const mote_call *c, mote_err *err);
int ch_check_run(void *vm, const mote_call *c, mote_err *err);
int ch_run_run(void *vm, const mote_call *c, mote_err *err);
int ch_check_float(void *vm, const mote_call *c, mote_err *err);
int ch_run_float(void *vm, const mote_call *c, mote_err *err);
/* run.c: a command's run options (seed, particles=, injector, threads), and whether the body and
 * plasma are there (else the call's error) */
mote_ch_run_opts ch_run_opts(const ch_model *m, const mote_call *c, const mote_ch_geometry *g);
int ch_need_setup(ch_model *m, const mote_call *c, mote_err *err);
/* run.c: a file a run writes under the output prefix (PREFIX + suffix), noted for the check */
int ch_note_prefixed(ch_model *m, const mote_call *c, const char *suffix, const char *kind,
                     mote_err *err);
/* timeseries.c: `evolve` */
int ch_check_evolve(void *vm, const mote_call *c, mote_err *err);
/* `monitor dt=T file=FILE` (checked and run alike: the dry model knows the file too) */
int ch_run_monitor(void *vm, const mote_call *c, mote_err *err);
int ch_run_monitor_stop(void *vm, const mote_call *c, mote_err *err);
int ch_run_evolve(void *vm, const mote_call *c, mote_err *err);
int ch_check_output(void *vm, const mote_call *c, mote_err *err);
int ch_run_output(void *vm, const mote_call *c, mote_err *err);

/* float with dielectric parts: their steady state with the conductor (timeseries.c). */
int ch_float_patches(ch_model *m, const mote_call *c, mote_err *err);
/* The tracer of the model's body as `tracer` asks (run.c). */
mote_ch_tracer *ch_model_tracer(const ch_model *m, mote_err *err);

#endif
