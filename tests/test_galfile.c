/* test_galfile.c: Galactica's control file (spec 7.2, 7.3; test T15) and body files
 * (specs/nbody-galactica.md 7.5, 7.6; test T14): read,
 * write, read is bit-exact; ragged lines, D exponents, exponents without a letter, r*value, with
 * and without the info line (5 wide and zero-padded to a body row) all read; the Coulomb 25/16
 * layout; counts that fit no layout and bad tokens give the documented errors. */
#include "mote/nbody.h"
#include "test.h"

#include "../src/nbody/nb.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static char dir[64];

static const char *tmp_path(const char *name)
{
    static char p[256];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return p;
}

static void write_text(const char *name, const char *text)
{
    FILE *f = fopen(tmp_path(name), "w");
    fputs(text, f);
    fclose(f);
}

/* Two bodies in the 24/15 layout, ragged, with Fortran's number forms. */
static const char RAGGED[] =
    "0.0 0.9 1.5D0 1.0-3 3*0 0.0 0.0 0.05\n"
    "3*0, 0.4 0.4 0 1e-3 3*0 1 1 1 2\n"
    "0.9 0.1 0 0 0 0.1d0 0 3*0 3*0 0.01 0\n"
    "0.1,-0.9,0,0, 0,-0.9E+0,0 ,3*0, 0 0 0 0.005 0\n";

static void test_forms(void)
{
    printf("T14: Fortran's number forms, ragged lines\n");
    mote_err err = {0};
    write_text("ragged.dat", RAGGED);
    nb_galfile g;
    const int rc = nb_galfile_read(tmp_path("ragged.dat"), 0, -1, &g, &err);
    CHECK(rc == MOTE_OK, "read: %s", err.msg);
    if (rc)
        return;
    CHECK(g.n == 2 && g.info == 0, "n %u info %d", g.n, g.info);
    CHECK(g.head[2] == 1.5 && g.head[3] == 1.0e-3 && g.head[4] == 0 && g.head[6] == 0 &&
          g.head[9] == 0.05, "header %g %g %g", (double)g.head[2], (double)g.head[3], (double)g.head[9]);
    CHECK(g.head[13] == 0.4 && g.head[23] == 2, "E %g Mu %g", (double)g.head[13], (double)g.head[23]);
    CHECK(g.body[0] == 0.9 && g.body[1] == 0.1 && g.body[5] == 0.1 && g.body[13] == 0.01,
          "body 1 %g %g %g", (double)g.body[0], (double)g.body[5], (double)g.body[13]);
    CHECK(g.body[15] == 0.1 && g.body[16] == -0.9 && g.body[20] == -0.9 && g.body[28] == 0.005,
          "body 2 %g %g %g", (double)g.body[15], (double)g.body[20], (double)g.body[28]);
    nb_galfile_free(&g);
    /* exactly k2 bodies: the same file with n = 2; with n = 3 the count is wrong */
    CHECK(nb_galfile_read(tmp_path("ragged.dat"), 0, 2, &g, &err) == MOTE_OK, "k2: %s", err.msg);
    nb_galfile_free(&g);
    CHECK(nb_galfile_read(tmp_path("ragged.dat"), 0, 3, &g, &err) != MOTE_OK &&
          strstr(err.msg, "54 numbers, but 24 header numbers and 3 bodies of 15 make 69"),
          "k2 = 3: %s", err.msg);
}

/* read, write, read: every number the same, with and without the info line */
static void test_round_trip(void)
{
    printf("T14: read, write, read is bit-exact\n");
    mote_err err = {0};
    mote_nb nb;
    mote_nb_init(&nb, MOTE_NB_GRAVITY);
    mote_rng rng;
    mote_rng_seed(&rng, 3);
    for (int i = 0; i < 7; i++) {
        mote_real x[3], v[3];
        for (int a = 0; a < 3; a++) {
            x[a] = mote_rng_uniform(&rng) - 0.5;
            v[a] = (mote_rng_uniform(&rng) - 0.5) / 3;
        }
        CHECK(mote_nb_add(&nb, (mote_real)(1.0 / 7), 0, x, v, 1e-3 * (i + 1), &err) == MOTE_OK,
              "add: %s", err.msg);
    }
    for (uint32_t k = 0; k < 3 * nb.n; k++) {
        nb.d5p[k] = mote_rng_uniform(&rng) * 1e-7;
        nb.sp[k] = mote_rng_uniform(&rng) * 1e-9;
    }
    nb.T = (mote_real)0.123456789012345678;
    nb.dtp = (mote_real)1.0 / 3e4;
    nb.dt = (mote_real)1.0 / 1e4;
    for (int info = 0; info <= 1; info++) {
        nb_galfile g, h, k;
        mote_real *body = malloc(15 * nb.n * sizeof *body);
        nb_to_galfile(&nb, NULL, &g, body);
        CHECK(nb_galfile_write(tmp_path("rt.dat"), &g, info, &err) == MOTE_OK, "write: %s", err.msg);
        CHECK(nb_galfile_read(tmp_path("rt.dat"), 0, -1, &h, &err) == MOTE_OK, "read: %s", err.msg);
        int same = h.n == g.n && h.info == info && !memcmp(h.head, g.head, 24 * sizeof *h.head) &&
                   !memcmp(h.body, g.body, 15 * g.n * sizeof *h.body);
        CHECK(same, "info %d: the numbers read back differ", info);
        /* and through the system: file -> nb -> file */
        mote_nb t;
        mote_nb_init(&t, MOTE_NB_GRAVITY);
        CHECK(nb_from_galfile(&t, &h, "rt.dat", &err) == MOTE_OK, "from: %s", err.msg);
        mote_real *body2 = malloc(15 * t.n * sizeof *body2);
        nb_to_galfile(&t, h.head, &k, body2);
        same = k.n == g.n && !memcmp(k.head, g.head, 24 * sizeof *k.head) &&
               !memcmp(k.body, g.body, 15 * g.n * sizeof *k.body);
        CHECK(same && t.T == nb.T && t.dtp == nb.dtp && t.dt == nb.dt && !t.restart,
              "info %d: through the system", info);
        printf("  info line %s: %u bodies, header and bodies identical after read, write, read\n",
               info ? "on" : "off", h.n);
        free(body2);
        mote_nb_free(&t);
        nb_galfile_free(&h);
        free(body);
    }
    mote_nb_free(&nb);
}

/* the info line: 5 wide, or zero-padded to a body row (the MathCad layout); Coulomb 25/16 */
static void test_layouts(void)
{
    printf("T14: info lines and the Coulomb layout\n");
    mote_err err = {0};
    char text[4096];
    /* gravity, one body, info line of 5 */
    snprintf(text, sizeof text, "%s1 0 0 0 0 0 0 0 0 0 0 0 0 0.1 0\n20240102 1 1.99e30 1.5e11 3e-5\n",
             "0 1 0 0 0 0 0 0 0 0 0 0 0 0 0\n0 1e-3 0 0 0 0 0 0 0\n");
    write_text("info5.dat", text);
    nb_galfile g;
    CHECK(nb_galfile_read(tmp_path("info5.dat"), 0, -1, &g, &err) == MOTE_OK && g.n == 1 &&
          g.info == 1 && g.infov[0] == 20240102 && g.infov[3] == 1.5e11, "info 5: %s", err.msg);
    nb_galfile_free(&g);
    /* two bodies and the info line padded to 15 */
    snprintf(text, sizeof text, "%s0.5 1 0 0 0 0 0 0 0 0 0 0 0 0.1 0\n0.5 -1 0 0 0 0 0 0 0 0 0 0 0 0.1 0\n"
             "20240102 2 1.99e30 1.5e11 3e-5 0 0 0 0 0 0 0 0 0 0\n",
             "0 1 0 0 0 0 0 0 0 0 0 0 0 0 0\n0 1e-3 0 0 0 0 0 0 0\n");
    write_text("info15.dat", text);
    CHECK(nb_galfile_read(tmp_path("info15.dat"), 0, -1, &g, &err) == MOTE_OK && g.n == 2 &&
          g.info == 2 && g.infov[1] == 2, "info 15: %s n %u info %d", err.msg, g.n, g.info);
    nb_galfile_free(&g);
    /* Coulomb: 25 header numbers, 16 per particle (the charge last) */
    snprintf(text, sizeof text, "%s0.5 1 0 0 0 0 0 0 0 0 0 0 0 0 0 -1\n0.5 -1 0 0 0 0 0 0 0 0 0 0 0 0 0 1\n",
             "0 1 0 0 0 0 0 0 0 0 0 0 0 0 0\n0 1e-3 0 0 0 0 0 0 0 80\n");
    write_text("coulomb.dat", text);
    CHECK(nb_galfile_read(tmp_path("coulomb.dat"), 1, -1, &g, &err) == MOTE_OK && g.n == 2 &&
          g.head[24] == 80 && g.body[15] == -1 && g.body[31] == 1, "coulomb: %s", err.msg);
    nb_galfile_free(&g);
    /* read as gravity, the Coulomb file's 57 numbers fit no layout: the message says so */
    CHECK(nb_galfile_read(tmp_path("coulomb.dat"), 0, -1, &g, &err) != MOTE_OK &&
          strstr(err.msg, "57 numbers are not 24 header numbers and 15 per body") &&
          strstr(err.msg, "interaction=coulomb"), "coulomb as gravity: %s", err.msg);
    /* a token that is not a number, with its line */
    write_text("bad.dat", "0 1 0 0 0\n0 0 x 0\n");
    CHECK(nb_galfile_read(tmp_path("bad.dat"), 0, -1, &g, &err) != MOTE_OK &&
          strstr(err.msg, "bad.dat:2: expected a number, found 'x'"), "bad token: %s", err.msg);
    /* a repeat that blows a small file up */
    write_text("rep.dat", "0 1 67456745*2\n");
    CHECK(nb_galfile_read(tmp_path("rep.dat"), 0, -1, &g, &err) != MOTE_OK &&
          strstr(err.msg, "rep.dat:1: the repeats make more than"), "repeat: %s", err.msg);
    /* a mass above 1 */
    snprintf(text, sizeof text, "%s2 1 0 0 0 0 0 0 0 0 0 0 0 0.1 0\n",
             "0 1 0 0 0 0 0 0 0 0 0 0 0 0 0\n0 1e-3 0 0 0 0 0 0 0\n");
    write_text("mass.dat", text);
    CHECK(nb_galfile_read(tmp_path("mass.dat"), 0, 1, &g, &err) != MOTE_OK &&
          strstr(err.msg, "mass.dat:3: body 1: the mass 2 is not a fraction of the total"),
          "mass: %s", err.msg);
}

/* ---- T15: the control file ------------------------------------------------------------------ */

/* The Table-1 sample of spec 7.3: descriptions (or blanks) in columns 1-59, values from 60. */
static const char *const SAMPLE[][2] = {
    {"Length of area along axis X (A=1) 03.01.2016", "1."}, {"Height of are along axis Y (B <=1)", "1."},
    {"Thickness of area along axis Z (C <=1)", "1."}, {"Initial X coordinate of area", "0"},
    {"Initial Y coordinate of area", "0"}, {"Initial Z coordinate of area", "0"},
    {"Number of divisions over axis X", "2"}, {"Relative initial density of the area", "1."},
    {"Relative initial density of point body", "2."}, {"X - coordinate of a separate body", "1.5"},
    {"Y - coordinate of a separate body", "0.5"}, {"Z - coordinate of a separate body", "0.5"},
    {"Velocity of the separate body along axis X", "-0.4"}, {"Velocity of the separate body along axis Y", "-0.15"},
    {"Velocity of the separate body along axis Z", "0.5"}, {"Angular velocity of rotation of area", "0.0"},
    {"Relative X-coordinate of the axis of rotation", "0.5"}, {"Relative Y-coordinate of the axis of rotation", "0.5"},
    {"Absolute average density of the area, kg/m3", "1.E-7"}, {"Absolute density of bodies, kg/m3", "5000."},
    {"Depiction with respect to first body (below)", "0"}, {"Integration time step at Kl1=0", "5.0e-4"},
    {"Maximum dimension of TR array", "6000"}, {"Number of integration steps in one cycle", "1000"},
    {"Number of cycles", "1"}, {"Key: input data from file 4", "2"},
    {"Key: start of counting time/Step correction", "1"}, {"Search of encounters of body No. at Kl3", "0"},
    {"Key: writing data to file", "0"}, {"Number of interacting bodies", "12"},
    {"Interval of data (picture) output (in steps)", "500"}, {"Beginning step-by-step of data (pctrs) output", "0"},
    {"Key: writing trajectory parameters", "0"}, {"Steps interval of trajectory parameters", "50"},
    {"Display mode", "0"}, {"Correction of the area size on the screen", "1"},
    {"Coefficient of area form on the screen", "0.72"}, {"Coefficient of mass size of the screen", "0.08"},
    {"Coefficient of velocity on the screen", "3."}, {"Crrctn factor of step dtk at bodies' approach", "0.5"},
    {"Flat depiction of layer to Z", "0.3"}, {"Rotation of area relative to X-axis by angle", "10."},
    {"Rotation of area relative to Y-axis by angle", "20."}, {"Begining of screen area along x", "300."},
    {"Begining of screen area along y", "280."}, {"Image size in x", "150."},
    {"Image size in y", "70."}, {"Initial data file name", "sn2010Ap.dat"},
    {"Number of bodies in trajectory analysis", "2"}, {"Key: body velocity output", "0"},
    {"Velocity colour of the first body", "3"}, {"Velocity colour of the all bodies", "4"},
    {"", ""}, {"Number of the first body", "1 5"},
    {"Velocity colour the second body", "5"}, {"Free key of the second body", ""},
    {"Number of the second body", "2"}, {"Velocity colour of the third body", "8"},
    {"Free key of the third body", "1"}, {"Number of the third body", "4"},
};
#define NSAMPLE (sizeof SAMPLE / sizeof SAMPLE[0])

static const double SAMPLE_V[50] = {1, 1, 1, 0, 0, 0, 2, 1, 2, 1.5, 0.5, 0.5, -0.4, -0.15, 0.5, 0,
                                    0.5, 0.5, 1e-7, 5000, 0, 5e-4, 6000, 1000, 1, 2, 1, 0, 0, 12,
                                    500, 0, 0, 50, 0, 1, 0.72, 0.08, 3, 0.5, 0.3, 10, 20, 300, 280,
                                    150, 70, 0, 2, 0};

/* The sample with (described) or without descriptions. */
static void write_sample(const char *name, int described)
{
    FILE *f = fopen(tmp_path(name), "w");
    for (size_t k = 0; k < NSAMPLE; k++)
        fprintf(f, "%-59s%s\n", described ? SAMPLE[k][0] : "", SAMPLE[k][1]);
    fclose(f);
}

static int sample_ok(const nb_galctl *g, const char *what)
{
    int ok = 1;
    for (int k = 0; k < 50; k++)
        if (k != 47 && g->v[k] != SAMPLE_V[k]) {
            printf("  %s: line %d is %.17g, expected %.17g\n", what, k + 1, g->v[k], SAMPLE_V[k]);
            ok = 0;
        }
    static const long trio[3][3] = {{3, 4, 1}, {5, 0, 2}, {8, 1, 4}};
    ok = ok && g->ntrio == 3 && !strcmp(g->fima4, "sn2010Ap.dat");
    for (int t = 0; ok && t < 3; t++)
        for (int r = 0; r < 3; r++)
            ok = ok && g->trio[t][r] == trio[t][r];
    return ok;
}

static void test_control(void)
{
    printf("T15: the control file galacf26.dat\n");
    mote_err err = {0};
    nb_galctl g;
    /* the Table-1 sample, described: the trios by their descriptions */
    write_sample("galacf26.dat", 1);
    CHECK(nb_galctl_read(tmp_path("galacf26.dat"), 0, 0, &g, &err) == MOTE_OK, "read: %s", err.msg);
    CHECK(sample_ok(&g, "described") && !strcmp(g.date, "03.01.2016"), "the Table-1 sample (date '%s')",
          g.date);
    /* without descriptions: the prose layout, line 53 reserved */
    write_sample("plain.dat", 0);
    CHECK(nb_galctl_read(tmp_path("plain.dat"), 0, 0, &g, &err) == MOTE_OK && sample_ok(&g, "prose"),
          "prose: %s", err.msg);
    /* packed: trios at 51-53, 54-56, 57-59 */
    FILE *f = fopen(tmp_path("packed.dat"), "w");
    for (size_t k = 0; k < 50; k++)
        fprintf(f, "%-59s%s\n", "", SAMPLE[k][1]);
    static const char *const pk[9] = {"3", "4", "1", "5", "0", "2", "8", "1", "4"};
    for (int k = 0; k < 9; k++)
        fprintf(f, "%-59s%s\n", "", pk[k]);
    fclose(f);
    CHECK(nb_galctl_read(tmp_path("packed.dat"), 0, 1, &g, &err) == MOTE_OK && sample_ok(&g, "packed"),
          "packed: %s", err.msg);
    /* the column-60 rule: a token running across column 60 belongs to the description; tabs
     * count to 8-column stops; a line shorter than 60 gives the default */
    f = fopen(tmp_path("col60.dat"), "w");
    for (size_t k = 0; k < 50; k++) {
        if (k == 6) /* Mu: the description overruns column 60, the value follows */
            fprintf(f, "%-55sxxxxxxxxx 7\n", "Number of divisions over axis X");
        else if (k == 8) /* RoS: tabs to column 60 (7 tabs = 56 columns, then 3 blanks) */
            fprintf(f, "\t\t\t\t\t\t\t   2.5\n");
        else if (k == 9) /* Xs: a short line */
            fprintf(f, "X - coordinate\n");
        else
            fprintf(f, "%-59s%s\n", SAMPLE[k][0], SAMPLE[k][1]);
    }
    fclose(f);
    CHECK(nb_galctl_read(tmp_path("col60.dat"), 0, 0, &g, &err) == MOTE_OK && g.v[6] == 7 &&
          g.v[8] == 2.5 && g.v[9] == 0 && !g.have[9], "column 60: %s (Mu %g RoS %g Xs %g)", err.msg,
          g.v[6], g.v[8], g.v[9]);
    /* lenient: the last token of each line, wherever it is */
    f = fopen(tmp_path("lenient.dat"), "w");
    for (size_t k = 0; k < 50; k++)
        fprintf(f, "%s %s\n", k == 0 ? "A" : "p", SAMPLE[k][1][0] ? SAMPLE[k][1] : "0");
    fclose(f);
    CHECK(nb_galctl_read(tmp_path("lenient.dat"), 1, 0, &g, &err) == MOTE_OK && g.v[12] == -0.4 &&
          g.v[29] == 12 && !strcmp(g.fima4, "sn2010Ap.dat"), "lenient: %s", err.msg);
    /* write, read: the same values */
    write_sample("galacf26.dat", 1);
    nb_galctl h;
    CHECK(nb_galctl_read(tmp_path("galacf26.dat"), 0, 0, &g, &err) == MOTE_OK &&
          nb_galctl_write(tmp_path("out26.dat"), &g, &err) == MOTE_OK &&
          nb_galctl_read(tmp_path("out26.dat"), 0, 0, &h, &err) == MOTE_OK && sample_ok(&h, "written"),
          "write, read: %s", err.msg);
    f = fopen(tmp_path("out26.dat"), "r");
    char line[256];
    int n = 0, col60 = 1;
    while (fgets(line, sizeof line, f)) {
        n++;
        col60 = col60 && strlen(line) > 60 && line[58] == ' ' && line[59] != ' ';
    }
    fclose(f);
    CHECK(n == 60 && col60, "the written file: %d lines, values at column 60: %d", n, col60);
    /* a bad value, named with its line and parameter */
    f = fopen(tmp_path("bad26.dat"), "w");
    for (size_t k = 0; k < 50; k++)
        fprintf(f, "%-59s%s\n", SAMPLE[k][0], k == 6 ? "2.5" : SAMPLE[k][1]);
    fclose(f);
    CHECK(nb_galctl_read(tmp_path("bad26.dat"), 0, 0, &g, &err) != MOTE_OK &&
          strstr(err.msg, "bad26.dat:7: Mu (Number of divisions over axis X): expected a whole "
                          "number from column 60, found '2.5'"), "bad value: %s", err.msg);
    printf("  Table-1 sample, prose and packed trios, column 60 with tabs, lenient, write and read\n");
}

/* T25: the corrected step lands on DeltaT within one ulp, for fresh starts and continuations */
static void test_steps_between(void)
{
    printf("T25: steps between two dates\n");
    mote_err err = {0};
    mote_rng rng;
    mote_rng_seed(&rng, 25);
    double worst = 0;
    int n = 0;
    for (int k = 0; k < 200; k++) {
        const double jd1 = 2440000.5 + 20000 * mote_rng_uniform(&rng);
        const double jd2 = jd1 + 1 + 3000 * mote_rng_uniform(&rng);
        const double dt = 1e-6 * pow(10, 2 * mote_rng_uniform(&rng));
        for (int fresh = 0; fresh <= 1; fresh++) {
            mote_nb_steps st;
            CHECK(mote_nb_steps_between(jd1, jd2, 36525.636042, dt, fresh, 0.001, &st, &err) == MOTE_OK,
                  "steps: %s", err.msg);
            const double ulp = nextafter((double)st.DeltaT, INFINITY) - (double)st.DeltaT;
            const double off = fabs((double)(st.t_end - st.DeltaT)) / ulp;
            worst = off > worst ? off : worst;
            n++;
            CHECK(off <= 1 && fabs((double)st.DeltaT / dt - (double)st.Ltk) <= 0.5 + 1e-9,
                  "jd %.10g .. %.10g dt %g fresh %d: %.2f ulp, Ltk %llu", jd1, jd2, dt, fresh, off,
                  (unsigned long long)st.Ltk);
        }
    }
    printf("  %d intervals: T_end within %.1f ulp of DeltaT at worst\n", n, worst);
    mote_nb_steps st;
    CHECK(mote_nb_steps_between(2.0, 1.0, 36525.636042, 1e-5, 0, 0.001, &st, &err) != MOTE_OK &&
          strstr(err.msg, "need jd1 < jd2"), "order: %s", err.msg);
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/mote-galfile-XXXXXX");
    if (!mkdtemp(dir))
        return 1;
    test_forms();
    test_round_trip();
    test_layouts();
    test_control();
    test_steps_between();
    const char *names[] = {"ragged.dat", "rt.dat", "info5.dat", "info15.dat", "coulomb.dat",
                           "bad.dat", "mass.dat", "rep.dat", "galacf26.dat", "plain.dat",
                           "packed.dat", "col60.dat", "lenient.dat", "out26.dat", "bad26.dat"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++)
        remove(tmp_path(names[k]));
    rmdir(dir);
    return test_summary();
}
