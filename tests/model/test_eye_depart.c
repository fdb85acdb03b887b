/* test_eye_depart.c: the measured surfaces in the eye's mesh (lib/model/eye_depart.h): the
 * departure is the Zernike sum inside its zone, C2 across the zone's rim and the taper's end
 * (one-sided differences of value, slope and curvature), 0 beyond; a coarse P2 eye meshed with
 * and without departures (the same gmsh mesh of revolution), the anterior base aspheric (Q
 * -0.2): anterior nodes on the aspheric base (its apex lowered by c0) plus the anterior
 * departure and posterior nodes of the cornea on the base posterior (moved with the column)
 * plus the posterior departure, to 1e-12 mm; the sclera unmoved; the curved mesh valid (kt_eye_check_curved inside kt_eye_mesh);
 * a taper past the corneal edge or the limbus, a departure thicker than half the cornea and an
 * aspheric base that ends before the corneal edge refused (KT_EINPUT naming the field); a scene
 * with departures written (kt_scene_write_eye: coefficients in um) reads back to the same
 * doubles, and writes again to the same bytes. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "eye.h"
#include "kt_test.h"
#include "scene.h"
#include "scene_write.h"

#include "kt_test_gmsh.h"

#define NP KT_ZERN_NP

/* A coarse P2 eye, 1.5 D of cylinder at 30 deg, a toric posterior, no rings. */
static void coarse_eye(kt_eye *e)
{
    memset(e, 0, sizeof *e);
    e->r_ant_steep = 337.5 / (337.5 / 7.8 + 0.75);
    e->r_ant_flat = 337.5 / (337.5 / 7.8 - 0.75);
    e->steep_axis = 30;
    e->r_post_steep = 6.536, e->r_post_flat = 6.873, e->post_axis = 90;
    e->r_post = 2 / (1 / 6.536 + 1 / 6.873);
    e->t_central = 0.54;
    e->t_peripheral = 0.67;
    e->wtw = 11.7;
    e->limbus_width = 1.0;
    e->sclera_thickness = 0.53;
    e->globe_radius = 12;
    e->extent = 50;
    e->optical_zone = 6;
    e->h_optical = 0.5;
    e->h_incision = 0.5;
    e->h_cornea = 0.54;
    e->h_sclera = 2.0;
}

/* Departures of a few um: coma, trefoil, astigmatism and spherical terms (mm). */
static void departures(kt_eye *e, double scale)
{
    kt_eye_departure *a = &e->dep_ant, *p = &e->dep_post;
    a->conic = -0.2;
    a->order = 8, a->radius = 4, a->taper = 0.5 * e->wtw;
    a->coef[3] = 2e-3, a->coef[7] = -3e-3, a->coef[9] = 1.5e-3, a->coef[12] = 4e-3, a->coef[24] = -1e-3;
    p->order = 6, p->radius = 4, p->taper = 5.0;
    p->coef[5] = 3e-3, p->coef[8] = 2e-3, p->coef[12] = -2e-3;
    for (int j = 0; j < KT_ZERN_TERMS_MAX; j++) a->coef[j] *= scale, p->coef[j] *= scale;
}

static void test_profile(void)
{
    kt_eye e;
    coarse_eye(&e);
    departures(&e, 1);
    const kt_eye_departure *d = &e.dep_ant;
    double poly[NP * NP];
    kt_eye_departure_poly(d, poly);
    double x = 1.3, y = -2.1, sum = 0;
    for (int j = 0; j < kt_zern_nterms(d->order); j++) {
        int n, m;
        double mono[NP * NP];
        kt_zern_nm(j, &n, &m);
        kt_zern_mono(n, m, mono);
        sum += d->coef[j] * kt_zern_poly_value(mono, n, x / d->radius, y / d->radius);
    }
    CHECK_NEAR(kt_eye_departure_at(d, poly, x, y), sum, 1e-15, "inside the zone: the Zernike sum");
    /* Along a meridian, one-sided values, slopes and curvatures at the rim a and the end b. */
    double c = cos(0.7), s = sin(0.7), h = 1e-4;
    const double at[2] = {d->radius, d->taper};
    for (int k = 0; k < 2; k++) {
        double f[5];
        for (int i = -2; i <= 2; i++) f[i + 2] = kt_eye_departure_at(d, poly, (at[k] + i * h) * c, (at[k] + i * h) * s);
        double sl_in = (f[2] - f[1]) / h, sl_out = (f[3] - f[2]) / h;
        double cu_in = (f[2] - 2 * f[1] + f[0]) / (h * h), cu_out = (f[4] - 2 * f[3] + f[2]) / (h * h);
        CHECK(fabs(f[1] - f[3]) < 3 * h * (fabs(sl_in) + 1e-9) + 1e-12, "%s: value continuous (%.3g, %.3g)",
              k ? "taper end" : "zone rim", f[1], f[3]);
        CHECK(fabs(sl_in - sl_out) < 2 * h * (fabs(cu_in) + fabs(cu_out)) + 1e-9, "%s: slope continuous (%.6g, %.6g)",
              k ? "taper end" : "zone rim", sl_in, sl_out);
        CHECK(fabs(cu_in - cu_out) < 0.01 * fabs(cu_in) + 1e-4, "%s: curvature continuous (%.6g, %.6g)",
              k ? "taper end" : "zone rim", cu_in, cu_out);
    }
    CHECK(kt_eye_departure_at(d, poly, d->taper * c, d->taper * s) == 0 && kt_eye_departure_at(d, poly, 7, 0) == 0,
          "0 from the taper's end on");
    kt_eye_departure none = {0};
    CHECK(kt_eye_departure_at(&none, poly, 0.1, 0.2) == 0, "order 0: no departure");
}

static void test_mesh(void)
{
    kt_eye e;
    kt_err err = {0};
    kt_mesh plain, meas;
    coarse_eye(&e);
    int rc = kt_eye_mesh(&e, 2, 1, &plain, &err);
    CHECK(rc == KT_OK, "the eye without departures: %s", err.msg);
    departures(&e, 1);
    rc = rc ? rc : kt_eye_mesh(&e, 2, 1, &meas, &err);
    CHECK(rc == KT_OK, "the eye with departures (curved tets valid): %s", err.msg);
    if (rc) return;
    CHECK(plain.nn == meas.nn && plain.ne == meas.ne, "the same mesh of revolution: %d / %d nodes", plain.nn, meas.nn);
    kt_eye_geom g;
    CHECK(kt_eye_geom_init(&e, &g, &err) == KT_OK, "geometry");
    double pa[NP * NP], pp[NP * NP];
    kt_eye_departure_poly(&e.dep_ant, pa);
    kt_eye_departure_poly(&e.dep_post, pp);
    int *an = NULL, *in = NULL, na = 0, ni = 0;
    kt_mesh_group_nodes(&meas, kt_mesh_find_group(&meas, 2, "anterior"), &an, &na, &err);
    kt_mesh_group_nodes(&meas, kt_mesh_find_group(&meas, 2, "inner"), &in, &ni, &err);
    double worst_a = 0, worst_p = 0, moved = 0, biggest = 0;
    int npost = 0;
    for (int k = 0; k < na; k++) {
        const double *p = meas.xyz + 3 * (size_t)an[k];
        double want = kt_eye_base_apex(&g, &e) - kt_eye_base_sag(&g, &e, 0, p[0], p[1]) +
                      kt_eye_departure_at(&e.dep_ant, pa, p[0], p[1]);
        worst_a = fmax(worst_a, fabs(p[2] - want));
        biggest = fmax(biggest, fabs(kt_eye_departure_at(&e.dep_ant, pa, p[0], p[1])));
    }
    for (int k = 0; k < ni; k++) {
        const double *p = meas.xyz + 3 * (size_t)in[k];
        double rho = hypot(p[0], p[1]);
        if (rho >= g.Pp[0] - 1e-9) continue; /* the inner limbus and sclera */
        double want = g.z_pv - (g.z_apex - kt_eye_base_apex(&g, &e)) - kt_eye_base_sag(&g, &e, 1, p[0], p[1]) +
                      kt_eye_departure_at(&e.dep_post, pp, p[0], p[1]);
        worst_p = fmax(worst_p, fabs(p[2] - want));
        npost++;
    }
    for (int i = 0; i < meas.nn; i++) {
        const double *p = meas.xyz + 3 * (size_t)i, *q = plain.xyz + 3 * (size_t)i;
        if (atan2(hypot(q[0], q[1]), q[2]) >= g.alphaL)
            moved = fmax(moved, fabs(p[2] - q[2]) + fabs(p[0] - q[0]) + fabs(p[1] - q[1]));
    }
    CHECK(biggest > 5e-3, "the anterior departure reaches %.4f mm on the nodes", biggest);
    CHECK(g.z_apex - kt_eye_base_apex(&g, &e) > 0.05, "the aspheric cornea's apex %.4f mm lower", g.z_apex - kt_eye_base_apex(&g, &e));
    CHECK(worst_a < 1e-12, "%d anterior nodes on the toric + departure: worst %.3g mm", na, worst_a);
    CHECK(npost > 100 && worst_p < 1e-9, "%d posterior nodes on the base posterior + departure: worst %.3g mm", npost,
          worst_p);
    CHECK(moved == 0, "the sclera unmoved (%.3g mm)", moved);
    free(an), free(in);
    kt_mesh_free(&plain), kt_mesh_free(&meas);
}

static void test_refused(void)
{
    kt_eye e;
    kt_eye_geom g;
    kt_err err = {0};
    coarse_eye(&e);
    departures(&e, 1);
    CHECK(kt_eye_geom_init(&e, &g, &err) == KT_OK && kt_eye_departure_check(&g, &e, &err) == KT_OK, "valid: %s", err.msg);
    e.dep_ant.taper = 0.5 * e.wtw + 0.1;
    memset(&err, 0, sizeof err);
    CHECK(kt_eye_departure_check(&g, &e, &err) == KT_EINPUT && strstr(err.msg, "eye.anterior_departure.taper"),
          "a taper past the corneal edge: %s", err.msg);
    coarse_eye(&e);
    departures(&e, 1);
    e.dep_post.taper = g.Pp[0] + 0.1;
    memset(&err, 0, sizeof err);
    CHECK(kt_eye_departure_check(&g, &e, &err) == KT_EINPUT && strstr(err.msg, "eye.posterior_departure.taper"),
          "a posterior taper past the limbus: %s", err.msg);
    coarse_eye(&e);
    departures(&e, 80); /* 0.32 mm of spherical aberration */
    memset(&err, 0, sizeof err);
    CHECK(kt_eye_departure_check(&g, &e, &err) == KT_EINPUT && strstr(err.msg, "half its thickness"),
          "a departure of half the thickness: %s", err.msg);
    CHECK(kt_eye_base_sag(&g, &e, 0, 0, 0) == 0 && fabs(kt_eye_base_sag(&g, &e, 1, 0, 0)) < 1e-15, "base sags 0 at the axis");
    coarse_eye(&e);
    departures(&e, 1);
    e.dep_ant.conic = 0.9; /* oblate: the surface ends before the corneal edge */
    memset(&err, 0, sizeof err);
    CHECK(kt_eye_departure_check(&g, &e, &err) == KT_EINPUT && strstr(err.msg, "asphericity"), "Q 0.6: %s", err.msg);
}

/* The whole file at path (NULL on failure); the caller frees it. */
static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *buf = calloc(1, 1 << 20);
    size_t n = buf ? fread(buf, 1, (1 << 20) - 1, f) : 0;
    fclose(f);
    if (buf) buf[n] = '\0';
    return buf;
}

static void test_roundtrip(void)
{
    kt_scene *a = calloc(1, sizeof *a), *b = calloc(1, sizeof *b);
    kt_err err = {0};
    char p1[64] = "/tmp/kt-depart-XXXXXX", p2[80], p3[80];
    if (!a || !b || !mkdtemp(p1)) return;
    snprintf(p2, sizeof p2, "%s/a.yaml", p1), snprintf(p3, sizeof p3, "%s/b.yaml", p1);
    int rc = kt_scene_load("plans/eye.yaml", a, &err);
    CHECK(rc == KT_OK, "plans/eye.yaml: %s", err.msg);
    if (rc) return;
    departures(&a->eye, 1);
    a->eye.dep_ant.conic = -0.2035331;
    for (int j = 0; j < 45; j++) a->eye.dep_ant.coef[j] += 1e-3 * sin(0.37 * j + 0.1) / 3; /* not round in um */
    for (int j = 0; j < 28; j++) a->eye.dep_post.coef[j] += 1e-4 * cos(1.3 * j) / 7;
    FILE *f = fopen(p2, "w");
    rc = f && kt_scene_write_eye(f, a, "test", &err) == KT_OK ? KT_OK : KT_ERUN;
    if (f) fclose(f);
    rc = rc ? rc : kt_scene_load(p2, b, &err);
    CHECK(rc == KT_OK, "the written scene reads back: %s", err.msg);
    if (rc == KT_OK) {
        const kt_eye_departure *x[2] = {&a->eye.dep_ant, &a->eye.dep_post}, *y[2] = {&b->eye.dep_ant, &b->eye.dep_post};
        int same = 1;
        for (int k = 0; k < 2; k++) {
            same &= x[k]->order == y[k]->order && x[k]->conic == y[k]->conic && x[k]->radius == y[k]->radius &&
                    x[k]->taper == y[k]->taper;
            for (int j = 0; j < kt_zern_nterms(x[k]->order); j++) same &= x[k]->coef[j] == y[k]->coef[j];
        }
        CHECK(same, "every departure field reads back to the same double");
        f = fopen(p3, "w");
        rc = f && kt_scene_write_eye(f, b, "test", &err) == KT_OK ? KT_OK : KT_ERUN;
        if (f) fclose(f);
        char *ta = slurp(p2), *tb = slurp(p3);
        CHECK(rc == KT_OK && ta && tb && strcmp(ta, tb) == 0 && strstr(ta, " um, "), "written again: the same bytes");
        free(ta), free(tb);
    }
    remove(p2), remove(p3), rmdir(p1);
    free(a), free(b);
}

int main(void)
{
    test_profile();
    test_mesh();
    test_refused();
    test_roundtrip();
    return kt_test_done("test_eye_depart");
}
