/* output.c: what the separator writes for its users (specs/separator.md 3): the Tromp table and
 * its plot (all species and each one, error bars, d50 and d0* marked, kappa printed), the
 * profiles along the height and their three-panel plot, the frames (channel, grids with their
 * holes, particles at true size coloured by diameter or species), extended XYZ snapshots that
 * OVITO and ASE read, and the mass balance time series. Every file is written atomically. */
#include "mote/h5md.h"
#include "mote/vtk.h"
#include "mote/separator.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mote/datafile.h"
#include "mote/render.h"
#include "mote/buf.h"
#include "sep.h"


char *sep_png_name(const char *path)
{
    const size_t n = strlen(path);
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    const size_t stem = dot && (!slash || dot > slash) ? (size_t)(dot - path) : n;
    char *out = malloc(stem + 5);
    if (out) {
        memcpy(out, path, stem);
        memcpy(out + stem, ".png", 5);
    }
    return out;
}

/* The size unit for labels: micrometres below a millimetre, else millimetres. */
static void size_unit(double dmax, double *unit, const char **name)
{
    *unit = dmax < 1e-3 ? 1e-6 : 1e-3;
    *name = dmax < 1e-3 ? "\xC2\xB5m" : "mm";
}

/* ---- the Tromp curve ------------------------------------------------------------------------ */

int sep_write_tromp(const mote_sep_system *s, const char *path, const char *origin,
                    uint64_t seed, mote_sep_cut *cut_out, mote_err *err)
{
    const int nc = s->nclass, ns = s->nsp;
    double *T = malloc((size_t)nc * (size_t)(ns + 1) * sizeof *T), *hold = calloc((size_t)nc, sizeof *hold);
    if (!T || !hold) {
        free(T);
        free(hold);
        return mote_fail(err, MOTE_ENOMEM, "tromp: out of memory");
    }
    mote_sep_cut cut, cs[MOTE_SEP_MAX_SPECIES];
    mote_sep_tromp(s, T, &cut);
    for (int k = 0; k < ns; k++)
        mote_sep_tromp_species(s, k, T + (size_t)(k + 1) * (size_t)nc, &cs[k]);
    /* the hold-up: mass still in the channel per class */
    for (size_t i = 0; i < s->n; i++) {
        const double d = s->d[i];
        for (int c = 0; c < nc; c++)
            if (d >= s->class_edge[c] && d <= s->class_edge[c + 1]) {
                hold[c] += s->parcel * s->m[i];
                break;
            }
    }
    mote_datafile df;
    int rc = mote_datafile_open(&df, path, "separator-tromp", origin, seed, err);
    if (rc) {
        free(T);
        free(hold);
        return rc;
    }
    FILE *f = df.f;
    fprintf(f, "# t_s = %.10g\n", s->t);
    for (int k = 0; k < ns; k++)
        fprintf(f, "# d0_star_m %s = %.10g\n", s->sp[k].name, mote_sep_d0_star(s, k));
    fprintf(f, "# d25_m = %.10g\n# d50_m = %.10g\n# d75_m = %.10g\n# kappa = %.10g\n"
               "# Ep_m = %.10g\n# imperfection = %.10g\n# crossings_of_one_half = %d\n",
            cut.d25, cut.d50, cut.d75, cut.kappa, cut.Ep, cut.I, cut.crossings50);
    if (!(cut.d50 > 0))
        fprintf(f, "# d50: none (%s)\n", cut.crossings50 ? "" : T[0] < 0.5 ? "all to fines" :
                "all to coarse");
    if (ns > 1)
        for (int k = 0; k < ns; k++)
            fprintf(f, "# d50_m %s = %.10g\n# kappa %s = %.10g\n", s->sp[k].name, cs[k].d50,
                    s->sp[k].name, cs[k].kappa);
    /* each species' split: the mass fraction of what exited that went to the coarse */
    for (int k = 0; k < ns; k++) {
        double mf = 0, mc = 0;
        for (int i = 0; i < nc; i++) {
            mf += s->cls_mf[(size_t)i * MOTE_SEP_MAX_SPECIES + (size_t)k];
            mc += s->cls_mc[(size_t)i * MOTE_SEP_MAX_SPECIES + (size_t)k];
        }
        fprintf(f, "# to_coarse %s = %.10g\n", s->sp[k].name, mf + mc > 0 ? mc / (mf + mc) : NAN);
    }
    fprintf(f, "# columns: d_lo_m d_hi_m d_mean_m T_mass sigma_T n_fines n_coarse m_fines_kg "
               "m_coarse_kg T_number holdup_kg");
    if (ns > 1)
        for (int k = 0; k < ns; k++)
            fprintf(f, " T_%s", s->sp[k].name);
    fputc('\n', f);
    for (int i = 0; i < nc; i++) {
        const double n = (double)(s->cl_nf[i] + s->cl_nc[i]);
        const double se = n > 0 && !isnan(T[i]) ? sqrt(T[i] * (1 - T[i]) / n) : NAN;
        fprintf(f, "%.10g %.10g %.10g %.10g %.6g %llu %llu %.10g %.10g %.10g %.10g",
                s->class_edge[i], s->class_edge[i + 1],
                sqrt(s->class_edge[i] * s->class_edge[i + 1]), T[i], se,
                (unsigned long long)s->cl_nf[i], (unsigned long long)s->cl_nc[i], s->cl_mf[i],
                s->cl_mc[i], n > 0 ? (double)s->cl_nc[i] / n : NAN, hold[i]);
        if (ns > 1)
            for (int k = 0; k < ns; k++)
                fprintf(f, " %.10g", T[(size_t)(k + 1) * (size_t)nc + (size_t)i]);
        fputc('\n', f);
    }
    rc = mote_datafile_commit(&df, err);
    /* the plot */
    char *png = rc ? NULL : sep_png_name(path);
    if (!rc && !png)
        rc = mote_fail(err, MOTE_ENOMEM, "tromp: out of memory");
    if (!rc) {
        double unit;
        const char *uname;
        size_unit(s->class_edge[nc], &unit, &uname);
        double *dm = malloc((size_t)nc * sizeof *dm), *se = malloc((size_t)nc * sizeof *se);
        if (!dm || !se) {
            rc = mote_fail(err, MOTE_ENOMEM, "tromp: out of memory");
        } else {
            for (int i = 0; i < nc; i++) {
                dm[i] = sqrt(s->class_edge[i] * s->class_edge[i + 1]) / unit;
                const double n = (double)(s->cl_nf[i] + s->cl_nc[i]);
                se[i] = n > 0 && !isnan(T[i]) ? sqrt(T[i] * (1 - T[i]) / n) : NAN;
            }
            mote_series ser[MOTE_SEP_MAX_SPECIES + 1];
            const double *errs[MOTE_SEP_MAX_SPECIES + 1] = {se};
            char labels[MOTE_SEP_MAX_SPECIES + 1][48];
            int nser = 0;
            ser[nser++] = (mote_series){dm, T, (size_t)nc, ns > 1 ? "all species" : s->sp[0].name, 2};
            for (int k = 0; k < ns && ns > 1; k++) {
                snprintf(labels[k], sizeof labels[k], "%s", s->sp[k].name);
                errs[nser] = NULL;
                ser[nser++] = (mote_series){dm, T + (size_t)(k + 1) * (size_t)nc, (size_t)nc,
                                            labels[k], 2};
            }
            double marks[8];
            char mlab[8][64];
            const char *mlabs[8];
            int nm = 0;
            if (cut.d50 > 0) {
                marks[nm] = cut.d50 / unit;
                snprintf(mlab[nm], sizeof mlab[nm], "d50 = %.4g %s", cut.d50 / unit, uname);
                nm++;
            }
            for (int k = 0; k < ns && nm < 8; k++) {
                marks[nm] = mote_sep_d0_star(s, k) / unit;
                snprintf(mlab[nm], sizeof mlab[nm], "d0* %s = %.4g %s", s->sp[k].name, marks[nm],
                         uname);
                nm++;
            }
            for (int k = 0; k < nm; k++)
                mlabs[k] = mlab[k];
            char note[96], xl[64], title[160];
            if (cut.kappa > 0)
                snprintf(note, sizeof note, "kappa = d25/d75 = %.3f", cut.kappa);
            else
                snprintf(note, sizeof note, "kappa: no crossing of 1/4 and 3/4");
            snprintf(xl, sizeof xl, "particle diameter d (%s)", uname);
            snprintf(title, sizeof title, "Grade efficiency (Tromp curve), t = %.4g s", s->t);
            mote_plot_opts o = {0};
            o.title = title;
            o.xlabel = xl;
            o.ylabel = "partition number T (mass to coarse)";
            o.xlog = 1;
            o.xmin = s->class_edge[0] / unit;
            o.xmax = s->class_edge[nc] / unit;
            o.ymin = -0.02;
            o.ymax = 1.02;
            o.nxmark = nm;
            o.xmark = marks;
            o.xmark_label = mlabs;
            o.note = note;
            o.yerr = errs;
            rc = mote_plot_png(png, &o, ser, (size_t)nser, err);
        }
        free(dm);
        free(se);
    }
    free(png);
    if (cut_out)
        *cut_out = cut;
    free(T);
    free(hold);
    return rc;
}

/* ---- profiles ------------------------------------------------------------------------------- */

int sep_write_profiles(const mote_sep_system *s, const char *path, const char *origin,
                       uint64_t seed, mote_err *err)
{
    const int K = s->prof_K, ns = s->nsp;
    if (!(s->prof_time > 0))
        return mote_fail(err, MOTE_EINVAL, "profiles: nothing averaged yet (run past "
                         "average_from = %g s first)", s->avg_from);
    const double tw = s->prof_time, Ac = mote_sep_cross_section(s), dz = s->H / K;
    double *col = calloc((size_t)K * 6, sizeof *col);
    if (!col)
        return mote_fail(err, MOTE_ENOMEM, "profiles: out of memory");
    double *z = col, *eps = col + K, *ug = col + 2 * K, *vz = col + 3 * K, *dp = col + 4 * K,
           *p = col + 5 * K;
    for (int k = 0; k < K; k++) {
        z[k] = (k + 0.5) * dz;
        for (int j = 0; j < ns; j++)
            eps[k] += s->prof_eps[(size_t)k * MOTE_SEP_MAX_SPECIES + (size_t)j] / tw;
        ug[k] = s->prof_ug[k] / tw;
        vz[k] = s->prof_m[k] > 0 ? s->prof_mvz[k] / s->prof_m[k] : NAN;
        /* -dp/dz = eps_g rho_g g + (sum of the drag's z force in the slice) / (A_c dz) */
        dp[k] = (1 - eps[k]) * s->rho_sl[k] * s->g + s->prof_fd[k] / tw / (Ac * dz);
    }
    /* p(z) - p(H): the gradient integrated down from the top */
    for (int k = K - 1; k >= 0; k--)
        p[k] = (k == K - 1 ? 0.5 * dz * dp[k] : p[k + 1] + 0.5 * dz * (dp[k] + dp[k + 1]));
    mote_datafile df;
    int rc = mote_datafile_open(&df, path, "separator-profiles", origin, seed, err);
    if (rc) {
        free(col);
        return rc;
    }
    FILE *f = df.f;
    fprintf(f, "# average_from_s = %.10g\n# averaged_s = %.10g\n# t_s = %.10g\n", s->avg_from, tw,
            s->t);
    fprintf(f, "# columns: z_m eps_s");
    for (int j = 0; j < ns; j++)
        fprintf(f, " eps_%s", s->sp[j].name);
    fprintf(f, " N v_z_m_s u_g_m_s rho_mix_kg_m3 minus_dp_dz_Pa_m p_minus_pH_Pa\n");
    for (int k = 0; k < K; k++) {
        double rho_mix = (1 - eps[k]) * s->rho_sl[k];
        fprintf(f, "%.10g %.10g", z[k], eps[k]);
        for (int j = 0; j < ns; j++) {
            const double e = s->prof_eps[(size_t)k * MOTE_SEP_MAX_SPECIES + (size_t)j] / tw;
            rho_mix += e * s->sp[j].rho;
            fprintf(f, " %.10g", e);
        }
        fprintf(f, " %.10g %.10g %.10g %.10g %.10g %.10g\n", s->prof_n[k] / tw, vz[k], ug[k],
                rho_mix, dp[k], p[k]);
    }
    rc = mote_datafile_commit(&df, err);
    char *png = rc ? NULL : sep_png_name(path);
    if (!rc && !png)
        rc = mote_fail(err, MOTE_ENOMEM, "profiles: out of memory");
    if (!rc) {
        mote_series a = {eps, z, (size_t)K, NULL, 0}, b = {ug, z, (size_t)K, NULL, 0},
                    c = {vz, z, (size_t)K, NULL, 0};
        mote_plot_panel pan[3] = {{{0}, &a, 1}, {{0}, &b, 1}, {{0}, &c, 1}};
        pan[0].opts.title = "solids fraction";
        pan[0].opts.xlabel = "eps_s";
        pan[0].opts.ylabel = "height z (m)";
        pan[1].opts.title = "gas velocity";
        pan[1].opts.xlabel = "u_g (m/s)";
        pan[1].opts.ylabel = "height z (m)";
        pan[2].opts.title = "mean particle velocity";
        pan[2].opts.xlabel = "mass-weighted v_z (m/s)";
        pan[2].opts.ylabel = "height z (m)";
        for (int q = 0; q < 3; q++) {
            pan[q].opts.ymin = 0;
            pan[q].opts.ymax = s->H;
        }
        rc = mote_plot_panels_png(png, pan, 3, 1200, 700, err);
    }
    free(png);
    free(col);
    return rc;
}

/* ---- frames and snapshots ------------------------------------------------------------------- */

/* The solid parts of the plates as seen from the front: each plate's slab minus the union of
 * its holes' x ranges. *rects gets 4 numbers per rectangle (malloc'ed). */
int sep_plate_rects(const mote_sep_system *s, double **rects, size_t *n)
{
    size_t cap = 16, m = 0;
    double *r = malloc(cap * 4 * sizeof *r);
    if (!r)
        return -1;
    for (int q = 0; q < s->nplate; q++) {
        const mote_sep_plate *p = &s->plate[q];
        double *iv = malloc((p->nh ? p->nh : 1) * 2 * sizeof *iv);
        if (!iv) {
            free(r);
            return -1;
        }
        for (size_t h = 0; h < p->nh; h++) {
            iv[2 * h] = p->h[4 * h];
            iv[2 * h + 1] = p->h[4 * h + 1];
        }
        /* sort the intervals by their start (insertion: pattern holes come sorted) */
        for (size_t a = 1; a < p->nh; a++)
            for (size_t b = a; b > 0 && iv[2 * b] < iv[2 * b - 2]; b--) {
                const double t0 = iv[2 * b], t1 = iv[2 * b + 1];
                iv[2 * b] = iv[2 * b - 2];
                iv[2 * b + 1] = iv[2 * b - 1];
                iv[2 * b - 2] = t0;
                iv[2 * b - 1] = t1;
            }
        double x = 0;
        for (size_t h = 0; h <= p->nh; h++) {
            const double x1 = h < p->nh ? iv[2 * h] : s->W;
            if (x1 > x) {
                if (m == cap) {
                    cap *= 2;
                    double *t = realloc(r, cap * 4 * sizeof *t);
                    if (!t) {
                        free(iv);
                        free(r);
                        return -1;
                    }
                    r = t;
                }
                r[4 * m] = x;
                r[4 * m + 1] = p->zb;
                r[4 * m + 2] = x1;
                r[4 * m + 3] = p->zb + p->t;
                m++;
            }
            if (h < p->nh)
                x = fmax(x, iv[2 * h + 1]);
        }
        free(iv);
    }
    *rects = r;
    *n = m;
    return 0;
}

typedef struct {
    double y;
    size_t i;
} depth_key;

static int by_depth(const void *a, const void *b)
{
    const depth_key *p = a, *q = b;
    /* far (large y) first; ties by index for a stable picture */
    return p->y != q->y ? (p->y < q->y) - (p->y > q->y) : (p->i > q->i) - (p->i < q->i);
}

int sep_frame_png(const mote_sep_system *s, const char *path, const sep_frame_opts *fo,
                  mote_err *err)
{
    const size_t n = s->n;
    double *buf = malloc(4 * (n ? n : 1) * sizeof *buf);
    depth_key *key = malloc((n ? n : 1) * sizeof *key);
    double *rects = NULL;
    size_t nrect = 0;
    if (!buf || !key || sep_plate_rects(s, &rects, &nrect)) {
        free(buf);
        free(key);
        return mote_fail(err, MOTE_ENOMEM, "frames: out of memory");
    }
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
        if (s->dim == 3 && fo->y2 > fo->y1 && (s->y[i] < fo->y1 || s->y[i] > fo->y2))
            continue;
        key[m].y = s->dim == 3 ? s->y[i] : 0;
        key[m++].i = i;
    }
    if (s->dim == 3)
        qsort(key, m, sizeof *key, by_depth);
    double *x = buf, *z = buf + n, *r = buf + 2 * n, *v = buf + 3 * n;
    for (size_t k = 0; k < m; k++) {
        const size_t i = key[k].i;
        x[k] = s->x[i];
        z[k] = s->z[i];
        r[k] = 0.5 * s->d[i];
        v[k] = fo->by_species ? (double)s->s[i] : s->d[i];
    }
    double dmin, dmax, unit;
    const char *uname;
    mote_sep_size_range(s, &dmin, &dmax);
    size_unit(dmax, &unit, &uname);
    uint64_t fines = 0, coarse = 0, fed = 0;
    for (int k = 0; k < s->nsp; k++) {
        fines += s->cnt[k].fines;
        coarse += s->cnt[k].coarse;
        fed += s->cnt[k].fed;
    }
    char sub[256], bar[64], title[96];
    snprintf(sub, sizeof sub, "t = %.4f s   N = %zu   fed %llu   fines %llu   coarse %llu", s->t,
             s->n, (unsigned long long)fed, (unsigned long long)fines,
             (unsigned long long)coarse);
    snprintf(bar, sizeof bar, "d (%s)", uname);
    snprintf(title, sizeof title, "separator, U0 = %g m/s", s->U0);
    const char *names[MOTE_SEP_MAX_SPECIES];
    for (int k = 0; k < s->nsp; k++)
        names[k] = s->sp[k].name;
    mote_particles_opts o = {0};
    o.title = title;
    o.xlabel = "x (m)";
    o.ylabel = "z (m)";
    o.subtitle = sub;
    o.height = fo->px;
    o.xmin = 0;
    o.xmax = s->W;
    o.ymin = 0;
    o.ymax = s->H;
    o.vmin = dmin;
    o.vmax = dmax > dmin ? dmax : dmin * 1.0001;
    o.log_scale = 1;
    o.bar_unit = unit;
    o.bar_label = bar;
    if (fo->by_species) {
        o.ncat = s->nsp;
        o.cat_names = names;
    }
    /* the mesh walls where they are now, their outlines seen from the front (in 3D only the
     * edges that reach into the slice y1 ... y2 when one is asked for) */
    size_t nfe = 0;
    for (int k = 0; k < s->nmesh; k++)
        nfe += s->mesh[k].nfe;
    double *lines = nfe ? malloc(4 * nfe * sizeof *lines) : NULL;
    if (nfe && !lines) {
        free(buf);
        free(key);
        free(rects);
        return mote_fail(err, MOTE_ENOMEM, "frames: out of memory");
    }
    for (int k = 0; k < s->nmesh; k++) {
        const mote_sep_mesh *w = &s->mesh[k];
        sep_mesh_frame f;
        sep_mesh_frame_at(w, s->t, &f);
        for (size_t t = 0; t < w->nfe; t++) {
            double p[2][3], ylo = INFINITY, yhi = -INFINITY;
            for (int j = 0; j < 2; j++) {
                const double *q = w->v[w->fe[t][j]];
                const double d[3] = {q[0] - f.c0[0], q[1] - f.c0[1], q[2] - f.c0[2]};
                for (int a = 0; a < 3; a++)
                    p[j][a] = f.C[a] + f.R[a][0] * d[0] + f.R[a][1] * d[1] + f.R[a][2] * d[2];
                ylo = fmin(ylo, p[j][1]);
                yhi = fmax(yhi, p[j][1]);
            }
            if (fo->y2 > fo->y1 && (yhi < fo->y1 || ylo > fo->y2))
                continue;
            double *l = lines + 4 * o.nline++;
            l[0] = p[0][0], l[1] = p[0][2], l[2] = p[1][0], l[3] = p[1][2];
        }
    }
    o.lines = lines;
    const int rc = mote_particles_png(path, &o, x, z, r, v, m, rects, nrect, err);
    free(lines);
    free(buf);
    free(key);
    free(rects);
    return rc;
}

int sep_xyz_frame(FILE *f, const void *vs, mote_err *err)
{
    const mote_sep_system *s = vs;
    double dmin, dmax;
    mote_sep_size_range(s, &dmin, &dmax);
    const double D = s->dim == 3 ? s->D : s->D2 > 0 ? s->D2 : dmax;
    /* the element column holds X (ASE's and OVITO's dummy element, as in the hard-sphere
     * files): a species' own name is not an element; the name has its own column */
    char w[32], dd[32], h[32], t[32];
    mote_fmt_short(w, s->W);
    mote_fmt_short(dd, D);
    mote_fmt_short(h, s->H);
    mote_fmt_short(t, s->t);
    fprintf(f, "%zu\n", s->n);
    fprintf(f, "Lattice=\"%s 0 0 0 %s 0 0 0 %s\" Properties=species:S:1:species_name:S:1:id:I:1:"
               "pos:R:3:velo:R:3:radius:R:1 Time=%s pbc=\"F F F\" model=separator\n",
            w, dd, h, t);
    /* (the rows in 17 digits, exact, one format call a row: a trajectory of 10^6 particles) */
    for (size_t i = 0; i < s->n; i++)
        fprintf(f, "X %s %llu %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", s->sp[s->s[i]].name,
                (unsigned long long)s->id[i], s->x[i], s->dim == 3 ? s->y[i] : 0.5 * D, s->z[i],
                s->vx[i], s->vy[i], s->vz[i], 0.5 * s->d[i]);
    return MOTE_OK;
}

int sep_write_xyz(const mote_sep_system *s, const char *path, mote_err *err)
{
    return mote_frames_first(path, sep_xyz_frame, s, err);
}

/* The particles as one frame (h5md.h): positions and velocities (2D: the plane x, z), species,
 * ids, diameters and the last contact forces; written as H5MD (how 0: a new file, 1: appended)
 * or VTK (how 2). */
static int write_frame(const mote_sep_system *s, const char *path, const char *origin,
                       uint64_t seed, int how, mote_err *err)
{
    const size_t n = s->n, D = (size_t)s->dim;
    /* (with contact hertz also the angular velocity: a vector in 3D, its y component in 2D) */
    const int rot = s->hertz && s->w;
    const size_t nw = rot ? (D == 3 ? 3 : 1) : 0;
    double *buf = malloc((n ? n : 1) * (3 * D + 1 + nw) * sizeof *buf);
    int32_t *species = malloc((n ? n : 1) * sizeof *species);
    int64_t *id = malloc((n ? n : 1) * sizeof *id);
    int rc;
    if (!buf || !species || !id) {
        rc = mote_fail(err, MOTE_ENOMEM, "%s: out of memory for a frame of %zu particles", path,
                       n);
    } else {
        double *pos = buf, *vel = buf + n * D, *frc = buf + 2 * n * D, *dia = buf + 3 * n * D;
        double *om = dia + n;
        for (size_t i = 0; i < n; i++) { /* 2D: the plane x, z */
            const double r[3] = {s->x[i], s->y[i], s->z[i]}, v[3] = {s->vx[i], s->vy[i], s->vz[i]},
                         F[3] = {s->fx[i], s->fy[i], s->fz[i]};
            for (size_t a = 0; a < D; a++) {
                const size_t b = D == 3 ? a : 2 * a;
                pos[i * D + a] = r[b];
                vel[i * D + a] = v[b];
                frc[i * D + a] = s->dem ? F[b] : 0;
            }
            dia[i] = s->d[i];
            for (size_t a = 0; a < nw; a++)
                om[i * nw + a] = s->w[3 * i + (nw == 3 ? a : 1)];
            species[i] = s->s[i];
            id[i] = (int64_t)s->id[i];
        }
        const char *names[MOTE_SEP_MAX_SPECIES];
        for (int k = 0; k < s->nsp; k++)
            names[k] = s->sp[k].name;
        mote_h5md_frame fr = {.model = "separator", .origin = origin, .seed = seed,
                              .dim = s->dim, .n = n, .pos = pos, .vel = vel, .species = species,
                              .species_names = names, .nspecies_names = s->nsp, .id = id,
                              .nscalar = 1, .nvector = 1, .has_box = 1, .time = s->t,
                              .step = (int64_t)s->steps, .length_unit = "m", .time_unit = "s"};
        fr.scalar[0] = (mote_h5md_scalar){"diameter", "m", dia};
        fr.vector[0] = (mote_h5md_scalar){"contact_force", "N", frc};
        if (nw == 3)
            fr.vector[fr.nvector++] = (mote_h5md_scalar){"angular_velocity", "rad/s", om};
        else if (nw == 1) /* (2D: about y, the axis out of the plane x, z) */
            fr.scalar[fr.nscalar++] = (mote_h5md_scalar){"angular_velocity", "rad/s", om};
        fr.edges[0] = s->W;
        fr.edges[1] = s->dim == 3 ? s->D : s->H;
        fr.edges[2] = s->H;
        rc = how == 2   ? mote_vtk_particles(path, &fr, err)
             : how == 1 ? mote_h5md_append(path, &fr, err)
                        : mote_h5md_first(path, &fr, err);
    }
    free(buf);
    free(species);
    free(id);
    return rc;
}

int sep_write_h5md(const mote_sep_system *s, const char *path, const char *origin, uint64_t seed,
                   int append, mote_err *err)
{
    return write_frame(s, path, origin, seed, append ? 1 : 0, err);
}

int sep_write_vtk(const mote_sep_system *s, const char *path, mote_err *err)
{
    return write_frame(s, path, NULL, 0, 2, err);
}

/* ---- the balance ---------------------------------------------------------------------------- */

size_t sep_balance_width(const mote_sep_system *s)
{
    return 1 + 12 * (size_t)(s->nsp + 1);
}

void sep_balance_row(const mote_sep_system *s, double *row)
{
    double *r = row;
    *r++ = s->t;
    double in[MOTE_SEP_MAX_SPECIES + 1] = {0}, min[MOTE_SEP_MAX_SPECIES + 1] = {0};
    for (size_t i = 0; i < s->n; i++) {
        in[s->s[i]] += 1;
        min[s->s[i]] += s->parcel * s->m[i];
    }
    double back[MOTE_SEP_MAX_SPECIES + 1] = {0}, mback[MOTE_SEP_MAX_SPECIES + 1] = {0};
    for (size_t b = 0; b < s->nback; b++) {
        const int k = s->back_s[b];
        back[k] += 1;
        mback[k] += s->parcel * s->sp[k].rho * SEP_PI * s->back_d[b] * s->back_d[b] *
                    s->back_d[b] / 6;
    }
    double tot[12] = {0};
    for (int k = 0; k <= s->nsp; k++) {
        double v[12];
        if (k < s->nsp) {
            const mote_sep_count *c = &s->cnt[k];
            const double q[12] = {(double)c->fed, in[k], (double)c->fines, (double)c->coarse,
                                  (double)c->lost, back[k], c->m_fed, min[k], c->m_fines,
                                  c->m_coarse, c->m_lost, mback[k]};
            memcpy(v, q, sizeof v);
            for (int j = 0; j < 12; j++)
                tot[j] += v[j];
        } else {
            memcpy(v, tot, sizeof v);
        }
        memcpy(r, v, sizeof v);
        r += 12;
    }
}

void sep_balance_text(FILE *f, const mote_sep_system *s, int held, const double *rows,
                      size_t from, size_t to, int head)
{
    if (head) {
        fprintf(f, "# invariant_held = %d\n", held);
        fprintf(f, "# counts, then masses (kg), per species and in total (_all); fines_kg and "
                   "coarse_kg are the cumulative mass flows out\n# columns: t_s");
        static const char *const q[12] = {"fed", "in", "fines", "coarse", "lost", "backlog",
                                          "fed_kg", "in_kg", "fines_kg", "coarse_kg", "lost_kg",
                                          "backlog_kg"};
        for (int k = 0; k <= s->nsp; k++)
            for (int j = 0; j < 12; j++)
                fprintf(f, " %s_%s", q[j], k < s->nsp ? s->sp[k].name : "all");
        fputc('\n', f);
    }
    const size_t w = sep_balance_width(s);
    for (size_t r = from; r < to; r++) {
        for (size_t j = 0; j < w; j++)
            fprintf(f, j ? " %.10g" : "%.10g", rows[r * w + j]);
        fputc('\n', f);
    }
}

/* ---- the Tromp curve (spec 3.1) ------------------------------------------------------------- */

void mote_sep_tromp(const mote_sep_system *s, double *T, mote_sep_cut *cut)
{
    mote_sep_tromp_species(s, -1, T, cut);
}

void mote_sep_tromp_species(const mote_sep_system *s, int sp, double *T, mote_sep_cut *cut)
{
    for (int i = 0; i < s->nclass; i++) {
        const size_t q = (size_t)i * MOTE_SEP_MAX_SPECIES + (size_t)(sp < 0 ? 0 : sp);
        const double mf = sp < 0 ? s->cl_mf[i] : s->cls_mf[q], mc = sp < 0 ? s->cl_mc[i] : s->cls_mc[q];
        const double tot = mf + mc;
        T[i] = tot > 0 ? mc / tot : NAN;
    }
    const double x[3] = {0.25, 0.5, 0.75};
    double dx[3];
    cut->crossings50 = 0;
    for (int q = 0; q < 3; q++) {
        dx[q] = NAN;
        int prev = -1;
        for (int i = 0; i < s->nclass; i++) {
            if (isnan(T[i]))
                continue;
            if (prev >= 0 && (T[prev] < x[q]) != (T[i] < x[q])) {
                const double l0 = 0.5 * (log(s->class_edge[prev]) + log(s->class_edge[prev + 1]));
                const double l1 = 0.5 * (log(s->class_edge[i]) + log(s->class_edge[i + 1]));
                if (isnan(dx[q]))
                    dx[q] = exp(l0 + (x[q] - T[prev]) / (T[i] - T[prev]) * (l1 - l0));
                if (q == 1)
                    cut->crossings50++;
            }
            prev = i;
        }
    }
    cut->d25 = dx[0];
    cut->d50 = dx[1];
    cut->d75 = dx[2];
    cut->kappa = dx[0] / dx[2];
    cut->Ep = 0.5 * (dx[2] - dx[0]);
    cut->I = cut->Ep / dx[1];
}

/* ---- the mass balance (spec 2.11) ----------------------------------------------------------- */

int mote_sep_check_balance(const mote_sep_system *s)
{
    uint64_t in[MOTE_SEP_MAX_SPECIES] = {0};
    double min[MOTE_SEP_MAX_SPECIES] = {0};
    for (size_t i = 0; i < s->n; i++) {
        in[s->s[i]]++;
        min[s->s[i]] += s->parcel * s->m[i];
    }
    for (int k = 0; k < s->nsp; k++) {
        const mote_sep_count *c = &s->cnt[k];
        if (c->fed != in[k] + c->fines + c->coarse + c->lost)
            return -1;
        const double sum = min[k] + c->m_fines + c->m_coarse + c->m_lost;
        if (fabs(sum - c->m_fed) > 1e-12 * fmax(c->m_fed, 1e-300))
            return -1;
    }
    return 0;
}
