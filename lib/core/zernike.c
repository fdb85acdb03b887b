/* zernike.c: the normalized Zernike polynomials (OSA/ANSI order) as monomials (zernike.h). */
#include "zernike.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NP KT_ZERN_NP

int kt_zern_nterms(int order) { return (order + 1) * (order + 2) / 2; }

static double fact(int n)
{
    double f = 1;
    for (int i = 2; i <= n; i++) f *= i;
    return f;
}

static double binom(int n, int k) { return fact(n) / (fact(k) * fact(n - k)); }

void kt_zern_nm(int j, int *n, int *m)
{
    int nn = (int)ceil((-3 + sqrt(9 + 8.0 * j)) / 2);
    *n = nn;
    *m = 2 * j - nn * (nn + 2);
}

/* The radial part times cos/sin(|m| t) is rho^(n-2s-|m|) Re/Im (u + iv)^|m|, expanded
 * binomially. */
void kt_zern_mono(int n, int m, double *mono)
{
    memset(mono, 0, sizeof(double) * NP * NP);
    int am = abs(m);
    double norm = sqrt((m == 0 ? 1.0 : 2.0) * (n + 1));
    for (int s = 0; s <= (n - am) / 2; s++) {
        double c = (s % 2 ? -1 : 1) * fact(n - s) /
                   (fact(s) * fact((n + am) / 2 - s) * fact((n - am) / 2 - s));
        int p = (n - 2 * s - am) / 2;
        for (int i = 0; i <= p; i++)
            for (int l = 0; l <= am; l++) {
                /* (iv)^l: real for even l (m >= 0 keeps them), imaginary for odd l (m < 0) */
                if ((m >= 0) != (l % 2 == 0)) continue;
                double sg = ((m >= 0 ? l / 2 : (l - 1) / 2) % 2) ? -1 : 1;
                int pu = 2 * i + am - l, pv = 2 * (p - i) + l;
                mono[pu * NP + pv] += norm * c * binom(p, i) * binom(am, l) * sg;
            }
    }
}

void kt_zern_poly(const double *coef, int nterms, double *poly)
{
    double mono[NP * NP];
    memset(poly, 0, sizeof(double) * NP * NP);
    for (int t = 0; t < nterms; t++) {
        int n, m;
        kt_zern_nm(t, &n, &m);
        kt_zern_mono(n, m, mono);
        for (int i = 0; i < NP * NP; i++) poly[i] += coef[t] * mono[i];
    }
}

void kt_zern_poly_eval(const double *c, int N, double u, double v, double d[6])
{
    double pu[NP], pv[NP];
    pu[0] = pv[0] = 1;
    for (int i = 1; i <= N; i++) pu[i] = pu[i - 1] * u, pv[i] = pv[i - 1] * v;
    memset(d, 0, 6 * sizeof(double)); /* P, Pu, Pv, Puu, Puv, Pvv */
    for (int i = 0; i <= N; i++)
        for (int k = 0; i + k <= N; k++) {
            double a = c[i * NP + k];
            if (a == 0) continue;
            d[0] += a * pu[i] * pv[k];
            if (i >= 1) d[1] += a * i * pu[i - 1] * pv[k];
            if (k >= 1) d[2] += a * k * pu[i] * pv[k - 1];
            if (i >= 2) d[3] += a * i * (i - 1) * pu[i - 2] * pv[k];
            if (i >= 1 && k >= 1) d[4] += a * i * k * pu[i - 1] * pv[k - 1];
            if (k >= 2) d[5] += a * k * (k - 1) * pu[i] * pv[k - 2];
        }
}

double kt_zern_poly_value(const double *c, int N, double u, double v)
{
    double pu[NP], pv[NP], p = 0;
    pu[0] = pv[0] = 1;
    for (int i = 1; i <= N; i++) pu[i] = pu[i - 1] * u, pv[i] = pv[i - 1] * v;
    for (int i = 0; i <= N; i++)
        for (int k = 0; i + k <= N; k++) {
            double a = c[i * NP + k];
            if (a != 0) p += a * pu[i] * pv[k];
        }
    return p;
}
