/* surffit.h: what the mesher needs from a Pentacam export (lib/io/pentacam.h): the apex radii,
 * steep meridian and asphericity (conic Q) of a corneal surface from its elevation map, and
 * the corneal thickness profile from the pachymetry map, each over a documented zone
 * (keratome-patient(5), THE FIT), with the residuals. */
#ifndef KT_SURFFIT_H
#define KT_SURFFIT_H

#include "curv.h"
#include "patient.h"
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
    /* The measured surface in the mesh (kt_surffit_measured_eye; dep_order 0: not fitted): */
    int dep_order;              /* Zernike order of the departure */
    double dep_rms, dep_max;    /* its residuals over the zone, mm: the mesh's surface (base
                                   plus departure) against the map's cells */
    int dep_npts;               /* cells used */
    double dep_radius;          /* the departure's zone radius, mm */
} kt_surffit;

/* Fit an elevation map over the zone of diameter zone_d (mm) around the grid centre, then
 * around the fitted apex. Fewer than 12 measured cells there is KT_ERUN. */
int kt_surffit_elevation(const kt_pentacam_map *m, double zone_d, kt_surffit *out, kt_err *e);

/* The measured surface in the mesh (keratome-patient(5), THE FIT; lib/model/eye_depart.h): an
 * elevation map's departure from the surface eye's mesher builds (kt_eye_base_sag: the anterior
 * with eye->dep_ant.conic's asphericity, posterior 0; the posterior conic with its toric warp,
 * posterior 1), z = base sag - the map's value at each measured cell within a (mm) of the eye
 * axis (the grid centre), fitted with the normalized Zernike polynomials to the given order
 * about the axis on that disk (fewer than 3 cells a term lowers the order: d->order says what
 * was fitted); then the tilt terms (j = 1, 2: the map's decentration) set to 0, and for the
 * posterior the rotationally symmetric ones (m = 0: its radial profile is the pachymetry's);
 * tapered to 0 at `taper` (mm); d->conic the anterior base's (0 for the posterior); *rms and
 * *max the fit's residuals over those cells (all terms), mm; *npts their count. Order
 * KT_SURFFIT_DEP_ORDER is lri-plan's (keratome-patient(5), THE FIT: the residuals by order). */
#define KT_SURFFIT_DEP_ORDER 6
int kt_surffit_departure(const kt_pentacam_map *m, const kt_eye *eye, int posterior, int order, double a,
                         double taper, kt_eye_departure *d, double *rms, double *max, int *npts, kt_err *e);

/* The zone of a measured surface shrinks, by 0.25 mm steps down to this radius (mm), until the
 * map measures this fraction of its grid's cells (keratome-patient(5), THE FIT). */
#define KT_SURFFIT_DEP_MIN_RADIUS 2.0
#define KT_SURFFIT_DEP_COVER 0.9

/* The patient's measured surfaces into its eye scene: the anterior base aspheric with the fit's
 * Q (ant->conic), the front map's departure over the fit's zone (KT_SURFFIT_ZONE, or the
 * largest disk within it the map measures, KT_SURFFIT_DEP_COVER) into
 * eye->dep_ant, tapered to 0 at the corneal edge (white_to_white / 2); when the export has a
 * back map, its departure over the zone where the toric posterior is whole (rho_P / 2, rho_P
 * where the posterior cornea meets the limbus; keratome-scene(5)) into eye->dep_post, tapered to
 * 0 at rho_P as the toric posterior is; order KT_SURFFIT_DEP_ORDER; the residuals into
 * ant->dep_* and post->dep_* (post may be NULL without a back map); then the pair checked
 * against the eye (kt_eye_departure_check; KT_EINPUT naming the front map when they do not
 * fit). A no-op for a patient without a Pentacam export. */
int kt_surffit_measured_eye(const kt_patient *p, kt_eye *eye, kt_surffit *ant, kt_surffit *post, kt_err *e);

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
