/* separator.h: the gravitational separator (specs/separator.md): particles of several species
 * in a vertical gas upflow inside a channel, under gravity, buoyancy and Schiller-Naumann drag,
 * leaving at the top (fines) or the bottom (coarse); the one-dimensional axial gas model with
 * solids-fraction coupling, the size distributions and feed, the exact drag drift, exits and
 * bookkeeping, and the grade-efficiency (Tromp) curve; soft-sphere contacts (DEM) through cells
 * and a pair list, or the dilute mode (`collisions off`: walls reflect); perforated plates;
 * Langevin dispersion; exact state files. SI units throughout; z is up. */
#ifndef MOTE_SEPARATOR_H
#define MOTE_SEPARATOR_H

#include <stdint.h>

#include "mote/command.h"
#include "mote/core.h"
#include "mote/grid.h"

#define MOTE_SEP_MAX_SPECIES 16
/* A particle's velocity components, in a state file or set from Python: up to this in m/s */
#define MOTE_SEP_SPEED_MAX 1e6

/* ---- drag and terminal velocity (spec 2.7, 4) ---------------------------------------------- */

/* f(Re) of the Schiller-Naumann law: 1 + 0.15 Re^0.687 up to Re = 1000, 0.44 Re / 24 above. */
double mote_sep_drag_f(double Re);
/* The still-gas terminal velocity of a sphere (d, rho_p) in gas (rho_g, mu_g) under g, with
 * buoyancy: bisection on Re of C_d(Re) Re^2 = (4/3) Ar, Ar = rho_g (rho_p - rho_g) g d^3 / mu_g^2.
 * *Re_t gets the Reynolds number (may be NULL). 0 when the particle does not sink. */
double mote_sep_terminal_velocity(double d, double rho_p, double rho_g, double mu_g, double g,
                                  double *Re_t);
/* The diameter whose terminal velocity is v (the cut size d* for v = U0), by bisection. */
double mote_sep_cut_size(double v, double rho_p, double rho_g, double mu_g, double g);

/* ---- size distributions (spec 2.5) ---------------------------------------------------------- */

enum { MOTE_SEP_MONO, MOTE_SEP_LOGNORMAL, MOTE_SEP_ROSIN_RAMMLER, MOTE_SEP_LOGUNIFORM, MOTE_SEP_TABLE };

typedef struct {
    int type;
    double a, b;      /* mono: d; lognormal: d50, sigma_g; rosin_rammler: d', n */
    double lo, hi;    /* truncation (all but mono) */
    int number_basis; /* 0: mass basis (default), 1: number basis */
    /* the number-basis cumulative distribution on n nodes evenly spaced in ln d */
    int n;
    double *lnd, *cdf;
    /* table: tn rows of diameter td (increasing) and cumulative undersize tF (non-decreasing),
     * piecewise linear in ln d (owned; set with mote_sep_dist_table) */
    int tn;
    double *td, *tF;
} mote_sep_dist;

/* Give a table distribution its rows (copied); err names the first bad row (from 1). lo and
 * hi become the table's range unless already set inside it. */
int mote_sep_dist_table(mote_sep_dist *s, int n, const double *d, const double *F, mote_err *err);
/* Tabulate the sampling table of a distribution (4096 nodes); err on bad parameters. */
int mote_sep_dist_build(mote_sep_dist *s, mote_err *err);
void mote_sep_dist_free(mote_sep_dist *s);
/* A diameter from a uniform u in [0, 1) (inverse transform, linear in ln d). */
double mote_sep_dist_sample(const mote_sep_dist *s, double u);
/* The smallest and largest diameters it can give. */
double mote_sep_dist_min(const mote_sep_dist *s);
double mote_sep_dist_max(const mote_sep_dist *s);

/* ---- perforated grids (spec 2.4; plates.c) ---------------------------------------------------- */

#define MOTE_SEP_MAX_PLATES 16
/* The most holes a plate has (a pattern or a list), and the memory one takes (the hole, its bin
 * and its index entries) for the estimate checked before any is made. */
#define MOTE_SEP_MAX_HOLES 10000000
#define MOTE_SEP_HOLE_BYTES 48.0

/* A horizontal plate zb <= z <= zb + t pierced by rectangular holes [x1, x2] (x [y1, y2] in 3D). */
typedef struct {
    double zb, t;
    size_t nh;
    double *h;          /* 4 per hole: x1 x2 y1 y2 */
    int listed;         /* from a file (else a pattern) */
    long dropped;       /* pattern holes dropped for crossing a wall */
    double phi;         /* open-area fraction (prepare) */
    /* the bin index: about one hole per bin */
    int nbx, nby;
    double bwx, bwy;
    uint32_t *bin_start, *bin_idx;
} mote_sep_plate;

/* A plate from a pattern: holes of size a (x, y) at off + i pitch, kept when wholly inside the
 * cross-section W (x D). */
int mote_sep_plate_pattern(mote_sep_plate *p, int dim, double W, double D, double zb, double t,
                           const double a[2], const double pitch[2], const double off[2],
                           mote_err *err);
/* A plate from a list of nh holes (4 numbers each). */
int mote_sep_plate_list(mote_sep_plate *p, double zb, double t, const double *h, size_t nh,
                        mote_err *err);
void mote_sep_plate_free(mote_sep_plate *p);
/* Build the bin index (before hole_at, check and features). */
int mote_sep_plate_index(mote_sep_plate *p, int dim, double W, double D, mote_err *err);
/* Check a plate (number index for messages): inside the channel, holes non-empty, inside the
 * walls, not overlapping, none narrower than dmin, at least one. */
int mote_sep_plate_check(const mote_sep_plate *p, int index, int dim, double W, double D,
                         double H, double dmin, mote_err *err);
/* The open-area fraction. */
double mote_sep_plate_open(const mote_sep_plate *p, int dim, double W, double D);
/* The hole under (x, y), or -1 over solid. */
long mote_sep_plate_hole_at(const mote_sep_plate *p, int dim, double x, double y);
/* The contacts of a sphere of radius r centred at c with the plate: up to 4 features, each an
 * overlap delta > 0 and the unit normal n from the plate to the centre; the count, or -1 when
 * the centre is inside the solid. */
int mote_sep_plate_features(const mote_sep_plate *p, int dim, const double c[3], double r,
                            double delta[4], double n[4][3]);

/* ---- walls from meshes (issue 56; mesh.c) ------------------------------------------------- */

#define MOTE_SEP_MAX_MESHES 16
/* A rigid wall of triangles (from a mesh file, mesh.h), at rest or moving: translated at vel
 * and turned at omega (rad/s, right-handed) about the axis through centre (where it is at t = 0,
 * then moving with vel). Particles touch its faces, edges and vertices (both sides of an open
 * sheet); a solid one (every component closed) also keeps particles out of its inside. The
 * triangles' grid is in the wall's own frame (built for particles up to rmax). */
typedef struct {
    char name[64];           /* the file's base name (messages) */
    size_t nv, nt;
    double (*v)[3];          /* vertices at t = 0 (m) */
    uint32_t (*t)[3];        /* triangles (closed components wound outward) */
    int solid;
    double vel[3], axis[3], omega, centre[3];
    /* the grid: cells of edge h from lo, n[3] of them; cell c lists the triangles within
     * rmax of any of its points: ctri[cstart[c] .. cstart[c + 1]) */
    double lo[3], h, rmax;
    int nc[3];
    uint32_t *cstart, *ctri;
    /* the edges a picture draws: an open edge, or one whose two triangles meet at more than
     * 20 degrees (the outline, not a flat face's triangulation) */
    uint32_t (*fe)[2];
    size_t nfe;
    double (*plane)[4];      /* each triangle's unit normal n and n . (a vertex): a sphere
                              * farther from the plane than its radius cannot touch it */
} mote_sep_mesh;
void mote_sep_mesh_free(mote_sep_mesh *w);

/* ---- the system ----------------------------------------------------------------------------- */

typedef struct {
    char name[32];
    double rho;          /* material density, kg/m^3 */
    double E, nu;        /* Young's modulus (Pa; 0: not given) and Poisson's ratio (contact
                          * hertz) */
    mote_sep_dist dist;
    int have_dist;
    double w;            /* feed mass fraction */
} mote_sep_species;

/* per-species counters (spec 2.11) */
typedef struct {
    uint64_t fed, fines, coarse, lost;
    double m_fed, m_fines, m_coarse, m_lost, m_gen; /* m_gen: mass generated by the feed */
} mote_sep_count;

typedef struct {
    int dim;                             /* 2 or 3 */
    double W, H, D, D2;                  /* channel; D: 3D depth; D2: nominal 2D depth (0: d_max) */
    int open_bottom, open_top;
    double U0, rho_g, mu_g, g;           /* gas and gravity */
    /* an optional gas profile (spec 2.6): rho_g(z) and mu_g(z) (NaN: the constant mu_g) on gp_n
     * heights, linear between them and constant beyond; per slice centre in rho_sl, mu_sl */
    size_t gp_n;
    double *gp_z, *gp_rho, *gp_mu;
    double *rho_sl, *mu_sl;
    int coupling;                        /* solids-fraction feedback on the gas */
    int K;                               /* slices (0: auto, about 4 d_max each) */
    double eps_gas_min, chi;             /* clamp on eps_g; hindered-drag exponent */
    double D_t, T_gas;                   /* dispersion: turbulent coefficient (m^2/s), gas
                                          * temperature for Brownian diffusion (K; 0: none) */
    double e_pw;                         /* restitution at walls (-1: e_pp) */
    double parcel;                       /* each particle stands for this many of its size and
                                          * species (>= 1; the dilute mode only): the masses
                                          * tallied, fed and held, the solids fraction and the
                                          * drag on the gas count it; the counts are of parcels */
    double dt_user;                      /* the time step asked for (0: auto) */
    double dt;                           /* the time step in use (prepare) */
    /* the feed's backlog (spec 2.5): particles drawn but not yet placed */
    size_t nback, back_cap;
    int *back_s;
    double *back_d;
    /* contacts (spec 2.8, 2.9): dem (soft spheres) or off; restitution, stiffness k_hat (0:
     * from the overlap fraction delta_f at v_imp, 0: the default speed), contact-time steps */
    int dem, brute;
    double e_pp, khat, delta_f, v_imp;
    double e_pair[MOTE_SEP_MAX_SPECIES][MOTE_SEP_MAX_SPECIES]; /* overrides of e_pp (0: none) */
    int nc;
    double khat_used;                    /* the stiffness in use (prepare) */
    /* the contact law (issue 56): 0 linear spring-dashpot, frictionless, no rotation (spec
     * 2.8); 1 Hertz-Mindlin with tangential history, Coulomb friction, rotation and rolling
     * friction (constant directional torque), the constants from the species' E and nu */
    int hertz;
    double mu_pp, mu_pw;                 /* sliding friction between particles, at walls and
                                          * plates (-1: mu_pp) */
    double mur_pp, mur_pw;               /* rolling friction (-1 at walls: mur_pp) */
    double mu_pair[MOTE_SEP_MAX_SPECIES][MOTE_SEP_MAX_SPECIES];  /* overrides (-1: none) */
    double mur_pair[MOTE_SEP_MAX_SPECIES][MOTE_SEP_MAX_SPECIES];
    /* cohesion (SJKR: an attraction k_c times the contact area; J/m^3), between particles, at
     * walls and grids (-1: coh_pp), per species pair (-1: none) */
    double coh_pp, coh_pw;
    double coh_pair[MOTE_SEP_MAX_SPECIES][MOTE_SEP_MAX_SPECIES];
    double E_w, nu_w;                    /* the walls' and plates' material (0: the particle's) */
    int e_true;                          /* 1: the damping set so that a head-on rebound has the
                                          * restitution given; 0: LIGGGHTS's beta(e) */
    double hm_beta[MOTE_SEP_MAX_SPECIES * (MOTE_SEP_MAX_SPECIES + 1)]; /* (prepare) the damping
                                          * of each species pair, then at the walls */
    /* per particle with hertz (else NULL; s->cap each): angular velocity and torque (3 each),
     * the other torques' array (the contacts' pass writes there and the two swap), and the
     * tangential springs at walls and plates, one per axis (the axis of the contact's normal;
     * 9 each) */
    double *w, *tq, *tq2, *wh;
    size_t rot_cap;
    double rot_h1, rot_h2;               /* within a step: its angular kicks (the pending one and
                                          * the first half), made by the contacts' pass */
    /* the tangential springs of the listed pairs, 3 per row entry (both copies of a pair, the
     * same numbers: each made from the pair in the order lower id first); zero where the pair
     * is not in contact */
    double *hist;
    size_t hist_cap;
    /* the pairs made once each (contact hertz): pbuf, per pair in contact a slot of 9 (the
     * force on the owner, the lower index, the torques on the owner and on the partner; slot
     * 0: zeros); cidx, per owner entry (its row's index below its partner's) its pair's slot
     * (0: not in contact); mir, per entry the index of the same pair's entry in the partner's
     * row; ostart, per row the owner entries of the rows before it */
    double *pbuf;
    uint32_t *mir, *cidx, *ostart;
    size_t pbuf_cap, mir_cap, cidx_cap, ostart_cap;
    /* per particle the sums of its contacts with the box's walls, made by lanes (6), and
     * whether they were (wflag 1; 0 none; 2 made one by one) */
    double *wres;
    unsigned char *wflag;
    size_t wres_cap, wflag_cap;
    int nb_idx_ok;                       /* the rows' indices still name the particles they were
                                          * built for (no removal or reorder since), */
    size_t nb_n;                         /* the particles with rows (at the build) */
    int hist_ok;                         /* hist holds the springs of the present rows */
    /* the springs by the ids of their pairs (lower first), sorted: kept across a removal,
     * reorder or rebuild (hmap_pending: the list's entries are to be filled from it) */
    struct sep_hrec *hmap;
    size_t nhmap, hmap_cap;
    int hmap_pending;
    double *fx, *fy, *fz;                /* last contact forces, per particle */
    /* the cells (the core grid, grid.h): edges >= d_max + skin, at most about one per
     * particle, on the axes x, (y,) z; a counting sort at each search */
    mote_grid grid;
    int nsort;                           /* reorder the particles by cell every nsort steps (at
                                          * the first search after them) */
    uint64_t last_sort;                  /* the step of the last reorder */
    int32_t *nhead, *nnext;              /* particles added since: a list per cell */
    size_t nhead_cap, nnext_cap;
    size_t n_built;                      /* particles when the cells were built, */
    uint64_t built_step;                 /* and at which step (+1; 0: never) */
    /* the pair list (spec 2.9's allowed optimisation): the pairs closer than r_i + r_j + skin
     * when it was built; kept while no particle was added, removed or reordered and none has
     * moved more than skin/2 since, so it holds every contact a rebuild would find */
    double skin;                         /* (0: 0.3 d_min; < 0: none, search every step) */
    double skin_used;
    /* as rows: particle i's neighbours (every j, both ways) in nb[nb_start[i] ..
     * nb_start[i + 1]), each row in increasing index, so that a particle's contact forces are
     * summed in an order that depends on neither the build nor the threads */
    uint32_t *nb, *nb_start;
    size_t npl, nb_cap, nbs_cap;         /* npl: the pairs (half the entries) */
    size_t nb_w;                         /* the largest |i - j| of a listed pair */
    double *xref;                        /* positions at the build (3 per particle) */
    size_t xref_cap;
    /* each row's smallest gap |r_ij| - (r_i + r_j) at the build (+inf: an empty row), made at
     * the first force pass after a build or a load. The particles' displacements since the
     * build lie, block by block, in boxes; the separation of a pair changed by at most the
     * diagonal of the union of its two blocks' boxes, so a row whose gap exceeds that for
     * every pair it may list holds no contact and is not searched */
    double *gap;
    size_t gap_cap;
    int gap_ok;
    double *ebox;                        /* per block of SEP_EBLK particles (sep.h), the box of
                                          * their displacements since the build (lo x y z, hi x
                                          * y z), then scratch for the blocks' reach */
    size_t ebox_cap;
    int no_gap_skip;                     /* search every row (tests: the same forces either way) */
    int simd;                            /* lanes of the contact hertz law: 0 the widest the
                                          * processor runs; 2, 4: at most that (tests: the
                                          * same bits) */
    int no_pending;                      /* complete every step in a run (tests: the same bits
                                          * as a second half kick left for the next drift) */
    uint64_t gap_skips;                  /* rows not searched so far (diagnostic) */
    uint64_t mods, list_mods;            /* additions and removals so far; at the build */
    int list_ok;
    uint64_t list_builds;                /* how often it was built */
    double max_overlap;                  /* largest overlap / diameter met */
    uint64_t fast_moves;                 /* steps in which a particle moved more than r_min/4 */
    uint64_t contacts_pp;                /* particle contacts of the last step */
    uint64_t candidates;                 /* pairs tested in the last step's search */
    double *pv;                          /* scratch: predicted velocities (3 per particle; brute
                                          * force and the runs without a pair list) */
    double *gx, *gy, *gz;                /* the other forces: the contacts' pass writes the new
                                          * forces there and the two swap (the old ones give
                                          * the neighbours' predicted velocities meanwhile);
                                          * between passes scratch (the drag's sampling) */
    size_t g_cap;
    double kick_h;                       /* a second half kick v += kick_h F / m is pending
                                          * (0: none): the next drift makes it, or
                                          * mote_sep_complete */
    size_t *ex_i, nex, ex_cap;           /* scratch: the particles leaving in this step */
    int *ex_c;
    size_t pv_cap;
    unsigned char *exc;                  /* scratch: each particle's exit code in a step */
    size_t exc_cap;
    double *blk;                         /* scratch: per block of particles, slice sums */
    size_t blk_cap;
    int threads;                         /* threads for the passes over the particles (0, 1:
                                          * one); the results do not depend on it */
    size_t threads_min_n;                /* threads are used from this many particles up
                                          * (default SEP_THREADS_MIN_N, sep.h, measured) */
    int nsp;
    mote_sep_species sp[MOTE_SEP_MAX_SPECIES];
    int nplate;
    mote_sep_plate plate[MOTE_SEP_MAX_PLATES];
    int nmesh;
    mote_sep_mesh mesh[MOTE_SEP_MAX_MESHES];
    /* contact hertz with meshes: per particle SEP_MESH_SLOTS tangential springs at the walls'
     * triangles (4 each: a key, 0 when free, then the spring) */
    double *mh;
    size_t mh_cap;
    /* the feed (spec 2.5): band centre and height (0: 2 d_max), mass rate, window, velocity */
    double zf, hf, rate, t_start, t_stop;
    double fx1, fx2, fy1, fy2;           /* window (fx2 <= fx1: the whole cross-section) */
    double vf[3];
    /* the particles: structure of arrays */
    size_t n, cap;
    double *x, *y, *z, *vx, *vy, *vz, *d, *m;
    double *im;                          /* 1 / m */
    int *s;                              /* species */
    uint64_t *id;
    uint64_t next_id;
    /* the gas profile (spec 2.6) */
    double dz, *eps_s, *u_g;
    double tau_eps, *eps_r;              /* relaxation time of eps_s (0: none), relaxed eps_s */
    int eps_r_valid;
    int clamped;                         /* slices whose eps_g was clamped */
    /* bookkeeping and statistics */
    mote_sep_count cnt[MOTE_SEP_MAX_SPECIES];
    int nclass;                          /* Tromp classes */
    double *class_edge;                  /* nclass + 1 edges */
    double *cl_mf, *cl_mc;               /* per class: mass to fines, to coarse */
    uint64_t *cl_nf, *cl_nc;             /* counts */
    double *cls_mf, *cls_mc;             /* per class and species (class * MAX_SPECIES + k) */
    uint64_t *cls_nf, *cls_nc;
    /* profiles (spec 3.2): time-weighted sums per slice from avg_from on, over prof_time */
    double avg_from, prof_time;
    double prof_wait;                    /* time since the last sample (every 10th step) */
    double *prof_eps;                    /* K * (MAX_SPECIES): eps_s of each species */
    double *prof_n, *prof_mvz, *prof_m, *prof_ug, *prof_fd; /* count, m v_z, m, u_g, drag F_z */
    int prof_K;                          /* the slices the sums were made on */
    double t;
    uint64_t steps;
    mote_rng rng;
} mote_sep_system;

/* Fill defaults (2D, air at 20 C, g = 9.81, both ends open, coupling on, DEM with e 0.5,
 * delta_f 0.05, N_c 50). */
void mote_sep_init(mote_sep_system *s);
void mote_sep_free(mote_sep_system *s);
/* Check the parameters and prepare for running (slices, classes, the time step): err names
 * what is wrong. Called before the first step after a change. */
int mote_sep_prepare(mote_sep_system *s, mote_err *err);
/* d_min and d_max over all species' distributions. */
void mote_sep_size_range(const mote_sep_system *s, double *dmin, double *dmax);
/* Add `count` particles of species sp (or total mass `mass` when count is 0) in the feed zone. */
int mote_sep_insert(mote_sep_system *s, int sp, uint64_t count, double mass, mote_err *err);
/* Advance the simulated time by T in steps of s->dt (the last one shortened to land on T). */
int mote_sep_run(mote_sep_system *s, double T, mote_err *err);
/* Recompute the solids fraction and gas velocity of every slice (spec 2.6); with a relaxation
 * time, the relaxed fraction moves dt / tau_eps of the way (dt = 0: not at all, unless it was
 * never set). 0, or an error when out of memory (then nothing changed). */
int mote_sep_gas_update(mote_sep_system *s, double dt, mote_err *err);
/* The gas velocity at height z (interpolated between slice centres). */
double mote_sep_gas_at(const mote_sep_system *s, double z);
/* The gas density and viscosity at height z (the profile, else the constants). */
void mote_sep_gas_props(const mote_sep_system *s, double z, double *rho, double *mu);
/* The reference cut of species k (spec 3.1): the diameter whose still-gas terminal velocity is
 * the particle-free gas velocity at the feed height, G / rho_g(z_f). */
double mote_sep_d0_star(const mote_sep_system *s, int k);
/* Set the gas profile from n heights (strictly increasing), densities (> 0) and viscosities
 * (> 0, or NaN for the constant); err names the first bad row as row r (from 1). */
int mote_sep_set_gas_profile(mote_sep_system *s, size_t n, const double *z, const double *rho,
                             const double *mu, mote_err *err);
/* The bookkeeping invariant fed = in channel + fines + coarse + lost (spec 2.11): 0 when it
 * holds (counts exactly, masses to 1e-12), else -1. */
int mote_sep_check_balance(const mote_sep_system *s);

/* ---- contacts (spec 2.8, 2.9; dem.c) --------------------------------------------------------- */

/* The contact stiffness k_hat (N/m^2) and the time step the rule of 2.8 allows. */
double mote_sep_khat(const mote_sep_system *s);
double mote_sep_dt_limit(const mote_sep_system *s);
/* The pairs in contact (distance < r_i + r_j), by the cell grid or (brute) all pairs, as index
 * pairs i < j into pairs[2 k], sorted; the count (up to cap; more are counted, not stored). */
size_t mote_sep_pairs(mote_sep_system *s, int brute, uint32_t *pairs, size_t cap);

/* ---- state files (spec 2.12; state.c) -------------------------------------------------------- */

/* Write the whole state exactly (atomically), with the seed the script set. */
int mote_sep_save(const mote_sep_system *s, uint64_t seed, const char *path, mote_err *err);
/* Read a state written by mote_sep_save into s (replacing it only when the whole file is good;
 * errors name FILE:LINE). */
int mote_sep_load(mote_sep_system *s, uint64_t *seed, const char *path, mote_err *err);

/* ---- the Tromp curve (spec 3.1) ------------------------------------------------------------- */

typedef struct {
    double d25, d50, d75;       /* NAN when T does not cross */
    double kappa, Ep, I;
    int crossings50;            /* how often T crosses 1/2 */
} mote_sep_cut;

/* The partition numbers T_i (mass basis; NAN for empty classes) into T[nclass], and the
 * characteristic sizes. */
void mote_sep_tromp(const mote_sep_system *s, double *T, mote_sep_cut *cut);
/* The same for species k (k < 0: all). */
void mote_sep_tromp_species(const mote_sep_system *s, int k, double *T, mote_sep_cut *cut);
/* Zero the exit tallies of the classes and the profile sums; averaging restarts now. */
void mote_sep_reset_stats(mote_sep_system *s);
/* The cross-section area (W D, or W D2 in 2D). */
double mote_sep_cross_section(const mote_sep_system *s);
/* Make a pending second half kick (after a run every step is complete; within one, the kick
 * of a step the hook does not see rides on the next step's drift). */
void mote_sep_complete(mote_sep_system *s);
/* The pieces of mote_sep_run, for a run through the core's loop (mote_run, loop.h) with
 * observers: mote_sep_prepare first; mote_sep_advance, the model's advance, steps towards t_end
 * (the remainder of a step under 1e-9 of it is not taken) and returns after a step that
 * need(ctx, s) wants to see, complete (need NULL: none; need is asked after a step whose second
 * half kick is pending (DEM with the pair list): a step it does not want to see has its kick
 * ride on the next step's drift, the same bits; a step with nothing pending is always seen);
 * mote_sep_run_end completes the last step, updates the gas fractions and checks the mass
 * balance (rc: the run's code so far; returns the first error). */
int mote_sep_advance(mote_sep_system *s, double t_end, int (*need)(void *, const mote_sep_system *),
                     void *ctx, mote_err *err);
int mote_sep_run_end(mote_sep_system *s, int rc, mote_err *err);

extern const mote_model mote_model_separator;

#endif
