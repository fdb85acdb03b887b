/* test_surffit.c: the fit of a synthetic Pentacam export, written from a closed-form toric,
 * aspheric pair of surfaces and a thickness profile with missing cells: radii within 1 um,
 * axes within 0.5 deg, K within 0.01 D, Q and the thickness profile; the left eye's mirrored
 * export gives the mirrored axis (180 - axis), the same radii; the half-meridian powers of a
 * symmetric and an asymmetric (coma-like) cornea. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "kt_test.h"
#include "pentacam_synth.h"
#include "surffit.h"

static char dir[64];

static int fit_file(const char *name, const synth_surface *s, int mirror, double r_data, kt_surffit *out)
{
    char p[128];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    if (synth_write(p, s, NULL, ';', 1, mirror, r_data) != 0) return -1;
    kt_pentacam_map m;
    kt_err e = {0};
    int rc = kt_pentacam_read(p, KT_PENTACAM_ELEVATION, &m, &e);
    if (rc == KT_OK) rc = kt_surffit_elevation(&m, KT_SURFFIT_ZONE, out, &e);
    if (rc != KT_OK) fprintf(stderr, "%s: %s\n", name, e.msg);
    kt_pentacam_free(&m);
    return rc;
}

static double axis_diff(double a, double b)
{
    double d = fmod(fabs(a - b), 180);
    return fmin(d, 180 - d);
}

static void check_surface(const char *what, const kt_surffit *f, const synth_surface *s, double axis, double n)
{
    CHECK(fabs(f->r_steep - s->r_steep) <= 1e-3, "%s: steep radius %.6f vs %.6f mm", what, f->r_steep, s->r_steep);
    CHECK(fabs(f->r_flat - s->r_flat) <= 1e-3, "%s: flat radius %.6f vs %.6f mm", what, f->r_flat, s->r_flat);
    CHECK(axis_diff(f->axis, axis) <= 0.5, "%s: axis %.4f vs %.4f deg", what, f->axis, axis);
    CHECK(fabs(n / f->r_steep - n / s->r_steep) <= 0.01 && fabs(n / f->r_flat - n / s->r_flat) <= 0.01,
          "%s: K %.4f/%.4f vs %.4f/%.4f D", what, n / f->r_steep, n / f->r_flat, n / s->r_steep, n / s->r_flat);
    CHECK(fabs(f->conic - s->conic) <= 0.01, "%s: Q %.5f vs %.5f", what, f->conic, s->conic);
    CHECK(f->rms <= 1e-6 && f->max_resid <= 1e-5, "%s: residual rms %.3g, max %.3g mm", what, f->rms, f->max_resid);
    CHECK(f->npts > 3000, "%s: %d cells in the zone", what, f->npts);
}

static void test_pair(void)
{
    /* Anterior: K 44.70 / 43.27 D at 95 deg (with the rule, oblique by 5), Q -0.2, apex off
     * the grid centre; posterior: 0.35 D of against-the-rule-style toricity at 88 deg, Q -0.3,
     * measured out to 6.0 mm only. */
    synth_surface ant = {7.55, 7.80, 95, -0.2, 0.05, -0.03, 0};
    synth_surface post = {6.40, 6.68, 88, -0.3, 0.05, -0.03, 0};
    kt_surffit fa, fp, fa_os, fp_os;
    CHECK(fit_file("front_od.csv", &ant, 0, 6.5, &fa) == KT_OK, "anterior fit");
    CHECK(fit_file("back_od.csv", &post, 0, 6.0, &fp) == KT_OK, "posterior fit");
    check_surface("OD anterior", &fa, &ant, 95, 337.5);
    check_surface("OD posterior", &fp, &post, 88, 40);
    CHECK(fabs(fa.ax - 0.05) < 1e-4 && fabs(fa.ay + 0.03) < 1e-4, "apex found at (%.5f, %.5f)", fa.ax, fa.ay);
    /* The left eye, mirror image of the right: x -> -x in the instrument's frame, so the
     * steep meridian 95 deg becomes 85 deg and the apex moves to -x. */
    CHECK(fit_file("front_os.csv", &ant, 1, 6.5, &fa_os) == KT_OK, "OS anterior fit");
    CHECK(fit_file("back_os.csv", &post, 1, 6.0, &fp_os) == KT_OK, "OS posterior fit");
    check_surface("OS anterior", &fa_os, &ant, 85, 337.5);
    check_surface("OS posterior", &fp_os, &post, 92, 40);
    CHECK(fabs(fa_os.ax + 0.05) < 1e-4, "OS apex at x %.5f", fa_os.ax);
}

/* The half-meridian powers: equal on a biconic; a coma-like term kappa u r^2 (kappa < 0)
 * makes the half at -u the steeper. OS mirrors the axis. */
static void test_halves(void)
{
    synth_surface sym = {7.55, 7.80, 95, -0.2, 0.05, -0.03, 0}, coma = {7.55, 7.80, 95, -0.2, 0, 0, -4e-4};
    const char *names[3] = {"halves_sym.csv", "halves_coma.csv", "halves_coma_os.csv"};
    const synth_surface *ss[3] = {&sym, &coma, &coma};
    kt_halfmer h[3];
    for (int i = 0; i < 3; i++) {
        char p[128];
        snprintf(p, sizeof p, "%s/%s", dir, names[i]);
        CHECK(synth_write(p, ss[i], NULL, ';', 1, i == 2, 6.5) == 0, "write");
        kt_pentacam_map m;
        kt_err e = {0};
        kt_surffit f;
        int rc = kt_pentacam_read(p, KT_PENTACAM_ELEVATION, &m, &e);
        if (rc == KT_OK) rc = kt_surffit_elevation(&m, KT_SURFFIT_ZONE, &f, &e);
        if (rc == KT_OK) rc = kt_surffit_halves(&m, &f, &h[i], &e);
        CHECK(rc == KT_OK, "%s: %s", names[i], e.msg);
        kt_pentacam_free(&m);
    }
    double astig = 337.5 / 7.55 - 337.5 / 7.80;
    CHECK(fabs(h[0].k_a - h[0].k_b) < 0.02, "symmetric: halves %.4f and %.4f D", h[0].k_a, h[0].k_b);
    CHECK(fabs(h[0].k_a - h[0].k_flat - astig) < 0.1, "symmetric: half astigmatism %.3f vs %.3f D", h[0].k_a - h[0].k_flat,
          astig);
    /* The coma's r^3 part shows in the residual of the biconic fit (which absorbs some of it
     * as a shifted apex): the half at axis + 180 is the steeper, by at least 0.3 D (1012.5
     * kappa each way, 0.81 D, when nothing is absorbed); the left eye's mirror image the same. */
    CHECK(h[1].k_b - h[1].k_a > 0.3 && h[1].k_b - h[1].k_a < 0.81 + 0.02,
          "coma: the half at axis + 180 steeper by %.4f D (0.3 ... 0.81)", h[1].k_b - h[1].k_a);
    CHECK(axis_diff(h[2].axis, 85) < 0.5 && h[2].k_b - h[2].k_a > 0.3, "OS: axis %.2f, halves %.4f / %.4f", h[2].axis,
          h[2].k_a, h[2].k_b);
}

static void test_pachy(void)
{
    char p[128];
    snprintf(p, sizeof p, "%s/pachy.csv", dir);
    double t[3] = {0.545, 0.0035, 0.00012};
    CHECK(synth_write(p, NULL, t, ',', 0, 0, 6.8) == 0, "write");
    kt_pentacam_map m;
    kt_err e = {0};
    int rc = kt_pentacam_read(p, KT_PENTACAM_PACHYMETRY, &m, &e);
    kt_pachyfit pf;
    if (rc == KT_OK) rc = kt_surffit_pachymetry(&m, 0, 0, 6.25, &pf, &e);
    CHECK(rc == KT_OK, "pachymetry fit: %s", e.msg);
    if (rc == KT_OK) {
        CHECK_NEAR(pf.t0, 0.545, 1e-9, "central thickness");
        CHECK_NEAR(kt_pachyfit_at(&pf, 5.25), 0.545 + 0.0035 * 5.25 * 5.25 + 0.00012 * pow(5.25, 4), 1e-9,
                   "thickness at the 10.5 mm zone");
        CHECK(pf.rms < 1e-9, "profile residual %.3g mm", pf.rms);
    }
    kt_pentacam_free(&m);
    /* Too few cells: a zone inside one missing patch. */
    rc = kt_pentacam_read(p, KT_PENTACAM_PACHYMETRY, &m, &e);
    CHECK(rc == KT_OK, "read");
    if (rc == KT_OK) CHECK(kt_surffit_pachymetry(&m, 2, 1, 0.2, &pf, &e) == KT_ERUN, "a zone without data fails");
    kt_pentacam_free(&m);
}

/* An eye whose base anterior is the fitted toric (radii and axis), the rest the defaults of
 * keratome-scene(5). */
static void base_eye(kt_eye *eye, const kt_surffit *f)
{
    memset(eye, 0, sizeof *eye);
    eye->r_ant_steep = f->r_steep, eye->r_ant_flat = f->r_flat, eye->steep_axis = f->axis;
    eye->r_post = eye->r_post_steep = eye->r_post_flat = 6.7, eye->post_axis = 90;
    eye->t_central = 0.54, eye->t_peripheral = 0.67, eye->wtw = 11.7, eye->limbus_width = 1;
    eye->sclera_thickness = 0.53, eye->globe_radius = 12, eye->extent = 90, eye->optical_zone = 7;
    eye->h_optical = 0.25, eye->h_incision = 0.15, eye->h_cornea = 0.4, eye->h_sclera = 1.2;
    eye->dep_ant.conic = f->conic; /* lri-plan's base: aspheric with the fit's Q */
}

/* Read and fit one synthetic front map; its base eye. */
static int front(const char *name, const synth_surface *s, kt_pentacam_map *m, kt_surffit *f, kt_eye *eye)
{
    char p[128];
    kt_err e = {0};
    snprintf(p, sizeof p, "%s/%s", dir, name);
    if (synth_write(p, s, NULL, ';', 1, 0, 6.5) != 0) return -1;
    int rc = kt_pentacam_read(p, KT_PENTACAM_ELEVATION, m, &e);
    if (rc == KT_OK) rc = kt_surffit_elevation(m, KT_SURFFIT_ZONE, f, &e);
    if (rc != KT_OK) fprintf(stderr, "%s: %s\n", name, e.msg);
    if (rc == KT_OK) base_eye(eye, f);
    return rc;
}

/* Max |D1 - D0| over the zone (rho <= d0->radius) and over the taper, every 0.05 mm and 2 deg. */
static void dep_diff(const kt_eye_departure *d0, const kt_eye_departure *d1, double *zone, double *taper)
{
    double p0[KT_ZERN_NP * KT_ZERN_NP], p1[KT_ZERN_NP * KT_ZERN_NP];
    kt_eye_departure_poly(d0, p0);
    kt_eye_departure_poly(d1, p1);
    *zone = *taper = 0;
    for (double r = 0; r < d0->taper; r += 0.05)
        for (int k = 0; k < 180; k++) {
            double x = r * cos(k * KT_PI / 90), y = r * sin(k * KT_PI / 90);
            double v = fabs(kt_eye_departure_at(d1, p1, x, y) - kt_eye_departure_at(d0, p0, x, y));
            if (r <= d0->radius) *zone = fmax(*zone, v);
            else *taper = fmax(*taper, v);
        }
}

/* The order against measurement noise: the map with 1 um RMS of white noise added (a fixed
 * pseudo-random sequence), each order's departure against the noise-free map's at order 10.
 * The extension beyond the zone uses the expansion's slope and curvature at the rim, which
 * noise bends more the higher the order: printed, and order KT_SURFFIT_DEP_ORDER within 1 um in
 * the zone and 3 um in the taper, order 10 at least twice as far off in the taper. */
static void noisy_orders(const kt_pentacam_map *m, const kt_eye *eye)
{
    kt_pentacam_map mn = *m;
    kt_eye_departure d0, d;
    kt_err e = {0};
    double rms, mx, zone, taper, t_dep = NAN, t_10 = NAN, z_dep = NAN;
    int np;
    unsigned s = 12345;
    mn.v = malloc(sizeof(double) * m->n * m->n);
    if (!mn.v) return;
    for (int i = 0; i < m->n * m->n; i++) {
        double u[2];
        for (int k = 0; k < 2; k++) s = s * 1103515245u + 12345u, u[k] = ((s >> 8) + 0.5) / 16777216.0;
        mn.v[i] = m->v[i] + 1e-3 * sqrt(-2 * log(u[0])) * cos(2 * KT_PI * u[1]);
    }
    CHECK(kt_surffit_departure(m, eye, 0, 10, 4, 5.85, &d0, &rms, &mx, &np, &e) == KT_OK, "noise-free: %s", e.msg);
    printf("with 1 um RMS of noise: order, residual rms / max um, departure off by (max, um) in the zone, in the taper\n");
    for (int order = 4; order <= 10; order++) {
        CHECK(kt_surffit_departure(&mn, eye, 0, order, 4, 5.85, &d, &rms, &mx, &np, &e) == KT_OK, "noisy: %s", e.msg);
        dep_diff(&d0, &d, &zone, &taper);
        printf("%5d  %6.3f %6.3f  %6.3f  %6.3f\n", order, 1000 * rms, 1000 * mx, 1000 * zone, 1000 * taper);
        if (order == KT_SURFFIT_DEP_ORDER) t_dep = taper, z_dep = zone;
        if (order == 10) t_10 = taper;
    }
    CHECK(z_dep < 1e-3 && t_dep < 3e-3 && t_10 > 2 * t_dep, "order %d off by %.3f um in the zone, %.3f um in the taper; "
          "order 10 %.3f um", KT_SURFFIT_DEP_ORDER, 1000 * z_dep, 1000 * t_dep, 1000 * t_10);
    free(mn.v);
}

/* The measured surface's departure from the mesh's base (kt_surffit_departure): none for the
 * mesh's own toric (Q = 0, apex on the axis); a coma-like term kappa u r^2 gives the analytic
 * coefficients (u r^2 = a^3 rho^3 cos(t - axis), rho^3 cos t = Z_8 / (3 sqrt 8) + Z_2 / 3, the sine
 * part likewise with Z_7 and Z_1; the tilts Z_1, Z_2 left out); on the aspheric, decentred,
 * asymmetric front of asym-od.yaml, on lri-plan's base (aspheric with the fit's Q), the residual
 * falls with the order (the table printed is keratome-patient(5)'s, THE FIT) and is below 0.1 um
 * at lri-plan's order; with noise, noisy_orders; kt_surffit_measured_eye fills the eye, shrinks
 * the zone to what a map measures and refuses a map that measures too little. */
static void test_departure(void)
{
    synth_surface toric = {7.55, 7.80, 95, 0, 0, 0, 0}, coma = {7.55, 7.80, 95, 0, 0, 0, -4e-4};
    synth_surface asym = {337.5 / 44.75, 337.5 / 43.00, 92, -0.2, 0.04, -0.02, -4e-4};
    kt_pentacam_map m;
    kt_surffit f;
    kt_eye eye;
    kt_eye_departure d;
    kt_err e = {0};
    double rms, mx;
    int np;
    if (front("dep_toric.csv", &toric, &m, &f, &eye) == KT_OK) {
        eye.r_ant_steep = 7.55, eye.r_ant_flat = 7.80, eye.steep_axis = 95, eye.dep_ant.conic = 0; /* the exact toric */
        CHECK(kt_surffit_departure(&m, &eye, 0, 8, 4, 5.85, &d, &rms, &mx, &np, &e) == KT_OK, "toric: %s", e.msg);
        double big = 0;
        for (int j = 0; j < 45; j++) big = fmax(big, fabs(d.coef[j]));
        CHECK(big < 1e-9 && mx < 1e-9, "the mesh's own toric: no departure (largest coefficient %.3g mm, residual %.3g)", big,
              mx);
        CHECK(np > 4000 && d.order == 8 && d.radius == KT_SURFFIT_ZONE / 2 && d.taper == 5.85, "%d cells, order %d", np,
              d.order);
        kt_pentacam_free(&m);
    }
    if (front("dep_coma.csv", &coma, &m, &f, &eye) == KT_OK) {
        eye.r_ant_steep = 7.55, eye.r_ant_flat = 7.80, eye.steep_axis = 95, eye.dep_ant.conic = 0;
        CHECK(kt_surffit_departure(&m, &eye, 0, 8, 4, 5.85, &d, &rms, &mx, &np, &e) == KT_OK, "coma: %s", e.msg);
        double k3 = 4e-4 * 64, t = 95 * KT_PI / 180, want[45] = {0};
        want[8] = k3 * cos(t) / (3 * sqrt(8)), want[7] = k3 * sin(t) / (3 * sqrt(8));
        double worst = 0;
        for (int j = 0; j < 45; j++) worst = fmax(worst, fabs(d.coef[j] - want[j]));
        CHECK(worst < 1e-9 && rms < 1e-9, "coma: the analytic coefficients (Z_8 %.6f mm, Z_7 %.6f mm; the tilt left out), "
              "worst %.3g mm", d.coef[8], d.coef[7], worst);
        kt_pentacam_free(&m);
    }
    if (front("dep_asym.csv", &asym, &m, &f, &eye) == KT_OK) {
        double prev = INFINITY;
        int mono = 1;
        printf("departure of the asymmetric front (asym-od) from its fitted toric, %g mm zone:\n"
               "order  terms  rms um   max um  |D| max in the zone, in the taper (um)\n", KT_SURFFIT_ZONE);
        for (int order = 4; order <= 10; order++) {
            CHECK(kt_surffit_departure(&m, &eye, 0, order, 4, 5.85, &d, &rms, &mx, &np, &e) == KT_OK, "asym: %s", e.msg);
            double poly[KT_ZERN_NP * KT_ZERN_NP], din = 0, dout = 0;
            kt_eye_departure_poly(&d, poly);
            for (double r = 0; r < 5.85; r += 0.05)
                for (int k = 0; k < 180; k++) {
                    double v = fabs(kt_eye_departure_at(&d, poly, r * cos(k * KT_PI / 90), r * sin(k * KT_PI / 90)));
                    if (r <= d.radius) din = fmax(din, v);
                    else dout = fmax(dout, v);
                }
            printf("%5d  %5d  %7.4f  %7.4f  %6.2f  %6.2f  (%d cells)\n", order, kt_zern_nterms(order), 1000 * rms, 1000 * mx,
                   1000 * din, 1000 * dout, np);
            mono &= rms <= prev;
            prev = rms;
            if (order == KT_SURFFIT_DEP_ORDER)
                CHECK(rms < 1e-4 && mx < 1e-3, "order %d: residual rms %.4f um, max %.4f um", order, 1000 * rms, 1000 * mx);
        }
        CHECK(mono, "the residual falls with the order");
        noisy_orders(&m, &eye);
        kt_patient p;
        memset(&p, 0, sizeof p);
        snprintf(p.pentacam_front, sizeof p.pentacam_front, "%s/dep_asym.csv", dir);
        kt_surffit fa = f;
        CHECK(kt_surffit_measured_eye(&p, &eye, &fa, NULL, &e) == KT_OK, "measured eye: %s", e.msg);
        CHECK(eye.dep_ant.order == KT_SURFFIT_DEP_ORDER && eye.dep_ant.taper == 0.5 * eye.wtw && eye.dep_post.order == 0 &&
              fa.dep_order == KT_SURFFIT_DEP_ORDER && fa.dep_rms > 0 && fa.dep_radius == 4,
              "the eye carries the front's departure (taper %g mm), none behind", eye.dep_ant.taper);
        /* A map measured out to 3.1 mm only: the zone shrinks to what it covers; to 1.5 mm: refused. */
        snprintf(p.pentacam_front, sizeof p.pentacam_front, "%s/dep_small.csv", dir);
        CHECK(synth_write(p.pentacam_front, &asym, NULL, ';', 1, 0, 3.1) == 0, "write");
        CHECK(kt_surffit_measured_eye(&p, &eye, &fa, NULL, &e) == KT_OK && fa.dep_radius <= 3.1 && fa.dep_radius >= 2.75,
              "a map measured to 3.1 mm: zone radius %g mm (%s)", fa.dep_radius, e.msg);
        CHECK(synth_write(p.pentacam_front, &asym, NULL, ';', 1, 0, 1.5) == 0, "write");
        kt_err e2 = {0};
        CHECK(kt_surffit_measured_eye(&p, &eye, &fa, NULL, &e2) == KT_EINPUT && strstr(e2.msg, "dep_small.csv"),
              "a map measured to 1.5 mm: %s", e2.msg);
        kt_pentacam_free(&m);
    }
}

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/kt-surffit-XXXXXX");
    if (!mkdtemp(dir)) return 1;
    test_pair();
    test_halves();
    test_pachy();
    test_departure();
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0) return 1;
    return kt_test_done("test_surffit");
}
