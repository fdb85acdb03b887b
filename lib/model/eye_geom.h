/* eye_geom.h: analytic geometry of the parametric eye (internal to the eye module: eye.c and
 * eye_geom.c). Public entry points are in eye.h.
 *
 * Profile plane: (rho, z), rho = sqrt(x^2 + y^2) >= 0, the eye axis z. The globe centre is the
 * origin; the outer sclera is the sphere |p| = Rg, the inner one |p| = Ri = Rg - sclera.
 *
 *            A0 (apex, z_apex)
 *      anterior sphere (mean radius Ra, centre Ca on the axis), toric after the node warp
 *          .-''''-.         E  corneal edge (rho = wtw/2) on the outer globe sphere
 *        /  cornea  \ E___ Lo   limbus outer edge (rho = wtw/2 + limbus_width)
 *       |  .-'''-.   |limbus|   sclera: shell Ri..Rg from Lo/Li to the polar angle `extent`
 *          Pv     Pp ---- Li
 *   posterior conic (apical radius r_post, vertex Pv = apex - t_central, through Pp) */
#ifndef KT_EYE_GEOM_H
#define KT_EYE_GEOM_H

#include "eye_depart.h"
#include "mesh.h"

/* The mesh group tags of the eye (names and meaning in eye.h). */
enum { KT_EYE_REG_CORNEA = 1, KT_EYE_REG_LIMBUS, KT_EYE_REG_SCLERA };
enum { KT_EYE_SURF_ANTERIOR = 1, KT_EYE_SURF_INNER, KT_EYE_SURF_FIXED, KT_EYE_SURF_OUTER,
       KT_EYE_SURF_RING0 = 10 };

/* The default size slope away from an incision ring's floor (size increase per unit distance,
 * eye.mesh_size.floor_grading): at distance d from the floor the size is
 * h_floor + floor_grading (d - h_floor / 2), up to the ring's size (eye.c's size field;
 * eye_budget.c's estimate). */
#define KT_EYE_FLOOR_GRADING 0.5

/* The oval warp's ramp (eye_geom.c): its whole move is reached KT_EYE_OVAL_RAMP (rc - rv) outside
 * the optical zone (the ramp squeezes the tissue radially by 1 / KT_EYE_OVAL_RAMP = half at most)
 * or, when that lies beyond rc - limbus_width / 2 (the outermost ring), there, if the squeeze
 * keeps at least KT_EYE_OVAL_KEEP of the radial size. */
#define KT_EYE_OVAL_RAMP 2.0
#define KT_EYE_OVAL_KEEP 0.2

/* The horizontal less the vertical white-to-white, mm, where only the horizontal is given: the
 * population means 11.71 mm (Rufer et al. 2005, Orbscan II) and 10.63 mm (the optometric
 * literature's vertical diameter); an offset, not a ratio, as the anatomy has it (the sclera
 * overlapping the cornea more superiorly and inferiorly; keratome-scene(5), THE OVAL CORNEA). */
#define KT_EYE_WTW_DIFF 1.1

/* The eye's parameters as the scene gives them (internal units mm, degrees). */
#define KT_SCENE_MAX 16

/* An incision-ready surface of the eye: a ring cut into the cornea from the anterior surface. */
typedef struct kt_ring {
    char name[KT_NAME_MAX];     /* mesh surface group name, e.g. "incision-ring-1" */
    double diameter;            /* optical-zone diameter of the ring, mm */
    double depth;               /* depth below the anterior surface, mm (if depth_fraction 0) */
    double depth_fraction;      /* or a fraction of the local corneal thickness */
} kt_ring;

typedef struct kt_eye {
    double r_ant_steep, r_ant_flat; /* anterior corneal radii in the steep/flat meridians, mm */
    double steep_axis;              /* steep meridian, deg (ophthalmic convention, 0..180) */
    double r_post;                  /* posterior corneal (mean apical) radius, mm */
    double r_post_steep, r_post_flat; /* posterior apical radii in its steep/flat meridians, mm
                                       (equal: a posterior of revolution); their mean
                                       curvature is 1/r_post */
    double post_axis;               /* the posterior's steep meridian, deg (TABO, 0..180) */
    double t_central, t_peripheral; /* corneal thickness at the apex and at the limbus, mm */
    double wtw;                     /* white-to-white (corneal) diameter, mm: the horizontal one */
    double wtw_v;                   /* vertical white-to-white, mm, at most wtw; 0: wtw (a round
                                       cornea). Less than wtw: the oval cornea (kt_eye_warp_oval) */
    double limbus_width;            /* width of the limbal zone, mm */
    double sclera_thickness;        /* scleral thickness at the limbus, mm */
    double globe_radius;            /* outer scleral radius, mm */
    double extent;                  /* polar angle where the model is cut off, deg (180: whole globe) */
    double optical_zone;            /* diameter of the refined central zone, mm */
    double fibre_band;              /* width of the band inside the corneal edge over which the
                                       lamellae turn circumferential, mm (eye.fibres) */
    double fibre_density;           /* circumferential fibril density at the limbus relative to
                                       the central cornea (eye.fibres.limbal_density) */
    double h_optical, h_incision, h_cornea, h_sclera; /* element sizes, mm */
    double h_floor;                 /* size at the rings' floor (the crack front of an incision),
                                       mm; 0: no floor refinement (eye.mesh_size.incision_floor) */
    double floor_grading;           /* the size's growth away from the floor, mm per mm
                                       (eye.mesh_size.floor_grading); 0: KT_EYE_FLOOR_GRADING */
    double floor_centre, floor_sector; /* the floor is refined within floor_sector deg of the
                                       meridian floor_centre and its opposite (the scene's
                                       ordering.centre/sector); sector 0 or >= 90: all around */
    double site_meridian, site_distance, site_radius; /* a site meshed at h_incision: the
                                       vertical cylinder of site_radius around the point at
                                       site_distance from the axis on site_meridian (the main
                                       incision's tunnel; eye.mesh_size.site); radius 0: none */
    int nring;
    kt_ring ring[KT_SCENE_MAX];
    kt_eye_departure dep_ant, dep_post; /* the measured surfaces' departures from the base ones
                                       (eye_depart.h; eye.anterior_departure, posterior_departure);
                                       order 0: none */
} kt_eye;

/* The floor's size slope of eye (mm per mm): floor_grading, or KT_EYE_FLOOR_GRADING when 0. */
static inline double kt_eye_floor_slope(const kt_eye *eye)
{
    return eye->floor_grading > 0 ? eye->floor_grading : KT_EYE_FLOOR_GRADING;
}

typedef struct kt_eye_geom {
    double cs, cf;          /* steep and flat anterior curvatures, 1/mm */
    double cos_ax, sin_ax;  /* steep meridian direction (TABO angle) */
    double Ra;              /* mean anterior radius: 1/Ra = (cs + cf)/2 */
    double rc, rL;          /* radial distance of the corneal edge and of the limbus outer edge */
    double Rg, Ri;          /* outer and inner scleral radii */
    double z_apex, z_ca;    /* apex height, anterior sphere centre height */
    double phic;            /* half-angle at Ca of the cone through the corneal edge */
    double alphaL, alphaX;  /* polar angles (about the origin) of the limbus edge and model cut */
    double E[2], Pp[2], Lo[2], Li[2], So[2], Si[2]; /* profile points (rho, z) */
    double z_pv, Rp, k;     /* posterior vertex height, apical radius, k = 1 + Q (conic) */
    double cp_half;         /* half the posterior's apical curvature difference, 1/mm */
    double cos_pax, sin_pax; /* its steep meridian direction */
    double taper_in, taper_out; /* the posterior warp's taper: whole within rho <= taper_in,
                               none beyond taper_out (= Pp[0], where the posterior cornea
                               meets the limbus) */
    int whole;              /* extent = 180 deg: closed globe, no rim */
    int oval;               /* wtw_v < wtw: the corneal edge is the ellipse of semi-axes rc, rv */
    double rv;              /* vertical semi-axis of the corneal edge (rc when round) */
    double ov_r0, ov_r1;    /* the oval warp's ramp: no move within ov_r0 (optical_zone / 2),
                               the whole move from ov_r1 on */
    double ov_xb;           /* from here (rc - limbus_width / 2, the last ring) to the corneal
                               edge the posterior's share of the move falls to 0 */
} kt_eye_geom;

/* Derive and validate the geometry; inconsistent dimensions are KT_EINPUT. */
int kt_eye_geom_init(const kt_eye *eye, kt_eye_geom *g, kt_err *e);

/* The exact toric (biconic) anterior corneal surface height at (x, y); NAN where undefined. */
double kt_eye_geom_toric_z(const kt_eye_geom *g, double x, double y);
/* The rotationally symmetric base surfaces: mean anterior sphere, posterior conic, globe. */
double kt_eye_geom_sphere_z(const kt_eye_geom *g, double rho);
double kt_eye_geom_post_z(const kt_eye_geom *g, double rho);
double kt_eye_geom_globe_z(const kt_eye_geom *g, double rho);

/* The toric posterior warp's height change at (x, y) (mm, to add to the base posterior's z):
 * the posterior conic with the meridian's apical curvature 1/Rp + cp_half cos 2(theta - axis)
 * and the base's conic constant, less the base conic, times the taper (1 for rho <= taper_in,
 * a half cosine down to 0 at taper_out, 0 beyond); 0 for a posterior of revolution. */
double kt_eye_geom_post_delta(const kt_eye_geom *g, double x, double y);

/* Thickness of the base geometry at radial distance r: along the anterior normal in the
 * cornea, along the globe radius in the limbus, the sclera thickness beyond. */
double kt_eye_geom_thickness(const kt_eye_geom *g, double r);

/* Weight of the toric warp at a base-geometry point: 1 on the anterior corneal surface,
 * falling linearly to 0 at the posterior cornea, across the limbus to its scleral border. */
double kt_eye_geom_weight(const kt_eye_geom *g, double rho, double z);

/* Relative height of a base-geometry point through the thickness: 1 on the anterior (outer)
 * surface, 0 on the posterior (inner) one; in the cornea along the ray from the anterior
 * sphere's centre (as kt_eye_geom_weight), in the limbus the quad's outer coordinate; NAN in
 * the sclera. Clamped to [0, 1]. */
double kt_eye_geom_height(const kt_eye_geom *g, double rho, double z);

/* Height of the outer surface of cornea and limbus after the warp (the "anterior z"). */
double kt_eye_geom_outer_z(const kt_eye_geom *g, double x, double y);

/* A ring's profile segment: top point on the outer surface, unit direction into the tissue
 * (anterior normal in the cornea, globe radius in the limbus), depth. KT_EINPUT with the
 * ring's name when it lies outside cornea and limbus, in the optical zone, or too deep. */
int kt_eye_geom_ring(const kt_eye_geom *g, const kt_eye *eye, int i, double top[2],
                     double dir[2], double *depth, kt_err *e);

/* Height of the anterior surface over (x, y) and the corneal thickness at radial distance r
 * (mm) of the eye with these parameters; NAN when the parameters are inconsistent. */
double kt_eye_anterior_z(const kt_eye *eye, double x, double y);
double kt_eye_thickness(const kt_eye *eye, double r);

/* The oval cornea (keratome-scene(5), THE OVAL CORNEA). A base-geometry point of cornea or
 * limbus has shell coordinates (xi, h): h its relative height (1 on the outer surface, 0 on the
 * inner one; in the cornea along the ray from the anterior sphere's centre, in the limbus across
 * the quad whose outer side is the globe arc E-Lo), xi its position along the shell (in the
 * cornea the projected radius rho where its ray meets the anterior sphere, so a ring of
 * revolution has one xi; in the limbus rc + u (rL - rc), u across the quad). The warp moves a
 * point in its own meridian t from xi to xi + kt_eye_geom_oval_shift(xi, h, t), h kept: from
 * ov_r1 to the corneal edge the outer surface's point at xi lands on the ellipse of semi-axes
 * xi (horizontal) and xi - (rc - rv) (vertical), so the corneal edge lands on the white-to-white
 * ellipse and every ring lies at the same distance inside it in every meridian; the move ramps
 * linearly from 0 at ov_r0; near the edge the inner surface's share falls to 0 (the posterior
 * corneal boundary stays circular); across the limbus it falls to 0 at the limbus's outer edge.
 * 0 for a round eye and outside (ov_r0, rL). */
double kt_eye_geom_oval_shift(const kt_eye_geom *g, double xi, double h, double c, double s);
/* The radial distance (mm) in the meridian (cos t, sin t) = (c, s) of the outer surface's point
 * at horizontal-equivalent xi after the oval warp: xi + shift(xi, 1); xi when round. */
double kt_eye_geom_oval_rho(const kt_eye_geom *g, double xi, double c, double s);
/* The radius of the corneal edge (the white-to-white ellipse) in the meridian (c, s). */
double kt_eye_geom_edge_rho(const kt_eye_geom *g, double c, double s);
/* Move the nodes of a mesh of revolution of g by the oval warp (before kt_eye_warp_toric,
 * which takes the result as its base geometry: the warp keeps every surface of revolution
 * on itself). Nothing moves (the same bytes) when g is round; KT_ERUN when a node cannot be
 * mapped. */
int kt_eye_warp_oval(const kt_eye_geom *g, kt_mesh *m, kt_err *e);

/* Map the nodes of a mesh of revolution onto the toric anterior surface of g (mid-edge nodes
 * of the anterior cornea follow the surface) and, when the posterior is toric, onto the toric
 * posterior (kt_eye_geom_post_delta, weighted 1 on the posterior surface down to 0 on the
 * anterior one, tapered to 0 before the limbus: the limbus and sclera do not move);
 * KT_ERUN when a node cannot be mapped. */
int kt_eye_warp_toric(const kt_eye_geom *g, kt_mesh *m, kt_err *e);

/* Puts the mid-edge nodes of every P2 tet whose Jacobian is not positive at a corner or its
 * centre back on their edges' chords (except anterior-surface nodes, which stay on the toric
 * surface); *nstraight: how many nodes moved. Delaunay leaves a few slivers with all four
 * corners on the boundary, which curving to the geometry can invert (mesh-prep(1)). */
int kt_eye_straighten_inverted(kt_mesh *m, int *nstraight, kt_err *e);

/* KT_ERUN naming the tet when a P2 tet's Jacobian is not positive at its corners or centre. */
int kt_eye_check_curved(const kt_mesh *m, kt_err *e);

#endif
