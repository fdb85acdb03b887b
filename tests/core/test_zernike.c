/* test_zernike.c: the Zernike polynomials of lib/core/zernike.h: the OSA/ANSI index (j -> n, m
 * for the first 28 terms against the formula j = (n (n + 2) + m) / 2), closed forms of the
 * first terms (tilt, defocus, astigmatism, coma, spherical), orthonormality in the mean over
 * the unit disk (a polar Gauss-Legendre rule, exact for these degrees), the derivatives of
 * kt_zern_poly_eval against central differences, and kt_zern_poly_value equal to the bit to
 * kt_zern_poly_eval's value. */
#include <math.h>
#include <string.h>

#include "kt_test.h"
#include "util.h"
#include "zernike.h"

#define NP KT_ZERN_NP

static double zval(int j, double u, double v)
{
    int n, m;
    double mono[NP * NP], d[6];
    kt_zern_nm(j, &n, &m);
    kt_zern_mono(n, m, mono);
    kt_zern_poly_eval(mono, n, u, v, d);
    return d[0];
}

static void test_index(void)
{
    int bad = 0;
    for (int n = 0, j = 0; n <= 6; n++)
        for (int m = -n; m <= n; m += 2, j++) {
            int nn, mm;
            kt_zern_nm(j, &nn, &mm);
            bad += nn != n || mm != m || j != (n * (n + 2) + m) / 2;
        }
    CHECK(bad == 0, "%d of the first 28 indices wrong", bad);
    CHECK(kt_zern_nterms(8) == 45 && kt_zern_nterms(6) == 28, "terms to order 8: %d", kt_zern_nterms(8));
}

static void test_closed_forms(void)
{
    double u = 0.3, v = -0.55, r2 = u * u + v * v, t = atan2(v, u), r = sqrt(r2);
    double want[13] = {1,
                       2 * r * sin(t),
                       2 * r * cos(t),
                       sqrt(6) * r2 * sin(2 * t),
                       sqrt(3) * (2 * r2 - 1),
                       sqrt(6) * r2 * cos(2 * t),
                       sqrt(8) * r2 * r * sin(3 * t),
                       sqrt(8) * (3 * r2 * r - 2 * r) * sin(t),
                       sqrt(8) * (3 * r2 * r - 2 * r) * cos(t),
                       sqrt(8) * r2 * r * cos(3 * t),
                       0, 0,
                       sqrt(5) * (6 * r2 * r2 - 6 * r2 + 1)};
    for (int j = 0; j < 13; j++) {
        if (j == 10 || j == 11) continue;
        char what[32];
        snprintf(what, sizeof what, "Z_%d", j);
        CHECK_NEAR(zval(j, u, v), want[j], 1e-13, what);
    }
}

/* Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n). */
static void gauss(int n, double *x, double *w)
{
    for (int i = 0; i < n; i++) {
        double z = cos(KT_PI * (i + 0.75) / (n + 0.5)), dp = 0;
        for (int it = 0; it < 100; it++) {
            double p0 = 1, p1 = z;
            for (int k = 2; k <= n; k++) {
                double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
                p0 = p1, p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1);
            double dz = p1 / dp;
            z -= dz;
            if (fabs(dz) < 1e-16) break;
        }
        x[i] = z, w[i] = 2 / ((1 - z * z) * dp * dp);
    }
}

static void test_orthonormal(void)
{
    enum { NT = 45, NR = 12, NA = 40 };
    double xr[NR], wr[NR], G[NT][NT];
    memset(G, 0, sizeof G);
    gauss(NR, xr, wr);
    for (int i = 0; i < NR; i++) {
        double r = 0.5 * (xr[i] + 1), wgt = 0.5 * wr[i] * r; /* int_0^1 f r dr */
        for (int k = 0; k < NA; k++) {
            double t = 2 * KT_PI * k / NA, z[NT];
            for (int j = 0; j < NT; j++) z[j] = zval(j, r * cos(t), r * sin(t));
            for (int a = 0; a < NT; a++)
                for (int b = 0; b < NT; b++) G[a][b] += z[a] * z[b] * wgt * (2 * KT_PI / NA) / KT_PI;
        }
    }
    double worst = 0;
    for (int a = 0; a < NT; a++)
        for (int b = 0; b < NT; b++) worst = fmax(worst, fabs(G[a][b] - (a == b)));
    CHECK(worst < 1e-12, "orthonormal to order 8 in the mean over the disk: worst %.3g", worst);
}

static void test_derivatives(void)
{
    double coef[45], poly[NP * NP], d[6], dp[6], dm[6], h = 1e-5;
    for (int j = 0; j < 45; j++) coef[j] = sin(1.7 * j + 0.3) / (1 + j);
    kt_zern_poly(coef, 45, poly);
    double u = -0.41, v = 0.62, worst = 0;
    kt_zern_poly_eval(poly, 8, u, v, d);
    double direct = 0;
    for (int j = 0; j < 45; j++) direct += coef[j] * zval(j, u, v);
    CHECK_NEAR(d[0], direct, 1e-12, "the monomial sum against the terms' sum");
    CHECK(kt_zern_poly_value(poly, 8, u, v) == d[0], "kt_zern_poly_value equals kt_zern_poly_eval's value to the bit");
    kt_zern_poly_eval(poly, 8, u + h, v, dp);
    kt_zern_poly_eval(poly, 8, u - h, v, dm);
    worst = fmax(worst, fabs((dp[0] - dm[0]) / (2 * h) - d[1]));
    worst = fmax(worst, fabs((dp[1] - dm[1]) / (2 * h) - d[3]));
    worst = fmax(worst, fabs((dp[2] - dm[2]) / (2 * h) - d[4]));
    kt_zern_poly_eval(poly, 8, u, v + h, dp);
    kt_zern_poly_eval(poly, 8, u, v - h, dm);
    worst = fmax(worst, fabs((dp[0] - dm[0]) / (2 * h) - d[2]));
    worst = fmax(worst, fabs((dp[2] - dm[2]) / (2 * h) - d[5]));
    CHECK(worst < 1e-7, "derivatives against central differences: worst %.3g", worst);
}

int main(void)
{
    test_index();
    test_closed_forms();
    test_orthonormal();
    test_derivatives();
    return kt_test_done("test_zernike");
}
