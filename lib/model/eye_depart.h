/* eye_depart.h: the measured corneal surfaces in the eye's mesh (keratome-scene(5),
 * eye.anterior_departure and eye.posterior_departure).
 *
 * The anterior's base may be aspheric: the biconic of the eye's radii and steep axis with the
 * conic constant Q (conic, anterior only; 0: the toric, circles in the principal meridians).
 * Its height over the toric, dQ(x, y) = sag_toric - sag_Q, less c0, dQ at the corneal edge of
 * the conic of the mean apical curvature, moves every node of the cornea (rho <= rc, the
 * corneal edge's radius) by dQ - c0: the cornea moves as a column (its thickness and the rings'
 * depths unchanged), its apex down by c0, its edge stays on the globe up to what varies with the
 * meridian. Beyond rc a node moves by wQ (dQ(rc, its meridian) - c0), wQ = 1 up to the polar
 * angle (about the globe centre) of the corneal edge, a quintic step down to 0 at the limbus'
 * scleral edge: the limbus blends, the sclera stays.
 *
 * A departure is the height, mm along +z (towards the observer), that turns the base surface
 * the mesher builds (the anterior: the toric or the aspheric biconic above; the posterior: its
 * conic with its toric warp, moved with the column by dQ) into the measured one. With a the
 * zone radius, b the taper's end (a < b), rho the distance from the eye axis:
 *   rho <= a:      D = sum_j c_j Z_j(x / a, y / a)   (lib/core/zernike.h: OSA/ANSI index j,
 *                  normalized, so c_j is the term's RMS over the zone)
 *   a < rho < b:   D = (D_a + s D_r + s^2 D_rr / 2) S(s / (b - a)), s = rho - a, with D_a, D_r,
 *                  D_rr the value and first and second radial derivatives of the expansion at
 *                  (a, theta) and S(t) = 1 - 10 t^3 + 15 t^4 - 6 t^5
 *   rho >= b:      D = 0 (the base surface)
 * D, its slope and its curvature are continuous across both circles (C2). */
#ifndef KT_EYE_DEPART_H
#define KT_EYE_DEPART_H

#include "util.h"
#include "zernike.h"

typedef struct kt_eye_departure {
    double conic;                   /* the anterior base's Q (0: the toric); 0 for the posterior */
    int order;                      /* Zernike radial order, 2 ... 12; 0: no departure */
    double radius;                  /* a, mm */
    double taper;                   /* b, mm */
    double coef[KT_ZERN_TERMS_MAX]; /* c_j, mm, j = 0 ... kt_zern_nterms(order) - 1 */
} kt_eye_departure;

struct kt_eye;
struct kt_eye_geom;
struct kt_mesh;

/* The expansion's monomials (zernike.h) for kt_eye_departure_at; once per departure. */
void kt_eye_departure_poly(const kt_eye_departure *d, double poly[KT_ZERN_NP * KT_ZERN_NP]);

/* D(x, y), mm (0 when d->order is 0). */
double kt_eye_departure_at(const kt_eye_departure *d, const double *poly, double x, double y);

/* The sag (mm, >= 0 into the eye) below the apex of the anterior surface (posterior 0) or the
 * vertex of the posterior one (posterior 1) that the mesher builds before the departures (with
 * eye->dep_ant.conic's base), at (x, y); NAN outside its domain. What a measured surface's
 * departure is taken from (lib/optics/surffit.h). */
double kt_eye_base_sag(const struct kt_eye_geom *g, const struct kt_eye *eye, int posterior, double x, double y);

/* The anterior apex's height after the aspheric base's move: kt_eye_geom's z_apex - c0. */
double kt_eye_base_apex(const struct kt_eye_geom *g, const struct kt_eye *eye);

/* The eye's departures checked against its geometry: the aspheric base defined out to the
 * corneal edge; the anterior's taper ends at most at the corneal edge (white_to_white /
 * 2), the posterior's at most where the posterior cornea meets the limbus, and together they
 * leave at least half the base thickness everywhere (sampled every 0.05 mm and 2 deg). KT_EINPUT
 * naming the field. */
int kt_eye_departure_check(const struct kt_eye_geom *g, const struct kt_eye *eye, kt_err *e);

/* The mesh of revolution mapped onto the eye's surfaces: the toric warp (kt_eye_warp_toric),
 * then each node moved by wQ dQ(x, y) + w D_ant(x, y) + (1 - h) D_post(x, y), wQ, w and h from
 * the node's place in the mesh of revolution (w and h the toric warp's weight and relative
 * height: 1 and 1 on the anterior surface, 0 and 0 on the posterior): anterior nodes land
 * exactly on the base anterior plus D_ant, posterior nodes of the cornea on the base posterior
 * plus D_post; the sclera does not move. Without departures the toric warp alone. */
int kt_eye_warp_measured(const struct kt_eye_geom *g, const struct kt_eye *eye, struct kt_mesh *m,
                         kt_err *e);

#endif
