/* surffit.h: what the mesher needs from a Pentacam export (lib/io/pentacam.h): the apex radii,
 * steep meridian and asphericity (conic Q) of a corneal surface from its elevation map, and
 * the corneal thickness profile from the pachymetry map, each over a documented zone
 * (keratome-patient(5), THE FIT), with the residuals. */
#ifndef KT_SURFFIT_H
#define KT_SURFFIT_H

#include "curv.h"
#include "pentacam.h"

/* Zones (diameters, mm): the surfaces over the central 8 mm, the zone commonly used for the
 * Pentacam's best-fit reference surfaces, where the device's data are complete in normal eyes;
 * the thickness profile out to the incision zone plus 1 mm (keratome-patient(5), THE FIT). */
#define KT_SURFFIT_ZONE 8.0

/* A fitted surface: biconic z = -(sag) with one conic constant (kt_curv_fit, KT_FIT_TORIC). */
typedef struct kt_surffit {
    double r_steep, r_flat;     /* apex radii of the steep and flat meridians, mm */
    double axis;                /* steep meridian, deg TABO, 0 <= axis < 180 */
    double conic;               /* Q */
    double ax, ay;              /* apex, mm */
    double rms, max_resid;      /* residuals over the zone, mm */
    int npts;                   /* cells used */
    double zone;                /* mm */
} kt_surffit;

/* Fit an elevation map over the zone of diameter zone_d (mm) around the grid centre, then
 * around the fitted apex. Fewer than 12 measured cells there is KT_ERUN. */
int kt_surffit_elevation(const kt_pentacam_map *m, double zone_d, kt_surffit *out, kt_err *e);

/* The half-meridian powers (keratome-patient(5), UNEQUAL PAIRED ARCS), keratometric index:
 * the fitted biconic's apex power of the meridian (the same on both halves) plus what each half
 * adds: the axial power of the fit's residual on that half, about the fitted apex, averaged over
 * the 3 mm keratometry zone (r = 0.5 ... 1.5 mm): the residual of the cells within
 * KT_SURFFIT_HALF_WEDGE deg of the half-meridian, 0.3 ... 1.7 mm out, fitted as
 * z = z0 + t r + c r^2 + b r^3 + d r^4, the tilt t left out. A biconic has k_a = k_b. */
#define KT_SURFFIT_HALF_WEDGE 15.0
typedef struct kt_halfmer {
    double k_a, k_b;            /* D: the steep meridian's half at axis and at axis + 180 */
    double k_flat;              /* D: the mean of the flat meridian's halves (axis +- 90) */
    double axis;                /* deg, the steep axis of the fit (0 ... 180) */
    int npts;                   /* cells used, the four halves together */
} kt_halfmer;

int kt_surffit_halves(const kt_pentacam_map *m, const kt_surffit *fit, kt_halfmer *out, kt_err *e);

/* Thickness profile t(r) = t0 + t2 r^2 + t4 r^4 (mm, r from (cx, cy)) fitted to the
 * pachymetry map's cells with r <= r_max. */
typedef struct kt_pachyfit {
    double t0, t2, t4;          /* mm, 1/mm, 1/mm^3 */
    double rms, max_resid;      /* mm */
    int npts;
    double r_max;               /* mm */
} kt_pachyfit;

int kt_surffit_pachymetry(const kt_pentacam_map *m, double cx, double cy, double r_max, kt_pachyfit *out,
                          kt_err *e);
/* The profile's thickness at radius r, mm. */
double kt_pachyfit_at(const kt_pachyfit *p, double r);

#endif
