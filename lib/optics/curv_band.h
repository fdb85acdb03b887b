/* curv_band.h: first-order uncertainty bands of curvature's readings (issue 21; curvature(1),
 * UNCERTAINTY).
 *
 * A step's readings are a function of two zone fits, step 0's and the step's (curv.h), the
 * incised meridian and the target: kt_band_readings gives them as one vector, in the order of
 * the KT_RD_* indices below, named as curvature.tsv's columns. The derivative of a reading
 * along a parameter p whose displacement derivative is dudp (du/dp, mm per unit of p) is the
 * directional central difference through this same pipeline:
 *   dR/dp = [R(u + eps dudp) - R(u - eps dudp)] / (2 eps),
 * step 0's and the step's displacements moved together (the SIA, flattening and steepening are
 * differences between them). eps (in units of p) moves the anterior surface by at most
 * KT_BAND_DELTA_MM: eps = KT_BAND_DELTA_MM / max |dudp| over the anterior nodes of both steps.
 * Angles (the steep axis, the SIA's axis) are differenced on their 180-degree circle.
 *
 * The quantities are taken as independent: sd_R = sqrt(sum_p (dR/dp sd_p)^2). The 90% interval
 * is R +- 1.645 sd_R (the normal quantile; exact for a reading linear in normally distributed
 * quantities). A magnitude (cylinder, SIA, difference vector) cannot go below 0: its lower
 * bound is clipped at 0. An axis's interval is axis +- 1.645 sd on the 180-degree circle
 * (lo and hi are each reduced to [0, 180), so lo > hi says the interval contains 0 deg). */
#ifndef KT_CURV_BAND_H
#define KT_CURV_BAND_H

#include "curv.h"
#include "units.h"

/* The largest move of an anterior node in the central difference, mm: small against the
 * displacements (tens of um) so the difference is the derivative (the readings change with
 * the surface by a relative 1e-4 over it), large against the fits' round-off (1e-12 mm). */
#define KT_BAND_DELTA_MM 1e-3
/* The two-sided 90% quantile of the standard normal distribution. */
#define KT_BAND_Z90 KT_Z90

enum {
    KT_RD_K_STEEP, KT_RD_K_FLAT, KT_RD_AXIS, KT_RD_CYL, KT_RD_K_MEAN, KT_RD_DK_MEAN,
    KT_RD_FLAT, KT_RD_STEEP, KT_RD_COUPLING, KT_RD_SIA, KT_RD_SIA_X, KT_RD_SIA_Y, KT_RD_SIA_AXIS,
    KT_RD_DV, KT_RD_N
};

/* The reading's name (a curvature.tsv column: "k_steep_D", ...); KT_RD_N: NULL. */
const char *kt_band_reading_name(int r);
/* Its index, -1 when no reading has that name. */
int kt_band_reading_find(const char *name);
/* 1 for the axes (differenced and bounded on the 180-degree circle), 2 for the magnitudes
 * (lower bound clipped at 0), 0 otherwise. */
int kt_band_reading_kind(int r);

/* The readings of a step (fit) against step 0 (fit0): meridian = the incised one (deg), tia =
 * the target induced astigmatism (NULL: none; the difference vector is then NaN). Step 0
 * against itself gives zero changes and a NaN coupling ratio. */
void kt_band_readings(const kt_fit *fit0, const kt_fit *fit, double meridian, const kt_astig *tia,
                      double out[KT_RD_N]);

/* dR/dp from the readings at u + eps dudp (plus) and u - eps dudp (minus). */
void kt_band_derivative(const double plus[KT_RD_N], const double minus[KT_RD_N], double eps,
                        double d[KT_RD_N]);

/* A surface's points (kt_surf's xyz, 3 n, mm) and the derivative of their displacement along
 * one quantity q (du/dq at the same points, 3 n, mm per unit of q). */
typedef struct kt_band_pts {
    int n;
    const double *xyz, *dudp;
} kt_band_pts;

/* The kernel of the central difference above, for one quantity: d := dR/dq of every reading
 * of step s against step 0 (s0), both fitted with (fit, order, zone) as the readings are; *eps
 * := the step in q's unit (KT_BAND_DELTA_MM over the largest |dudp| of both); a quantity that
 * moves neither surface gives d = 0 and *eps = 0. A failed fit is its KT_ERUN. What curvature's
 * bands and lri-plan's readings both call. */
int kt_band_step_deriv(const kt_band_pts *s0, const kt_band_pts *s, int fit, int order, double zone, double meridian,
                       const kt_astig *tia, double d[KT_RD_N], double *eps, kt_err *e);

/* sd of every reading from the contributions c[k][r] = dR_r/dp_k sd_k of n quantities. */
void kt_band_sd(const double *c, int n, double sd[KT_RD_N]);

/* The 90% interval of reading r about its value v with standard deviation sd. */
void kt_band_interval(int r, double v, double sd, double *lo, double *hi);

#endif
