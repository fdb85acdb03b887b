/* lp_family.h: the planner's fourth stage (writes kt_lp_answer.fam): the candidate families of
 * arcs (lri-plan(1), DESCRIPTION): one arc on the steeper half, an equal pair on the
 * steep meridian, and, when the halves differ, an unequal pair; and each family's incision
 * plan built in memory (lib/model/plan.h): the arcs cut centre-out, after the main incision's
 * tunnel when it is simulated. */
#ifndef KT_LP_FAMILY_H
#define KT_LP_FAMILY_H

#include "lp.h"

/* Unequal paired arcs are tried when the two halves' astigmatism differ by more than 10%
 * (their ratio below 0.9; keratome-patient(5), UNEQUAL PAIRED ARCS: the project's rule). */
#define KT_LP_SYMMETRIC 0.9

/* fam := the families the patient's constraints allow, arcs of o->step per step to max_arc;
 * more than KT_LP_MAXSTEP steps is KT_EINPUT. */
int kt_lp_families_make(const kt_lp_opts *o, const kt_lp_eye *eye, kt_lp_families *fam, kt_err *e);

/* p := family f's plan on the patient's scene: its arcs at nstep steps of `step` deg (the
 * opposite one ratio x as long), centre-out at the zone's ring and the blade's depth, after the
 * main incision's tunnel when it is simulated. KT_EINPUT when the model refuses it. */
int kt_lp_family_plan(const kt_lp_scene *sc, const kt_lp_eye *eye, const kt_lp_family *f, double step, int nstep,
                      kt_plan *p, kt_err *e);

#endif
