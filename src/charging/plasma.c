/* plasma.c: the charging model's plasma (spec 3): species of Maxwellian components, the presets of
 * spec 3.2 (the thesis's Table 1, the NASA worst-case geostationary environment), and the derived
 * quantities of spec 3.3: thermal current density, mean speed, the Debye length. */
#include "mote/charging.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "ch.h"

static void add(mote_ch_plasma *p, const char *name, int Z, double m, double n1, double kT1,
                double n2, double kT2)
{
    mote_ch_species *s = &p->sp[p->nsp++];
    memset(s, 0, sizeof *s);
    snprintf(s->name, sizeof s->name, "%s", name);
    s->Z = Z;
    s->m = m;
    s->n[s->ncomp] = n1;
    s->kT[s->ncomp++] = kT1;
    if (n2 > 0) {
        s->n[s->ncomp] = n2;
        s->kT[s->ncomp++] = kT2;
    }
}

int mote_ch_plasma_preset(mote_ch_plasma *p, const char *name, double n, double kT,
                          mote_err *err)
{
    memset(p, 0, sizeof *p);
    if (strcmp(name, "geo-worst-case") == 0) { /* Table 1: cm^-3 and keV */
        add(p, "e", -1, MOTE_CH_ME, 0.2e6, 400, 1.2e6, 27500);
        add(p, "H+", 1, MOTE_CH_MP, 0.6e6, 200, 1.3e6, 28000);
    } else if (strcmp(name, "thesis-hot") == 0) {
        add(p, "e", -1, MOTE_CH_ME, 1.2e6, 27500, 0, 0);
        add(p, "H+", 1, MOTE_CH_MP, 1.3e6, 28000, 0, 0);
    } else if (strcmp(name, "single") == 0) {
        if (!(n > 0) || !(kT > 0))
            return mote_fail(err, MOTE_EINVAL, "plasma single: need n > 0 and kT > 0");
        add(p, "e", -1, MOTE_CH_ME, n, kT, 0, 0);
        add(p, "H+", 1, MOTE_CH_MP, n, kT, 0, 0);
    } else {
        return mote_fail(err, MOTE_EINVAL, "plasma: no preset '%s' (geo-worst-case, thesis-hot, "
                         "single)", name);
    }
    return MOTE_OK;
}

double mote_ch_j0(double n, double kT, double m, int Z)
{
    return fabs((double)Z) * MOTE_CH_E * n * sqrt(kT * MOTE_CH_E / (2 * MOTE_CH_PI * m));
}

double mote_ch_mean_speed(double kT, double m)
{
    return sqrt(8 * kT * MOTE_CH_E / (MOTE_CH_PI * m));
}

double mote_ch_debye(const mote_ch_plasma *p)
{
    double inv2 = 0; /* lambda^-2 = sum n q^2 / (eps0 kT) */
    for (int s = 0; s < p->nsp; s++)
        for (int k = 0; k < p->sp[s].ncomp; k++) {
            const double q = p->sp[s].Z * MOTE_CH_E;
            inv2 += p->sp[s].n[k] * q * q / (MOTE_CH_EPS0 * p->sp[s].kT[k] * MOTE_CH_E);
        }
    return inv2 > 0 ? 1 / sqrt(inv2) : INFINITY;
}

double mote_ch_oml(double A, double U, double n, double kT, double m, int Z)
{
    const double x = Z * U / kT; /* qU / kT */
    const double I0 = Z * MOTE_CH_E * A * n * sqrt(kT * MOTE_CH_E / (2 * MOTE_CH_PI * m));
    return I0 * (x >= 0 ? exp(-x) : 1 - x);
}

/* The library (data/materials.dat, compiled by scripts/materials.sh): the published values as
 * given there; the ion yield's peak d from its value at 1 keV, 2 d sqrt(1/E) / (1 + 1/E) = y1. */
static const struct {
    const char *name;
    double dmax, emax, Z, jph, eps_r, sigma, ion_y1, ion_emax, r1, n1, r2, n2;
    const char *source;
} LIB[] = {
#include "materials.inc"
};

const char *mote_ch_material_library(int k, mote_ch_material *m)
{
    if (k < 0 || (size_t)k >= sizeof LIB / sizeof LIB[0])
        return NULL;
    memset(m, 0, sizeof *m);
    snprintf(m->name, sizeof m->name, "%s", LIB[k].name);
    snprintf(m->source, sizeof m->source, "%s", LIB[k].source);
    m->see_dmax = LIB[k].dmax;
    m->see_emax = LIB[k].emax;
    m->photo_j = LIB[k].jph;
    m->Z = LIB[k].Z;
    m->eps_r = LIB[k].eps_r;
    m->sigma = LIB[k].sigma;
    m->see_r[0] = LIB[k].r1;
    m->see_r[1] = LIB[k].n1;
    m->see_r[2] = LIB[k].r2;
    m->see_r[3] = LIB[k].n2;
    m->ion_emax = LIB[k].ion_emax;
    m->ion_dmax = LIB[k].ion_y1 * (1 + 1 / LIB[k].ion_emax) * sqrt(LIB[k].ion_emax) / 2;
    m->kT_s = 2;
    m->kT_ph = 2;
    return m->name;
}

int mote_ch_material_preset(const char *name, mote_ch_material *m)
{
    /* spec 6.9: indicative values as in NASCAP-type material tables (the spec's test values) */
    /* Z: the atomic number, or for a compound the mean weighted by mass (from the standard
     * atomic weights: kapton C22H10N2O5 6.36, teflon (CF2)n 8.28, cover glass as SiO2 10.80) */
    static const struct {
        const char *name;
        double dmax, emax, jph, Z, eps_r; /* (eps_r: spec 6.9's table; 0 for conductors) */
    } T[] = {{"bare", 0, 1, 0, 0, 0},               {"aluminium", 0.97, 0.30, 4.0e-5, 13, 0},
             {"gold", 0.88, 0.80, 2.9e-5, 79, 0},   {"kapton", 2.1, 0.15, 2.0e-5, 6.36, 3.5},
             {"teflon", 3.0, 0.30, 2.0e-5, 8.28, 2.0}, {"cover-glass", 2.4, 0.40, 2.0e-5, 10.80, 3.8}};
    for (size_t k = 0; k < sizeof T / sizeof T[0]; k++)
        if (strcmp(T[k].name, name) == 0) {
            memset(m, 0, sizeof *m);
            snprintf(m->name, sizeof m->name, "%s", name);
            m->see_dmax = T[k].dmax;
            m->see_emax = T[k].emax;
            m->photo_j = T[k].jph;
            m->eps_r = T[k].eps_r;
            m->Z = T[k].Z;
            m->kT_s = 2;
            m->kT_ph = 2;
            snprintf(m->source, sizeof m->source, "%s", k ? "spec 6.9" : "");
            return 0;
        }
    for (int k = 0; mote_ch_material_library(k, m); k++)
        if (strcmp(m->name, name) == 0)
            return 0;
    return -1;
}

/* ---- NASCAP's range law ---- */

static double range_of(const double r[4], double E)
{
    return r[0] * pow(E, r[1]) + r[2] * pow(E, r[3]);
}

/* integral_0^E exp(-u (R(E) - R(E'))) dE' (keV): with E' = E (1 - y), 8-point Gauss-Legendre
 * rules on panels of y doubling from 1 / (1 + u E R'(E)) (the decay length of the integrand
 * near E' = E), until the integrand is below e^-40 or y reaches 1; on the panel that reaches
 * it, E' = E (1 - a) t^p, p = 2 / min(n1, n2, 1), which makes R(E') smooth in t where its
 * powers below 1 are not at E' = 0. */
static double range_integral(const double r[4], double E, double u)
{
    static const double gx[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                 0.9602898564975363};
    static const double gw[4] = {0.3626837833783620, 0.3137066661925261, 0.2223810344533745,
                                 0.1012285362903763};
    const double RE = range_of(r, E);
    const double dR = r[0] * r[1] * pow(E, r[1] - 1) + r[2] * r[3] * pow(E, r[3] - 1);
    double a = 0, h = 1 / (1 + u * E * fabs(dR)), sum = 0;
    while (a < 1) {
        const double b = fmin(1, a + h), mid = 0.5 * (a + b), half = 0.5 * (b - a);
        double s = 0;
        if (b < 1) {
            for (int k = 0; k < 4; k++)
                for (int sg = -1; sg <= 1; sg += 2) {
                    const double y = mid + sg * half * gx[k];
                    s += gw[k] * exp(-u * (RE - range_of(r, E * (1 - y))));
                }
            sum += s * half;
        } else {
            const double p = 2 / fmin(1, fmin(r[0] > 0 ? r[1] : 1, r[2] > 0 ? r[3] : 1));
            for (int q = 0; q < 4; q++) /* (t in quarters) */
                for (int k = 0; k < 4; k++)
                    for (int sg = -1; sg <= 1; sg += 2) {
                        const double t = 0.25 * (q + 0.5 + sg * 0.5 * gx[k]), tp = pow(t, p - 1);
                        s += gw[k] * p * tp * exp(-u * (RE - range_of(r, E * (1 - a) * tp * t)));
                    }
            sum += 0.125 * s * (1 - a);
        }
        if (u * (RE - range_of(r, E * (1 - b))) > 40)
            break;
        a = b;
        h *= 2;
    }
    return E * sum;
}

int mote_ch_see_range_fit(mote_ch_material *m, mote_err *err)
{
    const double *r = m->see_r, E = m->see_emax;
    if (!(r[0] > 0 || r[2] > 0) || r[0] < 0 || r[2] < 0 || !(r[1] >= 0) || !(r[3] >= 0))
        return mote_fail(err, MOTE_EINVAL, "material %s: the range law needs its range "
                         "see_r1=, see_n1=, see_r2=, see_n2= (R = r1 E^n1 + r2 E^n2 angstrom, E in "
                         "keV; none given, or negative)", m->name);
    if (!(m->see_dmax > 0) || !(E > 0))
        return mote_fail(err, MOTE_EINVAL, "material %s: the range law needs see_dmax > 0 and "
                         "see_emax > 0", m->name);
    /* the peak: d/dE of c1 f(E; c2) is c1 (1 - c2 R'(E) f(E; c2)), zero where F(c2) =
     * c2 R'(E) f(E; c2) = 1; F rises from 0 and crosses 1 when R is convex there. In kappa =
     * c2 E R'(E): scan up by factors of 2, then bisect. */
    const double dR = r[0] * r[1] * pow(E, r[1] - 1) + r[2] * r[3] * pow(E, r[3] - 1);
    if (!(dR > 0))
        return mote_fail(err, MOTE_EINVAL, "material %s: the range law's range does not grow "
                         "at see_emax", m->name);
    double lo = 1e-3, hi = 0;
    for (double k = 1e-3; k < 1e5; k *= 2) {
        const double F = k / E * range_integral(r, E, k / (E * dR));
        if (F > 1) {
            hi = k;
            break;
        }
        lo = k;
    }
    if (!(hi > 0))
        return mote_fail(err, MOTE_EINVAL, "material %s: its range law gives no peak of the yield "
                         "at see_emax = %g keV (the range must grow faster than linearly there)",
                         m->name, E);
    for (int it = 0; it < 100 && hi - lo > 1e-14 * hi; it++) {
        const double k = 0.5 * (lo + hi);
        if (k / E * range_integral(r, E, k / (E * dR)) > 1)
            hi = k;
        else
            lo = k;
    }
    m->see_c2 = 0.5 * (lo + hi) / (E * dR);
    m->see_c1 = m->see_dmax / range_integral(r, E, m->see_c2);
    return MOTE_OK;
}

void ch_yields_prepare(const mote_ch_material *m, ch_yields *y)
{
    memset(y, 0, sizeof *y);
    if (m->see_dmax > 0) {
        y->see_a = m->see_law == 1 ? m->see_dmax : m->see_dmax / (1 - exp(-2.28)); /* dmax K */
        y->emax = m->see_emax;
        y->ln_emax = log(m->see_emax);
        y->law = m->see_law;
        y->angle = m->see_angle;
        for (int k = 0; k < 4; k++)
            y->r[k] = m->see_r[k];
        y->c1 = m->see_c1;
        y->c2 = m->see_c2;
    }
    if (m->Z > 0) {
        const double lz = log(m->Z);
        y->bs_mz = 0.1382 - 0.9211 / sqrt(m->Z);
        y->bs_C = 0.1904 - 0.2236 * lz + 0.1292 * lz * lz - 0.01491 * lz * lz * lz;
        y->bs_ln = y->bs_C > 0 ? log(y->bs_C / 0.891) : 0;
    }
}

double ch_see_ln(const ch_yields *y, double E_keV, double lnE, double cos_t)
{
    if (!(y->see_a > 0) || !(E_keV > 0))
        return 0;
    const double x = E_keV / y->emax;
    if (y->law == 1)
        return y->see_a * x * exp(2 - 2 * sqrt(x));
    if (y->law == 2) /* (grazing, cos 0: c1 E) */
        return y->c1 * range_integral(y->r, E_keV, y->c2 * fmin(fmax(cos_t, 0), 1));
    const double t = exp(0.35 * (lnE - y->ln_emax)); /* x^0.35: x^-0.35 = 1/t, x^1.35 = x t */
    if (y->angle == 1) {
        const double c = fmax(cos_t, 1e-6); /* grazing: the limit dmax K x^0.65 2.28 */
        return y->see_a / t * -expm1(-2.28 * c * x * t) / c;
    }
    return y->see_a / t * (1 - exp(-2.28 * x * t));
}

double ch_bs_ln(const ch_yields *y, double E_keV, double lnE, double cos_t)
{
    if (!(y->bs_C > 0) || !(E_keV > 0.05))
        return 0;
    const double c = fmin(fmax(cos_t, 0), 1);
    if (E_keV >= 1) { /* ln(eta0 / 0.891) = ln(C / 0.891) + m_z ln E */
        const double l = y->bs_ln + y->bs_mz * lnE;
        return l >= 0 ? 0.891 : 0.891 * exp(c * l);
    }
    const double eta0 = fmin(y->bs_C * (lnE - log(0.05)) / log(20.0), 0.891);
    return eta0 > 0 ? 0.891 * exp(c * log(eta0 / 0.891)) : 0;
}

double mote_ch_see_yield(const mote_ch_material *m, double E_keV, double cos_t)
{
    ch_yields y;
    ch_yields_prepare(m, &y);
    return E_keV > 0 ? ch_see_ln(&y, E_keV, log(E_keV), cos_t) : 0;
}

double mote_ch_backscatter_yield(const mote_ch_material *m, double E_keV, double cos_t)
{
    ch_yields y;
    ch_yields_prepare(m, &y);
    return E_keV > 0 ? ch_bs_ln(&y, E_keV, log(E_keV), cos_t) : 0;
}

double mote_ch_backscatter_escape(double U, double E_eV)
{
    return U <= 0 ? 1 : E_eV > U ? 1 - U / E_eV : 0;
}

double mote_ch_ion_yield(const mote_ch_material *m, double E_keV)
{
    if (!(m->ion_dmax > 0) || !(E_keV > 0))
        return 0;
    const double x = E_keV / m->ion_emax;
    return 2 * m->ion_dmax * sqrt(x) / (1 + x);
}
