/* output.c: the charging model's files (spec 8), written after a `run` when `output prefix=P`
 * was given: P_triangles.csv (one row per triangle and side that can be hit), P_parts.csv (the
 * currents summed per part), P_surface.vtk (legacy VTK POLYDATA for ParaView, cell arrays),
 * P_summary.txt and P_summary.json, and P_surface.png (the body coloured by the net current
 * density, drawn through the render layer). Every file starts with '#' header lines (the JSON
 * and VTK formats have their own headers); numbers have 10 significant digits; every file is
 * written atomically. */
#include "mote/charging.h"
#include "mote/datafile.h"
#include "mote/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ch.h"
#include "mote/vtk.h"

/* The current of species s on triangle i, side side, and its variance. */
static double tri_current(const mote_ch_plasma *p, const mote_ch_result *r, int s, uint32_t i,
                          int side, double *var)
{
    int comp = 0;
    for (int q = 0; q < s; q++)
        comp += p->sp[q].ncomp;
    double I = 0, v = 0;
    const double N = (double)r->histories;
    for (int k = 0; k < p->sp[s].ncomp; k++) {
        const double h = (double)r->tri_hits[((size_t)(comp + k) * r->ntri + i) * 2 + (size_t)side];
        const double w = r->weight[s][k];
        I += w * h;
        v += w * w * h * (1 - h / N);
    }
    *var = v;
    return I;
}

/* The secondary-electron current (A, > 0: electrons leaving) of triangle i, side side: all
 * components. */
static double tri_see(const mote_ch_result *r, uint32_t i, int side)
{
    double see = 0;
    for (int q = 0; r->tri_see && q < r->ncomp; q++)
        see += r->tri_see[((size_t)q * r->ntri + i) * 2 + (size_t)side];
    return see;
}

/* The photoemission current (A, > 0) of triangle i, side side. */
static double tri_photo(const mote_ch_result *r, uint32_t i, int side)
{
    return r->tri_photo ? r->tri_photo[2 * (size_t)i + (size_t)side] : 0;
}

static uint64_t tri_hits(const mote_ch_result *r, int comp0, int ncomp, uint32_t i, int side)
{
    uint64_t h = 0;
    for (int k = 0; k < ncomp; k++)
        h += r->tri_hits[((size_t)(comp0 + k) * r->ntri + i) * 2 + (size_t)side];
    return h;
}

/* The quantity the picture shows for triangle i, side side (png_quantity, spec 8.4). */
static double tri_quantity(const ch_output *o, uint32_t i, int side);

/* J of triangle i, side side (all species, the secondaries, the photoelectrons), in A/m^2. */
static double tri_j(const ch_output *o, uint32_t i, int side)
{
    double J = tri_see(o->res, i, side) + tri_photo(o->res, i, side), v;
    for (int s = 0; s < o->plasma->nsp; s++)
        J += tri_current(o->plasma, o->res, s, i, side, &v);
    return J / o->body->area[i];
}

static double tri_quantity(const ch_output *o, uint32_t i, int side)
{
    const mote_ch_result *r = o->res;
    const double A = o->body->area[i];
    double v = 0, x;
    switch (o->png_q) {
    case CH_Q_SPECIES:
        return tri_current(o->plasma, r, o->png_sp, i, side, &x) / A;
    case CH_Q_SEE:
        return tri_see(r, i, side) / A;
    case CH_Q_PHOTO:
        return tri_photo(r, i, side) / A;
    case CH_Q_SIGMA:
    case CH_Q_RELERR:
        for (int s = 0; s < o->plasma->nsp; s++) {
            tri_current(o->plasma, r, s, i, side, &x);
            v += x;
        }
        v = sqrt(v) / A;
        if (o->png_q == CH_Q_SIGMA)
            return v;
        x = tri_j(o, i, side);
        return x != 0 ? v / fabs(x) : 0;
    case CH_Q_SUNLIT:
        return r->tri_sunlit ? r->tri_sunlit[2 * (size_t)i + (size_t)side] : 0;
    case CH_Q_HITS:
        return (double)tri_hits(r, 0, r->ncomp, i, side);
    case CH_Q_VSURF:
        return o->tri_V ? o->tri_V[i] : o->potential;
    default:
        return tri_j(o, i, side);
    }
}

/* The picture's title and colour-bar label for the quantity. */
static void quantity_names(const ch_output *o, char *title, size_t nt, char *label, size_t nl)
{
    static const char *const name[9][2] = {
        {"net current density", "J_net (A/m^2)"},
        {"", ""}, /* a species: below */
        {"secondary-electron current density", "J_see (A/m^2)"},
        {"photoelectron current density", "J_photo (A/m^2)"},
        {"standard error of the current density", "sigma_J (A/m^2)"},
        {"relative error of the current density", "relerr"},
        {"sunlit fraction", "sunlit fraction"},
        {"hits", "hits (all components)"},
        {"surface potential", "V (V)"}};
    const int q = o->png_q >= 0 && o->png_q < 9 ? o->png_q : CH_Q_JNET;
    if (q == CH_Q_SPECIES) {
        const char *sp = o->plasma->sp[o->png_sp].name;
        snprintf(title, nt, "%s current density", sp);
        snprintf(label, nl, "J_%s (A/m^2)", sp);
    } else {
        snprintf(title, nt, "%s", name[q][0]);
        snprintf(label, nl, "%s", name[q][1]);
    }
}

/* The sides of triangle i that are surfaces: the front of a closed triangle, both of a sheet. */
static int nsides(const mote_ch_body *b, uint32_t i) { return b->sphere || b->closed[i] ? 1 : 2; }

static void header(FILE *f, const ch_output *o)
{
    const mote_ch_geometry *g = &o->geom;
    fprintf(f, "# mode = %s\n# seed = %llu\n# histories_per_component = %llu\n", o->mode,
            (unsigned long long)o->seed, (unsigned long long)o->res->histories);
    fprintf(f, "# triangles = %u\n# area_m2 = %.10g\n# R_eq_m = %.10g\n# C_F = %.10g\n"
               "# R_bound_m = %.10g\n# R_gen_m = %.10g\n# potential_V = %.10g\n",
            o->body->sphere ? 0 : o->body->ntri, g->area, g->r_eq, g->capacitance, g->r_bound,
            o->r_gen, o->potential);
    for (int s = 0; s < o->plasma->nsp; s++) {
        const mote_ch_species *sp = &o->plasma->sp[s];
        for (int k = 0; k < sp->ncomp; k++)
            fprintf(f, "# species %s Z = %d m_kg = %.10g component %d n_m3 = %.10g kT_eV = %.10g\n",
                    sp->name, sp->Z, sp->m, k + 1, sp->n[k], sp->kT[k]);
    }
}

static int write_triangles(const ch_output *o, const char *path, mote_err *err)
{
    mote_datafile d;
    int rc = mote_datafile_open(&d, path, "charging-triangles", o->origin, o->seed, err);
    if (rc)
        return rc;
    FILE *f = d.f;
    const mote_ch_body *b = o->body;
    const mote_ch_plasma *p = o->plasma;
    header(f, o);
    fprintf(f, "# columns: index part material side area_m2 cx cy cz nx ny nz sunlit_fraction");
    for (int s = 0; s < p->nsp; s++)
        fprintf(f, " hits_%s I_%s_A", p->sp[s].name, p->sp[s].name);
    fprintf(f, " I_see_A I_photo_A I_net_A J_net_A_m2 sigma_J_A_m2 relerr\n");
    const uint32_t n = b->sphere ? 1 : b->ntri;
    for (uint32_t i = 0; i < n; i++)
        for (int side = 0; side < nsides(b, i); side++) {
            double c[3] = {0, 0, 0}, nrm[3] = {0, 0, 0}, area;
            if (b->sphere) {
                area = o->geom.area;
                memcpy(c, b->sphere_c, sizeof c);
            } else {
                area = b->area[i];
                for (int a = 0; a < 3; a++) {
                    c[a] = (b->v[i][0][a] + b->v[i][1][a] + b->v[i][2][a]) / 3;
                    nrm[a] = side ? -b->nrm[i][a] : b->nrm[i][a];
                }
            }
            const size_t q = 2 * (size_t)i + (size_t)side;
            fprintf(f, "%u %s %s %s %.10g %.10g %.10g %.10g %.10g %.10g %.10g %.10g", i,
                    b->sphere ? "sphere" : b->part_name[b->part[i]],
                    o->tri_mat ? o->tri_mat[i]->name : "bare", side ? "back" : "front", area, c[0],
                    c[1], c[2], nrm[0], nrm[1], nrm[2],
                    o->res->tri_sunlit ? o->res->tri_sunlit[q] : 0);
            double inet = 0, var = 0;
            int comp0 = 0;
            for (int s = 0; s < p->nsp; s++) {
                double v;
                const double I = tri_current(p, o->res, s, i, side, &v);
                fprintf(f, " %llu %.10g",
                        (unsigned long long)tri_hits(o->res, comp0, p->sp[s].ncomp, i, side), I);
                comp0 += p->sp[s].ncomp;
                inet += I;
                var += v;
            }
            const double see = tri_see(o->res, i, side), ph = tri_photo(o->res, i, side);
            inet += see + ph;
            const double J = inet / area, sJ = sqrt(var) / area;
            fprintf(f, " %.10g %.10g %.10g %.10g %.10g %.10g\n", see, ph, inet, J, sJ,
                    inet != 0 ? fabs(sqrt(var) / inet) : 0);
        }
    return mote_datafile_commit(&d, err);
}

static int write_parts(const ch_output *o, const char *path, mote_err *err)
{
    const mote_ch_body *b = o->body;
    const mote_ch_plasma *p = o->plasma;
    const int np = b->sphere ? 1 : b->nparts;
    double *I = calloc((size_t)np * (size_t)(p->nsp + 1), sizeof *I);
    double *V = calloc((size_t)np * (size_t)(p->nsp + 1), sizeof *V);
    double *A = calloc((size_t)np, sizeof *A), *S = calloc((size_t)np, sizeof *S);
    double *P = calloc((size_t)np, sizeof *P);
    const char **mat = calloc((size_t)np, sizeof *mat);
    if (!I || !V || !A || !S || !P || !mat) {
        free(I);
        free(V);
        free(A);
        free(S);
        free(P);
        free(mat);
        return mote_fail(err, MOTE_ENOMEM, "output: out of memory");
    }
    const uint32_t n = b->sphere ? 1 : b->ntri;
    for (uint32_t i = 0; i < n; i++) {
        const int part = b->sphere ? 0 : b->part[i];
        A[part] += b->sphere ? o->geom.area : b->area[i] * nsides(b, i);
        mat[part] = o->tri_mat ? o->tri_mat[i]->name : "bare"; /* a part has one material */
        for (int side = 0; side < nsides(b, i); side++) {
            const double see = tri_see(o->res, i, side), ph = tri_photo(o->res, i, side);
            S[part] += see;
            P[part] += ph;
            I[part * (p->nsp + 1) + p->nsp] += see + ph;
            for (int s = 0; s < p->nsp; s++) {
                double v;
                const double c = tri_current(p, o->res, s, i, side, &v);
                I[part * (p->nsp + 1) + s] += c;
                V[part * (p->nsp + 1) + s] += v;
                I[part * (p->nsp + 1) + p->nsp] += c;
                V[part * (p->nsp + 1) + p->nsp] += v;
            }
        }
    }
    mote_datafile d;
    int rc = mote_datafile_open(&d, path, "charging-parts", o->origin, o->seed, err);
    if (!rc) {
        FILE *f = d.f;
        header(f, o);
        fprintf(f, "# columns: part material area_m2");
        for (int s = 0; s < p->nsp; s++)
            fprintf(f, " I_%s_A sigma_%s_A", p->sp[s].name, p->sp[s].name);
        fprintf(f, " I_see_A I_photo_A I_net_A sigma_net_A J_net_A_m2\n");
        for (int k = 0; k < np; k++) {
            fprintf(f, "%s %s %.10g", b->sphere ? "sphere" : b->part_name[k],
                    mat[k] ? mat[k] : "bare", A[k]);
            for (int s = 0; s < p->nsp; s++)
                fprintf(f, " %.10g %.10g", I[k * (p->nsp + 1) + s], sqrt(V[k * (p->nsp + 1) + s]));
            fprintf(f, " %.10g %.10g", S[k], P[k]);
            fprintf(f, " %.10g %.10g", I[k * (p->nsp + 1) + p->nsp],
                    sqrt(V[k * (p->nsp + 1) + p->nsp]));
            fprintf(f, " %.10g\n", A[k] > 0 ? I[k * (p->nsp + 1) + p->nsp] / A[k] : 0);
        }
        rc = mote_datafile_commit(&d, err);
    }
    free(I);
    free(V);
    free(A);
    free(S);
    free(P);
    free(mat);
    return rc;
}



/* Legacy VTK data (vtk.h): text with 10 significant digits, or binary. */
static void vtk_put(FILE *f, const double *v, size_t n, int binary, int is_int)
{
    mote_vtk_put(f, v, n, binary, is_int, 10);
}

static void vtk_scalars(FILE *f, const char *name, const double *v, size_t n, int binary,
                        int is_int)
{
    fprintf(f, "SCALARS %s %s 1\nLOOKUP_TABLE default\n", name, is_int == 1 ? "int" : "double");
    vtk_put(f, v, n, binary, is_int);
}

/* The VTK file's header, points and triangles (v: room for 9 n numbers), to CELL_DATA. */
static void vtk_geometry(FILE *f, const ch_output *o, const char *title, double *v)
{
    const mote_ch_body *b = o->body;
    const uint32_t n = b->ntri;
    const int bin = o->vtk_binary;
    fprintf(f, "# vtk DataFile Version 3.0\n%s\n%s\nDATASET POLYDATA\nPOINTS %u double\n", title,
            bin ? "BINARY" : "ASCII", 3 * n);
    for (uint32_t i = 0; i < n; i++)
        for (int j = 0; j < 3; j++)
            for (int a = 0; a < 3; a++)
                v[9 * (size_t)i + 3 * (size_t)j + (size_t)a] = b->v[i][j][a];
    if (bin) {
        vtk_put(f, v, 9 * (size_t)n, 1, 0);
    } else { /* three to a line */
        for (uint32_t i = 0; i < 3 * n; i++)
            fprintf(f, "%.10g %.10g %.10g\n", v[3 * (size_t)i], v[3 * (size_t)i + 1],
                    v[3 * (size_t)i + 2]);
    }
    fprintf(f, "POLYGONS %u %u\n", n, 4 * n);
    if (bin) {
        for (uint32_t i = 0; i < n; i++) {
            v[4 * (size_t)i] = 3;
            for (int j = 0; j < 3; j++)
                v[4 * (size_t)i + 1 + (size_t)j] = 3.0 * i + j;
        }
        vtk_put(f, v, 4 * (size_t)n, 1, 1);
    } else {
        for (uint32_t i = 0; i < n; i++)
            fprintf(f, "3 %u %u %u\n", 3 * i, 3 * i + 1, 3 * i + 2);
    }
    fprintf(f, "CELL_DATA %u\n", n);
}

static int write_vtk(const ch_output *o, const char *path, mote_err *err)
{
    const mote_ch_body *b = o->body;
    const mote_ch_plasma *p = o->plasma;
    const uint32_t n = b->ntri;
    double *v = malloc((size_t)(9 * (size_t)n + 1) * sizeof *v);
    if (!v)
        return mote_fail(err, MOTE_ENOMEM, "output: out of memory for the VTK file");
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc) {
        free(v);
        return rc;
    }
    FILE *f = af.f;
    const int bin = o->vtk_binary;
    char title[160];
    snprintf(title, sizeof title, "mote charging: currents at U = %.6g V, seed %llu, %llu "
             "histories per component", o->potential, (unsigned long long)o->seed,
             (unsigned long long)o->res->histories);
    vtk_geometry(f, o, title, v);
    /* J_net: both sides of a sheet together; then each side, sigma, relerr, each species, the
     * emission, the sunlit fraction, hits, part */
    for (int a = 0; a < 5; a++) {
        static const char *const name[5] = {"J_net", "J_net_front", "J_net_back", "sigma_J",
                                            "relerr"};
        for (uint32_t i = 0; i < n; i++) {
            const double Jn = tri_j(o, i, 0) + (nsides(b, i) == 2 ? tri_j(o, i, 1) : 0);
            double var = 0, x;
            if (a >= 3)
                for (int side = 0; side < nsides(b, i); side++)
                    for (int sp = 0; sp < p->nsp; sp++) {
                        tri_current(p, o->res, sp, i, side, &x);
                        var += x;
                    }
            v[i] = a == 0   ? Jn
                   : a < 3  ? (a == 2 && nsides(b, i) == 1 ? 0 : tri_j(o, i, a - 1))
                   : a == 3 ? sqrt(var) / b->area[i]
                            : (Jn != 0 ? sqrt(var) / b->area[i] / fabs(Jn) : 0);
        }
        vtk_scalars(f, name[a], v, n, bin, 0);
    }
    for (int sp = 0; sp < p->nsp; sp++) {
        char name[48];
        snprintf(name, sizeof name, "J_%s", p->sp[sp].name);
        for (uint32_t i = 0; i < n; i++) {
            double J = 0, x;
            for (int side = 0; side < nsides(b, i); side++)
                J += tri_current(p, o->res, sp, i, side, &x);
            v[i] = J / b->area[i];
        }
        vtk_scalars(f, name, v, n, bin, 0);
    }
    /* the secondaries and photoelectrons leaving, both sides (A/m^2, > 0), the sunlit fraction
     * (the lit side's) */
    for (uint32_t i = 0; i < n; i++)
        v[i] = (tri_see(o->res, i, 0) + tri_see(o->res, i, 1)) / b->area[i];
    vtk_scalars(f, "J_see", v, n, bin, 0);
    for (uint32_t i = 0; i < n; i++)
        v[i] = (tri_photo(o->res, i, 0) + tri_photo(o->res, i, 1)) / b->area[i];
    vtk_scalars(f, "J_photo", v, n, bin, 0);
    for (uint32_t i = 0; i < n; i++)
        v[i] = o->res->tri_sunlit ? fmax(o->res->tri_sunlit[2 * (size_t)i],
                                         o->res->tri_sunlit[2 * (size_t)i + 1])
                                  : 0;
    vtk_scalars(f, "sunlit_fraction", v, n, bin, 0);
    for (uint32_t i = 0; i < n; i++)
        v[i] = (double)(tri_hits(o->res, 0, o->res->ncomp, i, 0) +
                        tri_hits(o->res, 0, o->res->ncomp, i, 1));
    vtk_scalars(f, "hits_total", v, n, bin, 2);
    for (uint32_t i = 0; i < n; i++)
        v[i] = b->part[i];
    vtk_scalars(f, "part_id", v, n, bin, 1);
    free(v);
    return mote_afile_commit(&af, err);
}

static int write_summary(const ch_output *o, const char *path, int json, mote_err *err)
{
    const mote_ch_plasma *p = o->plasma;
    const mote_ch_geometry *g = &o->geom;
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc)
        return rc;
    FILE *f = af.f;
    double inet = 0, var = 0, see[MOTE_CH_MAX_SPECIES] = {0}, see_var[MOTE_CH_MAX_SPECIES] = {0};
    uint64_t hits = 0;
    for (int s = 0; s < p->nsp; s++) {
        inet += o->res->current[s];
        var += o->res->sigma[s] * o->res->sigma[s];
        for (int k = 0; k < p->sp[s].ncomp; k++) { /* the secondaries a species knocks out */
            hits += o->res->hits[s][k];
            see[s] += o->res->see[s][k];
            see_var[s] += o->res->see_sigma[s][k] * o->res->see_sigma[s][k];
        }
        inet += see[s];
        var += see_var[s];
    }
    inet += o->res->photo;
    const double hitf = (double)hits / ((double)o->res->ncomp * (double)o->res->histories);
    if (json) {
        fprintf(f, "{\"model\":\"charging\",\"mode\":\"%s\",\"backscatter\":%s,\"seed\":%llu,"
                   "\"potential_V\":%.10g,"
                   "\"histories_per_component\":%llu,\"area_m2\":%.10g,\"R_eq_m\":%.10g,"
                   "\"R_bound_m\":%.10g,\"R_gen_m\":%.10g,\"C_F\":%.10g,\"debye_m\":%.10g,"
                   "\"species\":[",
                o->mode, o->backscatter ? "true" : "false", (unsigned long long)o->seed,
                o->potential,
                (unsigned long long)o->res->histories, g->area, g->r_eq, g->r_bound, o->r_gen, g->capacitance, mote_ch_debye(p));
        for (int s = 0; s < p->nsp; s++) {
            fprintf(f, "%s{\"name\":\"%s\",\"I_A\":%.10g,\"sigma_A\":%.10g,\"I_see_A\":%.10g,"
                       "\"sigma_see_A\":%.10g,\"components\":[",
                    s ? "," : "", p->sp[s].name, o->res->current[s], o->res->sigma[s], see[s],
                    sqrt(see_var[s]));
            for (int k = 0; k < p->sp[s].ncomp; k++)
                fprintf(f, "%s{\"n_m3\":%.10g,\"kT_eV\":%.10g,\"I_A\":%.10g,\"hits\":%llu}",
                        k ? "," : "", p->sp[s].n[k], p->sp[s].kT[k],
                        o->res->weight[s][k] * (double)o->res->hits[s][k],
                        (unsigned long long)o->res->hits[s][k]);
            fprintf(f, "]}");
        }
        if (o->have_float)
            fprintf(f, "],\"U_f_V\":%.10g,\"sigma_U_V\":%.10g,\"U_f_OML_V\":%.10g", o->potential,
                    o->sigma_U, o->oml);
        else
            fputc(']', f);
        fprintf(f, ",\"I_photo_A\":%.10g,\"lost\":%llu,\"steps_per_history\":%.6g,"
                   "\"ranks\":%d,\"warnings\":[",
                o->res->photo, (unsigned long long)o->res->lost,
                (double)o->res->steps / ((double)o->res->ncomp * (double)o->res->histories),
                ch_mpi_size(o->solo));
        for (const char *w = o->warnings; w && *w;) { /* one string a line, escaped */
            const char *e = strchr(w, '\n');
            const size_t l = e ? (size_t)(e - w) : strlen(w);
            fputs(w == o->warnings ? "\"" : ",\"", f);
            for (size_t q = 0; q < l; q++) {
                if (w[q] == '"' || w[q] == '\\')
                    fputc('\\', f);
                fputc(w[q], f);
            }
            fputc('"', f);
            w += l + (e != NULL);
        }
        fputc(']', f);
        fprintf(f, ",\"I_net_A\":%.10g,\"sigma_net_A\":%.10g,\"dU_dt_V_s\":%.10g,"
                   "\"hit_fraction\":%.10g,\"backface_hits\":%llu,\"traces_per_s\":%.4g,"
                   "\"threads\":%d}\n",
                inet, sqrt(var), inet / g->capacitance, hitf,
                (unsigned long long)o->res->backface_hits, o->res->traces_per_s, o->threads);
    } else {
        fprintf(f, "mote charging: summary (%s mode, seed %llu)\n\n", o->mode,
                (unsigned long long)o->seed);
        if (o->have_float)
            fprintf(f, "floating potential: U_f = %.10g V +- %.3g (the analytic OML estimate for "
                       "the equivalent sphere: %.10g V)\n\n", o->potential, o->sigma_U, o->oml);
        fprintf(f, "body: %u triangles, area %.10g m^2, R_eq %.10g m, R_bound %.10g m, C %.10g F\n",
                o->body->sphere ? 0 : o->body->ntri, g->area, g->r_eq, g->r_bound, g->capacitance);
        fprintf(f, "plasma: Debye length %.6g m; injection sphere R %.6g m\n\n", mote_ch_debye(p),
                o->r_gen);
        fprintf(f, "currents at U = %.6g V (%llu histories per component):\n", o->potential,
                (unsigned long long)o->res->histories);
        for (int s = 0; s < p->nsp; s++) {
            fprintf(f, "  %-4s %.10g A +- %.3g\n", p->sp[s].name, o->res->current[s],
                    o->res->sigma[s]);
            for (int k = 0; k < p->sp[s].ncomp; k++)
                fprintf(f, "       component %d (n %.4g m^-3, kT %.6g eV): %.10g A\n", k + 1,
                        p->sp[s].n[k], p->sp[s].kT[k],
                        o->res->weight[s][k] * (double)o->res->hits[s][k]);
            if (see[s] != 0)
                fprintf(f, "       %s it knocks out: +%.10g A +- %.3g\n",
                        o->backscatter && p->sp[s].Z < 0
                            ? "secondary and backscattered electrons"
                            : "secondary electrons",
                        see[s], sqrt(see_var[s]));
        }
        if (o->res->tri_photo)
            fprintf(f, "  photoelectrons %+.10g A\n", o->res->photo);
        fprintf(f, "  net  %.10g A +- %.3g%s\n\n", inet, sqrt(var),
                o->tri_mat ? " (with the emitted electrons)" : "");
        fprintf(f, "charging with these currents held constant (the thesis's model): dU/dt = "
                   "I / C = %.10g V/s\n", inet / g->capacitance);
        fprintf(f, "hit fraction %.6g, back-face hits %llu, %.4g traces/s on %d thread%s and %d "
                   "MPI rank%s\n", hitf, (unsigned long long)o->res->backface_hits,
                o->res->traces_per_s, o->threads, o->threads == 1 ? "" : "s", ch_mpi_size(o->solo),
                ch_mpi_size(o->solo) == 1 ? "" : "s");
        if (o->res->steps > 0)
            fprintf(f, "curved paths: %.4g steps per history, %llu lost, largest relative energy "
                       "error %.3g\n",
                    (double)o->res->steps / ((double)o->res->ncomp * (double)o->res->histories),
                    (unsigned long long)o->res->lost, o->res->max_energy_err);
        if (o->warnings && *o->warnings)
            fprintf(f, "\nwarnings:\n%s", o->warnings);
    }
    return mote_afile_commit(&af, err);
}

/* The body seen from view (a unit vector toward the viewer), coloured by J_net of the visible
 * side, shaded 0.35 + 0.65 |n . view| (spec 8.4); back faces of closed components culled. */
static int write_png(const ch_output *o, const char *path, mote_err *err)
{
    const mote_ch_body *b = o->body;
    const double *c = o->view;
    /* the screen basis: x = up x view (up = z, or y when looking along z), y = view x x */
    double up[3] = {0, 0, 1};
    if (fabs(c[2]) > 0.99) {
        up[1] = 1;
        up[2] = 0;
    }
    double ex[3] = {up[1] * c[2] - up[2] * c[1], up[2] * c[0] - up[0] * c[2],
                    up[0] * c[1] - up[1] * c[0]};
    const double l = sqrt(ex[0] * ex[0] + ex[1] * ex[1] + ex[2] * ex[2]);
    for (int a = 0; a < 3; a++)
        ex[a] /= l;
    const double ey[3] = {c[1] * ex[2] - c[2] * ex[1], c[2] * ex[0] - c[0] * ex[2],
                          c[0] * ex[1] - c[1] * ex[0]};
    double *xy = malloc((b->ntri ? b->ntri : 1) * 6 * sizeof *xy);
    double *depth = malloc((b->ntri ? b->ntri : 1) * sizeof *depth);
    double *val = malloc((b->ntri ? b->ntri : 1) * sizeof *val);
    double *shade = malloc((b->ntri ? b->ntri : 1) * sizeof *shade);
    if (!xy || !depth || !val || !shade) {
        free(xy);
        free(depth);
        free(val);
        free(shade);
        return mote_fail(err, MOTE_ENOMEM, "output: out of memory");
    }
    size_t n = 0;
    for (uint32_t i = 0; i < b->ntri; i++) {
        const double nv = b->nrm[i][0] * c[0] + b->nrm[i][1] * c[1] + b->nrm[i][2] * c[2];
        if (b->closed[i] && nv <= 0)
            continue; /* a back face */
        for (int j = 0; j < 3; j++) {
            const double *v = b->v[i][j];
            xy[6 * n + 2 * j] = v[0] * ex[0] + v[1] * ex[1] + v[2] * ex[2];
            xy[6 * n + 2 * j + 1] = v[0] * ey[0] + v[1] * ey[1] + v[2] * ey[2];
        }
        depth[n] = 0;
        for (int j = 0; j < 3; j++)
            depth[n] += (b->v[i][j][0] * c[0] + b->v[i][j][1] * c[1] + b->v[i][j][2] * c[2]) / 3;
        val[n] = tri_quantity(o, i, b->closed[i] || nv > 0 ? 0 : 1);
        shade[n] = 0.35 + 0.65 * fabs(nv);
        n++;
    }
    char title[200], what[96], label[96];
    quantity_names(o, what, sizeof what, label, sizeof label);
    if (o->png_q == CH_Q_VSURF && o->tri_V && o->time < 0) /* float's */
        snprintf(title, sizeof title, "%s in the steady state, U = %.6g V (%s mode)", what,
                 o->potential, o->mode);
    else if (o->png_q == CH_Q_VSURF && o->tri_V)
        snprintf(title, sizeof title, "%s at t = %.6g s, U = %.6g V (%s mode)", what, o->time,
                 o->potential, o->mode);
    else
        snprintf(title, sizeof title, "%s at U = %.6g V (%s mode, %llu histories)", what,
                 o->potential, o->mode, (unsigned long long)o->res->histories);
    mote_surface_opts so = {title, label, o->png_w, o->png_h, 0, 0, o->png_log};
    int rc = mote_surface_png(path, &so, xy, depth, val, shade, n, err);
    free(xy);
    free(depth);
    free(val);
    free(shade);
    return rc;
}

/* The body as binary little-endian PLY (spec 8.3): the vertices of each triangle, the faces
 * with the colour of the surface picture (viridis over the same range: the picture's quantity
 * on the front side) and J_net as a float property. */
static int write_ply(const ch_output *o, const char *path, mote_err *err)
{
    const mote_ch_body *b = o->body;
    double vmin = INFINITY, vmax = -INFINITY;
    for (uint32_t i = 0; i < b->ntri; i++) {
        double J = tri_quantity(o, i, 0);
        if (o->png_log)
            J = log10(fabs(J));
        if (isfinite(J)) {
            vmin = fmin(vmin, J);
            vmax = fmax(vmax, J);
        }
    }
    if (!(vmax > vmin)) {
        vmin -= 0.5;
        vmax += 0.5;
    }
    mote_afile af;
    int rc = mote_afile_open(&af, path, err);
    if (rc)
        return rc;
    FILE *f = af.f;
    fprintf(f, "ply\nformat binary_little_endian 1.0\ncomment mote charging: J_net at U = %.6g V, "
               "seed %llu\nelement vertex %u\nproperty float x\nproperty float y\nproperty float "
               "z\nelement face %u\nproperty list uchar int vertex_indices\nproperty uchar red\n"
               "property uchar green\nproperty uchar blue\nproperty float J_net\nend_header\n",
            o->potential, (unsigned long long)o->seed, 3 * b->ntri, b->ntri);
    /* little-endian words, whatever the machine */
    for (uint32_t i = 0; i < b->ntri; i++)
        for (int j = 0; j < 3; j++)
            for (int a = 0; a < 3; a++) {
                float x = (float)b->v[i][j][a];
                uint32_t w;
                memcpy(&w, &x, 4);
                const unsigned char by[4] = {(unsigned char)w, (unsigned char)(w >> 8),
                                             (unsigned char)(w >> 16), (unsigned char)(w >> 24)};
                fwrite(by, 1, 4, f);
            }
    for (uint32_t i = 0; i < b->ntri; i++) {
        unsigned char rec[1 + 12 + 3 + 4];
        rec[0] = 3;
        for (int j = 0; j < 3; j++) {
            const uint32_t idx = 3 * i + (uint32_t)j;
            for (int k = 0; k < 4; k++)
                rec[1 + 4 * j + k] = (unsigned char)(idx >> (8 * k));
        }
        const double J = tri_j(o, i, 0), q = tri_quantity(o, i, 0);
        const double val = o->png_log ? log10(fabs(q)) : q;
        double rgb[3];
        mote_viridis(isfinite(val) ? (val - vmin) / (vmax - vmin) : 0, rgb);
        for (int c = 0; c < 3; c++)
            rec[13 + c] = (unsigned char)lround(255 * rgb[c]);
        float jf = (float)J;
        uint32_t w;
        memcpy(&w, &jf, 4);
        for (int k = 0; k < 4; k++)
            rec[16 + k] = (unsigned char)(w >> (8 * k));
        fwrite(rec, 1, sizeof rec, f);
    }
    return mote_afile_commit(&af, err);
}

int ch_write_outputs(const ch_output *o, FILE *log, mote_err *err)
{
    if (ch_mpi_rank(o->solo) != 0) /* the first MPI rank writes; the others have the same numbers */
        return MOTE_OK;
    const size_t len = strlen(o->prefix) + 48;
    char *path = malloc(len);
    if (!path)
        return mote_fail(err, MOTE_ENOMEM, "output: out of memory");
    mote_make_dir_of(o->prefix); /* (the prefix= makes its folder) */
    int rc = MOTE_OK;
    static const char *const name[7] = {"_triangles.csv", "_parts.csv",   "_summary.txt",
                                        "_summary.json",  "_surface.vtk", "_surface.png",
                                        "_surface.ply"};
    for (int k = 0; k < 7 && !rc; k++) {
        if ((k == 0 && !o->triangles) || (k == 4 && !o->vtk) || (k == 5 && !o->png) ||
            (k == 6 && !o->ply))
            continue;
        if (k >= 4 && o->body->sphere)
            continue; /* the exact sphere has no triangles to draw */
        if (k == 5 && o->nviews > 1) { /* several views: a file each, named by the view */
            for (int v = 0; v < o->nviews && !rc; v++) {
                ch_output ov = *o;
                memcpy(ov.view, o->views[v], sizeof ov.view);
                snprintf(path, len, "%s_surface_%s.png", o->prefix, o->view_names[v]);
                rc = write_png(&ov, path, err);
                if (!rc && log)
                    fprintf(log, "output: wrote %s\n", path);
            }
            continue;
        }
        snprintf(path, len, "%s%s", o->prefix, name[k]);
        rc = k == 0   ? write_triangles(o, path, err)
             : k == 1 ? write_parts(o, path, err)
             : k <= 3 ? write_summary(o, path, k == 3, err)
             : k == 4 ? write_vtk(o, path, err)
             : k == 5 ? write_png(o, path, err)
                      : write_ply(o, path, err);
        if (!rc && log)
            fprintf(log, "output: wrote %s\n", path);
    }
    free(path);
    return rc;
}

int ch_write_potential(const ch_output *o, FILE *log, mote_err *err)
{
    if (ch_mpi_rank(o->solo) != 0 || o->body->sphere || (!o->vtk && !o->png))
        return MOTE_OK;
    const size_t len = strlen(o->prefix) + 48;
    char *path = malloc(len);
    const uint32_t n = o->body->ntri;
    double *v = malloc((size_t)(9 * (size_t)n + 1) * sizeof *v);
    if (!path || !v) {
        free(path);
        free(v);
        return mote_fail(err, MOTE_ENOMEM, "output: out of memory");
    }
    int rc = MOTE_OK;
    ch_output ov = *o;
    ov.png_q = CH_Q_VSURF;
    for (int k = 0; o->png && k < (o->nviews > 1 ? o->nviews : 1) && !rc; k++) {
        if (o->nviews > 1) {
            memcpy(ov.view, o->views[k], sizeof ov.view);
            snprintf(path, len, "%s_potential_%s.png", o->prefix, o->view_names[k]);
        } else {
            snprintf(path, len, "%s_potential.png", o->prefix);
        }
        rc = write_png(&ov, path, err);
        if (!rc && log)
            fprintf(log, "output: wrote %s\n", path);
    }
    if (!rc && o->vtk) {
        snprintf(path, len, "%s_potential.vtk", o->prefix);
        mote_afile af;
        if (!(rc = mote_afile_open(&af, path, err))) {
            char title[160];
            if (o->time < 0)
                snprintf(title, sizeof title, "mote charging: surface potential in the steady "
                         "state, U = %.6g V", o->potential);
            else
                snprintf(title, sizeof title, "mote charging: surface potential at t = %.6g s, "
                         "U = %.6g V", o->time, o->potential);
            vtk_geometry(af.f, o, title, v);
            for (uint32_t i = 0; i < n; i++)
                v[i] = o->tri_V[i];
            vtk_scalars(af.f, "V_surface", v, n, o->vtk_binary, 0);
            for (uint32_t i = 0; i < n; i++)
                v[i] = o->body->part[i];
            vtk_scalars(af.f, "part_id", v, n, o->vtk_binary, 1);
            rc = mote_afile_commit(&af, err);
        }
        if (!rc && log)
            fprintf(log, "output: wrote %s\n", path);
    }
    free(v);
    free(path);
    return rc;
}
