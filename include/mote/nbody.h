/* nbody.h: the N-body model (specs/nbody-galactica.md): material points under Newtonian gravity
 * or the Coulomb law, in Galactica's dimensionless form (G = 1, total mass 1), integrated by
 * Galactica's sixth-order Taylor scheme (spec 4.2, and its truncated orders 4.3) with
 * compensated summation (4.6); the exact axisymmetric rings of spec 9.1 and 9.2 as generators
 * and as references; the conserved quantities of spec 3.7. Every array is sized at run time;
 * the state lives in one struct (no globals). */
#ifndef MOTE_NBODY_H
#define MOTE_NBODY_H

#include "mote/command.h"
#include "mote/core.h"

#include <stdint.h>
#include <stdio.h>

/* ---- the real type (spec 4.6), chosen at build time: make PRECISION=double|long|quad ---------- */

#ifndef MOTE_NB_PRECISION
#define MOTE_NB_PRECISION 1
#endif
#if MOTE_NB_PRECISION == 2
typedef long double mote_real;
#define MOTE_REAL_DIG 21 /* significant digits that make a text round trip exact */
#define MOTE_REAL_NAME "long double"
#define MOTE_REAL_TOL 1e-19 /* the adaptive Taylor step's default tolerance (spec 4.5) */
#elif MOTE_NB_PRECISION == 4
__extension__ typedef _Float128 mote_real; /* __float128 on x86-64; glibc's libm functions */
#define MOTE_REAL_DIG 36
#define MOTE_REAL_NAME "quad"
#define MOTE_REAL_TOL 1e-33
#else
typedef double mote_real;
#define MOTE_REAL_DIG 17
#define MOTE_REAL_NAME "double"
#define MOTE_REAL_TOL 1e-16
#endif
/* The Taylor integrator's defaults (issue 37): in double a tolerance of 1e-18 at order 21 (an
 * odd order: see docs/nbody.md), where spec 4.5 took MOTE_REAL_TOL at order 20; the other types
 * keep the spec's. */
#if MOTE_NB_PRECISION == 1
#define MOTE_NB_TAYLOR_TOL 1e-18
#define MOTE_NB_TAYLOR_ORDER 21
#else
#define MOTE_NB_TAYLOR_TOL MOTE_REAL_TOL
#define MOTE_NB_TAYLOR_ORDER 20
#endif
#define MOTE_REAL_BUF 48
/* v written with MOTE_REAL_DIG significant digits (%.Ng) into buf, which is returned. */
const char *mote_real_str(mote_real v, char buf[MOTE_REAL_BUF]);
/* Parse a real at s (strtod's syntax) to the full precision; *end as strtod's. */
mote_real mote_real_parse(const char *s, char **end);

typedef enum { MOTE_NB_GRAVITY = 0, MOTE_NB_COULOMB = 1 } mote_nb_interaction;
enum { MOTE_NB_GALACTICA = 0, MOTE_NB_TAYLOR = 1, MOTE_NB_WH = 2 };
#define MOTE_NB_TAYLOR_MAX 60

/* ---- constants and scales (spec 3.5, 3.6) ------------------------------------------------- */

/* The constants of the Galactica-compatible unit sets (spec 3.6). */
#define MOTE_NB_G 6.67259e-11              /* m^3 kg^-1 s^-2 */
#define MOTE_NB_AU 1.49597870691e11        /* m */
#define MOTE_NB_SIDEREAL_YEAR_DAYS 365.25636042
#define MOTE_NB_EARTH_MASS 5.9742e24       /* kg */
#define MOTE_NB_SUN_EARTHS 332951.3        /* Sun mass in Earth masses */
#define MOTE_NB_SOLAR_SYSTEM_MASS 1.991787350282e30 /* kg */
#define MOTE_NB_E_CGSE 4.80298e-10         /* elementary charge, CGSE */
#define MOTE_NB_ME 9.1091e-31              /* kg */
#define MOTE_NB_MP 1.67252e-27
#define MOTE_NB_MN 1.67482e-27
#define MOTE_NB_R0 1.5e-15                 /* nuclear radius base, m */
#define MOTE_NB_RE 1.5e-15                 /* electron radius, m */
#define MOTE_NB_BOHR 5.29167e-11           /* m */

#define MOTE_NB_NORM_GLOBAL 2 /* mote_nb.adaptive: the Jorba-Zou global norm (spec 4.5) */
#define MOTE_NB_NAME 24 /* room for a body name and its terminating zero */

/* The scales of a run: x = x_m / Am, m_o = m / M, v = v_m kv, T = t kt (spec 3.5). */
typedef struct {
    double M;    /* mass scale M_Ss (kg) */
    double Am;   /* length scale (m) */
    double kv;   /* velocity scale (s/m) */
    double kt;   /* time scale (1/s) */
    double G;    /* gravitational constant used */
    double e2;   /* Coulomb constant e^2 / eps_d in kg m^3 s^-2 (with the 1e-9 of spec 3.2) */
    double eps;  /* relative permittivity */
    double Am_first; /* Am before the refinement Am := 1 / (kt kv) */
    int set;     /* 0: dimensionless (no physical scales) */
} mote_nb_units;

/* Scales with the time unit chosen first (spec 3.5, eq. 8 and 27), refined so that
 * Am = 1 / (kt kv) exactly: gravity with G, Coulomb with e2 = e^2 (SI) and eps. */
void mote_nb_units_from_time(mote_nb_units *u, mote_nb_interaction kind, double M, double kt,
                             double G, double e2, double eps);
/* Scales with the length unit Am chosen: kv from eq. 6 and kt = 1 / (Am kv). */
void mote_nb_units_from_length(mote_nb_units *u, mote_nb_interaction kind, double M, double Am,
                               double G, double e2, double eps);
/* Seconds in a named time unit: s, day, year (Julian, 365.25 d), century (the sidereal century
 * of spec 3.5); 0 for another name. */
double mote_nb_time_unit(const char *name);

/* ---- the system ----------------------------------------------------------------------------- */

typedef struct {
    mote_nb_interaction kind;
    uint32_t n, cap;
    mote_real *m, *q;          /* dimensionless mass and charge */
    mote_real *c, *w;          /* kernel coefficients (spec 3.3): a_i = c_i sum w_k r_ik / r^3 */
    mote_real *x, *v;          /* [3n] positions and velocities */
    mote_real *xc, *vc;        /* [3n] their compensation terms (Kahan) */
    mote_real *ra;             /* radius */
    mote_real *sp;             /* [3n] spin */
    mote_real *et;             /* thermal energy (from merges) */
    uint8_t *active;
    char (*name)[MOTE_NB_NAME]; /* body names ("" unnamed; see mote_nb_set_name) */
    mote_real *d5p;            /* [3n] fifth derivative at the start of the previous step */
    mote_real *acc, *jerk, *d4, *d5; /* [3n] this step's derivatives (scratch) */
    mote_real T, Tc;           /* time and its compensation */
    mote_real dt;              /* nominal step */
    mote_real dtp;             /* length of the previous step; 0 = no valid previous fifth derivative */
    int restart;            /* the next step is a restart step (first_step * dt): a fresh start */
    mote_real hlast;           /* the last step taken, by either integrator (for the monitor) */
    /* merging (spec 5) */
    int merging;            /* -1: when any body has a radius (default), 0 off, 1 on */
    uint64_t merges;        /* Galactica's Lsls */
    mote_real e_heat, e_spin;  /* energy into heat (eq. 11) and into spin by all merges */
    mote_real de_merge;        /* sum of E_tot(after) - E_tot(before) over merges */
    /* close approaches (spec 4.7, Galactica's bt), Galactica scheme while merging is on */
    mote_real bt;              /* step factor while a pair approaches contact (default 0.5; 1: off) */
    mote_real bt_hmin;         /* the shortest step, as a fraction of dt (default 1e-6) */
    mote_real happ;            /* the last step shortened by an approach (0: none) */
    mote_real max_overlap;     /* largest 1 - r / (Ra_i + Ra_k) of a merging pair */
    uint64_t hmin_forced;      /* adaptive steps held at hmin, longer than the tolerance allows */
    uint64_t approach_warnings; /* merges with an overlap above 10% after a step at bt_hmin dt */
    uint64_t steps;
    int order;              /* Galactica scheme order K, 2 ... 6 */
    mote_real first_step;      /* the restart step is first_step * dt (spec 4.2: 0.001) */
    int compensated;        /* compensated summation of x, v and T (default on) */
    int threads;            /* OpenMP threads of the pair passes (<= 1: one); results do not
                             * depend on it (every target sums its sources in index order) */
    uint32_t threads_min_n; /* threads are used from this many bodies up (default 1000; see
                             * NB_THREADS_MIN_N in nb.h for the measurement) */
    int simd;               /* pairs solved at once by the Taylor integrator's pair kernel: 0
                             * the widest the processor runs (8 with AVX-512F, 4 with AVX2, 2),
                             * or at most this many (1: one); the results do not depend on it */
    /* the general Taylor integrator (spec 4.4) */
    int integrator;         /* MOTE_NB_GALACTICA, MOTE_NB_TAYLOR or MOTE_NB_WH */
    int wh_corrector;       /* the Wisdom-Holman map's symplectic corrector: 0 (none), 3, 5, 7,
                             * 11 or 17 */
    /* the map's own state between two runs (wh.c): per body 3 Jacobi positions, 3 velocities
     * (corrected, half a drift ahead), then the inertial x and v it was synchronised to; live
     * while x and v still hold those (a change of the bodies starts the map afresh) */
    mote_real *wh_map;
    uint32_t wh_cap;
    int wh_live;
    mote_real wh_h;            /* the step and corrector the live map runs with */
    int wh_k;
    int taylor_order;       /* p, 2 ... MOTE_NB_TAYLOR_MAX */
    int taylor_memory;      /* 0 automatic, 1 store, 2 recompute */
    int adaptive;           /* 1: the step from the Taylor terms (spec 4.5), each body against
                             * its nearest neighbour; MOTE_NB_NORM_GLOBAL: one global norm
                             * (Taylor only); 0: dt */
    mote_real tol, safety, hmin, hmax; /* its tolerance, safety factor, bounds (0: none) */
    /* Galactica's literal step rule (spec 7.4, `step=doubling`): dt doubles, up to dt_max, when
     * the mean of D = |dMz_n - dMz_(n-1)| over a block of 5 steps exceeds 1.1 times the previous
     * block's; the block after a change is not compared */
    int doubling;
    mote_real dt_max;
    int dbl_have;              /* is dbl_prev set? */
    mote_real dbl_prev;        /* dMz after the previous step */
    mote_real dbl_sum;         /* the sum of D in the current block */
    int dbl_count;             /* steps in the current block */
    mote_real dbl_mean;        /* the previous block's mean (-1: not to be compared) */
    mote_real hprev;           /* the last adaptive step (0: none yet) */
    mote_real *tx;             /* (p + 1) blocks of 3n coefficients x^[n] */
    size_t tx_cap;
    mote_real *ts, *tf;        /* store mode: s^[j], f^[j] of every unordered pair */
    size_t tsf_cap;
    mote_real *tg;             /* a pass's G^[n] of every unordered pair (6 reals each) */
    size_t tg_cap;
    mote_real *tr;             /* store mode: R^[0], R^[1] of every unordered pair, [6][pairs] */
    size_t tr_cap;
    long double *taw;          /* the step's accelerations in long double (3n; double builds) */
    size_t taw_cap;
    mote_nb_units u;
    /* the constants in use (spec 3.6; the `constant` command replaces them): G (m^3 kg^-1 s^-2),
     * e2 = e^2 in kg m^3 s^-2 (with the 1e-9 of spec 3.2), the relative permittivity */
    double G, e2, eps;
    /* forces (spec 6.2): direct sums, or the approximate Barnes-Hut tree with opening angle
     * theta (the tree is scratch, rebuilt every step) */
    int tree_on;
    mote_real theta;
    /* Plummer softening (issue 37): every pair's r^2 is r^2 + soft^2 in the forces, their
     * derivatives and the potential energy (0: none) */
    mote_real soft;
    int tree_used;          /* some step of this run used the tree (outputs say so) */
    /* MPI (spec 6.3): this rank's bodies lo ... hi - 1 (all: 0 ... n - 1 on one process) */
    int mpi_rank, mpi_size;
    uint32_t lo, hi;
    struct nb_tree *tree;
    /* monitor references (spec 3.7), from the state at the start of the run */
    int ref_set;
    mote_real E0, Mza1, Lnorm1;
    mote_real L1[3];           /* L + S at the start (the reference of dL) */
} mote_nb;

void mote_nb_init(mote_nb *nb, mote_nb_interaction kind);
void mote_nb_free(mote_nb *nb);
/* Add a body (dimensionless values). Fails on non-finite values or a mass <= 0. */
int mote_nb_add(mote_nb *nb, mote_real m, mote_real q, const mote_real x[3], const mote_real v[3],
                mote_real ra,
                mote_err *err);
/* Name body i: 1 to MOTE_NB_NAME - 1 characters, a letter first, then letters, digits and
 * _ . + - (so a name is never a body number), and no other body of that name. */
int mote_nb_set_name(mote_nb *nb, uint32_t i, const char *name, mote_err *err);
/* The body a token names: a body's name, or its number 1 ... n; -1 when none. */
long mote_nb_find(const mote_nb *nb, const char *token);
/* Is the text a valid body name (mote_nb_set_name's rule)? */
int mote_nb_name_ok(const char *name);

/* Fill the kernel coefficients from masses and charges; fails when a Coulomb run has no
 * charge or two active bodies share a point. Called by the integrator before a run. */
int mote_nb_prepare(mote_nb *nb, mote_err *err);

/* Convert every body from SI (kg, m, m/s; charges in elementary charges) to the dimensionless
 * variables of u (spec 3.5, eq. 6). */
void mote_nb_from_si(mote_nb *nb, const mote_nb_units *u);

/* Shift to the barycentre (spec 3.4): the centre of mass position and velocity before the
 * shift go to xc and vc (may be NULL). */
void mote_nb_barycentric(mote_nb *nb, mote_real xc[3], mote_real vc[3]);

/* ---- steps between two dates (spec 9.5) ------------------------------------------------------- */

typedef struct {
    mote_real DeltaT;   /* the interval in the run's time unit */
    uint64_t Ltk;       /* steps: round(DeltaT / dT) */
    mote_real dtc;      /* the corrected step: DeltaT / Ltk, or fresh DeltaT / (Ltk - 1 + first) */
    mote_real t_end;    /* the time the steps reach, summed as the integrator sums them */
} mote_nb_steps;

/* The steps from JD1 to JD2 with nominal step dT, the time unit being `days` days (36525.636042
 * for the sidereal century); fresh: the first step is `first` (0.001) of the others. */
int mote_nb_steps_between(double jd1, double jd2, double days, mote_real dT, int fresh,
                          mote_real first, mote_nb_steps *out, mote_err *err);

/* ---- the Galactica scheme (spec 4.2, 4.3) --------------------------------------------------- */

/* The aggregated z moment's relative change dMz (spec 3.7) of the current state, in O(N). */
mote_real mote_nb_dmz(const mote_nb *nb);

/* Take `steps` steps of the nominal length dt; a step without a valid previous fifth
 * derivative (a fresh start) is first_step * dt long. */
int mote_nb_galactica(mote_nb *nb, uint64_t steps, mote_err *err);

/* Acceleration, jerk and the fourth and fifth derivatives at the current state, by the
 * Galactica scheme's two passes (into nb->acc, jerk, d4, d5); prepares the kernel first. */
int mote_nb_derivatives(mote_nb *nb, mote_err *err);

/* ---- the general Taylor integrator (spec 4.4) ------------------------------------------------ */

/* Run the chosen integrator (nb->integrator) for at most max_steps steps and up to the time
 * t_end (INFINITY: none), which is hit exactly. */
int mote_nb_integrate(mote_nb *nb, uint64_t max_steps, mote_real t_end, mote_err *err);
/* Merge every pair of active bodies closer than the sum of their radii (spec 5), repeating until
 * none touch; mote_nb_integrate calls it after every step when merging is on. */
int mote_nb_merge(mote_nb *nb, mote_err *err);
/* Dense output (spec 4.5): positions and velocities (3n each) at the time T_prev + s inside the
 * Taylor step just taken from T_prev, from that step's coefficients. */
void mote_nb_taylor_dense(const mote_nb *nb, mote_real s, mote_real *x, mote_real *v);
/* Take `steps` steps with the Taylor series of order taylor_order (fixed or adaptive). */
int mote_nb_taylor(mote_nb *nb, uint64_t steps, mote_err *err);
/* The normalized coefficients x^[0 .. p] of every body at the current state into X ((p + 1)
 * blocks of 3n); store != 0 keeps the pair histories in nb. Returns MOTE_ENOMEM when the pair
 * scratch cannot be allocated. */
int mote_nb_taylor_coefficients(mote_nb *nb, int p, int store, mote_real *X);
/* Jorba and Zou's order for a tolerance: ceil(1 - ln(tol)/2) (20 for 1e-16). */
int mote_nb_taylor_auto_order(mote_real tol);
/* Does a run of order p keep the pair histories (store) or recompute them? */
int mote_nb_taylor_memory_store(const mote_nb *nb, int p);

/* ---- conserved quantities (spec 3.7) -------------------------------------------------------- */

typedef struct {
    mote_real ekin, u, etot;
    mote_real P[3], L[3], S[3], R[3];  /* momentum, orbital and spin angular momentum, m-weighted position */
    mote_real mtot;
    mote_real ecorr;   /* E_tot - sum dE_merge (conserved through merges) */
    mote_real dE;      /* (E_corr - E0) / |E0|, or E_corr - E0 when E0 = 0 (mote_nb_de_absolute) */
    mote_real dMz;     /* (Mz + Sz - Mza1) / Mza1 (or over the normalisation of spec 3.7) */
    mote_real dL;      /* |L + S - (L + S)_0| / |(L + S)_0| */
} mote_nb_monitor;

void mote_nb_measure(const mote_nb *nb, mote_nb_monitor *mon);
/* dE is absolute, E_corr - E0, not relative: the reference energy E0 is 0. */
static inline int mote_nb_de_absolute(const mote_nb *nb) { return nb->ref_set && nb->E0 == 0; }
/* Take the current energy and aggregated z moment as the references of dE and dMz. */
void mote_nb_set_reference(mote_nb *nb);

/* ---- Solar-System data files (spec 9.3) ---------------------------------------------------- */

/* One body of a data file, converted to SI: GM (m^3/s^2), position (m), velocity (m/s), radius (m). */
typedef struct {
    char name[32];
    double gm, x[3], v[3], ra;
    long line;
} mote_nb_sbody;

typedef struct {
    mote_nb_sbody *b;
    int n;
} mote_nb_solar;

/* Read a 'mote solar-system 1' data file (format in docs/nbody.md); errors name file and line. */
int mote_nb_solar_read(const char *path, mote_nb_solar *s, mote_err *err);
void mote_nb_solar_free(mote_nb_solar *s);
/* Add the bodies named in the comma-separated list (NULL: all, in the file's order); with
 * merge_inner the masses of Mercury, Venus, Earth, Moon and Mars go to the Sun. Units: total mass,
 * the sidereal century and Am from eq. 8 refined (spec 3.5); then the barycentric frame. */
int mote_nb_solar_build(mote_nb *nb, const mote_nb_solar *s, const char *bodies, int merge_inner,
                        mote_err *err);

/* ---- the exact rings (spec 9.1, 9.2) -------------------------------------------------------- */

typedef struct {
    /* parameters */
    int nb;               /* bodies, central one included */
    double ka, e, tilt;   /* a = ka AU (gravity) or ka r_m (Coulomb); eccentricity; tilt (rad) */
    mote_real dt;         /* nominal step */
    /* gravity */
    double central_mass, total_mass, density;
    /* Coulomb */
    int A, Z, nq, lq;     /* mass number, nuclear charge, quantum numbers n and l */
    double time_unit, permittivity;
    /* results (SI unless stated) */
    double a, alpha1, rp, fN, mu1, vp, m0, m1, ra0, ra1, d, rn;
    /* dimensionless, in the build's real type */
    mote_real mo0, mo1, mu;    /* dimensionless masses and the Kepler parameter */
    mote_real a_o, rp_o, vp_o; /* a / Am, Rp / Am, vp kv */
    mote_real period;          /* dimensionless */
    mote_real M00;             /* N m_o1 (Rp/Am)(vp kv) */
    mote_real xc[3], vc[3];    /* centre of mass before the barycentric shift */
} mote_nb_ring;

/* The defaults of Appendix 1 (gravity) and Appendix 3 (Coulomb) of the seed document. */
void mote_nb_ring_defaults(mote_nb_ring *r, mote_nb_interaction kind);
/* Build the ring into an empty system (its scales included); fills the results of r. */
int mote_nb_ring_build(mote_nb *nb, mote_nb_ring *r, mote_err *err);
/* f_N = 1/4 sum_{j=1}^{N-1} 1 / sin(j pi / N). */
mote_real mote_nb_ring_fN(int N);
/* The exact position of ring body b (1 ... nb-1) at dimensionless time T. */
void mote_nb_ring_exact(const mote_nb_ring *r, int b, mote_real T, mote_real x[3]);
/* The largest |x - x_exact| / |x_exact| over the ring bodies, and the largest distance from the
 * tilted orbit plane over a (out_of_plane, may be NULL). */
mote_real mote_nb_ring_error(const mote_nb *nb, const mote_nb_ring *r, mote_real *out_of_plane);

/* ---- Galactica's area of matter (spec 9.4, control-file lines 1-20 and 22) ------------------ */

typedef struct {
    double B, C;          /* height and thickness of the box (A = 1) */
    double X0[3];         /* its corner */
    int Mu;               /* intervals along x */
    double RoS;           /* the separate body's density relative to the area (0: none) */
    double Xs[3], Us[3];  /* its position and velocity (dimensionless) */
    double wu, X01, Y01;  /* angular velocity about the axis through (X01, Y01) parallel to z */
    double Roa, Rob;      /* the area's mean density and the bodies' density, kg/m^3 */
    double Am;            /* the length unit, m (1 AU by default; only for SI values) */
    mote_real dt;         /* the nominal step */
    /* results */
    int nx, ny, nz;       /* nodes along x, y, z (the header's i2b, j2b, k2b) */
    int sep_added;        /* was the separate body added (no node closer than 1/Mu)? */
} mote_nb_area;

void mote_nb_area_defaults(mote_nb_area *a);
/* Build the area into an empty gravity system, with its scales. */
int mote_nb_area_build(mote_nb *nb, mote_nb_area *a, mote_err *err);

/* A Plummer sphere of n equal masses (G = 1, total mass 1, Plummer radius 1), barycentric, drawn
 * from the seed (Aarseth, Henon & Wielen 1974): the test problem of spec 6.2 (T18, T19). */
int mote_nb_plummer(mote_nb *nb, uint32_t n, uint64_t seed, mote_err *err);

/* ---- a Galactica job (spec 7) ------------------------------------------------------------------ */

typedef struct {
    const char *control;  /* the control file (galacf26.dat); the job's files are in its folder */
    int coulomb;          /* the Coulomb module: garek29.dat, galgok2, the 25/16 layout */
    int frames;           /* PNG pictures frame_000001.png, ... (spec 7.13) */
    int lenient, packed;  /* control-file reading: last token of a line; packed trios */
    int force;            /* start even when more than max_files files would be written */
    long max_files;       /* 0: 10 000 */
    int threads;
    double step_tol;      /* the step tolerance of Kl4 = 2, 3 (0: the build's default) */
    FILE *out;            /* the monitor and messages (NULL: quiet) */
    mote_nb *final;       /* when not NULL (and of the job's interaction): the final system */
    const mote_context *ctx; /* progress on a terminal and the live view (NULL: none) */
} mote_nb_job;

/* Run the job of a folder as Galactica would (spec 7.4): a first launch, a relaunch from the
 * checkpoint (Kl1 = 3, 4), a continuation from garez28.dat; errors also go to ErrGlctca. */
int mote_nb_job_run(const mote_nb_job *job, int *started, mote_err *err);
/* Check a job's control file without running or writing anything (a script's validation): the
 * values of a first launch, and k2 (0: unknown). A missing control file is not an error here. */
int mote_nb_job_check(const mote_nb_job *job, long *k2, mote_err *err);
/* Change the checkpoint of the job (KEY=VALUE words: Ltk Ltk2 Kl3 Kl7 Kl12 Kli Nbd dT) for its
 * next launch; a change of Ltk or Ltk2 plans Ltk * Ltk2 steps from the checkpoint's step. */
int mote_nb_job_edit(const mote_nb_job *job, int nedit, char *const *edits, mote_err *err);
/* `mote galactica [options]` (argv[0] is "galactica"): exit status 0, 1 (a bad job: nothing
 * ran) or 2 (a failure during the run). */
int mote_nb_galactica_main(int argc, char **argv, FILE *out, FILE *diag);

/* ---- the model as registered with the script language ---------------------------------------- */

extern const mote_model mote_model_nbody;

#endif
