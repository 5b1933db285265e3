/* mesh.c: mesh files (the charging spec 7.1-7.3) and their checks and repairs (its 4.2), for
 * every model that takes them (mesh.h). Files are read through Assimp (STL ASCII and binary,
 * OBJ, PLY, glTF and the rest; the node tree is walked so that OBJ groups and STL solids become
 * parts), or in the original program's plain format: numbers as a stream, 9 per triangle, the rest of a line dropped after a
 * triangle's ninth number, a non-numeric token abandoning the partial triangle and its line,
 * `#` starting a comment. The triangles are scaled, turned and moved, then repaired as a whole:
 * triangles below 1e-12 L^2 dropped (L the bounding-box diagonal), vertices closer than 1e-9 L
 * welded, triangles with the same three vertices dropped, components formed across shared
 * edges, closed components (every edge shared by exactly two triangles) oriented consistently
 * and outward (positive signed volume, the right-hand rule), open ones kept as two-sided
 * sheets. Every count is reported. */
#include "mote/mesh.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>


/* The triangles of one file before repair: vertices and part names. */
typedef struct {
    size_t n, cap;
    double (*v)[3][3];
    int *part;              /* index into names */
    char (*names)[MOTE_MESH_NAME_LEN];
    int nnames;
} soup;

static void soup_free(soup *s)
{
    free(s->v);
    free(s->part);
    free(s->names);
}

/* The index of a part name, added if new; -1 with err set (a name too long, memory). */
static int soup_name(soup *s, const char *name, mote_err *err)
{
    for (int k = 0; k < s->nnames; k++)
        if (strcmp(s->names[k], name) == 0)
            return k;
    if (strlen(name) >= sizeof s->names[0])
        return mote_fail(err, MOTE_EFORMAT, "the part name '%.40s...' is longer than %zu "
                         "characters", name, sizeof s->names[0] - 1), -1;
    char(*p)[MOTE_MESH_NAME_LEN] = realloc(s->names, (size_t)(s->nnames + 1) * sizeof *p);
    if (!p)
        return mote_fail(err, MOTE_ENOMEM, "out of memory"), -1;
    s->names = p;
    snprintf(s->names[s->nnames], sizeof s->names[0], "%s", name);
    return s->nnames++;
}

static int soup_add(soup *s, const double t[3][3], int part)
{
    if (s->n == s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 1024;
        double(*v)[3][3] = realloc(s->v, cap * sizeof *v);
        if (v)
            s->v = v;
        int *p = realloc(s->part, cap * sizeof *p);
        if (p)
            s->part = p;
        if (!v || !p)
            return -1;
        s->cap = cap;
    }
    memcpy(s->v[s->n], t, sizeof s->v[0]);
    s->part[s->n++] = part;
    return 0;
}

/* ---- the plain format (spec 7.2) ------------------------------------------------------------ */

static int read_plain(const char *path, soup *s, int part, int strict, uint32_t *abandoned,
                      int *trailing, mote_err *err)
{
    mote_lines in;
    int rc = mote_lines_open(&in, path, err);
    if (rc)
        return rc;
    double t[9];
    int k = 0; /* numbers of the current triangle so far */
    char *line;
    while (!rc && (line = mote_lines_next(&in)) != NULL) {
        char *hash = strchr(line, '#');
        if (hash)
            *hash = '\0';
        char *p = line;
        for (;;) {
            while (isspace((unsigned char)*p))
                p++;
            if (!*p)
                break;
            char *end;
            errno = 0;
            double v = strtod(p, &end);
            if (end != p && !isfinite(v) && (!*end || isspace((unsigned char)*end))) {
                rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: a coordinate that is not a finite "
                               "number ('%.*s')", path, in.line, (int)(end - p), p);
                break;
            }
            if (end == p || (*end && !isspace((unsigned char)*end))) {
                /* a non-numeric token: the partial triangle and the rest of the line go */
                (*abandoned)++;
                if (strict)
                    rc = mote_fail(err, MOTE_EFORMAT, "%s:%ld: expected a number, found '%.40s'",
                                   path, in.line, p);
                k = 0;
                break;
            }
            t[k++] = v;
            p = end;
            if (k == 9) { /* a triangle: the rest of its line is dropped */
                double tri[3][3];
                memcpy(tri, t, sizeof tri);
                if (soup_add(s, (const double(*)[3])tri, part))
                    rc = mote_fail(err, MOTE_ENOMEM, "%s: out of memory", path);
                k = 0;
                break;
            }
        }
    }
    int crc = mote_lines_close(&in, err);
    rc = crc ? crc : rc;
    if (!rc && k != 0 && strict)
        rc = mote_fail(err, MOTE_EFORMAT, "%s: the file ends inside a triangle (%d of 9 numbers)",
                       path, k);
    *trailing = k;
    return rc;
}

/* ---- Assimp --------------------------------------------------------------------------------- */

typedef struct {
    double m[4][4];
} xform;

static void xmul(const xform *a, const struct aiMatrix4x4 *b, xform *out)
{
    const double B[4][4] = {{b->a1, b->a2, b->a3, b->a4},
                            {b->b1, b->b2, b->b3, b->b4},
                            {b->c1, b->c2, b->c3, b->c4},
                            {b->d1, b->d2, b->d3, b->d4}};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double x = 0;
            for (int k = 0; k < 4; k++)
                x += a->m[i][k] * B[k][j];
            out->m[i][j] = x;
        }
}

static int walk(const struct aiScene *sc, const struct aiNode *node, const xform *parent, soup *s,
                const char *fallback, int depth, mote_err *err)
{
    if (depth > 256)
        return mote_fail(err, MOTE_EFORMAT, "mesh: the node tree is deeper than 256");
    xform x;
    xmul(parent, &node->mTransformation, &x);
    for (unsigned i = 0; i < node->mNumMeshes; i++) {
        const struct aiMesh *me = sc->mMeshes[node->mMeshes[i]];
        /* the part: the mesh (OBJ group, STL solid) name, else the material's, else fallback */
        const char *name = me->mName.length ? me->mName.data
                           : node != sc->mRootNode && node->mName.length ? node->mName.data
                                                                          : NULL;
        struct aiString mat;
        if (!name && me->mMaterialIndex < sc->mNumMaterials &&
            aiGetMaterialString(sc->mMaterials[me->mMaterialIndex], AI_MATKEY_NAME, &mat) ==
                aiReturn_SUCCESS &&
            mat.length && strcmp(mat.data, "DefaultMaterial") != 0)
            name = mat.data;
        const int part = soup_name(s, name ? name : fallback, err);
        if (part < 0)
            return err ? (int)err->code : MOTE_EFORMAT;
        for (unsigned f = 0; f < me->mNumFaces; f++) {
            const struct aiFace *face = &me->mFaces[f];
            if (face->mNumIndices != 3)
                continue; /* points and lines */
            double t[3][3];
            for (int j = 0; j < 3; j++) {
                if (face->mIndices[j] >= me->mNumVertices)
                    return mote_fail(err, MOTE_EFORMAT, "mesh: a face refers to vertex %u of %u",
                                     face->mIndices[j], me->mNumVertices);
                const struct aiVector3D *p = &me->mVertices[face->mIndices[j]];
                const double q[3] = {p->x, p->y, p->z};
                for (int a = 0; a < 3; a++)
                    t[j][a] = x.m[a][0] * q[0] + x.m[a][1] * q[1] + x.m[a][2] * q[2] + x.m[a][3];
            }
            if (soup_add(s, (const double(*)[3])t, part))
                return mote_fail(err, MOTE_ENOMEM, "mesh: out of memory");
        }
    }
    for (unsigned c = 0; c < node->mNumChildren; c++) {
        int rc = walk(sc, node->mChildren[c], &x, s, fallback, depth + 1, err);
        if (rc)
            return rc;
    }
    return MOTE_OK;
}

/* Assimp is a library that may abort the process (its assertions) or allocate what a damaged
 * header asks for, so it reads the file in a child process under an address-space limit; the
 * triangles come back through a pipe. A child that dies, for whatever reason, is an error that
 * names the file, and mote goes on. Cheap header counts (OFF, PLY) are checked against the file's
 * size first, so a damaged header is refused before anything is allocated. */

static int write_all(int fd, const void *buf, size_t n)
{
    const char *p = buf;
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return -1;
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

static int read_all(int fd, void *buf, size_t n)
{
    char *p = buf;
    while (n > 0) {
        ssize_t r = read(fd, p, n);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            return -1;
        p += r;
        n -= (size_t)r;
    }
    return 0;
}

/* The counts a mesh header declares against the bytes the file has: a vertex or a face takes at
 * least `vb` or `fb` bytes. 0, or an error naming the file. */
static int header_counts_fit(const char *path, double nv, double nf, double vb, double fb,
                             double size, mote_err *err)
{
    if (nv * vb + nf * fb > size)
        return mote_fail(err, MOTE_EFORMAT, "%s: the header declares %.0f vertices and %.0f faces, "
                         "more than a file of %.0f bytes holds (a damaged header)", path, nv, nf,
                         size);
    return MOTE_OK;
}

/* OFF and PLY headers read here, before Assimp sees them. */
static int precheck(const char *path, double size, mote_err *err)
{
    if (size <= 0) { /* (a size not known yet: the file's own) */
        struct stat st;
        if (stat(path, &st) != 0 || !S_ISREG(st.st_mode))
            return MOTE_OK; /* (the reader reports it) */
        size = (double)st.st_size;
    }
    FILE *f = fopen(path, "rb");
    if (!f)
        return mote_fail(err, MOTE_EIO, "%s: cannot open (%s)", path, strerror(errno));
    char head[65536];
    size_t n = fread(head, 1, sizeof head - 1, f);
    fclose(f);
    head[n] = '\0';
    if (memchr(head, '\0', n) && (n >= 3 && (!memcmp(head, "OFF", 3) || !memcmp(head, "ply", 3)))) {
        /* a NUL byte in a text header (a binary PLY's data starts after end_header) */
        const char *eh = strstr(head, "end_header");
        const char *nul = memchr(head, '\0', n);
        if (!eh || nul < eh)
            return mote_fail(err, MOTE_EFORMAT, "%s: a NUL byte in the header (not a text file)",
                             path);
    }
    if (n >= 3 && !memcmp(head, "OFF", 3)) {
        /* OFF: the counts line is the first after "OFF" that is not a comment */
        const char *p = head + 3;
        double nv = -1, nf = -1;
        while (*p) {
            p += strspn(p, " \t\r\n");
            if (*p == '#') {
                p += strcspn(p, "\n");
                continue;
            }
            if (sscanf(p, "%lf %lf", &nv, &nf) != 2)
                return mote_fail(err, MOTE_EFORMAT, "%s: an OFF file without its counts line "
                                 "(vertices faces edges)", path);
            break;
        }
        if (!(nv >= 0 && nf >= 0 && nv < 4e9 && nf < 4e9))
            return mote_fail(err, MOTE_EFORMAT, "%s: the OFF counts are not counts", path);
        for (const char *q = p; *q; q++) /* the rest must be text */
            if (!isprint((unsigned char)*q) && !isspace((unsigned char)*q))
                return mote_fail(err, MOTE_EFORMAT, "%s: a byte that is not text in the OFF "
                                 "file's first 64 KiB", path);
        return header_counts_fit(path, nv, nf, 6, 8, size, err);
    }
    if (n >= 3 && !memcmp(head, "ply", 3)) {
        /* (Assimp 5.2 reads a header without its end for ever) */
        if (!strstr(head, "end_header"))
            return mote_fail(err, MOTE_EFORMAT, "%s: a PLY header without end_header in its "
                             "first 64 KiB", path);
        const int binary = strstr(head, "format binary") != NULL;
        double nv = 0, nf = 0, v;
        const char *e;
        if ((e = strstr(head, "element vertex ")) && sscanf(e + 15, "%lf", &v) == 1)
            nv = v;
        if ((e = strstr(head, "element face ")) && sscanf(e + 13, "%lf", &v) == 1)
            nf = v;
        if (!(nv >= 0 && nf >= 0 && nv < 4e9 && nf < 4e9))
            return mote_fail(err, MOTE_EFORMAT, "%s: the PLY element counts are not counts", path);
        return header_counts_fit(path, nv, nf, binary ? 12 : 6, binary ? 13 : 8, size, err);
    }
    return MOTE_OK;
}

int mote_mesh_precheck(const char *path, mote_err *err) { return precheck(path, 0, err); }

/* The child: read with Assimp, write the soup (or the error) to fd, and exit. Its time is
 * bounded too (a reader that loops for ever on a damaged file ends with SIGXCPU or SIGALRM):
 * cpu_limit seconds of processor time, twice that of wall clock. Its own messages (Assimp's
 * assertions) go nowhere: the parent reports how it ended. */
static void assimp_child(int fd, const char *path, const char *fallback, double as_limit,
                         unsigned cpu_limit)
{
    /* a fatal signal ends the child as the default does, whatever handlers the parent had (a
     * fuzzer's or a sanitizer's would report the child's end as the parent's crash) */
    static const int fatal[] = {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGXCPU, SIGALRM};
    for (size_t k = 0; k < sizeof fatal / sizeof fatal[0]; k++)
        signal(fatal[k], SIG_DFL);
    struct rlimit cpu = {cpu_limit, cpu_limit + 1};
    setrlimit(RLIMIT_CPU, &cpu);
    alarm(2 * cpu_limit);
    int null = open("/dev/null", O_WRONLY);
    if (null >= 0) {
        dup2(null, 1);
        dup2(null, 2);
        close(null);
    }
#if !defined(__SANITIZE_ADDRESS__)
    if (as_limit > 0) {
        struct rlimit rl = {(rlim_t)as_limit, (rlim_t)as_limit};
        setrlimit(RLIMIT_AS, &rl);
    }
#else
    (void)as_limit; /* (AddressSanitizer's shadow memory needs the whole address space) */
#endif
    soup s = {0};
    mote_err e = {0};
    int32_t rc;
    const struct aiScene *sc =
        mote_mesh_assimp_import(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices);
    if (!sc || !sc->mRootNode) {
        rc = mote_fail(&e, MOTE_EFORMAT, "%s: not a mesh file Assimp reads (%s)", path,
                       aiGetErrorString());
    } else {
        xform id = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};
        rc = walk(sc, sc->mRootNode, &id, &s, fallback, 0, &e);
        if (rc && strncmp(e.msg, path, strlen(path)) != 0) {
            char m[sizeof e.msg];
            snprintf(m, sizeof m, "%s", e.msg);
            mote_fail(&e, e.code, "%s: %s", path, m);
        }
        aiReleaseImport(sc);
    }
    uint32_t len = rc ? (uint32_t)strlen(e.msg) : 0;
    uint64_t n = s.n;
    int32_t nn = s.nnames;
    int bad = write_all(fd, &rc, sizeof rc) || write_all(fd, &len, sizeof len) ||
              write_all(fd, e.msg, len);
    if (!rc && !bad)
        bad = write_all(fd, &n, sizeof n) || write_all(fd, &nn, sizeof nn) ||
              write_all(fd, s.names, (size_t)nn * sizeof s.names[0]) ||
              write_all(fd, s.v, s.n * sizeof s.v[0]) ||
              write_all(fd, s.part, s.n * sizeof s.part[0]);
    close(fd);
    _exit(bad ? 3 : 0);
}

/* The soup the child sent; 0, or an error. */
static int assimp_receive(int fd, const char *path, soup *s, mote_err *err)
{
    int32_t rc;
    uint32_t len;
    if (read_all(fd, &rc, sizeof rc) || read_all(fd, &len, sizeof len))
        return -1;
    if (rc) {
        char msg[sizeof err->msg];
        if (len >= sizeof msg || read_all(fd, msg, len))
            return -1;
        msg[len] = '\0';
        return mote_fail(err, rc, "%s", msg);
    }
    uint64_t n;
    int32_t nn;
    if (read_all(fd, &n, sizeof n) || read_all(fd, &nn, sizeof nn) || nn < 0 || n > UINT32_MAX)
        return -1;
    int rcm = mote_mem_check((double)n * (sizeof s->v[0] + sizeof s->part[0]) * 4,
                             "mesh: the triangles", err);
    if (rcm)
        return rcm;
    char(*names)[MOTE_MESH_NAME_LEN] = malloc(((size_t)nn + 1) * sizeof *names);
    double(*v)[3][3] = malloc((n ? n : 1) * sizeof *v);
    int *part = malloc((n ? n : 1) * sizeof *part);
    if (!names || !v || !part) {
        free(names);
        free(v);
        free(part);
        return mote_fail(err, MOTE_ENOMEM, "%s: out of memory", path);
    }
    free(s->names);
    free(s->v);
    free(s->part);
    s->names = names;
    s->v = v;
    s->part = part;
    s->n = s->cap = n;
    s->nnames = nn;
    if (read_all(fd, names, (size_t)nn * sizeof *names) || read_all(fd, v, n * sizeof *v) ||
        read_all(fd, part, n * sizeof *part))
        return -1;
    for (size_t i = 0; i < n; i++)
        if (part[i] < 0 || part[i] >= nn)
            return -1;
    for (int32_t k = 0; k < nn; k++)
        names[k][sizeof names[0] - 1] = '\0';
    return MOTE_OK;
}

/* The reader's processor time: this many seconds, and one more a MiB of the file. */
#define ASSIMP_CPU_SECONDS 10

static int read_assimp(const char *path, soup *s, const char *fallback, mote_err *err)
{
    struct stat st;
    if (stat(path, &st) != 0)
        return mote_fail(err, MOTE_EIO, "%s: cannot open (%s)", path, strerror(errno));
    if (!S_ISREG(st.st_mode))
        return mote_fail(err, MOTE_EIO, "%s: not a regular file", path);
    int rc = precheck(path, (double)st.st_size, err);
    if (rc)
        return rc;
    /* the child may use what the process has now, plus 64 bytes a byte of the file and 1 GiB,
     * within 3/4 of the machine's memory */
    double vsz = 0;
    FILE *sm = fopen("/proc/self/statm", "r");
    if (sm) {
        unsigned long pages;
        if (fscanf(sm, "%lu", &pages) == 1)
            vsz = (double)pages * (double)sysconf(_SC_PAGESIZE);
        fclose(sm);
    }
    double budget = 64.0 * (double)st.st_size + (double)(1u << 30);
    const double phys = mote_mem_physical();
    if (phys > 0 && budget > 0.75 * phys)
        budget = 0.75 * phys;
    int fds[2];
    if (pipe(fds) != 0)
        return mote_fail(err, MOTE_EIO, "%s: cannot make a pipe for the reader (%s)", path,
                         strerror(errno));
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        return mote_fail(err, MOTE_EIO, "%s: cannot start the mesh reader (%s)", path,
                         strerror(errno));
    }
    if (pid == 0) {
        close(fds[0]);
        assimp_child(fds[1], path, fallback, vsz + budget,
                     ASSIMP_CPU_SECONDS + (unsigned)(st.st_size >> 20));
    }
    close(fds[1]);
    rc = assimp_receive(fds[0], path, s, err);
    close(fds[0]);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    if (rc == -1 || (rc == 0 && !(WIFEXITED(status) && WEXITSTATUS(status) == 0))) {
        if (WIFSIGNALED(status))
            rc = mote_fail(err, MOTE_EFORMAT, "%s: Assimp stopped on this file (%s%s): not a mesh "
                           "file mote can read", path, strsignal(WTERMSIG(status)),
                           WTERMSIG(status) == SIGABRT ? ", an assertion or memory exhausted"
                           : WTERMSIG(status) == SIGXCPU || WTERMSIG(status) == SIGALRM
                               ? ", out of time: it may loop for ever on a damaged file"
                               : "");
        else
            rc = mote_fail(err, MOTE_EFORMAT, "%s: Assimp could not read this file (its reader "
                           "ended with status %d)", path,
                           WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    }
    return rc;
}

/* ---- repairs (spec 4.2) --------------------------------------------------------------------- */

typedef struct {
    uint32_t a, b;          /* a < b: the welded vertex ids of an edge */
    uint32_t tri;
    int8_t forward;         /* 1: the triangle runs a -> b */
} edge;

static int cmp_edge(const void *x, const void *y)
{
    const edge *p = x, *q = y;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    if (p->b != q->b)
        return p->b < q->b ? -1 : 1;
    return p->tri < q->tri ? -1 : p->tri > q->tri;
}

typedef struct {
    double x[3];
    uint32_t id;
    int64_t cell[3];
} vkey;

static int cmp_vkey(const void *x, const void *y)
{
    const vkey *p = x, *q = y;
    for (int a = 0; a < 3; a++)
        if (p->cell[a] != q->cell[a])
            return p->cell[a] < q->cell[a] ? -1 : 1;
    return 0;
}

static uint32_t find(uint32_t *up, uint32_t i)
{
    while (up[i] != i) {
        up[i] = up[up[i]];
        i = up[i];
    }
    return i;
}

/* Weld the soup's vertices (ids into vid[3 n]); the welded positions go to pos. */
static int weld(const soup *s, double eps, uint32_t *vid, double (**pos)[3], uint32_t *npos,
                uint32_t *welded)
{
    const size_t nv = 3 * s->n;
    vkey *k = malloc((nv ? nv : 1) * sizeof *k);
    uint32_t *up = malloc((nv ? nv : 1) * sizeof *up);
    if (!k || !up) {
        free(k);
        free(up);
        return -1;
    }
    /* cells of side eps / sqrt(3): two vertices in one cell are within eps, so a cell is welded
     * whole without comparing its vertices; cells up to 2 apart along each axis may hold vertices
     * within eps of each other, and a pair of cells is compared only until one pair of its
     * vertices welds them (once welded, the rest of the pair is skipped). Duplicated vertices,
     * however many, cost O(n log n). */
    const double side = eps / sqrt(3.0);
    for (size_t i = 0; i < nv; i++) {
        memcpy(k[i].x, s->v[i / 3][i % 3], sizeof k[i].x);
        k[i].id = (uint32_t)i;
        for (int a = 0; a < 3; a++)
            k[i].cell[a] = (int64_t)floor(k[i].x[a] / side);
        up[i] = (uint32_t)i;
    }
    qsort(k, nv, sizeof *k, cmp_vkey);
    size_t *run = malloc((nv + 1) * sizeof *run); /* the first key of each cell, then nv */
    if (!run) {
        free(k);
        free(up);
        return -1;
    }
    size_t nrun = 0;
    for (size_t i = 0; i < nv; i++)
        if (i == 0 || cmp_vkey(&k[i], &k[i - 1]) != 0)
            run[nrun++] = i;
    run[nrun] = nv;
    for (size_t r = 0; r < nrun; r++) { /* each cell's vertices under its lowest id */
        uint32_t low = UINT32_MAX;
        for (size_t i = run[r]; i < run[r + 1]; i++)
            low = k[i].id < low ? k[i].id : low;
        for (size_t i = run[r]; i < run[r + 1]; i++)
            up[k[i].id] = low;
    }
    for (size_t ra = 0; ra < nrun; ra++)
        for (int d = 0; d < 125; d++) {
            vkey probe;
            probe.cell[0] = k[run[ra]].cell[0] + d % 5 - 2;
            probe.cell[1] = k[run[ra]].cell[1] + (d / 5) % 5 - 2;
            probe.cell[2] = k[run[ra]].cell[2] + d / 25 - 2;
            if (cmp_vkey(&probe, &k[run[ra]]) <= 0)
                continue; /* (that pair of cells is examined from the other side) */
            size_t lo = ra + 1, hi = nrun;
            while (lo < hi) {
                size_t mid = (lo + hi) / 2;
                if (cmp_vkey(&k[run[mid]], &probe) < 0)
                    lo = mid + 1;
                else
                    hi = mid;
            }
            if (lo == nrun || cmp_vkey(&k[run[lo]], &probe) != 0)
                continue;
            const size_t rb = lo;
            int joined = find(up, k[run[ra]].id) == find(up, k[run[rb]].id);
            for (size_t i = run[ra]; !joined && i < run[ra + 1]; i++)
                for (size_t j = run[rb]; !joined && j < run[rb + 1]; j++) {
                    double d2 = 0;
                    for (int a = 0; a < 3; a++)
                        d2 += (k[i].x[a] - k[j].x[a]) * (k[i].x[a] - k[j].x[a]);
                    if (d2 <= eps * eps) {
                        uint32_t ri = find(up, k[i].id), rj = find(up, k[j].id);
                        up[ri > rj ? ri : rj] = ri < rj ? ri : rj;
                        joined = 1;
                    }
                }
        }
    free(run);
    /* number the roots in first-appearance order */
    uint32_t *num = malloc((nv ? nv : 1) * sizeof *num);
    *pos = malloc((nv ? nv : 1) * sizeof **pos);
    if (!num || !*pos) {
        free(k);
        free(up);
        free(num);
        return -1;
    }
    uint32_t n = 0, distinct = 0;
    for (size_t i = 0; i < nv; i++)
        num[i] = UINT32_MAX;
    for (size_t i = 0; i < nv; i++) {
        uint32_t r = find(up, (uint32_t)i);
        if (num[r] == UINT32_MAX) {
            num[r] = n;
            memcpy((*pos)[n++], s->v[r / 3][r % 3], sizeof (*pos)[0]);
        }
        vid[i] = num[r];
    }
    /* welded: vertices that were distinct points and became one */
    for (size_t i = 0; i < nv; i++) {
        const double *p = s->v[i / 3][i % 3], *q = (*pos)[vid[i]];
        distinct += p[0] != q[0] || p[1] != q[1] || p[2] != q[2];
    }
    *npos = n;
    *welded = distinct;
    free(k);
    free(up);
    free(num);
    return 0;
}

static int cmp_u32x3(const void *x, const void *y)
{
    const uint32_t *p = x, *q = y;
    for (int a = 0; a < 4; a++)
        if (p[a] != q[a])
            return p[a] < q[a] ? -1 : 1;
    return 0;
}

/* The length of the soup's bounding box's diagonal. */
static double soup_extent(const soup *s)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < s->n; i++)
        for (int j = 0; j < 3; j++)
            for (int a = 0; a < 3; a++) {
                lo[a] = fmin(lo[a], s->v[i][j][a]);
                hi[a] = fmax(hi[a], s->v[i][j][a]);
            }
    double L = 0;
    for (int a = 0; a < 3; a++)
        L += (hi[a] - lo[a]) * (hi[a] - lo[a]);
    return sqrt(L);
}

/* keep[i]: triangle i (welded vertices vid) is not degenerate and not a duplicate of an earlier
 * one (the same vertex set). 1 when out of memory. */
static int keep_triangles(const soup *s, const uint32_t *vid, const double (*pos)[3], double L,
                          uint8_t *keep, mote_mesh_report *rep)
{
    uint32_t(*key)[4] = malloc((s->n ? s->n : 1) * sizeof *key);
    if (!key)
        return 1;
    size_t nk = 0;
    for (size_t i = 0; i < s->n; i++) {
        const uint32_t *t = vid + 3 * i;
        double e1[3], e2[3], c[3];
        for (int a = 0; a < 3; a++) {
            e1[a] = pos[t[1]][a] - pos[t[0]][a];
            e2[a] = pos[t[2]][a] - pos[t[0]][a];
        }
        c[0] = e1[1] * e2[2] - e1[2] * e2[1];
        c[1] = e1[2] * e2[0] - e1[0] * e2[2];
        c[2] = e1[0] * e2[1] - e1[1] * e2[0];
        const double area = 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        if (!(area >= 1e-12 * L * L) || t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
            rep->degenerate++;
            continue;
        }
        uint32_t q[3] = {t[0], t[1], t[2]}; /* sorted ids, then the index */
        for (int x = 0; x < 2; x++)
            for (int y = 0; y < 2 - x; y++)
                if (q[y] > q[y + 1]) {
                    uint32_t z = q[y];
                    q[y] = q[y + 1];
                    q[y + 1] = z;
                }
        key[nk][0] = q[0];
        key[nk][1] = q[1];
        key[nk][2] = q[2];
        key[nk++][3] = (uint32_t)i;
    }
    qsort(key, nk, sizeof *key, cmp_u32x3);
    for (size_t k = 0; k < nk; k++) {
        if (k > 0 && !memcmp(key[k], key[k - 1], 3 * sizeof key[k][0])) {
            rep->duplicates++;
            continue;
        }
        keep[key[k][3]] = 1;
    }
    free(key);
    return 0;
}

/* The kept triangles' mesh: tri (kept -> soup index), their edges sorted by their ends, the
 * components across shared edges (up, union-find) and which are open (an edge not shared by
 * exactly two triangles opens its component), and each triangle's flip for a consistent
 * orientation. */
typedef struct {
    const uint32_t *vid, *tri;
    const double (*pos)[3];
    size_t nt;
    edge *e;
    uint32_t *up, *queue;
    int8_t *flip;
    uint8_t *open, *seen;
} kept_mesh;

static void mesh_components(kept_mesh *m)
{
    const size_t nt = m->nt;
    edge *e = m->e;
    for (size_t k = 0; k < nt; k++) {
        const uint32_t *t = m->vid + 3 * (size_t)m->tri[k];
        for (int j = 0; j < 3; j++) {
            uint32_t p = t[j], q = t[(j + 1) % 3];
            edge *x = &e[3 * k + (size_t)j];
            x->a = p < q ? p : q;
            x->b = p < q ? q : p;
            x->tri = (uint32_t)k;
            x->forward = p < q;
        }
        m->up[k] = (uint32_t)k;
    }
    qsort(e, 3 * nt, sizeof *e, cmp_edge);
    for (size_t i = 0; i < 3 * nt;) {
        size_t j = i;
        while (j < 3 * nt && e[j].a == e[i].a && e[j].b == e[i].b)
            j++;
        for (size_t k = i + 1; k < j; k++) {
            uint32_t r1 = find(m->up, e[i].tri), r2 = find(m->up, e[k].tri);
            if (r1 != r2)
                m->up[r1 > r2 ? r1 : r2] = r1 < r2 ? r1 : r2;
        }
        if (j - i != 2)
            for (size_t k = i; k < j; k++)
                m->open[e[k].tri] = 1;
        i = j;
    }
    for (size_t k = 0; k < nt; k++)
        if (m->open[k])
            m->open[find(m->up, (uint32_t)k)] = 1;
}

/* Orient the component of triangle start: across each edge shared by two triangles the
 * directions must differ; walk it breadth first from start. Its triangles are left in
 * queue[0 .. return). */
static size_t orient_component(kept_mesh *m, size_t start)
{
    const size_t nt = m->nt;
    const edge *e = m->e;
    size_t head = 0, tail = 0;
    m->queue[tail++] = (uint32_t)start;
    m->seen[start] = 1;
    while (head < tail) {
        const uint32_t t = m->queue[head++];
        const uint32_t *v = m->vid + 3 * (size_t)m->tri[t];
        for (int j = 0; j < 3; j++) {
            uint32_t p = v[j], q = v[(j + 1) % 3];
            edge probe = {p < q ? p : q, p < q ? q : p, 0, 0};
            /* the edge's group: the first record with these ends */
            size_t lo2 = 0, hi2 = 3 * nt;
            while (lo2 < hi2) {
                size_t mid = (lo2 + hi2) / 2;
                if (e[mid].a < probe.a || (e[mid].a == probe.a && e[mid].b < probe.b))
                    lo2 = mid + 1;
                else
                    hi2 = mid;
            }
            size_t end = lo2;
            while (end < 3 * nt && e[end].a == probe.a && e[end].b == probe.b)
                end++;
            if (end - lo2 != 2)
                continue;
            const edge *mine = e[lo2].tri == t ? &e[lo2] : &e[lo2 + 1];
            const edge *other = e[lo2].tri == t ? &e[lo2 + 1] : &e[lo2];
            if (m->seen[other->tri])
                continue;
            /* consistent when the two run the edge in opposite directions */
            const int mine_fwd = mine->forward ^ m->flip[t];
            m->flip[other->tri] = (int8_t)(other->forward == mine_fwd);
            m->seen[other->tri] = 1;
            m->queue[tail++] = other->tri;
        }
    }
    return tail;
}

/* Every component oriented; a closed one with negative signed volume turned inside out. */
static void mesh_orient(kept_mesh *m, mote_mesh_report *rep)
{
    for (size_t start = 0; start < m->nt; start++) {
        if (m->seen[start])
            continue;
        const size_t tail = orient_component(m, start);
        if (m->open[find(m->up, (uint32_t)start)]) {
            rep->open_components++;
            continue;
        }
        double vol = 0;
        for (size_t h = 0; h < tail; h++) {
            const uint32_t q = m->queue[h];
            const uint32_t *v = m->vid + 3 * (size_t)m->tri[q];
            const double *p0 = m->pos[v[0]], *p1 = m->pos[v[m->flip[q] ? 2 : 1]],
                         *p2 = m->pos[v[m->flip[q] ? 1 : 2]];
            vol += p0[0] * (p1[1] * p2[2] - p1[2] * p2[1]) -
                   p0[1] * (p1[0] * p2[2] - p1[2] * p2[0]) +
                   p0[2] * (p1[0] * p2[1] - p1[1] * p2[0]);
        }
        if (vol < 0)
            for (size_t h = 0; h < tail; h++)
                m->flip[m->queue[h]] ^= 1;
        rep->closed_components++;
    }
}

/* The kept triangles into m: the vertices they use (renumbered in order of first use), the
 * windings with the flips made, parts, components numbered in order of their first triangle. */
static int mesh_out(mote_mesh *out, const soup *s, const kept_mesh *m, mote_mesh_report *rep,
                    mote_err *err)
{
    const size_t nt = m->nt;
    size_t npos = 0;
    for (size_t k = 0; k < nt; k++)
        for (int j = 0; j < 3; j++) {
            const uint32_t v = m->vid[3 * (size_t)m->tri[k] + j];
            npos = v + 1 > npos ? v + 1 : npos;
        }
    uint32_t *vmap = malloc((npos ? npos : 1) * sizeof *vmap);
    uint32_t *cmap = malloc((nt ? nt : 1) * sizeof *cmap);
    out->v = malloc((npos ? npos : 1) * sizeof *out->v);
    out->t = malloc((nt ? nt : 1) * sizeof *out->t);
    out->part = malloc((nt ? nt : 1) * sizeof *out->part);
    out->comp = malloc((nt ? nt : 1) * sizeof *out->comp);
    out->closed = malloc(nt ? nt : 1);
    out->flipped = malloc(nt ? nt : 1);
    out->names = malloc((size_t)(s->nnames ? s->nnames : 1) * sizeof *out->names);
    if (!vmap || !cmap || !out->v || !out->t || !out->part || !out->comp || !out->closed ||
        !out->flipped || !out->names) {
        free(vmap);
        free(cmap);
        return mote_fail(err, MOTE_ENOMEM, "mesh: out of memory");
    }
    memcpy(out->names, s->names, (size_t)s->nnames * sizeof *out->names);
    out->nnames = s->nnames;
    for (size_t v = 0; v < npos; v++)
        vmap[v] = UINT32_MAX;
    for (size_t k = 0; k < nt; k++)
        cmap[k] = UINT32_MAX;
    size_t nv = 0, nc = 0;
    for (size_t k = 0; k < nt; k++) {
        const uint32_t *v = m->vid + 3 * (size_t)m->tri[k];
        const uint32_t w[3] = {v[0], v[m->flip[k] ? 2 : 1], v[m->flip[k] ? 1 : 2]};
        for (int j = 0; j < 3; j++) {
            if (vmap[w[j]] == UINT32_MAX) {
                memcpy(out->v[nv], m->pos[w[j]], sizeof out->v[0]);
                vmap[w[j]] = (uint32_t)nv++;
            }
            out->t[k][j] = vmap[w[j]];
        }
        const uint32_t root = find(m->up, (uint32_t)k);
        if (cmap[root] == UINT32_MAX)
            cmap[root] = (uint32_t)nc++;
        out->comp[k] = cmap[root];
        out->part[k] = s->part[m->tri[k]];
        out->closed[k] = !m->open[root];
        out->flipped[k] = (uint8_t)(m->flip[k] != 0);
        rep->flipped += out->flipped[k];
    }
    out->nv = nv;
    out->nt = nt;
    out->ncomp = nc;
    free(vmap);
    free(cmap);
    return MOTE_OK;
}

/* Repair the soup into out. */
static int repair(mote_mesh *out, soup *s, const char *path, mote_mesh_report *rep,
                  mote_err *err)
{
    rep->read = (uint32_t)s->n;
    const double L = soup_extent(s);
    if (!(L > 0) || !isfinite(L))
        return mote_fail(err, MOTE_EFORMAT, "%s: no triangle with a non-zero extent", path);
    uint32_t *vid = malloc((s->n ? 3 * s->n : 1) * sizeof *vid), npos = 0;
    double(*pos)[3] = NULL;
    if (!vid || weld(s, 1e-9 * L, vid, &pos, &npos, &rep->welded)) {
        free(vid);
        return mote_fail(err, MOTE_ENOMEM, "mesh: out of memory");
    }
    uint8_t *keep = calloc(s->n ? s->n : 1, 1);
    int rc = keep && !keep_triangles(s, vid, (const double(*)[3])pos, L, keep, rep)
                 ? MOTE_OK
                 : mote_fail(err, MOTE_ENOMEM, "mesh: out of memory");
    size_t nt = 0;
    uint32_t *tri = malloc((s->n ? s->n : 1) * sizeof *tri); /* kept -> soup index */
    for (size_t i = 0; !rc && tri && i < s->n; i++)
        if (keep[i])
            tri[nt++] = (uint32_t)i;
    kept_mesh m = {.vid = vid, .tri = tri, .pos = (const double(*)[3])pos, .nt = nt};
    m.e = malloc((nt ? 3 * nt : 1) * sizeof *m.e);
    m.up = malloc((nt ? nt : 1) * sizeof *m.up);
    m.flip = calloc(nt ? nt : 1, 1);
    m.open = calloc(nt ? nt : 1, 1);
    m.seen = calloc(nt ? nt : 1, 1);
    m.queue = malloc((nt ? nt : 1) * sizeof *m.queue);
    if (!rc && (!tri || !m.e || !m.up || !m.flip || !m.open || !m.seen || !m.queue))
        rc = mote_fail(err, MOTE_ENOMEM, "mesh: out of memory");
    if (!rc) {
        mesh_components(&m);
        mesh_orient(&m, rep);
        rc = mesh_out(out, s, &m, rep, err);
    }
    free(vid);
    free(pos);
    free(keep);
    free(tri);
    free(m.e);
    free(m.up);
    free(m.flip);
    free(m.open);
    free(m.seen);
    free(m.queue);
    return rc;
}

void mote_mesh_free(mote_mesh *m)
{
    free(m->v);
    free(m->t);
    free(m->part);
    free(m->comp);
    free(m->closed);
    free(m->flipped);
    free(m->names);
    memset(m, 0, sizeof *m);
}

int mote_mesh_is_plain(const char *path, const char *format)
{
    if (strcmp(format, "auto") != 0)
        return strcmp(format, "plain") == 0;
    /* extensions Assimp does not know: the plain format */
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char *dot = strrchr(base, '.');
    return !dot || !strcmp(dot, ".txt") || !strcmp(dot, ".dat") || !strcmp(dot, ".tri");
}

int mote_mesh_load(mote_mesh *out, const char *path, const mote_mesh_opts *o,
                   mote_mesh_report *rep, mote_err *err)
{
    memset(rep, 0, sizeof *rep);
    /* the part name when the file gives none: part= or the file's base name */
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    soup s = {0};
    mote_err e2 = {0};
    int fallback = soup_name(&s, o->part ? o->part : base, &e2);
    if (fallback < 0)
        return mote_fail(err, e2.code, "%s: %s", path, e2.msg);
    int rc = mote_mesh_is_plain(path, o->format)
                 ? read_plain(path, &s, fallback, o->strict, &rep->abandoned_lines,
                              &rep->trailing_numbers, err)
                 : read_assimp(path, &s, s.names[fallback], err);
    if (!rc && s.n == 0)
        rc = mote_fail(err, MOTE_EFORMAT, "%s: no triangles", path);
    /* scale, turn about the axis, move */
    const double th = o->rot_deg * 3.14159265358979323846 / 180, c = cos(th), sn = sin(th);
    for (size_t i = 0; !rc && i < s.n; i++)
        for (int j = 0; j < 3; j++) {
            double *p = s.v[i][j];
            for (int a = 0; a < 3; a++) {
                p[a] *= o->scale;
                if (!isfinite(p[a]))
                    rc = mote_fail(err, MOTE_EFORMAT, "%s: triangle %zu has a coordinate that is "
                                   "not a finite number", path, i + 1);
            }
            if (o->rot_axis >= 0) {
                const int u = (o->rot_axis + 1) % 3, w = (o->rot_axis + 2) % 3;
                const double pu = p[u], pw = p[w];
                p[u] = c * pu - sn * pw;
                p[w] = sn * pu + c * pw;
            }
            for (int a = 0; a < 3; a++)
                p[a] += o->offset[a];
        }
    mote_mesh m = {0};
    if (!rc)
        rc = repair(&m, &s, path, rep, err);
    if (!rc && rep->read == rep->degenerate + rep->duplicates)
        rc = mote_fail(err, MOTE_EFORMAT, "%s: every triangle is degenerate or a duplicate", path);
    soup_free(&s);
    if (rc) {
        mote_mesh_free(&m);
        return rc;
    }
    mote_mesh_free(out);
    *out = m;
    return MOTE_OK;
}

int mote_mesh_call_opts(const mote_call *c, const char *cmd, mote_mesh_opts *o, mote_err *err)
{
    memset(o, 0, sizeof *o);
    o->format = "auto";
    o->scale = 1;
    o->rot_axis = -1;
    const mote_arg *a;
    if ((a = mote_call_opt(c, "format"))) /* auto|plain|assimp */
        o->format = a->text;
    if ((a = mote_call_opt(c, "units"))) {
        static const double F[] = {1, 0.01, 0.001, 0.0254}; /* m|cm|mm|in */
        const int k = (int)a->i;
        if (mote_call_opt(c, "scale"))
            return mote_call_fail(err, c, mote_call_opt_index(c, "scale"), MOTE_EINVAL,
                                  "%s: give units= or scale=, not both", cmd);
        o->scale = F[k];
    }
    o->scale = mote_call_opt_r(c, "scale", o->scale);
    if ((a = mote_call_opt(c, "offset")))
        memcpy(o->offset, a->v, sizeof a->v);
    if ((a = mote_call_opt(c, "rotate"))) {
        char *end = NULL;
        const char ax = a->text[0];
        double deg = a->text[0] && a->text[1] == ',' ? strtod(a->text + 2, &end) : NAN;
        if ((ax != 'x' && ax != 'y' && ax != 'z') || !isfinite(deg) || *end)
            return mote_call_fail(err, c, mote_call_opt_index(c, "rotate"), MOTE_EINVAL,
                                  "%s: rotate: expected AXIS,DEGREES (x, y or z), found '%s'",
                                  cmd, a->text);
        o->rot_axis = ax - 'x';
        o->rot_deg = deg;
    }
    if ((a = mote_call_opt(c, "strict"))) /* yes|no */
        o->strict = a->i == 0;
    o->part = (a = mote_call_opt(c, "part")) ? a->text : NULL;
    return MOTE_OK;
}

void mote_mesh_report_line(FILE *log, const char *cmd, const char *path,
                           const mote_mesh_report *rep)
{
    fprintf(log, "%s: %u triangles read; %u degenerate and %u duplicate dropped, %u vertices "
                 "welded, %u turned to face outward; %u closed and %u open components (open "
                 "ones are two-sided sheets)%s\n",
            cmd, rep->read, rep->degenerate, rep->duplicates, rep->welded, rep->flipped,
            rep->closed_components, rep->open_components,
            rep->abandoned_lines ? "; some lines abandoned (see strict=yes)" : "");
    if (rep->trailing_numbers)
        fprintf(log, "%s: warning: %s ends inside a triangle (%d of 9 numbers, dropped; "
                     "strict=yes makes this an error)\n",
                cmd, path, rep->trailing_numbers);
}
