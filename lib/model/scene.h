/* scene.h: the scene YAML (geometry, regions, materials, loads, fixation, meshing, ordering). */
#ifndef KT_SCENE_H
#define KT_SCENE_H

#include "eye_geom.h"
#include "mesh.h"
#include "order.h"

/* Internal units: mm, MPa, N, degrees. The YAML gives quantities as "7.8 mm", "540 um",
 * "15 mmHg", "0.3 MPa", "90 deg"; every default is documented in man/man5/keratome-scene.5
 * with its literature source. */

enum { KT_MODEL_EYE = 1, KT_MODEL_BOX, KT_MODEL_SURFACE, KT_MODEL_IMAGE };
/* What the scene's geometry is (loads.reference): the measured shape under the scene's loads
 * (mesh-prep then computes the stress-free shape, lib/fem/refgeom.h), or already stress-free.
 * Or (prestressed) the measured shape under the loads, taken as it is: the solvers linearize
 * about it with the stress the loads cause in it (lib/fem/physics.h), and no stress-free shape
 * is computed. */
enum { KT_REFERENCE_LOADED = 0, KT_REFERENCE_UNLOADED = 1, KT_REFERENCE_PRESTRESSED = 2 };

/* Box (the paper's beams and brick): nodes n[3] over lengths len[3], mm. */
typedef struct kt_box {
    int n[3];
    double len[3];
    int fixed_face;             /* face renamed "fixed": 0..5 = xmin xmax ymin ymax zmin zmax, -1 none */
} kt_box;

/* Surface mesh (OFF/STL) or labelled image (INR) meshed with CGAL. */
typedef struct kt_cgal {
    char path[1024];            /* resolved relative to the scene file */
    double facet_size, cell_size, facet_distance; /* mm */
    int target_nodes;           /* if > 0, sizes are scaled to reach about this many nodes */
    double unit;                /* mm per file unit: the mesh is scaled by it (default 1) */
} kt_cgal;

typedef struct kt_region_mat {
    char region[KT_NAME_MAX];
    double E, nu;               /* MPa, - (isotropic; fibre: nu of the lamellar matrix) */
    int fibre;                  /* model: 0 isotropic, 1 fibre (lamellar, eye only) */
    double E1, E2, Gt;          /* fibre: in-plane moduli along a1 (nasal-temporal centrally)
                                   and a2, transverse shear modulus, MPa */
    double gt_profile[3];       /* fibre: G_transverse_profile, the transverse shear of the
                                   anterior, middle and posterior thirds of the thickness as
                                   measured, MPa; only their ratios are used (kt_gt_profile);
                                   all 0: off, Gt through the whole depth (the default) */
} kt_region_mat;

/* The Petsche et al. 2012 thirds (torsion, human stroma): 7.71 / 1.99 / 1.31 kPa, in MPa
 * (G_transverse_profile: on). */
#define KT_GT_PROFILE_PETSCHE {7.71e-3, 1.99e-3, 1.31e-3}

/* The transverse shear modulus of a tet of region r at relative depth s (0 at the anterior or
 * outer surface, 1 at the posterior or inner one; NAN outside cornea and limbus): r->Gt when
 * the profile is off or s is NAN, else r->Gt * gt_profile[third(s)] / H, H the harmonic mean of
 * the three: the layers in series (a full-thickness torsion test, a uniform transverse shear
 * stress) see r->Gt, as without the profile. Thirds: s < 1/3, s < 2/3, else. */
double kt_gt_profile(const kt_region_mat *r, double s);

typedef struct kt_pressure {
    char surface[KT_NAME_MAX];
    double p;                   /* MPa (YAML may say mmHg or kPa) */
} kt_pressure;

typedef struct kt_fixation {
    char surface[KT_NAME_MAX];
    unsigned mask;              /* bit c set: component c fixed */
    double value[3];            /* prescribed displacement, mm */
    int below_axis;             /* -1, or 0..2: mesh-prep creates group 'surface' from the */
    double below_value;         /* boundary triangles with every vertex at axis <= value (mm) */
} kt_fixation;

/* The uncertain quantities of the scene's `uncertainty:` section (keratome-scene(5),
 * UNCERTAINTY; lib/model/scene_unc.c holds their names, units, default standard deviations and
 * sources). */
enum { KT_UQ_E_INPLANE = 0, KT_UQ_G_TRANSVERSE, KT_UQ_IOP, KT_UQ_LIMBAL_DENSITY, KT_UQ_THICKNESS,
       KT_UQ_DEPTH, KT_UQ_AGE_SLOPE, KT_UQ_HEAL, KT_UQ_N };
enum { KT_UQ_NORMAL = 0, KT_UQ_UNIFORM };

typedef struct kt_uncertainty {
    double sd[KT_UQ_N];         /* standard deviation in the quantity's unit (kt_uq_unit) */
    int dist[KT_UQ_N];          /* KT_UQ_NORMAL or KT_UQ_UNIFORM (given by its sd) */
    double age;                 /* years: the age the cornea's moduli were scaled for
                                   (age_slope.age, lri-plan's patient), NAN: not age-scaled */
    double nontissue_cv;        /* the SIA's spread that no tissue quantity carries (healing
                                   variability, blade depth, keratometry), as a coefficient of
                                   variation of the SIA along itself (default
                                   KT_UQ_NONTISSUE_CV) */
} kt_uncertainty;
/* The non-tissue coefficient of variation: the clinical spread of the SIA (the pooled cv of the
 * spread rows of share/outcomes/lri-outcomes.tsv, 0.544) less the tissue band's median on the
 * training arms (0.206), in quadrature, by the calibration study (plans/studies/calibrate;
 * docs/validation.md, 8 December 2026, lri-plan's default mesh). */
#define KT_UQ_NONTISSUE_CV 0.503

/* The quantity's key, unit (as uncertainty.tsv writes it), default sd, source key. */
const char *kt_uq_name(int q);
const char *kt_uq_unit(int q);
double kt_uq_default_sd(int q);
const char *kt_uq_source(int q);
/* The age rule of lri-plan (kt_patient_age_factor): the cornea's moduli times
 * 1 + KT_UQ_AGE_SLOPE_VALUE (age - 60) / 10 (Li et al. 2024: +0.30 MPa per decade on 4.0). */
#define KT_UQ_AGE_SLOPE_VALUE 0.075
#define KT_UQ_AGE_PIVOT 60.0

/* The wound's state (keratome-scene(5), WOUND; docs/physics.md, "Healing"): immediate (the
 * elastic opening at the instant of cutting: no bridge) or healed (a scar of stiffness per area
 * k across every cut face pair, lib/fem/wound.h). k = bridge_stiffness
 * exp(-age_rate (age - KT_WOUND_AGE_PIVOT)) (1 - exp(-months / heal_time)) (the last factor 1
 * when months is not given: the asymptotic scar). */
enum { KT_WOUND_IMMEDIATE = 0, KT_WOUND_HEALED };
typedef struct kt_wound_scene {
    int state;                  /* KT_WOUND_* (default immediate) */
    double bridge_stiffness;    /* MPa/mm (N/mm^3): k of a healed wound at the pivot age */
    double age_rate;            /* 1/y: k falls by exp(-age_rate) per year of age */
    double age;                 /* y: the patient's age; NAN: the scene's age_slope age
                                   (lri-plan's patient), else the pivot */
    double months;              /* months after surgery; NAN: the asymptotic (healed) scar */
    double heal_time;           /* months: time constant of the scar's stiffening */
} kt_wound_scene;

/* Defaults identified by the calibration study (plans/studies/calibrate, 8 December 2026, on
 * share/outcomes/lri-outcomes.tsv sha256 2bab46b9263bc1a5... (docs/validation.md gives it whole); lri-plan's
 * default mesh, the one it plans on): the Laplace posterior's means, ln k60 = -1.764 +- 0.314
 * (k60 0.1713 MPa/mm) and the fall of ln k 0.057 +- 0.060 per decade of age (0.0057 /y; correlation 0.28; the prior
 * 0.06 +- 0.06 from the keratocyte density's decline, Moller-Pedersen 1997, Niederer 2007, which
 * the two studies' ages of 69 and 76 y barely move); heal_time the scar's stiffening (Gasset and
 * Dohlman 1968: no measurable strength for 12 days, a slow gain over 100 days), not identified
 * (the outcomes show no regression after day 1). */
#define KT_WOUND_K_DEFAULT 0.1713
#define KT_WOUND_AGE_RATE_DEFAULT 0.0057
#define KT_WOUND_HEAL_TIME_DEFAULT 1.5
#define KT_WOUND_AGE_PIVOT 60.0

typedef struct kt_scene {
    char path[1024], dir[1024]; /* the file and its folder */
    char name[KT_NAME_MAX];
    int model;                  /* KT_MODEL_* */
    int order;                  /* element order, 1 or 2 */
    int ordering;               /* KT_ORDERING_* */
    char ordering_set[KT_NAME_MAX]; /* surface group put last by the constrained ordering */
    int ordering_halo;          /* layers of tet neighbours added to that set (eye 2, else 1) */
    double ordering_sector;     /* eye: only incision-ring nodes within this angle (deg) of the
                                   centre meridian or its opposite join the set; NAN: all */
    double ordering_centre;     /* eye: the set's nodes nearest this meridian (deg, and the
                                   opposite one) are ordered last of all; NAN: no sweep */
    kt_eye eye;
    kt_box box;
    kt_cgal cgal;
    int nmat;
    kt_region_mat mat[KT_SCENE_MAX];
    int npressure;
    kt_pressure pressure[KT_SCENE_MAX];
    int nfix;
    kt_fixation fix[KT_SCENE_MAX];
    int reference;              /* KT_REFERENCE_* (loads.reference; default loaded) */
    double reference_tol;       /* mm: shape tolerance of the stress-free iteration
                                   (loads.reference_tolerance; default 3e-5 mm) */
    kt_uncertainty unc;         /* uncertainty: (defaults when absent) */
    kt_wound_scene wound;       /* wound: (defaults when absent) */
} kt_scene;

/* The bridge stiffness per area the scene's wound has, MPa/mm: 0 for an immediate wound. */
double kt_scene_wound_k(const kt_scene *s);
/* The same as if the state were healed (what heal = ln k would be; kt_fem_sens_plan). */
double kt_scene_wound_k_healed(const kt_scene *s);
/* The age it was taken at, y (wound.age, else the age_slope age, else the pivot). */
double kt_scene_wound_age(const kt_scene *s);


/* Load and validate a scene file. Unknown keys, duplicate keys, wrong types, missing or
 * unknown units and out-of-range values are KT_EINPUT with "file:line:col: expected ...". */
int kt_scene_load(const char *path, kt_scene *s, kt_err *e);

#endif
