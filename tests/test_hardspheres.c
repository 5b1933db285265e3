/* test_hardspheres.c: the hard-sphere model's commands through the library API.
 *
 * - compression (spec 7.6, 10 item 16): each variant 0.40 -> 0.45 -> 0.40 ends exactly on L*,
 *   with eta to 1e-12 and no overlap; a replay of the spec's algorithm written here gives a
 *   bit-identical state (so the right gap limits each move and the right wall moves); a single
 *   move without dynamics shifts the particles by exactly dL, dL/2 or 0; errors;
 * - image (spec 8.2): the file integrates to N exactly, its bins and columns are consistent, and
 *   the wall layering of spec 10 item 7 (contact maximum, spacing of the first three maxima in
 *   [1.7, 2.3] R) at eta 0.40 and 0.45;
 * - profile (spec 8.3): every row is inside the slab and the box, the rows equal a direct count
 *   of the state, sampling order, errors;
 * - measurements do not perturb the trajectory (spec 6.8): image K and profile ... K end in the
 *   state step K reaches, bit for bit. */
#include "mote/hardspheres.h"

#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "test.h"

static int sanitized;
static char tmpdir[256];

#define SPHERE_V (4.0 / 3.0 * MOTE_PI)

static void tmp_path(char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "%s/%s", tmpdir, name);
}

static int file_exists(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0;
}

static int same_state(const mote_ev *a, const mote_ev *b)
{
    return a->n == b->n && memcmp(a->p, b->p, a->n * sizeof *a->p) == 0 &&
           memcmp(a->heap, b->heap, a->n * sizeof *a->heap) == 0 && a->clock == b->clock &&
           a->time_total == b->time_total && a->collisions == b->collisions &&
           a->wall_collisions == b->wall_collisions &&
           memcmp(a->len, b->len, sizeof a->len) == 0;
}

static double brute_min_ratio(const mote_ev *ev)
{
    double best = INFINITY;
    double(*r)[3] = malloc(ev->n * sizeof *r);
    for (uint32_t i = 0; i < ev->n; i++)
        mote_ev_position(ev, i, r[i]);
    for (uint32_t i = 0; i < ev->n; i++)
        for (uint32_t j = i + 1; j < ev->n; j++) {
            double s = 0;
            for (int a = 0; a < ev->dim; a++) {
                double d = r[i][a] - r[j][a];
                if (ev->periodic[a])
                    d -= ev->len[a] * nearbyint(d / ev->len[a]);
                s += d * d;
            }
            double ratio = sqrt(s) / (mote_ev_radius(ev, i) + mote_ev_radius(ev, j));
            if (ratio < best)
                best = ratio;
        }
    free(r);
    return best;
}

/* A seeded and equilibrated slit. */
static void make_slit(mote_hs *hs, int64_t nn, double eta, uint64_t seed, uint64_t equil)
{
    mote_err err = {0};
    mote_hs_init(hs, NULL);
    mote_hs_seed(hs, test_seed(seed));
    CHECK(mote_hs_new(hs, nn, eta, &err) == MOTE_OK, "new %lld %g: %s", (long long)nn, eta,
          err.msg);
    if (equil)
        CHECK(mote_hs_step(hs, equil, &err) == MOTE_OK, "step: %s", err.msg);
}

/* ---- compression ----------------------------------------------------------------------------- */

/* The compress loop of spec 7.6, written from the spec's pseudo-code with the engine API. */
static int spec_compress(mote_hs *hs, int which, double eta, double dlmax, uint64_t k,
                         uint64_t *nmoves)
{
    mote_ev *ev = &hs->ev;
    mote_err err = {0};
    const double target = mote_hs_target_length(hs, eta), s = 1.1;
    *nmoves = 0;
    if (ev->len[0] == target)
        return MOTE_OK;
    int final = 0;
    while (!final) {
        /* gaps on positions projected to the clock (compress.c moves the walls in place
         * instead of rebuilding; see its opening comment) */
        double gl = INFINITY, gr = INFINITY, L = ev->len[0], delta;
        for (uint32_t i = 0; i < ev->n; i++) {
            double x = ev->p[i].r[0] + ev->p[i].v[0] * (ev->clock - ev->p[i].t);
            gl = fmin(gl, x - mote_ev_radius(ev, i));
            gr = fmin(gr, L - mote_ev_radius(ev, i) - x);
        }
        if (L > target) {
            double D = L - target;
            double cap = which == MOTE_HS_LEFT    ? gl / s
                         : which == MOTE_HS_RIGHT ? gr / s
                                                  : 2 * fmin(gl, gr) / s;
            delta = fmin(cap, dlmax);
            final = delta >= D;
            if (final)
                delta = D;
            else if (delta < 1e-13 * L)
                delta = 0;
        } else {
            double D = target - L;
            delta = -fmin(D, dlmax);
            final = D <= dlmax;
        }
        double shift = which == MOTE_HS_LEFT ? delta : which == MOTE_HS_BOTH ? delta / 2 : 0;
        if (mote_ev_move_walls(ev, 0, shift, final ? target : L - delta, &err))
            return MOTE_ERUNTIME;
        (*nmoves)++;
        if (mote_ev_run(ev, k * ev->n / 2, &err))
            return MOTE_ERUNTIME;
    }
    return MOTE_OK;
}

static const char *const variant_name[3] = {"left", "right", "both"};

static void test_compress(void)
{
    printf("compression (spec 7.6, 10 item 16)\n");
    mote_err err = {0};

    /* L* = 2 R + sum v / (eta A^2) */
    {
        mote_hs hs;
        make_slit(&hs, 3, 0.4, 1, 0);
        double A = hs.ev.len[1];
        double want = 2 + hs.ev.n * SPHERE_V / (0.45 * A * A);
        CHECK(fabs(mote_hs_target_length(&hs, 0.45) - want) <= 1e-14 * want,
              "target length %.17g, expected %.17g", mote_hs_target_length(&hs, 0.45), want);
        mote_hs_free(&hs);
    }

    /* One move without dynamics (K = 0, dLmax above the whole change; expansion has no gap
     * limit): left shifts every x by exactly +D, both by D/2, right not at all; y, z and v are
     * untouched; L lands exactly on L*. */
    for (int w = 0; w < 3; w++) {
        mote_hs hs;
        make_slit(&hs, 2, 0.45, 3, 5);
        mote_ev_rebuild(&hs.ev, &err); /* synchronised, so p.r are the positions */
        uint32_t n = hs.ev.n;
        mote_particle *before = malloc(n * sizeof *before);
        for (uint32_t id = 0; id < n; id++) /* by number: a rebuild may reorder the records */
            before[id] = hs.ev.p[mote_ev_slot(&hs.ev, id)];
        double target = mote_hs_target_length(&hs, 0.40);
        double D = target - hs.ev.len[0];
        CHECK(mote_hs_compress(&hs, w, 0.40, 1e9, 0, &err) == MOTE_OK, "%s", err.msg);
        CHECK(hs.ev.len[0] == target, "%s: L = %.17g, L* = %.17g", variant_name[w], hs.ev.len[0],
              target);
        double shift = w == MOTE_HS_LEFT ? D : w == MOTE_HS_BOTH ? D / 2 : 0, worst = 0;
        int others = 1;
        for (uint32_t id = 0; id < n; id++) {
            const mote_particle *q = &hs.ev.p[mote_ev_slot(&hs.ev, id)];
            worst = fmax(worst, fabs(q->r[0] - (before[id].r[0] + shift)));
            others &= q->r[1] == before[id].r[1] && q->r[2] == before[id].r[2] &&
                      memcmp(q->v, before[id].v, sizeof before[id].v) == 0;
        }
        CHECK(worst <= 1e-13 * target, "%s: x shifted wrongly by up to %.3g (expected shift %.6g)",
              variant_name[w], worst, shift);
        CHECK(others, "%s: y, z or v changed in a wall move", variant_name[w]);
        CHECK(mote_ev_check(&hs.ev, &err) == MOTE_OK, "%s: %s", variant_name[w], err.msg);
        printf("  one move %s: dL = %.6f, particle shift %.6f, exact to %.2g\n", variant_name[w],
               D, shift, worst);
        free(before);
        mote_hs_free(&hs);
    }

    /* Full cycles with dynamics: 0.40 -> 0.45 -> 0.40, each variant; compared with the replay
     * of the spec algorithm on an identical system, bit for bit. */
    int64_t nn = sanitized ? 2 : 3; /* not statistical: a smaller system is as good a test */
    double dlmax = 0.1;
    uint64_t k = 1;
    for (int w = 0; w < 3; w++) {
        mote_hs hs, ref;
        make_slit(&hs, nn, 0.40, 11, 20);
        make_slit(&ref, nn, 0.40, 11, 20);
        double w0 = mote_wall_seconds();
        const double etas[2] = {0.45, 0.40};
        for (int leg = 0; leg < 2; leg++) {
            double eta = etas[leg];
            uint64_t c0 = hs.ev.collisions, refmoves = 0;
            double L0 = hs.ev.len[0];
            int rc = mote_hs_compress(&hs, w, eta, dlmax, k, &err);
            CHECK(rc == MOTE_OK, "%s to %.2f: %s", variant_name[w], eta, err.msg);
            double target = mote_hs_target_length(&hs, eta);
            CHECK(hs.ev.len[0] == target, "%s to %.2f: L = %.17g, L* = %.17g", variant_name[w], eta,
                  hs.ev.len[0], target);
            double got = mote_hs_eta(&hs);
            CHECK(fabs(got - eta) <= 1e-12 * eta, "%s to %.2f: eta = %.17g", variant_name[w], eta,
                  got);
            CHECK(mote_ev_check(&hs.ev, &err) == MOTE_OK, "%s to %.2f: %s", variant_name[w], eta,
                  err.msg);
            double ratio = brute_min_ratio(&hs.ev);
            CHECK(ratio >= 1 - 1e-10, "%s to %.2f: overlap, closest pair at %.17g", variant_name[w],
                  eta, ratio);
            CHECK(spec_compress(&ref, w, eta, dlmax, k, &refmoves) == MOTE_OK, "replay failed");
            CHECK(same_state(&hs.ev, &ref.ev),
                  "%s to %.2f: the state differs from the replay of the spec 7.6 algorithm",
                  variant_name[w], eta);
            printf("  %s %.2f -> %.2f: L %.4f -> %.4f in %llu moves, %llu collisions; replay "
                   "identical: %s\n",
                   variant_name[w], leg ? 0.45 : 0.40, eta, L0, hs.ev.len[0],
                   (unsigned long long)refmoves, (unsigned long long)(hs.ev.collisions - c0),
                   same_state(&hs.ev, &ref.ev) ? "yes" : "NO");
        }
        printf("  %s cycle: %.2f s\n", variant_name[w], mote_wall_seconds() - w0);
        /* the replay must be able to tell the variants apart: another variant's replay differs */
        mote_hs other;
        make_slit(&other, nn, 0.40, 11, 20);
        uint64_t m;
        spec_compress(&other, (w + 1) % 3, 0.45, dlmax, k, &m);
        spec_compress(&other, (w + 1) % 3, 0.40, dlmax, k, &m);
        CHECK(!same_state(&hs.ev, &other.ev), "variants %s and %s give the same state",
              variant_name[w], variant_name[(w + 1) % 3]);
        mote_hs_free(&other);
        mote_hs_free(&hs);
        mote_hs_free(&ref);
    }

    /* Stress (spec 10 item 14): a slit compressed to 0.55 with both walls; the checker never
     * fails (run after every leg), energy unchanged. */
    {
        mote_hs hs;
        make_slit(&hs, 2, 0.45, 5, 10);
        double E0 = mote_ev_energy(&hs.ev), w0 = mote_wall_seconds();
        const double etas[3] = {0.50, 0.53, 0.55};
        for (int leg = 0; leg < 3; leg++) {
            CHECK(mote_hs_compress(&hs, MOTE_HS_BOTH, etas[leg], 0.05, 2, &err) == MOTE_OK,
                  "to %.2f: %s", etas[leg], err.msg);
            CHECK(mote_ev_check(&hs.ev, &err) == MOTE_OK, "at %.2f: %s", etas[leg], err.msg);
        }
        CHECK(hs.ev.len[0] == mote_hs_target_length(&hs, 0.55), "0.55 not reached exactly");
        CHECK(brute_min_ratio(&hs.ev) >= 1 - 1e-10, "overlap at 0.55");
        CHECK(fabs(mote_ev_energy(&hs.ev) - E0) <= 1e-12 * E0, "energy changed by compression");
        mote_ev_run(&hs.ev, 50 * hs.ev.n, &err);
        CHECK(mote_ev_check(&hs.ev, &err) == MOTE_OK, "running at 0.55: %s", err.msg);
        printf("  new 2 compressed to 0.55 (both walls) and run: %.2f s\n",
               mote_wall_seconds() - w0);
        mote_hs_free(&hs);
    }

    /* already at the target: nothing runs; errors */
    {
        mote_hs hs;
        make_slit(&hs, 2, 0.40, 1, 0);
        double L = mote_hs_target_length(&hs, 0.40);
        hs.ev.len[0] = L; /* make it exact: seeding may differ from L* in the last bit */
        mote_ev_rebuild(&hs.ev, &err);
        uint64_t c0 = hs.ev.collisions;
        CHECK(mote_hs_compress(&hs, MOTE_HS_LEFT, 0.40, 0.1, 5, &err) == MOTE_OK, "%s", err.msg);
        CHECK(hs.ev.collisions == c0, "compress to the current density ran dynamics");
        CHECK(mote_hs_compress(&hs, MOTE_HS_LEFT, 0.75, 0.1, 1, &err) == MOTE_EINVAL,
              "eta 0.75 > close packing accepted");
        CHECK(mote_hs_compress(&hs, MOTE_HS_LEFT, 0.0, 0.1, 1, &err) == MOTE_EINVAL,
              "eta 0 accepted");
        CHECK(mote_hs_compress(&hs, MOTE_HS_RIGHT, 0.45, 0.0, 1, &err) == MOTE_EINVAL,
              "dLmax 0 accepted");
        mote_hs_free(&hs);
        mote_hs_init(&hs, NULL);
        CHECK(mote_hs_compress(&hs, MOTE_HS_LEFT, 0.45, 0.1, 1, &err) == MOTE_EINVAL,
              "compress without a system accepted");
        mote_hs_bulk(&hs, 32, 0.3, &err);
        CHECK(mote_hs_compress(&hs, MOTE_HS_BOTH, 0.35, 0.1, 1, &err) == MOTE_EINVAL,
              "compress of a periodic box accepted");
        CHECK_HAS(err.msg, "periodic");
        mote_hs_free(&hs);
    }
}

/* ---- data files -------------------------------------------------------------------------------- */

typedef struct {
    double *col[8];
    int ncol, nrow, cap;
    double samples, A, L, bin_width;
    long rows_header;
    int has_rows_header;
} table;

static void table_free(table *t)
{
    for (int c = 0; c < 8; c++)
        free(t->col[c]);
    memset(t, 0, sizeof *t);
}

/* Read a data file: "# key = value" header lines and rows of numbers. Returns 0 on success. */
static int table_read(const char *path, table *t, int ncol)
{
    memset(t, 0, sizeof *t);
    t->ncol = ncol;
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    char line[4096];
    int bad = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#') {
            sscanf(line, "# samples = %lf", &t->samples);
            sscanf(line, "# A = %lf", &t->A);
            sscanf(line, "# L = %lf", &t->L);
            sscanf(line, "# bin_width = %lf", &t->bin_width);
            if (sscanf(line, "# rows = %ld", &t->rows_header) == 1)
                t->has_rows_header = 1;
            continue;
        }
        if (t->nrow == t->cap) {
            t->cap = t->cap ? 2 * t->cap : 256;
            for (int c = 0; c < ncol; c++)
                t->col[c] = realloc(t->col[c], (size_t)t->cap * sizeof(double));
        }
        char *p = line, *end;
        for (int c = 0; c < ncol; c++) {
            t->col[c][t->nrow] = strtod(p, &end);
            if (end == p)
                bad = 1;
            p = end;
        }
        while (*p == ' ' || *p == '\n')
            p++;
        if (*p)
            bad = 1; /* more columns than expected */
        t->nrow++;
    }
    fclose(f);
    return bad ? -2 : 0;
}

/* ---- image --------------------------------------------------------------------------------------- */

/* Consistency of an image file with the system it came from: bins, totals, columns. */
static void check_image_file(const char *path, const mote_hs *hs, uint64_t samples, int64_t p,
                             const char *label)
{
    table t;
    int rc = table_read(path, &t, 7);
    CHECK(rc == 0, "%s: cannot parse %s (%d)", label, path, rc);
    if (rc) {
        table_free(&t);
        return;
    }
    double A2 = mote_hs_cross_section(hs), L = hs->ev.len[0], delta = 1.0 / (double)p;
    double N = hs->ev.n, v1 = hs->ev.dim == 3 ? SPHERE_V : MOTE_PI;
    int slit = hs->geometry == MOTE_HS_SLIT;
    CHECK(t.samples == (double)samples, "%s: header says %g samples, expected %llu", label,
          t.samples, (unsigned long long)samples);
    int W = (int)ceil(L / delta);
    CHECK(t.nrow == W, "%s: %d bins, expected ceil(L/dx) = %d", label, t.nrow, W);
    double counts = 0, integral = 0, vol = 0, err_bad = 0, first_bad = 0;
    int geom_ok = 1, low_empty = 1;
    for (int b = 0; b < t.nrow; b++) {
        double lo = t.col[0][b], hi = t.col[1][b], mid = t.col[2][b], w = hi - lo;
        geom_ok &= fabs(lo - b * delta) < 1e-9 && fabs(mid - 0.5 * (lo + hi)) < 1e-9 &&
                   (b + 1 == t.nrow ? fabs(hi - L) < 1e-9 : fabs(w - delta) < 1e-9);
        counts += t.col[3][b];
        integral += t.col[4][b] * A2 * w;
        vol += t.col[6][b] * A2 * w;
        if (slit && hi <= 0.9 && t.col[3][b] != 0)
            low_empty = 0; /* centres are >= R = 1 from the wall */
        if (samples >= 2 && !(t.col[5][b] >= 0))
            err_bad++;
        if (t.col[4][b] < 0)
            first_bad++;
    }
    CHECK(geom_ok, "%s: bins are not [b dx, (b+1) dx) ending at L", label);
    CHECK(counts == N * (double)samples, "%s: counts sum to %.17g, expected N S = %.17g", label,
          counts, N * (double)samples);
    CHECK(fabs(integral - N) <= 1e-9 * N, "%s: rho integrates to %.17g, expected N = %g", label,
          integral, N);
    CHECK(fabs(vol - N * v1) <= 1e-9 * N * v1,
          "%s: rho_v integrates to %.17g, expected N v = %.17g", label, vol, N * v1);
    CHECK(low_empty, "%s: a bin below x = 0.9 holds centres", label);
    CHECK(err_bad == 0 && first_bad == 0, "%s: %g bad error values, %g negative densities", label,
          err_bad, first_bad);
    table_free(&t);
}

/* Layering (spec 10 item 7): the first maximum of the raw profile is the contact bin (x in
 * [1, 1.2]); the next two maxima are found on the profile smoothed with a 5-bin (0.5 R) moving
 * average, the smoothing the spec itself uses to find layers (8.6); it is four times narrower
 * than the ~2 R layer spacing, so it cannot move a (symmetric) layer maximum, and it suppresses
 * the bin-to-bin noise that would otherwise create spurious local maxima. Each maximum is the
 * highest point 1.0 .. 3.0 R beyond the previous one; to be counted as a layer it must stand
 * above the minimum before it by more than 3 standard errors of that difference, so that a flat
 * profile cannot pass by chance. The error of a 5-bin mean is the raw bins' block error / sqrt 5
 * (neighbouring bins hold different spheres, so their block means are close to independent), and
 * the maximum and the minimum, ~1 R apart, add in quadrature. Both walls are checked (the right
 * one mirrored). */
static void check_layering(const char *path, const char *label)
{
    table t;
    if (table_read(path, &t, 7)) {
        CHECK(0, "%s: cannot read %s", label, path);
        return;
    }
    int n = t.nrow;
    for (int side = 0; side < 2; side++) {
        /* profile seen from the wall: x measured from that wall */
        double *x = malloc((size_t)n * sizeof *x), *rho = malloc((size_t)n * sizeof *rho);
        double *er = malloc((size_t)n * sizeof *er), *sm = malloc((size_t)n * sizeof *sm);
        for (int b = 0; b < n; b++) {
            int src = side ? n - 1 - b : b;
            x[b] = side ? t.L - t.col[2][src] : t.col[2][src];
            rho[b] = t.col[4][src];
            er[b] = t.col[5][src];
        }
        for (int b = 0; b < n; b++) {
            double s = 0;
            int m = 0;
            for (int q = b - 2; q <= b + 2; q++)
                if (q >= 0 && q < n) {
                    s += rho[q];
                    m++;
                }
            sm[b] = s / m;
        }
        /* first maximum: the raw profile's highest bin within 2 R of the wall */
        int first = 0;
        for (int b = 0; b < n && x[b] < 2.0; b++)
            if (rho[b] > rho[first])
                first = b;
        CHECK(x[first] >= 1.0 && x[first] <= 1.2,
              "%s, %s wall: first maximum at x = %.3f, expected contact [1, 1.2]", label,
              side ? "right" : "left", x[first]);
        double xm[3] = {x[first], 0, 0};
        int prev = first;
        for (int m = 1; m < 3; m++) {
            int best = -1;
            for (int b = prev + 1; b < n && x[b] <= xm[m - 1] + 3.0; b++)
                if (x[b] >= xm[m - 1] + 1.0 && (best < 0 || sm[b] > sm[best]))
                    best = b;
            if (best < 0) {
                CHECK(0, "%s: no maximum %d found", label, m + 1);
                break;
            }
            int lo = prev;
            for (int b = prev; b <= best; b++)
                if (sm[b] < sm[lo])
                    lo = b;
            xm[m] = x[best];
            double spacing = xm[m] - xm[m - 1];
            double contrast = sm[best] - sm[lo];
            double noise = sqrt(er[best] * er[best] + er[lo] * er[lo]) / sqrt(5.0);
            /* bin centres 0.1 R apart, mirrored from L on the right: the bounds are inclusive,
             * up to the rounding of those differences */
            CHECK(spacing >= 1.7 - 1e-9 && spacing <= 2.3 + 1e-9,
                  "%s, %s wall: maxima %d and %d are %.3f R apart, expected [1.7, 2.3]", label,
                  side ? "right" : "left", m, m + 1, spacing);
            CHECK(contrast > 3 * noise,
                  "%s, %s wall: maximum %d stands only %.4f above the minimum (3 errors = %.4f)",
                  label, side ? "right" : "left", m + 1, contrast, 3 * noise);
            printf("  %s, %s wall: maximum %d at %.2f (spacing %.2f), %.3f above the minimum "
                   "at %.2f (error %.4f)\n",
                   label, side ? "right" : "left", m + 1, xm[m], spacing, contrast, x[lo], noise);
            prev = best;
        }
        printf("  %s, %s wall: first maximum at %.2f, rho = %.4f\n", label,
               side ? "right" : "left", x[first], rho[first]);
        free(x);
        free(rho);
        free(er);
        free(sm);
    }
    table_free(&t);
}

static void test_image(void)
{
    printf("image (spec 8.2)\n");
    mote_err err = {0};
    char path[512];
    tmp_path(path, sizeof path, "image.txt");

    /* one sample of the current state (K = 0), three bin widths */
    {
        mote_hs hs;
        make_slit(&hs, 2, 0.40, 2, 5);
        const int64_t ps[3] = {1, 3, 10};
        for (int q = 0; q < 3; q++) {
            CHECK(mote_hs_image(&hs, 0, ps[q], path, "image 0 p f", &err) == MOTE_OK, "%s",
                  err.msg);
            char label[64];
            snprintf(label, sizeof label, "image K=0 p=%lld", (long long)ps[q]);
            check_image_file(path, &hs, 1, ps[q], label);
        }
        /* K > 0 */
        CHECK(mote_hs_image(&hs, 7, 4, path, "image 7 4 f", &err) == MOTE_OK, "%s", err.msg);
        check_image_file(path, &hs, 7, 4, "image K=7 p=4");
        /* errors: no file is written */
        char bad[512];
        tmp_path(bad, sizeof bad, "nodir/image.txt");
        CHECK(mote_hs_image(&hs, 0, 10, bad, NULL, &err) != MOTE_OK, "image into a missing dir");
        CHECK_HAS(err.msg, "nodir/image.txt");
        CHECK(mote_hs_image(&hs, 1, 0, path, NULL, &err) == MOTE_EINVAL, "p = 0 accepted");
        mote_hs_free(&hs);
        mote_hs_init(&hs, NULL);
        CHECK(mote_hs_image(&hs, 1, 10, path, NULL, &err) == MOTE_EINVAL, "image without system");
        mote_hs_free(&hs);
    }
    /* 2D and periodic systems integrate to N as well */
    {
        mote_hs hs;
        mote_hs_init(&hs, NULL);
        mote_hs_new_disks(&hs, 10, 12, 0.5, &err);
        mote_hs_step(&hs, 5, &err);
        CHECK(mote_hs_image(&hs, 5, 10, path, NULL, &err) == MOTE_OK, "%s", err.msg);
        check_image_file(path, &hs, 5, 10, "image 2D slit");
        mote_hs_free(&hs);
        mote_hs_init(&hs, NULL);
        mote_hs_bulk(&hs, 108, 0.3, &err);
        CHECK(mote_hs_image(&hs, 3, 2, path, NULL, &err) == MOTE_OK, "%s", err.msg);
        check_image_file(path, &hs, 3, 2, "image bulk");
        mote_hs_free(&hs);
    }

    /* Layering at eta 0.45 (the issue) and 0.40 (spec 10 item 7): new 4 (N = 736, L ~ 50),
     * 100 collisions per particle of equilibration, then image with p = 10 over 600 collisions
     * per particle (600 samples). With 200 samples the third maximum at eta 0.40 failed its
     * 3-error test or its spacing for 3 of 20 seeds (the run is chaotic, so any change in
     * rounding picks another realisation); with 600 and the spacing bounds taken as inclusive
     * (below), none of 40 seeds failed. */
    const double etas[2] = {0.45, 0.40};
    for (int e = 0; e < 2; e++) {
        mote_hs hs;
        double w0 = mote_wall_seconds();
        make_slit(&hs, 4, etas[e], 21, 100);
        uint64_t K = 600; /* statistical: the same run length under the sanitizer (~0.6 s) */
        CHECK(mote_hs_image(&hs, K, 10, path, "image K 10 f", &err) == MOTE_OK, "%s", err.msg);
        char label[64];
        snprintf(label, sizeof label, "layering eta %.2f", etas[e]);
        check_image_file(path, &hs, K, 10, label);
        check_layering(path, label);
        printf("  %s: %.2f s\n", label, mote_wall_seconds() - w0);
        mote_hs_free(&hs);
    }
}

/* ---- profile ---------------------------------------------------------------------------------- */

static void check_profile_file(const char *path, const mote_hs *hs, double x1, double x2,
                               int64_t dots, const char *label)
{
    int d = hs->ev.dim;
    table t;
    int rc = table_read(path, &t, d == 3 ? 5 : 4);
    CHECK(rc == 0, "%s: cannot parse (%d)", label, rc);
    if (rc) {
        table_free(&t);
        return;
    }
    double A = hs->ev.len[1], Az = hs->ev.len[2];
    int xcol = d == 3 ? 4 : 3;
    int inside = 1, order = 1;
    /* values are printed with %.12g: allow that rounding at the edges */
    double tol = 1e-11 * hs->ev.len[0];
    for (int r = 0; r < t.nrow; r++) {
        double s = t.col[0][r], id = t.col[1][r], x = t.col[xcol][r], y = t.col[2][r];
        inside &= x >= x1 - tol && x <= x2 + tol && y >= 0 && y <= A * (1 + 1e-11);
        if (d == 3)
            inside &= t.col[3][r] >= 0 && t.col[3][r] <= Az * (1 + 1e-11);
        inside &= s >= 1 && s <= (double)dots && id >= 0 && id < hs->ev.n;
        if (r > 0)
            order &= s > t.col[0][r - 1] || (s == t.col[0][r - 1] && id > t.col[1][r - 1]);
    }
    CHECK(inside, "%s: a row lies outside the slab [%g, %g] or the box", label, x1, x2);
    CHECK(order, "%s: rows not ordered by sample, then id", label);
    CHECK(t.has_rows_header && t.rows_header == t.nrow, "%s: header rows = %ld, file has %d",
          label, t.rows_header, t.nrow);
    CHECK(t.samples == (double)dots, "%s: header samples = %g, expected %lld", label, t.samples,
          (long long)dots);

    /* the last sample is the current state: compare with a direct count */
    int direct = 0, match = 1, r = 0;
    while (r < t.nrow && t.col[0][r] < (double)dots)
        r++;
    for (uint32_t i = 0; i < hs->ev.n; i++) { /* by particle number */
        double pos[3];
        mote_ev_position(&hs->ev, mote_ev_slot(&hs->ev, i), pos);
        if (pos[0] < x1 || pos[0] > x2)
            continue;
        direct++;
        if (r >= t.nrow || t.col[1][r] != i || fabs(t.col[xcol][r] - pos[0]) > tol ||
            fabs(t.col[2][r] - pos[1]) > 1e-11 * A ||
            (d == 3 && fabs(t.col[3][r] - pos[2]) > 1e-11 * Az))
            match = 0;
        r++;
    }
    CHECK(match && r == t.nrow, "%s: the last sample's rows differ from the state (%d direct, "
          "%d rows left)", label, direct, t.nrow - r + direct);
    printf("  %s: %d rows, last sample %d particles in [%g, %g]\n", label, t.nrow, direct, x1, x2);
    table_free(&t);
}

static void test_profile(void)
{
    printf("profile (spec 8.3)\n");
    mote_err err = {0};
    char path[512];
    tmp_path(path, sizeof path, "profile.txt");
    mote_hs hs;
    make_slit(&hs, 3, 0.45, 4, 20);

    /* K = 0, dots = 1: the current state; a slab at the wall and one inside */
    CHECK(mote_hs_profile(&hs, 0, 2.5, 1, 0, path, "profile 0 2.5 1 0 f", &err) == MOTE_OK, "%s",
          err.msg);
    check_profile_file(path, &hs, 0, 2.5, 1, "profile K=0 wall slab");
    CHECK(mote_hs_profile(&hs, 10, 14, 1, 0, path, NULL, &err) == MOTE_OK, "%s", err.msg);
    check_profile_file(path, &hs, 10, 14, 1, "profile K=0 inner slab");
    /* an empty slab still writes a valid file */
    CHECK(mote_hs_profile(&hs, 0, 0.5, 1, 0, path, NULL, &err) == MOTE_OK, "%s", err.msg);
    check_profile_file(path, &hs, 0, 0.5, 1, "profile empty slab");
    /* several samples during a run */
    CHECK(mote_hs_profile(&hs, 5, 9, 5, 4, path, NULL, &err) == MOTE_OK, "%s", err.msg);
    check_profile_file(path, &hs, 5, 9, 5, "profile K=4 dots=5");
    {
        table t;
        table_read(path, &t, 5);
        int seen[6] = {0};
        for (int r = 0; r < t.nrow; r++)
            if (t.col[0][r] >= 1 && t.col[0][r] <= 5)
                seen[(int)t.col[0][r]] = 1;
        CHECK(seen[1] && seen[2] && seen[3] && seen[4] && seen[5], "not every sample has rows");
        table_free(&t);
    }
    /* errors write nothing */
    char other[512];
    tmp_path(other, sizeof other, "profile_err.txt");
    CHECK(mote_hs_profile(&hs, 5, 4, 1, 0, other, NULL, &err) == MOTE_EINVAL, "x1 > x2 accepted");
    CHECK(mote_hs_profile(&hs, 1, 4, 2, 0, other, NULL, &err) == MOTE_EINVAL,
          "K = 0 with dots = 2 accepted");
    CHECK(mote_hs_profile(&hs, 1, 4, 0, 3, other, NULL, &err) == MOTE_EINVAL, "dots 0 accepted");
    CHECK(!file_exists(other), "a rejected profile wrote a file");
    mote_hs_free(&hs);

    /* 2D */
    mote_hs_init(&hs, NULL);
    mote_hs_new_disks(&hs, 10, 12, 0.5, &err);
    mote_hs_step(&hs, 3, &err);
    CHECK(mote_hs_profile(&hs, 1, 6, 3, 2, path, NULL, &err) == MOTE_OK, "%s", err.msg);
    check_profile_file(path, &hs, 1, 6, 3, "profile 2D");
    mote_hs_free(&hs);
}

/* ---- measurements do not perturb the trajectory ---------------------------------------------- */

static void test_no_perturbation(void)
{
    printf("measurements do not perturb (spec 6.8)\n");
    mote_err err = {0};
    char path[512];
    tmp_path(path, sizeof path, "m.txt");
    mote_hs a, b;
    make_slit(&a, 3, 0.45, 8, 10);
    make_slit(&b, 3, 0.45, 8, 10);
    CHECK(same_state(&a.ev, &b.ev), "identical seeds differ");
    CHECK(mote_hs_image(&a, 17, 10, path, NULL, &err) == MOTE_OK, "%s", err.msg);
    CHECK(mote_hs_step(&b, 17, &err) == MOTE_OK, "%s", err.msg);
    CHECK(same_state(&a.ev, &b.ev), "image 17 and step 17 end in different states");
    CHECK(mote_hs_profile(&a, 3, 8, 7, 13, path, NULL, &err) == MOTE_OK, "%s", err.msg);
    CHECK(mote_hs_step(&b, 13, &err) == MOTE_OK, "%s", err.msg);
    CHECK(same_state(&a.ev, &b.ev), "profile ... 13 and step 13 end in different states");
    /* K = 0 changes nothing at all */
    CHECK(mote_hs_image(&a, 0, 10, path, NULL, &err) == MOTE_OK, "%s", err.msg);
    CHECK(mote_hs_profile(&a, 3, 8, 1, 0, path, NULL, &err) == MOTE_OK, "%s", err.msg);
    CHECK(same_state(&a.ev, &b.ev), "image/profile with K = 0 changed the state");
    /* and the comparison can fail: one more collision differs */
    mote_ev_run(&b.ev, 1, &err);
    CHECK(!same_state(&a.ev, &b.ev), "same_state cannot tell states apart");
    mote_hs_free(&a);
    mote_hs_free(&b);
}

int main(void)
{
    sanitized = getenv("MOTE_SANITIZED") != NULL;
    if (!test_tmpdir_make(tmpdir, sizeof tmpdir, "mote_test_hs"))
        return 1;
    double w0 = mote_wall_seconds();
    test_compress();
    test_image();
    test_profile();
    test_no_perturbation();
    test_remove_tree(tmpdir);
    printf("test_hardspheres: %.1f s\n", mote_wall_seconds() - w0);
    return test_summary();
}
