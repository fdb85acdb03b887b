/* lp_scene.h: the planner's second stage (writes kt_lp_answer.scene): the patient's eye scene
 * from the base scene (kt_patient_scene), --fast's sizes, a Pentacam patient's measured
 * surfaces in its eye (the maps' Zernike departures, kt_surffit_measured_eye, with their
 * residuals in mesh_ant and mesh_post), and the main incision's tunnel when it is simulated
 * (keratome-patient(5), MAIN INCISION), checked against the eye before any meshing, with
 * the mesh refined at its site (eye.mesh_size.site). */
#ifndef KT_LP_SCENE_H
#define KT_LP_SCENE_H

#include "lp.h"

/* --fast's incision-floor size, mm (lri-plan(1), --fast; a mesh setting, not a physical
 * number): measured on plans/patients/wtr-od.yaml, the --fast mesh's best arcs were 85 / 2 x 55
 * deg without a floor refinement, 75 / 2 x 50 with 0.1 mm and 0.08 mm, 70 / 2 x 50 with
 * 0.06 mm, against the default mesh's (floor 42 um) 70 / 2 x 50; 0.1 mm is the coarsest of
 * these within one 5 deg step of the default, at about 1.7x the CPU of no refinement. */
#define KT_LP_FAST_FLOOR 0.1

/* sc := the patient's scene on o->base (NULL: KT_SHARE_DIR/../plans/eye.yaml). Bad input
 * (a base that is no eye, values that make no eye, measured surfaces the eye cannot carry or
 * a map that measures too little of them, a tunnel that does not fit) is KT_EINPUT naming the
 * patient file, the front map or the base. */
int kt_lp_scene_make(const kt_lp_opts *o, const kt_lp_eye *eye, kt_lp_scene *sc, kt_err *e);

/* The main incision's external entry diameter, mm: the corneal edge (white-to-white) for a
 * clear-corneal incision, the middle of the limbal band for a limbal one. */
double kt_lp_main_entry(const kt_patient *p, const kt_scene *s);

#endif
