/* lp_patient.h: the planner's first stage (writes kt_lp_answer.eye): the patient file loaded
 * and checked, a Pentacam export fitted (anterior, posterior, pachymetry: lib/optics/surffit.h),
 * the halves of the steep meridian, the pachymetry at the zone and the blade depth. */
#ifndef KT_LP_PATIENT_H
#define KT_LP_PATIENT_H

#include "lp.h"

/* Unequal paired arcs (keratome-patient(5), UNEQUAL PAIRED ARCS; the project's rule, not a
 * publication's): the opposite arc's ratio is never below 0.2 (shorter, a single arc does it). */
#define KT_LP_RATIO_MIN 0.2

/* eye := o->patient loaded, fitted and checked (o->step against its max_arc too). Bad input
 * is KT_EINPUT naming the patient file (or the export) and what to change. */
int kt_lp_patient(const kt_lp_opts *o, kt_lp_eye *eye, kt_err *e);

#endif
