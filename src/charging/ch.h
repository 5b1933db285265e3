/* ch.h: internal to the charging model: what its files share. */
#ifndef MOTE_CH_INTERNAL_H
#define MOTE_CH_INTERNAL_H

#include "mote/charging.h"

#include <stdio.h>

/* The index of the part called name, added when new; -1 with err when out of room. */
int ch_body_part(mote_ch_body *b, const char *name, mote_err *err);
/* Add the triangle (p, q, r) of part `part`, turned so that its normal points away from `inside`
 * when that is given; a triangle of zero area is dropped. */
int ch_add_tri(mote_ch_body *b, const double p[3], const double q[3], const double r[3],
               const double *inside, int closed, int part, mote_err *err);

/* A material's electron yields prepared once (plasma.c): mote_ch_see_yield and
 * mote_ch_backscatter_yield at E (keV) with lnE = ln E given, for loops over many energies. */
typedef struct {
    double see_a, emax, ln_emax;   /* dmax K (universal) or dmax (Sternglass); 0: none */
    int law, angle;
    double r[4], c1, c2;           /* the range law's (law 2) */
    double bs_C, bs_mz, bs_ln;     /* Hunger-Kuechler's C and m, ln(C / 0.891); C 0: none */
} ch_yields;
void ch_yields_prepare(const mote_ch_material *m, ch_yields *y);
double ch_see_ln(const ch_yields *y, double E_keV, double lnE, double cos_t);
double ch_bs_ln(const ch_yields *y, double E_keV, double lnE, double cos_t);

/* This process's MPI rank (0 without MPI, mc.c): only rank 0 writes files. */
/* The MPI rank and number of ranks of this run (0 and 1 outside MPI, or solo: a run that stays
 * in this process, an ensemble's replica) */
int ch_mpi_rank(int solo);
int ch_mpi_size(int solo);

/* The Monte Carlo draws (mc.c): four uniforms in (0, 1) from block `draw` of a history's
 * Philox stream; the injection point's outward normal and the direction (cosine law) from
 * four uniforms; the kinetic energy at injection in units of kT for chi = q phi_g / kT. */
/* One cheap uniform in (0, 1) for the straight histories' early test (mc.c). */
double ch_uniform_cheap(const uint32_t key[2], uint64_t history, uint32_t comp);
void ch_uniforms4(const uint32_t key[2], uint64_t history, uint32_t comp, uint32_t draw,
                  double u[4]);
void ch_inject_dir(const double u[4], double nrm[3], double dir[3]);
/* cos(2 pi u) and sin(2 pi u) for 0 <= u < 1 (mc.c), within 2e-16 of libm's, faster. */
void ch_cossin_turn(double u, double *c, double *s);
double ch_inject_energy(const double e[4], double chi);

/* First hits on a convex body by walking over its triangles (convex.c): NULL when the body is
 * not proved convex (or out of memory); the trace returns the triangle, -1 for no hit in
 * tmin < s <= tmax, or -2 when it cannot decide (Embree then does). The scene is Embree's. */
typedef struct ch_convex ch_convex;
struct RTCSceneTy;
ch_convex *ch_convex_build(const mote_ch_body *b, struct RTCSceneTy *scene);
void ch_convex_free(ch_convex *cv);
long ch_convex_trace(const ch_convex *cv, const double o[3], const double d[3], double tmin,
                     double tmax, int *side, double *s);
/* Embree's first hit in the scene (trace.c): the primitive, -1 for none in tmin < s <= tmax;
 * *side 0 when dir is against the triangle's winding normal; *s. */
long ch_embree_first(struct RTCSceneTy *scene, const double org[3], const double dir[3],
                     double tmin, double tmax, int *side, double *s);
/* Up to CH_TRACE_MANY rays at once (tmax infinite): tri[j] as ch_convex_trace gives it. */
enum { CH_TRACE_MANY = 32 };
void ch_convex_trace_many(const ch_convex *cv, int n, const double (*o)[3], const double (*d)[3],
                          double tmin, long *tri, int *side, double *s);
/* mote_ch_trace for n <= CH_TRACE_MANY rays (trace.c): the same results, the walks' starts
 * side by side. */
void ch_trace_many(const mote_ch_tracer *t, int n, const double (*o)[3], const double (*d)[3],
                   double tmin, long *tri, int *side, double *s);
/* Whether the tracer walks (the body proved convex); the walk turned off (tests and
 * benchmarks: Embree alone) or on again. */
int ch_tracer_convex(const mote_ch_tracer *t);
/* The early-exit boxes of a body that is not convex (trace.c), up to 8: their number, corners
 * copied to lo[k], hi[k] (0 for the exact sphere and a convex body). */
int ch_tracer_boxes(const mote_ch_tracer *t, double lo[][3], double hi[][3]);
void ch_tracer_walk(mote_ch_tracer *t, int on);

/* A curved path in the field of a charged mesh (path.c, spec 6.3). */
typedef struct {
    const mote_ch_tracer *t;
    double c[3];           /* the field's centre */
    double k;              /* q U R_f / m (m^3/s^2): the acceleration is k r / |r|^3 outside */
    double rf, R;          /* the field radius, the injection radius */
    double rj;             /* beyond it, conics in closed form (0: integrate all the way) */
    double eta;            /* dt = eta |r| / |v| */
    long max_steps;
    double overlap;        /* the chords' overlap (m), for Embree's single precision */
    double lo[3], hi[3];   /* the body's bounding box: rays only for chords that meet it */
    /* the solved field (`field solved`, ftree.c): NULL for the equivalent sphere's */
    const mote_ch_ftree *tree;
    double qu;             /* q U / m: the acceleration is qu E1(x), E1 the field per volt */
    double rfar;           /* beyond it (from c) the monopole k r / |r|^3 (its error there
                            * below the tree's); rj is at least rfar */
    int emitted;           /* 1: paths from the surface (bound ones turn back) */
    const double *tri_phi; /* each triangle's potential per volt (NULL: 1, the body at U) */
    const struct ch_fcache *cache; /* the field's cache (fcache.c; NULL: the tree alone) */
    const double *coef;    /* its conductors' potentials per volt of U (NULL: all 1) */
} ch_path;

typedef struct {
    long tri;              /* the triangle hit, -1 out through the injection sphere, -2 lost */
    int side;
    double v2;             /* the speed squared at the hit (m^2/s^2) */
    double eerr;           /* |E_end - E_0| / (K_0 + |q phi_0|) at the last integrated point */
    double dir[3];         /* the last chord's unit direction (the impact direction) */
    double x[3];           /* the hit point, from the field's centre */
    long steps;
} ch_hit;

/* Follow the particle at r (from c) with velocity v (m/s). */
void ch_path_follow(const ch_path *P, const double r[3], const double v[3], ch_hit *out);

/* What the output files of spec 8 are written from (output.c). */
typedef struct {
    const char *prefix, *origin, *mode;
    uint64_t seed;
    const mote_ch_plasma *plasma;
    const mote_ch_body *body;
    const mote_ch_result *res;
    mote_ch_geometry geom;
    double r_gen, potential;
    int threads;
    int triangles, vtk, png, ply; /* which files (the parts table and summaries always) */
    int vtk_binary;               /* vtk_format=binary */
    int png_w, png_h, png_log;
    double view[3];               /* unit vector toward the viewer */
    int have_float;               /* written by `float`: its root, error and the OML estimate */
    double sigma_U, oml;
    const mote_ch_material *const *tri_mat; /* per triangle (NULL: all bare) */
    int backscatter;              /* the emission includes backscattered electrons */
    int nviews;                   /* png_view: one file per view (P_surface.png for one view, */
    double (*views)[3];           /* else P_surface_NAME.png) */
    char (*view_names)[16];
    const char *warnings;         /* the validity warnings (spec 3.4), lines; NULL: none */
    int png_q, png_sp;            /* png_quantity: CH_Q_*, and the species of CH_Q_SPECIES */
    int solo;                     /* the run stays in this process (mote_context.solo) */
    const double *tri_V;          /* differential charging: each triangle's surface potential */
    double time;                  /* at this time (s) (NULL: U everywhere) */
} ch_output;

/* png_quantity (spec 8.4) */
enum { CH_Q_JNET, CH_Q_SPECIES, CH_Q_SEE, CH_Q_PHOTO, CH_Q_SIGMA, CH_Q_RELERR, CH_Q_SUNLIT,
       CH_Q_HITS, CH_Q_VSURF };

int ch_write_outputs(const ch_output *o, FILE *log, mote_err *err);
/* After `evolve` with dielectric parts: P_potential.png (a file per view) and P_potential.vtk,
 * the surface potential o->tri_V at o->time (png and vtk as o says; not the exact sphere). */
int ch_write_potential(const ch_output *o, FILE *log, mote_err *err);

/* The solved field's cache (fcache.c): an octree of cells over the cube of half-width half
 * about centre, each with the potential and field per volt of each of f's conductors at its
 * corners (trilinear between them) where that is within tol of the treecode (opening angle
 * theta) at the centre and the face centres (tol absolute in the potential per volt, relative
 * to |E| + 1/half in the field), cut down to cells of hmin; the cells that hold a triangle and
 * those still off at hmin are left to the tree; more than max_bytes of cells refused (an
 * error saying so, nothing kept). eval: 0 and the value when the cache answers
 * x (the conductors' fields combined with coef, NULL: all 1), 1 when the tree must. */
typedef struct ch_fcache ch_fcache;
/* the model's cache: over CH_FCACHE_REACH R_bound about the centre (the default injection
 * sphere's 1.05), cells down to R_bound / CH_FCACHE_CELLS, within CH_FCACHE_TOL */
#define CH_FCACHE_REACH 1.1
#define CH_FCACHE_CELLS 32
#define CH_FCACHE_TOL 1e-3
#define CH_FCACHE_MAX_BYTES 1e9 /* refused beyond (a clear error: use cache=off) */
ch_fcache *ch_fcache_build(const mote_ch_body *b, const mote_ch_bem *f, double theta,
                           const double centre[3], double half, double hmin, double tol,
                           double max_bytes, int threads, mote_err *err);
int ch_fcache_eval(const ch_fcache *c, const double *coef, const double x[3], double *phi,
                   double E[3]);
void ch_fcache_stats(const ch_fcache *c, long *cached, long *tree, size_t *bytes);
void ch_fcache_free(ch_fcache *c);

/* The net current's characteristic I(U) and the charging law it gives (evolve.c, spec 6.6). */
typedef struct {
    int n, down;                /* points; down: U falls from U0 (the net current is negative) */
    double *U, *I, *d;          /* the grid along the path, the currents, the Hermite slopes */
    double Uf;                  /* the root (floating potential) */
    int nt;
    double *tt, *tu;            /* t(U) on a fine grid */
    double tau;                 /* C / |dI/dU| at U_f */
    int ncol;                   /* per point: each species' current, the secondaries', the */
    double *col;                /* photoelectrons', the net current's error: [n][ncol] */
} ch_table;

int ch_table_build(const mote_ch_plasma *p, const mote_ch_body *b, const mote_ch_tracer *tr,
                   const mote_ch_run_opts *o, double U0, ch_table *t, mote_err *err);
double ch_table_eval(const ch_table *t, double U);
int ch_table_times(ch_table *t, double C, mote_err *err);
double ch_table_u_at(const ch_table *t, double time);
double ch_table_t_at(const ch_table *t, double U);
/* Column j of the table at U, interpolated linearly between the points. */
double ch_table_col(const ch_table *t, double U, int j);
void ch_table_free(ch_table *t);

/* Differential charging (diff.c, spec 6.10): the patches' circuit, the currents tabulated at
 * nodes of U made when first needed (node: one evaluation at U: the conductor's net current,
 * its error and each patch's net current at each dv of the grid), and the implicit
 * integration of (U, V_p - U). */
#define CH_MAX_PATCHES 16
typedef struct {
    int np, ndv;
    double scale, U0, C;                  /* the grid's scale (V), the first node, C (F) */
    double Cp[CH_MAX_PATCHES], Rp[CH_MAX_PATCHES]; /* F, ohm (INFINITY: no conduction) */
    /* have_cv: the vacuum capacitance matrix of the conductor (0) and the patches' outer
     * surfaces (1 + p), (np + 1)^2 row by row (F), in place of C alone on the conductor */
    int have_cv;
    double Cv[(CH_MAX_PATCHES + 1) * (CH_MAX_PATCHES + 1)];
    double *dv;                           /* [ndv] ascending, dv[ndv / 2] = 0 */
    int nn;                               /* nodes made: their lattice index, currents */
    int *node_j;
    double *node_Ic, *node_sig, *node_Ip; /* Ip: [nn][np][ndv] */
    int (*node)(void *ctx, double U, double *Ic, double *sig, double *Ip, mote_err *err);
    void *ctx;
    long steps;
    /* direct (the solved field with the conductors at their own potentials, issue 55): no
     * table, each state's currents from a run at its potentials: direct(ctx, V, J, sJ, sig) the
     * conductor's (J[0]) and each patch's (J[1 + p]) net current at the absolute potentials V
     * (np + 1), their errors sJ and the net current's error. The common mode (all potentials
     * together, through the vacuum capacitance alone: fast) is floated at each step, the
     * differentials V_p - U (through the layers: slow) advanced by steps that change none by
     * more than dv_step. J, sig: the last state's; sigma_U the float's error, tau_c the common
     * mode's time constant (sum Cv over |dI/dU|). */
    int (*direct)(void *ctx, const double *V, double *J, double *sJ, double *sig, mote_err *err);
    double dv_step;
    double J[CH_MAX_PATCHES + 1], sig, sigma_U, tau_c, slope; /* (slope: |dI/dU|, 0: none) */
    long runs;
} ch_patches;

int ch_patches_init(ch_patches *P, int np, double scale, double U0, mote_err *err);
void ch_patches_free(ch_patches *P);
/* The conductor's current, each patch's and the conductor's error at U and dV[np]. */
int ch_patches_currents(ch_patches *P, double U, const double *dV, double *Ic, double *Ip,
                        double *sig, mote_err *err);
/* The whole charge at y = (U, dV_1 ... dV_np): C U, or with the matrix sum_kl Cv_kl V_l. */
double ch_patches_charge(const ch_patches *P, const double *y);
/* direct: float the common mode of y (U, keeping dV_1 ... dV_np), P->J its currents. */
int ch_patches_float(ch_patches *P, double *y, mote_err *err);
/* The steady state (float): y = (U, dV_1 ... dV_np) where the whole net current is zero and
 * each patch's current equals its leak. The tables: by implicit Euler steps of the circuit
 * growing to 10^15 s (the state time evolution from y reaches). direct: by Newton's method
 * from y (the Jacobian by differences; steps of at most 5 kT or half a potential), until each
 * step is within tol of its potential or within the noise; the Newton steps into *iters, the currents there into P->J
 * (direct) and P->sig, the statistical errors of y into sy[np + 1] (direct: from each part's
 * current's error through the Jacobian; NAN when the tables give none); P->sigma_U the common
 * mode's. */
int ch_patches_steady(ch_patches *P, double *y, double tol, int *iters, double *sy, mote_err *err);
/* Integrate y = (U, dV_1 ... dV_np) from *t to t1, *h the step to try (updated). */
int ch_patches_advance(ch_patches *P, double *y, double *h, double t1, double *t, mote_err *err);

/* tally.c: 128-bit integers for the fixed-point tallies of emission and patches (a GCC and
 * Clang extension), in units of 2^-40 */
__extension__ typedef __int128 ch_i128;
#define FIX 1099511627776.0 /* 2^40 */
/* This process's MPI rank and the ranks' number (solo: a run that stays in this process, an
 * ensemble's replica on one rank: 0 and 1) */
void ch_mpi_layout(int solo, int *rank, int *size);
/* Sum n 128-bit integers over the ranks (in place). */
void ch_mpi_sum128(int solo, ch_i128 *v, size_t n);
/* Sum the tallies of one component over the ranks: the hit counts per triangle and side, the
 * counters, the largest energy error, the secondary scores (n128 128-bit integers). */
void ch_mpi_merge(int solo, uint64_t *tally, size_t ntally, uint64_t cnt[4], double *eerr,
                  ch_i128 *see, size_t n128);
/* Photoelectrons followed (the solved field, mc.c): the share of n of them, histories first ..
 * first + n - 1, emitted from triangle tri's side at temperature kT_ph, that escape. */
typedef struct {
    double (*escape)(void *ctx, uint32_t tri, int side, uint64_t first, uint64_t n, double kT_ph);
    void *ctx;
    uint64_t paths; /* how many in all */
} ch_photo_tracer;
/* Photoemission (spec 6.8): the sunlit triangles' photocurrents into r (patchy: also the
 * patches' rows of differential charging); no random numbers, unless tr (not NULL) follows
 * the photoelectrons instead of the escape fraction of a sphere's field. */
int ch_photoemission(const mote_ch_body *b, const mote_ch_tracer *t, const mote_ch_run_opts *o,
                     mote_ch_result *r, uint32_t ntri, double U_s, int patchy,
                     const ch_photo_tracer *tr, mote_err *err);

#endif
