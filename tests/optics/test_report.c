/* test_report.c: the pieces of curvature's report against closed forms: base64 (the RFC 4648
 * test vectors), posterior and total corneal power of spherical and biconic shells (the
 * thick-lens formula evaluated here by hand), the meridional section of one tet, the wound gape
 * of split nodes, and the section's exaggeration factor. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "b64.h"
#include "curv_report.h"
#include "curv_total.h"
#include "kt_test.h"
#include "svg.h"

#define DEG KT_CURV_DEG

static void test_b64(void)
{
    static const char *in[] = {"", "f", "fo", "foo", "foob", "fooba", "foobar"},
                      *out[] = {"", "Zg==", "Zm8=", "Zm9v", "Zm9vYg==", "Zm9vYmE=", "Zm9vYmFy"};
    char buf[32];
    for (int i = 0; i < 7; i++) {
        size_t n = kt_b64_encode((const unsigned char *)in[i], strlen(in[i]), buf);
        CHECK(strcmp(buf, out[i]) == 0 && n == strlen(out[i]) && n == kt_b64_len(strlen(in[i])),
              "base64(\"%s\") = \"%s\", expected \"%s\"", in[i], buf, out[i]);
    }
    /* the streaming writer gives the same text as the buffer encoder, across its chunk size */
    size_t n = 5000;
    unsigned char *bytes = malloc(n);
    char *want = malloc(kt_b64_len(n) + 1), *got = NULL;
    size_t glen = 0;
    for (size_t i = 0; i < n; i++) bytes[i] = (unsigned char)(i * 37 + 11);
    kt_b64_encode(bytes, n, want);
    FILE *f = open_memstream(&got, &glen);
    CHECK(kt_b64_write(f, bytes, n) == 0, "kt_b64_write failed");
    fclose(f);
    CHECK(glen == strlen(want) && memcmp(got, want, glen) == 0, "streamed base64 differs (%zu vs %zu chars)", glen,
          strlen(want));
    free(bytes), free(want), free(got);
}

/* Points on a biconic (conic 0) with principal radii rs at meridian axis and rf at axis + 90,
 * apex (0, 0, z0): the sections along the principal meridians are circles. */
static double *biconic(double rs, double rf, double axis, double z0, double rmax, int *n)
{
    int m = 60, k = 0;
    double *xyz = malloc(sizeof(double) * 3 * (2 * m + 1) * (2 * m + 1));
    double c = cos(axis * DEG), s = sin(axis * DEG);
    for (int j = -m; j <= m; j++)
        for (int i = -m; i <= m; i++) {
            double x = rmax * i / m, y = rmax * j / m;
            if (x * x + y * y > rmax * rmax) continue;
            double u = x * c + y * s, v = -x * s + y * c, q1 = u * u / rs + v * v / rf;
            xyz[3 * k] = x, xyz[3 * k + 1] = y;
            xyz[3 * k + 2] = z0 - q1 / (1 + sqrt(1 - u * u / (rs * rs) - v * v / (rf * rf)));
            k++;
        }
    *n = k;
    return xyz;
}

static void fit_of(const double *xyz, int n, kt_fit *f)
{
    kt_err e = {0};
    CHECK(kt_curv_fit(xyz, n, KT_FIT_TORIC, 6, 3, 0, 0, f, NULL, 0, &e) == KT_OK, "fit: %s", e.msg);
}

/* Gullstrand's equivalent power of two refracting surfaces of radii ra, rp (mm) d mm apart. */
static double thick_lens(double ra, double rp, double d)
{
    double pa = (1.376 - 1.000) * 1000 / ra, pp = (1.336 - 1.376) * 1000 / rp;
    return pa + pp - d / 1000 / 1.376 * pa * pp;
}

static void shell(double ras, double raf, double rps, double rpf, double axis, double d, const char *what)
{
    int na, np;
    double *a = biconic(ras, raf, axis, 0, 2.4, &na), *p = biconic(rps, rpf, axis, -d, 2.4, &np);
    kt_fit fa, fp;
    fit_of(a, na, &fa);
    fit_of(p, np, &fp);
    kt_cornea_n n;
    kt_cornea_n_default(&n);
    kt_total t;
    kt_curv_total(&fa, &fp, &n, &t);
    char w[128];
    snprintf(w, sizeof w, "%s: thickness", what);
    CHECK_NEAR(t.thickness, d, 1e-6, w);
    snprintf(w, sizeof w, "%s: posterior K steep", what);
    CHECK_NEAR(t.post_steep, -40 / rps, 2e-4, w);
    snprintf(w, sizeof w, "%s: posterior K flat", what);
    CHECK_NEAR(t.post_flat, -40 / rpf, 2e-4, w);
    snprintf(w, sizeof w, "%s: total K steep", what);
    CHECK_NEAR(t.tot_steep, thick_lens(ras, rps, d), 2e-4, w);
    snprintf(w, sizeof w, "%s: total K flat", what);
    CHECK_NEAR(t.tot_flat, thick_lens(raf, rpf, d), 2e-4, w);
    snprintf(w, sizeof w, "%s: total cylinder", what);
    CHECK_NEAR(t.tot_cyl, thick_lens(ras, rps, d) - thick_lens(raf, rpf, d), 2e-4, w);
    if (ras != raf) {
        double da = fmod(t.tot_axis - axis + 270, 180) - 90;
        CHECK(fabs(da) < 0.05, "%s: total axis %.3f, expected %.1f", what, t.tot_axis, axis);
        da = fmod(t.post_axis - axis + 270, 180) - 90;
        CHECK(fabs(da) < 0.05, "%s: posterior axis %.3f, expected %.1f", what, t.post_axis, axis);
    }
    printf("%s: total %.4f / %.4f D (closed form %.4f / %.4f), posterior %.4f / %.4f D\n", what, t.tot_steep,
           t.tot_flat, thick_lens(ras, rps, d), thick_lens(raf, rpf, d), t.post_steep, t.post_flat);
    free(a), free(p);
}

static void test_total(void)
{
    /* Gullstrand's exact eye cornea: 7.7 / 6.8 mm, 0.5 mm: 43.05 D total */
    shell(7.7, 7.7, 6.8, 6.8, 0, 0.5, "sphere shell 7.7/6.8");
    CHECK_NEAR(thick_lens(7.7, 6.8, 0.5), 43.053, 2e-5, "Gullstrand's corneal power 43.05 D");
    shell(7.6, 7.9, 6.4, 6.6, 90, 0.55, "biconic shell, with the rule");
    shell(7.7, 7.85, 6.5, 6.75, 30, 0.52, "biconic shell at 30 deg");
}

/* One tet straddling the plane x = 0 (meridian 90: r = y), plus two points split from one
 * input node (the wound's faces) near the plane. */
static void test_section(void)
{
    double xyz[] = {-1, 5, 0, 1, 5, 0, 1, 6, 0, 1, 5, 1, 0.2, 5.2, 0.1, 0.2, 5.2, 0.1};
    double disp[18], org[] = {1, 2, 3, 4, 5, 5};
    for (int i = 0; i < 6; i++) disp[3 * i] = 0, disp[3 * i + 1] = 0.01 * xyz[3 * i + 1], disp[3 * i + 2] = 0.02;
    disp[15] += 0.003, disp[16] += 0.004; /* the second face of the split node: 5 um away */
    int type[] = {10}, ptr[] = {0, 4}, conn[] = {0, 1, 2, 3};
    kt_vtk_field fl[2];
    memset(fl, 0, sizeof fl);
    strcpy(fl[0].name, "displacement"), fl[0].ncomp = 3, fl[0].v = disp;
    strcpy(fl[1].name, "origin"), fl[1].ncomp = 1, fl[1].is_int = 1, fl[1].v = org;
    kt_vtk v = {0, 6, xyz, 1, type, ptr, conn, 2, fl};
    kt_section s;
    kt_err e = {0};
    CHECK(kt_curv_section(&v, NULL, 5, 90, 5.25, 1.2, &s, &e) == KT_OK, "section: %s", e.msg);
    CHECK(s.n == 1 && s.nv[0] == 3, "one triangle expected, got %d polygons", s.n);
    /* edges A-B, A-C, A-D cross x = 0 at (r, z) = (5, 0), (5.5, 0), (5, 0.5) */
    double want[3][2] = {{5, 0}, {5.5, 0}, {5, 0.5}};
    for (int w = 0; s.n == 1 && w < 3; w++) {
        int found = 0;
        for (int k = 0; k < 3; k++) {
            const double *b = s.base + 2 * k, *d = s.def + 2 * k;
            if (hypot(b[0] - want[w][0], b[1] - want[w][1]) < 1e-12) {
                found = 1; /* the displacement is linear, so interpolation is exact */
                CHECK(fabs(d[0] - 0.01 * b[0]) < 1e-12 && fabs(d[1] - 0.02) < 1e-12, "displacement at (%g, %g)", b[0], b[1]);
            }
        }
        CHECK(found, "corner (%g, %g) missing", want[w][0], want[w][1]);
    }
    CHECK_NEAR(s.gape, 0.005, 1e-12, "gape of the split node");
    CHECK_NEAR(s.max_disp, hypot(0.055, 0.02), 1e-12, "largest in-plane displacement");
    kt_section_free(&s);
    /* outside the window: nothing */
    CHECK(kt_curv_section(&v, NULL, 5, 90, 8, 1, &s, &e) == KT_OK && s.n == 0, "window at 8 mm: %d polygons", s.n);
    kt_section_free(&s);
}

static void test_scale_factors(void)
{
    double md[] = {0.012, 0.0004, 0.03, 0.5};
    for (int i = 0; i < 4; i++) {
        double f = kt_report_exaggeration(md[i], 0.1), m = f / pow(10, floor(log10(f) + 1e-9));
        CHECK((f * md[i] <= 0.1 * (1 + 1e-12) && f * md[i] > 0.1 / 2.5 - 1e-12) || (f == 1 && md[i] >= 0.1),
              "factor %g for %g mm", f, md[i]);
        CHECK(fabs(m - 1) < 1e-9 || fabs(m - 2) < 1e-9 || fabs(m - 5) < 1e-9, "factor %g is not 1, 2 or 5 x 10^k", f);
    }
    CHECK(kt_report_exaggeration(0, 0.1) == 1, "nothing moves: factor 1");
    double lo = 0.13, hi = 1.37;
    kt_svg_nice_range(&lo, &hi, 5);
    CHECK(fabs(lo - 0) < 1e-12 && fabs(hi - 1.4) < 1e-12, "nice range [%g, %g], expected [0, 1.4]", lo, hi);
}

/* The headline says over- and under-correction and an axis flip (the demo's 1.50 D @ 90 ->
 * 0.46 D @ 0, correction index 1.31, read as a success from the cards before). */
static void test_verdict(void)
{
    char b[512];
    kt_alpins va;
    kt_astig tia = {1.5, 0};
    kt_curv_alpins((kt_astig){1.50, 90}, (kt_astig){0.46, 0.4}, &tia, &va);
    kt_report_verdict((kt_astig){1.50, 90}, (kt_astig){0.46, 0.4}, &va, 1, b, sizeof b);
    CHECK(strncmp(b, "Over-correction", 15) == 0 && strstr(b, "axis flips") && strstr(b, "0.46 D @ 0"), "%s", b);
    kt_curv_alpins((kt_astig){1.50, 90}, (kt_astig){0.90, 90}, &tia, &va);
    kt_report_verdict((kt_astig){1.50, 90}, (kt_astig){0.90, 90}, &va, 1, b, sizeof b);
    CHECK(strncmp(b, "Under-correction", 16) == 0 && !strstr(b, "flips"), "%s", b);
    kt_curv_alpins((kt_astig){1.50, 90}, (kt_astig){0.02, 0}, &tia, &va);
    kt_report_verdict((kt_astig){1.50, 90}, (kt_astig){0.02, 0}, &va, 1, b, sizeof b);
    CHECK(strncmp(b, "On target", 9) == 0 && !strstr(b, "flips"), "%s (0.02 D left: no axis to flip)", b);
    kt_curv_alpins((kt_astig){1.50, 90}, (kt_astig){0.46, 0}, NULL, &va);
    kt_report_verdict((kt_astig){1.50, 90}, (kt_astig){0.46, 0}, &va, 0, b, sizeof b);
    CHECK(strncmp(b, "No target", 9) == 0 && strstr(b, "flips"), "%s", b);
}

int main(void)
{
    test_verdict();
    test_b64();
    test_total();
    test_section();
    test_scale_factors();
    return kt_test_done("test_report");
}
