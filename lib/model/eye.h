/* eye.h: the parametric eye (anterior segment or whole globe) meshed with the gmsh C API.
 *
 * Frame: the eye's optical axis is +z (towards the observer), the corneal apex on the axis.
 * Seen from the front (from +z), x points to the examiner's right and y up, so a meridian at
 * angle t (degrees, counter-clockwise from +x, the standard TABO convention) is the direction
 * (cos t, sin t, 0). The anterior cornea is toric: radius r_ant_steep in the steep meridian,
 * r_ant_flat at 90 degrees from it.
 *
 * Groups written (names are the contract other tools rely on):
 *   regions (dim 3):  "cornea" 1, "limbus" 2, "sclera" 3
 *   surfaces (dim 2): "anterior" 1  anterior corneal surface (cornea region only)
 *                     "inner"    2  posterior cornea + inner limbus/sclera: IOP acts here
 *                     "fixed"    3  where the model is cut off (absent for the whole globe)
 *                     "outer"    4  outer surface of limbus and sclera
 *                     ring k     10+k  the scene's incision-ready surfaces, named by the scene
 *                                      ("incision-ring-1", ...), embedded in the volume */
#ifndef KT_EYE_H
#define KT_EYE_H

#include "mesh.h"
#include "eye_geom.h"

/* Mesh the eye at the given element order; progress on stderr unless quiet. Fails (KT_ERUN)
 * when gmsh fails or returns no tets, and (KT_EINPUT) on inconsistent geometry (an incision
 * ring outside the cornea and limbus, deeper than the local thickness). */
int kt_eye_mesh(const kt_eye *eye, int order, int quiet, kt_mesh *m, kt_err *e);

/* The cornea and optical-zone element sizes the mesher uses at an element order: the scene's,
 * at most t_central / 2.5 for order 1 (two linear tets or more through the corneal thickness)
 * and t_central for order 2 (keratome-scene(5), mesh_size). */
void kt_eye_sizes(const kt_eye *eye, int order, double *h_cornea, double *h_optical);
/* The divisor of that rule: 2.5 for order 1, 1 for order 2. */
double kt_eye_layers(int order);

/* Most tets a scene's eye may ask for (estimated by kt_eye_estimate_tets): about 2.8 million
 * order-2 nodes, 8.4 million DOFs, whose factorization needs more than a 24 GiB machine holds;
 * gmsh takes about an hour to mesh it on 2 cores. */
#define KT_EYE_MAX_TETS 2000000
/* *tets = the number of tets the eye's size fields ask for at this order, estimated from the
 * regions' volumes before meshing (eye_budget.c: low rather than high, by up to about 20%).
 * Inconsistent geometry is KT_EINPUT, as in kt_eye_geom_init. */
int kt_eye_estimate_tets(const kt_eye *eye, int order, double *tets, kt_err *e);


/* The oval cornea (eye_geom.h, kt_eye_warp_oval; keratome-scene(5), THE OVAL CORNEA). */
/* The least vertical white-to-white (mm) the oval warp takes for this eye's other dimensions:
 * wtw - 1.6 (wtw - limbus_width - optical_zone) / 2 (its ramp squeezes no element to less than
 * a fifth of its radial size); NAN when they do not make an eye. */
double kt_eye_wtw_v_min(const kt_eye *eye);
/* The radial distance (mm) from the axis, in the meridian `meridian` (deg TABO), of the anterior
 * surface's curve that has the horizontal diameter `diameter` (an incision ring's zone, a
 * tunnel's entry) after the oval warp: diameter / 2 for a round eye; on the oval, from
 * KT_EYE_OVAL_RAMP (rc - rv) outside the optical zone on, diameter / 2 - (wtw - wtw_v) / 2 at
 * 90 deg. NAN when the eye's dimensions are inconsistent. */
double kt_eye_oval_radius(const kt_eye *eye, double diameter, double meridian);
/* The chord (mm, seen from the front) between the ends of the arc of that curve from meridian
 * `from` to `to` (deg, counter-clockwise), and its length along the curve (mm, seen from the
 * front; 0.5 diameter (to - from) in radians for a round eye). NAN for an inconsistent eye. */
double kt_eye_arc_chord(const kt_eye *eye, double diameter, double from, double to);
double kt_eye_arc_length(const kt_eye *eye, double diameter, double from, double to);

/* Lamellar frames of the eye's tets (eye.fibres; keratome-scene(5)), at each tet's centroid:
 * F[13 t + 0..2] a1 and [3..5] a2, the in-plane fibre directions (nasal-temporal and
 * superior-inferior centrally, turned about n from a1 towards a2 by w times the tangent-plane
 * angle from a1 to the radial direction c x n reduced to [-45, 45] deg: radial/circumferential
 * at w = 1), [6..8] n, the normal (from the anterior sphere's centre in the cornea, the globe's
 * centre elsewhere), [9..11] c, the in-plane circumferential direction, [12] w, the limbal weight:
 * 0 inside rc - limbal_band, 1 from the corneal edge rc = white_to_white/2 on (and in limbus and
 * sclera), smoothstep between. On an oval cornea rc is the edge's radius in the tet's meridian
 * (kt_eye_geom_edge_rho), and radial / circumferential are the normal / tangent of the ellipse
 * x^2/a^2 + y^2/b^2 through the centroid (a, b the white-to-white semi-axes). */
int kt_eye_fibre_frames(const kt_eye *eye, const kt_mesh *m, double *F, kt_err *e);

/* Relative depth of each tet's centroid (mean of its corners) through the local thickness of
 * cornea and limbus: S[t] = 0 at the anterior (outer) surface, 1 at the posterior (inner) one,
 * NAN in the sclera. The toric warp (kt_eye_warp_toric) is undone first, so the depth is that
 * of the mesh of revolution the tet came from: in the cornea along the ray from the anterior
 * sphere's centre, in the limbus across its quad (eye_geom.h, kt_eye_geom_height). For
 * G_transverse_profile (kt_gt_profile). */
int kt_eye_depth_fractions(const kt_eye *eye, const kt_mesh *m, double *S, kt_err *e);

#endif
