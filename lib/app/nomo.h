/* nomo.h: inverse planning from a simulated nomogram (the nomogram.tsv of the nomogram study,
 * plans/studies/nomogram): given an eye's keratometry, age and the cylinder to correct, the arc
 * of one incision and of a pair that the simulated cases say induce it, with the predicted
 * residual cylinder. See lri-nomogram(1). */
#ifndef KT_NOMO_H
#define KT_NOMO_H

#include "util.h"
#include "units.h"
#include "patient.h"

/* One simulated case: one arc of one run of the study. */
typedef struct kt_nomo_case {
    char eye[64];
    double age;       /* years */
    double cyl_pre;   /* pre-operative cylinder of the simulated eye, D */
    double axis;      /* its steep axis, deg (the incisions are centred there) */
    int incisions;    /* 1 or 2 */
    double arc;       /* deg, of each incision */
    double depth;     /* fraction of the local thickness */
    double diameter;  /* mm */
    double sia;       /* surgically induced astigmatism, D */
    double sia_axis;  /* its axis, deg */
    double sia_sd;    /* the SIA's first-order sd, D (column sia_sd_D: the study's runs with
                         augsolve --uncertainty, curvature's sia_D_sd); NAN: the table has none */
    int line;         /* its line in the table (1: the header) */
} kt_nomo_case;

/* The table: every case of a nomogram.tsv. */
typedef struct kt_nomo {
    kt_nomo_case *c;
    int n;
} kt_nomo;

/* Plausible inputs (lri-nomogram(1)): what lri-plan's patient file accepts (keratome-patient(5),
 * lib/model/patient.h: keratometry in [20, 70] D, an age in [18, 110] y, an SIA in [0, 5] D, an
 * axis in [0, 180] deg with 180 read as 0), a cylinder to correct in (0, 10] D (LRIs treat up
 * to about 3 D). */
#define KT_NOMO_K_MIN KT_PATIENT_K_MIN
#define KT_NOMO_K_MAX KT_PATIENT_K_MAX
#define KT_NOMO_AGE_MIN KT_PATIENT_AGE_MIN
#define KT_NOMO_AGE_MAX KT_PATIENT_AGE_MAX
#define KT_NOMO_SIA_MAX KT_PATIENT_SIA_MAX
#define KT_NOMO_CYL_MAX 10.0
/* The cylinder LRIs treat: about 0.5 to 3.0 D, the range of the LRI nomograms (Nichamin 2006,
 * docs/references.md [7]); outside it lri-nomogram answers with a warning on stderr. */
#define KT_NOMO_LRI_MIN 0.5
#define KT_NOMO_LRI_MAX 3.0
/* The table lri-nomogram reads when none is given: the quick nomogram study's (share/). */
#define KT_NOMO_DEFAULT "nomogram/nomogram.tsv"

/* The two-sided 90% quantile of the standard normal distribution (the band's interval, as
 * curvature's: optics/curv_band.h). */
#define KT_NOMO_Z90 KT_Z90
/* A residual below this (D; the answer prints 0.01 D) has no direction of its own for the band:
 * its derivative is then taken along the pre-operative astigmatism (lri-nomogram(1), BAND). */
#define KT_NOMO_RES_DIR 0.005

/* Limits of a table: bytes in one line (its end included), cases. */
#define KT_NOMO_MAX_LINE 65536
#define KT_NOMO_MAX_CASES 1000000

/* Read a nomogram.tsv (tab-separated, a header naming at least eye, age_y, cyl_pre_D, axis_deg,
 * incisions, arc_deg, depth, diameter_mm, sia_D, sia_axis_deg; optionally sia_sd_D, the SIA's
 * first-order sd: a number >= 0 or NaN; a table without it reads as before, every sd NAN).
 * Bad input: KT_EINPUT with "path:line:col: expected ...". A UTF-8 byte-order mark before the
 * header is skipped. A simulated eye is keyed by all its defining columns (eye, age_y,
 * cyl_pre_D, axis_deg: one name may stand for eyes of several ages), a case by those and
 * incisions, arc_deg, depth, diameter_mm: a header naming a column twice, and a case given
 * twice (its second line named, and the first), are refused. */
int kt_nomo_read(kt_nomo *t, const char *path, kt_err *e);
void kt_nomo_free(kt_nomo *t);

/* The question. depth and diameter <= 0: the deepest depth and the most frequent diameter of
 * the table's cases. */
typedef struct kt_nomo_query {
    double k_steep, k_flat, axis; /* D, D, deg: the keratometry */
    double age;                   /* years */
    double target;                /* the cylinder to correct, D */
    double depth, diameter;
    double main_sia, main_axis;   /* the main incision's SIA vector, D and deg (0: none; the axis of
                                     the induced steepening, as lri-plan's sia): it is
                                     added to the keratometric astigmatism by double-angle sum,
                                     and the arcs correct the sum (centred on its steep axis) */
} kt_nomo_query;

/* The answer for one incision count. */
typedef struct kt_nomo_answer {
    int incisions;         /* 1 or 2; 0: the table has no case with this count */
    double arc;            /* deg: where the simulated SIA (interpolated in arc and age) meets
                              the target, or the longest simulated arc when none reaches it */
    double sia;            /* the SIA predicted at that arc, D */
    double residual;       /* the predicted post-operative cylinder |pre + SIA|, D */
    double residual_axis;  /* and its axis, deg */
    double arc_lo, arc_hi; /* the simulated arcs the answer lies between (equal when exact) */
    double age_lo, age_hi; /* the simulated ages used (equal: one age; the query's age clamped
                              to the table's range when outside it) */
    int reached;           /* 1 when some simulated arc induces the target */
    double depth, diameter;
    /* The band (lri-nomogram(1), BAND): the SIA's first-order sd at the answer's arc,
     * interpolated like the SIA (linear in arc from 0 at arc 0, then in age); the residual's
     * sd, |d residual / d SIA| sia_sd (the residual's double-angle vector against the SIA's;
     * the pre-op's against the SIA's below KT_NOMO_RES_DIR), and its 90% interval residual +- 1.645
     * sd, the lower end clipped at 0. NAN when the table has no sia_sd_D. */
    double sia_sd, residual_sd, residual_lo90, residual_hi90;
    /* The table's lines (kt_nomo_case.line) of the cases the answer used: for the eye of the
     * lower age and of the higher (the same eye when one age), the cases at the arcs below and
     * above the answer (equal when exact; 0: none, the arc 0 of no SIA). */
    int rows[2][2];
} kt_nomo_answer;

/* Answer q from t for one incision and for a pair: ans[0] one, ans[1] a pair. Returns KT_OK,
 * or KT_EINPUT when the query is out of range or the table has no usable case. */
int kt_nomo_plan(const kt_nomo *t, const kt_nomo_query *q, kt_nomo_answer ans[2], kt_err *e);

/* The astigmatism the arcs correct: the keratometric cylinder (K steep - K flat at axis) plus
 * the main incision's SIA vector; *axis its steep axis, [0, 180). */
double kt_nomo_pre(const kt_nomo_query *q, double *axis);

/* The table's range of simulated ages, years (min, max). */
void kt_nomo_ages(const kt_nomo *t, double *lo, double *hi);

#endif
