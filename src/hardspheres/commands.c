/* commands.c: the hard-spheres model's script commands: the table the script language reads, the
 * validation of each command on a dry model (what system will exist, which files earlier commands
 * will write), and the calls into the model when the script runs. */
#include "mote/h5md.h"
#include "mote/vtk.h"
#include "mote/hardspheres.h"

#include <stdlib.h>
#include <string.h>

#include "help.inc"
#include "help_outputs.inc"
#include "measure.h"
#include "plot.h"

/* The model as the script layer sees it: the system plus, in a dry (validation) run, what is
 * known about the system each command will meet. */
typedef struct {
    mote_hs hs;
    int dry;
    /* dry state */
    int d_has, d_geometry, d_dim;
    uint64_t d_n; /* 0 = unknown */
} hs_model;

static void *model_create(mote_context *ctx, int dry)
{
    hs_model *m = calloc(1, sizeof *m);
    if (!m)
        return NULL;
    mote_hs_init(&m->hs, ctx);
    m->dry = dry;
    if (dry)
        m->hs.log = NULL;
    return m;
}

static void model_destroy(void *vm)
{
    hs_model *m = vm;
    if (!m)
        return;
    mote_hs_free(&m->hs);
    free(m);
}

static void model_status(void *vm, FILE *out) { mote_hs_status(&((hs_model *)vm)->hs, out); }

static void model_live(void *vm, mote_buf *b) { hs_live_frame(&((hs_model *)vm)->hs, b); }

static int model_settle(void *vm, mote_err *err) { return mote_hs_settle(&((hs_model *)vm)->hs, err); }

static void model_seed(void *vm, uint64_t seed) { mote_hs_seed(&((hs_model *)vm)->hs, seed); }

/* The particles as arrays, in the users' numbering (the engine keeps them in spatial order, so
 * these are copies): positions projected to the current time, velocities, radii, masses. */
static int model_arrays(void *vm, mote_array *out, int cap)
{
    const mote_hs *hs = &((hs_model *)vm)->hs;
    const mote_ev *ev = &hs->ev;
    const size_t n = hs->has_system ? ev->n : 0;
    const int d = ev->dim == 2 ? 2 : 3;
    static const char *const names[4] = {"positions", "velocities", "radii", "masses"};
    int k = 0;
    for (; k < 4 && k < cap; k++) {
        const size_t cols = k < 2 ? (size_t)d : 1;
        double *a = malloc((n ? n : 1) * cols * sizeof *a);
        if (!a) {
            while (k-- > 0)
                free(out[k].data);
            return -1;
        }
        for (uint32_t id = 0; id < n; id++) {
            const uint32_t i = mote_ev_slot(ev, id);
            double r[3];
            if (k == 0)
                mote_ev_position(ev, i, r);
            else if (k == 1)
                mote_ev_velocity(ev, i, r);
            else
                r[0] = k == 2 ? mote_ev_radius(ev, i) : mote_ev_mass(ev, i);
            memcpy(a + id * cols, r, cols * sizeof *a);
        }
        out[k] = (mote_array){.name = names[k], .data = a, .type = 'd', .rows = n, .cols = cols,
                              .row_stride = (long)(cols * sizeof *a), .col_stride = sizeof *a,
                              .owned = 1, .unit = k == 0 || k == 2 ? "R" : k == 1 ? "sqrt(kT/m)"
                                                                                  : "m"};
    }
    return k;
}

static int model_set_array(void *vm, const char *name, const double *v, size_t rows,
                           size_t cols, mote_err *err)
{
    return mote_hs_set_array(&((hs_model *)vm)->hs, name, v, rows, cols, err);
}

static int model_plot(void *vm, const char *data_path, const char *png_path,
                      const mote_call *c, mote_err *err)
{
    return hs_plot_file(data_path, png_path, err);
}

/* ---- validation helpers ------------------------------------------------------------------------ */

static int need_system(hs_model *m, const mote_call *c, mote_err *err)
{
    if (!m->d_has)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "%s: no system exists yet; create one first with new, bulk, "
                              "new_disks, bulk_disks or load",
                              c->name);
    return MOTE_OK;
}

static int check_collisions(const hs_model *m, const mote_call *c, int argi, uint64_t k,
                            mote_err *err)
{
    if (m->d_n && k > 0 && k > ((1ull << 62) - 1) / m->d_n)
        return mote_call_fail(err, c, argi, MOTE_EINVAL,
                              "%s: K = %llu is too large for N = %llu (K*N must be below 2^62)",
                              c->name, (unsigned long long)k, (unsigned long long)m->d_n);
    return MOTE_OK;
}

static int located(mote_err *err, const mote_call *c, int argi, int rc)
{
    /* turn a model error message into a located validation error */
    if (rc) {
        char msg[sizeof err->msg];
        snprintf(msg, sizeof msg, "%s", err->msg);
        mote_call_fail(err, c, argi, (mote_status)rc, "%s", msg);
    }
    return rc;
}

/* ---- seeding -------------------------------------------------------------------------------------- */

static void dry_system(hs_model *m, int geometry, int dim, uint64_t n)
{
    m->d_has = 1;
    m->d_geometry = geometry;
    m->d_dim = dim;
    m->d_n = n;
}

static int check_new(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    int rc = mote_hs_new_ok(c->args[0].i, c->args[1].r, err);
    if (rc)
        return located(err, c, c->args[0].i < 2 ? 0 : 1, rc);
    dry_system(m, MOTE_HS_SLIT, 3, mote_hs_new_count(c->args[0].i));
    return MOTE_OK;
}
static int run_new(void *vm, const mote_call *c, mote_err *err)
{
    return mote_hs_new(&((hs_model *)vm)->hs, c->args[0].i, c->args[1].r, err);
}

static int check_bulk(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    int rc = mote_hs_bulk_ok(c->args[0].i, c->args[1].r, err);
    if (rc)
        return located(err, c, strstr(err->msg, "eta = ") ? 1 : 0, rc);
    dry_system(m, MOTE_HS_PERIODIC, 3, (uint64_t)c->args[0].i);
    return MOTE_OK;
}
static int run_bulk(void *vm, const mote_call *c, mote_err *err)
{
    return mote_hs_bulk(&((hs_model *)vm)->hs, c->args[0].i, c->args[1].r, err);
}

static int check_new_disks(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    int rc = mote_hs_new_disks_ok(c->args[0].i, c->args[1].i, c->args[2].r, err);
    if (rc)
        return located(err, c, c->args[0].i < 2 ? 0 : c->args[1].i < 3 ? 1 : 2, rc);
    dry_system(m, MOTE_HS_SLIT, 2, (uint64_t)(c->args[0].i * c->args[1].i));
    return MOTE_OK;
}
static int run_new_disks(void *vm, const mote_call *c, mote_err *err)
{
    return mote_hs_new_disks(&((hs_model *)vm)->hs, c->args[0].i, c->args[1].i, c->args[2].r,
                             err);
}

static int check_bulk_disks(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    int rc = mote_hs_bulk_disks_ok(c->args[0].i, c->args[1].r, err);
    if (rc)
        return located(err, c, strstr(err->msg, "eta = ") ? 1 : 0, rc);
    dry_system(m, MOTE_HS_PERIODIC, 2, (uint64_t)c->args[0].i);
    return MOTE_OK;
}
static int run_bulk_disks(void *vm, const mote_call *c, mote_err *err)
{
    return mote_hs_bulk_disks(&((hs_model *)vm)->hs, c->args[0].i, c->args[1].r, err);
}

/* ---- files ------------------------------------------------------------------------------------------ */

static int check_save(void *vm, const mote_call *c, mote_err *err) { return need_system(vm, c, err); }
static int run_save(void *vm, const mote_call *c, mote_err *err)
{
    return mote_hs_save(&((hs_model *)vm)->hs, c->args[0].path, err);
}

static int check_load(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    const char *kind = mote_outputs_find(&c->ctx->outputs, c->args[0].path);
    if (kind) { /* written by an earlier save of this script: the system as it was then */
        m->d_has = 1;
        return MOTE_OK;
    }
    int geometry, dim;
    uint64_t n;
    int rc = mote_hs_peek(c->args[0].path, &geometry, &dim, &n, err);
    if (rc)
        return located(err, c, 0, rc);
    dry_system(m, geometry, dim, n);
    return MOTE_OK;
}
static int run_load(void *vm, const mote_call *c, mote_err *err)
{
    return mote_hs_load(&((hs_model *)vm)->hs, c->args[0].path, err);
}

/* ---- dynamics --------------------------------------------------------------------------------------- */

static int check_temperature(void *vm, const mote_call *c, mote_err *err)
{
    return need_system(vm, c, err);
}
static int run_temperature(void *vm, const mote_call *c, mote_err *err)
{
    return mote_hs_temperature(&((hs_model *)vm)->hs, c->args[0].r, err);
}

/* A command that runs K collisions per particle (argument argi): a system, and K N in range. */
static int check_run_k(hs_model *m, const mote_call *c, int argi, mote_err *err)
{
    int rc = need_system(m, c, err);
    return rc ? rc : check_collisions(m, c, argi, (uint64_t)c->args[argi].i, err);
}

static int check_step(void *vm, const mote_call *c, mote_err *err) { return check_run_k(vm, c, 0, err); }
static int run_step(void *vm, const mote_call *c, mote_err *err)
{
    return mote_hs_step(&((hs_model *)vm)->hs, (uint64_t)c->args[0].i, err);
}

/* eta of every compression command: below close packing in the system's dimension */
static int check_compress_args(hs_model *m, const mote_call *c, mote_err *err)
{
    double cp = m->d_dim == 2 ? 0.90689968211710892 : 0.74048048969306104;
    if (!(c->args[0].r < cp))
        return mote_call_fail(err, c, 0, MOTE_EINVAL,
                              "%s: eta must be in (0, %.5f) (close packing), found %s", c->name,
                              cp, c->args[0].text);
    return check_collisions(m, c, 2, (uint64_t)c->args[2].i, err);
}

static int check_compress_any(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    int rc = need_system(m, c, err);
    if (rc)
        return rc;
    if (m->d_geometry == MOTE_HS_PERIODIC)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "%s: the system here is periodic (from bulk or bulk_disks); only a "
                              "slit has walls to move (compress a periodic box with compress_box)",
                              c->name);
    return check_compress_args(m, c, err);
}

static int check_compress_box(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    int rc = need_system(m, c, err);
    if (rc)
        return rc;
    if (m->d_geometry == MOTE_HS_SLIT)
        return mote_call_fail(err, c, -1, MOTE_EINVAL,
                              "compress_box: the system here is a slit; move its walls with "
                              "compress_left_wall, compress_right_wall or compress_two_walls");
    return check_compress_args(m, c, err);
}
static int run_compress_box(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    return located(err, c, -1,
                   mote_hs_compress_box(&m->hs, c->args[0].r, c->args[1].r,
                                        (uint64_t)c->args[2].i, err));
}

static int run_compress_which(void *vm, const mote_call *c, int which, mote_err *err)
{
    return mote_hs_compress(&((hs_model *)vm)->hs, which, c->args[0].r, c->args[1].r,
                            (uint64_t)c->args[2].i, err);
}
static int run_compress_left(void *vm, const mote_call *c, mote_err *err)
{
    return run_compress_which(vm, c, MOTE_HS_LEFT, err);
}
static int run_compress_right(void *vm, const mote_call *c, mote_err *err)
{
    return run_compress_which(vm, c, MOTE_HS_RIGHT, err);
}
static int run_compress_both(void *vm, const mote_call *c, mote_err *err)
{
    return run_compress_which(vm, c, MOTE_HS_BOTH, err);
}

static int check_compress(void *vm, const mote_call *c, mote_err *err)
{
    return mote_call_fail(err, c, -1, MOTE_EINVAL,
                          "'compress' is not a command: say which wall moves: "
                          "compress_left_wall (compressl), compress_right_wall (compressr) or "
                          "compress_two_walls (compresst, compress_both_walls), each with "
                          "arguments eta dLmax K");
}
static int run_compress(void *vm, const mote_call *c, mote_err *err)
{
    return check_compress(vm, c, err);
}

/* ---- measurements ------------------------------------------------------------------------------- */

/* Report what a command wrote (the file is its last argument). */
static void wrote(hs_model *m, const mote_call *c)
{
    if (m->hs.log)
        fprintf(m->hs.log, "%s: wrote %s\n", c->name, c->args[c->nargs - 1].path);
}

static int check_image(void *vm, const mote_call *c, mote_err *err) { return check_run_k(vm, c, 0, err); }
static int run_image(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    char *origin = mote_call_origin(c);
    int rc = origin ? mote_hs_image(&m->hs, (uint64_t)c->args[0].i, c->args[1].i,
                                    c->args[2].path, origin, err)
                    : mote_fail(err, MOTE_ENOMEM, "out of memory");
    if (!rc)
        wrote(m, c);
    free(origin);
    return rc;
}

static int check_profile(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    if (!(c->args[0].r <= c->args[1].r))
        return mote_call_fail(err, c, 1, MOTE_EINVAL, "profile: x2 must not be below x1 (%s > %s)",
                              c->args[0].text, c->args[1].text);
    if (c->args[3].i == 0 && c->args[2].i != 1)
        return mote_call_fail(err, c, 3, MOTE_EINVAL,
                              "profile: K = 0 samples the current state once, so dots must be 1");
    return check_run_k(m, c, 3, err);
}
static int run_profile(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    char *origin = mote_call_origin(c);
    int rc = origin ? mote_hs_profile(&m->hs, c->args[0].r, c->args[1].r, c->args[2].i,
                                      (uint64_t)c->args[3].i, c->args[4].path, origin, err)
                    : mote_fail(err, MOTE_ENOMEM, "out of memory");
    if (!rc)
        wrote(m, c);
    free(origin);
    return rc;
}

static int run_bins(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    m->hs.bins = c->args[0].i;
    if (m->hs.log)
        fprintf(m->hs.log, "bins: %lld per R (bin width %g R) for pressure and chempot\n",
                (long long)m->hs.bins, 1.0 / (double)m->hs.bins);
    return MOTE_OK;
}

typedef int (*measure_fn)(hs_model *m, const mote_call *c, const char *path, const char *origin,
                          mote_result *res, mote_err *err);

/* Run a measurement writing its last argument, then print its key=value summary line. */
static int run_measure(hs_model *m, const mote_call *c, measure_fn fn, mote_err *err)
{
    char *origin = mote_call_origin(c);
    mote_result res = {0};
    int rc = origin ? fn(m, c, c->args[c->nargs - 1].path, origin, &res, err)
                    : mote_fail(err, MOTE_ENOMEM, "out of memory");
    for (int k = 0; !rc && k < res.n; k++) /* (the replicas of an ensemble average them) */
        mote_call_result(c, res.kv[k].key, res.kv[k].value);
    if (!rc && m->hs.log) {
        mote_result_print(&res, c->name, m->hs.log);
        wrote(m, c);
    }
    free(origin);
    return rc;
}

static int check_measure(void *vm, const mote_call *c, mote_err *err)
{
    return check_run_k(vm, c, 0, err);
}

static int do_pressure(hs_model *m, const mote_call *c, const char *path, const char *origin,
                       mote_result *res, mote_err *err)
{
    return mote_hs_pressure(&m->hs, (uint64_t)c->args[0].i, path, origin, res, err);
}
static int run_pressure(void *vm, const mote_call *c, mote_err *err)
{
    return run_measure(vm, c, do_pressure, err);
}

static int do_chempot(hs_model *m, const mote_call *c, const char *path, const char *origin,
                      mote_result *res, mote_err *err)
{
    return mote_hs_chempot(&m->hs, (uint64_t)c->args[0].i, c->args[1].i, path, origin, res, err);
}
static int run_chempot(void *vm, const mote_call *c, mote_err *err)
{
    return run_measure(vm, c, do_chempot, err);
}

static int do_order(hs_model *m, const mote_call *c, const char *path, const char *origin,
                    mote_result *res, mote_err *err)
{
    return mote_hs_order(&m->hs, (uint64_t)c->args[0].i, path, origin, res, err);
}
static int run_order(void *vm, const mote_call *c, mote_err *err)
{
    return run_measure(vm, c, do_order, err);
}

static int do_rdf(hs_model *m, const mote_call *c, const char *path, const char *origin,
                  mote_result *res, mote_err *err)
{
    return mote_hs_rdf(&m->hs, (uint64_t)c->args[0].i, c->args[1].r, path, origin, res, err);
}
static int run_rdf(void *vm, const mote_call *c, mote_err *err)
{
    return run_measure(vm, c, do_rdf, err);
}

static int do_msd(hs_model *m, const mote_call *c, const char *path, const char *origin,
                  mote_result *res, mote_err *err)
{
    return mote_hs_msd(&m->hs, (uint64_t)c->args[0].i, path, origin, res, err);
}
static int run_msd(void *vm, const mote_call *c, mote_err *err)
{
    return run_measure(vm, c, do_msd, err);
}

static int check_check(void *vm, const mote_call *c, mote_err *err) { return need_system(vm, c, err); }
static int run_check(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    int rc = mote_hs_check(&m->hs, err);
    if (!rc && m->hs.log)
        fprintf(m->hs.log, "check: all invariants hold\n");
    return rc;
}

/* ---- configurations for viewers ----------------------------------------------------------------- */

/* file=: an extended XYZ name */
/* A trajectory's or snapshot's file: FILE.xyz (extended XYZ), FILE.h5|.h5md (H5MD) or, a
 * snapshot (vtk_ok), FILE.vtk (VTK), as format= says when given. */
enum { FORMAT_XYZ, FORMAT_H5MD, FORMAT_VTK }; /* format=e{xyz|h5md|vtk} */
static int check_xyz_name(const mote_call *c, int vtk_ok, mote_err *err)
{
    const int vtk = mote_call_vtk(c, "file", vtk_ok ? FORMAT_VTK : -1, err);
    if (vtk)
        return vtk < 0 ? err->code : MOTE_OK;
    const int h5md = mote_call_h5md(c, "file", FORMAT_H5MD, err);
    if (h5md < 0)
        return err->code;
    const char *f = mote_call_opt(c, "file")->text;
    size_t n = strlen(f);
    if (!h5md && (n < 4 || strcmp(f + n - 4, ".xyz") != 0))
        return mote_call_fail(err, c, mote_call_opt_index(c, "file"), MOTE_EINVAL,
                              "%s: FILE must end in .xyz (extended XYZ)%s .h5 (H5MD)%s, found "
                              "'%s'", c->name, vtk_ok ? "," : " or",
                              vtk_ok ? " or .vtk (VTK)" : "", f);
    return MOTE_OK;
}

/* The schedule of `trajectory` and `monitor`: every=K collisions per particle or dt=T of time,
 * one of them. */
static int check_schedule(hs_model *m, const mote_call *c, mote_err *err)
{
    int rc = need_system(m, c, err);
    const mote_arg *every = mote_call_opt(c, "every"), *dt = mote_call_opt(c, "dt");
    if (!rc && !!every == !!dt)
        rc = mote_call_fail(err, c, every ? mote_call_opt_index(c, "dt") : -1, MOTE_EINVAL,
                            "%s: give every=K (collisions per particle) or dt=T (time), %s",
                            c->name, every ? "not both" : "one of them");
    if (!rc && every)
        rc = check_collisions(m, c, mote_call_opt_index(c, "every"), (uint64_t)every->i, err);
    return rc;
}

static int snapshots_h5md(mote_hs *hs, uint64_t k, double dt, const char *prefix,
                          const char *origin, mote_err *err);
static int snapshots_vtk(mote_hs *hs, uint64_t k, double dt, const char *prefix,
                         const char *origin, mote_err *err);

/* Start a scheduled output (start: mote_hs_dump_start_on or mote_hs_monitor_start) and say so;
 * `what` is the first item's name ("frame", "row"). */
static int run_scheduled(hs_model *m, const mote_call *c, const char *what,
                         int (*start)(mote_hs *, uint64_t, double, const char *, const char *,
                                      mote_err *),
                         mote_err *err)
{
    char *origin = mote_call_origin(c);
    const mote_arg *every = mote_call_opt(c, "every");
    const uint64_t k = every ? (uint64_t)every->i : 0;
    const double dt = mote_call_opt_r(c, "dt", 0);
    const mote_arg *file = mote_call_opt(c, "file");
    const char *path = file ? file->path : mote_call_opt(c, "prefix")->path; /* (a series) */
    int rc = origin ? start(&m->hs, k, dt, path, origin, err)
                    : mote_fail(err, MOTE_ENOMEM, "out of memory");
    const char *in = file ? " in " : " as ";
    const char *ext = file                          ? ""
                      : start == mote_hs_frames_start ? "NNNNNN.png"
                      : start == snapshots_h5md        ? "NNNNNN.h5"
                      : start == snapshots_vtk         ? "NNNNNN.vtk"
                                                       : "NNNNNN.xyz";
    const char *sep = file ? "" : mote_series_sep(path);
    if (!rc && m->hs.log && k)
        fprintf(m->hs.log, "%s: %s 0%s%s%s%s, then one every %llu collisions per particle\n",
                c->name, what, in, path, sep, ext, (unsigned long long)k);
    else if (!rc && m->hs.log)
        fprintf(m->hs.log, "%s: %s 0%s%s%s%s, then one every %.17g of time\n", c->name, what, in,
                path, sep, ext, dt);
    free(origin);
    return rc;
}

/* `snapshot file=FILE.xyz` (one now) or `snapshot every=K|dt=T prefix=P` (a series: one now
 * and then on the schedule, P_000000.xyz on) */
static int check_snapshot(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    const mote_arg *file = mote_call_opt(c, "file"), *prefix = mote_call_opt(c, "prefix");
    const int sched = mote_call_opt(c, "every") || mote_call_opt(c, "dt");
    if (!file == !(sched || prefix))
        return mote_call_fail(err, c, file ? mote_call_opt_index(c, "file") : -1, MOTE_EINVAL,
                              "snapshot: give file=FILE.xyz (one now) or every=K or dt=T with "
                              "prefix=P (a series), %s", file ? "not both" : "one of them");
    if (file) {
        int rc = need_system(m, c, err);
        return rc ? rc : check_xyz_name(c, 1, err);
    }
    if (!prefix)
        return mote_call_fail(err, c, -1, MOTE_EINVAL, "snapshot: a series needs prefix=P "
                              "(files P_000000.xyz, ...)");
    int rc = check_schedule(m, c, err);
    const int fmt = mote_call_word(c, "format", FORMAT_XYZ);
    const char *ext = fmt == FORMAT_H5MD ? ".h5" : fmt == FORMAT_VTK ? ".vtk" : ".xyz";
    return rc ? rc : mote_outputs_note_series(&c->ctx->outputs, c, mote_call_opt_index(c, "prefix"),
                                              prefix->path, ext, "xyz", MOTE_SERIES_MAKES_DIR, err);
}
/* (the series' starts, as run_scheduled calls them) */
static int snapshots_h5md(mote_hs *hs, uint64_t k, double dt, const char *prefix,
                          const char *origin, mote_err *err)
{
    return mote_hs_snapshots_start_as(hs, k, dt, prefix, ".h5", origin, err);
}
static int snapshots_vtk(mote_hs *hs, uint64_t k, double dt, const char *prefix,
                         const char *origin, mote_err *err)
{
    return mote_hs_snapshots_start_as(hs, k, dt, prefix, ".vtk", origin, err);
}
static int run_snapshot(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    const mote_arg *file = mote_call_opt(c, "file");
    if (!file)
        return run_scheduled(m, c, "snapshot",
                             mote_call_word(c, "format", FORMAT_XYZ) == FORMAT_H5MD ? snapshots_h5md
                             : mote_call_word(c, "format", FORMAT_XYZ) == FORMAT_VTK
                                 ? snapshots_vtk
                                 : mote_hs_snapshots_start,
                             err);
    char *origin = mote_call_origin(c);
    int rc = origin ? mote_hs_snapshot(&m->hs, file->path, origin, err)
                    : mote_fail(err, MOTE_ENOMEM, "out of memory");
    if (!rc && m->hs.log)
        fprintf(m->hs.log, "%s: wrote %s\n", c->name, file->path);
    free(origin);
    return rc;
}

/* `frames every=K|dt=T prefix=P`: pictures now and on the schedule, P_000000.png on */
static int check_frames(void *vm, const mote_call *c, mote_err *err)
{
    int rc = check_schedule(vm, c, err);
    return rc ? rc : mote_outputs_note_series(&c->ctx->outputs, c,
                                              mote_call_opt_index(c, "prefix"),
                                              mote_call_opt(c, "prefix")->path, ".png", "frames",
                                              MOTE_SERIES_MAKES_DIR, err);
}
static int run_frames(void *vm, const mote_call *c, mote_err *err)
{
    return run_scheduled(vm, c, "frames", mote_hs_frames_start, err);
}
static int run_frames_stop(void *vm, const mote_call *c, mote_err *err)
{
    mote_hs_frames_stop(&((hs_model *)vm)->hs);
    return MOTE_OK;
}

static int check_dump(void *vm, const mote_call *c, mote_err *err)
{
    int rc = check_schedule(vm, c, err);
    return rc ? rc : check_xyz_name(c, 0, err);
}
static int run_dump(void *vm, const mote_call *c, mote_err *err)
{
    return run_scheduled(vm, c, "frame", mote_hs_dump_start_on, err);
}

/* `checkpoint every=K file=FILE` (the exact state on a schedule) and `checkpoint_stop`. */
static int check_checkpoint(void *vm, const mote_call *c, mote_err *err)
{
    return need_system(vm, c, err);
}
static int run_checkpoint(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    char *origin = mote_call_origin(c);
    const uint64_t k = (uint64_t)mote_call_opt(c, "every")->i;
    const char *path = mote_call_opt(c, "file")->path;
    int rc = origin ? mote_hs_checkpoint_start(&m->hs, k, path, origin, err)
                    : mote_fail(err, MOTE_ENOMEM, "out of memory");
    free(origin);
    if (!rc && m->hs.log)
        fprintf(m->hs.log, "%s: the state in %s now and every %llu collisions per particle\n",
                c->name, path, (unsigned long long)k);
    return rc;
}
static int run_checkpoint_stop(void *vm, const mote_call *c, mote_err *err)
{
    mote_hs_checkpoint_stop(&((hs_model *)vm)->hs);
    return MOTE_OK;
}

/* `monitor every=K|dt=T file=FILE` (the run's quantities over time) and `monitor_stop`. */
static int check_monitor(void *vm, const mote_call *c, mote_err *err)
{
    return check_schedule(vm, c, err);
}
static int run_monitor(void *vm, const mote_call *c, mote_err *err)
{
    ((hs_model *)vm)->hs.monitor_as = mote_call_word(c, "format", MOTE_AS_NAME);
    return run_scheduled(vm, c, "row", mote_hs_monitor_start, err);
}
static int run_monitor_stop(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    if (m->hs.log && m->hs.monitor)
        fprintf(m->hs.log, "monitor_stop: %llu rows written\n",
                (unsigned long long)mote_hs_monitor_rows(&m->hs));
    mote_hs_monitor_stop(&m->hs);
    return MOTE_OK;
}

static int run_snapshot_stop(void *vm, const mote_call *c, mote_err *err)
{
    mote_hs_snapshots_stop(&((hs_model *)vm)->hs);
    return MOTE_OK;
}

static int run_dump_stop(void *vm, const mote_call *c, mote_err *err)
{
    hs_model *m = vm;
    if (m->hs.log && m->hs.dump)
        fprintf(m->hs.log, "%s: %llu frames written\n", c->name,
                (unsigned long long)mote_hs_dump_frames(&m->hs));
    mote_hs_dump_stop(&m->hs);
    return MOTE_OK;
}

/* ---- the table ----------------------------------------------------------------------------------- */

static const mote_cmd hs_commands[] = {
    {"new", NULL, "i r", "new NN eta", "seed a 3D slit: N = (4NN-1)(2NN-1)^2+1 spheres at density eta",
     HS_HELP_NEW, check_new, run_new},
    {"bulk", NULL, "i r", "bulk N eta", "seed a periodic FCC cube of N = 4n^3 spheres", HS_HELP_BULK,
     check_bulk, run_bulk},
    {"new_disks", NULL, "i i r", "new_disks nx ny eta", "seed a 2D slit of nx*ny disks",
     HS_HELP_NEW_DISKS, check_new_disks, run_new_disks},
    {"bulk_disks", NULL, "i r", "bulk_disks N eta", "seed a periodic 2D triangular lattice of N = n^2 disks",
     HS_HELP_BULK_DISKS, check_bulk_disks, run_bulk_disks},
    {"save", NULL, "f>state", "save FILE", "write the exact state to FILE", HS_HELP_SAVE, check_save,
     run_save},
    {"load", NULL, "f<state", "load FILE", "read a state (mote or original-program format)",
     HS_HELP_LOAD, check_load, run_load},
    {"temperature", NULL, "r(0,1e100]", "temperature T", "rescale velocities so that kT_kin = T",
     HS_HELP_TEMPERATURE, check_temperature, run_temperature},
    {"step", NULL, "i>=1", "step K", "run K collisions per particle (floor(K N / 2) pair collisions)",
     HS_HELP_STEP, check_step, run_step},
    {"compress_left_wall", "compressl", "r>0 r>0 i>=1", "compress_left_wall eta dLmax K",
     "move the left wall until the density is eta", HS_HELP_COMPRESS_LEFT, check_compress_any,
     run_compress_left},
    {"compress_right_wall", "compressr", "r>0 r>0 i>=1", "compress_right_wall eta dLmax K",
     "move the right wall until the density is eta", HS_HELP_COMPRESS_RIGHT, check_compress_any,
     run_compress_right},
    {"compress_two_walls", "compresst compress_both_walls", "r>0 r>0 i>=1",
     "compress_two_walls eta dLmax K",
     "move both walls symmetrically until the density is eta", HS_HELP_COMPRESS_BOTH,
     check_compress_any, run_compress_both},
    {"compress_box", NULL, "r>0 r>0 i>=1", "compress_box eta dLmax K",
     "compress (or expand) a periodic box affinely until its packing fraction is eta",
     HS_HELP_COMPRESS_BOX, check_compress_box, run_compress_box},
    {"compress", NULL, "*", "compress ...", "always an error: name the wall to move",
     HS_HELP_COMPRESS, check_compress, run_compress},
    {"image", NULL, "i i[1,10000] f>image", "image K p FILE", "density profile along x (p bins per radius)",
     HS_HELP_IMAGE, check_image, run_image},
    {"profile", NULL, "r r i[1,1000000] i f>profile", "profile x1 x2 dots K FILE",
     "layer cut: centres with x1 <= x <= x2, projected on the y-z plane", HS_HELP_PROFILE,
     check_profile, run_profile},
    {"bins", NULL, "i[1,10000]", "bins p", "bins per R for the pressure and chempot profiles (default 10)",
     HS_HELP_BINS, NULL, run_bins},
    {"pressure", NULL, "i>=1 f>pressure", "pressure K FILE",
     "wall pressures, virial pressure and pressure-tensor profiles over K collisions per particle",
     HS_HELP_PRESSURE, check_measure, run_pressure},
    {"chempot", NULL, "i i>=1 f>chempot", "chempot K TRIALS FILE",
     "excess chemical potential by Widom test-particle insertion", HS_HELP_CHEMPOT, check_measure,
     run_chempot},
    {"order", NULL, "i f>order", "order K FILE",
     "crystallinity per wall layer: Steinhardt q6 and in-layer psi6", HS_HELP_ORDER, check_measure,
     run_order},
    {"rdf", NULL, "i r>0 f>rdf", "rdf K RMAX FILE",
     "radial distribution function g(r) up to RMAX, its contact value and Z (slit: in-layer g)",
     HS_HELP_RDF, check_measure, run_rdf},
    {"msd", NULL, "i>=4 f>msd", "msd K FILE",
     "mean-squared displacement and the self-diffusion coefficient D over K collisions per particle",
     HS_HELP_MSD, check_measure, run_msd},
    {"snapshot", NULL, "@file=f>xyz every=i>=1 dt=r>0 prefix=f format=e{xyz|h5md|vtk}",
     "snapshot file=FILE.xyz|every=K|dt=T prefix=P [format=xyz|h5md|vtk]",
     "the current configuration as extended XYZ (OVITO, VMD, ASE), H5MD or VTK, with local order; "
     "or a series",
     HS_HELP_SNAPSHOT, check_snapshot, run_snapshot},
    {"trajectory", "dump", "@every=i>=1 @file=f>xyz! dt=r>0 format=e{xyz|h5md}",
     "trajectory every=K|dt=T file=FILE.xyz|FILE.h5 [format=xyz|h5md]",
     "a trajectory: an XYZ (or H5MD) frame now and every K collisions per particle of later "
     "commands",
     HS_HELP_DUMP, check_dump, run_dump},
    {"frames", NULL, "@every=i>=1 @prefix=f! dt=r>0", "frames every=K|dt=T prefix=P",
     "a picture now and every K collisions per particle or T of time: P_000000.png ...",
     HS_HELP_FRAMES, check_frames, run_frames},
    MOTE_CMD_STOP(frames, NULL, NULL, run_frames_stop),
    MOTE_CMD_STOP(snapshot, NULL, NULL, run_snapshot_stop),
    MOTE_CMD_STOP(trajectory, "dump_stop", NULL, run_dump_stop),
    {"monitor", NULL, "@every=i>=1 @file=f>monitor! dt=r>0 format=e{table|csv|jsonl}",
     "monitor every=K|dt=T file=FILE [format=table|csv|jsonl]",
     "the run's time, collisions, temperature and pressure, a row every K collisions per "
     "particle or every T of time", HS_HELP_MONITOR, check_monitor, run_monitor},
    MOTE_CMD_STOP(monitor, NULL, NULL, run_monitor_stop),
    {"checkpoint", NULL, "every=i>=1! file=f>state!", "checkpoint every=K file=FILE",
     "keep the exact state in FILE every K collisions per particle (load continues from it)",
     HS_HELP_CHECKPOINT, check_checkpoint, run_checkpoint},
    MOTE_CMD_STOP(checkpoint, NULL, NULL, run_checkpoint_stop),
    {"check", NULL, "", "check", "verify every invariant of the simulation", HS_HELP_CHECK,
     check_check, run_check},
};

/* `picture FILE.png`: the picture of `frames`, now. */
static int model_picture(void *vm, const char *path, mote_err *err)
{
    const hs_model *m = vm;
    if (!m->hs.has_system)
        return mote_fail(err, MOTE_EINVAL, "no system exists yet");
    return hs_frame_png(&m->hs, path, err);
}

/* The box: the slit's width L along x (walls at 0 and L, or periodic), the periodic sides. */
static int model_cell(void *vm, double edges[3], double origin[3], int periodic[3])
{
    const hs_model *m = vm;
    if (!m->hs.has_system)
        return -1;
    const mote_ev *ev = &m->hs.ev;
    for (int a = 0; a < 3; a++) {
        edges[a] = a < ev->dim ? ev->len[a] : 0;
        origin[a] = 0;
        periodic[a] = a < ev->dim && ev->periodic[a];
    }
    return 0;
}

const mote_model mote_model_hardspheres = {
    .name = "hard-spheres",
    .summary = "hard spheres (or disks) between two walls or in a periodic box; event-driven",
    .cmds = hs_commands,
    .ncmds = sizeof hs_commands / sizeof hs_commands[0],
    .create = model_create,
    .destroy = model_destroy,
    .status = model_status,
    .settle = model_settle,
    .seed = model_seed,
    .seed_help = HS_HELP_SEED,
    .plot_kinds = "image|profile|pressure|chempot|order|rdf|msd|monitor",
    .plot = model_plot,
    .plot_help = HS_HELP_PLOT,
    .plot_lines = "image:x_mid,rho pressure:time|x_mid,P_wall|P_N chempot:x_mid,ln_rho_plus_mu_ex "
                  "rdf:r_mid|s_mid,g|g_wall msd:lag_time,msd order:time,xtal_frac",
    .live = model_live,
    .arrays = model_arrays,
    .set_array = model_set_array,
    .cell = model_cell,
    .picture = model_picture,
    .picture_help = "The picture of `frames`: the box seen along z, each particle a disc of its\n"
                    "radius coloured by its local order (crystal-like or fluid-like).\n",
};
