/* test_galfile.c: Galactica's body files (specs/nbody-galactica.md 7.5, 7.6; test T14): read,
 * write, read is bit-exact; ragged lines, D exponents, exponents without a letter, r*value, with
 * and without the info line (5 wide and zero-padded to a body row) all read; the Coulomb 25/16
 * layout; counts that fit no layout and bad tokens give the documented errors. */
#include "mote/nbody.h"
#include "test.h"

#include "../src/nbody/nb.h"

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

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/mote-galfile-XXXXXX");
    if (!mkdtemp(dir))
        return 1;
    test_forms();
    test_round_trip();
    test_layouts();
    const char *names[] = {"ragged.dat", "rt.dat", "info5.dat", "info15.dat", "coulomb.dat",
                           "bad.dat", "mass.dat", "rep.dat"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++)
        remove(tmp_path(names[k]));
    rmdir(dir);
    return test_summary();
}
