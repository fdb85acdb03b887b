/* patient.h: the patient YAML of lri-plan (man/man5/keratome-patient.5): which eye, age, IOP,
 * the cornea as keratometry or a Pentacam elevation export, the posterior cornea (measured or
 * the documented population default), pachymetry, white-to-white, the main cataract incision,
 * the target and the constraints on the arcs; and the patient's eye scene.
 *
 * Angles: TABO, degrees counter-clockwise from the examiner's right as the surgeon faces the
 * patient (+x of the model, lib/model/eye.h), for both eyes. The examiner's right is the
 * patient's left: nasal for a right eye (OD), temporal for a left eye (OS). So the temporal
 * meridian is 180 deg in OD and 0 deg in OS; superior is 90 deg in both. */
#ifndef KT_PATIENT_H
#define KT_PATIENT_H

#include "pentacam.h"
#include "scene.h"

enum { KT_EYE_OD = 0, KT_EYE_OS = 1 };
enum { KT_SOURCE_DEFAULT = 0, KT_SOURCE_KERATOMETRY, KT_SOURCE_PENTACAM };
enum { KT_MAIN_CLEAR_CORNEAL = 0, KT_MAIN_LIMBAL };
enum { KT_TARGET_TOTAL = 0, KT_TARGET_KERATOMETRIC };
enum { KT_ARCS_EITHER = 0, KT_ARCS_SINGLE, KT_ARCS_PAIRED };

/* Population and convention defaults (sources in keratome-patient(5)). */
#define KT_PATIENT_IOP_MMHG 15.0      /* Klein et al. 1992 (Beaver Dam Eye Study) */
#define KT_PATIENT_POST_RADIUS 6.7    /* mm, mean posterior apical radius (keratome-scene(5)) */
/* The default posterior astigmatism (D) follows the anterior keratometric cylinder C (D) by the
 * regressions of Eom et al. 2015 (928 eyes, by the anterior steep meridian's class):
 * with the rule 0.15 C + 0.22, oblique 0.05 C + 0.27, against the rule 0.27 (C not
 * significant); its steep meridian vertical (Koch et al. 2012: 86.6% of eyes). */
#define KT_PATIENT_POST_WTR_SLOPE 0.15
#define KT_PATIENT_POST_WTR_D 0.22
#define KT_PATIENT_POST_OBL_SLOPE 0.05
#define KT_PATIENT_POST_OBL_D 0.27
#define KT_PATIENT_POST_ATR_D 0.27
#define KT_PATIENT_POST_AXIS 90.0     /* deg, posterior steep meridian vertical, Koch et al. 2012 */
#define KT_PATIENT_N_POST 40.0        /* D mm: 1000 (1.376 - 1.336), posterior surface power */
#define KT_PATIENT_DEPTH_MAX 0.9      /* deepest blade setting, fraction of the pachymetry */
/* What the patient file accepts (keratome-patient(5)); lri-nomogram(1) accepts the same. An
 * axis lies in [0, 180] deg, 180 read as 0 (TABO). */
#define KT_PATIENT_AGE_MIN 18.0       /* years: adult eyes; the age rule's range */
#define KT_PATIENT_AGE_MAX 110.0
#define KT_PATIENT_K_MIN 20.0         /* D, anterior keratometry */
#define KT_PATIENT_K_MAX 70.0
#define KT_PATIENT_SIA_MAX 5.0        /* D, the surgeon's SIA magnitude */
#define KT_PATIENT_ZONE 10.5          /* mm, the incision zone, peripheral clear cornea (Nichamin
                                         2006); at most white_to_white - 1 mm when not given */

/* A toric surface at its apex: radii of the steep and flat meridians, the steep meridian,
 * the conic constant Q (NAN: not measured), and where the values came from. */
typedef struct kt_toric {
    double r_steep, r_flat;     /* mm */
    double axis;                /* deg, 0 <= axis < 180 */
    double conic;               /* Q (asphericity), NAN when not fitted */
    int source;                 /* KT_SOURCE_* */
} kt_toric;

/* The patient file's fields whose position a later refusal names (kt_patient_fail). */
enum {
    KT_PF_FILE = 0, KT_PF_EYE, KT_PF_AGE, KT_PF_CORNEA, KT_PF_KERATOMETRY, KT_PF_POSTERIOR, KT_PF_FRONT, KT_PF_BACK,
    KT_PF_PACHYMETRY, KT_PF_CENTRAL, KT_PF_T_ZONE, KT_PF_WTW, KT_PF_MAIN, KT_PF_ZONE, KT_PF_DEPTH, KT_PF_N
};

typedef struct kt_patient {
    char path[1024], dir[1024];
    int mark[KT_PF_N][2];       /* line and column of each KT_PF_* field in the file; 0 0: absent */
    char name[KT_NAME_MAX];
    char id[KT_NAME_MAX];       /* the patient's identifier; "" when not given */
    char dob[11];               /* date of birth, YYYY-MM-DD; "" when not given */
    char surgeon[KT_NAME_MAX];  /* "" when not given */
    int eye;                    /* KT_EYE_OD or KT_EYE_OS */
    double age;                 /* years */
    double iop;                 /* MPa */
    kt_toric ant, post;         /* anterior (keratometric index) and posterior corneal surfaces */
    char pentacam_front[1024], pentacam_back[1024], pentacam_pachy[1024]; /* "" when absent;
                                   resolved against the patient file's folder */
    double t_central;           /* central pachymetry, mm */
    double t_zone;              /* pachymetry at the incision zone, mm; NAN: from the model */
    double wtw;                 /* white-to-white, mm: horizontal */
    double wtw_v;               /* vertical white-to-white, mm (at most wtw) */
    int main_present;           /* a main incision is given */
    double main_meridian;       /* its site, deg TABO, 0 <= m < 360 */
    double main_width;          /* mm */
    int main_kind;              /* KT_MAIN_* */
    int main_simulate;          /* 1: cut in the model; 0: the surgeon's SIA vector below */
    double main_sia, main_sia_axis; /* D, deg */
    int side_present;           /* a side port (paracentesis) is given */
    double side_meridian;       /* its site, deg TABO, 0 <= m < 360 */
    double side_width;          /* mm */
    int target_kind;            /* KT_TARGET_* */
    double target_residual;     /* D */
    int arcs;                   /* KT_ARCS_* */
    double max_arc;             /* deg */
    double zone;                /* incision zone diameter, mm */
    double clearance;           /* deg at the zone: the least gap between an arc and a wound
                                   (KT_CLEARANCE_DEG, clearance.h) */
    double depth_fraction;      /* fraction of the pachymetry at the zone, or 0 ... */
    double depth;               /* ... the blade depth, mm */
} kt_patient;

/* Load and validate a patient file; bad input is KT_EINPUT "file:line:col: expected ...".
 * A Pentacam cornea leaves ant (and post, t_central when the export has them) to be filled
 * from the fit (lib/optics/surffit.h) by the caller. */
int kt_patient_load(const char *path, kt_patient *p, kt_err *e);

/* Record KT_EINPUT "PATIENT:line:col: FIELD: message" at the patient file's field `field`
 * (KT_PF_*), or at the first of the fallbacks (-1 ends the list) that the file has, else at
 * 1:1; returns it. Every refusal a patient file causes after it loads goes through here, so it
 * names the file, the line, the column and the field. */
int kt_patient_fail(const kt_patient *p, kt_err *e, int field, int fallback, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));

/* One of the patient's Pentacam maps (KT_PF_FRONT, KT_PF_BACK, KT_PF_PACHYMETRY), read with the
 * patient file's range for its values (pachymetry: 300-1200 um, the range of central_thickness
 * and thickness_at_zone) and its header checked against the patient file: the eye (an OD export
 * for an `eye: OS` patient is refused at the header's line and column), the kind and surface
 * (a back elevation named as the front map, a pachymetry as an elevation) and the unit (mm for
 * elevations, um for pachymetry). The grid is the reader's check. KT_EINPUT on any of it. */
int kt_patient_read_map(const kt_patient *p, int field, kt_pentacam_map *m, kt_err *e);

/* After the fits: the fitted anterior keratometry within the patient file's range for
 * keratometry (20-70 D), the posterior within [-15, -2] D and its mean radius smaller than the
 * anterior's (else the maps are swapped), the fitted central pachymetry within 300-1200 um;
 * each refusal at the map's field. post_fit / pachy_fit: 1 when those maps were fitted. */
int kt_patient_check_fit(const kt_patient *p, int post_fit, int pachy_fit, kt_err *e);

/* The pachymetry at the incision zone (mm) of the default eye's thickness profile
 * (keratome-scene(5): peripheral_thickness 670 um at the limbus) with the patient's cornea,
 * central thickness and white-to-white: the value used when cornea.thickness_at_zone is not
 * given; NAN when those do not make an eye. */
double kt_patient_model_zone_thickness(const kt_patient *p);

/* Keratometric power of a radius, D (index 1.3375), and the posterior surface power, D (< 0). */
double kt_patient_k(double r);
double kt_patient_post_k(double r);

/* *post := the population posterior cornea of an eye whose anterior is *ant (keratome-patient(5),
 * posterior): mean radius KT_PATIENT_POST_RADIUS, steep meridian KT_PATIENT_POST_AXIS, and a
 * cylinder by the anterior keratometric cylinder C = K(r_steep) - K(r_flat) and the class of
 * ant->axis: with the rule (60-120 deg) 0.15 C + 0.22 D, against the rule (0-30, 150-180 deg)
 * 0.27 D, oblique 0.05 C + 0.27 D (Eom et al. 2015); source KT_SOURCE_DEFAULT, conic NAN.
 * kt_patient_load applies it to keratometry; a caller that fits the anterior later (a Pentacam
 * front without a back) applies it after the fit (kt_patient_scene does so for the mesh). */
void kt_patient_default_posterior(const kt_toric *ant, kt_toric *post);

/* The eye meridian (deg TABO) of a named site for this eye: "temporal", "nasal", "superior",
 * "inferior", "superotemporal", "superonasal", "inferotemporal", "inferonasal"; NAN when the
 * name is none of those. */
double kt_patient_site(int eye, const char *name);

/* The patient's scene: base (an eye scene, e.g. plans/eye.yaml) with the patient's anterior
 * radii and axis, the posterior mean radius, central thickness, the peripheral thickness that
 * gives the pachymetry at the zone, white-to-white, IOP, one incision ring at the zone and
 * depth, the cornea and limbus moduli scaled by the age rule (keratome-patient(5)), and the
 * ordering centred on the steep meridian. KT_EINPUT when the values do not make an eye. */
int kt_patient_scene(const kt_patient *p, const kt_scene *base, kt_scene *s, kt_err *e);

/* The chord (mm, seen from the front) of an arc centred on `centre` of `arc` degrees at the
 * patient's incision zone: on the zone's curve of the patient's eye (kt_eye_oval_radius: the
 * zone follows the oval cornea), with the default eye's optical zone and limbus; NAN when the
 * values do not make an eye. */
double kt_patient_zone_chord(const kt_patient *p, double centre, double arc);

/* The age rule's stiffness factor: 1 + 0.075 (age - 60) / 10 (plans/studies/nomogram). */
double kt_patient_age_factor(double age);

#endif
