/* curv_total.h: posterior corneal power and total corneal power (thick lens), from fits of the
 * anterior and posterior corneal surfaces (lib/curv.h).
 *
 * Each surface's meridian curvature k(t) (1/mm) is its zone-averaged axial curvature
 * (kt_curv_meridian_k / 337.5: exact for a sphere and along the principal meridians of a
 * biconic). Surface powers, D: anterior Pa = 1000 (n_cornea - n_air) ka, posterior
 * Pp = 1000 (n_aqueous - n_cornea) kp (negative). Total corneal power of meridian t, the thick
 * lens of central thickness d (mm, anterior apex minus posterior apex along the axis):
 *   P = Pa + Pp - (d / 1000) / n_cornea Pa Pp        (Gullstrand's equivalent power). */
#ifndef KT_CURV_TOTAL_H
#define KT_CURV_TOTAL_H

#include "curv.h"

/* Refractive indices. Defaults from Gullstrand's exact schematic eye (No. 1): air 1.000,
 * cornea 1.376, aqueous 1.336 (Atchison DA, Smith G, Optics of the Human Eye, Butterworth-
 * Heinemann 2000, Table A1; Le Grand's full theoretical eye uses the same three values). */
#define KT_N_AIR 1.000
#define KT_N_CORNEA 1.376
#define KT_N_AQUEOUS 1.336

typedef struct kt_cornea_n {
    double air, cornea, aqueous;
} kt_cornea_n;

void kt_cornea_n_default(kt_cornea_n *n);

/* Posterior and total corneal power. Steep = the meridian of largest surface curvature for
 * the posterior surface (its power is the most negative there) and of largest total power for
 * the total; cyl >= 0 is the difference of the magnitudes at the two principal meridians. */
typedef struct kt_total {
    double thickness;                 /* mm */
    double post_steep, post_flat;     /* posterior surface power at its steep / flat meridian, D (< 0) */
    double post_axis, post_cyl;       /* deg, D */
    double tot_steep, tot_flat;       /* total corneal power, D */
    double tot_axis, tot_cyl, tot_mean; /* deg, D, D */
    double pmer[KT_CURV_NMERID];      /* total power at meridians 0, 2, ..., 178 deg, D */
} kt_total;

/* Total power of meridian t (deg) from the two fits (ant->az - post->az is the thickness). */
double kt_curv_total_meridian(const kt_fit *ant, const kt_fit *post, const kt_cornea_n *n, double t);

void kt_curv_total(const kt_fit *ant, const kt_fit *post, const kt_cornea_n *n, kt_total *out);

/* All fields NaN: no posterior surface. */
void kt_curv_total_none(kt_total *out);

/* mask[i] = 1 when input-mesh node i (0-based) is on the posterior corneal surface: a node of
 * the surface group "inner" and of the region "cornea" (lib/eye.h). *mask is the caller's;
 * NULL (and KT_OK) when the mesh lacks either group. */
int kt_curv_posterior_mask(const kt_mesh *m, unsigned char **mask, kt_err *e);

#endif
