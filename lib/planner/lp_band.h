/* lp_band.h: the planner's last stage (writes kt_lp_answer.band): the band of the chosen
 * prediction as a 2-D distribution (lri-plan(1), BAND).
 *
 * A prediction is a double-angle vector v = pre-op + main incision + the arcs' simulated SIA;
 * its uncertainty comes from the SIA's derivatives along the tissue quantities q (lp_read.h),
 * taken as independent normal: v ~ N(mean, Sigma), mean the prediction and
 *     Sigma = J diag(sd_q^2) J^T + Sigma_extra,
 * J the 2 x nq matrix of d(SIA_x, SIA_y)/dq at the step, Sigma_extra the caller's further
 * covariance (kt_lp_opts.band_extra, zero by default) plus the scene's non-tissue term
 * cv^2 s s^T, s the step's SIA from the intact eye (healing, blade and keratometry spread as a
 * coefficient of variation cv of the SIA along itself: uncertainty.nontissue_cv). The magnitude |v| is
 * what the surgeon reads; its distribution is that of the length of a 2-D normal vector (a
 * noncentral, in general elliptical, one): its CDF
 *     F(r) = P(|v| <= r)
 * is computed by quadrature in the frame of Sigma's principal axes (x along the minor axis,
 * sd sx, y along the major one, sd sy; mean (mx, my) there):
 *     F(r) = int_{-r}^{r} phi((x - mx)/sx)/sx [Phi((s - my)/sy) - Phi((-s - my)/sy)] dx,
 *     s = sqrt(r^2 - x^2),
 * substituting x = r cos t (t in [0, pi]) and integrating (16 panels of 16-point
 * Gauss-Legendre) over the part of the x range within 12 sx of mx, where the integrand is
 * smooth; exactly, by Phi, when Sigma has rank 1 (sx <= 1e-9 sy) or 0 (a point). The band is its 5% and 95% quantiles (bisection on F), and |v|'s mean and sd
 * (E|v| = int_0^inf (1 - F(r)) dr, E|v|^2 = |mean|^2 + trace Sigma). No linearization: near a
 * zero prediction the band does not collapse (the 95% quantile is then at least the SIA's own
 * sd along any direction, since P(|v| <= r) <= P(|e . v| <= r)). */
#ifndef KT_LP_BAND_H
#define KT_LP_BAND_H

#include "lp.h"

/* The band's probability: the 90% interval between the 5% and 95% quantiles. */
#define KT_LP_BAND_LO 0.05
#define KT_LP_BAND_HI 0.95

/* cov := J diag(sd^2) J^T + extra (extra NULL: none), J's columns d[q] (nq of them). */
void kt_lp_band_cov(int nq, const double (*d)[2], const double *sd, const kt_lp_cov *extra, kt_lp_cov *cov);
/* out := extra + cv^2 s s^T (extra NULL: zero): the non-tissue term of a prediction whose SIA
 * (double-angle, from the intact eye) is s, a spread of cv |s| along the SIA itself
 * (keratome-scene(5), UNCERTAINTY, nontissue_cv). */
void kt_lp_band_nontissue(const double s[2], double cv, const kt_lp_cov *extra, kt_lp_cov *out);
/* P(|v| <= r) for v ~ N(mean, cov). */
double kt_lp_band_cdf(const double mean[2], const kt_lp_cov *cov, double r);
/* b := the band of v ~ N(mean, cov): mean, cov, mag = |mean|, the magnitude's sd, lo and hi. */
void kt_lp_band_of(const double mean[2], const kt_lp_cov *cov, kt_lp_band *b);
/* The sd of the magnitude of a vector s along its own direction (the SIA's sd as curvature
 * reports it): sqrt(sum_q ((s/|s|) . d[q] sd[q])^2); the rms of the components at |s| = 0. */
double kt_lp_band_along(const double s[2], int nq, const double (*d)[2], const double *sd);

/* b := the chosen prediction's bands (none without derivatives: o->no_band). Reads a->run and
 * a->choice. */
void kt_lp_bands_make(const kt_lp_opts *o, const kt_lp_answer *a, kt_lp_bands *b);

#endif
