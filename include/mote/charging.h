/* charging.h: the spacecraft-charging model (specs/spacecraft-charging.md): a plasma of
 * Maxwellian components, a spacecraft body of triangles (or an exact sphere), and Monte Carlo
 * estimates of the current each surface collects, traced with Embree. SI units throughout;
 * temperatures as kT in eV. */
#ifndef MOTE_CHARGING_H
#define MOTE_CHARGING_H

#include "mote/command.h"
#include "mote/core.h"
#include "mote/mesh.h"

#include <stdint.h>

/* CODATA 2018 (spec 1.3) */
#define MOTE_CH_E 1.602176634e-19      /* C */
#define MOTE_CH_ME 9.1093837015e-31    /* kg */
#define MOTE_CH_MP 1.67262192369e-27   /* kg */
#define MOTE_CH_EPS0 8.8541878128e-12  /* F/m */
#define MOTE_CH_AMU 1.66053906660e-27  /* kg */
#define MOTE_CH_PI 3.14159265358979323846

/* ---- plasma (spec 3) ------------------------------------------------------------------------ */

enum { MOTE_CH_MAX_SPECIES = 16, MOTE_CH_MAX_COMPONENTS = 8 };

typedef struct {
    char name[16];
    int Z;                 /* charge number: q = Z e */
    double m;              /* kg */
    double drift[3];       /* drift velocity relative to the body, m/s (straight paths only) */
    int ncomp;
    double n[MOTE_CH_MAX_COMPONENTS];  /* m^-3 */
    double kT[MOTE_CH_MAX_COMPONENTS]; /* eV */
} mote_ch_species;

typedef struct {
    int nsp;
    mote_ch_species sp[MOTE_CH_MAX_SPECIES];
} mote_ch_plasma;

/* The presets of spec 3.2: "geo-worst-case", "thesis-hot", or "single" (n, kT for both). */
int mote_ch_plasma_preset(mote_ch_plasma *p, const char *name, double n, double kT,
                          mote_err *err);
/* One-sided thermal current density e n sqrt(kT / (2 pi m)) (A/m^2, magnitude; kT in eV). */
double mote_ch_j0(double n, double kT, double m, int Z);
/* Mean speed sqrt(8 kT / (pi m)) (m/s). */
double mote_ch_mean_speed(double kT, double m);
/* The multi-temperature Debye length of spec 3.3 (m). */
double mote_ch_debye(const mote_ch_plasma *p);

/* ---- body (spec 4) -------------------------------------------------------------------------- */

/* Part names are kept whole up to MOTE_CH_NAME_LEN - 1 bytes; a longer name in a mesh file, part=
 * or material assign is refused (never cut, which could merge two parts). */
#define MOTE_CH_NAME_LEN MOTE_MESH_NAME_LEN
/* The most triangles a body has (generated or loaded), and the memory one takes with its share
 * of the ray-tracing structure, for the estimate checked before a body is made. */
#define MOTE_CH_MAX_TRI 100000000
#define MOTE_CH_TRI_BYTES 330.0
/* The sizes of body (R_bound, m) that trace correctly in Embree's single precision (measured
 * exact from 1e-12 to 1e15 m; a decade kept at each end). */
#define MOTE_CH_SIZE_MIN 1e-9
#define MOTE_CH_SIZE_MAX 1e12

typedef struct {
    uint32_t ntri, cap;
    double (*v)[3][3];     /* vertices of each triangle */
    double (*nrm)[3];      /* outward unit normals */
    double *area;
    uint8_t *closed;       /* 1: of a closed component (one outer side); 0: a two-sided sheet */
    uint16_t *part;        /* the part each triangle belongs to (spec 4.1) */
    char (*part_name)[MOTE_CH_NAME_LEN];
    int nparts;
    int sphere;            /* 1: the exact analytic sphere (no triangles) */
    double sphere_r, sphere_c[3];
    double capacitance;    /* `body capacitance` (F, spec 4.3); 0: auto, 4 pi eps0 R_eq */
} mote_ch_body;

void mote_ch_body_free(mote_ch_body *b);
/* Generated bodies (spec 4.4), added to b: the exact sphere, an icosphere (20 4^level
 * triangles), a UV sphere (2 nlon (nlat - 1) triangles; halves: two parts, north (z > 0) and
 * south, nlat even), a box (12 subdiv^2 triangles), two
 * cubes of side `side` facing each other across `gap` along x. */
int mote_ch_body_sphere(mote_ch_body *b, double r, mote_err *err);
int mote_ch_body_icosphere(mote_ch_body *b, double r, int level, mote_err *err);
int mote_ch_body_uvsphere(mote_ch_body *b, double r, int nlon, int nlat, int halves,
                          mote_err *err);
int mote_ch_body_box(mote_ch_body *b, const double size[3], const double centre[3], int subdiv,
                     mote_err *err);
int mote_ch_body_twocubes(mote_ch_body *b, double side, double gap, mote_err *err);

/* Mesh files (spec 7.1-7.3, 4.2): STL, OBJ, PLY, glTF and the rest through Assimp, or the
 * original program's plain format (9 numbers per triangle); scaled, turned about an axis and
 * moved, then checked and repaired (degenerate and duplicate triangles dropped, vertices welded,
 * closed components oriented outward, open ones kept as two-sided sheets). */
typedef mote_mesh_opts mote_ch_load_opts;
typedef mote_mesh_report mote_ch_load_report;

int mote_ch_body_load(mote_ch_body *b, const char *path, const mote_ch_load_opts *o,
                      mote_ch_load_report *rep, mote_err *err);

/* Spec 4.3: the area (sheets counted twice), the area-weighted centre, R_bound, R_eq, C. */
typedef struct {
    double area, centre[3], r_bound, r_eq, capacitance;
    double r_field;        /* the field's radius R_f = C / (4 pi eps0) (spec 6.1) */
    /* Rigorous bounds on the body's capacitance (capacitance grows with the body: a body
     * inside another has the smaller): c_max = 4 pi eps0 R_bound, the ball about the centre
     * that holds it; c_min the larger of 8 eps0 r_in, the disk inscribed in its largest
     * triangle (Maxwell's 8 eps0 a), and, for closed components, 4 pi eps0 (3V / 4 pi)^(1/3),
     * the sphere of their volume (Polya and Szego 1951: of all bodies of a volume the sphere
     * has the least capacitance). */
    double c_min, c_max;
    double volume;         /* of the closed components (m^3) */
} mote_ch_geometry;
void mote_ch_body_geometry(const mote_ch_body *b, mote_ch_geometry *g);

/* ---- the body's own field in vacuum: boundary elements (bem.c, issue 55) ------------------- */

/* The panels a solve takes at most: its dense matrix is 8 n^2 bytes (16384: 2.1 GB). */
#define MOTE_CH_BEM_MAX 16384u
/* and the conductors (each with its own potential) */
#define MOTE_CH_BEM_MAX_CONDUCTORS 64
typedef struct {
    uint32_t n;          /* panels: the body's triangles */
    int nc;              /* conductors */
    double *sigma;       /* each panel's surface charge density with every conductor at 1 V
                          * (C/m^2; a sheet's: both sides together) */
    double *basis;       /* nc > 1: n x nc, column l (basis + l n) the density with conductor l
                          * at 1 V and the others at 0 (NULL: nc 1, sigma is it) */
    double *cmat;        /* nc x nc, the capacitance matrix: cmat[k nc + l] the charge on
                          * conductor k per volt on conductor l, the others at 0 (F) */
    double capacitance;  /* Q / U, all at U: the sum of sigma_j A_j, of cmat's entries (F) */
} mote_ch_bem;
/* The conducting body at 1 V: the charge on its panels and its capacitance (bem.c has the
 * method, its costs and accuracy). threads: the assembly's OpenMP threads. With a context
 * (else NULL), a progress line under label, and its interrupt heard between blocks of the
 * work (MOTE_EINTR, nothing kept). */
int mote_ch_bem_solve(const mote_ch_body *b, int threads, const mote_context *ctx,
                      const char *label, mote_ch_bem *f, mote_err *err);
/* The same for nc conductors, panel j on conductor cond[j] (0 .. nc - 1, each with a panel;
 * cond NULL: one): the capacitance matrix, each column's charge on the one LU. */
int mote_ch_bem_solve_conductors(const mote_ch_body *b, const int *cond, int nc, int threads,
                                 const mote_context *ctx, const char *label, mote_ch_bem *f,
                                 mote_err *err);
/* The potential (V, per volt on the body) at x, anywhere (a direct sum over the panels). */
double mote_ch_bem_potential(const mote_ch_body *b, const mote_ch_bem *f, const double x[3]);
void mote_ch_bem_free(mote_ch_bem *f);
size_t mote_ch_bem_bytes(uint32_t n);
/* The integral of dS / |p - y| over the flat triangle t, exactly (Wilton et al. 1984). */
double mote_ch_triangle_integral(double t[3][3], const double p[3]);
/* The same integral, returned, and its gradient with respect to p in g (exact). */
double mote_ch_triangle_gradient(double t[3][3], const double p[3], double g[3]);

/* The potential and field of a boundary-element solution anywhere, by a treecode (ftree.c has
 * the method, its error and costs): theta (0 < theta < 1) the opening angle, the panels' charge
 * densities sigma (per volt). The tree refers to b: keep b unchanged while it is used. */
typedef struct mote_ch_ftree mote_ch_ftree;
mote_ch_ftree *mote_ch_ftree_build(const mote_ch_body *b, const double *sigma, double theta,
                                   mote_err *err);
/* phi (V) and E (V/m) at x, per volt of the solution */
void mote_ch_ftree_eval(const mote_ch_ftree *T, const double x[3], double *phi, double E[3]);
/* The whole body's moments (the root's): centre, charge, dipole, quadrupole (xx yy zz xy xz yz,
 * traceless, per unit of the multipole series q / r + p.r / r^3 + r.Q.r / (2 r^5)), radius. */
void mote_ch_ftree_moments(const mote_ch_ftree *T, double c[3], double *q, double p[3],
                           double Q[6], double *r);
/* The radius about c beyond which the monopole's field is within about tol of the whole
 * (the dipole's and quadrupole's share below tol there; at least twice the panels' reach). */
double mote_ch_ftree_monopole_radius(const mote_ch_ftree *T, const double c[3], double tol);
/* The whole charge (C per volt: the capacitance of a one-conductor solution). */
double mote_ch_ftree_charge(const mote_ch_ftree *T);
size_t mote_ch_ftree_bytes(const mote_ch_ftree *T);
void mote_ch_ftree_free(mote_ch_ftree *T);

/* ---- tracing and Monte Carlo (spec 5) ------------------------------------------------------- */

typedef struct mote_ch_tracer mote_ch_tracer;
/* Build the ray-tracing structure of b (Embree, robust mode; the walk of a convex body, which
 * reads b's triangles: b must outlive the tracer, unchanged); NULL with err on failure. */
mote_ch_tracer *mote_ch_tracer_new(const mote_ch_body *b, mote_err *err);
void mote_ch_tracer_free(mote_ch_tracer *t);
/* The first triangle the ray org + s dir (s > tmin) meets, or -1; *side 0 front, 1 back; *s. */
long mote_ch_trace(const mote_ch_tracer *t, const double org[3], const double dir[3], double tmin,
                   int *side, double *s);
/* The same for the segment tmin < s <= tmax. */
long mote_ch_trace_seg(const mote_ch_tracer *t, const double org[3], const double dir[3],
                       double tmin, double tmax, int *side, double *s);

/* Whether anything lies on the segment org + s dir, tmin < s < tmax (any hit; Embree's
 * occlusion query). The exact sphere: its analytic test. */
int mote_ch_occluded(const mote_ch_tracer *t, const double org[3], const double dir[3],
                     double tmin, double tmax);

/* Counter-based Philox4x32-10 (Salmon et al. 2011): 4 words from a 128-bit counter and a
 * 64-bit key; every history has its own stream (spec 5.7). */
void mote_ch_philox(const uint32_t ctr[4], const uint32_t key[2], uint32_t out[4]);

/* ---- materials and secondary emission (spec 6.7, 6.9) ---------------------------------------- */

typedef struct {
    char name[24];
    double see_dmax, see_emax;  /* the electron yield curve: its peak and where (keV) */
    double photo_j;             /* photoemission current density at normal incidence, A/m^2 */
    double kT_s;                /* secondaries' temperature, eV */
    int see_law;                /* 0 universal, 1 Sternglass, 2 NASCAP's range law */
    int see_angle;              /* 0 none, 1 sec (the universal law's angular form) */
    double ion_dmax, ion_emax;  /* the ion-impact yield (0: none), keV */
    double kT_ph;               /* photoelectrons' temperature, eV */
    double Z;                   /* atomic number for electron backscatter (a compound's mean
                                 * weighted by mass); 0: no backscatter data */
    double eps_r;               /* relative permittivity for differential charging (spec 6.10);
                                 * 0: a conductor's preset (give eps_r= to `dielectric`) */
    double sigma;               /* bulk conductivity, S/m (the library's dielectrics; 0: none
                                 * known, `dielectric sigma=` gives it) */
    char source[16];            /* where the values come from (data/materials.dat), or "" */
    /* NASCAP's range law (see_law 2): the range R(E) = r1 E^n1 + r2 E^n2 (angstrom, E in keV)
     * as {r1, n1, r2, n2} (r1 = r2 = 0: none given), and the constants c1 (1/keV) and c2
     * (1/angstrom) that mote_ch_see_range_fit sets */
    double see_r[4], see_c1, see_c2;
} mote_ch_material;

/* The presets of spec 6.9 (bare, aluminium, gold, kapton, teflon, cover-glass); -1 if unknown. */
int mote_ch_material_preset(const char *name, mote_ch_material *m);
/* The library's k-th material (data/materials.dat; 0 ... count - 1), or NULL past the end. */
const char *mote_ch_material_library(int k, mote_ch_material *m);
/* The secondary yield of an electron of impact energy E (keV) at angle theta from the normal
 * (cos_t = cos theta), spec 6.7: the universal curve normalised to dmax at emax,
 * dmax K x^-0.35 (1 - exp(-2.28 x^1.35)), x = E/emax, K = 1/(1 - e^-2.28) (with see_angle=sec
 * 2.28 cos_t x^1.35 in the exponent and the whole divided by cos_t), or Sternglass's
 * dmax x exp(2 - 2 sqrt(x)). */
double mote_ch_see_yield(const mote_ch_material *m, double E_keV, double cos_t);
/* NASCAP's range law (Katz, Parks, Mandell, Harvey, Schnuelle and Wang, NASA CR-135256 (1977);
 * NASCAP-2K's documentation, Mandell et al. 2006): the primary loses energy along its range, at
 * the rate dE/dx = 1 / R'(E), and a secondary made at depth x escapes with probability
 * exp(-c2 x cos theta), so that
 *     delta(E, theta) = c1 integral_0^R(E) (dE/dx) exp(-c2 x cos theta) dx
 *                     = c1 integral_0^E exp(-c2 cos theta (R(E) - R(E'))) dE',
 * c2 chosen so that the yield at normal incidence peaks at see_emax, c1 so that it is see_dmax
 * there. Sets m->see_c1 and m->see_c2; an error when the range is not given (see_r) or gives no
 * such peak (a range that is not convex near see_emax). */
int mote_ch_see_range_fit(mote_ch_material *m, mote_err *err);
/* The backscattered fraction of electrons of impact energy E (keV) at angle theta (cos_t) on a
 * material of atomic number m->Z (0 without it): at normal incidence, from 1 keV up, the fit
 * of Hunger & Kuechler (1979, phys. stat. sol. (a) 56, K45), eta0 = C E^mz with
 * mz = 0.1382 - 0.9211 / sqrt(Z), C = 0.1904 - 0.2236 ln Z + 0.1292 ln^2 Z - 0.01491 ln^3 Z;
 * below 1 keV, eta0(1 keV) ln(E / 0.05) / ln 20, falling to 0 at 50 eV (an assumption below the
 * fit's range); at angle theta, Darlington's 0.891 (eta0 / 0.891)^cos(theta) (1975, J. Phys. D
 * 8, 85). */
double mote_ch_backscatter_yield(const mote_ch_material *m, double E_keV, double cos_t);
/* The share of backscattered electrons of a primary of energy E (eV) that escape a surface at
 * U (V): 1 at U <= 0, else 1 - U/E (their energies taken uniform on (0, E)), at least 0. */
double mote_ch_backscatter_escape(double U, double E_eV);
/* The ion-impact yield 2 dmax_i sqrt(x) / (1 + x), x = E/emax_i (0 without ion parameters). */
double mote_ch_ion_yield(const mote_ch_material *m, double E_keV);

/* A straight-line run (spec 5.1-5.3, 5.6): per component N histories from the injection sphere
 * of radius r_gen about the body's centre; tallies per triangle, side and species. */
typedef struct {
    uint64_t seed;
    int solo;       /* 1: under mpirun, this run stays in its process (an ensemble's replica) */
    uint64_t particles;    /* histories per component */
    double r_gen;          /* injection radius (m) */
    int threads;
    /* the charged body (spec 6.1-6.3): the potential U (V) of the body and, with field = 1, the
     * Coulomb field of the equivalent sphere (R_f: the exact sphere's radius, or the mesh's
     * R_eq); field = 0 keeps straight paths whatever U (faithful mode). A mesh in the field is
     * met by curved paths (spec 6.3): RK4 with steps dt = eta rho / |v| (eta 0 means 0.01), at
     * most max_steps (0 means 1e5) before a history counts as lost. */
    double potential;
    int field;
    double eta;
    long max_steps;
    /* the box injector (spec 5.2, straight paths only): the bounding box enlarged on each side
     * by margin times its diagonal, or by margin_m metres when that is > 0 */
    int box;
    double margin, margin_m;
    /* secondary emission by electron impact (spec 6.7): the material of each triangle (of the
     * exact sphere: one), or NULL for none */
    const mote_ch_material *const *tri_material;
    /* backscattered electrons (issue 37): with backscatter = 1, each electron impact on a
     * material with an atomic number also scores the backscattered fraction that escapes, in
     * the same emission tallies as its secondaries (scripts: on, `backscatter off`) */
    int backscatter;
    /* photoemission (spec 6.8): with sun = 1, light from the unit vector sun_dir at intensity
     * sun_intensity (1: 1 AU at normal incidence) on the materials' photo_j */
    int sun;
    double sun_dir[3], sun_intensity;
    /* differential charging (spec 6.10): the dielectric patch of each triangle (-1: the
     * conductor), npatch patches, and the grid dv[ndv] (ascending, V) of patch potentials
     * relative to the body at which each patch's net current is also tallied (field on only):
     * a hit of charge Z e whose impact energy E (eV) in the body's field has E - Z dv > 0 is
     * collected, with its emission at E - Z dv escaping by the patch's potential U + dv; NULL or
     * npatch 0: none */
    const int *tri_patch;
    int npatch, ndv;
    const double *dv;
    /* float (spec 6.5): the potential its search starts from (the root found is the one time
     * evolution from U0 reaches: the first sign change of I_net walking from U0 along it) */
    double U0;
    /* progress on a terminal (NULL: none): each run shows the share of its histories done under
     * the label (the command's name), and wipes the line when it ends; or, for a command of
     * several runs, `progress` (begun and ended by the command) shows each run as its next */
    const mote_context *progress_ctx;
    const char *progress_label;
    mote_progress *progress;
    /* the solved field (`field solved`): the treecode of the body's boundary-element charge
     * (per volt); a mesh's curved paths then follow it (its capacitance C replaces the body's
     * for R_f and the injection); NULL: the equivalent sphere's */
    const mote_ch_ftree *tree;
    /* conductors at their own potentials in the solved field (issue 55): bem's nc conductors
     * (frame and dielectric parts), triangle i on tri_cond[i], conductor k at cond_V[k] (V);
     * the run builds its own tree (opening angle theta) of their charge, sum_k V_k times bem's
     * column k, the paths follow it and an impact's energy is taken at its triangle's
     * potential. potential is then the frame's (the field is there when some V_k is not 0).
     * NULL: the body at potential everywhere. */
    const mote_ch_bem *bem;
    const int *tri_cond;
    const double *cond_V;
    double theta;
    /* the solved field's cache for the paths (src/charging/fcache.c: bem's conductors, or the
     * body at 1 V; NULL: the tree everywhere) */
    const struct ch_fcache *fcache;
} mote_ch_run_opts;

/* OML current (spec 6.4) of one Maxwellian component (n, kT eV, m, Z) to a sphere of area A at
 * potential U (A, signed as collected: Z e times the particle rate). */
double mote_ch_oml(double A, double U, double n, double kT, double m, int Z);

typedef struct {
    int nsp;
    uint32_t ntri;
    uint64_t histories;               /* per component */
    uint64_t hits[MOTE_CH_MAX_SPECIES][MOTE_CH_MAX_COMPONENTS];
    double weight[MOTE_CH_MAX_SPECIES][MOTE_CH_MAX_COMPONENTS]; /* A per history */
    double current[MOTE_CH_MAX_SPECIES];  /* collected, A (signed, spec 1.3) */
    /* secondary electrons emitted by the species' impacts (A, positive: they leave), per
     * component, and their standard errors */
    double see[MOTE_CH_MAX_SPECIES][MOTE_CH_MAX_COMPONENTS];
    double see_sigma[MOTE_CH_MAX_SPECIES][MOTE_CH_MAX_COMPONENTS];
    double sigma[MOTE_CH_MAX_SPECIES];    /* its standard error */
    int ncomp;                        /* components of all species, in order */
    uint64_t *tri_hits;               /* [component][triangle][side] */
    double *tri_see;                  /* the same for the secondary current, A (NULL: none) */
    uint64_t backface_hits;
    double seconds, traces_per_s;
    /* photoemission (spec 6.8; positive: electrons leave): the total, and per triangle and
     * side [triangle][side] the current and the sunlit fraction (NULL: the sun is off) */
    double photo;
    double *tri_photo, *tri_sunlit;
    /* the photoelectrons followed (the solved field): how many, and the standard error of
     * photo they leave (0 with the escape fractions) */
    uint64_t photo_paths;
    double photo_sigma;
    /* curved paths (spec 6.3): histories that ran out of steps, the steps taken, and the
     * largest relative energy error |dE| / (K0 + |q phi_g|) of a path */
    uint64_t lost, steps;
    double max_energy_err;
    /* differential charging (spec 6.10, o->npatch > 0): each patch's net current (A: collected,
     * plus its secondaries, backscattered and photoelectrons that escape) at each dv of the
     * grid, [npatch][ndv] */
    double *patch_I;
} mote_ch_result;

int mote_ch_run(const mote_ch_plasma *p, const mote_ch_body *b, const mote_ch_tracer *t,
                const mote_ch_run_opts *o, mote_ch_result *r, mote_err *err);
/* The net current of a run (A): the species' collected currents, the secondaries and the
 * photoelectrons that leave; its standard error in *sigma when that is not NULL. */
double mote_ch_net(const mote_ch_result *r, double *sigma);
/* The sunlit fraction of each triangle (frac[ntri]) and the side lit (side[ntri]: 0 front, 1
 * back, -1 none), from 16 stratified points per triangle, each casting a shadow ray toward sun
 * (a unit vector): a triangle is lit when its normal (a sheet: either side's) faces the sun. */
int mote_ch_sunlit(const mote_ch_body *b, const mote_ch_tracer *t, const double sun[3],
                   double *frac, int *side, int threads);
/* The escape fraction of emitted electrons of temperature kT (eV) from a body at U (V): 1 for
 * U <= 0, else (1 + U/kT) exp(-U/kT) (spec 6.7, 6.8). */
double mote_ch_escape(double U, double kT);
void mote_ch_result_free(mote_ch_result *r);

/* The floating potential (spec 6.5): the root U_f of the net collected current I(U), each I a
 * run of o (its potential replaced) with the same seed and histories (common random numbers),
 * bracketed by steps from o->U0 in the direction the current drives U (0.1 kT_min/e, doubling)
 * and refined until the bracket is below max(0.1 sigma_U, tol |U|); sigma_U =
 * sigma_I(U_f) / |dI/dU| from the final bracket. r receives the run at U_f; *oml the analytic
 * OML root of the equivalent sphere (no emission); *evals the runs made. */
int mote_ch_float(const mote_ch_plasma *p, const mote_ch_body *b, const mote_ch_tracer *t,
                  const mote_ch_run_opts *o, double tol, double *U_f, double *sigma_U,
                  double *oml, int *evals, mote_ch_result *r, mote_err *err);


extern const mote_model mote_model_charging;

#endif
