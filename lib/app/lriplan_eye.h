/* lriplan_eye.h: plan.html's drawing of the eye (lri-plan(1), --view): the eye from the front
 * with the main incision, the arcs and their end points, turned to the view the surgeon has
 * (sitting temporal or superior) or the examiner's (superior up, TABO 0 deg at the right).
 * Every label is placed where its estimated text box (from its font size and its characters)
 * meets no other label's box; the boxes are returned so a test can check them.
 *
 * Outputs: kt_lri_eye_svg writes one <svg> to f and fills *lab with the box of every text it
 * wrote, in the drawing's pixels (y down), in the order written. */
#ifndef KT_LRIPLAN_EYE_H
#define KT_LRIPLAN_EYE_H

#include <stdio.h>

#include "lp_choose.h"
#include "patient.h"

/* How the eye is drawn (lri-plan --view; default temporal). */
enum { KT_LRI_VIEW_TEMPORAL = 0, KT_LRI_VIEW_SUPERIOR, KT_LRI_VIEW_EXAMINER };
#define KT_LRI_VIEW_DEFAULT KT_LRI_VIEW_TEMPORAL

/* "temporal", "superior", "examiner"; and how the view is said on the sheet. */
const char *kt_lri_view_name(int view);
const char *kt_lri_view_words(int view);

/* The angle added to a TABO meridian to give its direction on the drawing (deg, counter-
 * clockwise on screen): 0 for the examiner; for a surgeon, the side they sit on is put at the
 * bottom (superior: 180; temporal: 90 in a right eye, 270 in a left eye). A turn, never a
 * mirror: clockwise on the eye is clockwise on the drawing. */
double kt_lri_view_turn(int view, int eye);

#define KT_LRI_MAXLABEL 64
typedef struct kt_lri_box {
    double x0, y0, x1, y1;      /* px, y down */
} kt_lri_box;
typedef struct kt_lri_labels {
    int n;
    kt_lri_box b[KT_LRI_MAXLABEL];
    char text[KT_LRI_MAXLABEL][48];
} kt_lri_labels;

/* The estimated box of a text of font size fs px (bold: 1) anchored at (x, y) (its baseline;
 * anchor 'l' start, 'm' middle), from DejaVu Sans's advance widths, rounded up. */
kt_lri_box kt_lri_text_box(const char *s, double fs, int bold, double x, double y, char anchor);
/* 1 when two boxes overlap (touching is not overlapping). */
int kt_lri_box_meet(const kt_lri_box *a, const kt_lri_box *b);

/* The drawing: the patient's cornea (white-to-white), zone, steep meridian, main incision, and
 * the narc arcs (from lp_choose.h: from and to in the order marked), in view `view`. */
void kt_lri_eye_svg(FILE *f, const kt_patient *p, const kt_lp_arc *arcs, int narc, int view, kt_lri_labels *lab);

#endif
