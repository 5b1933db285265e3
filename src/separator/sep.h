/* sep.h: internal to the separator model: what its files share. */
#ifndef MOTE_SEP_INTERNAL_H
#define MOTE_SEP_INTERNAL_H

#include "mote/separator.h"
#include "mote/buf.h"
#include "mote/mesh.h"

#include <math.h>

#define SEP_PI 3.14159265358979323846
/* contact.c: the Hertz-Mindlin law with tangential history and Coulomb friction (issue 56).
 * A material: Young's modulus (Pa) and Poisson's ratio. The constants of a pair (a wall: R2 and
 * m2 infinite), restitution e and friction mu. sep_hm_force: the force on body 1 from body 2
 * (n: unit normal from 2 to 1; v: the relative velocity of 1's contact point against 2's; xi:
 * the tangential spring, updated) for overlap delta over a step dt; returns |F_n|. */
typedef struct {
    double E, nu;
} sep_material;
typedef struct {
    double Y, G, R, m, beta, mu;
    double cn, gr; /* (sep_hm_damping: -2 sqrt(5/6) beta sqrt(2 Y*), sqrt(4 G* / Y*)) */
} sep_hm;
void sep_hm_pair(sep_hm *h, const sep_material *a, double R1, double m1, const sep_material *b,
                 double R2, double m2, double e, double mu);
/* Set the damping ratio beta of h (and the constants derived from it). */
void sep_hm_damping(sep_hm *h, double beta);

static inline double sep_dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The law (inline: the pair loop's cost is here). k_n = 4/3 Y* s, k_t = S_t = 8 G* s with
 * s = sqrt(R* delta); gamma_n = -2 sqrt(5/6) beta sqrt(S_n m*) = cn sqrt(s m*), gamma_t =
 * gamma_n sqrt(S_t / S_n) = gr gamma_n. */
static inline double sep_hm_force(const sep_hm *h, double delta, const double n[3],
                                  const double v[3], double dt, double xi[3], double F[3])
{
    const double sq = sqrt(h->R * delta);
    const double kn = 4.0 / 3.0 * h->Y * sq, kt = 8 * h->G * sq;
    const double gn = h->cn * sqrt(sq * h->m), gt = h->gr * gn;
    const double vn = sep_dot3(v, n);
    const double vt[3] = {v[0] - vn * n[0], v[1] - vn * n[1], v[2] - vn * n[2]};
    /* the normal force: repulsive (a damped spring that pulls is cut to 0) */
    double fn = kn * delta - gn * vn;
    fn = fn > 0 ? fn : 0;
    /* the history onto the present tangent plane (its length kept), then advanced */
    const double xn = sep_dot3(xi, n), x2 = sep_dot3(xi, xi);
    double xt[3] = {xi[0] - xn * n[0], xi[1] - xn * n[1], xi[2] - xn * n[2]};
    const double xt2 = sep_dot3(xt, xt);
    if (xt2 > 0 && xt2 != x2) {
        const double f = sqrt(x2 / xt2);
        for (int a = 0; a < 3; a++)
            xt[a] *= f;
    }
    for (int a = 0; a < 3; a++)
        xt[a] += vt[a] * dt;
    /* Coulomb's limit on the whole tangential force: beyond it the contact slides with
     * F_t = mu |F_n| along the trial force, and the spring is set to carry that force alone
     * (xi = -F_t / k_t: its direction stays against the sliding as k_t changes with the
     * overlap; one set to balance the dashpot too would turn round as the dashpot shrinks) */
    double ft[3] = {-kt * xt[0] - gt * vt[0], -kt * xt[1] - gt * vt[1], -kt * xt[2] - gt * vt[2]};
    const double f2 = sep_dot3(ft, ft), lim = h->mu * fn;
    if (f2 > lim * lim) {
        const double f = lim / sqrt(f2);
        for (int a = 0; a < 3; a++) {
            ft[a] *= f;
            xt[a] = kt > 0 ? -ft[a] / kt : 0;
        }
    }
    for (int a = 0; a < 3; a++) {
        xi[a] = xt[a];
        F[a] = fn * n[a] + ft[a];
    }
    return fn;
}
/* The damping ratio beta (<= 0) of the law above for which a head-on impact rebounds with
 * restitution e (0 < e <= 1): the rebound of this law depends on beta alone (not on the speed,
 * sizes, masses or moduli), found by integrating the dimensionless impact and bisecting. */
double sep_hm_beta_exact(double e);
/* LIGGGHTS's beta(e) = ln e / sqrt(ln^2 e + pi^2). */
double sep_hm_beta_liggghts(double e);
/* The Hertz contact time of a head-on impact at speed v (the undamped law): 2.868 (m^2 /
 * (R Y^2 v))^(1/5). */
double sep_hm_contact_time(double Y, double R, double m, double v);

/* A pair's tangential spring by the ids of the pair (a < b). */
struct sep_hrec {
    uint64_t a, b;
    double xi[3];
};
/* dem.c: keep the listed pairs' springs by their ids (before a removal, reorder or rebuild of
 * the list makes their places meaningless; nothing when there is nothing to keep or they are
 * kept already). */
int sep_hist_stash(mote_sep_system *s, mote_err *err);
/* The springs of the list's entries from the ones kept (or zero); s->hist_ok after. */
int sep_hist_fill(mote_sep_system *s, mote_err *err);
/* The springs of the contacts now, as records sorted by id (malloc'ed; *n of them): the ones
 * kept, or the list's (for the state file). */
int sep_hist_collect(const mote_sep_system *s, struct sep_hrec **out, size_t *n, mote_err *err);
/* The rotation arrays (hertz) for s->cap particles, the new ones zero. */
int sep_rot_reserve(mote_sep_system *s, mote_err *err);
/* 1 / the moment of inertia of a solid sphere of mass m (1 / m in im) and diameter d */
static inline double sep_inv_inertia(double im, double d)
{
    return 10 * im / (d * d);
}
/* Particle i's angular kicks w += h T / I with its last torque: h1 (a pending second half kick;
 * 0: none), then h2 (0: none); one expression wherever they are made (the same bits whether a
 * kick waits for the next step or not). */
static inline void sep_rot_kick(mote_sep_system *s, size_t i, double h1, double h2)
{
    const double iI = sep_inv_inertia(s->im[i], s->d[i]);
    for (int a = 0; a < 3; a++) {
        if (h1 > 0)
            s->w[3 * i + a] += h1 * iI * s->tq[3 * i + a];
        if (h2 > 0)
            s->w[3 * i + a] += h2 * iI * s->tq[3 * i + a];
    }
}

/* mesh.c: walls from meshes. A wall's place at time t: world x = C + R (x_b - c0) for x_b in
 * its own frame (C = c0 + vel t); its velocity at x is vel + w x (x - C). */
typedef struct {
    double R[3][3], C[3], c0[3], vel[3], w[3];
    int moving;
} sep_mesh_frame;
void sep_mesh_frame_at(const mote_sep_mesh *w, double t, sep_mesh_frame *f);
/* A contact with a wall: unit normal n from the wall to the centre, overlap delta, the wall's
 * velocity at the contact point and its angular velocity, and a key naming the wall and the
 * triangle (the tangential spring's, contact hertz). */
typedef struct {
    double n[3], delta, vw[3], ww[3], key;
} sep_mc;
/* the most wall contacts a particle has at once (beyond them, none), and its springs' slots */
#define SEP_MESH_MAXC 8
#define SEP_MESH_SLOTS 6
/* Add a wall from a repaired mesh (solid: every component must be closed). */
int sep_mesh_add(mote_sep_system *s, const mote_mesh *m, const char *path, int solid,
                 const double vel[3], const double axis[3], double omega, const double centre[3],
                 mote_err *err);
/* The wall's grid for particles up to radius rmax (nothing when built for it already). */
int sep_mesh_grid(mote_sep_mesh *w, double rmax, mote_err *err);
/* The contacts of the sphere (p, r) with every wall (frames fr: each wall's at this time),
 * each face, edge or vertex once, in the walls' and triangles' order; how many (at most
 * SEP_MESH_MAXC). */
int sep_mesh_contacts(const mote_sep_system *s, const sep_mesh_frame *fr, const double p[3],
                      double r, sep_mc *out);
/* Whether the sphere (p, r) touches a wall at time t or lies inside a solid one: the wall's
 * number from 1, or 0. */
int sep_mesh_blocks(const mote_sep_system *s, double t, const double p[3], double r);

/* the most steps a run may take (some 10^4 years at 10^5 steps a second): more is refused */
#define SEP_STEPS_MAX 1e13

/* dem.c: rebuild the cell lists; the cell of particle i; the contact forces into fx, fy, fz
 * from the positions, with the dashpots on the predicted velocities v + dt/2 F_old/m. */
int sep_cells_build(mote_sep_system *s, mote_err *err);
size_t sep_cell_of(const mote_sep_system *s, size_t i);
/* Enter particle i, added after the cells were built, in its cell's list of additions. */
int sep_cells_add(mote_sep_system *s, size_t i, mote_err *err);
/* Whether a particle of diameter d at (px, py, pz) would overlap one in the channel: through
 * the cells built after this step's exits, and their lists of particles added since. */
int sep_overlaps_any(const mote_sep_system *s, double px, double py, double pz, double d);
/* system.c: whether a sphere of radius r at (x, y, z) touches or is inside a plate. */
int sep_touches_plate(const mote_sep_system *s, double x, double y, double z, double r);
/* The contact forces (and with kick the second half kick) on s->threads threads. With the pair
 * list the kick is left pending (s->kick_h: the next drift or mote_sep_complete makes it);
 * brute force makes it here. pred < 0: nothing is known of the list's check; else pred says
 * whether a particle moved too far for the pair list (0, 1, with the blocks' boxes of the
 * displacements in s->ebox; 2: not checked, as the list was not valid when they were). */
int sep_contact_forces(mote_sep_system *s, double dt, int kick, int pred, mote_err *err);
/* *p (of *cap entries of size bytes) grown to hold at least need entries (with room to spare);
 * its contents kept. */
int sep_reserve(void **p, size_t *cap, size_t need, size_t size, mote_err *err);
/* The particles' blocks for the displacements' boxes (the pair list's row skip): SEP_EBLK
 * consecutive particles each; s->ebox for them (and their scratch). */
#define SEP_EBLK 64
int sep_ebox_reserve(mote_sep_system *s, mote_err *err);
/* The other forces' arrays s->gx, gy, gz: s->cap each (as fx, fy, fz). */
int sep_g_reserve(mote_sep_system *s, mote_err *err);
/* The scratch s->pv: at least 3 n doubles. */
int sep_pv_reserve(mote_sep_system *s, mote_err *err);
/* The neighbour rows from a list of pairs (a state being read): each row sorted. */
int sep_list_from_pairs(mote_sep_system *s, const uint32_t *pairs, size_t np, mote_err *err);

/* Below this many particles the passes run on one thread: the threads' start and meeting cost
 * more than they save (measured: bench/README.md). The default of threads_min_n. */
#define SEP_THREADS_MIN_N 4096

/* The threads for a pass over the particles. Every pass gives the same bits on any number. */
static inline int sep_threads(const mote_sep_system *s)
{
    return s->threads > 1 && s->n >= s->threads_min_n ? s->threads : 1;
}

/* Whether a particle of radius r at (x, y, z) may touch a side wall or an end of the channel
 * (W x D x H; both ends, however open): the largest of the differences r - x, x + r - W, ...
 * is positive. The contacts' pass and the drift (for it) decide alike with this expression. */
static inline int sep_near_wall(double r, double x, double y, double z, double W, double D,
                                double H, int dim)
{
    const double wx = r - x > x + r - W ? r - x : x + r - W;
    const double wz = r - z > z + r - H ? r - z : z + r - H;
    double wall = wx > wz ? wx : wz;
    if (dim == 3) {
        const double wy = r - y > y + r - D ? r - y : y + r - D;
        wall = wy > wall ? wy : wall;
    }
    return wall > 0;
}

/* The drift's exit codes (s->exc) carry this bit when the particle ends the drift near a wall
 * (sep_near_wall), for the contacts' pass that follows. */
#define SEP_EXC_WALL 16

/* feed.c: the feed of one step (the backlog, then the species' accounts). */
int sep_feed(mote_sep_system *s, mote_err *err);
/* feed.c: append a particle of species k with its id and d, m, x, y, z, vx, vy, vz, fx, fy,
 * fz (a state being read). */
int sep_append(mote_sep_system *s, int k, uint64_t id, const double v[11], mote_err *err);

/* system.c: the class tallies (all species and each; zeroed) and the profile sums of the K
 * slices, allocated afresh; the tallies freed. */
int sep_tallies_alloc(mote_sep_system *s, mote_err *err);
void sep_tallies_free(mote_sep_system *s);
int sep_profiles_alloc(mote_sep_system *s, mote_err *err);

/* Put the particles in the order of the cell lists just built
 * (spec 2.9: memory locality; ids do not change); the pair list must be built again. */
int sep_reorder(mote_sep_system *s, mote_err *err);

/* output.c */
typedef struct {
    int px;           /* picture height in pixels (0: 900) */
    int by_species;   /* colour by species instead of diameter */
    double y1, y2;    /* 3D: only particles with y1 <= y <= y2 (y2 <= y1: all) */
} sep_frame_opts;

/* path with its extension replaced by .png (malloc'ed). */
char *sep_png_name(const char *path);
/* The Tromp table and its PNG (path's stem + .png); *cut gets the all-species cut (may be NULL). */
int sep_write_tromp(const mote_sep_system *s, const char *path, const char *origin,
                    uint64_t seed, mote_sep_cut *cut, mote_err *err);
/* The profiles table and its three-panel PNG. */
int sep_write_profiles(const mote_sep_system *s, const char *path, const char *origin,
                       uint64_t seed, mote_err *err);
/* The live view's frame of the system (live.c). */
void sep_live_frame(const mote_sep_system *s, mote_buf *b);
/* The solid parts of the plates seen from the front: 4 numbers per rectangle (malloc'ed). */
int sep_plate_rects(const mote_sep_system *s, double **rects, size_t *n);
int sep_frame_png(const mote_sep_system *s, const char *path, const sep_frame_opts *fo,
                  mote_err *err);
int sep_write_xyz(const mote_sep_system *s, const char *path, mote_err *err);
/* The same frame as H5MD (h5md.h; SI units; 2D: the plane x, z): made anew (append 0) or
 * added at the end; id, species (with their names) and diameter per particle. */
int sep_write_h5md(const mote_sep_system *s, const char *path, const char *origin, uint64_t seed,
                   int append, mote_err *err);
/* The same frame as a VTK file (vtk.h), atomically. */
int sep_write_vtk(const mote_sep_system *s, const char *path, mote_err *err);
/* state.c: the descriptors of the state's scalar values (offsets in mote_sep_system), for the
 * parameter commands bound to them */
const struct mote_sf_field *sep_scalar_fields(size_t *n);
/* One extended XYZ frame of the system (arg) into f: a mote_frame_writer. */
int sep_xyz_frame(FILE *f, const void *s, mote_err *err);
/* One balance row (sep_balance_width numbers): t, then per species and in total the counts
 * fed, in, fines, coarse, lost, backlog and the same as masses. */
size_t sep_balance_width(const mote_sep_system *s);
void sep_balance_row(const mote_sep_system *s, double *row);
/* The balance file's text: its head (invariant_held, the columns) when head, then the rows
 * from .. to - 1 */
void sep_balance_text(FILE *f, const mote_sep_system *s, int held, const double *rows,
                      size_t from, size_t to, int head);

/* prepare.c: the gas profile's density and viscosity at z (the constants without a profile) */
void sep_profile_at(const mote_sep_system *s, double z, double *rho, double *mu);

#endif
