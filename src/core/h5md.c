/* h5md.c: H5MD 1.1 files through Debian's libhdf5 (see h5md.h for the layout). */
#include "mote/h5md.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <hdf5.h>

int mote_path_is_h5md(const char *path)
{
    const char *dot = strrchr(path, '.');
    return dot && !strchr(dot, '/') && (!strcasecmp(dot, ".h5") || !strcasecmp(dot, ".h5md"));
}

/* ---- HDF5's errors: silenced while mote works, their innermost message kept -------------------- */

typedef struct {
    H5E_auto2_t fn;
    void *data;
} quiet;

static quiet quiet_on(void)
{
    quiet q = {NULL, NULL};
    H5Eget_auto2(H5E_DEFAULT, &q.fn, &q.data);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    return q;
}

static void quiet_off(quiet q) { H5Eset_auto2(H5E_DEFAULT, q.fn, q.data); }

static herr_t last_desc(unsigned n, const H5E_error2_t *e, void *arg)
{
    if (e->desc && *e->desc)
        snprintf(arg, 160, "%s", e->desc); /* (walked upward: the last one kept is the cause) */
    (void)n;
    return 0;
}

/* Record "PATH: WHAT (HDF5: DETAIL)". */
static int h5_fail(mote_err *err, const char *path, const char *what)
{
    char detail[160] = "";
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, last_desc, detail);
    H5Eclear2(H5E_DEFAULT);
    return mote_fail(err, MOTE_EIO, "%s: %s%s%s%s", path, what, *detail ? " (HDF5: " : "",
                     detail, *detail ? ")" : "");
}

/* ---- the elements of a frame --------------------------------------------------------------------- */

enum { K_DOUBLE, K_INT32, K_INT64 };

typedef struct {
    char name[40];      /* path under /particles/all: "position", "box/edges" */
    int kind;           /* K_DOUBLE, ... */
    int per_particle;   /* [F][N]... or [F]... */
    int width;          /* D, or 0 for one number */
    const void *data;
    char unit[64];      /* "" when none */
} element;

#define MAX_ELEMENTS (6 + MOTE_H5MD_SCALARS + MOTE_H5MD_VECTORS)

static int elements_of(const mote_h5md_frame *fr, element *e)
{
    int k = 0;
    const char *L = fr->length_unit, *T = fr->time_unit;
    e[k] = (element){"position", K_DOUBLE, 1, fr->dim, fr->pos, ""};
    if (L)
        snprintf(e[k].unit, sizeof e[k].unit, "%s", L);
    k++;
    if (fr->vel) {
        e[k] = (element){"velocity", K_DOUBLE, 1, fr->dim, fr->vel, ""};
        if (L && T)
            snprintf(e[k].unit, sizeof e[k].unit, "%s %s-1", L, T);
        k++;
    }
    if (fr->species)
        e[k++] = (element){"species", K_INT32, 1, 0, fr->species, ""};
    if (fr->id)
        e[k++] = (element){"id", K_INT64, 1, 0, fr->id, ""};
    for (int s = 0; s < fr->nscalar && s < MOTE_H5MD_SCALARS; s++) {
        e[k] = (element){"", K_DOUBLE, 1, 0, fr->scalar[s].v, ""};
        snprintf(e[k].name, sizeof e[k].name, "%s", fr->scalar[s].name);
        if (fr->scalar[s].unit)
            snprintf(e[k].unit, sizeof e[k].unit, "%s", fr->scalar[s].unit);
        k++;
    }
    for (int s = 0; s < fr->nvector && s < MOTE_H5MD_VECTORS; s++) {
        e[k] = (element){"", K_DOUBLE, 1, fr->dim, fr->vector[s].v, ""};
        snprintf(e[k].name, sizeof e[k].name, "%s", fr->vector[s].name);
        if (fr->vector[s].unit)
            snprintf(e[k].unit, sizeof e[k].unit, "%s", fr->vector[s].unit);
        k++;
    }
    if (fr->has_box) {
        e[k] = (element){"box/edges", K_DOUBLE, 0, fr->dim, fr->edges, ""};
        if (L)
            snprintf(e[k].unit, sizeof e[k].unit, "%s", L);
        k++;
    }
    return k;
}

static hid_t h5type(int kind)
{
    return kind == K_DOUBLE ? H5T_NATIVE_DOUBLE : kind == K_INT32 ? H5T_NATIVE_INT32
                                                                    : H5T_NATIVE_INT64;
}

/* ---- writing the layout ------------------------------------------------------------------------ */

static int attr_string(hid_t obj, const char *name, const char *value)
{
    hid_t t = H5Tcopy(H5T_C_S1);
    hid_t sp = H5Screate(H5S_SCALAR);
    int ok = t >= 0 && sp >= 0 && H5Tset_size(t, strlen(value) + 1) >= 0;
    hid_t a = ok ? H5Acreate2(obj, name, t, sp, H5P_DEFAULT, H5P_DEFAULT) : -1;
    ok = a >= 0 && H5Awrite(a, t, value) >= 0;
    if (a >= 0)
        H5Aclose(a);
    if (sp >= 0)
        H5Sclose(sp);
    if (t >= 0)
        H5Tclose(t);
    return ok ? 0 : -1;
}

/* An attribute of n fixed-length strings (as long as the longest). */
static int attr_strings(hid_t obj, const char *name, const char *const *v, int n)
{
    size_t len = 1;
    for (int k = 0; k < n; k++)
        len = strlen(v[k]) + 1 > len ? strlen(v[k]) + 1 : len;
    char *buf = calloc(n > 0 ? (size_t)n : 1, len);
    if (!buf)
        return -1;
    for (int k = 0; k < n; k++)
        memcpy(buf + (size_t)k * len, v[k], strlen(v[k]));
    hid_t t = H5Tcopy(H5T_C_S1);
    const hsize_t nn = (hsize_t)n;
    hid_t sp = H5Screate_simple(1, &nn, NULL);
    hid_t a = t >= 0 && sp >= 0 && H5Tset_size(t, len) >= 0
                  ? H5Acreate2(obj, name, t, sp, H5P_DEFAULT, H5P_DEFAULT)
                  : -1;
    int ok = a >= 0 && H5Awrite(a, t, buf) >= 0;
    if (a >= 0)
        H5Aclose(a);
    if (sp >= 0)
        H5Sclose(sp);
    if (t >= 0)
        H5Tclose(t);
    free(buf);
    return ok ? 0 : -1;
}

static int attr_ints(hid_t obj, const char *name, const int32_t *v, hsize_t n)
{
    hid_t sp = n ? H5Screate_simple(1, &n, NULL) : H5Screate(H5S_SCALAR);
    hid_t a = sp >= 0 ? H5Acreate2(obj, name, H5T_STD_I32LE, sp, H5P_DEFAULT, H5P_DEFAULT) : -1;
    int ok = a >= 0 && H5Awrite(a, H5T_NATIVE_INT32, v) >= 0;
    if (a >= 0)
        H5Aclose(a);
    if (sp >= 0)
        H5Sclose(sp);
    return ok ? 0 : -1;
}

/* A group with no object times (the file depends only on its content). */
static hid_t group_new(hid_t parent, const char *name)
{
    hid_t gcpl = H5Pcreate(H5P_GROUP_CREATE);
    if (gcpl < 0)
        return -1;
    H5Pset_obj_track_times(gcpl, 0);
    hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
    if (lcpl >= 0)
        H5Pset_create_intermediate_group(lcpl, 1);
    hid_t g = lcpl >= 0 ? H5Gcreate2(parent, name, lcpl, gcpl, H5P_DEFAULT) : -1;
    if (lcpl >= 0)
        H5Pclose(lcpl);
    H5Pclose(gcpl);
    return g;
}

/* Particles per chunk: a chunk of one frame is at most ~512 KiB. */
static hsize_t chunk_particles(size_t n, int width)
{
    const hsize_t most = (hsize_t)(65536 / (width ? width : 1));
    const hsize_t least = 256 < most ? 256 : most; /* (room for a count that grows) */
    return n < least ? least : n > most ? most : (hsize_t)n;
}

/* An empty extendible dataset of rank 1-3: frames (unlimited), then particles (unlimited) when
 * per-particle, then the element's width (fixed) when it has one; chunked one frame at a time,
 * compressed (shuffle + deflate), filled with NaN or -1 where nothing is written. */
static hid_t dataset_new(hid_t parent, const char *name, int kind, int per_particle, int width,
                         size_t n)
{
    hsize_t dims[3] = {0, 0, 0}, maxd[3], chunk[3];
    int rank = 0;
    maxd[rank] = H5S_UNLIMITED;
    chunk[rank++] = 1;
    if (per_particle) {
        maxd[rank] = H5S_UNLIMITED;
        chunk[rank++] = chunk_particles(n, width);
    }
    if (width) {
        dims[rank] = maxd[rank] = chunk[rank] = (hsize_t)width;
        rank++;
    }
    hid_t sp = H5Screate_simple(rank, dims, maxd);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    hid_t d = -1;
    if (sp >= 0 && dcpl >= 0 && H5Pset_chunk(dcpl, rank, chunk) >= 0) {
        H5Pset_obj_track_times(dcpl, 0);
        const double nan = NAN;
        const int32_t m1 = -1;
        const int64_t m1l = -1;
        H5Pset_fill_value(dcpl, h5type(kind), kind == K_DOUBLE ? (const void *)&nan
                                              : kind == K_INT32 ? (const void *)&m1
                                                                : (const void *)&m1l);
        H5Pset_fill_time(dcpl, H5D_FILL_TIME_IFSET);
        H5Pset_shuffle(dcpl);
        H5Pset_deflate(dcpl, 4);
        const hid_t ft = kind == K_DOUBLE ? H5T_IEEE_F64LE : kind == K_INT32 ? H5T_STD_I32LE
                                                                             : H5T_STD_I64LE;
        d = H5Dcreate2(parent, name, ft, sp, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    }
    if (dcpl >= 0)
        H5Pclose(dcpl);
    if (sp >= 0)
        H5Sclose(sp);
    return d;
}

/* Element e's group and its value; its step and time are links to position's (the first
 * element, whose group layout_new made with them). */
static int element_new(hid_t all, const element *e, size_t n)
{
    const int first = !strcmp(e->name, "position");
    hid_t g = first ? H5Gopen2(all, e->name, H5P_DEFAULT) : group_new(all, e->name);
    if (g < 0)
        return -1;
    hid_t d = dataset_new(g, "value", e->kind, e->per_particle, e->width, n);
    int ok = d >= 0 && (!*e->unit || attr_string(d, "unit", e->unit) == 0);
    if (d >= 0)
        H5Dclose(d);
    if (ok && !first)
        ok = H5Lcreate_hard(all, "position/step", g, "step", H5P_DEFAULT, H5P_DEFAULT) >= 0 &&
             H5Lcreate_hard(all, "position/time", g, "time", H5P_DEFAULT, H5P_DEFAULT) >= 0;
    H5Gclose(g);
    return ok ? 0 : -1;
}

static int layout_new(hid_t file, const mote_h5md_frame *fr, const element *e, int ne)
{
    int ok = 1;
    hid_t h = group_new(file, "h5md");
    const int32_t version[2] = {1, 1};
    ok = h >= 0 && attr_ints(h, "version", version, 2) == 0;
    hid_t g = ok ? group_new(h, "author") : -1;
    const char *user = getenv("USER");
    ok = g >= 0 && attr_string(g, "name", user && *user ? user : "unknown") == 0;
    if (g >= 0)
        H5Gclose(g);
    g = ok ? group_new(h, "creator") : -1;
    ok = g >= 0 && attr_string(g, "name", "mote") == 0 &&
         attr_string(g, "version", MOTE_VERSION) == 0;
    if (g >= 0)
        H5Gclose(g);
    if (ok && fr->length_unit) {
        g = group_new(h, "modules/units");
        const int32_t uv[2] = {1, 0};
        ok = g >= 0 && attr_ints(g, "version", uv, 2) == 0 && attr_string(g, "system", "SI") == 0;
        if (g >= 0)
            H5Gclose(g);
    }
    if (h >= 0)
        H5Gclose(h);
    g = ok ? group_new(file, "parameters/mote") : -1;
    ok = g >= 0 && attr_string(g, "model", fr->model) == 0 &&
         attr_string(g, "command", fr->origin ? fr->origin : "(library call)") == 0;
    if (ok) {
        hid_t sp = H5Screate(H5S_SCALAR);
        hid_t a = sp >= 0 ? H5Acreate2(g, "seed", H5T_STD_U64LE, sp, H5P_DEFAULT, H5P_DEFAULT) : -1;
        ok = a >= 0 && H5Awrite(a, H5T_NATIVE_UINT64, &fr->seed) >= 0;
        if (a >= 0)
            H5Aclose(a);
        if (sp >= 0)
            H5Sclose(sp);
    }
    if (g >= 0)
        H5Gclose(g);
    hid_t all = ok ? group_new(file, "particles/all") : -1;
    g = all >= 0 ? group_new(all, "box") : -1;
    const int32_t dim = fr->dim;
    ok = g >= 0 && attr_ints(g, "dimension", &dim, 0) == 0;
    const char *bound[3];
    for (int a = 0; a < 3; a++)
        bound[a] = fr->has_box && fr->periodic[a] ? "periodic" : "none";
    ok = ok && attr_strings(g, "boundary", bound, fr->dim) == 0;
    if (g >= 0)
        H5Gclose(g);
    /* position's step and time first: the other elements link to them */
    hid_t pg = ok ? group_new(all, "position") : -1;
    hid_t st = pg >= 0 ? dataset_new(pg, "step", K_INT64, 0, 0, 0) : -1;
    hid_t tm = st >= 0 ? dataset_new(pg, "time", K_DOUBLE, 0, 0, 0) : -1;
    ok = tm >= 0 && (!fr->time_unit || attr_string(tm, "unit", fr->time_unit) == 0);
    if (tm >= 0)
        H5Dclose(tm);
    if (st >= 0)
        H5Dclose(st);
    if (pg >= 0)
        H5Gclose(pg);
    for (int k = 0; ok && k < ne; k++)
        ok = element_new(all, &e[k], fr->n) == 0;
    if (ok && fr->species && fr->species_names && fr->nspecies_names > 0) {
        g = H5Gopen2(all, "species", H5P_DEFAULT);
        ok = g >= 0 && attr_strings(g, "names", fr->species_names, fr->nspecies_names) == 0;
        if (g >= 0)
            H5Gclose(g);
    }
    if (all >= 0)
        H5Gclose(all);
    return ok ? 0 : -1;
}

/* ---- appending a frame --------------------------------------------------------------------------- */

/* Grow dataset `name` (under loc) to frames F+1 (and n particles when per-particle) and write
 * the frame's rows; old[] gets its dimensions before, for a cut back. */
static int dataset_append(hid_t loc, const char *name, int kind, int per_particle, int width,
                          const void *data, size_t n, hsize_t F, hsize_t old[3])
{
    hid_t d = H5Dopen2(loc, name, H5P_DEFAULT);
    if (d < 0)
        return -1;
    hid_t fs = H5Dget_space(d);
    const int rank = fs >= 0 ? H5Sget_simple_extent_ndims(fs) : -1;
    const int want = 1 + (per_particle != 0) + (width > 0);
    int ok = rank == want && H5Sget_simple_extent_dims(fs, old, NULL) == rank &&
             (!width || old[rank - 1] == (hsize_t)width) && old[0] == F;
    if (fs >= 0)
        H5Sclose(fs);
    hsize_t dims[3] = {F + 1, 0, 0}, start[3] = {F, 0, 0}, count[3] = {1, 0, 0};
    if (ok) {
        for (int r = 1; r < rank; r++)
            dims[r] = old[r];
        if (per_particle) {
            if (dims[1] < n)
                dims[1] = n;
            count[1] = n;
        }
        if (width)
            count[rank - 1] = (hsize_t)width;
        ok = H5Dset_extent(d, dims) >= 0;
    }
    const int grown = ok;
    if (ok && !(per_particle && n == 0)) {
        fs = H5Dget_space(d);
        hid_t ms = H5Screate_simple(rank, count, NULL);
        ok = fs >= 0 && ms >= 0 &&
             H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL) >= 0 &&
             H5Dwrite(d, h5type(kind), ms, fs, H5P_DEFAULT, data) >= 0;
        if (ms >= 0)
            H5Sclose(ms);
        if (fs >= 0)
            H5Sclose(fs);
    }
    if (grown && !ok)
        H5Dset_extent(d, old);
    H5Dclose(d);
    return ok ? 0 : -1;
}

/* The frame at the end of the open file; on a failure every dataset is cut back to its size
 * before. */
static int frame_append(hid_t file, const mote_h5md_frame *fr, const element *e, int ne)
{
    hid_t all = H5Gopen2(file, "particles/all", H5P_DEFAULT);
    if (all < 0)
        return -1;
    hsize_t F = 0, old[MAX_ELEMENTS + 2][3];
    int done = 0, ok = 1;
    hid_t st = H5Dopen2(all, "position/step", H5P_DEFAULT);
    hid_t sp = st >= 0 ? H5Dget_space(st) : -1;
    ok = sp >= 0 && H5Sget_simple_extent_ndims(sp) == 1 && H5Sget_simple_extent_dims(sp, &F, NULL) == 1;
    if (sp >= 0)
        H5Sclose(sp);
    if (st >= 0)
        H5Dclose(st);
    /* the datasets in order: position's step and time, then each element's value */
    const int nd = 2 + ne;
    char name[MAX_ELEMENTS + 2][64];
    snprintf(name[0], sizeof name[0], "position/step");
    snprintf(name[1], sizeof name[1], "position/time");
    for (int k = 0; k < ne; k++)
        snprintf(name[2 + k], sizeof name[2 + k], "%s/value", e[k].name);
    const int64_t step = fr->step;
    for (int k = 0; ok && k < nd; k++) {
        const element *x = k >= 2 ? &e[k - 2] : NULL;
        ok = dataset_append(all, name[k], x ? x->kind : k ? K_DOUBLE : K_INT64,
                            x && x->per_particle, x ? x->width : 0,
                            x ? x->data : k ? (const void *)&fr->time : (const void *)&step,
                            fr->n, F, old[k]) == 0;
        done += ok;
    }
    for (int k = 0; !ok && k < done; k++) { /* cut back what grew */
        hid_t d = H5Dopen2(all, name[k], H5P_DEFAULT);
        if (d >= 0) {
            H5Dset_extent(d, old[k]);
            H5Dclose(d);
        }
    }
    H5Gclose(all);
    return ok ? 0 : -1;
}

/* ---- the two entry points ------------------------------------------------------------------------- */

static int frame_bad(const char *path, const mote_h5md_frame *fr, mote_err *err)
{
    if (fr->dim != 2 && fr->dim != 3)
        return mote_fail(err, MOTE_EINVAL, "%s: internal: an H5MD frame of dimension %d", path,
                         fr->dim);
    if (fr->n && !fr->pos)
        return mote_fail(err, MOTE_EINVAL, "%s: internal: an H5MD frame without positions",
                         path);
    return MOTE_OK;
}

int mote_h5md_first(const char *path, const mote_h5md_frame *fr, mote_err *err)
{
    if (frame_bad(path, fr, err))
        return err->code;
    element e[MAX_ELEMENTS];
    const int ne = elements_of(fr, e);
    quiet q = quiet_on();
    /* the whole file in memory (HDF5's core driver), then written atomically */
    hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
    int ok = fapl >= 0 && fcpl >= 0 && H5Pset_fapl_core(fapl, (size_t)1 << 20, 0) >= 0;
    if (ok)
        H5Pset_obj_track_times(fcpl, 0);
    hid_t f = ok ? H5Fcreate(path, H5F_ACC_TRUNC, fcpl, fapl) : -1;
    ok = f >= 0 && layout_new(f, fr, e, ne) == 0 && frame_append(f, fr, e, ne) == 0 &&
         H5Fflush(f, H5F_SCOPE_GLOBAL) >= 0;
    void *image = NULL;
    ssize_t size = ok ? H5Fget_file_image(f, NULL, 0) : -1;
    ok = size > 0 && (image = malloc((size_t)size)) != NULL &&
         H5Fget_file_image(f, image, (size_t)size) == size;
    int rc = MOTE_OK;
    if (!ok)
        rc = !image && size > 0 ? mote_fail(err, MOTE_ENOMEM, "%s: out of memory for the "
                                                              "H5MD file (%zd bytes)",
                                            path, size)
                                : h5_fail(err, path, "cannot make the H5MD file");
    if (f >= 0)
        H5Fclose(f);
    if (fcpl >= 0)
        H5Pclose(fcpl);
    if (fapl >= 0)
        H5Pclose(fapl);
    quiet_off(q);
    if (!rc) {
        mote_afile af;
        rc = mote_afile_open(&af, path, err);
        if (!rc) {
            fwrite(image, 1, (size_t)size, af.f);
            rc = mote_afile_commit(&af, err);
        }
    }
    free(image);
    return rc;
}

/* Room on the disk for one more frame before HDF5 touches the file: a write that fails half
 * way (disk full, a file size limit) would leave HDF5's records pointing past the file's end,
 * so the space is taken first (posix_fallocate; HDF5 gives back what it did not use when it
 * closes the file, truncating it to its end). need: the frame's numbers uncompressed, with
 * room for the chunks' and the trees' records. */
static int reserve(const char *path, const element *e, int ne, size_t n, mote_err *err)
{
    size_t need = 256 * 1024;
    for (int k = 0; k < ne; k++)
        need += (e[k].per_particle ? (n + 256) : 1) * (size_t)(e[k].width ? e[k].width : 1) * 8;
    need += need / 16;
    int fd = open(path, O_WRONLY | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0) {
        const int e2 = errno;
        if (fd >= 0)
            close(fd);
        return mote_fail(err, MOTE_EIO, "%s: cannot open the H5MD trajectory to add a frame: %s",
                         path, strerror(e2));
    }
    const int rc = posix_fallocate(fd, st.st_size, (off_t)need);
    if (rc)
        (void)!ftruncate(fd, st.st_size); /* (whatever was taken, given back) */
    close(fd);
    if (rc)
        return mote_fail(err, MOTE_EIO, "%s: no room for another frame (%zu bytes): %s; the "
                         "file keeps the frames before", path, need, strerror(rc));
    return MOTE_OK;
}

int mote_h5md_append(const char *path, const mote_h5md_frame *fr, mote_err *err)
{
    if (frame_bad(path, fr, err))
        return err->code;
    element e[MAX_ELEMENTS];
    const int ne = elements_of(fr, e);
    if (reserve(path, e, ne, fr->n, err))
        return err->code;
    quiet q = quiet_on();
    int rc = MOTE_OK;
    hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    if (f < 0)
        rc = h5_fail(err, path, "cannot open the H5MD trajectory to add a frame");
    else if (frame_append(f, fr, e, ne) != 0)
        rc = h5_fail(err, path, "cannot add a frame to the H5MD trajectory; it keeps the frames "
                                "before");
    if (f >= 0 && H5Fclose(f) < 0 && !rc)
        rc = h5_fail(err, path, "cannot close the H5MD trajectory");
    quiet_off(q);
    return rc;
}
