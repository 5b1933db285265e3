/* prepare.c: the separator's set-up before a run (specs/separator.md 2.2, 2.6, 2.12): the gas
 * properties along the channel (a profile or constants), the ranges every parameter must be in
 * (again for a state read from a file), the grids, the slices, the tallies and the time step. */
#include "mote/separator.h"

#include "sep.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The profile's density and viscosity at z (the constants without a profile). */
void sep_profile_at(const mote_sep_system *s, double z, double *rho, double *mu)
{
    if (s->gp_n == 0) {
        *rho = s->rho_g;
        *mu = s->mu_g;
        return;
    }
    size_t k = 0;
    while (k + 1 < s->gp_n && s->gp_z[k + 1] < z)
        k++;
    double f = 0;
    if (k + 1 < s->gp_n)
        f = fmin(fmax((z - s->gp_z[k]) / (s->gp_z[k + 1] - s->gp_z[k]), 0), 1);
    const size_t k1 = k + 1 < s->gp_n ? k + 1 : k;
    *rho = (1 - f) * s->gp_rho[k] + f * s->gp_rho[k1];
    *mu = isnan(s->gp_mu[k]) ? s->mu_g : (1 - f) * s->gp_mu[k] + f * s->gp_mu[k1];
}

int mote_sep_set_gas_profile(mote_sep_system *s, size_t n, const double *z, const double *rho,
                             const double *mu, mote_err *err)
{
    if (n < 2)
        return mote_fail(err, MOTE_EINVAL, "a gas profile needs at least 2 heights, found %zu", n);
    const int with_mu = !isnan(mu[0]);
    for (size_t k = 0; k < n; k++) {
        if (!isfinite(z[k]) || (k > 0 && !(z[k] > z[k - 1])))
            return mote_fail(err, MOTE_EINVAL, "row %zu: the heights must increase (z = %g after "
                             "%g)", k + 1, z[k], k ? z[k - 1] : NAN);
        if (!(rho[k] > 0) || !isfinite(rho[k]))
            return mote_fail(err, MOTE_EINVAL, "row %zu: the gas density must be > 0, found %g",
                             k + 1, rho[k]);
        if (with_mu != !isnan(mu[k]) || (with_mu && (!(mu[k] > 0) || !isfinite(mu[k]))))
            return mote_fail(err, MOTE_EINVAL, "row %zu: the viscosity must be > 0 on every row "
                             "or on none, found %g", k + 1, mu[k]);
    }
    double *zz = malloc(n * sizeof *zz), *rr = malloc(n * sizeof *rr), *mm = malloc(n * sizeof *mm);
    if (!zz || !rr || !mm) {
        free(zz);
        free(rr);
        free(mm);
        return mote_fail(err, MOTE_ENOMEM, "out of memory for the gas profile");
    }
    memcpy(zz, z, n * sizeof *zz);
    memcpy(rr, rho, n * sizeof *rr);
    memcpy(mm, mu, n * sizeof *mm);
    free(s->gp_z);
    free(s->gp_rho);
    free(s->gp_mu);
    s->gp_z = zz;
    s->gp_rho = rr;
    s->gp_mu = mm;
    s->gp_n = n;
    return MOTE_OK;
}

void mote_sep_gas_props(const mote_sep_system *s, double z, double *rho, double *mu)
{
    if (s->gp_n == 0 || !s->rho_sl) {
        sep_profile_at(s, z, rho, mu);
        return;
    }
    const double q = z / s->dz - 0.5;
    if (!(q > 0) || s->K == 1) { /* (a height that is not a number: the bottom) */
        *rho = s->rho_sl[0];
        *mu = s->mu_sl[0];
    } else if (q >= s->K - 1) {
        *rho = s->rho_sl[s->K - 1];
        *mu = s->mu_sl[s->K - 1];
    } else {
        const int k = (int)q;
        const double f = q - k;
        *rho = (1 - f) * s->rho_sl[k] + f * s->rho_sl[k + 1];
        *mu = (1 - f) * s->mu_sl[k] + f * s->mu_sl[k + 1];
    }
}

double mote_sep_d0_star(const mote_sep_system *s, int k)
{
    double r0, m0, rf, mf;
    sep_profile_at(s, 0, &r0, &m0);
    sep_profile_at(s, s->zf, &rf, &mf);
    const double v = rf > 0 ? r0 * s->U0 / rf : s->U0;
    return mote_sep_cut_size(v, s->sp[k].rho, rf, mf, s->g);
}

void sep_tallies_free(mote_sep_system *s)
{
    free(s->cl_mf);
    free(s->cl_mc);
    free(s->cl_nf);
    free(s->cl_nc);
    free(s->cls_mf);
    free(s->cls_mc);
    free(s->cls_nf);
    free(s->cls_nc);
    s->cl_mf = s->cl_mc = s->cls_mf = s->cls_mc = NULL;
    s->cl_nf = s->cl_nc = s->cls_nf = s->cls_nc = NULL;
}

int sep_tallies_alloc(mote_sep_system *s, mote_err *err)
{
    const size_t nc = (size_t)s->nclass, ns = nc * MOTE_SEP_MAX_SPECIES;
    sep_tallies_free(s);
    s->cl_mf = calloc(nc, sizeof *s->cl_mf);
    s->cl_mc = calloc(nc, sizeof *s->cl_mc);
    s->cl_nf = calloc(nc, sizeof *s->cl_nf);
    s->cl_nc = calloc(nc, sizeof *s->cl_nc);
    s->cls_mf = calloc(ns, sizeof *s->cls_mf);
    s->cls_mc = calloc(ns, sizeof *s->cls_mc);
    s->cls_nf = calloc(ns, sizeof *s->cls_nf);
    s->cls_nc = calloc(ns, sizeof *s->cls_nc);
    if (!s->cl_mf || !s->cl_mc || !s->cl_nf || !s->cl_nc || !s->cls_mf || !s->cls_mc ||
        !s->cls_nf || !s->cls_nc)
        return mote_fail(err, MOTE_ENOMEM, "separator: out of memory for the size classes");
    return MOTE_OK;
}

int sep_profiles_alloc(mote_sep_system *s, mote_err *err)
{
    const size_t nK = (size_t)s->K;
    free(s->prof_eps);
    free(s->prof_n);
    free(s->prof_mvz);
    free(s->prof_m);
    free(s->prof_ug);
    free(s->prof_fd);
    s->prof_eps = calloc(nK * MOTE_SEP_MAX_SPECIES, sizeof *s->prof_eps);
    s->prof_n = calloc(nK, sizeof *s->prof_n);
    s->prof_mvz = calloc(nK, sizeof *s->prof_mvz);
    s->prof_m = calloc(nK, sizeof *s->prof_m);
    s->prof_ug = calloc(nK, sizeof *s->prof_ug);
    s->prof_fd = calloc(nK, sizeof *s->prof_fd);
    if (!s->prof_eps || !s->prof_n || !s->prof_mvz || !s->prof_m || !s->prof_ug || !s->prof_fd)
        return mote_fail(err, MOTE_ENOMEM, "separator: out of memory for the profiles");
    s->prof_K = s->K;
    s->prof_time = 0;
    return MOTE_OK;
}

/* contact hertz: what it needs (collisions, the pair list, each species' E and nu, friction
 * >= 0), and the damping of each pair and at the walls (the restitution's beta, once per
 * distinct value). */
static int prepare_hertz(mote_sep_system *s, mote_err *err)
{
    if (!s->dem)
        return mote_fail(err, MOTE_EINVAL, "separator: contact hertz with collisions off: "
                         "nothing would collide (collisions dem)");
    if (s->brute)
        return mote_fail(err, MOTE_EINVAL, "separator: contact hertz needs the cells' pair list "
                         "(neighbours cells)");
    for (int k = 0; k < s->nsp; k++) {
        const mote_sep_species *p = &s->sp[k];
        if (!(p->E > 0 && p->E < 1e15))
            return mote_fail(err, MOTE_EINVAL, "separator: contact hertz: species %s has no "
                             "Young's modulus (species name=%s density=%g E=PASCAL nu=RATIO)",
                             p->name, p->name, p->rho);
        if (!(p->nu > -1 && p->nu < 0.5))
            return mote_fail(err, MOTE_EINVAL, "separator: species %s: Poisson's ratio %g is "
                             "outside (-1, 0.5)", p->name, p->nu);
    }
    if (!(s->E_w == 0 || (s->E_w > 0 && s->E_w < 1e15)) || !(s->nu_w > -1 && s->nu_w < 0.5))
        return mote_fail(err, MOTE_EINVAL, "separator: wall_material E=%g nu=%g: E > 0 and nu in "
                         "(-1, 0.5)", s->E_w, s->nu_w);
    const double mu[6] = {s->mu_pp, s->mur_pp, s->coh_pp, s->mu_pw, s->mur_pw, s->coh_pw};
    const char *const mname[6] = {"friction", "rolling_friction", "cohesion", "friction_wall",
                                   "rolling_friction_wall", "cohesion_wall"};
    for (int q = 0; q < 6; q++)
        if (!(mu[q] >= 0 && mu[q] <= 1e15) && !(q >= 3 && mu[q] == -1))
            return mote_fail(err, MOTE_EINVAL, "separator: %s %g: must be >= 0", mname[q], mu[q]);
    const int M = MOTE_SEP_MAX_SPECIES;
    double seen_e[M * (M + 1)], seen_b[M * (M + 1)];
    int nseen = 0;
    for (int a = 0; a < s->nsp; a++)
        for (int b = 0; b <= s->nsp; b++) { /* (b == nsp: the walls) */
            const double e = b == s->nsp ? (s->e_pw >= 0 ? s->e_pw : s->e_pp)
                             : s->e_pair[a][b] > 0 ? s->e_pair[a][b] : s->e_pp;
            double beta = NAN;
            for (int q = 0; q < nseen; q++)
                if (seen_e[q] == e)
                    beta = seen_b[q];
            if (isnan(beta)) {
                beta = s->e_true ? sep_hm_beta_exact(e) : sep_hm_beta_liggghts(e);
                seen_e[nseen] = e;
                seen_b[nseen++] = beta;
            }
            s->hm_beta[b == s->nsp ? M * M + a : a * M + b] = beta;
        }
    return MOTE_OK;
}

int mote_sep_prepare(mote_sep_system *s, mote_err *err)
{
    if (!(s->W > 0) || !(s->H > 0) || (s->dim == 3 && !(s->D > 0)))
        return mote_fail(err, MOTE_EINVAL, "separator: no channel (channel W H%s)",
                         s->dim == 3 ? " D=DEPTH: a 3D channel needs its depth" : "");
    if (!(s->U0 >= 0))
        return mote_fail(err, MOTE_EINVAL, "separator: no gas upflow (gas U0 [rho_g mu_g])");
    if (s->nsp == 0)
        return mote_fail(err, MOTE_EINVAL, "separator: no species (species NAME RHO)");
    /* the ranges the commands check, again for a state read from a file */
    {
        const struct {
            const char *name;
            double v, lo, hi;
        } r[] = {{"eps_gas_min", s->eps_gas_min, 1e-9, 1}, {"hindered", s->chi, 0, 100},
                 {"restitution", s->e_pp, 1e-9, 1}, {"gas density", s->rho_g, 0, 1e6},
                 {"gas viscosity", s->mu_g, 0, 1e6}, {"gravity", s->g, 0, 1e6},
                 {"dispersion", s->D_t, 0, 1e6}, {"brownian", s->T_gas, 0, 1e6},
                 {"relax", s->tau_eps, 0, 1e30}, {"timestep", s->dt_user, 0, 1e30},
                 {"feed rate", s->rate, 0, 1e30}, {"feed band", s->hf, 0, 1e30},
                 {"stiffness overlap", s->delta_f, 0, 0.1}, {"khat", s->khat, 0, 1e30},
                 {"vimp", s->v_imp, 0, 1e30}};
        for (size_t k = 0; k < sizeof r / sizeof r[0]; k++)
            if (!(r[k].v >= r[k].lo && r[k].v <= r[k].hi))
                return mote_fail(err, MOTE_EINVAL, "separator: %s %g is outside [%g, %g]",
                                 r[k].name, r[k].v, r[k].lo, r[k].hi);
        if (!(s->e_pw <= 1) || (s->e_pw >= 0 && !(s->e_pw > 0)))
            return mote_fail(err, MOTE_EINVAL, "separator: restitution_wall %g is outside (0, 1]",
                             s->e_pw);
    }
    double wsum = 0;
    for (int k = 0; k < s->nsp; k++) {
        if (!s->sp[k].have_dist)
            return mote_fail(err, MOTE_EINVAL, "separator: species %s has no size distribution "
                             "(size %s TYPE ...)", s->sp[k].name, s->sp[k].name);
        wsum += s->sp[k].w;
    }
    if (s->rate > 0 && fabs(wsum - 1) > 1e-9) {
        char list[512] = "";
        for (int k = 0; k < s->nsp; k++) {
            const size_t l = strlen(list);
            snprintf(list + l, sizeof list - l, "%s%s %g", k ? ", " : "", s->sp[k].name,
                     s->sp[k].w);
        }
        return mote_fail(err, MOTE_EINVAL, "separator: the feed fractions must sum to 1, found "
                         "%.10g (%s)", wsum, list);
    }
    double dmin, dmax;
    mote_sep_size_range(s, &dmin, &dmax);
    const double wmin = s->dim == 3 ? fmin(s->W, s->D) : s->W;
    if (dmax >= wmin)
        return mote_fail(err, MOTE_EINVAL, "separator: the largest particle (%g m) does not fit "
                         "the channel (%g m across)", dmax, wmin);
    /* the grids: each checked, indexed, its open area; no two overlap */
    for (int k = 0; k < s->nplate; k++) {
        mote_sep_plate *p = &s->plate[k];
        int rc = mote_sep_plate_index(p, s->dim, s->W, s->D, err);
        if (!rc)
            rc = mote_sep_plate_check(p, k + 1, s->dim, s->W, s->D, s->H, dmin, err);
        if (rc)
            return rc;
        p->phi = mote_sep_plate_open(p, s->dim, s->W, s->D);
        for (int j = 0; j < k; j++) {
            const mote_sep_plate *q = &s->plate[j];
            if (p->zb < q->zb + q->t && q->zb < p->zb + p->t)
                return mote_fail(err, MOTE_EINVAL, "separator: grids %d (%g ... %g m) and %d (%g "
                                 "... %g m) overlap", j + 1, q->zb, q->zb + q->t, k + 1, p->zb,
                                 p->zb + p->t);
        }
    }
    /* the mesh walls (DEM in 3D): their grids for the largest particle */
    double dbig = dmax;
    for (size_t i = 0; s->nmesh && i < s->n; i++)
        dbig = fmax(dbig, s->d[i]);
    for (int k = 0; k < s->nmesh; k++) {
        if (s->dim != 3 || !s->dem)
            return mote_fail(err, MOTE_EINVAL, "separator: wall_mesh (%s) needs dim 3 and "
                             "collisions dem", s->mesh[k].name);
        int rc = sep_mesh_grid(&s->mesh[k], 0.5 * dbig, err);
        if (rc)
            return rc;
    }
    /* slices: about 4 d_max each, 10 ... 1000 */
    int K = s->K;
    if (K <= 0)
        K = (int)fmin(1000, fmax(10, floor(s->H / (4 * dmax) + 0.5)));
    if (K != s->K || !s->eps_s) {
        free(s->eps_s);
        free(s->u_g);
        free(s->eps_r);
        s->eps_s = calloc((size_t)K, sizeof *s->eps_s);
        s->u_g = calloc((size_t)K, sizeof *s->u_g);
        s->eps_r = calloc((size_t)K, sizeof *s->eps_r);
        s->eps_r_valid = 0;
        if (!s->eps_s || !s->u_g || !s->eps_r)
            return mote_fail(err, MOTE_ENOMEM, "separator: out of memory for %d slices", K);
        s->K = K;
    }
    s->dz = s->H / K;
    /* the gas properties at the slice centres */
    free(s->rho_sl);
    free(s->mu_sl);
    s->rho_sl = malloc((size_t)K * sizeof *s->rho_sl);
    s->mu_sl = malloc((size_t)K * sizeof *s->mu_sl);
    if (!s->rho_sl || !s->mu_sl)
        return mote_fail(err, MOTE_ENOMEM, "separator: out of memory for %d slices", K);
    for (int k = 0; k < K; k++)
        sep_profile_at(s, (k + 0.5) * s->dz, &s->rho_sl[k], &s->mu_sl[k]);
    /* Tromp classes: 20 log-spaced over [d_min, d_max] unless given */
    if (!s->class_edge) {
        if (s->nclass <= 0)
            s->nclass = 20;
        s->class_edge = malloc((size_t)(s->nclass + 1) * sizeof *s->class_edge);
        if (!s->class_edge)
            return mote_fail(err, MOTE_ENOMEM, "separator: out of memory");
        const double lo = dmin, hi = dmax > dmin ? dmax : dmin * 1.0001;
        for (int k = 0; k <= s->nclass; k++)
            s->class_edge[k] = exp(log(lo) + (log(hi) - log(lo)) * k / s->nclass);
    }
    if (!s->cl_mf && sep_tallies_alloc(s, err))
        return err->code;
    /* the profile sums, per slice (restarted when the slices change) */
    if ((s->prof_K != s->K || !s->prof_n) && sep_profiles_alloc(s, err))
        return err->code;
    /* the time step: with contacts, the contact time over N_c (spec 2.8), which a given step
     * must not exceed; in the dilute mode half a slice (the narrowest feature) per reference
     * speed U0 + v_t(d_max) + |v_f| */
    if (!(s->parcel >= 1 && s->parcel <= 1e15))
        return mote_fail(err, MOTE_EINVAL, "separator: parcel must be in [1, 1e15], found %g",
                         s->parcel);
    if (s->dem && s->parcel > 1)
        return mote_fail(err, MOTE_EINVAL, "separator: parcel %g with collisions dem: a parcel "
                         "would collide as one particle of its size, which needs a "
                         "coarse-graining law this version does not have; use collisions off "
                         "(parcels follow the gas independently) or parcel 1", s->parcel);
    if (s->hertz) {
        int rc = prepare_hertz(s, err);
        if (rc)
            return rc;
    }
    if (s->dem) {
        if (s->nc < 20)
            return mote_fail(err, MOTE_EINVAL, "separator: N_c must be at least 20, found %d",
                             s->nc);
        s->khat_used = mote_sep_khat(s);
        const double lim = mote_sep_dt_limit(s);
        if (s->dt_user > lim)
            return mote_fail(err, MOTE_EINVAL, "separator: the time step %g s is above the "
                             "stability limit %.6g s of the contacts (t_c,min / N_c, spec 2.8)",
                             s->dt_user, lim);
        s->dt = s->dt_user > 0 ? s->dt_user : lim;
    } else if (s->dt_user > 0) {
        s->dt = s->dt_user;
    } else {
        double vt = 0;
        for (int k = 0; k < s->nsp; k++)
            vt = fmax(vt, mote_sep_terminal_velocity(mote_sep_dist_max(&s->sp[k].dist),
                                                     s->sp[k].rho, s->rho_g, s->mu_g, s->g,
                                                     NULL));
        const double vref = s->U0 + (isfinite(vt) ? vt : 0) +
                            sqrt(s->vf[0] * s->vf[0] + s->vf[1] * s->vf[1] + s->vf[2] * s->vf[2]);
        /* the narrowest feature: a slice, the thinnest plate, the narrowest hole */
        double smin = s->dz;
        for (int k = 0; k < s->nplate; k++) {
            const mote_sep_plate *p = &s->plate[k];
            smin = fmin(smin, p->t);
            for (size_t h = 0; h < p->nh; h++) {
                smin = fmin(smin, p->h[4 * h + 1] - p->h[4 * h]);
                if (s->dim == 3)
                    smin = fmin(smin, p->h[4 * h + 3] - p->h[4 * h + 2]);
            }
        }
        s->dt = vref > 0 ? 0.5 * smin / vref : 1e-3;
    }
    return mote_sep_gas_update(s, 0, err);
}
