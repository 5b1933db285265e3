/* Files as Assimp reads them for the mesh reader (mesh.c).
 *
 * Assimp cuts an OBJ object name at its first blank: `o panel left` and `o panel right` both
 * become the part `panel`, and their materials cannot be told apart. An OBJ file is therefore
 * read through a file system of ours that hands Assimp the file's bytes with the blanks inside
 * each `o NAME` turned into '_' (the name `panel_left`; the text keeps its length, so offsets
 * stay true). The file is streamed, never read whole: each read also looks at up to
 * OBJ_REACH bytes either side of it, so that every line it touches is seen whole; an `o` line
 * longer than that is left as Assimp reads it. Other files (an OBJ's .mtl, other formats) are
 * read through the same streaming reader unchanged. */
#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "mote/mesh.h"

#define OBJ_REACH 4096

typedef struct {
    int fd;
    int obj;        /* an OBJ file: its object names are mended */
    size_t n, pos;  /* the file's size, the read position */
    char *win;      /* OBJ: the window around a read */
    size_t win_cap;
} obj_file;

/* Up to n bytes at off into buf (short only at the end of the file or on an error). */
static size_t read_at(int fd, char *buf, size_t n, size_t off)
{
    size_t got = 0;
    while (got < n) {
        const ssize_t k = pread(fd, buf + got, n - got, (off_t)(off + got));
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            break;
        got += (size_t)k;
    }
    return got;
}

/* In t[0 .. n), whose first byte is at file offset base in a file of size fsize: the blanks
 * inside each `o NAME` become '_', for every line seen whole (its start, and its end or the
 * file's end, inside t). */
static void mend_names(char *t, size_t n, size_t base, size_t fsize)
{
    size_t i = 0;
    if (base > 0) { /* the first line may have begun before the window: skip it */
        while (i < n && t[i] != '\n')
            i++;
        i++;
    }
    while (i < n) {
        size_t e = i;
        while (e < n && t[e] != '\n')
            e++;
        if (e == n && base + n < fsize)
            break; /* the line goes on past the window */
        size_t a = i;
        while (a < e && (t[a] == ' ' || t[a] == '\t'))
            a++;
        if (a + 1 < e && t[a] == 'o' && (t[a + 1] == ' ' || t[a + 1] == '\t')) {
            size_t b = a + 1, z = e;
            while (b < z && (t[b] == ' ' || t[b] == '\t'))
                b++;
            while (z > b && (t[z - 1] == ' ' || t[z - 1] == '\t' || t[z - 1] == '\r'))
                z--;
            for (size_t k = b; k < z; k++)
                if (t[k] == ' ' || t[k] == '\t')
                    t[k] = '_';
        }
        i = e + 1;
    }
}

static size_t file_read(struct aiFile *af, char *buf, size_t size, size_t count)
{
    obj_file *f = (obj_file *)af->UserData;
    if (size == 0 || count == 0 || f->pos >= f->n)
        return 0;
    size_t want = f->n - f->pos;
    if (count < want / size)
        want = count * size;
    want -= want % size;
    if (want == 0)
        return 0;
    size_t got;
    if (!f->obj) {
        got = read_at(f->fd, buf, want, f->pos);
    } else {
        const size_t back = f->pos < OBJ_REACH ? f->pos : OBJ_REACH;
        const size_t need = back + want + OBJ_REACH;
        if (need > f->win_cap) {
            char *w = realloc(f->win, need);
            if (!w)
                return 0;
            f->win = w;
            f->win_cap = need;
        }
        const size_t have = read_at(f->fd, f->win, need, f->pos - back);
        if (have <= back)
            return 0;
        mend_names(f->win, have, f->pos - back, f->n);
        got = have - back < want ? have - back : want;
        memcpy(buf, f->win + back, got);
    }
    got -= got % size;
    f->pos += got;
    return got / size;
}

static size_t file_write(struct aiFile *af, const char *buf, size_t size, size_t count)
{
    (void)af, (void)buf, (void)size, (void)count;
    return 0;
}
static size_t file_tell(struct aiFile *af) { return ((obj_file *)af->UserData)->pos; }
static size_t file_size(struct aiFile *af) { return ((obj_file *)af->UserData)->n; }
static void file_flush(struct aiFile *af) { (void)af; }

static enum aiReturn file_seek(struct aiFile *af, size_t off, enum aiOrigin how)
{
    obj_file *f = (obj_file *)af->UserData;
    const size_t base = how == aiOrigin_SET ? 0 : how == aiOrigin_CUR ? f->pos : f->n;
    if (base > f->n || off > f->n - base)
        return aiReturn_FAILURE;
    f->pos = base + off;
    return aiReturn_SUCCESS;
}

static int ends_with_obj(const char *path)
{
    const size_t n = strlen(path);
    return n >= 4 && path[n - 4] == '.' && (path[n - 3] | 32) == 'o' &&
           (path[n - 2] | 32) == 'b' && (path[n - 1] | 32) == 'j';
}

static struct aiFile *file_open(struct aiFileIO *io, const char *path, const char *mode)
{
    (void)io;
    if (!mode || mode[0] != 'r')
        return NULL;
    const int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return NULL;
    struct stat st;
    struct aiFile *af = calloc(1, sizeof *af);
    obj_file *f = calloc(1, sizeof *f);
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || !af || !f) {
        close(fd);
        free(af);
        free(f);
        return NULL;
    }
    *f = (obj_file){.fd = fd, .obj = ends_with_obj(path), .n = (size_t)st.st_size};
    af->ReadProc = file_read;
    af->WriteProc = file_write;
    af->TellProc = file_tell;
    af->FileSizeProc = file_size;
    af->SeekProc = file_seek;
    af->FlushProc = file_flush;
    af->UserData = (aiUserData)f;
    return af;
}

static void file_close(struct aiFileIO *io, struct aiFile *af)
{
    (void)io;
    if (!af)
        return;
    obj_file *f = (obj_file *)af->UserData;
    if (f) {
        close(f->fd);
        free(f->win);
    }
    free(f);
    free(af);
}

const struct aiScene *mote_mesh_assimp_import(const char *path, unsigned flags)
{
    struct aiFileIO io = {file_open, file_close, NULL};
    return aiImportFileEx(path, flags, &io);
}
