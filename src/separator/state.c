/* state.c: the separator's state file (`save`, `load`; specs/separator.md 2.12): the parameters,
 * species, plates, size classes, the particle arrays with their ids and last contact forces, the
 * random stream, the feed accounts and backlog, the relaxed solids fraction, the exit tallies,
 * the profile sums, counters, time and step number, every number exact (%.17g reads back to the
 * same double), so that save, load, save gives the same bytes and a run continued from a file
 * is bit for bit the run that never stopped. The schedules of frames, snapshots and the balance
 * belong to the script and are not in the file.
 *
 * The file is a sequence of lines "KEY value ...", read back in the order written; reading is
 * strict and names FILE:LINE for every fault. Counts are checked against what follows before
 * anything is allocated for them. */
#include "mote/separator.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "mote/statefile.h"

#include "sep.h"

#define SEP_PI 3.14159265358979323846

/* A real for the file: exact, with inf written "inf" (t_stop may be) and nan "nan" */
static void real_put(char out[64], const void *v)
{
    const double x = *(const double *)v;
    if (isinf(x))
        snprintf(out, 64, "%s", x > 0 ? "inf" : "-inf");
    else if (isnan(x))
        snprintf(out, 64, "nan");
    else
        mote_sf_exact_put(out, v);
}
static size_t real_get(const char *t, void *v)
{
    static const char *const words[3] = {"inf", "-inf", "nan"};
    const double values[3] = {INFINITY, -INFINITY, NAN};
    for (int k = 0; k < 3; k++) {
        const size_t n = strlen(words[k]);
        if (strncmp(t, words[k], n) == 0 && (t[n] == '\0' || t[n] == ' ' || t[n] == '\t')) {
            *(double *)v = values[k];
            return n;
        }
    }
    return mote_sf_exact_get(t, v);
}
static const mote_sf_codec REAL = {sizeof(double), real_put, real_get, NULL};


/* The scalar parameters by name ("real W 0.05", "int dim 2"), the counters and the random
 * stream, as descriptor tables (statefile.h); the seed is read into a scratch. */
#define SR(NAME, M)                                                                          \
    {.key = "real " NAME, .name = NAME, .type = MOTE_SF_CODEC,                            \
     .offset = offsetof(mote_sep_system, M), .codec = &REAL}
#define SI(NAME, M)                                                                          \
    {.key = "int " NAME, .name = NAME, .type = MOTE_SF_INT,                               \
     .offset = offsetof(mote_sep_system, M), .lo = -1, .hi = 1000000}
#define SU(K, NAME, M)                                                                       \
    {.key = K, .name = NAME, .type = MOTE_SF_U64, .offset = offsetof(mote_sep_system, M),    \
     .lo = MOTE_SF_ANY}
/* the file's version: 2 added `real parcel` (read as 1 from version 1); 3 the contact law
 * (hertz, friction, the species' E and nu, per-pair friction, the springs of the pairs, and
 * per particle with hertz its rotation and wall springs; read from older files as the linear
 * law); 4 the mesh walls (their triangles and motion) and, with contact hertz, the particles'
 * springs at them */
#define SEP_STATE_VERSION 4
/* a value added in file version 2 (read as its default from version 1) */
#define SR2(NAME, M)                                                                         \
    {.key = "real " NAME, .name = NAME, .type = MOTE_SF_CODEC,                            \
     .offset = offsetof(mote_sep_system, M), .codec = &REAL, .since = 2}
#define SR3(NAME, M)                                                                         \
    {.key = "real " NAME, .name = NAME, .type = MOTE_SF_CODEC,                            \
     .offset = offsetof(mote_sep_system, M), .codec = &REAL, .since = 3}
#define SI3(NAME, M)                                                                         \
    {.key = "int " NAME, .name = NAME, .type = MOTE_SF_INT,                               \
     .offset = offsetof(mote_sep_system, M), .lo = 0, .hi = 1, .since = 3}
static const mote_sf_field SCALARS[] = {
    SR("W", W), SR("H", H), SR("D", D), SR("D2", D2), SR("U0", U0), SR("rho_g", rho_g),
    SR("mu_g", mu_g), SR("g", g), SR("eps_gas_min", eps_gas_min), SR("chi", chi),
    SR("D_t", D_t), SR("T_gas", T_gas), SR("e_pw", e_pw), SR("dt_user", dt_user),
    SR("e_pp", e_pp), SR("khat", khat), SR("delta_f", delta_f), SR("v_imp", v_imp),
    SR("tau_eps", tau_eps), SR("zf", zf), SR("hf", hf), SR("rate", rate),
    SR("t_start", t_start), SR("t_stop", t_stop), SR("fx1", fx1), SR("fx2", fx2),
    SR("fy1", fy1), SR("fy2", fy2), SR("vfx", vf[0]), SR("vfy", vf[1]), SR("vfz", vf[2]),
    SR("avg_from", avg_from), SR("prof_time", prof_time), SR("prof_wait", prof_wait),
    SR("max_overlap", max_overlap), SR("t", t), SR2("parcel", parcel),
    SR3("mu_pp", mu_pp), SR3("mu_pw", mu_pw), SR3("mur_pp", mur_pp), SR3("mur_pw", mur_pw),
    SR3("E_w", E_w), SR3("nu_w", nu_w), SI3("hertz", hertz), SI3("e_true", e_true),
    SR3("coh_pp", coh_pp), SR3("coh_pw", coh_pw),
    SI("dim", dim), SI("open_bottom", open_bottom), SI("open_top", open_top),
    SI("coupling", coupling), SI("K", K), SI("dem", dem), SI("brute", brute), SI("nc", nc),
    SI("nsort", nsort), SI("eps_r_valid", eps_r_valid),
    SU("counters", "steps", steps), SU(NULL, "next_id", next_id),
    SU(NULL, "fast_moves", fast_moves), SU(NULL, "last_sort", last_sort),
    {.key = "rng", .name = "s", .type = MOTE_SF_HEX64, .offset = offsetof(mote_sep_system, rng.s),
     .count = 4},
};
static const mote_sf_field SEED[] = {
    {.key = "seed", .name = "S", .type = MOTE_SF_U64, .offset = 0, .lo = MOTE_SF_ANY},
};
#define NF(t) (sizeof t / sizeof t[0])

const mote_sf_field *sep_scalar_fields(size_t *n)
{
    *n = NF(SCALARS);
    return SCALARS;
}

/* The nested tables: a line "KEY N" says how many rows follow; each row is a line of its own
 * descriptors, read into a row structure and checked before it is kept. */
#define COUNT(KEY, LO, HI) {{.key = KEY, .name = "N", .type = MOTE_SF_U64, .lo = LO, .hi = HI}}
static const mote_sf_field N_GAS[] = COUNT("gasprofile", 0, 1e6);
static const mote_sf_field N_SPECIES[] = COUNT("species", 1, MOTE_SEP_MAX_SPECIES);
static const mote_sf_field N_TABLE[] = COUNT("table", 0, 100000);
static const mote_sf_field N_PLATES[] = COUNT("plates", 0, MOTE_SEP_MAX_PLATES);
static const mote_sf_field N_CLASSES[] = COUNT("classes", 2, 1000);
static const mote_sf_field N_SLICES[] = COUNT("slices", 1, 1000);
static const mote_sf_field N_BACKLOG[] = COUNT("backlog", 0, 1e8);
static const mote_sf_field N_PARTICLES[] = COUNT("particles", 0, 1e9);

#define RK(KEY, NAME, T, M)                                                                   \
    {.key = KEY, .name = NAME, .type = MOTE_SF_CODEC, .offset = offsetof(T, M), .codec = &REAL}
#define R(NAME, T, M) RK(NULL, NAME, T, M)
#define UK(KEY, NAME, T, M)                                                                   \
    {.key = KEY, .name = NAME, .type = MOTE_SF_U64, .offset = offsetof(T, M), .lo = MOTE_SF_ANY}
#define IK(KEY, NAME, T, M, LO, HI)                                                           \
    {.key = KEY, .name = NAME, .type = MOTE_SF_INT, .offset = offsetof(T, M), .lo = LO, .hi = HI}

typedef struct { double z, rho, mu; } gp_row;
static const mote_sf_field GP[] = {RK("gp", "Z", gp_row, z), R("RHO", gp_row, rho),
                                   R("MU", gp_row, mu)};

typedef struct {
    char name[sizeof ((mote_sep_species *)0)->name];
    int have, type, basis;
    double rho, w, a, b, lo, hi;
    double E, nu;
} sp_row;
static const mote_sf_field SP[] = {
    {.key = "sp", .name = "NAME", .type = MOTE_SF_WORD, .offset = offsetof(sp_row, name),
     .size = sizeof ((sp_row *)0)->name},
    IK(NULL, "HAVE", sp_row, have, 0, 1), IK(NULL, "TYPE", sp_row, type, 0, MOTE_SEP_LOGUNIFORM),
    IK(NULL, "BASIS", sp_row, basis, 0, 1), R("RHO", sp_row, rho), R("W", sp_row, w),
    R("A", sp_row, a), R("B", sp_row, b), R("LO", sp_row, lo), R("HI", sp_row, hi),
    {.name = "E", .type = MOTE_SF_CODEC, .offset = offsetof(sp_row, E), .codec = &REAL,
     .since = 3},
    {.name = "NU", .type = MOTE_SF_CODEC, .offset = offsetof(sp_row, nu), .codec = &REAL,
     .since = 3}};

typedef struct { double d, F; } table_row;
static const mote_sf_field TROW[] = {RK("row", "D", table_row, d), R("F", table_row, F)};

static const mote_sf_field COUNTS[] = {
    UK("count", "FED", mote_sep_count, fed), UK(NULL, "FINES", mote_sep_count, fines),
    UK(NULL, "COARSE", mote_sep_count, coarse), UK(NULL, "LOST", mote_sep_count, lost),
    R("M_FED", mote_sep_count, m_fed), R("M_FINES", mote_sep_count, m_fines),
    R("M_COARSE", mote_sep_count, m_coarse), R("M_LOST", mote_sep_count, m_lost),
    R("M_GEN", mote_sep_count, m_gen)};

typedef struct {
    uint64_t nh;
    int listed;
    int64_t dropped;
    double zb, t;
} plate_row;
static const mote_sf_field PLATE[] = {
    {.key = "plate", .name = "NHOLES", .type = MOTE_SF_U64, .offset = offsetof(plate_row, nh),
     .lo = 1, .hi = 1e8},
    IK(NULL, "LISTED", plate_row, listed, 0, 1),
    {.key = NULL, .name = "DROPPED", .type = MOTE_SF_I64, .offset = offsetof(plate_row, dropped),
     .lo = 0, .hi = 2e9},
    R("ZB", plate_row, zb), R("T", plate_row, t)};

/* A mesh wall (version 4): its counts, whether solid, its motion and name, then its vertices
 * and triangles. */
static const mote_sf_field N_MESHES[] = {{.key = "meshes", .name = "N", .type = MOTE_SF_U64,
                                          .lo = 0, .hi = MOTE_SEP_MAX_MESHES, .since = 4}};
typedef struct {
    uint64_t nv, nt;
    int solid;
    double vel[3], omega, axis[3], centre[3];
    char name[64];
} mesh_row;
static const mote_sf_field MESH[] = {
    {.key = "mesh", .name = "NV", .type = MOTE_SF_U64, .offset = offsetof(mesh_row, nv), .lo = 3,
     .hi = 4e9},
    {.name = "NT", .type = MOTE_SF_U64, .offset = offsetof(mesh_row, nt), .lo = 1, .hi = 4e9},
    IK(NULL, "SOLID", mesh_row, solid, 0, 1),
    {.name = "VELOCITY", .type = MOTE_SF_CODEC, .offset = offsetof(mesh_row, vel), .count = 3,
     .codec = &REAL},
    R("OMEGA", mesh_row, omega),
    {.name = "AXIS", .type = MOTE_SF_CODEC, .offset = offsetof(mesh_row, axis), .count = 3,
     .codec = &REAL},
    {.name = "CENTRE", .type = MOTE_SF_CODEC, .offset = offsetof(mesh_row, centre), .count = 3,
     .codec = &REAL},
    {.name = "NAME", .type = MOTE_SF_WORD, .offset = offsetof(mesh_row, name),
     .size = sizeof ((mesh_row *)0)->name}};
static const mote_sf_field MV[] = {{.key = "mv", .name = "XYZ", .type = MOTE_SF_CODEC,
                                    .offset = 0, .count = 3, .codec = &REAL}};
static const mote_sf_field MT[] = {{.key = "mt", .name = "ABC", .type = MOTE_SF_U32,
                                    .offset = 0, .count = 3, .lo = MOTE_SF_ANY}};
/* The particles' springs at the mesh walls (contact hertz, version 4): the particle's id, the
 * slot, the contact's key (wall and triangle) and the spring. */
static const mote_sf_field N_WS[] = {{.key = "wall_springs", .name = "N", .type = MOTE_SF_U64,
                                      .lo = 0, .hi = 1e11, .since = 4}};
typedef struct {
    uint64_t id;
    int slot;
    double k[4];
} ws_row;
static const mote_sf_field WS[] = {
    UK("ws", "ID", ws_row, id), IK(NULL, "SLOT", ws_row, slot, 0, SEP_MESH_SLOTS - 1),
    {.name = "KEY", .type = MOTE_SF_CODEC, .offset = offsetof(ws_row, k), .codec = &REAL},
    {.name = "XI", .type = MOTE_SF_CODEC, .offset = offsetof(ws_row, k[1]), .count = 3,
     .codec = &REAL}};

typedef struct { double x1, x2, y1, y2; } hole_row;
static const mote_sf_field HOLE[] = {RK("hole", "X1", hole_row, x1), R("X2", hole_row, x2),
                                     R("Y1", hole_row, y1), R("Y2", hole_row, y2)};

/* A size class: its lower edge and tallies, all species and each; the last line holds only the
 * upper edge of the last class. */
typedef struct { uint64_t nf, nc; double mf, mc; } tally;
typedef struct {
    double edge;
    tally all, sp[MOTE_SEP_MAX_SPECIES];
} edge_row;
static size_t edge_fields(mote_sf_field *f, int nsp, int last)
{
    static const char *const names[4] = {"NF", "NC", "MF", "MC"};
    static const char *const sp_names[4] = {"NF_SPECIES", "NC_SPECIES", "MF_SPECIES",
                                            "MC_SPECIES"};
    f[0] = (mote_sf_field)RK("edge", "EDGE", edge_row, edge);
    size_t n = 1;
    for (int k = -1; !last && k < nsp; k++) {
        const size_t at = k < 0 ? offsetof(edge_row, all)
                                : offsetof(edge_row, sp) + (size_t)k * sizeof(tally);
        for (int j = 0; j < 4; j++)
            f[n++] = (mote_sf_field){
                .name = k < 0 ? names[j] : sp_names[j], .type = j < 2 ? MOTE_SF_U64 : MOTE_SF_CODEC,
                .offset = at + (j == 0   ? offsetof(tally, nf)
                                : j == 1 ? offsetof(tally, nc)
                                : j == 2 ? offsetof(tally, mf)
                                         : offsetof(tally, mc)),
                .lo = 1, .hi = 0, .codec = j < 2 ? NULL : &REAL};
    }
    return n;
}

typedef struct {
    double eps_r, n, mvz, m, ug, fd;
    double eps[MOTE_SEP_MAX_SPECIES];
} slice_row;

/* A particle of the backlog: its species (any: checked against the species) and diameter. */
typedef struct {
    int s;
    double d;
} back_row;
static const mote_sf_field BACK[] = {IK("b", "SPECIES", back_row, s, 1, 0), R("D", back_row, d)};

typedef struct {
    int ok;
    uint64_t mods, list_mods, builds, n;
} pairs_head;
static const mote_sf_field PAIRS[] = {
    IK("pairlist", "OK", pairs_head, ok, 0, 1), UK(NULL, "MODS", pairs_head, mods),
    UK(NULL, "LIST_MODS", pairs_head, list_mods), UK(NULL, "BUILDS", pairs_head, builds),
    {.name = "N", .type = MOTE_SF_U64, .offset = offsetof(pairs_head, n), .lo = 0, .hi = 2e9}};
static const mote_sf_field PAIR[] = {
    {.key = "l", .name = "I", .type = MOTE_SF_U32, .offset = 0, .lo = MOTE_SF_ANY},
    {.name = "J", .type = MOTE_SF_U32, .offset = sizeof(uint32_t), .lo = MOTE_SF_ANY}};

/* The tangential springs of the pairs in contact (contact hertz; version 3): the ids, lower
 * first, and the spring. */
static const mote_sf_field N_HIST[] = {{.key = "springs", .name = "N", .type = MOTE_SF_U64,
                                        .lo = 0, .hi = 1e10, .since = 3}};
static const mote_sf_field HREC[] = {
    UK("h", "A", struct sep_hrec, a), UK(NULL, "B", struct sep_hrec, b),
    {.name = "XI", .type = MOTE_SF_CODEC, .offset = offsetof(struct sep_hrec, xi), .count = 3,
     .codec = &REAL}};

/* A particle: id, species (any: checked against the species), d, m, x, y, z, vx, vy, vz, fx,
 * fy, fz, with contact hertz its angular velocity, torque and wall springs (version 3), and,
 * with a pair list that still serves, the position where the list was built. */
typedef struct {
    uint64_t id;
    int s;
    double v[11];
    double rot[15];
    double xref[3];
} p_row;
static const mote_sf_field P[] = {
    UK("p", "ID", p_row, id), IK(NULL, "SPECIES", p_row, s, 1, 0), R("D", p_row, v[0]),
    R("M", p_row, v[1]), R("X", p_row, v[2]), R("Y", p_row, v[3]), R("Z", p_row, v[4]),
    R("VX", p_row, v[5]), R("VY", p_row, v[6]), R("VZ", p_row, v[7]), R("FX", p_row, v[8]),
    R("FY", p_row, v[9]), R("FZ", p_row, v[10])};
static const mote_sf_field P_ROT[] = {
    {.name = "W", .type = MOTE_SF_CODEC, .offset = offsetof(p_row, rot), .count = 3,
     .codec = &REAL},
    {.name = "TORQUE", .type = MOTE_SF_CODEC, .offset = offsetof(p_row, rot[3]), .count = 3,
     .codec = &REAL},
    {.name = "WALL_SPRINGS", .type = MOTE_SF_CODEC, .offset = offsetof(p_row, rot[6]),
     .count = 9, .codec = &REAL}};
static const mote_sf_field P_XREF[] = {
    {.name = "XREF", .type = MOTE_SF_CODEC, .offset = offsetof(p_row, xref), .count = 3,
     .codec = &REAL}};

/* The particle line's descriptors: P, with rot the rotation's, with xref the list's. */
static size_t p_fields(mote_sf_field *f, int rot, int xref)
{
    size_t n = 0;
    for (size_t k = 0; k < NF(P); k++)
        f[n++] = P[k];
    for (size_t k = 0; rot && k < NF(P_ROT); k++)
        f[n++] = P_ROT[k];
    if (xref)
        f[n++] = P_XREF[0];
    return n;
}

/* The rows of nrows lines: the species' restitutions and a slice's values depend on the
 * number of species. */
static mote_sf_field reals_field(const char *key, const char *name, size_t offset, int count)
{
    return (mote_sf_field){.key = key, .name = name, .type = MOTE_SF_CODEC, .offset = offset,
                           .count = count, .codec = &REAL};
}
static size_t slice_fields(mote_sf_field *f, int nsp)
{
    f[0] = (mote_sf_field)RK("slice", "EPS_R", slice_row, eps_r);
    f[1] = (mote_sf_field)R("N", slice_row, n);
    f[2] = (mote_sf_field)R("MVZ", slice_row, mvz);
    f[3] = (mote_sf_field)R("M", slice_row, m);
    f[4] = (mote_sf_field)R("UG", slice_row, ug);
    f[5] = (mote_sf_field)R("FD", slice_row, fd);
    f[6] = reals_field(NULL, "EPS", offsetof(slice_row, eps), nsp);
    return 7;
}

static void put_count(FILE *f, const mote_sf_field *d, uint64_t n)
{
    mote_sf_write(f, d, 1, &n, SEP_STATE_VERSION);
}

int mote_sep_save(const mote_sep_system *s, uint64_t seed, const char *path, mote_err *err)
{
    if (!s->class_edge || !s->eps_r || !s->prof_n)
        return mote_fail(err, MOTE_EINVAL, "%s: nothing to save before the system is prepared",
                         path);
    /* the springs of the pairs in contact, by id (contact hertz) */
    struct sep_hrec *hr = NULL;
    size_t nh = 0;
    if (sep_hist_collect(s, &hr, &nh, err))
        return err->code;
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc) {
        free(hr);
        return rc;
    }
    FILE *f = af.f;
    const int nsp = s->nsp;
    mote_sf_write_head(f, "separator", SEP_STATE_VERSION);
    mote_sf_write(f, SEED, NF(SEED), &seed, SEP_STATE_VERSION);
    mote_sf_write(f, SCALARS, NF(SCALARS), s, SEP_STATE_VERSION);
    put_count(f, N_GAS, s->gp_n);
    for (size_t k = 0; k < s->gp_n; k++) {
        const gp_row g = {s->gp_z[k], s->gp_rho[k], s->gp_mu[k]};
        mote_sf_write(f, GP, NF(GP), &g, SEP_STATE_VERSION);
    }
    put_count(f, N_SPECIES, (uint64_t)nsp);
    const mote_sf_field epair = reals_field("epair", "E", 0, nsp);
    mote_sf_field mupair = reals_field("mupair", "MU", 0, nsp),
                  murpair = reals_field("murpair", "MU_R", 0, nsp),
                  cohpair = reals_field("cohpair", "K", 0, nsp);
    mupair.since = murpair.since = cohpair.since = 3;
    for (int k = 0; k < nsp; k++) {
        const mote_sep_species *p = &s->sp[k];
        sp_row r = {.have = p->have_dist, .type = p->dist.type, .basis = p->dist.number_basis,
                    .rho = p->rho, .w = p->w, .a = p->dist.a, .b = p->dist.b, .lo = p->dist.lo,
                    .hi = p->dist.hi, .E = p->E, .nu = p->nu};
        memcpy(r.name, p->name, sizeof r.name);
        mote_sf_write(f, SP, NF(SP), &r, SEP_STATE_VERSION);
        put_count(f, N_TABLE, (uint64_t)p->dist.tn);
        for (int j = 0; j < p->dist.tn; j++) {
            const table_row t = {p->dist.td[j], p->dist.tF[j]};
            mote_sf_write(f, TROW, NF(TROW), &t, SEP_STATE_VERSION);
        }
        mote_sf_write(f, COUNTS, NF(COUNTS), &s->cnt[k], SEP_STATE_VERSION);
        mote_sf_write(f, &epair, 1, s->e_pair[k], SEP_STATE_VERSION);
        mote_sf_write(f, &mupair, 1, s->mu_pair[k], SEP_STATE_VERSION);
        mote_sf_write(f, &murpair, 1, s->mur_pair[k], SEP_STATE_VERSION);
        mote_sf_write(f, &cohpair, 1, s->coh_pair[k], SEP_STATE_VERSION);
    }
    put_count(f, N_PLATES, (uint64_t)s->nplate);
    for (int q = 0; q < s->nplate; q++) {
        const mote_sep_plate *p = &s->plate[q];
        const plate_row r = {p->nh, p->listed, p->dropped, p->zb, p->t};
        mote_sf_write(f, PLATE, NF(PLATE), &r, SEP_STATE_VERSION);
        for (size_t h = 0; h < p->nh; h++)
            mote_sf_write(f, HOLE, NF(HOLE), p->h + 4 * h, SEP_STATE_VERSION);
    }
    put_count(f, N_MESHES, (uint64_t)s->nmesh);
    for (int q = 0; q < s->nmesh; q++) {
        const mote_sep_mesh *w = &s->mesh[q];
        mesh_row r = {w->nv, w->nt, w->solid, {0}, w->omega, {0}, {0}, ""};
        memcpy(r.vel, w->vel, sizeof r.vel);
        memcpy(r.axis, w->axis, sizeof r.axis);
        memcpy(r.centre, w->centre, sizeof r.centre);
        memcpy(r.name, w->name, sizeof r.name);
        mote_sf_write(f, MESH, NF(MESH), &r, SEP_STATE_VERSION);
        for (size_t v = 0; v < w->nv; v++)
            mote_sf_write(f, MV, 1, w->v[v], SEP_STATE_VERSION);
        for (size_t t = 0; t < w->nt; t++)
            mote_sf_write(f, MT, 1, w->t[t], SEP_STATE_VERSION);
    }
    put_count(f, N_CLASSES, (uint64_t)s->nclass);
    mote_sf_field ef[1 + 4 * (MOTE_SEP_MAX_SPECIES + 1)];
    for (int i = 0; i <= s->nclass; i++) {
        const int last = i == s->nclass;
        edge_row r = {.edge = s->class_edge[i]};
        if (!last) {
            r.all = (tally){s->cl_nf[i], s->cl_nc[i], s->cl_mf[i], s->cl_mc[i]};
            for (int k = 0; k < nsp; k++) {
                const size_t q = (size_t)i * MOTE_SEP_MAX_SPECIES + (size_t)k;
                r.sp[k] = (tally){s->cls_nf[q], s->cls_nc[q], s->cls_mf[q], s->cls_mc[q]};
            }
        }
        mote_sf_write(f, ef, edge_fields(ef, nsp, last), &r, SEP_STATE_VERSION);
    }
    put_count(f, N_SLICES, (uint64_t)s->K);
    mote_sf_field sf[7];
    const size_t nsf = slice_fields(sf, nsp);
    for (int k = 0; k < s->K; k++) {
        slice_row r = {s->eps_r[k], s->prof_n[k], s->prof_mvz[k], s->prof_m[k], s->prof_ug[k],
                       s->prof_fd[k], {0}};
        memcpy(r.eps, s->prof_eps + (size_t)k * MOTE_SEP_MAX_SPECIES, (size_t)nsp * sizeof(double));
        mote_sf_write(f, sf, nsf, &r, SEP_STATE_VERSION);
    }
    put_count(f, N_BACKLOG, s->nback);
    for (size_t b = 0; b < s->nback; b++) {
        const back_row r = {s->back_s[b], s->back_d[b]};
        mote_sf_write(f, BACK, NF(BACK), &r, SEP_STATE_VERSION);
    }
    /* the pair list when it still serves (nothing added or removed since its build), so that a
     * continued run sums the contact forces in the same order */
    const int live = s->list_ok && s->mods == s->list_mods && s->xref_cap >= 3 * s->n;
    const pairs_head ph = {live, s->mods, s->list_mods, s->list_builds, live ? s->npl : 0};
    mote_sf_write(f, PAIRS, NF(PAIRS), &ph, SEP_STATE_VERSION);
    for (size_t i = 0; live && i < s->n; i++)
        for (uint32_t q = s->nb_start[i]; q < s->nb_start[i + 1]; q++)
            if (s->nb[q] > i) { /* each pair once, i < j */
                const uint32_t ab[2] = {(uint32_t)i, s->nb[q]};
                mote_sf_write(f, PAIR, NF(PAIR), ab, SEP_STATE_VERSION);
            }
    put_count(f, N_HIST, nh);
    for (size_t k = 0; k < nh; k++)
        mote_sf_write(f, HREC, NF(HREC), &hr[k], SEP_STATE_VERSION);
    free(hr);
    put_count(f, N_PARTICLES, s->n);
    const int rot = s->hertz && s->w;
    mote_sf_field pf[NF(P) + NF(P_ROT) + 1];
    const size_t npf = p_fields(pf, rot, live);
    for (size_t i = 0; i < s->n; i++) {
        p_row r = {s->id[i], s->s[i], {s->d[i], s->m[i], s->x[i], s->y[i], s->z[i], s->vx[i],
                   s->vy[i], s->vz[i], s->fx[i], s->fy[i], s->fz[i]}, {0}, {0}};
        if (rot) {
            memcpy(r.rot, s->w + 3 * i, 3 * sizeof *r.rot);
            memcpy(r.rot + 3, s->tq + 3 * i, 3 * sizeof *r.rot);
            memcpy(r.rot + 6, s->wh + 9 * i, 9 * sizeof *r.rot);
        }
        if (live)
            memcpy(r.xref, s->xref + 3 * i, sizeof r.xref);
        mote_sf_write(f, pf, npf, &r, SEP_STATE_VERSION);
    }
    const size_t S = SEP_MESH_SLOTS;
    uint64_t nws = 0;
    for (size_t k = 0; s->mh && k < s->n * S; k++)
        nws += s->mh[4 * k] != 0;
    put_count(f, N_WS, nws);
    for (size_t k = 0; s->mh && k < s->n * S; k++)
        if (s->mh[4 * k] != 0) {
            ws_row r = {s->id[k / S], (int)(k % S), {0}};
            memcpy(r.k, s->mh + 4 * k, sizeof r.k);
            mote_sf_write(f, WS, NF(WS), &r, SEP_STATE_VERSION);
        }
    fprintf(f, "end\n");
    return mote_afile_commit(&af, err);
}

/* ---- reading -------------------------------------------------------------------------------- */

typedef struct {
    mote_lines in;
    int version;
    mote_err *err;
} reader;

static int bad(reader *r, const char *what, const char *found)
{
    return mote_fail(r->err, MOTE_EINVAL, "%s:%ld: %s%s%s%s", r->in.path, r->in.line, what,
                     found ? " (found '" : "", found ? found : "", found ? "')" : "");
}

/* One line of the descriptors f[0 .. n) into base. */
static int row(reader *r, const mote_sf_field *f, size_t n, void *base)
{
    return mote_sf_read(&r->in, f, n, base, r->version, r->err);
}

/* "KEY N" into *n. */
static int count(reader *r, const mote_sf_field *f, uint64_t *n)
{
    return row(r, f, 1, n);
}

/* A species index of the line just read: 0 ... nsp - 1. */
static int species_ok(reader *r, int k, int nsp)
{
    if (k >= 0 && k < nsp)
        return MOTE_OK;
    return mote_fail(r->err, MOTE_EFORMAT, "%s:%ld: SPECIES must be in [0, %d], found %d",
                     r->in.path, r->in.line, nsp - 1, k);
}

static int read_gas(reader *r, mote_sep_system *s)
{
    uint64_t n;
    int rc = count(r, N_GAS, &n);
    if (rc || !n)
        return rc;
    double *g = malloc(3 * (size_t)n * sizeof *g);
    if (!g)
        return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
    for (uint64_t k = 0; k < n && !rc; k++) {
        gp_row x;
        rc = row(r, GP, NF(GP), &x);
        g[k] = x.z;
        g[n + k] = x.rho;
        g[2 * n + k] = x.mu;
    }
    mote_err e2 = {0};
    if (!rc && mote_sep_set_gas_profile(s, (size_t)n, g, g + n, g + 2 * n, &e2))
        rc = bad(r, e2.msg, NULL);
    free(g);
    return rc;
}

static int read_species(reader *r, mote_sep_system *s, int k, int nsp)
{
    mote_sep_species *p = &s->sp[k];
    sp_row x;
    x.E = 0;
    x.nu = 0.3; /* (older files: none) */
    int rc = row(r, SP, NF(SP), &x);
    if (rc)
        return rc;
    memcpy(p->name, x.name, sizeof p->name);
    p->have_dist = x.have;
    p->rho = x.rho;
    p->E = x.E;
    p->nu = x.nu;
    p->w = x.w;
    p->dist = (mote_sep_dist){.type = x.type, .a = x.a, .b = x.b, .lo = x.lo, .hi = x.hi,
                              .number_basis = x.basis};
    s->nsp = k + 1;
    if (!(p->rho > 0))
        return bad(r, "a species density must be > 0", NULL);
    uint64_t tn;
    rc = count(r, N_TABLE, &tn);
    if (!rc && tn) {
        double *tab = malloc(2 * (size_t)tn * sizeof *tab);
        if (!tab)
            return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
        for (uint64_t j = 0; j < tn && !rc; j++) {
            table_row t;
            rc = row(r, TROW, NF(TROW), &t);
            tab[j] = t.d;
            tab[tn + j] = t.F;
        }
        mote_err e2 = {0};
        if (!rc && mote_sep_dist_table(&p->dist, (int)tn, tab, tab + tn, &e2))
            rc = bad(r, e2.msg, NULL);
        p->dist.lo = x.lo;
        p->dist.hi = x.hi;
        free(tab);
    }
    if (!rc && p->have_dist && mote_sep_dist_build(&p->dist, r->err))
        return mote_fail(r->err, MOTE_EINVAL, "%s:%ld: %s", r->in.path, r->in.line,
                         r->err->msg);
    if (!rc)
        rc = row(r, COUNTS, NF(COUNTS), &s->cnt[k]);
    const mote_sf_field epair = reals_field("epair", "E", 0, nsp);
    mote_sf_field mupair = reals_field("mupair", "MU", 0, nsp),
                  murpair = reals_field("murpair", "MU_R", 0, nsp),
                  cohpair = reals_field("cohpair", "K", 0, nsp);
    mupair.since = murpair.since = cohpair.since = 3;
    if (!rc)
        rc = row(r, &epair, 1, s->e_pair[k]);
    if (!rc)
        rc = row(r, &mupair, 1, s->mu_pair[k]);
    if (!rc)
        rc = row(r, &murpair, 1, s->mur_pair[k]);
    if (!rc)
        rc = row(r, &cohpair, 1, s->coh_pair[k]);
    for (int j = 0; !rc && j < nsp; j++)
        if (!(s->mu_pair[k][j] == -1 || s->mu_pair[k][j] >= 0) ||
            !(s->mur_pair[k][j] == -1 || s->mur_pair[k][j] >= 0) ||
            !(s->coh_pair[k][j] == -1 || s->coh_pair[k][j] >= 0))
            rc = bad(r, "a pair's friction and cohesion must be >= 0 (or -1: none)", NULL);
    return rc;
}

static int read_plates(reader *r, mote_sep_system *s)
{
    uint64_t np;
    int rc = count(r, N_PLATES, &np);
    for (uint64_t q = 0; q < np && !rc; q++) {
        plate_row x;
        rc = row(r, PLATE, NF(PLATE), &x);
        if (rc)
            break;
        double *h = malloc((size_t)x.nh * 4 * sizeof *h);
        if (!h)
            return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
        for (uint64_t k = 0; k < x.nh && !rc; k++)
            rc = row(r, HOLE, NF(HOLE), h + 4 * k);
        if (!rc) {
            rc = mote_sep_plate_list(&s->plate[q], x.zb, x.t, h, (size_t)x.nh, r->err);
            s->plate[q].listed = x.listed;
            s->plate[q].dropped = (long)x.dropped;
            if (!rc)
                s->nplate = (int)q + 1;
        }
        free(h);
    }
    return rc;
}

static int read_meshes(reader *r, mote_sep_system *s)
{
    uint64_t nm = 0;
    int rc = r->version >= 4 ? count(r, N_MESHES, &nm) : MOTE_OK;
    for (uint64_t q = 0; q < nm && !rc; q++) {
        mesh_row x;
        rc = row(r, MESH, NF(MESH), &x);
        if (rc)
            break;
        const long at = r->in.line; /* (the wall's faults name its line) */
        /* grown as the lines come: a false count allocates little */
        mote_mesh m = {0};
        size_t vcap = 0, tcap = 0;
        for (uint64_t k = 0; k < x.nv && !rc; k++) {
            if (sep_reserve((void **)&m.v, &vcap, (size_t)k + 1, sizeof *m.v, r->err))
                rc = r->err->code;
            if (!rc)
                rc = row(r, MV, 1, m.v[k]);
            for (int a = 0; !rc && a < 3; a++)
                if (!isfinite(m.v[k][a]))
                    rc = bad(r, "a mesh vertex must be finite", NULL);
        }
        for (uint64_t k = 0; k < x.nt && !rc; k++) {
            if (sep_reserve((void **)&m.t, &tcap, (size_t)k + 1, sizeof *m.t, r->err))
                rc = r->err->code;
            if (!rc)
                rc = row(r, MT, 1, m.t[k]);
            for (int a = 0; !rc && a < 3; a++)
                if (m.t[k][a] >= x.nv)
                    rc = bad(r, "a triangle names a vertex beyond the mesh's", NULL);
        }
        m.nv = (size_t)x.nv;
        m.nt = (size_t)x.nt;
        m.closed = rc ? NULL : malloc(m.nt);
        if (!rc && !m.closed)
            rc = mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
        if (!rc)
            memset(m.closed, 1, m.nt); /* (a solid one's edges are checked by sep_mesh_add) */
        for (int a = 0; !rc && a < 3; a++)
            if (!isfinite(x.vel[a]) || !isfinite(x.axis[a]) || !isfinite(x.centre[a]) ||
                !isfinite(x.omega))
                rc = bad(r, "a mesh wall's motion must be finite", NULL);
        if (!rc) {
            mote_err e2 = {0};
            if (sep_mesh_add(s, &m, x.name, x.solid, x.vel, x.axis, x.omega, x.centre, &e2))
                rc = mote_fail(r->err, MOTE_EINVAL, "%s:%ld: %s", r->in.path, at, e2.msg);
            else /* (the axis as written: normalised once, when the wall was made) */
                memcpy(s->mesh[s->nmesh - 1].axis, x.axis, sizeof x.axis);
        }
        mote_mesh_free(&m);
    }
    return rc;
}

/* The particles' springs at the mesh walls, by id in the particles' order. */
static int read_wall_springs(reader *r, mote_sep_system *s)
{
    uint64_t n = 0;
    int rc = r->version >= 4 ? count(r, N_WS, &n) : MOTE_OK;
    if (!rc && n && !(s->hertz && s->mh))
        return bad(r, "wall springs are kept only with contact hertz and mesh walls", NULL);
    size_t i = 0, last = SIZE_MAX;
    for (uint64_t k = 0; k < n && !rc; k++) {
        ws_row x;
        rc = row(r, WS, NF(WS), &x);
        while (!rc && i < s->n && s->id[i] != x.id)
            i++;
        if (!rc && i == s->n)
            rc = bad(r, "a wall spring's particle is not among the particles (in their order)",
                     NULL);
        const size_t at = i * SEP_MESH_SLOTS + (size_t)x.slot;
        if (!rc && last != SIZE_MAX && at <= last)
            rc = bad(r, "the wall springs must be in the particles' and slots' order", NULL);
        if (!rc && !(x.k[0] >= 4294967296.0 && x.k[0] == floor(x.k[0]) &&
                     x.k[0] / 4294967296.0 < s->nmesh + 1))
            rc = bad(r, "a wall spring's key must name a mesh wall and a triangle", NULL);
        for (int a = 1; !rc && a < 4; a++)
            if (!isfinite(x.k[a]))
                rc = bad(r, "a wall spring must be finite", NULL);
        if (!rc) {
            memcpy(s->mh + 4 * at, x.k, sizeof x.k);
            last = at;
        }
    }
    return rc;
}

static int read_classes(reader *r, mote_sep_system *s)
{
    uint64_t n;
    int rc = count(r, N_CLASSES, &n);
    if (rc)
        return rc;
    s->nclass = (int)n;
    const size_t nc = (size_t)n;
    s->class_edge = malloc((nc + 1) * sizeof *s->class_edge);
    if (!s->class_edge)
        return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
    if (sep_tallies_alloc(s, r->err))
        return r->err->code;
    mote_sf_field ef[1 + 4 * (MOTE_SEP_MAX_SPECIES + 1)];
    for (size_t i = 0; i <= nc && !rc; i++) {
        edge_row x;
        rc = row(r, ef, edge_fields(ef, s->nsp, i == nc), &x);
        if (rc)
            break;
        s->class_edge[i] = x.edge;
        if (i == nc)
            break;
        s->cl_nf[i] = x.all.nf;
        s->cl_nc[i] = x.all.nc;
        s->cl_mf[i] = x.all.mf;
        s->cl_mc[i] = x.all.mc;
        for (int k = 0; k < s->nsp; k++) {
            const size_t q = i * MOTE_SEP_MAX_SPECIES + (size_t)k;
            s->cls_nf[q] = x.sp[k].nf;
            s->cls_nc[q] = x.sp[k].nc;
            s->cls_mf[q] = x.sp[k].mf;
            s->cls_mc[q] = x.sp[k].mc;
        }
    }
    for (size_t i = 0; i < nc && !rc; i++)
        if (!(s->class_edge[i + 1] > s->class_edge[i]) || !(s->class_edge[0] > 0))
            rc = bad(r, "the class edges must increase from above 0", NULL);
    return rc;
}

static int read_slices(reader *r, mote_sep_system *s)
{
    uint64_t n;
    int rc = count(r, N_SLICES, &n);
    if (!rc && n != (uint64_t)s->K)
        rc = bad(r, "the slices must match the parameter K", NULL);
    if (rc)
        return rc;
    const size_t K = (size_t)s->K;
    s->eps_s = calloc(K, sizeof *s->eps_s);
    s->u_g = calloc(K, sizeof *s->u_g);
    s->eps_r = calloc(K, sizeof *s->eps_r);
    if (!s->eps_s || !s->u_g || !s->eps_r)
        return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
    const double prof_time = s->prof_time; /* (read with the parameters) */
    if (sep_profiles_alloc(s, r->err))
        return r->err->code;
    s->prof_time = prof_time;
    mote_sf_field sf[7];
    const size_t nsf = slice_fields(sf, s->nsp);
    for (size_t k = 0; k < K && !rc; k++) {
        slice_row x;
        rc = row(r, sf, nsf, &x);
        if (rc)
            break;
        s->eps_r[k] = x.eps_r;
        s->prof_n[k] = x.n;
        s->prof_mvz[k] = x.mvz;
        s->prof_m[k] = x.m;
        s->prof_ug[k] = x.ug;
        s->prof_fd[k] = x.fd;
        memcpy(s->prof_eps + k * MOTE_SEP_MAX_SPECIES, x.eps, (size_t)s->nsp * sizeof(double));
    }
    return rc;
}

static int read_backlog(reader *r, mote_sep_system *s)
{
    uint64_t nb;
    int rc = count(r, N_BACKLOG, &nb);
    if (rc)
        return rc;
    s->back_s = malloc((nb ? nb : 1) * sizeof *s->back_s);
    s->back_d = malloc((nb ? nb : 1) * sizeof *s->back_d);
    if (!s->back_s || !s->back_d)
        return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
    s->back_cap = nb ? nb : 1;
    for (uint64_t b = 0; b < nb && !rc; b++) {
        back_row x;
        rc = row(r, BACK, NF(BACK), &x);
        if (!rc)
            rc = species_ok(r, x.s, s->nsp);
        if (!rc) {
            s->back_s[b] = x.s;
            s->back_d[b] = x.d;
            s->nback = b + 1;
        }
    }
    return rc;
}

/* The pair list's lines into pairs (malloc'ed, *np of them); its rows are made once the
 * particles are read. */
static int read_pairs(reader *r, pairs_head *h, uint32_t **pairs, size_t *np)
{
    int rc = row(r, PAIRS, NF(PAIRS), h);
    size_t cap = 0;
    for (uint64_t k = 0; k < h->n && !rc; k++) {
        uint32_t ab[2];
        rc = row(r, PAIR, NF(PAIR), ab);
        if (!rc && *np == cap) { /* grown as the lines come: a false count allocates little */
            cap = cap ? 2 * cap : 1024;
            uint32_t *p = realloc(*pairs, 2 * cap * sizeof *p);
            if (!p)
                return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
            *pairs = p;
        }
        if (!rc) {
            (*pairs)[2 * *np] = ab[0];
            (*pairs)[2 * *np + 1] = ab[1];
            (*np)++;
        }
    }
    return rc;
}

/* The springs' table into s->hmap (kept for the list's entries: s->hmap_pending). */
static int read_springs(reader *r, mote_sep_system *s)
{
    uint64_t n = 0;
    int rc = r->version >= 3 ? count(r, N_HIST, &n) : MOTE_OK;
    for (uint64_t k = 0; k < n && !rc; k++) {
        struct sep_hrec h;
        rc = row(r, HREC, NF(HREC), &h);
        if (!rc && !(h.a < h.b))
            rc = bad(r, "a spring's ids must be in increasing order", NULL);
        if (!rc && k && !(h.a > s->hmap[k - 1].a ||
                          (h.a == s->hmap[k - 1].a && h.b > s->hmap[k - 1].b)))
            rc = bad(r, "the springs must be sorted by their ids, each pair once", NULL);
        if (!rc && sep_reserve((void **)&s->hmap, &s->hmap_cap, k + 1, sizeof *s->hmap, r->err))
            rc = r->err->code;
        if (!rc)
            s->hmap[s->nhmap++] = h;
    }
    if (!rc && n && !s->hertz)
        rc = bad(r, "springs are kept only with contact hertz (int hertz 1)", NULL);
    s->hmap_pending = s->hertz;
    return rc;
}

static int read_particles(reader *r, mote_sep_system *s, int lok)
{
    uint64_t n;
    int rc = count(r, N_PARTICLES, &n);
    const int rot = s->hertz && r->version >= 3;
    mote_sf_field pf[NF(P) + NF(P_ROT) + 1];
    const size_t npf = p_fields(pf, rot, lok);
    /* the arrays grow as the lines come, so a false count allocates nothing large */
    for (uint64_t i = 0; i < n && !rc; i++) {
        p_row x;
        rc = row(r, pf, npf, &x);
        if (!rc)
            rc = species_ok(r, x.s, s->nsp);
        if (!rc && !(x.v[0] > 0 && x.v[1] > 0 && isfinite(x.v[0]) && isfinite(x.v[1])))
            rc = bad(r, "a particle needs a finite diameter and mass > 0", NULL);
        for (int q = 2; !rc && q < 11; q++)
            if (!isfinite(x.v[q]))
                rc = bad(r, "a particle's position, velocity and force must be finite", NULL);
        for (int q = 5; !rc && q < 8; q++)
            if (!(fabs(x.v[q]) <= MOTE_SEP_SPEED_MAX))
                rc = bad(r, "a particle's velocity components must be up to 1e6 m/s", NULL);
        for (int q = 0; !rc && rot && q < 15; q++)
            if (!isfinite(x.rot[q]))
                rc = bad(r, "a particle's rotation, torque and springs must be finite", NULL);
        if (!rc)
            rc = sep_append(s, x.s, x.id, x.v, r->err);
        if (!rc && s->hertz) {
            rc = sep_rot_reserve(s, r->err);
            if (!rc) {
                memcpy(s->w + 3 * i, x.rot, 3 * sizeof *x.rot);
                memcpy(s->tq + 3 * i, x.rot + 3, 3 * sizeof *x.rot);
                memcpy(s->wh + 9 * i, x.rot + 6, 9 * sizeof *x.rot);
            }
        }
        if (!rc && lok) {
            if (3 * (i + 1) > s->xref_cap) {
                const size_t cap = 6 * (i + 1);
                double *p = realloc(s->xref, cap * sizeof *p);
                if (!p)
                    return mote_fail(r->err, MOTE_ENOMEM, "%s: out of memory", r->in.path);
                s->xref = p;
                s->xref_cap = cap;
            }
            memcpy(s->xref + 3 * i, x.xref, sizeof x.xref);
        }
    }
    return rc;
}

static int read_body(reader *r, mote_sep_system *s, uint64_t *seed)
{
    int rc = mote_sf_read_head(&r->in, "separator", SEP_STATE_VERSION, &r->version, r->err);
    if (!rc)
        rc = row(r, SEED, NF(SEED), seed);
    if (!rc)
        rc = mote_sf_read(&r->in, SCALARS, NF(SCALARS), s, r->version, r->err);
    if (rc)
        return rc;
    if (s->dim != 2 && s->dim != 3)
        return bad(r, "dim must be 2 or 3", NULL);
    if (s->K < 1 || s->K > 1000)
        return bad(r, "the slices must number 1 to 1000", NULL);
    if (!(s->rng.s[0] | s->rng.s[1] | s->rng.s[2] | s->rng.s[3]))
        return bad(r, "the random stream's state must not be all zero", NULL);
    rc = read_gas(r, s);
    uint64_t nsp = 0;
    if (!rc)
        rc = count(r, N_SPECIES, &nsp);
    for (int k = 0; k < (int)nsp && !rc; k++)
        rc = read_species(r, s, k, (int)nsp);
    if (!rc)
        rc = read_plates(r, s);
    if (!rc)
        rc = read_meshes(r, s);
    if (!rc)
        rc = read_classes(r, s);
    if (!rc)
        rc = read_slices(r, s);
    if (!rc)
        rc = read_backlog(r, s);
    pairs_head ph = {0};
    uint32_t *pairs = NULL;
    size_t np = 0;
    if (!rc)
        rc = read_pairs(r, &ph, &pairs, &np);
    if (!rc)
        rc = read_springs(r, s);
    if (!rc)
        rc = read_particles(r, s, ph.ok);
    if (!rc)
        rc = read_wall_springs(r, s);
    /* sep_append counted the particles as additions: the counts of the file stand */
    for (size_t k = 0; !rc && k < 2 * np; k++)
        if (pairs[k] >= s->n)
            rc = bad(r, "the pair list names a particle beyond the last", NULL);
    if (!rc && ph.ok)
        rc = sep_list_from_pairs(s, pairs, np, r->err);
    free(pairs);
    if (!rc) {
        s->mods = ph.mods;
        s->list_ok = ph.ok;
        s->list_mods = ph.list_mods;
        s->list_builds = ph.builds;
    }
    const char *end = rc ? NULL : mote_lines_next(&r->in);
    if (!rc && (!end || strcmp(end, "end")))
        rc = bad(r, "expected 'end'", end ? end : "the end of the file");
    if (!rc && mote_lines_next(&r->in))
        rc = bad(r, "something after 'end'", NULL);
    return rc;
}

int mote_sep_load(mote_sep_system *s, uint64_t *seed, const char *path, mote_err *err)
{
    reader r = {.err = err};
    int rc = mote_lines_open(&r.in, path, err);
    if (rc)
        return rc;
    mote_sep_system t;
    mote_sep_init(&t);
    rc = read_body(&r, &t, seed);
    const int rc2 = mote_lines_close(&r.in, err);
    rc = rc2 ? rc2 : rc;
    if (rc) {
        mote_sep_free(&t);
        return rc;
    }
    mote_sep_free(s);
    *s = t;
    s->dz = s->H / s->K;
    return mote_sep_gas_update(s, 0, err);
}
