/* test_axialmap.c: axial power maps: the PNG decodes (libpng's reader) with the layout's size, the
 * colours of a 43 D sphere and of a toric cornea's bow-tie are the scale's colours for those
 * powers, the legend shows every bin, and bad colour scales are refused. */
#define _XOPEN_SOURCE 700
#include <math.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "curv.h"
#include "kt_test.h"
#include "axialmap.h"

#define SCALE_TSV KT_SHARE_DIR "/colour/axial.tsv" /* the build's share/ folder */
#define DEG KT_CURV_DEG

/* The scale read here with its own small parser (not kt_topo_scale_load): lo hi r g b. */
typedef struct ref_scale {
    int n;
    double lo[64], hi[64];
    int rgb[64][3];
} ref_scale;

static int ref_load(ref_scale *s)
{
    FILE *f = fopen(SCALE_TSV, "r");
    if (!f) return -1;
    char line[512];
    s->n = 0;
    while (fgets(line, sizeof line, f) && s->n < 64) {
        double lo, hi;
        int r, g, b;
        if (sscanf(line, "%lf %lf %d %d %d", &lo, &hi, &r, &g, &b) == 5) {
            s->lo[s->n] = lo, s->hi[s->n] = hi;
            s->rgb[s->n][0] = r, s->rgb[s->n][1] = g, s->rgb[s->n][2] = b;
            s->n++;
        }
    }
    fclose(f);
    return s->n > 0 ? 0 : -1;
}

static const int *ref_colour(const ref_scale *s, double p)
{
    for (int i = 0; i < s->n; i++)
        if (p >= s->lo[i] && p < s->hi[i]) return s->rgb[i];
    return p < s->lo[0] ? s->rgb[0] : s->rgb[s->n - 1];
}

/* Decode with libpng's simplified reader into RGB. */
static unsigned char *decode(const char *path, int *w, int *h)
{
    png_image im;
    memset(&im, 0, sizeof im);
    im.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&im, path)) return NULL;
    im.format = PNG_FORMAT_RGB;
    unsigned char *buf = malloc(PNG_IMAGE_SIZE(im));
    if (!buf || !png_image_finish_read(&im, NULL, buf, 0, NULL)) {
        free(buf);
        png_image_free(&im);
        return NULL;
    }
    *w = (int)im.width, *h = (int)im.height;
    return buf;
}

static int same_rgb(const unsigned char *px, const int *rgb)
{
    return px[0] == rgb[0] && px[1] == rgb[1] && px[2] == rgb[2];
}

/* A dense cloud on a torus of radii rs (steep, at `axis`) and rf, apex at the origin. */
static double torus_z(double rs, double rf, double axis, double x, double y)
{
    double c = cos(axis * DEG), s = sin(axis * DEG), xs = x * c + y * s, yf = -x * s + y * c;
    double rho = rf - rs + sqrt(rs * rs - xs * xs);
    return -rf + sqrt(rho * rho - yf * yf);
}

static int fit_torus(double rs, double rf, double axis, kt_fit *f)
{
    int n = 0;
    double *xyz = malloc(sizeof(double) * 3 * 81 * 81);
    for (int i = 0; i < 81; i++)
        for (int j = 0; j < 81; j++) {
            double x = -4.5 + 0.1125 * i, y = -4.5 + 0.1125 * j;
            xyz[3 * n] = x, xyz[3 * n + 1] = y, xyz[3 * n + 2] = torus_z(rs, rf, axis, x, y);
            n++;
        }
    kt_err e = {0};
    int rc = kt_curv_fit(xyz, n, KT_FIT_ZERNIKE, 8, 8.0, 0, 0, f, NULL, 0, &e);
    free(xyz);
    return rc;
}

static double power_cb(const void *ctx, double x, double y) { return kt_fit_axial_power(ctx, x, y); }

/* Render, write, decode; the pixel at (r mm, meridian t) from the centre of the map. */
typedef struct shot {
    unsigned char *rgb;
    int w, h;
    kt_topo_layout L;
    double px_per_mm;
} shot;

static int take(const kt_topo_scale *sc, const kt_fit *f, const char *path, shot *s)
{
    kt_err e = {0};
    kt_topo_map m;
    memset(&m, 0, sizeof m);
    m.cx = f->ax, m.cy = f->ay, m.radius = 4.0, m.zone = 3.0;
    snprintf(m.title[0], sizeof m.title[0], "AXIAL POWER (D)  TEST");
    snprintf(m.title[1], sizeof m.title[1], "K 43.00@90\xC2\xB0");
    kt_topo_image img;
    if (kt_topo_render(sc, &m, power_cb, f, &img, &e) || kt_topo_write_png(path, &img, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return -1;
    }
    kt_topo_image_free(&img);
    kt_topo_layout_of(sc, &s->L);
    s->px_per_mm = s->L.rad / 4.0;
    s->rgb = decode(path, &s->w, &s->h);
    return s->rgb ? 0 : -1;
}

static const unsigned char *at_polar(const shot *s, double r, double t)
{
    int x = (int)floor(s->L.cx + r * s->px_per_mm * cos(t * DEG));
    int y = (int)floor(s->L.cy - r * s->px_per_mm * sin(t * DEG));
    return s->rgb + 3 * ((size_t)y * s->w + x);
}

/* The legend's labels: the difference scale shows 0 and symmetric round values at bin centres
 * (it printed the edges -3.1 ... -0.1 and no 0 before); the absolute scale its edges. The
 * relative scale covers the range in aligned bins of a listed width, at most 24. */
static void test_legend_and_auto(void)
{
    kt_topo_scale d, a, r;
    kt_err e = {0};
    double val[KT_TOPO_MAXBIN + 1], pos[KT_TOPO_MAXBIN + 1];
    char b[32];
    CHECK(kt_topo_scale_load(KT_SHARE_DIR "/colour/difference.tsv", &d, &e) == KT_OK, "%s", e.msg);
    int n = kt_topo_legend_labels(&d, val, pos, KT_TOPO_MAXBIN + 1), zero = 0;
    CHECK(n == 13, "difference legend: %d labels, expected 13 (-3.0 to +3.0 by 0.5)", n);
    for (int k = 0; k < n; k++) {
        CHECK(fabs(val[k] - (-3.0 + 0.5 * k)) < 1e-12, "label %d: %g, expected %g", k, val[k], -3.0 + 0.5 * k);
        CHECK(fabs(val[k] + val[n - 1 - k]) < 1e-12, "labels %d and %d not symmetric", k, n - 1 - k);
        kt_topo_legend_text(val[k], 1, b, sizeof b);
        zero += strcmp(b, "0") == 0;
    }
    CHECK(zero == 1, "the difference legend labels 0 once (%d)", zero);
    kt_topo_legend_text(0.5, 1, b, sizeof b);
    CHECK(strcmp(b, "+0.5") == 0, "0.5 prints %s", b);
    kt_topo_legend_text(-0.25, 1, b, sizeof b);
    CHECK(strcmp(b, "-0.25") == 0, "-0.25 prints %s", b);
    CHECK(kt_topo_scale_load(SCALE_TSV, &a, &e) == KT_OK, "%s", e.msg);
    n = kt_topo_legend_labels(&a, val, pos, KT_TOPO_MAXBIN + 1);
    CHECK(n > 2 && val[0] == a.lo[0] && pos[0] == 0 && val[1] == a.lo[2], "absolute legend: edges every other bin");
    CHECK(kt_topo_scale_auto(&a, 42.31, 44.02, &r, &e) == KT_OK, "%s", e.msg);
    CHECK(r.n == 8 && r.lo[0] == 42.25 && r.hi[r.n - 1] == 44.25 && r.hi[0] - r.lo[0] == 0.25,
          "auto 42.31-44.02: %d bins %g-%g", r.n, r.lo[0], r.hi[r.n - 1]);
    CHECK(memcmp(r.rgb[0], a.rgb[0], 3) == 0 && memcmp(r.rgb[r.n - 1], a.rgb[a.n - 1], 3) == 0, "auto colours span the ramp");
    CHECK(kt_topo_scale_auto(&a, 30, 50, &r, &e) == KT_OK && r.n <= 24 && r.hi[0] - r.lo[0] == 1 && r.lo[0] <= 30 &&
          r.hi[r.n - 1] >= 50, "auto 30-50: %d bins of %g", r.n, r.hi[0] - r.lo[0]);
    CHECK(kt_topo_scale_auto(&a, NAN, 50, &r, &e) == KT_ERUN, "auto on NaN refused");
}

int main(void)
{
    test_legend_and_auto();
    ref_scale ref = {0};
    kt_topo_scale sc;
    kt_err e = {0};
    CHECK(ref_load(&ref) == 0, "cannot read %s", SCALE_TSV);
    CHECK(kt_topo_scale_load(SCALE_TSV, &sc, &e) == KT_OK, "%s", e.msg);
    if (ref.n == 0 || sc.n == 0) return kt_test_done("test_axialmap"); /* nothing more to check */
    CHECK(sc.n == ref.n && sc.n == 25, "scale has %d bins", sc.n);
    CHECK(sc.lo[0] == 30.0 && sc.hi[sc.n - 1] == 67.5, "scale range %g..%g", sc.lo[0], sc.hi[sc.n - 1]);
    for (int i = 0; i < sc.n; i++) CHECK(fabs(sc.hi[i] - sc.lo[i] - 1.5) < 1e-12, "bin %d is not 1.5 D", i);
    CHECK(kt_topo_scale_bin(&sc, 10) == 0 && kt_topo_scale_bin(&sc, 99) == sc.n - 1, "clamping");
    CHECK(kt_topo_scale_bin(&sc, NAN) == -1, "NaN bin");

    char dir[] = "/tmp/kt_topo_XXXXXX", path[256];
    CHECK(mkdtemp(dir) != NULL, "mkdtemp");

    /* A sphere of 43 D: the centre and the whole disk take the 43 D colour. */
    kt_fit f;
    CHECK(fit_torus(337.5 / 43.0, 337.5 / 43.0, 0, &f) == KT_OK, "sphere fit");
    snprintf(path, sizeof path, "%s/sphere.png", dir);
    shot s;
    CHECK(take(&sc, &f, path, &s) == 0, "render/decode %s", path);
    if (s.rgb) {
        CHECK(s.w == s.L.w && s.h == s.L.h && s.w == 720 && s.h == 580, "size %dx%d", s.w, s.h);
        const int *c43 = ref_colour(&ref, 43.0);
        CHECK(same_rgb(at_polar(&s, 0.3, 45), c43), "centre is not the 43 D colour");
        int off = 0;
        for (int t = 0; t < 360; t += 15)
            for (double r = 0.5; r < 3.9; r += 0.4) {
                if (fabs(r - 1.5) < 0.1) continue; /* the dashed zone circle */
                off += !same_rgb(at_polar(&s, r, t + 7), c43);
            }
        CHECK(off == 0, "%d disk samples off the 43 D colour", off);
        /* Legend: each bin's swatch centre has that bin's colour (highest bin on top). */
        int bad = 0;
        for (int i = 0; i < ref.n; i++) {
            int y = s.L.leg_y + (ref.n - 1 - i) * s.L.leg_h + s.L.leg_h / 2, x = s.L.leg_x + s.L.leg_w / 2;
            bad += !same_rgb(s.rgb + 3 * ((size_t)y * s.w + x), ref.rgb[i]);
        }
        CHECK(bad == 0, "%d legend swatches off their colour", bad);
        /* Outside the disk: white background; rim tick at 0 deg and title text: black pixels. */
        static const int white[3] = {255, 255, 255}, black[3] = {0, 0, 0};
        CHECK(same_rgb(s.rgb + 3 * ((size_t)(s.L.cy + s.L.rad + 2) * s.w + s.L.cx - s.L.rad - 2), white),
              "corner not white");
        int tick = 0, title = 0;
        for (int d = 1; d <= 8; d++) tick += same_rgb(s.rgb + 3 * ((size_t)s.L.cy * s.w + s.L.cx + s.L.rad + d), black);
        for (int y = 0; y < 50; y++)
            for (int x = 0; x < 300; x++) title += same_rgb(s.rgb + 3 * ((size_t)y * s.w + x), black);
        CHECK(tick >= 6, "no tick at 0 deg (%d)", tick);
        CHECK(title > 200, "no title text (%d black pixels)", title);
        free(s.rgb);
    }

    /* A toric cornea, 45.75 D at 90 and 42.75 D at 0: the bow-tie. Along the principal
     * meridians the axial power is exactly 337.5/R, so the map shows those bins' colours. */
    static const double axes[] = {90, 30, 160};
    for (int a = 0; a < 3; a++) {
        double ax = axes[a];
        CHECK(fit_torus(337.5 / 45.75, 337.5 / 42.75, ax, &f) == KT_OK, "torus fit");
        snprintf(path, sizeof path, "%s/toric%d.png", dir, a);
        CHECK(take(&sc, &f, path, &s) == 0, "render/decode %s", path);
        if (!s.rgb) continue;
        const int *steep = ref_colour(&ref, 45.75), *flat = ref_colour(&ref, 42.75);
        int bad = 0;
        for (double r = 0.6; r < 3.7; r += 0.5)
            for (int half = 0; half < 2; half++) {
                bad += !same_rgb(at_polar(&s, r, ax + 180 * half), steep);
                bad += !same_rgb(at_polar(&s, r, ax + 90 + 180 * half), flat);
            }
        CHECK(bad == 0, "toric @ %g: %d samples off the steep/flat colours", ax, bad);
        free(s.rgb);
    }

    /* Bad scales: a gap between bins, a malformed line. */
    snprintf(path, sizeof path, "%s/bad.tsv", dir);
    FILE *fp = fopen(path, "w");
    fputs("lo_D\thi_D\tr\tg\tb\n40\t41.5\t0\t0\t0\n42\t43.5\t1\t1\t1\n", fp);
    fclose(fp);
    kt_err e2 = {0};
    CHECK(kt_topo_scale_load(path, &sc, &e2) == KT_EINPUT && strstr(e2.msg, "bad.tsv:3"), "gap: %s", e2.msg);
    fp = fopen(path, "w");
    fputs("40 41.5 0 0\n", fp);
    fclose(fp);
    kt_err e3 = {0};
    CHECK(kt_topo_scale_load(path, &sc, &e3) == KT_EINPUT && strstr(e3.msg, "bad.tsv:1"), "short line: %s", e3.msg);

    /* Clean up the scratch folder. */
    static const char *names[] = {"sphere.png", "toric0.png", "toric1.png", "toric2.png", "bad.tsv"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        unlink(path);
    }
    rmdir(dir);
    return kt_test_done("test_axialmap");
}
