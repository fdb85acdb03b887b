/* curv.c: simulated keratometry of a fitted anterior corneal surface. */
#include <math.h>

#include "curv.h"

#define DEG KT_CURV_DEG

/* ---------------------------------------------------------------- keratometry */

/* Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n from the Chebyshev guesses). */
#define GL_N 16
static void gauss_legendre(double *x, double *w)
{
    for (int i = 0; i < GL_N; i++) {
        double z = cos(KT_CURV_PI * (i + 0.75) / (GL_N + 0.5)), dp = 1;
        for (int it = 0; it < 100; it++) {
            double p0 = 1, p1 = z;
            for (int k = 2; k <= GL_N; k++) {
                double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
                p0 = p1, p1 = p2;
            }
            dp = GL_N * (z * p1 - p0) / (z * z - 1);
            double dz = p1 / dp;
            z -= dz;
            if (fabs(dz) < 1e-16) break;
        }
        x[i] = z;
        w[i] = 2 / ((1 - z * z) * dp * dp);
    }
}

double kt_curv_meridian_k(const kt_fit *f, double t)
{
    double gx[GL_N], gw[GL_N], num = 0, den = 0;
    gauss_legendre(gx, gw);
    for (int half = 0; half < 2; half++) {
        double c = cos((t + 180 * half) * DEG), s = sin((t + 180 * half) * DEG);
        for (int i = 0; i < GL_N; i++) {
            double r = 0.5 * f->a * (gx[i] + 1), wr = gw[i] * r; /* area weight r dr */
            num += wr * kt_fit_axial_power(f, f->ax + r * c, f->ay + r * s);
            den += wr;
        }
    }
    return num / den;
}

double kt_curv_harmonic_axis(const double *v)
{
    double a2 = 0, b2 = 0;
    for (int i = 0; i < KT_CURV_NMERID; i++) {
        double t = i * 180.0 / KT_CURV_NMERID;
        a2 += v[i] * cos(2 * t * DEG);
        b2 += v[i] * sin(2 * t * DEG);
    }
    double ax = 0.5 * atan2(b2, a2) / DEG;
    if (ax < 0) ax += 180;
    if (ax >= 180 - 1e-9) ax = 0; /* 179.999... from round-off is 0 */
    return ax;
}

void kt_curv_simk(const kt_fit *f, kt_kerato *k)
{
    for (int i = 0; i < KT_CURV_NMERID; i++) k->kmer[i] = kt_curv_meridian_k(f, i * 180.0 / KT_CURV_NMERID);
    double ax = kt_curv_harmonic_axis(k->kmer);
    k->axis_steep = ax;
    k->k_steep = kt_curv_meridian_k(f, ax);
    k->k_flat = kt_curv_meridian_k(f, ax + 90);
    k->cyl = k->k_steep - k->k_flat;
    k->k_mean = 0.5 * (k->k_steep + k->k_flat);
}
