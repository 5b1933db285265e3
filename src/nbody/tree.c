/* tree.c: approximate forces with a Barnes-Hut octree (spec 6.2), for N beyond what the O(N^2)
 * sums allow. The tree is built once per step from the positions at the step's start, leaves of
 * at most NB_LEAF bodies. A cell is accepted for target i when its side over the distance from
 * x_i to its centre (weighted by the kernel weights w) is below theta and it does not hold i,
 * the distance first shortened by the offset delta of that centre from the cube's centre (Barnes
 * 1994: a centre near the cube's edge would otherwise let targets come too close); otherwise it
 * is opened, and an opened leaf gives its bodies one by one. The walk depends only
 * on the step's starting positions, so every pass of the step sees the same interaction list.
 * An accepted cell acts as a pseudo-body of weight W = sum w_j whose trajectory coefficients
 * (or position, velocity, acceleration, jerk in the Galactica scheme) are the w-weighted means of
 * its bodies', filled bottom up as the bodies' own become known; the pair recurrences of both
 * integrators then apply unchanged, at any order. Each target is summed by one thread over its
 * list in the walk's fixed order: the result does not depend on the number of threads. */
#include <stdlib.h>
#include <string.h>
#include <tgmath.h>

#include "nb.h"

#define NB_LEAF 8
#define NB_DEPTH 48

struct nb_tree {
    uint32_t ncell, cap, n;
    uint32_t *perm;        /* the active bodies, ordered by cell */
    uint32_t *pos;         /* a body's place in perm (UINT32_MAX: inactive) */
    uint32_t *start, *end; /* a cell's bodies: perm[start .. end) */
    uint32_t *child0;      /* its first child (children are consecutive), 0: a leaf */
    uint8_t *nchild;
    mote_real *side, *W;
    mote_real *delta;      /* the distance from a cell's cube centre to its weighted centre */
    mote_real *open2;      /* accepted beyond (delta + side / theta)^2 from the weighted centre */
    mote_real *com;        /* [3C] the w-weighted centre at the step's start (acceptance) */
    mote_real *cd;         /* cell data: blocks of 3C (Galactica: x v a j; Taylor: orders) */
    size_t cd_blocks;
};

void nb_tree_free(mote_nb *nb)
{
    nb_tree *t = nb->tree;
    if (!t)
        return;
    void *p[] = {t->perm, t->pos, t->start, t->end, t->child0, t->nchild, t->side, t->W, t->com,
                 t->cd, t->delta, t->open2};
    for (size_t k = 0; k < sizeof p / sizeof p[0]; k++)
        free(p[k]);
    free(t);
    nb->tree = NULL;
}

int nb_tree_check(mote_nb *nb, int blocks, mote_err *err)
{
    if (!nb->tree_on)
        return MOTE_OK;
    /* one sign of weight: the centre of a cell of mixed charges is undefined (spec 6.2) */
    int pos = 0, neg = 0;
    for (uint32_t i = 0; i < nb->n; i++)
        if (nb->active[i]) {
            pos |= nb->w[i] > 0;
            neg |= nb->w[i] < 0;
        }
    if (pos && neg)
        return mote_fail(err, MOTE_EINVAL, "forces tree: the charges have both signs; a cell of "
                                           "mixed charges has no centre (use forces direct)");
    nb_tree *t = nb->tree;
    if (!t) {
        t = calloc(1, sizeof *t);
        if (!t)
            return mote_fail(err, MOTE_ENOMEM, "forces tree: out of memory");
        nb->tree = t;
    }
    /* room for 2 N + 64 cells: a build that would need more makes larger leaves instead */
    const uint32_t cap = 2 * nb->n + 64;
    if (t->n != nb->n || t->cap != cap || t->cd_blocks < (size_t)blocks) {
        const size_t C = cap, nbk = (size_t)blocks > t->cd_blocks ? (size_t)blocks : t->cd_blocks;
        const size_t r = sizeof(mote_real), u = sizeof(uint32_t);
        struct {
            void **p;
            size_t bytes;
        } arr[] = {{(void **)&t->start, C * u},         {(void **)&t->end, C * u},
                   {(void **)&t->child0, C * u},        {(void **)&t->perm, (nb->n + 1) * u},
                   {(void **)&t->pos, (nb->n + 1) * u}, {(void **)&t->nchild, C},
                   {(void **)&t->side, C * r},          {(void **)&t->W, C * r},
                   {(void **)&t->delta, C * r},         {(void **)&t->open2, C * r},
                   {(void **)&t->com, 3 * C * r},       {(void **)&t->cd, nbk * 3 * C * r}};
        int fail = 0;
        for (size_t k = 0; k < sizeof arr / sizeof arr[0]; k++) {
            void *q = realloc(*arr[k].p, arr[k].bytes);
            fail |= !q;
            if (q)
                *arr[k].p = q;
        }
        if (fail) {
            nb_tree_free(nb);
            return mote_fail(err, MOTE_ENOMEM, "forces tree: out of memory for %u bodies", nb->n);
        }
        t->cap = cap;
        t->n = nb->n;
        t->cd_blocks = nbk;
    }
    return MOTE_OK;
}

/* Fill the cells' block b (3 reals a cell) from the bodies' src (3 reals a body), bottom up:
 * a leaf's the w-weighted mean of its bodies, a parent's the W-weighted mean of its children. */
static void fill(const mote_nb *nb, nb_tree *t, const mote_real *src, mote_real *dst)
{
    for (uint32_t c = t->ncell; c-- > 0;) {
        mote_real s[3] = {0, 0, 0};
        if (t->child0[c]) {
            for (uint32_t k = t->child0[c]; k < t->child0[c] + t->nchild[c]; k++)
                for (int a = 0; a < 3; a++)
                    s[a] += t->W[k] * dst[3 * (size_t)k + a];
        } else {
            for (uint32_t p = t->start[c]; p < t->end[c]; p++) {
                const uint32_t i = t->perm[p];
                for (int a = 0; a < 3; a++)
                    s[a] += nb->w[i] * src[3 * (size_t)i + a];
            }
        }
        for (int a = 0; a < 3; a++)
            dst[3 * (size_t)c + a] = s[a] / t->W[c];
    }
}

void nb_tree_build(mote_nb *nb)
{
    nb_tree *t = nb->tree;
    uint32_t na = 0;
    mote_real lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < nb->n; i++) {
        t->pos[i] = UINT32_MAX;
        if (!nb->active[i])
            continue;
        t->perm[na++] = i;
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], nb->x[3 * (size_t)i + a]);
            hi[a] = fmax(hi[a], nb->x[3 * (size_t)i + a]);
        }
    }
    t->ncell = 0;
    if (!na)
        return;
    mote_real side = 0, ctr[3];
    for (int a = 0; a < 3; a++) {
        side = fmax(side, hi[a] - lo[a]);
        ctr[a] = (lo[a] + hi[a]) / 2;
    }
    side = side > 0 ? side * (1 + 1e-12) : 1;
    /* cells in breadth-first order (children after parents); each cell's geometric centre in
     * com while building, replaced by the weighted centre at the end */
    t->ncell = 1;
    t->start[0] = 0;
    t->end[0] = na;
    t->side[0] = side;
    for (int a = 0; a < 3; a++)
        t->com[a] = ctr[a];
    uint32_t *tmp = t->pos; /* (pos is set at the end; its room serves as scratch here) */
    uint8_t depth_of_level = 0;
    uint32_t level_end = 1;
    for (uint32_t c = 0; c < t->ncell; c++) {
        if (c == level_end) {
            level_end = t->ncell;
            depth_of_level++;
        }
        t->child0[c] = 0;
        t->nchild[c] = 0;
        const uint32_t s0 = t->start[c], e0 = t->end[c];
        if (e0 - s0 <= NB_LEAF || depth_of_level >= NB_DEPTH || t->ncell + 8 > t->cap)
            continue;
        const mote_real *m = t->com + 3 * (size_t)c;
        uint32_t count[8] = {0};
        for (uint32_t p = s0; p < e0; p++) {
            const mote_real *x = nb->x + 3 * (size_t)t->perm[p];
            const int o = (x[0] >= m[0]) | (x[1] >= m[1]) << 1 | (x[2] >= m[2]) << 2;
            count[o]++;
        }
        uint32_t at[8], run = s0;
        for (int o = 0; o < 8; o++) {
            at[o] = run;
            run += count[o];
        }
        for (uint32_t p = s0; p < e0; p++) { /* a stable counting sort into tmp */
            const uint32_t i = t->perm[p];
            const mote_real *x = nb->x + 3 * (size_t)i;
            const int o = (x[0] >= m[0]) | (x[1] >= m[1]) << 1 | (x[2] >= m[2]) << 2;
            tmp[at[o]++] = i;
        }
        memcpy(t->perm + s0, tmp + s0, (e0 - s0) * sizeof *tmp);
        t->child0[c] = t->ncell;
        run = s0;
        for (int o = 0; o < 8; o++) {
            if (!count[o])
                continue;
            const uint32_t k = t->ncell++;
            t->start[k] = run;
            t->end[k] = run + count[o];
            run += count[o];
            t->side[k] = t->side[c] / 2;
            for (int a = 0; a < 3; a++)
                t->com[3 * (size_t)k + a] = m[a] + ((o >> a) & 1 ? 1 : -1) * t->side[k] / 2;
            t->nchild[c]++;
        }
    }
    for (uint32_t p = 0; p < nb->n; p++)
        t->pos[p] = UINT32_MAX;
    for (uint32_t p = 0; p < na; p++)
        t->pos[t->perm[p]] = p;
    for (uint32_t c = t->ncell; c-- > 0;) { /* the weights, bottom up */
        mote_real W = 0;
        if (t->child0[c])
            for (uint32_t k = t->child0[c]; k < t->child0[c] + t->nchild[c]; k++)
                W += t->W[k];
        else
            for (uint32_t p = t->start[c]; p < t->end[c]; p++)
                W += nb->w[t->perm[p]];
        t->W[c] = W;
    }
    /* (com holds the cubes' geometric centres until fill replaces them by the weighted ones:
     * the offset delta between the two goes into the acceptance test) */
    for (uint32_t c = 0; c < t->ncell; c++)
        for (int a = 0; a < 3; a++)
            t->cd[3 * (size_t)c + a] = t->com[3 * (size_t)c + a];
    fill(nb, t, nb->x, t->com);
    for (uint32_t c = 0; c < t->ncell; c++) {
        mote_real d2 = 0;
        for (int a = 0; a < 3; a++) {
            const mote_real d = t->com[3 * (size_t)c + a] - t->cd[3 * (size_t)c + a];
            d2 += d * d;
        }
        t->delta[c] = sqrt(d2);
        /* side / (d - delta) < theta  <=>  d > delta + side / theta (no square root per test) */
        const mote_real r = nb->theta > 0 ? t->delta[c] + t->side[c] / nb->theta : INFINITY;
        t->open2[c] = r * r;
    }
}

void nb_tree_fill(mote_nb *nb, int block, const mote_real *src)
{
    nb_tree *t = nb->tree;
    fill(nb, t, src, t->cd + (size_t)block * 3 * t->cap);
}

const mote_real *nb_tree_block(const mote_nb *nb, int block)
{
    return nb->tree->cd + (size_t)block * 3 * nb->tree->cap;
}

/* Walk the tree for target i: visit(src, is_cell, arg) for every source in the fixed order. */
void nb_tree_walk(const mote_nb *nb, uint32_t i, void (*visit)(uint32_t, int, void *), void *arg)
{
    const nb_tree *t = nb->tree;
    if (!t->ncell)
        return;
    const mote_real *xi = nb->x + 3 * (size_t)i;
    const uint32_t pi = t->pos[i];
    uint32_t stack[8 * NB_DEPTH + 16];
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
        const uint32_t c = stack[--sp];
        const int holds = pi >= t->start[c] && pi < t->end[c];
        if (!holds) {
            const mote_real *m = t->com + 3 * (size_t)c;
            const mote_real d0 = xi[0] - m[0], d1 = xi[1] - m[1], d2 = xi[2] - m[2];
            const mote_real d2s = d0 * d0 + d1 * d1 + d2 * d2;
            if (d2s > t->open2[c]) { /* side / (d - delta) < theta: accepted */
                visit(c, 1, arg);
                continue;
            }
        }
        if (!t->child0[c]) {
            for (uint32_t p = t->start[c]; p < t->end[c]; p++)
                if (t->perm[p] != i)
                    visit(t->perm[p], 0, arg);
            continue;
        }
        /* children pushed last first, so they are visited in octant order */
        for (uint32_t k = t->child0[c] + t->nchild[c]; k-- > t->child0[c];)
            stack[sp++] = k;
    }
}

mote_real nb_tree_weight(const mote_nb *nb, uint32_t cell) { return nb->tree->W[cell]; }

const uint32_t *nb_tree_order(const mote_nb *nb, uint32_t *count)
{
    *count = nb->tree->ncell ? nb->tree->end[0] : 0;
    return nb->tree->perm;
}

/* The walk's sources as a list: src[k] a body, or NB_TREE_CELL | cell. */
typedef struct {
    uint32_t *src;
    size_t n, cap;
    int failed;
} list_acc;

static void collect(uint32_t s, int cell, void *arg)
{
    list_acc *l = arg;
    if (l->n == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 1024;
        uint32_t *p = realloc(l->src, cap * sizeof *p);
        if (!p) {
            l->failed = 1;
            return;
        }
        l->src = p;
        l->cap = cap;
    }
    l->src[l->n++] = cell ? NB_TREE_CELL | s : s;
}

size_t nb_tree_list(const mote_nb *nb, uint32_t i, uint32_t **src, size_t *cap)
{
    list_acc l = {*src, 0, *cap, 0};
    nb_tree_walk(nb, i, collect, &l);
    *src = l.src;
    *cap = l.cap;
    return l.failed ? (size_t)-1 : l.n;
}
