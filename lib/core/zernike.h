/* zernike.h: the Zernike polynomials as the project uses them, one copy for the fits of
 * lib/optics (curv_fit.c, surffit.c) and the measured-surface warp of lib/model (eye_depart.c).
 *
 * Convention: OSA/ANSI (ISO 24157) single index j = (n (n + 2) + m) / 2, radial order n,
 * azimuthal frequency m (-n <= m <= n, n - m even); j = 0 piston, 1 vertical tilt (m = -1, sin),
 * 2 horizontal tilt, 3 oblique astigmatism, 4 defocus, 5 vertical astigmatism (cos 2t), ...
 * Normalized orthonormal in the mean over the unit disk: Z_n^m = N R_n^|m|(r) cos(m t) for
 * m >= 0, N R_n^|m|(r) sin(|m| t) for m < 0, N = sqrt((2 - d_m0)(n + 1)), so a coefficient is
 * the term's RMS over the disk. The angle t counter-clockwise from +u, (u, v) = (x - xc, y - yc) / a.
 *
 * A polynomial is kept as monomials: c[i * KT_ZERN_NP + k] is the coefficient of u^i v^k. */
#ifndef KT_ZERNIKE_H
#define KT_ZERNIKE_H

#define KT_ZERN_ORDER_MAX 12
#define KT_ZERN_NP (KT_ZERN_ORDER_MAX + 1)
#define KT_ZERN_TERMS_MAX ((KT_ZERN_ORDER_MAX + 1) * (KT_ZERN_ORDER_MAX + 2) / 2)

/* Terms of the expansion up to radial order `order`: (order + 1)(order + 2) / 2. */
int kt_zern_nterms(int order);

/* OSA/ANSI single index j -> (n, m). */
void kt_zern_nm(int j, int *n, int *m);

/* mono[KT_ZERN_NP * KT_ZERN_NP] = the monomial coefficients of the normalized Z_n^m (n <= 12). */
void kt_zern_mono(int n, int m, double *mono);

/* poly[KT_ZERN_NP * KT_ZERN_NP] = sum over j < nterms of coef[j] Z_j, as monomials. */
void kt_zern_poly(const double *coef, int nterms, double *poly);

/* A monomial polynomial of degree <= N at (u, v): d[0] P, d[1] P_u, d[2] P_v, d[3] P_uu,
 * d[4] P_uv, d[5] P_vv. */
void kt_zern_poly_eval(const double *c, int N, double u, double v, double d[6]);
/* P(u, v) alone, summed as kt_zern_poly_eval sums d[0] (the same value to the bit). */
double kt_zern_poly_value(const double *c, int N, double u, double v);

#endif
