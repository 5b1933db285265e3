/* xyz.c: configurations for viewers (OVITO, VMD, ASE) as extended XYZ: `snapshot FILE.xyz`, one
 * frame of the current state, `snapshot every=|dt= prefix=`, a series of them, `trajectory`, a
 * trajectory with a frame every K collisions per particle (or T of time) during every later
 * command that runs the dynamics, and the series of pictures of `frames`. Each frame holds
 * the box as Lattice, the periodic axes as pbc, and per particle (in particle-number order, as
 * in the state file) the position, velocity and radius, and the local order of the frame's own
 * configuration with the `order` command's definitions: q6 and the crystal-like flag in 3D,
 * |psi6| and the ordered flag in 2D, so a viewer can colour crystalline particles.
 *
 * Writing a frame only reads positions projected to the clock, so dumping never changes the
 * trajectory. A snapshot is written atomically; a trajectory is the core's growing file of
 * frames (mote_frames_first, mote_frames_append). */
#include "mote/hardspheres.h"
#include "mote/h5md.h"
#include "mote/vtk.h"

#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "measure.h"

enum { SERIES_XYZ = 1, SERIES_PNG = 2, SERIES_STATE = 3, SERIES_H5MD = 4, SERIES_VTK = 5 };

struct hs_dump {
    char *path, *origin;
    uint64_t k;       /* collisions per particle between frames (0: by time) */
    mote_schedule at; /* by time: the next frame at at.t0 + at.k at.dt */
    uint64_t next_at; /* value of ev.collisions at which the next frame is written */
    uint64_t frames;  /* written so far (a series: the next file's number) */
    int series;       /* a series of files (path: the prefix), not a trajectory: SERIES_XYZ
                       * or SERIES_H5MD (snapshots) or SERIES_PNG (frames); SERIES_STATE: one file, the
                       * state (path: the file; a checkpoint) */
};

/* One frame: the two header lines and N particle lines. */
typedef struct {
    const mote_hs *hs;
    const char *origin;
} frame_of_hs;

static int write_frame(FILE *f, const void *arg, mote_err *err)
{
    const mote_hs *hs = ((const frame_of_hs *)arg)->hs;
    const char *origin = ((const frame_of_hs *)arg)->origin;
    const mote_ev *ev = &hs->ev;
    const int d3 = ev->dim == 3;
    float *local = malloc((ev->n ? ev->n : 1) * sizeof *local);
    uint8_t *flag = malloc(ev->n ? ev->n : 1);
    int rc = local && flag ? hs_local_order(hs, local, flag, err)
                           : mote_fail(err, MOTE_ENOMEM, "out of memory for a frame of %u "
                                                         "particles", ev->n);
    if (rc) {
        free(local);
        free(flag);
        return rc;
    }
    char org[512]; /* a value of the comment line may not hold double quotes */
    snprintf(org, sizeof org, "%s", origin ? origin : "(library call)");
    for (char *q = org; *q; q++)
        if (*q == '"')
            *q = '\'';
    char pbc[3];
    for (int a = 0; a < 3; a++)
        pbc[a] = a < ev->dim && ev->periodic[a] ? 'T' : 'F';
    fprintf(f, "%" PRIu32 "\n", ev->n);
    fprintf(f,
            "Lattice=\"%.17g 0 0 0 %.17g 0 0 0 %.17g\" Properties=species:S:1:pos:R:3:velo:R:3:"
            "radius:R:1:%s Time=%.17g collisions=%" PRIu64 " pbc=\"%c %c %c\" "
            "model=hard-spheres geometry=%s command=\"%s\"\n",
            ev->len[0], ev->len[1], d3 ? ev->len[2] : 2 * mote_hs_mean_radius(hs),
            d3 ? "q6:R:1:solid:I:1" : "psi6:R:1:ordered:I:1", mote_ev_time(ev), ev->collisions,
            pbc[0], pbc[1], pbc[2], hs->geometry == MOTE_HS_SLIT ? "slit" : "periodic", org);
    for (uint32_t id = 0; id < ev->n; id++) {
        const uint32_t i = mote_ev_slot(ev, id);
        double r[3], v[3];
        mote_ev_position(ev, i, r);
        mote_ev_velocity(ev, i, v);
        if (!d3)
            r[2] = v[2] = 0;
        fprintf(f, "X %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.6g %d\n", r[0], r[1], r[2], v[0],
                v[1], v[2], mote_ev_radius(ev, i), local[i], flag[i]);
    }
    free(local);
    free(flag);
    return MOTE_OK;
}

/* The frame as H5MD (h5md.h): made anew (how 0) or added at the end (1); or as VTK (2, vtk.h). */
static int h5md_frame(const mote_hs *hs, const char *path, const char *origin, int how,
                      mote_err *err)
{
    const mote_ev *ev = &hs->ev;
    const size_t n = ev->n, D = (size_t)ev->dim;
    double *buf = malloc((n ? n : 1) * (2 * D + 2) * sizeof *buf);
    float *local = malloc((n ? n : 1) * sizeof *local);
    uint8_t *flag = malloc(n ? n : 1);
    int rc = buf && local && flag ? hs_local_order(hs, local, flag, err)
                                  : mote_fail(err, MOTE_ENOMEM, "out of memory for a frame of "
                                                                "%zu particles", n);
    if (!rc) {
        double *pos = buf, *vel = buf + n * D, *rad = vel + n * D, *ord = rad + n;
        for (uint32_t id = 0; id < ev->n; id++) {
            const uint32_t i = mote_ev_slot(ev, id);
            double r[3], v[3];
            mote_ev_position(ev, i, r);
            mote_ev_velocity(ev, i, v);
            for (size_t a = 0; a < D; a++) {
                pos[id * D + a] = r[a];
                vel[id * D + a] = v[a];
            }
            rad[id] = mote_ev_radius(ev, i);
            ord[id] = local[i];
        }
        mote_h5md_frame fr = {.model = "hard-spheres", .origin = origin, .seed = hs->seed,
                              .dim = ev->dim, .n = n, .pos = pos, .vel = vel, .nscalar = 2,
                              .has_box = 1, .time = mote_ev_time(ev),
                              .step = (int64_t)ev->collisions};
        fr.scalar[0] = (mote_h5md_scalar){"radius", NULL, rad};
        fr.scalar[1] = (mote_h5md_scalar){ev->dim == 3 ? "q6" : "psi6", NULL, ord};
        for (int a = 0; a < ev->dim; a++) {
            fr.edges[a] = ev->len[a];
            fr.periodic[a] = ev->periodic[a];
        }
        rc = how == 2   ? mote_vtk_particles(path, &fr, err)
             : how == 1 ? mote_h5md_append(path, &fr, err)
                        : mote_h5md_first(path, &fr, err);
    }
    free(buf);
    free(local);
    free(flag);
    return rc;
}

int mote_hs_snapshot(mote_hs *hs, const char *path, const char *origin, mote_err *err)
{
    if (!hs->has_system)
        return mote_fail(err, MOTE_EINVAL, "snapshot: no system");
    if (mote_path_is_h5md(path))
        return h5md_frame(hs, path, origin, 0, err);
    if (mote_path_is_vtk(path))
        return h5md_frame(hs, path, origin, 2, err);
    const frame_of_hs x = {hs, origin};
    return mote_frames_first(path, write_frame, &x, err);
}

/* A trajectory's first frame: its file written atomically (an earlier file is replaced only by
 * a complete frame). */
static int first_frame(mote_hs *hs, struct hs_dump *d, mote_err *err)
{
    int rc = mote_hs_snapshot(hs, d->path, d->origin, err);
    d->frames += !rc;
    return rc;
}

/* Append one frame (the core's growing file: cut back to its previous end on a failure). */
static int append_frame(mote_hs *hs, struct hs_dump *d, mote_err *err)
{
    const frame_of_hs x = {hs, d->origin};
    int rc = mote_path_is_h5md(d->path) ? h5md_frame(hs, d->path, d->origin, 1, err)
                                        : mote_frames_append(d->path, write_frame, &x, err);
    d->frames += !rc;
    return rc;
}

/* The next frame: appended to a trajectory, or the next file of a series (PREFIX_000000.xyz
 * on, written atomically; the prefix's folder made when missing). */
static int frame_out(mote_hs *hs, struct hs_dump *d, mote_err *err)
{
    if (!d->series)
        return d->frames ? append_frame(hs, d, err) : first_frame(hs, d, err);
    if (d->series == SERIES_STATE) {
        const int rc = mote_hs_write_state(hs, d->path, err);
        d->frames += !rc;
        return rc;
    }
    const int png = d->series == SERIES_PNG;
    char *p = mote_series_path(d->path, d->frames, 6, png                           ? ".png"
                                                  : d->series == SERIES_H5MD ? ".h5"
                                                  : d->series == SERIES_VTK  ? ".vtk"
                                                                             : ".xyz");
    if (!p)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", png ? "frames" : "snapshot");
    mote_make_dir_of(p);
    int rc = png ? hs_frame_png(hs, p, err) : mote_hs_snapshot(hs, p, d->origin, err);
    free(p);
    d->frames += !rc;
    return rc;
}

static void dump_free(struct hs_dump *d)
{
    if (!d)
        return;
    free(d->path);
    free(d->origin);
    free(d);
}

void mote_hs_dump_stop(mote_hs *hs)
{
    dump_free(hs->dump);
    hs->dump = NULL;
}

void mote_hs_snapshots_stop(mote_hs *hs)
{
    dump_free(hs->snaps);
    hs->snaps = NULL;
}

void mote_hs_frames_stop(mote_hs *hs)
{
    dump_free(hs->frames);
    hs->frames = NULL;
}

void mote_hs_checkpoint_stop(mote_hs *hs)
{
    dump_free(hs->ckpt);
    hs->ckpt = NULL;
}

static uint64_t dump_interval(const mote_hs *hs, const struct hs_dump *d)
{
    const uint64_t c = d->k * hs->ev.n / 2;
    return c ? c : 1;
}

int mote_hs_dump_start(mote_hs *hs, uint64_t k, const char *path, const char *origin,
                       mote_err *err)
{
    if (k < 1)
        return mote_fail(err, MOTE_EINVAL, "trajectory: K must be >= 1");
    return mote_hs_dump_start_on(hs, k, 0, path, origin, err);
}

/* A trajectory (series 0: path its file) or a series of snapshots (series 1: path the
 * prefix) on the schedule k or dt, its first frame written now. */
static struct hs_dump *dump_new(mote_hs *hs, const char *what, uint64_t k, double dt,
                                const char *path, const char *origin, int series,
                                uint64_t first, mote_err *err)
{
    if (!hs->has_system) {
        mote_fail(err, MOTE_EINVAL, "%s: no system", what);
        return NULL;
    }
    if ((k > 0) == (dt > 0) || !(dt >= 0)) {
        mote_fail(err, MOTE_EINVAL, "%s: give every=K or dt=T (> 0), one of them", what);
        return NULL;
    }
    struct hs_dump *d = calloc(1, sizeof *d);
    if (d) {
        d->path = strdup(path);
        d->origin = strdup(origin ? origin : "(library call)");
    }
    if (!d || !d->path || !d->origin) {
        dump_free(d);
        mote_fail(err, MOTE_ENOMEM, "%s: out of memory", what);
        return NULL;
    }
    d->k = k;
    d->series = series;
    d->frames = first;
    d->at = (mote_schedule){mote_ev_time(&hs->ev), dt, 1};
    if (frame_out(hs, d, err)) { /* the first frame, atomically */
        dump_free(d);
        return NULL;
    }
    d->next_at = k ? hs->ev.collisions + dump_interval(hs, d) : 0;
    return d;
}

int mote_hs_dump_start_on(mote_hs *hs, uint64_t k, double dt, const char *path,
                          const char *origin, mote_err *err)
{
    struct hs_dump *d = dump_new(hs, "trajectory", k, dt, path, origin, 0, 0, err);
    if (!d)
        return err->code;
    mote_hs_dump_stop(hs);
    hs->dump = d;
    return MOTE_OK;
}

int mote_hs_snapshots_start(mote_hs *hs, uint64_t k, double dt, const char *prefix,
                            const char *origin, mote_err *err)
{
    return mote_hs_snapshots_start_as(hs, k, dt, prefix, ".xyz", origin, err);
}

int mote_hs_snapshots_start_as(mote_hs *hs, uint64_t k, double dt, const char *prefix,
                               const char *ext, const char *origin, mote_err *err)
{
    /* the same prefix again continues the numbering */
    const uint64_t first = hs->snaps && !strcmp(hs->snaps->path, prefix) ? hs->snaps->frames : 0;
    const int series = !strcmp(ext, ".h5") ? SERIES_H5MD : !strcmp(ext, ".vtk") ? SERIES_VTK
                                                                                : SERIES_XYZ;
    struct hs_dump *d = dump_new(hs, "snapshot", k, dt, prefix, origin, series, first, err);
    if (!d)
        return err->code;
    mote_hs_snapshots_stop(hs);
    hs->snaps = d;
    return MOTE_OK;
}

int mote_hs_frames_start(mote_hs *hs, uint64_t k, double dt, const char *prefix,
                         const char *origin, mote_err *err)
{
    const uint64_t first =
        hs->frames && !strcmp(hs->frames->path, prefix) ? hs->frames->frames : 0;
    struct hs_dump *d = dump_new(hs, "frames", k, dt, prefix, origin, SERIES_PNG, first, err);
    if (!d)
        return err->code;
    mote_hs_frames_stop(hs);
    hs->frames = d;
    return MOTE_OK;
}

int mote_hs_checkpoint_start(mote_hs *hs, uint64_t k, const char *path, const char *origin,
                             mote_err *err)
{
    if (k < 1)
        return mote_fail(err, MOTE_EINVAL, "checkpoint: K must be >= 1");
    struct hs_dump *d = dump_new(hs, "checkpoint", k, 0, path, origin, SERIES_STATE, 0, err);
    if (!d)
        return err->code;
    mote_hs_checkpoint_stop(hs);
    hs->ckpt = d;
    return MOTE_OK;
}

uint64_t mote_hs_dump_frames(const mote_hs *hs) { return hs->dump ? hs->dump->frames : 0; }

/* A frame of a trajectory or a series, and the collision count of the next. */
static int fire_of(mote_hs *hs, struct hs_dump *d, mote_err *err)
{
    int rc = frame_out(hs, d, err);
    if (!rc && d->k)
        d->next_at = hs->ev.collisions + dump_interval(hs, d);
    return rc;
}
static int dump_fire(void *ctx, void *subject, mote_err *err)
{
    return fire_of(ctx, ((mote_hs *)ctx)->dump, err);
}
static int snaps_fire(void *ctx, void *subject, mote_err *err)
{
    return fire_of(ctx, ((mote_hs *)ctx)->snaps, err);
}
static int frames_fire(void *ctx, void *subject, mote_err *err)
{
    return fire_of(ctx, ((mote_hs *)ctx)->frames, err);
}
static int ckpt_fire(void *ctx, void *subject, mote_err *err)
{
    return fire_of(ctx, ((mote_hs *)ctx)->ckpt, err);
}

static void observer_of(mote_hs *hs, struct hs_dump *d,
                        int (*fire)(void *, void *, mote_err *), mote_observer *o)
{
    if (!d->k) { /* by time (a state loaded from another time: on from it) */
        const double now = mote_ev_time(&hs->ev);
        if (!(mote_schedule_next(&d->at) > now) || mote_schedule_next(&d->at) > now + d->at.dt)
            d->at = (mote_schedule){now, d->at.dt, 1};
        *o = (mote_observer){.at = &d->at, .ctx = hs, .fire = fire};
        return;
    }
    if (d->next_at <= hs->ev.collisions) /* a state loaded from another point of time */
        d->next_at = hs->ev.collisions + dump_interval(hs, d);
    *o = (mote_observer){.ctx = hs, .fire = fire, .every = dump_interval(hs, d),
                         .from = d->next_at};
}

size_t hs_dump_observer(mote_hs *hs, mote_observer *o)
{
    size_t n = 0;
    if (hs->dump)
        observer_of(hs, hs->dump, dump_fire, &o[n++]);
    if (hs->snaps)
        observer_of(hs, hs->snaps, snaps_fire, &o[n++]);
    if (hs->frames)
        observer_of(hs, hs->frames, frames_fire, &o[n++]);
    return n;
}

size_t hs_checkpoint_observer(mote_hs *hs, mote_observer *o)
{
    if (!hs->ckpt)
        return 0;
    observer_of(hs, hs->ckpt, ckpt_fire, o); /* (the last at its count: the others see the
                                                 engine as a run without it would) */
    return 1;
}
