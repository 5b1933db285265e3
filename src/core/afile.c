/* afile.c: atomic output files. Data is written to a temporary file in the target's own directory
 * (so rename is atomic on POSIX file systems), flushed and synced, then renamed over the target.
 * Any failure removes the temporary file: an earlier result is never destroyed. Where the file
 * system allows (Linux's O_TMPFILE), the temporary file has no name until the commit links it
 * and renames it over the target at once, so a run killed while writing leaves nothing behind. A
 * data file (datafile.h) committed under a name ending in .csv is converted to RFC 4180 CSV on
 * the way (mote_datafile_csv). */
#define _GNU_SOURCE /* O_TMPFILE */
#include "mote/core.h"
#include "mote/datafile.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char *dup_str(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d)
        memcpy(d, s, n);
    return d;
}

int mote_make_dir_of(const char *path)
{
    char buf[4096];
    const size_t n = strlen(path);
    if (n >= sizeof buf)
        return 0; /* (the open below names the problem) */
    memcpy(buf, path, n + 1);
    for (size_t i = 1; i < n; i++) {
        if (buf[i] != '/' || buf[i - 1] == '/')
            continue;
        buf[i] = '\0';
        struct stat st;
        if (stat(buf, &st) != 0 && mkdir(buf, 0777) != 0 && errno != EEXIST)
            return errno;
        buf[i] = '/';
    }
    return 0;
}

/* A temporary file for path's data, in its folder: unnamed (O_TMPFILE; *name then
 * /proc/self/fd/N, to read it back) where the file system has them, else path.tmp.XXXXXX. The
 * descriptor, or -1 with errno set; *name malloc'ed. */
static int open_temp(const char *path, char **name, int *anon, int mode)
{
    const size_t n = strlen(path) + 32;
    *name = malloc(n);
    if (!*name) {
        errno = ENOMEM;
        return -1;
    }
#ifdef O_TMPFILE
    const char *slash = strrchr(path, '/');
    char *dir = slash ? malloc((size_t)(slash - path) + 2) : NULL;
    if (dir) {
        memcpy(dir, path, (size_t)(slash - path) + (slash == path));
        dir[(size_t)(slash - path) + (slash == path)] = '\0';
    }
    int fd = slash && !dir ? -1 : open(dir ? dir : ".", O_TMPFILE | mode | O_CLOEXEC, 0644);
    free(dir);
    if (fd >= 0) {
        snprintf(*name, n, "/proc/self/fd/%d", fd);
        if (access(*name, R_OK) == 0) { /* (read back for the CSV form, linked at commit) */
            *anon = 1;
            return fd;
        }
        close(fd);
    }
#endif
    *anon = 0;
    snprintf(*name, n, "%s.tmp.XXXXXX", path);
    int fd2 = mkstemp(*name);
    if (fd2 >= 0)
        fchmod(fd2, 0644);
    return fd2;
}

/* The temporary file's data under a name of its own beside path (an unnamed one linked to a
 * fresh name; a named one has it), for the rename; 0 or an errno value. */
static int name_temp(mote_afile *af)
{
    if (!af->anon)
        return 0;
    const size_t n = strlen(af->path) + 32;
    char *named = malloc(n);
    if (!named)
        return ENOMEM;
    for (int tries = 0; tries < 100; tries++) {
        snprintf(named, n, "%s.tmp.XXXXXX", af->path);
        int fd = mkstemp(named); /* a fresh name: made, then given to the data */
        if (fd < 0)
            break;
        close(fd);
        unlink(named);
        if (linkat(AT_FDCWD, af->tmp, AT_FDCWD, named, AT_SYMLINK_FOLLOW) == 0) {
            free(af->tmp);
            af->tmp = named;
            af->anon = 0;
            return 0;
        }
        if (errno != EEXIST)
            break;
    }
    const int e = errno ? errno : EIO;
    free(named);
    return e;
}

int mote_afile_open(mote_afile *af, const char *path, mote_err *err)
{
    af->f = NULL;
    af->path = af->tmp = NULL;
    af->anon = 0;
    af->as = MOTE_AS_NAME;
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) /* a rename would replace a device */
        return mote_fail(err, MOTE_EIO,
                         "cannot write '%s': it exists and is not a regular file (mote writes a "
                         "file by renaming a complete copy over it)",
                         path);
    af->path = dup_str(path);
    if (!af->path)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", path);
    int fd = open_temp(path, &af->tmp, &af->anon, O_WRONLY);
    if (fd < 0) {
        int e = errno;
        free(af->path);
        free(af->tmp);
        af->path = af->tmp = NULL;
        return mote_fail(err, e == ENOMEM ? MOTE_ENOMEM : MOTE_EIO, "cannot write '%s': %s",
                         path, strerror(e));
    }
    af->f = fdopen(fd, "w");
    if (!af->f) {
        int e = errno;
        close(fd);
        if (!af->anon)
            unlink(af->tmp);
        free(af->path);
        free(af->tmp);
        af->path = af->tmp = NULL;
        return mote_fail(err, MOTE_EIO, "cannot write '%s': %s", path, strerror(e));
    }
    return MOTE_OK;
}

static void afile_release(mote_afile *af)
{
    free(af->path);
    free(af->tmp);
    af->path = af->tmp = NULL;
    af->f = NULL;
}

void mote_afile_abort(mote_afile *af)
{
    if (!af->tmp)
        return;
    if (af->f)
        fclose(af->f); /* (an unnamed file goes with its descriptor) */
    if (!af->anon)
        unlink(af->tmp);
    afile_release(af);
}

/* How a data file is converted when committed: RFC 4180 CSV under a .csv name or when asked,
 * JSON lines when asked (NULL: kept as written; also a file that is not a data file, its first
 * line not "# mote "). */
typedef int (*converter)(const char *in_path, FILE *out, mote_err *err);
static converter datafile_form(const mote_afile *af)
{
    const converter conv = mote_path_is_csv(af->path) || af->as == MOTE_AS_CSV
                               ? mote_datafile_csv
                           : af->as == MOTE_AS_JSONL ? mote_datafile_jsonl
                                                     : NULL;
    if (!conv)
        return NULL;
    FILE *in = fopen(af->tmp, "r");
    char head[8] = {0};
    int yes = in && fread(head, 1, 7, in) == 7 && memcmp(head, "# mote ", 7) == 0;
    if (in)
        fclose(in);
    return yes ? conv : NULL;
}

/* Replace the temporary file's data file by its converted form, in a second temporary file. */
static int convert_datafile(mote_afile *af, converter conv, mote_err *err)
{
    size_t n = strlen(af->path) + 32;
    char *tmp2 = malloc(n);
    if (!tmp2)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", af->path);
    free(tmp2);
    int anon2 = 0;
    int fd = open_temp(af->path, &tmp2, &anon2, O_WRONLY);
    FILE *out = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (!out) {
        int e = errno;
        if (fd >= 0) {
            close(fd);
            if (!anon2)
                unlink(tmp2);
        }
        free(tmp2);
        return mote_fail(err, MOTE_EIO, "cannot write '%s': %s", af->path, strerror(e));
    }
    int rc = conv(af->tmp, out, err);
    if (rc) {
        fclose(out);
        if (!anon2)
            unlink(tmp2);
        free(tmp2);
        return rc;
    }
    fclose(af->f);
    if (!af->anon)
        unlink(af->tmp);
    free(af->tmp);
    af->tmp = tmp2;
    af->anon = anon2;
    af->f = out;
    return MOTE_OK;
}

int mote_afile_commit(mote_afile *af, mote_err *err)
{
    if (!af->f || !af->tmp)
        return mote_fail(err, MOTE_EIO, "internal: commit of a file that is not open");
    int bad = ferror(af->f) != 0;
    int e = 0;
    /* a data file named *.csv is written as CSV (RFC 4180); one asked for in JSON lines so */
    converter conv = NULL;
    if (!bad && fflush(af->f) == 0 && (conv = datafile_form(af))) {
        int rc = convert_datafile(af, conv, err);
        if (rc) {
            mote_afile_abort(af);
            return rc;
        }
        bad = ferror(af->f) != 0;
    }
    if (fflush(af->f) != 0) {
        bad = 1;
        e = errno;
    }
    if (!bad && fsync(fileno(af->f)) != 0 && errno != EINVAL && errno != EROFS) {
        bad = 1;
        e = errno;
    }
    if (!bad && (e = name_temp(af)) != 0) /* (before the close: an unnamed file goes with it) */
        bad = 1;
    if (fclose(af->f) != 0 && !bad) {
        bad = 1;
        e = errno;
    }
    af->f = NULL;
    if (!bad && rename(af->tmp, af->path) != 0) {
        bad = 1;
        e = errno;
    }
    if (bad) {
        if (!af->anon)
            unlink(af->tmp);
        struct stat st;
        int rc = mote_fail(err, MOTE_EIO, "failed to write '%s': %s; %s", af->path,
                           e ? strerror(e) : "write error",
                           stat(af->path, &st) == 0 ? "its earlier content is kept"
                                                    : "no file was written");
        afile_release(af);
        return rc;
    }
    afile_release(af);
    return MOTE_OK;
}

int mote_dir_of_exists(const char *path)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        return 1;
    size_t n = (size_t)(slash - path);
    if (n == 0)
        return 1;
    char *dir = malloc(n + 1);
    if (!dir)
        return 0;
    memcpy(dir, path, n);
    dir[n] = '\0';
    struct stat st;
    int ok = stat(dir, &st) == 0 && S_ISDIR(st.st_mode);
    free(dir);
    return ok;
}

const char *mote_series_sep(const char *prefix)
{
    const size_t n = strlen(prefix);
    return n == 0 || prefix[n - 1] == '_' || prefix[n - 1] == '/' ? "" : "_";
}

char *mote_series_path(const char *prefix, uint64_t k, int digits, const char *ext)
{
    const size_t len = strlen(prefix) + strlen(ext) + 32;
    char *p = malloc(len);
    if (p)
        snprintf(p, len, "%s%s%0*llu%s", prefix, mote_series_sep(prefix), digits,
                 (unsigned long long)k, ext);
    return p;
}

/* ---- files followed while written ----------------------------------------------------------- */

int mote_partial_open(mote_partial *p, const char *path)
{
    mote_partial_keep(p);
    const size_t n = strlen(path) + sizeof ".partial";
    p->path = malloc(n);
    if (!p->path)
        return ENOMEM;
    snprintf(p->path, n, "%s.partial", path);
    mote_make_dir_of(p->path);
    p->f = fopen(p->path, "w");
    if (!p->f) {
        const int e = errno;
        free(p->path);
        p->path = NULL;
        return e;
    }
    return 0;
}

void mote_partial_flush(mote_partial *p)
{
    if (p->f)
        fflush(p->f);
}

void mote_partial_keep(mote_partial *p)
{
    if (p->f)
        fclose(p->f);
    free(p->path);
    p->f = NULL;
    p->path = NULL;
}

void mote_partial_done(mote_partial *p)
{
    if (p->path)
        unlink(p->path);
    mote_partial_keep(p);
}

/* ---- rows of a monitor or time series --------------------------------------------------------- */

int mote_rows_open(mote_rows *r, const char *path,
                   void (*header)(FILE *f, const void *arg, int growing), const void *arg,
                   mote_err *err)
{
    memset(r, 0, sizeof *r);
    r->path = strdup(path);
    r->text = r->path ? open_memstream(&r->buf, &r->len) : NULL;
    if (!r->text) {
        mote_rows_free(r);
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", path);
    }
    r->header = header;
    r->arg = arg;
    return MOTE_OK;
}

/* The rows kept on the disk (a spilled memory stream): an unnamed file in PATH's folder, else
 * the system's temporary one; NULL when neither can be made (the rows then stay in memory). */
static FILE *rows_store(const char *path)
{
    char *name = NULL;
    int anon = 0;
    int fd = open_temp(path, &name, &anon, O_RDWR);
    if (fd >= 0 && !anon)
        unlink(name); /* (a named one: nameless from now on) */
    free(name);
    FILE *f = fd >= 0 ? fdopen(fd, "w+") : NULL;
    if (!f && fd >= 0)
        close(fd);
    return f ? f : tmpfile();
}

/* Every row so far to f: those on the disk, then those in memory; 0 or an errno value. */
static int rows_copy(mote_rows *r, FILE *f)
{
    char buf[65536];
    for (off_t at = 0; at < (off_t)r->stored;) {
        const size_t want = r->stored - (size_t)at < sizeof buf ? r->stored - (size_t)at : sizeof buf;
        const ssize_t got = pread(fileno(r->store), buf, want, at);
        if (got <= 0)
            return got < 0 ? errno : EIO;
        if (fwrite(buf, 1, (size_t)got, f) != (size_t)got)
            return errno ? errno : EIO;
        at += got;
    }
    if (r->len && fwrite(r->buf, 1, r->len, f) != r->len)
        return errno ? errno : EIO;
    return 0;
}

/* The rows in memory moved to the disk store once they pass r->spill bytes (memory stays
 * bounded however long a run goes on); the memory stream is rewound, its FILE unchanged. A
 * store that cannot be made or written leaves them in memory (tried again at the next row). */
static void rows_spill(mote_rows *r)
{
    const size_t limit = r->spill ? r->spill : MOTE_ROWS_SPILL;
    if (r->len < limit)
        return;
    if (!r->store && !(r->store = rows_store(r->path)))
        return;
    for (size_t done = 0; done < r->len;) {
        const ssize_t put = pwrite(fileno(r->store), r->buf + done, r->len - done,
                                   (off_t)(r->stored + done));
        if (put <= 0)
            return; /* (only the first r->stored bytes of the store count) */
        done += (size_t)put;
    }
    r->stored += r->len;
    fseeko(r->text, 0, SEEK_SET);
    fflush(r->text); /* (len now 0; later rows overwrite the buffer) */
    r->sent = 0;
}

int mote_rows_follow(mote_rows *r, mote_err *err)
{
    if (!r->text)
        return MOTE_OK;
    if (fflush(r->text) != 0)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory after %zu rows", r->path,
                         r->rows);
    r->rows++;
    mote_partial *pt = &r->partial;
    if (!pt->f && !pt->path && mote_partial_open(pt, r->path) == 0) {
        r->header(pt->f, r->arg, 1);
        rows_copy(r, pt->f); /* (every row so far; a failed copy shows in the whole file) */
        r->sent = r->len;
    }
    if (pt->f) { /* (a partial file that cannot be made: the complete file is the result) */
        fwrite(r->buf + r->sent, 1, r->len - r->sent, pt->f);
        r->sent = r->len;
        mote_partial_flush(pt);
    }
    rows_spill(r);
    return MOTE_OK;
}

int mote_rows_start(mote_rows *r, mote_err *err)
{
    int rc = mote_rows_follow(r, err);
    if (!rc && access(r->path, F_OK) != 0)
        rc = mote_rows_write(r, err);
    return rc;
}

int mote_rows_write(mote_rows *r, mote_err *err)
{
    if (!r->text || fflush(r->text) != 0)
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", r->path ? r->path : "rows");
    mote_afile af;
    int rc = mote_afile_open(&af, r->path, err);
    if (rc)
        return rc;
    af.as = r->as;
    r->header(af.f, r->arg, 0);
    const int e = rows_copy(r, af.f);
    if (e) {
        mote_afile_abort(&af);
        return mote_fail(err, MOTE_EIO, "%s: reading back its rows failed: %s", r->path,
                         strerror(e));
    }
    rc = mote_afile_commit(&af, err);
    if (!rc)
        mote_partial_done(&r->partial);
    return rc;
}

void mote_rows_keep(mote_rows *r) { mote_partial_keep(&r->partial); }

void mote_rows_free(mote_rows *r)
{
    mote_partial_keep(&r->partial);
    if (r->text)
        fclose(r->text);
    if (r->store)
        fclose(r->store);
    free(r->buf);
    free(r->path);
    memset(r, 0, sizeof *r);
}

int mote_rows_end(mote_rows *r, int rc, mote_err *err)
{
    if (rc == MOTE_EINTR) {
        mote_rows_keep(r);
        return rc;
    }
    mote_err werr = {0};
    const int wrc = mote_rows_write(r, rc ? &werr : err);
    if (wrc)
        mote_rows_keep(r); /* (its rows so far stay in PATH.partial) */
    return rc ? rc : wrc;
}

/* ---- growing files of frames ------------------------------------------------------------------ */

int mote_frames_first(const char *path, mote_frame_writer frame, const void *arg, mote_err *err)
{
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc)
        return rc;
    if ((rc = frame(af.f, arg, err))) {
        mote_afile_abort(&af);
        return rc;
    }
    return mote_afile_commit(&af, err);
}

int mote_frames_append(const char *path, mote_frame_writer frame, const void *arg, mote_err *err)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return mote_fail(err, MOTE_EIO, "trajectory: '%s' is gone: %s", path, strerror(errno));
    FILE *f = fopen(path, "a");
    if (!f)
        return mote_fail(err, MOTE_EIO, "trajectory: cannot append to '%s': %s", path,
                         strerror(errno));
    int rc = frame(f, arg, err);
    int e = 0;
    if (fflush(f) != 0 || ferror(f))
        e = errno ? errno : EIO;
    if (fclose(f) != 0 && !e)
        e = errno ? errno : EIO;
    if (!rc && e)
        rc = mote_fail(err, MOTE_EIO, "trajectory: writing a frame to '%s' failed: %s", path,
                       strerror(e));
    if (rc && truncate(path, st.st_size) != 0) { /* keep whole frames only; nothing else to do */
    }
    return rc;
}
