/* outputs.c: the mixing box's output commands: `monitor` (the mixing curve, `record`),
 * `density_y`, `snapshot` (now, or a series), `frames`, `trajectory`, their stops and `movie`;
 * each an observer of the core's run loop, kept across runs. */
#include "model.h"
#include "mote/h5md.h"
#include "mote/vtk.h"
#include "mote/loop.h"
#include "mote/render.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* ---- measurements and pictures --------------------------------------------------------------- */

int mb_check_record(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    int rc = mb_need_placed(m, c, err);
    if (!rc)
        rc = mote_call_check_every_dt(c, 1, err);
    if (!rc)
        m->d_record_dt = mote_call_opt_r(c, "dt", 0);
    return rc;
}
int mb_run_record(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    mb_record_free(&m->rec);
    m->rec.origin = mote_call_origin(c);
    if (!m->rec.origin)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", c->name);
    m->rec.dt = mote_call_opt_r(c, "dt", 0);
    m->rec.every = m->rec.dt > 0 ? 0 : (uint64_t)mote_call_opt(c, "every")->i;
    /* the first row now, into FILE.partial, and into FILE when there is none yet: an earlier
     * complete FILE is replaced only by the complete file a run writes when it ends */
    int rc = mb_record_start(&m->rec, &m->sys, mote_call_opt(c, "file")->path,
                             mote_call_word(c, "format", MOTE_AS_NAME), err);
    if (rc) {
        mb_record_free(&m->rec);
        return rc;
    }
    m->rec.active = 1;
    m->rec_s = mote_call_observer(c, &m->rec_at, m->sys.time, m->sys.collisions, 1, &m->rec,
                                  mb_record_observe);
    if (m->log && m->rec.every)
        fprintf(m->log, "%s: every %llu collisions into %s\n", c->name,
                (unsigned long long)m->rec.every, m->rec.out.path);
    else if (m->log)
        fprintf(m->log, "%s: every %g s into %s\n", c->name, m->rec.dt, m->rec.out.path);
    return MOTE_OK;
}

int mb_check_density(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    int rc = mb_need_placed(m, c, err);
    if (!rc)
        m->d_density_dt = mote_call_opt(c, "dt")->r;
    return rc;
}
int mb_run_density(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    mb_density *d = &m->dens;
    mb_density_free(d);
    d->path = strdup(mote_call_opt(c, "file")->path);
    d->origin = mote_call_origin(c);
    d->nbins = mote_call_opt(c, "bins")->i;
    d->count[0] = calloc((size_t)d->nbins, sizeof(double));
    d->count[1] = calloc((size_t)d->nbins, sizeof(double));
    if (!d->path || !d->origin || !d->count[0] || !d->count[1]) {
        mb_density_free(d);
        return mote_fail(err, MOTE_ENOMEM, "density_y: out of memory");
    }
    d->dt = mote_call_opt(c, "dt")->r;
    d->y0 = m->sys.p.x_b;
    d->h = (m->sys.p.x_t - m->sys.p.x_b) / (double)d->nbins;
    int rc = mb_density_sample(d, &m->sys, err);
    if (!rc)
        rc = mb_density_write(d, &m->sys, err);
    if (rc) {
        mb_density_free(d);
        return rc;
    }
    d->active = 1;
    m->dens_at = (mote_schedule){m->sys.time, d->dt, 1};
    m->dens_s = (mote_observer){.at = &m->dens_at, .ctx = d,
                               .fire = mb_density_sample};
    if (m->log)
        fprintf(m->log, "density_y: %lld bins every %g s into %s\n", (long long)d->nbins, d->dt,
                d->path);
    return MOTE_OK;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n > k && strcmp(s + n - k, suffix) == 0;
}

/* `snapshot file=FILE` (.png or .xyz, now) or `snapshot every=K|dt=T prefix=P` (extended XYZ
 * now and on the schedule, P_000000.xyz on) */
int mb_check_snapshot(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    int rc = mb_need_placed(m, c, err);
    if (rc)
        return rc;
    const mote_arg *file = mote_call_opt(c, "file"), *prefix = mote_call_opt(c, "prefix");
    const int sched = mote_call_opt(c, "every") || mote_call_opt(c, "dt");
    if (!file == !(sched || prefix))
        return mote_call_fail(err, c, file ? mote_call_opt_index(c, "file") : -1, MOTE_EINVAL,
                              "snapshot: give file=FILE (one now) or every=K or dt=T with "
                              "prefix=P (a series), %s", file ? "not both" : "one of them");
    if (!file) {
        if (!prefix)
            return mote_call_fail(err, c, -1, MOTE_EINVAL, "snapshot: a series needs prefix=P "
                                  "(files P_000000.xyz, ...)");
        if ((rc = mote_call_check_every_dt(c, 1, err)))
            return rc;
        m->d_snaps_dt = mote_call_opt_r(c, "dt", 0);
        const int fmt = mote_call_word(c, "format", MB_FORMAT_XYZ);
        return mote_outputs_note_series(&c->ctx->outputs, c, mote_call_opt_index(c, "prefix"),
                                        prefix->path,
                                        fmt == MB_FORMAT_H5MD  ? ".h5"
                                        : fmt == MB_FORMAT_VTK ? ".vtk"
                                                               : ".xyz",
                                        "snapshot", 0, err);
    }
    const char *f = file->text;
    const int png = ends_with(f, ".png");
    if (png && mote_call_opt(c, "format"))
        return mote_call_fail(err, c, mote_call_opt_index(c, "format"), MOTE_EINVAL,
                              "snapshot: format= is for the particle files (.xyz, .h5, .vtk); a "
                              ".png is a picture");
    const int vtk = png ? 0 : mote_call_vtk(c, "file", MB_FORMAT_VTK, err);
    if (vtk)
        return vtk < 0 ? err->code : MOTE_OK;
    const int h5md = mote_call_h5md(c, "file", MB_FORMAT_H5MD, err);
    if (h5md < 0)
        return err->code;
    if (!png && !ends_with(f, ".xyz") && !h5md)
        return mote_call_fail(err, c, mote_call_opt_index(c, "file"), MOTE_EINVAL,
                              "snapshot: FILE must end in .png (a picture), .xyz (extended "
                              "XYZ), .h5 (H5MD) or .vtk (VTK), found '%s'",
                              f);
    return MOTE_OK;
}

/* Start the series of `frames` (xyz 0) or of `snapshot every=|dt=` (xyz 1): the first now. */
static int start_series(mb_model *m, const mote_call *c, mb_frames *fr, int xyz,
                        mote_observer *obs, mote_schedule *at, mote_err *err)
{
    char *prefix = strdup(mote_call_opt(c, "prefix")->path);
    char *origin = xyz ? mote_call_origin(c) : NULL;
    if (!prefix || (xyz && !origin)) {
        free(prefix);
        free(origin);
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", c->name);
    }
    if (!fr->prefix || strcmp(fr->prefix, prefix) != 0) { /* (the same prefix continues) */
        free(fr->prefix);
        fr->prefix = prefix;
        fr->next_index = 0;
    } else {
        free(prefix);
    }
    free(fr->origin);
    fr->origin = origin;
    fr->xyz = xyz;
    fr->dt = mote_call_opt_r(c, "dt", 0);
    fr->every = fr->dt > 0 ? 0 : (uint64_t)mote_call_opt(c, "every")->i;
    int rc = mb_frames_sample(fr, &m->sys, err);
    if (rc)
        return rc;
    fr->active = 1;
    *obs = mote_call_observer(c, at, m->sys.time, m->sys.collisions, 1, fr, mb_frames_sample);
    const char *ext = xyz == MB_SERIES_H5MD  ? ".h5"
                      : xyz == MB_SERIES_VTK ? ".vtk"
                      : xyz                  ? ".xyz"
                                             : ".png";
    if (m->log && fr->every)
        fprintf(m->log, "%s: every %llu collisions as %s%sNNNNNN%s from %06llu\n", c->name,
                (unsigned long long)fr->every, fr->prefix, mote_series_sep(fr->prefix), ext,
                (unsigned long long)(fr->next_index - 1));
    else if (m->log)
        fprintf(m->log, "%s: every %g s as %s%sNNNNNN%s from %06llu\n", c->name, fr->dt,
                fr->prefix, mote_series_sep(fr->prefix), ext,
                (unsigned long long)(fr->next_index - 1));
    return MOTE_OK;
}

int mb_run_snapshot(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    const mote_arg *file = mote_call_opt(c, "file");
    if (!file)
        return start_series(m, c, &m->snaps,
                            mote_call_word(c, "format", MB_FORMAT_XYZ) == MB_FORMAT_H5MD
                                ? MB_SERIES_H5MD
                            : mote_call_word(c, "format", MB_FORMAT_XYZ) == MB_FORMAT_VTK
                                ? MB_SERIES_VTK
                                : MB_SERIES_XYZ,
                            &m->snaps_s, &m->snaps_at, err);
    const char *path = file->path;
    char *origin = mote_call_origin(c);
    int rc;
    if (!origin)
        rc = mote_fail(err, MOTE_ENOMEM, "snapshot: out of memory");
    else if (ends_with(path, ".xyz") || mote_path_is_h5md(path) || mote_path_is_vtk(path))
        rc = mb_snapshot_xyz(&m->sys, path, origin, err);
    else
        rc = mb_snapshot_png(&m->sys, path, err);
    if (!rc && m->log)
        fprintf(m->log, "snapshot: wrote %s\n", path);
    free(origin);
    return rc;
}

int mb_check_frames(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    int rc = mb_need_placed(m, c, err);
    if (rc)
        return rc;
    const char *prefix = mote_call_opt(c, "prefix")->path;
    const int pi = mote_call_opt_index(c, "prefix");
    rc = mote_call_check_every_dt(c, 1, err);
    if (!rc)
        rc = mote_outputs_note_series(&c->ctx->outputs, c, pi, prefix, ".png", "frames", 0, err);
    if (!rc)
        m->d_frames_dt = mote_call_opt_r(c, "dt", 0);
    return rc;
}
int mb_run_frames(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    return start_series(m, c, &m->frames, 0, &m->frames_s, &m->frames_at, err);
}

/* `trajectory every=K|dt=T file=FILE.xyz`: a frame now and on the schedule, appended */
int mb_check_trajectory(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    int rc = mb_need_placed(m, c, err);
    if (!rc)
        rc = mote_call_check_every_dt(c, 1, err);
    if (!rc && mote_call_vtk(c, "file", -1, err) < 0)
        rc = err->code;
    const int h5md = rc ? 0 : mote_call_h5md(c, "file", MB_FORMAT_H5MD, err);
    if (h5md < 0)
        rc = err->code;
    if (!rc && !h5md && !ends_with(mote_call_opt(c, "file")->text, ".xyz"))
        rc = mote_call_fail(err, c, mote_call_opt_index(c, "file"), MOTE_EINVAL,
                            "trajectory: FILE must end in .xyz (extended XYZ) or .h5 (H5MD), "
                            "found '%s'",
                            mote_call_opt(c, "file")->text);
    if (!rc)
        m->d_traj_dt = mote_call_opt_r(c, "dt", 0);
    return rc;
}
int mb_run_trajectory(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    mb_trajectory *t = &m->traj;
    free(t->path);
    free(t->origin);
    t->active = 0;
    t->path = strdup(mote_call_opt(c, "file")->path);
    t->origin = mote_call_origin(c);
    if (!t->path || !t->origin)
        return mote_fail(err, MOTE_ENOMEM, "trajectory: out of memory");
    int rc = mb_snapshot_xyz(&m->sys, t->path, t->origin, err); /* the first frame */
    if (rc)
        return rc;
    t->active = 1;
    m->traj_s = mote_call_observer(c, &m->traj_at, m->sys.time, m->sys.collisions, 1, t,
                                   mb_trajectory_fire);
    if (m->log)
        fprintf(m->log, "trajectory: frame 0 in %s\n", t->path);
    return MOTE_OK;
}
/* `checkpoint every=K file=FILE`: the state as save writes it, now and every K disk-disk
 * collisions of the following runs (at a stop of the run loop the arrays, the counters and the
 * last collision times are the engine's: the same numbers a run ending there leaves). */
static int mb_checkpoint_fire(void *ctx, void *subject, mote_err *err)
{
    mb_model *m = ctx;
    return mb_save(&m->sys, &m->p, m->ckpt.path, err);
}
int mb_check_checkpoint(void *vm, const mote_call *c, mote_err *err)
{
    return mb_need_placed(vm, c, err);
}
int mb_run_checkpoint(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    char *p = strdup(mote_call_opt(c, "file")->path);
    if (!p)
        return mote_fail(err, MOTE_ENOMEM, "checkpoint: out of memory");
    free(m->ckpt.path);
    m->ckpt.path = p;
    m->ckpt.active = 0;
    int rc = mb_save(&m->sys, &m->p, p, err); /* the first, now */
    if (rc)
        return rc;
    m->ckpt.active = 1;
    m->ckpt_s = mote_call_observer(c, &m->ckpt_at, m->sys.time, m->sys.collisions, 1, m,
                                   mb_checkpoint_fire);
    if (m->log)
        fprintf(m->log, "checkpoint: the state in %s now and every %lld collisions\n", p,
                (long long)mote_call_opt(c, "every")->i);
    return MOTE_OK;
}
int mb_run_checkpoint_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((mb_model *)vm)->ckpt.active = 0;
    return MOTE_OK;
}
int mb_check_record_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((mb_model *)vm)->d_record_dt = 0;
    return MOTE_OK;
}
int mb_run_record_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((mb_model *)vm)->rec.active = 0; /* (FILE was written whole when the last run ended) */
    return MOTE_OK;
}
int mb_check_trajectory_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((mb_model *)vm)->d_traj_dt = 0;
    return MOTE_OK;
}
int mb_run_trajectory_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((mb_model *)vm)->traj.active = 0;
    return MOTE_OK;
}

int mb_check_snapshot_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((mb_model *)vm)->d_snaps_dt = 0;
    return MOTE_OK;
}
int mb_run_snapshot_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((mb_model *)vm)->snaps.active = 0;
    return MOTE_OK;
}

int mb_check_frames_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((mb_model *)vm)->d_frames_dt = 0;
    return MOTE_OK;
}
int mb_run_frames_stop(void *vm, const mote_call *c, mote_err *err)
{
    ((mb_model *)vm)->frames.active = 0;
    return MOTE_OK;
}

static int frames_of(const char *kind) { return kind && strcmp(kind, "frames") == 0; }

int mb_check_movie(void *vm, const mote_call *c, mote_err *err)
{
    const char *prefix = mote_call_opt(c, "prefix")->path;
    const int pi = mote_call_opt_index(c, "prefix");
    char *first = mb_frame_name(prefix, 0);
    int rc = MOTE_OK;
    struct stat st;
    if (!first)
        rc = mote_call_fail(err, c, pi, MOTE_ENOMEM, "out of memory");
    else if (!frames_of(mote_outputs_find(&c->ctx->outputs, prefix)) && stat(first, &st) != 0)
        rc = mote_call_fail(err, c, pi, MOTE_EINVAL,
                            "movie: no earlier 'frames' writes '%s' and it does not exist", first);
    free(first);
    return rc;
}
int mb_run_movie(void *vm, const mote_call *c, mote_err *err)
{
    mb_model *m = vm;
    const char *out = mote_call_opt(c, "file")->path;
    int ran = 0;
    int rc = mote_movie(mote_call_opt(c, "prefix")->path, mote_call_opt(c, "fps")->i, out,
                        m->ctx ? m->ctx->diag : NULL, &ran, err);
    if (!rc && ran && m->log)
        fprintf(m->log, "movie: wrote %s\n", out);
    return rc;
}

