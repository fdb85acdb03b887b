/* curv.h: simulated keratometry of a deformed anterior corneal surface.
 *
 * Frame (lib/model/eye.h): optical axis +z, seen from the front x right and y up; meridian t (deg,
 * TABO: counter-clockwise from +x) is the direction (cos t, sin t). Powers use the keratometric
 * index n = 1.3375: K = (n - 1) / R = 337.5 / R(mm) dioptres.
 *
 * Pipeline per step: kt_curv_extract (anterior nodes of a step mesh, deformed) -> kt_curv_fit
 * (a surface z = f(x, y) over a central zone, apex found by the fit) -> kt_curv_simk (steep and
 * flat K, axis, cylinder from the zone-averaged axial power of each meridian) -> against step 0:
 * kt_curv_alpins (vector analysis). lib/app/curvature_run.c drives a whole run folder. */
#ifndef KT_CURV_H
#define KT_CURV_H

#include "mesh.h"
#include "units.h"
#include "vtk.h"
#include "zernike.h"

#define KT_CURV_N_KERATO KT_N_KERATO /* 1000 (n - 1), n = 1.3375 keratometric index: D * mm */
#define KT_CURV_PI KT_PI
#define KT_CURV_DEG (KT_CURV_PI / 180)

/* ---- surface extraction (curv_surf.c) ---- */

/* The anterior surface of one step: nodes whose origin is in the mesh's "anterior" group. */
typedef struct kt_surf {
    int n;            /* anterior nodes */
    double *xyz;      /* 3n deformed positions (reference + displacement), mm */
    double *disp;     /* 3n displacements, mm */
    int *node;        /* n node numbers in the step mesh (0-based) */
    int *origin;      /* n input-mesh node numbers (1-based, as in the VTK field) */
    int ntri;
    int *tri;         /* 3 ntri indices into 0..n-1: boundary faces with all vertices anterior,
                       * oriented outwards; a 10-node tet's face gives four triangles */
} kt_surf;

/* mask[i] = 1 when input-mesh node i (0-based) is on the surface group "anterior"; *mask has
 * m->nn entries and is the caller's. A mesh without that group is KT_EINPUT naming `what`. */
int kt_curv_anterior_mask(const kt_mesh *m, const char *what, unsigned char **mask, kt_err *e);

/* The anterior surface of a step VTK (tets with POINT_DATA displacement and origin). A missing
 * field or an origin out of 1..mesh_nn is KT_EINPUT naming `what`. */
int kt_curv_extract(const kt_vtk *v, const char *what, const unsigned char *mask, int mesh_nn,
                    kt_surf *s, kt_err *e);
/* The in-memory entry (no step file): the points of step mesh m with displacement u (3 nn, mm)
 * whose input-mesh node origin[i] (0-based, < mesh_nn) has mask set: the same n, xyz, disp,
 * node and origin (1-based) as kt_curv_extract gives from the step's VTK, without the
 * triangles (ntri 0, tri NULL). A node without a surface node is KT_ERUN. */
int kt_curv_points(const kt_mesh *m, const double *u, const int *origin, const unsigned char *mask, int mesh_nn,
                   kt_surf *s, kt_err *e);
void kt_surf_free(kt_surf *s);

/* ---- fits (curv_fit.c) ---- */

enum { KT_FIT_ZERNIKE = 1, KT_FIT_TORIC, KT_FIT_ZERNIKE_AT };

/* A fitted surface z = f(x, y) over a disk of radius a (mm). Zernike: sag expanded in Zernike
 * polynomials (OSA/ANSI order) of (x - xc, y - yc) / a up to `order`, kept as monomials too.
 * Toric: z = z0 - q1 / (1 + sqrt(1 - (1 + conic) q2)) with d = (x - xc, y - yc),
 * q1 = d'Md, q2 = d'M^2 d (a biconic sharing one conic constant; M = diag(1/R1, 1/R2) rotated
 * to the principal axes). The apex (ax, ay), where the surface normal is the axis +z, is the
 * axis of axial power and keratometry; the fit is re-centred there (decentration and tilt).
 * KT_FIT_ZERNIKE_AT: the Zernike fit about (cx, cy) as given, not re-centred (a departure from a
 * reference surface, which has no apex: lib/optics/surffit.h); ax, ay = cx, cy. */
typedef struct kt_fit {
    int kind;
    double xc, yc;          /* fit centre, mm */
    double ax, ay, az;      /* apex, mm */
    double a;               /* zone radius, mm */
    int order, nterms;      /* Zernike */
    double zern[KT_ZERN_TERMS_MAX];                           /* Zernike coefficients, mm */
    double poly[(KT_ZERN_ORDER_MAX + 1) * (KT_ZERN_ORDER_MAX + 1)]; /* u^i v^j at [i*13+j] */
    double m11, m12, m22, conic, z0;                          /* toric, 1/mm, -, mm */
    int npts;               /* points in the zone */
    double rms;             /* residual RMS, mm */
} kt_fit;

/* Fit the points xyz (n of them) inside the disk of diameter zone_d (mm) centred first at
 * (cx, cy), then re-centred on the fitted apex. Zernike order is lowered, with a message in
 * *note (may be NULL), when the zone holds fewer than 3 points per term; fewer than 12 points
 * is KT_ERUN. */
int kt_curv_fit(const double *xyz, int n, int kind, int order, double zone_d, double cx,
                double cy, kt_fit *f, char *note, size_t note_len, kt_err *e);

/* Height and gradient of the fitted surface at (x, y), mm. */
void kt_fit_eval(const kt_fit *f, double x, double y, double *z, double *zx, double *zy);

/* Axial (sagittal) power in D at (x, y): (n - 1) sin(t) / r, t the angle between the surface
 * normal and the axis through the apex, r the distance from that axis; at the apex the limit,
 * the mean normal curvature. */
double kt_fit_axial_power(const kt_fit *f, double x, double y);

/* Best-fit sphere of n points (algebraic least squares): centre c[3] and radius, mm. */
int kt_curv_sphere_fit(const double *xyz, int n, double c[3], double *radius, kt_err *e);

/* ---- keratometry (curv.c) ---- */

/* Simulated keratometry's defaults (curvature(1): --zone, --fit, --order): a toric fit over the
 * central 3 mm, the zone of a keratometer's mires; a Zernike fit's order. lri-plan reads its
 * eyes with the same. */
#define KT_CURV_ZONE_DEFAULT 3.0
#define KT_CURV_FIT_DEFAULT KT_FIT_TORIC
#define KT_CURV_ORDER_DEFAULT 6

#define KT_CURV_NMERID 90   /* meridians sampled over 0..180 deg for the double-angle analysis */

/* Simulated keratometry over the fit's zone. K(t) is the axial power averaged over the zone's
 * meridian t (both half-meridians, area-weighted: int P r dr / int r dr); the steep axis is
 * the phase of the second harmonic of K(t); K steep = K(axis), K flat = K(axis + 90). */
typedef struct kt_kerato {
    double k_steep, k_flat;   /* D */
    double axis_steep;        /* deg, 0 <= axis < 180 */
    double cyl;               /* k_steep - k_flat, D */
    double k_mean;            /* (k_steep + k_flat) / 2, D */
    double kmer[KT_CURV_NMERID]; /* K at meridians 0, 2, ..., 178 deg */
} kt_kerato;

void kt_curv_simk(const kt_fit *f, kt_kerato *k);

/* The meridian (deg, 0 <= axis < 180) where the second harmonic of v (KT_CURV_NMERID values
 * at meridians 0, 2, ..., 178 deg) peaks. */
double kt_curv_harmonic_axis(const double *v);

/* Zone-averaged axial power of meridian t (deg), D. */
double kt_curv_meridian_k(const kt_fit *f, double t);

/* ---- vector analysis (curv_vec.c) ---- */

/* Astigmatism as a magnitude (D, plus cylinder at its steep meridian) and axis (deg). */
typedef struct kt_astig {
    double mag, axis;
} kt_astig;

/* Double-angle components (mag cos 2a, mag sin 2a) and back (axis in 0 <= axis < 180). */
void kt_astig_xy(kt_astig a, double xy[2]);
kt_astig kt_astig_from_xy(double x, double y);

/* Alpins vector analysis (Alpins 1993, J Cataract Refract Surg 19:524; Alpins 2001, JCRS
 * 27:31). SIA = post - pre in double-angle space. With a target induced astigmatism (TIA):
 * DV = TIA - SIA (what the surgery missed: the target minus the achieved astigmatism),
 * correction index CI = |SIA| / |TIA|, angle of error AE = axis(SIA) - axis(TIA) wrapped to
 * (-90, 90] (positive: counter-clockwise), magnitude of error ME = |SIA| - |TIA|, index of
 * success IOS = |DV| / |TIA|. Without a target those are NaN. */
typedef struct kt_alpins {
    kt_astig sia, tia, dv;
    double ci, ae, me, ios;
} kt_alpins;

void kt_curv_alpins(kt_astig pre, kt_astig post, const kt_astig *tia, kt_alpins *out);

#endif
