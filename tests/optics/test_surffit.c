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

int main(void)
{
    snprintf(dir, sizeof dir, "/tmp/kt-surffit-XXXXXX");
    if (!mkdtemp(dir)) return 1;
    test_pair();
    test_halves();
    test_pachy();
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0) return 1;
    return kt_test_done("test_surffit");
}
